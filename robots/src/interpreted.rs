//! A robot model for any description file: robid-symbolic derives its programs at run
//! time and [`Interpreted`] runs them behind [`robid_runtime::Model`]; [`model_for`]
//! picks the compiled model instead when the robot is a reference robot.
//!
//! ```
//! use robid_runtime::Model;
//! let text = include_str!("../descriptions/ur5e.toml");
//! let robot = robid_symbolic::Robot::from_toml(text, "ur5e.toml").unwrap();
//! let chosen = robots::interpreted::model_for(&robot).unwrap();
//! assert!(chosen.compiled);
//! assert_eq!(chosen.model.dof(), 6);
//! ```

use std::cell::RefCell;

use robid_runtime::Model;
use robid_runtime::model::{LengthError, PROGRAMS, ProgramKind, check_arguments, check_lanes};
use robid_symbolic::Robot;
use robid_symbolic::program::{BaseParameter, Compact, DeriveError, RobotPrograms};

use crate::models::Reference;

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
        "{place}robot `{robot}`: geometric symbol `{symbol}`{used} has no value; give it one in the description's [symbols] table (`{symbol} = {}`, in {unit})",
        example(unit)
    )]
    UnboundSymbol {
        /// Where the description file first uses it, as `file:line:column: `
        /// (`Robot::symbol_place`), or nothing for a robot built in code.
        place: String,
        /// Robot name.
        robot: String,
        /// The symbol.
        symbol: String,
        /// Where the description uses it, as ` (joint 2's `d`)`, or nothing.
        used: String,
        /// Its unit, by the value that first uses it: `m` (a DH length, a `xyz`), `rad` (a
        /// DH angle, a `rpy`), `m/s^2` (gravity).
        unit: &'static str,
    },
}

/// A derived robot whose programs are run by robid-symbolic's interpreter.
#[derive(Debug, Clone)]
pub struct Interpreted {
    programs: RobotPrograms,
    /// The base parameters' names, written once (`Model` lends them as `&str`).
    base_names: Vec<String>,
    /// Every program lowered for repeated runs with the geometry bound, in the order of
    /// [`robid_runtime::model::PROGRAMS`] (docs/performance.md#excitation).
    compact: Vec<Compact>,
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
        let geometry: Vec<f64> = programs
            .geometry
            .iter()
            .map(|(s, v)| {
                v.ok_or_else(|| ModelError::UnboundSymbol {
                    place: programs
                        .robot
                        .symbol_place(s)
                        .map_or_else(String::new, |place| format!("{place}: ")),
                    robot: programs.robot.name().to_owned(),
                    symbol: s.clone(),
                    used: used_by(&programs.robot, s),
                    unit: programs.robot.symbol_unit(s).unwrap_or("m or rad"),
                })
            })
            .collect::<Result<_, _>>()?;
        let base_names = programs.base.iter().map(|b| b.name.to_string()).collect();
        let compact = PROGRAMS
            .iter()
            .map(|info| {
                // the geometry is the last input group of every program that reads it
                let p = &programs[info.kind];
                let reads_geometry = p.inputs.len() > info.inputs.len();
                let bound: &[f64] = if reads_geometry { &geometry } else { &[] };
                p.compact(bound).unwrap_or_else(|e| {
                    unreachable!("the derivation appends the geometry group last: {e}")
                })
            })
            .collect();
        Ok(Self {
            programs,
            base_names,
            compact,
        })
    }

    /// The derived programs (names and expressions of the parameters included).
    pub fn programs(&self) -> &RobotPrograms {
        &self.programs
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
    fn standard_parameter_name(&self, index: usize) -> Option<&str> {
        self.programs.standard.get(index).map(String::as_str)
    }
    fn base_parameter_count(&self) -> usize {
        self.programs.base.len()
    }
    fn base_parameter_name(&self, index: usize) -> Option<&str> {
        self.base_names.get(index).map(String::as_str)
    }
    /// Checks every slice against the table (the same [`LengthError`] as the compiled
    /// models, and the output untouched on a mismatch), then interprets the program.
    fn run(
        &self,
        program: ProgramKind,
        inputs: &[&[f64]],
        output: &mut [f64],
    ) -> Result<(), LengthError> {
        check_arguments(program, self.sizes(), inputs, output)?;
        let p = &self.compact[program as usize];
        let expected = output.len();
        TEMPS
            .with(|t| p.run(inputs, &mut [output], &mut t.borrow_mut()))
            .map_err(|_| LengthError {
                argument: program.info().output.name,
                expected,
                found: 0,
            })
    }
    /// As [`run`](Self::run), each operation interpreted once for all `lanes` sets
    /// (`Compact::run_lanes`: the same results to the bit).
    fn run_lanes(
        &self,
        program: ProgramKind,
        lanes: usize,
        inputs: &[&[f64]],
        output: &mut [f64],
    ) -> Result<(), LengthError> {
        check_lanes(program, self.sizes(), lanes, inputs, output)?;
        let p = &self.compact[program as usize];
        let expected = output.len();
        TEMPS
            .with(|t| p.run_lanes(lanes, inputs, &mut [output], &mut t.borrow_mut()))
            .map_err(|_| LengthError {
                argument: program.info().output.name,
                expected,
                found: 0,
            })
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
            .find(|b| b.name.to_string() == name)
            .map(|b| b.expression.clone())
    }
}

