//! An independent plain-`f64` recursive Newton-Euler on a URDF's own frames, the numeric
//! reference for robid's URDF reader (it complements the DH reference [`crate::rnea`]).
//!
//! It shares nothing with robid-symbolic: the file is read with the `urdf-rs` crate (not
//! robid's roxmltree-based reader) and the dynamics are computed directly on the URDF's link
//! and joint frames, with no conversion to DH:
//!
//! - the whole tree: every link, fixed joints as rigid connections, revolute and continuous
//!   joints rotating about their axis, prismatic joints sliding along it; an axis is
//!   normalised (`1 1 0` is the unit vector along x + y); mimic tags are ignored, every
//!   movable joint is independent;
//! - link frame of a joint's child = parent frame * origin(xyz, rpy) * motion(q), with
//!   rpy = Rz(yaw) Ry(pitch) Rx(roll) and the axis given in the child (joint) frame;
//! - each link's `<inertial>` as written: mass, centre of mass at the inertial origin's xyz,
//!   inertia about the centre of mass in the inertial origin's rotated frame (a link without
//!   `<inertial>` has none);
//! - fixed base at the chosen base link (the root by default), gravity [0, 0, -9.81] in the
//!   base link's frame; rigid-body torques only (no `<dynamics>` damping or friction, no
//!   rotor inertia), as Pinocchio's `rnea`.
//!
//! `snap` is the reading rule of robid's URDF reader ("a value within 1e-9 of a multiple of
//! pi/2 may be treated as exact"): with `snap = true` every rpy angle (joint and inertial
//! origins) within 1e-9 of k pi/2 has the exact sine and cosine of k pi/2 (0 or +-1); with
//! `snap = false` the written values are used.
//!
//! ```text
//! Everything in the base frame. Links are visited from the base outwards; each joint is
//! crossed from the known link F to the new link T, forwards (parent to child, s = +1) or
//! backwards (child to parent, s = -1, when the base is not the root). The joint's axis u is
//! fixed in F and passes through the joint point c (the origin of the joint's child link):
//!   revolute:  w_T = w_F + s qd u,  wd_T = wd_F + s qdd u + w_F x s qd u,
//!              v_rel = s qd u x (O_T - c),  a_rel = s qdd u x (O_T - c) + s qd u x v_rel;
//!   prismatic: w_T = w_F,  wd_T = wd_F,  v_rel = s qd u,  a_rel = s qdd u;
//!   a(O_T) = a(O_F) + wd_F x r + w_F x (w_F x r) + a_rel + 2 w_F x v_rel,  r = O_T - O_F,
//!   starting from w = wd = 0 and a = -g at the base.
//! Wrench of link T about its origin, with its centre of mass C and inertia I_C (base axes):
//!   F = m a(C),  N = I_C wd + w x (I_C w) + (C - O_T) x F.
//! Subtrees, from the leaves in: f_F += f_T,  n_F += n_T + (O_T - O_F) x f_T;
//!   tau = s u . (n_T + (O_T - c) x f_T) (revolute) or s u . f_T (prismatic),
//! the effort of the joint's parent on its child (the subtree beyond a backwards joint is on
//! the parent's side, hence the sign s).
//! ```

use crate::rnea::{
    M3, V3, add, add3, cross, dot, identity, mat_mul, mat_vec, scale, sub, transpose,
};
use std::collections::HashMap;
use std::f64::consts::FRAC_PI_2;

/// How far from a multiple of pi/2 an rpy angle may be and still be snapped to it.
pub const SNAP_TOLERANCE: f64 = 1e-9;

/// Gravity in the base link's frame.
pub const GRAVITY: V3 = [0.0, 0.0, -9.81];

/// The motion a joint allows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Motion {
    /// A rigid connection.
    Fixed,
    /// Rotation about the axis (URDF `revolute` and `continuous`).
    Revolute,
    /// Translation along the axis.
    Prismatic,
}

