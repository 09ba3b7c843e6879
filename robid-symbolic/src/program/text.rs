//! The readable text form: one line per instruction, `t12 = t3 * MX4`.

use super::{Instr, Program, Value};
use std::fmt::{self, Write};

impl Program {
    /// How a value reads in the text form: `t3`, an input's symbol, or a literal.
    pub fn value_text(&self, v: Value) -> String {
        match v {
            Value::Temp(t) => format!("t{t}"),
            Value::Input(i) => self.input_name(i).to_owned(),
            Value::Const(c) => format!("{:?}", self.constants[c as usize]),
        }
    }

    /// The right-hand side of an instruction as text.
    pub fn instr_text(&self, instr: &Instr) -> String {
        let t = |v: Value| self.value_text(v);
        match *instr {
            Instr::Add(a, b) => format!("{} + {}", t(a), t(b)),
            Instr::Sub(a, b) => format!("{} - {}", t(a), t(b)),
            Instr::Mul(a, b) => format!("{} * {}", t(a), t(b)),
            Instr::Div(a, b) => format!("{} / {}", t(a), t(b)),
            Instr::Neg(a) => format!("-{}", t(a)),
            Instr::Sin(a) => format!("sin({})", t(a)),
            Instr::Cos(a) => format!("cos({})", t(a)),
            Instr::Sign(a) => format!("sign({})", t(a)),
            Instr::Sqrt(a) => format!("sqrt({})", t(a)),
        }
    }
}

impl fmt::Display for Program {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut header = String::new();
        for g in &self.inputs {
            let _ = write!(header, "input {}[{}]:", g.name, g.len());
            for e in &g.elements {
                let _ = write!(header, " {e}");
            }
            header.push('\n');
        }
        f.write_str(&header)?;
        writeln!(f, "# {}", self.operations())?;
        for (i, instr) in self.instrs.iter().enumerate() {
            writeln!(f, "t{i} = {}", self.instr_text(instr))?;
        }
        for o in &self.outputs {
            for (k, &v) in o.values.iter().enumerate() {
                writeln!(f, "{}[{k}] = {}", o.group.name, self.value_text(v))?;
            }
        }
        Ok(())
    }
}
