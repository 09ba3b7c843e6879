//! Loading tests: joins, time handling, bad input, and the real TX40 log.

use crate::DataError;
use std::path::{Path, PathBuf};

use super::*;
use crate::error::Error;

/// A fresh folder for one test's files, removed when the test ends (even by a panic).
struct Dir(tempfile::TempDir);

impl Dir {
    fn new() -> Self {
        Dir(tempfile::tempdir().unwrap())
    }
    fn file(&self, name: &str, text: &str) -> PathBuf {
        let p = self.0.path().join(name);
        std::fs::write(&p, text).unwrap();
        p
    }
}

fn cfg(text: &str) -> Config {
    Config::from_toml_str(text, Path::new("test.toml")).unwrap()
}

const TWO_FILES: &str = r#"
sample_rate = 10.0
[[source]]
position = "q{}"
[[source]]
torque = "q{}"
[units]
angle = "deg"
"#;

#[test]
fn joins_two_files_row_by_row() {
    let d = Dir::new();
    let a = d.file("pos.csv", "q1,q2\n0,180\n90,0\n");
    let b = d.file("tau.csv", "q1,q2\n1,2\n3,4\n");
    let data = load(&cfg(TWO_FILES), &[a, b], 2).unwrap();
    assert!((data.q[1][0] - std::f64::consts::PI).abs() < 1e-12);
    assert_eq!(data.tau[1], vec![2.0, 4.0]);
    assert!((data.sample_time - 0.1).abs() < 1e-15);
    assert!(data.warnings.is_empty());
}

/// `units.angle = "deg"` converts a revolute joint's positions, velocities and
/// accelerations, not a prismatic joint's (lengths: its 0.2 m stroke became 0.0035 m and
/// identification called the data rank-deficient), and every motor position (a motor
/// turns); in memory and on the record kept on disk alike.
#[test]
fn degrees_leave_a_prismatic_joint_in_metres() {
    let d = Dir::new();
    let file = d.file(
        "log.csv",
        "q1,q2,qd1,qd2,qdd1,qdd2,tau1,tau2,m1,m2
\
         180,0.2,90,0.1,45,0.05,1,2,360,720\n\
         90,0.1,90,0.1,45,0.05,1,2,360,720\n",
    );
    let mut config = cfg(
        "sample_rate = 10.0\n[[source]]\nposition = \"q{}\"\nvelocity = \"qd{}\"\n\
         acceleration = \"qdd{}\"\ntorque = \"tau{}\"\nmotor_position = \"m{}\"\n\
         [units]\nangle = \"deg\"\n",
    );
    config.prismatic = vec![false, true];
    let data = load(&config, std::slice::from_ref(&file), 2).unwrap();
    let pi = std::f64::consts::PI;
    let close = |a: f64, b: f64| (a - b).abs() < 1e-12;
    assert!(
        close(data.q[0][0], pi) && close(data.q[1][0], 0.2),
        "{:?}",
        data.q
    );
    let qd = data.qd.as_ref().unwrap();
    assert!(close(qd[0][0], pi / 2.0) && close(qd[1][0], 0.1), "{qd:?}");
    let qdd = data.qdd.as_ref().unwrap();
    assert!(
        close(qdd[0][0], pi / 4.0) && close(qdd[1][0], 0.05),
        "{qdd:?}"
    );
    let motor = data.motor.as_ref().unwrap();
    assert!(
        close(motor[0][0], 2.0 * pi) && close(motor[1][0], 4.0 * pi),
        "{motor:?}"
    );
    let record = SpilledRecord::open(&config, std::slice::from_ref(&file), 2)
        .unwrap()
        .unwrap();
    let read = record.read(0, 2).unwrap();
    assert!(
        close(read.q[0][0], pi) && close(read.q[1][0], 0.2),
        "{:?}",
        read.q
    );
}

/// `units.position_offset` is added to the positions once they are radians (metres for a
/// prismatic joint) on the joint side, whatever unit and side the columns are in; the
/// velocities, accelerations and motor positions stay as read. In memory and on disk alike.
#[test]
fn a_position_offset_moves_the_joint_positions_only() {
    let d = Dir::new();
    let file = d.file(
        "log.csv",
        "q1,q2,qd1,qd2,qdd1,qdd2,tau1,tau2,m1,m2\n\
         18000,0.2,9000,0.1,4500,0.05,1,2,36000,720\n\
         9000,0.1,9000,0.1,4500,0.05,1,2,36000,720\n",
    );
    let mut config = cfg(
        "sample_rate = 10.0\n[[source]]\nposition = \"q{}\"\nvelocity = \"qd{}\"\n\
         acceleration = \"qdd{}\"\ntorque = \"tau{}\"\nmotor_position = \"m{}\"\n\
         [units]\nangle = \"deg\"\nposition_offset = [-1.5, 0.25]\n\
         [drive]\nposition_side = \"motor\"\ngear_ratios = [100, 1]\n",
    );
    config.prismatic = vec![false, true];
    let pi = std::f64::consts::PI;
    let close = |a: f64, b: f64| (a - b).abs() < 1e-12;
    let data = load(&config, std::slice::from_ref(&file), 2).unwrap();
    let spilled = SpilledRecord::open(&config, std::slice::from_ref(&file), 2)
        .unwrap()
        .unwrap();
    let record = spilled.read(0, 2).unwrap();
    for data in [&data, &*record] {
        let q = [data.q[0][0], data.q[0][1], data.q[1][0], data.q[1][1]];
        assert!(
            close(q[0], pi - 1.5) && close(q[1], pi / 2.0 - 1.5),
            "{q:?}"
        );
        assert!(close(q[2], 0.45) && close(q[3], 0.35), "{q:?}");
        let qd = data.qd.as_ref().unwrap();
        assert!(close(qd[0][0], pi / 2.0) && close(qd[1][0], 0.1), "{qd:?}");
        let qdd = data.qdd.as_ref().unwrap();
        assert!(close(qdd[0][0], pi / 4.0), "{qdd:?}");
        let motor = data.motor.as_ref().unwrap();
        assert!(close(motor[0][0], 2.0 * pi), "{motor:?}");
    }
    // one value for every joint, or one per joint, each finite
    let bad = |offset: &str| {
        let text = format!(
            "sample_rate = 10.0\n[[source]]\nposition = \"q{{}}\"\ntorque = \"tau{{}}\"\n\
             [units]\nposition_offset = {offset}\n"
        );
        load(&cfg(&text), std::slice::from_ref(&file), 2)
            .unwrap_err()
            .to_string()
    };
    let e = bad("[0.1, 0.2, 0.3]");
    assert!(
        e.contains("units.position_offset") && e.contains("3 values for a model of 2 joints"),
        "{e}"
    );
    let e = bad("1e7");
    assert!(
        e.contains("test.toml:6:1") && e.contains("1e7 is not a finite number"),
        "{e}"
    );
}

