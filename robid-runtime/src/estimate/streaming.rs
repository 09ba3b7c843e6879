//! Least squares that never holds the observation matrix: OLS and WLS from triangular
//! factors accumulated block by block (docs/identification.md#streaming-least-squares).
//!
//! Each group of equations (each joint's) keeps its own upper-triangular factor R_j of
//! [W_j y_j] ((p + 1) x (p + 1)): rows are buffered, and every few hundred rows the
//! stacked [R_j; rows] is factorised again by Householder QR, which keeps
//! R_j' R_j = [W_j y_j]' [W_j y_j] without forming it. Memory is
//! O(groups x parameters^2 + buffer) whatever the number of rows.
//!
//! - OLS: the groups' factors stacked and factorised once more are the R of [W y], which
//!   the dense solver's second half solves (`lstsq::solve_factor`: column scaling by the
//!   column norms, SVD of R, the relative rank threshold, the same errors). The column
//!   norms of W are those of R, ||y|| that of R's last column.
//! - Residuals: ||y_j - W_j b|| = ||R_j [b; -1]|| for any b, so the OLS residual of each
//!   joint, which WLS weighs by, needs no second pass over the data.
//! - WLS: the weighted rows w_j [W_j y_j] have the factor w_j R_j; stacked and
//!   factorised they give the R of the weighted system.
//!
//! Every column is held divided by a power of two at least its largest magnitude (raised
//! when a larger value arrives, the factor's column rescaled exactly), so that no square
//! in the Householder norms overflows or underflows whatever the data's units: a power of
//! two commutes exactly with Householder QR.

use nalgebra::{DMatrix, DVector};

use crate::EstimateError;
use crate::error::{Error, Result};
use crate::estimate::least_squares::{
    check_tolerance, checked_weights, joint_sigma, weights_without_noise,
};
use crate::estimate::lstsq::{InverseGram, Solution, norm, solve_factor};
use crate::estimate::quality::{OUTLIER_ROWS, OUTLIER_SHARE};
use crate::estimate::result::{Residual, assemble_parts};
use crate::estimate::{Estimate, Estimator};

/// Rows buffered before a factor update. The fold ([`fold_rows`]) costs the same per row
/// whatever their number (it never touches the zeros below `R`'s diagonal), and 64 rows
/// of a system of 44 columns (22 KiB) stay in the first-level cache while each of their
/// columns is reflected.
const FOLD_ROWS: usize = 64;

/// The smallest power of two above `x` (finite, > 0); 2^1023 for larger values (x is then
/// below twice the result).
fn pow2_above(x: f64) -> f64 {
    let e = (x.to_bits() >> 52) & 0x7ff;
    match e {
        0 => f64::from_bits(1 << 52),
        2046.. => f64::from_bits(2046 << 52),
        e => f64::from_bits((e + 1) << 52),
    }
}

/// A scale that may be zero (a column with no non-zero value yet) as a divisor.
fn divisor(s: f64) -> f64 {
    if s > 0.0 { s } else { 1.0 }
}

/// Householder QR of `[r; b]` into `r`: `r` upper triangular (`n x n`), `b` rows of `n`
/// values (row-major), left as scratch. The reflection of column j involves only `r`'s
/// row j and `b`'s column j (the rows of `r` below j are zero there), and a column of `b`
/// that is zero needs none: a joint's equations are zero in the parameters of the links
/// before it (for the Panda, 8 to 43 of 44 columns live), so their columns cost nothing.
/// The rows go by `b`'s rows, contiguous, so that the updates vectorise. LAPACK's
/// reflections (`dlarfg`): `r`'s diagonal may come out negative, which changes no `r' r`.
fn fold_rows(r: &mut DMatrix<f64>, b: &mut [f64], n: usize) {
    #[cfg(target_arch = "x86_64")]
    if std::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU has AVX2, the feature `fold_rows_avx2` is compiled for.
        unsafe { fold_rows_avx2(r, b, n) };
        return;
    }
    fold_rows_body(r, b, n);
}

/// [`fold_rows`] in vectors of four (the same operations, unfused: the same values).
///
/// # Safety
/// The CPU must support AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn fold_rows_avx2(r: &mut DMatrix<f64>, b: &mut [f64], n: usize) {
    fold_rows_body(r, b, n);
}

