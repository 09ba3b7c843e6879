//! Nelder-Mead simplex search (Nelder, Mead 1965) with the dimension-adaptive
//! coefficients of Gao and Han (2012), which keep it working in tens of dimensions.

/// Minimises `f` from `x0` with initial steps `step`; stops after `max_evals`
/// evaluations or when the simplex values agree to `tol`. Returns the best point and value.
pub(crate) fn nelder_mead(
    f: &dyn Fn(&[f64]) -> f64,
    x0: &[f64],
    step: &[f64],
    max_evals: usize,
    tol: f64,
) -> (Vec<f64>, f64) {
    let n = x0.len();
    if n == 0 {
        return (x0.to_vec(), f(x0));
    }
    let nf = n as f64;
    let (alpha, beta, gamma, delta) = (1.0, 1.0 + 2.0 / nf, 0.75 - 0.5 / nf, 1.0 - 1.0 / nf);
    let mut simplex: Vec<(Vec<f64>, f64)> = Vec::with_capacity(n + 1);
    simplex.push((x0.to_vec(), f(x0)));
    for i in 0..n {
        let mut x = x0.to_vec();
        x[i] += step[i];
        let fx = f(&x);
        simplex.push((x, fx));
    }
    let mut evals = n + 1;
    let along = |c: &[f64], w: &[f64], t: f64| -> Vec<f64> {
        c.iter().zip(w).map(|(c, w)| c + t * (c - w)).collect()
    };
    while evals < max_evals {
        simplex.sort_by(|a, b| a.1.total_cmp(&b.1));
        let (fbest, fworst) = (simplex[0].1, simplex[n].1);
        if (fworst - fbest).abs() <= tol * (fbest.abs() + tol) {
            break;
        }
        let mut centroid = vec![0.0; n];
        for (x, _) in &simplex[..n] {
            for (c, v) in centroid.iter_mut().zip(x) {
                *c += v / nf;
            }
        }
        let worst = simplex[n].0.clone();
        let xr = along(&centroid, &worst, alpha);
        let fr = f(&xr);
        evals += 1;
        if fr < fbest {
            let xe = along(&centroid, &worst, alpha * beta);
            let fe = f(&xe);
            evals += 1;
            simplex[n] = if fe < fr { (xe, fe) } else { (xr, fr) };
        } else if fr < simplex[n - 1].1 {
            simplex[n] = (xr, fr);
        } else {
            let (xc, fc) = if fr < fworst {
                let x = along(&centroid, &worst, alpha * gamma);
                let fx = f(&x);
                (x, fx)
            } else {
                let x = along(&centroid, &worst, -gamma);
                let fx = f(&x);
                (x, fx)
            };
            evals += 1;
            if fc < fworst.min(fr) {
                simplex[n] = (xc, fc);
            } else {
                let best = simplex[0].0.clone();
                for (x, fx) in simplex.iter_mut().skip(1) {
                    for (v, b) in x.iter_mut().zip(&best) {
                        *v = b + delta * (*v - b);
                    }
                    *fx = f(x);
                }
                evals += n;
            }
        }
    }
    simplex.sort_by(|a, b| a.1.total_cmp(&b.1));
    simplex.swap_remove(0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn minimises_rosenbrock() {
        let f = |x: &[f64]| (1.0 - x[0]).powi(2) + 100.0 * (x[1] - x[0] * x[0]).powi(2);
        let (x, fx) = nelder_mead(&f, &[-1.2, 1.0], &[0.1, 0.1], 5000, 1e-14);
        assert!(fx < 1e-8 && (x[0] - 1.0).abs() < 1e-3, "{x:?} {fx}");
    }

    #[test]
    fn minimises_a_ten_dimensional_quadratic() {
        let f = |x: &[f64]| {
            x.iter()
                .enumerate()
                .map(|(i, v)| (i as f64 + 1.0) * (v - 1.0).powi(2))
                .sum::<f64>()
        };
        let (_, fx) = nelder_mead(&f, &[0.0; 10], &[0.5; 10], 20000, 1e-16);
        assert!(fx < 1e-8, "{fx}");
    }
}
