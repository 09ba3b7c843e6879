//! `robid excite ROBOT.toml [options] -o TRAJ.csv`: an exciting trajectory optimised for the
//! condition number (or D-optimality) of the stacked base regressor within the description's
//! joint limits, either a finite Fourier series (`--method fourier`, Swevers et al. 1997) or
//! optimal points joined by 7th-order polynomials (`--method points`, Milella); it
//! starts and ends at rest at `--start` (default: the middle of the position limits; a
//! URDF's continuous joint, which has none, stays within ±pi of its start). Prints
//! the condition number and the margin to every limit. The trajectory has the header
//! `t,q1..,qd1..,qdd1..`.

use std::f64::consts::PI;
use std::path::{Path, PathBuf};
use std::time::Instant;

use robid_runtime::excite::{
    Criterion, FourierDesign, Information, JointLimits, PointDesign, assess, margins,
    weights_from_sigma,
};
use robid_runtime::limits::{MAX_SAMPLE_RATE, MIN_JOINT_LIMIT};
use robid_runtime::simulate::Trajectory;
use robid_runtime::{Count, Model, Num, Series, num};

use super::description::{self, DescriptionFlags};
use super::flags::{self, check_samples, closed, count, only_for, positive, real};
use super::idle::Idle;
use super::{Error, files, out};
use robid_symbolic::robot::bounds;
use robots::interpreted::Interpreted;

/// Arguments of `robid excite`.
#[derive(Debug, clap::Args)]
pub(crate) struct Args {
    #[arg(help = description::robot_help!("the robot and its joint limits"))]
    robot: PathBuf,
    /// Design method: `fourier` (finite Fourier series, Swevers et al.) or `points` (optimal
    /// position, velocity and acceleration points with 7th-order polynomials, Milella).
    #[arg(long, value_enum, default_value_t = Method::Fourier)]
    method: Method,
    /// Duration in (0, 1e6] s (`fourier`: a whole number of periods 1 / base frequency).
    /// Duration x rate is a whole number of sample periods, at most 1e6.
    #[arg(long, default_value_t = 30.0, value_parser = real(positive(1e6, "s")))]
    duration: f64,
    /// Sample rate of the output in [0.001, 1e6] Hz. Duration x rate is at least 2 (three
    /// samples: both ends and one between).
    #[arg(long, default_value_t = 500.0, value_parser = real(closed(1e-3, 1e6, "Hz")))]
    rate: f64,
    /// Seed of the random starts (0 to 2^64 - 1).
    #[arg(long, default_value_t = 1, value_parser = flags::seed)]
    seed: u64,
    /// Start (and end) position `q1,..,qn`, at rest, inside the position limits (default:
    /// the middle of the position limits; a URDF's continuous joint, which has none, is
    /// kept within ±pi of its start, default 0). Each value in [-1e3, 1e3] rad or m, the
    /// bound of a description's position limits.
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true,
          value_parser = real(closed(-bounds::MAX_POSITION, bounds::MAX_POSITION, "rad or m")))]
    start: Vec<f64>,
    /// Expected torque noise per joint `s1,..,sn`, each in [1e-9, 1e6] N m: weights the
    /// regressor rows by 1 / s (what weighted least squares sees). Default: unweighted.
    #[arg(long, value_delimiter = ',', value_parser = real(closed(1e-9, 1e6, "N m")))]
    sigma: Vec<f64>,
    #[command(flatten)]
    description: DescriptionFlags,
    /// Acceleration limits `a1,..,an` (or one for every joint), each in [1e-6, 1e6]: replace
    /// the description's (a URDF states none).
    #[arg(long, value_delimiter = ',',
          value_parser = real(closed(MIN_JOINT_LIMIT, 1e6, "rad/s^2")))]
    acceleration_limits: Vec<f64>,
    /// Velocity limits `v1,..,vn` (or one for every joint), each in [1e-6, 1e4] (m/s for a
    /// prismatic joint): replace the description's, or give those it lacks (a URDF joint
    /// without `velocity` in a `<limit>`, e.g. a continuous joint without `<limit>`).
    #[arg(long, value_delimiter = ',',
          value_parser = real(closed(MIN_JOINT_LIMIT, 1e4, "rad/s")))]
    velocity_limits: Vec<f64>,
    /// Intervals between optimised points, 2 to 200 (`--method points` only; default 12).
    #[arg(long, value_parser = count(2, 200))]
    intervals: Option<usize>,
    /// Sweeps over the points per start, 1 to 1000 (`--method points` only; default 4).
    #[arg(long, value_parser = count(1, 1000))]
    sweeps: Option<usize>,
    /// Harmonics per joint, 2 to 50 (`--method fourier` only; default 5); the highest,
    /// harmonics x base frequency, must lie below --rate / 2.
    #[arg(long, value_parser = count(2, 50))]
    harmonics: Option<usize>,
    /// Base frequency in [1e-6, 100] Hz (`--method fourier` only; default 0.1): a lower one
    /// has a period longer than the longest --duration, 1e6 s.
    #[arg(long, value_parser = real(closed(1e-6, 100.0, "Hz")))]
    base_frequency: Option<f64>,
    /// Criterion: `cond` (condition number) or `d` (D-optimality).
    #[arg(long, value_enum, default_value_t = CriterionArg::Cond)]
    criterion: CriterionArg,
    /// Random starts, 1 to 1000 (default: 8 for `fourier`, 4 for `points`).
    #[arg(long, value_parser = count(1, 1000))]
    restarts: Option<usize>,
    /// Function evaluations per start (`fourier`; default 3000) or per point and sweep
    /// (`points`; default 120), 1 to 1e6.
    #[arg(long, value_parser = count(1, 1_000_000))]
    evaluations: Option<usize>,
    /// Reference parameters (`[standard]` or `[base]`): enables the torque limits (default
    /// for a URDF: its own `<inertial>` elements).
    #[arg(long)]
    parameters: Option<PathBuf>,
    /// Milella's piece-wise identification (`--method points` only): choose the widths of
    /// the pieces around the points by minimising the extended regressor's condition
    /// number, and write them to this TOML file as `[processing] pieces = [[start, end],
    /// ..]` for the identification config.
    #[arg(long)]
    pieces: Option<PathBuf>,
    /// Output CSV.
    #[arg(short, long)]
    output: PathBuf,
}

