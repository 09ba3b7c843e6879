//! `robid identify ROBOT.toml --data FILE... [--config CFG.toml] [--validate FILE...]
//! [--method ols|wls|rls|energy] [--json OUT.json] [--plot DIR]`: base parameters with
//! their uncertainty from measured data, the fit, and predictions of other files
//! (DESIGN.md 6 and 10). A table on stdout; JSON and SVG plots on request.
//!
//! The results are checked before anything is printed or written (every value finite),
//! and the warnings of an ill-conditioned identification (condition number above
//! [`CONDITION_WARNING`], a relative standard deviation above 100 %) go to stderr,
//! naming the parameters.

use std::path::{Path, PathBuf};

use robid_runtime::data::{Config, Method, load};
use robid_runtime::pipeline::{identify, validate};
use robid_runtime::report::{Report, plot_torques, text_table};
use robid_symbolic::Robot;
use robid_symbolic::program::BaseParameter;
use robots::interpreted::{Chosen, model_for};

use super::{Error, files, out};

/// The condition number of the observation matrix above which `identify` warns that the
/// data barely excite some directions of the parameters.
pub(crate) const CONDITION_WARNING: f64 = 1e5;

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
    /// Write SVG plots of measured vs predicted torque per joint into this folder
    /// (`fit_joint1.svg`.., `validation1_joint1.svg`..; existing files of these names are
    /// replaced).
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

/// Reads a description and chooses its model: the compiled model of a reference
/// description as it is (names and expressions from its generated code, no symbolic
/// derivation), else the derived one.
pub(crate) fn robot_model(path: &Path) -> Result<Chosen, Error> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("{}: cannot read: {e}", path.display()))?;
    if let Some(chosen) = compiled_reference(&text) {
        return Ok(chosen);
    }
    let robot = Robot::from_toml(&text, &path.display().to_string())?;
    Ok(model_for(&robot, &text)?)
}

/// The compiled model when `text` is a reference description (as `model_for` decides),
/// with the parameter names and expressions its generated code carries.
fn compiled_reference(text: &str) -> Option<Chosen> {
    macro_rules! reference {
        ($($file:literal => $model:ident),* $(,)?) => {
            $(
                if include_str!(concat!("../../descriptions/", $file)).trim() == text.trim() {
                    return Some(Chosen {
                        model: Box::new(robots::$model::default()),
                        compiled: true,
                        base: robots::$model::BASE_PARAMETER_NAMES
                            .iter()
                            .zip(robots::$model::BASE_PARAMETER_EXPRESSIONS)
                            .map(|(name, expression)| BaseParameter {
                                name: name.to_string(),
                                expression: expression.to_string(),
                            })
                            .collect(),
                        standard: robots::$model::STANDARD_PARAMETER_NAMES
                            .iter()
                            .map(|s| s.to_string())
                            .collect(),
                    });
                }
            )*
        };
    }
    reference!(
        "ur5e.toml" => Ur5e,
        "puma560.toml" => Puma560,
        "rx90.toml" => Rx90,
        "tx40.toml" => Tx40,
        "lwr4.toml" => Lwr4,
        "panda.toml" => Panda,
        "stanford.toml" => Stanford,
    );
    None
}

