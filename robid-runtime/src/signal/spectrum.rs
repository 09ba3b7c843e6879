//! Power spectral density by Welch's method (docs/identification.md#choosing-the-cutoff):
//! Hann-windowed segments of a power-of-two length with half overlap, each with its
//! straight-line trend removed, averaged. What the diagnostics read from it: the
//! bandwidth that holds a share of the signal's power, the noise floor (the median density
//! of the upper half of the band, where a measured robot signal is noise), and the highest
//! frequency at which the signal still stands above that floor.

use std::sync::Arc;

use realfft::num_complex::Complex;
use realfft::{RealFftPlanner, RealToComplex};

/// Shortest record a spectrum is computed for (samples).
pub const MIN_SPECTRUM_SAMPLES: usize = 64;

/// A one-sided power spectral density on a uniform frequency grid.
#[derive(Debug, Clone, PartialEq)]
pub struct Spectrum {
    /// Frequency step (Hz); bin k is at `k * resolution`.
    pub resolution: f64,
    /// Density per bin, in (unit of the signal)^2 / Hz, from 0 Hz to the Nyquist frequency.
    pub density: Vec<f64>,
    /// Segments averaged.
    pub segments: usize,
}

impl Spectrum {
    /// Welch's estimate of `x` sampled at `rate` Hz, with segments of the largest power of
    /// two at most a quarter of the record (so that about seven segments are averaged);
    /// `None` for fewer than [`MIN_SPECTRUM_SAMPLES`] samples, a non-finite value, a rate
    /// that is not positive and finite, or a density that is not finite (values whose
    /// squares overflow: `1e160 * sin` gave infinite and NaN densities).
    ///
    /// ```
    /// use robid_runtime::signal::Spectrum;
    /// let rate = 1000.0;
    /// let x: Vec<f64> = (0..8192).map(|k| (2.0 * std::f64::consts::PI * 50.0 * k as f64 / rate).sin()).collect();
    /// let s = Spectrum::welch(&x, rate).unwrap();
    /// let peak = s.frequency(s.density.iter().enumerate().max_by(|a, b| a.1.total_cmp(b.1)).unwrap().0);
    /// assert!((peak - 50.0).abs() <= s.resolution);
    /// // Parseval: the density integrates to the mean square, 1/2
    /// assert!((s.power() - 0.5).abs() < 0.01);
    /// ```
    pub fn welch(x: &[f64], rate: f64) -> Option<Spectrum> {
        let mut welch = Welch::new(1, x.len(), rate)?;
        welch.push(0, x);
        welch.finish().pop().flatten()
    }

    /// The frequency of bin `k` (Hz).
    pub fn frequency(&self, k: usize) -> f64 {
        k as f64 * self.resolution
    }

    /// The mean square of the (detrended) signal: the density's integral.
    pub fn power(&self) -> f64 {
        self.density.iter().sum::<f64>() * self.resolution
    }

    /// The frequency below which `share` (0 to 1) of the power lies, interpolated
    /// within the bin where the cumulative power crosses it (the last bin's frequency
    /// when there is no power); `None` for a share outside [0, 1] (it was clamped: 2 gave
    /// the upper edge of the last bin, -1 the lower edge of bin 0, a negative frequency,
    /// and NaN the Nyquist frequency, each as if asked for).
    pub fn bandwidth(&self, share: f64) -> Option<f64> {
        if !(0.0..=1.0).contains(&share) {
            return None;
        }
        let total: f64 = self.density.iter().sum();
        let goal = share * total;
        let mut below = 0.0;
        for (k, d) in self.density.iter().enumerate() {
            if below + d >= goal && *d > 0.0 {
                return Some(self.frequency(k) + self.resolution * ((goal - below) / d - 0.5));
            }
            below += d;
        }
        Some(self.frequency(self.density.len() - 1))
    }

    /// The noise floor: the median density of the upper half of the band, divided by the
    /// median-to-mean ratio of an average of `segments` periodograms (a scaled chi^2 with
    /// about 1.89 degrees of freedom per segment for half-overlapping Hann windows; Wilson
    /// and Hilferty's approximation of its median), so that white noise gives its mean
    /// density. The median ignores the lines (PWM ripple, resonances) that a mean would
    /// count.
    pub fn noise_floor(&self) -> f64 {
        let mut upper = self.density[self.density.len() / 2..].to_vec();
        upper.sort_by(f64::total_cmp);
        let dof = 1.89 * self.segments as f64;
        let median_to_mean = (1.0 - 2.0 / (9.0 * dof)).powi(3);
        upper[upper.len() / 2] / median_to_mean
    }

