//! The streaming accumulator against the dense solvers on the same equations.

use nalgebra::{DMatrix, DVector};

use super::*;
use crate::estimate::{Observation, dominated_columns, ols, wls};
use crate::rng::Rng;

/// Relative difference, with `floor` as the smallest magnitude compared.
fn close(a: f64, b: f64, tol: f64, floor: f64) -> bool {
    (a - b).abs() <= tol * a.abs().max(b.abs()).max(floor)
}

fn assert_same(s: &Estimate, d: &Estimate, tol: f64) {
    assert_eq!(s.names, d.names);
    assert_eq!(s.rows, d.rows);
    for i in 0..d.values.len() {
        assert!(
            close(s.values[i], d.values[i], tol, d.std[i]),
            "value {i}: {} vs {} (cond {:e})",
            s.values[i],
            d.values[i],
            d.condition_number
        );
        assert!(
            close(s.std[i], d.std[i], tol, 0.0),
            "std {i}: {} vs {}",
            s.std[i],
            d.std[i]
        );
    }
    assert!(
        close(s.sigma2, d.sigma2, tol, 0.0),
        "{} vs {}",
        s.sigma2,
        d.sigma2
    );
    assert!(
        close(s.condition_number, d.condition_number, tol, 0.0),
        "{} vs {}",
        s.condition_number,
        d.condition_number
    );
    match (s.scaled_condition_number, d.scaled_condition_number) {
        (Some(a), Some(b)) => assert!(close(a, b, tol, 0.0), "scaled cond {a} vs {b}"),
        other => panic!("{other:?}"),
    }
    assert!(close(s.error_bound, d.error_bound, tol, 0.0));
    for (a, b) in s.residual_rms.iter().zip(&d.residual_rms) {
        assert!(close(*a, *b, tol, 0.0), "rms {a} vs {b}");
    }
    match (&s.weights, &d.weights) {
        (Some(a), Some(b)) => {
            for (x, y) in a.iter().zip(b) {
                assert!(close(*x, *y, tol, 0.0), "weight {x} vs {y}");
            }
        }
        (None, None) => {}
        other => panic!("{other:?}"),
    }
    let kinds = |e: &Estimate| e.warnings.iter().map(|w| w.kind()).collect::<Vec<_>>();
    assert_eq!(kinds(s), kinds(d));
}

/// `groups` joints of `per_group` equations, `p` parameters whose columns differ in
/// magnitude by `spread` decades, noise growing with the joint; returns the dense
/// observation (joint-major) and the rows in the order they are pushed (interleaved by
/// sample, as the pipeline gives them).
fn problem(
    groups: usize,
    per_group: usize,
    p: usize,
    spread: f64,
    seed: u64,
) -> (Observation, Vec<(usize, Vec<f64>, f64)>) {
    let mut rng = Rng::new(seed);
    let beta: Vec<f64> = (0..p)
        .map(|i| (i as f64 + 1.0) * if i % 2 == 0 { 1.0 } else { -0.5 })
        .collect();
    let unit: Vec<f64> = (0..p)
        .map(|i| 10f64.powf(spread * (i as f64 / p.max(2) as f64 - 0.5)))
        .collect();
    let mut rows = Vec::new();
    for k in 0..per_group {
        for j in 0..groups {
            let t = k as f64 * 0.013;
            let row: Vec<f64> = (0..p)
                .map(|i| {
                    unit[i]
                        * ((t * (1.0 + 0.37 * i as f64) + j as f64).sin()
                            + 0.3 * rng.uniform(-1.0, 1.0))
                })
                .collect();
            let y = row
                .iter()
                .zip(&beta)
                .zip(&unit)
                .map(|((a, b), u)| a * b / u)
                .sum::<f64>()
                + 0.01 * (j + 1) as f64 * rng.uniform(-1.0, 1.0);
            rows.push((j, row, y));
        }
    }
    let n = rows.len();
    let mut w = DMatrix::zeros(n, p);
    let mut y = DVector::zeros(n);
    let mut joint_rows = Vec::new();
    let mut sample_of_row = Vec::new();
    let mut r = 0;
    for j in 0..groups {
        let start = r;
        for (k, (g, row, v)) in rows.iter().filter(|x| x.0 == j).enumerate() {
            debug_assert_eq!(*g, j);
            for (c, x) in row.iter().enumerate() {
                w[(r, c)] = *x;
            }
            y[r] = *v;
            sample_of_row.push(k);
            r += 1;
        }
        joint_rows.push(start..r);
    }
    let names = (1..=p).map(|i| format!("p{i}")).collect();
    let obs = Observation::new(w, y, joint_rows, sample_of_row, names).unwrap();
    (obs, rows)
}

