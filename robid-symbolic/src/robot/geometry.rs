//! Geometric values: numbers, or expressions in numbers, `pi` and symbol
//! names, read once when built and valid by construction.

use super::ParameterKind;
use crate::expr::{Arena, Ast, Id, Node, Num, ParseError};
use std::fmt;

/// A geometric value (a DH value or a gravity component), valid by
/// construction: a finite number, or an expression in numbers, `pi` and
/// symbol names such as `"pi/2"`, `"-L3"` or `"L2 + 0.1"`, read once.
///
/// Whether its magnitude suits its place (a length, an angle, gravity) is
/// checked when a [`Robot`](super::Robot) is built from it.
#[derive(Clone, Debug, PartialEq)]
pub enum Geometry {
    /// A finite number, kept exactly when its decimal form is short (0.425 is 17/40).
    Number(Number),
    /// An expression in numbers, `pi` and symbol names.
    Expression(Expression),
}

/// The number of a [`Geometry::Number`].
#[derive(Clone, Debug, PartialEq)]
pub struct Number {
    value: Num,
    text: String,
    ast: Ast,
}

impl Number {
    /// The value.
    pub fn value(&self) -> f64 {
        self.value.to_f64()
    }

    /// The value as an exact number when it has a short decimal form.
    pub fn exact(&self) -> Num {
        self.value
    }
}

/// The expression of a [`Geometry::Expression`]: it calls no function, uses
/// none of the names robid gives to joint variables and parameters, and every
/// number in it is finite.
#[derive(Clone, Debug, PartialEq)]
pub struct Expression {
    text: String,
    ast: Ast,
    symbols: Vec<String>,
}

impl Expression {
    /// The symbols the value depends on, in order of first use.
    pub fn symbols(&self) -> &[String] {
        &self.symbols
    }
}

/// A geometric value that cannot be built.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
#[error("{}; {}", self.message(), self.help())]
pub enum GeometryError {
    /// A number that is NaN or infinite.
    NotFinite(f64),
    /// Text that is not an expression, or beyond the expression reader's limits.
    Parse {
        /// The text.
        text: String,
        /// Why it is not read.
        error: ParseError,
    },
    /// The expression calls a function.
    Function(String),
    /// The expression uses a name robid gives to joint variables and parameters.
    Reserved {
        /// The text.
        text: String,
        /// The reserved name.
        name: String,
    },
}

impl GeometryError {
    /// What is wrong (the first part of the error's text).
    pub fn message(&self) -> String {
        match self {
            GeometryError::NotFinite(x) => format!("`{x}` is not a finite number"),
            GeometryError::Parse { text, error } => {
                format!("`{}` is not an expression: {error}", excerpt(text))
            }
            GeometryError::Function(text) => format!("`{}` calls a function", excerpt(text)),
            GeometryError::Reserved { text, name } if not_finite_name(name) => format!(
                "`{}` uses `{name}`, which reads as a number that is not finite",
                excerpt(text)
            ),
            GeometryError::Reserved { text, name } => format!(
                "`{}` uses `{name}`, a name robid gives to joint variables and parameters",
                excerpt(text)
            ),
        }
    }

    /// How to fix it (the second part of the error's text).
    pub fn help(&self) -> &'static str {
        match self {
            GeometryError::NotFinite(_) => "DH values and gravity are finite numbers",
            GeometryError::Parse {
                error: ParseError::Syntax { .. } | ParseError::DivisionByZero { .. },
                ..
            } => {
                "write a number, an angle such as \"pi/2\", or a symbol expression such as \"L3\" or \"-d4\""
            }
            GeometryError::Parse { .. } => {
                "geometric values are short expressions in numbers, pi and symbols"
            }
            GeometryError::Function(_) => {
                "geometric values are sums and products of numbers, pi and symbols"
            }
            GeometryError::Reserved { .. } => "rename the symbol, e.g. `L3` or `d_tool`",
        }
    }

    /// Byte offset of the problem in the text, when it is about one place of it.
    pub fn position(&self) -> Option<usize> {
        match self {
            GeometryError::Parse {
                error: ParseError::TooLong { .. },
                ..
            } => None,
            GeometryError::Parse { error, .. } => Some(error.position()),
            _ => None,
        }
    }
}

