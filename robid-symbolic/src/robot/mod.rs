//! Robot descriptions: a DH table with joint types, limits and drive terms.
//!
//! [`Robot`] is the validated description; `file.rs` reads it from TOML with
//! errors that name the line and column; `parameters.rs` names the standard
//! parameters; `dh.rs` turns either DH convention into modified-DH frames.

mod dh;
mod error;
mod file;
mod parameters;

pub use dh::FrameRow;
pub use error::DescriptionError;
pub use parameters::{DriveTerm, INERTIAL_NAMES, Parameter, ParameterKind};

use crate::expr::{Arena, Id, Num};

/// Denavit-Hartenberg convention of a table.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Convention {
    /// Craig / Khalil-Kleinfinger: Rx(alpha) Tx(a) Rz(theta) Tz(d).
    Modified,
    /// Classic: Rz(theta) Tz(d) Tx(a) Rx(alpha).
    Standard,
}

impl Convention {
    /// The word used in description files.
    pub fn as_str(self) -> &'static str {
        match self {
            Convention::Modified => "modified",
            Convention::Standard => "standard",
        }
    }
}

/// Joint type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum JointKind {
    /// theta = q + offset.
    Revolute,
    /// d = q + offset.
    Prismatic,
}

/// A geometric value: a number, an exact angle such as `pi/2`, or an expression
/// in named symbols (`L3`, `-d4`), kept symbolic through every derivation.
#[derive(Clone, Debug, PartialEq)]
pub struct Geometry(String);

impl Geometry {
    /// A number.
    pub fn number(value: f64) -> Geometry {
        match Num::from_f64(value) {
            Some(n) => Geometry(n.to_string()),
            None => Geometry(format!("{value:?}")),
        }
    }

    /// An expression in text form (checked when the robot is validated).
    pub fn text(text: &str) -> Geometry {
        Geometry(text.trim().to_owned())
    }

    /// Zero.
    pub fn zero() -> Geometry {
        Geometry("0".to_owned())
    }

    /// The value as an expression in `arena`.
    pub fn to_expr(&self, arena: &mut Arena) -> Id {
        arena
            .parse(&self.0)
            .expect("geometry is validated when the robot is built")
    }

    /// The text form.
    pub fn as_str(&self) -> &str {
        &self.0
    }
}

/// Joint limits (all optional).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Limits {
    /// Lower and upper position [rad or m].
    pub position: Option<[f64; 2]>,
    /// Maximum absolute velocity.
    pub velocity: Option<f64>,
    /// Maximum absolute acceleration.
    pub acceleration: Option<f64>,
    /// Maximum absolute torque or force.
    pub torque: Option<f64>,
}

/// Which drive terms a joint has.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Drive {
    /// Rotor inertia reflected to the joint: Ia qdd.
    pub ia: bool,
    /// Viscous friction: Fv qd.
    pub fv: bool,
    /// Coulomb friction: Fc sign(qd).
    pub fc: bool,
    /// Constant offset: Fo.
    pub fo: bool,
}

impl Drive {
    /// All drive terms.
    pub const ALL: Drive = Drive {
        ia: true,
        fv: true,
        fc: true,
        fo: true,
    };
    /// No drive term (rigid body only).
    pub const NONE: Drive = Drive {
        ia: false,
        fv: false,
        fc: false,
        fo: false,
    };
}

/// One row of the DH table and what belongs to its joint.
#[derive(Clone, Debug, PartialEq)]
pub struct Joint {
    /// Revolute or prismatic.
    pub kind: JointKind,
    /// Twist alpha.
    pub alpha: Geometry,
    /// Length a.
    pub a: Geometry,
    /// Offset d (the joint variable's offset for a prismatic joint).
    pub d: Geometry,
    /// Angle offset theta (the joint variable's offset for a revolute joint).
    pub theta: Geometry,
    /// Limits.
    pub limits: Limits,
    /// Drive terms.
    pub drive: Drive,
}

impl Joint {
    /// A revolute joint with numeric DH values, no limits, no drive terms.
    pub fn revolute(alpha: &str, a: f64, d: f64, theta: &str) -> Joint {
        Joint {
            kind: JointKind::Revolute,
            alpha: Geometry::text(alpha),
            a: Geometry::number(a),
            d: Geometry::number(d),
            theta: Geometry::text(theta),
            limits: Limits::default(),
            drive: Drive::NONE,
        }
    }

    /// A prismatic joint with numeric DH values, no limits, no drive terms.
    pub fn prismatic(alpha: &str, a: f64, d: f64, theta: &str) -> Joint {
        Joint {
            kind: JointKind::Prismatic,
            ..Joint::revolute(alpha, a, d, theta)
        }
    }
}

/// A validated robot description.
#[derive(Clone, Debug, PartialEq)]
pub struct Robot {
    /// Name (lower case, used for generated type names).
    pub name: String,
    /// DH convention of the table.
    pub convention: Convention,
    /// Gravity in the base frame.
    pub gravity: [Geometry; 3],
    /// Joints, base to tip.
    pub joints: Vec<Joint>,
    /// Default values of the geometric symbols, in order of first use.
    pub symbols: Vec<(String, Option<f64>)>,
}

impl Robot {
    /// Builds and validates a robot (gravity default [0, 0, -9.81] if `None`).
    pub fn new(
        name: &str,
        convention: Convention,
        gravity: Option<[Geometry; 3]>,
        joints: Vec<Joint>,
    ) -> Result<Robot, DescriptionError> {
        let gravity = gravity
            .unwrap_or_else(|| [Geometry::zero(), Geometry::zero(), Geometry::number(-9.81)]);
        let mut robot = Robot {
            name: name.to_owned(),
            convention,
            gravity,
            joints,
            symbols: Vec::new(),
        };
        robot.symbols = file::check_geometry(&robot, &[])?;
        Ok(robot)
    }

    /// Number of joints.
    pub fn dof(&self) -> usize {
        self.joints.len()
    }

    /// The same robot with the given drive terms on every joint.
    pub fn with_drive(mut self, drive: Drive) -> Robot {
        for j in &mut self.joints {
            j.drive = drive;
        }
        self
    }

    /// The same robot with another gravity vector (numbers).
    pub fn with_gravity(mut self, gravity: [f64; 3]) -> Robot {
        self.gravity = gravity.map(Geometry::number);
        self
    }
}
