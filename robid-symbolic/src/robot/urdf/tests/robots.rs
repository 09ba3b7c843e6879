//! The real robots: UR5 lengths, the Panda's hand and fingers, the Panda without a tip,
//! warnings, and base-parameter counts against the hand-written descriptions.

use super::*;
use crate::Derivation;
use crate::robot::Drive;

fn read(path: &str, tip: Option<&str>) -> UrdfChain {
    Robot::from_urdf(&repository_file(path), path, &selection(None, tip)).unwrap()
}

/// The distance between two lines (point, unit direction).
fn line_distance(p: [f64; 3], u: [f64; 3], q: [f64; 3], w: [f64; 3]) -> f64 {
    use super::super::rigid::{cross, dot, norm, sub};
    let n = cross(u, w);
    let between = sub(q, p);
    if norm(n) < 1e-12 {
        norm(cross(between, u))
    } else {
        dot(between, n).abs() / norm(n)
    }
}

#[test]
fn ur5_needs_no_tip_and_has_the_published_lengths() {
    let chain = read(UR5, None);
    assert_eq!(chain.robot.dof(), 6);
    assert_eq!(chain.links[5].link, "wrist_3_link");
    let names: Vec<&str> = chain.links[5]
        .attached
        .iter()
        .map(|a| a.name.as_str())
        .collect();
    assert_eq!(names, ["ee_link", "tool0"]);
    // invariants of the axes at q = 0, in the base frame
    let frames = dh_frames(&chain, &[0.0; 6]);
    let axis = |j: usize| {
        (
            frames[j].p,
            [frames[j].r[0][2], frames[j].r[1][2], frames[j].r[2][2]],
        )
    };
    let (p2, u2) = axis(1);
    let (p3, u3) = axis(2);
    let (p4, u4) = axis(3);
    assert!((line_distance(p2, u2, p3, u3) - 0.425).abs() < 1e-12);
    assert!((line_distance(p3, u3, p4, u4) - 0.39225).abs() < 1e-12);
    // the shoulder's height: frame 0 lies where axes 1 and 2 meet
    assert!((chain.base[2][3] - 0.089159).abs() < 1e-12);
    let r = rows(&chain.robot);
    let published = [
        (3, 2, 0.10915),
        (4, 2, 0.09465),
        (2, 1, 0.425),
        (3, 1, 0.39225),
    ];
    for (j, k, value) in published {
        assert!((r[j][k].abs() - value).abs() < 1e-12, "row {j}: {:?}", r[j]);
    }
    for (j, k) in [(1, 1), (4, 1), (5, 1)] {
        assert_eq!(r[j][k], 0.0, "a of joint {}", j + 1);
    }
    // ee_link lies 0.0823 along the last axis
    let ee = &chain.links[5].attached[0].frame;
    let offset = (ee[0][3].powi(2) + ee[1][3].powi(2) + ee[2][3].powi(2)).sqrt();
    assert!((offset - 0.0823).abs() < 1e-12);
    // the transmissions' `<joint>` children are not joints
    assert!(chain.links.iter().all(|l| !l.joint.ends_with("trans")));
    assert_eq!(chain.robot.name(), "ur5");
}

#[test]
fn panda_to_its_hand_carries_the_fingers_on_link_7() {
    let chain = read(PANDA, Some("panda_hand"));
    assert_eq!(chain.robot.dof(), 7);
    let names: Vec<&str> = chain.links[6]
        .attached
        .iter()
        .map(|a| a.name.as_str())
        .collect();
    for wanted in [
        "panda_link8",
        "panda_hand",
        "panda_leftfinger",
        "panda_rightfinger",
    ] {
        assert!(names.contains(&wanted), "{names:?}");
    }
    assert!(chain.links[..6].iter().all(|l| l.attached.is_empty()));
}