#[derive(Debug, Clone, Copy, clap::ValueEnum)]
enum Method {
    /// Finite Fourier series.
    Fourier,
    /// Optimal points joined by 7th-order polynomials.
    Points,
}

#[derive(Debug, Clone, Copy, clap::ValueEnum)]
enum CriterionArg {
    /// 2-norm condition number.
    Cond,
    /// D-optimality.
    D,
}

/// Refuses what cannot work before any work: an output that is an input, too many
/// samples, the options of the other method, too fine a harmonic for the sample rate.
fn check(args: &Args) -> Result<(), Error> {
    let mut inputs = vec![args.robot.as_path()];
    inputs.extend(args.parameters.as_deref());
    let mut outputs = vec![("--output", args.output.as_path())];
    outputs.extend(args.pieces.as_deref().map(|p| ("--pieces", p)));
    files::refuse(&inputs, &outputs)?;
    check_samples(args.duration, args.rate)?;
    match args.method {
        Method::Fourier => {
            let (method, owner) = ("--method fourier", "--method points");
            only_for(args.intervals.is_some(), "--intervals", owner, method)?;
            only_for(args.pieces.is_some(), "--pieces", owner, method)?;
            only_for(args.sweeps.is_some(), "--sweeps", owner, method)?;
            let highest = args.harmonics.unwrap_or(HARMONICS) as f64
                * args.base_frequency.unwrap_or(BASE_FREQUENCY);
            if 2.0 * highest >= args.rate {
                return Err(format!(
                    "--rate {} Hz is too low for the highest harmonic ({} Hz = --harmonics \
                     x --base-frequency): sample at more than twice its frequency, or lower \
                     --harmonics or --base-frequency",
                    num(args.rate),
                    num(highest)
                )
                .into());
            }
        }
        Method::Points => {
            let (method, owner) = ("--method points", "--method fourier");
            only_for(args.harmonics.is_some(), "--harmonics", owner, method)?;
            only_for(
                args.base_frequency.is_some(),
                "--base-frequency",
                owner,
                method,
            )?;
            // an interval the samples cannot follow: the search ran for a minute on 200
            // intervals of 5 ms at 100 Hz, then blamed the joints' room to move
            let intervals = args.intervals.unwrap_or(POINT_INTERVALS);
            let per_interval = args.duration * args.rate / intervals as f64;
            if per_interval < 2.0 {
                // (2 intervals is the least a design has)
                let fewer = if intervals > 2 {
                    "fewer --intervals, "
                } else {
                    ""
                };
                return Err(format!(
                    "--intervals {intervals} over --duration {} s gives intervals of {} s, \
                     {} each at --rate {} Hz, too few to follow one: give at least two \
                     samples per interval ({fewer}a longer --duration or a higher --rate)",
                    num(args.duration),
                    Num::rounded(args.duration / intervals as f64, 4),
                    samples(Num::rounded(per_interval, 3)),
                    num(args.rate)
                )
                .into());
            }
        }
    }
    Ok(())
}

