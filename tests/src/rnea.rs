//! An independent plain-`f64` recursive Newton-Euler inverse dynamics, the numeric reference
//! the symbolic derivations are checked against.
//!
//! It shares no code with robid-symbolic and deliberately takes another route: every quantity
//! is computed in the base frame from the homogeneous transforms of the user's own DH frames
//! (standard or modified, used as they are, with no conversion between conventions), and the
//! joint axis of each convention is taken where the textbook puts it (z_(j-1) through O_(j-1)
//! for standard DH, z_j through O_j for modified DH). Link j's parameters are about the origin
//! O_j of its own frame, as the user gives them.
//!
//! ```text
//! Forward pass (base frame, gravity as a base acceleration of -g), for link j with joint
//! axis u through p and parent origin O_(j-1):
//!   w_j  = w_(j-1) + qd u (revolute),   wd_j = wd_(j-1) + qdd u + w_(j-1) x qd u,
//!   a(O_j) = a(O_(j-1)) + wd_(j-1) x r + w_(j-1) x (w_(j-1) x r) + a_rel + 2 w_(j-1) x v_rel,
//!   r = O_j - O_(j-1);
//!   revolute:  v_rel = qd u x (O_j - p),  a_rel = qdd u x (O_j - p) + qd u x v_rel;
//!   prismatic: v_rel = qd u,              a_rel = qdd u.
//! Link wrench about O_j, with MS and J rotated into the base frame:
//!   F = M a + wd x MS + w x (w x MS),   N = J wd + w x (J w) + MS x a.
//! Backward pass:
//!   f_j = F_j + f_(j+1),   n_j = N_j + n_(j+1) + (O_(j+1) - O_j) x f_(j+1),
//!   tau_j = u . (n_j + (O_j - p) x f_j) (revolute) or u . f_j (prismatic),
//!           plus Ia qdd + Fv qd + Fc sign(qd) + Fo.
//! ```

use robid_runtime::Real;
use robid_symbolic::robot::{DriveTerm, Inertial, ParameterKind};
use robid_symbolic::{Arena, Convention, JointKind, Robot};

/// A 3-vector.
pub type V3 = [f64; 3];
/// A 3x3 matrix, row-major.
pub type M3 = [[f64; 3]; 3];

/// One numeric DH row (in the table's own convention).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DhRow {
    /// Joint type.
    pub kind: JointKind,
    /// Twist.
    pub alpha: f64,
    /// Length.
    pub a: f64,
    /// Offset along z (joint variable's offset when prismatic).
    pub d: f64,
    /// Angle (joint variable's offset when revolute).
    pub theta: f64,
}

/// A numeric DH chain.
#[derive(Clone, Debug, PartialEq)]
pub struct Chain {
    /// Convention of the rows.
    pub convention: Convention,
    /// The rows, base to tip.
    pub rows: Vec<DhRow>,
    /// Gravity in the base frame.
    pub gravity: V3,
}

/// The parameters of one link about its frame origin, in its frame, and its joint's drive terms.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Link {
    /// Mass.
    pub mass: f64,
    /// First moment of mass (mass times centre of mass).
    pub first_moment: V3,
    /// Inertia tensor about the frame origin.
    pub inertia: M3,
    /// Rotor inertia.
    pub ia: f64,
    /// Viscous friction.
    pub fv: f64,
    /// Coulomb friction.
    pub fc: f64,
    /// Offset.
    pub fo: f64,
}

/// A pose: rotation and position of a frame in the base frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    /// Orientation.
    pub rotation: M3,
    /// Origin.
    pub position: V3,
}

impl Chain {
    /// The numeric chain of a robot; symbolic lengths take the robot's default values.
    pub fn from_robot(robot: &Robot) -> Chain {
        let mut arena = Arena::new();
        let pairs: Vec<(&str, f64)> = robot
            .symbols()
            .iter()
            .map(|(n, v)| {
                (
                    n.as_str(),
                    v.unwrap_or_else(|| panic!("symbol {n} has no value")),
                )
            })
            .collect();
        let values = arena.values(&pairs);
        let mut number = |g: &robid_symbolic::robot::Geometry| {
            let id = arena.parse(g.as_str()).expect("validated geometry");
            arena.eval(&[id], &values).expect("bound symbols")[0]
        };
        let rows = robot
            .joints()
            .iter()
            .map(|j| DhRow {
                kind: j.kind,
                alpha: number(&j.alpha),
                a: number(&j.a),
                d: number(&j.d),
                theta: number(&j.theta),
            })
            .collect();
        let gravity = [0, 1, 2].map(|i| number(&robot.gravity()[i]));
        Chain {
            convention: robot.convention(),
            rows,
            gravity,
        }
    }

