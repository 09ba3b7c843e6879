//! A record kept on disk against the data set `load` gives: the same samples to the bit,
//! the same statistics and warnings, and the same errors.

use std::path::{Path, PathBuf};

use super::*;
use crate::data::RATE_CHECK_ROWS;
use crate::signal::Signals;

/// A 3-joint log of `n` rows at 1 kHz, `t,p1..p3,v1..v3,c1..c3`, with comment and blank
/// lines inside, and a stale row every 97 rows (repeated, then caught up).
fn log(n: usize) -> String {
    let mut out = String::from("# a logger's preamble\nt,p1,p2,p3,v1,v2,v3,c1,c2,c3\n");
    for k in 0..n {
        if k % 500 == 250 {
            out.push_str("# a comment\n\n");
        }
        // the stale row: the previous row's values again
        let s = if k % 97 == 50 { k - 1 } else { k } as f64;
        let t = k as f64 * 1e-3;
        let p: Vec<f64> = (1..=3)
            .map(|j| (0.7 * j as f64 * s * 1e-3).sin() * 30.0)
            .collect();
        let v: Vec<f64> = (1..=3)
            .map(|j| (0.7 * j as f64 * s * 1e-3).cos() * 20.0)
            .collect();
        let c: Vec<f64> = (1..=3).map(|j| 0.01 * s + j as f64).collect();
        out.push_str(&format!(
            "{t},{},{},{},{},{},{},{},{},{}\n",
            p[0], p[1], p[2], v[0], v[1], v[2], c[0], c[1], c[2]
        ));
    }
    out
}

/// Degrees, a torque scale, and motor-side positions and torques through a coupled
/// drive chain: every conversion `load` makes.
const CONFIG: &str = r#"
dof = 3
time_column = "t"
[[source]]
position = "p{}"
velocity = "v{}"
torque = "c{}"
[units]
angle = "deg"
torque_scale = [1.5, 2.0, 0.5]
[drive]
position_side = "motor"
torque_side = "motor"
gear_ratios = [100, -80, 50]
position_coupling = [[100, 0, 0], [0, -80, 0], [0, 30, 50]]
[processing]
lowpass = { cutoff = 20.0, order = 4, signals = ["q"] }
"#;

/// The data set's signals in the loader's roles order.
fn signals_of(d: &Dataset) -> [Option<&Signals>; 7] {
    [
        Some(&d.q),
        d.qd.as_ref(),
        d.qdd.as_ref(),
        Some(&d.tau),
        d.motor.as_ref(),
        d.temperature.as_ref(),
        d.joint_torque.as_ref(),
    ]
}

fn config(text: &str) -> Config {
    Config::from_toml_str(text, Path::new("test.toml")).unwrap()
}

fn file(dir: &tempfile::TempDir, text: &str) -> PathBuf {
    let path = dir.path().join("log.csv");
    std::fs::write(&path, text).unwrap();
    path
}

/// Windows of 4 KiB: the 3000 rows are read in about 60 windows, so that stale runs,
/// comments and time steps fall across their ends.
const SMALL: usize = 4096;

#[test]
fn blocks_are_the_loaded_samples_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let path = file(&dir, &log(3000));
    let config = config(CONFIG);
    let data = load(&config, std::slice::from_ref(&path), 3).unwrap();
    let record = SpilledRecord::open_in(&config, &[path], 3, SMALL)
        .unwrap()
        .expect("one regular file is kept on disk");
    assert!(record.chunks.len() > 40, "{} windows", record.chunks.len());
    let n = data.samples();
    assert_eq!(
        (record.samples(), record.dof(), record.name()),
        (n, 3, data.name.as_str())
    );
    assert_eq!(record.sample_time().to_bits(), data.sample_time.to_bits());
    assert_eq!(record.sampling(), &data.sampling[0]);
    assert!(!record.sampling().stale_rows.is_empty());
    assert_eq!(
        format!("{:?}", record.warnings()),
        format!("{:?}", data.warnings)
    );
    for (a, b) in [
        (0, n),
        (0, 1),
        (17, 1234),
        (n - 5, n + 10),
        (999, 1001),
        (250, 251),
    ] {
        let from_disk = record.read(a, b).unwrap();
        let in_memory = data.read(a, b).unwrap();
        assert_eq!(bits(&from_disk), bits(&in_memory), "{a}..{b}");
        assert_eq!(from_disk.origin, in_memory.origin, "{a}..{b}");
        assert_eq!(
            from_disk.sample_time.to_bits(),
            in_memory.sample_time.to_bits()
        );
    }
    for k in [0, 1, 249, 250, 251, 1500, n - 1] {
        assert_eq!(record.location(k), data.location(k), "sample {k}");
    }
    assert!(record.read(n, n + 1).is_err() && record.read(5, 5).is_err());
    assert_eq!(record.line(n), None);
}

