//! Time stamps: monotonicity, detection of irregular sampling, resampling onto a
//! uniform grid and joining files by time (linear interpolation).

use crate::DataError;
use std::fmt;
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};
use crate::limits::{MAX_SAMPLE_RATE, MIN_SAMPLE_RATE};

/// Something that was repaired while loading, and the caller should know about.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum Warning {
    /// Irregular time stamps were resampled onto a uniform grid.
    IrregularTime {
        /// The file.
        path: PathBuf,
        /// Smallest step found (s).
        min_step: f64,
        /// Largest step found (s).
        max_step: f64,
        /// Step of the uniform grid (s).
        step: f64,
        /// Median step (s).
        median_step: f64,
        /// RMS deviation of the regular steps from the median (s).
        jitter: f64,
        /// Ticks skipped by steps of at least 1.5 median steps.
        skipped_ticks: usize,
    },
    /// Rows that look like an old sample written again (see [`super::Sampling`]), more
    /// than [`super::STALE_SHARE`] of the file.
    StaleRows {
        /// The file.
        path: PathBuf,
        /// How many.
        stale: usize,
        /// Rows of the file.
        rows: usize,
        /// The file line of the first.
        first_line: u64,
    },
    /// Files joined by time only overlap partly: the samples of the first file outside
    /// the time stamps of this one were dropped (the record is the time every file
    /// covers).
    PartialOverlap {
        /// The file that was interpolated.
        path: PathBuf,
        /// Samples of the first file outside this file's time stamps.
        dropped: usize,
    },
    /// Time stamps whose median step gives a sample rate below
    /// [`super::SLOW_SAMPLE_RATE`]: too slow for a robot's dynamics, or a time column in
    /// ms read as seconds.
    SlowSampling {
        /// The file.
        path: PathBuf,
        /// Its median step (s).
        step: f64,
    },
    /// An angle column logged modulo a turn, unwrapped as it was read (see
    /// [`WRAP_TOLERANCE`](super::WRAP_TOLERANCE)).
    Unwrapped {
        /// The file.
        path: PathBuf,
        /// The column's role: `position` or `motor_position`.
        role: &'static str,
        /// The joint, from 1.
        joint: usize,
        /// How many jumps of a whole turn were taken out.
        wraps: usize,
        /// The file line of the first.
        first_line: u64,
        /// One turn in the file's unit (2 pi, or 360 for degrees).
        turn: f64,
    },
    /// Rows of a file joined by time that lie outside the time stamps of the first file:
    /// they are not used (the record is the time every file covers).
    JoinedRowsUnused {
        /// The file that was interpolated.
        path: PathBuf,
        /// Its rows outside the first file's time stamps.
        unused: usize,
        /// Its rows.
        rows: usize,
        /// The first file with time stamps.
        first: PathBuf,
    },
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Warning::IrregularTime {
                path,
                min_step,
                max_step,
                step,
                median_step,
                jitter,
                skipped_ticks,
            } => write!(
                f,
                "{}: irregular time steps ({:.6} s to {:.6} s, median {:.6} s, jitter {:.2e} s, {}); resampled onto a uniform grid of {:.6} s by linear interpolation (robid inspect shows the sampling)",
                path.display(),
                min_step,
                max_step,
                median_step,
                jitter,
                crate::Count(*skipped_ticks, "skipped tick"),
                step
            ),
            Warning::StaleRows {
                path,
                stale,
                rows,
                first_line,
            } => write!(
                f,
                "{}: {} ({:.1} %, the first at line {first_line}) {} the previous row and {} followed by a step that catches up: an old sample written again by the logger. Velocities and accelerations see a stop and a jump there; the low-pass smooths a few of them, but many bias the fit: fix the logger (robid inspect lists the sampling)",
                path.display(),
                crate::Count(*stale, "row"),
                100.0 * *stale as f64 / (*rows).max(1) as f64,
                if *stale == 1 { "repeats" } else { "repeat" },
                if *stale == 1 { "is" } else { "are" }
            ),
            Warning::Unwrapped {
                path,
                role,
                joint,
                wraps,
                first_line,
                turn,
            } => f.write_str(&super::unwrap::unwrapped_text(
                path,
                role,
                *joint,
                *wraps,
                *first_line,
                *turn,
            )),
            Warning::PartialOverlap { path, dropped } => write!(
                f,
                "{}: covers only part of the time range of the first file joined by time: the {} of that file outside the time stamps of this one {} dropped, keeping the time both cover",
                path.display(),
                crate::Count(*dropped, "sample"),
                if *dropped == 1 { "was" } else { "were" }
            ),
            Warning::SlowSampling { path, step } => write!(
                f,
                "{}: time stamps {} s apart (median), a sample rate of {} Hz, below the {} Hz a robot's dynamics need: is the time column in ms? Set `time_scale = 0.001` in the config (robid inspect shows the sampling)",
                path.display(),
                crate::Num::rounded(*step, 4),
                crate::Num::rounded(1.0 / *step, 4),
                super::SLOW_SAMPLE_RATE
            ),
            Warning::JoinedRowsUnused {
                path,
                unused,
                rows,
                first,
            } => write!(
                f,
                "{}: {unused} of its {} ({:.1} %) {} outside the time stamps of {}, which it is joined to by time, and {} not used; check that both time columns come from one clock in one unit",
                path.display(),
                crate::Count(*rows, "row"),
                100.0 * *unused as f64 / (*rows).max(1) as f64,
                if *unused == 1 { "lies" } else { "lie" },
                first.display(),
                if *unused == 1 { "is" } else { "are" }
            ),
        }
    }
}

