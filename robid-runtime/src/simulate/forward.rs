//! Forward dynamics from a model in base parameters.
//!
//! M(q) qdd = tau - h(q, qd), where h = c(q, qd) + g(q) + friction(qd) + offsets is the
//! inverse dynamics at zero acceleration (`Model::inverse_dynamics_into(q, qd, 0)`): the model's
//! own drive terms (Fv qd, Fc sign(qd), Fo) are therefore exactly those of the data it is
//! identified from. M(q) includes the rotor inertias Ia. The system is solved by Cholesky,
//! whose pivots must exceed the rounding of M(q) ([`pivot_tolerance`]).

use nalgebra::{Cholesky, DMatrix, DVector, Dyn, SymmetricEigen};

use crate::Model;
use crate::error::{Error, Result};
use crate::simulate::SimulateError;

/// A diagonal entry of M(q) at most this fraction of the largest in magnitude is zero:
/// rounding of parameters that are zero (a URDF link without `<inertial>`), not a body.
const ZERO_INERTIA: f64 = 1e-12;

/// The size, relative to its diagonal entry `M_jj`, at or below which a pivot of the
/// Cholesky factorisation of an n-joint mass matrix is rounding, not inertia:
/// `(n + 1)^2 eps`.
///
/// A pivot `d_j = M_jj - sum_k L_jk^2` is the inertia joint j adds to the joints before it
/// (a Schur complement); it is 0 when joint j moves the bodies as a combination of them
/// does (two joints on one axis with nothing massive between them), and then only rounding
/// decides its sign: plain Cholesky took a pivot of 0.8 eps M_22 as positive and the
/// simulation split the motion between the joints at random. Its rounding has two parts:
/// the factorisation's own, at most `(n + 1) eps M_jj` (Higham, *Accuracy and Stability of
/// Numerical Algorithms*, thm. 10.3: `|dM| <= gamma_(n+1) |L| |L^T|`, whose diagonal is
/// `M_jj`), and that of M(q) itself, whose composite-rigid-body evaluation sums each entry
/// over at most n links and so rounds `M_ik` by about `(n + 1) eps sqrt(M_ii M_kk)`; a
/// pivot combines up to n such entries with weights at most 1 in the diagonal's scale,
/// which gives at most `n (n + 1) eps M_jj`. Relative to each diagonal entry, not to the
/// largest, so that a light link (M(q) of condition 1e7) keeps its pivot near its own
/// diagonal. Measured: exactly singular mass matrices of 2- to 8-joint URDF chains gave
/// pivots and eigenvalues of -0.02 to 4 eps of their diagonal, regular random chains at
/// least 6e-7.
pub(super) fn pivot_tolerance(n: usize) -> f64 {
    let k = (n + 1) as f64;
    k * k * f64::EPSILON
}

/// The Cholesky factorisation of the mass matrix `m` (n x n, row-major), or `None` when
/// `m` is not positive definite by more than its rounding: a pivot at most
/// [`pivot_tolerance`] of its diagonal entry counts as zero.
pub(super) fn factor(m: &[f64], n: usize) -> Option<Cholesky<f64, Dyn>> {
    let chol = DMatrix::from_row_slice(n, n, m).cholesky()?;
    let l = chol.l_dirty();
    let tolerance = pivot_tolerance(n);
    (0..n)
        .all(|j| l[(j, j)] * l[(j, j)] > tolerance * m[j * n + j])
        .then_some(chol)
}

/// The joints (numbered from 1) whose diagonal entry of the mass matrix `m` (n x n,
/// row-major) is zero: they move no mass, or no inertia about their axis, at this state.
fn without_inertia(m: &[f64], n: usize) -> Vec<usize> {
    let diagonal = |j: usize| m[j * n + j].abs();
    let largest = (0..n).map(diagonal).fold(0.0, f64::max);
    (0..n)
        .filter(|&j| diagonal(j) <= ZERO_INERTIA * largest)
        .map(|j| j + 1)
        .collect()
}

/// A joint takes part in a motion that moves no mass when its squared component in the
/// null space of the diagonally scaled M(q) (summed over the null directions, out of 1)
/// is at least this: a share of a thousandth in velocity, far above the eigenvectors'
/// rounding (eps over the gap to the next eigenvalue).
const NULL_SHARE: f64 = 1e-6;

/// Iteration cap of the eigenvalue decomposition that explains a singular M(q).
const EIGEN_ITERATIONS: usize = 1_000;

