//! Closed-loop simulation along a reference trajectory (docs/identification.md#simulation).
//!
//! The controller computes tau = tau_ff + Kp (q_ref - q_meas) + Kd (qd_ref - qd), with the
//! computed-torque feed-forward tau_ff = ID(q_ref, qd_ref, qdd_ref) of the true model
//! (optional) and per-joint gains Kp = wn^2 M_jj(q_ref(0)), Kd = 2 zeta wn M_jj(q_ref(0)).
//! The plant M(q) qdd = tau - h(q, qd) (see [`ForwardDynamics`]) is integrated with
//! `substeps` fixed linearly implicit steps per reference interval, the controller running
//! at every step on the linearly interpolated reference. At each reference sample the
//! state, the applied torque and qdd = M^-1 (tau - h) are recorded, so the true record
//! satisfies the model exactly. Measurements: positions quantized to the encoder
//! resolution plus Gaussian noise; torques plus Gaussian noise; velocities and
//! accelerations are the true ones (plus optional Gaussian noise).
//!
//! Checks: the settings ([`Simulation::check`]: bandwidth up to [`MAX_BANDWIDTH`] Hz,
//! 1 to [`MAX_SUBSTEPS`] substeps, at most [`MAX_SIMULATION_STEPS`] integration steps in
//! all), the base parameters (finite, magnitude at most
//! [`MAX_PARAMETER`](crate::limits::MAX_PARAMETER); M(q) positive definite at the
//! reference's first state, else the parameters are blamed), the reference (finite and
//! within the ranges of [`crate::limits`], a bad sample named by its index and time). At
//! every reference sample the run is checked for divergence: a non-finite state, a
//! tracking error above [`DIVERGENCE_FACTOR`] times (the joint's reference range + 1 rad),
//! or a torque above [`MAX_TORQUE`](crate::limits::MAX_TORQUE) ends it with
//! [`crate::SimulateError::Diverged`], which says whether the controller is too fast for the integration
//! step.

use crate::DataError;
use crate::Model;
use crate::SimulateError;
use crate::error::{Error, Result, num};
use crate::excite::check_parameters;
use crate::limits::{MAX_ACCELERATION, MAX_POSITION, MAX_TORQUE, MAX_VELOCITY};

