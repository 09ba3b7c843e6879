//! Straight-line programs: the derived expressions as a list of binary
//! operations on temporaries, ready to be interpreted or emitted as code.
//!
//! A [`Program`] is built from a set of output expressions of one [`Arena`]
//! (`lower.rs`): each needed DAG node is computed once (common-subexpression
//! elimination comes from the hash-consing plus a memo of instructions),
//! negations are folded into subtractions, multiplications by 1 disappear,
//! instructions zero for every input or equal to an earlier one are folded
//! (`identities.rs`), and unused instructions are removed (`dce.rs`).
//! Temporaries are numbered in
//! the order they are computed, which follows the arena's topological order,
//! so the same derivation always gives the same program.
//!
//! The text form (`text.rs`) reads `t12 = t3 * MX4`, the operation count
//! (`count.rs`) counts exactly what the emitted code executes, and the
//! interpreter (`interpret.rs`) runs a program on `f64` slices.
//!
//! [`Arena`]: crate::expr::Arena

mod count;
mod customised;
mod dce;
mod factor;
mod identities;
mod interpret;
mod lower;
pub mod robot;
pub mod schedule;
mod share;
mod text;

#[cfg(test)]
mod tests;

pub use count::Operations;
pub use interpret::{Compact, LengthError};
pub use robot::{BaseParameter, DeriveError, RobotPrograms};

/// An operand: a temporary, an input element or a constant.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Value {
    /// The result of instruction `i` (`t{i}`).
    Temp(u32),
    /// Input element `i`, counted across all input groups in order.
    Input(u32),
    /// Constant `i` of [`Program::constants`].
    Const(u32),
}

/// One operation. `Sub(a, b)` is `a - b`, `Div(a, b)` is `a / b`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Instr {
    /// `a + b`.
    Add(Value, Value),
    /// `a - b`.
    Sub(Value, Value),
    /// `a * b`.
    Mul(Value, Value),
    /// `a / b`.
    Div(Value, Value),
    /// `-a`.
    Neg(Value),
    /// `sin(a)`.
    Sin(Value),
    /// `cos(a)`.
    Cos(Value),
    /// `sign(a)`: -1, 0 or 1.
    Sign(Value),
    /// `sqrt(a)`.
    Sqrt(Value),
}

impl Instr {
    /// The operands.
    pub fn operands(&self) -> Vec<Value> {
        match *self {
            Instr::Add(a, b) | Instr::Sub(a, b) | Instr::Mul(a, b) | Instr::Div(a, b) => {
                vec![a, b]
            }
            Instr::Neg(a) | Instr::Sin(a) | Instr::Cos(a) | Instr::Sign(a) | Instr::Sqrt(a) => {
                vec![a]
            }
        }
    }

    /// The same operation on operands passed through `f`.
    pub fn map(&self, mut f: impl FnMut(Value) -> Value) -> Instr {
        match *self {
            Instr::Add(a, b) => Instr::Add(f(a), f(b)),
            Instr::Sub(a, b) => Instr::Sub(f(a), f(b)),
            Instr::Mul(a, b) => Instr::Mul(f(a), f(b)),
            Instr::Div(a, b) => Instr::Div(f(a), f(b)),
            Instr::Neg(a) => Instr::Neg(f(a)),
            Instr::Sin(a) => Instr::Sin(f(a)),
            Instr::Cos(a) => Instr::Cos(f(a)),
            Instr::Sign(a) => Instr::Sign(f(a)),
            Instr::Sqrt(a) => Instr::Sqrt(f(a)),
        }
    }
}

/// A named group of inputs or outputs, e.g. `q` with elements `q1..q6`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Group {
    /// Name of the group (an argument or result name in emitted code).
    pub name: String,
    /// Names of the elements (for inputs: the symbol each element binds).
    pub elements: Vec<String>,
}

impl Group {
    /// A group named `name` with elements `element_names`.
    pub fn new(name: &str, elements: Vec<String>) -> Group {
        Group {
            name: name.to_owned(),
            elements,
        }
    }

    /// Number of elements.
    pub fn len(&self) -> usize {
        self.elements.len()
    }

    /// True when the group has no element.
    pub fn is_empty(&self) -> bool {
        self.elements.is_empty()
    }
}

/// An output group and the value of each of its elements.
#[derive(Clone, Debug, PartialEq)]
pub struct Output {
    /// Name and element names.
    pub group: Group,
    /// The value of each element.
    pub values: Vec<Value>,
}

/// A program could not be built.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ProgramError {
    /// An output depends on a symbol that is not among the inputs.
    #[error("an output depends on symbol `{0}`, which is not an input; add it to an input group")]
    Unbound(String),
}

/// A straight-line program: inputs, constants, instructions, outputs.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Program {
    /// Input groups; `Value::Input(i)` counts their elements in order.
    pub inputs: Vec<Group>,
    /// Constants (finite), `Value::Const(i)`.
    pub constants: Vec<f64>,
    /// Instructions; instruction `i` defines `Value::Temp(i)` and uses only earlier temporaries.
    pub instrs: Vec<Instr>,
    /// Output groups.
    pub outputs: Vec<Output>,
}

impl Program {
    /// The input group and element index of flat input `index`.
    pub fn input_position(&self, index: u32) -> (usize, usize) {
        let mut rest = index as usize;
        for (g, group) in self.inputs.iter().enumerate() {
            if rest < group.len() {
                return (g, rest);
            }
            rest -= group.len();
        }
        panic!("input {index} out of range")
    }

    /// Total number of input elements.
    pub fn input_len(&self) -> usize {
        self.inputs.iter().map(Group::len).sum()
    }

    /// The name of flat input `index` (the symbol it binds).
    pub fn input_name(&self, index: u32) -> &str {
        let (g, i) = self.input_position(index);
        &self.inputs[g].elements[i]
    }

    /// True when some instruction or output reads input group `group`.
    pub fn uses_input_group(&self, group: usize) -> bool {
        let reads = |v: Value| matches!(v, Value::Input(i) if self.input_position(i).0 == group);
        self.instrs
            .iter()
            .any(|ins| ins.operands().into_iter().any(reads))
            || self
                .outputs
                .iter()
                .any(|o| o.values.iter().any(|&v| reads(v)))
    }
}
