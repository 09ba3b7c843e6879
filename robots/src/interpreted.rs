//! A robot model for any description file: robid-symbolic derives its programs at run
//! time and [`Interpreted`] runs them behind [`robid_runtime::Model`]; [`model_for`]
//! picks the compiled model instead when the text is a reference description.
//!
//! ```
//! use robid_runtime::Model;
//! let text = include_str!("../descriptions/ur5e.toml");
//! let robot = robid_symbolic::Robot::from_toml(text, "ur5e.toml").unwrap();
//! let chosen = robots::interpreted::model_for(&robot, text).unwrap();
//! assert!(chosen.compiled);
//! assert_eq!(chosen.model.dof(), 6);
//! ```

use std::cell::RefCell;

use robid_runtime::Model;
use robid_symbolic::Robot;
use robid_symbolic::program::{BaseParameter, DeriveError, Program, RobotPrograms};

use crate::models::{Lwr4, Panda, Puma560, Rx90, Stanford, Tx40, Ur5e};

/// A description could not be turned into a model.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ModelError {
    /// The derivation (regrouping or program building) failed.
    #[error("robot `{robot}`: cannot derive its model: {source}")]
    Derive {
        /// Robot name.
        robot: String,
        /// What the derivation reported.
        source: DeriveError,
    },
    /// A geometric symbol has no value, so the model cannot be evaluated numerically.
    #[error(
        "robot `{robot}`: geometric symbol `{symbol}` has no value; give it one in the description's [symbols] table"
    )]
    UnboundSymbol {
        /// Robot name.
        robot: String,
        /// The symbol.
        symbol: String,
    },
}

/// A derived robot whose programs are run by robid-symbolic's interpreter.
#[derive(Debug, Clone)]
pub struct Interpreted {
    programs: RobotPrograms,
    geometry: Vec<f64>,
}

thread_local! {
    /// Scratch temporaries of the interpreter, one buffer per thread.
    static TEMPS: RefCell<Vec<f64>> = const { RefCell::new(Vec::new()) };
}

impl Interpreted {
    /// Derives `robot`'s programs (geometric symbols at their description values).
    pub fn new(robot: &Robot) -> Result<Self, ModelError> {
        let programs = RobotPrograms::derive(robot).map_err(|source| ModelError::Derive {
            robot: robot.name().to_owned(),
            source,
        })?;
        Self::from_programs(programs)
    }

    /// Wraps programs that are already derived.
    pub fn from_programs(programs: RobotPrograms) -> Result<Self, ModelError> {
        let geometry = programs
            .geometry
            .iter()
            .map(|(s, v)| {
                v.ok_or_else(|| ModelError::UnboundSymbol {
                    robot: programs.robot.name().to_owned(),
                    symbol: s.clone(),
                })
            })
            .collect::<Result<_, _>>()?;
        Ok(Self { programs, geometry })
    }

    /// The derived programs (names and expressions of the parameters included).
    pub fn programs(&self) -> &RobotPrograms {
        &self.programs
    }

    /// Runs `p`; on a length mismatch the output is filled with NaN, which the
    /// pipeline reports as a non-finite observation instead of a wrong result.
    fn run(&self, p: &Program, inputs: &[&[f64]], out: &mut [f64]) {
        let mut all: Vec<&[f64]> = inputs.to_vec();
        if !self.geometry.is_empty() {
            all.push(&self.geometry);
        }
        let ok = TEMPS.with(|t| p.run(&all, &mut [&mut *out], &mut t.borrow_mut()).is_ok());
        if !ok {
            out.iter_mut().for_each(|v| *v = f64::NAN);
        }
    }
}

impl Model for Interpreted {
    fn name(&self) -> &str {
        self.programs.robot.name()
    }
    fn dof(&self) -> usize {
        self.programs.robot.dof()
    }
    fn standard_parameter_count(&self) -> usize {
        self.programs.standard.len()
    }
    fn standard_parameter_name(&self, index: usize) -> &str {
        &self.programs.standard[index]
    }
    fn base_parameter_count(&self) -> usize {
        self.programs.base.len()
    }
    fn base_parameter_name(&self, index: usize) -> &str {
        &self.programs.base[index].name
    }
    fn base_regressor(&self, q: &[f64], qd: &[f64], qdd: &[f64], out: &mut [f64]) {
        self.run(&self.programs.base_regressor, &[q, qd, qdd], out);
    }
    fn standard_regressor(&self, q: &[f64], qd: &[f64], qdd: &[f64], out: &mut [f64]) {
        self.run(&self.programs.standard_regressor, &[q, qd, qdd], out);
    }
    fn inverse_dynamics(&self, q: &[f64], qd: &[f64], qdd: &[f64], base: &[f64], tau: &mut [f64]) {
        self.run(&self.programs.inverse_dynamics, &[q, qd, qdd, base], tau);
    }
    fn mass_matrix(&self, q: &[f64], base: &[f64], out: &mut [f64]) {
        self.run(&self.programs.mass_matrix, &[q, base], out);
    }
    fn gravity(&self, q: &[f64], base: &[f64], out: &mut [f64]) {
        self.run(&self.programs.gravity, &[q, base], out);
    }
    fn coriolis(&self, q: &[f64], qd: &[f64], base: &[f64], out: &mut [f64]) {
        self.run(&self.programs.coriolis, &[q, qd, base], out);
    }
    fn base_from_standard(&self, standard: &[f64], base: &mut [f64]) {
        self.run(&self.programs.base_from_standard, &[standard], base);
    }
}

