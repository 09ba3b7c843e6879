//! Dead-code removal: keeps the instructions the outputs need and renumbers
//! temporaries and constants in their original (topological) order; and the merging
//! of instructions that compute the same operation on the same operands.

use super::factor::{mapped, mapped_outputs};
use super::{Instr, Program, Value};
use rustc_hash::FxHashMap;

/// The program with each instruction that repeats an earlier one (the same operation
/// on the same operands, commutative ones in either order) replaced by that one, dead
/// code removed. The lowering's memo merges these as it writes them; a pass that
/// rewrites sums afterwards (`factor.rs`) can write one again.
pub(super) fn merge_identical(program: Program) -> Program {
    let mut seen: FxHashMap<Instr, Value> = FxHashMap::default();
    let mut map: Vec<Value> = Vec::with_capacity(program.instrs.len());
    let mut merged = false;
    for (t, instr) in program.instrs.iter().enumerate() {
        let key = match instr.map(|v| mapped(&map, v)) {
            Instr::Add(a, b) if b < a => Instr::Add(b, a),
            Instr::Mul(a, b) if b < a => Instr::Mul(b, a),
            other => other,
        };
        let value = *seen.entry(key).or_insert(Value::Temp(t as u32));
        merged |= value != Value::Temp(t as u32);
        map.push(value);
    }
    if !merged {
        return program;
    }
    let instrs = program
        .instrs
        .iter()
        .map(|i| i.map(|v| mapped(&map, v)))
        .collect();
    let outputs = mapped_outputs(&program.outputs, &map);
    remove_dead_code(Program {
        inputs: program.inputs,
        constants: program.constants,
        instrs,
        outputs,
    })
}

/// The program without unused instructions and constants.
pub(super) fn remove_dead_code(program: Program) -> Program {
    let mut live = vec![false; program.instrs.len()];
    let mut stack: Vec<usize> = Vec::new();
    let mark = |v: Value, live: &mut Vec<bool>, stack: &mut Vec<usize>| {
        if let Value::Temp(t) = v
            && !std::mem::replace(&mut live[t as usize], true)
        {
            stack.push(t as usize);
        }
    };
    for o in &program.outputs {
        for &v in &o.values {
            mark(v, &mut live, &mut stack);
        }
    }
    while let Some(t) = stack.pop() {
        for v in program.instrs[t].operands() {
            mark(v, &mut live, &mut stack);
        }
    }
    let mut temp_map = vec![u32::MAX; program.instrs.len()];
    let mut const_map = vec![u32::MAX; program.constants.len()];
    let mut constants = Vec::new();
    let mut renumber = |v: Value, temp_map: &[u32]| match v {
        Value::Temp(t) => Value::Temp(temp_map[t as usize]),
        Value::Const(c) => {
            if const_map[c as usize] == u32::MAX {
                const_map[c as usize] = constants.len() as u32;
                constants.push(program.constants[c as usize]);
            }
            Value::Const(const_map[c as usize])
        }
        input => input,
    };
    let mut instrs = Vec::new();
    for (t, instr) in program.instrs.iter().enumerate() {
        if live[t] {
            temp_map[t] = instrs.len() as u32;
            instrs.push(instr.map(|v| renumber(v, &temp_map)));
        }
    }
    let outputs = program
        .outputs
        .iter()
        .map(|o| super::Output {
            group: o.group.clone(),
            values: o.values.iter().map(|&v| renumber(v, &temp_map)).collect(),
        })
        .collect();
    Program {
        inputs: program.inputs,
        constants,
        instrs,
        outputs,
    }
}

#[cfg(test)]
mod tests {
    use super::super::{Group, Instr, Output, Program, Value};

    /// `a + b` written twice (once as `b + a`) and `a * b` twice become one each, and
    /// what read the second reads the first; a program without repeats is unchanged.
    #[test]
    fn repeated_instructions_are_merged() {
        let (a, b) = (Value::Input(0), Value::Input(1));
        let t = Value::Temp;
        let program = Program {
            inputs: vec![Group::new("x", vec!["a".into(), "b".into()])],
            constants: vec![],
            instrs: vec![
                Instr::Add(a, b),
                Instr::Mul(a, b),
                Instr::Add(b, a),
                Instr::Mul(t(0), t(1)),
                Instr::Mul(t(2), b),
                Instr::Sub(t(3), t(4)),
                Instr::Mul(t(2), t(1)),
            ],
            outputs: vec![Output {
                group: Group::new("out", vec!["o0".into(), "o1".into()]),
                values: vec![t(5), t(6)],
            }],
        };
        let merged = super::merge_identical(program.clone());
        assert_eq!(
            merged.instrs,
            vec![
                Instr::Add(a, b),
                Instr::Mul(a, b),
                Instr::Mul(t(0), t(1)),
                Instr::Mul(t(0), b),
                Instr::Sub(t(2), t(3)),
            ]
        );
        assert_eq!(merged.outputs[0].values, vec![t(4), t(2)]);
        let input = [1.5, -0.7];
        assert_eq!(program.eval(&[&input]), merged.eval(&[&input]));
        assert_eq!(super::merge_identical(merged.clone()), merged);
    }
}
