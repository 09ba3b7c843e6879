//! The sines and cosines of a program, computed together in one call at the top of the
//! emitted function (`T::sin_cos_array`, vectorised for `f64` on x86-64 with AVX2).
//!
//! Every angle whose value does not itself need a sine or cosine is batched: a joint
//! variable, a constant, or a temporary computed from them (a joint angle plus an offset
//! the simplifier could not fold, a sum of two joint angles). The instructions computing
//! such temporaries are hoisted before the call, in program order; an angle that depends
//! on another sine or cosine (none of the reference robots has one) keeps its
//! `x.sin_cos()` where the program first needs it.

use crate::program::{Instr, Program, Value};

/// What the emitter does with one instruction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Role {
    /// Emitted in program order after the batch.
    InOrder,
    /// Computes (part of) a batched angle: emitted before the batch, in program order.
    Hoisted,
    /// The sine or cosine of batched angle `angle`, bound by the batch call.
    Batched,
    /// The same sine or cosine as the earlier instruction `of` (programs built by hand):
    /// a copy of it after the batch.
    Copy { of: usize },
}

/// The plan of a program's trigonometry.
#[derive(Debug)]
pub(super) struct TrigBatch {
    /// The batched angles, in order of first use.
    pub(super) angles: Vec<Value>,
    /// Per angle, the instruction whose result is its sine, if the program needs it.
    pub(super) sin: Vec<Option<usize>>,
    /// Per angle, the instruction whose result is its cosine, if the program needs it.
    pub(super) cos: Vec<Option<usize>>,
    /// Per instruction.
    pub(super) role: Vec<Role>,
}

impl TrigBatch {
    pub(super) fn new(program: &Program) -> Self {
        let n = program.instrs.len();
        let is_trig = |i: &Instr| matches!(i, Instr::Sin(_) | Instr::Cos(_));
        // Whether an instruction's value needs a sine or cosine (its own or upstream).
        let mut needs_trig = vec![false; n];
        for (i, instr) in program.instrs.iter().enumerate() {
            needs_trig[i] = is_trig(instr)
                || instr.operands().into_iter().any(|v| match v {
                    Value::Temp(t) => needs_trig[t as usize],
                    _ => false,
                });
        }
        let batchable = |x: Value| match x {
            Value::Temp(t) => !needs_trig[t as usize],
            Value::Input(_) | Value::Const(_) => true,
        };
        let mut batch = TrigBatch {
            angles: Vec::new(),
            sin: Vec::new(),
            cos: Vec::new(),
            role: vec![Role::InOrder; n],
        };
        for (i, instr) in program.instrs.iter().enumerate() {
            let (x, is_sin) = match *instr {
                Instr::Sin(x) => (x, true),
                Instr::Cos(x) => (x, false),
                _ => continue,
            };
            if !batchable(x) {
                continue;
            }
            let a = match batch.angles.iter().position(|&y| y == x) {
                Some(a) => a,
                None => {
                    batch.angles.push(x);
                    batch.sin.push(None);
                    batch.cos.push(None);
                    batch.angles.len() - 1
                }
            };
            let slot = if is_sin {
                &mut batch.sin[a]
            } else {
                &mut batch.cos[a]
            };
            batch.role[i] = match *slot {
                Some(of) => Role::Copy { of },
                None => {
                    *slot = Some(i);
                    Role::Batched
                }
            };
        }
        batch.order_by_first_use(program);
        // The instructions the batched angles are computed from.
        let mut stack: Vec<u32> = batch
            .angles
            .iter()
            .filter_map(|&x| match x {
                Value::Temp(t) => Some(t),
                _ => None,
            })
            .collect();
        while let Some(t) = stack.pop() {
            let t = t as usize;
            if batch.role[t] == Role::Hoisted {
                continue;
            }
            batch.role[t] = Role::Hoisted;
            for v in program.instrs[t].operands() {
                if let Value::Temp(u) = v {
                    stack.push(u);
                }
            }
        }
        batch
    }
}