/// The model chosen for a description, with its parameter names and expressions.
pub struct Chosen {
    /// The model (compiled or interpreted).
    pub model: Box<dyn Model + Send + Sync>,
    /// True when the compiled reference model was chosen.
    pub compiled: bool,
    /// Base parameters with their expressions in the standard parameters.
    pub base: Vec<BaseParameter>,
    /// Standard parameter names, in column order.
    pub standard: Vec<String>,
}

impl std::fmt::Debug for Chosen {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Chosen")
            .field("robot", &self.model.name())
            .field("compiled", &self.compiled)
            .field("base", &self.base.len())
            .finish()
    }
}

impl Chosen {
    /// The expression of the base parameter `name` (None for extra columns).
    pub fn expression(&self, name: &str) -> Option<String> {
        self.base
            .iter()
            .find(|b| b.name == name)
            .map(|b| b.expression.clone())
    }
}

/// The text of each reference description and its compiled model (`default()` because a
/// model with geometric symbols is not a unit struct).
#[allow(clippy::default_constructed_unit_structs)]
fn compiled(text: &str) -> Option<Box<dyn Model + Send + Sync>> {
    let same = |reference: &str| reference.trim() == text.trim();
    Some(if same(include_str!("../descriptions/ur5e.toml")) {
        Box::new(Ur5e::default())
    } else if same(include_str!("../descriptions/puma560.toml")) {
        Box::new(Puma560::default())
    } else if same(include_str!("../descriptions/rx90.toml")) {
        Box::new(Rx90::default())
    } else if same(include_str!("../descriptions/tx40.toml")) {
        Box::new(Tx40::default())
    } else if same(include_str!("../descriptions/lwr4.toml")) {
        Box::new(Lwr4::default())
    } else if same(include_str!("../descriptions/panda.toml")) {
        Box::new(Panda::default())
    } else if same(include_str!("../descriptions/stanford.toml")) {
        Box::new(Stanford::default())
    } else {
        return None;
    })
}

/// The model of `robot`, parsed from `text`: the compiled reference model when `text`
/// is a reference description, else the interpreter. The derivation (for the names and
/// expressions) runs in both cases.
pub fn model_for(robot: &Robot, text: &str) -> Result<Chosen, ModelError> {
    let programs = RobotPrograms::derive(robot).map_err(|source| ModelError::Derive {
        robot: robot.name().to_owned(),
        source,
    })?;
    let base = programs.base.clone();
    let standard = programs.standard.clone();
    let (model, compiled): (Box<dyn Model + Send + Sync>, bool) = match compiled(text) {
        Some(m) if m.base_parameter_count() == base.len() => (m, true),
        _ => (Box::new(Interpreted::from_programs(programs)?), false),
    };
    Ok(Chosen {
        model,
        compiled,
        base,
        standard,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interpreted_equals_compiled() {
        let text = include_str!("../descriptions/tx40.toml");
        let robot = Robot::from_toml(text, "tx40.toml").unwrap();
        let i = Interpreted::new(&robot).unwrap();
        let c = Tx40;
        let (q, qd, qdd) = (
            [0.1, -0.4, 0.7, 1.1, -0.3, 0.2],
            [0.5, 0.2, -0.3, 0.8, 1.0, -1.2],
            [1.0, -2.0, 0.4, 0.3, -0.6, 2.0],
        );
        let p = Model::base_parameter_count(&c);
        let (mut a, mut b) = (vec![0.0; 6 * p], vec![0.0; 6 * p]);
        i.base_regressor(&q, &qd, &qdd, &mut a);
        Model::base_regressor(&c, &q, &qd, &qdd, &mut b);
        for (x, y) in a.iter().zip(&b) {
            assert!((x - y).abs() < 1e-9 * (1.0 + y.abs()));
        }
        let mut short = vec![0.0; 3];
        i.gravity(&q[..2], &vec![0.0; p], &mut short);
        assert!(short.iter().all(|v| v.is_nan()));
    }

    #[test]
    fn reference_text_chooses_the_compiled_model() {
        let text = include_str!("../descriptions/tx40.toml");
        let robot = Robot::from_toml(text, "tx40.toml").unwrap();
        assert!(model_for(&robot, text).unwrap().compiled);
        let edited = format!("{text}\n# a comment\ndrive = [\"Fv\"]\n");
        let robot = Robot::from_toml(&edited, "edited.toml");
        // a top-level key after a table belongs to the table; either way not compiled
        if let Ok(robot) = robot {
            assert!(!model_for(&robot, &edited).unwrap().compiled);
        }
    }
}
