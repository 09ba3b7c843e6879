//! The semidefinite program of `sdp.rs` as rows of `A x + s = b` with `s` in a product of
//! cones (zero, nonnegative, second-order and PSD cones), for any [`ConicSolver`]: the
//! program is built here, the solver (Clarabel, which needs OpenBLAS) lives in the
//! `robid-sdp` crate, so that choosing it rebuilds that small crate, not this one.

use nalgebra::{DMatrix, DVector};

use super::bounds::Bounds;
use super::prior::Pull;
use super::problem::Problem;
use crate::{Error, FeasibleError, Result};

/// A cone of a [`ConicProgram`]'s rows, in order, with its number of rows (its dimension
/// for a PSD cone).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Cone {
    /// `s = 0`: equalities.
    Zero(usize),
    /// `s >= 0`.
    Nonnegative(usize),
    /// `s_0 >= ||s_1..||`, of this many rows.
    SecondOrder(usize),
    /// The upper triangle of a symmetric `n x n` positive semidefinite matrix, column by
    /// column, the off-diagonal entries times `sqrt 2` (`n (n + 1) / 2` rows).
    PsdTriangle(usize),
}

/// `min q'x` subject to `A x + s = b`, `s` in the product of `cones` (rows in order); `A`
/// by its nonzero entries.
#[derive(Debug, Clone, PartialEq)]
pub struct ConicProgram {
    /// The number of variables (the columns of `A`, the length of `q`).
    pub variables: usize,
    /// The row of each nonzero entry of `A`.
    pub rows: Vec<usize>,
    /// The column of each nonzero entry of `A`.
    pub columns: Vec<usize>,
    /// The nonzero entries of `A`.
    pub values: Vec<f64>,
    /// `b`, one entry per row.
    pub b: Vec<f64>,
    /// The linear objective.
    pub q: Vec<f64>,
    /// The cones of the rows, in order.
    pub cones: Vec<Cone>,
}

/// Why a [`ConicSolver`] gives no solution.
#[derive(Debug, Clone, PartialEq)]
pub enum ConicFailure {
    /// The constraints exclude every point.
    Infeasible,
    /// The solver stopped without a solution, for this reason.
    Stopped(String),
}

/// A solver of [`ConicProgram`]s: the `robid-sdp` crate's Clarabel.
pub trait ConicSolver: std::fmt::Debug {
    /// The optimal `x` of `program`.
    fn solve(&self, program: &ConicProgram) -> std::result::Result<Vec<f64>, ConicFailure>;
}

/// Rows of `A x + s = b, s in K`, with the cones in order.
struct Conic {
    i: Vec<usize>,
    j: Vec<usize>,
    v: Vec<f64>,
    b: Vec<f64>,
    cones: Vec<Cone>,
}

impl Conic {
    fn row(&mut self, entries: &[(usize, f64)], b: f64) {
        let r = self.b.len();
        for &(j, v) in entries {
            if v != 0.0 {
                self.i.push(r);
                self.j.push(j);
                self.v.push(v);
            }
        }
        self.b.push(b);
    }

    /// `lhs . x >= rhs`, as s = lhs . x - rhs >= 0.
    fn at_least(&mut self, lhs: &[(usize, f64)], rhs: f64) {
        let neg: Vec<(usize, f64)> = lhs.iter().map(|&(j, v)| (j, -v)).collect();
        self.row(&neg, -rhs);
    }
}

/// Solves the conic program for `min ||a p - b||` under the constraints of `bounds`.
///
/// The pull towards the prior or the centre of the bounds is far too weak to move the
/// parameters with no effect on the fit away from wherever the interior-point method ends
/// (it is below the solver's tolerance), so they are settled by a second program: every
/// parameter with an effect is held at the first solution (the fit is unchanged) and the
/// others minimise their distance to the prior or centre under the same constraints.
pub(super) fn solve(
    problem: &Problem,
    bounds: &Bounds,
    a: &DMatrix<f64>,
    b: &DVector<f64>,
    pull: &Pull,
    solver: &dyn ConicSolver,
) -> Result<Vec<f64>> {
    let p = solve_stage(problem, bounds, a, b, pull, None, solver)?;
    let no_effect = problem.no_effect();
    if no_effect.is_empty() {
        return Ok(p);
    }
    // A failure here (numerical) keeps the first solution, which is feasible.
    Ok(solve_stage(problem, bounds, a, b, pull, Some((&p, &no_effect)), solver).unwrap_or(p))
}