/// How much finer than the design's own grid the margins are evaluated: the peaks between
/// its points exceeded those on it by up to 1e-3 (the overstatement falls with the square
/// of the spacing).
const FINER: usize = 64;
/// The most points of that evaluation (`--method points` with many intervals).
const MAX_FINE: usize = 200_000;

/// The rate of the grid on which the margins between the design's points are evaluated:
/// `rate`, capped at the readers' largest, [`MAX_SAMPLE_RATE`] (a grid the sampler refuses
/// failed the run after its optimisation, as a `--rate` never given; capped, the grid is
/// still ten times finer than any written trajectory, whose `--rate` is at most 1e6 Hz).
fn fine_rate(rate: f64) -> f64 {
    rate.min(MAX_SAMPLE_RATE)
}

/// `n` samples, in a message: "1 sample" (it said "1 samples"), "1.5 samples", "3 samples"
/// (a whole count through [`Count`]).
fn samples(n: Num) -> String {
    let shown = n.to_string();
    match shown.parse::<usize>() {
        Ok(k) => Count(k, "sample").to_string(),
        Err(_) => format!("{shown} samples"),
    }
}

/// Default intervals of `--method points`.
const POINT_INTERVALS: usize = 12;

/// Default harmonics per joint of `--method fourier`.
const HARMONICS: usize = 5;
/// Default base frequency (Hz) of `--method fourier`.
const BASE_FREQUENCY: f64 = 0.1;

/// The settings of `FourierDesign`, `PointDesign` and the sampling that flags fill, and
/// their flags.
const DESIGN_FLAGS: &[(&str, &str)] = &[
    ("harmonics", "--harmonics"),
    ("base_frequency", "--base-frequency"),
    ("restarts", "--restarts"),
    ("evaluations", "--evaluations"),
    ("duration", "--duration"),
    ("intervals", "--intervals"),
    ("sweeps", "--sweeps"),
    ("rate", "--rate"),
];

/// With a URDF's own inertials as the reference: warns about the joints with a torque
/// limit that move only links without mass or inertia, or prismatic ones that move only
/// links without mass, whose torque or force the reference gives as 0, so that the limit
/// constrains nothing. Nothing else of such a joint matters: the
/// criterion is that of the regressor, which does not depend on the parameters, and a
/// joint without a torque limit is not checked against the reference at all.
fn warn_unloaded(args: &Args, description: &description::Description, limits: &[JointLimits]) {
    let unloaded = description.urdf_unloaded();
    let limited = |joints: Vec<usize>| -> Vec<usize> {
        joints
            .into_iter()
            .filter(|&j| limits.get(j - 1).is_some_and(|l| l.torque.is_some()))
            .collect()
    };
    // a sliding joint's force is 0 when the links it moves have no mass, whatever their
    // inertia
    for (limited, empty) in [
        (limited(unloaded.empty), true),
        (limited(unloaded.sliding), false),
    ] {
        if !limited.is_empty() {
            warn_limited(args, description, &limited, empty);
        }
    }
}

/// The warning of [`warn_unloaded`] for the joints `limited` (with torque limits) that move
/// only links without mass or inertia (`empty`), or prismatic ones that move only links
/// without mass.
fn warn_limited(
    args: &Args,
    description: &description::Description,
    limited: &[usize],
    empty: bool,
) {
    let one = limited.len() == 1;
    let (it, its, limit, constrains, margin) = if one {
        (
            "it",
            "its",
            "its torque limit",
            "constrains",
            "its torque margin below is the whole limit",
        )
    } else {
        (
            "them",
            "their",
            "their torque limits",
            "constrain",
            "their torque margins below are the whole limits",
        )
    };
    out::warn(format_args!(
        "warning: {}, so the URDF's own inertials give {it} no torque: {limit} (the `effort` \
         of {its} <limit>) {constrains} nothing in the design, and {margin}; give these links \
         `<inertial>` elements with their mass and inertia, or give --parameters PARAMS.toml \
         (the design's criterion does not depend on them)",
        description.unloaded_cause(&args.robot, limited, empty)
    ));
}

