//! robid's models of URDF robots (`Robot::from_urdf`: the chain, robid's modified-DH frames
//! fitted to the joint axes, the URDF's inertials moved into them; docs/urdf.md) against
//! computations that share none of that code:
//! - the independent RNEA on the URDF's own frames (`tests::urdf_rnea`, which equals
//!   Pinocchio's `rnea` to 2.6e-15, `urdf_reference.rs`), for every program: inverse
//!   dynamics, gravity, Coriolis and each column of the mass matrix;
//! - robid's model of the hand-written DH description of the same robot (Panda, LWR4,
//!   TX40), with the URDF's inertials moved into the description's frames through link
//!   poses that are checked first;
//! - the base-parameter counts of the literature, and the numeric rank of the standard
//!   regressor for a URDF that no DH table describes directly;
//! - a round trip: inertials written into the URDF (`write_inertials`) and read back give
//!   the torques of the values written;
//! - `robot_model!` on a URDF: the generated code against the interpreter.

use std::f64::consts::FRAC_PI_2;

use nalgebra::DMatrix;
use robid_runtime::Model;
use robid_runtime::rng::Rng;
use robid_symbolic::Robot;
use robid_symbolic::robot::{ChainSelection, UrdfChain, write_inertials};
use robots::interpreted::Interpreted;
use tests::reference::by_name;
use tests::rnea::standard_from_links;
use tests::urdf_rnea::UrdfTree;

/// A URDF of the repository, the chain chosen and the base-parameter count expected
/// (rigid body only; `None`: the numeric rank of the standard regressor decides).
struct Case {
    name: &'static str,
    text: &'static str,
    tip: Option<&'static str>,
    base_parameters: Option<usize>,
}

const CASES: [Case; 6] = [
    Case {
        name: "panda",
        text: include_str!("../../../data/example_robot_data/panda/panda.urdf"),
        tip: Some("panda_hand"),
        base_parameters: Some(43),
    },
    Case {
        name: "ur5",
        text: include_str!("../../../data/example_robot_data/ur5/ur5_robot.urdf"),
        tip: None,
        base_parameters: Some(36),
    },
    Case {
        name: "kuka_lwr4",
        text: include_str!("../../../data/kuka_lwr4/description/kuka_lwr4.urdf"),
        tip: None,
        base_parameters: Some(43),
    },
    Case {
        name: "tx40",
        text: include_str!("../../../data/staubli_tx40/description/tx40_mdh_modified.urdf"),
        tip: None,
        base_parameters: Some(36),
    },
    Case {
        name: "skewed_arm",
        text: include_str!("../../reference/urdf/skewed_arm.urdf"),
        tip: Some("payload"),
        base_parameters: None,
    },
    Case {
        name: "kinova",
        text: include_str!("../../../data/example_robot_data/kinova/kinova.urdf"),
        tip: None,
        base_parameters: None,
    },
];

/// robid's chain of a case.
fn chain(case: &Case) -> UrdfChain {
    let selection = ChainSelection {
        base: None,
        tip: case.tip.map(str::to_owned),
    };
    Robot::from_urdf(case.text, case.name, &selection)
        .unwrap_or_else(|e| panic!("{}: {e}", case.name))
}

/// The URDF as urdf-rs reads it: the LWR4's joint `box_lwr_base_joint` has a second
/// `<origin>` that urdf-rs refuses; robid, like urdfdom, takes the first (the second is a
/// translation by zero, so nothing below depends on it).
fn reference(case: &Case) -> UrdfTree {
    let second = "\n    <origin rpy=\"0 0 0\" xyz=\"0 0 0\"/>\n    <parent link=\"box\"/>";
    let text = case
        .text
        .replacen(second, "\n    <parent link=\"box\"/>", 1);
    UrdfTree::from_str(&text, true).unwrap_or_else(|e| panic!("{}: {e}", case.name))
}

/// The chain's inertials as the standard parameters of its robot (drive terms 0).
fn standard(chain: &UrdfChain) -> Vec<f64> {
    use robid_symbolic::robot::{Inertial, ParameterKind};
    chain
        .robot
        .standard_parameters()
        .iter()
        .map(|p| match p.kind {
            ParameterKind::Inertial(i) => {
                chain.links[p.link].inertial[Inertial::ALL.iter().position(|&k| k == i).unwrap()]
            }
            ParameterKind::Drive(_) => 0.0,
        })
        .collect()
}

