//! Forward kinematics in modified-DH frames (with Khalil and Kleinfinger's gamma and b,
//! docs/conventions.md#khalil-kleinfinger-general-frames): rotations and offsets between
//! consecutive frames, base-frame poses, and the velocity and acceleration
//! recursion of Newton-Euler (docs/dynamics.md#kinematics-of-the-chain,
//! docs/dynamics.md#forward-recursion).

use super::vector::{self, Mat3, Vec3};
use crate::expr::{Arena, Id};
use crate::robot::{JointKind, Robot};

/// The joint-space inputs a derivation is made for: symbols, or constants
/// (e.g. qd = 0 and qdd = e_k for a column of the mass matrix).
#[derive(Clone, Debug)]
pub struct JointInputs {
    /// Joint positions.
    pub q: Vec<Id>,
    /// Joint velocities.
    pub qd: Vec<Id>,
    /// Joint accelerations.
    pub qdd: Vec<Id>,
    /// Gravity in the base frame (frame 0).
    pub gravity: Vec3,
}

impl JointInputs {
    /// The symbols `q1.., qd1.., qdd1..` and the robot's gravity in frame 0: the
    /// description's (world-frame) gravity turned by the base rotation, R_base' g
    /// (docs/conventions.md#gravity); as written when there is no base rotation.
    pub fn symbols(arena: &mut Arena, robot: &Robot) -> JointInputs {
        let n = robot.dof();
        let names = |prefix: &str, arena: &mut Arena| -> Vec<Id> {
            (1..=n)
                .map(|j| arena.var(&format!("{prefix}{j}")))
                .collect()
        };
        let q = names("q", arena);
        let qd = names("qd", arena);
        let qdd = names("qdd", arena);
        let world = [0, 1, 2].map(|i| robot.gravity()[i].to_expr(arena));
        let gravity = match robot.base() {
            Some(base) if !base.rotation_is_identity() => {
                let r = base.rotation(arena);
                vector::mat_t_vec(arena, &r, world)
            }
            _ => world,
        };
        JointInputs {
            q,
            qd,
            qdd,
            gravity,
        }
    }
}

/// Frames, poses, velocities and accelerations of every link.
#[derive(Clone, Debug)]
pub struct Kinematics {
    /// Joint types.
    pub kinds: Vec<JointKind>,
    /// R_(j-1, j): orientation of frame j in frame j-1.
    pub rotation: Vec<Mat3>,
    /// P_(j-1, j): origin of frame j in frame j-1.
    pub offset: Vec<Vec3>,
    /// R_(0, j): orientation of frame j in the base frame.
    pub base_rotation: Vec<Mat3>,
    /// p_(0, j): origin of frame j in the base frame.
    pub base_position: Vec<Vec3>,
    /// Angular velocity of link j in frame j.
    pub omega: Vec<Vec3>,
    /// Angular acceleration of link j in frame j.
    pub omega_dot: Vec<Vec3>,
    /// Linear velocity of O_j in frame j.
    pub velocity: Vec<Vec3>,
    /// Linear acceleration of O_j in frame j, gravity included as a base acceleration of -g.
    pub acceleration: Vec<Vec3>,
}

