//! Turning numeric dependency coefficients into expressions.
//!
//! A constant is kept exact when it is one to [`EXACT_TOLERANCE`]: a
//! fraction with a denominator up to [`MAX_DENOMINATOR`] (`1/9.81 =
//! 100/981`) or a decimal of up to 10 digits ([`rationalize`]); otherwise it
//! is the float itself ([`constant`]). The engine has no exact
//! form for irrational numbers such as `sqrt(3)/3` (the tangent of a pi/6
//! twist), so those are floats, correct to rounding.
//!
//! A coefficient that varies with the geometric symbols is fitted as a
//! polynomial in the atoms of `atoms.rs` (the symbols, and the sines and
//! cosines of symbolic angles), of the lowest degree up to [`MAX_DEGREE`]
//! that reproduces it, each monomial coefficient a [`constant`]
//! ([`fit_polynomial`]).

use super::atoms::Atom;
use crate::expr::{Arena, Id, Num, Values};

/// The largest denominator tried for a constant that is not a short fraction.
pub(crate) const MAX_DENOMINATOR: i128 = 10_000;

/// Relative distance within which a computed constant is taken for an exact
/// one: above the rounding of a computed coefficient, and small enough that
/// taking a number that is not exact for a nearby fraction or decimal moves
/// the torques by less than their rounding.
pub(crate) const EXACT_TOLERANCE: f64 = 1e-13;

/// Highest total degree of a fitted polynomial in the atoms.
pub(crate) const MAX_DEGREE: usize = 4;

/// Most monomials a fit may have (each needs a sample of the regressor at
/// other symbol values): 16 symbols at degree two have 153.
pub(crate) const MAX_MONOMIALS: usize = 160;

/// Relative residual within which a fit reproduces the sampled values.
pub(crate) const FIT_TOLERANCE: f64 = 1e-8;

/// The exact number equal to `x` to [`EXACT_TOLERANCE`] (relative), when
/// there is one: a fraction with a denominator up to [`MAX_DENOMINATOR`]
/// (`1/3`, `100/981`), or else a decimal of up to 10 digits (a product of
/// lengths, `0.166685`).
pub(crate) fn rationalize(x: f64) -> Option<Num> {
    if x == 0.0 {
        return Some(Num::ZERO);
    }
    if !x.is_finite() {
        return None;
    }
    let tolerance = EXACT_TOLERANCE * x.abs();
    fraction(x, tolerance).or_else(|| {
        (1..=10).find_map(|digits| {
            let scale = 10f64.powi(digits);
            let r = (x * scale).round() / scale;
            // Also far closer than the decimal's own step, so that a decimal
            // with many digits is not taken for a near number by chance.
            ((r - x).abs() <= tolerance.min(1e-4 / scale))
                .then(|| Num::parse_decimal(&format!("{r:.*}", digits as usize)))
                .flatten()
        })
    })
}

/// The fraction with the smallest denominator up to [`MAX_DENOMINATOR`]
/// within `tolerance` of `x`: a convergent of its continued fraction (any
/// fraction that close is one).
fn fraction(x: f64, tolerance: f64) -> Option<Num> {
    if x.abs() > 1e12 {
        return None;
    }
    let target = x.abs();
    let ulp = f64::from_bits(target.to_bits() + 1) - target;
    // Convergents h/k: h(n) = a h(n-1) + h(n-2), likewise k.
    let (mut h0, mut h1, mut k0, mut k1) = (0_i128, 1_i128, 1_i128, 0_i128);
    let mut rest = target;
    for _ in 0..64 {
        let a = rest.floor();
        let h = (a as i128).checked_mul(h1)?.checked_add(h0)?;
        let k = (a as i128).checked_mul(k1)?.checked_add(k0)?;
        if k > MAX_DENOMINATOR {
            return None;
        }
        // Also far closer than a convergent is by its nature (within 1/k^2), and that
        // closeness itself far above the float's own step, as a decimal must be far
        // closer than its step: a large number is within its relative tolerance of some
        // convergent by chance (a coefficient 9.09e8 was written 60909089260/67; of
        // random numbers near 1e4, 32 % were fractions, now 0.02 %).
        let close = 1e-4 / ((k as f64) * (k as f64));
        if close >= 64.0 * ulp && (h as f64 / k as f64 - target).abs() <= tolerance.min(close) {
            return Num::ratio(if x < 0.0 { -h } else { h }, k);
        }
        (h0, h1, k0, k1) = (h1, h, k1, k);
        let fractional = rest - a;
        if fractional <= 0.0 {
            return None;
        }
        rest = 1.0 / fractional;
    }
    None
}

