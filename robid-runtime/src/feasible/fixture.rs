//! Test problems shared by the feasible methods' unit tests: one link plus a rotor
//! inertia, every standard parameter its own base parameter (K = I), so that each known
//! optimum can be worked out by hand.

use super::{LinkInertial, Problem, SmoothOptions, Solution};

/// The one-link problem with `target` (XX1 .. M1, Ia1) identified with standard deviation
/// 1e-3 and `drives` appended as further terms of the same joint (target 0 unless set).
pub(super) fn problem_with(target: &[f64], drives: &[&str]) -> Problem {
    let mut names = names();
    names.extend(drives.iter().map(|d| format!("{d}1")));
    let n = names.len();
    let mut values = target.to_vec();
    values.resize(n, 0.0);
    Problem::new(names.clone(), names, nalgebra::DMatrix::identity(n, n))
        .unwrap()
        .with_target(&values, &vec![1e-3; n])
        .unwrap()
}

/// The inertial parameters' names of links 1 to `links`: `XX1 .. M1, XX2 ..`.
pub(super) fn link_names(links: usize) -> Vec<String> {
    (1..=links)
        .flat_map(|j| {
            crate::model::Inertial::ALL
                .iter()
                .map(move |s| format!("{}{j}", s.stem()))
        })
        .collect()
}

/// The standard names of the link and its rotor inertia: `XX1 .. M1, Ia1`.
pub(super) fn names() -> Vec<String> {
    let mut names: Vec<String> = crate::model::Inertial::ALL
        .iter()
        .map(|s| format!("{}1", s.stem()))
        .collect();
    names.push("Ia1".into());
    names
}

/// [`problem_with`] without further drive terms.
pub(super) fn problem(target: &[f64; 11]) -> Problem {
    problem_with(target, &[])
}

/// A link of 2 kg with its centre of mass at the origin and a diagonal inertia.
pub(super) fn link() -> [f64; 10] {
    LinkInertial {
        mass: 2.0,
        com: [0.0; 3],
        inertia: [[0.03, 0.0, 0.0], [0.0, 0.02, 0.0], [0.0, 0.0, 0.015]],
    }
    .to_standard()
}

/// A prior so weak that the data alone set the optimum.
pub(super) fn options() -> SmoothOptions {
    SmoothOptions {
        default_weight: 1e-9,
        ..SmoothOptions::default()
    }
}

/// The path is as long as measured, to the step: it is deterministic, and a wrong weight,
/// stopping rule or line search still ends near the optimum (which the values' bounds
/// allow), only earlier or later, so the count is what shows it.
pub(super) fn steps(s: &Solution, measured: usize) {
    assert_eq!(s.iterations, measured, "steps");
}

/// The link's ten values followed by the rotor inertia `ia`.
pub(super) fn target(link: [f64; 10], ia: f64) -> [f64; 11] {
    std::array::from_fn(|i| if i < 10 { link[i] } else { ia })
}
