//! How a file was sampled, from its time stamps and its rows: the median step, the jitter
//! of the regular steps, the ticks that steps skip, and stale rows (a logger that wrote
//! an old sample again). `robid inspect` reports them; loading warns about stale rows and
//! names skipped ticks and jitter in the warning about irregular time steps.

use std::path::PathBuf;

use serde::Serialize;

/// A step of at least this many median steps skips ticks.
pub const SKIP_RATIO: f64 = 1.5;
/// Share of stale rows above which loading warns (a handful in a long log is noise).
pub const STALE_SHARE: f64 = 1e-3;

/// Sampling statistics of one file.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Sampling {
    /// The file.
    pub path: PathBuf,
    /// Data rows.
    pub rows: usize,
    /// Median time step (s), when the file has a time column.
    pub step: Option<f64>,
    /// RMS deviation of the steps shorter than [`SKIP_RATIO`] median steps from the
    /// median (s), when the file has a time column.
    pub jitter: Option<f64>,
    /// Ticks skipped: over the steps of at least [`SKIP_RATIO`] median steps, the number
    /// of median steps each spans less one.
    pub skipped_ticks: usize,
    /// Rows equal to the previous row in every column (at rest, quantised slow motion, or
    /// stale).
    pub repeated_rows: usize,
    /// Rows (0-based) that look like an old sample written again: equal to the previous
    /// row in every column, in a run after which some column catches up the steps it
    /// missed.
    pub stale_rows: Vec<usize>,
}

impl Sampling {
    /// The statistics of the time steps (`None` without a time column).
    pub(crate) fn steps(&self) -> Option<Steps> {
        Some(Steps {
            median: self.step?,
            jitter: self.jitter?,
            skipped_ticks: self.skipped_ticks,
        })
    }

    /// The statistics of a file with time stamps `time` (seconds, increasing) and data
    /// `columns` (one vector per column, all of the same length).
    pub fn of(path: PathBuf, time: Option<&[f64]>, columns: &[Vec<f64>]) -> Sampling {
        let mut scan = SamplingScan::new(columns.len());
        scan.push(time, columns, None);
        scan.finish(path)
    }

    /// One line for people: rows, step and jitter, skipped ticks, stale rows.
    pub fn summary(&self) -> String {
        let share = |n: usize| 100.0 * n as f64 / self.rows.max(1) as f64;
        let mut s = format!("{}: {} rows", self.path.display(), self.rows);
        if let (Some(step), Some(jitter)) = (self.step, self.jitter) {
            s += &format!(
                ", median step {:.4} ms ({:.1} Hz), jitter {:.4} ms, {} skipped ticks ({:.1} %)",
                1e3 * step,
                1.0 / step,
                1e3 * jitter,
                self.skipped_ticks,
                share(self.skipped_ticks)
            );
        }
        s + &format!(
            ", {} rows repeat the previous one ({:.1} %), {} of them stale ({:.2} %)",
            self.repeated_rows,
            share(self.repeated_rows),
            self.stale_rows.len(),
            share(self.stale_rows.len())
        )
    }
}

/// The statistics of a sequence of time stamps.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Steps {
    pub(crate) median: f64,
    pub(crate) jitter: f64,
    pub(crate) skipped_ticks: usize,
}

/// Median step, jitter of the regular steps and skipped ticks of increasing time stamps
/// (`None` for fewer than two).
pub(crate) fn step_statistics(t: &[f64]) -> Option<Steps> {
    let mut steps = StepCounts::default();
    for w in t.windows(2) {
        steps.push(w[1] - w[0]);
    }
    steps.statistics()
}

/// Distinct steps counted before they are kept one by one instead.
const DISTINCT_STEPS: usize = 64;

/// The time steps of a file, as the statistics need them: their values in any order (the
/// statistics sort them). A clock's steps take few distinct values (the hour's 3.6 M
/// steps at 1 kHz, written with three decimals, take 21), so they are counted per value
/// (its bits) while there are at most [`DISTINCT_STEPS`] of them; past that every step is
/// kept.
#[derive(Debug, Clone, Default)]
pub(crate) struct StepCounts {
    /// Each distinct step's bits and count (empty once `all` is used).
    counts: Vec<(u64, usize)>,
    /// The index in `counts` of the last step (the next is often the same).
    last: usize,
    /// Every step, once there were too many distinct ones to count.
    all: Vec<f64>,
    /// Whether `all` holds the steps.
    listed: bool,
}

