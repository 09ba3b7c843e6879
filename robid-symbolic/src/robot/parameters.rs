//! The standard parameters of a robot (docs/conventions.md#standard-parameters). What a
//! parameter is, and its name, is [`robid_core::ParameterId`]: one type for every
//! crate, parsed in one place.

use super::Robot;
pub use robid_core::{DriveTerm, Inertial, ParameterId, ParameterKind};

impl Robot {
    /// The standard parameters: per link `XX XY XZ YY YZ ZZ MX MY MZ M`, then
    /// the joint's enabled drive terms `Ia Fv Fc Fo`.
    pub fn standard_parameters(&self) -> Vec<ParameterId> {
        let mut out = Vec::new();
        for (j, joint) in self.joints.iter().enumerate() {
            let inertial = Inertial::ALL.map(ParameterKind::Inertial);
            let drive = joint.drive.terms().map(ParameterKind::Drive);
            out.extend(
                inertial
                    .into_iter()
                    .chain(drive)
                    .map(|kind| ParameterId::new(j, kind)),
            );
        }
        out
    }
}
