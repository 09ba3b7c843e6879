//! Both DH conventions as modified-DH frames.
//!
//! A standard table Rz(theta_j) Tz(d_j) Tx(a_j) Rx(alpha_j) regroups as
//! Rz(theta_1) Tz(d_1) [Tx(a_1) Rx(alpha_1) Rz(theta_2) Tz(d_2)] ..., which is a
//! modified table with alpha'_j = alpha_(j-1), a'_j = a_(j-1) (zero for j = 1)
//! and the same theta and d. The user's standard frame j is then modified
//! frame j followed by the constant Tx(a_j) Rx(alpha_j), so standard-frame link
//! parameters map linearly to modified-frame ones (see `dynamics::link`).

use super::{Convention, Geometry, JointKind, Robot};
use crate::expr::{Arena, Unbound};

/// One row in modified-DH form, plus the constant transform from the modified
/// link frame to the user's link frame (`user_alpha`, `user_a`; zero for a
/// modified table).
#[derive(Clone, Debug, PartialEq)]
pub struct FrameRow {
    /// Joint type.
    pub kind: JointKind,
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
                    alpha: j[i].alpha.clone(),
                    a: j[i].a.clone(),
                    d: j[i].d.clone(),
                    theta: j[i].theta.clone(),
                    user_alpha: Geometry::zero(),
                    user_a: Geometry::zero(),
                },
                Convention::Standard => FrameRow {
                    kind: j[i].kind,
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
    /// origin to frame j+1's, at (a_(j+1), -d_(j+1) sin alpha_(j+1), d_(j+1) cos
    /// alpha_(j+1)); the last link of a modified table has no next joint and gets a
    /// segment of length zero. The default prior of `robid feasible` models each link
    /// as a solid along this segment.
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
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn link_segments(&self) -> Result<Vec<[[f64; 3]; 2]>, Unbound> {
        let rows = self.numeric_rows()?;
        let n = rows.len();
        Ok((0..n)
            .map(|j| match self.convention {
                Convention::Standard => {
                    let [alpha, a, d, _] = rows[j];
                    [[-a, -d * alpha.sin(), -d * alpha.cos()], [0.0; 3]]
                }
                Convention::Modified if j + 1 < n => {
                    let [alpha, a, d, _] = rows[j + 1];
                    [[0.0; 3], [a, -d * alpha.sin(), d * alpha.cos()]]
                }
                Convention::Modified => [[0.0; 3]; 2],
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
    /// Modified DH: joint j's frame is DH frame j, at Rx(alpha_j) Tx(a_j) Rz(theta_j)
    /// Tz(d_j) in frame j-1. Standard DH: joint j turns about z_(j-1), so its frame is DH
    /// frame j-1 (turned by the joint) and DH frame j lies at Rz(theta_j) Tz(d_j) Tx(a_j)
    /// Rx(alpha_j) in it.
    ///
    /// # Errors
    /// A symbol the geometry uses has no value in the description.
    pub fn joint_placements(&self) -> Result<Vec<JointPlacement>, Unbound> {
        let rows = self.numeric_rows()?;
        let mut out: Vec<JointPlacement> = Vec::with_capacity(rows.len());
        for [alpha, a, d, theta] in rows {
            let placement = match self.convention {
                Convention::Modified => JointPlacement {
                    origin: product(&[rot_x(alpha), trans_x(a), rot_z(theta), trans_z(d)]),
                    link_frame: IDENTITY,
                },
                Convention::Standard => JointPlacement {
                    // DH frame j-1 in joint j-1's frame: the previous link's placement
                    origin: out.last().map_or(IDENTITY, |p| p.link_frame),
                    link_frame: product(&[rot_z(theta), trans_z(d), trans_x(a), rot_x(alpha)]),
                },
            };
            out.push(placement);
        }
        Ok(out)
    }

    /// Per joint `[alpha, a, d, theta]` at the description's symbol values.
    fn numeric_rows(&self) -> Result<Vec<[f64; 4]>, Unbound> {
        let mut arena = Arena::new();
        let mut ids = Vec::new();
        for joint in self.joints() {
            for g in [&joint.alpha, &joint.a, &joint.d, &joint.theta] {
                ids.push(g.to_expr(&mut arena));
            }
        }
        let mut pairs = Vec::new();
        for (name, value) in self.symbols() {
            pairs.push((name.as_str(), value.ok_or_else(|| Unbound(name.clone()))?));
        }
        let values = arena.values(&pairs);
        let v = arena.eval(&ids, &values)?;
        Ok(v.chunks(4).map(|c| [c[0], c[1], c[2], c[3]]).collect())
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

fn trans_z(length: f64) -> Pose {
    let mut p = IDENTITY;
    p[2][3] = length;
    p
}
