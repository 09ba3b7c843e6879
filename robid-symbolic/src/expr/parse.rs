//! Reading expressions from text: `pi/2`, `-L3`, `2*a3 + d4^2`, `sin(q1)^2`.
//!
//! Grammar: sum = product (('+' | '-') product)*; product = unary (('*' | '/') unary)*;
//! unary = '-' unary | power; power = atom ('^' integer | '^(' integer ')')?;
//! atom = number | 'pi' | name | function '(' sum ')' | '(' sum ')'.

use super::{Arena, Id, Num};

/// Text that is not an expression.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("at character {position}: {message}")]
pub struct ParseError {
    /// Byte offset in the text.
    pub position: usize,
    /// What was expected.
    pub message: String,
}

struct Parser<'a, 'b> {
    text: &'a [u8],
    pos: usize,
    arena: &'b mut Arena,
}

impl Arena {
    /// Parses an expression, building it through the smart constructors.
    pub fn parse(&mut self, text: &str) -> Result<Id, ParseError> {
        let mut p = Parser {
            text: text.as_bytes(),
            pos: 0,
            arena: self,
        };
        let e = p.sum()?;
        p.skip_space();
        if p.pos < p.text.len() {
            return Err(p.error("unexpected character; expected an operator or the end"));
        }
        Ok(e)
    }
}

impl Parser<'_, '_> {
    fn error(&self, message: &str) -> ParseError {
        ParseError {
            position: self.pos,
            message: message.to_owned(),
        }
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

    fn sum(&mut self) -> Result<Id, ParseError> {
        let mut terms = vec![self.product()?];
        loop {
            if self.eat(b'+') {
                terms.push(self.product()?);
            } else if self.eat(b'-') {
                let t = self.product()?;
                terms.push(self.arena.neg(t));
            } else {
                return Ok(self.arena.add(&terms));
            }
        }
    }

    fn product(&mut self) -> Result<Id, ParseError> {
        let mut acc = self.unary()?;
        loop {
            if self.eat(b'*') {
                let f = self.unary()?;
                acc = self.arena.mul2(acc, f);
            } else if self.eat(b'/') {
                let f = self.unary()?;
                if self.arena.is_zero(f) {
                    return Err(self.error("division by zero"));
                }
                acc = self.arena.div(acc, f);
            } else {
                return Ok(acc);
            }
        }
    }

    fn unary(&mut self) -> Result<Id, ParseError> {
        if self.eat(b'-') {
            let x = self.unary()?;
            return Ok(self.arena.neg(x));
        }
        if self.eat(b'+') {
            return self.unary();
        }
        self.power()
    }

    fn power(&mut self) -> Result<Id, ParseError> {
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
        while self.pos < self.text.len() && self.text[self.pos].is_ascii_digit() {
            self.pos += 1;
        }
        let exponent: i32 = std::str::from_utf8(&self.text[start..self.pos])
            .ok()
            .and_then(|s| s.parse().ok())
            .ok_or_else(|| self.error("expected an integer exponent"))?;
        if parenthesised && !self.eat(b')') {
            return Err(self.error("expected `)`"));
        }
        if exponent < 0 && self.arena.is_zero(base) {
            return Err(self.error("zero to a negative power"));
        }
        Ok(self.arena.pow(base, exponent))
    }

    fn atom(&mut self) -> Result<Id, ParseError> {
        match self.peek() {
            Some(b'(') => {
                self.pos += 1;
                let e = self.sum()?;
                if !self.eat(b')') {
                    return Err(self.error("expected `)`"));
                }
                Ok(e)
            }
            Some(c) if c.is_ascii_digit() || c == b'.' => self.number(),
            Some(c) if c.is_ascii_alphabetic() || c == b'_' => self.name(),
            _ => Err(self.error("expected a number, a name or `(`")),
        }
    }

    fn number(&mut self) -> Result<Id, ParseError> {
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
        let value = Num::parse_decimal(text)
            .or_else(|| text.parse::<f64>().ok().and_then(Num::from_f64))
            .ok_or_else(|| ParseError {
                position: start,
                message: format!("`{text}` is not a number"),
            })?;
        Ok(self.arena.num(value))
    }

    fn name(&mut self) -> Result<Id, ParseError> {
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
            return Ok(self.arena.pi());
        }
        let function: Option<fn(&mut Arena, Id) -> Id> = match name.as_str() {
            "sin" => Some(Arena::sin),
            "cos" => Some(Arena::cos),
            "sign" => Some(Arena::sign),
            "sqrt" => Some(Arena::sqrt),
            _ => None,
        };
        match function {
            Some(f) => {
                if !self.eat(b'(') {
                    return Err(self.error(&format!("expected `(` after `{name}`")));
                }
                let x = self.sum()?;
                if !self.eat(b')') {
                    return Err(self.error("expected `)`"));
                }
                Ok(f(self.arena, x))
            }
            None => Ok(self.arena.var(&name)),
        }
    }
}

#[cfg(test)]
mod tests {
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
        assert_eq!(err.position, 9);
        assert!(a.parse("sin x").is_err());
        assert!(a.parse("1/0").is_err());
        assert!(a.parse("x $ y").is_err());
    }
}
