//! The README's command sequence end to end (excite, simulate, identify, feasible with the
//! default method and bounds), on a modified-DH cobot (UR5e, no drive terms) and a
//! standard-DH industrial arm with rotor inertias and friction (KUKA KR 6 R900): the link
//! parameters a user gets are plausible, not only consistent.

use crate::common;

use std::collections::BTreeMap;
use std::path::Path;

use common::{folder, robid, stderr};

/// The standard parameters of a parameter file or a `robid feasible` TOML output.
fn standard(path: &Path) -> BTreeMap<String, f64> {
    let text = std::fs::read_to_string(path).unwrap();
    let v: toml::Value = toml::from_str(&text).unwrap();
    v["standard"]
        .as_table()
        .unwrap()
        .iter()
        .map(|(k, x)| {
            (
                k.clone(),
                x.as_float().or(x.as_integer().map(|i| i as f64)).unwrap(),
            )
        })
        .collect()
}

/// What one run of `robid feasible` gave.
struct Feasible {
    /// Standard parameters.
    standard: BTreeMap<String, f64>,
    /// Per link: mass and centre of mass.
    links: Vec<(f64, [f64; 3])>,
    /// chi^2 and the number of base parameters, from the output's header.
    chi2: f64,
    base: usize,
    /// Standard error of the run.
    stderr: String,
}

/// Runs `robid` with `args` and asserts it succeeds.
fn run(args: &[&str]) -> String {
    let o = robid(args);
    let err = stderr(&o);
    assert!(o.status.success(), "robid {args:?}: {err}");
    err
}

/// excite -> simulate (torque noise 0.2 N m, an encoder of 1e-5 rad, positions and
/// torques only, as a real log) -> identify (WLS: differentiated, cutoff "auto") in `dir`;
/// returns the identification JSON.
fn identify(dir: &Path, robot: &str, parameters: &str, excite: &[&str]) -> String {
    let path = |name: &str| dir.join(name).display().to_string();
    let (traj, data, result) = (path("traj.csv"), path("data.csv"), path("result.json"));
    let mut args = vec!["excite", robot, "-o", &traj];
    args.extend_from_slice(excite);
    run(&args);
    run(&[
        "simulate",
        robot,
        "--parameters",
        parameters,
        "--trajectory",
        &traj,
        "--torque-noise",
        "0.2",
        "--quantization",
        "1e-5",
        "--columns",
        "positions",
        "-o",
        &data,
    ]);
    run(&[
        "identify", robot, "--data", &data, "--method", "wls", "--json", &result,
    ]);
    result
}

/// `robid feasible robot --identified result [extra] -o dir/name`.
fn feasible(dir: &Path, robot: &str, result: &str, name: &str, extra: &[&str]) -> Feasible {
    let out = dir.join(name);
    let mut args = vec![
        "feasible",
        robot,
        "--identified",
        result,
        "-o",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let stderr = run(&args);
    let text = std::fs::read_to_string(&out).unwrap();
    let header = text
        .lines()
        .find_map(|l| l.strip_prefix("# chi^2 = "))
        .expect("a chi^2 line");
    let mut words = header.split_whitespace();
    let chi2: f64 = words.next().unwrap().parse().unwrap();
    let base: usize = words.nth(1).unwrap().parse().unwrap();
    let v: toml::Value = toml::from_str(&text).unwrap();
    let links = v["links"]
        .as_array()
        .unwrap()
        .iter()
        .map(|l| {
            let com = l["com"].as_array().unwrap();
            (
                l["mass"].as_float().unwrap(),
                [0, 1, 2].map(|i| com[i].as_float().unwrap()),
            )
        })
        .collect();
    Feasible {
        standard: standard(&out),
        links,
        chi2,
        base,
        stderr,
    }
}

/// Plausible under the default bounds (masses in [0, 50] kg, centres of mass in a 2 m
/// box): every mass inside and away from its bounds (no value at a bound is reported),
/// every centre of mass in its box, and a fit within the noise (chi^2 at most the number
/// of base parameters).
fn plausible(label: &str, f: &Feasible) {
    assert!(
        !f.stderr.contains("at its lower bound") && !f.stderr.contains("at its upper bound"),
        "{label}: a value at a bound: {}",
        f.stderr
    );
    for (j, (m, c)) in f.links.iter().enumerate() {
        assert!(*m > 1e-3 && *m < 50.0, "{label}: link {} mass {m}", j + 1);
        assert!(
            c.iter().all(|x| x.abs() < 1.0),
            "{label}: link {} centre of mass {c:?}",
            j + 1
        );
    }
    assert!(
        f.chi2 <= f.base as f64,
        "{label}: chi^2 {} over {} base parameters",
        f.chi2,
        f.base
    );
}

/// UR5e: plausible with the default prior; with the truth as a firm prior (weight 100),
/// within 1 % of the truth (relative norm of the standard parameters; measured 0.48 %,
/// 2.5 % at the default weight 1, where the data's noise decides what they determine)
/// while still fitting the data within one std.
#[test]
fn ur5e_readme_sequence_gives_plausible_links_and_the_truth_with_the_truth_as_prior() {
    let dir = folder();
    let robot = "descriptions/ur5e.toml";
    let truth_file = "parameters/ur5e.toml";
    let result = identify(dir.path(), robot, truth_file, &["--drive", "Fv,Fc"]);
    let plain = feasible(dir.path(), robot, &result, "links.toml", &[]);
    plausible("ur5e", &plain);
    let pulled = feasible(
        dir.path(),
        robot,
        &result,
        "pulled.toml",
        &["--prior", truth_file, "--prior-weight", "100"],
    );
    plausible("ur5e with the truth as prior", &pulled);
    let truth = standard(&common::manifest().join(truth_file));
    let (mut d, mut t) = (0.0, 0.0);
    for (name, v) in &truth {
        d += (pulled.standard[name] - v).powi(2);
        t += v * v;
    }
    let relative = (d / t).sqrt();
    eprintln!(
        "ur5e: chi^2 {} (default prior), distance to the truth with it as prior {relative:.4}",
        plain.chi2
    );
    assert!(relative <= 0.01, "distance to the truth {relative}");
}

/// KUKA KR 6 R900 (standard DH, Ia, Fv, Fc on every joint): plausible, and every rotor
/// inertia within a factor 10 of the truth, also Ia1 and Ia2, which the data see only in
/// sums with link inertias (measured with the default interior-point method 0.515, 0.415,
/// 0.149, 0.040, 0.033, 0.022; with the Cholesky fit 0.508, 0.415, 0.149, 0.040, 0.033,
/// 0.022; the truth 0.45, 0.40, 0.15, 0.04, 0.035, 0.02).
#[test]
fn kr6_readme_sequence_gives_plausible_links_and_rotor_inertias() {
    let dir = folder();
    let robot = "descriptions/kr6r900.toml";
    let truth_file = "parameters/kr6r900.toml";
    let result = identify(dir.path(), robot, truth_file, &[]);
    let f = feasible(dir.path(), robot, &result, "links.toml", &[]);
    plausible("kr6r900", &f);
    let truth = standard(&common::manifest().join(truth_file));
    for j in 1..=6 {
        let name = format!("Ia{j}");
        let (got, want) = (f.standard[&name], truth[&name]);
        assert!(
            got >= want / 10.0 && got <= want * 10.0,
            "{name}: {got} against the truth's {want}"
        );
    }
}
