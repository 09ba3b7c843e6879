//! Both DH conventions as modified-DH frames.
//!
//! A standard table Rz(theta_j) Tz(d_j) Tx(a_j) Rx(alpha_j) regroups as
//! Rz(theta_1) Tz(d_1) [Tx(a_1) Rx(alpha_1) Rz(theta_2) Tz(d_2)] ..., which is a
//! modified table with alpha'_j = alpha_(j-1), a'_j = a_(j-1) (zero for j = 1)
//! and the same theta and d. The user's standard frame j is then modified
//! frame j followed by the constant Tx(a_j) Rx(alpha_j), so standard-frame link
//! parameters map linearly to modified-frame ones (see `dynamics::link`).
//!
//! A modified table may add Khalil and Kleinfinger's `gamma_j`, `b_j` in front of a row
//! (frame j-1 -> j = Rz(gamma_j) Tz(b_j) Rx(alpha_j) Tx(a_j) Rz(theta_j) Tz(d_j),
//! docs/conventions.md#khalil-kleinfinger-general-frames); a standard table has none.
//! The numeric poses here also place the description's base and tool frames
//! (docs/conventions.md#base-and-tool-frames).

use super::{Convention, Geometry, JointKind, Robot, Transform};
use crate::expr::{Arena, Unbound};

/// One row in modified-DH form, plus the constant transform from the modified
/// link frame to the user's link frame (`user_alpha`, `user_a`; zero for a
/// modified table).
#[derive(Clone, Debug, PartialEq)]
pub struct FrameRow {
    /// Joint type.
    pub kind: JointKind,
    /// Khalil-Kleinfinger gamma_j: rotation about z_(j-1) before the row (0 for a DH row).
    pub gamma: Geometry,
    /// Khalil-Kleinfinger b_j: translation along z_(j-1) before the row (0 for a DH row).
    pub b: Geometry,
    /// Modified-DH alpha_j.
    pub alpha: Geometry,
    /// Modified-DH a_j.
    pub a: Geometry,
    /// d_j (offset for a prismatic joint).
    pub d: Geometry,
    /// theta_j (offset for a revolute joint).
    pub theta: Geometry,
    /// Rotation about x from the modified to the user's link frame.
    pub user_alpha: Geometry,
    /// Translation along x from the modified to the user's link frame.
    pub user_a: Geometry,
}

impl Robot {
    /// The table in modified-DH form, whatever the user's convention.
    pub fn frame_rows(&self) -> Vec<FrameRow> {
        let j = self.joints();
        (0..j.len())
            .map(|i| match self.convention {
                Convention::Modified => FrameRow {
                    kind: j[i].kind,
                    gamma: j[i].gamma.clone(),
                    b: j[i].b.clone(),
                    alpha: j[i].alpha.clone(),
                    a: j[i].a.clone(),
                    d: j[i].d.clone(),
                    theta: j[i].theta.clone(),
                    user_alpha: Geometry::zero(),
                    user_a: Geometry::zero(),
                },
                Convention::Standard => FrameRow {
                    kind: j[i].kind,
                    gamma: Geometry::zero(),
                    b: Geometry::zero(),
                    alpha: if i == 0 {
                        Geometry::zero()
                    } else {
                        j[i - 1].alpha.clone()
                    },
                    a: if i == 0 {
                        Geometry::zero()
                    } else {
                        j[i - 1].a.clone()
                    },
                    d: j[i].d.clone(),
                    theta: j[i].theta.clone(),
                    user_alpha: j[i].alpha.clone(),
                    user_a: j[i].a.clone(),
                },
            })
            .collect()
    }