/// A motor angle logged modulo a turn (here degrees in [-180, 180): a single-turn encoder
/// of a motion of +-400 degrees) is unwrapped on disk as in memory, to the bit, with the
/// same warning, and gives the samples of the log written unwrapped (to the rounding of
/// a turn added).
#[test]
fn wrapped_angles_are_unwrapped_on_disk_as_in_memory() {
    let dir = tempfile::tempdir().unwrap();
    let wrap = |text: &str| -> String {
        let mut lines = text.lines();
        let mut out = String::new();
        for l in lines.by_ref() {
            out += &format!("{l}\n");
            if l.starts_with("t,") {
                break;
            }
        }
        for l in lines {
            let mut f: Vec<String> = l.split(',').map(str::to_string).collect();
            if f.len() > 1 {
                let p: f64 = f[1].parse().unwrap();
                f[1] = ((13.0 * p + 180.0).rem_euclid(360.0) - 180.0).to_string();
            }
            out += &(f.join(",") + "\n");
        }
        out
    };
    let scaled = |text: &str| -> String {
        let mut out = String::new();
        for l in text.lines() {
            let mut f: Vec<String> = l.split(',').map(str::to_string).collect();
            if let Some(p) = f.get(1).and_then(|x| x.parse::<f64>().ok()) {
                f[1] = (13.0 * p).to_string();
            }
            out += &(f.join(",") + "\n");
        }
        out
    };
    let config = config(CONFIG);
    let path = file(&dir, &wrap(&log(3000)));
    let data = load(&config, std::slice::from_ref(&path), 3).unwrap();
    let record = SpilledRecord::open_in(&config, std::slice::from_ref(&path), 3, SMALL)
        .unwrap()
        .expect("one regular file is kept on disk");
    let n = data.samples();
    assert_eq!(
        bits(&record.read(0, n).unwrap()),
        bits(&data.read(0, n).unwrap())
    );
    let warnings = format!("{:?}", record.warnings());
    assert_eq!(warnings, format!("{:?}", data.warnings));
    let told = data.warnings.iter().map(ToString::to_string);
    let told: Vec<String> = told
        .filter(|w| w.contains("jump by a whole turn"))
        .collect();
    // +-390 degrees about 0: two turns out and back, more than once
    assert!(
        told.len() == 1 && told[0].contains("joint 1's positions jump by a whole turn (360)"),
        "{told:?}"
    );
    let plain_path = dir.path().join("plain.csv");
    std::fs::write(&plain_path, scaled(&log(3000))).unwrap();
    let plain = load(&config, &[plain_path], 3).unwrap();
    let worst = (0..n)
        .map(|k| (data.q[0][k] - plain.q[0][k]).abs())
        .fold(0.0, f64::max);
    assert!(worst < 1e-12, "{worst}");
}

/// The loader keeps per joint the extremes of the joint-side positions and torques (after
/// the units and the drive chain) as it reads them: on disk window by window and in
/// memory, both the data set's own, to the bit. A slice (a block read) does not claim the
/// record's.
#[test]
fn the_loader_keeps_the_extremes() {
    let dir = tempfile::tempdir().unwrap();
    let path = file(&dir, &log(3000));
    let config = config(CONFIG);
    let data = load(&config, std::slice::from_ref(&path), 3).unwrap();
    let record = SpilledRecord::open_in(&config, &[path], 3, SMALL)
        .unwrap()
        .expect("one regular file is kept on disk");
    let extremes = |x: &crate::signal::Signals| -> Vec<[u64; 2]> {
        x.joints()
            .map(|v| {
                let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
                let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
                [lo.to_bits(), hi.to_bits()]
            })
            .collect()
    };
    let bits = |r: &[[f64; 2]]| -> Vec<[u64; 2]> {
        r.iter().map(|[a, b]| [a.to_bits(), b.to_bits()]).collect()
    };
    let (q, tau) = (extremes(&data.q), extremes(&data.tau));
    assert_eq!(q.len(), 3);
    for kept in [Record::extremes(&data), record.extremes()] {
        assert_eq!(bits(&kept.position), q);
        assert_eq!(bits(&kept.torque), tau);
    }
    // the velocities' agreement with the positions, window by window on disk (the strides
    // across a window's edge left out): joint 1's velocity column, 20 cos(0.7 t) beside
    // positions 30 sin(0.7 t), is 20 / 21 of their derivative through the drive chain
    let scales =
        |e: &Extremes| -> Vec<f64> { e.velocity.iter().map(|a| a.scale().unwrap()).collect() };
    let (memory, disk) = (scales(Record::extremes(&data)), scales(record.extremes()));
    assert_eq!((memory.len(), disk.len()), (3, 3));
    assert!((memory[0] - 20.0 / 21.0).abs() < 1e-3, "{memory:?}");
    for (a, b) in memory.iter().zip(&disk) {
        // measured 1e-4 to 4.4e-4 apart (each window starts its strides afresh, and the
        // log repeats a row every 97)
        assert!(
            (a - b).abs() < 1e-3 * a.abs(),
            "{memory:?} against {disk:?}"
        );
    }
    // joint side: 30 degrees of the motors through gear ratios of 50 and more (and the
    // coupling), in radians
    let position = &data.extremes.position;
    assert!(
        position
            .iter()
            .all(|[lo, hi]| lo < hi && hi.abs().max(lo.abs()) < 0.02),
        "{position:?}"
    );
    assert_eq!(data.slice(0, 10).unwrap().extremes, Extremes::default());
}

