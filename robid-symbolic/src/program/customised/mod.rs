//! The customised Newton-Euler algorithm written straight into a program
//! (Khalil and Kleinfinger 1987; docs/dynamics.md#customised-newton-euler): the
//! recursion is run on program values instead of expressions, and every operation whose
//! operands are known folds away (0, +-1, a constant times a constant), so only the
//! nonzero components of each vector are computed and a rotation by a DH angle alpha in
//! {0, +-pi/2} costs nothing. Khalil and Kleinfinger's Rz(gamma_j) Tz(b_j) in front of a
//! row (docs/conventions.md#khalil-kleinfinger-general-frames) is one more rotation and
//! offset, left out altogether where gamma_j or b_j is exactly 0, so a DH table costs
//! what it cost without them. Each intermediate quantity gets a
//! temporary of its own, so nothing is expanded.
//!
//! The forward recursion uses Khalil's U_j = skew(wd_j) + skew(w_j)^2, shared
//! by the link's force F_j = M_j vd_j + U_j MS_j and by the next link's
//! acceleration vd_(j+1) = R' (vd_j + U_j P_(j+1)).
//!
//! A value is an [`E`]: a numeric coefficient times a program value (or a
//! plain number). Coefficients are carried lazily, so `a x + a y` costs one
//! multiplication by `a`, and signs cost nothing until an output needs one.
//!
//! Here: values, frames and rotations. `values.rs`: arithmetic on values;
//! `forward.rs`: the forward recursion; `backward.rs`: link wrenches, their
//! transfer and the torques; `columns.rs`: base regressor columns; `crba.rs`: the
//! mass matrix by the composite-rigid-body algorithm.

mod backward;
mod columns;
mod crba;
mod forward;
mod values;

use super::lower::Lowering;
use super::{ProgramError, Value};
use crate::dynamics::LinkParameters;
use crate::expr::{Arena, Id};
use crate::robot::{JointKind, Robot};

/// `c * v`, or the number `c` when `v` is `None`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(in crate::program) struct E {
    c: f64,
    v: Option<Value>,
}

type V3 = [E; 3];

const ZERO: E = E { c: 0.0, v: None };

fn number(c: f64) -> E {
    E { c, v: None }
}

fn neg(a: E) -> E {
    E { c: -a.c, v: a.v }
}

/// One modified-DH frame as expressions: sin and cos of gamma, alpha and theta, b, a, d.
#[derive(Clone, Copy, Debug)]
pub(in crate::program) struct FrameExprs {
    kind: JointKind,
    sg: Id,
    cg: Id,
    b: Id,
    sa: Id,
    ca: Id,
    st: Id,
    ct: Id,
    a: Id,
    d: Id,
}

/// The frame expressions of `robot` for joint positions `q`.
pub(in crate::program) fn frame_exprs(
    arena: &mut Arena,
    robot: &Robot,
    q: &[Id],
) -> Vec<FrameExprs> {
    robot
        .frame_rows()
        .iter()
        .enumerate()
        .map(|(j, row)| {
            let gamma = row.gamma.to_expr(arena);
            let b = row.b.to_expr(arena);
            let alpha = row.alpha.to_expr(arena);
            let a = row.a.to_expr(arena);
            let mut theta = row.theta.to_expr(arena);
            let mut d = row.d.to_expr(arena);
            match row.kind {
                JointKind::Revolute => theta = arena.add2(theta, q[j]),
                JointKind::Prismatic => d = arena.add2(d, q[j]),
            }
            FrameExprs {
                kind: row.kind,
                sg: arena.sin(gamma),
                cg: arena.cos(gamma),
                b,
                sa: arena.sin(alpha),
                ca: arena.cos(alpha),
                st: arena.sin(theta),
                ct: arena.cos(theta),
                a,
                d,
            }
        })
        .collect()
}

/// A frame as program values.
#[derive(Clone, Copy, Debug)]
struct Frame {
    kind: JointKind,
    /// sin and cos of gamma; `None` when gamma is exactly 0 (no rotation at all).
    gamma: Option<(E, E)>,
    /// b (zero for a DH row).
    b: E,
    sa: E,
    ca: E,
    st: E,
    ct: E,
    /// The DH row's part of the origin, [a, -sa d, ca d].
    p_dh: V3,
    /// P_(j-1, j) = Rz(gamma) [a, -sa d, ca d] + [0, 0, b].
    p: V3,
}

/// Link parameters as program values.
#[derive(Clone, Copy, Debug)]
struct Link {
    inertia: [E; 6],
    ms: V3,
    m: E,
    ia: E,
    fv: E,
    fc: E,
    fo: E,
}

/// The choices of the customised Newton-Euler algorithm ([`Lowering::newton_euler`],
/// docs/dynamics.md#customised-newton-euler): `tip` and `reuse` are not always the
/// cheaper, so a program is built with each and the cheapest kept; the others are
/// always taken, none ever costing flops (`every_other_choice_pays`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(in crate::program) struct Choices {
    /// An acceleration component `a x` whose product the next link's acceleration
    /// computed already enters `MS x vd` as that product.
    pub reuse: bool,
    /// The last link's wrench written in its parent's frame ([`Lowering::tip`]).
    pub tip: bool,
    /// Planar angular motion carried as a rotated unit vector (`forward.rs`).
    pub plane: bool,
    /// The moments after a perpendicular joint projected instead of rotated back.
    pub projection: bool,
    /// The last link's moment taken about its parent's origin when that is on its axis.
    pub shift: bool,
}

