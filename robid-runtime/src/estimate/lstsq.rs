//! Least squares by QR then SVD of R, never by normal equations.
//!
//! The columns of W are scaled to unit norm first (W = W_s D, D = diag of the column
//! norms) and y to unit norm, so that neither the QR nor the SVD sees the magnitudes of
//! the data (a sample of 1e200 once made the SVD loop for ever): every entry they see is
//! at most 1.
//!
//! [W_s y_s] = Q R_a (Householder), with R_a = [[R, z], [0, rho]]: z = Q'y_s (first n
//! entries). R = U S V' (nalgebra's `try_svd`, capped at
//! [`SVD_ITERATIONS`](crate::limits::SVD_ITERATIONS)). The rank is decided on the
//! singular values of the scaled W with a relative threshold (a parameter's unit does not
//! make it unidentifiable), gamma = V S^-1 U' z, and exactly unscaled: beta = |y| D^-1
//! gamma, (W'W)^-1 = D^-1 V S^-2 V' D^-1. The condition number reported is that of W
//! itself (the singular values of R D), and beside it that of W with unit-norm columns
//! (the singular values of R), which does not depend on the parameters' units.
//!
//! The QR runs on blocks of rows in parallel (tall-skinny QR): each block's R, then the
//! R factors stacked and factorised again. It is the same R (up to row signs) as one QR
//! of the whole matrix, stays in cache, and never copies W whole.

use crate::EstimateError;
use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;

use crate::error::{Error, Result};
use crate::limits::SVD_ITERATIONS;

/// Rows per block of the tall-skinny QR.
const BLOCK: usize = 1024;

/// The upper-triangular factor of `a` (at least `a.ncols()` rows, padded with zeros).
fn r_factor(a: DMatrix<f64>) -> DMatrix<f64> {
    let (m, n) = a.shape();
    let a = if m < n {
        a.resize_vertically(n, 0.0)
    } else {
        a
    };
    a.qr().r()
}

/// R of the tall matrix [W D^-1, y / y_scale] ((cols + 1) x (cols + 1), upper
/// triangular), by blocks: each block's R, then the blocks' factors stacked two by two
/// in a fixed tree (block 2k with 2k + 1, then the pairs' results two by two), so that the
/// result does not depend on how the threads took the work (a `reduce_with` paired them as
/// the scheduling fell: two runs of one binary differed by up to 6e-11 of a parameter's
/// deviation).
fn augmented_r(w: &DMatrix<f64>, y: &DVector<f64>, d: &[f64], y_scale: f64) -> DMatrix<f64> {
    let (m, n) = w.shape();
    let blocks = m.div_ceil(BLOCK).max(1);
    let stack = |a: &DMatrix<f64>, b: &DMatrix<f64>| {
        let mut s = DMatrix::zeros(a.nrows() + b.nrows(), n + 1);
        s.view_mut((0, 0), a.shape()).copy_from(a);
        s.view_mut((a.nrows(), 0), b.shape()).copy_from(b);
        r_factor(s)
    };
    let mut factors: Vec<DMatrix<f64>> = (0..blocks)
        .into_par_iter()
        .map(|b| {
            let (lo, hi) = (b * BLOCK, ((b + 1) * BLOCK).min(m));
            let mut a = DMatrix::zeros(hi - lo, n + 1);
            for (j, dj) in d.iter().enumerate() {
                let src = w.view((lo, j), (hi - lo, 1));
                for (dst, v) in a.column_mut(j).iter_mut().zip(src.iter()) {
                    *dst = v / dj;
                }
            }
            for (dst, v) in a.column_mut(n).iter_mut().zip(y.rows(lo, hi - lo).iter()) {
                *dst = v / y_scale;
            }
            r_factor(a)
        })
        .collect();
    while factors.len() > 1 {
        factors = factors
            .par_chunks(2)
            .map(|pair| match pair {
                [a, b] => stack(a, b),
                [a, ..] => a.clone(),
                [] => DMatrix::zeros(n + 1, n + 1),
            })
            .collect();
    }
    factors
        .pop()
        .unwrap_or_else(|| DMatrix::zeros(n + 1, n + 1))
}

