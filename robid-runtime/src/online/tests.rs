use super::*;
use crate::estimate::{Observation, Rls, ols};
use crate::rng::Rng;
use nalgebra::{DMatrix, DVector};

const N: usize = 5;

/// A random well-conditioned system: rows of standard normal entries, a known beta,
/// `noise` times standard normal added to y.
fn system(rows: usize, noise: f64, seed: u64) -> (Vec<[f64; N]>, Vec<f64>) {
    let mut rng = Rng::new(seed);
    let truth: [f64; N] = core::array::from_fn(|i| 1.0 + i as f64);
    let phi: Vec<[f64; N]> = (0..rows)
        .map(|_| core::array::from_fn(|_| rng.normal()))
        .collect();
    let y = phi
        .iter()
        .map(|r| dot(r, &truth) + noise * rng.normal())
        .collect();
    (phi, y)
}

#[test]
fn zomaya_online_rls_matches_the_batch_recursion() {
    let (phi, y) = system(400, 0.1, 7);
    for lambda in [1.0, 0.97] {
        let mut online = OnlineRls::<N>::new(lambda, 1e4).unwrap();
        let mut batch = Rls::new(N, lambda, 1e4).unwrap();
        for (r, &v) in phi.iter().zip(&y) {
            online.update(r, v).unwrap();
            batch.update(r, v).unwrap();
        }
        let worst = (0..N)
            .map(|i| (online.estimate()[i] - batch.beta()[i]).abs())
            .fold(0.0, f64::max);
        let worst_p = (0..N * N)
            .map(|k| (online.covariance()[k / N][k % N] - batch.covariance()[(k / N, k % N)]).abs())
            .fold(0.0, f64::max);
        eprintln!("lambda {lambda}: beta {worst:e}, P {worst_p:e}");
        // one update (`online::update_state`) behind both: the same numbers
        assert_eq!(worst, 0.0, "lambda {lambda}: beta differs");
        assert_eq!(worst_p, 0.0, "lambda {lambda}: P differs");
        assert_eq!(online.updates(), 400);
    }
}

#[test]
fn zomaya_online_rls_is_least_squares_for_lambda_one() {
    let (phi, y) = system(300, 0.1, 11);
    let mut online = OnlineRls::<N>::new(1.0, 1e8).unwrap();
    for (r, &v) in phi.iter().zip(&y) {
        online.update(r, v).unwrap();
    }
    let w = DMatrix::from_fn(phi.len(), N, |i, j| phi[i][j]);
    let names = (0..N).map(|i| format!("b{i}")).collect();
    let obs = Observation::single(w, DVector::from_vec(y), names).unwrap();
    let o = ols(&obs, 1e-10).unwrap();
    // P(0) = p0 I regularises: beta_rls = (W'W + I/p0)^-1 W'y, off by at most about
    // |beta| / (p0 * smallest eigenvalue of W'W, ~ 300 (1 - sqrt(5/300))^2 = 228)
    // = 7.4 / 2.3e10 = 3.2e-10; measured 6.0e-11 to 1.4e-10
    for i in 0..N {
        let d = (online.estimate()[i] - o.values[i]).abs();
        assert!(
            d < 2.8e-10,
            "parameter {i}: {} vs {}",
            online.estimate()[i],
            o.values[i]
        );
    }
}

/// The on-line estimator takes the forgetting factors the batch estimator and the config
/// take, `[0.5, 1]`, and no others: it took any in (0, 1], so a factor of 0.1 (or 1e-300)
/// refused by `estimation.forgetting` ran on line and wound up to `P_LIMIT` within a few
/// hundred updates.
#[test]
fn zomaya_online_rls_takes_the_forgetting_factors_of_the_batch_estimator() {
    for lambda in [
        0.0,
        1e-300,
        0.1,
        0.49,
        f64::from_bits(MIN_FORGETTING.to_bits() - 1),
        0.5,
        0.97,
        1.0,
        1.0 + f64::EPSILON,
        f64::NAN,
    ] {
        let online = OnlineRls::<2>::new(lambda, 1.0);
        let batch = crate::estimate::check_forgetting(lambda);
        assert_eq!(online.is_ok(), batch.is_ok(), "lambda {lambda}");
        assert_eq!(
            online.is_ok(),
            forgetting_in_range(lambda),
            "lambda {lambda}"
        );
        assert_eq!(
            online.is_ok(),
            (0.5..=1.0).contains(&lambda),
            "lambda {lambda}"
        );
        if let Err(e) = online {
            assert!(matches!(e, OnlineRlsError::Forgetting(l) if l.to_bits() == lambda.to_bits()));
            let e = e.to_string();
            assert!(e.contains("must satisfy 0.5 <= lambda <= 1"), "{e}");
        }
    }
    assert_eq!(crate::estimate::MIN_FORGETTING, MIN_FORGETTING);
}

#[test]
fn zomaya_online_rls_refuses_bad_input_and_keeps_its_state() {
    assert_eq!(
        OnlineRls::<2>::new(0.0, 1.0),
        Err(OnlineRlsError::Forgetting(0.0))
    );
    assert!(OnlineRls::<2>::new(1.5, 1.0).is_err());
    // an extreme value is written short, not with its 300 digits
    let e = OnlineRls::<2>::new(-1e-300, 1.0).unwrap_err().to_string();
    assert!(e.starts_with("the forgetting factor -1e-300 must"), "{e}");
    assert!(OnlineRls::<2>::new(f64::NAN, 1.0).is_err());
    assert_eq!(
        OnlineRls::<2>::new(1.0, -1.0),
        Err(OnlineRlsError::InitialCovariance(-1.0))
    );
    assert!(OnlineRls::<2>::new(1.0, f64::INFINITY).is_err());

    let mut rls = OnlineRls::<2>::new(1.0, 1e3).unwrap();
    rls.update(&[1.0, 2.0], 3.0).unwrap();
    let before = rls.clone();
    assert_eq!(
        rls.update(&[1.0, f64::NAN], 1.0),
        Err(OnlineRlsError::NonFinite {
            what: "phi",
            index: 1
        })
    );
    assert_eq!(
        rls.update(&[1.0, 1.0], f64::INFINITY),
        Err(OnlineRlsError::NonFinite {
            what: "y",
            index: 0
        })
    );
    let short = rls.update_rows(&[1.0, 2.0, 3.0], &[1.0, 2.0]);
    assert!(matches!(short, Err(OnlineRlsError::Length(_))), "{short:?}");
    assert_eq!(rls, before);
    assert!(rls.update_rows(&[1.0, 2.0, 3.0, 4.0], &[1.0, 2.0]).is_ok());
    assert_eq!(rls.updates(), 3);
}

#[test]
fn zomaya_online_rls_stops_before_winding_up() {
    // the second parameter is never excited: with lambda = 0.5 its P doubles every update,
    // from 1 to past P_LIMIT = 1e150 after log2(1e150) = 498.3 updates
    let mut rls = OnlineRls::<2>::new(0.5, 1.0).unwrap();
    let mut accepted = 0;
    let error = loop {
        match rls.update(&[1.0, 0.0], 2.0) {
            Ok(_) => accepted += 1,
            Err(e) => break e,
        }
        assert!(accepted < 1000, "no wind-up detected");
    };
    assert!(matches!(error, OnlineRlsError::WindUp(_)), "{error}");
    assert_eq!(accepted, 498);
    assert!(rls.estimate().iter().all(|v| v.is_finite()));
    assert!((rls.estimate()[0] - 2.0).abs() < 1e-12);
    rls.reset();
    assert_eq!(rls.covariance(), &[[1.0, 0.0], [0.0, 1.0]]);
}
