//! `robid inspect ROBOT.toml [--data FILE...] [--config CFG.toml] [--drive ..] [--json]`:
//! what a log holds before identifying from it (robid_runtime::inspect): per file the
//! sampling (median step, jitter, skipped ticks, stale rows), per joint the bandwidth and
//! noise of positions and torques, torque saturation and time at rest, and a suggested
//! low-pass cutoff with its reason (what `cutoff = "auto"` uses). A single-file log is kept
//! on disk and read block by block (`data::SpilledRecord`), as `robid identify` reads it,
//! so an hour-long log is never held in memory.

use std::path::PathBuf;

use robid_runtime::data::{Config, Gaps, Record, Sampling, SpilledRecord, load, load_segments};
use robid_runtime::inspect::inspect_record;
use robid_runtime::signal::MIN_SPECTRUM_SAMPLES;
use robid_symbolic::Robot;
use robots::limits::beyond_limits;

use super::description::{self, DescriptionFlags};
use super::identify::{config_for, data_files};
use super::{Error, out};

/// Arguments of `robid inspect`.
#[derive(Debug, clap::Args)]
pub(crate) struct Args {
    #[arg(help = description::robot_help!("the joint count and the torque limits"))]
    robot: PathBuf,
    #[command(flatten)]
    description: DescriptionFlags,
    /// Data files, one per `[[source]]` of the config (default: the config's `file`s).
    #[arg(long, num_args = 1..)]
    data: Vec<PathBuf>,
    /// Identification config (columns, units, drive chain; its rest velocity is used).
    /// Without it the data need the columns `t,q1..,qd1..,qdd1..,tau1..`.
    #[arg(long)]
    config: Option<PathBuf>,
    /// Print JSON instead of the table.
    #[arg(long)]
    json: bool,
}

/// Runs the subcommand.
pub(crate) fn run(args: &Args) -> Result<(), Error> {
    let robot = description::read(&args.robot, &args.description)?;
    let mut config = config_for(args.config.as_deref(), &args.data)?;
    config.prismatic = description::prismatic(&robot);
    let files = data_files(&args.data, args.config.as_deref(), &config)?;
    if config.processing.gaps == Gaps::Split {
        return run_segments(args, &robot, &config, &files);
    }
    // on disk when it can be (as `data::load_record` keeps it), with its sampling; else
    // loaded in memory, whose errors are the ones reported
    let (data, sampling): (Box<dyn Record>, Vec<Sampling>) =
        match SpilledRecord::open(&config, &files, robot.dof()) {
            Ok(Some(record)) => {
                let sampling = vec![record.sampling().clone()];
                (Box::new(record), sampling)
            }
            _ => {
                let data = load(&config, &files, robot.dof()).map_err(needs_a_spectrum)?;
                let sampling = data.sampling.clone();
                (Box::new(data), sampling)
            }
        };
    for w in data.warnings() {
        out::warn(format_args!("warning: {w}"));
    }
    let limits: Vec<Option<f64>> = robot.joints().iter().map(|j| j.limits.torque).collect();
    let inspection =
        inspect_record(data.as_ref(), sampling, &config, &limits).map_err(|e| config.locate(e))?;
    for w in beyond_limits(&robot, data.extremes(), &args.robot) {
        out::warn(format_args!("warning: {w}"));
    }
    let text = if args.json {
        serde_json::to_string_pretty(&inspection)? + "\n"
    } else {
        inspection.text()
    };
    Ok(out::print(&text)?)
}

/// `gaps = "split"`: the record cut at its gaps, each segment inspected on its own as
/// `robid identify` processes it (inspect refused such a config, which identify took).
/// The text gives the inspection of each segment (which names its lines) in turn; the
/// JSON is an array of `{ "segment": place, "inspection": ... }`.
/// The loader asks for the 2 samples a time step needs, the spectra inspect estimates for
/// many more: a file of one row said "at least 2 are needed", then of two rows "at least
/// 64". The loader's count is raised to the spectra's, so the first message is the last.
fn needs_a_spectrum(e: robid_runtime::Error) -> robid_runtime::Error {
    match e {
        robid_runtime::Error::TooFewSamples {
            context,
            found,
            required,
            ..
        } if required < MIN_SPECTRUM_SAMPLES => robid_runtime::Error::TooFewSamples {
            context,
            found,
            required: MIN_SPECTRUM_SAMPLES,
            hint: "inspect estimates each joint's spectrum, which needs a longer record: record \
                   a longer trajectory",
        },
        e => e,
    }
}

fn run_segments(
    args: &Args,
    robot: &Robot,
    config: &Config,
    files: &[PathBuf],
) -> Result<(), Error> {
    let segments = load_segments(config, files, robot.dof())?;
    for w in segments.all_warnings() {
        out::warn(format_args!("warning: {w}"));
    }
    let limits: Vec<Option<f64>> = robot.joints().iter().map(|j| j.limits.torque).collect();
    let mut text = format!(
        "{}: {} cut at its {} (gaps = \"split\")\n",
        segments.file.display(),
        robid_runtime::Count(segments.segments.len(), "segment"),
        robid_runtime::Count(segments.gaps.len(), "gap")
    );
    let mut json = Vec::new();
    let mut short = Vec::new();
    for (k, (data, span)) in segments.segments.iter().zip(&segments.spans).enumerate() {
        // a segment too short for the spectra is left out, as identify leaves it out
        let inspection = match inspect_record(data, data.sampling.clone(), config, &limits) {
            Ok(inspection) => inspection,
            Err(robid_runtime::Error::TooFewSamples { required, .. }) => {
                short.push(format!("{span}: at least {required} samples are needed"));
                continue;
            }
            Err(e) => return Err(config.locate(e).into()),
        };
        for w in beyond_limits(robot, data.extremes(), &args.robot) {
            out::warn(format_args!("warning: segment {}: {w}", k + 1));
        }
        // (the inspection names its segment and lines)
        text += "\n";
        text += &inspection.text();
        json.push(serde_json::json!({ "segment": span, "inspection": inspection }));
    }
    let spans = segments.single.iter().map(|s| format!("{s}: one sample"));
    short.extend(spans);
    if !short.is_empty() {
        out::warn(format_args!(
            "warning: {}: segments too short to inspect: {}",
            segments.file.display(),
            short.join("; ")
        ));
    }
    if json.is_empty() {
        return Err(format!(
            "{}: no segment between its gaps is long enough to inspect ({})",
            segments.file.display(),
            short.join("; ")
        )
        .into());
    }
    let shown = if args.json {
        serde_json::to_string_pretty(&json)? + "\n"
    } else {
        text
    };
    Ok(out::print(&shown)?)
}
