//! Smart constructors: every node they create has been through the
//! simplification passes, so expressions stay canonical as they are built.

use super::simplify::{collect, fold, order, pythagoras, trig};
use super::{Arena, Id, Node, Num};

impl Arena {
    /// Sum of terms.
    pub fn add(&mut self, terms: &[Id]) -> Id {
        let flat = collect::flatten(self, terms, |n| match n {
            Node::Add(t) => Some(t),
            _ => None,
        });
        let (constant, rest) = fold::split_constants(self, &flat, Num::ZERO, std::ops::Add::add);
        let mut collected = collect::like_terms(self, &rest);
        pythagoras::sin2_plus_cos2(self, &mut collected);
        let mut out: Vec<Id> = collected
            .into_iter()
            .filter(|(c, _)| !c.is_zero())
            .map(|(c, m)| self.term(c, m))
            .collect();
        if !constant.is_zero() {
            out.push(self.num(constant));
        }
        order::sort(&mut out);
        match out.len() {
            0 => self.zero(),
            1 => out[0],
            _ => self.intern(Node::Add(out.into())),
        }
    }

    /// `a + b`.
    pub fn add2(&mut self, a: Id, b: Id) -> Id {
        self.add(&[a, b])
    }

    /// `a - b`.
    pub fn sub(&mut self, a: Id, b: Id) -> Id {
        let nb = self.neg(b);
        self.add(&[a, nb])
    }

    /// `-a`.
    pub fn neg(&mut self, a: Id) -> Id {
        self.scale(Num::MINUS_ONE, a)
    }

    /// `c * a` for a number `c`.
    pub fn scale(&mut self, c: Num, a: Id) -> Id {
        let c = self.num(c);
        self.mul(&[c, a])
    }

    /// Product of factors.
    pub fn mul(&mut self, factors: &[Id]) -> Id {
        let flat = collect::flatten(self, factors, |n| match n {
            Node::Mul(f) => Some(f),
            _ => None,
        });
        let (coefficient, rest) = fold::split_constants(self, &flat, Num::ONE, std::ops::Mul::mul);
        if coefficient.is_zero() {
            return self.zero();
        }
        let mut out = collect::like_factors(self, &rest);
        order::sort(&mut out);
        if out.is_empty() {
            return self.num(coefficient);
        }
        if coefficient.is_one() && out.len() == 1 {
            return out[0];
        }
        // c * (a + b) = c*a + c*b: a scaled sum is distributed so like terms meet.
        if let [single] = out[..]
            && let Node::Add(terms) = self.node(single).clone()
        {
            let scaled: Vec<Id> = terms.iter().map(|&t| self.scale(coefficient, t)).collect();
            return self.add(&scaled);
        }
        if !coefficient.is_one() {
            out.insert(0, self.num(coefficient));
        }
        self.intern(Node::Mul(out.into()))
    }

    /// `a * b`.
    pub fn mul2(&mut self, a: Id, b: Id) -> Id {
        self.mul(&[a, b])
    }

    /// `a / b`. A literal zero `b` is not refused here (as [`Arena::parse`] refuses
    /// `1/0`): it stays the node `0^(-1)`, which evaluates to infinity; check a divisor
    /// that can be zero before dividing.
    pub fn div(&mut self, a: Id, b: Id) -> Id {
        let inv = self.pow(b, -1);
        self.mul(&[a, inv])
    }

    /// `a ^ n` for an integer `n` (a literal zero to a negative power is kept as it is,
    /// see [`Arena::div`]).
    pub fn pow(&mut self, a: Id, n: i32) -> Id {
        if n == 0 {
            return self.one();
        }
        if n == 1 {
            return a;
        }
        match self.node(a).clone() {
            Node::Num(c) => match c.powi(n) {
                Some(v) => self.num(v),
                None => self.intern(Node::Pow(a, n)),
            },
            // (x^m)^n = x^(m n); kept as it is when m n does not fit.
            Node::Pow(base, m) => match m.checked_mul(n) {
                Some(k) => self.pow(base, k),
                None => self.intern(Node::Pow(a, n)),
            },
            // (c x y)^n = c^n x^n y^n keeps products flat for collecting.
            Node::Mul(factors) => {
                let powered: Vec<Id> = factors.iter().map(|&f| self.pow(f, n)).collect();
                self.mul(&powered)
            }
            _ => self.intern(Node::Pow(a, n)),
        }
    }

    /// Sine.
    pub fn sin(&mut self, a: Id) -> Id {
        trig::sin(self, a)
    }

    /// Cosine.
    pub fn cos(&mut self, a: Id) -> Id {
        trig::cos(self, a)
    }

    /// Sign (-1, 0, 1).
    pub fn sign(&mut self, a: Id) -> Id {
        match self.as_num(a) {
            Some(c) if c.is_zero() => self.zero(),
            Some(c) => self.int(if c.is_negative() { -1 } else { 1 }),
            None => self.intern(Node::Sign(a)),
        }
    }

    /// Square root.
    pub fn sqrt(&mut self, a: Id) -> Id {
        match self.as_num(a).and_then(fold::exact_sqrt) {
            Some(root) => self.num(root),
            None => self.intern(Node::Sqrt(a)),
        }
    }

    /// The constant pi.
    pub fn pi(&mut self) -> Id {
        self.intern(Node::Pi)
    }

    /// Rebuilds `coefficient * monomial` (monomial `None` means 1) in canonical form.
    pub(crate) fn term(&mut self, coefficient: Num, monomial: Option<Id>) -> Id {
        let Some(m) = monomial else {
            return self.num(coefficient);
        };
        if coefficient.is_one() {
            return m;
        }
        let c = self.num(coefficient);
        let factors: Vec<Id> = match self.node(m) {
            Node::Mul(f) => std::iter::once(c).chain(f.iter().copied()).collect(),
            _ => vec![c, m],
        };
        self.intern(Node::Mul(factors.into()))
    }

    /// Splits a term into its numeric coefficient and the rest (`None` when it is a number).
    pub(crate) fn split_term(&mut self, t: Id) -> (Num, Option<Id>) {
        match self.node(t).clone() {
            Node::Num(c) => (c, None),
            Node::Mul(f) => match self.as_num(f[0]) {
                Some(c) if f.len() == 2 => (c, Some(f[1])),
                Some(c) => (c, Some(self.intern(Node::Mul(f[1..].into())))),
                None => (Num::ONE, Some(t)),
            },
            _ => (Num::ONE, Some(t)),
        }
    }
}
