//! The decisive check: every URDF link's pose computed from the URDF equals robid's DH
//! forward kinematics times `ChainLink::frame`, at random q, on random chains and on the
//! real files.

use super::*;
use robid_core::rng::Rng;
use std::f64::consts::{FRAC_PI_2, PI};
use std::fmt::Write;

fn random_unit(rng: &mut Rng) -> [f64; 3] {
    loop {
        let v = [
            rng.uniform(-1.0, 1.0),
            rng.uniform(-1.0, 1.0),
            rng.uniform(-1.0, 1.0),
        ];
        let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        if n > 0.2 && n <= 1.0 {
            return v.map(|x| x / n);
        }
    }
}

fn random_vector(rng: &mut Rng, size: f64) -> [f64; 3] {
    [
        rng.uniform(-size, size),
        rng.uniform(-size, size),
        rng.uniform(-size, size),
    ]
}

/// A right angle as files write it: exact, or printed to 12 digits.
fn right_angle(rng: &mut Rng) -> String {
    match rng.below(5) {
        0 => "0".to_owned(),
        1 => "1.57079632679".to_owned(),
        2 => "-1.5707963267948966".to_owned(),
        3 => "3.14159265359".to_owned(),
        _ => format!("{:?}", -FRAC_PI_2),
    }
}

fn triple(v: [f64; 3]) -> String {
    format!("{:?} {:?} {:?}", v[0], v[1], v[2])
}

/// A random URDF chain of `n` movable joints with fixed joints between, parallel,
/// coincident and intersecting axes, right-angle rotations, a side branch (a revolute
/// joint off the chain) and a fixed tool; returns the text and the tip link.
fn random_urdf(rng: &mut Rng, n: usize) -> (String, String) {
    let mut text = String::from("<robot name=\"random\">\n  <link name=\"l0\"/>\n");
    let mut links = 1;
    let mut previous_axis: Option<[f64; 3]> = None;
    let mut last = "l0".to_owned();
    for j in 0..n {
        let case = if previous_axis.is_some() {
            rng.below(6)
        } else {
            0
        };
        if case == 0 && rng.below(3) == 0 {
            // a fixed joint between
            let child = format!("l{links}");
            links += 1;
            let _ = write!(
                text,
                "  <link name=\"{child}\"/>\n  <joint name=\"f{j}\" type=\"fixed\"><parent link=\"{last}\"/><child link=\"{child}\"/><origin xyz=\"{}\" rpy=\"{}\"/></joint>\n",
                triple(random_vector(rng, 0.4)),
                triple(random_vector(rng, PI))
            );
            last = child;
        }
        let same = previous_axis.unwrap_or([0.0, 0.0, 1.0]);
        let (xyz, rpy, axis) = match case {
            // parallel, coincident, intersecting
            1 => (triple(random_vector(rng, 0.4)), "0 0 0".to_owned(), same),
            2 => (triple(same.map(|x| x * 0.3)), "0 0 0".to_owned(), same),
            3 => (
                "0 0 0".to_owned(),
                triple(random_vector(rng, PI)),
                random_unit(rng),
            ),
            4 => {
                let rpy = format!(
                    "{} {} {}",
                    right_angle(rng),
                    right_angle(rng),
                    right_angle(rng)
                );
                let mut axis = [0.0; 3];
                axis[rng.below(3)] = if rng.below(2) == 0 { 1.0 } else { -1.0 };
                (triple(random_vector(rng, 0.4)), rpy, axis)
            }
            _ => (
                triple(random_vector(rng, 0.4)),
                triple(random_vector(rng, PI)),
                random_unit(rng),
            ),
        };
        let kind = match rng.below(4) {
            0 => "prismatic",
            1 => "continuous",
            _ => "revolute",
        };
        let child = format!("l{links}");
        links += 1;
        let mass = rng.uniform(0.5, 3.0);
        let _ = write!(
            text,
            "  <link name=\"{child}\"><inertial><origin xyz=\"{}\" rpy=\"{}\"/><mass value=\"{mass:?}\"/><inertia ixx=\"0.05\" ixy=\"0.001\" ixz=\"-0.002\" iyy=\"0.04\" iyz=\"0.003\" izz=\"0.03\"/></inertial></link>\n  <joint name=\"j{j}\" type=\"{kind}\"><parent link=\"{last}\"/><child link=\"{child}\"/><origin xyz=\"{xyz}\" rpy=\"{rpy}\"/><axis xyz=\"{}\"/><limit lower=\"-1\" upper=\"1\" effort=\"10\" velocity=\"2\"/></joint>\n",
            triple(random_vector(rng, 0.1)),
            triple(random_vector(rng, PI)),
            triple(axis)
        );
        if rng.below(3) == 0 {
            let side = format!("s{j}");
            let _ = write!(
                text,
                "  <link name=\"{side}\"><inertial><mass value=\"0.7\"/><inertia ixx=\"0.01\" ixy=\"0\" ixz=\"0\" iyy=\"0.01\" iyz=\"0\" izz=\"0.01\"/></inertial></link>\n  <joint name=\"side{j}\" type=\"revolute\"><parent link=\"{child}\"/><child link=\"{side}\"/><origin xyz=\"{}\"/><axis xyz=\"0 1 0\"/></joint>\n",
                triple(random_vector(rng, 0.2))
            );
        }
        previous_axis = Some(axis);
        last = child;
    }
    let _ = write!(
        text,
        "  <link name=\"tool\"/>\n  <joint name=\"tool_joint\" type=\"fixed\"><parent link=\"{last}\"/><child link=\"tool\"/><origin xyz=\"0 0 0.1\" rpy=\"0.3 0 0\"/></joint>\n</robot>\n"
    );
    (text, last)
}

