//! `sample_rate` against a time column the config does not read
//! (docs/identification.md#data-and-configuration).
//!
//! A config that gives `sample_rate` reads no time column, and a log that carries one at
//! another rate would make every derivative and filter wrong by the ratio without a word.
//! So a file with exactly one column named as a time ([`time_name`]) that the config does
//! not read has that column read beside the others in its first [`RATE_CHECK_ROWS`] rows
//! (in the same pass, as an optional column: a field that is not a number is no error),
//! and its median step is compared with `1 / sample_rate`: more than [`RATE_TOLERANCE`]
//! apart is an error at the `sample_rate` key naming the file, the column, both rates and
//! the fixes. A column that is not a clock (a step that is zero, negative or not a number,
//! or fewer than [`REGULAR_SHARE`] of the steps within [`REGULAR_SPREAD`] of the median)
//! says nothing.

use std::path::Path;

use crate::data::Config;
use crate::error::{Result, num};

/// The data rows of a file whose time stamps are compared with `sample_rate`: the median
/// step of so many is the clock's, and a long record parses the column in its first
/// window or two only.
pub const RATE_CHECK_ROWS: usize = 100_000;
/// Relative difference between the time column's median step and `1 / sample_rate`
/// above which the config's rate is refused.
pub const RATE_TOLERANCE: f64 = 0.01;
/// Share of the steps that must lie within [`REGULAR_SPREAD`] of the median step for
/// the column to count as a clock.
pub const REGULAR_SHARE: f64 = 0.9;
/// Relative distance from the median step within which a step is regular.
pub const REGULAR_SPREAD: f64 = 0.1;

/// The time column of a file that the config does not read, checked against its
/// `sample_rate`.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct UnreadTime {
    /// The column's name.
    pub(crate) name: String,
    /// Seconds per unit of the column, when its name or the config's `time_scale` says.
    pub(crate) scale: Option<f64>,
}

/// Whether the column name `name` is a time name, and then its unit in seconds when the
/// name gives it: `Some(None)` for a time name without unit, `Some(Some(1e-3))` for one
/// in milliseconds, `None` for any other name.
///
/// A time name is, compared without case, `time`, `times`, `timestamp`, `timestamps`,
/// `time_stamp` or `stamp`, or `t` in lower case (`T` is more often a temperature),
/// optionally followed by a unit as `_ms`, ` [ms]` or ` (ms)`: `s`, `sec`, `secs`,
/// `second`, `seconds`; `ms`, `msec`; `us`, `µs`, `usec`; `ns`, `nsec`.
///
/// ```
/// use robid_runtime::data::time_name;
/// assert_eq!(time_name("t"), Some(None));
/// assert_eq!(time_name("Timestamp"), Some(None));
/// assert_eq!(time_name("time_s"), Some(Some(1.0)));
/// assert_eq!(time_name("time [ms]"), Some(Some(1e-3)));
/// assert_eq!(time_name("T"), None);
/// assert_eq!(time_name("tau1"), None);
/// ```
pub fn time_name(name: &str) -> Option<Option<f64>> {
    let name = name.trim();
    let lower = name.to_lowercase();
    let bracketed = |open: char, close: char| {
        let inner = lower.strip_suffix(close)?;
        let (stem, unit) = inner.rsplit_once(open)?;
        Some((stem.trim_end(), Some(unit.trim())))
    };
    let (stem, unit) = bracketed('[', ']')
        .or_else(|| bracketed('(', ')'))
        .or_else(|| {
            let (stem, unit) = lower.rsplit_once('_')?;
            unit_scale(unit).map(|_| (stem, Some(unit)))
        })
        .unwrap_or((lower.as_str(), None));
    let is_time = match stem {
        "t" => name.starts_with('t'),
        "time" | "times" | "timestamp" | "timestamps" | "time_stamp" | "stamp" => true,
        _ => false,
    };
    match (is_time, unit) {
        (false, _) => None,
        (true, None) => Some(None),
        (true, Some(unit)) => unit_scale(unit).map(Some),
    }
}

/// Seconds per `unit` (lower case), for the units of [`time_name`].
fn unit_scale(unit: &str) -> Option<f64> {
    match unit {
        "s" | "sec" | "secs" | "second" | "seconds" => Some(1.0),
        "ms" | "msec" => Some(1e-3),
        "us" | "µs" | "usec" => Some(1e-6),
        "ns" | "nsec" => Some(1e-9),
        _ => None,
    }
}

