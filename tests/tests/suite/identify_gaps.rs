//! A simulated UR5e log (30 s at 100 Hz, torque noise differing between joints, position
//! noise and quantization) with 2 s cut out of its middle, a logger that paused
//! (docs/identification.md#gaps-in-the-time-stamps): refused by default, naming the
//! setting; with `[processing] gaps = "split"` identified from its two continuous
//! segments, each processed on its own:
//!
//! - with the simulation's velocities and accelerations, the true base parameters lie
//!   within three of the stated standard deviations for at least 95 % of them;
//! - from the positions alone (differentiated, low-passed at `cutoff = "auto"`, chosen on
//!   the longest segment), the estimate equals, to 1e-10, the two sides given by hand as
//!   two data sets and stacked as `[runs]` stacks them;
//! - a short third segment after a second gap is left out with a warning naming its lines,
//!   and the estimate is the two others'.

use std::path::{Path, PathBuf};

use robid_runtime::Model;
use robid_runtime::data::{Config, RunFiles, RunMode, Runs, load_runs, load_segments};
use robid_runtime::estimate::Estimate;
use robid_runtime::inspect::resolve_cutoff;
use robid_runtime::pipeline::{identify_runs, identify_segments};
use robid_runtime::simulate::{Noise, Simulation};
use robid_symbolic::Drive;
use robots::Ur5e;
use tests::reference::by_name;

const DURATION: f64 = 30.0;
const RATE: f64 = 100.0;

fn truth(model: &Ur5e) -> Vec<f64> {
    let r = by_name("ur5e");
    let standard = r.parameter_values(&r.robot().with_drive(Drive::NONE));
    let mut base = vec![0.0; model.base_parameter_count()];
    model.base_from_standard_into(&standard, &mut base).unwrap();
    base
}

/// The simulated log `t,q1..,qd1..,qdd1..,tau1..`: its header and data rows.
fn simulated(model: &Ur5e, dir: &Path) -> (String, Vec<String>) {
    let noise = Noise {
        torque: vec![0.8, 0.8, 0.4, 0.1, 0.1, 0.05],
        position: 1e-5,
        quantization: std::f64::consts::TAU / f64::from(1 << 20),
        ..Noise::default()
    };
    let trajectory = tests::reference::random_fourier("ur5e", 5, DURATION, RATE);
    let path = dir.join("full.csv");
    Simulation {
        noise,
        seed: 5,
        ..Simulation::default()
    }
    .run(model, &truth(model), &trajectory)
    .unwrap()
    .measured
    .write_csv(&path)
    .unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let mut lines = text.lines().map(String::from);
    let header = lines.next().unwrap();
    (header, lines.collect())
}