/// A config that gives neither `sample_rate` nor `time_column` reads the file's time
/// column, found by its name with its unit (`time_ms`), in memory and on disk alike (it
/// was refused as "no time column", though the example config shows `time_column = "t"`
/// among the defaults); two time columns, or none, leave it to the config.
#[test]
fn without_time_keys_the_time_column_is_found_by_name() {
    let d = Dir::new();
    let mut text = String::from("time_ms,q1,tau1\n");
    for k in 0..50 {
        text.push_str(&format!("{},{},1\n", 2 * k, f64::from(k).sin()));
    }
    let file = d.file("log.csv", &text);
    let config = cfg("[[source]]\nposition = \"q{}\"\ntorque = \"tau{}\"\n");
    let data = load(&config, std::slice::from_ref(&file), 1).unwrap();
    assert!(
        (data.sample_time - 2e-3).abs() < 1e-15,
        "{}",
        data.sample_time
    );
    let record = SpilledRecord::open(&config, std::slice::from_ref(&file), 1)
        .unwrap()
        .unwrap();
    assert!((record.sample_time() - 2e-3).abs() < 1e-15);
    let mut two = String::from("t,time,q1,tau1\n");
    for k in 0..50 {
        two.push_str(&format!("{k},{k},{},1\n", f64::from(k).sin()));
    }
    let two = d.file("two.csv", &two);
    let e = load(&config, &[two], 1).unwrap_err().to_string();
    assert!(e.contains("no time column"), "{e}");
}

/// The time column found by name must be the same in every source's file: positions and
/// torques in two files, each with `time_ms`, are read at 2 ms; files whose time columns
/// differ (`t` in one, `time_ms` in the other) leave it to the config, which then has
/// none: the error names both columns. A config that names its time column keeps it, even beside another column called
/// `t` (a controller's tick count here, at another step).
#[test]
fn the_time_column_found_by_name_is_each_files_and_never_the_configs() {
    let d = Dir::new();
    let two_sources = "[[source]]\nposition = \"q{}\"\n[[source]]\ntorque = \"tau{}\"\n";
    let column = |time: &str, name: &str, step: f64| {
        let mut text = format!("{time},{name}\n");
        for k in 0..50 {
            text.push_str(&format!("{},{}\n", step * f64::from(k), f64::from(k).sin()));
        }
        text
    };
    let q = d.file("q.csv", &column("time_ms", "q1", 2.0));
    let tau = d.file("tau.csv", &column("time_ms", "tau1", 2.0));
    let data = load(&cfg(two_sources), &[q.clone(), tau], 1).unwrap();
    assert!(
        (data.sample_time - 2e-3).abs() < 1e-15,
        "{}",
        data.sample_time
    );
    let other = d.file("other.csv", &column("t", "tau1", 0.002));
    let e = load(&cfg(two_sources), &[q, other], 1)
        .unwrap_err()
        .to_string();
    // named (it said "the data has no time column", which each file had)
    assert!(
        e.contains("the files' time columns have different names (`time_ms` in")
            && e.contains("or set `sample_rate = ...` (Hz)"),
        "{e}"
    );

    let mut text = String::from("clock,t,q1,tau1\n");
    for k in 0..50 {
        text.push_str(&format!(
            "{},{},{},1\n",
            1e-3 * f64::from(k),
            4 * k,
            f64::from(k).sin()
        ));
    }
    let file = d.file("ticks.csv", &text);
    let named =
        cfg("time_column = \"clock\"\n[[source]]\nposition = \"q{}\"\ntorque = \"tau{}\"\n");
    let data = load(&named, std::slice::from_ref(&file), 1).unwrap();
    assert!(
        (data.sample_time - 1e-3).abs() < 1e-15,
        "{}",
        data.sample_time
    );
}

/// A time column the config names takes the unit its name gives when `time_scale` is
/// left out (`time_column = "t_ms"` read milliseconds as seconds: a 500 Hz log as
/// 0.5 Hz), in memory and on disk; a `time_scale` the config gives is kept, 1 included
/// (`time_scale = 1` was taken as not given: a `t_ms` column holding seconds was read at
/// 1000 times its rate, and the fit was meaningless with exit 0).
#[test]
fn a_named_time_column_takes_the_unit_of_its_name() {
    let d = Dir::new();
    let mut text = String::from("t_ms,q1,tau1\n");
    for k in 0..50 {
        text.push_str(&format!("{},{},1\n", 2 * k, f64::from(k).sin()));
    }
    let file = d.file("log.csv", &text);
    let source = "[[source]]\nposition = \"q{}\"\ntorque = \"tau{}\"\n";
    let config = cfg(&format!("time_column = \"t_ms\"\n{source}"));
    let data = load(&config, std::slice::from_ref(&file), 1).unwrap();
    assert!(
        (data.sample_time - 2e-3).abs() < 1e-15,
        "{}",
        data.sample_time
    );
    let record = SpilledRecord::open(&config, std::slice::from_ref(&file), 1)
        .unwrap()
        .unwrap();
    assert!(
        (record.sample_time() - 2e-3).abs() < 1e-15,
        "{}",
        record.sample_time()
    );
    // the config's own scale wins (here a clock in tenths of a millisecond)
    let config = cfg(&format!(
        "time_column = \"t_ms\"\ntime_scale = 1e-4\n{source}"
    ));
    let data = load(&config, std::slice::from_ref(&file), 1).unwrap();
    assert!(
        (data.sample_time - 2e-4).abs() < 1e-15,
        "{}",
        data.sample_time
    );
    let mut seconds = String::from("t_ms,q1,tau1\n");
    for k in 0..50 {
        seconds.push_str(&format!(
            "{},{},1\n",
            0.002 * f64::from(k),
            f64::from(k).sin()
        ));
    }
    let file = d.file("seconds.csv", &seconds);
    for scale in ["1", "1.0"] {
        let config = cfg(&format!(
            "time_column = \"t_ms\"\ntime_scale = {scale}\n{source}"
        ));
        let data = load(&config, std::slice::from_ref(&file), 1).unwrap();
        assert!(
            (data.sample_time - 2e-3).abs() < 1e-15,
            "{scale}: {}",
            data.sample_time
        );
        let record = SpilledRecord::open(&config, std::slice::from_ref(&file), 1)
            .unwrap()
            .unwrap();
        assert!((record.sample_time() - 2e-3).abs() < 1e-15, "{scale}");
    }
}

