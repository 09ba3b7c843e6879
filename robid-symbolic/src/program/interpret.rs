//! The interpreter: runs a program on `f64` values, the reference that emitted
//! code is tested against and what the CLI uses for descriptions that are not
//! compiled in.

use super::{Group, Instr, Program, Value};

/// Inputs or outputs whose lengths do not match the program's groups.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{what} `{group}` has {found} values, the program expects {expected}")]
pub struct LengthError {
    /// `input` or `output`.
    pub what: &'static str,
    /// Name of the group.
    pub group: String,
    /// Length given.
    pub found: usize,
    /// Length expected.
    pub expected: usize,
}

impl Program {
    /// Runs the program: one slice per input group, one per output group.
    /// `temps` is scratch space reused between calls.
    pub fn run(
        &self,
        inputs: &[&[f64]],
        outputs: &mut [&mut [f64]],
        temps: &mut Vec<f64>,
    ) -> Result<(), LengthError> {
        check(
            "input",
            self.inputs.iter().map(|g| (&g.name, g.len())),
            inputs.iter().map(|s| s.len()),
        )?;
        check(
            "output",
            self.outputs.iter().map(|o| (&o.group.name, o.values.len())),
            outputs.iter().map(|s| s.len()),
        )?;
        let flat: Vec<f64> = inputs.iter().flat_map(|s| s.iter().copied()).collect();
        temps.clear();
        temps.reserve(self.instrs.len());
        for instr in &self.instrs {
            let x = {
                let v = |v: Value| match v {
                    Value::Temp(t) => temps[t as usize],
                    Value::Input(i) => flat[i as usize],
                    Value::Const(c) => self.constants[c as usize],
                };
                match *instr {
                    Instr::Add(a, b) => v(a) + v(b),
                    Instr::Sub(a, b) => v(a) - v(b),
                    Instr::Mul(a, b) => v(a) * v(b),
                    Instr::Div(a, b) => v(a) / v(b),
                    Instr::Neg(a) => -v(a),
                    Instr::Sin(a) => v(a).sin(),
                    Instr::Cos(a) => v(a).cos(),
                    Instr::Sign(a) => sign(v(a)),
                    Instr::Sqrt(a) => v(a).sqrt(),
                }
            };
            temps.push(x);
        }
        for (o, out) in self.outputs.iter().zip(outputs.iter_mut()) {
            for (slot, &v) in out.iter_mut().zip(&o.values) {
                *slot = match v {
                    Value::Temp(t) => temps[t as usize],
                    Value::Input(i) => flat[i as usize],
                    Value::Const(c) => self.constants[c as usize],
                };
            }
        }
        Ok(())
    }

    /// Runs the program and returns one vector per output group.
    pub fn eval(&self, inputs: &[&[f64]]) -> Result<Vec<Vec<f64>>, LengthError> {
        let mut outs: Vec<Vec<f64>> = self
            .outputs
            .iter()
            .map(|o| vec![0.0; o.values.len()])
            .collect();
        let mut slices: Vec<&mut [f64]> = outs.iter_mut().map(|v| v.as_mut_slice()).collect();
        self.run(inputs, &mut slices, &mut Vec::new())?;
        Ok(outs)
    }
}

fn check<'a>(
    what: &'static str,
    expected: impl Iterator<Item = (&'a String, usize)>,
    found: impl Iterator<Item = usize>,
) -> Result<(), LengthError> {
    let expected: Vec<_> = expected.collect();
    let found: Vec<usize> = found.collect();
    if found.len() != expected.len() {
        return Err(LengthError {
            what,
            group: format!("{} groups", what),
            found: found.len(),
            expected: expected.len(),
        });
    }
    for ((name, e), f) in expected.into_iter().zip(found) {
        if e != f {
            return Err(LengthError {
                what,
                group: name.clone(),
                found: f,
                expected: e,
            });
        }
    }
    Ok(())
}

/// The operation of one [`Compact`] instruction.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Op {
    Add,
    Sub,
    Mul,
    Div,
    Neg,
    Sin,
    Cos,
    Sign,
    Sqrt,
}

/// A program lowered for repeated interpretation: every operand is an index into one
/// register file `[inputs | bound inputs | constants | temporaries]`, so the loop reads
/// operands without matching on their kind, and a run allocates nothing once its register
/// buffer has grown. It computes the same operations in the same order as
/// [`Program::run`], so the results are the same to the bit (docs/performance.md#excitation).
#[derive(Clone, Debug, PartialEq)]
pub struct Compact {
    /// Operation, first and second operand register (the first again for one operand).
    ops: Vec<(Op, u32, u32)>,
    /// The input groups still passed to [`Compact::run`]: name and length.
    inputs: Vec<(String, usize)>,
    /// The bound input values, then the constants.
    fixed: Vec<f64>,
    /// Output groups: name and the register of each element.
    outputs: Vec<(String, Vec<u32>)>,
}