/// With a parameter file as the reference: warns about the joints with a torque limit
/// whose torque its parameters leave 0 at every state ([`Idle::find`], the check of `robid
/// torques --parameters`), so that the limit constrains nothing, as [`warn_unloaded`] does
/// for a URDF's own inertials. A joint without a torque limit is not checked against the
/// reference at all, so nothing is said about it.
fn warn_idle(
    args: &Args,
    description: &description::Description,
    file: &Path,
    model: &dyn Model,
    base: &[f64],
    limits: &[JointLimits],
) -> Result<(), Error> {
    let limited = |j: usize| limits.get(j - 1).is_some_and(|l| l.torque.is_some());
    let idle = Idle::find(model, base, &limited)?;
    if idle.joints.is_empty() {
        return Ok(());
    }
    out::warn(format_args!(
        "warning: {}, so the reference gives {}; {}",
        idle.cause(description, &args.robot, file),
        no_torque(idle.joints.len() == 1, idle.exact),
        idle.fix(file)
    ));
    Ok(())
}

/// What a reference that gives one joint (`one`) or several no torque (`exact`, else a
/// negligible one) means for the design: "it no torque: its torque limit constrains nothing
/// in the design, and its torque margin below is the whole limit".
fn no_torque(one: bool, exact: bool) -> String {
    let torque = if exact {
        "no torque"
    } else {
        "no torque to speak of"
    };
    if one {
        format!(
            "it {torque}: its torque limit constrains nothing in the design, and its torque \
             margin below is the whole limit"
        )
    } else {
        format!(
            "them {torque}: their torque limits constrain nothing in the design, and their \
             torque margins below are the whole limits"
        )
    }
}

/// The values of a per-joint limit flag (`--acceleration-limits`, `--velocity-limits`) for
/// `n` joints: none, one for every joint, or one per joint.
fn per_joint(flag: &str, values: &[f64], n: usize, args: &Args) -> Result<Vec<Option<f64>>, Error> {
    let letter = if flag.starts_with("--acceleration") {
        "a"
    } else {
        "v"
    };
    match values {
        [] => Ok(vec![None; n]),
        [v] => Ok(vec![Some(*v); n]),
        many if many.len() == n => Ok(many.iter().copied().map(Some).collect()),
        many => Err(format!(
            "{flag} has {} but {} has {}; give one value or {}",
            Count(many.len(), "value"),
            args.robot.display(),
            Count(n, "joint"),
            Series(letter, n)
        )
        .into()),
    }
}

/// Refuses a joint's limit that a design cannot take (`JointLimits::check`: below
/// `MIN_JOINT_LIMIT`, such as a description's `velocity = 1e-320`), naming the description
/// and the joint (a URDF joint also by its name) and the ways out, before the design: the
/// design's own check named the library's type (``JointLimits `velocity`: joint 1: ...``).
/// A limit given on the command line is in range already (its flag's parser).
fn check_limits(
    args: &Args,
    description: &description::Description,
    limits: &[JointLimits],
) -> Result<(), Error> {
    for (j, l) in limits.iter().enumerate() {
        let Err(e) = l.check(j + 1) else { continue };
        let robid_runtime::Error::Setting { key, problem, .. } = e else {
            return Err(e.into());
        };
        let problem = problem
            .strip_prefix(&format!("joint {}: ", j + 1))
            .unwrap_or(&problem);
        // a description's limit is read within the description's range, narrower than the
        // design's (velocity up to 1e4, not 1e6): the range stated is the description's
        let read = match key.as_str() {
            "velocity" => Some((l.velocity, bounds::MAX_VELOCITY)),
            "acceleration" => Some((l.acceleration, bounds::MAX_ACCELERATION)),
            "torque" => l.torque.map(|t| (t, bounds::MAX_TORQUE)),
            _ => None,
        };
        let [lo, hi] = l.position;
        let problem = match read {
            Some((x, high)) => format!(
                "{} must lie in [{MIN_JOINT_LIMIT:e}, {high:e}] (a smaller limit leaves the \
                 joint nothing to excite)",
                num(x)
            ),
            None if key == "position" => format!(
                "[{}, {}] must be finite within +-{:e}, with high - low at least \
                 {MIN_JOINT_LIMIT:e}",
                // a continuous joint's are computed (its --start +- pi): rounded, but
                // never across the bound they are compared with
                Num::rounded_keeping(lo, 6, |r| (r.abs() > bounds::MAX_POSITION)
                    == (lo.abs() > bounds::MAX_POSITION)),
                Num::rounded_keeping(hi, 6, |r| (r.abs() > bounds::MAX_POSITION)
                    == (hi.abs() > bounds::MAX_POSITION)),
                bounds::MAX_POSITION
            ),
            None => problem.to_owned(),
        };
        let joint = match description.urdf.as_ref().and_then(|c| c.links.get(j)) {
            Some(link) => format!("joint {} (`{}`)", j + 1, link.joint),
            None => format!("joint {}", j + 1),
        };
        let what = if key == "position" {
            "position limits".to_owned()
        } else {
            format!("{key} limit")
        };
        let flag = match key.as_str() {
            "velocity" | "acceleration" => format!(", or give --{key}-limits"),
            _ => String::new(),
        };
        // the joint's table, where the limit is written (file:line:column)
        let at = description
            .robot
            .joint_place(j)
            .map_or_else(|| args.robot.display().to_string(), str::to_owned);
        return Err(format!(
            "{at}: {joint}: the {what} {problem}; correct it in the description{flag}"
        )
        .into());
    }
    Ok(())
}

