//! Repeated acquisitions of one trajectory (`[runs]`): each run identified on its own, the
//! runs identified together (stacked equations, or the sample-wise mean of the records),
//! and the run-to-run spread of every parameter
//! (docs/identification.md#repeated-acquisitions).
//!
//! F. Milella, "Direct Estimate of Closed-Form Dynamic Equation Parameters of a Robot:
//! Tools and Methods for Designing Experiments" (docs/references.md#milella), Phase IV:
//! ten acquisitions of each trajectory and their maximum variations (Fig. 3).

use crate::Model;
use crate::data::{Config, Dataset, RunMode, joined_with};
use crate::error::{Error, Result};
use crate::estimate::{Estimate, Observation};
use crate::inspect::CutoffSuggestion;
use crate::pipeline::identify::{
    estimate_with_known, estimated_parameters, not_physical_warnings, observation_counted,
    rest_cause,
};
use crate::pipeline::observe::RestCount;
use crate::pipeline::prepare::samples_needed;
use crate::pipeline::stream::{stacked_streaming, streams};
use crate::pipeline::{Identification, identify};
use crate::signal::Signals;
use crate::validate::{Fit, Prediction, UsedRows};

/// The spread of the runs identified one by one.
#[derive(Debug, Clone, PartialEq)]
pub struct RunSpread {
    /// Parameter names.
    pub names: Vec<String>,
    /// The values of each run (`values[run][parameter]`).
    pub values: Vec<Vec<f64>>,
    /// Per parameter, the mean of the runs' values.
    pub mean: Vec<f64>,
    /// Per parameter, the sample standard deviation of the runs' values (divided by
    /// runs - 1): the spread actually seen.
    pub std: Vec<f64>,
    /// Per parameter, the root mean square of the standard deviations each run reports:
    /// the spread the statistics of one run predict.
    pub reported_std: Vec<f64>,
    /// Per joint, the root mean square over the samples of the sample-wise standard
    /// deviation of the measured torque across the runs (N m); `None` when the runs do not
    /// share one time grid.
    pub torque_std: Option<Vec<f64>>,
}

/// The result of [`identify_runs`].
#[derive(Debug, Clone)]
pub struct RepeatedIdentification {
    /// Robot name.
    pub robot: String,
    /// The unit of each joint's torque ([`Identification::joint_units`]).
    pub joint_units: Vec<&'static str>,
    /// How the runs were combined.
    pub mode: RunMode,
    /// The estimate from all runs together.
    pub estimate: Estimate,
    /// Its fit on the combined data (stacked: the runs end to end; averaged: the mean
    /// record).
    pub fit: Fit,
    /// Measured against predicted on the combined data.
    pub prediction: Prediction,
    /// The rows of the mean record (averaged mode: the same lines of every run's file,
    /// `file` naming them all); `None` for stacked runs.
    pub used: Option<UsedRows>,
    /// The cutoff chosen for `cutoff = "auto"` on the combined data (averaged mode).
    pub cutoff: Option<CutoffSuggestion>,
    /// Each run identified alone, in order.
    pub runs: Vec<Identification>,
    /// The run-to-run spread.
    pub spread: RunSpread,
}

/// Identifies repeated acquisitions `runs` of one trajectory with `config` (its `[runs]
/// mode`, stacked when the config has no `[runs]`): every run alone, then all together,
/// with the spread across the runs. At least two runs. An error of one run's data is an
/// [`Error::Run`] naming the run ([`Config::run_error`]).
pub fn identify_runs(
    model: &(dyn Model + Sync),
    runs: &[Dataset],
    config: &Config,
) -> Result<RepeatedIdentification> {
    if runs.len() < 2 {
        return Err(config.key_error(
            "runs.files",
            format!(
                "{}: repeated acquisitions need at least two",
                crate::Count(runs.len(), "run")
            ),
        ));
    }
    let mode = config.runs.as_ref().map(|r| r.mode).unwrap_or_default();
    check_lengths(model, runs, config)?;
    let each = runs
        .iter()
        .enumerate()
        .map(|(i, d)| identify(model, d, config).map_err(|e| config.run_error(i, &d.name, e)))
        .collect::<Result<Vec<_>>>()?;
    let spread = spread(&each, runs)?;
    let robot = model.name().to_string();
    Ok(match mode {
        RunMode::Averaged => {
            let mean = average(runs).map_err(|e| config.locate(e))?;
            let id = identify(model, &mean, config)?;
            // the same rows of every run's file (the first alone was named)
            let files: Vec<&str> = each.iter().map(|r| r.used.file.as_str()).collect();
            let used = UsedRows {
                file: format!("the mean of {}", files.join(", ")),
                ..id.used
            };
            RepeatedIdentification {
                robot,
                joint_units: crate::report::joint_units(&config.prismatic, model.dof()),
                mode,
                estimate: id.estimate,
                fit: id.fit,
                prediction: id.prediction,
                used: Some(used),
                cutoff: id.cutoff,
                runs: each,
                spread,
            }
        }
        RunMode::Stacked => {
            let (mut estimate, prediction) = if streams(config) {
                stacked_streaming(model, runs, config)?
            } else {
                stacked_dense(model, runs, config)?
            };
            let unphysical = not_physical_warnings(model, config, &estimate)?;
            estimate.warnings.extend(unphysical);
            RepeatedIdentification {
                robot,
                joint_units: crate::report::joint_units(&config.prismatic, model.dof()),
                mode,
                fit: prediction.fit(),
                estimate,
                prediction,
                used: None,
                cutoff: None,
                runs: each,
                spread,
            }
        }
    })
}

