//! The customised Newton-Euler algorithm written straight into a program
//! (Khalil and Kleinfinger; Khalil and Dombre 9.5.3): the recursion is run on
//! program values instead of expressions, and every operation whose operands
//! are known folds away (0, +-1, a constant times a constant), so only the
//! nonzero components of each vector are computed and a rotation by a DH
//! angle alpha in {0, +-pi/2} costs nothing. Each intermediate quantity gets a
//! temporary of its own, so nothing is expanded.
//!
//! The forward recursion uses Khalil's U_j = skew(wd_j) + skew(w_j)^2, shared
//! by the link's force F_j = M_j vd_j + U_j MS_j and by the next link's
//! acceleration vd_(j+1) = R' (vd_j + U_j P_(j+1)).
//!
//! A value is an [`E`]: a numeric coefficient times a program value (or a
//! plain number). Coefficients are carried lazily, so `a x + a y` costs one
//! multiplication by `a`, and signs cost nothing until an output needs one.

use super::lower::{Lowering, Signed};
use super::{Instr, ProgramError, Value};
use crate::dynamics::LinkParameters;
use crate::expr::{Arena, Id};
use crate::robot::{JointKind, Robot};

/// `c * v`, or the number `c` when `v` is `None`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct E {
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

/// One modified-DH frame as expressions: sin and cos of alpha and theta, a, d.
#[derive(Clone, Copy, Debug)]
pub(super) struct FrameExprs {
    kind: JointKind,
    sa: Id,
    ca: Id,
    st: Id,
    ct: Id,
    a: Id,
    d: Id,
}

