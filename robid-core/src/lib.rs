//! The `no_std` vocabulary that robid's symbolic engine and its runtime share, without
//! dependencies:
//!
//! - what a parameter is ([`ParameterId`], [`BaseName`], [`DriveTerm`]), parsed and
//!   written in one place;
//! - the table of the programs every robot model has ([`PROGRAMS`]);
//! - the nearest names to a misspelt one ([`names`], with the `std` feature);
//! - the seeded random generator ([`rng::Rng`]; its normal distribution with the `std`
//!   feature, which robid-runtime's `std` turns on);
//! - the line and column of a place in a text ([`text::line_column`]), for every
//!   message that points into a file.
//!
//! `robid_runtime::model` and `robid_runtime::rng` re-export all of it, so user code
//! and generated code name these items through the runtime.
#![no_std]

#[cfg(any(test, feature = "std"))]
extern crate std;

#[cfg(any(test, feature = "std"))]
pub mod names;
mod parameter;
mod program;
pub mod rng;
pub mod text;

pub use parameter::{BaseName, DriveTerm, Inertial, ParameterId, ParameterKind, ParseNameError};
pub use program::{Argument, PROGRAMS, ProgramInfo, ProgramKind, Size, Sizes};

/// The comment robid writes in a URDF just before a `<limit>` whose `effort="0"` or
/// `velocity="0"` stands for a limit the description does not give (the format requires
/// both attributes of a revolute or prismatic joint): the URDF reader takes these zeros as
/// no limit without warning that an exporter may have lost the robot's limits.
pub const URDF_NO_LIMIT_NOTE: &str = "0: the description gives no torque or no velocity limit";
