//! Prints fit (chi^2, max |z|) and time of the feasible-parameter methods on three problems:
//! the TX40 identified from its real log (train rows 0-24750, 61 base parameters with drive
//! terms and extra columns) and the simulated UR5e and Panda (`feasible_simulated.rs`'s
//! setup: 1 % noise on beta, CAD-like bounds around the truth). Methods: SDP projection of
//! the base parameters (`solve_sdp`), consistent least squares on the observation matrix
//! (`consistent_least_squares`; for the simulated robots, 300 random states with 1 % torque
//! noise), the interior-point and Cholesky fits with the SDP's weak pull
//! (`solve_interior`, `solve_smooth`) and the Gaz et al. search (`solve_anneal`, default
//! options). Nothing is asserted.
//!
//! `cargo run --release -p tests --features sdp --example feasible_timing`
//! (without `--features sdp` only the search runs).

use std::path::PathBuf;

use nalgebra::{DMatrix, DVector};
use robid_runtime::data::{Config, load_config_files};
use robid_runtime::estimate::Observation;
use robid_runtime::feasible::{
    AnnealOptions, Bounds, LinkBounds, LinkInertial, Problem, SmoothOptions, Solution,
    solve_anneal, solve_interior, solve_smooth,
};
use robid_runtime::pipeline::{estimate, observe, prepare};
use robid_runtime::rng::Rng;
use robid_symbolic::{Derivation, Drive};
use tests::reference::by_name;
use tests::state::{bind, random_state};

fn repo(p: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..").join(p)
}

fn report(label: &str, method: &str, s: &Solution) {
    println!(
        "{label:6} {method:26} chi^2 {:>10.4e}  max |z| {:>7.3}  min eig {:>9.2e}  {:>8.3} s {:>5} it  {}",
        s.chi2,
        s.max_normalized_residual(),
        s.min_eigenvalues
            .iter()
            .copied()
            .fold(f64::INFINITY, f64::min),
        s.seconds,
        s.iterations,
        if s.violations.is_empty() {
            String::new()
        } else {
            format!("(bounds not met: {})", s.violations.join("; "))
        }
    );
}

#[cfg(feature = "sdp")]
fn convex(label: &str, problem: &Problem, bounds: &Bounds, w: &DMatrix<f64>, y: &DVector<f64>) {
    use robid_runtime::feasible::{SdpOptions, consistent_least_squares, solve_sdp};
    use robid_sdp::Clarabel;
    let s = solve_sdp(problem, bounds, &SdpOptions::default(), &Clarabel).unwrap();
    report(label, "sdp projection", &s);
    let s =
        consistent_least_squares(problem, w, y, bounds, &SdpOptions::default(), &Clarabel).unwrap();
    report(label, "consistent least squares", &s);
}

#[cfg(not(feature = "sdp"))]
fn convex(label: &str, _: &Problem, _: &Bounds, _: &DMatrix<f64>, _: &DVector<f64>) {
    println!("{label:6} (sdp methods need --features sdp)");
}

fn run(label: &str, problem: &Problem, bounds: &Bounds, w: &DMatrix<f64>, y: &DVector<f64>) {
    println!(
        "{label}: {} base parameters, {} standard parameters, {} equations",
        problem.base_names.len(),
        problem.standard_names.len(),
        w.nrows()
    );
    convex(label, problem, bounds, w, y);
    // the SDP's problem: the same weak pull (1e-6)
    let smooth = SmoothOptions {
        default_weight: 1e-6,
        ..SmoothOptions::default()
    };
    let s = solve_interior(problem, bounds, &smooth).unwrap();
    report(label, "interior-point", &s);
    let s = solve_smooth(problem, bounds, &smooth).unwrap();
    report(label, "cholesky", &s);
    let s = solve_anneal(problem, bounds, &AnnealOptions::default()).unwrap();
    report(label, "anneal (8 restarts)", &s);
}

