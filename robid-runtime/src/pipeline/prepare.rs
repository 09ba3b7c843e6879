//! Signal preparation: sample range, zero-phase low-pass, velocities and accelerations,
//! rotor-dynamics compensation, trimming.
//!
//! Edges: a log may start or end during motion. The low-pass pads each signal with an
//! odd extension as long as the filter's settling time (not scipy's few samples), so the
//! start-up transient dies out in the padding; what is left near an edge (the extension
//! bends the signal's curvature, which two differentiations amplify) is removed by an
//! automatic trim of one settling time at each real end of the record. `processing.trim`
//! drops samples at each end of the used range; where the range reaches a real end of the
//! record, the larger of the two counts is dropped there (they overlap, they do not add).

use std::borrow::Cow;

use crate::DataError;
use crate::Num;
use crate::data::{Config, Cutoff, Dataset, Derivative, Record, Signal, joined_with};
use crate::drive::FrictionModel;
use crate::error::{Error, Result, num};
use crate::inspect::{CutoffSuggestion, suggest_cutoff};
use crate::signal::{SavitzkyGolay, Signals, Sos, butterworth_hz, central_difference};

/// Joint signals ready for the regressor.
#[derive(Debug, Clone)]
pub struct Prepared {
    /// Positions.
    pub q: Signals,
    /// Velocities.
    pub qd: Signals,
    /// Accelerations.
    pub qdd: Signals,
    /// Joint torques (rotor-compensated when configured).
    pub tau: Signals,
    /// The motor encoders' signals, when the data have them and the config uses them
    /// (rotor compensation, rotor-side extra columns).
    pub rotor: Option<RotorStates>,
    /// Sample time (s).
    pub sample_time: f64,
}

/// Motor-encoder signals reflected to the link side, on the samples of [`Prepared`].
#[derive(Debug, Clone)]
pub struct RotorStates {
    /// thetadot: differentiated from the motor positions low-passed like the positions.
    pub thetad: Signals,
    /// thetaddot.
    pub thetadd: Signals,
    /// Drive temperatures (deg C) as read, when the data have them.
    pub temperature: Option<Signals>,
    /// Link-side joint torques of a joint-torque sensor (`joint_torque` columns), low-passed
    /// like the torque, when the data have them.
    pub joint_torque: Option<Signals>,
}

impl Prepared {
    /// Number of samples.
    pub fn samples(&self) -> usize {
        self.q.samples()
    }

    /// Checks that the four signals have `dof` joints and as many samples as the
    /// positions; `context` names the user in the error.
    pub fn check(&self, dof: usize, context: &str) -> Result<()> {
        let rotor = self.rotor.as_ref();
        let rotor = [
            rotor.map(|r| ("motor velocities", &r.thetad)),
            rotor.map(|r| ("motor accelerations", &r.thetadd)),
            rotor.and_then(|r| Some(("temperatures", r.temperature.as_ref()?))),
        ];
        for (what, x) in [
            ("positions", &self.q),
            ("velocities", &self.qd),
            ("accelerations", &self.qdd),
            ("torques", &self.tau),
        ]
        .into_iter()
        .chain(rotor.into_iter().flatten())
        {
            if x.dof() != dof {
                return Err(Error::Data(DataError::JointCountMismatch {
                    context: format!("{context}: {what}"),
                    expected: dof,
                    found: x.dof(),
                }));
            }
            if x.samples() != self.samples() {
                return Err(Error::DimensionMismatch {
                    what: format!("{context}: samples of the {what}"),
                    expected: self.samples(),
                    found: x.samples(),
                });
            }
        }
        Ok(())
    }
}

/// Share of the impulse response's absolute sum left after the padding's length.
const PADDING_TOLERANCE: f64 = 1e-4;
/// Share of the impulse response's absolute sum left after the automatic trim (the main
/// lobe of the response: where the bent curvature of the extension still shows in qdd).
const SETTLING_TOLERANCE: f64 = 1e-1;