/// Relative deviation of a step from the mean step above which sampling is irregular.
pub const IRREGULAR_TOLERANCE: f64 = 0.01;

/// A step between two time stamps longer than this many median steps is a gap: the
/// recording stopped there (a paused logger, a lost connection), and the time stamps are
/// refused ([`DataError::TimeGap`]) instead of resampled across it.
///
/// Why 10: shorter steps are the jitter of a clock and the odd lost packet or few (the
/// LWR4 logs of `data/kuka_lwr4` step at most 1.36 median steps; a lost packet is 2),
/// which linear interpolation repairs: across 10 steps, the straight line departs from a
/// sinusoid of period 200 steps (at 1 kHz, a motion at 5 Hz) by at most
/// 1 - cos(pi / 20) = 1.2 % of its amplitude, and from slower motion by less. Longer
/// holes leave a stretch where the motion would be invented: a straight line in the
/// positions, which two differentiations turn into zero acceleration between two spikes.
pub const GAP_RATIO: f64 = 10.0;

/// Checks that `t` increases strictly; `lines` are the file lines of the samples.
pub fn check_monotonic(t: &[f64], lines: &[u64], path: &Path) -> Result<()> {
    for k in 1..t.len() {
        if t[k] <= t[k - 1] {
            return Err(Error::Data(DataError::NonMonotonicTime {
                path: path.to_path_buf(),
                line: lines.get(k).copied().unwrap_or(0),
                previous: t[k - 1],
                value: t[k],
            }));
        }
    }
    Ok(())
}

/// Whether a sample time of `step` seconds gives a sample rate robid takes, within
/// [[`MIN_SAMPLE_RATE`], [`MAX_SAMPLE_RATE`]] Hz: the one rule for a sample time, taken
/// from time stamps ([`check_sample_time`]) or given ([`crate::data::Dataset::new`]).
pub(crate) fn sample_time_accepted(step: f64) -> bool {
    step > 0.0 && (MIN_SAMPLE_RATE..=MAX_SAMPLE_RATE).contains(&(1.0 / step))
}

/// Checks the mean step `step` of time stamps (from the first to the last over the
/// steps, [`Clock::mean_step`]) against the sample rates robid takes
/// ([`sample_time_accepted`]): the rule of every reader of time stamps, the loader of
/// identification data (in memory and window by window) and the trajectories of
/// simulation ([`crate::simulate::Trajectory`]), so that `robid simulate` does not run on
/// a time column that `robid identify` would refuse. `what` names the time stamps (their
/// file); `fix` ends the message ([`DataError::SampleRate`]).
pub(crate) fn check_sample_time(
    step: f64,
    what: impl FnOnce() -> String,
    fix: &'static str,
) -> Result<()> {
    if sample_time_accepted(step) {
        return Ok(());
    }
    Err(Error::Data(DataError::SampleRate {
        what: what(),
        step,
        fix,
    }))
}

/// [`check_sample_time`] of increasing time stamps `t` (at least two): their mean step,
/// when accepted.
pub(crate) fn check_time_stamps(
    t: &[f64],
    what: impl FnOnce() -> String,
    fix: &'static str,
) -> Result<f64> {
    let mut clock = Clock::default();
    clock.push(t);
    let step = clock.mean_step();
    check_sample_time(step, what, fix)?;
    Ok(step)
}