/// One link: its inertial element, about its centre of mass, in the link's own axes.
#[derive(Clone, Debug)]
struct Body {
    name: String,
    mass: f64,
    /// Centre of mass in the link frame.
    com: V3,
    /// Inertia about the centre of mass, in the link frame's axes.
    inertia: M3,
}

/// One joint, with its origin resolved into a rotation and a translation.
#[derive(Clone, Debug)]
struct Joint {
    name: String,
    motion: Motion,
    parent: usize,
    child: usize,
    /// The joint (child) frame at q = 0 in the parent frame.
    rotation: M3,
    translation: V3,
    /// Unit axis in the joint frame.
    axis: V3,
}

/// One crossing of a joint while walking the tree out from the base.
#[derive(Clone, Copy, Debug)]
struct Step {
    joint: usize,
    from: usize,
    to: usize,
    /// `true` from parent to child.
    forwards: bool,
}

/// A link's pose and motion in the base frame.
#[derive(Clone, Copy, Debug)]
struct Kinematics {
    rotation: M3,
    origin: V3,
    w: V3,
    wd: V3,
    /// Acceleration of the origin, gravity included as a base acceleration of -g.
    acc: V3,
}

/// A URDF robot as a tree of links and joints, read with `urdf-rs`.
#[derive(Clone, Debug)]
pub struct UrdfTree {
    bodies: Vec<Body>,
    joints: Vec<Joint>,
    root: usize,
}

impl UrdfTree {
    /// Reads a URDF document; `snap` as in the [module documentation](self). Fails on an
    /// unreadable document, repeated names, unknown links, a link that is the child of two
    /// joints, no single root, a link the root does not reach, a floating, planar or
    /// spherical joint, or a movable joint with a zero or non-finite axis.
    pub fn from_str(text: &str, snap: bool) -> Result<UrdfTree, String> {
        let robot = urdf_rs::read_from_string(text).map_err(|e| e.to_string())?;
        let mut index = HashMap::new();
        let mut bodies = Vec::with_capacity(robot.links.len());
        for link in &robot.links {
            if index.insert(link.name.clone(), bodies.len()).is_some() {
                return Err(format!("link {} is defined twice", link.name));
            }
            let inertial = &link.inertial;
            let rotation = rpy(&inertial.origin.rpy, snap);
            let i = &inertial.inertia;
            let tensor = [
                [i.ixx, i.ixy, i.ixz],
                [i.ixy, i.iyy, i.iyz],
                [i.ixz, i.iyz, i.izz],
            ];
            bodies.push(Body {
                name: link.name.clone(),
                mass: inertial.mass.value,
                com: *inertial.origin.xyz,
                inertia: mat_mul(&mat_mul(&rotation, &tensor), &transpose(&rotation)),
            });
        }
        let mut names = HashMap::new();
        let mut parent_of: Vec<Option<usize>> = vec![None; bodies.len()];
        let mut joints = Vec::with_capacity(robot.joints.len());
        for joint in &robot.joints {
            if names.insert(joint.name.clone(), joints.len()).is_some() {
                return Err(format!("joint {} is defined twice", joint.name));
            }
            let find = |link: &str| {
                index
                    .get(link)
                    .copied()
                    .ok_or_else(|| format!("joint {}: no link named {link}", joint.name))
            };
            let (parent, child) = (find(&joint.parent.link)?, find(&joint.child.link)?);
            if parent_of[child].replace(joints.len()).is_some() {
                return Err(format!(
                    "link {} is the child of two joints",
                    joint.child.link
                ));
            }
            let motion = match joint.joint_type {
                urdf_rs::JointType::Fixed => Motion::Fixed,
                urdf_rs::JointType::Revolute | urdf_rs::JointType::Continuous => Motion::Revolute,
                urdf_rs::JointType::Prismatic => Motion::Prismatic,
                ref other => {
                    return Err(format!(
                        "joint {}: type {other:?} is not supported",
                        joint.name
                    ));
                }
            };
            let axis = *joint.axis.xyz;
            let norm = dot(axis, axis).sqrt();
            if motion != Motion::Fixed && !(norm.is_finite() && norm > 0.0) {
                return Err(format!(
                    "joint {}: axis {axis:?} has no direction",
                    joint.name
                ));
            }
            joints.push(Joint {
                name: joint.name.clone(),
                motion,
                parent,
                child,
                rotation: rpy(&joint.origin.rpy, snap),
                translation: *joint.origin.xyz,
                axis: if motion == Motion::Fixed {
                    [0.0; 3]
                } else {
                    scale(1.0 / norm, axis)
                },
            });
        }
        let roots: Vec<usize> = (0..bodies.len())
            .filter(|&l| parent_of[l].is_none())
            .collect();
        let [root] = roots[..] else {
            let names: Vec<&str> = roots.iter().map(|&l| bodies[l].name.as_str()).collect();
            return Err(format!("expected one root link, found {names:?}"));
        };
        let tree = UrdfTree {
            bodies,
            joints,
            root,
        };
        let reached = tree.walk(root).len() + 1;
        if reached != tree.bodies.len() {
            return Err(format!(
                "the root {} reaches {reached} of {} links (a cycle of joints)",
                tree.bodies[root].name,
                tree.bodies.len()
            ));
        }
        Ok(tree)
    }

