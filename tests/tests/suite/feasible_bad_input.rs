//! Bad input to the feasible-parameter extraction gives a clear error, never a panic.

use robid_runtime::Error;
use robid_runtime::FeasibleError;
use robid_runtime::feasible::{
    Bounds, ConicFailure, ConicProgram, ConicSolver, LinkBounds, Problem, SdpOptions, solve_sdp,
};

/// One link, base parameters ZZ1 and M1 (K picks two standard parameters).
fn problem() -> Problem {
    let names: Vec<String> = [
        "XX1", "XY1", "XZ1", "YY1", "YZ1", "ZZ1", "MX1", "MY1", "MZ1", "M1",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    let mut rows = vec![vec![0.0; 10]; 2];
    rows[0][5] = 1.0;
    rows[1][9] = 1.0;
    Problem::from_rows(names, vec!["ZZ1".into(), "M1".into()], &rows).unwrap()
}

#[test]
fn nan_and_wrong_counts_are_rejected() {
    let p = problem();
    assert!(
        p.clone()
            .with_target(&[f64::NAN, 1.0], &[0.1, 0.1])
            .is_err()
    );
    assert!(p.clone().with_target(&[1.0, 1.0], &[0.1, -0.1]).is_err());
    // a deviation of 0 is a parameter known exactly
    assert!(p.clone().with_target(&[1.0, 1.0], &[0.1, 0.0]).is_ok());
    assert!(matches!(
        p.clone().with_target(&[1.0], &[0.1]),
        Err(Error::DimensionMismatch { .. })
    ));
    let e = p
        .clone()
        .with_identified(&["ZZ1".into(), "Q9".into()], &[1.0, 1.0], &[0.1, 0.1]);
    assert!(matches!(e, Err(Error::Setting { .. })));
    assert!(Problem::from_rows(vec!["XX1".into()], vec!["B".into()], &[vec![1.0, 2.0]]).is_err());
}

#[test]
fn bounds_that_exclude_every_solution_are_reported() {
    // Mass 1 is identified, but the bounds force the mass into [5, 6]: the fit is poor but
    // feasible; total mass [10, 20] with one link of at most 6 kg is infeasible.
    let p = problem().with_target(&[0.1, 1.0], &[0.01, 0.01]).unwrap();
    let b = Bounds {
        links: vec![LinkBounds {
            mass: [0.0, 6.0],
            ..LinkBounds::default()
        }],
        total_mass: Some([10.0, 20.0]),
        margin: Some(1e-6),
    };
    assert!(matches!(
        b.validate(),
        Err(Error::Feasible(FeasibleError::NoFeasibleParameters { .. }))
    ));
    // refused before any solver runs
    assert!(matches!(
        solve_sdp(&p, &b, &SdpOptions::default(), &Unreached),
        Err(Error::Feasible(FeasibleError::NoFeasibleParameters { .. }))
    ));
}

/// A conic solver a test never reaches.
#[derive(Debug)]
struct Unreached;

impl ConicSolver for Unreached {
    fn solve(&self, _: &ConicProgram) -> Result<Vec<f64>, ConicFailure> {
        panic!("the solver was called")
    }
}

#[cfg(feature = "sdp")]
#[test]
fn sdp_projects_inconsistent_identified_values_onto_consistent_ones() {
    // A negative identified mass: the SDP returns the nearest consistent set (mass >= margin).
    let p = problem().with_target(&[0.1, -1.0], &[0.01, 0.01]).unwrap();
    let s = solve_sdp(
        &p,
        &Bounds::wide(1),
        &SdpOptions::default(),
        &robid_sdp::Clarabel,
    )
    .unwrap();
    assert!(s.min_eigenvalues[0] > 0.0);
    assert!(s.standard[9] > 0.0);
}
