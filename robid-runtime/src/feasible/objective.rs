//! The objective the pure-Rust methods minimise, as residual rows in the standard
//! parameters p (docs/experiments.md#feasible-parameters):
//!
//! ```text
//! || L^-1 (K p - beta) ||^2  +  sum_s w_s ((p_s - p0_s) / scale_s)^2
//!                            +  mu * sum (violated bound / its scale)^2
//! ```
//!
//! with p0 the prior (the user's, else the default of `prior`). The first two terms are
//! convex quadratics; the bounds on masses, centres of mass, the total mass and the
//! diagonal of each inertia about its centre of mass enter as a stiff exterior penalty
//! (weight `mu`) with the shifts of an augmented Lagrangian, which the methods update
//! until the bounds hold to 1e-7 of their scale. `smooth` (a trust-region Newton method over
//! Cholesky factors) and `interior` (a log-det barrier in p) minimise the same rows, so
//! their optima compare.

use nalgebra::{DMatrix, DVector};

use super::bounds::{Bounds, TENSOR_ELEMENTS};
use super::cholesky::{PER_LINK, inside};
use super::prior::Pull;
use super::problem::Problem;
use super::smooth::SmoothOptions;
use crate::{Error, FeasibleError, Result};

/// One inequality g(p) >= 0 of the bounds, linear or (the inertia diagonal) not.
#[derive(Debug, Clone, Copy)]
enum Bound {
    /// sum of `coefficient * p[index]` minus `rhs`, over the listed entries.
    Linear {
        entries: [(usize, f64); 2],
        rhs: f64,
        scale: f64,
        /// Whether its range is open (low < high): points strictly inside exist.
        open: bool,
    },
    /// `sign * (I_c[row][column] - limit)` for the link with standard indices `link`
    /// (`I_c` the inertia about the centre of mass).
    InertiaElement {
        link: [usize; PER_LINK],
        row: usize,
        column: usize,
        limit: f64,
        sign: f64,
        scale: f64,
    },
    /// The total mass: `sign * (sum of masses - limit)`.
    TotalMass {
        limit: f64,
        sign: f64,
        scale: f64,
        open: bool,
    },
}

/// A linear bound `sum of coefficient * p[index] - rhs >= 0` with its scale, for a barrier.
#[derive(Debug, Clone)]
pub(super) struct Linear {
    pub(super) entries: Vec<(usize, f64)>,
    pub(super) rhs: f64,
    pub(super) scale: f64,
}

impl Linear {
    /// The bound's value at p (positive strictly inside).
    pub(super) fn value(&self, p: &[f64]) -> f64 {
        self.entries.iter().map(|&(i, c)| c * p[i]).sum::<f64>() - self.rhs
    }
}

/// The stiffest penalty [`Objective::stiffen`] reaches.
const MAX_PENALTY: f64 = 1e14;

/// The index among a link's ten standard values of the inertia tensor's entry (row,
/// column): `XX XY XZ YY YZ ZZ`.
const STANDARD_ENTRY: [[usize; 3]; 3] = [[0, 1, 2], [1, 3, 4], [2, 4, 5]];

/// The residual rows of the objective.
#[derive(Clone)]
pub(super) struct Objective<'a> {
    pub(super) problem: &'a Problem,
    /// Whitened K and target.
    a: DMatrix<f64>,
    b: DVector<f64>,
    pub(super) pull: Pull,
    bounds: Vec<Bound>,
    penalty: f64,
    /// Per bound, the shift of the augmented Lagrangian (its multiplier over twice the
    /// penalty, in units of the bound's scale): the penalty acts on g / scale - shift, so
    /// that updating the shifts drives violations to zero at a finite penalty.
    shifts: Vec<f64>,
}

impl<'a> Objective<'a> {
    /// The objective of `problem` under `bounds`, pulled by `pull`, with bound penalty
    /// `penalty`.
    pub(super) fn new(problem: &'a Problem, bounds: &Bounds, pull: Pull, penalty: f64) -> Self {
        let bounds = inequalities(problem, bounds, &pull.scale);
        Objective {
            problem,
            a: &problem.whitening * &problem.k,
            b: &problem.whitening * &problem.target,
            shifts: vec![0.0; bounds.len()],
            bounds,
            pull,
            penalty,
        }
    }

