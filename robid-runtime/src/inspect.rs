//! Diagnostics of a data set before identification (docs/identification.md#choosing-the-cutoff):
//! per joint the bandwidth and noise of positions and torques, saturation and time at
//! rest; per file the sampling; and a low-pass cutoff with its reason, which
//! `cutoff = "auto"` in a config uses.
//!
//! The cutoff rule. Accelerations are differentiated twice from the positions, so the
//! low-pass must pass the motion and stop the noise. The motion's bandwidth is where the
//! positions hold [`MOTION_SHARE`] of their power (the largest over the joints that
//! move); a zero-phase Butterworth at [`MOTION_MARGIN`] times that frequency passes the
//! motion's harmonics undistorted (an order-4 filter applied forward and backward keeps
//! 99.6 % of the amplitude at a fifth of its cutoff). When some moving joint's position
//! spectrum meets its noise floor (it falls below [`NOISE_RATIO`] times the floor)
//! below that, the cutoff moves down to there, but not below [`MIN_MARGIN`] times the
//! motion's bandwidth.

use serde::{Deserialize, Serialize};

use crate::data::{Config, Cutoff, Dataset, Record, Sampling};
use crate::error::{Error, Result};
use crate::signal::{Spectrum, Welch, butterworth_hz};

mod rest;

/// Share of the positions' power that defines the motion's bandwidth.
pub const MOTION_SHARE: f64 = 0.999;
/// Cutoff over motion bandwidth.
pub const MOTION_MARGIN: f64 = 5.0;
/// The least cutoff over motion bandwidth, however noisy the positions.
pub const MIN_MARGIN: f64 = 2.0;
/// A position spectrum this many times its noise floor is still signal.
pub const NOISE_RATIO: f64 = 100.0;
/// Share of a torque's power that defines its bandwidth.
pub const TORQUE_SHARE: f64 = 0.99;
/// A joint moves when its position's standard deviation is this many times its noise.
pub const MOVING_RATIO: f64 = 10.0;
/// A torque within this share of its extreme value counts as at the extreme.
pub const EXTREME_TOLERANCE: f64 = 1e-3;
/// The least standard deviation of a moving position (rad or m).
pub const MIN_MOTION: f64 = 1e-9;
/// The low-pass of the positions whose velocities give the time at rest (a log without
/// velocity columns) when no joint moves, so that no cutoff follows from the motion: this
/// share of the Nyquist frequency.
pub const STILL_CUTOFF_SHARE: f64 = 0.1;
/// Velocity below which a joint is at rest when the config gives none (rad/s or m/s):
/// the threshold identification uses then.
pub const DEFAULT_REST_VELOCITY: f64 = crate::data::DEFAULT_REST_VELOCITY;

/// A suggested low-pass cutoff and why.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CutoffSuggestion {
    /// The cutoff (Hz).
    pub cutoff: f64,
    /// The motion's bandwidth (Hz): where the positions hold [`MOTION_SHARE`] of their power.
    pub motion_bandwidth: f64,
    /// The joint (1-based) with the widest motion.
    pub joint: usize,
    /// One sentence for people.
    pub reason: String,
}

