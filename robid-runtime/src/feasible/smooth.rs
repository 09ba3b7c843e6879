//! The default method: the covariance-weighted fit of the standard parameters to the
//! identified base parameters, over the log-Cholesky parameters of every link (so every
//! point is physically consistent, see `log_cholesky`), solved by Levenberg-Marquardt
//! (the `levenberg-marquardt` crate):
//!
//! ```text
//! minimise  || L^-1 (K p(x) - beta) ||^2  +  sum_s w_s ((p_s(x) - p0_s) / scale_s)^2
//!           +  mu * sum (violated linear bounds / their scale)^2
//! ```
//!
//! with p0 the prior (the user's, else the default of `prior`). The objective is convex
//! in the standard parameters p, the consistent set is convex, and the parametrisation
//! maps its interior smoothly and one-to-one, so the local optimum the solver finds is the
//! global one whenever it lies inside (the prior keeps it there unless the data push a
//! link to the boundary, which is then approached). Bounds on masses, centres of mass,
//! the total mass and the diagonal of each inertia about its centre of mass enter as a
//! stiff exterior penalty (weight `mu`, [`SmoothOptions::penalty`]). Non-negative drive
//! terms (Ia, Fv, Fc) are exponentials of their variables; Fo and extra columns are free.

use std::time::Instant;

use levenberg_marquardt::{LeastSquaresProblem, LevenbergMarquardt};
use nalgebra::storage::Owned;
use nalgebra::{DMatrix, DVector, Dyn};

use super::bounds::Bounds;
use super::log_cholesky::{PER_LINK, inside, jacobian, standard_of, theta_of};
use super::prior::{Prior, Pull};
use super::problem::Problem;
use super::solution::{Method, Solution};
use crate::{Error, FeasibleError, Result};

/// Settings of the log-Cholesky fit.
#[derive(Debug, Clone, PartialEq)]
pub struct SmoothOptions {
    /// The user's prior (e.g. CAD values); the default prior settles the rest.
    pub prior: Option<Prior>,
    /// Weight of the default prior (see [`Prior::weight`]): it settles what the data leave
    /// free and holds what they barely determine.
    pub default_weight: f64,
    /// Weight of a bound's violation (relative to its parameter's scale), in chi^2 units.
    pub penalty: f64,
    /// Patience of the solver: at most `patience * (variables + 1)` evaluations.
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

/// One inequality g(p) >= 0 of the bounds, linear or (the inertia diagonal) not.
#[derive(Debug, Clone, Copy)]
enum Bound {
    /// sum of `coefficient * p[index]` minus `rhs`, over the listed entries.
    Linear {
        entries: [(usize, f64); 2],
        rhs: f64,
        scale: f64,
    },
    /// `sign * (I_c[axis][axis] - limit)` for the link with standard indices `link`.
    InertiaDiagonal {
        link: [usize; PER_LINK],
        axis: usize,
        limit: f64,
        sign: f64,
        scale: f64,
    },
    /// The total mass: `sign * (sum of masses - limit)`.
    TotalMass { limit: f64, sign: f64, scale: f64 },
}

/// The least-squares problem in the variables x.
#[derive(Clone)]
struct Fit<'a> {
    problem: &'a Problem,
    /// Whitened K and target.
    a: DMatrix<f64>,
    b: DVector<f64>,
    pull: Pull,
    bounds: Vec<Bound>,
    penalty: f64,
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
        let layout = &self.problem.layout;
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

    /// d standard / d x, sparse: per standard parameter, the first variable it depends on
    /// and its derivatives by that variable and the next ones (a link's ten, or one).
    fn standard_jacobian(&self, x: &DVector<f64>) -> Vec<(usize, Vec<f64>)> {
        let layout = &self.problem.layout;
        let mut d = vec![(0, Vec::new()); layout.len()];
        let mut v = 0;
        for map in &self.maps {
            match *map {
                Map::Link(j) => {
                    let jac = jacobian(&self.theta(x, j));
                    for (k, &i) in layout.links[j].iter().enumerate() {
                        d[i] = (v, jac[k].to_vec());
                    }
                    v += PER_LINK;
                }
                Map::Positive(i) => {
                    d[i] = (v, vec![x[v].clamp(-700.0, 700.0).exp()]);
                    v += 1;
                }
                Map::Free(i) => {
                    d[i] = (v, vec![1.0]);
                    v += 1;
                }
            }
        }
        d
    }

