//! Each body's standard parameters against an independent sum over its URDF links in the
//! base frame at q = 0.

use super::super::inertial::tensor;
use super::super::rigid::{mul, transpose};
use super::*;

/// Mass, first moment and inertia about the origin, in the base frame.
#[derive(Clone, Copy, Debug, Default)]
struct Sums {
    m: f64,
    ms: [f64; 3],
    j: [[f64; 3]; 3],
}

impl Sums {
    /// Adds a point-mass-plus-inertia: mass `m` at `c` with inertia `i` about `c`.
    fn add(&mut self, m: f64, c: [f64; 3], i: [[f64; 3]; 3]) {
        self.m += m;
        for (ms, c) in self.ms.iter_mut().zip(c) {
            *ms += m * c;
        }
        let cc = c[0] * c[0] + c[1] * c[1] + c[2] * c[2];
        for a in 0..3 {
            for b in 0..3 {
                let identity = if a == b { cc } else { 0.0 };
                self.j[a][b] += i[a][b] + m * (identity - c[a] * c[b]);
            }
        }
    }

    fn difference(&self, other: &Sums) -> f64 {
        let mut worst = (self.m - other.m).abs();
        for a in 0..3 {
            worst = worst.max((self.ms[a] - other.ms[a]).abs());
            for b in 0..3 {
                worst = worst.max((self.j[a][b] - other.j[a][b]).abs());
            }
        }
        worst
    }
}

/// The URDF's own sum over `links`, in the frame of `base`, every joint at zero.
fn urdf_sum(text: &str, base: &str, links: &[&str]) -> Sums {
    let urdf = xml::read(&Place { file: "t", text }).unwrap();
    let poses = direct_poses(&direct_joints(text), base, &HashMap::new());
    let mut sums = Sums::default();
    for link in urdf
        .links
        .iter()
        .filter(|l| links.contains(&l.name.as_str()))
    {
        if let Some(i) = &link.inertial {
            let com = poses[&link.name].then(&i.origin);
            let rotated = mul(&mul(&com.r, &tensor(&i.inertia)), &transpose(&com.r));
            sums.add(i.mass, com.p, rotated);
        }
    }
    sums
}

/// A body's standard parameters (in robid frame j) moved to the base frame through its
/// centre of mass.
fn chain_sum(frame: &Rigid, p: &[f64; 10]) -> Sums {
    let m = p[9];
    let mut sums = Sums::default();
    if m == 0.0 {
        return sums;
    }
    let c = [p[6] / m, p[7] / m, p[8] / m];
    let cc = c[0] * c[0] + c[1] * c[1] + c[2] * c[2];
    let j = tensor(&[p[0], p[1], p[2], p[3], p[4], p[5]]);
    let about_com: [[f64; 3]; 3] = std::array::from_fn(|a| {
        std::array::from_fn(|b| {
            let identity = if a == b { cc } else { 0.0 };
            j[a][b] - m * (identity - c[a] * c[b])
        })
    });
    let rotated = mul(&mul(&frame.r, &about_com), &transpose(&frame.r));
    let c_base: [f64; 3] = std::array::from_fn(|k| {
        frame.p[k] + frame.r[k][0] * c[0] + frame.r[k][1] * c[1] + frame.r[k][2] * c[2]
    });
    sums.add(m, c_base, rotated);
    sums
}

/// Every body of `chain` against the URDF's sum over its links; returns the whole chain's
/// sums (URDF, robid).
fn check_bodies(text: &str, chain: &UrdfChain, base: &str) -> (Sums, Sums) {
    let frames = dh_frames(chain, &vec![0.0; chain.robot.dof()]);
    let mut whole = (Sums::default(), Sums::default());
    for (link, frame) in chain.links.iter().zip(&frames) {
        let mut names = vec![link.link.as_str()];
        names.extend(link.attached.iter().map(|a| a.name.as_str()));
        let expected = urdf_sum(text, base, &names);
        let got = chain_sum(frame, &link.inertial);
        let worst = expected.difference(&got);
        assert!(worst < 1e-12, "body of {}: {worst:e}", link.joint);
        whole.0.add(expected.m, [0.0; 3], [[0.0; 3]; 3]);
        for k in 0..3 {
            whole.0.ms[k] += expected.ms[k];
        }
        whole.1.add(got.m, [0.0; 3], [[0.0; 3]; 3]);
        for k in 0..3 {
            whole.1.ms[k] += got.ms[k];
        }
    }
    whole
}

