//! A nonlinear friction model of the rotor of a strain-wave (harmonic-drive) joint, the
//! `fhat` of the rotor-dynamics compensation (docs/identification.md#nonlinear-rotor-friction):
//!
//! ```text
//! f(w, tl, T) = s(w) (Fc + Fl |tl| + Fs exp(-(w/ws)^2)) exp(-kc (T - T0))
//!             + Fv w exp(-kv (T - T0)),          s(w) = tanh(w / eps)
//! ```
//!
//! with `w` the rotor velocity reflected to the link side (rad/s), `tl` the load torque,
//! the joint torque `tau_J` (N m), and `T` the temperature (deg C). The Coulomb level rises
//! linearly with the load torque, as the tooth contact force of the gear does (Bittencourt
//! and Gunnarsson 2012; Madsen, Rosenlund, Brandt and Zhang 2020 for strain-wave gears);
//! the Stribeck term adds the static friction that falls off with velocity
//! (Armstrong-Helouvry 1991); the Coulomb and viscous levels fall with temperature as the
//! lubricant's viscosity does (Bittencourt and Gunnarsson 2012). `s` is a smooth sign: it
//! keeps the model differentiable for the fit and bounded through a velocity reversal,
//! and simulation and identification share its `eps` (`smoothing`, default
//! [`DEFAULT_SMOOTHING`]). References in docs/references.md.
//!
//! The parameters of one joint are a [`JointFriction`], those of a robot a
//! [`FrictionModel`], written as a TOML file of `[[friction]]` tables; `fit` identifies
//! a joint's parameters from samples by nonlinear least squares ([`identify_friction`]).

mod fit;

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::data::{DataError, KeyMap, TomlFile};
use crate::error::{Error, Result, num};
use crate::limits::{MAX_PARAMETER, MAX_TEMPERATURE, MAX_TORQUE, MAX_VELOCITY};
use crate::{Count, Num};

pub use fit::{
    FixedParameter, FrictionFit, FrictionFitOptions, FrictionParameter, FrictionSample,
    LOAD_SPREAD, TEMPERATURE_SPREAD, identify_friction, widest_smoothing,
};

/// The default `eps` of the smooth sign `tanh(w / eps)`, rad/s: at 0.01 rad/s (a slow
/// joint motion) the sign is within 5e-9 of 1, while a velocity reversal stays smooth.
pub const DEFAULT_SMOOTHING: f64 = 1e-3;

/// The largest accepted magnitude of a temperature coefficient, 1/K: one Kelvin changing
/// the friction by a factor e is no lubricant (real ones are near 0.01/K), and the bound
/// keeps `exp(-k (T - T0))` finite over any plausible temperature.
pub const TEMPERATURE_COEFFICIENT_LIMIT: f64 = 1.0;

/// The lowest temperature, deg C.
const ABSOLUTE_ZERO: f64 = -273.15;

fn default_smoothing() -> f64 {
    DEFAULT_SMOOTHING
}

/// The friction parameters of one joint's rotor (see the module documentation for the
/// equation). Units: N m, rad/s, deg C.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JointFriction {
    /// `Fc`, the Coulomb level at no load, N m (not negative).
    pub coulomb: f64,
    /// `Fl`, the rise of the Coulomb level per N m of load torque (dimensionless, in
    /// [0, 1): below 1 the compensation's implicit equation has one solution).
    pub load: f64,
    /// `Fs`, the Stribeck (static) excess at rest, N m (not negative).
    pub stribeck: f64,
    /// `ws`, the Stribeck velocity, rad/s (positive).
    pub stribeck_velocity: f64,
    /// `Fv`, the viscous coefficient, N m s/rad (not negative).
    pub viscous: f64,
    /// `kc`, the fall of the Coulomb and Stribeck terms per Kelvin, 1/K.
    pub coulomb_temperature: f64,
    /// `kv`, the fall of the viscous term per Kelvin, 1/K.
    pub viscous_temperature: f64,
    /// `T0`, the temperature at which `Fc`, `Fs`, `Fv` hold, deg C.
    pub reference_temperature: f64,
    /// `eps` of the smooth sign `tanh(w / eps)`, rad/s (positive).
    #[serde(default = "default_smoothing")]
    pub smoothing: f64,
}

