//! From a model, data and a config to identified parameters, fit and validation.
//!
//! Every entry point checks the config against the model, places errors about config keys
//! at their file:line ([`Config::locate`]), names a data row by its file:line, and checks
//! what it returns: no NaN or infinity in a successful result.

use crate::DataError;
use crate::EstimateError;
use crate::estimate::error::{own_parameters, solves_alone};
use crate::pipeline::observe::{
    RestCount, check_observation_size, long_enough, observe_counted, speed_unit,
};
use std::ops::Range;

use crate::data::{
    Config, Dataset, Estimation, Method, ParameterFile, Record, Warning, check_joints,
};
use crate::error::{Error, Result, num};
use crate::estimate::{
    CONDITION_WARNING, ENERGY_CONDITION_RATIO, Estimate, KnownParameters, Observation,
    QualityWarning, dominated_columns, energy, link_by_link, model_energy_observation, ols_with,
    per_axis, rls, wls_with,
};
use crate::inspect::CutoffSuggestion;
use crate::pipeline::prepare::{Plan, PreparedRows, Rows, prepare_rows};
use crate::pipeline::stream::{identify_streaming, streams, validate_streaming};
use crate::pipeline::{Prepared, decimator};
use crate::validate::{Fit, Prediction, UsedRows};
use crate::{Model, Num};

/// The result of [`identify`].
#[derive(Debug, Clone)]
pub struct Identification {
    /// Robot name (from the model).
    pub robot: String,
    /// Estimated parameters (base parameters, then extra columns), with their quality
    /// warnings (`estimate.warnings`).
    pub estimate: Estimate,
    /// Fit on the estimation data.
    pub fit: Fit,
    /// Measured vs predicted on the estimation data.
    pub prediction: Prediction,
    /// Warnings from loading.
    pub warnings: Vec<Warning>,
    /// The rows of the data used for estimation.
    pub used: UsedRows,
    /// The cutoff chosen for `cutoff = "auto"` (validation data get their own unless the
    /// config is resolved first with [`crate::inspect::resolve_cutoff`]).
    pub cutoff: Option<CutoffSuggestion>,
    /// The unit of each joint's torque, by its kind
    /// ([`joint_units`](crate::report::joint_units)): "N m" or "N".
    pub joint_units: Vec<&'static str>,
}

/// Builds the observation of a data set: prepare (with `processing.range`), regressor,
/// decimate, stack. Returns it with the decimated sample time.
pub fn observation(
    model: &(dyn Model + Sync),
    data: &Dataset,
    config: &Config,
) -> Result<(Observation, f64)> {
    observation_counted(model, data, config).map(|c| (c.obs, c.dt))
}

/// The samples (decimated) over which the processing correlates the residuals: the
/// low-pass's `sample rate / (decimation x cutoff)` (its `cutoff = "auto"` as `auto`
/// chose it), the time a Butterworth filter of that cutoff takes to forget, 0 without a
/// low-pass (the decimation filter's own correlation, a sample or two, Newey and West's
/// rule covers: [`robust_lag`](crate::estimate::robust_lag)). Two cutoff periods, and a
/// Savitzky-Golay window counted besides, moved the robust deviations no closer to the
/// spread over records (`robots/examples/robust_calibration.rs`,
/// docs/identification.md#robust-standard-deviations).
pub(crate) fn correlated_samples(
    config: &Config,
    auto: Option<&CutoffSuggestion>,
    sample_time: f64,
) -> Result<usize> {
    let factor = decimator(config).map_err(|e| config.locate(e))?.factor();
    let cutoff = config.processing.lowpass.as_ref().and_then(|lp| {
        auto.map(|a| a.cutoff)
            .or_else(|| lp.cutoff.hz())
            .filter(|c| *c > 0.0 && c.is_finite())
    });
    Ok(cutoff.map_or(0, |c| {
        (1.0 / (sample_time * factor as f64 * c)).ceil().min(1e9) as usize
    }))
}

