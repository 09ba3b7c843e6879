//! A synthetic 6-joint model for tests and benches: a regressor with the structure of a
//! serial arm (row j depends on links k >= j, trigonometric terms computed once per
//! sample, inertia, Coriolis-like, gravity-like, drive and friction columns), not a real
//! robot. Included by the pipeline tests and by the workspace's `benches/pipeline.rs`.

#![allow(dead_code)]

use super::Model;
use super::Real;
use super::{LengthError, ProgramKind, check_arguments, check_length};

/// Joints.
pub(crate) const DOF: usize = 6;
/// Per-link columns: 4 rigid-body-like, Ia, Fv, Fc, Fo.
const PER_LINK: usize = 8;

/// The synthetic model.
#[derive(Debug)]
pub(crate) struct Synthetic {
    names: Vec<String>,
    /// The columns of the full layout (`DOF * PER_LINK`) this model has, in order.
    keep: Vec<usize>,
}

impl Default for Synthetic {
    fn default() -> Self {
        Self::without(&[])
    }
}

impl Synthetic {
    /// The model without the drive terms `dropped` (e.g. `["Fv", "Fc"]`) of every link.
    pub(crate) fn without(dropped: &[&str]) -> Self {
        let mut names = Vec::new();
        let mut keep = Vec::new();
        for k in 1..=DOF {
            for (i, n) in ["A", "B", "G", "C", "Ia", "Fv", "Fc", "Fo"]
                .into_iter()
                .enumerate()
            {
                if !dropped.contains(&n) {
                    names.push(format!("{n}{k}"));
                    keep.push((k - 1) * PER_LINK + i);
                }
            }
        }
        Self { names, keep }
    }

    /// The regressor of the kept columns.
    fn kept_regressor(&self, q: &[f64], qd: &[f64], qdd: &[f64], out: &mut [f64]) {
        let (p, n) = (DOF * PER_LINK, self.keep.len());
        let mut full = vec![0.0; DOF * p];
        Self::regressor(q, qd, qdd, &mut full);
        for j in 0..DOF {
            for (c, &i) in self.keep.iter().enumerate() {
                out[j * n + c] = full[j * p + i];
            }
        }
    }

    /// The parameters of the kept columns in the full layout (0 elsewhere).
    fn full(&self, base: &[f64]) -> Vec<f64> {
        let mut full = vec![0.0; DOF * PER_LINK];
        for (&i, b) in self.keep.iter().zip(base) {
            full[i] = *b;
        }
        full
    }

    /// The true parameters of the kept columns.
    pub(crate) fn truth(&self) -> Vec<f64> {
        let all = true_parameters();
        self.keep.iter().map(|&i| all[i]).collect()
    }

    fn regressor(q: &[f64], qd: &[f64], qdd: &[f64], out: &mut [f64]) {
        let p = DOF * PER_LINK;
        out[..DOF * p].iter_mut().for_each(|v| *v = 0.0);
        let mut s = [0.0; DOF];
        let mut c = [0.0; DOF];
        for i in 0..DOF {
            (s[i], c[i]) = q[i].sin_cos();
        }
        for k in 0..DOF {
            let base = k * PER_LINK;
            for j in 0..=k {
                let row = &mut out[j * p..(j + 1) * p];
                row[base] = (c[j] * c[k] - s[j] * s[k]) * qdd[k] + s[k] * qd[j] * qd[k];
                row[base + 1] = (s[j] * c[k] - c[j] * s[k]) * qdd[j] + c[k] * qd[k] * qd[k];
                row[base + 2] = c[k] * s[j] + c[j];
                row[base + 3] = s[k] * c[j] * (qdd[j] + qdd[k]) + c[j] * qd[k];
            }
            let row = &mut out[k * p..(k + 1) * p];
            row[base + 4] = qdd[k];
            row[base + 5] = qd[k];
            row[base + 6] = qd[k].sign();
            row[base + 7] = 1.0;
        }
    }

    fn torque(q: &[f64], qd: &[f64], qdd: &[f64], base: &[f64], tau: &mut [f64]) {
        let p = DOF * PER_LINK;
        let mut y = vec![0.0; DOF * p];
        Self::regressor(q, qd, qdd, &mut y);
        for (j, t) in tau.iter_mut().enumerate().take(DOF) {
            *t = y[j * p..(j + 1) * p]
                .iter()
                .zip(base)
                .map(|(a, b)| a * b)
                .sum();
        }
    }
}

