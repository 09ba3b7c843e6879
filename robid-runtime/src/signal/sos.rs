//! Second-order sections and zero-phase (forward-backward) filtering.
//!
//! The same algorithm as `scipy.signal.sosfiltfilt`: odd extension of the signal by
//! `3 * (2 * sections + 1 - trailing zeros)` samples at each end, initial conditions
//! equal to the steady state for the first (and, backwards, the last) extended
//! sample, transposed direct form II in each section.

use crate::error::{Error, Result};
use crate::signal::passes::{Forward, Kept, Take};

/// A cascade of second-order sections, each `[b0, b1, b2, a0, a1, a2]` with `a0 = 1`.
#[derive(Debug, Clone, PartialEq)]
pub struct Sos {
    sections: Vec<[f64; 6]>,
}

impl Sos {
    /// Wraps sections (normalised so that `a0 = 1`).
    ///
    /// # Errors
    ///
    /// A section whose `a0` is 0 (no recursion can be written for it: it was kept, and
    /// filtered as if it were 1) or whose coefficients, normalised, are not finite.
    pub fn new(mut sections: Vec<[f64; 6]>) -> Result<Self> {
        for (i, s) in sections.iter_mut().enumerate() {
            let a0 = s[3];
            if a0 == 0.0 {
                return Err(Error::setting(
                    "Sos",
                    "sections",
                    format!("section {i} has a0 = 0; a section's a0 must be nonzero"),
                ));
            }
            if a0 != 1.0 {
                for c in s.iter_mut() {
                    *c /= a0;
                }
            }
            if let Some(c) = s.iter().find(|c| !c.is_finite()) {
                return Err(Error::setting(
                    "Sos",
                    "sections",
                    format!(
                        "section {i} has a coefficient {} (after dividing by a0); every \
                         coefficient must be finite",
                        crate::error::num(*c)
                    ),
                ));
            }
        }
        Ok(Self { sections })
    }

    /// The sections.
    pub fn sections(&self) -> &[[f64; 6]] {
        &self.sections
    }

    /// Gain at zero frequency.
    pub fn dc_gain(&self) -> f64 {
        self.sections
            .iter()
            .map(|s| (s[0] + s[1] + s[2]) / (s[3] + s[4] + s[5]))
            .product()
    }

    /// The same filter scaled to a gain of exactly 1 at zero frequency (the first section's
    /// numerator divided by [`Sos::dc_gain`]); unchanged when that gain is 0 or not finite.
    pub fn with_unit_dc_gain(mut self) -> Self {
        let gain = self.dc_gain();
        if gain != 0.0
            && gain.is_finite()
            && let Some(first) = self.sections.first_mut()
        {
            for b in &mut first[..3] {
                *b /= gain;
            }
        }
        self
    }

    /// Number of samples added at each end by [`Sos::filtfilt`] (scipy's `padlen`).
    pub fn pad_length(&self) -> usize {
        let zb = self.sections.iter().filter(|s| s[2] == 0.0).count();
        let za = self.sections.iter().filter(|s| s[5] == 0.0).count();
        3 * (2 * self.sections.len() + 1 - zb.min(za))
    }

    /// The largest magnitude of the filter's poles (the roots of `z^2 + a1 z + a2` of
    /// every section): below 1 for a stable filter, its impulse response decaying as its
    /// power.
    pub fn pole_radius(&self) -> f64 {
        self.sections
            .iter()
            .map(|s| {
                let (a1, a2) = (s[4] / s[3], s[5] / s[3]);
                let d = a1 * a1 - 4.0 * a2;
                if d < 0.0 {
                    a2.sqrt()
                } else {
                    0.5 * (a1.abs() + d.sqrt())
                }
            })
            .fold(0.0, f64::max)
    }