    /// The root link's name.
    pub fn root(&self) -> &str {
        &self.bodies[self.root].name
    }

    /// The movable (revolute, continuous, prismatic) joints, in file order.
    pub fn joints(&self) -> Vec<String> {
        self.joints
            .iter()
            .filter(|j| j.motion != Motion::Fixed)
            .map(|j| j.name.clone())
            .collect()
    }

    /// The motion of the joint `name`, if there is one.
    pub fn motion(&self, name: &str) -> Option<Motion> {
        self.joints
            .iter()
            .find(|j| j.name == name)
            .map(|j| j.motion)
    }

    /// Torques (forces for prismatic joints) of the named movable joints, fixed base at the
    /// root; every other movable joint is held at zero (position, velocity, acceleration 0).
    /// Panics on an unknown, fixed or repeated name, or on lengths that differ from `chain`'s.
    pub fn torques(&self, chain: &[&str], q: &[f64], qd: &[f64], qdd: &[f64]) -> Vec<f64> {
        self.torques_from(self.root(), chain, q, qd, qdd)
    }

    /// As [`torques`](Self::torques) with the fixed base at the link `base` (gravity
    /// [0, 0, -9.81] in its frame): joints between the base and the root are crossed from
    /// child to parent, and their torque is still the effort of the parent on the child.
    /// Panics as `torques`, or on an unknown base.
    pub fn torques_from(
        &self,
        base: &str,
        chain: &[&str],
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
    ) -> Vec<f64> {
        let base = self.link(base);
        let columns = self.columns(chain);
        let n = chain.len();
        assert!(
            q.len() == n && qd.len() == n && qdd.len() == n,
            "{n} joints, {} positions, {} velocities, {} accelerations",
            q.len(),
            qd.len(),
            qdd.len()
        );
        let spread = |x: &[f64]| {
            let mut all = vec![0.0; self.joints.len()];
            for (&c, &v) in columns.iter().zip(x) {
                all[c] = v;
            }
            all
        };
        let (q, qd, qdd) = (spread(q), spread(qd), spread(qdd));
        let steps = self.walk(base);
        let states = self.kinematics(&steps, &q, &qd, &qdd);
        // each link's own wrench about its origin
        let mut f = vec![[0.0; 3]; self.bodies.len()];
        let mut n_o = vec![[0.0; 3]; self.bodies.len()];
        for (l, body) in self.bodies.iter().enumerate() {
            let k = &states[l];
            let lever = mat_vec(&k.rotation, body.com);
            let a_com = add3(k.acc, cross(k.wd, lever), cross(k.w, cross(k.w, lever)));
            let inertia = mat_mul(
                &mat_mul(&k.rotation, &body.inertia),
                &transpose(&k.rotation),
            );
            f[l] = scale(body.mass, a_com);
            n_o[l] = add3(
                mat_vec(&inertia, k.wd),
                cross(k.w, mat_vec(&inertia, k.w)),
                cross(lever, f[l]),
            );
        }
        let mut tau = vec![0.0; self.joints.len()];
        for step in steps.iter().rev() {
            let (ft, nt) = (f[step.to], n_o[step.to]);
            let joint = &self.joints[step.joint];
            let (point, u, s) = self.axis(step, &states);
            tau[step.joint] = s * match joint.motion {
                Motion::Revolute => dot(u, add(nt, cross(sub(states[step.to].origin, point), ft))),
                Motion::Prismatic => dot(u, ft),
                Motion::Fixed => 0.0,
            };
            let lever = sub(states[step.to].origin, states[step.from].origin);
            f[step.from] = add(f[step.from], ft);
            n_o[step.from] = add3(n_o[step.from], nt, cross(lever, ft));
        }
        columns.iter().map(|&c| tau[c]).collect()
    }

