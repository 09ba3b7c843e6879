//! Whether a record's velocity and acceleration columns are the derivatives of its
//! positions and velocities, gathered by the loader as it reads the samples (next to
//! [`Extremes`](super::Extremes)): per joint, the least-squares scale `s` of a column's
//! integral over a stride against the change of what it derives over it, the correlation
//! of the two, and the column's range. A column in other units (degrees per second beside
//! radians, a motor-side velocity, a time column in milliseconds) is a scale far from 1 at
//! a correlation near 1; a dead one is one value throughout while what it derives moves.
//! The fit took either as it came (the viscous friction 57 times too small, an inertia of
//! 1e13 fitted to an acceleration column of zeros; no word).

use crate::signal::Signals;

use super::speed::SPEED_STRIDE;

/// Which column a [`DerivativeAgreement`] is of, for its words.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DerivativeColumn {
    /// The velocity column, against the positions.
    Velocity,
    /// The acceleration column, against the velocity column.
    Acceleration,
}

impl DerivativeColumn {
    /// The column's name in messages, and its `[processing]` key.
    pub fn name(self) -> &'static str {
        match self {
            DerivativeColumn::Velocity => "velocity",
            DerivativeColumn::Acceleration => "acceleration",
        }
    }

    /// The unit the column's values are in, per second, when they are the derivative.
    fn unit(self) -> &'static str {
        match self {
            DerivativeColumn::Velocity => "the positions' unit",
            DerivativeColumn::Acceleration => "the velocities' unit",
        }
    }

    /// What the column is the derivative of.
    pub fn of(self) -> &'static str {
        match self {
            DerivativeColumn::Velocity => "its positions",
            DerivativeColumn::Acceleration => "its velocity column",
        }
    }
}

/// The sums over one joint's strides (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DerivativeAgreement {
    /// Sum of the squared changes of what the column derives.
    moved: f64,
    /// Sum of those changes times the column's integrals.
    cross: f64,
    /// Sum of the squared integrals.
    integrated: f64,
    /// The column's smallest and largest value.
    range: [f64; 2],
}

impl Default for DerivativeAgreement {
    fn default() -> Self {
        Self {
            moved: 0.0,
            cross: 0.0,
            integrated: 0.0,
            range: [f64::INFINITY, f64::NEG_INFINITY],
        }
    }
}

/// The least |correlation| at which a scale is told: the column follows the changes
/// closely, so a scale far from 1 is a unit, not noise.
pub const AGREEMENT_CORRELATION: f64 = 0.9;

/// The range of scales that pass (a velocity filtered in the drive, lagging the
/// positions, reads a little below 1).
pub const AGREEMENT_SCALES: [f64; 2] = [0.8, 1.25];

impl DerivativeAgreement {
    /// Adds the strides of one joint's signal `x` and its derivative column `dx` sampled
    /// at `time(k)` (s): between samples k and k + [`SPEED_STRIDE`], k a multiple of it,
    /// the column integrated by the trapezoid rule.
    pub fn add(&mut self, x: &[f64], dx: &[f64], time: &dyn Fn(usize) -> f64) {
        let mut k = 0;
        while k + SPEED_STRIDE < x.len().min(dx.len()) {
            let integral: f64 = (k..k + SPEED_STRIDE)
                .map(|i| 0.5 * (dx[i] + dx[i + 1]) * (time(i + 1) - time(i)))
                .sum();
            // finite: the loader refuses values that are not, or beyond their range, first
            let change = x[k + SPEED_STRIDE] - x[k];
            self.moved += change * change;
            self.cross += change * integral;
            self.integrated += integral * integral;
            k += SPEED_STRIDE;
        }
        for &v in dx {
            self.range = [self.range[0].min(v), self.range[1].max(v)];
        }
    }

    /// Adds `other`'s sums (another part of the same record).
    pub fn join(&mut self, other: &DerivativeAgreement) {
        self.moved += other.moved;
        self.cross += other.cross;
        self.integrated += other.integrated;
        self.range = [
            self.range[0].min(other.range[0]),
            self.range[1].max(other.range[1]),
        ];
    }

    /// The correlation of the column's integrals with the changes over the strides, in
    /// [-1, 1]; `None` when either is zero throughout.
    pub fn correlation(&self) -> Option<f64> {
        let d = (self.moved * self.integrated).sqrt();
        (d > 0.0 && d.is_finite()).then(|| (self.cross / d).clamp(-1.0, 1.0))
    }

    /// The column's scale against the derivative: the least-squares factor `s` of
    /// `integral = s change` (1 when they agree); `None` when what it derives does not
    /// change.
    pub fn scale(&self) -> Option<f64> {
        (self.moved > 0.0 && self.moved.is_finite()).then(|| self.cross / self.moved)
    }

    /// The column's smallest and largest value; `None` before any sample.
    pub fn range(&self) -> Option<[f64; 2]> {
        (self.range[0] <= self.range[1]).then_some(self.range)
    }

    /// The scale when the column clearly follows the changes (|correlation| at least
    /// [`AGREEMENT_CORRELATION`]) yet at a scale outside [`AGREEMENT_SCALES`]; `None` when
    /// they agree or say nothing clear.
    ///
    /// ```
    /// use robid_runtime::data::DerivativeAgreement;
    /// assert_eq!(DerivativeAgreement::default().disagreement(), None);
    /// ```
    pub fn disagreement(&self) -> Option<f64> {
        let (r, s) = (self.correlation()?, self.scale()?);
        let [lo, hi] = AGREEMENT_SCALES;
        (r.abs() >= AGREEMENT_CORRELATION && !(lo..=hi).contains(&s)).then_some(s)
    }

