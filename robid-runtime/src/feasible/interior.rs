//! The default method: the objective of `objective` minimised directly in the standard
//! parameters p by a primal interior-point (log-barrier) method, the textbook path
//! following of Boyd and Vandenberghe, "Convex Optimization" (2004), ch. 11
//! (docs/experiments.md#feasible-parameters):
//!
//! ```text
//! minimise  f(p) + mu B(p),   B(p) = - sum_links log det(P_j(p) - margin I)
//!                                    - sum_{Ia, Fv, Fc} log p_i
//!                                    - sum_{linear bounds} log (g_l(p) / scale_l)
//! ```
//!
//! The linear bounds are the masses' ranges, the centre-of-mass boxes (`h - lo m >= 0`,
//! `hi m - h >= 0`) and the total mass's range, each with an open range, when the start
//! moved strictly inside them ([`inside_linear`]) is consistent; the bounds on the
//! inertia about the centre of mass (not linear in p) and closed ranges stay penalties of
//! the objective (an augmented Lagrangian).
//!
//! for mu falling tenfold per stage, each stage solved by Newton's method with a
//! backtracking line search that never leaves the interior. f is the sum of squares of
//! `objective` (Gauss-Newton Hessian, exact for all but the violated nonlinear bounds) and
//! B's gradient and Hessian are closed form (d log det P = tr(P^-1 dP)). Every iterate is
//! physically consistent with a margin; the problem is convex in p, so the method reaches
//! the global optimum that the SDP finds, to the barrier's gap `nu mu` (`nu` the barrier's
//! degree), which it drives below 1e-8 of the objective. Needs only the Rust toolchain.

use std::time::Instant;

use nalgebra::{DMatrix, DVector, Matrix4};

use super::bounds::Bounds;
use super::cholesky::PER_LINK;
use super::inertial::{LinkInertial, pseudo_inertia, pseudo_inertia_min_eigenvalue};
use super::layout::Layout;
use super::objective::{Linear, Objective};
use super::problem::Problem;
use super::smooth::SmoothOptions;
use super::solution::{Method, Solution};
use crate::{Error, FeasibleError, Result};

/// The barrier weight falls by this factor per stage.
const MU_FACTOR: f64 = 10.0;
/// Stop when the barrier's gap `nu mu` is below this share of the objective (plus one):
/// chi^2 to 1e-8, while the interior is still wide enough for the Newton steps to be
/// accurate (a smaller gap puts the iterate within rounding of the boundary).
const GAP: f64 = 1e-8;
/// From this gap on, the multipliers of the bounds are updated once per stage.
const SETTLE: f64 = 1e-3;
/// Newton steps per stage at most.
const STEPS_PER_STAGE: usize = 60;
/// The bounds hold when no violation exceeds this share of the bound's scale (the
/// solution's own check allows 1e-6 of the bound).
const BOUND_TOLERANCE: f64 = 1e-9;
/// Extra rounds of multiplier updates at the final barrier weight, at most.
const ROUNDS: usize = 30;

/// The barrier of the consistent set, the non-negative drive terms and the linear bounds
/// with an open range.
struct Barrier<'a> {
    links: &'a [[usize; PER_LINK]],
    positive: Vec<usize>,
    margin: f64,
    /// P(e_k) for each of a link's ten parameters (P is linear in them).
    basis: [Matrix4<f64>; PER_LINK],
    /// Masses, centre-of-mass boxes and the total mass, when a start strictly inside them
    /// was found ([`inside_linear`]); else they stay penalties of the objective.
    linear: Vec<Linear>,
}

impl Barrier<'_> {
    /// The barrier's degree: its gap at the optimum of a stage is `nu mu`.
    fn degree(&self) -> f64 {
        (4 * self.links.len() + self.positive.len() + self.linear.len()) as f64
    }

    /// Each link's P - margin I, or `None` outside the interior.
    fn shifted(&self, p: &[f64], idx: &[usize; PER_LINK]) -> Option<Matrix4<f64>> {
        let values: [f64; PER_LINK] = idx.map(|i| p[i]);
        Some(pseudo_inertia(&values) - Matrix4::identity() * self.margin)
    }

    /// B(p), or `None` outside the interior.
    fn value(&self, p: &[f64]) -> Option<f64> {
        let mut b = 0.0;
        for idx in self.links {
            let c = self.shifted(p, idx)?.cholesky()?;
            let det: f64 = c.l().diagonal().iter().map(|d| d.ln()).sum();
            b -= 2.0 * det;
        }
        for &i in &self.positive {
            if !(p[i] > 0.0) {
                return None;
            }
            b -= p[i].ln();
        }
        for l in &self.linear {
            let g = l.value(p) / l.scale;
            if !(g > 0.0) {
                return None;
            }
            b -= g.ln();
        }
        b.is_finite().then_some(b)
    }

    /// Adds `mu` times B's gradient and Hessian at an interior p.
    fn add_derivatives(&self, p: &[f64], mu: f64, g: &mut DVector<f64>, h: &mut DMatrix<f64>) {
        for idx in self.links {
            let Some(q) = self.shifted(p, idx).and_then(|s| s.try_inverse()) else {
                continue;
            };
            let qe: Vec<Matrix4<f64>> = self.basis.iter().map(|e| q * e).collect();
            for (a, &i) in idx.iter().enumerate() {
                g[i] -= mu * qe[a].trace();
                for (b, &k) in idx.iter().enumerate() {
                    // tr(Q E_a Q E_b)
                    h[(i, k)] += mu * qe[a].component_mul(&qe[b].transpose()).sum();
                }
            }
        }
        for &i in &self.positive {
            g[i] -= mu / p[i];
            h[(i, i)] += mu / (p[i] * p[i]);
        }
        for l in &self.linear {
            let v = l.value(p);
            for &(i, ci) in &l.entries {
                g[i] -= mu * ci / v;
                for &(k, ck) in &l.entries {
                    h[(i, k)] += mu * ci * ck / (v * v);
                }
            }
        }
    }
}