    /// Multiplies the penalty by `factor` (at most up to [`MAX_PENALTY`]), keeping the
    /// multipliers: for bounds that the data push against harder than the penalty holds.
    pub(super) fn stiffen(&mut self, factor: f64) {
        let next = (self.penalty * factor).min(MAX_PENALTY);
        for s in &mut self.shifts {
            *s *= self.penalty / next;
        }
        self.penalty = next;
    }

    /// The multiplier update of the augmented Lagrangian (Powell-Hestenes-Rockafellar for
    /// inequalities: shift = max(0, shift - g / scale)) at p; returns the largest violation
    /// of a bound at p, in units of its scale.
    pub(super) fn update_shifts(&mut self, p: &[f64]) -> f64 {
        let mut grad = Vec::new();
        let mut worst: f64 = 0.0;
        for k in 0..self.bounds.len() {
            let (g, scale) = self.bound(&self.bounds[k], p, &mut grad);
            let g = g / scale;
            worst = worst.max(-g);
            self.shifts[k] = (self.shifts[k] - g).max(0.0);
        }
        worst
    }

    /// The objective of `problem` under `bounds` with the prior, weights and penalty of
    /// `options`, each checked first (the entry of both pure-Rust methods).
    pub(super) fn from_options(
        problem: &'a Problem,
        bounds: &Bounds,
        options: &SmoothOptions,
    ) -> Result<Self> {
        options.check()?;
        bounds.check_for(problem.layout.links.len())?;
        let pull = Pull::new(
            problem,
            bounds,
            options.prior.as_ref(),
            options.default_weight,
        )?;
        Ok(Objective::new(problem, bounds, pull, options.penalty))
    }

    /// The linear bounds with an open range (masses, centre-of-mass boxes, the total
    /// mass), which a barrier can keep: [`Objective::drop_open_linear`] then removes them.
    pub(super) fn open_linear(&self) -> Vec<Linear> {
        let masses = || self.problem.layout.links.iter().map(|idx| idx[9]);
        self.bounds
            .iter()
            .filter_map(|b| match *b {
                Bound::Linear {
                    entries,
                    rhs,
                    scale,
                    open: true,
                } => Some(Linear {
                    entries: entries.iter().copied().filter(|e| e.1 != 0.0).collect(),
                    rhs,
                    scale,
                }),
                Bound::TotalMass {
                    limit,
                    sign,
                    scale,
                    open: true,
                } => Some(Linear {
                    entries: masses().map(|i| (i, sign)).collect(),
                    rhs: sign * limit,
                    scale,
                }),
                _ => None,
            })
            .collect()
    }

    /// Removes the bounds [`Objective::open_linear`] gives from the penalties.
    pub(super) fn drop_open_linear(&mut self) {
        let keep: Vec<bool> = self
            .bounds
            .iter()
            .map(|b| {
                !matches!(
                    b,
                    Bound::Linear { open: true, .. } | Bound::TotalMass { open: true, .. }
                )
            })
            .collect();
        let mut k = keep.iter();
        self.bounds.retain(|_| *k.next().unwrap_or(&true));
        let mut k = keep.iter();
        self.shifts.retain(|_| *k.next().unwrap_or(&true));
    }

    /// The number of residual rows.
    pub(super) fn rows(&self) -> usize {
        self.a.nrows() + self.pull.target.len() + self.bounds.len()
    }