/// The body of [`fold_rows`].
#[inline(always)]
fn fold_rows_body(r: &mut DMatrix<f64>, b: &mut [f64], n: usize) {
    let k = b.len() / n;
    let mut w = vec![0.0; n];
    for j in 0..n {
        let sigma: f64 = (0..k).map(|i| b[i * n + j] * b[i * n + j]).sum();
        if sigma == 0.0 {
            continue;
        }
        let alpha = r[(j, j)];
        let norm = (alpha * alpha + sigma).sqrt();
        let beta = if alpha > 0.0 { -norm } else { norm };
        // the reflection I - tau v v' with v = [1; b[.][j] / (alpha - beta)]
        let tau = (beta - alpha) / beta;
        let scale = 1.0 / (alpha - beta);
        let w = &mut w[j + 1..];
        for (c, w) in w.iter_mut().enumerate() {
            *w = r[(j, j + 1 + c)];
        }
        for row in b.chunks_exact(n) {
            let v = row[j] * scale;
            if v != 0.0 {
                for (w, x) in w.iter_mut().zip(&row[j + 1..]) {
                    *w += v * x;
                }
            }
        }
        for (c, w) in w.iter().enumerate() {
            r[(j, j + 1 + c)] -= tau * w;
        }
        for row in b.chunks_exact_mut(n) {
            let t = tau * row[j] * scale;
            if t != 0.0 {
                for (x, w) in row[j + 1..].iter_mut().zip(w.iter()) {
                    *x -= t * w;
                }
            }
        }
        r[(j, j)] = beta;
    }
}

/// The R factor of one group's [W y], by blocks of rows.
#[derive(Debug, Clone)]
struct Factor {
    /// Power-of-two scale of each column, y's last (0: nothing but zeros so far).
    scale: Vec<f64>,
    /// R of [W y] with column j divided by `scale[j]`, upper triangular.
    r: DMatrix<f64>,
    /// Rows not yet folded into `r`, as given (row-major, `width` values each).
    pending: Vec<f64>,
    /// Rows given.
    rows: usize,
}

impl Factor {
    fn new(width: usize) -> Self {
        Self {
            scale: vec![0.0; width],
            r: DMatrix::zeros(width, width),
            pending: Vec::new(),
            rows: 0,
        }
    }

    fn width(&self) -> usize {
        self.scale.len()
    }

    fn push(&mut self, row: &[f64], y: f64) {
        self.pending.extend_from_slice(row);
        self.pending.push(y);
        self.rows += 1;
        if self.pending.len() >= FOLD_ROWS * self.width() {
            self.flush();
        }
    }

    /// Raises column j's scale to `s` (a power of two), rescaling the factor exactly.
    fn raise(&mut self, j: usize, s: f64) {
        if s > self.scale[j] {
            if self.scale[j] > 0.0 {
                self.r.column_mut(j).scale_mut(self.scale[j] / s);
            }
            self.scale[j] = s;
        }
    }

    /// Folds the pending rows into the factor: QR of [R; rows].
    fn flush(&mut self) {
        let n1 = self.width();
        let k = self.pending.len() / n1;
        if k == 0 {
            return;
        }
        // each column's largest magnitude, row by row (contiguous: it vectorises)
        let mut big = vec![0.0f64; n1];
        for row in self.pending.chunks_exact(n1) {
            for (m, v) in big.iter_mut().zip(row) {
                *m = m.max(v.abs());
            }
        }
        for (j, big) in big.into_iter().enumerate() {
            if big > 0.0 {
                self.raise(j, pow2_above(big));
            }
        }
        let inv: Vec<f64> = self.scale.iter().map(|s| 1.0 / divisor(*s)).collect();
        for row in self.pending.chunks_exact_mut(n1) {
            for (v, inv) in row.iter_mut().zip(&inv) {
                *v *= inv;
            }
        }
        fold_rows(&mut self.r, &mut self.pending, n1);
        self.pending.clear();
    }

    /// The factor with column j in units of `common[j]` (at least `scale[j]`).
    fn r_in(&self, common: &[f64]) -> DMatrix<f64> {
        let mut r = self.r.clone();
        for (j, (s, c)) in self.scale.iter().zip(common).enumerate() {
            if *s > 0.0 && s != c {
                r.column_mut(j).scale_mut(s / c);
            }
        }
        r
    }

    /// The leverages of this group's rows summed, `tr(W_j (W'W)^-1 W_j')` under the fit
    /// `s` of the whole system (the pending rows folded in first): from the factor,
    /// `W_j'W_j = R_j'R_j` in the columns' scales, taken as the dense path takes them
    /// ([`Solution::leverage`]).
    fn leverage(&self, s: &Solution) -> f64 {
        let n = s.scales.len();
        let units: Vec<f64> = self.scale[..n].iter().map(|v| divisor(*v)).collect();
        s.leverage(self.r.columns(0, n), &units)
    }