fn filter_all(sos: Option<&Sos>, pad: usize, x: &Signals) -> Result<Signals> {
    match sos {
        Some(s) => {
            let joints: Vec<&[f64]> = x.joints().collect();
            Signals::new(s.filtfilt_padded_all(&joints, pad)?)
        }
        None => Ok(x.clone()),
    }
}

/// Samples dropped automatically at each real end of a record: one settling time of the
/// low-pass (0 without one).
pub fn automatic_trim(config: &Config, sample_time: f64) -> Result<usize> {
    match &config.processing.lowpass {
        Some(lp) => {
            let cutoff = lp.cutoff.hz().ok_or_else(|| {
                Error::setting(
                    "Config",
                    "processing.lowpass.cutoff",
                    "\"auto\" is chosen from data: resolve it first (inspect::resolve_cutoff)",
                )
            })?;
            Ok(butterworth_hz(lp.order, cutoff, 1.0 / sample_time)?
                .settling_samples(SETTLING_TOLERANCE, 1 << 20))
        }
        None => Ok(0),
    }
}

/// The first derivative of every joint: central differences, or the Savitzky-Golay fit
/// of `processing.differentiation` (docs/identification.md#savitzky-golay-derivatives).
fn differentiate(x: &Signals, dt: f64, sg: Option<&SavitzkyGolay>) -> Result<Signals> {
    match sg {
        Some(sg) => savitzky_golay(x, dt, sg, 1),
        None => x.try_map(|v| central_difference(v, dt)),
    }
}

/// The second derivative: central differences of the first derivative `first`, or the
/// Savitzky-Golay second derivative of `x` itself (one fit, not two in a row).
fn differentiate_twice(
    x: &Signals,
    first: &Signals,
    dt: f64,
    sg: Option<&SavitzkyGolay>,
) -> Result<Signals> {
    match sg {
        Some(sg) => savitzky_golay(x, dt, sg, 2),
        None => differentiate(first, dt, None),
    }
}

fn savitzky_golay(x: &Signals, dt: f64, sg: &SavitzkyGolay, order: usize) -> Result<Signals> {
    // the weights once for every joint (a long window's took seconds per channel)
    let kernel = sg.kernel(order, dt)?;
    x.try_map(|v| kernel.apply(v))
        .map_err(|e| match e {
            Error::TooFewSamples { found, required, .. } => Error::setting(
                "Config",
                "processing.differentiation.window",
                format!(
                    "{required} samples is longer than the record ({found} samples); use a shorter window"
                ),
            ),
            e => e,
        })
}

/// Applies the `[processing]` options (estimation range, low-pass, derivatives, trim)
/// and the rotor compensation of `[drive.rotor]` to a data set.
pub fn prepare(data: &Dataset, config: &Config) -> Result<Prepared> {
    prepare_rows(data, config, Rows::Estimation)
        .map(|rows| rows.prepared)
        .map_err(|e| config.locate(e))
}

/// What [`prepare_rows`] gives the pipeline.
pub(crate) struct PreparedRows {
    /// The signals.
    pub(crate) prepared: Prepared,
    /// The samples of the data set kept.
    pub(crate) kept: std::ops::Range<usize>,
    /// The torque before the low-pass (rotor-compensated like `prepared.tau`) on the kept
    /// samples, when `[processing] lowpass` filters the torque: the fit is also reported
    /// against it.
    pub(crate) unfiltered_tau: Option<Signals>,
    /// The cutoff chosen for `cutoff = "auto"`.
    pub(crate) auto_cutoff: Option<CutoffSuggestion>,
}

/// Which sample range of `[processing]` applies.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Rows {
    /// `processing.range`.
    Estimation,
    /// `processing.validation_range`.
    Validation,
}

impl Rows {
    fn key(self) -> &'static str {
        match self {
            Rows::Estimation => "processing.range",
            Rows::Validation => "processing.validation_range",
        }
    }
}

