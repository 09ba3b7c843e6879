//! Numbers in messages.

use core::fmt;

/// A number for a message (`{}` of `Num(x)`): the shortest text that reads back as `x`,
/// plain while that is short (1e-4 <= |x| < 1e6: `0.5`, `100`, `0.001`; below 1e15 while
/// scientific notation would not save 3 characters: `1234567`, `1200000`), else in
/// scientific notation (`2e14`, `1e308`, `-2.5e-320`); at most 24 characters. Every message that
/// shows a value from the input writes it so: `{}` of an f64 writes every digit, 309 of
/// them for 1e308 and 320 for 1e-320, which buries the message. It allocates nothing, so
/// the `no_std` parts use it too; [`num`](crate::num) gives it as a `String`.
///
/// ```
/// use robid_runtime::Num;
/// assert_eq!(format!("{}", Num(100.0)), "100");
/// assert_eq!(format!("{}", Num(1e-3)), "0.001");
/// assert_eq!(format!("{}", Num(1e30)), "1e30");
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Num(pub f64);

impl fmt::Display for Num {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let x = self.0;
        // a negative zero reads as zero ("previous -0" for a time stamp of -0.0)
        if x == 0.0 {
            return f.write_str("0");
        }
        if (x.abs() >= 1e-4 && x.abs() < 1e6) || !x.is_finite() {
            return write!(f, "{x}");
        }
        if (1e6..1e15).contains(&x.abs()) {
            // a large round number is shorter in scientific notation (a sample rate of
            // 200000000000000 Hz reads as 2e14 Hz); one with many digits is not
            let (mut plain, mut exp) = (Text::default(), Text::default());
            let written = fmt::Write::write_fmt(&mut plain, format_args!("{x}"))
                .and_then(|()| fmt::Write::write_fmt(&mut exp, format_args!("{x:e}")));
            if written.is_err() || plain.len < exp.len + 3 {
                return write!(f, "{x}");
            }
        }
        write!(f, "{x:e}")
    }
}

impl Num {
    /// A computed value for a message: `x` rounded to `digits` significant digits (1 to
    /// 17), written as [`Num`] writes it. A result carries every digit of its arithmetic
    /// (a span of 0.32323208000000037 K, a mass of -4.7123414472056454e-11 kg), which
    /// says nothing more than `0.323` or `-4.71e-11` does. Zero and non-finite values are
    /// kept as they are.
    ///
    /// ```
    /// use robid_runtime::Num;
    /// assert_eq!(Num::rounded(0.32323208000000037, 3).to_string(), "0.323");
    /// assert_eq!(Num::rounded(-4.7123414472056454e-11, 3).to_string(), "-4.71e-11");
    /// assert_eq!(Num::rounded(2.5, 6).to_string(), "2.5");
    /// ```
    pub fn rounded(x: f64, digits: usize) -> Num {
        if x == 0.0 || !x.is_finite() {
            return Num(x);
        }
        // `{:.*e}` rounds the exact decimal expansion; parsing gives the double nearest
        // the rounded decimal, which `Num` writes as that decimal
        let mut text = Text::default();
        let digits = digits.clamp(1, 17);
        if fmt::Write::write_fmt(&mut text, format_args!("{:.*e}", digits - 1, x)).is_err() {
            return Num(x);
        }
        match text.as_str().parse::<f64>() {
            // -1.8e308, rounded from -f64::MAX, is beyond every double
            Ok(r) if r.is_finite() => Num(r),
            _ => Num(x),
        }
    }

    /// [`Num::rounded`] to `digits` significant digits, or to the fewest more that still
    /// pass `keep`: a value shown next to a bound it is compared with must not round onto
    /// it (a span of 0.99996 K "less than 1 K" is written 0.99996, not 1). `x` itself when
    /// no rounding passes.
    ///
    /// ```
    /// use robid_runtime::Num;
    /// assert_eq!(Num::rounded_keeping(0.323232, 3, |s| s < 1.0).to_string(), "0.323");
    /// assert_eq!(Num::rounded_keeping(0.99996, 3, |s| s < 1.0).to_string(), "0.99996");
    /// ```
    pub fn rounded_keeping(x: f64, digits: usize, keep: impl Fn(f64) -> bool) -> Num {
        (digits.clamp(1, 17)..=17)
            .map(|d| Num::rounded(x, d))
            .find(|r| keep(r.0))
            .unwrap_or(Num(x))
    }
}

/// A count and what it counts, for a message (`{}` of `Count(n, "joint")`): `1 joint`,
/// `0 joints`, `6 joints`; a noun ending in a consonant and `y` takes `ies` (`1 entry`,
/// `2 entries`). Every message that counts joints, values, rows or tables writes the count
/// so: `"{n} joints"` said "1 joints" of a one-joint robot. The noun may be several words,
/// the last one counted (`Count(1, "[[joint]] table")`).
///
/// ```
/// use robid_runtime::Count;
/// assert_eq!(Count(1, "joint").to_string(), "1 joint");
/// assert_eq!(Count(2, "value").to_string(), "2 values");
/// assert_eq!(Count(3, "entry").to_string(), "3 entries");
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Count(pub usize, pub &'static str);

impl fmt::Display for Count {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let Count(n, noun) = *self;
        if n == 1 {
            return write!(f, "{n} {noun}");
        }
        let bytes = noun.as_bytes();
        match bytes {
            [.., c, b'y'] if !b"aeiou".contains(c) => {
                write!(f, "{n} {}ies", &noun[..noun.len() - 1])
            }
            _ => write!(f, "{n} {noun}s"),
        }
    }
}

