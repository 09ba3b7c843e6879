//! `robid identify --static` end to end (docs/identification.md#static-samples): gravity
//! samples of the LWR IV+ in the frames of Gaz et al. 2016, made by the model's gravity
//! program from known base parameters, give back the twelve gravity coefficients.

use crate::common;

use std::path::{Path, PathBuf};

use common::{fails_with, folder, robid, stderr, stdout};
use robid_runtime::Model;
use robid_runtime::feasible::GravityCoefficients;
use robid_runtime::rng::Rng;

const LWR: &str = "tests/fixtures/lwr4_gaz2016.toml";

/// Writes `poses` gravity samples for base parameters `beta`; returns the path.
fn samples(dir: &Path, model: &dyn Model, beta: &[f64], poses: usize) -> PathBuf {
    let n = model.dof();
    let names = |x: &'static str| (1..=n).map(move |i| format!("{x}{i}"));
    let mut text = names("q").chain(names("g")).collect::<Vec<_>>().join(",") + "\n";
    let mut rng = Rng::new(2016);
    for _ in 0..poses {
        let q: Vec<f64> = (0..n).map(|_| rng.uniform(-2.9, 2.9)).collect();
        let mut g = vec![0.0; n];
        model.gravity_into(&q, beta, &mut g).unwrap();
        let row: Vec<String> = q.iter().chain(&g).map(|v| format!("{v:e}")).collect();
        text += &(row.join(",") + "\n");
    }
    let path = dir.join("gravity.csv");
    std::fs::write(&path, text).unwrap();
    path
}

/// What `robid identify ROBOT --static` made of `poses` gravity samples of random base
/// parameters (seeded by `seed`): the model, the parameters, stdout, stderr and the JSON.
struct Static {
    model: robots::interpreted::Interpreted,
    beta: Vec<f64>,
    out: String,
    err: String,
    json: serde_json::Value,
}

fn identify_static(robot: &str, seed: u64, poses: usize) -> Static {
    let dir = folder();
    let description = robid_symbolic::Robot::from_file(Path::new(robot)).unwrap();
    let model = robots::interpreted::Interpreted::new(&description).unwrap();
    let mut rng = Rng::new(seed);
    let beta: Vec<f64> = (0..model.base_parameter_count())
        .map(|_| rng.uniform(-1.0, 1.0))
        .collect();
    let csv = samples(dir.path(), &model, &beta, poses);
    let json = dir.path().join("static.json");
    let o = robid(&[
        "identify",
        robot,
        "--static",
        csv.to_str().unwrap(),
        "--json",
        json.to_str().unwrap(),
    ]);
    let (out, err) = (stdout(&o), stderr(&o));
    assert!(o.status.success(), "{err}");
    let json = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    Static {
        model,
        beta,
        out,
        err,
        json,
    }
}

#[test]
fn gaz_identify_static_gravity_samples_give_the_gravity_coefficients() {
    let Static {
        model,
        beta,
        out,
        err,
        json: v,
    } = identify_static(LWR, 7, 30);
    let nb = model.base_parameter_count();
    assert!(out.starts_with("gravity samples: 210 equations"), "{out}");
    assert!(
        err.contains("gravity samples determine 12 of the 43 base parameters"),
        "{err}"
    );
    let truth = GravityCoefficients::of_model(&model).unwrap();
    let expected = truth.values(&beta).unwrap();
    let parameters = v["parameters"].as_array().unwrap();
    assert_eq!(parameters.len(), 12);
    assert_eq!(v["undetermined"].as_array().unwrap().len(), 31);
    for (p, (name, x)) in parameters.iter().zip(truth.names.iter().zip(&expected)) {
        assert_eq!(p["name"].as_str().unwrap(), name);
        let value = p["value"].as_f64().unwrap();
        // exact samples written to full precision: rounding only (the library test
        // measured 6.0e-16 relative)
        assert!((value - x).abs() < 1e-10, "{name}: {value} against {x}");
        // the combination's terms give its value from the base parameters, led by its name
        let base = |n: &str| (0..nb).find(|&b| model.base_parameter_name(b) == Some(n));
        let terms = p["terms"].as_array().unwrap();
        assert_eq!(terms[0]["parameter"].as_str(), Some(name.as_str()));
        let sum: f64 = terms
            .iter()
            .map(|t| {
                let b = base(t["parameter"].as_str().unwrap()).unwrap();
                t["coefficient"].as_f64().unwrap() * beta[b]
            })
            .sum();
        assert!((sum - x).abs() < 1e-9, "{name}: {sum} against {x}");
        let expression = p["expression"].as_str().unwrap();
        assert!(expression.starts_with(name.as_str()), "{expression}");
        assert!(out.contains(expression), "{expression} in {out}");
    }
}

