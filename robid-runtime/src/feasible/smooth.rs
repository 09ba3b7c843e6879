//! The objective of `objective` (the covariance-weighted fit of the standard parameters to
//! the identified base parameters, the prior's pull and the bounds' penalty) minimised over
//! the Cholesky factors of every link's pseudo-inertia (so every point is physically
//! consistent, see `cholesky`) by argmin's trust-region Newton method with Steihaug's
//! conjugate-gradient subproblem, on the exact Hessian (the factorisation's own curvature
//! included).
//!
//! The objective is convex in the standard parameters p and the consistent set is convex;
//! the map from factors to pseudo-inertias is onto and, where the factor is invertible, a
//! local diffeomorphism, so a stationary point with invertible factors is the global
//! optimum (Burer and Monteiro, Math. Program. 95, 2003, for the factored form of a convex
//! semidefinite problem). Unlike the log-Cholesky form, whose boundary lies at infinity, a
//! singular pseudo-inertia (a link the data push to the boundary, common on real data) is
//! a finite point, reached at a linear rate. Non-negative drive terms (Ia, Fv, Fc) are
//! squares of their variables; Fo and extra columns are free.
//!
//! Where the data are far firmer than the prior, p (quadratic in the factors) must stay on
//! what the data fix, a curved valley in the factors, and the steps crawl along it: the
//! README sequence's KR 6 R900 takes 6 675 steps where the interior-point method takes 497
//! (docs/experiments.md#cholesky-parametrisation).

use std::time::Instant;

use argmin::core::{CostFunction, Executor, Gradient, Hessian};
use argmin::solver::trustregion::{Steihaug, TrustRegion};
use nalgebra::{DMatrix, DVector};

use super::bounds::Bounds;
use super::cholesky::{ENTRIES, PER_LINK, jacobian, second_derivative, standard_of, theta_of};
use super::objective::Objective;
use super::prior::Prior;
use super::problem::Problem;
use super::solution::{Method, Solution};
use crate::{Error, FeasibleError, Result};

/// Settings of the pure-Rust fits (interior-point and Cholesky).
#[derive(Debug, Clone, PartialEq)]
pub struct SmoothOptions {
    /// The user's prior (e.g. CAD values); the default prior settles the rest.
    pub prior: Option<Prior>,
    /// Weight of the default prior (see [`Prior::weight`]): it settles what the data leave
    /// free and holds what they barely determine.
    pub default_weight: f64,
    /// Weight of a bound's violation (relative to its parameter's scale), in chi^2 units.
    pub penalty: f64,
    /// Patience of the solver: at most `patience * (variables + 1)` Newton steps in all
    /// (trust-region steps for the Cholesky fit).
    pub patience: usize,
}

impl Default for SmoothOptions {
    fn default() -> SmoothOptions {
        SmoothOptions {
            prior: None,
            default_weight: super::prior::DEFAULT_PRIOR_WEIGHT,
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
                    p[i] = x[v] * x[v];
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
                Map::Positive(i) => x.push(p[i].max(0.0).sqrt()),
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
                    let d = 2.0 * x[v];
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

impl Fit<'_> {
    /// The residuals at x with their Jacobians in p and in x.
    fn linearise(&self, x: &DVector<f64>) -> (DVector<f64>, DMatrix<f64>, DMatrix<f64>) {
        let p = self.standard(x);
        let jp = self.objective.jacobian(&p);
        let jx = self.chain(x, &jp);
        (self.objective.residuals(&p), jp, jx)
    }

    /// The residuals at x, `None` where they are not finite (a wild trial step).
    fn residuals_at(&self, x: &DVector<f64>) -> Option<DVector<f64>> {
        let r = self.objective.residuals(&self.standard(x));
        r.iter().all(|v| v.is_finite()).then_some(r)
    }
}

impl CostFunction for Fit<'_> {
    type Param = DVector<f64>;
    type Output = f64;

    fn cost(&self, x: &DVector<f64>) -> std::result::Result<f64, argmin::core::Error> {
        // outside the finite range the trust region shrinks (its reduction ratio is -inf)
        Ok(self
            .residuals_at(x)
            .map_or(f64::INFINITY, |r| r.norm_squared()))
    }
}

impl Gradient for Fit<'_> {
    type Param = DVector<f64>;
    type Gradient = DVector<f64>;

    fn gradient(&self, x: &DVector<f64>) -> std::result::Result<DVector<f64>, argmin::core::Error> {
        let (r, _, jx) = self.linearise(x);
        Ok(jx.tr_mul(&r) * 2.0)
    }
}

