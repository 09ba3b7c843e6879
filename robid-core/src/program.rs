//! The table of the programs every robot model has: one entry per program with its
//! name, documentation, inputs and output shape. The symbolic builder, the Rust and C
//! emitters, the `Model` implementations (generated and interpreted),
//! `robid model`'s operation counts and `robid bench` all iterate this table, so adding
//! a program is one entry here plus its builder in robid-symbolic.

/// How many entries an argument has, in terms of a model's sizes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Size {
    /// One entry per joint.
    Joints,
    /// One entry per base parameter.
    Base,
    /// One entry per standard parameter.
    Standard,
    /// A `joints x joints` matrix, row-major.
    JointsByJoints,
    /// A `joints x base parameters` matrix, row-major.
    JointsByBase,
    /// A `joints x standard parameters` matrix, row-major.
    JointsByStandard,
}

/// The sizes of one model: what a [`Size`] is measured in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Sizes {
    /// Number of joints.
    pub joints: usize,
    /// Number of base parameters.
    pub base: usize,
    /// Number of standard parameters.
    pub standard: usize,
}

impl Size {
    /// The number of entries for a model of `sizes`.
    pub const fn len(self, sizes: Sizes) -> usize {
        let Sizes {
            joints,
            base,
            standard,
        } = sizes;
        match self {
            Size::Joints => joints,
            Size::Base => base,
            Size::Standard => standard,
            Size::JointsByJoints => joints * joints,
            Size::JointsByBase => joints * base,
            Size::JointsByStandard => joints * standard,
        }
    }

    /// The shape in words, for documentation: `joints x base parameters`.
    pub const fn describe(self) -> &'static str {
        match self {
            Size::Joints => "one entry per joint",
            Size::Base => "one entry per base parameter",
            Size::Standard => "one entry per standard parameter",
            Size::JointsByJoints => "joints x joints, row-major",
            Size::JointsByBase => "joints x base parameters, row-major",
            Size::JointsByStandard => "joints x standard parameters, row-major",
        }
    }
}

/// An input or output of a program: its name (the argument's name in generated code
/// and in the runtime's `LengthError`) and its size.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Argument {
    /// Name: `q`, `qd`, `qdd`, `base`, `standard`, `tau`, `out`.
    pub name: &'static str,
    /// Number of entries.
    pub size: Size,
}

impl Argument {
    /// Joint positions.
    pub const Q: Argument = Argument::new("q", Size::Joints);
    /// Joint velocities.
    pub const QD: Argument = Argument::new("qd", Size::Joints);
    /// Joint accelerations.
    pub const QDD: Argument = Argument::new("qdd", Size::Joints);
    /// Base parameters, in the model's order.
    pub const BASE: Argument = Argument::new("base", Size::Base);
    /// Standard parameters, in the model's order.
    pub const STANDARD: Argument = Argument::new("standard", Size::Standard);
    /// Joint torques (forces for prismatic joints).
    pub const TAU: Argument = Argument::new("tau", Size::Joints);

    const fn new(name: &'static str, size: Size) -> Argument {
        Argument { name, size }
    }

    /// An output matrix or vector named `out`.
    const fn out(size: Size) -> Argument {
        Argument::new("out", size)
    }
}

/// One of the programs a model has.
///
/// ```
/// use robid_core::ProgramKind;
/// let p = ProgramKind::MassMatrix.info();
/// assert_eq!(p.name, "mass_matrix");
/// assert_eq!(p.inputs.len(), 2); // q and the base parameters
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum ProgramKind {
    /// Y(q, qd, qdd).
    StandardRegressor,
    /// Y_b(q, qd, qdd).
    BaseRegressor,
    /// tau(q, qd, qdd, base).
    InverseDynamics,
    /// M(q).
    MassMatrix,
    /// g(q).
    Gravity,
    /// c(q, qd).
    Coriolis,
    /// base = K standard.
    BaseFromStandard,
}

/// What the table says about one program.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ProgramInfo {
    /// Which program.
    pub kind: ProgramKind,
    /// Name of the generated function and of the program (`inverse_dynamics`); the
    /// `Model` method that runs it is this name with `_into`.
    pub name: &'static str,
    /// One sentence for the documentation of the generated function.
    pub summary: &'static str,
    /// The inputs, in order (geometric symbols are part of the model value, not inputs).
    pub inputs: &'static [Argument],
    /// The output.
    pub output: Argument,
}

