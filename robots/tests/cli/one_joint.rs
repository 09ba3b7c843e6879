//! A robot of one joint (`tests/fixtures/pendulum1.toml`) through the command line: every
//! message that counts joints or lists per-joint values says "1 joint" and "give s1" (they
//! said "1 joints" and "give s1,..,s1", each message writing its own plural), a static
//! sample too few is named by its file with a fix that applies, and a payload that its one
//! joint torque cannot determine gets advice that can be followed.

use std::path::Path;

use crate::common::{fails_with, folder, robid, stderr, write};

const ONE: &str = "tests/fixtures/pendulum1.toml";

/// `robid ARGS` fails with every one of `expected`, and with no plural or range written
/// for several joints ("1 joints", "s1,..,s1").
#[track_caller]
fn refused(args: &[&str], expected: &[&str]) {
    let o = robid(args);
    fails_with(&o, expected);
    let e = stderr(&o);
    assert!(!e.contains("1 joints") && !e.contains(",..,"), "{e}");
}

/// A trajectory `t,q1,qd1,qdd1` of one joint: a sine of 0.5 rad at 0.5 Hz, 4 s at 50 Hz.
fn trajectory(dir: &Path) -> String {
    let mut text = String::from("t,q1,qd1,qdd1\n");
    let w = std::f64::consts::PI;
    for k in 0..=200 {
        let t = 0.02 * k as f64;
        let (s, c) = (w * t).sin_cos();
        text.push_str(&format!(
            "{t},{},{},{}\n",
            0.5 * s,
            0.5 * w * c,
            -0.5 * w * w * s
        ));
    }
    write(dir, "traj.csv", &text).display().to_string()
}

/// The pendulum's parameters: 2 kg, centre of mass 0.3 m out along x.
fn parameters(dir: &Path) -> String {
    write(
        dir,
        "params.toml",
        "[standard]\nXX1 = 0.01\nYY1 = 0.2\nZZ1 = 0.2\nMX1 = 0.6\nM1 = 2\n",
    )
    .display()
    .to_string()
}

#[test]
fn one_joint_messages_count_one_joint() {
    let dir = folder();
    let out = dir.path().join("out.csv").display().to_string();
    let excite = |extra: &[&str]| {
        let mut args = vec![
            "excite",
            ONE,
            "-o",
            &out,
            "--duration",
            "10",
            "--rate",
            "20",
        ];
        args.extend(extra);
        args.into_iter().map(str::to_owned).collect::<Vec<_>>()
    };
    let run = |args: Vec<String>, expected: &[&str]| {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        refused(&args, expected);
    };
    run(
        excite(&["--sigma", "1,2"]),
        &[
            "--sigma has 2 values but",
            "pendulum1.toml has 1 joint; give s1",
        ],
    );
    run(
        excite(&["--start", "0.1,0.2"]),
        &["--start has 2 values but", "has 1 joint; give q1"],
    );
    run(
        excite(&["--velocity-limits", "1,2"]),
        &[
            "--velocity-limits has 2 values but",
            "has 1 joint; give one value or v1",
        ],
    );
    run(
        excite(&["--acceleration-limits", "1,2"]),
        &["has 1 joint; give one value or a1"],
    );
    let traj = trajectory(dir.path());
    let params = parameters(dir.path());
    let simulate = |extra: &[&str]| {
        let mut args = vec![
            "simulate",
            ONE,
            "--parameters",
            &params,
            "--trajectory",
            &traj,
            "-o",
            &out,
        ];
        args.extend(extra);
        args.into_iter().map(str::to_owned).collect::<Vec<_>>()
    };
    run(
        simulate(&["--torque-noise", "0.1,0.2"]),
        &[
            "--torque-noise has 2 values but",
            "has 1 joint; give one value or s1",
        ],
    );
    run(
        simulate(&["--columns", "positions", "--currents", "1,2"]),
        &["--currents has 2 values but", "has 1 joint; give k1"],
    );
    run(
        simulate(&["--flexible", "drives/ur5e_flexible.toml"]),
        &[
            "has 6 [[joint]] tables but",
            "has 1 joint; give one per joint",
        ],
    );
    // states of a robot with more joints
    let states = write(
        dir.path(),
        "states.csv",
        "q1,q2,qd1,qd2,qdd1,qdd2\n0,0,0,0,0,0\n",
    );
    run(
        vec![
            "torques".into(),
            ONE.into(),
            "--parameters".into(),
            params.clone(),
            "--states".into(),
            states.display().to_string(),
        ],
        &["has a column `q2`, for joint 2 of a robot with 1 joint"],
    );
    // identification: a data file with a second joint, a per-joint setting of two values
    let data = write(
        dir.path(),
        "data.csv",
        "t,q1,q2,tau1,tau2\n0,0,0,0,0\n0.01,0,0,0,0\n",
    );
    let identify = |config: &str| {
        let config = write(dir.path(), "config.toml", config);
        vec![
            "identify".to_owned(),
            ONE.to_owned(),
            "--data".to_owned(),
            data.display().to_string(),
            "--config".to_owned(),
            config.display().to_string(),
        ]
    };
    run(
        identify("[processing]\nrest_velocity = [0.1, 0.2]\n"),
        &["2 values for a model of 1 joint; give one number for all joints"],
    );
    run(identify("dof = 2\n"), &["2 joints, but the model has 1"]);
    run(
        identify("time_column = \"t\"\n[[source]]\nposition = \"q{}\"\ntorque = \"tau{}\"\n"),
        &[
            "has a column `q2`, for joint 2 of a model with 1 joint",
            "list the 1 column to read",
        ],
    );
}