fn streamed(obs: &Observation, rows: &[(usize, Vec<f64>, f64)]) -> StreamingLeastSquares {
    let mut s = StreamingLeastSquares::new(obs.names.clone(), obs.joint_rows.len()).unwrap();
    for (j, row, y) in rows {
        s.push(*j, row, *y).unwrap();
    }
    s
}

/// OLS and WLS equal the dense solvers to 1e-10 on systems of several sizes, with columns
/// of equal and of very different magnitudes (12 decades), rows enough for many buffer
/// updates.
#[test]
fn ols_and_wls_equal_the_dense_solvers() {
    for (groups, per_group, p, spread, seed) in [
        (1, 300, 3, 0.0, 1),
        (2, 2000, 5, 0.0, 2),
        (6, 1500, 24, 3.0, 3),
        (7, 700, 40, 12.0, 4),
    ] {
        let (obs, rows) = problem(groups, per_group, p, spread, seed);
        let mut s = streamed(&obs, &rows);
        assert_eq!(s.rows(), obs.rows());
        assert_eq!(s.group_rows(), vec![per_group; groups]);
        assert_same(&s.ols(1e-12).unwrap(), &ols(&obs, 1e-12).unwrap(), 1e-10);
        assert_same(&s.wls(1e-12).unwrap(), &wls(&obs, 1e-12).unwrap(), 1e-10);
    }
}

/// Equations split in parts accumulated apart and merged give the result of one
/// accumulation, whatever the parts' magnitudes (the second part is 2^40 larger in one
/// column, so the scales differ).
#[test]
fn merged_parts_equal_one_accumulation() {
    let (obs, mut rows) = problem(3, 900, 6, 2.0, 7);
    for r in rows.iter_mut().skip(1500) {
        r.1[2] *= 1.0995e12;
    }
    let whole = streamed(&obs, &rows).ols(1e-12).unwrap();
    let mut parts: Vec<StreamingLeastSquares> =
        rows.chunks(1000).map(|c| streamed(&obs, c)).collect();
    let mut first = parts.remove(0);
    for p in parts {
        first.merge(p).unwrap();
    }
    assert_eq!(first.rows(), rows.len());
    assert_same(&first.ols(1e-12).unwrap(), &whole, 1e-10);
    let other = StreamingLeastSquares::new(vec!["x".into()], 3).unwrap();
    assert!(first.merge(other).is_err());
}

/// Magnitudes whose squares overflow or underflow (1e200, 1e-150) are solved as the dense
/// solver solves them; at 1e-200 the covariance of that parameter (1e400) overflows, and
/// both refuse it with the same error.
#[test]
fn extreme_magnitudes_are_solved_like_the_dense_path() {
    for scale in [1e200, 1e-150, 1e-200] {
        let (mut obs, mut rows) = problem(2, 400, 3, 0.0, 11);
        for r in rows.iter_mut() {
            r.1[1] *= scale;
        }
        obs.w.column_mut(1).scale_mut(scale);
        let mut s = streamed(&obs, &rows);
        match (s.ols(1e-12), ols(&obs, 1e-12)) {
            (Ok(a), Ok(b)) => assert_same(&a, &b, 1e-10),
            (
                Err(Error::NonFiniteResult { what: a, .. }),
                Err(Error::NonFiniteResult { what: b, .. }),
            ) => {
                assert_eq!(scale, 1e-200);
                assert_eq!(a, b);
                continue;
            }
            other => panic!("{scale:e}: {other:?}"),
        }
        assert_same(&s.wls(1e-12).unwrap(), &wls(&obs, 1e-12).unwrap(), 1e-10);
    }
}

