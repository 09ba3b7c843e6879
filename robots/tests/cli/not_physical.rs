//! Identified values no physical robot has: a base parameter or an extra column that every
//! physically consistent robot keeps >= 0 (a sum of moments of inertia, a rotor inertia, a
//! friction), estimated below zero beyond 3 standard deviations. `robid identify` warns of
//! each (`not_physical`), and `robid feasible`'s result far from the data names them
//! instead of blaming the bounds, the prior or the method.

use crate::common;

use std::path::Path;

use common::{folder, robid, robid_in, sine_trajectory, stderr, stdout};

/// `data` with the sign of column `column` flipped (a joint's torque read with the
/// opposite convention).
fn flipped(data: &str, column: &str, out: &Path) -> String {
    let text = std::fs::read_to_string(data).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap();
    let at = header.split(',').position(|c| c == column).unwrap();
    let mut written = format!("{header}\n");
    for line in lines {
        let row: Vec<String> = line
            .split(',')
            .enumerate()
            .map(|(i, v)| match (i == at, v.strip_prefix('-')) {
                (false, _) => v.to_owned(),
                (true, Some(positive)) => positive.to_owned(),
                (true, None) => format!("-{v}"),
            })
            .collect();
        written.push_str(&row.join(","));
        written.push('\n');
    }
    std::fs::write(out, written).unwrap();
    out.display().to_string()
}

/// The parameters of the `not_physical` warnings of an identification's JSON report.
fn not_physical(json: &Path) -> Vec<String> {
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(json).unwrap()).unwrap();
    v["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|w| w["kind"] == "not_physical")
        .flat_map(|w| w["parameters"].as_array().unwrap().clone())
        .map(|p| p.as_str().unwrap().to_owned())
        .collect()
}