/// A random state: angles in +-pi, prismatic positions in +-0.05 m.
fn state(robot: &Robot, rng: &mut Rng) -> [Vec<f64>; 3] {
    let n = robot.dof();
    let q = robot
        .joints()
        .iter()
        .map(|j| match j.kind {
            robid_symbolic::JointKind::Revolute => rng.uniform(-3.1, 3.1),
            robid_symbolic::JointKind::Prismatic => rng.uniform(-0.05, 0.05),
        })
        .collect();
    let qd = (0..n).map(|_| rng.uniform(-2.0, 2.0)).collect();
    let qdd = (0..n).map(|_| rng.uniform(-4.0, 4.0)).collect();
    [q, qd, qdd]
}

/// The largest difference relative to the largest entry of `b` (at least 1 N m).
fn relative(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    let scale = b.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs() / scale)
        .fold(0.0, f64::max)
}

/// Both sides round differently (robid's frames are fitted from the URDF's in f64, the
/// reference works in the URDF's own): 1e-12 of the state's largest torque leaves three
/// orders of magnitude over the measured worst (printed).
const TOLERANCE: f64 = 1e-12;

/// Every program of robid's model of each URDF equals the reference on the URDF's own
/// frames: inverse dynamics, gravity = RNEA(q, 0, 0), Coriolis = RNEA(q, qd, 0) -
/// RNEA(q, 0, 0), mass matrix column k = RNEA(q, 0, e_k) - RNEA(q, 0, 0), at 20 random
/// states each.
#[test]
fn urdf_models_equal_the_rnea_on_the_urdf_frames() {
    let mut rng = Rng::from_state(0x00ad_f001);
    for case in &CASES {
        let chain = chain(case);
        let tree = reference(case);
        let joints: Vec<&str> = chain.links.iter().map(|l| l.joint.as_str()).collect();
        let model = Interpreted::new(&chain.robot).unwrap();
        let n = model.dof();
        let mut base = vec![0.0; model.base_parameter_count()];
        model
            .base_from_standard_into(&standard(&chain), &mut base)
            .unwrap();
        let mut worst: f64 = 0.0;
        for _ in 0..20 {
            let [q, qd, qdd] = state(&chain.robot, &mut rng);
            let zero = vec![0.0; n];
            let rnea = |qd: &[f64], qdd: &[f64]| tree.torques(&joints, &q, qd, qdd);
            let at_rest = rnea(&zero, &zero);
            let mut tau = vec![0.0; n];
            model
                .inverse_dynamics_into(&q, &qd, &qdd, &base, &mut tau)
                .unwrap();
            worst = worst.max(relative(&tau, &rnea(&qd, &qdd)));
            model.gravity_into(&q, &base, &mut tau).unwrap();
            worst = worst.max(relative(&tau, &at_rest));
            model.coriolis_into(&q, &qd, &base, &mut tau).unwrap();
            let moving: Vec<f64> = rnea(&qd, &zero)
                .iter()
                .zip(&at_rest)
                .map(|(a, b)| a - b)
                .collect();
            worst = worst.max(relative(&tau, &moving));
            let mut m = vec![0.0; n * n];
            model.mass_matrix_into(&q, &base, &mut m).unwrap();
            for k in 0..n {
                let mut e = zero.clone();
                e[k] = 1.0;
                let column: Vec<f64> = rnea(&zero, &e)
                    .iter()
                    .zip(&at_rest)
                    .map(|(a, b)| a - b)
                    .collect();
                let ours: Vec<f64> = (0..n).map(|i| m[i * n + k]).collect();
                worst = worst.max(relative(&ours, &column));
            }
        }
        eprintln!("{}: largest difference {worst:e}", case.name);
        assert!(worst <= TOLERANCE, "{}: {worst:e}", case.name);
    }
}

