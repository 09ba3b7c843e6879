//! A two-link planar arm in a vertical plane with viscous and Coulomb friction: a small,
//! exactly known model for the unit tests of `simulate` and `excite`.

use crate::Model;
use crate::Real;
use crate::model::{LengthError, ProgramKind, check_arguments, check_length};

/// Gravity (m/s^2).
const G0: f64 = 9.81;

/// The limits the `excite` tests give the pendulum: an asymmetric range, both joints alike.
pub(crate) fn pendulum_limits() -> Vec<crate::excite::JointLimits> {
    vec![
        crate::excite::JointLimits {
            position: [-1.0, 2.0],
            velocity: 1.5,
            acceleration: 4.0,
            torque: None,
        };
        2
    ]
}

/// The planar 2R arm; `l1` is the first link's length.
#[derive(Debug)]
pub(crate) struct Pendulum {
    l1: f64,
    names: Vec<String>,
}

impl Default for Pendulum {
    fn default() -> Self {
        let names = [
            "ZZR1", "ZZ2", "MX2", "MY2", "MXR1", "MY1", "Fv1", "Fc1", "Fv2", "Fc2",
        ];
        Self {
            l1: 0.5,
            names: names.iter().map(|s| s.to_string()).collect(),
        }
    }
}

impl Pendulum {
    /// Reference base parameters (consistent: M(q) positive definite).
    pub(crate) fn base(&self) -> Vec<f64> {
        vec![1.2, 0.3, 0.5, 0.05, 3.0, -0.1, 0.6, 0.9, 0.3, 0.4]
    }
}

impl Model for Pendulum {
    fn name(&self) -> &str {
        "pendulum2"
    }
    fn dof(&self) -> usize {
        2
    }
    fn standard_parameter_count(&self) -> usize {
        10
    }
    fn standard_parameter_name(&self, index: usize) -> Option<&str> {
        self.names.get(index).map(String::as_str)
    }
    fn base_parameter_count(&self) -> usize {
        10
    }
    fn base_parameter_name(&self, index: usize) -> Option<&str> {
        self.names.get(index).map(String::as_str)
    }
    fn run(
        &self,
        program: ProgramKind,
        inputs: &[&[f64]],
        output: &mut [f64],
    ) -> Result<(), LengthError> {
        check_arguments(program, self.sizes(), inputs, output)?;
        match (program, inputs) {
            (ProgramKind::BaseRegressor, [q, qd, qdd]) => self.base_regressor(q, qd, qdd, output),
            (ProgramKind::StandardRegressor, [q, qd, qdd]) => {
                self.standard_regressor(q, qd, qdd, output)
            }
            (ProgramKind::InverseDynamics, [q, qd, qdd, base]) => {
                self.inverse_dynamics(q, qd, qdd, base, output)
            }
            (ProgramKind::MassMatrix, [q, base]) => self.mass_matrix(q, base, output),
            (ProgramKind::Gravity, [q, base]) => self.gravity(q, base, output),
            (ProgramKind::Coriolis, [q, qd, base]) => self.coriolis(q, qd, base, output),
            (ProgramKind::BaseFromStandard, [standard]) => {
                self.base_from_standard(standard, output)
            }
            _ => unreachable!("check_arguments checked the number of inputs"),
        }
    }
}

