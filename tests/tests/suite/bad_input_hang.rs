//! Class "hangs" of issue 11: one finite but huge sample (qdd1 = 1e200 in one row of a good
//! file) left `identify` at 100 % CPU for ever inside the SVD, for ols, wls and rls alike.
//! Now the value is rejected at load time naming its row and column, and the estimators
//! themselves finish on such an entry (column scaling, a capped SVD); every iterative loop
//! stops at a documented cap.

use robid_runtime::DataError;
use robid_runtime::EstimateError;
use tests::fuzz_data;
use tests::scratch::Scratch;

use std::sync::mpsc;
use std::time::Duration;

use nalgebra::{DMatrix, DVector};
use robid_runtime::Error;
use robid_runtime::data::{Config, Dataset, Method, load};
use robid_runtime::estimate::{Observation, ols, per_axis, rls, wls};
use robid_runtime::excite::FourierDesign;
use robid_runtime::feasible::AnnealOptions;
use robid_runtime::nelder_mead::NelderMead;
use robid_runtime::signal::Signals;
use robid_runtime::simulate::{Simulation, Trajectory};
use robots::Ur5e;

/// Runs `f` on a thread and fails the test when it takes more than `seconds`.
fn within<T: Send + 'static>(
    seconds: u64,
    what: &str,
    f: impl FnOnce() -> T + Send + 'static,
) -> T {
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        let _ = tx.send(f());
    });
    rx.recv_timeout(Duration::from_secs(seconds))
        .unwrap_or_else(|_| panic!("{what} did not finish within {seconds} s"))
}

/// The reported case: qdd1 = 1e200 in one row, for every method: an error at load time
/// naming the file, the line and the column, and the range; never a hang, never "use a
/// richer trajectory".
#[test]
fn a_huge_sample_is_named_at_load_time_for_every_method() {
    let tmp = Scratch::new();
    let csv = fuzz_data::motion_csv(&fuzz_data::motion(400));
    let mut lines: Vec<String> = csv.lines().map(str::to_string).collect();
    // data row 57 is line 58 of the file (the header is line 1)
    let mut fields: Vec<String> = lines[57].split(',').map(str::to_string).collect();
    fields[13] = "1e200".into(); // t, q1..6, qd1..6, qdd1
    lines[57] = fields.join(",");
    let file = tmp.path("huge.csv");
    std::fs::write(&file, lines.join("\n")).unwrap();
    for method in [
        Method::Ols,
        Method::Wls,
        Method::Rls,
        Method::Energy,
        Method::LinkByLink,
        Method::PerAxis,
    ] {
        let mut config = Config::default_mapping();
        config.estimation.method = method;
        let f = file.clone();
        let e = within(30, "load", move || load(&config, &[f], 6).unwrap_err());
        let text = e.to_string();
        assert!(
            matches!(e, Error::Data(DataError::OutOfRange { .. })),
            "{text}"
        );
        assert!(
            text.contains("huge.csv:58: column `qdd1` is 1e200") && text.contains("<= 1e8"),
            "{text}"
        );
        assert!(!text.contains("richer trajectory"), "{text}");
    }
}

/// The same value in a data set built in code is named by its sample.
#[test]
fn a_huge_sample_in_a_data_set_built_in_code_is_named_by_its_sample() {
    let mut tau = Signals::from_fn(6, 100, |_, _| 1.0);
    tau[2][41] = 1e200;
    let e = Dataset::new("mine", 0.01, Signals::zeros(6, 100), tau).unwrap_err();
    assert_eq!(
        e.to_string(),
        "data set `mine`, sample 41: joint 3 torque (after units and drive chain) is 1e200, \
         outside the accepted range |torque| <= 1e7; repair or remove this row (a value this \
         large is a logging, unit or export error, not a measurement)"
    );
}