/// What the data show about one joint.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct JointReport {
    /// Joint number (1-based).
    pub joint: usize,
    /// Whether the joint moves (its position's spread is [`MOVING_RATIO`] times its noise).
    pub moves: bool,
    /// Smallest and largest position (rad or m).
    pub position_range: [f64; 2],
    /// Where the detrended position holds [`MOTION_SHARE`] of its power (Hz); `None` for a
    /// joint that does not move (`moves` false): a joint at rest has no bandwidth (a
    /// constant position has no power, and the cumulative share ran to the Nyquist
    /// frequency, reported as its bandwidth; noise alone fills the band as well).
    pub position_bandwidth: Option<f64>,
    /// The highest frequency where the position spectrum is [`NOISE_RATIO`] times its
    /// noise floor (Hz).
    pub position_signal_top: f64,
    /// RMS of the position noise, from the spectrum's floor (rad or m).
    pub position_noise: f64,
    /// Where the detrended torque holds [`TORQUE_SHARE`] of its power (Hz); `None` for a
    /// constant torque (a column of zeros, a joint that carries no load), whose residue
    /// of rounding spreads over every frequency and used to be reported near Nyquist.
    pub torque_bandwidth: Option<f64>,
    /// RMS of the torque noise, from the spectrum's floor (N m or N).
    pub torque_noise: f64,
    /// Share of samples whose torque lies within [`EXTREME_TOLERANCE`] of the largest
    /// or the smallest torque of the record (a clipped signal holds many).
    pub torque_at_extremes: f64,
    /// Share of samples whose torque magnitude is at least 98 % of the description's
    /// torque limit, when it has one.
    pub torque_at_limit: Option<f64>,
    /// Share of samples at rest: |velocity| below the rest velocity, or every sample of
    /// a joint that does not move (`moves` false), whatever its velocity's noise (under
    /// `rest_velocity = 0` such a joint was "at rest 0.0 %" beside "moves no").
    pub at_rest: f64,
    /// The velocity column's scale against the positions' derivative, 1 when they agree
    /// ([`DerivativeAgreement::scale`]: 57.3 for degrees per second beside radians);
    /// `None` when the record has no velocity columns (or is a data set built in memory,
    /// without the loader's sums) or the joint does not move.
    ///
    /// [`DerivativeAgreement::scale`]: crate::data::DerivativeAgreement::scale
    pub velocity_scale: Option<f64>,
    /// How closely the velocity column follows the positions' derivative: the correlation
    /// of its integral with the positions' change over strides of 8 samples, near 1 when
    /// it is their derivative in any unit ([`DerivativeAgreement::correlation`]); `None` as
    /// for the scale. Far below 1 for a moving joint, the column is not this joint's
    /// velocity, or is mostly noise.
    ///
    /// [`DerivativeAgreement::correlation`]: crate::data::DerivativeAgreement::correlation
    pub velocity_correlation: Option<f64>,
}

/// The diagnostics of a data set.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Inspection {
    /// The data set's name.
    pub name: String,
    /// Sample rate after loading (Hz).
    pub sample_rate: f64,
    /// Samples.
    pub samples: usize,
    /// Each file's sampling.
    pub sampling: Vec<Sampling>,
    /// Per joint.
    pub joints: Vec<JointReport>,
    /// The suggested low-pass cutoff; `None` when no joint moves beyond its noise (the
    /// cutoff follows the motion: with none there is nothing to suggest, and
    /// `cutoff = "auto"` refuses the data). Everything else is reported all the same.
    pub cutoff: Option<CutoffSuggestion>,
    /// The rest velocity used (rad/s or m/s per joint).
    pub rest_velocity: Vec<f64>,
}

/// The error for a signal of `data` that has no spectrum: too short, or not finite.
fn no_spectrum(data: &dyn Record, what: &str, joint: usize) -> Error {
    Error::TooFewSamples {
        context: format!(
            "{}: the spectrum of the {what} of joint {joint}",
            files(data)
        ),
        found: data.samples(),
        required: crate::signal::MIN_SPECTRUM_SAMPLES,
        hint: "a spectrum needs a longer record: record a longer trajectory",
    }
}

/// The files of `data` (each source's, joined), else its name.
fn files(data: &dyn Record) -> String {
    let files = data.files();
    if files.is_empty() {
        return format!("data set `{}`", data.name());
    }
    files
        .iter()
        .map(|p| p.display().to_string())
        .collect::<Vec<_>>()
        .join(" + ")
}

/// Samples read at a time for the position spectra of [`suggest_cutoff`].
const SPECTRUM_BLOCK: usize = 1 << 16;

/// The spectrum of each joint's position in `data`, read block by block ([`Welch`]), so
/// that a record kept on disk is never held whole.
fn position_spectra(data: &dyn Record) -> Result<Vec<Spectrum>> {
    let (n, rate) = (data.samples(), 1.0 / data.sample_time());
    let mut spectra =
        Welch::new(data.dof(), n, rate).ok_or_else(|| no_spectrum(data, "position", 1))?;
    for start in (0..n).step_by(SPECTRUM_BLOCK) {
        let block = data.read(start, start + SPECTRUM_BLOCK)?;
        for (j, q) in block.q.joints().enumerate() {
            spectra.push(j, q);
        }
    }
    spectra
        .finish()
        .into_iter()
        .enumerate()
        .map(|(j, s)| s.ok_or_else(|| no_spectrum(data, "position", j + 1)))
        .collect()
}

