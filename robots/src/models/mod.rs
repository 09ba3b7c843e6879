//! The reference robots, compiled by `robot_model!` from `descriptions/`.

mod lwr4;
mod panda;
mod puma560;
mod rx90;
mod stanford;
mod tx40;
mod ur5e;

#[cfg(test)]
mod consistency;
#[cfg(test)]
mod generated;

pub use lwr4::Lwr4;
pub use panda::Panda;
pub use puma560::Puma560;
pub use rx90::Rx90;
pub use stanford::Stanford;
pub use tx40::Tx40;
pub use ur5e::Ur5e;

use robid_runtime::Model;
use robid_runtime::data::ParameterFile;
use robid_symbolic::Robot;

/// A reference robot: its description, its nominal parameters and its compiled model.
///
/// ```
/// let ur5e = robots::Reference::named("ur5e").unwrap();
/// assert_eq!(ur5e.model().dof(), 6);
/// assert_eq!(robots::Reference::matching(&ur5e.robot()).unwrap().name, "ur5e");
/// ```
#[derive(Debug)]
pub struct Reference {
    /// Name: the description's `name` and the stem of its files.
    pub name: &'static str,
    /// The description (TOML), `descriptions/NAME.toml`.
    pub description: &'static str,
    /// Nominal parameters (a parameter file with a `[standard]` table), `parameters/NAME.toml`.
    pub parameters: &'static str,
    /// Each base parameter as an expression in the standard parameters (from the generated code).
    pub base_expressions: &'static [&'static str],
    model: fn() -> Box<dyn Model + Send + Sync>,
}

/// Registry entry of a compiled reference robot.
macro_rules! reference {
    ($name:literal, $ty:ident) => {
        Reference {
            name: $name,
            description: include_str!(concat!("../../descriptions/", $name, ".toml")),
            parameters: include_str!(concat!("../../parameters/", $name, ".toml")),
            base_expressions: &$ty::BASE_PARAMETER_EXPRESSIONS,
            model: || Box::new($ty::default()),
        }
    };
}

/// Every reference robot.
#[allow(clippy::default_constructed_unit_structs)] // the robots with symbols are not unit structs
pub static REFERENCES: [Reference; 7] = [
    reference!("ur5e", Ur5e),
    reference!("puma560", Puma560),
    reference!("rx90", Rx90),
    reference!("tx40", Tx40),
    reference!("lwr4", Lwr4),
    reference!("panda", Panda),
    reference!("stanford", Stanford),
];

impl Reference {
    /// The reference robot called `name`.
    pub fn named(name: &str) -> Option<&'static Reference> {
        REFERENCES.iter().find(|r| r.name == name)
    }

    /// The reference robot whose description is `robot` (the same table, drive terms,
    /// gravity, symbols and name, however the file is written).
    pub fn matching(robot: &Robot) -> Option<&'static Reference> {
        REFERENCES
            .iter()
            .find(|r| r.robot_checked().is_ok_and(|own| own == *robot))
    }

    /// The compiled model (geometric symbols at their description values).
    pub fn model(&self) -> Box<dyn Model + Send + Sync> {
        (self.model)()
    }

    /// The description as a [`Robot`] (the checked-in files are valid; a test reads each).
    pub fn robot(&self) -> Robot {
        self.robot_checked()
            .unwrap_or_else(|e| unreachable!("reference description {}: {e}", self.name))
    }

    /// The nominal parameter file (the checked-in files are valid; a test reads each).
    pub fn parameter_file(&self) -> ParameterFile {
        let path = format!("parameters/{}.toml", self.name);
        ParameterFile::parse(self.parameters, path.as_ref())
            .unwrap_or_else(|e| unreachable!("reference parameters {}: {e}", self.name))
    }

    /// The nominal values of `robot.standard_parameters()` (`robot` is this description,
    /// possibly with other drive terms): missing names are 0, and names of parameters
    /// `robot` does not have (drive terms it leaves out) are ignored.
    pub fn parameter_values(&self, robot: &Robot) -> Vec<f64> {
        let file = self.parameter_file();
        robot
            .standard_parameters()
            .iter()
            .map(|p| file.get(&p.to_string()).unwrap_or(0.0))
            .collect()
    }

    fn robot_checked(&self) -> Result<Robot, robid_symbolic::DescriptionError> {
        Robot::from_toml(self.description, &format!("{}.toml", self.name))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_reference_is_consistent() {
        for r in &REFERENCES {
            let robot = r.robot();
            assert_eq!(robot.name(), r.name);
            let model = r.model();
            assert_eq!(model.name(), r.name);
            assert_eq!(model.base_parameter_count(), r.base_expressions.len());
            assert_eq!(Reference::matching(&robot).map(|m| m.name), Some(r.name));
            assert_eq!(Reference::named(r.name).map(|m| m.name), Some(r.name));
            // every name is a parameter of the description with all drive terms, and the
            // values are physically consistent
            let all = robot.clone().with_drive(robid_symbolic::Drive::ALL);
            let names: Vec<String> = all
                .standard_parameters()
                .iter()
                .map(|p| p.to_string())
                .collect();
            r.parameter_file()
                .prior(&names)
                .unwrap_or_else(|e| panic!("{e}"));
        }
        assert!(Reference::named("r2d2").is_none());
    }
}
