//! The inertial and drive parameters of each link as expressions, and their
//! move from the user's link frames into modified-DH frames.

use super::vector::{self, Mat3, Vec3};
use crate::expr::{Arena, Id};
use crate::robot::{DriveTerm, ParameterKind, Robot};

/// Parameters of one link (about the frame origin, in the link frame) and its joint's drive.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LinkParameters {
    /// Inertia tensor entries about O_j: XX XY XZ YY YZ ZZ.
    pub inertia: [Id; 6],
    /// First moments MX MY MZ.
    pub first_moment: Vec3,
    /// Mass.
    pub mass: Id,
    /// Rotor inertia Ia.
    pub ia: Id,
    /// Viscous friction Fv.
    pub fv: Id,
    /// Coulomb friction Fc.
    pub fc: Id,
    /// Offset Fo.
    pub fo: Id,
}

impl LinkParameters {
    /// All zero.
    pub fn zero(arena: &mut Arena) -> LinkParameters {
        let z = arena.zero();
        LinkParameters {
            inertia: [z; 6],
            first_moment: [z; 3],
            mass: z,
            ia: z,
            fv: z,
            fc: z,
            fo: z,
        }
    }
}

/// Parameters of every link in modified-DH frames, given the value of each
/// standard parameter (in the order of `Robot::standard_parameters`, in the
/// user's frames). Disabled drive terms are zero.
pub fn link_parameters(arena: &mut Arena, robot: &Robot, values: &[Id]) -> Vec<LinkParameters> {
    let parameters = robot.standard_parameters();
    assert_eq!(
        values.len(),
        parameters.len(),
        "one value per standard parameter"
    );
    let mut links: Vec<LinkParameters> = (0..robot.dof())
        .map(|_| LinkParameters::zero(arena))
        .collect();
    for (p, &v) in parameters.iter().zip(values) {
        let l = &mut links[p.link];
        match p.kind {
            ParameterKind::Inertia(k) => l.inertia[k] = v,
            ParameterKind::FirstMoment(k) => l.first_moment[k] = v,
            ParameterKind::Mass => l.mass = v,
            ParameterKind::Drive(DriveTerm::Ia) => l.ia = v,
            ParameterKind::Drive(DriveTerm::Fv) => l.fv = v,
            ParameterKind::Drive(DriveTerm::Fc) => l.fc = v,
            ParameterKind::Drive(DriveTerm::Fo) => l.fo = v,
        }
    }
    let rows = robot.frame_rows();
    links
        .into_iter()
        .zip(&rows)
        .map(|(l, row)| {
            let alpha = row.user_alpha.to_expr(arena);
            let a = row.user_a.to_expr(arena);
            if arena.is_zero(alpha) && arena.is_zero(a) {
                l
            } else {
                to_parent_frame(arena, l, alpha, a)
            }
        })
        .collect()
}

/// The symbols of every standard parameter (`XX1`, ...), in order.
pub fn parameter_symbols(arena: &mut Arena, robot: &Robot) -> Vec<Id> {
    robot
        .standard_parameters()
        .iter()
        .map(|p| arena.var(&p.name))
        .collect()
}

/// Parameters expressed in a frame F from parameters in a frame F' with
/// F -> F' = Tx(a) Rx(alpha) (the user's standard-DH link frame seen from the
/// modified-DH one).
pub fn to_parent_frame(arena: &mut Arena, l: LinkParameters, alpha: Id, a: Id) -> LinkParameters {
    let (s, c) = (arena.sin(alpha), arena.cos(alpha));
    let one = arena.one();
    let zero = arena.zero();
    let ns = arena.neg(s);
    let r = [[one, zero, zero], [zero, c, ns], [zero, s, c]];
    transfer(arena, l, &r, [a, zero, zero])
}

/// Inertial parameters of a body given in a frame F' (origin t, orientation R
/// in a frame F), expressed in F: with u = R MS', MS = u + M t and
/// J = R J' R' + (2 t.u + M t.t) I - u t' - t u' - M t t' (the parallel-axis
/// theorem for a moved origin). Drive terms are carried over unchanged.
pub fn transfer(arena: &mut Arena, l: LinkParameters, r: &Mat3, t: Vec3) -> LinkParameters {
    let j = vector::symmetric(&l.inertia);
    let rj = vector::mat_mul(arena, r, &j);
    let rjrt = vector::mat_mul(arena, &rj, &vector::transpose(r));
    let u = vector::mat_vec(arena, r, l.first_moment);
    let m = l.mass;
    let mt = vector::scale(arena, m, t);
    let first_moment = vector::add(arena, u, mt);
    let t_dot_u = vector::dot(arena, t, u);
    let t_dot_t = vector::dot(arena, t, t);
    let two_tu = arena.scale(crate::expr::Num::int(2), t_dot_u);
    let m_tt = arena.mul2(m, t_dot_t);
    let diagonal = arena.add2(two_tu, m_tt);
    let entry = |arena: &mut Arena, i: usize, k: usize| {
        let mut terms = vec![rjrt[i][k]];
        if i == k {
            terms.push(diagonal);
        }
        let ut = arena.mul2(u[i], t[k]);
        let tu = arena.mul2(t[i], u[k]);
        let mtt = arena.mul(&[m, t[i], t[k]]);
        for x in [ut, tu, mtt] {
            terms.push(arena.neg(x));
        }
        arena.add(&terms)
    };
    let inertia = [(0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2)].map(|(i, k)| entry(arena, i, k));
    LinkParameters {
        inertia,
        first_moment,
        mass: m,
        ..l
    }
}
