//! Closed-loop simulation along a reference trajectory (docs/identification.md#simulation).
//!
//! The controller computes tau = tau_ff + M(q) (wn^2 (q_ref - q_meas) + 2 zeta wn (qd_ref -
//! qd)), with the computed-torque feed-forward tau_ff = ID(q_ref, qd_ref, qdd_ref) of the
//! true model (optional): the PD acts through the mass matrix, so every joint's error
//! follows the same second-order dynamics of bandwidth wn whatever the coupling between
//! the links (gains scaled by the diagonal of M alone left a light wrist coupled to heavier
//! links far faster than wn, which an explicit integrator cannot follow). The feed-forward
//! takes the Coulomb terms `Fc sign(qd)` at the joint's own velocity, not the reference's
//! ([`Coulomb`]): the plant's discontinuous friction then cancels in the closed loop (at the
//! reference's velocity the difference, up to 2 Fc over a light link's inertia, switched
//! at every stop and reversal, and the link chattered about zero velocity).
//! The plant M(q) qdd = tau - h(q, qd) (see [`ForwardDynamics`]) is integrated with
//! `substeps` classical Runge-Kutta steps per reference interval (fourth order, so that the
//! positions agree with the accelerations and torques recorded at the samples), the
//! controller running at every stage on the reference interpolated by quintic Hermite
//! polynomials (through
//! the positions, velocities and accelerations at both samples, so that the interpolated
//! velocity and acceleration are the derivatives of the interpolated position: a linear
//! interpolation of the positions would bend away from the trajectory by up to qdd dt^2 / 8
//! mid-interval, and the PD loop's answer to that, a torque periodic with the sample period
//! and proportional to qdd, would be recorded at the same phase of every interval, biasing
//! the inertias seen by anyone who differentiates the positions). At each reference sample the
//! state, the applied torque and qdd = M^-1 (tau - h) are recorded, so the true record
//! satisfies the model exactly. Measurements: positions quantized to the encoder
//! resolution plus Gaussian noise, the reading the PD loop acts on at the sample (one draw
//! for both: the loop read another than the log wrote); torques plus Gaussian noise; velocities and
//! accelerations are the true ones (plus optional Gaussian noise).
//!
//! Checks: the settings ([`Simulation::check`]: bandwidth up to [`MAX_BANDWIDTH`] Hz,
//! 1 to [`MAX_SUBSTEPS`] substeps, at most [`MAX_SIMULATION_STEPS`] integration steps in
//! all), the base parameters (finite, magnitude at most
//! [`MAX_BASE_PARAMETER`](crate::limits::MAX_BASE_PARAMETER); M(q) positive definite at the
//! reference's first state by more than its rounding, else a joint that moves no mass or
//! inertia is named ([`crate::SimulateError::NoInertia`]), or joints whose motions coincide
//! ([`crate::SimulateError::Coinciding`]), or the parameters are blamed), the reference (finite and
//! within the ranges of [`crate::limits`], a bad sample named by its index and time). At
//! every reference sample the run is checked for divergence: a non-finite state, a
//! tracking error above [`DIVERGENCE_FACTOR`] times (the joint's reference range + 1 rad),
//! or a torque above [`MAX_TORQUE`](crate::limits::MAX_TORQUE) ends it with
//! [`crate::SimulateError::Diverged`], which says whether the controller is too fast for the integration
//! step.

use crate::Count;
use crate::DataError;
use crate::Model;
use crate::SimulateError;
use crate::error::{Error, Result, num};
use crate::excite::check_parameters;
use crate::limits::{MAX_ACCELERATION, MAX_POSITION, MAX_TORQUE, MAX_VELOCITY, MIN_RESOLUTION};

/// The reference at the fraction `s` of an interval of `interval` seconds between the
/// samples `a` and `b` (each `[q, qd, qdd]`): quintic Hermite interpolation, exact for
/// polynomials up to degree 5, its velocity and acceleration the derivatives of its
/// position.
pub(super) fn quintic(
    s: f64,
    interval: f64,
    a: &[Vec<f64>; 3],
    b: &[Vec<f64>; 3],
    out: &mut [Vec<f64>; 3],
) {
    let (s2, s3) = (s * s, s * s * s);
    let (s4, s5) = (s3 * s, s3 * s2);
    // basis for q0, T v0, T^2 a0, T^2 a1, T v1, q1; and its first and second derivatives in s
    let h = [
        1.0 - 10.0 * s3 + 15.0 * s4 - 6.0 * s5,
        s - 6.0 * s3 + 8.0 * s4 - 3.0 * s5,
        0.5 * s2 - 1.5 * s3 + 1.5 * s4 - 0.5 * s5,
        0.5 * s3 - s4 + 0.5 * s5,
        -4.0 * s3 + 7.0 * s4 - 3.0 * s5,
        10.0 * s3 - 15.0 * s4 + 6.0 * s5,
    ];
    let d = [
        -30.0 * s2 + 60.0 * s3 - 30.0 * s4,
        1.0 - 18.0 * s2 + 32.0 * s3 - 15.0 * s4,
        s - 4.5 * s2 + 6.0 * s3 - 2.5 * s4,
        1.5 * s2 - 4.0 * s3 + 2.5 * s4,
        -12.0 * s2 + 28.0 * s3 - 15.0 * s4,
        30.0 * s2 - 60.0 * s3 + 30.0 * s4,
    ];
    let dd = [
        -60.0 * s + 180.0 * s2 - 120.0 * s3,
        -36.0 * s + 96.0 * s2 - 60.0 * s3,
        1.0 - 9.0 * s + 18.0 * s2 - 10.0 * s3,
        3.0 * s - 12.0 * s2 + 10.0 * s3,
        -24.0 * s + 84.0 * s2 - 60.0 * s3,
        60.0 * s - 180.0 * s2 + 120.0 * s3,
    ];
    let t = interval;
    for j in 0..out[0].len() {
        let c = [
            a[0][j],
            t * a[1][j],
            t * t * a[2][j],
            t * t * b[2][j],
            t * b[1][j],
            b[0][j],
        ];
        let dot = |w: &[f64; 6]| w.iter().zip(&c).map(|(w, c)| w * c).sum::<f64>();
        out[0][j] = dot(&h);
        out[1][j] = dot(&d) / t;
        out[2][j] = dot(&dd) / (t * t);
    }
}

/// Largest controller bandwidth (Hz).
pub const MAX_BANDWIDTH: f64 = 1e6;
/// Largest number of substeps per reference interval.
pub const MAX_SUBSTEPS: usize = 10_000;
/// Largest number of integration steps of a run: reference samples x substeps before it
/// starts, and the Runge-Kutta steps it takes, each substep's splits for a stiff plant
/// included (up to 1,000 per substep), while it runs.
pub const MAX_SIMULATION_STEPS: usize = 200_000_000;

