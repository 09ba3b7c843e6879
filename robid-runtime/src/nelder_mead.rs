//! Nelder-Mead simplex minimisation with the dimension-adaptive coefficients of Gao and Han,
//! which keep the method effective in tens of dimensions. Used by the trajectory designs
//! (`excite`) and the feasible-parameter search (`feasible`).
//!
//! ## Reference
//! J. A. Nelder, R. Mead, "A simplex method for function minimization", Computer Journal 7,
//! 1965; F. Gao, L. Han, "Implementing the Nelder-Mead simplex algorithm with adaptive
//! parameters", Computational Optimization and Applications 51, 2012.
//!
//! ```
//! # use robid_runtime::nelder_mead::NelderMead;
//! let nm = NelderMead { step: vec![0.5, 0.7], ..NelderMead::default() };
//! let m = nm.minimize(&[0.0, 0.0], |x| (x[0] - 1.0).powi(2) + (x[1] + 3.0).powi(2)).unwrap();
//! assert!((m.x[0] - 1.0).abs() < 1e-3 && (m.x[1] + 3.0).abs() < 1e-3);
//! ```

use crate::error::{Error, Result};

/// Settings of a minimisation. It stops after `max_evaluations` evaluations (the cap of
/// every loop: at most `max_evaluations + n` evaluations are made) or when the simplex's
/// function values differ by at most `tolerance * |best| + absolute_tolerance`.
#[derive(Debug, Clone, PartialEq)]
pub struct NelderMead {
    /// Largest number of function evaluations.
    pub max_evaluations: usize,
    /// Relative part of the stopping tolerance.
    pub tolerance: f64,
    /// Absolute part of the stopping tolerance.
    pub absolute_tolerance: f64,
    /// Edge lengths of the initial simplex along each coordinate: one value for every
    /// coordinate, or one per coordinate.
    pub step: Vec<f64>,
}

impl Default for NelderMead {
    fn default() -> Self {
        Self {
            max_evaluations: 2000,
            tolerance: 1e-9,
            absolute_tolerance: 1e-9,
            step: vec![0.3],
        }
    }
}

/// The best point found and its value.
#[derive(Debug, Clone, PartialEq)]
pub struct Minimum {
    /// The point.
    pub x: Vec<f64>,
    /// f(x).
    pub value: f64,
    /// Evaluations used.
    pub evaluations: usize,
}