    /// Settling time in samples: the length after which the impulse response of the
    /// cascade (one pass) keeps less than `tolerance` of its absolute sum (at most
    /// `limit` samples are examined).
    ///
    /// # Panics
    ///
    /// For a `tolerance` outside (0, 1), a programmer's constant: 0 or less gave the
    /// limit, NaN 0 samples, 1 or more 0 samples.
    pub fn settling_samples(&self, tolerance: f64, limit: usize) -> usize {
        assert!(
            tolerance > 0.0 && tolerance < 1.0,
            "Sos::settling_samples: the tolerance {tolerance} must lie strictly between 0 and 1"
        );
        // the impulse response, in blocks until a block adds nothing measurable and the
        // blocks after it, decaying at most as fast as the slowest pole, could not either
        // (a block of a filter whose poles lie near the unit circle adds little, yet
        // the tail after it sums to much: near the Nyquist frequency its estimate was 1
        // sample where the tail took 10 % of the response over 1e5 samples)
        const BLOCK: usize = 1024;
        let per_block = self.pole_radius().powi(BLOCK as i32);
        let after = if per_block < 1.0 {
            per_block / (1.0 - per_block)
        } else {
            f64::INFINITY
        };
        let mut h: Vec<f64> = Vec::new();
        let mut zi = vec![[0.0; 2]; self.sections.len()];
        let mut total = 0.0;
        while h.len() < limit.max(1) {
            let start = h.len();
            h.resize((start + BLOCK).min(limit.max(1)), 0.0);
            if start == 0 {
                h[0] = 1.0;
            }
            self.filter_in_place(&mut h[start..], &mut zi);
            let added: f64 = h[start..].iter().map(|v| v.abs()).sum();
            total += added;
            if added * (1.0 + after) <= 1e-3 * tolerance * total {
                break;
            }
        }
        let mut tail = 0.0;
        for (k, v) in h.iter().enumerate().rev() {
            tail += v.abs();
            if tail > tolerance * total {
                return k + 1;
            }
        }
        0
    }

    /// Zero-phase filtering with an odd extension of `pad` samples at each end (at most
    /// `x.len() - 1`) instead of scipy's short default: with `pad` at least the
    /// [`Sos::settling_samples`], the start-up transient dies out inside the extension,
    /// so a record cut during motion is filtered nearly as if it went on.
    pub fn filtfilt_padded(&self, x: &[f64], pad: usize) -> Result<Vec<f64>> {
        Ok(self.filtfilt_padded_all(&[x], pad)?.remove(0))
    }

    /// [`Sos::filtfilt_padded`] of every signal of `x` (all of the same length), filtered
    /// side by side as [`Sos::filtfilt_channels`] does (one vector instruction serves
    /// several of them): each signal goes through the same operations as alone, so the
    /// values are the same as [`Sos::filtfilt`] of its padded signal.
    pub fn filtfilt_padded_all(&self, x: &[&[f64]], pad: usize) -> Result<Vec<Vec<f64>>> {
        let (g, n) = (x.len(), x.first().map_or(0, |v| v.len()));
        if x.iter().any(|v| v.len() != n) {
            return Err(Error::DimensionMismatch {
                what: "samples of each filtered signal".into(),
                expected: n,
                found: x.iter().map(|v| v.len()).find(|&l| l != n).unwrap_or(n),
            });
        }
        let pad = pad.max(self.pad_length()).min(n.saturating_sub(1));
        self.check_length(n)?;
        if g == 0 {
            return Ok(Vec::new());
        }
        // the odd extension by `pad` of `filtfilt_padded`, between the filter's own pad
        // rows, which `filtfilt_extended` fills
        let outer = self.pad_length();
        let padded = n + 2 * pad;
        // each row padded with channels of zeros to whole lanes of the passes (no partial
        // lane, which would be copied row by row into a buffer and back)
        let width = super::passes::padded_width(g, self.sections.len());
        let zeros = std::iter::repeat_n(0.0, width - g);
        // row by row (the signals side by side), each row appended: the outer rows zero,
        // then the odd extension on the left, the signals, the odd extension on the right
        let mut ext = Vec::with_capacity((padded + 2 * outer) * width);
        ext.resize(outer * width, 0.0);
        for r in 0..pad {
            ext.extend(x.iter().map(|v| 2.0 * v[0] - v[pad - r]));
            ext.extend(zeros.clone());
        }
        for k in 0..n {
            ext.extend(x.iter().map(|v| v[k]));
            ext.extend(zeros.clone());
        }
        for r in pad + n..padded {
            ext.extend(
                x.iter()
                    .map(|v| 2.0 * v[n - 1] - v[n - 1 - (r - pad - n + 1)]),
            );
            ext.extend(zeros.clone());
        }
        ext.resize((padded + 2 * outer) * width, 0.0);
        self.filtfilt_extended(&mut ext, width, Kept::ALL)?;
        // taken out row by row too
        let mut out: Vec<Vec<f64>> = (0..g).map(|_| Vec::with_capacity(n)).collect();
        for row in ext[(outer + pad) * width..(outer + pad + n) * width].chunks_exact(width) {
            for (o, &v) in out.iter_mut().zip(row) {
                o.push(v);
            }
        }
        Ok(out)
    }

