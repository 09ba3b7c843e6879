//! `robid feasible ROBOT.toml --identified RESULT.json [--bounds BOUNDS.toml]
//! [--method sdp|anneal] [--prior CAD.toml [--prior-weight W]] -o OUT`: physically
//! consistent link parameters that reproduce identified base parameters (DESIGN.md 7, 10). Writes OUT as TOML, or as URDF
//! `<inertial>` elements when OUT ends in `.urdf` or `.xml`. Identified parameters with an
//! empty expression that are not base parameters of the description (the extra columns of
//! an identification config) are kept as free terms.

use std::path::{Path, PathBuf};

use robid_runtime::feasible::{
    AnnealOptions, Bounds, Prior, Problem, SdpOptions, solve_anneal, solve_sdp, to_toml, to_urdf,
};
use robid_symbolic::{Derivation, Robot};
use serde::Deserialize;

use super::Error;
use super::parameters::standard_parameters;

/// Arguments of `robid feasible`.
#[derive(Debug, clap::Args)]
pub(crate) struct Args {
    /// The robot description (TOML).
    robot: PathBuf,
    /// The identification result (JSON of `robid identify`: parameters with name, value, std).
    #[arg(long)]
    identified: PathBuf,
    /// Bounds on masses, centres of mass, inertias and the total mass (TOML).
    #[arg(long)]
    bounds: Option<PathBuf>,
    /// `sdp` (convex, global optimum) or `anneal` (Gaz et al. global search).
    #[arg(long, default_value = "sdp")]
    method: String,
    /// Prior standard parameters, e.g. CAD values (a parameter file with a `[standard]`
    /// table; parameters it does not list have no prior). `--method sdp` only.
    #[arg(long)]
    prior: Option<PathBuf>,
    /// Weight of the pull towards the prior: a deviation of one parameter scale (from the
    /// bounds, e.g. the largest mass) costs this many chi^2 units. The default 1 settles
    /// what the data barely determine and leaves what they determine; 100 overrides data.
    #[arg(long, default_value_t = 1.0)]
    prior_weight: f64,
    /// Output file: TOML, or URDF inertial elements for a `.urdf` / `.xml` name.
    #[arg(short, long)]
    output: PathBuf,
}

#[derive(Deserialize)]
struct Identified {
    parameters: Vec<IdentifiedParameter>,
}

#[derive(Deserialize)]
struct IdentifiedParameter {
    name: String,
    #[serde(default)]
    expression: String,
    value: f64,
    std: f64,
}

fn read(path: &Path) -> Result<String, Error> {
    std::fs::read_to_string(path)
        .map_err(|e| format!("{}: cannot read: {e}", path.display()).into())
}

/// Runs the subcommand.
pub(crate) fn run(args: &Args) -> Result<(), Error> {
    let robot = Robot::from_toml(&read(&args.robot)?, &args.robot.display().to_string())?;
    let json = read(&args.identified)?;
    let identified: Identified = serde_json::from_str(&json)
        .map_err(|e| format!("{}: not an identification result: {e}; expected {{\"parameters\": [{{\"name\", \"value\", \"std\"}}]}}", args.identified.display()))?;
    let problem = problem(&robot)?;
    // Extra columns of the identification config (no expression, not a base parameter,
    // e.g. a coupled wrist's `Iam6`) are kept as free terms.
    let extra: Vec<String> = identified
        .parameters
        .iter()
        .filter(|p| p.expression.is_empty() && !problem.base_names.contains(&p.name))
        .map(|p| p.name.clone())
        .collect();
    let problem = problem.with_extra_columns(&extra)?;
    let names: Vec<String> = identified
        .parameters
        .iter()
        .map(|p| p.name.clone())
        .collect();
    let values: Vec<f64> = identified.parameters.iter().map(|p| p.value).collect();
    let std: Vec<f64> = identified.parameters.iter().map(|p| p.std).collect();
    let problem = problem.with_identified(&names, &values, &std)?;
    let links = problem.layout.links.len();
    let bounds = match &args.bounds {
        Some(path) => Bounds::from_toml(&read(path)?, &path.display().to_string(), links)?,
        None => Bounds::wide(links),
    };
    let prior = match &args.prior {
        Some(path) => Some(Prior {
            standard: standard_parameters(path, &problem.standard_names)?,
            weight: args.prior_weight,
        }),
        None => None,
    };
    if !(args.prior_weight.is_finite() && args.prior_weight >= 0.0) {
        return Err(format!(
            "--prior-weight {}: must be a finite number >= 0",
            args.prior_weight
        )
        .into());
    }
    let solution = match args.method.as_str() {
        "sdp" => solve_sdp(
            &problem,
            &bounds,
            &SdpOptions {
                prior,
                ..SdpOptions::default()
            },
        )?,
        "anneal" if prior.is_some() => {
            return Err(
                "--prior: only --method sdp uses a prior; drop --prior or use --method sdp".into(),
            );
        }
        "anneal" => solve_anneal(&problem, &bounds, &AnnealOptions::default())?,
        other => return Err(format!("--method {other}: unknown; use sdp or anneal").into()),
    };
    let urdf = matches!(
        args.output.extension().and_then(|e| e.to_str()),
        Some("urdf" | "xml")
    );
    let text = if urdf {
        to_urdf(&solution, robot.name())
    } else {
        to_toml(&solution, robot.name())
    };
    std::fs::write(&args.output, text)
        .map_err(|e| format!("{}: cannot write: {e}", args.output.display()))?;
    eprintln!(
        "{}: chi^2 {:.3e}, max |z| {:.3}, smallest pseudo-inertia eigenvalue {:.3e}, {:.3} s{}",
        solution.method.name(),
        solution.chi2,
        solution.max_normalized_residual(),
        solution
            .min_eigenvalues
            .iter()
            .copied()
            .fold(f64::INFINITY, f64::min),
        solution.seconds,
        if solution.violations.is_empty() {
            String::new()
        } else {
            format!("; bounds not met: {}", solution.violations.join("; "))
        }
    );
    Ok(())
}

/// K evaluated at the description's geometric values.
fn problem(robot: &Robot) -> Result<Problem, Error> {
    let mut derivation = Derivation::new(robot);
    let base = derivation.base_parameters()?;
    let mut pairs = Vec::new();
    for (name, value) in robot.symbols() {
        let v = value.ok_or_else(|| {
            format!("geometric symbol `{name}` has no value; give it one in the description")
        })?;
        pairs.push((name.as_str(), v));
    }
    let values = derivation.arena.values(&pairs);
    let mut k = vec![vec![0.0; base.standard.len()]; base.base.len()];
    for (b, bp) in base.base.iter().enumerate() {
        for &(s, c) in &bp.terms {
            k[b][s] = derivation
                .arena
                .eval(&[c], &values)
                .map_err(|e| format!("{e:?}"))?[0];
        }
    }
    let standard = base.standard.iter().map(|p| p.name.clone()).collect();
    let names = base.base.iter().map(|b| b.name.clone()).collect();
    Ok(Problem::from_rows(standard, names, &k)?)
}