impl Model for Synthetic {
    fn name(&self) -> &str {
        "synthetic6"
    }
    fn dof(&self) -> usize {
        DOF
    }
    fn standard_parameter_count(&self) -> usize {
        self.names.len()
    }
    fn standard_parameter_name(&self, index: usize) -> Option<&str> {
        self.names.get(index).map(String::as_str)
    }
    fn base_parameter_count(&self) -> usize {
        self.names.len()
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
impl Synthetic {
    fn base_regressor(
        &self,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
        out: &mut [f64],
    ) -> Result<(), LengthError> {
        check_length("q", q, DOF)?;
        check_length("qd", qd, DOF)?;
        check_length("qdd", qdd, DOF)?;
        self.kept_regressor(q, qd, qdd, out);
        Ok(())
    }
    fn standard_regressor(
        &self,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
        out: &mut [f64],
    ) -> Result<(), LengthError> {
        check_length("q", q, DOF)?;
        check_length("qd", qd, DOF)?;
        check_length("qdd", qdd, DOF)?;
        self.kept_regressor(q, qd, qdd, out);
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
        check_length("q", q, DOF)?;
        check_length("qd", qd, DOF)?;
        check_length("qdd", qdd, DOF)?;
        Self::torque(q, qd, qdd, &self.full(base), tau);
        Ok(())
    }
    fn mass_matrix(&self, q: &[f64], base: &[f64], out: &mut [f64]) -> Result<(), LengthError> {
        check_length("q", q, DOF)?;
        let base = &self.full(base);
        let zero = [0.0; DOF];
        let mut g = [0.0; DOF];
        Self::torque(q, &zero, &zero, base, &mut g);
        for i in 0..DOF {
            let mut e = [0.0; DOF];
            e[i] = 1.0;
            let mut t = [0.0; DOF];
            Self::torque(q, &zero, &e, base, &mut t);
            for r in 0..DOF {
                out[r * DOF + i] = t[r] - g[r];
            }
        }
        Ok(())
    }
    fn gravity(&self, q: &[f64], base: &[f64], out: &mut [f64]) -> Result<(), LengthError> {
        check_length("q", q, DOF)?;
        Self::torque(q, &[0.0; DOF], &[0.0; DOF], &self.full(base), out);
        Ok(())
    }
    fn coriolis(
        &self,
        q: &[f64],
        qd: &[f64],
        base: &[f64],
        out: &mut [f64],
    ) -> Result<(), LengthError> {
        check_length("q", q, DOF)?;
        check_length("qd", qd, DOF)?;
        let base = &self.full(base);
        let mut g = [0.0; DOF];
        Self::torque(q, &[0.0; DOF], &[0.0; DOF], base, &mut g);
        Self::torque(q, qd, &[0.0; DOF], base, out);
        for (o, g) in out.iter_mut().zip(g) {
            *o -= g;
        }
        Ok(())
    }
    fn base_from_standard(&self, standard: &[f64], base: &mut [f64]) -> Result<(), LengthError> {
        base.copy_from_slice(standard);
        Ok(())
    }
}

/// True parameter values used with the synthetic model.
pub(crate) fn true_parameters() -> Vec<f64> {
    (0..DOF * PER_LINK)
        .map(|i| 0.5 + ((i * 37 % 11) as f64) * 0.3 * if i % 3 == 0 { -1.0 } else { 1.0 })
        .collect()
}

/// An exciting trajectory (sums of sines) with analytic derivatives at time `t`.
pub(crate) fn trajectory(t: f64, q: &mut [f64], qd: &mut [f64], qdd: &mut [f64]) {
    for j in 0..DOF {
        let (mut a, mut b, mut c) = (0.0, 0.0, 0.0);
        for h in 1..=3 {
            let w = 0.7 * (h as f64) * (1.0 + 0.13 * j as f64);
            let amp = 0.6 / h as f64;
            let ph = 0.9 * j as f64 + h as f64;
            a += amp * (w * t + ph).sin();
            b += amp * w * (w * t + ph).cos();
            c -= amp * w * w * (w * t + ph).sin();
        }
        q[j] = a;
        qd[j] = b;
        qdd[j] = c;
    }
}

/// CSV text `t,q1..q6,tau1..tau6` of `n` samples at `rate` Hz with torques from the true
/// parameters plus deterministic pseudo-noise of amplitude `noise` on every joint.
pub(crate) fn csv(n: usize, rate: f64, noise: f64) -> String {
    csv_with_noise(n, rate, [noise; DOF])
}

/// [`csv`] with a pseudo-noise amplitude per joint.
pub(crate) fn csv_with_noise(n: usize, rate: f64, noise: [f64; DOF]) -> String {
    csv_seeded(n, rate, noise, 7)
}

/// [`csv_with_noise`] with the noise generator's seed: another acquisition of the same
/// trajectory.
pub(crate) fn csv_seeded(n: usize, rate: f64, noise: [f64; DOF], seed: u64) -> String {
    let model = Synthetic::default();
    let beta = true_parameters();
    let mut out = String::from("t,q1,q2,q3,q4,q5,q6,tau1,tau2,tau3,tau4,tau5,tau6\n");
    let (mut q, mut qd, mut qdd, mut tau) = ([0.0; DOF], [0.0; DOF], [0.0; DOF], [0.0; DOF]);
    let mut seed = seed;
    for k in 0..n {
        let t = k as f64 / rate;
        trajectory(t, &mut q, &mut qd, &mut qdd);
        model
            .inverse_dynamics_into(&q, &qd, &qdd, &beta, &mut tau)
            .unwrap();
        out.push_str(&format!("{t}"));
        for v in q {
            out.push_str(&format!(",{v}"));
        }
        for (v, amplitude) in tau.into_iter().zip(noise) {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let r = ((seed >> 11) as f64 / (1u64 << 53) as f64) - 0.5;
            out.push_str(&format!(",{}", v + amplitude * r));
        }
        out.push('\n');
    }
    out
}

/// The config matching [`csv`].
pub(crate) const CONFIG: &str = r#"
dof = 6
time_column = "t"
[[source]]
position = "q{}"
torque = "tau{}"
[processing]
lowpass = { cutoff = 20.0, order = 4, signals = ["q"] }
trim = 200   # filter start-up transients at the ends are amplified by differentiation
decimation = 10
rest_velocity = 0.02
"#;
