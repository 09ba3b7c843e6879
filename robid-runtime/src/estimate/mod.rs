//! Estimators (docs/identification.md#estimators): OLS, WLS (Gautier's per-joint weights),
//! recursive least squares with forgetting factor (also link by link, Zomaya's order),
//! and the energy model. Least squares
//! always goes through QR and an SVD of R with a relative rank threshold, never the normal
//! equations.

mod energy;
pub(crate) mod error;
pub(crate) mod hac;
mod known;
mod least_squares;
mod link_by_link;
mod lstsq;
pub(crate) use lstsq::condition_number;
mod observation;
mod per_axis;
mod physical;
mod quality;
mod result;
mod rls;
mod streaming;

pub use energy::{
    EnergyRegressor, energy, energy_observation, friction_power, model_energy_observation,
    quadrature,
};
pub use error::EstimateError;
pub(crate) use error::{not_excited, undetermined};
pub use hac::{RobustStd, robust_lag};
pub use known::KnownParameters;
pub use least_squares::{SIGMA_FLOOR, check_names, ols, wls};
pub(crate) use least_squares::{ols_with, wls_with};
pub use link_by_link::{link_by_link, link_by_link_steps};
pub use observation::Observation;
pub use per_axis::{AxisFit, PerAxis, per_axis};
pub use physical::{
    NOT_PHYSICAL_Z, Sign, SignDefinite, base_signs, extra_column_sign, not_physical,
    opposite_signs, signs_of,
};
#[cfg(test)]
pub(crate) use quality::assess;
pub(crate) use quality::dominated_columns;
pub use quality::{
    CONDITION_WARNING, ENERGY_CONDITION_RATIO, OUTLIER_ROWS, OUTLIER_SHARE, QualityWarning,
    REL_STD_WARNING, ROUNDING_EFFECT,
};
pub use result::{Estimate, Estimator, error_bound};
pub use rls::{MIN_FORGETTING, Rls, check_forgetting, rls};
pub(crate) use streaming::Dominance;
pub use streaming::StreamingLeastSquares;

/// The equations a least-squares fit of `parameters` needs: one more than the parameters,
/// so that a residual is left for the standard deviations (as many fit any data exactly,
/// whatever the noise). Every check of a fit's size counts with it.
pub(crate) const fn equations_needed(parameters: usize) -> usize {
    parameters.saturating_add(1)
}

/// What the equations of [`equations_needed`] are for, in a message: "the 49 equations the
/// 48 parameters need", "the 2 equations the 1 parameter needs" (it said "the 1 parameters
/// need").
pub(crate) fn equations_purpose(parameters: usize) -> String {
    let verb = if parameters == 1 { "needs" } else { "need" };
    format!(
        "the {} the {} {verb}",
        crate::Count(equations_needed(parameters), "equation"),
        crate::Count(parameters, "parameter")
    )
}