#[test]
fn every_body_of_the_real_robots_sums_its_links() {
    for (path, base, tip) in [
        (PANDA, "panda_link0", Some("panda_hand")),
        (UR5, "world", None),
        (LWR4, "box", None),
        (TX40, "base_link", None),
    ] {
        let text = repository_file(path);
        let chain = Robot::from_urdf(&text, path, &selection(None, tip)).unwrap();
        check_bodies(&text, &chain, base);
    }
}

#[test]
fn the_panda_to_its_hand_has_the_urdfs_mass_and_centre_of_mass() {
    let text = repository_file(PANDA);
    let chain = Robot::from_urdf(&text, PANDA, &selection(None, Some("panda_hand"))).unwrap();
    let (urdf, robid) = check_bodies(&text, &chain, "panda_link0");
    // every link but the fixed base panda_link0, summed from the file directly
    let all: Vec<String> = xml::read(&Place {
        file: "t",
        text: &text,
    })
    .unwrap()
    .links
    .iter()
    .map(|l| l.name.clone())
    .filter(|n| n != "panda_link0")
    .collect();
    let names: Vec<&str> = all.iter().map(String::as_str).collect();
    let direct = urdf_sum(&text, "panda_link0", &names);
    assert!((direct.m - robid.m).abs() < 1e-12 && (urdf.m - robid.m).abs() < 1e-12);
    // link1 to link8, the hand, its tcp and both fingers: 16.82 kg
    assert_eq!(names.len(), 12);
    assert!((direct.m - 16.822132).abs() < 1e-9, "{}", direct.m);
    for k in 0..3 {
        let com = robid.ms[k] / robid.m;
        assert!((direct.ms[k] / direct.m - com).abs() < 1e-12, "{k}");
    }
}

#[test]
fn the_bodies_of_random_chains_sum_their_links() {
    use std::fmt::Write;
    // a chain with side links on fixed and off-path joints and rotated inertial frames
    let mut text = String::from("<robot name=\"r\"><link name=\"b\"/>");
    let mut rng = robid_core::rng::Rng::new(3);
    let mut parent = "b".to_owned();
    for j in 0..4 {
        let v = |rng: &mut robid_core::rng::Rng| {
            format!(
                "{:?} {:?} {:?}",
                rng.uniform(-0.5, 0.5),
                rng.uniform(-0.5, 0.5),
                rng.uniform(-0.5, 0.5)
            )
        };
        let inertial = |rng: &mut robid_core::rng::Rng| {
            format!(
                "<inertial><origin xyz=\"{}\" rpy=\"{}\"/><mass value=\"{:?}\"/><inertia ixx=\"0.3\" ixy=\"-0.01\" ixz=\"0.02\" iyy=\"0.2\" iyz=\"0.015\" izz=\"0.25\"/></inertial>",
                v(rng),
                v(rng),
                rng.uniform(0.1, 2.0)
            )
        };
        let _ = write!(
            text,
            "<link name=\"l{j}\">{}</link><joint name=\"j{j}\" type=\"revolute\"><parent link=\"{parent}\"/><child link=\"l{j}\"/><origin xyz=\"{}\" rpy=\"{}\"/><axis xyz=\"{}\"/></joint>",
            inertial(&mut rng),
            v(&mut rng),
            v(&mut rng),
            v(&mut rng)
        );
        let _ = write!(
            text,
            "<link name=\"fixed{j}\">{}</link><joint name=\"f{j}\" type=\"fixed\"><parent link=\"l{j}\"/><child link=\"fixed{j}\"/><origin xyz=\"{}\" rpy=\"{}\"/></joint>",
            inertial(&mut rng),
            v(&mut rng),
            v(&mut rng)
        );
        let _ = write!(
            text,
            "<link name=\"side{j}\">{}</link><joint name=\"s{j}\" type=\"prismatic\"><parent link=\"fixed{j}\"/><child link=\"side{j}\"/><origin xyz=\"{}\" rpy=\"{}\"/><axis xyz=\"1 0 0\"/></joint>",
            inertial(&mut rng),
            v(&mut rng),
            v(&mut rng)
        );
        parent = format!("l{j}");
    }
    text.push_str("</robot>");
    let chain = Robot::from_urdf(&text, "r.urdf", &selection(None, Some("l3"))).unwrap();
    assert_eq!(chain.links[3].attached.len(), 2);
    let (urdf, robid) = check_bodies(&text, &chain, "b");
    assert!((urdf.m - robid.m).abs() < 1e-12);
}