/// The values of one flag or list for `n` joints, for a message (`{}` of
/// `Series("s", n)`), as they are typed: `s1` for one joint, `s1,s2` and `s1,s2,s3` for two
/// and three, `s1,..,s6` for more. `"s1,..,s{n}"` told a one-joint robot to "give
/// s1,..,s1".
///
/// ```
/// use robid_runtime::Series;
/// assert_eq!(Series("s", 1).to_string(), "s1");
/// assert_eq!(Series("q", 2).to_string(), "q1,q2");
/// assert_eq!(Series("k", 6).to_string(), "k1,..,k6");
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Series(pub &'static str, pub usize);

impl fmt::Display for Series {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let Series(letter, n) = *self;
        match n {
            0 => f.write_str("nothing"),
            1..=3 => {
                for i in 1..=n {
                    let comma = if i > 1 { "," } else { "" };
                    write!(f, "{comma}{letter}{i}")?;
                }
                Ok(())
            }
            _ => write!(f, "{letter}1,..,{letter}{n}"),
        }
    }
}

/// Room for one number in exponent form (a sign, 17 digits, the point and `e-308`),
/// without allocating.
#[derive(Default)]
struct Text {
    bytes: [u8; 32],
    len: usize,
}

impl Text {
    fn as_str(&self) -> &str {
        core::str::from_utf8(&self.bytes[..self.len]).unwrap_or("")
    }
}

impl fmt::Write for Text {
    fn write_str(&mut self, s: &str) -> fmt::Result {
        let end = self.len + s.len();
        self.bytes
            .get_mut(self.len..end)
            .ok_or(fmt::Error)?
            .copy_from_slice(s.as_bytes());
        self.len = end;
        Ok(())
    }
}

#[cfg(all(test, feature = "std"))]
mod tests {
    use super::*;

    #[test]
    fn rounded_keeps_the_digits_asked_for() {
        let is = |x: f64, d: usize, want: &str| {
            assert_eq!(Num::rounded(x, d).to_string(), want, "{x:e} to {d}");
        };
        is(0.32323208000000037, 3, "0.323");
        is(-4.7123414472056454e-11, 3, "-4.71e-11");
        is(-0.00014373054988615016, 7, "-0.0001437305");
        is(0.1002665123456789, 7, "0.1002665");
        is(1234567.0, 2, "1200000");
        // large round numbers in scientific notation (a sample rate of 200000000000000 Hz)
        is(2e14, 3, "2e14");
        is(1e6, 3, "1e6");
        is(1.5e7, 3, "1.5e7");
        is(123456789.0, 17, "123456789");
        is(-1234567.5, 17, "-1234567.5");
        is(9.9996, 3, "10");
        is(5e-324, 3, "5e-324");
        is(2.5, 17, "2.5");
        is(0.1 + 0.2, 17, "0.30000000000000004");
        is(0.1 + 0.2, 40, "0.30000000000000004");
        is(0.123, 0, "0.1");
        is(0.0, 3, "0");
        // a negative zero reads as zero (a time stamp "previous -0")
        is(-0.0, 3, "0");
        assert_eq!(Num(-0.0).to_string(), "0");
        is(f64::NAN, 3, "NaN");
        is(f64::NEG_INFINITY, 3, "-inf");
        // rounding up beyond the largest double keeps the value
        is(-f64::MAX, 3, "-1.7976931348623157e308");
        // the rounding never reaches the bound it is compared with
        assert_eq!(Num::rounded_keeping(0.99996, 3, |s| s < 1.0).0, 0.99996);
        assert_eq!(
            Num::rounded_keeping(10.0000001, 2, |v| v > 10.0).0,
            10.0000001
        );
        assert_eq!(Num::rounded_keeping(0.323232, 3, |s| s < 1.0).0, 0.323);
    }

    #[test]
    fn counts_and_series_are_written_for_one_joint_too() {
        let count = |n: usize, noun: &'static str| Count(n, noun).to_string();
        assert_eq!(count(1, "joint"), "1 joint");
        assert_eq!(count(0, "joint"), "0 joints");
        assert_eq!(count(7, "[[joint]] table"), "7 [[joint]] tables");
        assert_eq!(count(1, "entry"), "1 entry");
        assert_eq!(count(2, "entry"), "2 entries");
        assert_eq!(count(2, "key"), "2 keys");
        let series = |letter: &'static str, n: usize| Series(letter, n).to_string();
        assert_eq!(series("s", 1), "s1");
        assert_eq!(series("s", 2), "s1,s2");
        assert_eq!(series("s", 3), "s1,s2,s3");
        assert_eq!(series("q", 4), "q1,..,q4");
        assert_eq!(series("q", 0), "nothing");
    }
}