/// [`prepare`] with the range `rows`; also returns the samples of `data` kept and the
/// unfiltered torque.
pub(crate) fn prepare_rows(data: &Dataset, config: &Config, rows: Rows) -> Result<PreparedRows> {
    let plan = Plan::new(data, config, rows)?;
    let kept = plan.kept.clone();
    let (prepared, unfiltered_tau) = plan.signals(Cow::Borrowed(data), config)?;
    let (prepared, unfiltered_tau) = plan.cut(data, 0, prepared, unfiltered_tau, kept.clone())?;
    Ok(PreparedRows {
        prepared,
        kept,
        unfiltered_tau,
        auto_cutoff: plan.auto_cutoff,
    })
}

/// How the signals of a data set are prepared: the low-pass, the derivatives, the rotor
/// compensation, and the samples kept. The preparation of any block of the kept samples
/// ([`Plan::block`]) is that of the whole record to the low-pass's settling tolerance:
/// each block is prepared with [`Plan::margin`] more samples of the record on each side.
pub(crate) struct Plan {
    sos: Option<Sos>,
    /// Samples of odd extension at each end of what is filtered.
    pad: usize,
    sg: Option<SavitzkyGolay>,
    friction: Option<FrictionModel>,
    /// The samples of the data set kept.
    pub(crate) kept: std::ops::Range<usize>,
    /// The cutoff chosen for `cutoff = "auto"`.
    pub(crate) auto_cutoff: Option<CutoffSuggestion>,
    /// Samples of the record on each side of a block prepared with it.
    margin: usize,
}

/// The first and the end of the samples kept of a record of `total` samples: the range
/// `lo..hi`, less `trim` at each end of it and at least `settle` (the low-pass's settling)
/// from the record's ends; nothing is kept when `end <= start`. What [`Plan::new`] keeps
/// and [`samples_needed`] counts on.
fn kept_bounds(
    total: usize,
    (lo, hi): (usize, usize),
    trim: usize,
    settle: usize,
) -> (usize, usize) {
    (
        lo.saturating_add(trim).max(settle),
        hi.saturating_sub(trim).min(total.saturating_sub(settle)),
    )
}

/// The fewest samples a record needs for the processing of a config, and why.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Need {
    /// Samples.
    pub(crate) samples: usize,
    /// What takes them: the ends (trims, the low-pass's settling, `processing.range`),
    /// then what the samples kept between them must give.
    pub(crate) why: String,
}

