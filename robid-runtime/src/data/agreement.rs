//! Whether a record's velocity columns are the derivatives of its positions, gathered by
//! the loader as it reads the samples (next to [`Extremes`](super::Extremes)): per joint,
//! the least-squares scale `s` of the velocities' integral over a stride against the
//! positions' change over it, and the correlation of the two. A velocity column in other
//! units than the positions (degrees per second beside radians, a motor-side velocity, a
//! time column in milliseconds) is a scale far from 1 at a correlation near 1; the fit
//! took it as it came (the viscous friction 57 times too small, no word).

use crate::signal::Signals;

use super::speed::SPEED_STRIDE;

/// The sums over one joint's strides (see the module docs).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct VelocityAgreement {
    /// Sum of the squared position changes.
    moved: f64,
    /// Sum of the position changes times the velocities' integrals.
    cross: f64,
    /// Sum of the squared integrals.
    integrated: f64,
}

/// The least |correlation| at which a scale is told: the velocities follow the positions'
/// changes closely, so a scale far from 1 is a unit, not noise.
pub const AGREEMENT_CORRELATION: f64 = 0.9;

/// The range of scales that pass (a velocity filtered in the drive, lagging the
/// positions, reads a little below 1).
pub const AGREEMENT_SCALES: [f64; 2] = [0.8, 1.25];

impl VelocityAgreement {
    /// Adds the strides of one joint's positions `q` and velocities `qd` sampled at
    /// `time(k)` (s): between samples k and k + [`SPEED_STRIDE`], k a multiple of it, the
    /// velocities integrated by the trapezoid rule.
    pub(crate) fn add(&mut self, q: &[f64], qd: &[f64], time: &dyn Fn(usize) -> f64) {
        let mut k = 0;
        while k + SPEED_STRIDE < q.len().min(qd.len()) {
            let integral: f64 = (k..k + SPEED_STRIDE)
                .map(|i| 0.5 * (qd[i] + qd[i + 1]) * (time(i + 1) - time(i)))
                .sum();
            // finite: the loader refuses values that are not, or beyond their range, first
            let change = q[k + SPEED_STRIDE] - q[k];
            self.moved += change * change;
            self.cross += change * integral;
            self.integrated += integral * integral;
            k += SPEED_STRIDE;
        }
    }

    /// Adds `other`'s sums (another part of the same record).
    pub fn join(&mut self, other: &VelocityAgreement) {
        self.moved += other.moved;
        self.cross += other.cross;
        self.integrated += other.integrated;
    }

    /// The correlation of the velocities' integrals with the positions' changes over the
    /// strides, in [-1, 1]; `None` when either is zero throughout.
    pub fn correlation(&self) -> Option<f64> {
        let d = (self.moved * self.integrated).sqrt();
        (d > 0.0 && d.is_finite()).then(|| (self.cross / d).clamp(-1.0, 1.0))
    }

    /// The velocities' scale against the positions' derivative: the least-squares factor
    /// `s` of `integral = s change` (1 when they agree); `None` when the positions do not
    /// move.
    pub fn scale(&self) -> Option<f64> {
        (self.moved > 0.0 && self.moved.is_finite()).then(|| self.cross / self.moved)
    }

    /// The scale when the velocities clearly follow the positions
    /// (|correlation| at least [`AGREEMENT_CORRELATION`]) yet at a scale outside
    /// [`AGREEMENT_SCALES`]; `None` when they agree or say nothing clear.
    ///
    /// ```
    /// use robid_runtime::data::VelocityAgreement;
    /// assert_eq!(VelocityAgreement::default().disagreement(), None);
    /// ```
    pub fn disagreement(&self) -> Option<f64> {
        let (r, s) = (self.correlation()?, self.scale()?);
        let [lo, hi] = AGREEMENT_SCALES;
        (r.abs() >= AGREEMENT_CORRELATION && !(lo..=hi).contains(&s)).then_some(s)
    }
}

impl VelocityAgreement {
    /// What a record whose joint `number` (from 1) has these sums says, when its velocities
    /// disagree with its positions ([`VelocityAgreement::disagreement`]): the scale, the
    /// likely cause and the fix; `None` when they agree or say nothing clear.
    ///
    /// ```
    /// use robid_runtime::data::VelocityAgreement;
    /// assert_eq!(VelocityAgreement::default().warning(1), None);
    /// ```
    pub fn warning(&self, number: usize) -> Option<String> {
        let s = self.disagreement()?;
        let cause = if s < 0.0 {
            "of the opposite sign: the velocity column counts the joint's direction the other \
             way"
        } else {
            super::error::derivative_cause(1.0 / s)
        };
        Some(format!(
            "joint {number}'s velocity column is {} times the derivative of its positions, \
             which it follows closely ({cause}); identification takes the velocities from it \
             (`processing.velocity` \"auto\", the default, or \"data\"): give them in the \
             positions' unit per second, or set `velocity = \"differentiate\"` in [processing]",
            crate::Num::rounded(s, 3)
        ))
    }
}

