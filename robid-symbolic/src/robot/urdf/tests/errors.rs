//! Every mistake the reader names, with its place and wording; no panic on garbage.

use super::*;
use crate::robot::bounds::MAX_JOINTS;

/// A two-joint arm with `joints` replacing its joints (links a, b, c).
fn arm(joints: &str) -> String {
    format!(
        "<robot name=\"arm\">\n<link name=\"a\"/>\n<link name=\"b\"/>\n<link name=\"c\"/>\n{joints}</robot>\n"
    )
}

const J1: &str = "<joint name=\"j1\" type=\"revolute\"><parent link=\"a\"/><child link=\"b\"/><axis xyz=\"0 0 1\"/></joint>\n";
const J2: &str = "<joint name=\"j2\" type=\"revolute\"><parent link=\"b\"/><child link=\"c\"/><origin xyz=\"0.5 0 0\"/><axis xyz=\"0 0 1\"/></joint>\n";

fn error_of(text: &str, chosen: &ChainSelection) -> String {
    match Robot::from_urdf(text, "t.urdf", chosen) {
        Ok(_) => panic!("no error for\n{text}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn each_mistake_is_named_at_its_place() {
    let two = format!("{J1}{J2}");
    let cases: Vec<(String, &str, &[&str])> = vec![
        ("<robot name=\"x\"><link name=\"a\"></robot>".to_owned(), "t.urdf:1:", &["not well-formed XML"]),
        ("<model name=\"x\"/>".to_owned(), "t.urdf:1:1:", &["`<model>`, not `<robot>`"]),
        (arm(&J1.replace(" type=\"revolute\"", "")), "t.urdf:5:1:", &["`<joint name=\"j1\">` has no `type` attribute", "add `type=\"...\"`"]),
        (arm(&J1.replace("0 0 1", "0 x 1")), "t.urdf:5:", &["`x` is not a number"]),
        (arm(&J1.replace("0 0 1", "0 inf 1")), "t.urdf:5:", &["is not finite", "write finite numbers"]),
        (arm(&J1.replace("0 0 1", "0 1e300 1")), "t.urdf:5:", &["`1e300` is beyond ±1e9, not a value of a robot", "write the axis as a direction of moderate components, e.g. `0 0 1`"]),
        // the fix gives the unit of the attribute at fault
        (arm(&J1.replace("<axis", "<limit effort=\"10\" velocity=\"1e30\"/><axis")), "t.urdf:5:", &["`1e30` is beyond ±1e9", "velocity limit in rad/s"]),
        (arm(&J1.replace("<axis", "<limit effort=\"1e30\" velocity=\"1\"/><axis")), "t.urdf:5:", &["`1e30` is beyond ±1e9", "effort limit in N m"]),
        (arm(&J1.replace("<axis", "<origin xyz=\"0 0 1e10\"/><axis")), "t.urdf:5:", &["`1e10` is beyond ±1e9", "position in m"]),
        // masses and inertias within what parameter files take (1e9 kg was read, and what
        // `robid model` wrote of it was refused)
        (arm(J1).replace("<link name=\"b\"/>", "<link name=\"b\"><inertial><mass value=\"2e6\"/><inertia ixx=\"1\" ixy=\"0\" ixz=\"0\" iyy=\"1\" iyz=\"0\" izz=\"1\"/></inertial></link>"), "t.urdf:3:", &["`2e6` is beyond ±1e6", "mass in kg"]),
        (arm(J1).replace("<link name=\"b\"/>", "<link name=\"b\"><inertial><mass value=\"1\"/><inertia ixx=\"1\" ixy=\"0\" ixz=\"0\" iyy=\"1\" iyz=\"0\" izz=\"1e7\"/></inertial></link>"), "t.urdf:3:", &["`1e7` is beyond ±1e6", "inertia about the centre of mass"]),
        (arm(&J1.replace("0 0 1", "0 1")), "t.urdf:5:", &["has 2 numbers", "write 3 numbers"]),
        (arm(&J1.replace("0 0 1", "1")), "t.urdf:5:", &["`xyz=\"1\"` of `<axis>` has 1 number; write 3 numbers"]),
        (arm(&J1.replace("0 0 1", "0 0 0")), "t.urdf:5:", &["the axis of `<joint name=\"j1\">` has no direction"]),
        (arm(&J1.replace("revolute", "hinge")), "t.urdf:5:", &["unknown joint type `hinge`", "revolute, continuous, prismatic"]),
        (arm(&format!("{J1}{}", J2.replace("\"b\"/><child", "\"bb\"/><child"))), "t.urdf:6:", &["the parent link `bb` of joint `j2` is no `<link>`", "`b`"]),
        (arm(&format!("{J1}{}", J2.replace("j2", "j1"))), "t.urdf:6:1:", &["a second joint is named `j1` (the first is on line 5)"]),
        (arm(&format!("{J1}{}", J2.replace("\"b\"/><child", "\"a\"/><child").replace("\"c\"/>", "\"b\"/>"))), "t.urdf:6:", &["link `b` has two parents"]),
        (arm(&format!("{J1}{}", J2.replace("<child link=\"c\"", "<child link=\"a\""))), "t.urdf:", &["closes a cycle"]),
        (arm(J1), "t.urdf:4:1:", &["several root links", "`a`, `c`"]),
        (
            arm(&format!("{J1}{J2}")).replace("<link name=\"c\"/>", "<link name=\"c\"><inertial><mass value=\"-1\"/><inertia ixx=\"1\" ixy=\"0\" ixz=\"0\" iyy=\"1\" iyz=\"0\" izz=\"1\"/></inertial></link>"),
            "t.urdf:4:",
            &["link `c`: the mass -1 is negative"],
        ),
        (
            arm(&format!("{J1}{J2}")).replace("<link name=\"c\"/>", "<link name=\"c\"><inertial><mass value=\"1\"/></inertial></link>"),
            "t.urdf:4:",
            &["has no `<inertia"],
        ),
        // a negative moment, and products of inertia too large for the moments
        (
            arm(&format!("{J1}{J2}")).replace("<link name=\"c\"/>", "<link name=\"c\"><inertial><mass value=\"1\"/><inertia ixx=\"-5\" ixy=\"0\" ixz=\"0\" iyy=\"1\" iyz=\"0\" izz=\"1\"/></inertial></link>"),
            "t.urdf:4:",
            &["link `c`: the inertia about the centre of mass is not positive semidefinite", "-5.0000e0", "signs of the products"],
        ),
        (
            arm(&format!("{J1}{J2}")).replace("<link name=\"c\"/>", "<link name=\"c\"><inertial><mass value=\"1\"/><inertia ixx=\"1\" ixy=\"2\" ixz=\"0\" iyy=\"1\" iyz=\"0\" izz=\"1\"/></inertial></link>"),
            "t.urdf:4:",
            &["not positive semidefinite", "-1.0000e0"],
        ),
        (arm(&format!("{J1}{}", J2.replace("</joint>", "<mimic joint=\"j1\"/></joint>"))), "t.urdf:6:", &["joint `j2` of the chain mimics joint `j1`"]),
        (arm(&format!("{J1}{}", J2.replace("revolute", "floating"))), "t.urdf:6:1:", &["joint `j2` is floating"]),
        (arm(&format!("{J1}{}", J2.replace("</joint>", "<limit effort=\"-1\" velocity=\"1\"/></joint>"))), "t.urdf:6:", &["`<limit>` of joint `j2`: effort -1 is not a positive number up to 1e7"]),
        (arm(&format!("{J1}{}", J2.replace("<origin xyz=\"0.5 0 0\"/>", "<origin xyz=\"0.5 0 0\" rpy=\"90 0 0\"/>"))), "t.urdf:6:", &["`rpy=\"90 0 0\"` of `<joint name=\"j2\">` has the angle `90`, more than a turn", "1.5707963267948966 for 90 degrees"]),
        (arm(&format!("{J1}{}", J2.replace("</joint>", "<limit lower=\"1\" upper=\"-1\"/></joint>"))), "t.urdf:6:", &["lower 1 is above upper -1", "PyBullet reads lower > upper as no limit", "leave `lower` and `upper` out"]),
        (arm(&format!("{J1}{}", J2.replace("</joint>", "<limit lower=\"-2000\" upper=\"2000\"/></joint>"))), "t.urdf:6:", &["go beyond ±1000", "`type=\"continuous\"`"]),
        (arm(&two.replace("revolute", "fixed")), "t.urdf:1:14:", &["the URDF has no revolute, continuous or prismatic joint (its joints are fixed, floating or planar)", "make the joints that move"]),
    ];
    for (text, place, words) in &cases {
        let message = error_of(text, &ChainSelection::default());
        assert!(message.starts_with(place), "{message}\nexpected at {place}");
        for w in *words {
            assert!(message.contains(w), "{message}\nexpected {w:?}");
        }
    }
}

/// The SO-100's first joint: pi/2 written `1.57079` turns its axis 6.3e-6 rad off the
/// horizontal, so gravity in frame 0 has a component of 6.2e-5 m/s^2: taken as 0 and told
/// at the joint, with the element and the fix (it was an error).
#[test]
fn a_right_angle_printed_short_on_the_first_axis_levels_gravity() {
    let two = format!("{J1}{J2}");
    let text = arm(&two.replace(
        "<axis xyz=\"0 0 1\"/></joint>\n<joint name=\"j2\"",
        "<origin rpy=\"1.57079 0 0\"/><axis xyz=\"0 1 0\"/></joint>\n<joint name=\"j2\"",
    ));
    let chain = Robot::from_urdf(&text, "t.urdf", &ChainSelection::default()).unwrap();
    let told = one_warning(&chain, "gravity in robid frame 0");
    for w in [
        "t.urdf:5:1: gravity in robid frame 0, whose z is joint `j1`'s axis, has",
        "6.2",
        "e-5 m/s^2 below 0.001 m/s^2: taken as 0",
        "the `<origin>` rotation of joint `j1` is 6.3e-6 rad from a right angle",
        "`1.5708`",
    ] {
        assert!(told.contains(w), "{}\nexpected {w:?}", told);
    }
    let g: Vec<&str> = chain.robot.gravity().iter().map(|g| g.as_str()).collect();
    assert_eq!(g.iter().filter(|g| **g == "0").count(), 2, "{g:?}");
}

/// A value read from the URDF is shown short in the message, as the rest of robid writes
/// numbers: a subnormal limit or mass is `1e-320`, not a decimal of 320 digits.
#[test]
fn values_read_are_shown_short() {
    let limit = |attributes: &str| {
        arm(&format!(
            "{J1}{}",
            J2.replace("</joint>", &format!("<limit {attributes}/></joint>"))
        ))
    };
    let cases = [
        (
            limit("lower=\"-1e-320\" upper=\"-2e-320\""),
            "`<limit>` of joint `j2`: lower -1e-320 is above upper -2e-320; ",
        ),
        (
            limit("lower=\"-999999999.5\" upper=\"1\""),
            "`<limit>` of joint `j2`: positions [-9.999999995e8, 1] go beyond ±1000; ",
        ),
        (
            limit("effort=\"1\" velocity=\"-1e-320\""),
            "`<limit>` of joint `j2`: velocity -1e-320 is not a positive number up to 10000; ",
        ),
        (
            arm(&format!("{J1}{J2}")).replace(
                "<link name=\"c\"/>",
                "<link name=\"c\"><inertial><mass value=\"-1e-320\"/><inertia ixx=\"1\" ixy=\"0\" ixz=\"0\" iyy=\"1\" iyz=\"0\" izz=\"1\"/></inertial></link>",
            ),
            "the mass -1e-320 is negative; ",
        ),
    ];
    for (text, expected) in &cases {
        let message = error_of(text, &ChainSelection::default());
        assert!(
            message.contains(expected),
            "{message}\nexpected {expected:?}"
        );
        assert!(message.len() < 400, "{message}");
    }
}

/// Only a huge position limit is told to use a continuous joint; a huge effort is told
/// its unit (it was told "masses in kg").
#[test]
fn huge_limits_get_the_fix_of_their_kind() {
    let effort = arm(&format!(
        "{J1}{}",
        J2.replace(
            "</joint>",
            "<limit effort=\"1e16\" velocity=\"1\"/></joint>"
        )
    ));
    let message = error_of(&effort, &ChainSelection::default());
    assert!(message.contains("`1e16` is beyond"), "{message}");
    assert!(message.contains("effort limit in N m"), "{message}");
    assert!(!message.contains("continuous"), "{message}");
}

/// An effort or velocity above the largest robid takes is a placeholder for no limit
/// (10 of the 13 iCub models write `velocity="50000"`): read as none, with one warning
/// at the first naming the joint; the file was refused.
#[test]
fn placeholder_rate_limits_are_no_limits() {
    let text = arm(&format!(
        "{}{}",
        J1.replace(
            "</joint>",
            "<limit lower=\"-1\" upper=\"1\" effort=\"20\" velocity=\"50000\"/></joint>"
        ),
        J2.replace(
            "</joint>",
            "<limit lower=\"-1\" upper=\"1\" effort=\"1e8\" velocity=\"2\"/></joint>"
        )
    ));
    let chain = Robot::from_urdf(&text, "t.urdf", &ChainSelection::default()).unwrap();
    let limits: Vec<_> = chain
        .robot
        .joints
        .iter()
        .map(|j| j.limits.clone())
        .collect();
    assert_eq!(
        (limits[0].velocity, limits[0].torque),
        (None, Some(20.0)),
        "{limits:?}"
    );
    assert_eq!(
        (limits[1].velocity, limits[1].torque),
        (Some(2.0), None),
        "{limits:?}"
    );
    assert_eq!(chain.warnings.len(), 1, "{:?}", chain.warnings);
    let w = chain
        .warnings
        .iter()
        .find(|w| w.contains("taken as no limit"));
    assert!(
        w.is_some_and(|w| w.starts_with("t.urdf:5:")
            && w.contains("`velocity=\"50000\"` of joint `j1` (and 1 more such value)")),
        "{:?}",
        chain.warnings
    );
}

/// A revolute joint's limits in degrees (`lower="-360"`) are warned about at its
/// `<limit>`; `excite` designed within them. So is an origin in millimetres.
#[test]
fn revolute_limits_in_degrees_are_warned_about() {
    let text = arm(&format!(
        "{J1}{}",
        J2.replace(
            "</joint>",
            "<limit lower=\"-360\" upper=\"360\" effort=\"1\" velocity=\"1\"/></joint>"
        )
    ));
    let chain = Robot::from_urdf(&text, "t.urdf", &ChainSelection::default()).unwrap();
    let mm = text.replace("<origin xyz=\"0.5 0 0\"/>", "<origin xyz=\"500 0 0\"/>");
    let long = Robot::from_urdf(&mm, "t.urdf", &ChainSelection::default()).unwrap();
    let w = long.warnings.iter().find(|w| w.contains("in millimetres?"));
    assert!(
        w.is_some_and(
            |w| w.starts_with("t.urdf:6:") && w.contains("joint `j2`'s origin is at `500 0 0` m")
        ),
        "{:?}",
        long.warnings
    );
    let w = chain.warnings.iter().find(|w| w.contains("in degrees?"));
    assert!(
        w.is_some_and(|w| w.starts_with("t.urdf:6:")
            && w.contains("joint `j2`'s limits [-360, 360] reach beyond 7.86 rad")),
        "{:?}",
        chain.warnings
    );
}

#[test]
fn duplicate_links_and_mimics_of_chain_joints_off_the_chain() {
    let text = arm(&format!("{J1}{J2}")).replace(
        "<link name=\"c\"/>",
        "<link name=\"c\"/>\n<link name=\"a\"/>",
    );
    let message = error_of(&text, &ChainSelection::default());
    assert!(
        message.starts_with("t.urdf:5:1: a second link is named `a` (the first is on line 2)"),
        "{message}"
    );
    let side = "<link name=\"d\"/><joint name=\"s\" type=\"revolute\"><parent link=\"b\"/><child link=\"d\"/><mimic joint=\"j2\"/></joint>\n";
    let text = arm(&format!("{J1}{J2}{side}"));
    let message = error_of(&text, &selection(None, Some("c")));
    assert!(
        message.contains("joint `s` mimics joint `j2` of the chain"),
        "{message}"
    );
}

/// A robot attached to the world by a floating or planar joint is not taken as fixed-base
/// without a word: the error names the joint at its line and both fixes. A base chosen
/// below the joint is the user's statement that it stands still; a floating joint beside
/// the chain (an object in the world) does not carry it.
#[test]
fn a_floating_or_planar_support_is_refused() {
    let world = |kind: &str| {
        arm(&format!(
            "<joint name=\"mount\" type=\"{kind}\"><parent link=\"world\"/><child link=\"a\"/></joint>\n{J1}{J2}"
        ))
        .replace("<link name=\"a\"/>", "<link name=\"world\"/>\n<link name=\"a\"/>")
    };
    for kind in ["floating", "planar"] {
        let text = world(kind);
        let message = error_of(&text, &ChainSelection::default());
        assert!(
            message.starts_with(&format!(
                "t.urdf:6:1: joint `mount` is {kind}: the chain hangs from link `a`"
            )),
            "{message}"
        );
        for w in [
            "robid models a fixed base",
            "make the joint `type=\"fixed\"`",
            "`--base a`",
        ] {
            assert!(message.contains(w), "{message}\nexpected {w:?}");
        }
        // also with the world chosen as the base explicitly
        assert_eq!(error_of(&text, &selection(Some("world"), None)), message);
        // the link below it chosen as the base: the chain of a fixed `a`
        let chain = Robot::from_urdf(&text, "t.urdf", &selection(Some("a"), None)).unwrap();
        assert_eq!(chain.robot.dof(), 2);
        // fixed: the same chain
        let fixed = world("fixed");
        let chain = Robot::from_urdf(&fixed, "t.urdf", &ChainSelection::default()).unwrap();
        assert_eq!(chain.robot.dof(), 2);
        // an object floating beside the chain does not carry it
        let beside = fixed.replace(
            "</robot>",
            &format!("<link name=\"box\"/><joint name=\"loose\" type=\"{kind}\"><parent link=\"world\"/><child link=\"box\"/></joint>\n</robot>"),
        );
        let chain = Robot::from_urdf(&beside, "t.urdf", &selection(None, Some("c"))).unwrap();
        assert_eq!(chain.robot.dof(), 2);
    }
}

#[test]
fn bad_selections_name_the_nearest_links() {
    let text = arm(&format!("{J1}{J2}"));
    let message = error_of(&text, &selection(Some("bb"), None));
    assert!(
        message.starts_with(
            "the chain's base link (`ChainSelection::base`): the URDF has no link `bb`"
        ),
        "{message}"
    );
    assert!(
        message.contains("the nearest link names are `b`"),
        "{message}"
    );
    let message = error_of(&text, &selection(Some("b"), Some("a")));
    assert!(
        message.contains("link `a` is not below the base link `b`"),
        "{message}"
    );
    // nothing movable between the two links chosen: the pair is named, not the tip alone
    let fixed_tip = text.replace(
        "</robot>",
        "<link name=\"tcp\"/><joint name=\"flange\" type=\"fixed\"><parent link=\"c\"/><child link=\"tcp\"/></joint>\n</robot>",
    );
    assert_eq!(
        error_of(&fixed_tip, &selection(Some("c"), Some("tcp"))),
        "the chain's base and tip links (`ChainSelection::base` and `ChainSelection::tip`): no \
         movable (revolute, continuous or prismatic) joint lies between the base link `c` and \
         the tip link `tcp`; choose a base and a tip below it with the joints to model between \
         them (the base may be the root link `a`, the default)"
    );
    // a tip alone is the tip's fault (the base is the root)
    let message = error_of(&text, &selection(None, Some("a")));
    assert!(
        message.starts_with("the chain's tip link (`ChainSelection::tip`): no movable joint lies between links `a` and `a`"),
        "{message}"
    );
}

#[test]
fn odd_robot_names_become_identifiers_with_a_warning() {
    let two = format!("{J1}{J2}");
    for (name, expected, warned) in [
        ("kuka-lwr", "kuka_lwr", false),
        ("self", "self_robot", true),
        ("2dof", "robot_2dof", true),
    ] {
        let text = arm(&two).replace("name=\"arm\"", &format!("name=\"{name}\""));
        let chain = Robot::from_urdf(&text, "t.urdf", &ChainSelection::default()).unwrap();
        assert_eq!(chain.robot.name(), expected);
        assert_eq!(
            chain
                .warnings
                .iter()
                .any(|w| w.starts_with("t.urdf:1:14: the robot name")),
            warned,
            "{:?}",
            chain.warnings
        );
    }
}

#[test]
fn files_are_read_or_named_in_the_error() {
    let chain = Robot::from_urdf_file(
        std::path::Path::new(&format!("{}/../{UR5}", env!("CARGO_MANIFEST_DIR"))),
        &ChainSelection::default(),
    )
    .unwrap();
    assert_eq!(chain.robot.dof(), 6);
    let e = Robot::from_urdf_file(
        std::path::Path::new("no/such.urdf"),
        &ChainSelection::default(),
    )
    .unwrap_err()
    .to_string();
    assert!(e.starts_with("no/such.urdf: cannot read the file"), "{e}");
}

#[test]
fn truncated_and_garbled_files_are_errors_not_panics() {
    let text = repository_file(PANDA);
    let chosen = selection(None, Some("panda_hand"));
    for cut in (0..text.len()).step_by(41) {
        if text.is_char_boundary(cut) {
            let _ = Robot::from_urdf(&text[..cut], "t.urdf", &chosen);
        }
    }
    let mut rng = robid_core::rng::Rng::new(11);
    let noise = ['<', '>', '"', '=', '/', ' ', '0', 'x', '-', '.', 'e', '9'];
    let mut errors = 0;
    for _ in 0..400 {
        let mut bytes = text.clone().into_bytes();
        for _ in 0..3 {
            let at = rng.below(bytes.len());
            bytes[at] = noise[rng.below(noise.len())] as u8;
        }
        let Ok(garbled) = String::from_utf8(bytes) else {
            continue;
        };
        if let Err(e) = Robot::from_urdf(&garbled, "t.urdf", &chosen) {
            errors += 1;
            assert!(!e.to_string().contains("NaN"), "{e}");
        }
    }
    // measured 352 of the 400 (seeded)
    assert!(errors > 176, "{errors}");
}

/// Elements nested deeper than MAX_URDF_DEPTH are refused at the first too deep (149 000
/// nested took 22 s, every element's ancestors walked); the deepest allowed is read.
#[test]
fn elements_nested_too_deep_are_refused_at_the_first() {
    use crate::robot::bounds::MAX_URDF_DEPTH;
    let chosen = selection(None, None);
    let nested = |depth: usize| {
        // <robot> is depth 1, the nest depth 2 to depth
        let inner = depth - 1;
        let mut text = arm(&format!("{J1}{J2}"));
        let nest = format!("{}{}\n", "<g>".repeat(inner), "</g>".repeat(inner));
        text = text.replace("</robot>", &format!("{nest}</robot>"));
        text
    };
    assert!(Robot::from_urdf(&nested(MAX_URDF_DEPTH), "t.urdf", &chosen).is_ok());
    let e = error_of(&nested(MAX_URDF_DEPTH + 1), &chosen);
    let column = 3 * (MAX_URDF_DEPTH - 1) + 1;
    assert!(
        e.starts_with(&format!("t.urdf:7:{column}: `<g>` is nested more than 64")),
        "{e}"
    );
    let e = error_of(&nested(149_000), &chosen);
    assert!(e.contains("nested more than"), "{e}");
}

/// A repeated element of a link, an inertial or a joint is warned about at the second
/// one, and the first is used, as URDF parsers do (a second `<inertial>` or `<axis>`
/// used to be dropped without a word).
#[test]
fn repeated_elements_are_warned_about_and_the_first_used() {
    let inertial = "<inertial><mass value=\"1\"/><inertia ixx=\"1\" ixy=\"0\" ixz=\"0\" iyy=\"1\" iyz=\"0\" izz=\"1\"/></inertial>";
    let two = format!("{J1}{J2}");
    for (text, tag, place) in [
        (
            arm(&two).replace(
                "<link name=\"c\"/>",
                &format!("<link name=\"c\">{inertial}{inertial}</link>"),
            ),
            "`<link name=\"c\">` has 2 `<inertial>` elements",
            "t.urdf:4:",
        ),
        (
            arm(&two).replace(
                "<link name=\"c\"/>",
                &format!(
                    "<link name=\"c\">{}</link>",
                    inertial.replace("<inertia ", "<mass value=\"5\"/><inertia ")
                ),
            ),
            "`<inertial>` has 2 `<mass>` elements",
            "t.urdf:4:",
        ),
        (
            arm(&format!(
                "{J1}{}",
                J2.replace("</joint>", "<axis xyz=\"1 0 0\"/></joint>")
            )),
            "`<joint name=\"j2\">` has 2 `<axis>` elements",
            "t.urdf:6:",
        ),
    ] {
        let chain = Robot::from_urdf(&text, "t.urdf", &ChainSelection::default()).unwrap();
        let w = chain.warnings.iter().find(|w| w.contains(tag));
        assert!(
            w.is_some_and(|w| w.starts_with(place) && w.contains("the first is used")),
            "{:?}",
            chain.warnings
        );
    }
}

/// A `<robot>` that xacro left empty and nameless is told both mistakes (it was told only
/// the missing name).
#[test]
fn an_empty_nameless_robot_is_told_it_has_no_links() {
    let message = error_of("<robot>\n</robot>\n", &ChainSelection::default());
    assert!(
        message.contains("has no `name` attribute") && message.contains("has no `<link>`"),
        "{message}"
    );
}

/// Undeclared namespace prefixes other than xacro's (Drake's `drake:` extensions in
/// airo-models' UR files) made the whole file unreadable ("not well-formed XML: an
/// unknown namespace prefix"); their elements and attributes are ignored, with a warning
/// at the first, and the robot is the one without them. Places after them are kept.
#[test]
fn undeclared_extension_prefixes_are_ignored_with_a_warning() {
    let two = format!("{J1}{J2}");
    let plain = Robot::from_urdf(&arm(&two), "t.urdf", &ChainSelection::default()).unwrap();
    let extended = arm(&two.replace(
        "<axis xyz=\"0 0 1\"/></joint>\n<joint name=\"j2\"",
        "<axis xyz=\"0 0 1\"/><limit drake:acceleration=\"2.5\" gz:x='1'/></joint>\n\
         <drake:collision_filter_group name=\"g\"><drake:member link=\"a\"/>\
         </drake:collision_filter_group>\n<joint name=\"j2\"",
    ));
    assert!(extended.contains("drake:member") && extended.contains("gz:x"));
    let chain = Robot::from_urdf(&extended, "t.urdf", &ChainSelection::default()).unwrap();
    assert_eq!(chain.robot, plain.robot);
    let w = chain
        .warnings
        .iter()
        .find(|w| w.contains("namespace prefix"));
    assert!(
        w.is_some_and(|w| w.starts_with("t.urdf:5:")
            && w.contains("`drake:` (and 1 more prefixes)")
            && w.contains("ignored")),
        "{:?}",
        chain.warnings
    );
    // a mistake after them is still named at its own line
    let broken = extended.replace("<origin xyz=\"0.5 0 0\"/>", "<origin xyz=\"0.5 x 0\"/>");
    let message = error_of(&broken, &ChainSelection::default());
    assert!(message.starts_with("t.urdf:7:"), "{message}");
}

/// An impossible inertial (here TIAGo's antenna: products of inertia too large for its
/// moments) on a link the model does not use, fixed to the base, is warned about once,
/// naming the link; the file is read. The same inertial on a link of a body (fixed to a
/// moving link) is an error naming the link, as is a negative mass.
#[test]
fn impossible_inertials_are_errors_only_on_the_chains_bodies() {
    let antenna = r#"<robot name="b03">
  <link name="base"/>
  <link name="antenna"><inertial><mass value="0.000001"/>
    <inertia ixx="0.00000002371" ixy="0.00000006119" ixz="0.00000001179" iyy="0.00000002833" iyz="0.00000000774" izz="0.00000003849"/></inertial></link>
  <joint name="antenna_joint" type="fixed"><parent link="base"/><child link="antenna"/><origin xyz="-0.2 0.1 0.2"/></joint>
  <link name="l1"><inertial><origin xyz="0.1 0 0"/><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <joint name="j1" type="revolute">
    <parent link="base"/><child link="l1"/><origin xyz="0 0 0.3" rpy="1.5707963267948966 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-2" upper="2" effort="10" velocity="2"/>
  </joint>
</robot>"#;
    let chain = Robot::from_urdf(antenna, "t.urdf", &ChainSelection::default())
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(chain.robot.dof(), 1);
    assert_eq!(chain.links[0].inertial[9], 1.0);
    let warned: Vec<&String> = chain
        .warnings
        .iter()
        .filter(|w| w.contains("not positive semidefinite"))
        .collect();
    assert_eq!(warned.len(), 1, "{:?}", chain.warnings);
    for w in [
        "t.urdf:4:5: link `antenna`: the inertia about the centre of mass",
        "the model does not use its inertial",
    ] {
        assert!(warned[0].contains(w), "{}\nexpected {w:?}", warned[0]);
    }
    // a second one, with a negative mass, is counted in the same warning
    let two = antenna.replace(
        "</robot>",
        "<link name=\"antenna2\"><inertial><mass value=\"-1\"/><inertia ixx=\"1\" ixy=\"0\" ixz=\"0\" iyy=\"1\" iyz=\"0\" izz=\"1\"/></inertial></link>\n<joint name=\"a2\" type=\"fixed\"><parent link=\"base\"/><child link=\"antenna2\"/></joint>\n</robot>",
    );
    let chain = Robot::from_urdf(&two, "t.urdf", &ChainSelection::default()).unwrap();
    assert!(
        chain
            .warnings
            .iter()
            .any(|w| w.contains("(link `antenna2` has an impossible inertial too, also unused)")),
        "{:?}",
        chain.warnings
    );
    // fixed to the moving link l1: part of its body, so an error at the link
    let on_body = antenna.replace(
        "<parent link=\"base\"/><child link=\"antenna\"/>",
        "<parent link=\"l1\"/><child link=\"antenna\"/>",
    );
    let message = error_of(&on_body, &ChainSelection::default());
    assert!(
        message.starts_with("t.urdf:4:5: link `antenna`: the inertia about the centre of mass is not positive semidefinite"),
        "{message}"
    );
    let message = error_of(
        &two.replace(
            "<parent link=\"base\"/><child link=\"antenna2\"/>",
            "<parent link=\"l1\"/><child link=\"antenna2\"/>",
        ),
        &ChainSelection::default(),
    );
    assert!(
        message.contains("link `antenna2`: the mass -1 is negative"),
        "{message}"
    );
}

/// When no tip is given, a chain-selection error says what is wrong with the file or the
/// base, not with a tip: a URDF without movable joints is the file's error; a base with no
/// movable joint below it is the base's. A tree's candidate tips are the leaves below a
/// movable joint, not a sensor fixed to the base.
#[test]
fn chain_errors_without_a_tip_name_what_is_wrong() {
    let fixed = r#"<robot name="mini">
  <link name="base"/>
  <link name="l1"/>
  <link name="l2"/>
  <joint name="j1" type="fixed"><parent link="base"/><child link="l1"/><origin xyz="0 0 0.3"/></joint>
  <joint name="j2" type="fixed"><parent link="l1"/><child link="l2"/><origin xyz="0.4 0 0"/></joint>
</robot>"#;
    let message = error_of(fixed, &ChainSelection::default());
    assert!(
        message.starts_with(
            "t.urdf:1:14: the URDF has no revolute, continuous or prismatic joint (its joints are fixed, floating or planar), so it has no chain to model; "
        ),
        "{message}"
    );
    assert!(!message.contains("tip"), "{message}");
    let lone = "<robot name=\"one\"><link name=\"base\"/></robot>";
    let message = error_of(lone, &ChainSelection::default());
    assert!(message.contains("(it has no joint)"), "{message}");
    // a ROS-Industrial `base` frame, fixed below `base_link`, chosen as the base
    let text = arm(&format!("{J1}{J2}")).replace(
        "</robot>",
        "<link name=\"base\"/><joint name=\"frame\" type=\"fixed\"><parent link=\"a\"/><child link=\"base\"/></joint>\n</robot>",
    );
    let message = error_of(&text, &selection(Some("base"), None));
    assert_eq!(
        message,
        "the chain's base link (`ChainSelection::base`): no movable (revolute, continuous or \
         prismatic) joint lies below link `base`; choose a base above the joints to model, such \
         as the root link `a` (the default)"
    );
    // two branches and a sensor fixed to the base: the sensor is no candidate tip
    let tree = text.replace(
        "</robot>",
        "<link name=\"d\"/><joint name=\"side\" type=\"revolute\"><parent link=\"b\"/><child link=\"d\"/><axis xyz=\"0 1 0\"/></joint>\n\
         <link name=\"e\"/><joint name=\"tcp\" type=\"fixed\"><parent link=\"c\"/><child link=\"e\"/></joint>\n</robot>",
    );
    let message = error_of(&tree, &ChainSelection::default());
    assert_eq!(
        message,
        "the chain's tip link (`ChainSelection::tip`): the movable joints below link `a` do not \
         form a single path, so the chain's tip must be chosen; choose the tip among `e`, `d`, \
         or `b`, where the chain branches (the joints below it are held)"
    );
}

/// A gripper of mimic joints (as xArm's): every leaf's chain holds a mimic joint, so the
/// leaves alone were suggested, each refused when chosen; the link where the chain
/// branches, which works, was never named. It is now, and the leaves are named with why.
#[test]
fn a_gripper_of_mimic_joints_suggests_the_link_above_it() {
    let joint = |name: &str, parent: &str, child: &str, mimic: &str| {
        format!(
            "<link name=\"{child}\"/><joint name=\"{name}\" type=\"revolute\"><parent \
             link=\"{parent}\"/><child link=\"{child}\"/><origin xyz=\"0.1 0 0\"/><axis \
             xyz=\"0 0 1\"/><limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"/>{mimic}</joint>\n"
        )
    };
    let gripper = format!(
        "<link name=\"g\"/><joint name=\"fix\" type=\"fixed\"><parent link=\"c\"/><child \
         link=\"g\"/></joint>\n{}{}{}",
        joint("drive", "g", "l1", ""),
        joint("l2j", "l1", "l2", "<mimic joint=\"drive\"/>"),
        joint("r1j", "g", "r1", "<mimic joint=\"drive\"/>")
    );
    let text = arm(&format!("{J1}{J2}{gripper}"));
    let message = error_of(&text, &ChainSelection::default());
    assert!(
        message.contains("choose the tip `c`, where the chain branches"),
        "{message}"
    );
    assert!(
        message.contains(
            "not the leaves `l2`, `r1`: with `l2` as the tip, joint `l2j` of the chain mimics \
             joint `drive` (robid models independent joints)"
        ),
        "{message}"
    );
    // the suggestion works
    let chain = Robot::from_urdf(&text, "t.urdf", &selection(None, Some("c"))).unwrap();
    assert_eq!(chain.robot.dof(), 2);
}

/// A `<mimic>` naming no joint is told at its place with the nearest joint names: off the
/// chain in a warning, the joint held at its `offset` (it was accepted without a word,
/// then refused, which refused Alex's URDF of example-robot-data for a hand's typo whatever
/// the chain); on the chain it is an error that says so.
#[test]
fn a_mimic_of_no_joint_is_named_at_its_place() {
    let off = r#"<robot name="b07">
  <link name="base"/>
  <link name="hand"/>
  <joint name="j1" type="revolute">
    <parent link="base"/><child link="hand"/><origin xyz="0 0 0.3"/><axis xyz="0 0 1"/>
  </joint>
  <link name="finger1"/>
  <link name="finger2"/>
  <joint name="finger_joint" type="revolute">
    <parent link="hand"/><child link="finger1"/><origin xyz="0.1 0.02 0"/><axis xyz="0 0 1"/>
  </joint>
  <joint name="f2" type="revolute">
    <parent link="hand"/><child link="finger2"/><origin xyz="0.1 -0.02 0"/><axis xyz="0 0 1"/>
    <mimic joint="finger_joint_that_does_not_exist"/>
  </joint>
</robot>"#;
    let chain = Robot::from_urdf(off, "t.urdf", &selection(None, Some("hand"))).unwrap();
    let told = one_warning(&chain, "mimics");
    assert!(
        told.starts_with(
            "t.urdf:14:19: joint `f2` mimics joint `finger_joint_that_does_not_exist`, which is \
             no `<joint>` of the robot: off the chain it is held at its `offset`"
        ) && told.ends_with("the nearest joint names are `finger_joint`, `f2`, `j1`"),
        "{}",
        told
    );
    let on = arm(&format!(
        "{J1}{}",
        J2.replace("</joint>", "<mimic joint=\"nope\"/></joint>")
    ));
    let message = error_of(&on, &ChainSelection::default());
    assert!(
        message.starts_with("t.urdf:6:")
            && message
                .contains("joint `j2` of the chain mimics joint `nope`, which is no `<joint>`"),
        "{message}"
    );
}

/// A `<!DOCTYPE>` is well-formed XML: the error says that robid does not read DTDs and to
/// remove it (it used to say "not well-formed XML ... every tag closed"). An unexpanded
/// xacro file is told to be expanded with xacro first, whether its `xacro:` prefix is
/// declared or not; the `xmlns:xacro` declaration that xacro leaves in its output is fine.
#[test]
fn doctypes_and_xacro_files_are_told_what_to_do() {
    let two = arm(&format!("{J1}{J2}"));
    let doctype = format!("<?xml version=\"1.0\"?>\n<!DOCTYPE robot>\n{two}");
    let message = error_of(&doctype, &ChainSelection::default());
    assert!(
        message.starts_with(
            "t.urdf:2:1: the URDF has a document type declaration (`<!DOCTYPE ...>`), and robid \
             does not read DTDs"
        ),
        "{message}"
    );
    assert!(message.contains("remove the `<!DOCTYPE ...>`"), "{message}");
    assert!(!message.contains("well-formed"), "{message}");
    let entities = format!(
        "<!DOCTYPE robot [<!ENTITY a \"&b;&b;\"><!ENTITY b \"xx\">]>\n{}",
        two.replace("0.5 0 0", "&a; 0 0")
    );
    let message = error_of(&entities, &ChainSelection::default());
    assert!(
        message.starts_with("t.urdf:1:1: the URDF has a document type"),
        "{message}"
    );
    let expand = "expand it with xacro first";
    // an undeclared prefix: not well-formed XML, but the help says what the file is
    let undeclared = two.replace(
        "</robot>",
        "<xacro:property name=\"a\" value=\"1\"/>\n</robot>",
    );
    let message = error_of(&undeclared, &ChainSelection::default());
    assert!(
        message.starts_with(
            "t.urdf:7:2: the URDF is not well-formed XML: an unknown namespace prefix 'xacro'"
        ) && message.contains(expand),
        "{message}"
    );
    let declared = undeclared.replace(
        "<robot name=\"arm\">",
        "<robot name=\"arm\" xmlns:xacro=\"http://www.ros.org/wiki/xacro\">",
    );
    let message = error_of(&declared, &ChainSelection::default());
    assert_eq!(
        message,
        format!(
            "t.urdf:7:1: the URDF is an unexpanded xacro file (`<xacro:property>`); {expand} \
             (`xacro robot.urdf.xacro > robot.urdf`) and give robid the URDF it writes"
        )
    );
    let expression = two.replace("0.5 0 0", "${l} 0 0");
    let message = error_of(&expression, &ChainSelection::default());
    assert!(
        message.starts_with("t.urdf:6:")
            && message.contains("an unexpanded xacro file (`xyz=\"${l} 0 0\"`)")
            && message.contains(expand),
        "{message}"
    );
    // xacro's output keeps the declaration
    let expanded = two.replace(
        "<robot name=\"arm\">",
        "<robot name=\"arm\" xmlns:xacro=\"http://wiki.ros.org/xacro\">",
    );
    let chain = Robot::from_urdf(&expanded, "t.urdf", &ChainSelection::default()).unwrap();
    assert_eq!(chain.robot.dof(), 2);
    // xacro text in a comment (xarm7's URDF keeps a `${prefix}` link commented out) does
    // not make an ordinary XML mistake a xacro file; outside the comment it still does
    let commented = two.replace(
        "</robot>",
        "<!-- <link name=\"${prefix}eef\"/> <xacro:x/> -->\n</robot>",
    );
    let typo = commented.replacen("<link ", "<link name=\"x\" ", 1);
    let message = error_of(&typo, &ChainSelection::default());
    assert!(
        message.contains("not well-formed XML") && !message.contains(expand),
        "{message}"
    );
    let message = error_of(&format!("{typo}${{l}}"), &ChainSelection::default());
    assert!(message.contains(expand), "{message}");
}

/// An inertial that is possible as a tensor but no body's, on a link of the chain's bodies,
/// is read with one warning per kind naming the link, its values and the fix, and listed in
/// `UrdfChain::unphysical` (they used to be accepted without a word): principal moments
/// that break the triangle inequality (the eavr SCARA's placeholder 1, 100, 1), and a zero
/// mass with a nonzero inertia. Moments that sit on the bound (a flat plate) printed
/// rounded, a point mass (a mass without inertia), a massless link, and such an inertial
/// on a link the model does not use are not warned about.
#[test]
fn inertials_of_no_body_are_warned_about_on_the_chains_bodies() {
    let with = |b: &str, c: &str| {
        let inertial =
            |m: &str, i: &str| format!("<inertial><mass value=\"{m}\"/><inertia {i}/></inertial>");
        let tensor = |xx: &str, xy: &str, yy: &str, zz: &str| {
            format!("ixx=\"{xx}\" ixy=\"{xy}\" ixz=\"0\" iyy=\"{yy}\" iyz=\"0\" izz=\"{zz}\"")
        };
        let link = |spec: &str| match spec {
            "triangle" => inertial("1", &tensor("1", "0", "100", "1")),
            // the same moments 1, 1, 100 about axes turned 45 degrees about z
            "turned" => inertial("1", &tensor("50.5", "49.5", "50.5", "1")),
            "massless inertia" => inertial("0", &tensor("0.01", "0", "0.01", "0.01")),
            // a flat plate: izz = ixx + iyy (0.3580245), printed to seven digits
            "plate" => inertial("2", &tensor("0.1234567", "0", "0.2345678", "0.3580246")),
            "point" => inertial("2", &tensor("0", "0", "0", "0")),
            "none" => inertial("0", &tensor("0", "0", "0", "0")),
            _ => inertial("1", &tensor("0.02", "0", "0.03", "0.04")),
        };
        // with limits: a joint without is warned about too
        let limit = "<limit effort=\"1\" velocity=\"1\"/></joint>";
        arm(&format!("{J1}{J2}").replace("</joint>", limit))
            .replace(
                "<link name=\"b\"/>",
                &format!("<link name=\"b\">{}</link>", link(b)),
            )
            .replace(
                "<link name=\"c\"/>",
                &format!("<link name=\"c\">{}</link>", link(c)),
            )
    };
    let read = |text: &str| {
        Robot::from_urdf(text, "t.urdf", &ChainSelection::default())
            .unwrap_or_else(|e| panic!("{e}\n{text}"))
    };
    let chain = read(&with("solid", "triangle"));
    assert_eq!(chain.warnings.len(), 1, "{:?}", chain.warnings);
    let w = &chain.warnings[0];
    for part in [
        "t.urdf:4:",
        "link `c`: the principal moments 1, 1, 100 kg m^2 of the inertia about the centre of mass break the triangle inequality: the largest exceeds the sum of the other two by 98 kg m^2, so no body has this inertial",
        "(`robid torques`, `excite` and `simulate` without --parameters, the prior of `robid feasible`) it is used as written, and their results are those of the file, not of a robot",
        "correct the `<inertia>`",
        "give parameters of your own",
    ] {
        assert!(w.contains(part), "{w}\nexpected {part:?}");
    }
    assert_eq!(chain.unphysical.len(), 1);
    assert_eq!(chain.unphysical[0].link, "c");
    assert!(chain.unphysical[0].problem.contains("1, 1, 100"));
    // the inertial is used as written: the model reads the file
    assert_eq!(chain.links[1].inertial[9], 1.0);
    let chain = read(&with("turned", "triangle"));
    assert_eq!(chain.warnings.len(), 1, "{:?}", chain.warnings);
    let w = &chain.warnings[0];
    assert!(
        w.starts_with("t.urdf:3:")
            && w.contains("link `b`: the principal moments 1, 1, 100 kg m^2")
            && w.contains("(the moments of `ixx` to `izz` with the products of inertia)")
            && w.contains("(link `c` has such an inertial too)"),
        "{w}"
    );
    assert_eq!(chain.unphysical.len(), 2);
    let chain = read(&with("massless inertia", "solid"));
    assert_eq!(chain.warnings.len(), 1, "{:?}", chain.warnings);
    let w = &chain.warnings[0];
    assert!(
        w.starts_with("t.urdf:3:")
            && w.contains("link `b`: the mass is 0 but the inertia is not (ixx 0.01, ixy 0, ixz 0, iyy 0.01, iyz 0, izz 0.01 kg m^2), so no body has this inertial")
            && w.contains("give the link its mass, or write its inertia as zeros"),
        "{w}"
    );
    assert_eq!(chain.unphysical[0].link, "b");
    for (b, c) in [("plate", "point"), ("none", "solid")] {
        let chain = read(&with(b, c));
        assert!(chain.warnings.is_empty(), "{b}, {c}: {:?}", chain.warnings);
        assert!(chain.unphysical.is_empty());
    }
    // on a link fixed to the base, which the model does not use: nothing to say
    let beside = with("solid", "solid").replace(
        "</robot>",
        "<link name=\"d\"><inertial><mass value=\"1\"/><inertia ixx=\"1\" ixy=\"0\" ixz=\"0\" iyy=\"100\" iyz=\"0\" izz=\"1\"/></inertial></link>\n\
         <joint name=\"sensor\" type=\"fixed\"><parent link=\"a\"/><child link=\"d\"/></joint>\n</robot>",
    );
    let chain = read(&beside);
    assert!(chain.warnings.is_empty(), "{:?}", chain.warnings);
    assert!(chain.unphysical.is_empty());
}

/// A mass or inertia written as 1e-320, or far below the chain's largest, to mean 0 is
/// judged as 0 (`negligible`: below 1e-12 of the largest of its kind, or subnormal): a
/// mass of 1e-320 kg with an inertia of 0.01 kg m^2 is warned about as a zero mass with an
/// inertia (it used to pass, as only an exact 0 was checked), the body counts as massless
/// (`UrdfChain::massless`), and a body whose every value is 1e-320 as empty
/// (`UrdfChain::empty`). 1e-11 of the largest mass is a mass.
#[test]
fn negligible_masses_and_inertias_count_as_zero() {
    let with = |b: &str, c: &str| {
        let link = |name: &str, (m, i): (&str, &str)| {
            format!(
                "<link name=\"{name}\"><inertial><mass value=\"{m}\"/><inertia ixx=\"{i}\" \
                 ixy=\"0\" ixz=\"0\" iyy=\"{i}\" iyz=\"0\" izz=\"{i}\"/></inertial></link>"
            )
        };
        let limit = "<limit effort=\"1\" velocity=\"1\"/></joint>";
        let spec = |s: &str| match s {
            "denormal mass" => ("1e-320", "0.01"),
            "denormal" => ("1e-320", "1e-320"),
            "tiny mass" => ("1e-13", "0.01"),
            "small mass" => ("1e-11", "0.01"),
            _ => ("1", "0.02"),
        };
        arm(&format!("{J1}{J2}").replace("</joint>", limit))
            .replace("<link name=\"b\"/>", &link("b", spec(b)))
            .replace("<link name=\"c\"/>", &link("c", spec(c)))
    };
    let read = |text: &str| {
        Robot::from_urdf(text, "t.urdf", &ChainSelection::default())
            .unwrap_or_else(|e| panic!("{e}\n{text}"))
    };
    for (c, told) in [
        ("denormal mass", "the mass 1e-320 kg is negligible"),
        ("tiny mass", "the mass 1e-13 kg is negligible"),
    ] {
        let chain = read(&with("solid", c));
        assert_eq!(chain.warnings.len(), 1, "{c}: {:?}", chain.warnings);
        let w = &chain.warnings[0];
        assert!(
            w.starts_with("t.urdf:4:")
                && w.contains(&format!("link `c`: {told} (below 1e-12 of the chain's largest, 1 kg, or subnormal), as good as 0, but the inertia is not (ixx 0.01"))
                && w.contains("give the link its mass, or write its inertia as zeros"),
            "{w}"
        );
        assert_eq!(chain.unphysical.len(), 1);
        assert!(!chain.massless(0) && chain.massless(1), "{c}");
        assert!(!chain.empty(1) && !chain.exactly_zero(1, true), "{c}");
    }
    let chain = read(&with("solid", "small mass"));
    assert!(chain.warnings.is_empty(), "{:?}", chain.warnings);
    assert!(!chain.massless(1));
    // every value 1e-320: both bodies are empty, whatever the other's values
    let chain = read(&with("denormal", "denormal"));
    assert!(chain.warnings.is_empty(), "{:?}", chain.warnings);
    assert!(chain.empty(0) && chain.empty(1));
    assert!(!chain.exactly_zero(0, false));
    let chain = read(&with("solid", "denormal"));
    assert!(!chain.empty(0) && chain.empty(1) && chain.massless(1));
}

/// A revolute or prismatic joint without `<limit>` (which urdfdom, and so ROS tools and
/// Pinocchio, refuse) is read without limits and warned about once, at the first, naming
/// the others (it used to be accepted without a word); a continuous joint needs none.
#[test]
fn revolute_and_prismatic_joints_without_limits_are_warned_about() {
    let limit = "<limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"/></joint>";
    let limited = arm(&format!("{J1}{J2}").replace("</joint>", limit));
    let read = |text: &str| {
        Robot::from_urdf(text, "t.urdf", &ChainSelection::default())
            .unwrap_or_else(|e| panic!("{e}"))
    };
    let about_limits = |chain: &UrdfChain| -> Vec<String> {
        chain
            .warnings
            .iter()
            .filter(|w| w.contains("<limit>"))
            .cloned()
            .collect()
    };
    assert!(about_limits(&read(&limited)).is_empty());
    let continuous = arm(&format!("{J1}{}", J2.replace("</joint>", limit)).replace(
        "revolute\"><parent link=\"a\"",
        "continuous\"><parent link=\"a\"",
    ));
    assert!(continuous.contains("continuous"));
    assert!(about_limits(&read(&continuous)).is_empty());
    let chain = read(&arm(&format!("{J1}{}", J2.replace("</joint>", limit))));
    assert_eq!(
        about_limits(&chain),
        [
            "t.urdf:5:1: joint `j1` is revolute but has no `<limit>`: robid reads it without \
          position, velocity or torque limits, but the URDF format requires the element for \
          revolute and prismatic joints, and urdfdom, the parser of ROS tools and Pinocchio, \
          refuses the file; add `<limit lower=\"..\" upper=\"..\" effort=\"..\" \
          velocity=\"..\"/>`, or make a joint that turns without end `type=\"continuous\"`"
        ]
    );
    assert!(chain.robot.joints()[0].limits.position.is_none());
    let chain = read(&arm(&format!(
        "{J1}{}",
        J2.replace("revolute", "prismatic")
    )));
    let warned = about_limits(&chain);
    assert_eq!(warned.len(), 1, "{warned:?}");
    assert!(
        warned[0].starts_with("t.urdf:5:1: joint `j1` is revolute but has no `<limit>`")
            && warned[0].ends_with("(joint `j2` has none either)"),
        "{}",
        warned[0]
    );
    let chain = read(&arm(&format!(
        "{}{J1}",
        J2.replace("revolute", "prismatic")
    )));
    assert!(
        about_limits(&chain)[0]
            .starts_with("t.urdf:5:1: joint `j2` is prismatic but has no `<limit>`"),
        "{:?}",
        chain.warnings
    );
}

/// `effort="0"` or `velocity="0"` on a joint robid can move is read as no torque or velocity
/// limit (URDF's default), but exporters write 0 as a placeholder for a limit they do not
/// know: it is warned about once, at the first such `<limit>`, naming each joint, which of
/// the two it has at 0, what robid takes and the fix (it used to be taken as no limit
/// without a word); a fixed joint's `<limit>` (Kinova's URDF writes zeros there) and
/// nonzero limits are not warned about.
#[test]
fn zero_effort_or_velocity_limits_are_warned_about() {
    let read = read_ok;
    let about = |chain: &UrdfChain| warned(chain, "robid takes 0 as");
    let with = limited;
    let whole = "lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"";
    assert!(about(&read(&with(whole, whole))).is_empty());
    let chain = read(&with(
        whole,
        "lower=\"-1\" upper=\"1\" effort=\"0\" velocity=\"2\"",
    ));
    assert_eq!(
        about(&chain),
        [
            "t.urdf:6:111: the `<limit>` of joint `j2` has `effort=\"0\"`: robid takes 0 as no \
             torque limit (`robid excite` then leaves the torque unbounded), but URDF exporters \
             write 0 where they do not know a limit; if the robot has limits, write the \
             robot's torque limits in the URDF (`effort` in N m or N)"
        ]
    );
    let joint = &chain.robot.joints()[1];
    assert_eq!(
        (joint.limits.torque, joint.limits.velocity),
        (None, Some(2.0))
    );
    // both joints, one message at the first, naming the second and what it has at 0
    let chain = read(&with(
        "lower=\"-1\" upper=\"1\" effort=\"3\" velocity=\"0\"",
        "lower=\"-1\" upper=\"1\" effort=\"0\" velocity=\"0\"",
    ));
    let warned = about(&chain);
    assert_eq!(
        warned,
        [
            "t.urdf:5:88: the `<limit>` of joint `j1` has `velocity=\"0\"` (also: joint `j2` \
             has `effort=\"0\"` and `velocity=\"0\"`): robid takes 0 as no torque limit and \
             no velocity limit (`robid excite` then leaves the torque unbounded and asks for \
             --velocity-limits), but URDF exporters write 0 where they do not know a limit; \
             if the robot has limits, write the robot's limits in the URDF (`effort` in N m \
             or N, `velocity` in rad/s or m/s), or give the velocity limits to `robid \
             excite` as --velocity-limits"
        ]
    );
    assert_eq!(chain.robot.joints()[0].limits.velocity, None);
    // a velocity of 0 alone points to --velocity-limits; a continuous joint is warned too
    let continuous =
        with("effort=\"1\" velocity=\"0\"", whole).replacen("revolute", "continuous", 1);
    let warned = about(&read(&continuous));
    assert!(
        warned.len() == 1
            && warned[0]
                .contains("joint `j1` has `velocity=\"0\"`: robid takes 0 as no velocity limit")
            && warned[0].ends_with("or give them to `robid excite` as --velocity-limits"),
        "{warned:?}"
    );
    // a fixed joint's zeros are not robid's concern
    let fixed = arm(&format!(
        "{}{J1}",
        J2.replace("revolute", "fixed").replace(
            "</joint>",
            "<limit effort=\"0\" lower=\"0\" upper=\"0\" velocity=\"0\"/></joint>"
        )
    ));
    let chain = read(&fixed.replace(
        "</joint>\n</robot>",
        &format!("<limit {whole}/></joint>\n</robot>"),
    ));
    assert!(about(&chain).is_empty(), "{:?}", chain.warnings);
    // robid's own URDF notes that its zeros stand for limits the description lacks
    // (`robid feasible -o x.urdf` warned about its own file): no warning there, the zeros
    // still no limit; another comment does not count
    let zeros = "lower=\"-1\" upper=\"1\" effort=\"0\" velocity=\"0\"";
    for (comment, warns) in [
        (
            format!("<!-- {} -->", robid_core::URDF_NO_LIMIT_NOTE),
            false,
        ),
        ("<!-- limits unknown -->".to_string(), true),
    ] {
        let text = with(whole, zeros).replace(
            &format!("<limit {zeros}/>"),
            &format!("{comment}\n    <limit {zeros}/>"),
        );
        let chain = read(&text);
        assert_eq!(
            !about(&chain).is_empty(),
            warns,
            "{comment}: {:?}",
            chain.warnings
        );
        let joint = &chain.robot.joints()[1];
        assert_eq!((joint.limits.torque, joint.limits.velocity), (None, None));
    }
}

/// `effort="0"` and `velocity="0"` on a joint off the chain robid moves (a gripper's finger
/// that `--tip` leaves out: exporters write zeros there) are not warned about: robid takes
/// no limit of it. The same finger on the chain is. The warning used to name every movable
/// joint of the file, the finger left out included.
#[test]
fn zero_limits_off_the_chain_are_not_warned_about() {
    let limit = "<limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"/>";
    let text = format!(
        "<robot name=\"arm\">\n<link name=\"a\"/>\n<link name=\"b\"/>\n<link name=\"c\"/>\n\
         <link name=\"finger\"/>\n<link name=\"tool\"/>\n{}{}\
         <joint name=\"finger_joint\" type=\"prismatic\"><parent link=\"c\"/><child \
         link=\"finger\"/><axis xyz=\"1 0 0\"/><limit lower=\"0\" upper=\"0.04\" \
         effort=\"0\" velocity=\"0\"/></joint>\n\
         <joint name=\"tool_joint\" type=\"fixed\"><parent link=\"c\"/><child \
         link=\"tool\"/><origin xyz=\"0 0 0.1\"/></joint>\n</robot>\n",
        J1.replace("</joint>", &format!("{limit}</joint>")),
        J2.replace("</joint>", &format!("{limit}</joint>")),
    );
    let warned = |tip: &str| -> Vec<String> {
        Robot::from_urdf(&text, "t.urdf", &selection(None, Some(tip)))
            .unwrap_or_else(|e| panic!("{e}"))
            .warnings
            .into_iter()
            .filter(|w| w.contains("robid takes 0 as"))
            .collect()
    };
    assert_eq!(warned("tool"), Vec::<String>::new());
    let on_chain = warned("finger");
    assert!(
        on_chain.len() == 1
            && on_chain[0].contains("the `<limit>` of joint `finger_joint` has `effort=\"0\"` and"),
        "{on_chain:?}"
    );
}

/// A `<limit>` without `effort` or `velocity` (which urdfdom, and so ROS tools and Pinocchio,
/// refuse) on a joint robid can move is read as no torque or velocity limit and warned
/// about once, at the first such `<limit>`, naming each joint and what it lacks (it used to
/// be accepted without a word); a fixed joint's `<limit>` is not robid's concern.
#[test]
fn limits_without_effort_or_velocity_are_warned_about() {
    let read = read_ok;
    let about = |chain: &UrdfChain| warned(chain, "in every `<limit>`");
    let with = limited;
    let whole = "lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"";
    assert!(about(&read(&with(whole, whole))).is_empty());
    // effort="0" is a value (robid's "none"); urdfdom reads it
    let zero = "lower=\"-1\" upper=\"1\" effort=\"0\" velocity=\"0\"";
    assert!(about(&read(&with(zero, zero))).is_empty());
    let chain = read(&with(whole, "lower=\"-1\" upper=\"1\" effort=\"2\""));
    assert_eq!(
        about(&chain),
        [
            "t.urdf:6:111: the `<limit>` of joint `j2` has no `velocity`: robid takes a missing \
             `velocity` as no velocity limit (`robid excite` then asks for --velocity-limits), \
             but the URDF format requires `effort` and `velocity` in every `<limit>`, and \
             urdfdom, the parser of ROS tools and Pinocchio, refuses the file; add the robot's \
             values (`effort` in N m or N, `velocity` in rad/s or m/s)"
        ]
    );
    let joint = &chain.robot.joints()[1];
    assert_eq!(
        (joint.limits.torque, joint.limits.velocity),
        (Some(2.0), None)
    );
    // both joints, one message at the first, naming the second and what it lacks
    let chain = read(&with(
        "lower=\"-1\" upper=\"1\" velocity=\"1\"",
        "lower=\"-1\" upper=\"1\"",
    ));
    let warned = about(&chain);
    assert_eq!(warned.len(), 1, "{warned:?}");
    assert!(
        warned[0].starts_with("t.urdf:5:88: ")
            && warned[0].contains(
                "the `<limit>` of joint `j1` has no `effort` (also: joint `j2` has no `effort` or \
             `velocity`): robid takes a missing `effort` as no torque limit and a missing \
             `velocity` as no velocity limit"
            ),
        "{}",
        warned[0]
    );
    assert_eq!(chain.robot.joints()[0].limits.torque, None);
    // a continuous joint's <limit> needs them too; a fixed joint's is not read
    let continuous = with("effort=\"1\"", whole).replacen("revolute", "continuous", 1);
    let warned = about(&read(&continuous));
    assert!(
        warned.len() == 1 && warned[0].contains("joint `j1` has no `velocity`"),
        "{warned:?}"
    );
    let fixed = arm(&format!(
        "{}{J1}",
        J2.replace("revolute", "fixed")
            .replace("</joint>", "<limit lower=\"0\" upper=\"0\"/></joint>")
    ));
    let chain = read(&fixed.replace(
        "</joint>\n</robot>",
        "<limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"/></joint>\n</robot>",
    ));
    assert!(about(&chain).is_empty(), "{:?}", chain.warnings);
    // a joint without <limit> has the other warning only
    let bare = read(&arm(&format!(
        "{J1}{}",
        J2.replace("</joint>", &format!("<limit {whole}/></joint>"))
    )));
    assert!(
        about(&bare).is_empty() && bare.warnings.len() == 1,
        "{:?}",
        bare.warnings
    );
}

/// Two consecutive axes a little off parallel (a calibrated UR's shoulder and elbow, 1e-4
/// rad, 0.4 m apart): their common normal, along which the DH table runs, lies 4 km from
/// the joints; the frames keep their origins near the joints, but the row between them has
/// `b` and `d` of 4 km, beyond a DH length, refused in one error that names the pair, their
/// angle and how to write them, also as the first two joints of a chain. (1e-3 rad, 400 m,
/// is read: `nearly_parallel.rs`.)
#[test]
fn nearly_parallel_axes_are_named_and_their_far_frames_refused() {
    let joint = |name: &str, parent: &str, child: &str, origin: &str| {
        format!(
            "<joint name=\"{name}\" type=\"revolute\"><parent link=\"{parent}\"/><child link=\"{child}\"/><origin {origin}/><axis xyz=\"0 0 1\"/></joint>\n"
        )
    };
    let text = |j3: &str| {
        format!(
            "<robot name=\"arm\">\n<link name=\"a\"/>\n<link name=\"b\"/>\n<link name=\"c\"/>\n<link name=\"d\"/>\n{}{}{}</robot>\n",
            joint(
                "j1",
                "a",
                "b",
                "xyz=\"0 0 0.1\" rpy=\"1.5707963267948966 0 0\""
            ),
            joint("j2", "b", "c", "xyz=\"0 0 0.1\""),
            joint("j3", "c", "d", j3),
        )
    };
    // 2 m apart and 1.6e-9 rad from parallel (the angle rule's 1e-9 rad is parallel; an
    // axis, as `rpy` values this small are taken as 0): the common normal 1.25e9 m away,
    // beyond what robid keeps the digits of
    let skewed = text("xyz=\"2 0 0\"").replacen(
        "<axis xyz=\"0 0 1\"/></joint>\n</robot>",
        "<axis xyz=\"1.6e-9 0 1\"/></joint>\n</robot>",
        1,
    );
    let first_two = skewed.replacen("type=\"revolute\"", "type=\"fixed\"", 1);
    for text in [&skewed, &first_two] {
        let message = error_of(text, &ChainSelection::default());
        for w in [
            "t.urdf:7:1: the common normal from joint `j2`'s axis to the next lies 1.25e9 m from the joint",
            "beyond the ±1e9 m that robid keeps the digits of",
            "the axes of joints `j2` and `j3` are 1.6e-9 rad from parallel",
            "exactly parallel",
        ] {
            assert!(message.contains(w), "{message}\nexpected {w:?}");
        }
        assert!(!message.contains("t.urdf:8:"), "{message}");
    }
    // intersecting axes 1e-6 rad apart: the twist is measured, taken as written (it was
    // refused as near a right angle), and the consequence for the base parameters told
    let chain = Robot::from_urdf(
        &text("xyz=\"0 0 0.3\" rpy=\"0 1e-6 0\""),
        "t.urdf",
        &ChainSelection::default(),
    )
    .unwrap();
    assert_eq!(chain.robot.joints()[2].alpha.as_str(), "0.000001");
    let told = one_warning(&chain, "taken as measured");
    for w in [
        "t.urdf:8:1: joint `j3`'s axis is 1.0e-6 rad from parallel to the previous one's:",
        "to identify the nominal set, write the origins and axes so that the angle is exact",
    ] {
        assert!(told.contains(w), "{}\nexpected {w:?}", told);
    }
    // exactly parallel axes 0.1 µm apart: a length below 1 µm is rounding, taken as 0 and
    // told (it was refused; romeo_laas_small of example-robot-data has two, 1.1e-8 m)
    let chain = Robot::from_urdf(
        &text("xyz=\"0.0000001 0 0\""),
        "t.urdf",
        &ChainSelection::default(),
    )
    .unwrap();
    assert_eq!(chain.robot.joints()[2].a.as_str(), "0");
    let told = one_warning(&chain, "taken as 0");
    assert!(
        told.contains("at joint `j3`, `a` = 1e-7 m: taken as 0"),
        "{}",
        told
    );
}

/// A chain longer than robid derives is told how to take a part of it: `--base` and
/// `--tip` for a URDF, fewer rows for a table (both used to say only the limit).
#[test]
fn too_many_joints_are_told_how_to_take_a_part() {
    let n = MAX_JOINTS + 1;
    let links: String = (0..=n)
        .map(|i| format!("<link name=\"l{i}\"/>\n"))
        .collect();
    let joints: String = (0..n)
        .map(|i| {
            format!(
                "<joint name=\"j{i}\" type=\"revolute\"><parent link=\"l{i}\"/><child link=\"l{}\"/>\
                 <origin xyz=\"0.1 0 0\"/><axis xyz=\"0 {} {}\"/></joint>\n",
                i + 1,
                i % 2,
                1 - i % 2
            )
        })
        .collect();
    let urdf = format!("<robot name=\"long\">\n{links}{joints}</robot>\n");
    let message = error_of(&urdf, &ChainSelection::default());
    assert!(
        message.contains(&format!("the robot has {n} joints")),
        "{message}"
    );
    assert!(message.contains("--base LINK and --tip LINK"), "{message}");
    let rows = "[[joints]]\nalpha = \"pi/2\"\na = 0.1\nd = 0\n".repeat(n);
    let table =
        format!("name = \"long\"\nconvention = \"modified\"\ngravity = [0, 0, -9.81]\n{rows}");
    let message = Robot::from_toml(&table, "long.toml")
        .unwrap_err()
        .to_string();
    assert!(
        message.contains(&format!("at most {MAX_JOINTS} rows")),
        "{message}"
    );
}

/// The chain of a URDF that must be read.
fn read_ok(text: &str) -> UrdfChain {
    Robot::from_urdf(text, "t.urdf", &ChainSelection::default()).unwrap_or_else(|e| panic!("{e}"))
}

/// The warnings of `chain` that contain `marker`.
fn warned(chain: &UrdfChain, marker: &str) -> Vec<String> {
    chain
        .warnings
        .iter()
        .filter(|w| w.contains(marker))
        .cloned()
        .collect()
}

/// The two-joint arm with `<limit first/>` on j1 and `<limit second/>` on j2.
fn limited(first: &str, second: &str) -> String {
    arm(&format!(
        "{}{}",
        J1.replace("</joint>", &format!("<limit {first}/></joint>")),
        J2.replace("</joint>", &format!("<limit {second}/></joint>"))
    ))
}

/// An inertia indefinite only by printing noise (iCub's `head`: every entry 0 but
/// `ixz="2.40741e-35"`, eigenvalues ±2.4e-35 kg m^2) is read without an error or a
/// warning: below the inertia of its mass at 1 µm from its centre, it is zero. A real
/// error of sign of the same tensor's size scale is still refused.
#[test]
fn an_inertia_indefinite_only_by_noise_is_read() {
    let text = |ixz: &str| {
        arm(&format!("{J1}{J2}")).replace(
            "<link name=\"c\"/>",
            &format!(
                "<link name=\"c\"><inertial><origin xyz=\"0.0185 -0.1108 0\"/><mass value=\"1.33687\"/><inertia ixx=\"0\" ixy=\"0\" ixz=\"{ixz}\" iyy=\"0\" iyz=\"0\" izz=\"0\"/></inertial></link>"
            ),
        )
    };
    let chain = Robot::from_urdf(&text("2.40741e-35"), "t.urdf", &ChainSelection::default())
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(
        chain.warnings.iter().all(|w| w.contains("no `<limit>`")),
        "{:?}",
        chain.warnings
    );
    assert_eq!(chain.links[1].inertial[9], 1.33687);
    let message = error_of(&text("0.01"), &ChainSelection::default());
    assert!(message.contains("not positive semidefinite"), "{message}");
}

/// A file cut short is told at its end, where it stops (the parser gives no place: it was
/// 1:1 of a file cut in its fourth line), with the likely cause.
#[test]
fn a_file_cut_short_is_told_at_its_end() {
    let whole = arm(&format!("{J1}{J2}"));
    for cut in [whole.find("</joint>").unwrap() + 3, whole.len() - 9] {
        let text = &whole[..cut];
        let last = text.trim_end();
        let line = last.matches('\n').count() + 1;
        let column = last.len() - last.rfind('\n').unwrap();
        let message = error_of(text, &ChainSelection::default());
        assert!(
            message.starts_with(&format!(
                "t.urdf:{line}:{column}: the URDF is not well-formed XML"
            )) && message.contains("is it cut short?"),
            "{message}"
        );
    }
}

/// An axis of tiny components is a direction like any other: its norm underflowed to zero
/// (`0 0 1e-200`) and it was refused as having none. Subnormal ones carry no digits and
/// are refused ([`a_subnormal_axis_has_no_direction`]).
#[test]
fn an_axis_of_tiny_components_has_a_direction() {
    let half = std::f64::consts::FRAC_1_SQRT_2;
    for (xyz, unit) in [
        ("0 0 1e-200", [0.0, 0.0, 1.0]),
        ("1e-170 -1e-170 0", [half, -half, 0.0]),
        ("0 3e-308 -3e-308", [0.0, half, -half]),
        ("0 -3e8 4e8", [0.0, -0.6, 0.8]),
    ] {
        let text = arm(&format!("{J1}{J2}").replacen("0 0 1", xyz, 1));
        let axis = direct_joints(&text)[0].axis;
        assert!(
            axis.iter().zip(unit).all(|(a, u)| (a - u).abs() < 1e-15),
            "{xyz}: {axis:?}"
        );
    }
}

/// A name of 400 000 characters was quoted whole in the message and compared with every
/// link for the nearest (47 s for 200 000 characters); it is refused, quoted short.
#[test]
fn a_huge_name_is_refused_quoted_short() {
    let huge = "x".repeat(400_000);
    let text = arm(&format!(
        "{J1}{}",
        J2.replace("\"b\"/><child", &format!("\"{huge}\"/><child"))
    ));
    let message = error_of(&text, &ChainSelection::default());
    assert!(
        message.contains(
            "`link=\"xxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxx.. (400000 characters)\"` of `<parent>` is \
             longer than 256 characters, the most robid reads; give it a shorter name"
        ),
        "{message}"
    );
    assert!(message.len() < 400, "{message}");
}

/// A joint `name` moving link `child` of link `parent` about x.
fn turning(name: &str, parent: &str, child: &str) -> String {
    format!(
        "<link name=\"{child}\"/><joint name=\"{name}\" type=\"continuous\"><parent \
         link=\"{parent}\"/><child link=\"{child}\"/></joint>"
    )
}

/// A comb of a thousand teeth (a movable side joint at every link of a long chain): the
/// analysis of the candidate tips checked every leaf's chain against every other (15 s
/// for 2000 teeth, cubic); it names a few and counts the rest. Chains longer than robid
/// derives are no candidates: the deepest link of such a path that is one is offered. The
/// leaves not tried are counted as such, apart from the tips (they were "(and 992 more
/// leaves)" after the tips, and so after a tip whose leaves all fail for one reason).
#[test]
fn a_tree_of_many_branches_names_a_few_tips() {
    let comb: String = (1..=1000)
        .map(|i| {
            let spine = turning(&format!("j{i}"), &format!("l{}", i - 1), &format!("l{i}"));
            spine + &turning(&format!("k{i}"), &format!("l{i}"), &format!("s{i}"))
        })
        .collect();
    let text = format!("<robot name=\"comb\"><link name=\"l0\"/>{comb}</robot>");
    let message = error_of(&text, &ChainSelection::default());
    assert!(
        message.ends_with(
            "choose the tip among `s1`, `s2`, `s3`, `s4`, `s5`, `s6`, `s7`, `s8`, or `l1`, \
             where the chain branches (the joints below it are held); 992 more leaves were not \
             checked"
        ),
        "{message}"
    );
    let n = MAX_JOINTS + 8;
    let fork: String = ["a", "b"]
        .iter()
        .flat_map(|side| {
            (1..=n).map(move |i| {
                let parent = if i == 1 {
                    "root".to_owned()
                } else {
                    format!("{side}{}", i - 1)
                };
                turning(&format!("{side}j{i}"), &parent, &format!("{side}{i}"))
            })
        })
        .collect();
    let text = format!("<robot name=\"fork\"><link name=\"root\"/>{fork}</robot>");
    let message = error_of(&text, &ChainSelection::default());
    assert!(
        message.ends_with(&format!(
            "choose the tip among `a{MAX_JOINTS}`, `b{MAX_JOINTS}`; not the leaves `a{n}`, \
             `b{n}`: with `a{n}` as the tip, the chain has {n} movable joints, and robid derives \
             at most {MAX_JOINTS}"
        )),
        "{message}"
    );
}

/// A generated URDF of thousands of mistakes is told the first fifty and a count; lists
/// inside one message (root links, joints without `<limit>`) name eight and count the rest.
/// A file of 3000 side joints without `<limit>` wrote their names in one warning; 5000
/// broken joints wrote 5000 errors.
#[test]
fn thousands_of_mistakes_are_told_in_a_page() {
    let broken: String = (0..3000)
        .map(|i| {
            format!("<joint name=\"j{i}\" type=\"fixed\"><parent link=\"x{i}\"/><child link=\"a\"/></joint>")
        })
        .collect();
    let message = error_of(&arm(&broken), &ChainSelection::default());
    assert_eq!(message.lines().count(), 51, "{message}");
    assert!(
        message.lines().last().unwrap().contains(
            "2950 more mistakes from here on are not shown; fix the ones above and read the \
             file again"
        ),
        "{message}"
    );
    let lone: String = (0..3000)
        .map(|i| format!("<link name=\"l{i}\"/>"))
        .collect();
    let message = error_of(&arm(&format!("{J1}{J2}{lone}")), &ChainSelection::default());
    assert!(
        message.contains(
            "several root links (links no joint moves): `a`, `l0`, `l1`, `l2`, `l3`, `l4`, \
             `l5`, `l6` (and 2993 more); connect"
        ),
        "{message}"
    );
    let sides: String = (0..3000)
        .map(|i| {
            format!(
                "<link name=\"s{i}\"/><joint name=\"k{i}\" type=\"revolute\"><parent link=\"b\"/><child link=\"s{i}\"/></joint>"
            )
        })
        .collect();
    let chain = Robot::from_urdf(
        &arm(&format!("{J1}{J2}{sides}")),
        "t.urdf",
        &selection(None, Some("c")),
    )
    .unwrap();
    let text = chain.warnings.join("\n");
    assert!(text.len() < 10_000, "{} bytes", text.len());
    assert!(
        text.contains("`k5`, `k6` (and 2993 more) have none either"),
        "{text}"
    );
}

/// Elements and attributes of a declared namespace (Drake's `<drake:joint type="ball">`
/// under `xmlns:drake`) are another tool's, as for URDF parsers: ignored with a warning at
/// the first, the robot the one without them. They were read by their local name: the
/// ball joint was refused as an unknown type, a planar one gave its child a second parent,
/// and `<u:robot>` was a robot. A default namespace leaves the elements URDF's.
#[test]
fn elements_of_a_declared_namespace_are_not_urdf() {
    let two = format!("{J1}{J2}");
    let plain = Robot::from_urdf(&arm(&two), "t.urdf", &ChainSelection::default()).unwrap();
    let declared =
        |text: &str| text.replace("<robot ", "<robot xmlns:drake=\"http://drake.mit.edu\" ");
    for extra in [
        "<drake:joint name=\"ball\" type=\"ball\"><parent link=\"a\"/><child link=\"c\"/></drake:joint>\n",
        "<drake:joint name=\"p\" type=\"planar\"><parent link=\"a\"/><child link=\"c\"/></drake:joint>\n",
        "<drake:link name=\"c\"/>\n",
    ] {
        let text = declared(&arm(&format!("{two}{extra}")));
        let chain = Robot::from_urdf(&text, "t.urdf", &ChainSelection::default())
            .unwrap_or_else(|e| panic!("{e}\n{text}"));
        assert_eq!(chain.robot, plain.robot, "{text}");
        let w = chain
            .warnings
            .iter()
            .find(|w| w.contains("namespace prefix `drake:`"));
        assert!(
            w.is_some_and(|w| w.starts_with("t.urdf:7:") && w.contains("ignored")),
            "{:?}",
            chain.warnings
        );
    }
    // a prefixed attribute is not the URDF's, even before it
    let text = declared(&arm(&two.replace(
        "<joint name=\"j2\" type=",
        "<joint name=\"j2\" drake:type=\"ball\" type=",
    )));
    let chain = Robot::from_urdf(&text, "t.urdf", &ChainSelection::default())
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(chain.robot, plain.robot);
    // a prefixed root is no `<robot>`
    let text = arm(&two)
        .replace(
            "<robot name=\"arm\">",
            "<u:robot xmlns:u=\"http://u\" name=\"arm\">",
        )
        .replace("</robot>", "</u:robot>");
    let message = error_of(&text, &ChainSelection::default());
    assert!(
        message.contains("the top element is `<u:robot>`, not `<robot>`"),
        "{message}"
    );
    // a default namespace puts unprefixed elements in it: they are URDF's all the same
    let text = arm(&two).replace("<robot ", "<robot xmlns=\"http://www.ros.org\" ");
    let chain = Robot::from_urdf(&text, "t.urdf", &ChainSelection::default())
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(chain.robot, plain.robot);
    assert!(
        !chain.warnings.iter().any(|w| w.contains("namespace")),
        "{:?}",
        chain.warnings
    );
}

/// A centre of mass in millimetres read as metres (`<inertial><origin xyz="250 0 0">`)
/// is warned of at its `<inertial>`, as a joint origin that far is; so is a prismatic
/// mimic joint off the chain held 20 m out by its `offset`. Both were silent (a torque of
/// 3907 N m from a 1 kg link).
#[test]
fn a_centre_of_mass_or_a_mimic_offset_in_millimetres_is_warned_of() {
    let two = format!("{J1}{J2}");
    let mass = |x: &str| {
        format!(
            "<link name=\"c\"><inertial><origin xyz=\"{x} 0 0\"/><mass value=\"1\"/>\
             <inertia ixx=\"0.01\" ixy=\"0\" ixz=\"0\" iyy=\"0.01\" iyz=\"0\" izz=\"0.01\"/>\
             </inertial></link>"
        )
    };
    let far = |text: &str| -> Vec<String> {
        let chain = Robot::from_urdf(text, "t.urdf", &selection(None, Some("c")))
            .unwrap_or_else(|e| panic!("{e}"));
        chain
            .warnings
            .into_iter()
            .filter(|w| w.contains("in millimetres?"))
            .collect()
    };
    let near = arm(&two).replace("<link name=\"c\"/>", &mass("0.25"));
    assert!(far(&near).is_empty());
    for (x, shown) in [("250", "250"), ("5e8", "500000000")] {
        let text = arm(&two).replace("<link name=\"c\"/>", &mass(x));
        let told = far(&text);
        assert!(
            told.len() == 1
                && told[0].starts_with("t.urdf:4:")
                && told[0].contains(&format!(
                    "link `c`'s centre of mass (its `<inertial>`'s `<origin>`) is at `{shown} 0 0` m"
                )),
            "{told:?}"
        );
    }
    // a prismatic joint off the chain, on link b, mimicking another one held at 0
    let side = |offset: &str| {
        arm(&format!(
            "{two}<joint name=\"t\" type=\"revolute\"><parent link=\"b\"/><child link=\"e\"/>\
             <axis xyz=\"1 0 0\"/><limit effort=\"1\" velocity=\"1\"/></joint>\
             <joint name=\"s\" type=\"prismatic\"><parent link=\"b\"/><child link=\"d\"/>\
             <axis xyz=\"1 0 0\"/><limit effort=\"1\" velocity=\"1\"/>\
             <mimic joint=\"t\" offset=\"{offset}\"/></joint>\n"
        ))
        .replace(
            "<link name=\"c\"/>",
            "<link name=\"c\"/><link name=\"d\"/><link name=\"e\"/>",
        )
    };
    assert!(far(&side("0.02")).is_empty());
    for (offset, shown) in [("20", "20"), ("1e8", "1e8")] {
        let told = far(&side(offset));
        assert!(
            told.len() == 1
                && told[0].starts_with("t.urdf:7:")
                && told[0].contains(&format!("joint `s`, off the chain, is held at {shown} m"))
                && told[0].contains(&format!("offset {shown})")),
            "{told:?}"
        );
    }
}

/// An axis of subnormal components (`0 4e-320 4e-320`, no digits) has no direction, as a
/// zero axis: it was read as `0 1 1` normalised (and `1e-320 0 0` as `1 0 0`, which
/// [`an_axis_of_tiny_components_has_a_direction`] took). A fixed joint's, unused, is fine.
#[test]
fn a_subnormal_axis_has_no_direction() {
    for xyz in ["1e-320 0 0", "0 5e-324 -5e-324"] {
        let message = error_of(
            &arm(&format!("{J1}{J2}").replacen("0 0 1", xyz, 1)),
            &ChainSelection::default(),
        );
        assert!(message.contains("subnormal"), "{message}");
    }
    let message = error_of(
        &arm(&format!("{J1}{J2}").replace(
            "<origin xyz=\"0.5 0 0\"/><axis xyz=\"0 0 1\"/>",
            "<origin xyz=\"0.5 0 0\"/><axis xyz=\"0 4e-320 4e-320\"/>",
        )),
        &ChainSelection::default(),
    );
    assert!(
        message.starts_with("t.urdf:6:")
            && message.contains("the axis of `<joint name=\"j2\">` has no direction")
            && message.contains("below 2.2e-308, subnormal"),
        "{message}"
    );
    let fixed = arm(&format!("{J1}{J2}").replace(
        "<joint name=\"j2\" type=\"revolute\"",
        "<joint name=\"j2\" type=\"fixed\"",
    ))
    .replace(
        "0.5 0 0\"/><axis xyz=\"0 0 1\"",
        "0.5 0 0\"/><axis xyz=\"0 4e-320 0\"",
    );
    assert!(fixed.contains("4e-320"));
    Robot::from_urdf(&fixed, "t.urdf", &ChainSelection::default())
        .unwrap_or_else(|e| panic!("{e}"));
}

/// A value that is not finite in an element robid does not read (`<dynamics
/// damping="nan">`, a visual's origin, an element's text) is an error at its place:
/// `robid feasible -o` copied it into the URDF it wrote. Names are no numbers, and an
/// infinite position bound is no limit, as before.
#[test]
fn values_that_are_not_finite_are_refused_wherever_they_are() {
    for (inside, place, what) in [
        (
            "<dynamics damping=\"nan\" friction=\"0\"/>",
            "t.urdf:6:",
            "`damping=\"nan\"` of `<dynamics>` of `<joint name=\"j2\">` is not finite",
        ),
        (
            "<dynamics damping=\"0\" friction=\"-inf\"/>",
            "t.urdf:6:",
            "`friction=\"-inf\"` of `<dynamics>`",
        ),
        (
            "<calibration rising=\"1 NaN\"/>",
            "t.urdf:6:",
            "`rising=\"1 NaN\"`",
        ),
        (
            "<x>infinity</x>",
            "t.urdf:6:",
            "the text `infinity` of `<x>` of `<joint name=\"j2\">` is not finite",
        ),
    ] {
        let text = arm(&format!("{J1}{J2}")).replace(
            "<origin xyz=\"0.5 0 0\"/><axis xyz=\"0 0 1\"/></joint>",
            &format!("<origin xyz=\"0.5 0 0\"/><axis xyz=\"0 0 1\"/>{inside}</joint>"),
        );
        let message = error_of(&text, &ChainSelection::default());
        assert!(
            message.starts_with(place)
                && message.contains(what)
                && message.contains("write finite numbers"),
            "{message}"
        );
    }
    // a link's visual, and a value robid reads, told once
    let text = arm(&format!("{J1}{J2}")).replace(
        "<link name=\"c\"/>",
        "<link name=\"c\"><visual><origin xyz=\"nan 0 0\"/></visual></link>",
    );
    let message = error_of(&text, &ChainSelection::default());
    assert!(
        message.starts_with("t.urdf:4:")
            && message.contains("of `<link name=\"c\">` is not finite"),
        "{message}"
    );
    let text = arm(&format!("{J1}{J2}").replace("0.5 0 0", "0.5 inf 0"));
    let message = error_of(&text, &ChainSelection::default());
    assert_eq!(message.matches("not finite").count(), 1, "{message}");
    // names are no numbers; an infinite bound is no limit
    let text = arm(&format!("{J1}{J2}").replace("<axis xyz=\"0 0 1\"/></joint>\n<joint name=\"j2\"", "<axis xyz=\"0 0 1\"/><limit lower=\"-inf\" upper=\"inf\" effort=\"1\" velocity=\"1\"/></joint>\n<joint name=\"j2\""))
        .replace("\"c\"", "\"inf\"");
    assert!(text.contains("lower=\"-inf\"") && text.contains("name=\"inf\""));
    Robot::from_urdf(&text, "t.urdf", &ChainSelection::default()).unwrap_or_else(|e| panic!("{e}"));
}
