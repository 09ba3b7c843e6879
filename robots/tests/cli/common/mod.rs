//! What the CLI tests share: running the `robid` binary from the crate folder, its
//! output as text, and fresh temporary folders (never a folder left by an earlier run).

#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

/// The crate folder (`robots/`), where relative paths such as `descriptions/ur5e.toml`
/// resolve.
pub(crate) fn manifest() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// A `robid` command run from the crate folder, its standard input empty.
pub(crate) fn command(args: &[&str]) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_robid"));
    c.args(args).current_dir(manifest()).stdin(Stdio::null());
    c
}

/// Runs `robid` from the crate folder and collects its output.
pub(crate) fn robid(args: &[&str]) -> Output {
    command(args).output().expect("robid runs")
}

/// Runs `robid` from `dir` (for relative output paths such as `./x.csv`).
pub(crate) fn robid_in(dir: &Path, args: &[&str]) -> Output {
    command(args).current_dir(dir).output().expect("robid runs")
}

/// Standard output as text.
pub(crate) fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// Standard error as text.
pub(crate) fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// A fresh temporary folder, removed when dropped.
pub(crate) fn folder() -> tempfile::TempDir {
    tempfile::tempdir().expect("a temporary folder")
}

/// A file of the crate (`descriptions/ur5e.toml`) as an absolute path string.
pub(crate) fn asset(relative: &str) -> String {
    manifest().join(relative).display().to_string()
}

/// Writes `text` to `dir/name` and returns the path.
pub(crate) fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).expect("test file written");
    path
}

/// A states file of the UR5e (`q1..q6,qd1..qd6,qdd1..qdd6`) with `rows` rows.
pub(crate) fn ur5e_states(dir: &Path, rows: usize) -> PathBuf {
    let mut text =
        String::from("q1,q2,q3,q4,q5,q6,qd1,qd2,qd3,qd4,qd5,qd6,qdd1,qdd2,qdd3,qdd4,qdd5,qdd6\n");
    for k in 0..rows {
        let x = 0.001 * k as f64;
        text.push_str(&format!(
            "{x},0.1,0.2,0.3,0.4,0.5,0.1,0,0,0,0,0,0,0.2,0,0,0,0\n"
        ));
    }
    write(dir, "states.csv", &text)
}

/// A smooth trajectory `t,q1..,qd1..,qdd1..` of `joints` joints, `seconds` long at
/// 100 Hz, written to `dir/name`: on joint j (from 0), a_j sin(w_j t + p_j) with
/// a_j = 0.6 + 0.1 (j mod 6) rad, w_j = `speed` (0.9 + 0.37 j) rad/s, p_j = 0.7 j.
pub(crate) fn sine_trajectory(
    dir: &Path,
    name: &str,
    joints: usize,
    seconds: f64,
    speed: f64,
) -> String {
    let mut text = String::from("t");
    for prefix in ["q", "qd", "qdd"] {
        for j in 1..=joints {
            text.push_str(&format!(",{prefix}{j}"));
        }
    }
    text.push('\n');
    for k in 0..=(seconds * 100.0) as usize {
        let t = k as f64 / 100.0;
        let (mut q, mut qd, mut qdd) = (Vec::new(), Vec::new(), Vec::new());
        for j in 0..joints {
            let (a, w, p) = (
                0.6 + 0.1 * (j % 6) as f64,
                speed * (0.9 + 0.37 * j as f64),
                0.7 * j as f64,
            );
            q.push(a * (w * t + p).sin());
            qd.push(a * w * (w * t + p).cos());
            qdd.push(-a * w * w * (w * t + p).sin());
        }
        let row: Vec<String> = std::iter::once(t)
            .chain(q)
            .chain(qd)
            .chain(qdd)
            .map(|v| format!("{v}"))
            .collect();
        text.push_str(&row.join(","));
        text.push('\n');
    }
    write(dir, name, &text).display().to_string()
}

/// Asserts that `o` ended with an error (status 1) and a message containing every one
/// of `expected`, without a panic.
#[track_caller]
pub(crate) fn fails_with(o: &Output, expected: &[&str]) {
    let e = stderr(o);
    assert_eq!(o.status.code(), Some(1), "status {:?}: {e}", o.status);
    assert!(!e.contains("panicked"), "{e}");
    for x in expected {
        assert!(e.contains(x), "expected `{x}` in: {e}");
    }
}

/// The significant digits of the numbers in `text` (the most of any one): a number is a
/// word that parses as one, after the punctuation around it.
pub(crate) fn most_digits(text: &str) -> (usize, String) {
    let mut most = (0, String::new());
    for word in text.split(|c: char| c.is_whitespace() || "[],;:()".contains(c)) {
        if word.parse::<f64>().is_err() {
            continue;
        }
        let mantissa = word.split(['e', 'E']).next().unwrap_or("");
        let digits: String = mantissa.chars().filter(char::is_ascii_digit).collect();
        let count = digits.trim_start_matches('0').len();
        if count > most.0 {
            most = (count, word.to_string());
        }
    }
    most
}