/// The frame expressions of `robot` for joint positions `q`.
pub(super) fn frame_exprs(arena: &mut Arena, robot: &Robot, q: &[Id]) -> Vec<FrameExprs> {
    robot
        .frame_rows()
        .iter()
        .enumerate()
        .map(|(j, row)| {
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
    sa: E,
    ca: E,
    st: E,
    ct: E,
    /// P_(j-1, j) = [a, -sa d, ca d].
    p: V3,
}

/// Angular motion about a single axis off z: w_xy = a e and
/// wd_xy = b e + w_z (w_y, -w_x), for a 2-vector e. Then w_xy and wd_xy cost
/// a rotation of e alone, and U_yz = -b e_x, U_xz = b e_y.
#[derive(Clone, Copy, Debug)]
struct Plane {
    e: [E; 2],
    a: E,
    b: E,
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

/// The forward recursion's results: frames as values, joint velocities and
/// accelerations, and w, wd, vd, U of every link.
pub(super) struct Kinematics {
    frames: Vec<Frame>,
    qd: Vec<E>,
    qdd: Vec<E>,
    kin: Vec<(V3, V3, V3, [[E; 3]; 3])>,
}

/// Joint inputs of one run: velocities, accelerations, gravity (expressions).
pub(super) struct RunInputs<'a> {
    /// Joint velocities.
    pub qd: &'a [Id],
    /// Joint accelerations.
    pub qdd: &'a [Id],
    /// Gravity in the base frame.
    pub gravity: [Id; 3],
}

impl Lowering<'_> {
    /// The expression `id` as a value.
    pub(super) fn e(&mut self, id: Id) -> Result<E, ProgramError> {
        let s = self.lower(id)?;
        Ok(self.e_of(s))
    }

    fn e_of(&self, s: Signed) -> E {
        let sign = if s.negative { -1.0 } else { 1.0 };
        match s.value {
            Value::Const(i) => number(sign * self.constant_value(i)),
            v => E {
                c: sign,
                v: Some(v),
            },
        }
    }

    /// The value with its coefficient's magnitude applied; the sign is left.
    fn signed(&mut self, e: E) -> Signed {
        let negative = e.c < 0.0;
        let m = e.c.abs();
        let value = match e.v {
            None => self.constant(m),
            Some(v) if m == 1.0 => v,
            Some(v) => {
                let c = self.constant(m);
                self.emit(Instr::Mul(v, c))
            }
        };
        Signed { value, negative }
    }

    /// The value as an output: a negation is paid for here.
    pub(super) fn output(&mut self, e: E) -> Value {
        if let Some(v) = e.v
            && e.c < 0.0
            && e.c != -1.0
        {
            // The sign goes into the coefficient.
            let c = self.constant(e.c);
            return self.emit(Instr::Mul(v, c));
        }
        let s = self.signed(e);
        self.materialize(s)
    }

    /// `e` with its coefficient's magnitude applied if that product exists.
    fn reuse(&self, e: E) -> E {
        match e.v {
            Some(v) if e.c.abs() != 1.0 && e.c != 0.0 => {
                match self.existing_product(v, e.c.abs()) {
                    Some(p) => E {
                        c: e.c.signum(),
                        v: Some(p),
                    },
                    None => e,
                }
            }
            _ => e,
        }
    }

    fn mul(&mut self, a: E, b: E) -> E {
        if a.c == 0.0 || b.c == 0.0 {
            return ZERO;
        }
        let (a, b) = (self.reuse(a), self.reuse(b));
        let v = match (a.v, b.v) {
            (None, x) | (x, None) => x,
            (Some(x), Some(y)) => Some(self.emit(Instr::Mul(x, y))),
        };
        E { c: a.c * b.c, v }
    }

    /// Sum: numbers folded, equal values merged, and the terms with the same
    /// coefficient magnitude added first and multiplied once.
    fn add(&mut self, terms: &[E]) -> E {
        let mut k = 0.0;
        let mut items: Vec<(Value, f64)> = Vec::new();
        for t in terms {
            if t.c == 0.0 {
                continue;
            }
            match t.v {
                None => k += t.c,
                Some(v) => match items.iter_mut().find(|x| x.0 == v) {
                    Some(x) => x.1 += t.c,
                    None => items.push((v, t.c)),
                },
            }
        }
        let mut groups: Vec<(f64, Vec<Signed>)> = Vec::new();
        for (v, c) in items.into_iter().filter(|x| x.1 != 0.0) {
            let s = Signed {
                value: v,
                negative: c < 0.0,
            };
            match groups.iter_mut().find(|g| g.0 == c.abs()) {
                Some(g) => g.1.push(s),
                None => groups.push((c.abs(), vec![s])),
            }
        }
        let mut parts: Vec<E> = groups
            .into_iter()
            .map(|(m, members)| {
                let s = self.sum(&members);
                E {
                    c: if s.negative { -m } else { m },
                    v: Some(s.value),
                }
            })
            .collect();
        match (parts.len(), k == 0.0) {
            (0, _) => return number(k),
            (1, true) => return parts[0],
            _ => {}
        }
        if k != 0.0 {
            parts.push(number(k));
        }
        let signed: Vec<Signed> = parts.into_iter().map(|p| self.signed(p)).collect();
        let s = self.sum(&signed);
        self.e_of(s)
    }

    fn add3(&mut self, vectors: &[V3]) -> V3 {
        [0, 1, 2].map(|i| {
            let terms: Vec<E> = vectors.iter().map(|v| v[i]).collect();
            self.add(&terms)
        })
    }

    fn cross(&mut self, a: V3, b: V3) -> V3 {
        [(1, 2), (2, 0), (0, 1)].map(|(i, j)| {
            let p = self.mul(a[i], b[j]);
            let q = self.mul(a[j], b[i]);
            self.add(&[p, neg(q)])
        })
    }

    fn mat_vec(&mut self, m: &[[E; 3]; 3], v: V3) -> V3 {
        [0, 1, 2].map(|i| {
            let terms: Vec<E> = (0..3).map(|k| self.mul(m[i][k], v[k])).collect();
            self.add(&terms)
        })
    }

    /// R v for R = Rx(alpha) Rz(theta).
    fn rotate(&mut self, f: &Frame, v: V3) -> V3 {
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

    /// R' v for R = Rx(alpha) Rz(theta).
    fn rotate_back(&mut self, f: &Frame, v: V3) -> V3 {
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

    /// U = skew(wd) + skew(w)^2.
    fn u_matrix(&mut self, w: V3, wd: V3) -> [[E; 3]; 3] {
        let sq = [0, 1, 2].map(|i| self.mul(w[i], w[i]));
        let mut u = [[ZERO; 3]; 3];
        for i in 0..3 {
            let (j, k) = ((i + 1) % 3, (i + 2) % 3);
            u[i][i] = self.add(&[neg(sq[j]), neg(sq[k])]);
            // skew(w)^2 (i, j) = w_i w_j; skew(wd) (i, j) = -wd_k, (j, i) = wd_k
            let wij = self.mul(w[i], w[j]);
            u[i][j] = self.add(&[wij, neg(wd[k])]);
            u[j][i] = self.add(&[wij, wd[k]]);
        }
        u
    }

    /// J wd + w x (J w), written with the entries of U (which hold the
    /// products w_i w_j already): with J = [XX XY XZ; XY YY YZ; XZ YZ ZZ],
    /// N_x = XX wdx - XY U20 + XZ U10 + YZ (U11 - U22) + (ZZ - YY) wy wz, and
    /// the other two by the cyclic permutation x -> y -> z.
    fn euler(&mut self, inertia: &[E; 6], w: V3, wd: V3, u: &[[E; 3]; 3]) -> V3 {
        let [xx, xy, xz, yy, yz, zz] = *inertia;
        // j[a][b]: the inertia entry (a, b).
        let j = [[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]];
        [0, 1, 2].map(|a| {
            let (b, c) = ((a + 1) % 3, (a + 2) % 3);
            // N_a = J_aa wd_a - J_ab U_ca + J_ac U_ba + J_bc (U_bb - U_cc) + (J_cc - J_bb) w_b w_c
            let diagonal = self.mul(j[a][a], wd[a]);
            let t1 = self.mul(j[a][b], u[c][a]);
            let t2 = self.mul(j[a][c], u[b][a]);
            // U_bb - U_cc = w_b^2 - w_c^2, from the squares (U_bb may be dead).
            let (sb, sc) = (self.mul(w[b], w[b]), self.mul(w[c], w[c]));
            let squares = self.add(&[sb, neg(sc)]);
            let t3 = self.mul(j[b][c], squares);
            let difference = self.add(&[j[c][c], neg(j[b][b])]);
            let wbwc = self.mul(w[b], w[c]);
            let t4 = self.mul(difference, wbwc);
            self.add(&[diagonal, neg(t1), t2, t3, t4])
        })
    }

    fn frame(&mut self, f: &FrameExprs) -> Result<Frame, ProgramError> {
        let (sa, ca, d) = (self.e(f.sa)?, self.e(f.ca)?, self.e(f.d)?);
        let py = self.mul(sa, d);
        Ok(Frame {
            kind: f.kind,
            sa,
            ca,
            st: self.e(f.st)?,
            ct: self.e(f.ct)?,
            p: [self.e(f.a)?, neg(py), self.mul(ca, d)],
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

    fn sign_of(&mut self, x: E) -> E {
        match x.v {
            _ if x.c == 0.0 => ZERO,
            None => number(x.c.signum()),
            Some(v) => E {
                c: x.c.signum(),
                v: Some(self.emit(Instr::Sign(v))),
            },
        }
    }

    /// The planar form of link `f`'s w and wd, from its parent's (`plane`,
    /// `w`, `wd`): it starts where a joint is perpendicular to a parent that
    /// turns about its own z only (w_xy = W e, wd_xy = Wd e, e = z_(j-1)
    /// in frame j) and carries on through joints with alpha in {0, pi}.
    fn plane(&mut self, f: &Frame, plane: Option<Plane>, w: V3, wd: V3) -> Option<Plane> {
        let zero = |x: E| x.c == 0.0;
        if zero(f.ca) && [w[0], w[1], wd[0], wd[1]].into_iter().all(zero) {
            let e = self.rotate_back(f, [ZERO, ZERO, number(1.0)]);
            Some(Plane {
                e: [e[0], e[1]],
                a: w[2],
                b: wd[2],
            })
        } else if zero(f.sa) {
            let p = plane?;
            let e = self.rotate_back(f, [p.e[0], p.e[1], ZERO]);
            Some(Plane {
                e: [e[0], e[1]],
                ..p
            })
        } else {
            None
        }
    }

    /// The forward recursion of the customised Newton-Euler algorithm.
    pub(super) fn forward(
        &mut self,
        frames: &[FrameExprs],
        inputs: &RunInputs<'_>,
    ) -> Result<Kinematics, ProgramError> {
        let n = frames.len();
        let frames: Vec<Frame> = frames
            .iter()
            .map(|f| self.frame(f))
            .collect::<Result<_, _>>()?;
        let mut qd = Vec::with_capacity(n);
        let mut qdd = Vec::with_capacity(n);
        for j in 0..n {
            qd.push(self.e(inputs.qd[j])?);
            qdd.push(self.e(inputs.qdd[j])?);
        }
        let mut g = [ZERO; 3];
        for (x, &id) in g.iter_mut().zip(&inputs.gravity) {
            *x = neg(self.e(id)?);
        }
        // Forward: w, wd, vd and U of every link.
        let (mut w, mut wd, mut vd) = ([ZERO; 3], [ZERO; 3], g);
        let mut u = [[ZERO; 3]; 3];
        let mut plane: Option<Plane> = None;
        let mut kin = Vec::with_capacity(n);
        for (j, f) in frames.iter().enumerate() {
            let up = self.mat_vec(&u, f.p);
            let vd_parent = self.add3(&[vd, up]);
            let vd_in = self.rotate_back(f, vd_parent);
            let w_in = self.rotate_back(f, w);
            let wd_in = self.rotate_back(f, wd);
            plane = self.plane(f, plane, w, wd);
            let wy_qd = self.mul(w_in[1], qd[j]);
            let wx_qd = self.mul(w_in[0], qd[j]);
            let (w_z, wd_z) = match f.kind {
                JointKind::Revolute => (self.add(&[w_in[2], qd[j]]), self.add(&[wd_in[2], qdd[j]])),
                JointKind::Prismatic => (w_in[2], wd_in[2]),
            };
            if let Some(p) = plane {
                // w_xy = a e, wd_xy = b e + w_z (w_y, -w_x).
                w = [self.mul(p.a, p.e[0]), self.mul(p.a, p.e[1]), w_z];
                let (be_x, be_y) = (self.mul(p.b, p.e[0]), self.mul(p.b, p.e[1]));
                let (zy, zx) = (self.mul(w_z, w[1]), self.mul(w_z, w[0]));
                wd = [self.add(&[be_x, zy]), self.add(&[be_y, neg(zx)]), wd_z];
            } else if f.kind == JointKind::Revolute {
                w = [w_in[0], w_in[1], w_z];
                wd = [
                    self.add(&[wd_in[0], wy_qd]),
                    self.add(&[wd_in[1], neg(wx_qd)]),
                    wd_z,
                ];
            } else {
                w = w_in;
                wd = wd_in;
            }
            vd = match f.kind {
                JointKind::Revolute => vd_in,
                JointKind::Prismatic => [
                    self.add(&[vd_in[0], wy_qd, wy_qd]),
                    self.add(&[vd_in[1], neg(wx_qd), neg(wx_qd)]),
                    self.add(&[vd_in[2], qdd[j]]),
                ],
            };
            u = self.u_matrix(w, wd);
            if let Some(p) = plane {
                // w_y w_z - wd_x and w_x w_z + wd_y, with the products cancelled.
                let (be_x, be_y) = (self.mul(p.b, p.e[0]), self.mul(p.b, p.e[1]));
                u[1][2] = neg(be_x);
                u[0][2] = be_y;
            }
            kin.push((w, wd, vd, u));
        }
        Ok(Kinematics {
            frames,
            qd,
            qdd,
            kin,
        })
    }

    /// `axes[j][i]`: the axis z_i of joint i <= j expressed in frame j.
    pub(super) fn axes(&mut self, k: &Kinematics) -> Vec<Vec<V3>> {
        let z = [ZERO, ZERO, number(1.0)];
        let mut axes: Vec<Vec<V3>> = Vec::with_capacity(k.frames.len());
        for f in &k.frames {
            let mut here: Vec<V3> = match axes.last() {
                Some(previous) => previous.iter().map(|&a| self.rotate_back(f, a)).collect(),
                None => Vec::new(),
            };
            here.push(z);
            axes.push(here);
        }
        axes
    }

    /// `arms[j][i]`: z_i x P_(i, j) expressed in frame j, for i <= j, where
    /// P_(i, j) is the vector from O_i to O_j: the torque about z_i of a
    /// force f at O_j is arms[j][i] . f.
    pub(super) fn arms(&mut self, k: &Kinematics, axes: &[Vec<V3>]) -> Vec<Vec<V3>> {
        let mut arms: Vec<Vec<V3>> = Vec::with_capacity(k.frames.len());
        for (j, f) in k.frames.iter().enumerate() {
            let mut here: Vec<V3> = Vec::with_capacity(j + 1);
            if j > 0 {
                for i in 0..j {
                    let previous = arms[j - 1][i];
                    let moment = self.cross(axes[j - 1][i], f.p);
                    let sum = self.add3(&[previous, moment]);
                    here.push(self.rotate_back(f, sum));
                }
            }
            here.push([ZERO; 3]);
            arms.push(here);
        }
        arms
    }

    /// The torques of the wrench (`force`, `moment`) at O_j, expressed in
    /// frame j, at every joint i <= j.
    pub(super) fn projected(
        &mut self,
        k: &Kinematics,
        axes: &[Vec<V3>],
        arms: &[Vec<V3>],
        j: usize,
        force: V3,
        moment: V3,
    ) -> Vec<E> {
        let mut tau = vec![ZERO; k.frames.len()];
        for (i, t) in tau.iter_mut().enumerate().take(j + 1) {
            let terms: Vec<E> = match k.frames[i].kind {
                JointKind::Revolute => (0..3)
                    .flat_map(|c| [(axes[j][i][c], moment[c]), (arms[j][i][c], force[c])])
                    .map(|(a, b)| self.mul(a, b))
                    .collect(),
                JointKind::Prismatic => (0..3).map(|c| self.mul(axes[j][i][c], force[c])).collect(),
            };
            *t = self.add(&terms);
        }
        tau
    }

    /// The base regressor column of a single link parameter: `l` holds
    /// link `j`'s parameters (one slot at 1, the others at 0), its wrench is
    /// projected on the joint axes ([`Lowering::projected`]).
    pub(super) fn link_column(
        &mut self,
        k: &Kinematics,
        axes: &[Vec<V3>],
        arms: &[Vec<V3>],
        j: usize,
        l: &LinkParameters,
    ) -> Result<Vec<E>, ProgramError> {
        let l = self.link(l)?;
        let (w, wd, vd, u) = k.kin[j];
        let m_vd = vd.map(|x| self.mul(l.m, x));
        let u_ms = self.mat_vec(&u, l.ms);
        let force = self.add3(&[m_vd, u_ms]);
        let euler = self.euler(&l.inertia, w, wd, &u);
        let ms_x_vd = self.cross(l.ms, vd);
        let moment = self.add3(&[euler, ms_x_vd]);
        let mut tau = self.projected(k, axes, arms, j, force, moment);
        let ia = self.mul(l.ia, k.qdd[j]);
        let fv = self.mul(l.fv, k.qd[j]);
        let s = self.sign_of(k.qd[j]);
        let fc = self.mul(l.fc, s);
        tau[j] = self.add(&[tau[j], ia, fv, fc, l.fo]);
        Ok(tau)
    }

    /// Joint torques of the customised Newton-Euler algorithm.
    pub(super) fn newton_euler(
        &mut self,
        frames: &[FrameExprs],
        inputs: &RunInputs<'_>,
        links: &[LinkParameters],
    ) -> Result<Vec<E>, ProgramError> {
        let n = frames.len();
        let links: Vec<Link> = links
            .iter()
            .map(|l| self.link(l))
            .collect::<Result<_, _>>()?;
        let Kinematics {
            frames,
            qd,
            qdd,
            kin,
        } = self.forward(frames, inputs)?;
        // Backward: wrenches and torques.
        let mut tau = vec![ZERO; n];
        let mut f_next: V3 = [ZERO; 3];
        let mut n_next: V3 = [ZERO; 3];
        for j in (0..n).rev() {
            let (w, wd, vd, u) = kin[j];
            let l = &links[j];
            let m_vd = vd.map(|x| self.mul(l.m, x));
            let u_ms = self.mat_vec(&u, l.ms);
            let force = self.add3(&[m_vd, u_ms]);
            let euler = self.euler(&l.inertia, w, wd, &u);
            let ms_x_vd = self.cross(l.ms, vd);
            let moment = self.add3(&[euler, ms_x_vd]);
            let (f, m) = if j + 1 < n {
                let next = &frames[j + 1];
                let rf = self.rotate(next, f_next);
                let rm = self.rotate(next, n_next);
                let p_x_rf = self.cross(next.p, rf);
                (self.add3(&[force, rf]), self.add3(&[moment, rm, p_x_rf]))
            } else {
                (force, moment)
            };
            let axis = match frames[j].kind {
                JointKind::Revolute => m[2],
                JointKind::Prismatic => f[2],
            };
            let ia = self.mul(l.ia, qdd[j]);
            let fv = self.mul(l.fv, qd[j]);
            let s = self.sign_of(qd[j]);
            let fc = self.mul(l.fc, s);
            tau[j] = self.add(&[axis, ia, fv, fc, l.fo]);
            f_next = f;
            n_next = m;
        }
        Ok(tau)
    }

    /// `a + sum b_k c_k` for expressions b_k, c_k (the fallback of a base
    /// parameter without a link slot).
    pub(super) fn add_products(&mut self, a: E, products: &[(Id, Id)]) -> Result<E, ProgramError> {
        let mut terms = vec![a];
        for &(b, c) in products {
            let (b, c) = (self.e(b)?, self.e(c)?);
            terms.push(self.mul(b, c));
        }
        Ok(self.add(&terms))
    }
}