#[test]
fn row_count_mismatch_is_an_error() {
    let d = Dir::new();
    let a = d.file("pos.csv", "q1,q2\n0,0\n1,1\n2,2\n");
    let b = d.file("tau.csv", "q1,q2\n1,2\n3,4\n");
    let e = load(&cfg(TWO_FILES), &[a, b], 2).unwrap_err();
    assert!(
        matches!(
            e,
            Error::Data(DataError::RowCountMismatch {
                first_rows: 3,
                second_rows: 2,
                ..
            })
        ),
        "{e}"
    );
}

/// Files that each have a time column, under different names (`t` and `time`), are joined
/// row by row (no time column was read), and a row count that differs says why: it said
/// to give each file a time column, which each had.
#[test]
fn a_row_count_mismatch_names_time_columns_of_different_names() {
    let d = Dir::new();
    let a = d.file("pos.csv", "t,q1,q2\n0,0,0\n0.1,1,1\n0.2,2,2\n");
    let b = d.file("tau.csv", "time,q1,q2\n0,1,2\n0.1,3,4\n");
    // no sample rate: the time is the files'
    let config = cfg(&TWO_FILES.replace("sample_rate = 10.0\n", ""));
    let e = load(&config, &[a.clone(), b.clone()], 2)
        .unwrap_err()
        .to_string();
    let names = format!(
        "the files' time columns have different names (`t` in {}, `time` in {}), so none \
         was read and the files were joined row by row",
        a.display(),
        b.display()
    );
    assert!(e.contains(&names), "{e}");
    // as many rows in each: the same message, where it said "the data has no time column"
    let c = d.file("tau3.csv", "time,q1,q2\n0,1,2\n0.1,3,4\n0.2,5,6\n");
    let e = load(&config, &[a.clone(), c.clone()], 2)
        .unwrap_err()
        .to_string();
    let names = names.replace(&b.display().to_string(), &c.display().to_string());
    assert!(e.contains(&names) && !e.contains("no time column"), "{e}");
    // the same names: joined by time, no mismatch
    let b = d.file("tau.csv", "t,q1,q2\n0,1,2\n0.2,3,4\n");
    assert!(load(&config, &[a, b], 2).is_ok());
}

#[test]
fn joint_count_mismatch_is_an_error() {
    let d = Dir::new();
    let a = d.file("pos.csv", "q1,q2\n0,0\n1,1\n");
    let text = TWO_FILES.replace("torque = \"q{}\"", "torque = [\"q1\"]");
    let e = load(&cfg(&text), &[a.clone(), a], 2).unwrap_err();
    assert!(
        matches!(
            &e,
            Error::Data(DataError::ConfigKey { line: Some(6), key, .. }) if key == "source[2].torque"
        ),
        "{e}"
    );
    assert!(
        e.to_string()
            .contains("1 column name for a model of 2 joints"),
        "{e}"
    );
}

/// A file with a column for one joint more than the model's, read through a template,
/// is another robot's: refused at the source's key, by the in-memory and the streaming
/// reader alike; a source listing its columns reads them and passes.
#[test]
fn a_column_for_one_joint_more_is_refused() {
    let d = Dir::new();
    let a = d.file("pos.csv", "q1,q2,q3\n0,0,0\n1,1,1\n");
    let config = cfg(TWO_FILES);
    let e = load(&config, &[a.clone(), a.clone()], 2).unwrap_err();
    assert!(
        matches!(
            &e,
            Error::Data(DataError::ConfigKey { line: Some(4), key, .. }) if key == "source[1].position"
        ),
        "{e}"
    );
    assert!(e.to_string().contains("column `q3`, for joint 3"), "{e}");
    let both = d.file(
        "both.csv",
        "q1,q2,q3,tau1,tau2,tau3\n0,0,0,1,1,1\n1,1,1,1,1,1\n",
    );
    let one = cfg("sample_rate = 10.0\n[[source]]\nposition = \"q{}\"\ntorque = \"tau{}\"\n");
    assert!(SpilledRecord::open(&one, std::slice::from_ref(&both), 2).is_err());
    assert!(load(&one, std::slice::from_ref(&both), 3).is_ok());
    // a template without `{}` names one column, its own, never a surplus joint
    let single = d.file("one.csv", "angle,torque\n0,1\n1,1\n");
    let named = cfg("sample_rate = 10.0\n[[source]]\nposition = \"angle\"\ntorque = \"torque\"\n");
    assert!(load(&named, std::slice::from_ref(&single), 1).is_ok());
    let listed = cfg(&TWO_FILES.replace("\"q{}\"", "[\"q1\", \"q2\"]"));
    assert!(load(&listed, &[a.clone(), a], 2).is_ok());
}