/// When the mass matrix `m` (n x n, row-major, with a positive diagonal) is positive
/// semidefinite to its rounding, as physically consistent parameters make it, and
/// singular: the joints (numbered from 1) whose motions coincide, and the joint velocities
/// that move no mass (its null vector, the largest component 1). `None` when `m` is
/// indefinite beyond rounding: inconsistent parameters. Judged on `D^-1/2 M D^-1/2` (D its
/// diagonal, a unit diagonal), so that joints of other units and light links weigh alike,
/// against the pivots' tolerance (the smallest eigenvalue is at most the smallest
/// relative pivot).
fn coinciding(m: &[f64], n: usize) -> Option<(Vec<usize>, Vec<f64>)> {
    let root: Vec<f64> = (0..n).map(|j| m[j * n + j].sqrt()).collect();
    if !root.iter().all(|r| *r > 0.0 && r.is_finite()) {
        return None;
    }
    let scaled = DMatrix::from_fn(n, n, |i, k| m[i * n + k] / (root[i] * root[k]));
    let eigen = SymmetricEigen::try_new(scaled, f64::EPSILON, EIGEN_ITERATIONS)?;
    let tolerance = pivot_tolerance(n);
    let lowest = eigen.eigenvalues.imin();
    if eigen.eigenvalues[lowest] < -tolerance {
        return None;
    }
    let null: Vec<usize> = (0..n)
        .filter(|&c| c == lowest || eigen.eigenvalues[c] <= tolerance)
        .collect();
    let joints: Vec<usize> = (0..n)
        .filter(|&j| {
            null.iter()
                .map(|&c| eigen.eigenvectors[(j, c)].powi(2))
                .sum::<f64>()
                >= NULL_SHARE
        })
        .collect();
    if joints.len() < 2 {
        return None;
    }
    // the velocities: the scaled null vector back in joint units, the largest +1
    let mut motion: Vec<f64> = (0..n)
        .map(|j| {
            if joints.contains(&j) {
                eigen.eigenvectors[(j, lowest)] / root[j]
            } else {
                0.0
            }
        })
        .collect();
    let largest = motion
        .iter()
        .copied()
        .fold(0.0, |a: f64, v| if v.abs() > a.abs() { v } else { a });
    motion.iter_mut().for_each(|v| *v /= largest);
    Some((joints.iter().map(|j| j + 1).collect(), motion))
}

/// The error of a mass matrix `m` (n x n, row-major; `what`: of which model at which
/// state) that [`factor`] refused: joints that move nothing when its diagonal says so
/// ([`SimulateError::NoInertia`]: the parameters leave bodies empty, as a URDF's links
/// without `<inertial>` do), joints whose motions coincide when it is positive
/// semidefinite, as physically consistent parameters make it
/// ([`SimulateError::Coinciding`]), else parameters that are not physically consistent.
pub(super) fn singular(what: String, m: &[f64], n: usize) -> Error {
    let joints = without_inertia(m, n);
    if !joints.is_empty() {
        return Error::Simulate(SimulateError::NoInertia {
            what,
            joints,
            dof: n,
        });
    }
    match coinciding(m, n) {
        Some((joints, motion)) => Error::Simulate(SimulateError::Coinciding {
            what,
            joints,
            motion,
        }),
        None => Error::Singular {
            what,
            hint: "the parameters are not physically consistent; use a feasible parameter set (robid feasible)",
        },
    }
}

/// Scratch space and the model for repeated forward-dynamics calls.
#[derive(Debug)]
pub struct ForwardDynamics<'a, M: Model + ?Sized> {
    model: &'a M,
    base: &'a [f64],
    m: Vec<f64>,
    h: Vec<f64>,
    zero: Vec<f64>,
}

impl<'a, M: Model + ?Sized> ForwardDynamics<'a, M> {
    /// Forward dynamics of `model` with base parameters `base` (length checked).
    pub fn new(model: &'a M, base: &'a [f64]) -> Result<Self> {
        if base.len() != model.base_parameter_count() {
            return Err(Error::DimensionMismatch {
                what: format!("base parameters of {}", model.name()),
                expected: model.base_parameter_count(),
                found: base.len(),
            });
        }
        let n = model.dof();
        Ok(Self {
            model,
            base,
            m: vec![0.0; n * n],
            h: vec![0.0; n],
            zero: vec![0.0; n],
        })
    }

    /// The model.
    pub fn model(&self) -> &M {
        self.model
    }

    /// The base parameters.
    pub fn base(&self) -> &[f64] {
        self.base
    }