impl JointFriction {
    /// The friction at rotor velocity `w` (rad/s), load torque `tl` (N m) and temperature
    /// `temperature` (deg C).
    pub fn evaluate(&self, w: f64, tl: f64, temperature: f64) -> f64 {
        let (odd, even) = self.terms(w, temperature);
        odd * (self.coulomb + self.load * tl.abs() + self.stribeck_part(w)) + even
    }

    /// `s(w) exp(-kc dT)` and `Fv w exp(-kv dT)`.
    fn terms(&self, w: f64, temperature: f64) -> (f64, f64) {
        let dt = temperature - self.reference_temperature;
        let odd = (w / self.smoothing).tanh() * (-self.coulomb_temperature * dt).exp();
        let even = self.viscous * w * (-self.viscous_temperature * dt).exp();
        (odd, even)
    }

    /// `Fs exp(-(w / ws)^2)`.
    fn stribeck_part(&self, w: f64) -> f64 {
        let r = w / self.stribeck_velocity;
        self.stribeck * (-r * r).exp()
    }

    /// The joint torque `tau_J` that solves `tau_J = y - f(w, tau_J, T)`, `y` being the
    /// motor torque less the rotor inertia's (`K_r i - B thetadd`): `None` when the load
    /// slope `Fl exp(-kc (T - T0))` is not below 1 at `temperature` (then the equation may
    /// have no or two solutions).
    ///
    /// The equation is the scalar fixed point of the compensation. `f` is linear in `|tl|`
    /// with slope `b = s(w) Fl exp(-kc dT)`, `|b| < 1`, so `h(tau) = tau + f(w, tau, T) - y`
    /// increases strictly and is linear on each side of 0: its one root is
    /// `(y - a) / (1 + b)` when `y - a >= 0` and `(y - a) / (1 - b)` otherwise, with
    /// `a = f(w, 0, T)`. This is what Newton's method would converge to, in one step.
    pub fn joint_torque(&self, y: f64, w: f64, temperature: f64) -> Option<f64> {
        let (odd, even) = self.terms(w, temperature);
        let b = odd * self.load;
        if !(b.abs() < 1.0) {
            return None;
        }
        let a = odd * (self.coulomb + self.stribeck_part(w)) + even;
        let free = y - a;
        let tau = if free >= 0.0 {
            free / (1.0 + b)
        } else {
            free / (1.0 - b)
        };
        tau.is_finite().then_some(tau)
    }

    /// The first value out of range, as `(field, problem)`, each value as read (`Num`).
    pub(crate) fn problem(&self) -> Option<(&'static str, String)> {
        self.problem_shown(|v, _| Num(v))
    }

    /// [`JointFriction::problem`] of fitted values, which carry every digit of their
    /// arithmetic: each to four significant digits, or more where four would round it
    /// into its range (a `load` of 1.00000002 is not written 1).
    pub(crate) fn fitted_problem(&self) -> Option<(&'static str, String)> {
        self.problem_shown(|v, out| Num::rounded_keeping(v, 4, out))
    }

