//! The `robid` binary end to end: forms scripts rely on (docs/command-line.md#stability) and
//! bad input that must give a located error, never a panic.

use crate::common;

use std::path::Path;

use common::{folder, robid, stderr, stdout};

#[test]
fn emit_prints_the_checked_in_code() {
    let o = robid(&["emit", "descriptions/ur5e.toml"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let checked_in =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("generated/ur5e.rs"))
            .unwrap();
    assert!(
        stdout(&o) == checked_in,
        "robid emit differs from generated/ur5e.rs"
    );
}

/// Every subcommand that reads a description reads TOML and URDF alike, and its `--help`
/// (short and long) says so in the same words; `excite`, `simulate` and `feasible` used to
/// say "(TOML)" alone.
#[test]
fn every_description_argument_says_toml_or_urdf() {
    let subcommands = [
        "model", "emit", "torques", "simulate", "excite", "identify", "feasible", "inspect",
        "friction", "payload",
    ];
    for sub in subcommands {
        for flag in ["-h", "--help"] {
            let o = robid(&[sub, flag]);
            assert!(o.status.success(), "{sub} {flag}: {}", stderr(&o));
            let help = stdout(&o);
            let arguments = help
                .split_once("Arguments:")
                .and_then(|(_, rest)| rest.split_once("Options:"))
                .map(|(arguments, _)| arguments)
                .unwrap_or_else(|| panic!("{sub} {flag}: no Arguments section in {help}"));
            assert!(
                (arguments.contains("<ROBOT>") || arguments.contains("[ROBOT]"))
                    && arguments
                        .contains("Robot description file (TOML, or URDF by its extension)"),
                "{sub} {flag}: {arguments}"
            );
            assert!(!arguments.contains("(TOML)"), "{sub} {flag}: {arguments}");
        }
    }
}

/// `--lang c` writes FILE.c and FILE.h (compiled and checked against the Rust models in
/// tests/tests/suite/emit_c.rs); its misuses are errors naming the flag.
#[test]
fn emit_c_writes_a_header_and_a_source() {
    let dir = folder();
    let source = dir.path().join("arm.c");
    let source = source.to_str().unwrap();
    let o = robid(&[
        "emit",
        "descriptions/tx40.toml",
        "--lang",
        "c",
        "--scalar",
        "float",
        "-o",
        source,
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let header = std::fs::read_to_string(dir.path().join("arm.h")).unwrap();
    assert!(header.contains("void tx40_mass_matrix(const float q[6], const float base["));
    let code = std::fs::read_to_string(source).unwrap();
    assert!(code.contains("#include \"arm.h\""), "{code}");
    for (args, says) in [
        (vec!["--lang", "c"], "give `-o FILE.c`"),
        (vec!["--lang", "c", "-o", "arm.txt"], "must end in `.c`"),
        (vec!["--scalar", "float"], "`--scalar` is for `--lang c`"),
    ] {
        let mut all = vec!["emit", "descriptions/tx40.toml"];
        all.extend(args);
        let o = robid(&all);
        assert_eq!(o.status.code(), Some(1), "{all:?}");
        assert!(stderr(&o).contains(says), "{all:?}: {}", stderr(&o));
    }
}

#[test]
fn model_json_has_the_documented_shape() {
    let o = robid(&["model", "descriptions/ur5e.toml", "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!(v["name"], "ur5e");
    assert_eq!(v["dof"], 6);
    assert_eq!(v["convention"], "modified");
    assert_eq!(v["standard_parameters"].as_array().unwrap().len(), 60);
    let base = v["base_parameters"].as_array().unwrap();
    assert_eq!(base.len(), 36);
    assert_eq!(base[0]["name"], "ZZR1");
    let terms = base[0]["terms"].as_array().unwrap();
    assert!(
        terms
            .iter()
            .any(|t| t["parameter"] == "ZZ1" && t["coefficient"] == 1.0)
    );
    assert!(
        v["unidentifiable"]
            .as_array()
            .unwrap()
            .iter()
            .any(|p| p == "XX1")
    );
    for program in [
        "inverse_dynamics",
        "base_regressor",
        "mass_matrix",
        "gravity",
    ] {
        assert!(
            v["operations"][program]["mul"].as_u64().unwrap() > 0,
            "{program}"
        );
    }
}

#[test]
fn a_malformed_description_names_file_line_and_column() {
    let dir = folder();
    let file = dir.path().join("bad.toml");
    std::fs::write(
        &file,
        "name = \"x\"\nconvention = \"sideways\"\n[[joints]]\nalpha = 0\n",
    )
    .unwrap();
    let o = robid(&["model", file.to_str().unwrap()]);
    assert!(!o.status.success());
    let e = stderr(&o);
    assert!(e.contains("bad.toml:2:14"), "{e}");
    assert!(e.contains("unknown DH convention `sideways`"), "{e}");
    assert!(!e.contains("panicked"), "{e}");
}

#[test]
fn a_missing_file_is_an_error_not_a_panic() {
    let o = robid(&["model", "descriptions/no_such_robot.toml"]);
    assert!(!o.status.success());
    let e = stderr(&o);
    assert!(
        e.contains("no_such_robot.toml") && e.contains("cannot read"),
        "{e}"
    );
    assert!(!e.contains("panicked"), "{e}");
}

/// Parameter files (`torques`, `simulate`, `excite`, `feasible --prior`): each mistake is
/// named with the file and the fix; a good file gives the torques of the reference robot.
#[test]
fn parameter_file_mistakes_are_named() {
    let dir = folder();
    let dir = dir.path();
    let states = dir.join("states.csv");
    std::fs::write(
        &states,
        "q1,q2,q3,q4,q5,q6,qd1,qd2,qd3,qd4,qd5,qd6,qdd1,qdd2,qdd3,qdd4,qdd5,qdd6\n\
         0,0.1,0.2,0.3,0.4,0.5,0,0,0,0,0,0,0,0,0,0,0,0\n",
    )
    .unwrap();
    let torques = |text: &str| {
        let params = dir.join("params.toml");
        std::fs::write(&params, text).unwrap();
        robid(&[
            "torques",
            "descriptions/ur5e.toml",
            "--parameters",
            params.to_str().unwrap(),
            "--states",
            states.to_str().unwrap(),
        ])
    };
    for (text, expected) in [
        (
            "[standard]\nM9 = 1.0\n",
            "`M9`, of link 9, but this robot has 6 links",
        ),
        (
            "[standard]\nM2 = \"heavy\"\n",
            "`M2` = \"heavy\" is not a finite number",
        ),
        (
            "[standard]\nM2 = 1.0\n[base]\nZZR1 = 1.0\n",
            "a second table [base], after [standard] on line 1",
        ),
        // the tables each with its use: [known] is not the robot's parameters (it was
        // offered beside them, then refused)
        (
            "M2 = 1.0\n",
            "holds one table: [standard] (standard parameters) or [base] (base parameters) for \
             the robot's parameters, or [known] for the parameters known beforehand",
        ),
        (
            "",
            "has no table; a parameter file holds one table: [standard]",
        ),
        // every missing name counted (it was told to drop the drive terms, the first
        // missing being `Fv1`, then, that fixed, "[base] has no `XXR2`")
        ("[base]\nZZR1 = 1.0\n", "of the model's"),
        ("[standard\n", "params.toml"),
    ] {
        let o = torques(text);
        assert!(!o.status.success(), "{text}");
        assert!(stderr(&o).contains(expected), "{text}: {}", stderr(&o));
    }
    let o = torques(&std::fs::read_to_string("parameters/ur5e.toml").unwrap());
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).starts_with("tau1,"), "{}", stdout(&o));
}

/// `robid excite` with each method from a given start: a CSV of t, q, qd, qdd at the
/// requested rate, at rest at the start at both ends, inside every limit of the description
/// (checked on the samples, not only on the printed margins); a start of the wrong length or
/// outside the limits is a named error. Small budgets: the designs' quality is tested in
/// `tests/tests/excitation_*.rs`.
#[test]
fn excite_writes_a_trajectory_at_rest_at_the_start_within_the_limits() {
    let dir = folder();
    let dir = dir.path();
    let description: toml::Value =
        toml::from_str(&std::fs::read_to_string("descriptions/ur5e.toml").unwrap()).unwrap();
    let limits: Vec<&toml::Value> = description["joints"]
        .as_array()
        .unwrap()
        .iter()
        .map(|j| &j["limits"])
        .collect();
    let number = |v: &toml::Value| v.as_float().unwrap();
    let start = [0.1, -1.2, 1.0, 0.0, 0.5, 0.0];
    let start_arg = "0.1,-1.2,1,0,0.5,0";
    for (method, budget) in [
        (
            "points",
            ["--restarts", "1", "--evaluations", "20", "--sweeps", "1"],
        ),
        (
            "fourier",
            ["--restarts", "1", "--evaluations", "200", "--seed", "3"],
        ),
    ] {
        let output = dir.join(format!("{method}.csv"));
        let mut args = vec![
            "excite",
            "descriptions/ur5e.toml",
            "--method",
            method,
            "--start",
            start_arg,
            "--duration",
            "10",
            "--rate",
            "200",
            "-o",
            output.to_str().unwrap(),
        ];
        args.extend_from_slice(&budget);
        let o = robid(&args);
        assert!(o.status.success(), "{method}: {}", stderr(&o));
        let report = stdout(&o);
        let cond: f64 = report
            .split("condition number ")
            .nth(1)
            .and_then(|r| r.split_whitespace().next())
            .and_then(|v| v.parse().ok())
            .unwrap_or_else(|| panic!("{method}: no condition number in {report}"));
        assert!(cond.is_finite() && cond >= 1.0, "{method}: cond {cond}");
        let text = std::fs::read_to_string(&output).unwrap();
        let mut lines = text.lines();
        let header: Vec<&str> = lines.next().unwrap().split(',').collect();
        assert_eq!(header.len(), 19, "{method}: {header:?}");
        assert_eq!(
            (header[0], header[1], header[7], header[13]),
            ("t", "q1", "qd1", "qdd1")
        );
        let rows: Vec<Vec<f64>> = lines
            .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
            .collect();
        assert_eq!(rows.len(), 10 * 200 + 1, "{method}");
        assert!((rows.last().unwrap()[0] - 10.0).abs() < 1e-9, "{method}");
        for end in [&rows[0], rows.last().unwrap()] {
            for j in 0..6 {
                assert!(
                    (end[1 + j] - start[j]).abs() < 1e-9,
                    "{method}: q{} {end:?}",
                    j + 1
                );
                assert!(
                    end[7 + j].abs() < 1e-9 && end[13 + j].abs() < 1e-9,
                    "{method}: {end:?}"
                );
            }
        }
        for row in &rows {
            for (j, l) in limits.iter().enumerate() {
                let p = l["position"].as_array().unwrap();
                let q = row[1 + j];
                assert!(
                    number(&p[0]) <= q && q <= number(&p[1]),
                    "{method}: q{} = {q}",
                    j + 1
                );
                assert!(
                    row[7 + j].abs() <= number(&l["velocity"]),
                    "{method}: qd{}",
                    j + 1
                );
                assert!(
                    row[13 + j].abs() <= number(&l["acceleration"]),
                    "{method}: qdd{}",
                    j + 1
                );
            }
        }
    }
    for (start, expected) in [
        (
            "0.1,-1.2,1",
            "--start has 3 values but descriptions/ur5e.toml has 6 joints",
        ),
        ("0.1,-1.2,1,0,0.5,9", "9 is outside the limits"),
    ] {
        let o = robid(&[
            "excite",
            "descriptions/ur5e.toml",
            "--start",
            start,
            "-o",
            dir.join("bad.csv").to_str().unwrap(),
        ]);
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(1), "{start}: {e}");
        assert!(e.contains(expected), "{start}: {e}");
    }
    // A torque limit the tiny budget cannot meet (joints 1-3 at 40 N m): a named breach,
    // the CSV kept for inspection.
    let tight = dir.join("ur5e_tight.toml");
    std::fs::write(
        &tight,
        std::fs::read_to_string("descriptions/ur5e.toml")
            .unwrap()
            .replace("torque = 150.0", "torque = 40.0"),
    )
    .unwrap();
    let output = dir.join("tight.csv");
    let o = robid(&[
        "excite",
        tight.to_str().unwrap(),
        "--method",
        "points",
        "--start",
        "0,-1.5,0,-1.5,0,0",
        "--restarts",
        "1",
        "--evaluations",
        "20",
        "--sweeps",
        "1",
        "--duration",
        "10",
        "--parameters",
        "parameters/ur5e.toml",
        "-o",
        output.to_str().unwrap(),
    ]);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(
        e.contains("exceeds joint 2 torque by") && e.contains("--sweeps"),
        "{e}"
    );
    // (a fresh folder: the file is this run's, not one left by an earlier run)
    assert!(output.exists());
}

/// `--pieces` writes Milella's pieces as a config fragment that the identification config
/// reads: one window per interior point, each around its point, lower condition number
/// than the minimum widths (said in the header).
#[test]
fn excite_points_writes_pieces_for_the_config() {
    let dir = folder();
    let (output, pieces) = (dir.path().join("p.csv"), dir.path().join("pieces.toml"));
    let o = robid(&[
        "excite",
        "descriptions/ur5e.toml",
        "--method",
        "points",
        "--intervals",
        "6",
        "--duration",
        "12",
        "--rate",
        "100",
        "--restarts",
        "1",
        "--sweeps",
        "1",
        "--evaluations",
        "20",
        "--pieces",
        pieces.to_str().unwrap(),
        "-o",
        output.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = std::fs::read_to_string(&pieces).unwrap();
    let v: toml::Value = toml::from_str(&text).unwrap();
    let windows = v["processing"]["pieces"].as_array().unwrap();
    assert_eq!(windows.len(), 5, "{text}");
    for (i, w) in windows.iter().enumerate() {
        let (a, b) = (w[0].as_float().unwrap(), w[1].as_float().unwrap());
        let point = 2.0 * (i + 1) as f64;
        assert!(
            a < point && point < b && a >= point - 1.0 && b <= point + 1.0,
            "{text}"
        );
    }
    let config = format!("[estimation]\nmethod = \"ols\"\n{text}");
    let config: robid_runtime::data::Config =
        robid_runtime::data::Config::from_toml_str(&config, "c.toml".as_ref()).unwrap();
    assert_eq!(config.processing.pieces.unwrap().len(), 5);
}

/// `robid bench --json` gives every program's time and its multiple of the baseline timed
/// in turn with it, consistent with each other (a ratio is a time over a baseline near the
/// run's median one), and the same names in both, each time also flat as `<program>_ns`;
/// an unknown robot is refused.
#[test]
fn bench_json_has_each_program_with_its_ratio() {
    let o = robid(&["bench", "--robot", "stanford", "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(stdout(&o).trim()).unwrap();
    let (programs, ratios) = (&v["programs"], &v["ratios"]);
    let base = v["baseline_trig_ns"].as_f64().unwrap();
    assert!(base > 0.0, "{v}");
    let names: Vec<&String> = programs.as_object().unwrap().keys().collect();
    assert_eq!(names.len(), 7, "{v}");
    assert_eq!(
        names,
        ratios.as_object().unwrap().keys().collect::<Vec<_>>(),
        "{v}"
    );
    for name in names {
        let (ns, ratio) = (
            programs[name].as_f64().unwrap(),
            ratios[name].as_f64().unwrap(),
        );
        assert!(ns > 0.0 && ratio > 0.0, "{name}: {v}");
        // the flat form scripts read: `inverse_dynamics_ns`, ...
        assert_eq!(v[format!("{name}_ns")].as_f64(), Some(ns), "{name}: {v}");
        // medians of different batches, so not equal: under a loaded machine they were 4
        // times apart; this catches a ratio or a time in other units (a factor of 1e3)
        let implied = ns / ratio;
        assert!(
            implied / base < 50.0 && base / implied < 50.0,
            "{name}: {v}"
        );
    }
    assert!(v["batched_trig_ratio"].as_f64().unwrap() > 0.0, "{v}");
    let o = robid(&["bench", "--robot", "nope"]);
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains("no compiled robot `nope`"),
        "{}",
        stderr(&o)
    );
}

/// The model table's columns line up whatever their values' lengths: a URDF's fitted
/// lengths print in full (SO-101's `a3 = 0.116000021120688`) and pushed the columns after
/// them out of line; each column now starts where its heading does, in every row.
#[test]
fn model_table_columns_line_up_with_long_values() {
    let o = robid(&["model", "../data/example_robot_data/so101/so101.urdf"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    let mut lines = text
        .lines()
        .skip_while(|l| !l.trim_start().starts_with("j  type"));
    let header = lines.next().expect("the DH table");
    let rows: Vec<&str> = lines.take_while(|l| !l.is_empty()).collect();
    assert_eq!(rows.len(), 6, "{text}");
    assert!(
        rows.iter().any(|r| r.contains("0.116000021120688")),
        "{text}"
    );
    for heading in [" alpha", " a ", " d ", " theta"] {
        let at = header.find(heading).expect(heading) + 1;
        for row in &rows {
            let (before, after) = row.split_at(at);
            assert!(
                before.ends_with(' ') && !after.starts_with(' '),
                "column `{}` at {at}:\n{header}\n{row}",
                heading.trim()
            );
        }
    }
}

/// The margins `excite` prints: the joints' rows after the header, as numbers.
fn printed_margins(o: &std::process::Output) -> Vec<Vec<f64>> {
    let out = stdout(o);
    assert!(o.status.success(), "{out}{}", stderr(o));
    out.lines()
        .skip_while(|l| !l.starts_with("joint  pos_low"))
        .skip(1)
        .map(|l| {
            l.split_whitespace()
                .skip(1)
                .take(4)
                .map(|x| x.parse().unwrap())
                .collect()
        })
        .collect()
}

/// The printed margins are never larger than the true ones, between the samples too: at
/// a coarse --rate they were taken at the samples alone (Fourier at 1.2 Hz printed a
/// velocity margin 1.2 % above the one at 100 Hz, points at 2 Hz one 10 % above it). The
/// same design (same seed) is sampled coarse and fine.
#[test]
fn excite_margins_hold_between_coarse_samples() {
    let dir = folder();
    let out = dir.path().join("t.csv");
    let run = |method: &str, rate: &str| {
        printed_margins(&robid(&[
            "excite",
            "descriptions/ur5e.toml",
            "--method",
            method,
            "--rate",
            rate,
            "--evaluations",
            "100",
            "--restarts",
            "1",
            "-o",
            out.to_str().unwrap(),
        ]))
    };
    for (method, coarse) in [("fourier", "1.2"), ("points", "2")] {
        let (c, f) = (run(method, coarse), run(method, "500"));
        assert_eq!(c.len(), 6);
        for (cj, fj) in c.iter().zip(&f) {
            for (x, y) in cj.iter().zip(fj) {
                // four significant digits printed
                assert!(*x <= y + 2e-4 * y.abs(), "{method}: {c:?} above {f:?}");
            }
        }
    }
}
