//! Exact numbers: rationals while they fit, floats after that.

use std::cmp::Ordering;
use std::fmt;
use std::hash::{Hash, Hasher};

/// A numeric constant of an expression.
///
/// Rationals keep DH geometry exact (0.425 is 17/40, so `d^2 C^2 + d^2 S^2`
/// cancels exactly); an operation whose result does not fit in `i128` falls
/// back to a float, which is still correct to rounding.
#[derive(Clone, Copy, Debug)]
pub enum Num {
    /// `numerator / denominator`, reduced, denominator > 0.
    Rational(i128, i128),
    /// A float that is not known exactly (never NaN).
    Float(f64),
}

/// Greatest common divisor of the magnitudes (`i128::MIN` included).
fn gcd(a: i128, b: i128) -> u128 {
    let (mut a, mut b) = (a.unsigned_abs(), b.unsigned_abs());
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a
}

/// `n / d` rounded once, through its decimal form, when `d` (> 0) is 2^a 5^b: the
/// standard library's parsing rounds a decimal to the nearest float.
fn decimal_to_f64(n: i128, d: i128) -> Option<f64> {
    let (mut rest, mut twos, mut fives) = (d, 0u32, 0u32);
    while rest % 2 == 0 {
        rest /= 2;
        twos += 1;
    }
    while rest % 5 == 0 {
        rest /= 5;
        fives += 1;
    }
    if rest != 1 {
        return None;
    }
    let k = twos.max(fives);
    let factor = 2_i128
        .checked_pow(k - twos)?
        .checked_mul(5_i128.checked_pow(k - fives)?)?;
    format!("{}e-{k}", n.checked_mul(factor)?).parse().ok()
}

impl Num {
    /// Zero.
    pub const ZERO: Num = Num::Rational(0, 1);
    /// One.
    pub const ONE: Num = Num::Rational(1, 1);
    /// Minus one.
    pub const MINUS_ONE: Num = Num::Rational(-1, 1);

    /// The integer `n`.
    pub fn int(n: i64) -> Num {
        Num::Rational(n as i128, 1)
    }

    /// `numerator / denominator` reduced, or `None` when the denominator is 0
    /// or the reduced form does not fit in `i128`.
    pub fn ratio(numerator: i128, denominator: i128) -> Option<Num> {
        if denominator == 0 {
            return None;
        }
        // A gcd of 2^127 (both are i128::MIN) does not fit in i128 but divides both.
        let g = gcd(numerator, denominator).max(1);
        let reduce = |v: i128| match i128::try_from(g) {
            Ok(g) => Some(v / g),
            Err(_) => Some(if v < 0 { -1 } else { 1 }),
        };
        let (n, d) = (reduce(numerator)?, reduce(denominator)?);
        if d < 0 {
            Some(Num::Rational(n.checked_neg()?, d.checked_neg()?))
        } else {
            Some(Num::Rational(n, d))
        }
    }

    /// The exact value of a finite float whose shortest decimal form is short
    /// (0.425 -> 17/40), else the float itself. `None` for NaN or infinity.
    pub fn from_f64(value: f64) -> Option<Num> {
        if !value.is_finite() {
            return None;
        }
        if value == value.trunc() && value.abs() < 1e30 {
            return Some(Num::Rational(value as i128, 1));
        }
        Some(Self::parse_decimal(&format!("{value:e}")).unwrap_or(Num::Float(value)))
    }

    /// Parses a decimal literal such as `-0.3922`, `12`, `1.5e-3` exactly.
    pub fn parse_decimal(text: &str) -> Option<Num> {
        let (mantissa, exponent) = match text.find(['e', 'E']) {
            Some(i) => (&text[..i], text[i + 1..].parse::<i32>().ok()?),
            None => (text, 0),
        };
        let (negative, digits) = match mantissa.strip_prefix('-') {
            Some(rest) => (true, rest),
            None => (false, mantissa.strip_prefix('+').unwrap_or(mantissa)),
        };
        let (int_part, frac_part) = digits.split_once('.').unwrap_or((digits, ""));
        if int_part.is_empty() && frac_part.is_empty() {
            return None;
        }
        if !int_part
            .chars()
            .chain(frac_part.chars())
            .all(|c| c.is_ascii_digit())
        {
            return None;
        }
        let all: String = format!("{int_part}{frac_part}");
        let mut numerator: i128 = all.parse().ok()?;
        if negative {
            numerator = -numerator;
        }
        let scale = exponent.checked_sub(i32::try_from(frac_part.len()).ok()?)?;
        let ten_pow = |k: u32| 10_i128.checked_pow(k);
        if scale >= 0 {
            Num::ratio(numerator.checked_mul(ten_pow(scale.unsigned_abs())?)?, 1)
        } else {
            Num::ratio(numerator, ten_pow(scale.unsigned_abs())?)
        }
    }