/// The sums of the joints of `q` and `qd` sampled at `time(k)`, added to `sums`.
pub(crate) fn add_agreements(
    sums: &mut Vec<VelocityAgreement>,
    q: &Signals,
    qd: &Signals,
    time: &dyn Fn(usize) -> f64,
) {
    sums.resize(q.dof(), VelocityAgreement::default());
    for ((a, x), v) in sums.iter_mut().zip(q.joints()).zip(qd.joints()) {
        a.add(x, v, time);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A sine of 1 rad at 1 Hz sampled at 1 kHz with its derivative: scale 1, correlation
    /// 1; the velocities in degrees per second, 57.3 times; negated, -1; noise beside
    /// positions at rest says nothing; a lag of 5 ms (a filter in the drive) passes.
    #[test]
    fn the_scale_names_a_unit_and_only_a_clear_one() {
        let w = 2.0 * std::f64::consts::PI;
        let n = 5000;
        let q: Vec<f64> = (0..n).map(|k| (w * k as f64 * 1e-3).sin()).collect();
        let qd = |scale: f64, lag: f64| -> Vec<f64> {
            (0..n)
                .map(|k| scale * w * (w * (k as f64 * 1e-3 - lag)).cos())
                .collect()
        };
        let sums = |q: &[f64], v: &[f64]| {
            let mut a = VelocityAgreement::default();
            // in two parts, as the loader's windows come
            a.add(&q[..2000], &v[..2000], &|k| k as f64 * 1e-3);
            let mut b = VelocityAgreement::default();
            b.add(&q[2000..], &v[2000..], &|k| k as f64 * 1e-3);
            a.join(&b);
            a
        };
        let agree = sums(&q, &qd(1.0, 0.0));
        // measured: 1 - 5e-6 (the trapezoid) and 1 - 1e-11
        assert!((agree.scale().unwrap() - 1.0).abs() < 1e-5);
        assert!(agree.correlation().unwrap() > 1.0 - 1e-9);
        assert_eq!(agree.disagreement(), None);
        let degrees = 180.0 / std::f64::consts::PI;
        let s = sums(&q, &qd(degrees, 0.0)).disagreement().unwrap();
        assert!((s / degrees - 1.0).abs() < 1e-5, "{s}");
        let s = sums(&q, &qd(-1.0, 0.0)).disagreement().unwrap();
        assert!((s + 1.0).abs() < 1e-5, "{s}");
        assert_eq!(sums(&q, &qd(1.0, 5e-3)).disagreement(), None);
        // at the edges of the range that passes
        assert_eq!(sums(&q, &qd(0.81, 0.0)).disagreement(), None);
        assert!(sums(&q, &qd(0.79, 0.0)).disagreement().is_some());
        assert_eq!(sums(&q, &qd(1.24, 0.0)).disagreement(), None);
        assert!(sums(&q, &qd(1.26, 0.0)).disagreement().is_some());
        // positions at rest, velocities of noise: no scale, nothing told
        let mut rng = crate::rng::Rng::new(3);
        let noise: Vec<f64> = (0..n).map(|_| rng.uniform(-1e-3, 1e-3)).collect();
        let still = sums(&vec![0.5; n], &noise);
        assert_eq!(
            (still.scale(), still.correlation(), still.disagreement()),
            (None, None, None)
        );
        // moving positions, velocities of noise: no clear correlation, nothing told
        let noisy = sums(&q, &noise);
        assert!(noisy.correlation().unwrap().abs() < 0.1);
        assert_eq!(noisy.disagreement(), None);
        // what is told: the scale, the likely unit or the sign, the fix
        assert_eq!(agree.warning(2), None);
        let w = sums(&q, &qd(degrees, 0.0)).warning(2).unwrap();
        assert!(
            w.starts_with("joint 2's velocity column is 57.3 times the derivative")
                && w.contains("are the velocities in degrees per second")
                && w.contains("`velocity = \"differentiate\"`"),
            "{w}"
        );
        let w = sums(&q, &qd(-1.0, 0.0)).warning(2).unwrap();
        assert!(
            w.contains("is -1 times") && w.contains("of the opposite sign"),
            "{w}"
        );
        let w = sums(&q, &qd(0.5, 0.0)).warning(2).unwrap();
        assert!(
            w.contains("is 0.5 times") && w.contains("not the derivative"),
            "{w}"
        );
    }
}
