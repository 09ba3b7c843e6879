//! Numeric rank analysis of candidate regressor columns sampled at random
//! states: zero columns (no effect) and linear dependencies on earlier columns.
//!
//! Columns are visited in order and orthogonalised against the columns kept
//! so far (Gram-Schmidt, twice for stability, as a column-norm-pivot-free QR
//! that keeps the earliest columns); a column whose residual is tiny relative
//! to its norm is dependent, and its coefficients on the kept columns come
//! from a least-squares solve (SVD) on the kept columns.

use nalgebra::{DMatrix, DVector, SVD};

/// Most iterations of an SVD: finite input converges in a few sweeps per
/// singular value; the cap only guarantees an end.
const SVD_ITERATIONS: usize = 10_000;

/// The SVD of `a` as nalgebra's `svd(true, true)` computes it, or `None`
/// when an entry is not finite or it does not converge within the cap.
pub(crate) fn svd(a: DMatrix<f64>) -> Option<SVD<f64, nalgebra::Dyn, nalgebra::Dyn>> {
    if a.iter().any(|x| !x.is_finite()) {
        return None;
    }
    a.try_svd(true, true, f64::EPSILON * 5.0, SVD_ITERATIONS)
}

/// What the analysis found for a column.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Status {
    /// Independent of the earlier kept columns; its position among the kept.
    Kept(usize),
    /// Identically zero: the parameter has no effect.
    Zero,
    /// A combination of kept columns: (kept position, coefficient).
    Dependent(Vec<(usize, f64)>),
}

/// Relative residual below which a column counts as dependent.
const DEPENDENT: f64 = 1e-8;

/// Classifies `columns` (each a sampled column of length m); `None` when a
/// value is not finite or the least-squares solve does not converge.
pub(crate) fn analyse(columns: &[Vec<f64>]) -> Option<Vec<Status>> {
    if columns.iter().flatten().any(|x| !x.is_finite()) {
        return None;
    }
    let m = columns.first().map_or(0, Vec::len);
    let scale = columns
        .iter()
        .map(|c| norm(c))
        .fold(0.0_f64, f64::max)
        .max(1.0);
    let mut basis: Vec<Vec<f64>> = Vec::new();
    let mut kept: Vec<usize> = Vec::new();
    let mut status = Vec::with_capacity(columns.len());
    for (i, c) in columns.iter().enumerate() {
        let size = norm(c);
        if size <= 1e-11 * scale {
            status.push(Status::Zero);
            continue;
        }
        let mut r = c.clone();
        for _ in 0..2 {
            for b in &basis {
                let p: f64 = b.iter().zip(&r).map(|(x, y)| x * y).sum();
                r.iter_mut().zip(b).for_each(|(x, y)| *x -= p * y);
            }
        }
        let residual = norm(&r);
        if residual > DEPENDENT * size {
            r.iter_mut().for_each(|x| *x /= residual);
            basis.push(r);
            status.push(Status::Kept(kept.len()));
            kept.push(i);
        } else {
            status.push(Status::Dependent(Vec::new()));
        }
    }
    // Coefficients of each dependent column on the kept ones.
    if status.iter().any(|s| matches!(s, Status::Dependent(_))) {
        let a = DMatrix::from_fn(m, kept.len(), |r, k| columns[kept[k]][r]);
        let svd = svd(a)?;
        for (i, s) in status.iter_mut().enumerate() {
            if let Status::Dependent(coefficients) = s {
                let b = DVector::from_column_slice(&columns[i]);
                let x = svd
                    .solve(&b, 1e-12)
                    .unwrap_or_else(|_| DVector::zeros(kept.len()));
                *coefficients = x
                    .iter()
                    .enumerate()
                    .filter(|(_, v)| v.abs() > 1e-10)
                    .map(|(k, &v)| (k, v))
                    .collect();
            }
        }
    }
    Some(status)
}

/// Coefficients of `column` on the given kept columns (least squares);
/// `None` when a value is not finite or the solve does not converge.
pub(crate) fn coefficients(kept: &[&Vec<f64>], column: &[f64]) -> Option<Vec<f64>> {
    let m = column.len();
    let a = DMatrix::from_fn(m, kept.len(), |r, k| kept[k][r]);
    let b = DVector::from_column_slice(column);
    if b.iter().any(|x| !x.is_finite()) {
        return None;
    }
    Some(
        svd(a)?
            .solve(&b, 1e-12)
            .map(|x| x.iter().copied().collect())
            .unwrap_or_else(|_| vec![0.0; kept.len()]),
    )
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

#[cfg(test)]
mod tests {
    use super::{Status, analyse};

    #[test]
    fn finds_zero_and_dependent_columns() {
        let a = vec![1.0, 2.0, 3.0, 4.0];
        let b = vec![0.0, 1.0, 0.0, 1.0];
        let zero = vec![0.0; 4];
        let dep: Vec<f64> = a.iter().zip(&b).map(|(x, y)| 2.0 * x - 0.5 * y).collect();
        let s = analyse(&[a, zero, b, dep]).unwrap();
        assert_eq!(s[0], Status::Kept(0));
        assert_eq!(s[1], Status::Zero);
        assert_eq!(s[2], Status::Kept(1));
        match &s[3] {
            Status::Dependent(c) => {
                assert_eq!(c.len(), 2);
                assert!((c[0].1 - 2.0).abs() < 1e-12 && (c[1].1 + 0.5).abs() < 1e-12);
            }
            other => panic!("expected a dependency, got {other:?}"),
        }
    }

    #[test]
    fn values_that_are_not_finite_are_refused() {
        assert_eq!(analyse(&[vec![1.0, f64::NAN]]), None);
        assert_eq!(analyse(&[vec![1.0, f64::INFINITY], vec![0.0, 1.0]]), None);
        assert_eq!(
            super::coefficients(&[&vec![1.0, 2.0]], &[f64::NAN, 1.0]),
            None
        );
    }
}
