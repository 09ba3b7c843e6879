#![doc = "robid-symbolic: the symbolic engine of robid and everything derived with it."]
//!
//! Expressions ([`expr`]), robot descriptions ([`robot`]), kinematics and dynamics
//! ([`dynamics`]). Data flows one way: description -> derivation -> program.

pub mod dynamics;
pub mod expr;
pub mod regroup;
pub mod robot;
pub mod sample;

pub use dynamics::{Derivation, Regressor};
pub use expr::{Arena, Id, Node, Num, Symbol, Values};
pub use robot::{Convention, DescriptionError, Drive, Joint, JointKind, Robot};
pub mod program;
pub mod emit;