impl Hessian for Fit<'_> {
    type Param = DVector<f64>;
    type Hessian = DMatrix<f64>;

    /// The exact Hessian of the sum of squares in x, but for the bound rows' own
    /// curvature: 2 Jx' Jx plus the gradient in p times the (constant) second derivatives
    /// of p(x), which make the Newton step converge fast where Gauss-Newton crawls.
    fn hessian(&self, x: &DVector<f64>) -> std::result::Result<DMatrix<f64>, argmin::core::Error> {
        let (r, jp, jx) = self.linearise(x);
        let mut h = jx.tr_mul(&jx) * 2.0;
        let gp = jp.tr_mul(&r) * 2.0;
        let layout = &self.objective.problem.layout;
        let mut v = 0;
        for map in &self.maps {
            match *map {
                Map::Link(j) => {
                    let g: [f64; PER_LINK] = std::array::from_fn(|s| gp[layout.links[j][s]]);
                    for (a, (_, i, k)) in ENTRIES.iter().enumerate() {
                        for (b, (_, m, l)) in ENTRIES.iter().enumerate() {
                            if k == l {
                                h[(v + a, v + b)] += second_derivative(&g, *i, *m);
                            }
                        }
                    }
                    v += PER_LINK;
                }
                Map::Positive(i) => {
                    h[(v, v)] += 2.0 * gp[i];
                    v += 1;
                }
                Map::Free(_) => v += 1,
            }
        }
        Ok(h)
    }
}

/// Conjugate-gradient steps of a trust-region subproblem, at most (more than the
/// variables: rounding spoils the conjugacy on these ill-conditioned Hessians).
const STEIHAUG_ITERATIONS: u64 = 200;
/// The trust region's largest radius in the variables (square roots of kg and kg m^2).
const MAX_RADIUS: f64 = 1e3;
/// Rounds of the augmented Lagrangian's multiplier update, at most.
const BOUND_ROUNDS: usize = 12;
/// The bounds hold when no violation exceeds this share of the bound's scale, as in the
/// interior-point method (the solution's own check allows 1e-6 of the bound).
const BOUND_TOLERANCE: f64 = 1e-9;

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
    let margin = bounds.margin_for(layout, Some(&objective.pull.target))?;
    let p0 = objective.start(margin)?;
    let mut fit = Fit {
        objective,
        margin,
        maps,
        x: DVector::zeros(0),
    };
    fit.x = fit.variables(&p0).ok_or_else(|| {
        Error::Feasible(FeasibleError::NoFeasibleParameters {
            reason: "the prior of a link cannot be made physically consistent; check the prior's masses and inertias".into(),
        })
    })?;
    // rounds of the bounds' multipliers until the bounds hold
    let budget = options.patience.saturating_mul(fit.x.len() + 1);
    let mut iterations = 0;
    let mut last = f64::INFINITY;
    for _ in 0..BOUND_ROUNDS {
        let (next, used) = minimise(fit, budget.saturating_sub(iterations))?;
        fit = next;
        iterations += used;
        let p = fit.standard(&fit.x);
        let violation = fit.objective.update_shifts(&p);
        if violation <= BOUND_TOLERANCE {
            break;
        }
        // the multipliers converge at the rate data / (data + penalty): a violation that
        // falls slowly means data firmer than the penalty
        if violation > 0.25 * last {
            fit.objective.stiffen(10.0);
        }
        last = violation;
    }
    let p = fit.standard(&fit.x);
    let value = fit.objective.fit_value(&p);
    let mut solution = Solution::assemble(problem, bounds, Method::Cholesky, p, start.elapsed())?;
    solution.iterations = iterations;
    solution.objective = Some(value);
    solution.determined = super::prior::determined(problem, &fit.objective.pull);
    solution.unpulled = super::prior::unpulled(problem, &fit.objective.pull);
    Ok(solution)
}

/// Trust-region iterations per call of the solver; between calls the fit stops when the
/// objective fell by less than [`STALL`] of itself (plus one).
const CHUNK: usize = 25;
/// See [`CHUNK`]. The objective is in chi^2 units: a chunk that gains less than 1e-8 of it
/// (or 1e-8 in all, near zero) changes nothing the data can tell; the fit then sits within
/// 1e-6 of the SDP's chi^2 (relative, or 1e-10 absolute) on the test problems.
const STALL: f64 = 1e-8;