/// The dense solver's errors: rank deficiency naming the unexcited parameters, too few
/// equations, a bad rank tolerance; and the accumulator's own: non-finite values, wrong
/// lengths, groups out of range.
#[test]
fn errors_are_those_of_the_dense_path() {
    let (mut obs, mut rows) = problem(2, 300, 4, 0.0, 5);
    obs.w.column_mut(2).fill(0.0);
    for r in rows.iter_mut() {
        r.1[2] = 0.0;
    }
    let dense = ols(&obs, 1e-10).unwrap_err().to_string();
    let mut s = streamed(&obs, &rows);
    assert_eq!(s.ols(1e-10).unwrap_err().to_string(), dense);
    assert!(dense.contains("p3"), "{dense}");
    assert_eq!(s.wls(1e-10).unwrap_err().to_string(), dense);
    assert!(
        s.ols(0.0)
            .unwrap_err()
            .to_string()
            .contains("rank_tolerance")
    );

    let names: Vec<String> = vec!["a".into(), "b".into()];
    let mut few = StreamingLeastSquares::new(names.clone(), 1).unwrap();
    few.push(0, &[1.0, 2.0], 3.0).unwrap();
    assert!(matches!(few.ols(1e-10), Err(Error::TooFewSamples { .. })));
    let e = few.push(0, &[1.0, f64::NAN], 3.0).unwrap_err().to_string();
    assert!(e.contains("`b`") || e.contains("b"), "{e}");
    assert!(few.push(0, &[1.0, 1.0], f64::INFINITY).is_err());
    assert!(few.push(0, &[1.0], 1.0).is_err());
    assert!(few.push(1, &[1.0, 1.0], 1.0).is_err());
    assert_eq!(few.rows(), 1, "refused equations are not added");
    assert!(StreamingLeastSquares::new(vec![], 1).is_err());
    assert!(StreamingLeastSquares::new(names.clone(), 0).is_err());
    assert!(StreamingLeastSquares::new(vec!["a".into(), "a".into()], 1).is_err());
}

/// A group with no equations is left out of the fit and has a residual RMS of 0, as an
/// empty joint block of the dense path.
#[test]
fn an_empty_group_is_left_out() {
    let (obs, rows) = problem(2, 300, 3, 0.0, 9);
    let mut s = StreamingLeastSquares::new(obs.names.clone(), 3).unwrap();
    for (j, row, y) in &rows {
        s.push(*j, row, *y).unwrap();
    }
    let mut with_empty = obs.clone();
    with_empty.joint_rows.push(obs.rows()..obs.rows());
    assert_same(
        &s.ols(1e-12).unwrap(),
        &ols(&with_empty, 1e-12).unwrap(),
        1e-10,
    );
    assert_same(
        &s.wls(1e-12).unwrap(),
        &wls(&with_empty, 1e-12).unwrap(),
        1e-10,
    );
}

#[test]
fn powers_of_two_bound_their_argument() {
    for x in [1.0, 1.5, 3.0, 1e-300, 5e-324, 1e300, f64::MAX, 0.75] {
        let s = pow2_above(x);
        assert_eq!(
            s.to_bits() & ((1 << 52) - 1),
            0,
            "{x}: {s} is a power of two"
        );
        assert!(x < s || (x >= 2f64.powi(1023) && x < 2.0 * s), "{x}: {s}");
        assert!(
            s <= 2.0 * x || x < f64::MIN_POSITIVE,
            "{x}: {s} is the smallest"
        );
    }
    assert_eq!(pow2_above(1.0), 2.0);
    assert_eq!(pow2_above(3.0), 4.0);
}