/// The fewest samples `data` needs for the processing of `config` to keep enough of them
/// to estimate `parameters` parameters from its torque equations (0: none counted): the
/// trims, the low-pass's settling (from the record's ends) and `processing.range`
/// ([`kept_bounds`], as [`Plan::new`] keeps them), at least 2 samples kept between them,
/// as many as the decimation's anti-alias filters need and as give one equation per
/// parameter after the decimation ([`crate::pipeline::decimator`]), and as many as the
/// zero-phase filter and a Savitzky-Golay window take. A lower bound of what the
/// identification needs (the rest removal and `processing.pieces` drop more, a cutoff of
/// "auto" is chosen from the data): a record this long may still be too short, a shorter
/// one always is. `None` when the config cannot be read so (its own errors say why) or no
/// length is enough (the range and the trims leave nothing).
pub(crate) fn samples_needed(data: &Dataset, config: &Config, parameters: usize) -> Option<Need> {
    let p = &config.processing;
    let dof = data.dof().max(1);
    let sos = p
        .lowpass
        .as_ref()
        .and_then(|lp| butterworth_hz(lp.order, lp.cutoff.hz()?, 1.0 / data.sample_time).ok());
    let settle = sos
        .as_ref()
        .map_or(0, |s| s.settling_samples(SETTLING_TOLERANCE, 1 << 20));
    let dec = crate::pipeline::decimator(config).ok()?;
    let factor = dec.factor();
    // equations, one per joint and sample left by the decimation (which keeps one in
    // `factor`, rounded up, less those its filter leaves unsettled at each end:
    // [`Decimator::settled`]): one more than the parameters, so that a residual is left
    let per_joint = crate::estimate::equations_needed(parameters).div_ceil(dof);
    let for_parameters = per_joint
        .saturating_add(2 * dec.unsettled())
        .saturating_sub(1)
        .saturating_mul(factor)
        .saturating_add(usize::from(per_joint > 0));
    let kept = 2.max(dec.min_len()).max(for_parameters);
    let enough = |n: usize| {
        let (lo, hi) = match p.range {
            Some([a, b]) if b <= n => (a, b),
            Some(_) => return false,
            None => (0, n),
        };
        let (start, end) = kept_bounds(n, (lo, hi), p.trim, settle);
        end >= start.saturating_add(kept)
    };
    // the fewest samples that keep enough: `enough` holds from some length on (the
    // config's values unchecked, saturating: a range of any size is refused, not a panic)
    let most = [
        kept,
        p.trim,
        p.trim,
        settle,
        settle,
        p.range.map_or(0, |r| r[1]),
        1,
    ]
    .into_iter()
    .fold(0usize, usize::saturating_add);
    if !enough(most) {
        return None;
    }
    let (mut lo, mut hi) = (0, most);
    while lo < hi {
        let mid = lo + (hi - lo) / 2;
        if enough(mid) {
            hi = mid;
        } else {
            lo = mid + 1;
        }
    }
    let mut why = Vec::new();
    match p.range {
        Some([a, b]) => why.push(format!(
            "processing.range [{a}, {b}] less {} samples at each end of it",
            p.trim.max(settle)
        )),
        None if p.trim >= settle && p.trim > 0 => why.push(format!(
            "{} samples at each end (processing.trim, within which the low-pass settles in \
             {settle})",
            p.trim
        )),
        None if settle > 0 => why.push(format!(
            "{settle} samples at each end for the low-pass to settle"
        )),
        None => {}
    }
    why.push(if kept == for_parameters {
        let decimated = if factor > 1 {
            format!(
                ", one sample in {factor} kept by processing.decimation less {} at each end \
                 that its filter does not settle",
                dec.unsettled()
            )
        } else {
            String::new()
        };
        format!(
            "{kept} between them for more equations than the {parameters} parameters at {} \
             equations per sample{decimated}",
            data.dof()
        )
    } else if kept == dec.min_len() && kept > 2 {
        format!("{kept} between them for the anti-alias filters of processing.decimation")
    } else {
        format!("{kept} between them")
    });
    let mut samples = lo;
    // the zero-phase filter of the whole record (q and tau are always filtered)
    if let Some(s) = sos.as_ref().filter(|_| {
        p.lowpass.as_ref().is_some_and(|lp| {
            lp.signals
                .iter()
                .any(|s| matches!(s, Signal::Q | Signal::Tau))
        })
    }) && s.pad_length() >= samples
    {
        samples = s.pad_length() + 1;
        why.push(format!(
            "{samples} in all for the low-pass's zero-phase filter"
        ));
    }
    // a Savitzky-Golay window over the whole record, when something is differentiated
    let measured = |d: Derivative, has: bool| d != Derivative::Differentiate && has;
    let differentiates = !measured(p.velocity, data.qd.is_some())
        || !measured(p.acceleration, data.qdd.is_some())
        || config.drive.rotor.is_some()
        || config.uses_rotor_signals();
    if let Some(w) = p
        .differentiation
        .savitzky_golay()
        .ok()
        .flatten()
        .map(|g| g.window())
        && differentiates
        && w > samples
    {
        samples = w;
        why.push(format!(
            "{w} in all for the Savitzky-Golay window of processing.differentiation"
        ));
    }
    Some(Need {
        samples,
        why: why.join(" and "),
    })
}