/// The suggested low-pass cutoff for the positions of `data` (see the module's rule),
/// read block by block.
pub fn suggest_cutoff(data: &dyn Record) -> Result<CutoffSuggestion> {
    cutoff_of(data, &position_spectra(data)?).ok_or_else(|| {
        Error::setting(
            "Config",
            "processing.lowpass.cutoff",
            format!(
                "\"auto\" needs motion, and no joint of {} moves beyond its noise; give the cutoff in Hz",
                data.name()
            ),
        )
    })
}

/// The suggested low-pass cutoff for `data` from the spectra of its positions; `None` when
/// no joint moves beyond its noise.
fn cutoff_of(data: &dyn Record, spectra: &[Spectrum]) -> Option<CutoffSuggestion> {
    let rate = 1.0 / data.sample_time();
    let mut widest: Option<(f64, usize)> = None;
    let mut noisiest: Option<(f64, usize)> = None;
    for (j, s) in spectra.iter().enumerate() {
        if !moves(s) {
            continue;
        }
        // MOTION_SHARE lies in [0, 1]: always a bandwidth
        let Some(b) = s.bandwidth(MOTION_SHARE) else {
            continue;
        };
        if widest.is_none_or(|(w, _)| b > w) {
            widest = Some((b, j + 1));
        }
        let top = s.above_floor(NOISE_RATIO);
        if noisiest.is_none_or(|(t, _)| top < t) {
            noisiest = Some((top, j + 1));
        }
    }
    let (motion, joint) = widest?;
    let nyquist = rate / 2.0;
    let mut cutoff = MOTION_MARGIN * motion;
    let mut reason = format!(
        "the positions hold {:.1} % of their power below {} Hz (joint {joint}); {MOTION_MARGIN} times that passes the motion undistorted",
        100.0 * MOTION_SHARE,
        two_digits(motion)
    );
    if let Some((top, noisy)) = noisiest
        && top < cutoff
    {
        cutoff = top.max(MIN_MARGIN * motion);
        reason += &format!(
            ", lowered to where joint {noisy}'s position spectrum meets its noise floor ({} Hz; at least {MIN_MARGIN} times the motion)",
            two_digits(top)
        );
    }
    let highest = 0.8 * nyquist;
    if cutoff > highest {
        cutoff = highest;
        reason += &format!(
            ", capped at 0.8 times the Nyquist frequency ({} Hz)",
            two_digits(nyquist)
        );
    }
    let lowest = crate::signal::MIN_CUTOFF * nyquist * 1.01;
    Some(CutoffSuggestion {
        cutoff: two_digits(cutoff).max(lowest),
        motion_bandwidth: motion,
        joint,
        reason,
    })
}

/// Replaces `cutoff = "auto"` in `config` by the cutoff suggested for `data` and returns
/// the suggestion (`None` when the config gives a frequency or no low-pass). Resolve it
/// once on the estimation data so that validation data are filtered the same way.
pub fn resolve_cutoff(config: &mut Config, data: &dyn Record) -> Result<Option<CutoffSuggestion>> {
    match &mut config.processing.lowpass {
        Some(lp) if lp.cutoff == Cutoff::Auto => {
            let s = suggest_cutoff(data)?;
            lp.cutoff = Cutoff::Hz(s.cutoff);
            Ok(Some(s))
        }
        _ => Ok(None),
    }
}

/// Whether a position with spectrum `s` moves beyond its noise (and beyond rounding: a
/// constant signal's detrended residue is of the order of 1e-17).
fn moves(s: &Spectrum) -> bool {
    let spread = s.power().sqrt();
    spread > MOVING_RATIO * s.noise_rms() && spread > MIN_MOTION
}

/// The bandwidth of a position's motion, `None` when the joint does not move ([`moves`]).
fn position_bandwidth(s: &Spectrum) -> Option<f64> {
    moves(s).then(|| s.bandwidth(MOTION_SHARE)).flatten()
}

/// Spread (RMS of the detrended torque, N m or N) below which a torque is constant:
/// rounding leaves about 1e-15 of its value.
pub const MIN_TORQUE_SPREAD: f64 = 1e-9;

