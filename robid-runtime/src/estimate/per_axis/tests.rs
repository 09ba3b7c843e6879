//! Per-axis identification against each axis solved independently (nalgebra's SVD solve on
//! the axis's own columns) and against known answers.

use nalgebra::{DMatrix, DVector};

use super::per_axis;
use crate::estimate::{Estimator, Observation};
use crate::rng::Rng;

/// Three axes of a serial-like structure: axis 3 sees c, axis 2 sees b and c, axis 1 sees
/// a, b and c (row j depends on links >= j). Axis noise levels `noise`.
fn serial(rng: &mut Rng, rows: usize, truth: [f64; 3], noise: [f64; 3]) -> Observation {
    let mut w = DMatrix::zeros(3 * rows, 3);
    let mut y = DVector::zeros(3 * rows);
    for (j, sigma) in noise.iter().enumerate() {
        for r in 0..rows {
            let i = j * rows + r;
            for c in j..3 {
                w[(i, c)] = rng.uniform(-1.0, 1.0) * (1.0 + c as f64);
            }
            let clean: f64 = (0..3).map(|c| w[(i, c)] * truth[c]).sum();
            y[i] = clean + sigma * rng.normal();
        }
    }
    Observation::new(
        w,
        y,
        (0..3).map(|j| j * rows..(j + 1) * rows).collect(),
        (0..3 * rows).map(|i| i % rows).collect(),
        vec!["a".into(), "b".into(), "c".into()],
    )
    .unwrap()
}

/// The OLS of rows `rows` on columns `cols` alone: values and standard deviations.
fn independent(obs: &Observation, rows: std::ops::Range<usize>, cols: &[usize]) -> Vec<(f64, f64)> {
    let w = DMatrix::from_fn(rows.len(), cols.len(), |r, c| {
        obs.w[(rows.start + r, cols[c])]
    });
    let y = obs.y.rows(rows.start, rows.len()).into_owned();
    let beta = w.clone().svd(true, true).solve(&y, 1e-14).unwrap();
    let sigma2 = (&y - &w * &beta).norm_squared() / (rows.len() - cols.len()) as f64;
    let inv = (w.transpose() * &w).try_inverse().unwrap();
    (0..cols.len())
        .map(|k| (beta[k], (sigma2 * inv[(k, k)]).sqrt()))
        .collect()
}

#[test]
fn milella_per_axis_takes_each_parameter_from_its_best_axis() {
    let mut rng = Rng::new(4);
    let rows = 200;
    // axis 3 is quiet, axis 1 noisy: c from axis 3, b from axis 2, a only from axis 1
    let obs = serial(&mut rng, rows, [1.5, -0.7, 0.4], [0.5, 0.05, 0.01]);
    let p = per_axis(&obs, 1e-10).unwrap();
    assert_eq!(
        p.axes.iter().map(|a| a.joint).collect::<Vec<_>>(),
        [3, 2, 1]
    );
    assert_eq!(p.axes[0].determined, ["c"]);
    assert_eq!(p.axes[1].determined, ["b", "c"]);
    assert_eq!(p.axes[2].determined, ["a", "b", "c"]);
    // each axis's estimates, computed apart
    let axis3 = independent(&obs, 2 * rows..3 * rows, &[2]);
    let axis2 = independent(&obs, rows..2 * rows, &[1, 2]);
    let axis1 = independent(&obs, 0..rows, &[0, 1, 2]);
    let rel = |(v, s): (f64, f64)| s / v.abs();
    // the best of the candidates, by the smallest relative deviation
    let candidates = [
        vec![(1, axis1[0])],
        vec![(1, axis1[1]), (2, axis2[0])],
        vec![(1, axis1[2]), (2, axis2[1]), (3, axis3[0])],
    ];
    for (c, options) in candidates.iter().enumerate() {
        let &(joint, (value, std)) = options
            .iter()
            .min_by(|x, y| rel(x.1).total_cmp(&rel(y.1)))
            .unwrap();
        assert_eq!(p.source[c], joint, "parameter {c}");
        assert!((p.estimate.values[c] - value).abs() < 1e-12 * value.abs());
        assert!(
            (p.estimate.std[c] - std).abs() < 1e-9 * std,
            "{} {std}",
            p.estimate.std[c]
        );
    }
    // with these noise levels: c from the quiet wrist, b from axis 2
    assert_eq!(p.source, [1, 2, 3]);
    // noise-free data give the truth exactly
    let exact = serial(&mut rng, rows, [1.5, -0.7, 0.4], [0.0; 3]);
    let p = per_axis(&exact, 1e-10).unwrap();
    for (v, t) in p.estimate.values.iter().zip([1.5, -0.7, 0.4]) {
        assert!((v - t).abs() < 1e-12, "{v} vs {t}");
    }
}

