//! The mass matrix by the composite-rigid-body algorithm (Featherstone's CRBA, in
//! Khalil's form with link parameters about the frame origins;
//! docs/dynamics.md#composite-rigid-body-mass-matrix), written on the same lazy values
//! as the customised Newton-Euler algorithm, so zero parameters and DH angles in
//! {0, +-pi/2} fold away.
//!
//! From the tip inwards, the composite body C_j of links j..n is carried in frame j
//! (mass, first moment and inertia about O_j): C_j = link j + C_(j+1) rotated by
//! R_(j, j+1) and moved from O_(j+1) to O_j by the parallel-axis transfer. A unit
//! acceleration of joint j at rest accelerates C_j alone, as one rigid body; its wrench
//! about O_j gives M_jj (plus the rotor inertia Ia_j) and, moved to the frames of the
//! joints before j, the entries M_ij, i < j. Only i <= j is computed.

use super::super::ProgramError;
use super::{E, Frame, FrameExprs, Link, Lowering, V3, ZERO, neg};
use crate::dynamics::LinkParameters;
use crate::robot::JointKind;

/// A composite body in its frame: inertia about the origin (XX XY XZ YY YZ ZZ, the
/// tensor's entries), first moment, mass.
#[derive(Clone, Copy, Debug)]
struct Composite {
    inertia: [E; 6],
    ms: V3,
    m: E,
}

/// The slot of entry (a, b) of a symmetric 3 x 3 tensor in XX XY XZ YY YZ ZZ.
fn slot(a: usize, b: usize) -> usize {
    const SLOTS: [[usize; 3]; 3] = [[0, 1, 2], [1, 3, 4], [2, 4, 5]];
    SLOTS[a][b]
}

