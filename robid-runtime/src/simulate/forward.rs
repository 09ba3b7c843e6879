//! Forward dynamics from a model in base parameters.
//!
//! M(q) qdd = tau - h(q, qd), where h = c(q, qd) + g(q) + friction(qd) + offsets is the
//! inverse dynamics at zero acceleration (`Model::inverse_dynamics_into(q, qd, 0)`): the model's
//! own drive terms (Fv qd, Fc sign(qd), Fo) are therefore exactly those of the data it is
//! identified from. M(q) includes the rotor inertias Ia. The system is solved by Cholesky.

use nalgebra::{DMatrix, DVector};

use crate::Model;
use crate::error::{Error, Result};

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
    /// Fails when M(q) is not positive definite (physically inconsistent parameters).
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
        let chol = m.cholesky().ok_or_else(|| Error::Singular {
            what: format!("mass matrix M(q) of {} at q = {q:?}", self.model.name()),
            hint: "the parameters are not physically consistent; use a feasible parameter set",
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
}
