//! M(q) of the Lagrange-Euler model is symmetric positive definite at random positions for the
//! reference parameters (rotor inertias included), for every reference robot.

use nalgebra::DMatrix;
use robid_runtime::rng::Rng;
use robid_symbolic::{Derivation, Drive};
use tests::reference::by_name;
use tests::state::{bind, random_state};

/// Evaluates M(q) at 100 random positions; returns the matrices.
fn mass_matrices(name: &str, negate: bool) -> Vec<DMatrix<f64>> {
    let r = by_name(name);
    let robot = r.robot().with_drive(Drive::ALL);
    let mut parameters = r.parameter_values(&robot);
    if negate {
        parameters.iter_mut().for_each(|p| *p = -*p);
    }
    let mut d = Derivation::new(&robot);
    let symbols = d.parameter_symbols();
    let model = d.lagrange(&symbols);
    let n = robot.dof();
    let roots: Vec<_> = model.mass_matrix.iter().flatten().copied().collect();
    let mut rng = Rng::from_state(0x5eed_0002);
    (0..100)
        .map(|_| {
            let state = random_state(&robot, &mut rng);
            let values = bind(&mut d.arena, &robot, &state, Some(&parameters));
            let v = d.arena.eval(&roots, &values).unwrap();
            DMatrix::from_row_slice(n, n, &v)
        })
        .collect()
}

fn check(name: &str) {
    for m in mass_matrices(name, false) {
        let scale = m.amax();
        for i in 0..m.nrows() {
            for k in 0..i {
                assert!(
                    (m[(i, k)] - m[(k, i)]).abs() <= 1e-12 * scale,
                    "{name}: M not symmetric at ({i}, {k}):\n{m}"
                );
            }
        }
        assert!(
            m.clone().cholesky().is_some(),
            "{name}: M not positive definite:\n{m}"
        );
        let smallest = m.symmetric_eigenvalues().min();
        assert!(smallest > 1e-9 * scale, "{name}: eigenvalue {smallest}");
    }
}

// One test per reference robot, each running `check(name)`.
tests::per_robot!(check);

/// The check can fail: with every parameter negated, M(q) is negative definite.
#[test]
fn negated_parameters_are_rejected() {
    for m in mass_matrices("stanford", true) {
        assert!(m.cholesky().is_none());
    }
}
