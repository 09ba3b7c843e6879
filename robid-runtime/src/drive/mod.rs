//! The drive chain between what is measured and the joint-side model
//! (docs/identification.md#drive-chain): gear ratios and couplings, torque constants,
//! rotor-dynamics compensation, and extra regressor columns for drive terms the symbolic
//! model does not have.

mod chain;
mod extra;
mod rotor;

pub use chain::{DriveChain, DriveConfig, Side};
pub use extra::{ExtraColumn, ExtraTerm, TermSignal};
pub use rotor::RotorConfig;