/// The streaming outlier check finds the columns `dominated_columns` finds, with the same
/// shares, the largest entry's tag and the 100-row minimum.
#[test]
fn dominance_equals_dominated_columns() {
    let w = DMatrix::from_fn(200, 4, |i, j| match j {
        0 => (i as f64 * 0.3).sin(),
        1 if i == 57 => 1e3,
        2 if i == 91 => 1e200,
        3 => 0.0,
        _ => 1e-3 * (i as f64).cos(),
    });
    let dense = dominated_columns(&w);
    let mut d = Dominance::new(4);
    for i in 0..200 {
        let row: Vec<f64> = w.row(i).iter().copied().collect();
        d.push(&row, i);
    }
    let s = d.dominated();
    assert_eq!(s.len(), dense.len());
    for (a, b) in s.iter().zip(&dense) {
        assert_eq!((a.0, a.1), (b.0, b.1));
        assert!(close(a.2, b.2, 1e-12, 0.0), "{a:?} vs {b:?}");
    }
    let mut few = Dominance::new(4);
    for i in 0..99 {
        few.push(&[0.0, if i == 3 { 1e3 } else { 1.0 }, 0.0, 0.0], i);
    }
    assert!(few.dominated().is_empty());
    few.push(&[0.0, 1.0, 0.0, 0.0], 99);
    assert_eq!(few.dominated().len(), 1);
}

/// The rows that change neither a scale nor the top entries (added in one vectorised pass)
/// give the sums, to the bit, of checking every entry: a reference of the per-entry pass
/// (each |v| divided by its column's power-of-two scale, squared and added when not zero)
/// on rows whose magnitudes grow now and then, with zeros and a column of zeros.
#[test]
fn dominance_sums_are_those_of_every_entry_checked() {
    let mut rng = crate::rng::Rng::new(5);
    let n = 9;
    let mut d = Dominance::new(n);
    let (mut scale, mut sum) = (vec![0.0f64; n], vec![0.0f64; n]);
    for i in 0..5000 {
        let row: Vec<f64> = (0..n)
            .map(|c| match c {
                0 => 0.0,
                1 if i % 7 == 0 => 0.0,
                _ => rng.normal() * (1.0 + (i / 1000) as f64) * 10f64.powi(c as i32 - 4),
            })
            .collect();
        d.push(&row, i);
        for c in 0..n {
            let a = row[c].abs();
            if a > scale[c] {
                let s = pow2_above(a);
                if scale[c] > 0.0 {
                    sum[c] *= (scale[c] / s) * (scale[c] / s);
                }
                scale[c] = s;
            }
            if a > 0.0 {
                sum[c] += (a / scale[c]) * (a / scale[c]);
            }
        }
    }
    for c in 0..n {
        assert_eq!(d.sum[c].to_bits(), sum[c].to_bits(), "column {c}");
        assert_eq!(d.columns[c].scale, scale[c], "column {c}");
    }
}

