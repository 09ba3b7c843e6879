//! Class "load-time checks" of issue 11: every number read from a CSV file or a config is
//! finite and within the documented range of its quantity (`robid_runtime::limits`), checked
//! when it is read, and named by file:line and column (CSV) or file:line:column and key
//! (config); sizes (samples = duration x rate, integration steps) are checked against their
//! limits before anything is allocated, with an error that names them.

use robid_runtime::DataError;
use tests::fuzz_data;
use tests::scratch::Scratch;

use std::path::PathBuf;
use std::time::Instant;

use robid_runtime::Error;
use robid_runtime::data::{Config, load};
use robid_runtime::excite::{Fourier, JointSeries, PointDesign};
use robid_runtime::limits;

/// The good record with the field `column` of data row `row` set to `value`.
fn record_with(tmp: &Scratch, name: &str, row: usize, column: &str, value: &str) -> PathBuf {
    let csv = fuzz_data::motion_csv(&fuzz_data::motion(300));
    let header = fuzz_data::default_header();
    let c = header.iter().position(|h| h == column).unwrap();
    let mut lines: Vec<String> = csv.lines().map(str::to_string).collect();
    let mut fields: Vec<String> = lines[row + 1].split(',').map(str::to_string).collect();
    fields[c] = value.into();
    lines[row + 1] = fields.join(",");
    let p = tmp.path(name);
    std::fs::write(&p, lines.join("\n")).unwrap();
    p
}

#[test]
fn each_quantity_is_checked_against_its_range_with_line_and_column() {
    let tmp = Scratch::new();
    for (column, value, quantity, limit) in [
        ("q2", "2e6", "position", "1e6"),
        ("qd3", "-2e6", "velocity", "1e6"),
        ("qdd4", "3e8", "acceleration", "1e8"),
        ("tau5", "1e200", "torque", "1e7"),
        ("t", "1e11", "time", "1e10"),
    ] {
        let f = record_with(&tmp, &format!("{column}.csv"), 20, column, value);
        let e = load(&Config::default_mapping(), &[f], 6).unwrap_err();
        let text = e.to_string();
        assert!(
            matches!(e, Error::Data(DataError::OutOfRange { .. })),
            "{text}"
        );
        assert!(
            text.contains(&format!("{column}.csv:22: column `{column}`"))
                && text.contains(&format!("|{quantity}| <= {limit}")),
            "{text}"
        );
    }
    // values within range load
    let f = record_with(&tmp, "fine.csv", 20, "qdd4", "9e7");
    assert!(load(&Config::default_mapping(), &[f], 6).is_ok());
}

/// Raw columns within range that the units and drive chain scale out of range are named
/// by their file line too.
#[test]
fn the_joint_side_values_are_checked_after_the_drive_chain() {
    let tmp = Scratch::new();
    let f = record_with(&tmp, "scaled.csv", 0, "t", "0");
    let text = "time_column = \"t\"\n[[source]]\nposition = \"q{}\"\ntorque = \"tau{}\"\n\
                [units]\ntorque_scale = [1e6, 1, 1, 1, 1, 1]\n";
    let config = Config::from_toml_str(text, &tmp.path("scaled.toml")).unwrap();
    let e = load(&config, &[f], 6).unwrap_err();
    let text = e.to_string();
    assert!(
        text.contains("scaled.csv:")
            && text.contains("joint 1 torque (after units and drive chain)"),
        "{text}"
    );
}

