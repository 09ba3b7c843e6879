//! The subcommands of `robid` (docs/command-line.md). Each file holds one subcommand;
//! they read descriptions and data, call the library crates and print.

mod bench;
mod demo;
mod description;
mod emit;
mod excite;
mod feasible;
mod files;
mod flags;
mod friction;
mod identified;
mod identify;
mod idle;
mod inspect;
mod model;
mod out;
mod payload;
mod schedule;
mod simulate;
mod states;
mod torques;

use clap::error::{ContextKind, ContextValue};
use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};
use robid_runtime::names;
use std::process::ExitCode;

/// robid: closed-form robot dynamics, base parameters and identification.
#[derive(Debug, Parser)]
#[command(name = "robid", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Standard and base parameters of a robot, their expressions and operation counts.
    Model(model::Args),
    /// The main job: identifies the Staubli TX40 from its built-in real log and writes a report.
    Demo,
    /// Base parameters with their uncertainty from measured data, fit and validation.
    ///
    /// Warns on stderr, naming them, when the condition number of the observation matrix
    /// exceeds 1e4, a parameter's relative standard deviation exceeds 100 % (unless that
    /// deviation moves the torques by less than 1e-9 of their norm, as a parameter of about
    /// 0 in noise-free data does), a few rows dominate a parameter's column (an outlier),
    /// or a validation reuses estimation rows.
    Identify(identify::Args),
    /// What a log holds before identifying from it: sampling, bandwidth and noise per
    /// joint, saturation, time at rest, and a suggested low-pass cutoff with its reason.
    Inspect(inspect::Args),
    /// Inverse dynamics row by row from a parameter file and a state file.
    ///
    /// Parameter values lie within +-1e6 (SI units) and states within +-1e6; a torque that
    /// is not a finite number is an error naming its row.
    Torques(torques::Args),
    /// The generated Rust module of a robot, pretty-printed.
    Emit(emit::Args),
    /// Median nanoseconds per call of the compiled reference models.
    Bench(bench::Args),
    /// An exciting trajectory optimised within the joint limits.
    Excite(excite::Args),
    /// Physically consistent link parameters from identified base parameters (TOML or URDF).
    Feasible(feasible::Args),
    /// The nonlinear rotor friction of every joint from a two-encoder log (motor and link
    /// encoders), written as a friction file for `[drive.rotor] friction`.
    Friction(friction::Args),
    /// Closed-loop simulation of a trajectory with noise, producing data with known truth.
    ///
    /// A run whose positions leave the trajectory by more than 1 rad (plus ten times the
    /// position noise and quantization) is refused as diverged; nothing is written then.
    Simulate(simulate::Args),
    /// The ten inertial parameters of a payload on the last link, with standard deviations
    /// and a physical consistency check, from joint torques and the robot's known model.
    Payload(payload::Args),
}

/// Parses the command line, runs the subcommand and reports errors on stderr: status 0
/// on success, 1 on an error (2 for a command line clap rejects), 141 when standard
/// output was closed by its reader (see `out`).
pub(crate) fn run() -> ExitCode {
    let parsed = numbers_may_be_negative(Cli::command())
        .try_get_matches()
        .and_then(|matches| Cli::from_arg_matches(&matches));
    let cli = match parsed {
        Ok(cli) => cli,
        Err(e) => {
            let code = u8::try_from(e.exit_code()).unwrap_or(2);
            // clap quotes a refused value whole, and the value parser's message again: a
            // 5000-character value made a 10 kB message
            if let Some(ContextValue::String(value)) = e.get(ContextKind::InvalidValue)
                && value.chars().count() > 40
            {
                let text = e.render().to_string();
                eprint!("{}", text.replace(value.as_str(), &names::short(value)));
                return ExitCode::from(code);
            }
            return match e.print() {
                Err(io) if !e.use_stderr() => out::stdout_failure(&io),
                _ => ExitCode::from(code),
            };
        }
    };
    // a run's files change together or not at all: a header beside no source, a JSON result
    // beside the report of an earlier run (docs/robustness.md#outputs-of-one-run-together)
    let result = robid_runtime::output::together(|| {
        match cli.command {
            Command::Model(args) => model::run(&args),
            Command::Demo => demo::run(),
            Command::Identify(args) => identify::run(&args),
            Command::Inspect(args) => inspect::run(&args),
            Command::Torques(args) => torques::run(&args),
            Command::Emit(args) => emit::run(&args),
            Command::Bench(args) => bench::run(&args),
            Command::Excite(args) => excite::run(&args),
            Command::Feasible(args) => feasible::run(&args),
            Command::Friction(args) => friction::run(&args),
            Command::Simulate(args) => simulate::run(&args),
            Command::Payload(args) => payload::run(&args),
        }
        .or_else(|e| {
            // files written before standard output failed (a reader that closed the pipe)
            // are whole and this run's: they stand
            if out::stdout_or_reader_failed(e.as_ref()) {
                robid_runtime::output::place_held()?;
            }
            Err(e)
        })
    });
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => out::error(e.as_ref()),
    }
}

/// `command` with every flag that takes a value taking a negative number too
/// (`--duration -10`): clap read `-10` as an unknown flag ("unexpected argument") where the
/// flag's own check says what range it takes. A flag of real numbers takes any value
/// after a hyphen, as clap's own test of a negative number knows neither `-inf`, `-nan`
/// nor `-1e-320`; the others (paths, names) only numbers, so that `--plot --json r.json`
/// is not a folder named `--json`.
fn numbers_may_be_negative(command: clap::Command) -> clap::Command {
    command
        .mut_args(|arg| {
            if !arg.get_action().takes_values() || arg.is_positional() {
                return arg;
            }
            if arg.get_value_parser().type_id() == std::any::TypeId::of::<f64>() {
                arg.allow_hyphen_values(true)
            } else {
                arg.allow_negative_numbers(true)
            }
        })
        .mut_subcommands(numbers_may_be_negative)
}

/// Any error a subcommand reports: a message that says what and how to fix it.
pub(crate) type Error = Box<dyn std::error::Error>;
