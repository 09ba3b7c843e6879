//! `robid friction ROBOT.toml --config CFG.toml [--data FILE...] [--parameters P.toml]
//! -o FRICTION.toml`: the nonlinear rotor friction of every joint from a two-encoder log
//! (docs/command-line.md#robid-friction, docs/identification.md#nonlinear-rotor-friction).
//!
//! Per sample the friction is `f = K_r i - B thetaddot - tau_J` (Madsen et al. 2020,
//! eq. 14): the torque through the drive chain, the rotor inertias of `[drive.rotor]` and
//! the joint torque, from `joint_torque` columns or, with `--parameters`, from the rigid
//! model's inverse dynamics. Each joint is fitted on its own; the table on stdout gives the
//! parameters with their standard deviations, the residuals and what was held fixed and
//! why, and the file is written
//! atomically only when every joint's fit succeeded.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use robid_runtime::Num;
use robid_runtime::data::{Config, load};
use robid_runtime::drive::{
    DEFAULT_SMOOTHING, FrictionFit, FrictionFitOptions, FrictionModel, FrictionParameter,
    FrictionSample, identify_friction, widest_smoothing,
};
use robid_runtime::limits::MAX_VELOCITY;
use robid_runtime::pipeline::{JointTorqueSource, REFERENCE_TEMPERATURE, friction_samples};
use robid_runtime::progress::Progress;

use robots::limits::beyond_limits;

use super::description::{self, DescriptionFlags};
use super::flags::{positive, real};
use super::{Error, files, out};

/// Arguments of `robid friction`.
#[derive(Debug, clap::Args)]
pub(crate) struct Args {
    #[arg(help = description::robot_help!())]
    robot: PathBuf,
    #[command(flatten)]
    description: DescriptionFlags,
    /// Identification config with `motor_position` columns and `[drive.rotor]` (the rotor
    /// inertias B); `joint_torque` and `temperature` columns when the log has them.
    #[arg(long)]
    config: PathBuf,
    /// Data files, one per `[[source]]` of the config; default: their `file` entries.
    #[arg(long, num_args = 1..)]
    data: Vec<PathBuf>,
    /// The rigid model's parameters (`[base]` or `[standard]`): tau_J from its inverse
    /// dynamics instead of `joint_torque` columns.
    #[arg(long)]
    parameters: Option<PathBuf>,
    /// The friction model to write (`[[friction]]` tables, one per joint).
    #[arg(short, long)]
    output: PathBuf,
    /// `eps` of the smooth sign `tanh(w / eps)`, rad/s, in (0, 1e6]: the fit uses it and
    /// writes it as each joint's `smoothing`. Give the `smoothing` of the friction model
    /// that made the data (a simulation's): fitted with another, the Stribeck terms take
    /// up the difference.
    #[arg(long, default_value_t = DEFAULT_SMOOTHING,
          value_parser = real(positive(MAX_VELOCITY, "rad/s")))]
    smoothing: f64,
}

/// The keys of an identification config that friction's fit does not apply, each with
/// its reason.
const UNAPPLIED: [(&[&str], &str); 5] = [
    (&["runs"], "it fits the one record given"),
    (
        &["processing.decimation"],
        "it fits every sample: a decimation's filter would smear the friction's reversals \
         at zero speed",
    ),
    (
        &["processing.pieces", "processing.rest_velocity"],
        "it fits every sample of the estimation range, those near rest too: the friction \
         turns there",
    ),
    (
        &["processing.validation_range"],
        "it predicts no run: it fits the estimation range",
    ),
    (
        &["estimation"],
        "it fits each joint's friction by its own nonlinear least squares",
    ),
];

