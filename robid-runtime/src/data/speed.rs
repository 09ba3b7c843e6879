//! How fast a record's positions move, gathered by the loader as it reads the samples
//! (next to [`Extremes`](super::Extremes)): per joint, a histogram of the mean speed
//! between samples [`SPEED_STRIDE`] apart, on a scale of powers of two. The speed that the
//! fastest 1 % of a record reaches is what the description's velocity limits are checked
//! against (no joint passes its limit at all): time stamps in seconds under a
//! `time_scale` of 1e-3 move every joint a thousand times faster than it can, and the fit
//! takes the accelerations as they come (parameters 1e-6 of the truth, no word). A share
//! rather than the largest speed leaves out a glitch in the positions; a small one still
//! sees a joint at rest most of the record (a median missed a log half at rest); a stride
//! of several samples divides the encoder noise by a longer time than one step.

use crate::signal::Signals;

/// Samples between the two positions of one speed: 8 (at 1 kHz, a position noise of
/// 1e-4 rad reads as 0.02 rad/s).
pub const SPEED_STRIDE: usize = 8;

/// Bins of the histogram: bin `b` holds speeds in [2^(b - 40), 2^(b - 39)), the first
/// also those below (rest, 0), the last also those above (2^-40 to 2^23, about 1e-12 to
/// 8e6 rad/s or m/s).
const BINS: usize = 64;

/// The power of two of the lower edge of bin 0.
const LOWEST: i32 = -40;

/// One joint's histogram of speeds (see the module docs).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SpeedHistogram {
    counts: [u64; BINS],
}

impl Default for SpeedHistogram {
    fn default() -> SpeedHistogram {
        SpeedHistogram { counts: [0; BINS] }
    }
}

impl SpeedHistogram {
    /// Counts one speed (rad/s or m/s; its magnitude).
    pub fn add(&mut self, speed: f64) {
        let speed = speed.abs();
        let b = if speed > 0.0 && speed.is_finite() {
            (speed.log2().floor() as i64 - i64::from(LOWEST)).clamp(0, BINS as i64 - 1) as usize
        } else if speed.is_finite() {
            0
        } else {
            BINS - 1
        };
        self.counts[b] += 1;
    }

    /// The speeds counted.
    pub fn count(&self) -> u64 {
        self.counts.iter().sum()
    }

    /// A speed that at least a `share` (0 to 1) of the counted speeds reach: the lower
    /// edge of the bin where the fastest `share` of them begins, so at most the speed
    /// itself and more than half of it; `None` without speeds, 0 when that bin is the
    /// lowest (rest).
    ///
    /// ```
    /// use robid_runtime::data::SpeedHistogram;
    /// let mut h = SpeedHistogram::default();
    /// for v in [0.0, 0.0, 0.0, 1.0, 3.0, 3.1, 100.0, 150.0] {
    ///     h.add(v);
    /// }
    /// // a quarter of the speeds reach 100: at least 64 (the bin [64, 128))
    /// assert_eq!(h.reached_by(0.25), Some(64.0));
    /// // half of them reach 3: at least 2
    /// assert_eq!(h.reached_by(0.5), Some(2.0));
    /// assert_eq!(SpeedHistogram::default().reached_by(0.5), None);
    /// ```
    pub fn reached_by(&self, share: f64) -> Option<f64> {
        let n = self.count();
        if n == 0 {
            return None;
        }
        let wanted = (share.clamp(0.0, 1.0) * n as f64).ceil().max(1.0) as u64;
        let mut seen = 0;
        let b = (0..BINS).rev().find(|&b| {
            seen += self.counts[b];
            seen >= wanted
        })?;
        Some(if b == 0 {
            0.0
        } else {
            2f64.powi(LOWEST + b as i32)
        })
    }

    /// Adds `other`'s counts (another part of the same record).
    pub fn join(&mut self, other: &SpeedHistogram) {
        for (a, b) in self.counts.iter_mut().zip(&other.counts) {
            *a += b;
        }
    }

