//! `sample_rate` against a time column the config does not read
//! (docs/identification.md#data-and-configuration).
//!
//! A config that gives `sample_rate` reads no time column, and a log that carries one at
//! another rate would make every derivative and filter wrong by the ratio without a word.
//! So a file with exactly one column named as a time ([`time_name`]) that the config does
//! not read has that column read beside the others (in the same pass, as an optional
//! column: a field that is not a number is no error), and judged in blocks of
//! [`RATE_CHECK_ROWS`] steps, from the first row to the last: a block whose median step is
//! more than [`RATE_TOLERANCE`] from `1 / sample_rate` is an error at the `sample_rate` key
//! naming the file, the column, both rates and the fixes (and, after blocks at the rate,
//! the block's lines: the file changed its rate there), and a step longer than
//! [`GAP_RATIO`] median steps (a paused logger, which `sample_rate` would bridge as one
//! step) is a [`DataError::TimeGap`](crate::DataError::TimeGap) naming the line, the two
//! stamps and the fix. A block that is not a clock (a stamp going back, or fewer than
//! [`REGULAR_SHARE`] of its steps within [`REGULAR_SPREAD`] of the median of its positive
//! steps, a repeated stamp counting against it) says nothing, nor does the step after a
//! stamp going back in the next block (it starts from a stamp out of order). A field that
//! is not a number is left out (the step spans it): neither it nor a repeated stamp hides
//! the gaps of its block.

use std::path::Path;

use crate::DataError;
use crate::data::{Config, GAP_RATIO};
use crate::error::{Error, Result, num};

/// The steps of a time column judged together against `sample_rate` and for gaps: the
/// median step of so many is the clock's, and a record kept on disk holds no more of
/// them at a time.
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
    let (stem, unit) = stem_and_unit(name);
    let is_time = match stem.as_str() {
        "t" => name.starts_with('t'),
        "time" | "times" | "timestamp" | "timestamps" | "time_stamp" | "stamp" => true,
        _ => false,
    };
    match (is_time, unit) {
        (false, _) => None,
        (true, None) => Some(None),
        (true, Some(unit)) => unit_scale(&unit).map(Some),
    }
}

/// A column name, in lower case, split into its stem and the unit it ends with (` [ms]`,
/// ` (ms)`, or `_ms` when the part after the last `_` is a time unit).
fn stem_and_unit(name: &str) -> (String, Option<String>) {
    let lower = name.trim().to_lowercase();
    let bracketed = |open: char, close: char| {
        let inner = lower.strip_suffix(close)?;
        let (stem, unit) = inner.rsplit_once(open)?;
        Some((stem.trim_end().to_owned(), Some(unit.trim().to_owned())))
    };
    bracketed('[', ']')
        .or_else(|| bracketed('(', ')'))
        .or_else(|| {
            let (stem, unit) = lower.rsplit_once('_')?;
            unit_scale(unit).map(|_| (stem.to_owned(), Some(unit.to_owned())))
        })
        .unwrap_or_else(|| (lower.clone(), None))
}

