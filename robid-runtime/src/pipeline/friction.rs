//! Rotor friction samples from a two-encoder log, for [`crate::drive::identify_friction`]
//! (docs/identification.md#nonlinear-rotor-friction): Madsen et al.'s eq. 14 solved for
//! the friction, `f = K_r i - B thetaddot - tau_J`, per joint and sample.
//!
//! `K_r i` is the configured torque through the drive chain (link side), B the inertias
//! of `[drive.rotor]`, thetadot and thetaddot the reflected motor encoders differentiated
//! as the rotor compensation does, and tau_J either the `joint_torque` columns (a
//! joint-torque sensor) or the rigid model's inverse dynamics
//! on the link-side states. The load of the friction model is tau_J; its temperature
//! the `temperature` columns, else [`REFERENCE_TEMPERATURE`] throughout.

use crate::Model;
use crate::data::{Config, Dataset, DerivativeAgreement};
use crate::drive::{FrictionSample, RotorConfig};
use crate::error::{Error, Result};
use crate::pipeline::prepare::{Rows, prepare_rows};
use crate::signal::Signals;

/// The temperature (deg C) of every sample of a log without `temperature` columns: the
/// fit then holds the temperature coefficients at 0 (a spread of 0 K), and the model
/// holds at any temperature.
pub const REFERENCE_TEMPERATURE: f64 = 25.0;

/// Where tau_J came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JointTorqueSource {
    /// The `joint_torque` columns of the data.
    Measured,
    /// The rigid model's inverse dynamics with given parameters.
    Model,
}

/// What [`friction_samples`] gives.
#[derive(Debug, Clone)]
pub struct FrictionData {
    /// The samples of each joint, joint 1 first.
    pub samples: Vec<Vec<FrictionSample>>,
    /// Where tau_J came from.
    pub joint_torque: JointTorqueSource,
    /// Whether the data have `temperature` columns (else [`REFERENCE_TEMPERATURE`]).
    pub temperature_measured: bool,
    /// What the data say against themselves, which the fit would take as friction: a
    /// motor encoder that does not move with its link encoder through the gear ratio (a
    /// ratio of the wrong sign, motor positions in degrees), a joint-torque column of one
    /// value while the joint moves (a dead sensor).
    pub warnings: Vec<String>,
}

/// The friction samples of `data` (estimation range and trim of `config`): tau_J from the
/// inverse dynamics of `model` with the base parameters `base` when given, else from the
/// data's `joint_torque` columns.
///
/// Errors: no `[drive.rotor]` (B is needed), no motor encoders, neither `joint_torque`
/// columns nor a model, and whatever [`crate::pipeline::prepare`] refuses.
pub fn friction_samples(
    data: &Dataset,
    config: &Config,
    model: Option<(&dyn Model, &[f64])>,
) -> Result<FrictionData> {
    let rotor = config.drive.rotor.as_ref().ok_or_else(|| {
        config.key_error(
            "drive.rotor",
            "the friction is what the motor torque leaves after the rotor inertia's and the \
             joint's: add [drive.rotor] with inertia = [...] (B, link side; 0 when unknown)",
        )
    })?;
    // only B thetaddot is subtracted here: the friction is what is being measured
    let mut bare = config.clone();
    bare.drive.rotor = Some(RotorConfig {
        inertia: rotor.inertia.clone(),
        viscous: None,
        coulomb: None,
        friction: None,
        residual: None,
    });
    bare.extra_columns.clear();
    // The friction is not linear in the rotor speed: its sign turns within a few mrad/s,
    // and a low-pass on the torque (or a decimation's anti-alias filter) would smear each
    // reversal over the filter's length, biasing the fit near zero speed (a 10 Hz
    // low-pass on the torque made the UR5e's identified friction 2.9 % wrong against 0.2 %
    // without, tests/tests/suite/flexible_ur5e.rs). Only the positions are filtered here,
    // and every sample is kept.
    if let Some(lowpass) = &mut bare.processing.lowpass {
        lowpass.signals.retain(|s| *s == crate::data::Signal::Q);
        if lowpass.signals.is_empty() {
            bare.processing.lowpass = None;
        }
    }
    bare.processing.decimation = crate::data::Decimation::default();
    let rows = prepare_rows(data, &bare, Rows::Estimation).map_err(|e| config.locate(e))?;
    let p = &rows.prepared;
    let dof = data.dof();
    let states = p.rotor.as_ref().ok_or_else(|| {
        config.key_error(
            "drive.rotor",
            "the data has no `motor_position` columns; add motor_position = [...] to a [[source]]",
        )
    })?;
    let n = p.samples();
    let (tau_j, source) = match (model, &states.joint_torque) {
        (Some((model, base)), _) => {
            let mut out = crate::signal::Signals::zeros(dof, n);
            let (mut q, mut qd, mut qdd, mut tau) = (
                vec![0.0; dof],
                vec![0.0; dof],
                vec![0.0; dof],
                vec![0.0; dof],
            );
            for k in 0..n {
                p.q.sample_into(k, &mut q);
                p.qd.sample_into(k, &mut qd);
                p.qdd.sample_into(k, &mut qdd);
                model.inverse_dynamics_into(&q, &qd, &qdd, base, &mut tau)?;
                for j in 0..dof {
                    out[j][k] = tau[j];
                }
            }
            (out, JointTorqueSource::Model)
        }
        (None, Some(t)) => (t.clone(), JointTorqueSource::Measured),
        (None, None) => {
            return Err(config.key_error(
                "source",
                "no joint torque: add joint_torque = [...] (a joint-torque sensor, link side, \
                 N m) to a [[source]], or give the rigid model's parameters (--parameters)",
            ));
        }
    };
    let mut warnings = encoder_warnings(&p.q, &states.thetad, p.sample_time);
    if let (Some(t), JointTorqueSource::Measured) = (&states.joint_torque, source) {
        warnings.extend(dead_joint_torques(&p.qd, t));
    }
    let mut samples = vec![Vec::with_capacity(n); dof];
    for (j, out) in samples.iter_mut().enumerate() {
        for k in 0..n {
            let sample = FrictionSample {
                velocity: states.thetad[j][k],
                load: tau_j[j][k],
                temperature: states
                    .temperature
                    .as_ref()
                    .map_or(REFERENCE_TEMPERATURE, |t| t[j][k]),
                friction: p.tau[j][k] - tau_j[j][k],
            };
            if !(sample.load.is_finite() && sample.friction.is_finite()) {
                return Err(Error::NonFiniteResult {
                    what: format!(
                        "the joint torque or friction of joint {} at {}",
                        j + 1,
                        data.location(rows.kept.start + k)
                    ),
                    cause: "the states or parameters are too large; check the data near that \
                            row and the parameter values"
                        .into(),
                });
            }
            out.push(sample);
        }
    }
    Ok(FrictionData {
        samples,
        joint_torque: source,
        temperature_measured: states.temperature.is_some(),
        warnings,
    })
}