    /// What a record whose joint `number` (from 1) has these sums for its `column` says:
    /// that the column is one value throughout while `moves` (what it derives clearly
    /// changes: the caller's judgement), or that it disagrees with the derivative
    /// ([`DerivativeAgreement::disagreement`]), with the scale, the likely cause and the
    /// fix; `None` when they agree or say nothing clear.
    ///
    /// ```
    /// use robid_runtime::data::{DerivativeAgreement, DerivativeColumn};
    /// assert_eq!(DerivativeAgreement::default().warning(1, DerivativeColumn::Velocity, true), None);
    /// ```
    pub fn warning(&self, number: usize, column: DerivativeColumn, moves: bool) -> Option<String> {
        let name = column.name();
        let of = column.of();
        let fix = |what: &str| {
            format!(
                "identification takes the {name}s from it (`processing.{name}` \"auto\", the \
                 default, or \"data\"): {what}, or set `{name} = \"differentiate\"` in \
                 [processing]"
            )
        };
        if let Some([lo, hi]) = self.range().filter(|r| r[0] == r[1] && moves) {
            debug_assert_eq!(lo, hi);
            return Some(format!(
                "joint {number}'s {name} column is {} over the whole record while {of} {}: \
                 a dead channel or the wrong column; {}",
                crate::Num(lo),
                match column {
                    DerivativeColumn::Velocity => "change",
                    DerivativeColumn::Acceleration => "changes",
                },
                fix(&format!("check the config's {name} columns and the logger"))
            ));
        }
        let s = self.disagreement()?;
        let cause = if s < 0.0 {
            format!(
                "of the opposite sign: the {name} column counts the joint's direction the other way"
            )
        } else {
            super::error::derivative_cause(1.0 / s, column).to_string()
        };
        Some(format!(
            "joint {number}'s {name} column is {} times the derivative of {of}, which it \
             follows closely ({cause}); {}",
            crate::Num::rounded(s, 3),
            fix(&format!("give them in {} per second", column.unit()))
        ))
    }
}

/// The sums of the joints of `x` and their derivative columns `dx` sampled at `time(k)`,
/// added to `sums`.
pub(crate) fn add_agreements(
    sums: &mut Vec<DerivativeAgreement>,
    x: &Signals,
    dx: &Signals,
    time: &dyn Fn(usize) -> f64,
) {
    sums.resize(x.dof(), DerivativeAgreement::default());
    for ((a, x), v) in sums.iter_mut().zip(x.joints()).zip(dx.joints()) {
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
            let mut a = DerivativeAgreement::default();
            // in two parts, as the loader's windows come
            a.add(&q[..2000], &v[..2000], &|k| k as f64 * 1e-3);
            let mut b = DerivativeAgreement::default();
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
        assert_eq!(agree.warning(2, DerivativeColumn::Velocity, true), None);
        let w = sums(&q, &qd(degrees, 0.0))
            .warning(2, DerivativeColumn::Velocity, true)
            .unwrap();
        assert!(
            w.starts_with("joint 2's velocity column is 57.3 times the derivative")
                && w.contains("are the velocities in degrees per second")
                && w.contains("`velocity = \"differentiate\"`"),
            "{w}"
        );
        let w = sums(&q, &qd(-1.0, 0.0))
            .warning(2, DerivativeColumn::Velocity, true)
            .unwrap();
        assert!(
            w.contains("is -1 times") && w.contains("of the opposite sign"),
            "{w}"
        );
        let w = sums(&q, &qd(0.5, 0.0))
            .warning(2, DerivativeColumn::Velocity, true)
            .unwrap();
        assert!(
            w.contains("is 0.5 times") && w.contains("not the derivative"),
            "{w}"
        );
        // an acceleration column is told in its own words
        let w = sums(&q, &qd(degrees, 0.0)).warning(3, DerivativeColumn::Acceleration, true);
        let w = w.unwrap();
        assert!(
            w.starts_with(
                "joint 3's acceleration column is 57.3 times the derivative of its velocity column"
            ) && w.contains("are the accelerations in degrees per second squared")
                && w.contains("`acceleration = \"differentiate\"`"),
            "{w}"
        );
    }

    /// A column of one value beside motion is a dead channel, told only when the caller
    /// says that what it derives clearly moves; its range is kept across parts.
    #[test]
    fn a_dead_column_is_told_beside_motion() {
        let q: Vec<f64> = (0..100).map(|k| (k as f64 * 0.05).sin()).collect();
        let mut dead = DerivativeAgreement::default();
        assert_eq!(dead.range(), None);
        dead.add(&q[..50], &[0.0; 50], &|k| k as f64 * 1e-3);
        let mut rest = DerivativeAgreement::default();
        rest.add(&q[50..], &[0.0; 50], &|k| k as f64 * 1e-3);
        dead.join(&rest);
        assert_eq!(dead.range(), Some([0.0, 0.0]));
        let w = dead.warning(4, DerivativeColumn::Velocity, true).unwrap();
        assert!(
            w.starts_with("joint 4's velocity column is 0 over the whole record while its positions change: a dead channel"),
            "{w}"
        );
        assert_eq!(dead.warning(4, DerivativeColumn::Velocity, false), None);
        let w = dead
            .warning(1, DerivativeColumn::Acceleration, true)
            .unwrap();
        assert!(w.contains("while its velocity column changes"), "{w}");
        // a column that varies is not dead, whatever it says of the derivative
        let mut flicker = [0.0; 50];
        flicker[7] = 1e-9;
        let mut live = DerivativeAgreement::default();
        live.add(&q[..50], &flicker, &|k| k as f64 * 1e-3);
        assert_eq!(live.range(), Some([0.0, 1e-9]));
        assert_eq!(live.warning(4, DerivativeColumn::Velocity, true), None);
    }
}
