//! Lagrange-Euler dynamics from the energies (docs/dynamics.md#lagrange-euler): M(q), c(q, qd),
//! g(q), the total energy, and tau = d/dt(dL/dqd) - dL/dq by symbolic
//! differentiation. Independent of Newton-Euler, so the two check each other.

use super::kinematics::{JointInputs, Kinematics};
use super::link::LinkParameters;
use super::vector;
use crate::expr::{Arena, Id, Node, Num, Symbol};

/// The closed-form Lagrange-Euler model.
#[derive(Clone, Debug)]
pub struct Lagrange {
    /// Kinetic energy T (rotor inertias included).
    pub kinetic: Id,
    /// Potential energy U.
    pub potential: Id,
    /// M(q), row-major `dof x dof`.
    pub mass_matrix: Vec<Vec<Id>>,
    /// c(q, qd): Coriolis and centripetal torques.
    pub coriolis: Vec<Id>,
    /// g(q): gravity torques.
    pub gravity: Vec<Id>,
    /// Fv qd + Fc sign(qd) + Fo.
    pub friction: Vec<Id>,
    /// tau = M qdd + c + g + friction.
    pub torques: Vec<Id>,
}

fn symbol_of(arena: &Arena, id: Id) -> Symbol {
    match arena.node(id) {
        Node::Sym(s) => *s,
        _ => panic!("Lagrange-Euler needs symbolic joint inputs"),
    }
}

/// T = sum 1/2 w'Jw + MS'(V x w) + 1/2 M V'V + 1/2 Ia qd^2.
pub fn kinetic_energy(
    arena: &mut Arena,
    kin: &Kinematics,
    qd: &[Id],
    params: &[LinkParameters],
) -> Id {
    let half = Num::ratio(1, 2).expect("nonzero");
    let mut terms = Vec::new();
    for (j, p) in params.iter().enumerate() {
        let (w, v) = (kin.omega[j], kin.velocity[j]);
        let jw = vector::mat_vec(arena, &vector::symmetric(&p.inertia), w);
        let wjw = vector::dot(arena, w, jw);
        terms.push(arena.scale(half, wjw));
        let v_x_w = vector::cross(arena, v, w);
        terms.push(vector::dot(arena, p.first_moment, v_x_w));
        let vv = vector::dot(arena, v, v);
        let mvv = arena.mul2(p.mass, vv);
        terms.push(arena.scale(half, mvv));
        let qd2 = arena.pow(qd[j], 2);
        let rotor = arena.mul2(p.ia, qd2);
        terms.push(arena.scale(half, rotor));
    }
    arena.add(&terms)
}

/// U = -sum g'(M p_0j + R_0j MS_j).
pub fn potential_energy(
    arena: &mut Arena,
    kin: &Kinematics,
    gravity: vector::Vec3,
    params: &[LinkParameters],
) -> Id {
    let mut terms = Vec::new();
    for (j, p) in params.iter().enumerate() {
        let mp = vector::scale(arena, p.mass, kin.base_position[j]);
        let rms = vector::mat_vec(arena, &kin.base_rotation[j], p.first_moment);
        let position = vector::add(arena, mp, rms);
        let g = vector::dot(arena, gravity, position);
        terms.push(arena.neg(g));
    }
    arena.add(&terms)
}

/// Derives the Lagrange-Euler model; `inputs` must be symbols.
pub fn lagrange(
    arena: &mut Arena,
    kin: &Kinematics,
    inputs: &JointInputs,
    params: &[LinkParameters],
) -> Lagrange {
    let n = params.len();
    let kinetic = kinetic_energy(arena, kin, &inputs.qd, params);
    let potential = potential_energy(arena, kin, inputs.gravity, params);
    let q: Vec<Symbol> = inputs.q.iter().map(|&x| symbol_of(arena, x)).collect();
    let qd: Vec<Symbol> = inputs.qd.iter().map(|&x| symbol_of(arena, x)).collect();
    // dT/dqd_i, then its derivatives by qd_k (M) and q_k (part of c).
    let momentum: Vec<Id> = qd.iter().map(|&s| arena.diff(kinetic, s)).collect();
    let mut mass_matrix = vec![Vec::with_capacity(n); n];
    let mut d_momentum_dq = vec![Vec::with_capacity(n); n];
    for k in 0..n {
        let by_qd = arena.diff_all(&momentum, qd[k]);
        let by_q = arena.diff_all(&momentum, q[k]);
        for i in 0..n {
            mass_matrix[i].push(by_qd[i]);
            d_momentum_dq[i].push(by_q[i]);
        }
    }
    let dt_dq: Vec<Id> = q.iter().map(|&s| arena.diff(kinetic, s)).collect();
    let gravity: Vec<Id> = q.iter().map(|&s| arena.diff(potential, s)).collect();
    let mut coriolis = Vec::with_capacity(n);
    let mut friction = Vec::with_capacity(n);
    let mut torques = Vec::with_capacity(n);
    for i in 0..n {
        let mut c: Vec<Id> = (0..n)
            .map(|k| arena.mul2(d_momentum_dq[i][k], inputs.qd[k]))
            .collect();
        c.push(arena.neg(dt_dq[i]));
        let c = arena.add(&c);
        let p = &params[i];
        let sign = arena.sign(inputs.qd[i]);
        let fv = arena.mul2(p.fv, inputs.qd[i]);
        let fc = arena.mul2(p.fc, sign);
        let f = arena.add(&[fv, fc, p.fo]);
        let mut t: Vec<Id> = (0..n)
            .map(|k| arena.mul2(mass_matrix[i][k], inputs.qdd[k]))
            .collect();
        t.extend([c, gravity[i], f]);
        torques.push(arena.add(&t));
        coriolis.push(c);
        friction.push(f);
    }
    Lagrange {
        kinetic,
        potential,
        mass_matrix,
        coriolis,
        gravity,
        friction,
        torques,
    }
}