#[test]
fn errors_are_those_of_load() {
    let dir = tempfile::tempdir().unwrap();
    let rows: Vec<String> = log(2000).lines().map(str::to_string).collect();
    // the index in `rows` of data row k (after the preamble, header and comments)
    let data_rows: Vec<usize> = (0..rows.len())
        .filter(|&i| rows[i].starts_with(|c: char| c.is_ascii_digit()))
        .collect();
    let with = |k: usize, row: &str| {
        let mut r = rows.clone();
        r[data_rows[k]] = row.to_string();
        r.join("\n") + "\n"
    };
    let mut cases = vec![
        (CONFIG.to_string(), with(1700, "1.7,0,0,0,0,0,0,0,0,nan")),
        (CONFIG.to_string(), with(900, "0.9,0,0,0,0,0,0,0,1e300,0")),
        (CONFIG.to_string(), with(1200, "1.2,0,0,0,0,0,0,0,0")),
        (CONFIG.replace("cutoff = 20.0", "cutoff = 600.0"), log(2000)),
        (CONFIG.replace("c{}", "x{}"), log(2000)),
        (
            CONFIG.replace(
                "time_column = \"t\"",
                "time_column = \"t\"\ntime_scale = 1e-6",
            ),
            log(2000),
        ),
    ];
    // time going back at each of 60 rows in a row: some are a window's first
    for k in 1000..1060 {
        let (_, rest) = rows[data_rows[k]].split_once(',').unwrap();
        cases.push((CONFIG.to_string(), with(k, &format!("0,{rest}"))));
    }
    for (i, (text, csv)) in cases.into_iter().enumerate() {
        let config = config(&text);
        let path = file(&dir, &csv);
        let Err(dense) = load(&config, std::slice::from_ref(&path), 3) else {
            panic!("case {i} loads");
        };
        let record = load_record_in(&config, &[path], 3, SMALL).err();
        assert_eq!(
            record.map(|e| e.to_string()),
            Some(dense.to_string()),
            "case {i}"
        );
    }
}

/// `log(n)` with the time stamp of data row k replaced by `stamp(k)`.
fn restamped(n: usize, stamp: impl Fn(usize) -> f64) -> String {
    let mut k = 0;
    log(n)
        .lines()
        .map(|line| match line.split_once(',') {
            Some((t, rest)) if t.parse::<f64>().is_ok() => {
                k += 1;
                format!("{},{rest}\n", stamp(k - 1))
            }
            _ => format!("{line}\n"),
        })
        .collect()
}