    /// Each link's segment of the kinematic chain in its own (user's) frame, from the
    /// axis of the joint that moves it to the axis of the next joint, with the
    /// description's symbol values and every joint variable at its offset (m).
    ///
    /// Standard DH: link j runs from frame j-1's origin, at (-a_j, -d_j sin alpha_j,
    /// -d_j cos alpha_j) in frame j, to frame j's origin. Modified DH: from frame j's
    /// origin to frame j+1's, at Rz(gamma_(j+1)) (a_(j+1), -d_(j+1) sin alpha_(j+1),
    /// d_(j+1) cos alpha_(j+1)) + (0, 0, b_(j+1)); the last link of a modified table has
    /// no next joint and runs to the tool frame's origin when the description gives a
    /// `[tool]`, else its segment has length zero. The link of a prismatic joint with
    /// position limits slides along the joint's axis through its bearing on the previous
    /// link, so it reaches back along that axis to where the bearing is at the travel's end
    /// farthest from it (`d_j + q` of the largest size over the limits): standard DH, from
    /// frame j-1's origin at that travel, (-a_j, -(d_j + q) sin alpha_j, -(d_j + q) cos
    /// alpha_j); modified DH, from (0, 0, -(d_j + q)) (the Stanford arm's boom, a joint
    /// travel of 0.2 to 0.9 m, had a segment of length zero, too short for any inertia).
    /// The default prior of `robid feasible` models each link as a solid along this segment.
    ///
    /// # Errors
    /// A symbol the geometry uses has no value in the description.
    ///
    /// # Examples
    /// ```
    /// use robid_symbolic::{Convention, Joint, Robot};
    /// let robot = Robot::new(
    ///     "arm",
    ///     Convention::Standard,
    ///     None,
    ///     vec![Joint::revolute("0", 0.5, 0.0, "0")?, Joint::revolute("0", 0.3, 0.0, "0")?],
    /// )?;
    /// let segments = robot.link_segments()?;
    /// assert_eq!(segments[0], [[-0.5, 0.0, 0.0], [0.0, 0.0, 0.0]]);
    ///
    /// // a boom sliding 0.2 to 0.9 m along its axis reaches back 0.9 m to its bearing
    /// let mut boom = Joint::prismatic("0", 0.0, 0.0, "0")?;
    /// boom.limits.position = Some([0.2, 0.9]);
    /// let joints = vec![Joint::revolute("0", 0.0, 0.4, "0")?, boom];
    /// let robot = Robot::new("arm", Convention::Modified, None, joints)?;
    /// assert_eq!(robot.link_segments()?[1], [[0.0, 0.0, -0.9], [0.0; 3]]);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn link_segments(&self) -> Result<Vec<[[f64; 3]; 2]>, Unbound> {
        let rows = self.numeric_rows()?;
        let tool = self.tool_pose()?;
        let n = rows.len();
        // how far along its axis a prismatic link reaches back to its bearing: d_j + q at
        // the end of the travel farthest from it (None: revolute, or no limits to say)
        let travel = |j: usize| -> Option<f64> {
            let joint = &self.joints()[j];
            let [lo, hi] = joint.limits.position?;
            let d = rows[j][2];
            (joint.kind == JointKind::Prismatic).then(|| {
                if (d + lo).abs() > (d + hi).abs() {
                    d + lo
                } else {
                    d + hi
                }
            })
        };
        Ok((0..n)
            .map(|j| {
                let from = match (self.convention, travel(j)) {
                    (Convention::Standard, reach) => {
                        let [alpha, a, d, ..] = rows[j];
                        let reach = reach.unwrap_or(d);
                        [-a, -reach * alpha.sin(), -reach * alpha.cos()]
                    }
                    (Convention::Modified, Some(reach)) => [0.0, 0.0, -reach],
                    (Convention::Modified, None) => [0.0; 3],
                };
                match self.convention {
                    Convention::Standard => [from, [0.0; 3]],
                    Convention::Modified if j + 1 < n => {
                        let [alpha, a, d, _, gamma, b] = rows[j + 1];
                        let p = product(&[
                            rot_z(gamma),
                            trans_z(b),
                            rot_x(alpha),
                            trans_x(a),
                            trans_z(d),
                        ]);
                        [from, [p[0][3], p[1][3], p[2][3]]]
                    }
                    Convention::Modified => match tool {
                        Some(t) => [from, [t[0][3], t[1][3], t[2][3]]],
                        None => [from, [0.0; 3]],
                    },
                }
            })
            .collect())
    }

    /// Where each joint sits, for a description with joint frames (URDF): per joint, the
    /// pose of its frame (joint variable at zero; z its axis) in the previous joint's frame
    /// (the base frame for the first), and the pose of the user's DH link frame in it. Each
    /// joint frame moves with its link, turning about or sliding along its z axis, so the
    /// chain base -> joint 1 -> ... is a URDF chain whose link j carries link j's inertia
    /// placed by the second pose. Poses are 4x4 homogeneous matrices, row-major.
    ///
    /// Modified DH: joint j's frame is DH frame j, at Rz(gamma_j) Tz(b_j) Rx(alpha_j)
    /// Tx(a_j) Rz(theta_j) Tz(d_j) in frame j-1. Standard DH: joint j turns about z_(j-1),
    /// so its frame is DH frame j-1 (turned by the joint) and DH frame j lies at
    /// Rz(theta_j) Tz(d_j) Tx(a_j) Rx(alpha_j) in it. The first joint's frame is placed in
    /// the world frame: the description's `[base]` ([`Robot::base_pose`]) comes first.
    /// [`Robot::tool_placement`] places the tool frame the same way.
    ///
    /// # Errors
    /// A symbol the geometry uses has no value in the description.
    pub fn joint_placements(&self) -> Result<Vec<JointPlacement>, Unbound> {
        let rows = self.numeric_rows()?;
        let base = self.base_pose()?;
        let mut out: Vec<JointPlacement> = Vec::with_capacity(rows.len());
        for [alpha, a, d, theta, gamma, b] in rows {
            let mut placement = match self.convention {
                Convention::Modified => JointPlacement {
                    origin: product(&[
                        rot_z(gamma),
                        trans_z(b),
                        rot_x(alpha),
                        trans_x(a),
                        rot_z(theta),
                        trans_z(d),
                    ]),
                    link_frame: IDENTITY,
                },
                Convention::Standard => JointPlacement {
                    // DH frame j-1 in joint j-1's frame: the previous link's placement
                    origin: out.last().map_or(IDENTITY, |p| p.link_frame),
                    link_frame: product(&[rot_z(theta), trans_z(d), trans_x(a), rot_x(alpha)]),
                },
            };
            if out.is_empty() {
                placement.origin = product(&[base, placement.origin]);
            }
            out.push(placement);
        }
        Ok(out)
    }

    /// The pose of frame 0 in the world frame: the description's `[base]`, the identity
    /// without one.
    ///
    /// # Errors
    /// A symbol the base transform uses has no value in the description.
    pub fn base_pose(&self) -> Result<Pose, Unbound> {
        match self.base() {
            Some(t) => self.pose_of(t),
            None => Ok(IDENTITY),
        }
    }

    /// The pose of the tool frame in the user's frame n (the last link's frame), if the
    /// description gives a `[tool]`.
    ///
    /// # Errors
    /// A symbol the tool transform uses has no value in the description.
    pub fn tool_pose(&self) -> Result<Option<Pose>, Unbound> {
        self.tool().map(|t| self.pose_of(t)).transpose()
    }

    /// The pose of the tool frame in the last joint's frame (see
    /// [`Robot::joint_placements`]), if the description gives a `[tool]`: the tool pose in
    /// frame n, behind the last link's DH frame for a standard table.
    ///
    /// # Errors
    /// A symbol the geometry uses has no value in the description.
    ///
    /// # Examples
    /// ```
    /// use robid_symbolic::Robot;
    /// let text = "name = \"arm\"\nconvention = \"modified\"\n[tool]\nxyz = [0, 0, 0.1]\n\
    ///             [[joints]]\n";
    /// let robot = Robot::from_toml(text, "arm.toml")?;
    /// let tool = robot.tool_placement()?.unwrap();
    /// assert_eq!(tool[2][3], 0.1);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn tool_placement(&self) -> Result<Option<Pose>, Unbound> {
        let Some(tool) = self.tool_pose()? else {
            return Ok(None);
        };
        let last = self.joint_placements()?.last().map(|p| p.link_frame);
        Ok(Some(product(&[last.unwrap_or(IDENTITY), tool])))
    }

    /// The gravity vector in the world frame (the description's `gravity`) at its symbol
    /// values.
    pub fn gravity_values(&self) -> Result<[f64; 3], Unbound> {
        let mut arena = Arena::new();
        let ids: Vec<_> = self
            .gravity()
            .iter()
            .map(|g| g.to_expr(&mut arena))
            .collect();
        let v = self.evaluate(&mut arena, &ids)?;
        Ok([v[0], v[1], v[2]])
    }

    /// A transform at the description's symbol values.
    fn pose_of(&self, t: &Transform) -> Result<Pose, Unbound> {
        let mut arena = Arena::new();
        let ids: Vec<_> = t
            .xyz
            .iter()
            .chain(&t.rpy)
            .map(|g| g.to_expr(&mut arena))
            .collect();
        let v = self.evaluate(&mut arena, &ids)?;
        Ok(product(&[
            trans_x(v[0]),
            trans_y(v[1]),
            trans_z(v[2]),
            rot_z(v[5]),
            rot_y(v[4]),
            rot_x(v[3]),
        ]))
    }

    /// Per joint `[alpha, a, d, theta, gamma, b]` at the description's symbol values.
    pub(super) fn numeric_rows(&self) -> Result<Vec<[f64; 6]>, Unbound> {
        let mut arena = Arena::new();
        let mut ids = Vec::new();
        for joint in self.joints() {
            for g in [
                &joint.alpha,
                &joint.a,
                &joint.d,
                &joint.theta,
                &joint.gamma,
                &joint.b,
            ] {
                ids.push(g.to_expr(&mut arena));
            }
        }
        let v = self.evaluate(&mut arena, &ids)?;
        Ok(v.chunks(6)
            .map(|c| [c[0], c[1], c[2], c[3], c[4], c[5]])
            .collect())
    }

    /// `ids` at the description's symbol values.
    fn evaluate(&self, arena: &mut Arena, ids: &[crate::expr::Id]) -> Result<Vec<f64>, Unbound> {
        let mut pairs = Vec::new();
        for (name, value) in self.symbols() {
            pairs.push((name.as_str(), value.ok_or_else(|| Unbound(name.clone()))?));
        }
        let values = arena.values(&pairs);
        arena.eval(ids, &values)
    }
}