    /// Steady-state section states for a unit constant input (scipy's `sosfilt_zi`).
    pub fn steady_state(&self) -> Vec<[f64; 2]> {
        let mut scale = 1.0;
        self.sections
            .iter()
            .map(|s| {
                let h = (s[0] + s[1] + s[2]) / (1.0 + s[4] + s[5]);
                let zi = [
                    scale * (s[1] + s[2] - (s[4] + s[5]) * h),
                    scale * (s[2] - s[5] * h),
                ];
                scale *= h;
                zi
            })
            .collect()
    }

    /// Causal filtering in place, starting from the states `zi` (updated).
    pub fn filter_in_place(&self, x: &mut [f64], zi: &mut [[f64; 2]]) {
        for v in x.iter_mut() {
            let mut cur = *v;
            for (s, z) in self.sections.iter().zip(zi.iter_mut()) {
                let out = s[0] * cur + z[0];
                z[0] = s[1] * cur - s[4] * out + z[1];
                z[1] = s[2] * cur - s[5] * out;
                cur = out;
            }
            *v = cur;
        }
    }

    /// One pass of a zero-phase filter over `x` in place, from and to the section states
    /// `state` ([`Sos::steady_state`] times the first sample where a pass starts), in the
    /// order of its samples or from the last (`backward`): the operations of
    /// [`Sos::filtfilt`] on this processor, so that a filter run block by block with its
    /// states carried gives its values to the bit.
    pub(crate) fn pass(&self, state: &mut [[f64; 2]], x: &mut [f64], backward: bool) {
        super::passes::pass(&self.sections, state, x, backward);
    }

    /// Zero-phase filtering (as `scipy.signal.sosfiltfilt`); `x` needs more than
    /// [`Sos::pad_length`] samples.
    pub fn filtfilt(&self, x: &[f64]) -> Result<Vec<f64>> {
        let mut work = Vec::new();
        let mut out = vec![0.0; x.len()];
        self.filtfilt_into(x, &mut work, &mut out)?;
        Ok(out)
    }

    /// [`Sos::filtfilt`] writing into `out` (same length as `x`), reusing `work`.
    pub fn filtfilt_into(&self, x: &[f64], work: &mut Vec<f64>, out: &mut [f64]) -> Result<()> {
        let n = x.len();
        let pad = self.pad_length();
        if n <= pad {
            return Err(Error::TooFewSamples {
                context: "zero-phase filter".into(),
                found: n,
                required: pad + 1,
                hint: "use a longer record or a lower filter order",
            });
        }
        if out.len() != n {
            return Err(Error::DimensionMismatch {
                what: "filter output".into(),
                expected: n,
                found: out.len(),
            });
        }
        // the layout of `filtfilt_extended`: free pad rows before and after the samples
        work.clear();
        work.resize(n + 2 * pad, 0.0);
        work[pad..pad + n].copy_from_slice(x);
        self.filtfilt_extended(work, 1, Kept::ALL)?;
        out.copy_from_slice(&work[pad..pad + n]);
        Ok(())
    }
}

