//! Standard deviations robust to autocorrelated residuals: the Newey-West
//! (heteroscedasticity and autocorrelation consistent, Bartlett kernel) covariance
//! (docs/identification.md#statistics).
//!
//! The classical `sigma^2 (W'W)^-1` assumes independent equations. The low-pass filters and
//! the decimation filter correlate the residuals of neighbouring samples, and then it
//! understates how far the estimates move from one record of the noise to the next.
//! With the score of sample t, `g_t = W_t' e_t` (`W_t` the rows of sample t, every joint's,
//! `e_t` their residuals; the weighted rows and residuals for WLS),
//!
//! ```text
//! S = sum_{l=-L..L} (1 - |l| / (L + 1)) sum_t g_t g_{t-l}'
//! cov(beta) = m / (m - c) (W'W)^-1 S (W'W)^-1        (m equations, c parameters)
//! ```
//!
//! The lag pairs are taken by sample index within one segment (a run, a piece of
//! `processing.pieces`): none reaches across a gap or a run boundary. A sample with no
//! equation (every joint's removed near rest) has a score of zero. The factor `m / (m - c)`
//! is the degrees-of-freedom correction of the classical `sigma^2`: with independent,
//! equal noise the two covariances agree on average.
//!
//! The scores arrive in order, one sample at a time ([`Scores::push`]); only the last
//! `L + 1` are kept (a ring), so that the streaming path needs no more than it holds
//! already, and `S` is summed window by window ([`Scores`]), one rank-1 update a sample
//! whatever the lag.
//!
//! ## Reference
//! W. K. Newey, K. D. West, "A simple, positive semi-definite, heteroskedasticity and
//! autocorrelation consistent covariance matrix", Econometrica 55(3), 1987;
//! W. K. Newey, K. D. West, "Automatic lag selection in covariance matrix estimation",
//! Review of Economic Studies 61(4), 1994.

use std::collections::VecDeque;

use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};

use crate::estimate::lstsq::InverseGram;

/// The lag of the Bartlett kernel for `samples` samples whose residual correlation lasts
/// about `correlated` samples: the larger of Newey and West's rule
/// `floor(4 (T / 100)^(2/9))` (1994) and `correlated`, at most `samples - 1`.
pub fn robust_lag(samples: usize, correlated: usize) -> usize {
    let rule = (4.0 * (samples as f64 / 100.0).powf(2.0 / 9.0)).floor() as usize;
    rule.max(correlated).min(samples.saturating_sub(1))
}

/// The Newey-West standard deviations of an estimate with what they were taken over.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RobustStd {
    /// sqrt(diag(cov)) of the Newey-West covariance, in parameter order.
    pub std: Vec<f64>,
    /// The Bartlett kernel's lag, in (decimated) samples.
    pub lag: usize,
    /// Samples scored (those with at least one equation).
    pub samples: usize,
}

impl RobustStd {
    /// `Some(self)` when every deviation is finite (a window's scores, up to `L + 1`
    /// residuals summed, can square past the largest float where the residual's norm does
    /// not: residuals beyond about 1e150), else `None`, so that no report writes an
    /// infinite or NaN deviation.
    pub(crate) fn finite(self) -> Option<Self> {
        self.std.iter().all(|v| v.is_finite()).then_some(self)
    }
}

/// The sum `S` of the scores' lagged outer products, from scores given sample by sample.
///
/// The Bartlett weights are a box of `L + 1` samples correlated with itself: with
/// `G_e = sum_{t = e - L..e} g_t` the sum of the window ending at sample `e` (scores outside
/// the segment, and of samples without equations, zero), every pair `g_t g_s'` with
/// `|t - s| = l <= L` lies in `L + 1 - l` windows, so
/// `S = 1 / (L + 1) sum_e G_e G_e'` over the windows that hold a score. One rank-1 update a
/// window, whatever the lag: the pairs one by one cost `L c` more a sample, which a long
/// lag (a low cutoff without decimation: thousands of samples) made the whole cost.
#[derive(Debug, Clone)]
pub(crate) struct Scores {
    /// The solved system's `(W'W)^-1`, whose column scales `D` divide each score: the
    /// scores of a column near 1e200 would square to infinity, and its unscaled
    /// `(W'W)^-1` underflows to 0.
    inverse: InverseGram,
    /// `1 / D`.
    unscale: Vec<f64>,
    lag: usize,
    /// The scores (sample, score) of the window ending at `end`, oldest first.
    ring: VecDeque<(usize, DVector<f64>)>,
    /// Their sum `G_end`.
    window: DVector<f64>,
    /// The segment and the last sample of the window (`None` before a segment's first
    /// score).
    end: Option<(usize, usize)>,
    /// Scores taken out of `window` since it was last summed afresh from the ring (so that
    /// the roundings of its subtractions do not pile up over a long record).
    removed: usize,
    /// The upper triangle of `(L + 1) S` (symmetric).
    s: DMatrix<f64>,
    /// The score being summed (segment, sample, partial score).
    current: Option<(usize, usize, DVector<f64>)>,
    samples: usize,
}

