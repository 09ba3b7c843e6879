use super::*;
use crate::estimate::ols;

/// Two joints of `k` samples; columns `a` (joint 1 only), `b` and `c` (both joints, with
/// joint 2's entries of `c` equal to `ratio` times those of `b`).
fn system(k: usize, ratio: Option<f64>, zero_a: bool) -> Observation {
    let mut w = DMatrix::zeros(2 * k, 3);
    for s in 0..k {
        let x = s as f64 * 0.37;
        w[(s, 0)] = if zero_a { 0.0 } else { x.sin() };
        w[(s, 1)] = (1.3 * x).cos();
        w[(s, 2)] = 1.0;
        w[(k + s, 1)] = (0.7 * x).sin();
        w[(k + s, 2)] = match ratio {
            Some(r) => r * (0.7 * x).sin(),
            None => (1.9 * x).cos(),
        };
    }
    let y = &w * DVector::from_column_slice(&[1.0, -2.0, 0.5]);
    Observation::new(
        w,
        y,
        vec![0..k, k..2 * k],
        (0..k).chain(0..k).collect(),
        vec!["a".into(), "b".into(), "c".into()],
    )
    .unwrap()
}

#[test]
fn zomaya_link_by_link_small_system_steps_and_values() {
    let obs = system(200, None, false);
    assert_eq!(
        link_by_link_steps(&obs, 1e-10).unwrap(),
        vec![vec![0], vec![1, 2]]
    );
    let e = link_by_link(&obs, 1.0, 1e-10).unwrap();
    let o = ols(&obs, 1e-10).unwrap();
    // exact data: OLS gives the truth to rounding (measured 1.3e-15); link by link up to
    // the start P(0) = 1e8 I on unit-RMS columns, which pulls a one-column step toward 0 by
    // a factor 1 / (1 + 1e8 * 200 rows), 5e-11 (measured 4.0e-11 for `a`; 1.0e-10 and
    // 2.6e-11 for `b` and `c`, a two-column step, plus what `a`'s error passes on)
    for (i, truth) in [1.0, -2.0, 0.5].into_iter().enumerate() {
        assert!((e.values[i] - truth).abs() < 2e-10, "{:?}", e.values);
        assert!((o.values[i] - truth).abs() < 1e-14, "{:?}", o.values);
    }
}

#[test]
fn zomaya_link_by_link_names_what_a_step_cannot_see() {
    // b and c are collinear in joint 2's rows: the whole system has full rank (joint 1
    // separates them), but the step of joint 2 cannot
    let obs = system(200, Some(2.0), false);
    assert!(ols(&obs, 1e-10).is_ok());
    let e = link_by_link(&obs, 1.0, 1e-10).unwrap_err().to_string();
    assert!(
        e.contains("rank-deficient") && e.contains('b') && e.contains('c'),
        "{e}"
    );
    // a column zero everywhere is never estimated
    let obs = system(200, None, true);
    let e = link_by_link_steps(&obs, 1e-10).unwrap_err().to_string();
    assert!(
        e.contains("rank 2 of 3") && e.contains("not excited: a"),
        "{e}"
    );
    // settings
    let obs = system(200, None, false);
    assert!(link_by_link(&obs, 0.0, 1e-10).is_err());
    assert!(link_by_link(&obs, 1.0, f64::NAN).is_err());
}

/// Two joints with `rows[j]` equations: `a` in joint 1's only, `b` in both, `d` in joint
/// 2's only (exact data).
fn uneven(rows: [usize; 2]) -> Observation {
    let total = rows[0] + rows[1];
    let mut w = DMatrix::zeros(total, 3);
    for s in 0..rows[0] {
        let x = (s + 1) as f64 * 0.37;
        w[(s, 0)] = x.sin();
        w[(s, 1)] = (1.3 * x).cos();
    }
    for s in 0..rows[1] {
        let x = s as f64 * 0.37;
        w[(rows[0] + s, 1)] = (0.7 * x).sin() + 0.2;
        w[(rows[0] + s, 2)] = 1.0;
    }
    let y = &w * DVector::from_column_slice(&[1.0, -2.0, 0.5]);
    Observation::new(
        w,
        y,
        vec![0..rows[0], rows[0]..total],
        (0..rows[0]).chain(0..rows[1]).collect(),
        vec!["a".into(), "b".into(), "d".into()],
    )
    .unwrap()
}

/// A joint left with too few equations while another has more lost them (in the pipeline
/// to processing.rest_velocity): the error names the joint and the fix; it was the step's
/// "least squares with 2 parameters: 1 samples, at least 2 are needed; use more data, less
/// decimation, or fewer parameters", or with none "rank-deficient data: .. not excited: d;
/// use a richer trajectory". A record too short for every joint keeps the old hint.
#[test]
fn zomaya_link_by_link_names_a_joint_whose_equations_were_removed() {
    use crate::estimate::Estimator;
    for (rows, found, required) in [([200, 0], 0, 1), ([200, 1], 1, 2)] {
        let e = link_by_link(&uneven(rows), 1.0, 1e-10).unwrap_err();
        assert!(
            matches!(e, Error::Estimate(EstimateError::AxisLacksEquations {
                method: Estimator::LinkByLink, joint: 2, found: f, required: r, most: 200 })
                if (f, r) == (found, required)),
            "{e:?}"
        );
        let message = e.to_string();
        assert!(
            message.starts_with("link-by-link identification: joint 2 has ")
                && message.contains(
                    "it estimates each link's parameters from its own joint's equations: move \
                     joint 2 in the trajectory, or lower processing.rest_velocity for it"
                ),
            "{message}"
        );
        assert!(!message.contains("more data"), "{message}");
    }
    let message = link_by_link(&uneven([200, 1]), 1.0, 1e-10)
        .unwrap_err()
        .to_string();
    assert!(
        message.contains(
            "joint 2 has 1 equations, fewer than the 2 parameters its step estimates, while \
             another joint has 200"
        ),
        "{message}"
    );
    // every joint as short: the record is too short
    let message = link_by_link(&uneven([1, 1]), 1.0, 1e-10)
        .unwrap_err()
        .to_string();
    assert!(message.contains("use more data"), "{message}");
    // enough on each joint, however uneven: solved
    let e = link_by_link(&uneven([200, 3]), 1.0, 1e-10).unwrap();
    assert!((e.values[2] - 0.5).abs() < 1e-6, "{:?}", e.values);
}
