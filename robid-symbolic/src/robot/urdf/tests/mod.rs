//! Tests of the URDF reader: kinematics against the URDF (random chains and the real
//! files), the real robots, inertials, errors and writing back.

mod errors;
mod inertials;
mod kinematics;
mod limits_gravity;
mod nearly_parallel;
mod pinocchio;
mod printed_angles;
mod robots;
mod tidy;
mod writing;

use super::super::file::Place;
use super::rigid::Rigid;
use super::xml::{self, JointType};
use super::{ChainSelection, UrdfChain};
use crate::expr::Arena;
use crate::robot::{JointKind, Pose, Robot};
use std::collections::HashMap;

/// The text of a file of the repository.
pub(super) fn repository_file(path: &str) -> String {
    let full = format!("{}/../{path}", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(&full).unwrap_or_else(|e| panic!("{full}: {e}"))
}

pub(super) const PANDA: &str = "data/example_robot_data/panda/panda.urdf";
pub(super) const UR5: &str = "data/example_robot_data/ur5/ur5_robot.urdf";
pub(super) const LWR4: &str = "data/kuka_lwr4/description/kuka_lwr4.urdf";
pub(super) const TX40: &str = "data/staubli_tx40/description/tx40_mdh_modified.urdf";
pub(super) const KINOVA: &str = "data/example_robot_data/kinova/kinova.urdf";
pub(super) const XARM7: &str = "data/example_robot_data/xarm7/xarm7.urdf";
pub(super) const SO101: &str = "data/example_robot_data/so101/so101.urdf";

/// The one warning of `chain` that contains `what` (fails unless there is exactly one).
pub(super) fn one_warning<'a>(chain: &'a UrdfChain, what: &str) -> &'a str {
    let told: Vec<&String> = chain.warnings.iter().filter(|w| w.contains(what)).collect();
    assert_eq!(told.len(), 1, "{:?}", chain.warnings);
    told[0]
}

pub(super) fn selection(base: Option<&str>, tip: Option<&str>) -> ChainSelection {
    ChainSelection {
        base: base.map(str::to_owned),
        tip: tip.map(str::to_owned),
    }
}

/// One joint of a URDF for the direct computation: parent, child, origin, axis, type.
pub(super) struct DirectJoint {
    pub(super) name: String,
    pub(super) parent: String,
    pub(super) child: String,
    pub(super) origin: Rigid,
    pub(super) axis: [f64; 3],
    pub(super) prismatic: bool,
    pub(super) moves: bool,
}

/// The joints of a URDF text as read by the XML reader.
pub(super) fn direct_joints(text: &str) -> Vec<DirectJoint> {
    let urdf = xml::read(&Place { file: "t", text }).unwrap();
    urdf.joints
        .iter()
        .map(|j| DirectJoint {
            name: j.name.clone(),
            parent: j.parent.clone(),
            child: j.child.clone(),
            origin: j.origin,
            axis: j.axis,
            prismatic: j.kind == JointType::Prismatic,
            moves: j.kind.movable(),
        })
        .collect()
}

/// Every link's pose in `root`'s frame, the joints named in `q` at those values, the
/// others at zero: parent pose * origin * (rotation about the axis by q, or translation
/// along it).
pub(super) fn direct_poses(
    joints: &[DirectJoint],
    root: &str,
    q: &HashMap<String, f64>,
) -> HashMap<String, Rigid> {
    let mut poses = HashMap::new();
    poses.insert(root.to_owned(), Rigid::IDENTITY);
    let mut changed = true;
    while changed {
        changed = false;
        for j in joints {
            if poses.contains_key(&j.child) {
                continue;
            }
            let Some(parent) = poses.get(&j.parent).copied() else {
                continue;
            };
            let value = if j.moves {
                q.get(&j.name).copied().unwrap_or(0.0)
            } else {
                0.0
            };
            let motion = if j.prismatic {
                Rigid::translation(j.axis.map(|x| x * value))
            } else {
                Rigid::rotation(j.axis, value)
            };
            poses.insert(j.child.clone(), parent.then(&j.origin).then(&motion));
            changed = true;
        }
    }
    poses
}

/// `[alpha, a, d, theta]` of each joint of a robot.
pub(super) fn rows(robot: &Robot) -> Vec<[f64; 4]> {
    general_rows(robot)
        .into_iter()
        .map(|[alpha, a, d, theta, _]| [alpha, a, d, theta])
        .collect()
}

