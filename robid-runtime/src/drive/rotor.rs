//! Rotor-dynamics compensation with a motor-side encoder (Madsen et al. 2020, eq. 14;
//! docs/identification.md#rotor-dynamics-compensation):
//! tau_J = K_r i - B thetaddot - fhat(thetadot).
//!
//! theta are the motor positions reflected through the gear ratios to the link side,
//! B the rotor inertias (link side) and fhat a friction estimate on the rotor,
//! here viscous plus Coulomb: fhat = F_v thetadot + F_c sign(thetadot).
//!
//! ## Reference
//! E. Madsen, S. A. Timm, N. A. Ujfalusi, O. S. Rosenlund, D. Brandt, X. Zhang,
//! "Dynamics parametrization and calibration of flexible-joint collaborative industrial
//! robot manipulators", Mathematical Problems in Engineering, 2020.

use serde::{Deserialize, Serialize};

use crate::data::PerJoint;
use crate::error::Result;
use crate::signal::Signals;

/// The `[drive.rotor]` table: known rotor inertias and rotor friction estimate.
///
/// ```toml
/// [drive.rotor]
/// inertia = [0.1, 0.1, 0.1, 0.02, 0.02, 0.02]   # B, kg m^2 reflected to the link side
/// viscous = 0.0                                  # F_v of fhat
/// coulomb = 0.0                                  # F_c of fhat
/// ```
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RotorConfig {
    /// B.
    pub inertia: PerJoint,
    /// Viscous rotor friction.
    pub viscous: Option<PerJoint>,
    /// Coulomb rotor friction.
    pub coulomb: Option<PerJoint>,
}

impl RotorConfig {
    /// Checks the sizes.
    pub fn check(&self, dof: usize) -> Result<()> {
        self.inertia.values(dof, "drive.rotor.inertia")?;
        if let Some(v) = &self.viscous {
            v.values(dof, "drive.rotor.viscous")?;
        }
        if let Some(c) = &self.coulomb {
            c.values(dof, "drive.rotor.coulomb")?;
        }
        Ok(())
    }

    /// Subtracts B thetaddot + fhat(thetadot) from the torques in place (per joint signals).
    pub fn compensate(&self, tau: &mut Signals, thetad: &Signals, thetadd: &Signals) -> Result<()> {
        let dof = tau.dof();
        let b = self.inertia.values(dof, "drive.rotor.inertia")?;
        let fv = match &self.viscous {
            Some(v) => v.values(dof, "drive.rotor.viscous")?,
            None => vec![0.0; dof],
        };
        let fc = match &self.coulomb {
            Some(v) => v.values(dof, "drive.rotor.coulomb")?,
            None => vec![0.0; dof],
        };
        for (j, tj) in tau.joints_mut().enumerate() {
            for ((t, w), a) in tj.iter_mut().zip(&thetad[j]).zip(&thetadd[j]) {
                *t -= b[j] * a + fv[j] * w + fc[j] * crate::Real::sign(*w);
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn subtracts_rotor_inertia_and_friction() {
        let cfg = RotorConfig {
            inertia: PerJoint::Each(vec![2.0, 0.5]),
            viscous: Some(PerJoint::All(0.1)),
            coulomb: Some(PerJoint::All(1.0)),
        };
        let signals = |x: [[f64; 2]; 2]| Signals::new(x.map(Vec::from).to_vec()).unwrap();
        let mut tau = signals([[10.0, 10.0], [1.0, 1.0]]);
        cfg.compensate(
            &mut tau,
            &signals([[1.0, -1.0], [0.0, 2.0]]),
            &signals([[3.0, 0.0], [2.0, 0.0]]),
        )
        .unwrap();
        let expected = [[2.9, 11.1], [0.0, -0.2]];
        for (t, e) in tau.joints().zip(expected) {
            assert!(t.iter().zip(e).all(|(a, b)| (a - b).abs() < 1e-12), "{t:?}");
        }
        assert!(cfg.check(3).is_err());
    }
}