/// The first step of increasing time stamps `t` longer than [`GAP_RATIO`] median steps:
/// the index of the sample after it and the median step. `None` without such a step, or
/// with fewer than two steps (no typical step to compare with).
pub(crate) fn find_gap(t: &[f64]) -> Option<(usize, f64)> {
    if t.len() < 3 {
        return None;
    }
    let (mut shortest, mut longest) = (f64::INFINITY, 0.0f64);
    for w in t.windows(2) {
        shortest = shortest.min(w[1] - w[0]);
        longest = longest.max(w[1] - w[0]);
    }
    // the median is at least the shortest step: nothing more to look for (the usual case,
    // without sorting the steps)
    if !(longest > GAP_RATIO * shortest) {
        return None;
    }
    let mut steps: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).collect();
    // the median of `sampling` (the upper one of an even count)
    let middle = steps.len() / 2;
    let median = *steps.select_nth_unstable_by(middle, f64::total_cmp).1;
    let k = (1..t.len()).find(|&k| t[k] - t[k - 1] > GAP_RATIO * median)?;
    Some((k, median))
}

/// Every gap of increasing time stamps `t` ([`find_gap`]: a step longer than
/// [`GAP_RATIO`] median steps): the indices of the samples after them, in order.
pub(crate) fn find_gaps(t: &[f64]) -> Vec<usize> {
    match find_gap(t) {
        None => Vec::new(),
        Some((first, median)) => (first..t.len())
            .filter(|&k| t[k] - t[k - 1] > GAP_RATIO * median)
            .collect(),
    }
}

/// Refuses increasing time stamps `t` with a gap ([`find_gap`]): a
/// [`DataError::TimeGap`] at `at(k)`, the place of sample `k` after the gap (its file
/// line), ending with `fix`.
pub(crate) fn check_gaps(
    t: &[f64],
    at: impl FnOnce(usize) -> String,
    fix: &'static str,
) -> Result<()> {
    match find_gap(t) {
        None => Ok(()),
        Some((k, median)) => Err(Error::Data(DataError::TimeGap {
            location: at(k),
            from: t[k - 1],
            to: t[k],
            median,
            fix,
        })),
    }
}

/// The sample time of increasing time stamps `t` (at least 2) and, when some step differs
/// from their mean step by more than [`IRREGULAR_TOLERANCE`], the [`Grid`] to resample
/// them onto with the warning to issue.
pub fn regularity(t: &[f64], path: &Path) -> (f64, Option<(Grid, Warning)>) {
    let mut clock = Clock::default();
    clock.push(t);
    let resampled = clock
        .irregular()
        .then(|| super::sampling::step_statistics(t))
        .flatten()
        .map(|s| {
            let grid = clock.grid(&s);
            (grid, clock.irregular_warning(&s, &grid, path))
        });
    let step = resampled.as_ref().map_or(clock.mean_step(), |r| r.0.step);
    (step, resampled)
}

/// The uniform grid that irregular time stamps are resampled onto: the clock's tick from
/// the first stamp to the last, each skipped tick filled (see [`regularity`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Grid {
    /// The first time stamp (s).
    pub start: f64,
    /// The step (s).
    pub step: f64,
    /// Its samples: the last is the last stamp.
    pub samples: usize,
}

impl Grid {
    /// The time of sample `k` (s).
    pub fn time(&self, k: usize) -> f64 {
        self.start + self.step * k as f64
    }

    /// The times of samples `range`.
    pub fn times(&self, range: std::ops::Range<usize>) -> Vec<f64> {
        range.map(|k| self.time(k)).collect()
    }
}

/// The extent and the extreme steps of time stamps read in parts, in order: what
/// [`regularity`] decides from.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Clock {
    first: f64,
    last: f64,
    samples: usize,
    min_step: f64,
    max_step: f64,
}

impl Default for Clock {
    fn default() -> Self {
        Self {
            first: 0.0,
            last: 0.0,
            samples: 0,
            min_step: f64::INFINITY,
            max_step: 0.0,
        }
    }
}

impl Clock {
    /// The next time stamps.
    pub(crate) fn push(&mut self, t: &[f64]) {
        for &v in t {
            if self.samples == 0 {
                self.first = v;
            } else {
                let d = v - self.last;
                self.min_step = self.min_step.min(d);
                self.max_step = self.max_step.max(d);
            }
            self.last = v;
            self.samples += 1;
        }
    }

    /// The mean step: the time from the first stamp to the last over the steps.
    pub(crate) fn mean_step(&self) -> f64 {
        (self.last - self.first) / self.samples.saturating_sub(1) as f64
    }

    /// Whether some step differs from the mean by more than [`IRREGULAR_TOLERANCE`].
    pub(crate) fn irregular(&self) -> bool {
        let step = self.mean_step();
        (self.max_step - step).max(step - self.min_step) > IRREGULAR_TOLERANCE * step
    }

