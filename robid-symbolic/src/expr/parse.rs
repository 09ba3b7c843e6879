//! Reading expressions from text: `pi/2`, `-L3`, `2*a3 + d4^2`, `sin(q1)^2`.
//!
//! Grammar: sum = product (('+' | '-') product)*; product = unary (('*' | '/') unary)*;
//! unary = ('-' | '+') unary | power; power = atom ('^' integer | '^(' integer ')')?;
//! atom = number | 'pi' | name | function '(' sum ')' | '(' sum ')'.
//!
//! The text is first read into an [`Ast`] (no arena involved), which is then
//! built through the smart constructors (`ast.rs`). Text comes from users
//! (description files, macro input), so the reader has limits, each a named
//! [`ParseError`]: at most [`MAX_EXPRESSION_LEN`] bytes, at most
//! [`MAX_NESTING`] levels of parentheses, function calls and signs (the reader
//! recurses once per level, so the limit keeps the stack small), and integer
//! exponents within ±[`MAX_EXPONENT`].

use super::ast::{Ast, Function, Op};
use super::{Arena, Id, Num};

/// Longest expression text read, in bytes. Longer text is a
/// [`ParseError::TooLong`]: a geometric value is a few symbols and numbers,
/// and the cost of building a product grows with the square of its length.
pub const MAX_EXPRESSION_LEN: usize = 4096;

/// Deepest nesting read: parentheses, function calls and unary signs each
/// count one level (`-(-(x))` is four). Deeper text is a
/// [`ParseError::TooDeep`].
pub const MAX_NESTING: usize = 64;

/// Largest integer exponent magnitude: `x^64` and `x^(-64)` are read,
/// `x^65` is a [`ParseError::Exponent`], also when powers combine
/// (`(x^8)^9`, `x^40 * x^40`).
pub const MAX_EXPONENT: i32 = 64;

/// Text that is not an expression, or is beyond the reader's limits.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ParseError {
    /// The text does not follow the grammar.
    #[error("at character {position}: {message}")]
    Syntax {
        /// Byte offset in the text.
        position: usize,
        /// What was expected.
        message: String,
    },
    /// The text is longer than [`MAX_EXPRESSION_LEN`].
    #[error(
        "the expression is {length} bytes long, more than the {MAX_EXPRESSION_LEN} robid reads; write a shorter expression"
    )]
    TooLong {
        /// Length of the text in bytes.
        length: usize,
    },
    /// Parentheses, function calls and signs nest deeper than [`MAX_NESTING`].
    #[error(
        "at character {position}: parentheses, function calls and signs nest deeper than {MAX_NESTING} levels; simplify the expression"
    )]
    TooDeep {
        /// Byte offset where the limit was passed.
        position: usize,
    },
    /// An integer exponent, written or combined, beyond ±[`MAX_EXPONENT`].
    #[error(
        "at character {position}: the exponent {exponent} is beyond ±{MAX_EXPONENT}; use a smaller power"
    )]
    Exponent {
        /// Byte offset of the power.
        position: usize,
        /// The exponent as written or combined.
        exponent: String,
    },
    /// A number, written or computed from written numbers, that is not finite
    /// (beyond about ±1.8e308) or is not zero but rounds to zero.
    #[error(
        "at character {position}: `{number}` is out of the range of 64-bit floating point numbers; use a number between 1e-300 and 1e300 in magnitude"
    )]
    OutOfRange {
        /// Byte offset of the number or operation.
        position: usize,
        /// The number as written or computed.
        number: String,
    },
    /// A division by an expression that is zero, or zero to a negative power.
    #[error("at character {position}: division by zero")]
    DivisionByZero {
        /// Byte offset of the division or power.
        position: usize,
    },
}

impl ParseError {
    /// Byte offset in the text where the problem is (0 for a text too long).
    pub fn position(&self) -> usize {
        match self {
            ParseError::Syntax { position, .. }
            | ParseError::TooDeep { position }
            | ParseError::Exponent { position, .. }
            | ParseError::OutOfRange { position, .. }
            | ParseError::DivisionByZero { position } => *position,
            ParseError::TooLong { .. } => 0,
        }
    }
}