    /// The pose of `link` in the root frame (rotation and origin as a homogeneous matrix)
    /// with the chain's joints at `q` and every other joint at zero. Panics as
    /// [`torques`](Self::torques), or on an unknown link.
    pub fn link_pose(&self, link: &str, chain: &[&str], q: &[f64]) -> [[f64; 4]; 4] {
        let columns = self.columns(chain);
        assert_eq!(q.len(), chain.len(), "one position per joint");
        let mut all = vec![0.0; self.joints.len()];
        for (&c, &v) in columns.iter().zip(q) {
            all[c] = v;
        }
        let zeros = vec![0.0; self.joints.len()];
        let steps = self.walk(self.root);
        let k = self.kinematics(&steps, &all, &zeros, &zeros)[self.link(link)];
        let (r, p) = (k.rotation, k.origin);
        [
            [r[0][0], r[0][1], r[0][2], p[0]],
            [r[1][0], r[1][1], r[1][2], p[1]],
            [r[2][0], r[2][1], r[2][2], p[2]],
            [0.0, 0.0, 0.0, 1.0],
        ]
    }

    fn link(&self, name: &str) -> usize {
        self.bodies
            .iter()
            .position(|b| b.name == name)
            .unwrap_or_else(|| panic!("no link named {name}"))
    }

    /// The joint index of each name of `chain`.
    fn columns(&self, chain: &[&str]) -> Vec<usize> {
        let mut columns: Vec<usize> = Vec::with_capacity(chain.len());
        for name in chain {
            let c = self
                .joints
                .iter()
                .position(|j| j.name == *name)
                .unwrap_or_else(|| panic!("no joint named {name}"));
            assert!(
                self.joints[c].motion != Motion::Fixed,
                "joint {name} is fixed"
            );
            assert!(!columns.contains(&c), "joint {name} is named twice");
            columns.push(c);
        }
        columns
    }

    /// Every joint crossing, breadth first from `base` (each link reached once).
    fn walk(&self, base: usize) -> Vec<Step> {
        let mut seen = vec![false; self.bodies.len()];
        seen[base] = true;
        let mut steps = Vec::new();
        let mut next = 0;
        let mut frontier = vec![base];
        while next < frontier.len() {
            let from = frontier[next];
            next += 1;
            for (j, joint) in self.joints.iter().enumerate() {
                let (to, forwards) = if joint.parent == from {
                    (joint.child, true)
                } else if joint.child == from {
                    (joint.parent, false)
                } else {
                    continue;
                };
                if !seen[to] {
                    seen[to] = true;
                    frontier.push(to);
                    steps.push(Step {
                        joint: j,
                        from,
                        to,
                        forwards,
                    });
                }
            }
        }
        steps
    }

    /// Joint point, unit axis (both in the base frame) and sign of a crossing, once the poses
    /// of its links are known.
    fn axis(&self, step: &Step, states: &[Kinematics]) -> (V3, V3, f64) {
        let joint = &self.joints[step.joint];
        let child = &states[joint.child];
        let s = if step.forwards { 1.0 } else { -1.0 };
        (child.origin, mat_vec(&child.rotation, joint.axis), s)
    }

