//! Design criteria on the stacked base regressor W = [Y_b(t_1); ...; Y_b(t_K)].
//!
//! Both criteria are computed from the information matrix W'W (p x p, accumulated sample by
//! sample, so no tall matrix is stored): the singular values of W are the square roots of
//! its eigenvalues. cond_2(W) = sqrt(lambda_max / lambda_min) is exact in exact arithmetic
//! and accurate to many digits while cond(W) is far below 1e8, the only range that matters
//! for a design, and so for every design without row weights. Columns are not scaled.
//!
//! From cond(W) = 1e5 on ([`DIRECT`]), where the eigenvalues of W'W, known to about
//! eps lambda_max, give lambda_min to worse than 2e-6 of itself (and nothing above about
//! 3e7), the criteria are computed on the equilibrated matrix A = D^-1 W'W D^-1 (D = the column
//! norms of W, [`scaled_criteria`]): W = B D with the columns of B of unit norm, and the
//! eigenvalues of D A D are set by the entries of W'W to a relative accuracy of about
//! eps cond(A) (Demmel and Veselić 1992), however different the columns' scales. Regressor
//! rows weighted 1e6 apart (`robid excite --sigma 1e-6,1`) give cond(W) near 1e8 for any
//! trajectory, which the direct computation took for rank deficiency: every trajectory's
//! criterion was infinite and the design failed. Only a W whose equilibrated columns are
//! themselves dependent (cond(A) beyond about 3e7) leaves a parameter unexcited.
//!
//! ## Reference
//! J. Swevers, C. Ganseman, D. B. Tukel, J. De Schutter, H. Van Brussel, "Optimal robot
//! excitation and identification", IEEE Trans. Robotics and Automation 13(5), 1997 (condition
//! number and D-optimality of the regressor); J. Demmel, K. Veselić, "Jacobi's method is
//! more accurate than QR", SIAM J. Matrix Anal. Appl. 13(4), 1992 (the eigenvalues of a
//! scaled positive definite matrix D A D are set to relative accuracy eps cond(A)).

use nalgebra::DMatrix;
use nalgebra::linalg::SymmetricTridiagonal;

use crate::estimate::SIGMA_FLOOR;
use crate::simulate::Trajectory;
use crate::{LengthError, Model};

/// What a design minimises.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum Criterion {
    /// The 2-norm condition number of W.
    #[default]
    Condition,
    /// D-optimality: minimises -log det(W'W / K) / p, K the number of samples.
    DOptimal,
}

/// Accumulates W'W from regressor evaluations.
#[derive(Debug, Clone)]
pub struct Information {
    /// W'W.
    pub gram: DMatrix<f64>,
    /// Samples added.
    pub samples: usize,
    y: Vec<f64>,
    /// The regressors of [`Information::add_lanes`], lane-major.
    lanes: Vec<f64>,
    weights: Option<Vec<f64>>,
}

/// Row weights `1 / sigma_j` with each sigma floored at [`SIGMA_FLOOR`] of the largest:
/// each weight at most `1 / SIGMA_FLOOR` times the smallest positive finite weight (the
/// others are left for the design's check to refuse). The floor of weighted least squares
/// and of [`crate::excite::weights_from_sigma`], applied where weights enter W'W, so a
/// design given weights in code (`FourierDesign::weights`, `PointDesign::weights`, each in
/// (0, 1e9], so up to 1e9 apart or more) weighs its rows as the command line and the
/// estimator do: weights 1e9 apart made the criterion of every trajectory infinite.
///
/// ```
/// use robid_runtime::excite::floor_weights;
/// assert_eq!(floor_weights(&[1e9, 1.0, 2.0]), vec![1e6, 1.0, 2.0]);
/// assert_eq!(floor_weights(&[3.0, 1.0]), vec![3.0, 1.0]);
/// ```
pub fn floor_weights(weights: &[f64]) -> Vec<f64> {
    let smallest = weights
        .iter()
        .copied()
        .filter(|w| *w > 0.0 && w.is_finite())
        .fold(f64::INFINITY, f64::min);
    if !smallest.is_finite() {
        return weights.to_vec();
    }
    let cap = smallest / SIGMA_FLOOR;
    weights
        .iter()
        .map(|&w| if w > cap && w.is_finite() { cap } else { w })
        .collect()
}