/// A 4x4 homogeneous transform, row-major.
pub type Pose = [[f64; 4]; 4];

/// Where one joint sits (see [`Robot::joint_placements`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointPlacement {
    /// The joint's frame (joint variable at zero) in the previous joint's frame.
    pub origin: Pose,
    /// The user's DH frame of the link the joint moves, in the joint's frame.
    pub link_frame: Pose,
}

const IDENTITY: Pose = [
    [1.0, 0.0, 0.0, 0.0],
    [0.0, 1.0, 0.0, 0.0],
    [0.0, 0.0, 1.0, 0.0],
    [0.0, 0.0, 0.0, 1.0],
];

fn product(poses: &[Pose]) -> Pose {
    poses.iter().fold(IDENTITY, |acc, p| {
        std::array::from_fn(|i| std::array::from_fn(|k| (0..4).map(|m| acc[i][m] * p[m][k]).sum()))
    })
}

fn rot_x(angle: f64) -> Pose {
    let (s, c) = angle.sin_cos();
    [
        [1.0, 0.0, 0.0, 0.0],
        [0.0, c, -s, 0.0],
        [0.0, s, c, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ]
}

fn rot_y(angle: f64) -> Pose {
    let (s, c) = angle.sin_cos();
    [
        [c, 0.0, s, 0.0],
        [0.0, 1.0, 0.0, 0.0],
        [-s, 0.0, c, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ]
}

fn rot_z(angle: f64) -> Pose {
    let (s, c) = angle.sin_cos();
    [
        [c, -s, 0.0, 0.0],
        [s, c, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ]
}

fn trans_x(length: f64) -> Pose {
    let mut p = IDENTITY;
    p[0][3] = length;
    p
}

fn trans_y(length: f64) -> Pose {
    let mut p = IDENTITY;
    p[1][3] = length;
    p
}

fn trans_z(length: f64) -> Pose {
    let mut p = IDENTITY;
    p[2][3] = length;
    p
}
