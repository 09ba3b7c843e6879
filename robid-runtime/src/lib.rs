#![cfg_attr(
    not(feature = "std"),
    doc = "robid runtime: the `no_std` scalar, model trait, program table, parameter names and random generator that generated models use (the identification pipeline needs the `std` feature)."
)]
#![cfg_attr(feature = "std", doc = include_str!("../README.md"))]
#![cfg_attr(not(feature = "std"), no_std)]
// Range checks are written `!(lo < x && x <= hi)` so that NaN fails them too.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod fused;
pub mod lanes;
pub mod model;
pub mod online;
mod real;
#[cfg(feature = "std")]
pub use robid_core::names;
pub use robid_core::rng;
pub mod trig;
pub mod wrench;

mod number;

pub use model::{LengthError, Model};
pub use number::{Count, Num, Series};
pub use real::{FUSED_MUL_ADD, Real};

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
mod finite;
#[cfg(feature = "std")]
pub mod inspect;
#[cfg(feature = "std")]
pub mod limits;
#[cfg(feature = "std")]
pub mod nelder_mead;
#[cfg(feature = "std")]
pub mod output;
#[cfg(feature = "std")]
pub mod payload;
#[cfg(feature = "std")]
pub mod pipeline;
#[cfg(feature = "std")]
pub mod progress;
#[cfg(feature = "std")]
pub mod report;
#[cfg(feature = "std")]
pub mod signal;
#[cfg(feature = "std")]
pub mod simulate;
#[cfg(feature = "std")]
mod toml_syntax;
#[cfg(feature = "std")]
pub mod validate;

#[cfg(feature = "std")]
pub use error::{
    DataError, Error, EstimateError, FeasibleError, OutputError, Result, SimulateError, num,
};