/// The bandwidth of a torque, `None` when it is constant.
fn torque_bandwidth(s: &Spectrum) -> Option<f64> {
    (s.power().sqrt() > MIN_TORQUE_SPREAD)
        .then(|| s.bandwidth(TORQUE_SHARE))
        .flatten()
}

/// `x` rounded to two significant digits (the double nearest the decimal, so that it
/// prints as written: 2.9, not 2.9000000000000004).
fn two_digits(x: f64) -> f64 {
    if !(x > 0.0 && x.is_finite()) {
        return x;
    }
    format!("{x:.1e}").parse().unwrap_or(x)
}

/// The diagnostics of `data`; `config` gives the rest velocity (default
/// [`DEFAULT_REST_VELOCITY`]), `torque_limits` the description's limits where it has them.
/// [`inspect_record`] of a data set in memory, with its sampling.
pub fn inspect(
    data: &Dataset,
    config: &Config,
    torque_limits: &[Option<f64>],
) -> Result<Inspection> {
    inspect_record(data, data.sampling.clone(), config, torque_limits)
}

/// Samples read at a time by [`inspect_record`].
const INSPECT_BLOCK: usize = SPECTRUM_BLOCK;

/// The diagnostics of `data` read block by block, so that a record kept on disk
/// ([`crate::data::SpilledRecord`]) is never held whole: the same as [`inspect`] of the
/// same samples in memory, to the bit. `sampling` is each file's sampling (what the
/// report shows of them); `config` gives the rest velocity (default
/// [`DEFAULT_REST_VELOCITY`]), `torque_limits` the description's limits where it has them.
///
/// The record is read two or three times: once for the spectra, the ranges and the
/// torque at its limit, once for the torque at its extremes (which needs the torque's
/// range) and, when the data have no velocities, the low-pass's forward pass, and once
/// more, from the last block to the first, for its backward pass (the time at rest from
/// the velocities of the low-passed positions).
pub fn inspect_record(
    data: &dyn Record,
    sampling: Vec<Sampling>,
    config: &Config,
    torque_limits: &[Option<f64>],
) -> Result<Inspection> {
    inspect_in(data, sampling, config, torque_limits, INSPECT_BLOCK)
}

/// What the first pass gathers of one joint besides its spectra.
struct Gathered {
    /// Smallest and largest position, and torque.
    position_range: (f64, f64),
    torque_range: (f64, f64),
    /// Samples whose torque is at 98 % of the limit or beyond.
    at_limit: usize,
    /// Samples at rest by the measured velocity.
    at_rest: usize,
}

/// `range` widened to the values of `x`, in order.
fn widen(range: &mut (f64, f64), x: &[f64]) {
    *range = x.iter().fold(*range, |(a, b), v| (a.min(*v), b.max(*v)));
}