/// Settings that contradict each other are refused at their key: a sample rate beside a
/// time column (which sets the rate), and one column read by two roles of a source or
/// twice by one (the positions read again as torques).
#[test]
fn contradicting_settings_are_refused_at_their_key() {
    let check = |text: &str| cfg(text).check(2).unwrap_err().to_string();
    let e = check("sample_rate = 100.0\ntime_column = \"t\"\n");
    assert!(
        e.contains("`sample_rate`: is given with time_column"),
        "{e}"
    );
    let e = check("sample_rate = 1.0\n[[source]]\nposition = \"q{}\"\ntorque = \"q{}\"\n");
    assert!(
        e.contains("`source[1].torque`: reads column `q1` as source[1].position does"),
        "{e}"
    );
    let e = check("sample_rate = 1.0\n[[source]]\nposition = [\"a\", \"a\"]\n");
    assert!(e.contains("reads column `a` twice"), "{e}");
    assert!(cfg(TWO_FILES).check(2).is_ok());
}

/// The header names are those the column reader sees, whatever the file's dialect: quoted
/// names, a blank first line, comment lines, a byte-order mark, CRLF, gzip. (A quoted
/// header once gave `"qd1"` with its quotes, so the default mapping missed the
/// velocities and differentiated the positions instead.)
#[test]
fn header_names_are_the_readers_in_every_dialect() {
    let d = Dir::new();
    let want: Vec<String> = ["t", "q1", "qd1"].map(String::from).into();
    for (name, text) in [
        ("plain.csv", "t,q1,qd1\n0,1,2\n"),
        ("quoted.csv", "\"t\",\"q1\",\"qd1\"\n0,1,2\n"),
        ("blank.csv", "\n\nt,q1,qd1\n0,1,2\n"),
        ("comment.csv", "# logger v2\nt, q1 ,qd1\r\n0,1,2\r\n"),
        ("bom.csv", "\u{feff}t,q1,qd1\n0,1,2\n"),
        ("last.csv", "t,q1,qd1"),
        ("semicolons.csv", "t;q1;qd1\n0;1;2\n"),
        ("tabs.csv", "# a, b\nt\tq1\tqd1\n0\t1\t2\n"),
        ("rtde.csv", "t q1 qd1\r\n0 1 2\r\n"),
    ] {
        assert_eq!(read_header(&d.file(name, text)).unwrap(), want, "{name}");
        let columns = read_columns(&d.file(name, text), &want);
        if name != "last.csv" {
            assert_eq!(
                columns.unwrap().columns,
                vec![vec![0.0], vec![1.0], vec![2.0]]
            );
        }
    }
    let gz = d.0.path().join("log.csv.gz");
    let mut e = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
    std::io::Write::write_all(&mut e, b"\"t\",q1,qd1\n0,1,2\n").unwrap();
    std::fs::write(&gz, e.finish().unwrap()).unwrap();
    assert_eq!(read_header(&gz).unwrap(), want);
    assert!(read_header(&d.file("empty.csv", "")).unwrap().is_empty());
}

#[test]
fn missing_sample_rate_and_roles_are_errors() {
    let d = Dir::new();
    let a = d.file("x.csv", "q1,t1\n0,0\n1,1\n");
    let e = load(
        &cfg("[[source]]\nposition = \"q{}\"\ntorque = \"t{}\""),
        std::slice::from_ref(&a),
        1,
    )
    .unwrap_err();
    assert!(e.to_string().contains("sample_rate"), "{e}");
    let e = load(
        &cfg("sample_rate = 1.0\n[[source]]\nposition = \"q{}\""),
        std::slice::from_ref(&a),
        1,
    )
    .unwrap_err();
    assert!(e.to_string().contains("torque"), "{e}");
    let e = load(
        &cfg("sample_rate = 1.0\n[[source]]\nposition = \"q{}\"\ntorque = \"t{}\""),
        &[a.clone(), a],
        1,
    )
    .unwrap_err();
    assert!(e.to_string().contains("2 files"), "{e}");
}

const TIMED: &str = r#"
time_column = "t"
[[source]]
position = "q{}"
[[source]]
torque = "tau{}"
"#;

#[test]
fn irregular_time_is_resampled_with_a_warning() {
    let d = Dir::new();
    // q = 2 t sampled irregularly: resampling must stay on the line
    let a = d.file("q.csv", "t,q1\n0,0\n0.1,0.2\n0.25,0.5\n0.3,0.6\n0.4,0.8\n");
    let b = d.file("tau.csv", "t,tau1\n0,0\n0.2,2\n0.4,4\n");
    let data = load(&cfg(TIMED), &[a, b], 1).unwrap();
    assert!((data.sample_time - 0.1).abs() < 1e-12);
    // (and the torques' 5 Hz is slow: warned about too)
    assert!(
        data.warnings
            .iter()
            .any(|w| matches!(w, Warning::IrregularTime { .. }))
    );
    for k in 0..5 {
        let t = 0.1 * k as f64;
        assert!((data.q[0][k] - 2.0 * t).abs() < 1e-12);
        assert!((data.tau[0][k] - 10.0 * t).abs() < 1e-12, "joined by time");
    }
}