impl StepCounts {
    /// Counts one more step.
    pub(crate) fn push(&mut self, d: f64) {
        if self.listed {
            self.all.push(d);
            return;
        }
        let bits = d.to_bits();
        if let Some(c) = self.counts.get_mut(self.last)
            && c.0 == bits
        {
            c.1 += 1;
            return;
        }
        if let Some(i) = self.counts.iter().position(|c| c.0 == bits) {
            self.counts[i].1 += 1;
            self.last = i;
        } else if self.counts.len() < DISTINCT_STEPS {
            self.last = self.counts.len();
            self.counts.push((bits, 1));
        } else {
            let n = self.counts.iter().map(|c| c.1).sum::<usize>();
            self.all.reserve(2 * n + 1);
            for &(bits, count) in &self.counts {
                self.all
                    .extend(std::iter::repeat_n(f64::from_bits(bits), count));
            }
            self.all.push(d);
            self.counts = Vec::new();
            self.listed = true;
        }
    }

    /// The median step, the jitter of the regular steps and the skipped ticks (`None`
    /// without steps): the steps sorted (`f64::total_cmp`), the median the one at half
    /// their count, and the jitter's sum taken over them in that order, whether they were
    /// counted per value or kept (each value's count of equal terms in turn: the same
    /// additions in the same order, so the same bits).
    pub(crate) fn statistics(mut self) -> Option<Steps> {
        let sorted: Vec<(f64, usize)> = if self.listed {
            // steps equal under `total_cmp` have the same bits: any sort gives the same order
            self.all.sort_unstable_by(f64::total_cmp);
            self.all
                .chunk_by(|a, b| a.to_bits() == b.to_bits())
                .map(|run| (run[0], run.len()))
                .collect()
        } else {
            let mut v: Vec<(f64, usize)> = self
                .counts
                .iter()
                .map(|&(bits, count)| (f64::from_bits(bits), count))
                .collect();
            v.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
            v
        };
        let n: usize = sorted.iter().map(|s| s.1).sum();
        if n == 0 {
            return None;
        }
        let (mut seen, mut median) = (0, f64::NAN);
        for &(d, count) in &sorted {
            seen += count;
            if seen > n / 2 {
                median = d;
                break;
            }
        }
        let (mut sum, mut regular, mut skipped_ticks) = (0.0, 0usize, 0usize);
        for &(d, count) in &sorted {
            if d >= SKIP_RATIO * median {
                skipped_ticks += count * ((d / median).round() as usize).saturating_sub(1);
            } else {
                let square = (d - median).powi(2);
                for _ in 0..count {
                    sum += square;
                }
                regular += count;
            }
        }
        Some(Steps {
            median,
            jitter: (sum / regular.max(1) as f64).sqrt(),
            skipped_ticks,
        })
    }
}

/// [`Sampling`] of a file read in parts, in order: the same statistics as
/// [`Sampling::of`] on the whole file, holding only the time steps (counted per value,
/// [`StepCounts`]) and the rows before a run of repeated rows.
///
/// Stale rows are the rows equal to the previous row in every column, in runs that look
/// like an old sample written again: some column steps steadily into the run (its last two
/// steps differ by at most half) and leaves it with the steps the run missed (r + 1 times
/// the step before for a run of r rows, within half a step, same sign). Quantised slow
/// motion does not do that: its steps take two neighbouring values, never 0 and 2. A run
/// that reaches the last row is not stale (nothing catches up), and runs are looked for
/// from row 3 on (three rows before one are needed).
#[derive(Debug, Clone)]
pub(crate) struct SamplingScan {
    rows: usize,
    steps: StepCounts,
    last_time: Option<f64>,
    repeated_rows: usize,
    stale_rows: Vec<usize>,
    /// The file line of the first stale row, when lines are given.
    first_stale_line: Option<u64>,
    /// The last three rows (oldest first), column by column.
    recent: Vec<[f64; 3]>,
    /// The open run of repeated rows: its first row, that row's line, and the three rows
    /// before it.
    run: Option<(usize, Option<u64>, Vec<[f64; 3]>)>,
}

