//! Inputs that were accepted or refused with a message that named the wrong place or said
//! it wrongly (a bad-input review, 7 December 2026): a validation file that is the data
//! file under another name, a Fourier design whose evaluation grid exceeded the readers'
//! rate, a `--start` beyond the bound of positions blamed on the description, plurals of one, a
//! parameter file that is not UTF-8 and an invisible character in a header name.

use std::path::Path;

use crate::common::{fails_with, folder, robid, robid_in, stderr, stdout, write};

/// A robot of one revolute joint about the vertical: one base parameter, `ZZR1`.
const ONE: &str = "name = \"one\"\nconvention = \"standard\"\ngravity = [0, 0, -9.81]\n\
[[joints]]\nalpha = 0\na = 0.5\nd = 0\ntheta = 0\n\
limits = { position = [-3, 3], velocity = 3, acceleration = 20, torque = 100 }\n";

/// Data of [`ONE`] with `ZZR1 = 0.5`: a sine of 1 rad at 0.5 Hz, 4 s at 100 Hz, with a
/// little noise so that the fit leaves a residual.
fn one_data(dir: &Path) -> String {
    let mut text = String::from("t,q1,qd1,qdd1,tau1\n");
    let w = std::f64::consts::PI;
    for k in 0..=400 {
        let t = 0.01 * k as f64;
        let (s, c) = (w * t).sin_cos();
        let noise = 1e-3 * ((k * 7919) % 13) as f64;
        text.push_str(&format!(
            "{t},{s},{},{},{}\n",
            w * c,
            -w * w * s,
            -0.5 * w * w * s + noise
        ));
    }
    write(dir, "data.csv", &text).display().to_string()
}

/// `--validate` of the `--data` file under another name (`./data.csv`, a symbolic link) is
/// warned of as repeating the fit, as the same name is: it was compared as a string, and
/// the training data were reported as a validation with no warning.
#[test]
fn validation_on_the_data_file_under_another_name_is_warned_of() {
    let dir = folder();
    write(dir.path(), "one.toml", ONE);
    one_data(dir.path());
    std::os::unix::fs::symlink("data.csv", dir.path().join("same.csv")).unwrap();
    for validate in ["data.csv", "./data.csv", "same.csv"] {
        let o = robid_in(
            dir.path(),
            &[
                "identify",
                "one.toml",
                "--data",
                "data.csv",
                "--validate",
                validate,
            ],
        );
        let e = stderr(&o);
        assert!(o.status.success(), "{validate}: {e}");
        assert!(
            e.contains("uses rows that were used for estimation: it repeats the fit"),
            "{validate}: {e}"
        );
    }
}

/// A Fourier design of many harmonics over a short period: the grid on which its margins
/// are evaluated asked for 1.02e7 Hz, refused after the optimisation as "--rate: 10240000
/// Hz must lie in [1e-3, 1e7] Hz", a rate never given; it is now capped at the readers'
/// largest rate and the design is written.
#[test]
fn a_fourier_design_of_a_short_period_is_not_refused_for_a_rate_never_given() {
    let dir = folder();
    let out = dir.path().join("traj.csv");
    let o = robid(&[
        "excite",
        "tests/fixtures/two_link.toml",
        "--duration",
        "0.01",
        "--base-frequency",
        "100",
        "--harmonics",
        "25",
        "--rate",
        "10000",
        "--restarts",
        "1",
        "--evaluations",
        "20",
        "-o",
        out.to_str().unwrap(),
    ]);
    let e = stderr(&o);
    assert!(!e.contains("--rate"), "{e}");
    // the design itself may find no trajectory that excites both joints in 10 ms; what
    // matters is that no rate was blamed
    if o.status.success() {
        assert!(out.exists());
    }
}

/// `--start` is checked as it is read against the bound of position limits, +-1e3: a
/// URDF continuous joint's start of 1e6 (its limits are its start +- pi) was blamed on
/// the description ("the position limits [999996.8584073464, 1000003.1415926536] must be
/// finite within +-1e3 ...; correct it in the description") while 5000 was accepted.
#[test]
fn a_start_beyond_the_bound_of_positions_names_start() {
    let dir = folder();
    let urdf = write(dir.path(), "co.urdf", CONTINUOUS);
    let out = dir.path().join("t.csv");
    let excite = |start: &str| {
        robid(&[
            "excite",
            urdf.to_str().unwrap(),
            "--duration",
            "10",
            "--rate",
            "20",
            "--acceleration-limits",
            "10",
            "--restarts",
            "1",
            "--evaluations",
            "20",
            "--start",
            start,
            "-o",
            out.to_str().unwrap(),
        ])
    };
    for (start, value) in [
        ("0,1e6", "1e6"),
        ("0,5000", "5000"),
        ("-1000.5,0", "-1000.5"),
    ] {
        let o = excite(start);
        let e = stderr(&o);
        // refused by the flag's parser, as every flag's range is (clap's status 2)
        assert_eq!(o.status.code(), Some(2), "{e}");
        assert!(
            e.contains(&format!(
                "for '--start <START>': {value} is outside [-1000, 1000] rad or m"
            )),
            "{e}"
        );
    }
    // a start of the revolute joint outside its limits: the limits as typed
    fails_with(
        &excite("3.5,0"),
        &["--start: q1 = 3.5 is outside the limits (-3, 3) of joint 1"],
    );
}

