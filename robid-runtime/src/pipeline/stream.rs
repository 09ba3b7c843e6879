//! Identification and validation that never hold the observation matrix
//! (docs/identification.md#streaming-least-squares).
//!
//! The kept samples of the record are cut into blocks; each block is prepared from the
//! data set with a margin of the record on each side ([`Plan::block`]: the low-pass,
//! derivatives and rotor compensation of the whole record, to the low-pass's settling
//! tolerance), its regressor rows are evaluated with an overlap on both sides long enough
//! for the decimation filter to forget the block's edges ([`Decimator::settling`]),
//! decimated as a block, and the block's own decimated samples kept: the same equations as
//! the dense observation's, to the filters' settling tolerances. Blocks are taken in
//! record order, each built in parallel (regressor rows, channel groups of the filter,
//! joints' factors). With one filtering stage the estimation pass carries the filter's
//! forward states from block to block ([`Carry`]), so that a block after the first is
//! evaluated and filtered from its first sample on (its overlap on the left is only
//! prepared) and only the overlap on the right is evaluated twice.
//!
//! OLS and WLS take one pass: each block's equations go into one
//! [`StreamingLeastSquares`] (per-joint R factors, the joints updated in parallel); the
//! outlier check (`Dominance`) rides along. The prediction (measured against predicted
//! torque, the fit and the report's plots) takes a second pass with the estimated values,
//! which filters the predicted torque of each joint only (the filter is linear: the
//! decimated `W beta` is the decimated `Y(t) beta`; the equations kept and their measured
//! torques are the estimation pass's, as the dense prediction takes the observation's),
//! as many blocks at once as there are threads. A validation's prediction filters the
//! torque and the velocity too, and removes the equations near rest itself.
//! Memory is the data set, one block of prepared
//! signals and of regressor channels, the R factors, and one measured and one predicted
//! torque per equation: never the prepared record nor the equations' rows.

use std::ops::Range;

use rayon::prelude::*;

use crate::Model;
use crate::data::{Config, Dataset, Method, Record};
use crate::error::{Error, Result};
use crate::estimate::hac::Scores;
use crate::estimate::{
    Dominance, Estimate, EstimateError, QualityWarning, StreamingLeastSquares, equations_needed,
    equations_purpose, robust_lag,
};
use crate::pipeline::Identification;
use crate::pipeline::identify::{checked_plan, correlated_samples, piece_breaks, rest_cause};
use crate::pipeline::observe::{Carry, Equations, Observer, RestCount, decimator_for, long_enough};
use crate::pipeline::prepare::{Plan, Rows};
use crate::progress::Progress;
use crate::signal::Decimator;
use crate::validate::{Prediction, UsedRows};

/// Tolerance of the decimation filter's settling (relative to its impulse response's
/// absolute sum) that sets the blocks' overlap.
const SETTLING_TOLERANCE: f64 = 1e-15;

/// Processed samples per block, at least (four times the overlap when that is more).
const BLOCK: usize = 16_384;

/// Bytes of regressor channels a block may take: blocks are as long as that allows (the
/// longer, the less overlap is evaluated twice); a record up to half a block longer is
/// one block, with no overlap at all.
const BLOCK_BYTES: usize = 64 << 20;

/// Blocks per thread the prediction pass takes at once.
const PREDICTION_BATCH: usize = 4;

/// The prediction pass's blocks are this many estimation blocks long: it filters a few
/// channels per joint, not the regressor's, so longer blocks cost little memory and
/// spare overlap (evaluated twice: 14 % of the hour's prediction rows with the estimation's
/// blocks, 7 % with these, 3 % less time in all; four times as long was no faster and took
/// the hour's peak memory from about 200 to 250 MiB, docs/performance.md#streaming-identification).
const PREDICTION_SPAN: usize = 2;

/// A record's kept samples cut into blocks of equations.
pub(crate) struct Stream<'a> {
    model: &'a (dyn Model + Sync),
    config: &'a Config,
    data: &'a dyn Record,
    plan: &'a Plan,
    names: Vec<String>,
    dec: Decimator,
    overlap: usize,
    block: usize,
    /// The decimated samples the decimation filter settled ([`Decimator::settled`]).
    settled: Range<usize>,
    rest: Option<Vec<f64>>,
    /// The equations are for an estimate (else for a validation's prediction).
    estimating: bool,
}

