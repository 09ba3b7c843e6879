//! Named link variables and equality constraints between them in the form of Gaz et al.'s
//! eq. 15 (`I7xz = c7x c7z m7`): one variable equals a constant times a product of others
//! (docs/experiments.md#two-step-extraction). The search adds each as a penalty row
//! `sqrt(penalty) (left - coefficient * product) / scale`, next to the bound penalties.

use std::fmt;
use std::str::FromStr;

use crate::Num;
use crate::feasible::bounds::{LinkBounds, TENSOR_ELEMENTS};
use crate::limits::MAX_PARAMETER;
use crate::names::short;
use crate::{Error, Result};

use super::parametrise::{PER_LINK, link_of};

/// What a link variable is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Quantity {
    /// The mass `m`, kg.
    Mass,
    /// A coordinate (0 x, 1 y, 2 z) of the centre of mass in the link frame, m.
    Com(usize),
    /// An element of the inertia tensor about the centre of mass in the link frame,
    /// indexed as [`TENSOR_ELEMENTS`], kg m^2.
    Inertia(usize),
}

/// A link variable named as in Gaz et al. 2016: `m3`, `c3x`, `I7xz` (link numbers from 1).
///
/// ```
/// use robid_runtime::feasible::{Quantity, Variable};
/// let v: Variable = "I7xz".parse().unwrap();
/// assert_eq!((v.link, v.quantity), (6, Quantity::Inertia(4)));
/// assert_eq!(v.to_string(), "I7xz");
/// assert!("q7".parse::<Variable>().is_err());
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Variable {
    /// The link, 0-based.
    pub link: usize,
    /// The quantity.
    pub quantity: Quantity,
}

const AXES: [&str; 3] = ["x", "y", "z"];

impl FromStr for Variable {
    type Err = Error;

    fn from_str(s: &str) -> Result<Variable> {
        let bad = || {
            Error::setting(
                "Variable",
                "name",
                format!(
                    "`{}` is not a link variable; write m<link>, c<link>x|y|z or \
                     I<link>xx|yy|zz|xy|xz|yz with links from 1 (e.g. m7, c7z, I7xz)",
                    short(s.trim())
                ),
            )
        };
        let s = s.trim();
        let (head, rest) = s.split_at(s.chars().next().map_or(0, char::len_utf8));
        let digits: String = rest.chars().take_while(char::is_ascii_digit).collect();
        let suffix = &rest[digits.len()..];
        let link: usize = digits.parse().ok().filter(|&j| j >= 1).ok_or_else(bad)?;
        let quantity = match (head, suffix) {
            ("m", "") => Quantity::Mass,
            ("c", a) => Quantity::Com(AXES.iter().position(|x| *x == a).ok_or_else(bad)?),
            ("I", e) => Quantity::Inertia(
                TENSOR_ELEMENTS
                    .iter()
                    .position(|(n, _, _)| *n == e)
                    .ok_or_else(bad)?,
            ),
            _ => return Err(bad()),
        };
        Ok(Variable {
            link: link - 1,
            quantity,
        })
    }
}

impl fmt::Display for Variable {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let j = self.link + 1;
        match self.quantity {
            Quantity::Mass => write!(f, "m{j}"),
            Quantity::Com(a) => write!(f, "c{j}{}", AXES[a]),
            Quantity::Inertia(e) => write!(f, "I{j}{}", TENSOR_ELEMENTS[e].0),
        }
    }
}

impl Variable {
    /// Its value in a full vector of search variables.
    pub(crate) fn value(&self, x: &[f64]) -> f64 {
        let at = self.link * PER_LINK;
        match self.quantity {
            Quantity::Mass => x[at],
            Quantity::Com(a) => x[at + 1 + a],
            Quantity::Inertia(e) => {
                let (_, row, column) = TENSOR_ELEMENTS[e];
                link_of(&x[at..at + PER_LINK]).inertia[row][column]
            }
        }
    }

    /// Its index among the search variables, for a mass or a centre-of-mass coordinate.
    pub(crate) fn index(&self) -> Option<usize> {
        let at = self.link * PER_LINK;
        match self.quantity {
            Quantity::Mass => Some(at),
            Quantity::Com(a) => Some(at + 1 + a),
            Quantity::Inertia(_) => None,
        }
    }