/// [`inspect_record`] reading `block` samples at a time.
fn inspect_in(
    data: &dyn Record,
    sampling: Vec<Sampling>,
    config: &Config,
    torque_limits: &[Option<f64>],
    block: usize,
) -> Result<Inspection> {
    let (n, dof) = (data.samples(), data.dof());
    let rate = 1.0 / data.sample_time();
    let block = block.max(1);
    let rest_velocity = config.processing.rest_velocities(dof)?;
    let limit = |j: usize| torque_limits.get(j).copied().flatten();
    // the spectra of the positions (0..dof), then of the torques
    let mut spectra =
        Welch::new(2 * dof, n, rate).ok_or_else(|| no_spectrum(data, "position", 1))?;
    let mut joints: Vec<Gathered> = (0..dof)
        .map(|_| Gathered {
            position_range: (f64::INFINITY, f64::NEG_INFINITY),
            torque_range: (f64::INFINITY, f64::NEG_INFINITY),
            at_limit: 0,
            at_rest: 0,
        })
        .collect();
    // the first pass: spectra, ranges, the torque at its limit, rest by measured velocity
    let mut measured = false;
    for start in (0..n).step_by(block) {
        let part = data.read(start, start + block)?;
        measured = part.qd.is_some();
        for (j, g) in joints.iter_mut().enumerate() {
            let (q, tau) = (&part.q[j], &part.tau[j]);
            spectra.push(j, q);
            spectra.push(dof + j, tau);
            widen(&mut g.position_range, q);
            widen(&mut g.torque_range, tau);
            if let Some(l) = limit(j) {
                g.at_limit += tau.iter().filter(|v| v.abs() >= 0.98 * l).count();
            }
            if let Some(qd) = &part.qd {
                g.at_rest += qd[j].iter().filter(|v| v.abs() < rest_velocity[j]).count();
            }
        }
    }
    let mut torques = spectra.finish();
    let positions = torques
        .drain(..dof)
        .enumerate()
        .map(|(j, s)| s.ok_or_else(|| no_spectrum(data, "position", j + 1)))
        .collect::<Result<Vec<_>>>()?;
    let ranges: Vec<_> = joints
        .iter()
        .map(|g| (g.position_range, g.torque_range))
        .collect();
    let counts: Vec<_> = joints.iter().map(|g| (g.at_limit, g.at_rest)).collect();
    // a log where nothing moves is reported (sampling, noise, ranges, time at rest), with
    // no cutoff: inspecting it once ended in the error of `cutoff = "auto"`
    let cutoff = cutoff_of(data, &positions);
    // the second pass (and the third, backwards, for velocities from the positions): the
    // torque at its extremes, which needs the torque's range
    let mut at_extremes = vec![0usize; dof];
    let mut extremes = |part: &Dataset| {
        for (j, count) in at_extremes.iter_mut().enumerate() {
            let (tlo, thi) = ranges[j].1;
            let span = (thi - tlo).max(f64::MIN_POSITIVE);
            *count += part.tau[j]
                .iter()
                .filter(|v| {
                    (thi - **v) <= EXTREME_TOLERANCE * span
                        || (**v - tlo) <= EXTREME_TOLERANCE * span
                })
                .count();
        }
    };
    let at_rest = if measured {
        for start in (0..n).step_by(block) {
            extremes(&*data.read(start, start + block)?);
        }
        counts.iter().map(|c| c.1).collect()
    } else {
        let at = cutoff
            .as_ref()
            .map_or(STILL_CUTOFF_SHARE * rate / 2.0, |c| c.cutoff);
        let sos = butterworth_hz(4, at, rate)?;
        rest::rest_counts(data, &sos, &rest_velocity, block, extremes)?
    };
    let count = n as f64;
    let joints = positions
        .into_iter()
        .zip(torques)
        .enumerate()
        .map(|(j, (sq, st))| {
            let st = st.ok_or_else(|| no_spectrum(data, "torque", j + 1))?;
            let ((lo, hi), _) = ranges[j];
            let moves = moves(&sq);
            let agreement = data.extremes().velocity.get(j).filter(|_| moves);
            Ok(JointReport {
                joint: j + 1,
                moves,
                position_range: [lo, hi],
                position_bandwidth: position_bandwidth(&sq),
                position_signal_top: sq.above_floor(NOISE_RATIO),
                position_noise: sq.noise_rms(),
                torque_bandwidth: torque_bandwidth(&st),
                torque_noise: st.noise_rms(),
                torque_at_extremes: at_extremes[j] as f64 / count,
                torque_at_limit: limit(j).map(|_| counts[j].0 as f64 / count),
                at_rest: if moves {
                    at_rest[j] as f64 / count
                } else {
                    1.0
                },
                velocity_scale: agreement.and_then(|a| a.scale()),
                velocity_correlation: agreement.and_then(|a| a.correlation()),
            })
        })
        .collect::<Result<_>>()?;
    Ok(Inspection {
        name: data.name().to_string(),
        sample_rate: rate,
        samples: n,
        sampling,
        joints,
        cutoff,
        rest_velocity,
    })
}