impl<'a> Stream<'a> {
    /// The blocks of `data`'s samples kept by `plan`, with `config`'s decimation and rest
    /// removal; `estimating`: the equations are for an estimate (at least one per
    /// parameter), else for a prediction.
    pub(crate) fn new(
        model: &'a (dyn Model + Sync),
        data: &'a dyn Record,
        plan: &'a Plan,
        config: &'a Config,
        estimating: bool,
    ) -> Result<Self> {
        // the parameters and channels, and the checks of the signals against the model and
        // the config, on the first sample
        let (first, _) = plan.block(data, config, 0..1)?;
        let observer = Observer::new(model, &first, config)?;
        // an estimate needs one equation more than its parameters, a prediction one
        let cols = observer.names.len();
        let (needed, purpose) = if estimating {
            let needed = equations_needed(cols);
            (needed, equations_purpose(cols))
        } else {
            (1, "the one a prediction needs".to_owned())
        };
        let dec = decimator_for(
            config,
            data.name(),
            (plan.kept.len(), model.dof()),
            needed,
            &purpose,
        )?;
        let f = dec.factor();
        let overlap = if f == 1 {
            0
        } else {
            dec.settling(SETTLING_TOLERANCE).div_ceil(f) * f
        };
        let by_memory = BLOCK_BYTES / (8 * observer.channels().max(1));
        let block = BLOCK.max(by_memory).max(4 * overlap).div_ceil(f) * f;
        let n = plan.kept.len();
        let block = if n <= block + block / 2 {
            n.max(1)
        } else {
            block
        };
        let rest = Some(config.processing.rest_velocities(model.dof())?);
        let settled = dec.settled(n);
        Ok(Self {
            model,
            config,
            data,
            plan,
            names: observer.names,
            dec,
            overlap,
            block,
            settled,
            rest,
            estimating,
        })
    }

    /// The progress of a pass over the kept samples titled `what` (shown when the config
    /// asks for it: [`Config::progress`]).
    fn progress(&self, what: &str) -> Progress {
        Progress::new(
            self.config.progress,
            format!("identify: {what} of {}", self.data.name()),
            self.blocks(self.block).iter().map(|b| b.len() as u64).sum(),
            "samples",
        )
    }

    /// Parameter names (base parameters, then extra columns).
    pub(crate) fn names(&self) -> &[String] {
        &self.names
    }

    /// The total decimation factor.
    pub(crate) fn factor(&self) -> usize {
        self.dec.factor()
    }

    /// The thresholds of `processing.rest_velocity` per joint, if the config has them.
    pub(crate) fn rest(&self) -> Option<&[f64]> {
        self.rest.as_deref()
    }

    /// The blocks of processed samples, in record order: those of the decimated samples
    /// the decimation filter settled ([`Decimator::settled`]; its first is a multiple of the
    /// factor, and so is every block's start). A block's overlap reaches beyond them.
    fn blocks(&self, size: usize) -> Vec<Range<usize>> {
        let (n, f) = (self.plan.kept.len(), self.dec.factor());
        let (start, end) = (self.settled.start * f, (self.settled.end * f).min(n));
        (start..end)
            .step_by(size)
            .map(|b| b..(b + size).min(end))
            .collect()
    }

    /// Calls `with` with the observer of block `b`'s prepared samples and overlap, the
    /// block's place among them, the first processed sample they hold, and the torque
    /// before the low-pass when it filters the torque.
    fn in_block<T>(
        &self,
        b: &Range<usize>,
        with: impl FnOnce(
            &Observer<'_>,
            Range<usize>,
            usize,
            Option<&crate::signal::Signals>,
        ) -> Result<T>,
    ) -> Result<T> {
        let lo = b.start.saturating_sub(self.overlap);
        let hi = (b.end + self.overlap).min(self.plan.kept.len());
        let (prepared, unfiltered) = self.plan.block(self.data, self.config, lo..hi)?;
        let observer = Observer::new(self.model, &prepared, self.config)?;
        with(&observer, b.start - lo..b.end - lo, lo, unfiltered.as_ref())
            .map_err(|e| shifted(e, lo))
    }

