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
        let mut arena = Arena::new();
        let mut ids = Vec::new();
        for joint in self.joints() {
            for g in [&joint.alpha, &joint.a, &joint.d] {
                ids.push(g.to_expr(&mut arena));
            }
        }
        let mut pairs = Vec::new();
        for (name, value) in self.symbols() {
            pairs.push((name.as_str(), value.ok_or_else(|| Unbound(name.clone()))?));
        }
        let values = arena.values(&pairs);
        let v = arena.eval(&ids, &values)?;
        let n = self.dof();
        let row = |j: usize| (v[3 * j], v[3 * j + 1], v[3 * j + 2]);
        Ok((0..n)
            .map(|j| match self.convention {
                Convention::Standard => {
                    let (alpha, a, d) = row(j);
                    [[-a, -d * alpha.sin(), -d * alpha.cos()], [0.0; 3]]
                }
                Convention::Modified if j + 1 < n => {
                    let (alpha, a, d) = row(j + 1);
                    [[0.0; 3], [a, -d * alpha.sin(), d * alpha.cos()]]
                }
                Convention::Modified => [[0.0; 3]; 2],
            })
            .collect())
    }
}
