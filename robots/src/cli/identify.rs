//! `robid identify ROBOT.toml [--data FILE...] [--config CFG.toml] [--validate FILE...]
//! [--method ols|wls|rls|link-by-link|energy|per-axis] [--json OUT.json] [--plot DIR] [--report OUT.html]`, or
//! `robid identify ROBOT.toml --static SAMPLES.csv [--json OUT.json]`: base parameters with
//! their uncertainty from measured data, the fit, and predictions of other files
//! (docs/identification.md, docs/command-line.md#robid-identify). A table on stdout; JSON
//! and SVG plots on request.
//!
//! The results are checked before anything is printed or written (every value finite),
//! and the report's quality warnings (an ill-conditioned observation matrix, parameters
//! known to worse than their own size, an outlier, a validation that repeats the
//! estimation rows) also go to stderr, naming the parameters.

use std::path::{Path, PathBuf};

use robid_runtime::data::{
    Config, EXAMPLE_CONFIG, Loaded, Method, Record, load_or_split, load_runs, read_header,
};
use robid_runtime::estimate::check_forgetting;
use robid_runtime::inspect::resolve_cutoff;
use robid_runtime::pipeline::{
    identify, identify_runs, identify_segments, identify_static, validate_loaded,
};
use robid_runtime::report::{Report, ReportWarning, plot_torques, text_table, write_html};
use robid_runtime::{Count, Num};
use robid_symbolic::Robot;
use robid_symbolic::program::BaseParameter;
use robots::Reference;
use robots::interpreted::{Chosen, model_for};
use robots::limits::beyond_limits;

use super::description::{self, DescriptionFlags};
use super::{Error, files, out};

/// Arguments of `robid identify`.
#[derive(Debug, clap::Args)]
pub(crate) struct Args {
    #[arg(required_unless_present = "example_config", help = description::robot_help!("the robot, with the drive terms to identify"))]
    robot: Option<PathBuf>,
    #[command(flatten)]
    description: DescriptionFlags,
    /// Data files, one per `[[source]]` of the config (CSV, optionally gzip); default: the
    /// `file` of each `[[source]]` (relative to the config file).
    #[arg(long, num_args = 1..)]
    data: Vec<PathBuf>,
    /// Identification config (columns, units, drive chain, processing). Without it the
    /// data need the columns `t,q1..qn,qd1..qdn,qdd1..qddn,tau1..taun` (`robid simulate`),
    /// or `t,q1..qn,tau1..taun` (`robid simulate --columns positions`: differentiated,
    /// with `cutoff = "auto"`).
    #[arg(long)]
    config: Option<PathBuf>,
    /// Files to predict with the identified parameters (as many per data set as --data).
    #[arg(long, num_args = 1..)]
    validate: Vec<PathBuf>,
    /// A reference model's parameters (a `[base]` or `[standard]` file: CAD values, a data
    /// sheet, an earlier identification): each --validate file is also predicted with it,
    /// and the report gives both NMSEs of Madsen et al.'s eq. 22 and the relative
    /// improvement (their Table 5). Extra columns of the config are zero in the reference.
    /// Needs --validate.
    // checked in `run`, to say why (clap's `requires` said only "required arguments")
    #[arg(long)]
    reference: Option<PathBuf>,
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
    /// Write one self-contained HTML report to this file: figures, parameters, warnings
    /// and per joint the measured vs predicted torque with its residual (inline SVG).
    #[arg(long)]
    report: Option<PathBuf>,
    /// Static samples of a numeric model (CSV, as Gaz et al. 2016 take them from the robot's
    /// controller): `q1..qn` with `g1..gn` (gravity torques) or with `M11 M12 .. M1n M22 ..
    /// Mnn` (the upper triangle of the mass matrix, `Mij` for i <= j). Identifies, by least
    /// squares, the combinations of base parameters such samples determine and names the
    /// others: a table on standard output, and with --json the same as JSON (no config,
    /// data, validation, plots or HTML report: the samples are the whole input).
    #[arg(
        long = "static",
        value_name = "SAMPLES.csv",
        conflicts_with_all = ["data", "config", "validate", "reference", "method", "plot", "report"]
    )]
    static_samples: Option<PathBuf>,
    /// Print a complete annotated config (every key, its default and what it does) and exit.
    #[arg(long, exclusive = true)]
    example_config: bool,
}

