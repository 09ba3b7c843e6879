//! `robid excite ROBOT.toml [options] -o TRAJ.csv`: an exciting trajectory (finite Fourier
//! series, Swevers et al. 1997) optimised for the condition number (or D-optimality) of the
//! stacked base regressor within the description's joint limits; prints the condition number
//! and the margin to every limit. The trajectory has the header `t,q1..,qd1..,qdd1..`.

use std::path::PathBuf;
use std::time::Instant;

use robid_runtime::Model;
use robid_runtime::excite::{Criterion, FourierDesign, JointLimits, assess};

use super::Error;
use super::simulate::{Interpreted, read_parameters};

/// Arguments of `robid excite`.
#[derive(Debug, clap::Args)]
pub(crate) struct Args {
    /// Robot description (TOML) with joint limits.
    robot: PathBuf,
    /// Design method (the finite Fourier series of Swevers et al.).
    #[arg(long, value_enum, default_value_t = Method::Fourier)]
    method: Method,
    /// Duration (s): a whole number of periods 1 / base frequency.
    #[arg(long, default_value_t = 30.0)]
    duration: f64,
    /// Sample rate of the output (Hz).
    #[arg(long, default_value_t = 500.0)]
    rate: f64,
    /// Seed of the random starts.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Drive terms in the regressor, e.g. `Fv,Fc` (default: the description's).
    #[arg(long, value_delimiter = ',')]
    drive: Vec<String>,
    /// Harmonics per joint.
    #[arg(long, default_value_t = 5)]
    harmonics: usize,
    /// Base frequency (Hz).
    #[arg(long, default_value_t = 0.1)]
    base_frequency: f64,
    /// Criterion: `cond` (condition number) or `d` (D-optimality).
    #[arg(long, value_enum, default_value_t = CriterionArg::Cond)]
    criterion: CriterionArg,
    /// Random starts.
    #[arg(long, default_value_t = 8)]
    restarts: usize,
    /// Function evaluations per start.
    #[arg(long, default_value_t = 3000)]
    evaluations: usize,
    /// Reference parameters (`[standard]` or `[base]`): enables the torque limits.
    #[arg(long)]
    parameters: Option<PathBuf>,
    /// Output CSV.
    #[arg(short, long)]
    output: PathBuf,
}

#[derive(Debug, Clone, Copy, clap::ValueEnum)]
enum Method {
    /// Finite Fourier series.
    Fourier,
}

#[derive(Debug, Clone, Copy, clap::ValueEnum)]
enum CriterionArg {
    /// 2-norm condition number.
    Cond,
    /// D-optimality.
    D,
}

/// Runs the subcommand.
pub(crate) fn run(args: &Args) -> Result<(), Error> {
    let model = Interpreted::load(&args.robot, &args.drive)?;
    let limits = model
        .programs
        .robot
        .joints
        .iter()
        .enumerate()
        .map(|(j, joint)| {
            let l = &joint.limits;
            let missing = |what: &str| {
                format!(
                    "{}: joint {} has no {what} limit; add `limits = {{ position = [lo, hi], velocity = .., acceleration = .. }}`",
                    args.robot.display(),
                    j + 1
                )
            };
            Ok(JointLimits {
                position: l.position.ok_or_else(|| missing("position"))?,
                velocity: l.velocity.ok_or_else(|| missing("velocity"))?,
                acceleration: l.acceleration.ok_or_else(|| missing("acceleration"))?,
                torque: l.torque,
            })
        })
        .collect::<Result<Vec<_>, String>>()?;
    let reference = match &args.parameters {
        Some(p) => Some(read_parameters(p, &model)?),
        None => None,
    };
    let periods = args.duration * args.base_frequency;
    if (periods - periods.round()).abs() > 1e-9 || periods.round() < 1.0 {
        return Err(format!(
            "--duration {} s is not a whole number of periods of {} s; choose a multiple of 1 / --base-frequency so the trajectory ends at rest",
            args.duration,
            1.0 / args.base_frequency
        )
        .into());
    }
    let Method::Fourier = args.method;
    let design = FourierDesign {
        harmonics: args.harmonics,
        base_frequency: args.base_frequency,
        criterion: match args.criterion {
            CriterionArg::Cond => Criterion::Condition,
            CriterionArg::D => Criterion::DOptimal,
        },
        restarts: args.restarts,
        evaluations: args.evaluations,
        seed: args.seed,
        progress: true,
        ..FourierDesign::default()
    };
    let start = Instant::now();
    let result = design.optimize(&model, &limits, reference.as_deref())?;
    let elapsed = start.elapsed();
    let trajectory = result.fourier.sample(args.duration, args.rate)?;
    trajectory.write_csv(&args.output)?;
    let a = assess(&model, &trajectory, &limits, reference.as_deref(), 1);
    println!(
        "{}: {} base parameters, {} s at {} Hz written to {}",
        model.name(),
        model.base_parameter_count(),
        args.duration,
        args.rate,
        args.output.display()
    );
    println!(
        "condition number {:.2} ({} samples stacked); optimised in {:.1} s ({} evaluations)",
        a.condition_number,
        a.samples,
        elapsed.as_secs_f64(),
        result.evaluations
    );
    println!("margins to the limits (limit - peak; position: distance to each end):");
    println!("joint  pos_low  pos_high  velocity  acceleration  torque");
    for (j, m) in a.margins.iter().enumerate() {
        let torque = m.torque.map_or("-".to_string(), |t| format!("{t:.2}"));
        println!(
            "{:5}  {:7.3}  {:8.3}  {:8.3}  {:12.3}  {torque}",
            j + 1,
            m.position_low,
            m.position_high,
            m.velocity,
            m.acceleration
        );
    }
    if !a.within_limits() {
        return Err("the sampled trajectory exceeds a limit (see the margins); lower the rate of change or the safety factor".into());
    }
    Ok(())
}
