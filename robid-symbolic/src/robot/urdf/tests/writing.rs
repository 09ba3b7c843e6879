//! `write_inertials`: a round trip reproduces the parameters, every byte outside the
//! replaced `<inertial>` elements stays.

use super::super::write_inertials;
use super::*;

/// The text without the `<inertial>` elements of `links`.
fn without_inertials(text: &str, links: &[&str]) -> String {
    let urdf = xml::read(&Place { file: "t", text }).unwrap();
    let mut ranges: Vec<std::ops::Range<usize>> = urdf
        .links
        .iter()
        .filter(|l| links.contains(&l.name.as_str()))
        .filter_map(|l| l.inertial.as_ref().map(|i| i.range.clone()))
        .collect();
    ranges.sort_by_key(|r| r.start);
    let mut out = String::new();
    let mut at = 0;
    for r in ranges {
        out.push_str(&text[at..r.start]);
        at = r.end;
    }
    out.push_str(&text[at..]);
    out
}

fn largest_difference(a: &[[f64; 10]], b: &[[f64; 10]]) -> f64 {
    a.iter()
        .flatten()
        .zip(b.iter().flatten())
        .fold(0.0, |m, (x, y)| m.max((x - y).abs()))
}

/// Physical changes of each body: mass scaled, centre of mass and inertia shifted.
fn changed(chain: &UrdfChain) -> Vec<[f64; 10]> {
    chain
        .links
        .iter()
        .enumerate()
        .map(|(k, l)| {
            let mut p = l.inertial;
            let s = 1.0 + 0.1 * (k as f64 + 1.0);
            for x in &mut p {
                *x *= s;
            }
            p[0] += 0.01;
            p[3] += 0.02;
            p[5] += 0.015;
            p
        })
        .collect()
}

#[test]
fn the_real_robots_round_trip_and_keep_every_other_byte() {
    for (path, tip) in [
        (PANDA, Some("panda_hand")),
        (UR5, None),
        (LWR4, None),
        (TX40, None),
    ] {
        let text = repository_file(path);
        let chosen = selection(None, tip);
        let chain = Robot::from_urdf(&text, path, &chosen).unwrap();
        for target in [
            chain.links.iter().map(|l| l.inertial).collect::<Vec<_>>(),
            changed(&chain),
        ] {
            let (written, warnings) = write_inertials(&text, path, &chain, &target).unwrap();
            assert!(warnings.is_empty(), "{warnings:?}");
            let again = Robot::from_urdf(&written, path, &chosen).unwrap();
            let got: Vec<[f64; 10]> = again.links.iter().map(|l| l.inertial).collect();
            let worst = largest_difference(&got, &target);
            assert!(worst < 1e-12, "{path}: {worst:e}");
            assert_eq!(again.robot, chain.robot);
            let names: Vec<&str> = chain.links.iter().map(|l| l.link.as_str()).collect();
            assert_eq!(
                without_inertials(&written, &names),
                without_inertials(&text, &names),
                "{path}"
            );
        }
    }
}

#[test]
fn a_body_lighter_than_its_attached_links_takes_their_inertials() {
    let text = repository_file(PANDA);
    let chosen = selection(None, Some("panda_hand"));
    let chain = Robot::from_urdf(&text, PANDA, &chosen).unwrap();
    let mut target: Vec<[f64; 10]> = chain.links.iter().map(|l| l.inertial).collect();
    // link 7 with the hand: the body lighter than the hand and fingers alone
    target[6] = target[6].map(|x| x * 0.2);
    let (written, warnings) = write_inertials(&text, PANDA, &chain, &target).unwrap();
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    let removed = [
        "panda_link8",
        "panda_hand",
        "panda_hand_tcp",
        "panda_leftfinger",
        "panda_rightfinger",
    ];
    for name in removed {
        assert!(
            warnings[0].contains(&format!("`{name}`")),
            "{}",
            warnings[0]
        );
    }
    assert!(
        warnings[0].starts_with(&format!("{PANDA}:180:")),
        "{}",
        warnings[0]
    );
    let again = Robot::from_urdf(&written, PANDA, &chosen).unwrap();
    let got: Vec<[f64; 10]> = again.links.iter().map(|l| l.inertial).collect();
    assert!(largest_difference(&got, &target) < 1e-12);
    let urdf = xml::read(&Place {
        file: "t",
        text: &written,
    })
    .unwrap();
    for name in removed {
        assert!(
            urdf.links
                .iter()
                .any(|l| l.name == name && l.inertial.is_none()),
            "{name}"
        );
    }
}

