//! The fitted DH values carry the URDF's decimals, not the rounding of their sums.

use super::*;
use crate::robot::urdf::build::tidy;

#[test]
fn rounding_of_sums_is_dropped_and_needed_digits_are_kept() {
    assert_eq!(0.1 + 0.2, 0.30000000000000004);
    assert_eq!(tidy(0.1 + 0.2), 0.3);
    assert_eq!(tidy(0.42000000000000004), 0.42);
    assert_eq!(tidy(-(0.1 + 0.2)), -0.3);
    assert_eq!(tidy(0.3999999999999999), 0.4);
    assert_eq!(tidy(9.81 * (1.0 + f64::EPSILON)), 9.81);
    assert_eq!(tidy(0.0), 0.0);
    // small values move by the fit's absolute rounding, not by their own last place
    assert_eq!(tidy(-0.000350099999999999), -0.0003501);
    // values that need their digits stay as they are
    for x in [
        0.123456789012345,
        2f64.sqrt(),
        1e-6 + 1e-14,
        0.42 + 1e-14,
        123.456789,
    ] {
        assert_eq!(tidy(x), x, "{x:e}");
    }
    // nothing moves by more than 8 units of 2^-52 or 4 units in its last place
    let floor = 8.0 * f64::EPSILON;
    for x in [1.0 / 3.0, 0.1 / 3.0, 2.0 / 3.0, 300.0 / 7.0, -1e-5 / 3.0] {
        let moved = (tidy(x) - x).abs();
        assert!(
            moved <= floor.max(4.0 * x.abs() * f64::EPSILON),
            "{x:e}: {moved:e}"
        );
    }
    let ulp = 300.0 * f64::EPSILON;
    assert_eq!(tidy(300.0 + 3.0 * ulp), 300.0);
    assert_ne!(tidy(300.0 + 8.0 * ulp), 300.0);
    assert_eq!(tidy(0.42 + 1.5e-15), 0.42);
    assert_ne!(tidy(0.42 + 2.5e-15), 0.42);
}

#[test]
fn a_urdf_whose_lengths_add_up_gives_their_decimal_sum() {
    // joint 3's origin 0.2045 along y of link 2, then joint 4's 0.2155 along z of link 3,
    // with right angles written 1 ulp short (the KUKA iiwa 14's, as MuJoCo Menagerie's
    // URDF writes them): the fitted d is 0.42, not 0.42000000000000004
    let urdf = "<robot name=\"arm\">
  <link name=\"base\"/><link name=\"l1\"/><link name=\"l2\"/><link name=\"l3\"/><link name=\"l4\"/>
  <joint name=\"j1\" type=\"revolute\"><parent link=\"base\"/><child link=\"l1\"/><origin xyz=\"0 0 0.1575\"/><axis xyz=\"0 0 1\"/>
    <limit lower=\"-2\" upper=\"2\" effort=\"100\" velocity=\"1\"/></joint>
  <joint name=\"j2\" type=\"revolute\"><parent link=\"l1\"/><child link=\"l2\"/><origin xyz=\"0 0 0.2025\" rpy=\"1.5707963267948963 0 3.141592653589793\"/><axis xyz=\"0 0 1\"/>
    <limit lower=\"-2\" upper=\"2\" effort=\"100\" velocity=\"1\"/></joint>
  <joint name=\"j3\" type=\"revolute\"><parent link=\"l2\"/><child link=\"l3\"/><origin xyz=\"0 0.2045 0\" rpy=\"1.5707963267948963 0 3.141592653589793\"/><axis xyz=\"0 0 1\"/>
    <limit lower=\"-2\" upper=\"2\" effort=\"100\" velocity=\"1\"/></joint>
  <joint name=\"j4\" type=\"revolute\"><parent link=\"l3\"/><child link=\"l4\"/><origin xyz=\"0 0 0.2155\" rpy=\"1.5707963267948963 0 0\"/><axis xyz=\"0 0 1\"/>
    <limit lower=\"-2\" upper=\"2\" effort=\"100\" velocity=\"1\"/></joint>
</robot>";
    let chain = Robot::from_urdf(urdf, "arm.urdf", &ChainSelection::default()).unwrap();
    let d: Vec<String> = chain
        .robot
        .joints()
        .iter()
        .map(|j| j.d.as_str().to_string())
        .collect();
    assert!(d.contains(&"0.42".to_string()), "{d:?}");
}

/// Unitree Z1's joint offset `a = sqrt(0.218^2 + 0.057^2) = 0.225328648866495`: its square
/// in the base parameters is the decimal of its float, `0.0507730000000002` (the float
/// nearest the exact square, 0.050773000000000198448...), not
/// `2030920000000007937933343401/40000000000000000000000000000`.
#[test]
fn base_parameters_of_a_long_length_are_written_as_decimals() {
    let urdf = r#"<robot name="b09">
  <link name="base"/>
  <link name="l1"><inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <link name="l2"><inertial><origin xyz="0.1 0 0"/><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <link name="l3"><inertial><origin xyz="0.1 0 0"/><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><axis xyz="0 0 1"/><limit lower="-2" upper="2" effort="10" velocity="2"/></joint>
  <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/><origin xyz="0 0 0.3"/><axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="10" velocity="2"/></joint>
  <joint name="j3" type="revolute"><parent link="l2"/><child link="l3"/><origin xyz="0.218 0 0.057"/><axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="10" velocity="2"/></joint>
</robot>"#;
    let chain = Robot::from_urdf(urdf, "b09.urdf", &ChainSelection::default()).unwrap();
    let programs = crate::program::RobotPrograms::derive(&chain.robot).unwrap();
    let text: Vec<String> = programs
        .base
        .iter()
        .map(|b| format!("{} = {}", b.name, b.expression))
        .collect();
    assert!(
        text.contains(&"ZZR2 = ZZ2 + 0.0507730000000002*M3".to_owned()),
        "{text:?}"
    );
    assert!(text.iter().all(|t| !t.contains('/')), "{text:?}");
}
