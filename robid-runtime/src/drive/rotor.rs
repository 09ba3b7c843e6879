//! Rotor-dynamics compensation with a motor-side encoder (Madsen et al. 2020, eq. 14;
//! docs/identification.md#rotor-dynamics-compensation):
//! tau_J = K_r i - B thetaddot - fhat(thetadot).
//!
//! theta are the motor positions reflected through the gear ratios to the link side,
//! B the rotor inertias (link side) and fhat a friction estimate on the rotor: viscous
//! plus Coulomb, fhat = F_v thetadot + F_c sign(thetadot) ([`RotorConfig::compensate`]), or
//! the nonlinear [`FrictionModel`] of rotor velocity, load torque and temperature
//! ([`RotorConfig::compensate_nonlinear`]), whose load torque is tau_J itself.
//!
//! ## Reference
//! E. Madsen, S. A. Timm, N. A. Ujfalusi, O. S. Rosenlund, D. Brandt, X. Zhang,
//! "Dynamics parametrization and calibration of flexible-joint collaborative industrial
//! robot manipulators", Mathematical Problems in Engineering, 2020.

use serde::{Deserialize, Serialize};

use std::path::PathBuf;

use super::{FrictionModel, Residual};
use crate::data::PerJoint;
use crate::error::{Error, Result, num};
use crate::signal::Signals;

/// The `[drive.rotor]` table: known rotor inertias and rotor friction estimate.
///
/// ```toml
/// [drive.rotor]
/// inertia = [0.1, 0.1, 0.1, 0.02, 0.02, 0.02]   # B, kg m^2 reflected to the link side
/// viscous = 0.0                                  # F_v of fhat
/// coulomb = 0.0                                  # F_c of fhat
/// # friction = "friction.toml"  # or: the nonlinear fhat (a FrictionModel file), not with
/// #                             # viscous/coulomb; T from the `temperature` columns
/// residual = ["Fc", "Fv"]                        # rotor-side residual columns, see Residual
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
    /// A [`FrictionModel`] file (relative to the config file): the nonlinear rotor friction
    /// of the compensation, in place of `viscous` and `coulomb`.
    pub friction: Option<PathBuf>,
    /// Rotor-side residual columns (see [`Residual`]).
    pub residual: Option<Residual>,
}

impl RotorConfig {
    /// Checks the sizes, that the inertias are not negative, and that the friction is given
    /// once.
    pub fn check(&self, dof: usize) -> Result<()> {
        self.inertias(dof)?;
        if self.friction.is_some() {
            for (key, given) in [("viscous", &self.viscous), ("coulomb", &self.coulomb)] {
                if given.is_some() {
                    return Err(Error::setting(
                        "Config",
                        "drive.rotor.friction",
                        format!(
                            "is given with `drive.rotor.{key}`: the friction model holds the \
                             rotor friction, which would be subtracted twice; remove \
                             `drive.rotor.{key}`"
                        ),
                    ));
                }
            }
        }
        if let Some(r) = &self.residual {
            r.terms(dof)?;
        }
        self.friction(dof)?;
        Ok(())
    }

    /// B, one per joint. An inertia is a mass times a squared length, so a negative one is
    /// a typing error (a lost sign), not a drive: subtracting it would add the rotor's
    /// torque instead, and the identified inertias would absorb the difference without a
    /// warning.
    fn inertias(&self, dof: usize) -> Result<Vec<f64>> {
        let what = "kg m^2, but an inertia cannot be negative; write the rotor inertia \
                    reflected to the link side (0 for none)";
        non_negative(&self.inertia, dof, "drive.rotor.inertia", what)
    }

    /// The viscous and Coulomb coefficients of the rotor friction (0 when not given). A
    /// negative one would be friction that drives the rotor, which no bearing does.
    fn friction(&self, dof: usize) -> Result<[Vec<f64>; 2]> {
        let coefficient = |given: &Option<PerJoint>, key: &str, unit: &str| match given {
            Some(v) => non_negative(
                v,
                dof,
                key,
                &format!(
                    "{unit}, but friction cannot drive the rotor; write its size (0 for none)"
                ),
            ),
            None => Ok(vec![0.0; dof]),
        };
        Ok([
            coefficient(&self.viscous, "drive.rotor.viscous", "N m s/rad")?,
            coefficient(&self.coulomb, "drive.rotor.coulomb", "N m")?,
        ])
    }

    /// Subtracts B thetaddot + fhat(thetadot) from the torques in place (per joint signals).
    pub fn compensate(&self, tau: &mut Signals, thetad: &Signals, thetadd: &Signals) -> Result<()> {
        let dof = tau.dof();
        let b = self.inertias(dof)?;
        let [fv, fc] = self.friction(dof)?;
        for (j, tj) in tau.joints_mut().enumerate() {
            for ((t, w), a) in tj.iter_mut().zip(&thetad[j]).zip(&thetadd[j]) {
                *t -= b[j] * a + fv[j] * w + fc[j] * crate::Real::sign(*w);
            }
        }
        Ok(())
    }