/// `x` as an exact number when it is one (see [`rationalize`]), else as a float.
pub(crate) fn constant(x: f64) -> Num {
    rationalize(x).unwrap_or(Num::Float(x))
}

/// Monomials of total degree at most `degree` in the atoms, each as the list
/// of its atoms' positions (with repetition, non-decreasing), the constant
/// first. A paired cosine appears at most once in a monomial
/// (`cos^2 = 1 - sin^2`), so the monomials are independent functions.
pub(crate) fn monomials(atoms: &[Atom], degree: usize) -> Vec<Vec<usize>> {
    let mut out = vec![Vec::new()];
    let mut previous = vec![Vec::new()];
    for _ in 0..degree {
        let mut next = Vec::new();
        for m in &previous {
            let from = m.last().copied().unwrap_or(0);
            for (a, atom) in atoms.iter().enumerate().skip(from) {
                if atom.paired_cosine && m.last() == Some(&a) {
                    continue;
                }
                let mut longer = m.clone();
                longer.push(a);
                next.push(longer);
            }
        }
        out.extend(next.iter().cloned());
        previous = next;
        if !within_limit(out.len()) {
            break;
        }
    }
    out
}

/// Whether a fit of `monomials` monomials is within [`MAX_MONOMIALS`].
pub(crate) fn within_limit(monomials: usize) -> bool {
    monomials <= MAX_MONOMIALS
}

/// Samples for a fit: the atoms' values and the coefficient's value at each
/// sample of the geometric symbols.
pub(crate) struct Samples<'a> {
    /// `atoms[s][a]`: atom `a` at sample `s`.
    pub(crate) atoms: &'a [Vec<f64>],
    /// The coefficient at each sample.
    pub(crate) values: &'a [f64],
    /// The geometric symbols' values at each sample, for checking the result.
    pub(crate) geometry: &'a [Values],
}

/// Fits `values` by a polynomial of total degree at most `degree` in the
/// atoms, by least squares on the first `fit` samples; returns its
/// expression when it reproduces every sample to [`FIT_TOLERANCE`], with
/// exact coefficients where they are exact (floats otherwise).
pub(crate) fn fit_polynomial(
    arena: &mut Arena,
    atoms: &[Atom],
    degree: usize,
    samples: &Samples<'_>,
    fit: usize,
) -> Option<Id> {
    let basis = monomials(atoms, degree);
    let fit = fit.min(samples.values.len());
    if !within_limit(basis.len()) || fit < basis.len() {
        return None;
    }
    let value_of = |s: usize, m: &[usize]| m.iter().map(|&a| samples.atoms[s][a]).product::<f64>();
    let a = nalgebra::DMatrix::from_fn(fit, basis.len(), |r, m| value_of(r, &basis[m]));
    let scale = samples.values.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    if scale == 0.0 {
        return Some(arena.zero());
    }
    let x = super::rank::least_squares(&a, &samples.values[..fit])?;
    let fitted = &a * nalgebra::DVector::from_column_slice(&x);
    let worst = fitted
        .iter()
        .zip(&samples.values[..fit])
        .fold(0.0_f64, |m, (f, v)| m.max((f - v).abs()));
    if worst > FIT_TOLERANCE * scale {
        return None;
    }
    // Size of each monomial over the samples, to drop coefficients that are
    // rounding noise.
    let size: Vec<f64> = (0..basis.len()).map(|m| a.column(m).amax()).collect();
    let build = |arena: &mut Arena, exact: bool| {
        let mut terms = Vec::new();
        for (m, (monomial, c)) in basis.iter().zip(x.iter()).enumerate() {
            if c.abs() * size[m] <= 1e-12 * scale {
                continue;
            }
            let number = if exact { constant(*c) } else { Num::Float(*c) };
            let mut factors = vec![arena.num(number)];
            factors.extend(monomial.iter().map(|&i| atoms[i].id));
            terms.push(arena.mul(&factors));
        }
        arena.add(&terms)
    };
    let reproduces = |arena: &Arena, e: Id| {
        samples.geometry.iter().zip(samples.values).all(|(g, v)| {
            arena
                .eval(&[e], g)
                .is_ok_and(|r| (r[0] - v).abs() <= FIT_TOLERANCE * scale)
        })
    };
    // Exact numbers where they fit, else the fitted floats.
    let exact = build(arena, true);
    if reproduces(arena, exact) {
        return Some(exact);
    }
    let floats = build(arena, false);
    reproduces(arena, floats).then_some(floats)
}

