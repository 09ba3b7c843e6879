//! Turning numeric dependency coefficients into exact ones: a rational number,
//! or, when lengths are symbols, a polynomial of degree two at most in them
//! (products of geometric values), fitted over several geometry samples and
//! checked on one more.

use crate::expr::{Arena, Id, Num};

/// The exact number closest to `x` among short decimals and small fractions,
/// when one is within rounding of it.
pub(crate) fn rationalize(x: f64) -> Option<Num> {
    // Small fractions first (1/3 must not become 0.333333333), then short decimals.
    let tolerance = 1e-10 * x.abs().max(1.0);
    for denominator in 1..=720_i128 {
        let numerator = (x * denominator as f64).round();
        if (numerator / denominator as f64 - x).abs() <= tolerance {
            return Num::ratio(numerator as i128, denominator);
        }
    }
    for digits in 1..=10 {
        let scale = 10f64.powi(digits);
        let r = (x * scale).round() / scale;
        // Far closer than the decimal's own step: pi is not 3.1415926536.
        if (r - x).abs() <= tolerance.min(1e-3 / scale) {
            return Num::parse_decimal(&format!("{r:.*}", digits as usize));
        }
    }
    None
}

/// Monomials of degree <= 2 in `symbols`, as exponent lists.
pub(crate) fn monomials(symbols: usize) -> Vec<Vec<usize>> {
    let mut out = vec![vec![]];
    for i in 0..symbols {
        out.push(vec![i]);
    }
    for i in 0..symbols {
        for k in i..symbols {
            out.push(vec![i, k]);
        }
    }
    out
}

/// Fits `values[s] = sum_m c_m monomial_m(samples[s])` exactly; `None` when the
/// fit leaves a residual or a coefficient is not a short exact number.
pub(crate) fn fit_polynomial(
    arena: &mut Arena,
    symbols: &[Id],
    samples: &[Vec<f64>],
    values: &[f64],
) -> Option<Id> {
    let basis = monomials(symbols.len());
    let rows = samples.len();
    let a = nalgebra::DMatrix::from_fn(rows, basis.len(), |r, m| {
        basis[m].iter().map(|&i| samples[r][i]).product::<f64>()
    });
    let b = nalgebra::DVector::from_column_slice(values);
    let x = super::rank::svd(a.clone())?.solve(&b, 1e-12).ok()?;
    let fitted = &a * &x;
    let scale = values.iter().fold(1.0_f64, |m, v| m.max(v.abs()));
    if (fitted - &b).amax() > 1e-8 * scale {
        return None;
    }
    let mut terms = Vec::new();
    for (m, c) in basis.iter().zip(x.iter()) {
        if c.abs() < 1e-10 {
            continue;
        }
        let c = rationalize(*c)?;
        let mut factors = vec![arena.num(c)];
        factors.extend(m.iter().map(|&i| symbols[i]));
        terms.push(arena.mul(&factors));
    }
    Some(arena.add(&terms))
}

#[cfg(test)]
mod tests {
    use super::{fit_polynomial, rationalize};
    use crate::expr::{Arena, Num};

    #[test]
    fn rationalizes_lengths_and_fractions() {
        assert_eq!(rationalize(0.425 * 0.3922), Num::parse_decimal("0.166685"));
        assert_eq!(rationalize(-1.0 / 3.0), Num::ratio(-1, 3));
        assert_eq!(rationalize(std::f64::consts::PI), None);
    }

    #[test]
    fn fits_products_of_lengths() {
        let mut a = Arena::new();
        let (l1, l2) = (a.var("L1"), a.var("L2"));
        let samples: Vec<Vec<f64>> = (0..12)
            .map(|i| vec![0.1 + 0.07 * i as f64, 0.9 - 0.05 * (i * i % 7) as f64])
            .collect();
        let values: Vec<f64> = samples
            .iter()
            .map(|s| 2.0 * s[0] * s[1] - s[1] * s[1] + 0.5)
            .collect();
        let e = fit_polynomial(&mut a, &[l1, l2], &samples, &values).unwrap();
        let expected = a.parse("2*L1*L2 - L2^2 + 0.5").unwrap();
        assert_eq!(e, expected);
    }
}