    /// Its range under `b`: the mass's, the coordinate's, the element's (a moment on the
    /// diagonal without its own lies in the link's `inertia` range); `None` for a product
    /// of inertia without a bound.
    pub(crate) fn range(&self, b: &LinkBounds) -> Option<[f64; 2]> {
        match self.quantity {
            Quantity::Mass => Some(b.mass),
            Quantity::Com(a) => Some(b.com[a]),
            Quantity::Inertia(e) => b.tensor[e].or((e < 3).then_some(b.inertia)),
        }
    }

    /// Its typical magnitude under `b`: the largest magnitude its bounds allow.
    pub(crate) fn scale(&self, b: &LinkBounds) -> f64 {
        let wide = |r: [f64; 2]| r[0].abs().max(r[1].abs());
        self.range(b).map_or(b.inertia[1], wide).max(1e-9)
    }
}

/// The most factors (constants and variables) on the right of an [`Equality`]: Gaz et al.'s
/// have three, and a message names the equality whole, so its length stays bounded.
pub const MAX_EQUALITY_FACTORS: usize = 16;

/// `left = coefficient * factors[0] * factors[1] * ...` (Gaz et al.'s eq. 15 form).
///
/// ```
/// use robid_runtime::feasible::Equality;
/// // Gaz et al. 2016, eq. 15
/// let e: Equality = "I7xz = c7x * c7z * m7".parse().unwrap();
/// assert_eq!(e.factors.len(), 3);
/// assert_eq!(e.to_string(), "I7xz = c7x * c7z * m7");
/// let half: Equality = "c6y = -0.5 * c6x".parse().unwrap();
/// assert_eq!(half.coefficient, -0.5);
/// assert!("I7xz = ".parse::<Equality>().is_err());
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Equality {
    /// The variable on the left.
    pub left: Variable,
    /// The constant factor on the right (1 when none is written).
    pub coefficient: f64,
    /// The variables multiplied on the right (none: `left` equals the constant).
    pub factors: Vec<Variable>,
}

impl FromStr for Equality {
    type Err = Error;

    fn from_str(s: &str) -> Result<Equality> {
        let bad = |why: &str| {
            Error::setting(
                "Equality",
                "text",
                format!(
                    "`{}`: {why}; write e.g. `I7xz = c7x * c7z * m7` or `c6y = -0.5 * c6x`",
                    short(s.trim())
                ),
            )
        };
        let (left, right) = s.split_once('=').ok_or_else(|| bad("no `=`"))?;
        let left: Variable = left.parse()?;
        let mut coefficient = 1.0;
        let mut factors = Vec::new();
        for (k, part) in right.split('*').enumerate() {
            if k == MAX_EQUALITY_FACTORS {
                let count = right.split('*').count();
                return Err(bad(&format!(
                    "{count} factors, more than {MAX_EQUALITY_FACTORS} (a constant and variables)"
                )));
            }
            let part = part.trim();
            if part.is_empty() {
                return Err(bad("an empty factor"));
            }
            match part.parse::<f64>() {
                Ok(c) if c.is_finite() && c.abs() <= MAX_PARAMETER => coefficient *= c,
                Ok(_) => return Err(bad("a constant that is not finite or beyond 1e6")),
                // a negated variable, `c6y = -c6x`, as `-1 * c6x`
                Err(_) => match part.strip_prefix('-') {
                    Some(variable) => {
                        coefficient = -coefficient;
                        factors.push(variable.trim().parse::<Variable>()?);
                    }
                    None => factors.push(part.parse::<Variable>()?),
                },
            }
        }
        Ok(Equality {
            left,
            coefficient,
            factors,
        })
    }
}

impl fmt::Display for Equality {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} = ", self.left)?;
        let mut parts: Vec<String> = Vec::new();
        if self.coefficient != 1.0 || self.factors.is_empty() {
            parts.push(format!("{}", self.coefficient));
        }
        parts.extend(self.factors.iter().map(Variable::to_string));
        write!(f, "{}", parts.join(" * "))
    }
}

impl Equality {
    /// Its text for a message, shortened past 80 characters as a user's text is
    /// ([`crate::names::shortened`]): links numbered in the billions make even a few
    /// factors long.
    pub(crate) fn quoted(&self) -> String {
        crate::names::shortened(&self.to_string(), 80).into_owned()
    }

