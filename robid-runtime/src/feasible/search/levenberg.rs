//! A bounded Levenberg-Marquardt polish (Marquardt 1963) of a least-squares residual:
//! forward-difference Jacobian (the search's re-evaluates only the stepped link), damped
//! Gauss-Newton steps in the variables that no bound holds (a variable at a bound the
//! gradient pushes against stays there), clipped to the box. Used after Nelder-Mead, whose
//! progress in tens of dimensions is slow near the optimum.

use nalgebra::{DMatrix, DVector};

/// The Jacobian of a residual at x, given the residual there.
pub(crate) type Jacobian<'a> = dyn Fn(&[f64], &DVector<f64>) -> DMatrix<f64> + 'a;

/// [`polish_with`] with the Jacobian by [`forward_differences`] (the search gives its own,
/// which re-evaluates only what a step changes).
#[cfg(test)]
pub(crate) fn polish(
    r: &dyn Fn(&[f64]) -> DVector<f64>,
    lo: &[f64],
    hi: &[f64],
    x0: &[f64],
    iterations: usize,
) -> Vec<f64> {
    let jacobian = |x: &[f64], rx: &DVector<f64>| forward_differences(r, lo, hi, x, rx);
    polish_with(r, &jacobian, lo, hi, x0, iterations)
}

/// Minimises ||r(x)||^2 over [lo, hi] from `x0` for at most `iterations` steps, with the
/// Jacobian of `r` at x (whose residual is rx) from `jacobian`; stops after a step that
/// gains less than 1e-15 (1 + f), or when no damping finds a step that does not raise f.
pub(crate) fn polish_with(
    r: &dyn Fn(&[f64]) -> DVector<f64>,
    jacobian: &Jacobian<'_>,
    lo: &[f64],
    hi: &[f64],
    x0: &[f64],
    iterations: usize,
) -> Vec<f64> {
    let n = x0.len();
    let mut x = x0.to_vec();
    let mut rx = r(&x);
    let mut fx = rx.norm_squared();
    let mut mu = 1e-3;
    for _ in 0..iterations {
        let j = jacobian(&x, &rx);
        debug_assert_eq!(j.nrows(), rx.len(), "a Jacobian row per residual");
        let jt = j.transpose();
        let g = &jt * &rx;
        let h = &jt * &j;
        // Variables at a bound that the gradient pushes outwards stay there (active set);
        // the step is solved in the others, so clamping does not bend it.
        let span = |i: usize| 1e-12 * (hi[i] - lo[i]).max(1e-12);
        let free: Vec<usize> = (0..n)
            .filter(|&i| {
                !((x[i] <= lo[i] + span(i) && g[i] > 0.0)
                    || (x[i] >= hi[i] - span(i) && g[i] < 0.0))
            })
            .collect();
        let m = free.len();
        let hf = DMatrix::from_fn(m, m, |a, b| h[(free[a], free[b])]);
        let gf = DVector::from_fn(m, |a, _| g[free[a]]);
        let mut improved = false;
        for _ in 0..8 {
            let mut damped = hf.clone();
            for a in 0..m {
                damped[(a, a)] += mu * (hf[(a, a)] + 1e-12);
            }
            let Some(step) = damped.cholesky().map(|c| c.solve(&(-&gf))) else {
                mu *= 10.0;
                continue;
            };
            let mut delta = DVector::zeros(n);
            for (a, &i) in free.iter().enumerate() {
                delta[i] = step[a];
            }
            let y: Vec<f64> = (0..n)
                .map(|i| (x[i] + delta[i]).clamp(lo[i], hi[i]))
                .collect();
            let ry = r(&y);
            let fy = ry.norm_squared();
            // a tie is taken: near a large residual floor the objective's rounding hides
            // the last gains of the variables (its gain of zero then ends the polish)
            if fy <= fx {
                x = y;
                rx = ry;
                let gain = fx - fy;
                fx = fy;
                mu = (mu * 0.3).max(1e-12);
                improved = gain > 1e-15 * (1.0 + fx);
                break;
            }
            mu *= 10.0;
        }
        if !improved {
            break;
        }
    }
    x
}

/// The forward-difference Jacobian of `r` at x, whose residual is rx: variable i steps
/// by [`step`].
#[cfg(test)]
pub(crate) fn forward_differences(
    r: &dyn Fn(&[f64]) -> DVector<f64>,
    lo: &[f64],
    hi: &[f64],
    x: &[f64],
    rx: &DVector<f64>,
) -> DMatrix<f64> {
    let mut j = DMatrix::zeros(rx.len(), x.len());
    for i in 0..x.len() {
        let mut y = x.to_vec();
        let step = step(y[i], lo[i], hi[i]);
        y[i] += step;
        j.set_column(i, &((r(&y) - rx) / step));
    }
    j
}

