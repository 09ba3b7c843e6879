#![doc = "robid-symbolic: the symbolic engine of robid and everything derived with it."]
//!
//! Expressions ([`expr`]), robot descriptions ([`robot`]), kinematics and
//! dynamics ([`dynamics`]), base parameters ([`regroup`]), straight-line
//! programs ([`program`]) and Rust emission ([`emit`]). Data flows one way:
//! description -> derivation -> base parameters -> program -> emitted code.

pub mod dynamics;
pub mod emit;
pub mod expr;
pub mod program;
pub mod regroup;
pub mod robot;
pub mod sample;

pub use dynamics::{Derivation, Regressor};
pub use expr::{Arena, Id, Node, Num, Symbol, Values};
pub use robot::{Convention, DescriptionError, Drive, Joint, JointKind, Robot};