/// What makes a rigid plant stiff, for the error of the step cap ([`StepBudget`]).
const STIFF_RIGID: &str = "a link with little inertia and a large viscous friction (its \
     `Fv` over its inertia is the rate), or a controller bandwidth far above the motion; \
     check the parameters, lower the bandwidth (--bandwidth)";
/// A tracking error above this many times (the joint's reference range + 1 rad or m) is a
/// diverged simulation.
pub const DIVERGENCE_FACTOR: f64 = 10.0;
use crate::progress::Progress;
use crate::rng::Rng;
use crate::signal::Signals;
use crate::simulate::forward;
use crate::simulate::{ForwardDynamics, Record, Trajectory};

/// Measurement noise and quantization.
#[derive(Debug, Clone, PartialEq)]
pub struct Noise {
    /// Standard deviation of the torque noise per joint (N m), one value for all joints
    /// or one per joint.
    pub torque: Vec<f64>,
    /// Standard deviation of the position noise (rad).
    pub position: f64,
    /// Standard deviation of the velocity noise (rad/s).
    pub velocity: f64,
    /// Standard deviation of the acceleration noise (rad/s^2).
    pub acceleration: f64,
    /// Encoder resolution (rad per count); 0 for none.
    pub quantization: f64,
}

impl Default for Noise {
    /// No noise at all.
    fn default() -> Self {
        Self {
            torque: vec![0.0],
            position: 0.0,
            velocity: 0.0,
            acceleration: 0.0,
            quantization: 0.0,
        }
    }
}

/// Simulation settings.
#[derive(Debug, Clone, PartialEq)]
pub struct Simulation {
    /// Closed-loop natural frequency of the PD loop (Hz).
    pub bandwidth: f64,
    /// Damping ratio of the PD loop.
    pub damping: f64,
    /// Add the computed-torque feed-forward of the true model.
    pub feedforward: bool,
    /// Integration (and control) steps per reference sample interval.
    pub substeps: usize,
    /// Measurement noise.
    pub noise: Noise,
    /// Seed of the noise.
    pub seed: u64,
    /// Show the progress of a long run on standard error ([`crate::progress`]).
    pub progress: bool,
}

impl Default for Simulation {
    fn default() -> Self {
        Self {
            bandwidth: 10.0,
            damping: 1.0,
            feedforward: true,
            substeps: 10,
            noise: Noise::default(),
            seed: 1,
            progress: false,
        }
    }
}

/// What a simulation produced.
#[derive(Debug, Clone)]
pub struct Simulated {
    /// The measured record (noise and quantization applied).
    pub measured: Record,
    /// The true record: the states the plant went through and the torques applied.
    pub truth: Record,
}

fn invalid(key: &str, problem: String) -> Error {
    Error::setting("Simulation", key, problem)
}

impl Simulation {
    /// Checks the settings against a model of `dof` joints.
    pub fn check(&self, dof: usize) -> Result<()> {
        if !(self.bandwidth > 0.0 && self.bandwidth <= MAX_BANDWIDTH) {
            return Err(invalid(
                "bandwidth",
                format!(
                    "{} Hz must lie in (0, {MAX_BANDWIDTH:e}] Hz",
                    num(self.bandwidth)
                ),
            ));
        }
        if !(self.damping > 0.0 && self.damping <= 1e3) {
            return Err(invalid(
                "damping",
                format!("{} must lie in (0, 1000]", num(self.damping)),
            ));
        }
        if !(1..=MAX_SUBSTEPS).contains(&self.substeps) {
            return Err(invalid(
                "substeps",
                format!("{} must lie between 1 and {MAX_SUBSTEPS}", self.substeps),
            ));
        }
        let n = &self.noise;
        if n.torque.len() != 1 && n.torque.len() != dof {
            return Err(invalid(
                "noise.torque",
                format!(
                    "{} for a model of {}; give one value or one per joint",
                    Count(n.torque.len(), "value"),
                    Count(dof, "joint")
                ),
            ));
        }
        for (key, x, limit) in [
            ("noise.position", n.position, MAX_POSITION),
            ("noise.velocity", n.velocity, MAX_VELOCITY),
            ("noise.acceleration", n.acceleration, MAX_ACCELERATION),
            ("noise.quantization", n.quantization, MAX_POSITION),
        ]
        .into_iter()
        .chain(n.torque.iter().map(|&x| ("noise.torque", x, MAX_TORQUE)))
        {
            if !(x >= 0.0 && x <= limit) {
                return Err(invalid(
                    key,
                    format!("{} must be zero or positive, at most {limit:e}", num(x)),
                ));
            }
        }
        if n.quantization > 0.0 && n.quantization < MIN_RESOLUTION {
            return Err(invalid(
                "noise.quantization",
                format!(
                    "{} must be 0 or at least {MIN_RESOLUTION:e} rad per count (a finer \
                     resolution than any encoder's, and a position divided by it overflows); \
                     write 0 for no quantization",
                    num(n.quantization)
                ),
            ));
        }
        Ok(())
    }