/// `--static`: the combinations of base parameters static samples determine
/// (docs/identification.md#static-samples), a table on stdout, the undetermined ones on
/// stderr, and the JSON report on request.
fn run_static(args: &Args, robot: &Path, samples: &Path) -> Result<(), Error> {
    let outputs: Vec<(&str, &Path)> = args.json.iter().map(|p| ("--json", p.as_path())).collect();
    files::refuse(&[robot, samples], &outputs)?;
    let chosen = robot_model(robot, &args.description)?;
    let model = chosen.model.as_ref();
    // the estimators' default relative singular-value threshold (`estimation.rank_tolerance`)
    let fit = identify_static(model, samples, STATIC_RANK_TOLERANCE)?;
    let e = &fit.estimate;
    if let Some(bad) = e.values.iter().chain(&e.std).find(|v| !v.is_finite()) {
        return Err(format!("the static fit gave {bad}; nothing was written").into());
    }
    // each combination's base parameters: its name is only the one that leads it
    let name = |b: usize| model.base_parameter_name(b).unwrap_or("?").to_owned();
    let expressions: Vec<String> = (0..e.names.len())
        .map(|i| fit.determined.expression(i, name))
        .collect();
    let mut table = format!(
        "{} samples: {} equations, condition number {}\n{:<10} {:>14} {:>12} {:>8}  {}\n",
        fit.kind.name(),
        e.rows,
        Num::rounded(e.condition_number, 4),
        "parameter",
        "value",
        "std",
        "std %",
        "combination"
    );
    for (i, expression) in expressions.iter().enumerate() {
        table += &format!(
            "{:<10} {:>14.6e} {:>12.3e} {:>8}  {expression}\n",
            e.names[i],
            e.values[i],
            e.std[i],
            // a value of 0 has no relative deviation ("inf" for 0/0), as in the report
            Some(e.rel_std_percent[i])
                .filter(|r| r.is_finite())
                .map_or_else(|| "-".to_owned(), |r| robid_runtime::report::fixed(r, 2))
        );
    }
    out::print(&table)?;
    for w in &fit.warnings {
        out::warn(format_args!("warning: {w}"));
    }
    if !fit.undetermined.is_empty() {
        out::warn(format_args!(
            "{} samples determine {} of the {} base parameters (each named after the one \
             that leads its combination); not determined by them: {}",
            fit.kind.name(),
            e.names.len(),
            e.names.len() + fit.undetermined.len(),
            fit.undetermined.join(" ")
        ));
    }
    for w in &e.warnings {
        out::warn(format_args!("warning: {}", w));
    }
    if let Some(path) = &args.json {
        let parameters: Vec<serde_json::Value> = (0..e.names.len())
            .map(|i| {
                let terms: Vec<serde_json::Value> = fit
                    .determined
                    .terms(i)
                    .into_iter()
                    .map(|(b, c)| serde_json::json!({"parameter": name(b), "coefficient": c}))
                    .collect();
                serde_json::json!({
                    "name": e.names[i],
                    "value": e.values[i],
                    "std": e.std[i],
                    "rel_std_percent": e.rel_std_percent[i],
                    "expression": expressions[i],
                    "terms": terms,
                })
            })
            .collect();
        let report = serde_json::json!({
            "kind": fit.kind.name(),
            "equations": e.rows,
            "condition_number": e.condition_number,
            "parameters": parameters,
            "undetermined": fit.undetermined,
        });
        let text = serde_json::to_string_pretty(&report).map_err(|e| e.to_string())?;
        files::write(path, &(text + "\n"))?;
    }
    Ok(())
}

/// The relative singular-value threshold of `--static` (the estimators' default).
const STATIC_RANK_TOLERANCE: f64 = 1e-10;

/// The estimators of the command line.
#[derive(Debug, Clone, Copy, clap::ValueEnum)]
enum MethodArg {
    /// Ordinary least squares.
    Ols,
    /// Weighted least squares (per-joint weights from the OLS residuals).
    Wls,
    /// Recursive least squares (forgetting factor from the config).
    Rls,
    /// Link by link from the last joint backwards, recursive least squares at each step.
    LinkByLink,
    /// Energy (power-balance) model.
    Energy,
    /// Per-axis least squares (Milella): each joint's equation on its own.
    PerAxis,
}

