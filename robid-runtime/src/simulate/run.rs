//! Closed-loop simulation along a reference trajectory (DESIGN 6.7).
//!
//! At every sample of the reference the controller computes
//! tau = tau_ff + Kp (q_ref - q_meas) + Kd (qd_ref - qd_meas), with the computed-torque
//! feed-forward tau_ff = ID(q_ref, qd_ref, qdd_ref) of the true model (optional), and
//! per-joint gains Kp = wn^2 M_jj(q_ref(0)), Kd = 2 zeta wn M_jj(q_ref(0)). The torque
//! is held over the sample interval while the plant M(q) qdd = tau - h(q, qd) is
//! integrated with `substeps` fixed RK4 steps. Measurements: positions quantized to the
//! encoder resolution plus Gaussian noise; torques plus Gaussian noise; velocities and
//! accelerations are the true ones (plus optional Gaussian noise).

use crate::Model;
use crate::error::{Error, Result};
use crate::simulate::{ForwardDynamics, Record, Rng, Trajectory};

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
    /// RK4 steps per reference sample interval.
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
            substeps: 4,
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
    Error::InvalidConfig {
        key: key.into(),
        problem,
    }
}

impl Simulation {
    /// Checks the settings against a model of `dof` joints.
    pub fn check(&self, dof: usize) -> Result<()> {
        let positive = |x: f64| x > 0.0 && x.is_finite();
        let non_negative = |x: f64| x >= 0.0 && x.is_finite();
        if !positive(self.bandwidth) {
            return Err(invalid(
                "bandwidth",
                format!("{} Hz must be positive", self.bandwidth),
            ));
        }
        if !positive(self.damping) {
            return Err(invalid(
                "damping",
                format!("{} must be positive", self.damping),
            ));
        }
        if self.substeps == 0 {
            return Err(invalid("substeps", "must be at least 1".into()));
        }
        let n = &self.noise;
        if n.torque.len() != 1 && n.torque.len() != dof {
            return Err(Error::JointCountMismatch {
                context: "torque noise".into(),
                expected: dof,
                found: n.torque.len(),
            });
        }
        for (key, x) in [
            ("position noise", n.position),
            ("velocity noise", n.velocity),
            ("acceleration noise", n.acceleration),
            ("quantization", n.quantization),
        ]
        .into_iter()
        .chain(n.torque.iter().map(|&x| ("torque noise", x)))
        {
            if !non_negative(x) {
                return Err(invalid(key, format!("{x} must be zero or positive")));
            }
        }
        Ok(())
    }

    /// Simulates `model` with true base parameters `base` tracking `reference`.
    pub fn run<M: Model + ?Sized>(
        &self,
        model: &M,
        base: &[f64],
        reference: &Trajectory,
    ) -> Result<Simulated> {
        let n = model.dof();
        self.check(n)?;
        if reference.dof() != n {
            return Err(Error::JointCountMismatch {
                context: "reference trajectory".into(),
                expected: n,
                found: reference.dof(),
            });
        }
        let samples = reference.samples();
        let mut fd = ForwardDynamics::new(model, base)?;
        let mut rng = Rng::new(self.seed);
        let (mut qr, mut qdr, mut qddr) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        reference.state(0, &mut qr, &mut qdr, &mut qddr);
        let mut m = vec![0.0; n * n];
        model.mass_matrix(&qr, base, &mut m);
        let wn = std::f64::consts::TAU * self.bandwidth;
        let kp: Vec<f64> = (0..n).map(|j| wn * wn * m[j * n + j]).collect();
        let kd: Vec<f64> = (0..n)
            .map(|j| 2.0 * self.damping * wn * m[j * n + j])
            .collect();
        let (mut q, mut qd) = (qr.clone(), qdr.clone());
        let mut truth = Record {
            trajectory: Trajectory::zeros(n, reference.t.clone()),
            tau: vec![vec![0.0; samples]; n],
        };
        let mut measured = truth.clone();
        let (mut tau, mut qdd) = (vec![0.0; n], vec![0.0; n]);
        let sigma_tau = |j: usize| self.noise.torque[j.min(self.noise.torque.len() - 1)];
        for k in 0..samples {
            reference.state(k, &mut qr, &mut qdr, &mut qddr);
            let q_meas: Vec<f64> = (0..n)
                .map(|j| self.measure_position(q[j], &mut rng))
                .collect();
            if self.feedforward {
                model.inverse_dynamics(&qr, &qdr, &qddr, base, &mut tau);
            } else {
                tau.iter_mut().for_each(|t| *t = 0.0);
            }
            for j in 0..n {
                tau[j] += kp[j] * (qr[j] - q_meas[j]) + kd[j] * (qdr[j] - qd[j]);
            }
            fd.accelerations(&q, &qd, &tau, &mut qdd)?;
            for j in 0..n {
                let tr = &mut truth.trajectory;
                (tr.q[j][k], tr.qd[j][k], tr.qdd[j][k]) = (q[j], qd[j], qdd[j]);
                truth.tau[j][k] = tau[j];
                let me = &mut measured.trajectory;
                me.q[j][k] = q_meas[j];
                me.qd[j][k] = qd[j] + self.noise.velocity * rng.normal();
                me.qdd[j][k] = qdd[j] + self.noise.acceleration * rng.normal();
                measured.tau[j][k] = tau[j] + sigma_tau(j) * rng.normal();
            }
            if k + 1 < samples {
                let h = (reference.t[k + 1] - reference.t[k]) / self.substeps as f64;
                for _ in 0..self.substeps {
                    rk4(&mut fd, &mut q, &mut qd, &tau, h)?;
                }
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

/// One classical Runge-Kutta step of (q, qd)' = (qd, qdd(q, qd, tau)) with tau held.
fn rk4<M: Model + ?Sized>(
    fd: &mut ForwardDynamics<'_, M>,
    q: &mut [f64],
    qd: &mut [f64],
    tau: &[f64],
    h: f64,
) -> Result<()> {
    let n = q.len();
    let mut a = [vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]];
    let mut v = [qd.to_vec(), vec![0.0; n], vec![0.0; n], vec![0.0; n]];
    let (mut qs, mut vs) = (vec![0.0; n], vec![0.0; n]);
    fd.accelerations(q, qd, tau, &mut a[0])?;
    for (stage, c) in [(1, 0.5), (2, 0.5), (3, 1.0)] {
        for j in 0..n {
            qs[j] = q[j] + c * h * v[stage - 1][j];
            vs[j] = qd[j] + c * h * a[stage - 1][j];
        }
        v[stage].copy_from_slice(&vs);
        let (_, rest) = a.split_at_mut(stage);
        fd.accelerations(&qs, &vs, tau, &mut rest[0])?;
    }
    for j in 0..n {
        q[j] += h / 6.0 * (v[0][j] + 2.0 * v[1][j] + 2.0 * v[2][j] + v[3][j]);
        qd[j] += h / 6.0 * (a[0][j] + 2.0 * a[1][j] + 2.0 * a[2][j] + a[3][j]);
    }
    Ok(())
}
