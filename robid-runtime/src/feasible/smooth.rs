//! The objective of `objective` (the covariance-weighted fit of the standard parameters to
//! the identified base parameters, the prior's pull and the bounds' penalty) minimised over
//! the log-Cholesky parameters of every link (so every point is physically consistent, see
//! `log_cholesky`) by Levenberg-Marquardt (the `levenberg-marquardt` crate).
//!
//! The objective is convex in the standard parameters p, the consistent set is convex, and
//! the parametrisation maps its interior smoothly and one-to-one, so the local optimum the
//! solver finds is the global one whenever it lies inside; an optimum on the boundary (a
//! link the data push to a singular pseudo-inertia, common on real data) is only
//! approached, slowly, where the interior-point method of `interior` lands on it. The
//! prior's weight is lowered in stages ([`CONTINUATION`]). Non-negative drive terms (Ia,
//! Fv, Fc) are exponentials of their variables; Fo and extra columns are free.

use std::time::Instant;

use levenberg_marquardt::{LeastSquaresProblem, LevenbergMarquardt};
use nalgebra::storage::Owned;
use nalgebra::{DMatrix, DVector, Dyn};

use super::bounds::Bounds;
use super::log_cholesky::{PER_LINK, jacobian, standard_of, theta_of};
use super::objective::Objective;
use super::prior::Prior;
use super::problem::Problem;
use super::solution::{Method, Solution};
use crate::{Error, FeasibleError, Result};

/// Settings of the pure-Rust fits (interior-point and log-Cholesky).
#[derive(Debug, Clone, PartialEq)]
pub struct SmoothOptions {
    /// The user's prior (e.g. CAD values); the default prior settles the rest.
    pub prior: Option<Prior>,
    /// Weight of the default prior (see [`Prior::weight`]): it settles what the data leave
    /// free and holds what they barely determine.
    pub default_weight: f64,
    /// Weight of a bound's violation (relative to its parameter's scale), in chi^2 units.
    pub penalty: f64,
    /// Patience of the solver: at most `patience * (variables + 1)` evaluations per stage
    /// (log-Cholesky) or Newton steps in all (interior-point).
    pub patience: usize,
}

impl Default for SmoothOptions {
    fn default() -> SmoothOptions {
        SmoothOptions {
            prior: None,
            default_weight: 1e-2,
            penalty: 1e6,
            patience: 100,
        }
    }
}

impl SmoothOptions {
    /// Checks the weights and the patience.
    pub fn check(&self) -> Result<()> {
        let bad = |key: &str, problem: String| Err(Error::setting("SmoothOptions", key, problem));
        if !(self.default_weight >= 0.0 && self.default_weight <= 1e12) {
            return bad(
                "default_weight",
                format!("{} must lie in [0, 1e12]", self.default_weight),
            );
        }
        if !(self.penalty > 0.0 && self.penalty <= 1e16) {
            return bad("penalty", format!("{} must lie in (0, 1e16]", self.penalty));
        }
        if !(1..=100_000).contains(&self.patience) {
            return bad(
                "patience",
                format!("{} must lie between 1 and 100000", self.patience),
            );
        }
        Ok(())
    }
}

/// Where a variable's standard value comes from.
#[derive(Debug, Clone, Copy)]
enum Map {
    /// The ten parameters of a link.
    Link(usize),
    /// A non-negative drive term, the exponential of its variable.
    Positive(usize),
    /// A free term.
    Free(usize),
}

/// The least-squares problem in the variables x.
#[derive(Clone)]
struct Fit<'a> {
    objective: Objective<'a>,
    margin: f64,
    maps: Vec<Map>,
    x: DVector<f64>,
}

impl Fit<'_> {
    fn theta(&self, x: &DVector<f64>, j: usize) -> [f64; PER_LINK] {
        std::array::from_fn(|k| x[j * PER_LINK + k])
    }

    /// The standard parameters of x.
    fn standard(&self, x: &DVector<f64>) -> Vec<f64> {
        let layout = &self.objective.problem.layout;
        let mut p = vec![0.0; layout.len()];
        let mut v = 0;
        for map in &self.maps {
            match *map {
                Map::Link(j) => {
                    let s = standard_of(&self.theta(x, j), self.margin);
                    for (&i, value) in layout.links[j].iter().zip(s) {
                        p[i] = value;
                    }
                    v += PER_LINK;
                }
                Map::Positive(i) => {
                    p[i] = x[v].clamp(-700.0, 700.0).exp();
                    v += 1;
                }
                Map::Free(i) => {
                    p[i] = x[v];
                    v += 1;
                }
            }
        }
        p
    }

    /// The variables of standard parameters p (each link strictly inside the set).
    fn variables(&self, p: &[f64]) -> Option<DVector<f64>> {
        let layout = &self.objective.problem.layout;
        let mut x = Vec::new();
        for map in &self.maps {
            match *map {
                Map::Link(j) => x.extend(theta_of(&layout.link_values(j, p), self.margin)?),
                Map::Positive(i) => x.push(p[i].ln()),
                Map::Free(i) => x.push(p[i]),
            }
        }
        Some(DVector::from_vec(x))
    }

    /// d residuals / d x from d residuals / d p, through the block-diagonal d p / d x (a
    /// link's ten by ten block, or one entry).
    fn chain(&self, x: &DVector<f64>, jp: &DMatrix<f64>) -> DMatrix<f64> {
        let layout = &self.objective.problem.layout;
        let mut out = DMatrix::zeros(jp.nrows(), x.len());
        let mut v = 0;
        for map in &self.maps {
            match *map {
                Map::Link(j) => {
                    let jac = jacobian(&self.theta(x, j));
                    for (k, &i) in layout.links[j].iter().enumerate() {
                        let column = jp.column(i);
                        for (t, d) in jac[k].iter().enumerate() {
                            if *d != 0.0 {
                                out.column_mut(v + t).axpy(*d, &column, 1.0);
                            }
                        }
                    }
                    v += PER_LINK;
                }
                Map::Positive(i) => {
                    let d = x[v].clamp(-700.0, 700.0).exp();
                    out.column_mut(v).axpy(d, &jp.column(i), 0.0);
                    v += 1;
                }
                Map::Free(i) => {
                    out.column_mut(v).copy_from(&jp.column(i));
                    v += 1;
                }
            }
        }
        out
    }
}

