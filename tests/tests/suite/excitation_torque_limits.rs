//! Torque limits in both exciting-trajectory designs: the one limit not held by construction,
//! so the designs penalise its excess. On the UR5e (rigid body, reference parameters, from a
//! pose near upright) with joint 2 limited to 40 N m, a design that ignores the torques
//! exceeds that limit (measured: 74 N m points, 72 N m Fourier), and the same design with
//! the reference parameters keeps every torque within every limit on the sampled trajectory
//! (39.4 and 37.9 N m).

use crate::simulation_model;

use robid_runtime::Model;
use robid_runtime::excite::{FourierDesign, JointLimits, PointDesign, assess};
use robid_runtime::simulate::Trajectory;
use robid_symbolic::Drive;
use simulation_model::{Interpreted, reference};

const START: [f64; 6] = [0.0, -1.5, 0.0, -1.5, 0.0, 0.0];
const LIMIT: f64 = 40.0;
const RATE: f64 = 200.0;

/// The UR5e's published limits with joint 2's torque lowered to `LIMIT`.
fn setup() -> (Interpreted, Vec<f64>, Vec<JointLimits>) {
    let (model, truth, mut limits) = reference("ur5e", Drive::NONE, |_, _| 0.0);
    limits[1].torque = Some(LIMIT);
    (model, truth, limits)
}

/// Joint 2's peak torque and whether every limit holds.
fn outcome(
    model: &Interpreted,
    truth: &[f64],
    limits: &[JointLimits],
    tr: &Trajectory,
) -> (f64, bool) {
    let a = assess(model, tr, limits, Some(truth), 1).unwrap();
    let peak = a.margins[1].peak_torque.expect("torques were computed");
    (peak, a.within_limits())
}

fn check(label: &str, design: impl Fn(Option<&[f64]>) -> Trajectory) {
    let (model, truth, limits) = setup();
    assert_eq!(model.dof(), 6);
    let (free_peak, _) = outcome(&model, &truth, &limits, &design(None));
    let (peak, within) = outcome(&model, &truth, &limits, &design(Some(&truth)));
    println!(
        "{label}: joint 2 peak torque {free_peak:.1} N m ignoring the limit, {peak:.1} N m with it (limit {LIMIT})"
    );
    assert!(
        free_peak > LIMIT,
        "{label}: the limit does not bind ({free_peak})"
    );
    assert!(
        within && peak <= LIMIT,
        "{label}: peak {peak} with the limit {LIMIT}"
    );
}

#[test]
fn the_point_design_keeps_a_binding_torque_limit() {
    check("points", |torque| {
        let (model, _, limits) = setup();
        let design = PointDesign {
            duration: 10.0,
            restarts: 1,
            start: Some(START.to_vec()),
            ..PointDesign::default()
        };
        let r = design
            .optimize(&model, &limits, torque)
            .expect("point design");
        r.points.sample(RATE).expect("sampling")
    });
}

#[test]
fn the_fourier_design_keeps_a_binding_torque_limit() {
    check("fourier", |torque| {
        let (model, _, limits) = setup();
        let design = FourierDesign {
            restarts: 1,
            evaluations: 300,
            start: Some(START.to_vec()),
            ..FourierDesign::default()
        };
        let r = design
            .optimize(&model, &limits, torque)
            .expect("fourier design");
        r.fourier.sample(10.0, RATE).expect("sampling")
    });
}
