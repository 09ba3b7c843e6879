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
    /// The statistics of a file with time stamps `time` (seconds, increasing) and data
    /// `columns` (one vector per column, all of the same length).
    pub fn of(path: PathBuf, time: Option<&[f64]>, columns: &[Vec<f64>]) -> Sampling {
        let rows = columns.first().map_or(0, Vec::len);
        let (step, jitter, skipped_ticks) = match time.and_then(step_statistics) {
            Some(s) => (Some(s.median), Some(s.jitter), s.skipped_ticks),
            None => (None, None, 0),
        };
        Sampling {
            path,
            rows,
            step,
            jitter,
            skipped_ticks,
            repeated_rows: (1..rows)
                .filter(|&k| columns.iter().all(|c| c[k] == c[k - 1]))
                .count(),
            stale_rows: stale_rows(columns),
        }
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
    if t.len() < 2 {
        return None;
    }
    let mut steps: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).collect();
    let median = median(&mut steps);
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

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// The rows equal to the previous row in every column, in runs that look like an old
/// sample written again: some column steps steadily into the run (its last two steps
/// differ by at most half) and leaves it with the steps the run missed (r + 1 times the
/// step before for a run of r rows, within half a step, same sign). Quantised slow motion
/// does not do that: its steps take two neighbouring values, never 0 and 2.
fn stale_rows(columns: &[Vec<f64>]) -> Vec<usize> {
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
}