impl LeastSquaresProblem<f64, Dyn, Dyn> for Fit<'_> {
    type ResidualStorage = Owned<f64, Dyn>;
    type JacobianStorage = Owned<f64, Dyn, Dyn>;
    type ParameterStorage = Owned<f64, Dyn>;

    fn set_params(&mut self, x: &DVector<f64>) {
        self.x.copy_from(x);
    }

    fn params(&self) -> DVector<f64> {
        self.x.clone()
    }

    fn residuals(&self) -> Option<DVector<f64>> {
        let r = self.objective.residuals(&self.standard(&self.x));
        r.iter().all(|v| v.is_finite()).then_some(r)
    }

    fn jacobian(&self) -> Option<DMatrix<f64>> {
        let p = self.standard(&self.x);
        let j = self.chain(&self.x, &self.objective.jacobian(&p));
        j.iter().all(|v| v.is_finite()).then_some(j)
    }
}

/// The prior's weight is raised this much at first and lowered tenfold per round to its
/// own value: each round starts next to its optimum, so no link's mass is driven towards
/// zero early, where the exponential parametrisation leaves it no gradient to come back.
const CONTINUATION: [f64; 5] = [1e4, 1e3, 1e2, 1e1, 1.0];
/// Rounds of the augmented Lagrangian's multiplier update after the stages, at most.
const BOUND_ROUNDS: usize = 3;

/// Physically consistent standard parameters that reproduce the identified base
/// parameters of `problem` within the bounds, settled by the prior where the data leave
/// them free (see the module documentation).
pub fn solve_smooth(
    problem: &Problem,
    bounds: &Bounds,
    options: &SmoothOptions,
) -> Result<Solution> {
    let start = Instant::now();
    let layout = &problem.layout;
    let objective = Objective::from_options(problem, bounds, options)?;
    let mut maps: Vec<Map> = (0..layout.links.len()).map(Map::Link).collect();
    maps.extend(layout.drives.iter().map(|d| {
        if d.kind.non_negative() {
            Map::Positive(d.index)
        } else {
            Map::Free(d.index)
        }
    }));
    maps.extend(layout.extra.iter().map(|&i| Map::Free(i)));
    let p0 = objective.start(bounds.margin)?;
    let mut fit = Fit {
        objective,
        margin: bounds.margin,
        maps,
        x: DVector::zeros(0),
    };
    fit.x = fit.variables(&p0).ok_or_else(|| {
        Error::Feasible(FeasibleError::NoFeasibleParameters {
            reason: "the prior of a link cannot be made physically consistent; check the prior's masses and inertias".into(),
        })
    })?;
    let weight = fit.objective.pull.weight.clone();
    // the prior's stages, then rounds at its own weight until the bounds hold
    let rounds = CONTINUATION
        .into_iter()
        .chain(std::iter::repeat_n(1.0, BOUND_ROUNDS));
    for (round, factor) in rounds.enumerate() {
        fit.objective.pull.weight = weight.iter().map(|w| w * factor).collect();
        let (next, report) = LevenbergMarquardt::new()
            .with_patience(options.patience)
            .minimize(fit);
        fit = next;
        if !report.objective_function.is_finite() {
            return Err(Error::Feasible(FeasibleError::NoFeasibleParameters {
                reason: format!(
                    "the log-Cholesky fit stopped without a finite objective ({:?}); check the identified values and the bounds",
                    report.termination
                ),
            }));
        }
        let p = fit.standard(&fit.x);
        let violation = fit.objective.update_shifts(&p);
        if round + 1 >= CONTINUATION.len() && violation <= 1e-7 {
            break;
        }
    }
    let p = fit.standard(&fit.x);
    let mut solution =
        Solution::assemble(problem, bounds, Method::LogCholesky, p, start.elapsed())?;
    solution.determined = super::prior::determined(problem, &fit.objective.pull);
    Ok(solution)
}
