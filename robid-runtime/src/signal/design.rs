//! Digital low-pass design as second-order sections, the way `scipy.signal` does it.
//!
//! Analog prototype (Butterworth or Chebyshev type I) -> frequency pre-warping ->
//! bilinear transform -> sections. Sections are ordered as `scipy.signal.zpk2sos`
//! orders them for a low-pass (poles farthest from the unit circle first, the gain in
//! the first section, for odd orders the real pole first), so the coefficients can be
//! compared with scipy's one to one.

use nalgebra::Complex;

use crate::error::{Error, Result};
use crate::signal::Sos;

type C = Complex<f64>;

/// Butterworth low-pass of `order`, `cutoff` normalised to the Nyquist frequency (0 < cutoff < 1),
/// as `scipy.signal.butter(order, cutoff, output="sos")`.
pub fn butterworth(order: usize, cutoff: f64) -> Result<Sos> {
    check(order, cutoff)?;
    let n = order as f64;
    // buttap: p = -exp(j pi m / (2N)), m = -N+1, -N+3, ..., N-1
    let poles: Vec<C> = (0..order)
        .map(|i| {
            let m = -(n - 1.0) + 2.0 * i as f64;
            -C::from_polar(1.0, core::f64::consts::PI * m / (2.0 * n))
        })
        .collect();
    digital_lowpass(&poles, 1.0, cutoff)
}

/// Butterworth low-pass with the cutoff in Hz for data sampled at `sample_rate` Hz.
///
/// # Errors
///
/// A `sample_rate` or `cutoff_hz` that is not positive and finite (each checked on its
/// own: their ratio alone took -10 Hz at -100 Hz for 0.2 of the Nyquist frequency), and
/// what [`butterworth`] refuses of the order and the normalised cutoff.
pub fn butterworth_hz(order: usize, cutoff_hz: f64, sample_rate: f64) -> Result<Sos> {
    Error::positive_and_finite(
        "butterworth",
        "sample_rate",
        "the sample rate",
        sample_rate,
        "Hz",
    )?;
    Error::positive_and_finite("butterworth", "cutoff", "the cutoff", cutoff_hz, "Hz")?;
    butterworth(order, cutoff_hz / (0.5 * sample_rate))
}

/// Smallest pass-band ripple (dB) that [`chebyshev1`] accepts. scipy's `10^(r/10) - 1`,
/// kept to match its coefficients, cancels all but about `log10(0.23 r / 2.2e-16)` digits:
/// 9 at 1e-6 dB, none near 5e-16 dB, where the design's coefficients were NaN. The
/// smaller the ripple, the farther above the cutoff the half-power point lies
/// (`cosh(acosh(1 / eps) / order)` times it: 2083 times for order 1 at 1e-6 dB), so a
/// smaller ripple is a wider filter, not a flatter one; robid's decimation uses 0.05 dB.
pub const MIN_RIPPLE: f64 = 1e-6;

/// Largest pass-band ripple (dB) that [`chebyshev1`] accepts: an even order passes zero
/// frequency at the bottom of its ripple, a gain of `10^(-r/20)`, 1e-5 at 100 dB, and a
/// pass band that varies by that much is no pass band (3100 dB overflowed `10^(r/10)` and
/// gave a filter of gain 0).
pub const MAX_RIPPLE: f64 = 100.0;

/// Chebyshev type I low-pass with `ripple_db` pass-band ripple,
/// as `scipy.signal.cheby1(order, ripple_db, cutoff, output="sos")`.
///
/// # Errors
///
/// What [`butterworth`] refuses of the order and the cutoff, a ripple outside
/// [[`MIN_RIPPLE`], [`MAX_RIPPLE`]] dB, and a design whose coefficients are not finite or
/// whose gain at zero frequency is 0 or not finite (none within these ranges, as a test
/// checks; kept as the last guard).
pub fn chebyshev1(order: usize, ripple_db: f64, cutoff: f64) -> Result<Sos> {
    check(order, cutoff)?;
    if !(MIN_RIPPLE..=MAX_RIPPLE).contains(&ripple_db) {
        return Err(Error::setting(
            "chebyshev1",
            "ripple_db",
            format!(
                "pass-band ripple {} dB must lie in [{MIN_RIPPLE:e}, {MAX_RIPPLE}] dB (a \
                 smaller one loses the design's digits, a larger one leaves no pass band)",
                crate::error::num(ripple_db)
            ),
        ));
    }
    let n = order as f64;
    let eps = (10f64.powf(0.1 * ripple_db) - 1.0).sqrt();
    let mu = (1.0 / eps).asinh() / n;
    let poles: Vec<C> = (0..order)
        .map(|i| {
            let m = -(n - 1.0) + 2.0 * i as f64;
            let theta = core::f64::consts::PI * m / (2.0 * n);
            -C::new(mu, theta).sinh()
        })
        .collect();
    let mut gain = poles.iter().fold(C::new(1.0, 0.0), |acc, p| acc * -p).re;
    if order.is_multiple_of(2) {
        gain /= (1.0 + eps * eps).sqrt();
    }
    digital_lowpass(&poles, gain, cutoff)
}

