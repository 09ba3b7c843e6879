//! `robid simulate ROBOT.toml --parameters PARAMS.toml --trajectory TRAJ.csv -o DATA.csv`:
//! closed-loop simulation with noise (robid_runtime::simulate), writing
//! `t,q1..,qd1..,qdd1..,tau1..`. Also holds what `excite` shares: the interpreted model of
//! a description and the parameter file reader.
//!
//! The PD loop's `--bandwidth` is at most a quarter of the trajectory's sample rate
//! (taken at its largest time step): the reference is known only at its samples, and
//! beyond that the integration would diverge. The result is checked before it is
//! written: every value finite and the simulated positions (with `--flexible` the true
//! link positions) within [`TRACKING_LIMIT`] of the trajectory (plus ten times the
//! position noise and quantization).

use std::path::{Path, PathBuf};

use robid_runtime::data::SLOW_SAMPLE_RATE;
use robid_runtime::limits::{MIN_RESOLUTION, MIN_SAMPLE_RATE};
use robid_runtime::signal::Signals;
use robid_runtime::simulate::{Flexibility, Noise, Record, SimulateError, Simulation, Trajectory};
use robid_runtime::{Count, Model, Num, Series, num};
use robots::interpreted::Interpreted;

use super::description::{self, Description, DescriptionFlags};
use super::flags::{self, closed, either_sign, positive, real, zero_or};
use super::{Error, files, out};

/// How far (rad or m) the simulated positions may leave the reference before the run
/// counts as diverged.
pub(crate) const TRACKING_LIMIT: f64 = 1.0;

/// Arguments of `robid simulate`.
#[derive(Debug, clap::Args)]
pub(crate) struct Args {
    #[arg(help = description::robot_help!())]
    robot: PathBuf,
    /// Parameter file with a `[standard]` (missing names are 0) or a `[base]` table
    /// (values within +-1e6, see README "Parameter files"); default for a URDF: its own
    /// `<inertial>` elements.
    #[arg(long)]
    parameters: Option<PathBuf>,
    /// Reference trajectory (CSV with header t,q1..,qd1..,qdd1..; states within +-1e6).
    #[arg(long)]
    trajectory: PathBuf,
    #[command(flatten)]
    description: DescriptionFlags,
    /// Torque noise standard deviation in [0, 1e6] N m: one value, or one per joint
    /// separated by commas.
    #[arg(long, value_delimiter = ',', default_value = "0",
          value_parser = real(closed(0.0, 1e6, "N m")))]
    torque_noise: Vec<f64>,
    /// Position noise standard deviation in [0, 1] rad (m for a prismatic joint).
    #[arg(long, default_value_t = 0.0, value_parser = real(closed(0.0, 1.0, "rad")))]
    position_noise: f64,
    /// Encoder resolution per count: 0 or [1e-12, 1] rad (0: none).
    #[arg(long, default_value_t = 0.0,
          value_parser = real(zero_or(MIN_RESOLUTION, 1.0, "rad")))]
    quantization: f64,
    /// PD loop bandwidth in (0, 1e4] Hz, at most a quarter of the trajectory's sample rate.
    #[arg(long, default_value_t = 10.0, value_parser = real(positive(1e4, "Hz")))]
    bandwidth: f64,
    /// Seed of the noise (0 to 2^64 - 1).
    #[arg(long, default_value_t = 1, value_parser = flags::seed)]
    seed: u64,
    /// What to write: `all` (`t,q,qd,qdd,tau`, velocities and accelerations exact, for
    /// checking) or `positions` (`t,q,tau`, as a real log: `identify` differentiates).
    /// [default: all]
    #[arg(long, value_enum)]
    columns: Option<Columns>,
    /// Write every sample at this rate, in [0.001, 1e6] Hz (a whole fraction of the
    /// trajectory's rate; default: the trajectory's rate). `--columns positions` only.
    #[arg(long, value_parser = real(closed(MIN_SAMPLE_RATE, 1e6, "Hz")))]
    rate: Option<f64>,
    /// Write motor currents `i1..in` instead of torques: the torque per ampere at each
    /// joint (torque constant times gear ratio), `k1,..,kn` of magnitude in [1e-6, 1e6]
    /// N m/A, negative for a motor wired the other way round (`--currents=-2,3`).
    /// `--columns positions` only.
    #[arg(
        long,
        value_delimiter = ',',
        allow_hyphen_values = true,
        value_parser = real(either_sign(1e-6, 1e6, "N m/A"))
    )]
    currents: Vec<f64>,
    /// Joint-flexibility file (TOML: per joint the transmission's stiffness, hardening and
    /// damping, rotor inertia, gear ratio, torque constant and rotor friction; the drives'
    /// temperature): simulate a robot with two encoders per joint, under a motor-side
    /// controller, and write what it logs, `t,q1..,theta1..,i1..,T1..` (link encoders,
    /// motor encoders in motor radians, currents, temperatures; `--rate` applies).
    #[arg(long)]
    flexible: Option<PathBuf>,
    /// With `--flexible`: also write the true joint torques `tauJ1..` (for checking; a
    /// robot without joint-torque sensors does not log them).
    #[arg(long)]
    joint_torque: bool,
    /// Output CSV.
    #[arg(short, long)]
    output: PathBuf,
}