/// Refuses, before any run is identified, a run shorter than the processing of every run
/// needs ([`samples_needed`]: the trims, the low-pass's settling, the decimation, the
/// samples for the parameters): an [`Error::Run`] naming the run, its file with its rows,
/// and the samples needed with what takes them. Without it a short run among long ones
/// failed when its turn came, after the runs before it were identified, by whichever
/// step ran out first ("0 samples, at least 2 are needed" of the trims, or advice to
/// raise the cutoff), naming neither its length nor the length needed.
fn check_lengths(model: &(dyn Model + Sync), runs: &[Dataset], config: &Config) -> Result<()> {
    config.check(model.dof())?;
    // a config that cannot say (a known-parameter file that cannot be read) is named by
    // the identification itself
    let parameters = estimated_parameters(model, config).unwrap_or(0);
    let short = |d: &Dataset| {
        samples_needed(d, config, parameters).filter(|need| d.samples() < need.samples)
    };
    // when no run is long enough, the processing asks too much, not one run too little
    let hint = if runs.iter().all(|d| short(d).is_some()) {
        "every run is this short: ask less of [processing] (a lower decimation or trim, a \
         higher low-pass cutoff) or record longer runs"
    } else {
        "remove the run from runs.files or record it in full (all runs are processed alike)"
    };
    for (i, d) in runs.iter().enumerate() {
        if let Some(need) = short(d) {
            let e = Error::TooFewSamples {
                context: format!(
                    "{}{}: too short for the processing of every run, which takes {}",
                    UsedRows::of(d, 0..d.samples()),
                    joined_with(d),
                    need.why
                ),
                found: d.samples(),
                required: need.samples,
                hint,
            };
            return Err(config.run_error(i, &d.name, e));
        }
    }
    Ok(())
}

/// The stacked runs' estimate and prediction through the whole stacked observation
/// matrix (every method; OLS and WLS without known parameters stream instead, see
/// `pipeline::stream`).
pub(crate) fn stacked_dense(
    model: &(dyn Model + Sync),
    runs: &[Dataset],
    config: &Config,
) -> Result<(Estimate, Prediction)> {
    let mut parts = Vec::with_capacity(runs.len());
    // what the removal of the equations near rest left, over the runs: a rank deficiency
    // it explains is said as `processing.rest_velocity`'s, as for one record
    let mut rest = RestCount::default();
    // the torques before filtering, joint by joint, run after run as `stack` puts them
    let mut unfiltered = Some(vec![Vec::new(); model.dof()]);
    for (i, d) in runs.iter().enumerate() {
        let counted =
            observation_counted(model, d, config).map_err(|e| config.run_error(i, &d.name, e))?;
        rest.add(&counted.rest);
        unfiltered = unfiltered.zip(counted.unfiltered).map(|(mut all, raw)| {
            all.iter_mut().zip(raw).for_each(|(a, r)| a.extend(r));
            all
        });
        parts.push((counted.obs, counted.dt));
    }
    let dt = parts.first().map_or(1.0, |p| p.1);
    let obs = stack(parts.into_iter().map(|p| p.0).collect())?;
    let estimate = estimate_with_known(model, &obs, config)
        .map_err(|e| config.locate(rest_cause(&rest, config, model.dof(), e)))?;
    let mut prediction = Prediction::new(&obs, &estimate.values, dt)?;
    prediction.unfiltered = unfiltered;
    prediction.check("the stacked runs")?;
    Ok((estimate, prediction))
}