/// Smallest cutoff, as a fraction of the Nyquist frequency, that a design accepts.
pub const MIN_CUTOFF: f64 = 1e-5;

/// Largest cutoff, as a fraction of the Nyquist frequency, that a design accepts: closer
/// to it the poles come within about `1 - MAX_CUTOFF` of -1, where they and the gain lose
/// their digits (order 20 within 5e-9 of it gave a filter of gain 0), and the filter
/// passes nearly everything anyway.
pub const MAX_CUTOFF: f64 = 1.0 - MIN_CUTOFF;

fn check(order: usize, cutoff: f64) -> Result<()> {
    if order == 0 || order > 20 {
        return Err(Error::setting(
            "butterworth",
            "order",
            format!("filter order {order} must be between 1 and 20"),
        ));
    }
    if !(cutoff > 0.0 && cutoff < 1.0) {
        return Err(Error::setting(
            "butterworth",
            "cutoff",
            format!(
                "normalised cutoff {} must lie strictly between 0 and 1 (the Nyquist frequency); lower the cutoff or raise the sample rate",
                crate::error::num(cutoff)
            ),
        ));
    }
    if cutoff > MAX_CUTOFF {
        return Err(Error::setting(
            "butterworth",
            "cutoff",
            format!(
                "normalised cutoff {} is within {MIN_CUTOFF:e} of the Nyquist frequency, where the filter's poles are too close to -1 to be represented; lower the cutoff, or leave the low-pass out (so close to the Nyquist frequency it filters almost nothing)",
                crate::error::num(cutoff)
            ),
        ));
    }
    if cutoff < MIN_CUTOFF {
        return Err(Error::setting(
            "butterworth",
            "cutoff",
            format!(
                "normalised cutoff {} is below {MIN_CUTOFF:e} of the Nyquist frequency, where the filter's poles are too close to 1 to be represented; raise the cutoff or decimate the data first",
                crate::error::num(cutoff)
            ),
        ));
    }
    Ok(())
}