/// Physically consistent standard parameters that reproduce the identified base
/// parameters of `problem` within the bounds, settled by the prior where the data leave
/// them free: the global optimum of the convex fit, by an interior-point method (see the
/// module documentation). `options.patience` caps the Newton steps at `patience` per
/// variable.
pub fn solve_interior(
    problem: &Problem,
    bounds: &Bounds,
    options: &SmoothOptions,
) -> Result<Solution> {
    let start = Instant::now();
    let layout = &problem.layout;
    let mut objective = Objective::from_options(problem, bounds, options)?;
    let margin = bounds.margin_for(layout, Some(&objective.pull.target))?;
    let mut p = objective.start(margin)?;
    let mut barrier = Barrier {
        links: &layout.links,
        positive: (0..p.len())
            .filter(|&i| objective.non_negative(i))
            .collect(),
        margin,
        basis: std::array::from_fn(|k| {
            let mut e = [0.0; PER_LINK];
            e[k] = 1.0;
            pseudo_inertia(&e)
        }),
        linear: Vec::new(),
    };
    // the linear bounds in the barrier, from a start strictly inside them: the iterates
    // never leave them (as penalties, a bound the data push far against was left behind
    // where the penalty's stiffening stalled: a 59 kg link against [0, 50])
    if let Some(inside) = inside_linear(&p, layout, bounds, margin) {
        barrier.linear = objective.open_linear();
        if barrier.value(&inside).is_some() {
            objective.drop_open_linear();
            p = inside;
        } else {
            barrier.linear.clear();
        }
    }
    let nu = barrier.degree();
    let mut mu = objective.value(&p).max(1.0) / nu;
    let budget = options.patience.saturating_mul(p.len() + 1);
    let mut steps_left = budget;
    // the barrier's path; near its end (gap below SETTLE of the objective) the multipliers
    // of the bounds are updated once per stage, then at the last weight until they hold
    let mut rounds = 0;
    let mut last = f64::INFINITY;
    loop {
        p = newton(&objective, &barrier, p, mu, &mut steps_left)?;
        let f = objective.value(&p);
        let converged = nu * mu <= GAP * (1.0 + f);
        let violation = if nu * mu <= SETTLE * (1.0 + f) {
            objective.update_shifts(&p)
        } else {
            0.0
        };
        // the multipliers converge at the rate data / (data + penalty): a violation that
        // falls slowly means data firmer than the penalty
        if violation > BOUND_TOLERANCE && violation > 0.25 * last {
            objective.stiffen(10.0);
        }
        last = violation;
        if steps_left == 0 || (converged && (violation <= BOUND_TOLERANCE || rounds == ROUNDS)) {
            break;
        }
        if converged {
            rounds += 1;
        } else {
            mu /= MU_FACTOR;
        }
    }
    let value = objective.fit_value(&p);
    let mut solution = Solution::assemble(problem, bounds, Method::Interior, p, start.elapsed())?;
    solution.iterations = budget - steps_left;
    solution.objective = Some(value);
    solution.determined = super::prior::determined(problem, &objective.pull);
    solution.unpulled = super::prior::unpulled(problem, &objective.pull);
    Ok(solution)
}

/// Share of an open range kept between a start moved inside it and its ends.
const INSIDE: f64 = 0.05;

/// p with every link's mass and centre of mass moved strictly inside their ranges (onto a
/// closed range, which stays a penalty) and the total mass inside its range (the inertia
/// about the centre of mass kept in shape, scaled with the mass), or `None` when the
/// masses cannot reach the total or a link is not consistent. The share kept from the
/// ends is [`INSIDE`], or less where the total needs it: a total of [0.1, 0.2] kg under
/// links of [0, 50] kg is out of reach of masses kept 2.5 kg from zero (the bounds were
/// then penalties, and the fit ended at 2.2 kg).
fn inside_linear(p: &[f64], layout: &Layout, bounds: &Bounds, margin: f64) -> Option<Vec<f64>> {
    [1.0, 1e-2, 1e-4, 1e-6]
        .iter()
        .find_map(|s| inside_linear_by(p, layout, bounds, margin, INSIDE * s))
}

