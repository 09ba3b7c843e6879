//! The text form of expressions (`2*L3*sin(q2) - MZ3`), re-readable by `parse`.

use super::{Arena, Id, Node};
use std::fmt::Write;

/// Binding strength, to decide on parentheses.
#[derive(PartialEq, PartialOrd, Clone, Copy)]
enum Level {
    Sum,
    Product,
    Power,
    Atom,
}

impl Arena {
    /// The expression as text.
    pub fn display(&self, id: Id) -> String {
        let mut out = String::new();
        self.write(&mut out, id, Level::Sum);
        out
    }

    fn level(&self, id: Id) -> Level {
        match self.node(id) {
            Node::Add(_) => Level::Sum,
            Node::Mul(_) => Level::Product,
            Node::Num(c) if c.is_negative() || c.as_integer().is_none() => Level::Product,
            Node::Pow(..) => Level::Power,
            _ => Level::Atom,
        }
    }

    fn write(&self, out: &mut String, id: Id, context: Level) {
        let parens = self.level(id) < context;
        if parens {
            out.push('(');
        }
        match self.node(id) {
            Node::Num(c) => {
                let _ = write!(out, "{c}");
            }
            Node::Pi => out.push_str("pi"),
            Node::Sym(s) => out.push_str(self.symbol_name(*s)),
            Node::Add(terms) => {
                for (i, &t) in terms.iter().enumerate() {
                    let negative = match self.node(t) {
                        Node::Num(c) => c.is_negative(),
                        Node::Mul(f) => self.as_num(f[0]).is_some_and(|c| c.is_negative()),
                        _ => false,
                    };
                    if negative {
                        out.push_str(if i == 0 { "-" } else { " - " });
                        self.write_negated(out, t);
                    } else {
                        if i > 0 {
                            out.push_str(" + ");
                        }
                        self.write(out, t, Level::Sum);
                    }
                }
            }
            Node::Mul(factors) => self.write_product(out, factors),
            Node::Pow(base, n) => {
                self.write(out, *base, Level::Atom);
                if *n < 0 {
                    let _ = write!(out, "^({n})");
                } else {
                    let _ = write!(out, "^{n}");
                }
            }
            Node::Sin(x) => self.write_call(out, "sin", *x),
            Node::Cos(x) => self.write_call(out, "cos", *x),
            Node::Sign(x) => self.write_call(out, "sign", *x),
            Node::Sqrt(x) => self.write_call(out, "sqrt", *x),
        }
        if parens {
            out.push(')');
        }
    }

    /// Writes `-t` for a term with a negative coefficient.
    fn write_negated(&self, out: &mut String, t: Id) {
        match self.node(t) {
            Node::Num(c) => {
                let _ = write!(out, "{}", -*c);
            }
            Node::Mul(f) => {
                let c = self.as_num(f[0]).expect("negative coefficient");
                let c = -c;
                if c.is_one() {
                    self.write_factors(out, &f[1..]);
                } else {
                    let _ = write!(out, "{c}*");
                    self.write_factors(out, &f[1..]);
                }
            }
            _ => self.write(out, t, Level::Product),
        }
    }

    fn write_product(&self, out: &mut String, factors: &[Id]) {
        match self.as_num(factors[0]) {
            Some(c) if c == super::Num::MINUS_ONE => {
                out.push('-');
                self.write_factors(out, &factors[1..]);
            }
            _ => self.write_factors(out, factors),
        }
    }

    fn write_factors(&self, out: &mut String, factors: &[Id]) {
        for (i, &f) in factors.iter().enumerate() {
            if i > 0 {
                out.push('*');
            }
            let level = if i == 0 { Level::Product } else { Level::Power };
            self.write(out, f, level);
        }
    }

    fn write_call(&self, out: &mut String, name: &str, x: Id) {
        out.push_str(name);
        out.push('(');
        self.write(out, x, Level::Sum);
        out.push(')');
    }
}