    /// The first value out of range, each written by `show(value, out_of_range)`.
    fn problem_shown(
        &self,
        show: impl Fn(f64, &dyn Fn(f64) -> bool) -> Num,
    ) -> Option<(&'static str, String)> {
        let fields = [
            ("coulomb", self.coulomb),
            ("load", self.load),
            ("stribeck", self.stribeck),
            ("stribeck_velocity", self.stribeck_velocity),
            ("viscous", self.viscous),
            ("coulomb_temperature", self.coulomb_temperature),
            ("viscous_temperature", self.viscous_temperature),
            ("reference_temperature", self.reference_temperature),
            ("smoothing", self.smoothing),
        ];
        if let Some((name, v)) = fields.iter().find(|(_, v)| !v.is_finite()) {
            return Some((name, format!("{v} is not a finite number")));
        }
        for (name, v, unit, limit) in [
            ("coulomb", self.coulomb, "N m", MAX_TORQUE),
            ("stribeck", self.stribeck, "N m", MAX_TORQUE),
            ("viscous", self.viscous, "N m s/rad", MAX_PARAMETER),
        ] {
            if v < 0.0 {
                return Some((
                    name,
                    format!(
                        "{} {unit} is negative; friction opposes the motion, give 0 or more",
                        show(v, &|r| r < 0.0)
                    ),
                ));
            }
            // a torque range's worth of friction is a unit or typing mistake (1e300 made
            // every joint torque infinite, blamed on the simulation)
            if v > limit {
                return Some((
                    name,
                    format!(
                        "{} {unit} is above {limit:e} {unit}; give the friction in SI units",
                        show(v, &|r| r > limit)
                    ),
                ));
            }
        }
        let outside = |r: f64| !(0.0..1.0).contains(&r);
        if outside(self.load) {
            return Some((
                "load",
                format!(
                    "{} must lie in [0, 1) (N m of Coulomb friction per N m of load torque; \
                     real gears are near 0.01)",
                    show(self.load, &outside)
                ),
            ));
        }
        for (name, v) in [
            ("stribeck_velocity", self.stribeck_velocity),
            ("smoothing", self.smoothing),
        ] {
            let outside = |r: f64| !(r > 0.0 && r <= MAX_VELOCITY);
            if outside(v) {
                return Some((
                    name,
                    format!(
                        "{} rad/s must lie in (0, {MAX_VELOCITY:e}] rad/s",
                        show(v, &outside)
                    ),
                ));
            }
        }
        let unreal = |r: f64| !(ABSOLUTE_ZERO..=MAX_TEMPERATURE).contains(&r);
        if unreal(self.reference_temperature) {
            return Some((
                "reference_temperature",
                format!(
                    "{} deg C is outside [{ABSOLUTE_ZERO}, {MAX_TEMPERATURE:e}] deg C; give the \
                     temperature in degrees Celsius at which the values hold",
                    show(self.reference_temperature, &unreal)
                ),
            ));
        }
        let beyond = |r: f64| r.abs() > TEMPERATURE_COEFFICIENT_LIMIT;
        for (name, v) in [
            ("coulomb_temperature", self.coulomb_temperature),
            ("viscous_temperature", self.viscous_temperature),
        ] {
            if beyond(v) {
                return Some((
                    name,
                    format!(
                        "{} 1/K is beyond +-{TEMPERATURE_COEFFICIENT_LIMIT} 1/K; give the \
                         coefficient per Kelvin (lubricants are near 0.01/K)",
                        show(v, &beyond)
                    ),
                ));
            }
        }
        None
    }
}

/// The rotor friction of every joint, joint 1 first.
///
/// ```
/// use robid_runtime::drive::FrictionModel;
///
/// let text = "\
/// [[friction]]
/// joint = 1
/// coulomb = 2.0               # Fc, N m
/// load = 0.02                 # Fl, N m per N m of load torque
/// stribeck = 1.0              # Fs, N m
/// stribeck_velocity = 0.1     # ws, rad/s
/// viscous = 3.0               # Fv, N m s/rad
/// coulomb_temperature = 0.01  # kc, 1/K
/// viscous_temperature = 0.015 # kv, 1/K
/// reference_temperature = 35.0
/// ";
/// let model = FrictionModel::from_toml_str(text, "friction.toml".as_ref()).unwrap();
/// // fast and at the reference temperature: Coulomb, load and viscous terms
/// let f = model.evaluate(0, 2.0, 10.0, 35.0);
/// assert!((f - (2.0 + 0.02 * 10.0 + 3.0 * 2.0)).abs() < 1e-9);
/// // the joint torque that the compensation finds: tau_J = y - f(w, tau_J, T)
/// let tau = model.joint_torque(0, 50.0, 2.0, 35.0).unwrap();
/// assert!((tau - (50.0 - model.evaluate(0, 2.0, tau, 35.0))).abs() < 1e-12);
/// let back = FrictionModel::from_toml_str(&model.to_toml_string(), "f.toml".as_ref());
/// assert_eq!(back.unwrap(), model);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct FrictionModel {
    joints: Vec<JointFriction>,
}

