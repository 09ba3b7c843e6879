//! How a [`SpilledRecord`](super::SpilledRecord) keeps one column of a window in its
//! temporary file: as few bytes as give back every value to the bit.
//!
//! A log's values are decimals written with a fixed number of places (`0.12345`), which
//! the parser turns into the nearest double, `digits / 10^places` correctly rounded. Such
//! a column is kept as its digits, 4 bytes a value instead of 8, and read back by the same
//! division (exact: the digits and the power of ten are exact doubles, so the quotient is
//! the nearest double to the same decimal). Whether a column can be is checked value by
//! value when it is written (the decoded value compared with the value's bits); any
//! other column is kept as its 8 bytes. File lines that follow each other (a log without
//! comments or blank lines) are kept as the first line alone. The temporary file of the
//! hour of issue 19 (15 columns and the lines) is then 60 bytes a sample instead of 128.

/// The powers of ten a column's digits are divided by (exact doubles).
const POWERS: [f64; 10] = [1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9];

/// Values looked at to choose a column's number of places.
const PROBE: usize = 64;

/// Where and how one column of a window is kept.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Stored {
    /// `len` values, 8 bytes each, at byte `at`.
    Raw { at: u64 },
    /// `len` integers, 4 bytes each, at byte `at`: each value is its integer divided by
    /// `10^places` (to the bit).
    Decimal { at: u64, places: u8 },
    /// Lines `first, first + 1, ...` (nothing in the file).
    Consecutive { first: u64 },
}

/// The places of `v` as a decimal of at most 9 places whose digits fit an `i32`: the
/// fewest that give `v` back to the bit.
fn places_of(v: f64) -> Option<usize> {
    POWERS
        .iter()
        .position(|&p| decode(encode(v, p), p).to_bits() == v.to_bits())
}

/// `v`'s digits at the power of ten `p` (saturated to `i32`; exact only when they decode
/// to `v`).
#[inline(always)]
fn encode(v: f64, p: f64) -> i32 {
    // rounded to the nearest integer by adding and taking away 1.5 * 2^52 (exact below
    // 2^51, which is all an i32 holds; no call to `rint`, which x86-64's baseline lacks,
    // so that the loop vectorises)
    const ROUND: f64 = 6_755_399_441_055_744.0;
    ((v * p + ROUND) - ROUND) as i32
}

/// The value of `digits` at the power of ten `p`.
#[inline(always)]
fn decode(digits: i32, p: f64) -> f64 {
    f64::from(digits) / p
}

/// `x` as digits at one number of places, written to `out` (cleared first), and the
/// number of places; `None` when some value is not such a decimal (then `out` holds
/// nothing meaningful).
pub(super) fn digits(x: &[f64], out: &mut Vec<i32>) -> Option<u8> {
    // the most places the first values need: a value written with fewer (a trailing zero
    // dropped) is as exact with more
    let mut places = 0;
    for &v in x.iter().take(PROBE) {
        places = places.max(places_of(v)?);
    }
    let p = POWERS[places];
    out.clear();
    out.resize(x.len(), 0);
    #[cfg(target_arch = "x86_64")]
    if std::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU has AVX2, which `encode_avx2` is compiled for.
        return unsafe { encode_avx2(x, p, out) }.then_some(places as u8);
    }
    encode_all(x, p, out).then_some(places as u8)
}

/// Writes each value's digits at the power of ten `p` to `out`: whether all decode to
/// their value. One pass without an early exit, which the compiler vectorises (the
/// division of the check is most of the work).
#[inline(always)]
fn encode_all(x: &[f64], p: f64, out: &mut [i32]) -> bool {
    let mut exact = true;
    for (d, &v) in out.iter_mut().zip(x) {
        *d = encode(v, p);
        exact &= decode(*d, p).to_bits() == v.to_bits();
    }
    exact
}

/// [`encode_all`] in vectors of four (the same operations: the same digits and answer).
///
/// # Safety
/// The CPU must support AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn encode_avx2(x: &[f64], p: f64, out: &mut [i32]) -> bool {
    encode_all(x, p, out)
}

/// Appends the values of the digits in `bytes` (each an `i32`'s native bytes, as written
/// from `digits`) at `places` to `out`, without first zeroing the space they take.
pub(super) fn values(bytes: &[u8], places: u8, out: &mut Vec<f64>) {
    let p = POWERS[usize::from(places)];
    out.reserve(bytes.len() / 4);
    #[cfg(target_arch = "x86_64")]
    if std::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU has AVX2, which `decode_avx2` is compiled for.
        unsafe { decode_avx2(bytes, p, out) };
        return;
    }
    decode_all(bytes, p, out);
}

