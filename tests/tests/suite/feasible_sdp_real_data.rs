//! Acceptance (issue 7) on real data: physically consistent parameters of the Staubli TX40
//! (FIGAROH log, train rows 0-24750, predict rows 29250-45000 as in `identify_tx40.rs`) and
//! of the KUKA LWR4+ (FloBaRoID runs, train run 1, predict run 2 as in `identify_lwr4.rs`).
//!
//! For each robot: the unconstrained OLS fit, then two physically consistent fits, both
//! solved as semidefinite programs (pseudo-inertia LMIs):
//!
//! - `projection`: the SDP projection of the identified base parameters, weighted by their
//!   full covariance sigma^2 (W'W)^-1;
//! - `consistent least squares`: the same constraints directly on ||W K p - y||.
//!
//! Asserted: the feasible parameters predict the held-out torques with a relative error at
//! most 10 % (relative) above the unconstrained fit's, every link's pseudo-inertia is
//! positive definite, and the mass, centre-of-mass and total-mass bounds hold. The bounds
//! are loose, from the robot's catalogue weight (TX40 27 kg, LWR4+ 16 kg, fixed base
//! included): every link 0.05 kg to the whole weight, the moving links together between
//! half the weight and the weight, centres of mass within the arm's reach.

#![cfg(feature = "sdp")]

use std::path::PathBuf;

use nalgebra::{DMatrix, DVector};
use robid_runtime::Model;
use robid_runtime::data::{Config, Dataset, load, load_config_files};
use robid_runtime::drive::{ExtraColumn, ExtraTerm, TermSignal};
use robid_runtime::estimate::Observation;
use robid_runtime::feasible::{
    Bounds, LinkBounds, Problem, SdpOptions, Solution, consistent_least_squares, solve_sdp,
};
use robid_runtime::pipeline::{estimate, observation, observe, prepare};
use robid_runtime::validate::Prediction;
use robid_sdp::Clarabel;
use robots::interpreted::{Chosen, model_for};

fn repo(p: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..").join(p)
}

fn chosen(description: &str) -> Chosen {
    let text = std::fs::read_to_string(repo(description)).unwrap();
    let robot = robid_symbolic::Robot::from_toml(&text, description).unwrap();
    model_for(&robot).unwrap()
}

/// Loose bounds from the catalogue weight `weight` (kg) and the reach `reach` (m).
fn bounds(links: usize, weight: f64, reach: f64) -> Bounds {
    Bounds {
        links: vec![
            LinkBounds {
                mass: [0.05, weight],
                com: [[-reach, reach]; 3],
                inertia: [0.0, 0.5 * weight * reach * reach],
                tensor: [None; 6],
            };
            links
        ],
        total_mass: Some([0.5 * weight, weight]),
        margin: Some(1e-6),
    }
}

/// The covariance sigma^2 (W'W)^-1 of the OLS estimate `beta` (through the QR of W).
fn covariance(obs: &Observation, beta: &DVector<f64>) -> DMatrix<f64> {
    let (rows, cols) = obs.w.shape();
    let sigma2 = (&obs.y - &obs.w * beta).norm_squared() / (rows - cols) as f64;
    let r = obs.w.clone().qr().r();
    let r_inv = r
        .solve_upper_triangular(&DMatrix::identity(cols, cols))
        .expect("W has full column rank");
    (&r_inv * r_inv.transpose()) * sigma2
}

/// The feasible-parameter problem of `model` with the observation's extra columns.
fn problem(model: &dyn Model, obs: &Observation) -> Problem {
    let problem = Problem::from_model(model).unwrap();
    let nb = problem.base_names.len();
    assert_eq!(problem.base_names[..], obs.names[..nb]);
    problem.with_extra_columns(&obs.names[nb..]).unwrap()
}

/// Held-out relative errors: unconstrained, SDP projection, consistent least squares.
struct Figures {
    unconstrained: f64,
    projection: f64,
    least_squares: f64,
}

fn relative_error(obs: &Observation, base: &[f64], dt: f64) -> f64 {
    Prediction::new(obs, base, dt).unwrap().fit().relative_error
}