/// The file form: `[[friction]]` tables with a joint number.
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct File {
    friction: Vec<Row>,
}

/// One `[[friction]]` table: a [`JointFriction`] and its joint (from 1).
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct Row {
    joint: usize,
    coulomb: f64,
    load: f64,
    stribeck: f64,
    stribeck_velocity: f64,
    viscous: f64,
    coulomb_temperature: f64,
    viscous_temperature: f64,
    reference_temperature: f64,
    #[serde(default = "default_smoothing")]
    smoothing: f64,
}

impl Row {
    fn new(joint: usize, f: &JointFriction) -> Row {
        Row {
            joint,
            coulomb: f.coulomb,
            load: f.load,
            stribeck: f.stribeck,
            stribeck_velocity: f.stribeck_velocity,
            viscous: f.viscous,
            coulomb_temperature: f.coulomb_temperature,
            viscous_temperature: f.viscous_temperature,
            reference_temperature: f.reference_temperature,
            smoothing: f.smoothing,
        }
    }

    fn friction(&self) -> JointFriction {
        JointFriction {
            coulomb: self.coulomb,
            load: self.load,
            stribeck: self.stribeck,
            stribeck_velocity: self.stribeck_velocity,
            viscous: self.viscous,
            coulomb_temperature: self.coulomb_temperature,
            viscous_temperature: self.viscous_temperature,
            reference_temperature: self.reference_temperature,
            smoothing: self.smoothing,
        }
    }
}

impl FrictionModel {
    /// A model of `joints` (joint 1 first), checked (see [`FrictionModel::check`]).
    pub fn new(joints: Vec<JointFriction>) -> Result<FrictionModel> {
        let model = FrictionModel { joints };
        model.check()?;
        Ok(model)
    }

    /// Refuses a model without joints, and any value that is not finite or out of range,
    /// naming the joint and the field: `coulomb` or `stribeck` outside [0, 1e7] N m,
    /// `viscous` outside [0, 1e6] N m s/rad, `load` outside [0, 1), `stribeck_velocity` or
    /// `smoothing` outside (0, 1e6] rad/s, a temperature coefficient beyond
    /// +-[`TEMPERATURE_COEFFICIENT_LIMIT`], `reference_temperature` outside [-273.15, 1e3]
    /// deg C.
    pub fn check(&self) -> Result<()> {
        if self.joints.is_empty() {
            return Err(Error::setting(
                "FrictionModel",
                "joints",
                "is empty; give the friction of every joint",
            ));
        }
        for (j, f) in self.joints.iter().enumerate() {
            if let Some((field, problem)) = f.problem() {
                return Err(Error::setting(
                    "FrictionModel",
                    &format!("friction[{}].{field}", j + 1),
                    format!("joint {}: {problem}", j + 1),
                ));
            }
        }
        Ok(())
    }

    /// The number of joints.
    pub fn dof(&self) -> usize {
        self.joints.len()
    }

    /// The parameters of every joint, joint 1 first.
    pub fn joints(&self) -> &[JointFriction] {
        &self.joints
    }

    /// The parameters of `joint` (from 0), if the model has it.
    pub fn joint(&self, joint: usize) -> Option<&JointFriction> {
        self.joints.get(joint)
    }