/// An observation with what its preparation left to say of it ([`observation_counted`]).
pub(crate) struct CountedObservation {
    pub(crate) obs: Observation,
    /// The decimated sample time.
    pub(crate) dt: f64,
    /// What the removal of the equations near rest left.
    pub(crate) rest: RestCount,
    /// The torques before filtering at the equations, per joint, when they are filtered.
    pub(crate) unfiltered: Option<Vec<Vec<f64>>>,
}

/// [`observation`] with what the removal of the equations near rest left of them
/// ([`RestCount`], for [`rest_cause`]) and, when its torques are filtered, the torques
/// before the filter at its equations ([`unfiltered_torque`]).
pub(crate) fn observation_counted(
    model: &(dyn Model + Sync),
    data: &Dataset,
    config: &Config,
) -> Result<CountedObservation> {
    let rows = checked_prepare(model, data, config, Rows::Estimation)?;
    let (mut obs, dt, rest) = torque_observation(model, &rows.prepared, config, data, &rows.kept)?;
    obs.correlated = correlated_samples(config, rows.auto_cutoff.as_ref(), data.sample_time)?;
    let factor = decimator(config).map_err(|e| config.locate(e))?.factor();
    let unfiltered = unfiltered_torque(&obs, &rows, factor);
    Ok(CountedObservation {
        obs,
        dt,
        rest,
        unfiltered,
    })
}

pub(crate) fn checked_prepare(
    model: &dyn Model,
    data: &Dataset,
    config: &Config,
    rows: Rows,
) -> Result<PreparedRows> {
    check_data(model, data, config)?;
    prepare_rows(data, config, rows).map_err(|e| config.locate(e))
}

/// The plan of the preparation of `data`'s signals (checked as [`checked_prepare`]
/// checks them), for preparing them block by block.
pub(crate) fn checked_plan(
    model: &dyn Model,
    data: &dyn Record,
    config: &Config,
    rows: Rows,
) -> Result<Plan> {
    check_data(model, data, config)?;
    Plan::new(data, config, rows).map_err(|e| config.locate(e))
}

/// The model's joint count against the limit, the config and the data.
fn check_data(model: &dyn Model, data: &dyn Record, config: &Config) -> Result<()> {
    check_joints(model.dof())?;
    config.check(model.dof())?;
    if data.dof() != model.dof() {
        return Err(Error::Data(DataError::JointCountMismatch {
            context: format!("data set {}", data.name()),
            expected: model.dof(),
            found: data.dof(),
        }));
    }
    Ok(())
}

/// The observation of prepared signals that are the samples `kept` of `data`; a
/// non-finite equation is named by its data row.
fn torque_observation(
    model: &(dyn Model + Sync),
    prepared: &Prepared,
    config: &Config,
    data: &Dataset,
    kept: &Range<usize>,
) -> Result<(Observation, f64, RestCount)> {
    let (obs, rest) = observe_counted(model, prepared, config, data.name()).map_err(|e| {
        e.placed(|k| (kept.start + k, data.location(kept.start + k)))
            .unwrap_or_else(|e| config.locate(e))
    })?;
    let dt =
        prepared.sample_time * decimator(config).map_err(|e| config.locate(e))?.factor() as f64;
    Ok((obs, dt, rest))
}

