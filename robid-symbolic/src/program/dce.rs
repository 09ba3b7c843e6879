//! Dead-code removal: keeps the instructions the outputs need and renumbers
//! temporaries and constants in their original (topological) order.

use super::{Program, Value};

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