/// Runs the identification and prints the table.
pub(crate) fn run(args: &Args) -> Result<(), Error> {
    let mut inputs: Vec<&Path> = vec![&args.robot];
    inputs.extend(args.config.as_deref());
    inputs.extend(args.data.iter().map(PathBuf::as_path));
    inputs.extend(args.validate.iter().map(PathBuf::as_path));
    let mut outputs: Vec<&Path> = Vec::new();
    outputs.extend(args.json.as_deref());
    outputs.extend(args.plot.as_deref());
    files::refuse(&inputs, &outputs)?;
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
            MethodArg::Energy => Method::Energy,
        };
    }
    let per_set = config.sources.len().max(1);
    if args.data.len() != per_set {
        let fix = match &args.config {
            Some(path) => format!(
                "{} has {per_set} [[source]] tables; give one file per table",
                path.display()
            ),
            None => "without --config, give one file with the columns \
                     t,q1..,qd1..,qdd1..,tau1.. (or a --config with one [[source]] per file)"
                .to_string(),
        };
        return Err(format!("--data: {} files given; {fix}", args.data.len()).into());
    }
    if !args.validate.len().is_multiple_of(per_set) {
        return Err(format!(
            "--validate: {} files given; give them in groups of {per_set}, one per [[source]] \
             of --config",
            args.validate.len()
        )
        .into());
    }
    let prefixes: Vec<String> = std::iter::once("fit".to_string())
        .chain((1..=args.validate.len() / per_set).map(|k| format!("validation{k}")))
        .collect();
    if let Some(dir) = &args.plot {
        let plots = files::plot_files(dir, &prefixes, model.dof());
        let plots: Vec<&Path> = plots.iter().map(PathBuf::as_path).collect();
        files::refuse(&inputs, &plots)?;
    }
    let data = load(&config, &args.data, model.dof())?;
    for w in &data.warnings {
        out::warn(format_args!("warning: {w}"));
    }
    let id = identify(model, &data, &config)?;
    let mut report = Report::from_identification(&id, |n| chosen.expression(n));
    let mut predictions = vec![id.prediction.clone()];
    for group in args.validate.chunks(per_set) {
        let d = load(&config, group, model.dof())?;
        for w in &d.warnings {
            out::warn(format_args!("warning: {w}"));
        }
        let p = validate(model, &d, &config, &id.estimate.values)?;
        report = report.with_validation(&group[0].display().to_string(), &p.fit());
        predictions.push(p);
    }
    check_report(&report)?;
    // files first: a reader that closes standard output early does not cost them
    if let Some(path) = &args.json {
        report.write_json(path)?;
    }
    if let Some(dir) = &args.plot {
        for (prefix, p) in prefixes.iter().zip(&predictions) {
            plot_torques(p, dir, prefix)?;
        }
    }
    for w in warnings(&report) {
        out::warn(format_args!("warning: {w}"));
    }
    let mut stdout = out::Stdout::new();
    stdout.write_str(&text_table(&report))?;
    if let Some(path) = &args.json {
        writeln!(stdout, "JSON report: {}", path.display())?;
    }
    if let Some(dir) = &args.plot {
        writeln!(
            stdout,
            "plots: {}/{{fit,validation*}}_joint*.svg",
            dir.display()
        )?;
    }
    stdout.flush()?;
    Ok(())
}

/// Refuses a report with a value that is not a finite number (nothing is printed or
/// written then), naming the value.
fn check_report(report: &Report) -> Result<(), Error> {
    let fix = "a sample far out of range in the data (check the columns for outliers) or \
               data that do not excite this parameter";
    if !report.condition_number.is_finite() {
        return Err(format!(
            "the condition number of the observation matrix is {}: {fix}",
            report.condition_number
        )
        .into());
    }
    for p in &report.parameters {
        if !(p.value.is_finite() && p.std.is_finite()) {
            return Err(format!(
                "the identified {} is {} +- {}, not a finite number: {fix}",
                p.name, p.value, p.std
            )
            .into());
        }
    }
    let fits = std::iter::once((
        "the fit",
        &report.fit.rms_per_joint,
        report.fit.relative_error,
        report.fit.nmse,
    ))
    .chain(
        report
            .validation
            .iter()
            .map(|v| (v.file.as_str(), &v.rms_per_joint, v.relative_error, v.nmse)),
    );
    for (what, rms, relative, nmse) in fits {
        if !(relative.is_finite() && nmse.is_finite() && rms.iter().all(|x| x.is_finite())) {
            return Err(
                format!("the prediction errors of {what} are not finite numbers: {fix}").into(),
            );
        }
    }
    Ok(())
}