impl Scores {
    /// No scores yet, for the parameters of the solved system whose `(W'W)^-1` is
    /// `inverse`, and the kernel's `lag`.
    pub(crate) fn new(inverse: InverseGram, lag: usize) -> Self {
        let cols = inverse.scales.len();
        Self {
            unscale: inverse.scales.iter().map(|d| 1.0 / d).collect(),
            inverse,
            lag,
            ring: VecDeque::with_capacity(lag + 1),
            window: DVector::zeros(cols),
            end: None,
            removed: 0,
            s: DMatrix::zeros(cols, cols),
            current: None,
            samples: 0,
        }
    }

    /// Adds `factor * row` to the score of sample `sample` of segment `segment` (one
    /// equation's `W_t' e_t`: its row times its residual). Equations come in order of
    /// (segment, sample), those of one sample together, whatever their joints.
    pub(crate) fn add(&mut self, segment: usize, sample: usize, row: &[f64], factor: f64) {
        let unscale = &self.unscale;
        match &mut self.current {
            Some((s, k, g)) if *s == segment && *k == sample => g
                .iter_mut()
                .zip(row.iter().zip(unscale))
                .for_each(|(g, (w, u))| *g += factor * (w * u)),
            _ => {
                let g = DVector::from_iterator(
                    row.len(),
                    row.iter().zip(unscale).map(|(w, u)| factor * (w * u)),
                );
                if let Some((s, k, g)) = self.current.replace((segment, sample, g)) {
                    self.push(s, k, g);
                }
            }
        }
    }

    /// Adds the score `g` of sample `sample` of segment `segment` (after every earlier one;
    /// a sample that does not come after the window's starts a segment of its own).
    fn push(&mut self, segment: usize, sample: usize, g: DVector<f64>) {
        match self.end {
            // the windows ending between the last score and this one
            Some((s, e)) if s == segment && sample > e => {
                let mut e = e;
                while e + 1 < sample && !self.ring.is_empty() {
                    e += 1;
                    self.slide(e);
                    self.take_window();
                }
            }
            Some(_) => self.drain(),
            None => {}
        }
        self.slide(sample);
        self.window += &g;
        self.ring.push_back((sample, g));
        self.end = Some((segment, sample));
        self.take_window();
        self.samples += 1;
    }

    /// Moves the window's end to sample `e`: the scores before `e - L` leave it.
    fn slide(&mut self, e: usize) {
        self.end = self.end.map(|(s, _)| (s, e));
        while let Some((k, _)) = self.ring.front() {
            if k + self.lag >= e {
                break;
            }
            if let Some((_, old)) = self.ring.pop_front() {
                self.window -= old;
                self.removed += 1;
            }
        }
        if self.removed > self.lag {
            self.window.fill(0.0);
            for (_, g) in &self.ring {
                self.window += g;
            }
            self.removed = 0;
        }
    }

    /// The segment's last windows (those ending after its last score), then none.
    fn drain(&mut self) {
        if let Some((_, mut e)) = self.end {
            while !self.ring.is_empty() {
                e += 1;
                self.slide(e);
                if !self.ring.is_empty() {
                    self.take_window();
                }
            }
        }
        self.end = None;
        self.window.fill(0.0);
        self.removed = 0;
    }

    /// `(L + 1) S += G G'` for the window as it stands (the upper triangle).
    fn take_window(&mut self) {
        let g = &self.window;
        for b in 0..g.len() {
            if g[b] != 0.0 {
                self.s
                    .column_mut(b)
                    .rows_mut(0, b + 1)
                    .axpy(g[b], &g.rows(0, b + 1), 1.0);
            }
        }
    }

