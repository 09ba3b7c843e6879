//! The `robid` binary end to end: forms scripts rely on (DESIGN.md 10) and
//! bad input that must give a located error, never a panic.

use std::path::Path;
use std::process::{Command, Output};

fn robid(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_robid"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("robid runs")
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn emit_prints_the_checked_in_code() {
    let o = robid(&["emit", "descriptions/ur5e.toml"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let checked_in =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("generated/ur5e.rs"))
            .unwrap();
    assert!(
        stdout(&o) == checked_in,
        "robid emit differs from generated/ur5e.rs"
    );
}

#[test]
fn model_json_has_the_documented_shape() {
    let o = robid(&["model", "descriptions/ur5e.toml", "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!(v["name"], "ur5e");
    assert_eq!(v["dof"], 6);
    assert_eq!(v["convention"], "modified");
    assert_eq!(v["standard_parameters"].as_array().unwrap().len(), 60);
    let base = v["base_parameters"].as_array().unwrap();
    assert_eq!(base.len(), 36);
    assert_eq!(base[0]["name"], "ZZR1");
    let terms = base[0]["terms"].as_array().unwrap();
    assert!(
        terms
            .iter()
            .any(|t| t["parameter"] == "ZZ1" && t["coefficient"] == 1.0)
    );
    assert!(
        v["unidentifiable"]
            .as_array()
            .unwrap()
            .iter()
            .any(|p| p == "XX1")
    );
    for program in [
        "inverse_dynamics",
        "base_regressor",
        "mass_matrix",
        "gravity",
    ] {
        assert!(
            v["operations"][program]["mul"].as_u64().unwrap() > 0,
            "{program}"
        );
    }
}

#[test]
fn a_malformed_description_names_file_line_and_column() {
    let dir = std::env::temp_dir().join(format!("robid-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("bad.toml");
    std::fs::write(
        &file,
        "name = \"x\"\nconvention = \"sideways\"\n[[joints]]\nalpha = 0\n",
    )
    .unwrap();
    let o = robid(&["model", file.to_str().unwrap()]);
    assert!(!o.status.success());
    let e = stderr(&o);
    assert!(e.contains("bad.toml:2:14"), "{e}");
    assert!(e.contains("unknown DH convention `sideways`"), "{e}");
    assert!(!e.contains("panicked"), "{e}");
}

#[test]
fn a_missing_file_is_an_error_not_a_panic() {
    let o = robid(&["model", "descriptions/no_such_robot.toml"]);
    assert!(!o.status.success());
    let e = stderr(&o);
    assert!(
        e.contains("no_such_robot.toml") && e.contains("cannot read"),
        "{e}"
    );
    assert!(!e.contains("panicked"), "{e}");
}

/// Parameter files (`torques`, `simulate`, `excite`, `feasible --prior`): each mistake is
/// named with the file and the fix; a good file gives the torques of the reference robot.
#[test]
fn parameter_file_mistakes_are_named() {
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("cli_parameters");
    std::fs::create_dir_all(&dir).unwrap();
    let states = dir.join("states.csv");
    std::fs::write(
        &states,
        "q1,q2,q3,q4,q5,q6,qd1,qd2,qd3,qd4,qd5,qd6,qdd1,qdd2,qdd3,qdd4,qdd5,qdd6\n\
         0,0.1,0.2,0.3,0.4,0.5,0,0,0,0,0,0,0,0,0,0,0,0\n",
    )
    .unwrap();
    let torques = |text: &str| {
        let params = dir.join("params.toml");
        std::fs::write(&params, text).unwrap();
        robid(&[
            "torques",
            "descriptions/ur5e.toml",
            "--parameters",
            params.to_str().unwrap(),
            "--states",
            states.to_str().unwrap(),
        ])
    };
    for (text, expected) in [
        (
            "[standard]\nM9 = 1.0\n",
            "`M9`, which is not a standard parameter",
        ),
        (
            "[standard]\nM2 = \"heavy\"\n",
            "`M2` = \"heavy\" is not a finite number",
        ),
        (
            "[standard]\nM2 = 1.0\n[base]\nZZR1 = 1.0\n",
            "exactly one of the tables",
        ),
        ("[base]\nZZR1 = 1.0\n", "[base] has no `"),
        ("[standard\n", "params.toml"),
    ] {
        let o = torques(text);
        assert!(!o.status.success(), "{text}");
        assert!(stderr(&o).contains(expected), "{text}: {}", stderr(&o));
    }
    let o = torques(&std::fs::read_to_string("parameters/ur5e.toml").unwrap());
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).starts_with("tau1,"), "{}", stdout(&o));
}