/// The columns `robid simulate` writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum Columns {
    /// `t,q1..,qd1..,qdd1..,tau1..`.
    All,
    /// `t,q1..,tau1..` (or `i1..` with `--currents`).
    Positions,
}

/// Runs the subcommand.
pub(crate) fn run(args: &Args) -> Result<(), Error> {
    let mut inputs = vec![args.robot.as_path(), &args.trajectory];
    inputs.extend(args.parameters.as_deref());
    inputs.extend(args.flexible.as_deref());
    files::refuse(&inputs, &[("--output", &args.output)])?;
    let description = description::load(&args.robot, &args.description)?;
    let model = Interpreted::new(&description.robot)?;
    let n = model.dof();
    if args.torque_noise.len() != 1 && args.torque_noise.len() != n {
        return Err(format!(
            "--torque-noise has {} but {} has {}; give one value or {}",
            Count(args.torque_noise.len(), "value"),
            args.robot.display(),
            Count(n, "joint"),
            Series("s", n)
        )
        .into());
    }
    log_settings(args, n)?;
    let base = description.base_parameters(args.parameters.as_deref(), &model)?;
    // a log of positions given as the reference (a recorded run): it needs the velocities
    // and accelerations the PD loop follows, which `robid excite` writes with the positions
    let remedy = format!(
        "; or design a reference trajectory with them: `robid excite {} -o TRAJ.csv`",
        args.robot.display()
    );
    super::states::read_with(&args.trajectory, &Trajectory::header(n), n, &remedy)?;
    let reference = Trajectory::read_csv(&args.trajectory, n)?;
    let span = reference.q.extremes();
    for w in robots::limits::trajectory_beyond_limits(&description.robot, &span, &args.robot) {
        out::warn(format_args!("warning: {}: {w}", args.trajectory.display()));
    }
    check_bandwidth(args.bandwidth, &reference, &args.trajectory)?;
    let every = every_sample(args.rate, &reference, &args.trajectory)?;
    let sim = Simulation {
        bandwidth: args.bandwidth,
        seed: args.seed,
        progress: true,
        noise: Noise {
            torque: args.torque_noise.clone(),
            position: args.position_noise,
            quantization: args.quantization,
            ..Noise::default()
        },
        ..Simulation::default()
    };
    unloaded(args, &description)?;
    if let Some(path) = &args.flexible {
        return run_flexible(
            args,
            &description,
            path,
            &model,
            &base,
            &reference,
            &sim,
            every,
        );
    }
    let result = sim
        .run(&model, &base, &reference)
        .map_err(|e| refused(args, &description, e))?;
    let tolerance = TRACKING_LIMIT + 10.0 * (args.position_noise + args.quantization);
    check_result(&result.truth, &reference, tolerance)?;
    check_result(&result.measured, &reference, f64::INFINITY)?;
    match args.columns.unwrap_or(Columns::All) {
        Columns::All => result.measured.write_csv(&args.output)?,
        Columns::Positions => {
            let currents = (!args.currents.is_empty()).then_some(args.currents.as_slice());
            result
                .measured
                .write_log_csv(&args.output, every, currents)
                .map_err(|e| on_current_flags(args, &result.measured, every, e))?;
        }
    }
    let mut stdout = out::Stdout::new();
    writeln!(
        stdout,
        "{}: {} samples simulated, {}written to {}",
        model.name(),
        reference.samples(),
        written(reference.samples(), every),
        args.output.display()
    )?;
    stdout.flush()?;
    Ok(())
}