impl Arena {
    /// Parses an expression, building it through the smart constructors.
    ///
    /// Fails on text that is not an expression and past the documented limits:
    /// [`MAX_EXPRESSION_LEN`] bytes, [`MAX_NESTING`] levels, exponents within
    /// ±[`MAX_EXPONENT`]; every number in the result is finite.
    pub fn parse(&mut self, text: &str) -> Result<Id, ParseError> {
        let ast = Ast::parse(text)?;
        self.build_checked(&ast)
    }
}

impl Ast {
    /// Reads `text` (no arena involved; see [`Arena::parse`] for the limits).
    pub(crate) fn parse(text: &str) -> Result<Ast, ParseError> {
        if text.len() > MAX_EXPRESSION_LEN {
            return Err(ParseError::TooLong { length: text.len() });
        }
        let mut p = Parser {
            text: text.as_bytes(),
            pos: 0,
            depth: 0,
        };
        let e = p.sum()?;
        p.skip_space();
        if p.pos < p.text.len() {
            return Err(p.error("unexpected character; expected an operator or the end"));
        }
        Ok(e)
    }
}

struct Parser<'a> {
    text: &'a [u8],
    pos: usize,
    /// Current nesting (parentheses, calls, signs).
    depth: usize,
}

impl Parser<'_> {
    fn error(&self, message: &str) -> ParseError {
        ParseError::Syntax {
            position: self.pos,
            message: message.to_owned(),
        }
    }

    /// Enters one nesting level.
    fn enter(&mut self) -> Result<(), ParseError> {
        self.depth += 1;
        if self.depth > MAX_NESTING {
            return Err(ParseError::TooDeep { position: self.pos });
        }
        Ok(())
    }

    fn leave(&mut self) {
        self.depth -= 1;
    }

    fn skip_space(&mut self) {
        while self.pos < self.text.len() && self.text[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
    }

    fn peek(&mut self) -> Option<u8> {
        self.skip_space();
        self.text.get(self.pos).copied()
    }

    fn eat(&mut self, c: u8) -> bool {
        if self.peek() == Some(c) {
            self.pos += 1;
            true
        } else {
            false
        }
    }

    fn sum(&mut self) -> Result<Ast, ParseError> {
        let mut terms = vec![(false, self.product()?)];
        loop {
            if self.eat(b'+') {
                terms.push((false, self.product()?));
            } else if self.eat(b'-') {
                terms.push((true, self.product()?));
            } else {
                return Ok(Ast::Sum(terms, self.pos));
            }
        }
    }

    fn product(&mut self) -> Result<Ast, ParseError> {
        let first = self.unary()?;
        let mut rest = Vec::new();
        loop {
            let op = if self.eat(b'*') {
                Op::Mul
            } else if self.eat(b'/') {
                Op::Div
            } else {
                break;
            };
            let factor = self.unary()?;
            // Errors about the operation point after its right operand.
            rest.push((op, factor, self.pos));
        }
        Ok(if rest.is_empty() {
            first
        } else {
            Ast::Product(Box::new(first), rest)
        })
    }

    fn unary(&mut self) -> Result<Ast, ParseError> {
        for (sign, negate) in [(b'-', true), (b'+', false)] {
            if self.eat(sign) {
                self.enter()?;
                let x = self.unary()?;
                self.leave();
                return Ok(if negate { Ast::Neg(Box::new(x)) } else { x });
            }
        }
        self.power()
    }

    fn power(&mut self) -> Result<Ast, ParseError> {
        let base = self.atom()?;
        if !self.eat(b'^') {
            return Ok(base);
        }
        let parenthesised = self.eat(b'(');
        self.skip_space();
        let start = self.pos;
        if self.text.get(self.pos) == Some(&b'-') {
            self.pos += 1;
        }
        let digits = self.pos;
        while self.pos < self.text.len() && self.text[self.pos].is_ascii_digit() {
            self.pos += 1;
        }
        if self.pos == digits {
            return Err(self.error("expected an integer exponent"));
        }
        let written = String::from_utf8_lossy(&self.text[start..self.pos]).into_owned();
        let exponent = match written.parse::<i32>() {
            Ok(n) if n.unsigned_abs() <= MAX_EXPONENT.unsigned_abs() => n,
            _ => {
                return Err(ParseError::Exponent {
                    position: start,
                    exponent: written,
                });
            }
        };
        if parenthesised && !self.eat(b')') {
            return Err(self.error("expected `)`"));
        }
        Ok(Ast::Power(Box::new(base), exponent, start))
    }

    fn atom(&mut self) -> Result<Ast, ParseError> {
        match self.peek() {
            Some(b'(') => {
                self.pos += 1;
                self.enter()?;
                let e = self.sum()?;
                if !self.eat(b')') {
                    return Err(self.error("expected `)`"));
                }
                self.leave();
                Ok(e)
            }
            Some(c) if c.is_ascii_digit() || c == b'.' => self.number(),
            Some(c) if c.is_ascii_alphabetic() || c == b'_' => self.name(),
            _ => Err(self.error("expected a number, a name or `(`")),
        }
    }

    fn number(&mut self) -> Result<Ast, ParseError> {
        let start = self.pos;
        let digit = |c: u8| c.is_ascii_digit() || c == b'.';
        while self.pos < self.text.len() && digit(self.text[self.pos]) {
            self.pos += 1;
        }
        // Exponent part: 1e-3, 2.5E4.
        if matches!(self.text.get(self.pos), Some(b'e' | b'E')) {
            let save = self.pos;
            self.pos += 1;
            if matches!(self.text.get(self.pos), Some(b'+' | b'-')) {
                self.pos += 1;
            }
            let digits_start = self.pos;
            while self.pos < self.text.len() && self.text[self.pos].is_ascii_digit() {
                self.pos += 1;
            }
            if self.pos == digits_start {
                self.pos = save;
            }
        }
        let text = std::str::from_utf8(&self.text[start..self.pos]).unwrap_or("");
        if let Some(exact) = Num::parse_decimal(text) {
            return Ok(Ast::Number(exact));
        }
        let Ok(float) = text.parse::<f64>() else {
            return Err(ParseError::Syntax {
                position: start,
                message: format!("`{text}` is not a number"),
            });
        };
        // Not finite, or rounded to zero although a digit is not zero.
        let underflow = float == 0.0 && text.split(['e', 'E']).next().is_some_and(nonzero_digits);
        match Num::from_f64(float) {
            Some(value) if !underflow => Ok(Ast::Number(value)),
            _ => Err(ParseError::OutOfRange {
                position: start,
                number: text.to_owned(),
            }),
        }
    }

    fn name(&mut self) -> Result<Ast, ParseError> {
        let start = self.pos;
        while self.pos < self.text.len()
            && (self.text[self.pos].is_ascii_alphanumeric() || self.text[self.pos] == b'_')
        {
            self.pos += 1;
        }
        let name = std::str::from_utf8(&self.text[start..self.pos])
            .unwrap_or("")
            .to_owned();
        if name == "pi" {
            return Ok(Ast::Pi);
        }
        let function = match name.as_str() {
            "sin" => Function::Sin,
            "cos" => Function::Cos,
            "sign" => Function::Sign,
            "sqrt" => Function::Sqrt,
            _ => return Ok(Ast::Name(name)),
        };
        if !self.eat(b'(') {
            return Err(self.error(&format!("expected `(` after `{name}`")));
        }
        self.enter()?;
        let x = self.sum()?;
        if !self.eat(b')') {
            return Err(self.error("expected `)`"));
        }
        self.leave();
        Ok(Ast::Call(function, Box::new(x)))
    }
}

