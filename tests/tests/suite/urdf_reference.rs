//! The URDF inverse-dynamics reference `tests::urdf_rnea` against Pinocchio's `rnea`
//! (tests/reference/urdf/: the script, its CSV output and the README with the version),
//! against a second computation of its link poses, against itself with pi/2 snapping, and
//! against the DH reference `tests::rnea` on the Staubli TX40, whose URDF link frames are
//! the modified-DH frames of robots/descriptions/tx40.toml.

use nalgebra::{Isometry3, Rotation3, Translation3, Unit, UnitQuaternion, Vector3};
use std::collections::HashMap;
use std::f64::consts::FRAC_PI_2;
use tests::reference::by_name;
use tests::rnea::{Chain, Link, express_in_parent};
use tests::urdf_rnea::{Motion, UrdfTree};

/// Name, URDF text and Pinocchio's torques of each robot.
const ROBOTS: [(&str, &str, &str); 8] = [
    (
        "panda",
        include_str!("../../../data/example_robot_data/panda/panda.urdf"),
        include_str!("../../reference/urdf/panda.csv"),
    ),
    (
        "ur5",
        include_str!("../../../data/example_robot_data/ur5/ur5_robot.urdf"),
        include_str!("../../reference/urdf/ur5.csv"),
    ),
    (
        "kuka_lwr4",
        include_str!("../../../data/kuka_lwr4/description/kuka_lwr4.urdf"),
        include_str!("../../reference/urdf/kuka_lwr4.csv"),
    ),
    (
        "tx40",
        include_str!("../../../data/staubli_tx40/description/tx40_mdh_modified.urdf"),
        include_str!("../../reference/urdf/tx40.csv"),
    ),
    (
        "skewed_arm",
        include_str!("../../reference/urdf/skewed_arm.urdf"),
        include_str!("../../reference/urdf/skewed_arm.csv"),
    ),
    (
        "kinova",
        include_str!("../../../data/example_robot_data/kinova/kinova.urdf"),
        include_str!("../../reference/urdf/kinova.csv"),
    ),
    (
        "xarm7",
        include_str!("../../../data/example_robot_data/xarm7/xarm7.urdf"),
        include_str!("../../reference/urdf/xarm7.csv"),
    ),
    (
        "so101",
        include_str!("../../../data/example_robot_data/so101/so101.urdf"),
        include_str!("../../reference/urdf/so101.csv"),
    ),
];

/// One state of a Pinocchio CSV.
struct State {
    q: Vec<f64>,
    qd: Vec<f64>,
    qdd: Vec<f64>,
    tau: Vec<f64>,
}

/// The joint names (Pinocchio's order) and the states of a CSV whose columns are
/// `q:<joint>`, `qd:<joint>`, `qdd:<joint>`, `tau:<joint>`, one block per kind.
fn read_csv(text: &str) -> (Vec<String>, Vec<State>) {
    let mut lines = text.lines();
    let header: Vec<(&str, &str)> = lines
        .next()
        .expect("header")
        .split(',')
        .map(|c| c.split_once(':').expect("kind:joint"))
        .collect();
    let n = header.len() / 4;
    assert_eq!(header.len(), 4 * n);
    let names: Vec<String> = header[..n].iter().map(|(_, j)| j.to_string()).collect();
    for (b, kind) in ["q", "qd", "qdd", "tau"].into_iter().enumerate() {
        for (c, name) in names.iter().enumerate() {
            assert_eq!(
                header[b * n + c],
                (kind, name.as_str()),
                "column {}",
                b * n + c
            );
        }
    }
    let states = lines
        .map(|line| {
            let x: Vec<f64> = line.split(',').map(|v| v.parse().unwrap()).collect();
            assert_eq!(x.len(), 4 * n);
            State {
                q: x[..n].to_vec(),
                qd: x[n..2 * n].to_vec(),
                qdd: x[2 * n..3 * n].to_vec(),
                tau: x[3 * n..].to_vec(),
            }
        })
        .collect();
    (names, states)
}

/// The LWR4 joint `box_lwr_base_joint` has two `<origin>` elements, `xyz="-0.25 0 1"` then
/// `xyz="0 0 0"`.
const LWR4_ORIGINS: &str = "<origin rpy=\"0 0 0\" xyz=\"-0.25 0 1\"/>\n    \
                            <origin rpy=\"0 0 0\" xyz=\"0 0 0\"/>";

