//! Bad input on the identification path (docs/robustness.md#what-is-checked), end to end
//! from files through
//! `load` and `identify` with the compiled UR5e: clear errors naming the file, line or
//! column and the parameters not excited; never a panic.

use robid_runtime::DataError;
use robid_runtime::EstimateError;
use std::path::PathBuf;
use tests::scratch::Scratch;

use robid_runtime::Error;
use robid_runtime::data::{Config, load};
use robid_runtime::pipeline::identify;
use robots::Ur5e;

const CONFIG: &str = r#"
time_column = "t"
[[source]]
position = "q{}"
velocity = "qd{}"
acceleration = "qdd{}"
torque = "tau{}"
"#;

/// A CSV with `rows` samples of a smooth motion of `joints` joints (only joint 1 moves
/// when `only_first`); `edit` may change the text before it is written.
fn csv(
    tmp: &Scratch,
    name: &str,
    rows: usize,
    joints: usize,
    only_first: bool,
    edit: impl Fn(String) -> String,
) -> PathBuf {
    let mut h = vec!["t".to_string()];
    for p in ["q", "qd", "qdd", "tau"] {
        h.extend((1..=joints).map(|j| format!("{p}{j}")));
    }
    let mut s = h.join(",") + "\n";
    for k in 0..rows {
        let t = k as f64 * 0.01;
        let mut row = vec![format!("{t}")];
        for p in 0..4 {
            for j in 0..joints {
                let w = 0.7 + 0.37 * j as f64;
                let a = if only_first && j > 0 { 0.0 } else { 1.0 };
                let v = match p {
                    0 => a * (w * t).sin(),
                    1 => a * w * (w * t).cos(),
                    2 => -a * w * w * (w * t).sin(),
                    _ => (1.3 * w * t).cos() + 0.1 * j as f64,
                };
                row.push(format!("{v}"));
            }
        }
        s += &(row.join(",") + "\n");
    }
    let path = tmp.path(name);
    std::fs::write(&path, edit(s)).unwrap();
    path
}

fn run(tmp: &Scratch, file: PathBuf, config: &str) -> Result<(), Error> {
    let config = Config::from_toml_str(config, &tmp.path("cfg.toml"))?;
    let data = load(&config, &[file], 6)?;
    identify(&Ur5e, &data, &config).map(|_| ())
}

#[test]
fn wrong_joint_count_in_data() {
    let tmp = Scratch::new();
    let e = run(&tmp, csv(&tmp, "five.csv", 400, 5, false, |s| s), CONFIG).unwrap_err();
    assert!(
        matches!(e, Error::Data(DataError::MissingColumn { ref column, .. }) if column == "q6"),
        "{e}"
    );
    let e = run(
        &tmp,
        csv(&tmp, "six.csv", 400, 6, false, |s| s),
        &format!("dof = 5\n{CONFIG}"),
    )
    .unwrap_err();
    // the config's `dof` is named at its file:line
    assert!(
        matches!(&e, Error::Data(DataError::ConfigKey { line: Some(1), key, .. }) if key == "dof"),
        "{e}"
    );
    assert!(
        e.to_string().contains("5 joints, but the model has 6"),
        "{e}"
    );
}

#[test]
fn nan_in_csv_names_the_line_and_column() {
    let tmp = Scratch::new();
    let f = csv(&tmp, "nan.csv", 400, 6, false, |s| {
        let mut lines: Vec<String> = s.lines().map(str::to_string).collect();
        let mut fields: Vec<&str> = lines[10].split(',').collect();
        fields[3] = "NaN";
        lines[10] = fields.join(",");
        lines.join("\n")
    });
    let e = run(&tmp, f, CONFIG).unwrap_err();
    let text = e.to_string();
    assert!(
        matches!(e, Error::Data(DataError::NotFinite { line: 11, .. })),
        "{text}"
    );
    assert!(text.contains("nan.csv") && text.contains("q3"), "{text}");
}

#[test]
fn missing_column_lists_the_header() {
    let tmp = Scratch::new();
    let f = csv(&tmp, "missing.csv", 400, 6, false, |s| {
        s.replacen("tau4", "torque4", 1)
    });
    let e = run(&tmp, f, CONFIG).unwrap_err();
    assert!(
        matches!(e, Error::Data(DataError::MissingColumn { ref column, .. }) if column == "tau4"),
        "{e}"
    );
    assert!(e.to_string().contains("torque4"), "{e}");
}

