//! The two-step extraction of Gaz, Flacco, De Luca (ICRA 2016, Sec. III;
//! docs/experiments.md#two-step-extraction): first the gravity parameters (masses and first
//! moments) from the gravity coefficients alone, inside their boxes (their problem 16);
//! then every other parameter from the whole problem with the masses and centres of mass
//! that the gravity step determined held at its values, under the total-mass range and the
//! equality constraints (their problem 19 with eq. 15).

use super::equality::{Quantity, Variable};
use super::parametrise::PER_LINK;
use super::{AnnealOptions, search};
use crate::Result;
use crate::feasible::bounds::Bounds;
use crate::feasible::problem::Problem;
use crate::feasible::solution::Solution;

/// The result of [`solve_two_step`].
#[derive(Debug, Clone)]
pub struct TwoStep {
    /// The first step's solution of the gravity problem (its masses and centres of mass
    /// are the ones the gravity coefficients determine; the rest are don't-care values).
    pub gravity: Solution,
    /// The masses and centre-of-mass coordinates the first step determined, held in the
    /// second, with their values.
    pub held: Vec<(Variable, f64)>,
    /// The second step's solution of the whole problem: the result.
    pub solution: Solution,
}

/// Gaz et al.'s two-step extraction (see the module docs). `gravity` is the problem of the
/// gravity coefficients (e.g. [`GravityCoefficients::problem`](crate::feasible::GravityCoefficients::problem)
/// with its target set), `problem` the whole one, over the same standard parameters.
///
/// The first step searches with the equalities that name only masses and centre-of-mass
/// coordinates (the values it holds must meet them; Gaz et al.'s eq. 15 names inertias, and
/// such equalities are imposed in the second step only, as theirs) and, unlike their
/// problem 16, with the total-mass range: the masses the
/// gravity coefficients do not see (the first link's) count as anything in their boxes, so
/// the range only excludes held masses that no second step could complete; without it the
/// first step often holds masses whose sum leaves the range out of reach. The second step
/// uses `options` as given plus the held values.
///
/// ```no_run
/// # fn f(gravity: &robid_runtime::feasible::Problem, full: &robid_runtime::feasible::Problem,
/// #      bounds: &robid_runtime::feasible::Bounds) -> robid_runtime::Result<()> {
/// use robid_runtime::feasible::{AnnealOptions, solve_two_step};
/// let options = AnnealOptions {
///     restarts: 1000, // as in the paper
///     mass_step: Some(10.0),
///     equalities: vec!["I7xz = c7x * c7z * m7".parse()?, "I7yz = c7y * c7z * m7".parse()?],
///     ..AnnealOptions::default()
/// };
/// let result = solve_two_step(gravity, full, bounds, &options)?;
/// println!("chi^2 {} then {}", result.gravity.chi2, result.solution.chi2);
/// # Ok(()) }
/// ```
pub fn solve_two_step(
    gravity: &Problem,
    problem: &Problem,
    bounds: &Bounds,
    options: &AnnealOptions,
) -> Result<TwoStep> {
    if gravity.standard_names != problem.standard_names {
        return Err(crate::Error::setting(
            "solve_two_step",
            "gravity",
            "the gravity problem and the whole problem have different standard parameters; \
             build the gravity problem from the whole one (GravityCoefficients::problem)",
        ));
    }
    let (solution, held) = solve_gravity_step(gravity, bounds, options)?;
    let mut second = options.clone();
    second.fixed.extend(held.iter().copied());
    let (full, _) = search(problem, bounds, &second, "feasible: anneal, second step")?;
    Ok(TwoStep {
        gravity: solution,
        held,
        solution: full,
    })
}

/// The first step of [`solve_two_step`] alone: the gravity problem's solution and the
/// masses and centre-of-mass coordinates it determines (the variables that change its fit),
/// with their values.
pub fn solve_gravity_step(
    gravity: &Problem,
    bounds: &Bounds,
    options: &AnnealOptions,
) -> Result<(Solution, Vec<(Variable, f64)>)> {
    // the equalities over masses and centres of mass only: the values held after this
    // step must meet them (`m2 = 3` was held at 1.09 kg, then refused in the second step)
    let first = AnnealOptions {
        equalities: options
            .equalities
            .iter()
            .filter(|e| {
                std::iter::once(&e.left)
                    .chain(&e.factors)
                    .all(|v| v.index().is_some())
            })
            .cloned()
            .collect(),
        ..options.clone()
    };
    let (solution, searched) = search(gravity, bounds, &first, "feasible: anneal, gravity step")?;
    let mut held = Vec::new();
    for i in searched {
        let (link, slot) = (i / PER_LINK, i % PER_LINK);
        let quantity = match slot {
            0 => Quantity::Mass,
            1..=3 => Quantity::Com(slot - 1),
            _ => continue,
        };
        let Some(l) = &solution.links[link] else {
            continue;
        };
        let value = match quantity {
            Quantity::Com(a) => l.com[a],
            _ => l.mass,
        };
        held.push((Variable { link, quantity }, value));
    }
    Ok((solution, held))
}