    /// Whether the stamps can be resampled: they increase strictly and no step is a gap
    /// (longer than [`GAP_RATIO`] times `median`, the median step, as [`find_gap`] finds
    /// one).
    pub(crate) fn resamplable(&self, median: f64) -> bool {
        self.min_step > 0.0 && !(self.max_step > GAP_RATIO * median)
    }

    /// The grid that the stamps, whose steps have the statistics `steps`, are resampled
    /// onto: from the first stamp to the last in as many ticks as the stamps span, each
    /// step counting one tick and each step of at least [`SKIP_RATIO`](super::SKIP_RATIO)
    /// median steps the ticks it skips ([`Steps::skipped_ticks`](super::sampling::Steps)).
    /// Stamps of a regular clock with lost ticks fall on it, and keep their values: on the
    /// grid of their mean step, longer by the lost ticks' share, every sample would be
    /// interpolated between two, which halves its noise's variance at mid-step (a 2/3
    /// share on average: standard deviations 18 % too small) and smooths the motion.
    /// Jitter alone (no skipped tick) gives the mean step.
    pub(crate) fn grid(&self, steps: &super::sampling::Steps) -> Grid {
        let ticks = self.samples.saturating_sub(1) + steps.skipped_ticks;
        Grid {
            start: self.first,
            step: (self.last - self.first) / ticks.max(1) as f64,
            samples: ticks + 1,
        }
    }

    /// The warning that the stamps of `path`, whose steps have the statistics `steps`,
    /// were resampled onto `grid`.
    pub(crate) fn irregular_warning(
        &self,
        steps: &super::sampling::Steps,
        grid: &Grid,
        path: &Path,
    ) -> Warning {
        Warning::IrregularTime {
            path: path.to_path_buf(),
            min_step: self.min_step,
            max_step: self.max_step,
            step: grid.step,
            median_step: steps.median,
            jitter: steps.jitter,
            skipped_ticks: steps.skipped_ticks,
        }
    }
}

/// Linear interpolation of the samples (`t`, `x`) at the increasing times `at`
/// (clamped to the end values outside `t`).
pub fn interpolate(t: &[f64], x: &[f64], at: &[f64]) -> Vec<f64> {
    let mut out = Vec::with_capacity(at.len());
    let mut k = 0;
    for &s in at {
        while k + 2 < t.len() && t[k + 1] < s {
            k += 1;
        }
        if s <= t[0] {
            out.push(x[0]);
        } else if s >= t[t.len() - 1] {
            out.push(x[t.len() - 1]);
        } else {
            let w = (s - t[k]) / (t[k + 1] - t[k]);
            out.push(x[k] + w * (x[k + 1] - x[k]));
        }
    }
    out
}

/// The line of the sample nearest in time to each of the increasing times `at`, of the
/// samples at the increasing times `t` with the file lines `lines`: where a resampled
/// sample comes from, for messages.
pub fn nearest_lines(t: &[f64], lines: &[u64], at: &[f64]) -> Vec<u64> {
    let mut k = 0;
    at.iter()
        .map(|&s| {
            while k + 1 < t.len() && (t[k + 1] - s).abs() <= (t[k] - s).abs() {
                k += 1;
            }
            lines.get(k).copied().unwrap_or(0)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn detects_non_monotonic_time_with_line() {
        let e = check_monotonic(&[0.0, 0.1, 0.1], &[2, 3, 4], Path::new("a.csv")).unwrap_err();
        assert!(
            matches!(e, Error::Data(DataError::NonMonotonicTime { line: 4, .. })),
            "{e}"
        );
        assert!(e.to_string().starts_with("a.csv:4"), "{e}");
    }

    #[test]
    fn regular_and_irregular() {
        let t: Vec<f64> = (0..100).map(|k| k as f64 * 0.005).collect();
        assert!(regularity(&t, Path::new("x")).1.is_none());
        let mut j = t.clone();
        j[50] += 0.001;
        let (step, w) = regularity(&j, Path::new("x"));
        assert!((step - 0.005).abs() < 1e-12);
        assert!(w.unwrap().1.to_string().contains("resampled"));
    }

    #[test]
    fn interpolation_is_exact_on_lines() {
        let t = [0.0, 0.1, 0.35, 0.4];
        let x: Vec<f64> = t.iter().map(|v| 2.0 * v + 1.0).collect();
        let at = [0.0, 0.05, 0.2, 0.4, 0.5];
        let y = interpolate(&t, &x, &at);
        for (a, v) in at.iter().zip(&y) {
            assert!((v - (2.0 * a.min(0.4) + 1.0)).abs() < 1e-12);
        }
    }
}