/// One conic program. With `settle = Some((p, free))`, every parameter outside `free` is
/// fixed at `p` and the objective is the pull alone (weight 1).
fn solve_stage(
    problem: &Problem,
    bounds: &Bounds,
    a: &DMatrix<f64>,
    b: &DVector<f64>,
    pull: &Pull,
    settle: Option<(&[f64], &[usize])>,
    solver: &dyn ConicSolver,
) -> Result<Vec<f64>> {
    let margin = bounds.margin_for(&problem.layout, Some(&pull.target))?;
    let layout = &problem.layout;
    let ns = problem.standard_names.len();
    bounds.check_for(layout.links.len())?;
    let t = ns; // epigraph variable of the norm
    let mut c = Conic {
        i: vec![],
        j: vec![],
        v: vec![],
        b: vec![],
        cones: vec![],
    };

    // Second-order cone: (t, A p - b, pull rows): each parameter is pulled towards
    // `pull.target` with `pull.weight`.
    // (`Pull::new` gives one target and weight per standard parameter.)
    let (p0, weight) = (&pull.target, &pull.weight);
    let scale = &pull.scale;
    c.row(&[(t, -1.0)], 0.0);
    if let Some((fixed, free)) = settle {
        // Relative weights only: a parameter with a prior outweighs one without.
        let top = weight
            .iter()
            .copied()
            .fold(0.0, f64::max)
            .max(f64::MIN_POSITIVE);
        for &s in free {
            let sw = (weight[s] / top).sqrt();
            c.row(&[(s, -sw / scale[s])], -sw * p0[s] / scale[s]);
        }
        let soc = c.b.len();
        c.cones.push(Cone::SecondOrder(soc));
        let before = c.b.len();
        for (s, v) in fixed.iter().enumerate() {
            if !free.contains(&s) {
                c.row(&[(s, 1.0)], *v);
            }
        }
        let zero = c.b.len() - before;
        if zero > 0 {
            c.cones.push(Cone::Zero(zero));
        }
    } else {
        for r in 0..a.nrows() {
            let entries: Vec<(usize, f64)> = (0..ns).map(|s| (s, -a[(r, s)])).collect();
            c.row(&entries, -b[r]);
        }
        for s in (0..ns).filter(|&s| weight[s] > 0.0) {
            let sw = weight[s].sqrt();
            c.row(&[(s, -sw / scale[s])], -sw * p0[s] / scale[s]);
        }
        let soc = c.b.len();
        c.cones.push(Cone::SecondOrder(soc));
    }

    // Linear bounds.
    let before = c.b.len();
    let mut masses = Vec::new();
    for (j, idx) in layout.links.iter().enumerate() {
        let lb = &bounds.links[j];
        let m = idx[9];
        masses.push((m, 1.0));
        c.at_least(&[(m, 1.0)], lb.mass[0]);
        c.at_least(&[(m, -1.0)], -lb.mass[1]);
        for ax in 0..3 {
            let h = idx[6 + ax];
            c.at_least(&[(h, 1.0), (m, -lb.com[ax][0])], 0.0);
            c.at_least(&[(h, -1.0), (m, lb.com[ax][1])], 0.0);
        }
    }
    if let Some(tm) = bounds.total_mass {
        c.at_least(&masses, tm[0]);
        let neg: Vec<(usize, f64)> = masses.iter().map(|&(m, _)| (m, -1.0)).collect();
        c.at_least(&neg, -tm[1]);
    }
    for d in &layout.drives {
        if d.kind.non_negative() {
            c.at_least(&[(d.index, 1.0)], 0.0);
        }
    }
    let linear = c.b.len() - before;
    if linear > 0 {
        c.cones.push(Cone::Nonnegative(linear));
    }

    // Pseudo-inertia LMIs, upper triangle column by column, off-diagonals times sqrt(2).
    let r2 = std::f64::consts::SQRT_2;
    for idx in &layout.links {
        let [xx, xy, xz, yy, yz, zz, mx, my, mz, m] = *idx;
        let entries: [(Vec<(usize, f64)>, bool); 10] = [
            (vec![(xx, -0.5), (yy, 0.5), (zz, 0.5)], true),
            (vec![(xy, -r2)], false),
            (vec![(xx, 0.5), (yy, -0.5), (zz, 0.5)], true),
            (vec![(xz, -r2)], false),
            (vec![(yz, -r2)], false),
            (vec![(xx, 0.5), (yy, 0.5), (zz, -0.5)], true),
            (vec![(mx, r2)], false),
            (vec![(my, r2)], false),
            (vec![(mz, r2)], false),
            (vec![(m, 1.0)], true),
        ];
        for (coef, diagonal) in entries {
            let neg: Vec<(usize, f64)> = coef.iter().map(|&(j, v)| (j, -v)).collect();
            c.row(&neg, if diagonal { -margin } else { 0.0 });
        }
        c.cones.push(Cone::PsdTriangle(4));
    }

    let mut q = vec![0.0; ns + 1];
    q[t] = 1.0;
    let program = ConicProgram {
        variables: ns + 1,
        rows: c.i,
        columns: c.j,
        values: c.v,
        b: c.b,
        q,
        cones: c.cones,
    };
    match solver.solve(&program) {
        Ok(x) if x.len() == ns + 1 => Ok(x[..ns].to_vec()),
        Ok(x) => Err(Error::Feasible(FeasibleError::NoFeasibleParameters {
            reason: format!(
                "the conic solver gave {} values for {} variables",
                x.len(),
                ns + 1
            ),
        })),
        Err(ConicFailure::Infeasible) => Err(Error::Feasible(FeasibleError::NoFeasibleParameters {
            reason: "the bounds and the physical-consistency constraints exclude every solution; widen the mass or centre-of-mass bounds, the total-mass range, or lower the margin".to_owned(),
        })),
        Err(ConicFailure::Stopped(why)) => Err(Error::Feasible(FeasibleError::NoFeasibleParameters {
            reason: format!("the conic solver stopped ({why}); check the bounds' scale (kg, m, kg m^2)"),
        })),
    }
}