    /// Calls `fold` with each block's equations in record order (each block built in
    /// parallel); the first error stops it. A block's equations are folded while the
    /// next block's are built, so that the sequential parts of both (the least squares
    /// updates; reading and cutting a block) overlap.
    pub(crate) fn run(&self, mut fold: impl FnMut(Equations) -> Result<()> + Send) -> Result<()> {
        let f = self.dec.factor();
        // the channels before decimation, one set of buffers for every block
        let mut groups = Vec::new();
        let mut pending: Option<Equations> = None;
        let progress = self.progress("least squares");
        // the decimation filter's forward states from block to block, when it has one
        // filtering stage: a block after the first is filtered from its first sample on
        // (its overlap on the left is prepared, not filtered: the prepared signals at a
        // block's first samples then come from the same low-pass and differences as the
        // samples before them, as without the carry; prepared from the block's first
        // sample, the estimate of a 300 s record moved 2.2 times farther from the dense
        // path's, 2e-10 of a parameter's value or deviation)
        let mut carry = self.dec.carried_sections().map(Carry::new);
        for b in self.blocks(self.block) {
            let (next, folded) = rayon::join(
                || {
                    self.in_block(&b, |observer, core, lo, _| {
                        let mut eq = observer.window(
                            &self.dec,
                            self.overlap,
                            self.rest.as_deref(),
                            core,
                            &mut groups,
                            carry.as_mut(),
                        )?;
                        // `lo` is a multiple of the factor: the decimated samples shift by
                        // lo / f
                        eq.sample.iter_mut().for_each(|k| *k += lo / f);
                        Ok(eq)
                    })
                },
                || pending.take().map_or(Ok(()), &mut fold),
            );
            // the earlier block's error first, as if they had run in turn
            folded?;
            pending = Some(next?);
            progress.add(b.len() as u64);
        }
        pending.map_or(Ok(()), fold)
    }

    /// Measured and predicted torque per joint with `values` (the decimated sample time
    /// `dt`, times from the record's first sample used), in the dense [`Prediction`]'s
    /// order: joint by joint, samples in order; with the decimated samples, and the
    /// torque before filtering at them (before the low-pass when it filters the torque,
    /// before the decimation otherwise; `None` when neither filters it).
    /// `expected`: the number of equations per joint when known (the estimation pass
    /// counted them), so that the per-equation lists, the one part of the result that
    /// grows with the record, are allocated once at their size. `estimated`: the
    /// equations the estimation pass kept and their measured torques, which the
    /// prediction then takes (only the predicted torque of each joint is filtered again,
    /// one channel per joint instead of three); `None`: the pass filters the torque and the
    /// velocity too and removes the equations near rest itself (a validation).
    fn prediction(
        &self,
        values: &[f64],
        dt: f64,
        expected: Option<&[usize]>,
        estimated: Option<Estimated>,
    ) -> Result<PredictionParts> {
        let dof = self.model.dof();
        let f = self.dec.factor();
        let size = |j: usize| expected.and_then(|e| e.get(j)).map_or(0, |&n| n);
        let lists = || -> Vec<Vec<f64>> { (0..dof).map(|j| Vec::with_capacity(size(j))).collect() };
        let (kept, given) = match estimated {
            Some(Estimated { kept, measured }) => (Some(kept), Some(measured)),
            None => (None, None),
        };
        let mut measured = given.unwrap_or_else(&lists);
        let (mut predicted, mut raw) = (lists(), lists());
        let mut samples: Vec<Vec<usize>> = (0..dof).map(|j| Vec::with_capacity(size(j))).collect();
        let mut has_raw = f > 1;
        // (joint, decimated sample, measured (unless the estimation's), predicted, torque
        // before filtering) of a block, and whether it filtered the torque
        let block = |b: &Range<usize>| {
            self.in_block(b, |observer, core, lo, unfiltered| {
                let tau = unfiltered.unwrap_or(&observer.signals.tau);
                let (part, count) = match &kept {
                    // the estimation's equations: only the prediction is filtered
                    Some(kept) => {
                        let part = observer.window_predicted(
                            &self.dec,
                            self.overlap,
                            core,
                            values,
                            |j, k| kept[(k + lo / f) * dof + j],
                        )?;
                        let part: Vec<_> = part
                            .into_iter()
                            .map(|(j, k, p)| (j, k + lo / f, None, p, tau[j][k * f]))
                            .collect();
                        (part, RestCount::default())
                    }
                    None => {
                        let (part, count) = observer.window_prediction(
                            &self.dec,
                            self.overlap,
                            self.rest.as_deref(),
                            core,
                            values,
                        )?;
                        let part: Vec<_> = part
                            .into_iter()
                            .map(|(j, k, y, p)| (j, k + lo / f, Some(y), p, tau[j][k * f]))
                            .collect();
                        (part, count)
                    }
                };
                Ok((part, unfiltered.is_some(), count))
            })
        };
        // the blocks are independent: as many at once as there are threads (each block's
        // own work is parallel too, but reading and preparing it is not), appended in
        // record order, the earliest block's error first. A batch holds four blocks per
        // thread, so that a thread done with its blocks takes another of the batch instead
        // of waiting for the slowest (what a batch holds until it is appended is small: a
        // few values per equation)
        let blocks = self.blocks(self.block * PREDICTION_SPAN);
        let mut rest = RestCount::default();
        let progress = self.progress(if self.estimating {
            "prediction"
        } else {
            "validation"
        });
        for batch in blocks.chunks(PREDICTION_BATCH * rayon::current_num_threads().max(1)) {
            let parts: Vec<Result<_>> = batch.par_iter().map(block).collect();
            progress.add(batch.iter().map(|b| b.len() as u64).sum());
            for part in parts {
                let (part, filtered, count) = part?;
                has_raw |= filtered;
                rest.add(&count);
                for (j, k, y, p, r) in part {
                    if let Some(y) = y {
                        measured[j].push(y);
                    }
                    predicted[j].push(p);
                    samples[j].push(k);
                    raw[j].push(r);
                }
            }
        }
        let time = samples
            .iter()
            .map(|s| s.iter().map(|&k| k as f64 * dt).collect())
            .collect();
        Ok(PredictionParts {
            prediction: Prediction {
                measured,
                predicted,
                time,
                unfiltered: None,
                used: None,
            },
            samples,
            raw: has_raw.then_some(raw),
            rest,
        })
    }
}