    /// Subtracts B thetaddot + fhat from the torques in place with the nonlinear friction
    /// `model` (docs/identification.md#nonlinear-rotor-friction): per sample, tau_J solves
    /// `tau_J = y - f(thetadot, tau_J, T)` with `y = K_r i - B thetaddot` the torque in
    /// `tau` less the rotor inertia's, since the load torque of `f` is tau_J itself (see
    /// [`FrictionModel::joint_torque`]: exact, as `f` is linear in `|tau_J|` with slope
    /// below 1). `temperature` gives T per joint; `None` evaluates every joint at its
    /// reference temperature.
    ///
    /// Errors: `viscous` or `coulomb` given here as well (the rotor friction would be
    /// subtracted twice), a model or temperature of another joint count or length, a
    /// non-finite temperature (named by joint and sample), a load slope of 1 or more.
    pub fn compensate_nonlinear(
        &self,
        model: &FrictionModel,
        tau: &mut Signals,
        thetad: &Signals,
        thetadd: &Signals,
        temperature: Option<&Signals>,
    ) -> Result<()> {
        let dof = tau.dof();
        let b = self.inertias(dof)?;
        for (key, given) in [("viscous", &self.viscous), ("coulomb", &self.coulomb)] {
            if given.is_some() {
                return Err(Error::setting(
                    "RotorConfig",
                    key,
                    format!(
                        "is given with a nonlinear friction model, which holds the rotor \
                         friction; remove `drive.rotor.{key}`"
                    ),
                ));
            }
        }
        model.check()?;
        if model.dof() != dof {
            return Err(Error::DimensionMismatch {
                what: "joints of the rotor friction model (one per joint of the torques)".into(),
                expected: dof,
                found: model.dof(),
            });
        }
        if let Some(t) = temperature
            && t.dof() != dof
        {
            return Err(Error::DimensionMismatch {
                what: "joints of the temperatures (one per joint of the torques)".into(),
                expected: dof,
                found: t.dof(),
            });
        }
        for (j, tj) in tau.joints_mut().enumerate() {
            let samples = tj.len();
            for (what, s) in [
                ("velocities", Some(thetad)),
                ("accelerations", Some(thetadd)),
                ("temperatures", temperature),
            ] {
                if let Some(s) = s
                    && s[j].len() != samples
                {
                    return Err(Error::DimensionMismatch {
                        what: format!("rotor {what} of joint {} (one per torque sample)", j + 1),
                        expected: samples,
                        found: s[j].len(),
                    });
                }
            }
            let reference = model.joints()[j].reference_temperature;
            for (k, t) in tj.iter_mut().enumerate() {
                let temp = temperature.map_or(reference, |s| s[j][k]);
                if !temp.is_finite() {
                    return Err(Error::setting(
                        "RotorConfig::compensate_nonlinear",
                        &format!("temperature[{}][{k}]", j + 1),
                        format!(
                            "joint {} sample {k} (from 0) is {temp}; repair the temperature",
                            j + 1
                        ),
                    ));
                }
                let y = *t - b[j] * thetadd[j][k];
                *t = model.joint_torque(j, y, thetad[j][k], temp)?;
            }
        }
        Ok(())
    }
}

