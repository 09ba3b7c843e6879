#![doc = "robid runtime: the `no_std` scalar and model traits that generated models implement, and, with the `std` feature, the identification pipeline."]
#![cfg_attr(feature = "std", doc = "")]
#![cfg_attr(
    feature = "std",
    doc = "With `std`, every input (data files, config files, settings given in code) is checked against the documented limits of [`limits`] before any work, every solver stops at an iteration cap, and a successful result holds no NaN or infinity; an [`Error`] names the input, its place (file:line and column, config key at file:line:column, or the setting's field) and the fix."
)]
#![cfg_attr(not(feature = "std"), no_std)]
// Range checks are written `!(lo < x && x <= hi)` so that NaN fails them too.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod model;
mod real;
pub mod rng;

pub use model::{LengthError, Model};
pub use real::Real;

#[cfg(feature = "std")]
pub mod data;
#[cfg(feature = "std")]
pub mod drive;
#[cfg(feature = "std")]
mod error;
#[cfg(feature = "std")]
pub mod estimate;
#[cfg(feature = "std")]
pub mod excite;
#[cfg(feature = "std")]
pub mod feasible;
#[cfg(feature = "std")]
pub mod limits;
#[cfg(feature = "std")]
pub mod nelder_mead;
#[cfg(feature = "std")]
pub mod output;
#[cfg(feature = "std")]
pub mod pipeline;
#[cfg(feature = "std")]
pub mod report;
#[cfg(feature = "std")]
pub mod signal;
#[cfg(feature = "std")]
pub mod simulate;
#[cfg(feature = "std")]
pub mod validate;

#[cfg(feature = "std")]
pub use error::{
    DataError, Error, EstimateError, FeasibleError, OutputError, Result, SimulateError,
};