    /// Simulates `model` with true base parameters `base` tracking `reference` (see the
    /// module documentation for what is checked).
    pub fn run<M: Model + ?Sized>(
        &self,
        model: &M,
        base: &[f64],
        reference: &Trajectory,
    ) -> Result<Simulated> {
        let n = model.dof();
        self.check(n)?;
        if reference.dof() != n {
            return Err(Error::Data(DataError::JointCountMismatch {
                context: "reference trajectory".into(),
                expected: n,
                found: reference.dof(),
            }));
        }
        let samples = reference.samples();
        crate::limits::check_size(
            || {
                format!(
                    "integration steps ({samples} samples x {} substeps)",
                    self.substeps
                )
            },
            samples as f64 * self.substeps as f64,
            MAX_SIMULATION_STEPS,
            "use fewer substeps or a shorter trajectory",
        )?;
        reference.check("reference trajectory")?;
        reference.check_derivatives(|k| format!("reference trajectory, sample {k}"))?;
        let mut fd = ForwardDynamics::new(model, base)?;
        check_parameters("Simulation::run", "base", model, base)?;
        let mut rng = Rng::new(self.seed);
        let mut r0 = [vec![0.0; n], vec![0.0; n], vec![0.0; n]];
        let mut r1 = r0.clone();
        let [q0, qd0, qdd0] = &mut r0;
        reference.state(0, q0, qd0, qdd0);
        let mut m = vec![0.0; n * n];
        model.mass_matrix_into(&r0[0], base, &mut m)?;
        if forward::factor(&m, n).is_none() {
            return Err(forward::singular(
                format!(
                    "the mass matrix M(q) of {} at the reference's first state q = {:?}",
                    model.name(),
                    r0[0]
                ),
                &m,
                n,
            ));
        }
        let wn = std::f64::consts::TAU * self.bandwidth;
        let (kp, kd) = (wn * wn, 2.0 * self.damping * wn);
        let mut mass = vec![0.0; n * n];
        let mut pd = vec![0.0; n];
        // divergence: a tracking error beyond DIVERGENCE_FACTOR x (reference range + 1)
        let allowed: Vec<f64> = reference
            .q
            .joints()
            .map(|v| {
                let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
                let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
                DIVERGENCE_FACTOR * (hi - lo + 1.0)
            })
            .collect();
        let diverged = |k: usize, reason: String| {
            let dt = if samples > 1 {
                (reference.t[samples - 1] - reference.t[0]) / (samples - 1) as f64
            } else {
                0.0
            };
            // the finest step: a substep split MAX_SPLIT times
            let h = dt / self.substeps as f64 / MAX_SPLIT;
            let fix = if wn * h > 0.5 {
                format!(
                    "the controller bandwidth {} Hz is too high for the finest integration step \
                     {h:.3e} s ({:.6} Hz reference, {} substeps split at most {MAX_SPLIT} times): \
                     lower the bandwidth below {:.3} Hz or raise the substeps or the trajectory's \
                     sample rate",
                    self.bandwidth,
                    1.0 / dt,
                    self.substeps,
                    0.5 / (std::f64::consts::TAU * h)
                )
            } else {
                "raise the bandwidth (--bandwidth; the integration follows it, and a slower \
                 loop lets a joint fall away from its reference, as an arm under gravity does), \
                 or check the reference trajectory near this sample (its velocities and \
                 accelerations must be the derivatives of its positions, within the robot's \
                 limits) and the parameters"
                    .to_string()
            };
            Error::Simulate(SimulateError::Diverged {
                time: reference.t[k],
                sample: k,
                reason,
                fix,
            })
        };
        let (mut q, mut qd) = (r0[0].clone(), r0[1].clone());
        let mut truth = Record {
            trajectory: Trajectory::zeros(n, reference.t.clone()),
            tau: Signals::zeros(n, samples),
        };
        let mut measured = truth.clone();
        let (mut tau, mut qdd) = (vec![0.0; n], vec![0.0; n]);
        let mut r = r0.clone();
        let sigma_tau = |j: usize| self.noise.torque[j.min(self.noise.torque.len() - 1)];
        // the Coulomb terms apart: the feed-forward takes them at the joint's own velocity
        let coulomb = Coulomb::new(model, base)?;
        // the control law, tau = feedforward + M(q) servo: the feed-forward of the reference
        // with the Coulomb friction at the velocity qd (`friction`: scratch space), and the
        // servo acceleration from the measured error (`noise` is the position noise of the
        // measurement, held over a step)
        let feedforward = |r: &[Vec<f64>; 3], qd: &[f64], tau: &mut [f64], friction: &mut [f64]| {
            if !self.feedforward {
                tau.iter_mut().for_each(|t| *t = 0.0);
                return Ok(());
            }
            model.inverse_dynamics_into(&r[0], &r[1], &r[2], &coulomb.smooth, tau)?;
            if coulomb.levels.is_some() {
                coulomb.torques(model, &r[0], qd, friction)?;
                tau.iter_mut()
                    .zip(friction.iter())
                    .for_each(|(t, f)| *t += f);
            }
            Ok::<(), crate::LengthError>(())
        };
        let servo = |r: &[Vec<f64>; 3], q: &[f64], qd: &[f64], noise: &[f64], pd: &mut [f64]| {
            for j in 0..n {
                let e = r[0][j] - (self.quantize(q[j]) + noise[j]);
                pd[j] = kp * e + kd * (r[1][j] - qd[j]);
            }
        };
        // the torque at a sample, recorded
        let mut friction = vec![0.0; n];
        let mut control =
            |r: &[Vec<f64>; 3], q: &[f64], qd: &[f64], noise: &[f64], tau: &mut [f64]| {
                feedforward(r, qd, tau, &mut friction)?;
                servo(r, q, qd, noise, &mut pd);
                model.mass_matrix_into(q, base, &mut mass)?;
                for i in 0..n {
                    tau[i] += (0..n).map(|j| mass[i * n + j] * pd[j]).sum::<f64>();
                }
                Ok::<(), crate::LengthError>(())
            };
        let mut stage_pd = vec![0.0; n];
        let mut stage_friction = vec![0.0; n];
        let mut noise = vec![0.0; n];
        let draw = |rng: &mut Rng, noise: &mut [f64]| {
            noise
                .iter_mut()
                .for_each(|v| *v = self.noise.position * rng.normal());
        };
        // the state and the torque at sample k, checked for divergence
        let check = |k: usize, r: &[Vec<f64>; 3], q: &[f64], qd: &[f64], tau: &[f64]| {
            for j in 0..n {
                let e = q[j] - r[0][j];
                if !(q[j].is_finite() && qd[j].is_finite() && tau[j].is_finite()) {
                    return Err(diverged(
                        k,
                        format!("the state of joint {} is not finite", j + 1),
                    ));
                }
                if e.abs() > allowed[j] {
                    return Err(diverged(
                        k,
                        format!(
                            "joint {} is {e:.3e} from its reference (more than {:.3e})",
                            j + 1,
                            allowed[j]
                        ),
                    ));
                }
                if tau[j].abs() > MAX_TORQUE {
                    return Err(diverged(
                        k,
                        format!(
                            "the torque of joint {} is {:.3e} (more than {MAX_TORQUE:e})",
                            j + 1,
                            tau[j]
                        ),
                    ));
                }
            }
            Ok(())
        };
        let inconsistent = |k: usize, q: &[f64], e: Error| match e {
            Error::Singular { what, .. } => Error::Singular {
                what: format!(
                    "{what} (reached at reference sample {k}, t = {} s, q = {q:?})",
                    reference.t[k]
                ),
                hint: "the parameters are not physically consistent at this state (M(q) was positive definite at the start); use a feasible parameter set (robid feasible)",
            },
            Error::Simulate(SimulateError::Coinciding {
                what,
                joints,
                motion,
            }) => Error::Simulate(SimulateError::Coinciding {
                what: format!(
                    "{what} (reached at reference sample {k}, t = {} s)",
                    reference.t[k]
                ),
                joints,
                motion,
            }),
            Error::Simulate(SimulateError::NoInertia { what, joints, dof }) => {
                Error::Simulate(SimulateError::NoInertia {
                    what: format!(
                        "{what} (reached at reference sample {k}, t = {} s)",
                        reference.t[k]
                    ),
                    joints,
                    dof,
                })
            }
            e => e,
        };
        let mut budget = StepBudget::new();
        let progress = Progress::new(self.progress, "simulate", samples as u64, "samples");
        let counter = progress.counter();
        for k in 0..samples {
            counter.tick();
            let [a, b, c] = &mut r0;
            reference.state(k, a, b, c);
            draw(&mut rng, &mut noise);
            control(&r0, &q, &qd, &noise, &mut tau)?;
            check(k, &r0, &q, &qd, &tau)?;
            fd.accelerations(&q, &qd, &tau, &mut qdd)
                .map_err(|e| inconsistent(k, &q, e))?;
            for j in 0..n {
                let tr = &mut truth.trajectory;
                (tr.q[j][k], tr.qd[j][k], tr.qdd[j][k]) = (q[j], qd[j], qdd[j]);
                truth.tau[j][k] = tau[j];
                let me = &mut measured.trajectory;
                // the position the loop read for this torque (`noise`, held over the
                // first substep), not another draw; the draw the log took is still taken,
                // unused, so that a seed's other noise (the torques') is what it was and a
                // run without position noise writes the same record as before
                me.q[j][k] = self.quantize(q[j]) + noise[j];
                let _ = rng.normal();
                me.qd[j][k] = qd[j] + self.noise.velocity * rng.normal();
                me.qdd[j][k] = qdd[j] + self.noise.acceleration * rng.normal();
                measured.tau[j][k] = tau[j] + sigma_tau(j) * rng.normal();
            }
            if k + 1 < samples {
                let [a, b, c] = &mut r1;
                reference.state(k + 1, a, b, c);
                let interval = reference.t[k + 1] - reference.t[k];
                let h = interval / self.substeps as f64;
                // Runge-Kutta steps per substep: enough for the fastest damping of this state
                // (viscous friction on a light link, the loop's own)
                let (damping, _) =
                    damping_rate(model, base, &q, &qd).map_err(|e| inconsistent(k, &q, e))?;
                let rate = damping + kd + wn;
                // beyond the cap the explicit integration is unstable: refused, unless the
                // rate came from a Coulomb level's sign, which differenced across zero
                // velocity is level / 1e-6, no rate of the plant (it chatters there at any
                // step; the split is capped as it always was)
                let split = match split_for(h, rate) {
                    Ok(split) => split,
                    Err(_) => {
                        let (damping, joint) = damping_rate(model, &coulomb.smooth, &q, &qd)
                            .map_err(|e| inconsistent(k, &q, e))?;
                        let rate = damping + kd + wn;
                        if let Err(needed) = split_for(h, rate) {
                            let cause = if kd + wn >= damping {
                                bandwidth_cause(self.bandwidth, kd + wn, h, rate)
                            } else {
                                rigid_cause(model, base, &q, joint, damping, h, rate)
                            };
                            return Err(too_stiff(k, reference.t[k], rate, h, needed, cause));
                        }
                        MAX_SPLIT as usize
                    }
                };
                for i in 0..self.substeps {
                    budget.take(split, rate, k, samples, reference.t[k], STIFF_RIGID)?;
                    if i > 0 {
                        draw(&mut rng, &mut noise);
                    }
                    for part in 0..split {
                        // classical Runge-Kutta: the controller and the reference at each stage
                        let mut f =
                            |c: f64, q: &[f64], qd: &[f64], acc: &mut [f64]| -> Result<()> {
                                let s = (i as f64 + (part as f64 + c) / split as f64)
                                    / self.substeps as f64;
                                quintic(s, interval, &r0, &r1, &mut r);
                                // M^-1 (feedforward + M servo - h) = M^-1 (feedforward - h)
                                // + servo: one mass matrix per stage
                                feedforward(&r, qd, &mut tau, &mut stage_friction)?;
                                servo(&r, q, qd, &noise, &mut stage_pd);
                                fd.accelerations(q, qd, &tau, acc)?;
                                acc.iter_mut().zip(&stage_pd).for_each(|(a, s)| *a += s);
                                Ok(())
                            };
                        rk4_step(&mut f, &mut q, &mut qd, h / split as f64)
                            .map_err(|e| inconsistent(k, &q, e))?;
                        // a state that left every physical range diverged (before the next
                        // step's mass matrix is computed from it)
                        if q.iter().any(|v| !(v.abs() <= MAX_POSITION))
                            || qd.iter().any(|v| !(v.abs() <= MAX_VELOCITY))
                        {
                            return Err(diverged(
                                k,
                                "the state left every physical range between two samples".into(),
                            ));
                        }
                    }
                    if q.iter().chain(qd.iter()).any(|v| !v.is_finite()) {
                        return Err(diverged(
                            k,
                            "the state became infinite between two samples".into(),
                        ));
                    }
                }
            }
        }
        measured.trajectory.check("the simulated measurement")?;
        truth.trajectory.check("the simulated truth")?;
        for (j, v) in measured.tau.joints().enumerate() {
            if let Some(k) = v.iter().position(|x| !(x.abs() <= MAX_TORQUE)) {
                return Err(diverged(
                    k,
                    format!("the measured torque of joint {} is {:.3e}", j + 1, v[k]),
                ));
            }
        }
        Ok(Simulated { measured, truth })
    }