/// Irregular time stamps (what `load` resamples) are kept on disk and resampled as each
/// block is read, to the same values as `load`'s, bit for bit: a jittered clock with lost
/// ticks, a clock whose rate drifts, so that the grid runs up to 15 samples away from
/// the rows (across the ends of the 4 KiB windows), and a clock on the grid but for a
/// late stamp every 100 rows (a block's ends then fall on stamps). They used to be loaded in memory,
/// however long: a real logger's clock always jitters.
#[test]
fn irregular_clocks_are_resampled_on_disk_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let n = 3000;
    // up to 0.2 ms either way, two ticks lost after row 1500 and one after 2200
    let jittered = |k: usize| {
        let jitter = ((k * 7919) % 41) as f64 / 40.0 - 0.5;
        let lost = if k > 2200 {
            3e-3
        } else if k > 1500 {
            2e-3
        } else {
            0.0
        };
        k as f64 * 1e-3 + 0.4e-3 * jitter + lost
    };
    // steps from 1 ms to 1.04 ms
    let drifting = |k: usize| k as f64 * 1e-3 * (1.0 + 0.02 * k as f64 / n as f64);
    // on the grid but every 100th stamp, 0.3 ms late: most grid times fall on a stamp
    let late = |k: usize| k as f64 * 1e-3 + if k % 100 == 50 { 0.3e-3 } else { 0.0 };
    let config = config(CONFIG);
    for (name, csv) in [
        ("jittered", restamped(n, jittered)),
        ("drifting", restamped(n, drifting)),
        ("on the grid", restamped(n, late)),
    ] {
        let path = file(&dir, &csv);
        let data = load(&config, std::slice::from_ref(&path), 3).unwrap();
        assert!(
            data.warnings
                .iter()
                .any(|w| matches!(w, Warning::IrregularTime { .. })),
            "{name}: {:?}",
            data.warnings
        );
        let record = SpilledRecord::open_in(&config, std::slice::from_ref(&path), 3, SMALL)
            .unwrap()
            .unwrap_or_else(|| panic!("{name}: kept on disk"));
        assert!(
            record.chunks.len() > 40,
            "{name}: {} windows",
            record.chunks.len()
        );
        assert_eq!(record.samples(), data.samples(), "{name}");
        assert_eq!(record.sample_time().to_bits(), data.sample_time.to_bits());
        assert_eq!(record.sampling(), &data.sampling[0], "{name}");
        assert_eq!(
            format!("{:?}", record.warnings()),
            format!("{:?}", data.warnings),
            "{name}"
        );
        // the grid's samples: the rows and the lost ticks
        let m = data.samples();
        let mut ranges = vec![(0, m), (0, 1), (m - 1, m), (m - 5, m + 10), (1490, 1520)];
        ranges.extend((0..40).map(|i| (i * 71, i * 71 + 1 + (i * 37) % 200)));
        for (a, b) in ranges {
            let from_disk = record.read(a, b).unwrap();
            let in_memory = data.read(a, b).unwrap();
            assert_eq!(bits(&from_disk), bits(&in_memory), "{name}: {a}..{b}");
            assert_eq!(from_disk.origin, in_memory.origin, "{name}: {a}..{b}");
        }
        // `load_record` keeps it on disk: its warnings are the record's
        let loaded = load_record_in(&config, &[path], 3, SMALL).unwrap();
        assert_eq!(loaded.read(0, m).unwrap().q, data.q, "{name}");
        // each sample's line, read alone, is the one read with its block
        for k in [0, 1, 1501, 1502, 2203, m - 1] {
            let lines = &data.origin.as_ref().unwrap().lines;
            assert_eq!(record.line(k), Some(lines[k]), "{name}: {k}");
        }
        assert_eq!(record.line(m), None, "{name}");
    }
}

/// [`CONFIG`] with `sample_rate = rate` instead of its time column (line 3).
fn at_rate(rate: &str) -> String {
    CONFIG.replace("time_column = \"t\"", &format!("sample_rate = {rate}"))
}

/// `log(n)` with the time column `t` written by `stamp(k)` for row k (`None`: no time
/// column), its header renamed `name`.
fn stamped(n: usize, name: &str, stamp: Option<&dyn Fn(usize) -> String>) -> String {
    let mut k = 0;
    log(n)
        .lines()
        .map(|line| {
            let Some((first, rest)) = line.split_once(',') else {
                return format!("{line}\n");
            };
            if first == "t" {
                return match stamp {
                    Some(_) => format!("{name},{rest}\n"),
                    None => format!("{rest}\n"),
                };
            }
            if line.starts_with('#') {
                return format!("{line}\n");
            }
            let row = match stamp {
                Some(s) => format!("{},{rest}\n", s(k)),
                None => format!("{rest}\n"),
            };
            k += 1;
            row
        })
        .collect()
}