/// The 2-norm of `x` without overflow or underflow (scaled by the largest magnitude).
pub(crate) fn norm(x: impl Iterator<Item = f64> + Clone) -> f64 {
    let big = x.clone().fold(0.0f64, |m, v| m.max(v.abs()));
    if big == 0.0 || !big.is_finite() {
        return big;
    }
    big * x.map(|v| (v / big) * (v / big)).sum::<f64>().sqrt()
}

/// `(W'W)^-1` kept as `D^-1 A D^-1`: `A` that of W with its columns scaled to unit norm,
/// `D` the column scales. Unscaled, the entries of a column near 1e200 underflow to 0
/// (its standard deviation came out 0, 0 % of its value); the statistics take `A` and `D`
/// apart ([`root_diagonal`](Self::root_diagonal), the robust deviations' scores).
#[derive(Debug, Clone)]
pub(crate) struct InverseGram {
    /// `A = (W_s'W_s)^-1` with `W_s = W D^-1`.
    pub(crate) scaled: DMatrix<f64>,
    /// `D` (1 for an unscaled matrix).
    pub(crate) scales: Vec<f64>,
}

impl InverseGram {
    /// An inverse Gram matrix given unscaled (`D = I`; RLS's and link-by-link's `P`).
    pub(crate) fn unscaled(p: DMatrix<f64>) -> Self {
        let scales = vec![1.0; p.nrows()];
        Self { scaled: p, scales }
    }

    /// `(W'W)^-1` formed whole (tests compare it with a direct inverse).
    #[cfg(test)]
    pub(crate) fn whole(&self) -> DMatrix<f64> {
        let n = self.scales.len();
        DMatrix::from_fn(n, n, |i, j| {
            self.scaled[(i, j)] / self.scales[i] / self.scales[j]
        })
    }

    /// `sqrt((W'W)^-1_jj) = sqrt(A_jj) / d_j` of each parameter (a rounding below 0 is 0).
    pub(crate) fn root_diagonal(&self) -> Vec<f64> {
        self.scales
            .iter()
            .enumerate()
            .map(|(j, d)| self.scaled[(j, j)].max(0.0).sqrt() / d)
            .collect()
    }
}

/// A full-rank least-squares solution with what the statistics need.
#[derive(Debug, Clone)]
pub(crate) struct Solution {
    pub(crate) beta: DVector<f64>,
    /// (W'W)^-1 with the column scales apart (formed whole, its entries of a column near
    /// 1e200 underflow to 0).
    pub(crate) inverse: InverseGram,
    pub(crate) condition_number: f64,
    /// The condition number of W with its columns scaled to unit norm
    /// ([`scaled_condition`]): the figure that does not depend on the parameters' units.
    pub(crate) scaled_condition_number: f64,
    /// The column scales D (the column norms of W, 1 for a zero column).
    pub(crate) scales: Vec<f64>,
    /// `S^-1 V'` of the scaled R = U S V': `T'T = (W_s'W_s)^-1` with `W_s = W D^-1`, which
    /// the leverages are taken with ([`Solution::leverage`]).
    scaled_root: DMatrix<f64>,
}

impl Solution {
    /// Both condition numbers.
    pub(crate) fn condition(&self) -> Condition {
        Condition {
            raw: self.condition_number,
            scaled: self.scaled_condition_number,
        }
    }

    /// The leverages of the rows of `x` summed, `tr(X (W'W)^-1 X')`, with column j of `x`
    /// in units of `units[j]` (the rows are `x diag(units)`): taken in the scaled space
    /// the solver factors, `sum_i ||S^-1 V' D^-1 x_i||^2`, never through `(W'W)^-1`, whose
    /// entries of a column near 1e200 underflow to 0 (a joint's leverage then came out
    /// about 1 too small, and its WLS sigma biased low).
    pub(crate) fn leverage(&self, x: nalgebra::DMatrixView<'_, f64>, units: &[f64]) -> f64 {
        let mut scaled = x.into_owned();
        for (j, mut c) in scaled.column_iter_mut().enumerate() {
            c.scale_mut(units[j] / self.scales[j]);
        }
        (scaled * self.scaled_root.transpose()).norm_squared()
    }

