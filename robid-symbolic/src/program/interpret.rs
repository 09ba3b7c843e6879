//! The interpreter: runs a program on `f64` values, the reference that emitted
//! code is tested against and what the CLI uses for descriptions that are not
//! compiled in.

use super::{Instr, Program, Value};
use robid_runtime::Real;

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
                    Instr::Sign(a) => v(a).sign(),
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