/// Two columns equal on axis 1 cannot be separated there: axis 1 determines neither, axis 2
/// (where they differ) gives both; when no axis separates them, the error names them.
#[test]
fn milella_per_axis_keeps_only_what_an_axis_determines() {
    let mut rng = Rng::new(9);
    let rows = 50;
    let mut w = DMatrix::zeros(2 * rows, 3);
    for r in 0..rows {
        let x = rng.uniform(-1.0, 1.0);
        w[(r, 0)] = x;
        w[(r, 1)] = x;
        w[(r, 2)] = rng.uniform(-1.0, 1.0);
        w[(rows + r, 0)] = rng.uniform(-1.0, 1.0);
        w[(rows + r, 1)] = rng.uniform(-1.0, 1.0);
    }
    let truth = DVector::from_vec(vec![0.3, 0.9, -2.0]);
    let y = &w * &truth;
    let names: Vec<String> = vec!["a".into(), "b".into(), "c".into()];
    let make = |w: DMatrix<f64>, y: DVector<f64>| {
        Observation::new(
            w,
            y,
            vec![0..rows, rows..2 * rows],
            (0..2 * rows).map(|i| i % rows).collect(),
            names.clone(),
        )
        .unwrap()
    };
    let p = per_axis(&make(w.clone(), y), 1e-10).unwrap();
    assert_eq!(p.axes[1].determined, ["c"]);
    assert_eq!(p.axes[1].rank, 2);
    assert_eq!(p.axes[0].determined, ["a", "b"]);
    assert_eq!(p.source, [2, 2, 1]);
    for (v, t) in p.estimate.values.iter().zip(truth.iter()) {
        assert!((v - t).abs() < 1e-12, "{v} vs {t}");
    }
    // axis 2 no longer separates a and b either
    let mut tied = w;
    for r in rows..2 * rows {
        tied[(r, 1)] = tied[(r, 0)];
    }
    let y = &tied * &truth;
    let e = per_axis(&make(tied, y), 1e-10).unwrap_err().to_string();
    assert!(
        e.contains("no joint's equation alone determines a, b ("),
        "{e}"
    );
}

/// The serial structure of [`serial`] with `rows[j]` equations on axis j + 1 (noise-free).
fn uneven(rows: [usize; 3]) -> Observation {
    let mut rng = Rng::new(11);
    let total: usize = rows.iter().sum();
    let mut w = DMatrix::zeros(total, 3);
    let mut blocks = Vec::new();
    let mut start = 0;
    for (j, &n) in rows.iter().enumerate() {
        for i in start..start + n {
            for c in j..3 {
                w[(i, c)] = rng.uniform(-1.0, 1.0);
            }
        }
        blocks.push(start..start + n);
        start += n;
    }
    let y = &w * DVector::from_vec(vec![1.5, -0.7, 0.4]);
    let samples = blocks.iter().flat_map(|b| 0..b.len()).collect();
    Observation::new(
        w,
        y,
        blocks,
        samples,
        vec!["a".into(), "b".into(), "c".into()],
    )
    .unwrap()
}