/// A config's `sample_rate` is checked against a time column of the file that it does
/// not read: a log at 500 Hz with `sample_rate = 1000` is refused, by `load`, by the
/// record on disk (read in windows) and by `load_record`, with one message; at 500 it
/// loads, on disk as in memory, and so does a file without a time column.
#[test]
fn a_time_column_at_another_rate_than_sample_rate_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let path = file(
        &dir,
        &stamped(3000, "t", Some(&|k| format!("{}", k as f64 * 2e-3))),
    );
    let files = std::slice::from_ref(&path);
    let wrong = config(&at_rate("1000.0"));
    let dense = load(&wrong, files, 3).unwrap_err();
    assert_eq!(
        dense.to_string(),
        format!(
            "test.toml:3:1: `sample_rate`: 1000 Hz, but the time column `t` of {} steps at \
             500 Hz (median step 0.002 s, read as seconds): every derivative and filter would \
             be off by a factor of 2; replace `sample_rate` by `time_column = \"t\"` to use \
             the time stamps, or correct `sample_rate` (to 500 if the time stamps are right)",
            path.display()
        )
    );
    let disk = SpilledRecord::open_in(&wrong, files, 3, SMALL).unwrap_err();
    assert_eq!(disk.to_string(), dense.to_string());
    let record = load_record_in(&wrong, files, 3, SMALL).err();
    assert_eq!(record.map(|e| e.to_string()), Some(dense.to_string()));
    // the right rate: loaded, kept on disk, the same samples
    let right = config(&at_rate("500.0"));
    let data = load(&right, files, 3).unwrap();
    let record = SpilledRecord::open_in(&right, files, 3, SMALL)
        .unwrap()
        .expect("kept on disk");
    assert_eq!(record.read(0, data.samples()).unwrap().q, data.q);
    assert_eq!(data.sample_time, 2e-3);
    // no time column: nothing to check
    let plain = file(&dir, &stamped(3000, "t", None));
    assert!(!std::fs::read_to_string(&plain).unwrap().contains("\nt,"));
    let plain = std::slice::from_ref(&plain);
    assert!(load(&wrong, plain, 3).is_ok());
    assert!(
        SpilledRecord::open_in(&wrong, plain, 3, SMALL)
            .unwrap()
            .is_some()
    );
}

/// Where the time column is not a clock, or its unit makes it agree, nothing is said; a
/// unit in the column's name is used, and named in the fix.
#[test]
fn a_time_column_that_is_not_a_clock_is_not_checked() {
    let dir = tempfile::tempdir().unwrap();
    let wrong = config(&at_rate("1000.0"));
    let loads = |csv: String| {
        let path = file(&dir, &csv);
        let files = std::slice::from_ref(&path);
        let dense = load(&wrong, files, 3)
            .map(|_| ())
            .map_err(|e| e.to_string());
        let record = load_record_in(&wrong, files, 3, SMALL)
            .map(|_| ())
            .map_err(|e| e.to_string());
        assert_eq!(dense, record);
        dense
    };
    let at = |step: f64| move |k: usize| format!("{}", k as f64 * step);
    for (case, csv) in [
        // a stamp repeated, then going back
        (
            "repeated",
            stamped(3000, "t", Some(&|k| format!("{}", (k / 2) as f64 * 2e-3))),
        ),
        (
            "back",
            stamped(
                3000,
                "time",
                Some(&|k| format!("{}", ((k * 7) % 3000) as f64 * 2e-3)),
            ),
        ),
        // irregular steps: the square of the row number
        (
            "irregular",
            stamped(3000, "t", Some(&|k| format!("{}", (k * k) as f64 * 1e-6))),
        ),
        // text, not numbers: a date
        (
            "text",
            stamped(
                3000,
                "timestamp",
                Some(&|k| format!("2024-05-01T12:00:{k}")),
            ),
        ),
        // milliseconds at the config's rate, and sample numbers, in a column without unit
        ("ms", stamped(3000, "t", Some(&at(1.0)))),
        // not a time name
        ("name", stamped(3000, "tick", Some(&at(2e-3)))),
        ("T", stamped(3000, "T", Some(&at(2e-3)))),
        // within 1 %
        ("close", stamped(3000, "time_s", Some(&at(1.009e-3)))),
    ] {
        assert_eq!(loads(csv), Ok(()), "{case}");
    }
    // sample numbers (or milliseconds at 1 kHz: not told apart) with `sample_rate = 500`
    let path = file(&dir, &stamped(3000, "t", Some(&|k| format!("{}", 7 + k))));
    assert!(load(&config(&at_rate("500.0")), &[path], 3).is_ok());
    // a unit in the name: milliseconds at 500 Hz
    let e = loads(stamped(3000, "time_ms", Some(&at(2.0)))).unwrap_err();
    assert!(
        e.contains("the time column `time_ms` of")
            && e.contains("steps at 500 Hz (median step 0.002 s):")
            && e.contains("`time_column = \"time_ms\"` and `time_scale = 0.001` to use"),
        "{e}"
    );
    // 2 % apart is refused
    let e = loads(stamped(3000, "time_s", Some(&at(1.02e-3)))).unwrap_err();
    assert!(
        e.contains("steps at 980.4 Hz (median step 0.00102 s)"),
        "{e}"
    );
    // two time columns: which one is the clock is not guessed
    let two: String = stamped(3000, "t", Some(&at(2e-3)))
        .lines()
        .map(|l| match l.split_once(',') {
            Some(("t", rest)) => format!("t,time,{rest}\n"),
            Some((t, rest)) if !l.starts_with('#') => format!("{t},{t},{rest}\n"),
            _ => format!("{l}\n"),
        })
        .collect();
    assert_eq!(loads(two), Ok(()));
}