#[test]
fn panda_without_a_tip_lists_the_leaves() {
    let text = repository_file(PANDA);
    let e = Robot::from_urdf(&text, PANDA, &ChainSelection::default()).unwrap_err();
    let message = e.to_string();
    assert!(message.contains("do not form a single path"), "{message}");
    // the fingers' chains hold the mimic finger joint: named as what does not work
    assert!(
        message.contains(
            "choose the tip `panda_hand_tcp`; not the leaves `panda_leftfinger`, \
             `panda_rightfinger`: "
        ),
        "{message}"
    );
    assert!(
        message.contains("mimics joint `panda_finger_joint1`"),
        "{message}"
    );
}

#[test]
fn the_lwr4_warns_about_its_second_origin_and_everyone_about_dynamics() {
    let chain = read(LWR4, None);
    assert_eq!(chain.robot.name(), "kuka_lwr");
    assert_eq!(chain.robot.dof(), 7);
    let second = chain
        .warnings
        .iter()
        .find(|w| w.contains("`<origin>` elements"))
        .unwrap();
    assert!(
        second.starts_with(&format!(
            "{LWR4}:55:5: `<joint name=\"box_lwr_base_joint\">` has 2"
        )),
        "{second}"
    );
    let dynamics: Vec<&String> = chain
        .warnings
        .iter()
        .filter(|w| w.contains("<dynamics"))
        .collect();
    assert_eq!(dynamics.len(), 1);
    assert!(dynamics[0].contains("Fv and Fc"));
}

fn count(robot: &Robot) -> usize {
    Derivation::new(robot).base_parameters().unwrap().base.len()
}

fn description(name: &str) -> Robot {
    let path = format!("robots/descriptions/{name}.toml");
    Robot::from_toml(&repository_file(&path), &path)
        .unwrap()
        .with_drive(Drive::NONE)
}

#[test]
fn base_parameter_counts_equal_the_hand_written_descriptions() {
    let ur5 = read(UR5, None).robot;
    assert_eq!(count(&ur5), 36);
    assert_eq!(count(&ur5), count(&description("ur5e")));
    let panda = read(PANDA, Some("panda_hand")).robot;
    assert_eq!(count(&panda), 43);
    assert_eq!(count(&panda), count(&description("panda")));
    let lwr4 = read(LWR4, None).robot;
    assert_eq!(count(&lwr4), 43);
    assert_eq!(count(&lwr4), count(&description("lwr4")));
    let tx40 = read(TX40, None).robot;
    assert_eq!(count(&tx40), 36);
    assert_eq!(count(&tx40), count(&description("tx40")));
}
/// The inner rows (2 to n-1: the first and last hold frame choices, such as where frame 0
/// sits) equal the hand-written tables' up to the signs of axes (z_j follows the URDF's
/// axis sign, flipping alpha, a and d) and theta offsets of 0 or pi (x_j points from axis
/// j to axis j+1, so a_j >= 0 where the Franka table writes a_5 = -0.0825).
#[test]
fn inner_rows_equal_the_hand_written_tables_up_to_signs() {
    for (path, tip, name) in [
        (PANDA, Some("panda_hand"), "panda"),
        (LWR4, None, "lwr4"),
        (TX40, None, "tx40"),
    ] {
        let urdf = rows(&read(path, tip).robot);
        let toml = rows(&description(name));
        let n = urdf.len();
        assert_eq!(n, toml.len());
        for j in 1..n - 1 {
            for k in 0..3 {
                assert!(
                    (urdf[j][k].abs() - toml[j][k].abs()).abs() < 1e-12,
                    "{name} row {}: {:?} {:?}",
                    j + 1,
                    urdf[j],
                    toml[j]
                );
            }
        }
    }
    let panda = rows(&read(PANDA, Some("panda_hand")).robot);
    let thetas: Vec<f64> = panda.iter().map(|r| r[3]).collect();
    let pi = std::f64::consts::PI;
    assert_eq!(thetas, [0.0, 0.0, 0.0, pi, 0.0, pi, 0.0]);
}
