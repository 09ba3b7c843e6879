//! The Newton-Euler and Lagrange-Euler regressors agree at 100 random states for every
//! reference robot, with all drive terms (docs/dynamics.md#newton-euler-equals-lagrange-euler).

use robid_runtime::rng::Rng;
use robid_symbolic::{Derivation, Drive};
use tests::reference::by_name;
use tests::state::{bind, close, random_state};

/// Regressor entries are torques per unit parameter: with lengths below 1 m, speeds up to
/// 2 rad/s, accelerations up to 5 rad/s^2 and g = 9.81 they are O(1..100), so an absolute
/// floor of 1e-9 (scale 1) for entries that cancel to zero is as strict as the relative bound.
const RELATIVE: f64 = 1e-9;

fn check(name: &str) {
    let robot = by_name(name).robot().with_drive(Drive::ALL);
    let mut d = Derivation::new(&robot);
    let ne = d.regressor();
    let le = d.lagrange_regressor();
    assert_eq!(ne.parameters, le.parameters);
    let mut roots = ne.entries();
    let count = roots.len();
    roots.extend(le.entries());
    let mut rng = Rng::from_state(0x5eed_0001);
    for s in 0..100 {
        let state = random_state(&robot, &mut rng);
        let values = bind(&mut d.arena, &robot, &state, None);
        let v = d.arena.eval(&roots, &values).unwrap();
        let (a, b) = v.split_at(count);
        for (k, (x, y)) in a.iter().zip(b).enumerate() {
            let (p, j) = (k / robot.dof(), k % robot.dof());
            assert!(
                close(*x, *y, RELATIVE, 1.0),
                "{name} state {s} ({state:?}): joint {} column {}: NE {x} vs LE {y}",
                j + 1,
                ne.parameters[p]
            );
        }
    }
}

// One test per reference robot, each running `check(name)`.
tests::per_robot!(check);