/// The programs, written by hand (`run` dispatches to them).
impl Pendulum {
    fn base_regressor(
        &self,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
        out: &mut [f64],
    ) -> Result<(), LengthError> {
        check_length("q", q, 2)?;
        check_length("qd", qd, 2)?;
        check_length("qdd", qdd, 2)?;
        let (s1, c1) = q[0].sin_cos();
        let (s2, c2) = q[1].sin_cos();
        let (s12, c12) = (q[0] + q[1]).sin_cos();
        let l = self.l1;
        let v = 2.0 * qd[0] * qd[1] + qd[1] * qd[1];
        let a = 2.0 * qdd[0] + qdd[1];
        let row1 = [
            qdd[0],
            qdd[0] + qdd[1],
            l * (c2 * a - s2 * v) + G0 * c12,
            l * (-s2 * a - c2 * v) - G0 * s12,
            G0 * c1,
            -G0 * s1,
            qd[0],
            qd[0].sign(),
            0.0,
            0.0,
        ];
        let w = qd[0] * qd[0];
        let row2 = [
            0.0,
            qdd[0] + qdd[1],
            l * (c2 * qdd[0] + s2 * w) + G0 * c12,
            l * (-s2 * qdd[0] + c2 * w) - G0 * s12,
            0.0,
            0.0,
            0.0,
            0.0,
            qd[1],
            qd[1].sign(),
        ];
        out[..10].copy_from_slice(&row1);
        out[10..20].copy_from_slice(&row2);
        Ok(())
    }
    fn standard_regressor(
        &self,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
        out: &mut [f64],
    ) -> Result<(), LengthError> {
        check_length("q", q, 2)?;
        check_length("qd", qd, 2)?;
        check_length("qdd", qdd, 2)?;
        self.base_regressor_into(q, qd, qdd, out)?;
        Ok(())
    }
    fn inverse_dynamics(
        &self,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
        base: &[f64],
        tau: &mut [f64],
    ) -> Result<(), LengthError> {
        check_length("q", q, 2)?;
        check_length("qd", qd, 2)?;
        check_length("qdd", qdd, 2)?;
        let mut y = [0.0; 20];
        self.base_regressor_into(q, qd, qdd, &mut y)?;
        for j in 0..2 {
            tau[j] = (0..10).map(|i| y[j * 10 + i] * base[i]).sum();
        }
        Ok(())
    }
    fn mass_matrix(&self, q: &[f64], p: &[f64], out: &mut [f64]) -> Result<(), LengthError> {
        check_length("q", q, 2)?;
        let (s2, c2) = q[1].sin_cos();
        let k = self.l1 * (p[2] * c2 - p[3] * s2);
        out[0] = p[0] + p[1] + 2.0 * k;
        out[1] = p[1] + k;
        out[2] = p[1] + k;
        out[3] = p[1];
        Ok(())
    }
    fn gravity(&self, q: &[f64], base: &[f64], out: &mut [f64]) -> Result<(), LengthError> {
        check_length("q", q, 2)?;
        self.inverse_dynamics_into(q, &[0.0; 2], &[0.0; 2], &base_without_friction(base), out)?;
        Ok(())
    }
    fn coriolis(
        &self,
        q: &[f64],
        qd: &[f64],
        base: &[f64],
        out: &mut [f64],
    ) -> Result<(), LengthError> {
        check_length("q", q, 2)?;
        check_length("qd", qd, 2)?;
        let p = base_without_friction(base);
        let mut g = [0.0; 2];
        self.gravity_into(q, base, &mut g)?;
        self.inverse_dynamics_into(q, qd, &[0.0; 2], &p, out)?;
        out[0] -= g[0];
        out[1] -= g[1];
        Ok(())
    }
    fn base_from_standard(&self, standard: &[f64], base: &mut [f64]) -> Result<(), LengthError> {
        base[..10].copy_from_slice(&standard[..10]);
        Ok(())
    }
}

fn base_without_friction(base: &[f64]) -> Vec<f64> {
    let mut p = base.to_vec();
    p[6..].iter_mut().for_each(|x| *x = 0.0);
    p
}

#[test]
fn mass_matrix_matches_the_regressor() {
    let p = Pendulum::default();
    let base = p.base();
    let q = [0.4, -1.1];
    let mut m = [0.0; 4];
    p.mass_matrix_into(&q, &base, &mut m).unwrap();
    let mut g = [0.0; 2];
    p.inverse_dynamics_into(&q, &[0.0; 2], &[0.0; 2], &base, &mut g)
        .unwrap();
    for k in 0..2 {
        let mut e = [0.0; 2];
        e[k] = 1.0;
        let mut t = [0.0; 2];
        p.inverse_dynamics_into(&q, &[0.0; 2], &e, &base, &mut t)
            .unwrap();
        for i in 0..2 {
            assert!((t[i] - g[i] - m[i * 2 + k]).abs() < 1e-12);
        }
    }
}
