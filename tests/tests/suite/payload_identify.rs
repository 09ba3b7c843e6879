//! Payload identification (`robid_runtime::payload`, docs/identification.md#payload-identification)
//! on data with a known payload:
//!
//! - from joint torques: a simulated UR5e whose truth is the reference parameters with a
//!   payload added to link 6's standard parameters, closed-loop along a random Fourier
//!   trajectory with torque noise; the model without the payload is known;
//! - from a wrist force-torque sensor: synthetic wrench samples of the payload at random
//!   link states, with noise;
//!
//! and the errors for data that do not excite the payload.

use robid_runtime::Model;
use robid_runtime::feasible::LinkInertial;
use robid_runtime::payload::{
    JointSample, Payload, PayloadOptions, WrenchSample, from_torques, from_wrenches,
    last_link_columns,
};
use robid_runtime::rng::Rng;
use robid_runtime::simulate::{Noise, Record, Simulation};
use robid_runtime::wrench::{apply, wrench_matrix};
use robid_symbolic::Drive;
use robots::Ur5e;
use tests::reference::by_name;

/// A 2 kg gripper, its centre of mass 6 cm out along the flange axis.
fn gripper() -> LinkInertial {
    LinkInertial {
        mass: 2.0,
        com: [0.01, -0.02, 0.06],
        inertia: [
            [0.006, 0.0005, 0.0],
            [0.0005, 0.007, 0.0003],
            [0.0, 0.0003, 0.004],
        ],
    }
}

/// The UR5e's reference standard parameters (no drive terms).
fn reference() -> Vec<f64> {
    let r = by_name("ur5e");
    r.parameter_values(&r.robot().with_drive(Drive::NONE))
}

fn base(model: &Ur5e, standard: &[f64]) -> Vec<f64> {
    let mut base = vec![0.0; model.base_parameter_count()];
    model.base_from_standard_into(standard, &mut base).unwrap();
    base
}

/// A closed-loop run of the UR5e carrying `payload`, with torque noise.
fn simulate_with(model: &Ur5e, payload: &LinkInertial, seed: u64) -> Record {
    let mut truth = reference();
    let columns = last_link_columns(model).unwrap();
    for (c, p) in columns.iter().zip(payload.to_standard()) {
        truth[*c] += p;
    }
    let trajectory = tests::reference::random_fourier("ur5e", seed, 20.0, 100.0);
    Simulation {
        noise: Noise {
            torque: vec![0.8, 0.8, 0.4, 0.1, 0.1, 0.05],
            position: 1e-5,
            ..Noise::default()
        },
        seed,
        ..Simulation::default()
    }
    .run(model, &base(model, &truth), &trajectory)
    .unwrap()
    .measured
}

fn samples(record: &Record) -> Vec<JointSample> {
    let n = record.trajectory.dof();
    (0..record.trajectory.samples())
        .map(|k| {
            let (mut q, mut qd, mut qdd) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
            record.trajectory.state(k, &mut q, &mut qd, &mut qdd);
            JointSample {
                q,
                qd,
                qdd,
                tau: record.tau.sample(k),
            }
        })
        .collect()
}

/// How many of the ten values lie within three standard deviations of the truth.
fn within_three_sigma(p: &Payload, truth: &[f64; 10]) -> usize {
    let (v, s) = (p.parameters(), p.std());
    (0..10)
        .filter(|&k| (v[k] - truth[k]).abs() <= 3.0 * s[k])
        .count()
}

#[test]
fn payload_from_ur5e_joint_torques_recovers_the_mass_within_three_sigma() {
    let model = Ur5e;
    let record = simulate_with(&model, &gripper(), 21);
    let known = base(&model, &reference());
    let p = from_torques(
        &model,
        &known,
        &samples(&record),
        &PayloadOptions::default(),
    )
    .unwrap();
    let truth = gripper().to_standard();
    let (v, s) = (p.parameters(), p.std());
    let com = p.consistency.physical.map(|l| l.com);
    println!(
        "UR5e payload from torques: mass {:.4} +- {:.4} kg (truth 2), centre of mass {com:?}, \
         {} of 10 within 3 sigma, consistent: {}",
        v[9],
        s[9],
        within_three_sigma(&p, &truth),
        p.consistency.is_consistent()
    );
    // Measured: mass 1.9992 +- 0.0019 kg, centre of mass (0.0099, -0.0200, 0.0601) m, all
    // ten within 3 sigma, consistent. Bounds: 3 sigma, and twice the measured sigma.
    assert!((v[9] - 2.0).abs() <= 3.0 * s[9], "{} +- {}", v[9], s[9]);
    assert!(s[9] < 0.004, "mass standard deviation {}", s[9]);
    assert!(
        (v[8] - truth[8]).abs() <= 3.0 * s[8],
        "MZ {} +- {}",
        v[8],
        s[8]
    );
    assert!(within_three_sigma(&p, &truth) >= 9);
}