/// A hand whose second finger mimics the first (`f2 = f1 + 0.8`): off the chain, the first
/// finger is held at 0 and the second where the relation puts it, 0.8 rad (it used to be
/// held at 0). A third joint following the second (`f3 = 2 f2 + 0.1`, prismatic) is at
/// 1.7 m.
const MIMIC_HAND: &str = r#"<robot name="b06">
  <link name="base"/>
  <link name="hand"><inertial><origin xyz="0.05 0 0"/><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <joint name="j1" type="revolute">
    <parent link="base"/><child link="hand"/><origin xyz="0 0 0.3" rpy="1.5707963267948966 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-2" upper="2" effort="10" velocity="2"/>
  </joint>
  <link name="finger1"><inertial><origin xyz="0.1 0 0"/><mass value="0.5"/><inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial></link>
  <link name="finger2"><inertial><origin xyz="0.1 0 0"/><mass value="0.5"/><inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial></link>
  <link name="slider"><inertial><origin xyz="0 0.1 0"/><mass value="0.25"/><inertia ixx="0.001" ixy="0" ixz="0" iyy="0.002" iyz="0" izz="0.003"/></inertial></link>
  <joint name="f1" type="revolute">
    <parent link="hand"/><child link="finger1"/><origin xyz="0.1 0.02 0"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="10" velocity="2"/>
  </joint>
  <joint name="f2" type="revolute">
    <parent link="hand"/><child link="finger2"/><origin xyz="0.1 -0.02 0"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="10" velocity="2"/>
    <mimic joint="f1" multiplier="1" offset="0.8"/>
  </joint>
  <joint name="f3" type="prismatic">
    <parent link="finger2"/><child link="slider"/><axis xyz="1 0 0"/>
    <limit lower="-2" upper="2" effort="10" velocity="2"/>
    <mimic joint="f2" multiplier="2" offset="0.1"/>
  </joint>
</robot>"#;

#[test]
fn mimic_joints_off_the_chain_are_held_where_their_relation_puts_them() {
    let chain = Robot::from_urdf(MIMIC_HAND, "t.urdf", &selection(None, Some("hand"))).unwrap();
    // the same hand with the fingers placed by hand: f2 turned by 0.8 rad in its origin,
    // the slider moved by 1.7 m along x of finger2
    let placed = MIMIC_HAND
        .replace(
            "<origin xyz=\"0.1 -0.02 0\"/>",
            "<origin xyz=\"0.1 -0.02 0\" rpy=\"0 0 0.8\"/>",
        )
        .replace(
            "<child link=\"slider\"/>",
            "<child link=\"slider\"/><origin xyz=\"1.7 0 0\"/>",
        )
        .replace("<mimic joint=\"f1\" multiplier=\"1\" offset=\"0.8\"/>", "")
        .replace("<mimic joint=\"f2\" multiplier=\"2\" offset=\"0.1\"/>", "");
    let expected = Robot::from_urdf(&placed, "t.urdf", &selection(None, Some("hand"))).unwrap();
    let worst = chain.links[0]
        .inertial
        .iter()
        .zip(&expected.links[0].inertial)
        .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
    assert!(worst < 1e-15, "{worst:e}");
    for (a, b) in chain.links[0]
        .attached
        .iter()
        .zip(&expected.links[0].attached)
    {
        assert_eq!(a.name, b.name);
        assert!(difference(&a.frame, &b.frame) < 1e-15, "{}", a.name);
    }
    // held at 0, the first moment of the hand's body would differ by the fingers' turn
    let at_zero = MIMIC_HAND
        .replace(" offset=\"0.8\"", "")
        .replace(" offset=\"0.1\"", "");
    let zero = Robot::from_urdf(&at_zero, "t.urdf", &selection(None, Some("hand"))).unwrap();
    assert!((zero.links[0].inertial[7] - chain.links[0].inertial[7]).abs() > 1e-3);
    // joints following each other in a cycle: an error at the `<mimic>`
    let cycle = MIMIC_HAND.replace(
        "<limit lower=\"-1\" upper=\"1\" effort=\"10\" velocity=\"2\"/>\n  </joint>\n  <joint name=\"f2\"",
        "<limit lower=\"-1\" upper=\"1\" effort=\"10\" velocity=\"2\"/><mimic joint=\"f3\"/>\n  </joint>\n  <joint name=\"f2\"",
    );
    assert_ne!(cycle, MIMIC_HAND);
    let message = Robot::from_urdf(&cycle, "t.urdf", &selection(None, Some("hand")))
        .unwrap_err()
        .to_string();
    assert!(
        message
            .contains("the joints `f1`, `f3`, `f2` follow each other through `<mimic>` in a cycle"),
        "{message}"
    );
    // a joint that follows itself is told so (it read "the joints `f2` follow each other")
    let itself = MIMIC_HAND.replace("<mimic joint=\"f2\"", "<mimic joint=\"f3\"");
    assert_ne!(itself, MIMIC_HAND);
    let message = Robot::from_urdf(&itself, "t.urdf", &selection(None, Some("hand")))
        .unwrap_err()
        .to_string();
    assert!(
        message.contains("the joint `f3` follows itself through `<mimic>`")
            && message.contains("name that joint in `<mimic joint=...>`"),
        "{message}"
    );
}