impl TrigBatch {
    /// Puts the angles in the order the arithmetic first needs their sine or cosine (ties
    /// and unused ones in the order found): the batch evaluates them in that order, so
    /// that a program whose first steps need the last joint's angle (the mass matrix's
    /// backward recursion) does not wait for every other angle's sine and cosine first.
    fn order_by_first_use(&mut self, program: &Program) {
        // the angle whose sine or cosine each instruction gives (a copy's as its source's)
        let mut angle_of: Vec<Option<usize>> = vec![None; program.instrs.len()];
        for (a, (s, c)) in self.sin.iter().zip(&self.cos).enumerate() {
            for i in [s, c].into_iter().flatten() {
                angle_of[*i] = Some(a);
            }
        }
        let mut first_use = vec![usize::MAX; self.angles.len()];
        for (j, instr) in program.instrs.iter().enumerate() {
            match self.role[j] {
                Role::Copy { of } => angle_of[j] = angle_of[of],
                Role::InOrder => {
                    for v in instr.operands() {
                        if let Value::Temp(t) = v
                            && let Some(a) = angle_of[t as usize]
                        {
                            first_use[a] = first_use[a].min(j);
                        }
                    }
                }
                Role::Hoisted | Role::Batched => {}
            }
        }
        let mut order: Vec<usize> = (0..self.angles.len()).collect();
        order.sort_by_key(|&a| first_use[a]);
        self.angles = order.iter().map(|&a| self.angles[a]).collect();
        self.sin = order.iter().map(|&a| self.sin[a]).collect();
        self.cos = order.iter().map(|&a| self.cos[a]).collect();
    }
}

#[cfg(test)]
mod tests {
    use super::{Role, TrigBatch};
    use crate::program::{Instr, Program, Value};

    fn program(instrs: Vec<Instr>) -> Program {
        Program {
            instrs,
            ..Program::default()
        }
    }

    /// The batch takes the angles in the order the arithmetic first needs them: here the
    /// third angle's cosine, then the second's sine (through a copy), then the first's.
    #[test]
    fn angles_are_batched_in_the_order_they_are_first_needed() {
        let (q1, q2, q3) = (Value::Input(0), Value::Input(1), Value::Input(2));
        let p = program(vec![
            Instr::Sin(q1),                             // t0
            Instr::Sin(q2),                             // t1
            Instr::Cos(q3),                             // t2
            Instr::Mul(Value::Temp(2), q1),             // t3: needs q3
            Instr::Sin(q2),                             // t4: a copy of t1
            Instr::Add(Value::Temp(3), Value::Temp(4)), // t5: needs q2
            Instr::Add(Value::Temp(5), Value::Temp(0)), // t6: needs q1
        ]);
        let b = TrigBatch::new(&p);
        assert_eq!(b.angles, vec![q3, q2, q1]);
        assert_eq!(b.sin, vec![None, Some(1), Some(0)]);
        assert_eq!(b.cos, vec![Some(2), None, None]);
    }

    /// Inputs, constants and temporaries computed without trigonometry are batched (the
    /// temporaries' instructions hoisted); an angle computed from a sine is not; a second
    /// sine of the same angle becomes a copy.
    #[test]
    fn batches_the_angles_that_need_no_trigonometry() {
        let (q1, q2, c0) = (Value::Input(0), Value::Input(1), Value::Const(0));
        let p = program(vec![
            Instr::Mul(q1, q2),             // t0: hoisted
            Instr::Add(Value::Temp(0), c0), // t1 = q1 q2 + c0: hoisted, an angle
            Instr::Sin(q1),                 // t2
            Instr::Mul(q2, q2),             // t3: in order
            Instr::Cos(Value::Temp(1)),     // t4
            Instr::Cos(q1),                 // t5
            Instr::Sin(Value::Temp(2)),     // t6 = sin(sin(q1)): in order
            Instr::Sin(q1),                 // t7 = t2
            Instr::Sin(c0),                 // t8
            Instr::Add(Value::Temp(2), q2), // t9: in order
            Instr::Cos(Value::Temp(9)),     // t10: in order (needs t2)
        ]);
        let b = TrigBatch::new(&p);
        assert_eq!(b.angles, vec![q1, Value::Temp(1), c0]);
        assert_eq!(b.sin, vec![Some(2), None, Some(8)]);
        assert_eq!(b.cos, vec![Some(5), Some(4), None]);
        use Role::*;
        assert_eq!(
            b.role,
            vec![
                Hoisted,
                Hoisted,
                Batched,
                InOrder,
                Batched,
                Batched,
                InOrder,
                Copy { of: 2 },
                Batched,
                InOrder,
                InOrder,
            ]
        );
    }
}