/// The TX40 training rows 0-24750 (the margin workaround of `identify_tx40.rs`).
fn tx40() {
    let text = std::fs::read_to_string(repo("robots/configs/tx40_robot.toml")).unwrap();
    let robot = robid_symbolic::Robot::from_toml(&text, "tx40_robot.toml").unwrap();
    let chosen = robots::interpreted::model_for(&robot).unwrap();
    let config = Config::from_file(repo("robots/configs/tx40.toml")).unwrap();
    let data = load_config_files(&config, 6).unwrap();
    let (a, b, margin) = (0, 24750, 1000);
    let data = data.slice(a, b + margin).unwrap();
    let mut p = prepare(&data, &config).unwrap();
    let trim = config.processing.trim;
    let end = (b - trim).min(p.samples());
    for v in [&mut p.q, &mut p.qd, &mut p.qdd, &mut p.tau] {
        *v = v.range(0..end);
    }
    let obs: Observation = observe(chosen.model.as_ref(), &p, &config).unwrap();
    let e = estimate(&obs, &config).unwrap();
    let (rows, cols) = obs.w.shape();
    let sigma2 = (&obs.y - &obs.w * e.beta()).norm_squared() / (rows - cols) as f64;
    let r_inv = obs
        .w
        .clone()
        .qr()
        .r()
        .solve_upper_triangular(&DMatrix::identity(cols, cols))
        .unwrap();
    let cov = (&r_inv * r_inv.transpose()) * sigma2;
    let problem = Problem::from_model(chosen.model.as_ref()).unwrap();
    let nb = problem.base_names.len();
    let problem = problem
        .with_extra_columns(&obs.names[nb..])
        .unwrap()
        .with_covariance(&e.values, &cov)
        .unwrap();
    let bounds = Bounds {
        links: vec![
            LinkBounds {
                mass: [0.05, 27.0],
                com: [[-0.6, 0.6]; 3],
                inertia: [0.0, 5.0],
                tensor: [None; 6],
            };
            6
        ],
        total_mass: Some([13.5, 27.0]),
        margin: Some(1e-6),
    };
    run("TX40", &problem, &bounds, &obs.w, &obs.y);
}

/// A simulated robot as in `feasible_simulated.rs` (UR5e, Panda), with an observation
/// matrix of 300 random states for consistent least squares.
fn simulated(name: &str, label: &str) {
    let reference = by_name(name);
    let robot = reference.robot().with_drive(Drive::NONE);
    let truth = reference.parameter_values(&robot);
    let mut derivation = Derivation::new(&robot);
    let base = derivation.base_parameters().unwrap();
    let mut rng = Rng::from_state(0xFEA5);
    let state = random_state(&robot, &mut rng);
    let values = bind(&mut derivation.arena, &robot, &state, None);
    let ns = base.standard.len();
    let nb = base.base.len();
    let mut k = DMatrix::zeros(nb, ns);
    for (b, bp) in base.base.iter().enumerate() {
        for &(s, c) in &bp.terms {
            k[(b, s)] = derivation.arena.eval(&[c], &values).unwrap()[0];
        }
    }
    let exact = &k * DVector::from_column_slice(&truth);
    let std: Vec<f64> = exact.iter().map(|v| 0.01 * v.abs() + 1e-4).collect();
    let beta: Vec<f64> = exact
        .iter()
        .zip(&std)
        .map(|(v, s)| v + s * rng.uniform(-1.0, 1.0))
        .collect();
    let problem = Problem::new(
        base.standard.iter().map(|p| p.to_string()).collect(),
        base.base.iter().map(|b| b.name.to_string()).collect(),
        k,
    )
    .unwrap()
    .with_target(&beta, &std)
    .unwrap();
    let layout = &problem.layout;
    let mut total = 0.0;
    let links = (0..layout.links.len())
        .map(|j| {
            let link = LinkInertial::from_standard(&layout.link_values(j, &truth)).unwrap();
            total += link.mass;
            LinkBounds {
                mass: [0.0, 2.0 * link.mass + 1.0],
                com: link.com.map(|c| [c - 0.15, c + 0.15]),
                inertia: [0.0, 2.0 * link.principal_moments()[2] + 0.01],
                tensor: [None; 6],
            }
        })
        .collect();
    let bounds = Bounds {
        links,
        total_mass: Some([0.9 * total, 1.1 * total]),
        margin: Some(1e-7),
    };
    // W: the base regressor at 300 random states; y = W beta_true + 1 % noise.
    let n = robot.dof();
    let columns: Vec<_> = base.columns.iter().flatten().copied().collect();
    let states = 300;
    let mut w = DMatrix::zeros(states * n, nb);
    for s in 0..states {
        let state = random_state(&robot, &mut rng);
        let values = bind(&mut derivation.arena, &robot, &state, None);
        let yb = derivation.arena.eval(&columns, &values).unwrap();
        for i in 0..n {
            for b in 0..nb {
                w[(s * n + i, b)] = yb[b * n + i];
            }
        }
    }
    let clean = &w * &exact;
    let y = clean.map(|v| v + 0.01 * v.abs() * rng.uniform(-1.0, 1.0));
    run(label, &problem, &bounds, &w, &y);
}

fn main() {
    let profile = if cfg!(debug_assertions) {
        "dev"
    } else {
        "release"
    };
    println!("profile: {profile}");
    tx40();
    simulated("ur5e", "UR5e");
    simulated("panda", "Panda");
}