/// The values of `given` for `dof` joints, refused at the entry of the first negative one
/// (`key[j]`, or `key` for one number for all joints) with "joint j has VALUE `what`".
fn non_negative(given: &PerJoint, dof: usize, key: &str, what: &str) -> Result<Vec<f64>> {
    let values = given.values(dof, key)?;
    match values.iter().position(|x| *x < 0.0) {
        Some(j) => Err(Error::setting(
            "Config",
            &match given {
                PerJoint::All(_) => key.to_owned(),
                PerJoint::Each(_) => format!("{key}[{}]", j + 1),
            },
            format!("joint {} has {} {what}", j + 1, num(values[j])),
        )),
        None => Ok(values),
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
            friction: None,
            residual: None,
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

    /// A negative rotor inertia is refused at its entry (it used to be subtracted with its
    /// sign, adding the rotor's torque); zero (no rotor) is accepted.
    #[test]
    fn a_negative_rotor_inertia_is_refused_at_its_entry() {
        let with = |inertia| RotorConfig {
            inertia,
            viscous: None,
            coulomb: None,
            friction: None,
            residual: None,
        };
        with(PerJoint::Each(vec![0.0, 0.5])).check(2).unwrap();
        let e = with(PerJoint::Each(vec![0.5, -0.13])).check(2).unwrap_err();
        assert_eq!(
            e.to_string(),
            "Config `drive.rotor.inertia[2]`: joint 2 has -0.13 kg m^2, but an inertia cannot \
             be negative; write the rotor inertia reflected to the link side (0 for none)"
        );
        let e = with(PerJoint::All(-1e-300))
            .check(2)
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("Config `drive.rotor.inertia`: joint 1 has -1e-300 kg m^2"),
            "{e}"
        );
        let signals = |x: [f64; 2]| Signals::new(x.map(|v| vec![v]).to_vec()).unwrap();
        let mut tau = signals([1.0, 1.0]);
        assert!(
            with(PerJoint::Each(vec![0.5, -0.13]))
                .compensate(&mut tau, &signals([0.0, 0.0]), &signals([1.0, 1.0]))
                .is_err()
        );
        // and so are negative friction coefficients, which would drive the rotor
        let rubbing = |viscous, coulomb| RotorConfig {
            viscous,
            coulomb,
            ..with(PerJoint::All(0.1))
        };
        rubbing(Some(PerJoint::All(0.0)), Some(PerJoint::All(0.2)))
            .check(2)
            .unwrap();
        let e = rubbing(Some(PerJoint::Each(vec![0.1, -2.0])), None)
            .check(2)
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("Config `drive.rotor.viscous[2]`: joint 2 has -2 N m s/rad"),
            "{e}"
        );
        let e = rubbing(None, Some(PerJoint::All(-0.5)))
            .check(2)
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("Config `drive.rotor.coulomb`: joint 1 has -0.5 N m, but friction"),
            "{e}"
        );
    }

    #[test]
    fn nonlinear_compensation_solves_for_the_joint_torque() {
        let model = FrictionModel::new(vec![
            crate::drive::friction::tests::truth(),
            crate::drive::JointFriction {
                load: 0.05,
                ..crate::drive::friction::tests::truth()
            },
        ])
        .unwrap();
        let cfg = RotorConfig {
            inertia: PerJoint::Each(vec![2.0, 0.5]),
            viscous: None,
            coulomb: None,
            friction: None,
            residual: None,
        };
        let signals = |x: [[f64; 3]; 2]| Signals::new(x.map(Vec::from).to_vec()).unwrap();
        let measured = signals([[40.0, -30.0, 0.5], [-60.0, 5.0, 70.0]]);
        let (w, a) = (
            signals([[1.0, -0.05, 0.0], [-2.0, 0.3, 0.02]]),
            signals([[3.0, 0.0, -1.0], [2.0, -4.0, 0.0]]),
        );
        let temp = signals([[25.0, 35.0, 45.0], [30.0, 40.0, 50.0]]);
        let mut tau = measured.clone();
        cfg.compensate_nonlinear(&model, &mut tau, &w, &a, Some(&temp))
            .unwrap();
        let b = [2.0, 0.5];
        let mut worst = 0.0_f64;
        for j in 0..2 {
            for k in 0..3 {
                let y = measured[j][k] - b[j] * a[j][k];
                let f = model.evaluate(j, w[j][k], tau[j][k], temp[j][k]);
                worst = worst.max((tau[j][k] - (y - f)).abs());
            }
        }
        // measured 3.6e-15
        assert!(worst < 1e-12, "{worst}");
        // without temperatures: the reference temperature
        let mut at_reference = measured.clone();
        cfg.compensate_nonlinear(&model, &mut at_reference, &w, &a, None)
            .unwrap();
        let y = measured[0][0] - 2.0 * 3.0;
        let f = model.evaluate(0, 1.0, at_reference[0][0], 35.0);
        assert!((at_reference[0][0] - (y - f)).abs() < 1e-12);
        // the constant friction as well is refused, as is another joint count
        let both = RotorConfig {
            viscous: Some(PerJoint::All(0.1)),
            ..cfg.clone()
        };
        let e = both
            .compensate_nonlinear(&model, &mut measured.clone(), &w, &a, None)
            .unwrap_err()
            .to_string();
        assert!(e.contains("viscous"), "{e}");
        let one = FrictionModel::new(vec![model.joints()[0]]).unwrap();
        assert!(
            cfg.compensate_nonlinear(&one, &mut measured.clone(), &w, &a, None)
                .is_err()
        );
        let mut bad_temp = temp.clone();
        bad_temp.joints_mut().nth(1).unwrap()[2] = f64::NAN;
        let e = cfg
            .compensate_nonlinear(&model, &mut measured.clone(), &w, &a, Some(&bad_temp))
            .unwrap_err()
            .to_string();
        assert!(e.contains("joint 2 sample 2"), "{e}");
    }
}