    /// The standard deviations `sqrt(diag(m / (m - c) G S G))` with G the `(W'W)^-1` of the
    /// solved system of `rows` equations (m) and c parameters, taken scaled:
    /// `D^-1 sqrt(diag(A S_s A))` with the scores `D^-1 W_t' e_t` ([`InverseGram`]).
    pub(crate) fn finish(mut self, rows: usize) -> RobustStd {
        if let Some((s, k, g)) = self.current.take() {
            self.push(s, k, g);
        }
        self.drain();
        let n = self.s.nrows();
        let width = (self.lag + 1) as f64;
        let s = DMatrix::from_fn(n, n, |a, b| self.s[(a.min(b), a.max(b))] / width);
        let a = &self.inverse.scaled;
        let cov = a * s * a;
        let dof = rows as f64 / rows.saturating_sub(n).max(1) as f64;
        RobustStd {
            // a rounding below 0 is 0; an overflow stays NaN or infinite (`f64::max` would
            // have made a NaN 0), for [`RobustStd::finite`]
            std: (0..n)
                .map(|i| {
                    let v = dof * cov[(i, i)];
                    (if v < 0.0 { 0.0 } else { v.sqrt() }) / self.inverse.scales[i]
                })
                .collect(),
            lag: self.lag,
            samples: self.samples,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The Newey-West covariance of a small problem computed densely: the n x n matrix of
    /// kernel weights between samples (0 across a segment's edge and beyond the lag), the
    /// scores as columns, G (sum_ts k_ts g_t g_s') G; the accumulator agrees to 1e-12
    /// relative, with joints whose equations arrive per sample in any order and a sample
    /// with no equation.
    #[test]
    fn the_scores_give_the_dense_newey_west_covariance() {
        let (cols, lag) = (3, 3);
        // (segment, sample) of each scored sample: a hole at sample 4, a new segment at 7,
        // a hole longer than the lag from 10 to 13
        let samples: Vec<(usize, usize)> = (0..18)
            .filter(|&k| k != 4 && !(10..=13).contains(&k))
            .map(|k| (usize::from(k >= 7), k))
            .collect();
        let value = |k: usize, j: usize, c: usize| ((k * 7 + j * 3 + c) as f64 * 0.731).sin();
        let residual = |k: usize, j: usize| ((k * 5 + j) as f64 * 1.37).cos();
        let gram: DMatrix<f64> =
            DMatrix::from_fn(cols, cols, |a, b| if a == b { 2.0 + a as f64 } else { 0.3 });
        let inverse = gram.try_inverse().unwrap();
        let mut scores = Scores::new(InverseGram::unscaled(inverse.clone()), lag);
        let mut g: DMatrix<f64> = DMatrix::zeros(cols, samples.len());
        for (t, &(segment, k)) in samples.iter().enumerate() {
            for j in [1, 0] {
                let row: Vec<f64> = (0..cols).map(|c| value(k, j, c)).collect();
                scores.add(segment, k, &row, residual(k, j));
                for c in 0..cols {
                    g[(c, t)] += row[c] * residual(k, j);
                }
            }
        }
        let kernel: DMatrix<f64> = DMatrix::from_fn(samples.len(), samples.len(), |a, b| {
            let ((sa, ka), (sb, kb)) = (samples[a], samples[b]);
            let l = ka.abs_diff(kb);
            if sa != sb || l > lag {
                0.0
            } else {
                1.0 - l as f64 / (lag + 1) as f64
            }
        });
        let rows = 2 * samples.len();
        let s: DMatrix<f64> = &g * kernel * g.transpose();
        let dense: DMatrix<f64> = (&inverse * s * &inverse) * (rows as f64 / (rows - cols) as f64);
        let robust = scores.finish(rows);
        assert_eq!((robust.lag, robust.samples), (lag, samples.len()));
        for i in 0..cols {
            let expected = dense[(i, i)].sqrt();
            assert!(
                (robust.std[i] / expected - 1.0).abs() < 1e-12,
                "{i}: {} vs {expected}",
                robust.std[i]
            );
        }
    }

    /// Samples that restart within one segment (a caller's slip: two records given one
    /// segment) pair nothing across the restart, nor panic: the same as two segments.
    #[test]
    fn a_restart_of_the_samples_pairs_nothing_across_it() {
        let inverse = InverseGram::unscaled(DMatrix::from_element(1, 1, 0.1));
        let score = |k: usize| [((k * 3) as f64 * 0.7).sin() + 0.2];
        let run = |second: usize| {
            let mut scores = Scores::new(inverse.clone(), 3);
            for (segment, k) in (0..6).map(|k| (0, k)).chain((0..6).map(|k| (second, k))) {
                scores.add(segment, k, &score(k), 1.0);
            }
            scores.finish(12).std[0]
        };
        assert_eq!(run(0), run(1));
    }

    /// With lag 0 and one equation per sample the covariance is White's: G (sum e_t^2
    /// x_t x_t') G, which for one column of ones is sum e_t^2 / m^2.
    #[test]
    fn lag_zero_is_whites_covariance() {
        let e = [1.0, -2.0, 0.5, 3.0];
        let mut scores = Scores::new(InverseGram::unscaled(DMatrix::from_element(1, 1, 0.25)), 0);
        for (k, e) in e.iter().enumerate() {
            scores.add(0, k, &[1.0], *e);
        }
        let robust = scores.finish(4);
        let expected = (14.25f64 / 16.0 * 4.0 / 3.0).sqrt();
        assert!((robust.std[0] - expected).abs() < 1e-15, "{robust:?}");
    }

    #[test]
    fn the_lag_follows_newey_and_west_or_the_correlation() {
        // 4 (T / 100)^(2/9): 4 at 100 samples, 11.1 at 10,000
        assert_eq!(robust_lag(100, 0), 4);
        assert_eq!(robust_lag(10_000, 0), 11);
        assert_eq!(robust_lag(10_000, 30), 30);
        assert_eq!(robust_lag(3, 30), 2);
        assert_eq!(robust_lag(0, 0), 0);
    }
}