/// `[alpha, a, d, theta, b]` of each joint of a robot (its `gamma` is 0: the reader does
/// not write one).
pub(super) fn general_rows(robot: &Robot) -> Vec<[f64; 5]> {
    let mut arena = Arena::new();
    let mut ids = Vec::new();
    for joint in robot.joints() {
        assert_eq!(joint.gamma.as_str(), "0");
        for g in [&joint.alpha, &joint.a, &joint.d, &joint.theta, &joint.b] {
            ids.push(g.to_expr(&mut arena));
        }
    }
    let values = arena.values(&[]);
    let v = arena.eval(&ids, &values).unwrap();
    v.chunks(5)
        .map(|c| [c[0], c[1], c[2], c[3], c[4]])
        .collect()
}

fn rot_x(angle: f64) -> Rigid {
    Rigid::rotation([1.0, 0.0, 0.0], angle)
}

fn rot_z(angle: f64) -> Rigid {
    Rigid::rotation([0.0, 0.0, 1.0], angle)
}

/// robid frames 1..n in the base link frame at `q`: `base` Tz(b) Rx(alpha) Tx(a)
/// Rz(theta + q) Tz(d) ... (d + q for a prismatic joint).
pub(super) fn dh_frames(chain: &UrdfChain, q: &[f64]) -> Vec<Rigid> {
    let mut at = Rigid::from_pose(&chain.base);
    let mut out = Vec::new();
    for ((row, joint), &qj) in general_rows(&chain.robot)
        .iter()
        .zip(chain.robot.joints())
        .zip(q)
    {
        let [alpha, a, d, theta, b] = *row;
        let (theta, d) = match joint.kind {
            JointKind::Revolute => (theta + qj, d),
            JointKind::Prismatic => (theta, d + qj),
        };
        at = at
            .then(&Rigid::translation([0.0, 0.0, b]))
            .then(&rot_x(alpha))
            .then(&Rigid::translation([a, 0.0, 0.0]))
            .then(&rot_z(theta))
            .then(&Rigid::translation([0.0, 0.0, d]));
        out.push(at);
    }
    out
}

/// The largest difference between two poses' entries.
pub(super) fn difference(a: &Pose, b: &Pose) -> f64 {
    let mut worst = 0.0_f64;
    for i in 0..4 {
        for k in 0..4 {
            worst = worst.max((a[i][k] - b[i][k]).abs());
        }
    }
    worst
}

/// Checks every URDF link of the chain at `q` (by robid joint) against the direct
/// computation, to `tolerance`; returns the largest difference.
pub(super) fn check_kinematics(
    text: &str,
    chain: &UrdfChain,
    base: &str,
    tip: &str,
    q: &[f64],
    tolerance: f64,
) -> f64 {
    let joints = direct_joints(text);
    let values: HashMap<String, f64> = chain
        .links
        .iter()
        .zip(q)
        .map(|(l, &v)| (l.joint.clone(), v))
        .collect();
    let poses = direct_poses(&joints, base, &values);
    let frames = dh_frames(chain, q);
    let mut worst = 0.0_f64;
    for (link, frame) in chain.links.iter().zip(&frames) {
        let at = frame.then(&Rigid::from_pose(&link.frame));
        worst = worst.max(difference(&at.pose(), &poses[&link.link].pose()));
        for attached in &link.attached {
            let there = at.then(&Rigid::from_pose(&attached.frame));
            worst = worst.max(difference(&there.pose(), &poses[&attached.name].pose()));
        }
    }
    let tip_pose = frames[frames.len() - 1].then(&Rigid::from_pose(&chain.tool));
    worst = worst.max(difference(&tip_pose.pose(), &poses[tip].pose()));
    assert!(worst <= tolerance, "poses differ by {worst:e} at q = {q:?}");
    worst
}

/// robid's torques of `chain` with the URDF's own inertials, from its symbolic inverse
/// dynamics evaluated at a state (`q`, `qd`, `qdd`; joints in chain order): what the
/// cross-checks against independent torques compare.
pub(super) fn own_inertials_torques(
    chain: &UrdfChain,
) -> impl FnMut(&[f64], &[f64], &[f64]) -> Vec<f64> {
    let mut d = crate::Derivation::new(&chain.robot);
    let symbols = d.parameter_symbols();
    let tau = d.inverse_dynamics(&symbols);
    let names: Vec<String> = d
        .standard_parameters()
        .iter()
        .map(ToString::to_string)
        .collect();
    let parameters: Vec<f64> = chain.links.iter().flat_map(|l| l.inertial).collect();
    move |q, qd, qdd| {
        let mut pairs: Vec<(String, f64)> = names
            .iter()
            .cloned()
            .zip(parameters.iter().copied())
            .collect();
        for (p, values) in [("q", q), ("qd", qd), ("qdd", qdd)] {
            for (j, &v) in values.iter().enumerate() {
                pairs.push((format!("{p}{}", j + 1), v));
            }
        }
        let refs: Vec<(&str, f64)> = pairs.iter().map(|(a, b)| (a.as_str(), *b)).collect();
        let values = d.arena.values(&refs);
        d.arena.eval(&tau, &values).unwrap()
    }
}
