//! Operation counts: what the program (and the code emitted from it) executes.

use super::{Instr, Program};
use std::fmt;

/// Number of operations of each kind. A subtraction counts as an addition.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Operations {
    /// Multiplications.
    pub mul: usize,
    /// Additions and subtractions.
    pub add: usize,
    /// Negations.
    pub neg: usize,
    /// Divisions.
    pub div: usize,
    /// Sines.
    pub sin: usize,
    /// Cosines.
    pub cos: usize,
    /// Signs (Coulomb friction).
    pub sign: usize,
    /// Square roots.
    pub sqrt: usize,
}

impl Operations {
    /// Floating-point operations in the usual sense: mul + add + neg (trigonometry not counted).
    pub fn flops(&self) -> usize {
        self.mul + self.add + self.neg
    }
}

impl fmt::Display for Operations {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} mul, {} add, {} neg", self.mul, self.add, self.neg)?;
        for (n, what) in [
            (self.div, "div"),
            (self.sin, "sin"),
            (self.cos, "cos"),
            (self.sign, "sign"),
            (self.sqrt, "sqrt"),
        ] {
            if n > 0 {
                write!(f, ", {n} {what}")?;
            }
        }
        Ok(())
    }
}

impl Program {
    /// The operation count.
    pub fn operations(&self) -> Operations {
        let mut ops = Operations::default();
        for instr in &self.instrs {
            match instr {
                Instr::Add(..) | Instr::Sub(..) => ops.add += 1,
                Instr::Mul(..) => ops.mul += 1,
                Instr::Div(..) => ops.div += 1,
                Instr::Neg(_) => ops.neg += 1,
                Instr::Sin(_) => ops.sin += 1,
                Instr::Cos(_) => ops.cos += 1,
                Instr::Sign(_) => ops.sign += 1,
                Instr::Sqrt(_) => ops.sqrt += 1,
            }
        }
        ops
    }
}
