//! Class "messages that name the wrong cause" of issue 11. Each error names its real cause,
//! the kind of input and the place, and the fix:
//!
//! - without a config file a missing column said "... fix the column name in the config":
//!   the default mapping is named as such, a config file's key by file:line;
//! - a qdd outlier got "use a richer trajectory": it is named as an outlier at its row;
//! - a bad trajectory row in `simulate` was blamed on the parameters: it is named by its row;
//! - config keys are named by file:line:column, library settings by their field.

use robid_runtime::EstimateError;
use tests::fuzz_data;
use tests::scratch::Scratch;

use robid_runtime::Error;
use robid_runtime::data::{Config, Cutoff, Lowpass, Signal, load};
use robid_runtime::estimate::QualityWarning;
use robid_runtime::excite::FourierDesign;
use robid_runtime::pipeline::identify;
use robid_runtime::simulate::{Simulation, Trajectory};
use robots::Ur5e;

fn record() -> String {
    fuzz_data::motion_csv(&fuzz_data::motion(400))
}

#[test]
fn a_missing_column_names_where_the_column_names_came_from() {
    let tmp = Scratch::new();
    let text = record().replacen("tau4", "torque4", 1);
    let f = tmp.write("renamed.csv", &text);
    // no config file: the default mapping, and no config file blamed
    let e = load(&Config::default_mapping(), std::slice::from_ref(&f), 6).unwrap_err();
    let m = e.to_string();
    assert!(
        m.contains("no column `tau4`")
            && m.contains("the default column mapping needs the header t,q1..qn,qd1..qdn,qdd1..qddn,tau1..taun"),
        "{m}"
    );
    // it names no config file to fix (there is none); it may suggest writing one
    assert!(!m.contains("in the config") && !m.contains(".toml"), "{m}");
    // a config file: its key at its line
    let cfg = tmp.path("map.toml");
    let config = Config::from_toml_str(
        "time_column = \"t\"\n[[source]]\nposition = \"q{}\"\ntorque = \"tau{}\"\n",
        &cfg,
    )
    .unwrap();
    let e = load(&config, &[f], 6).unwrap_err();
    assert!(
        e.to_string().ends_with(&format!(
            "fix `source[1].torque` at {}:4 or the file's header",
            cfg.display()
        )),
        "{e}"
    );
}

#[test]
fn an_acceleration_outlier_is_named_at_its_row_not_blamed_on_the_trajectory() {
    let tmp = Scratch::new();
    let mut lines: Vec<String> = record().lines().map(str::to_string).collect();
    // data row 150 (file line 152): qdd3 = 5e7, inside the accepted range (1e8)
    let mut fields: Vec<String> = lines[151].split(',').map(str::to_string).collect();
    fields[15] = "5e7".into();
    lines[151] = fields.join(",");
    let f = tmp.write("outlier.csv", &lines.join("\n"));
    let config = Config::default_mapping();
    let data = load(&config, &[f], 6).unwrap();
    let at = "outlier.csv:152";
    match identify(&Ur5e, &data, &config) {
        Err(e) => {
            let m = e.to_string();
            assert!(
                matches!(e, Error::Estimate(EstimateError::Outlier { .. })),
                "{m}"
            );
            assert!(m.contains(at) && !m.contains("richer trajectory"), "{m}");
        }
        Ok(id) => {
            let found = id.estimate.warnings.iter().any(
                |w| matches!(w, QualityWarning::Outlier { location, .. } if location.ends_with(at)),
            );
            assert!(found, "{:?}", id.estimate.warnings);
        }
    }
}