    /// Counts the speeds of positions `q` (one joint) sampled at times `time(k)` (s):
    /// between samples k and k + [`SPEED_STRIDE`], k a multiple of it. A step of zero or
    /// less is skipped (the loader refuses them before this).
    pub(crate) fn add_positions(&mut self, q: &[f64], time: &dyn Fn(usize) -> f64) {
        let mut k = 0;
        while k + SPEED_STRIDE < q.len() {
            let dt = time(k + SPEED_STRIDE) - time(k);
            if dt > 0.0 {
                self.add((q[k + SPEED_STRIDE] - q[k]) / dt);
            }
            k += SPEED_STRIDE;
        }
    }
}

/// The histograms of the joints of `q` sampled at `time(k)`, added to `speeds`.
pub(crate) fn count_speeds(
    speeds: &mut Vec<SpeedHistogram>,
    q: &Signals,
    time: &dyn Fn(usize) -> f64,
) {
    speeds.resize(q.dof(), SpeedHistogram::default());
    for (h, x) in speeds.iter_mut().zip(q.joints()) {
        h.add_positions(x, time);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each speed lands in the bin of its power of two, rest and the out-of-scale ones in
    /// the end bins; the speed a share reaches is the lower edge of its bin.
    #[test]
    fn speeds_fall_in_their_powers_of_two() {
        let mut h = SpeedHistogram::default();
        h.add(1.0);
        h.add(-1.5);
        h.add(0.0);
        h.add(1e-300);
        h.add(1e300);
        h.add(f64::INFINITY);
        let at = |b: i32| h.counts[(b - LOWEST) as usize];
        assert_eq!(at(0), 2);
        assert_eq!(h.counts[0], 2);
        assert_eq!(h.counts[BINS - 1], 2);
        assert_eq!(h.count(), 6);
        // the fastest third: the top bin; half: [1, 2); all: the lowest bin, rest
        assert_eq!(h.reached_by(1.0 / 3.0), Some(2f64.powi(23)));
        assert_eq!(h.reached_by(0.5), Some(1.0));
        assert_eq!(h.reached_by(1.0), Some(0.0));
        // a share of nothing still counts the fastest speed
        assert_eq!(h.reached_by(0.0), Some(2f64.powi(23)));
    }

    /// A sine of amplitude 1 rad at 1 Hz, sampled at 1 kHz: the speeds its samples reach
    /// (the mean |velocity| over a stride is near |2 pi cos|) within the bin's factor; the
    /// same positions with time stamps a thousand times shorter (seconds read as
    /// milliseconds) about a thousand times faster.
    #[test]
    fn a_sine_reaches_its_speeds() {
        let q: Vec<f64> = (0..10_000)
            .map(|k| (2.0 * std::f64::consts::PI * k as f64 * 1e-3).sin())
            .collect();
        let reached = |dt: f64, share: f64| {
            let mut h = SpeedHistogram::default();
            h.add_positions(&q, &|k| k as f64 * dt);
            assert_eq!(h.count(), 1249);
            h.reached_by(share).unwrap()
        };
        // the median of |2 pi cos|, 4.44 rad/s, and the speed its fastest 1 % reach
        // (2 pi cos(pi / 200), 6.28): each at most, and more than half of it
        let median = 2.0 * std::f64::consts::PI * (std::f64::consts::PI / 4.0).cos();
        let m = reached(1e-3, 0.5);
        assert!(m <= median && m > median / 2.0, "{m}");
        let top = reached(1e-3, 0.01);
        let tau = std::f64::consts::TAU;
        assert!(top <= tau && top > tau / 2.0, "{top}");
        assert_eq!(reached(1e-6, 0.01), 1024.0 * top);
        let mut joined = SpeedHistogram::default();
        joined.join(&SpeedHistogram::default());
        assert_eq!(joined.count(), 0);
    }
}