/// Equations pushed in bulk (groups updated in parallel) give the result of pushing them
/// one by one; a bad equation anywhere refuses the whole bulk with the error `push` gives.
#[test]
fn bulk_pushes_equal_single_ones() {
    let (obs, rows) = problem(4, 500, 5, 1.0, 13);
    let mut one = streamed(&obs, &rows);
    let mut bulk = StreamingLeastSquares::new(obs.names.clone(), 4).unwrap();
    for part in rows.chunks(777) {
        let groups: Vec<usize> = part.iter().map(|r| r.0).collect();
        let w: Vec<f64> = part.iter().flat_map(|r| r.1.iter().copied()).collect();
        let y: Vec<f64> = part.iter().map(|r| r.2).collect();
        bulk.push_rows(&groups, &w, &y).unwrap();
    }
    assert_eq!(bulk.group_rows(), one.group_rows());
    let (a, b) = (bulk.wls(1e-12).unwrap(), one.wls(1e-12).unwrap());
    assert_eq!(a.values, b.values, "the same operations in the same order");
    let before = bulk.rows();
    let mut w = vec![1.0; 10];
    w[7] = f64::NAN;
    let e = bulk.push_rows(&[0, 1], &w, &[1.0, 2.0]).unwrap_err();
    // the second equation's, told as pushing it alone tells it: the 501st of group 2
    let alone = one.push(1, &w[5..], 2.0).unwrap_err();
    assert_eq!(e.to_string(), alone.to_string());
    assert!(
        e.to_string().contains("equation 501 of group 2") && e.to_string().contains("p3"),
        "{e}"
    );
    assert_eq!(bulk.names(), obs.names.as_slice());
    match alone {
        Error::Estimate(EstimateError::NonFiniteObservation { joint, .. }) => assert_eq!(joint, 2),
        other => panic!("{other:?}"),
    }
    let e = bulk.push_rows(&[0, 1], &[1.0; 7], &[1.0, 2.0]).unwrap_err();
    assert!(
        e.to_string().ends_with("expected 10 entries, found 7"),
        "{e}"
    );
    assert!(bulk.push_rows(&[0, 9], &[1.0; 10], &[1.0, 2.0]).is_err());
    assert!(bulk.push_rows(&[0], &[1.0; 10], &[1.0, 2.0]).is_err());
    assert_eq!(bulk.rows(), before, "nothing added");
}

/// The structured fold keeps `R' R = [R; B]' [R; B]` and `R` upper triangular, with rows
/// whose leading columns are zero (a late joint's equations, whose reflections are
/// skipped), and a column zero in the first rows (a zero on the factor's diagonal when
/// the next rows reach it).
#[test]
fn the_fold_keeps_the_gram_matrix() {
    let n = 9;
    let mut rng = Rng::new(5);
    // a factor: the R of some rows (column 4 never non-zero, like an unused parameter)
    let entry = |rng: &mut Rng, c: usize| if c == 4 { 0.0 } else { rng.normal() };
    let mut r = DMatrix::<f64>::zeros(n, n);
    let first: Vec<f64> = (0..20 * n).map(|i| entry(&mut rng, i % n)).collect();
    fold_rows(&mut r, &mut first.clone(), n);
    let mut gram = DMatrix::<f64>::zeros(n, n);
    let add = |gram: &mut DMatrix<f64>, rows: &[f64]| {
        for row in rows.chunks_exact(n) {
            let v = DVector::from_column_slice(row);
            *gram += &v * v.transpose();
        }
    };
    add(&mut gram, &first);
    for lead in [0, 3, 6, 8] {
        let rows: Vec<f64> = (0..13 * n)
            .map(|i| if i % n < lead { 0.0 } else { rng.normal() })
            .collect();
        fold_rows(&mut r, &mut rows.clone(), n);
        add(&mut gram, &rows);
        for i in 0..n {
            for j in 0..i {
                assert_eq!(r[(i, j)], 0.0, "below the diagonal at ({i}, {j})");
            }
        }
        let rtr = r.transpose() * &r;
        let scale = gram.amax();
        for (a, b) in rtr.iter().zip(gram.iter()) {
            assert!(
                (a - b).abs() <= 1e-13 * scale,
                "{a} vs {b}, leading zeros {lead}"
            );
        }
    }
}