/// Reads a description and chooses its model: the compiled model of a reference robot
/// (names and expressions from its generated code, no symbolic derivation), else the
/// derived one.
pub(crate) fn robot_model(path: &Path, flags: &DescriptionFlags) -> Result<Chosen, Error> {
    model_of(&description::read(path, flags)?)
}

/// The model of a robot already read: the compiled reference model when `robot` is a
/// reference robot, else the derived one.
pub(crate) fn model_of(robot: &Robot) -> Result<Chosen, Error> {
    if let Some(chosen) = compiled_reference(robot) {
        return Ok(chosen);
    }
    Ok(model_for(robot)?)
}

/// The compiled model when `robot` is a reference robot, with the parameter names and
/// expressions its generated code carries.
fn compiled_reference(robot: &Robot) -> Option<Chosen> {
    let reference = Reference::matching(robot)?;
    let model = reference.model();
    let base = (0..model.base_parameter_count())
        .zip(reference.base_expressions)
        .map(|(i, expression)| {
            Some(BaseParameter {
                name: model.base_parameter_name(i)?.parse().ok()?,
                expression: (*expression).to_owned(),
            })
        })
        .collect::<Option<_>>()?;
    let standard = robid_runtime::model::standard_parameter_names(&*model);
    Some(Chosen {
        model,
        compiled: true,
        base,
        standard,
    })
}

/// The config read from `path`, else the default mapping for the header of the first data
/// file (with velocities, or a log of positions and torques: see
/// `Config::default_mapping_for`).
pub(crate) fn config_for(path: Option<&Path>, data: &[PathBuf]) -> Result<Config, Error> {
    Ok(match (path, data) {
        (Some(p), _) => {
            let config = Config::from_file(p)?;
            // a factor outside [0.5, 1] (`online::forgetting_in_range`, which the config's
            // own check also applies) at its file:line before anything is read: a tiny one
            // (1e-320) once overflowed the recursion after the processing, without file:line
            check_forgetting(config.estimation.forgetting).map_err(|e| config.locate(e))?;
            config
        }
        (None, [file]) => Config::default_mapping_for(&read_header(file)?),
        // none or several files: the count check says what to give
        (None, _) => Config::default_mapping(),
    })
}

/// Warns of each key of `unapplied` that the config read from `path` gives and that
/// `command` does not apply, each table entry's keys with their own reason: a key left
/// without a word read as applied (payload's standard deviations came from equations a
/// `decimation` would have thinned; friction took one record under `[runs]`), and one
/// reason for all keys told an `[estimation]` of a decimation's filter.
pub(crate) fn warn_unapplied(
    config: &Config,
    path: &Path,
    command: &str,
    unapplied: &[(&[&str], &str)],
) {
    for &(keys, why) in unapplied {
        for (key, line, column) in config.given(keys) {
            out::warn(format_args!(
                "warning: {}:{line}:{column}: `{key}` is not applied by `robid {command}` \
                 ({why}); it reads the rest of the config",
                path.display()
            ));
        }
    }
}

/// The data files: `data` (`--data`), else the `file` of each `[[source]]` of the config
/// read from `config_path` (resolved against the config's folder).
pub(crate) fn data_files(
    data: &[PathBuf],
    config_path: Option<&Path>,
    config: &Config,
) -> Result<Vec<PathBuf>, Error> {
    let per_set = config.sources.len().max(1);
    if data.is_empty() {
        if config_path.is_none() {
            return Err(
                "--data: give the data file (columns t,q1..,qd1..,qdd1..,tau1.., as \
                        `robid simulate` writes), or a --config whose [[source]] tables name \
                        their files"
                    .into(),
            );
        }
        // the loader's own check: a table without `file` or a file that is not there is
        // named at its key, with the path as resolved against the config's folder
        return Ok(config.source_files()?);
    }
    if data.len() != per_set {
        let fix = match config_path {
            Some(path) => format!(
                "{} has {}; give one file per table",
                path.display(),
                Count(per_set, "[[source]] table")
            ),
            None => "without --config, give one file with the columns \
                     t,q1..,qd1..,qdd1..,tau1.. (or a --config with one [[source]] per file)"
                .to_string(),
        };
        return Err(format!("--data: {} files given; {fix}", data.len()).into());
    }
    Ok(data.to_vec())
}