/// Share of the low-pass's impulse response left beyond a block's margin: the block's
/// edges change its kept samples by about this much of the signal, below the filter's own
/// rounding (about 1e-16 of the signal), which two differentiations amplify by 1 / dt^2
/// in the accelerations either way.
const BLOCK_TOLERANCE: f64 = 1e-20;

impl Plan {
    /// The plan of `config`'s `[processing]` for `data` with the range `rows`; checks the
    /// settings against the data (derivatives and motor encoders the data must have, the
    /// range and trims).
    pub(crate) fn new(data: &dyn Record, config: &Config, rows: Rows) -> Result<Self> {
        let p = &config.processing;
        let dt = data.sample_time();
        // the signals the record has, from its first sample
        let head = || data.read(0, 1);
        let auto_cutoff = match &p.lowpass {
            Some(lp) if lp.cutoff == Cutoff::Auto => Some(suggest_cutoff(data)?),
            _ => None,
        };
        // the low-pass's cutoff in Hz, chosen by "auto" or given
        let cutoff = p.lowpass.as_ref().map(|lp| {
            auto_cutoff
                .as_ref()
                .map_or(lp.cutoff.hz(), |s| Some(s.cutoff))
                .unwrap_or_default()
        });
        let sos = match (&p.lowpass, cutoff) {
            (Some(lp), Some(cutoff)) => Some({
                butterworth_hz(lp.order, cutoff, 1.0 / dt).map_err(|e| match e {
                    Error::Setting { key, problem, .. } => Error::setting(
                        "Config",
                        if key == "order" {
                            "processing.lowpass.order"
                        } else {
                            "processing.lowpass.cutoff"
                        },
                        format!(
                            "{problem} (cutoff {} Hz, data sampled at {} Hz)",
                            num(cutoff),
                            Num::rounded(1.0 / dt, 6)
                        ),
                    ),
                    e => e,
                })?
            }),
            _ => None,
        };
        let (pad, settle, tail) = match &sos {
            Some(s) => (
                s.settling_samples(PADDING_TOLERANCE, 1 << 20),
                s.settling_samples(SETTLING_TOLERANCE, 1 << 20),
                s.settling_samples(BLOCK_TOLERANCE, 1 << 22),
            ),
            None => (0, 0, 0),
        };
        let sg = p.differentiation.savitzky_golay()?;
        if p.velocity == Derivative::Data && head()?.qd.is_none() {
            return Err(missing("processing.velocity", "velocity"));
        }
        if p.acceleration == Derivative::Data && head()?.qdd.is_none() {
            return Err(missing("processing.acceleration", "acceleration"));
        }
        let mut friction = None;
        if config.drive.rotor.is_some() || config.uses_rotor_signals() {
            if head()?.motor.is_none() {
                return Err(no_motor(config));
            }
            if let Some(file) = config
                .drive
                .rotor
                .as_ref()
                .and_then(|r| r.friction.as_ref())
            {
                friction = Some(friction_model(config, file, data.dof())?);
            }
        }
        // the range is cut after filtering and differentiation, so that its ends are free
        // of filter start-up transients (a split of one record into training and test data)
        let range = match rows {
            Rows::Estimation => p.range,
            Rows::Validation => p.validation_range,
        };
        let (lo, hi) = match range {
            Some([a, b]) if a < b && b <= data.samples() => (a, b),
            Some([a, b]) => {
                return Err(Error::setting(
                    "Config",
                    rows.key(),
                    format!(
                        "[{a}, {b}] does not lie inside {}{}, which has {} samples; choose a \
                         range inside the data (the end is exclusive: at most {})",
                        data.name(),
                        joined_with(data),
                        data.samples(),
                        data.samples()
                    ),
                ));
            }
            None => (0, data.samples()),
        };
        // processing.trim inside the range, and at least one settling time from the
        // record's real ends (where the filter saw no data)
        let t = p.trim;
        let (start, end) = kept_bounds(data.samples(), (lo, hi), t, settle);
        if end <= start + 1 {
            let found = end.saturating_sub(start);
            // a Butterworth filter settles fastest near half the Nyquist frequency, and
            // ever more slowly towards 0 and towards the Nyquist frequency: which way
            // to move the cutoff depends on its side (it used to say "raise" always)
            let nyquist = 0.5 / dt;
            if let Some(c) = cutoff
                && hi.saturating_sub(t) > lo + t + 1
            {
                // the trims alone leave samples: the low-pass's settling takes them
                let (way, side) = if c > 0.5 * nyquist {
                    ("lower", "close to the Nyquist frequency")
                } else {
                    ("raise", "far below the Nyquist frequency")
                };
                // the cutoff as typed, or as chosen; the Nyquist frequency of a sample
                // time measured from time stamps rounded (499.9999879160976 Hz from Unix
                // time stamps at 1 kHz), but never onto the cutoff below it
                let chosen = if auto_cutoff.is_some() {
                    format!("\"auto\" chose {} Hz, which", Num::rounded(c, 6))
                } else {
                    format!("{} Hz", num(c))
                };
                let nyquist_shown = Num::rounded_keeping(nyquist, 6, |n| n > c);
                return Err(Error::setting(
                    "Config",
                    "processing.lowpass.cutoff",
                    format!(
                        "{chosen} settles over {settle} samples at each end of the record (a \
                         cutoff {side}, {} Hz, settles slowly), which leaves {found} of the {} \
                         samples of {}{} (at least 2 are needed); {way} it: the filter settles \
                         fastest near half the Nyquist frequency, {} Hz; or use a longer record",
                        nyquist_shown,
                        hi - lo,
                        data.name(),
                        joined_with(data),
                        Num::rounded(0.5 * nyquist, 6)
                    ),
                ));
            }
            return Err(Error::TooFewSamples {
                context: format!(
                    "{}{} after trimming {t} samples at each end ({settle} at the record's ends for the low-pass to settle)",
                    data.name(),
                    // "a.csv, joined with b.csv, after trimming"
                    Some(joined_with(data))
                        .filter(|j| !j.is_empty())
                        .map_or_else(String::new, |j| j + ","),
                ),
                found,
                required: 2,
                // the trims and the range alone leave too few: the cutoff is not the cause
                hint: match (range, rows) {
                    (Some(_), Rows::Estimation) => {
                        "reduce processing.trim, widen processing.range or use a longer record"
                    }
                    (Some(_), Rows::Validation) => {
                        "reduce processing.trim, widen processing.validation_range or use a \
                         longer record"
                    }
                    (None, _) => "reduce processing.trim or use a longer record",
                },
            });
        }
        // the filter's memory, two differentiations (or a Savitzky-Golay window) after it
        let stencil = sg.as_ref().map_or(2, |g| g.window());
        Ok(Self {
            sos,
            pad,
            sg,
            friction,
            kept: start..end,
            auto_cutoff,
            margin: tail + stencil + 1,
        })
    }