/// The base-parameter counts of the literature (Panda 43, UR 36, LWR4 43, TX40 36 with no
/// drive terms) and, for the skewed arm and the Jaco 2, the numeric rank of the standard regressor
/// stacked over 30 random states (singular values below 1e-9 of the largest are zero).
#[test]
fn urdf_base_parameter_counts_are_the_known_answers() {
    let mut rng = Rng::from_state(0x00ad_f002);
    for case in &CASES {
        let chain = chain(case);
        let model = Interpreted::new(&chain.robot).unwrap();
        let count = model.base_parameter_count();
        let expected = case.base_parameters.unwrap_or_else(|| {
            let (n, s) = (model.dof(), model.standard_parameter_count());
            let rows: Vec<f64> = (0..30)
                .flat_map(|_| {
                    let [q, qd, qdd] = state(&chain.robot, &mut rng);
                    let mut y = vec![0.0; n * s];
                    model
                        .standard_regressor_into(&q, &qd, &qdd, &mut y)
                        .unwrap();
                    y
                })
                .collect();
            let w = DMatrix::from_row_slice(30 * n, s, &rows);
            let sv = w.singular_values();
            let largest = sv.max();
            sv.iter().filter(|&&x| x > 1e-9 * largest).count()
        });
        assert_eq!(count, expected, "{}", case.name);
    }
}

/// A 4x4 rigid transform from a rotation and a translation.
fn transform(rotation: &[[f64; 3]; 3], position: [f64; 3]) -> [[f64; 4]; 4] {
    let mut t = [[0.0; 4]; 4];
    for r in 0..3 {
        t[r][..3].copy_from_slice(&rotation[r]);
        t[r][3] = position[r];
    }
    t[3][3] = 1.0;
    t
}

/// The product of two 4x4 transforms.
fn product(a: &[[f64; 4]; 4], b: &[[f64; 4]; 4]) -> [[f64; 4]; 4] {
    std::array::from_fn(|i| std::array::from_fn(|k| (0..4).map(|m| a[i][m] * b[m][k]).sum()))
}

/// The inverse of a rigid 4x4 transform.
fn inverse(t: &[[f64; 4]; 4]) -> [[f64; 4]; 4] {
    let mut out = [[0.0; 4]; 4];
    for r in 0..3 {
        for c in 0..3 {
            out[r][c] = t[c][r];
        }
        out[r][3] = -(0..3).map(|k| t[k][r] * t[k][3]).sum::<f64>();
    }
    out[3][3] = 1.0;
    out
}