/// Config numbers: finite and in range, named at their file:line:column.
#[test]
fn config_numbers_are_checked_and_located() {
    let tmp = Scratch::new();
    let source = "[[source]]\nposition = \"q{}\"\ntorque = \"tau{}\"\n";
    let timed = format!("time_column = \"t\"\n{source}");
    let f = record_with(&tmp, "cfg.csv", 0, "t", "0");
    for (text, key, line) in [
        (format!("sample_rate = 1e300\n{source}"), "sample_rate", 1),
        (format!("sample_rate = nan\n{source}"), "sample_rate", 1),
        // found by the fuzzer: a subnormal rate made the sample time infinite
        (format!("sample_rate = 1e-320\n{source}"), "sample_rate", 1),
        (format!("time_scale = inf\n{timed}"), "time_scale", 1),
        (
            format!("{timed}[units]\ntorque_scale = [1, 1, inf, 1, 1, 1]\n"),
            "units.torque_scale",
            6,
        ),
        (
            format!("{timed}[drive]\ngear_ratios = [1, 0, 1, 1, 1, 1]\n"),
            "drive.gear_ratios",
            6,
        ),
        (
            format!("{timed}[processing]\nlowpass = {{ cutoff = 60.0 }}\n"),
            "processing.lowpass.cutoff",
            6,
        ),
        (
            format!("{timed}[processing]\ndecimation = [1000, 1000]\n"),
            "processing.decimation",
            6,
        ),
        (
            format!("{timed}[processing]\nrest_velocity = -1\n"),
            "processing.rest_velocity",
            6,
        ),
        (
            format!("{timed}[estimation]\nforgetting = 2.0\n"),
            "estimation.forgetting",
            6,
        ),
        (
            format!(
                "{timed}[[extra_column]]\nname = \"F\"\nterms = [{{ row = 1, signal = \"qd\", joints = [1], coefficient = 1e300 }}]\n"
            ),
            "extra_column[1].terms[1].coefficient",
            7,
        ),
    ] {
        let path = tmp.path("k.toml");
        let config = Config::from_toml_str(&text, &path).unwrap();
        let e = match load(&config, std::slice::from_ref(&f), 6) {
            Err(e) => e,
            Ok(_) => panic!("{key}: loaded"),
        };
        assert!(
            matches!(&e, Error::Data(DataError::ConfigKey { key: k, line: Some(l), .. }) if k == key && *l == line),
            "{key}: {e}"
        );
        assert!(
            e.to_string()
                .starts_with(&format!("{}:{line}:", path.display())),
            "{e}"
        );
    }
}

/// Time stamps that give an absurd sample rate name the time scale.
#[test]
fn an_absurd_sample_rate_from_time_stamps_names_time_scale() {
    let tmp = Scratch::new();
    let f = record_with(&tmp, "ns.csv", 0, "t", "0");
    let text = "time_column = \"t\"\ntime_scale = 1e-9\n[[source]]\nposition = \"q{}\"\ntorque = \"tau{}\"\n";
    let config = Config::from_toml_str(text, &tmp.path("ns.toml")).unwrap();
    let e = load(&config, &[f], 6).unwrap_err();
    assert!(
        matches!(&e, Error::Data(DataError::ConfigKey { key, line: Some(2), .. }) if key == "time_scale"),
        "{e}"
    );
}

/// `excite --rate 1e9` and `--duration 1e9` aborted on a 240 GB allocation: the sizes are
/// checked first, named, and refused at once.
#[test]
fn trajectory_sizes_are_checked_before_allocating() {
    let fourier = Fourier {
        base_frequency: 0.1,
        joints: vec![JointSeries::from_free(0.0, &[0.1, 0.2, 0.3, 0.4]); 6],
    };
    let start = Instant::now();
    let e = fourier.sample(30.0, 1e9).unwrap_err();
    assert!(
        matches!(&e, Error::Setting { owner, key, .. } if owner == "Fourier::sample" && key == "rate"),
        "{e}"
    );
    let e = fourier.sample(1e9, 500.0).unwrap_err();
    assert!(
        matches!(e, Error::TooLarge { limit, .. } if limit == limits::MAX_SAMPLES),
        "{e}"
    );
    assert!(
        e.to_string()
            .starts_with("trajectory samples (1e9 s at 500 Hz): 500000000001")
            && e.to_string()
                .contains("shorten the duration or lower the rate"),
        "{e}"
    );
    let e = fourier.sample(f64::INFINITY, 500.0).unwrap_err();
    assert!(e.to_string().contains("`duration`"), "{e}");
    let e = PointDesign {
        duration: 1e9,
        ..PointDesign::default()
    }
    .check(6)
    .unwrap_err();
    assert!(e.to_string().starts_with("PointDesign `duration`"), "{e}");
    assert!(
        start.elapsed().as_secs_f64() < 1.0,
        "checked, not allocated"
    );
}