/// A log whose clock pauses is refused as `load` refuses it, also when it would be kept
/// on disk: its clock is irregular, so it is loaded in memory, where the gap is named.
#[test]
fn a_paused_clock_is_refused_as_load_refuses_it() {
    let dir = tempfile::tempdir().unwrap();
    // the logger stopped for 30 s after row 1800
    let mut rows: Vec<String> = log(3000).lines().map(str::to_string).collect();
    let header = rows.iter().position(|r| r.starts_with("t,")).unwrap();
    let mut data_rows = 0;
    for r in rows.iter_mut().skip(header + 1) {
        if let Some((t, rest)) = r.split_once(',')
            && let Ok(t) = t.parse::<f64>()
        {
            if data_rows > 1800 {
                *r = format!("{},{rest}", t + 30.0);
            }
            data_rows += 1;
        }
    }
    let path = file(&dir, &(rows.join("\n") + "\n"));
    let config = config(CONFIG);
    assert!(
        SpilledRecord::open_in(&config, std::slice::from_ref(&path), 3, SMALL)
            .unwrap()
            .is_none()
    );
    let dense = load(&config, std::slice::from_ref(&path), 3).unwrap_err();
    let record = load_record_in(&config, &[path], 3, SMALL).err().unwrap();
    assert!(
        matches!(&record, Error::Data(DataError::TimeGap { .. })),
        "{record}"
    );
    assert_eq!(record.to_string(), dense.to_string());
    assert!(
        record
            .to_string()
            .contains("the time stamps jump from 1.8 s to 31.801 s"),
        "{record}"
    );
}

/// The time column that a config with `sample_rate` does not read is checked over its
/// whole length, not only in its first [`RATE_CHECK_ROWS`] rows: a pause of the logger
/// (a gap, [`crate::data::GAP_RATIO`]) anywhere, or a rate that changes after the first rows, is
/// refused, by `load` and by the record on disk alike, naming the line, the two stamps
/// (or the lines at the other rate) and the fix, also beside a repeated stamp or a field
/// that is not a number. Both used to load without a word.
#[test]
fn a_gap_or_another_rate_anywhere_in_an_unread_time_column_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let rate = config(&at_rate("1000.0"));
    let n = RATE_CHECK_ROWS + RATE_CHECK_ROWS / 2;
    let later = RATE_CHECK_ROWS + 20_000;
    let errors = |csv: String| {
        let path = file(&dir, &csv);
        let files = std::slice::from_ref(&path);
        let dense = load(&rate, files, 3).map(|_| ()).map_err(|e| e.to_string());
        let disk = SpilledRecord::open_in(&rate, files, 3, 1 << 20)
            .map(|_| ())
            .map_err(|e| e.to_string());
        assert_eq!(dense, disk);
        (dense, path)
    };
    // at the rate throughout: loads
    let (ok, _) = errors(stamped(n, "t", Some(&|k| format!("{}", k as f64 * 1e-3))));
    assert_eq!(ok, Ok(()));
    // the logger paused 2 s after row `later`
    let paused = |k: usize| {
        let t = k as f64 * 1e-3;
        format!("{}", if k > later { t + 2.0 } else { t })
    };
    let (e, path) = errors(stamped(n, "t", Some(&paused)));
    let e = e.unwrap_err();
    // the file line of row k: the preamble, the header, a comment and a blank line every
    // 500 rows
    let line_of = |k: usize| 3 + k + 2 * ((k + 250) / 500);
    let line = line_of(later + 1);
    assert!(
        e.starts_with(&format!(
            "{}:{line}, column `t` (not read: the config gives `sample_rate`): the time \
             stamps jump from 120 s to 122.001 s, a gap of 2.001 s, 2000 times the median \
             step of 0.001 s",
            path.display()
        )) && e.contains("split the file at this line into two files"),
        "{e}"
    );
    // and in the first rows too
    let early = |k: usize| {
        format!(
            "{}",
            if k > 1000 {
                k as f64 * 1e-3 + 2.0
            } else {
                k as f64 * 1e-3
            }
        )
    };
    let (e, _) = errors(stamped(3000, "t", Some(&early)));
    assert!(
        e.unwrap_err()
            .contains("the time stamps jump from 1 s to 3.001 s")
    );
    // a stamp repeated and a field that is not a number in the block of the pause
    // hide it no more (each hid every gap of its block)
    let glitches = |k: usize| match k {
        10 => early(9),
        20 => String::new(),
        _ => early(k),
    };
    let (e, _) = errors(stamped(3000, "t", Some(&glitches)));
    assert!(
        e.unwrap_err()
            .contains("the time stamps jump from 1 s to 3.001 s")
    );
    // the rate halves after row `later`: the block of steps it shares with the rate before
    // is no clock, the next is named by its lines
    let slower = |k: usize| {
        let t = if k > later {
            later as f64 * 1e-3 + (k - later) as f64 * 2e-3
        } else {
            k as f64 * 1e-3
        };
        format!("{t}")
    };
    let (e, path) = errors(stamped(n + RATE_CHECK_ROWS, "t", Some(&slower)));
    let e = e.unwrap_err();
    assert!(
        e.starts_with(&format!(
            "test.toml:3:1: `sample_rate`: 1000 Hz, but the time column `t` of {} steps at \
             500 Hz in lines {}-{} (median step 0.002 s): every derivative and filter would \
             be off by a factor of 2; the rate of the file changes before these lines: \
             replace `sample_rate` by `time_column = \"t\"` to use the time stamps",
            path.display(),
            line_of(2 * RATE_CHECK_ROWS),
            line_of(n + RATE_CHECK_ROWS - 1),
        )),
        "{e}"
    );
}