pub(crate) fn run(args: &Args) -> Result<(), Error> {
    check(args)?;
    let description = description::load(&args.robot, &args.description)?;
    let model = Interpreted::new(&description.robot)?;
    let n = model.dof();
    let accelerations = per_joint("--acceleration-limits", &args.acceleration_limits, n, args)?;
    let velocities = per_joint("--velocity-limits", &args.velocity_limits, n, args)?;
    if !args.start.is_empty() && args.start.len() != n {
        return Err(format!(
            "--start has {} but {} has {}; give {}",
            Count(args.start.len(), "value"),
            args.robot.display(),
            Count(n, "joint"),
            Series("q", n)
        )
        .into());
    }
    // A URDF's continuous joint has no position limits (URDF ignores the lower and upper of
    // its <limit>). Its dynamics repeat every turn, so one turn around its start holds
    // every pose it has: the design keeps it there instead of asking for limits that a
    // continuous joint cannot carry.
    let continuous = |j: usize| {
        description
            .urdf
            .as_ref()
            .and_then(|chain| chain.links.get(j))
            .filter(|link| link.continuous)
    };
    let mut turning = Vec::new();
    let robot = &model.programs().robot;
    let limits = robot
        .joints()
        .iter()
        .enumerate()
        .map(|(j, joint)| {
            let l = &joint.limits;
            let missing = |what: &str| {
                let file = args.robot.display();
                let flag = |unit: &str| {
                    format!(
                        "give --{what}-limits {} ({unit}; or one value for every joint)",
                        Series(if what == "velocity" { "v" } else { "a" }, n)
                    )
                };
                match &description.urdf {
                    // a URDF joint by its name: the robid number is not in the file
                    Some(chain) => {
                        let joint = format!(
                            "{file}: joint {} (`{}`)",
                            j + 1,
                            chain.links.get(j).map_or("?", |link| link.joint.as_str())
                        );
                        match what {
                            "acceleration" => format!(
                                "{joint} has no acceleration limit (a URDF states none); {}",
                                flag("rad/s^2 or m/s^2")
                            ),
                            "velocity" => format!(
                                "{joint} has no velocity limit (no `velocity` in a <limit> \
                                 element); {}, or write <limit velocity=\"..\"> in the joint",
                                flag("rad/s or m/s")
                            ),
                            _ => format!(
                                "{joint} has no position limits; give the joint \
                                 `lower` and `upper` in its <limit> element (<limit \
                                 lower=\"..\" upper=\"..\" velocity=\"..\" effort=\"..\"/>, \
                                 which a revolute or prismatic joint needs in URDF)"
                            ),
                        }
                    }
                    None => {
                        let fix = match what {
                            "acceleration" => format!(", or {}", flag("rad/s^2 or m/s^2")),
                            "velocity" => format!(", or {}", flag("rad/s or m/s")),
                            _ => String::new(),
                        };
                        // the joint's table, where the limits go (file:line:column)
                        let at = robot
                            .joint_place(j)
                            .map_or_else(|| file.to_string(), str::to_owned);
                        format!(
                            "{at}: joint {} has no {what} limit; add `limits = {{ position = \
                             [lo, hi], velocity = .., acceleration = .. }}`{fix}",
                            j + 1
                        )
                    }
                }
            };
            let position = match (l.position, continuous(j)) {
                (Some(position), _) => position,
                (None, Some(link)) => {
                    let centre = args.start.get(j).copied().unwrap_or(0.0);
                    turning.push(format!("{} (`{}`)", j + 1, link.joint));
                    [centre - PI, centre + PI]
                }
                (None, None) => return Err(missing("position")),
            };
            Ok(JointLimits {
                position,
                velocity: velocities[j]
                    .or(l.velocity)
                    .ok_or_else(|| missing("velocity"))?,
                acceleration: accelerations[j]
                    .or(l.acceleration)
                    .ok_or_else(|| missing("acceleration"))?,
                torque: l.torque,
            })
        })
        .collect::<Result<Vec<_>, String>>()?;
    check_limits(args, &description, &limits)?;
    let reference = match &args.parameters {
        Some(p) => {
            let base = description::read_parameters(p, true)?.base_parameters(&model)?;
            warn_idle(args, &description, p, &model, &base, &limits)?;
            Some(base)
        }
        None => {
            warn_unloaded(args, &description, &limits);
            description.urdf_base_parameters(&model)?
        }
    };
    if let Some((last, first)) = turning.split_last() {
        let (joints, are) = if first.is_empty() {
            (format!("joint {last} is"), "it")
        } else {
            (
                format!("joints {} and {last} are", first.join(", ")),
                "each",
            )
        };
        out::warn(format_args!(
            "warning: {joints} continuous, without position limits: the design keeps {are} \
             within ±pi of its start (--start, default 0), one turn, which holds every pose \
             of its dynamics; for another range make the joint `type=\"revolute\"` with \
             `lower` and `upper` in its <limit> (URDF ignores them for a continuous joint)"
        ));
    }
    let start_pose = if args.start.is_empty() {
        limits
            .iter()
            .map(|l| 0.5 * (l.position[0] + l.position[1]))
            .collect()
    } else {
        for (j, (q, l)) in args.start.iter().zip(&limits).enumerate() {
            if !(l.position[0] < *q && *q < l.position[1]) {
                return Err(format!(
                    "--start: q{} = {} is outside the limits ({}, {}) of joint {} in {}; \
                     choose a start strictly inside them",
                    j + 1,
                    num(*q),
                    // rounded, but never across the start they are compared with
                    Num::rounded_keeping(l.position[0], 6, |r| *q > l.position[0] || r >= *q),
                    Num::rounded_keeping(l.position[1], 6, |r| *q < l.position[1] || r <= *q),
                    j + 1,
                    args.robot.display()
                )
                .into());
            }
        }
        args.start.clone()
    };
    let weights = match args.sigma.len() {
        0 => None,
        k if k == n => Some(
            weights_from_sigma(&args.sigma, "excite", "sigma")
                .map_err(|e| e.on_flags(&[("sigma", "--sigma")]))?,
        ),
        k => {
            return Err(format!(
                "--sigma has {} but {} has {}; give {}",
                Count(k, "value"),
                args.robot.display(),
                Count(n, "joint"),
                Series("s", n)
            )
            .into());
        }
    };
    let criterion = match args.criterion {
        CriterionArg::Cond => Criterion::Condition,
        CriterionArg::D => Criterion::DOptimal,
    };
    let start = Instant::now();
    // `fine`: the trajectory on the design's own grid, where it holds the limits: the
    // margins printed are the smaller of its and the samples' (at a coarse --rate the
    // samples alone overstated them, a velocity margin of 0.294 for a true 0.072)
    let (trajectory, fine, evaluations): (Trajectory, Trajectory, usize) = match args.method {
        Method::Fourier => {
            let base_frequency = args.base_frequency.unwrap_or(BASE_FREQUENCY);
            let periods = args.duration * base_frequency;
            if (periods - periods.round()).abs() > 1e-9 || periods.round() < 1.0 {
                return Err(format!(
                    "--duration {} s is not a whole number of periods of {} s; choose a multiple of 1 / --base-frequency so the trajectory ends at rest",
                    num(args.duration),
                    num(1.0 / base_frequency)
                )
                .into());
            }
            let design = FourierDesign {
                harmonics: args.harmonics.unwrap_or(HARMONICS),
                base_frequency,
                criterion,
                weights: weights.clone(),
                restarts: args.restarts.unwrap_or(8),
                evaluations: args.evaluations.unwrap_or(3000),
                seed: args.seed,
                start: Some(start_pose),
                progress: true,
                ..FourierDesign::default()
            };
            let result = design
                .optimize(&model, &limits, reference.as_deref())
                .map_err(|e| e.on_flags(DESIGN_FLAGS))?;
            // one period holds every state of the periodic series; the readers' largest
            // rate caps the grid (a short period of many harmonics, 25 at 100 Hz, asked
            // for 1.02e7 Hz, refused as a `--rate` the user never gave), still finer than
            // any --rate
            let fine = result
                .fourier
                .sample(
                    1.0 / base_frequency,
                    fine_rate((FINER * design.fine_points()) as f64 * base_frequency),
                )
                .map_err(|e| e.on_flags(DESIGN_FLAGS))?;
            (
                result
                    .fourier
                    .sample(args.duration, args.rate)
                    .map_err(|e| e.on_flags(DESIGN_FLAGS))?,
                fine,
                result.evaluations,
            )
        }
        Method::Points => {
            let design = PointDesign {
                duration: args.duration,
                intervals: args.intervals.unwrap_or(POINT_INTERVALS),
                criterion,
                weights: weights.clone(),
                restarts: args.restarts.unwrap_or(4),
                sweeps: args.sweeps.unwrap_or(4),
                evaluations: args.evaluations.unwrap_or(120),
                seed: args.seed,
                start: Some(start_pose),
                progress: true,
                ..PointDesign::default()
            };
            let result = design
                .optimize(&model, &limits, reference.as_deref())
                .map_err(|e| e.on_flags(DESIGN_FLAGS))?;
            let trajectory = result
                .points
                .sample(args.rate)
                .map_err(|e| e.on_flags(DESIGN_FLAGS))?;
            let finer = (MAX_FINE / (design.fine * design.intervals)).clamp(1, FINER);
            let fine = result
                .points
                .sample(fine_rate(
                    (finer * design.fine * design.intervals) as f64 / args.duration,
                ))
                .map_err(|e| e.on_flags(DESIGN_FLAGS))?;
            if let Some(path) = &args.pieces {
                write_pieces(&model, &result.points, path)?;
            }
            (trajectory, fine, result.evaluations)
        }
    };
    let elapsed = start.elapsed();
    check_trajectory(&trajectory)?;
    let mut a = assess(&model, &trajectory, &limits, reference.as_deref(), 1)?;
    let between = margins(&fine, &limits, reference.as_deref().map(|b| (&model, b)))?;
    for (m, f) in a.margins.iter_mut().zip(&between) {
        *m = m.tighter(f);
    }
    // D-optimality can settle on a finite criterion where some parameter is not excited
    // at all: such a trajectory is no design (it was written, and its data then refused)
    if !a.condition_number.is_finite() {
        return Err(format!(
            "the designed trajectory leaves some base parameter unexcited (condition number \
             {}); nothing was written: give the joints more room to move (their position \
             range, --velocity-limits, --acceleration-limits, a --start away from the \
             limits) or the search more work (--restarts, --evaluations)",
            a.condition_number
        )
        .into());
    }
    trajectory.write_csv(&args.output)?;
    let mut stdout = out::Stdout::new();
    writeln!(
        stdout,
        "{}: {}, {} s at {} Hz written to {}",
        model.name(),
        Count(model.base_parameter_count(), "base parameter"),
        args.duration,
        args.rate,
        args.output.display()
    )?;
    // with --sigma the design weighed the rows by 1 / sigma: its figure is the weighted
    // one (the unweighted one, printed alone, was not what it optimised)
    let unweighted = condition(a.condition_number);
    let figure = match &weights {
        None => format!("condition number {unweighted} ("),
        Some(w) => {
            let mut info = Information::new(&model).with_weights(w);
            info.add_trajectory(&model, &trajectory, 1)?;
            format!(
                "condition number {} weighted by 1 / --sigma, as the design weighed the rows \
                 (unweighted {unweighted}; ",
                condition(info.condition_number())
            )
        }
    };
    writeln!(
        stdout,
        "{figure}{} samples stacked); optimised in {:.1} s ({} evaluations)",
        a.samples,
        elapsed.as_secs_f64(),
        evaluations
    )?;
    writeln!(
        stdout,
        "margins to the limits (limit - peak; position: distance to each end):"
    )?;
    writeln!(
        stdout,
        "joint  pos_low  pos_high  velocity  acceleration  torque"
    )?;
    // four significant digits: a margin to a tiny limit (1e-6) read 0.000 or -0.00
    let short = |x: f64| Num::rounded(x, 4).to_string();
    for (j, m) in a.margins.iter().enumerate() {
        let torque = m.torque.map_or("-".to_string(), short);
        writeln!(
            stdout,
            "{:5}  {:>7}  {:>8}  {:>8}  {:>12}  {torque}",
            j + 1,
            short(m.position_low),
            short(m.position_high),
            short(m.velocity),
            short(m.acceleration)
        )?;
    }
    stdout.flush()?;
    warn_barely_exciting(a.condition_number);
    if !a.within_limits() {
        let exceeded: Vec<String> = a
            .margins
            .iter()
            .enumerate()
            .flat_map(|(j, m)| {
                [
                    ("position", m.position_low.min(m.position_high)),
                    ("velocity", m.velocity),
                    ("acceleration", m.acceleration),
                    ("torque", m.torque.unwrap_or(0.0)),
                ]
                .into_iter()
                .filter(|(_, margin)| *margin < 0.0)
                .map(move |(what, margin)| {
                    format!("joint {} {what} by {}", j + 1, Num::rounded(-margin, 3))
                })
            })
            .collect();
        let fix = if exceeded.iter().any(|e| e.contains("torque")) {
            "torques are held by a penalty, not by construction: give the search more work \
             (--sweeps, --evaluations, --restarts) or start from a pose with less load (--start)"
        } else {
            "the design holds these limits on its own grid: sample at a higher --rate or design \
             with more margin"
        };
        // the trajectory stands beside the error, for inspection
        robid_runtime::output::place_held()?;
        return Err(format!(
            "the sampled trajectory (written to {} for inspection) exceeds {}; {fix}",
            args.output.display(),
            exceeded.join(", ")
        )
        .into());
    }
    Ok(())
}

