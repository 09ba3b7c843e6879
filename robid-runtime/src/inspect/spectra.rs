//! The Welch spectra of several signals of one record (every joint's position and torque),
//! given block by block: [`signal::Welch`](crate::signal::Welch)'s spectra to the bit,
//! with one Hann window, one FFT plan and one work buffer for all the signals instead of
//! one each. A Welch segment is a quarter of the record long (the spectrum's definition),
//! so that each signal still holds up to one segment of samples and its density (1.5 x
//! the segment's length in values); the window, the plan, the FFT's input, output and
//! scratch, which `Welch` holds per signal (about 4 x the segment's length more), are
//! shared: on an hour at 1 kHz (segments of 2^19 samples) 14 signals took about 330 MB
//! as 14 `Welch`es and take about 110 MB here.
//!
//! The arithmetic is `signal/spectrum.rs`'s, repeated (`Welch` cannot share its buffers):
//! the same segments, detrended, windowed, transformed and summed in the same order.

use std::sync::Arc;

use realfft::num_complex::Complex;
use realfft::{RealFftPlanner, RealToComplex};

use crate::signal::{MIN_SPECTRUM_SAMPLES, Spectrum};

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

/// Welch's estimates of `count` signals of `samples` samples each at `rate` Hz.
pub(super) struct Spectra {
    rate: f64,
    len: usize,
    hop: usize,
    window_power: f64,
    work: Work,
    signals: Vec<Signal>,
}

impl Spectra {
    /// As [`Welch::new`](crate::signal::Welch::new) for each of `count` signals; `None`
    /// for fewer than [`MIN_SPECTRUM_SAMPLES`] samples or a rate that is not positive.
    pub(super) fn new(count: usize, samples: usize, rate: f64) -> Option<Spectra> {
        if samples < MIN_SPECTRUM_SAMPLES || !(rate > 0.0) {
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
        Some(Spectra {
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

    /// The next samples of signal `i`.
    pub(super) fn push(&mut self, i: usize, mut part: &[f64]) {
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
    /// complete segment).
    pub(super) fn finish(self) -> Vec<Option<Spectrum>> {
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
                Some(Spectrum {
                    resolution: rate / len as f64,
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