    /// `sqrt(x (W'W)^-1 x')` of a combination `x` of the parameters (what a deviation of 1
    /// in the residual gives it), taken as `||S^-1 V' D^-1 x'||` with the overflow-safe
    /// [`norm`]: through `(W'W)^-1`, or a sum of squares, a column near 1e200 gave 0.
    pub(crate) fn root_quadratic(&self, x: &[f64]) -> f64 {
        let scaled =
            DVector::from_iterator(x.len(), x.iter().zip(&self.scales).map(|(v, d)| v / d));
        norm((&self.scaled_root * scaled).iter().copied())
    }
}

/// The column norms of `w` (the scaling D), 1 for an all-zero column: such a column stays
/// zero after scaling and the SVD reports it with the other unexcited directions (an
/// early return on zero columns alone would understate the rank deficiency when other
/// columns are dependent too). A non-finite entry is an error naming its row and column.
pub(crate) fn column_scales(w: &DMatrix<f64>, names: &[String]) -> Result<Vec<f64>> {
    let name = |j: usize| {
        names
            .get(j)
            .cloned()
            .unwrap_or_else(|| format!("column {}", j + 1))
    };
    if let Some(i) = w.iter().position(|v| !v.is_finite()) {
        let (r, c) = (i % w.nrows().max(1), i / w.nrows().max(1));
        return Err(Error::Estimate(EstimateError::NonFiniteObservation {
            location: format!("equation {}", r + 1),
            sample: None,
            joint: 0,
            parameter: name(c),
            value: w[(r, c)],
        }));
    }
    Ok(w.column_iter()
        .map(|c| norm(c.iter().copied()))
        .map(|d| if d == 0.0 { 1.0 } else { d })
        .collect())
}

/// Capped SVD of a small square matrix.
fn svd(
    r: DMatrix<f64>,
    vectors: bool,
    what: &str,
) -> Result<nalgebra::SVD<f64, nalgebra::Dyn, nalgebra::Dyn>> {
    r.try_svd(vectors, vectors, f64::EPSILON, SVD_ITERATIONS)
        .ok_or_else(|| Error::NoConvergence {
            what: format!("the SVD of {what}"),
            iterations: SVD_ITERATIONS,
            hint: "the data hold values of wildly different magnitudes; check them for outliers",
        })
}

/// Solves min ||y - W beta||; `tolerance` is relative to the largest singular value of the
/// column-scaled W. Rank-deficient W is an error naming the parameters in the unexcited
/// directions.
pub(crate) fn solve(
    w: &DMatrix<f64>,
    y: &DVector<f64>,
    names: &[String],
    tolerance: f64,
) -> Result<Solution> {
    let (m, n) = w.shape();
    // as many equations as parameters fit any data exactly: no residual is left for the
    // standard deviations
    if m < super::equations_needed(n) || n == 0 {
        return Err(Error::TooFewSamples {
            context: format!("least squares with {n} parameters"),
            found: m,
            required: n + 1,
            hint: "use more data, less decimation, or fewer parameters",
        });
    }
    let d = column_scales(w, names)?;
    if let Some(r) = y.iter().position(|v| !v.is_finite()) {
        return Err(Error::Estimate(EstimateError::NonFiniteObservation {
            location: format!("equation {}", r + 1),
            sample: None,
            joint: 0,
            parameter: "torque".into(),
            value: y[r],
        }));
    }
    let y_norm = norm(y.iter().copied());
    let y_scale = if y_norm > 0.0 { y_norm } else { 1.0 };
    let ra = augmented_r(w, y, &d, y_scale);
    solve_factor(&ra, &d, y_scale, names, tolerance)
}