    /// The pose of every link frame j (1..=n) in the base frame at `q`.
    pub fn poses(&self, q: &[f64]) -> Vec<Pose> {
        let mut pose = Pose {
            rotation: identity(),
            position: [0.0; 3],
        };
        self.rows
            .iter()
            .zip(q)
            .map(|(row, &qj)| {
                let (theta, d) = match row.kind {
                    JointKind::Revolute => (row.theta + qj, row.d),
                    JointKind::Prismatic => (row.theta, row.d + qj),
                };
                let steps = match self.convention {
                    Convention::Modified => [
                        Step::RotX(row.alpha),
                        Step::Along(0, row.a),
                        Step::RotZ(theta),
                        Step::Along(2, d),
                    ],
                    Convention::Standard => [
                        Step::RotZ(theta),
                        Step::Along(2, d),
                        Step::Along(0, row.a),
                        Step::RotX(row.alpha),
                    ],
                };
                for s in steps {
                    pose = s.apply(pose);
                }
                pose
            })
            .collect()
    }

    /// Joint torques (forces for prismatic joints) for link parameters `links`.
    pub fn inverse_dynamics(&self, links: &[Link], q: &[f64], qd: &[f64], qdd: &[f64]) -> Vec<f64> {
        let n = self.rows.len();
        assert!(links.len() == n && q.len() == n && qd.len() == n && qdd.len() == n);
        let poses = self.poses(q);
        let base = Pose {
            rotation: identity(),
            position: [0.0; 3],
        };
        // Joint axis (point, direction) of each joint, by convention.
        let axes: Vec<(V3, V3)> = (0..n)
            .map(|j| {
                let frame = match self.convention {
                    Convention::Modified => poses[j],
                    Convention::Standard => {
                        if j == 0 {
                            base
                        } else {
                            poses[j - 1]
                        }
                    }
                };
                (frame.position, column(&frame.rotation, 2))
            })
            .collect();
        let (mut w, mut wd) = ([0.0; 3], [0.0; 3]);
        let mut acc = scale(-1.0, self.gravity);
        let mut origin = [0.0; 3];
        let mut forces = Vec::with_capacity(n);
        let mut moments = Vec::with_capacity(n);
        for j in 0..n {
            let (p, u) = axes[j];
            let o = poses[j].position;
            let r = sub(o, origin);
            let coincident = add3(acc, cross(wd, r), cross(w, cross(w, r)));
            let (w_new, wd_new, v_rel, a_rel) = match self.rows[j].kind {
                JointKind::Revolute => {
                    let spin = scale(qd[j], u);
                    let v_rel = cross(spin, sub(o, p));
                    let a_rel = add(cross(scale(qdd[j], u), sub(o, p)), cross(spin, v_rel));
                    let wd_new = add3(wd, scale(qdd[j], u), cross(w, spin));
                    (add(w, spin), wd_new, v_rel, a_rel)
                }
                JointKind::Prismatic => (w, wd, scale(qd[j], u), scale(qdd[j], u)),
            };
            acc = add3(coincident, a_rel, scale(2.0, cross(w, v_rel)));
            w = w_new;
            wd = wd_new;
            origin = o;
            // Link wrench about O_j, parameters rotated into the base frame.
            let rot = &poses[j].rotation;
            let ms = mat_vec(rot, links[j].first_moment);
            let inertia = mat_mul(&mat_mul(rot, &links[j].inertia), &transpose(rot));
            let m = links[j].mass;
            forces.push(add3(scale(m, acc), cross(wd, ms), cross(w, cross(w, ms))));
            moments.push(add3(
                mat_vec(&inertia, wd),
                cross(w, mat_vec(&inertia, w)),
                cross(ms, acc),
            ));
        }
        let mut tau = vec![0.0; n];
        let (mut f, mut nm) = ([0.0; 3], [0.0; 3]);
        for j in (0..n).rev() {
            let o = poses[j].position;
            let child_lever = if j + 1 < n {
                cross(sub(poses[j + 1].position, o), f)
            } else {
                [0.0; 3]
            };
            f = add(forces[j], f);
            nm = add3(moments[j], nm, child_lever);
            let (p, u) = axes[j];
            let rigid = match self.rows[j].kind {
                JointKind::Revolute => dot(u, add(nm, cross(sub(o, p), f))),
                JointKind::Prismatic => dot(u, f),
            };
            let l = &links[j];
            tau[j] = rigid + l.ia * qdd[j] + l.fv * qd[j] + l.fc * qd[j].sign() + l.fo;
        }
        tau
    }
}

