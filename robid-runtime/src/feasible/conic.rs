//! The semidefinite program of `sdp.rs` written for Clarabel: rows of
//! `A x + s = b` with `s` in a product of cones (zero, nonnegative, second-order
//! and PSD cones), solved by Clarabel's interior-point method.

use crate::FeasibleError;
use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettingsBuilder, DefaultSolver, IPSolver, SolverStatus, SupportedConeT,
};
use nalgebra::{DMatrix, DVector};

use super::bounds::Bounds;
use super::prior::Pull;
use super::problem::Problem;
use crate::{Error, Result};

/// Rows of `A x + s = b, s in K`, with the cones in order.
struct Conic {
    i: Vec<usize>,
    j: Vec<usize>,
    v: Vec<f64>,
    b: Vec<f64>,
    cones: Vec<SupportedConeT<f64>>,
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
) -> Result<Vec<f64>> {
    let p = solve_stage(problem, bounds, a, b, pull, None)?;
    let no_effect = problem.no_effect();
    if no_effect.is_empty() {
        return Ok(p);
    }
    // A failure here (numerical) keeps the first solution, which is feasible.
    Ok(solve_stage(problem, bounds, a, b, pull, Some((&p, &no_effect))).unwrap_or(p))
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
        c.cones.push(SupportedConeT::SecondOrderConeT(soc));
        let before = c.b.len();
        for (s, v) in fixed.iter().enumerate() {
            if !free.contains(&s) {
                c.row(&[(s, 1.0)], *v);
            }
        }
        let zero = c.b.len() - before;
        if zero > 0 {
            c.cones.push(SupportedConeT::ZeroConeT(zero));
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
        c.cones.push(SupportedConeT::SecondOrderConeT(soc));
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
        c.cones.push(SupportedConeT::NonnegativeConeT(linear));
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
        c.cones.push(SupportedConeT::PSDTriangleConeT(4));
    }

    let n = ns + 1;
    let a_mat = CscMatrix::new_from_triplets(c.b.len(), n, c.i, c.j, c.v);
    let p_mat = CscMatrix::<f64>::zeros((n, n));
    let mut q = vec![0.0; n];
    q[t] = 1.0;
    let settings = DefaultSettingsBuilder::default()
        .verbose(false)
        .max_iter(400)
        .build()
        .map_err(|e| {
            Error::Feasible(FeasibleError::NoFeasibleParameters {
                reason: format!("solver settings: {e}"),
            })
        })?;
    let mut solver =
        DefaultSolver::new(&p_mat, &q, &a_mat, &c.b, &c.cones, settings).map_err(|e| {
            Error::Feasible(FeasibleError::NoFeasibleParameters {
                reason: format!("solver setup: {e:?}"),
            })
        })?;
    solver.solve();
    match solver.solution.status {
        SolverStatus::Solved | SolverStatus::AlmostSolved => Ok(solver.solution.x[..ns].to_vec()),
        SolverStatus::PrimalInfeasible | SolverStatus::AlmostPrimalInfeasible => Err(Error::Feasible(FeasibleError::NoFeasibleParameters {
            reason: "the bounds and the physical-consistency constraints exclude every solution; widen the mass or centre-of-mass bounds, the total-mass range, or lower the margin".to_owned(),
        })),
        other => Err(Error::Feasible(FeasibleError::NoFeasibleParameters {
            reason: format!("the conic solver stopped with status {other:?}; check the bounds' scale (kg, m, kg m^2)"),
        })),
    }
}