/// The error of a simulation run as the user should read it: a run refused because
/// joints move no mass or inertia ([`SimulateError::NoInertia`]) with a URDF's own
/// inertials as the parameters names those joints and their links as the URDF does, and
/// the ways out (the links' `<inertial>` elements, or `--parameters`). ROS-Industrial
/// support packages leave every `<inertial>` out.
///
/// Joints whose motions coincide ([`SimulateError::Coinciding`]) of a URDF are also named
/// as the URDF names them, with the links between them.
fn refused(args: &Args, description: &Description, e: robid_runtime::Error) -> Error {
    if let (Some(chain), robid_runtime::Error::Simulate(SimulateError::Coinciding { joints, .. })) =
        (&description.urdf, &e)
    {
        let name = |j: usize| chain.links.get(j - 1).map(|l| (&l.joint, &l.link));
        let (Some(&lowest), Some(&highest)) = (joints.first(), joints.last()) else {
            return e.into();
        };
        let mut named: Vec<String> = joints
            .iter()
            .filter_map(|&j| name(j).map(|(joint, _)| format!("joint {j} is `{joint}`")))
            .collect();
        named.extend(
            (lowest..highest)
                .filter_map(|k| name(k).map(|(_, link)| format!("link {k} is `{link}`"))),
        );
        return format!("{e} (in {}: {})", args.robot.display(), named.join(", ")).into();
    }
    let (
        Some(chain),
        None,
        robid_runtime::Error::Simulate(SimulateError::NoInertia { joints, .. }),
    ) = (&description.urdf, &args.parameters, &e)
    else {
        return e.on_flags(SIMULATION_FLAGS).into();
    };
    if !joints
        .first()
        .is_some_and(|&j| (1..=chain.links.len()).contains(&j))
    {
        return e.into();
    }
    no_inertia(args, description, joints)
}

/// The error of a log whose current `iJ` would be beyond what robid's readers accept
/// ([`SimulateError::Unreadable`]: the torque over a tiny `--currents` value, a large
/// `--torque-noise` included) with the fix in flags; any other error as it is.
fn on_current_flags(
    args: &Args,
    record: &Record,
    every: usize,
    mut e: robid_runtime::Error,
) -> robid_runtime::Error {
    if let robid_runtime::Error::Simulate(SimulateError::Unreadable {
        column, limit, fix, ..
    }) = &mut e
        && let Some(j) = column
            .strip_prefix('i')
            .and_then(|j| j.parse::<usize>().ok())
            .filter(|j| (1..=args.currents.len()).contains(j))
    {
        let largest = record.largest_torque(j - 1, every);
        // one value for every joint, or one per joint (checked before the run)
        let noise = args.torque_noise[(j - 1).min(args.torque_noise.len() - 1)];
        *fix = format!(
            "the torque of joint {j} reaches {} N m (--torque-noise {} N m included), and \
             --currents gives it {} N m/A: give --currents a value of magnitude at least \
             {} N m/A for joint {j}, or a smaller --torque-noise",
            Num::rounded(largest, 4),
            num(noise),
            num(args.currents[j - 1]),
            Num::rounded(largest / *limit, 3)
        );
    }
    e
}

/// The joints (numbered from 1) that a URDF's own inertials leave without mass or inertia,
/// when they are the parameters (no `--parameters`): 0 or negligible beside the chain's
/// largest (`Description::urdf_unloaded`). Such a robot is refused before the run, as a
/// singular mass matrix would refuse it: a mass of 1e-320 kg left M(q) nonsingular in
/// name, and the run wrote torques of 1e-321 N m (no digits) as data.
fn unloaded(args: &Args, description: &Description) -> Result<(), Error> {
    if args.parameters.is_some() {
        return Ok(());
    }
    let empty = description.urdf_unloaded().empty;
    if empty.is_empty() {
        return Ok(());
    }
    Err(no_inertia(args, description, &empty))
}

