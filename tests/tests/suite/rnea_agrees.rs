//! The independent plain-f64 RNEA of `tests::rnea` (base-frame, user's own DH frames) agrees
//! with the symbolic Newton-Euler regressor, the Lagrange-Euler regressor and the
//! Lagrange-Euler mass matrix, for the reference parameters and for random parameters, with
//! all drive terms, for every reference robot.

use robid_runtime::rng::Rng;
use robid_symbolic::{Derivation, Drive};
use tests::reference::by_name;
use tests::rnea::{Chain, links_from_standard};
use tests::state::{State, bind, close, random_parameters, random_state, regressor_times};

/// The RNEA and the derivations round differently; 1e-9 relative (floor 1 N m, see
/// ne_equals_le.rs) leaves several orders of magnitude to spare over f64 rounding.
const RELATIVE: f64 = 1e-9;

fn check(name: &str) {
    let r = by_name(name);
    let robot = r.robot().with_drive(Drive::ALL);
    let n = robot.dof();
    let chain = Chain::from_robot(&robot);
    let mut d = Derivation::new(&robot);
    let ne = d.regressor();
    let le = d.lagrange_regressor();
    let symbols = d.parameter_symbols();
    let model = d.lagrange(&symbols);
    let mut roots = ne.entries();
    let count = roots.len();
    roots.extend(le.entries());
    roots.extend(model.mass_matrix.iter().flatten());
    let mut rng = Rng::from_state(0x5eed_0004);
    let reference = r.parameter_values(&robot);
    for s in 0..40 {
        let parameters = if s % 2 == 0 {
            reference.clone()
        } else {
            random_parameters(reference.len(), &mut rng)
        };
        let links = links_from_standard(&robot, &parameters);
        let state = random_state(&robot, &mut rng);
        let values = bind(&mut d.arena, &robot, &state, Some(&parameters));
        let v = d.arena.eval(&roots, &values).unwrap();
        let tau_ne = regressor_times(&v[..count], n, &parameters);
        let tau_le = regressor_times(&v[count..2 * count], n, &parameters);
        let tau = chain.inverse_dynamics(&links, &state.q, &state.qd, &state.qdd);
        for j in 0..n {
            assert!(
                close(tau[j], tau_ne[j], RELATIVE, 1.0) && close(tau[j], tau_le[j], RELATIVE, 1.0),
                "{name} sample {s}: joint {}: RNEA {} NE {} LE {}",
                j + 1,
                tau[j],
                tau_ne[j],
                tau_le[j]
            );
        }
        // Column k of M(q) is the RNEA torque for qdd = e_k at rest, less the torque at rest
        // (gravity and the constant offsets; sign(0) = 0 removes Coulomb friction).
        let mass = &v[2 * count..];
        let rest = State {
            q: state.q.clone(),
            qd: vec![0.0; n],
            qdd: vec![0.0; n],
        };
        let at_rest = chain.inverse_dynamics(&links, &rest.q, &rest.qd, &rest.qdd);
        for k in 0..n {
            let mut qdd = vec![0.0; n];
            qdd[k] = 1.0;
            let column = chain.inverse_dynamics(&links, &rest.q, &rest.qd, &qdd);
            for i in 0..n {
                let m_ik = column[i] - at_rest[i];
                assert!(
                    close(m_ik, mass[i * n + k], RELATIVE, 1.0),
                    "{name} sample {s}: M[{i}][{k}]: RNEA {m_ik} vs LE {}",
                    mass[i * n + k]
                );
            }
        }
    }
}

// One test per reference robot, each running `check(name)`.
tests::per_robot!(check);

/// The comparison can fail: one parameter changed by 1 % moves the RNEA torques away.
#[test]
fn a_changed_parameter_is_detected() {
    let r = by_name("puma560");
    let robot = r.robot().with_drive(Drive::ALL);
    let chain = Chain::from_robot(&robot);
    let mut d = Derivation::new(&robot);
    let ne = d.regressor();
    let mut parameters = r.parameter_values(&robot);
    let state = random_state(&robot, &mut Rng::from_state(7));
    let values = bind(&mut d.arena, &robot, &state, None);
    let v = d.arena.eval(&ne.entries(), &values).unwrap();
    let tau_ne = regressor_times(&v, robot.dof(), &parameters);
    let mz = robot
        .standard_parameters()
        .iter()
        .position(|p| p.to_string() == "MX2")
        .unwrap();
    parameters[mz] *= 1.01;
    let links = links_from_standard(&robot, &parameters);
    let tau = chain.inverse_dynamics(&links, &state.q, &state.qd, &state.qdd);
    assert!((0..robot.dof()).any(|j| !close(tau[j], tau_ne[j], RELATIVE, 1.0)));
}