/// Zero-phase filtering of `g` channels at once. `block` is `n x g`, row-major (one
/// row per sample), and is replaced by the filtered signals. The inner loops run over
/// channels, so they vectorise; the result equals [`Sos::filtfilt`] on each channel.
impl Sos {
    /// See the impl's doc: [`Sos::filtfilt`] of every column of a row-major block.
    ///
    /// # Errors
    ///
    /// `DimensionMismatch` for a block whose length is not a multiple of `g`, and
    /// `TooFewSamples` for too few rows ([`Sos::filtfilt`]).
    pub fn filtfilt_channels(&self, block: &mut [f64], g: usize) -> Result<()> {
        if g == 0 {
            return Ok(());
        }
        if !block.len().is_multiple_of(g) {
            return Err(Error::DimensionMismatch {
                what: format!("values of a block of {g} channels (whole rows)"),
                expected: block.len().next_multiple_of(g),
                found: block.len(),
            });
        }
        let n = block.len() / g;
        let pad = self.check_length(n)?;
        let mut ext = vec![0.0; (n + 2 * pad) * g];
        ext[pad * g..(pad + n) * g].copy_from_slice(block);
        self.filtfilt_extended(&mut ext, g, Kept::ALL)?;
        block.copy_from_slice(&ext[pad * g..(pad + n) * g]);
        Ok(())
    }

    /// Checks that `n` samples are enough and returns the pad length.
    pub(crate) fn check_length(&self, n: usize) -> Result<usize> {
        let pad = self.pad_length();
        if n <= pad {
            return Err(Error::TooFewSamples {
                context: "zero-phase filter".into(),
                found: n,
                required: pad + 1,
                hint: "use a longer record, less trimming or a lower decimation factor",
            });
        }
        Ok(pad)
    }

    /// Zero-phase filtering of `g` channels held in `ext` (row-major) with
    /// [`Sos::pad_length`] free rows before and after the data rows: the pads are
    /// filled with the odd extension, then filtered forward and backward in place (the
    /// backward pass stores the rows `kept` only: the others are left forward-filtered).
    pub(crate) fn filtfilt_extended(&self, ext: &mut [f64], g: usize, kept: Kept) -> Result<()> {
        self.filtfilt_extended_from(ext, g, kept, Forward::whole())
    }

    /// [`Sos::filtfilt_extended`] with the rows, first states and handed states of
    /// `forward` ([`Forward`]: a block of a stream whose forward pass goes on from the
    /// previous block's); the front pad is filled and filtered only when the forward pass
    /// starts from the first row.
    pub(crate) fn filtfilt_extended_from(
        &self,
        ext: &mut [f64],
        g: usize,
        kept: Kept,
        forward: Forward<'_>,
    ) -> Result<()> {
        self.filtfilt_extended_taking(ext, g, kept, forward, None)
            .map(drop)
    }

    /// [`Sos::filtfilt_extended_from`], the backward pass packing the rows it keeps among
    /// `take`'s rows at its row `take.at` when the passes can
    /// ([`passes_taking`](super::passes::passes_taking)): returns whether they did.
    pub(crate) fn filtfilt_extended_taking(
        &self,
        ext: &mut [f64],
        g: usize,
        kept: Kept,
        forward: Forward<'_>,
        take: Option<Take>,
    ) -> Result<bool> {
        let pad = self.pad_length();
        let rows = ext.len() / g;
        let n = rows.saturating_sub(2 * pad);
        self.check_length(n)?;
        for i in 0..pad {
            // front: 2 x[0] - x[pad - i]; back: 2 x[n-1] - x[n-2-i]
            if forward.from == 0 {
                let (head, tail) = ext.split_at_mut(pad * g);
                let first = &tail[..g];
                let src = &tail[(pad - i) * g..(pad - i + 1) * g];
                for ((d, s), f) in head[i * g..(i + 1) * g].iter_mut().zip(src).zip(first) {
                    *d = 2.0 * f - s;
                }
            }
            let (body, back) = ext.split_at_mut((pad + n) * g);
            let last = &body[(pad + n - 1) * g..];
            let src = &body[(pad + n - 2 - i) * g..(pad + n - 1 - i) * g];
            for ((d, s), l) in back[i * g..(i + 1) * g].iter_mut().zip(src).zip(last) {
                *d = 2.0 * l - s;
            }
        }
        let zi = self.steady_state();
        Ok(super::passes::passes_taking(
            &self.sections,
            &zi,
            ext,
            g,
            kept,
            forward,
            take,
        ))
    }
}