#[test]
fn links_without_inertial_get_one() {
    let text = "<robot name=\"arm\">\n  <link name=\"a\"/>\n  <link name=\"b\"/>\n  <link name=\"c\">\n    <visual/>\n  </link>\n  <joint name=\"j1\" type=\"revolute\"><parent link=\"a\"/><child link=\"b\"/><axis xyz=\"0 0 1\"/></joint>\n  <joint name=\"j2\" type=\"prismatic\"><parent link=\"b\"/><child link=\"c\"/><origin xyz=\"0.5 0 0\" rpy=\"0.3 0.2 0.1\"/><axis xyz=\"0 1 1\"/></joint>\n</robot>\n";
    let chosen = ChainSelection::default();
    let chain = Robot::from_urdf(text, "t.urdf", &chosen).unwrap();
    assert!(chain.links.iter().all(|l| l.inertial == [0.0; 10]));
    let target = [
        [0.5, 0.01, -0.02, 0.4, 0.03, 0.3, 0.2, -0.1, 0.05, 2.0],
        [0.05, 0.0, 0.0, 0.05, 0.0, 0.02, 0.0, 0.0, 0.1, 1.0],
    ];
    let (written, _) = write_inertials(text, "t.urdf", &chain, &target).unwrap();
    assert!(
        written.starts_with(
            "<robot name=\"arm\">\n  <link name=\"a\"/>\n  <link name=\"b\">\n    <inertial>\n"
        ),
        "{written}"
    );
    assert!(
        written.contains("    <visual/>\n    <inertial>"),
        "{written}"
    );
    let again = Robot::from_urdf(&written, "t.urdf", &chosen).unwrap();
    let got: Vec<[f64; 10]> = again.links.iter().map(|l| l.inertial).collect();
    assert!(largest_difference(&got, &target) < 1e-12, "{got:?}");
}

#[test]
fn parameters_that_are_not_physical_are_refused() {
    let text = repository_file(UR5);
    let chain = Robot::from_urdf(&text, UR5, &ChainSelection::default()).unwrap();
    let mut target: Vec<[f64; 10]> = chain.links.iter().map(|l| l.inertial).collect();
    target[2][9] = -1.0;
    let e = write_inertials(&text, UR5, &chain, &target)
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("`inertials[2]` of `write_inertials`: the parameters of link `forearm_link`"),
        "{e}"
    );
    let e = write_inertials(&text, UR5, &chain, &target[..3])
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("3 parameter sets for a chain of 6 joints"),
        "{e}"
    );
}

/// A chain link that is a point mass (50 kg, inertia 0) with a tool fixed to it, as
/// `/tmp/hunt_urdf/min/pm2.urdf` of the 7 December 2026 bug hunt.
const POINT_MASS_WITH_TOOL: &str = r#"<robot name="pm2">
  <link name="base"/>
  <link name="l1">
    <inertial><origin xyz="0.1 0 0"/><mass value="50"/><inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/></inertial>
  </link>
  <link name="tool1">
    <inertial><origin xyz="0 0.05 0.1"/><mass value="3"/><inertia ixx="0.05" ixy="0" ixz="0" iyy="0.04" iyz="0" izz="0.03"/></inertial>
  </link>
  <link name="l2">
    <inertial><origin xyz="0.2 0 0"/><mass value="2"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.02"/></inertial>
  </link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="100" velocity="3"/></joint>
  <joint name="f1" type="fixed"><parent link="l1"/><child link="tool1"/><origin xyz="0 0 0.2"/></joint>
  <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/><origin xyz="0.3 0 0"/><axis xyz="0 1 0"/><limit lower="-3" upper="3" effort="100" velocity="3"/></joint>
</robot>
"#;

#[test]
fn what_is_written_reads_back_when_the_remainder_is_indefinite_by_rounding() {
    let chosen = ChainSelection::default();
    let chain = Robot::from_urdf(POINT_MASS_WITH_TOOL, "pm2.urdf", &chosen).unwrap();
    let mut target: Vec<[f64; 10]> = chain.links.iter().map(|l| l.inertial).collect();
    // body 1 as `robid feasible` wrote it: the point mass's remainder after the tool has a
    // principal moment of -2e-8 kg m^2 (2e-10 of the body's 53 kg), far beyond the
    // reader's floor for 50 kg (its inertia at 1 um, 5e-11)
    target[0][0] -= 2e-8;
    target[0][1] += 5e-9;
    let (written, warnings) = write_inertials(POINT_MASS_WITH_TOOL, "pm2.urdf", &chain, &target)
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(warnings.is_empty(), "{warnings:?}");
    let again = Robot::from_urdf(&written, "pm2f.urdf", &chosen).unwrap_or_else(|e| panic!("{e}"));
    assert!(again.warnings.is_empty(), "{:?}", again.warnings);
    // the tool keeps its inertial; the remainder moved to the nearest physical inertia,
    // well within 1e-9 of the body's largest parameter
    assert!(
        written.contains(r#"<origin xyz="0 0.05 0.1"/><mass value="3"/>"#),
        "{written}"
    );
    let got: Vec<[f64; 10]> = again.links.iter().map(|l| l.inertial).collect();
    let worst = largest_difference(&got, &target);
    assert!(worst > 0.0 && worst < 1e-9 * 53.0, "{worst:e}");
    // beyond that the whole body goes on `l1`, and still reads back
    target[0][0] -= 1e-6;
    let (written, warnings) =
        write_inertials(POINT_MASS_WITH_TOOL, "pm2.urdf", &chain, &target).unwrap();
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert!(warnings[0].contains("`tool1`"), "{}", warnings[0]);
    let again = Robot::from_urdf(&written, "pm2f.urdf", &chosen).unwrap_or_else(|e| panic!("{e}"));
    let got: Vec<[f64; 10]> = again.links.iter().map(|l| l.inertial).collect();
    assert!(largest_difference(&got, &target) < 1e-12);
}