/// The energy model's observation of prepared signals (windows of
/// `estimation.energy_window` seconds); extra columns are not part of it.
pub fn energy_observation_of(
    model: &(dyn Model + Sync),
    prepared: &Prepared,
    config: &Config,
) -> Result<Observation> {
    if let Some(c) = config.extra_columns_for(model.dof())?.first() {
        return Err(config.key_error(
            "estimation.method",
            format!(
                "the energy model has no power term for the extra column `{}`; use ols, wls or rls with extra columns",
                c.name
            ),
        ));
    }
    let seconds = config.estimation.energy_window;
    let window = (seconds / prepared.sample_time).round() as usize;
    if window == 0 {
        // it was taken as one sample: 10 000 windows of one step each, fit 132 %
        return Err(config.key_error(
            "estimation.energy_window",
            format!(
                "{} s is less than half of the sample time ({} s): a window spans at least \
                 one step (the default is 0.05 s)",
                crate::num(seconds),
                crate::num(prepared.sample_time)
            ),
        ));
    }
    // one equation per window: too few windows for the parameters is the window's doing
    // (a 5 s window on 10 s was told "2 samples ... use less decimation")
    let samples = prepared.samples();
    let windows = samples.saturating_sub(1) / window;
    let needed = crate::estimate::equations_needed(model.base_parameter_count());
    if windows < needed {
        let longest = samples.saturating_sub(1) / needed;
        return Err(config.key_error(
            "estimation.energy_window",
            format!(
                "{} s windows give {} of the record's {} s (one equation each), and the {} \
                 need at least {needed}; {}",
                crate::num(seconds),
                crate::Count(windows, "window"),
                crate::num(samples.saturating_sub(1) as f64 * prepared.sample_time),
                crate::Count(model.base_parameter_count(), "parameter"),
                if longest == 0 {
                    "record a longer trajectory".to_owned()
                } else {
                    format!(
                        "use windows of at most {} s, or a longer record",
                        crate::num(longest as f64 * prepared.sample_time)
                    )
                }
            ),
        ));
    }
    model_energy_observation(model, prepared, window)
}

/// Replaces the generic ill-conditioning warning of an energy estimate by one that compares
/// it with the torque model on the same samples, and raises it also when the energy
/// model is more than [`ENERGY_CONDITION_RATIO`] times worse conditioned.
fn energy_conditioning(estimate: &mut Estimate, torque: &Observation) -> Result<()> {
    let cond = crate::estimate::condition_number(&torque.w, &torque.names)?.raw;
    let energy = estimate.condition_number;
    if energy > CONDITION_WARNING || energy > ENERGY_CONDITION_RATIO * cond {
        estimate
            .warnings
            .retain(|w| !matches!(w, QualityWarning::IllConditioned { .. }));
        estimate.warnings.insert(
            0,
            QualityWarning::EnergyIllConditioned {
                energy,
                torque: cond,
                energy_equations: estimate.rows,
                torque_equations: torque.w.nrows(),
            },
        );
    }
    Ok(())
}

/// Gives `prediction` the torque before any low-pass at its samples, when its measured
/// torque is filtered ([`unfiltered_torque`]).
fn with_unfiltered(
    prediction: &mut Prediction,
    obs: &Observation,
    rows: &PreparedRows,
    factor: usize,
) {
    if let Some(raw) = unfiltered_torque(obs, rows, factor) {
        prediction.unfiltered = Some(raw);
    }
}

/// The torque before any low-pass at each equation of `obs`, per joint, when its measured
/// torque is filtered: by `[processing] lowpass` on `tau`, or by the anti-alias filter of
/// a decimation (`factor` > 1; decimated sample k is processed sample k * factor); `None`
/// when the torque is not filtered.
pub(crate) fn unfiltered_torque(
    obs: &Observation,
    rows: &PreparedRows,
    factor: usize,
) -> Option<Vec<Vec<f64>>> {
    let raw = match &rows.unfiltered_tau {
        Some(raw) => raw,
        None if factor > 1 => &rows.prepared.tau,
        None => return None,
    };
    Some(
        obs.joint_rows
            .iter()
            .enumerate()
            .map(|(j, r)| {
                obs.sample_of_row[r.clone()]
                    .iter()
                    .map(|&k| raw[j][k * factor])
                    .collect()
            })
            .collect(),
    )
}

/// Estimates with the configured method.
pub fn estimate(obs: &Observation, config: &Config) -> Result<Estimate> {
    let e = &config.estimation;
    let result = match e.method {
        Method::Ols => ols_with(obs, e.rank_tolerance, e.robust_std),
        Method::Wls => wls_with(obs, e.rank_tolerance, e.robust_std),
        Method::Rls => rls(obs, e.forgetting, e.rank_tolerance),
        Method::PerAxis => per_axis(obs, e.rank_tolerance)
            .map(|p| p.estimate)
            .map_err(|e| rest_removed(e, config, obs.joint_rows.len())),
        Method::LinkByLink => link_by_link(obs, e.forgetting, e.rank_tolerance)
            .map_err(|e| rest_removed(e, config, obs.joint_rows.len())),
        Method::Energy => Err(Error::setting(
            "Config",
            "estimation.method",
            "the energy model is built from the signals, not from a torque observation: use pipeline::identify",
        )),
    };
    result.map_err(|e| config.locate(e))
}

