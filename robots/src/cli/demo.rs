//! `robid demo`: the main job on a built-in default robot, with no arguments.
//!
//! For now: the UR5e's complete model (parameters, base parameters, operation
//! counts). The identification pipeline will extend it to a full run.

use super::Error;
use robid_symbolic::Robot;

/// The default robot's description, built in.
const UR5E: &str = include_str!("../../descriptions/ur5e.toml");

/// Runs the demo.
pub(crate) fn run() -> Result<(), Error> {
    let robot = Robot::from_toml(UR5E, "robots/descriptions/ur5e.toml")?;
    print!("{}", super::model::render(&robot, false)?);
    Ok(())
}