/// The condition number above which a designed trajectory is told to excite some base
/// parameter barely: good designs have tens to hundreds; this is a thousand times more.
const BARELY_EXCITING: f64 = 1e5;

/// Warns when the written trajectory's condition number (unweighted, as printed) is above
/// [`BARELY_EXCITING`] or not finite: the design found nothing better within the limits
/// (`--velocity-limits 1e-6` gave cond 3e7 without a word beyond the figure), and
/// least squares on its data would hardly see some parameter.
/// A condition number as printed: two decimals (`41.93`), in exponent form from 1e5 on
/// (`3.210e7`, which weights 1e6 apart give: `32099193.94`).
fn condition(c: f64) -> String {
    if c < 1e5 {
        format!("{c:.2}")
    } else {
        format!("{c:.3e}")
    }
}

fn warn_barely_exciting(condition: f64) {
    if condition <= BARELY_EXCITING {
        return;
    }
    out::warn(format_args!(
        "warning: condition number {}: the trajectory barely excites some base parameter \
         (good designs have tens to hundreds), so its identification would be poor; give \
         the joints more room to move (their position range, velocity and acceleration \
         limits: --velocity-limits, --acceleration-limits, a --start away from the limits) \
         or the search more work (--restarts, --evaluations)",
        Num::rounded(condition, 4)
    ));
}