/// The estimators finish on an observation with an entry of 1e200 (what once looped in
/// the SVD): column scaling makes the solve exact, the results are finite.
#[test]
fn the_estimators_finish_on_a_huge_entry() {
    let m = 600;
    let mut w = DMatrix::from_fn(m, 4, |i, j| {
        ((i * (j + 3)) as f64 * 0.37).sin() + 0.2 * j as f64
    });
    w[(123, 2)] = 1e200;
    let beta = DVector::from_vec(vec![1.5, -0.5, 2e-200, 3.0]);
    let noise = DVector::from_fn(m, |i, _| 1e-3 * ((i * 7919) as f64).cos());
    let y = &w * &beta + noise;
    let names = vec!["a".to_string(), "b".into(), "c".into(), "d".into()];
    let half = m / 2;
    let obs = Observation::new(
        w,
        y,
        vec![0..half, half..m],
        (0..half).chain(0..half).collect(),
        names,
    )
    .unwrap();
    for (name, run) in [
        (
            "ols",
            ols as fn(&Observation, f64) -> robid_runtime::Result<_>,
        ),
        ("wls", wls),
        ("rls", |o: &Observation, t: f64| rls(o, 1.0, t)),
    ] {
        let o = obs.clone();
        let e = within(30, name, move || run(&o, 1e-10)).unwrap();
        assert!(
            e.values.iter().chain(&e.std).all(|v| v.is_finite()) && e.condition_number.is_finite(),
            "{name}: {e:?}"
        );
        assert!(
            (e.values[0] - 1.5).abs() < 1e-3 && (e.values[3] - 3.0).abs() < 1e-3,
            "{name}: {:?}",
            e.values
        );
        assert!(e.condition_number > 1e150, "{name}: {}", e.condition_number);
    }
    // per-axis: each joint's least squares on its column-scaled rows
    let o = obs.clone();
    let p = within(30, "per-axis", move || per_axis(&o, 1e-10)).unwrap();
    let e = &p.estimate;
    assert!(
        e.values.iter().chain(&e.std).all(|v| v.is_finite()) && e.condition_number.is_finite(),
        "per-axis: {e:?}"
    );
    assert!(
        (e.values[0] - 1.5).abs() < 1e-3 && (e.values[3] - 3.0).abs() < 1e-3,
        "per-axis: {:?}",
        e.values
    );
    // a non-finite entry is named by its equation and column
    let mut w = obs.w.clone();
    w[(7, 1)] = f64::INFINITY;
    let e = Observation::new(
        w,
        obs.y.clone(),
        obs.joint_rows.clone(),
        obs.sample_of_row.clone(),
        obs.names.clone(),
    )
    .unwrap_err();
    assert!(
        matches!(&e, Error::Estimate(EstimateError::NonFiniteObservation { joint: 1, parameter, .. }) if parameter == "b"),
        "{e}"
    );
}

/// Every iterative loop has a cap, and the caps are settings checked before the work.
#[test]
fn every_iterative_loop_stops_at_its_cap() {
    // Nelder-Mead on a function that never converges
    let nm = NelderMead {
        max_evaluations: 500,
        tolerance: 0.0,
        absolute_tolerance: 0.0,
        step: vec![1.0],
    };
    let mut calls = 0usize;
    within(10, "nelder-mead", move || {
        let r = nm.minimize(&[0.0; 4], |x| {
            calls += 1;
            -x.iter().sum::<f64>()
        });
        assert!(r.unwrap().evaluations <= 504 && calls <= 505);
    });
    // optimiser budgets beyond the caps are refused before any work
    let design = FourierDesign {
        evaluations: usize::MAX,
        ..FourierDesign::default()
    };
    let e = design.check(6).unwrap_err();
    assert!(
        e.to_string().starts_with("FourierDesign `evaluations`"),
        "{e}"
    );
    let anneal = AnnealOptions {
        iterations: usize::MAX,
        ..AnnealOptions::default()
    };
    let e = anneal.check().unwrap_err();
    assert!(
        e.to_string().starts_with("AnnealOptions `iterations`"),
        "{e}"
    );
    // a simulation's integration steps are counted before it runs
    let t: Vec<f64> = (0..100_000).map(|k| k as f64 * 1e-3).collect();
    let reference = Trajectory::zeros(6, t);
    let sim = Simulation {
        substeps: 10_000,
        ..Simulation::default()
    };
    let base = fuzz_data::ur5e_base();
    let e = within(10, "simulation", move || {
        sim.run(&Ur5e, &base, &reference).unwrap_err()
    });
    assert!(matches!(e, Error::TooLarge { .. }), "{e}");
    assert!(e.to_string().contains("integration steps"), "{e}");
}