/// Writes the rows `keep` (0-based ranges) of the log to `dir/name`.
fn write(dir: &Path, name: &str, log: &(String, Vec<String>), keep: &[[usize; 2]]) -> PathBuf {
    let mut text = format!("{}\n", log.0);
    for [a, b] in keep {
        for row in &log.1[*a..*b] {
            text.push_str(row);
            text.push('\n');
        }
    }
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

/// A config of `dir` reading `t`, the positions and torques (and the simulation's
/// velocities and accelerations when `derivatives`), with `extra` appended.
fn config(dir: &Path, derivatives: bool, extra: &str) -> Config {
    let (columns, processing) = if derivatives {
        (
            "velocity = \"qd{}\"\nacceleration = \"qdd{}\"\n",
            "velocity = \"data\"\nacceleration = \"data\"\n",
        )
    } else {
        ("", "lowpass = { cutoff = \"auto\" }\n")
    };
    let text = format!(
        "time_column = \"t\"\n[[source]]\nposition = \"q{{}}\"\ntorque = \"tau{{}}\"\n\
         {columns}[processing]\n{processing}{extra}"
    );
    let path = dir.join("identify.toml");
    std::fs::write(&path, &text).unwrap();
    Config::from_toml_str(&text, &path).unwrap()
}

fn difference(a: &Estimate, b: &Estimate) -> f64 {
    assert_eq!(a.names, b.names);
    (0..a.values.len())
        .map(|i| (a.values[i] - b.values[i]).abs() / a.values[i].abs().max(a.std[i]))
        .fold(0.0, f64::max)
}

#[test]
fn a_log_with_a_gap_is_identified_from_its_segments() {
    let model = Ur5e;
    let folder = tempfile::tempdir().unwrap();
    let dir = folder.path();
    let log = simulated(&model, dir);
    assert_eq!(log.1.len(), 3001);
    // 2 s (200 rows) cut out of the middle; a third segment of 0.2 s after another gap
    let gapped = write(dir, "gapped.csv", &log, &[[0, 1400], [1600, 3001]]);
    let three = write(
        dir,
        "three.csv",
        &log,
        &[[0, 1400], [1600, 2600], [2980, 3001]],
    );
    let two = write(dir, "two.csv", &log, &[[0, 1400], [1600, 2600]]);

    // refused by default, naming the setting
    let refuse = config(dir, true, "");
    let e = robid_runtime::data::load(&refuse, std::slice::from_ref(&gapped), 6)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("1402: the time stamps jump from 13.99 s to 16 s")
            && e.contains("set `gaps = \"split\"` in [processing]"),
        "{e}"
    );

    // the truth within the stated standard deviations
    let split = config(dir, true, "gaps = \"split\"\n");
    let segments = load_segments(&split, std::slice::from_ref(&gapped), 6).unwrap();
    assert_eq!(segments.segments.len(), 2);
    let id = identify_segments(&model, &segments, &split).unwrap();
    let (e, truth) = (&id.identification.estimate, truth(&model));
    let inside = (0..truth.len())
        .filter(|&i| (e.values[i] - truth[i]).abs() <= 3.0 * e.std[i])
        .count();
    println!(
        "UR5e with a 2 s gap, {} base parameters: {inside} within 3 std, cond {:.1}",
        truth.len(),
        e.condition_number
    );
    assert!(inside as f64 >= 0.95 * truth.len() as f64, "{inside}");

    // from the positions alone: the two sides stacked by hand as runs
    let mut split = config(dir, false, "gaps = \"split\"\n");
    let segments = load_segments(&split, std::slice::from_ref(&gapped), 6).unwrap();
    // the cutoff chosen once, on the longest segment, for both ways
    let longest = segments.longest().unwrap();
    resolve_cutoff(&mut split, longest).unwrap();
    let id = identify_segments(&model, &segments, &split).unwrap();
    let before = write(dir, "before.csv", &log, &[[0, 1400]]);
    let after = write(dir, "after.csv", &log, &[[1600, 3001]]);
    let mut runs = split.clone();
    runs.processing.gaps = Default::default();
    runs.runs = Some(Runs {
        mode: RunMode::Stacked,
        files: vec![RunFiles::One(before), RunFiles::One(after)],
    });
    let sets = load_runs(&runs, 6).unwrap();
    let by_hand = identify_runs(&model, &sets, &runs).unwrap();
    let d = difference(&id.identification.estimate, &by_hand.estimate);
    println!("segments against the two sides stacked as runs: {d:.2e}");
    assert!(d < 1e-10, "{d}");

    // a short third segment left out, with a warning naming it
    let segments = load_segments(&split, &[three], 6).unwrap();
    assert_eq!(segments.segments.len(), 3);
    let id3 = identify_segments(&model, &segments, &split).unwrap();
    let warning = id3.segments.dropped_warning().expect("a segment left out");
    println!("{warning}");
    assert!(
        warning.contains("1 of the 3 segments between its gaps left out: lines 2402 to 2422"),
        "{warning}"
    );
    let id2 =
        identify_segments(&model, &load_segments(&split, &[two], 6).unwrap(), &split).unwrap();
    let d = difference(&id3.identification.estimate, &id2.identification.estimate);
    assert!(d < 1e-12, "{d}");
}