#[test]
fn non_monotonic_time() {
    let tmp = Scratch::new();
    let f = csv(&tmp, "time.csv", 400, 6, false, |s| {
        let mut lines: Vec<String> = s.lines().map(str::to_string).collect();
        lines.swap(20, 21);
        lines.join("\n")
    });
    let e = run(&tmp, f, CONFIG).unwrap_err();
    assert!(
        matches!(e, Error::Data(DataError::NonMonotonicTime { .. })),
        "{e}"
    );
}

#[test]
fn too_few_samples() {
    let tmp = Scratch::new();
    let e = run(&tmp, csv(&tmp, "short.csv", 1, 6, false, |s| s), CONFIG).unwrap_err();
    assert!(matches!(e, Error::TooFewSamples { .. }), "{e}");
    let trimmed = format!("{CONFIG}[processing]\ntrim = 30\n");
    let e = run(&tmp, csv(&tmp, "short2.csv", 50, 6, false, |s| s), &trimmed).unwrap_err();
    assert!(matches!(e, Error::TooFewSamples { .. }), "{e}");
}

/// The base regressor of the UR5e along the motion of `still.csv` (joint 1 moving, the
/// others at zero), one row block every tenth sample.
fn still_observation() -> nalgebra::DMatrix<f64> {
    use robid_runtime::Model;
    let nb = Ur5e.base_parameter_count();
    let mut rows = Vec::new();
    for k in (0..600).step_by(10) {
        let t = k as f64 * 0.01;
        let w = 0.7;
        let mut q = [0.0; 6];
        let mut qd = [0.0; 6];
        let mut qdd = [0.0; 6];
        q[0] = (w * t).sin();
        qd[0] = w * (w * t).cos();
        qdd[0] = -w * w * (w * t).sin();
        let mut y = vec![0.0; 6 * nb];
        Model::base_regressor_into(&Ur5e, &q, &qd, &qdd, &mut y).unwrap();
        rows.extend(y);
    }
    nalgebra::DMatrix::from_row_slice(rows.len() / nb, nb, &rows)
}

/// The numerical rank of the columns `keep` of `w` (all when `None`), columns scaled to
/// unit norm, singular values below 1e-9 of the largest counted as zero.
fn rank_of(w: &nalgebra::DMatrix<f64>, keep: Option<&[usize]>) -> usize {
    let all: Vec<usize> = (0..w.ncols()).collect();
    let keep = keep.unwrap_or(&all);
    let mut m = w.select_columns(keep);
    for mut c in m.column_iter_mut() {
        let norm = c.norm();
        if norm > 0.0 {
            c /= norm;
        }
    }
    let s = m.singular_values();
    let largest = s.max();
    s.iter().filter(|&&v| v > 1e-9 * largest).count()
}

#[test]
fn rank_deficient_data_names_the_parameters_not_excited() {
    let tmp = Scratch::new();
    // every equation: by default the still joints' would be dropped, leaving one
    let every = format!("{CONFIG}[processing]\nrest_velocity = 0\n");
    let e = run(&tmp, csv(&tmp, "still.csv", 600, 6, true, |s| s), &every).unwrap_err();
    match &e {
        // joints 2 to 6 do not move: named (robid-runtime's `StillJoints`)
        Error::Estimate(EstimateError::StillJoints {
            rank,
            columns,
            unexcited,
            joints,
        }) => {
            assert_eq!(joints, &[2, 3, 4, 5, 6], "{e}");
            // the same motion through the model, computed here: W's rank, and the named
            // parameters are exactly those in its dependencies
            let names = robid_runtime::model::base_parameter_names(&Ur5e);
            let w = still_observation();
            assert_eq!((*rank, *columns), (rank_of(&w, None), names.len()), "{e}");
            let named: Vec<usize> = unexcited
                .iter()
                .map(|u| names.iter().position(|n| n == u).expect("a base parameter"))
                .collect();
            // the columns outside the named ones are independent: every dependency is
            // among the named parameters
            let outside: Vec<usize> = (0..names.len()).filter(|i| !named.contains(i)).collect();
            assert_eq!(rank_of(&w, Some(&outside)), outside.len(), "{e}");
            // and each named one takes part in a dependency: dropping it keeps the rank
            for &u in &named {
                let without: Vec<usize> = (0..names.len()).filter(|&i| i != u).collect();
                assert_eq!(rank_of(&w, Some(&without)), *rank, "{}: {e}", names[u]);
            }
        }
        _ => panic!("expected rank deficiency, got {e}"),
    }
    println!("{e}");
}