/// The error of `joints` (numbered from 1, within the chain, not empty) of a URDF that
/// move no mass or inertia with its own inertials: the joints and their links as the URDF
/// names them, and the ways out.
fn no_inertia(args: &Args, description: &Description, joints: &[usize]) -> Error {
    let Some(chain) = &description.urdf else {
        return "the robot moves no mass or inertia; give --parameters PARAMS.toml".into();
    };
    let lowest = joints.first().copied().unwrap_or(1).max(1);
    let one = joints.len() == 1;
    let (it, its, moves) = if one {
        ("it", "its", "moves")
    } else {
        ("them", "their", "move")
    };
    // the bodies the lowest of them moves: its own and every one after it
    let cause = if (lowest - 1..chain.links.len()).all(|k| chain.empty(k)) {
        description.unloaded_cause(&args.robot, joints, true)
    } else {
        let named: Vec<String> = joints
            .iter()
            .map(|&j| {
                format!(
                    "{j} (`{}`)",
                    chain.links.get(j - 1).map_or("?", |l| l.joint.as_str())
                )
            })
            .collect();
        let named = match named.split_last() {
            Some((last, [])) => format!("joint {last}"),
            Some((last, first)) => format!("joints {} and {last}", first.join(", ")),
            None => String::new(),
        };
        let all: Vec<String> = chain.links[lowest - 1..]
            .iter()
            .flat_map(|link| {
                std::iter::once(&link.link).chain(link.attached.iter().map(|a| &a.name))
            })
            .map(|name| format!("`{name}`"))
            .collect();
        format!(
            "{named} of {} {moves} no mass or inertia about {its} axis: the links {it} \
             {moves} ({}) carry none about it in the URDF",
            args.robot.display(),
            all.join(", ")
        )
    };
    format!(
        "{cause}, so no torque accelerates {it} and the robot cannot be simulated with the \
         URDF's own inertials (the mass matrix is singular); give these links `<inertial>` \
         elements with their mass and inertia, or give --parameters PARAMS.toml (a \
         [standard] or [base] parameter file)"
    )
    .into()
}

/// `--flexible`: the two-encoder log of a robot with flexible joints, and the largest
/// deflection per joint on standard output.
#[allow(clippy::too_many_arguments)]
fn run_flexible(
    args: &Args,
    description: &Description,
    path: &Path,
    model: &Interpreted,
    base: &[f64],
    reference: &Trajectory,
    sim: &Simulation,
    every: usize,
) -> Result<(), Error> {
    let flex = Flexibility::read(path)?;
    if flex.joints.len() != model.dof() {
        return Err(format!(
            "{} has {} but {} has {}; give one per joint",
            path.display(),
            Count(flex.joints.len(), "[[joint]] table"),
            args.robot.display(),
            Count(model.dof(), "joint")
        )
        .into());
    }
    let log = sim
        .run_flexible(model, base, &flex, reference)
        .map_err(|e| refused(args, description, e))?;
    // the rigid run's rule on the true link positions: a log whose joints left their
    // reference (by 2 rad beside a reference within 0.6) was written with exit 0
    let tolerance = TRACKING_LIMIT + 10.0 * (args.position_noise + args.quantization);
    check_tracking(&log.true_q, reference, tolerance).map_err(|(what, t)| {
        format!(
            "{}; with --flexible, check the joint-flexibility file {} too (a stiffness or rotor \
             inertia far from the robot's, a bandwidth near the transmission's resonance)",
            diverged(&what, t, bandwidth_limit(reference)),
            path.display()
        )
    })?;
    log.write_csv(&args.output, every, args.joint_torque)?;
    let deflection: Vec<String> = log
        .largest_deflection()
        .iter()
        .map(|d| format!("{d:.2e}"))
        .collect();
    // a prismatic joint's deflection is a length (it was said in rad)
    let prismatic = super::description::prismatic(&description.robot);
    let unit = match (prismatic.iter().any(|p| *p), prismatic.iter().all(|p| *p)) {
        (_, true) => "m",
        (true, false) => "rad or m",
        (false, _) => "rad",
    };
    let mut stdout = out::Stdout::new();
    writeln!(
        stdout,
        "{}: {} samples simulated with flexible joints (largest deflection per joint [{}] \
         {unit}), {}written to {}",
        model.name(),
        reference.samples(),
        deflection.join(" "),
        written(reference.samples(), every),
        args.output.display()
    )?;
    stdout.flush()?;
    Ok(())
}