fn check(label: &str, s: &Solution, bounds: &Bounds) {
    for (j, e) in s.min_eigenvalues.iter().enumerate() {
        assert!(
            *e > 0.0,
            "{label}: link {} pseudo-inertia min eigenvalue {e}",
            j + 1
        );
        assert!(s.links[j].is_some(), "{label}: link {} has no mass", j + 1);
    }
    // The SDP cannot impose the non-convex upper bound on the principal moments; the rest holds.
    let hard: Vec<_> = s
        .violations
        .iter()
        .filter(|v| !v.contains("principal moment"))
        .collect();
    assert!(hard.is_empty(), "{label}: {hard:?}");
    let total: f64 = s.links.iter().flatten().map(|l| l.mass).sum();
    let range = bounds.total_mass.unwrap();
    assert!(
        total >= range[0] - 1e-6 && total <= range[1] + 1e-6,
        "{label}: total mass {total}"
    );
}

/// Unconstrained fit, covariance-weighted projection and consistent least squares on
/// `train` (each checked for consistency), then each predicting every `held_out` set.
fn compare(
    label: &str,
    model: &dyn Model,
    train: &Observation,
    held_out: &[(&str, &Observation)],
    dt: f64,
    config: &Config,
    bounds: &Bounds,
) -> Vec<Figures> {
    let e = estimate(train, config).unwrap();
    let cov = covariance(train, &e.beta());
    let p = problem(model, train)
        .with_covariance(e.values.as_slice(), &cov)
        .unwrap();
    let projection = solve_sdp(&p, bounds, &SdpOptions::default(), &Clarabel).unwrap();
    check(&format!("{label} projection"), &projection, bounds);
    let least_squares = consistent_least_squares(
        &p,
        &train.w,
        &train.y,
        bounds,
        &SdpOptions::default(),
        &Clarabel,
    )
    .unwrap();
    check(&format!("{label} least squares"), &least_squares, bounds);
    println!(
        "{label}: {} equations, {} parameters; unconstrained OLS: train {:.2} %",
        train.rows(),
        train.cols(),
        100.0 * relative_error(train, &e.values, dt)
    );
    for (name, s) in [
        ("SDP projection", &projection),
        ("consistent least squares", &least_squares),
    ] {
        let total: f64 = s.links.iter().flatten().map(|l| l.mass).sum();
        println!(
            "{label} {name}: train {:.2} %, chi^2 {:.3e} over {} base parameters, max |z| {:.2}, smallest pseudo-inertia eigenvalue {:.2e}, moving mass {total:.2} kg, {:.3} s",
            100.0 * relative_error(train, &s.base, dt),
            s.chi2,
            s.base.len(),
            s.max_normalized_residual(),
            s.min_eigenvalues
                .iter()
                .copied()
                .fold(f64::INFINITY, f64::min),
            s.seconds
        );
        if !s.violations.is_empty() {
            println!("  reported: {:?}", s.violations);
        }
    }
    held_out
        .iter()
        .map(|(name, obs)| {
            let f = Figures {
                unconstrained: relative_error(obs, &e.values, dt),
                projection: relative_error(obs, &projection.base, dt),
                least_squares: relative_error(obs, &least_squares.base, dt),
            };
            println!(
                "{label} {name}: held-out relative error unconstrained {:.2} %, SDP projection {:.2} % ({:+.1} % relative), consistent least squares {:.2} % ({:+.1} % relative)",
                100.0 * f.unconstrained,
                100.0 * f.projection,
                100.0 * (f.projection / f.unconstrained - 1.0),
                100.0 * f.least_squares,
                100.0 * (f.least_squares / f.unconstrained - 1.0),
            );
            f
        })
        .collect()
}

/// Both feasible fits predict at most `factor` times the unconstrained fit's error.
fn assert_at_most(label: &str, f: &Figures, factor: f64) {
    for (name, e) in [
        ("SDP projection", f.projection),
        ("consistent least squares", f.least_squares),
    ] {
        assert!(
            e <= factor * f.unconstrained,
            "{label} {name}: held-out relative error {e} above {factor} x the unconstrained {}",
            f.unconstrained
        );
    }
}

