//! Reference robots: their descriptions (`descriptions/`), their models compiled
//! by `robot_model!` (`robots::Ur5e`, ...), and the generated code checked in for
//! review (`generated/`, kept up to date by a test).

pub mod extraction;
pub mod figaroh;
pub mod interpreted;
pub mod limits;
pub mod models;

pub use models::{Lwr4, Panda, Puma560, REFERENCES, Reference, Rx90, Stanford, Tx40, Ur5e};