/// The entry of `link` that holds the standard parameter `kind`, written out variant by
/// variant (this module shares no mapping with robid-symbolic); the tensor's products
/// are set on both sides by the callers.
fn entry(l: &mut Link, kind: ParameterKind) -> &mut f64 {
    match kind {
        ParameterKind::Inertial(i) => match i {
            Inertial::XX => &mut l.inertia[0][0],
            Inertial::XY => &mut l.inertia[0][1],
            Inertial::XZ => &mut l.inertia[0][2],
            Inertial::YY => &mut l.inertia[1][1],
            Inertial::YZ => &mut l.inertia[1][2],
            Inertial::ZZ => &mut l.inertia[2][2],
            Inertial::MX => &mut l.first_moment[0],
            Inertial::MY => &mut l.first_moment[1],
            Inertial::MZ => &mut l.first_moment[2],
            Inertial::M => &mut l.mass,
        },
        ParameterKind::Drive(DriveTerm::Ia) => &mut l.ia,
        ParameterKind::Drive(DriveTerm::Fv) => &mut l.fv,
        ParameterKind::Drive(DriveTerm::Fc) => &mut l.fc,
        ParameterKind::Drive(DriveTerm::Fo) => &mut l.fo,
    }
}

/// Link parameters from values of `robot.standard_parameters()` (in the user's frames).
pub fn links_from_standard(robot: &Robot, values: &[f64]) -> Vec<Link> {
    let parameters = robot.standard_parameters();
    assert_eq!(parameters.len(), values.len());
    let mut links = vec![Link::default(); robot.dof()];
    for (p, &v) in parameters.iter().zip(values) {
        let l = &mut links[p.link];
        *entry(l, p.kind) = v;
        // the tensor is symmetric
        l.inertia[1][0] = l.inertia[0][1];
        l.inertia[2][0] = l.inertia[0][2];
        l.inertia[2][1] = l.inertia[1][2];
    }
    links
}

/// The values of `robot.standard_parameters()` for link parameters (inverse of
/// [`links_from_standard`]).
pub fn standard_from_links(robot: &Robot, links: &[Link]) -> Vec<f64> {
    robot
        .standard_parameters()
        .iter()
        .map(|p| *entry(&mut links[p.link].clone(), p.kind))
        .collect()
}

/// Parameters given in a frame B, expressed in a frame A where B has orientation `rotation`
/// and origin `origin`: MS_A = R MS_B + M t, and by the parallel-axis theorem through the
/// centre of mass J_A = R J_B R' + M (|t|^2 I - t t') + (2 t.u) I - u t' - t u' with u = R MS_B
/// (valid for any mass, including the zero or negative ones of random parameter sets).
pub fn express_in_parent(link: &Link, rotation: &M3, origin: V3) -> Link {
    let u = mat_vec(rotation, link.first_moment);
    let t = origin;
    let m = link.mass;
    let rj = mat_mul(&mat_mul(rotation, &link.inertia), &transpose(rotation));
    let mut inertia = rj;
    for (r, row) in inertia.iter_mut().enumerate() {
        for (c, x) in row.iter_mut().enumerate() {
            let delta = if r == c { 1.0 } else { 0.0 };
            *x += m * (dot(t, t) * delta - t[r] * t[c]) + 2.0 * dot(t, u) * delta
                - u[r] * t[c]
                - t[r] * u[c];
        }
    }
    Link {
        mass: m,
        first_moment: add(u, scale(m, t)),
        inertia,
        ..*link
    }
}