/// A 1 kHz clock that lost every 37th tick is resampled onto its tick, not onto its mean
/// step (1.028 ms): every sample it kept falls on the grid with its value and its line,
/// only the lost ticks are interpolated, and the noise keeps its variance. On the mean
/// step's grid every sample was interpolated between two: the noise's standard deviation
/// came out 18 % too small (0.82 of the file's, measured on this clock), and the
/// identified parameters' stated standard deviations with it.
#[test]
fn a_clock_that_lost_ticks_is_resampled_onto_its_tick() {
    let d = Dir::new();
    let text = "time_column = \"t\"\n[[source]]\nposition = \"q{}\"\ntorque = \"tau{}\"";
    let (ticks, mut seed) = (4000usize, 12345u64);
    let mut noise = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let (mut csv, mut kept) = (String::from("t,q1,tau1\n"), Vec::new());
    for k in (0..=ticks).filter(|k| k % 37 != 36) {
        let (t, tau) = (k as f64 * 1e-3, noise());
        csv += &format!("{t},{},{tau}\n", (3.0 * t).sin());
        kept.push((k, tau));
    }
    let path = d.file("lost.csv", &csv);
    let data = load(&cfg(text), std::slice::from_ref(&path), 1).unwrap();
    assert!(
        (data.sample_time - 1e-3).abs() < 1e-15,
        "{}",
        data.sample_time
    );
    assert_eq!(data.samples(), ticks + 1);
    assert!(
        matches!(data.warnings[..], [Warning::IrregularTime { skipped_ticks: 108, step, .. }]
            if (step - 1e-3).abs() < 1e-15),
        "{:?}",
        data.warnings
    );
    let lines = &data.origin.as_ref().unwrap().lines;
    for (row, &(k, tau)) in kept.iter().enumerate() {
        assert!((data.tau[0][k] - tau).abs() < 1e-12, "tick {k}");
        assert_eq!(lines[k], row as u64 + 2, "tick {k}");
    }
    let variance = |x: &[f64]| {
        let mean = x.iter().sum::<f64>() / x.len() as f64;
        x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / x.len() as f64
    };
    let file: Vec<f64> = kept.iter().map(|k| k.1).collect();
    let ratio = (variance(&data.tau[0]) / variance(&file)).sqrt();
    assert!(ratio > 0.98, "noise std {ratio} of the file's");
}

/// A 1 kHz log of `rows` rows, `t,q1,tau1`, whose clock pauses for `pause` seconds
/// after row `at` and jitters by up to `jitter` of a step.
fn paused_log(rows: usize, at: usize, pause: f64, jitter: f64) -> String {
    let mut csv = String::from("t,q1,tau1\n");
    for k in 0..rows {
        let wobble = jitter * 1e-3 * ((k * 7919) % 13) as f64 / 12.0;
        let t = k as f64 * 1e-3 + wobble + if k > at { pause } else { 0.0 };
        csv.push_str(&format!("{t},{},1\n", (3.0 * t).sin()));
    }
    csv
}

/// A log whose clock pauses (the logger stopped 30 s in the middle of a 1 kHz record)
/// is refused, naming the line after the gap, both time stamps, the gap against the
/// median step, and the fix; it used to be resampled onto a grid of the mean step (20 ms)
/// with a warning, the 30 s bridged by a straight line. Jitter and a few lost ticks
/// still load, with the warning about irregular steps.
#[test]
fn a_gap_in_the_time_stamps_is_refused_with_its_line() {
    let d = Dir::new();
    let text = "time_column = \"t\"\n[[source]]\nposition = \"q{}\"\ntorque = \"tau{}\"";
    let a = d.file("paused.csv", &paused_log(3000, 1499, 30.0, 0.0));
    let e = load(&cfg(text), std::slice::from_ref(&a), 1).unwrap_err();
    assert!(
        matches!(&e, Error::Data(DataError::TimeGap { location, .. })
            if *location == format!("{}:1502", a.display())),
        "{e}"
    );
    let message = e.to_string();
    for part in [
        "the time stamps jump from 1.499 s to 31.5 s, a gap of 30.001 s, 30000 times the \
         median step of 0.001 s (more than 10 is a gap, not jitter)",
        "set `gaps = \"split\"` in [processing] to cut the record at every gap",
        "or delete the rows on one side of the gap",
    ] {
        assert!(message.contains(part), "{part}: {message}");
    }
    // just above the threshold, on the second source too
    let b = d.file("q.csv", &paused_log(300, 100, 0.0095, 0.0));
    let c = d.file("tau.csv", &paused_log(300, 200, 0.0, 0.0));
    let e = load(&cfg(TIMED), &[c, b.clone()], 1)
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with(&format!("{}:103: ", b.display())) && e.contains("10.5 times"),
        "{e}"
    );
    // just below it: a hole of 9.5 steps is resampled with the warning
    let b = d.file("q.csv", &paused_log(300, 100, 0.0085, 0.0));
    let data = load(&cfg(text), std::slice::from_ref(&b), 1).unwrap();
    assert!(
        matches!(data.warnings[0], Warning::IrregularTime { .. }),
        "{:?}",
        data.warnings
    );
    // a time column in ms, scaled to seconds (9 ms is 0.009000000000000001 s): the stamps
    // are written without the rounding digits
    let mut ms = String::from("t,q1,tau1\n");
    for k in 0..300 {
        let t = if k > 9 { k + 30_000 } else { k };
        ms += &format!("{t},{},1\n", 0.01 * k as f64);
    }
    let b = d.file("ms.csv", &ms);
    let e = load(&cfg(&format!("time_scale = 1e-3\n{text}")), &[b], 1)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("jump from 0.009 s to 30.01 s, a gap of 30.001 s"),
        "{e}"
    );
    // jitter of 40 % of a step and a lost tick load as before
    let b = d.file("q.csv", &paused_log(3000, 700, 0.001, 0.4));
    let data = load(&cfg(text), std::slice::from_ref(&b), 1).unwrap();
    assert!(matches!(data.warnings[0], Warning::IrregularTime { .. }));
}

/// Time stamps 10 s apart (a 100 Hz log's time column in ms) are warned about, naming
/// `time_scale`, by both loaders; 100 Hz is not.
#[test]
fn a_time_column_in_ms_is_warned_about() {
    let d = Dir::new();
    let rows = |scale: f64| {
        let mut text = String::from("t,q1,tau1\n");
        for k in 0..=200 {
            text += &format!("{},{},1\n", scale * k as f64, (0.05 * k as f64).sin());
        }
        text
    };
    let slow = d.file("ms.csv", &rows(10.0));
    let config = cfg("time_column = \"t\"\n[[source]]\nposition = \"q{}\"\ntorque = \"tau{}\"\n");
    let data = load(&config, std::slice::from_ref(&slow), 1).unwrap();
    let w: Vec<String> = data.warnings.iter().map(ToString::to_string).collect();
    assert!(
        w.iter()
            .any(|w| w.contains("ms.csv: time stamps 10 s apart")
                && w.contains("time_scale = 0.001")),
        "{w:?}"
    );
    let record = crate::data::load_record(&config, std::slice::from_ref(&slow), 1).unwrap();
    assert!(
        record
            .warnings()
            .iter()
            .any(|w| matches!(w, Warning::SlowSampling { .. })),
        "{:?}",
        record.warnings()
    );
    let fast = d.file("s.csv", &rows(0.01));
    let data = load(&config, &[fast], 1).unwrap();
    assert!(data.warnings.is_empty(), "{:?}", data.warnings);
}