/// Identifies, prints and writes the friction model.
pub(crate) fn run(args: &Args) -> Result<(), Error> {
    let mut config = Config::from_file(&args.config)?;
    super::identify::warn_unapplied(&config, &args.config, "friction", &UNAPPLIED);
    // not applied, so not checked either (a `[runs]` of one file was refused after the
    // warning that it is not applied)
    config.runs = None;
    let data = super::identify::data_files(&args.data, Some(&args.config), &config)?;
    // the rotor friction the config names is what this command identifies (the config's
    // next `robid identify` reads it): it may be the output, the other files not
    let written = (config.drive.rotor.as_ref())
        .and_then(|r| r.friction.as_deref())
        .map(|f| config.resolve(f));
    let mut referenced = config.referenced_files();
    referenced.retain(|f| Some(f) != written.as_ref());
    let mut inputs: Vec<&Path> = vec![&args.robot, &args.config];
    inputs.extend(data.iter().map(PathBuf::as_path));
    inputs.extend(referenced.iter().map(PathBuf::as_path));
    inputs.extend(args.parameters.as_deref());
    files::refuse(&inputs, &[("--output", &args.output)])?;
    if config.drive.rotor.is_none() {
        return Err(config
            .key_error(
                "drive.rotor",
                "robid friction needs [drive.rotor] with inertia = [...] (the rotor inertias B, \
                 link side; 0 when unknown): the friction is K_r i - B thetaddot - tau_J",
            )
            .into());
    }
    let description = super::description::read(&args.robot, &args.description)?;
    config.prismatic = super::description::prismatic(&description);
    let chosen = super::identify::model_of(&description)?;
    let model = chosen.model.as_ref();
    let base = match &args.parameters {
        Some(p) => Some(description::read_parameters(p, true)?.base_parameters(model)?),
        None => None,
    };
    let data = load(&config, &data, model.dof())?;
    for w in &data.warnings {
        out::warn(format_args!("warning: {w}"));
    }
    // a dead current channel, torques or positions beyond the limits, as identify warns
    for w in beyond_limits(&description, &data.extremes, &args.robot) {
        out::warn(format_args!("warning: {w}"));
    }
    let found = friction_samples(
        &data,
        &config,
        base.as_deref()
            .map(|b| (model as &dyn robid_runtime::Model, b)),
    )?;
    for w in &found.warnings {
        out::warn(format_args!("warning: {w}"));
    }
    smoothing_fits(&found.samples, args.smoothing, &data.name)?;
    let options = FrictionFitOptions {
        smoothing: args.smoothing,
        ..FrictionFitOptions::default()
    };
    let mut fits = Vec::with_capacity(found.samples.len());
    let progress = Progress::new(true, "friction: fit", fits.capacity() as u64, "joints");
    for (j, samples) in found.samples.iter().enumerate() {
        let fit = identify_friction(samples, &options).map_err(|e| {
            // the samples are the joint's, made by the drive chain from the data: a fit
            // that no friction has is told at the chain's key in the config, with what
            // makes the samples (it was the library's names, or "singular or not positive
            // definite"); what the samples lack (a reversal) is the data's
            let problem = match e {
                robid_runtime::Error::Setting {
                    owner,
                    key,
                    problem,
                    ..
                } if owner == "identify_friction" && key == "fit" => problem,
                robid_runtime::Error::Setting { owner, problem, .. }
                    if owner == "identify_friction" =>
                {
                    return format!(
                        "joint {}: its friction samples from {}: {problem}",
                        j + 1,
                        data.name
                    );
                }
                robid_runtime::Error::Singular { .. } => "they do not oppose the motion: no \
                     friction with non-negative Coulomb, Stribeck and viscous terms fits them; \
                     check that the samples are rotor friction (signs, units, link-side \
                     velocities)"
                    .to_string(),
                e => return format!("joint {}: {e}", j + 1),
            };
            let key = if config.drive.torque_constants.is_some() {
                "drive.torque_constants"
            } else {
                "drive.gear_ratios"
            };
            let joint = j + 1;
            config
                .key_error(
                    key,
                    format!(
                        "joint {joint}: its friction samples K_r i - B thetaddot - tau_J from \
                         {}: {problem}: the signs and units of joint {joint}'s torque constant \
                         and gear ratio, and of its motor_position and joint_torque columns",
                        data.name
                    ),
                )
                .to_string()
        })?;
        fits.push(fit);
        progress.tick();
    }
    progress.finish();
    for (j, fit) in fits.iter().enumerate() {
        if let Some(w) = no_friction(j + 1, fit) {
            out::warn(format_args!("warning: {w}"));
        }
    }
    let text = table(&fits, found.joint_torque, found.temperature_measured);
    let friction = FrictionModel::new(fits.iter().map(|f| f.friction).collect())?;
    friction.write(&args.output)?;
    let mut stdout = out::Stdout::new();
    stdout.write_str(&text)?;
    writeln!(stdout, "written: {}", args.output.display())?;
    stdout.flush()?;
    Ok(())
}

