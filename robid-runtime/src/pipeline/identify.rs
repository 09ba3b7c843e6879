//! From a model, data and a config to identified parameters, fit and validation.

use crate::Model;
use crate::data::{Config, Dataset, Method, Warning};
use crate::error::{Error, Result};
use crate::estimate::{Estimate, Observation, energy, model_energy_observation, ols, rls, wls};
use crate::pipeline::{Prepared, decimator, observe, prepare};
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
    let prepared = checked_prepare(model, data, config)?;
    torque_observation(model, &prepared, config)
}

fn checked_prepare(model: &dyn Model, data: &Dataset, config: &Config) -> Result<Prepared> {
    config.check(model.dof())?;
    if data.dof() != model.dof() {
        return Err(Error::JointCountMismatch {
            context: format!("data set {}", data.name),
            expected: model.dof(),
            found: data.dof(),
        });
    }
    prepare(data, config)
}

fn torque_observation(
    model: &(dyn Model + Sync),
    prepared: &Prepared,
    config: &Config,
) -> Result<(Observation, f64)> {
    let obs = observe(model, prepared, config)?;
    let dt = prepared.sample_time * decimator(config)?.factor() as f64;
    Ok((obs, dt))
}

/// The energy model's observation of prepared signals (windows of
/// `estimation.energy_window` seconds); extra columns are not part of it.
pub fn energy_observation_of(
    model: &(dyn Model + Sync),
    prepared: &Prepared,
    config: &Config,
) -> Result<Observation> {
    if let Some(c) = config.extra_columns.first() {
        return Err(Error::InvalidConfig {
            key: "estimation.method".into(),
            problem: format!(
                "the energy model has no power term for the extra column `{}`; use ols, wls or rls with extra columns",
                c.name
            ),
        });
    }
    let window = (config.estimation.energy_window / prepared.sample_time).round() as usize;
    model_energy_observation(model, prepared, window.max(1))
}

/// Estimates with the configured method.
pub fn estimate(obs: &Observation, config: &Config) -> Result<Estimate> {
    let e = &config.estimation;
    match e.method {
        Method::Ols => ols(obs, e.rank_tolerance),
        Method::Wls => wls(obs, e.rank_tolerance),
        Method::Rls => rls(obs, e.forgetting, e.rank_tolerance),
        Method::Energy => Err(Error::InvalidConfig {
            key: "estimation.method".into(),
            problem: "the energy model is built from the signals, not from a torque observation: use pipeline::identify".into(),
        }),
    }
}

/// The whole pipeline: observation matrix from `data`, estimation, fit. With the energy
/// method the parameters come from the energy observation and the fit is still the
/// torque prediction of the (filtered, decimated) torque observation.
pub fn identify(
    model: &(dyn Model + Sync),
    data: &Dataset,
    config: &Config,
) -> Result<Identification> {
    let prepared = checked_prepare(model, data, config)?;
    let estimate_of = |obs: &Observation| match config.estimation.method {
        Method::Energy => energy(
            &energy_observation_of(model, &prepared, config)?,
            config.estimation.rank_tolerance,
        ),
        _ => estimate(obs, config),
    };
    let (obs, dt) = torque_observation(model, &prepared, config)?;
    let estimate = estimate_of(&obs)?;
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