/// A file joined by time whose steps are more than `GAP_RATIO` times the first file's is
/// refused (its time column in ms beside one in s: two of its 101 stamps fell in the
/// first file's 1 s, and the torque was interpolated between them, with exit 0); a
/// temperature may be logged that slowly.
#[test]
fn a_file_joined_by_time_much_coarser_than_the_first_is_refused() {
    let d = Dir::new();
    let mut q = String::from("t,q1\n");
    let mut ms = String::from("t,tau1\n");
    let mut temperature = String::from("t,T1\n");
    for k in 0..=100 {
        let t = 0.01 * k as f64;
        q += &format!("{t},{}\n", 2.0 * t);
        ms += &format!("{},{}\n", 1000.0 * t, 10.0 * t);
        temperature += &format!("{},{}\n", 0.1 * k as f64, 30.0);
    }
    let a = d.file("q.csv", &q);
    let b = d.file("tau_ms.csv", &ms);
    let e = load(&cfg(TIMED), &[a.clone(), b], 1)
        .unwrap_err()
        .to_string();
    for part in ["tau_ms.csv", "1000 times", "q.csv", "one unit"] {
        assert!(e.contains(part), "{part}: {e}");
    }
    // ten times coarser is a slower logger, not a gap
    let mut slow = String::from("t,tau1\n");
    for k in 0..=10 {
        let t = 0.1 * k as f64;
        slow += &format!("{t},{}\n", 10.0 * t);
    }
    let b = d.file("tau_slow.csv", &slow);
    assert!(load(&cfg(TIMED), &[a.clone(), b], 1).is_ok());
    // a temperature logged at 10 Hz beside positions and torques at 100 Hz
    let mut qt = String::from("t,q1,tau1\n");
    for k in 0..=1000 {
        let t = 0.01 * k as f64;
        qt += &format!("{t},{},{}\n", 2.0 * t, 10.0 * t);
    }
    let a = d.file("qt.csv", &qt);
    let c = d.file("temperature.csv", &temperature);
    let with_temperature = "time_column = \"t\"\n[[source]]\nposition = \"q{}\"\n\
                            torque = \"tau{}\"\n[[source]]\ntemperature = \"T{}\"\n";
    let data = load(&cfg(with_temperature), &[a, c], 1).unwrap();
    assert_eq!(data.samples(), 1001);
}

/// A file of temperatures alone at 1 Hz beside positions and torques at 100 Hz is not
/// warned about as a time column in ms (temperatures vary slowly); a torque file as slow
/// still is.
#[test]
fn a_slow_file_of_temperatures_alone_is_not_warned_about() {
    let d = Dir::new();
    let mut qt = String::from("t,q1,tau1\n");
    for k in 0..=1000 {
        let t = 0.01 * k as f64;
        qt += &format!("{t},{},{}\n", (0.5 * t).sin(), 10.0 * t);
    }
    let (mut temperature, mut torque) = (String::from("t,T1\n"), String::from("t,q1,tau1\n"));
    for k in 0..=10 {
        temperature += &format!("{k},{}\n", 30.0 + 0.1 * k as f64);
        torque += &format!("{k},{},{}\n", 0.1 * k as f64, 10.0 * k as f64);
    }
    let a = d.file("qt.csv", &qt);
    let c = d.file("temperature.csv", &temperature);
    let config = "time_column = \"t\"\n[[source]]\nposition = \"q{}\"\n\
                  torque = \"tau{}\"\n[[source]]\ntemperature = \"T{}\"\n";
    let data = load(&cfg(config), &[a, c], 1).unwrap();
    assert!(
        !data
            .warnings
            .iter()
            .any(|w| matches!(w, Warning::SlowSampling { .. })),
        "{:?}",
        data.warnings
    );
    // a file with positions and torques as slow is warned about
    let b = d.file("tau.csv", &torque);
    let config = "time_column = \"t\"\n[[source]]\nposition = \"q{}\"\n\
                  torque = \"tau{}\"\n";
    let data = load(&cfg(config), &[b], 1).unwrap();
    let w: Vec<String> = data.warnings.iter().map(ToString::to_string).collect();
    assert!(
        w.iter()
            .any(|w| w.contains("tau.csv: time stamps 1 s apart") && w.contains("time_scale")),
        "{w:?}"
    );
}