/// Every program, in the order of [`ProgramKind`].
pub const PROGRAMS: [ProgramInfo; 7] = [
    ProgramInfo {
        kind: ProgramKind::StandardRegressor,
        name: "standard_regressor",
        summary: "Standard regressor Y(q, qd, qdd): tau = Y * standard.",
        inputs: &[Argument::Q, Argument::QD, Argument::QDD],
        output: Argument::out(Size::JointsByStandard),
    },
    ProgramInfo {
        kind: ProgramKind::BaseRegressor,
        name: "base_regressor",
        summary: "Base regressor Y_b(q, qd, qdd): tau = Y_b * base.",
        inputs: &[Argument::Q, Argument::QD, Argument::QDD],
        output: Argument::out(Size::JointsByBase),
    },
    ProgramInfo {
        kind: ProgramKind::InverseDynamics,
        name: "inverse_dynamics",
        summary: "Inverse dynamics with base parameters (customised Newton-Euler): joint torques, drive terms included.",
        inputs: &[Argument::Q, Argument::QD, Argument::QDD, Argument::BASE],
        output: Argument::TAU,
    },
    ProgramInfo {
        kind: ProgramKind::MassMatrix,
        name: "mass_matrix",
        summary: "Joint-space inertia matrix M(q), rotor inertias included.",
        inputs: &[Argument::Q, Argument::BASE],
        output: Argument::out(Size::JointsByJoints),
    },
    ProgramInfo {
        kind: ProgramKind::Gravity,
        name: "gravity",
        summary: "Gravity torques g(q).",
        inputs: &[Argument::Q, Argument::BASE],
        output: Argument::out(Size::Joints),
    },
    ProgramInfo {
        kind: ProgramKind::Coriolis,
        name: "coriolis",
        summary: "Coriolis and centripetal torques c(q, qd) (no gravity, no friction).",
        inputs: &[Argument::Q, Argument::QD, Argument::BASE],
        output: Argument::out(Size::Joints),
    },
    ProgramInfo {
        kind: ProgramKind::BaseFromStandard,
        name: "base_from_standard",
        summary: "Base parameters from standard parameters: base = K * standard.",
        inputs: &[Argument::STANDARD],
        output: Argument::BASE,
    },
];

impl ProgramKind {
    /// Every program, in table order.
    pub const ALL: [ProgramKind; 7] = [
        ProgramKind::StandardRegressor,
        ProgramKind::BaseRegressor,
        ProgramKind::InverseDynamics,
        ProgramKind::MassMatrix,
        ProgramKind::Gravity,
        ProgramKind::Coriolis,
        ProgramKind::BaseFromStandard,
    ];

    /// The table entry of this program.
    pub const fn info(self) -> &'static ProgramInfo {
        &PROGRAMS[self as usize]
    }

    /// The program named `name` (`"mass_matrix"`), if there is one.
    pub fn from_name(name: &str) -> Option<ProgramKind> {
        PROGRAMS.iter().find(|p| p.name == name).map(|p| p.kind)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_table_is_in_kind_order_with_unique_names() {
        for (i, (p, k)) in PROGRAMS.iter().zip(ProgramKind::ALL).enumerate() {
            assert_eq!(p.kind, k);
            assert_eq!(k as usize, i);
            assert_eq!(ProgramKind::from_name(p.name), Some(k));
        }
        assert_eq!(ProgramKind::from_name("jacobian"), None);
    }

    #[test]
    fn sizes() {
        let s = Sizes {
            joints: 6,
            base: 36,
            standard: 84,
        };
        let out = |k: ProgramKind| k.info().output.size.len(s);
        assert_eq!(out(ProgramKind::BaseRegressor), 216);
        assert_eq!(out(ProgramKind::StandardRegressor), 504);
        assert_eq!(out(ProgramKind::MassMatrix), 36);
        assert_eq!(out(ProgramKind::InverseDynamics), 6);
        assert_eq!(out(ProgramKind::BaseFromStandard), 36);
    }
}