    /// The value g(p) of a bound, its scale and its gradient in p (sparse: (index,
    /// derivative)).
    fn bound(&self, bound: &Bound, p: &[f64], grad: &mut Vec<(usize, f64)>) -> (f64, f64) {
        grad.clear();
        match *bound {
            Bound::Linear {
                entries,
                rhs,
                scale,
                ..
            } => {
                grad.extend(entries.iter().filter(|e| e.1 != 0.0));
                let g = entries.iter().map(|&(i, c)| c * p[i]).sum::<f64>() - rhs;
                (g, scale)
            }
            Bound::InertiaElement {
                link,
                row,
                column,
                limit,
                sign,
                scale,
            } => {
                // I_c = J - (|h|^2 I - h h') / m, J the inertia about the origin
                let (a, b) = (row, column);
                let entry = link[STANDARD_ENTRY[a][b]];
                let m = p[link[9]].max(1e-300);
                let h = [p[link[6]], p[link[7]], p[link[8]]];
                let delta = if a == b { 1.0 } else { 0.0 };
                let norm2: f64 = h.iter().map(|v| v * v).sum();
                let shift = delta * norm2 - h[a] * h[b];
                let value = p[entry] - shift / m;
                grad.push((entry, sign));
                for (k, hk) in h.iter().enumerate() {
                    // d shift / d h_k
                    let mut d = 2.0 * delta * hk;
                    if k == a {
                        d -= h[b];
                    }
                    if k == b {
                        d -= h[a];
                    }
                    grad.push((link[6 + k], -sign * d / m));
                }
                grad.push((link[9], sign * shift / (m * m)));
                (sign * (value - limit), scale)
            }
            Bound::TotalMass {
                limit, sign, scale, ..
            } => {
                let layout = &self.problem.layout;
                let total: f64 = layout.links.iter().map(|idx| p[idx[9]]).sum();
                grad.extend(layout.links.iter().map(|idx| (idx[9], sign)));
                (sign * (total - limit), scale)
            }
        }
    }

    /// The residual rows at p: data, pull, bounds.
    pub(super) fn residuals(&self, p: &[f64]) -> DVector<f64> {
        let mut r = DVector::zeros(self.rows());
        let data = &self.a * DVector::from_column_slice(p) - &self.b;
        let nb = data.len();
        r.rows_mut(0, nb).copy_from(&data);
        let pull = &self.pull;
        for (s, v) in p.iter().enumerate() {
            r[nb + s] = pull.weight[s].sqrt() * (v - pull.target[s]) / pull.scale[s];
        }
        let start = nb + p.len();
        let mut grad = Vec::new();
        let mu = self.penalty.sqrt();
        for (k, bound) in self.bounds.iter().enumerate() {
            let (g, scale) = self.bound(bound, p, &mut grad);
            r[start + k] = mu * (g / scale - self.shifts[k]).min(0.0);
        }
        r
    }

    /// d residuals / d p at p.
    pub(super) fn jacobian(&self, p: &[f64]) -> DMatrix<f64> {
        let ns = p.len();
        let nb = self.a.nrows();
        let mut jac = DMatrix::zeros(self.rows(), ns);
        jac.rows_mut(0, nb).copy_from(&self.a);
        let pull = &self.pull;
        for s in 0..ns {
            jac[(nb + s, s)] = pull.weight[s].sqrt() / pull.scale[s];
        }
        let mut grad = Vec::new();
        let mu = self.penalty.sqrt();
        for (k, bound) in self.bounds.iter().enumerate() {
            let (g, scale) = self.bound(bound, p, &mut grad);
            if g / scale < self.shifts[k] {
                for &(i, d) in &grad {
                    jac[(nb + ns + k, i)] += mu * d / scale;
                }
            }
        }
        jac
    }

    /// The objective's value at p.
    pub(super) fn value(&self, p: &[f64]) -> f64 {
        self.residuals(p).norm_squared()
    }

    /// The data's and the prior's part of the value at p (chi^2 units), without the
    /// bounds' penalty, whose shifts differ between methods: what two methods that meet
    /// the bounds compare by.
    pub(super) fn fit_value(&self, p: &[f64]) -> f64 {
        let rows = self.a.nrows() + self.pull.target.len();
        self.residuals(p).rows(0, rows).norm_squared()
    }