/// The forward difference's step of a variable at `x` in [lo, hi]: 1e-7 of the box's
/// width, backwards where forwards leaves the box.
pub(crate) fn step(x: f64, lo: f64, hi: f64) -> f64 {
    let h = 1e-7 * (hi - lo).max(1e-12);
    if x + h <= hi { h } else { -h }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_a_bounded_nonlinear_least_squares_problem() {
        // r = (x0^2 - 4, x0 x1 - 2): solution (2, 1) inside the box.
        let r = |x: &[f64]| DVector::from_vec(vec![x[0] * x[0] - 4.0, x[0] * x[1] - 2.0]);
        let x = polish(&r, &[0.0, 0.0], &[5.0, 5.0], &[1.0, 3.0], 100);
        assert!(
            // measured exactly (2, 1)
            (x[0] - 2.0).abs() < 1e-15 && (x[1] - 1.0).abs() < 1e-15,
            "{x:?}"
        );
    }

    /// A minimum outside the box: the variable the bound holds stays at it, the other
    /// reaches its own optimum (the step is solved in the free variable alone).
    #[test]
    fn a_variable_at_a_bound_stays_there() {
        // (x0 - 3)^2 + (x1 - x0 + 1)^2 on [0, 2] x [0, 5]: x0 = 2 at its bound, x1 = 1
        let r = |x: &[f64]| DVector::from_vec(vec![x[0] - 3.0, x[1] - x[0] + 1.0]);
        let x = polish(&r, &[0.0, 0.0], &[2.0, 5.0], &[0.5, 4.0], 100);
        assert_eq!(x[0], 2.0);
        // measured 7.3e-13 (the forward differences' step, 1e-7 of the box)
        assert!((x[1] - 1.0).abs() < 1.5e-12, "{x:?}");
        // and from the bound itself, the gradient pushing outwards
        let x = polish(&r, &[0.0, 0.0], &[2.0, 5.0], &[2.0, 0.0], 100);
        assert_eq!(x[0], 2.0);
        assert!((x[1] - 1.0).abs() < 1.5e-12, "{x:?}");
        // no steps: the start as it is
        assert_eq!(
            polish(&r, &[0.0, 0.0], &[2.0, 5.0], &[0.5, 4.0], 0),
            [0.5, 4.0]
        );
    }

    /// One step on a linear residual is Marquardt's: (H + mu diag H) step = -g with
    /// mu = 1e-3. On r = 10 (x - 4) from 0 that is 4 / 1.001.
    #[test]
    fn one_step_is_marquardts_scaled_damping() {
        let r = |x: &[f64]| DVector::from_vec(vec![10.0 * (x[0] - 4.0)]);
        let x = polish(&r, &[0.0], &[10.0], &[0.0], 1);
        // the forward difference's rounding; measured 1.27e-9
        assert!((x[0] - 4.0 / 1.001).abs() < 2.5e-9, "{x:?}");
    }

    /// With one step, a variable counts as at its bound within 1e-12 of its box's width
    /// (here 4e-12), and only when the gradient pushes it outwards: held, the step is
    /// solved in the other variable alone; free, the step moves both and the clamp holds
    /// the first at its bound. Bounds: 2x the largest miss measured (1.64e-10, the
    /// forward differences' rounding).
    #[test]
    fn a_variable_is_held_within_a_width_fraction_of_its_bound() {
        // x1 after one step from (x0, start) on the box [1, 5] x [0, 10]
        let check = |r: &dyn Fn(&[f64]) -> DVector<f64>, start: f64, cases: [(f64, f64); 3]| {
            for (x0, want) in cases {
                let x1 = polish(r, &[1.0, 0.0], &[5.0, 10.0], &[x0, start], 1)[1];
                assert!((x1 - want).abs() < 3.5e-10, "x0 {x0}: {x1} against {want}");
            }
        };
        // upper bound: r = (x0 - 6, x1 - x0 + 1) from x1 = 5; held, x1 steps to
        // 5 - 1/1.001; free, to 5 - 0.002 / 1.004
        let r = |x: &[f64]| DVector::from_vec(vec![x[0] - 6.0, x[1] - x[0] + 1.0]);
        let (held, free) = (5.0 - 1.0 / 1.001, 5.0 - 0.002 / 1.004002);
        check(
            &r,
            5.0,
            [(5.0, held), (5.0 - 1e-12, held), (5.0 - 5e-12, free)],
        );
        // lower bound, the mirror image: r = (x0, x1 - x0 - 3) from x1 = 3
        let r = |x: &[f64]| DVector::from_vec(vec![x[0], x[1] - x[0] - 3.0]);
        let (held, free) = (3.0 + 1.0 / 1.001, 3.0 + 0.002 / 1.004002);
        check(
            &r,
            3.0,
            [(1.0, held), (1.0 + 1e-12, held), (1.0 + 5e-12, free)],
        );
        // at the lower bound with a gradient of exactly zero in x0 (r = (x0 - x1 + 1,
        // x1 - 3) from (0, 1)): free, both move, towards (2, 3)
        let r = |x: &[f64]| DVector::from_vec(vec![x[0] - x[1] + 1.0, x[1] - 3.0]);
        let x = polish(&r, &[0.0, 0.0], &[5.0, 10.0], &[0.0, 1.0], 1);
        let want = [2.0 / 1.004002, 1.0 + 2.002 / 1.004002];
        assert!(
            (x[0] - want[0]).abs() < 3.5e-10 && (x[1] - want[1]).abs() < 3.5e-10,
            "{x:?} against {want:?}"
        );
    }

    /// A variable the residual does not see (a zero column, no curvature) still gets a
    /// positive damping (mu 1e-12), so the step is solved: the seen variable takes its
    /// Marquardt step, the unseen one stays.
    #[test]
    fn a_variable_without_curvature_does_not_stop_the_step() {
        let r = |x: &[f64]| DVector::from_vec(vec![10.0 * (x[0] - 4.0)]);
        let x = polish(&r, &[0.0, 0.0], &[10.0, 10.0], &[0.0, 1.0], 1);
        // as in the one-variable step (measured 1.27e-9 there)
        assert!((x[0] - 4.0 / 1.001).abs() < 2.5e-9 && x[1] == 1.0, "{x:?}");
    }

    /// r and the number of times it was evaluated.
    fn counted(
        r: impl Fn(f64) -> Vec<f64>,
    ) -> (
        impl Fn(&[f64]) -> DVector<f64>,
        std::rc::Rc<std::cell::Cell<usize>>,
    ) {
        let n = std::rc::Rc::new(std::cell::Cell::new(0));
        let count = n.clone();
        let f = move |x: &[f64]| {
            count.set(count.get() + 1);
            DVector::from_vec(r(x[0]))
        };
        (f, n)
    }

    /// Near a large residual floor (f = 1e6 + (x - 4)^2) the objective cannot tell the
    /// last steps apart: a step that ties is taken, then the polish stops. Measured: a
    /// miss of 8.09e-11 after 7 evaluations; refusing ties stops at 9.0e-7 after 14, and a
    /// stop that ignored the gain of zero runs to the budget (201 evaluations).
    #[test]
    fn a_step_the_rounding_hides_is_taken_and_ends_the_polish() {
        let (r, evaluations) = counted(|x| vec![x - 4.0, 1e3]);
        let x = polish(&r, &[0.0], &[10.0], &[1.0], 100);
        assert!((x[0] - 4.0).abs() < 1.6e-10, "{x:?}");
        assert!(evaluations.get() <= 7, "{} evaluations", evaluations.get());
    }

    /// The polish stops at the first step that gains less than 1e-15 (1 + f): on r = (x^2,
    /// c) Gauss-Newton halves x, so f = x^4 + c^2 falls ever more slowly. Measured (the
    /// counts are exact): c = 0 stops after 29 evaluations at x = 6.13e-5, c = 1e3 after
    /// 19 at 1.96e-3. A threshold without the 1 (relative only) or without the f
    /// (absolute only), or a gain that is not the fall, runs 21 to 2001 evaluations.
    #[test]
    fn the_polish_stops_once_a_step_gains_less_than_1e_15_of_one_plus_f() {
        for (c, budget, at) in [(0.0, 29, 6.13e-5), (1e3, 19, 1.96e-3)] {
            let (r, evaluations) = counted(move |x| vec![x * x, c]);
            let x = polish(&r, &[-2.0], &[2.0], &[1.0], 1000);
            assert!(
                evaluations.get() <= budget && x[0] > at / 2.0 && x[0] < at * 2.0,
                "c = {c}: {} evaluations, x = {}",
                evaluations.get(),
                x[0]
            );
        }
    }
}