/// Rows far weaker than those already folded (a record that starts with a strong motion
/// and goes on with a faint one): the reflection's sign follows the diagonal, so that
/// `alpha - beta` adds two magnitudes rather than cancelling them. The faint rows alone
/// determine the second parameter; with the other sign its estimate was off by parts in a
/// million.
#[test]
fn faint_rows_after_strong_ones_keep_their_precision() {
    let mut rng = Rng::new(11);
    let mut rows = Vec::new();
    for _ in 0..1000 {
        rows.push((0, vec![1.0, 0.0], 1.0));
    }
    for _ in 0..1000 {
        let (a, c) = (rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0));
        let noise = 1e-7 * rng.uniform(-1.0, 1.0);
        rows.push((0, vec![1e-4 * a, 1e-4 * c], 1e-4 * (a + 2.0 * c) + noise));
    }
    let mut w = DMatrix::zeros(rows.len(), 2);
    let mut y = DVector::zeros(rows.len());
    for (r, (_, row, v)) in rows.iter().enumerate() {
        w[(r, 0)] = row[0];
        w[(r, 1)] = row[1];
        y[r] = *v;
    }
    let names = vec!["p1".to_string(), "p2".to_string()];
    let n = rows.len();
    let obs = Observation::new(
        w,
        y,
        std::iter::once(0..n).collect(),
        (0..n).collect(),
        names,
    )
    .unwrap();
    let mut s = streamed(&obs, &rows);
    assert_same(&s.ols(1e-12).unwrap(), &ols(&obs, 1e-12).unwrap(), 1e-10);
}

/// Streamed WLS gives each group the degrees of freedom its own equations lose to the fit
/// (their leverages, from the group's factor), as the dense WLS does: with every group's
/// equations in parameters of their own, group j's residual has `r_j - 2` of them (it had
/// `r_j - 6`, the parameters taken once per group).
#[test]
fn wls_weights_take_each_groups_leverage() {
    let counts = [40usize, 40, 20];
    let names: Vec<String> = (0..6).map(|i| format!("p{i}")).collect();
    let mut s = StreamingLeastSquares::new(names, 3).unwrap();
    let mut equations = Vec::new();
    for (j, &count) in counts.iter().enumerate() {
        for k in 0..count {
            let t = k as f64 * 0.13 + j as f64;
            let mut row = [0.0; 6];
            row[2 * j] = t.sin();
            row[2 * j + 1] = 1.0 + 0.3 * t.cos();
            let y = 1.5 * t.sin() - 0.5 + (j + 1) as f64 * 0.01 * (t * 17.1).sin();
            s.push(j, &row, y).unwrap();
            equations.push((j, row, y));
        }
    }
    let first = s.ols(1e-10).unwrap();
    let weights = s.wls(1e-10).unwrap().weights.unwrap();
    for (j, &count) in counts.iter().enumerate() {
        let rss: f64 = equations
            .iter()
            .filter(|e| e.0 == j)
            .map(|(_, row, y)| {
                let r = y - row
                    .iter()
                    .zip(&first.values)
                    .map(|(a, b)| a * b)
                    .sum::<f64>();
                r * r
            })
            .sum();
        let sigma = (rss / (count - 2) as f64).sqrt();
        assert!(
            (weights[j] * sigma - 1.0).abs() < 1e-9,
            "group {}: weight {} against 1 / sigma {}",
            j + 1,
            weights[j],
            1.0 / sigma
        );
    }
}