/// Solves from `ra`, the R factor ((n + 1) x (n + 1), upper triangular) of
/// [W D^-1, y / y_scale] with D = `d` the column norms of W (1 for a zero column): the
/// second half of [`solve`], shared with the streaming accumulator
/// ([`crate::estimate::StreamingLeastSquares`]), which builds the factor block by block.
/// The caller has checked that there are at least n equations.
pub(crate) fn solve_factor(
    ra: &DMatrix<f64>,
    d: &[f64],
    y_scale: f64,
    names: &[String],
    tolerance: f64,
) -> Result<Solution> {
    let n = d.len();
    let r = ra.view((0, 0), (n, n)).into_owned();
    let qty = ra.view((0, n), (n, 1)).into_owned();
    let svd_s = svd(r.clone(), true, "the scaled observation matrix")?;
    let (Some(u), Some(vt)) = (svd_s.u.as_ref(), svd_s.v_t.as_ref()) else {
        return Err(Error::Singular {
            what: "observation matrix (SVD failed)".into(),
            hint: "check the data for extreme values",
        });
    };
    let s = &svd_s.singular_values;
    let smax = s.max();
    let cut = tolerance * smax;
    let null: Vec<usize> = (0..n).filter(|&k| !(s[k] > cut)).collect();
    if !(smax > 0.0) || !null.is_empty() {
        return Err(Error::Estimate(EstimateError::RankDeficient {
            rank: n - null.len(),
            columns: n,
            unexcited: unexcited(vt, &null, names),
        }));
    }
    let uty = u.transpose() * qty;
    let scaled = DVector::from_iterator(n, (0..n).map(|k| uty[k] / s[k]));
    let v = vt.transpose();
    let gamma = &v * scaled;
    let beta = DVector::from_iterator(n, (0..n).map(|j| gamma[j] * y_scale / d[j]));
    let mut scaled_root = vt.clone();
    for k in 0..n {
        scaled_root.row_mut(k).scale_mut(1.0 / s[k]);
    }
    let inverse = InverseGram {
        scaled: scaled_root.transpose() * &scaled_root,
        scales: d.to_vec(),
    };
    let condition_number = condition(&r, u, &svd_s.singular_values, vt, d)?;
    if beta
        .iter()
        .chain(inverse.root_diagonal().iter())
        .any(|v| !v.is_finite())
    {
        return Err(Error::NonFiniteResult {
            what: "the least-squares solution".into(),
            cause: format!(
                "the columns of the observation matrix span magnitudes too different to unscale (condition number {condition_number:e}); check the data for outliers and the parameters' units"
            ),
        });
    }
    Ok(Solution {
        beta,
        inverse,
        condition_number,
        scaled_condition_number: scaled_condition(s)?,
        scales: d.to_vec(),
        scaled_root,
    })
}

/// cond(W) = ||R D|| ||(R D)^-1|| from the R factor of the column-scaled W (R = U S V')
/// and the scales D. Both norms are largest singular values, which an SVD computes to
/// full relative accuracy, and (R D)^-1 = D^-1 V S^-1 U' is formed from the well-scaled
/// factors, so the condition number is right even where it is far beyond 1 / epsilon.
fn condition(
    r: &DMatrix<f64>,
    u: &DMatrix<f64>,
    s: &DVector<f64>,
    vt: &DMatrix<f64>,
    d: &[f64],
) -> Result<f64> {
    let n = d.len();
    let mut rd = r.clone();
    for (j, dj) in d.iter().enumerate() {
        rd.column_mut(j).scale_mut(*dj);
    }
    let mut inv = vt.transpose();
    for k in 0..n {
        inv.column_mut(k).scale_mut(1.0 / s[k]);
    }
    let mut inv = inv * u.transpose();
    for (i, di) in d.iter().enumerate() {
        inv.row_mut(i).scale_mut(1.0 / di);
    }
    let largest = |m: DMatrix<f64>| -> Result<f64> {
        Ok(svd(m, false, "the observation matrix")?
            .singular_values
            .max())
    };
    let cond = largest(rd)? * largest(inv)?;
    if cond.is_finite() {
        Ok(cond.max(1.0))
    } else {
        Err(Error::NonFiniteResult {
            what: "the condition number of the observation matrix".into(),
            cause: "the parameters' columns differ by more than the floating-point range: check the data and the parameters' units".into(),
        })
    }
}

/// The condition numbers of an observation matrix W.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Condition {
    /// Of W itself, `s_max / s_min` (what reports call `cond(W)`, and Milella's error bound
    /// takes): it depends on the parameters' units.
    pub(crate) raw: f64,
    /// Of W with its columns scaled to unit norm ([`scaled_condition`]): the same in any
    /// units of the parameters.
    pub(crate) scaled: f64,
}