#[test]
fn gaz_identify_static_refuses_bad_columns_and_other_data() {
    let dir = folder();
    let bad = dir.path().join("bad.csv");
    std::fs::write(&bad, "q1,q2,q3,q4,q5,q6,q7,g1,g2\n0,0,0,0,0,0,0,1,2\n").unwrap();
    let o = robid(&["identify", LWR, "--static", bad.to_str().unwrap()]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("no column `g3`"), "{}", stderr(&o));
    // the values are range-checked (1e150 went into the estimate and the JSON), and an
    // empty or binary file is told as such (was "holds neither gravity columns ...")
    let q = "q1,q2,q3,q4,q5,q6,q7";
    for (text, expected) in [
        (
            format!("{q},g1,g2,g3,g4,g5,g6,g7\n0,0,0,0,0,0,0,1,2,3,4,5,6,1e150\n"),
            "bad.csv:2: column `g7` is 1e150, outside the accepted range |torque| <= 1e7",
        ),
        (
            format!("{q},g1,g2,g3,g4,g5,g6,g7\n0,0,0,0,0,0,2e6,1,2,3,4,5,6,7\n"),
            "bad.csv:2: column `q7` is 2e6, outside the accepted range |position|",
        ),
        (String::new(), "the file is empty"),
        ("\u{1}\u{2}\0PK\n\0\0\n".into(), "is this a CSV file?"),
    ] {
        std::fs::write(&bad, text).unwrap();
        let o = robid(&["identify", LWR, "--static", bad.to_str().unwrap()]);
        fails_with(&o, &[expected]);
    }
    let o = robid(&[
        "identify",
        LWR,
        "--static",
        bad.to_str().unwrap(),
        "--data",
        "x.csv",
    ]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("cannot be used with"), "{}", stderr(&o));
}

/// A combination that absorbs other base parameters is written with them, in the table and
/// the JSON: the Stanford arm's gravity determines `MY2 - MZ3` (it was given as `MY2` alone,
/// whose value, 1.0245 for the reference parameters, is not MY2's).
#[test]
fn a_static_combination_is_written_with_the_parameters_it_absorbs() {
    let Static { out, json: v, .. } = identify_static("descriptions/stanford.toml", 3, 10);
    let row = out
        .lines()
        .find(|l| l.starts_with("MY2 "))
        .unwrap_or_default();
    assert!(row.ends_with("  MY2 - MZ3"), "{out}");
    let my2 = v["parameters"]
        .as_array()
        .unwrap()
        .iter()
        .find(|p| p["name"] == "MY2")
        .unwrap();
    assert_eq!(my2["expression"], "MY2 - MZ3");
    let terms = my2["terms"].as_array().unwrap();
    assert_eq!(terms.len(), 2);
    assert_eq!(terms[1]["parameter"], "MZ3");
    assert!((terms[1]["coefficient"].as_f64().unwrap() + 1.0).abs() < 1e-9);
}

/// Gravity samples whose torques are 0 at every pose (a logger that wrote nothing) fitted
/// every combination to 0 +- 0 with "inf" for its relative deviation and no word; a column
/// of one nonzero value is a dead channel too. Samples of real parameters are not told.
#[test]
fn a_static_file_of_dead_columns_is_warned_about() {
    let dir = folder();
    let description = robid_symbolic::Robot::from_file(Path::new(LWR)).unwrap();
    let model = robots::interpreted::Interpreted::new(&description).unwrap();
    let zeros = vec![0.0; model.base_parameter_count()];
    let csv = samples(dir.path(), &model, &zeros, 30);
    let run = |csv: &Path| {
        let o = robid(&["identify", LWR, "--static", csv.to_str().unwrap()]);
        assert!(o.status.success(), "{}", stderr(&o));
        (stdout(&o), stderr(&o))
    };
    let (out, err) = run(&csv);
    assert!(
        err.contains("is 0 at every pose: the file holds no gravity torques"),
        "{err}"
    );
    assert!(!out.contains("inf"), "{out}");
    // g3 at 1.5 in samples of real parameters
    let mut rng = Rng::new(3);
    let beta: Vec<f64> = zeros.iter().map(|_| rng.uniform(-1.0, 1.0)).collect();
    let csv = samples(dir.path(), &model, &beta, 30);
    let (_, err) = run(&csv);
    assert!(
        !err.contains("dead channel") && !err.contains("holds no"),
        "{err}"
    );
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap();
    let g3 = header.split(',').position(|c| c == "g3").unwrap();
    let constant: String = lines
        .map(|l| {
            let mut cells: Vec<&str> = l.split(',').collect();
            cells[g3] = "1.5";
            cells.join(",") + "\n"
        })
        .collect();
    std::fs::write(&csv, format!("{header}\n{constant}")).unwrap();
    let (_, err) = run(&csv);
    assert!(
        err.contains("column `g3` is 1.5 at every pose while the model's gravity torque there changes with the pose: a dead channel"),
        "{err}"
    );
}
