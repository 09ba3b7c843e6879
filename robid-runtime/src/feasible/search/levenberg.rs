//! A bounded Levenberg-Marquardt polish (Marquardt 1963) of a least-squares residual:
//! forward-difference Jacobian, damped Gauss-Newton steps in the variables that no bound
//! holds (a variable at a bound the gradient pushes against stays there), clipped to the
//! box. Used after Nelder-Mead, whose progress in tens of dimensions is slow near the optimum.

use nalgebra::{DMatrix, DVector};

/// Minimises ||r(x)||^2 over [lo, hi] from `x0` for at most `iterations` steps.
pub(crate) fn polish(
    r: &dyn Fn(&[f64]) -> DVector<f64>,
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
        let mut j = DMatrix::zeros(rx.len(), n);
        for i in 0..n {
            let h = 1e-7 * (hi[i] - lo[i]).max(1e-12);
            let mut y = x.clone();
            let step = if y[i] + h <= hi[i] { h } else { -h };
            y[i] += step;
            j.set_column(i, &((r(&y) - &rx) / step));
        }
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
            if fy < fx {
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
}
