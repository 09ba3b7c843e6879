//! Numbers in messages.

use core::fmt;

/// A number for a message (`{}` of `Num(x)`): the shortest text that reads back as `x`,
/// plain while that is short (1e-4 <= |x| < 1e15: `0.5`, `100`, `0.001`), else in
/// scientific notation (`1e308`, `-2.5e-320`); at most 24 characters. Every message that
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
        if x == 0.0 || (x.abs() >= 1e-4 && x.abs() < 1e15) || !x.is_finite() {
            write!(f, "{x}")
        } else {
            write!(f, "{x:e}")
        }
    }
}