    /// Pose, velocity and acceleration of every link in the frame of the link `steps` start
    /// from (the base), for every joint's values.
    fn kinematics(&self, steps: &[Step], q: &[f64], qd: &[f64], qdd: &[f64]) -> Vec<Kinematics> {
        let start = Kinematics {
            rotation: identity(),
            origin: [0.0; 3],
            w: [0.0; 3],
            wd: [0.0; 3],
            acc: scale(-1.0, GRAVITY),
        };
        let mut states = vec![start; self.bodies.len()];
        for step in steps {
            let joint = &self.joints[step.joint];
            let j = step.joint;
            let k = states[step.from];
            // the joint's motion: rotation and translation of the child in the joint frame
            let (turn, slide) = match joint.motion {
                Motion::Fixed => (identity(), [0.0; 3]),
                Motion::Revolute => (axis_angle(joint.axis, q[j]), [0.0; 3]),
                Motion::Prismatic => (identity(), scale(q[j], joint.axis)),
            };
            let (rotation, origin) = if step.forwards {
                // child = parent * origin * motion
                let r = mat_mul(&mat_mul(&k.rotation, &joint.rotation), &turn);
                let p = add(
                    k.origin,
                    mat_vec(
                        &k.rotation,
                        add(joint.translation, mat_vec(&joint.rotation, slide)),
                    ),
                );
                (r, p)
            } else {
                // parent = child * motion^-1 * origin^-1
                let r = mat_mul(
                    &mat_mul(&k.rotation, &transpose(&turn)),
                    &transpose(&joint.rotation),
                );
                let p = sub(
                    sub(k.origin, mat_vec(&k.rotation, slide)),
                    mat_vec(&r, joint.translation),
                );
                (r, p)
            };
            // joint point and axis: the joint's child frame (the new link forwards, the known
            // one backwards), axis fixed in the known link
            let (point, child_rotation) = if step.forwards {
                (origin, rotation)
            } else {
                (k.origin, k.rotation)
            };
            let u = mat_vec(&child_rotation, joint.axis);
            let s = if step.forwards { 1.0 } else { -1.0 };
            let r = sub(origin, k.origin);
            let coincident = add3(k.acc, cross(k.wd, r), cross(k.w, cross(k.w, r)));
            let (w, wd, v_rel, a_rel) = match joint.motion {
                Motion::Fixed => (k.w, k.wd, [0.0; 3], [0.0; 3]),
                Motion::Revolute => {
                    let spin = scale(s * qd[j], u);
                    let arm = sub(origin, point);
                    let v_rel = cross(spin, arm);
                    let a_rel = add(cross(scale(s * qdd[j], u), arm), cross(spin, v_rel));
                    let wd = add3(k.wd, scale(s * qdd[j], u), cross(k.w, spin));
                    (add(k.w, spin), wd, v_rel, a_rel)
                }
                Motion::Prismatic => (k.w, k.wd, scale(s * qd[j], u), scale(s * qdd[j], u)),
            };
            states[step.to] = Kinematics {
                rotation,
                origin,
                w,
                wd,
                acc: add3(coincident, a_rel, scale(2.0, cross(k.w, v_rel))),
            };
        }
        states
    }
}

/// Sine and cosine of an rpy angle, exact at multiples of pi/2 when snapping.
fn sin_cos(angle: f64, snap: bool) -> (f64, f64) {
    if snap {
        let k = (angle / FRAC_PI_2).round();
        if (angle - k * FRAC_PI_2).abs() <= SNAP_TOLERANCE {
            // k is small: the angle is finite and within 1e-9 of k pi/2
            return match (k as i64).rem_euclid(4) {
                0 => (0.0, 1.0),
                1 => (1.0, 0.0),
                2 => (0.0, -1.0),
                _ => (-1.0, 0.0),
            };
        }
    }
    angle.sin_cos()
}

