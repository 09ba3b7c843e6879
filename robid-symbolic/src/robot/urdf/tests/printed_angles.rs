//! Right angles printed to a few decimals (`1.5708`, `3.1416`), as CAD exports and
//! Kinova's URDFs write them, are those right angles; coarser or other values are not.

use super::*;
use crate::robot::urdf::xml::printed_right_angle;
use std::f64::consts::{FRAC_PI_2, PI};

#[test]
fn a_right_angle_printed_to_its_decimals_is_that_angle() {
    for (word, k) in [
        ("1.5708", 1.0),
        ("-1.5708", -1.0),
        ("3.1416", 2.0),
        ("-3.14159", -2.0),
        ("4.7124", 3.0),
        ("6.2832", 4.0),
        ("1.57080", 1.0),
        ("1.5707963267948966", 1.0),
        // the same four decimals in exponent form (C's %E, and others)
        ("1.5708e0", 1.0),
        ("1.5708E+00", 1.0),
        ("-0.15708e1", -1.0),
        ("15708e-4", 1.0),
    ] {
        assert_eq!(printed_right_angle(word), Some(k * FRAC_PI_2), "{word}");
    }
    // too few decimals to tell, not the rounding of a right angle, zero, or no decimals
    for word in [
        "1.571",
        "3.14",
        "1.57079",
        "1.5709",
        "0.7854",
        "0.0000",
        "2",
        "7.8540",
        "1.571E+00",
        "0.15708e2",
        "15708e-3",
        "1.5708e99999999999999999999",
    ] {
        assert_eq!(printed_right_angle(word), None, "{word}");
    }
}

/// Two links of Kinova's Gen3 URDF as its maker writes them: right angles to four
/// decimals, tiny leftovers of a CAD export, and a fixed joint with a zero axis.
const KINOVA_LIKE: &str = r#"<robot name="gen3_part">
  <link name="base_link"/>
  <link name="shoulder"><inertial><origin xyz="0 -0.01 -0.07"/><mass value="1.3773"/>
    <inertia ixx="0.00457" ixy="0" ixz="0" iyy="0.004831" iyz="0.000448" izz="0.001409"/></inertial></link>
  <link name="arm"><inertial><origin xyz="0 -0.1 -0.013"/><mass value="1.1636"/>
    <inertia ixx="0.011088" ixy="0" ixz="0" iyy="0.001072" iyz="-0.000691" izz="0.011255"/></inertial></link>
  <link name="flange"/>
  <joint name="Actuator1" type="revolute"><origin xyz="0 0 0.15643" rpy="3.1416 2.7629E-18 -4.9305E-36"/>
    <parent link="base_link"/><child link="shoulder"/><axis xyz="0 0 1"/>
    <limit effort="39" lower="-100.0" upper="100.0" velocity="0.8727"/></joint>
  <joint name="Actuator2" type="revolute"><origin xyz="0 0.005375 -0.12838" rpy="1.5708 2.1343E-17 -1.1102E-16"/>
    <parent link="shoulder"/><child link="arm"/><axis xyz="0 0 1"/>
    <limit lower="-2.41" upper="2.41" effort="39" velocity="0.8727"/></joint>
  <joint name="EndEffector" type="fixed"><origin xyz="0 -0.2 0" rpy="-1.5708 0 0"/>
    <parent link="arm"/><child link="flange"/><axis xyz="0 0 0"/></joint>
</robot>"#;

#[test]
fn a_makers_urdf_with_four_decimal_right_angles_is_read_as_written_exactly() {
    let chain = Robot::from_urdf(KINOVA_LIKE, "gen3.urdf", &ChainSelection::default()).unwrap();
    assert_eq!(chain.robot.dof(), 2);
    let alpha: Vec<&str> = chain
        .robot
        .joints()
        .iter()
        .map(|j| j.alpha.as_str())
        .collect();
    assert_eq!(alpha, ["0", "pi/2"]);
    // the base turned by exactly pi about x: gravity exactly along +z of frame 0
    let exact = KINOVA_LIKE
        .replace("3.1416 ", &format!("{PI:?} "))
        .replace("\"1.5708 ", &format!("\"{FRAC_PI_2:?} "))
        .replace("\"-1.5708 ", &format!("\"{:?} ", -FRAC_PI_2));
    assert_ne!(exact, KINOVA_LIKE);
    let written = Robot::from_urdf(&exact, "gen3.urdf", &ChainSelection::default()).unwrap();
    assert_eq!(chain.robot.gravity(), written.robot.gravity());
    for (a, b) in chain.robot.joints().iter().zip(written.robot.joints()) {
        assert_eq!(
            [&a.alpha, &a.a, &a.d, &a.theta].map(|g| g.as_str().to_string()),
            [&b.alpha, &b.a, &b.d, &b.theta].map(|g| g.as_str().to_string())
        );
    }
    // one warning names the first printed angle and counts the others
    let printed: Vec<&String> = chain
        .warnings
        .iter()
        .filter(|w| w.contains("printed to a few decimals"))
        .collect();
    assert_eq!(printed.len(), 1, "{:?}", chain.warnings);
    assert!(printed[0].contains("`3.1416` and 2 more"), "{}", printed[0]);
    assert!(written.warnings.iter().all(|w| !w.contains("printed")));
}