/// The URDF as Pinocchio reads it. urdfdom (Pinocchio's URDF parser) takes the first
/// `<origin>` of a joint and ignores the others (its model puts `lwr_base_link` at
/// (-0.25, 0, 1), see tests/reference/urdf/README.md); `urdf-rs` refuses the file
/// (`lwr4_second_origin_is_refused_by_urdf_rs`), so the LWR4's second origin is removed.
fn as_pinocchio_reads(robot: &str, urdf: &str) -> String {
    if robot != "kuka_lwr4" {
        return urdf.to_string();
    }
    assert_eq!(urdf.matches(LWR4_ORIGINS).count(), 1);
    urdf.replace(LWR4_ORIGINS, "<origin rpy=\"0 0 0\" xyz=\"-0.25 0 1\"/>")
}

fn tree(robot: &str, urdf: &str, snap: bool) -> UrdfTree {
    UrdfTree::from_str(&as_pinocchio_reads(robot, urdf), snap).unwrap()
}

/// `urdf-rs` 0.10 refuses a joint with two `<origin>` elements (serde's duplicate field).
#[test]
fn lwr4_second_origin_is_refused_by_urdf_rs() {
    let (_, urdf, _) = ROBOTS[2];
    let error = UrdfTree::from_str(urdf, false).unwrap_err();
    assert!(error.contains("duplicate field `origin`"), "{error}");
}

/// The largest torque magnitude of a state, the scale of its comparison (torques that
/// nearly cancel are compared with the state's size, not their own).
fn size(tau: &[f64]) -> f64 {
    tau.iter().fold(1.0f64, |m, t| m.max(t.abs()))
}

/// Pinocchio works in local frames with spatial algebra (and turns rpy into a quaternion and
/// back), the reference in the base frame with 3-vectors: the same sums in another order.
/// Measured maximum of |tau_ref - tau_pin| / max(1, max |tau|) over the 100 states: 2.6e-15
/// (all five robots); 1e-12 leaves a margin of almost 400.
const PINOCCHIO: f64 = 1e-12;

#[test]
fn torques_equal_pinocchio() {
    let mut worst: f64 = 0.0;
    for (robot, urdf, csv) in ROBOTS {
        let t = tree(robot, urdf, false);
        let (names, states) = read_csv(csv);
        // Pinocchio's model holds every movable joint of the file
        let mut ours = t.joints();
        let mut theirs = names.clone();
        ours.sort();
        theirs.sort();
        assert_eq!(ours, theirs, "{robot}");
        let chain: Vec<&str> = names.iter().map(String::as_str).collect();
        assert_eq!(states.len(), 20);
        for (s, state) in states.iter().enumerate() {
            let tau = t.torques(&chain, &state.q, &state.qd, &state.qdd);
            let scale = size(&state.tau);
            for (j, (a, b)) in tau.iter().zip(&state.tau).enumerate() {
                let e = (a - b).abs() / scale;
                worst = worst.max(e);
                assert!(
                    e <= PINOCCHIO,
                    "{robot} state {s} {}: {a} vs Pinocchio {b}",
                    chain[j]
                );
            }
        }
    }
    eprintln!("largest relative difference to Pinocchio: {worst:e}");
}

/// The pose of every link by chaining the `urdf_rs` joint origins by hand with nalgebra
/// (roll-pitch-yaw and axis-angle rotations), the second computation of the poses.
fn chained_poses(urdf: &str, chain: &[&str], q: &[f64]) -> HashMap<String, Isometry3<f64>> {
    let robot = urdf_rs::read_from_string(urdf).unwrap();
    let value: HashMap<&str, f64> = chain.iter().copied().zip(q.iter().copied()).collect();
    let mut poses: HashMap<String, Isometry3<f64>> = HashMap::new();
    let children: Vec<&str> = robot.joints.iter().map(|j| j.child.link.as_str()).collect();
    let root = robot
        .links
        .iter()
        .find(|l| !children.contains(&l.name.as_str()))
        .unwrap();
    poses.insert(root.name.clone(), Isometry3::identity());
    while poses.len() < robot.links.len() {
        for joint in &robot.joints {
            let Some(&parent) = poses.get(&joint.parent.link) else {
                continue;
            };
            if poses.contains_key(&joint.child.link) {
                continue;
            }
            let [x, y, z] = *joint.origin.xyz;
            let [r, p, w] = *joint.origin.rpy;
            let origin = Isometry3::from_parts(
                Translation3::new(x, y, z),
                UnitQuaternion::from_rotation_matrix(&Rotation3::from_euler_angles(r, p, w)),
            );
            let axis = Unit::new_normalize(Vector3::from(*joint.axis.xyz));
            let v = value.get(joint.name.as_str()).copied().unwrap_or(0.0);
            let motion = match joint.joint_type {
                urdf_rs::JointType::Revolute | urdf_rs::JointType::Continuous => {
                    Isometry3::from_parts(
                        Translation3::identity(),
                        UnitQuaternion::from_axis_angle(&axis, v),
                    )
                }
                urdf_rs::JointType::Prismatic => {
                    Isometry3::translation(v * axis.x, v * axis.y, v * axis.z)
                }
                _ => Isometry3::identity(),
            };
            poses.insert(joint.child.link.clone(), parent * origin * motion);
        }
    }
    poses
}