/// robid's model of a URDF equals robid's model of the hand-written DH description of the
/// same robot, given the URDF's inertials moved into the description's frames. `base` is
/// where the description's base frame sits in the URDF's root frame (a translation), and
/// q_urdf = q_dh + `offsets`. The mapping is checked first: every URDF link frame is, at
/// random angles, the description's link frame times one constant transform (1e-12).
fn equals_the_description(case: &Case, description: &str, base: [f64; 3], offsets: &[f64]) {
    let chain = chain(case);
    let tree = reference(case);
    let joints: Vec<&str> = chain.links.iter().map(|l| l.joint.as_str()).collect();
    let dh_robot = by_name(description)
        .robot()
        .with_drive(robid_symbolic::Drive::NONE);
    let dh_chain = tests::rnea::Chain::from_robot(&dh_robot);
    let identity = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let b = transform(&identity, base);
    let dh_pose = |q_dh: &[f64]| -> Vec<[[f64; 4]; 4]> {
        dh_chain
            .poses(q_dh)
            .iter()
            .map(|p| product(&b, &transform(&p.rotation, p.position)))
            .collect()
    };
    let to_urdf =
        |q_dh: &[f64]| -> Vec<f64> { q_dh.iter().zip(offsets).map(|(q, o)| q + o).collect() };
    // X_j: the URDF link frame in the description's frame j, from q_dh = 0
    let zero = vec![0.0; offsets.len()];
    let x: Vec<[[f64; 4]; 4]> = dh_pose(&zero)
        .iter()
        .zip(&chain.links)
        .map(|(h, l)| {
            product(
                &inverse(h),
                &tree.link_pose(&l.link, &joints, &to_urdf(&zero)),
            )
        })
        .collect();
    let mut rng = Rng::from_state(0x00ad_f003);
    for _ in 0..10 {
        let [q, _, _] = state(&dh_robot, &mut rng);
        for ((h, x), l) in dh_pose(&q).iter().zip(&x).zip(&chain.links) {
            let ours = product(h, x);
            let urdf = tree.link_pose(&l.link, &joints, &to_urdf(&q));
            let e = ours
                .iter()
                .flatten()
                .zip(urdf.iter().flatten())
                .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
            assert!(e <= 1e-12, "{}: link {} off by {e:e}", case.name, l.link);
        }
    }
    // the bodies in the description's frames: robid frame j -> URDF link frame -> frame j
    let links: Vec<tests::rnea::Link> = chain
        .links
        .iter()
        .zip(&x)
        .map(|(l, x)| {
            let t = product(x, &inverse(&l.frame));
            let rotation = [0, 1, 2].map(|a| [0, 1, 2].map(|b| t[a][b]));
            let origin = [0, 1, 2].map(|a| t[a][3]);
            let i = &l.inertial;
            let link = tests::rnea::Link {
                mass: i[9],
                first_moment: [i[6], i[7], i[8]],
                inertia: [[i[0], i[1], i[2]], [i[1], i[3], i[4]], [i[2], i[4], i[5]]],
                ..Default::default()
            };
            tests::rnea::express_in_parent(&link, &rotation, origin)
        })
        .collect();
    let urdf = Interpreted::new(&chain.robot).unwrap();
    let mut urdf_base = vec![0.0; urdf.base_parameter_count()];
    urdf.base_from_standard_into(&standard(&chain), &mut urdf_base)
        .unwrap();
    let dh = Interpreted::new(&dh_robot).unwrap();
    let mut dh_base = vec![0.0; dh.base_parameter_count()];
    dh.base_from_standard_into(&standard_from_links(&dh_robot, &links), &mut dh_base)
        .unwrap();
    let n = dh.dof();
    let mut worst: f64 = 0.0;
    for _ in 0..20 {
        let [q, qd, qdd] = state(&dh_robot, &mut rng);
        let (mut a, mut b) = (vec![0.0; n], vec![0.0; n]);
        urdf.inverse_dynamics_into(&to_urdf(&q), &qd, &qdd, &urdf_base, &mut a)
            .unwrap();
        dh.inverse_dynamics_into(&q, &qd, &qdd, &dh_base, &mut b)
            .unwrap();
        worst = worst.max(relative(&a, &b));
    }
    eprintln!(
        "{} URDF model against {description}.toml: {worst:e}",
        case.name
    );
    assert!(worst <= TOLERANCE, "{}: {worst:e}", case.name);
}

/// The TX40 URDF's link frames are tx40.toml's modified-DH frames raised by 0.320 m, with
/// q_urdf = q_dh + (0, -pi/2, pi/2, 0, 0, 0) (`urdf_reference.rs`
/// `tx40_urdf_frames_are_the_dh_frames`).
#[test]
fn tx40_urdf_model_equals_the_dh_description() {
    let offsets = [0.0, -FRAC_PI_2, FRAC_PI_2, 0.0, 0.0, 0.0];
    equals_the_description(&CASES[3], "tx40", [0.0, 0.0, 0.320], &offsets);
}

/// The Panda URDF's root is the base frame of panda.toml (Franka's modified DH table),
/// with the same joint angles.
#[test]
fn panda_urdf_model_equals_the_dh_description() {
    equals_the_description(&CASES[0], "panda", [0.0; 3], &[0.0; 7]);
}

/// The LWR4 URDF's `lwr_base_link` sits at (-0.25, 0, 1) in its root `box`, and is the
/// base frame of lwr4.toml (standard DH), with the same joint angles.
#[test]
fn lwr4_urdf_model_equals_the_dh_description() {
    equals_the_description(&CASES[2], "lwr4", [-0.25, 0.0, 1.0], &[0.0; 7]);
}