/// The seconds per unit that the name of a column the config names as its time column
/// gives, whatever its stem (`T_MS`, `zeit_ms`: the config says it is the time, where
/// [`time_name`] must tell a time from a temperature `T`); `None` without a time unit.
fn time_column_unit(name: &str) -> Option<f64> {
    stem_and_unit(name).1.as_deref().and_then(unit_scale)
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

/// A column whose name is a time name, and the seconds per unit its name gives.
type TimeColumn = (String, Option<f64>);

/// Per source's file (`paths`), its one column whose name is a time name ([`time_name`])
/// and that the source does not read, with the unit its name gives; `None` for a file with
/// none or several.
fn time_like_columns(
    config: &Config,
    paths: &[std::path::PathBuf],
    dof: usize,
) -> crate::error::Result<Vec<Option<TimeColumn>>> {
    let mut columns = Vec::new();
    for (source, path) in config.sources.iter().zip(paths) {
        let header = super::table::read_header(path)?;
        let (read, _) = super::load::source_columns(config, source, dof);
        let mut names = header
            .iter()
            .filter(|h| !read.contains(h))
            .filter_map(|h| time_name(h).map(|unit| (h.clone(), unit)));
        columns.push(match (names.next(), names.next()) {
            (Some(this), None) => Some(this),
            _ => None,
        });
    }
    Ok(columns)
}

/// When `config` names no time column and no sample rate and every source's file has a
/// time column under a different name (`t` in one, `time` in another), so that none was
/// read and the files were joined row by row: what to do, naming each file's column.
pub(crate) fn differing_time_columns(
    config: &Config,
    paths: &[std::path::PathBuf],
    dof: usize,
) -> Option<String> {
    if config.time_column.is_some() || config.sample_rate.is_some() || paths.len() < 2 {
        return None;
    }
    let columns: Vec<TimeColumn> = time_like_columns(config, paths, dof)
        .ok()?
        .into_iter()
        .collect::<Option<_>>()?;
    if columns.iter().all(|c| c.0 == columns[0].0) {
        return None;
    }
    let each: Vec<String> = columns
        .iter()
        .zip(paths)
        .map(|(c, p)| format!("`{}` in {}", crate::data::error::quoted(&c.0), p.display()))
        .collect();
    Some(format!(
        "the files' time columns have different names ({}), so none was read and the files \
         were joined row by row: give the time column one name in every file (robid finds \
         it by that name, or set `time_column`) so that they are joined by time",
        each.join(", ")
    ))
}

/// `config` with the time column of its files when it gives neither `sample_rate` nor
/// `time_column`: the one column of each source's file (`paths`) whose name is a time
/// name ([`time_name`]) and that the source does not read, the same in every file, with
/// the unit its name gives as `time_scale` (when the config leaves that at 1). A config
/// that says nothing of time so reads a log with a `t` column as the example config
/// shows, where it was refused as having no time column; `config` itself otherwise
/// (none such column, or several, or files that differ).
///
/// A `time_column` the config names takes the unit its name gives (`t_ms`, `time [us]`)
/// when `time_scale` is left at 1, as a column found by name does: `time_column =
/// "t_ms"` alone read the milliseconds as seconds, a 1 kHz log as 1 Hz, and the error
/// that followed pointed at the rest velocity and the angle units.
pub(crate) fn with_found_time_column<'a>(
    config: &'a Config,
    paths: &[std::path::PathBuf],
    dof: usize,
) -> crate::error::Result<std::borrow::Cow<'a, Config>> {
    use std::borrow::Cow;
    if let Some(name) = &config.time_column {
        return Ok(match time_column_unit(name) {
            Some(scale) if config.time_scale.is_none() => {
                let mut config = config.clone();
                config.time_scale = Some(scale);
                Cow::Owned(config)
            }
            _ => Cow::Borrowed(config),
        });
    }
    if config.sample_rate.is_some() || paths.is_empty() {
        return Ok(Cow::Borrowed(config));
    }
    let columns = time_like_columns(config, paths, dof)?;
    let Some(Some(first)) = columns.first() else {
        return Ok(Cow::Borrowed(config));
    };
    if columns.iter().any(|c| c.as_ref() != Some(first)) {
        return Ok(Cow::Borrowed(config));
    }
    let (name, unit) = first.clone();
    let mut config = config.clone();
    config.time_column = Some(name);
    if config.time_scale.is_none() {
        config.time_scale = unit;
    }
    Ok(Cow::Owned(config))
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
    let scale = unit.or(config.time_scale);
    Some(UnreadTime {
        name: name.clone(),
        scale,
    })
}

/// The steps of a time column read in parts, in order, judged block by block: every
/// [`RATE_CHECK_ROWS`] steps make a [`Block`], so that the whole column is checked in
/// bounded memory (a record kept on disk reads it window by window).
#[derive(Debug, Clone)]
pub(crate) struct Steps {
    /// Steps per block: [`RATE_CHECK_ROWS`] (fewer in tests).
    size: usize,
    /// The last stamp and its file line.
    last: Option<(f64, u64)>,
    /// Whether the last step went back: the next starts from a stamp out of order.
    back: bool,
    /// The steps of the current block: the stamps before and after each, and the line of
    /// the later.
    steps: Vec<Step>,
    /// Not a clock: a step of the current block goes back.
    unusable: bool,
    /// The file line of the current block's first stamp.
    start: u64,
    /// The blocks judged so far.
    blocks: Vec<Block>,
}