impl Kinematics {
    /// Derives the kinematics of `robot` for the given inputs.
    pub fn new(arena: &mut Arena, robot: &Robot, inputs: &JointInputs) -> Kinematics {
        let rows = robot.frame_rows();
        let n = rows.len();
        let zero3 = vector::zero(arena);
        let one = arena.one();
        let zero = arena.zero();
        let identity = [[one, zero, zero], [zero, one, zero], [zero, zero, one]];
        let mut k = Kinematics {
            kinds: rows.iter().map(|r| r.kind).collect(),
            rotation: Vec::with_capacity(n),
            offset: Vec::with_capacity(n),
            base_rotation: Vec::with_capacity(n),
            base_position: Vec::with_capacity(n),
            omega: Vec::with_capacity(n),
            omega_dot: Vec::with_capacity(n),
            velocity: Vec::with_capacity(n),
            acceleration: Vec::with_capacity(n),
        };
        let (mut r0, mut p0) = (identity, zero3);
        let (mut w, mut wd, mut v) = (zero3, zero3, zero3);
        let minus_g = inputs.gravity.map(|g| arena.neg(g));
        let mut vd = minus_g;
        for (j, row) in rows.iter().enumerate() {
            let alpha = row.alpha.to_expr(arena);
            let a = row.a.to_expr(arena);
            let mut theta = row.theta.to_expr(arena);
            let mut d = row.d.to_expr(arena);
            match row.kind {
                JointKind::Revolute => theta = arena.add2(theta, inputs.q[j]),
                JointKind::Prismatic => d = arena.add2(d, inputs.q[j]),
            }
            let (sa, ca) = (arena.sin(alpha), arena.cos(alpha));
            let (st, ct) = (arena.sin(theta), arena.cos(theta));
            let mut rot = vector::rot_x_rot_z(arena, sa, ca, st, ct);
            let nsa_d = {
                let sd = arena.mul2(sa, d);
                arena.neg(sd)
            };
            let mut p = [a, nsa_d, arena.mul2(ca, d)];
            // Khalil-Kleinfinger: Rz(gamma) Tz(b) in front of the row; a DH row (both
            // exactly 0) is left as it is.
            let gamma = row.gamma.to_expr(arena);
            if !arena.is_zero(gamma) {
                let rz = vector::rot_z(arena, gamma);
                rot = vector::mat_mul(arena, &rz, &rot);
                p = vector::mat_vec(arena, &rz, p);
            }
            let b = row.b.to_expr(arena);
            if !arena.is_zero(b) {
                p[2] = arena.add2(p[2], b);
            }

            // Velocities: the parent's, moved into frame j, plus the joint's own motion.
            let w_in = vector::mat_t_vec(arena, &rot, w);
            let wd_in = vector::mat_t_vec(arena, &rot, wd);
            let lever = vector::cross(arena, w, p);
            let v_parent = vector::add(arena, v, lever);
            let v_in = vector::mat_t_vec(arena, &rot, v_parent);
            let w_x_p = vector::cross(arena, w, p);
            let w_x_w_x_p = vector::cross(arena, w, w_x_p);
            let wd_x_p = vector::cross(arena, wd, p);
            let vd_parent = vector::sum(arena, &[vd, wd_x_p, w_x_w_x_p]);
            let vd_in = vector::mat_t_vec(arena, &rot, vd_parent);
            let (qd, qdd) = (inputs.qd[j], inputs.qdd[j]);
            // (R' w_(j-1)) x (qd z) = [wy qd, -wx qd, 0]
            let wy_qd = arena.mul2(w_in[1], qd);
            let wx_qd = arena.mul2(w_in[0], qd);
            let neg_wx_qd = arena.neg(wx_qd);
            let w_x_qdz = [wy_qd, neg_wx_qd, zero];
            match row.kind {
                JointKind::Revolute => {
                    w = [w_in[0], w_in[1], arena.add2(w_in[2], qd)];
                    let extra = [w_x_qdz[0], w_x_qdz[1], qdd];
                    wd = vector::add(arena, wd_in, extra);
                    v = v_in;
                    vd = vd_in;
                }
                JointKind::Prismatic => {
                    w = w_in;
                    wd = wd_in;
                    v = [v_in[0], v_in[1], arena.add2(v_in[2], qd)];
                    let two = arena.int(2);
                    let coriolis = w_x_qdz.map(|c| arena.mul2(two, c));
                    let extra = [coriolis[0], coriolis[1], qdd];
                    vd = vector::add(arena, vd_in, extra);
                }
            }
            let rp = vector::mat_vec(arena, &r0, p);
            p0 = vector::add(arena, p0, rp);
            r0 = vector::mat_mul(arena, &r0, &rot);
            k.rotation.push(rot);
            k.offset.push(p);
            k.base_rotation.push(r0);
            k.base_position.push(p0);
            k.omega.push(w);
            k.omega_dot.push(wd);
            k.velocity.push(v);
            k.acceleration.push(vd);
        }
        k
    }
}