/// What the estimation pass keeps for the prediction ([`Stream::prediction`]): the
/// equations it kept (joint j of decimated sample k at `k * dof + j`) and their measured
/// torques, per joint in sample order.
struct Estimated {
    kept: Vec<bool>,
    measured: Vec<Vec<f64>>,
}

/// What [`Stream::prediction`] gives.
struct PredictionParts {
    prediction: Prediction,
    /// The decimated sample of each prediction, per joint.
    samples: Vec<Vec<usize>>,
    /// The torque before filtering at each, per joint.
    raw: Option<Vec<Vec<f64>>>,
    /// What the removal of the equations near rest left.
    rest: RestCount,
}

/// An error of a block whose prepared samples start at processed sample `lo`, placed
/// among the record's processed samples.
fn shifted(e: Error, lo: usize) -> Error {
    e.placed(|k| (k + lo, format!("processed sample {}", k + lo)))
        .unwrap_or_else(|e| e)
}

/// The segment of a stream's decimated sample (`None`: not in the estimate).
type SegmentOf<'a> = &'a (dyn Fn(usize) -> Option<usize> + Sync);

/// Sets the Newey-West standard deviations of `estimate` ([`Estimate::set_robust`], which
/// judges its uncertain parameters again by them), which `ls` solved from the
/// equations of `passes` (each a stream and the segment of each of its decimated samples,
/// `None` for a sample the estimate left out): a pass over every stream's equations again
/// with the estimated values, each equation's score `w_j^2 (y - W_row beta) W_row` (`w_j`
/// its joint's weight, 1 for OLS) added to its sample's, the last `lag` samples' scores
/// kept ([`Scores`]); `samples` scored samples in all and `correlated` samples of the
/// processing's correlation choose the lag, as the dense path's
/// `estimate::least_squares::robust_std`.
fn robust_pass(
    passes: &[(&Stream<'_>, SegmentOf<'_>)],
    ls: &StreamingLeastSquares,
    estimate: &mut Estimate,
    samples: usize,
    correlated: usize,
) -> Result<()> {
    let Some(solved) = ls.solved() else {
        return Err(Error::setting(
            "robust_pass",
            "ls",
            "solve the least squares before their robust deviations",
        ));
    };
    let values = &estimate.values;
    let mut scores = Scores::new(solved.inverse.clone(), robust_lag(samples, correlated));
    for (stream, segment) in passes {
        stream.run(|eq| {
            // the block's equations sample by sample (joints in order within a sample)
            let mut order: Vec<(usize, usize, usize)> = (0..eq.y.len())
                .filter_map(|i| segment(eq.sample[i]).map(|s| (s, eq.sample[i], i)))
                .collect();
            order.sort_unstable();
            for (s, k, i) in order {
                let row = eq.row(i);
                let w = solved.weights[eq.joint[i]];
                let fitted: f64 = row.iter().zip(values).map(|(a, b)| a * b).sum();
                scores.add(s, k, row, w * w * (eq.y[i] - fitted));
            }
            Ok(())
        })?;
    }
    let robust = scores.finish(estimate.rows);
    estimate.set_robust(robust.finite(), &solved.relative_column_norms);
    Ok(())
}