/// A step between two stamps of the column.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Step {
    from: f64,
    to: f64,
    /// The file line of `to`.
    line: u64,
    /// Whether the step before went back: `from` is out of order, and the step no gap.
    after_back: bool,
}

impl Step {
    fn length(&self) -> f64 {
        self.to - self.from
    }
}

/// What a block of steps says of the column.
#[derive(Debug, Clone, PartialEq)]
struct Block {
    /// The file lines of the block's first and last stamps.
    lines: [u64; 2],
    /// Its median step when it is a clock ([`Steps::median`]); `None` otherwise, and for
    /// a short last block ([`MIN_TAIL`]), judged for gaps by the block before.
    median: Option<f64>,
    /// Its first gap, a step longer than [`GAP_RATIO`] median steps, with that median.
    gap: Option<(Step, f64)>,
}

/// A last block of fewer steps than this (or than half a block) has too few for a median
/// of its own: its gaps are judged against the median of the block before, its rate is not
/// judged again.
const MIN_TAIL: usize = 1000;

impl Default for Steps {
    fn default() -> Self {
        Steps::in_blocks(RATE_CHECK_ROWS)
    }
}

impl Steps {
    /// Steps judged in blocks of `size`.
    fn in_blocks(size: usize) -> Self {
        Steps {
            size: size.max(1),
            last: None,
            back: false,
            steps: Vec::new(),
            unusable: false,
            start: 0,
            blocks: Vec::new(),
        }
    }

    /// The next time stamps of the column (NaN where a field was not a number), at the
    /// file lines `lines` (0 where not given). A stamp that is not a finite number is
    /// left out, as a field that is not there: the step spans it.
    pub(crate) fn push(&mut self, t: &[f64], lines: &[u64]) {
        for (k, &v) in t.iter().enumerate() {
            if !v.is_finite() {
                continue;
            }
            let line = lines.get(k).copied().unwrap_or(0);
            if let Some((last, last_line)) = self.last {
                if self.steps.is_empty() {
                    self.start = last_line;
                }
                self.steps.push(Step {
                    from: last,
                    to: v,
                    line,
                    after_back: self.back,
                });
                self.back = v < last;
                self.unusable |= self.back;
                if self.steps.len() >= self.size {
                    self.close_block();
                }
            }
            self.last = Some((v, line));
        }
    }

    /// Judges the current block and starts the next.
    fn close_block(&mut self) {
        let Some(last) = self.steps.last() else {
            return;
        };
        let lines = [self.start, last.line];
        let unusable = std::mem::take(&mut self.unusable);
        let short_tail = self.steps.len() < MIN_TAIL.min(self.size / 2) && !self.blocks.is_empty();
        let median = if unusable || short_tail {
            None
        } else {
            Steps::median(&self.steps)
        };
        let reference = match (unusable, short_tail) {
            (true, _) => None,
            (false, true) => self.blocks.last().and_then(|b| b.median),
            (false, false) => median,
        };
        let gap = reference.and_then(|m| {
            self.steps
                .iter()
                .find(|s| !s.after_back && s.length() > GAP_RATIO * m)
                .map(|s| (*s, m))
        });
        self.blocks.push(Block { lines, median, gap });
        self.steps.clear();
    }

    /// The median of the positive steps of `steps` when they are a clock: at least
    /// [`REGULAR_SHARE`] of all its steps within [`REGULAR_SPREAD`] of that median (a
    /// step that is zero or negative is not). `None` otherwise, or without positive
    /// steps. (A block with a step back has no median: [`Steps::close_block`].)
    fn median(steps: &[Step]) -> Option<f64> {
        let mut lengths: Vec<f64> = steps
            .iter()
            .map(Step::length)
            .filter(|&d| d > 0.0)
            .collect();
        if lengths.is_empty() {
            return None;
        }
        // as `sampling`'s median (the upper one of an even count)
        let middle = lengths.len() / 2;
        let median = *lengths.select_nth_unstable_by(middle, f64::total_cmp).1;
        let regular = lengths
            .iter()
            .filter(|&&d| (d / median - 1.0).abs() <= REGULAR_SPREAD)
            .count();
        (regular as f64 >= REGULAR_SHARE * steps.len() as f64).then_some(median)
    }