/// `--smoothing` `eps` too wide for the joints' friction `samples` (from `data`): the fit
/// counts a sample as moving beyond `10 eps`, so a joint whose samples reverse beyond the
/// default smoothing's threshold but not beyond that one is refused naming the flag, the
/// joints, their speeds and the widest smoothing every such joint takes (`--smoothing 1`
/// was told of joint 1 alone that its samples have "no velocity reversal" and to "record
/// motion in both directions", which they held).
fn smoothing_fits(samples: &[Vec<FrictionSample>], eps: f64, data: &str) -> Result<(), Error> {
    let widest: Vec<f64> = samples.iter().map(|s| widest_smoothing(s)).collect();
    let hidden: Vec<usize> = (0..samples.len())
        .filter(|&j| widest[j] > DEFAULT_SMOOTHING && eps >= widest[j])
        .collect();
    if hidden.is_empty() {
        return Ok(());
    }
    let bound = widest
        .iter()
        .copied()
        .filter(|&w| w > DEFAULT_SMOOTHING)
        .fold(f64::INFINITY, f64::min);
    let speeds: Vec<String> = hidden
        .iter()
        .map(|&j| {
            let (forward, backward) = samples[j].iter().fold((0.0, 0.0), |(f, b), s| {
                (f64::max(f, s.velocity), f64::max(b, -s.velocity))
            });
            format!(
                "joint {} ({} rad/s forward, {} backward)",
                j + 1,
                Num::rounded(forward, 3),
                Num::rounded(backward, 3)
            )
        })
        .collect();
    Err(format!(
        "--smoothing {} rad/s: the fit counts a sample as moving from ten times the smoothing, \
         {} rad/s (where the smooth sign tanh(w / eps) is within 4e-9 of +-1), which the \
         friction samples from {data} do not reach both ways at {}; give a smoothing below {} \
         rad/s (the default is {})",
        Num(eps),
        Num::rounded(10.0 * eps, 6),
        speeds.join(", "),
        Num::rounded_keeping(bound, 2, |v| v < bound),
        Num(DEFAULT_SMOOTHING)
    )
    .into())
}

/// What the fit of joint `number` says when the data pulled both its Coulomb and its
/// viscous friction below 0 (each held at 0): what they call friction, the motor's torque
/// less the rotor's and the joint's, is not one (a torque constant 1000 times too large,
/// a gear ratio or a joint torque of the wrong sign gave a friction file of zeros and exit
/// 0, its residual thousands of times a friction).
fn no_friction(number: usize, fit: &FrictionFit) -> Option<String> {
    let held = [FrictionParameter::Coulomb, FrictionParameter::Viscous];
    held.iter().all(|p| fit.is_fixed(*p)).then(|| {
        format!(
            "joint {number}: the data pull both its Coulomb and its viscous friction below 0 \
             (held at 0; RMS residual {} N m): the motor's torque less the rotor's and the \
             joint's is not a friction; check the torque constants, the gear ratios' signs \
             and the joint torques' sign and unit",
            Num::rounded(fit.rms, 3)
        )
    })
}

/// A standard deviation relative to its value, ` (1.2 %)`; nothing for a value of 0.
fn relative(std: f64, value: f64) -> String {
    if value == 0.0 {
        String::new()
    } else {
        format!(" ({} %)", Num::rounded(100.0 * std / value.abs(), 2))
    }
}

/// The printed table: the source of tau_J and T, then per joint the parameters with their
/// standard deviations, the residuals and what was held fixed.
fn table(fits: &[FrictionFit], source: JointTorqueSource, temperature: bool) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "rotor friction f = K_r i - B thetaddot - tau_J, tau_J from {}",
        match source {
            JointTorqueSource::Measured => "the joint_torque columns",
            JointTorqueSource::Model => "the rigid model's inverse dynamics (--parameters)",
        }
    );
    if !temperature {
        let _ = writeln!(
            s,
            "no temperature columns: every sample at {REFERENCE_TEMPERATURE} deg C, so the \
             temperature coefficients are held at 0 (add temperature = [...] to a [[source]] \
             to identify them)"
        );
    }
    let _ = writeln!(
        s,
        "+- one standard deviation, for independent residuals (samples of a filtered log are \
         correlated: read them as lower bounds)"
    );
    for (j, fit) in fits.iter().enumerate() {
        let f = &fit.friction;
        let _ = writeln!(
            s,
            "\njoint {}: {} samples, RMS residual {:.4e} N m, largest {:.4e} N m",
            j + 1,
            fit.samples,
            fit.rms,
            fit.max_residual
        );
        let values = [
            f.coulomb,
            f.load,
            f.stribeck,
            f.stribeck_velocity,
            f.viscous,
            f.coulomb_temperature,
            f.viscous_temperature,
        ];
        for (p, v) in FrictionParameter::ALL.into_iter().zip(values) {
            let spread = match fit.std_dev_of(p) {
                _ if fit.is_fixed(p) => "  (held)".to_owned(),
                Some(std) => format!("  +- {std:.2e}{}", relative(std, v)),
                None => "  +- (not determined)".to_owned(),
            };
            let _ = writeln!(s, "  {:<22}{v:>14.6e}{spread}", p.name());
        }
        let _ = writeln!(
            s,
            "  {:<22}{:>14.6e}",
            "reference_temperature", f.reference_temperature
        );
        for h in &fit.fixed {
            // the seven digits of the table above
            let _ = writeln!(
                s,
                "  held {} = {}: {}",
                h.parameter.name(),
                Num::rounded(h.value, 7),
                h.reason
            );
        }
    }
    s
}
