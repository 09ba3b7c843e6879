//! Low-pass filtering and decimation, as `scipy.signal.decimate` with its default filter
//! scaled to unit gain at zero frequency.
//!
//! Each stage of factor q applies a Chebyshev type I low-pass of order 8 with
//! 0.05 dB ripple and cutoff 0.8 / q (normalised to Nyquist) forward and backward
//! (zero phase, [`Sos::filtfilt`]) and keeps every q-th sample starting with the
//! first. An even-order Chebyshev design passes zero frequency at the bottom of its
//! ripple, 0.05 dB down, so scipy's two passes scale a slow signal by 0.98855 per stage:
//! decimated torques came out 1.1 % low against the measured ones (2.3 % for two stages),
//! an error the fit reported that no model could remove. Each stage's filter is divided
//! by its gain at zero frequency ([`Sos::with_unit_dc_gain`]); the pass band then ripples
//! 0.05 dB above 1 instead of below. A total factor is split into stages of at most 10 (e.g. 100 = 10 x 10,
//! FIGAROH's `decimate(decimate(x, 10), 10)`), because the 8th-order design loses
//! accuracy for larger single factors.

use crate::error::{Error, Result};
use crate::signal::passes::{Forward, Kept, Take};
use crate::signal::{Signals, Sos, chebyshev1};

/// What is wrong with decimation `factors` whose product exceeds
/// [`MAX_DECIMATION`](crate::limits::MAX_DECIMATION), written exactly (a factor of
/// 9223372036854775807 was written 9.223372036854776e18); `None` when it does not.
pub(crate) fn decimation_too_large(factors: &[usize]) -> Option<String> {
    let limit = crate::limits::MAX_DECIMATION as u128;
    let total = factors
        .iter()
        .try_fold(1u128, |t, &q| t.checked_mul(q as u128));
    let shown = match total {
        Some(t) if t <= limit => return None,
        Some(t) => t.to_string(),
        None => format!("beyond {}", crate::Num::rounded(u128::MAX as f64, 2)),
    };
    Some(format!(
        "a total factor of {shown} is more than the limit of {limit}"
    ))
}

/// A chain of decimation stages.
#[derive(Debug, Clone)]
pub struct Decimator {
    stages: Vec<(usize, Option<Sos>)>,
}

impl Decimator {
    /// Stages with the given factors, applied in order (factor 1 = no-op).
    pub fn new(factors: &[usize]) -> Result<Self> {
        if let Some(problem) = decimation_too_large(factors) {
            return Err(Error::setting("Config", "processing.decimation", problem));
        }
        let stages = factors
            .iter()
            .map(|&q| match q {
                0 => Err(Error::setting(
                    "Config",
                    "processing.decimation",
                    "a decimation factor of 0 is meaningless; use 1 for none",
                )),
                1 => Ok((1, None)),
                q => Ok((
                    q,
                    Some(chebyshev1(8, 0.05, 0.8 / q as f64)?.with_unit_dc_gain()),
                )),
            })
            .collect::<Result<Vec<_>>>()?;
        Ok(Self { stages })
    }

    /// Splits `total` into stages of at most 10 (largest factors first).
    pub fn with_total(total: usize) -> Result<Self> {
        Self::new(&split_factor(total)?)
    }

    /// The total factor.
    pub fn factor(&self) -> usize {
        self.stages.iter().map(|s| s.0).product()
    }

    /// The fewest input samples the stages can filter: a stage after stages of total
    /// factor `r` filters `ceil(n / r)` samples, which must be more than its filter's pad
    /// length ([`Sos::pad_length`]). 1 when no stage filters.
    pub fn min_len(&self) -> usize {
        let mut rate = 1;
        let mut needed = 1;
        for (q, sos) in &self.stages {
            if let Some(sos) = sos {
                needed = needed.max(sos.pad_length() * rate + 1);
            }
            rate *= q;
        }
        needed
    }

    /// Length of the output for an input of `n` samples.
    pub fn output_len(&self, n: usize) -> usize {
        self.stages.iter().fold(n, |n, s| n.div_ceil(s.0))
    }