/// [`EstimateError::AxisLacksEquations`] of per-axis or link-by-link identification said as
/// the `processing.rest_velocity` that removed the joint's equations (`dof` joints), with
/// its value for that joint and the list that keeps them all; other errors as they are.
fn rest_removed(e: Error, config: &Config, dof: usize) -> Error {
    let Error::Estimate(EstimateError::AxisLacksEquations {
        method,
        joint,
        found,
        required,
        ..
    }) = e
    else {
        return e;
    };
    let key = "processing.rest_velocity";
    let Ok(mut values) = config.processing.rest_velocities(dof) else {
        return e;
    };
    let Some(v) = joint.checked_sub(1).and_then(|j| values.get_mut(j)) else {
        return e;
    };
    let threshold = format!("{} {}", num(*v), speed_unit(&config.prismatic, joint - 1));
    *v = 0.0;
    let list = values
        .iter()
        .map(|&x| num(x))
        .collect::<Vec<_>>()
        .join(", ");
    let (what, fix) = if found == 0 {
        (
            format!(
                "{threshold} removes every equation of joint {joint}: its |velocity| \
                 stays below it in the whole record"
            ),
            format!(
                "move joint {joint} in the trajectory (at rest in the whole record, it leaves \
                 parameters undetermined whatever rest_velocity), or, if it moves slower than \
                 {threshold}, lower rest_velocity for it"
            ),
        )
    } else {
        (
            format!(
                "{threshold} leaves joint {joint} {found} equations (where its |velocity| \
                 reaches it), {} the {required} {}",
                crate::estimate::error::short_of(found, required),
                own_parameters(method)
            ),
            format!("move joint {joint} more in the trajectory, or lower rest_velocity for it"),
        )
    };
    Error::setting(
        "Config",
        key,
        format!(
            "{what}, and {} identification {}: {fix} (`rest_velocity = [{list}]` keeps all its \
             equations)",
            method.name(),
            solves_alone(method)
        ),
    )
}

/// A rank deficiency said as the removal of the equations near rest when it took (nearly)
/// all of a joint's ([`RestCount::rank_cause`]); other errors as they are. One record's
/// equations, or the stacked runs' (`rest` summed over the runs).
pub(crate) fn rest_cause(rest: &RestCount, config: &Config, dof: usize, e: Error) -> Error {
    // a tolerance raised far above the default cuts singular values that data of any
    // richness have (0.5 was told as "use a richer trajectory"): said at its key
    let tolerance = config.estimation.rank_tolerance;
    let default = Estimation::default().rank_tolerance;
    if let Error::Estimate(EstimateError::RankDeficient {
        rank,
        columns,
        unexcited,
    }) = &e
        && tolerance > 1e3 * default
    {
        return Error::setting(
            "Config",
            "estimation.rank_tolerance",
            format!(
                "{} counts singular values below {} times the largest as zero (default {:e}): \
                 rank {rank} of {columns} parameters, {}; lower it (the data \
                 may be rich enough), or use a richer trajectory",
                Num(tolerance),
                Num(tolerance),
                default,
                crate::estimate::not_excited(*rank, *columns, unexcited),
            ),
        );
    }
    let thresholds = config.processing.rest_velocities(dof).ok();
    let in_file = !matches!(
        config.mapping("processing.rest_velocity"),
        crate::data::ColumnMapping::Default | crate::data::ColumnMapping::Code
    );
    rest.rank_cause(thresholds.as_deref(), e, in_file, &config.prismatic)
}