impl Inspection {
    /// A table for people.
    pub fn text(&self) -> String {
        use std::fmt::Write as _;
        let mut s = format!(
            "{}: {} samples at {:.1} Hz\n",
            self.name, self.samples, self.sample_rate
        );
        for f in &self.sampling {
            let _ = writeln!(s, "  {}", f.summary());
        }
        let _ = writeln!(
            s,
            "\n  j  moves  position range        bandwidth  signal to  noise       torque bw  torque noise  at extremes  at limit  at rest  velocity\n                                   (99.9 %)   (100x floor)  (position)  (99 %)     (RMS)                                     (x dq/dt)"
        );
        for r in &self.joints {
            let limit = r
                .torque_at_limit
                .map_or_else(|| "-".to_string(), |v| format!("{:.1} %", 100.0 * v));
            // a joint that does not move has no bandwidth: said so, in the column's width
            let bandwidth = r
                .position_bandwidth
                .map_or_else(|| "at rest".to_string(), |b| format!("{b:.2} Hz"));
            // nor a constant torque
            let torque_bandwidth = r
                .torque_bandwidth
                .map_or_else(|| "constant".to_string(), |b| format!("{b:.1} Hz"));
            let velocity = velocity_column(r);
            let _ = writeln!(
                s,
                "{:>3}  {:<5}  [{:>8.3}, {:>8.3}]  {:>10}  {:>7.1} Hz  {:>9.2e}  {:>10}  {:>11.2e}  {:>9.1} %  {:>8}  {:>5.1} %  {:>9}",
                r.joint,
                if r.moves { "yes" } else { "no" },
                r.position_range[0],
                r.position_range[1],
                bandwidth,
                r.position_signal_top,
                r.position_noise,
                torque_bandwidth,
                r.torque_noise,
                100.0 * r.torque_at_extremes,
                limit,
                100.0 * r.at_rest,
                velocity
            );
        }
        let _ = match &self.cutoff {
            Some(c) => writeln!(
                s,
                "\nsuggested low-pass cutoff: {} Hz ({})",
                c.cutoff, c.reason
            ),
            None => writeln!(
                s,
                "\nno joint moves beyond its noise: no low-pass cutoff to suggest (it follows \
                 the motion; cutoff = \"auto\" refuses these data), and identification needs \
                 motion: record a trajectory that moves the joints (robid excite designs one)"
            ),
        };
        s
    }
}

