//! Reading a URDF as a robid [`Robot`] (docs/urdf.md).
//!
//! `xml.rs` reads the `<link>` and `<joint>` elements with every number checked and every
//! mistake located; `rigid.rs` holds rigid transforms and the angle rule; `chain.rs` builds
//! the tree and chooses the chain; `frames.rs` fits the modified-DH table to the joint
//! axes; `build.rs` makes the validated robot (name, limits, gravity); `inertial.rs` sums
//! each body's standard parameters; `write.rs` writes identified parameters back.

mod build;
mod chain;
mod frames;
mod inertial;
mod rigid;
mod write;
mod xml;

#[cfg(test)]
mod tests;

pub use chain::ChainSelection;
pub use inertial::{NEGLIGIBLE_SHARE, UnphysicalInertial, negligible};

use super::bounds::MAX_DESCRIPTION_LEN;
use super::file::Place;
use super::{DescriptionError, Inertial, JointKind, ParameterId, ParameterKind, Pose, Robot};
use frames::Axis;
use std::io::Read;
use std::path::Path;

/// A URDF chain as a robid robot, with what is needed to go back to the URDF's frames.
#[derive(Clone, Debug, PartialEq)]
pub struct UrdfChain {
    /// Modified DH, numeric, no drive terms, the URDF's limits; gravity in frame 0.
    pub robot: Robot,
    /// One per robid joint, base to tip.
    pub links: Vec<ChainLink>,
    /// robid frame 0 in the base link's frame.
    pub base: Pose,
    /// The tip link's frame in robid frame n.
    pub tool: Pose,
    /// What is valid but worth knowing: `file:line:column: what; what to do`.
    pub warnings: Vec<String>,
    /// The links of the chain's bodies whose `<inertial>` no body has (a zero mass with an
    /// inertia, moments breaking the triangle inequality), each also in a warning: the
    /// URDF's standard parameters are then no real robot's (docs/urdf.md#inertials).
    pub unphysical: Vec<UnphysicalInertial>,
}

impl UrdfChain {
    /// The URDF's value of standard parameter `id`: the inertial parameters of each chain
    /// link's body in robid's frame (`None` for a drive term, which a URDF does not give,
    /// or a link past the chain).
    pub fn inertial_value(&self, id: ParameterId) -> Option<f64> {
        let ParameterKind::Inertial(inertial) = id.kind else {
            return None;
        };
        let k = Inertial::ALL.iter().position(|&i| i == inertial)?;
        Some(self.links.get(id.link)?.inertial[k])
    }

    /// The largest magnitude of each kind of standard parameter among the chain's bodies:
    /// inertia entries, first moments, mass.
    fn largest(&self) -> [f64; 3] {
        self.links.iter().fold([0.0; 3], |[j, ms, m], link| {
            let p = &link.inertial;
            let top = |r: std::ops::Range<usize>, from: f64| {
                p[r].iter().fold(from, |a: f64, x| a.max(x.abs()))
            };
            [top(0..6, j), top(6..9, ms), m.max(p[9].abs())]
        })
    }

    /// Whether the body of robid link `j` (0-based; `links[j].inertial`) has no mass: its
    /// mass is 0 or [`negligible`] beside the largest of the chain's bodies (a mass of
    /// 1e-320 kg, written to mean 0, next to real ones; docs/urdf.md#inertials).
    pub fn massless(&self, j: usize) -> bool {
        self.links
            .get(j)
            .is_none_or(|link| negligible(link.inertial[9], self.largest()[2]))
    }

    /// Whether the body of robid link `j` (0-based) has neither mass nor inertia: each of
    /// its standard parameters is 0 or [`negligible`] beside the largest of its kind among
    /// the chain's bodies (inertia entries, first moments, masses).
    pub fn empty(&self, j: usize) -> bool {
        let largest = self.largest();
        self.links.get(j).is_none_or(|link| {
            link.inertial.iter().enumerate().all(|(k, &x)| {
                let kind = match k {
                    0..6 => 0,
                    6..9 => 1,
                    _ => 2,
                };
                negligible(x, largest[kind])
            })
        })
    }

    /// Whether the bodies of robid links `from..` (0-based) are all exactly 0 where
    /// [`UrdfChain::massless`] (`mass_only`) or [`UrdfChain::empty`] find them so, rather
    /// than only negligible: the messages say "0" then, and "0 or negligible" otherwise.
    pub fn exactly_zero(&self, from: usize, mass_only: bool) -> bool {
        self.links.iter().skip(from).all(|link| {
            if mass_only {
                link.inertial[9] == 0.0
            } else {
                link.inertial.iter().all(|&x| x == 0.0)
            }
        })
    }

    /// The URDF's inertials as the values of `robot.standard_parameters()`, drive terms 0
    /// (`robot` is this chain's robot, perhaps with drive terms added).
    pub fn standard_values(&self, robot: &Robot) -> Vec<f64> {
        robot
            .standard_parameters()
            .into_iter()
            .map(|p| self.inertial_value(p).unwrap_or(0.0))
            .collect()
    }

