//! Finite Fourier series trajectories that start and end every period at rest.
//!
//! Joint j (Swevers et al. 1997, with the constant chosen so that q(0) = q0):
//!   q(t)   = q0 + sum_l [ a_l / (w l) sin(w l t) - b_l / (w l) (cos(w l t) - 1) ]
//!   qd(t)  = sum_l [ a_l cos(w l t) + b_l sin(w l t) ]
//!   qdd(t) = sum_l w l [ -a_l sin(w l t) + b_l cos(w l t) ]
//! with w = 2 pi f the base frequency. Rest at t = 0 (and so at every multiple of the
//! period) holds by construction: a_1 = -sum_{l>1} a_l gives qd(0) = 0 and
//! b_1 = -sum_{l>1} l b_l gives qdd(0) = 0 ([`JointSeries::from_free`]).
//!
//! ## Reference
//! J. Swevers, C. Ganseman, D. B. Tukel, J. De Schutter, H. Van Brussel, "Optimal robot
//! excitation and identification", IEEE Trans. Robotics and Automation 13(5), 1997.

use std::f64::consts::TAU;

use crate::error::{Error, Result};
use crate::simulate::Trajectory;

/// The series of one joint.
#[derive(Debug, Clone, PartialEq)]
pub struct JointSeries {
    /// Position at t = 0 (and at every multiple of the period).
    pub q0: f64,
    /// Sine coefficients of the velocity, a_1..a_N.
    pub a: Vec<f64>,
    /// Cosine coefficients of the velocity, b_1..b_N.
    pub b: Vec<f64>,
}

impl JointSeries {
    /// A series from the free coefficients a_2..a_N, b_2..b_N (`free` holds the N - 1 a's
    /// then the N - 1 b's) with a_1 and b_1 chosen so that the joint starts at rest.
    pub fn from_free(q0: f64, free: &[f64]) -> Self {
        let m = free.len() / 2;
        let (fa, fb) = free.split_at(m);
        let a1 = -fa.iter().sum::<f64>();
        let b1 = -fb
            .iter()
            .enumerate()
            .map(|(i, b)| (i + 2) as f64 * b)
            .sum::<f64>();
        Self {
            q0,
            a: std::iter::once(a1).chain(fa.iter().copied()).collect(),
            b: std::iter::once(b1).chain(fb[..m].iter().copied()).collect(),
        }
    }

    /// (q, qd, qdd) at time t for base frequency `w` (rad/s).
    pub fn eval(&self, w: f64, t: f64) -> [f64; 3] {
        let mut out = [self.q0, 0.0, 0.0];
        for (i, (a, b)) in self.a.iter().zip(&self.b).enumerate() {
            let wl = w * (i + 1) as f64;
            let (s, c) = (wl * t).sin_cos();
            out[0] += a / wl * s - b / wl * (c - 1.0);
            out[1] += a * c + b * s;
            out[2] += wl * (-a * s + b * c);
        }
        out
    }

    /// Multiplies the motion (not q0) by `s`.
    pub fn scale(&mut self, s: f64) {
        self.a
            .iter_mut()
            .chain(self.b.iter_mut())
            .for_each(|x| *x *= s);
    }
}

/// A Fourier trajectory of every joint.
#[derive(Debug, Clone, PartialEq)]
pub struct Fourier {
    /// Base frequency f (Hz); the period is 1 / f.
    pub base_frequency: f64,
    /// One series per joint, all with the same number of harmonics.
    pub joints: Vec<JointSeries>,
}

impl Fourier {
    /// The base angular frequency w = 2 pi f.
    pub fn omega(&self) -> f64 {
        TAU * self.base_frequency
    }

    /// The period 1 / f (s).
    pub fn period(&self) -> f64 {
        1.0 / self.base_frequency
    }

    /// Writes (q, qd, qdd) of every joint at time t.
    pub fn state(&self, t: f64, q: &mut [f64], qd: &mut [f64], qdd: &mut [f64]) {
        let w = self.omega();
        for (j, s) in self.joints.iter().enumerate() {
            [q[j], qd[j], qdd[j]] = s.eval(w, t);
        }
    }