    /// `q` rounded to the encoder's resolution.
    fn quantize(&self, q: f64) -> f64 {
        let r = self.noise.quantization;
        if r > 0.0 { (q / r).round() * r } else { q }
    }
}

/// The largest |h lambda| kept per Runge-Kutta step, for the bound of the damping rates
/// (the method is stable to 2.78 on the negative real axis; a mode that fast decays within
/// a step, so only its stability matters).
pub(super) const RK4_REACH: f64 = 2.5;
/// The most Runge-Kutta steps one substep is split into.
pub(super) const MAX_SPLIT: f64 = 1000.0;

/// The Runge-Kutta steps a substep of `h` seconds is split into where the plant's
/// fastest rate is `rate` (`h rate / RK4_REACH`, at least 1), or, beyond [`MAX_SPLIT`], the
/// steps it would need as the error: past the cap the explicit integration is unstable,
/// and a split clamped to it let the run diverge after minutes, blamed on the bandwidth.
pub(super) fn split_for(h: f64, rate: f64) -> std::result::Result<usize, f64> {
    let needed = (h * rate / RK4_REACH).ceil();
    if needed > MAX_SPLIT {
        Err(needed)
    } else {
        Ok(needed.max(1.0) as usize)
    }
}

/// [`SimulateError::TooStiff`] in the interval after reference sample `k` (at `t`), for a
/// substep `h` that needs `needed` steps at `rate`, with `cause`.
pub(super) fn too_stiff(k: usize, t: f64, rate: f64, h: f64, needed: f64, cause: String) -> Error {
    Error::Simulate(SimulateError::TooStiff {
        time: t,
        sample: k,
        rate,
        step: h,
        needed,
        limit: MAX_SPLIT as usize,
        cause,
    })
}

