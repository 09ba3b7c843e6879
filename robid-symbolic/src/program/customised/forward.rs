//! The forward recursion: w, wd, vd and Khalil's U of every link, with
//! planar angular motion (after a joint perpendicular to the base axis)
//! carried as a rotated unit vector.

use super::super::ProgramError;
use super::{E, Frame, FrameExprs, Lowering, RunInputs, V3, ZERO, neg, number};
use crate::robot::JointKind;

/// Angular motion about a single axis off z: w_xy = a e and
/// wd_xy = b e + w_z (w_y, -w_x), for a 2-vector e. Then w_xy and wd_xy cost
/// a rotation of e alone, and U_yz = -b e_x, U_xz = b e_y.
#[derive(Clone, Copy, Debug)]
struct Plane {
    e: [E; 2],
    a: E,
    b: E,
}

/// The forward recursion's results: frames as values, joint velocities and
/// accelerations, and w, wd, vd, U of every link.
pub(in crate::program) struct Kinematics {
    pub(super) frames: Vec<Frame>,
    pub(super) qd: Vec<E>,
    pub(super) qdd: Vec<E>,
    pub(super) kin: Vec<KinLink>,
    /// The base's acceleration as the links feel it, `vd_0 = -g` in frame 0.
    pub(super) vd0: V3,
}

/// w, wd, vd and U of a link.
pub(super) type KinLink = (V3, V3, V3, [[E; 3]; 3]);

impl Lowering<'_> {
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
    pub(in crate::program) fn forward(
        &mut self,
        frames: &[FrameExprs],
        inputs: &RunInputs<'_>,
    ) -> Result<Kinematics, ProgramError> {
        self.forward_with(frames, inputs, true)
    }

    /// [`Lowering::forward`], with the planar form of the angular motion or without.
    pub(in crate::program) fn forward_with(
        &mut self,
        frames: &[FrameExprs],
        inputs: &RunInputs<'_>,
        planar: bool,
    ) -> Result<Kinematics, ProgramError> {
        let n = frames.len();
        self.mark(|| "frames".to_owned());
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
            self.mark(|| format!("forward {}: vd", j + 1));
            let up = self.mat_vec(&u, f.p);
            let vd_parent = self.add3(&[vd, up]);
            let vd_in = self.rotate_back(f, vd_parent);
            self.mark(|| format!("forward {}: w, wd", j + 1));
            let w_in = self.rotate_back(f, w);
            let wd_in = self.rotate_back(f, wd);
            plane = match planar {
                true => self.plane(f, plane, w, wd),
                false => None,
            };
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
            self.mark(|| format!("forward {}: U", j + 1));
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
            vd0: g,
        })
    }

    /// U = skew(wd) + skew(w)^2.
    pub(super) fn u_matrix(&mut self, w: V3, wd: V3) -> [[E; 3]; 3] {
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
}
