#![doc = "robid-symbolic: the symbolic engine of robid and everything derived with it."]
//!
//! Expressions ([`expr`]), robot descriptions ([`robot`]), kinematics and dynamics
//! ([`dynamics`]). Data flows one way: description -> derivation -> program.

pub mod expr;
pub mod sample;

pub use expr::{Arena, Id, Node, Num, Symbol, Values};