/// True when a decimal mantissa has a digit other than 0.
fn nonzero_digits(mantissa: &str) -> bool {
    mantissa.bytes().any(|c| c.is_ascii_digit() && c != b'0')
}

#[cfg(test)]
mod tests {
    use super::{MAX_EXPONENT, MAX_EXPRESSION_LEN, MAX_NESTING, ParseError};
    use crate::expr::Arena;

    #[test]
    fn round_trip_through_text() {
        let mut a = Arena::new();
        for text in [
            "2*L3*sin(q2) - MZ3",
            "pi/2",
            "-L3",
            "x^(-1)*y",
            "0.425*M3 + XX2",
            "1/3*x",
        ] {
            let e = a.parse(text).unwrap();
            let shown = a.display(e);
            let again = a.parse(&shown).unwrap();
            assert_eq!(e, again, "{text} -> {shown}");
        }
    }

    #[test]
    fn errors_say_where() {
        let mut a = Arena::new();
        let err = a.parse("2 * (x + ").unwrap_err();
        assert_eq!(err.position(), 9);
        assert!(matches!(a.parse("sin x"), Err(ParseError::Syntax { .. })));
        assert!(matches!(
            a.parse("1/0"),
            Err(ParseError::DivisionByZero { position: 3 })
        ));
        assert!(matches!(
            a.parse("1/(x - x)"),
            Err(ParseError::DivisionByZero { .. })
        ));
        assert!(matches!(
            a.parse("(x - x)^(-2)"),
            Err(ParseError::DivisionByZero { .. })
        ));
        assert!(matches!(a.parse("x $ y"), Err(ParseError::Syntax { .. })));
        assert!(matches!(a.parse("pi/"), Err(ParseError::Syntax { .. })));
    }