impl Geometry {
    /// A number; fails when it is NaN or infinite.
    pub fn number(value: f64) -> Result<Geometry, GeometryError> {
        let exact = Num::from_f64(value).ok_or(GeometryError::NotFinite(value))?;
        let exact_text = exact.to_string();
        // The text form reads back (it is how the value has always been
        // built); the number itself is the fallback.
        let ast = Ast::parse(&exact_text).unwrap_or(Ast::Number(exact));
        // A long fraction that is the float's own decimal (a length fitted from a URDF,
        // 9217659541255431/25000000000000000) is shown as that decimal, 0.36870638165021724
        // (the exact number stays the value).
        let decimal = format!("{value:?}");
        let text = if exact_text.contains('/') && decimal.len() < exact_text.len() {
            decimal
        } else {
            exact_text
        };
        Ok(Geometry::Number(Number {
            value: exact,
            text,
            ast,
        }))
    }

    /// An expression in numbers, `pi` and symbol names, read now (within the
    /// limits of [`Arena::parse`]); fails on text that is not one, that calls a
    /// function or that uses a name robid gives to joint variables and
    /// parameters (`q1`, `qd1`, `qdd1`, `XX1` .. `M1`, `Ia1`, `Fv1`, `Fc1`,
    /// `Fo1`) or that reads as a non-finite number (`inf`, `nan`).
    pub fn text(text: &str) -> Result<Geometry, GeometryError> {
        let text = text.trim();
        let parse_error = |error| GeometryError::Parse {
            text: text.to_owned(),
            error,
        };
        let ast = Ast::parse(text).map_err(parse_error)?;
        if ast.calls_function() {
            return Err(GeometryError::Function(text.to_owned()));
        }
        let mut arena = Arena::new();
        let root = arena.build_checked(&ast).map_err(parse_error)?;
        let symbols: Vec<String> = arena
            .free_symbols(&[root])
            .into_iter()
            .map(|s| arena.symbol_name(s).to_owned())
            .collect();
        if let Some(name) = symbols.iter().find(|s| reserved(s)) {
            return Err(GeometryError::Reserved {
                text: text.to_owned(),
                name: name.clone(),
            });
        }
        Ok(Geometry::Expression(Expression {
            text: text.to_owned(),
            ast,
            symbols,
        }))
    }

    /// Zero.
    pub fn zero() -> Geometry {
        Geometry::Number(Number {
            value: Num::ZERO,
            text: "0".to_owned(),
            ast: Ast::parse("0").unwrap_or(Ast::Number(Num::ZERO)),
        })
    }

    /// The value as an expression in `arena`.
    pub fn to_expr(&self, arena: &mut Arena) -> Id {
        match self {
            Geometry::Number(n) => arena.build_unchecked(&n.ast),
            Geometry::Expression(e) => arena.build_unchecked(&e.ast),
        }
    }

    /// The text form (re-readable by [`Geometry::text`]).
    pub fn as_str(&self) -> &str {
        match self {
            Geometry::Number(n) => &n.text,
            Geometry::Expression(e) => &e.text,
        }
    }

    /// The symbols the value depends on, in order of first use (none for a number).
    pub fn symbols(&self) -> &[String] {
        match self {
            Geometry::Number(_) => &[],
            Geometry::Expression(e) => &e.symbols,
        }
    }

    /// True when the value is exactly zero.
    pub fn is_zero(&self) -> bool {
        let mut arena = Arena::new();
        let id = self.to_expr(&mut arena);
        arena.is_zero(id)
    }

    /// When the value has no symbol and is exactly `k pi/2` for an integer
    /// `k` (a number 0 included): `k` (DH angles of this form are exact).
    pub(crate) fn quarter_turns(&self) -> Option<i128> {
        let mut arena = Arena::new();
        let id = self.to_expr(&mut arena);
        let c = match arena.node(id) {
            Node::Num(c) if c.is_zero() => return Some(0),
            Node::Pi => Num::ONE,
            Node::Mul(f) if f.len() == 2 && matches!(arena.node(f[1]), Node::Pi) => {
                arena.as_num(f[0])?
            }
            _ => return None,
        };
        (c * Num::int(2)).as_integer()
    }
}