/// The table's velocity column of joint report `r`: the scale when the velocities follow
/// the positions (`1` or `0.9991` when they agree, `57.3` for degrees per second), their correlation when they do not clearly
/// (`r 0.42`), `-` without velocity columns or motion.
fn velocity_column(r: &JointReport) -> String {
    use crate::data::AGREEMENT_CORRELATION;
    match (r.velocity_scale, r.velocity_correlation) {
        (Some(s), Some(c)) if c.abs() >= AGREEMENT_CORRELATION => {
            crate::Num::rounded(s, 4).to_string()
        }
        (_, Some(c)) => format!("r {c:.2}"),
        _ => "-".to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;
    use crate::signal::Signals;

    /// Two joints: one moving (0.5 and 2 Hz, plus weak vibrations from 3 to 30 Hz that
    /// hold 3e-7 of the power) with white noise of standard deviation `noise`, one at rest
    /// (noise only).
    fn data(noise: f64) -> Dataset {
        let rate = 500.0;
        let n = 30_000;
        let mut rng = Rng::new(3);
        let two_pi = 2.0 * std::f64::consts::PI;
        let q0: Vec<f64> = (0..n)
            .map(|k| {
                let t = k as f64 / rate;
                let vibration: f64 = (3..=30).map(|f| 1e-4 * (two_pi * f as f64 * t).sin()).sum();
                (two_pi * 0.5 * t).sin()
                    + 0.2 * (two_pi * 2.0 * t).sin()
                    + vibration
                    + noise * rng.normal()
            })
            .collect();
        let q1: Vec<f64> = (0..n).map(|_| 1e-4 * rng.normal()).collect();
        let tau: Vec<Vec<f64>> = vec![q0.iter().map(|q| 3.0 * q).collect(), vec![0.5; n]];
        Dataset::new(
            "test",
            1.0 / rate,
            Signals::new(vec![q0, q1]).unwrap(),
            Signals::new(tau).unwrap(),
        )
        .unwrap()
    }

    /// A log where no joint moves is reported, not refused: every joint said not to move
    /// and at rest, no cutoff suggested and the text saying why (it failed with the error
    /// of `cutoff = "auto"`, "auto needs motion"), while the suggestion `"auto"` asks for
    /// is still refused.
    #[test]
    fn a_log_where_nothing_moves_is_reported() {
        let moving = data(1e-5);
        let still = Dataset::new(
            "still",
            moving.sample_time,
            Signals::new(vec![moving.q[1].to_vec(), moving.q[1].to_vec()]).unwrap(),
            moving.tau.clone(),
        )
        .unwrap();
        let i = inspect(&still, &Config::default(), &[None, None]).unwrap();
        assert!(i.cutoff.is_none(), "{:?}", i.cutoff);
        assert!(
            i.joints.iter().all(|j| !j.moves && j.at_rest > 0.99),
            "{:?}",
            i.joints
        );
        assert!(i.joints[0].torque_noise > 0.0);
        let text = i.text();
        assert!(
            text.contains("no joint moves beyond its noise: no low-pass cutoff to suggest"),
            "{text}"
        );
        let e = suggest_cutoff(&still).unwrap_err().to_string();
        assert!(e.contains("\"auto\" needs motion"), "{e}");
    }

    /// A joint that does not move has no bandwidth: a constant position (no power at all)
    /// and a noisy one alike are reported at rest, in the JSON as `null`, while the moving
    /// joint keeps its bandwidth. The constant joint's was the Nyquist frequency, "250.00
    /// Hz", the noisy one's near it.
    #[test]
    fn a_joint_at_rest_has_no_bandwidth() {
        let moving = data(1e-5);
        let n = moving.q[0].len();
        for (what, rest) in [("constant", vec![0.3; n]), ("noisy", moving.q[1].to_vec())] {
            let d = Dataset::new(
                "rest",
                moving.sample_time,
                Signals::new(vec![moving.q[0].to_vec(), rest]).unwrap(),
                moving.tau.clone(),
            )
            .unwrap();
            let i = inspect(&d, &Config::default(), &[None, None]).unwrap();
            let b = i.joints[0].position_bandwidth.unwrap();
            assert!((b - 2.0).abs() < 0.25, "{what}: {b}");
            assert_eq!(i.joints[1].position_bandwidth, None, "{what}");
            let text = i.text();
            let row = text
                .lines()
                .find(|l| l.starts_with("  2  no"))
                .unwrap_or_else(|| panic!("{what}: {text}"));
            assert!(row.contains("]     at rest  "), "{what}: {row}");
            assert!(!row.contains("250.00"), "{what}: {row}");
            let json = serde_json::to_value(&i).unwrap();
            assert!(json["joints"][1]["position_bandwidth"].is_null(), "{what}");
            // a joint that does not move is at rest throughout, even where no velocity
            // is below the rest velocity (it was "at rest 0.0 %" under 0)
            let mut config = Config::default();
            config.processing.rest_velocity = Some(crate::data::PerJoint::All(0.0));
            let i = inspect(&d, &config, &[None, None]).unwrap();
            assert_eq!(i.joints[1].at_rest, 1.0, "{what}");
            assert!(i.joints[0].at_rest < 0.01, "{what}: {:?}", i.joints[0]);
        }
    }

    /// A constant torque (here a column of zeros) has no bandwidth either: "constant", in
    /// the JSON `null`; it was reported near the Nyquist frequency.
    #[test]
    fn a_constant_torque_has_no_bandwidth() {
        let moving = data(1e-5);
        let n = moving.q[0].len();
        let d = Dataset::new(
            "still torque",
            moving.sample_time,
            moving.q.clone(),
            Signals::new(vec![moving.tau[0].to_vec(), vec![0.0; n]]).unwrap(),
        )
        .unwrap();
        let i = inspect(&d, &Config::default(), &[None, None]).unwrap();
        assert!(i.joints[0].torque_bandwidth.is_some());
        assert_eq!(i.joints[1].torque_bandwidth, None);
        let text = i.text();
        let row = text.lines().find(|l| l.starts_with("  2  ")).unwrap();
        assert!(row.contains("    constant  "), "{row}");
        let json = serde_json::to_value(&i).unwrap();
        assert!(json["joints"][1]["torque_bandwidth"].is_null());
    }

    /// The widest motion is the moving joint's; the vibrations stand above the noise up to
    /// 30 Hz, so the cutoff is five times the motion's bandwidth; the resting joint is said
    /// not to move and to be at rest.
    #[test]
    fn the_cutoff_is_five_times_the_motion() {
        let d = data(1e-5);
        let c = suggest_cutoff(&d).unwrap();
        assert_eq!(c.joint, 1);
        // 99.9 % of the power: the 2 Hz harmonic holds 3.8 % of it, so the bandwidth is
        // on that line (within the Hann window's leakage; measured 2.13 Hz, seeded)
        assert!((c.motion_bandwidth - 2.0).abs() < 0.25, "{c:?}");
        assert!(
            (c.cutoff - two_digits(5.0 * c.motion_bandwidth)).abs() < 1e-12,
            "{c:?}"
        );
        assert!(c.reason.contains("joint 1"), "{}", c.reason);
        let i = inspect(&d, &Config::default(), &[Some(3.0), None]).unwrap();
        assert!(i.joints[0].moves && !i.joints[1].moves);
        // measured 1 and 0.018 (the moving joint's reversals)
        assert!(
            i.joints[1].at_rest > 0.99 && i.joints[0].at_rest < 0.035,
            "{:?}",
            i.joints
        );
        // torque 3 q peaks at 3.6 N m: above 98 % of a 3 N m limit for part of the time
        // (measured 0.192 of it)
        let limit = i.joints[0].torque_at_limit.unwrap();
        assert!(limit > 0.1 && limit < 0.38, "{limit}");
        assert_eq!(i.joints[1].torque_at_limit, None);
        // a constant torque sits at its extremes all the time
        assert_eq!(i.joints[1].torque_at_extremes, 1.0);
        assert!(i.text().contains("suggested low-pass cutoff"));
    }

    /// Noisy positions: the vibrations drown, the position spectrum meets its noise floor
    /// just above the motion, and the cutoff follows it down, but not below twice the
    /// motion.
    #[test]
    fn noise_lowers_the_cutoff() {
        let clean = suggest_cutoff(&data(1e-5)).unwrap();
        let noisy = suggest_cutoff(&data(3e-3)).unwrap();
        assert!(noisy.cutoff < clean.cutoff, "{noisy:?} vs {clean:?}");
        // the cutoff is rounded to two digits, 0.05 Hz at most below 10 Hz (measured 4.3 Hz
        // against twice the 2.13 Hz motion)
        assert!(
            noisy.cutoff >= 2.0 * noisy.motion_bandwidth - 0.05,
            "{noisy:?}"
        );
        assert!(noisy.reason.contains("noise floor"), "{}", noisy.reason);
    }

    #[test]
    fn no_motion_is_an_error_that_says_so() {
        let n = 1000;
        let d = Dataset::new(
            "still",
            0.01,
            Signals::new(vec![vec![0.3; n]]).unwrap(),
            Signals::new(vec![vec![1.0; n]]).unwrap(),
        )
        .unwrap();
        let e = suggest_cutoff(&d).unwrap_err().to_string();
        assert!(e.contains("no joint of still moves"), "{e}");
    }

    /// A record shorter than a spectrum needs names its file and says to record longer; it
    /// was "the spectrum of the position of joint 1: 2 samples, at least 64 are needed; a
    /// spectrum needs a longer record", with no file.
    #[test]
    fn a_record_too_short_for_a_spectrum_names_its_file() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("two.csv");
        std::fs::write(&file, "t,q1,qd1,qdd1,tau1\n0,0.1,1,0,2\n0.001,0.2,1,0,2\n").unwrap();
        let config = Config::default_mapping();
        let data = crate::data::load(&config, std::slice::from_ref(&file), 1).unwrap();
        let e = inspect(&data, &config, &[None]).unwrap_err().to_string();
        assert_eq!(
            e,
            format!(
                "{}: the spectrum of the position of joint 1: 2 samples, at least 64 are \
                 needed; a spectrum needs a longer record: record a longer trajectory",
                file.display()
            )
        );
        // a data set not from a file is named as such
        let d = Dataset::new(
            "short",
            0.01,
            Signals::new(vec![vec![0.3; 5]]).unwrap(),
            Signals::new(vec![vec![1.0; 5]]).unwrap(),
        )
        .unwrap();
        let e = suggest_cutoff(&d).unwrap_err().to_string();
        assert!(
            e.starts_with("data set `short`: the spectrum of the position of joint 1: 5 samples"),
            "{e}"
        );
    }

    #[test]
    fn two_significant_digits() {
        assert_eq!(two_digits(18.34), 18.0);
        assert_eq!(two_digits(0.1234), 0.12);
        assert_eq!(two_digits(1234.0), 1200.0);
    }
}

#[cfg(test)]
mod stream_tests;
