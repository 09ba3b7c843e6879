//! `robid feasible` end to end (docs/command-line.md#robid-feasible) on the TX40's
//! identification JSON
//! (`tests/fixtures/tx40_identified.json`, written by `robid identify
//! configs/tx40_robot.toml --config configs/tx40.toml --data ... --json`, 61 parameters
//! including the coupled-wrist extra columns `Iam6 fvm6 fsm6`) with loose bounds
//! (`tests/fixtures/tx40_bounds.toml`).

use crate::common;

use std::path::{Path, PathBuf};

use common::{asset, fails_with, folder, robid, stderr, write};

/// Arms of the repository's URDF examples, with their makers' inertials.
const UR5_URDF: &str = "../data/example_robot_data/ur5/ur5_robot.urdf";
const KINOVA_URDF: &str = "../data/example_robot_data/kinova/kinova.urdf";
const XARM7_URDF: &str = "../data/example_robot_data/xarm7/xarm7.urdf";

/// A path in a test's fresh output folder.
fn out(dir: &tempfile::TempDir, name: &str) -> PathBuf {
    dir.path().join(name)
}

/// Runs `robid feasible` on the fixture; returns chi^2 from the summary line.
fn feasible(method: &str, output: &Path) -> f64 {
    feasible_with(method, output, &[])
}

/// `feasible` with extra arguments.
fn feasible_with(method: &str, output: &Path, extra: &[&str]) -> f64 {
    feasible_summary(method, output, extra).0
}

