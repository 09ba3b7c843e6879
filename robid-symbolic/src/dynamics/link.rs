//! The inertial and drive parameters of each link as expressions, and their
//! move from the user's link frames into modified-DH frames.

use super::vector::{self, Mat3, Vec3};
use crate::expr::{Arena, Id};
use crate::robot::{DriveTerm, ParameterId, ParameterKind, Robot};

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

    /// True when the ten inertial parameters are the constant 0.
    pub fn is_zero_inertial(&self, arena: &Arena) -> bool {
        self.inertia
            .iter()
            .chain(&self.first_moment)
            .chain([&self.mass])
            .all(|&x| arena.is_zero(x))
    }

    /// The entry of the standard parameter `kind` (docs/conventions.md#standard-parameters).
    pub fn slot_mut(&mut self, kind: ParameterKind) -> &mut Id {
        match kind {
            ParameterKind::Inertial(i) => match i.index() {
                k @ 0..=5 => &mut self.inertia[k],
                k @ 6..=8 => &mut self.first_moment[k - 6],
                _ => &mut self.mass,
            },
            ParameterKind::Drive(DriveTerm::Ia) => &mut self.ia,
            ParameterKind::Drive(DriveTerm::Fv) => &mut self.fv,
            ParameterKind::Drive(DriveTerm::Fc) => &mut self.fc,
            ParameterKind::Drive(DriveTerm::Fo) => &mut self.fo,
        }
    }
}

/// The constant transform from each modified-DH link frame to the user's
/// link frame, as (alpha, a) expressions; `None` where they coincide.
pub fn user_frames(arena: &mut Arena, robot: &Robot) -> Vec<Option<(Id, Id)>> {
    robot
        .frame_rows()
        .iter()
        .map(|row| {
            let alpha = row.user_alpha.to_expr(arena);
            let a = row.user_a.to_expr(arena);
            (!(arena.is_zero(alpha) && arena.is_zero(a))).then_some((alpha, a))
        })
        .collect()
}

/// Parameters of every link in modified-DH frames, given the value of each
/// standard parameter (`parameters` as from `Robot::standard_parameters`, in the
/// user's frames; `frames` from [`user_frames`]). Disabled drive terms are zero.
pub fn link_parameters(
    arena: &mut Arena,
    parameters: &[ParameterId],
    frames: &[Option<(Id, Id)>],
    values: &[Id],
) -> Vec<LinkParameters> {
    assert_eq!(
        values.len(),
        parameters.len(),
        "one value per standard parameter"
    );
    let mut links: Vec<LinkParameters> = (0..frames.len())
        .map(|_| LinkParameters::zero(arena))
        .collect();
    for (p, &v) in parameters.iter().zip(values) {
        *links[p.link].slot_mut(p.kind) = v;
    }
    links
        .into_iter()
        .zip(frames)
        .map(|(l, frame)| match *frame {
            Some((alpha, a)) if !l.is_zero_inertial(arena) => to_parent_frame(arena, l, alpha, a),
            _ => l,
        })
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