/// `s_max / s_min` of the singular values `s` of R of the column-scaled W (the singular
/// values of W with its columns scaled to unit norm, which the solver factors), at least
/// 1; an error when it overflows (a smallest singular value below the floating-point
/// range).
fn scaled_condition(s: &DVector<f64>) -> Result<f64> {
    let cond = s.max() / s.min();
    if cond.is_finite() {
        Ok(cond.max(1.0))
    } else {
        Err(Error::NonFiniteResult {
            what: "the condition number of the column-scaled observation matrix".into(),
            cause: "its smallest singular value is below the floating-point range: the columns are dependent; use a richer trajectory".into(),
        })
    }
}

/// The condition numbers of W, raw and with unit-norm columns (column scaling, QR, the
/// capped SVD of the scaled R, see [`solve`]).
pub(crate) fn condition_number(w: &DMatrix<f64>, names: &[String]) -> Result<Condition> {
    let n = w.ncols();
    let d = column_scales(w, names)?;
    let ra = augmented_r(w, &DVector::zeros(w.nrows()), &d, 1.0);
    let r = ra.view((0, 0), (n, n)).into_owned();
    let f = svd(r.clone(), true, "the scaled observation matrix")?;
    let (Some(u), Some(vt)) = (f.u.as_ref(), f.v_t.as_ref()) else {
        return Err(Error::Singular {
            what: "observation matrix (SVD failed)".into(),
            hint: "check the data for extreme values",
        });
    };
    let null: Vec<usize> = (0..n).filter(|&k| !(f.singular_values[k] > 0.0)).collect();
    if !null.is_empty() {
        return Err(Error::Estimate(EstimateError::RankDeficient {
            rank: n - null.len(),
            columns: n,
            unexcited: unexcited(vt, &null, names),
        }));
    }
    Ok(Condition {
        raw: condition(&r, u, &f.singular_values, vt, &d)?,
        scaled: scaled_condition(&f.singular_values)?,
    })
}

