//! Lowering output expressions of an arena to a straight-line program.
//!
//! Nodes are visited in id order (children before parents), each once. A node
//! lowers to a value and a sign, so a negation is never computed on its own:
//! `x*(-1) + y` becomes `y - x`, `sin(-x)` becomes `-sin(x)` and the sign is
//! carried on to the parent, and only an output (or the argument of `sqrt`)
//! that ends up negative pays for a `neg`. Sums are added pairwise (a shallow
//! tree the processor can run in parallel); products multiply their symbolic
//! factors first and a numeric coefficient last, skipping coefficients of
//! magnitude one. A memo of instructions merges identical operations that
//! the arena keeps as different nodes (e.g. the products inside two sums).

use super::dce;
use super::{Group, Instr, Output, Program, ProgramError, Value};
use crate::expr::{Arena, Id, Node};
use std::collections::HashMap;

/// A value and whether the node's value is its negation.
#[derive(Clone, Copy, Debug)]
struct Signed {
    value: Value,
    negative: bool,
}

impl Signed {
    fn plus(value: Value) -> Signed {
        Signed {
            value,
            negative: false,
        }
    }

    fn flip(self, flip: bool) -> Signed {
        Signed {
            value: self.value,
            negative: self.negative != flip,
        }
    }
}

struct Lowering<'a> {
    arena: &'a Arena,
    inputs: HashMap<&'a str, u32>,
    constants: Vec<f64>,
    constant_index: HashMap<u64, u32>,
    instrs: Vec<Instr>,
    memo: HashMap<Instr, Value>,
    lowered: Vec<Option<Signed>>,
}

impl Program {
    /// Builds the program computing `outputs` (groups of expressions of
    /// `arena`) from `inputs` (groups whose elements name the symbols they
    /// bind). Every symbol an output depends on must be an input.
    pub fn build(
        arena: &Arena,
        inputs: Vec<Group>,
        outputs: Vec<(Group, Vec<Id>)>,
    ) -> Result<Program, ProgramError> {
        let names: Vec<String> = inputs
            .iter()
            .flat_map(|g| g.elements.iter().cloned())
            .collect();
        let mut l = Lowering {
            arena,
            inputs: names
                .iter()
                .enumerate()
                .map(|(i, n)| (n.as_str(), i as u32))
                .collect(),
            constants: Vec::new(),
            constant_index: HashMap::new(),
            instrs: Vec::new(),
            memo: HashMap::new(),
            lowered: vec![None; arena.len()],
        };
        let roots: Vec<Id> = outputs.iter().flat_map(|(_, ids)| ids.clone()).collect();
        let needed = arena.reachable(&roots);
        for index in (0..needed.len()).filter(|&i| needed[i]) {
            let s = l.node(arena.id_at(index))?;
            l.lowered[index] = Some(s);
        }
        let outputs = outputs
            .into_iter()
            .map(|(group, ids)| {
                let values = ids
                    .iter()
                    .map(|id| {
                        let s = l.lowered[id.index()].expect("lowered");
                        l.materialize(s)
                    })
                    .collect();
                Output { group, values }
            })
            .collect();
        let program = Program {
            inputs,
            constants: l.constants,
            instrs: l.instrs,
            outputs,
        };
        Ok(dce::remove_dead_code(program))
    }
}