#[cfg(test)]
mod tests {

    /// Near the Nyquist frequency the poles lie near -1 and the impulse response decays
    /// slowly from a small start: the settling time grows as 1 / (1 - cutoff). It stopped
    /// after the first block where one added little (order 8: 2682, 25434 and 44356
    /// samples at 1e-3, 1e-4 and 1e-5 from the Nyquist frequency; order 2 at 5e-9: 1).
    #[test]
    fn settling_near_the_nyquist_frequency_grows_with_the_closeness() {
        for order in [2, 8, 20] {
            let settle = |gap: f64| {
                crate::signal::butterworth(order, 1.0 - gap)
                    .unwrap()
                    .settling_samples(0.1, 1 << 24)
            };
            for gap in [1e-3, 1e-4] {
                let (near, far) = (settle(0.1 * gap), settle(gap));
                assert!(
                    (8 * far..12 * far).contains(&near),
                    "order {order}: {near} samples at {:e}, {far} at {gap:e}",
                    0.1 * gap
                );
            }
        }
    }

    use super::Sos;
    use crate::signal::butterworth;

    /// The DC gain is the product of the sections' `sum(b) / sum(a)`; the padding is
    /// scipy's `padlen`, `3 * (2 * sections + 1 - min(trailing zeros of b, of a))`.
    #[test]
    fn dc_gain_and_padding_of_given_sections() {
        let first_order = [1.0, 1.0, 0.0, 1.0, -0.5, 0.0];
        let second_order = [1.0, 2.0, 1.0, 1.0, -0.4, 0.2];
        let sos = Sos::new(vec![first_order, second_order]).unwrap();
        assert!((sos.dc_gain() - 2.0 / 0.5 * 4.0 / 0.8).abs() < 1e-12);
        assert_eq!(sos.pad_length(), 3 * (2 * 2 + 1 - 1));
        assert_eq!(
            Sos::new(vec![first_order; 3]).unwrap().pad_length(),
            3 * (2 * 3 + 1 - 3)
        );
        assert_eq!(
            Sos::new(vec![second_order; 2]).unwrap().pad_length(),
            3 * (2 * 2 + 1)
        );
        // a section with a trailing zero in a only does not shorten the padding
        let a_only = [1.0, 2.0, 1.0, 1.0, -0.5, 0.0];
        assert_eq!(Sos::new(vec![a_only; 2]).unwrap().pad_length(), 3 * 5);
        // a0 is divided out; an a0 of 0, or a coefficient that is not finite, is refused
        let halved = Sos::new(vec![[2.0, 4.0, 2.0, 2.0, -0.8, 0.4]]).unwrap();
        assert_eq!(halved.sections(), &[second_order]);
        for bad in [
            [1.0, 2.0, 1.0, 0.0, -0.4, 0.2],
            [1.0, f64::NAN, 1.0, 1.0, -0.4, 0.2],
            [1.0, 2.0, 1.0, 1e-320, -0.4, 0.2],
        ] {
            let e = Sos::new(vec![second_order, bad]).unwrap_err().to_string();
            assert!(e.contains("section 1 has"), "{e}");
        }
        // scipy: butter(4, 0.2) pads 15, butter(5, 0.2) 18
        assert_eq!(butterworth(4, 0.2).unwrap().pad_length(), 15);
        assert_eq!(butterworth(5, 0.2).unwrap().pad_length(), 18);
    }

    #[test]
    fn filtfilt_matches_scipy() {
        // scipy 1.17.1: sosfiltfilt(butter(4, 0.2, output="sos"), x)
        let x: Vec<f64> = (0..40)
            .map(|k| {
                let k = k as f64;
                (0.3 * k).sin() + 0.5 * (1.7 * k).cos() + 0.01 * k * k
            })
            .collect();
        let y = butterworth(4, 0.2).unwrap().filtfilt(&x).unwrap();
        let expected = [
            (0, 0.5014492611227331),
            (1, 0.6099471977572288),
            (7, 1.3181715886849164),
            (20, 3.721073471156536),
            (39, 13.977661643677571),
        ];
        for (i, e) in expected {
            assert!((y[i] - e).abs() < 1e-11, "y[{i}] = {} vs {e}", y[i]);
        }
    }