    /// The value as a float: the nearest one when the numerator and denominator are
    /// exact floats (at most 2^53) or the number is a decimal (a denominator 2^a 5^b: a
    /// float's own 17 digits, `1.5707995267948966`, whose numerator is not exact and
    /// whose quotient rounded twice was one ulp off, so `from_f64(x).to_f64()` is `x`),
    /// else within an ulp or two of it.
    pub fn to_f64(self) -> f64 {
        match self {
            Num::Rational(n, d) => {
                const EXACT: u128 = 1 << 53;
                if n.unsigned_abs() <= EXACT && d.unsigned_abs() <= EXACT {
                    n as f64 / d as f64
                } else {
                    decimal_to_f64(n, d).unwrap_or(n as f64 / d as f64)
                }
            }
            Num::Float(x) => x,
        }
    }

    /// True when exactly zero.
    pub fn is_zero(self) -> bool {
        matches!(self, Num::Rational(0, _)) || matches!(self, Num::Float(x) if x == 0.0)
    }

    /// True when exactly one.
    pub fn is_one(self) -> bool {
        matches!(self, Num::Rational(1, 1)) || matches!(self, Num::Float(x) if x == 1.0)
    }

    /// True when negative (a rational by its numerator: the denominator is positive).
    pub fn is_negative(self) -> bool {
        match self {
            Num::Rational(n, _) => n < 0,
            Num::Float(x) => x < 0.0,
        }
    }

    /// The integer value, when it is one.
    pub fn as_integer(self) -> Option<i128> {
        match self {
            Num::Rational(n, 1) => Some(n),
            _ => None,
        }
    }

    fn float(x: f64) -> Num {
        if x == x.trunc() && x.abs() < 1e15 {
            Num::Rational(x as i128, 1)
        } else {
            Num::Float(x)
        }
    }

    fn sum(self, other: Num) -> Num {
        if let (Num::Rational(a, b), Num::Rational(c, d)) = (self, other) {
            let exact = a
                .checked_mul(d)
                .zip(c.checked_mul(b))
                .and_then(|(x, y)| x.checked_add(y))
                .zip(b.checked_mul(d))
                .and_then(|(n, m)| Num::ratio(n, m));
            if let Some(sum) = exact {
                return sum;
            }
        }
        Num::float(self.to_f64() + other.to_f64())
    }

    fn product(self, other: Num) -> Num {
        if let (Num::Rational(a, b), Num::Rational(c, d)) = (self, other) {
            // Cross-reduce first so products stay small.
            let g1 = i128::try_from(gcd(a, d).max(1)).ok();
            let g2 = i128::try_from(gcd(c, b).max(1)).ok();
            let exact = g1.zip(g2).and_then(|(g1, g2)| {
                let (n, m) = ((a / g1).checked_mul(c / g2)?, (b / g2).checked_mul(d / g1)?);
                Num::ratio(n, m)
            });
            if let Some(product) = exact {
                return product;
            }
        }
        Num::float(self.to_f64() * other.to_f64())
    }

    fn negated(self) -> Num {
        match self {
            Num::Rational(n, d) => match n.checked_neg() {
                Some(n) => Num::Rational(n, d),
                None => Num::Float(-self.to_f64()),
            },
            Num::Float(x) => Num::Float(-x),
        }
    }

    /// Reciprocal, `None` for zero.
    pub fn recip(self) -> Option<Num> {
        match self {
            Num::Rational(n, d) => Num::ratio(d, n),
            Num::Float(x) if x != 0.0 => Some(Num::Float(1.0 / x)),
            Num::Float(_) => None,
        }
    }

    /// Integer power, `None` for 0 to a negative power.
    pub fn powi(self, exponent: i32) -> Option<Num> {
        let mut base = if exponent < 0 { self.recip()? } else { self };
        let mut k = exponent.unsigned_abs();
        let mut result = Num::ONE;
        if k <= SMALL_POWER {
            // One multiplication at a time, as the values have always been rounded.
            for _ in 0..k {
                result = result * base;
            }
            return Some(result);
        }
        // By squaring: any exponent in 32 steps.
        while k > 0 {
            if k & 1 == 1 {
                result = result * base;
            }
            base = base * base;
            k >>= 1;
        }
        Some(result)
    }
}

/// Powers up to this exponent are multiplied out one factor at a time.
const SMALL_POWER: u32 = 64;