impl Program {
    /// The program lowered for repeated interpretation; the trailing input groups holding
    /// `bound.len()` elements take the values `bound` (e.g. geometric symbols) and are no
    /// longer passed to [`Compact::run`]. The error names the input groups when `bound`
    /// does not cover whole trailing groups.
    pub fn compact(&self, bound: &[f64]) -> Result<Compact, LengthError> {
        let mut free = self.inputs.len();
        let mut covered = 0;
        while covered < bound.len() && free > 0 {
            free -= 1;
            covered += self.inputs[free].len();
        }
        if covered != bound.len() {
            return Err(LengthError {
                what: "input",
                group: "bound trailing groups".into(),
                found: bound.len(),
                expected: covered,
            });
        }
        let input_count: usize = self.inputs.iter().map(Group::len).sum();
        let reg = |v: Value| -> u32 {
            match v {
                Value::Input(i) => i,
                Value::Const(c) => (input_count + c as usize) as u32,
                Value::Temp(t) => (input_count + self.constants.len()) as u32 + t,
            }
        };
        let ops = self
            .instrs
            .iter()
            .map(|instr| match *instr {
                Instr::Add(a, b) => (Op::Add, reg(a), reg(b)),
                Instr::Sub(a, b) => (Op::Sub, reg(a), reg(b)),
                Instr::Mul(a, b) => (Op::Mul, reg(a), reg(b)),
                Instr::Div(a, b) => (Op::Div, reg(a), reg(b)),
                Instr::Neg(a) => (Op::Neg, reg(a), reg(a)),
                Instr::Sin(a) => (Op::Sin, reg(a), reg(a)),
                Instr::Cos(a) => (Op::Cos, reg(a), reg(a)),
                Instr::Sign(a) => (Op::Sign, reg(a), reg(a)),
                Instr::Sqrt(a) => (Op::Sqrt, reg(a), reg(a)),
            })
            .collect();
        Ok(Compact {
            ops,
            inputs: self.inputs[..free]
                .iter()
                .map(|g| (g.name.clone(), g.len()))
                .collect(),
            fixed: bound.iter().chain(&self.constants).copied().collect(),
            outputs: self
                .outputs
                .iter()
                .map(|o| {
                    (
                        o.group.name.clone(),
                        o.values.iter().map(|&v| reg(v)).collect(),
                    )
                })
                .collect(),
        })
    }
}

impl Compact {
    /// Runs the program: one slice per input group that is not bound, one per output
    /// group. `registers` is scratch space reused between calls.
    pub fn run(
        &self,
        inputs: &[&[f64]],
        outputs: &mut [&mut [f64]],
        registers: &mut Vec<f64>,
    ) -> Result<(), LengthError> {
        check_groups(
            "input",
            self.inputs.iter().map(|(name, len)| (name, *len)),
            inputs.iter().map(|s| s.len()),
        )?;
        check_groups(
            "output",
            self.outputs.iter().map(|(name, regs)| (name, regs.len())),
            outputs.iter().map(|s| s.len()),
        )?;
        let r = registers;
        r.clear();
        r.reserve(
            self.fixed.len() + self.ops.len() + inputs.iter().map(|s| s.len()).sum::<usize>(),
        );
        for s in inputs {
            r.extend_from_slice(s);
        }
        r.extend_from_slice(&self.fixed);
        for &(op, a, b) in &self.ops {
            let (x, y) = (r[a as usize], r[b as usize]);
            r.push(match op {
                Op::Add => x + y,
                Op::Sub => x - y,
                Op::Mul => x * y,
                Op::Div => x / y,
                Op::Neg => -x,
                Op::Sin => x.sin(),
                Op::Cos => x.cos(),
                Op::Sign => sign(x),
                Op::Sqrt => x.sqrt(),
            });
        }
        for ((_, regs), out) in self.outputs.iter().zip(outputs.iter_mut()) {
            for (slot, &i) in out.iter_mut().zip(regs) {
                *slot = r[i as usize];
            }
        }
        Ok(())
    }
}

