//! Products folded into the sums that use them: `t = a * b; u = t + c` is emitted as
//! `u = T::mul_add(a, b, c)`.
//!
//! `robid_runtime::Real::mul_add` rounds once where the build
//! targets a fused multiply-add instruction (x86-64 with `fma`, AArch64) and computes
//! `a * b + c` elsewhere, so without that instruction the code gives the same values to
//! the bit as the unfused one. With it, one instruction replaces two and the chain of
//! dependent operations is shorter (the UR5e's inverse dynamics 81 -> 70 ns with
//! `target-cpu=native`, docs/performance.md#fused-multiply-adds). Rust never fuses
//! operations on its own, so the emitter says where.
//!
//! A product is folded when the sum or difference is its only use (not an output) and
//! both are emitted at the same place (the trigonometric batch's hoisting, `trig.rs`).
//! The operation counts are those of the program: a fused multiply-add is still one
//! multiplication and one addition.

use super::trig::Role;
use crate::program::{Instr, Program, Value};

/// How an addition or subtraction takes in the product it absorbs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Fused {
    /// `a * b + c` (either order of the sum).
    Plus { a: Value, b: Value, c: Value },
    /// `a * b - c`.
    Minus { a: Value, b: Value, c: Value },
    /// `c - a * b`, written `mul_add(-a, b, c)` (negation is exact).
    From { a: Value, b: Value, c: Value },
}

/// Per instruction of a program: the product an addition absorbs, and whether a
/// product is absorbed (so not emitted on its own).
#[derive(Debug)]
pub(super) struct Fusion {
    pub(super) fused: Vec<Option<Fused>>,
    pub(super) absorbed: Vec<bool>,
}

impl Fusion {
    /// The products of `program` to fold, given each instruction's `role` in the
    /// emitted order.
    pub(super) fn new(program: &Program, role: &[Role]) -> Self {
        let n = program.instrs.len();
        let mut uses = vec![0usize; n];
        let operands = program.instrs.iter().flat_map(Instr::operands);
        let outputs = program
            .outputs
            .iter()
            .flat_map(|o| o.values.iter().copied());
        for v in operands.chain(outputs) {
            if let Value::Temp(t) = v {
                uses[t as usize] += 1;
            }
        }
        let mut fusion = Fusion {
            fused: vec![None; n],
            absorbed: vec![false; n],
        };
        for (i, instr) in program.instrs.iter().enumerate() {
            // a product that can be folded into instruction i: its only use, emitted
            // in the same place, not already folded elsewhere
            let product = |v: Value| match v {
                Value::Temp(t)
                    if uses[t as usize] == 1
                        && role[t as usize] == role[i]
                        && role[i] != Role::Batched =>
                {
                    match program.instrs[t as usize] {
                        Instr::Mul(a, b) => Some((t as usize, a, b)),
                        _ => None,
                    }
                }
                _ => None,
            };
            // of two products, fold the later one, so the earlier can be computed
            // while the later's operands are still being made
            let later =
                |x: Option<(usize, Value, Value)>, y: Option<(usize, Value, Value)>| match (x, y) {
                    (Some(p), Some(q)) => Some(if q.0 > p.0 { (q, false) } else { (p, true) }),
                    (Some(p), None) => Some((p, true)),
                    (None, Some(q)) => Some((q, false)),
                    (None, None) => None,
                };
            let choice = match *instr {
                Instr::Add(x, y) => later(product(x), product(y)).map(|((t, a, b), first)| {
                    let c = if first { y } else { x };
                    (t, Fused::Plus { a, b, c })
                }),
                Instr::Sub(x, y) => later(product(x), product(y)).map(|((t, a, b), first)| {
                    if first {
                        (t, Fused::Minus { a, b, c: y })
                    } else {
                        (t, Fused::From { a, b, c: x })
                    }
                }),
                _ => None,
            };
            if let Some((t, f)) = choice {
                fusion.fused[i] = Some(f);
                fusion.absorbed[t] = true;
            }
        }
        fusion
    }
}

#[cfg(test)]
mod tests {
    use super::{Fused, Fusion};
    use crate::emit::trig::Role;
    use crate::program::{Group, Instr, Output, Program, Value};

    fn program(instrs: Vec<Instr>, values: Vec<Value>) -> Program {
        let names = |n: usize| (0..n).map(|k| format!("x{k}")).collect();
        Program {
            inputs: vec![Group::new("x", names(4))],
            constants: vec![],
            instrs,
            outputs: vec![Output {
                group: Group::new("y", names(values.len())),
                values,
            }],
        }
    }

    const X: [Value; 4] = [
        Value::Input(0),
        Value::Input(1),
        Value::Input(2),
        Value::Input(3),
    ];

    /// Each form of sum takes its product in, with the operands in place.
    #[test]
    fn sums_and_differences_absorb_their_only_products() {
        let [a, b, c, _] = X;
        for (instr, want) in [
            (Instr::Add(Value::Temp(0), c), Fused::Plus { a, b, c }),
            (Instr::Add(c, Value::Temp(0)), Fused::Plus { a, b, c }),
            (Instr::Sub(Value::Temp(0), c), Fused::Minus { a, b, c }),
            (Instr::Sub(c, Value::Temp(0)), Fused::From { a, b, c }),
        ] {
            let p = program(vec![Instr::Mul(a, b), instr], vec![Value::Temp(1)]);
            let f = Fusion::new(&p, &[Role::InOrder; 2]);
            assert_eq!(f.fused, vec![None, Some(want)]);
            assert_eq!(f.absorbed, vec![true, false]);
        }
    }

    /// A product with another use, an output, a product in another place of the
    /// emitted order, and a sum of two non-products are left as they are.
    #[test]
    fn products_with_other_uses_stay() {
        let [a, b, c, _] = X;
        let used_twice = program(
            vec![
                Instr::Mul(a, b),
                Instr::Add(Value::Temp(0), c),
                Instr::Sub(Value::Temp(0), c),
            ],
            vec![Value::Temp(1), Value::Temp(2)],
        );
        let an_output = program(
            vec![Instr::Mul(a, b), Instr::Add(Value::Temp(0), c)],
            vec![Value::Temp(0), Value::Temp(1)],
        );
        let sum = program(
            vec![Instr::Add(a, b), Instr::Add(Value::Temp(0), c)],
            vec![Value::Temp(1)],
        );
        for p in [&used_twice, &an_output, &sum] {
            let f = Fusion::new(p, &vec![Role::InOrder; p.instrs.len()]);
            assert!(f.fused.iter().all(Option::is_none), "{p:?}");
            assert!(!f.absorbed.iter().any(|&x| x));
        }
        let hoisted = Fusion::new(&an_output, &[Role::Hoisted, Role::InOrder]);
        assert!(hoisted.fused.iter().all(Option::is_none));
    }

    /// Of two products, the later one is folded and the earlier stays a product.
    #[test]
    fn the_later_of_two_products_is_folded() {
        let [a, b, c, d] = X;
        let p = program(
            vec![
                Instr::Mul(a, b),
                Instr::Mul(c, d),
                Instr::Sub(Value::Temp(0), Value::Temp(1)),
            ],
            vec![Value::Temp(2)],
        );
        let f = Fusion::new(&p, &[Role::InOrder; 3]);
        assert_eq!(
            f.fused[2],
            Some(Fused::From {
                a: c,
                b: d,
                c: Value::Temp(0)
            })
        );
        assert_eq!(f.absorbed, vec![false, true, false]);
    }
}