    /// The standard deviation of white noise at the noise floor over the whole band.
    pub fn noise_rms(&self) -> f64 {
        (self.noise_floor() * self.resolution * (self.density.len() - 1) as f64).sqrt()
    }

    /// The highest frequency at which the density exceeds `ratio` times the noise floor
    /// (0 when it never does).
    pub fn above_floor(&self, ratio: f64) -> f64 {
        let floor = self.noise_floor();
        self.density
            .iter()
            .rposition(|d| *d > ratio * floor)
            .map_or(0.0, |k| self.frequency(k))
    }
}

/// What one signal has gathered.
struct Signal {
    density: Vec<f64>,
    segments: usize,
    /// The samples from the next segment's start that no segment has taken yet.
    held: Vec<f64>,
    finite: bool,
    failed: bool,
}

/// The work shared by the signals: the window and the transform.
struct Work {
    window: Vec<f64>,
    fft: Arc<dyn RealToComplex<f64>>,
    input: Vec<f64>,
    output: Vec<Complex<f64>>,
    scratch: Vec<Complex<f64>>,
}

/// [`Spectrum::welch`] of signals given in parts, in order (a record read block by block):
/// each signal holds one segment's samples, not the signal, and gets the same spectrum to
/// the bit (the same segments, transformed and summed in the same order). The signals
/// share the window, the FFT plan and its buffers (about four segments' worth), so that
/// the spectra of every joint's position and torque of an hour at 1 kHz (segments of 2^19
/// samples) take about 110 MB, not 330 MB as one accumulator each.
///
/// ```
/// use robid_runtime::signal::{Spectrum, Welch};
/// let x: Vec<f64> = (0..5000).map(|k| (0.05 * k as f64).sin()).collect();
/// let y: Vec<f64> = x.iter().map(|v| 2.0 * v).collect();
/// let mut welch = Welch::new(2, x.len(), 100.0).unwrap();
/// x.chunks(777).for_each(|part| welch.push(0, part));
/// y.chunks(1000).for_each(|part| welch.push(1, part));
/// let spectra = welch.finish();
/// assert_eq!(spectra[0], Spectrum::welch(&x, 100.0));
/// assert_eq!(spectra[1], Spectrum::welch(&y, 100.0));
/// ```
pub struct Welch {
    rate: f64,
    len: usize,
    hop: usize,
    window_power: f64,
    work: Work,
    signals: Vec<Signal>,
}

impl std::fmt::Debug for Welch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Welch")
            .field("rate", &self.rate)
            .field("len", &self.len)
            .field("signals", &self.signals.len())
            .finish_non_exhaustive()
    }
}

impl Welch {
    /// The estimates of `count` signals of `samples` samples each at `rate` Hz, with
    /// segments of the largest power of two at most a quarter of them; `None` for fewer
    /// than [`MIN_SPECTRUM_SAMPLES`] samples or a rate that is not positive and finite.
    pub fn new(count: usize, samples: usize, rate: f64) -> Option<Welch> {
        if samples < MIN_SPECTRUM_SAMPLES || !(rate > 0.0 && rate.is_finite()) {
            return None;
        }
        let len = 1usize << (samples / 4).max(16).ilog2();
        let window: Vec<f64> = (0..len)
            .map(|k| 0.5 - 0.5 * (2.0 * std::f64::consts::PI * k as f64 / len as f64).cos())
            .collect();
        let window_power: f64 = window.iter().map(|w| w * w).sum();
        let fft = RealFftPlanner::<f64>::new().plan_fft_forward(len);
        let signals = (0..count)
            .map(|_| Signal {
                density: vec![0.0; len / 2 + 1],
                segments: 0,
                held: Vec::new(),
                finite: true,
                failed: false,
            })
            .collect();
        Some(Welch {
            rate,
            len,
            hop: len / 2,
            window_power,
            work: Work {
                window,
                input: fft.make_input_vec(),
                output: fft.make_output_vec(),
                scratch: fft.make_scratch_vec(),
                fft,
            },
            signals,
        })
    }