/// The time column of `header` to check against the config's `sample_rate`: `None`
/// unless the config gives `sample_rate` (and no `time_column`) and exactly one column of
/// `header` is a time name ([`time_name`]) that is not among the columns `read`.
pub(crate) fn unread_time_column(
    config: &Config,
    header: &[String],
    read: &[String],
) -> Option<UnreadTime> {
    if config.sample_rate.is_none() || config.time_column.is_some() {
        return None;
    }
    let mut candidates = header
        .iter()
        .filter(|h| !read.contains(h))
        .filter_map(|h| time_name(h).map(|unit| (h, unit)));
    let (name, unit) = candidates.next()?;
    if candidates.next().is_some() {
        return None;
    }
    // the config's own unit for its time column, when it gives one
    let scale = unit.or((config.time_scale != 1.0).then_some(config.time_scale));
    Some(UnreadTime {
        name: name.clone(),
        scale,
    })
}

/// The steps of a time column read in parts, in order (at most [`RATE_CHECK_ROWS`]
/// rows of it): what [`Steps::median`] decides from.
#[derive(Debug, Clone, Default)]
pub(crate) struct Steps {
    last: Option<f64>,
    steps: Vec<f64>,
    /// Not a clock: a step that is not a positive number.
    unusable: bool,
}

impl Steps {
    /// The next time stamps of the column (NaN where a field was not a number).
    pub(crate) fn push(&mut self, t: &[f64]) {
        if self.unusable {
            return;
        }
        for &v in t {
            if let Some(last) = self.last {
                let d = v - last;
                if !(d > 0.0 && d.is_finite()) {
                    self.unusable = true;
                    self.steps = Vec::new();
                    return;
                }
                self.steps.push(d);
            }
            self.last = Some(v);
        }
    }

    /// The median step when the column is a clock: strictly increasing, at least
    /// [`REGULAR_SHARE`] of its steps within [`REGULAR_SPREAD`] of the median. `None`
    /// otherwise, or without steps.
    pub(crate) fn median(mut self) -> Option<f64> {
        if self.unusable || self.steps.is_empty() {
            return None;
        }
        self.steps.sort_by(f64::total_cmp);
        // as `sampling`'s median
        let median = self.steps[self.steps.len() / 2];
        let regular = self
            .steps
            .iter()
            .filter(|&&d| (d / median - 1.0).abs() <= REGULAR_SPREAD)
            .count();
        (regular as f64 >= REGULAR_SHARE * self.steps.len() as f64).then_some(median)
    }
}

/// Checks the config's `sample_rate` against the time column `column` of the file
/// `path`, whose steps are `steps`: an error at the `sample_rate` key when its median
/// step differs from `1 / sample_rate` by more than [`RATE_TOLERANCE`]. Nothing is said
/// when the column is not a clock ([`Steps::median`]), nor, for a column whose unit
/// neither its name nor `time_scale` gives, when it agrees with the rate read in ms, µs
/// or ns, or counts samples (a median step of exactly 1).
pub(crate) fn check_rate(
    config: &Config,
    path: &Path,
    column: &UnreadTime,
    steps: Steps,
) -> Result<()> {
    let (Some(fs), Some(median)) = (config.sample_rate, steps.median()) else {
        return Ok(());
    };
    let agrees = |scale: f64| (median * scale * fs - 1.0).abs() <= RATE_TOLERANCE;
    let consistent = match column.scale {
        Some(scale) => agrees(scale),
        None => median == 1.0 || [1.0, 1e-3, 1e-6, 1e-9].into_iter().any(agrees),
    };
    if consistent {
        return Ok(());
    }
    let step = median * column.scale.unwrap_or(1.0);
    let rate = 1.0 / step;
    let name = &column.name;
    let scale = match column.scale {
        Some(s) if s != 1.0 => format!(" and `time_scale = {}`", num(s)),
        _ => String::new(),
    };
    let read_as = if column.scale.is_none() {
        ", read as seconds"
    } else {
        ""
    };
    Err(config.key_error(
        "sample_rate",
        format!(
            "{} Hz, but the time column `{name}` of {} steps at {} Hz (median step {} s{read_as}): \
             every derivative and filter would be off by a factor of {}; replace `sample_rate` \
             by `time_column = \"{name}\"`{scale} to use the time stamps, or correct \
             `sample_rate` (to {} if the time stamps are right)",
            num(fs),
            path.display(),
            num(short(rate)),
            num(short(step)),
            num(short((rate / fs).max(fs / rate))),
            num(short(rate)),
        ),
    ))
}

