//! Forward dynamics from a model in base parameters.
//!
//! M(q) qdd = tau - h(q, qd), where h = c(q, qd) + g(q) + friction(qd) + offsets is the
//! inverse dynamics at zero acceleration (`Model::inverse_dynamics_into(q, qd, 0)`): the model's
//! own drive terms (Fv qd, Fc sign(qd), Fo) are therefore exactly those of the data it is
//! identified from. M(q) includes the rotor inertias Ia. The system is solved by Cholesky.

use nalgebra::{DMatrix, DVector};

use crate::Model;
use crate::error::{Error, Result};
use crate::simulate::SimulateError;

/// A diagonal entry of M(q) at most this fraction of the largest in magnitude is zero:
/// rounding of parameters that are zero (a URDF link without `<inertial>`), not a body.
const ZERO_INERTIA: f64 = 1e-12;

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

/// The error of a mass matrix `m` (n x n, row-major; `what`: of which model at which
/// state) that Cholesky refused: joints that move nothing when its diagonal says so
/// ([`SimulateError::NoInertia`]: the parameters leave bodies empty, as a URDF's links
/// without `<inertial>` do), else parameters that are not physically consistent.
pub(super) fn singular(what: String, m: &[f64], n: usize) -> Error {
    let joints = without_inertia(m, n);
    if joints.is_empty() {
        Error::Singular {
            what,
            hint: "the parameters are not physically consistent; use a feasible parameter set (robid feasible)",
        }
    } else {
        Error::Simulate(SimulateError::NoInertia {
            what,
            joints,
            dof: n,
        })
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
    /// Fails when M(q) is not positive definite: physically inconsistent parameters, or a
    /// joint that moves no mass or inertia ([`SimulateError::NoInertia`]).
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
        let m = DMatrix::from_row_slice(n, n, &self.m);
        let rhs = DVector::from_iterator(n, (0..n).map(|j| tau[j] - self.h[j]));
        let chol = m.cholesky().ok_or_else(|| {
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