/// `cutoff = "auto"` reads a record kept on disk block by block: the suggestion is the
/// one its data set in memory gets (the position spectra are the same to the bit).
#[test]
fn the_suggested_cutoff_of_a_record_on_disk_is_its_data_sets() {
    let dir = tempfile::tempdir().unwrap();
    let path = file(&dir, &log(3000));
    let config = config(CONFIG);
    let data = load(&config, std::slice::from_ref(&path), 3).unwrap();
    let record = SpilledRecord::open_in(&config, &[path], 3, SMALL)
        .unwrap()
        .unwrap();
    let (a, b) = (
        crate::inspect::suggest_cutoff(&record).unwrap(),
        crate::inspect::suggest_cutoff(&data).unwrap(),
    );
    assert_eq!(format!("{a:?}"), format!("{b:?}"));
}

/// Each signal's values as bits, in the loader's roles order.
fn bits(d: &Dataset) -> [Option<Vec<u64>>; 7] {
    signals_of(d).map(|s| {
        s.map(|s| {
            s.joints()
                .flat_map(|x| x.iter().map(|v| v.to_bits()))
                .collect::<Vec<_>>()
        })
    })
}

/// ms stamps, degrees, motor positions through a coupled chain, temperatures, joint torques.
const EVERY_ROLE: &str = r#"
dof = 2
time_column = "t"
time_scale = 1e-3
[[source]]
position = "p{}"
torque = "c{}"
motor_position = "m{}"
temperature = "T{}"
joint_torque = "j{}"
[units]
angle = "deg"
torque_scale = [1.5, 0.5]
[drive]
position_side = "motor"
torque_side = "motor"
gear_ratios = [100, -80]
position_coupling = [[100, 0], [30, -80]]
"#;

fn every_role(n: usize, stamp: &dyn Fn(usize) -> String) -> String {
    let mut out = String::from("t,p1,p2,m1,m2,T1,T2,j1,j2,c1,c2\n");
    for k in 0..n {
        let s = k as f64;
        let f = |a: f64| format!("{}", (a * s * 1e-2).sin() * 37.3 + a);
        out.push_str(&format!(
            "{},{},{},{},{},{},{},{},{},{},{}\n",
            stamp(k),
            f(0.7),
            f(1.3),
            f(2.1),
            f(0.4),
            f(0.05),
            f(0.06),
            f(1.9),
            f(2.7),
            f(3.1),
            f(0.9)
        ));
    }
    out
}