/// Checks the log flags against `--columns`, `--flexible` and the joint count.
fn log_settings(args: &Args, n: usize) -> Result<(), Error> {
    if args.flexible.is_some() {
        for (given, flag) in [
            (args.columns.is_some(), "--columns"),
            (!args.currents.is_empty(), "--currents"),
        ] {
            if given {
                return Err(format!(
                    "{flag} does not apply with --flexible, whose log is t,q..,theta..,i..,T.. \
                     (the torque constants are in the flexibility file); drop {flag}"
                )
                .into());
            }
        }
        return Ok(());
    }
    flags::only_for(
        args.joint_torque,
        "--joint-torque",
        "--flexible",
        "a rigid simulation",
    )?;
    if args.columns.unwrap_or(Columns::All) == Columns::All {
        flags::only_for(
            args.rate.is_some(),
            "--rate",
            "--columns positions",
            "--columns all",
        )?;
        flags::only_for(
            !args.currents.is_empty(),
            "--currents",
            "--columns positions",
            "--columns all",
        )?;
    }
    if !args.currents.is_empty() && args.currents.len() != n {
        return Err(format!(
            "--currents has {} but {} has {}; give {}",
            Count(args.currents.len(), "value"),
            args.robot.display(),
            Count(n, "joint"),
            Series("k", n)
        )
        .into());
    }
    Ok(())
}

/// `"N rows "` when `--rate` writes every `every`-th of the `samples` (the first
/// included), else nothing: the count the output file has.
fn written(samples: usize, every: usize) -> String {
    if every > 1 {
        format!("{} rows ", samples.div_ceil(every))
    } else {
        String::new()
    }
}

/// Every how many trajectory samples one is written for `--rate`: the rate must be a
/// whole fraction of the trajectory's.
fn every_sample(rate: Option<f64>, reference: &Trajectory, path: &Path) -> Result<usize, Error> {
    let Some(rate) = rate else { return Ok(1) };
    let t = &reference.t;
    let own = (t.len() - 1) as f64 / (t[t.len() - 1] - t[0]);
    let every = (own / rate).round();
    if every < 1.0 || (own / rate - every).abs() > 1e-6 * every {
        // the trajectory's rate as people read it (200 Hz, not 200.000000 Hz)
        let own = robid_runtime::Num::rounded(own, 6);
        return Err(format!(
            "--rate {} Hz is not a whole fraction of the rate of {} ({own} Hz); choose \
             {own} Hz divided by a whole number, or design the trajectory at a multiple of {} \
             Hz",
            num(rate),
            path.display(),
            num(rate)
        )
        .into());
    }
    // A factor as large as the record leaves its first sample alone: a log of one row,
    // which nothing reads (every reader needs two time stamps at least).
    let samples = t.len() as f64;
    if every >= samples {
        return Err(format!(
            "--rate {} Hz keeps one of every {} samples of {}, which has {}: the log would \
             hold 1 row, and a log needs at least 2; raise --rate to at least {} Hz (one row \
             at each end), or simulate a longer trajectory",
            num(rate),
            num(every),
            path.display(),
            t.len(),
            num(own / (samples - 1.0))
        )
        .into());
    }
    Ok(every as usize)
}