/// The warnings of an identification: a condition number above [`CONDITION_WARNING`] and
/// every parameter with a relative standard deviation above 100 %.
///
/// The runtime's report is to carry these warnings itself (issue 11); until it does,
/// they are derived here from the report's values.
fn warnings(report: &Report) -> Vec<String> {
    let mut out = Vec::new();
    if report.condition_number > CONDITION_WARNING {
        out.push(format!(
            "condition number {:.3e} is above {CONDITION_WARNING:e}: the data barely excite \
             some combinations of parameters; use a richer trajectory (robid excite)",
            report.condition_number
        ));
    }
    let poor: Vec<String> = report
        .parameters
        .iter()
        .filter_map(|p| {
            p.rel_std_percent
                .filter(|r| *r > 100.0)
                .map(|r| format!("{} ({r:.0} %)", p.name))
        })
        .collect();
    if !poor.is_empty() {
        out.push(format!(
            "relative standard deviation above 100 % (the value is not determined by the \
             data): {}",
            poor.join(", ")
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use robid_runtime::report::{FitEntry, ParameterEntry, ValidationEntry};

    /// A report of three parameters with relative standard deviations 45 %, 150 % and
    /// none (a value of zero), condition number `cond`.
    fn report(cond: f64) -> Report {
        let p = |name: &str, value: f64, std: f64, rel: Option<f64>| ParameterEntry {
            name: name.into(),
            expression: String::new(),
            value,
            std,
            rel_std_percent: rel,
        };
        Report {
            robot: "r".into(),
            method: "ols".into(),
            samples: 100,
            condition_number: cond,
            parameters: vec![
                p("ZZR1", -2.2e6, 1.0e6, Some(45.0)),
                p("MX2", 0.1, 0.15, Some(150.0)),
                p("Fo1", 0.0, 0.1, None),
            ],
            fit: FitEntry {
                relative_error: 0.1,
                rms_per_joint: vec![0.1, 0.2],
                nmse: 0.5,
            },
            validation: vec![ValidationEntry {
                file: "run2.csv".into(),
                relative_error: 0.2,
                rms_per_joint: vec![0.1, 0.2],
                nmse: 0.5,
            }],
        }
    }

    /// The issue's case: condition number 6.9e9 and ZZR1 = -2.2e6 +- 1.0e6 used to be
    /// written without a warning.
    #[test]
    fn warnings_name_the_condition_number_and_the_undetermined_parameters() {
        let w = warnings(&report(6.9e9));
        assert_eq!(w.len(), 2, "{w:?}");
        assert!(
            w[0].contains("condition number 6.900e9 is above 1e5"),
            "{w:?}"
        );
        assert!(w[1].ends_with(": MX2 (150 %)"), "{w:?}");
        let w = warnings(&report(CONDITION_WARNING));
        assert_eq!(w.len(), 1, "{w:?}");
        assert!(w[0].contains("MX2"), "{w:?}");
    }

    #[test]
    fn a_report_with_a_non_finite_value_is_refused_naming_it() {
        assert!(check_report(&report(10.0)).is_ok());
        let mut r = report(10.0);
        r.parameters[1].value = f64::NAN;
        let e = check_report(&r).unwrap_err().to_string();
        assert!(e.contains("the identified MX2 is NaN"), "{e}");
        let mut r = report(10.0);
        r.validation[0].rms_per_joint[1] = f64::INFINITY;
        let e = check_report(&r).unwrap_err().to_string();
        assert!(e.contains("run2.csv"), "{e}");
        assert!(check_report(&report(f64::INFINITY)).is_err());
    }

    /// The shortcut gives what the derivation gives: same names, expressions and model.
    #[test]
    fn compiled_reference_equals_the_derived_choice() {
        for name in robots::REFERENCE_ROBOTS {
            let path = Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("descriptions")
                .join(format!("{name}.toml"));
            let text = std::fs::read_to_string(&path).unwrap();
            let fast = compiled_reference(&text).unwrap();
            let robot = Robot::from_toml(&text, name).unwrap();
            let derived = model_for(&robot, &text).unwrap();
            assert!(fast.compiled && derived.compiled, "{name}");
            assert_eq!(fast.standard, derived.standard, "{name}");
            assert_eq!(fast.base.len(), derived.base.len(), "{name}");
            for (a, b) in fast.base.iter().zip(&derived.base) {
                assert_eq!((&a.name, &a.expression), (&b.name, &b.expression), "{name}");
            }
            assert_eq!(fast.model.name(), derived.model.name());
        }
        assert!(compiled_reference("name = \"other\"").is_none());
    }
}
