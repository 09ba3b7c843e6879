//! Gear ratios, coupling matrices and torque constants: motor side -> joint side.
//!
//! Motor positions theta_m = R_q q and joint torques tau = R_tau K_r i, where K_r
//! holds the torque constants (current -> motor torque). Both R default to
//! `diag(gear_ratios)`; a coupled wrist gives full matrices, and R_q and R_tau may differ
//! (Staubli TX40: R_q[6,5] = N6 but R_tau[5,6] = N6).

use nalgebra::DMatrix;
use serde::{Deserialize, Serialize};

use crate::Count;
use crate::data::PerJoint;
use crate::drive::RotorConfig;
use crate::error::{Error, Result};
use crate::limits::MAX_FACTOR;
use crate::signal::Signals;

/// Which side of the transmission a signal is measured on.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Side {
    /// Link side (after the gear): no conversion.
    #[default]
    Joint,
    /// Motor side (before the gear): converted with the ratios and couplings.
    Motor,
}

/// The `[drive]` table of the config.
///
/// ```toml
/// [drive]
/// position_side = "motor"
/// torque_side = "motor"
/// gear_ratios = [32, 32, 45, -48, 45, 32]
/// position_coupling = [[32,0,0,0,0,0], ..., [0,0,0,0,32,32]]   # R_q, row-major rows
/// torque_coupling = [[...], ...]                                # R_tau
/// torque_constants = [0.5, ...]    # K_r, current -> motor torque
/// [drive.rotor]                    # see RotorConfig
/// ```
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DriveConfig {
    /// Side of the position (and velocity, acceleration) columns.
    #[serde(default, deserialize_with = "crate::toml_syntax::word")]
    pub position_side: Side,
    /// Side of the torque columns.
    #[serde(default, deserialize_with = "crate::toml_syntax::word")]
    pub torque_side: Side,
    /// Gear ratios with sign (motor angle / joint angle): one for all joints or one per
    /// joint.
    pub gear_ratios: Option<PerJoint>,
    /// R_q with theta_m = R_q q (default diag(gear_ratios)).
    pub position_coupling: Option<Vec<Vec<f64>>>,
    /// R_tau with tau_joint = R_tau tau_motor (default diag(gear_ratios)).
    pub torque_coupling: Option<Vec<Vec<f64>>>,
    /// Torque constants K_r (current -> motor torque); default 1.
    pub torque_constants: Option<PerJoint>,
    /// Rotor-dynamics compensation with a motor-side encoder.
    pub rotor: Option<RotorConfig>,
}

/// The linear maps of the drive chain, ready to apply.
#[derive(Debug, Clone)]
pub struct DriveChain {
    /// q = position_inverse * theta_m (identity when positions are on the joint side).
    position_inverse: DMatrix<f64>,
    /// Inverse of R_q for motor encoders (always motor side).
    motor_inverse: DMatrix<f64>,
    /// tau = torque_map * (K_r i).
    torque_map: DMatrix<f64>,
    constants: Vec<f64>,
    dof: usize,
}

impl DriveConfig {
    /// Checks sizes and invertibility.
    pub fn check(&self, dof: usize) -> Result<()> {
        DriveChain::new(self, dof).map(|_| ())
    }

    fn ratio_matrix(
        &self,
        given: &Option<Vec<Vec<f64>>>,
        key: &str,
        dof: usize,
    ) -> Result<Option<DMatrix<f64>>> {
        let bad = |key: String, problem: String| Err(Error::setting("Config", &key, problem));
        if let Some(rows) = given {
            let key = format!("drive.{key}");
            if rows.len() != dof {
                return bad(
                    key,
                    format!(
                        "{} for a model of {}; give a {dof} x {dof} matrix",
                        Count(rows.len(), "row"),
                        Count(dof, "joint")
                    ),
                );
            }
            let mut m = DMatrix::zeros(dof, dof);
            for (i, r) in rows.iter().enumerate() {
                if r.len() != dof {
                    return bad(
                        format!("{key}[{}]", i + 1),
                        format!("{} entries; each row needs {dof}", r.len()),
                    );
                }
                for (j, v) in r.iter().enumerate() {
                    if !(v.abs() <= MAX_FACTOR) {
                        return bad(
                            format!("{key}[{}][{}]", i + 1, j + 1),
                            format!(
                                "{} is not a finite number of magnitude at most {MAX_FACTOR:e}",
                                crate::error::num(*v)
                            ),
                        );
                    }
                    m[(i, j)] = *v;
                }
            }
            return Ok(Some(m));
        }
        // (the ratios are checked by DriveChain::new)
        let ratios = self.gear_ratios.as_ref();
        Ok(ratios
            .map(|n| n.values(dof, "drive.gear_ratios"))
            .transpose()?
            .map(|n| DMatrix::from_diagonal(&nalgebra::DVector::from_vec(n))))
    }
}