    /// Every block, the last one closed.
    fn finish(mut self) -> Vec<Block> {
        self.close_block();
        self.blocks
    }
}

/// The fix for a gap in a time column that the config does not read.
const UNREAD_GAP_FIX: &str = "with `sample_rate`, the rows on either side would be taken \
     for one sample apart; read the time column instead of `sample_rate` (`time_column`) and \
     set `gaps = \"split\"` in [processing] to identify from the continuous segments between \
     the gaps, or split the file at this line into two files, or delete the rows on one side \
     of the gap";

/// Checks the config's `sample_rate` against the time column `column` of the file
/// `path`, whose steps are `steps`, block by block ([`Steps`]), in file order: an error at
/// the `sample_rate` key when a block's median step differs from `1 / sample_rate` by more
/// than [`RATE_TOLERANCE`] (a later block's error names its lines), and a
/// [`DataError::TimeGap`](crate::DataError::TimeGap) at the line after a step longer than
/// [`GAP_RATIO`] median steps (the stamps in seconds, in the column's unit). Nothing is
/// said of a block that is not a clock ([`Steps::median`]), nor, for a column whose unit
/// neither its name nor `time_scale` gives, when it agrees with the rate read in ms, µs
/// or ns, or counts samples (a median step of exactly 1); the unit the first clock block
/// agrees in is the unit of the rest.
pub(crate) fn check_rate(
    config: &Config,
    path: &Path,
    column: &UnreadTime,
    steps: Steps,
) -> Result<()> {
    let Some(fs) = config.sample_rate else {
        return Ok(());
    };
    let mut unit = column.scale;
    // whether a block before agreed with the rate: then a block that does not is where
    // the file changes its rate
    let mut agreed_before = false;
    for block in &steps.finish() {
        if let Some(median) = block.median {
            let agrees = |scale: f64| (median * scale * fs - 1.0).abs() <= RATE_TOLERANCE;
            let agreed = match unit {
                Some(scale) => agrees(scale).then_some(scale),
                None => [1.0, 1e-3, 1e-6, 1e-9]
                    .into_iter()
                    .find(|&s| agrees(s))
                    .or((median == 1.0).then_some(1.0 / fs)),
            };
            match agreed {
                Some(scale) => {
                    unit = Some(scale);
                    agreed_before = true;
                }
                None => {
                    let later = agreed_before.then_some(block.lines);
                    return Err(rate_error(config, path, column, median, unit, later));
                }
            }
        }
        if let Some((step, median)) = block.gap {
            let scale = unit.unwrap_or(1.0);
            return Err(Error::Data(DataError::TimeGap {
                location: format!(
                    "{}:{}, column `{}` (not read: the config gives `sample_rate`)",
                    path.display(),
                    step.line,
                    crate::data::error::quoted(&column.name)
                ),
                from: step.from * scale,
                to: step.to * scale,
                median: median * scale,
                fix: UNREAD_GAP_FIX,
            }));
        }
    }
    Ok(())
}

