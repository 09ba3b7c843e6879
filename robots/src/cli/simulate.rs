//! `robid simulate ROBOT.toml --parameters PARAMS.toml --trajectory TRAJ.csv -o DATA.csv`:
//! closed-loop simulation with noise (robid_runtime::simulate), writing
//! `t,q1..,qd1..,qdd1..,tau1..`. Also holds what `excite` shares: the interpreted model of
//! a description and the parameter file reader.

use std::path::{Path, PathBuf};

use robid_runtime::Model;
use robid_runtime::simulate::{Noise, Simulation, Trajectory};
use robid_symbolic::{Drive, Robot};
use robots::interpreted::Interpreted;

use super::Error;

/// Arguments of `robid simulate`.
#[derive(Debug, clap::Args)]
pub(crate) struct Args {
    /// Robot description (TOML).
    robot: PathBuf,
    /// Parameter file with a `[standard]` (missing names are 0) or a `[base]` table.
    #[arg(long)]
    parameters: PathBuf,
    /// Reference trajectory (CSV with header t,q1..,qd1..,qdd1..).
    #[arg(long)]
    trajectory: PathBuf,
    /// Drive terms added to every joint, e.g. `Fv,Fc` (default: the description's).
    #[arg(long, value_delimiter = ',')]
    drive: Vec<String>,
    /// Torque noise standard deviation (N m): one value, or one per joint separated by commas.
    #[arg(long, value_delimiter = ',', default_value = "0")]
    torque_noise: Vec<f64>,
    /// Position noise standard deviation (rad).
    #[arg(long, default_value_t = 0.0)]
    position_noise: f64,
    /// Encoder resolution (rad per count); 0 for none.
    #[arg(long, default_value_t = 0.0)]
    quantization: f64,
    /// PD loop bandwidth (Hz).
    #[arg(long, default_value_t = 10.0)]
    bandwidth: f64,
    /// Seed of the noise.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Output CSV.
    #[arg(short, long)]
    output: PathBuf,
}

/// Runs the subcommand.
pub(crate) fn run(args: &Args) -> Result<(), Error> {
    let model = load_model(&args.robot, &args.drive)?;
    let base = super::parameters::base_parameters(&args.parameters, &model)?;
    let reference = Trajectory::read_csv(&args.trajectory, model.dof())?;
    let sim = Simulation {
        bandwidth: args.bandwidth,
        seed: args.seed,
        noise: Noise {
            torque: args.torque_noise.clone(),
            position: args.position_noise,
            quantization: args.quantization,
            ..Noise::default()
        },
        ..Simulation::default()
    };
    let out = sim.run(&model, &base, &reference)?;
    out.measured.write_csv(&args.output)?;
    println!(
        "{}: {} samples simulated, written to {}",
        model.name(),
        reference.samples(),
        args.output.display()
    );
    Ok(())
}

/// The drive terms named on the command line (`Ia`, `Fv`, `Fc`, `Fo`).
pub(crate) fn parse_drive(names: &[String]) -> Result<Option<Drive>, Error> {
    if names.is_empty() {
        return Ok(None);
    }
    let mut d = Drive::NONE;
    for n in names {
        match n.trim() {
            "Ia" => d.ia = true,
            "Fv" => d.fv = true,
            "Fc" => d.fc = true,
            "Fo" => d.fo = true,
            other => {
                return Err(
                    format!("--drive: unknown term `{other}`; use Ia, Fv, Fc or Fo").into(),
                );
            }
        }
    }
    Ok(Some(d))
}

/// Reads and derives a description, with the drive terms named by `drive` when
/// given, as an interpreted `Model` (the one adapter, `robots::interpreted`).
pub(crate) fn load_model(path: &Path, drive: &[String]) -> Result<Interpreted, Error> {
    let mut robot = Robot::from_file(path)?;
    if let Some(d) = parse_drive(drive)? {
        robot = robot.with_drive(d);
    }
    Ok(Interpreted::new(&robot)?)
}