/// One static pose of gravity torque for the two combinations (`MX1`, `MY1`) that gravity
/// torques of a pendulum determine: named by the file, with a fix that applies to static
/// samples. It was "least squares with 2 parameters: 1 samples, at least 2 are needed; use
/// more data, less decimation, or fewer parameters", without the file, and decimation is
/// not a setting of static samples.
#[test]
fn one_joint_static_samples_too_few_name_the_file() {
    let dir = folder();
    let csv = write(dir.path(), "gravity.csv", "q1,g1\n0.3,5.6\n");
    let o = robid(&["identify", ONE, "--static", csv.to_str().unwrap()]);
    fails_with(
        &o,
        &[
            "gravity.csv: static samples, 1 equation per pose, for the 2 combinations of base \
             parameters that gravity torques determine (and one equation more): 1 sample, at \
             least 3 are needed; add rows to the file, each at a pose unlike the others",
        ],
    );
    assert!(!stderr(&o).contains("decimation"), "{}", stderr(&o));
    // two poses fit any torques exactly, with no residual for the deviations
    let csv = write(dir.path(), "gravity.csv", "q1,g1\n0.3,5.6\n1.1,2.6\n");
    let o = robid(&["identify", ONE, "--static", csv.to_str().unwrap()]);
    assert!(
        stderr(&o).contains("2 samples, at least 3 are needed"),
        "{}",
        stderr(&o)
    );
    // three poses are enough
    let csv = write(
        dir.path(),
        "gravity.csv",
        "q1,g1\n0.3,5.6\n1.1,2.6\n-0.4,-3.5\n",
    );
    let o = robid(&["identify", ONE, "--static", csv.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
}

/// The joint torque of one revolute joint sees at most three of the payload's ten
/// parameters (`ZZ`, `MX`, `MY`) whatever the motion: the advice was "use a richer
/// trajectory or remove these parameters", which no motion and no flag can follow.
#[test]
fn one_joint_payload_gets_advice_that_can_be_followed() {
    let dir = folder();
    let params = parameters(dir.path());
    let mut text = String::from("q1,qd1,qdd1,tau1\n");
    for k in 0..100 {
        let t = 0.05 * k as f64;
        let q = (1.3 * t).sin();
        text.push_str(&format!(
            "{q},{},{},{}\n",
            1.3 * (1.3 * t).cos(),
            -1.69 * q,
            3.0 * q
        ));
    }
    let data = write(dir.path(), "data.csv", &text);
    let o = robid(&[
        "payload",
        ONE,
        "--parameters",
        &params,
        "--data",
        data.to_str().unwrap(),
    ]);
    fails_with(
        &o,
        &[
            "data.csv: rank-deficient data: rank 3 of the payload's 10 parameters; not determined:",
            "the joint torques of `pendulum1` (1 joint) determine at most 3 combinations of \
             the ten whatever the motion",
            "force-torque sensor",
        ],
    );
    // no motion excites what the joint torque cannot see: "not excited" was wrong
    for wrong in ["remove these parameters", "not excited"] {
        assert!(!stderr(&o).contains(wrong), "{}", stderr(&o));
    }
}
