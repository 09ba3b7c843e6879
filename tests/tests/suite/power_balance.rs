//! Power balance along smooth random trajectories, friction off (rotor inertias on):
//! the time derivative of the total energy H = T + U of the Lagrange-Euler model equals the
//! power tau . qd of the Newton-Euler torques, for every reference robot, with the reference
//! parameters and with random ones.

use robid_runtime::rng::Rng;
use robid_symbolic::{Derivation, Drive};
use tests::reference::by_name;
use tests::state::{Trajectory, bind, random_parameters};

/// Step of the five-point central difference
/// dH/dt = (H(t-2h) - 8 H(t-h) + 8 H(t+h) - H(t+2h)) / (12 h) + O(h^4 H^(5) / 30).
const STEP: f64 = 2e-4;

/// Tolerance relative to the power scale (sum over joints of |tau_j qd_j|, at least 1 W).
/// Truncation: the trajectory's frequencies are at most 1 Hz, so H's spectrum reaches a few
/// times 2 pi rad/s; H^(5) <= (4 * 2 pi)^5 |H| ~ 1e7 |H|, and h^4 / 30 = 5e-17, giving
/// < 1e-9 |H| W (a loose bound: the errors seen are below 1e-10 of the scale). Rounding:
/// 1.5 eps |H| / h ~ 2e-12 |H| W. With |H| below a few hundred J both stay under 1e-8 of a
/// 1 W scale, while any wrong term (of the order of the torques) is off by far more.
const RELATIVE: f64 = 1e-8;

fn check(name: &str) {
    let r = by_name(name);
    let drive = Drive {
        ia: true,
        ..Drive::NONE
    };
    let robot = r.robot().with_drive(drive);
    let n = robot.dof();
    let mut d = Derivation::new(&robot);
    let symbols = d.parameter_symbols();
    let model = d.lagrange(&symbols);
    let energy = d.arena.add2(model.kinetic, model.potential);
    let tau = d.inverse_dynamics(&symbols);
    let mut roots = vec![energy];
    roots.extend(&tau);
    let mut rng = Rng::from_state(0x5eed_0005);
    let reference = r.parameter_values(&robot);
    for (k, parameters) in [
        reference.clone(),
        random_parameters(reference.len(), &mut rng),
    ]
    .iter()
    .enumerate()
    {
        let trajectory = Trajectory::random(&robot, &mut rng);
        for i in 0..40 {
            let t = 0.1 * i as f64;
            let mut h = [0.0; 4];
            for (slot, offset) in h.iter_mut().zip([-2.0, -1.0, 1.0, 2.0]) {
                let state = trajectory.at(t + offset * STEP);
                let values = bind(&mut d.arena, &robot, &state, Some(parameters));
                *slot = d.arena.eval(&[energy], &values).unwrap()[0];
            }
            let dh_dt = (h[0] - 8.0 * h[1] + 8.0 * h[2] - h[3]) / (12.0 * STEP);
            let state = trajectory.at(t);
            let values = bind(&mut d.arena, &robot, &state, Some(parameters));
            let v = d.arena.eval(&roots, &values).unwrap();
            let power: f64 = (0..n).map(|j| v[1 + j] * state.qd[j]).sum();
            let scale: f64 = (0..n)
                .map(|j| (v[1 + j] * state.qd[j]).abs())
                .sum::<f64>()
                .max(1.0);
            assert!(
                (dh_dt - power).abs() <= RELATIVE * scale,
                "{name} set {k} t = {t}: dH/dt = {dh_dt} but tau . qd = {power} (H = {})",
                v[0]
            );
        }
    }
}

// One test per reference robot, each running `check(name)`.
tests::per_robot!(check);