/// The KR 6 R900 (Ia, Fv, Fc per joint) simulated with torque noise 0.2 N m: its fit
/// warns of nothing unphysical; with joint 6's torque of the opposite sign, its rotor
/// inertia and frictions come out negative (measured Ia6 -0.0203 +- 0.00094, Fv6 -0.607
/// +- 0.0049, Fc6 -0.988 +- 0.0105: 22, 123 and 94 standard deviations) and are named,
/// each with what to check.
#[test]
fn a_torque_of_the_opposite_sign_gives_rotor_inertia_and_friction_below_zero() {
    let dir = folder();
    let d = dir.path();
    let trajectory = sine_trajectory(d, "trajectory6.csv", 6, 20.0, 1.0);
    let data = d.join("data.csv").display().to_string();
    let robot = "descriptions/kr6r900.toml";
    let o = robid(&[
        "simulate",
        robot,
        "--parameters",
        "parameters/kr6r900.toml",
        "--trajectory",
        &trajectory,
        "--torque-noise",
        "0.2",
        "-o",
        &data,
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let json = d.join("fit.json");
    let o = robid(&[
        "identify",
        robot,
        "--data",
        &data,
        "--json",
        json.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(not_physical(&json).is_empty(), "{}", stderr(&o));
    assert!(!stderr(&o).contains("physical robot"), "{}", stderr(&o));

    let bad = flipped(&data, "tau6", &d.join("flipped.csv"));
    let o = robid(&[
        "identify",
        robot,
        "--data",
        &bad,
        "--json",
        json.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(not_physical(&json), ["Ia6", "Fv6", "Fc6"], "{}", stderr(&o));
    let e = stderr(&o);
    for part in [
        "warning: `Fv6` = -0.6",
        "standard deviations, but it is Fv6, which is >= 0 for every physical robot",
        "check the model (friction or drive terms it lacks",
        "the sign of each joint's position and torque",
        // the joint whose friction is all below zero is named, with the fix
        "warning: joint 6's friction is negative (Fv6, Fc6, each beyond 3 standard \
         deviations)",
        "give it a negative factor in `[units] torque_scale`",
    ] {
        assert!(e.contains(part), "{part}: {e}");
    }
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let flipped: Vec<_> = v["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|w| w["kind"] == "opposite_sign")
        .map(|w| w["parameters"].clone())
        .collect();
    assert_eq!(flipped, [serde_json::json!(["Fv6", "Fc6"])], "{e}");
    // the fix the warning gives: a negative factor for joint 6's torque
    let fix = d.join("fix.toml");
    std::fs::write(
        &fix,
        "dof = 6\ntime_column = \"t\"\n[[source]]\nposition = \"q{}\"\nvelocity = \"qd{}\"\n\
         acceleration = \"qdd{}\"\ntorque = \"tau{}\"\n[units]\n\
         torque_scale = [1, 1, 1, 1, 1, -1]\n",
    )
    .unwrap();
    let o = robid(&[
        "identify",
        robot,
        "--data",
        &bad,
        "--config",
        fix.to_str().unwrap(),
        "--json",
        json.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(not_physical(&json).is_empty(), "{}", stderr(&o));
    assert!(
        !stderr(&o).contains("friction is negative"),
        "{}",
        stderr(&o)
    );
}

/// The reference robots simulated from their parameter files with every drive term (the
/// UR5e without: its file has none), torque noise 0.2 N m: their fits warn of nothing
/// unphysical.
#[test]
fn the_reference_robots_fits_warn_of_nothing_unphysical() {
    let dir = folder();
    let d = dir.path();
    for (robot, joints, drive) in [
        ("ur5e", 6, "none"),
        ("rx90", 6, "Ia,Fv,Fc,Fo"),
        ("puma560", 6, "Ia,Fv,Fc,Fo"),
        ("tx40", 6, "Ia,Fv,Fc,Fo"),
        ("lwr4", 7, "Ia,Fv,Fc,Fo"),
        ("panda", 7, "Ia,Fv,Fc,Fo"),
    ] {
        let trajectory = sine_trajectory(d, &format!("trajectory{joints}.csv"), joints, 20.0, 1.0);
        let description = format!("descriptions/{robot}.toml");
        let data = d.join(format!("{robot}.csv")).display().to_string();
        let o = robid(&[
            "simulate",
            &description,
            "--drive",
            drive,
            "--parameters",
            &format!("parameters/{robot}.toml"),
            "--trajectory",
            &trajectory,
            "--torque-noise",
            "0.2",
            "-o",
            &data,
        ]);
        assert!(o.status.success(), "{robot}: {}", stderr(&o));
        let json = d.join(format!("{robot}.json"));
        let o = robid(&[
            "identify",
            &description,
            "--drive",
            drive,
            "--data",
            &data,
            "--json",
            json.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{robot}: {}", stderr(&o));
        assert!(not_physical(&json).is_empty(), "{robot}: {}", stderr(&o));
    }
}

/// The real KUKA LWR4+ log (data/kuka_lwr4, its config's friction columns Fv, Fc, Fo):
/// `ZZR1` (= YY1 + ZZ2), `ZZR3` (= YY3 + ZZ4) and `ZZ7` come out negative, and so do
/// the viscous frictions of joints 5 and 7 (measured -1.02, -0.399, -0.212, -0.661,
/// -0.381: 31, 21, 41, 21 and 23 classical standard deviations). The config low-passes the
/// torques at 8 Hz of a 200 Hz log, and the robust deviations are 4 to 10 times the
/// classical ones (0.145, 0.156, 0.0187, 0.299, 0.0641): judged by them, `ZZR1`, `ZZ7` and
/// `Fv7` stay beyond 3 (7.0, 11.4 and 5.9) and are named, `ZZR3` and `Fv5` (2.6 and 2.2)
/// are not. Feasible, 11 robust standard deviations from `ZZ7`, says that the identified
/// values are not physical rather than blaming the bounds, the prior or the method (with
/// the data alone too, `--prior-weight 0`).
#[test]
fn the_lwr4_log_gives_moments_of_inertia_and_frictions_below_zero() {
    let dir = folder();
    let json = dir.path().join("lwr4.json");
    let o = robid(&[
        "identify",
        "descriptions/lwr4.toml",
        "--drive",
        "none",
        "--config",
        "../data/kuka_lwr4/identify.toml",
        "--json",
        json.to_str().unwrap(),
    ]);
    let e = stderr(&o);
    assert!(o.status.success(), "{e}");
    assert_eq!(not_physical(&json), ["ZZR1", "ZZ7", "Fv7"], "{e}");
    for part in [
        "`ZZR1` = -1.02 +- 0.145 is negative by 7.0 robust standard deviations, but it \
         is YY1 + ZZ2",
        "`ZZ7` = -0.212 +- 0.0187 is negative by 11.4 robust standard deviations, but it \
         is ZZ7,",
        "`Fv7` = -0.381 +- 0.0641 is negative by 5.9 robust standard deviations, but its \
         extra column (qd7 in row 7) is a friction or an inertia of the drives",
    ] {
        assert!(e.contains(part), "{part}: {e}");
    }
    // the regrouped sums that may be negative are not named (XXR7 = XX7 - YY7 is -0.175)
    assert!(!e.contains("`XXR7`") && !e.contains("`XXR3`"), "{e}");
    // Fv7 below zero beside Fc7 above it: no joint's friction is all negative
    assert!(!e.contains("friction is negative"), "{e}");
    for extra in [&[][..], &["--prior-weight", "0"][..]] {
        let out = dir.path().join("links.toml");
        let mut args = vec![
            "feasible",
            "descriptions/lwr4.toml",
            "--identified",
            json.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let o = robid(&args);
        let e = stderr(&o);
        assert!(o.status.success(), "{e}");
        for part in [
            "the result is 11 standard deviations from the identified `ZZ7` (max |z|; |z| <= 3 fits the data), \
             because the identified values themselves are not physical: `ZZR1` = -1.02 +- 0.145 \
             (7.0 robust standard deviations below 0, though YY1 + ZZ2 is >= 0 for every \
             physical robot)",
            "fix the identification first",
        ] {
            assert!(e.contains(part), "{extra:?} {part}: {e}");
        }
        assert!(!e.contains("overrule the data"), "{extra:?}: {e}");
    }
}

/// The real TX40 log of `robid demo` (its rotor Coulomb friction `fsm6`, sign(qd5 + qd6) in
/// rows 5 and 6, is one such column, measured 2.10 +- 0.18) gives no such warning.
#[test]
fn the_tx40_demo_warns_of_nothing_unphysical() {
    let dir = folder();
    let o = robid_in(dir.path(), &["demo"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let (out, e) = (stdout(&o), stderr(&o));
    assert!(out.contains("fsm6"), "{out}");
    assert!(
        !out.contains("physical robot") && !e.contains("physical robot"),
        "{out}{e}"
    );
}
