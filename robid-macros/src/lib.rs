//! `robot_model!`: compiles a robot description into straight-line, allocation-free,
//! `no_std` Rust (a thin shell over `robid_symbolic`, which does all the work).
//!
//! The crate using the macro must depend on `robid-runtime` (with
//! `default-features = false` in a `no_std` crate): the emitted code is generic
//! over `robid_runtime::Real` and implements `robid_runtime::Model`.
//!
//! # From a description file
//!
//! ```ignore
//! robid_macros::robot_model!(file = "descriptions/ur5e.toml");
//! // with all drive terms (Ia, Fv, Fc, Fo) on every joint, under another name:
//! robid_macros::robot_model!(file = "descriptions/panda.toml", name = "panda_drive", drive = [Ia, Fv, Fc, Fo]);
//! ```
//!
//! The path is relative to the directory of the calling crate's `Cargo.toml`
//! (or, if not found there, to the directory of the file invoking the macro);
//! the file is tracked, so Cargo rebuilds when it changes. The format is the
//! one of the command-line tool (see `robid_symbolic::robot`).
//!
//! # Inline
//!
//! ```ignore
//! robid_macros::robot_model! {
//!     name = "planar",
//!     convention = "modified",        // or "standard"
//!     gravity = [0, -9.81, 0],        // optional, default [0, 0, -9.81]
//!     drive = [Ia, Fv],               // optional drive terms of every joint
//!     symbols = [L1 = 0.5],           // optional values of geometric symbols
//!     joints = [
//!         //       alpha   a     d  theta
//!         revolute(0,      0,    0, 0),
//!         revolute(0,      "L1", 0, 0),
//!         prismatic("pi/2", 0,   0, 0),
//!     ],
//! }
//! ```
//!
//! Each joint is `revolute(alpha, a, d, theta)` or `prismatic(alpha, a, d,
//! theta)`, a row of the DH table; a value is a number or a string holding an
//! exact angle (`"pi/2"`) or an expression in geometric symbols (`"-L3"`).
//!
//! Either form defines a type named after the robot (`ur5e` -> `Ur5e`) with
//! constants (`DOF`, parameter counts and names, base-parameter expressions)
//! and the functions `standard_regressor`, `base_regressor`,
//! `inverse_dynamics`, `mass_matrix`, `gravity`, `coriolis` and
//! `base_parameters`, each generic over the scalar and on fixed-size arrays.
//!
//! Mistakes in the input are compile errors pointing at the offending item
//! (all of them at once); the type is then still defined, as a placeholder, so
//! that its uses do not add errors of their own. For a file, each mistake is
//! one error at the path, its message starting with the file, line and
//! column (a TOML syntax error is reported alone). Values are checked against
//! the limits documented in `robid_symbolic::robot::bounds` (lengths,
//! angles, gravity, limits, sizes) and `robid_symbolic::expr` (expression
//! length, nesting and exponents).

mod check;
mod expand;
mod input;

use proc_macro::TokenStream;

/// Defines a robot's model type from a description; see the crate documentation.
#[proc_macro]
pub fn robot_model(input: TokenStream) -> TokenStream {
    let input = syn::parse_macro_input!(input as input::Input);
    expand::expand(input).into()
}