    #[test]
    fn channels_match_single_filtfilt() {
        let sos = butterworth(3, 0.1).unwrap();
        let g = 3;
        let n = 50;
        let x: Vec<Vec<f64>> = (0..g)
            .map(|c| {
                (0..n)
                    .map(|k| ((k * (c + 1)) as f64 * 0.21).sin() + c as f64)
                    .collect()
            })
            .collect();
        let mut block: Vec<f64> = (0..n).flat_map(|k| x.iter().map(move |v| v[k])).collect();
        sos.filtfilt_channels(&mut block, g).unwrap();
        for (c, xc) in x.iter().enumerate() {
            let y = sos.filtfilt(xc).unwrap();
            for k in 0..n {
                assert!((block[k * g + c] - y[k]).abs() < 1e-13);
            }
        }
        assert!(
            sos.filtfilt_channels(&mut vec![0.0; 3 * sos.pad_length()], 3)
                .is_err()
        );
        // a block that is no whole number of rows: an error, not a panic in the copy
        let e = sos
            .filtfilt_channels(&mut vec![1.0; 100], 3)
            .unwrap_err()
            .to_string();
        assert!(e.contains("block of 3 channels"), "{e}");
    }

    #[test]
    fn signals_filtered_side_by_side_equal_each_alone() {
        let sos = crate::signal::butterworth_hz(4, 20.0, 1000.0).unwrap();
        for (g, n, pad) in [(7, 400, 150), (1, 40, 0), (5, 30, 500), (4, 2000, 1000)] {
            let x: Vec<Vec<f64>> = (0..g)
                .map(|c| {
                    (0..n)
                        .map(|k| {
                            ((k * (c + 2)) as f64 * 0.013).sin() * (c as f64 + 0.5) + 0.1 * k as f64
                        })
                        .collect()
                })
                .collect();
            let views: Vec<&[f64]> = x.iter().map(Vec::as_slice).collect();
            let all = sos.filtfilt_padded_all(&views, pad).unwrap();
            for (c, v) in x.iter().enumerate() {
                // the reference: the odd extension written out, filtered alone
                let p = pad.max(sos.pad_length()).min(n - 1);
                let mut ext: Vec<f64> = (1..=p).rev().map(|i| 2.0 * v[0] - v[i]).collect();
                ext.extend_from_slice(v);
                ext.extend((1..=p).map(|i| 2.0 * v[n - 1] - v[n - 1 - i]));
                let alone = sos.filtfilt(&ext).unwrap()[p..p + n].to_vec();
                assert_eq!(all[c], alone, "g {g} n {n} channel {c}");
                assert_eq!(sos.filtfilt_padded(v, pad).unwrap(), alone);
            }
        }
        assert!(
            sos.filtfilt_padded_all(&[&[0.0; 10][..], &[0.0; 9][..]], 0)
                .is_err()
        );
        assert!(sos.filtfilt_padded_all(&[&[0.0; 5][..]], 0).is_err());
    }

    #[test]
    fn settling_and_long_padding() {
        // 4th-order 25 Hz low-pass at 5 kHz: the impulse response lasts ~ 2 / 25 Hz
        let sos = crate::signal::butterworth_hz(4, 25.0, 5000.0).unwrap();
        let k = sos.settling_samples(1e-3, 100_000);
        // measured 584
        assert!((300..800).contains(&k), "{k}");
        // a ramp-and-sine cut mid-motion: long odd padding keeps the edges right
        let x: Vec<f64> = (0..3000)
            .map(|i| {
                let t = i as f64 / 5000.0;
                0.7 * t + 0.3 * (2.0 * t + 0.4).sin()
            })
            .collect();
        let short = sos.filtfilt(&x).unwrap();
        let long = sos.filtfilt_padded(&x, k).unwrap();
        let err = |y: &[f64]| (0..50).map(|i| (y[i] - x[i]).abs()).fold(0.0, f64::max);
        // measured 4.2e-6 (1.0e-3 without the long padding: a ratio of 4.1e-3)
        assert!(err(&long) < 8.5e-6, "{}", err(&long));
        assert!(
            err(&long) < 8e-3 * err(&short),
            "{} vs {}",
            err(&long),
            err(&short)
        );
        // and at the other end (measured 1.23e-5, 9.4e-3 without the long padding: 1.3e-3)
        let n = x.len();
        let end = |y: &[f64]| (n - 50..n).map(|i| (y[i] - x[i]).abs()).fold(0.0, f64::max);
        assert!(end(&long) < 2.5e-5, "{}", end(&long));
        assert!(end(&long) < 2.6e-3 * end(&short));
        // in the middle both are the plain filter
        assert!((long[1500] - short[1500]).abs() < 1e-9);
    }