    /// The starting point of both methods: the prior, each link just inside the consistent
    /// set (pseudo-inertia at least `margin` plus a small share of its scale), and the
    /// drive and free terms that fit best with those links (non-negative ones at least a
    /// small positive value).
    pub(super) fn start(&self, margin: f64) -> Result<Vec<f64>> {
        let layout = &self.problem.layout;
        let pull = &self.pull;
        let mut p = pull.target.clone();
        for idx in &layout.links {
            let values: [f64; PER_LINK] = idx.map(|i| p[i]);
            let floor = margin + 1e-6 * pull.scale[idx[9]].max(1e-12);
            let link = inside(&values, floor);
            if super::inertial::pseudo_inertia_min_eigenvalue(&link) <= margin {
                return Err(Error::Feasible(FeasibleError::NoFeasibleParameters {
                    reason: "the prior of a link cannot be made physically consistent; check the prior's masses and inertias".into(),
                }));
            }
            for (&i, v) in idx.iter().zip(link) {
                p[i] = v;
            }
        }
        let linear: Vec<usize> = layout
            .drives
            .iter()
            .map(|d| d.index)
            .chain(layout.extra.iter().copied())
            .collect();
        if linear.is_empty() {
            return Ok(p);
        }
        let cols: Vec<DVector<f64>> = linear
            .iter()
            .map(|&i| self.a.column(i).into_owned())
            .collect();
        let ad = DMatrix::from_columns(&cols);
        for &i in &linear {
            p[i] = 0.0;
        }
        let rest = &self.b - &self.a * DVector::from_column_slice(&p);
        let d = ad
            .try_svd(true, true, f64::EPSILON, crate::limits::SVD_ITERATIONS)
            .and_then(|s| s.solve(&rest, 1e-10).ok())
            .unwrap_or_else(|| DVector::zeros(linear.len()));
        for (k, &i) in linear.iter().enumerate() {
            p[i] = if self.non_negative(i) {
                d[k].max(1e-6 * pull.scale[i])
            } else {
                d[k]
            };
        }
        Ok(p)
    }

    /// True for a drive term that cannot be negative (Ia, Fv, Fc).
    pub(super) fn non_negative(&self, index: usize) -> bool {
        self.problem
            .layout
            .drives
            .iter()
            .any(|d| d.index == index && d.kind.non_negative())
    }
}

