//! Robot descriptions: a DH table with joint types, limits and drive terms.
//!
//! [`Robot`] is the validated description: its fields are private and every
//! way to build or change one checks it (`check.rs`), so a `Robot` in hand is
//! always usable. [`Geometry`] is one DH value or gravity component, valid by
//! construction (`geometry.rs`). `file.rs` reads a robot from TOML, reporting
//! every mistake with its line and column; [`bounds`] holds the documented
//! limits on values and sizes; `parameters.rs` names the standard parameters;
//! `dh.rs` turns either DH convention into modified-DH frames; `urdf/` reads a URDF
//! chain as a modified-DH robot with the frames back to the URDF's links
//! ([`Robot::from_urdf`], docs/urdf.md).

pub mod bounds;
mod check;
mod dh;
mod error;
mod file;
mod geometry;
mod interval;
mod parameters;
mod read;
mod transform;
mod urdf;
mod write;

pub use dh::{FrameRow, JointPlacement, Pose};
pub use error::DescriptionError;
pub use geometry::{Expression, Geometry, GeometryError, Number};
pub use parameters::{DriveTerm, Inertial, ParameterId, ParameterKind};
pub use transform::Transform;
pub use urdf::{
    AttachedLink, ChainLink, ChainSelection, NEGLIGIBLE_SHARE, UnphysicalInertial, UrdfChain,
    negligible, write_inertials,
};

pub(crate) use check::name_problem;
use check::{Code, Parts};

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

/// Joint limits (all optional).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Limits {
    /// Lower and upper position (rad or m).
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

    /// Whether the joint has `term`.
    pub fn has(self, term: DriveTerm) -> bool {
        match term {
            DriveTerm::Ia => self.ia,
            DriveTerm::Fv => self.fv,
            DriveTerm::Fc => self.fc,
            DriveTerm::Fo => self.fo,
        }
    }

    /// Turns `term` on.
    pub fn add(&mut self, term: DriveTerm) {
        *match term {
            DriveTerm::Ia => &mut self.ia,
            DriveTerm::Fv => &mut self.fv,
            DriveTerm::Fc => &mut self.fc,
            DriveTerm::Fo => &mut self.fo,
        } = true;
    }

    /// The terms the joint has, in the standard order.
    pub fn terms(self) -> impl Iterator<Item = DriveTerm> {
        DriveTerm::ALL.into_iter().filter(move |&t| self.has(t))
    }
}

impl FromIterator<DriveTerm> for Drive {
    fn from_iter<I: IntoIterator<Item = DriveTerm>>(terms: I) -> Drive {
        let mut d = Drive::NONE;
        for t in terms {
            d.add(t);
        }
        d
    }
}

/// One row of the DH table and what belongs to its joint: plain data, checked
/// when a [`Robot`] is built from it.
///
/// In the modified convention a row may carry Khalil and Kleinfinger's two extra values,
/// `gamma` about and `b` along z_(j-1), placed in front of the DH row: frame j-1 -> j is
/// Rz(gamma) Tz(b) Rx(alpha) Tx(a) Rz(theta) Tz(d) (docs/conventions.md#khalil-kleinfinger-general-frames).
#[derive(Clone, Debug, PartialEq)]
pub struct Joint {
    /// Revolute or prismatic.
    pub kind: JointKind,
    /// Rotation gamma about z_(j-1) (rad), before the DH row (modified convention only; 0
    /// for a plain DH row).
    pub gamma: Geometry,
    /// Translation b along z_(j-1) (m), before the DH row (modified convention only; 0 for
    /// a plain DH row).
    pub b: Geometry,
    /// Twist alpha (rad).
    pub alpha: Geometry,
    /// Length a (m).
    pub a: Geometry,
    /// Offset d (m) (the joint variable's offset for a prismatic joint).
    pub d: Geometry,
    /// Angle offset theta (rad) (the joint variable's offset for a revolute joint).
    pub theta: Geometry,
    /// Limits.
    pub limits: Limits,
    /// Drive terms.
    pub drive: Drive,
}