    /// ||y - W beta|| of this group's rows (the pending rows folded in first).
    fn residual_norm(&self, beta: &DVector<f64>) -> f64 {
        let n = beta.len();
        let sy = divisor(self.scale[n]);
        let u = DVector::from_iterator(
            n + 1,
            (0..n)
                .map(|j| beta[j] * (self.scale[j] / sy))
                .chain(std::iter::once(-1.0)),
        );
        sy * norm((&self.r * u).iter().copied())
    }
}

/// OLS and WLS (Gautier's per-joint weights) from equations given a block at a time
/// (docs/identification.md#streaming-least-squares). The results equal those of
/// [`ols`](crate::estimate::ols) and [`wls`](crate::estimate::wls) on the stacked
/// observation to rounding.
///
/// ```
/// use robid_runtime::estimate::StreamingLeastSquares;
///
/// // y = 2 a - b, two joints (groups) of equations
/// let mut ls = StreamingLeastSquares::new(vec!["a".into(), "b".into()], 2).unwrap();
/// for k in 0..50 {
///     let t = k as f64 * 0.1;
///     let noise = 1e-3 * (7.3 * t).sin();
///     ls.push(0, &[t.sin(), 1.0], 2.0 * t.sin() - 1.0 + noise).unwrap();
///     ls.push(1, &[t.cos(), t], 2.0 * t.cos() - t + 10.0 * noise).unwrap();
/// }
/// // OLS misses a by 2.5e-4 (the loud group's noise leaks in), WLS by 3.0e-6
/// let ols = ls.ols(1e-10).unwrap();
/// assert!((ols.values[0] - 2.0).abs() < 5e-4 && (ols.values[1] + 1.0).abs() < 5e-5);
/// let wls = ls.wls(1e-10).unwrap();
/// assert!((wls.values[0] - 2.0).abs() < 6e-6 && (wls.values[1] + 1.0).abs() < 5e-5);
/// assert_eq!(wls.rows, 100);
/// let weights = wls.weights.unwrap();
/// assert!(weights[0] > weights[1], "the first group is ten times quieter");
/// ```
#[derive(Debug, Clone)]
pub struct StreamingLeastSquares {
    names: Vec<String>,
    groups: Vec<Factor>,
    /// The last system [`ols`](Self::ols) or [`wls`](Self::wls) solved.
    solved: Option<Solved>,
}

/// What the robust standard deviations need of the last system a
/// [`StreamingLeastSquares`] solved, with a pass over its equations again.
#[derive(Debug, Clone)]
pub(crate) struct Solved {
    /// `(W'W)^-1` of the solved (for WLS weighted) columns.
    pub(crate) inverse: InverseGram,
    /// Each group's weight (1 for OLS).
    pub(crate) weights: Vec<f64>,
    /// `||W_i|| / ||y||` of each column of the solved system.
    pub(crate) relative_column_norms: Vec<f64>,
}

impl StreamingLeastSquares {
    /// An empty system with the parameters `names` (at least one, unique) and `groups`
    /// groups of equations (joints; at least one).
    pub fn new(names: Vec<String>, groups: usize) -> Result<Self> {
        crate::estimate::check_names(&names)?;
        if names.is_empty() || groups == 0 {
            return Err(Error::setting(
                "StreamingLeastSquares::new",
                if names.is_empty() { "names" } else { "groups" },
                "give at least one parameter and one group of equations",
            ));
        }
        let width = names.len() + 1;
        Ok(Self {
            groups: vec![Factor::new(width); groups],
            names,
            solved: None,
        })
    }

    /// Parameter names.
    pub fn names(&self) -> &[String] {
        &self.names
    }

    /// Equations given so far.
    pub fn rows(&self) -> usize {
        self.groups.iter().map(|g| g.rows).sum()
    }

    /// Equations given so far in each group.
    pub fn group_rows(&self) -> Vec<usize> {
        self.groups.iter().map(|g| g.rows).collect()
    }