impl Information {
    /// An empty accumulator for a model.
    pub fn new<M: Model + ?Sized>(model: &M) -> Self {
        let p = model.base_parameter_count();
        Self {
            gram: DMatrix::zeros(p, p),
            samples: 0,
            y: vec![0.0; model.dof() * p],
            lanes: Vec::new(),
            weights: None,
        }
    }

    /// Scales the rows of joint j by `weights[j]` (e.g. 1 / the joint's torque noise sigma,
    /// so that W'W is the information weighted least squares sees), each weight at most
    /// 1 / [`SIGMA_FLOOR`] times the smallest ([`floor_weights`]), as weighted least squares
    /// and `robid excite --sigma` ([`crate::excite::weights_from_sigma`]) floor a sigma at
    /// [`SIGMA_FLOOR`] of the largest.
    pub fn with_weights(mut self, weights: &[f64]) -> Self {
        self.weights = Some(floor_weights(weights));
        self
    }

    /// Empties the accumulator (keeping its buffers and weights).
    pub fn reset(&mut self) {
        self.gram.fill(0.0);
        self.samples = 0;
    }

    /// Adds the rows Y_b(q, qd, qdd).
    pub fn add<M: Model + ?Sized>(
        &mut self,
        model: &M,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
    ) -> Result<(), LengthError> {
        model.base_regressor_into(q, qd, qdd, &mut self.y)?;
        self.add_y(model.dof());
        Ok(())
    }

    /// Adds the rows Y_b of `lanes` samples given lane-major (joint i of sample l at
    /// `i * lanes + l`, [`Model::run_lanes`]): the model evaluates them in one call (an
    /// interpreter dispatches each operation once for all of them), then they are added
    /// sample by sample, so W'W is the same to the bit as with [`Information::add`] on
    /// each sample in order.
    pub fn add_lanes<M: Model + ?Sized>(
        &mut self,
        model: &M,
        lanes: usize,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
    ) -> Result<(), LengthError> {
        let p = self.gram.ncols();
        let rows = model.dof();
        self.lanes.resize(rows * p * lanes, 0.0);
        model.run_lanes(
            crate::model::ProgramKind::BaseRegressor,
            lanes,
            &[q, qd, qdd],
            &mut self.lanes,
        )?;
        for l in 0..lanes {
            for (y, &v) in self
                .y
                .iter_mut()
                .zip(self.lanes.iter().skip(l).step_by(lanes))
            {
                *y = v;
            }
            self.add_y(rows);
        }
        Ok(())
    }

    /// Adds the `rows` regressor rows in `y` (weighted first, when weights are set).
    fn add_y(&mut self, rows: usize) {
        if let Some(w) = &self.weights {
            let p = self.gram.ncols();
            for (row, w) in self.y.chunks_mut(p).zip(w) {
                row.iter_mut().for_each(|y| *y *= w);
            }
        }
        add_rows(&mut self.gram, &self.y, rows);
        self.samples += 1;
    }

    /// Adds every `stride`-th sample of a trajectory.
    pub fn add_trajectory<M: Model + ?Sized>(
        &mut self,
        model: &M,
        trajectory: &Trajectory,
        stride: usize,
    ) -> Result<(), LengthError> {
        let n = trajectory.dof();
        let (mut q, mut qd, mut qdd) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        for k in (0..trajectory.samples()).step_by(stride.max(1)) {
            trajectory.state(k, &mut q, &mut qd, &mut qdd);
            self.add(model, &q, &qd, &qdd)?;
        }
        Ok(())
    }

    /// Singular values of W, largest first.
    pub fn singular_values(&self) -> Vec<f64> {
        singular_values(&self.gram)
    }

    /// cond_2(W) (infinite when W is rank deficient).
    pub fn condition_number(&self) -> f64 {
        condition_from_singular(&self.singular_values())
    }

    /// The value of a criterion (smaller is better).
    pub fn cost(&self, criterion: Criterion) -> f64 {
        cost(&self.gram, self.samples, criterion)
    }
}

/// gram += Y'Y (lower triangle) for a row-major `rows x p` block `y`.
///
/// On x86-64 with AVX2 the same loop is compiled for 4-wide vectors and chosen at run time:
/// every element still gets the same multiplication and addition in the same order (Rust
/// never fuses them), so the sums are the same to the bit on every machine.
pub(crate) fn add_rows(gram: &mut DMatrix<f64>, y: &[f64], rows: usize) {
    let p = gram.ncols();
    let g = gram.as_mut_slice();
    #[cfg(target_arch = "x86_64")]
    if std::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU was just found to support AVX2.
        unsafe { add_rows_avx2(g, y, rows, p) };
        return;
    }
    add_rows_into(g, y, rows, p);
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn add_rows_avx2(g: &mut [f64], y: &[f64], rows: usize, p: usize) {
    add_rows_into(g, y, rows, p);
}