/// The model of `robot`: the compiled reference model when `robot` is a reference
/// description ([`Reference::matching`]), else the interpreter. The derivation (for the
/// names and expressions) runs in both cases.
pub fn model_for(robot: &Robot) -> Result<Chosen, ModelError> {
    let programs = RobotPrograms::derive(robot).map_err(|source| ModelError::Derive {
        robot: robot.name().to_owned(),
        source,
    })?;
    let base = programs.base.clone();
    let standard = programs.standard.clone();
    let (model, compiled): (Box<dyn Model + Send + Sync>, bool) =
        match Reference::matching(robot).map(Reference::model) {
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

/// A value of a symbol of unit `unit` for the hint: `9.81` for gravity, `0.3` for a length
/// or an angle.
fn example(unit: &str) -> &'static str {
    if unit == "m/s^2" { "9.81" } else { "0.3" }
}

/// Where `robot`'s DH table first uses `symbol`, as ` (joint 2's `d`)`; nothing when only
/// the gravity or a base or tool transform does.
fn used_by(robot: &Robot, symbol: &str) -> String {
    robot
        .joints()
        .iter()
        .enumerate()
        .find_map(|(j, joint)| {
            [
                ("gamma", &joint.gamma),
                ("b", &joint.b),
                ("alpha", &joint.alpha),
                ("a", &joint.a),
                ("d", &joint.d),
                ("theta", &joint.theta),
            ]
            .into_iter()
            .find(|(_, g)| g.symbols().iter().any(|s| s == symbol))
            .map(|(name, _)| format!(" (joint {}'s `{name}`)", j + 1))
        })
        .unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A symbol left without a value is named with the joint and value that use it.
    #[test]
    fn an_unbound_symbol_is_named_where_it_is_used() {
        let text = "name = \"s\"\nconvention = \"modified\"\ngravity = [0, 0, -9.81]\n\
                    [[joints]]\nalpha = 0\na = 0\nd = 0\n\
                    [[joints]]\nalpha = \"pi/2\"\na = 0\nd = \"L2\"\n";
        let robot = Robot::from_toml(text, "s.toml").unwrap();
        let message = Interpreted::new(&robot).unwrap_err().to_string();
        assert!(
            message.starts_with(
                "s.toml:11:5: robot `s`: geometric symbol `L2` (joint 2's `d`) has no value"
            ) && message.contains("(`L2 = 0.3`, in m)"),
            "{message}"
        );
        // the place survives the changes the command line makes (--drive), and a symbol
        // used only by gravity or [base], which no joint names, has its place too
        let drive = robid_symbolic::Drive::NONE;
        let message = Interpreted::new(&robot.with_drive(drive))
            .unwrap_err()
            .to_string();
        assert!(message.starts_with("s.toml:11:5: "), "{message}");
        let text = "name = \"s\"\nconvention = \"modified\"\ngravity = [0, 0, \"-g\"]\n\
                    [[joints]]\nalpha = 0\na = 0\nd = 0\n";
        let robot = Robot::from_toml(text, "g.toml").unwrap();
        let message = Interpreted::new(&robot).unwrap_err().to_string();
        assert!(
            message.starts_with("g.toml:3:18: robot `s`: geometric symbol `g` has no value"),
            "{message}"
        );
        // each symbol's hint in its own unit: gravity's in m/s^2 (it said "in m or rad"),
        // a length's in m, an angle's in rad
        assert!(message.ends_with("(`g = 9.81`, in m/s^2)"), "{message}");
        let angle = Robot::from_toml(
            &text
                .replace("\"-g\"", "-9.81")
                .replace("alpha = 0", "alpha = \"t\""),
            "t.toml",
        )
        .unwrap();
        let message = Interpreted::new(&angle).unwrap_err().to_string();
        assert!(message.ends_with("(`t = 0.3`, in rad)"), "{message}");
        // a robot built in code has no place to name
        let robot = robot.with_symbol_value("g", 9.81).unwrap();
        assert!(Interpreted::new(&robot).is_ok());
    }

    #[test]
    fn interpreted_equals_compiled() {
        let text = include_str!("../descriptions/tx40.toml");
        let robot = Robot::from_toml(text, "tx40.toml").unwrap();
        let i = Interpreted::new(&robot).unwrap();
        let c = crate::Tx40;
        let (q, qd, qdd) = (
            [0.1, -0.4, 0.7, 1.1, -0.3, 0.2],
            [0.5, 0.2, -0.3, 0.8, 1.0, -1.2],
            [1.0, -2.0, 0.4, 0.3, -0.6, 2.0],
        );
        let p = Model::base_parameter_count(&c);
        let (mut a, mut b) = (vec![0.0; 6 * p], vec![0.0; 6 * p]);
        i.base_regressor_into(&q, &qd, &qdd, &mut a).unwrap();
        c.base_regressor_into(&q, &qd, &qdd, &mut b).unwrap();
        for (x, y) in a.iter().zip(&b) {
            assert!((x - y).abs() < 1e-9 * (1.0 + y.abs()));
        }
    }

    /// One contract for both kinds of model: the same `LengthError` for the same wrong
    /// slice, and the output left as it was.
    #[test]
    fn a_wrong_length_is_the_same_error_for_compiled_and_interpreted() {
        let text = include_str!("../descriptions/tx40.toml");
        let robot = Robot::from_toml(text, "tx40.toml").unwrap();
        let models: [Box<dyn Model>; 2] = [
            Box::new(Interpreted::new(&robot).unwrap()),
            crate::Reference::named("tx40").unwrap().model(),
        ];
        let p = models[1].base_parameter_count();
        let ns = models[1].standard_parameter_count();
        let (q, short, base) = ([0.3; 6], [0.3; 2], vec![0.5; p]);
        let mut errors = Vec::new();
        for m in &models {
            let mut out = vec![7.0; 6];
            let e = [
                m.gravity_into(&short, &base, &mut out).unwrap_err(),
                m.gravity_into(&q, &base[1..], &mut out).unwrap_err(),
                m.gravity_into(&q, &base, &mut out[..5]).unwrap_err(),
                m.inverse_dynamics_into(&q, &q, &short, &base, &mut out)
                    .unwrap_err(),
                m.coriolis_into(&q, &short, &base, &mut out).unwrap_err(),
                m.mass_matrix_into(&q, &base, &mut out).unwrap_err(),
                m.base_regressor_into(&q, &q, &q, &mut out).unwrap_err(),
                m.standard_regressor_into(&q, &q, &short, &mut vec![0.0; 6 * ns])
                    .unwrap_err(),
                m.base_from_standard_into(&base, &mut vec![0.0; p])
                    .unwrap_err(),
            ];
            assert!(out.iter().all(|&v| v == 7.0), "output written on error");
            assert_eq!(m.base_parameter_name(p), None);
            assert_eq!(m.standard_parameter_name(ns), None);
            errors.push(e);
        }
        assert_eq!(errors[0], errors[1]);
        assert_eq!(
            errors[0][0],
            LengthError {
                argument: "q",
                expected: 6,
                found: 2
            }
        );
        assert_eq!(errors[0][2].argument, "out");
        assert_eq!(errors[0][8].argument, "standard");
    }

    #[test]
    fn reference_text_chooses_the_compiled_model() {
        let text = include_str!("../descriptions/tx40.toml");
        let robot = Robot::from_toml(text, "tx40.toml").unwrap();
        assert!(model_for(&robot).unwrap().compiled);
        // the same robot with viscous friction on every joint (a top-level key, before
        // the first table): another model, so not the compiled one
        let edited = text.replacen(
            "gravity = [0, 0, -9.81]\n",
            "gravity = [0, 0, -9.81]\ndrive = [\"Fv\"]\n",
            1,
        );
        assert_ne!(edited, text, "the edit applies");
        let robot = Robot::from_toml(&edited, "edited.toml").unwrap();
        assert_eq!(robot.standard_parameters().len(), 6 * 10 + 6);
        assert!(!model_for(&robot).unwrap().compiled);
    }
}