/// The TX40 observation of rows `a..b` (the margin workaround of `identify_tx40.rs`: filter
/// and differentiate inside the gap between the two parts, cut the margin before the
/// regressor).
fn tx40_rows(chosen: &Chosen, data: &Dataset, config: &Config, a: usize, b: usize) -> Observation {
    const MARGIN: usize = 1000;
    let lo = a.saturating_sub(MARGIN);
    let data = data.slice(lo, b + MARGIN).unwrap();
    let mut p = prepare(&data, config).unwrap();
    let trim = config.processing.trim;
    let (s, e) = (
        (a - lo).saturating_sub(trim),
        (b - lo - trim).min(p.samples()),
    );
    for v in [&mut p.q, &mut p.qd, &mut p.qdd, &mut p.tau] {
        *v = v.range(s..e);
    }
    observe(chosen.model.as_ref(), &p, config).unwrap()
}

#[test]
fn tx40_feasible_parameters_predict_held_out_rows_within_ten_percent_of_unconstrained() {
    let chosen = chosen("robots/configs/tx40_robot.toml");
    let config = Config::from_file(repo("robots/configs/tx40.toml")).unwrap();
    let data = load_config_files(&config, 6).unwrap();
    let train = tx40_rows(&chosen, &data, &config, 0, 24750);
    let held_out = tx40_rows(&chosen, &data, &config, 29250, 45000);
    let dt = 100.0 / 5000.0;
    let model = chosen.model.as_ref();
    let b = bounds(model.dof(), 27.0, 0.6);
    let f = compare(
        "TX40",
        model,
        &train,
        &[("rows 29250-45000", &held_out)],
        dt,
        &config,
        &b,
    );
    assert_at_most("TX40", &f[0], 1.1);
}

/// The LWR4 fit with the README's model (rigid body, Fv, Fc, Fo) is physically impossible:
/// ZZR1 = -1.02 +- 0.03 and ZZ7 = -0.21 +- 0.005 kg m^2, and the feasible parameters then
/// predict run 2 12.5 % (relative) worse. Negative inertia on a joint without gravity load
/// is the signature of a torque proportional to position (for motion at frequency w,
/// k q = -(k / w^2) qdd): a torsion spring, e.g. the cables through joints 1 and 7. With a
/// spring column K_j q_j on joints 1 and 7, ZZR1 = 0.73 and ZZ7 = 0.007 become physical,
/// K1 = 0.46 and K7 = 0.22 N m/rad, and every run is predicted better (run 2 1.97 % against
/// 2.03 %, run 3 11.96 % against 13.1 %). Asserted with that model: run 2 within 10 %
/// (relative) of the unconstrained fit (measured +6.8 %), run 3 at most 0.6 times the
/// unconstrained error (measured 6.07 % against 11.96 %).
#[test]
fn lwr4_feasible_parameters_within_ten_percent_on_run2_and_better_on_run3() {
    let chosen = chosen("robots/configs/lwr4_robot.toml");
    let mut config = Config::from_file(repo("robots/configs/lwr4.toml")).unwrap();
    // joint torsion springs (see above)
    for j in [1, 7] {
        config.extra_columns.push(ExtraColumn {
            name: format!("K{j}"),
            terms: vec![ExtraTerm {
                row: j,
                signal: TermSignal::Q,
                joints: vec![j],
                coefficient: 1.0,
            }],
        });
    }
    let model = chosen.model.as_ref();
    let run1 = load_config_files(&config, 7).unwrap();
    let (train, dt) = observation(model, &run1, &config).unwrap();
    let run = |k: usize| {
        let file = repo(&format!("data/kuka_lwr4/data/measurements_{k}.csv.gz"));
        let d = load(&config, &[file], 7).unwrap();
        observation(model, &d, &config).unwrap().0
    };
    let (run2, run3) = (run(2), run(3));
    let b = bounds(model.dof(), 16.0, 0.8);
    let f = compare(
        "LWR4",
        model,
        &train,
        &[("run 2", &run2), ("run 3", &run3)],
        dt,
        &config,
        &b,
    );
    assert_at_most("LWR4 run 2", &f[0], 1.1);
    assert_at_most("LWR4 run 3", &f[1], 0.6);
}
