//! Reading a robot description on the command line: the one place that reads the file (a
//! TOML description, or a URDF by its extension, docs/urdf.md), prints its warnings
//! (file:line, e.g. a `drive` key that TOML gave to the last joint) and applies `--drive`,
//! `--base` and `--tip`, so that every subcommand sees the same robot.

use std::path::Path;

use robid_runtime::Model;
use robid_runtime::data::ParameterFile;
use robid_symbolic::regroup::{BaseParameter, folded_offsets};
use robid_symbolic::robot::{ChainSelection, DriveTerm, ParameterId, UrdfChain};
use robid_symbolic::{DescriptionError, Drive, JointKind, Robot};

use super::{Error, out};

/// The help of every subcommand's description argument, one text for all of them (each
/// subcommand reads TOML and URDF alike, see [`load`]): `#[arg(help = robot_help!())]`, or
/// `robot_help!("what the subcommand reads from it")`.
macro_rules! robot_help {
    () => {
        "Robot description file (TOML, or URDF by its extension)"
    };
    ($what:literal) => {
        concat!($crate::cli::description::robot_help!(), ": ", $what)
    };
}
pub(crate) use robot_help;

/// The flags of every subcommand that reads a description: `--drive`, and for a URDF the
/// chain (`--base`, `--tip`).
#[derive(Debug, Clone, Default, clap::Args)]
pub(crate) struct DescriptionFlags {
    /// Drive terms of every joint, e.g. `Ia,Fv,Fc,Fo`, or `none` for the rigid bodies alone
    /// (replaces the description's; give the same terms to every subcommand of one job).
    #[arg(long, value_delimiter = ',')]
    pub(crate) drive: Vec<String>,
    /// URDF only: the link the chain starts from (default: the root link).
    #[arg(long = "base", value_name = "LINK")]
    pub(crate) base_link: Option<String>,
    /// URDF only: the link the chain ends at (default: where the movable joints end, when
    /// they form one path; a tree needs it).
    #[arg(long = "tip", value_name = "LINK")]
    pub(crate) tip_link: Option<String>,
}

/// A description as read: the robot, and for a URDF the chain with the URDF's own
/// inertials and frames.
#[derive(Debug)]
pub(crate) struct Description {
    /// The robot, with the drive terms of `--drive`.
    pub(crate) robot: Robot,
    /// The chain of a URDF (`None` for a TOML description).
    pub(crate) urdf: Option<UrdfChain>,
}

impl Description {
    /// A URDF's value of the inertial parameter `name` (`None` for a TOML description, a
    /// drive term or an unknown name).
    pub(crate) fn urdf_inertial(&self, name: &str) -> Option<f64> {
        self.urdf.as_ref()?.inertial_value(name.parse().ok()?)
    }

    /// The base parameters of `model` (this description's model): those of the parameter
    /// file `parameters` (`--parameters`) when given, else the URDF's own inertials; an
    /// error for a TOML description without a parameter file.
    pub(crate) fn base_parameters(
        &self,
        parameters: Option<&Path>,
        model: &dyn Model,
    ) -> Result<Vec<f64>, Error> {
        match parameters {
            Some(path) => Ok(read_parameters(path, true)?.base_parameters(model)?),
            None => self.urdf_base_parameters(model)?.ok_or_else(|| {
                "--parameters: give a parameter file with a [standard] or a [base] table (see \
                 docs/command-line.md); only a URDF description carries its own inertials"
                    .into()
            }),
        }
    }

    /// With a URDF's own inertials, the joints (numbered from 1) whose torque they leave
    /// out: `empty`, those that move only links without mass or inertia (their torque is 0
    /// at every state), `sliding`, the other prismatic joints that move only links without
    /// mass (their force is 0 at every state: it holds only the masses it moves), and
    /// `massless`, the other revolute joints that move only links without mass (their
    /// torque holds no gravity). Each is a run of joints up to the last, since a joint
    /// moves every link after it. A mass or inertia counts as none when it is 0 or
    /// negligible beside the chain's largest (`UrdfChain::massless` and `empty`: a mass of
    /// 1e-320 kg, written to mean 0, is none). All empty for a TOML description.
    pub(crate) fn urdf_unloaded(&self) -> Unloaded {
        let Some(chain) = &self.urdf else {
            return Unloaded::default();
        };
        // the first joint of the run up to the last whose links all have `holds`
        let first = |holds: &dyn Fn(usize) -> bool| {
            let n = chain.links.len();
            let after = (0..n).rposition(|k| !holds(k)).map_or(0, |k| k + 1);
            (after < n).then_some(after + 1)
        };
        let empty_from = first(&|k| chain.empty(k));
        let massless_from = first(&|k| chain.massless(k));
        let n = chain.links.len();
        let empty: Vec<usize> = empty_from.map_or(Vec::new(), |j| (j..=n).collect());
        let (sliding, massless) = massless_from
            .map_or(Vec::new(), |j| {
                (j..=n).filter(|j| !empty.contains(j)).collect()
            })
            .into_iter()
            .partition(|&j| self.robot.joints()[j - 1].kind == JointKind::Prismatic);
        Unloaded {
            empty,
            sliding,
            massless,
        }
    }

