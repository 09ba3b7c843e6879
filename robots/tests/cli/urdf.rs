//! A URDF as the description of any subcommand (docs/command-line.md, "Descriptions,
//! `--drive`, `--base` and `--tip`"): the chain flags, the URDF's own inertials where no
//! parameters are given, and `robid feasible` writing the user's URDF back.

use std::f64::consts::PI;
use std::path::{Path, PathBuf};

use robid_runtime::Model;
use robid_symbolic::Robot;
use robid_symbolic::robot::{ChainSelection, Inertial, ParameterKind, UrdfChain};
use robots::interpreted::Interpreted;

use crate::common::{asset, fails_with, folder, robid, stderr, stdout, write};

/// The UR5 of example-robot-data.
const UR5: &str = "../data/example_robot_data/ur5/ur5_robot.urdf";
/// The Panda of example-robot-data (a tree: the hand's two fingers).
const PANDA: &str = "../data/example_robot_data/panda/panda.urdf";

/// The chain robid reads from `path` (relative to the crate folder).
fn chain(path: &str, tip: Option<&str>) -> UrdfChain {
    let selection = ChainSelection {
        base: None,
        tip: tip.map(str::to_owned),
    };
    Robot::from_urdf_file(Path::new(&asset(path)), &selection).unwrap()
}

/// The base parameters of the chain's model from its own inertials.
fn urdf_base(chain: &UrdfChain, model: &dyn Model) -> Vec<f64> {
    let standard: Vec<f64> = chain
        .robot
        .standard_parameters()
        .iter()
        .map(|p| match p.kind {
            ParameterKind::Inertial(i) => {
                chain.links[p.link].inertial[Inertial::ALL.iter().position(|&k| k == i).unwrap()]
            }
            ParameterKind::Drive(_) => 0.0,
        })
        .collect();
    let mut base = vec![0.0; model.base_parameter_count()];
    model.base_from_standard_into(&standard, &mut base).unwrap();
    base
}

/// Six-joint states `q1..q6,qd1..qd6,qdd1..qdd6`, varied row by row.
fn states(dir: &Path) -> PathBuf {
    let mut text =
        String::from("q1,q2,q3,q4,q5,q6,qd1,qd2,qd3,qd4,qd5,qd6,qdd1,qdd2,qdd3,qdd4,qdd5,qdd6\n");
    for k in 0..5 {
        let x = 0.3 * k as f64;
        let row: Vec<String> = (0..18)
            .map(|i| format!("{}", (x + 0.17 * i as f64).sin()))
            .collect();
        text.push_str(&row.join(","));
        text.push('\n');
    }
    write(dir, "states.csv", &text)
}

/// The torques of a `robid torques` output, row by row.
fn torques(csv: &str) -> Vec<Vec<f64>> {
    csv.lines()
        .skip(1)
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect()
}