    /// Adds the equation `row . beta = y` to group `group`. A row of the wrong length, a
    /// group out of range or a non-finite value is an error (the equation is not added).
    pub fn push(&mut self, group: usize, row: &[f64], y: f64) -> Result<()> {
        let n = self.names.len();
        if row.len() != n {
            return Err(Error::DimensionMismatch {
                what: "equation (regressor row)".into(),
                expected: n,
                found: row.len(),
            });
        }
        let groups = self.groups.len();
        let Some(g) = self.groups.get_mut(group) else {
            return Err(Error::DimensionMismatch {
                what: "group of the equation (joint index, 0-based, below)".into(),
                expected: groups,
                found: group,
            });
        };
        let bad = row
            .iter()
            .position(|v| !v.is_finite())
            .map(|c| (self.names[c].clone(), row[c]))
            .or((!y.is_finite()).then(|| ("torque".to_string(), y)));
        if let Some((parameter, value)) = bad {
            return Err(Error::Estimate(EstimateError::NonFiniteObservation {
                location: format!("equation {} of group {}", g.rows + 1, group + 1),
                sample: None,
                joint: group + 1,
                parameter,
                value,
            }));
        }
        g.push(row, y);
        Ok(())
    }

    /// Adds equations in bulk: equation i is `w[i * n..(i + 1) * n] . beta = y[i]` in
    /// group `groups[i]` (n parameters). The groups are updated in parallel; the result is
    /// that of pushing the equations one by one. Nothing is added if any equation is
    /// refused (as by [`push`](Self::push)).
    pub fn push_rows(&mut self, groups: &[usize], w: &[f64], y: &[f64]) -> Result<()> {
        let n = self.names.len();
        if groups.len() != y.len() || w.len() != n * y.len() {
            return Err(Error::DimensionMismatch {
                what: "equations (regressor values, groups and torques)".into(),
                expected: n * y.len(),
                found: w.len(),
            });
        }
        for (i, &g) in groups.iter().enumerate() {
            let row = &w[i * n..(i + 1) * n];
            if g >= self.groups.len() || row.iter().chain([&y[i]]).any(|v| !v.is_finite()) {
                // the error of pushing it alone
                let mut probe = StreamingLeastSquares {
                    names: self.names.clone(),
                    groups: vec![Factor::new(0); self.groups.len()],
                    solved: None,
                };
                if let Some(f) = probe.groups.get_mut(g) {
                    f.rows = self.groups[g].rows;
                }
                return probe.push(g, row, y[i]);
            }
        }
        use rayon::prelude::*;
        self.groups
            .par_iter_mut()
            .enumerate()
            .for_each(|(j, factor)| {
                for (i, _) in groups.iter().enumerate().filter(|(_, g)| **g == j) {
                    factor.push(&w[i * n..(i + 1) * n], y[i]);
                }
            });
        Ok(())
    }

    /// Adds the equations of `other` (same parameters and groups), as if they had been
    /// pushed here: for accumulating parts of a record in parallel.
    pub fn merge(&mut self, mut other: StreamingLeastSquares) -> Result<()> {
        if other.names != self.names || other.groups.len() != self.groups.len() {
            return Err(Error::DimensionMismatch {
                what: "parameters and groups of the merged system".into(),
                expected: self.names.len() * self.groups.len(),
                found: other.names.len() * other.groups.len(),
            });
        }
        for (a, b) in self.groups.iter_mut().zip(&mut other.groups) {
            a.flush();
            b.flush();
            if b.rows == 0 {
                continue;
            }
            for (j, s) in b.scale.iter().enumerate() {
                a.raise(j, *s);
            }
            let width = a.width();
            let mut stacked = DMatrix::zeros(2 * width, width);
            stacked
                .view_mut((0, 0), (width, width))
                .copy_from(&a.r_in(&a.scale));
            stacked
                .view_mut((width, 0), (width, width))
                .copy_from(&b.r_in(&a.scale));
            a.r = stacked.qr().r();
            a.rows += b.rows;
        }
        Ok(())
    }

    fn flush(&mut self) {
        self.groups.iter_mut().for_each(Factor::flush);
    }