    /// The cause, as in "joint 2 (`j2`) of FILE moves only links without mass or inertia:
    /// `flange`, `tool0` (no `<inertial>` element, or an empty one)": `joints` (numbered
    /// from 1, not empty) of the URDF `file` and the links the lowest of them moves, all
    /// `empty` (without mass or inertia) or all without mass.
    pub(crate) fn unloaded_cause(&self, file: &Path, joints: &[usize], empty: bool) -> String {
        let Some(chain) = &self.urdf else {
            return String::new();
        };
        let named: Vec<String> = joints
            .iter()
            .map(|&j| {
                let name = chain.links.get(j - 1).map_or("?", |l| l.joint.as_str());
                format!("{j} (`{name}`)")
            })
            .collect();
        let (named, moves) = match named.split_last() {
            Some((last, [])) => (format!("joint {last}"), "moves"),
            Some((last, first)) => (format!("joints {} and {last}", first.join(", ")), "move"),
            None => (String::new(), "moves"),
        };
        let lowest = joints.first().copied().unwrap_or(1).max(1);
        let links: Vec<String> = chain
            .links
            .iter()
            .skip(lowest - 1)
            .flat_map(|link| {
                std::iter::once(&link.link).chain(link.attached.iter().map(|a| &a.name))
            })
            .map(|name| format!("`{name}`"))
            .collect();
        let file = file.display();
        let links = links.join(", ");
        let exact = chain.exactly_zero(lowest - 1, !empty);
        let share = robid_symbolic::robot::NEGLIGIBLE_SHARE;
        match (empty, exact) {
            (true, true) => format!(
                "{named} of {file} {moves} only links without mass or inertia: {links} (no \
                 `<inertial>` element, or an empty one)"
            ),
            (true, false) => format!(
                "{named} of {file} {moves} only links without mass or inertia: {links} (no \
                 `<inertial>` element, an empty one, or values negligible beside the chain's \
                 largest: below {share:e} of it, or subnormal such as 1e-320)"
            ),
            (false, true) => format!("{named} of {file} {moves} only links without mass: {links}"),
            (false, false) => format!(
                "{named} of {file} {moves} only links without mass: {links} (masses 0 or \
                 negligible beside the chain's largest: below {share:e} of it, or subnormal \
                 such as 1e-320)"
            ),
        }
    }

