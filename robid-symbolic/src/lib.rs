#![doc = "robid-symbolic: the symbolic engine of robid and everything derived with it."]
//!
//! Expressions ([`expr`]), robot descriptions ([`robot`]), kinematics and
//! dynamics ([`dynamics`]), base parameters ([`regroup`]), straight-line
//! programs ([`program`]) and Rust and C emission ([`emit`]). Data flows one way:
//! description -> derivation -> base parameters -> program -> emitted code.
//!
//! Derive a two-link planar arm (gravity in its plane) and print its base parameters,
//! each an expression in the standard parameters, and the cost of its programs:
//!
//! ```
//! use robid_symbolic::program::RobotPrograms;
//! use robid_symbolic::{Derivation, Robot};
//!
//! let text = r#"
//! name = "planar2"
//! convention = "modified"
//! gravity = [0, -9.81, 0]
//! [[joints]]
//! [[joints]]
//! a = "L1"
//! [symbols]
//! L1 = 0.5
//! "#;
//! let robot = Robot::from_toml(text, "planar2.toml")?;
//! let mut d = Derivation::new(&robot);
//! let base = d.base_parameters()?;
//! for b in &base.base {
//!     println!("{} = {}", b.name, d.arena.display(b.expression));
//! }
//! // ZZR1 = ZZ1 + M2*L1^2 and MXR1 = MX1 + L1*M2 (the length stays a symbol), MY1, ZZ2,
//! // MX2, MY2
//! assert_eq!(base.base.len(), 6);
//!
//! // The straight-line programs the generated code is made of.
//! let programs = RobotPrograms::derive(&robot)?;
//! for (info, program) in programs.iter() {
//!     println!("{}: {}", info.name, program.operations());
//! }
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod dynamics;
pub mod emit;
pub mod expr;
pub mod program;
pub mod regroup;
pub mod robot;

pub use dynamics::{Derivation, Regressor};
pub use expr::{Arena, Id, Node, Num, Symbol, Values};
pub use robot::{Convention, DescriptionError, Drive, Joint, JointKind, Robot, Transform};
