//! Class "results" of issue 11: a successful run never returns NaN or an infinity; a
//! non-finite or runaway result is a named error pointing at its cause.
//!
//! - `simulate` with a bandwidth of 1000 Hz on a 100 Hz trajectory diverged to 1.5e31 N m
//!   and reported success: now the divergence is detected and blamed on the bandwidth, and
//!   a loop too fast for the finest integration step is refused before the first step;
//! - `feasible` given an identified value of 1e308 wrote "chi^2 = 0": the inputs are checked
//!   (values and deviations finite and in range, deviations positive) and so is the result;
//! - `--sigma 0` reported "weights: [inf, ...]": a zero noise is refused by name;
//! - torques that are all zero give an error that says so, not an infinite relative error.

use robid_runtime::SimulateError;
use tests::fuzz_data;
use tests::scratch::Scratch;

use robid_runtime::Error;
use robid_runtime::data::{Config, load};
use robid_runtime::excite::{FourierDesign, weights_from_sigma};
use robid_runtime::feasible::{AnnealOptions, Bounds, Problem, solve_anneal};
use robid_runtime::pipeline::identify;
use robid_runtime::simulate::{Simulation, Trajectory};
use robots::Ur5e;

/// The generated motion as a reference trajectory at 100 Hz.
fn reference(rows: usize) -> Trajectory {
    let m = fuzz_data::motion(rows);
    let [q, qd, qdd, _] = m.signals;
    Trajectory { t: m.t, q, qd, qdd }
}

#[test]
fn a_diverging_simulation_is_an_error_that_blames_the_bandwidth() {
    let base = fuzz_data::ur5e_base();
    let r = reference(300);
    // a loop so fast that even the finest Runge-Kutta split of a substep cannot follow it
    let fast = Simulation {
        bandwidth: 1e6,
        ..Simulation::default()
    };
    let e = fast.run(&Ur5e, &base, &r).unwrap_err();
    let text = e.to_string();
    // refused before the first step (it diverged first, then was blamed on the bandwidth)
    assert!(
        matches!(e, Error::Simulate(SimulateError::TooStiff { .. })),
        "{text}"
    );
    assert!(
        text.contains("at t = 0 s")
            && text.contains("the controller bandwidth, 1e6 Hz, makes most of it")
            && text.contains("lower the bandwidth (--bandwidth) below about"),
        "{text}"
    );
    // the default bandwidth tracks, and the record is finite
    let ok = Simulation::default().run(&Ur5e, &base, &r).unwrap();
    assert!(
        ok.measured
            .tau
            .joints()
            .chain(&ok.measured.trajectory.q)
            .flatten()
            .all(|v| v.is_finite() && v.abs() < 1e3)
    );
}

fn problem() -> Problem {
    Problem::from_model(&Ur5e).unwrap()
}

#[test]
fn feasible_inputs_and_outputs_are_checked() {
    let p = problem();
    let n = p.base_names.len();
    let base = fuzz_data::ur5e_base();
    // an identified value of 1e308 is refused by name (it once gave "chi^2 = 0")
    let mut values = base.clone();
    values[3] = 1e308;
    let e = p.clone().with_target(&values, &vec![0.01; n]).unwrap_err();
    let text = e.to_string();
    assert!(
        text.contains(&format!("`{}` is 1e308", p.base_names[3])) && text.contains("1e6"),
        "{text}"
    );
    // deviations: negative and infinite are refused; zero (a parameter known exactly) and a
    // tiny one are handled by the documented floor
    let mut std = vec![0.01; n];
    std[5] = -0.01;
    assert!(p.clone().with_target(&base, &std).is_err());
    std[5] = 0.0;
    assert!(p.clone().with_target(&base, &std).is_ok());
    std[5] = f64::INFINITY;
    assert!(p.clone().with_target(&base, &std).is_err());
    std[5] = 1e-300;
    let p = p.with_target(&base, &std).unwrap();
    let options = AnnealOptions {
        restarts: 1,
        iterations: 300,
        local_evaluations: 300,
        polish_iterations: 5,
        hops: 0,
        ..AnnealOptions::default()
    };
    let s = solve_anneal(&p, &Bounds::wide(6), &options).unwrap();
    assert!(s.chi2.is_finite() && s.chi2 > 0.0, "{}", s.chi2);
    assert!(s.standard.iter().chain(&s.base).all(|v| v.is_finite()));
}

#[test]
fn a_zero_torque_noise_is_refused_by_name_not_turned_into_infinite_weights() {
    let e = weights_from_sigma(&[0.5, 0.0, 0.2], "excite", "sigma").unwrap_err();
    let text = e.to_string();
    assert!(
        text.starts_with("excite `sigma`: joint 2 has 0") && text.contains("infinite"),
        "{text}"
    );
    assert_eq!(
        weights_from_sigma(&[0.5, 0.25], "excite", "sigma").unwrap(),
        vec![2.0, 4.0]
    );
    let design = FourierDesign {
        weights: Some(vec![1.0, f64::INFINITY, 1.0, 1.0, 1.0, 1.0]),
        ..FourierDesign::default()
    };
    let e = design.check(6).unwrap_err();
    assert!(
        e.to_string()
            .starts_with("FourierDesign `weights`: the weight of joint 2 is inf"),
        "{e}"
    );
}

#[test]
fn all_zero_torques_are_an_error_that_says_so() {
    let tmp = Scratch::new();
    let mut m = fuzz_data::motion(300);
    m.signals[3].joints_mut().flatten().for_each(|v| *v = 0.0);
    let f = tmp.write("still.csv", &fuzz_data::motion_csv(&m));
    let config = Config::default_mapping();
    let data = load(&config, &[f], 6).unwrap();
    let e = identify(&Ur5e, &data, &config).unwrap_err();
    assert!(
        matches!(e, Error::NonFiniteResult { .. })
            && e.to_string().contains("torques are all zero"),
        "{e}"
    );
}
