//! `robid model --schedule P` (issue 17, Zomaya 1994 item 6): the parallel schedule of a
//! derived program, its figures checked against the operation counts of the same report
//! and against the bounds every schedule obeys; bad values refused with a message.

use crate::common;

use common::{fails_with, folder, robid, stderr, stdout, write};

#[test]
fn zomaya_model_schedule_reports_consistent_figures() {
    let o = robid(&["model", "descriptions/ur5e.toml", "--schedule", "3"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    assert!(
        text.contains("parallel schedule of inverse_dynamics"),
        "{text}"
    );
    assert!(text.contains("FFD") && text.contains("BFD"), "{text}");

    let o = robid(&[
        "model",
        "descriptions/ur5e.toml",
        "--json",
        "--schedule",
        "3",
        "--schedule-program",
        "base_regressor",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    let s = &v["schedule"];
    let n = |x: &serde_json::Value| x.as_u64().unwrap();
    assert_eq!(s["program"], "base_regressor");
    // one time unit per operation: the serial time is the operation count
    let ops = &v["operations"]["base_regressor"];
    let count: u64 = ["mul", "add", "neg", "sin", "cos", "sign"]
        .iter()
        .map(|k| n(&ops[k]))
        .sum();
    assert_eq!(n(&s["serial"]), count);
    assert_eq!(n(&s["tasks"]), count);
    let (serial, cp) = (n(&s["serial"]), n(&s["critical_path"]));
    assert!(n(&s["level_estimate"]) >= cp);
    for rule in s["rules"].as_array().unwrap() {
        let makespan = n(&rule["makespan"]);
        assert!(makespan >= cp && 3 * makespan >= serial && makespan <= serial);
        let processors = rule["processors"].as_array().unwrap();
        assert_eq!(processors.len(), 3);
        let load: u64 = processors.iter().map(|p| n(&p["load"])).sum();
        let tasks: u64 = processors.iter().map(|p| n(&p["tasks"])).sum();
        assert_eq!((load, tasks), (serial, serial));
        let mul: u64 = processors.iter().map(|p| n(&p["mul"])).sum();
        assert_eq!(mul, n(&ops["mul"]));
        let speed_up = rule["speed_up"].as_f64().unwrap();
        assert_eq!(speed_up, serial as f64 / makespan as f64);
    }
    let scaling = s["scaling"].as_array().unwrap();
    assert_eq!(scaling.len(), 3);
    assert_eq!(n(&scaling[0]["ffd_makespan"]), serial);
    assert_eq!(n(&scaling[0]["bfd_makespan"]), serial);
}

#[test]
fn zomaya_model_schedule_refuses_bad_values() {
    let robot = "descriptions/ur5e.toml";
    let o = robid(&["model", robot, "--schedule", "0"]);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(
        e.contains("'--schedule <P>'") && e.contains("outside 1..=4096"),
        "{e}"
    );
    let o = robid(&[
        "model",
        robot,
        "--schedule",
        "2",
        "--schedule-program",
        "jacobian",
    ]);
    fails_with(
        &o,
        &[
            "--schedule-program jacobian",
            "inverse_dynamics, mass_matrix",
        ],
    );
    let o = robid(&["model", robot, "--schedule-program", "gravity"]);
    fails_with(&o, &["--schedule-program needs --schedule P"]);
    // a program without operations has no schedule (a speed-up of 1 and an efficiency
    // of 33.3 % were printed for 0 / 0 on 3 processors)
    let dir = folder();
    let slide = write(
        dir.path(),
        "slide.toml",
        "name = \"slide\"\nconvention = \"modified\"\n[[joints]]\ntype = \"prismatic\"\n\
         alpha = 0\na = 0\nd = 0\n",
    );
    let o = robid(&[
        "model",
        slide.to_str().unwrap(),
        "--schedule",
        "3",
        "--schedule-program",
        "base_from_standard",
    ]);
    fails_with(
        &o,
        &["--schedule-program base_from_standard: the program has no operations for this robot"],
    );
}