impl SamplingScan {
    /// A scan of a file with `columns` data columns.
    pub(crate) fn new(columns: usize) -> Self {
        Self {
            rows: 0,
            steps: StepCounts::default(),
            last_time: None,
            repeated_rows: 0,
            stale_rows: Vec::new(),
            first_stale_line: None,
            recent: vec![[0.0; 3]; columns],
            run: None,
        }
    }

    /// The next rows: their time stamps (when the file has a time column), their data
    /// columns and their file lines (when known).
    pub(crate) fn push(
        &mut self,
        time: Option<&[f64]>,
        columns: &[Vec<f64>],
        lines: Option<&[u64]>,
    ) {
        if let Some(t) = time {
            for &v in t {
                if let Some(last) = self.last_time {
                    self.steps.push(v - last);
                }
                self.last_time = Some(v);
            }
        }
        let n = columns.first().map_or(0, Vec::len);
        for i in 0..n {
            let k = self.rows;
            let repeats = k > 0 && columns.iter().zip(&self.recent).all(|(c, r)| c[i] == r[2]);
            if repeats {
                self.repeated_rows += 1;
                if self.run.is_none() && k >= 3 {
                    let line = lines.and_then(|l| l.get(i).copied());
                    self.run = Some((k, line, self.recent.clone()));
                }
            } else if let Some((start, line, before)) = self.run.take() {
                // the run ended on the previous row: does some column catch up?
                let run = (k - start) as f64;
                let catches_up = columns.iter().zip(&before).any(|(c, b)| {
                    let (before, earlier, after) = (b[2] - b[1], b[1] - b[0], c[i] - b[2]);
                    let ratio = after / before;
                    before != 0.0
                        && (earlier - before).abs() <= 0.5 * before.abs()
                        && (run + 0.5..=run + 1.5).contains(&ratio)
                });
                if catches_up {
                    if self.stale_rows.is_empty() {
                        self.first_stale_line = line;
                    }
                    self.stale_rows.extend(start..k);
                }
            }
            for (c, r) in columns.iter().zip(&mut self.recent) {
                *r = [r[1], r[2], c[i]];
            }
            self.rows += 1;
        }
    }

    /// The file line of the first stale row (when lines were given).
    pub(crate) fn first_stale_line(&self) -> Option<u64> {
        self.first_stale_line
    }

