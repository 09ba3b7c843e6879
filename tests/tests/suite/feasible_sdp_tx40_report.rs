//! The SDP against the other feasible methods on the TX40's identification report
//! (`robots/tests/fixtures/tx40_identified.json`, written by `robid identify
//! configs/tx40_robot.toml --config configs/tx40.toml --json` on the real log: 61
//! parameters including the coupled wrist's extra columns `Iam6 fvm6 fsm6`), with the
//! loose bounds of `robots/tests/fixtures/tx40_bounds.toml` and the problem `robid
//! feasible` builds (`robots::extraction::problem`, the extra columns as free terms). The
//! command line's own tests run the other methods on the same files; these need the `sdp`
//! feature, and here they need no build of the `robid` binary.

#![cfg(feature = "sdp")]

use std::path::{Path, PathBuf};

use robid_runtime::data::ParameterFile;
use robid_runtime::feasible::{
    AnnealOptions, Bounds, Prior, Problem, SdpOptions, SmoothOptions, Solution, solve_anneal,
    solve_interior, solve_sdp, solve_smooth,
};
use robid_symbolic::Robot;

/// The default prior's weight in `robid feasible` (its `--prior-weight` without `--prior`).
const DEFAULT_PRIOR_WEIGHT: f64 = 1e-2;

fn repo(p: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..").join(p)
}

/// The extraction problem of the report, as `robid feasible` sets it up.
fn problem() -> Problem {
    let robot = Robot::from_file(&repo("robots/configs/tx40_robot.toml")).unwrap();
    let problem = robots::extraction::problem(&robot).unwrap();
    let text = std::fs::read_to_string(repo("robots/tests/fixtures/tx40_identified.json")).unwrap();
    let report: serde_json::Value = serde_json::from_str(&text).unwrap();
    let entries = report["parameters"].as_array().unwrap();
    let field = |e: &serde_json::Value, key: &str| e[key].as_f64().unwrap();
    let names: Vec<String> = entries
        .iter()
        .map(|e| e["name"].as_str().unwrap().to_owned())
        .collect();
    let extra: Vec<String> = entries
        .iter()
        .filter(|e| e["expression"].as_str().unwrap_or("").is_empty())
        .map(|e| e["name"].as_str().unwrap().to_owned())
        .filter(|n| !problem.base_names.contains(n))
        .collect();
    assert_eq!(extra, ["Iam6", "fvm6", "fsm6"]);
    let values: Vec<f64> = entries.iter().map(|e| field(e, "value")).collect();
    let std: Vec<f64> = entries.iter().map(|e| field(e, "std")).collect();
    problem
        .with_extra_columns(&extra)
        .unwrap()
        .with_identified(&names, &values, &std)
        .unwrap()
}