    /// The friction of `joint` (from 0) at rotor velocity `w` (rad/s), load torque `tl`
    /// (N m) and temperature `temperature` (deg C); 0 for a joint the model does not have
    /// (see [`FrictionModel::dof`]).
    pub fn evaluate(&self, joint: usize, w: f64, tl: f64, temperature: f64) -> f64 {
        self.joints
            .get(joint)
            .map_or(0.0, |f| f.evaluate(w, tl, temperature))
    }

    /// The joint torque of `joint` (from 0) that solves `tau_J = y - f(w, tau_J, T)` (see
    /// [`JointFriction::joint_torque`]); an error names the joint when the model has no
    /// such joint or the load slope reaches 1 at this temperature.
    pub fn joint_torque(&self, joint: usize, y: f64, w: f64, temperature: f64) -> Result<f64> {
        let f = self.joints.get(joint).ok_or_else(|| {
            Error::setting(
                "FrictionModel::joint_torque",
                "joint",
                format!(
                    "joint {} is not in the model of {}",
                    joint + 1,
                    Count(self.joints.len(), "joint")
                ),
            )
        })?;
        f.joint_torque(y, w, temperature)
            .ok_or_else(|| Error::NonFiniteResult {
                what: format!(
                    "the joint torque of joint {} at {} deg C",
                    joint + 1,
                    num(temperature)
                ),
                cause: format!(
                    "the load slope Fl exp(-kc (T - T0)) = {} exp({}) is not below 1 here; check \
                 `load` and `coulomb_temperature` of the friction model and the temperature",
                    num(f.load),
                    // computed: every digit of -0.30000000000000004 says no more than -0.3
                    Num::rounded(
                        -f.coulomb_temperature * (temperature - f.reference_temperature),
                        4
                    )
                ),
            })
    }

    /// Parses `[[friction]]` tables (one per joint, `joint = 1 ..`, in any order, every
    /// joint from 1 to the largest once; `smoothing` may be left out); `path` names the
    /// text in errors, which give file:line:column.
    pub fn from_toml_str(text: &str, path: &Path) -> Result<FrictionModel> {
        let file: File = toml::from_str(text)
            .map_err(|e| crate::toml_syntax::syntax_error(text, path, TomlFile::Friction, &e))?;
        let keys = KeyMap::parse(text);
        let at = |position: usize, field: &str, problem: String| {
            let key = format!("friction[{position}].{field}");
            let (line, column) = keys.find(&key).unzip();
            Error::Data(DataError::ConfigKey {
                path: path.to_path_buf(),
                line,
                column,
                key,
                problem,
            })
        };
        let n = file.friction.len();
        let mut joints: Vec<Option<JointFriction>> = vec![None; n];
        for (i, row) in file.friction.iter().enumerate() {
            let position = i + 1;
            if !(1..=n).contains(&row.joint) {
                return Err(at(
                    position,
                    "joint",
                    format!(
                        "{} is not a joint from 1 to {n} (the number of [[friction]] tables); \
                         give one table per joint",
                        row.joint
                    ),
                ));
            }
            let slot = &mut joints[row.joint - 1];
            if slot.is_some() {
                return Err(at(
                    position,
                    "joint",
                    format!("joint {} has a second table; give one per joint", row.joint),
                ));
            }
            let f = row.friction();
            if let Some((field, problem)) = f.problem() {
                return Err(at(
                    position,
                    field,
                    format!("joint {}: {problem}", row.joint),
                ));
            }
            *slot = Some(f);
        }
        if n == 0 {
            return Err(Error::Data(DataError::ConfigKey {
                path: path.to_path_buf(),
                line: None,
                column: None,
                key: "friction".into(),
                problem: "no [[friction]] table; give one per joint".into(),
            }));
        }
        // n tables, each joint from 1 to n at most once: every slot is filled
        Ok(FrictionModel {
            joints: joints.into_iter().flatten().collect(),
        })
    }