/// Appends the value of each digits in `bytes` at the power of ten `p` to `out`.
#[inline(always)]
fn decode_all(bytes: &[u8], p: f64, out: &mut Vec<f64>) {
    out.extend(
        bytes
            .chunks_exact(4)
            .map(|d| decode(i32::from_ne_bytes(d.try_into().expect("four bytes")), p)),
    );
}

/// [`decode_all`] in vectors of four (the same operations: the same values).
///
/// # Safety
/// The CPU must support AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn decode_avx2(bytes: &[u8], p: f64, out: &mut Vec<f64>) {
    decode_all(bytes, p, out);
}

/// The first line when `lines` follow each other.
pub(super) fn consecutive(lines: &[u64]) -> Option<u64> {
    let first = *lines.first()?;
    let mut follow = true;
    for (i, &l) in lines.iter().enumerate() {
        follow &= l == first.wrapping_add(i as u64);
    }
    follow.then_some(first)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;

    fn round_trip(x: &[f64]) -> Option<u8> {
        let mut d = Vec::new();
        let places = digits(x, &mut d)?;
        let mut back = Vec::new();
        values(bytemuck::cast_slice(&d), places, &mut back);
        let bits = |v: &[f64]| v.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&back), bits(x), "values given back to the bit");
        Some(places)
    }

    /// Decimals written with a fixed number of places and parsed come back to the bit, at
    /// the places written; the same values with one more place too.
    #[test]
    fn written_decimals_come_back_to_the_bit() {
        let mut rng = Rng::new(7);
        for places in 0..=9usize {
            let x: Vec<f64> = (0..5000)
                .map(|_| {
                    // digits within an i32 at 9 places
                    let v = (rng.normal() * 0.7).clamp(-2.1, 2.1);
                    let v: f64 = format!("{v:.places$}").parse().unwrap();
                    // "-0.00" is -0, refused below
                    v + 0.0
                })
                .collect();
            assert_eq!(round_trip(&x), Some(places as u8), "{places} places");
        }
        // the largest digits an i32 holds, and values written with fewer places
        let x: Vec<f64> = ["2.147483647", "-2.147483647", "0.5", "-0", "1"]
            .iter()
            .map(|s| s.parse().unwrap())
            .collect();
        assert_eq!(x[3].to_bits(), (-0.0f64).to_bits());
        // -0 has no digits of its own: the column is kept whole
        assert_eq!(round_trip(&x), None);
        assert_eq!(round_trip(&x[..3]), Some(9));
    }

    /// The scalar loops give the same digits, answer and values as the vector ones.
    #[test]
    fn every_instance_agrees() {
        let mut rng = Rng::new(3);
        let mut x: Vec<f64> = (0..1001)
            .map(|_| format!("{:.5}", rng.normal()).parse::<f64>().unwrap() + 0.0)
            .collect();
        for bad in [None, Some(0.1 + 0.2)] {
            if let Some(b) = bad {
                x[999] = b;
            }
            let mut d = Vec::new();
            let places = digits(&x, &mut d);
            let mut scalar = vec![0; x.len()];
            let exact = encode_all(&x, POWERS[5], &mut scalar);
            assert_eq!((exact, places.is_some()), (bad.is_none(), bad.is_none()));
            if let Some(places) = places {
                assert_eq!(scalar, d);
                let (mut a, mut b) = (Vec::new(), Vec::new());
                values(bytemuck::cast_slice(&d), places, &mut a);
                decode_all(bytemuck::cast_slice(&d), POWERS[5], &mut b);
                assert_eq!(a.len(), d.len());
                assert!(a.iter().zip(&b).all(|(a, b)| a.to_bits() == b.to_bits()));
            }
        }
    }

    /// A column that is not such a decimal (more places, digits beyond an i32, a value
    /// computed rather than read, not finite) is refused, even past the values looked at
    /// to choose the places.
    #[test]
    fn other_columns_are_refused() {
        let mut x = vec![0.25; 1000];
        assert_eq!(round_trip(&x), Some(2));
        for bad in [
            0.1 + 0.2,
            2.147483648,
            1e-10,
            f64::NAN,
            f64::INFINITY,
            3.0e9,
        ] {
            x[700] = bad;
            assert_eq!(round_trip(&x), None, "{bad}");
        }
        assert_eq!(consecutive(&[4, 5, 6, 7]), Some(4));
        assert_eq!(consecutive(&[4, 5, 7, 8]), None);
        assert_eq!(consecutive(&[]), None);
    }
}