    /// The prepared signals of the kept samples `block` (indices into [`Plan::kept`]) and
    /// their torque before the low-pass when the low-pass filters the torque: the
    /// samples of the whole record's preparation, to [`BLOCK_TOLERANCE`] of the signals
    /// (the same when the block and its margins reach both ends of the record).
    pub(crate) fn block(
        &self,
        data: &dyn Record,
        config: &Config,
        block: std::ops::Range<usize>,
    ) -> Result<(Prepared, Option<Signals>)> {
        let (start, end) = (self.kept.start + block.start, self.kept.start + block.end);
        let from = start.saturating_sub(self.margin);
        let to = (end + self.margin).min(data.samples());
        let (prepared, unfiltered) = self.signals(data.read(from, to)?, config)?;
        self.cut(data, from, prepared, unfiltered, start..end)
    }

    /// The samples `keep` of `data` from signals prepared from its sample `from` on,
    /// checked finite.
    fn cut(
        &self,
        data: &dyn Record,
        from: usize,
        prepared: Prepared,
        unfiltered: Option<Signals>,
        keep: std::ops::Range<usize>,
    ) -> Result<(Prepared, Option<Signals>)> {
        let local = keep.start - from..keep.end - from;
        let prepared = Prepared {
            q: prepared.q.into_range(local.clone()),
            qd: prepared.qd.into_range(local.clone()),
            qdd: prepared.qdd.into_range(local.clone()),
            tau: prepared.tau.into_range(local.clone()),
            rotor: prepared.rotor.map(|r| RotorStates {
                thetad: r.thetad.into_range(local.clone()),
                thetadd: r.thetadd.into_range(local.clone()),
                temperature: r.temperature.map(|t| t.into_range(local.clone())),
                joint_torque: r.joint_torque.map(|t| t.into_range(local.clone())),
            }),
            sample_time: prepared.sample_time,
        };
        let rotor = prepared.rotor.as_ref();
        let rotor = [
            rotor.map(|r| ("motor velocity", &r.thetad)),
            rotor.map(|r| ("motor acceleration", &r.thetadd)),
        ];
        for (signal, x) in [
            ("position", &prepared.q),
            ("velocity", &prepared.qd),
            ("acceleration", &prepared.qdd),
            ("torque", &prepared.tau),
        ]
        .into_iter()
        .chain(rotor.into_iter().flatten())
        {
            if let Some((j, k)) = x.first_non_finite() {
                return Err(Error::NonFiniteResult {
                    what: format!(
                        "the processed {signal} of joint {} at {}",
                        j + 1,
                        data.location(keep.start + k)
                    ),
                    cause: "the low-pass filter, differentiation or rotor compensation overflowed; check [processing] (a higher cutoff, measured velocities) and the data near that row".into(),
                });
            }
        }
        Ok((prepared, unfiltered.map(|t| t.into_range(local))))
    }

