//! `--drive` on every subcommand that reads a description, and the warning about a `drive`
//! key that TOML gave to the last joint.

use crate::common::{fails_with, folder, robid, stderr, stdout, write};

/// Two joints; the `drive` line at the end belongs to joint 2 in TOML.
const STRAY: &str = "name = \"arm\"\nconvention = \"modified\"\ngravity = [0, 0, 0]\n\
                     [[joints]]\nalpha = 0\n[[joints]]\nalpha = \"pi/2\"\na = 0.3\n\n\
                     drive = [\"Fv\", \"Fc\"]\n";

#[test]
fn a_stray_drive_key_is_warned_about_and_drive_replaces_it() {
    let dir = folder();
    let robot = write(dir.path(), "arm.toml", STRAY);
    let robot = robot.to_str().unwrap();
    let o = robid(&["model", robot]);
    assert!(o.status.success(), "{}", stderr(&o));
    let (out, err) = (stdout(&o), stderr(&o));
    assert!(
        err.contains("arm.toml:10:9: only joint 2, the last, has a `drive` key"),
        "{err}"
    );
    assert!(out.contains("Fv2") && !out.contains("Fv1"), "{out}");
    for command in ["model", "emit"] {
        let o = robid(&[command, robot, "--drive", "Fv,Fc"]);
        assert!(o.status.success(), "{command}: {}", stderr(&o));
        assert!(!stderr(&o).contains("warning"), "{command}: {}", stderr(&o));
        let out = stdout(&o);
        assert!(
            out.contains("Fv1") && out.contains("Fc1"),
            "{command}: {out}"
        );
    }
    let o = robid(&["model", robot, "--drive", "Fx"]);
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains("--drive: unknown term `Fx`"),
        "{}",
        stderr(&o)
    );
    // `none` removes the description's terms (and its stray key's warning); not with others
    let o = robid(&["model", robot, "--drive", "none"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!stdout(&o).contains("Fv") && !stderr(&o).contains("warning"));
    let o = robid(&["model", robot, "--drive", "Fv,none"]);
    fails_with(&o, &["--drive: `none` is alone or not at all"]);
    // a term named twice, on the command line or in a description, is a slip
    let o = robid(&["model", robot, "--drive", "Fv,Ia,Fv"]);
    fails_with(&o, &["--drive: `Fv` is named twice"]);
    let dir = folder();
    let twice = write(
        dir.path(),
        "twice.toml",
        "name = \"arm\"\nconvention = \"modified\"\ndrive = [\"Ia\", \"Ia\"]\n\
         [[joints]]\nalpha = 0\na = 0\nd = 0\n",
    );
    let o = robid(&["model", twice.to_str().unwrap()]);
    fails_with(&o, &["twice.toml:3:", "the drive term `Ia` is named twice"]);
}

/// `torques --drive Fv` computes tau = Fv qd for a robot without gravity or mass: the
/// viscous terms exist only because of the flag.
#[test]
fn torques_uses_the_drive_terms_of_the_flag() {
    let dir = folder();
    let d = dir.path();
    let robot = write(d, "arm.toml", STRAY);
    let params = write(d, "p.toml", "[standard]\nFv1 = 2.0\nFv2 = 3.0\n");
    let states = write(
        d,
        "s.csv",
        "q1,q2,qd1,qd2,qdd1,qdd2\n0.1,0.2,0.5,-1.5,0,0\n",
    );
    let run = |drive: &str| {
        robid(&[
            "torques",
            robot.to_str().unwrap(),
            "--parameters",
            params.to_str().unwrap(),
            "--states",
            states.to_str().unwrap(),
            "--drive",
            drive,
        ])
    };
    let o = run("Fv");
    assert!(o.status.success(), "{}", stderr(&o));
    let row: Vec<f64> = stdout(&o)
        .lines()
        .nth(1)
        .unwrap()
        .split(',')
        .map(|x| x.parse().unwrap())
        .collect();
    assert_eq!(row, [1.0, -4.5]);
    // without Fv in the model the file's Fv1 is not a parameter
    let o = run("Fc");
    assert!(!o.status.success());
    assert!(stderr(&o).contains("`Fv1`"), "{}", stderr(&o));
}

/// A drive offset on a prismatic joint with gravity along its axis cannot be told from the
/// weight: `model` and `emit` say which base parameters hold it and how to avoid it; the
/// same joint level, or without `Fo`, gets no warning.
#[test]
fn an_offset_inside_the_weight_is_warned_about() {
    let dir = folder();
    let tilted = "name = \"slide\"\nconvention = \"modified\"\ngravity = [0, 3, -9.3]\n\
                  drive = [\"Ia\", \"Fv\", \"Fo\"]\n\
                  [[joints]]\ntype = \"prismatic\"\nalpha = 0\na = 0\nd = 0\ntheta = 0\n\
                  [[joints]]\nalpha = \"pi/2\"\na = 0.3\nd = 0\n";
    let robot = write(dir.path(), "slide.toml", tilted);
    let robot = robot.to_str().unwrap();
    for command in ["model", "emit"] {
        let o = robid(&[command, robot]);
        assert!(o.status.success(), "{command}: {}", stderr(&o));
        let err = stderr(&o);
        assert!(
            err.contains("the drive offset `Fo1` of joint 1 and the weight along its axis")
                && err.contains("folded into `MR1`")
                && err.contains("describe joint 1 without `Fo`")
                && !err.contains("Fo2"),
            "{command}: {err}"
        );
    }
    for quiet in [
        tilted.replace("[0, 3, -9.3]", "[0, 9.8, 0]"),
        tilted.replace("\"Fv\", \"Fo\"", "\"Fv\""),
    ] {
        let robot = write(dir.path(), "quiet.toml", &quiet);
        let o = robid(&["model", robot.to_str().unwrap()]);
        assert!(o.status.success(), "{}", stderr(&o));
        assert!(!stderr(&o).contains("warning"), "{quiet}: {}", stderr(&o));
    }
}