/// The fastest rate the integration follows with a substep of `h` seconds, 1/s.
pub(super) fn reach(h: f64) -> f64 {
    MAX_SPLIT * RK4_REACH / h
}

/// The cause of [`SimulateError::TooStiff`] when the controller's rate `loop_rate`
/// (`2 zeta wn + wn` on a rigid plant, `kd / B + sqrt(kp / B)` on a flexible joint's rotor;
/// either proportional to the bandwidth) of a loop of `bandwidth` Hz is most of the plant's `rate`: the
/// bandwidth that fits the substep `h`.
pub(super) fn bandwidth_cause(bandwidth: f64, loop_rate: f64, h: f64, rate: f64) -> String {
    let fits = bandwidth * (reach(h) - (rate - loop_rate)).max(0.0) / loop_rate;
    format!(
        "the controller bandwidth, {} Hz, makes most of it ({} 1/s): lower the bandwidth \
         (--bandwidth) below about {} Hz, or sample the trajectory faster",
        crate::Num(bandwidth),
        crate::Num::rounded(loop_rate, 3),
        crate::Num::rounded(fits, 2)
    )
}

/// The cause of [`SimulateError::TooStiff`] of a rigid plant whose velocity-dependent
/// torques make its fastest rate, `damping` of the whole `rate` (1/s) at positions `q`,
/// mostly through the velocity of `joint` (from 0): its viscous friction `Fv` over the
/// inertia it moves when the model has that parameter and it makes most of that column of
/// dh/dqd, else both candidates (the friction and the Coriolis and centrifugal torques of
/// a light link).
fn rigid_cause<M: Model + ?Sized>(
    model: &M,
    base: &[f64],
    q: &[f64],
    joint: usize,
    damping: f64,
    h: f64,
    rate: f64,
) -> String {
    let n = q.len();
    let mut m = vec![0.0; n * n];
    // the inertia the joint moves with the others free, 1 / (M^-1)_jj: its friction's
    // rate is Fv over it
    let inertia = match model.mass_matrix_into(q, base, &mut m) {
        Ok(()) => nalgebra::DMatrix::from_row_slice(n, n, &m)
            .try_inverse()
            .map_or(f64::NAN, |inverse| 1.0 / inverse[(joint, joint)]),
        Err(_) => f64::NAN,
    };
    let j = joint + 1;
    let name = format!("Fv{j}");
    let fv = (0..base.len())
        .find(|&i| model.base_parameter_name(i) == Some(name.as_str()))
        .map(|i| base[i]);
    // the rate of the friction alone: Fv over the joint's inertia
    let of_friction = fv.map(|fv| fv.abs() / inertia).filter(|r| r.is_finite());
    let fits = |value: f64| {
        crate::Num::rounded(
            value.abs() * (reach(h) - (rate - damping)).max(0.0) / damping,
            2,
        )
    };
    match (fv, of_friction) {
        (Some(fv), Some(r)) if r >= 0.5 * damping => format!(
            "the viscous friction of joint {j}, {name} = {} N m s/rad, on the little inertia \
             it moves ({} kg m^2 at this state, 1 / (M^-1){j}{j}: a rate of {} 1/s) makes \
             it: check {name} and the inertia of the links joint {j} moves in the parameters; \
             the integration follows {name} below about {} N m s/rad at this inertia",
            crate::Num(fv),
            crate::Num::rounded(inertia, 3),
            crate::Num::rounded(r, 3),
            fits(fv)
        ),
        _ => format!(
            "the torques that change with the velocity of joint {j} make it, on the little \
             inertia they move ({} kg m^2 at this state, 1 / (M^-1){j}{j}): its viscous friction \
             ({}) or the Coriolis and centrifugal torques of a light link; check the \
             friction and the inertias of the links joint {j} moves in the parameters",
            crate::Num::rounded(inertia, 3),
            match fv {
                Some(fv) => format!("{name} = {}", crate::Num(fv)),
                None => format!("the model has no {name}"),
            }
        ),
    }
}

/// The Runge-Kutta steps a run has taken, counted against [`MAX_SIMULATION_STEPS`] with
/// the splits of every substep: the check before a run counts samples x substeps, and a
/// stiff plant splits each substep up to [`MAX_SPLIT`] times, so a run that check allowed
/// could take 1,000 times as long (hours).
pub(super) struct StepBudget {
    used: usize,
    cap: usize,
}

#[cfg(test)]
thread_local! {
    /// The cap of the runs of this test thread: a test of the cap lowers it, so that a run
    /// that would take hours stops in milliseconds.
    pub(crate) static STEP_CAP: std::cell::Cell<usize> =
        const { std::cell::Cell::new(MAX_SIMULATION_STEPS) };
}

impl StepBudget {
    pub(super) fn new() -> StepBudget {
        #[cfg(test)]
        let cap = STEP_CAP.with(std::cell::Cell::get);
        #[cfg(not(test))]
        let cap = MAX_SIMULATION_STEPS;
        StepBudget { used: 0, cap }
    }

    /// Takes the `split` steps of one substep of the interval after reference sample `k`
    /// (of `samples`, at time `t`), where the plant's fastest rate is `rate`; refused, before
    /// any is taken, when they pass the cap: the error names the sample, the rate and the
    /// split, and `cause` (what makes this plant stiff, and what to change).
    pub(super) fn take(
        &mut self,
        split: usize,
        rate: f64,
        k: usize,
        samples: usize,
        t: f64,
        cause: &str,
    ) -> Result<()> {
        self.used = self.used.saturating_add(split);
        if self.used <= self.cap {
            return Ok(());
        }
        Err(Error::TooLarge {
            what: format!(
                "Runge-Kutta steps of the simulation, reached after reference sample {k} of \
                 {samples} (t = {} s), where the plant's fastest rate, {rate:.3e} 1/s, splits \
                 each substep into {split} steps",
                crate::Num(t)
            ),
            found: self.used as f64,
            limit: self.cap,
            fix: format!(
                "the plant is far stiffer than its motion: {cause}, or shorten the trajectory"
            ),
        })
    }
}

