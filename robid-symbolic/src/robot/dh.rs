//! Both DH conventions as modified-DH frames.
//!
//! A standard table Rz(theta_j) Tz(d_j) Tx(a_j) Rx(alpha_j) regroups as
//! Rz(theta_1) Tz(d_1) [Tx(a_1) Rx(alpha_1) Rz(theta_2) Tz(d_2)] ..., which is a
//! modified table with alpha'_j = alpha_(j-1), a'_j = a_(j-1) (zero for j = 1)
//! and the same theta and d. The user's standard frame j is then modified
//! frame j followed by the constant Tx(a_j) Rx(alpha_j), so standard-frame link
//! parameters map linearly to modified-frame ones (see `dynamics::link`).

use super::{Convention, Geometry, JointKind, Robot};

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
}
