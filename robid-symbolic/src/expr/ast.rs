//! An expression as read from text (`parse.rs`), before it is built in an
//! arena, and its building through the smart constructors.
//!
//! Building replays exactly the constructor calls of reading straight into
//! the arena, so the nodes (and their ids) are the same either way. A
//! validated geometric value keeps its `Ast` and is built again, without
//! checks, in each derivation's arena (`robot::Geometry`).

use super::parse::{MAX_EXPONENT, ParseError};
use super::{Arena, Id, Node, Num};
use std::convert::Infallible;

/// A function of the expression language.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Function {
    Sin,
    Cos,
    Sign,
    Sqrt,
}

/// A product's operator.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Op {
    Mul,
    Div,
}

/// An expression as read. Positions are byte offsets in the text, for errors.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Ast {
    /// A number.
    Number(Num),
    /// `pi`.
    Pi,
    /// A symbol name.
    Name(String),
    /// A function call.
    Call(Function, Box<Ast>),
    /// A sum (also of one term): each term with `true` when subtracted, and
    /// the position after the last term.
    Sum(Vec<(bool, Ast)>, usize),
    /// A product: the first factor, then each operator, factor and the
    /// position after the factor.
    Product(Box<Ast>, Vec<(Op, Ast, usize)>),
    /// Unary minus.
    Neg(Box<Ast>),
    /// An integer power and the position of its exponent.
    Power(Box<Ast>, i32, usize),
}

impl Ast {
    /// True when the text calls a function.
    pub(crate) fn calls_function(&self) -> bool {
        let mut stack = vec![self];
        while let Some(ast) = stack.pop() {
            match ast {
                Ast::Call(..) => return true,
                Ast::Number(_) | Ast::Pi | Ast::Name(_) => {}
                Ast::Neg(x) | Ast::Power(x, ..) => stack.push(x),
                Ast::Sum(terms, _) => stack.extend(terms.iter().map(|(_, t)| t)),
                Ast::Product(first, rest) => {
                    stack.push(first);
                    stack.extend(rest.iter().map(|(_, f, _)| f));
                }
            }
        }
        false
    }
}

impl Arena {
    /// Builds a parsed expression with the checks of [`Arena::parse`]: no
    /// division by zero, every number finite, exponents within ±`MAX_EXPONENT`.
    pub(crate) fn build_checked(&mut self, ast: &Ast) -> Result<Id, ParseError> {
        let root = self.build(ast, &mut checks)?;
        // Every node the checks of the steps did not reach (none is expected).
        let seen = self.reachable(&[root]);
        for index in (0..seen.len()).filter(|&i| seen[i]) {
            let id = self.id_at(index);
            if let Some(problem) = problem(self, id, 0) {
                return Err(problem);
            }
        }
        Ok(root)
    }

    /// Builds an expression that was built with checks before (in another
    /// arena); cannot fail.
    pub(crate) fn build_unchecked(&mut self, ast: &Ast) -> Id {
        match self.build(ast, &mut |_, _| Ok::<(), Infallible>(())) {
            Ok(id) => id,
            Err(never) => match never {},
        }
    }

    /// The constructor calls of reading (see `parse.rs`), with `check` run on
    /// each step that can divide by zero or overflow.
    fn build<E>(
        &mut self,
        ast: &Ast,
        check: &mut impl FnMut(&mut Arena, Step) -> Result<(), E>,
    ) -> Result<Id, E> {
        Ok(match ast {
            Ast::Number(n) => self.num(*n),
            Ast::Pi => self.pi(),
            Ast::Name(name) => self.var(name),
            Ast::Call(f, x) => {
                let x = self.build(x, check)?;
                match f {
                    Function::Sin => self.sin(x),
                    Function::Cos => self.cos(x),
                    Function::Sign => self.sign(x),
                    Function::Sqrt => self.sqrt(x),
                }
            }
            Ast::Sum(terms, position) => {
                let mut ids = Vec::with_capacity(terms.len());
                for (negated, t) in terms {
                    let t = self.build(t, check)?;
                    ids.push(if *negated { self.neg(t) } else { t });
                }
                let sum = self.add(&ids);
                check(self, Step::Result(sum, *position))?;
                sum
            }
            Ast::Product(first, rest) => {
                let mut acc = self.build(first, check)?;
                for (op, factor, position) in rest {
                    let f = self.build(factor, check)?;
                    acc = match op {
                        Op::Mul => self.mul2(acc, f),
                        Op::Div => {
                            check(self, Step::Divisor(f, *position))?;
                            self.div(acc, f)
                        }
                    };
                    check(self, Step::Result(acc, *position))?;
                }
                acc
            }
            Ast::Neg(x) => {
                let x = self.build(x, check)?;
                self.neg(x)
            }
            Ast::Power(base, n, position) => {
                let base = self.build(base, check)?;
                if *n < 0 {
                    check(self, Step::Divisor(base, *position))?;
                }
                let p = self.pow(base, *n);
                check(self, Step::Result(p, *position))?;
                p
            }
        })
    }
}

/// What a check looks at.
enum Step {
    /// A divisor (or the base of a negative power), at a position.
    Divisor(Id, usize),
    /// The result of an operation, at a position.
    Result(Id, usize),
}

fn checks(arena: &mut Arena, step: Step) -> Result<(), ParseError> {
    match step {
        Step::Divisor(d, position) if arena.is_zero(d) => {
            Err(ParseError::DivisionByZero { position })
        }
        Step::Divisor(..) => Ok(()),
        Step::Result(id, position) => problem(arena, id, position).map_or(Ok(()), Err),
    }
}

/// A number that is not finite or an exponent beyond the limit in `id`, its
/// operands or theirs (the nodes one operation creates), if any.
fn problem(arena: &Arena, id: Id, position: usize) -> Option<ParseError> {
    let own = |id: Id| match arena.node(id) {
        Node::Num(c) if !c.to_f64().is_finite() => Some(ParseError::OutOfRange {
            position,
            number: c.to_string(),
        }),
        Node::Pow(_, n) if n.unsigned_abs() > MAX_EXPONENT.unsigned_abs() => {
            Some(ParseError::Exponent {
                position,
                exponent: n.to_string(),
            })
        }
        _ => None,
    };
    own(id).or_else(|| {
        arena.node(id).children().iter().find_map(|&c| {
            own(c).or_else(|| match arena.node(c) {
                Node::Mul(factors) => factors.iter().find_map(|&f| own(f)),
                _ => None,
            })
        })
    })
}

#[cfg(test)]
mod tests {
    use super::Ast;
    use crate::expr::Arena;

    /// Building from the Ast gives the node reading straight into the arena
    /// gave before (the same constructor calls, so the same ids).
    #[test]
    fn unchecked_building_matches_parsing() {
        let texts = ["-0.425", "pi/2", "-pi/2", "L2 + 2*L3 - d4/3", "(L1 - L2)^2"];
        let mut parsed = Arena::new();
        let mut built = Arena::new();
        for text in texts {
            let a = parsed.parse(text).unwrap();
            let b = built.build_unchecked(&Ast::parse(text).unwrap());
            assert_eq!(a, b, "{text}");
            assert_eq!(parsed.len(), built.len(), "{text}");
        }
    }

    #[test]
    fn function_calls_are_found() {
        assert!(Ast::parse("b*c - a + b/sin(d)").unwrap().calls_function());
        assert!(!Ast::parse("-(L1 + 2)^2").unwrap().calls_function());
    }
}