    /// Every sample of `data` prepared (low-pass, derivatives, rotor compensation), and
    /// the torque before the low-pass when the low-pass filters it. The torque the
    /// low-pass leaves as it is is moved out of `data` when it is owned (a block read from
    /// a record), not copied.
    fn signals(
        &self,
        mut data: Cow<'_, Dataset>,
        config: &Config,
    ) -> Result<(Prepared, Option<Signals>)> {
        let p = &config.processing;
        let dt = data.sample_time;
        let pad = self.pad;
        let on = |s: Signal| {
            self.sos
                .as_ref()
                .filter(|_| p.lowpass.as_ref().is_some_and(|lp| lp.signals.contains(&s)))
        };
        let sg = self.sg.as_ref();
        let q = filter_all(on(Signal::Q), pad, &data.q)?;
        let (qd, qd_measured) = match (p.velocity, &data.qd) {
            (Derivative::Auto | Derivative::Data, Some(v)) => {
                (filter_all(on(Signal::Qd), pad, v)?, true)
            }
            (Derivative::Data, None) => return Err(missing("processing.velocity", "velocity")),
            _ => (differentiate(&q, dt, sg)?, false),
        };
        let qdd = match (p.acceleration, &data.qdd) {
            (Derivative::Auto | Derivative::Data, Some(a)) => filter_all(on(Signal::Qdd), pad, a)?,
            (Derivative::Data, None) => {
                return Err(missing("processing.acceleration", "acceleration"));
            }
            // a measured velocity is differentiated once, a differentiated one from q
            _ if qd_measured => differentiate(&qd, dt, sg)?,
            _ => differentiate_twice(&q, &qd, dt, sg)?,
        };
        let mut tau = match (on(Signal::Tau), &mut data) {
            (None, Cow::Owned(d)) => std::mem::take(&mut d.tau),
            (sos, d) => filter_all(sos, pad, &d.tau)?,
        };
        let mut unfiltered_tau = on(Signal::Tau).map(|_| data.tau.clone());
        let mut rotor_states = None;
        if config.drive.rotor.is_some() || config.uses_rotor_signals() {
            let motor = data.motor.as_ref().ok_or_else(|| no_motor(config))?;
            let theta = filter_all(on(Signal::Q), pad, motor)?;
            let thetad = differentiate(&theta, dt, sg)?;
            let thetadd = differentiate_twice(&theta, &thetad, dt, sg)?;
            if let Some(rotor) = &config.drive.rotor {
                for t in std::iter::once(&mut tau).chain(unfiltered_tau.as_mut()) {
                    match &self.friction {
                        Some(m) => rotor.compensate_nonlinear(
                            m,
                            t,
                            &thetad,
                            &thetadd,
                            data.temperature.as_ref(),
                        )?,
                        None => rotor.compensate(t, &thetad, &thetadd)?,
                    }
                }
            }
            let joint_torque = match &data.joint_torque {
                Some(t) => Some(filter_all(on(Signal::Tau), pad, t)?),
                None => None,
            };
            rotor_states = Some(RotorStates {
                thetad,
                thetadd,
                temperature: data.temperature.clone(),
                joint_torque,
            });
        }
        Ok((
            Prepared {
                q,
                qd,
                qdd,
                tau,
                rotor: rotor_states,
                sample_time: dt,
            },
            unfiltered_tau,
        ))
    }
}