    /// The nesting limit is exact: `MAX_NESTING` levels of each kind are read,
    /// one more is the named error, and text far deeper (the 40 kB alpha that
    /// overflowed the stack) fails the same way.
    #[test]
    fn nesting_is_limited() {
        let mut a = Arena::new();
        let nest =
            |open: &str, close: &str, n: usize| format!("{}x{}", open.repeat(n), close.repeat(n));
        for (open, close, levels) in [
            ("(", ")", 1),
            ("sin(", ")", 1),
            ("-", "", 1),
            ("+", "", 1),
            ("-(", ")", 2),
        ] {
            let fits = nest(open, close, MAX_NESTING / levels);
            assert!(a.parse(&fits).is_ok(), "{open}: {MAX_NESTING} levels");
            let deeper = nest(open, close, MAX_NESTING / levels + 1);
            assert!(
                matches!(a.parse(&deeper), Err(ParseError::TooDeep { .. })),
                "{open}: one level more"
            );
        }
        let huge = nest("(", ")", 1000);
        assert!(matches!(a.parse(&huge), Err(ParseError::TooDeep { .. })));
        let minus = format!("{}x", "-".repeat(2000));
        assert!(matches!(a.parse(&minus), Err(ParseError::TooDeep { .. })));
    }

    #[test]
    fn long_text_is_refused_before_reading() {
        let mut a = Arena::new();
        let sum = vec!["x"; MAX_EXPRESSION_LEN / 2].join("+");
        assert!(sum.len() < MAX_EXPRESSION_LEN);
        let e = a.parse(&sum).unwrap();
        assert_eq!(a.display(e), format!("{}*x", MAX_EXPRESSION_LEN / 2));
        let long = format!("{sum}+x+x");
        assert!(matches!(
            a.parse(&long),
            Err(ParseError::TooLong { length }) if length == long.len()
        ));
        let deep = format!("{}x{}", "(".repeat(20_000), ")".repeat(20_000));
        assert!(matches!(a.parse(&deep), Err(ParseError::TooLong { .. })));
    }

    #[test]
    fn exponents_are_bounded_as_written_and_combined() {
        let mut a = Arena::new();
        assert!(a.parse(&format!("x^{MAX_EXPONENT}")).is_ok());
        assert!(a.parse(&format!("x^(-{MAX_EXPONENT})")).is_ok());
        for text in [
            "x^65",
            "x^(-65)",
            "x^99999999",
            "x^99999999999999999999",
            "2^1024",
            "(x^8)^9",
            "x^40 * x^40",
            "x^40 / x^(-40)",
            "(2*x)^40 * x^40",
        ] {
            assert!(
                matches!(a.parse(text), Err(ParseError::Exponent { .. })),
                "{text}: {:?}",
                a.parse(text)
            );
        }
        let e = a.parse("(x^8)^8").unwrap();
        assert_eq!(a.display(e), "x^64");
    }

    #[test]
    fn numbers_stay_finite() {
        let mut a = Arena::new();
        for text in [
            "1e400",
            "1e-400",
            "1e300 * 1e300",
            "(1e300*x) * 1e300",
            "1e300*x + 1e300*x*1e300",
            "1e200^2",
        ] {
            assert!(
                matches!(
                    a.parse(text),
                    Err(ParseError::OutOfRange { .. }) | Err(ParseError::Exponent { .. })
                ),
                "{text}: {:?}",
                a.parse(text)
            );
        }
        let tiny = a.parse("1e-320").unwrap();
        assert!(a.as_num(tiny).is_some_and(|n| n.to_f64() > 0.0));
        let zero = a.parse("0e-400").unwrap();
        assert!(a.is_zero(zero));
    }
}