    /// The value g(p) of a bound and its gradient in p (sparse: (index, derivative)).
    fn bound(&self, bound: &Bound, p: &[f64], grad: &mut Vec<(usize, f64)>) -> (f64, f64) {
        grad.clear();
        match *bound {
            Bound::Linear {
                entries,
                rhs,
                scale,
            } => {
                grad.extend(entries.iter().filter(|e| e.1 != 0.0));
                let g = entries.iter().map(|&(i, c)| c * p[i]).sum::<f64>() - rhs;
                (g, scale)
            }
            Bound::InertiaDiagonal {
                link,
                axis,
                limit,
                sign,
                scale,
            } => {
                // I_c[a][a] = J[a][a] - (|h|^2 - h_a^2) / m
                let diagonal = [0, 3, 5][axis];
                let m = p[link[9]].max(1e-300);
                let h = [p[link[6]], p[link[7]], p[link[8]]];
                let off: f64 = (0..3).filter(|&k| k != axis).map(|k| h[k] * h[k]).sum();
                let value = p[link[diagonal]] - off / m;
                grad.push((link[diagonal], sign));
                for k in (0..3).filter(|&k| k != axis) {
                    grad.push((link[6 + k], -sign * 2.0 * h[k] / m));
                }
                grad.push((link[9], sign * off / (m * m)));
                (sign * (value - limit), scale)
            }
            Bound::TotalMass { limit, sign, scale } => {
                let layout = &self.problem.layout;
                let total: f64 = layout.links.iter().map(|idx| p[idx[9]]).sum();
                grad.extend(layout.links.iter().map(|idx| (idx[9], sign)));
                (sign * (total - limit), scale)
            }
        }
    }

    fn rows(&self) -> usize {
        self.a.nrows() + self.pull.target.len() + self.bounds.len()
    }

    fn residuals_at(&self, x: &DVector<f64>) -> DVector<f64> {
        let p = self.standard(x);
        let mut r = DVector::zeros(self.rows());
        let data = &self.a * DVector::from_column_slice(&p) - &self.b;
        let nb = data.len();
        r.rows_mut(0, nb).copy_from(&data);
        for (s, v) in p.iter().enumerate() {
            let pull = &self.pull;
            r[nb + s] = pull.weight[s].sqrt() * (v - pull.target[s]) / pull.scale[s];
        }
        let start = nb + p.len();
        let mut grad = Vec::new();
        let mu = self.penalty.sqrt();
        for (k, bound) in self.bounds.iter().enumerate() {
            let (g, scale) = self.bound(bound, &p, &mut grad);
            r[start + k] = mu * g.min(0.0) / scale;
        }
        r
    }

    fn jacobian_at(&self, x: &DVector<f64>) -> DMatrix<f64> {
        let p = self.standard(x);
        let ns = p.len();
        let nb = self.a.nrows();
        let dp = self.standard_jacobian(x);
        let mut jac = DMatrix::zeros(self.rows(), x.len());
        // row += factor * d p_s / d x
        let add = |jac: &mut DMatrix<f64>, row: usize, s: usize, factor: f64| {
            let (start, values) = &dp[s];
            for (k, v) in values.iter().enumerate() {
                jac[(row, start + k)] += factor * v;
            }
        };
        for (s, (_, derivatives)) in dp.iter().enumerate() {
            let column = self.a.column(s);
            if derivatives.iter().any(|v| *v != 0.0) {
                for (r, a) in column.iter().enumerate() {
                    if *a != 0.0 {
                        add(&mut jac, r, s, *a);
                    }
                }
            }
            add(
                &mut jac,
                nb + s,
                s,
                self.pull.weight[s].sqrt() / self.pull.scale[s],
            );
        }
        let mut grad = Vec::new();
        let mu = self.penalty.sqrt();
        for (k, bound) in self.bounds.iter().enumerate() {
            let (g, scale) = self.bound(bound, &p, &mut grad);
            if g < 0.0 {
                for &(i, d) in &grad {
                    add(&mut jac, nb + ns + k, i, mu * d / scale);
                }
            }
        }
        jac
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
        let r = self.residuals_at(&self.x);
        r.iter().all(|v| v.is_finite()).then_some(r)
    }

    fn jacobian(&self) -> Option<DMatrix<f64>> {
        let j = self.jacobian_at(&self.x);
        j.iter().all(|v| v.is_finite()).then_some(j)
    }
}

