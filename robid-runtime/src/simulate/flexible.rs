//! Flexible-joint simulation: robots whose joints have a compliant transmission (a
//! strain-wave gear) between a motor with its own encoder and the link, logged as such a
//! robot logs (docs/identification.md#flexible-joint-simulation).
//!
//! Spong's model with the rotor positions reflected through the gear ratios to the link
//! side (Madsen et al. 2020, eqs. 1-2):
//!
//! ```text
//! M(q) q'' + h(q, q') = tau_J                        link (h: the rigid model's rest,
//!                                                     its own drive terms included)
//! B theta'' + f(theta', tau_J, T) + tau_J = u        rotor, u = N k i the motor torque
//! tau_J = K1 d + K3 d^3 + D d',   d = theta - q      transmission
//! ```
//!
//! The transmission stiffens with its deflection (a hardening cubic, as strain-wave gears
//! do: Tuttle and Seering 1996, Dhaouadi et al. 2003), `f` is the nonlinear rotor friction
//! of [`crate::drive::JointFriction`], `T` the temperature, warming from `start` towards
//! `end` with a time constant. A motor-side controller tracks the reference: the rigid
//! model's torque along the reference as feed-forward, the deflection that torque needs
//! added to the motor reference, the rotor's inertia and friction fed forward, and a PD
//! loop on the motor encoder with gains scaled by each joint's rotor plus link inertia.
//! Four state vectors (q, q', theta, theta') are integrated by classical Runge-Kutta with
//! enough steps per sample for the stiffest mode of the state (the transmission, the
//! friction near a reversal, the PD loop on the rotor).
//!
//! The log holds the link encoder `q`, the motor encoder `theta_m = N theta` (motor
//! radians), the motor current `i`, the temperature `T`, and (for checking) the true joint
//! torque `tau_J`.

use std::path::{Path, PathBuf};

use serde::Deserialize;

use super::run::{
    MAX_SPLIT, StepBudget, bandwidth_cause, quintic, reach, rk4_step, split_for, too_stiff,
};
use super::{ForwardDynamics, Simulation, Trajectory};
use crate::Model;
use crate::SimulateError;
use crate::data::{DataError, KeyMap, TomlFile};
use crate::drive::{FrictionModel, JointFriction};
use crate::error::{Error, Result, num};
use crate::excite::check_parameters;
use crate::limits::{MAX_POSITION, MAX_TORQUE, MAX_VELOCITY, MIN_FACTOR};
use crate::progress::Progress;
use crate::rng::Rng;
use crate::signal::Signals;

/// One joint's transmission, rotor and drive.
#[derive(Debug, Clone, PartialEq)]
pub struct FlexibleJoint {
    /// `N`, motor angle per joint angle (with sign).
    pub gear_ratio: f64,
    /// `B`, the rotor inertia reflected to the link side, kg m^2.
    pub rotor_inertia: f64,
    /// `k`, the motor's torque constant, N m/A on the motor shaft (`u = N k i`).
    pub torque_constant: f64,
    /// `K1`, the transmission's stiffness at no load, N m/rad.
    pub stiffness: f64,
    /// `K3`, its hardening, N m/rad^3 (`tau_J = K1 d + K3 d^3 + D d'`).
    pub hardening: f64,
    /// `D`, its damping, N m s/rad.
    pub damping: f64,
    /// The rotor friction `f(theta', tau_J, T)`.
    pub friction: JointFriction,
}

impl FlexibleJoint {
    /// The elastic torque at deflection `d`.
    pub fn elastic(&self, d: f64) -> f64 {
        self.stiffness * d + self.hardening * d * d * d
    }

    /// The deflection whose elastic torque is `tau` (Newton's method on the monotone
    /// cubic, from the linear deflection, which overshoots towards the root: it converges
    /// monotonically).
    pub fn deflection(&self, tau: f64) -> f64 {
        let mut d = tau / self.stiffness;
        for _ in 0..50 {
            let step = (self.elastic(d) - tau) / (self.stiffness + 3.0 * self.hardening * d * d);
            d -= step;
            if step.abs() <= 1e-15 * d.abs() {
                break;
            }
        }
        d
    }
}

/// The temperature of the drives, the same for every joint: `T(t) = end - (end - start)
/// exp(-t / time_constant)`, deg C.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TemperatureProfile {
    /// At t = 0.
    pub start: f64,
    /// Approached as t grows.
    pub end: f64,
    /// Seconds.
    pub time_constant: f64,
}

impl TemperatureProfile {
    /// The temperature at time `t`.
    pub fn at(&self, t: f64) -> f64 {
        self.end - (self.end - self.start) * (-t / self.time_constant).exp()
    }
}

