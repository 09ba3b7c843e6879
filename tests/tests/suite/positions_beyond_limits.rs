//! A log whose positions are in degrees, read as radians (the default `angle = "rad"`),
//! passes the description's position limits many times over, and identification fits it
//! without a word. The loader keeps per joint the extremes of the positions as it reads
//! them (`Record::extremes`, no pass of its own), and `robots::limits::
//! beyond_limits` (what `robid identify` and `robid inspect` warn with) names each joint
//! beyond its limits: for the record kept on disk (`load_record`, one file), the data set
//! in memory (`load`) and each run of `[runs]` (`load_runs`); its velocity column, left
//! in radians per second, is named as disagreeing with those positions. The same log in
//! radians gives no warning.

use std::path::Path;

use robid_runtime::data::{Config, Record, load, load_record, load_runs};
use robots::limits::beyond_limits;
use tests::fuzz_data::{self, Motion};
use tests::scratch::Scratch;

/// The UR5e's motion (within its limits in radians) with its positions in degrees.
fn in_degrees(mut m: Motion) -> Motion {
    for joint in m.signals[0].joints_mut() {
        joint.iter_mut().for_each(|q| *q = q.to_degrees());
    }
    m
}

const CONFIG: &str = "time_column = \"t\"\n[[source]]\nposition = \"q{}\"\n\
                      velocity = \"qd{}\"\nacceleration = \"qdd{}\"\ntorque = \"tau{}\"\n";

#[test]
fn a_log_in_degrees_read_as_radians_is_named_beyond_the_limits() {
    let tmp = Scratch::new();
    let radians = fuzz_data::motion(600);
    let degrees = in_degrees(fuzz_data::motion(600));
    let rad = tmp.write("radians.csv", &fuzz_data::motion_csv(&radians));
    let deg = tmp.write("degrees.csv", &fuzz_data::motion_csv(&degrees));
    let robot = robots::Reference::named("ur5e").unwrap().robot();
    let description = Path::new("ur5e.toml");
    // the largest excursion in radians, and so in degrees
    let top: Vec<f64> = radians.signals[0]
        .joints()
        .map(|q| q.iter().fold(0.0f64, |a, v| a.max(v.abs())))
        .collect();
    assert!(top.iter().all(|&t| (0.5..1.2).contains(&t)), "{top:?}");
    let config = Config::from_toml_str(CONFIG, &tmp.path("c.toml")).unwrap();
    let warnings = |record: &dyn Record| beyond_limits(&robot, record.extremes(), description);
    // every joint beyond its limits ([-6.2832, 6.2832] rad, joint 3 [-3.1416, 3.1416]):
    // its excursion of 30 to 70 degrees read as radians; and its velocity column, left in
    // radians per second, 1 / 57.3 of the derivative of those positions
    let check = |w: Vec<String>, how: &str| {
        assert_eq!(w.len(), 12, "{how}: {w:?}");
        for (j, w) in w.chunks(2).enumerate() {
            assert!(
                w[0].starts_with(&format!("joint {}'s positions span [", j + 1))
                    && w[0].contains("rad, beyond its limits [")
                    && w[0].contains("in ur5e.toml: positions in degrees, or motor angles? set `angle = \"deg\"` in [units]"),
                "{how}: {}", w[0]
            );
            assert!(
                w[1].starts_with(&format!(
                    "joint {}'s velocity column is 0.0175 times the derivative of its positions",
                    j + 1
                )) && w[1].contains(
                    "are the positions in degrees and the velocities in radians per second?"
                ),
                "{how}: {}",
                w[1]
            );
        }
        // the span is the log's: joint 1's largest position in degrees, to 4 digits
        let hi = degrees.signals[0][0]
            .iter()
            .fold(f64::MIN, |a, &v| a.max(v));
        let told = format!("{}]", robid_runtime::Num::rounded(hi, 4));
        assert!(w[0].contains(&told), "{how}: `{told}` in {}", w[0]);
    };
    // the record kept on disk, read window by window
    let record = load_record(&config, std::slice::from_ref(&deg), 6).unwrap();
    assert!(record.samples() == 600 && record.as_ref().extremes().position.len() == 6);
    check(warnings(record.as_ref()), "on disk");
    // in memory
    check(
        warnings(&load(&config, std::slice::from_ref(&deg), 6).unwrap()),
        "in memory",
    );
    // in radians: nothing
    let record = load_record(&config, std::slice::from_ref(&rad), 6).unwrap();
    assert_eq!(warnings(record.as_ref()), Vec::<String>::new());
    // runs: the second one in degrees
    let runs = format!("{CONFIG}[runs]\nfiles = [\"radians.csv\", \"degrees.csv\"]\n");
    let config = Config::from_toml_str(&runs, &tmp.path("runs.toml")).unwrap();
    let sets = load_runs(&config, 6).unwrap();
    assert_eq!(warnings(&sets[0]), Vec::<String>::new());
    check(warnings(&sets[1]), "run 2");
}