/// The inequalities of the bounds, each with the scale of its parameter.
fn inequalities(problem: &Problem, bounds: &Bounds, scale: &[f64]) -> Vec<Bound> {
    let mut out = Vec::new();
    let mut masses = 0.0;
    for (j, idx) in problem.layout.links.iter().enumerate() {
        let b = &bounds.links[j];
        let m = idx[9];
        let linear = |entries: [(usize, f64); 2], rhs: f64, scale: f64| Bound::Linear {
            entries,
            rhs,
            scale,
        };
        masses += scale[m];
        out.push(linear([(m, 1.0), (m, 0.0)], b.mass[0], scale[m]));
        out.push(linear([(m, -1.0), (m, 0.0)], -b.mass[1], scale[m]));
        for axis in 0..3 {
            let h = idx[6 + axis];
            let [lo, hi] = b.com[axis];
            out.push(linear([(h, 1.0), (m, -lo)], 0.0, scale[h]));
            out.push(linear([(h, -1.0), (m, hi)], 0.0, scale[h]));
            for (limit, sign) in [(b.inertia[0], 1.0), (b.inertia[1], -1.0)] {
                out.push(Bound::InertiaDiagonal {
                    link: *idx,
                    axis,
                    limit,
                    sign,
                    scale: scale[idx[0]],
                });
            }
        }
    }
    if let Some([lo, hi]) = bounds.total_mass {
        for (limit, sign) in [(lo, 1.0), (hi, -1.0)] {
            out.push(Bound::TotalMass {
                limit,
                sign,
                scale: masses,
            });
        }
    }
    out
}

/// Physically consistent standard parameters that reproduce the identified base
/// parameters of `problem` within the bounds, settled by the prior where the data leave
/// them free (see the module documentation).
pub fn solve_smooth(
    problem: &Problem,
    bounds: &Bounds,
    options: &SmoothOptions,
) -> Result<Solution> {
    let start = Instant::now();
    options.check()?;
    let layout = &problem.layout;
    bounds.check_for(layout.links.len())?;
    let pull = Pull::new(
        problem,
        bounds,
        options.prior.as_ref(),
        options.default_weight,
    )?;
    let a = &problem.whitening * &problem.k;
    let b = &problem.whitening * &problem.target;
    let mut maps: Vec<Map> = (0..layout.links.len()).map(Map::Link).collect();
    maps.extend(layout.drives.iter().map(|d| {
        if d.kind.non_negative() {
            Map::Positive(d.index)
        } else {
            Map::Free(d.index)
        }
    }));
    maps.extend(layout.extra.iter().map(|&i| Map::Free(i)));

    // start: the prior, each link just inside the consistent set, and the drive terms
    // that fit best with those links (non-negative ones at least a small positive value)
    let mut p0 = pull.target.clone();
    let mut x0 = Vec::new();
    for idx in &layout.links {
        let values: [f64; PER_LINK] = idx.map(|i| p0[i]);
        let scale = pull.scale[idx[9]].max(1e-12);
        let link = inside(&values, bounds.margin + 1e-6 * scale);
        let theta = theta_of(&link, bounds.margin).ok_or_else(|| {
            Error::Feasible(FeasibleError::NoFeasibleParameters {
                reason: "the prior of a link cannot be made physically consistent; check the prior's masses and inertias".into(),
            })
        })?;
        for (&i, v) in idx.iter().zip(link) {
            p0[i] = v;
        }
        x0.extend(theta);
    }
    let linear: Vec<usize> = maps
        .iter()
        .filter_map(|m| match *m {
            Map::Positive(i) | Map::Free(i) => Some(i),
            Map::Link(_) => None,
        })
        .collect();
    if !linear.is_empty() {
        let cols: Vec<DVector<f64>> = linear.iter().map(|&i| a.column(i).into_owned()).collect();
        let ad = DMatrix::from_columns(&cols);
        for &i in &linear {
            p0[i] = 0.0;
        }
        let rest = &b - &a * DVector::from_column_slice(&p0);
        let d = ad
            .try_svd(true, true, f64::EPSILON, crate::limits::SVD_ITERATIONS)
            .and_then(|s| s.solve(&rest, 1e-10).ok())
            .unwrap_or_else(|| DVector::zeros(linear.len()));
        for (k, m) in maps
            .iter()
            .filter(|m| !matches!(m, Map::Link(_)))
            .enumerate()
        {
            match *m {
                Map::Positive(i) => x0.push(d[k].max(1e-6 * pull.scale[i]).ln()),
                Map::Free(_) => x0.push(d[k]),
                Map::Link(_) => {}
            }
        }
    }
    let fit = Fit {
        problem,
        a,
        b,
        bounds: inequalities(problem, bounds, &pull.scale),
        pull,
        penalty: options.penalty,
        margin: bounds.margin,
        maps,
        x: DVector::from_vec(x0),
    };
    let (fit, report) = LevenbergMarquardt::new()
        .with_patience(options.patience)
        .minimize(fit);
    if !report.objective_function.is_finite() {
        return Err(Error::Feasible(FeasibleError::NoFeasibleParameters {
            reason: format!(
                "the log-Cholesky fit stopped without a finite objective ({:?}); check the identified values and the bounds",
                report.termination
            ),
        }));
    }
    let p = fit.standard(&fit.x);
    let mut solution =
        Solution::assemble(problem, bounds, Method::LogCholesky, p, start.elapsed())?;
    solution.determined = super::prior::determined(problem, &fit.pull);
    Ok(solution)
}
