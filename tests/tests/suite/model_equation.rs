//! The Newton-Euler regressor times random parameters equals the closed-form Lagrange-Euler
//! model M(q) qdd + c(q, qd) + g(q) + friction, with all drive terms, for every reference robot.

use robid_runtime::rng::Rng;
use robid_symbolic::{Derivation, Drive};
use tests::reference::by_name;
use tests::state::{bind, close, random_parameters, random_state, regressor_times};

/// Torques are O(1..100) N m for parameters in [-1, 1]; see ne_equals_le.rs for the floor.
const RELATIVE: f64 = 1e-9;

fn check(name: &str) {
    let robot = by_name(name).robot().with_drive(Drive::ALL);
    let n = robot.dof();
    let mut d = Derivation::new(&robot);
    let ne = d.regressor();
    let symbols = d.parameter_symbols();
    let model = d.lagrange(&symbols);
    let mut roots = ne.entries();
    let count = roots.len();
    roots.extend(model.mass_matrix.iter().flatten());
    roots.extend(&model.coriolis);
    roots.extend(&model.gravity);
    roots.extend(&model.friction);
    let mut rng = Rng::from_state(0x5eed_0003);
    for s in 0..50 {
        let parameters = random_parameters(ne.parameters.len(), &mut rng);
        let state = random_state(&robot, &mut rng);
        let values = bind(&mut d.arena, &robot, &state, Some(&parameters));
        let v = d.arena.eval(&roots, &values).unwrap();
        let tau = regressor_times(&v[..count], n, &parameters);
        let rest = &v[count..];
        let (m, rest) = rest.split_at(n * n);
        let (c, rest) = rest.split_at(n);
        let (g, rest) = rest.split_at(n);
        // `model.torques` is M qdd + c + g + f by construction: the regressor is the check
        let f = &rest[..n];
        for i in 0..n {
            let m_qdd: f64 = (0..n).map(|k| m[i * n + k] * state.qdd[k]).sum();
            let model_tau = m_qdd + c[i] + g[i] + f[i];
            assert!(
                close(tau[i], model_tau, RELATIVE, 1.0),
                "{name} sample {s}: joint {}: Y p = {} but M qdd + c + g + f = {model_tau}",
                i + 1,
                tau[i]
            );
        }
    }
}

// One test per reference robot, each running `check(name)`.
tests::per_robot!(check);