/// The friction model of `[drive.rotor] friction` (resolved against the config's folder),
/// checked against the data's joint count.
fn friction_model(config: &Config, file: &std::path::Path, dof: usize) -> Result<FrictionModel> {
    let path = config.resolve(file);
    let model = FrictionModel::read(&path).map_err(|e| match e {
        // the file the key names is missing: the key is what to look at, not the path alone
        Error::Data(crate::DataError::Io { ref source, .. })
            if source.kind() == std::io::ErrorKind::NotFound =>
        {
            config.key_error(
                "drive.rotor.friction",
                format!(
                    "the friction file {} does not exist (a relative path is read from the \
                     config's folder); `robid friction` writes it from a log with joint-torque \
                     sensors (docs/identification.md#nonlinear-rotor-friction), or remove the \
                     line to identify viscous and Coulomb friction instead",
                    path.display()
                ),
            )
        }
        e => e,
    })?;
    if model.dof() != dof {
        return Err(config.key_error(
            "drive.rotor.friction",
            format!(
                "{} has {}, but the data have {}; give one table per joint (robid friction writes them)",
                path.display(),
                crate::Count(model.dof(), "[[friction]] table"),
                crate::Count(dof, "joint")
            ),
        ));
    }
    Ok(model)
}

/// The error for a config that uses the motor encoders on data without them, at the
/// first key that does.
fn no_motor(config: &Config) -> Error {
    let user = config.extra_columns.iter().enumerate().find_map(|(i, c)| {
        let (k, signal) = c.rotor_term()?;
        Some((
            format!("extra_column[{}].terms[{}].signal", i + 1, k + 1),
            crate::drive::signal_name(signal),
        ))
    });
    let (key, what) = match (&config.drive.rotor, user) {
        (Some(_), _) => ("drive.rotor".to_string(), "rotor compensation"),
        (None, Some((key, signal))) => (key, signal),
        (None, None) => ("drive.rotor".to_string(), "rotor compensation"),
    };
    Error::setting(
        "Config",
        &key,
        format!(
            "{what} needs the motor encoders, but the data has no `motor_position` columns; \
             add motor_position = [...] to a [[source]]"
        ),
    )
}

fn missing(key: &str, role: &str) -> Error {
    Error::setting(
        "Config",
        key,
        format!(
            "the data has no `{role}` columns; add them to a [[source]] or let robid differentiate (\"auto\")"
        ),
    )
}