impl Lowering<'_> {
    fn get(&self, id: Id) -> Signed {
        self.lowered[id.index()].expect("children are lowered before parents")
    }

    fn constant(&mut self, x: f64) -> Value {
        let bits = x.to_bits();
        if let Some(&i) = self.constant_index.get(&bits) {
            return Value::Const(i);
        }
        let i = self.constants.len() as u32;
        self.constants.push(x);
        self.constant_index.insert(bits, i);
        Value::Const(i)
    }

    /// Appends an instruction unless the same one exists (commutative operands sorted).
    fn emit(&mut self, instr: Instr) -> Value {
        let instr = match instr {
            Instr::Add(a, b) if b < a => Instr::Add(b, a),
            Instr::Mul(a, b) if b < a => Instr::Mul(b, a),
            other => other,
        };
        if let Some(&v) = self.memo.get(&instr) {
            return v;
        }
        let v = Value::Temp(self.instrs.len() as u32);
        self.instrs.push(instr);
        self.memo.insert(instr, v);
        v
    }

    /// The value itself, paying for a negation if it is negative.
    fn materialize(&mut self, s: Signed) -> Value {
        if !s.negative {
            return s.value;
        }
        match s.value {
            Value::Const(i) => {
                let c = -self.constants[i as usize];
                self.constant(c)
            }
            v => self.emit(Instr::Neg(v)),
        }
    }

    fn node(&mut self, id: Id) -> Result<Signed, ProgramError> {
        let arena = self.arena;
        Ok(match arena.node(id) {
            Node::Num(c) => {
                let x = c.to_f64();
                let value = self.constant(x.abs());
                Signed {
                    value,
                    negative: x < 0.0,
                }
            }
            Node::Pi => Signed::plus(self.constant(std::f64::consts::PI)),
            Node::Sym(s) => {
                let name = arena.symbol_name(*s);
                match self.inputs.get(name) {
                    Some(&i) => Signed::plus(Value::Input(i)),
                    None => return Err(ProgramError::Unbound(name.to_owned())),
                }
            }
            Node::Add(terms) => {
                let terms: Vec<Signed> = terms.iter().map(|&t| self.get(t)).collect();
                self.sum(&terms)
            }
            Node::Mul(factors) => self.product(factors),
            Node::Pow(x, n) => {
                let x = self.get(*x);
                self.power(x, *n)
            }
            Node::Sin(x) => {
                let x = self.get(*x);
                Signed::plus(self.emit(Instr::Sin(x.value))).flip(x.negative)
            }
            Node::Cos(x) => {
                let x = self.get(*x);
                Signed::plus(self.emit(Instr::Cos(x.value)))
            }
            Node::Sign(x) => {
                let x = self.get(*x);
                Signed::plus(self.emit(Instr::Sign(x.value))).flip(x.negative)
            }
            Node::Sqrt(x) => {
                let x = self.get(*x);
                let v = self.materialize(x);
                Signed::plus(self.emit(Instr::Sqrt(v)))
            }
        })
    }

    /// Pairwise sum; a negative operand turns an addition into a subtraction.
    fn sum(&mut self, terms: &[Signed]) -> Signed {
        match terms {
            [] => Signed::plus(self.constant(0.0)),
            [one] => *one,
            _ => {
                let (left, right) = terms.split_at(terms.len() / 2);
                let a = self.sum(left);
                let b = self.sum(right);
                match (a.negative, b.negative) {
                    (false, false) => Signed::plus(self.emit(Instr::Add(a.value, b.value))),
                    (true, true) => {
                        Signed::plus(self.emit(Instr::Add(a.value, b.value))).flip(true)
                    }
                    (false, true) => Signed::plus(self.emit(Instr::Sub(a.value, b.value))),
                    (true, false) => Signed::plus(self.emit(Instr::Sub(b.value, a.value))),
                }
            }
        }
    }

    /// Product: symbolic factors left to right, then the coefficient's magnitude.
    fn product(&mut self, factors: &[Id]) -> Signed {
        let (coefficient, rest) = match self.arena.as_num(factors[0]) {
            Some(c) => (c.to_f64(), &factors[1..]),
            None => (1.0, factors),
        };
        let mut negative = coefficient < 0.0;
        let mut acc: Option<Value> = None;
        for &f in rest {
            let s = self.get(f);
            negative ^= s.negative;
            acc = Some(match acc {
                None => s.value,
                Some(a) => self.emit(Instr::Mul(a, s.value)),
            });
        }
        let magnitude = coefficient.abs();
        let value = match acc {
            None => self.constant(magnitude),
            Some(a) if magnitude == 1.0 => a,
            Some(a) => {
                let c = self.constant(magnitude);
                self.emit(Instr::Mul(a, c))
            }
        };
        Signed { value, negative }
    }

    /// `x^n` by repeated squaring; a negative power divides 1 by it.
    fn power(&mut self, x: Signed, n: i32) -> Signed {
        let negative = x.negative && n % 2 != 0;
        let mut k = n.unsigned_abs();
        let mut square = x.value;
        let mut acc: Option<Value> = None;
        while k > 0 {
            if k & 1 == 1 {
                acc = Some(match acc {
                    None => square,
                    Some(a) => self.emit(Instr::Mul(a, square)),
                });
            }
            k >>= 1;
            if k > 0 {
                square = self.emit(Instr::Mul(square, square));
            }
        }
        let mut value = acc.unwrap_or_else(|| self.constant(1.0));
        if n < 0 {
            let one = self.constant(1.0);
            value = self.emit(Instr::Div(one, value));
        }
        Signed { value, negative }
    }
}