/// Refuses a sampled trajectory with a value that is not finite.
fn check_trajectory(tr: &Trajectory) -> Result<(), Error> {
    for (name, block) in [("q", &tr.q), ("qd", &tr.qd), ("qdd", &tr.qdd)] {
        for (j, signal) in block.joints().enumerate() {
            if let Some(k) = signal.iter().position(|x| !x.is_finite()) {
                return Err(format!(
                    "the designed trajectory has {name}{} = {} at t = {} s; nothing was \
                     written: design again with another --seed",
                    j + 1,
                    signal[k],
                    tr.t.get(k).copied().unwrap_or(f64::NAN)
                )
                .into());
            }
        }
    }
    Ok(())
}

/// Chooses the pieces around `points` (Milella's eq. 15) and writes them as a config
/// fragment.
fn write_pieces(
    model: &(dyn robid_runtime::Model + Sync),
    points: &robid_runtime::excite::Points,
    path: &std::path::Path,
) -> Result<(), Error> {
    let pieces = robid_runtime::excite::PieceDesign::default().optimise(model, points)?;
    let windows: Vec<String> = pieces
        .windows
        .iter()
        .map(|[a, b]| format!("[{a:.6}, {b:.6}]"))
        .collect();
    let text = format!(
        "# Milella's piece-wise identification: the windows (s from the start of the \
         trajectory) around the optimal points; condition number of the extended regressor \
         {:.2} (every width at its minimum: {:.2}), {:.0} % of the record.\n[processing]\n\
         pieces = [\n    {},\n]\n",
        pieces.condition_number,
        pieces.initial_condition_number,
        100.0 * pieces.coverage(points.duration()),
        windows.join(",\n    ")
    );
    robid_runtime::output::write_bytes(path, text.as_bytes())?;
    let mut stdout = out::Stdout::new();
    writeln!(
        stdout,
        "pieces: {} windows, condition number {:.2} ({:.2} with every width at its \
         minimum), written to {}",
        pieces.windows.len(),
        pieces.condition_number,
        pieces.initial_condition_number,
        path.display()
    )?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_trajectory_with_a_non_finite_value_is_not_written() {
        let mut tr = Trajectory::zeros(2, vec![0.0, 0.5, 1.0]);
        assert!(check_trajectory(&tr).is_ok());
        tr.qd[1][1] = f64::NAN;
        let e = check_trajectory(&tr).unwrap_err().to_string();
        assert!(e.contains("qd2 = NaN at t = 0.5 s"), "{e}");
    }
}