/// Files joined by time that overlap only partly give the overlap, as the warning says:
/// the samples of the first file outside the second file's time stamps are dropped
/// (they were kept, with the second file's first or last value held there: torques
/// frozen while the positions move). Files that do not overlap are refused.
#[test]
fn files_joined_by_time_keep_only_their_overlap() {
    let d = Dir::new();
    // q = 2 t from 0 to 1 s, tau = 10 t from 0.3 s to 0.8 s
    let mut q = String::from("t,q1\n");
    for k in 0..=100 {
        let t = 0.01 * k as f64;
        q += &format!("{t},{}\n", 2.0 * t);
    }
    let mut tau = String::from("t,tau1\n");
    for k in 30..=80 {
        let t = 0.01 * k as f64;
        tau += &format!("{t},{}\n", 10.0 * t);
    }
    let a = d.file("q.csv", &q);
    let b = d.file("tau.csv", &tau);
    let data = load(&cfg(TIMED), &[a.clone(), b.clone()], 1).unwrap();
    assert_eq!(data.samples(), 51);
    for k in 0..51 {
        let t = 0.3 + 0.01 * k as f64;
        assert!((data.q[0][k] - 2.0 * t).abs() < 1e-9, "{k}");
        assert!((data.tau[0][k] - 10.0 * t).abs() < 1e-9, "{k}");
    }
    // the first sample is line 32 of q.csv (t = 0.3 s)
    assert_eq!(crate::data::Record::line(&data, 0), Some(32));
    assert_eq!(data.warnings.len(), 1, "{:?}", data.warnings);
    let w = data.warnings[0].to_string();
    assert!(
        matches!(
            data.warnings[0],
            Warning::PartialOverlap { dropped: 50, .. }
        ) && w.contains("50 samples of")
            && w.contains("were dropped"),
        "{w}"
    );
    // the other way round: the record is the overlap too
    let reversed = "time_column = \"t\"\n[[source]]\ntorque = \"tau{}\"\n\
                    [[source]]\nposition = \"q{}\"\n";
    let data = load(&cfg(reversed), &[b, a.clone()], 1).unwrap();
    assert_eq!(data.samples(), 51);
    // the rows of the positions outside the torques' time stamps are not used, and said
    assert_eq!(data.warnings.len(), 1, "{:?}", data.warnings);
    let w = data.warnings[0].to_string();
    assert!(
        matches!(
            data.warnings[0],
            Warning::JoinedRowsUnused {
                unused: 50,
                rows: 101,
                ..
            }
        ) && w.contains("50 of its 101 rows")
            && w.contains("tau.csv"),
        "{w}"
    );
    // no overlap: an error naming both files and their time ranges
    let mut late = String::from("t,tau1\n");
    for k in 0..=10 {
        late += &format!("{},1\n", 2.0 + 0.01 * k as f64);
    }
    let c = d.file("late.csv", &late);
    let e = load(&cfg(TIMED), &[a.clone(), c.clone()], 1)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains(&format!("{}", c.display()))
            && e.contains(&format!("{}", a.display()))
            && e.contains("2 s to 2.1 s")
            && e.contains("0 s to 1 s"),
        "{e}"
    );
}

#[test]
fn non_monotonic_time_names_the_line() {
    let d = Dir::new();
    let a = d.file("q.csv", "t,q1\n0,0\n0.1,0.2\n0.1,0.5\n");
    let e = load(&cfg(TIMED), &[a.clone(), a], 1).unwrap_err();
    assert!(
        matches!(e, Error::Data(DataError::NonMonotonicTime { line: 4, .. })),
        "{e}"
    );
}

#[test]
fn too_few_rows_is_an_error() {
    let d = Dir::new();
    let a = d.file("q.csv", "t,q1,tau1\n0,0,0\n");
    let text = "time_column = \"t\"\n[[source]]\nposition = \"q{}\"\ntorque = \"tau{}\"";
    let e = load(&cfg(text), &[a], 1).unwrap_err();
    assert!(matches!(e, Error::TooFewSamples { .. }), "{e}");
}

pub(crate) fn repo_data(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../data")
        .join(rel)
}

/// The TX40 drive chain on the real log: joint-torque ranges as in the dataset README.
#[test]
fn tx40_joint_torque_ranges_match_the_readme() {
    let config = Config::from_file(repo_data("staubli_tx40/identify.toml")).unwrap();
    let data = load(&config, &[], 6).unwrap();
    assert_eq!(data.samples(), 45000);
    assert!((data.sample_time - 2e-4).abs() < 1e-15);
    let expected = [
        (-93.6, 93.2),
        (-95.0, 71.4),
        (-34.4, 28.7),
        (-11.9, 10.3),
        (-21.6, 21.8),
        (-10.4, 12.7),
    ];
    for (j, (lo, hi)) in expected.iter().enumerate() {
        let min = data.tau[j].iter().copied().fold(f64::INFINITY, f64::min);
        let max = data.tau[j]
            .iter()
            .copied()
            .fold(f64::NEG_INFINITY, f64::max);
        // the README rounds to 0.1 N m: at most 0.05 off (measured 0.046 at worst)
        assert!(
            (min - lo).abs() <= 0.05 && (max - hi).abs() <= 0.05,
            "joint {}: [{min}, {max}]",
            j + 1
        );
    }
}

/// The annotated example config is a complete, valid config: it parses, passes its checks
/// and loads its own `file` (relative to the config's folder).
#[test]
fn the_example_config_loads_its_own_file() {
    let d = Dir::new();
    let mut csv = String::from("t,q1,q2,q3,q4,q5,q6,tau_1,tau_2,tau_3,tau_4,tau_5,tau_6\n");
    for k in 0..2000 {
        let t = k as f64 * 1e-3;
        let q = (t * 3.0).sin();
        csv.push_str(&format!("{t},{q},{q},{q},{q},{q},{q},1,2,3,4,5,6\n"));
    }
    d.file("run1.csv.gz", &csv);
    let path = d.file("identify.toml", EXAMPLE_CONFIG);
    let config = Config::from_file(&path).unwrap();
    config.check(6).unwrap();
    let data = load_config_files(&config, 6).unwrap();
    assert_eq!(data.samples(), 2000);
    assert_eq!(data.tau[5][7], 6.0);
    assert_eq!(config.estimation.method, Method::Wls);
}