/// A URDF of a revolute joint and a continuous one (review's repro_11).
const CONTINUOUS: &str = r#"<?xml version="1.0"?>
<robot name="t">
  <link name="base"/>
  <link name="l1"><inertial><origin xyz="0.1 0 0"/><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <link name="l2"><inertial><origin xyz="0.1 0 0"/><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><origin xyz="0 0 0.1"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="10" velocity="2"/></joint>
  <joint name="j2" type="continuous"><parent link="l1"/><child link="l2"/><origin xyz="0.3 0 0"/><axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="10" velocity="2"/></joint>
</robot>
"#;

/// Counts of one are singular: "1 sample each", "1 base parameter", "on 1 processor", "the
/// 2 equations the 1 parameter needs" (each said the plural).
#[test]
fn counts_of_one_are_singular() {
    let dir = folder();
    let one = write(dir.path(), "one.toml", ONE).display().to_string();
    let o = robid(&[
        "excite",
        "tests/fixtures/two_link.toml",
        "--method",
        "points",
        "--duration",
        "0.02",
        "--rate",
        "100",
        "--intervals",
        "2",
        "-o",
        "/dev/null",
    ]);
    fails_with(
        &o,
        &["gives intervals of 0.01 s, 1 sample each at --rate 100 Hz"],
    );
    let o = robid(&[
        "excite",
        &one,
        "--duration",
        "10",
        "--restarts",
        "1",
        "--evaluations",
        "20",
        "-o",
        dir.path().join("t.csv").to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stdout(&o).contains("one: 1 base parameter, 10 s"),
        "{}",
        stdout(&o)
    );
    let o = robid(&["model", &one, "--schedule", "1"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).contains("on 1 processor ("), "{}", stdout(&o));
    // at rest but for one sample: the rest velocity leaves one equation
    let mut text = String::from("t,q1,qd1,qdd1,tau1\n");
    for k in 0..20 {
        let qd = if k == 10 { 1 } else { 0 };
        text.push_str(&format!("{},0,{qd},0,0\n", 0.01 * k as f64));
    }
    let data = write(dir.path(), "rest.csv", &text);
    let o = robid(&["identify", &one, "--data", data.to_str().unwrap()]);
    fails_with(&o, &["fewer than the 2 equations the 1 parameter needs;"]);
}

/// A parameter file that is not UTF-8 is told to be saved as UTF-8, and nothing else: it
/// also said "check the path and permissions", which are not at fault.
#[test]
fn a_parameter_file_not_utf8_is_told_only_to_be_saved_as_utf8() {
    let dir = folder();
    let one = write(dir.path(), "one.toml", ONE).display().to_string();
    let params = dir.path().join("p.toml");
    std::fs::write(&params, b"[base]\nZZR1 = 1.0 # \xb5\n").unwrap();
    let states = write(dir.path(), "st.csv", "q1,qd1,qdd1\n0,0,0\n");
    let o = robid(&[
        "torques",
        &one,
        "--parameters",
        params.to_str().unwrap(),
        "--states",
        states.to_str().unwrap(),
    ]);
    fails_with(
        &o,
        &["it is not UTF-8 text (invalid byte at offset 20); save it as UTF-8"],
    );
    assert!(!stderr(&o).contains("permissions"), "{}", stderr(&o));
}

/// A header name with a zero-width space is quoted with it escaped: "no column `q1` in the
/// header (found: t, q1, ...)" listed what looked like the very column said to be missing.
#[test]
fn an_invisible_character_in_a_header_name_is_shown() {
    let dir = folder();
    let one = write(dir.path(), "one.toml", ONE).display().to_string();
    let data = write(
        dir.path(),
        "zw.csv",
        "t,q1\u{200b},qd1,qdd1,tau1\n0,0,0,0,0\n0.01,0,0,0,0\n",
    );
    let o = robid(&["identify", &one, "--data", data.to_str().unwrap()]);
    fails_with(
        &o,
        &["no column `q1` in the header (found: t, q1\\u{200b}, qd1"],
    );
}