/// Minimises the fit from its x by argmin's trust-region Newton method (Steihaug's
/// conjugate-gradient subproblem), at most `budget` iterations; returns the fit at the
/// best point and the iterations used.
fn minimise(mut fit: Fit<'_>, budget: usize) -> Result<(Fit<'_>, usize)> {
    let stopped = |why: String| {
        Error::Feasible(FeasibleError::NoFeasibleParameters {
            reason: format!(
                "the smooth fit stopped: {why}; check the identified values and the bounds"
            ),
        })
    };
    let mut used = 0;
    let mut now = fit.cost(&fit.x).map_err(|e| stopped(e.to_string()))?;
    if !now.is_finite() {
        return Err(stopped("the start has no finite objective".into()));
    }
    while used < budget {
        let chunk = CHUNK.min(budget - used);
        let x0 = fit.x.clone();
        let solver = TrustRegion::new(Steihaug::new().with_max_iters(STEIHAUG_ITERATIONS))
            .with_max_radius(MAX_RADIUS)
            .map_err(|e| stopped(e.to_string()))?;
        let result = Executor::new(fit, solver)
            .configure(|state| state.param(x0).max_iters(chunk as u64))
            .run()
            .map_err(|e| stopped(e.to_string()))?;
        used += chunk;
        let best = result.state.best_param;
        let cost = result.state.best_cost;
        fit = result
            .problem
            .problem
            .ok_or_else(|| stopped("the solver kept the problem".into()))?;
        if let Some(best) = best
            && cost <= now
        {
            fit.x = best;
        }
        let fell = now - cost;
        now = now.min(cost);
        if fell <= STALL * (1.0 + now) {
            break;
        }
    }
    Ok((fit, used))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::feasible::LinkBounds;
    use crate::feasible::fixture::{link, options, problem, problem_with, target};

    fn solve(problem: &Problem, bounds: &Bounds) -> Solution {
        let s = solve_smooth(problem, bounds, &options()).unwrap();
        assert_eq!(s.method, Method::Cholesky);
        assert!(s.violations.is_empty(), "{:?}", s.violations);
        s
    }

    /// Each setting has its range, both ends checked.
    #[test]
    fn settings_outside_their_ranges_are_refused() {
        let with = |edit: &dyn Fn(&mut SmoothOptions)| {
            let mut o = SmoothOptions::default();
            edit(&mut o);
            o.check()
        };
        for (edit, ok) in [
            (
                &(|o: &mut SmoothOptions| o.default_weight = 0.0) as &dyn Fn(&mut SmoothOptions),
                true,
            ),
            (&|o: &mut SmoothOptions| o.default_weight = 1e12, true),
            (&|o: &mut SmoothOptions| o.default_weight = -1e-9, false),
            (&|o: &mut SmoothOptions| o.default_weight = 2e12, false),
            (&|o: &mut SmoothOptions| o.penalty = 1e16, true),
            (&|o: &mut SmoothOptions| o.penalty = -1.0, false),
            (&|o: &mut SmoothOptions| o.penalty = 2e16, false),
            (&|o: &mut SmoothOptions| o.patience = 1, true),
            (&|o: &mut SmoothOptions| o.patience = 100_000, true),
            (&|o: &mut SmoothOptions| o.patience = 100_001, false),
        ] {
            assert_eq!(with(edit).is_ok(), ok);
        }
    }

    /// A consistent target inside the bounds is its own optimum.
    #[test]
    fn a_consistent_target_is_returned_as_it_is() {
        let t = target(link(), 0.1);
        let s = solve(&problem(&t), &Bounds::wide(1));
        assert_eq!(s.iterations, 50);
        let worst = s
            .standard
            .iter()
            .zip(&t)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        // the start is the target itself: equal to rounding (chi^2 measured 2.0e-25)
        assert!(worst < 1e-14, "{:?} vs {t:?}", s.standard);
        assert!(s.chi2 < 4e-25, "chi2 {}", s.chi2);
    }

    /// Negative non-negative drive terms are held at zero, a free one kept with its sign:
    /// chi^2 = (Ia / std)^2 + (Fv / std)^2 = 16 + 4.
    #[test]
    fn drive_terms_are_held_at_zero_or_kept_by_their_kind() {
        // the free term between two non-negative ones, so that each variable's place counts
        let mut t = target(link(), -0.004).to_vec();
        t.extend([-0.3, -0.002]);
        let s = solve(&problem_with(&t, &["Fo", "Fv"]), &Bounds::wide(1));
        assert_eq!(s.iterations, 50);
        // squares of variables driven to zero: measured 1.5e-39 and 3.1e-35, nothing the
        // data (std 1e-3) can tell from zero
        for i in [10, 12] {
            assert!(
                s.standard[i] >= 0.0 && s.standard[i] < 1e-30,
                "{}",
                s.standard[i]
            );
        }
        // the free term is fitted exactly (measured 0)
        assert!((s.standard[11] + 0.3).abs() < 1e-15, "{}", s.standard[11]);
        // measured 20 - 6.4e-8
        assert!((s.chi2 - 20.0).abs() < 1.3e-7, "chi2 {}", s.chi2);
    }

    /// Two consistent links are each their own optimum: each link has its own variables.
    #[test]
    fn two_links_keep_their_own_values() {
        let second = crate::feasible::LinkInertial {
            mass: 1.2,
            com: [0.05, -0.02, 0.1],
            inertia: [[0.01, 0.001, 0.0], [0.001, 0.012, 0.0], [0.0, 0.0, 0.008]],
        }
        .to_standard();
        let names = crate::feasible::fixture::link_names(2);
        let t: Vec<f64> = link().into_iter().chain(second).collect();
        let problem = Problem::new(names.clone(), names, DMatrix::identity(20, 20))
            .unwrap()
            .with_target(&t, &[1e-3; 20])
            .unwrap();
        let s = solve(&problem, &Bounds::wide(2));
        let worst = s
            .standard
            .iter()
            .zip(&t)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        // the start is the target: equal to rounding (measured 4.4e-16)
        assert_eq!(s.iterations, 50);
        assert!(worst < 1e-14, "{:?}", s.standard);
    }

    /// Each kind of bound met at its known optimum (worked out in the interior-point
    /// method's test of the same name): a mass bound 5 mm below (chi^2 25), a product of
    /// inertia capped at 0 (4), a moment capped 0.003 below (9), the total mass 0.01 below
    /// (100), a centre-of-mass box edge 5 cm inside x = 0.1 m ((0.1 / 1e-3)^2 / (1 + 0.05^2)).
    #[test]
    fn each_kind_of_bound_is_met_at_its_known_optimum() {
        let mut l = link();
        l[1] = 0.002;
        let t = target(l, 0.1);
        let at = |edit: &dyn Fn(&mut Bounds), t: &[f64; 11]| {
            let mut bounds = Bounds::wide(1);
            edit(&mut bounds);
            let p = problem(t);
            (solve(&p, &bounds), p.std)
        };
        // a parameter moved by delta costs (delta / std)^2, std with the solvers' floor
        let cost = |delta: f64, std: f64| (delta / std).powi(2);
        let (s, std) = at(
            &|b| {
                b.links[0] = LinkBounds {
                    mass: [0.0, 1.995],
                    ..LinkBounds::default()
                }
            },
            &t,
        );
        // measured: (steps, value - bound, chi^2 - optimum) (325, 1.9e-9, -1.9e-5), then
        // (600, 5.3e-8, -2.1e-4), (600, 7.9e-8, -4.8e-4), (575, 8.7e-8, -1.7e-3), and
        // (575, 8.6e-7, -1.7e-5 of chi^2): the bounds hold to the penalty's tolerance, and
        // chi^2 falls short of the optimum by 2 delta / std^2 times that excess. The steps
        // are exact: the method is deterministic, and a changed stopping rule shows here.
        assert_eq!(s.iterations, 325);
        assert!((s.standard[9] - 1.995).abs() < 4e-9);
        assert!((s.chi2 - cost(0.005, std[9])).abs() < 3.9e-5, "{}", s.chi2);
        let (s, std) = at(&|b| b.links[0].tensor[3] = Some([-1.0, 0.0]), &t);
        assert_eq!(s.iterations, 600);
        assert!(s.standard[1].abs() < 1.1e-7);
        assert!((s.chi2 - cost(0.002, std[1])).abs() < 4.3e-4, "{}", s.chi2);
        let (s, std) = at(&|b| b.links[0].tensor[2] = Some([0.0, 0.012]), &t);
        assert_eq!(s.iterations, 600);
        assert!((s.standard[5] - 0.012).abs() < 1.6e-7);
        assert!((s.chi2 - cost(0.003, std[5])).abs() < 9.6e-4, "{}", s.chi2);
        let (s, std) = at(&|b| b.total_mass = Some([0.0, 1.99]), &t);
        assert_eq!(s.iterations, 575);
        assert!((s.standard[9] - 1.99).abs() < 1.8e-7);
        assert!((s.chi2 - cost(0.01, std[9])).abs() < 3.5e-3, "{}", s.chi2);
        let mut shifted = link();
        shifted[6] = 0.2;
        shifted[3] += 2.0 * 0.01;
        shifted[5] += 2.0 * 0.01;
        let (s, std) = at(&|b| b.links[0].com[0] = [-1.0, 0.05], &target(shifted, 0.1));
        // h - 0.05 m = 0.1 shared by h and m: 0.1^2 / (std_h^2 + 0.05^2 std_m^2)
        let want = 0.01 / (std[6] * std[6] + 0.0025 * std[9] * std[9]);
        assert_eq!(s.iterations, 575);
        assert!((s.standard[6] - 0.05 * s.standard[9]).abs() < 1.8e-6);
        assert!((s.chi2 / want - 1.0).abs() < 3.5e-5, "{} vs {want}", s.chi2);
    }

    /// The budget of trust-region steps is patience x (variables + 1), in chunks of 25:
    /// 3 x 12 = 36 steps (25 + 11) where the fit needs more.
    #[test]
    fn the_patience_caps_the_steps() {
        let t = target(link(), 0.1);
        let mut bounds = Bounds::wide(1);
        bounds.links[0].mass = [0.0, 1.995];
        let options = SmoothOptions {
            patience: 3,
            ..options()
        };
        let s = solve_smooth(&problem(&t), &bounds, &options).unwrap();
        assert_eq!(s.iterations, 36);
    }

    /// A target that breaks the triangle inequality lands on the boundary of the
    /// consistent set at the best consistent fit, chi^2 = (0.015^2 / 3) / 1e-6 = 75.
    #[test]
    fn an_inconsistent_target_lands_on_the_boundary() {
        let mut l = link();
        l[0] = 0.05;
        let s = solve(&problem(&target(l, 0.1)), &Bounds::wide(1));
        assert_eq!(s.iterations, 50);
        let margin = crate::feasible::DEFAULT_MARGIN;
        let e = s.min_eigenvalues[0];
        assert!(
            e >= margin * (1.0 - 1e-6) && e < 2.0 * margin,
            "eigenvalue {e}"
        );
        // measured 75.020 (the margin keeps the point 1e-6 inside)
        assert!((s.chi2 - 75.0).abs() < 0.04, "chi2 {}", s.chi2);
    }

    /// The gradient and Hessian of the fit in the Cholesky variables against central
    /// differences of its cost, at a point with residuals, drive terms of both kinds and a
    /// violated bound.
    #[test]
    fn the_fit_derivatives_match_its_cost() {
        let mut l = link();
        l[0] = 0.05;
        let mut t = target(l, -0.004).to_vec();
        t.extend([0.01, -0.3]);
        let problem = problem_with(&t, &["Fv", "Fo"]);
        let mut bounds = Bounds::wide(1);
        bounds.links[0].mass = [0.0, 1.9];
        let objective = Objective::from_options(&problem, &bounds, &options()).unwrap();
        let maps = vec![
            Map::Link(0),
            Map::Positive(10),
            // the free term before a non-negative one: each variable's place counts
            Map::Free(12),
            Map::Positive(11),
        ];
        let mut fit = Fit {
            objective,
            margin: crate::feasible::DEFAULT_MARGIN,
            maps,
            x: DVector::zeros(0),
        };
        let p0 = fit
            .objective
            .start(crate::feasible::DEFAULT_MARGIN)
            .unwrap();
        let x = fit.variables(&p0).unwrap().map(|v| v * 1.1 + 0.01);
        fit.x = x.clone();
        let n = x.len();
        assert_eq!(n, 13);
        let g = fit.gradient(&x).unwrap();
        let h = fit.hessian(&x).unwrap();
        let mut worst = (0.0f64, 0.0f64);
        for i in 0..n {
            let step = 1e-6 * (1.0 + x[i].abs());
            let (mut up, mut down) = (x.clone(), x.clone());
            up[i] += step;
            down[i] -= step;
            let dc = (fit.cost(&up).unwrap() - fit.cost(&down).unwrap()) / (2.0 * step);
            worst.0 = worst.0.max((dc - g[i]).abs() / (1.0 + g[i].abs()));
            let dg = (fit.gradient(&up).unwrap() - fit.gradient(&down).unwrap()) / (2.0 * step);
            for k in 0..n {
                worst.1 = worst
                    .1
                    .max((dg[k] - h[(k, i)]).abs() / (1.0 + h[(k, i)].abs()));
            }
        }
        // measured 2.1e-6 and 1.9e-8: central differences with a step of 1e-6 are exact to
        // the rounding of the cost (about 1e-16 of 1e4 over 1e-6) and O(step^2)
        assert!(worst.0 < 4e-6 && worst.1 < 4e-8, "{worst:?}");
    }
}