impl std::ops::Add for Num {
    type Output = Num;
    fn add(self, other: Num) -> Num {
        self.sum(other)
    }
}

impl std::ops::Mul for Num {
    type Output = Num;
    fn mul(self, other: Num) -> Num {
        self.product(other)
    }
}

impl std::ops::Neg for Num {
    type Output = Num;
    fn neg(self) -> Num {
        self.negated()
    }
}

impl PartialEq for Num {
    fn eq(&self, other: &Num) -> bool {
        match (self, other) {
            (Num::Rational(a, b), Num::Rational(c, d)) => a == c && b == d,
            (Num::Float(x), Num::Float(y)) => x.to_bits() == y.to_bits(),
            _ => false,
        }
    }
}

impl Eq for Num {}

impl Hash for Num {
    fn hash<H: Hasher>(&self, state: &mut H) {
        match self {
            Num::Rational(n, d) => (0u8, n, d).hash(state),
            Num::Float(x) => (1u8, x.to_bits()).hash(state),
        }
    }
}

impl PartialOrd for Num {
    fn partial_cmp(&self, other: &Num) -> Option<Ordering> {
        self.to_f64().partial_cmp(&other.to_f64())
    }
}

/// The largest denominator written as a fraction (`1/3`, `51/280`): regrouping's exact
/// coefficients have at most 10,000 (`regroup/exact.rs`), and products of two of them
/// stay readable. A number with a larger one that is no short decimal is written as the
/// shortest decimal of its float (docs/regrouping.md).
const LONG_DENOMINATOR: i128 = 1_000_000;

/// Written re-readably: an integer, a decimal that reads back as the same number, a short
/// fraction, or for a longer fraction the shortest decimal of its float (which reads back
/// as that float, not as the same fraction); a float as the shortest decimal.
impl fmt::Display for Num {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Num::Rational(n, 1) => write!(f, "{n}"),
            Num::Rational(n, d) => {
                let x = self.to_f64();
                // Decimal form when the number is the shortest decimal of a float (a DH
                // length, 0.425 = 17/40): it reads back as this number exactly. With more
                // than 53 bits in n or d and a denominator that is not 2^a 5^b, n/d in
                // floats can be an ulp or two from that float, so its neighbours are
                // tried too.
                let step = |x: f64, k: i64| f64::from_bits(x.to_bits().wrapping_add_signed(k));
                if let Some(exact) = [0, 1, -1, 2, -2]
                    .map(|k| step(x, k))
                    .into_iter()
                    .find(|&c| c.is_finite() && Num::from_f64(c) == Some(*self))
                {
                    write!(f, "{exact}")
                } else if d > LONG_DENOMINATOR {
                    // a product of long decimals (2030920000000007937933343401/
                    // 40000000000000000000000000000): the shortest decimal of its float,
                    // which is what every computation uses
                    write!(f, "{x:?}")
                } else {
                    write!(f, "{n}/{d}")
                }
            }
            Num::Float(x) => write!(f, "{x:?}"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Num;

    #[test]
    fn decimals_are_exact() {
        assert_eq!(Num::from_f64(0.425), Num::ratio(17, 40));
        assert_eq!(Num::parse_decimal("-0.3922"), Num::ratio(-3922, 10000));
        assert_eq!(Num::parse_decimal("1.5e-3"), Num::ratio(3, 2000));
        assert_eq!(Num::from_f64(f64::NAN), None);
    }

    /// A float read exactly gives back itself: its 17-digit decimal's numerator is not
    /// an exact float, and dividing the two rounded twice (one ulp off for
    /// 1.5707995267948966).
    #[test]
    fn floats_read_exactly_convert_back_to_themselves() {
        let mut x: u64 = 0x9e37_79b9_7f4a_7c15;
        let mut checked = 0;
        for _ in 0..200_000 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let v = f64::from_bits(x);
            if !v.is_finite() || v.abs() > 1e30 || v.abs() < 1e-30 {
                continue;
            }
            let back = Num::from_f64(v).unwrap().to_f64();
            assert_eq!(back.to_bits(), v.to_bits(), "{v:e}");
            checked += 1;
        }
        assert!(checked > 10_000, "{checked}");
        for v in [
            1.5707995267948966,
            0.36870638165021724,
            -0.1333,
            1e-7,
            123456.789,
        ] {
            assert_eq!(Num::from_f64(v).unwrap().to_f64(), v);
        }
        // a rational that is not a decimal stays within an ulp
        let third = Num::ratio(1, 3).unwrap().to_f64();
        assert_eq!(third, 1.0 / 3.0);
    }

