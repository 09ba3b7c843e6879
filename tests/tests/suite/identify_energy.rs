//! The energy (power balance) model end to end on the UR5e (issue 5,
//! docs/identification.md#energy-model):
//! `identify` with `method = "energy"` builds one equation per window of
//! `estimation.energy_window` seconds,
//! T(t_b) - T(t_a) + integral of g(q).qd dt (+ friction integrals) = integral of tau.qd dt,
//! from the compiled model's base regressor, and solves it by least squares.
//!
//! The records are exact inverse dynamics of the compiled UR5e (reference parameters)
//! along a random Fourier trajectory at 1 kHz, so that the energy identity holds up to the
//! integrals' rule (`estimate::quadrature`, exact for cubics). (The closed-loop simulator integrates with a first-order implicit
//! scheme whose energy error, 0.13 % of the window's work at 10 substeps per millisecond
//! and proportional to the step, biases the energy model beyond its noise; it is fine for
//! the torque model, which holds pointwise.)
//!
//! - noise-free: every one of the 36 base parameters is identified (the energy model sees
//!   all of them: full rank), each within 1e-7 of the largest (the integrals' error times
//!   the condition number; 1e-4 with the trapezoidal rule);
//! - with torque noise that differs between joints, position noise and quantization: the
//!   reported standard deviations are honest (the truth within 3 std for >= 90 % of the
//!   parameters); the parameters that this experiment leaves undetermined (std above
//!   their magnitude) are named in the output.

use robid_runtime::Model;
use robid_runtime::data::{Config, Dataset, Derivative, Method};
use robid_runtime::pipeline::{energy_observation_of, identify, prepare};
use robid_runtime::rng::Rng;
use robid_runtime::signal::Signals;
use robid_runtime::simulate::Trajectory;
use robid_symbolic::Drive;
use robots::Ur5e;
use tests::reference::by_name;

const DURATION: f64 = 60.0;
const RATE: f64 = 1000.0;

fn truth(model: &Ur5e) -> Vec<f64> {
    let r = by_name("ur5e");
    let standard = r.parameter_values(&r.robot().with_drive(Drive::NONE));
    let mut base = vec![0.0; model.base_parameter_count()];
    model.base_from_standard_into(&standard, &mut base).unwrap();
    base
}

fn trajectory(seed: u64) -> Trajectory {
    tests::reference::random_fourier("ur5e", seed, DURATION, RATE)
}

/// Inverse dynamics along the trajectory; `noise` = (torque std per joint, position std,
/// encoder resolution), applied to the measured torques and positions.
fn record(model: &Ur5e, truth: &[f64], seed: u64, noise: Option<([f64; 6], f64, f64)>) -> Dataset {
    let tr = trajectory(seed);
    let n = tr.samples();
    let mut rng = Rng::new(seed);
    let (mut q, mut qd, mut qdd, mut tau) = ([0.0; 6], [0.0; 6], [0.0; 6], [0.0; 6]);
    let mut qs = Signals::zeros(6, n);
    let mut taus = Signals::zeros(6, n);
    for k in 0..n {
        tr.state(k, &mut q, &mut qd, &mut qdd);
        Model::inverse_dynamics_into(model, &q, &qd, &qdd, truth, &mut tau).unwrap();
        for j in 0..6 {
            let (mut x, mut t) = (q[j], tau[j]);
            if let Some((torque, position, step)) = noise {
                t += torque[j] * rng.normal();
                x = (x / step).round() * step + position * rng.normal();
            }
            qs[j][k] = x;
            taus[j][k] = t;
        }
    }
    Dataset::new("ur5e-energy", 1.0 / RATE, qs, taus)
        .unwrap()
        .with_velocities(tr.qd.clone())
        .unwrap()
}

fn config() -> Config {
    let mut c = Config::default();
    c.processing.velocity = Derivative::Data;
    c.estimation.method = Method::Energy;
    c
}

#[test]
fn energy_model_sees_every_base_parameter_of_the_ur5e() {
    let model = Ur5e;
    let truth = truth(&model);
    let data = record(&model, &truth, 11, None);
    let id = identify(&model, &data, &config()).unwrap();
    let e = &id.estimate;
    assert_eq!(e.names.len(), 36);
    let scale = truth.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let worst = (0..truth.len())
        .map(|i| (e.values[i] - truth[i]).abs())
        .fold(0.0, f64::max);
    println!(
        "energy model, noise-free: {} windows, cond {:.0}, worst error {worst:.2e} (scale {scale:.2}), torque fit {:.2e}",
        e.rows, e.condition_number, id.fit.relative_error
    );
    // the integrals' rule leaves < 1e-9 of the work in each equation (checked below);
    // times a condition number of a few 1e4 that bounds the parameter error by ~1e-5
    // (measured: 6.0e-9 of 4.21, torque fit 8.3e-8; with the trapezoidal rule 1.13e-4
    // and 2.5e-6)
    assert!(worst < 1e-7 * scale, "worst error {worst}");
    assert!(id.fit.relative_error < 5e-7, "{:?}", id.fit);
    // the equations: the truth satisfies them up to the integrals' rule
    let prepared = prepare(&data, &config()).unwrap();
    let obs = energy_observation_of(&model, &prepared, &config()).unwrap();
    let r = &obs.y - &obs.w * nalgebra::DVector::from_column_slice(&truth);
    assert!(
        r.norm() < 1e-9 * obs.y.norm(),
        "{} of {}",
        r.norm(),
        obs.y.norm()
    );
}

#[test]
fn energy_model_statistics_are_honest_with_noise() {
    let model = Ur5e;
    let truth = truth(&model);
    let noise = (
        [0.8, 0.8, 0.4, 0.1, 0.1, 0.05],
        1e-5,
        std::f64::consts::TAU / f64::from(1 << 20),
    );
    let data = record(&model, &truth, 12, Some(noise));
    let energy = identify(&model, &data, &config()).unwrap();
    let e = &energy.estimate;
    println!(
        "energy model, noisy: {} windows, cond {:.0}, torque fit {:.2} %",
        e.rows,
        e.condition_number,
        100.0 * energy.fit.relative_error
    );
    let mut inside = 0;
    let mut undetermined = Vec::new();
    for (i, t) in truth.iter().enumerate() {
        let z = (e.values[i] - t) / e.std[i];
        inside += usize::from(z.abs() <= 3.0);
        if e.std[i] > e.values[i].abs().max(t.abs()) {
            undetermined.push(e.names[i].clone());
        }
        println!(
            "{:6} {:>10.5} +- {:<9.5} truth {:>10.5} ({z:+.2} std)",
            e.names[i], e.values[i], e.std[i], t
        );
    }
    println!(
        "undetermined by the energy model in this experiment (std above the magnitude): {}",
        undetermined.join(" ")
    );
    let coverage = inside as f64 / truth.len() as f64;
    // a 3-std interval holds the truth with probability 0.997 when the statistics are
    // honest; 0.9 of 36 leaves room for the correlated estimates of one record
    assert!(coverage >= 0.9, "coverage {coverage}");
    // the large, well-excited ones are determined
    for name in ["ZZR1", "MXR2", "MXR3"] {
        assert!(
            !undetermined.iter().any(|n| n == name),
            "{name} undetermined"
        );
    }
}