/// Inertials written into the URDF and read back give the torques of the values written
/// (1e-12), whether the attached links keep theirs (the Panda's hand and fingers, a heavier
/// link 7) or cannot (a link 7 lighter than what hangs from it).
#[test]
fn inertials_written_into_the_urdf_reproduce_the_torques() {
    let case = &CASES[0];
    let original = chain(case);
    let mut rng = Rng::from_state(0x00ad_f004);
    for scale in [1.3, 0.1] {
        // every body heavier (or, for 0.1, much lighter) with the same shape
        let written: Vec<[f64; 10]> = original
            .links
            .iter()
            .map(|l| l.inertial.map(|x| x * scale))
            .collect();
        let (text, _warnings) = write_inertials(case.text, case.name, &original, &written).unwrap();
        let selection = ChainSelection {
            base: None,
            tip: case.tip.map(str::to_owned),
        };
        let read = Robot::from_urdf(&text, case.name, &selection).unwrap();
        let model = Interpreted::new(&read.robot).unwrap();
        let with = |links: &[[f64; 10]]| {
            let mut c = read.clone();
            for (l, v) in c.links.iter_mut().zip(links) {
                l.inertial = *v;
            }
            let mut base = vec![0.0; model.base_parameter_count()];
            model
                .base_from_standard_into(&standard(&c), &mut base)
                .unwrap();
            base
        };
        let (expected, got) = (
            with(&written),
            with(&read.links.iter().map(|l| l.inertial).collect::<Vec<_>>()),
        );
        for _ in 0..10 {
            let [q, qd, qdd] = state(&read.robot, &mut rng);
            let (mut a, mut b) = (vec![0.0; 7], vec![0.0; 7]);
            model
                .inverse_dynamics_into(&q, &qd, &qdd, &expected, &mut a)
                .unwrap();
            model
                .inverse_dynamics_into(&q, &qd, &qdd, &got, &mut b)
                .unwrap();
            let e = relative(&b, &a);
            assert!(e <= TOLERANCE, "scale {scale}: {e:e}");
        }
    }
}

// The Panda read from its URDF at compile time, the hand and fingers attached to link 7.
robid_macros::robot_model!(
    file = "../data/example_robot_data/panda/panda.urdf",
    tip = "panda_hand"
);

/// `robot_model!` on a URDF: the generated code carries the URDF's inertials
/// (`URDF_STANDARD_PARAMETERS`, equal to the reader's) and every program agrees with the
/// interpreter of the same chain at random states (1e-12 of the output's largest entry).
#[test]
fn robot_model_on_a_urdf_agrees_with_the_interpreter() {
    use robid_runtime::model::ProgramKind;
    let chain = chain(&CASES[0]);
    assert_eq!(Panda::URDF_STANDARD_PARAMETERS.to_vec(), standard(&chain));
    let interpreted = Interpreted::new(&chain.robot).unwrap();
    let compiled: &dyn Model = &Panda;
    assert_eq!(compiled.sizes(), interpreted.sizes());
    let sizes = compiled.sizes();
    let mut base = vec![0.0; sizes.base];
    compiled
        .base_from_standard_into(&Panda::URDF_STANDARD_PARAMETERS, &mut base)
        .unwrap();
    let mut rng = Rng::from_state(0x00ad_f005);
    for _ in 0..10 {
        let [q, qd, qdd] = state(&chain.robot, &mut rng);
        let standard: Vec<f64> = (0..sizes.standard)
            .map(|_| rng.uniform(-1.0, 1.0))
            .collect();
        for kind in ProgramKind::ALL {
            let inputs: Vec<&[f64]> = kind
                .info()
                .inputs
                .iter()
                .map(|a| match a.name {
                    "q" => q.as_slice(),
                    "qd" => qd.as_slice(),
                    "qdd" => qdd.as_slice(),
                    "base" => base.as_slice(),
                    _ => standard.as_slice(),
                })
                .collect();
            let n = kind.info().output.size.len(sizes);
            let (mut a, mut b) = (vec![0.0; n], vec![0.0; n]);
            compiled.run(kind, &inputs, &mut a).unwrap();
            interpreted.run(kind, &inputs, &mut b).unwrap();
            let e = relative(&a, &b);
            assert!(e <= TOLERANCE, "{}: {e:e}", kind.info().name);
        }
    }
}