/// The same motion's torques in mN m, read as N m (the default `torque_scale = 1`): every
/// joint whose torque passes five times its limit (the UR5e's 150, 150, 150, 28, 28, 28
/// N m) is named with its peak and the settings to look at, in memory and on disk; the
/// torques in N m give no warning, nor does the log in mN m with `torque_scale = 1e-3`.
#[test]
fn torques_in_millinewton_metres_read_as_newton_metres_are_named_beyond_the_limits() {
    let tmp = Scratch::new();
    let mut milli = fuzz_data::motion(600);
    for joint in milli.signals[3].joints_mut() {
        joint.iter_mut().for_each(|tau| *tau *= 1e3);
    }
    let newton = fuzz_data::motion(600);
    // the joints whose torque in mN m passes five times the limit
    let limits = [150.0, 150.0, 150.0, 28.0, 28.0, 28.0];
    let expected: Vec<usize> = (0..6)
        .filter(|&j| {
            let peak = milli.signals[3][j]
                .iter()
                .fold(0.0f64, |a, v| a.max(v.abs()));
            peak > 5.0 * limits[j]
        })
        .collect();
    assert!(expected.len() >= 3, "{expected:?}");
    let path = tmp.write("milli.csv", &fuzz_data::motion_csv(&milli));
    let plain = tmp.write("newton.csv", &fuzz_data::motion_csv(&newton));
    let robot = robots::Reference::named("ur5e").unwrap().robot();
    let description = Path::new("ur5e.toml");
    let config = Config::from_toml_str(CONFIG, &tmp.path("c.toml")).unwrap();
    let warnings = |record: &dyn Record| beyond_limits(&robot, record.extremes(), description);
    let check = |w: Vec<String>, how: &str| {
        assert_eq!(w.len(), expected.len(), "{how}: {w:?}");
        for (w, &j) in w.iter().zip(&expected) {
            assert!(
                w.starts_with(&format!("joint {}'s torques reach ", j + 1))
                    && w.contains(&format!("times its limit {} N m in ur5e.toml", limits[j]))
                    && w.contains("set `torque_scale` in the config's [units]"),
                "{how}: {w}"
            );
        }
    };
    let record = load_record(&config, std::slice::from_ref(&path), 6).unwrap();
    check(warnings(record.as_ref()), "on disk");
    check(
        warnings(&load(&config, std::slice::from_ref(&path), 6).unwrap()),
        "in memory",
    );
    let record = load_record(&config, std::slice::from_ref(&plain), 6).unwrap();
    assert_eq!(warnings(record.as_ref()), Vec::<String>::new());
    let scaled = format!("{CONFIG}[units]\ntorque_scale = 1e-3\n");
    let config = Config::from_toml_str(&scaled, &tmp.path("s.toml")).unwrap();
    let record = load_record(&config, &[path], 6).unwrap();
    assert_eq!(warnings(record.as_ref()), Vec::<String>::new());
}