    /// The model as `[[friction]]` tables, joint 1 first (read back exactly by
    /// [`FrictionModel::from_toml_str`]).
    pub fn to_toml_string(&self) -> String {
        let file = File {
            friction: self
                .joints
                .iter()
                .enumerate()
                .map(|(j, f)| Row::new(j + 1, f))
                .collect(),
        };
        let body = toml::to_string(&file).unwrap_or_default();
        format!(
            "# Rotor friction per joint (docs/identification.md#nonlinear-rotor-friction):\n\
             # f = tanh(w/smoothing) (coulomb + load |tau_J| + stribeck exp(-(w/stribeck_velocity)^2))\n\
             #     exp(-coulomb_temperature (T - reference_temperature))\n\
             #   + viscous w exp(-viscous_temperature (T - reference_temperature))\n\
             # units: N m, rad/s (link side), deg C\n\n{body}"
        )
    }

    /// Reads a friction file (see [`FrictionModel::from_toml_str`]).
    pub fn read(path: &Path) -> Result<FrictionModel> {
        let text = crate::data::read_text(path, "friction file")?;
        FrictionModel::from_toml_str(&text, path)
    }

    /// Writes the model to `path` atomically (see [`crate::output::write_atomically`]).
    pub fn write(&self, path: &Path) -> Result<()> {
        crate::output::write_bytes(path, self.to_toml_string().as_bytes())
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;

    /// The parameters of the synthetic tests (plausible for a small strain-wave joint).
    pub(in crate::drive) fn truth() -> JointFriction {
        JointFriction {
            coulomb: 2.0,
            load: 0.02,
            stribeck: 1.0,
            stribeck_velocity: 0.1,
            viscous: 3.0,
            coulomb_temperature: 0.01,
            viscous_temperature: 0.015,
            reference_temperature: 35.0,
            smoothing: DEFAULT_SMOOTHING,
        }
    }

    #[test]
    fn evaluates_the_equation() {
        let f = truth();
        // w = 0.1 = ws, tl = -20, T = 45: dT = 10
        let s = (0.1_f64 / 1e-3).tanh();
        let by_hand = s * (2.0 + 0.02 * 20.0 + 1.0 * (-1.0_f64).exp()) * (-0.1_f64).exp()
            + 3.0 * 0.1 * (-0.15_f64).exp();
        assert!((f.evaluate(0.1, -20.0, 45.0) - by_hand).abs() < 1e-12);
        // by hand to 6 digits: 2.767879 * 0.904837 + 0.3 * 0.860708 = 2.504480 + 0.258212;
        // the last digit is rounded, half a unit is 5e-7 (measured 2.8e-7)
        assert!((f.evaluate(0.1, -20.0, 45.0) - 2.762693).abs() < 5e-7);
        // odd in w, even in tl; at rest 0
        assert_eq!(f.evaluate(-0.1, 20.0, 45.0), -f.evaluate(0.1, -20.0, 45.0));
        assert_eq!(f.evaluate(0.0, 20.0, 45.0), 0.0);
        // within the smoothing the sign is not yet 1: tanh(1) of the static level
        let static_level = 2.0 + 1.0 * (-1e-4_f64).exp();
        assert!(
            (f.evaluate(1e-3, 0.0, 35.0) - (1.0_f64.tanh() * static_level + 3e-3)).abs() < 1e-12
        );
    }

    #[test]
    fn the_joint_torque_solves_the_implicit_equation() {
        let f = truth();
        let mut rng = crate::rng::Rng::new(3);
        let mut worst = 0.0_f64;
        for _ in 0..2000 {
            let (y, w, t) = (
                rng.uniform(-80.0, 80.0),
                rng.uniform(-3.0, 3.0) * rng.unit().powi(3),
                rng.uniform(0.0, 60.0),
            );
            let tau = f.joint_torque(y, w, t).unwrap();
            let error = (tau - (y - f.evaluate(w, tau, t))).abs();
            worst = worst.max(error);
        }
        // measured 1.4e-14 (rounding of torques up to 80 N m)
        assert!(worst < 1e-12, "{worst}");
        // a load slope of 1 has no unique solution
        let steep = JointFriction {
            load: 0.99,
            coulomb_temperature: 0.5,
            ..f
        };
        assert!(steep.joint_torque(10.0, 1.0, 0.0).is_none());
        let model = FrictionModel::new(vec![steep]).unwrap();
        let e = model
            .joint_torque(0, 10.0, 1.0, 0.0)
            .unwrap_err()
            .to_string();
        assert!(e.contains("joint 1") && e.contains("load slope"), "{e}");
        // the exponent, computed, to four digits (it was -0.30000000000000004 here); the
        // temperature as given
        let warm = JointFriction {
            load: 0.99,
            coulomb_temperature: -0.1,
            reference_temperature: 0.1,
            ..f
        };
        let e = FrictionModel::new(vec![warm])
            .unwrap()
            .joint_torque(0, 10.0, 1.0, 3.1)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("of joint 1 at 3.1 deg C") && e.contains("= 0.99 exp(0.3) is not below 1"),
            "{e}"
        );
    }