    /// The next samples of signal `i` (below the `count` of [`Welch::new`]).
    ///
    /// # Panics
    ///
    /// For `i` at or above that `count`, which the caller chose.
    pub fn push(&mut self, i: usize, mut part: &[f64]) {
        let count = self.signals.len();
        assert!(
            i < count,
            "Welch::push: signal {i} of a Welch of {count} signals (they are numbered from 0)"
        );
        let (len, hop) = (self.len, self.hop);
        let (work, s) = (&mut self.work, &mut self.signals[i]);
        s.finite &= part.iter().all(|v| v.is_finite());
        if !s.finite {
            return;
        }
        while s.held.len() + part.len() >= len {
            if s.held.is_empty() {
                // whole segments straight from the part
                while part.len() >= len {
                    work.segment(s, &part[..len]);
                    part = &part[hop..];
                }
                break;
            }
            // a segment that starts in the held samples
            let need = len - s.held.len();
            let mut held = std::mem::take(&mut s.held);
            held.extend_from_slice(&part[..need]);
            part = &part[need..];
            work.segment(s, &held);
            held.drain(..hop);
            s.held = held;
        }
        s.held.extend_from_slice(part);
    }

    /// Each signal's spectrum; `None` for one with a value that was not finite (or no
    /// complete segment), or whose density is not (values whose squares overflow, or a
    /// rate so small that the scale does).
    pub fn finish(self) -> Vec<Option<Spectrum>> {
        let (rate, len, window_power) = (self.rate, self.len, self.window_power);
        self.signals
            .into_iter()
            .map(|s| {
                if !s.finite || s.failed || s.segments == 0 {
                    return None;
                }
                let mut density = s.density;
                // one-sided density: |X|^2 / (rate * sum w^2), doubled except at 0 and Nyquist
                let scale = 1.0 / (rate * window_power * s.segments as f64);
                let last = density.len() - 1;
                for (k, d) in density.iter_mut().enumerate() {
                    *d *= if k == 0 || k == last {
                        scale
                    } else {
                        2.0 * scale
                    };
                }
                let resolution = rate / len as f64;
                // a NaN or an infinity would pass for a spectrum in every reading of it
                let finite = resolution.is_finite() && density.iter().all(|d| d.is_finite());
                finite.then_some(Spectrum {
                    resolution,
                    density,
                    segments: s.segments,
                })
            })
            .collect()
    }
}

impl Work {
    /// Adds the density of one segment `x` to `s`.
    fn segment(&mut self, s: &mut Signal, x: &[f64]) {
        detrended(x, &mut self.input);
        for (v, w) in self.input.iter_mut().zip(&self.window) {
            *v *= w;
        }
        // the lengths are the planner's own: this cannot fail
        if self
            .fft
            .process_with_scratch(&mut self.input, &mut self.output, &mut self.scratch)
            .is_err()
        {
            s.failed = true;
            return;
        }
        for (d, c) in s.density.iter_mut().zip(&self.output) {
            *d += c.norm_sqr();
        }
        s.segments += 1;
    }
}