impl Compact {
    /// Runs the program on `lanes` argument sets at once, dispatching each operation once
    /// for all of them (the loop over the sets is what the compiler vectorises). Every
    /// input and output is lane-major: element `i` of set `l` is at `i * lanes + l`, so a
    /// group of `n` elements holds `n * lanes` values. Each set gets exactly the
    /// operations of [`Compact::run`], so its results are the same to the bit.
    ///
    /// # Errors
    /// A group whose length is not `lanes` times its element count, as [`Compact::run`]
    /// names it (with that product as the expected length); `lanes` = 0 is refused.
    pub fn run_lanes(
        &self,
        lanes: usize,
        inputs: &[&[f64]],
        outputs: &mut [&mut [f64]],
        registers: &mut Vec<f64>,
    ) -> Result<(), LengthError> {
        if lanes == 0 {
            return Err(LengthError {
                what: "input",
                group: "lanes".into(),
                found: 0,
                expected: 1,
            });
        }
        check_groups(
            "input",
            self.inputs.iter().map(|(name, len)| (name, *len * lanes)),
            inputs.iter().map(|s| s.len()),
        )?;
        check_groups(
            "output",
            self.outputs
                .iter()
                .map(|(name, regs)| (name, regs.len() * lanes)),
            outputs.iter().map(|s| s.len()),
        )?;
        let r = registers;
        r.clear();
        let first = inputs.iter().map(|s| s.len()).sum::<usize>() + self.fixed.len() * lanes;
        r.reserve(first + self.ops.len() * lanes);
        for s in inputs {
            r.extend_from_slice(s);
        }
        for &v in &self.fixed {
            r.extend(core::iter::repeat_n(v, lanes));
        }
        r.resize(first + self.ops.len() * lanes, 0.0);
        for (k, &(op, a, b)) in self.ops.iter().enumerate() {
            // operands always name earlier registers (the program is in order)
            let (done, next) = r.split_at_mut(first + k * lanes);
            let d = &mut next[..lanes];
            let x = &done[a as usize * lanes..][..lanes];
            let y = &done[b as usize * lanes..][..lanes];
            let unary = |d: &mut [f64], f: fn(f64) -> f64| {
                d.iter_mut().zip(x).for_each(|(d, &x)| *d = f(x));
            };
            let binary = |d: &mut [f64], f: fn(f64, f64) -> f64| {
                d.iter_mut()
                    .zip(x.iter().zip(y))
                    .for_each(|(d, (&x, &y))| *d = f(x, y));
            };
            match op {
                Op::Add => binary(d, |x, y| x + y),
                Op::Sub => binary(d, |x, y| x - y),
                Op::Mul => binary(d, |x, y| x * y),
                Op::Div => binary(d, |x, y| x / y),
                Op::Neg => unary(d, |x| -x),
                Op::Sin => unary(d, f64::sin),
                Op::Cos => unary(d, f64::cos),
                Op::Sign => unary(d, sign),
                Op::Sqrt => unary(d, f64::sqrt),
            }
        }
        for ((_, regs), out) in self.outputs.iter().zip(outputs.iter_mut()) {
            for (slot, &i) in out.chunks_exact_mut(lanes).zip(regs) {
                slot.copy_from_slice(&r[i as usize * lanes..][..lanes]);
            }
        }
        Ok(())
    }
}

/// [`check`] without allocating: group counts, then each group's length.
fn check_groups<'a>(
    what: &'static str,
    expected: impl Iterator<Item = (&'a String, usize)> + Clone,
    found: impl ExactSizeIterator<Item = usize>,
) -> Result<(), LengthError> {
    let count = expected.clone().count();
    if found.len() != count {
        return Err(LengthError {
            what,
            group: format!("{what} groups"),
            found: found.len(),
            expected: count,
        });
    }
    for ((name, e), f) in expected.zip(found) {
        if e != f {
            return Err(LengthError {
                what,
                group: name.clone(),
                found: f,
                expected: e,
            });
        }
    }
    Ok(())
}

/// Coulomb friction's sign as the emitted code computes it (`robid_runtime::Real::sign`):
/// -1, 0 or 1, with 0 at exactly zero (unlike `f64::signum`); the tests that compare the
/// emitted code with this interpreter hold the two to the same values.
fn sign(x: f64) -> f64 {
    if x > 0.0 {
        1.0
    } else if x < 0.0 {
        -1.0
    } else {
        0.0
    }
}

#[cfg(test)]
mod sign_tests {
    use super::sign;

    /// Zero at both zeros, as the emitted code's `Real::sign`: a joint at rest has no
    /// Coulomb torque.
    #[test]
    fn sign_is_zero_at_zero_and_unit_elsewhere() {
        assert_eq!(sign(0.0), 0.0);
        assert_eq!(sign(-0.0), 0.0);
        assert_eq!(sign(1e-300), 1.0);
        assert_eq!(sign(-2.5), -1.0);
    }
}