/// Stale rows and skipped ticks are counted per file and named in the warnings, with the
/// file line of the first stale row; the data are left as they were.
#[test]
fn stale_rows_and_skipped_ticks_are_reported() {
    let d = Dir::new();
    let mut csv = String::from("t,q1,tau1\n");
    let mut t = 0.0;
    for k in 0..400 {
        // a tick missing every 50 rows, a stale row every 100
        t += if k % 50 == 49 { 0.004 } else { 0.002 };
        let q = if k % 100 == 60 {
            0.01 * (k - 1) as f64
        } else {
            0.01 * k as f64
        };
        csv.push_str(&format!("{t},{q},1\n"));
    }
    let a = d.file("run.csv", &csv);
    let text = "time_column = \"t\"\n[[source]]\nposition = \"q{}\"\ntorque = \"tau{}\"";
    let data = load(&cfg(text), &[a], 1).unwrap();
    let s = &data.sampling[0];
    assert_eq!(s.rows, 400);
    assert_eq!(s.skipped_ticks, 8);
    assert_eq!(s.stale_rows, [60, 160, 260, 360]);
    let warnings: Vec<String> = data.warnings.iter().map(ToString::to_string).collect();
    assert!(
        warnings
            .iter()
            .any(|w| w.contains("4 rows (1.0 %, the first at line 62)")),
        "{warnings:?}"
    );
    assert!(
        warnings.iter().any(|w| w.contains("8 skipped ticks")),
        "{warnings:?}"
    );
    // not repaired: the stale value is still there (resampled onto the grid of the tick:
    // the 400 rows and the 8 lost ticks)
    assert_eq!(data.samples(), 408);
    assert!(
        (data.q[0][61] - data.q[0][60]).abs() < 1e-12,
        "row 60 (after a lost tick) repeats row 59"
    );
}

/// A method's name in reports is the one a config writes (serde), for every method.
#[test]
fn method_names_are_the_config_names() {
    use crate::data::Method;
    for m in [
        Method::Ols,
        Method::Wls,
        Method::Rls,
        Method::LinkByLink,
        Method::Energy,
        Method::PerAxis,
    ] {
        let written = toml::to_string(&std::collections::BTreeMap::from([("m", m)])).unwrap();
        assert_eq!(written.trim(), format!("m = \"{}\"", m.name()));
    }
}

/// A log as UR's RTDE recorder writes it (single spaces, `\r\n`, columns numbered from 0)
/// loads through a config with `{0}` templates; a `{}` template on it names the file's
/// numbering and the template that reads it.
#[test]
fn an_rtde_log_loads_with_zero_based_templates() {
    let d = Dir::new();
    let mut text =
        String::from("timestamp actual_q_0 actual_q_1 target_moment_0 target_moment_1\r\n");
    for k in 0..5 {
        let t = k as f64 * 0.002;
        text += &format!("{t} {} {} {} {}\r\n", 0.1 * t, -0.2 * t, 1.5 + t, -2.0 + t);
    }
    let path = d.file("robot_data.csv", &text);
    let config = |q: &str| {
        cfg(&format!(
            "time_column = \"timestamp\"\n[[source]]\nposition = \"actual_q_{q}\"\ntorque = \"target_moment_{q}\"\n"
        ))
    };
    let data = load(&config("{0}"), std::slice::from_ref(&path), 2).unwrap();
    assert_eq!(data.q[1].len(), 5);
    assert!((data.q[1][4] + 0.2 * 0.008).abs() < 1e-15);
    assert!((data.tau[0][2] - 1.504).abs() < 1e-15);
    assert!((data.sample_time - 0.002).abs() < 1e-12);
    let e = load(&config("{}"), &[path], 2).unwrap_err().to_string();
    assert!(e.contains("no column `actual_q_2`"), "{e}");
    assert!(
        e.contains("numbers these columns from 0 (`actual_q_0` to `actual_q_1`)"),
        "{e}"
    );
    assert!(e.contains("`\"actual_q_{0}\"`"), "{e}");
}

/// `[runs]` with one file is refused in words, "1 run: ..." (it was "1 run(s)").
#[test]
fn one_run_is_counted_in_words() {
    let text = "time_column = \"t\"\n[[source]]\nposition = \"q{}\"\ntorque = \"tau{}\"\n\
                [runs]\nfiles = [\"a.csv\"]\n";
    let config = Config::from_toml_str(text, Path::new("runs.toml")).unwrap();
    let e = load_runs(&config, 1).unwrap_err().to_string();
    assert!(
        e.contains("1 run: repeated acquisitions need at least two; list one entry per run"),
        "{e}"
    );
}

/// The warnings of joined and repeated rows agree with their counts: "the 1 samples of
/// that file outside .. were dropped" and "1 of its 2000 rows .. lie" were written.
#[test]
fn warnings_of_one_row_are_in_the_singular() {
    let path = PathBuf::from("c.csv");
    let w = Warning::PartialOverlap {
        path: path.clone(),
        dropped: 1,
    }
    .to_string();
    assert!(
        w.contains("the 1 sample of that file outside the time stamps of this one was dropped"),
        "{w}"
    );
    let w = Warning::JoinedRowsUnused {
        path: path.clone(),
        unused: 1,
        rows: 2000,
        first: PathBuf::from("p.csv"),
    }
    .to_string();
    assert!(
        w.contains("1 of its 2000 rows (0.1 %) lies outside") && w.contains("and is not used"),
        "{w}"
    );
    let w = Warning::StaleRows {
        path,
        stale: 1,
        rows: 10,
        first_line: 3,
    }
    .to_string();
    assert!(
        w.contains("1 row (10.0 %, the first at line 3) repeats the previous row and is followed"),
        "{w}"
    );
}

/// A temperature below absolute zero is refused at its file:line and column, as other
/// values out of range are (-300 deg C was fitted without a word).
#[test]
fn a_temperature_below_absolute_zero_is_refused_at_load() {
    let d = Dir::new();
    let mut qt = String::from("t,q1,tau1,T1\n");
    for k in 0..=100 {
        let t = 0.01 * k as f64;
        let temperature = if k == 40 { -300.0 } else { 30.0 };
        qt += &format!("{t},{},{},{temperature}\n", (3.0 * t).sin(), 10.0 * t);
    }
    let a = d.file("qt.csv", &qt);
    let config = "time_column = \"t\"\n[[source]]\nposition = \"q{}\"\n\
                  torque = \"tau{}\"\ntemperature = \"T{}\"\n";
    let e = load(&cfg(config), &[a], 1).unwrap_err().to_string();
    assert!(
        e.contains("qt.csv:42: column `T1` is -300, outside the accepted range -273.15 <= temperature <= 1e3; repair or remove this row (a value below absolute zero"),
        "{e}"
    );
}
