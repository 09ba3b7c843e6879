//! The backward recursion: link wrenches (Euler equation written with U),
//! their transfer to the parent, and the torques; with the moments of the
//! links after a perpendicular joint projected instead of rotated back, and
//! the last link's moment taken about its parent's origin when that is on
//! its axis.

use super::super::ProgramError;
use super::forward::{KinLink, Kinematics};
use super::{Choices, E, Frame, FrameExprs, Link, Lowering, RunInputs, V3, ZERO, neg, number};
use crate::dynamics::LinkParameters;
use crate::robot::JointKind;

/// The last link's kinematics in its parent's frame ([`Lowering::tip`]).
struct Tip {
    /// Its joint axis.
    z: V3,
    w: V3,
    wd: V3,
    vd: V3,
    u: [[E; 3]; 3],
}

/// Links `start..=end` whose moments' x, y components are projected on
/// `axes[k - start]` (see [`Lowering::projection`]).
struct Projection {
    start: usize,
    end: usize,
    axes: Vec<V3>,
}

impl Lowering<'_> {
    /// Joint torques of the customised Newton-Euler algorithm. With `reuse`,
    /// an acceleration component a * x whose product is computed already (in
    /// the next link's acceleration) enters MS x vd as that product. With `tip`, the
    /// last link's wrench is written in its parent's frame when that is allowed (see
    /// [`Lowering::tip`]).
    pub(in crate::program) fn newton_euler(
        &mut self,
        frames: &[FrameExprs],
        inputs: &RunInputs<'_>,
        links: &[LinkParameters],
        choices: Choices,
    ) -> Result<Vec<E>, ProgramError> {
        let Choices { reuse, tip, .. } = choices;
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
            vd0,
        } = self.forward_with(frames, inputs, choices.plane)?;
        self.mark(|| "backward: projection axes, shift".to_owned());
        let projection = match choices.projection {
            true => self.projection(&frames),
            false => None,
        };
        let shift = match choices.shift {
            true => self.shift(&frames, &kin, &links),
            false => None,
        };
        // Not where the projection reaches the last link (its moment is projected in
        // its own frame there).
        let tip = tip
            && n >= 2
            && frames[n - 1].kind == JointKind::Revolute
            && projection.as_ref().is_none_or(|pr| pr.end + 1 < n);
        let mut projected: Vec<E> = Vec::new();
        // Backward: wrenches and torques.
        let mut tau = vec![ZERO; n];
        let mut f_next: V3 = [ZERO; 3];
        let mut n_next: V3 = [ZERO; 3];
        for j in (0..n).rev() {
            let l = &links[j];
            let in_parent = tip && j + 1 == n;
            self.mark(|| format!("backward {}: kinematics in the parent frame", j + 1));
            let (w, wd, vd, u, ms, axis_of) = if in_parent {
                let f = &frames[j];
                let t = self.tip(f, kin[j - 1], qd[j], qdd[j]);
                (t.w, t.wd, t.vd, t.u, self.rotate(f, l.ms), Some(t.z))
            } else {
                let (w, wd, vd, u) = kin[j];
                (w, wd, vd, u, l.ms, None)
            };
            self.mark(|| format!("backward {}: F", j + 1));
            let m_vd = vd.map(|x| self.mul(l.m, x));
            let u_ms = self.mat_vec(&u, ms);
            let force = self.add3(&[m_vd, u_ms]);
            self.mark(|| format!("backward {}: N (Euler)", j + 1));
            let (inertia, vd_moment) = match shift {
                // vd_o is the acceleration of the parent's origin, vd_(n-1) in the
                // parent's frame
                Some((d, _)) if in_parent => (self.shifted_inertia(l, d), kin[j - 1].2),
                Some((d, vd_o)) if j + 1 == n => (self.shifted_inertia(l, d), vd_o),
                _ => (l.inertia, vd),
            };
            let inertia = match in_parent {
                true => self.rotate_inertia(&frames[j], inertia),
                false => inertia,
            };
            // Of the moments of the projected links only e . n_xy is needed,
            // and w_xy lies along e there.
            let projected_link = projection
                .as_ref()
                .is_some_and(|pr| (pr.start..=pr.end).contains(&j));
            let euler = self.euler(&inertia, w, wd, &u, !projected_link);
            let vd_moment = match reuse {
                true => vd_moment.map(|x| self.reuse(x)),
                false => vd_moment,
            };
            self.mark(|| format!("backward {}: MS x vd", j + 1));
            let ms_x_vd = self.cross(ms, vd_moment);
            let moment = self.add3(&[euler, ms_x_vd]);
            self.mark(|| format!("backward {}: f, n (transfer)", j + 1));
            let (f, m) = if j + 1 < n {
                let next = &frames[j + 1];
                // the tip's wrench is in this frame already
                let (rf, mut rm) = match tip && j + 2 == n {
                    true => (f_next, n_next),
                    false => (self.rotate(next, f_next), self.rotate(next, n_next)),
                };
                if let Some(pr) = &projection
                    && pr.start < j + 1
                    && j < pr.end
                {
                    let e = pr.axes[j + 1 - pr.start];
                    projected.push(self.mul(e[0], n_next[0]));
                    projected.push(self.mul(e[1], n_next[1]));
                    (rm[0], rm[1]) = (ZERO, ZERO);
                }
                let p_x_rf = match shift {
                    // The moment of the last link is about O_j already.
                    Some(_) if j + 2 == n => [ZERO; 3],
                    _ => self.cross(next.p, rf),
                };
                (self.add3(&[force, rf]), self.add3(&[moment, rm, p_x_rf]))
            } else {
                (force, moment)
            };
            let mut m = m;
            if let Some(pr) = &projection
                && j < pr.start
            {
                if j + 1 == pr.start {
                    projected.push(m[2]);
                    m[2] = self.add(&projected);
                }
                // Not needed below the perpendicular joint (n_z alone is).
                (m[0], m[1]) = (ZERO, ZERO);
            }
            self.mark(|| format!("backward {}: torque", j + 1));
            let axis = match (frames[j].kind, axis_of) {
                (JointKind::Revolute, Some(z)) => {
                    let terms = [0, 1, 2].map(|i| self.mul(z[i], m[i]));
                    self.add(&terms)
                }
                (JointKind::Revolute, None) => m[2],
                (JointKind::Prismatic, _) => f[2],
            };
            let ia = self.mul(l.ia, qdd[j]);
            let fv = self.mul(l.fv, qd[j]);
            let s = self.sign_of(qd[j]);
            let fc = self.mul(l.fc, s);
            tau[j] = self.add(&[axis, ia, fv, fc, l.fo]);
            f_next = f;
            n_next = m;
        }
        // At rest, a revolute joint whose axis is vertical whatever q (it and every
        // joint before it parallel to z_0, and gravity along z_0) does no work against
        // gravity (turning about a vertical axis moves no mass up or down): its torque is
        // its constant drive term alone, where the sums above only cancel numerically.
        let zero = |x: &E| x.c == 0.0;
        if qd.iter().chain(&qdd).all(zero) && zero(&vd0[0]) && zero(&vd0[1]) {
            let vertical = frames.iter().take_while(|f| zero(&f.sa)).count();
            for j in (0..vertical).filter(|&j| frames[j].kind == JointKind::Revolute) {
                tau[j] = links[j].fo;
            }
        }
        Ok(tau)
    }

    /// J wd + w x (J w), written with the entries of U (which hold the
    /// products w_i w_j already): with J = [XX XY XZ; XY YY YZ; XZ YZ ZZ],
    /// N_x = XX wdx - XY U20 + XZ U10 + YZ (U11 - U22) + (ZZ - YY) wy wz, and
    /// the other two by the cyclic permutation x -> y -> z. Without
    /// `zz_xy`, N_x and N_y leave out ZZ's part, w_z ZZ (w_y, -w_x), for a
    /// link whose N_xy is only projected on a direction along which w_xy lies.
    pub(super) fn euler(
        &mut self,
        inertia: &[E; 6],
        w: V3,
        wd: V3,
        u: &[[E; 3]; 3],
        zz_xy: bool,
    ) -> V3 {
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
            let diagonal_of = |k: usize| {
                if k == 2 && a < 2 && !zz_xy {
                    ZERO
                } else {
                    j[k][k]
                }
            };
            let difference = self.add(&[diagonal_of(c), neg(diagonal_of(b))]);
            let wbwc = self.mul(w[b], w[c]);
            let t4 = self.mul(difference, wbwc);
            self.add(&[diagonal, neg(t1), t2, t3, t4])
        })
    }

    /// Where joints 2..=p are parallel to joint 1 (so of the moments of
    /// links 1..=p only n_z is needed), joint s = p + 1 perpendicular to
    /// them and joints s+1..=m parallel to s, the x, y components of the
    /// moments of links s..m reach the torques only through z_p, and
    /// z_p . R_(k+1) n_(k+1) = e_(k+1) . n_(k+1) with e_k = z_p in frame k: so
    /// they are projected on e_k instead of rotated back link by link.
    fn projection(&mut self, frames: &[Frame]) -> Option<Projection> {
        let zero = |x: E| x.c == 0.0;
        let start = 1
            + (1..frames.len())
                .take_while(|&i| zero(frames[i].sa))
                .count();
        if start >= frames.len() || !zero(frames[start].ca) {
            return None;
        }
        let end = start
            + (start + 1..frames.len())
                .take_while(|&i| zero(frames[i].sa))
                .count();
        let mut e = self.rotate_back(&frames[start], [ZERO, ZERO, number(1.0)]);
        let mut axes = vec![e];
        for f in &frames[start + 1..=end] {
            e = self.rotate_back(f, e);
            axes.push(e);
        }
        Some(Projection { start, end, axes })
    }

    /// The last link's moment taken about O_(n-1) instead of O_n when O_(n-1)
    /// is on its axis (a_n = b_n = 0; r = O_(n-1) O_n = [0, 0, d] in frame n) and
    /// it has neither mass nor MZ: n + r x F = J' wd + w x (J' w) + MS x vd_o
    /// with J' = J - MS r' - r MS' (XZ - d MX, YZ - d MY) and vd_o the
    /// acceleration of O_(n-1). The torque about z_n is the same, the
    /// parent's P x R f drops out and vd_n is not needed. Returns d and vd_o.
    fn shift(&mut self, frames: &[Frame], kin: &[KinLink], links: &[Link]) -> Option<(E, V3)> {
        let zero = |x: E| x.c == 0.0;
        let n = frames.len();
        let (f, l) = (frames.last()?, links.last()?);
        if n < 2
            || f.kind != JointKind::Revolute
            || !zero(f.p_dh[0])
            || !zero(f.b)
            || !zero(l.m)
            || !zero(l.ms[2])
        {
            return None;
        }
        // The DH part of P is [0, -sa d, ca d] (and P = Rz(gamma) of it, along z_n)
        let (a, b) = (self.mul(f.ca, f.p_dh[2]), self.mul(f.sa, f.p_dh[1]));
        let d = self.add(&[a, neg(b)]);
        let vd_o = self.rotate_back(f, kin[n - 2].2);
        Some((d, vd_o))
    }

    /// The last link's kinematics in its parent's frame, from the parent's
    /// (`w`, `wd`, `vd`, `U`): the joint axis z = R z_n, w = w_p + qd z,
    /// wd = wd_p + qdd z + w_p x qd z, vd = vd_p + U_p P (the acceleration of O_n) and
    /// U of those. With alpha in {0, +-pi/2} and gamma = 0, z is a coordinate axis and
    /// none of this rotates anything: the last link's w, wd and vd and its wrench are
    /// not rotated (only its inertia and MS are, [`Lowering::rotate_inertia`]), its
    /// squares and products of w are mostly its parent's, and so are the entries U_ak
    /// (a != k) of U about the axis k.
    fn tip(&mut self, f: &Frame, parent: KinLink, qd: E, qdd: E) -> Tip {
        let (w_p, wd_p, vd_p, u_p) = parent;
        let z = self.rotate(f, [ZERO, ZERO, number(1.0)]);
        let z_qd = z.map(|x| self.mul(x, qd));
        let z_qdd = z.map(|x| self.mul(x, qdd));
        let w = self.add3(&[w_p, z_qd]);
        let w_x_z = self.cross(w_p, z_qd);
        let wd = self.add3(&[wd_p, z_qdd, w_x_z]);
        let up = self.mat_vec(&u_p, f.p);
        let vd = self.add3(&[vd_p, up]);
        let mut u = self.u_matrix(w, wd);
        // U = U_p + qdd skew(z) + 2 qd z w_p' + qd^2 z z' - (2 qd w_p . z + qd^2) I, so
        // where z is the coordinate axis k the entries U_ak (a != k) are the parent's.
        let zero = |x: E| x.c == 0.0;
        if let [k] = *(0..3).filter(|&i| !zero(z[i])).collect::<Vec<_>>() {
            for a in (0..3).filter(|&a| a != k) {
                u[a][k] = u_p[a][k];
            }
        }
        Tip { z, w, wd, vd, u }
    }

    /// R J R' for the rotation R = Rz(gamma) Rx(alpha) Rz(theta) of frame `f` and the
    /// inertia `j` = [XX, XY, XZ, YY, YZ, ZZ]: the symmetric matrix turned about z, x
    /// and z in turn ([`Lowering::turn_symmetric`]), which costs nothing for alpha in
    /// {0, +-pi/2} and gamma = 0 but the turn by theta.
    pub(super) fn rotate_inertia(&mut self, f: &Frame, j: [E; 6]) -> [E; 6] {
        let [xx, xy, xz, yy, yz, zz] = j;
        let mut m = [[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]];
        m = self.turn_symmetric(m, (0, 1, 2), (f.st, f.ct));
        m = self.turn_symmetric(m, (1, 2, 0), (f.sa, f.ca));
        if let Some(g) = f.gamma {
            m = self.turn_symmetric(m, (0, 1, 2), g);
        }
        [m[0][0], m[0][1], m[0][2], m[1][1], m[1][2], m[2][2]]
    }

    /// Q M Q' for symmetric `m` and the turn Q by the angle with (sin, cos) `(s, c)`
    /// about axis `k`, taking axis `a` towards axis `b` (`(a, b, k)` = (x, y, z) for a
    /// turn about z, (y, z, x) about x). With the block's first row turned,
    /// (u, v) = (c M_aa - s M_ab, c M_ab - s M_bb): M'_aa = c u - s v, M'_ab = s u + c v,
    /// M'_bb = M_aa + M_bb - M'_aa (the trace of the block is kept),
    /// (M'_ak, M'_bk) = the turn of (M_ak, M_bk) and M'_kk = M_kk.
    fn turn_symmetric(
        &mut self,
        m: [[E; 3]; 3],
        (a, b, k): (usize, usize, usize),
        (s, c): (E, E),
    ) -> [[E; 3]; 3] {
        // c x - s y
        let mut first = |x: E, y: E| {
            let (p, q) = (self.mul(c, x), self.mul(s, y));
            self.add(&[p, neg(q)])
        };
        let (u, v) = (first(m[a][a], m[a][b]), first(m[a][b], m[b][b]));
        let (aa, ak) = (first(u, v), first(m[a][k], m[b][k]));
        // s x + c y
        let mut second = |x: E, y: E| {
            let (p, q) = (self.mul(s, x), self.mul(c, y));
            self.add(&[p, q])
        };
        let (ab, bk) = (second(u, v), second(m[a][k], m[b][k]));
        let bb = self.add(&[m[a][a], m[b][b], neg(aa)]);
        let mut out = m;
        out[a][a] = aa;
        out[b][b] = bb;
        (out[a][b], out[b][a]) = (ab, ab);
        (out[a][k], out[k][a]) = (ak, ak);
        (out[b][k], out[k][b]) = (bk, bk);
        out
    }

    fn shifted_inertia(&mut self, l: &Link, d: E) -> [E; 6] {
        let mut j = l.inertia;
        for (slot, ms) in [(2, l.ms[0]), (4, l.ms[1])] {
            let t = self.mul(d, ms);
            j[slot] = self.add(&[j[slot], neg(t)]);
        }
        j
    }
}