/// The whole pipeline: observation matrix from `data`, estimation, fit. With the energy
/// method the parameters come from the energy observation and the fit is still the
/// torque prediction of the (filtered, decimated) torque observation.
///
/// OLS and WLS without known parameters stream: they never hold the observation matrix
/// (`pipeline::stream`, docs/identification.md#streaming-least-squares); the other
/// methods build it.
pub fn identify(
    model: &(dyn Model + Sync),
    data: &dyn Record,
    config: &Config,
) -> Result<Identification> {
    let mut id = if streams(config) {
        let plan = checked_plan(model, data, config, Rows::Estimation)?;
        identify_streaming(model, data, config, &plan)?
    } else {
        check_data(model, data, config)?;
        // the observation's size before the record is read: at least the samples of
        // processing.range less the trims, each with a torque, a velocity and the base
        // parameters' columns per joint
        let p = &config.processing;
        let span = p.range.map_or(data.samples(), |[a, b]| b.saturating_sub(a));
        check_observation_size(
            span.saturating_sub(2 * p.trim),
            model.dof() * (model.base_parameter_count() + 2),
        )?;
        let whole = data.read(0, data.samples())?;
        let rows = checked_prepare(model, &whole, config, Rows::Estimation)?;
        identify_dense(model, &whole, config, rows)?
    };
    id.estimate
        .warnings
        .extend(super::advice::processing_warnings(config, data)?);
    let unphysical = not_physical_warnings(model, config, &id.estimate)?;
    id.estimate.warnings.extend(unphysical);
    Ok(id)
}

/// The `not_physical` warnings of `estimate`, an identification of `model` with `config`:
/// each base parameter or extra column whose sign every physical robot fixes, estimated on
/// the other side of zero by more than [`NOT_PHYSICAL_Z`](crate::estimate::NOT_PHYSICAL_Z)
/// of the larger of its classical and robust standard deviations
/// ([`not_physical`](crate::estimate::not_physical)), then a joint's friction all below zero
/// ([`opposite_signs`](crate::estimate::opposite_signs)).
pub(crate) fn not_physical_warnings(
    model: &dyn Model,
    config: &Config,
    estimate: &Estimate,
) -> Result<Vec<QualityWarning>> {
    let extra = config
        .extra_columns_for(model.dof())
        .map_err(|e| config.locate(e))?;
    let signs = crate::estimate::signs_of(model, &extra)?;
    let mut warnings = crate::estimate::not_physical(
        &estimate.names,
        &estimate.values,
        &estimate.std,
        estimate.robust.as_ref().map(|r| r.std.as_slice()),
        &signs,
    );
    warnings.extend(crate::estimate::opposite_signs(
        &warnings,
        &estimate.names,
        model.dof(),
    ));
    Ok(warnings)
}