    /// Per robid link j, the segment its URDF body spans, both ends in robid frame j:
    /// from joint j's point (the URDF link's origin, on joint j's axis; for a prismatic
    /// joint with limits, moved back along the axis to where its bearing is at the end of
    /// the travel farthest from it) to joint j+1's point at q = 0 (the tip link's origin
    /// for the last link). What [`Robot::link_segments`] is for a description, from the
    /// URDF's joints rather than the fitted DH frames: a frame's origin lies at the foot
    /// of a common normal, which two skew axes can put metres from the links (axes 0.1 rad
    /// apart whose normal is 4 cm long and 1.5 m below the joints), so the segments
    /// between the frames' origins size and place no body of the robot.
    ///
    /// # Errors
    /// Never for a chain read from a URDF (its geometry is numeric); a symbol without a
    /// value otherwise.
    pub fn link_segments(&self) -> Result<Vec<[[f64; 3]; 2]>, crate::expr::Unbound> {
        let placements = self.robot.joint_placements()?;
        let point = |p: &Pose| [p[0][3], p[1][3], p[2][3]];
        let apply = |t: &Pose, v: [f64; 3]| -> [f64; 3] {
            std::array::from_fn(|i| t[i][0] * v[0] + t[i][1] * v[1] + t[i][2] * v[2] + t[i][3])
        };
        let n = self.links.len();
        Ok((0..n)
            .map(|j| {
                let mut from = point(&self.links[j].frame);
                let joint = &self.robot.joints()[j];
                if let (JointKind::Prismatic, Some([lo, hi])) = (joint.kind, joint.limits.position)
                {
                    // the bearing, fixed to the previous body, lies -q along z_j
                    from[2] -= if lo.abs() > hi.abs() { lo } else { hi };
                }
                let to = match self.links.get(j + 1) {
                    Some(next) => apply(&placements[j + 1].origin, point(&next.frame)),
                    None => point(&self.tool),
                };
                [from, to]
            })
            .collect())
    }
}

/// The rigid body robid joint j moves.
#[derive(Clone, Debug, PartialEq)]
pub struct ChainLink {
    /// The URDF joint (robid joint j).
    pub joint: String,
    /// Whether that joint is `continuous`: it turns without end, and URDF ignores the
    /// `lower` and `upper` of its `<limit>`, so the robot has no position limits for it.
    pub continuous: bool,
    /// The URDF link it moves.
    pub link: String,
    /// That URDF link's frame in robid frame j.
    pub frame: Pose,
    /// Links rigidly attached to it (through fixed joints, or joints off the chain held
    /// at zero).
    pub attached: Vec<AttachedLink>,
    /// Standard parameters `[XX XY XZ YY YZ ZZ MX MY MZ M]` of the whole body about the
    /// origin of robid frame j, in frame j.
    pub inertial: [f64; 10],
}

/// A URDF link rigidly attached to a chain link.
#[derive(Clone, Debug, PartialEq)]
pub struct AttachedLink {
    /// The URDF link.
    pub name: String,
    /// Its frame in the chain link's frame.
    pub frame: Pose,
}