/// The error of a block of the time column `column` whose median step `median` does not
/// agree with the config's rate, read in `unit` (seconds per unit, when known): the first
/// block judged offers to correct `sample_rate`; a block `later` (its first and last
/// lines), after blocks at the rate, is where the file changed its rate.
fn rate_error(
    config: &Config,
    path: &Path,
    column: &UnreadTime,
    median: f64,
    unit: Option<f64>,
    later: Option<[u64; 2]>,
) -> Error {
    let fs = config.sample_rate.unwrap_or(1.0);
    let step = median * unit.unwrap_or(1.0);
    let rate = 1.0 / step;
    let name = &column.name;
    let scale = match column.scale {
        Some(s) if s != 1.0 => format!(" and `time_scale = {}`", num(s)),
        _ => String::new(),
    };
    let read_as = if unit.is_none() {
        ", read as seconds"
    } else {
        ""
    };
    let (lines, fix) = match later {
        None => (
            String::new(),
            format!(
                "replace `sample_rate` by `time_column = \"{name}\"`{scale} to use the time \
                 stamps, or correct `sample_rate` (to {} if the time stamps are right)",
                num(short(rate))
            ),
        ),
        Some([first, last]) => (
            format!(" in lines {first}-{last}"),
            format!(
                "the rate of the file changes before these lines: replace `sample_rate` by \
                 `time_column = \"{name}\"`{scale} to use the time stamps (a record at two \
                 rates is resampled onto one), or split the file where its rate changes"
            ),
        ),
    };
    config.key_error(
        "sample_rate",
        format!(
            "{} Hz, but the time column `{name}` of {} steps at {} Hz{lines} (median step {} \
             s{read_as}): every derivative and filter would be off by a factor of {}; {fix}",
            num(fs),
            path.display(),
            num(short(rate)),
            num(short(step)),
            num(short((rate / fs).max(fs / rate))),
        ),
    )
}