/// [`identify`] through the whole observation matrix (every method; the reference of the
/// streaming path in tests).
pub(crate) fn identify_dense(
    model: &(dyn Model + Sync),
    data: &Dataset,
    config: &Config,
    rows: PreparedRows,
) -> Result<Identification> {
    let (prepared, kept) = (&rows.prepared, &rows.kept);
    let known = known_parameters(model, config)?;
    let tolerance = config.estimation.rank_tolerance;
    // the system the method solves, reduced by the known parameters
    // the system the method solves (borrowed, not copied, unless the energy model or the
    // known parameters make a new one), then the estimate of every base parameter
    let estimate_of = |obs: &Observation| -> Result<Estimate> {
        let energy_system;
        let system = match config.estimation.method {
            Method::Energy => {
                energy_system = energy_observation_of(model, prepared, config)?;
                &energy_system
            }
            _ => obs,
        };
        let solve = |system: &Observation| match config.estimation.method {
            Method::Energy => energy(system, tolerance).map_err(|e| config.locate(e)),
            _ => estimate(system, config),
        };
        match &known {
            Some(k) => {
                let reduced = k.reduce(system).map_err(|e| config.locate(e))?;
                k.expand(&solve(&reduced)?, system, &reduced, tolerance)
                    .map_err(|e| config.locate(e))
            }
            None => solve(system),
        }
    };
    let (mut obs, dt, rest) = torque_observation(model, prepared, config, data, kept)?;
    obs.correlated = correlated_samples(config, rows.auto_cutoff.as_ref(), data.sample_time)?;
    if config.estimation.method != Method::Energy {
        let known = known.as_ref().map_or(0, |k| k.known_names().len());
        long_enough(data, kept, model.dof(), obs.cols().saturating_sub(known))?;
    }
    let factor = decimator(config).map_err(|e| config.locate(e))?.factor();
    // the data row of an equation
    let location = |row: usize| {
        let k = obs.sample_of_row.get(row).copied().unwrap_or(0);
        data.location(kept.start + k * factor)
    };
    let dominated = dominated_columns(&obs.w);
    let pieces = pieces_of(&obs, config, data, kept.start, factor)?;
    let mut estimate = estimate_of(pieces.as_ref().unwrap_or(&obs)).map_err(|e| match e {
        Error::Estimate(EstimateError::RankDeficient { ref unexcited, .. }) => {
            match dominated
                .iter()
                .find(|(c, _, _)| unexcited.contains(&obs.names[*c]))
            {
                Some(&(c, row, share)) => Error::Estimate(EstimateError::Outlier {
                    location: location(row),
                    parameter: obs.names[c].clone(),
                    share,
                }),
                None => config.locate(rest_cause(&rest, config, model.dof(), e)),
            }
        }
        e => e,
    })?;
    if let Some(k) = &known {
        estimate.warnings.extend(known_without_effect(model, k));
    }
    if config.estimation.method == Method::Energy {
        let reduced = match &known {
            Some(k) => Some(k.reduce(&obs).map_err(|e| config.locate(e))?),
            None => None,
        };
        energy_conditioning(&mut estimate, reduced.as_ref().unwrap_or(&obs))
            .map_err(|e| config.locate(e))?;
    }
    for &(c, row, share) in &dominated {
        estimate.warnings.push(QualityWarning::Outlier {
            parameter: obs.names[c].clone(),
            location: location(row),
            share,
        });
    }
    // the samples of the equations: every factor-th, less those the decimation filter's
    // settling left out at the ends and the ends' samples near rest
    let (first, last) = obs
        .sample_of_row
        .iter()
        .fold((usize::MAX, 0), |(a, b), &k| (a.min(k), b.max(k)));
    let used = UsedRows::of(data, kept.clone()).with_equations(
        data,
        kept.start + first.min(last) * factor,
        kept.start + last * factor,
        factor,
    );
    let mut prediction = Prediction::new(&obs, &estimate.values, dt)?
        .starting_at(kept.start as f64 * data.sample_time);
    with_unfiltered(&mut prediction, &obs, &rows, factor);
    prediction.check(&format!("the estimation data ({used})"))?;
    prediction.used = Some(used.clone());
    estimate.warnings.extend(prediction.warnings());
    Ok(Identification {
        robot: model.name().to_string(),
        fit: prediction.fit(),
        prediction,
        estimate,
        warnings: data.warnings.clone(),
        used,
        cutoff: rows.auto_cutoff.clone(),
        joint_units: crate::report::joint_units(&config.prismatic, model.dof()),
    })
}

/// The rows of `obs` within `processing.pieces` (Milella's piece-wise estimation), if the
/// config has pieces: decimated sample k is record sample `start + k * factor`.
fn pieces_of(
    obs: &Observation,
    config: &Config,
    data: &Dataset,
    start: usize,
    factor: usize,
) -> Result<Option<Observation>> {
    let Some(pieces) = &config.processing.pieces else {
        return Ok(None);
    };
    let time = |k: usize| (start + k * factor) as f64 * data.sample_time;
    let inside = |k: usize| pieces.iter().any(|[a, b]| (*a..=*b).contains(&time(k)));
    let mut selected = obs.select_samples(inside)?;
    // each piece is a segment of its own: no lag of the robust deviations reaches across
    selected.breaks = piece_breaks(obs.sample_of_row.iter().max().map_or(0, |m| m + 1), inside);
    if selected.rows() < crate::estimate::equations_needed(obs.cols()) {
        return Err(config.key_error(
            "processing.pieces",
            format!(
                "the pieces hold {} equations of the estimation range, no more than the {} \
                 parameters; check that they are in seconds from the record's first sample \
                 and inside processing.range",
                selected.rows(),
                obs.cols()
            ),
        ));
    }
    Ok(Some(selected))
}