/// Runs the identification and prints the table.
pub(crate) fn run(args: &Args) -> Result<(), Error> {
    if args.example_config {
        return Ok(out::print(EXAMPLE_CONFIG)?);
    }
    let robot = args.robot.as_deref().ok_or("give the robot description")?;
    if args.reference.is_some() && args.validate.is_empty() {
        return Err(
            "--reference: the reference model is compared with the identified one on \
                    validation data (each --validate data set is predicted with both, and the \
                    report gives both NMSEs), so it needs --validate: give --validate FILE... \
                    (data not used for the identification, as many files per data set as \
                    --data), or drop --reference"
                .into(),
        );
    }
    if let Some(samples) = &args.static_samples {
        return run_static(args, robot, samples);
    }
    let mut config = config_for(args.config.as_deref(), &args.data)?;
    // a validation range with no validation file applies to nothing (said nothing)
    if args.validate.is_empty()
        && let Some(path) = &args.config
    {
        warn_unapplied(
            &config,
            path,
            "identify",
            &[(
                &["processing.validation_range"],
                "it cuts the --validate files, and none is given",
            )],
        );
    }
    // repeated acquisitions: the config's [runs] lists every run's files
    let runs: Option<Vec<PathBuf>> = match &config.runs {
        Some(_) if !args.data.is_empty() => {
            return Err(
                "--data: the config's [runs] lists the runs' files; give no --data \
                        (or remove [runs] to identify one data set)"
                    .into(),
            );
        }
        Some(r) => Some(
            r.files
                .iter()
                .flat_map(|f| f.paths())
                .map(|f| config.resolve(&f))
                .collect(),
        ),
        None => None,
    };
    let data = match &runs {
        Some(files) => files.clone(),
        None => data_files(&args.data, args.config.as_deref(), &config)?,
    };
    let referenced = config.referenced_files();
    let mut inputs: Vec<&Path> = vec![robot];
    inputs.extend(args.config.as_deref());
    inputs.extend(data.iter().map(PathBuf::as_path));
    inputs.extend(referenced.iter().map(PathBuf::as_path));
    inputs.extend(args.validate.iter().map(PathBuf::as_path));
    inputs.extend(args.reference.as_deref());
    let mut outputs: Vec<(&str, &Path)> = Vec::new();
    outputs.extend(args.json.as_deref().map(|p| ("--json", p)));
    outputs.extend(args.report.as_deref().map(|p| ("--report", p)));
    let plot: Vec<(&str, &Path)> = args.plot.iter().map(|d| ("--plot", d.as_path())).collect();
    files::refuse_with_folders(&inputs, &outputs, &plot)?;
    let description = description::read(robot, &args.description)?;
    config.prismatic = description::prismatic(&description);
    let chosen = model_of(&description)?;
    let model = chosen.model.as_ref();
    if let Some(m) = args.method {
        config.estimation.method = match m {
            MethodArg::Ols => Method::Ols,
            MethodArg::Wls => Method::Wls,
            MethodArg::Rls => Method::Rls,
            MethodArg::LinkByLink => Method::LinkByLink,
            MethodArg::Energy => Method::Energy,
            MethodArg::PerAxis => Method::PerAxis,
        };
        // an error about the method names the flag, not the config's line it replaced
        let name = clap::ValueEnum::to_possible_value(&m)
            .map(|v| v.get_name().to_owned())
            .unwrap_or_default();
        config.set_by_flag("estimation.method", format!("--method {name}"));
    }
    let per_set = config.sources.len().max(1);
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
        // against the inputs and the other outputs (`--json DIR/fit_joint1.svg` would be
        // replaced by the plot), not checked as files: the folder may not exist yet
        let mut written = outputs.clone();
        written.extend(plots.iter().map(|p| ("--plot", p.as_path())));
        files::distinct(&inputs, &written)?;
        files::check_named_files(&plots, "--plot")?;
        let stale = files::stale_plots(dir, &plots);
        if !stale.is_empty() {
            let names: Vec<String> = stale
                .iter()
                .filter_map(|p| p.file_name().map(|n| n.to_string_lossy().into_owned()))
                .collect();
            out::warn(format_args!(
                "warning: --plot {}: {} named as robid's plots that this run does not \
                 write, left by an earlier run: {}; remove them, or plot into an empty folder",
                dir.display(),
                robid_runtime::Count(names.len(), "file"),
                names.join(", ")
            ));
        }
    }
    // the progress of reading a long log and of the streaming passes over it, as excite
    // shows its design's
    config.progress = true;
    // one record is read from its file block by block (a long log is never held whole);
    // repeated runs, and a record cut at its gaps (`gaps = "split"`), are loaded in memory
    let (sets, record) = match runs {
        Some(_) => (load_runs(&config, model.dof())?, None),
        None => (
            Vec::new(),
            Some(load_or_split(&config, &data, model.dof())?),
        ),
    };
    let first: &dyn Record = match (record.as_ref().and_then(Loaded::longest), sets.first()) {
        (Some(r), _) => r,
        (None, Some(d)) => d,
        (None, None) => return Err("[runs] lists no files; list the runs' files".into()),
    };
    // what the data say before any fit, printed as soon as read (a long log takes a
    // while) and kept for the JSON and HTML reports
    let mut data_warnings = Vec::new();
    let mut warn = |w: String| {
        out::warn(format_args!("warning: {w}"));
        data_warnings.push(w);
    };
    if let Some(path) = &args.config {
        for (key, why) in config.unused_columns() {
            let place = match config.given(&[&key]).first() {
                Some((_, line, column)) => format!("{}:{line}:{column}: ", path.display()),
                None => format!("{}: ", path.display()),
            };
            warn(format!(
                "{place}`{key}` is read but not used by this fit: {why}; add what uses it, \
                 or remove the key"
            ));
        }
    }
    let warnings = sets.iter().flat_map(|d| d.warnings.clone());
    for w in warnings.chain(record.iter().flat_map(Loaded::warnings)) {
        warn(w.to_string());
    }
    // data beyond the description's limits (degrees read as radians, mm as m, mN m as N m,
    // another robot's log), from the extremes the loader kept, as `robid inspect` warns
    // of them
    match &record {
        Some(r) => beyond_limits(&description, &r.extremes(), robot)
            .into_iter()
            .for_each(&mut warn),
        None => {
            for (i, d) in sets.iter().enumerate() {
                let files = d.files();
                let files: Vec<String> = files.iter().map(|f| f.display().to_string()).collect();
                for w in beyond_limits(&description, &d.extremes, robot) {
                    warn(format!("run {} ({}): {w}", i + 1, files.join(", ")));
                }
            }
        }
    }
    // "auto" is chosen once, on the estimation data (the first run), and used for the
    // other runs and the validation data too
    let auto = resolve_cutoff(&mut config, first).map_err(|e| config.locate(e))?;
    let reference = match &args.reference {
        Some(path) => {
            let (values, warnings) = reference_values(path, model, &config)?;
            warnings.into_iter().for_each(&mut warn);
            Some((path, values))
        }
        None => None,
    };
    let (mut report, prediction, values) = if config.runs.is_some() {
        let id = identify_runs(model, &sets, &config)?;
        let report = Report::from_runs(&id, |n| chosen.expression(n));
        (report, id.prediction, id.estimate.values)
    } else if let Some(Loaded::Segments(segments)) = &record {
        let s = identify_segments(model, segments, &config)?;
        let report = Report::from_segments(&s, |n| chosen.expression(n));
        let id = s.identification;
        (report, id.prediction, id.estimate.values)
    } else {
        let id = identify(model, first, &config)?;
        let report = Report::from_identification(&id, |n| chosen.expression(n));
        (report, id.prediction, id.estimate.values)
    };
    report.cutoff = auto;
    report.pieces = config.processing.pieces.clone();
    let mut predictions = vec![prediction];
    for group in args.validate.chunks(per_set) {
        let d = load_or_split(&config, group, model.dof())?;
        for w in d.warnings() {
            warn(w.to_string());
        }
        let files: Vec<String> = group.iter().map(|f| f.display().to_string()).collect();
        for w in beyond_limits(&description, &d.extremes(), robot) {
            warn(format!("--validate {}: {w}", files.join(", ")));
        }
        let (p, segments) = validate_loaded(model, &d, &config, &values)?;
        report = report.with_prediction(&p);
        if let Some(u) = &segments {
            report = report.with_validation_segments(u);
        }
        if let Some((path, values)) = &reference {
            let fit = validate_loaded(model, &d, &config, values)?.0.fit();
            let index = report.validation.len() - 1;
            report = report.with_reference(index, &path.display().to_string(), &fit);
        }
        predictions.push(p);
    }
    // the data's warnings first in the reports, where the quality warnings of the fit
    // follow them (printed as read, above)
    let printed = report.warnings.len();
    let data = data_warnings.into_iter().map(ReportWarning::data);
    report.warnings.splice(0..0, data);
    report.check()?;
    // files first: a reader that closes standard output early does not cost them; the
    // plots first of all, as they create their folder, which `--json` and `--report` may
    // name (`--plot out --json out/fit.json`)
    if let Some(dir) = &args.plot {
        for (prefix, p) in prefixes.iter().zip(&predictions) {
            plot_torques(p, &report.joint_units, dir, prefix)?;
        }
    }
    if let Some(path) = &args.json {
        report.write_json(path)?;
    }
    if let Some(path) = &args.report {
        let named: Vec<(&str, &_)> = prefixes
            .iter()
            .map(String::as_str)
            .zip(&predictions)
            .collect();
        write_html(path, &report, &named)?;
    }
    let quality = report.warnings.len() - printed..;
    for w in &report.warnings[quality] {
        out::warn(format_args!("warning: {}", w.message));
    }
    let mut stdout = out::Stdout::new();
    stdout.write_str(&text_table(&report))?;
    if let Some(path) = &args.json {
        writeln!(stdout, "JSON report: {}", path.display())?;
    }
    if let Some(path) = &args.report {
        writeln!(stdout, "HTML report: {}", path.display())?;
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

/// The values of the reference model of `--reference`: its base parameters (from a `[base]`
/// table, or mapped from a `[standard]` one), then the value of every extra column of the
/// config (and of `[drive.rotor] residual`) from the file's `[extra]` table, 0 where it
/// has none; and the warnings of those it has not, and of `[extra]` values of no column.
fn reference_values(
    path: &Path,
    model: &dyn robid_runtime::model::Model,
    config: &Config,
) -> Result<(Vec<f64>, Vec<String>), Error> {
    let file = description::read_parameters(path, true)?;
    let mut values = file.base_parameters(model)?;
    let extra = config
        .extra_columns_for(model.dof())
        .map_err(|e| config.locate(e))?;
    // the extra columns' values from the file's [extra] table (robid feasible writes it),
    // 0 where it has none: said, as they were left out without a word
    let given: Vec<(&str, f64)> = file.extra().collect();
    let mut missing = Vec::new();
    for column in &extra {
        match given.iter().find(|(n, _)| *n == column.name) {
            Some((_, v)) => values.push(*v),
            None => {
                values.push(0.0);
                missing.push(column.name.as_str());
            }
        }
    }
    let mut warnings = Vec::new();
    if !missing.is_empty() {
        warnings.push(format!(
            "--reference {}: no value for the config's extra {} {}, taken as 0 in the \
             reference's prediction; give {} in an [extra] table of the file (robid feasible \
             writes one) if the reference has them",
            path.display(),
            if missing.len() == 1 {
                "column"
            } else {
                "columns"
            },
            missing.join(", "),
            if missing.len() == 1 { "it" } else { "them" },
        ));
    }
    let unused: Vec<&str> = given
        .iter()
        .map(|(n, _)| *n)
        .filter(|n| !extra.iter().any(|c| c.name == *n))
        .collect();
    if !unused.is_empty() {
        warnings.push(format!(
            "--reference {}: [extra] {} {} no extra column of the config, left out of the \
             reference's prediction",
            path.display(),
            unused.join(", "),
            if unused.len() == 1 { "is" } else { "are" },
        ));
    }
    Ok((values, warnings))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The shortcut gives what the derivation gives: same names, expressions and model.
    #[test]
    fn compiled_reference_equals_the_derived_choice() {
        for reference in &robots::REFERENCES {
            let name = reference.name;
            let robot = reference.robot();
            let fast = compiled_reference(&robot).unwrap();
            let derived = model_for(&robot).unwrap();
            assert!(fast.compiled && derived.compiled, "{name}");
            assert_eq!(fast.standard, derived.standard, "{name}");
            assert_eq!(fast.base.len(), derived.base.len(), "{name}");
            for (a, b) in fast.base.iter().zip(&derived.base) {
                assert_eq!((&a.name, &a.expression), (&b.name, &b.expression), "{name}");
            }
            assert_eq!(fast.model.name(), derived.model.name());
        }
        // a reference robot with one more drive term is another robot
        let ur5e = robots::Reference::named("ur5e").unwrap().robot();
        let edited = ur5e.with_drive(robid_symbolic::Drive::ALL);
        assert!(compiled_reference(&edited).is_none());
    }
}
