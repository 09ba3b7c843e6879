//! Arithmetic on lazy values [`E`]: products and sums fold numbers, merge
//! equal values and share one multiplication per coefficient.

use super::super::lower::Signed;
use super::super::{Instr, ProgramError, Value};
use super::{E, Lowering, V3, ZERO, neg, number};
use crate::expr::Id;

impl Lowering<'_> {
    /// The expression `id` as a value.
    pub(in crate::program) fn e(&mut self, id: Id) -> Result<E, ProgramError> {
        let s = self.lower(id)?;
        Ok(self.e_of(s))
    }

    pub(super) fn e_of(&self, s: Signed) -> E {
        let sign = if s.negative { -1.0 } else { 1.0 };
        match s.value {
            Value::Const(i) => number(sign * self.constant_value(i)),
            v => E {
                c: sign,
                v: Some(v),
            },
        }
    }

    /// The value with its coefficient's magnitude applied; the sign is left.
    pub(super) fn signed(&mut self, e: E) -> Signed {
        let negative = e.c < 0.0;
        let m = e.c.abs();
        let value = match e.v {
            None => self.constant(m),
            Some(v) if m == 1.0 => v,
            Some(v) => {
                let c = self.constant(m);
                self.emit(Instr::Mul(v, c))
            }
        };
        Signed { value, negative }
    }

    /// The value as an output: a negation is paid for here.
    pub(in crate::program) fn output(&mut self, e: E) -> Value {
        if let Some(v) = e.v
            && e.c < 0.0
            && e.c != -1.0
        {
            // The sign goes into the coefficient.
            let c = self.constant(e.c);
            return self.emit(Instr::Mul(v, c));
        }
        let s = self.signed(e);
        self.materialize(s)
    }

    /// As [`Lowering::output`], but the negative of a difference `a - b` is the
    /// difference `b - a` instead of a negation: the same one instruction, and the
    /// original difference is dead code when nothing else reads it. Used by the mass
    /// matrix only, whose entries often end in a sign.
    pub(in crate::program) fn output_swapping(&mut self, e: E) -> Value {
        if e.c == -1.0
            && let Some(v) = e.v
            && let Some(Instr::Sub(a, b)) = self.instr_of(v)
        {
            return self.emit(Instr::Sub(b, a));
        }
        self.output(e)
    }

    /// `e` with its coefficient's magnitude applied if that product exists.
    pub(super) fn reuse(&self, e: E) -> E {
        match e.v {
            Some(v) if e.c.abs() != 1.0 && e.c != 0.0 => {
                match self.existing_product(v, e.c.abs()) {
                    Some(p) => E {
                        c: e.c.signum(),
                        v: Some(p),
                    },
                    None => e,
                }
            }
            _ => e,
        }
    }

    pub(super) fn mul(&mut self, a: E, b: E) -> E {
        if a.c == 0.0 || b.c == 0.0 {
            return ZERO;
        }
        let v = match (a.v, b.v) {
            (None, x) | (x, None) => x,
            (Some(x), Some(y)) => Some(self.emit(Instr::Mul(x, y))),
        };
        E { c: a.c * b.c, v }
    }

    /// Sum: numbers folded, equal values merged, and the terms with the same
    /// coefficient magnitude added first and multiplied once.
    pub(super) fn add(&mut self, terms: &[E]) -> E {
        let mut k = 0.0;
        let mut items: Vec<(Value, f64)> = Vec::new();
        for t in terms {
            if t.c == 0.0 {
                continue;
            }
            match t.v {
                None => k += t.c,
                Some(v) => match items.iter_mut().find(|x| x.0 == v) {
                    Some(x) => x.1 += t.c,
                    None => items.push((v, t.c)),
                },
            }
        }
        let mut groups: Vec<(f64, Vec<Signed>)> = Vec::new();
        for (v, c) in items.into_iter().filter(|x| x.1 != 0.0) {
            let s = Signed {
                value: v,
                negative: c < 0.0,
            };
            match groups.iter_mut().find(|g| g.0 == c.abs()) {
                Some(g) => g.1.push(s),
                None => groups.push((c.abs(), vec![s])),
            }
        }
        let mut parts: Vec<E> = groups
            .into_iter()
            .map(|(m, members)| {
                let s = self.sum(&members);
                E {
                    c: if s.negative { -m } else { m },
                    v: Some(s.value),
                }
            })
            .collect();
        match (parts.len(), k == 0.0) {
            (0, _) => return number(k),
            (1, true) => return parts[0],
            _ => {}
        }
        if k != 0.0 {
            parts.push(number(k));
        }
        let signed: Vec<Signed> = parts.into_iter().map(|p| self.signed(p)).collect();
        let s = self.sum(&signed);
        self.e_of(s)
    }

    pub(super) fn add3(&mut self, vectors: &[V3]) -> V3 {
        [0, 1, 2].map(|i| {
            let terms: Vec<E> = vectors.iter().map(|v| v[i]).collect();
            self.add(&terms)
        })
    }

    pub(super) fn cross(&mut self, a: V3, b: V3) -> V3 {
        [(1, 2), (2, 0), (0, 1)].map(|(i, j)| {
            let p = self.mul(a[i], b[j]);
            let q = self.mul(a[j], b[i]);
            self.add(&[p, neg(q)])
        })
    }

    pub(super) fn mat_vec(&mut self, m: &[[E; 3]; 3], v: V3) -> V3 {
        [0, 1, 2].map(|i| {
            let terms: Vec<E> = (0..3).map(|k| self.mul(m[i][k], v[k])).collect();
            self.add(&terms)
        })
    }

    pub(super) fn sign_of(&mut self, x: E) -> E {
        match x.v {
            _ if x.c == 0.0 => ZERO,
            None => number(x.c.signum()),
            Some(v) => E {
                c: x.c.signum(),
                v: Some(self.emit(Instr::Sign(v))),
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::super::lower::Lowering;
    use super::super::super::{Group, Value};
    use super::super::{E, ZERO, number};
    use crate::expr::Arena;

    /// One input group `x` with one element.
    fn group() -> Vec<Group> {
        vec![Group {
            name: "x".to_owned(),
            elements: vec!["x".to_owned()],
        }]
    }

    /// The input `x` as a value.
    const X: E = E {
        c: 1.0,
        v: Some(Value::Input(0)),
    };

    /// sign(0) is 0, not the sign of +0.0 (which `f64::signum` gives as 1): the
    /// customised programs take sign(qd) for Coulomb friction, and qd is the number 0
    /// in the programs at rest.
    #[test]
    fn the_sign_of_zero_is_zero() {
        let (arena, inputs) = (Arena::new(), group());
        let mut l = Lowering::new(&arena, &inputs);
        let x = X;
        assert_eq!(l.sign_of(ZERO), ZERO);
        assert_eq!(l.sign_of(number(-2.5)), number(-1.0));
        let s = l.sign_of(E { c: -3.0, ..x });
        assert_eq!(s.c, -1.0);
        assert!(s.v.is_some());
    }

    /// A product with the number 0 is the number 0 whatever the other factor, so that
    /// no zero-coefficient program value is ever carried (or multiplied out).
    #[test]
    fn a_product_with_zero_is_the_number_zero() {
        let (arena, inputs) = (Arena::new(), group());
        let mut l = Lowering::new(&arena, &inputs);
        let x = X;
        assert_eq!(l.mul(ZERO, x), ZERO);
        assert_eq!(l.mul(x, ZERO), ZERO);
        assert_eq!(l.mul(number(2.0), x), E { c: 2.0, ..x });
    }

    /// An output that is zero is the constant +0.0 (not -0.0, which a sign test or a
    /// printed table would show).
    #[test]
    fn a_zero_output_is_positive_zero() {
        let (arena, inputs) = (Arena::new(), group());
        let mut l = Lowering::new(&arena, &inputs);
        let Value::Const(i) = l.output(ZERO) else {
            panic!("a zero output is a constant");
        };
        let zero = l.constant_value(i);
        assert!(zero == 0.0 && zero.is_sign_positive(), "{zero}");
    }
}