/// Without `--parameters`, `robid torques` on a URDF is the rigid-body inverse dynamics of
/// the URDF as written: equal to the reader's chain with its inertials through the
/// interpreter (to the last printed digit: the output is Rust's shortest exact form).
#[test]
fn urdf_torques_without_parameters_use_its_own_inertials() {
    let dir = folder();
    let states = states(dir.path());
    let o = robid(&["torques", UR5, "--states", states.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let printed = torques(&stdout(&o));
    let chain = chain(UR5, None);
    let model = Interpreted::new(&chain.robot).unwrap();
    let base = urdf_base(&chain, &model);
    let text = std::fs::read_to_string(&states).unwrap();
    for (line, row) in text.lines().skip(1).zip(&printed) {
        let x: Vec<f64> = line.split(',').map(|v| v.parse().unwrap()).collect();
        let mut tau = vec![0.0; 6];
        model
            .inverse_dynamics_into(&x[..6], &x[6..12], &x[12..], &base, &mut tau)
            .unwrap();
        assert_eq!(&tau, row);
    }
    // the URDF's <dynamics> is named once, as not part of the model
    assert_eq!(stderr(&o).matches("<dynamics").count(), 1, "{}", stderr(&o));
}

/// `--tip` chooses the chain of a tree, and the errors speak of the flags.
#[test]
fn urdf_chain_flags() {
    let o = robid(&["model", PANDA]);
    fails_with(
        &o,
        &[
            "--tip:",
            "panda_hand_tcp",
            "panda_leftfinger",
            "panda_rightfinger",
        ],
    );
    let o = robid(&["model", PANDA, "--tip", "panda_hand"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stdout(&o).contains("(7 DOF, modified DH)"),
        "{}",
        stdout(&o)
    );
    // which URDF joint each row is, and what the last link carries
    assert!(
        stdout(&o)
            .contains("7  joint `panda_joint7` moves `panda_link7`, with panda_link8, panda_hand"),
        "{}",
        stdout(&o)
    );
    let o = robid(&["model", PANDA, "--tip", "panda_hnd"]);
    fails_with(&o, &["--tip:", "no link `panda_hnd`", "panda_hand"]);
    // nothing movable between the two links given: both flags, both links (it used to
    // blame --tip alone)
    let o = robid(&["model", UR5, "--base", "wrist_3_link", "--tip", "tool0"]);
    fails_with(
        &o,
        &[
            "error: --base and --tip: no movable (revolute, continuous or prismatic) joint lies \
           between the base link `wrist_3_link` and the tip link `tool0`; choose a base and a \
           tip below it",
        ],
    );
    let o = robid(&["model", "descriptions/ur5e.toml", "--base", "base_link"]);
    fails_with(
        &o,
        &["--base chooses the chain of a URDF", "TOML description"],
    );
    // a TOML description still needs parameters
    let dir = folder();
    let states = states(dir.path());
    let o = robid(&[
        "torques",
        "descriptions/ur5e.toml",
        "--states",
        states.to_str().unwrap(),
    ]);
    fails_with(&o, &["--parameters", "only a URDF description carries"]);
}

/// Identified base parameters of the UR5 whose links are the URDF's scaled by 1.2 (a
/// heavier robot of the same shape), each with a deviation of 1e-6.
fn identified(dir: &Path) -> PathBuf {
    let chain = chain(UR5, None);
    let model = Interpreted::new(&chain.robot).unwrap();
    let base = urdf_base(&chain, &model);
    let entries: Vec<String> = base
        .iter()
        .enumerate()
        .map(|(i, v)| {
            let name = model.base_parameter_name(i).unwrap();
            format!(
                "{{\"name\": \"{name}\", \"value\": {:e}, \"std\": 1e-6}}",
                1.2 * v
            )
        })
        .collect();
    write(
        dir,
        "identified.json",
        &format!("{{\"parameters\": [{}]}}", entries.join(", ")),
    )
}

/// `robid feasible` on a URDF writes the user's own file back with only the chain links'
/// `<inertial>` elements changed, and reading it gives the torques of the same solution
/// written as a parameter file (1e-12: the URDF holds the values in another form, centre
/// of mass and inertia about it in the link frame).
#[test]
fn feasible_writes_the_users_urdf_back() {
    let dir = folder();
    let identified = identified(dir.path());
    let solve = |output: &str| {
        let path = dir.path().join(output);
        let o = robid(&[
            "feasible",
            UR5,
            "--identified",
            identified.to_str().unwrap(),
            "-o",
            path.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        assert!(
            stderr(&o).contains("prior: the URDF's own"),
            "{}",
            stderr(&o)
        );
        path
    };
    let (urdf, toml) = (solve("ur5.urdf"), solve("ur5.toml"));
    // every line outside the <inertial> elements as it was
    let outside = |text: &str| -> Vec<String> {
        let mut inside = false;
        let mut kept = Vec::new();
        for line in text.lines() {
            let t = line.trim();
            if t.starts_with("<inertial") {
                inside = true;
            }
            if !inside {
                kept.push(line.to_owned());
            }
            if t.starts_with("</inertial") {
                inside = false;
            }
        }
        kept
    };
    let original = std::fs::read_to_string(asset(UR5)).unwrap();
    let written = std::fs::read_to_string(&urdf).unwrap();
    assert_ne!(original, written);
    assert_eq!(outside(&original), outside(&written));
    let states = states(dir.path());
    let from_urdf = robid(&[
        "torques",
        urdf.to_str().unwrap(),
        "--states",
        states.to_str().unwrap(),
    ]);
    let from_toml = robid(&[
        "torques",
        UR5,
        "--parameters",
        toml.to_str().unwrap(),
        "--states",
        states.to_str().unwrap(),
    ]);
    assert!(from_urdf.status.success(), "{}", stderr(&from_urdf));
    assert!(from_toml.status.success(), "{}", stderr(&from_toml));
    let (a, b) = (torques(&stdout(&from_urdf)), torques(&stdout(&from_toml)));
    for (x, y) in a.iter().zip(&b) {
        let scale = y.iter().fold(1.0_f64, |m, v| m.max(v.abs()));
        for (p, q) in x.iter().zip(y) {
            assert!((p - q).abs() <= 1e-12 * scale, "{p} vs {q}");
        }
    }
    // the written inertials reproduce the identified robot: 1.2 times the URDF's torques
    let scaled = robid(&["torques", UR5, "--states", states.to_str().unwrap()]);
    let c = torques(&stdout(&scaled));
    for (x, y) in a.iter().zip(&c) {
        let scale = y.iter().fold(1.0_f64, |m, v| m.max(v.abs()));
        for (p, q) in x.iter().zip(y) {
            assert!((p - 1.2 * q).abs() <= 1e-4 * scale, "{p} vs 1.2 x {q}");
        }
    }
}

/// Kinova's Jaco 2 of example-robot-data (joints 1, 4 and 6 continuous).
const KINOVA: &str = "../data/example_robot_data/kinova/kinova.urdf";

/// The lowest and highest value of each column `q1..q6` of a trajectory file.
fn position_ranges(path: &Path) -> Vec<[f64; 2]> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut ranges = vec![[f64::INFINITY, f64::NEG_INFINITY]; 6];
    for line in text.lines().skip(1) {
        let row: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
        for (r, q) in ranges.iter_mut().zip(&row[1..7]) {
            *r = [r[0].min(*q), r[1].max(*q)];
        }
    }
    ranges
}

/// `robid excite` on a URDF with continuous joints, whose `<limit>` lower and upper URDF
/// ignores: each stays within ±pi of its start, with a warning that says so and how to
/// choose another range, instead of advice to add limits the file already has.
#[test]
fn excite_keeps_continuous_joints_within_a_turn_of_their_start() {
    let dir = folder();
    let design = [
        "--acceleration-limits",
        "2",
        "--duration",
        "10",
        "--rate",
        "20",
        "--restarts",
        "1",
        "--evaluations",
        "20",
    ];
    let excite = |start: &[&str], output: &str| {
        let output = dir.path().join(output);
        let mut args = vec!["excite", KINOVA, "-o", output.to_str().unwrap()];
        args.extend(design);
        args.extend(start);
        (robid(&args), output)
    };
    let (o, output) = excite(&[], "centred.csv");
    assert!(o.status.success(), "{}", stderr(&o));
    let err = stderr(&o);
    let warned: Vec<&str> = err.lines().filter(|l| l.contains("continuous")).collect();
    assert_eq!(warned.len(), 1, "{err}");
    assert!(
        warned[0].starts_with(
            "warning: joints 1 (`j2s6s200_joint_1`), 4 (`j2s6s200_joint_4`) and 6 \
             (`j2s6s200_joint_6`) are continuous, without position limits: the design keeps \
             each within ±pi of its start"
        ),
        "{}",
        warned[0]
    );
    assert!(warned[0].contains("`type=\"revolute\"`"), "{}", warned[0]);
    let ranges = position_ranges(&output);
    for j in [0, 3, 5] {
        let [lo, hi] = ranges[j];
        assert!(
            -PI <= lo && hi <= PI && hi - lo > 0.1,
            "q{}: {lo} {hi}",
            j + 1
        );
    }
    // a start beyond ±pi is a start like any other for a joint that turns without end
    let (o, output) = excite(&["--start", "4,3,3,-4,3,7"], "turned.csv");
    assert!(o.status.success(), "{}", stderr(&o));
    for (j, centre) in [(0, 4.0), (3, -4.0), (5, 7.0)] {
        let [lo, hi] = position_ranges(&output)[j];
        assert!(
            centre - PI <= lo && hi <= centre + PI,
            "q{}: {lo} {hi}",
            j + 1
        );
    }
    // a limit a continuous joint does carry is asked for as it is
    let text = std::fs::read_to_string(asset(KINOVA)).unwrap().replacen(
        " velocity=\"0.628318530718\"",
        "",
        1,
    );
    let urdf = write(dir.path(), "kinova.urdf", &text);
    let o = robid(&[
        "excite",
        urdf.to_str().unwrap(),
        "-o",
        dir.path().join("no.csv").to_str().unwrap(),
        "--acceleration-limits",
        "2",
    ]);
    fails_with(
        &o,
        &[
            "kinova.urdf: joint 1 (`j2s6s200_joint_1`) has no velocity limit",
            "--velocity-limits",
        ],
    );
    assert!(!stderr(&o).contains("lower"), "{}", stderr(&o));
}

/// A continuous joint without `<limit>` (valid URDF: Bravo 7, SCARA quills) has no velocity
/// limit. `robid excite` names the joint and the file and points to `--velocity-limits`,
/// which supplies it (one value for every joint, or one per joint, in range); it used to
/// ask for a `velocity` in a `<limit>` element the joint does not have, with no way out
/// but editing the file.
#[test]
fn excite_takes_velocity_limits_a_urdf_lacks() {
    let dir = folder();
    let urdf = write(
        dir.path(),
        "arm.urdf",
        r#"<?xml version="1.0"?>
<robot name="arm">
  <link name="base"/>
  <link name="l1"><inertial><origin xyz="0.1 0 0"/><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <link name="l2"><inertial><origin xyz="0.1 0 0"/><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <joint name="shoulder" type="revolute">
    <parent link="base"/><child link="l1"/><origin xyz="0 0 0.3" rpy="1.5707963267948966 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-2" upper="2" effort="10" velocity="2"/>
  </joint>
  <joint name="wrist_roll" type="continuous">
    <parent link="l1"/><child link="l2"/><origin xyz="0.4 0 0" rpy="0 1.5707963267948966 0"/><axis xyz="0 0 1"/>
  </joint>
</robot>
"#,
    );
    let output = dir.path().join("traj.csv");
    let excite = |extra: &[&str]| {
        let mut args = vec![
            "excite",
            urdf.to_str().unwrap(),
            "-o",
            output.to_str().unwrap(),
            "--acceleration-limits",
            "5",
            "--duration",
            "10",
            "--rate",
            "20",
            "--restarts",
            "1",
            "--evaluations",
            "20",
        ];
        args.extend(extra);
        robid(&args)
    };
    let o = excite(&[]);
    fails_with(
        &o,
        &[
            "arm.urdf: joint 2 (`wrist_roll`) has no velocity limit",
            "give --velocity-limits v1,v2 (",
        ],
    );
    assert!(!output.exists());
    // one value for every joint, or one per joint: the given one is the limit
    for limits in ["1.5", "2,1.5"] {
        let o = excite(&["--velocity-limits", limits]);
        assert!(o.status.success(), "{limits}: {}", stderr(&o));
        let text = std::fs::read_to_string(&output).unwrap();
        let peak = |column: usize| {
            text.lines()
                .skip(1)
                .map(|line| {
                    line.split(',')
                        .nth(column)
                        .unwrap()
                        .parse::<f64>()
                        .unwrap()
                        .abs()
                })
                .fold(0.0, f64::max)
        };
        let (qd1, qd2) = (peak(3), peak(4));
        assert!(0.0 < qd2 && qd2 <= 1.5, "{limits}: qd2 peaks at {qd2}");
        // the flag replaces the URDF's own 2 rad/s of joint 1 too
        let limit = if limits == "1.5" { 1.5 } else { 2.0 };
        assert!(0.0 < qd1 && qd1 <= limit, "{limits}: qd1 peaks at {qd1}");
    }
    // a wrong count names the joints; a value out of range is refused by the parser
    fails_with(
        &excite(&["--velocity-limits", "1,2,3"]),
        &[
            "--velocity-limits has 3 values but",
            "has 2 joints; give one value or v1,v2",
        ],
    );
    let o = excite(&["--velocity-limits", "0"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("0 is outside [1e-6, 1e4] rad/s"),
        "{}",
        stderr(&o)
    );
    let o = excite(&["--velocity-limits", "1e5"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    // a TOML description without velocity limits: the same way out
    let toml = write(
        dir.path(),
        "planar.toml",
        "name = \"planar\"\nconvention = \"modified\"\ngravity = [0, -9.81, 0]\n\
         [[joints]]\nalpha = 0\na = 0\nd = 0\nlimits = { position = [-3, 3], acceleration = 10 }\n\
         [[joints]]\nalpha = 0\na = 0.5\nd = 0\nlimits = { position = [-3, 3], acceleration = 10 }\n",
    );
    let design = [
        "--duration",
        "10",
        "--rate",
        "20",
        "--restarts",
        "1",
        "--evaluations",
        "20",
    ];
    let mut args = vec![
        "excite",
        toml.to_str().unwrap(),
        "-o",
        output.to_str().unwrap(),
    ];
    args.extend(design);
    fails_with(
        &robid(&args),
        &[
            // the joint's table, by its line (it named the file alone)
            "planar.toml:4:1: joint 1 has no velocity limit",
            "or give --velocity-limits v1,v2 (",
        ],
    );
    args.extend(["--velocity-limits", "1"]);
    let o = robid(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    // a joint without position limits: its table's line too
    let unlimited = write(
        dir.path(),
        "unlimited.toml",
        "name = \"planar\"\nconvention = \"modified\"\ngravity = [0, -9.81, 0]\n\
         [[joints]]\nalpha = 0\na = 0\nd = 0\nlimits = { position = [-3, 3], acceleration = 10 }\n\
         \n[[joints]]\nalpha = 0\na = 0.5\nd = 0\n",
    );
    args[1] = unlimited.to_str().unwrap();
    fails_with(
        &robid(&args),
        &["unlimited.toml:10:1: joint 2 has no position limit; add `limits = {"],
    );
    // a revolute joint without <limit> (urdfdom refuses it, robid reads it): named, and
    // told what to write, not to change a <limit> element it does not have
    let revolute = write(
        dir.path(),
        "revolute.urdf",
        &std::fs::read_to_string(&urdf)
            .unwrap()
            .replace(r#"type="continuous""#, r#"type="revolute""#),
    );
    let mut args = vec![
        "excite",
        revolute.to_str().unwrap(),
        "-o",
        output.to_str().unwrap(),
        "--acceleration-limits",
        "5",
        "--velocity-limits",
        "1",
    ];
    args.extend(design);
    // the reader's warning first (the file is no valid URDF for ROS tools), then excite's
    // own error, unchanged
    let o = robid(&args);
    assert!(
        stderr(&o).contains(
            "warning: ",
        ) && stderr(&o).contains(
            "revolute.urdf:10:3: joint `wrist_roll` is revolute but has no `<limit>`: robid reads \
             it without position, velocity or torque limits, but the URDF format requires the \
             element"
        ),
        "{}",
        stderr(&o)
    );
    fails_with(
        &o,
        &[
            "revolute.urdf: joint 2 (`wrist_roll`) has no position limits; give the joint \
             `lower` and `upper` in its <limit> element (<limit lower=\"..\" upper=\"..\"",
        ],
    );
}

/// Two joints; `flange`, which joint 2 moves, has no `<inertial>` (as every link of
/// ROS-Industrial's support packages), and `tool0` hangs from it on a fixed joint.
const MASSLESS_FLANGE: &str = r#"<?xml version="1.0"?>
<robot name="flanged">
  <link name="base"/>
  <link name="l1"><inertial><origin xyz="0.1 0 0"/><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <link name="flange"/>
  <link name="tool0"/>
  <joint name="j1" type="revolute">
    <parent link="base"/><child link="l1"/><origin xyz="0 0 0.3"/><axis xyz="0 0 1"/>
    <limit lower="-2" upper="2" effort="10" velocity="2"/>
  </joint>
  <joint name="j2" type="revolute">
    <parent link="l1"/><child link="flange"/><origin xyz="0.4 0 0" rpy="1.5707963267948966 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-2" upper="2" effort="10" velocity="2"/>
  </joint>
  <joint name="flange-tool0" type="fixed">
    <parent link="flange"/><child link="tool0"/><origin xyz="0 0 0.1"/>
  </joint>
</robot>
"#;

/// `robid simulate` of a URDF whose joint moves only links without `<inertial>` (legal
/// URDF): the mass matrix is singular because that joint moves nothing, so the joint and
/// its links are named with the two ways out, instead of "the parameters are not
/// physically consistent; use robid feasible" (they are consistent, and feasible needs an
/// identification the user does not have). A parameter file that leaves a link empty is
/// told the same way, by joint number.
#[test]
fn simulate_names_a_joint_that_moves_only_massless_links() {
    let dir = folder();
    let urdf = write(dir.path(), "flanged.urdf", MASSLESS_FLANGE);
    let mut trajectory = String::from("t,q1,q2,qd1,qd2,qdd1,qdd2\n");
    for k in 0..20 {
        trajectory.push_str(&format!("{},0,0,0,0,0,0\n", 0.01 * k as f64));
    }
    let trajectory = write(dir.path(), "traj.csv", &trajectory);
    let output = dir.path().join("data.csv");
    let simulate = |urdf: &Path, extra: &[&str]| {
        let mut args = vec![
            "simulate",
            urdf.to_str().unwrap(),
            "--trajectory",
            trajectory.to_str().unwrap(),
            "-o",
            output.to_str().unwrap(),
        ];
        args.extend(extra);
        robid(&args)
    };
    let not_blamed = |o: &std::process::Output| {
        let e = stderr(o);
        assert!(
            !e.contains("physically consistent") && !e.contains("robid feasible"),
            "{e}"
        );
        assert!(!output.exists());
    };
    let o = simulate(&urdf, &[]);
    fails_with(
        &o,
        &[
            "error: joint 2 (`j2`) of ",
            "flanged.urdf moves only links without mass or inertia: `flange`, `tool0` (no \
             `<inertial>` element",
            "so no torque accelerates it",
            "give these links `<inertial>` elements with their mass and inertia, or give \
             --parameters PARAMS.toml",
        ],
    );
    not_blamed(&o);
    // no inertial at all: every joint, every link
    let bare = write(
        dir.path(),
        "bare.urdf",
        &MASSLESS_FLANGE.replace(
            r#"<inertial><origin xyz="0.1 0 0"/><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>"#,
            "",
        ),
    );
    let o = simulate(&bare, &[]);
    fails_with(
        &o,
        &[
            "error: joints 1 (`j1`) and 2 (`j2`) of ",
            "move only links without mass or inertia: `l1`, `flange`, `tool0`",
        ],
    );
    not_blamed(&o);
    // a parameter file that leaves link 2 empty: the joint by its number
    let parameters = write(
        dir.path(),
        "link1.toml",
        "[standard]\nXX1 = 0.01\nYY1 = 0.02\nZZ1 = 0.02\nMX1 = 0.1\nM1 = 1\n",
    );
    let o = simulate(&urdf, &["--parameters", parameters.to_str().unwrap()]);
    fails_with(
        &o,
        &[
            "is singular: joint 2 moves no mass or inertia (M22 = 0)",
            "give that link its mass and inertia",
        ],
    );
    not_blamed(&o);
}

/// A URDF whose flange's values are written as 1e-320 to mean 0 (or lie below 1e-12 of the
/// chain's largest) is told as one whose flange is empty: `torques` warns that joint 2's
/// torque is "0 or negligible", `simulate` refuses the run naming the joint and links, as
/// for a flange without `<inertial>`, and a flange with inertia but a negligible mass gets
/// the warning of a massless link. Only exact zeros counted: the run wrote torques of
/// 1e-321 N m (no digits) as data, and no warning was given.
#[test]
fn negligible_inertials_count_as_none() {
    let dir = folder();
    let flange = |m: &str, i: &str| {
        MASSLESS_FLANGE.replace(
            r#"<link name="flange"/>"#,
            &format!(
                r#"<link name="flange"><inertial><mass value="{m}"/><inertia ixx="{i}" ixy="0" ixz="0" iyy="{i}" iyz="0" izz="{i}"/></inertial></link>"#
            ),
        )
    };
    let rows = write(
        dir.path(),
        "rows.csv",
        "q1,q2,qd1,qd2,qdd1,qdd2\n0.1,0.2,0.3,0.4,0.5,0.6\n1,1,1,1,1,1\n",
    );
    let mut trajectory = String::from("t,q1,q2,qd1,qd2,qdd1,qdd2\n");
    for k in 0..20 {
        trajectory.push_str(&format!("{},0,0,0,0,0,0\n", 0.01 * k as f64));
    }
    let trajectory = write(dir.path(), "traj.csv", &trajectory);
    let output = dir.path().join("data.csv");
    for (m, i) in [("1e-320", "1e-320"), ("1e-14", "1e-15")] {
        let urdf = write(dir.path(), "tiny.urdf", &flange(m, i));
        let o = robid(&[
            "torques",
            urdf.to_str().unwrap(),
            "--states",
            rows.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        let e = stderr(&o);
        assert!(
            e.contains(&format!(
                "warning: joint 2 (`j2`) of {} moves only links without mass or inertia: \
                 `flange`, `tool0` (no `<inertial>` element, an empty one, or values \
                 negligible beside the chain's largest: below 1e-12 of it, or subnormal such as \
                 1e-320), so with the URDF's own inertials its torque tau2 is 0 or negligible \
                 in every row",
                urdf.display()
            )),
            "{m}: {e}"
        );
        let o = robid(&[
            "simulate",
            urdf.to_str().unwrap(),
            "--trajectory",
            trajectory.to_str().unwrap(),
            "-o",
            output.to_str().unwrap(),
        ]);
        fails_with(
            &o,
            &[
                "error: joint 2 (`j2`) of ",
                "tiny.urdf moves only links without mass or inertia: `flange`, `tool0`",
                "so no torque accelerates it",
                "or give --parameters PARAMS.toml",
            ],
        );
        assert!(!output.exists());
    }
    // inertia with a mass of 1e-320: the warning of a link without mass
    let urdf = write(dir.path(), "spinning.urdf", &flange("1e-320", "0.01"));
    let o = robid(&[
        "torques",
        urdf.to_str().unwrap(),
        "--states",
        rows.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let e = stderr(&o);
    for part in [
        "link `flange`: the mass 1e-320 kg is negligible (below 1e-12 of the chain's largest, 1 \
         kg, or subnormal), as good as 0, but the inertia is not",
        "joint 2 (`j2`) of ",
        "spinning.urdf moves only links without mass: `flange`, `tool0` (masses 0 or negligible \
         beside the chain's largest: below 1e-12 of it, or subnormal such as 1e-320), so with \
         the URDF's own inertials its torque tau2 holds no gravity",
    ] {
        assert!(e.contains(part), "expected {part:?} in {e}");
    }
}

/// The inertial of `l1` in [`MASSLESS_FLANGE`].
const L1_INERTIAL: &str = r#"<inertial><origin xyz="0.1 0 0"/><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>"#;

/// A parameter file for [`MASSLESS_FLANGE`] that gives both links mass and inertia.
const FLANGED_PARAMETERS: &str = "[standard]\nXX1 = 0.01\nYY1 = 0.02\nZZ1 = 0.02\nMX1 = 0.1\n\
    M1 = 1\nXX2 = 0.01\nYY2 = 0.01\nZZ2 = 0.01\nMZ2 = 0.05\nM2 = 0.5\n";

/// `robid torques` with a URDF's own inertials, where a joint moves only links without
/// `<inertial>`: that joint's torque is 0 in every row, which used to be written without
/// a word; it is warned about naming the joint, its links and the ways out (the output is
/// still written: it is the URDF as written). A joint that moves links with inertia but
/// no mass is told that its torque holds no gravity. A parameter file, or a URDF whose
/// every joint moves mass, gives no such warning.
#[test]
fn torques_warn_about_a_joint_that_moves_only_massless_links() {
    let dir = folder();
    let urdf = write(dir.path(), "flanged.urdf", MASSLESS_FLANGE);
    let mut text = String::from("q1,q2,qd1,qd2,qdd1,qdd2\n");
    for k in 0..5 {
        let x = 0.2 * k as f64;
        text.push_str(&format!("{x},{},{},0.5,1,{}\n", 1.0 - x, 0.3 + x, 2.0 - x));
    }
    let rows = write(dir.path(), "rows.csv", &text);
    let torques = |urdf: &Path, extra: &[&str]| {
        let mut args = vec![
            "torques",
            urdf.to_str().unwrap(),
            "--states",
            rows.to_str().unwrap(),
        ];
        args.extend(extra);
        let o = robid(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        o
    };
    let column = |o: &std::process::Output, j: usize| -> Vec<f64> {
        stdout(o)
            .lines()
            .skip(1)
            .map(|l| l.split(',').nth(j).unwrap().parse().unwrap())
            .collect()
    };
    let o = torques(&urdf, &[]);
    let warning = format!(
        "warning: joint 2 (`j2`) of {} moves only links without mass or inertia: `flange`, \
         `tool0` (no `<inertial>` element, or an empty one), so with the URDF's own inertials \
         its torque tau2 is 0 in every row; give these links `<inertial>` elements with their \
         mass and inertia, or give --parameters PARAMS.toml (a [standard] or [base] parameter \
         file)\n",
        urdf.display()
    );
    assert!(stderr(&o).ends_with(&warning), "{}", stderr(&o));
    assert!(column(&o, 1).iter().all(|&t| t == 0.0), "{}", stdout(&o));
    assert!(column(&o, 0).iter().all(|&t| t != 0.0), "{}", stdout(&o));
    // no inertial at all: every joint, every link
    let bare = write(
        dir.path(),
        "bare.urdf",
        &MASSLESS_FLANGE.replace(L1_INERTIAL, ""),
    );
    let o = torques(&bare, &[]);
    assert!(
        stderr(&o).contains("warning: joints 1 (`j1`) and 2 (`j2`) of ",)
            && stderr(&o).contains(
                "move only links without mass or inertia: `l1`, `flange`, `tool0` (no \
             `<inertial>` element, or an empty one), so with the URDF's own inertials their \
             torques tau1 and tau2 are 0 in every row"
            ),
        "{}",
        stderr(&o)
    );
    // inertia without mass: no gravity in joint 2's torque, which is not 0
    let spinning = write(
        dir.path(),
        "spinning.urdf",
        &MASSLESS_FLANGE.replace(
            r#"<link name="flange"/>"#,
            r#"<link name="flange"><inertial><mass value="0"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.02"/></inertial></link>"#,
        ),
    );
    let o = torques(&spinning, &[]);
    let warning = format!(
        "warning: joint 2 (`j2`) of {} moves only links without mass: `flange`, `tool0`, so \
         with the URDF's own inertials its torque tau2 holds no gravity, only the inertia of \
         these links; give them their masses in their `<inertial>` elements, or give \
         --parameters PARAMS.toml (a [standard] or [base] parameter file)\n",
        spinning.display()
    );
    assert!(stderr(&o).ends_with(&warning), "{}", stderr(&o));
    assert!(column(&o, 1).iter().any(|&t| t != 0.0), "{}", stdout(&o));
    // a parameter file gives joint 2 its mass: no warning
    let parameters = write(dir.path(), "params.toml", FLANGED_PARAMETERS);
    let o = torques(&urdf, &["--parameters", parameters.to_str().unwrap()]);
    assert!(!stderr(&o).contains("moves only links"), "{}", stderr(&o));
    assert!(!stderr(&o).contains("no mass or inertia"), "{}", stderr(&o));
    assert!(column(&o, 1).iter().all(|&t| t != 0.0), "{}", stdout(&o));
    // a parameter file that leaves link 2 empty: joint 2's torque is 0 in every row, told
    // as for the URDF's own inertials (it used to be written without a word)
    let link1 = write(
        dir.path(),
        "link1.toml",
        "[standard]\nXX1 = 0.01\nYY1 = 0.02\nZZ1 = 0.02\nMX1 = 0.1\nM1 = 1\n",
    );
    let o = torques(&urdf, &["--parameters", link1.to_str().unwrap()]);
    let e = stderr(&o);
    assert!(
        e.starts_with(&format!(
            "warning: with the parameters of {}, joint 2 (`j2`) of {} moves no mass or \
             inertia that its torque feels: every base parameter its torque depends on (",
            link1.display(),
            urdf.display()
        )) && e.ends_with(&format!(
            ") is 0, so its torque tau2 is 0 in every row; give the links from link 2 on \
             their masses and inertias in {}, mass off a revolute joint's axis or inertia \
             about it (a standard parameter it does not name counts as 0)\n",
            link1.display()
        )),
        "{e}"
    );
    assert!(column(&o, 1).iter().all(|&t| t == 0.0), "{}", stdout(&o));
    // link 2 at 1e-320 (denormal torques, which used to pass as a load): the same, told
    // as negligible
    let denormal = write(
        dir.path(),
        "denormal.toml",
        &format!(
            "{}XX2 = 1e-320\nYY2 = 1e-320\nZZ2 = 1e-320\nM2 = 1e-320\n",
            std::fs::read_to_string(&link1).unwrap()
        ),
    );
    let o = torques(&urdf, &["--parameters", denormal.to_str().unwrap()]);
    let e = stderr(&o);
    assert!(
        e.contains(&format!(
            "joint 2 (`j2`) of {} moves no mass or inertia to speak of that its torque feels: \
             every base parameter its torque depends on (",
            urdf.display()
        )) && e.contains(
            ") is 0 or negligible: its torque stays below 1e-12 of the largest joint's, or \
             below 1e-15 N m, so its torque tau2 is 0 or negligible in every row; give the \
             links from link 2 on"
        ),
        "{e}"
    );
    assert!(
        column(&o, 1).iter().all(|&t| t.abs() < 1e-300),
        "{}",
        stdout(&o)
    );
    // an empty [standard] table: every joint
    let nothing = write(dir.path(), "nothing.toml", "[standard]\n");
    let o = torques(&urdf, &["--parameters", nothing.to_str().unwrap()]);
    assert!(
        stderr(&o).contains("joints 1 (`j1`) and 2 (`j2`) of ")
            && stderr(&o).contains("so their torques tau1 and tau2 are 0 in every row"),
        "{}",
        stderr(&o)
    );
    // a URDF whose every joint moves mass: no warning
    let states = states(dir.path());
    let o = robid(&["torques", UR5, "--states", states.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!stderr(&o).contains("without mass"), "{}", stderr(&o));
}

/// `robid excite` with a URDF's own inertials, where a joint moves only links without
/// `<inertial>`: the design's criterion uses the regressor, which does not depend on the
/// parameters, so that is no matter for it; but the torque limit of such a joint (its
/// `effort`) is checked against a torque that is 0, so it constrains nothing and its
/// margin is the whole limit. That is warned about naming the joint; without a torque limit
/// on it (effort 0: none), or with --parameters that give it a torque, nothing is said. A
/// parameter file that leaves its torque 0 is warned about as `robid torques --parameters`
/// warns (it used to be taken without a word), but only for a joint with a torque limit.
#[test]
fn excite_warns_when_a_massless_joint_has_a_torque_limit() {
    let dir = folder();
    let out = dir.path().join("trajectory.csv");
    let excite = |urdf: &Path, extra: &[&str]| {
        let mut args = vec![
            "excite",
            urdf.to_str().unwrap(),
            "--acceleration-limits",
            "10",
            "--duration",
            "10",
            "--rate",
            "50",
            "--harmonics",
            "2",
            "--restarts",
            "1",
            "--evaluations",
            "50",
            "-o",
            out.to_str().unwrap(),
        ];
        args.extend(extra);
        let o = robid(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        o
    };
    let urdf = write(dir.path(), "flanged.urdf", MASSLESS_FLANGE);
    let o = excite(&urdf, &[]);
    let warning = format!(
        "warning: joint 2 (`j2`) of {} moves only links without mass or inertia: `flange`, \
         `tool0` (no `<inertial>` element, or an empty one), so the URDF's own inertials give \
         it no torque: its torque limit (the `effort` of its <limit>) constrains \
         nothing in the design, and its torque margin below is the whole limit; give these \
         links `<inertial>` elements with their mass and inertia, or give --parameters \
         PARAMS.toml (the design's criterion does not depend on them)\n",
        urdf.display()
    );
    assert!(stderr(&o).contains(&warning), "{}", stderr(&o));
    // no torque limit on joint 2: the criterion is that of the regressor, unaffected
    let free = write(
        dir.path(),
        "free.urdf",
        &MASSLESS_FLANGE.replace(
            r#"<limit lower="-2" upper="2" effort="10" velocity="2"/>
  </joint>
  <joint name="flange-tool0""#,
            r#"<limit lower="-2" upper="2" effort="0" velocity="2"/>
  </joint>
  <joint name="flange-tool0""#,
        ),
    );
    assert_ne!(std::fs::read_to_string(&free).unwrap(), MASSLESS_FLANGE);
    let o = excite(&free, &[]);
    assert!(!stderr(&o).contains("without mass"), "{}", stderr(&o));
    let parameters = write(dir.path(), "params.toml", FLANGED_PARAMETERS);
    let o = excite(&urdf, &["--parameters", parameters.to_str().unwrap()]);
    assert!(!stderr(&o).contains("without mass"), "{}", stderr(&o));
    assert!(!stderr(&o).contains("no mass or inertia"), "{}", stderr(&o));
    // a parameter file that leaves link 2 empty: joint 2's torque limit constrains nothing
    let link1 = write(
        dir.path(),
        "link1.toml",
        "[standard]\nXX1 = 0.01\nYY1 = 0.02\nZZ1 = 0.02\nMX1 = 0.1\nM1 = 1\n",
    );
    let o = excite(&urdf, &["--parameters", link1.to_str().unwrap()]);
    let e = stderr(&o);
    assert!(
        e.contains(&format!(
            "warning: with the parameters of {}, joint 2 (`j2`) of {} moves no mass or \
             inertia that its torque feels: every base parameter its torque depends on (",
            link1.display(),
            urdf.display()
        )) && e.contains(&format!(
            ") is 0, so the reference gives it no torque: its torque limit constrains nothing \
             in the design, and its torque margin below is the whole limit; give the links \
             from link 2 on their masses and inertias in {}, mass off a revolute joint's axis \
             or inertia about it (a standard parameter it does not name counts as 0)\n",
            link1.display()
        )),
        "{e}"
    );
    // the same file with no torque limit on joint 2: nothing to say
    let o = excite(&free, &["--parameters", link1.to_str().unwrap()]);
    assert!(!stderr(&o).contains("no mass or inertia"), "{}", stderr(&o));
}

/// `robid simulate` without `--parameters` simulates a URDF whose chain has an inertial of
/// no body (here principal moments 1, 1, 100, which break the triangle inequality; M(q) is
/// positive definite with them), after the reader's warning naming the link and the
/// values: real vendor files have such inertials, and their torques are still worth
/// simulating; with `--parameters` no warning is needed for the parameters.
#[test]
fn simulate_warns_about_a_urdfs_inertials_of_no_body() {
    let dir = folder();
    let urdf = write(
        dir.path(),
        "placeholder.urdf",
        &MASSLESS_FLANGE.replace(
            r#"<link name="flange"/>"#,
            r#"<link name="flange"><inertial><mass value="1"/><inertia ixx="1" ixy="0" ixz="0" iyy="100" iyz="0" izz="1"/></inertial></link>"#,
        ),
    );
    let mut trajectory = String::from("t,q1,q2,qd1,qd2,qdd1,qdd2\n");
    for k in 0..20 {
        trajectory.push_str(&format!("{},0,0,0,0,0,0\n", 0.01 * k as f64));
    }
    let trajectory = write(dir.path(), "traj.csv", &trajectory);
    let output = dir.path().join("data.csv");
    let simulate = |extra: &[&str]| {
        let mut args = vec![
            "simulate",
            urdf.to_str().unwrap(),
            "--trajectory",
            trajectory.to_str().unwrap(),
            "-o",
            output.to_str().unwrap(),
        ];
        args.extend(extra);
        robid(&args)
    };
    let o = simulate(&[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("warning: ") && stderr(&o).contains("link `flange`: the principal"),
        "{}",
        stderr(&o)
    );
    assert!(output.exists());
    std::fs::remove_file(&output).unwrap();
    let parameters = write(
        dir.path(),
        "physical.toml",
        "[standard]\nXX1 = 0.01\nYY1 = 0.02\nZZ1 = 0.02\nMX1 = 0.1\nM1 = 1\n\
         XX2 = 0.01\nYY2 = 0.01\nZZ2 = 0.01\nM2 = 1\n",
    );
    let o = simulate(&["--parameters", parameters.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(output.exists());
}

/// The URDF's own inertials as the values of its chain's standard parameters (names and
/// values), as `robot_model!` and the reader give them.
fn urdf_standard(path: &str) -> (Vec<String>, Vec<f64>) {
    let chain = chain(path, None);
    let names = chain
        .robot
        .standard_parameters()
        .iter()
        .map(|p| p.to_string())
        .collect();
    (names, chain.standard_values(&chain.robot))
}

/// `robid emit` of a URDF prints the code `robot_model!(file = "x.urdf")` compiles (both
/// through `robid_symbolic::emit::model_tokens`), `URDF_STANDARD_PARAMETERS` included: the
/// file's own inertials, which it used to leave out.
#[test]
fn urdf_emit_holds_the_urdf_standard_parameters() {
    let (names, expected) = urdf_standard(UR5);
    assert_eq!(names.len(), 60);
    let o = robid(&["emit", UR5]);
    assert!(o.status.success(), "{}", stderr(&o));
    let code = stdout(&o);
    let (_, array) = code
        .split_once("pub const URDF_STANDARD_PARAMETERS: [f64; 60] = [")
        .unwrap_or_else(|| panic!("no URDF_STANDARD_PARAMETERS in {code}"));
    let emitted: Vec<f64> = array
        .split_once("];")
        .unwrap()
        .0
        .split(',')
        .map(str::trim)
        .filter(|v| !v.is_empty())
        .map(|v| v.trim_end_matches("f64").parse().unwrap())
        .collect();
    assert_eq!(emitted, expected);
    // a TOML description has no URDF inertials
    let o = robid(&["emit", "descriptions/ur5e.toml"]);
    assert!(!stdout(&o).contains("URDF_STANDARD_PARAMETERS"));
}
/// The values of `URDF_STANDARD_PARAMETERS` in the Rust code `robid emit` prints for
/// `path`, as written.
fn rust_urdf_standard(path: &str) -> Vec<f64> {
    let o = robid(&["emit", path]);
    assert!(o.status.success(), "{}", stderr(&o));
    let code = stdout(&o);
    let (_, array) = code
        .split_once("pub const URDF_STANDARD_PARAMETERS: [f64; ")
        .and_then(|(_, rest)| rest.split_once("] = ["))
        .unwrap_or_else(|| panic!("no URDF_STANDARD_PARAMETERS in {code}"));
    array
        .split_once("];")
        .unwrap()
        .0
        .split(',')
        .map(str::trim)
        .filter(|v| !v.is_empty())
        .map(|v| v.trim_end_matches("f64").parse().unwrap())
        .collect()
}

/// The C compiler, if there is one (`$CC`, else `cc`).
fn c_compiler() -> Option<String> {
    let cc = std::env::var("CC").unwrap_or_else(|_| "cc".to_owned());
    std::process::Command::new(&cc)
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success())
        .then_some(cc)
}

/// `robid emit ROBOT.urdf --lang c` holds the URDF's own inertials as
/// `NAME_urdf_standard_parameters`, as the Rust code holds `URDF_STANDARD_PARAMETERS` (it
/// used to leave them out): compiled warning-free (C99, -Wall -Wextra -pedantic) with a
/// program that prints them and passes them to `NAME_base_from_standard`, the values are
/// the Rust constant's to the last bit (with `--scalar float`, rounded to float) and the
/// base parameters those of the interpreter. A TOML description has no such array.
#[test]
fn urdf_emit_c_holds_the_urdf_standard_parameters() {
    let Some(cc) = c_compiler() else {
        eprintln!("skipped: no C compiler (set CC or install cc)");
        return;
    };
    let chain = chain(UR5, None);
    let prefix = chain.robot.name().to_lowercase();
    let rust = rust_urdf_standard(UR5);
    assert_eq!(rust, chain.standard_values(&chain.robot));
    let model = Interpreted::new(&chain.robot).unwrap();
    let base = urdf_base(&chain, &model);
    let (n, nb) = (rust.len(), base.len());
    let dir = folder();
    let d = dir.path();
    for real in ["double", "float"] {
        let source = d.join(format!("arm_{real}.c"));
        let o = robid(&[
            "emit",
            UR5,
            "--lang",
            "c",
            "--scalar",
            real,
            "-o",
            source.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        let header = std::fs::read_to_string(d.join(format!("arm_{real}.h"))).unwrap();
        assert!(
            header.contains(&format!(
                "extern const {real} {prefix}_urdf_standard_parameters[{n}];"
            )),
            "{header}"
        );
        assert!(
            header.contains(&format!(
                "in the order of\n   {prefix}_standard_parameter_names"
            )),
            "{header}"
        );
        let main = format!(
            "#include <stdio.h>\n#include \"arm_{real}.h\"\n\nint main(void)\n{{\n    \
             {real} base[{nb}];\n    int i;\n    \
             for (i = 0; i < {n}; i++) printf(\"%.17g \", (double){prefix}_urdf_standard_parameters[i]);\n    \
             printf(\"\\n\");\n    \
             {prefix}_base_from_standard({prefix}_urdf_standard_parameters, base);\n    \
             for (i = 0; i < {nb}; i++) printf(\"%.17g \", (double)base[i]);\n    \
             printf(\"\\n\");\n    return 0;\n}}\n"
        );
        write(d, &format!("main_{real}.c"), &main);
        let exe = d.join(format!("main_{real}"));
        let built = std::process::Command::new(&cc)
            .current_dir(d)
            .args(["-std=c99", "-Wall", "-Wextra", "-pedantic", "-Werror"])
            .args(["-Wno-unused-but-set-variable", "-o"])
            .arg(&exe)
            .args([
                format!("main_{real}.c"),
                format!("arm_{real}.c"),
                "-lm".into(),
            ])
            .output()
            .unwrap();
        assert!(
            built.status.success(),
            "{real}: {}",
            String::from_utf8_lossy(&built.stderr)
        );
        let ran = std::process::Command::new(&exe).output().unwrap();
        assert!(ran.status.success());
        let text = String::from_utf8(ran.stdout).unwrap();
        let lines: Vec<Vec<f64>> = text
            .lines()
            .map(|l| l.split_whitespace().map(|x| x.parse().unwrap()).collect())
            .collect();
        let (values, c_base) = (&lines[0], &lines[1]);
        if real == "double" {
            assert_eq!(values, &rust);
        } else {
            let rounded: Vec<f64> = rust.iter().map(|&x| f64::from(x as f32)).collect();
            assert_eq!(values, &rounded);
        }
        let tolerance = if real == "double" { 1e-12 } else { 1e-5 };
        let scale = base.iter().fold(1e-300_f64, |m, x| m.max(x.abs()));
        for (k, (c, r)) in c_base.iter().zip(&base).enumerate() {
            assert!(
                (c - r).abs() <= tolerance * scale,
                "{real}: base parameter {k}: C {c}, interpreter {r}"
            );
        }
    }
    let toml = d.join("ur5e.c");
    let o = robid(&[
        "emit",
        "descriptions/ur5e.toml",
        "--lang",
        "c",
        "-o",
        toml.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    for file in ["ur5e.c", "ur5e.h"] {
        let text = std::fs::read_to_string(d.join(file)).unwrap();
        assert!(!text.contains("urdf_standard_parameters"), "{file}");
    }
}

/// `robid model ROBOT.urdf --standard-parameters FILE` writes the URDF's own inertials as
/// a `[standard]` parameter file (the values of `URDF_STANDARD_PARAMETERS`, which no
/// subcommand used to write), which `torques --parameters` and `feasible --prior` read:
/// the torques are those of the URDF as written, to the last bit.
#[test]
fn urdf_standard_parameters_are_written_as_a_parameter_file() {
    let dir = folder();
    let (names, expected) = urdf_standard(UR5);
    let file = dir.path().join("ur5_standard.toml");
    let o = robid(&[
        "model",
        UR5,
        "--standard-parameters",
        file.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).contains("base parameters"), "{}", stdout(&o));
    let text = std::fs::read_to_string(&file).unwrap();
    let table = text.split_once("\n[standard]\n").unwrap().1;
    let written: Vec<(String, f64)> = table
        .lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| {
            let (name, value) = l.split_once(" = ").unwrap();
            (name.to_owned(), value.parse().unwrap())
        })
        .collect();
    let wanted: Vec<(String, f64)> = names.into_iter().zip(expected).collect();
    assert_eq!(written, wanted);
    assert!(
        text.contains("# link 1: joint `shoulder_pan_joint` moves `shoulder_link`"),
        "{text}"
    );
    // read by torques: the URDF's own torques
    let states = states(dir.path());
    let states = states.to_str().unwrap();
    let own = robid(&["torques", UR5, "--states", states]);
    let read = robid(&[
        "torques",
        UR5,
        "--states",
        states,
        "--parameters",
        file.to_str().unwrap(),
    ]);
    assert!(read.status.success(), "{}", stderr(&read));
    assert_eq!(stdout(&read), stdout(&own));
    // read by feasible as the prior
    let identified = identified(dir.path());
    let out = dir.path().join("feasible.toml");
    let o = robid(&[
        "feasible",
        UR5,
        "--identified",
        identified.to_str().unwrap(),
        "--prior",
        file.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    // a TOML description has no inertials to write
    let none = dir.path().join("none.toml");
    let o = robid(&[
        "model",
        "descriptions/ur5e.toml",
        "--standard-parameters",
        none.to_str().unwrap(),
    ]);
    fails_with(
        &o,
        &[
            "--standard-parameters writes a URDF's own <inertial> elements, but \
             descriptions/ur5e.toml is a TOML description",
        ],
    );
    assert!(!none.exists());
}

/// `robid model ROBOT.urdf --write-description FILE` writes the DH table fitted to the
/// chain as a description file: given to `torques` with the URDF's own inertials it gives
/// the URDF's torques byte for byte, and it names the file it came from; the same path
/// for both outputs is refused and neither is written.
#[test]
fn urdf_chain_is_written_as_a_description() {
    let dir = folder();
    let description = dir.path().join("ur5.toml");
    let standard = dir.path().join("ur5_standard.toml");
    let o = robid(&[
        "model",
        UR5,
        "--write-description",
        description.to_str().unwrap(),
        "--standard-parameters",
        standard.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = std::fs::read_to_string(&description).unwrap();
    assert!(
        text.starts_with("# The DH table robid fitted to the chain of ")
            && text.contains("ur5_robot.urdf")
            && text.contains("calibrated = true")
            && text.contains("alpha = \"-pi/2\"")
            && text.contains(
                "# joint 2: URDF joint `shoulder_lift_joint` moves `upper_arm_link`\n[[joints]]\n"
            ),
        "{text}"
    );
    let states = states(dir.path());
    let states = states.to_str().unwrap();
    let own = robid(&["torques", UR5, "--states", states]);
    let written = robid(&[
        "torques",
        description.to_str().unwrap(),
        "--states",
        states,
        "--parameters",
        standard.to_str().unwrap(),
    ]);
    assert!(written.status.success(), "{}", stderr(&written));
    assert_eq!(stdout(&written), stdout(&own));
    let same = dir.path().join("same.toml");
    let o = robid(&[
        "model",
        UR5,
        "--write-description",
        same.to_str().unwrap(),
        "--standard-parameters",
        same.to_str().unwrap(),
    ]);
    assert!(!o.status.success());
    assert!(!same.exists(), "{}", stderr(&o));
}

/// A URDF's continuous joint has no position limit, and a description no continuous
/// joint type: the written description says so at the joint, with the limit `robid
/// excite` needs (which refused the description with "no position limit" and nothing
/// more); a revolute joint with limits gets no such line.
#[test]
fn a_continuous_joint_is_told_in_the_written_description() {
    let dir = folder();
    let description = dir.path().join("kinova.toml");
    let o = robid(&[
        "model",
        KINOVA,
        "--write-description",
        description.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = std::fs::read_to_string(&description).unwrap();
    let told = "# continuous in the URDF: no position limit here; `robid excite` needs one, \
                `position = [-3.1416, 3.1416]` in `limits` keeps it within a turn";
    for joint in ["j2s6s200_joint_1", "j2s6s200_joint_4", "j2s6s200_joint_6"] {
        let at = text.find(&format!("URDF joint `{joint}`")).unwrap();
        let line_end = at + text[at..].find('\n').unwrap() + 1;
        assert!(text[line_end..].starts_with(told), "{joint}: {text}");
    }
    assert_eq!(text.matches(told).count(), 3, "{text}");
}

/// `robid emit` of a URDF whose links after a joint have no mass or inertia warns that the
/// URDF's own inertials held in the code leave that joint's torque 0, in Rust and in C (it
/// wrote the all-zero values without a word); the code is written all the same, and a URDF
/// with every inertial gets no warning.
#[test]
fn urdf_emit_warns_when_the_urdf_inertials_leave_a_torque_out() {
    let dir = folder();
    let urdf = write(dir.path(), "flanged.urdf", MASSLESS_FLANGE);
    let cause = format!(
        "warning: joint 2 (`j2`) of {} moves only links without mass or inertia: `flange`, \
         `tool0` (no `<inertial>` element, or an empty one), so with the URDF's own inertials",
        urdf.display()
    );
    let o = robid(&["emit", urdf.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).contains("URDF_STANDARD_PARAMETERS"));
    let e = stderr(&o);
    assert!(e.contains(&cause), "{e}");
    assert!(
        e.contains(
            "(`URDF_STANDARD_PARAMETERS` in the code) its torque tau2 is 0 at every state; \
             give these links `<inertial>` elements with their mass and inertia, or give the \
             generated functions parameters of your own"
        ),
        "{e}"
    );
    let source = dir.path().join("arm.c");
    let o = robid(&[
        "emit",
        urdf.to_str().unwrap(),
        "--lang",
        "c",
        "-o",
        source.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(source.exists());
    let e = stderr(&o);
    assert!(
        e.contains(&cause)
            && e.contains("_urdf_standard_parameters` in the code) its torque tau2 is 0"),
        "{e}"
    );
    let o = robid(&["emit", UR5]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!stderr(&o).contains("own inertials"), "{}", stderr(&o));
}

/// A prismatic joint that moves only links with inertia but no mass has a force of 0 at
/// every state (it holds only the masses it moves): `robid torques` and `robid emit` say
/// so, where they said it "holds no gravity, only the inertia of these links", and `robid
/// excite` warns that its force limit constrains nothing.
#[test]
fn a_sliding_joint_moving_only_massless_links_is_told_its_force_is_0() {
    let dir = folder();
    let urdf = write(
        dir.path(),
        "slider.urdf",
        r#"<?xml version="1.0"?>
<robot name="slider">
  <link name="base"/>
  <link name="l1"><inertial><origin xyz="0.1 0 0"/><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <link name="carriage"><inertial><mass value="0"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.03"/></inertial></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><origin xyz="0 0 0.1" rpy="1.5707963267948966 0 0"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="10" velocity="2"/></joint>
  <joint name="j2" type="prismatic"><parent link="l1"/><child link="carriage"/><origin xyz="0.3 0 0"/><axis xyz="1 0 0"/><limit lower="-0.2" upper="0.2" effort="50" velocity="1"/></joint>
</robot>
"#,
    );
    let rows = write(
        dir.path(),
        "rows.csv",
        "q1,q2,qd1,qd2,qdd1,qdd2\n0.3,0.1,0.5,0.2,1,2\n-0.7,-0.05,-1,0.3,2,-1\n",
    );
    let o = robid(&[
        "torques",
        urdf.to_str().unwrap(),
        "--states",
        rows.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        e.contains("joint 2 (`j2`) of ")
            && e.contains(
                "slider.urdf moves only links without mass: `carriage`, so with the URDF's own \
                 inertials its force tau2 is 0 in every row (a sliding joint's force holds \
                 only the masses it moves)"
            ),
        "{e}"
    );
    assert!(!e.contains("no gravity"), "{e}");
    for line in stdout(&o).lines().skip(1) {
        let tau2: f64 = line.split(',').nth(1).unwrap().parse().unwrap();
        assert_eq!(tau2, 0.0, "{}", stdout(&o));
    }
    let o = robid(&["emit", urdf.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("its force tau2 is 0 at every state"),
        "{}",
        stderr(&o)
    );
    let traj = dir.path().join("traj.csv");
    let o = robid(&[
        "excite",
        urdf.to_str().unwrap(),
        "-o",
        traj.to_str().unwrap(),
        "--acceleration-limits",
        "5",
        "--duration",
        "4",
        "--restarts",
        "1",
        "--evaluations",
        "50",
    ]);
    assert!(
        stderr(&o).contains("slider.urdf moves only links without mass: `carriage`, so the URDF's own inertials give it no torque"),
        "{}",
        stderr(&o)
    );
}

/// `robid model ROBOT.urdf` gives each base parameter's value from the URDF's own
/// inertials (JSON `value`, and a block of the text), the values the model's own map from
/// the standard parameters gives; a drive term has none, and a TOML description none.
#[test]
fn model_gives_the_base_parameters_of_the_urdf_inertials() {
    let chain = chain(UR5, None);
    let model = Interpreted::new(&chain.robot).unwrap();
    let expected = urdf_base(&chain, &model);
    let o = robid(&["model", UR5, "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let report: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    let values: Vec<f64> = report["base_parameters"]
        .as_array()
        .unwrap()
        .iter()
        .map(|b| b["value"].as_f64().unwrap())
        .collect();
    assert_eq!(values.len(), expected.len());
    for (i, (v, e)) in values.iter().zip(&expected).enumerate() {
        assert!(
            (v - e).abs() <= 1e-12 * e.abs().max(1.0),
            "{i}: {v} against {e}"
        );
    }
    let text = stdout(&robid(&["model", UR5]));
    assert!(
        text.contains("base parameters from the URDF's inertials"),
        "{text}"
    );
    // a drive term has no value in a URDF
    let o = robid(&["model", UR5, "--drive", "Fv", "--json"]);
    let report: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    let fv = report["base_parameters"]
        .as_array()
        .unwrap()
        .iter()
        .find(|b| b["name"] == "Fv1")
        .unwrap();
    assert!(fv.get("value").is_none(), "{fv}");
    let text = stdout(&robid(&["model", UR5, "--drive", "Fv"]));
    assert!(
        text.lines().any(|l| l.trim_start().starts_with("Fv1 ")
            && l.ends_with("= (a drive term: not in a URDF)")),
        "{text}"
    );
    let toml = stdout(&robid(&["model", "descriptions/ur5e.toml", "--json"]));
    assert!(!toml.contains("\"value\""), "{toml}");
}

/// Two joints on one axis with a massless link between them (`a`), the second carrying a
/// 1 kg link: M(q) = 0.02 [[1, 1], [1, 1]] at every q, singular; `joint` is `revolute`
/// or `prismatic`. `a_inertial` is link `a`'s `<inertial>` (empty for none).
fn coaxial(joint: &str, a_inertial: &str) -> String {
    format!(
        r#"<robot name="coax">
  <link name="base"/>
  <link name="a">{a_inertial}</link>
  <link name="b">
    <inertial><origin xyz="0.1 0 0"/><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
  </link>
  <joint name="j1" type="{joint}"><parent link="base"/><child link="a"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="10" velocity="3"/></joint>
  <joint name="j2" type="{joint}"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="10" velocity="3"/></joint>
</robot>
"#
    )
}

/// Runs `robid simulate` of `urdf` along 1 s of two sines at 500 Hz into `dir/sim.csv`.
fn simulate_coaxial(dir: &Path, urdf: &Path) -> (std::process::Output, PathBuf) {
    let mut text = String::from("t,q1,q2,qd1,qd2,qdd1,qdd2\n");
    for k in 0..=500 {
        let t = k as f64 / 500.0;
        let (a, b) = ((1.5 * t).sin(), (2.0 * t).sin());
        let (da, db) = (1.5 * (1.5 * t).cos(), 2.0 * (2.0 * t).cos());
        text.push_str(&format!(
            "{t},{},{},{},{},{},{}\n",
            0.2 * a,
            0.2 * b,
            0.2 * da,
            0.2 * db,
            -0.45 * a,
            -0.8 * b
        ));
    }
    let trajectory = write(dir, "traj.csv", &text);
    let output = dir.join("sim.csv");
    let o = robid(&[
        "simulate",
        urdf.to_str().unwrap(),
        "--trajectory",
        trajectory.to_str().unwrap(),
        "-o",
        output.to_str().unwrap(),
    ]);
    (o, output)
}

/// Two revolute joints on one axis with nothing massive between them: M(q) is singular at
/// every q, and only the sum of the two accelerations is determined. Rounding left plain
/// Cholesky a pivot of 0.8 eps of M22, and `simulate` wrote accelerations split between
/// the joints at random with exit 0; a pivot within the rounding of M(q) now counts as 0.
/// The joints are named ([`coinciding_joints_are_named`]). The same robot with a light
/// link between the joints (1 mg, 8e-9 kg m^2: M(q) of condition number 1e7) is regular
/// and simulates.
#[test]
fn simulate_refuses_a_mass_matrix_singular_to_rounding() {
    let dir = folder();
    let urdf = write(dir.path(), "coax.urdf", &coaxial("revolute", ""));
    let (o, output) = simulate_coaxial(dir.path(), &urdf);
    fails_with(
        &o,
        &["the mass matrix M(q) of coax at the reference's first state"],
    );
    assert!(!output.exists());
    coinciding_joints_are_named(&o);
    let light = r#"<inertial><mass value="1e-6"/><inertia ixx="8e-9" ixy="0" ixz="0" iyy="8e-9" iyz="0" izz="8e-9"/></inertial>"#;
    let urdf = write(dir.path(), "light.urdf", &coaxial("revolute", light));
    let (o, output) = simulate_coaxial(dir.path(), &urdf);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(output.exists());
}

/// The error of two joints on one axis with nothing massive between them names the joints,
/// by number and by their URDF names, the motion that moves no mass, and the fix.
#[track_caller]
fn coinciding_joints_are_named(o: &std::process::Output) {
    fails_with(
        o,
        &[
            "is singular: joints 1 and 2 move the same bodies the same way (the joint \
             velocities [1, -1] move no mass)",
            "nothing with mass or inertia lies between them (link 1)",
            "give link 1 a mass and inertia (in a URDF, an `<inertial>` element), or describe \
             the two joints as one",
            "coax.urdf: joint 1 is `j1`, joint 2 is `j2`, link 1 is `a`)",
        ],
    );
    let e = stderr(o);
    assert!(
        !e.contains("physically consistent") && !e.contains("robid feasible"),
        "{e}"
    );
}

/// Two prismatic joints along one axis with a massless link between them: the URDF's
/// inertials are valid, so the singular mass matrix is told as the joints' arrangement
/// (it said "the parameters are not physically consistent; use a feasible parameter set"),
/// naming the joints; a `[base]` file that makes M(q) indefinite is still told as
/// inconsistent parameters.
#[test]
fn simulate_names_prismatic_joints_that_move_one_body_alike() {
    let dir = folder();
    let urdf = write(dir.path(), "coax.urdf", &coaxial("prismatic", ""));
    let (o, output) = simulate_coaxial(dir.path(), &urdf);
    coinciding_joints_are_named(&o);
    assert!(!output.exists());
    let light = r#"<inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>"#;
    let urdf = write(dir.path(), "two.urdf", &coaxial("prismatic", light));
    let negative = write(dir.path(), "negative.toml", "[base]\nM1 = -0.5\nM2 = 1\n");
    let trajectory = dir.path().join("traj.csv");
    let o = robid(&[
        "simulate",
        urdf.to_str().unwrap(),
        "--parameters",
        negative.to_str().unwrap(),
        "--trajectory",
        trajectory.to_str().unwrap(),
        "-o",
        output.to_str().unwrap(),
    ]);
    fails_with(
        &o,
        &["is singular or not positive definite; the parameters are not physically consistent"],
    );
    assert!(!output.exists());
}

/// Two skew axes 0.1 rad apart whose common normal, 4 cm long, lies 1.5 m below the
/// joints: robid's frames 1 and 2 sit at its feet, far from both links.
const SKEW: &str = r#"<robot name="skew">
  <link name="base"/>
  <joint name="j1" type="revolute"><axis xyz="0 0 1"/><parent link="base"/><child link="l1"/>
    <limit lower="-3" upper="3" effort="100" velocity="3"/></joint>
  <link name="l1"><inertial><origin xyz="0.02 0.05 0.15"/><mass value="3"/>
    <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.005"/></inertial></link>
  <joint name="j2" type="revolute"><origin xyz="0.04 0.179700 0.291007" rpy="-0.1 0 0"/>
    <axis xyz="0 0 1"/><parent link="l1"/><child link="l2"/>
    <limit lower="-3" upper="3" effort="100" velocity="3"/></joint>
  <link name="l2"><inertial><origin xyz="0.1 0 0"/><mass value="2"/>
    <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.005"/></inertial></link>
</robot>
"#;

/// `robid feasible` on a URDF sizes and places the links by the URDF's joints, not by the
/// fitted frames' origins: with SKEW's frames 1.5 m below the links, each link's own
/// centre of mass was told as 1.65 m and 1.8 m from "the link's segment" (the 4 cm
/// between the frames' origins) with a bound to put it 4 cm from them, though the fit
/// reproduced the URDF's inertials, which the identified values came from.
#[test]
fn feasible_sizes_a_urdfs_links_by_its_joints() {
    let dir = folder();
    let urdf = write(dir.path(), "skew.urdf", SKEW);
    let chain = Robot::from_urdf(SKEW, "skew.urdf", &ChainSelection::default()).unwrap();
    // frame 1 is far from joint 2's point, which the segments of the links run between
    let segments = chain.link_segments().unwrap();
    assert!(chain.robot.link_segments().unwrap()[0][1][2].abs() < 1e-9);
    let [from, to] = segments[0];
    assert!(
        from.iter().map(|v| v * v).sum::<f64>().sqrt() > 1.0,
        "{from:?}"
    );
    let length: f64 = (0..3)
        .map(|i| (to[i] - from[i]).powi(2))
        .sum::<f64>()
        .sqrt();
    assert!((length - 0.3444).abs() < 1e-3, "{length}");
    let model = Interpreted::new(&chain.robot).unwrap();
    let entries: Vec<String> = urdf_base(&chain, &model)
        .iter()
        .enumerate()
        .map(|(i, v)| {
            let name = model.base_parameter_name(i).unwrap();
            format!("{{\"name\": \"{name}\", \"value\": {v:e}, \"std\": 1e-6}}")
        })
        .collect();
    let identified = write(
        dir.path(),
        "identified.json",
        &format!("{{\"parameters\": [{}]}}", entries.join(", ")),
    );
    let out = dir.path().join("out.urdf");
    let o = robid(&[
        "feasible",
        urdf.to_str().unwrap(),
        "--identified",
        identified.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        !stderr(&o).contains("no body of its size"),
        "{}",
        stderr(&o)
    );
    let back = Robot::from_urdf_file(&out, &ChainSelection::default()).unwrap();
    for (a, b) in back.links.iter().zip(&chain.links) {
        for (x, y) in a.inertial.iter().zip(&b.inertial) {
            assert!((x - y).abs() < 1e-4 * (1.0 + y.abs()), "{x} vs {y}");
        }
    }
}