/// [`inside_linear`] keeping a share `inside` of each range from its ends.
fn inside_linear_by(
    p: &[f64],
    layout: &Layout,
    bounds: &Bounds,
    margin: f64,
    inside: f64,
) -> Option<Vec<f64>> {
    let inner = |[lo, hi]: [f64; 2]| {
        let w = inside * (hi - lo);
        [lo + w, hi - w]
    };
    let mut links = Vec::with_capacity(layout.links.len());
    let mut masses = Vec::with_capacity(layout.links.len());
    for (j, idx) in layout.links.iter().enumerate() {
        let b = &bounds.links[j];
        let link = LinkInertial::from_standard(&idx.map(|i| p[i]))?;
        let [lo, hi] = inner(b.mass);
        masses.push(([lo, hi], link.mass.clamp(lo, hi)));
        let mut com = link.com;
        for (c, range) in com.iter_mut().zip(b.com) {
            let [lo, hi] = inner(range);
            *c = c.clamp(lo, hi);
        }
        links.push((link, com));
    }
    if let Some(range) = bounds.total_mass {
        let [lo, hi] = inner(range);
        let least: f64 = masses.iter().map(|(r, _)| r[0]).sum();
        let most: f64 = masses.iter().map(|(r, _)| r[1]).sum();
        let (lo, hi) = (lo.max(least), hi.min(most));
        if lo > hi {
            return None;
        }
        let total: f64 = masses.iter().map(|(_, m)| m).sum();
        let target = total.clamp(lo, hi);
        // every mass the same share of the way to the end of its range the total moves to
        let room: f64 = masses
            .iter()
            .map(|([a, b], m)| if target > total { b - m } else { m - a })
            .sum();
        if room > 0.0 {
            let t = ((target - total).abs() / room).min(1.0);
            for ([a, b], m) in &mut masses {
                *m += t * if target > total { *b - *m } else { *a - *m };
            }
        }
    }
    let mut out = p.to_vec();
    for ((idx, (link, com)), (_, mass)) in layout.links.iter().zip(links).zip(masses) {
        if mass <= margin {
            return None;
        }
        // the second moments about the centre of mass raised by `a I` (the inertia by 2a)
        // so that the pseudo-inertia stays above the margin: its Schur complement needs
        // Sigma_c > margin (I + m / (m - margin) c c'), which moving c out can break
        let c2: f64 = com.iter().map(|c| c * c).sum();
        let a = 2.0 * margin * (1.0 + mass / (mass - margin) * c2);
        let mut moved = LinkInertial {
            mass,
            com,
            inertia: link.inertia.map(|row| row.map(|v| v * mass / link.mass)),
        };
        if pseudo_inertia_min_eigenvalue(&moved.to_standard()) <= 2.0 * margin {
            for (k, row) in moved.inertia.iter_mut().enumerate() {
                row[k] += 2.0 * a;
            }
        }
        for (&i, v) in idx.iter().zip(moved.to_standard()) {
            out[i] = v;
        }
    }
    Some(out)
}

/// Newton's method on `f + mu B` from the interior point p, at most [`STEPS_PER_STAGE`]
/// steps (and `steps_left`); every step stays in the interior.
fn newton(
    objective: &Objective<'_>,
    barrier: &Barrier<'_>,
    mut p: Vec<f64>,
    mu: f64,
    steps_left: &mut usize,
) -> Result<Vec<f64>> {
    let stuck = || {
        Error::Feasible(FeasibleError::NoFeasibleParameters {
            reason: "the interior-point fit left the consistent set or met a non-finite value; check the identified values and the bounds".into(),
        })
    };
    let phi = |p: &[f64]| -> Option<f64> {
        let v = objective.value(p) + mu * barrier.value(p)?;
        v.is_finite().then_some(v)
    };
    for _ in 0..STEPS_PER_STAGE {
        if *steps_left == 0 {
            break;
        }
        *steps_left -= 1;
        let r = objective.residuals(&p);
        let j = objective.jacobian(&p);
        let mut g = j.tr_mul(&r) * 2.0;
        let mut h = j.tr_mul(&j) * 2.0;
        barrier.add_derivatives(&p, mu, &mut g, &mut h);
        let step = newton_step(h, &g).ok_or_else(stuck)?;
        let slope = g.dot(&step);
        let now = phi(&p).ok_or_else(stuck)?;
        if -slope <= 1e-14 * (1.0 + now.abs()) {
            break;
        }
        match backtrack(&phi, &p, &step, now, slope) {
            Some(trial) => p = trial,
            None => break,
        }
    }
    Ok(p)
}

/// Backtracking line search along `step` from p, where phi is `now` and its slope along
/// the step `slope` (< 0): the longest of 1, 1/2, 1/4, ... down to 1e-12 that stays in
/// phi's domain and decreases phi by at least 1e-4 of the slope's prediction (Armijo);
/// `None` when none does.
fn backtrack(
    phi: &dyn Fn(&[f64]) -> Option<f64>,
    p: &[f64],
    step: &DVector<f64>,
    now: f64,
    slope: f64,
) -> Option<Vec<f64>> {
    let mut s = 1.0;
    loop {
        let trial: Vec<f64> = p.iter().zip(step.iter()).map(|(a, d)| a + s * d).collect();
        if let Some(v) = phi(&trial)
            && v <= now + 1e-4 * s * slope
        {
            return Some(trial);
        }
        s *= 0.5;
        if s < 1e-12 {
            return None;
        }
    }
}