/// The Coulomb friction of a model apart from its other terms, for the feed-forward that
/// takes it at the joint's own velocity (see [`Simulation::run`]).
struct Coulomb {
    /// The base parameters with the Coulomb levels set to zero.
    smooth: Vec<f64>,
    /// The Coulomb levels alone (every other base parameter zero), when one is not zero.
    levels: Option<Vec<f64>>,
    /// Per Coulomb level, its joint (from 0) and value: `Fcj` is `Fc_j sign(qd_j)` in row
    /// j (docs/conventions.md), so the friction torques need no inverse dynamics; `None`
    /// when the model's own inverse dynamics with `levels` does not agree (then it computes
    /// them).
    joints: Option<Vec<(usize, f64)>>,
}

impl Coulomb {
    /// The Coulomb levels of `model` with base parameters `base`: those named `Fc1`,
    /// `Fc2`, ...
    fn new<M: Model + ?Sized>(model: &M, base: &[f64]) -> Result<Coulomb> {
        let n = model.dof();
        let mut smooth = base.to_vec();
        let mut levels = vec![0.0; base.len()];
        let mut joints = Vec::new();
        for (i, value) in base.iter().enumerate() {
            let joint = model
                .base_parameter_name(i)
                .and_then(|name| name.strip_prefix("Fc"))
                .filter(|j| j.bytes().all(|b| b.is_ascii_digit()))
                .and_then(|j| j.parse::<usize>().ok())
                .filter(|j| (1..=n).contains(j));
            if let Some(j) = joint {
                (smooth[i], levels[i]) = (0.0, *value);
                joints.push((j - 1, *value));
            }
        }
        if levels.iter().all(|&c| c == 0.0) {
            return Ok(Coulomb {
                smooth: base.to_vec(),
                levels: None,
                joints: None,
            });
        }
        let mut coulomb = Coulomb {
            smooth,
            levels: Some(levels),
            joints: Some(joints),
        };
        // the direct torques checked against the model's at velocities of either sign and 0
        let (mut direct, mut own) = (vec![0.0; n], vec![0.0; n]);
        let probe: Vec<f64> = (0..n).map(|j| [0.7, -1.3, 0.0][j % 3]).collect();
        coulomb.torques(model, &probe, &probe, &mut direct)?;
        let joints = coulomb.joints.take();
        coulomb.torques(model, &probe, &probe, &mut own)?;
        let scale = base.iter().fold(1.0, |m, v| v.abs().max(m));
        let agree = direct
            .iter()
            .zip(&own)
            .all(|(a, b)| (a - b).abs() <= 1e-12 * scale);
        coulomb.joints = joints.filter(|_| agree);
        Ok(coulomb)
    }

    /// The Coulomb friction torques at the velocities `qd` (and positions `q`, on which
    /// they do not depend) into `out`.
    fn torques<M: Model + ?Sized>(
        &self,
        model: &M,
        q: &[f64],
        qd: &[f64],
        out: &mut [f64],
    ) -> std::result::Result<(), crate::LengthError> {
        out.iter_mut().for_each(|t| *t = 0.0);
        match (&self.joints, &self.levels) {
            (Some(joints), _) => {
                for &(j, level) in joints {
                    out[j] += level * crate::Real::sign(qd[j]);
                }
            }
            (None, Some(levels)) => {
                let zero = vec![0.0; q.len()];
                model.inverse_dynamics_into(q, qd, &zero, levels, out)?;
            }
            (None, None) => {}
        }
        Ok(())
    }
}

/// A bound on the damping rates of the plant at (q, qd): the infinity norm of
/// M^-1 dh/dqd, with dh/dqd by one-sided differences away from zero velocity (so that a
/// Coulomb term's sign does not flip); with the joint (from 0) whose velocity makes the
/// largest term of the largest row, for the error of a plant too stiff to integrate.
fn damping_rate<M: Model + ?Sized>(
    model: &M,
    base: &[f64],
    q: &[f64],
    qd: &[f64],
) -> Result<(f64, usize)> {
    let n = q.len();
    let zero = vec![0.0; n];
    let mut m = vec![0.0; n * n];
    model.mass_matrix_into(q, base, &mut m)?;
    let (mut h0, mut h1) = (vec![0.0; n], vec![0.0; n]);
    model.inverse_dynamics_into(q, qd, &zero, base, &mut h0)?;
    let mut d = nalgebra::DMatrix::zeros(n, n);
    let mut shifted = qd.to_vec();
    for k in 0..n {
        let eps = 1e-6 * (1.0 + qd[k].abs()) * if qd[k] < 0.0 { -1.0 } else { 1.0 };
        shifted[k] = qd[k] + eps;
        model.inverse_dynamics_into(q, &shifted, &zero, base, &mut h1)?;
        shifted[k] = qd[k];
        for i in 0..n {
            d[(i, k)] = (h1[i] - h0[i]) / eps;
        }
    }
    let chol = forward::factor(&m, n).ok_or_else(|| {
        forward::singular(
            format!("the mass matrix M(q) of {} at q = {q:?}", model.name()),
            &m,
            n,
        )
    })?;
    let b = chol.solve(&d);
    let (mut rate, mut joint) = (0.0, 0);
    for i in 0..n {
        let row = (0..n).map(|j| b[(i, j)].abs()).sum::<f64>();
        if row > rate {
            rate = row;
            joint = (0..n)
                .max_by(|&a, &c| b[(i, a)].abs().total_cmp(&b[(i, c)].abs()))
                .unwrap_or(0);
        }
    }
    Ok((rate, joint))
}

