//! `robid identify ROBOT.toml --data FILE... [--config CFG.toml] [--validate FILE...]
//! [--method ols|wls|rls|energy] [--json OUT.json] [--plot DIR]`: base parameters with
//! their uncertainty from measured data, the fit, and predictions of other files
//! (DESIGN.md 6 and 10). A table on stdout; JSON and SVG plots on request.

use std::path::{Path, PathBuf};

use robid_runtime::data::{Config, Method, load};
use robid_runtime::pipeline::{identify, validate};
use robid_runtime::report::{Report, plot_torques, text_table};
use robid_symbolic::Robot;
use robots::interpreted::{Chosen, model_for};

use super::Error;

/// Arguments of `robid identify`.
#[derive(Debug, clap::Args)]
pub(crate) struct Args {
    /// Robot description file (TOML), with the drive terms to identify.
    robot: PathBuf,
    /// Data files, one per `[[source]]` of the config (CSV, optionally gzip).
    #[arg(long, num_args = 1.., required = true)]
    data: Vec<PathBuf>,
    /// Identification config (columns, units, drive chain, processing). Without it the
    /// data need the columns `t,q1..qn,qd1..qdn,qdd1..qddn,tau1..taun` (`robid simulate`).
    #[arg(long)]
    config: Option<PathBuf>,
    /// Files to predict with the identified parameters (as many per data set as --data).
    #[arg(long, num_args = 1..)]
    validate: Vec<PathBuf>,
    /// Estimator (overrides the config's `[estimation] method`).
    #[arg(long, value_enum)]
    method: Option<MethodArg>,
    /// Write the JSON report to this file.
    #[arg(long)]
    json: Option<PathBuf>,
    /// Write SVG plots of measured vs predicted torque per joint into this folder.
    #[arg(long)]
    plot: Option<PathBuf>,
}

/// The estimators of the command line.
#[derive(Debug, Clone, Copy, clap::ValueEnum)]
enum MethodArg {
    /// Ordinary least squares.
    Ols,
    /// Weighted least squares (per-joint weights from the OLS residuals).
    Wls,
    /// Recursive least squares (forgetting factor from the config).
    Rls,
    /// Energy (power-balance) model.
    Energy,
}

/// The config for data written by `robid simulate` (or any file with that header).
pub(crate) fn default_config() -> Config {
    let text = r#"
time_column = "t"
[[source]]
position = "q{}"
velocity = "qd{}"
acceleration = "qdd{}"
torque = "tau{}"
"#;
    Config::from_toml_str(text, Path::new("<default config>")).unwrap_or_default()
}

/// Reads a description and chooses its model (compiled or interpreted).
pub(crate) fn robot_model(path: &Path) -> Result<Chosen, Error> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("{}: cannot read: {e}", path.display()))?;
    let robot = Robot::from_toml(&text, &path.display().to_string())?;
    Ok(model_for(&robot, &text)?)
}

/// Runs the identification and prints the table.
pub(crate) fn run(args: &Args) -> Result<(), Error> {
    let chosen = robot_model(&args.robot)?;
    let model = chosen.model.as_ref();
    let mut config = match &args.config {
        Some(p) => Config::from_file(p)?,
        None => default_config(),
    };
    if let Some(m) = args.method {
        config.estimation.method = match m {
            MethodArg::Ols => Method::Ols,
            MethodArg::Wls => Method::Wls,
            MethodArg::Rls => Method::Rls,
            MethodArg::Energy => {
                return Err(
                    "--method energy: the energy model needs an energy regressor, which the \
                            compiled and interpreted models do not provide yet; use ols, wls or rls"
                        .into(),
                );
            }
        };
    }
    let per_set = config.sources.len().max(1);
    if args.data.len() != per_set {
        return Err(format!(
            "--data: {} files given, the config has {per_set} [[source]] tables; give one file per table",
            args.data.len()
        )
        .into());
    }
    if !args.validate.len().is_multiple_of(per_set) {
        return Err(format!(
            "--validate: {} files given; give them in groups of {per_set} (one per [[source]])",
            args.validate.len()
        )
        .into());
    }
    let data = load(&config, &args.data, model.dof())?;
    for w in &data.warnings {
        eprintln!("warning: {w}");
    }
    let id = identify(model, &data, &config)?;
    let mut report = Report::from_identification(&id, |n| chosen.expression(n));
    let mut predictions = vec![("fit".to_string(), id.prediction.clone())];
    for (k, files) in args.validate.chunks(per_set).enumerate() {
        let d = load(&config, files, model.dof())?;
        for w in &d.warnings {
            eprintln!("warning: {w}");
        }
        let p = validate(model, &d, &config, &id.estimate.values)?;
        report = report.with_validation(&files[0].display().to_string(), &p.fit());
        predictions.push((format!("validation{}", k + 1), p));
    }
    print!("{}", text_table(&report));
    if let Some(path) = &args.json {
        report.write_json(path)?;
        println!("JSON report: {}", path.display());
    }
    if let Some(dir) = &args.plot {
        for (prefix, p) in &predictions {
            plot_torques(p, dir, prefix)?;
        }
        println!("plots: {}/{{fit,validation*}}_joint*.svg", dir.display());
    }
    Ok(())
}