/// Whether [`identify`](crate::pipeline::identify) streams: OLS or WLS without known
/// parameters (the other methods and the known-parameter reduction take the dense
/// observation).
pub(crate) fn streams(config: &Config) -> bool {
    matches!(config.estimation.method, Method::Ols | Method::Wls)
        && config.estimation.known.is_none()
}

/// An error of the observation with its processed sample placed at its data row.
fn located(e: Error, config: &Config, data: &dyn Record, kept: &Range<usize>) -> Error {
    e.placed(|k| (kept.start + k, data.location(kept.start + k)))
        .unwrap_or_else(|e| config.locate(e))
}

/// The prediction with the torque before filtering (as `identify::with_unfiltered`),
/// its check and the rows used.
fn finish_prediction(parts: PredictionParts, used: &UsedRows, what: &str) -> Result<Prediction> {
    let mut prediction = parts.prediction;
    prediction.unfiltered = parts.raw;
    prediction.check(&format!("{what} ({used})"))?;
    prediction.used = Some(used.clone());
    Ok(prediction)
}

/// [`identify`](crate::pipeline::identify) for OLS and WLS, streaming: the same result
/// as the dense path to rounding.
pub(crate) fn identify_streaming(
    model: &(dyn Model + Sync),
    data: &dyn Record,
    config: &Config,
    plan: &Plan,
) -> Result<Identification> {
    let kept = &plan.kept;
    let at = |e: Error| located(e, config, data, kept);
    let stream = Stream::new(model, data, plan, config, true).map_err(at)?;
    let names = stream.names().to_vec();
    let (dof, cols, factor) = (model.dof(), names.len(), stream.factor());
    long_enough(data, kept, dof, cols)?;
    let time = |k: usize| (kept.start + k * factor) as f64 * data.sample_time();
    let inside = |k: usize| match &config.processing.pieces {
        Some(pieces) => pieces.iter().any(|[a, b]| (*a..=*b).contains(&time(k))),
        None => true,
    };
    let mut ls = StreamingLeastSquares::new(names.clone(), dof).map_err(at)?;
    let mut dominance = Dominance::new(cols);
    // equations per joint, before the pieces: the prediction's, which takes their
    // measured torques and which equations are kept from here, as the dense prediction
    // takes them from the observation (only the predicted torque is then filtered again)
    let mut per_joint = vec![0; dof];
    let decimated = kept.len().div_ceil(factor);
    let mut estimated = Estimated {
        kept: vec![false; decimated * dof],
        measured: (0..dof).map(|_| Vec::with_capacity(decimated)).collect(),
    };
    let mut rest = RestCount::default();
    // the decimated samples with an equation in the estimate (for the robust deviations'
    // lag)
    let mut scored = vec![false; decimated];
    stream
        .run(|eq| {
            rest.add(&eq.rest);
            for i in 0..eq.y.len() {
                let j = eq.joint[i];
                dominance.push(eq.row(i), eq.sample[i]);
                per_joint[j] += 1;
                estimated.kept[eq.sample[i] * dof + j] = true;
                estimated.measured[j].push(eq.y[i]);
            }
            if config.processing.pieces.is_none() {
                eq.sample.iter().for_each(|&k| scored[k] = true);
                return ls.push_rows(&eq.joint, &eq.w, &eq.y);
            }
            let keep: Vec<usize> = (0..eq.y.len()).filter(|&i| inside(eq.sample[i])).collect();
            keep.iter().for_each(|&i| scored[eq.sample[i]] = true);
            let joint: Vec<usize> = keep.iter().map(|&i| eq.joint[i]).collect();
            let w: Vec<f64> = keep
                .iter()
                .flat_map(|&i| eq.row(i).iter().copied())
                .collect();
            let y: Vec<f64> = keep.iter().map(|&i| eq.y[i]).collect();
            ls.push_rows(&joint, &w, &y)
        })
        .map_err(at)?;
    rest.check(
        config,
        stream.rest(),
        equations_needed(cols),
        &equations_purpose(cols),
    )
    .map_err(at)?;
    if config.processing.pieces.is_some() && ls.rows() < equations_needed(cols) {
        return Err(config.key_error(
            "processing.pieces",
            format!(
                "the pieces hold {} equations of the estimation range, no more than the {} \
                 parameters; check that they are in seconds from the record's first sample \
                 and inside processing.range",
                ls.rows(),
                cols
            ),
        ));
    }
    let location = |k: usize| data.location(kept.start + k * factor);
    let dominated = dominance.dominated();
    let tolerance = config.estimation.rank_tolerance;
    let result = match config.estimation.method {
        Method::Wls => ls.wls(tolerance),
        _ => ls.ols(tolerance),
    };
    let mut estimate = result.map_err(|e| config.locate(e)).map_err(|e| match e {
        Error::Estimate(EstimateError::RankDeficient { ref unexcited, .. }) => {
            match dominated
                .iter()
                .find(|(c, _, _)| unexcited.contains(&names[*c]))
            {
                Some(&(c, k, share)) => Error::Estimate(EstimateError::Outlier {
                    location: location(k),
                    parameter: names[c].clone(),
                    share,
                }),
                None => config.locate(rest_cause(&rest, config, dof, e)),
            }
        }
        e => e,
    })?;
    for &(c, k, share) in &dominated {
        estimate.warnings.push(QualityWarning::Outlier {
            parameter: names[c].clone(),
            location: location(k),
            share,
        });
    }
    // each piece a segment of its own, as the dense path's `pieces_of` gives them
    let breaks = match &config.processing.pieces {
        Some(_) => piece_breaks(decimated, inside),
        None => Vec::new(),
    };
    let segment = |k: usize| inside(k).then(|| breaks.partition_point(|&b| b <= k));
    let correlated = correlated_samples(config, plan.auto_cutoff.as_ref(), data.sample_time())?;
    let samples = scored.iter().filter(|s| **s).count();
    if config.estimation.robust_std {
        robust_pass(
            &[(&stream, &segment)],
            &ls,
            &mut estimate,
            samples,
            correlated,
        )
        .map_err(at)?;
    }
    // the samples of the equations (every factor-th, less the decimation filter's settling
    // and the ends' samples near rest), as the dense path says them
    let with_equation = |k: &usize| estimated.kept[k * dof..(k + 1) * dof].contains(&true);
    let first = (0..decimated).find(with_equation).unwrap_or(0);
    let last = (0..decimated).rev().find(with_equation).unwrap_or(0);
    let used = UsedRows::of(data, kept.clone()).with_equations(
        data,
        kept.start + first * factor,
        kept.start + last * factor,
        factor,
    );
    let dt = data.sample_time() * factor as f64;
    let mut parts = stream
        .prediction(&estimate.values, dt, Some(&per_joint), Some(estimated))
        .map_err(at)?;
    parts.prediction = parts
        .prediction
        .starting_at(kept.start as f64 * data.sample_time());
    let prediction = finish_prediction(parts, &used, "the estimation data")?;
    estimate.warnings.extend(prediction.warnings());
    Ok(Identification {
        robot: model.name().to_string(),
        fit: prediction.fit(),
        prediction,
        estimate,
        warnings: data.warnings().to_vec(),
        used,
        cutoff: plan.auto_cutoff.clone(),
        joint_units: crate::report::joint_units(&config.prismatic, model.dof()),
    })
}

