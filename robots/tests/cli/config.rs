//! `robid identify` with a config: `--example-config` prints a config that works, and the
//! `file` of each `[[source]]` is read (relative to the config) when `--data` is not given.

use crate::common::{folder, robid, stderr, stdout, write};

/// One revolute joint about a horizontal axis (gravity along x of the base).
const PENDULUM: &str = "name = \"pendulum\"\nconvention = \"modified\"\n\
                        gravity = [-9.81, 0, 0]\ndrive = [\"Fv\"]\n[[joints]]\nalpha = 0\n";

/// A log of the pendulum with noise-like torque: the test compares two runs, not values.
fn log() -> String {
    let mut csv = String::from("time,angle,torque\n");
    for k in 0..3000 {
        let t = k as f64 * 2e-3;
        let q = 1.2 * (1.3 * t).sin() + 0.3 * (4.1 * t).cos();
        let tau = 2.0 * q.cos() + 0.4 * (1.3 * t).cos() + 0.05 * (97.0 * t).sin();
        csv.push_str(&format!("{t},{q},{tau}\n"));
    }
    csv
}

const CONFIG: &str = "dof = 1\ntime_column = \"time\"\n[[source]]\nposition = [\"angle\"]\n\
                      torque = [\"torque\"]\n[processing]\nlowpass = { cutoff = 5.0 }\n";

#[test]
fn the_sources_files_are_read_relative_to_the_config() {
    let dir = folder();
    let d = dir.path();
    let robot = write(d, "pendulum.toml", PENDULUM);
    std::fs::create_dir(d.join("logs")).unwrap();
    let data = write(&d.join("logs"), "run.csv", &log());
    std::fs::create_dir(d.join("jobs")).unwrap();
    let with_file = CONFIG.replace("[[source]]\n", "[[source]]\nfile = \"../logs/run.csv\"\n");
    let job = write(&d.join("jobs"), "job.toml", &with_file);
    let plain = write(d, "plain.toml", CONFIG);
    let (robot, job, plain, data) = (
        robot.to_str().unwrap(),
        job.to_str().unwrap(),
        plain.to_str().unwrap(),
        data.to_str().unwrap(),
    );
    let from_config = robid(&["identify", robot, "--config", job]);
    assert!(from_config.status.success(), "{}", stderr(&from_config));
    assert!(stdout(&from_config).contains("fit: relative error"));
    let explicit = robid(&["identify", robot, "--config", plain, "--data", data]);
    assert!(explicit.status.success(), "{}", stderr(&explicit));
    // the same rows of the same file, named through the config's folder
    assert_eq!(
        stdout(&from_config).replace("jobs/../", ""),
        stdout(&explicit)
    );
    // --data overrides the config's files
    let full = log();
    let shorter = full.lines().take(2001).collect::<Vec<_>>().join("\n");
    let other = write(d, "other.csv", &shorter);
    let o = robid(&[
        "identify",
        robot,
        "--config",
        job,
        "--data",
        other.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_ne!(stdout(&o), stdout(&from_config));
    // without files anywhere, the message says where to put them
    let o = robid(&["identify", robot, "--config", plain]);
    assert!(!o.status.success());
    let e = stderr(&o);
    assert!(
        e.contains("plain.toml: [[source]] 1 has no `file`") && e.contains("--data"),
        "{e}"
    );
    let o = robid(&["identify", robot]);
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains("--data: give the data file"),
        "{}",
        stderr(&o)
    );
}

/// The printed example is a working config for a six-joint robot's log.
#[test]
fn the_example_config_is_printed_and_works() {
    let o = robid(&["identify", "--example-config"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    assert_eq!(text, robid_runtime::data::EXAMPLE_CONFIG);
    for key in [
        "[[source]]",
        "[units]",
        "[drive]",
        "[processing]",
        "[estimation]",
        "lowpass",
    ] {
        assert!(text.contains(key), "{key}");
    }
    // the README shows the same text
    let readme = std::fs::read_to_string(crate::common::manifest().join("../README.md")).unwrap();
    assert!(
        readme.contains(text.trim_end()),
        "README.md does not show the example config"
    );
    // flags other than --example-config are refused with it
    let o = robid(&["identify", "--example-config", "--method", "ols"]);
    assert!(!o.status.success());
}

/// `robid inspect` reads the same config and files as `identify` and suggests a cutoff;
/// `cutoff = "auto"` in the config makes `identify` use that cutoff and say so, and the
/// JSON report carries it.
#[test]
fn inspect_suggests_the_cutoff_that_auto_uses() {
    let dir = folder();
    let d = dir.path();
    let robot = write(d, "pendulum.toml", PENDULUM);
    write(d, "run.csv", &log());
    let auto = CONFIG
        .replace("cutoff = 5.0", "cutoff = \"auto\"")
        .replace("[[source]]\n", "[[source]]\nfile = \"run.csv\"\n");
    let config = write(d, "auto.toml", &auto);
    let (robot, config) = (robot.to_str().unwrap(), config.to_str().unwrap());
    let o = robid(&["inspect", robot, "--config", config]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    assert!(text.contains("suggested low-pass cutoff:"), "{text}");
    let o = robid(&["inspect", robot, "--config", config, "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let json: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    let cutoff = json["cutoff"]["cutoff"].as_f64().unwrap();
    assert!(cutoff > 0.0 && cutoff < 250.0, "{cutoff}");
    assert_eq!(json["joints"].as_array().unwrap().len(), 1);
    assert_eq!(json["sampling"][0]["rows"], 3000);
    let report = d.join("report.json");
    let o = robid(&[
        "identify",
        robot,
        "--config",
        config,
        "--json",
        report.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stdout(&o).contains(&format!("low-pass cutoff (auto): {cutoff} Hz")),
        "{}",
        stdout(&o)
    );
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(report).unwrap()).unwrap();
    assert_eq!(report["cutoff"]["cutoff"].as_f64(), Some(cutoff));
}