/// `x` less its least-squares straight line, into `out`.
fn detrended(x: &[f64], out: &mut [f64]) {
    let n = x.len() as f64;
    let mid = (n - 1.0) / 2.0;
    let mean = x.iter().sum::<f64>() / n;
    let (mut sxy, mut sxx) = (0.0, 0.0);
    for (k, v) in x.iter().enumerate() {
        let t = k as f64 - mid;
        sxy += t * (v - mean);
        sxx += t * t;
    }
    let slope = sxy / sxx;
    for (k, (o, v)) in out.iter_mut().zip(x).enumerate() {
        *o = v - mean - slope * (k as f64 - mid);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;

    fn sine(f: f64, rate: f64, n: usize, amplitude: f64) -> Vec<f64> {
        (0..n)
            .map(|k| amplitude * (2.0 * std::f64::consts::PI * f * k as f64 / rate).sin())
            .collect()
    }

    /// White noise of standard deviation s: a flat density s^2 / (rate / 2), whose floor
    /// and RMS say so; a ramp (trend) adds nothing.
    #[test]
    fn white_noise_has_a_flat_floor_of_its_variance() {
        let (rate, s) = (2000.0, 0.3);
        let mut rng = Rng::new(5);
        let x: Vec<f64> = (0..65536)
            .map(|k| s * rng.normal() + 1e-3 * k as f64)
            .collect();
        let sp = Spectrum::welch(&x, rate).unwrap();
        let flat = s * s / (rate / 2.0);
        // the median of 4096 bins, each an average of 7 segments (relative spread about
        // 0.38 / sqrt(4096 / 1.6) = 0.8 %): measured 0.992 after the median correction
        // (0.943 without it)
        assert!(
            (sp.noise_floor() / flat - 1.0).abs() < 0.025,
            "{}",
            sp.noise_floor() / flat
        );
        assert!(
            (sp.noise_rms() / s - 1.0).abs() < 0.0125,
            "{}",
            sp.noise_rms()
        );
        assert!((sp.power() / (s * s) - 1.0).abs() < 0.02, "{}", sp.power());
        // half the power of white noise lies below half the Nyquist frequency; the half
        // point moves by twice the spread of the lower half's share, sqrt(2 / n) / 2 =
        // 0.28 %, so 0.55 % of rate / 4 per standard error: 4 of them allowed (measured
        // 0.23 %); likewise 3.6 standard errors sqrt(2 / n) for the power (measured 0.6 %)
        // and the RMS's half of the floor's (measured 0.42 %)
        assert!((sp.bandwidth(0.5).unwrap() / (rate / 4.0) - 1.0).abs() < 0.022);
    }

    /// Two tones and a noise floor: the bandwidths and the last frequency above the floor
    /// fall on the tones.
    #[test]
    fn tones_above_noise_are_found() {
        let (rate, n) = (1000.0, 40_000);
        let mut rng = Rng::new(9);
        let low = sine(2.0, rate, n, 1.0);
        let high = sine(40.0, rate, n, 0.05);
        let x: Vec<f64> = (0..n)
            .map(|k| low[k] + high[k] + 1e-3 * rng.normal())
            .collect();
        let sp = Spectrum::welch(&x, rate).unwrap();
        // 99 % of the power is in the 2 Hz tone (the 40 Hz one holds 0.25 %): measured
        // 2.157 Hz, 1.3 bins past it
        assert!(
            (sp.bandwidth(0.99).unwrap() - 2.0).abs() < 2.0 * sp.resolution,
            "{}",
            sp.bandwidth(0.99).unwrap()
        );
        // the 40 Hz tone's Hann leakage spreads its last 4 % over a few bins: measured
        // 40.128 Hz (1.05 bins), and the last bin above the floor 40.41 Hz (3.3 bins)
        let b = sp.bandwidth(0.9999).unwrap();
        assert!((b - 40.0).abs() < 2.0 * sp.resolution, "{b}");
        let top = sp.above_floor(100.0);
        assert!((top - 40.0).abs() < 5.0 * sp.resolution, "{top}");
    }

    /// The estimate of a signal given in parts equals that of the whole, bit for bit,
    /// however it is cut (parts shorter and longer than a segment, cut at and next to the
    /// segments' starts); a value that is not finite in any part, or too few samples, give
    /// none.
    #[test]
    fn welch_in_parts_is_welch_of_the_whole() {
        let mut rng = Rng::new(5);
        for n in [64, 100, 3000, 10_007] {
            let x: Vec<f64> = (0..n)
                .map(|k| (0.01 * k as f64).sin() + 0.01 * k as f64 + 0.1 * rng.normal())
                .collect();
            let whole = Spectrum::welch(&x, 250.0).unwrap();
            let len = 2 * (whole.density.len() - 1);
            for part in [
                1,
                7,
                len / 2 - 1,
                len / 2,
                len - 1,
                len,
                len + 1,
                3 * len / 2,
                n,
            ] {
                let mut welch = Welch::new(1, n, 250.0).unwrap();
                x.chunks(part).for_each(|p| welch.push(0, p));
                let parts = welch.finish().pop().flatten().unwrap();
                assert_eq!(parts.segments, whole.segments, "{n} in parts of {part}");
                assert_eq!(parts.resolution.to_bits(), whole.resolution.to_bits());
                let bits = |s: &Spectrum| s.density.iter().map(|d| d.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(&parts), bits(&whole), "{n} in parts of {part}");
            }
            // a NaN in a later part spoils its signal only
            let mut bad = Welch::new(2, n, 250.0).unwrap();
            bad.push(0, &x[..n / 2]);
            bad.push(1, &x[..n / 2]);
            bad.push(0, &[f64::NAN]);
            bad.push(0, &x[n / 2..]);
            bad.push(1, &x[n / 2..]);
            let spectra = bad.finish();
            assert!(spectra[0].is_none(), "{n}");
            assert_eq!(spectra[1].as_ref(), Some(&whole), "{n}");
        }
        assert!(Welch::new(1, 63, 250.0).is_none() && Welch::new(1, 64, 0.0).is_none());
    }

    /// Welch's density against a direct computation from its definition: each
    /// half-overlapping segment less its least-squares line (solved from the normal
    /// equations), times the Hann window, transformed by a plain DFT sum; |X|^2 averaged
    /// over the segments, over rate times the window's power, doubled but at 0 and
    /// Nyquist. 3000 samples give segments of 512 (the largest power of two up to a
    /// quarter of the record) and 10 of them.
    #[test]
    fn welch_equals_its_definition_computed_directly() {
        let (rate, n) = (200.0, 3000);
        let mut rng = Rng::new(3);
        let x: Vec<f64> = (0..n)
            .map(|k| {
                let t = k as f64 / rate;
                0.7 * (2.0 * std::f64::consts::PI * 13.0 * t).sin() + 0.2 * t + 0.05 * rng.normal()
            })
            .collect();
        let sp = Spectrum::welch(&x, rate).unwrap();
        let (len, segments) = (512, 10);
        assert_eq!((sp.segments, sp.density.len()), (segments, len / 2 + 1));
        assert_eq!(sp.resolution, rate / len as f64);
        let w: Vec<f64> = (0..len)
            .map(|k| {
                let a = 2.0 * std::f64::consts::PI * k as f64 / len as f64;
                (a / 2.0).sin().powi(2)
            })
            .collect();
        let power: f64 = w.iter().map(|v| v * v).sum();
        let mut want = vec![0.0; len / 2 + 1];
        for seg in 0..segments {
            let y = &x[seg * len / 2..seg * len / 2 + len];
            // the line a + b k by the normal equations
            let (s0, s1, s2) = (
                len as f64,
                (0..len).map(|k| k as f64).sum::<f64>(),
                (0..len).map(|k| (k * k) as f64).sum::<f64>(),
            );
            let (t0, t1) = (
                y.iter().sum::<f64>(),
                y.iter().enumerate().map(|(k, v)| k as f64 * v).sum::<f64>(),
            );
            let b = (s0 * t1 - s1 * t0) / (s0 * s2 - s1 * s1);
            let a = (t0 - b * s1) / s0;
            for (m, d) in want.iter_mut().enumerate() {
                let (mut re, mut im) = (0.0, 0.0);
                for k in 0..len {
                    let v = (y[k] - a - b * k as f64) * w[k];
                    let phase = 2.0 * std::f64::consts::PI * (k * m % len) as f64 / len as f64;
                    re += v * phase.cos();
                    im -= v * phase.sin();
                }
                *d += re * re + im * im;
            }
        }
        let scale = 1.0 / (rate * power * segments as f64);
        let top = want.iter().copied().fold(0.0, f64::max) * scale;
        for (m, (got, d)) in sp.density.iter().zip(&want).enumerate() {
            let one_sided = if m == 0 || m == len / 2 { 1.0 } else { 2.0 };
            // the FFT's rounding against the sum's: measured 1.2e-15 of the peak
            assert!(
                (got - d * one_sided * scale).abs() < 2.4e-15 * top,
                "bin {m}: {got} against {}",
                d * one_sided * scale
            );
        }
    }

    /// The detrended segment is the least-squares residual: orthogonal to a constant and
    /// to the sample index, and what it removed is a straight line.
    #[test]
    fn detrending_removes_exactly_the_least_squares_line() {
        let mut rng = Rng::new(11);
        let x: Vec<f64> = (0..257)
            .map(|k| rng.normal() + 0.3 * k as f64 - 4.0)
            .collect();
        let mut out = vec![0.0; x.len()];
        detrended(&x, &mut out);
        let sum: f64 = out.iter().sum();
        let moment: f64 = out.iter().enumerate().map(|(k, v)| k as f64 * v).sum();
        let removed: Vec<f64> = x.iter().zip(&out).map(|(a, b)| a - b).collect();
        let bend = removed
            .windows(3)
            .map(|r| (r[0] - 2.0 * r[1] + r[2]).abs())
            .fold(0.0, f64::max);
        // rounding of sums of 257 values near 80: measured 3.7e-12, 4.0e-10, 1.4e-14
        assert!(sum.abs() < 7.4e-12, "{sum}");
        assert!(moment.abs() < 8e-10, "{moment}");
        assert!(bend < 2.9e-14, "{bend}");
    }

    /// The bandwidth interpolates inside the bin where the cumulative power crosses the
    /// share (bin k spans k +- 1/2 resolutions), skips empty bins, and is the last bin's
    /// frequency when there is no power at all.
    #[test]
    fn the_bandwidth_interpolates_within_the_crossing_bin() {
        let sp = |density: Vec<f64>| Spectrum {
            resolution: 2.0,
            density,
            segments: 1,
        };
        let flat = sp(vec![1.0; 4]);
        for (share, want) in [(0.25, 1.0), (0.5, 3.0), (0.625, 4.0), (1.0, 7.0)] {
            assert_eq!(flat.bandwidth(share), Some(want), "share {share}");
        }
        // a share outside [0, 1] (clamped: 2 gave 7 as 1 does, -1 the lower edge of the
        // first bin with power, NaN the Nyquist frequency)
        for share in [2.0, 1.0 + 1e-12, -1.0, -1e-300, f64::NAN, f64::INFINITY] {
            assert_eq!(flat.bandwidth(share), None, "share {share}");
        }
        let gaps = sp(vec![0.0, 2.0, 0.0, 2.0]);
        // 3/4 of the power: all of bin 1 and half of bin 3
        assert_eq!(gaps.bandwidth(0.75), Some(6.0));
        // no power asked for: the first non-empty bin's lower edge
        assert_eq!(gaps.bandwidth(0.0), Some(1.0));
        assert_eq!(sp(vec![0.0; 3]).bandwidth(0.5), Some(4.0));
    }

    /// The floor is the median of the upper half of the band over the median-to-mean ratio
    /// of a chi^2 with 1.89 degrees of freedom per segment; the RMS integrates it over the
    /// band; the last bin above a multiple of it is found from the top.
    #[test]
    fn the_floor_is_the_corrected_median_of_the_upper_band() {
        // upper half: density[3..] = 2, 5, 3, 4: median (the upper middle) 4 (the median
        // of density[1..] would be 5)
        let sp = Spectrum {
            resolution: 0.5,
            density: vec![9.0, 10.0, 20.0, 2.0, 5.0, 3.0, 4.0],
            segments: 4,
        };
        let dof: f64 = 1.89 * 4.0;
        let ratio = (1.0 - 2.0 / (9.0 * dof)).powi(3);
        let floor = 4.0 / ratio;
        assert_eq!(sp.noise_floor(), floor);
        assert_eq!(sp.noise_rms(), (floor * 0.5 * 6.0).sqrt());
        // the floor is 4.374: above 1.1 times it (4.81) the last is bin 4 (5.0), above 2.2
        // times (9.62) bin 2 (20.0), above 10 times none
        assert_eq!(sp.above_floor(1.1), 2.0);
        assert_eq!(sp.above_floor(2.2), 1.0);
        assert_eq!(sp.above_floor(10.0), 0.0);
    }

    #[test]
    fn too_short_or_not_finite_gives_none() {
        assert!(Spectrum::welch(&[1.0; 63], 100.0).is_none());
        assert!(Spectrum::welch(&[1.0; 64], 0.0).is_none());
        assert!(Spectrum::welch(&[1.0; 64], -1.0).is_none());
        let mut x = vec![0.0; 100];
        x[3] = f64::NAN;
        assert!(Spectrum::welch(&x, 100.0).is_none());
        assert!(Spectrum::welch(&[0.5; 64], 100.0).is_some());
        // finite values whose squares overflow, and a rate that is not finite or so small
        // that the density's scale overflows: no spectrum (they gave inf and NaN densities)
        let loud = sine(3.0, 100.0, 1000, 1e160);
        assert!(Spectrum::welch(&loud, 100.0).is_none());
        assert!(Spectrum::welch(&sine(3.0, 100.0, 1000, 1e140), 100.0).is_some());
        let x = sine(3.0, 100.0, 1000, 1.0);
        for rate in [f64::INFINITY, f64::NAN, 1e-320] {
            assert!(Spectrum::welch(&x, rate).is_none(), "{rate}");
        }
    }

    /// A signal number at or above the count is the caller's error, told with both (it
    /// was an index out of bounds).
    #[test]
    #[should_panic(expected = "signal 5 of a Welch of 1 signals")]
    fn pushing_a_signal_beyond_the_count_is_told() {
        Welch::new(1, 100, 100.0).unwrap().push(5, &[1.0; 10]);
    }
}
