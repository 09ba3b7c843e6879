//! `robot_model!`: compiles a robot description into straight-line, allocation-free,
//! `no_std` Rust (a thin shell over `robid_symbolic`, which does all the work).
//!
//! The crate using the macro must depend on `robid-runtime` (with
//! `default-features = false` in a `no_std` crate): the emitted code is generic
//! over `robid_runtime::Real` and implements `robid_runtime::Model`.
//!
//! # From a description file
//!
//! The path is relative to the directory of the calling crate's `Cargo.toml`
//! (or, if not found there, to the directory of the file invoking the macro);
//! the file is tracked, so Cargo rebuilds when it changes. The format is the
//! one of the command-line tool (see `robid_symbolic::robot`). The examples
//! below use `descriptions/planar2.toml` of this crate: a two-link planar arm
//! (modified DH, both axes along z, links of 0.5 m and 0.3 m) with gravity
//! along -y, so that at q = 0 both links point along x, across gravity.
//!
//! ```
//! robid_macros::robot_model!(file = "descriptions/planar2.toml");
//! use robid_runtime::Model;
//!
//! // Point masses at the link ends: 2 kg at x = 0.5 m of frame 1, 1 kg at x = 0.3 m of
//! // frame 2. Standard parameters per link, about the frame origin:
//! // XX XY XZ YY YZ ZZ MX MY MZ M (a point mass m at (x, 0, 0) has YY = ZZ = m x^2, MX = m x).
//! let point = |m: f64, x: f64| [0.0, 0.0, 0.0, m * x * x, 0.0, m * x * x, m * x, 0.0, 0.0, m];
//! let standard: Vec<f64> = point(2.0, 0.5).into_iter().chain(point(1.0, 0.3)).collect();
//!
//! // Through the runtime's `Model` trait (slices, lengths checked; its methods end in
//! // `_into`), as the identification pipeline uses it.
//! let arm: &dyn Model = &Planar2;
//! assert_eq!((arm.dof(), arm.standard_parameter_count()), (2, 20));
//! assert_eq!(arm.base_parameter_name(0), Some("ZZR1"));
//! let mut base = vec![0.0; arm.base_parameter_count()];
//! arm.base_from_standard_into(&standard, &mut base)?;
//!
//! // Holding the arm straight out at rest takes tau1 = g (m1 l1 + m2 (l1 + l2)) and
//! // tau2 = g m2 l2.
//! let (g, zero) = (9.81, [0.0; 2]);
//! let mut tau = [0.0; 2];
//! arm.inverse_dynamics_into(&zero, &zero, &zero, &base, &mut tau)?;
//! assert!((tau[0] - g * (2.0 * 0.5 + 1.0 * 0.8)).abs() < 1e-12);
//! assert!((tau[1] - g * 1.0 * 0.3).abs() < 1e-12);
//!
//! // The base regressor gives the same torques in any state: tau = Y_b(q, qd, qdd) base.
//! let (q, qd, qdd) = ([0.3, -1.2], [0.5, 2.0], [-1.0, 4.0]);
//! let mut y = vec![0.0; 2 * base.len()];
//! arm.base_regressor_into(&q, &qd, &qdd, &mut y)?;
//! arm.inverse_dynamics_into(&q, &qd, &qdd, &base, &mut tau)?;
//! for (row, t) in y.chunks(base.len()).zip(tau) {
//!     let dot: f64 = row.iter().zip(&base).map(|(a, b)| a * b).sum();
//!     assert!((dot - t).abs() < 1e-12);
//! }
//!
//! // Stretched out, the mass matrix is that of two point masses on a rigid rod:
//! // M11 = m1 l1^2 + m2 (l1 + l2)^2, M12 = m2 (l1 + l2) l2, M22 = m2 l2^2.
//! let mut m = [0.0; 4];
//! arm.mass_matrix_into(&zero, &base, &mut m)?;
//! let expected = [2.0 * 0.25 + 0.64, 0.8 * 0.3, 0.8 * 0.3, 0.09];
//! assert!(m.iter().zip(expected).all(|(a, b)| (a - b).abs() < 1e-12));
//!
//! // A slice of the wrong length is an error naming the argument, never a panic.
//! let err = arm.inverse_dynamics_into(&[0.0; 3], &zero, &zero, &base, &mut tau).unwrap_err();
//! assert_eq!(err.argument, "q");
//!
//! // The type's own functions take and return fixed-size arrays, generic over the scalar.
//! let base: [f64; Planar2::BASE_PARAMETERS] = Planar2.base_from_standard(&standard.try_into().unwrap());
//! let tau32: [f32; 2] = Planar2.gravity(&[0.0f32; 2], &base.map(|b| b as f32));
//! assert!((tau32[1] - 2.943).abs() < 1e-5);
//! # Ok::<(), robid_runtime::model::LengthError>(())
//! ```
//!
//! Options: `name` for another type name, and `drive` to add drive terms (`Ia`,
//! `Fv`, `Fc`, `Fo`) to every joint:
//!
//! ```
//! robid_macros::robot_model!(file = "descriptions/planar2.toml", name = "planar2_drive", drive = [Ia, Fv, Fc, Fo]);
//!
//! // Ten inertial parameters and four drive terms per joint.
//! assert_eq!(Planar2Drive::STANDARD_PARAMETERS, 2 * (10 + 4));
//! assert_eq!(Planar2Drive::STANDARD_PARAMETER_NAMES[10..14], ["Ia1", "Fv1", "Fc1", "Fo1"]);
//! ```
//!
//! # From a URDF
//!
//! A file ending in `.urdf` is read as a URDF (docs/urdf.md of the repository): the chain
//! from `base` (default: the root link) to `tip` (default: where the movable joints end,
//! when they form one path), fixed joints and everything hanging off the chain merged
//! into the link that carries it. robid fits its own modified-DH frames to the joint axes,
//! so the URDF's `<inertial>` elements come with the model as standard parameters in
//! those frames, `URDF_STANDARD_PARAMETERS`:
//!
//! ```
//! robid_macros::robot_model!(file = "descriptions/planar2.urdf");
//! use robid_runtime::Model;
//!
//! let arm: &dyn Model = &Planar2Urdf;
//! let mut base = vec![0.0; arm.base_parameter_count()];
//! arm.base_from_standard_into(&Planar2Urdf::URDF_STANDARD_PARAMETERS, &mut base)?;
//!
//! // The file's point masses (2 kg at 0.5 m, 1 kg at 0.8 m from the shoulder), held
//! // straight out against gravity.
//! let mut tau = [0.0; 2];
//! arm.inverse_dynamics_into(&[0.0; 2], &[0.0; 2], &[0.0; 2], &base, &mut tau)?;
//! assert!((tau[0] - 9.81 * (2.0 * 0.5 + 1.0 * 0.8)).abs() < 1e-12, "{tau:?}");
//! assert!((tau[1] - 9.81 * 1.0 * 0.3).abs() < 1e-12);
//! # Ok::<(), robid_runtime::model::LengthError>(())
//! ```
//!
//! `robot_model!(file = "panda.urdf", tip = "panda_hand")` chooses the chain of a tree.
//!
//! # Inline
//!
//! ```
//! robid_macros::robot_model! {
//!     name = "planar",
//!     convention = "modified",        // or "standard"
//!     gravity = [0, -9.81, 0],        // optional, default [0, 0, -9.81]
//!     drive = [Ia, Fv],               // optional drive terms of every joint
//!     symbols = [L1 = 0.5],           // optional values of geometric symbols
//!     calibrated = false,             // optional: true for a measured table (angles as written)
//!     joints = [
//!         //       alpha   a     d  theta
//!         revolute(0,      0,    0, 0),
//!         revolute(0,      "L1", 0, 0),
//!         prismatic("pi/2", 0,   0, 0),
//!     ],
//! }
//! use robid_runtime::Model;
//!
//! // A geometric symbol stays symbolic: it is a field of the type, which `Default`
//! // sets to the description's value.
//! let arm = Planar::default();
//! assert_eq!(arm.L1, 0.5);
//! assert_eq!(arm.dof(), 3);
//!
//! // A 1 kg point mass at the origin of frame 2, which lies L1 from axis 1 along x:
//! // holding it at q = 0 against gravity along -y takes g L1 at joint 1.
//! let mut standard = vec![0.0; arm.standard_parameter_count()];
//! let m2 = (0..standard.len()).position(|i| arm.standard_parameter_name(i) == Some("M2"));
//! standard[m2.unwrap()] = 1.0;
//! for l1 in [0.5, 0.8] {
//!     // (the type's own `gravity` takes and returns arrays; the trait's `gravity_into`, slices)
//!     let arm: &dyn Model = &Planar { L1: l1 };
//!     let mut base = vec![0.0; arm.base_parameter_count()];
//!     arm.base_from_standard_into(&standard, &mut base)?;
//!     let mut g = [0.0; 3];
//!     arm.gravity_into(&[0.0; 3], &base, &mut g)?;
//!     assert!((g[0] - 9.81 * l1).abs() < 1e-12, "{g:?}");
//! }
//! # Ok::<(), robid_runtime::model::LengthError>(())
//! ```
//!
//! Each joint is `revolute(alpha, a, d, theta)` or `prismatic(alpha, a, d,
//! theta)`, a row of the DH table; a value is a number or a string holding an
//! exact angle (`"pi/2"`) or an expression in geometric symbols (`"-L3"`). In a
//! modified table a row may add Khalil and Kleinfinger's rotation about and
//! translation along `z_(j-1)` before it, by name:
//! `revolute("pi/2", 0.1, 0, 0, gamma = "pi/4", b = 0.05)`
//! (docs/conventions.md, "Khalil-Kleinfinger general frames"). Frame 0's pose in
//! the world, a file's `[base]`, is
//! `base = pose(xyz = [x, y, z], rpy = [roll, pitch, yaw])` (either part optional):
//! gravity stays given in the world and is turned into frame 0. A tool frame places
//! nothing in the compiled model; it is written in a description file for the command
//! line.
//!
//! ```
//! robid_macros::robot_model! {
//!     name = "offset_arm",
//!     convention = "modified",
//!     joints = [
//!         revolute(0, 0, 0, 0),
//!         // joint 2's frame turned by gamma about z1 and moved by b along it first
//!         revolute(0, 0.5, 0, 0, gamma = "pi/2", b = 0.2),
//!     ],
//! }
//! use robid_runtime::Model;
//!
//! // A 1 kg point mass at the origin of frame 2 (0.5 m from axis 1 along the turned x,
//! // which is y of frame 1): gravity along -z acts on no joint of this vertical-axis arm.
//! let arm: &dyn Model = &OffsetArm;
//! let mut standard = vec![0.0; arm.standard_parameter_count()];
//! standard[19] = 1.0; // M2
//! let mut base = vec![0.0; arm.base_parameter_count()];
//! arm.base_from_standard_into(&standard, &mut base)?;
//! let mut g = [0.0; 2];
//! arm.gravity_into(&[0.3, -0.7], &base, &mut g)?;
//! assert!(g.iter().all(|t| t.abs() < 1e-12), "{g:?}");
//! // accelerating joint 1 alone takes the point mass's inertia about axis 1: m r^2 with
//! // r = 0.5 m (b moves along the axis, which does not change r)
//! let mut tau = [0.0; 2];
//! arm.inverse_dynamics_into(&[0.0; 2], &[0.0; 2], &[1.0, 0.0], &base, &mut tau)?;
//! assert!((tau[0] - 0.25).abs() < 1e-12, "{tau:?}");
//! # Ok::<(), robid_runtime::model::LengthError>(())
//! ```
//!
//! Either form defines a type named after the robot (`ur5e` -> `Ur5e`) with
//! constants (`DOF`, parameter counts and names, base-parameter expressions)
//! and the functions `standard_regressor`, `base_regressor`,
//! `inverse_dynamics`, `mass_matrix`, `gravity`, `coriolis` and
//! `base_from_standard`, each generic over the scalar and on fixed-size arrays.
//! For x86-64 each also gets a private instance compiled with AVX2 and FMA, which
//! the type's `Model::run` calls on a processor that has both (fused multiply-adds,
//! vectorised sines and cosines; `robid_runtime::fused`); the generic functions
//! never switch.
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