/// Refuses a bandwidth above a quarter of the trajectory's sample rate at its largest step.
fn check_bandwidth(bandwidth: f64, reference: &Trajectory, path: &Path) -> Result<(), Error> {
    let limit = bandwidth_limit(reference);
    let step = 0.25 / limit;
    // (a relative margin for time stamps such as 0.01 k, whose steps differ by rounding)
    // a trajectory far slower than any robot's dynamics: the time column's unit, not the
    // bandwidth (a time column in ms was told to lower --bandwidth to 0.05 Hz)
    if 1.0 / step < SLOW_SAMPLE_RATE && bandwidth > limit * (1.0 + 1e-9) {
        return Err(format!(
            "{}: time steps of up to {} s, a sample rate of {} Hz, below the {} Hz a robot's \
             dynamics need: is its time column in milliseconds? write it in seconds (the \
             reference's loop at --bandwidth {} Hz needs steps of at most {} s)",
            path.display(),
            rounded(step),
            rounded(1.0 / step),
            num(SLOW_SAMPLE_RATE),
            num(bandwidth),
            rounded(0.25 / bandwidth)
        )
        .into());
    }
    if bandwidth > limit * (1.0 + 1e-9) {
        return Err(format!(
            "--bandwidth {} Hz is above a quarter of the sample rate of {} ({} Hz at its \
             largest time step {} s), the fastest loop the reference can drive; lower \
             --bandwidth to at most {} Hz or resample the trajectory finer",
            num(bandwidth),
            path.display(),
            rounded(1.0 / step),
            rounded(step),
            rounded(limit)
        )
        .into());
    }
    Ok(())
}

/// `x` to six significant digits, written short: a rate or step derived from time stamps
/// (24.999999999996 Hz for steps of 0.01 s) as people read it, and a slow one (2.5e-7 Hz)
/// not as 0.0000.
fn rounded(x: f64) -> String {
    num(format!("{x:.5e}").parse().unwrap_or(x))
}

/// Refuses a record with a non-finite value, or whose positions leave the reference by more
/// than `tolerance` (a diverged simulation).
fn check_result(record: &Record, reference: &Trajectory, tolerance: f64) -> Result<(), Error> {
    let tr = &record.trajectory;
    let blocks = [
        ("q", &tr.q),
        ("qd", &tr.qd),
        ("qdd", &tr.qdd),
        ("tau", &record.tau),
    ];
    for (name, block) in blocks {
        for (j, signal) in block.joints().enumerate() {
            if let Some(k) = signal.iter().position(|x| !x.is_finite()) {
                return Err(diverged(
                    &format!("{name}{} is {}", j + 1, signal[k]),
                    reference.t.get(k).copied().unwrap_or(f64::NAN),
                    bandwidth_limit(reference),
                ));
            }
        }
    }
    check_tracking(&tr.q, reference, tolerance)
        .map_err(|what| diverged(&what.0, what.1, bandwidth_limit(reference)))
}

/// The first position of `q` more than `tolerance` from the reference's, as what is wrong
/// and the time it is at.
fn check_tracking(
    q: &Signals,
    reference: &Trajectory,
    tolerance: f64,
) -> Result<(), (String, f64)> {
    for (j, (q, r)) in q.joints().zip(&reference.q).enumerate() {
        if let Some((k, e)) = q
            .iter()
            .zip(r)
            .map(|(q, r)| (q - r).abs())
            .enumerate()
            .find(|(_, e)| e.is_nan() || *e > tolerance)
        {
            return Err((
                format!("q{} is {e:.3e} away from the reference", j + 1),
                reference.t.get(k).copied().unwrap_or(f64::NAN),
            ));
        }
    }
    Ok(())
}

/// A diverged run at time `t` (`what`: which value), with the way out. The loop's bandwidth
/// is at most a quarter of the sample rate ([`check_bandwidth`]), which the integration
/// follows: a joint that leaves its reference was too slow to hold it (an arm under
/// gravity falls away from a slow loop), so the advice is to raise the bandwidth, up to
/// `limit` Hz (it said "lower --bandwidth", which made it worse).
fn diverged(what: &str, t: f64, limit: f64) -> Error {
    format!(
        "the simulation diverged: at t = {t} s, {what}; raise --bandwidth (a slower loop \
         lets a joint fall away from its reference; at most {} Hz, a quarter of the \
         trajectory's sample rate), or check the trajectory (its velocities and accelerations \
         must be the derivatives of its positions) and the parameters (a nearly singular mass \
         matrix cannot be controlled)",
        rounded(limit)
    )
    .into()
}

/// The largest bandwidth [`check_bandwidth`] accepts for `reference` (Hz).
fn bandwidth_limit(reference: &Trajectory) -> f64 {
    let step = reference
        .t
        .windows(2)
        .map(|w| w[1] - w[0])
        .fold(0.0, f64::max);
    0.25 / step
}