#[test]
fn a_bad_trajectory_row_is_named_by_its_row_not_blamed_on_the_parameters() {
    let tmp = Scratch::new();
    let m = fuzz_data::motion(200);
    // in a file: its line and column
    let mut text = String::from("t");
    for p in ["q", "qd", "qdd"] {
        for j in 1..=6 {
            text.push_str(&format!(",{p}{j}"));
        }
    }
    text.push('\n');
    for k in 0..200 {
        text.push_str(&format!("{}", m.t[k]));
        for block in &m.signals[..3] {
            for (j, v) in block.joints().enumerate() {
                let bad = k == 77 && std::ptr::eq(block, &m.signals[2]) && j == 1;
                text.push_str(&format!(",{}", if bad { 5e8 } else { v[k] }));
            }
        }
        text.push('\n');
    }
    let e = Trajectory::read_csv(&tmp.write("traj.csv", &text), 6).unwrap_err();
    let msg = e.to_string();
    // short: a large round value in exponent form (the line says where it is)
    assert!(msg.contains("traj.csv:79: column `qdd2` is 5e8,"), "{msg}");
    // built in code: the sample and its time
    let [q, qd, mut qdd, _] = m.signals.clone();
    qdd[2][17] = f64::NAN;
    let reference = Trajectory {
        t: m.t.clone(),
        q: q.clone(),
        qd: qd.clone(),
        qdd,
    };
    let base = fuzz_data::ur5e_base();
    let e = Simulation::default()
        .run(&Ur5e, &base, &reference)
        .unwrap_err();
    let msg = e.to_string();
    assert!(
        msg.starts_with("reference trajectory, sample 17 (t = 0.17): qdd3 is NaN"),
        "{msg}"
    );
    assert!(!msg.contains("parameters"), "{msg}");
    // parameters that are inconsistent are named as such
    let good = Trajectory {
        t: m.t.clone(),
        q,
        qd,
        qdd: m.signals[2].clone(),
    };
    let bad: Vec<f64> = base.iter().map(|v| -v).collect();
    let e = Simulation::default().run(&Ur5e, &bad, &good).unwrap_err();
    assert!(
        e.to_string()
            .contains("the parameters are not physically consistent"),
        "{e}"
    );
}

#[test]
fn config_keys_are_named_by_file_line_and_settings_by_their_field() {
    let tmp = Scratch::new();
    let cfg = tmp.path("keys.toml");
    let config = Config::from_toml_str(
        "sample_rate = 0\n[[source]]\nposition = \"q{}\"\ntorque = \"tau{}\"\n",
        &cfg,
    )
    .unwrap();
    let e = config.check(6).unwrap_err();
    assert!(
        e.to_string()
            .starts_with(&format!("{}:1:1: `sample_rate`: 0 Hz", cfg.display())),
        "{e}"
    );
    // settings given in code: their type and field, never "config"
    let e = Simulation {
        bandwidth: -1.0,
        ..Simulation::default()
    }
    .check(6)
    .unwrap_err();
    assert!(matches!(e, Error::Setting { .. }));
    assert_eq!(
        e.to_string(),
        "Simulation `bandwidth`: -1 Hz must lie in (0, 1e6] Hz"
    );
    let e = FourierDesign {
        harmonics: 1,
        ..FourierDesign::default()
    }
    .check(6)
    .unwrap_err();
    assert!(
        e.to_string()
            .starts_with("FourierDesign `harmonics`: 1 must lie between 2 and")
    );
    let mut code = Config::default();
    code.processing.lowpass = Some(Lowpass {
        cutoff: Cutoff::Hz(0.0),
        order: 4,
        signals: vec![Signal::Q],
    });
    let e = code.check(6).unwrap_err();
    assert_eq!(
        e.to_string(),
        "Config `processing.lowpass.cutoff`: 0 Hz must be a positive number"
    );
}

/// Found by the fuzzer: without a config file, time stamps in the wrong unit were reported
/// as a `Config` key. They are named as a problem of the default mapping's time column.
#[test]
fn time_stamps_in_another_unit_under_the_default_mapping_name_the_time_column() {
    let tmp = Scratch::new();
    let text: String = record()
        .lines()
        .enumerate()
        .map(|(i, l)| {
            if i == 0 {
                return format!("{l}\n");
            }
            let (t, rest) = l.split_once(',').unwrap();
            format!("{},{rest}\n", t.parse::<f64>().unwrap() * 1e9)
        })
        .collect();
    let e = load(&Config::default_mapping(), &[tmp.write("ns.csv", &text)], 6).unwrap_err();
    let m = e.to_string();
    assert!(
        m.starts_with("the default config `time_scale`:")
            && m.contains("the time column must be in seconds: convert it"),
        "{m}"
    );
}