    /// Full-rate samples within which a change at one end of a record reaches the
    /// decimated signal: each stage's settling time (its impulse response's tail below
    /// `tolerance` of its absolute sum, [`Sos::settling_samples`]) at that stage's input
    /// rate, plus one sample of it, summed. Decimating a block of a record that extends
    /// this far beyond the samples kept gives them as decimating the whole record does,
    /// to about `tolerance` of the signal (the zero-phase filter runs both ways, and
    /// each way forgets where it started within the settling time).
    ///
    /// # Panics
    ///
    /// For a `tolerance` outside (0, 1), a programmer's constant (NaN gave 1 sample, 0
    /// and -1 the limit of 4 194 305), also without a filtering stage.
    pub fn settling(&self, tolerance: f64) -> usize {
        assert!(
            tolerance > 0.0 && tolerance < 1.0,
            "Decimator::settling: the tolerance {tolerance} must lie strictly between 0 and 1"
        );
        let mut rate = 1;
        let mut total = 0;
        for (q, sos) in &self.stages {
            if let Some(sos) = sos {
                total += rate * (sos.settling_samples(tolerance, 1 << 22) + 1);
            }
            rate *= q;
        }
        total
    }

    /// The decimated samples of a record of `n` samples whose noise the anti-alias filters
    /// reduced: all but [`Decimator::unsettled`] at each end (a range of output indices;
    /// `0..n` without decimation). A record too short for the filters
    /// ([`Decimator::min_len`]) keeps every sample: what it is too short for says so.
    pub fn settled(&self, n: usize) -> std::ops::Range<usize> {
        let m = self.output_len(n);
        if n < self.min_len() {
            return 0..m;
        }
        let ends = self.unsettled();
        ends..m.saturating_sub(ends).max(ends)
    }

    /// The decimated samples at each end of a record whose noise the anti-alias filters
    /// did not reduce (0 without decimation). The zero-phase filter extends the record by
    /// its odd reflection at each end, as scipy's does, which pins the filtered signal
    /// there to the end sample itself: the first decimated sample carries that one
    /// sample's noise whole, about `f / 0.8` times the variance of a decimated sample
    /// inside the record (the passband keeps `0.8 / f` of white noise), and its next
    /// neighbours much of it. The fit leans on such an equation and its residual does not
    /// show the noise: a UR5e record of 10 000 samples decimated by 500 (20 samples) had
    /// standard deviations 2.5 times smaller than the estimates' spread. Counted at the
    /// start, up to the last decimated sample in which the first sample's weight, squared,
    /// is more than `0.8 / f` (the white-noise gain of one inside); the end, where the
    /// record may stop anywhere between two kept samples, takes as many (the end sample's
    /// weight is below that beyond them whatever the phase, as a test checks).
    pub fn unsettled(&self) -> usize {
        let f = self.factor();
        if f == 1 {
            return 0;
        }
        // the first sample's influence is gone within the settling time: a record of
        // twice that gives its weights as a longer one does
        let n = (2 * self.settling(1e-6) + 2 * f).max(self.min_len());
        // the impulse on a constant of 1, which the stages pass as it is (unit DC gain):
        // an impulse alone decays into subnormal numbers, whose arithmetic took 58 ms for
        // [9, 8, 3] (4 ms this way; the weights that matter exceed 1e-3, far above the
        // rounding of the constant)
        let mut impulse = vec![1.0; n];
        impulse[0] = 2.0;
        let Ok(weights) = self.apply(&impulse) else {
            return 0;
        };
        let gain = 0.8 / f as f64;
        weights
            .iter()
            .rposition(|w| (w - 1.0) * (w - 1.0) > gain)
            .map_or(0, |k| k + 1)
    }

    /// Decimates one signal.
    pub fn apply(&self, x: &[f64]) -> Result<Vec<f64>> {
        let mut cur = x.to_vec();
        let mut work = Vec::new();
        let mut filtered = Vec::new();
        for (q, sos) in &self.stages {
            let Some(sos) = sos else { continue };
            filtered.resize(cur.len(), 0.0);
            sos.filtfilt_into(&cur, &mut work, &mut filtered)?;
            cur = filtered.iter().step_by(*q).copied().collect();
        }
        Ok(cur)
    }