#[test]
fn payload_from_a_wrist_sensor_recovers_all_ten_parameters() {
    let truth = gripper().to_standard();
    let mut rng = Rng::new(3);
    let samples: Vec<WrenchSample> = (0..500)
        .map(|_| {
            let mut v = |s: f64| [0; 3].map(|_| rng.uniform(-s, s));
            let (omega, omegadot, vdot) = (v(2.0), v(10.0), v(5.0));
            // Gravity seen by a wrist in a random orientation.
            let gravity = {
                let d = v(1.0);
                let n = d.iter().map(|x| x * x).sum::<f64>().sqrt().max(1e-3);
                d.map(|x| 9.81 * x / n)
            };
            let mut wrench = apply(&wrench_matrix(&omega, &omegadot, &vdot, &gravity), &truth);
            // Sensor noise: 0.3 N on forces, 0.01 N m on moments.
            for (r, w) in wrench.iter_mut().enumerate() {
                *w += if r < 3 { 0.3 } else { 0.01 } * rng.normal();
            }
            WrenchSample {
                omega,
                omegadot,
                vdot,
                gravity,
                wrench,
            }
        })
        .collect();
    let p = from_wrenches(&samples, &PayloadOptions::default()).unwrap();
    let (v, s) = (p.parameters(), p.std());
    println!(
        "payload from wrenches: mass {:.4} +- {:.4} kg, XX {:.5} +- {:.5} (truth {:.5}), \
         {} of 10 within 3 sigma, weights {:?}",
        v[9],
        s[9],
        v[0],
        s[0],
        truth[0],
        within_three_sigma(&p, &truth),
        p.estimate.weights
    );
    // Measured: mass 2.0008 +- 0.0012 kg, XX 0.01400 +- 0.00007 kg m^2, all ten within
    // 3 sigma. Bounds: 3 sigma, and twice the measured sigma.
    assert!((v[9] - 2.0).abs() <= 3.0 * s[9]);
    assert!(s[9] < 0.0025, "mass standard deviation {}", s[9]);
    assert!(within_three_sigma(&p, &truth) >= 9);
    assert!(
        p.consistency.is_consistent(),
        "{:?}",
        p.consistency.problems
    );
}

#[test]
fn payload_held_still_is_a_rank_error_naming_the_inertia() {
    // At rest only the weight and its moment show: the inertia is not excited.
    let truth = gripper().to_standard();
    let gravity = [0.0, 0.0, -9.81];
    let samples: Vec<WrenchSample> = (0..20)
        .map(|_| WrenchSample {
            omega: [0.0; 3],
            omegadot: [0.0; 3],
            vdot: [0.0; 3],
            gravity,
            wrench: apply(
                &wrench_matrix(&[0.0; 3], &[0.0; 3], &[0.0; 3], &gravity),
                &truth,
            ),
        })
        .collect();
    let e = from_wrenches(&samples, &PayloadOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("not excited"), "{e}");
    assert!(e.contains("XX") && e.contains("ZZ"), "{e}");

    // A robot at rest: the same from joint torques.
    let model = Ur5e;
    let known = base(&model, &reference());
    let rest: Vec<JointSample> = (0..20)
        .map(|_| JointSample {
            q: vec![0.1, -1.0, 1.2, -0.5, 0.3, 0.2],
            qd: vec![0.0; 6],
            qdd: vec![0.0; 6],
            tau: vec![1.0; 6],
        })
        .collect();
    let e = from_torques(&model, &known, &rest, &PayloadOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("not excited") && e.contains("XX"), "{e}");
}

#[test]
fn payload_sample_of_the_wrong_size_is_an_error_naming_it() {
    let model = Ur5e;
    let known = base(&model, &reference());
    let bad = vec![JointSample {
        q: vec![0.0; 6],
        qd: vec![0.0; 6],
        qdd: vec![0.0; 5],
        tau: vec![0.0; 6],
    }];
    let e = from_torques(&model, &known, &bad, &PayloadOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("payload sample 1") && e.contains("qdd"), "{e}");
}