/// Stacks observations with the same columns: joint block j of the result holds block j
/// of every run in turn; the sample indices of each run follow those of the previous one
/// (the runs end to end in time).
pub fn stack(parts: Vec<Observation>) -> Result<Observation> {
    let first = parts.first().ok_or_else(|| Error::TooFewSamples {
        context: "the runs to stack".into(),
        found: 0,
        required: 1,
        hint: "give at least one run",
    })?;
    let (cols, blocks, names) = (first.cols(), first.joint_rows.len(), first.names.clone());
    for p in &parts {
        if p.names != names || p.joint_rows.len() != blocks {
            return Err(Error::DimensionMismatch {
                what: "columns or joint blocks of a stacked run".into(),
                expected: cols,
                found: p.cols(),
            });
        }
    }
    let rows: usize = parts.iter().map(Observation::rows).sum();
    let mut w = nalgebra::DMatrix::zeros(rows, cols);
    let mut y = nalgebra::DVector::zeros(rows);
    let mut joint_rows = Vec::with_capacity(blocks);
    let mut sample_of_row = Vec::with_capacity(rows);
    let offsets: Vec<usize> = parts
        .iter()
        .scan(0, |next, p| {
            let at = *next;
            *next += p.sample_of_row.iter().max().map_or(0, |m| m + 1);
            Some(at)
        })
        .collect();
    let mut at = 0;
    for j in 0..blocks {
        let start = at;
        for (p, offset) in parts.iter().zip(&offsets) {
            let b = p.joint_rows[j].clone();
            let n = b.len();
            w.rows_mut(at, n).copy_from(&p.w.rows(b.start, n));
            y.rows_mut(at, n).copy_from(&p.y.rows(b.start, n));
            sample_of_row.extend(p.sample_of_row[b].iter().map(|k| k + offset));
            at += n;
        }
        joint_rows.push(start..at);
    }
    let mut stacked = Observation::new(w, y, joint_rows, sample_of_row, names)?;
    // each run is a segment of its own (and each of its pieces)
    for (p, offset) in parts.iter().zip(&offsets) {
        if *offset > 0 {
            stacked.breaks.push(*offset);
        }
        stacked
            .breaks
            .extend(p.breaks.iter().filter(|&&b| b > 0).map(|b| b + offset));
    }
    stacked.breaks.sort_unstable();
    stacked.breaks.dedup();
    stacked.correlated = parts.iter().map(|p| p.correlated).max().unwrap_or(0);
    Ok(stacked)
}

/// The sample-wise mean of records of one trajectory on the same time grid (the same joint
/// count, sample time and number of samples; measured velocities and the other optional
/// signals in all runs or in none). Errors name `runs.files[i]` (owner `Config`).
pub fn average(runs: &[Dataset]) -> Result<Dataset> {
    let first = runs.first().ok_or_else(|| {
        Error::setting(
            "Config",
            "runs.files",
            "no runs to average; list at least two",
        )
    })?;
    let bad = |i: usize, problem: String| -> Error {
        Error::setting(
            "Config",
            &format!("runs.files[{}]", i + 1),
            format!(
                "{problem}; averaging needs every run on the same time grid (use mode = \"stacked\" for runs of different lengths)"
            ),
        )
    };
    for (i, d) in runs.iter().enumerate().skip(1) {
        if d.dof() != first.dof() {
            return Err(bad(
                i,
                format!(
                    "{} has {}, {} has {}",
                    d.name,
                    crate::Count(d.dof(), "joint"),
                    first.name,
                    first.dof()
                ),
            ));
        }
        if d.samples() != first.samples() {
            return Err(bad(
                i,
                format!(
                    "{} has {} samples, {} has {}",
                    d.name,
                    d.samples(),
                    first.name,
                    first.samples()
                ),
            ));
        }
        if (d.sample_time - first.sample_time).abs() > 1e-9 * first.sample_time {
            return Err(bad(
                i,
                format!(
                    "{} is sampled every {} s, {} every {} s",
                    d.name, d.sample_time, first.name, first.sample_time
                ),
            ));
        }
    }
    let optional = |f: fn(&Dataset) -> Option<&Signals>, what: &str| -> Result<Option<Signals>> {
        let present: Vec<&Signals> = runs.iter().filter_map(f).collect();
        if present.is_empty() {
            return Ok(None);
        }
        if present.len() != runs.len() {
            let i = runs.iter().position(|d| f(d).is_none()).unwrap_or(0);
            return Err(bad(
                i,
                format!("{} has no {what} while other runs have them", runs[i].name),
            ));
        }
        Ok(Some(mean(&present)))
    };
    let q: Vec<&Signals> = runs.iter().map(|d| &d.q).collect();
    let tau: Vec<&Signals> = runs.iter().map(|d| &d.tau).collect();
    let mut data = Dataset::new_at(
        format!("mean of {} runs ({} ...)", runs.len(), first.name),
        first.sample_time,
        mean(&q),
        mean(&tau),
        first.origin.clone(),
    )?;
    if let Some(v) = optional(|d| d.qd.as_ref(), "velocities")? {
        data = data.with_velocities(v)?;
    }
    if let Some(a) = optional(|d| d.qdd.as_ref(), "accelerations")? {
        data = data.with_accelerations(a)?;
    }
    if let Some(m) = optional(|d| d.motor.as_ref(), "motor positions")? {
        data = data.with_motor_positions(m)?;
    }
    if let Some(t) = optional(|d| d.temperature.as_ref(), "temperatures")? {
        data = data.with_temperatures(t)?;
    }
    if let Some(t) = optional(|d| d.joint_torque.as_ref(), "joint torques")? {
        data = data.with_joint_torques(t)?;
    }
    data.warnings = runs.iter().flat_map(|d| d.warnings.clone()).collect();
    data.sampling = first.sampling.clone();
    Ok(data)
}