#[cfg(test)]
mod tests {
    use super::{Samples, constant, fit_polynomial, fraction, monomials, rationalize};
    use crate::expr::{Arena, Num, Values};
    use crate::regroup::atoms::Atom;

    #[test]
    fn rationalizes_lengths_and_fractions() {
        assert_eq!(rationalize(0.425 * 0.3922), Num::parse_decimal("0.166685"));
        assert_eq!(rationalize(-1.0 / 3.0), Num::ratio(-1, 3));
        assert_eq!(rationalize(std::f64::consts::PI), None);
        // 2 cos(pi/4) 0.553 = 0.78206009999.. is not the decimal 0.7820601.
        let x = 2.0 * std::f64::consts::FRAC_PI_4.cos() * 0.553;
        assert_eq!(rationalize(x), None);
    }

    /// The tolerance is relative: a small number 3e-9 away (relatively) from 1/3000 is
    /// no fraction, though 1e-12 away in absolute terms. Decimals and fractions agree
    /// where both exist (what makes the bounds at 1e12 and at the largest denominator
    /// equivalent in mutants-equivalent.txt).
    #[test]
    fn the_tolerance_is_relative_and_decimals_equal_fractions() {
        assert_eq!(rationalize(1.0 / 3000.0 + 1e-12), None);
        assert_eq!(rationalize(1.0 / 3000.0), Num::ratio(1, 3000));
        // 5e-5 from 60909089260/67 is within 1e-13 of it, relatively, but a float near
        // 9e8 cannot tell a fraction of denominator 67 from its neighbours: no fraction
        // (nor any other: it was 2177272668324/2395), the float's own decimal, where
        // 123456789/7 is one
        let near = 60_909_089_260.0 / 67.0 + 5e-5;
        assert_eq!(rationalize(near).map(Num::to_f64), Some(near));
        assert_eq!(rationalize(123_456_789.0 / 7.0), Num::ratio(123_456_789, 7));
        // within a loose tolerance of 1/3, yet only as close as a convergent of
        // denominator 3 is by chance (2e-5 against 1/9): no fraction
        assert_eq!(fraction(1.0 / 3.0 + 2e-5, 1e-4), None);
        assert_eq!(fraction(1.0 / 3.0 + 2e-6, 1e-4), Num::ratio(1, 3));
        assert_eq!(
            Num::parse_decimal("1000000000000.0"),
            Num::ratio(1_000_000_000_000, 1)
        );
        assert_eq!(Num::parse_decimal("0.0007"), Num::ratio(7, 10_000));
        // past 1e12 no fraction is sought: the float itself is a short decimal there (its
        // step is 2^-11), kept exactly rather than taken for the nearby 9000000000001/3
        assert_eq!(
            rationalize(3e12 + 1.0 / 3.0),
            Num::ratio(6_000_000_000_000_667, 2000)
        );
        assert_eq!(rationalize(3e12 + 0.5), Num::ratio(6_000_000_000_001, 2));
    }