impl Joint {
    /// A joint with these DH values, no limits and no drive terms.
    pub fn new(
        kind: JointKind,
        alpha: Geometry,
        a: Geometry,
        d: Geometry,
        theta: Geometry,
    ) -> Joint {
        Joint {
            kind,
            gamma: Geometry::zero(),
            b: Geometry::zero(),
            alpha,
            a,
            d,
            theta,
            limits: Limits::default(),
            drive: Drive::NONE,
        }
    }

    /// The same joint with Khalil and Kleinfinger's `gamma` (rotation about z_(j-1)) and `b`
    /// (translation along it) in front of its DH row; for a modified table only (a
    /// standard table with either nonzero is refused when the robot is built).
    ///
    /// ```
    /// use robid_symbolic::robot::Geometry;
    /// use robid_symbolic::{Convention, Joint, Robot};
    /// let joint = Joint::revolute("pi/2", 0.1, 0.0, "0")?
    ///     .with_gamma_b(Geometry::text("pi/4")?, Geometry::number(0.05)?);
    /// let robot = Robot::new("arm", Convention::Modified, None, vec![joint])?;
    /// assert_eq!(robot.joints()[0].gamma.as_str(), "pi/4");
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn with_gamma_b(self, gamma: Geometry, b: Geometry) -> Joint {
        Joint { gamma, b, ..self }
    }

    /// A revolute joint with numeric lengths, no limits and no drive terms;
    /// the angles are text such as `"pi/2"` or `"0"` (see [`Geometry::text`]).
    pub fn revolute(alpha: &str, a: f64, d: f64, theta: &str) -> Result<Joint, GeometryError> {
        Ok(Joint::new(
            JointKind::Revolute,
            Geometry::text(alpha)?,
            Geometry::number(a)?,
            Geometry::number(d)?,
            Geometry::text(theta)?,
        ))
    }

    /// A prismatic joint with numeric lengths, no limits and no drive terms
    /// (see [`Joint::revolute`]).
    pub fn prismatic(alpha: &str, a: f64, d: f64, theta: &str) -> Result<Joint, GeometryError> {
        Ok(Joint {
            kind: JointKind::Prismatic,
            ..Joint::revolute(alpha, a, d, theta)?
        })
    }
}

/// A validated robot description.
///
/// Built by [`Robot::new`], [`Robot::from_toml`] or [`Robot::from_file`], and
/// changed only through the `with_*` methods, each of which checks the result:
/// a name that is a Rust identifier and not a keyword (it names generated
/// code), 1 to [`bounds::MAX_JOINTS`] joints, values whose magnitudes suit
/// their place (see [`bounds`]), finite limits, and a value for a symbol
/// only when some DH value or gravity uses it.
#[derive(Clone, Debug, PartialEq)]
pub struct Robot {
    name: String,
    convention: Convention,
    gravity: [Geometry; 3],
    joints: Vec<Joint>,
    base: Option<Transform>,
    tool: Option<Transform>,
    symbols: Vec<(String, Option<f64>)>,
    /// Each symbol's unit, as `symbols` (see [`Robot::symbol_unit`]).
    symbol_units: Vec<&'static str>,
    /// Whether its DH values were measured: fitted to a URDF or calibrated (see
    /// `check::Parts::measured`).
    measured: bool,
    uses: SymbolUses,
    joint_places: JointPlaces,
}

/// Where a description file first uses each geometric symbol, as `file:line:column`
/// ([`Robot::symbol_place`]); empty for a robot built in code. Where a robot was written is
/// not part of what it is: two robots that differ only here are equal.
#[derive(Clone, Debug, Default)]
struct SymbolUses(Vec<(String, String)>);

impl PartialEq for SymbolUses {
    fn eq(&self, _: &SymbolUses) -> bool {
        true
    }
}

/// Where a description file wrote each joint's `[[joints]]` table, as `file:line:column`
/// ([`Robot::joint_place`]); empty for a robot built in code. Like [`SymbolUses`], not part
/// of what the robot is.
#[derive(Clone, Debug, Default)]
struct JointPlaces(Vec<String>);