fn bounds(problem: &Problem) -> Bounds {
    let path = repo("robots/tests/fixtures/tx40_bounds.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    Bounds::from_toml(&text, "bounds", problem.layout.links.len()).unwrap()
}

/// The SDP with the default prior of solid links at `weight` (or with `prior`, the default
/// prior then at its default weight), as `robid feasible --method sdp` solves it.
fn sdp(problem: &Problem, prior: Option<Prior>, weight: f64) -> Solution {
    let options = SdpOptions {
        prior,
        regularization: weight,
    };
    solve_sdp(problem, &bounds(problem), &options, &robid_sdp::Clarabel).unwrap()
}

/// On the real log the pure-Rust methods reach the SDP's optimum: chi^2 within 1e-3
/// relative, with the data alone (weight 1e-6) and with the default prior (0.01; its
/// optimum lies on the boundary of the consistent set).
#[test]
fn pure_rust_methods_equal_sdp_on_the_tx40_report() {
    let problem = problem();
    let b = bounds(&problem);
    for weight in [1e-6, DEFAULT_PRIOR_WEIGHT] {
        let reference = sdp(&problem, None, weight);
        let options = SmoothOptions {
            default_weight: weight,
            ..SmoothOptions::default()
        };
        for s in [
            solve_interior(&problem, &b, &options).unwrap(),
            solve_smooth(&problem, &b, &options).unwrap(),
        ] {
            eprintln!(
                "weight {weight}: {} chi^2 {:.5}, sdp {:.5}",
                s.method.name(),
                s.chi2,
                reference.chi2
            );
            assert!(
                (s.chi2 - reference.chi2).abs() <= 1e-3 * reference.chi2,
                "weight {weight}: {} {}, sdp {}",
                s.method.name(),
                s.chi2,
                reference.chi2
            );
        }
    }
}

/// The SDP's global optimum fits at least as well as the stochastic search, whose
/// feasible set is smaller (it also bounds the principal moments); both with the data
/// alone, as the search has no default prior.
#[test]
fn sdp_fits_the_tx40_report_at_least_as_well_as_anneal() {
    let problem = problem();
    let optimum = sdp(&problem, None, 1e-6);
    let search = solve_anneal(&problem, &bounds(&problem), &AnnealOptions::default()).unwrap();
    eprintln!("sdp chi^2 {}, anneal {}", optimum.chi2, search.chi2);
    assert!(
        optimum.chi2 <= search.chi2 * (1.0 + 1e-6),
        "sdp {}, anneal {}",
        optimum.chi2,
        search.chi2
    );
    assert!(optimum.min_eigenvalues.iter().all(|&e| e > 0.0));
}

/// With the CAD values of `robots/parameters/tx40.toml` as a prior at the command line's
/// default weight with `--prior` (`Prior::DEFAULT_WEIGHT`, 100: each link trusted to 10 %
/// of its own values), the masses the data barely determine move towards CAD while every
/// base parameter stays within 3 standard deviations of its identified value, as the
/// interior-point method through `robid feasible`. Measured (sum |m - m_CAD| without ->
/// with the prior; chi^2; max |z|): 27.94 -> 0.361 kg (ratio 0.013), 15.38 -> 75.05,
/// 2.34 -> 2.85; bound 2x the ratio. (At the old default, weight 1 on the solids' scales:
/// 2.25 kg, chi^2 17.5; weight 1 on the links' own scales: 1.75 kg, chi^2 32.7.)
#[test]
fn sdp_prior_pulls_the_free_directions_towards_cad() {
    let problem = problem();
    let cad = [10.5, 3.6, 4.07, 3.62, 1.02, 0.2];
    let distance = |s: &Solution| -> f64 {
        s.links
            .iter()
            .zip(&cad)
            .map(|(l, m)| (l.as_ref().unwrap().mass - m).abs())
            .sum()
    };
    let file = ParameterFile::read(Path::new(&repo("robots/parameters/tx40.toml"))).unwrap();
    let prior = Prior {
        standard: file.prior(&problem.standard_names).unwrap(),
        weight: Prior::DEFAULT_WEIGHT,
    };
    let plain = sdp(&problem, None, DEFAULT_PRIOR_WEIGHT);
    let pulled = sdp(&problem, Some(prior), DEFAULT_PRIOR_WEIGHT);
    let (d0, d1) = (distance(&plain), distance(&pulled));
    eprintln!(
        "sum |m - m_CAD|: without prior {d0:.3} kg, with prior {d1:.3} kg; chi^2 {:.3} -> {:.3}; \
         max |z| {:.3} -> {:.3}",
        plain.chi2,
        pulled.chi2,
        plain.max_normalized_residual(),
        pulled.max_normalized_residual()
    );
    assert!(d1 < 0.026 * d0, "without prior {d0}, with prior {d1}");
    let z = pulled.max_normalized_residual();
    assert!(
        z <= 3.0,
        "max |z| {z}, chi^2 {} against {}",
        pulled.chi2,
        plain.chi2
    );
}