    #[test]
    fn arithmetic_stays_exact() {
        let a = Num::from_f64(0.1).unwrap();
        let b = Num::from_f64(0.2).unwrap();
        assert_eq!(a + b, Num::from_f64(0.3).unwrap());
        assert_eq!(a * b, Num::ratio(1, 50).unwrap());
        assert_eq!(Num::int(2).powi(-2), Num::ratio(1, 4));
    }

    #[test]
    fn extreme_rationals_do_not_overflow() {
        let min = Num::Rational(i128::MIN, 1);
        assert_eq!((-min).to_f64(), -(i128::MIN as f64));
        assert!(Num::ratio(i128::MIN, -1).is_none());
        assert_eq!(Num::ratio(i128::MIN, i128::MIN), Some(Num::ONE));
        assert_eq!(
            Num::ratio(i128::MIN, 2),
            Some(Num::Rational(i128::MIN / 2, 1))
        );
        let product = Num::Rational(-(1 << 63), 1) * Num::Rational(1 << 64, 1);
        assert_eq!(product.to_f64(), -(2f64.powi(127)));
        assert_eq!(Num::parse_decimal("1.5e-2147483648"), None);
        assert_eq!(Num::parse_decimal("1e-2147483648"), None);
        assert_eq!(Num::parse_decimal("1e2147483647"), None);
    }

    #[test]
    fn large_powers_are_fast_and_overflow_to_infinity() {
        assert_eq!(Num::int(2).powi(100).map(Num::to_f64), Some(2f64.powi(100)));
        assert_eq!(Num::int(2).powi(200).map(Num::to_f64), Some(2f64.powi(200)));
        assert_eq!(Num::int(3).powi(4), Num::ratio(81, 1));
        let huge = Num::int(2).powi(i32::MAX).unwrap();
        assert_eq!(huge.to_f64(), f64::INFINITY);
        let tiny = Num::int(2).powi(i32::MIN).unwrap();
        assert_eq!(tiny.to_f64(), 0.0);
    }

    #[test]
    fn overflow_falls_back_to_float() {
        let big = Num::Rational(i128::MAX / 3, 1);
        let product = big * big;
        assert!(matches!(product, Num::Float(_)));
        assert!((product.to_f64() / (big.to_f64() * big.to_f64()) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn display_prefers_decimals() {
        assert_eq!(Num::from_f64(0.425).unwrap().to_string(), "0.425");
        assert_eq!(Num::ratio(1, 3).unwrap().to_string(), "1/3");
    }

    /// A long fraction (the square of a URDF's fitted length 0.225328648866495, times 1)
    /// is written as the shortest decimal of its float, not with 29 digits; short
    /// fractions stay fractions; nothing changes its value.
    #[test]
    fn long_fractions_are_written_as_the_decimal_of_their_float() {
        let a = Num::from_f64(0.225328648866495).unwrap();
        let square = a * a;
        assert_eq!(
            square,
            Num::Rational(2030920000000007937933343401, 40000000000000000000000000000)
        );
        // the float nearest 0.0507730000000001984483335850...: rounded once (the
        // numerator and denominator each rounded first gave 0.05077300000000021)
        assert_eq!(square.to_string(), "0.0507730000000002");
        let text: f64 = square.to_string().parse().unwrap();
        assert_eq!(text, square.to_f64());
        assert_eq!((-square).to_string(), "-0.0507730000000002");
        assert_eq!(
            Num::ratio(7624390023667207, 6250000000000000000)
                .unwrap()
                .to_string(),
            "0.001219902403786753"
        );
        for (n, d, text) in [
            (1, 3, "1/3"),
            (51, 280, "51/280"),
            (-100, 981, "-100/981"),
            (1, 999_983, "1/999983"),
        ] {
            assert_eq!(Num::ratio(n, d).unwrap().to_string(), text);
        }
        // a number read from a decimal is written as that decimal, which reads back as
        // the same number, also when n/d in floats is an ulp from its float
        let mut rng = robid_core::rng::Rng::new(7);
        for _ in 0..20_000 {
            let x = (rng.unit() - 0.5) * 10f64.powi(rng.below(12) as i32 - 6);
            let exact = Num::from_f64(x).unwrap();
            assert!(matches!(exact, Num::Rational(..)), "{x:e}");
            assert_eq!(Num::parse_decimal(&exact.to_string()), Some(exact), "{x:e}");
        }
        assert_eq!(
            Num::from_f64(0.36870638165021724).unwrap().to_string(),
            "0.36870638165021724"
        );
    }
}