    /// "0", or "0 or negligible" when the links of `joints` (the lowest's and those after
    /// it) are not all exactly 0 in what makes them unloaded (their masses, or everything).
    fn zero(&self, joints: &[usize], mass_only: bool) -> &'static str {
        let lowest = joints.first().copied().unwrap_or(1).max(1);
        match &self.urdf {
            Some(chain) if !chain.exactly_zero(lowest - 1, mass_only) => "0 or negligible",
            _ => "0",
        }
    }

    /// With a URDF: warns about the joints whose torque its own inertials leave without
    /// gravity (they move only links without mass) or 0 (links without mass or inertia),
    /// naming the joints, the links and the fix, for the runs that use those inertials
    /// (`torques`, `emit`): "warning: CAUSE, so {inertials} its torque tau2 is 0 {when};
    /// give these links `<inertial>` elements with their mass and inertia, {fix}". Nothing
    /// for a TOML description.
    pub(crate) fn warn_unloaded(&self, file: &Path, inertials: &str, when: &str, fix: &str) {
        let unloaded = self.urdf_unloaded();
        let kinds = [
            (&unloaded.massless, Kind::Massless),
            (&unloaded.sliding, Kind::Sliding),
            (&unloaded.empty, Kind::Empty),
        ];
        for (joints, kind) in kinds {
            if joints.is_empty() {
                continue;
            }
            let one = joints.len() == 1;
            let is = if one { "is" } else { "are" };
            let (its, consequence, link_fix) = match kind {
                Kind::Empty => (
                    if one { "its torque" } else { "their torques" },
                    format!("{is} {} {when}", self.zero(joints, false)),
                    "give these links `<inertial>` elements with their mass and inertia",
                ),
                Kind::Sliding => (
                    if one { "its force" } else { "their forces" },
                    format!(
                        "{is} {} {when} (a sliding joint's force holds only the masses it moves)",
                        self.zero(joints, true)
                    ),
                    "give them their masses in their `<inertial>` elements",
                ),
                Kind::Massless => (
                    if one { "its torque" } else { "their torques" },
                    format!(
                        "{} no gravity, only the inertia of these links",
                        if one { "holds" } else { "hold" }
                    ),
                    "give them their masses in their `<inertial>` elements",
                ),
            };
            let empty = kind == Kind::Empty;
            super::out::warn(format_args!(
                "warning: {}, so {inertials} {its} {} {consequence}; {link_fix}, {fix}",
                self.unloaded_cause(file, joints, empty),
                torque_names(joints),
            ));
        }
    }

    /// The base parameters of `model` (this description's model) from the URDF's own
    /// `<inertial>` elements, drive terms 0; `None` for a TOML description.
    pub(crate) fn urdf_base_parameters(
        &self,
        model: &dyn Model,
    ) -> Result<Option<Vec<f64>>, Error> {
        let Some(chain) = &self.urdf else {
            return Ok(None);
        };
        let names = robid_runtime::model::standard_parameter_names(model);
        let standard: Vec<f64> = names
            .iter()
            .map(|name| {
                name.parse()
                    .ok()
                    .and_then(|id| chain.inertial_value(id))
                    .unwrap_or(0.0)
            })
            .collect();
        let mut base = vec![0.0; model.base_parameter_count()];
        model.base_from_standard_into(&standard, &mut base)?;
        Ok(Some(base))
    }
}

/// Which of [`Unloaded`]'s lists a warning is about.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Kind {
    Empty,
    Sliding,
    Massless,
}

/// The joints whose torque a URDF's own inertials leave out ([`Description::urdf_unloaded`]).
#[derive(Debug, Default, PartialEq, Eq)]
pub(crate) struct Unloaded {
    /// Joints that move only links without mass or inertia: their torque is 0.
    pub(crate) empty: Vec<usize>,
    /// The other prismatic joints that move only links without mass: their force is 0.
    pub(crate) sliding: Vec<usize>,
    /// The other (revolute) joints that move only links without mass: their torque holds
    /// no gravity.
    pub(crate) massless: Vec<usize>,
}

/// `tau2` or `tau1 and tau2`, the torques of `joints` (numbered from 1).
pub(crate) fn torque_names(joints: &[usize]) -> String {
    let names: Vec<String> = joints.iter().map(|j| format!("tau{j}")).collect();
    match names.split_last() {
        Some((last, [])) => last.clone(),
        Some((last, first)) => format!("{} and {last}", first.join(", ")),
        None => String::new(),
    }
}

/// A URDF error about the chain's choice, told in terms of `--base` and `--tip` (the
/// library names its `ChainSelection` fields, one or both); any other error as it is.
fn as_flags(e: DescriptionError) -> Error {
    match e {
        DescriptionError::Argument {
            argument,
            message,
            help,
        } if argument.contains("ChainSelection::") => {
            let flag = match (
                argument.contains("ChainSelection::base"),
                argument.contains("ChainSelection::tip"),
            ) {
                (true, true) => "--base and --tip",
                (_, true) => "--tip",
                _ => "--base",
            };
            format!("{flag}: {message}; {help}").into()
        }
        other => other.into(),
    }
}

/// Which joints of `robot` are prismatic, for a config's `prismatic`
/// (`robid_runtime::data::Config::prismatic`): their columns are lengths, which
/// `units.angle` leaves as read.
pub(crate) fn prismatic(robot: &Robot) -> Vec<bool> {
    robot
        .joints()
        .iter()
        .map(|j| j.kind == JointKind::Prismatic)
        .collect()
}

/// Whether `path` names a URDF (by its extension, `.urdf` in any case).
pub(crate) fn is_urdf(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("urdf"))
}