/// `feasible` with extra arguments: chi^2 and max |z| (the largest misfit of a base
/// parameter in units of its standard deviation) of its summary.
fn feasible_summary(method: &str, output: &Path, extra: &[&str]) -> (f64, f64) {
    let mut args = vec![
        "feasible",
        "configs/tx40_robot.toml",
        "--identified",
        "tests/fixtures/tx40_identified.json",
        "--bounds",
        "tests/fixtures/tx40_bounds.toml",
        "--method",
        method,
        "-o",
        output.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let o = robid(&args);
    let err = stderr(&o);
    assert!(o.status.success(), "{err}");
    let after = |label: &str| -> f64 {
        err.split(label)
            .nth(1)
            .and_then(|r| r.split(',').next())
            .and_then(|v| v.parse().ok())
            .unwrap_or_else(|| panic!("no {label}in the summary: {err}"))
    };
    eprintln!("{err}");
    // the fixture has drive terms and extra columns, which a URDF cannot hold: said
    if output.extension().is_some_and(|e| e == "urdf") {
        for part in [
            "holds the links' inertials only, not 27 identified values (Ia1 Fv1 Fc1 Fo1 ",
            " Iam6 fvm6 fsm6): a URDF has no place for drive terms or extra columns",
        ] {
            assert!(err.contains(part), "{part}: {err}");
        }
    }
    (after("chi^2 "), after("max |z| "))
}

/// The TOML output: every standard parameter in `[standard]` and the extra columns in
/// `[extra]`, six links, each with a positive mass and a positive definite pseudo-inertia,
/// total mass in its range; `robid torques` reads it as the robot's parameters (the extra
/// columns in `[standard]` made it refuse the file, advising to rename them).
fn check_toml(path: &Path) {
    let text = std::fs::read_to_string(path).unwrap();
    let v: toml::Value = toml::from_str(&text).expect("the output is TOML");
    let standard = v["standard"].as_table().unwrap();
    for name in ["XX1", "ZZ6", "M6", "Ia1", "Fv6", "Fo3"] {
        assert!(standard.contains_key(name), "{name} missing");
    }
    assert_eq!(standard.len(), 6 * 14);
    let extra = v["extra"].as_table().unwrap();
    assert_eq!(
        extra.keys().collect::<Vec<_>>(),
        ["Iam6", "fsm6", "fvm6"],
        "{text}"
    );
    let states = path.with_extension("states.csv");
    let header: Vec<String> = ["q", "qd", "qdd"]
        .iter()
        .flat_map(|p| (1..=6).map(move |j| format!("{p}{j}")))
        .collect();
    std::fs::write(
        &states,
        header.join(",") + "\n" + &["0.1"; 18].join(",") + "\n",
    )
    .unwrap();
    let o = robid(&[
        "torques",
        "configs/tx40_robot.toml",
        "--parameters",
        path.to_str().unwrap(),
        "--states",
        states.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let links = v["links"].as_array().unwrap();
    assert_eq!(links.len(), 6);
    let mut total = 0.0;
    for l in links {
        let m = l["mass"].as_float().unwrap();
        assert!(m > 0.0, "{l:?}");
        assert!(
            l["pseudo_inertia_min_eigenvalue"].as_float().unwrap() > 0.0,
            "{l:?}"
        );
        total += m;
    }
    assert!(
        (13.5 - 1e-6..=27.0 + 1e-6).contains(&total),
        "total {total}"
    );
}

/// The URDF output: six `<inertial>` elements with positive masses.
fn check_urdf(path: &Path) {
    let text = std::fs::read_to_string(path).unwrap();
    assert_eq!(text.matches("<inertial>").count(), 6);
    assert_eq!(text.matches("</inertial>").count(), 6);
    let masses: Vec<f64> = text
        .split("<mass value=\"")
        .skip(1)
        .map(|r| r.split('"').next().unwrap().parse().unwrap())
        .collect();
    assert_eq!(masses.len(), 6);
    assert!(masses.iter().all(|m| *m > 0.0), "{masses:?}");
}

/// Gaz et al.'s search writes consistent links (TOML) that fit the identified parameters.
/// The default method is the interior-point fit. With the data alone (`--prior-weight 0`)
/// it reaches the convex fit's global optimum, so it fits at least as well as the stochastic
/// search (measured chi^2 13.68 against anneal's 13.91 and 14.08 in two runs: the parallel
/// search's path varies), as the Cholesky fit does; the default prior of solid
/// links settles what the data leave free at a small cost in fit (measured 15.39). The
/// fits with the default prior are written as URDF (the output's extension chooses).
/// One test, so that the search (the dear part) runs once.
#[test]
fn feasible_methods_write_consistent_links_and_the_convex_fits_beat_anneal() {
    let dir = folder();
    let anneal_path = out(&dir, "anneal.toml");
    let anneal = feasible("anneal", &anneal_path);
    // measured 13.91 and 14.08; bound 2x
    assert!(anneal <= 28.0, "chi^2 {anneal}");
    check_toml(&anneal_path);
    let path = out(&dir, "default.toml");
    let o = robid(&[
        "feasible",
        "configs/tx40_robot.toml",
        "--identified",
        "tests/fixtures/tx40_identified.json",
        "--bounds",
        "tests/fixtures/tx40_bounds.toml",
        "-o",
        path.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).starts_with("interior-point: chi^2 "),
        "{}",
        stderr(&o)
    );
    check_toml(&path);
    for method in ["cholesky", "interior-point"] {
        let data_alone = feasible_with(
            method,
            &out(&dir, &format!("{method}_data_alone.toml")),
            &["--prior-weight", "0"],
        );
        let urdf = out(&dir, &format!("{method}_default.urdf"));
        let with_prior = feasible(method, &urdf);
        check_urdf(&urdf);
        assert!(
            data_alone <= anneal * (1.0 + 1e-6),
            "{method} {data_alone}, anneal {anneal}"
        );
        // the default prior's price in fit: measured x1.125; bound 2x of the excess
        assert!(
            with_prior <= 1.25 * data_alone,
            "{method}: with the default prior {with_prior}, data alone {data_alone}"
        );
    }
}

/// With `--prior-weight 0` no prior pulls what the data leave free, so neither the summary
/// nor the written file says those values are the prior's: they said "values from the
/// prior ... or the nearest to them" of a link-1 mass left at its lower bound of 0.05 kg.
/// At the default weight the values are the prior's, and the message says so.
#[test]
fn feasible_at_prior_weight_zero_does_not_call_the_free_values_the_priors() {
    let dir = folder();
    let run = |extra: &[&str], name: &str| {
        let path = out(&dir, name);
        let mut args = vec![
            "feasible",
            "configs/tx40_robot.toml",
            "--identified",
            "tests/fixtures/tx40_identified.json",
            "--bounds",
            "tests/fixtures/tx40_bounds.toml",
            "-o",
            path.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let o = robid(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        (stderr(&o), std::fs::read_to_string(&path).unwrap())
    };
    let unseen = "XX1 XY1 XZ1 YY1 YZ1 MX1 MY1 MZ1 M1 MZ2 M2";
    let (err, text) = run(&["--prior-weight", "0"], "data_alone.toml");
    for message in [&err, &text] {
        assert!(!message.contains("from the prior"), "{message}");
        assert!(
            message.contains(&format!(
                "values that no prior pulls (its weight is 0), so wherever the solver stopped \
                 within the physical constraints and bounds, not the prior's (a prior weight \
                 above 0 or --bounds settle them): {unseen}"
            )),
            "{message}"
        );
    }
    let (err, text) = run(&[], "default.toml");
    for message in [&err, &text] {
        assert!(
            message.contains(&format!(
                "values from the prior (the default prior where none is given), or the \
                 nearest to them that the physical constraints and bounds allow: {unseen}"
            )),
            "{message}"
        );
        assert!(!message.contains("no prior pulls"), "{message}");
    }
}

#[test]
fn feasible_rejects_an_unknown_method_and_a_foreign_result() {
    let dir = folder();
    let path = out(&dir, "bad.toml");
    let path = path.to_str().unwrap();
    let o = robid(&[
        "feasible",
        "configs/tx40_robot.toml",
        "--identified",
        "tests/fixtures/tx40_identified.json",
        "--method",
        "genetic",
        "-o",
        path,
    ]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("--method genetic"), "{}", stderr(&o));
    // The TX40 result against the UR5e description: base parameters missing.
    let o = robid(&[
        "feasible",
        "descriptions/ur5e.toml",
        "--identified",
        "tests/fixtures/tx40_identified.json",
        "--method",
        "anneal",
        "-o",
        path,
    ]);
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains("identify with the same robot description"),
        "{}",
        stderr(&o)
    );
}

/// Bounds that no consistent link meets (link 1's inertia about its centre of mass with
/// xx and yy at most 0.001 but zz at least 0.01, against zz <= xx + yy): each method ends
/// outside a bound it imposes, and that is an error with nothing written, naming the bounds
/// (the default method wrote its result and exited 0 before, its violations a note).
#[test]
fn feasible_fails_when_the_fit_ends_outside_the_bounds_it_imposes() {
    let dir = folder();
    let bounds = write(
        dir.path(),
        "b.toml",
        "[links.1]\ninertia_tensor = { xx = [0.0, 0.001], yy = [0.0, 0.001], zz = [0.01, 1.0] }\n",
    );
    for method in ["interior-point", "cholesky"] {
        let path = out(&dir, "f.toml");
        let o = bounded("tx40", &bounds, method, &path);
        fails_with(
            &o,
            &[
                &format!("the {method} fit ended outside bounds it imposes: link 1: inertia"),
                "outside [0, 0.001]",
                "nothing was written",
                // the fit is within 3 std of the identified values (max |z| 2.3): the bounds
                // are to blame, not the data ("the data push hard" was said whatever the fit)
                "so the data do not push against these bounds: they contradict each other",
                "check the bounds file",
            ],
        );
        assert!(!path.exists(), "{method}");
    }
}

/// `robid feasible` on the fixture robot `robot` (`tx40`: the TX40's description and
/// identification; `two_link`: the two-link arm's) with `bounds`, `method`, to `output`.
fn bounded(robot: &str, bounds: &Path, method: &str, output: &Path) -> std::process::Output {
    let (description, identified) = match robot {
        "tx40" => (
            "configs/tx40_robot.toml",
            "tests/fixtures/tx40_identified.json",
        ),
        _ => (
            "tests/fixtures/two_link.toml",
            "tests/fixtures/two_link_identified.json",
        ),
    };
    robid(&[
        "feasible",
        description,
        "--identified",
        identified,
        "--bounds",
        bounds.to_str().unwrap(),
        "--method",
        method,
        "-o",
        output.to_str().unwrap(),
    ])
}

/// The identification result of fixture `name` (`tests/fixtures/NAME`), to be edited.
fn fixture_json(name: &str) -> serde_json::Value {
    let text = std::fs::read_to_string(asset(&format!("tests/fixtures/{name}"))).unwrap();
    serde_json::from_str(&text).unwrap()
}

/// `robid feasible` on the two-link arm (`tests/fixtures/two_link.toml`) with the
/// identification `identified` (default: its fixture), written to `output`, with `extra`
/// arguments; succeeds, and returns standard error.
fn two_link(identified: Option<&Path>, output: &Path, extra: &[&str]) -> String {
    let fixture = Path::new("tests/fixtures/two_link_identified.json");
    let mut args = vec![
        "feasible",
        "tests/fixtures/two_link.toml",
        "--identified",
        identified.unwrap_or(fixture).to_str().unwrap(),
        "-o",
        output.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let o = robid(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    stderr(&o)
}

/// Bounds the data push far against (a two-link arm identified near 3 kg, bounded to a
/// total of at least 80 kg with links of at most 50 kg): the interior-point path stalled
/// outside them when they were penalties (it wrote link 1 at 59 kg and exited 0; then the
/// default took the Cholesky method's path). The masses and the total mass are in its
/// barrier now: it meets them itself, by the default and by name, nothing said about
/// another path; the file holds masses within the bounds.
#[test]
fn feasible_default_meets_bounds_the_data_push_far_against() {
    let dir = folder();
    let bounds = write(dir.path(), "b.toml", "total_mass = [80.0, 200.0]\n");
    for method in [&[][..], &["--method", "interior-point"]] {
        let path = out(&dir, "f.toml");
        let mut args = vec!["--bounds", bounds.to_str().unwrap()];
        args.extend_from_slice(method);
        let err = two_link(None, &path, &args);
        let m = masses(&path);
        let tolerance = |bound: f64| 1e-6 * (1.0 + bound);
        assert!(m.iter().all(|&m| m <= 50.0 + tolerance(50.0)), "{m:?}");
        let total: f64 = m.iter().sum();
        assert!(total >= 80.0 - tolerance(80.0), "{total}: {err}");
        assert!(
            !err.contains("bounds not met") && !err.contains("ended outside"),
            "{err}"
        );
    }
}

/// An extra column named like a drive term the description does not have (`Fv1` of an
/// arm without drive terms, as the LWR4 config's friction columns are) stays an extra
/// column: written under `[extra]`, not as the arm's friction in `[standard]`, where a
/// negative value made the file unreadable to every other subcommand.
#[test]
fn feasible_keeps_an_extra_column_named_like_a_drive_term_extra() {
    let dir = folder();
    let mut json = fixture_json("two_link_identified.json");
    json["parameters"]
        .as_array_mut()
        .unwrap()
        .push(serde_json::json!({"name": "Fv1", "expression": "", "value": -1e-3, "std": 1e-4}));
    let identified = write(dir.path(), "id.json", &json.to_string());
    let path = out(&dir, "f.toml");
    two_link(Some(&identified), &path, &[]);
    let v: toml::Value = toml::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    assert!(v["standard"].get("Fv1").is_none(), "{v}");
    // the free term takes its identified value (to the solver's tolerance)
    let fv1 = v["extra"]["Fv1"].as_float().unwrap();
    assert!((fv1 + 1e-3).abs() < 1e-9, "{fv1}");
}

/// `robid feasible` on the two-link arm with the fixture's first base parameter (`ZZR1`,
/// `ZZ1 + YY2 + 0.16*M2`) written as `expression`, to `output`.
fn two_link_with_expression(
    dir: &tempfile::TempDir,
    expression: &str,
    output: &Path,
) -> std::process::Output {
    let mut json = fixture_json("two_link_identified.json");
    assert_eq!(json["parameters"][0]["name"], "ZZR1");
    json["parameters"][0]["expression"] = expression.into();
    let identified = write(dir.path(), "id.json", &json.to_string());
    robid(&[
        "feasible",
        "tests/fixtures/two_link.toml",
        "--identified",
        identified.to_str().unwrap(),
        "-o",
        output.to_str().unwrap(),
    ])
}

/// A base parameter's expression that is no expression, names something that is no
/// standard parameter, or is not linear in them, is refused naming the file, the entry,
/// the expression and what is wrong (it passed unread: the check compared only what its
/// own reader of sums could read); nothing is written.
#[test]
fn feasible_refuses_an_identified_expression_it_cannot_read() {
    let dir = folder();
    let path = out(&dir, "f.toml");
    for (expression, problem) in [
        (
            "#### garbage ###",
            "is not an expression robid reads (at character 0: expected a number, a name or `(`)",
        ),
        (
            "XX1 + 0.5*M6 + )",
            "is not an expression robid reads (at character 15: expected a number, a name",
        ),
        (
            "null*M2",
            "names `null`, neither a standard parameter nor a geometric symbol",
        ),
        (
            "ZZ1 + YY2*M2",
            "is not linear in the standard parameters: its coefficient of `YY2` is `M2`",
        ),
    ] {
        let o = two_link_with_expression(&dir, expression, &path);
        fails_with(
            &o,
            &[
                &format!("id.json: parameters[0] `ZZR1`: the expression `{expression}` {problem}"),
                "the file was not written by robid identify for this description",
                "two_link.toml",
                "or identify again",
            ],
        );
        assert!(!path.exists(), "{expression}");
    }
}

/// An exact coefficient `n/d`, as robid writes one that is no short decimal, is read: the
/// description's own (`4/25` for 0.16) is taken, another (`1/5`) refused as a result of
/// another geometry (neither was compared before: the reader of sums took no `/`).
#[test]
fn feasible_reads_an_exact_coefficient_of_an_identified_expression() {
    let dir = folder();
    let path = out(&dir, "f.toml");
    let o = two_link_with_expression(&dir, "ZZ1 + YY2 + 4/25*M2", &path);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(path.exists());
    std::fs::remove_file(&path).unwrap();
    let o = two_link_with_expression(&dir, "ZZ1 + YY2 + 1/5*M2", &path);
    fails_with(
        &o,
        &[
            "id.json: `ZZR1` is ZZ1 + YY2 + 1/5*M2 in the result, but ZZ1 + YY2 + 0.16*M2 for",
            "the result was identified with another robot, or another version of this description",
        ],
    );
    assert!(!path.exists());
}

/// A result far from the data is said: the two-step extraction on the two-link arm holds
/// the mass of link 2 at what the gravity step chose (the gravity coefficients MX2 and MY2
/// leave it free) and reproduces ZZ2 hundreds of standard deviations away; it was written
/// without a word. The default method fits the same data within them, and says nothing.
#[test]
fn feasible_warns_of_a_result_far_from_the_data() {
    let dir = folder();
    let run = |extra: &[&str]| two_link(None, &out(&dir, "f.toml"), extra);
    let far = run(&["--method", "anneal", "--two-step"]);
    assert!(
        far.contains("standard deviations from the identified") && far.contains("--two-step"),
        "{far}"
    );
    let near = run(&[]);
    assert!(!near.contains("standard deviations from"), "{near}");
}

/// A result with more entries foreign to the description than extra columns are kept for
/// as free terms is refused at once, naming the count and the first names (1000 of them
/// used to run for minutes, each a variable of the solvers); a few are kept.
#[test]
fn feasible_refuses_a_result_with_too_many_foreign_entries() {
    let dir = folder();
    let mut json = fixture_json("tx40_identified.json");
    let run = |json: &serde_json::Value, name: &str| {
        let identified = dir.path().join(name);
        std::fs::write(&identified, json.to_string()).unwrap();
        robid(&[
            "feasible",
            "configs/tx40_robot.toml",
            "--identified",
            identified.to_str().unwrap(),
            "-o",
            out(&dir, "out.toml").to_str().unwrap(),
        ])
    };
    let entry = |i: usize| serde_json::json!({"name": format!("x{i}"), "expression": "", "value": 0.1, "std": 0.01});
    let parameters = json["parameters"].as_array_mut().unwrap();
    parameters.extend((0..2).map(entry));
    let o = run(&json, "two.json");
    assert!(o.status.success(), "{}", stderr(&o));
    // a name that is no word is refused: written back as a TOML key, `Iam 6` broke the
    // file, and `a = 1\n[links]` would have added a table of its own
    for name in ["Iam 6", "a = 1\n[links]", ""] {
        let mut odd = json.clone();
        odd["parameters"].as_array_mut().unwrap()[0]["name"] = name.into();
        let o = run(&odd, "odd.json");
        fails_with(&o, &["parameters[0] `", "the name is not a parameter name"]);
    }
    let parameters = json["parameters"].as_array_mut().unwrap();
    // the fixture's own three extra columns (a coupled wrist's) and 98 foreign names
    parameters.extend((2..98).map(entry));
    let o = run(&json, "many.json");
    fails_with(
        &o,
        &[
            "101 entries are not base parameters",
            "(`Iam6`, ",
            "100 extra columns",
        ],
    );
}

/// The link masses of a TOML output.
fn masses(path: &Path) -> Vec<f64> {
    let v: toml::Value = toml::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    v["links"]
        .as_array()
        .unwrap()
        .iter()
        .map(|l| l["mass"].as_float().unwrap())
        .collect()
}

/// With the CAD values of `parameters/tx40.toml` as a prior (its drive terms and the wrist
/// columns have none), at the default weight (100: each link trusted to 10 % of its own
/// values), the masses the data barely determine move towards CAD, while every base
/// parameter stays within 3 of its standard deviations of the identified value: the data
/// keep what they determine firmly. The prior, rough CAD values (FIGAROH's nominal URDF),
/// competes with the data where they are less firm than 10 %: chi^2 rises from 15.4 to 75
/// for the 61 identified values (at the old default, weight 1 per the solids' scales, to
/// 17.5). Measured (sum |m - m_CAD| without -> with the prior; chi^2; max |z|) in the note
/// of each test; the sdp method's (feature `sdp`) is the suite's `feasible_sdp_tx40_report`,
/// on the same files without the binary, with its own weight.
fn prior_pulls_the_free_directions_towards_cad(method: &str, ratio: Option<f64>) {
    let dir = folder();
    let cad = [10.5, 3.6, 4.07, 3.62, 1.02, 0.2];
    let distance = |m: &[f64]| -> f64 { m.iter().zip(&cad).map(|(a, b)| (a - b).abs()).sum() };
    let plain = out(&dir, &format!("{method}_plain.toml"));
    let (chi2_plain, z_plain) = feasible_summary(method, &plain, &[]);
    let pulled = out(&dir, &format!("{method}_prior.toml"));
    let (chi2, z) = feasible_summary(method, &pulled, &["--prior", "parameters/tx40.toml"]);
    check_toml(&pulled);
    let (d0, d1) = (distance(&masses(&plain)), distance(&masses(&pulled)));
    eprintln!(
        "{method}: sum |m - m_CAD|: without prior {d0:.3} kg, with prior {d1:.3} kg; chi^2 \
         {chi2_plain:.3} -> {chi2:.3}; max |z| {z_plain:.3} -> {z:.3}"
    );
    // every method measured 0.36 kg with the prior (of 23 kg): bound 2x
    assert!(d1 < 0.72, "with prior {d1} kg (without {d0})");
    // a deterministic method's masses without the prior are where its pull to the centre
    // of the bounds leaves them; the search's are where its random walk stopped, no
    // reference (21.4 kg, 12.3 kg after a change of its Jacobian's rounding)
    if let Some(ratio) = ratio {
        assert!(d1 < ratio * d0, "without prior {d0}, with prior {d1}");
    }
    // the data keep what they determine: no base parameter is moved past 3 std
    assert!(z <= 3.0, "max |z| {z} (chi^2 {chi2} against {chi2_plain})");
}

/// Measured: sum |m - m_CAD| 27.95 -> 0.36 kg (ratio 0.013; 2.24 kg at the old default),
/// chi^2 15.38 -> 75.05, max |z| 2.34 -> 2.85; bound 2x.
#[test]
fn feasible_interior_point_prior_pulls_the_free_directions_towards_cad() {
    prior_pulls_the_free_directions_towards_cad("interior-point", Some(0.026));
}

/// The same optimum as the interior-point method, so the same measured figures and bounds.
#[test]
fn feasible_cholesky_prior_pulls_the_free_directions_towards_cad() {
    prior_pulls_the_free_directions_towards_cad("cholesky", Some(0.026));
}

/// Measured: sum |m - m_CAD| 12.27 -> 0.36 kg, chi^2 13.93 -> 73.76, max |z| 2.04 -> 2.85.
#[test]
fn feasible_anneal_prior_pulls_the_free_directions_towards_cad() {
    prior_pulls_the_free_directions_towards_cad("anneal", None);
}

#[test]
fn feasible_rejects_a_base_table_prior() {
    let dir = folder();
    let path = out(&dir, "bad_prior.toml");
    let run = |method: &str, prior: &str| {
        robid(&[
            "feasible",
            "configs/tx40_robot.toml",
            "--identified",
            "tests/fixtures/tx40_identified.json",
            "--method",
            method,
            "--prior",
            prior,
            "-o",
            path.to_str().unwrap(),
        ])
    };
    let base = out(&dir, "base_prior.toml");
    std::fs::write(&base, "[base]\nZZR1 = 1.0\n").unwrap();
    for method in ["interior-point", "anneal"] {
        let o = run(method, base.to_str().unwrap());
        assert!(!o.status.success());
        assert!(stderr(&o).contains("[standard] table"), "{}", stderr(&o));
    }
    // sdp in a build without it says so first, whatever else is wrong
    #[cfg(not(feature = "sdp"))]
    {
        let o = run("sdp", "no_such_prior.toml");
        assert!(!o.status.success());
        assert!(stderr(&o).contains("--features sdp"), "{}", stderr(&o));
        assert!(!stderr(&o).contains("no_such_prior"), "{}", stderr(&o));
    }
}

/// The LWR IV+ in the frames of Gaz et al. 2016 with their bounds (Tables I and III, eq. 18;
/// `tests/fixtures/lwr4_gaz2016*.toml`), and identified base parameters of a robot inside
/// those bounds: every mass 2 kg (14 kg in all), each centre of mass at the centre of its
/// box, inertias at the centre of their element boxes; deviation 1e-5 each. Returns the
/// JSON's path.
fn lwr_identified(dir: &tempfile::TempDir) -> PathBuf {
    use robid_runtime::feasible::{Bounds, LinkInertial, Problem};
    let robot =
        robid_symbolic::Robot::from_file(Path::new("tests/fixtures/lwr4_gaz2016.toml")).unwrap();
    let model = robots::interpreted::Interpreted::new(&robot).unwrap();
    let problem = Problem::from_model(&model).unwrap();
    let text = std::fs::read_to_string("tests/fixtures/lwr4_gaz2016_bounds.toml").unwrap();
    let bounds = Bounds::from_toml(&text, "bounds", 7).unwrap();
    let mut p = vec![0.0; problem.standard_names.len()];
    for (j, b) in bounds.links.iter().enumerate() {
        let mid = |e: usize| {
            let r = b.tensor[e].unwrap();
            0.5 * (r[0] + r[1])
        };
        let link = LinkInertial {
            mass: 2.0,
            com: b.com.map(|r| 0.5 * (r[0] + r[1])),
            inertia: [
                [mid(0), mid(3), mid(4)],
                [mid(3), mid(1), mid(5)],
                [mid(4), mid(5), mid(2)],
            ],
        };
        for (&i, v) in problem.layout.links[j].iter().zip(link.to_standard()) {
            p[i] = v;
        }
    }
    let beta = problem.base_of(&p);
    let entries: Vec<String> = problem
        .base_names
        .iter()
        .zip(beta.iter())
        .map(|(n, v)| format!("{{\"name\": \"{n}\", \"value\": {v:e}, \"std\": 1e-5}}"))
        .collect();
    let path = out(dir, "lwr_identified.json");
    std::fs::write(
        &path,
        format!("{{\"parameters\": [{}]}}", entries.join(", ")),
    )
    .unwrap();
    path
}

#[test]
fn gaz_feasible_two_step_on_the_lwr_with_the_papers_bounds() {
    let dir = folder();
    let identified = lwr_identified(&dir);
    let output = out(&dir, "lwr.toml");
    let args = [
        "feasible",
        "tests/fixtures/lwr4_gaz2016.toml",
        "--identified",
        identified.to_str().unwrap(),
        "--bounds",
        "tests/fixtures/lwr4_gaz2016_bounds.toml",
        "--method",
        "anneal",
        "--two-step",
        "--restarts",
        "2",
        "--equal",
        "I7xz = c7x * c7z * m7",
        "--equal",
        "I7yz = c7y * c7z * m7",
        "--mass-step",
        "10",
        "-o",
        output.to_str().unwrap(),
    ];
    let o = robid(&args);
    let err = stderr(&o);
    assert!(o.status.success(), "{err}");
    // the gravity step: the twelve coefficients fitted exactly (a solution exists; whitened
    // by deviations of 1e-5, rounding gives chi^2 near 1e-20; measured 3.3e-29)
    let line = err
        .lines()
        .find(|l| l.starts_with("gravity step: chi^2 "))
        .unwrap();
    let chi2: f64 = line["gravity step: chi^2 ".len()..]
        .split(' ')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!(chi2 < 1e-18, "{line}");
    assert!(line.contains("over 12 gravity coefficients"), "{line}");
    // the second step keeps the 23 held values: the output's masses are the printed ones
    let held: Vec<(String, f64)> = line
        .split("holds ")
        .nth(1)
        .unwrap()
        .split(", ")
        .map(|h| {
            let (name, value) = h.split_once(" = ").unwrap();
            (name.to_owned(), value.parse().unwrap())
        })
        .collect();
    assert_eq!(held.len(), 23, "{line}");
    let text = std::fs::read_to_string(&output).unwrap();
    let v: toml::Value = toml::from_str(&text).unwrap();
    let standard = v["standard"].as_table().unwrap();
    let value = |name: &str| standard[name].as_float().unwrap();
    for (name, x) in held.iter().filter(|(n, _)| n.starts_with('m')) {
        let m = value(&format!("M{}", &name[1..]));
        // printed with 7 significant digits
        assert!((m - x).abs() <= 1e-6 * x.abs(), "{name}: {m} against {x}");
    }
    // eq. 15 makes the products of inertia about frame 7's origin vanish (I_xz about the
    // origin is I_xz about the centre of mass minus m c_x c_z); measured 5.5e-12 and
    // 2.7e-11 kg m^2 (this target has c7x = c7y = 0, so the check is weak: the unit test
    // gaz_an_equality_holds_where_the_fit_is_blind tests the equality itself)
    for name in ["XZ7", "YZ7"] {
        assert!(value(name).abs() < 5.5e-11, "{name} = {}", value(name));
    }
    // Whether the second step can fit the whole problem depends on step 1's choice among
    // the gravity solutions (docs/experiments.md#two-step-extraction): here it cannot
    // (measured chi^2 2.9e7), and the summary says which bounds the result misses.
    eprintln!("{err}");
}

#[test]
fn gaz_feasible_refuses_gaz_options_out_of_place() {
    let dir = folder();
    let identified = lwr_identified(&dir);
    let output = out(&dir, "lwr.toml");
    let run = |extra: &[&str]| {
        let mut args = vec![
            "feasible",
            "tests/fixtures/lwr4_gaz2016.toml",
            "--identified",
            identified.to_str().unwrap(),
            "-o",
            output.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let o = robid(&args);
        assert!(!o.status.success());
        assert!(!output.exists());
        stderr(&o)
    };
    let e = run(&["--two-step"]);
    assert!(
        e.contains("--two-step is an option of --method anneal, not of --method interior-point"),
        "{e}"
    );
    let e = run(&["--method", "anneal", "--equal", "I7xz = c7x * q7"]);
    assert!(e.contains("--equal: `q7` is not a link variable"), "{e}");
    let e = run(&["--method", "anneal", "--mass-step", "10"]);
    assert!(e.contains("no `total_mass` range"), "{e}");
    let e = run(&["--method", "anneal", "--restarts", "0"]);
    assert!(e.contains("0 is outside 1..=10000"), "{e}");
    let e = run(&[
        "--method",
        "anneal",
        "--equal",
        "I8xz = c7x",
        "--bounds",
        "tests/fixtures/lwr4_gaz2016_bounds.toml",
    ]);
    // named by its flag, not by the library's `AnnealOptions` (it said "AnnealOptions
    // `fixed`: link 8 named in a fixed value or an equality")
    assert!(
        e.contains("--equal: `I8xz = c7x` names link 8, but the robot has 7 links")
            && !e.contains("AnnealOptions"),
        "{e}"
    );
    // the TX40's result holds extra config columns: no gravity step for them
    let o = robid(&[
        "feasible",
        "configs/tx40_robot.toml",
        "--identified",
        "tests/fixtures/tx40_identified.json",
        "--method",
        "anneal",
        "--two-step",
        "-o",
        output.to_str().unwrap(),
    ]);
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains("extra config columns"),
        "{}",
        stderr(&o)
    );
}

/// A description's `[base]` and `[tool]` reach the URDF: the first joint's origin is the
/// base transform (here 1.2 m up, turned a quarter turn about z), and a massless `tool`
/// link hangs from the last link on a fixed joint at the tool pose. `robid model` prints
/// both.
#[test]
fn feasible_urdf_places_the_base_and_the_tool() {
    let dir = folder();
    let text = std::fs::read_to_string(common::asset("configs/tx40_robot.toml")).unwrap();
    let description = out(&dir, "tx40_mounted.toml");
    std::fs::write(
        &description,
        format!(
            "{text}\n[base]\nxyz = [0, 0, 1.2]\nrpy = [0, 0, \"pi/2\"]\n\n[tool]\nxyz = [0, 0, 0.065]\n"
        ),
    )
    .unwrap();
    let urdf = out(&dir, "mounted.urdf");
    let o = robid(&[
        "feasible",
        description.to_str().unwrap(),
        "--identified",
        "tests/fixtures/tx40_identified.json",
        "--bounds",
        "tests/fixtures/tx40_bounds.toml",
        "-o",
        urdf.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    check_urdf(&urdf);
    let text = std::fs::read_to_string(&urdf).unwrap();
    let joint1 = text.split("<joint name=\"joint1\"").nth(1).unwrap();
    assert!(
        joint1.contains("<origin xyz=\"0e0 0e0 1.2e0\" rpy=\"0e0 0e0 1.5707963267948966e0\"/>"),
        "{joint1}"
    );
    let tool = text
        .split("<joint name=\"tool_joint\" type=\"fixed\">")
        .nth(1)
        .unwrap();
    assert!(tool.contains("<parent link=\"link6\"/>"), "{tool}");
    assert!(tool.contains("<child link=\"tool\"/>"), "{tool}");
    assert!(tool.contains("<origin xyz=\"0e0 0e0 6.5e-2\""), "{tool}");
    assert!(text.contains("<link name=\"tool\"/>"));
    let o = robid(&["model", description.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let model = common::stdout(&o);
    assert!(
        model.contains("base (frame 0 in the world): xyz [0, 0, 1.2], rpy [0, 0, pi/2]"),
        "{model}"
    );
    assert!(
        model.contains("tool (in frame n): xyz [0, 0, 0.065], rpy [0, 0, 0]"),
        "{model}"
    );
}

/// One revolute joint about the vertical with a = d = 0: the link has no length and the
/// data see only ZZ1. The default prior's solids have no size then; it used to make a speck
/// of 1 mm at the density ZZ1 asks of it and wrote M1 = 9.5e5 kg (chi^2 5e-16). Now every
/// convex method refuses, naming the bounds entries to give, and writes nothing; with
/// bounds (not the defaults) or a prior for the link the run goes through, the link's
/// prior the centre of its bounds, and the parameters the data do not see are said to
/// come from the prior. A tool 1 cm out is a length, but far too short for the identified
/// inertia (solids of 8.1e10 kg/m^3, 1.6e4 kg): refused the same way.
#[test]
fn feasible_asks_for_bounds_where_the_links_have_no_length() {
    let dir = folder();
    let joint = "name = \"spindle\"\nconvention = \"modified\"\ngravity = [0, 0, -9.81]\n\n\
                 [[joints]]\nalpha = 0\na = 0\nd = 0\nlimits = { position = [-2.9, 2.9] }\n";
    let robot = common::write(dir.path(), "spindle.toml", joint);
    let identified = common::write(
        dir.path(),
        "spindle.json",
        r#"{"parameters": [{"name": "ZZ1", "expression": "ZZ1", "value": 0.05, "std": 1e-4}]}"#,
    );
    let output = out(&dir, "links.toml");
    let run = |robot: &Path, extra: &[&str]| {
        let mut args = vec![
            "feasible",
            robot.to_str().unwrap(),
            "--identified",
            identified.to_str().unwrap(),
            "-o",
            output.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        robid(&args)
    };
    let refusal = [
        "spindle.toml: the robot's links have no length",
        "give ranges for link 1 in --bounds (e.g. `[links.1]` with `mass = [lo, hi]`",
        "or values in --prior",
    ];
    for method in ["interior-point", "cholesky"] {
        fails_with(&run(&robot, &["--method", method]), &refusal);
        assert!(!output.exists(), "{method}");
    }
    // a bounds file that leaves link 1 at the default ranges says nothing of its size
    let loose = common::write(dir.path(), "loose.toml", "total_mass = [0.0, 100.0]\n");
    fails_with(
        &run(&robot, &["--bounds", loose.to_str().unwrap()]),
        &refusal,
    );
    let bounds = common::write(
        dir.path(),
        "bounds.toml",
        "[links.1]\nmass = [1.0, 3.0]\ncom = [[-0.05, 0.05], [-0.05, 0.05], [-0.05, 0.05]]\n\
         inertia = [0.0, 0.1]\n",
    );
    let o = run(&robot, &["--bounds", bounds.to_str().unwrap()]);
    let err = stderr(&o);
    assert!(o.status.success(), "{err}");
    assert!(
        err.contains("; the prior of link 1 is the centre of the bounds in ")
            && err.contains("bounds.toml"),
        "{err}"
    );
    let unseen = "not from the data (no effect on the torques), values from the prior (the \
                  default prior where none is given), or the nearest to them that the physical constraints and bounds allow: XX1 XY1 XZ1 \
                  YY1 YZ1 MX1 MY1 MZ1 M1";
    assert!(err.contains(unseen), "{err}");
    let text = std::fs::read_to_string(&output).unwrap();
    assert!(
        text.contains(
            "# Not from the data (no effect on the dynamics), values from the prior (the \
             default prior where none is given), or the nearest to them that the physical constraints and bounds allow: XX1 XY1 XZ1 YY1 \
             YZ1 MX1 MY1 MZ1 M1."
        ),
        "{text}"
    );
    let v: toml::Value = toml::from_str(&text).unwrap();
    let zz = v["standard"]["ZZ1"].as_float().unwrap();
    assert!((zz - 0.05).abs() < 1e-6, "{zz}");
    // the centre of the mass range (measured 2.0000006 kg)
    let mass = masses(&output)[0];
    assert!((mass - 2.0).abs() < 1e-3, "{mass}");
    // a prior with all the link's values needs no bounds
    std::fs::remove_file(&output).unwrap();
    let prior = common::write(
        dir.path(),
        "prior.toml",
        "[standard]\nXX1 = 0.04\nXY1 = 0.0\nXZ1 = 0.0\nYY1 = 0.04\nYZ1 = 0.0\nZZ1 = 0.05\n\
         MX1 = 0.0\nMY1 = 0.0\nMZ1 = 0.0\nM1 = 1.5\n",
    );
    let o = run(&robot, &["--prior", prior.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let mass = masses(&output)[0];
    assert!((mass - 1.5).abs() < 1e-3, "{mass}");
    // a tool 1 cm out: a length, too short for 0.05 kg m^2
    let tooled = common::write(
        dir.path(),
        "tooled.toml",
        &format!("{joint}\n[tool]\nxyz = [0, 0, 0.01]\n"),
    );
    std::fs::remove_file(&output).unwrap();
    fails_with(
        &run(&tooled, &[]),
        &[
            "tooled.toml: solid links along the description's segments would need a density \
             of 8.1e10 kg/m^3 (more than 1e5)",
            "give ranges for link 1 in --bounds",
        ],
    );
    assert!(!output.exists());
}

/// The Stanford arm (`descriptions/stanford.toml`, joint 3 a prismatic boom) simulated
/// with its reference parameters along a smooth trajectory, with torque noise: the path of
/// the written data file in `d`.
fn stanford_data(d: &Path) -> PathBuf {
    let mut trajectory = String::from("t,q1,q2,q3,qd1,qd2,qd3,qdd1,qdd2,qdd3\n");
    let (w, a, c) = ([1.1, 1.7, 1.3], [1.0, 0.8, 0.2], [0.0, 0.0, 0.55]);
    for k in 0..2000 {
        let t = k as f64 * 5e-3;
        let (mut q, mut qd, mut qdd) = ([0.0; 3], [0.0; 3], [0.0; 3]);
        for j in 0..3 {
            let (w1, w2, phase) = (w[j], 2.9 * w[j], w[j] * t);
            let (s1, s2) = (phase.sin(), (w2 * t + 1.0).sin());
            let (c1, c2) = (phase.cos(), (w2 * t + 1.0).cos());
            q[j] = c[j] + a[j] * (s1 + 0.3 * s2);
            qd[j] = a[j] * (w1 * c1 + 0.3 * w2 * c2);
            qdd[j] = -a[j] * (w1 * w1 * s1 + 0.3 * w2 * w2 * s2);
        }
        let row: Vec<String> = std::iter::once(t)
            .chain(q)
            .chain(qd)
            .chain(qdd)
            .map(|v| format!("{v:e}"))
            .collect();
        trajectory.push_str(&row.join(","));
        trajectory.push('\n');
    }
    let trajectory = write(d, "trajectory.csv", &trajectory);
    let data = d.join("data.csv");
    let o = robid(&[
        "simulate",
        "descriptions/stanford.toml",
        "--parameters",
        "parameters/stanford.toml",
        "--trajectory",
        trajectory.to_str().unwrap(),
        "--torque-noise",
        "0.05",
        "-o",
        data.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    data
}

/// The Stanford arm identified from its simulated data and then made consistent by the
/// default `feasible`, without bounds or a prior: the default prior sizes the prismatic
/// boom from its joint's travel (0.2 to 0.9 m) and the fit succeeds, every link's
/// pseudo-inertia positive definite and the boom's mass near its true 4.25 kg. It was
/// refused: "solid links ... would need a density of 5.7e5 kg/m^3 ... check the
/// description's lengths", the boom's segment having length zero.
#[test]
fn feasible_sizes_the_stanford_arms_prismatic_boom_by_its_travel() {
    let dir = folder();
    let d = dir.path();
    let data = stanford_data(d);
    let config = write(
        d,
        "config.toml",
        "dof = 3\ntime_column = \"t\"\n[[source]]\nposition = \"q{}\"\n\
         velocity = \"qd{}\"\nacceleration = \"qdd{}\"\ntorque = \"tau{}\"\n",
    );
    let result = d.join("result.json");
    let o = robid(&[
        "identify",
        "descriptions/stanford.toml",
        "--config",
        config.to_str().unwrap(),
        "--data",
        data.to_str().unwrap(),
        "--json",
        result.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let links = d.join("links.toml");
    let o = robid(&[
        "feasible",
        "descriptions/stanford.toml",
        "--identified",
        result.to_str().unwrap(),
        "-o",
        links.to_str().unwrap(),
    ]);
    let err = stderr(&o);
    assert!(o.status.success(), "{err}");
    assert!(!err.contains("density"), "{err}");
    let v: toml::Value = toml::from_str(&std::fs::read_to_string(&links).unwrap()).unwrap();
    let links = v["links"].as_array().unwrap();
    assert_eq!(links.len(), 3);
    for (j, link) in links.iter().enumerate() {
        let eigenvalue = link["pseudo_inertia_min_eigenvalue"].as_float().unwrap();
        let mass = link["mass"].as_float().unwrap();
        assert!(eigenvalue > 0.0 && mass > 0.0, "link {}: {link}", j + 1);
    }
    // the boom's mass is what the data see (M3 is a base parameter): measured 4.24998
    let boom = links[2]["mass"].as_float().unwrap();
    assert!((boom - 4.25).abs() < 0.05, "{boom}");
    // the fit stays with the data: every base parameter within 3 standard deviations
    let max_z: f64 = err
        .split("max |z| ")
        .nth(1)
        .and_then(|r| r.split(',').next())
        .and_then(|z| z.parse().ok())
        .unwrap_or_else(|| panic!("no max |z| in {err}"));
    assert!(max_z < 3.0, "{err}");
}

/// The workflow with known parameters (docs/identification.md, "Known parameters"): the
/// Stanford arm simulated with torque noise, identified with `M2` and `M3` in a `[known]`
/// file, then `feasible` on its JSON. The base parameter `M3` has no unknown term left, so
/// the report gives it std 0 and `"known": true`: an exact value, which `feasible` reproduces
/// (it used to refuse the entry: "std 0 ... a standard deviation is positive").
#[test]
fn feasible_takes_an_identification_with_known_parameters() {
    let dir = folder();
    let d = dir.path();
    let data = stanford_data(d);
    write(d, "known.toml", "[known]\nM2 = 5.01\nM3 = 4.25\n");
    let config = write(
        d,
        "config.toml",
        "dof = 3\ntime_column = \"t\"\n[[source]]\nposition = \"q{}\"\n\
         velocity = \"qd{}\"\nacceleration = \"qdd{}\"\ntorque = \"tau{}\"\n\
         [estimation]\nknown = \"known.toml\"\n",
    );
    let result = d.join("result.json");
    let o = robid(&[
        "identify",
        "descriptions/stanford.toml",
        "--config",
        config.to_str().unwrap(),
        "--data",
        data.to_str().unwrap(),
        "--json",
        result.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&result).unwrap()).unwrap();
    let m3 = json["parameters"]
        .as_array()
        .unwrap()
        .iter()
        .find(|p| p["name"] == "M3")
        .expect("M3 is a base parameter");
    assert_eq!(m3["std"], 0.0, "{m3}");
    assert_eq!(m3["known"], true, "{m3}");
    // known values that fix nothing are named in a warning (they were taken silently, and
    // moved only the reported error bound): M2, grouped with free parameters of the
    // Stanford arm, and XX1 of a first joint about z, which enters no torque
    assert!(
        stderr(&o).contains("warning: the known M2 fixes nothing"),
        "{}",
        stderr(&o)
    );
    write(d, "more.toml", "[known]\nM2 = 5.01\nM3 = 4.25\nXX1 = 0.1\n");
    let more = write(
        d,
        "more_config.toml",
        &std::fs::read_to_string(&config)
            .unwrap()
            .replace("known.toml", "more.toml"),
    );
    let o = robid(&[
        "identify",
        "descriptions/stanford.toml",
        "--config",
        more.to_str().unwrap(),
        "--data",
        data.to_str().unwrap(),
    ]);
    assert!(
        o.status.success()
            && stderr(&o).contains("warning: the known XX1, M2 fix nothing: each enters"),
        "{}",
        stderr(&o)
    );
    let links = d.join("links.toml");
    for method in ["interior-point", "cholesky"] {
        let o = robid(&[
            "feasible",
            "descriptions/stanford.toml",
            "--identified",
            result.to_str().unwrap(),
            "--prior",
            "parameters/stanford.toml",
            "--method",
            method,
            "-o",
            links.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{method}: {}", stderr(&o));
        let v: toml::Value = toml::from_str(&std::fs::read_to_string(&links).unwrap()).unwrap();
        let m3 = v["standard"]["M3"].as_float().unwrap();
        // the known value within the floor of its variance, 1e-5 of it
        assert!((m3 - 4.25).abs() < 1e-4, "{method}: M3 {m3}");
    }
}

/// Gravity along another direction than -z (here up: the robot hangs from a ceiling)
/// reaches the URDF as a root link `world` on a fixed joint that turns it to -z, where URDF
/// readers put gravity: the URDF's torques are the description's with the same links, to
/// rounding. They lost gravity (or turned it over) before.
#[test]
fn feasible_urdf_carries_a_gravity_off_the_vertical() {
    let dir = folder();
    let text = std::fs::read_to_string(common::asset("configs/tx40_robot.toml")).unwrap();
    let hanging = text.replace("gravity = [0, 0, -9.81]", "gravity = [0, 0, 9.81]");
    assert_ne!(hanging, text);
    let description = common::write(dir.path(), "tx40_hanging.toml", &hanging);
    let mut written = Vec::new();
    for name in ["hanging.urdf", "hanging.toml"] {
        let output = out(&dir, name);
        let o = robid(&[
            "feasible",
            description.to_str().unwrap(),
            "--identified",
            "tests/fixtures/tx40_identified.json",
            "--bounds",
            "tests/fixtures/tx40_bounds.toml",
            "-o",
            output.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        written.push(output);
    }
    let urdf = std::fs::read_to_string(&written[0]).unwrap();
    assert!(
        urdf.contains("<link name=\"world\"/>") && urdf.contains("<child link=\"base_link\"/>"),
        "{urdf}"
    );
    check_urdf(&written[0]);
    // the rigid links alone on both sides: the URDF carries no drive terms
    let rigid: String = hanging
        .lines()
        .filter(|l| !l.starts_with("drive"))
        .map(|l| format!("{l}\n"))
        .collect();
    let rigid = common::write(dir.path(), "rigid.toml", &rigid);
    let links: String = std::fs::read_to_string(&written[1])
        .unwrap()
        .lines()
        .filter(|l| {
            // the inertial parameters (XX1 .. M6), not the drive's or the config's columns
            let key = l.split(" = ").next().unwrap_or_default();
            let stem = key.trim_end_matches(|c: char| c.is_ascii_digit());
            !l.contains(" = ")
                || (stem.len() < key.len()
                    && ["XX", "XY", "XZ", "YY", "YZ", "ZZ", "MX", "MY", "MZ", "M"].contains(&stem))
        })
        .map(|l| format!("{l}\n"))
        .collect();
    let links = common::write(dir.path(), "links.toml", &links);
    let states = common::ur5e_states(dir.path(), 5);
    let torques = |args: &[&str]| -> Vec<f64> {
        let o = robid(args);
        assert!(o.status.success(), "{}", stderr(&o));
        common::stdout(&o)
            .lines()
            .skip(1)
            .flat_map(|l| {
                l.split(',')
                    .map(|v| v.parse::<f64>().unwrap())
                    .collect::<Vec<_>>()
            })
            .collect()
    };
    let states = states.to_str().unwrap();
    let from_urdf = torques(&["torques", written[0].to_str().unwrap(), "--states", states]);
    let from_toml = torques(&[
        "torques",
        rigid.to_str().unwrap(),
        "--parameters",
        links.to_str().unwrap(),
        "--states",
        states,
    ]);
    assert_eq!(from_urdf.len(), from_toml.len());
    let largest = from_toml.iter().fold(0.0f64, |m, t| m.max(t.abs()));
    assert!(largest > 1.0, "{from_toml:?}");
    for (u, t) in from_urdf.iter().zip(&from_toml) {
        assert!((u - t).abs() <= 1e-9 * largest, "{u} against {t}");
    }
}

/// A trajectory of two sines per joint (`t, q.., qd.., qdd..`, 10 s at 100 Hz, within
/// +-1.3 rad and 2.3 rad/s) for `robid simulate`.
fn sines(dir: &Path, name: &str, joints: usize) -> PathBuf {
    let names = |p: &'static str| (1..=joints).map(move |j| format!("{p}{j}"));
    let header: Vec<String> = std::iter::once("t".to_owned())
        .chain(names("q"))
        .chain(names("qd"))
        .chain(names("qdd"))
        .collect();
    let mut text = header.join(",") + "\n";
    for i in 0..1001 {
        let t = 0.01 * i as f64;
        let mut row = vec![t];
        for derivative in 0..3 {
            for j in 0..joints {
                let jf = j as f64;
                let terms = [
                    (0.8, 0.7 + 0.23 * jf, 0.5 * jf),
                    (0.5, 1.9 + 0.41 * jf, 1.3 * jf),
                ];
                row.push(
                    terms
                        .iter()
                        .map(|&(a, w, phase): &(f64, f64, f64)| {
                            let x = w * t + phase;
                            match derivative {
                                0 => a * x.sin(),
                                1 => a * w * x.cos(),
                                _ => -a * w * w * x.sin(),
                            }
                        })
                        .sum(),
                );
            }
        }
        let row: Vec<String> = row.iter().map(|v| format!("{v:.10e}")).collect();
        text += &(row.join(",") + "\n");
    }
    write(dir, &format!("{name}_sines.csv"), &text)
}

/// The prior of a URDF's arm against the data (base parameters identified by weighted
/// least squares from simulated torques with 3 N m of noise), at the default weight, with
/// both pure-Rust convex methods, on the UR5, the Kinova and the xArm7:
///
/// - the URDF's own (true) inertials as the prior: every link keeps its mass within 10 %
///   and its centre of mass within 4 cm of the URDF's, at a data chi^2 below the number of
///   base parameters. At the old default (weight 1 per solid-cylinder scale) the noise
///   carried poorly determined directions to the bounds: the UR5's wrist flange (0.188 kg)
///   became 1.3 g with its centre of mass 1.15 m away, the Kinova's link 5 (0.463 kg)
///   0.165 kg; at weight 1 per the links' own scales the UR5's link 3 weighed 29 % too much
///   with its centre of mass 10 cm off, the xArm7's link 4 54 %. Measured now: masses
///   within 4.4 %, centres of mass within 27 mm.
/// - a prior 1.3 times too large (every inertial of a `--prior` file): the data still win
///   where they determine the parameters, every base parameter within 3 standard deviations
///   of its identified value (measured at most 2.46, 2.34 with the true prior; a weight of
///   1e3 gave 3.6 and 6.1), and what they leave stays a body near the prior: every mass
///   between 0.85 and 1.45 of the URDF's (measured 0.98 to 1.30; on the solids' scales the
///   UR5's flange weighed 0.37 of it), nothing at a bound.
#[test]
fn feasible_urdf_prior_holds_what_the_data_leave_and_yields_to_what_they_weigh() {
    let dir = folder();
    for (robot, name, joints) in [
        (UR5_URDF, "ur5", 6),
        (KINOVA_URDF, "kinova", 6),
        (XARM7_URDF, "xarm7", 7),
    ] {
        let trajectory = sines(dir.path(), name, joints);
        let truth = out(&dir, &format!("{name}_truth.toml"));
        let data = out(&dir, &format!("{name}.csv"));
        let result = out(&dir, &format!("{name}.json"));
        let model = [robot, "--standard-parameters", truth.to_str().unwrap()];
        let simulate = [
            "simulate",
            robot,
            "--trajectory",
            trajectory.to_str().unwrap(),
            "--torque-noise",
            "3",
            "--seed",
            "2",
            "-o",
            data.to_str().unwrap(),
        ];
        let identify = [
            "identify",
            robot,
            "--data",
            data.to_str().unwrap(),
            "--method",
            "wls",
            "--json",
            result.to_str().unwrap(),
        ];
        for args in [
            &[&["model"][..], &model[..]].concat(),
            &simulate[..],
            &identify[..],
        ] {
            let o = robid(args);
            assert!(o.status.success(), "{args:?}: {}", stderr(&o));
        }
        let standard = |path: &Path| -> toml::Table {
            let v: toml::Table = toml::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
            v["standard"].as_table().unwrap().clone()
        };
        let truth = standard(&truth);
        // every inertial 1.3 times the URDF's: masses, first moments and inertias
        let wrong: String = truth
            .iter()
            .map(|(k, v)| format!("{k} = {:e}\n", 1.3 * v.as_float().unwrap()))
            .collect();
        let wrong = write(
            dir.path(),
            &format!("{name}_wrong.toml"),
            &format!("[standard]\n{wrong}"),
        );
        let identified: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&result).unwrap()).unwrap();
        let base = identified["parameters"].as_array().unwrap().len() as f64;
        for (prior, flags) in [
            ("urdf", vec![]),
            ("x1.3", vec!["--prior", wrong.to_str().unwrap()]),
        ] {
            for method in ["interior-point", "cholesky"] {
                let fit = out(&dir, &format!("{name}_{prior}_{method}.toml"));
                let args = [
                    &[
                        "feasible",
                        robot,
                        "--identified",
                        result.to_str().unwrap(),
                        "--method",
                        method,
                        "-o",
                        fit.to_str().unwrap(),
                    ][..],
                    &flags[..],
                ]
                .concat();
                let o = robid(&args);
                let err = stderr(&o);
                assert!(o.status.success(), "{err}");
                let after = |label: &str| -> f64 {
                    err.split(label)
                        .nth(1)
                        .and_then(|r| r.split(',').next())
                        .and_then(|v| v.trim().parse().ok())
                        .unwrap_or_else(|| panic!("no {label} in {err}"))
                };
                let (chi2, z) = (after(&format!("{method}: chi^2 ")), after("max |z| "));
                let what = format!("{name}, {prior} prior, {method}");
                eprintln!("{what}: chi^2 {chi2:.2} of {base}, max |z| {z:.3}");
                assert!(!err.contains("at its lower bound"), "{what}: {err}");
                assert!(!err.contains("at its upper bound"), "{what}: {err}");
                assert!(z <= 3.0, "{what}: a base parameter {z} std off");
                let fit = standard(&fit);
                let value = |t: &toml::Table, key: String| t[&key].as_float().unwrap();
                for j in 1..=joints {
                    let (m0, m) = (value(&truth, format!("M{j}")), value(&fit, format!("M{j}")));
                    let off = ["MX", "MY", "MZ"]
                        .iter()
                        .map(|c| {
                            let key = format!("{c}{j}");
                            (value(&fit, key.clone()) / m - value(&truth, key) / m0).powi(2)
                        })
                        .sum::<f64>()
                        .sqrt();
                    eprintln!(
                        "{what}, link {j}: {m:.4} kg ({:.3}), com off {off:.4} m",
                        m / m0
                    );
                    if prior == "urdf" {
                        assert!(
                            (m / m0 - 1.0).abs() < 0.1,
                            "{what}, link {j}: {m} kg, true {m0}"
                        );
                        assert!(off < 0.04, "{what}, link {j}: centre of mass {off} m off");
                    } else {
                        assert!(
                            (0.85..=1.45).contains(&(m / m0)),
                            "{what}, link {j}: {m} kg, true {m0}"
                        );
                    }
                }
                if prior == "urdf" {
                    assert!(chi2 < base, "{what}: chi^2 {chi2} over {base}");
                }
            }
        }
    }
}

/// Bounds the consistency margin rules out (principal moments of at most the margin, which
/// a pseudo-inertia at least margin x I keeps at twice it) are refused by every method at
/// their key in the bounds file, `[default]` when the links inherit them, nothing written:
/// `mass = [0, 1e-300]` failed as "the interior-point fit left the consistent set".
#[test]
fn feasible_names_bounds_below_the_margin_in_the_bounds_file() {
    let dir = folder();
    let bounds = write(
        dir.path(),
        "b.toml",
        "margin = 1e-2\n[default]\nmass = [0.0, 5.0]\ninertia = [0.0, 0.01]\n",
    );
    let path = out(&dir, "f.toml");
    let at = format!(
        "{}:4:1: `default.inertia`: link 1's upper bound 0.01 kg m^2 is below 0.02 kg m^2",
        bounds.display()
    );
    for method in ["interior-point", "cholesky", "anneal"] {
        let o = bounded("two_link", &bounds, method, &path);
        assert!(
            !o.status.success() && stderr(&o).contains(&at),
            "{method}: {}",
            stderr(&o)
        );
        assert!(!path.exists());
    }
}

/// A link given twice in a bounds file under two spellings of its number is named at the
/// second table, nothing written: `[links.1] mass = [0, 50]` then `[links.01] mass = [10,
/// 11]` fitted 2.5 kg to link 1 with exit status 0, one table silently dropped.
#[test]
fn feasible_names_a_link_given_twice_in_the_bounds_file() {
    let dir = folder();
    let bounds = write(
        dir.path(),
        "b.toml",
        "[links.1]\nmass = [0.0, 50.0]\n[links.01]\nmass = [10.0, 11.0]\n",
    );
    let path = out(&dir, "f.toml");
    let o = bounded("two_link", &bounds, "interior-point", &path);
    fails_with(
        &o,
        &[&format!(
            "{}:3:8: `links.01`: link 1 is given twice, as [links.1] on line 1 and here; \
             give one table per link",
            bounds.display()
        )],
    );
    assert!(!path.exists());
}

/// `--equal` quotes its text short (a 5,000-character name gave a 5,138-byte error, 5,000
/// nested parentheses one of 10,139 bytes), and parentheses nested 60,000 deep are refused
/// as any other name, with no recursion to overflow the stack; nothing written. (100,000
/// levels, 200 kB, exceed the 128 KiB the kernel passes as one argument: the library's
/// test takes them.)
#[test]
fn feasible_equal_quotes_long_text_short() {
    let dir = folder();
    let path = out(&dir, "f.toml");
    let nested = |depth: usize| format!("m1 = {}m2{}", "(".repeat(depth), ")".repeat(depth));
    for (equal, quoted) in [
        (format!("m1 = {}", "x".repeat(5000)), 5000),
        (nested(5000), 10_002),
        (nested(60_000), 120_002),
    ] {
        let o = two_link_anneal(&path, &["--equal", &equal]);
        fails_with(
            &o,
            &[
                "--equal: `",
                &format!("({quoted} characters)` is not a link variable"),
            ],
        );
        assert!(stderr(&o).len() < 400, "{} bytes", stderr(&o).len());
        assert!(!path.exists());
    }
}

/// The output's extension chooses its format, and one that is neither TOML nor URDF is
/// refused before any fit, nothing written (`-o x.json` got TOML silently).
#[test]
fn feasible_refuses_an_output_of_another_format() {
    let dir = folder();
    let path = out(&dir, "links.json");
    let o = robid(&[
        "feasible",
        "tests/fixtures/two_link.toml",
        "--identified",
        "tests/fixtures/two_link_identified.json",
        "-o",
        path.to_str().unwrap(),
    ]);
    fails_with(
        &o,
        &[
            "--output",
            "writes TOML (`.toml`) or URDF (`.urdf`, `.xml`), not `.json`",
        ],
    );
    assert!(!path.exists());
}

/// `robid feasible` on the two-link arm with `--method anneal` and `extra` arguments.
fn two_link_anneal(output: &Path, extra: &[&str]) -> std::process::Output {
    let mut args = vec![
        "feasible",
        "tests/fixtures/two_link.toml",
        "--identified",
        "tests/fixtures/two_link_identified.json",
        "--method",
        "anneal",
        "-o",
        output.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    robid(&args)
}

/// `anneal` imposes every bound: where the data push against an element bound and a
/// closed total mass (the two-link arm's xy of 0.01 under `xy >= 0.05`, its 3 kg and more
/// under a total of exactly 5 kg), it wrote xy 0.04998 and 5.00006 kg with "bounds not
/// met" and exit status 0; Gaz et al.'s step penalty (`--mass-step`) never reached the
/// closed range (11.26 kg written). Now the result meets them, with or without the step.
#[test]
fn feasible_anneal_meets_the_bounds_the_data_push_against() {
    let dir = folder();
    let bounds = write(
        dir.path(),
        "b.toml",
        "total_mass = [5, 5]\n[default]\nmass = [0.01, 10]\ninertia = [0, 5]\n\
         [links.2]\ninertia_tensor = { xx = [0.0, 0.01], xy = [0.05, 0.1] }\n",
    );
    let path = out(&dir, "f.toml");
    for extra in [&[][..], &["--mass-step", "1e3"]] {
        let mut args = vec!["--bounds", bounds.to_str().unwrap()];
        args.extend_from_slice(extra);
        let o = two_link_anneal(&path, &args);
        let err = stderr(&o);
        assert!(
            o.status.success() && !err.contains("not met"),
            "{extra:?}: {err}"
        );
        let v: toml::Value = toml::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
        let s = &v["standard"];
        let get = |k: &str| s[k].as_float().unwrap();
        let total = get("M1") + get("M2");
        assert!((total - 5.0).abs() <= 1e-5, "{extra:?}: total {total}");
        // the element about the centre of mass from the one about the frame origin
        let xy = get("XY2") + get("MX2") * get("MY2") / get("M2");
        assert!(xy >= 0.05 - 1e-6, "{extra:?}: xy {xy}");
    }
}

/// `anneal` imposes its equalities and says when it cannot: contradictory ones
/// (`c2x = 0.5`, `c2x = 0.2`: 0.35 was written; `m1 = 2 m2`, `m2 = 2 m1`, which only
/// massless links meet) fail naming them, nothing written; a
/// constant outside its variable's bounds (`m2 = -3`: accepted) is refused before the
/// search; a ratio the data do not follow (`c2y = -0.5 * c2x`, missed by 25 %) holds.
#[test]
fn feasible_anneal_meets_its_equalities_or_names_them() {
    let dir = folder();
    let path = out(&dir, "f.toml");
    let o = two_link_anneal(&path, &["--equal", "c2x = 0.5", "--equal", "c2x = 0.2"]);
    fails_with(
        &o,
        &[
            "equality `c2x = 0.5` not met: c2x = ",
            "equality `c2x = 0.2` not met",
            "nothing was written",
        ],
    );
    assert!(!path.exists());
    // only zero meets both, which a mass cannot be: they ended at the floor of 1e-6 kg,
    // 1e-6 apart, counted as met, and the result was written (the floor is now twice the
    // margin of 1e-6, where a pseudo-inertia of at least the margin stays reachable)
    let o = two_link_anneal(&path, &["--equal", "m1 = 2 * m2", "--equal", "m2 = 2 * m1"]);
    fails_with(
        &o,
        &[
            "equality `m1 = 2 * m2` not met: m1 = 2e-6, the right side 4e-6",
            "equality `m2 = 2 * m1` not met",
            "nothing was written",
        ],
    );
    assert!(!path.exists());
    let o = two_link_anneal(&path, &["--equal", "m2 = -3"]);
    fails_with(
        &o,
        &["--equal: `m2 = -3` sets m2 outside its bounds [0, 50]"],
    );
    assert!(!path.exists());
    let o = two_link_anneal(&path, &["--equal", "c2y = -0.5 * c2x"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: toml::Value = toml::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    let get = |k: &str| v["standard"][k].as_float().unwrap();
    // c = (MX, MY) / M: the ratio of the first moments
    let (mx, my) = (get("MX2"), get("MY2"));
    assert!(
        (my + 0.5 * mx).abs() <= 1e-6 * (1.0 + mx.abs()),
        "MX2 {mx}, MY2 {my}"
    );
}

/// `anneal` keeps the pseudo-inertia margin: its box held every second moment about the
/// centre of mass above the margin, which the first moment's coupling to the mass does not
/// carry over to the pseudo-inertia (a margin of 1e-3 gave 6.7e-4 with exit status 0).
#[test]
fn feasible_anneal_keeps_the_margin() {
    let dir = folder();
    let path = out(&dir, "f.toml");
    // a mass the data do not see (link 1's) kept inside its box: it stayed at the middle
    // of its bounds, half the margin under a bound of [0, 1.1e-3]
    let light = "[links.1]\nmass = [0.0, 0.0011]\n";
    for (margin, extra) in [("1e-3", ""), ("1e-2", ""), ("1e-3", light)] {
        let bounds = write(dir.path(), "m.toml", &format!("margin = {margin}\n{extra}"));
        let o = two_link_anneal(&path, &["--bounds", bounds.to_str().unwrap()]);
        assert!(o.status.success(), "{}", stderr(&o));
        let text = std::fs::read_to_string(&path).unwrap();
        let least: Vec<f64> = text
            .lines()
            .filter_map(|l| l.strip_prefix("pseudo_inertia_min_eigenvalue = "))
            .map(|v| v.parse().unwrap())
            .collect();
        assert_eq!(least.len(), 2, "{text}");
        let margin: f64 = margin.parse().unwrap();
        for l in least {
            assert!(l >= margin * (1.0 - 1e-9), "{margin}: {l} in {text}");
        }
    }
}

/// A result of static samples holds only the base parameters gravity determines: it is
/// told as such (it was refused as a result of another description, "base parameter
/// `ZZR1` is missing from the identified result; identify with the same robot
/// description"), and nothing is written.
#[test]
fn feasible_refuses_a_result_of_static_samples_as_such() {
    let dir = folder();
    let mut text = String::from("q1,q2,g1,g2\n");
    for k in 0..8 {
        let (a, b) = (0.4 * k as f64 - 1.3, 1.1 - 0.3 * k as f64);
        let g = |x: f64| 9.81 * x.cos();
        text.push_str(&format!("{a},{b},{},{}\n", 3.0 * g(a) + g(a + b), g(a + b)));
    }
    let samples = write(dir.path(), "static.csv", &text);
    let json = dir.path().join("static.json");
    let o = robid(&[
        "identify",
        "tests/fixtures/two_link.toml",
        "--static",
        samples.to_str().unwrap(),
        "--json",
        json.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let path = out(&dir, "f.toml");
    let o = robid(&[
        "feasible",
        "tests/fixtures/two_link.toml",
        "--identified",
        json.to_str().unwrap(),
        "-o",
        path.to_str().unwrap(),
    ]);
    fails_with(
        &o,
        &[
            "static.json: a result of static samples (`robid identify --static`, gravity)",
            "feasible needs every base parameter",
        ],
    );
    assert!(
        !stderr(&o).contains("same robot description"),
        "{}",
        stderr(&o)
    );
    assert!(!path.exists());
}

/// Noise-free simulated UR5e data identified to deviations near 1e-11: the Cholesky fit
/// crawls and stops short in what only the default prior decides (reported by a review:
/// masses 0.9 kg off the interior-point optimum, nothing said). `--method cholesky` now
/// checks its result against the interior-point optimum and warns, naming both objectives
/// and the value that differs most (measured: 0.02418 against 0.01798, `M3` 4.955 against
/// 4.054); the default method says nothing of the kind.
#[test]
fn feasible_cholesky_says_where_it_stopped_short() {
    let dir = folder();
    let path = |name: &str| out(&dir, name).to_str().unwrap().to_string();
    let (trajectory, data, identified) = (path("traj.csv"), path("sim.csv"), path("id.json"));
    for args in [
        vec![
            "excite",
            "descriptions/ur5e.toml",
            "--duration",
            "10",
            "--rate",
            "100",
        ],
        vec![
            "simulate",
            "descriptions/ur5e.toml",
            "--parameters",
            "parameters/ur5e.toml",
        ],
        vec![
            "identify",
            "descriptions/ur5e.toml",
            "--data",
            &data,
            "--json",
            &identified,
        ],
    ] {
        let mut args = args.clone();
        match args[0] {
            "excite" => args.extend(["-o", &trajectory]),
            "simulate" => args.extend(["--trajectory", &trajectory, "-o", &data]),
            _ => {}
        }
        let o = robid(&args);
        assert!(o.status.success(), "{}", stderr(&o));
    }
    for (method, warned) in [("cholesky", true), ("interior-point", false)] {
        let output = path(&format!("{method}.toml"));
        let o = robid(&[
            "feasible",
            "descriptions/ur5e.toml",
            "--identified",
            &identified,
            "--method",
            method,
            "-o",
            &output,
        ]);
        let text = stderr(&o);
        assert!(o.status.success(), "{text}");
        assert_eq!(
            text.contains("warning: the cholesky fit stopped short of the optimum"),
            warned,
            "{method}: {text}"
        );
        assert!(Path::new(&output).exists(), "{method}: nothing written");
    }
}