/// One classical Runge-Kutta step of q'' = f(t, q, q') over `h`: `f(c, q, qd, acc)` gives
/// the acceleration at the fraction `c` of the step. Fourth order, so the positions it
/// integrates agree with the accelerations and torques recorded at the samples (a
/// first-order step's error, amplified by the PD loop, made them differ by 24 % at 10
/// substeps and a 10 Hz loop, which anyone differentiating the positions saw as biased
/// inertias).
pub(super) fn rk4_step(
    f: &mut impl FnMut(f64, &[f64], &[f64], &mut [f64]) -> Result<()>,
    q: &mut [f64],
    qd: &mut [f64],
    h: f64,
) -> Result<()> {
    let n = q.len();
    let (mut a1, mut a2, mut a3, mut a4) = (vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let (mut qs, mut vs) = (vec![0.0; n], vec![0.0; n]);
    f(0.0, q, qd, &mut a1)?;
    for j in 0..n {
        qs[j] = q[j] + 0.5 * h * qd[j];
        vs[j] = qd[j] + 0.5 * h * a1[j];
    }
    let v2 = vs.clone();
    f(0.5, &qs, &vs, &mut a2)?;
    for j in 0..n {
        qs[j] = q[j] + 0.5 * h * v2[j];
        vs[j] = qd[j] + 0.5 * h * a2[j];
    }
    let v3 = vs.clone();
    f(0.5, &qs, &vs, &mut a3)?;
    for j in 0..n {
        qs[j] = q[j] + h * v3[j];
        vs[j] = qd[j] + h * a3[j];
    }
    let v4 = vs.clone();
    f(1.0, &qs, &vs, &mut a4)?;
    for j in 0..n {
        q[j] += h / 6.0 * (qd[j] + 2.0 * v2[j] + 2.0 * v3[j] + v4[j]);
        qd[j] += h / 6.0 * (a1[j] + 2.0 * a2[j] + 2.0 * a3[j] + a4[j]);
    }
    Ok(())
}

#[cfg(test)]
mod interpolation_tests {
    use super::quintic;

    /// A quintic polynomial is reproduced exactly, with its velocity and acceleration; the
    /// ends are the samples.
    #[test]
    fn quintic_hermite_is_exact_for_quintics() {
        let p = |t: f64| {
            [0.3, -1.2, 0.7, 2.0, -0.5, 0.9]
                .iter()
                .rev()
                .fold(0.0, |acc, c| acc * t + c)
        };
        let v = |t: f64| {
            -1.2 + 2.0 * 0.7 * t + 3.0 * 2.0 * t * t - 4.0 * 0.5 * t.powi(3) + 5.0 * 0.9 * t.powi(4)
        };
        let a = |t: f64| 2.0 * 0.7 + 6.0 * 2.0 * t - 12.0 * 0.5 * t * t + 20.0 * 0.9 * t.powi(3);
        let (t0, t1) = (0.4, 0.65);
        let at = |t: f64| [vec![p(t)], vec![v(t)], vec![a(t)]];
        let mut out = [vec![0.0], vec![0.0], vec![0.0]];
        for s in [0.0, 0.1, 0.37, 0.5, 0.9, 1.0] {
            quintic(s, t1 - t0, &at(t0), &at(t1), &mut out);
            let t = t0 + s * (t1 - t0);
            assert!((out[0][0] - p(t)).abs() < 1e-13, "q at {s}");
            assert!((out[1][0] - v(t)).abs() < 1e-12, "qd at {s}");
            assert!((out[2][0] - a(t)).abs() < 1e-10, "qdd at {s}");
        }
    }
}

#[cfg(test)]
mod coulomb_tests {
    use super::{Coulomb, Simulation};
    use crate::Model;
    use crate::signal::Signals;
    use crate::simulate::Trajectory;
    use crate::simulate::tests::Pendulum;

    /// The pendulum with a light second link, like a gripper's jaw (0.012 kg, 1.6e-5 kg m^2
    /// about its joint, SO-101's), and Coulomb friction of 0.07 N m on it: 4,400 rad/s^2
    /// over its inertia.
    fn light() -> Vec<f64> {
        let mut base = Pendulum::default().base();
        (base[1], base[2], base[3], base[8], base[9]) = (1.6e-5, 1e-4, 0.0, 2e-3, 0.07);
        base
    }

    /// Both joints out and back along `0.5 a (1 - cos(2 pi t / T))^2 / 2` over T = 3 s, then
    /// 1 s at rest, at 500 Hz: a start, two reversals and a stop of each joint.
    fn out_and_back() -> Trajectory {
        let (rate, period) = (500.0, 3.0);
        let t: Vec<f64> = (0..2000).map(|k| k as f64 / rate).collect();
        let w = std::f64::consts::TAU / period;
        let at = |t: f64, j: usize| -> [f64; 3] {
            if t >= period {
                return [0.0; 3];
            }
            let a = [0.6, -0.9][j];
            let (s, c) = (w * t).sin_cos();
            [
                0.25 * a * (1.0 - c).powi(2),
                0.5 * a * w * (1.0 - c) * s,
                0.5 * a * w * w * (s * s + (1.0 - c) * c),
            ]
        };
        let signal = |i: usize| -> Signals {
            Signals::new(
                (0..2)
                    .map(|j| t.iter().map(|&t| at(t, j)[i]).collect())
                    .collect(),
            )
            .unwrap()
        };
        Trajectory {
            t: t.clone(),
            q: signal(0),
            qd: signal(1),
            qdd: signal(2),
        }
    }

    /// A light link with Coulomb friction tracks its reference: the feed-forward takes the
    /// friction at the joint's own velocity, so `Fc sign(qd)` cancels in the closed loop.
    /// It took it at the reference's: where the two velocities differ in sign (at a stop
    /// or a reversal), the discontinuous difference, 2 Fc over the link's inertia, made the
    /// link chatter about zero velocity, out of reach of the PD loop and of the integration
    /// step: here 0.071 rad off the reference, still at 0.15 rad/s at the end of the rest,
    /// with recorded accelerations of 4,559 rad/s^2 for the reference's 3.95 (and the heavy
    /// first link 3.9e-6 rad off). The records satisfy the model with its own `sign(0) = 0`.
    #[test]
    fn a_light_link_with_coulomb_friction_tracks_its_reference() {
        let p = Pendulum::default();
        let base = light();
        let r = out_and_back();
        let out = Simulation::default().run(&p, &base, &r).unwrap();
        let tr = &out.truth.trajectory;
        let last = r.samples() - 1;
        let largest = |s: &[f64]| s.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        for j in 0..2 {
            let error = (0..r.samples())
                .map(|k| (tr.q[j][k] - r.q[j][k]).abs())
                .fold(0.0, f64::max);
            // measured 1.8e-13 and 2.7e-13 rad
            assert!(error < 1e-8, "joint {}: tracking error {error}", j + 1);
            let (qdd, reference) = (largest(&tr.qdd[j]), largest(&r.qdd[j]));
            // measured: the reference's to 1e-8
            assert!(
                qdd < 1.01 * reference,
                "joint {}: qdd {qdd} for {reference}",
                j + 1
            );
            // measured 4e-36 rad/s
            assert!(
                tr.qd[j][last].abs() < 1e-6,
                "joint {}: {}",
                j + 1,
                tr.qd[j][last]
            );
        }
        let mut tau = [0.0; 2];
        for k in 0..r.samples() {
            let s = |v: &Signals| [v[0][k], v[1][k]];
            p.inverse_dynamics_into(&s(&tr.q), &s(&tr.qd), &s(&tr.qdd), &base, &mut tau)
                .unwrap();
            for (t, truth) in tau.iter().zip(out.truth.tau.joints()) {
                assert!((t - truth[k]).abs() < 1e-9, "sample {k}: {t} {}", truth[k]);
            }
        }
    }

    /// The Coulomb levels are found by name and computed directly, as the model does
    /// (`sign(0) = 0`); without any the feed-forward is the model's inverse dynamics alone.
    #[test]
    fn coulomb_levels_are_found_by_name() {
        let p = Pendulum::default();
        let base = p.base();
        let c = Coulomb::new(&p, &base).unwrap();
        assert_eq!(c.joints, Some(vec![(0, 0.9), (1, 0.4)]));
        assert_eq!(c.smooth[7], 0.0);
        assert_eq!(c.smooth[9], 0.0);
        let mut out = [0.0; 2];
        c.torques(&p, &[0.0; 2], &[-0.1, 0.0], &mut out).unwrap();
        assert_eq!(out, [-0.9, 0.0]);
        let mut none = base.clone();
        (none[7], none[9]) = (0.0, 0.0);
        let c = Coulomb::new(&p, &none).unwrap();
        assert!(c.levels.is_none() && c.joints.is_none());
        assert_eq!(c.smooth, none);
    }
}

#[cfg(test)]
mod consistency_tests {
    use super::Simulation;
    use crate::Model;
    use crate::signal::Signals;
    use crate::simulate::Trajectory;
    use crate::simulate::tests::Pendulum;

    /// What the simulator records at the samples agrees with the motion it integrates:
    /// the second differences of the simulated positions equal the recorded accelerations
    /// (which satisfy the model with the recorded torques) to 1.5e-6 RMS at worst, with
    /// friction and the default 10 Hz loop. (The first-order scheme missed by 24 %; a
    /// differentiating identification then saw inertias biased by 4-6 %.)
    #[test]
    fn positions_agree_with_the_recorded_accelerations() {
        let rate = 500.0;
        let t: Vec<f64> = (0..2000).map(|k| k as f64 / rate).collect();
        let w = [1.3, 2.1];
        let joint = |f: &dyn Fn(f64, f64) -> f64| -> Signals {
            Signals::new(
                w.iter()
                    .map(|&w| t.iter().map(|&t| f(w, t)).collect())
                    .collect(),
            )
            .unwrap()
        };
        let reference = Trajectory {
            t: t.clone(),
            q: joint(&|w, t| 0.8 * (w * t).sin()),
            qd: joint(&|w, t| 0.8 * w * (w * t).cos()),
            qdd: joint(&|w, t| -0.8 * w * w * (w * t).sin()),
        };
        let model = Pendulum::default();
        let run = Simulation::default()
            .run(&model, &model.base(), &reference)
            .unwrap();
        let tr = &run.truth.trajectory;
        let dt = 1.0 / rate;
        for j in 0..2 {
            let (mut e2, mut a2) = (0.0, 0.0);
            for k in 1..t.len() - 1 {
                let c = (tr.q[j][k + 1] - 2.0 * tr.q[j][k] + tr.q[j][k - 1]) / (dt * dt);
                e2 += (c - tr.qdd[j][k]).powi(2);
                a2 += tr.qdd[j][k].powi(2);
            }
            let ratio = (e2 / a2).sqrt();
            // measured 5.6e-7 and 1.47e-6
            assert!(ratio < [1.1e-6, 2.9e-6][j], "joint {}: {ratio}", j + 1);
        }
    }

    /// The PD loop reads the positions the log writes, as a robot's loop reads the encoders
    /// it logs: the position each recorded torque answers, `q_ref - (pd - kd (qd_ref - qd))
    /// / kp` with `pd = M(q)^-1 (tau - ID(ref))`, is the recorded measurement (measured
    /// within 3.5e-18 rad). The log drew its position noise apart from the loop's: here
    /// 5.1e-3 rad apart at worst for sigma = 1e-3, and through `robid simulate
    /// --position-noise 0.002` on the UR5 (checked with Pinocchio) 2.7e-3 to 2.8e-3 rad RMS
    /// per joint, sqrt(2) sigma, as two independent draws are.
    #[test]
    fn the_loop_reads_the_logged_positions() {
        use super::Noise;
        let rate = 500.0;
        let t: Vec<f64> = (0..500).map(|k| k as f64 / rate).collect();
        let joint = |f: &dyn Fn(f64, f64) -> f64| -> Signals {
            Signals::new(
                [1.3, 2.1]
                    .iter()
                    .map(|&w| t.iter().map(|&t| f(w, t)).collect())
                    .collect(),
            )
            .unwrap()
        };
        let r = Trajectory {
            t: t.clone(),
            q: joint(&|w, t| 0.8 * (w * t).sin()),
            qd: joint(&|w, t| 0.8 * w * (w * t).cos()),
            qdd: joint(&|w, t| -0.8 * w * w * (w * t).sin()),
        };
        let model = Pendulum::default();
        // no Coulomb friction: the feed-forward is the inverse dynamics of the reference
        let mut base = model.base();
        (base[7], base[9]) = (0.0, 0.0);
        let sigma = 1e-3;
        let simulation = Simulation {
            noise: Noise {
                position: sigma,
                ..Noise::default()
            },
            ..Simulation::default()
        };
        let run = simulation.run(&model, &base, &r).unwrap();
        let wn = std::f64::consts::TAU * simulation.bandwidth;
        let (kp, kd) = (wn * wn, 2.0 * simulation.damping * wn);
        let (tr, me) = (&run.truth.trajectory, &run.measured.trajectory);
        let (mut worst, mut spread) = (0.0_f64, 0.0);
        let (mut ff, mut mass) = ([0.0; 2], [0.0; 4]);
        for k in 0..r.samples() {
            let s = |v: &Signals| [v[0][k], v[1][k]];
            model
                .inverse_dynamics_into(&s(&r.q), &s(&r.qd), &s(&r.qdd), &base, &mut ff)
                .unwrap();
            model.mass_matrix_into(&s(&tr.q), &base, &mut mass).unwrap();
            let b = [run.truth.tau[0][k] - ff[0], run.truth.tau[1][k] - ff[1]];
            let det = mass[0] * mass[3] - mass[1] * mass[2];
            let pd = [
                (mass[3] * b[0] - mass[1] * b[1]) / det,
                (mass[0] * b[1] - mass[2] * b[0]) / det,
            ];
            for (j, pd) in pd.iter().enumerate() {
                let read = r.q[j][k] - (pd - kd * (r.qd[j][k] - tr.qd[j][k])) / kp;
                worst = worst.max((read - me.q[j][k]).abs());
                spread += (me.q[j][k] - tr.q[j][k]).powi(2);
            }
        }
        // the noise is there: the log's positions are sigma from the truth
        let spread = (spread / (2 * r.samples()) as f64).sqrt();
        assert!((0.9 * sigma..1.1 * sigma).contains(&spread), "{spread}");
        assert!(
            worst < 1e-12,
            "the loop read {worst} rad from the logged position"
        );
    }
}