/// The decimated samples, of `samples`, that start a piece: inside one and after a sample
/// that is not (or first).
pub(crate) fn piece_breaks(samples: usize, inside: impl Fn(usize) -> bool) -> Vec<usize> {
    (0..samples)
        .filter(|&k| inside(k) && (k == 0 || !inside(k - 1)))
        .collect()
}

/// [`QualityWarning::KnownWithoutEffect`] of the known parameters `k` of `model` that fix
/// nothing, if any.
fn known_without_effect(model: &dyn Model, k: &KnownParameters) -> Option<QualityWarning> {
    let names = crate::model::standard_parameter_names(model);
    (!k.without_effect().is_empty()).then(|| QualityWarning::KnownWithoutEffect {
        parameters: k
            .without_effect()
            .iter()
            .filter_map(|&i| names.get(i).cloned())
            .collect(),
    })
}

/// [`estimate`] of the torque observation `obs` of `model` with the standard parameters of
/// `estimation.known` fixed: reduced, solved and expanded to every base parameter, with
/// the warning of those that fix nothing (the stacked runs and segments; a single record
/// takes [`identify_dense`], which also serves the energy model).
pub(crate) fn estimate_with_known(
    model: &dyn Model,
    obs: &Observation,
    config: &Config,
) -> Result<Estimate> {
    let Some(k) = known_parameters(model, config)? else {
        return estimate(obs, config);
    };
    let reduced = k.reduce(obs).map_err(|e| config.locate(e))?;
    let mut e = k
        .expand(
            &estimate(&reduced, config)?,
            obs,
            &reduced,
            config.estimation.rank_tolerance,
        )
        .map_err(|e| config.locate(e))?;
    e.warnings.extend(known_without_effect(model, &k));
    Ok(e)
}

/// The regrouping with the standard parameters of `estimation.known` fixed, if the config
/// names a file (resolved against the config's folder).
/// The parameters the torque equations estimate for `model` with `config`: the base
/// parameters and the extra columns, less those `estimation.known` fixes (what
/// `long_enough` counts); 0 for the energy model, whose equations are not the torques'.
pub(crate) fn estimated_parameters(model: &dyn Model, config: &Config) -> Result<usize> {
    if config.estimation.method == Method::Energy {
        return Ok(0);
    }
    let known = known_parameters(model, config)?.map_or(0, |k| k.known_names().len());
    let columns = model.base_parameter_count() + config.extra_columns_for(model.dof())?.len();
    Ok(columns.saturating_sub(known))
}

fn known_parameters(model: &dyn Model, config: &Config) -> Result<Option<KnownParameters>> {
    let Some(file) = &config.estimation.known else {
        return Ok(None);
    };
    let path = config.resolve(file);
    let names = crate::model::standard_parameter_names(model);
    let values = ParameterFile::read(&path)?.known(&names)?;
    let known = KnownParameters::new(model, &values).map_err(|e| config.locate(e))?;
    if known.kept_names().is_empty() && config.extra_columns_for(model.dof())?.is_empty() {
        return Err(config.key_error(
            "estimation.known",
            format!(
                "the known values in {} fix every base parameter: nothing is left to identify; \
                 list fewer known parameters",
                path.display()
            ),
        ));
    }
    Ok(Some(known))
}

/// Predicts the torques of another data set with identified values (base parameters then
/// extra columns, as in [`Estimate::values`]), processed like the estimation data but on
/// its own: `processing.validation_range` applies (default: the whole data set), not the
/// estimation's `processing.range`. The prediction records the rows used. It streams:
/// the observation matrix is never held, only the measured and predicted torques.
pub fn validate(
    model: &(dyn Model + Sync),
    data: &dyn Record,
    config: &Config,
    values: &[f64],
) -> Result<Prediction> {
    let plan = checked_plan(model, data, config, Rows::Validation)?;
    validate_streaming(model, data, config, &plan, values)
}