/// [`validate`](crate::pipeline::validate), streaming.
pub(crate) fn validate_streaming(
    model: &(dyn Model + Sync),
    data: &dyn Record,
    config: &Config,
    plan: &Plan,
    values: &[f64],
) -> Result<Prediction> {
    let kept = &plan.kept;
    let stream = Stream::new(model, data, plan, config, false)
        .map_err(|e| located(e, config, data, kept))?;
    let names = stream.names();
    if values.len() != names.len() {
        return Err(Error::DimensionMismatch {
            what: "parameter values".into(),
            expected: names.len(),
            found: values.len(),
        });
    }
    if let Some(i) = values.iter().position(|v| !v.is_finite()) {
        return Err(Error::setting(
            "validate",
            "values",
            format!(
                "the value of `{}` is {}; give finite identified values",
                names[i], values[i]
            ),
        ));
    }
    let dt = data.sample_time() * stream.factor() as f64;
    let mut parts = stream
        .prediction(values, dt, None, None)
        .map_err(|e| located(e, config, data, kept))?;
    parts
        .rest
        .check(
            config,
            stream.rest(),
            1,
            &format!("the one a prediction of {} needs", data.name()),
        )
        .map_err(|e| located(e, config, data, kept))?;
    parts.prediction = parts
        .prediction
        .starting_at(kept.start as f64 * data.sample_time());
    let used = UsedRows::of(data, kept.clone());
    finish_prediction(parts, &used, "the validation data")
}