    /// The links it names, 0-based.
    pub(crate) fn links(&self) -> impl Iterator<Item = usize> + '_ {
        std::iter::once(self.left.link).chain(self.factors.iter().map(|v| v.link))
    }

    /// `(left - right) / scale` at a full vector of search variables.
    pub(crate) fn violation(&self, x: &[f64], bounds: &[LinkBounds]) -> f64 {
        let right: f64 =
            self.coefficient * self.factors.iter().map(|v| v.value(x)).product::<f64>();
        (self.left.value(x) - right) / self.left.scale(&bounds[self.left.link])
    }

    /// What a result that misses it says (`None` when it holds): its sides at a full vector
    /// of search variables, within the tolerance of the bounds' check (1e-6 (1 + |right|),
    /// [`Solution`](crate::feasible::Solution)`::violations`), and, where both sides are
    /// that small, within 0.1 % of the larger side unless the difference is below 1e-8 of
    /// the left variable's scale under `bounds` (the search's own accuracy): equalities
    /// that only zero meets (`m1 = 2 * m2` with `m2 = 2 * m1`) ended with both masses at
    /// their floor of 1e-6 kg, 1e-6 apart, and counted as met.
    pub(crate) fn unmet(&self, x: &[f64], bounds: &[LinkBounds]) -> Option<String> {
        let left = self.left.value(x);
        let right = self.coefficient * self.factors.iter().map(|v| v.value(x)).product::<f64>();
        let off = (left - right).abs();
        let scale = self.left.scale(&bounds[self.left.link]);
        let missed = off > 1e-6 * (1.0 + right.abs())
            || (off > 1e-3 * left.abs().max(right.abs()) && off > 1e-8 * scale);
        missed.then(|| {
            format!(
                "equality `{}` not met: {} = {}, the right side {}",
                self.quoted(),
                self.left,
                Num::rounded(left, 8),
                Num::rounded(right, 8)
            )
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_bad_names_are_refused() {
        for name in ["m1", "c2x", "c12z", "I3xx", "I7yz"] {
            assert_eq!(name.parse::<Variable>().unwrap().to_string(), name);
        }
        for bad in ["", "m", "m0", "c3w", "I3zx", "x3", "m3x", "c-1x"] {
            let e = bad.parse::<Variable>().unwrap_err().to_string();
            assert!(e.contains("not a link variable"), "{bad}: {e}");
        }
        let e = "I7xz = c7x * * m7".parse::<Equality>().unwrap_err();
        assert!(e.to_string().contains("empty factor"), "{e}");
        assert!("I7xz c7x".parse::<Equality>().is_err());
        assert!("I7xz = 1e400 * c7x".parse::<Equality>().is_err());
        // finite but beyond the documented magnitude of an input (limits.rs)
        assert!("I7xz = 2e6 * c7x".parse::<Equality>().is_err());
    }

    /// Text of `--equal` is quoted short in every message (a 5,000-character name was
    /// echoed whole), and parentheses, which an equality does not take, are refused as a
    /// name without any recursion however deep they nest (5,000 and 100,000 levels).
    #[test]
    fn long_or_deeply_nested_text_is_quoted_short() {
        let nested = |depth: usize| format!("m6 = {}m1{}", "(".repeat(depth), ")".repeat(depth));
        for (text, quoted) in [
            (format!("m6 = {}", "x".repeat(5000)), 5000),
            (format!("{} = m1", "x".repeat(5000)), 5000),
            ("y".repeat(5000), 5000),
            (nested(5000), 10_002),
            (nested(100_000), 200_002),
            (format!("m6 = {}", "m1 * ".repeat(1000)), 0),
        ] {
            let e = text.parse::<Equality>().unwrap_err().to_string();
            assert!(e.len() < 300, "{} bytes: {}", e.len(), &e[..300]);
            if quoted > 0 {
                assert!(e.contains(&format!("({quoted} characters)")), "{e}");
            }
        }
    }

    /// An equality of more than [`MAX_EQUALITY_FACTORS`] factors is refused with the count:
    /// its messages name it whole.
    #[test]
    fn an_equality_of_too_many_factors_is_refused() {
        let e = format!("m6 = {}m1", "m1 * ".repeat(MAX_EQUALITY_FACTORS))
            .parse::<Equality>()
            .unwrap_err()
            .to_string();
        assert!(e.contains("17 factors, more than 16"), "{e}");
        let most = format!("m6 = {}m1", "m1 * ".repeat(MAX_EQUALITY_FACTORS - 1));
        assert_eq!(
            most.parse::<Equality>().unwrap().factors.len(),
            MAX_EQUALITY_FACTORS
        );
        // links numbered in the billions: the equality is shortened in messages
        let far = format!(
            "m6 = {}m1",
            "m1234567890 * ".repeat(MAX_EQUALITY_FACTORS - 1)
        );
        let quoted = far.parse::<Equality>().unwrap().quoted();
        assert!(
            quoted.ends_with(" characters)") && quoted.len() < 100,
            "{quoted}"
        );
    }

    /// An equality prints as it is written: the coefficient only when it is not 1 or stands
    /// alone.
    #[test]
    fn equalities_print_as_written() {
        for text in ["I7xz = c7x * c7z * m7", "c6y = -0.5 * c6x", "I2xy = 0.001"] {
            let e: Equality = text.parse().unwrap();
            assert_eq!(e.to_string(), text);
        }
        let e: Equality = "m1 = 2 * c1x * 0.5".parse().unwrap();
        assert_eq!(e.to_string(), "m1 = c1x");
        // a negated variable (it was "`-c2x` is not a link variable")
        let e: Equality = "c2z = -c2x".parse().unwrap();
        assert_eq!(
            (e.coefficient, e.to_string().as_str()),
            (-1.0, "c2z = -1 * c2x")
        );
        let e: Equality = "c2z = -0.5 * -c2x".parse().unwrap();
        assert_eq!(e.coefficient, 0.5);
    }

    /// A result that misses an equality by more than 1e-6 (1 + |right|) is named with both
    /// sides; one within it is not.
    #[test]
    fn an_unmet_equality_is_named_with_both_sides() {
        let mut x = vec![0.0; PER_LINK];
        x[0] = 2.0;
        x[1] = 0.1;
        let e: Equality = "c1x = 0.05 * m1".parse().unwrap();
        let b = LinkBounds::default();
        let bounds = [b];
        assert_eq!(e.unmet(&x, &bounds), None);
        x[1] = 0.1 + 2e-6;
        assert_eq!(
            e.unmet(&x, &bounds).as_deref(),
            Some("equality `c1x = 0.05 * m1` not met: c1x = 0.100002, the right side 0.1")
        );
        x[1] = 0.1 + 1e-6;
        assert_eq!(e.unmet(&x, &bounds), None);
        x[1] = 0.1 - 2e-6;
        assert!(e.unmet(&x, &bounds).is_some());
        // sides near zero: 0.1 % of the larger side, unless within 1e-8 of the scale
        let m: Equality = "m1 = 2 * c1x".parse().unwrap();
        let scale = m.left.scale(&b);
        (x[0], x[1]) = (1e-6, 1e-6);
        assert!(m.unmet(&x, &bounds).unwrap().contains("not met: m1 = 1e-6"));
        // 8e-7 apart: beyond 1e-8 of the scale (50 kg), within 1e-6 (1 + |right|)
        (x[0], x[1]) = (5e-4, (5e-4 - 8e-7) / 2.0);
        assert!(m.unmet(&x, &bounds).is_some(), "0.16 % of the larger side");
        (x[0], x[1]) = (1e-3, (1e-3 - 8e-7) / 2.0);
        assert_eq!(m.unmet(&x, &bounds), None, "0.08 %");
        (x[0], x[1]) = (1e-9 * scale, 0.0);
        assert_eq!(m.unmet(&x, &bounds), None);
        (x[0], x[1]) = (2e-8 * scale, 0.0);
        assert!(m.unmet(&x, &bounds).is_some());
        // a moment without its own bound lies in the link's inertia range; a product has none
        let v: Variable = "I1xx".parse().unwrap();
        assert_eq!(v.range(&b), Some(b.inertia));
        let v: Variable = "I1xy".parse().unwrap();
        assert_eq!(v.range(&b), None);
    }

    #[test]
    fn the_violation_is_the_scaled_difference() {
        // link 1 at m = 2, c = (0.1, 0, 0.3), no inertia: I1xz = 0 against c1x c1z m1 = 0.06
        let mut x = vec![0.0; PER_LINK];
        x[0] = 2.0;
        x[1] = 0.1;
        x[3] = 0.3;
        let b = LinkBounds {
            tensor: [None, None, None, None, Some([-0.2, 0.1]), None],
            ..LinkBounds::default()
        };
        let e: Equality = "I1xz = c1x * c1z * m1".parse().unwrap();
        assert!((e.violation(&x, &[b]) - (0.0 - 0.06) / 0.2).abs() < 1e-15);
        let e: Equality = "m1 = 4 * c1z".parse().unwrap();
        assert!((e.violation(&x, &[b]) - (2.0 - 1.2) / 50.0).abs() < 1e-15);
    }
}