    /// Decimates the channels `channels` of a row-major `n x stride` block (one row per
    /// sample) and returns the `output_len(n) x channels.len()` row-major result.
    /// Processes the channels in lockstep (see [`Sos::filtfilt_channels`]).
    pub fn apply_block(
        &self,
        source: &[f64],
        stride: usize,
        channels: &[usize],
    ) -> Result<Vec<f64>> {
        let g = channels.len();
        let (block, width) = self.apply_block_padded(source, stride, channels)?;
        if width == g {
            return Ok(block);
        }
        Ok(block
            .chunks_exact(width)
            .flat_map(|row| &row[..g])
            .copied()
            .collect())
    }

    /// [`Decimator::apply_block`] with each row of the result padded with channels of
    /// zeros to [`Decimator::padded_width`] of the channels: `(values, row width)`.
    pub(crate) fn apply_block_padded(
        &self,
        source: &[f64],
        stride: usize,
        channels: &[usize],
    ) -> Result<(Vec<f64>, usize)> {
        let g = channels.len();
        let width = self.padded_width(g);
        let zeros = std::iter::repeat_n(0.0, width - g);
        let contiguous = channels.windows(2).all(|w| w[1] == w[0] + 1);
        // the channels with the first stage's pad rows before and after them, which the
        // filter fills (so the samples are written once, not zeroed first)
        let (n, pad) = (source.len() / stride.max(1), self.first_pad());
        let mut ext = Vec::with_capacity((n + 2 * pad) * width);
        ext.resize(pad * width, 0.0);
        for row in source.chunks_exact(stride.max(1)).take(n) {
            if contiguous && g > 0 {
                ext.extend_from_slice(&row[channels[0]..channels[0] + g]);
            } else {
                ext.extend(channels.iter().map(|&c| row[c]));
            }
            ext.extend(zeros.clone());
        }
        ext.resize((n + 2 * pad) * width, 0.0);
        Ok((self.apply_gathered(&mut ext, width)?, width))
    }

    /// The row width to lay `g` channels out in for [`Decimator::apply_gathered`]: `g`
    /// padded with channels of zeros to whole lanes of the filter's passes on this
    /// processor (which then copy no partial lane into a buffer and back row by row);
    /// the zeros stay zeros and the other channels' values are the same to the bit.
    pub(crate) fn padded_width(&self, g: usize) -> usize {
        self.stages
            .iter()
            .find_map(|(_, sos)| sos.as_ref())
            .map_or(g, |sos| {
                crate::signal::passes::padded_width(g, sos.sections().len())
            })
    }

    /// Rows of padding the first filtering stage needs on each side of a block (0 when no
    /// stage filters): the layout [`Decimator::apply_gathered`] takes.
    pub(crate) fn first_pad(&self) -> usize {
        self.stages
            .iter()
            .find_map(|(_, sos)| sos.as_ref().map(Sos::pad_length))
            .unwrap_or(0)
    }

    /// [`Decimator::apply_block`] of `g` channels already gathered into `ext`: row-major,
    /// [`Decimator::first_pad`] rows before and after the samples, which the filter fills
    /// (their values are not read). The first stage filters `ext` in place, so that its
    /// buffer can serve the next block; without a filtering stage the samples are taken
    /// from it as they are.
    pub(crate) fn apply_gathered(&self, ext: &mut Vec<f64>, g: usize) -> Result<Vec<f64>> {
        self.apply_gathered_from(ext, g, Forward::whole())
    }

    /// The number of sections of the one stage that filters, when exactly one does (a
    /// total factor of up to 10): the blocks of a stream can then carry its forward
    /// states from one to the next ([`Decimator::apply_gathered_from`]) instead of
    /// filtering an overlap on their left again; `None` otherwise.
    pub(crate) fn carried_sections(&self) -> Option<usize> {
        let mut filtering = self.stages.iter().filter_map(|(_, s)| s.as_ref());
        match (filtering.next(), filtering.next()) {
            (Some(sos), None) => Some(sos.sections().len()),
            _ => None,
        }
    }