/// A warning per joint whose motor velocities `thetad` (link side, through the gear
/// ratio) disagree with its link positions `q` sampled every `dt` seconds as a velocity
/// column disagrees with its positions ([`DerivativeAgreement::disagreement`]): the
/// joint's deflection is a small part of its motion, so the two agree within a few per
/// cent when the drive chain is right.
fn encoder_warnings(q: &Signals, thetad: &Signals, dt: f64) -> Vec<String> {
    let mut warnings = Vec::new();
    for (j, (x, w)) in q.joints().zip(thetad.joints()).enumerate() {
        let mut agreement = DerivativeAgreement::default();
        agreement.add(x, w, &|k| k as f64 * dt);
        let Some(s) = agreement.disagreement() else {
            continue;
        };
        let near = |x: f64| (s / x - 1.0).abs() < 0.02;
        let cause = if s < 0.0 {
            "of the opposite sign: is the gear ratio's sign that of the motor's direction?"
        } else if near(180.0 / std::f64::consts::PI) {
            "57.3 times: are the motor positions in degrees? they are read in motor radians"
        } else {
            "is the gear ratio the joint's? are the motor positions in motor radians?"
        };
        warnings.push(format!(
            "joint {}'s motor encoder, through its gear ratio, moves {} times its link encoder \
             ({cause}); the friction is read at the motor's speed and its torque through the \
             same ratio: check `drive.gear_ratios` and the motor_position columns",
            j + 1,
            crate::Num::rounded(s, 3)
        ));
    }
    warnings
}

/// A warning per joint whose joint-torque column `tau_j` is one value over the record
/// while its link velocities `qd` are not all 0: a dead sensor, whose zeros the fit
/// would take as the joint carrying no load.
fn dead_joint_torques(qd: &Signals, tau_j: &Signals) -> Vec<String> {
    let mut warnings = Vec::new();
    for (j, (v, t)) in qd.joints().zip(tau_j.joints()).enumerate() {
        let constant = t.iter().all(|x| *x == t[0]);
        if constant && v.iter().any(|x| *x != 0.0) {
            warnings.push(format!(
                "joint {}'s joint torque is {} over the whole record while the joint moves: a \
                 dead sensor or the wrong column (the friction would be all of the motor's \
                 torque); check the config's joint_torque columns",
                j + 1,
                crate::Num(t[0])
            ));
        }
    }
    warnings
}