/// Analog prototype poles (cutoff 1 rad/s, no zeros) -> digital low-pass sections;
/// an error for coefficients that are not finite or a gain at zero frequency of 0.
fn digital_lowpass(proto: &[C], proto_gain: f64, cutoff: f64) -> Result<Sos> {
    let fs2 = 4.0; // 2 * fs with scipy's normalised fs = 2
    let warped = fs2 * (core::f64::consts::PI * cutoff / 2.0).tan();
    let n = proto.len();
    let analog: Vec<C> = proto.iter().map(|p| p * warped).collect();
    let k_analog = proto_gain * warped.powi(n as i32);
    let digital: Vec<C> = analog.iter().map(|p| (fs2 + p) / (fs2 - p)).collect();
    let denom = analog
        .iter()
        .fold(C::new(1.0, 0.0), |acc, p| acc * (fs2 - p));
    let gain = k_analog * (C::new(1.0, 0.0) / denom).re;

    // one pole of each conjugate pair, chosen on the prototype (unit circle, well-separated
    // imaginary parts), not on the digital pole, whose imaginary part vanishes as the
    // cutoff does
    let mut pairs: Vec<C> = proto
        .iter()
        .zip(&digital)
        .filter(|(a, _)| a.im > 1e-9)
        .map(|(_, d)| if d.im < 0.0 { d.conj() } else { *d })
        .collect();
    pairs.sort_by(|a, b| a.norm().total_cmp(&b.norm()));
    let real: Option<C> = (n % 2 == 1).then(|| {
        proto
            .iter()
            .zip(&digital)
            .min_by(|a, b| a.0.im.abs().total_cmp(&b.0.im.abs()))
            .map_or(C::new(0.0, 0.0), |(_, d)| *d)
    });
    let mut sections = Vec::with_capacity(n.div_ceil(2));
    if let Some(p) = real {
        sections.push([1.0, 2.0, 1.0, 1.0, -p.re, 0.0]);
    }
    for (i, p) in pairs.iter().enumerate() {
        let last = i + 1 == pairs.len();
        let b = if real.is_some() && last {
            [1.0, 1.0, 0.0]
        } else {
            [1.0, 2.0, 1.0]
        };
        sections.push([b[0], b[1], b[2], 1.0, -2.0 * p.re, p.norm_sqr()]);
    }
    if n == 1 {
        // one real pole and one zero at -1
        sections[0] = [1.0, 1.0, 0.0, 1.0, -real.map_or(0.0, |p| p.re), 0.0];
    }
    for c in &mut sections[0][..3] {
        *c *= gain;
    }
    let sos = Sos::new(sections)?;
    let dc = sos.dc_gain();
    if !(dc.is_finite() && dc != 0.0) {
        return Err(Error::setting(
            "butterworth",
            "cutoff",
            format!(
                "the design at normalised cutoff {} has a gain of {} at zero frequency; \
                 choose a cutoff and order nearer the usual ones",
                crate::error::num(cutoff),
                crate::error::num(dc)
            ),
        ));
    }
    Ok(sos)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Within 1e-5 of the Nyquist frequency the design is refused: order 20 within 5e-9
    /// of it gave gain 0. At the limit the gain is still 1.
    #[test]
    fn a_cutoff_at_the_nyquist_frequency_is_refused() {
        let e = butterworth(20, 1.0 - 5e-9).unwrap_err().to_string();
        assert!(e.contains("within 1e-5 of the Nyquist frequency"), "{e}");
        for order in [1, 2, 7, 20] {
            let sos = butterworth(order, MAX_CUTOFF).unwrap();
            assert!((sos.dc_gain() - 1.0).abs() < 1e-9, "{}", sos.dc_gain());
            assert!(sos.pole_radius() < 1.0);
        }
    }

    fn assert_sos(sos: &Sos, expected: &[[f64; 6]]) {
        assert_eq!(sos.sections().len(), expected.len());
        for (s, e) in sos.sections().iter().zip(expected) {
            for (a, b) in s.iter().zip(e) {
                assert!((a - b).abs() <= 1e-12 * b.abs().max(1e-3), "{s:?} vs {e:?}");
            }
        }
    }

    // Reference numbers: scipy 1.17.1, scipy.signal.butter / cheby1 with output="sos".
    #[test]
    fn butterworth_order4_50hz_at_1khz_matches_scipy() {
        let sos = butterworth_hz(4, 50.0, 1000.0).unwrap();
        assert_sos(
            &sos,
            &[
                [
                    4.1659920440659937e-04,
                    8.331_984_088_131_987e-4,
                    4.1659920440659937e-04,
                    1.0,
                    -1.4796742169311934,
                    5.558_215_432_824_889e-1,
                ],
                [
                    1.0,
                    2.0,
                    1.0,
                    1.0,
                    -1.7009643319435257,
                    7.884_997_398_152_979e-1,
                ],
            ],
        );
    }

    #[test]
    fn butterworth_order4_low_cutoff_matches_scipy() {
        let sos = butterworth(4, 0.01).unwrap();
        assert_sos(
            &sos,
            &[
                [
                    5.845_142_433_144_487e-8,
                    1.1690284866288973e-07,
                    5.845_142_433_144_487e-8,
                    1.0,
                    -1.9426382305401135,
                    9.435_972_784_703_671e-1,
                ],
                [
                    1.0,
                    2.0,
                    1.0,
                    1.0,
                    -1.975_269_634_851_873,
                    9.762_447_923_594_398e-1,
                ],
            ],
        );
    }

    #[test]
    fn butterworth_odd_order_matches_scipy() {
        let sos = butterworth(3, 0.1).unwrap();
        assert_sos(
            &sos,
            &[
                [
                    0.00289819463372143,
                    0.00579638926744286,
                    0.00289819463372143,
                    1.0,
                    -0.726542528005361,
                    0.0,
                ],
                [1.0, 1.0, 0.0, 1.0, -1.647552215703991, 0.7323389172728038],
            ],
        );
    }

    #[test]
    fn chebyshev_decimation_filter_matches_scipy() {
        let sos = chebyshev1(8, 0.05, 0.08).unwrap();
        assert_sos(
            &sos,
            &[
                [
                    3.5863243209995223e-09,
                    7.172_648_641_999_045e-9,
                    3.5863243209995223e-09,
                    1.0,
                    -1.8204968644767618,
                    8.308_597_403_796_137e-1,
                ],
                [
                    1.0,
                    2.0,
                    1.0,
                    1.0,
                    -1.8289505620176847,
                    8.553_173_710_387_741e-1,
                ],
                [
                    1.0,
                    2.0,
                    1.0,
                    1.0,
                    -1.8517334482627625,
                    9.015_161_055_713_813e-1,
                ],
                [
                    1.0,
                    2.0,
                    1.0,
                    1.0,
                    -1.8965395961864169,
                    9.644_245_584_642_932e-1,
                ],
            ],
        );
        let odd = chebyshev1(3, 0.05, 0.3).unwrap();
        assert_sos(
            &odd,
            &[
                [
                    0.09222689686087072,
                    0.18445379372174145,
                    0.09222689686087072,
                    1.0,
                    -0.26630456094563476,
                    0.0,
                ],
                [1.0, 1.0, 0.0, 1.0, -0.4451433056793242, 0.4507583546673763],
            ],
        );
    }

    /// The ripple is refused outside [1e-6, 100] dB (1e-20 dB gave NaN coefficients,
    /// 3100 dB a filter of gain 0); within it every order and cutoff designs finite
    /// sections with the gain at zero frequency of the ripple's bottom (even orders) or 1.
    #[test]
    fn the_ripple_is_bounded_and_the_designs_within_it_are_finite() {
        for ripple in [
            1e-20,
            5e-16,
            9e-7,
            100.5,
            400.0,
            3100.0,
            f64::NAN,
            f64::INFINITY,
        ] {
            let e = chebyshev1(4, ripple, 0.3).unwrap_err().to_string();
            assert!(e.contains("must lie in [1e-6, 100] dB"), "{ripple}: {e}");
        }
        for ripple in [MIN_RIPPLE, 0.05, 3.0, MAX_RIPPLE] {
            for order in [1, 2, 3, 8, 19, 20] {
                for cutoff in [MIN_CUTOFF, 0.3, MAX_CUTOFF] {
                    let sos = chebyshev1(order, ripple, cutoff).unwrap();
                    assert!(sos.sections().iter().flatten().all(|c| c.is_finite()));
                    let want = if order % 2 == 0 {
                        10f64.powf(-ripple / 20.0)
                    } else {
                        1.0
                    };
                    // the poles near 1 at the smallest cutoff: 1e-6 relative at order 8
                    // in `bad_design_inputs_are_errors`, more at order 20 (measured below
                    // 1e-3 here)
                    let gain = sos.dc_gain();
                    assert!(
                        (gain / want - 1.0).abs() < 1e-2,
                        "order {order}, {ripple} dB, cutoff {cutoff}: {gain} against {want}"
                    );
                }
            }
        }
    }

    #[test]
    fn unit_dc_gain() {
        for order in 1..=9 {
            let sos = butterworth(order, 0.2).unwrap();
            assert!((sos.dc_gain() - 1.0).abs() < 1e-12, "order {order}");
        }
    }

    #[test]
    fn bad_design_inputs_are_errors() {
        assert!(butterworth(0, 0.1).is_err());
        assert!(butterworth(4, 1.0).is_err());
        assert!(butterworth(4, f64::NAN).is_err());
        assert!(butterworth_hz(4, 600.0, 1000.0).is_err());
        assert!(chebyshev1(8, -1.0, 0.1).is_err());
        // the bounds themselves: order 20 and a cutoff of exactly MIN_CUTOFF are designed,
        // order 21, a ripple of 0 dB and a cutoff of 0 are refused, each by its own check
        assert!(butterworth(20, 0.3).is_ok());
        assert!(butterworth(21, 0.3).is_err());
        assert!(butterworth(4, MIN_CUTOFF).is_ok());
        assert!(chebyshev1(8, 0.0, 0.1).is_err());
        // each of the sample rate and the cutoff in Hz on its own (their ratio, 0.2, was
        // taken for -10 Hz at -100 Hz)
        for (cutoff, rate, key) in [
            (-10.0, -100.0, "sample rate -10"),
            (10.0, -100.0, "sample rate -100"),
            (-10.0, 100.0, "cutoff -10 Hz"),
            (f64::NAN, 100.0, "cutoff NaN Hz"),
            (10.0, f64::INFINITY, "sample rate inf"),
            (f64::INFINITY, f64::INFINITY, "sample rate inf"),
        ] {
            let e = butterworth_hz(2, cutoff, rate).unwrap_err().to_string();
            assert!(e.contains(key), "{cutoff} Hz at {rate} Hz: {e}");
        }
        let zero = butterworth(4, 0.0).unwrap_err().to_string();
        assert!(zero.contains("strictly between 0 and 1"), "{zero}");
        // a cutoff too small to represent is an error, not an empty filter (the fuzzer's
        // `cutoff = 1e-12` once built no sections and indexed an empty list)
        assert!(butterworth(4, 1e-12).is_err());
        for order in 1..=8 {
            let s = butterworth(order, 2.0 * MIN_CUTOFF).unwrap();
            assert_eq!(s.sections().len(), order.div_ceil(2), "order {order}");
            // rounding, amplified: a section's 1 + a1 + a2 = |1 - p|^2 ~ (pi cutoff)^2 =
            // 3.9e-9 cancels terms of order 1, so its gain carries ~4 eps / 3.9e-9 = 2.3e-7,
            // and order 8 has four sections (measured 4.3e-8 at order 8, 5.5e-13 at order 1)
            assert!(
                (s.dc_gain() - 1.0).abs() < 1e-6,
                "order {order}: {}",
                s.dc_gain()
            );
        }
    }
}