/// Parameters sorted by their weight in the null-space directions (weight > 1e-3).
fn unexcited(vt: &DMatrix<f64>, null: &[usize], names: &[String]) -> Vec<String> {
    let n = vt.ncols();
    let mut weight: Vec<(f64, usize)> = (0..n)
        .map(|i| (null.iter().map(|&k| vt[(k, i)].powi(2)).sum::<f64>(), i))
        .collect();
    weight.sort_by(|a, b| b.0.total_cmp(&a.0));
    weight
        .into_iter()
        .filter(|(w, _)| *w > 1e-3)
        .map(|(_, i)| {
            names
                .get(i)
                .cloned()
                .unwrap_or_else(|| format!("column {}", i + 1))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The scaled norm is the 2-norm, also where the squares overflow or underflow.
    #[test]
    fn the_norm_neither_overflows_nor_underflows() {
        for scale in [1.0, 1e300, 1e-300] {
            let n = norm([3.0 * scale, -4.0 * scale].into_iter());
            assert!((n / (5.0 * scale) - 1.0).abs() < 1e-15, "{scale}: {n}");
        }
        assert_eq!(norm([0.0, 0.0].into_iter()), 0.0);
    }

    /// A block with fewer rows than columns (the last block of a record) is padded to a
    /// square factor, which equals the factor of the rows themselves (R' R = A' A).
    #[test]
    fn a_short_block_gives_a_square_factor() {
        let a = DMatrix::from_row_slice(2, 3, &[1.0, 2.0, 3.0, 0.0, 4.0, 5.0]);
        let r = r_factor(a.clone());
        assert_eq!(r.shape(), (3, 3));
        let gram = r.transpose() * &r - a.transpose() * &a;
        assert!(gram.amax() < 1e-12, "{gram}");
    }

    /// The factor of many blocks is the same to the bit whatever the number of threads
    /// and however they take the work (the blocks paired in a fixed tree).
    #[test]
    fn the_factor_does_not_depend_on_the_threads() {
        let mut rng = crate::rng::Rng::new(7);
        let (m, n) = (37 * BLOCK + 17, 9);
        let w = DMatrix::from_fn(m, n, |_, j| rng.normal() * (j + 1) as f64);
        let y = DVector::from_fn(m, |_, _| rng.normal());
        let d: Vec<f64> = (1..=n).map(|j| j as f64).collect();
        let factor = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            // several times each: the work is taken differently from run to run
            (0..4)
                .map(|_| pool.install(|| augmented_r(&w, &y, &d, 2.0)))
                .collect::<Vec<_>>()
        };
        let one = factor(1).remove(0);
        for threads in [1, 2, 3, 8] {
            for r in factor(threads) {
                assert_eq!(r, one, "{threads} threads");
            }
        }
    }

    fn names(n: usize) -> Vec<String> {
        (1..=n).map(|i| format!("p{i}")).collect()
    }

    #[test]
    fn exact_solution_and_inverse_gram() {
        let w = DMatrix::from_row_slice(4, 2, &[1.0, 0.0, 1.0, 1.0, 1.0, 2.0, 1.0, 3.0]);
        let y = DVector::from_vec(vec![1.0, 3.0, 5.0, 7.0]);
        let s = solve(&w, &y, &names(2), 1e-12).unwrap();
        assert!((s.beta[0] - 1.0).abs() < 1e-12 && (s.beta[1] - 2.0).abs() < 1e-12);
        let g = (w.transpose() * &w).try_inverse().unwrap();
        assert!((g - s.inverse.whole()).norm() < 1e-12);
        // W'W = [[4, 6], [6, 14]] has the eigenvalues 9 +- sqrt(61): cond(W) = 3.759
        let want = ((9.0 + 61f64.sqrt()) / (9.0 - 61f64.sqrt())).sqrt();
        assert!(
            (s.condition_number - want).abs() < 1e-12 * want,
            "{}",
            s.condition_number
        );
    }

    #[test]
    fn rank_deficiency_names_the_unexcited_parameters() {
        // column 3 is never excited, columns 1 and 2 are fine (one equation more than
        // parameters: as many are refused before the rank is known)
        let w = DMatrix::from_row_slice(
            4,
            3,
            &[1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 2.0, 1.0, 0.0],
        );
        let y = DVector::from_vec(vec![1.0, 2.0, 3.0, 4.0]);
        match solve(&w, &y, &names(3), 1e-10) {
            Err(Error::Estimate(EstimateError::RankDeficient {
                rank: 2,
                columns: 3,
                unexcited,
            })) => assert_eq!(unexcited, vec!["p3"]),
            other => panic!("{other:?}"),
        }
        // two identical columns: both named
        let w = DMatrix::from_row_slice(4, 2, &[1.0, 1.0, 2.0, 2.0, 3.0, 3.0, 4.0, 4.0]);
        match solve(&w, &y, &names(2), 1e-10) {
            Err(Error::Estimate(EstimateError::RankDeficient { unexcited, .. })) => {
                assert_eq!(unexcited.len(), 2)
            }
            other => panic!("{other:?}"),
        }
        // a zero column and two dependent ones: rank 1 of 3, all three named (zero columns
        // alone would give rank 2 and name only the zero one)
        let w = DMatrix::from_row_slice(
            4,
            3,
            &[1.0, 0.0, 2.0, 2.0, 0.0, 4.0, 3.0, 0.0, 6.0, 4.0, 0.0, 8.0],
        );
        match solve(&w, &y, &names(3), 1e-10) {
            Err(Error::Estimate(EstimateError::RankDeficient {
                rank,
                columns,
                mut unexcited,
            })) => {
                unexcited.sort();
                assert_eq!((rank, columns), (1, 3));
                assert_eq!(unexcited, vec!["p1", "p2", "p3"]);
            }
            other => panic!("{other:?}"),
        }
    }

    /// The rank tolerance is relative to the largest singular value: two unit columns at
    /// an angle t have singular values sqrt(1 +- cos t), and the system is refused exactly
    /// when the smaller one falls below tolerance x the larger (a third, zero equation
    /// changes neither).
    #[test]
    fn the_rank_tolerance_is_relative_to_the_largest_singular_value() {
        let t: f64 = 1e-3;
        let w = DMatrix::from_row_slice(3, 2, &[1.0, t.cos(), 0.0, t.sin(), 0.0, 0.0]);
        let y = DVector::from_vec(vec![1.0, 2.0, 0.0]);
        let ratio = ((1.0 - t.cos()) / (1.0 + t.cos())).sqrt();
        assert!(solve(&w, &y, &names(2), 0.8 * ratio).is_ok());
        assert!(matches!(
            solve(&w, &y, &names(2), 1.25 * ratio),
            Err(Error::Estimate(EstimateError::RankDeficient {
                rank: 1,
                ..
            }))
        ));
    }

    /// The torques are scaled by their norm for the factorisation: torques of 1e300 give
    /// parameters of 1e300, and all-zero torques give zero parameters (a zero norm is not
    /// divided by).
    #[test]
    fn the_torques_scale_out() {
        let w = DMatrix::from_row_slice(3, 2, &[1.0, 0.0, 0.0, 1.0, 1.0, 1.0]);
        let y = DVector::from_vec(vec![1.0, 2.0, 3.0]);
        let one = solve(&w, &y, &names(2), 1e-12).unwrap().beta;
        let big = solve(&w, &(&y * 1e300), &names(2), 1e-12).unwrap().beta;
        for (a, b) in one.iter().zip(big.iter()) {
            assert!((b / 1e300 - a).abs() < 1e-14 * a.abs(), "{one} vs {big}");
        }
        let zero = solve(&w, &DVector::zeros(3), &names(2), 1e-12).unwrap();
        assert_eq!(zero.beta.as_slice(), [0.0, 0.0]);
    }

    #[test]
    fn blocked_qr_equals_one_qr_on_a_tall_system() {
        let m = 3 * BLOCK + 17;
        let w = DMatrix::from_fn(m, 4, |i, j| ((i * (j + 3)) as f64 * 0.37).sin() + j as f64);
        let beta = DVector::from_vec(vec![1.0, -2.0, 0.5, 3.0]);
        let noise = DVector::from_fn(m, |i, _| 1e-3 * ((i * 7919) as f64).cos());
        let y = &w * &beta + noise;
        let s = solve(&w, &y, &names(4), 1e-12).unwrap();
        let reference = w.clone().svd(true, true).solve(&y, 1e-14).unwrap();
        assert!(
            (&s.beta - &reference).norm() < 1e-10,
            "{} vs {reference}",
            s.beta
        );
        let g = (w.transpose() * &w).try_inverse().unwrap();
        assert!((g - s.inverse.whole()).norm() < 1e-10);
        let reference = w.singular_values();
        let want = reference.max() / reference.min();
        assert!((s.condition_number - want).abs() < 1e-9 * want);
        assert!((condition_number(&w, &names(4)).unwrap().raw - want).abs() < 1e-9 * want);
        // with unit-norm columns: the singular values of W D^-1, by SVD of W itself, the same
        // from `solve` and `condition_number`, and unchanged by a column in other units
        let unit = |w: &DMatrix<f64>| {
            let mut u = w.clone();
            for mut c in u.column_iter_mut() {
                let n = c.norm();
                c /= n;
            }
            let s = u.singular_values();
            s.max() / s.min()
        };
        let scaled = unit(&w);
        assert!((s.scaled_condition_number - scaled).abs() < 1e-10 * scaled);
        let mut other = w.clone();
        other.column_mut(1).scale_mut(1e-6);
        let c = condition_number(&other, &names(4)).unwrap();
        assert!((c.scaled - scaled).abs() < 1e-10 * scaled, "{c:?}");
        assert!(c.raw > 1e3 * want, "{c:?} against {want}");
    }

    /// One entry of 1e200 among values of order 1 (the sample that once hung the SVD):
    /// the scaled problem is solved, and the solution is the exact one.
    #[test]
    fn a_huge_entry_is_solved_not_looped_on() {
        let m = 200;
        let mut w = DMatrix::from_fn(m, 3, |i, j| {
            ((i * (j + 2)) as f64 * 0.71).sin() + 0.1 * j as f64
        });
        w[(17, 1)] = 1e200;
        let beta = DVector::from_vec(vec![2.0, 3e-200, -1.0]);
        let y = &w * &beta;
        let s = solve(&w, &y, &names(3), 1e-12).unwrap();
        assert!(
            (s.beta[0] - 2.0).abs() < 1e-9 && (s.beta[2] + 1.0).abs() < 1e-9,
            "{}",
            s.beta
        );
        assert!((s.beta[1] / 3e-200 - 1.0).abs() < 1e-9, "{}", s.beta);
        // measured 1.0e199
        assert!(s.condition_number.is_finite() && s.condition_number > 5.1e198);
        // the statistics: sqrt((W'W)^-1) of the middle parameter is of order 1e-200, never
        // 0 nor NaN
        let root = s.inverse.root_diagonal();
        assert!(root.iter().all(|v| v.is_finite() && *v > 0.0), "{root:?}");
        // a non-finite entry names its row and column
        w[(5, 2)] = f64::INFINITY;
        match solve(&w, &y, &names(3), 1e-12) {
            Err(Error::Estimate(EstimateError::NonFiniteObservation {
                location,
                parameter,
                ..
            })) => {
                assert_eq!(
                    (location.as_str(), parameter.as_str()),
                    ("equation 6", "p3")
                )
            }
            other => panic!("{other:?}"),
        }
    }

    /// `sqrt(x (W'W)^-1 x')` of a combination with a column near 1e200 (what the known
    /// parameters' expansion takes for a folded parameter) is that of the problem in units,
    /// scaled: formed through `(W'W)^-1` whole it was 0. Against a direct inverse on the
    /// problem in units, to 1e-10.
    #[test]
    fn a_combination_of_a_huge_column_keeps_its_spread() {
        let m = 50;
        let w = DMatrix::from_fn(m, 2, |i, j| ((i * (j + 3)) as f64 * 0.37).sin() + j as f64);
        let y = DVector::from_fn(m, |i, _| (i as f64 * 0.11).cos());
        let units = solve(&w, &y, &names(2), 1e-12).unwrap();
        let g = (w.transpose() * &w).try_inverse().unwrap();
        let x = [0.5, 3.0];
        let direct = (0.25 * g[(0, 0)] + 3.0 * g[(0, 1)] + 9.0 * g[(1, 1)]).sqrt();
        assert!((units.root_quadratic(&x) / direct - 1.0).abs() < 1e-10);
        let mut huge = w.clone();
        huge.column_mut(1).scale_mut(1e200);
        let s = solve(&huge, &y, &names(2), 1e-12).unwrap();
        // the second parameter in units 1e200 times smaller: x's second entry 1e200 times
        // larger reads the same combination
        let got = s.root_quadratic(&[0.5, 3e200]);
        assert!(
            (got / direct - 1.0).abs() < 1e-10,
            "{got:e} against {direct:e}"
        );
        let tiny = s.root_quadratic(&[0.0, 3.0]);
        let want = 3.0 * g[(1, 1)].sqrt() / 1e200;
        assert!(
            (tiny / want - 1.0).abs() < 1e-10,
            "{tiny:e} against {want:e}"
        );
    }

    /// Columns of very different units are not rank deficient: the rank decision is made
    /// on the scaled columns, the solution is exact.
    #[test]
    fn columns_of_different_units_are_full_rank() {
        let m = 100;
        let w = DMatrix::from_fn(m, 2, |i, j| {
            let x = (i as f64 * 0.37).sin() + 0.3 * (i as f64 * 1.9).cos() * j as f64;
            if j == 0 {
                1e-8 * x
            } else {
                1e8 * (x + (i as f64 * 0.11).cos())
            }
        });
        let y = &w * DVector::from_vec(vec![1e8, 1e-8]);
        let s = solve(&w, &y, &names(2), 1e-10).unwrap();
        assert!((s.beta[0] / 1e8 - 1.0).abs() < 1e-9 && (s.beta[1] / 1e-8 - 1.0).abs() < 1e-9);
        // measured 2.09e16
        assert!(s.condition_number > 1.05e16);
    }

    #[test]
    fn too_few_rows_is_an_error() {
        let w = DMatrix::from_row_slice(1, 2, &[1.0, 2.0]);
        assert!(matches!(
            solve(&w, &DVector::from_vec(vec![1.0]), &names(2), 1e-10),
            Err(Error::TooFewSamples { .. })
        ));
    }
}