/// The loop of [`add_rows`] on the column-major `p x p` slice `g`.
#[inline(always)]
fn add_rows_into(g: &mut [f64], y: &[f64], rows: usize, p: usize) {
    for row in y.chunks_exact(p).take(rows) {
        for (a, &ya) in row.iter().enumerate() {
            if ya == 0.0 {
                continue;
            }
            let col = &mut g[a * p + a..(a + 1) * p];
            for (g, yb) in col.iter_mut().zip(&row[a..]) {
                *g += ya * yb;
            }
        }
    }
}

/// Iteration cap of the symmetric eigenvalue solver of the criteria (QL sweeps in all).
const EIGEN_ITERATIONS: usize = 10_000;

/// Singular values of W from the lower triangle of W'W, largest first; all zero when W'W
/// holds a non-finite value or the eigenvalue iteration does not converge within its cap
/// (the criteria are then infinite: such a design is never chosen).
///
/// Only the eigenvalues are computed (Householder tridiagonalisation, then the implicit QL
/// iteration with Wilkinson shifts, no eigenvectors): the criteria need nothing else, and
/// the eigenvectors cost most of a full decomposition (docs/performance.md#excitation).
pub(crate) fn singular_values(gram: &DMatrix<f64>) -> Vec<f64> {
    let n = gram.ncols();
    if gram.iter().any(|v| !v.is_finite()) {
        return vec![0.0; n];
    }
    let Some(mut s) = symmetric_eigenvalues(gram.clone()) else {
        return vec![0.0; n];
    };
    for l in &mut s {
        *l = l.max(0.0).sqrt();
    }
    s.sort_by(|a, b| b.total_cmp(a));
    s
}

/// The eigenvalues of a symmetric matrix given by its lower triangle (unordered); `None`
/// when the QL iteration needs more than [`EIGEN_ITERATIONS`] sweeps. The matrix is scaled
/// by its largest magnitude first, as nalgebra's `SymmetricEigen` does.
pub(crate) fn symmetric_eigenvalues(mut m: DMatrix<f64>) -> Option<Vec<f64>> {
    let n = m.ncols();
    let amax = m.amax();
    if n == 0 || amax == 0.0 {
        return Some(vec![0.0; n]);
    }
    m.unscale_mut(amax);
    let (d, e) = SymmetricTridiagonal::new(m).unpack_tridiagonal();
    let mut d: Vec<f64> = d.iter().copied().collect();
    let mut e: Vec<f64> = e.iter().copied().chain([0.0]).collect();
    let mut sweeps = 0;
    for l in 0..n {
        loop {
            let mut m = l;
            while m + 1 < n {
                let dd = d[m].abs() + d[m + 1].abs();
                if e[m].abs() <= f64::EPSILON * dd {
                    break;
                }
                m += 1;
            }
            if m == l {
                break;
            }
            sweeps += 1;
            if sweeps > EIGEN_ITERATIONS {
                return None;
            }
            // one implicit QL sweep on rows l..=m with the Wilkinson shift
            let mut g = (d[l + 1] - d[l]) / (2.0 * e[l]);
            // the matrix is scaled to magnitudes of at most 1: no hypot needed against
            // overflow (and an infinite g only zeroes the shift's correction)
            let mut r = (g * g + 1.0).sqrt();
            g = d[m] - d[l] + e[l] / (g + r.copysign(g));
            let (mut s, mut c, mut p) = (1.0, 1.0, 0.0);
            let mut deflated = false;
            for i in (l..m).rev() {
                let f = s * e[i];
                let b = c * e[i];
                r = (f * f + g * g).sqrt();
                e[i + 1] = r;
                if r == 0.0 {
                    d[i + 1] -= p;
                    e[m] = 0.0;
                    deflated = true;
                    break;
                }
                s = f / r;
                c = g / r;
                g = d[i + 1] - p;
                r = (d[i] - g) * s + 2.0 * c * b;
                p = s * r;
                d[i + 1] = g + p;
                g = c * r - b;
            }
            if !deflated {
                d[l] -= p;
                e[l] = g;
                e[m] = 0.0;
            }
        }
    }
    d.iter_mut().for_each(|x| *x *= amax);
    Some(d)
}

