//! The closed-form grouping rules of Gautier and Khalil, applied from the last
//! joint down to joint 2 on the link parameters in modified-DH frames
//! (Gautier and Khalil 1990; Khalil and Dombre 2002, the chapter on base inertial
//! parameters; derived in docs/regrouping.md#revolute-joints and
//! docs/regrouping.md#prismatic-joints).
//!
//! The rules are not tabulated here but derived: for a revolute joint j the
//! part of link j that is invariant under rotation about z_j, i.e. the inertia
//! YYj diag(1, 1, 0), the first moment (0, 0, MZj) and the mass Mj, moves
//! rigidly into link j-1 through the constant part of the joint transform
//! (R = Rx(alpha_j), origin P_j = (a_j, -S d_j, C d_j)) by the parallel-axis
//! transfer; this reproduces XXRj = XXj - YYj, XXR(j-1) = XX(j-1) + YYj +
//! 2 d MZj + d^2 Mj, ... exactly. For a prismatic joint the inertia of link j
//! (invariant under translation along z_j) moves into link j-1, rotated by the
//! constant R = Rx(alpha_j) Rz(theta_j).
//!
//! With Khalil and Kleinfinger's gamma_j and b_j (docs/conventions.md#khalil-kleinfinger-general-frames)
//! the constant part of the joint transform gains Rz(gamma_j) Tz(b_j) in front: R =
//! Rz(gamma_j) Rx(alpha_j) and P_j = Rz(gamma_j) (a_j, -S d_j, C d_j) + (0, 0, b_j) for a
//! revolute joint, R = Rz(gamma_j) Rx(alpha_j) Rz(theta_j) for a prismatic one; for a DH
//! row (both 0) nothing changes.

use crate::dynamics::LinkParameters;
use crate::dynamics::link::transfer;
use crate::dynamics::vector::{self, Mat3};
use crate::expr::{Arena, Id};
use crate::robot::{FrameRow, JointKind, ParameterKind};

/// Slot indices: 0..6 inertia, 6..9 first moment, 9 mass, 10..14 Ia Fv Fc Fo.
pub(crate) const SLOT_YY: usize = 3;

/// Applies the rules in place: a parameter moved into the parent link leaves its slot at
/// zero.
pub(crate) fn apply(arena: &mut Arena, rows: &[FrameRow], links: &mut [LinkParameters]) {
    let n = links.len();
    for j in (1..n).rev() {
        let row = &rows[j];
        let alpha = row.alpha.to_expr(arena);
        let (s, c) = (arena.sin(alpha), arena.cos(alpha));
        let zero = arena.zero();
        let one = arena.one();
        let ns = arena.neg(s);
        let rx: Mat3 = [[one, zero, zero], [zero, c, ns], [zero, s, c]];
        let gamma = row.gamma.to_expr(arena);
        let rz = (!arena.is_zero(gamma)).then(|| vector::rot_z(arena, gamma));
        let b = row.b.to_expr(arena);
        let mut moved = LinkParameters::zero(arena);
        let l = links[j];
        match row.kind {
            JointKind::Revolute => {
                let d = row.d.to_expr(arena);
                let a = row.a.to_expr(arena);
                let sd = arena.mul2(s, d);
                let mut p = [a, arena.neg(sd), arena.mul2(c, d)];
                let mut r = rx;
                if let Some(rz) = &rz {
                    p = vector::mat_vec(arena, rz, p);
                    r = vector::mat_mul(arena, rz, &rx);
                }
                if !arena.is_zero(b) {
                    p[2] = arena.add2(p[2], b);
                }
                let yy = l.inertia[SLOT_YY];
                moved.inertia[0] = yy;
                moved.inertia[SLOT_YY] = yy;
                moved.first_moment[2] = l.first_moment[2];
                moved.mass = l.mass;
                links[j].inertia[0] = arena.sub(l.inertia[0], yy);
                links[j].inertia[SLOT_YY] = zero;
                links[j].first_moment[2] = zero;
                links[j].mass = zero;
                let into_parent = transfer(arena, moved, &r, p);
                add_inertial(arena, &mut links[j - 1], &into_parent);
            }
            JointKind::Prismatic => {
                let theta = row.theta.to_expr(arena);
                let (st, ct) = (arena.sin(theta), arena.cos(theta));
                let mut r = vector::rot_x_rot_z(arena, s, c, st, ct);
                if let Some(rz) = &rz {
                    r = vector::mat_mul(arena, rz, &r);
                }
                moved.inertia = l.inertia;
                links[j].inertia = [zero; 6];
                let into_parent = transfer(arena, moved, &r, [zero; 3]);
                add_inertial(arena, &mut links[j - 1], &into_parent);
            }
        }
    }
}

fn add_inertial(arena: &mut Arena, target: &mut LinkParameters, extra: &LinkParameters) {
    for k in 0..6 {
        target.inertia[k] = arena.add2(target.inertia[k], extra.inertia[k]);
    }
    for k in 0..3 {
        target.first_moment[k] = arena.add2(target.first_moment[k], extra.first_moment[k]);
    }
    target.mass = arena.add2(target.mass, extra.mass);
}

/// The 14 slots of a link as a list.
pub(crate) fn slots(l: &LinkParameters) -> [Id; 14] {
    let i = l.inertia;
    let m = l.first_moment;
    [
        i[0], i[1], i[2], i[3], i[4], i[5], m[0], m[1], m[2], l.mass, l.ia, l.fv, l.fc, l.fo,
    ]
}

/// A link whose only nonzero slot is `slot`, set to 1.
pub(crate) fn unit(arena: &mut Arena, slot: usize) -> LinkParameters {
    let mut l = LinkParameters::zero(arena);
    let one = arena.one();
    *l.slot_mut(ParameterKind::ALL[slot]) = one;
    l
}