impl Robot {
    /// Reads the chain `selection` of a URDF as a robid robot (docs/urdf.md); `file` names
    /// the text in errors and warnings.
    ///
    /// # Errors
    /// Malformed XML, missing or bad values, a link tree that is not a tree, a chain that
    /// cannot be chosen or modelled, or a DH table or limit outside robid's
    /// [`bounds`](super::bounds): each with its place and fix.
    ///
    /// # Examples
    /// ```
    /// use robid_symbolic::robot::ChainSelection;
    /// use robid_symbolic::Robot;
    /// let urdf = r#"<robot name="arm">
    ///   <link name="base"/>
    ///   <link name="upper"><inertial><mass value="2"/>
    ///     <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.05"/></inertial></link>
    ///   <link name="lower"/>
    ///   <joint name="shoulder" type="revolute"><parent link="base"/><child link="upper"/>
    ///     <origin xyz="0 0 0.3"/><axis xyz="0 0 1"/>
    ///     <limit lower="-3" upper="3" effort="50" velocity="2"/></joint>
    ///   <joint name="elbow" type="continuous"><parent link="upper"/><child link="lower"/>
    ///     <origin xyz="0.5 0 0" rpy="1.5707963267948966 0 0"/><axis xyz="0 0 1"/></joint>
    /// </robot>"#;
    /// let chain = Robot::from_urdf(urdf, "arm.urdf", &ChainSelection::default())?;
    /// assert_eq!(chain.robot.dof(), 2);
    /// assert_eq!(chain.links[1].joint, "elbow");
    /// assert!(chain.links[1].continuous && chain.robot.joints()[1].limits.position.is_none());
    /// assert_eq!(chain.links[0].inertial[9], 2.0);
    /// # Ok::<(), robid_symbolic::DescriptionError>(())
    /// ```
    pub fn from_urdf(
        text: &str,
        file: &str,
        selection: &ChainSelection,
    ) -> Result<UrdfChain, DescriptionError> {
        let place = Place { file, text };
        let urdf = xml::read(&place)?;
        let mut warnings = urdf.warnings.clone();
        let tree = chain::tree(&place, &urdf, &mut warnings)?;
        let chain = chain::choose(&place, &urdf, &tree, selection, &mut warnings)?;
        if let Some(w) = xml::zero_limits(&place, chain.joints.iter().map(|&j| &urdf.joints[j])) {
            warnings.push(w);
        }
        let unphysical = inertial::check(&place, &urdf, &chain, &mut warnings)?;
        let axes: Vec<Axis> = chain
            .joints
            .iter()
            .map(|&j| {
                let joint = &urdf.joints[j];
                let frame = chain.in_base[tree.ends[j].0].then(&joint.origin);
                Axis {
                    direction: frame.apply_vector(joint.axis),
                    point: frame.p,
                    hint: frame.apply_vector([1.0, 0.0, 0.0]),
                }
            })
            .collect();
        let fit = frames::fit(&axes);
        let name = build::robot_name(&place, &urdf, &mut warnings);
        let gravity = build::gravity(&tree.at_zero[chain.base], &fit);
        let gravity = build::level(&place, &urdf, &chain, gravity, &mut warnings);
        let robot = build::robot(&place, &urdf, &chain, &fit, gravity, &name, &mut warnings)?;
        warnings.extend(build::measured_twists(&place, &urdf, &chain, &fit));
        warnings.extend(build::calibrated_pairs(&place, &urdf, &tree, &chain, &fit));
        let links = chain
            .bodies
            .iter()
            .enumerate()
            .map(|(k, body)| {
                let to_frame = fit.frames[k + 1].inverse();
                let link = body[0];
                let in_link = chain.in_base[link].inverse();
                let mut parameters = [0.0; 10];
                for &l in body {
                    if let Some(i) = &urdf.links[l].inertial {
                        let p = inertial::parameters(&to_frame.then(&chain.in_base[l]), i);
                        parameters = inertial::sum(parameters, p);
                    }
                }
                let joint = &urdf.joints[chain.joints[k]];
                ChainLink {
                    joint: joint.name.clone(),
                    continuous: joint.kind == xml::JointType::Continuous,
                    link: urdf.links[link].name.clone(),
                    frame: to_frame.then(&chain.in_base[link]).pose(),
                    attached: body[1..]
                        .iter()
                        .map(|&a| AttachedLink {
                            name: urdf.links[a].name.clone(),
                            frame: in_link.then(&chain.in_base[a]).pose(),
                        })
                        .collect(),
                    inertial: parameters,
                }
            })
            .collect();
        let n = chain.joints.len();
        Ok(UrdfChain {
            robot,
            links,
            base: fit.frames[0].pose(),
            tool: fit.frames[n]
                .inverse()
                .then(&chain.in_base[chain.tip])
                .pose(),
            warnings: capped(warnings),
            unphysical,
        })
    }

    /// Reads a URDF file (at most [`MAX_DESCRIPTION_LEN`] bytes) like [`Robot::from_urdf`].
    ///
    /// # Errors
    /// The file cannot be read, is too long or not UTF-8, or [`Robot::from_urdf`]'s errors.
    pub fn from_urdf_file(
        path: &Path,
        selection: &ChainSelection,
    ) -> Result<UrdfChain, DescriptionError> {
        let file = path.display().to_string();
        let text = read_text(path, &file)?;
        Robot::from_urdf(&text, &file, selection)
    }
}

/// The text of a file of at most [`MAX_DESCRIPTION_LEN`] bytes.
fn read_text(path: &Path, file: &str) -> Result<String, DescriptionError> {
    let read_error = |reason: String| DescriptionError::Read {
        file: file.to_owned(),
        reason,
    };
    let handle =
        std::fs::File::open(path).map_err(|e| read_error(robid_core::names::io_problem(&e)))?;
    let mut bytes = Vec::new();
    handle
        .take(MAX_DESCRIPTION_LEN as u64 + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| read_error(e.to_string()))?;
    if bytes.len() > MAX_DESCRIPTION_LEN {
        return Err(read_error(format!(
            "it is longer than {MAX_DESCRIPTION_LEN} bytes, the most robid reads; meshes belong in their own files"
        )));
    }
    String::from_utf8(bytes).map_err(|e| {
        read_error(format!(
            "it is not UTF-8 text (invalid byte at offset {}); save it as UTF-8",
            e.utf8_error().valid_up_to()
        ))
    })
}

pub use write::write_inertials;

/// At most [`MAX_ERRORS`](super::error::MAX_ERRORS) warnings and a count of the rest (a
/// generated URDF of 5000 `<mimic>` elements naming no joint warned 5000 times).
fn capped(mut warnings: Vec<String>) -> Vec<String> {
    let most = super::error::MAX_ERRORS;
    if warnings.len() > most {
        let rest = warnings.len() - most;
        warnings.truncate(most);
        warnings.push(format!(
            "{rest} more warnings are not shown: fix the ones above and read the file again"
        ));
    }
    warnings
}