    /// Joint accelerations for torques `tau` at state (q, qd), written to `qdd`.
    /// Fails when M(q) is not positive definite by more than its rounding (a Cholesky
    /// pivot at most `(n + 1)^2 eps` of its diagonal entry counts as zero): physically
    /// inconsistent parameters, joints whose motions coincide
    /// ([`SimulateError::Coinciding`]), or a joint that moves no mass or inertia
    /// ([`SimulateError::NoInertia`]).
    pub fn accelerations(
        &mut self,
        q: &[f64],
        qd: &[f64],
        tau: &[f64],
        qdd: &mut [f64],
    ) -> Result<()> {
        let n = self.model.dof();
        self.model.mass_matrix_into(q, self.base, &mut self.m)?;
        self.model
            .inverse_dynamics_into(q, qd, &self.zero, self.base, &mut self.h)?;
        let rhs = DVector::from_iterator(n, (0..n).map(|j| tau[j] - self.h[j]));
        let chol = factor(&self.m, n).ok_or_else(|| {
            singular(
                format!("the mass matrix M(q) of {} at q = {q:?}", self.model.name()),
                &self.m,
                n,
            )
        })?;
        let x = chol.solve(&rhs);
        qdd[..n].copy_from_slice(x.as_slice());
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simulate::tests::Pendulum;

    #[test]
    fn inverse_then_forward_is_identity() {
        let p = Pendulum::default();
        let base = p.base();
        let mut fd = ForwardDynamics::new(&p, &base).unwrap();
        let (q, qd, qdd) = ([0.3, -0.7], [0.5, 1.2], [2.0, -3.0]);
        let mut tau = [0.0; 2];
        p.inverse_dynamics_into(&q, &qd, &qdd, &base, &mut tau)
            .unwrap();
        let mut back = [0.0; 2];
        fd.accelerations(&q, &qd, &tau, &mut back).unwrap();
        for j in 0..2 {
            assert!((back[j] - qdd[j]).abs() < 1e-10, "{back:?}");
        }
        assert!(matches!(
            ForwardDynamics::new(&p, &[1.0]),
            Err(Error::DimensionMismatch { .. })
        ));
    }

    /// Base parameters of the pendulum whose second link is a point mass `m` at `x` along
    /// it and whose first link is massless (`ZZR1 = m l1^2`, `ZZ2 = m x^2`, `MX2 = m x`),
    /// without friction, and with `ZZR1` raised by `extra` of itself. At q2 = 0 the point
    /// mass lies on the line through both axes: turning joint 1 one way and joint 2 back by
    /// (l1 + x) / x moves no mass, so M(q) is singular there (with `extra` = 0).
    pub(crate) fn point_mass(m: f64, x: f64, extra: f64) -> Vec<f64> {
        let l1 = 0.5;
        let mut base = vec![0.0; 10];
        base[0] = m * l1 * l1 * (1.0 + extra);
        base[1] = m * x * x;
        base[2] = m * x;
        base[4] = m * l1;
        base
    }

    /// A mass matrix singular in exact arithmetic is refused although rounding leaves
    /// plain Cholesky a tiny positive pivot (here at least one of these cases; the
    /// simulation then split the motion between the joints at random), by the forward
    /// dynamics and by `Simulation::run` before it starts, naming the joints whose motions
    /// coincide and the motion that moves no mass (joint 2 turning back by (l1 + x) / x
    /// times joint 1), not the parameters, which are consistent; one that is regular by a
    /// relative 1e-7 (condition number about 1e8) is not refused, and simulates.
    #[test]
    fn a_mass_matrix_singular_to_rounding_is_refused() {
        let p = Pendulum::default();
        let (q, qd, tau) = ([0.0; 2], [0.0; 2], [0.0; 2]);
        let mut qdd = [0.0; 2];
        let mut plain_took = 0;
        for m in [1.0, 0.7, 2.3] {
            for x in [0.1, 0.15, 0.2, 0.3, 0.35, 0.45, 0.7] {
                let base = point_mass(m, x, 0.0);
                let mut mass = [0.0; 4];
                p.mass_matrix_into(&q, &base, &mut mass).unwrap();
                if DMatrix::from_row_slice(2, 2, &mass).cholesky().is_some() {
                    plain_took += 1;
                }
                let e = ForwardDynamics::new(&p, &base)
                    .unwrap()
                    .accelerations(&q, &qd, &tau, &mut qdd)
                    .unwrap_err();
                let velocity = format!("[{}, 1]", crate::Num::rounded(-x / (0.5 + x), 3));
                assert!(
                    matches!(&e, Error::Simulate(SimulateError::Coinciding { joints, .. }) if joints == &[1, 2]),
                    "{m} {x}: {e:?}"
                );
                let e = e.to_string();
                assert!(
                    e.contains(&format!(
                        "is singular: joints 1 and 2 move the same bodies the same way (the \
                         joint velocities {velocity} move no mass)"
                    )) && e.contains("give link 1 a mass and inertia")
                        && e.contains("describe the two joints as one")
                        && !e.contains("not physically consistent"),
                    "{m} {x}: {e}"
                );
                let reference = crate::simulate::run_tests::reference(0.2, 500.0);
                let e = crate::simulate::Simulation::default()
                    .run(&p, &base, &reference)
                    .unwrap_err()
                    .to_string();
                assert!(
                    e.starts_with(
                        "the mass matrix M(q) of pendulum2 at the reference's first state"
                    ),
                    "{m} {x}: {e}"
                );
            }
        }
        assert!(plain_took > 0, "no case for the tolerance");
        // regular by 1e-7 of ZZR1: simulated
        let base = point_mass(1.0, 0.3, 1e-7);
        let reference = crate::simulate::run_tests::reference(0.5, 500.0);
        crate::simulate::Simulation::default()
            .run(&p, &base, &reference)
            .unwrap();
    }

    /// A joint whose bodies carry nothing (a URDF's last link without `<inertial>`) makes
    /// M(q) singular through a zero diagonal entry: that joint is named, and the
    /// parameters are not called physically inconsistent (they are consistent, only
    /// empty). Parameters that are inconsistent are still called so.
    #[test]
    fn a_joint_that_moves_nothing_is_named() {
        let p = Pendulum::default();
        let mut base = p.base();
        // link 2 empty: ZZ2, MX2, MY2
        base[1..4].fill(0.0);
        let (q, qd, tau) = ([0.3, -0.4], [0.0; 2], [0.0; 2]);
        let mut qdd = [0.0; 2];
        let e = ForwardDynamics::new(&p, &base)
            .unwrap()
            .accelerations(&q, &qd, &tau, &mut qdd)
            .unwrap_err();
        assert!(
            matches!(&e, Error::Simulate(SimulateError::NoInertia { joints, dof: 2, .. }) if joints == &[2]),
            "{e:?}"
        );
        let message = e.to_string();
        assert!(
            message.starts_with(
                "the mass matrix M(q) of pendulum2 at q = [0.3, -0.4] is singular: joint 2 \
                 moves no mass or inertia (M22 = 0), so no torque accelerates it"
            ) && message.contains("give link 2 (the last) no mass")
                && message.contains("`<inertial>`")
                && !message.contains("physically consistent"),
            "{message}"
        );
        // every link empty: every joint named, from the first link on
        let empty = vec![0.0; base.len()];
        let e = ForwardDynamics::new(&p, &empty)
            .unwrap()
            .accelerations(&q, &qd, &tau, &mut qdd)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("joints 1 and 2 move no mass or inertia (M11 = M22 = 0)")
                && e.contains("give links 1 to 2 no mass"),
            "{e}"
        );
        // a negative inertia is not an empty body
        base[1] = -0.3;
        let e = ForwardDynamics::new(&p, &base)
            .unwrap()
            .accelerations(&q, &qd, &tau, &mut qdd)
            .unwrap_err();
        assert!(matches!(e, Error::Singular { .. }), "{e:?}");
        assert!(e.to_string().contains("not physically consistent"), "{e}");
    }

    /// `Simulation::run` checks M(q) at the reference's first state the same way.
    #[test]
    fn a_simulation_names_a_joint_that_moves_nothing_before_it_starts() {
        let p = Pendulum::default();
        let mut base = p.base();
        base[1..4].fill(0.0);
        let reference = crate::simulate::run_tests::reference(1.0, 100.0);
        let e = crate::simulate::Simulation::default()
            .run(&p, &base, &reference)
            .unwrap_err();
        assert!(
            matches!(&e, Error::Simulate(SimulateError::NoInertia { joints, .. }) if joints == &[2]),
            "{e:?}"
        );
        assert!(
            e.to_string().starts_with(
                "the mass matrix M(q) of pendulum2 at the reference's first state q = [0.0, \
                 0.0] is singular: joint 2 moves no mass or inertia"
            ),
            "{e}"
        );
    }
}
