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

/// A `lower` or `upper` beyond ±1e9 (ROS and Gazebo files write ±1e16, the iris drone's
/// rotors of example-robot-data) or infinite is no position limit, told once; the other
/// limits stay. It was an error ("not a value of a robot"), and one such side alone would
/// have been read as 0.
#[test]
fn an_unbounded_position_limit_is_none() {
    for (lower, upper) in [("-1e+16", "1e+16"), ("-inf", "0.5"), ("-1", "1e300")] {
        let text = TILTED.replace(
            "<limit lower=\"-2\" upper=\"1.5\"",
            &format!("<limit lower=\"{lower}\" upper=\"{upper}\""),
        );
        let chain = Robot::from_urdf(&text, "t.urdf", &selection(Some("base"), None))
            .unwrap_or_else(|e| panic!("{lower} {upper}: {e}"));
        let j2 = &chain.robot.joints()[1].limits;
        assert_eq!(j2.position, None, "{lower} {upper}");
        assert_eq!(j2.velocity, Some(4.0));
        let told = one_warning(&chain, "taken as no position limit");
        assert!(told.contains("of joint `j2`"), "{}", told);
    }
}

/// A chain hung from `world` through a fixed `mount` (line 3) and a fixed `adapter`
/// (line 4) between the base and joint 1 (line 5).
const MOUNTED: &str = "<robot name=\"mounted\">
  <link name=\"world\"/><link name=\"base\"/><link name=\"plate\"/><link name=\"a\"/><link name=\"b\"/>
  <joint name=\"mount\" type=\"fixed\"><parent link=\"world\"/><child link=\"base\"/><origin rpy=\"MOUNT\"/></joint>
  <joint name=\"adapter\" type=\"fixed\"><parent link=\"base\"/><child link=\"plate\"/><origin xyz=\"0 0 0.1\" rpy=\"ADAPTER\"/></joint>
  <joint name=\"j1\" type=\"revolute\"><parent link=\"plate\"/><child link=\"a\"/><origin xyz=\"0 0 0.3\"/><axis xyz=\"AXIS\"/></joint>
  <joint name=\"j2\" type=\"revolute\"><parent link=\"a\"/><child link=\"b\"/><origin xyz=\"0.4 0 0\" rpy=\"1.5707963267948966 0 0\"/><axis xyz=\"0 0 1\"/></joint>
</robot>";

/// A mounting tilt of 1e-5 to 1e-4 rad gives gravity components below 1e-3 m/s^2: they are
/// taken as 0 with a warning (they were an error) placed at the element that tilts joint
/// 1's axis, the fixed joint above or below the base or joint 1's own axis, and naming it
/// with its angle. Tilts that only add up to a small one (no element near a right angle)
/// are told at joint 1. The change it makes is bounded against m g l with the share
/// dropped (it was "less than 1e-4 of their size", false of a SCARA, whose gravity torques
/// are all the tilt's).
#[test]
fn a_small_tilt_is_placed_at_the_element_that_tilts() {
    let text = |mount: &str, adapter: &str, axis: &str| {
        MOUNTED
            .replace("MOUNT", mount)
            .replace("ADAPTER", adapter)
            .replace("AXIS", axis)
    };
    // the one warning about gravity, and the robot's gravity (components taken as 0)
    let warning = |text: &str, base: Option<&str>| {
        let chain = Robot::from_urdf(text, "t.urdf", &selection(base, None))
            .unwrap_or_else(|e| panic!("{e}"));
        let told = one_warning(&chain, "gravity in robid frame 0");
        let g: Vec<f64> = chain.robot.gravity().iter().map(value).collect();
        (told.to_owned(), g)
    };
    let level = "0 0 0";
    let up = "0 0 1";
    assert!(
        Robot::from_urdf(
            &text(level, level, up),
            "t.urdf",
            &ChainSelection::default()
        )
        .is_ok()
    );
    for (text, base, place, named) in [
        (
            text("1e-5 0 0", level, up),
            None,
            "t.urdf:3:",
            "the `<origin>` rotation of fixed joint `mount` is 1.0e-5 rad from a right angle",
        ),
        // chosen as the base, `base` is still tilted by `mount` against the root's gravity
        (
            text("1e-5 0 0", level, up),
            Some("base"),
            "t.urdf:3:",
            "fixed joint `mount` is 1.0e-5 rad",
        ),
        (
            text(level, "0 3e-5 1.5707963267948966", up),
            None,
            "t.urdf:4:",
            "the `<origin>` rotation of fixed joint `adapter` is 3.0e-5 rad from a right angle",
        ),
        (
            text(level, level, "0 2e-5 1"),
            None,
            "t.urdf:5:",
            "the `<axis>` of joint `j1` is 2.0e-5 rad from a right angle",
        ),
    ] {
        let (message, g) = warning(&text, base);
        for part in [
            place,
            named,
            "gravity in robid frame 0, whose z is joint `j1`'s axis, has",
            "taken as 0",
            "too little for any data to tell from none",
            // bounded against m g l, not the gravity torques: a SCARA's are all the tilt's
            "of m g l, the torque of the links' weight about a horizontal axis",
            "a SCARA's",
        ] {
            assert!(message.contains(part), "{message}\nexpected {part:?}");
        }
        assert!(message.starts_with(place), "{message}");
        assert!(!message.contains("of their size"), "{message}");
        // what is left is one component, the whole of gravity (every tilt here is about a
        // horizontal axis)
        assert_eq!(g.iter().filter(|&&x| x != 0.0).count(), 1, "{g:?}");
        assert!(
            (g.iter().map(|x| x * x).sum::<f64>().sqrt() - 9.81).abs() < 1e-6,
            "{g:?}"
        );
    }
    // two tilts of 0.3 rad that leave 1e-5 rad between them: no element to blame
    let (message, _) = warning(&text("0.3 0 0", "-0.30001 0 0", up), None);
    assert!(
        message.starts_with("t.urdf:5:")
            && message.contains("a right angle on the path from the root"),
        "{message}"
    );
}