/// The stacked runs' estimate and prediction (as [`stack`](crate::pipeline::stack) then
/// [`estimate`](crate::pipeline::estimate) and [`Prediction::new`] give them), streaming:
/// every run's equations go into one accumulator, joint by joint; in the prediction, joint
/// j holds every run's equations in turn, each run's samples after the previous run's.
pub(crate) fn stacked_streaming(
    model: &(dyn Model + Sync),
    runs: &[Dataset],
    config: &Config,
) -> Result<(Estimate, Prediction)> {
    let in_run = |i: usize, d: &Dataset, e: Error| config.run_error(i, &d.name, e);
    let plans = runs
        .iter()
        .enumerate()
        .map(|(i, d)| checked_plan(model, d, config, Rows::Estimation).map_err(|e| in_run(i, d, e)))
        .collect::<Result<Vec<_>>>()?;
    let streams = plans
        .iter()
        .zip(runs)
        .enumerate()
        .map(|(i, (p, d))| {
            Stream::new(model, d, p, config, true)
                .map_err(|e| in_run(i, d, located(e, config, d, &p.kept)))
        })
        .collect::<Result<Vec<_>>>()?;
    let Some(first) = streams.first() else {
        return Err(Error::TooFewSamples {
            context: "the runs to stack".into(),
            found: 0,
            required: 1,
            hint: "give at least one run",
        });
    };
    let dof = model.dof();
    let mut ls = StreamingLeastSquares::new(first.names().to_vec(), dof)?;
    // what the removal of the equations near rest left, over the runs (as the dense
    // stacked path counts it)
    let mut rest = RestCount::default();
    // the samples with an equation, over the runs (the robust deviations' lag)
    let mut samples = 0;
    let mut correlated = 0;
    for (i, ((s, p), d)) in streams.iter().zip(&plans).zip(runs).enumerate() {
        let mut scored = vec![false; p.kept.len().div_ceil(s.factor())];
        s.run(|eq| {
            rest.add(&eq.rest);
            eq.sample.iter().for_each(|&k| scored[k] = true);
            ls.push_rows(&eq.joint, &eq.w, &eq.y)
        })
        .map_err(|e| in_run(i, d, located(e, config, d, &p.kept)))?;
        samples += scored.iter().filter(|s| **s).count();
        correlated = correlated.max(
            correlated_samples(config, p.auto_cutoff.as_ref(), d.sample_time)
                .map_err(|e| in_run(i, d, e))?,
        );
    }
    let tolerance = config.estimation.rank_tolerance;
    let mut estimate = match config.estimation.method {
        Method::Wls => ls.wls(tolerance),
        _ => ls.ols(tolerance),
    }
    .map_err(|e| config.locate(rest_cause(&rest, config, dof, e)))?;
    // each run a segment of its own
    let segments: Vec<_> = (0..streams.len())
        .map(|i| move |_: usize| Some(i))
        .collect();
    let passes: Vec<(&Stream<'_>, SegmentOf<'_>)> = streams
        .iter()
        .zip(&segments)
        .map(|(s, f)| (s, f as SegmentOf<'_>))
        .collect();
    if config.estimation.robust_std {
        robust_pass(&passes, &ls, &mut estimate, samples, correlated)?;
    }
    let dt = runs[0].sample_time * first.factor() as f64;
    let mut stacked = Prediction {
        measured: vec![Vec::new(); dof],
        predicted: vec![Vec::new(); dof],
        time: vec![Vec::new(); dof],
        unfiltered: None,
        used: None,
    };
    let mut offset = 0;
    // the torques before filtering, when every run's are filtered
    let mut unfiltered = Some(vec![Vec::new(); dof]);
    for (i, ((s, plan), d)) in streams.iter().zip(&plans).zip(runs).enumerate() {
        let PredictionParts {
            prediction: p,
            samples,
            raw,
            ..
        } = s
            .prediction(&estimate.values, dt, None, None)
            .map_err(|e| in_run(i, d, located(e, config, d, &plan.kept)))?;
        for (j, s) in samples.iter().enumerate() {
            stacked.measured[j].extend(&p.measured[j]);
            stacked.predicted[j].extend(&p.predicted[j]);
            stacked.time[j].extend(s.iter().map(|&k| (k + offset) as f64 * dt));
        }
        unfiltered = unfiltered.zip(raw).map(|(mut all, raw)| {
            all.iter_mut().zip(raw).for_each(|(a, r)| a.extend(r));
            all
        });
        offset += samples.iter().flatten().max().map_or(0, |m| m + 1);
    }
    stacked.unfiltered = unfiltered;
    stacked.check("the stacked runs")?;
    Ok((estimate, stacked))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::data::load;
    use crate::pipeline::identify;
    use crate::pipeline::prepare::Rows;
    use crate::pipeline::tests::synthetic::{CONFIG, DOF, Synthetic, csv_with_noise};

    /// The identification's prediction holds the estimation pass's equations, as the
    /// dense prediction holds the observation's: per joint the same equations (decimated
    /// samples) and their measured torques to the bit (the equations' `y`, not the torque
    /// filtered again by the prediction pass, which differs by rounding), and predicted
    /// torques equal to each equation's row times the values to rounding. Several blocks,
    /// with the removal of the equations near rest.
    #[test]
    fn the_prediction_takes_the_estimations_equations() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("run.csv");
        std::fs::write(&file, csv_with_noise(60_000, 1000.0, [0.05; DOF])).unwrap();
        let text = format!("{CONFIG}[estimation]\nmethod = \"wls\"\n");
        let config = Config::from_toml_str(&text, std::path::Path::new("s.toml")).unwrap();
        assert!(config.processing.rest_velocity.is_some());
        let data = load(&config, &[file], DOF).unwrap();
        let model = Synthetic::default();
        let plan = Plan::new(&data, &config, Rows::Estimation).unwrap();
        let stream = Stream::new(&model, &data, &plan, &config, true).unwrap();
        // (decimated sample, y, row) of each joint's equations
        let mut equations: Vec<Vec<(usize, f64, Vec<f64>)>> = vec![Vec::new(); DOF];
        let mut blocks = 0;
        stream
            .run(|eq| {
                blocks += 1;
                for i in 0..eq.y.len() {
                    equations[eq.joint[i]].push((eq.sample[i], eq.y[i], eq.row(i).to_vec()));
                }
                Ok(())
            })
            .unwrap();
        assert!(blocks >= 2, "{blocks} blocks");
        let id = identify(&model, &data, &config).unwrap();
        let (p, values) = (&id.prediction, &id.estimate.values);
        let dt = data.sample_time * stream.factor() as f64;
        let start = plan.kept.start as f64 * data.sample_time;
        let mut removed = 0;
        for (j, eqs) in equations.iter().enumerate() {
            removed += plan.kept.len().div_ceil(stream.factor()) - eqs.len();
            let y: Vec<f64> = eqs.iter().map(|e| e.1).collect();
            assert!(p.measured[j] == y, "joint {j}: measured torques");
            let time: Vec<f64> = eqs.iter().map(|e| start + e.0 as f64 * dt).collect();
            assert_eq!(p.time[j].len(), time.len(), "joint {j}");
            for (a, b) in p.time[j].iter().zip(&time) {
                assert!(
                    (a - b).abs() <= 1e-9 * b.abs().max(1.0),
                    "joint {j}: {a} vs {b}"
                );
            }
            let scale = y.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            for ((e, predicted), i) in eqs.iter().zip(&p.predicted[j]).zip(0..) {
                let w: f64 = e.2.iter().zip(values).map(|(a, b)| a * b).sum();
                assert!(
                    (predicted - w).abs() <= 1e-9 * scale,
                    "joint {j}, equation {i}: {predicted} vs {w}"
                );
            }
        }
        assert!(removed > 0, "no equation removed near rest");
    }
}
