//! Estimators (docs/identification.md#estimators): OLS, WLS (Gautier's per-joint weights),
//! recursive least squares with forgetting factor, and the energy model. Least squares
//! always goes through QR and an SVD of R with a relative rank threshold, never the normal
//! equations.

mod energy;
mod error;
mod least_squares;
mod lstsq;
pub(crate) use lstsq::condition_number;
mod observation;
mod quality;
mod result;
mod rls;

pub use energy::{
    EnergyRegressor, energy, energy_observation, friction_power, model_energy_observation,
};
pub use error::EstimateError;
pub use least_squares::{SIGMA_FLOOR, check_names, ols, wls};
pub use observation::Observation;
#[cfg(test)]
pub(crate) use quality::assess;
pub(crate) use quality::dominated_columns;
pub use quality::{
    CONDITION_WARNING, ENERGY_CONDITION_RATIO, OUTLIER_ROWS, OUTLIER_SHARE, QualityWarning,
    REL_STD_WARNING,
};
pub use result::{Estimate, Estimator, error_bound};
pub use rls::{Rls, rls};
