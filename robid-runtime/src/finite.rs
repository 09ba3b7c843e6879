//! Finiteness checks of long slices (regressor rows, prepared signals), written so that
//! the compiler vectorises the common case, every value finite.

/// Whether a value of `x` is infinite or NaN: one pass without an early exit of a
/// comparison per value (`!(|v| <= f64::MAX)`, true for NaN), which the compiler
/// vectorises into one compare and one OR per vector of values even without AVX
/// (`cmpnlepd`). The mask of the exponent's bits compared as 64-bit integers, its
/// predecessor, took three more instructions per vector there (SSE2 compares 32-bit
/// integers only): the check of every regressor row was 3.4 % of the hour's
/// identification.
pub(crate) fn any_non_finite(x: &[f64]) -> bool {
    x.iter().fold(false, |any, v| any | !(v.abs() <= f64::MAX))
}

/// The first non-finite value of `x` with its index. The common case, every value
/// finite, is one vectorised pass ([`any_non_finite`]); a search with an early exit
/// (one compare and branch per value) was 2.2 % of the hour's identification as the
/// check of its prepared signals.
pub(crate) fn first_non_finite(x: &[f64]) -> Option<(usize, f64)> {
    if !any_non_finite(x) {
        return None;
    }
    x.iter().position(|v| !v.is_finite()).map(|c| (c, x[c]))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_first_non_finite_value_is_found_wherever_it_is() {
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            for n in [1, 3, 8, 17, 64] {
                for at in 0..n {
                    let mut x: Vec<f64> = (0..n).map(|i| i as f64 - 2.5).collect();
                    x[n - 1] = f64::MAX;
                    x[at] = bad;
                    assert!(any_non_finite(&x));
                    let (i, v) = first_non_finite(&x).unwrap();
                    assert_eq!(i, at);
                    assert_eq!(v.to_bits(), bad.to_bits());
                }
            }
        }
        // two and three of them: the first is found whatever the others are
        for n in [2, 3, 9, 33] {
            for count in [2, 3] {
                let mut x = vec![1.5; n];
                for i in 0..count.min(n) {
                    x[n - 1 - i * (n - 1) / count] = f64::NAN;
                }
                let first = x.iter().position(|v| v.is_nan()).unwrap();
                assert_eq!(first_non_finite(&x).map(|(i, _)| i), Some(first), "{x:?}");
            }
        }
        assert_eq!(first_non_finite(&[0.0, -f64::MAX, f64::MIN_POSITIVE]), None);
        assert!(!any_non_finite(&[]));
    }
}
