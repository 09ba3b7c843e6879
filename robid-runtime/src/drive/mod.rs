//! The drive chain between what is measured and the joint-side model
//! (docs/identification.md#drive-chain): gear ratios and couplings, torque constants,
//! rotor-dynamics compensation (with a constant or a nonlinear rotor friction model), and extra regressor columns for drive terms the symbolic
//! model does not have.

mod chain;
mod extra;
mod friction;
mod residual;
mod rotor;

pub use chain::{DriveChain, DriveConfig, Side};
pub use extra::{ExtraColumn, ExtraTerm, RotorSample, TermSignal, signal_name};
pub use friction::{
    DEFAULT_SMOOTHING, FixedParameter, FrictionFit, FrictionFitOptions, FrictionModel,
    FrictionParameter, FrictionSample, JointFriction, LOAD_SPREAD, TEMPERATURE_COEFFICIENT_LIMIT,
    TEMPERATURE_SPREAD, identify_friction, widest_smoothing,
};
pub use residual::{Residual, ResidualTerm};
pub use rotor::RotorConfig;