/// A mimic joint held off the chain outside its own `<limit>` (the relation's offset
/// beyond the joint's range) is warned about at its `<mimic>`, naming the joint, the
/// relation, the value and the limits; the links are placed as the relation says all the
/// same. Inside its limits, without limits, or in the fixed base (not used), nothing is
/// said.
#[test]
fn a_mimic_joint_held_outside_its_limits_is_warned_about() {
    let read = |text: &str| {
        Robot::from_urdf(text, "t.urdf", &selection(None, Some("hand")))
            .unwrap_or_else(|e| panic!("{e}"))
    };
    let mimic_warnings = |chain: &UrdfChain| -> Vec<String> {
        chain
            .warnings
            .iter()
            .filter(|w| w.contains("<mimic>"))
            .cloned()
            .collect()
    };
    assert!(mimic_warnings(&read(MIMIC_HAND)).is_empty());
    let f2_limit =
        "<limit lower=\"-1\" upper=\"1\" effort=\"10\" velocity=\"2\"/>\n    <mimic joint=\"f1\"";
    let narrow = MIMIC_HAND.replace(
        f2_limit,
        "<limit lower=\"-0.5\" upper=\"0.5\" effort=\"10\" velocity=\"2\"/>\n    <mimic joint=\"f1\"",
    );
    assert_ne!(narrow, MIMIC_HAND);
    let chain = read(&narrow);
    let warned = mimic_warnings(&chain);
    assert_eq!(warned.len(), 1, "{warned:?}");
    assert_eq!(
        warned[0],
        "t.urdf:18:19: joint `f2`, off the chain, follows joint `f1` through `<mimic>` \
         (multiplier 1, offset 0.8), which holds it at 0.8 rad where joint `f1` is held at 0, \
         outside its own `<limit>` [-0.5, 0.5]: robid places the links it moves there, as the \
         URDF's relation says (docs/urdf.md#choosing-the-chain), though the joint cannot go \
         there; check the mimic's `offset` and `multiplier` against the joint's `lower` and \
         `upper`"
    );
    // placed as the relation says all the same
    assert_eq!(chain.links[0].inertial, read(MIMIC_HAND).links[0].inertial);
    // the prismatic f3 = 2 f2 + 0.1 at 1.7 m, beyond [0, 1]
    let short = MIMIC_HAND.replace(
        "<limit lower=\"-2\" upper=\"2\" effort=\"10\" velocity=\"2\"/>\n    <mimic joint=\"f2\"",
        "<limit lower=\"0\" upper=\"1\" effort=\"10\" velocity=\"2\"/>\n    <mimic joint=\"f2\"",
    );
    let warned = mimic_warnings(&read(&short));
    assert_eq!(warned.len(), 1, "{warned:?}");
    assert!(
        warned[0].contains("joint `f3`, off the chain, follows joint `f2` through `<mimic>` (multiplier 2, offset 0.1), which holds it at 1.7 m where joint `f2` is held at 0.8, outside its own `<limit>` [0, 1]"),
        "{}",
        warned[0]
    );
    // without a <limit>, or equal lower and upper (no position limits): nothing to check
    for text in [
        MIMIC_HAND.replace(f2_limit, "<mimic joint=\"f1\""),
        MIMIC_HAND.replace(
            f2_limit,
            "<limit lower=\"0\" upper=\"0\" effort=\"10\" velocity=\"2\"/>\n    <mimic joint=\"f1\"",
        ),
    ] {
        assert!(mimic_warnings(&read(&text)).is_empty());
    }
    // a flap fixed to the base's side, which the model does not use
    let flap = MIMIC_HAND.replace(
        "</robot>",
        "<link name=\"flap\"/><joint name=\"flap\" type=\"revolute\"><parent link=\"base\"/><child link=\"flap\"/>\
         <limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"/><mimic joint=\"f1\" offset=\"5\"/></joint>\n</robot>",
    );
    let chain = Robot::from_urdf(&flap, "t.urdf", &selection(Some("base"), Some("hand")))
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(mimic_warnings(&chain).is_empty(), "{:?}", chain.warnings);
}