/// The URDF rotation of roll, pitch, yaw: Rz(yaw) Ry(pitch) Rx(roll).
fn rpy(angles: &[f64; 3], snap: bool) -> M3 {
    let (sr, cr) = sin_cos(angles[0], snap);
    let (sp, cp) = sin_cos(angles[1], snap);
    let (sy, cy) = sin_cos(angles[2], snap);
    let x = [[1.0, 0.0, 0.0], [0.0, cr, -sr], [0.0, sr, cr]];
    let y = [[cp, 0.0, sp], [0.0, 1.0, 0.0], [-sp, 0.0, cp]];
    let z = [[cy, -sy, 0.0], [sy, cy, 0.0], [0.0, 0.0, 1.0]];
    mat_mul(&z, &mat_mul(&y, &x))
}

/// Rotation by `angle` about the unit vector `u` (Rodrigues): I + s [u]x + (1 - c) [u]x^2.
fn axis_angle(u: V3, angle: f64) -> M3 {
    let (s, c) = angle.sin_cos();
    let k = [[0.0, -u[2], u[1]], [u[2], 0.0, -u[0]], [-u[1], u[0], 0.0]];
    let k2 = mat_mul(&k, &k);
    let mut r = identity();
    for (i, row) in r.iter_mut().enumerate() {
        for (j, x) in row.iter_mut().enumerate() {
            *x += s * k[i][j] + (1.0 - c) * k2[i][j];
        }
    }
    r
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rnea::column;

    const PENDULUM: &str = r#"<robot name="pendulum">
      <link name="top">
        <inertial><origin xyz="0 0 0.2"/><mass value="4.0"/>
          <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.2" iyz="0" izz="0.3"/></inertial>
      </link>
      <joint name="swing" type="revolute">
        <origin xyz="0 0 -0.5" rpy="0 0 0"/>
        <parent link="top"/><child link="bob"/><axis xyz="0 2 0"/>
        <limit lower="-3" upper="3" effort="10" velocity="1"/>
      </joint>
      <link name="bob">
        <inertial><origin xyz="0 0 -0.7"/><mass value="2.0"/>
          <inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/></inertial>
      </link>
    </robot>"#;

    /// A point mass m at distance l below a joint about y: tau = m l^2 qdd + m g l sin(q)
    /// (a positive angle about y swings the mass towards -x, gravity pulls it back).
    #[test]
    fn pendulum_matches_closed_form() {
        let tree = UrdfTree::from_str(PENDULUM, false).unwrap();
        assert_eq!(tree.joints(), ["swing"]);
        let (m, l, g) = (2.0, 0.7, 9.81);
        for (q, qd, qdd) in [(0.4, -1.3, 2.1), (-2.0, 0.5, -0.7)] {
            let tau = tree.torques(&["swing"], &[q], &[qd], &[qdd])[0];
            let expected = m * l * l * qdd + m * g * l * f64::sin(q);
            assert!((tau - expected).abs() < 1e-12, "{tau} vs {expected}");
        }
    }

    /// With the base at the bob, the top link turns by phi = -q about y through the joint,
    /// its centre of mass l = 0.7 above it (gravity tips it over): the joint must apply to
    /// the top (Iyy + m l^2) phi'' - m g l sin(phi) about y, and the effort of the parent
    /// (top) on the child (bob) is the opposite.
    #[test]
    fn pendulum_upside_down_from_the_bob() {
        let tree = UrdfTree::from_str(PENDULUM, false).unwrap();
        let (m, l, g, iyy) = (4.0, 0.7, 9.81, 0.2);
        let (q, qd, qdd) = (0.3, 0.9, -1.7);
        let tau = tree.torques_from("bob", &["swing"], &[q], &[qd], &[qdd])[0];
        let needed = (iyy + m * l * l) * (-qdd) - m * g * l * f64::sin(-q);
        assert!((tau - (-needed)).abs() < 1e-12, "{tau} vs {}", -needed);
    }

    /// A chain a -(revolute r, origin t1)-> b -(prismatic p, origin t2)-> c, its torques with
    /// the base at c equal those of the same mechanism written with c as its root, each joint
    /// reversed by hand. With pure-translation origins, X_c = X_b Trans(t2) Trans(q2 u2) and
    /// X_b = X_a Trans(t1) R(u1, q1) give X_b = X_c Trans(q2 (-u2)) Trans(-t2) and
    /// X_a = X_b R(-u1, q1) Trans(-t1): in the rewritten file c -(p, origin 0, axis -u2)-> b'
    /// -(r, origin -t2, axis -u1)-> a', with b's centre of mass at its xyz - t2 in b' and a's
    /// at its xyz - t1 in a' (same axes). The effort of b' on a' along -u1 is the
    /// effort of a on b along u1 (two sign changes), so the torques are the same numbers.
    #[test]
    fn base_away_from_the_root_equals_the_reversed_file() {
        let original = r#"<robot name="forward">
          <link name="a"><inertial><origin xyz="0.1 -0.2 0.05" rpy="0.3 0.2 0.1"/>
            <mass value="2.5"/><inertia ixx="0.05" ixy="0.001" ixz="0" iyy="0.04" iyz="0.002"
            izz="0.03"/></inertial></link>
          <joint name="r" type="revolute"><origin xyz="0.3 0.1 -0.2"/>
            <parent link="a"/><child link="b"/><axis xyz="1 2 2"/>
            <limit lower="-3" upper="3" effort="10" velocity="1"/></joint>
          <link name="b"><inertial><origin xyz="0.2 0.05 0.1" rpy="-0.4 0.1 0.9"/>
            <mass value="1.5"/><inertia ixx="0.02" ixy="0" ixz="0.001" iyy="0.03" iyz="0"
            izz="0.025"/></inertial></link>
          <joint name="p" type="prismatic"><origin xyz="-0.1 0.25 0.15"/>
            <parent link="b"/><child link="c"/><axis xyz="0 3 4"/>
            <limit lower="-1" upper="1" effort="10" velocity="1"/></joint>
          <link name="c"><inertial><origin xyz="0 0 0.1"/><mass value="7"/>
            <inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link>
        </robot>"#;
        // a at (0.1, -0.2, 0.05) - t1 in a', b at (0.2, 0.05, 0.1) - t2 in b'
        let reversed = r#"<robot name="reversed">
          <link name="c"/>
          <joint name="p" type="prismatic"><origin xyz="0 0 0"/>
            <parent link="c"/><child link="b"/><axis xyz="0 -3 -4"/>
            <limit lower="-1" upper="1" effort="10" velocity="1"/></joint>
          <link name="b"><inertial><origin xyz="0.3 -0.2 -0.05" rpy="-0.4 0.1 0.9"/>
            <mass value="1.5"/><inertia ixx="0.02" ixy="0" ixz="0.001" iyy="0.03" iyz="0"
            izz="0.025"/></inertial></link>
          <joint name="r" type="revolute"><origin xyz="0.1 -0.25 -0.15"/>
            <parent link="b"/><child link="a"/><axis xyz="-1 -2 -2"/>
            <limit lower="-3" upper="3" effort="10" velocity="1"/></joint>
          <link name="a"><inertial><origin xyz="-0.2 -0.3 0.25" rpy="0.3 0.2 0.1"/>
            <mass value="2.5"/><inertia ixx="0.05" ixy="0.001" ixz="0" iyy="0.04" iyz="0.002"
            izz="0.03"/></inertial></link>
        </robot>"#;
        let (forward, backward) = (
            UrdfTree::from_str(original, false).unwrap(),
            UrdfTree::from_str(reversed, false).unwrap(),
        );
        assert_eq!(forward.root(), "a");
        assert_eq!(backward.root(), "c");
        let chain = ["r", "p"];
        for (q, qd, qdd) in [
            ([0.7, 0.15], [-1.1, 0.4], [2.3, -0.8]),
            ([-2.1, -0.3], [0.6, -0.9], [-1.4, 1.7]),
        ] {
            let a = forward.torques_from("c", &chain, &q, &qd, &qdd);
            let b = backward.torques(&chain, &q, &qd, &qdd);
            for (x, y) in a.iter().zip(&b) {
                assert!((x - y).abs() < 1e-12, "{a:?} vs {b:?}");
            }
            // and the base matters: from the root the same state needs other efforts
            let from_root = forward.torques(&chain, &q, &qd, &qdd);
            assert!((from_root[0] - a[0]).abs() > 1e-3, "{from_root:?} vs {a:?}");
        }
    }

    /// A prismatic joint along a written `0 0 3` axis lifting a mass: f = m (qdd + g).
    #[test]
    fn vertical_slider() {
        let text = r#"<robot name="lift">
          <link name="a"/>
          <joint name="up" type="prismatic">
            <origin xyz="0.1 0.2 0.3" rpy="0 0 0.7"/>
            <parent link="a"/><child link="b"/><axis xyz="0 0 3"/>
            <limit lower="-1" upper="1" effort="10" velocity="1"/>
          </joint>
          <link name="b">
            <inertial><origin xyz="0.3 -0.1 0.2" rpy="0.4 0.5 0.6"/><mass value="3.0"/>
              <inertia ixx="0.1" ixy="0.01" ixz="0" iyy="0.2" iyz="0" izz="0.3"/></inertial>
          </link>
        </robot>"#;
        let tree = UrdfTree::from_str(text, false).unwrap();
        let f = tree.torques(&["up"], &[0.2], &[0.7], &[1.5])[0];
        assert!((f - 3.0 * (1.5 + 9.81)).abs() < 1e-12, "{f}");
        let pose = tree.link_pose("b", &["up"], &[0.2]);
        assert!((pose[2][3] - 0.5).abs() < 1e-15 && (pose[0][3] - 0.1).abs() < 1e-15);
    }

    #[test]
    fn snapping_is_exact_and_limited() {
        // as written in the UR5 and TX40 files: 1.57079632679 and -3.14159265359
        let (half, minus_pi) = (FRAC_PI_2 - 4.9e-12, -std::f64::consts::PI - 2.1e-12);
        assert_eq!(sin_cos(half, true), (1.0, 0.0));
        assert_eq!(sin_cos(minus_pi, true), (0.0, -1.0));
        assert_eq!(sin_cos(-FRAC_PI_2, true), (-1.0, 0.0));
        assert_eq!(sin_cos(0.0, true), (0.0, 1.0));
        assert_eq!(sin_cos(5.0 * FRAC_PI_2, true), (1.0, 0.0));
        let far = FRAC_PI_2 - 2e-9;
        assert_eq!(sin_cos(far, true), far.sin_cos());
        assert_ne!(sin_cos(half, false), (1.0, 0.0));
        let r = rpy(&[FRAC_PI_2, 0.0, 0.0], true);
        assert_eq!(column(&r, 2), [0.0, -1.0, 0.0]);
    }

    #[test]
    fn bad_trees_are_refused() {
        let two_roots = r#"<robot name="x"><link name="a"/><link name="b"/></robot>"#;
        assert!(
            UrdfTree::from_str(two_roots, false)
                .unwrap_err()
                .contains("one root")
        );
        let cycle = r#"<robot name="x"><link name="a"/><link name="b"/><link name="c"/>
          <joint name="j1" type="fixed"><parent link="a"/><child link="b"/></joint>
          <joint name="j2" type="fixed"><parent link="c"/><child link="b"/></joint>
          </robot>"#;
        assert!(
            UrdfTree::from_str(cycle, false)
                .unwrap_err()
                .contains("two joints")
        );
        let floating = r#"<robot name="x"><link name="a"/><link name="b"/>
          <joint name="j" type="floating"><parent link="a"/><child link="b"/></joint>
          </robot>"#;
        assert!(
            UrdfTree::from_str(floating, false)
                .unwrap_err()
                .contains("not supported")
        );
        let no_axis = r#"<robot name="x"><link name="a"/><link name="b"/>
          <joint name="j" type="continuous"><parent link="a"/><child link="b"/>
          <axis xyz="0 0 0"/></joint></robot>"#;
        assert!(
            UrdfTree::from_str(no_axis, false)
                .unwrap_err()
                .contains("no direction")
        );
    }
}