/// A joint whose equations its own parameters fit whole (two rows, two parameters of its
/// own: leverages 2, no degree of freedom left) gets a weight that estimates no noise,
/// and both WLS paths say so for that joint alone; four such rows leave two degrees of
/// freedom and no warning.
#[test]
fn a_weight_that_estimates_no_noise_is_warned_of() {
    let warned = |last: usize| {
        let counts = [40usize, 40, last];
        let names: Vec<String> = (0..6).map(|i| format!("p{i}")).collect();
        let mut s = StreamingLeastSquares::new(names.clone(), 3).unwrap();
        let (mut rows, mut ys, mut blocks) = (Vec::new(), Vec::new(), Vec::new());
        for (j, &count) in counts.iter().enumerate() {
            let start = rows.len();
            for k in 0..count {
                let t = k as f64 * 0.13 + j as f64;
                let mut row = [0.0; 6];
                row[2 * j] = t.sin();
                row[2 * j + 1] = 1.0 + 0.3 * t.cos();
                let y = 1.5 * t.sin() - 0.5 + 0.01 * (t * 17.1).sin();
                s.push(j, &row, y).unwrap();
                rows.push(row);
                ys.push(y);
            }
            blocks.push(start..rows.len());
        }
        let w = nalgebra::DMatrix::from_fn(rows.len(), 6, |r, c| rows[r][c]);
        let obs = crate::estimate::Observation::new(
            w,
            nalgebra::DVector::from_vec(ys),
            blocks,
            (0..rows.len()).collect(),
            names,
        )
        .unwrap();
        let joints = |e: crate::estimate::Estimate| -> Vec<(usize, usize, f64)> {
            e.warnings
                .iter()
                .filter_map(|w| match *w {
                    crate::estimate::QualityWarning::WeightWithoutNoise {
                        joint,
                        rows,
                        freedom,
                    } => Some((joint, rows, freedom)),
                    _ => None,
                })
                .collect()
        };
        let streamed = joints(s.wls(1e-10).unwrap());
        let in_memory = joints(crate::estimate::wls(&obs, 1e-10).unwrap());
        assert_eq!(streamed.len(), in_memory.len());
        for (a, b) in streamed.iter().zip(&in_memory) {
            assert!(
                a.0 == b.0 && a.1 == b.1 && (a.2 - b.2).abs() < 1e-9,
                "{a:?} {b:?}"
            );
        }
        streamed
    };
    let told = warned(2);
    assert_eq!(told.len(), 1, "{told:?}");
    assert_eq!((told[0].0, told[0].1), (3, 2));
    assert!(told[0].2 < 1e-9, "{told:?}");
    assert!(warned(4).is_empty());
}

/// A column near 1e200 (which the solvers accept): its entry of the unscaled `(W'W)^-1`
/// (1e-400) underflows to 0, and the leverages taken through it lost that column's share
/// and more (measured: the two joints' 0.38 and 0.45, summed 0.84 for 3 parameters, and
/// each joint's WLS sigma was biased low). Taken in the scaled space, both paths give each joint the leverages of the
/// same problem with the column divided by 1e200 (leverages do not depend on a column's
/// unit), computed apart from the solver through the normal equations, and they sum to
/// the 3 parameters; the WLS weights are those of the rescaled problem.
#[test]
fn a_huge_column_keeps_its_leverage() {
    let (mut obs, mut rows) = problem(2, 400, 3, 0.0, 11);
    let tame = obs.clone();
    for r in rows.iter_mut() {
        r.1[1] *= 1e200;
    }
    obs.w.column_mut(1).scale_mut(1e200);
    // independent: (W'W)^-1 of the rescaled columns, x' G x row by row
    let gram = (tame.w.transpose() * &tame.w).try_inverse().unwrap();
    let want: Vec<f64> = tame
        .joint_rows
        .iter()
        .map(|b| {
            b.clone()
                .map(|i| {
                    let x = tame.w.row(i);
                    (x * &gram * x.transpose())[(0, 0)]
                })
                .sum()
        })
        .collect();
    assert!((want.iter().sum::<f64>() - 3.0).abs() < 1e-12, "{want:?}");
    let dense = crate::estimate::lstsq::solve(&obs.w, &obs.y, &obs.names, 1e-12).unwrap();
    let in_memory: Vec<f64> = crate::estimate::least_squares::joint_leverages(&obs, &dense)
        .into_iter()
        .map(|(_, h)| h)
        .collect();
    let mut s = streamed(&obs, &rows);
    s.flush();
    let (_, solution) = s.solve(Estimator::Ols, &[1.0, 1.0], 1e-12).unwrap();
    let streaming: Vec<f64> = s.groups.iter().map(|g| g.leverage(&solution)).collect();
    for (name, got) in [("in memory", &in_memory), ("streaming", &streaming)] {
        assert!(
            (got.iter().sum::<f64>() - 3.0).abs() < 1e-10,
            "{name}: {got:?} sum to 3"
        );
        for (a, b) in got.iter().zip(&want) {
            assert!((a - b).abs() < 1e-10, "{name}: {got:?} against {want:?}");
        }
    }
    // on the rescaled (ordinary) problem, what (W'W)^-1 gave before
    let tame_fit = crate::estimate::lstsq::solve(&tame.w, &tame.y, &tame.names, 1e-12).unwrap();
    for ((_, a), b) in crate::estimate::least_squares::joint_leverages(&tame, &tame_fit)
        .iter()
        .zip(&want)
    {
        assert!((a - b).abs() < 1e-10, "{a} against {b}");
    }
    let weights = |e: Estimate| e.weights.unwrap();
    let rescaled = weights(wls(&tame, 1e-12).unwrap());
    for got in [
        weights(wls(&obs, 1e-12).unwrap()),
        weights(s.wls(1e-12).unwrap()),
    ] {
        for (a, b) in got.iter().zip(&rescaled) {
            assert!(close(*a, *b, 1e-10, 0.0), "{got:?} against {rescaled:?}");
        }
    }
}