/// `x` rounded to four significant digits (a rate or a step measured from time stamps,
/// written short: `500`, not `499.99999999999994`).
fn short(x: f64) -> f64 {
    format!("{x:.3e}").parse().unwrap_or(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn steps(t: &[f64]) -> Steps {
        let mut s = Steps::default();
        s.push(t);
        s
    }

    #[test]
    fn time_names_and_their_units() {
        for (name, unit) in [
            ("t", Some(None)),
            ("time", Some(None)),
            (" Time ", Some(None)),
            ("timestamp", Some(None)),
            ("TimeStamps", Some(None)),
            ("time_stamp", Some(None)),
            ("stamp", Some(None)),
            ("time_s", Some(Some(1.0))),
            ("t_s", Some(Some(1.0))),
            ("time (s)", Some(Some(1.0))),
            ("time[sec]", Some(Some(1.0))),
            ("time_ms", Some(Some(1e-3))),
            ("timestamp [us]", Some(Some(1e-6))),
            ("t_ns", Some(Some(1e-9))),
            ("T", None),
            ("T_s", None),
            ("time_min", None),
            ("time [h]", None),
            ("tau1", None),
            ("temperature", None),
            ("q1", None),
            ("stamps_ms_x", None),
        ] {
            assert_eq!(time_name(name), unit, "{name}");
        }
    }

    /// The steps read in parts, cut anywhere, are the steps of the whole column.
    #[test]
    fn steps_in_parts_are_the_whole_steps() {
        let t: Vec<f64> = (0..1000).map(|k| 12.5 + 0.002 * k as f64).collect();
        let whole = steps(&t);
        let median = whole.clone().median().unwrap();
        assert!((median - 0.002).abs() < 1e-15, "{median}");
        for cuts in [[1, 2], [0, 999], [317, 318], [500, 1000]] {
            let mut s = Steps::default();
            for part in [&t[..cuts[0]], &t[cuts[0]..cuts[1]], &t[cuts[1]..]] {
                s.push(part);
            }
            assert_eq!(s.steps, whole.steps, "{cuts:?}");
        }
    }

    /// A column that is not a clock gives no median: a repeated or decreasing stamp, a
    /// field that was not a number, steps scattered; a few skipped ticks and some jitter
    /// leave it a clock.
    #[test]
    fn only_a_clock_has_a_median() {
        assert_eq!(steps(&[0.0, 0.1, 0.1, 0.2]).median(), None);
        assert_eq!(steps(&[0.0, 0.1, 0.05, 0.2]).median(), None);
        assert_eq!(steps(&[0.0, f64::NAN, 0.2]).median(), None);
        assert_eq!(steps(&[0.0]).median(), None);
        let mut rng = crate::rng::Rng::new(3);
        let mut t = vec![0.0];
        for _ in 0..1000 {
            t.push(t.last().unwrap() + rng.uniform(0.001, 0.01));
        }
        assert_eq!(steps(&t).median(), None);
        // 5 % of the ticks skipped, the rest with 2 % jitter
        let mut t = vec![0.0];
        for k in 0..1000 {
            let step = if k % 20 == 0 { 0.002 } else { 0.001 };
            t.push(t.last().unwrap() + step * rng.uniform(0.98, 1.02));
        }
        let median = steps(&t).median().unwrap();
        assert!((median / 0.001 - 1.0).abs() < 0.02, "{median}");
    }

    #[test]
    fn rates_are_written_short() {
        assert_eq!(short(1.0 / 0.002000000000000001), 500.0);
        assert_eq!(num(short(1000.0 / 3.0)), "333.3");
        assert_eq!(num(short(0.0020000000000000018)), "0.002");
        assert_eq!(short(1e300), 1e300);
        assert_eq!(short(1e-300), 1e-300);
    }
}