#[test]
fn random_chains_match_the_urdf_at_random_configurations() {
    let mut rng = Rng::new(20261126);
    for case in 0..200 {
        let n = 1 + rng.below(8);
        let (text, tip) = random_urdf(&mut rng, n);
        let chain = Robot::from_urdf(&text, "random.urdf", &selection(None, Some(&tip)))
            .unwrap_or_else(|e| panic!("case {case}: {e}\n{text}"));
        assert_eq!(chain.robot.dof(), n, "case {case}");
        for trial in 0..4 {
            let q: Vec<f64> = (0..n)
                .map(|_| {
                    if trial == 0 {
                        0.0
                    } else {
                        rng.uniform(-2.0, 2.0)
                    }
                })
                .collect();
            check_kinematics(&text, &chain, "l0", &tip, &q, 1e-12);
        }
    }
}

#[test]
fn the_real_urdfs_match_at_random_configurations() {
    let mut rng = Rng::new(7);
    for (path, base, tip) in [
        (PANDA, "panda_link0", Some("panda_hand")),
        (UR5, "world", None),
        (LWR4, "box", None),
        (TX40, "base_link", None),
    ] {
        let text = repository_file(path);
        let chain = Robot::from_urdf(&text, path, &selection(None, tip)).unwrap();
        let tip = tip.map_or_else(
            || {
                chain
                    .links
                    .last()
                    .map(|l| l.link.clone())
                    .unwrap_or_default()
            },
            str::to_owned,
        );
        let root = direct_joints(&text)
            .iter()
            .map(|j| j.parent.clone())
            .find(|p| !direct_joints(&text).iter().any(|j| &j.child == p))
            .unwrap();
        assert_eq!(root, base, "{path}");
        for trial in 0..20 {
            let q: Vec<f64> = (0..chain.robot.dof())
                .map(|_| {
                    if trial == 0 {
                        0.0
                    } else {
                        rng.uniform(-2.0, 2.0)
                    }
                })
                .collect();
            check_kinematics(&text, &chain, base, &tip, &q, 1e-12);
        }
    }
}