/// The reference's link poses equal the hand-chained ones for the first five states of each
/// CSV, for every link: 1e-13 on rotation entries and metres (both round each product once
/// per joint, through a quaternion on one side; measured maximum 1.3e-15).
#[test]
fn link_poses_equal_hand_chained_urdf_rs_poses() {
    let mut worst: f64 = 0.0;
    for (robot, urdf, csv) in ROBOTS {
        let t = tree(robot, urdf, false);
        let (names, states) = read_csv(csv);
        let chain: Vec<&str> = names.iter().map(String::as_str).collect();
        for state in states.iter().take(5) {
            let poses = chained_poses(&as_pinocchio_reads(robot, urdf), &chain, &state.q);
            for (link, pose) in &poses {
                let ours = t.link_pose(link, &chain, &state.q);
                let m = pose.to_homogeneous();
                for (r, row) in ours.iter().enumerate() {
                    for (c, x) in row.iter().enumerate() {
                        let e = (x - m[(r, c)]).abs();
                        worst = worst.max(e);
                        assert!(
                            e <= 1e-13,
                            "{robot} {link} [{r}][{c}]: {x} vs {}",
                            m[(r, c)]
                        );
                    }
                }
            }
        }
    }
    eprintln!("largest pose difference: {worst:e}");
}

/// Snapping changes only what it snaps: files without rpy angles within 1e-9 of k pi/2
/// other than exact zeros (the LWR4, the skewed arm; the xArm7 writes its right angles
/// `1.5708`, 3.7e-6 rad away, which this rule leaves alone) give bit-identical torques; the
/// Panda and the SO-101 write pi/2 as the double nearest to it, whose cosine is 6.1e-17
/// instead of 0, a change at the rounding level (measured 3.2e-16 and 2.2e-16 of the
/// state's size); the UR5, TX40 and Kinova write 1.57079632679 and 3.14159265359, 4.9e-12
/// and 2.1e-12 rad from pi/2 and pi, a change of that order (measured 1.8e-11, 7.5e-12 and
/// 7.0e-12 of the state's size): non-zero and below 1e-10.
#[test]
fn snapping_changes_only_the_snapped_angles() {
    for (robot, urdf, csv) in ROBOTS {
        let (exact, snapped) = (tree(robot, urdf, false), tree(robot, urdf, true));
        let (names, states) = read_csv(csv);
        let chain: Vec<&str> = names.iter().map(String::as_str).collect();
        let mut worst: f64 = 0.0;
        for state in &states {
            let a = exact.torques(&chain, &state.q, &state.qd, &state.qdd);
            let b = snapped.torques(&chain, &state.q, &state.qd, &state.qdd);
            let scale = size(&a);
            for (x, y) in a.iter().zip(&b) {
                worst = worst.max((x - y).abs() / scale);
            }
        }
        eprintln!("{robot}: largest snapping change {worst:e}");
        match robot {
            "kuka_lwr4" | "skewed_arm" | "xarm7" => assert_eq!(worst, 0.0, "{robot}"),
            "panda" | "so101" => assert!(worst <= 1e-14, "{robot}: {worst:e}"),
            "ur5" | "tx40" | "kinova" => {
                assert!(worst > 1e-13 && worst <= 1e-10, "{robot}: {worst:e}")
            }
            other => panic!("no expectation for {other}"),
        }
    }
}

/// The TX40 URDF (FIGAROH's `tx40_mdh_modified.urdf`) and robots/descriptions/tx40.toml
/// (modified DH, theta_j = q_j + theta offset_j).
const TX40: usize = 3;

/// What the comparison of the joint origins found: link_j of the URDF is DH frame j of
/// tx40.toml moved up by the URDF's joint_1 height, 0.320 m (DH frame 0 is at the shoulder,
/// the URDF's base_link at the floor), and the URDF's joint angles are the DH angles theta:
/// joint_6's origin holds the theta offset pi (rpy = (pi/2, pi, 0), that is Rx(pi/2) Rz(pi)),
/// those of joints 2 and 3 (-pi/2 and pi/2) are not in the URDF, so
/// q_urdf = q_dh + (0, -pi/2, pi/2, 0, 0, 0).
const TX40_BASE_HEIGHT: f64 = 0.320;
const TX40_URDF_MINUS_DH: [f64; 6] = [0.0, -FRAC_PI_2, FRAC_PI_2, 0.0, 0.0, 0.0];

