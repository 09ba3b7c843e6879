//! Numeric rank analysis of candidate regressor columns sampled at random
//! states: zero columns (no effect) and linear dependencies on earlier columns.
//!
//! Columns are visited in order and orthogonalised against the columns kept
//! so far (Gram-Schmidt, twice for stability, as a column-norm-pivot-free QR
//! that keeps the earliest columns); a column whose residual is tiny relative
//! to its norm, and to the kept columns' in the combination nearest to it, is
//! dependent, and its coefficients on the kept columns come from a
//! least-squares solve (Householder QR) on the kept columns.

use nalgebra::{DMatrix, DVector};

/// Smallest diagonal entry of the triangular factor, for columns scaled to
/// unit norm, of a matrix taken to have full column rank: a column whose
/// part outside the span of the columns before it is smaller than this
/// fraction of its norm makes the least-squares problem singular.
const FULL_RANK: f64 = 1e-12;

/// The least-squares solution of `a x = b` for `a` of full column rank, or
/// `None` when a value is not finite, `a` has fewer rows than columns or is
/// not of full numeric rank.
///
/// Householder QR of `a` with its columns scaled to unit norm: direct and
/// backward stable. (An iterative SVD was used before; nalgebra's can return
/// a decomposition that does not reproduce its matrix,
/// <https://github.com/dimforge/nalgebra/issues/1172>, which gave dependency
/// coefficients wrong by 1e-5 for some sampled regressors.)
pub(crate) fn least_squares(a: &DMatrix<f64>, b: &[f64]) -> Option<Vec<f64>> {
    let (m, n) = a.shape();
    if b.len() != m || a.iter().chain(b).any(|x| !x.is_finite()) || m < n {
        return None;
    }
    if n == 0 {
        return Some(Vec::new());
    }
    let norms: Vec<f64> = a.column_iter().map(|c| c.norm()).collect();
    if norms.contains(&0.0) {
        return None;
    }
    let mut scaled = a.clone();
    for (mut column, &s) in scaled.column_iter_mut().zip(&norms) {
        column /= s;
    }
    let qr = scaled.qr();
    let r = qr.r();
    // (The entries are finite: checked above.)
    if (0..n).any(|i| r[(i, i)].abs() <= FULL_RANK) {
        return None;
    }
    let qtb = qr.q().transpose() * DVector::from_column_slice(b);
    let y = r.solve_upper_triangular(&qtb)?;
    let x: Vec<f64> = y.iter().zip(&norms).map(|(v, s)| v / s).collect();
    x.iter().all(|v| v.is_finite()).then_some(x)
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

/// Relative residual below which a column counts as dependent: above rounding (the
/// dependent columns of the test suites' robots and of 2 000 random symbolic ones leave
/// at most 7e-13 of their norms, the kept ones at least 1e-7), below what the angles a
/// description keeps as written leave (a twist 1e-9 rad from a right angle,
/// `RIGHT_ANGLE_SNAP`, leaves about 1e-9), so the base parameters and torques hold for
/// the table as written (docs/regrouping.md#numeric-rank-analysis). Relative to the
/// column's norm plus those of the kept columns in the combination that comes nearest to
/// it, each times its coefficient (`combined_size`).
pub(crate) const DEPENDENT: f64 = 1e-11;

/// Norm, relative to the largest column of its unit (at least 1), below which a
/// column has no effect.
pub(crate) const NO_EFFECT: f64 = 1e-11;

/// Classifies `columns` (each a sampled column of length m); `None` when a
/// value is not finite. `units[i]` names column i's unit (any number; columns
/// of one unit share it): a column has no effect when its norm is below
/// [`NO_EFFECT`] of the largest column of its unit, so that a first moment's
/// column, which grows with the lengths, is not measured against a mass's,
/// which grows with their square (a 1 um offset beside a 1 km slider: the
/// offset's first moments are 1e-12 of the slider's mass column, 1e-9 of its
/// first moments).
pub(crate) fn analyse(columns: &[Vec<f64>], units: &[usize]) -> Option<Vec<Status>> {
    if columns.iter().flatten().any(|x| !x.is_finite()) || units.len() != columns.len() {
        return None;
    }
    let order: Vec<usize> = (0..columns.len()).collect();
    analyse_in_order(columns, units, &order).map(|(status, _)| status)
}

/// A kept column that a later column of its unit depends on with a coefficient above this
/// (in magnitude) is that column shrunk by the coefficient: see [`analyse_preferring_larger`].
pub(crate) const SHRUNK: f64 = 10.0;

/// [`analyse`], but where a column depends on a kept column of the same unit with a
/// coefficient above [`SHRUNK`], the larger one is kept and the smaller folded into it.
/// Dimensionless coefficients that large come from a kept column that nearly vanishes: a
/// prismatic link measured 1e-3 rad off a right angle has its `MY` column 1e-3 of its `MZ`
/// one, and keeping the earlier gave `MYR2 = MY2 + 1000 MZ2 + 1000 MZ3`, where the nominal
/// table gives `MZR2 = MZ2 + MZ3` (now `MZR2 = MZ2 + MZ3 + 0.001 MY2`). Taken one exchange at
/// a time, the larger column visited just before the smaller, until none is left (at most
/// one pass per column). Kept positions and coefficients are in candidate order, as
/// [`analyse`] gives them. With geometric symbols an exchanged coefficient may be the
/// reciprocal of a polynomial in them, which robid cannot write for every value of them:
/// the caller then keeps the earlier column ([`analyse`]).
pub(crate) fn analyse_preferring_larger(
    columns: &[Vec<f64>],
    units: &[usize],
) -> Option<Vec<Status>> {
    if columns.iter().flatten().any(|x| !x.is_finite()) || units.len() != columns.len() {
        return None;
    }
    let mut order: Vec<usize> = (0..columns.len()).collect();
    for _ in 0..=columns.len() {
        let (status, kept) = analyse_in_order(columns, units, &order)?;
        // the first column, in visiting order, that a shrunk kept column of its unit leads
        let exchange = order.iter().find_map(|&d| match &status[d] {
            Status::Dependent(coefficients) => coefficients
                .iter()
                .find(|&&(k, c)| units[kept[k]] == units[d] && c.abs() > SHRUNK)
                .map(|&(k, _)| (d, kept[k])),
            _ => None,
        });
        let Some((larger, smaller)) = exchange else {
            return Some(in_candidate_order(status, &kept));
        };
        order.retain(|&i| i != larger);
        let at = order.iter().position(|&i| i == smaller)?;
        order.insert(at, larger);
    }
    // each exchange puts a column before one it is more than ten times: no cycle, so the
    // passes above suffice; were they not, the analysis in the given order stands
    analyse(columns, units)
}

/// Statuses whose kept positions follow `kept` (the visiting order) renumbered in
/// candidate order.
fn in_candidate_order(mut status: Vec<Status>, kept: &[usize]) -> Vec<Status> {
    let mut sorted = kept.to_vec();
    sorted.sort_unstable();
    let position = |visited: usize| sorted.binary_search(&kept[visited]).unwrap_or(visited);
    for s in &mut status {
        match s {
            Status::Kept(k) => *k = position(*k),
            Status::Dependent(coefficients) => {
                for (k, _) in coefficients.iter_mut() {
                    *k = position(*k);
                }
                coefficients.sort_by_key(|&(k, _)| k);
            }
            Status::Zero => {}
        }
    }
    status
}

/// The analysis visiting the columns in `order`: each column's status (indexed as
/// `columns`, kept positions and coefficients in visiting order) and the kept columns in
/// visiting order. The values are finite and `units` as long as `columns` (checked by the
/// callers).
fn analyse_in_order(
    columns: &[Vec<f64>],
    units: &[usize],
    order: &[usize],
) -> Option<(Vec<Status>, Vec<usize>)> {
    let m = columns.first().map_or(0, Vec::len);
    let sizes: Vec<f64> = columns.iter().map(|c| norm(c)).collect();
    let scale = |unit: usize| {
        sizes
            .iter()
            .zip(units)
            .filter(|&(_, &u)| u == unit)
            .fold(1.0_f64, |m, (&s, _)| m.max(s))
    };
    let mut basis: Vec<Vec<f64>> = Vec::new();
    // the triangular factor by rows: kept column k is `sum_j factor[k][j] basis[j]`, j <= k
    let mut factor: Vec<Vec<f64>> = Vec::new();
    let mut kept: Vec<usize> = Vec::new();
    let mut status = vec![Status::Zero; columns.len()];
    for &i in order {
        let c = &columns[i];
        let size = sizes[i];
        if size <= NO_EFFECT * scale(units[i]) {
            continue;
        }
        let mut r = c.clone();
        let mut projections = vec![0.0; basis.len()];
        for _ in 0..2 {
            for (b, total) in basis.iter().zip(&mut projections) {
                let p: f64 = b.iter().zip(&r).map(|(x, y)| x * y).sum();
                r.iter_mut().zip(b).for_each(|(x, y)| *x -= p * y);
                *total += p;
            }
        }
        let residual = norm(&r);
        let kept_sizes = kept.iter().map(|&k| sizes[k]);
        if residual > DEPENDENT * (size + combined_size(&factor, &projections, kept_sizes)) {
            r.iter_mut().for_each(|x| *x /= residual);
            basis.push(r);
            projections.push(residual);
            factor.push(projections);
            status[i] = Status::Kept(kept.len());
            kept.push(i);
        } else {
            status[i] = Status::Dependent(Vec::new());
        }
    }
    // Coefficients of each dependent column on the kept ones.
    if status.iter().any(|s| matches!(s, Status::Dependent(_))) {
        let a = DMatrix::from_fn(m, kept.len(), |r, k| columns[kept[k]][r]);
        for (i, s) in status.iter_mut().enumerate() {
            if let Status::Dependent(coefficients) = s {
                let x = least_squares(&a, &columns[i])?;
                *coefficients = x
                    .into_iter()
                    .enumerate()
                    .filter(|(_, v)| v.abs() > 1e-10)
                    .collect();
            }
        }
    }
    Some((status, kept))
}

/// `sum_k |x_k| size_k` for the combination `x` of the kept columns (of norms `sizes`,
/// triangular factor `factor` by rows) whose projections on the orthonormal basis are
/// `projections`: how large the columns a candidate is measured against are, in it. Each
/// sampled column is known to its rounding, relative to its own norm, so a combination
/// with large coefficients (of a kept column that nearly depends on the ones before it) is
/// known only to that rounding times them: a column 5.5e-6 of its norm outside the others
/// (a calibrated twist) left a column that depends on it exactly 4.7e-11 of its norm off,
/// and it was kept, one base parameter too many that no trajectory could excite.
fn combined_size(
    factor: &[Vec<f64>],
    projections: &[f64],
    sizes: impl Iterator<Item = f64>,
) -> f64 {
    let n = projections.len();
    let mut x = vec![0.0; n];
    for k in (0..n).rev() {
        let later: f64 = (k + 1..n).map(|l| x[l] * factor[l][k]).sum();
        x[k] = (projections[k] - later) / factor[k][k];
    }
    x.iter().zip(sizes).map(|(x, s)| x.abs() * s).sum()
}

/// Coefficients of `column` on the given kept columns (least squares);
/// `None` when a value is not finite or the kept columns are not
/// independent.
pub(crate) fn coefficients(kept: &[&Vec<f64>], column: &[f64]) -> Option<Vec<f64>> {
    let a = DMatrix::from_fn(column.len(), kept.len(), |r, k| kept[k][r]);
    least_squares(&a, column)
}

/// The Euclidean norm.
pub(crate) fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

#[cfg(test)]
mod tests {
    use super::{Status, analyse, least_squares};
    use nalgebra::DMatrix;

    /// Least squares refuses what it cannot solve (a right-hand side of another length, a
    /// value that is not finite, fewer rows than columns, a zero or dependent column) and
    /// solves a square system exactly.
    #[test]
    fn least_squares_solves_or_refuses() {
        let a = DMatrix::from_row_slice(2, 2, &[2.0, 1.0, 1.0, 3.0]);
        let x = least_squares(&a, &[5.0, 10.0]).unwrap();
        assert!(
            (x[0] - 1.0).abs() < 1e-14 && (x[1] - 3.0).abs() < 1e-14,
            "{x:?}"
        );
        assert_eq!(least_squares(&a, &[5.0]), None);
        assert_eq!(least_squares(&a, &[5.0, f64::NAN]), None);
        let mut bad = a.clone();
        bad[(1, 1)] = f64::INFINITY;
        assert_eq!(least_squares(&bad, &[5.0, 10.0]), None);
        let wide = DMatrix::from_row_slice(1, 2, &[1.0, 2.0]);
        assert_eq!(least_squares(&wide, &[1.0]), None);
        let zero = DMatrix::from_row_slice(2, 2, &[1.0, 0.0, 1.0, 0.0]);
        assert_eq!(least_squares(&zero, &[1.0, 1.0]), None);
        let dependent = DMatrix::from_row_slice(2, 2, &[1.0, 2.0, 2.0, 4.0]);
        assert_eq!(least_squares(&dependent, &[1.0, 2.0]), None);
        let empty = DMatrix::<f64>::zeros(2, 0);
        assert_eq!(least_squares(&empty, &[1.0, 2.0]), Some(Vec::new()));
    }

    #[test]
    fn finds_zero_and_dependent_columns() {
        let a = vec![1.0, 2.0, 3.0, 4.0];
        let b = vec![0.0, 1.0, 0.0, 1.0];
        let zero = vec![0.0; 4];
        let dep: Vec<f64> = a.iter().zip(&b).map(|(x, y)| 2.0 * x - 0.5 * y).collect();
        let s = analyse(&[a, zero, b, dep], &[0; 4]).unwrap();
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

    /// Both thresholds are relative: a column of rounding noise (1e-9 against columns of
    /// norm 1e3) is zero, a column 5e-14 of its size away from the span of the others
    /// (rounding) is dependent, while one 5e-10 away (what a twist written 1e-9 rad from a
    /// right angle leaves) or 1e-6 away is kept.
    #[test]
    fn the_thresholds_are_relative_to_the_columns() {
        let a = vec![1e3, 0.0, 0.0, 0.0];
        let noise = vec![0.0, 1e-9, 0.0, 0.0];
        let near = vec![2e3, 1e-10, 0.0, 0.0];
        let measured = vec![2e3, 0.0, 0.0, 1e-6];
        let apart = vec![1e3, 0.0, 1e-3, 0.0];
        let s = analyse(&[a, noise, near, measured, apart], &[0; 5]).unwrap();
        assert_eq!(s[0], Status::Kept(0));
        assert_eq!(s[1], Status::Zero);
        assert!(matches!(s[2], Status::Dependent(_)), "{:?}", s[2]);
        assert_eq!(s[3], Status::Kept(1));
        assert_eq!(s[4], Status::Kept(2));
    }

    /// The zero test is relative to the columns of the same unit: a column 1e-12 of the
    /// largest is zero among columns of its unit, kept when the large one is of another
    /// unit and its own unit's largest is near it.
    #[test]
    fn a_column_is_measured_against_its_own_unit() {
        let large = vec![1e6, 0.0, 0.0];
        let small = vec![0.0, 1e-6, 0.0];
        let peer = vec![0.0, 0.0, 1e-3];
        let same = analyse(&[large.clone(), small.clone(), peer.clone()], &[0, 0, 0]).unwrap();
        assert_eq!(same[1], Status::Zero);
        let apart = analyse(&[large, small, peer], &[1, 0, 0]).unwrap();
        assert_eq!(apart[1], Status::Kept(1));
        // below 1e-11 of its own unit's largest (at least 1): zero
        let tiny = analyse(&[vec![1.0, 0.0], vec![0.0, 1e-12]], &[0, 1]).unwrap();
        assert_eq!(tiny[1], Status::Zero);
        // a list of units of another length is refused
        assert_eq!(analyse(&[vec![1.0]], &[]), None);
    }

    /// A column that depends exactly on a kept column nearly dependent itself is dependent:
    /// `near` is 5e-6 of its norm outside `a`, with a rounding error of 1e-15 in a third
    /// direction, which leaves `across` 2e-10 of its norm outside both, above 1e-11, and it
    /// was kept; measured against the combination (`2e5 near - 2e5 a`) it is rounding. A
    /// column really apart from both is still kept.
    #[test]
    fn a_column_on_a_nearly_dependent_one_is_dependent() {
        let a = vec![1.0, 0.0, 0.0, 0.0];
        let near = vec![1.0, 5e-6, 1e-15, 0.0];
        let across = vec![0.0, 1.0, 0.0, 0.0];
        let apart = vec![0.0, 1.0, 0.0, 1e-3];
        let s = analyse(&[a, near, across, apart], &[0; 4]).unwrap();
        assert_eq!(s[0], Status::Kept(0));
        assert_eq!(s[1], Status::Kept(1));
        match &s[2] {
            Status::Dependent(c) => assert!((c[1].1 - 2e5).abs() < 1e-3, "{c:?}"),
            other => panic!("expected a dependency, got {other:?}"),
        }
        assert_eq!(s[3], Status::Kept(2));
    }

    /// The combination is solved from the triangular factor: `c = 3 a1 + 4 a2` with
    /// `a1 = (1, 0, 0)` and `a2 = (2, 2, 0)` (factor rows `[1]`, `[2, 2]` on `e1`, `e2`),
    /// projections `(11, 8)`, is `3 |a1| + 4 |a2|`.
    #[test]
    fn the_combined_size_is_the_coefficients_times_the_norms() {
        let factor = vec![vec![1.0], vec![2.0, 2.0]];
        let size = super::combined_size(&factor, &[11.0, 8.0], [1.0, 8f64.sqrt()].into_iter());
        assert!((size - (3.0 + 4.0 * 8f64.sqrt())).abs() < 1e-14, "{size}");
        assert_eq!(super::combined_size(&[], &[], std::iter::empty()), 0.0);
    }

    /// Of two columns of one unit, one more than ten times the other, the larger is kept
    /// and the smaller folded into it, positions in candidate order; columns of other units,
    /// or within a factor ten, keep the earlier.
    #[test]
    fn the_larger_of_two_columns_of_one_unit_is_kept() {
        use super::analyse_preferring_larger;
        let other = vec![0.0, 0.0, 1.0, 0.0];
        let large = vec![1.0, 2.0, 0.0, 3.0];
        let small: Vec<f64> = large.iter().map(|x| 1e-3 * x).collect();
        // a kept column between the two: the positions change with the order
        let columns = [small.clone(), other.clone(), large.clone()];
        let earlier = analyse(&columns, &[0; 3]).unwrap();
        assert!(matches!(&earlier[2], Status::Dependent(c) if (c[0].1 - 1e3).abs() < 1e-9));
        let s = analyse_preferring_larger(&columns, &[0; 3]).unwrap();
        assert_eq!(s[1], Status::Kept(0));
        assert_eq!(s[2], Status::Kept(1));
        match &s[0] {
            Status::Dependent(c) => {
                assert_eq!(c.len(), 1);
                assert_eq!(c[0].0, 1);
                assert!((c[0].1 - 1e-3).abs() < 1e-15, "{c:?}");
            }
            other => panic!("expected a dependency, got {other:?}"),
        }
        // another unit, or a factor of five: the earlier stays
        assert_eq!(
            analyse_preferring_larger(&columns, &[1, 0, 0]).unwrap(),
            analyse(&columns, &[1, 0, 0]).unwrap()
        );
        let fivefold: Vec<f64> = large.iter().map(|x| 0.2 * x).collect();
        let near = [other, fivefold, large];
        assert_eq!(
            analyse_preferring_larger(&near, &[0; 3]).unwrap(),
            analyse(&near, &[0; 3]).unwrap()
        );
    }

    #[test]
    fn values_that_are_not_finite_are_refused() {
        assert_eq!(analyse(&[vec![1.0, f64::NAN]], &[0]), None);
        assert_eq!(
            analyse(&[vec![1.0, f64::INFINITY], vec![0.0, 1.0]], &[0, 0]),
            None
        );
        assert_eq!(
            super::coefficients(&[&vec![1.0, 2.0]], &[f64::NAN, 1.0]),
            None
        );
    }
}