    /// Solves the groups stacked with weights (all 1 for OLS); returns the estimate's
    /// statistics for the solved (weighted) system, and its solution (of the weighted
    /// columns), kept as the last system solved ([`solved`](Self::solved)).
    fn solve(
        &mut self,
        method: Estimator,
        weights: &[f64],
        tolerance: f64,
    ) -> Result<(Estimate, Solution)> {
        let n = self.names.len();
        let m = self.rows();
        // as many equations as parameters fit any data exactly: no residual is left for
        // the standard deviations
        if m < super::equations_needed(n) {
            return Err(Error::TooFewSamples {
                context: format!("least squares with {n} parameters"),
                found: m,
                required: n + 1,
                hint: "use more data, less decimation, or fewer parameters",
            });
        }
        // the weights' largest power of two goes into the common scales, so that the
        // stacked factors are at most as large as the groups' own
        let top = pow2_above(weights.iter().copied().fold(f64::MIN_POSITIVE, f64::max));
        let mut common = vec![0.0f64; n + 1];
        for g in &self.groups {
            for (c, s) in common.iter_mut().zip(&g.scale) {
                *c = c.max(*s);
            }
        }
        let width = n + 1;
        let used: Vec<(usize, &Factor)> = self
            .groups
            .iter()
            .enumerate()
            .filter(|(_, g)| g.rows > 0)
            .collect();
        let mut stacked = DMatrix::zeros(used.len() * width, width);
        for (i, (j, g)) in used.iter().enumerate() {
            let r = g.r_in(&common) * (weights[*j] / top);
            stacked
                .view_mut((i * width, 0), (width, width))
                .copy_from(&r);
        }
        let rc = stacked.qr().r();
        // the dense solver's scaling: columns of W to unit norm, y to unit norm
        let col_norm = |j: usize| norm(rc.view((0, j), (j + 1, 1)).iter().copied());
        let mut ra = rc.clone();
        let mut d = Vec::with_capacity(n);
        for (j, s) in common.iter().enumerate() {
            let c = col_norm(j);
            if c > 0.0 {
                ra.column_mut(j).scale_mut(1.0 / c);
            }
            if j < n {
                let dj = divisor(*s) * top * c;
                d.push(if dj > 0.0 { dj } else { 1.0 });
            }
        }
        let y_norm = col_norm(n);
        let y_scale = if y_norm > 0.0 {
            divisor(common[n]) * top * y_norm
        } else {
            1.0
        };
        let s = solve_factor(&ra, &d, y_scale, &self.names, tolerance)?;
        // residual of the solved system: ||R_c [C beta / c_y; -1]|| in units of c_y
        let sy = divisor(common[n]);
        let u = DVector::from_iterator(
            n + 1,
            (0..n)
                .map(|j| s.beta[j] * (divisor(common[j]) / sy))
                .chain(std::iter::once(-1.0)),
        );
        let rho = norm((&rc * u).iter().copied());
        let error_bound = if rho == 0.0 {
            0.0
        } else if y_norm == 0.0 {
            f64::INFINITY
        } else {
            s.condition_number * rho / y_norm
        };
        let per_joint_rms = self
            .groups
            .iter()
            .map(|g| {
                if g.rows == 0 {
                    0.0
                } else {
                    g.residual_norm(&s.beta) / (g.rows as f64).sqrt()
                }
            })
            .collect();
        let solved_norm = sy * top * rho;
        // ||W_j|| / ||y|| (the scales' common `top` cancels)
        let relative_column_norms: Vec<f64> = (0..n)
            .map(|j| (col_norm(j) / y_norm) * (divisor(common[j]) / sy))
            .collect();
        self.solved = Some(Solved {
            inverse: s.inverse.clone(),
            weights: weights.to_vec(),
            relative_column_norms: relative_column_norms.clone(),
        });
        let e = assemble_parts(
            method,
            self.names.clone(),
            s.beta.clone(),
            &s.inverse,
            s.condition(),
            Residual {
                norm: solved_norm,
                rows: m,
                per_joint_rms,
                error_bound,
                relative_column_norms,
            },
        )?;
        Ok((e, s))
    }

    /// Ordinary least squares on every equation given; `tolerance` is the relative
    /// singular-value threshold (as [`ols`](crate::estimate::ols)).
    pub fn ols(&mut self, tolerance: f64) -> Result<Estimate> {
        check_tolerance(tolerance)?;
        self.flush();
        let ones = vec![1.0; self.groups.len()];
        Ok(self.solve(Estimator::Ols, &ones, tolerance)?.0)
    }

    /// The last system [`ols`](Self::ols) or [`wls`](Self::wls) solved.
    pub(crate) fn solved(&self) -> Option<&Solved> {
        self.solved.as_ref()
    }