impl NelderMead {
    /// Minimises `f` from `x0`. Non-finite values count as +infinity.
    ///
    /// `step` must hold one value or one per coordinate of `x0`, all finite, `x0` must
    /// be finite and both tolerances finite and not negative; otherwise an
    /// [`Error::Setting`] names the setting.
    pub fn minimize(&self, x0: &[f64], mut f: impl FnMut(&[f64]) -> f64) -> Result<Minimum> {
        let n = x0.len();
        // NaN or a negative tolerance never stops the search: it ran to max_evaluations
        for (key, t) in [
            ("tolerance", self.tolerance),
            ("absolute_tolerance", self.absolute_tolerance),
        ] {
            if !(t >= 0.0 && t.is_finite()) {
                return Err(Error::setting(
                    "NelderMead",
                    key,
                    format!("{} must be finite and 0 or more", crate::error::num(t)),
                ));
            }
        }
        if !(self.step.len() == 1 || self.step.len() == n) {
            return Err(Error::setting(
                "NelderMead",
                "step",
                format!(
                    "{} steps for {n} coordinates; give one or one per coordinate",
                    self.step.len()
                ),
            ));
        }
        if self.step.iter().chain(x0).any(|v| !v.is_finite()) {
            return Err(Error::setting(
                "NelderMead",
                "step",
                "the steps and the start must be finite",
            ));
        }
        let mut eval = |x: &[f64]| {
            let v = f(x);
            if v.is_finite() { v } else { f64::INFINITY }
        };
        if n == 0 {
            let value = eval(x0);
            return Ok(Minimum {
                x: Vec::new(),
                value,
                evaluations: 1,
            });
        }
        let nf = n as f64;
        let (alpha, beta, gamma, delta) = (1.0, 1.0 + 2.0 / nf, 0.75 - 0.5 / nf, 1.0 - 1.0 / nf);
        let mut simplex: Vec<(Vec<f64>, f64)> = Vec::with_capacity(n + 1);
        simplex.push((x0.to_vec(), eval(x0)));
        for i in 0..n {
            let mut x = x0.to_vec();
            x[i] += self.step[i.min(self.step.len() - 1)];
            let v = eval(&x);
            simplex.push((x, v));
        }
        let mut used = n + 1;
        let along = |c: &[f64], w: &[f64], t: f64| -> Vec<f64> {
            c.iter().zip(w).map(|(c, w)| c + t * (c - w)).collect()
        };
        while used < self.max_evaluations {
            simplex.sort_by(|a, b| a.1.total_cmp(&b.1));
            let (best, worst) = (simplex[0].1, simplex[n].1);
            // false while worst is infinite (inf - finite, or inf - inf = NaN)
            if worst - best <= self.tolerance * best.abs() + self.absolute_tolerance {
                break;
            }
            let mut c = vec![0.0; n];
            for (x, _) in &simplex[..n] {
                for (ci, xi) in c.iter_mut().zip(x) {
                    *ci += xi / nf;
                }
            }
            let w = simplex[n].0.clone();
            let xr = along(&c, &w, alpha);
            let fr = eval(&xr);
            used += 1;
            if fr < best {
                let xe = along(&c, &w, alpha * beta);
                let fe = eval(&xe);
                used += 1;
                simplex[n] = if fe < fr { (xe, fe) } else { (xr, fr) };
            } else if fr < simplex[n - 1].1 {
                simplex[n] = (xr, fr);
            } else {
                // outside contraction if the reflection improved on the worst, else inside
                let t = if fr < worst { alpha * gamma } else { -gamma };
                let xc = along(&c, &w, t);
                let fc = eval(&xc);
                used += 1;
                if fc < fr.min(worst) {
                    simplex[n] = (xc, fc);
                } else {
                    // shrink towards the best vertex
                    let x0 = simplex[0].0.clone();
                    for (x, v) in simplex.iter_mut().skip(1) {
                        for (xi, bi) in x.iter_mut().zip(&x0) {
                            *xi = bi + delta * (*xi - bi);
                        }
                        *v = eval(x);
                    }
                    used += n;
                }
            }
        }
        simplex.sort_by(|a, b| a.1.total_cmp(&b.1));
        let (x, value) = simplex.swap_remove(0);
        Ok(Minimum {
            x,
            value,
            evaluations: used,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rosenbrock(x: &[f64]) -> f64 {
        (1.0 - x[0]).powi(2) + 100.0 * (x[1] - x[0] * x[0]).powi(2)
    }

    #[test]
    fn finds_the_minimum_of_rosenbrock_and_a_quadratic() {
        let nm = NelderMead {
            max_evaluations: 5000,
            tolerance: 1e-14,
            absolute_tolerance: 1e-14,
            step: vec![0.5],
        };
        let r = nm.minimize(&[-1.2, 1.0], rosenbrock).unwrap();
        // measured 2.0e-10 and 7.5e-9
        assert!(
            (r.x[0] - 1.0).abs() < 4e-10 && (r.x[1] - 1.0).abs() < 1.5e-8,
            "{r:?}"
        );
        let q = nm
            .minimize(&[1.0; 10], |x| {
                x.iter()
                    .enumerate()
                    .map(|(i, v)| (i + 1) as f64 * (v - 0.5).powi(2))
                    .sum()
            })
            .unwrap();
        // measured 9.4e-15 after 1236 evaluations (the cap is 5000 plus one simplex)
        assert!(q.value < 2e-14, "{q:?}");
        assert!(q.evaluations <= 5000 + 11);
        // infinite values are avoided
        let c = nm
            .minimize(&[0.5], |x| {
                if x[0] < 0.0 {
                    f64::NAN
                } else {
                    (x[0] - 0.1).powi(2)
                }
            })
            .unwrap();
        // measured 2.4e-8
        assert!((c.x[0] - 0.1).abs() < 5e-8);
    }

    #[test]
    fn per_coordinate_steps_and_a_relative_tolerance() {
        let nm = NelderMead {
            max_evaluations: 5000,
            tolerance: 1e-14,
            absolute_tolerance: 1e-28,
            step: vec![0.1, 0.1],
        };
        let r = nm.minimize(&[-1.2, 1.0], rosenbrock).unwrap();
        // measured 2.0e-29 and 3.9e-15
        assert!(r.value < 4e-29 && (r.x[0] - 1.0).abs() < 8e-15, "{r:?}");
        let nm = NelderMead {
            max_evaluations: 20_000,
            tolerance: 1e-16,
            absolute_tolerance: 1e-32,
            step: vec![0.5; 10],
        };
        let q = nm
            .minimize(&[0.0; 10], |x| {
                x.iter()
                    .enumerate()
                    .map(|(i, v)| (i as f64 + 1.0) * (v - 1.0).powi(2))
                    .sum::<f64>()
            })
            .unwrap();
        // measured 1.7e-30
        assert!(q.value < 3.3e-30, "{q:?}");
        // the steps scale the simplex: a coordinate with a tiny scale converges too
        let nm = NelderMead {
            step: vec![1.0, 1e-6],
            tolerance: 1e-14,
            absolute_tolerance: 1e-14,
            ..NelderMead::default()
        };
        let s = nm
            .minimize(&[0.3, 0.0], |x| {
                let (u, v) = (x[0] - 2.0, 1e6 * x[1] - 1.0);
                u * u + v * v + 0.5 * u * v
            })
            .unwrap();
        // measured 8.6e-9 and 3.5e-14 (3.5e-8 of the coordinate's scale)
        assert!(
            (s.x[0] - 2.0).abs() < 1.7e-8 && (s.x[1] - 1e-6).abs() < 7e-14,
            "{s:?}"
        );
    }

    #[test]
    fn a_step_per_coordinate_or_one_for_all() {
        let nm = NelderMead {
            step: vec![0.1; 3],
            ..NelderMead::default()
        };
        let e = nm.minimize(&[0.0, 0.0], rosenbrock).unwrap_err();
        assert!(e.to_string().contains("3 steps for 2 coordinates"), "{e}");
        let nm = NelderMead::default();
        assert!(nm.minimize(&[f64::NAN, 0.0], rosenbrock).is_err());
    }

    /// A NaN or negative tolerance never stopped the search, which ran to
    /// `max_evaluations` (review 147): refused, naming the setting.
    #[test]
    fn refuses_a_tolerance_that_is_nan_negative_or_infinite() {
        for t in [f64::NAN, -1e-9, f64::INFINITY] {
            for (relative, key) in [(true, "tolerance"), (false, "absolute_tolerance")] {
                let nm = NelderMead {
                    max_evaluations: 1000,
                    tolerance: if relative { t } else { 1e-9 },
                    absolute_tolerance: if relative { 1e-9 } else { t },
                    ..NelderMead::default()
                };
                let e = nm
                    .minimize(&[0.0, 0.0], rosenbrock)
                    .unwrap_err()
                    .to_string();
                assert!(e.contains(key) && e.contains("finite and 0 or more"), "{e}");
            }
        }
    }

    /// The evaluation cap holds whatever the function does (here: never converges).
    #[test]
    fn stops_at_the_evaluation_cap() {
        let nm = NelderMead {
            max_evaluations: 300,
            tolerance: 0.0,
            absolute_tolerance: 0.0,
            ..NelderMead::default()
        };
        let mut calls = 0;
        let m = nm
            .minimize(&[0.0; 5], |x| {
                calls += 1;
                -x.iter().sum::<f64>()
            })
            .unwrap();
        assert!(calls <= 300 + 5 + 1 && m.evaluations <= 300 + 5, "{calls}");
    }
}