/// The inequalities of the bounds, each with the scale of its parameter.
fn inequalities(problem: &Problem, bounds: &Bounds, scale: &[f64]) -> Vec<Bound> {
    let mut out = Vec::new();
    let mut masses = 0.0;
    for (j, idx) in problem.layout.links.iter().enumerate() {
        let b = &bounds.links[j];
        let m = idx[9];
        let linear =
            |entries: [(usize, f64); 2], rhs: f64, scale: f64, [lo, hi]: [f64; 2]| Bound::Linear {
                entries,
                rhs,
                scale,
                open: lo < hi,
            };
        masses += scale[m];
        out.push(linear([(m, 1.0), (m, 0.0)], b.mass[0], scale[m], b.mass));
        out.push(linear([(m, -1.0), (m, 0.0)], -b.mass[1], scale[m], b.mass));
        for axis in 0..3 {
            let h = idx[6 + axis];
            let [lo, hi] = b.com[axis];
            out.push(linear([(h, 1.0), (m, -lo)], 0.0, scale[h], [lo, hi]));
            out.push(linear([(h, -1.0), (m, hi)], 0.0, scale[h], [lo, hi]));
            for (limit, sign) in [(b.inertia[0], 1.0), (b.inertia[1], -1.0)] {
                out.push(Bound::InertiaElement {
                    link: *idx,
                    row: axis,
                    column: axis,
                    limit,
                    sign,
                    scale: scale[idx[0]],
                });
            }
        }
        for (range, (_, row, column)) in b.tensor.iter().zip(TENSOR_ELEMENTS) {
            let Some([lo, hi]) = *range else { continue };
            for (limit, sign) in [(lo, 1.0), (hi, -1.0)] {
                out.push(Bound::InertiaElement {
                    link: *idx,
                    row,
                    column,
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
                open: lo < hi,
            });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::feasible::prior::Prior;
    use crate::feasible::{LinkBounds, LinkInertial, fixture};

    /// Two links, every standard parameter its own base parameter.
    fn problem() -> Problem {
        let names = crate::feasible::fixture::link_names(2);
        let n = names.len();
        Problem::new(names.clone(), names, nalgebra::DMatrix::identity(n, n))
            .unwrap()
            .with_target(&vec![0.1; n], &vec![1e-2; n])
            .unwrap()
    }

    /// Every kind of bound violated at once, and a point with an offset centre of mass and
    /// products of inertia: the Jacobian of the residuals equals their central differences
    /// (the penalty rows of the violated bounds included), and each violated bound adds
    /// its share to the objective.
    #[test]
    fn the_jacobian_matches_the_residuals_with_every_bound_violated() {
        let problem = problem();
        let link = |m: f64, c: [f64; 3]| {
            LinkInertial {
                mass: m,
                com: c,
                inertia: [
                    [0.03, 0.004, -0.002],
                    [0.004, 0.025, 0.003],
                    [-0.002, 0.003, 0.02],
                ],
            }
            .to_standard()
        };
        let mut p = link(1.5, [0.05, -0.08, 0.1]).to_vec();
        p.extend(link(0.8, [-0.1, 0.02, 0.04]));
        let tight = LinkBounds {
            mass: [2.0, 3.0],
            com: [[0.06, 0.1], [-0.05, 0.0], [-0.1, 0.05]],
            inertia: [0.021, 0.024],
            tensor: [
                Some([0.0, 0.01]),
                Some([0.03, 0.04]),
                Some([0.0, 0.01]),
                Some([-0.01, -0.005]),
                Some([0.0, 0.01]),
                Some([-0.01, -0.005]),
            ],
        };
        let bounds = Bounds {
            links: vec![tight, tight],
            total_mass: Some([5.0, 6.0]),
            margin: Some(1e-6),
        };
        let pull = Pull::new(&problem, &bounds, None, 1e-2).unwrap();
        let mut objective = Objective::new(&problem, &bounds, pull, 1e4);
        let free = Objective::new(&problem, &Bounds::wide(2), objective.pull.clone(), 1e4);
        assert!(
            objective.value(&p) > free.value(&p) + 1.0,
            "the bounds add to the objective"
        );
        // after the update, at a point where the masses meet their lower bound 2 kg by less
        // than the shift (g / scale = 0.3 / 3 < 1.5 / 3... the row stays active): the rows
        // that the multipliers keep active must be in the Jacobian
        let mut inside = p.clone();
        inside[9] = 2.3;
        inside[19] = 2.3;
        for shifted in [false, true] {
            if shifted {
                objective.update_shifts(&p);
            }
            let p = if shifted { inside.clone() } else { p.clone() };
            let j = objective.jacobian(&p);
            let step = 1e-7;
            for i in 0..p.len() {
                let (mut up, mut down) = (p.clone(), p.clone());
                up[i] += step;
                down[i] -= step;
                let fd = (objective.residuals(&up) - objective.residuals(&down)) / (2.0 * step);
                for r in 0..fd.len() {
                    // central differences of step 1e-7: measured 7.1e-8 at most, relative
                    assert!(
                        (fd[r] - j[(r, i)]).abs() <= 1.5e-7 * (1.0 + j[(r, i)].abs()),
                        "row {r}, parameter {i}: {} vs {} (shifted {shifted})",
                        fd[r],
                        j[(r, i)]
                    );
                }
            }
        }
    }

    /// The bounds' values against independent computations: each element of the inertia
    /// about the centre of mass (`LinkInertial::from_standard`), each centre-of-mass box
    /// edge through the centre of mass itself (zero there), and the pull rows (zero at the
    /// prior, sqrt(weight) one scale away).
    #[test]
    fn the_bounds_and_the_pull_have_their_values() {
        let problem = problem();
        let inertial = LinkInertial {
            mass: 1.5,
            com: [0.05, -0.08, 0.1],
            inertia: [
                [0.03, 0.004, -0.002],
                [0.004, 0.025, 0.003],
                [-0.002, 0.003, 0.02],
            ],
        };
        let mut p = inertial.to_standard().to_vec();
        p.extend(inertial.to_standard());
        let back = LinkInertial::from_standard(&inertial.to_standard()).unwrap();
        let pull = Pull::new(&problem, &Bounds::wide(2), None, 1e-2).unwrap();
        let objective = Objective::new(&problem, &Bounds::wide(2), pull.clone(), 1.0);
        let mut grad = Vec::new();
        for (_, row, column) in TENSOR_ELEMENTS {
            let bound = Bound::InertiaElement {
                link: problem.layout.links[0],
                row,
                column,
                limit: 0.0,
                sign: 1.0,
                scale: 1.0,
            };
            let (g, _) = objective.bound(&bound, &p, &mut grad);
            assert!(
                (g - back.inertia[row][column]).abs() < 1e-15,
                "{row}{column}: {g}"
            );
        }
        let idx = problem.layout.links[0];
        for axis in 0..3 {
            let c = inertial.com[axis];
            for (sign, coefficient) in [(1.0, -c), (-1.0, c)] {
                let bound = Bound::Linear {
                    entries: [(idx[6 + axis], sign), (idx[9], coefficient)],
                    rhs: 0.0,
                    scale: 1.0,
                    open: true,
                };
                let (g, _) = objective.bound(&bound, &p, &mut grad);
                assert!(g.abs() < 1e-15, "axis {axis}: {g}");
            }
        }
        // the inequalities of a box around the centre of mass: every one slack by m * 0.01
        let mut bounds = Bounds::wide(2);
        bounds.links[0].com = inertial.com.map(|c| [c - 0.01, c + 0.01]);
        let boxed = Objective::new(&problem, &bounds, pull.clone(), 1.0);
        let slack: Vec<f64> = boxed
            .bounds
            .iter()
            .filter_map(|b| match b {
                Bound::Linear { entries, .. } if entries[1].1 != 0.0 && entries[0].0 < 10 => {
                    Some(boxed.bound(b, &p, &mut grad).0)
                }
                _ => None,
            })
            .collect();
        assert_eq!(slack.len(), 6);
        assert!(slack.iter().all(|g| (g - 0.015).abs() < 1e-12), "{slack:?}");
        let nb = problem.base_names.len();
        let r = objective.residuals(&pull.target);
        assert!(r.rows(nb, p.len()).iter().all(|v| v.abs() < 1e-15));
        let mut moved = pull.target.clone();
        moved[3] += pull.scale[3];
        let r = objective.residuals(&moved);
        assert!(
            (r[nb + 3] - pull.weight[3].sqrt()).abs() < 1e-12,
            "{}",
            r[nb + 3]
        );
    }

    /// The multiplier update: a violated bound's shift grows by its violation (in units of
    /// its scale) and the worst violation is returned; a slack bound's shift falls to zero.
    /// Stiffening scales the shifts so that penalty x shift (the multiplier) is kept, up to
    /// the stiffest penalty.
    #[test]
    fn the_multipliers_are_updated_and_kept_when_stiffening() {
        let problem = fixture::problem(&fixture::target(fixture::link(), 0.1));
        let mut bounds = Bounds::wide(1);
        bounds.links[0].mass = [3.0, 4.0];
        let pull = Pull::new(&problem, &bounds, None, 1e-9).unwrap();
        let mut objective = Objective::new(&problem, &bounds, pull, 100.0);
        // 2 kg against at least 3 kg, in units of the mass scale (4 kg): 0.25; the upper
        // bound is slack by 0.5
        let p = fixture::target(fixture::link(), 0.1);
        let worst = objective.update_shifts(&p);
        assert!((worst - 0.25).abs() < 1e-15, "{worst}");
        assert!((objective.shifts[0] - 0.25).abs() < 1e-15);
        assert_eq!(objective.shifts[1], 0.0);
        // twice: the shift accumulates
        objective.update_shifts(&p);
        assert!((objective.shifts[0] - 0.5).abs() < 1e-15);
        // a point inside: the shift falls by the slack (0.25), then to zero
        let mut inside = p;
        inside[9] = 4.0;
        assert_eq!(objective.update_shifts(&inside), 0.0);
        assert!((objective.shifts[0] - 0.25).abs() < 1e-15);
        objective.update_shifts(&inside);
        assert_eq!(objective.shifts[0], 0.0);
        objective.update_shifts(&p);
        objective.stiffen(10.0);
        assert_eq!(objective.penalty, 1000.0);
        assert!((objective.shifts[0] - 0.025).abs() < 1e-15);
        objective.stiffen(1e20);
        assert_eq!(objective.penalty, MAX_PENALTY);
        assert!((objective.shifts[0] - 0.025 * 1000.0 / MAX_PENALTY).abs() < 1e-27);
    }

    /// The start: a consistent prior stays where it is, an inconsistent link is raised just
    /// inside the consistent set, the drive terms are those that fit best with the links
    /// (a rotor inertia at least 1e-6 of its scale, an offset of any sign).
    #[test]
    fn the_start_is_consistent_and_fits_the_drive_terms() {
        let mut t: Vec<f64> = fixture::target(fixture::link(), -0.1).to_vec();
        t.push(-0.3);
        let problem = fixture::problem_with(&t, &["Fo"]);
        let options = fixture::options();
        let objective = Objective::from_options(&problem, &Bounds::wide(1), &options).unwrap();
        let p = objective.start(1e-6).unwrap();
        // the centre of the wide bounds is a consistent link: kept as the prior gives it
        assert_eq!(p[..10], objective.pull.target[..10]);
        assert_eq!(p[10], 1e-6 * objective.pull.scale[10]);
        assert!((p[11] + 0.3).abs() < 1e-15, "{}", p[11]);
        assert!(objective.non_negative(10) && !objective.non_negative(11));
        assert!(!objective.non_negative(9));
        // a prior with a mass but no inertia: raised to the floor
        let mut standard = vec![None; 12];
        for (i, v) in [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 2.0]
            .iter()
            .enumerate()
        {
            standard[i] = Some(*v);
        }
        // the start and its link's least pseudo-inertia eigenvalue under a prior
        let start = |standard: Vec<Option<f64>>| {
            let options = SmoothOptions {
                prior: Some(Prior {
                    standard,
                    weight: 1.0,
                }),
                ..fixture::options()
            };
            let objective = Objective::from_options(&problem, &Bounds::wide(1), &options).unwrap();
            let p = objective.start(1e-6).unwrap();
            let link: [f64; 10] = std::array::from_fn(|i| p[i]);
            let least = crate::feasible::pseudo_inertia_min_eigenvalue(&link);
            (p, least, objective.pull.scale[9])
        };
        let (_, least, scale) = start(standard);
        let floor = 1e-6 + 1e-6 * scale;
        assert!(
            least >= floor * (1.0 - 1e-9) && least <= 1.01 * floor,
            "{least}"
        );
        // a negative mass too: its pseudo-inertia raised to the floor gives a small
        // positive mass
        let mut standard = vec![None; 12];
        standard[9] = Some(-1.0);
        let (p, least, _) = start(standard);
        assert!(p[9] > 0.0 && least >= 1e-6, "{p:?}");
    }

    /// A drive term regrouped with a link parameter (ZZR1 = ZZ1 + Ia1) starts at what the
    /// start's link leaves of the identified value: Ia1 = ZZR1 - ZZ1.
    #[test]
    fn a_regrouped_drive_term_starts_at_what_the_link_leaves() {
        let names = fixture::names();
        // every link parameter its own base parameter but ZZ1, which joins Ia1
        let rows: Vec<usize> = (0..10).filter(|&i| i != 5).collect();
        let mut k = DMatrix::zeros(10, 11);
        for (r, &i) in rows.iter().enumerate() {
            k[(r, i)] = 1.0;
        }
        k[(9, 5)] = 1.0;
        k[(9, 10)] = 1.0;
        let mut base: Vec<String> = rows.iter().map(|&i| names[i].clone()).collect();
        base.push("ZZR1".into());
        let mut target: Vec<f64> = rows.iter().map(|&i| fixture::link()[i]).collect();
        target.push(10.0);
        let problem = Problem::new(names, base, k)
            .unwrap()
            .with_target(&target, &[1e-3; 10])
            .unwrap();
        let objective =
            Objective::from_options(&problem, &Bounds::wide(1), &fixture::options()).unwrap();
        let p = objective.start(1e-6).unwrap();
        assert!(p[5] > 0.1, "ZZ1 {}", p[5]);
        // rounding of the solve of one whitened column (measured 8.9e-16, one ulp of 7.5)
        let error = p[10] - (10.0 - p[5]);
        assert!(error.abs() < 4e-15, "Ia1 {} ZZ1 {}", p[10], p[5]);
    }
}