    /// Weighted least squares with each group's weight 1 / sigma_j from its OLS residual
    /// (as [`wls`](crate::estimate::wls)).
    pub fn wls(&mut self, tolerance: f64) -> Result<Estimate> {
        check_tolerance(tolerance)?;
        self.flush();
        let ones = vec![1.0; self.groups.len()];
        let (first, solution) = self.solve(Estimator::Ols, &ones, tolerance)?;
        let beta = first.beta();
        let leverages: Vec<(usize, f64)> = self
            .groups
            .iter()
            .map(|g| (g.rows, g.leverage(&solution)))
            .collect();
        let sigma: Vec<f64> = self
            .groups
            .iter()
            .zip(&leverages)
            .map(|(g, &(rows, leverage))| {
                let rss = g.residual_norm(&beta);
                joint_sigma(rss, rows, leverage)
            })
            .collect();
        let weights = checked_weights(&sigma)?;
        let (mut e, _) = self.solve(Estimator::Wls, &weights, tolerance)?;
        e.weights = Some(weights);
        e.warnings.extend(weights_without_noise(&leverages));
        Ok(e)
    }
}

/// The share of each column's squared norm held by its largest [`OUTLIER_ROWS`] entries,
/// from rows given one at a time: the streaming form of `dominated_columns`, each entry
/// tagged (by the pipeline: its sample).
#[derive(Debug, Clone)]
pub(crate) struct Dominance {
    columns: Vec<ColumnTop>,
    /// Per column: sum of (v / scale)^2.
    sum: Vec<f64>,
    /// Per column: 1 / scale (exact: a power of two), which each value is multiplied by
    /// instead of divided by the scale: the same value, without a division per entry.
    inverse: Vec<f64>,
    /// Per column: the largest magnitude that changes neither the scale nor the top
    /// entries. A row within every column's floor (nearly all of them) only adds to the
    /// sums, in one pass that the compiler vectorises; any other row takes the pass that
    /// checks each entry. The same sums either way: an entry of 0 adds 0.
    floor: Vec<f64>,
    rows: usize,
}

#[derive(Debug, Clone, Copy)]
struct ColumnTop {
    /// Power-of-two scale of the squares (0: only zeros so far).
    scale: f64,
    /// The largest |v| with their tags, largest first.
    top: [(f64, usize); OUTLIER_ROWS],
}

impl Dominance {
    pub(crate) fn new(columns: usize) -> Self {
        Self {
            columns: vec![
                ColumnTop {
                    scale: 0.0,
                    top: [(0.0, 0); OUTLIER_ROWS],
                };
                columns
            ],
            sum: vec![0.0; columns],
            inverse: vec![0.0; columns],
            floor: vec![0.0; columns],
            rows: 0,
        }
    }

    /// Adds one row (finite values) with its tag.
    pub(crate) fn push(&mut self, row: &[f64], tag: usize) {
        self.rows += 1;
        let rare = row
            .iter()
            .zip(&self.floor)
            .fold(false, |r, (v, f)| r | (v.abs() > *f));
        if !rare {
            for ((s, v), inv) in self.sum.iter_mut().zip(row).zip(&self.inverse) {
                let t = v.abs() * inv;
                *s += t * t;
            }
            return;
        }
        for (i, (c, v)) in self.columns.iter_mut().zip(row).enumerate() {
            let a = v.abs();
            if a > c.scale {
                let s = pow2_above(a);
                if c.scale > 0.0 {
                    let f = c.scale / s;
                    self.sum[i] *= f * f;
                }
                c.scale = s;
                self.inverse[i] = 1.0 / s;
            }
            if a > 0.0 {
                let t = a * self.inverse[i];
                self.sum[i] += t * t;
            }
            if a > c.top[OUTLIER_ROWS - 1].0 {
                c.top[OUTLIER_ROWS - 1] = (a, tag);
                c.top.sort_by(|x, y| y.0.total_cmp(&x.0));
            }
            self.floor[i] = c.scale.min(c.top[OUTLIER_ROWS - 1].0);
        }
    }

    /// (column, tag of its largest entry, share) of the dominated columns, with at least
    /// 100 rows given (as `dominated_columns`).
    pub(crate) fn dominated(&self) -> Vec<(usize, usize, f64)> {
        if self.rows < 100 {
            return Vec::new();
        }
        self.columns
            .iter()
            .enumerate()
            .filter_map(|(j, c)| {
                let top: f64 = c.top.iter().map(|t| (t.0 / divisor(c.scale)).powi(2)).sum();
                let share = top / self.sum[j];
                (share > OUTLIER_SHARE).then_some((j, c.top[0].1, share))
            })
            .collect()
    }
}

#[cfg(test)]
mod tests;