impl DriveChain {
    /// Builds the maps for `dof` joints.
    pub fn new(cfg: &DriveConfig, dof: usize) -> Result<Self> {
        // checked even where both couplings replace them: a wrong count or a zero ratio
        // beside two coupling matrices was read without a word
        if let Some(n) = &cfg.gear_ratios {
            let n = n.values(dof, "drive.gear_ratios")?;
            crate::data::nonzero(n, "drive.gear_ratios")?;
        }
        let rq = cfg.ratio_matrix(&cfg.position_coupling, "position_coupling", dof)?;
        let rt = cfg.ratio_matrix(&cfg.torque_coupling, "torque_coupling", dof)?;
        let needs = |side: Side, m: &Option<DMatrix<f64>>, key: &str| -> Result<()> {
            if side == Side::Motor && m.is_none() {
                return Err(Error::setting(
                    "Config",
                    key,
                    "motor-side signals need `drive.gear_ratios` or a coupling matrix",
                ));
            }
            Ok(())
        };
        needs(cfg.position_side, &rq, "drive.position_side")?;
        needs(cfg.torque_side, &rt, "drive.torque_side")?;
        let eye = DMatrix::identity(dof, dof);
        let motor_inverse = match &rq {
            Some(m) => m.clone().try_inverse().ok_or_else(|| {
                Error::setting(
                    "Config",
                    if cfg.position_coupling.is_some() {
                        "drive.position_coupling"
                    } else {
                        "drive.gear_ratios"
                    },
                    "the position coupling R_q is singular; every joint needs a non-zero gear ratio and the coupling must be invertible",
                )
            })?,
            None => eye.clone(),
        };
        let position_inverse = if cfg.position_side == Side::Motor {
            motor_inverse.clone()
        } else {
            eye.clone()
        };
        let torque_map = match (cfg.torque_side, rt) {
            // a singular map confines the joint torques to a subspace: no drive is made so
            // ([[1, 1], [1, 1]] was taken, the fit 67 % off without a word)
            (Side::Motor, Some(m)) if m.clone().try_inverse().is_none() => {
                return Err(Error::setting(
                    "Config",
                    if cfg.torque_coupling.is_some() {
                        "drive.torque_coupling"
                    } else {
                        "drive.gear_ratios"
                    },
                    "the torque coupling R_tau is singular; every joint needs a non-zero gear ratio and the coupling must be invertible",
                ));
            }
            (Side::Motor, Some(m)) => m,
            _ => eye,
        };
        let constants = match &cfg.torque_constants {
            Some(k) => crate::data::nonzero(
                k.values(dof, "drive.torque_constants")?,
                "drive.torque_constants",
            )?,
            None => vec![1.0; dof],
        };
        if let Some(r) = &cfg.rotor {
            r.check(dof)?;
        }
        Ok(Self {
            position_inverse,
            motor_inverse,
            torque_map,
            constants,
            dof,
        })
    }

    /// Joint positions (or velocities, accelerations) from the measured ones, per joint.
    ///
    /// # Panics
    /// When `measured` does not hold one joint per joint of the chain ([`DriveChain::dof`]):
    /// a size the caller controls (the chain and the record come from one configuration,
    /// whose joint count the readers check first); an infallible map keeps the readers'
    /// chains of calls simple.
    pub fn joint_positions(&self, measured: Signals) -> Signals {
        apply(&self.position_inverse, measured, None)
    }

