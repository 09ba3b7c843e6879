//! Limits and gravity of the robot read from a URDF.

use super::*;
use crate::robot::Geometry;

fn value(g: &Geometry) -> f64 {
    let mut arena = Arena::new();
    let id = g.to_expr(&mut arena);
    let values = arena.values(&[]);
    arena.eval(&[id], &values).unwrap()[0]
}

const TILTED: &str = "<robot name=\"tilted\">
  <link name=\"world\"/><link name=\"mount\"/><link name=\"base\"/><link name=\"a\"/><link name=\"b\"/>
  <joint name=\"m\" type=\"fixed\"><parent link=\"world\"/><child link=\"mount\"/><origin xyz=\"1 2 3\" rpy=\"0.3 -0.2 0.1\"/></joint>
  <joint name=\"slide\" type=\"prismatic\"><parent link=\"mount\"/><child link=\"base\"/><origin xyz=\"0 0 0.2\" rpy=\"0 0.4 0\"/><axis xyz=\"1 0 0\"/></joint>
  <joint name=\"j1\" type=\"continuous\"><parent link=\"base\"/><child link=\"a\"/><origin xyz=\"0.1 0 0.3\" rpy=\"0.5 0 0\"/><axis xyz=\"0 1 0\"/>
    <limit lower=\"-1\" upper=\"1\" effort=\"20\" velocity=\"3\"/></joint>
  <joint name=\"j2\" type=\"revolute\"><parent link=\"a\"/><child link=\"b\"/><origin xyz=\"0.4 0 0\"/><axis xyz=\"0 0 1\"/>
    <limit lower=\"-2\" upper=\"1.5\" effort=\"0\" velocity=\"4\"/></joint>
</robot>";

#[test]
fn gravity_is_the_roots_down_in_frame_0() {
    // the base below a fixed tilted mount and a prismatic joint held at zero
    let chain = Robot::from_urdf(TILTED, "t.urdf", &selection(Some("base"), None)).unwrap();
    assert_eq!(chain.robot.dof(), 2);
    let poses = direct_poses(&direct_joints(TILTED), "world", &HashMap::new());
    let frame0 = poses["base"].then(&Rigid::from_pose(&chain.base));
    let expected: Vec<f64> = (0..3).map(|k| -9.81 * frame0.r[2][k]).collect();
    for (g, e) in chain.robot.gravity().iter().zip(&expected) {
        assert!((value(g) - e).abs() < 1e-12, "{} {e}", value(g));
    }
    // from the root, frame 0 lies on the first axis with gravity along -z of the world
    let chain = Robot::from_urdf(TILTED, "t.urdf", &ChainSelection::default()).unwrap();
    assert_eq!(chain.robot.dof(), 3);
    let up: Vec<f64> = chain.robot.gravity().iter().map(value).collect();
    let frame0 = Rigid::from_pose(&chain.base);
    for (k, g) in up.iter().enumerate() {
        assert!((g + 9.81 * frame0.r[2][k]).abs() < 1e-12);
    }
}

#[test]
#[allow(clippy::approx_constant)] // the UR5 file's printed 2 pi
fn limits_come_from_the_limit_elements() {
    let chain = Robot::from_urdf(TILTED, "t.urdf", &selection(Some("base"), None)).unwrap();
    let [j1, j2] = [
        &chain.robot.joints()[0].limits,
        &chain.robot.joints()[1].limits,
    ];
    // continuous: no position limits
    assert_eq!(j1.position, None);
    assert_eq!((j1.velocity, j1.torque), (Some(3.0), Some(20.0)));
    // effort 0: no torque limit
    assert_eq!(j2.position, Some([-2.0, 1.5]));
    assert_eq!((j2.velocity, j2.torque), (Some(4.0), None));
    let ur5 = Robot::from_urdf(&repository_file(UR5), UR5, &ChainSelection::default()).unwrap();
    let first = &ur5.robot.joints()[0].limits;
    assert_eq!(first.position, Some([-6.28318530718, 6.28318530718]));
    assert_eq!((first.velocity, first.torque), (Some(3.15), Some(150.0)));
}