/// The UR5 of example-robot-data as its `ur*_gripper` files write it: right angles computed
/// by xacro from `pi = 3.14159265` (`1.570796325`, 1.8e-9 rad short of pi/2; `-3.14159265`
/// is pi rounded to 8 decimals, a printed right angle).
#[test]
fn right_angles_of_a_rounded_pi_are_those_angles_with_a_warning() {
    let exact = repository_file(UR5);
    let gripper = exact
        .replace("1.57079632679", "1.570796325")
        .replace("3.14159265359", "3.14159265");
    assert_ne!(gripper, exact);
    let chain = Robot::from_urdf(&gripper, "ur5_gripper.urdf", &ChainSelection::default())
        .unwrap_or_else(|e| panic!("{e}"));
    let written = Robot::from_urdf(&exact, "ur5.urdf", &ChainSelection::default()).unwrap();
    assert_eq!(chain.robot.gravity(), written.robot.gravity());
    for (a, b) in chain.robot.joints().iter().zip(written.robot.joints()) {
        assert_eq!(
            [&a.alpha, &a.a, &a.d, &a.theta].map(|g| g.as_str().to_string()),
            [&b.alpha, &b.a, &b.d, &b.theta].map(|g| g.as_str().to_string())
        );
    }
    let near: Vec<&String> = chain
        .warnings
        .iter()
        .filter(|w| w.contains("rad of a right angle"))
        .collect();
    assert_eq!(near.len(), 1, "{:?}", chain.warnings);
    assert!(
        near[0]
            .starts_with("ur5_gripper.urdf:86:18: `rpy` angles within 1e-8 rad of a right angle"),
        "{}",
        near[0]
    );
    assert!(
        near[0].contains("`1.570796325`, 1.8e-9 rad from pi/2, and 3 more"),
        "{}",
        near[0]
    );
    assert!(
        written
            .warnings
            .iter()
            .all(|w| !w.contains("rad of a right angle"))
    );
}

/// A right angle off by more than the rounding of pi (2e-8 rad) is not taken for one: it
/// is used as written. The UR5's shoulder pitch becomes joint 2's `theta`, an offset of
/// a revolute joint's variable, which is taken at any value (a fitted twist that close to
/// a right angle is measured too, taken with a warning: `tests/errors.rs`).
#[test]
fn an_angle_further_from_a_right_angle_is_not_snapped() {
    let exact = repository_file(UR5);
    for (word, snapped) in [
        ("1.570796332", true),   // 5.3e-9 rad beyond pi/2
        ("1.5707963468", false), // 2.0e-8
        ("1.57079635", false),   // 2.3e-8, and not pi/2 rounded to 8 decimals
    ] {
        let text = exact.replacen("1.57079632679", word, 1);
        let chain = Robot::from_urdf(&text, "ur5.urdf", &ChainSelection::default())
            .unwrap_or_else(|e| panic!("{word}: {e}"));
        let told = chain
            .warnings
            .iter()
            .any(|w| w.contains(&format!("`{word}`")));
        assert_eq!(told, snapped, "{word}: {:?}", chain.warnings);
        let theta = chain.robot.joints()[1].theta.as_str();
        let theta: f64 = theta
            .parse()
            .unwrap_or_else(|_| panic!("{word}: theta {theta}"));
        let off = word.parse::<f64>().unwrap() - FRAC_PI_2;
        match snapped {
            true => assert_eq!(theta, 0.0, "{word}"),
            false => assert!((theta.abs() - off.abs()).abs() < 1e-12, "{word}: {theta}"),
        }
    }
}

/// Right angles printed to nine decimals or more (`1.57079632679` of every UR and
/// ROS-Industrial file, `3.14159265358979`) are within 1e-9 rad of the right angle, so the
/// 1e-9 rule takes them as written: no warning, which used to tell such files to write "10
/// decimals or more". A right angle printed to four decimals still gets it.
#[test]
fn right_angles_the_1e9_rule_takes_are_not_warned_about() {
    let arm = |rpy: &str| {
        format!(
            r#"<robot name="b01">
  <link name="base"/>
  <link name="l1"><inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <link name="l2"><inertial><origin xyz="0.2 0 0"/><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><axis xyz="0 0 1"/>
    <limit lower="-2" upper="2" effort="10" velocity="2"/></joint>
  <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/>
    <origin xyz="0 0 0.3" rpy="{rpy} 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-2" upper="2" effort="10" velocity="2"/></joint>
</robot>"#
        )
    };
    let printed = |text: &str| {
        let chain = Robot::from_urdf(text, "t.urdf", &ChainSelection::default())
            .unwrap_or_else(|e| panic!("{e}"));
        let alpha = chain.robot.joints()[1].alpha.as_str().to_string();
        let warned = chain
            .warnings
            .iter()
            .any(|w| w.contains("printed to a few decimals"));
        (alpha, warned)
    };
    for (rpy, alpha) in [
        ("1.57079632679", "pi/2"),
        ("3.14159265358979", "pi"),
        ("-1.570796327", "-pi/2"),
        ("4.7123889804", "-pi/2"),
        ("1.5707963267948966", "pi/2"),
    ] {
        assert_eq!(printed(&arm(rpy)), (alpha.to_owned(), false), "{rpy}");
    }
    for (rpy, alpha) in [("1.5708", "pi/2"), ("3.1416", "pi"), ("-1.57080", "-pi/2")] {
        assert_eq!(printed(&arm(rpy)), (alpha.to_owned(), true), "{rpy}");
    }
    // the repository's UR5, whose right angles are `1.57079632679` and `3.14159265359`
    let ur5 = Robot::from_urdf(
        &repository_file(UR5),
        "ur5.urdf",
        &ChainSelection::default(),
    )
    .unwrap();
    assert!(
        ur5.warnings.iter().all(|w| !w.contains("right angle")),
        "{:?}",
        ur5.warnings
    );
}
