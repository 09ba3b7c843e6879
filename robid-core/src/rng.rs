//! The one seeded random-number generator (SplitMix64, Steele, Lea and Flood 2014, with
//! Box-Muller normals): the symbolic engine's sampled states, simulations, trajectory
//! designs, the feasible-parameter search and the tests are reproducible from one integer
//! on every platform, without a dependency. `no_std` but for the normal distribution,
//! which needs the `std` feature (std's `ln` and `sin_cos`).
//!
//! ```
//! use robid_core::rng::Rng;
//!
//! let mut a = Rng::new(7);
//! let x = a.uniform(-1.0, 1.0);
//! assert!((-1.0..1.0).contains(&x));
//! assert_eq!(Rng::new(7).uniform(-1.0, 1.0), x); // equal seeds, equal sequences
//! assert!(a.below(6) < 6);
//! ```

/// Seeded generator: raw 64-bit values, uniform reals and integers, standard normals and
/// independent streams. Equal seeds give equal sequences.
#[derive(Debug, Clone)]
pub struct Rng {
    state: u64,
    /// The second value of the last Box-Muller pair (`normal`, with `std`).
    #[cfg_attr(not(feature = "std"), allow(dead_code))]
    spare: Option<f64>,
}

/// SplitMix64's increment (the golden ratio in 64 bits).
const GAMMA: u64 = 0x9e37_79b9_7f4a_7c15;

impl Rng {
    /// A generator from a seed (mixed, so that seeds 0, 1, 2 .. start far apart).
    pub fn new(seed: u64) -> Self {
        Self::from_state(seed ^ GAMMA)
    }

    /// A generator whose SplitMix64 state is `state` as given, unmixed: the stream the
    /// symbolic engine's sampling was built on (its regrouping samples and test cases
    /// keep their values).
    pub fn from_state(state: u64) -> Self {
        Self { state, spare: None }
    }

    /// Next raw 64-bit value.
    pub fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(GAMMA);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in [low, high).
    pub fn uniform(&mut self, low: f64, high: f64) -> f64 {
        low + (high - low) * self.unit()
    }

    /// Uniform integer in 0..n (the remainder of 64 random bits: a bias below n / 2^64).
    ///
    /// # Panics
    /// If `n` is zero.
    pub fn below(&mut self, n: usize) -> usize {
        assert!(n > 0, "Rng::below: empty range");
        (self.next_u64() % n as u64) as usize
    }

    /// Standard normal (Box-Muller, both values used).
    #[cfg(feature = "std")]
    pub fn normal(&mut self) -> f64 {
        if let Some(x) = self.spare.take() {
            return x;
        }
        let u1 = 1.0 - self.unit(); // (0, 1]
        let u2 = self.unit();
        let r = (-2.0 * u1.ln()).sqrt();
        let (s, c) = (std::f64::consts::TAU * u2).sin_cos();
        self.spare = Some(r * s);
        r * c
    }

    /// A generator for stream `index` derived from this one's state (independent restarts).
    pub fn fork(&self, index: u64) -> Self {
        let mut r = Rng::new(self.state ^ index.wrapping_mul(0xd1b5_4a32_d192_ed03));
        r.next_u64();
        r
    }
}

#[cfg(all(test, feature = "std"))]
mod tests {
    use super::*;
    use std::vec::Vec;

    #[test]
    fn reproducible_and_standard_normal() {
        let mut a = Rng::new(7);
        let mut b = Rng::new(7);
        assert_eq!(a.next_u64(), b.next_u64());
        let n = 20_000;
        let xs: Vec<f64> = (0..n).map(|_| a.normal()).collect();
        let mean = xs.iter().sum::<f64>() / n as f64;
        let var = xs.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / n as f64;
        // 4.2 and 5 standard errors: sigma(mean) = 1/sqrt(n) = 0.0071, sigma(var) = sqrt(2/n) = 0.01
        assert!(mean.abs() < 0.03, "{mean}");
        assert!((var - 1.0).abs() < 0.05, "{var}");
        let u: Vec<f64> = (0..n).map(|_| a.unit()).collect();
        assert!(u.iter().all(|x| (0.0..1.0).contains(x)));
        assert!((0..1000).all(|_| (-2.0..3.0).contains(&a.uniform(-2.0, 3.0))));
        assert_ne!(
            Rng::new(7).fork(1).next_u64(),
            Rng::new(7).fork(2).next_u64()
        );
    }

    #[test]
    fn integers_cover_the_range_evenly() {
        let mut r = Rng::new(1);
        let mut count = [0usize; 5];
        for _ in 0..10_000 {
            count[r.below(5)] += 1;
        }
        // binomial(10000, 0.2): sigma 40, the bounds are 5 sigma
        assert!(
            count.iter().all(|&c| (1800..2200).contains(&c)),
            "{count:?}"
        );
        assert_eq!(r.below(1), 0);
    }

    /// The first values of the raw stream (SplitMix64's published sequence for state 0 is
    /// 0xe220a8397b1dcdaf, 0x6e789e6aa1b965f4, ...) and the seed mixing of `new`.
    #[test]
    fn the_stream_is_splitmix64() {
        let mut r = Rng::from_state(0);
        assert_eq!(r.next_u64(), 0xe220_a839_7b1d_cdaf);
        assert_eq!(r.next_u64(), 0x6e78_9e6a_a1b9_65f4);
        assert_eq!(
            Rng::new(5).next_u64(),
            Rng::from_state(5 ^ GAMMA).next_u64()
        );
    }
}
