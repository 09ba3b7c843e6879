//! Least squares by QR then SVD of R, never by normal equations.
//!
//! [W y] = Q R_a (Householder), with R_a = [[R, z], [0, rho]]: z = Q'y (first n entries).
//! R = U S V'. The singular values of R are those of W, so the rank is decided with a
//! relative threshold on them, the condition number is s_max / s_min,
//! beta = V S^-1 U' z, and (W'W)^-1 = V S^-2 V'.
//!
//! The QR runs on blocks of rows in parallel (tall-skinny QR): each block's R, then the
//! R factors stacked and factorised again. It is the same R (up to row signs) as one QR
//! of the whole matrix, stays in cache, and never copies W whole.

use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;

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

/// R of the tall matrix [W y] ((cols + 1) x (cols + 1), upper triangular), by blocks.
fn augmented_r(w: &DMatrix<f64>, y: &DVector<f64>) -> DMatrix<f64> {
    let (m, n) = w.shape();
    let blocks = m.div_ceil(BLOCK).max(1);
    (0..blocks)
        .into_par_iter()
        .map(|b| {
            let (lo, hi) = (b * BLOCK, ((b + 1) * BLOCK).min(m));
            let mut a = DMatrix::zeros(hi - lo, n + 1);
            a.view_mut((0, 0), (hi - lo, n))
                .copy_from(&w.view((lo, 0), (hi - lo, n)));
            a.view_mut((0, n), (hi - lo, 1))
                .copy_from(&y.rows(lo, hi - lo));
            r_factor(a)
        })
        .reduce_with(|a, b| {
            let mut s = DMatrix::zeros(a.nrows() + b.nrows(), n + 1);
            s.view_mut((0, 0), a.shape()).copy_from(&a);
            s.view_mut((a.nrows(), 0), b.shape()).copy_from(&b);
            r_factor(s)
        })
        .unwrap_or_else(|| DMatrix::zeros(n + 1, n + 1))
}

use crate::error::{Error, Result};

/// A full-rank least-squares solution with what the statistics need.
#[derive(Debug, Clone)]
pub(crate) struct Solution {
    pub(crate) beta: DVector<f64>,
    /// (W'W)^-1.
    pub(crate) inverse_gram: DMatrix<f64>,
    pub(crate) condition_number: f64,
}

/// Solves min ||y - W beta||; `tolerance` is relative to the largest singular value.
/// Rank-deficient W is an error naming the parameters in the unexcited directions.
pub(crate) fn solve(
    w: &DMatrix<f64>,
    y: &DVector<f64>,
    names: &[String],
    tolerance: f64,
) -> Result<Solution> {
    let (m, n) = w.shape();
    if m < n || n == 0 {
        return Err(Error::TooFewSamples {
            context: format!("least squares with {n} parameters"),
            found: m,
            required: n.max(1),
            hint: "use more data, less decimation, or fewer parameters",
        });
    }
    let ra = augmented_r(w, y);
    let r = ra.view((0, 0), (n, n)).into_owned();
    let qty = ra.view((0, n), (n, 1)).into_owned();
    let svd = r.svd(true, true);
    let (Some(u), Some(vt)) = (svd.u.as_ref(), svd.v_t.as_ref()) else {
        return Err(Error::Singular {
            what: "observation matrix (SVD failed)".into(),
            hint: "check the data for extreme values",
        });
    };
    let s = &svd.singular_values;
    let smax = s.max();
    let smin = s.min();
    let cut = tolerance * smax;
    let null: Vec<usize> = (0..n).filter(|&k| s[k] <= cut || s[k].is_nan()).collect();
    if smax == 0.0 || !null.is_empty() {
        return Err(Error::RankDeficient {
            rank: n - null.len(),
            columns: n,
            unexcited: unexcited(vt, &null, names),
        });
    }
    let uty = u.transpose() * qty;
    let scaled = DVector::from_iterator(n, (0..n).map(|k| uty[k] / s[k]));
    let v = vt.transpose();
    let beta = &v * scaled;
    let mut vs = v.clone();
    for k in 0..n {
        vs.column_mut(k).scale_mut(1.0 / (s[k] * s[k]));
    }
    let inverse_gram = vs * vt;
    Ok(Solution {
        beta,
        inverse_gram,
        condition_number: smax / smin,
    })
}

/// Singular values of W (via QR), largest first.
pub(crate) fn singular_values(w: &DMatrix<f64>) -> Vec<f64> {
    let n = w.ncols();
    let r = if w.nrows() > n {
        augmented_r(w, &DVector::zeros(w.nrows()))
            .view((0, 0), (n, n))
            .into_owned()
    } else {
        w.clone()
    };
    let mut s: Vec<f64> = r.singular_values().iter().copied().collect();
    s.sort_by(|a, b| b.total_cmp(a));
    s
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
        assert!((g - &s.inverse_gram).norm() < 1e-12);
        assert!(s.condition_number > 1.0);
    }

    #[test]
    fn rank_deficiency_names_the_unexcited_parameters() {
        // column 3 is never excited, columns 1 and 2 are fine
        let w = DMatrix::from_row_slice(3, 3, &[1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0]);
        let y = DVector::from_vec(vec![1.0, 2.0, 3.0]);
        match solve(&w, &y, &names(3), 1e-10) {
            Err(Error::RankDeficient {
                rank: 2,
                columns: 3,
                unexcited,
            }) => assert_eq!(unexcited, vec!["p3"]),
            other => panic!("{other:?}"),
        }
        // two identical columns: both named
        let w = DMatrix::from_row_slice(3, 2, &[1.0, 1.0, 2.0, 2.0, 3.0, 3.0]);
        match solve(&w, &y, &names(2), 1e-10) {
            Err(Error::RankDeficient { unexcited, .. }) => assert_eq!(unexcited.len(), 2),
            other => panic!("{other:?}"),
        }
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
        assert!((g - &s.inverse_gram).norm() < 1e-10);
        let sv = singular_values(&w);
        let mut reference: Vec<f64> = w.singular_values().iter().copied().collect();
        reference.sort_by(|a, b| b.total_cmp(a));
        for (a, b) in sv.iter().zip(&reference) {
            assert!((a - b).abs() < 1e-9 * b);
        }
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