    #[test]
    fn constants_are_exact_fractions_or_floats() {
        // 1/9.81 is past the short fractions but exact with its denominator.
        assert_eq!(constant(1.0 / 9.81), Num::ratio(100, 981).unwrap());
        assert_eq!(constant(-2.0 / 4.905), Num::ratio(-400, 981).unwrap());
        assert_eq!(constant(0.5), Num::ratio(1, 2).unwrap());
        // Irrational: the float itself.
        let t = -(std::f64::consts::PI / 6.0).tan();
        assert!(matches!(constant(t), Num::Float(x) if x == t));
        assert!(matches!(constant(std::f64::consts::PI), Num::Float(_)));
        assert!(matches!(constant(2f64.sqrt()), Num::Float(_)));
    }

    fn plain(arena: &mut Arena, name: &str) -> Atom {
        Atom {
            id: arena.var(name),
            paired_cosine: false,
            trig: false,
        }
    }

    #[test]
    fn monomials_keep_a_paired_cosine_to_the_first_power() {
        let mut a = Arena::new();
        let s = plain(&mut a, "s");
        let c = Atom {
            id: a.var("c"),
            paired_cosine: true,
            trig: true,
        };
        // 1, s, c, s^2, s c (not c^2).
        assert_eq!(monomials(&[s, c], 2).len(), 5);
        // Two plain atoms: 1, x, y, x^2, x y, y^2.
        let t = plain(&mut a, "t");
        assert_eq!(monomials(&[s, t], 2).len(), 6);
    }

    #[test]
    fn fits_products_of_lengths() {
        let mut a = Arena::new();
        let atoms = [plain(&mut a, "L1"), plain(&mut a, "L2")];
        let points: Vec<Vec<f64>> = (0..12)
            .map(|i| vec![0.1 + 0.07 * i as f64, 0.9 - 0.05 * (i * i % 7) as f64])
            .collect();
        let values: Vec<f64> = points
            .iter()
            .map(|s| 2.0 * s[0] * s[1] - s[1] * s[1] + 0.5)
            .collect();
        let geometry: Vec<_> = points
            .iter()
            .map(|p| a.values(&[("L1", p[0]), ("L2", p[1])]))
            .collect();
        let samples = Samples {
            atoms: &points,
            values: &values,
            geometry: &geometry,
        };
        // Degree one cannot reproduce it; degree two does, exactly, from as few samples as
        // it has monomials (six), not from fewer.
        assert_eq!(fit_polynomial(&mut a, &atoms, 1, &samples, 9), None);
        let e = fit_polynomial(&mut a, &atoms, 2, &samples, 9).unwrap();
        let expected = a.parse("2*L1*L2 - L2^2 + 0.5").unwrap();
        assert_eq!(e, expected);
        assert_eq!(
            fit_polynomial(&mut a, &atoms, 2, &samples, 6),
            Some(expected)
        );
        assert_eq!(fit_polynomial(&mut a, &atoms, 2, &samples, 5), None);
    }

    /// Samples of one length `L` and the values of `f` there.
    fn samples_of(a: &mut Arena, lengths: &[f64], f: impl Fn(f64) -> f64) -> SampleSet {
        let points: Vec<Vec<f64>> = lengths.iter().map(|l| vec![*l]).collect();
        let values = lengths.iter().map(|l| f(*l)).collect();
        let geometry = lengths.iter().map(|l| a.values(&[("L", *l)])).collect();
        SampleSet {
            points,
            values,
            geometry,
        }
    }

    struct SampleSet {
        points: Vec<Vec<f64>>,
        values: Vec<f64>,
        geometry: Vec<Values>,
    }