    /// The settling time is the first sample from which the impulse response's absolute
    /// tail is at most `tolerance` of its absolute sum: checked against the response
    /// computed a million samples long, for short and long responses and tolerances down
    /// to 1e-15.
    #[test]
    fn settling_is_where_the_tail_falls_below_the_tolerance() {
        let n = 1 << 20;
        for sos in [
            crate::signal::butterworth_hz(4, 25.0, 5000.0).unwrap(),
            crate::signal::butterworth_hz(4, 1.0, 1000.0).unwrap(),
            crate::signal::chebyshev1(8, 0.05, 0.08).unwrap(),
        ] {
            let mut h = vec![0.0; n];
            h[0] = 1.0;
            let mut zi = vec![[0.0; 2]; sos.sections().len()];
            sos.filter_in_place(&mut h, &mut zi);
            let total: f64 = h.iter().map(|v| v.abs()).sum();
            // tail[k] = sum of |h| from k on
            let mut tail = vec![0.0; n + 1];
            for k in (0..n).rev() {
                tail[k] = tail[k + 1] + h[k].abs();
            }
            for tolerance in [1e-3, 1e-12, 1e-15] {
                let k = sos.settling_samples(tolerance, n);
                let bound = tolerance * total;
                // the sums differ in order from the function's: 1e-9 of slack
                assert!(tail[k] <= bound * (1.0 + 1e-9), "{tolerance}: {k}");
                assert!(
                    k > 0 && tail[k - 1] > bound * (1.0 - 1e-9),
                    "{tolerance}: {k}"
                );
            }
        }
    }

    /// A tolerance outside (0, 1) is a programmer's error, told as such (NaN gave 0
    /// samples, 0 and -1 the limit).
    #[test]
    fn a_tolerance_outside_zero_to_one_is_refused() {
        let sos = butterworth(4, 0.05).unwrap();
        for tolerance in [f64::NAN, 0.0, -1.0, 1.0] {
            let e =
                std::panic::catch_unwind(|| sos.settling_samples(tolerance, 1 << 22)).unwrap_err();
            let e = e.downcast_ref::<String>().unwrap();
            assert!(e.contains("strictly between 0 and 1"), "{tolerance}: {e}");
        }
    }

    #[test]
    fn constant_passes_unchanged() {
        let sos = butterworth(4, 0.05).unwrap();
        let y = sos.filtfilt(&[2.5; 100]).unwrap();
        assert!(y.iter().all(|v| (v - 2.5).abs() < 1e-10));
    }

    #[test]
    fn too_short_signal_is_an_error() {
        let sos = butterworth(4, 0.05).unwrap();
        assert_eq!(sos.pad_length(), 15);
        assert!(sos.filtfilt(&[1.0; 15]).is_err());
        assert!(sos.filtfilt(&[1.0; 16]).is_ok());
        // the error says how many samples are needed, by either path
        let needs = |e: crate::error::Error| match e {
            crate::error::Error::TooFewSamples {
                found, required, ..
            } => (found, required),
            e => panic!("{e}"),
        };
        assert_eq!(needs(sos.filtfilt(&[1.0; 15]).unwrap_err()), (15, 16));
        let mut block = vec![1.0; 2 * 15];
        assert_eq!(
            needs(sos.filtfilt_channels(&mut block, 2).unwrap_err()),
            (15, 16)
        );
    }
}