    /// Values read are written as read; fitted ones to four digits, but never rounded into
    /// their range.
    #[test]
    fn a_fitted_value_out_of_range_is_written_short() {
        let good = truth();
        let load = JointFriction {
            load: 1.0123456789012344,
            ..good
        };
        assert_eq!(
            load.problem().unwrap().1,
            "1.0123456789012344 must lie in [0, 1) (N m of Coulomb friction per N m of load \
             torque; real gears are near 0.01)"
        );
        assert!(
            load.fitted_problem()
                .unwrap()
                .1
                .starts_with("1.012 must lie")
        );
        let hot = JointFriction {
            coulomb_temperature: 1.000000012345679,
            ..good
        };
        assert!(
            hot.fitted_problem()
                .unwrap()
                .1
                .starts_with("1.00000001 1/K is beyond +-1 1/K"),
            "{:?}",
            hot.fitted_problem()
        );
        let negative = JointFriction {
            viscous: -0.0123456789,
            ..good
        };
        assert!(
            negative
                .fitted_problem()
                .unwrap()
                .1
                .starts_with("-0.01235 N m s/rad")
        );
    }

    #[test]
    fn check_names_the_joint_and_the_field() {
        let good = truth();
        let cases = [
            (
                JointFriction {
                    coulomb: -1.0,
                    ..good
                },
                "friction[2].coulomb",
            ),
            (
                JointFriction {
                    viscous: f64::NAN,
                    ..good
                },
                "friction[2].viscous",
            ),
            (JointFriction { load: 1.0, ..good }, "friction[2].load"),
            (
                JointFriction {
                    stribeck_velocity: 0.0,
                    ..good
                },
                "friction[2].stribeck_velocity",
            ),
            (
                JointFriction {
                    smoothing: -1e-3,
                    ..good
                },
                "friction[2].smoothing",
            ),
            (
                JointFriction {
                    viscous_temperature: 2.0,
                    ..good
                },
                "friction[2].viscous_temperature",
            ),
            (
                JointFriction {
                    viscous: 2e6,
                    ..good
                },
                "friction[2].viscous",
            ),
            (
                JointFriction {
                    stribeck: 2e7,
                    ..good
                },
                "friction[2].stribeck",
            ),
            (
                JointFriction {
                    reference_temperature: -300.0,
                    ..good
                },
                "friction[2].reference_temperature",
            ),
        ];
        for (bad, key) in cases {
            let e = FrictionModel::new(vec![good, bad]).unwrap_err().to_string();
            assert!(e.contains(key) && e.contains("joint 2"), "{e}");
        }
        // the limits themselves are accepted
        let edge = JointFriction {
            coulomb: 1e7,
            viscous: 1e6,
            reference_temperature: -273.15,
            ..good
        };
        assert!(FrictionModel::new(vec![edge]).is_ok());
        assert!(FrictionModel::new(vec![]).is_err());
        assert!(FrictionModel::new(vec![good]).is_ok());
    }