impl Lowering<'_> {
    /// The mass matrix, row-major and symmetric, of the links `links` (base parameters
    /// in their slots) in the frames `frames`.
    pub(in crate::program) fn mass_matrix(
        &mut self,
        frames: &[FrameExprs],
        links: &[LinkParameters],
    ) -> Result<Vec<E>, ProgramError> {
        let n = frames.len();
        let links: Vec<Link> = links
            .iter()
            .map(|l| self.link(l))
            .collect::<Result<_, _>>()?;
        let frames: Vec<Frame> = frames
            .iter()
            .map(|f| self.frame(f))
            .collect::<Result<_, _>>()?;
        let mut m = vec![ZERO; n * n];
        let mut next: Option<Composite> = None;
        for j in (0..n).rev() {
            let l = &links[j];
            let mut c = Composite {
                inertia: l.inertia,
                ms: l.ms,
                m: l.m,
            };
            if let Some(child) = next {
                let moved = self.transfer(&frames[j + 1], child);
                c = Composite {
                    inertia: [0, 1, 2, 3, 4, 5]
                        .map(|k| self.add(&[c.inertia[k], moved.inertia[k]])),
                    ms: self.add3(&[c.ms, moved.ms]),
                    m: self.add(&[c.m, moved.m]),
                };
            }
            // The wrench about O_j, in frame j, of C_j for a unit acceleration of joint j.
            let (mut f, mut moment) = match frames[j].kind {
                JointKind::Revolute => (
                    [neg(c.ms[1]), c.ms[0], ZERO],
                    [c.inertia[2], c.inertia[4], c.inertia[5]],
                ),
                JointKind::Prismatic => ([ZERO, ZERO, c.m], [c.ms[1], neg(c.ms[0]), ZERO]),
            };
            let axis = |kind: JointKind, f: &V3, moment: &V3| match kind {
                JointKind::Revolute => moment[2],
                JointKind::Prismatic => f[2],
            };
            m[j * n + j] = self.add(&[axis(frames[j].kind, &f, &moment), l.ia]);
            // Moved to the frames of the joints before j: f_(k-1) = R f_k,
            // n_(k-1) = R n_k + P_k x f_(k-1).
            for k in (1..=j).rev() {
                let fr = &frames[k];
                f = self.rotate(fr, f);
                let rn = self.rotate(fr, moment);
                let p_x_f = self.cross(fr.p, f);
                moment = self.add3(&[rn, p_x_f]);
                let entry = axis(frames[k - 1].kind, &f, &moment);
                m[(k - 1) * n + j] = entry;
                m[j * n + k - 1] = entry;
            }
            next = Some(c);
        }
        Ok(m)
    }

    /// The composite `c` of frame `f`'s link, in the parent's frame about its origin:
    /// rotated by R = Rz(gamma) Rx(alpha) Rz(theta), then moved by P (the parallel-axis
    /// transfer, docs/dynamics.md#composite-rigid-body-mass-matrix).
    fn transfer(&mut self, f: &Frame, c: Composite) -> Composite {
        let mut j = self.rotate_tensor(2, (f.st, f.ct), c.inertia);
        j = self.rotate_tensor(0, (f.sa, f.ca), j);
        if let Some(g) = f.gamma {
            j = self.rotate_tensor(2, g, j);
        }
        let u = self.rotate(f, c.ms);
        let p = f.p;
        // cm = u + m P, the first moment about O_(j-1).
        let mp = p.map(|x| self.mul(c.m, x));
        let cm = self.add3(&[u, mp]);
        // J + (P . (cm + u)) I - cm P' - P u' (skew(a) skew(b) = b a' - (a . b) I).
        let cu = self.add3(&[cm, u]);
        let diag_terms: [E; 3] = [0, 1, 2].map(|l| self.mul(p[l], cu[l]));
        let mut inertia = j;
        for a in 0..3 {
            for b in a..3 {
                let k = slot(a, b);
                inertia[k] = if a == b {
                    let others: Vec<E> =
                        (0..3).filter(|&l| l != a).map(|l| diag_terms[l]).collect();
                    let mut terms = vec![j[k]];
                    terms.extend(others);
                    self.add(&terms)
                } else {
                    let x = self.mul(cm[a], p[b]);
                    let y = self.mul(p[a], u[b]);
                    self.add(&[j[k], neg(x), neg(y)])
                };
            }
        }
        Composite {
            inertia,
            ms: cm,
            m: c.m,
        }
    }

    /// R J R' for the rotation R by the angle with (sin, cos) `(s, c)` about axis `axis`
    /// (0: x, 2: z) of the symmetric tensor J (XX XY XZ YY YZ ZZ). In the plane (a, b)
    /// of the rotation, with D = J_aa - J_bb and t = s^2 D + 2 c s J_ab:
    /// J_aa' = J_aa - t, J_bb' = J_bb + t, J_ab' = c s D + (c^2 - s^2) J_ab; across it
    /// J_ak' = c J_ak - s J_bk, J_bk' = s J_ak + c J_bk; J_kk' = J_kk. For a known angle
    /// the products of the entries with c^2, s^2, c s fold instead.
    fn rotate_tensor(&mut self, axis: usize, (s, c): (E, E), j: [E; 6]) -> [E; 6] {
        let (a, b) = ((axis + 1) % 3, (axis + 2) % 3);
        let (jaa, jbb, jab) = (j[slot(a, a)], j[slot(b, b)], j[slot(a, b)]);
        let (jak, jbk) = (j[slot(a, axis)], j[slot(b, axis)]);
        let ss = self.mul(s, s);
        let cc = self.mul(c, c);
        let cs = self.mul(c, s);
        let mut out = j;
        if s.v.is_none() && c.v.is_none() {
            // A known angle: the plain products fold into coefficients.
            let (x, y, z) = (self.mul(cc, jaa), self.mul(cs, jab), self.mul(ss, jbb));
            out[slot(a, a)] = self.add(&[x, neg(y), neg(y), z]);
            let (x, y, z) = (self.mul(ss, jaa), self.mul(cs, jab), self.mul(cc, jbb));
            out[slot(b, b)] = self.add(&[x, y, y, z]);
            let d = self.add(&[jaa, neg(jbb)]);
            let (x, y) = (self.mul(cs, d), self.mul(cc, jab));
            let z = self.mul(ss, jab);
            out[slot(a, b)] = self.add(&[x, y, neg(z)]);
        } else {
            let cs2 = self.twice(cs);
            let c2 = self.add(&[cc, neg(ss)]);
            let d = self.add(&[jaa, neg(jbb)]);
            let (x, y) = (self.mul(ss, d), self.mul(cs2, jab));
            let t = self.add(&[x, y]);
            out[slot(a, a)] = self.add(&[jaa, neg(t)]);
            out[slot(b, b)] = self.add(&[jbb, t]);
            let (x, y) = (self.mul(cs, d), self.mul(c2, jab));
            out[slot(a, b)] = self.add(&[x, y]);
        }
        let (x, y) = (self.mul(c, jak), self.mul(s, jbk));
        out[slot(a, axis)] = self.add(&[x, neg(y)]);
        let (x, y) = (self.mul(s, jak), self.mul(c, jbk));
        out[slot(b, axis)] = self.add(&[x, y]);
        out
    }

    /// 2 x as a value of its own (its coefficient's magnitude applied once), so that
    /// products with it carry no coefficient.
    fn twice(&mut self, x: E) -> E {
        let scaled = E { c: 2.0 * x.c, ..x };
        if x.v.is_none() {
            return scaled;
        }
        let s = self.signed(scaled);
        E {
            c: if s.negative { -1.0 } else { 1.0 },
            v: Some(s.value),
        }
    }
}