/// The condition number of W with unit-norm columns, from both paths (the streaming one
/// from R, whose column norms are W's), is `s_max / s_min` of W with each column divided
/// by its norm, by an SVD of W itself; a column taken in other units (x 1e-3) leaves it as
/// it was (to 1e-10) where the raw condition number moves by a factor of about 1e3.
#[test]
fn the_scaled_condition_number_is_that_of_unit_norm_columns() {
    let (obs, rows) = problem(3, 500, 6, 4.0, 21);
    let independent = |w: &DMatrix<f64>| {
        let mut unit = w.clone();
        for mut c in unit.column_iter_mut() {
            let n = c.norm();
            c /= n;
        }
        let s = unit.singular_values();
        s.max() / s.min()
    };
    let want = independent(&obs.w);
    let fits = |obs: &Observation, rows: &[(usize, Vec<f64>, f64)]| {
        let mut s = streamed(obs, rows);
        [
            ols(obs, 1e-12).unwrap(),
            wls(obs, 1e-12).unwrap(),
            s.ols(1e-12).unwrap(),
            s.wls(1e-12).unwrap(),
        ]
    };
    let before = fits(&obs, &rows);
    // OLS (dense, streaming) against the SVD; WLS is of the weighted W
    for e in [&before[0], &before[2]] {
        let got = e.scaled_condition_number.unwrap();
        assert!(close(got, want, 1e-10, 0.0), "{got} against {want}");
        // the columns' units spread over 4 decades: the raw figure is far above
        assert!(e.condition_number > 10.0 * got, "{}", e.condition_number);
    }
    let (mut other, mut other_rows) = (obs.clone(), rows.clone());
    // the smallest column (1e-2) in a unit a thousand times larger
    other.w.column_mut(0).scale_mut(1e-3);
    for r in other_rows.iter_mut() {
        r.1[0] *= 1e-3;
    }
    assert!(close(independent(&other.w), want, 1e-10, 0.0));
    for (a, b) in before.iter().zip(&fits(&other, &other_rows)) {
        let (x, y) = (
            a.scaled_condition_number.unwrap(),
            b.scaled_condition_number.unwrap(),
        );
        assert!(close(x, y, 1e-10, 0.0), "{x} against {y}");
        let ratio = b.condition_number / a.condition_number;
        assert!(ratio > 100.0, "raw moved by {ratio}");
    }
}
