//! The search's last step with a prior: the parameters the data do not see moved to the
//! prior. The pull is a term of the searched objective, but the whitened misfit of the
//! data is stiffer than a weak pull by many orders (deviations of 1e-6 against a weight of
//! 0.01), so that the search stopped wherever it reached its target: a mass the data do
//! not weigh ended at 1.30 kg, 2.59 kg or 2.48 kg for a prior of 2.5 kg under weights of
//! 1e-4, 0.01 and 1, where the convex methods return 2.5 kg. In the null space of the
//! whitened K the misfit does not change, and the pull is a linear least squares there.

use nalgebra::{DMatrix, DVector};

use super::super::Problem;
use super::super::bounds::Bounds;
use super::super::prior::Pull;
use super::super::solution::{Method, Solution};

/// Relative singular-value threshold of the rank of the whitened K and of the pull in
/// its null space.
const RANK_TOLERANCE: f64 = 1e-12;

/// Bisections of the step's length when the whole step leaves the constraints.
const BISECTIONS: usize = 50;

/// `standard` moved towards the pull's targets within the null space of `a` (the whitened
/// K), so that the data's misfit does not change: the pull's least squares there, then the
/// longest part of that step that keeps every link's pseudo-inertia at least `margin` (or
/// its value before, where that is lower) and meets no fewer bounds than before.
pub(super) fn towards_prior(
    problem: &Problem,
    bounds: &Bounds,
    a: &DMatrix<f64>,
    pull: &Pull,
    margin: f64,
    standard: Vec<f64>,
) -> Vec<f64> {
    let Some(step) = null_space_step(a, pull, &standard) else {
        return standard;
    };
    let judge = |p: &[f64]| {
        Solution::assemble(
            problem,
            bounds,
            Method::Anneal,
            p.to_vec(),
            Default::default(),
        )
        .ok()
        .map(|s| {
            let out = outside(&s, bounds);
            (s.min_eigenvalues, s.violations.len(), out)
        })
    };
    let Some((eigenvalues, violations, out)) = judge(&standard) else {
        return standard;
    };
    let at = |t: f64| -> Vec<f64> {
        standard
            .iter()
            .zip(step.iter())
            .map(|(p, d)| p + t * d)
            .collect()
    };
    let keeps = |t: f64| {
        judge(&at(t)).is_some_and(|(e, v, o)| {
            v <= violations
                && o.iter().zip(&out).all(|(now, before)| *now <= *before)
                && e.iter()
                    .zip(&eigenvalues)
                    .all(|(now, before)| *now >= margin.min(*before))
        })
    };
    if keeps(1.0) {
        return at(1.0);
    }
    let (mut good, mut bad) = (0.0, 1.0);
    for _ in 0..BISECTIONS {
        let t = 0.5 * (good + bad);
        if keeps(t) {
            good = t;
        } else {
            bad = t;
        }
    }
    if good > 0.0 { at(good) } else { standard }
}

/// How far each link's mass and centre-of-mass coordinates lie outside their bounds (0
/// inside), without the checks' tolerance: the step stops at a face of the box, where
/// the checks let it pass by their tolerance (a centre of mass at 1.000002 m for a bound
/// of 1 m).
fn outside(s: &Solution, bounds: &Bounds) -> Vec<f64> {
    let beyond = |v: f64, r: [f64; 2]| (r[0] - v).max(v - r[1]).max(0.0);
    s.links
        .iter()
        .zip(&bounds.links)
        .flat_map(|(l, b)| match l {
            Some(l) => [
                beyond(l.mass, b.mass),
                beyond(l.com[0], b.com[0]),
                beyond(l.com[1], b.com[1]),
                beyond(l.com[2], b.com[2]),
            ],
            None => [f64::INFINITY; 4],
        })
        .collect()
}

/// The step `P y` of least pull `||D (p + P y - target)||` with `P` the projector on the
/// null space of `a` and `D` the pull's weights over its scales; `None` when `a` has no
/// null space or the pull none in it.
fn null_space_step(a: &DMatrix<f64>, pull: &Pull, p: &[f64]) -> Option<DVector<f64>> {
    let n = p.len();
    let svd = a
        .clone()
        .try_svd(false, true, f64::EPSILON, crate::limits::SVD_ITERATIONS)?;
    let vt = svd.v_t.as_ref()?;
    let top = svd.singular_values.max();
    let mut projector = DMatrix::identity(n, n);
    for (k, s) in svd.singular_values.iter().enumerate() {
        if *s > RANK_TOLERANCE * top {
            let v = vt.row(k).transpose();
            projector -= &v * v.transpose();
        }
    }
    let d = DVector::from_fn(n, |s, _| {
        if pull.weight[s] > 0.0 {
            pull.weight[s].sqrt() / pull.scale[s]
        } else {
            0.0
        }
    });
    let dp = DMatrix::from_fn(n, n, |i, j| d[i] * projector[(i, j)]);
    let gap = DVector::from_fn(n, |s, _| d[s] * (pull.target[s] - p[s]));
    let svd = dp.try_svd(true, true, f64::EPSILON, crate::limits::SVD_ITERATIONS)?;
    let top = svd.singular_values.max();
    if !(top > 0.0) {
        return None;
    }
    let y = svd.solve(&gap, RANK_TOLERANCE * top).ok()?;
    let step = projector * y;
    (step.iter().all(|v| v.is_finite()) && step.iter().any(|v| *v != 0.0)).then_some(step)
}