/// `x` rounded to four significant digits (a rate or a step measured from time stamps,
/// written short: `500`, not `499.99999999999994`).
fn short(x: f64) -> f64 {
    format!("{x:.3e}").parse().unwrap_or(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The file lines of `n` stamps: from line 2, after the header.
    fn lines(n: usize) -> Vec<u64> {
        (2..2 + n as u64).collect()
    }

    /// The median step of `t` as one block.
    fn median(t: &[f64]) -> Option<f64> {
        let mut s = Steps::default();
        s.push(t, &lines(t.len()));
        s.finish().first().and_then(|b| b.median)
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

    /// A time column the config names gives its unit whatever its stem's case or word
    /// (`T_MS` was read as seconds: a 1 kHz log as 1 Hz).
    #[test]
    fn a_named_time_column_gives_its_unit() {
        for (name, unit) in [
            ("T_MS", Some(1e-3)),
            ("t_ms", Some(1e-3)),
            ("Zeit [us]", Some(1e-6)),
            ("stamp_S", Some(1.0)),
            ("T", None),
            ("time_min", None),
            ("clock", None),
        ] {
            assert_eq!(time_column_unit(name), unit, "{name}");
        }
    }

    /// The steps read in parts, cut anywhere, are judged as the whole column, in blocks
    /// whatever the parts.
    #[test]
    fn steps_in_parts_are_the_whole_steps() {
        let t: Vec<f64> = (0..1000).map(|k| 12.5 + 0.002 * k as f64).collect();
        let at = lines(t.len());
        let mut whole = Steps::in_blocks(300);
        whole.push(&t, &at);
        let whole = whole.finish();
        assert_eq!(whole.len(), 4);
        assert_eq!(whole[0].lines, [2, 302]);
        assert_eq!(whole[3].lines, [902, 1001]);
        let median = whole[0].median.unwrap();
        assert!((median - 0.002).abs() < 1e-15, "{median}");
        for cuts in [[1, 2], [0, 999], [317, 318], [500, 1000]] {
            let mut s = Steps::in_blocks(300);
            for part in [0..cuts[0], cuts[0]..cuts[1], cuts[1]..t.len()] {
                s.push(&t[part.clone()], &at[part]);
            }
            assert_eq!(s.finish(), whole, "{cuts:?}");
        }
    }

    /// Every block is judged: a gap in a later block, at its line with its stamps and the
    /// block's median; in a short last block, against the median of the block before; a
    /// block that is not a clock has neither median nor gap, and the blocks after it are
    /// judged again.
    #[test]
    fn every_block_is_judged_for_gaps() {
        let gapped = |at: usize, size: usize| {
            let t: Vec<f64> = (0..1000)
                .map(|k| 0.001 * k as f64 + if k >= at { 0.5 } else { 0.0 })
                .collect();
            let mut s = Steps::in_blocks(size);
            s.push(&t, &lines(t.len()));
            s.finish()
        };
        let blocks = gapped(750, 300);
        assert_eq!(blocks.len(), 4);
        assert!(blocks[..2].iter().all(|b| b.gap.is_none()));
        let (step, median) = blocks[2].gap.unwrap();
        assert_eq!(step.line, 751 + 1);
        assert!((step.from - 0.749).abs() < 1e-12 && (step.to - 1.25).abs() < 1e-12);
        assert!((median - 0.001).abs() < 1e-12);
        // the last block holds 9 steps: judged with the median before it
        let blocks = gapped(995, 110);
        let last = blocks.last().unwrap();
        assert_eq!((last.median, last.lines), (None, [992, 1001]));
        assert_eq!(last.gap.unwrap().0.line, 996 + 1);
        // a stamp going back in the second block: nothing said of it, the third is judged
        let mut t: Vec<f64> = (0..900).map(|k| 0.001 * k as f64).collect();
        t[400] = 0.0;
        let mut s = Steps::in_blocks(300);
        s.push(&t, &lines(t.len()));
        let blocks = s.finish();
        assert_eq!(blocks.len(), 3);
        assert!(blocks[1].median.is_none() && blocks[1].gap.is_none());
        assert!(blocks[0].median.is_some() && blocks[2].median.is_some());
    }

    /// A stamp repeated or a field that is not a number in a block leaves it a clock,
    /// whose gap is found (each hid every gap of its block); the step back to the clock
    /// after a stamp going back as a block's last is no gap in the next block, as it is
    /// none in its own (it was taken for one).
    #[test]
    fn a_stamp_out_of_order_hides_no_gap() {
        let gapped = |t: &mut Vec<f64>| {
            for v in &mut t[600..] {
                *v += 0.5;
            }
        };
        for case in ["repeated", "not a number"] {
            let mut t: Vec<f64> = (0..900).map(|k| 0.001 * k as f64).collect();
            t[10] = if case == "repeated" { t[9] } else { f64::NAN };
            gapped(&mut t);
            let mut s = Steps::in_blocks(1000);
            s.push(&t, &lines(t.len()));
            let blocks = s.finish();
            let (step, median) = blocks[0].gap.unwrap_or_else(|| panic!("{case}"));
            assert_eq!(step.line, 600 + 2, "{case}");
            assert!((median - 0.001).abs() < 1e-12, "{case}");
        }
        // a stamp going back as the last of a block: the step after it starts the next
        // block, and is no gap
        let mut t: Vec<f64> = (0..900).map(|k| 0.001 * k as f64).collect();
        t[300] = 0.1;
        let mut s = Steps::in_blocks(300);
        s.push(&t, &lines(t.len()));
        let blocks = s.finish();
        assert_eq!(blocks.len(), 3);
        assert!(blocks.iter().all(|b| b.gap.is_none()), "{blocks:?}");
        assert!(blocks[0].median.is_none() && blocks[1].median.is_some());
    }

    /// A column that is not a clock gives no median: a stamp repeated in few steps, a
    /// decreasing stamp, fields that were not numbers, steps scattered; a few skipped
    /// ticks and some jitter leave it a clock.
    #[test]
    fn only_a_clock_has_a_median() {
        assert_eq!(median(&[0.0, 0.1, 0.1, 0.2]), None);
        assert_eq!(median(&[0.0, 0.1, 0.05, 0.2]), None);
        assert_eq!(median(&[0.0, f64::NAN, f64::INFINITY]), None);
        assert_eq!(median(&[0.0]), None);
        let mut rng = crate::rng::Rng::new(3);
        let mut t = vec![0.0];
        for _ in 0..1000 {
            t.push(t.last().unwrap() + rng.uniform(0.001, 0.01));
        }
        assert_eq!(median(&t), None);
        // 5 % of the ticks skipped, the rest with 2 % jitter
        let mut t = vec![0.0];
        for k in 0..1000 {
            let step = if k % 20 == 0 { 0.002 } else { 0.001 };
            t.push(t.last().unwrap() + step * rng.uniform(0.98, 1.02));
        }
        let m = median(&t).unwrap();
        assert!((m / 0.001 - 1.0).abs() < 0.02, "{m}");
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
