//! Base regressor columns: the wrench of one link parameter, projected on
//! the axes of the joints before it (expressed in the link's frame).

use super::super::ProgramError;
use super::forward::Kinematics;
use super::{E, Lowering, V3, ZERO, number};
use crate::dynamics::LinkParameters;
use crate::robot::JointKind;

impl Lowering<'_> {
    /// `axes[j][i]`: the axis z_i of joint i <= j expressed in frame j.
    pub(in crate::program) fn axes(&mut self, k: &Kinematics) -> Vec<Vec<V3>> {
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
    pub(in crate::program) fn arms(&mut self, k: &Kinematics, axes: &[Vec<V3>]) -> Vec<Vec<V3>> {
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
    pub(in crate::program) fn projected(
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
    pub(in crate::program) fn link_column(
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
        let euler = self.euler(&l.inertia, w, wd, &u, true);
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
}