fn tx40_dh_q(q_urdf: &[f64]) -> Vec<f64> {
    q_urdf
        .iter()
        .zip(TX40_URDF_MINUS_DH)
        .map(|(q, o)| q - o)
        .collect()
}

/// Every link frame of the URDF (read with snapping, so that its pi/2 angles are those of the
/// description) is the DH frame moved up by 0.320 m, at the 20 states of the CSV: 1e-12
/// (measured 3.6e-16, rounding; without snapping the written 1.57079632679 moves them by
/// up to 1.6e-11, bound 1e-10).
#[test]
fn tx40_urdf_frames_are_the_dh_frames() {
    let (_, urdf, csv) = ROBOTS[TX40];
    let chain = Chain::from_robot(&by_name("tx40").robot());
    let (names, states) = read_csv(csv);
    let joints: Vec<&str> = names.iter().map(String::as_str).collect();
    assert_eq!(
        joints,
        [
            "joint_1", "joint_2", "joint_3", "joint_4", "joint_5", "joint_6"
        ]
    );
    for snap in [true, false] {
        let t = tree("tx40", urdf, snap);
        let mut worst: f64 = 0.0;
        for state in &states {
            let dh = chain.poses(&tx40_dh_q(&state.q));
            for (j, pose) in dh.iter().enumerate() {
                let ours = t.link_pose(&format!("link_{}", j + 1), &joints, &state.q);
                let mut origin = pose.position;
                origin[2] += TX40_BASE_HEIGHT;
                for ((row, rotation), o) in ours.iter().zip(&pose.rotation).zip(origin) {
                    for (x, y) in row.iter().zip(rotation) {
                        worst = worst.max((x - y).abs());
                    }
                    worst = worst.max((row[3] - o).abs());
                }
            }
        }
        eprintln!("tx40 frames, snap {snap}: largest difference {worst:e}");
        let bound = if snap { 1e-12 } else { 1e-10 };
        assert!(worst <= bound, "snap {snap}: {worst:e}");
    }
}

/// The standard rotation of a URDF rpy, with angles within 1e-9 of k pi/2 replaced by the
/// double nearest to k pi/2 (as the description's `pi/2`).
fn snapped_rpy(rpy: [f64; 3]) -> Rotation3<f64> {
    let snap = |x: f64| {
        let k = (x / FRAC_PI_2).round();
        if (x - k * FRAC_PI_2).abs() <= 1e-9 {
            k * FRAC_PI_2
        } else {
            x
        }
    };
    Rotation3::from_euler_angles(snap(rpy[0]), snap(rpy[1]), snap(rpy[2]))
}

/// The URDF reference equals the DH reference `tests::rnea` on the TX40, both with the
/// URDF's inertials (moved to the link frame origins by `rnea::express_in_parent`, the
/// parallel-axis theorem): measured 1.5e-15 of the state's size, bound 1e-12 as Pinocchio's.
#[test]
fn tx40_torques_equal_the_dh_reference() {
    let (_, urdf, csv) = ROBOTS[TX40];
    let chain = Chain::from_robot(&by_name("tx40").robot());
    let t = tree("tx40", urdf, true);
    let robot = urdf_rs::read_from_string(urdf).unwrap();
    let links: Vec<Link> = (1..=6)
        .map(|j| {
            let link = robot
                .links
                .iter()
                .find(|l| l.name == format!("link_{j}"))
                .unwrap();
            let inertial = &link.inertial;
            let i = &inertial.inertia;
            let about_com = Link {
                mass: inertial.mass.value,
                inertia: [
                    [i.ixx, i.ixy, i.ixz],
                    [i.ixy, i.iyy, i.iyz],
                    [i.ixz, i.iyz, i.izz],
                ],
                ..Link::default()
            };
            let r = snapped_rpy(*inertial.origin.rpy);
            let rotation = [0, 1, 2].map(|a| [0, 1, 2].map(|b| r[(a, b)]));
            express_in_parent(&about_com, &rotation, *inertial.origin.xyz)
        })
        .collect();
    let (names, states) = read_csv(csv);
    let joints: Vec<&str> = names.iter().map(String::as_str).collect();
    let mut worst: f64 = 0.0;
    for state in &states {
        let ours = t.torques(&joints, &state.q, &state.qd, &state.qdd);
        let dh = chain.inverse_dynamics(&links, &tx40_dh_q(&state.q), &state.qd, &state.qdd);
        let scale = size(&dh);
        for (a, b) in ours.iter().zip(&dh) {
            worst = worst.max((a - b).abs() / scale);
        }
    }
    eprintln!("tx40 against the DH reference: {worst:e}");
    assert!(worst <= PINOCCHIO, "{worst:e}");
    // every joint is revolute, as in the description
    assert!(joints.iter().all(|j| t.motion(j) == Some(Motion::Revolute)));
}