#[derive(Clone, Copy)]
enum Step {
    RotX(f64),
    RotZ(f64),
    Along(usize, f64),
}

impl Step {
    fn apply(self, pose: Pose) -> Pose {
        match self {
            Step::RotX(t) => Pose {
                rotation: mat_mul(&pose.rotation, &rot_x(t)),
                ..pose
            },
            Step::RotZ(t) => Pose {
                rotation: mat_mul(&pose.rotation, &rot_z(t)),
                ..pose
            },
            Step::Along(axis, x) => Pose {
                position: add(pose.position, scale(x, column(&pose.rotation, axis))),
                ..pose
            },
        }
    }
}

/// Rotation about x.
pub fn rot_x(t: f64) -> M3 {
    let (s, c) = t.sin_cos();
    [[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]]
}

/// Rotation about z.
pub fn rot_z(t: f64) -> M3 {
    let (s, c) = t.sin_cos();
    [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]
}

pub(crate) fn identity() -> M3 {
    [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
}

pub(crate) fn column(m: &M3, k: usize) -> V3 {
    [m[0][k], m[1][k], m[2][k]]
}

pub(crate) fn add(a: V3, b: V3) -> V3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

pub(crate) fn add3(a: V3, b: V3, c: V3) -> V3 {
    add(add(a, b), c)
}

pub(crate) fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

pub(crate) fn scale(s: f64, a: V3) -> V3 {
    [s * a[0], s * a[1], s * a[2]]
}

pub(crate) fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub(crate) fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

pub(crate) fn mat_vec(m: &M3, v: V3) -> V3 {
    [dot(m[0], v), dot(m[1], v), dot(m[2], v)]
}

pub(crate) fn transpose(m: &M3) -> M3 {
    [column(m, 0), column(m, 1), column(m, 2)]
}

/// Matrix product.
pub fn mat_mul(a: &M3, b: &M3) -> M3 {
    let bt = transpose(b);
    [0, 1, 2].map(|r| [0, 1, 2].map(|c| dot(a[r], bt[c])))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A single pendulum (one revolute joint about z0 = z1, gravity along -y0): point mass m at
    /// distance l along x1 gives tau = m l^2 qdd + m g l cos(q).
    #[test]
    fn pendulum_matches_closed_form() {
        for convention in [Convention::Modified, Convention::Standard] {
            let chain = Chain {
                convention,
                rows: vec![DhRow {
                    kind: JointKind::Revolute,
                    alpha: 0.0,
                    a: 0.0,
                    d: 0.0,
                    theta: 0.0,
                }],
                gravity: [0.0, -9.81, 0.0],
            };
            let (m, l) = (2.0, 0.7);
            let link = express_in_parent(
                &Link {
                    mass: m,
                    ..Link::default()
                },
                &identity(),
                [l, 0.0, 0.0],
            );
            let (q, qd, qdd) = (0.4, -1.3, 2.1);
            let tau = chain.inverse_dynamics(&[link], &[q], &[qd], &[qdd])[0];
            let expected = m * l * l * qdd + m * 9.81 * l * q.cos();
            assert!((tau - expected).abs() < 1e-12, "{tau} vs {expected}");
        }
    }

    /// A prismatic joint lifting a mass straight up: f = m (qdd + g).
    #[test]
    fn vertical_slider_matches_closed_form() {
        let chain = Chain {
            convention: Convention::Modified,
            rows: vec![DhRow {
                kind: JointKind::Prismatic,
                alpha: 0.0,
                a: 0.3,
                d: 0.1,
                theta: 0.5,
            }],
            gravity: [0.0, 0.0, -9.81],
        };
        let link = Link {
            mass: 3.0,
            first_moment: [0.3, -0.6, 0.9],
            ..Link::default()
        };
        let f = chain.inverse_dynamics(&[link], &[0.2], &[0.7], &[1.5])[0];
        assert!((f - 3.0 * (1.5 + 9.81)).abs() < 1e-12, "{f}");
    }
}
