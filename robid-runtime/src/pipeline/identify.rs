//! From a model, data and a config to identified parameters, fit and validation.

use crate::Model;
use crate::data::{Config, Dataset, Method, Warning};
use crate::error::{Error, Result};
use crate::estimate::{Estimate, Observation, ols, rls, wls};
use crate::pipeline::{decimator, observe, prepare};
use crate::validate::{Fit, Prediction};

/// The result of [`identify`].
#[derive(Debug, Clone)]
pub struct Identification {
    /// Robot name (from the model).
    pub robot: String,
    /// Estimated parameters (base parameters, then extra columns).
    pub estimate: Estimate,
    /// Fit on the estimation data.
    pub fit: Fit,
    /// Measured vs predicted on the estimation data.
    pub prediction: Prediction,
    /// Warnings from loading.
    pub warnings: Vec<Warning>,
}

/// Builds the observation of a data set: prepare, regressor, decimate, stack.
/// Returns it with the decimated sample time.
pub fn observation(
    model: &(dyn Model + Sync),
    data: &Dataset,
    config: &Config,
) -> Result<(Observation, f64)> {
    config.check(model.dof())?;
    if data.dof() != model.dof() {
        return Err(Error::JointCountMismatch {
            context: format!("data set {}", data.name),
            expected: model.dof(),
            found: data.dof(),
        });
    }
    let prepared = prepare(data, config)?;
    let obs = observe(model, &prepared, config)?;
    let dt = prepared.sample_time * decimator(config)?.factor() as f64;
    Ok((obs, dt))
}

/// Estimates with the configured method.
pub fn estimate(obs: &Observation, config: &Config) -> Result<Estimate> {
    let e = &config.estimation;
    match e.method {
        Method::Ols => ols(obs, e.rank_tolerance),
        Method::Wls => wls(obs, e.rank_tolerance),
        Method::Rls => rls(obs, e.forgetting, e.rank_tolerance),
    }
}

/// The whole pipeline: observation matrix from `data`, estimation, fit.
pub fn identify(
    model: &(dyn Model + Sync),
    data: &Dataset,
    config: &Config,
) -> Result<Identification> {
    let (obs, dt) = observation(model, data, config)?;
    let estimate = estimate(&obs, config)?;
    let prediction = Prediction::new(&obs, &estimate.values, dt);
    Ok(Identification {
        robot: model.name().to_string(),
        fit: prediction.fit(),
        prediction,
        estimate,
        warnings: data.warnings.clone(),
    })
}

/// Predicts the torques of another data set with identified values (base parameters then
/// extra columns, as in [`Estimate::values`]), processed like the estimation data.
pub fn validate(
    model: &(dyn Model + Sync),
    data: &Dataset,
    config: &Config,
    values: &[f64],
) -> Result<Prediction> {
    let (obs, dt) = observation(model, data, config)?;
    if values.len() != obs.cols() {
        return Err(Error::DimensionMismatch {
            what: "parameter values".into(),
            expected: obs.cols(),
            found: values.len(),
        });
    }
    Ok(Prediction::new(&obs, values, dt))
}