impl PartialEq for JointPlaces {
    fn eq(&self, _: &JointPlaces) -> bool {
        true
    }
}

impl Robot {
    /// Builds and checks a robot (gravity `[0, 0, -9.81]` if `None`); the
    /// errors name the argument (`joints[2].a`).
    pub fn new(
        name: &str,
        convention: Convention,
        gravity: Option<[Geometry; 3]>,
        joints: Vec<Joint>,
    ) -> Result<Robot, DescriptionError> {
        let parts = Parts {
            name: name.to_owned(),
            convention,
            gravity: gravity.unwrap_or_else(default_gravity),
            joints,
            base: None,
            tool: None,
            values: Vec::new(),
            unread_words: Vec::new(),
            measured: false,
            uses: Vec::new(),
            joint_places: Vec::new(),
        };
        parts.check(&Code).map_err(DescriptionError::from_errors)
    }

    /// [`Robot::new`] for a table measured by a calibration (a description's
    /// `calibrated = true`): a numeric angle a few microradians from a right angle is
    /// taken as written, where a typed one is refused as the right angle mistyped. Exact
    /// right angles (`"pi/2"`, or a number within 1e-9 rad of one) stay exact.
    ///
    /// # Examples
    /// ```
    /// use robid_symbolic::{Convention, Joint, Robot};
    /// // a twist measured 3.2 microradians off pi/2
    /// let joints = vec![
    ///     Joint::revolute("0", 0.0, 0.0, "0")?,
    ///     Joint::revolute("1.5707995267948966", 0.0, 0.0, "0")?,
    /// ];
    /// assert!(Robot::new("arm", Convention::Modified, None, joints.clone()).is_err());
    /// let robot = Robot::new_calibrated("arm", Convention::Modified, None, joints)?;
    /// assert_eq!(robot.dof(), 2);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn new_calibrated(
        name: &str,
        convention: Convention,
        gravity: Option<[Geometry; 3]>,
        joints: Vec<Joint>,
    ) -> Result<Robot, DescriptionError> {
        let parts = Parts {
            name: name.to_owned(),
            convention,
            gravity: gravity.unwrap_or_else(default_gravity),
            joints,
            base: None,
            tool: None,
            values: Vec::new(),
            unread_words: Vec::new(),
            measured: true,
            uses: Vec::new(),
            joint_places: Vec::new(),
        };
        parts.check(&Code).map_err(DescriptionError::from_errors)
    }

    /// Name (used for generated type names: `ur5e` -> `Ur5e`).
    pub fn name(&self) -> &str {
        &self.name
    }

    /// DH convention of the table.
    pub fn convention(&self) -> Convention {
        self.convention
    }

    /// Gravity in the world frame (m/s^2): the frame the base transform places robid's
    /// frame 0 in ([`Robot::base`]); without a base transform, frame 0 itself. The
    /// dynamics use it in frame 0, `R_base' g` (docs/conventions.md#gravity).
    pub fn gravity(&self) -> &[Geometry; 3] {
        &self.gravity
    }

    /// The pose of frame 0 in the world frame (the description's `[base]`), if given: a
    /// robot mounted on a wall or rotated on its plate.
    pub fn base(&self) -> Option<&Transform> {
        self.base.as_ref()
    }

    /// The end-effector (tool) frame in the last link's frame n (the description's
    /// `[tool]`), if given.
    pub fn tool(&self) -> Option<&Transform> {
        self.tool.as_ref()
    }

    /// Joints, base to tip.
    pub fn joints(&self) -> &[Joint] {
        &self.joints
    }

    /// The geometric symbols, in order of first use, with their values in the
    /// description (`None`: a run-time input of the generated model).
    pub fn symbols(&self) -> &[(String, Option<f64>)] {
        &self.symbols
    }

    /// Where the description file first uses geometric symbol `symbol`, as
    /// `file:line:column` (the value that uses it), so that a message about the symbol (it
    /// has no value where values are needed) can point there; `None` for a robot built in
    /// code or a symbol it does not use.
    ///
    /// ```
    /// use robid_symbolic::Robot;
    /// let text = "name = \"arm\"\nconvention = \"modified\"\n\
    ///             [[joints]]\nalpha = 0\n[[joints]]\nalpha = 0\na = \"L2\"\n";
    /// let robot = Robot::from_toml(text, "arm.toml").unwrap();
    /// assert_eq!(robot.symbol_place("L2"), Some("arm.toml:7:5"));
    /// assert_eq!(robot.symbol_place("L3"), None);
    /// ```
    pub fn symbol_place(&self, symbol: &str) -> Option<&str> {
        self.uses
            .0
            .iter()
            .find(|(s, _)| s == symbol)
            .map(|(_, place)| place.as_str())
    }

    /// The unit of geometric symbol `symbol`, by the value that first uses it: `"m"` (a DH
    /// length, an `xyz`), `"rad"` (a DH angle, an `rpy`) or `"m/s^2"` (gravity); `None` for
    /// a symbol the robot does not use.
    ///
    /// ```
    /// use robid_symbolic::Robot;
    /// let text = "name = \"arm\"\nconvention = \"modified\"\ngravity = [0, 0, \"-g\"]\n\
    ///             [[joints]]\nalpha = \"t\"\na = \"L2\"\n";
    /// let robot = Robot::from_toml(text, "arm.toml").unwrap();
    /// assert_eq!(robot.symbol_unit("L2"), Some("m"));
    /// assert_eq!(robot.symbol_unit("t"), Some("rad"));
    /// assert_eq!(robot.symbol_unit("g"), Some("m/s^2"));
    /// assert_eq!(robot.symbol_unit("L3"), None);
    /// ```
    pub fn symbol_unit(&self, symbol: &str) -> Option<&'static str> {
        let at = self.symbols.iter().position(|(s, _)| s == symbol)?;
        self.symbol_units.get(at).copied()
    }

    /// Where the description file wrote joint `joint`'s table (0-based, as in
    /// [`Robot::joints`]), as `file:line:column`, so that a message about the joint (it has
    /// no position limit where a design needs one) can point there; `None` for a robot
    /// built in code.
    ///
    /// ```
    /// use robid_symbolic::Robot;
    /// let text = "name = \"arm\"\nconvention = \"modified\"\n\
    ///             [[joints]]\nalpha = 0\n[[joints]]\nalpha = 0\n";
    /// let robot = Robot::from_toml(text, "arm.toml").unwrap();
    /// assert_eq!(robot.joint_place(1), Some("arm.toml:5:1"));
    /// assert_eq!(robot.joint_place(2), None);
    /// ```
    pub fn joint_place(&self, joint: usize) -> Option<&str> {
        self.joint_places.0.get(joint).map(String::as_str)
    }

    /// The geometric symbols without a value: run-time inputs of the models
    /// (fields of the generated type).
    pub fn run_time_symbols(&self) -> Vec<&str> {
        self.symbols
            .iter()
            .filter(|(_, v)| v.is_none())
            .map(|(s, _)| s.as_str())
            .collect()
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

    /// The same robot with the given drive terms on joint `joint` (0-based).
    pub fn with_joint_drive(
        mut self,
        joint: usize,
        drive: Drive,
    ) -> Result<Robot, DescriptionError> {
        let dof = self.dof();
        let Some(j) = self.joints.get_mut(joint) else {
            return Err(DescriptionError::Argument {
                argument: "`joint` of `Robot::with_joint_drive`".to_owned(),
                message: format!("joint index {joint} is out of range"),
                help: format!("the robot has {dof} joints, indices 0 to {}", dof - 1),
            });
        };
        j.drive = drive;
        Ok(self)
    }

    /// The same robot with another gravity vector (m/s^2), checked as in a description.
    pub fn with_gravity(self, gravity: [f64; 3]) -> Result<Robot, DescriptionError> {
        let mut g = Vec::with_capacity(3);
        for (i, value) in gravity.into_iter().enumerate() {
            g.push(
                Geometry::number(value).map_err(|e| DescriptionError::Argument {
                    argument: format!("`gravity[{i}]` of `Robot::with_gravity`"),
                    message: e.to_string(),
                    help: "give gravity in m/s^2, e.g. [0.0, 0.0, -9.81]".to_owned(),
                })?,
            );
        }
        let mut parts = self.into_parts();
        parts.gravity = [g[0].clone(), g[1].clone(), g[2].clone()];
        parts.check(&Code).map_err(DescriptionError::from_errors)
    }

    /// The same robot with frame 0 placed at `base` in the world frame (checked as in a
    /// description; `None` removes it). Gravity stays in the world frame.
    ///
    /// ```
    /// use robid_symbolic::robot::Geometry;
    /// use robid_symbolic::{Convention, Joint, Robot, Transform};
    /// // on a wall: frame 0 turned a quarter turn about the world's x, 1 m up
    /// let mut wall = Transform::numbers([0.0, 0.0, 1.0], [0.0; 3])?;
    /// wall.rpy[0] = Geometry::text("pi/2")?;
    /// let joints = vec![Joint::revolute("0", 0.0, 0.0, "0")?];
    /// let robot = Robot::new("arm", Convention::Modified, None, joints)?.with_base(Some(wall))?;
    /// let pose = robot.base_pose()?;
    /// assert_eq!(pose[2][3], 1.0);
    /// assert!((pose[2][1] - 1.0).abs() < 1e-15); // y_0 points up
    /// // the f64 nearest pi/2 is pi/2 exactly; an angle 1e-6 rad from it is refused
    /// let exact = Transform::numbers([0.0; 3], [std::f64::consts::FRAC_PI_2, 0.0, 0.0])?;
    /// let same = robot.clone().with_base(Some(exact))?;
    /// assert_eq!(same.base().unwrap().rpy[0].as_str(), "pi/2");
    /// let near = Transform::numbers([0.0; 3], [std::f64::consts::FRAC_PI_2 + 1e-6, 0.0, 0.0])?;
    /// assert!(robot.with_base(Some(near)).is_err());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn with_base(self, base: Option<Transform>) -> Result<Robot, DescriptionError> {
        let mut parts = self.into_parts();
        parts.base = base;
        parts.check(&Code).map_err(DescriptionError::from_errors)
    }

    /// The same robot with the tool frame `tool` in frame n (checked as in a description;
    /// `None` removes it).
    pub fn with_tool(self, tool: Option<Transform>) -> Result<Robot, DescriptionError> {
        let mut parts = self.into_parts();
        parts.tool = tool;
        parts.check(&Code).map_err(DescriptionError::from_errors)
    }

    /// The same robot under another name (checked as in a description).
    pub fn with_name(self, name: &str) -> Result<Robot, DescriptionError> {
        let mut parts = self.into_parts();
        parts.name = name.to_owned();
        parts.check(&Code).map_err(DescriptionError::from_errors)
    }

    /// The same robot with a value for geometric symbol `symbol`, which some
    /// DH value or gravity component must use (the error names the nearest
    /// symbol that is used).
    pub fn with_symbol_value(self, symbol: &str, value: f64) -> Result<Robot, DescriptionError> {
        let mut parts = self.into_parts();
        parts.values.retain(|(s, _)| s != symbol);
        parts.values.push((symbol.to_owned(), value));
        parts.check(&Code).map_err(DescriptionError::from_errors)
    }

    fn into_parts(self) -> Parts {
        Parts {
            name: self.name,
            convention: self.convention,
            gravity: self.gravity,
            joints: self.joints,
            base: self.base,
            tool: self.tool,
            values: self
                .symbols
                .into_iter()
                .filter_map(|(s, v)| Some((s, v?)))
                .collect(),
            unread_words: Vec::new(),
            measured: self.measured,
            uses: self.uses.0,
            joint_places: self.joint_places.0,
        }
    }
}

/// `[0, 0, -9.81]`.
pub(super) fn default_gravity() -> [Geometry; 3] {
    let g = Geometry::number(-9.81).unwrap_or_else(|_| Geometry::zero());
    [Geometry::zero(), Geometry::zero(), g]
}