/// The smallest and the largest eigenvalue of the symmetric tridiagonal matrix with
/// diagonal `d` and off-diagonal `e`, by bisection on Sturm counts from the Gershgorin
/// interval (both searched in one loop, so the two chains of divisions overlap), each to
/// within a few units of roundoff of the matrix's norm: the accuracy of the QL iteration,
/// at a fraction of its cost when only the extremes are needed (the condition number).
pub(crate) fn extreme_eigenvalues(d: &[f64], e: &[f64]) -> (f64, f64) {
    let n = d.len();
    let off = |i: usize| e.get(i).map_or(0.0, |x| x.abs());
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for (i, di) in d.iter().enumerate() {
        let r = off(i) + i.checked_sub(1).map_or(0.0, off);
        lo = lo.min(di - r);
        hi = hi.max(di + r);
    }
    let norm = lo.abs().max(hi.abs());
    if norm == 0.0 {
        return (0.0, 0.0);
    }
    let tol = 4.0 * f64::EPSILON * norm;
    // the smallest pivot allowed, as LAPACK's dstebz: a zero pivot becomes -pivmin
    let pivmin = f64::MIN_POSITIVE * e.iter().fold(1.0f64, |m, x| m.max(x * x));
    // the numbers of eigenvalues below x and below y (LDL' pivots of T - x I, T - y I),
    // in one loop so that the two dependent chains of divisions overlap
    let counts = |x: f64, y: f64| {
        let (mut p, mut q) = (d[0] - x, d[0] - y);
        let (mut below_x, mut below_y) = (usize::from(p < 0.0), usize::from(q < 0.0));
        for i in 1..n {
            let e2 = e[i - 1] * e[i - 1];
            if p.abs() < pivmin {
                p = -pivmin;
            }
            if q.abs() < pivmin {
                q = -pivmin;
            }
            p = d[i] - x - e2 / p;
            q = d[i] - y - e2 / q;
            below_x += usize::from(p < 0.0);
            below_y += usize::from(q < 0.0);
        }
        (below_x, below_y)
    };
    // [a0, b0] brackets the smallest (none below a0, at least one below b0), [a1, b1] the
    // largest (fewer than n below a1, all below b1)
    let (mut a0, mut b0) = (lo - tol, hi + tol);
    let (mut a1, mut b1) = (a0, b0);
    while b0 - a0 > tol || b1 - a1 > tol {
        let (m0, m1) = (0.5 * (a0 + b0), 0.5 * (a1 + b1));
        let (c0, c1) = counts(m0, m1);
        if c0 >= 1 {
            b0 = m0;
        } else {
            a0 = m0;
        }
        if c1 >= n {
            b1 = m1;
        } else {
            a1 = m1;
        }
    }
    (0.5 * (a0 + b0), 0.5 * (a1 + b1))
}

/// sigma_max / sigma_min, infinite when sigma_min is zero.
pub(crate) fn condition_from_singular(s: &[f64]) -> f64 {
    match (s.first(), s.last()) {
        (Some(&hi), Some(&lo)) if lo > 0.0 && lo > hi * 1e-15 => hi / lo,
        _ => f64::INFINITY,
    }
}

