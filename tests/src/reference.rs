//! The reference robots of `robots/`, compiled in with `include_str!` so no test reads files
//! at run time.

use robid_symbolic::{Drive, Robot};

/// A reference robot: its description file and its reference parameter file.
#[derive(Clone, Copy, Debug)]
pub struct Reference {
    /// Robot name (also the file stem).
    pub name: &'static str,
    /// The description (TOML).
    pub description: &'static str,
    /// The parameter file (TOML with a `[standard]` table).
    pub parameters: &'static str,
}

macro_rules! reference {
    ($name:literal) => {
        Reference {
            name: $name,
            description: include_str!(concat!("../../robots/descriptions/", $name, ".toml")),
            parameters: include_str!(concat!("../../robots/parameters/", $name, ".toml")),
        }
    };
}

/// Every reference robot.
pub const ROBOTS: [Reference; 7] = [
    reference!("ur5e"),
    reference!("puma560"),
    reference!("rx90"),
    reference!("tx40"),
    reference!("lwr4"),
    reference!("panda"),
    reference!("stanford"),
];

/// The reference robot with this name.
pub fn by_name(name: &str) -> Reference {
    *ROBOTS
        .iter()
        .find(|r| r.name == name)
        .unwrap_or_else(|| panic!("no reference robot `{name}`"))
}

impl Reference {
    /// The description with the given drive terms on every joint.
    pub fn robot(&self, drive: Drive) -> Robot {
        Robot::from_toml(self.description, &format!("{}.toml", self.name))
            .unwrap_or_else(|e| panic!("{e}"))
            .with_drive(drive)
    }

    /// The `[standard]` table as (name, value) pairs, in file order.
    pub fn parameter_table(&self) -> Vec<(String, f64)> {
        parse_standard_table(self.parameters)
            .unwrap_or_else(|e| panic!("{}: parameters: {e}", self.name))
    }

    /// The reference values of `robot.standard_parameters()` (missing names are 0;
    /// names of parameters the robot does not have, e.g. disabled drive terms, are ignored).
    pub fn parameter_values(&self, robot: &Robot) -> Vec<f64> {
        let table = self.parameter_table();
        robot
            .standard_parameters()
            .iter()
            .map(|p| {
                table
                    .iter()
                    .find(|(n, _)| *n == p.name)
                    .map_or(0.0, |(_, v)| *v)
            })
            .collect()
    }
}

/// Reads the `[standard]` table of a parameter file: `NAME = number` lines, `#` comments.
/// A deliberately small reader (the files are written by hand in this one shape).
pub fn parse_standard_table(text: &str) -> Result<Vec<(String, f64)>, String> {
    let mut out = Vec::new();
    let mut in_standard = false;
    for (i, raw) in text.lines().enumerate() {
        let line = raw.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        if line.starts_with('[') {
            in_standard = line == "[standard]";
            continue;
        }
        if !in_standard {
            continue;
        }
        let (name, value) = line
            .split_once('=')
            .ok_or_else(|| format!("line {}: expected `NAME = value`", i + 1))?;
        let value: f64 = value
            .trim()
            .parse()
            .map_err(|e| format!("line {}: {e}", i + 1))?;
        out.push((name.trim().to_owned(), value));
    }
    Ok(out)
}
