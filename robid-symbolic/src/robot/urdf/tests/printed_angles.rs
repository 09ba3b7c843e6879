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