/// The record of `path` kept on disk (windows of `window` bytes) against `load`: the same
/// samples to the bit over many ranges (every range with `all`), lines, statistics and
/// warnings; or, when it is not kept on disk, `load_record`'s outcome is `load`'s.
/// Whether it was kept on disk.
fn same_as_load(name: &str, config: &Config, path: &Path, window: usize, all: bool) -> bool {
    let dense = load(config, &[path.to_path_buf()], 2);
    let record = match SpilledRecord::open_in(config, &[path.to_path_buf()], 2, window) {
        Ok(Some(r)) => r,
        Ok(None) => {
            let loaded = load_record_in(config, &[path.to_path_buf()], 2, window);
            match (&dense, &loaded) {
                (Err(a), Err(b)) => assert_eq!(a.to_string(), b.to_string(), "{name}"),
                (Ok(_), Ok(_)) => {}
                _ => panic!(
                    "{name}: load {:?} vs load_record {:?}",
                    dense.is_ok(),
                    loaded.is_ok()
                ),
            }
            return false;
        }
        Err(e) => {
            let d = dense.err().map(|e| e.to_string());
            assert!(d.is_some(), "{name}: open refuses ({e}) what load takes");
            let loaded = load_record_in(config, &[path.to_path_buf()], 2, window).err();
            assert_eq!(loaded.map(|e| e.to_string()), d, "{name}");
            return false;
        }
    };
    let data = dense.unwrap_or_else(|e| panic!("{name}: load refuses ({e}) a record kept on disk"));
    let n = data.samples();
    assert_eq!(record.samples(), n, "{name}");
    assert_eq!(
        record.sample_time().to_bits(),
        data.sample_time.to_bits(),
        "{name}"
    );
    assert_eq!(record.sampling(), &data.sampling[0], "{name}");
    assert_eq!(
        format!("{:?}", record.warnings()),
        format!("{:?}", data.warnings),
        "{name}"
    );
    let mut ranges = Vec::new();
    if all {
        for a in 0..n {
            for b in a + 1..=n {
                ranges.push((a, b));
            }
        }
    } else {
        ranges.extend([(0, n), (0, 1), (n - 1, n), (n - 2, n), (0, 2)]);
        ranges.extend((0..200).map(|i| {
            let a = (i * 7919) % n;
            (a, (a + 1 + (i * 37) % 300).min(n))
        }));
    }
    for (a, b) in ranges {
        let d = record
            .read(a, b)
            .unwrap_or_else(|e| panic!("{name}: {a}..{b}: {e}"));
        let m = data.read(a, b).unwrap();
        assert_eq!(bits(&d), bits(&m), "{name}: {a}..{b}");
        assert_eq!(d.origin, m.origin, "{name}: {a}..{b}");
    }
    for k in [0, n / 2, n - 1] {
        assert_eq!(record.location(k), data.location(k), "{name}: {k}");
    }
    true
}

fn write_log(dir: &tempfile::TempDir, text: &str) -> PathBuf {
    let path = dir.path().join("log.csv");
    std::fs::write(&path, text).unwrap();
    path
}

/// A number in [0, 1) drawn from `k`.
fn unit(k: usize) -> f64 {
    ((k as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 11) as f64 / (1u64 << 53) as f64
}

/// Irregular clocks at their edges, kept on disk and resampled block by block, equal
/// `load` to the bit with every role (motor positions, temperatures, joint torques), stamps
/// in ms (`time_scale`), degrees and a coupled drive chain, in files of 64 to 131 rows read in
/// windows of a few rows (a last window of one row among them): stamps 0.5 to 1.5 steps
/// apart, on the grid but for some (grid times on stamps), a clock drifting to twice its
/// rate, a step of exactly 10 median steps (resampled) and just above (refused as `load`
/// refuses it), a stamp going back or repeated (`load`'s error).
#[test]
fn irregular_clocks_at_their_edges_are_resampled_as_load_does() {
    let dir = tempfile::tempdir().unwrap();
    let config = config(EVERY_ROLE);
    type Stamp = Box<dyn Fn(usize) -> String>;
    let stamps: Vec<(&str, Stamp, bool)> = vec![
        (
            "jitter",
            Box::new(|k| format!("{}", k as f64 + 0.3 * (unit(k) - 0.5))),
            true,
        ),
        (
            "steps of 0.5 to 1.5",
            Box::new(|k| format!("{}", (0..k).map(|i| 0.5 + unit(i + 17)).sum::<f64>())),
            true,
        ),
        (
            "on the grid, some late",
            Box::new(|k| {
                if k % 5 == 2 {
                    format!("{k}.25")
                } else {
                    format!("{k}")
                }
            }),
            true,
        ),
        (
            "drifting",
            Box::new(|k| format!("{}", k as f64 * (1.0 + k as f64 / 100.0))),
            true,
        ),
        (
            "gap of 10",
            Box::new(|k| format!("{}", if k >= 30 { k + 9 } else { k })),
            true,
        ),
        (
            "gap above 10",
            Box::new(|k| {
                if k >= 30 {
                    format!("{}", k as f64 + 9.000001)
                } else {
                    format!("{k}")
                }
            }),
            false,
        ),
        (
            "back",
            Box::new(|k| {
                if k == 40 {
                    "38.5".into()
                } else {
                    format!("{k}")
                }
            }),
            false,
        ),
        (
            "repeated",
            Box::new(|k| if k == 40 { "39".into() } else { format!("{k}") }),
            false,
        ),
    ];
    for n in [64, 131] {
        for (name, stamp, kept) in &stamps {
            let path = write_log(&dir, &every_role(n, stamp.as_ref()));
            for window in [180, 333, 1 << 20] {
                let label = format!("{name}, {n} rows, windows of {window} bytes");
                assert_eq!(
                    same_as_load(&label, &config, &path, window, n == 64),
                    *kept,
                    "{label}"
                );
            }
        }
    }
}