/// A criterion's value for W'W (lower triangle) of `samples` samples.
pub(crate) fn cost(gram: &DMatrix<f64>, samples: usize, criterion: Criterion) -> f64 {
    match criterion {
        Criterion::Condition => {
            let n = gram.ncols();
            if n == 0 || gram.iter().any(|v| !v.is_finite()) {
                return f64::INFINITY;
            }
            let amax = gram.amax();
            if amax == 0.0 {
                return f64::INFINITY;
            }
            let (d, e) = SymmetricTridiagonal::new(gram.unscale(amax)).unpack_tridiagonal();
            let (lo, hi) = extreme_eigenvalues(d.as_slice(), e.as_slice());
            // lambda_min known to worse than about eps cond^2 = 2e-6 of itself (cond above
            // 1e5), or within the bisection's resolution of zero (above about 3e7): rank
            // deficiency, or columns of very different scales (rows weighted far apart),
            // which the equilibrated matrix tells apart
            if lo <= DIRECT * hi {
                let cond = scaled_criteria(gram, samples)
                    .map_or(f64::INFINITY, |s| (hi * amax * s.inverse_max).sqrt());
                // the bound of `condition_from_singular`
                return if cond < 1e15 { cond } else { f64::INFINITY };
            }
            condition_from_singular(&[hi.sqrt(), lo.sqrt()])
        }
        Criterion::DOptimal => {
            let s = singular_values(gram);
            let (Some(&first), Some(&last)) = (s.first(), s.last()) else {
                return f64::INFINITY;
            };
            // the smallest eigenvalue blurred by the roundoff of the largest (or not
            // finite): the equilibrated matrix, as for the condition number
            if !(last * last > DIRECT * first * first) {
                return scaled_criteria(gram, samples).map_or(f64::INFINITY, |s| s.d_optimal);
            }
            let k = samples.max(1) as f64;
            -s.iter().map(|x| (x * x / k).ln()).sum::<f64>() / s.len() as f64
        }
    }
}

/// The ratio lambda_min / lambda_max of W'W below which the criteria go through the
/// equilibrated matrix ([`scaled_criteria`]): its eigenvalues, computed directly to about
/// eps lambda_max, give lambda_min to about eps cond(W)^2 of itself, 2e-6 at this ratio
/// (cond(W) = 1e5, a thousand times the condition of a good unweighted design; 10 % at
/// cond 2e7, and nothing at all above about 3e7).
const DIRECT: f64 = 1e-10;

/// The ratio lambda_min / lambda_max of the equilibrated matrix at and below which its
/// columns are taken as dependent (rank deficiency): its eigenvalues' resolution.
const UNRESOLVED: f64 = 4.0 * f64::EPSILON;

/// What [`scaled_criteria`] finds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Scaled {
    /// 1 / lambda_min(W'W), the largest eigenvalue of (W'W)^-1.
    pub(crate) inverse_max: f64,
    /// The D-optimality criterion, -(log det(W'W) - p log K) / p.
    pub(crate) d_optimal: f64,
}