/// A joint-flexibility file (`robid simulate --flexible FLEX.toml`): the temperature and
/// one `[[joint]]` table per joint.
///
/// ```
/// use robid_runtime::simulate::Flexibility;
/// let text = r#"
/// [temperature]
/// start = 25.0
/// end = 40.0
/// time_constant = 600.0
///
/// [[joint]]
/// joint = 1
/// gear_ratio = 101.0
/// rotor_inertia = 0.2
/// torque_constant = 0.12
/// stiffness = 3.0e4
/// hardening = 2.0e9
/// damping = 30.0
/// friction = { coulomb = 4.0, load = 0.02, stribeck = 1.0, stribeck_velocity = 0.05,
///              viscous = 6.0, coulomb_temperature = 0.005, viscous_temperature = 0.01,
///              reference_temperature = 25.0 }
/// "#;
/// let flex = Flexibility::from_toml_str(text, "flex.toml".as_ref()).unwrap();
/// assert_eq!(flex.joints.len(), 1);
/// // the deflection under 30 N m, about 0.94 mrad: the hardening takes 6 % of the torque
/// let d = flex.joints[0].deflection(30.0);
/// assert!((flex.joints[0].elastic(d) - 30.0).abs() < 1e-12 && (d - 9.44e-4).abs() < 1e-6);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Flexibility {
    /// Per joint, joint 1 first.
    pub joints: Vec<FlexibleJoint>,
    /// The drives' temperature.
    pub temperature: TemperatureProfile,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct File {
    temperature: TemperatureProfile,
    joint: Vec<Row>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Row {
    joint: usize,
    gear_ratio: f64,
    rotor_inertia: f64,
    torque_constant: f64,
    stiffness: f64,
    #[serde(default)]
    hardening: f64,
    #[serde(default)]
    damping: f64,
    friction: JointFriction,
}

/// What makes a flexible plant stiff, for the error of the step cap ([`StepBudget`]).
const STIFF_FLEXIBLE: &str = "a rotor inertia far below the robot's, a stiff transmission on a \
     light link, or a controller bandwidth far above the motion; check the joint-flexibility \
     file, lower the bandwidth (--bandwidth)";

/// The largest transmission stiffness accepted, N m/rad (a rigid joint is simulated
/// without `--flexible`).
const MAX_STIFFNESS: f64 = 1e9;

impl Row {
    /// The first value out of range, as `(field, problem)`.
    fn problem(&self) -> Option<(&'static str, String)> {
        // Every factor the simulation divides by or scales with, in one table: a magnitude
        // range (the gear ratio has a sign) with its unit and why it ends there. The floor
        // is that of every factor that scales a signal (`MIN_FACTOR`): a rotor inertia of
        // 1e-320 made the rotor's acceleration infinite at the first step ("diverged",
        // naming no key), a torque constant of 1e-320 wrote `inf` as every current, a
        // stiffness of 1e-320 made the deflection under any torque infinite.
        let factors = [
            (
                "rotor_inertia",
                self.rotor_inertia,
                false,
                [MIN_FACTOR, 1e6],
                "kg m^2",
                "the rotor's inertia reflected to the link side, its own times the gear \
                 ratio squared; its acceleration divides by it",
            ),
            (
                "torque_constant",
                self.torque_constant,
                false,
                [MIN_FACTOR, 1e6],
                "N m/A",
                "the currents, torque / (gear ratio x torque constant), divide by it",
            ),
            (
                "stiffness",
                self.stiffness,
                false,
                [MIN_FACTOR, MAX_STIFFNESS],
                "N m/rad",
                "the deflection under a torque divides by it; a rigid joint is simulated \
                 without --flexible",
            ),
            (
                "gear_ratio",
                self.gear_ratio,
                true,
                [1e-3, 1e6],
                "",
                "motor angle per joint angle, with its sign",
            ),
        ];
        for (field, x, signed, [low, high], unit, why) in factors {
            let magnitude = if signed { x.abs() } else { x };
            if !(low..=high).contains(&magnitude) {
                let unit = if unit.is_empty() {
                    String::new()
                } else {
                    format!(" {unit}")
                };
                let range = if signed {
                    format!("must be of magnitude {low:e} to {high:e}")
                } else {
                    format!("must lie in [{low:e}, {high:e}]{unit}")
                };
                return Some((field, format!("{}{unit} {range} ({why})", num(x))));
            }
        }
        for (field, x) in [("hardening", self.hardening), ("damping", self.damping)] {
            if !(0.0..=1e15).contains(&x) {
                return Some((
                    field,
                    format!("{} must be zero or positive, at most 1e15", num(x)),
                ));
            }
        }
        self.friction
            .problem()
            .map(|(field, problem)| (field, format!("friction.{field}: {problem}")))
            .map(|(_, p)| ("friction", p))
    }
}

impl Flexibility {
    /// Reads a joint-flexibility file.
    pub fn read(path: &Path) -> Result<Flexibility> {
        let text = crate::data::read_text(path, "joint-flexibility file")?;
        Flexibility::from_toml_str(&text, path)
    }

    /// Reads the text of a joint-flexibility file, naming it `path` in errors.
    pub fn from_toml_str(text: &str, path: &Path) -> Result<Flexibility> {
        let file: File = toml::from_str(text)
            .map_err(|e| crate::toml_syntax::syntax_error(text, path, TomlFile::Flexibility, &e))?;
        let keys = KeyMap::parse(text);
        let at = |key: String, problem: String| {
            let (line, column) = keys.find(&key).unzip();
            Error::Data(DataError::ConfigKey {
                path: PathBuf::from(path),
                line,
                column,
                key,
                problem,
            })
        };
        let t = file.temperature;
        for (field, x) in [("start", t.start), ("end", t.end)] {
            if !(-100.0..=300.0).contains(&x) {
                return Err(at(
                    format!("temperature.{field}"),
                    format!("{} deg C must lie in [-100, 300]", num(x)),
                ));
            }
        }
        if !(t.time_constant > 0.0 && t.time_constant <= 1e9) {
            return Err(at(
                "temperature.time_constant".into(),
                format!("{} s must be positive, at most 1e9", num(t.time_constant)),
            ));
        }
        let n = file.joint.len();
        let mut joints: Vec<Option<FlexibleJoint>> = vec![None; n];
        for (i, row) in file.joint.iter().enumerate() {
            let key = |field: &str| format!("joint[{}].{field}", i + 1);
            if !(1..=n).contains(&row.joint) {
                return Err(at(
                    key("joint"),
                    format!(
                        "{} is not a joint from 1 to {n} (the number of [[joint]] tables); give \
                         one table per joint",
                        row.joint
                    ),
                ));
            }
            if let Some((field, problem)) = row.problem() {
                return Err(at(key(field), format!("joint {}: {problem}", row.joint)));
            }
            let slot = &mut joints[row.joint - 1];
            if slot.is_some() {
                return Err(at(
                    key("joint"),
                    format!("joint {} has a second table; give one per joint", row.joint),
                ));
            }
            *slot = Some(FlexibleJoint {
                gear_ratio: row.gear_ratio,
                rotor_inertia: row.rotor_inertia,
                torque_constant: row.torque_constant,
                stiffness: row.stiffness,
                hardening: row.hardening,
                damping: row.damping,
                friction: row.friction,
            });
        }
        if n == 0 {
            return Err(at(
                "joint".into(),
                "no [[joint]] table; give one per joint of the robot".into(),
            ));
        }
        Ok(Flexibility {
            // every slot is filled: n tables, each a distinct joint of 1..=n
            joints: joints.into_iter().flatten().collect(),
            temperature: t,
        })
    }

    /// The rotor friction of every joint as one model (for the compensation of the data).
    pub fn friction(&self) -> Result<FrictionModel> {
        FrictionModel::new(self.joints.iter().map(|j| j.friction).collect())
    }
}

/// What a flexible-joint robot logs, and the truth behind it.
#[derive(Debug, Clone)]
pub struct FlexibleRecord {
    /// Time stamps, s.
    pub t: Vec<f64>,
    /// Link encoder positions (noise and quantization applied), rad.
    pub q: Signals,
    /// Motor encoder positions on the motor side, `N theta` (noise and quantization
    /// applied), motor rad.
    pub motor: Signals,
    /// Motor currents (with the torque noise divided by `N k`), A.
    pub current: Signals,
    /// Drive temperatures, deg C.
    pub temperature: Signals,
    /// The true joint torques `tau_J`, N m.
    pub joint_torque: Signals,
    /// The true link positions, rad.
    pub true_q: Signals,
    /// The true rotor positions reflected to the link side, rad.
    pub true_theta: Signals,
}

impl FlexibleRecord {
    /// The largest |theta - q| per joint over the run (the transmission's deflection).
    pub fn largest_deflection(&self) -> Vec<f64> {
        self.true_theta
            .joints()
            .zip(self.true_q.joints())
            .map(|(th, q)| {
                th.iter()
                    .zip(q)
                    .map(|(a, b)| (a - b).abs())
                    .fold(0.0, f64::max)
            })
            .collect()
    }

    /// Writes `t,q1..,theta1..,i1..,T1..` and with `joint_torque` also `tauJ1..`, every
    /// `every`-th sample. A value beyond what robid's readers accept is refused first
    /// ([`crate::SimulateError::Unreadable`]), with nothing written.
    pub fn write_csv(&self, path: &Path, every: usize, joint_torque: bool) -> Result<()> {
        use crate::limits::Quantity;
        let n = self.q.dof();
        let mut header = vec!["t".to_string()];
        let mut signals = vec![&self.q, &self.motor, &self.current, &self.temperature];
        let mut prefixes = vec!["q", "theta", "i", "T"];
        let mut groups = vec![
            Quantity::Position,
            Quantity::Position,
            Quantity::Torque,
            Quantity::Temperature,
        ];
        if joint_torque {
            signals.push(&self.joint_torque);
            prefixes.push("tauJ");
            groups.push(Quantity::Torque);
        }
        for p in &prefixes {
            header.extend((1..=n).map(|j| format!("{p}{j}")));
        }
        let every = every.max(1);
        let rows = self.t.len().div_ceil(every);
        let fill = |r: usize, row: &mut Vec<f64>| {
            let k = r * every;
            row.push(self.t[k]);
            for s in &signals {
                row.extend(s.joints().map(|v| v[k]));
            }
        };
        let quantities = super::trajectory::column_quantities(n, &groups);
        super::trajectory::check_rows(path, &header, &quantities, rows, fill, |column| {
            match prefixes.get(column.saturating_sub(1) / n.max(1)) {
                Some(&"theta") => "a motor position is the link's times the gear ratio: give \
                     a smaller gear ratio, or a reference nearer 0"
                    .to_string(),
                Some(&"i") => "a current is the torque over the gear ratio times the torque \
                     constant: give a larger torque constant or gear ratio, or less torque noise"
                    .to_string(),
                _ => "the simulation produced it: check the parameters, the flexibility file, \
                     the reference and the noise settings"
                    .to_string(),
            }
        })?;
        super::trajectory::write_rows(path, header, rows, fill)
    }
}

/// The motor-side controller's reference at one instant: link states, the joint torque
/// the rigid model needs, and the motor position that gives it.
struct Reference {
    q: [Vec<f64>; 3],
    tau: Vec<f64>,
    theta: Vec<f64>,
}

impl Simulation {
    /// Simulates `model` (true base parameters `base`) with the flexible joints of `flex`
    /// tracking `reference` under a motor-side controller of bandwidth
    /// [`Simulation::bandwidth`]; the noise settings apply to both encoders (positions,
    /// quantization per count of each) and, divided by `N k`, the torque noise to the
    /// currents.
    pub fn run_flexible<M: Model + ?Sized>(
        &self,
        model: &M,
        base: &[f64],
        flex: &Flexibility,
        reference: &Trajectory,
    ) -> Result<FlexibleRecord> {
        let n = model.dof();
        self.check(n)?;
        if flex.joints.len() != n || reference.dof() != n {
            return Err(Error::Data(DataError::JointCountMismatch {
                context: "joint-flexibility file and reference trajectory".into(),
                expected: n,
                found: if flex.joints.len() != n {
                    flex.joints.len()
                } else {
                    reference.dof()
                },
            }));
        }
        reference.check("reference trajectory")?;
        reference.check_derivatives(|k| format!("reference trajectory, sample {k}"))?;
        let samples = reference.samples();
        crate::limits::check_size(
            || {
                format!(
                    "integration steps ({samples} samples x {} substeps)",
                    self.substeps
                )
            },
            samples as f64 * self.substeps as f64,
            super::MAX_SIMULATION_STEPS,
            "use fewer substeps or a shorter trajectory",
        )?;
        check_parameters("Simulation::run_flexible", "base", model, base)?;
        let mut fd = ForwardDynamics::new(model, base)?;
        let joints = &flex.joints;
        let wn = std::f64::consts::TAU * self.bandwidth;
        // PD gains per joint on the rotor plus the link's own inertia at the start
        let mut r0 = [vec![0.0; n], vec![0.0; n], vec![0.0; n]];
        {
            let [a, b, c] = &mut r0;
            reference.state(0, a, b, c);
        }
        let mut mass = vec![0.0; n * n];
        model.mass_matrix_into(&r0[0], base, &mut mass)?;
        let inertia: Vec<f64> = (0..n)
            .map(|j| joints[j].rotor_inertia + mass[j * n + j].max(0.0))
            .collect();
        let kp: Vec<f64> = inertia.iter().map(|i| i * wn * wn).collect();
        let kd: Vec<f64> = inertia
            .iter()
            .map(|i| 2.0 * self.damping * i * wn)
            .collect();
        let quantize = |x: f64| {
            let r = self.noise.quantization;
            if r > 0.0 { (x / r).round() * r } else { x }
        };
        let sigma_tau = |j: usize| self.noise.torque[j.min(self.noise.torque.len() - 1)];
        // the reference at an instant: the rigid torque along it and the motor position
        // whose deflection gives that torque
        let target = |r: &[Vec<f64>; 3], out: &mut Reference| -> Result<()> {
            out.q.clone_from(r);
            model.inverse_dynamics_into(&r[0], &r[1], &r[2], base, &mut out.tau)?;
            for j in 0..n {
                out.theta[j] = r[0][j] + joints[j].deflection(out.tau[j]);
            }
            Ok(())
        };
        let new_reference = || Reference {
            q: [vec![0.0; n], vec![0.0; n], vec![0.0; n]],
            tau: vec![0.0; n],
            theta: vec![0.0; n],
        };
        // the motor encoder's reading of rotor position `theta` (link side) with the noise
        // sample `noise` (motor side): what the log writes and the PD loop reads, divided
        // by N (it read quantize(N theta) / N + noise as link radians, N times the noise
        // the log carried)
        let encoder =
            |g: &FlexibleJoint, theta: f64, noise: f64| quantize(g.gear_ratio * theta) + noise;
        // the motor torque u: feed-forward of the joint torque, the rotor's inertia and
        // friction, and the PD loop on the measured motor position (noise held over a step)
        let command = |r: &Reference,
                       theta: &[f64],
                       thetad: &[f64],
                       noise: &[f64],
                       temp: f64,
                       u: &mut [f64]| {
            for j in 0..n {
                let g = &joints[j];
                let measured = encoder(g, theta[j], noise[j]) / g.gear_ratio;
                u[j] = r.tau[j]
                    + g.rotor_inertia * r.q[2][j]
                    + g.friction.evaluate(r.q[1][j], r.tau[j], temp)
                    + kp[j] * (r.theta[j] - measured)
                    + kd[j] * (r.q[1][j] - thetad[j]);
            }
        };
        // the joint torques of a state
        let transmission = |x: &[f64], v: &[f64], tau: &mut [f64]| {
            for j in 0..n {
                let g = &joints[j];
                tau[j] = g.elastic(x[n + j] - x[j]) + g.damping * (v[n + j] - v[j]);
            }
        };
        let t0 = reference.t[0];
        let temperature = |t: f64| flex.temperature.at(t - t0);
        let allowed: Vec<f64> = reference
            .q
            .joints()
            .map(|v| {
                let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
                let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
                super::DIVERGENCE_FACTOR * (hi - lo + 1.0)
            })
            .collect();
        let diverged = |k: usize, reason: String| {
            Error::Simulate(SimulateError::Diverged {
                time: reference.t[k],
                sample: k,
                reason,
                fix: "check the joint-flexibility file (a stiffness or rotor inertia far from \
                      the robot's, a bandwidth near the transmission's resonance) and the \
                      reference trajectory near this sample"
                    .into(),
            })
        };

        // state: positions (q, theta) and velocities (q', theta'), theta on the link side,
        // starting at rest on the reference with the transmission deflected by the load
        let mut reference_now = new_reference();
        target(&r0, &mut reference_now)?;
        let mut x: Vec<f64> = r0[0].iter().chain(&reference_now.theta).copied().collect();
        let mut v: Vec<f64> = r0[1].iter().chain(&r0[1]).copied().collect();
        let zeros = || Signals::zeros(n, samples);
        let mut out = FlexibleRecord {
            t: reference.t.clone(),
            q: zeros(),
            motor: zeros(),
            current: zeros(),
            temperature: zeros(),
            joint_torque: zeros(),
            true_q: zeros(),
            true_theta: zeros(),
        };
        let mut rng = Rng::new(self.seed);
        let mut noise = vec![0.0; n];
        let draw = |rng: &mut Rng, noise: &mut [f64]| {
            noise
                .iter_mut()
                .for_each(|e| *e = self.noise.position * rng.normal());
        };
        let (mut tau, mut u, mut qdd) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        let mut r1 = r0.clone();
        let mut r = r0.clone();
        let mut stage = new_reference();
        let mut budget = StepBudget::new();
        let progress = Progress::new(self.progress, "simulate", samples as u64, "samples");
        let counter = progress.counter();
        for k in 0..samples {
            counter.tick();
            {
                let [a, b, c] = &mut r0;
                reference.state(k, a, b, c);
            }
            target(&r0, &mut reference_now)?;
            draw(&mut rng, &mut noise);
            let temp = temperature(reference.t[k]);
            command(&reference_now, &x[n..], &v[n..], &noise, temp, &mut u);
            transmission(&x, &v, &mut tau);
            for j in 0..n {
                let g = &joints[j];
                let e = x[j] - r0[0][j];
                if !(x[j].is_finite() && x[n + j].is_finite() && u[j].is_finite()) {
                    return Err(diverged(
                        k,
                        format!("the state of joint {} is not finite", j + 1),
                    ));
                }
                if e.abs() > allowed[j] || u[j].abs() > MAX_TORQUE {
                    return Err(diverged(
                        k,
                        format!(
                            "joint {} is {e:.3e} from its reference with a motor torque of {:.3e}",
                            j + 1,
                            u[j]
                        ),
                    ));
                }
                let link = quantize(x[j]) + self.noise.position * rng.normal();
                // the reading the controller took at this sample
                let motor = encoder(g, x[n + j], noise[j]);
                // the draw the motor encoder's own noise took: a seed gives the log it
                // gave before whenever the position noise is 0 (the torque noise's draws
                // unmoved; robots/tests/cli/flexible.rs's validation depends on them)
                let _ = rng.normal();
                let per_amp = g.gear_ratio * g.torque_constant;
                out.q[j][k] = link;
                out.motor[j][k] = motor;
                out.current[j][k] = (u[j] + sigma_tau(j) * rng.normal()) / per_amp;
                out.temperature[j][k] = temp;
                out.joint_torque[j][k] = tau[j];
                out.true_q[j][k] = x[j];
                out.true_theta[j][k] = x[n + j];
            }
            if k + 1 == samples {
                break;
            }
            {
                let [a, b, c] = &mut r1;
                reference.state(k + 1, a, b, c);
            }
            let interval = reference.t[k + 1] - reference.t[k];
            let h = interval / self.substeps as f64;
            for i in 0..self.substeps {
                if i > 0 {
                    draw(&mut rng, &mut noise);
                }
                // Runge-Kutta steps for this substep: enough for the fastest rate of the
                // state, the friction's slope taken at the smallest rotor speed the
                // substep can reach
                let s0 = i as f64 / self.substeps as f64;
                quintic(s0, interval, &r0, &r1, &mut r);
                target(&r, &mut stage)?;
                let temp = temperature(reference.t[k] + s0 * interval);
                command(&stage, &x[n..], &v[n..], &noise, temp, &mut u);
                transmission(&x, &v, &mut tau);
                let slowest: Vec<f64> = (0..n)
                    .map(|j| {
                        let g = &joints[j];
                        let f = g.friction.evaluate(v[n + j], tau[j], temp);
                        let acc = (u[j] - f - tau[j]) / g.rotor_inertia;
                        (v[n + j].abs() - 2.0 * h * acc.abs()).max(0.0)
                    })
                    .collect();
                let fastest =
                    self.fastest_rate(model, base, joints, &x, &slowest, &tau, &kp, &kd)?;
                let rate = fastest.rate;
                // beyond the cap the explicit integration is unstable: refused, unless the
                // rate beyond it is the friction's smooth sign or Stribeck term near a
                // reversal, which saturate (the split is capped there, as it always was)
                let split = match split_for(h, rate) {
                    Ok(split) => split,
                    Err(_) => match split_for(h, fastest.stiff) {
                        Ok(_) => MAX_SPLIT as usize,
                        Err(needed) => {
                            return Err(too_stiff(
                                k,
                                reference.t[k],
                                fastest.stiff,
                                h,
                                needed,
                                fastest.cause(joints, self.bandwidth, h),
                            ));
                        }
                    },
                };
                budget.take(split, rate, k, samples, reference.t[k], STIFF_FLEXIBLE)?;
                for part in 0..split {
                    let mut f = |c: f64, x: &[f64], v: &[f64], acc: &mut [f64]| -> Result<()> {
                        let s =
                            (i as f64 + (part as f64 + c) / split as f64) / self.substeps as f64;
                        quintic(s, interval, &r0, &r1, &mut r);
                        target(&r, &mut stage)?;
                        let temp = temperature(reference.t[k] + s * interval);
                        command(&stage, &x[n..], &v[n..], &noise, temp, &mut u);
                        transmission(x, v, &mut tau);
                        fd.accelerations(&x[..n], &v[..n], &tau, &mut qdd)?;
                        for j in 0..n {
                            let g = &joints[j];
                            acc[j] = qdd[j];
                            acc[n + j] =
                                (u[j] - g.friction.evaluate(v[n + j], tau[j], temp) - tau[j])
                                    / g.rotor_inertia;
                        }
                        Ok(())
                    };
                    rk4_step(&mut f, &mut x, &mut v, h / split as f64)?;
                    if x.iter().any(|p| !(p.abs() <= MAX_POSITION))
                        || v.iter().any(|w| !(w.abs() <= MAX_VELOCITY))
                    {
                        return Err(diverged(
                            k,
                            "the state left every physical range between two samples".into(),
                        ));
                    }
                }
            }
            transmission(&x, &v, &mut tau);
        }
        Ok(out)
    }

    /// A bound on the fastest rate of the flexible plant at positions `x` with rotor speeds
    /// down to `slowest`: per joint the transmission's resonance on the rotor and link
    /// inertias, its damping, the friction's slope (the smooth sign's is level / eps at a
    /// reversal), and the PD loop's.
    ///
    /// Each rate is taken where it acts. The PD loop (`kp`, `kd`), the rotor friction and
    /// the transmission's rotor side act on the rotor alone (`kd / B`, `sqrt(kp / B)`,
    /// `D / B`, `sqrt(K / B)`); the transmission's link side on the link through `M^-1`
    /// (`D` and `K` times the row's absolute sum of `M^-1`, its coupling to the other joints'
    /// transmissions included). The loop's rate was `kd / (B + M_jj) + wn`, the gains over
    /// the inertia they were designed for: on a rotor 35 times lighter than its link it
    /// counted 188 1/s where the derivative term acts at 4549, and RK4 went unstable at
    /// 100 Hz (currents of 578 A where 1.3 A were true) with no refusal.
    #[allow(clippy::too_many_arguments)]
    fn fastest_rate<M: Model + ?Sized>(
        &self,
        model: &M,
        base: &[f64],
        joints: &[FlexibleJoint],
        x: &[f64],
        slowest: &[f64],
        tau: &[f64],
        kp: &[f64],
        kd: &[f64],
    ) -> Result<Fastest> {
        let n = joints.len();
        let mut mass = vec![0.0; n * n];
        model.mass_matrix_into(&x[..n], base, &mut mass)?;
        // the link's compliance: M^-1, whose row j maps the joint torques to joint j's
        // acceleration
        let inverse = super::forward::factor(&mass, n)
            .ok_or_else(|| {
                super::forward::singular(
                    format!(
                        "the mass matrix M(q) of {} at q = {:?}",
                        model.name(),
                        &x[..n]
                    ),
                    &mass,
                    n,
                )
            })?
            .inverse();
        // the transmissions' tangent stiffness, at up to twice the deflection (a step moves it)
        let stiffness: Vec<f64> = joints
            .iter()
            .enumerate()
            .map(|(j, g)| {
                let d = 2.0 * (x[n + j] - x[j]);
                g.stiffness + 3.0 * g.hardening * d * d
            })
            .collect();
        let wn = std::f64::consts::TAU * self.bandwidth;
        let mut fastest = Fastest {
            rate: 0.0,
            stiff: 0.0,
            joint: 0,
            term: Term::Bandwidth,
            part: 0.0,
            link: 0.0,
            loop_rate: wn,
        };
        for (j, g) in joints.iter().enumerate() {
            let b = g.rotor_inertia;
            // the link side: joint j's acceleration per joint torque, through every
            // transmission
            let row = |weight: &dyn Fn(usize) -> f64| {
                (0..n)
                    .map(|k| inverse[(j, k)].abs() * weight(k))
                    .sum::<f64>()
            };
            let link_stiffness = row(&|k| stiffness[k]);
            let link_damping = row(&|k| joints[k].damping);
            let f = &g.friction;
            let level = f.coulomb + f.load * tau[j].abs() + f.stribeck;
            let sech = 1.0 / (slowest[j] / f.smoothing).cosh();
            // the smooth sign's and the Stribeck term's slopes saturate (apart for the
            // error of a plant too stiff to integrate); the viscous one does not
            let saturating = level * sech * sech / f.smoothing
                + f.stribeck * stribeck_slope(f.stribeck_velocity, slowest[j]);
            let loop_rate = kd[j] / b + (kp[j] / b).sqrt();
            let terms = [
                (Term::Resonance, (stiffness[j] / b + link_stiffness).sqrt()),
                (Term::Damping, g.damping / b + link_damping),
                (Term::Friction, f.viscous / b),
                (Term::Bandwidth, loop_rate),
            ];
            let stiff = terms.iter().map(|(_, r)| r).sum::<f64>();
            fastest.rate = fastest.rate.max(stiff + saturating / b);
            if stiff > fastest.stiff {
                let (term, part) = terms
                    .into_iter()
                    .max_by(|a, b| a.1.total_cmp(&b.1))
                    .unwrap_or((Term::Bandwidth, 0.0));
                (fastest.stiff, fastest.joint, fastest.term, fastest.part) = (stiff, j, term, part);
                fastest.link = 1.0 / inverse[(j, j)];
                fastest.loop_rate = loop_rate;
            }
        }
        Ok(fastest)
    }
}

/// The term of a flexible plant's fastest rate ([`Fastest`]).
#[derive(Clone, Copy, Debug, PartialEq)]
enum Term {
    /// The transmission's resonance on the rotor and link inertias.
    Resonance,
    /// The transmission's damping over the rotor and link inertias.
    Damping,
    /// The rotor friction's slope over the rotor inertia.
    Friction,
    /// The controller's own rate on the rotor.
    Bandwidth,
}

/// The bound on a flexible plant's fastest rate and what makes most of it: the joint
/// whose rate is the largest and the largest of its terms, for the error of a plant too
/// stiff to integrate ([`crate::SimulateError::TooStiff`]).
struct Fastest {
    /// The bound, 1/s (the loop's rate included), for the split of a substep.
    rate: f64,
    /// The bound without the friction's saturating terms (its smooth sign and Stribeck
    /// term), 1/s, for the error: what is stiff at every step.
    stiff: f64,
    /// The joint of the largest rate, from 0.
    joint: usize,
    /// Its largest term.
    term: Term,
    /// That term's rate, 1/s.
    part: f64,
    /// The link's inertia at the joint, `1 / (M^-1)_jj` (what the joint's torque moves).
    link: f64,
    /// The controller's rate at the joint, `kd / B + sqrt(kp / B)` on the rotor, 1/s.
    loop_rate: f64,
}

impl Fastest {
    /// What makes the rate, with the values of `joints` (the flexibility file's) and the
    /// fix, for a substep of `h` seconds of a loop of `bandwidth` Hz.
    fn cause(&self, joints: &[FlexibleJoint], bandwidth: f64, h: f64) -> String {
        let j = self.joint + 1;
        let g = &joints[self.joint];
        let num = crate::Num;
        let rounded = crate::Num::rounded;
        // the value of the term's quantity the integration follows, scaling it with its
        // rate (its rate is proportional to it but for the resonance, to its square root)
        let room = (reach(h) - (self.stiff - self.part)).max(0.0) / self.part;
        let inertias = format!(
            "rotor_inertia {} kg m^2, the link's inertia {} kg m^2 at this state",
            num(g.rotor_inertia),
            rounded(self.link, 3)
        );
        match self.term {
            Term::Damping => format!(
                "the transmission damping of joint {j}, damping = {} N m s/rad in the \
                 joint-flexibility file, over its inertias ({inertias}: a rate of {} 1/s) \
                 makes it: check joint {j}'s `damping`; the integration follows a damping below \
                 about {} N m s/rad",
                num(g.damping),
                rounded(self.part, 3),
                rounded(g.damping * room, 2)
            ),
            Term::Resonance => format!(
                "the transmission of joint {j}, stiffness = {} N m/rad (hardening {} N m/rad^3) \
                 in the joint-flexibility file, resonating on its inertias ({inertias}: {} \
                 1/s) makes it: check joint {j}'s `stiffness`, `hardening` and \
                 `rotor_inertia`; the integration follows a stiffness below about {} N m/rad",
                num(g.stiffness),
                num(g.hardening),
                rounded(self.part, 3),
                rounded(g.stiffness * room * room, 2)
            ),
            Term::Friction => format!(
                "the rotor's viscous friction of joint {j}, viscous = {} N m s/rad in the \
                 joint-flexibility file, over rotor_inertia {} kg m^2 ({} 1/s) makes it: check \
                 joint {j}'s `viscous` and `rotor_inertia`; the integration follows a viscous \
                 friction below about {} N m s/rad",
                num(g.friction.viscous),
                num(g.rotor_inertia),
                rounded(self.part, 3),
                rounded(g.friction.viscous * room, 2)
            ),
            Term::Bandwidth => bandwidth_cause(bandwidth, self.loop_rate, h, self.stiff),
        }
    }
}

/// A bound on `|d exp(-(w / ws)^2) / dw| = 2 |w| / ws^2 exp(-(w / ws)^2)` over rotor speeds
/// `|w| >= slowest`: its peak `sqrt(2 / e) / ws` at `|w| = ws / sqrt(2)` when `slowest` is
/// below that, else its value at `slowest` (it falls beyond the peak). Taken at the slowest
/// speed the substep can reach, as the smooth sign's slope is: bounded by `1 / ws` at every
/// speed, it made a run split every substep to the cap when `ws` was small (a Stribeck
/// velocity of 1e-6 rad/s ran for minutes), though the term changes only near a reversal.
fn stribeck_slope(ws: f64, slowest: f64) -> f64 {
    let w = slowest.max(ws / std::f64::consts::SQRT_2);
    let r = w / ws;
    // exp(-r^2) is 0 in f64 long before r = 30, where 2 r / ws could overflow
    if r > 30.0 {
        0.0
    } else {
        2.0 * r * (-r * r).exp() / ws
    }
}

#[cfg(test)]
mod tests;
