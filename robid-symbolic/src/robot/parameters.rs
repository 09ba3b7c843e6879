//! The standard parameters of a robot and their names (docs/conventions.md#standard-parameters).

use super::Robot;

/// A drive term of a joint.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum DriveTerm {
    /// Rotor inertia reflected to the joint (Ia qdd).
    Ia,
    /// Viscous friction (Fv qd).
    Fv,
    /// Coulomb friction (Fc sign(qd)).
    Fc,
    /// Constant offset (Fo).
    Fo,
}

impl DriveTerm {
    /// Name prefix (`Ia`, `Fv`, `Fc`, `Fo`).
    pub fn prefix(self) -> &'static str {
        match self {
            DriveTerm::Ia => "Ia",
            DriveTerm::Fv => "Fv",
            DriveTerm::Fc => "Fc",
            DriveTerm::Fo => "Fo",
        }
    }
}

/// What a standard parameter is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ParameterKind {
    /// Entry of the inertia tensor about the link frame origin: 0..6 = XX XY XZ YY YZ ZZ.
    Inertia(usize),
    /// First moment of mass: 0..3 = MX MY MZ.
    FirstMoment(usize),
    /// Mass M.
    Mass,
    /// A drive term of the joint.
    Drive(DriveTerm),
}

/// The inertial parameter names of one link, in the standard order.
pub const INERTIAL_NAMES: [&str; 10] = ["XX", "XY", "XZ", "YY", "YZ", "ZZ", "MX", "MY", "MZ", "M"];

/// One standard parameter.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Parameter {
    /// Name such as `XX2` or `Fv3`.
    pub name: String,
    /// Link / joint index, 0-based.
    pub link: usize,
    /// What it is.
    pub kind: ParameterKind,
}

impl Robot {
    /// The standard parameters: per link `XX XY XZ YY YZ ZZ MX MY MZ M`, then
    /// the joint's enabled drive terms `Ia Fv Fc Fo`.
    pub fn standard_parameters(&self) -> Vec<Parameter> {
        let mut out = Vec::new();
        for (j, joint) in self.joints.iter().enumerate() {
            let n = j + 1;
            for (k, base) in INERTIAL_NAMES.iter().enumerate() {
                let kind = match k {
                    0..=5 => ParameterKind::Inertia(k),
                    6..=8 => ParameterKind::FirstMoment(k - 6),
                    _ => ParameterKind::Mass,
                };
                out.push(Parameter {
                    name: format!("{base}{n}"),
                    link: j,
                    kind,
                });
            }
            let d = joint.drive;
            for (on, term) in [
                (d.ia, DriveTerm::Ia),
                (d.fv, DriveTerm::Fv),
                (d.fc, DriveTerm::Fc),
                (d.fo, DriveTerm::Fo),
            ] {
                if on {
                    out.push(Parameter {
                        name: format!("{}{n}", term.prefix()),
                        link: j,
                        kind: ParameterKind::Drive(term),
                    });
                }
            }
        }
        out
    }
}