impl Choices {
    /// Every choice taken.
    pub(in crate::program) const ALL: Choices = Choices {
        reuse: true,
        tip: true,
        plane: true,
        projection: true,
        shift: true,
    };
}

/// Joint inputs of one run: velocities, accelerations, gravity (expressions).
pub(in crate::program) struct RunInputs<'a> {
    /// Joint velocities.
    pub qd: &'a [Id],
    /// Joint accelerations.
    pub qdd: &'a [Id],
    /// Gravity in the base frame.
    pub gravity: [Id; 3],
}

impl Lowering<'_> {
    /// Rz(gamma) v, with (sin, cos) of gamma.
    fn rotate_gamma(&mut self, (sg, cg): (E, E), v: V3) -> V3 {
        let a = self.mul(cg, v[0]);
        let b = self.mul(sg, v[1]);
        let c = self.mul(sg, v[0]);
        let d = self.mul(cg, v[1]);
        [self.add(&[a, neg(b)]), self.add(&[c, d]), v[2]]
    }

    /// R v for R = Rz(gamma) Rx(alpha) Rz(theta) (Rx(alpha) Rz(theta) for a DH row).
    fn rotate(&mut self, f: &Frame, v: V3) -> V3 {
        let u = self.rotate_dh(f, v);
        match f.gamma {
            Some(g) => self.rotate_gamma(g, u),
            None => u,
        }
    }

    /// R' v for R = Rz(gamma) Rx(alpha) Rz(theta).
    fn rotate_back(&mut self, f: &Frame, v: V3) -> V3 {
        let v = match f.gamma {
            Some((sg, cg)) => self.rotate_gamma((neg(sg), cg), v),
            None => v,
        };
        self.rotate_back_dh(f, v)
    }

    /// Rx(alpha) Rz(theta) v.
    fn rotate_dh(&mut self, f: &Frame, v: V3) -> V3 {
        let a = self.mul(f.ct, v[0]);
        let b = self.mul(f.st, v[1]);
        let c = self.mul(f.st, v[0]);
        let d = self.mul(f.ct, v[1]);
        let u = [self.add(&[a, neg(b)]), self.add(&[c, d]), v[2]];
        let a = self.mul(f.ca, u[1]);
        let b = self.mul(f.sa, u[2]);
        let c = self.mul(f.sa, u[1]);
        let d = self.mul(f.ca, u[2]);
        [u[0], self.add(&[a, neg(b)]), self.add(&[c, d])]
    }

    /// (Rx(alpha) Rz(theta))' v.
    fn rotate_back_dh(&mut self, f: &Frame, v: V3) -> V3 {
        let a = self.mul(f.ca, v[1]);
        let b = self.mul(f.sa, v[2]);
        let c = self.mul(f.sa, v[1]);
        let d = self.mul(f.ca, v[2]);
        let u = [v[0], self.add(&[a, b]), self.add(&[d, neg(c)])];
        let a = self.mul(f.ct, u[0]);
        let b = self.mul(f.st, u[1]);
        let c = self.mul(f.st, u[0]);
        let d = self.mul(f.ct, u[1]);
        [self.add(&[a, b]), self.add(&[d, neg(c)]), u[2]]
    }

    fn frame(&mut self, f: &FrameExprs) -> Result<Frame, ProgramError> {
        let (sa, ca, d) = (self.e(f.sa)?, self.e(f.ca)?, self.e(f.d)?);
        let py = self.mul(sa, d);
        let p_dh = [self.e(f.a)?, neg(py), self.mul(ca, d)];
        let (sg, cg, b) = (self.e(f.sg)?, self.e(f.cg)?, self.e(f.b)?);
        // gamma = 0 (or a whole turn): the identity, folded away
        let gamma = (!(sg == ZERO && cg == number(1.0))).then_some((sg, cg));
        let mut p = match gamma {
            Some(g) => self.rotate_gamma(g, p_dh),
            None => p_dh,
        };
        if b.c != 0.0 {
            p[2] = self.add(&[p[2], b]);
        }
        Ok(Frame {
            kind: f.kind,
            gamma,
            b,
            sa,
            ca,
            st: self.e(f.st)?,
            ct: self.e(f.ct)?,
            p_dh,
            p,
        })
    }

    fn link(&mut self, l: &LinkParameters) -> Result<Link, ProgramError> {
        let mut inertia = [ZERO; 6];
        for (x, &id) in inertia.iter_mut().zip(&l.inertia) {
            *x = self.e(id)?;
        }
        let mut ms = [ZERO; 3];
        for (x, &id) in ms.iter_mut().zip(&l.first_moment) {
            *x = self.e(id)?;
        }
        Ok(Link {
            inertia,
            ms,
            m: self.e(l.mass)?,
            ia: self.e(l.ia)?,
            fv: self.e(l.fv)?,
            fc: self.e(l.fc)?,
            fo: self.e(l.fo)?,
        })
    }
}