    /// Samples `duration` seconds at `rate` Hz (t = 0, 1/rate, ..., duration inclusive);
    /// a duration that is no whole number of sample periods 1 / rate is an error.
    /// The size is checked before allocating ([`crate::limits::MAX_SAMPLES`]).
    pub fn sample(&self, duration: f64, rate: f64) -> Result<Trajectory> {
        let count = sample_count("Fourier::sample", duration, rate, self.joints.len())?;
        let t: Vec<f64> = (0..count).map(|k| k as f64 / rate).collect();
        let mut tr = Trajectory::zeros(self.joints.len(), t);
        let w = self.omega();
        for (j, s) in self.joints.iter().enumerate() {
            for k in 0..count {
                [tr.q[j][k], tr.qd[j][k], tr.qdd[j][k]] = s.eval(w, tr.t[k]);
            }
        }
        tr.check_finite("Fourier::sample")?;
        Ok(tr)
    }
}

/// Number of samples of `duration` s at `rate` Hz for `dof` joints, both ends included;
/// checks both and the size.
pub(crate) fn sample_count(owner: &str, duration: f64, rate: f64, dof: usize) -> Result<usize> {
    let n = crate::limits::trajectory_samples(owner, duration, rate, dof)?;
    if n < 3 {
        return Err(Error::TooFewSamples {
            context: "trajectory".into(),
            found: n,
            required: 3,
            hint: "raise the duration or the sample rate",
        });
    }
    Ok(n)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn starts_at_rest_and_is_periodic_with_consistent_derivatives() {
        let s = JointSeries::from_free(0.4, &[0.3, -0.2, 0.1, 0.5, 0.25, -0.4]);
        let w = TAU * 0.2;
        let [q, qd, qdd] = s.eval(w, 0.0);
        assert!((q - 0.4).abs() < 1e-14 && qd.abs() < 1e-14 && qdd.abs() < 1e-12);
        let end = s.eval(w, 5.0);
        assert!((end[0] - 0.4).abs() < 1e-12 && end[1].abs() < 1e-12 && end[2].abs() < 1e-12);
        let (t, h) = (1.3, 1e-5);
        let (p, m) = (s.eval(w, t + h), s.eval(w, t - h));
        let mid = s.eval(w, t);
        // central differences, h = 1e-5: measured 1.0e-10 and 1.1e-9
        assert!(((p[0] - m[0]) / (2.0 * h) - mid[1]).abs() < 2e-10);
        assert!(((p[1] - m[1]) / (2.0 * h) - mid[2]).abs() < 2.2e-9);
        assert!(sample_count("f", 1.0, 0.0, 1).is_err());
        assert_eq!(sample_count("f", 1.0, 10.0, 1).unwrap(), 11);
        assert_eq!(sample_count("f", 0.3, 10.0, 1).unwrap(), 4);
        // 72.5 sample periods: the last sample fell 0.069 s past the end, off rest
        let e = sample_count("Fourier::sample", 10.0, 7.25, 6).unwrap_err();
        assert!(
            e.to_string()
                .contains("10 s at a rate of 7.25 Hz is 72.5 sample periods, not a whole number"),
            "{e}"
        );
        // the sizes of `excite --rate 1e9` and `--duration 1e9` are named, not allocated
        for (d, r) in [(30.0, 1e9), (1e9, 500.0), (1e300, 1e6)] {
            let e = sample_count("Fourier::sample", d, r, 6).unwrap_err();
            assert!(
                matches!(e, Error::TooLarge { .. } | Error::Setting { .. }),
                "{e}"
            );
        }
        let e = sample_count("Fourier::sample", 1e9, 500.0, 6).unwrap_err();
        assert!(
            e.to_string()
                .contains("shorten the duration or lower the rate"),
            "{e}"
        );
    }
}
