//! Reading a robot description on the command line: the one place that reads the file,
//! prints its warnings (file:line, e.g. a `drive` key that TOML gave to the last joint)
//! and applies `--drive`, so that every subcommand sees the same robot.

use std::path::Path;

use robid_symbolic::robot::DriveTerm;
use robid_symbolic::{Drive, Robot};

use super::{Error, out};

/// `--drive TERMS`, shared by every subcommand that reads a description.
#[derive(Debug, Clone, Default, clap::Args)]
pub(crate) struct DriveFlag {
    /// Drive terms of every joint, e.g. `Ia,Fv,Fc,Fo` (replaces the description's; give the
    /// same terms to every subcommand of one job).
    #[arg(long, value_delimiter = ',')]
    pub(crate) drive: Vec<String>,
}

/// The drive terms named on the command line (`Ia`, `Fv`, `Fc`, `Fo`); `None` when none.
pub(crate) fn parse_drive(names: &[String]) -> Result<Option<Drive>, Error> {
    if names.is_empty() {
        return Ok(None);
    }
    let d = names
        .iter()
        .map(|n| {
            n.trim()
                .parse::<DriveTerm>()
                .map_err(|e| format!("--drive: unknown term `{}`; {}", n.trim(), e.expected))
        })
        .collect::<Result<Drive, _>>()?;
    Ok(Some(d))
}

/// Reads the description at `path`, warns on stderr about what it probably does not mean,
/// and gives every joint the drive terms of `drive` when any are named.
pub(crate) fn read(path: &Path, drive: &DriveFlag) -> Result<Robot, Error> {
    let (mut robot, warnings) = Robot::from_file_with_warnings(path)?;
    if let Some(d) = parse_drive(&drive.drive)? {
        robot = robot.with_drive(d);
    } else {
        for w in &warnings {
            out::warn(format_args!("warning: {w}"));
        }
    }
    Ok(robot)
}