/// The sample-wise mean of signals of the same shape.
fn mean(signals: &[&Signals]) -> Signals {
    let joints: Vec<Vec<&[f64]>> = signals.iter().map(|s| s.joints().collect()).collect();
    let r = signals.len() as f64;
    Signals::from_fn(signals[0].dof(), signals[0].samples(), |j, k| {
        joints.iter().map(|s| s[j][k]).sum::<f64>() / r
    })
}

/// The spread of the runs' estimates and of their measured torques.
fn spread(each: &[Identification], runs: &[Dataset]) -> Result<RunSpread> {
    let names = each[0].estimate.names.clone();
    if let Some(i) = each.iter().position(|id| id.estimate.names != names) {
        return Err(Error::DimensionMismatch {
            what: format!("parameters of run {} (against run 1)", i + 1),
            expected: names.len(),
            found: each[i].estimate.names.len(),
        });
    }
    let r = each.len() as f64;
    let values: Vec<Vec<f64>> = each.iter().map(|id| id.estimate.values.clone()).collect();
    let p = names.len();
    let mean: Vec<f64> = (0..p)
        .map(|i| values.iter().map(|v| v[i]).sum::<f64>() / r)
        .collect();
    let std = (0..p)
        .map(|i| (values.iter().map(|v| (v[i] - mean[i]).powi(2)).sum::<f64>() / (r - 1.0)).sqrt())
        .collect();
    let reported_std = (0..p)
        .map(|i| {
            (each
                .iter()
                .map(|id| id.estimate.std[i].powi(2))
                .sum::<f64>()
                / r)
                .sqrt()
        })
        .collect();
    let same_grid = runs
        .iter()
        .all(|d| d.samples() == runs[0].samples() && d.dof() == runs[0].dof());
    let torque_std = same_grid.then(|| {
        let taus: Vec<Vec<&[f64]>> = runs.iter().map(|d| d.tau.joints().collect()).collect();
        let n = runs[0].samples().max(1) as f64;
        (0..runs[0].dof())
            .map(|j| {
                let var: f64 = (0..runs[0].samples())
                    .map(|k| {
                        let m = taus.iter().map(|t| t[j][k]).sum::<f64>() / r;
                        taus.iter().map(|t| (t[j][k] - m).powi(2)).sum::<f64>() / (r - 1.0)
                    })
                    .sum();
                (var / n).sqrt()
            })
            .collect()
    });
    let spread = RunSpread {
        names,
        values,
        mean,
        std,
        reported_std,
        torque_std,
    };
    let finite = spread
        .mean
        .iter()
        .chain(&spread.std)
        .chain(&spread.reported_std)
        .chain(spread.torque_std.iter().flatten())
        .all(|v| v.is_finite());
    if !finite {
        return Err(Error::NonFiniteResult {
            what: "the spread of the runs".into(),
            cause: "the runs' estimates or torques overflowed: check the data's units".into(),
        });
    }
    Ok(spread)
}
