//! Shared helpers of the workspace-level integration tests.
//!
//! - [`reference`]: the reference robots (descriptions and parameter sets, compiled in);
//! - [`rnea`]: an independent plain-`f64` recursive Newton-Euler, the numeric reference;
//! - [`state`]: random states, smooth trajectories and symbol bindings for evaluation.

pub mod reference;
pub mod rnea;
pub mod state;