    /// [`Decimator::apply_gathered`] with the forward pass of its filtering stage as
    /// `forward` gives it ([`Forward`]: rows counted in `ext`, pad rows included; states
    /// [`Decimator::carried_sections`] pairs per channel). Only a decimator with one
    /// filtering stage takes a `forward` other than [`Forward::whole`]. A block of a record
    /// whose forward pass goes on from the states the previous block handed on at its
    /// first row, and which extends [`Decimator::settling`] samples beyond the samples
    /// kept on its right, gives them as decimating the whole record does, to the settling
    /// tolerance: the forward pass is the whole record's to the bit.
    pub(crate) fn apply_gathered_from(
        &self,
        ext: &mut Vec<f64>,
        g: usize,
        forward: Forward<'_>,
    ) -> Result<Vec<f64>> {
        let range = self.apply_gathered_in(ext, g, forward)?;
        if range == (0..ext.len()) {
            return Ok(std::mem::take(ext));
        }
        Ok(ext[range].to_vec())
    }

    /// [`Decimator::apply_gathered_from`], the decimated rows left in `ext` instead of a
    /// vector of their own: they are `ext[range]` for the range returned (row-major, `g`
    /// values a row), so that a buffer reused from block to block is not copied out (the
    /// rest of `ext` holds what the filter left there).
    pub(crate) fn apply_gathered_in(
        &self,
        ext: &mut Vec<f64>,
        g: usize,
        forward: Forward<'_>,
    ) -> Result<std::ops::Range<usize>> {
        let carried = forward.from != 0 || forward.start.is_some() || forward.hand.is_some();
        assert!(
            !carried || self.carried_sections().is_some(),
            "a decimation of several filtering stages carries no forward states"
        );
        if g == 0 {
            return Ok(0..0);
        }
        let mut forward = Some(forward);
        // where the last stage's rows are: in `ext`, or in a vector of their own after a
        // later stage
        let mut range = 0..ext.len();
        let mut block: Option<Vec<f64>> = None;
        let mut first = true;
        for (q, sos) in &self.stages {
            let Some(sos) = sos else { continue };
            let pad = sos.pad_length();
            let mut later;
            let in_later = !first;
            let ext: &mut Vec<f64> = if first {
                first = false;
                &mut *ext
            } else {
                let b = block.take().unwrap_or_else(|| ext[range.clone()].to_vec());
                later = Vec::with_capacity(b.len() + 2 * pad * g);
                later.resize(pad * g, 0.0);
                later.extend_from_slice(&b);
                later.resize(b.len() + 2 * pad * g, 0.0);
                &mut later
            };
            // the rows this stage keeps: every q-th of the samples after the pad
            let kept = Kept {
                every: *q,
                first: pad % *q,
            };
            let forward = forward.take().unwrap_or_else(Forward::whole);
            // the rows kept, packed at the end of `ext` by the backward pass (each read
            // from its place afterwards, long gone from the cache, took 1.7 % of the
            // hour's identification), or moved to its front from their places when the
            // passes cannot pack them
            let rows = ext.len() / g;
            let n = rows.saturating_sub(2 * pad);
            let m = n.div_ceil(*q);
            let take = Take {
                rows: pad..pad + n,
                at: rows - m,
            };
            let packed = take.at * g..rows * g;
            let kept_at = if sos.filtfilt_extended_taking(ext, g, kept, forward, Some(take))? {
                packed
            } else {
                for (i, r) in (pad..pad + n).step_by(*q).enumerate() {
                    ext.copy_within(r * g..(r + 1) * g, i * g);
                }
                0..m * g
            };
            if in_later {
                block = Some(ext[kept_at].to_vec());
            } else {
                range = kept_at;
            }
        }
        if let Some(b) = block {
            ext.clear();
            ext.extend_from_slice(&b);
            range = 0..ext.len();
        }
        Ok(range)
    }