/// An axis with too few equations while another has more lost them (to
/// processing.rest_velocity): the error names the joint and the fixes, not the record's
/// length, which it used to blame ("0 samples, at least 1 are needed; use more data or less
/// decimation"); a record too short for every axis keeps that hint.
#[test]
fn an_axis_whose_equations_were_removed_is_named() {
    use crate::EstimateError;
    use crate::error::Error;
    for (rows, joint, found, required) in [([200, 0, 200], 2, 0, 1), ([3, 200, 200], 1, 3, 3)] {
        let e = per_axis(&uneven(rows), 1e-10).unwrap_err();
        assert!(
            matches!(e, Error::Estimate(EstimateError::AxisLacksEquations { method: Estimator::PerAxis, joint: j, found: f, required: r, most: 200 })
                if (j, f, r) == (joint, found, required)),
            "{e:?}"
        );
        let message = e.to_string();
        assert!(!message.contains("more data"), "{message}");
        assert!(
            message.contains(&format!(
                "move joint {joint} in the trajectory, or lower processing.rest_velocity for it"
            )),
            "{message}"
        );
    }
    let message = per_axis(&uneven([200, 0, 200]), 1e-10)
        .unwrap_err()
        .to_string();
    assert!(
        message.starts_with(
            "per-axis identification: joint 2 has no equations, while another joint has 200: \
             all of them were removed, as processing.rest_velocity removes a joint's equations \
             where its |velocity| is below it (the joint is at rest in the whole record"
        ),
        "{message}"
    );
    let message = per_axis(&uneven([2, 200, 200]), 1e-10)
        .unwrap_err()
        .to_string();
    assert!(
        message.starts_with(
            "per-axis identification: joint 1 has 2 equations, fewer than the 3 parameters of \
             its own equation, while another joint has 200: the others were removed"
        ),
        "{message}"
    );
    // every axis as short: the record is too short (joints 1 and 2 have no more equations
    // than parameters; the axes are solved from the last)
    let message = per_axis(&uneven([2, 2, 2]), 1e-10).unwrap_err().to_string();
    assert_eq!(
        message,
        "the per-axis identification of joint 2: 2 samples, at least 3 are needed; use more \
         data or less decimation"
    );
    // enough equations on each axis (one more than its parameters), however uneven: solved
    let p = per_axis(&uneven([4, 50, 200]), 1e-10).unwrap();
    assert!(
        (p.estimate.values[0] - 1.5).abs() < 1e-12,
        "{:?}",
        p.estimate
    );
}

/// Torques near 1e-170 (W the same, y and the truth scaled): every value and deviation is
/// the unscaled one times the scale, and so is each axis's residual RMS. The residual's
/// squares underflowed, and every deviation read 0 (exact).
#[test]
fn tiny_torques_keep_their_deviations() {
    let scale = 1e-170;
    let plain = serial(&mut Rng::new(4), 100, [1.5, -0.7, 0.4], [0.5, 0.05, 0.01]);
    let mut tiny = plain.clone();
    tiny.y *= scale;
    let (p, t) = (
        per_axis(&plain, 1e-10).unwrap(),
        per_axis(&tiny, 1e-10).unwrap(),
    );
    let near = |a: f64, b: f64| (a * scale - b).abs() <= 1e-12 * b.abs();
    for k in 0..3 {
        assert!(
            near(p.estimate.values[k], t.estimate.values[k]),
            "value {k}"
        );
        assert!(
            near(p.estimate.std[k], t.estimate.std[k]),
            "std {k}: {} against {}",
            t.estimate.std[k],
            p.estimate.std[k] * scale
        );
    }
    for (a, b) in p.axes.iter().zip(&t.axes) {
        assert!(near(a.residual_rms, b.residual_rms), "axis {}", a.joint);
    }
}