/// The drive terms named on the command line (`Ia`, `Fv`, `Fc`, `Fo`, or `none` alone: no
/// drive term, whatever the description has); `None` without `--drive`.
pub(crate) fn parse_drive(names: &[String]) -> Result<Option<Drive>, Error> {
    if names.is_empty() {
        return Ok(None);
    }
    let mut d = Drive::NONE;
    if let [only] = names
        && only.trim() == "none"
    {
        return Ok(Some(d));
    }
    for n in names.iter().map(|n| n.trim()) {
        if n == "none" {
            return Err(
                "--drive: `none` is alone or not at all (none removes every drive term); \
                 name the terms, or give none"
                    .into(),
            );
        }
        let term = n.parse::<DriveTerm>().map_err(|e| {
            format!(
                "--drive: unknown term `{}`; {}, or `none` alone for no drive term",
                robid_runtime::names::short(n),
                e.expected
            )
        })?;
        if d.has(term) {
            return Err(format!("--drive: `{n}` is named twice; name each term once").into());
        }
        d.add(term);
    }
    Ok(Some(d))
}

/// Reads the description at `path`, warns on stderr about what it probably does not mean,
/// and gives every joint the drive terms of `--drive` when any are named.
pub(crate) fn read(path: &Path, flags: &DescriptionFlags) -> Result<Robot, Error> {
    Ok(load(path, flags)?.robot)
}

/// Reads the description at `path` like [`read`], keeping a URDF's chain.
pub(crate) fn load(path: &Path, flags: &DescriptionFlags) -> Result<Description, Error> {
    let drive = parse_drive(&flags.drive)?;
    let (mut robot, urdf, warnings) = if is_urdf(path) {
        let selection = ChainSelection {
            base: flags.base_link.clone(),
            tip: flags.tip_link.clone(),
        };
        let chain = Robot::from_urdf_file(path, &selection).map_err(as_flags)?;
        // a URDF's warnings are about the file, whatever --drive says
        for w in &chain.warnings {
            out::warn(format_args!("warning: {w}"));
        }
        (chain.robot.clone(), Some(chain), Vec::new())
    } else {
        if let Some(flag) = [("--base", &flags.base_link), ("--tip", &flags.tip_link)]
            .into_iter()
            .find_map(|(flag, value)| value.as_ref().map(|_| flag))
        {
            return Err(format!(
                "{flag} chooses the chain of a URDF, but {} is a TOML description (a DH table is \
                 one chain already); drop {flag}, or give the robot's .urdf file",
                path.display()
            )
            .into());
        }
        let (robot, warnings) = Robot::from_file_with_warnings(path)?;
        (robot, None, warnings)
    };
    match drive {
        Some(d) => robot = robot.with_drive(d),
        None => {
            for w in &warnings {
                out::warn(format_args!("warning: {w}"));
            }
        }
    }
    Ok(Description { robot, urdf })
}

/// Warns about each drive offset the regrouping folded into other base parameters
/// ([`folded_offsets`]): only its sum with the weight along the joint's axis is
/// identifiable, and the gravity vector holds it, which `robid model` shows and `robid emit`
/// writes into `gravity`.
pub(crate) fn warn_folded_offsets(standard: &[ParameterId], base: &[BaseParameter]) {
    for folded in folded_offsets(standard, base) {
        let joint = folded.offset.link + 1;
        let into: Vec<String> = folded.into.iter().map(|b| format!("`{b}`")).collect();
        out::warn(format_args!(
            "warning: the drive offset `{}` of joint {joint} and the weight along its axis are \
             one constant force (the axis keeps a component of gravity whatever the joints \
             do): only their sum is identifiable, folded into {}, and the gravity vector g(q) \
             holds the offset; where g(q) is used on its own, describe joint {joint} without \
             `Fo` (a `drive` key in its [[joints]] entry) \
             (docs/dynamics.md#drive-offsets-inside-the-weight)",
            folded.offset,
            into.join(", ")
        ));
    }
}

/// Reads the parameter file at `path`, warning about each link whose values no body has
/// (`ParameterFile::unphysical`: moments that break the triangle inequality), as a URDF's
/// such inertials are warned about; the readers' errors are the impossible values.
/// `missing_is_zero`: a missing value counts as 0 (false for a prior, whose missing values
/// are free: its links with missing values are not judged).
pub(crate) fn read_parameters(path: &Path, missing_is_zero: bool) -> Result<ParameterFile, Error> {
    let file = ParameterFile::read(path)?;
    for w in file.unphysical(missing_is_zero) {
        out::warn(format_args!("warning: {w}"));
    }
    Ok(file)
}
