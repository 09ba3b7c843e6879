//! `robid emit ROBOT.toml [-o FILE]`: the generated Rust module of a robot,
//! pretty-printed: the same text `robot_model!` compiles and that is checked
//! into robots/generated/ for the reference robots.

use super::{Error, files, out};
use robid_symbolic::Robot;
use robid_symbolic::emit::emit_robot;
use std::path::PathBuf;

/// Arguments of `robid emit`.
#[derive(Debug, clap::Args)]
pub(crate) struct Args {
    /// Robot description file (TOML).
    robot: PathBuf,
    /// Write to this file instead of standard output.
    #[arg(short, long)]
    output: Option<PathBuf>,
}

/// Emits the module.
pub(crate) fn run(args: &Args) -> Result<(), Error> {
    if let Some(path) = &args.output {
        files::refuse(&[&args.robot], &[path])?;
    }
    let robot = Robot::from_file(&args.robot)?;
    let code = emit_robot(&robot)?;
    match &args.output {
        Some(path) => files::write(path, &code)?,
        None => out::print(&code)?,
    }
    Ok(())
}