    /// Decimates many signals in parallel; signals that are identically zero are
    /// passed through without filtering.
    pub fn apply_all(&self, signals: &Signals) -> Result<Signals> {
        signals.try_map(|x| {
            if x.iter().all(|v| *v == 0.0) {
                Ok(vec![0.0; self.output_len(x.len())])
            } else {
                self.apply(x)
            }
        })
    }
}

/// Whether `n` splits into stages of at most 10 (no prime factor above 7).
fn splits(n: usize) -> bool {
    let mut rest = n;
    for p in [2, 3, 5, 7] {
        while rest.is_multiple_of(p) {
            rest /= p;
        }
    }
    rest == 1
}

/// Splits a total decimation factor into factors of at most 10.
///
/// # Errors
///
/// A total of 0, one above [`MAX_DECIMATION`](crate::limits::MAX_DECIMATION), or one with
/// a prime factor above 7 (the message suggests the nearest factors that split).
pub fn split_factor(total: usize) -> Result<Vec<usize>> {
    if total == 0 {
        return Err(Error::setting(
            "Config",
            "processing.decimation",
            "a decimation factor of 0 is meaningless; use 1 for none",
        ));
    }
    // before the search for the nearest factors that split, which walks one integer at a
    // time (usize::MAX never returned)
    if let Some(problem) = decimation_too_large(&[total]) {
        return Err(Error::setting("Config", "processing.decimation", problem));
    }
    let mut rest = total;
    let mut out = Vec::new();
    while rest > 1 {
        let Some(f) = (2..=10).rev().find(|f| rest.is_multiple_of(*f)) else {
            // the stages found and the rest as one stage, or the nearest factors that split
            // (it said "e.g. decimation = [10, 5]" of 13, a factor of 50)
            let stages: Vec<String> = out.iter().chain([&rest]).map(usize::to_string).collect();
            let below = (1..total).rev().find(|&n| splits(n));
            // suggestions within the limit only, which also bounds the search
            let above =
                (total + 1..=(2 * total).min(crate::limits::MAX_DECIMATION)).find(|&n| splits(n));
            let near: Vec<String> = below
                .into_iter()
                .chain(above)
                .map(|n| n.to_string())
                .collect();
            return Err(Error::setting(
                "Config",
                "processing.decimation",
                format!(
                    "factor {total} has a prime factor above 10, so it does not split into \
                     stages of at most 10 (larger single stages lose accuracy); give the stages \
                     explicitly, decimation = [{}], or a factor that splits, such as {}",
                    stages.join(", "),
                    near.join(" or ")
                ),
            ));
        };
        out.push(f);
        rest /= f;
    }
    if out.is_empty() {
        out.push(1);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn signal() -> Vec<f64> {
        (0..200)
            .map(|k| {
                let k = k as f64;
                (0.05 * k).sin() + 0.3 * (2.1 * k).sin() + 0.001 * k
            })
            .collect()
    }

    /// `min_len` is the shortest record every stage filters: one sample less fails.
    #[test]
    fn min_len_is_the_shortest_record_the_stages_filter() {
        for factors in [&[10][..], &[10, 10], &[5, 1, 4]] {
            let d = Decimator::new(factors).unwrap();
            let n = d.min_len();
            assert!(d.apply(&vec![1.0; n]).is_ok(), "{factors:?}");
            assert!(d.apply(&vec![1.0; n - 1]).is_err(), "{factors:?}");
        }
        assert_eq!(Decimator::new(&[1]).unwrap().min_len(), 1);
    }

    /// A constant comes through every stage unchanged (scipy's filter, at the bottom of
    /// its 0.05 dB ripple at zero frequency, gave 0.98855 of it per stage).
    #[test]
    fn a_constant_is_decimated_to_itself() {
        for factors in [&[2][..], &[10], &[5, 2], &[10, 10]] {
            let d = Decimator::new(factors)
                .unwrap()
                .apply(&[3.5; 4000])
                .unwrap();
            for v in &d {
                assert!((v - 3.5).abs() < 1e-12, "{factors:?}: {v}");
            }
        }
    }

    // scipy 1.17.1: scipy.signal.decimate(x, 10) and decimate(x, 3), divided by the squared
    // gain at zero frequency of scipy's filter (10^(-0.05 / 20) per pass, both passes)
    #[test]
    fn matches_scipy_decimate() {
        let scipy = 10f64.powf(-0.05 / 10.0);
        let d = Decimator::new(&[10]).unwrap().apply(&signal()).unwrap();
        assert_eq!(d.len(), 20);
        for (i, e) in [
            (0, 0.00193708575552111),
            (1, 0.49172942243073364),
            (5, 0.6466763310721192),
            (10, -0.8611792188785817),
            (19, 0.07625414565407923),
        ] {
            assert!((d[i] * scipy - e).abs() < 1e-9, "d[{i}] = {} vs {e}", d[i]);
        }
        let d3 = Decimator::new(&[3]).unwrap().apply(&signal()).unwrap();
        assert_eq!(d3.len(), 67);
        for (i, e) in [
            (0, -0.00090911565693105),
            (1, 0.15168172768447735),
            (30, -0.8794525568451358),
            (66, -0.2630388918546998),
        ] {
            assert!(
                (d3[i] * scipy - e).abs() < 1e-9,
                "d3[{i}] = {} vs {e}",
                d3[i]
            );
        }
    }

    /// The decimated samples [`Decimator::settled`] keeps are those in which neither end
    /// sample weighs more than the white-noise gain 0.8 / f of a sample inside, however the
    /// record ends between two kept samples (the end takes as many as the start); the
    /// first decimated sample is the first sample itself (the odd extension pins it), and
    /// the count is tight at the start.
    #[test]
    fn settled_samples_carry_no_end_samples_noise() {
        assert_eq!(Decimator::new(&[1]).unwrap().settled(50), 0..50);
        let impulse = |n: usize, at: usize| {
            let mut x = vec![0.0; n];
            x[at] = 1.0;
            x
        };
        // the stages and the samples left out at each end (as docs/identification.md says)
        for (stages, left_out) in [
            (&[2][..], 1),
            (&[10], 1),
            (&[3, 2], 1),
            (&[2, 10], 1),
            (&[10, 5], 2),
            (&[10, 10], 2),
            (&[10, 10, 5], 3),
            (&[10, 10, 10], 7),
        ] {
            let dec = Decimator::new(stages).unwrap();
            let (f, ends) = (dec.factor(), dec.unsettled());
            assert_eq!(ends, left_out, "{stages:?}");
            let gain = 0.8 / f as f64;
            let base = 30 * f + dec.min_len();
            let first = dec.apply(&impulse(base, 0)).unwrap();
            assert!((first[0] - 1.0).abs() < 0.05, "{stages:?}: {}", first[0]);
            assert!(
                ends >= 1 && first[ends - 1].powi(2) > gain,
                "{stages:?}: {ends}"
            );
            for r in (0..f).step_by((f / 20).max(1)) {
                let n = base + 1 + r;
                let settled = dec.settled(n);
                assert_eq!(settled, ends..dec.output_len(n) - ends);
                for at in [0, n - 1] {
                    let w = dec.apply(&impulse(n, at)).unwrap();
                    for k in settled.clone() {
                        assert!(
                            w[k] * w[k] <= gain,
                            "{stages:?}, {n} samples: sample {at} weighs {} in {k}",
                            w[k]
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn block_matches_single_channels() {
        let dec = Decimator::new(&[3, 2]).unwrap();
        let x = signal();
        let y: Vec<f64> = x.iter().map(|v| v * v).collect();
        let source: Vec<f64> = x.iter().zip(&y).flat_map(|(a, b)| [*a, 7.0, *b]).collect();
        let out = dec.apply_block(&source, 3, &[2, 0]).unwrap();
        let (dx, dy) = (dec.apply(&x).unwrap(), dec.apply(&y).unwrap());
        assert_eq!(out.len(), 2 * dx.len());
        for k in 0..dx.len() {
            assert!((out[2 * k] - dy[k]).abs() < 1e-12 && (out[2 * k + 1] - dx[k]).abs() < 1e-12);
        }
        // adjacent channels (copied row by row) give the same
        let adjacent = dec.apply_block(&source, 3, &[1, 2]).unwrap();
        let seven = dec.apply(&[7.0; 200]).unwrap();
        for k in 0..dx.len() {
            assert!(
                (adjacent[2 * k] - seven[k]).abs() < 1e-12
                    && (adjacent[2 * k + 1] - dy[k]).abs() < 1e-12
            );
        }
    }

    /// A chain's settling time is each stage's settling time plus one sample, at that
    /// stage's input rate, summed (a stage of factor 1 adds nothing); a block decimated
    /// with that much of the signal on each side gives the whole signal's samples, and
    /// with a quarter of it, not.
    #[test]
    fn settling_sums_the_stages_and_bounds_a_blocks_edges() {
        let dec = Decimator::new(&[3, 1, 2]).unwrap();
        assert_eq!(dec.factor(), 6);
        let stage = |q: f64| {
            chebyshev1(8, 0.05, 0.8 / q)
                .unwrap()
                .settling_samples(1e-12, 1 << 22)
        };
        assert_eq!(dec.settling(1e-12), (stage(3.0) + 1) + 3 * (stage(2.0) + 1));
        let x: Vec<f64> = (0..12_000)
            .map(|k| {
                let k = k as f64;
                (0.013 * k).sin() + 0.4 * (0.9 * k).cos() + 0.2 * (2.3 * k).sin()
            })
            .collect();
        let whole = dec.apply(&x).unwrap();
        let worst = |overlap: usize| {
            let overlap = overlap.div_ceil(6) * 6;
            let (a, b) = (6000, 7200);
            let part = dec.apply(&x[a - overlap..b + overlap]).unwrap();
            (a / 6..b / 6)
                .map(|k| (part[k - (a - overlap) / 6] - whole[k]).abs())
                .fold(0.0, f64::max)
        };
        let full = dec.settling(1e-15);
        // measured: 0 (the same values) with the settling time, a few ulp allowed;
        // 1.4e-7 with a quarter of it
        assert!(worst(full) < 1e-14, "{:e}", worst(full));
        assert!(worst(full / 4) > 7e-8, "{:e}", worst(full / 4));
    }

    /// A record decimated block by block, each block's forward pass going on from the
    /// states the previous block handed on at its first sample (no overlap on the left)
    /// and [`Decimator::settling`] samples beyond it on the right, gives the whole
    /// record's decimation to rounding; the blocks' forward passes started afresh from
    /// their first sample instead do not. Several channels, blocks of uneven lengths.
    #[test]
    fn blocks_carrying_the_forward_states_give_the_whole_records_decimation() {
        let dec = Decimator::new(&[10]).unwrap();
        assert_eq!(dec.carried_sections(), Some(4));
        assert_eq!(Decimator::new(&[10, 2]).unwrap().carried_sections(), None);
        assert_eq!(
            Decimator::new(&[1, 5, 1]).unwrap().carried_sections(),
            Some(4)
        );
        assert_eq!(Decimator::new(&[1]).unwrap().carried_sections(), None);
        let (n, g, ns) = (20_000, 5, 4);
        let x: Vec<f64> = (0..n * g)
            .map(|i| {
                let (k, c) = ((i / g) as f64, (i % g) as f64);
                (0.013 * k * (1.0 + 0.1 * c)).sin() + 0.4 * (0.9 * k + c).cos() + c
            })
            .collect();
        let whole = dec.apply_block(&x, g, &(0..g).collect::<Vec<_>>()).unwrap();
        let scale = whole.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let (pad, overlap) = (dec.first_pad(), dec.settling(1e-15).div_ceil(10) * 10);
        let worst = |carried: bool| {
            let mut states: Vec<[f64; 2]> = Vec::new();
            let mut worst = 0.0f64;
            let cuts = [0, 3_000, 9_990, 10_000, 15_550, n];
            for b in cuts.windows(2) {
                let (lo, hi) = (b[0], (b[1] + overlap).min(n));
                let mut ext = vec![0.0; (hi - lo + 2 * pad) * g];
                ext[pad * g..(pad + hi - lo) * g].copy_from_slice(&x[lo * g..hi * g]);
                let mut handed = vec![[0.0; 2]; g * ns];
                let go_on = carried && !states.is_empty();
                let forward = Forward {
                    from: if go_on { pad } else { 0 },
                    start: go_on.then_some(states.as_slice()),
                    hand: Some((pad + b[1] - lo, handed.as_mut_slice())),
                };
                let out = dec.apply_gathered_from(&mut ext, g, forward).unwrap();
                states = handed;
                for k in b[0] / 10..b[1].div_ceil(10) {
                    for c in 0..g {
                        let d = out[(k - lo / 10) * g + c] - whole[k * g + c];
                        worst = worst.max(d.abs() / scale);
                    }
                }
            }
            worst
        };
        eprintln!("carried {:e}, afresh {:e}", worst(true), worst(false));
        // measured: 3.1e-15 carried with scipy's filter, 1.0e-14 scaled to unit gain at
        // zero frequency (rounding either way), 0.078 afresh
        assert!(worst(true) < 5e-14, "{:e}", worst(true));
        assert!(worst(false) > 1e-3, "{:e}", worst(false));
    }

    /// A tolerance outside (0, 1) is a programmer's error, told as such.
    #[test]
    fn a_settling_tolerance_outside_zero_to_one_is_refused() {
        for factors in [&[10][..], &[1]] {
            let dec = Decimator::new(factors).unwrap();
            for tolerance in [f64::NAN, 0.0, -1.0, 2.0] {
                let e = std::panic::catch_unwind(|| dec.settling(tolerance)).unwrap_err();
                let e = e.downcast_ref::<String>().unwrap();
                assert!(e.contains("strictly between 0 and 1"), "{tolerance}: {e}");
            }
        }
    }

    #[test]
    fn factor_splitting() {
        assert_eq!(split_factor(100).unwrap(), vec![10, 10]);
        assert_eq!(split_factor(20).unwrap(), vec![10, 2]);
        assert_eq!(split_factor(1).unwrap(), vec![1]);
        assert!(split_factor(13).is_err());
        // the advice is a factor of the total, or a nearby one that splits (it was [10, 5]
        // for 13)
        for (total, advice) in [
            (
                13,
                "decimation = [13], or a factor that splits, such as 12 or 14",
            ),
            (
                26,
                "decimation = [2, 13], or a factor that splits, such as 25 or 27",
            ),
            (
                143,
                "decimation = [143], or a factor that splits, such as 140 or 144",
            ),
        ] {
            let e = split_factor(total).unwrap_err().to_string();
            assert!(e.contains(advice), "{e}");
        }
        assert!(split_factor(0).is_err());
        // a total above the limit is refused before the search for the nearest factors
        // that split, which walked one integer at a time (usize::MAX never returned);
        // a prime just below the limit is advised factors within it
        for total in [usize::MAX, 17_000_000_000_000, 10_007] {
            let e = split_factor(total).unwrap_err().to_string();
            assert!(e.contains("more than the limit of 10000"), "{total}: {e}");
            let e = Decimator::with_total(total).unwrap_err().to_string();
            assert!(e.contains("more than the limit of 10000"), "{total}: {e}");
        }
        let e = split_factor(9_967).unwrap_err().to_string();
        assert!(e.contains("such as 9800 or 10000"), "{e}");
        assert_eq!(Decimator::with_total(100).unwrap().output_len(44960), 450);
    }

    #[test]
    fn parallel_matches_serial_and_keeps_zeros() {
        let dec = Decimator::with_total(10).unwrap();
        // no zero sample in the first signal: only an all-zero signal skips the filter
        let lifted: Vec<f64> = signal().iter().map(|v| v + 2.0).collect();
        let signals = Signals::new(vec![lifted, vec![0.0; 200]]).unwrap();
        let out = dec.apply_all(&signals).unwrap();
        assert_eq!(out[0], dec.apply(&signals[0]).unwrap());
        assert_eq!(out[1], [0.0; 20]);
    }
}
