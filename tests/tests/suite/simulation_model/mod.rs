//! Shared by the simulation and excitation tests: a reference robot's model with chosen drive
//! terms, run by robid-symbolic's program interpreter behind `robid_runtime::Model` (the
//! compiled `robots::*` models carry only the drive terms of their description files), and
//! its reference base parameters with chosen drive values.

#![allow(dead_code)]

use robid_runtime::Model;
use robid_runtime::data::Dataset;
use robid_runtime::excite::JointLimits;
use robid_runtime::simulate::{Noise, Simulation, Trajectory};
use robid_symbolic::Drive;
use robid_symbolic::robot::{DriveTerm, ParameterKind};
use tests::reference::by_name;

pub(crate) mod excitation;

/// The one interpreted-model adapter of the project.
pub(crate) use robots::interpreted::Interpreted;

/// The reference robot `name` with `drive` terms, its reference base parameters (drive values
/// from `drive_value(term, joint)`, joints from 0) and its joint limits.
pub(crate) fn reference(
    name: &str,
    drive: Drive,
    drive_value: impl Fn(DriveTerm, usize) -> f64,
) -> (Interpreted, Vec<f64>, Vec<JointLimits>) {
    let r = by_name(name);
    let robot = r.robot().with_drive(drive);
    let model = Interpreted::new(&robot).expect("derivation");
    let file = r.parameter_file();
    let standard: Vec<f64> = robot
        .standard_parameters()
        .iter()
        .map(|p| match (file.get(&p.to_string()), p.kind) {
            (Some(v), _) => v,
            (None, ParameterKind::Drive(t)) => drive_value(t, p.link),
            (None, ParameterKind::Inertial(_)) => 0.0,
        })
        .collect();
    let mut base = vec![0.0; model.base_parameter_count()];
    model.base_from_standard_into(&standard, &mut base).unwrap();
    let limits = robot
        .joints()
        .iter()
        .map(|j| JointLimits {
            position: j.limits.position.expect("position limits"),
            velocity: j.limits.velocity.expect("velocity limit"),
            acceleration: j.limits.acceleration.expect("acceleration limit"),
            torque: j.limits.torque,
        })
        .collect();
    (model, base, limits)
}

/// Identification on simulated data and prediction of another simulated run.
#[derive(Debug)]
pub(crate) struct Outcome {
    /// Identified base parameters.
    pub(crate) values: Vec<f64>,
    /// ||beta_hat - beta|| / ||beta||.
    pub(crate) parameter_error: f64,
    /// ||W (beta_hat - beta)|| / ||W beta|| on the validation run: how far the identified
    /// parameters are from the truth where it matters, free of the measurement noise.
    pub(crate) model_error: f64,
    /// Relative torque error on the validation run with the identified parameters.
    pub(crate) validation_error: f64,
    /// The same with the true parameters: the noise floor.
    pub(crate) noise_floor: f64,
}

/// A noisy simulated record of `trajectory` (noise `noise`, seed `seed`).
pub(crate) fn simulated(
    model: &Interpreted,
    truth: &[f64],
    trajectory: &Trajectory,
    noise: &Noise,
    seed: u64,
) -> Dataset {
    Simulation {
        noise: noise.clone(),
        seed,
        ..Simulation::default()
    }
    .run(model, truth, trajectory)
    .expect("simulation")
    .measured
    .dataset("sim")
    .expect("data set")
}

/// The validation records of [`mean_outcome`] with `seeds` noise seeds: `valid` simulated
/// with seed 12 + 2 s for s = 0..seeds. The same for every trajectory compared on them, so
/// they are simulated once (the closed-loop simulation is most of the comparison's time).
pub(crate) fn validation_records(
    model: &Interpreted,
    truth: &[f64],
    valid: &Trajectory,
    noise: &Noise,
    seeds: u64,
) -> Vec<Dataset> {
    (0..seeds)
        .map(|s| simulated(model, truth, valid, noise, 12 + 2 * s))
        .collect()
}

/// Simulates `train` with `noise` (seed `seed`), identifies by `method` ("ols" or "wls")
/// from it (velocities and accelerations as recorded) and predicts the validation record
/// `vdata`.
pub(crate) fn identify_and_validate(
    model: &Interpreted,
    truth: &[f64],
    train: &Trajectory,
    vdata: &Dataset,
    noise: &Noise,
    method: &str,
    seed: u64,
) -> Outcome {
    use robid_runtime::data::Config;
    use robid_runtime::pipeline::{identify, validate};
    let config = Config::from_toml_str(
        &format!(
            "[processing]\nvelocity = \"data\"\nacceleration = \"data\"\n[estimation]\nmethod = \"{method}\"\n"
        ),
        std::path::Path::new("simulated.toml"),
    )
    .expect("config");
    let data = simulated(model, truth, train, noise, seed);
    let id = identify(model, &data, &config).expect("identification");
    let error = |beta: &[f64]| {
        validate(model, vdata, &config, beta)
            .expect("validation")
            .fit()
            .relative_error
    };
    let values = id.estimate.values.clone();
    let predict = |beta: &[f64]| -> Vec<f64> {
        validate(model, vdata, &config, beta)
            .expect("validation")
            .predicted
            .concat()
    };
    let (p_hat, p_true) = (predict(&values), predict(truth));
    let d: Vec<f64> = p_hat.iter().zip(&p_true).map(|(a, b)| a - b).collect();
    let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
    let diff: Vec<f64> = values.iter().zip(truth).map(|(a, b)| a - b).collect();
    Outcome {
        parameter_error: norm(&diff) / norm(truth),
        model_error: norm(&d) / norm(&p_true),
        validation_error: error(&values),
        noise_floor: error(truth),
        values,
    }
}

/// The mean of [`identify_and_validate`] over the noise seeds of `validation` (from
/// [`validation_records`]; training seed 11 + 2 s): (parameter error, model error,
/// validation error, noise floor).
pub(crate) fn mean_outcome(
    model: &Interpreted,
    truth: &[f64],
    train: &Trajectory,
    validation: &[Dataset],
    noise: &Noise,
    method: &str,
) -> [f64; 4] {
    let mut sum = [0.0; 4];
    let seeds = validation.len() as f64;
    for (s, vdata) in (0..).zip(validation) {
        let o = identify_and_validate(model, truth, train, vdata, noise, method, 11 + 2 * s);
        for (a, b) in sum.iter_mut().zip([
            o.parameter_error,
            o.model_error,
            o.validation_error,
            o.noise_floor,
        ]) {
            *a += b / seeds;
        }
    }
    sum
}

/// The expected relative parameter error of weighted least squares on `trajectory` with
/// torque noise `sigma` per joint: sqrt(trace((W' S^-1 W)^-1)) / ||beta||, S = diag(sigma^2)
/// (what a design does for the estimate, free of any one noise draw).
pub(crate) fn expected_error(
    model: &Interpreted,
    truth: &[f64],
    trajectory: &Trajectory,
    sigma: &[f64],
) -> f64 {
    let weights: Vec<f64> = sigma.iter().map(|s| 1.0 / s).collect();
    let mut info = robid_runtime::excite::Information::new(model).with_weights(&weights);
    info.add_trajectory(model, trajectory, 1).unwrap();
    let g = info.gram.clone().lower_triangle() + info.gram.clone().lower_triangle().transpose()
        - nalgebra::DMatrix::from_diagonal(&info.gram.diagonal());
    let inverse = g
        .try_inverse()
        .expect("the trajectory excites every base parameter");
    let norm = truth.iter().map(|x| x * x).sum::<f64>().sqrt();
    inverse.trace().sqrt() / norm
}
