//! Newton-Euler inverse dynamics, linear in the link parameters
//! (docs/dynamics.md#newton-euler-linear-in-the-parameters; Khalil and Dombre 2002, the
//! chapter on dynamic modelling).

use super::kinematics::Kinematics;
use super::link::LinkParameters;
use super::vector::{self, Vec3};
use crate::expr::{Arena, Id};
use crate::robot::JointKind;

/// The wrench (F_j, N_j) of link j about O_j, in frame j:
/// F = M vd + wd x MS + w x (w x MS), N = J wd + w x (J w) + MS x vd.
pub fn link_wrench(
    arena: &mut Arena,
    kin: &Kinematics,
    j: usize,
    p: &LinkParameters,
) -> (Vec3, Vec3) {
    let (w, wd, vd) = (kin.omega[j], kin.omega_dot[j], kin.acceleration[j]);
    let ms = p.first_moment;
    let m_vd = vector::scale(arena, p.mass, vd);
    let wd_x_ms = vector::cross(arena, wd, ms);
    let w_x_ms = vector::cross(arena, w, ms);
    let w_x_w_x_ms = vector::cross(arena, w, w_x_ms);
    let force = vector::sum(arena, &[m_vd, wd_x_ms, w_x_w_x_ms]);
    let inertia = vector::symmetric(&p.inertia);
    let j_wd = vector::mat_vec(arena, &inertia, wd);
    let j_w = vector::mat_vec(arena, &inertia, w);
    let w_x_jw = vector::cross(arena, w, j_w);
    let ms_x_vd = vector::cross(arena, ms, vd);
    let moment = vector::sum(arena, &[j_wd, w_x_jw, ms_x_vd]);
    (force, moment)
}

/// Joint torques tau for link parameters `params` (modified-DH frames), with
/// the drive terms Ia qdd + Fv qd + Fc sign(qd) + Fo.
pub fn inverse_dynamics(
    arena: &mut Arena,
    kin: &Kinematics,
    qd: &[Id],
    qdd: &[Id],
    params: &[LinkParameters],
) -> Vec<Id> {
    let n = params.len();
    let mut tau = vec![arena.zero(); n];
    let mut f = vector::zero(arena);
    let mut m = vector::zero(arena);
    let zero = arena.zero();
    let is_zero = |v: &Vec3| v.iter().all(|&x| x == zero);
    for j in (0..n).rev() {
        // A link without inertial parameters (a regressor column of another
        // link) adds no wrench: skip building zeros.
        let (force, moment) = if params[j].is_zero_inertial(arena) {
            ([zero; 3], [zero; 3])
        } else {
            link_wrench(arena, kin, j, &params[j])
        };
        // Add the child's wrench, moved into frame j.
        if j + 1 < n && !(is_zero(&f) && is_zero(&m)) {
            let r = &kin.rotation[j + 1];
            let rf = vector::mat_vec(arena, r, f);
            let rm = vector::mat_vec(arena, r, m);
            let p_x_rf = vector::cross(arena, kin.offset[j + 1], rf);
            f = vector::add(arena, force, rf);
            m = vector::sum(arena, &[moment, rm, p_x_rf]);
        } else {
            f = force;
            m = moment;
        }
        let p = &params[j];
        let sign = arena.sign(qd[j]);
        let axis = match kin.kinds[j] {
            JointKind::Revolute => m[2],
            JointKind::Prismatic => f[2],
        };
        let ia = arena.mul2(p.ia, qdd[j]);
        let fv = arena.mul2(p.fv, qd[j]);
        let fc = arena.mul2(p.fc, sign);
        tau[j] = arena.add(&[axis, ia, fv, fc, p.fo]);
    }
    tau
}