    /// Motor encoder positions reflected to the link side: R_q^-1 theta_m.
    ///
    /// # Panics
    /// When `motor` does not hold one joint per joint of the chain ([`DriveChain::dof`]):
    /// a size the caller controls (the chain and the record come from one configuration,
    /// whose joint count the readers check first); an infallible map keeps the readers'
    /// chains of calls simple.
    pub fn reflected_motor_positions(&self, motor: Signals) -> Signals {
        apply(&self.motor_inverse, motor, None)
    }

    /// Joint torques from the measured torques or currents: R_tau K_r i.
    ///
    /// # Panics
    /// When `measured` does not hold one joint per joint of the chain ([`DriveChain::dof`]):
    /// a size the caller controls (the chain and the record come from one configuration,
    /// whose joint count the readers check first); an infallible map keeps the readers'
    /// chains of calls simple.
    pub fn joint_torques(&self, measured: Signals) -> Signals {
        apply(&self.torque_map, measured, Some(&self.constants))
    }

    /// Number of joints.
    pub fn dof(&self) -> usize {
        self.dof
    }
}

/// out_i = sum_j m_ij * scale_j * x_j, skipping zero entries; a diagonal map works in
/// place (a long record is not copied), with the same values as the sum (`0 + c x`), and
/// leaves a joint whose factor is 1 as it is (the common chain, none configured, is the
/// identity: every block read would otherwise be passed over for nothing). The one value
/// that differs from the sum is a `-0` read from a file, which `0 + 1 * -0` made `+0`: it
/// stays `-0`, equal to `0` in every comparison.
fn apply(m: &DMatrix<f64>, x: Signals, scale: Option<&[f64]>) -> Signals {
    // a record of another joint count was read out of bounds with nalgebra's message
    assert_eq!(
        x.dof(),
        m.ncols(),
        "DriveChain: the signals have {} joints, the chain {}; build the chain for the record's joints",
        x.dof(),
        m.ncols()
    );
    let c = |i: usize, j: usize| m[(i, j)] * scale.map_or(1.0, |s| s[j]);
    let n = m.nrows();
    let diagonal =
        n == m.ncols() && n == x.dof() && (0..n).all(|i| (0..n).all(|j| i == j || c(i, j) == 0.0));
    if diagonal {
        let mut x = x;
        for (i, xi) in x.joints_mut().enumerate() {
            let ci = c(i, i);
            if ci == 1.0 {
                continue;
            }
            for v in xi.iter_mut() {
                *v = if ci != 0.0 { 0.0 + ci * *v } else { 0.0 };
            }
        }
        return x;
    }
    let mut out = Signals::zeros(n, x.samples());
    for (i, oi) in out.joints_mut().enumerate() {
        for (j, xj) in x.joints().enumerate() {
            let c = c(i, j);
            if c != 0.0 {
                for (o, v) in oi.iter_mut().zip(xj) {
                    *o += c * v;
                }
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tx40() -> DriveConfig {
        let n = [32.0, 32.0, 45.0, -48.0, 45.0, 32.0];
        let mut rq: Vec<Vec<f64>> = (0..6)
            .map(|i| (0..6).map(|j| if i == j { n[i] } else { 0.0 }).collect())
            .collect();
        let mut rt = rq.clone();
        rq[5][4] = 32.0;
        rt[4][5] = 32.0;
        DriveConfig {
            position_side: Side::Motor,
            torque_side: Side::Motor,
            gear_ratios: Some(PerJoint::Each(n.to_vec())),
            position_coupling: Some(rq),
            torque_coupling: Some(rt),
            ..Default::default()
        }
    }

    /// Signals whose sample k of joint j is (k + 1) values[j].
    fn per_joint(values: &[f64], samples: usize) -> Signals {
        Signals::from_fn(values.len(), samples, |j, k| (k + 1) as f64 * values[j])
    }

    #[test]
    fn tx40_wrist_coupling() {
        let chain = DriveChain::new(&tx40(), 6).unwrap();
        let theta = per_joint(&[32.0, 64.0, 45.0, -96.0, 90.0, 320.0], 1);
        let q = chain.joint_positions(theta.clone());
        // q_i = theta_i / N_i for i <= 5, q6 = theta6 / N6 - q5
        let expect = [1.0, 2.0, 1.0, 2.0, 2.0, 8.0];
        for (a, e) in q.joints().zip(expect) {
            assert!((a[0] - e).abs() < 1e-12);
        }
        let tm = per_joint(&[1.0, 1.0, 1.0, 1.0, 1.0, 2.0], 1);
        let tau = chain.joint_torques(tm);
        // tau_5 = N5 tm5 + N6 tm6 = 45 + 64
        let expect = [32.0, 32.0, 45.0, -48.0, 109.0, 64.0];
        for (a, e) in tau.joints().zip(expect) {
            assert!((a[0] - e).abs() < 1e-12);
        }
    }

    /// Motor encoders are reflected through R_q^-1 whatever the side of the position
    /// columns; torque constants scale the currents before R_tau.
    #[test]
    fn motor_encoders_and_torque_constants() {
        let mut c = tx40();
        c.position_side = Side::Joint;
        c.torque_constants = Some(PerJoint::Each(vec![2.0, 1.0, 1.0, 1.0, 0.5, 1.0]));
        c.check(6).unwrap();
        let chain = DriveChain::new(&c, 6).unwrap();
        assert_eq!(chain.dof(), 6);
        let theta = per_joint(&[32.0, 64.0, 45.0, -96.0, 90.0, 320.0], 2);
        // joint-side positions pass through; motor positions are reflected
        assert_eq!(chain.joint_positions(theta.clone()), theta);
        let reflected = chain.reflected_motor_positions(theta.clone());
        assert_eq!(reflected.dof(), 6);
        for (a, e) in reflected.joints().zip([1.0, 2.0, 1.0, 2.0, 2.0, 8.0]) {
            assert!(
                (a[0] - e).abs() < 1e-12 && (a[1] - 2.0 * e).abs() < 1e-12,
                "{a:?}"
            );
        }
        let current = per_joint(&[1.0, 1.0, 1.0, 1.0, 1.0, 2.0], 1);
        let tau = chain.joint_torques(current);
        assert_eq!(tau.dof(), 6);
        // tau_1 = N1 * 2 * i1; tau_5 = N5 * 0.5 * i5 + N6 * i6
        let expect = [64.0, 32.0, 45.0, -48.0, 22.5 + 64.0, 64.0];
        for (a, e) in tau.joints().zip(expect) {
            assert!((a[0] - e).abs() < 1e-12, "{a:?} vs {e}");
        }
    }

    /// No chain configured is the identity: the values are left as read, to the bit (a
    /// `-0` too, which the sum `0 + 1 * x` would make `+0`); a joint whose factor is 1 in a
    /// diagonal chain is left so as well, the others scaled.
    #[test]
    fn the_identity_leaves_the_values_as_read() {
        let chain = DriveChain::new(&DriveConfig::default(), 3).unwrap();
        let x = Signals::from_fn(3, 4, |j, k| match (j, k) {
            (0, 1) => -0.0,
            (2, 3) => f64::MIN_POSITIVE / 4.0,
            _ => (k as f64 - 1.5) * (j + 1) as f64 * 0.1,
        });
        let bits =
            |s: &Signals| -> Vec<u64> { s.joints().flatten().map(|v| v.to_bits()).collect() };
        for y in [
            chain.joint_positions(x.clone()),
            chain.joint_torques(x.clone()),
        ] {
            assert_eq!(bits(&y), bits(&x));
        }
        let diagonal = DriveConfig {
            gear_ratios: Some(PerJoint::Each(vec![1.0, 2.0, 1.0])),
            torque_side: Side::Motor,
            ..Default::default()
        };
        let tau = DriveChain::new(&diagonal, 3)
            .unwrap()
            .joint_torques(x.clone());
        let (got, read): (Vec<&[f64]>, Vec<&[f64]>) =
            (tau.joints().collect(), x.joints().collect());
        assert_eq!(got[0][1].to_bits(), (-0.0f64).to_bits());
        assert_eq!(got[2], read[2]);
        for (a, b) in got[1].iter().zip(read[1]) {
            assert_eq!(*a, 2.0 * b);
        }
    }

    /// `gear_ratios = 101` is every joint's ratio, as `torque_constants = 0.125` is every
    /// joint's constant (it was refused as "not a list").
    #[test]
    fn one_gear_ratio_is_every_joints() {
        let read = |text: &str| -> DriveConfig { toml::from_str(text).unwrap() };
        let one = read("torque_side = \"motor\"\nposition_side = \"motor\"\ngear_ratios = 101\n");
        let each = read(
            "torque_side = \"motor\"\nposition_side = \"motor\"\ngear_ratios = [101, 101, 101]\n",
        );
        let x = per_joint(&[1.0, -2.0, 3.0], 4);
        let (one, each) = (
            DriveChain::new(&one, 3).unwrap(),
            DriveChain::new(&each, 3).unwrap(),
        );
        let values = |s: Signals| -> Vec<f64> { s.joints().flatten().copied().collect() };
        let tau = values(one.joint_torques(x.clone()));
        assert_eq!(tau, values(each.joint_torques(x.clone())));
        assert_eq!(tau[..2], [101.0, 202.0]);
        assert_eq!(
            values(one.joint_positions(x.clone())),
            values(each.joint_positions(x))
        );
    }

    #[test]
    fn bad_drive_configs_are_errors() {
        let mut c = tx40();
        c.gear_ratios = Some(PerJoint::Each(vec![1.0; 5]));
        c.position_coupling = None;
        assert!(matches!(
            DriveChain::new(&c, 6),
            Err(Error::Setting { ref key, .. }) if key == "drive.gear_ratios"
        ));
        assert!(c.check(6).is_err());
        // also where both couplings replace them (read without a word)
        for ratios in [vec![1.0; 5], vec![0.0, 32.0, 45.0, -48.0, 45.0, 32.0]] {
            let mut c = tx40();
            assert!(c.position_coupling.is_some() && c.torque_coupling.is_some());
            c.gear_ratios = Some(PerJoint::Each(ratios));
            assert!(matches!(
                DriveChain::new(&c, 6),
                Err(Error::Setting { ref key, .. }) if key == "drive.gear_ratios"
            ));
        }
        let mut c = tx40();
        c.position_coupling = Some(vec![vec![0.0; 6]; 6]);
        assert!(matches!(
            DriveChain::new(&c, 6),
            Err(Error::Setting { ref key, .. }) if key == "drive.position_coupling"
        ));
        // a singular torque coupling with motor-side torques, as the position coupling
        let mut c = tx40();
        c.torque_side = Side::Motor;
        c.torque_coupling = Some(vec![vec![1.0; 6]; 6]);
        assert!(matches!(
            DriveChain::new(&c, 6),
            Err(Error::Setting { ref key, ref problem, .. })
                if key == "drive.torque_coupling" && problem.contains("R_tau is singular")
        ));
        let mut c = tx40();
        c.torque_coupling.as_mut().unwrap()[2][1] = f64::NAN;
        assert!(matches!(
            DriveChain::new(&c, 6),
            Err(Error::Setting { ref key, .. }) if key == "drive.torque_coupling[3][2]"
        ));
        let mut c = tx40();
        c.position_coupling = None;
        c.gear_ratios = Some(PerJoint::Each(vec![32.0, 0.0, 1.0, 1.0, 1.0, 1.0]));
        assert!(DriveChain::new(&c, 6).is_err());
        let c = DriveConfig {
            position_side: Side::Motor,
            ..Default::default()
        };
        assert!(matches!(DriveChain::new(&c, 6), Err(Error::Setting { .. })));
    }

    /// A record of 5 joints through a chain of 2 panicked inside nalgebra ("Matrix index
    /// out of bounds"); the documented panic names both counts and the fix.
    #[test]
    #[should_panic(expected = "the signals have 5 joints, the chain 2; build the chain")]
    fn a_record_of_another_joint_count_is_named() {
        let chain = DriveChain::new(&DriveConfig::default(), 2).unwrap();
        chain.joint_torques(Signals::zeros(5, 3));
    }
}
