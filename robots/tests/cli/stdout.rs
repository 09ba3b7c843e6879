//! Standard output that goes away: `robid torques .. | head -1` (the reader closes the
//! pipe) ends quietly with status 141 (128 + SIGPIPE), `robid model .. > /dev/full`
//! (a write error) with one line naming standard output and status 1; never a panic
//! (they used to end with "failed printing to stdout", status 101).

use crate::common;

use std::process::Stdio;

use common::{command, folder, ur5e_states};

/// The subcommands that print their result, with arguments; the states file has 5000
/// rows so that `torques` writes more than a pipe holds.
fn printing(states: &str) -> Vec<Vec<String>> {
    let args = |a: &[&str]| a.iter().map(|s| s.to_string()).collect::<Vec<_>>();
    vec![
        args(&["emit", "descriptions/ur5e.toml"]),
        args(&["model", "descriptions/ur5e.toml"]),
        args(&["model", "descriptions/panda.toml", "--json"]),
        args(&[
            "torques",
            "descriptions/ur5e.toml",
            "--parameters",
            "parameters/ur5e.toml",
            "--states",
            states,
        ]),
    ]
}

#[test]
fn a_closed_pipe_ends_the_program_quietly_with_status_141() {
    let dir = folder();
    let states = ur5e_states(dir.path(), 5000);
    for args in printing(states.to_str().unwrap()) {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let mut child = command(&args)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("robid starts");
        // The reader goes away before robid has written anything (it first reads and
        // derives the robot): every write meets a closed pipe.
        drop(child.stdout.take());
        let o = child.wait_with_output().expect("robid ends");
        let e = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(141), "{args:?}: {e}");
        assert!(
            e.is_empty(),
            "{args:?}: a closed pipe is not an error to report: {e}"
        );
    }
}

/// An output file that is the closed pipe (`-o /dev/stdout | head -1`) ends the program
/// the same quiet way; it used to say "/dev/stdout: cannot write: Broken pipe (os error
/// 32); check that the folder exists and is writable".
#[cfg(target_os = "linux")]
#[test]
fn an_output_file_on_a_closed_pipe_ends_the_program_quietly() {
    let dir = folder();
    let states = ur5e_states(dir.path(), 5000);
    let mut child = command(&[
        "torques",
        "descriptions/ur5e.toml",
        "--parameters",
        "parameters/ur5e.toml",
        "--states",
        states.to_str().unwrap(),
        "-o",
        "/dev/stdout",
    ])
    .stdout(Stdio::piped())
    .stderr(Stdio::piped())
    .spawn()
    .expect("robid starts");
    drop(child.stdout.take());
    let o = child.wait_with_output().expect("robid ends");
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(141), "{e}");
    assert!(e.is_empty(), "a closed pipe is not an error to report: {e}");
}

#[cfg(target_os = "linux")]
#[test]
fn a_full_disk_is_one_line_naming_standard_output_and_status_1() {
    let dir = folder();
    let states = ur5e_states(dir.path(), 10);
    let mut cases = printing(states.to_str().unwrap());
    cases.push(vec!["--help".to_string()]);
    for args in cases {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let full = std::fs::OpenOptions::new()
            .write(true)
            .open("/dev/full")
            .expect("/dev/full on Linux");
        let o = command(&args).stdout(full).output().expect("robid runs");
        let e = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {e}");
        assert_eq!(e.lines().count(), 1, "{args:?}: {e}");
        assert!(
            e.starts_with("error: cannot write to standard output: ")
                && e.contains("No space left on device"),
            "{args:?}: {e}"
        );
    }
}

/// The same subcommands with a reader that takes everything: complete output, status 0
/// (what the buffered writer must not lose at the end).
#[test]
fn a_reader_that_stays_gets_everything() {
    let dir = folder();
    let states = ur5e_states(dir.path(), 5000);
    let o = command(&[
        "torques",
        "descriptions/ur5e.toml",
        "--parameters",
        "parameters/ur5e.toml",
        "--states",
        states.to_str().unwrap(),
    ])
    .output()
    .expect("robid runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8_lossy(&o.stdout);
    assert_eq!(text.lines().count(), 5001);
    assert!(text.ends_with('\n'));
    let last: Vec<f64> = text
        .lines()
        .last()
        .unwrap()
        .split(',')
        .map(|v| v.parse().unwrap())
        .collect();
    assert_eq!(last.len(), 6);
}

/// `identify` writes its files before it prints: a reader that goes away early ends the
/// program (141) but does not cost the JSON report.
#[test]
fn identify_writes_its_report_before_printing() {
    let dir = folder();
    let json = dir.path().join("result.json");
    let mut child = command(&[
        "identify",
        "configs/tx40_robot.toml",
        "--config",
        "configs/tx40.toml",
        "--data",
        "../data/staubli_tx40/data/pos_read_data.csv.gz",
        "../data/staubli_tx40/data/curr_data.csv.gz",
        "--json",
        json.to_str().unwrap(),
    ])
    .stdout(Stdio::piped())
    .stderr(Stdio::piped())
    .spawn()
    .expect("robid starts");
    drop(child.stdout.take());
    let o = child.wait_with_output().expect("robid ends");
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(141), "{e}");
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(report["parameters"].as_array().unwrap().len(), 61);
}

/// Rows for standard output wait in a temporary file; a temporary folder that takes none
/// (`TMPDIR` missing) is named as such with the fix (it said "cannot read: No such file
/// or directory; check the path and permissions").
#[test]
fn a_temporary_folder_that_takes_no_file_is_named_with_the_fix() {
    let dir = common::folder();
    let states = common::ur5e_states(dir.path(), 3);
    let states = states.display().to_string();
    let o = common::command(&[
        "torques",
        "descriptions/ur5e.toml",
        "--parameters",
        "parameters/ur5e.toml",
        "--states",
        &states,
    ])
    .env("TMPDIR", dir.path().join("missing"))
    .output()
    .unwrap();
    common::fails_with(
        &o,
        &[
            "missing: cannot keep a temporary file",
            "set TMPDIR to a folder",
        ],
    );
}