/// [`identify`] through the whole observation matrix whatever the method: the reference
/// of the streaming path in tests.
#[cfg(test)]
pub(crate) fn identify_dense_of(
    model: &(dyn Model + Sync),
    data: &Dataset,
    config: &Config,
) -> Result<Identification> {
    let rows = checked_prepare(model, data, config, Rows::Estimation)?;
    let mut id = identify_dense(model, data, config, rows)?;
    // as `identify` judges every estimate
    let unphysical = not_physical_warnings(model, config, &id.estimate)?;
    id.estimate.warnings.extend(unphysical);
    Ok(id)
}

/// [`validate`] through the whole observation matrix: the reference of the streaming
/// path in tests.
#[cfg(test)]
pub(crate) fn validate_dense(
    model: &(dyn Model + Sync),
    data: &Dataset,
    config: &Config,
    values: &[f64],
) -> Result<Prediction> {
    let rows = checked_prepare(model, data, config, Rows::Validation)?;
    let (obs, dt, _) = torque_observation(model, &rows.prepared, config, data, &rows.kept)?;
    if values.len() != obs.cols() {
        return Err(Error::DimensionMismatch {
            what: "parameter values".into(),
            expected: obs.cols(),
            found: values.len(),
        });
    }
    if let Some(i) = values.iter().position(|v| !v.is_finite()) {
        return Err(Error::setting(
            "validate",
            "values",
            format!(
                "the value of `{}` is {}; give finite identified values",
                obs.names[i], values[i]
            ),
        ));
    }
    let used = UsedRows::of(data, rows.kept.clone());
    let mut prediction =
        Prediction::new(&obs, values, dt)?.starting_at(rows.kept.start as f64 * data.sample_time);
    let factor = decimator(config).map_err(|e| config.locate(e))?.factor();
    with_unfiltered(&mut prediction, &obs, &rows, factor);
    prediction.check(&format!("the validation data ({used})"))?;
    prediction.used = Some(used);
    Ok(prediction)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::estimate::Estimator;
    use nalgebra::{DMatrix, DVector};

    /// A torque observation with orthogonal columns of equal norm (condition number 1) and
    /// energy estimates of chosen condition numbers: the warning is raised exactly above
    /// the ratio or the absolute threshold, names both figures and replaces the generic one.
    #[test]
    fn an_energy_estimate_is_compared_with_the_torque_model() {
        let w = DMatrix::from_row_slice(4, 2, &[1.0, 0.0, 0.0, 1.0, 2.0, 0.0, 0.0, 2.0]);
        let names = vec!["a".to_string(), "b".to_string()];
        let torque = Observation::new(
            w,
            DVector::zeros(4),
            vec![0..2, 2..4],
            vec![0, 1, 2, 3],
            names.clone(),
        )
        .unwrap();
        let estimate = |cond: f64| Estimate {
            method: Estimator::Energy,
            names: names.clone(),
            values: vec![1.0, 2.0],
            std: vec![0.1, 0.1],
            rel_std_percent: vec![10.0, 5.0],
            sigma2: 1.0,
            condition_number: cond,
            scaled_condition_number: Some(cond),
            error_bound: 0.5,
            residual_rms: vec![0.1],
            rows: 3,
            weights: None,
            warnings: vec![QualityWarning::IllConditioned {
                condition_number: cond,
                threshold: CONDITION_WARNING,
            }],
            known: Vec::new(),
            robust: None,
        };
        for (cond, raised) in [(3.9, false), (4.1, true), (2e4, true)] {
            let mut e = estimate(cond);
            energy_conditioning(&mut e, &torque).unwrap();
            let first = &e.warnings[0];
            assert_eq!(
                matches!(first, QualityWarning::EnergyIllConditioned { .. }),
                raised,
                "{cond}"
            );
            if raised {
                let QualityWarning::EnergyIllConditioned {
                    energy,
                    torque,
                    energy_equations,
                    torque_equations,
                } = first
                else {
                    unreachable!()
                };
                assert_eq!(*energy, cond);
                assert!((torque - 1.0).abs() < 1e-12, "{torque}");
                assert_eq!((*energy_equations, *torque_equations), (3, 4));
                assert_eq!(e.warnings.len(), 1, "the generic warning is replaced");
                assert!(first.to_string().contains("--method wls or ols"));
            } else {
                assert_eq!(e.warnings.len(), 1);
            }
        }
    }
}
