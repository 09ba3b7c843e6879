//! The identification pipeline: data set -> prepared signals -> observation matrix ->
//! estimate -> fit (docs/identification.md#pipeline-overview). Regressor rows and filtering
//! run in parallel (rayon).

mod advice;
mod friction;
mod identify;
mod observe;
mod prepare;
mod runs;
mod segments;
mod static_samples;
mod stream;

pub use friction::{FrictionData, JointTorqueSource, REFERENCE_TEMPERATURE, friction_samples};
pub use identify::{
    Identification, energy_observation_of, estimate, identify, observation, validate,
};
pub use observe::{decimator, observe};
pub use prepare::{Prepared, RotorStates, automatic_trim, prepare};
pub use runs::{RepeatedIdentification, RunSpread, average, identify_runs, stack};
pub use segments::{
    DroppedSegment, SegmentUse, SegmentedIdentification, identify_segments, validate_loaded,
    validate_segments,
};
pub use static_samples::{StaticFit, StaticKind, identify_static, static_rows};

#[cfg(test)]
pub(crate) mod tests;
