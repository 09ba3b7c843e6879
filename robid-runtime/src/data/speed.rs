//! How fast a record's positions move, gathered by the loader as it reads the samples
//! (next to [`Extremes`](super::Extremes)): per joint, a histogram of the mean speed
//! between samples [`SPEED_STRIDE`] apart, on a scale of powers of two. Its median is what
//! the description's velocity limits are checked against: time stamps in milliseconds
//! read as seconds (a `time_scale` of 1e-3 too many) move every joint a thousand times
//! faster than it can, and the fit takes the accelerations as they come (parameters
//! 1e-6 of the truth, no word). The median does not mind a glitch in the positions nor
//! the noise of a joint at rest, and a stride of several samples keeps the encoder noise
//! divided by a longer time than one step.

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

    /// The median speed, to within a factor of sqrt(2): the geometric middle of the bin
    /// that holds it; `None` without speeds.
    ///
    /// ```
    /// use robid_runtime::data::SpeedHistogram;
    /// let mut h = SpeedHistogram::default();
    /// for v in [0.0, 1.0, 3.0, 3.1, 100.0] {
    ///     h.add(v);
    /// }
    /// let m = h.median().unwrap();
    /// assert!(m > 3.0 / 2f64.sqrt() && m < 3.0 * 2f64.sqrt(), "{m}");
    /// assert_eq!(SpeedHistogram::default().median(), None);
    /// ```
    pub fn median(&self) -> Option<f64> {
        let n = self.count();
        if n == 0 {
            return None;
        }
        let mut seen = 0;
        let b = self.counts.iter().position(|&c| {
            seen += c;
            2 * seen >= n
        })?;
        Some(2f64.powf(f64::from(LOWEST) + b as f64 + 0.5))
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
    /// the end bins; the median is that of the speeds counted.
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
        // the third and fourth of six in [1, 2): the middle of that bin
        assert_eq!(h.median(), Some(2f64.sqrt()));
    }

    /// A sine of amplitude 1 rad at 1 Hz, sampled at 1 kHz: its median speed (the mean
    /// |velocity| over a stride is |2 pi cos| near its median, 4.44 rad/s) within the
    /// bin's factor; the same positions with time stamps a thousand times shorter
    /// (milliseconds read as seconds) a thousand times faster.
    #[test]
    fn a_sine_moves_at_its_median_speed() {
        let q: Vec<f64> = (0..10_000)
            .map(|k| (2.0 * std::f64::consts::PI * k as f64 * 1e-3).sin())
            .collect();
        let median = |dt: f64| {
            let mut h = SpeedHistogram::default();
            h.add_positions(&q, &|k| k as f64 * dt);
            assert_eq!(h.count(), 1249);
            h.median().unwrap()
        };
        let true_median = 2.0 * std::f64::consts::PI * (std::f64::consts::PI / 4.0).cos();
        let m = median(1e-3);
        assert!(
            m > true_median / 2f64.sqrt() && m < true_median * 2f64.sqrt(),
            "{m}"
        );
        let fast = median(1e-6);
        assert!(fast > 1e3 * m / 2.0 && fast < 1e3 * m * 2.0, "{fast}");
        let mut joined = SpeedHistogram::default();
        joined.join(&SpeedHistogram::default());
        assert_eq!(joined.count(), 0);
    }
}