    /// The statistics of the rows pushed, for the file `path`.
    pub(crate) fn finish(self, path: PathBuf) -> Sampling {
        let (step, jitter, skipped_ticks) = match self.steps.statistics() {
            Some(s) => (Some(s.median), Some(s.jitter), s.skipped_ticks),
            None => (None, None, 0),
        };
        Sampling {
            path,
            rows: self.rows,
            step,
            jitter,
            skipped_ticks,
            repeated_rows: self.repeated_rows,
            stale_rows: self.stale_rows,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A ramp of 10 counts per sample with one stale row and two skipped ticks at 2 ms.
    #[test]
    fn stale_rows_skips_and_jitter_are_counted() {
        let mut t: Vec<f64> = (0..20).map(|k| 0.002 * k as f64).collect();
        // two ticks missing after row 12
        for v in &mut t[13..] {
            *v += 0.004;
        }
        t[5] += 0.0001;
        let mut x: Vec<f64> = (0..20).map(|k| 0.01 * k as f64).collect();
        x[8] = x[7];
        let y = vec![1.0; 20];
        let s = Sampling::of("a.csv".into(), Some(&t), &[x.clone(), y.clone()]);
        assert_eq!(s.rows, 20);
        assert!((s.step.unwrap() - 0.002).abs() < 1e-15);
        assert_eq!(s.skipped_ticks, 2);
        // steps 0.0021 and 0.0019 among 18 regular ones
        let jitter = (2.0 * 0.0001f64.powi(2) / 18.0).sqrt();
        assert!((s.jitter.unwrap() - jitter).abs() < 1e-12, "{:?}", s.jitter);
        assert_eq!(s.stale_rows, [8]);
        // every row of the constant column repeats, but only row 8 of both columns
        assert_eq!(s.repeated_rows, 1);
        assert!(s.summary().contains("2 skipped ticks") && s.summary().contains("1 of them stale"));
    }

    /// The statistics as first written: every step kept, sorted, the median at half their
    /// count and the jitter summed in sorted order.
    fn reference_steps(mut steps: Vec<f64>) -> Option<Steps> {
        if steps.is_empty() {
            return None;
        }
        steps.sort_by(f64::total_cmp);
        let median = steps[steps.len() / 2];
        let (mut sum, mut regular, mut skipped_ticks) = (0.0, 0usize, 0usize);
        for d in &steps {
            if *d >= SKIP_RATIO * median {
                skipped_ticks += ((d / median).round() as usize).saturating_sub(1);
            } else {
                sum += (d - median).powi(2);
                regular += 1;
            }
        }
        Some(Steps {
            median,
            jitter: (sum / regular.max(1) as f64).sqrt(),
            skipped_ticks,
        })
    }

    /// Time stamps of a clock (few distinct steps, counted per value), of a jittered clock
    /// (many, kept one by one) and of one that turns jittered late, with skipped ticks:
    /// the median, jitter and skipped ticks are the reference's to the bit.
    #[test]
    fn step_statistics_are_the_sorted_steps_to_the_bit() {
        let mut rng = crate::rng::Rng::new(5);
        for case in 0..60 {
            let rows = 2 + (rng.uniform(0.0, 1.0) * 20_000.0) as usize;
            let (jitter, from) = match case % 3 {
                0 => (0.0, rows),
                1 => (3e-5, 0),
                _ => (2e-5, rows - rows / 50),
            };
            let mut t = Vec::with_capacity(rows);
            let mut k = 0usize;
            for r in 0..rows {
                if rng.uniform(0.0, 1.0) < 0.01 {
                    k += 1 + (rng.uniform(0.0, 1.0) * 3.0) as usize;
                }
                let wobble = if r >= from {
                    (rng.uniform(-jitter, jitter) * 1e6).round() / 1e6
                } else {
                    0.0
                };
                // written with three or six decimals and read back
                t.push(((k as f64 * 1e-3 + wobble) * 1e6).round() / 1e6 + 1e3 * (case % 2) as f64);
                k += 1;
            }
            let steps: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).collect();
            let (got, want) = (step_statistics(&t), reference_steps(steps));
            let bits = |s: Option<Steps>| {
                s.map(|s| (s.median.to_bits(), s.jitter.to_bits(), s.skipped_ticks))
            };
            assert_eq!(
                bits(got),
                bits(want),
                "case {case}: {got:?} against {want:?}"
            );
        }
        assert_eq!(step_statistics(&[1.0]), None);
        let constant = step_statistics(&[0.0, 0.5, 1.0]).unwrap();
        assert_eq!(
            (constant.median, constant.jitter, constant.skipped_ticks),
            (0.5, 0.0, 0)
        );
    }

    /// A robot at rest, or quantised slow motion (steps of 0 and 1 count, or 1 and 2),
    /// repeats rows honestly: those are not stale.
    #[test]
    fn rest_and_slow_motion_are_not_stale() {
        let rest = vec![0.5; 50];
        for speed in [0.3, 0.7, 1.3, 1.9] {
            let slow: Vec<f64> = (0..200).map(|k| (speed * k as f64).floor()).collect();
            let s = Sampling::of("b.csv".into(), None, &[rest.repeat(4), slow]);
            assert!(s.stale_rows.is_empty(), "{speed}: {:?}", s.stale_rows);
            assert_eq!((s.step, s.jitter, s.skipped_ticks), (None, None, 0));
        }
    }

    /// A run of two stale rows is followed by a triple step.
    #[test]
    fn a_run_of_stale_rows_is_found() {
        let mut x: Vec<f64> = (0..12).map(|k| 10.0 * k as f64).collect();
        x[5] = 40.0;
        x[6] = 40.0;
        let s = Sampling::of("c.csv".into(), None, std::slice::from_ref(&x));
        assert_eq!(s.stale_rows, [5, 6]);
        // a stop that does not catch up is motion, not a stale sample
        x[7] = 40.0;
        x[8] = 50.0;
        let s = Sampling::of("c.csv".into(), None, std::slice::from_ref(&x));
        assert!(s.stale_rows.is_empty(), "{:?}", s.stale_rows);
    }

    /// The rows' scan as first written (whole columns, random access): the reference of
    /// the streaming [`SamplingScan`].
    fn reference_stale_rows(columns: &[Vec<f64>]) -> Vec<usize> {
        let rows = columns.first().map_or(0, Vec::len);
        let repeats = |k: usize| columns.iter().all(|c| c[k] == c[k - 1]);
        let mut stale = Vec::new();
        let mut k = 3;
        while k + 1 < rows {
            if !repeats(k) {
                k += 1;
                continue;
            }
            let mut last = k;
            while last + 1 < rows && repeats(last + 1) {
                last += 1;
            }
            if last + 1 == rows {
                break;
            }
            let run = (last - k + 1) as f64;
            let catches_up = columns.iter().any(|c| {
                let (before, earlier, after) = (
                    c[k - 1] - c[k - 2],
                    c[k - 2] - c[k - 3],
                    c[last + 1] - c[last],
                );
                let ratio = after / before;
                before != 0.0
                    && (earlier - before).abs() <= 0.5 * before.abs()
                    && (run + 0.5..=run + 1.5).contains(&ratio)
            });
            if catches_up {
                stale.extend(k..=last);
            }
            k = last + 1;
        }
        stale
    }

    /// Ramps with stale runs, rests and quantised slow motion, at random: the scan in one
    /// part, and in parts cut anywhere, finds the reference's stale rows and counts.
    #[test]
    fn the_scan_in_parts_is_the_whole_scan() {
        let mut rng = crate::rng::Rng::new(11);
        for case in 0..300 {
            let rows = 2 + (rng.uniform(0.0, 1.0) * 60.0) as usize;
            let mut a = vec![0.0; rows];
            let b: Vec<f64> = (0..rows).map(|k| (0.4 * k as f64).floor()).collect();
            for k in 1..rows {
                a[k] = a[k - 1]
                    + if rng.uniform(0.0, 1.0) < 0.8 {
                        1.0
                    } else {
                        0.0
                    };
            }
            // stale runs: rows repeated, then the ramp catches up
            for _ in 0..3 {
                let k = (rng.uniform(0.0, 1.0) * rows as f64) as usize;
                let len = 1 + (rng.uniform(0.0, 1.0) * 3.0) as usize;
                for r in k..(k + len).min(rows) {
                    a[r] = a[k.saturating_sub(1)];
                }
            }
            let columns = [a, if case % 2 == 0 { b } else { vec![1.0; rows] }];
            let t: Vec<f64> = (0..rows).map(|k| 1e-3 * k as f64).collect();
            let whole = Sampling::of("x.csv".into(), Some(&t), &columns);
            assert_eq!(
                whole.stale_rows,
                reference_stale_rows(&columns),
                "case {case}"
            );
            let cuts = [
                (rng.uniform(0.0, 1.0) * rows as f64) as usize,
                (rng.uniform(0.0, 1.0) * rows as f64) as usize,
            ];
            let (c0, c1) = (cuts[0].min(cuts[1]), cuts[0].max(cuts[1]));
            let mut scan = SamplingScan::new(2);
            for part in [0..c0, c0..c1, c1..rows] {
                let cols: Vec<Vec<f64>> =
                    columns.iter().map(|c| c[part.clone()].to_vec()).collect();
                let lines: Vec<u64> = part.clone().map(|k| k as u64 + 2).collect();
                scan.push(Some(&t[part]), &cols, Some(&lines));
            }
            let first_line = scan.first_stale_line();
            assert_eq!(first_line, whole.stale_rows.first().map(|&k| k as u64 + 2));
            assert_eq!(
                scan.finish("x.csv".into()),
                whole,
                "case {case}, cuts {c0} {c1}"
            );
        }
    }
}