/// The settings of `Simulation` that flags fill, and their flags.
const SIMULATION_FLAGS: &[(&str, &str)] = &[
    ("bandwidth", "--bandwidth"),
    ("noise.torque", "--torque-noise"),
    ("noise.position", "--position-noise"),
    ("noise.quantization", "--quantization"),
];

#[cfg(test)]
mod tests {
    use super::*;

    /// A two-joint record at rest on the reference at t = 0, 0.1, 0.2.
    fn record() -> (Record, Trajectory) {
        let reference = Trajectory::zeros(2, vec![0.0, 0.1, 0.2]);
        let record = Record {
            trajectory: reference.clone(),
            tau: robid_runtime::signal::Signals::zeros(2, 3),
        };
        (record, reference)
    }

    #[test]
    fn a_record_on_the_reference_passes() {
        let (mut r, reference) = record();
        r.trajectory.q[1][2] = 0.9;
        assert!(check_result(&r, &reference, 1.0).is_ok());
    }

    #[test]
    fn a_diverged_record_is_refused_naming_the_value_and_the_time() {
        let (mut r, reference) = record();
        r.tau[1][2] = f64::INFINITY;
        let e = check_result(&r, &reference, 1.0).unwrap_err().to_string();
        assert!(e.contains("at t = 0.2 s, tau2 is inf"), "{e}");
        let (mut r, reference) = record();
        r.trajectory.q[0][1] = -1.5;
        let e = check_result(&r, &reference, 1.0).unwrap_err().to_string();
        assert!(e.contains("at t = 0.1 s, q1 is 1.500e0 away"), "{e}");
        // the loop is within the integration's reach (at most 2.5 Hz on 10 Hz samples):
        // raising it is the way out (the message said to lower it)
        assert!(
            e.contains("raise --bandwidth") && e.contains("at most 2.5 Hz"),
            "{e}"
        );
        assert!(check_result(&r, &reference, f64::INFINITY).is_ok());
    }

    /// A --rate so low that one row would be written (1e-300 Hz of a 100 Hz trajectory was
    /// a factor of 1e302, saturated to usize::MAX, and wrote a log of one row) is refused,
    /// with the lowest rate that writes two.
    #[test]
    fn a_rate_that_writes_one_row_is_refused() {
        let reference = Trajectory::zeros(1, vec![0.0, 0.01, 0.02, 0.03, 0.04]);
        let path = Path::new("t.csv");
        assert_eq!(every_sample(Some(25.0), &reference, path).unwrap(), 4);
        for rate in [20.0, 1e-300] {
            let e = every_sample(Some(rate), &reference, path)
                .unwrap_err()
                .to_string();
            assert!(
                e.contains("the log would hold 1 row") && e.contains("at least 25 Hz"),
                "{e}"
            );
        }
    }

    #[test]
    fn the_bandwidth_is_at_most_a_quarter_of_the_sample_rate() {
        let reference = Trajectory::zeros(1, vec![0.0, 0.01, 0.02, 0.04]);
        let path = Path::new("t.csv");
        assert!(check_bandwidth(12.5, &reference, path).is_ok());
        let e = check_bandwidth(13.0, &reference, path)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("--bandwidth 13 Hz")
                && e.contains("(50 Hz at its largest time step 0.02 s)")
                && e.contains("at most 12.5 Hz"),
            "{e}"
        );
        // a trajectory with steps of 1e6 s (the limit was written "at most 0.0000 Hz"):
        // slower than any robot's dynamics, told as the time column's unit
        let slow = Trajectory::zeros(1, vec![0.0, 1e6, 2e6]);
        let e = check_bandwidth(10.0, &slow, path).unwrap_err().to_string();
        assert!(
            e.contains("t.csv: time steps of up to 1e6 s, a sample rate of 1e-6 Hz")
                && e.contains("needs steps of at most 0.025 s"),
            "{e}"
        );
        // slow but fast enough for the loop asked: accepted
        let five = Trajectory::zeros(1, vec![0.0, 0.2, 0.4]);
        assert!(check_bandwidth(1.0, &five, path).is_ok());
    }
}