impl fmt::Display for Geometry {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// At most the first 40 characters of `text`, for messages.
pub(crate) fn excerpt(text: &str) -> String {
    match text.char_indices().nth(40) {
        Some((end, _)) => format!("{}...", &text[..end]),
        None => text.to_owned(),
    }
}

/// True for names the derivation uses itself: joint variables (`q1`, `qd1`, `qdd1`),
/// standard and base parameters (`XX1`, `ZZR1`), with any digits after the stem.
pub(crate) fn reserved(name: &str) -> bool {
    let digits = name.len() - name.trim_end_matches(|c: char| c.is_ascii_digit()).len();
    let stem = &name[..name.len() - digits];
    let parameter = |s: &str| ParameterKind::ALL.iter().any(|k| k.stem() == s);
    let used = ["qdd", "qd", "q"].contains(&stem)
        || parameter(stem)
        || stem.strip_suffix('R').is_some_and(parameter);
    (digits > 0 && used) || name == "pi" || not_finite_name(name)
}

/// `inf`, `infinity` and `nan` in any case: as symbols they would read as
/// non-finite numbers in every text robid writes.
fn not_finite_name(name: &str) -> bool {
    matches!(
        name.to_ascii_lowercase().as_str(),
        "inf" | "infinity" | "nan"
    )
}

#[cfg(test)]
mod tests {
    use super::{Geometry, GeometryError};
    use crate::expr::Arena;

    /// A float that is only a long fraction is written as its decimal, which reads back as
    /// the same exact number; short fractions and decimals keep their form.
    #[test]
    fn long_fractions_are_written_as_decimals() {
        let x = Geometry::number(0.36870638165021724).unwrap();
        assert_eq!(x.as_str(), "0.36870638165021724");
        assert_eq!(Geometry::number(0.425).unwrap().as_str(), "0.425");
    }

    #[test]
    fn invalid_values_are_errors_not_panics() {
        assert!(matches!(
            Geometry::number(f64::NAN),
            Err(GeometryError::NotFinite(_))
        ));
        assert!(matches!(
            Geometry::number(f64::NEG_INFINITY),
            Err(GeometryError::NotFinite(_))
        ));
        assert!(matches!(
            Geometry::text("pi/"),
            Err(GeometryError::Parse { .. })
        ));
        assert!(matches!(
            Geometry::text("sin(L)"),
            Err(GeometryError::Function(_))
        ));
        assert!(matches!(
            Geometry::text("2*q1"),
            Err(GeometryError::Reserved { name, .. }) if name == "q1"
        ));
        assert!(matches!(
            Geometry::text("2^1024"),
            Err(GeometryError::Parse { .. })
        ));
        for name in ["inf", "NaN", "Infinity"] {
            let e = Geometry::text(&format!("pi/{name}")).unwrap_err();
            assert!(e.to_string().contains("not finite"), "{e}");
        }
        assert!(Geometry::text("L_inf + nan2").is_ok());
    }

    #[test]
    fn names_of_variables_and_parameters_are_reserved() {
        // a base parameter's name is a symbol of the derivation too (`ZZR1`)
        for name in ["q1", "qdd12", "XX1", "M3", "Fo2", "ZZR1", "MR2", "MXR10"] {
            assert!(super::reserved(name), "{name}");
        }
        for name in ["q", "L1", "Ma1", "ZZR", "R1", "XXRR1", "d_tool", "qq1"] {
            assert!(!super::reserved(name), "{name}");
        }
    }

    #[test]
    fn values_build_in_any_arena() {
        let g = Geometry::text(" L2 - 0.1 + L1 ").unwrap();
        assert_eq!(g.as_str(), "L2 - 0.1 + L1");
        assert_eq!(g.symbols(), ["L2", "L1"]);
        let mut a = Arena::new();
        let built = g.to_expr(&mut a);
        let parsed = a.parse("L1 + L2 - 0.1").unwrap();
        assert_eq!(built, parsed);
        let n = Geometry::number(-0.425).unwrap();
        assert_eq!(n.as_str(), "-0.425");
        assert!(n.symbols().is_empty());
        assert!(Geometry::zero().is_zero() && !n.is_zero());
    }

    #[test]
    fn quarter_turns_are_recognised() {
        let k = |t: &str| Geometry::text(t).unwrap().quarter_turns();
        assert_eq!(k("pi/2"), Some(1));
        assert_eq!(k("-pi"), Some(-2));
        assert_eq!(k("0"), Some(0));
        assert_eq!(k("pi/3"), None);
        assert_eq!(k("1.5707963"), None);
        assert_eq!(k("A + pi/2"), None);
    }
}