/// Solves H step = -g by Cholesky, adding a small multiple of the identity when H is not
/// numerically positive definite (a free term the data and the prior leave undetermined).
fn newton_step(h: DMatrix<f64>, g: &DVector<f64>) -> Option<DVector<f64>> {
    let top = h.diagonal().iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let mut shift = 0.0;
    for _ in 0..12 {
        let mut shifted = h.clone();
        for i in 0..shifted.nrows() {
            shifted[(i, i)] += shift;
        }
        if let Some(c) = shifted.cholesky() {
            let step = -c.solve(g);
            return step.iter().all(|v| v.is_finite()).then_some(step);
        }
        shift = if shift == 0.0 {
            1e-14 * top.max(1e-300)
        } else {
            shift * 100.0
        };
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::feasible::fixture::{link, options, problem, steps, target};
    use crate::feasible::{LinkBounds, LinkInertial};

    /// The barrier's value, gradient and Hessian agree: a known value (P - margin I = 2 I
    /// and Ia = 0.5 give B = -4 ln 2 - ln 0.5), and the derivatives against central
    /// differences at an interior point.
    #[test]
    fn the_barrier_derivatives_match_its_value() {
        let layout =
            crate::feasible::Layout::from_names(&problem(&[0.0; 11]).standard_names).unwrap();
        let margin = 1e-3;
        let barrier = Barrier {
            links: &layout.links,
            positive: vec![10],
            margin,
            basis: std::array::from_fn(|k| {
                let mut e = [0.0; PER_LINK];
                e[k] = 1.0;
                pseudo_inertia(&e)
            }),
            linear: Vec::new(),
        };
        assert_eq!(barrier.degree(), 5.0);
        let two = [layout.links[0]; 2];
        let pair = Barrier {
            links: &two,
            positive: vec![10, 10, 10],
            linear: Vec::new(),
            ..barrier
        };
        assert_eq!(pair.degree(), 11.0);
        // P = (2 + margin) I: Sigma = (2 + margin) I, so J = tr(Sigma) I - Sigma = 2 (2 + margin) I
        let s = 2.0 + margin;
        let mut p = vec![
            2.0 * s,
            0.0,
            0.0,
            2.0 * s,
            0.0,
            2.0 * s,
            0.0,
            0.0,
            0.0,
            s,
            0.5,
        ];
        let known = -4.0 * 2.0f64.ln() - 0.5f64.ln();
        assert!((barrier.value(&p).unwrap() - known).abs() < 1e-12);
        // with two linear bounds, a mass of at least 0.5 (scale 2) and a centre of mass
        // x of at most 0.2 (0.2 m - MX >= 0, scale 0.5): -ln((s - 0.5) / 2) - ln(0.2 s / 0.5)
        let barrier = Barrier {
            linear: vec![
                Linear {
                    entries: vec![(9, 1.0)],
                    rhs: 0.5,
                    scale: 2.0,
                },
                Linear {
                    entries: vec![(6, -1.0), (9, 0.2)],
                    rhs: 0.0,
                    scale: 0.5,
                },
            ],
            ..barrier
        };
        assert_eq!(barrier.degree(), 7.0);
        let known = known - ((s - 0.5) / 2.0).ln() - (0.2 * s / 0.5).ln();
        assert!((barrier.value(&p).unwrap() - known).abs() < 1e-12);
        // outside a linear bound: no value
        let mut outside = p.clone();
        outside[6] = 0.2 * s;
        assert_eq!(barrier.value(&outside), None);
        // an interior point with products of inertia and an offset centre of mass
        p = target(
            LinkInertial {
                mass: 1.5,
                com: [0.05, -0.02, 0.1],
                inertia: [
                    [0.03, 0.002, -0.001],
                    [0.002, 0.025, 0.003],
                    [-0.001, 0.003, 0.02],
                ],
            }
            .to_standard(),
            0.2,
        )
        .to_vec();
        let n = p.len();
        let mu = 0.7;
        let mut g = DVector::zeros(n);
        let mut h = DMatrix::zeros(n, n);
        barrier.add_derivatives(&p, mu, &mut g, &mut h);
        let gradient = |p: &[f64]| {
            let mut g = DVector::zeros(n);
            barrier.add_derivatives(p, mu, &mut g, &mut DMatrix::zeros(n, n));
            g
        };
        let step = 1e-6;
        for i in 0..n {
            let (mut up, mut down) = (p.clone(), p.clone());
            up[i] += step;
            down[i] -= step;
            let fd =
                mu * (barrier.value(&up).unwrap() - barrier.value(&down).unwrap()) / (2.0 * step);
            // central differences of step 1e-6: measured 3.9e-8 (gradient) and 2.7e-7
            // (Hessian) at most, relative
            assert!(
                (fd - g[i]).abs() < 8e-8 * (1.0 + g[i].abs()),
                "gradient {i}: {fd} vs {}",
                g[i]
            );
            let dg = (gradient(&up) - gradient(&down)) / (2.0 * step);
            for k in 0..n {
                assert!(
                    (dg[k] - h[(k, i)]).abs() < 5.4e-7 * (1.0 + h[(k, i)].abs()),
                    "hessian {k} {i}: {} vs {}",
                    dg[k],
                    h[(k, i)]
                );
            }
        }
        // outside: a mass at zero and a negative rotor inertia
        let mut out = p.clone();
        out[10] = 0.0;
        assert!(barrier.value(&out).is_none());
        out = p.clone();
        out[9] = 0.0;
        assert!(barrier.value(&out).is_none());
    }

    /// A singular Hessian (a direction neither the data, the prior nor the barrier sees)
    /// still gives a finite step: the smallest identity shift that makes it positive
    /// definite, so that the shifted system holds; a positive definite one is solved as is.
    /// The line search on phi(x) = x^2 from x = 1 along -2 (slope -4): the full step
    /// reaches x = -1, where phi is back at 1 (no decrease), the half step x = 0 (phi 0)
    /// is taken. A phi that rises by half the Armijo margin at every step length is
    /// refused, as is a phi with no finite value anywhere along the step, after the 40
    /// lengths 1 to 2^-39 (the next, 2^-40 = 9.1e-13, is below 1e-12).
    #[test]
    fn the_line_search_takes_the_longest_step_with_enough_decrease() {
        let step = DVector::from_vec(vec![-2.0]);
        let square = |x: &[f64]| Some(x[0] * x[0]);
        assert_eq!(
            backtrack(&square, &[1.0], &step, 1.0, -4.0),
            Some(vec![0.0])
        );
        // the slope's prediction at length s is -4 s; a rise of half its Armijo share
        let rise = |x: &[f64]| Some(1.0 + 0.5e-4 * 4.0 * (1.0 - x[0]) / 2.0);
        assert_eq!(backtrack(&rise, &[1.0], &step, 1.0, -4.0), None);
        let calls = std::cell::Cell::new(0);
        let nowhere = |_: &[f64]| {
            calls.set(calls.get() + 1);
            None
        };
        assert_eq!(backtrack(&nowhere, &[1.0], &step, 1.0, -4.0), None);
        assert_eq!(calls.get(), 40);
    }

    #[test]
    fn a_singular_hessian_gets_the_smallest_shift_that_works() {
        let g = DVector::from_vec(vec![1.0, -2.0]);
        let h = DMatrix::from_row_slice(2, 2, &[2.0, 0.0, 0.0, 4.0]);
        let step = newton_step(h, &g).unwrap();
        assert!(
            (step[0] + 0.5).abs() < 1e-15 && (step[1] - 0.5).abs() < 1e-15,
            "{step}"
        );
        let h = DMatrix::from_row_slice(2, 2, &[1.0, 1.0, 1.0, 1.0]);
        let step = newton_step(h.clone(), &g).unwrap();
        // the residual of the unshifted system is the shift times the step: tiny
        let residual = &h * &step + &g;
        let shift = residual.norm() / step.norm();
        assert!(shift > 0.0 && shift < 1e-9, "shift {shift}, step {step}");
        // the first shift is 1e-14 of the largest diagonal element (4 here): the residual
        // over the step recovers it to the rounding of h step ~ 1e13 (measured 1.2 %)
        let step = newton_step(&h * 4.0, &g).unwrap();
        let shift = (&h * 4.0 * &step + &g).norm() / step.norm();
        assert!((shift / 4e-14 - 1.0).abs() < 0.025, "shift {shift}");
        // an indefinite one: the shift grows by 100 from there until it works, 1e-8 for an
        // eigenvalue of -1e-10
        let h = DMatrix::from_row_slice(2, 2, &[1.0, 0.0, 0.0, -1e-10]);
        let step = newton_step(h, &g).unwrap();
        let want = 2.0 / (1e-8 - 1e-10);
        assert!((step[1] / want - 1.0).abs() < 1e-7, "{step} vs {want}");
    }

    /// Settings out of range are refused by both pure-Rust methods, naming the setting.
    #[test]
    fn bad_settings_are_refused_by_name() {
        let problem = problem(&target(link(), 0.1));
        for (options, key) in [
            (
                SmoothOptions {
                    default_weight: f64::NAN,
                    ..options()
                },
                "default_weight",
            ),
            (
                SmoothOptions {
                    penalty: 0.0,
                    ..options()
                },
                "penalty",
            ),
            (
                SmoothOptions {
                    patience: 0,
                    ..options()
                },
                "patience",
            ),
        ] {
            for solve in [solve_interior, super::super::solve_smooth] {
                let e = solve(&problem, &Bounds::wide(1), &options).unwrap_err();
                assert!(e.to_string().contains(key), "{e}");
            }
        }
    }

    /// The start moved inside the linear bounds: each mass and centre-of-mass coordinate
    /// clamped 5 % inside its range, the inertia about the centre of mass scaled with the
    /// mass, the masses moved together until the total is inside its range; no such start
    /// for a closed range or a total the masses cannot reach.
    #[test]
    fn the_start_moves_inside_the_linear_bounds() {
        let t = target(link(), 0.1);
        let problem = problem(&t);
        let layout = &problem.layout;
        let mut bounds = Bounds::wide(1);
        bounds.links[0].mass = [0.0, 1.0];
        bounds.links[0].com[2] = [0.1, 0.3];
        let p = inside_linear(&t, layout, &bounds, 1e-6).unwrap();
        let moved = LinkInertial::from_standard(&std::array::from_fn(|i| p[i])).unwrap();
        assert!((moved.mass - 0.95).abs() < 1e-12, "{moved:?}");
        assert!((moved.com[2] - 0.11).abs() < 1e-12, "{moved:?}");
        assert!(
            (moved.inertia[0][0] - 0.03 * 0.95 / 2.0).abs() < 1e-12,
            "{moved:?}"
        );
        // a total mass above the link's mass: the mass moves up to it (within its range)
        bounds.links[0].mass = [0.0, 10.0];
        bounds.total_mass = Some([5.0, 7.0]);
        let p = inside_linear(&t, layout, &bounds, 1e-6).unwrap();
        assert!((p[9] - 5.1).abs() < 1e-12, "{}", p[9]);
        // the total's two bounds in the barrier, last: 5.1 - 5 and 7 - 5.1
        let linear = Objective::from_options(&problem, &bounds, &options())
            .unwrap()
            .open_linear();
        let total: Vec<f64> = linear[8..].iter().map(|l| l.value(&p)).collect();
        assert!(
            (total[0] - 0.1).abs() < 1e-12 && (total[1] - 1.9).abs() < 1e-12,
            "{total:?}"
        );
        // a total below the link's mass: the mass moves down to it
        let mut below = bounds.clone();
        below.total_mass = Some([0.5, 1.0]);
        let p = inside_linear(&t, layout, &below, 1e-6).unwrap();
        assert!((p[9] - 0.975).abs() < 1e-12, "{}", p[9]);
        // a closed range: onto it (a penalty keeps it); a total out of the masses' reach:
        // no start
        let mut b = bounds.clone();
        b.links[0].mass = [5.5, 5.5];
        b.links[0].com[1] = [0.3, 0.3];
        let p = inside_linear(&t, layout, &b, 1e-6).unwrap();
        assert_eq!((p[9], p[7]), (5.5, 0.3 * 5.5));
        b.total_mass = Some([20.0, 30.0]);
        assert!(inside_linear(&t, layout, &b, 1e-6).is_none());
        // a total far below the range's 5 % (0.1 to 0.2 kg under [0, 50] kg): kept less
        // far from the ends, inside the total (there was no start, the bounds penalties)
        let mut small = Bounds::wide(1);
        small.total_mass = Some([0.1, 0.2]);
        let p = inside_linear(&t, layout, &small, 1e-6).unwrap();
        assert!(p[9] > 0.1 && p[9] < 0.2, "{}", p[9]);
        // the barrier's linear bounds: the open ranges, two per mass, axis and total
        let open = |b: &Bounds| {
            Objective::from_options(&problem, b, &options())
                .unwrap()
                .open_linear()
                .len()
        };
        assert_eq!(open(&bounds), 2 + 6 + 2);
        // a closed mass and y axis, a closed total: in the penalties
        b.total_mass = Some([5.5, 5.5]);
        assert_eq!(open(&b), 4);
    }

    /// A centre of mass moved 5 m out with the inertia about it kept leaves the consistent
    /// set with a margin (the margin's share of m c c' exceeds the second moments): the
    /// start raises the inertia about the centre of mass to stay consistent, and the fit
    /// meets the box in the barrier (as a penalty the box was missed: x 0.06 against
    /// [5, 6]).
    #[test]
    fn a_start_moved_far_is_kept_consistent() {
        let t = target(link(), 0.1);
        let problem = problem(&t);
        let mut bounds = Bounds::wide(1);
        bounds.links[0].com[0] = [5.0, 6.0];
        bounds.margin = Some(0.01);
        // a prior at the link itself, centre of mass at the origin
        let options = SmoothOptions {
            prior: Some(crate::feasible::Prior {
                standard: t.iter().map(|&v| Some(v)).collect(),
                weight: 1e-6,
            }),
            ..options()
        };
        let objective = Objective::from_options(&problem, &bounds, &options).unwrap();
        let start = objective.start(0.01).unwrap();
        let inside = inside_linear(&start, &problem.layout, &bounds, 0.01).unwrap();
        let barrier = Barrier {
            links: &problem.layout.links,
            positive: vec![10],
            margin: 0.01,
            basis: std::array::from_fn(|k| {
                let mut e = [0.0; PER_LINK];
                e[k] = 1.0;
                pseudo_inertia(&e)
            }),
            linear: objective.open_linear(),
        };
        assert!(barrier.value(&inside).is_some());
        let s = solve_interior(&problem, &bounds, &options).unwrap();
        assert!(s.unmet.is_empty(), "{:?}", s.unmet);
        let x = s.standard[6] / s.standard[9];
        assert!((5.0 - 1e-6..=6.0).contains(&x), "{x}");
    }

    /// A consistent target inside the bounds is its own optimum: the barrier and the
    /// penalty leave it where it is.
    #[test]
    fn a_consistent_target_is_returned_as_it_is() {
        let t = target(link(), 0.1);
        let s = solve_interior(&problem(&t), &Bounds::wide(1), &options()).unwrap();
        steps(&s, 68);
        // the barrier's gap, the mass and centre-of-mass ranges in it too (measured
        // 4.5e-11 at most, chi^2 4.3e-15; the gap allows 1e-8)
        for (got, want) in s.standard.iter().zip(&t) {
            assert!((got - want).abs() < 9e-11, "{:?} vs {t:?}", s.standard);
        }
        assert!(s.chi2 < 9e-15, "chi2 {}", s.chi2);
    }

    /// A consistent link of 12 g (a gripper jaw; its pseudo-inertia's smallest eigenvalue
    /// is 5.0e-7, below the margin of ordinary links) measured to 1e-9 is returned as it is
    /// (chi^2 7e-16 measured): the default margin is 1 % of the prior's smallest eigenvalue.
    /// The margin of ordinary links, 1e-6, moves it hundreds of standard deviations (chi^2
    /// 3.1e5 measured).
    #[test]
    fn a_small_consistent_link_is_not_held_off_by_the_margin() {
        let jaw = LinkInertial {
            mass: 0.012,
            com: [0.005, -0.01, 0.02],
            inertia: [[2e-6, 0.0, 0.0], [0.0, 5e-6, 0.0], [0.0, 0.0, 6e-6]],
        }
        .to_standard();
        let t = target(jaw, 1e-7);
        let names = crate::feasible::fixture::names();
        let p = Problem::new(names.clone(), names, DMatrix::identity(11, 11))
            .unwrap()
            .with_target(&t, &[1e-9; 11])
            .unwrap();
        let smallest = crate::feasible::pseudo_inertia_min_eigenvalue(&jaw);
        assert!(smallest > 4.9e-7 && smallest < 5.1e-7, "{smallest}");
        let prior = SmoothOptions {
            prior: Some(crate::feasible::Prior {
                standard: t.iter().map(|&v| Some(v)).collect(),
                weight: 1.0,
            }),
            ..options()
        };
        let s = solve_interior(&p, &Bounds::wide(1), &prior).unwrap();
        assert!(s.chi2 < 1e-6, "chi2 {}", s.chi2);
        let given = Bounds {
            margin: Some(crate::feasible::DEFAULT_MARGIN),
            ..Bounds::wide(1)
        };
        let held = solve_interior(&p, &given, &prior).unwrap();
        assert!(held.chi2 > 1e4, "chi2 {}", held.chi2);
    }

    /// A negative rotor inertia is held at zero (the barrier of Ia >= 0), the rest kept:
    /// chi^2 = (Ia / std)^2, std with the solvers' floor.
    #[test]
    fn a_negative_rotor_inertia_is_held_at_zero() {
        let t = target(link(), -0.004);
        let s = solve_interior(&problem(&t), &Bounds::wide(1), &options()).unwrap();
        steps(&s, 133);
        // measured 1.4e-12 and chi^2 1.1e-8 above the optimum
        assert!(
            s.standard[10] >= 0.0 && s.standard[10] < 2.8e-12,
            "{}",
            s.standard[10]
        );
        let optimum = (0.004 / problem(&t).std[10]).powi(2);
        assert!((s.chi2 - optimum).abs() < 2.2e-8, "chi2 {}", s.chi2);
    }

    /// A mass bound below the identified mass (with the centre of mass at the origin, so
    /// the mass couples to nothing else) is met exactly, the other values kept: chi^2 =
    /// ((m - bound) / std)^2 = 25.
    #[test]
    fn a_mass_bound_is_met_exactly() {
        let t = target(link(), 0.1);
        let mut bounds = Bounds::wide(1);
        bounds.links[0] = LinkBounds {
            mass: [0.0, 1.995],
            ..LinkBounds::default()
        };
        let s = solve_interior(&problem(&t), &bounds, &options()).unwrap();
        steps(&s, 102);
        // measured 9.3e-11 kg, and chi^2 9.3e-7 below the optimum with the floored
        // deviation (2 x 0.005 / std^2 times that excess)
        assert!(
            (s.standard[9] - 1.995).abs() < 1.9e-10,
            "mass {}",
            s.standard[9]
        );
        let optimum = (0.005 / problem(&t).std[9]).powi(2);
        assert!((s.chi2 - optimum).abs() < 1.9e-6, "chi2 {}", s.chi2);
        assert!(s.violations.is_empty(), "{:?}", s.violations);
    }

    /// Each kind of bound met at its known optimum (centre of mass at the origin unless
    /// said, so that the bound couples to nothing else): a product of inertia capped at 0
    /// (chi^2 (0.002 / 1e-3)^2 = 4), a moment capped 0.003 below its value (9), the total
    /// mass capped 0.01 below (100), and a centre-of-mass box edge 5 cm inside a centre of
    /// mass at x = 0.1 m, where h_x - 0.05 m = 0.1 is shared by h_x and m:
    /// (0.1 / 1e-3)^2 / (1 + 0.05^2).
    #[test]
    fn each_kind_of_bound_is_met_at_its_known_optimum() {
        let mut l = link();
        l[1] = 0.002; // XY: with the centre of mass at the origin, I_c's xy
        let t = target(l, 0.1);
        let solve = |edit: &dyn Fn(&mut Bounds), t: &[f64; 11], measured: usize| {
            let mut bounds = Bounds::wide(1);
            edit(&mut bounds);
            let s = solve_interior(&problem(t), &bounds, &options()).unwrap();
            steps(&s, measured);
            assert!(s.violations.is_empty(), "{:?}", s.violations);
            s
        };
        // against the optima with the floored deviations; measured (value - bound, chi^2 -
        // optimum): (5.3e-8, -2.1e-4), (1.8e-8, -1.1e-4), (1.7e-8, -3.5e-4), and for the
        // centre of mass 3.4e-8 m kg and -6.9e-7 of chi^2
        let std = problem(&t).std;
        let cost = |delta: f64, i: usize| (delta / std[i]).powi(2);
        let s = solve(&|b| b.links[0].tensor[3] = Some([-1.0, 0.0]), &t, 81);
        assert!(s.standard[1].abs() < 1.1e-7, "{}", s.standard[1]);
        assert!((s.chi2 - cost(0.002, 1)).abs() < 4.3e-4, "{}", s.chi2);
        let s = solve(&|b| b.links[0].tensor[2] = Some([0.0, 0.012]), &t, 83);
        assert!((s.standard[5] - 0.012).abs() < 3.7e-8, "{}", s.standard[5]);
        assert!((s.chi2 - cost(0.003, 5)).abs() < 2.2e-4, "{}", s.chi2);
        // (in the barrier: a start 5 % inside the link's [0, 50] kg could not meet this
        // total, so it was a penalty, 87 steps)
        let s = solve(&|b| b.total_mass = Some([0.0, 1.99]), &t, 82);
        assert!((s.standard[9] - 1.99).abs() < 3.5e-8, "{}", s.standard[9]);
        assert!((s.chi2 - cost(0.01, 9)).abs() < 7e-4, "{}", s.chi2);
        let mut shifted = link();
        shifted[6] = 0.2; // MX: centre of mass at x = 0.1 m
        shifted[3] += 2.0 * 0.01; // YY and ZZ by the parallel axis: m x^2 = 0.02
        shifted[5] += 2.0 * 0.01;
        let t = target(shifted, 0.1);
        let s = solve(&|b| b.links[0].com[0] = [-1.0, 0.05], &t, 95);
        let (h, m) = (s.standard[6], s.standard[9]);
        let std = problem(&t).std;
        let want = 0.1f64.powi(2) / (std[6].powi(2) + (0.05 * std[9]).powi(2));
        assert!((h - 0.05 * m).abs() < 6.9e-8, "h {h}, m {m}");
        assert!(
            (s.chi2 - want).abs() < 1.4e-6 * want,
            "chi2 {} vs {want}",
            s.chi2
        );
    }

    /// Bounds that no consistent link meets (XX and YY at most 0.001, ZZ at least 0.01,
    /// against ZZ <= XX + YY): the multipliers cannot settle, so the fit stops after its
    /// rounds at the last barrier weight, well inside the budget of Newton steps, and
    /// reports what it could not meet.
    #[test]
    fn bounds_no_consistent_link_meets_end_after_the_rounds_and_are_reported() {
        let t = target(link(), 0.1);
        let mut bounds = Bounds::wide(1);
        bounds.links[0].tensor[0] = Some([0.0, 0.001]);
        bounds.links[0].tensor[1] = Some([0.0, 0.001]);
        bounds.links[0].tensor[2] = Some([0.01, 1.0]);
        let s = solve_interior(&problem(&t), &bounds, &options()).unwrap();
        // the budget is 100 x 12 steps
        steps(&s, 133);
        assert_eq!(s.violations.len(), 3, "{:?}", s.violations);
    }

    /// A target that breaks the triangle inequality (XX > YY + ZZ about the centre of
    /// mass) is moved onto the boundary of the consistent set: its smallest pseudo-inertia
    /// eigenvalue is the margin, and the fit is the best consistent one, better than the
    /// nearest point that a naive repair (raising YY) gives.
    #[test]
    fn an_inconsistent_target_lands_on_the_boundary() {
        let mut l = link();
        l[0] = 0.05; // XX above YY + ZZ = 0.035 (com at the origin: J = I_c)
        let t = target(l, 0.1);
        let s = solve_interior(&problem(&t), &Bounds::wide(1), &options()).unwrap();
        steps(&s, 108);
        let margin = crate::feasible::DEFAULT_MARGIN;
        let e = s.min_eigenvalues[0];
        // measured 1 + 5.5e-6 margins
        assert!(
            e >= margin * (1.0 - 1e-6) && e < margin * (1.0 + 1.1e-5),
            "eigenvalue {e}"
        );
        // raising YY by 0.015 alone is consistent and costs (0.015 / 1e-3)^2 = 225; the
        // optimum spreads the change over XX, YY and ZZ: (0.015^2 / 3) / 1e-6 = 75, here
        // measured 75.020 (the margin keeps the point 1e-6 inside the boundary)
        assert!((s.chi2 - 75.0).abs() < 0.04, "chi2 {}", s.chi2);
    }
}