/// The criteria of W'W (lower triangle, `samples` samples) through the equilibrated matrix
/// A = D^-1 W'W D^-1, D = sqrt(diag(W'W)) (unit diagonal): `None` when a column of W is
/// zero or not finite, or when A's own smallest eigenvalue is below [`UNRESOLVED`] times
/// its largest (the columns of W are dependent however they are scaled: rank deficiency).
/// Otherwise A = L L' (Cholesky), lambda_min(W'W) = 1 / lambda_max(D^-1 A^-1 D^-1), the
/// largest eigenvalue being resolved where the smallest is not, and log det(W'W) =
/// 2 sum log L_ii + 2 sum log D_ii: both to a relative accuracy of about eps cond(A),
/// whatever the spread of the column scales (the module documentation). Used only from
/// cond(W) = 1e5 on ([`DIRECT`]), so the criteria of every better-conditioned candidate
/// (every good design) are unchanged to the bit.
pub(crate) fn scaled_criteria(gram: &DMatrix<f64>, samples: usize) -> Option<Scaled> {
    let p = gram.ncols();
    let scale: Vec<f64> = (0..p).map(|i| gram[(i, i)].sqrt()).collect();
    if p == 0 || scale.iter().any(|d| !(*d > 0.0 && d.is_finite())) {
        return None;
    }
    // the lower triangle of W'W holds the values: both triangles of A from it
    let a = DMatrix::from_fn(p, p, |i, j| {
        let (r, c) = if i >= j { (i, j) } else { (j, i) };
        gram[(r, c)] / (scale[r] * scale[c])
    });
    if a.iter().any(|v| !v.is_finite()) {
        return None;
    }
    let (d, e) = SymmetricTridiagonal::new(a.clone()).unpack_tridiagonal();
    let (lo, hi) = extreme_eigenvalues(d.as_slice(), e.as_slice());
    if !(lo > UNRESOLVED * hi) {
        return None;
    }
    let chol = a.cholesky()?;
    let log_det = 2.0
        * chol
            .l_dirty()
            .diagonal()
            .iter()
            .chain(&scale)
            .map(|x| x.ln())
            .sum::<f64>();
    let inverse = chol.inverse();
    let g_inverse = DMatrix::from_fn(p, p, |i, j| inverse[(i, j)] / (scale[i] * scale[j]));
    let amax = g_inverse.amax();
    if !(amax > 0.0 && amax.is_finite()) {
        return None;
    }
    let (d, e) = SymmetricTridiagonal::new(g_inverse.unscale(amax)).unpack_tridiagonal();
    let (_, inverse_hi) = extreme_eigenvalues(d.as_slice(), e.as_slice());
    let inverse_max = inverse_hi * amax;
    let k = samples.max(1) as f64;
    let d_optimal = -(log_det - p as f64 * k.ln()) / p as f64;
    (inverse_max > 0.0 && inverse_max.is_finite() && d_optimal.is_finite()).then_some(Scaled {
        inverse_max,
        d_optimal,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::SymmetricEigen;

    #[test]
    fn condition_of_a_known_matrix() {
        // W = diag(3, 1) stacked with zeros: cond 3
        let mut g = DMatrix::zeros(2, 2);
        add_rows(&mut g, &[3.0, 0.0, 0.0, 1.0, 0.0, 0.0], 3);
        assert!((condition_from_singular(&singular_values(&g)) - 3.0).abs() < 1e-12);
        // a general W against nalgebra's SVD
        let w = DMatrix::from_row_slice(
            4,
            3,
            &[1., 2., 0.5, -1., 0.3, 2., 0.2, -0.7, 1., 3., 1., -1.],
        );
        let mut g = DMatrix::zeros(3, 3);
        add_rows(&mut g, w.as_slice().to_vec().as_slice(), 0);
        let rows: Vec<f64> = (0..4)
            .flat_map(|r| (0..3).map(move |c| (r, c)))
            .map(|(r, c)| w[(r, c)])
            .collect();
        add_rows(&mut g, &rows, 4);
        let svd = w.svd(false, false);
        let want = svd.singular_values.max() / svd.singular_values.min();
        assert!((condition_from_singular(&singular_values(&g)) - want).abs() < 1e-9 * want);
        assert!(cost(&g, 4, Criterion::DOptimal).is_finite());
        assert_eq!(
            cost(&DMatrix::zeros(2, 2), 1, Criterion::Condition),
            f64::INFINITY
        );
    }

    /// The default `Model::run_lanes` equals one run per set, and `add_lanes` gives the
    /// W'W of adding the same samples one by one, to the bit (weights included); lengths
    /// that are not `lanes` times the table's, and zero lanes, are errors.
    #[test]
    fn lanes_give_the_same_information_to_the_bit() {
        use crate::model::ProgramKind;
        use crate::pipeline::tests::synthetic::Synthetic;
        let model = Synthetic::default();
        let n = model.dof();
        let mut rng = crate::rng::Rng::new(3);
        let lanes = 5;
        let states: Vec<[Vec<f64>; 3]> = (0..lanes)
            .map(|_| [(); 3].map(|()| (0..n).map(|_| rng.uniform(-2.0, 2.0)).collect()))
            .collect();
        let lane_major = |s: usize| -> Vec<f64> {
            (0..n * lanes)
                .map(|k| states[k % lanes][s][k / lanes])
                .collect()
        };
        let (q, qd, qdd) = (lane_major(0), lane_major(1), lane_major(2));
        let weights: Vec<f64> = (0..n).map(|j| 1.0 + j as f64 / 3.0).collect();
        let mut one = Information::new(&model).with_weights(&weights);
        for [q, qd, qdd] in &states {
            one.add(&model, q, qd, qdd).unwrap();
        }
        let mut all = Information::new(&model).with_weights(&weights);
        all.add_lanes(&model, lanes, &q, &qd, &qdd).unwrap();
        let bits = |m: &DMatrix<f64>| m.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&all.gram), bits(&one.gram));
        assert_eq!(all.samples, lanes);
        // the weights: joint j's row times weights[j], applied here by hand
        let p = model.base_parameter_count();
        let mut by_hand = DMatrix::zeros(p, p);
        let mut y = vec![0.0; n * p];
        for [q, qd, qdd] in &states {
            model.base_regressor_into(q, qd, qdd, &mut y).unwrap();
            for (row, w) in y.chunks_mut(p).zip(&weights) {
                row.iter_mut().for_each(|v| *v *= w);
            }
            add_rows(&mut by_hand, &y, n);
        }
        assert_eq!(bits(&one.gram), bits(&by_hand));
        // the default run_lanes, gravity: set l's torques at l, l + lanes, ...
        let base: Vec<f64> = (0..model.base_parameter_count())
            .map(|i| 0.1 * i as f64)
            .collect();
        let base_lanes: Vec<f64> = base.iter().flat_map(|b| [*b; 5]).collect();
        let mut tau = vec![0.0; n * lanes];
        model
            .run_lanes(ProgramKind::Gravity, lanes, &[&q, &base_lanes], &mut tau)
            .unwrap();
        for (l, [q, ..]) in states.iter().enumerate() {
            let mut want = vec![0.0; n];
            model.gravity_into(q, &base, &mut want).unwrap();
            let got: Vec<f64> = (0..n).map(|i| tau[i * lanes + l]).collect();
            assert_eq!(got, want);
        }
        let e = all
            .add_lanes(&model, lanes, &q[1..], &qd, &qdd)
            .unwrap_err();
        assert_eq!((e.argument, e.expected), ("q", n * lanes));
        let e = model
            .run_lanes(ProgramKind::Gravity, 0, &[&[], &[]], &mut [])
            .unwrap_err();
        assert_eq!(e.argument, "lanes");
    }

    /// The extreme eigenvalues by bisection against nalgebra's full decomposition, on the
    /// tridiagonal forms of random information matrices of growing condition and on edge
    /// cases; the condition criterion equals the one from every eigenvalue.
    #[test]
    fn extreme_eigenvalues_match_the_full_decomposition() {
        let mut rng = crate::rng::Rng::new(11);
        for (size, spread) in [
            (1, 1.0f64),
            (2, 1.0),
            (5, 10.0),
            (12, 1e2),
            (48, 1e3),
            (60, 1e4),
        ] {
            let rows = 3 * size;
            let w: Vec<f64> = (0..rows * size)
                .map(|i| rng.normal() * spread.powf((i % size) as f64 / size as f64))
                .collect();
            let mut g = DMatrix::zeros(size, size);
            add_rows(&mut g, &w, rows);
            let full = g.clone().lower_triangle() + g.clone().lower_triangle().transpose()
                - DMatrix::from_diagonal(&g.diagonal());
            let all = SymmetricEigen::new(full.clone()).eigenvalues;
            let (want_lo, want_hi) = (all.min(), all.max());
            let (d, e) = SymmetricTridiagonal::new(full).unpack_tridiagonal();
            let (lo, hi) = extreme_eigenvalues(d.as_slice(), e.as_slice());
            // measured: 3e-16 of the largest at most
            assert!(
                (lo - want_lo).abs() <= 1e-14 * want_hi,
                "{size}: {lo} {want_lo}"
            );
            assert!(
                (hi - want_hi).abs() <= 1e-14 * want_hi,
                "{size}: {hi} {want_hi}"
            );
            let by_all = condition_from_singular(&singular_values(&g));
            let fast = cost(&g, rows, Criterion::Condition);
            // both find lambda_min to a few eps lambda_max, so cond agrees to about
            // eps cond^2 relative (measured: 9.2e-9 at cond 1.2e4, the bound 1.2e-7)
            assert!(
                (fast - by_all).abs() <= 4.0 * f64::EPSILON * by_all * by_all * by_all,
                "{size}: {fast} {by_all}"
            );
        }
        assert_eq!(extreme_eigenvalues(&[0.0; 3], &[0.0; 2]), (0.0, 0.0));
        let (lo, hi) = extreme_eigenvalues(&[2.0, 5.0, 2.0, 1.0], &[0.0; 3]);
        assert!((lo - 1.0).abs() <= 20.0 * f64::EPSILON && (hi - 5.0).abs() <= 20.0 * f64::EPSILON);
        // a singular W'W: infinite condition
        let mut g = DMatrix::zeros(3, 3);
        add_rows(&mut g, &[1.0, 2.0, 3.0, 2.0, 4.0, 6.0], 2);
        assert_eq!(cost(&g, 2, Criterion::Condition), f64::INFINITY);
    }

    /// Rows weighted 1e6 apart (`--sigma 1e-6,1`): cond(W) near 1e8, beyond what the
    /// eigenvalues of W'W resolve directly, which made both criteria infinite for every
    /// trajectory. Through the equilibrated matrix both match W's SVD; columns that are
    /// dependent stay infinitely bad, however their rows are weighted.
    #[test]
    fn criteria_resolve_rows_weighted_far_apart() {
        let mut rng = crate::rng::Rng::new(5);
        let (p, rows) = (6, 40);
        // joint 1's rows (even), weighted 1e6, do not see the last two parameters; joint
        // 2's rows (odd), weighted 1, see all
        let w: Vec<f64> = (0..rows * p)
            .map(|i| {
                let (r, c) = (i / p, i % p);
                match (r % 2, c) {
                    (0, c) if c >= p - 2 => 0.0,
                    (0, _) => 1e6 * rng.normal(),
                    _ => rng.normal(),
                }
            })
            .collect();
        let criteria = |w: &[f64]| {
            let mut g = DMatrix::zeros(p, p);
            add_rows(&mut g, w, rows);
            let svd = DMatrix::from_row_slice(rows, p, w).svd(false, false);
            let s = svd.singular_values;
            let want_d = -s.iter().map(|x| (x * x / rows as f64).ln()).sum::<f64>() / p as f64;
            (
                cost(&g, rows, Criterion::Condition),
                s.max() / s.min(),
                cost(&g, rows, Criterion::DOptimal),
                want_d,
            )
        };
        let (cond, want, d, want_d) = criteria(&w);
        // beyond what the direct computation resolves well (2e6: it was off by about 1e-3)
        assert!(want > 1e6, "{want}");
        eprintln!(
            "cond {cond:e} (SVD {want:e}), D {d} (SVD {want_d}): {:e}, {:e} relative",
            (cond - want).abs() / want,
            (d - want_d).abs() / want_d.abs()
        );
        // measured: 4.7e-16 and 2.0e-16 relative (the direct computation: about 1e-3)
        assert!((cond - want).abs() < 1e-12 * want, "{cond} vs {want}");
        assert!((d - want_d).abs() < 1e-12 * want_d.abs(), "{d} vs {want_d}");
        // the last parameter a copy of the one before it: rank deficient, weighted or not
        let mut copy = w.clone();
        for r in 0..rows {
            copy[r * p + p - 1] = copy[r * p + p - 2];
        }
        let (cond, _, d, _) = criteria(&copy);
        assert_eq!((cond, d), (f64::INFINITY, f64::INFINITY));
        // a column never excited
        let mut zero = w;
        for r in 0..rows {
            zero[r * p + 1] = 0.0;
        }
        let (cond, _, d, _) = criteria(&zero);
        assert_eq!((cond, d), (f64::INFINITY, f64::INFINITY));
    }

    /// The eigenvalue-only solver against nalgebra's full decomposition, on random
    /// information matrices W'W of growing condition (columns scaled by up to 1e4) and on
    /// edge cases (zero, 1 x 1, diagonal, repeated eigenvalues).
    #[test]
    fn eigenvalues_match_the_full_decomposition() {
        let mut rng = crate::rng::Rng::new(7);
        for (size, spread) in [
            (1, 1.0f64),
            (2, 1.0),
            (5, 10.0),
            (12, 1e2),
            (48, 1e3),
            (60, 1e4),
        ] {
            let rows = 3 * size;
            let w: Vec<f64> = (0..rows * size)
                .map(|i| rng.normal() * spread.powf((i % size) as f64 / size as f64))
                .collect();
            let mut g = DMatrix::zeros(size, size);
            add_rows(&mut g, &w, rows);
            let full = g.clone().lower_triangle() + g.clone().lower_triangle().transpose()
                - DMatrix::from_diagonal(&g.diagonal());
            let mut want: Vec<f64> = SymmetricEigen::new(full)
                .eigenvalues
                .iter()
                .copied()
                .collect();
            let mut got = symmetric_eigenvalues(g).unwrap();
            want.sort_by(f64::total_cmp);
            got.sort_by(f64::total_cmp);
            let top = want[size - 1];
            for (a, b) in got.iter().zip(&want) {
                assert!((a - b).abs() <= 1e-12 * top, "{size}: {got:?} {want:?}");
            }
        }
        assert_eq!(
            symmetric_eigenvalues(DMatrix::zeros(3, 3)),
            Some(vec![0.0; 3])
        );
        let d = DMatrix::from_diagonal(&nalgebra::DVector::from_vec(vec![2.0, 5.0, 2.0, 1.0]));
        let mut e = symmetric_eigenvalues(d).unwrap();
        e.sort_by(f64::total_cmp);
        assert_eq!(e, vec![1.0, 2.0, 2.0, 5.0]);
    }
}