/// Largest controller bandwidth (Hz).
pub const MAX_BANDWIDTH: f64 = 1e6;
/// Largest number of substeps per reference interval.
pub const MAX_SUBSTEPS: usize = 10_000;
/// Largest number of integration steps of a run (reference samples x substeps).
pub const MAX_SIMULATION_STEPS: usize = 200_000_000;
/// A tracking error above this many times (the joint's reference range + 1 rad or m) is a
/// diverged simulation.
pub const DIVERGENCE_FACTOR: f64 = 10.0;
use crate::rng::Rng;
use crate::signal::Signals;
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
                    "{} values for a model of {dof} joints; give one value or one per joint",
                    n.torque.len()
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
        let mut fd = ForwardDynamics::new(model, base)?;
        check_parameters("Simulation::run", "base", model, base)?;
        let mut rng = Rng::new(self.seed);
        let mut r0 = [vec![0.0; n], vec![0.0; n], vec![0.0; n]];
        let mut r1 = r0.clone();
        let [q0, qd0, qdd0] = &mut r0;
        reference.state(0, q0, qd0, qdd0);
        let mut m = vec![0.0; n * n];
        model.mass_matrix_into(&r0[0], base, &mut m)?;
        if nalgebra::DMatrix::from_row_slice(n, n, &m)
            .cholesky()
            .is_none()
        {
            return Err(Error::Singular {
                what: format!(
                    "the mass matrix M(q) of {} at the reference's first state q = {:?}",
                    model.name(),
                    r0[0]
                ),
                hint: "the parameters are not physically consistent; use a feasible parameter set (robid feasible)",
            });
        }
        let wn = std::f64::consts::TAU * self.bandwidth;
        let kp: Vec<f64> = (0..n).map(|j| wn * wn * m[j * n + j]).collect();
        let kd: Vec<f64> = (0..n)
            .map(|j| 2.0 * self.damping * wn * m[j * n + j])
            .collect();
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
            let h = dt / self.substeps as f64;
            let fix = if wn * h > 0.5 {
                format!(
                    "the controller bandwidth {} Hz is too high for the integration step {h:.3e} s \
                     ({:.6} Hz reference, {} substeps): lower the bandwidth below {:.3} Hz or raise \
                     the substeps or the trajectory's sample rate",
                    self.bandwidth,
                    1.0 / dt,
                    self.substeps,
                    0.5 / (std::f64::consts::TAU * h)
                )
            } else {
                "check the reference trajectory near this sample (its velocities and accelerations \
                 must be the derivatives of its positions, within the robot's limits) and the \
                 parameters"
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
        let control = |r: &[Vec<f64>; 3], q: &[f64], qd: &[f64], rng: &mut Rng, tau: &mut [f64]| {
            if self.feedforward {
                model.inverse_dynamics_into(&r[0], &r[1], &r[2], base, tau)?;
            } else {
                tau.iter_mut().for_each(|t| *t = 0.0);
            }
            for j in 0..n {
                let e = r[0][j] - self.measure_position(q[j], rng);
                tau[j] += kp[j] * e + kd[j] * (r[1][j] - qd[j]);
            }
            Ok::<(), crate::LengthError>(())
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
            e => e,
        };
        for k in 0..samples {
            let [a, b, c] = &mut r0;
            reference.state(k, a, b, c);
            control(&r0, &q, &qd, &mut rng, &mut tau)?;
            check(k, &r0, &q, &qd, &tau)?;
            fd.accelerations(&q, &qd, &tau, &mut qdd)
                .map_err(|e| inconsistent(k, &q, e))?;
            for j in 0..n {
                let tr = &mut truth.trajectory;
                (tr.q[j][k], tr.qd[j][k], tr.qdd[j][k]) = (q[j], qd[j], qdd[j]);
                truth.tau[j][k] = tau[j];
                let me = &mut measured.trajectory;
                me.q[j][k] = self.measure_position(q[j], &mut rng);
                me.qd[j][k] = qd[j] + self.noise.velocity * rng.normal();
                me.qdd[j][k] = qdd[j] + self.noise.acceleration * rng.normal();
                measured.tau[j][k] = tau[j] + sigma_tau(j) * rng.normal();
            }
            if k + 1 < samples {
                let [a, b, c] = &mut r1;
                reference.state(k + 1, a, b, c);
                let h = (reference.t[k + 1] - reference.t[k]) / self.substeps as f64;
                for i in 0..self.substeps {
                    let s = i as f64 / self.substeps as f64;
                    for (x, (x0, x1)) in r.iter_mut().zip(r0.iter().zip(&r1)) {
                        for j in 0..n {
                            x[j] = x0[j] + s * (x1[j] - x0[j]);
                        }
                    }
                    control(&r, &q, &qd, &mut rng, &mut tau)?;
                    step(&mut fd, &mut q, &mut qd, &tau, &kd, h)
                        .map_err(|e| inconsistent(k, &q, e))?;
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

    fn measure_position(&self, q: f64, rng: &mut Rng) -> f64 {
        let r = self.noise.quantization;
        let quantized = if r > 0.0 { (q / r).round() * r } else { q };
        quantized + self.noise.position * rng.normal()
    }
}

/// One linearly implicit (Rosenbrock-Euler) step, stable for the stiff damping of viscous
/// friction and the PD loop on light links: with D = dh/dqd (by one-sided differences away
/// from zero velocity, so Coulomb signs do not flip) and the controller's Kd,
/// (M + h (D + Kd)) dqd = h (tau - h(q, qd)); qd += dqd; q += h qd (semi-implicit).
fn step<M: Model + ?Sized>(
    fd: &mut ForwardDynamics<'_, M>,
    q: &mut [f64],
    qd: &mut [f64],
    tau: &[f64],
    kd: &[f64],
    h: f64,
) -> Result<()> {
    let n = q.len();
    let model = fd.model();
    let base = fd.base();
    let zero = vec![0.0; n];
    let mut m = vec![0.0; n * n];
    model.mass_matrix_into(q, base, &mut m)?;
    let mut h0 = vec![0.0; n];
    model.inverse_dynamics_into(q, qd, &zero, base, &mut h0)?;
    let mut a = nalgebra::DMatrix::from_row_slice(n, n, &m);
    let mut shifted = qd.to_vec();
    let mut h1 = vec![0.0; n];
    for k in 0..n {
        let eps = 1e-6 * (1.0 + qd[k].abs()) * if qd[k] < 0.0 { -1.0 } else { 1.0 };
        shifted[k] = qd[k] + eps;
        model.inverse_dynamics_into(q, &shifted, &zero, base, &mut h1)?;
        shifted[k] = qd[k];
        for i in 0..n {
            a[(i, k)] += h * (h1[i] - h0[i]) / eps;
        }
        a[(k, k)] += h * kd[k];
    }
    let rhs = nalgebra::DVector::from_iterator(n, (0..n).map(|j| h * (tau[j] - h0[j])));
    let dv = a.lu().solve(&rhs).ok_or_else(|| Error::Singular {
        what: format!("implicit step matrix of {} at q = {q:?}", model.name()),
        hint: "the parameters are not physically consistent; use a feasible parameter set",
    })?;
    for j in 0..n {
        qd[j] += dv[j];
        q[j] += h * qd[j];
    }
    Ok(())
}