    #[test]
    fn toml_round_trip_and_file_errors() {
        let second = JointFriction {
            coulomb: 0.1 + 0.2, // not a short decimal: written exactly all the same
            smoothing: 2e-3,
            ..truth()
        };
        let model = FrictionModel::new(vec![truth(), second]).unwrap();
        let text = model.to_toml_string();
        let back = FrictionModel::from_toml_str(&text, "f.toml".as_ref()).unwrap();
        assert_eq!(back, model);

        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("friction.toml");
        model.write(&path).unwrap();
        assert_eq!(FrictionModel::read(&path).unwrap(), model);

        // joints in any order; smoothing defaults
        let row = |j: usize, coulomb: &str| {
            format!(
                "[[friction]]\njoint = {j}\ncoulomb = {coulomb}\nload = 0.0\nstribeck = 0.0\n\
                 stribeck_velocity = 1.0\nviscous = 0.5\ncoulomb_temperature = 0.0\n\
                 viscous_temperature = 0.0\nreference_temperature = 25.0\n"
            )
        };
        let swapped = format!("{}{}", row(2, "3.0"), row(1, "1.0"));
        let m = FrictionModel::from_toml_str(&swapped, "f.toml".as_ref()).unwrap();
        assert_eq!(m.joints()[0].coulomb, 1.0);
        assert_eq!(m.joints()[1].coulomb, 3.0);
        assert_eq!(m.joints()[1].smoothing, DEFAULT_SMOOTHING);

        let error = |text: String| {
            FrictionModel::from_toml_str(&text, "f.toml".as_ref())
                .unwrap_err()
                .to_string()
        };
        // a negative value: file, line and column of the key, the joint
        let e = error(format!("{}{}", row(1, "1.0"), row(2, "-3.0")));
        assert!(
            e.starts_with("f.toml:13:1: `friction[2].coulomb`: joint 2"),
            "{e}"
        );
        // beyond the ranges of real friction, at the key (1e300 made the torques infinite,
        // blamed on the simulation; a reference of 1e4 deg C overflowed exp(-k (T - T0)))
        let e = error(format!("{}{}", row(1, "1.0"), row(2, "1e300")));
        assert!(
            e.starts_with("f.toml:13:1: `friction[2].coulomb`: joint 2: 1e300 N m is above 1e7"),
            "{e}"
        );
        let hot = row(1, "1.0").replace("25.0", "1e4");
        let e = error(hot);
        assert!(
            e.starts_with("f.toml:10:1: `friction[1].reference_temperature`: joint 1: 10000 deg C is outside [-273.15, 1e3]"),
            "{e}"
        );
        let e = error(row(1, "1.0").replace("stribeck_velocity = 1.0", "stribeck_velocity = 1e7"));
        assert!(e.contains("`friction[1].stribeck_velocity`"), "{e}");
        let e = error(format!("{}{}", row(1, "1.0"), row(1, "1.0")));
        assert!(e.contains("second table"), "{e}");
        let e = error(format!("{}{}", row(1, "1.0"), row(3, "1.0")));
        assert!(
            e.contains("`friction[2].joint`") && e.contains("from 1 to 2"),
            "{e}"
        );
        let e = error(format!("{}colour = 1\n", row(1, "1.0")));
        assert!(e.contains("colour"), "{e}");
        assert!(error(String::new()).contains("friction"));
        let missing = row(1, "1.0").replace("load = 0.0\n", "");
        assert!(error(missing).contains("load"));
    }
}