    impl SampleSet {
        fn samples(&self) -> Samples<'_> {
            Samples {
                atoms: &self.points,
                values: &self.values,
                geometry: &self.geometry,
            }
        }
    }

    /// What a fit keeps is judged against the values' size: a genuine small coefficient on
    /// a large monomial stays (1e-6 L^2 with L up to 1e3), the samples the fit did not use
    /// reject an interpolation (L^3 by degree two through three samples), and rounding
    /// noise of values of size 1e3 leaves no extra term.
    #[test]
    fn a_fit_is_judged_against_the_size_of_the_values() {
        let mut a = Arena::new();
        let atoms = [plain(&mut a, "L")];
        let lengths: Vec<f64> = (0..8).map(|i| 100.0 + 125.0 * i as f64).collect();
        let set = samples_of(&mut a, &lengths, |l| 1e-6 * l * l + l);
        let e = fit_polynomial(&mut a, &atoms, 2, &set.samples(), 5).unwrap();
        let at = a.values(&[("L", 333.0)]);
        let got = a.eval(&[e], &at).unwrap()[0];
        assert!(
            (got - (1e-6 * 333.0 * 333.0 + 333.0)).abs() < 1e-9,
            "{}",
            a.display(e)
        );
        let short: Vec<f64> = (0..8).map(|i| 0.2 + 0.1 * i as f64).collect();
        let set = samples_of(&mut a, &short, |l| l * l * l);
        assert_eq!(fit_polynomial(&mut a, &atoms, 2, &set.samples(), 3), None);
        let set = samples_of(&mut a, &short, |l| 1000.0 * l * l - 500.0);
        let e = fit_polynomial(&mut a, &atoms, 2, &set.samples(), 8).unwrap();
        assert_eq!(e, a.parse("1000*L^2 - 500").unwrap(), "{}", a.display(e));
    }

    /// A fit has at most MAX_MONOMIALS monomials: 159 atoms at degree one (160 with the
    /// constant) are fitted, 160 atoms are refused whatever the samples; monomials() stops
    /// growing only past the cap.
    #[test]
    fn the_monomial_cap_is_inclusive() {
        let mut a = Arena::new();
        let names: Vec<String> = (0..160).map(|i| format!("L{i}")).collect();
        let atoms: Vec<Atom> = names.iter().map(|n| plain(&mut a, n)).collect();
        assert_eq!(monomials(&atoms[..159], 1).len(), super::MAX_MONOMIALS);
        assert!(monomials(&atoms[..159], 2).len() > super::MAX_MONOMIALS);
        let mut rng = robid_core::rng::Rng::from_state(3);
        let points: Vec<Vec<f64>> = (0..170)
            .map(|_| (0..160).map(|_| rng.uniform(0.1, 1.0)).collect())
            .collect();
        for count in [159, 160] {
            let values: Vec<f64> = points
                .iter()
                .map(|p| 1.0 + p[..count].iter().sum::<f64>())
                .collect();
            let geometry: Vec<_> = points
                .iter()
                .map(|p| {
                    let pairs: Vec<(&str, f64)> =
                        names.iter().zip(p).map(|(n, v)| (n.as_str(), *v)).collect();
                    a.values(&pairs)
                })
                .collect();
            let samples = Samples {
                atoms: &points,
                values: &values,
                geometry: &geometry,
            };
            let fitted = fit_polynomial(&mut a, &atoms[..count], 1, &samples, 170);
            assert_eq!(fitted.is_some(), count == 159, "{count} atoms");
        }
    }

    #[test]
    fn irrational_coefficients_stay_floats() {
        let mut a = Arena::new();
        let atoms = [plain(&mut a, "L")];
        let k = 3f64.sqrt();
        let points: Vec<Vec<f64>> = (0..6).map(|i| vec![0.2 + 0.13 * i as f64]).collect();
        let values: Vec<f64> = points.iter().map(|p| k * p[0]).collect();
        let geometry: Vec<_> = points.iter().map(|p| a.values(&[("L", p[0])])).collect();
        let samples = Samples {
            atoms: &points,
            values: &values,
            geometry: &geometry,
        };
        let e = fit_polynomial(&mut a, &atoms, 1, &samples, 4).unwrap();
        let at = a.values(&[("L", 0.7)]);
        let got = a.eval(&[e], &at).unwrap()[0];
        assert!((got - k * 0.7).abs() < 1e-14, "{}", a.display(e));
    }
}
