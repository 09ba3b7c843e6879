//! `robid payload ROBOT.toml --parameters PARAMS.toml --data DATA.csv [--config C.toml]
//! [-o PAYLOAD.toml]`: the ten inertial parameters of a payload on the last link from joint
//! torques, the robot's model without the payload being known
//! (docs/command-line.md#robid-payload). Without a config DATA.csv has the columns
//! `q1..qn,qd1..qdn,qdd1..qddn,tau1..taun` (`robid simulate` writes them, with `t`, which
//! is not used); with one, any log that `robid identify` reads with it (its columns, units,
//! drive chain, low-pass and derivatives). PARAMS.toml holds the model's `[standard]` or
//! `[base]` table, as for `robid torques`.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use robid_runtime::data::{Config, Extremes};
use robid_runtime::model::Inertial;
use robid_runtime::payload::{
    Consistency, JointSample, Payload, PayloadOptions, Verdict, from_torques,
};
use robid_runtime::{Count, Num};

use robots::limits::beyond_limits;

use super::description::{self, DescriptionFlags};
use super::{Error, files, out};

/// Arguments of `robid payload`.
#[derive(Debug, clap::Args)]
pub(crate) struct Args {
    #[arg(help = description::robot_help!())]
    robot: PathBuf,
    #[command(flatten)]
    description: DescriptionFlags,
    /// The robot's parameters without the payload: a `[standard]` or a `[base]` table.
    #[arg(long)]
    parameters: PathBuf,
    /// Samples with the payload on, header q1..qn,qd1..qdn,qdd1..qddn,tau1..taun; with
    /// --config, one file per `[[source]]` (default: the config's `file`s).
    #[arg(long, num_args = 1..)]
    data: Vec<PathBuf>,
    /// Identification config (`robid identify --example-config`): the data are read,
    /// converted and processed as `identify` does (columns, units, drive chain, range,
    /// low-pass, derivatives), so a real log of positions and torques or currents serves.
    #[arg(long)]
    config: Option<PathBuf>,
    /// Ordinary least squares instead of weighted (per-joint weights).
    #[arg(long)]
    ols: bool,
    /// Writes the payload as TOML (a `[payload]` table of the ten values and their
    /// standard deviations, and a `[payload.physical]` table).
    #[arg(short, long)]
    output: Option<PathBuf>,
}

/// The keys of an identification config that the payload's processing does not apply,
/// each with its reason: those of the robot's own identification (decimation, equations
/// near rest, pieces, the estimator, repeated runs, extra columns) and of validation.
const UNAPPLIED: [(&[&str], &str); 6] = [
    (
        &["processing.decimation"],
        "its least squares take every processed sample",
    ),
    (
        &["processing.rest_velocity", "processing.pieces"],
        "its least squares take every processed sample of the estimation range, those near \
         rest too",
    ),
    (
        &["processing.validation_range"],
        "it predicts no run: it fits the estimation range",
    ),
    (
        &["estimation"],
        "--ols chooses the method, weighted least squares by default",
    ),
    (
        &["runs"],
        "it identifies the payload from the one data set given",
    ),
    (
        &["extra_column"],
        "the robot's torques come from its parameter file; the least squares estimate the \
         payload's ten parameters alone",
    ),
];

/// Identifies the payload, prints it and writes it when asked.
pub(crate) fn run(args: &Args) -> Result<(), Error> {
    let config = match &args.config {
        Some(path) => {
            let config = super::identify::config_for(Some(path), &args.data)?;
            super::identify::warn_unapplied(&config, path, "payload", &UNAPPLIED);
            Some(config)
        }
        None => None,
    };
    let data = match &config {
        Some(c) => super::identify::data_files(&args.data, args.config.as_deref(), c)?,
        None => match &args.data[..] {
            [file] => vec![file.clone()],
            _ => {
                return Err(format!(
                    "--data: {} files given; without --config give one file with the columns \
                     q1..,qd1..,qdd1..,tau1.. (or a --config with one [[source]] per file)",
                    args.data.len()
                )
                .into());
            }
        },
    };
    if let Some(output) = &args.output {
        let referenced = config
            .iter()
            .flat_map(Config::referenced_files)
            .collect::<Vec<_>>();
        let mut inputs: Vec<&Path> = vec![&args.robot, &args.parameters];
        inputs.extend(args.config.as_deref());
        inputs.extend(data.iter().map(PathBuf::as_path));
        inputs.extend(referenced.iter().map(PathBuf::as_path));
        files::refuse(&inputs, &[("--output", output)])?;
    }
    let robot = description::read(&args.robot, &args.description)?;
    let chosen = super::identify::model_of(&robot)?;
    let model = chosen.model.as_ref();
    let base = description::read_parameters(&args.parameters, true)?.base_parameters(model)?;
    let (samples, extremes) = match &config {
        Some(config) => processed_samples(config, &data, model.dof())?,
        None => state_samples(&data[0], model.dof())?,
    };
    // what `identify` warns of in a log, before the fit: a dead torque channel, data
    // beyond the description's limits, derivative columns in other units (a payload fitted
    // to a sixth torque of zeros was "physically consistent: yes")
    for w in beyond_limits(&robot, &extremes, &args.robot) {
        out::warn(format_args!("warning: {}: {w}", data[0].display()));
    }
    let options = PayloadOptions {
        weighted: !args.ols,
        ..PayloadOptions::default()
    };
    let payload = from_torques(model, &base, &samples, &options)
        .map_err(|e| format!("{}: {e}", data[0].display()))?;
    out::print(&summary(&payload))?;
    // the estimate's own (ill-conditioned, uncertain), as `identify` gives them: four
    // samples gave cond 5e10 and a centre of mass 1.7 km away with a word only on the
    // consistency
    for w in &payload.estimate.warnings {
        out::warn(format_args!("warning: {w}"));
    }
    if let Some(p) = &args.output {
        files::write(p, &toml(&payload))?;
    }
    Ok(())
}

/// The samples of a file of states and torques, `q1..,qd1..,qdd1..,tau1..` (`n` joints),
/// with their positions' and torques' extremes. Rows that repeat an earlier row exactly
/// are warned of: a sample counted twice (a file appended to itself) shrinks the standard
/// deviations by the square root of the count and says nothing new.
fn state_samples(file: &Path, n: usize) -> Result<(Vec<JointSample>, Extremes), Error> {
    let names: Vec<String> = ["q", "qd", "qdd", "tau"]
        .iter()
        .flat_map(|p| (1..=n).map(move |j| format!("{p}{j}")))
        .collect();
    // a log of positions and torques: a config processes it as `identify` does
    let remedy = "; or give a --config (robid identify --example-config) to differentiate a \
                  log of `t,q1..,tau1..` as `robid identify` does, with its units and drive \
                  chain (docs/command-line.md#robid-payload)";
    let table = super::states::read_with(file, &names, n, remedy)?;
    // told as `torques` tells it (it said "0 samples, at least 11 are needed", counting
    // equations, beside one row's "1 sample, at least 2")
    if table.rows() == 0 {
        return Err(super::states::no_rows(
            file,
            &names,
            "the file has its header alone",
        ));
    }
    let mut seen = std::collections::HashSet::new();
    let mut repeated = Vec::new();
    for k in 0..table.rows() {
        let row: Vec<u64> = table.columns.iter().map(|c| c[k].to_bits()).collect();
        if !seen.insert(row) {
            repeated.push(table.lines[k]);
        }
    }
    if let Some(first) = repeated.first() {
        out::warn(format_args!(
            "warning: {}: {} of {} repeat an earlier row exactly (the first at line {first}): \
             a sample counted twice makes the standard deviations smaller than the data \
             allow; remove the repeated rows (a file appended to itself; or noise-free \
             samples of a periodic trajectory, whose periods repeat to the bit: keep one \
             period)",
            file.display(),
            Count(repeated.len(), "row"),
            table.rows()
        ));
    }
    let range = |c: &[f64]| {
        c.iter()
            .fold([f64::INFINITY, f64::NEG_INFINITY], |[a, b], &v| {
                [a.min(v), b.max(v)]
            })
    };
    let extremes = Extremes {
        position: table.columns[..n].iter().map(|c| range(c)).collect(),
        torque: table.columns[3 * n..].iter().map(|c| range(c)).collect(),
        ..Extremes::default()
    };
    let samples = (0..table.lines.len())
        .map(|k| {
            let block = |b: usize| (0..n).map(|j| table.columns[b * n + j][k]).collect();
            JointSample {
                q: block(0),
                qd: block(1),
                qdd: block(2),
                tau: block(3),
            }
        })
        .collect();
    Ok((samples, extremes))
}

/// The samples of the data `files` read and processed with `config` as `robid identify`
/// reads and processes them (`data::load`, `pipeline::prepare`), warning of what loading
/// repaired, with the extremes the loader kept.
fn processed_samples(
    config: &Config,
    files: &[PathBuf],
    n: usize,
) -> Result<(Vec<JointSample>, Extremes), Error> {
    let data = robid_runtime::data::load(config, files, n)?;
    for w in &data.warnings {
        out::warn(format_args!("warning: {w}"));
    }
    let p = robid_runtime::pipeline::prepare(&data, config)?;
    let samples = (0..p.samples())
        .map(|k| JointSample {
            q: p.q.sample(k),
            qd: p.qd.sample(k),
            qdd: p.qdd.sample(k),
            tau: p.tau.sample(k),
        })
        .collect();
    Ok((samples, data.extremes))
}

/// What is printed: the ten values with their deviations, then the physical reading.
fn summary(p: &Payload) -> String {
    let e = &p.estimate;
    let mut s = format!(
        "payload on the last link ({}, {} equations, condition number {:.1})\n",
        e.method.name(),
        e.rows,
        e.condition_number
    );
    // the deviations the verdict judges by: the larger of the classical and the robust
    let std = p.std();
    for (k, name) in e.names.iter().enumerate() {
        let _ = writeln!(s, "  {name:<3} {:>14.6e} +- {:.2e}", e.values[k], std[k]);
    }
    let c = &p.consistency;
    // the digits of the table's M: six decimals wrote -0.000000 for a mass of -8.1e-11
    let _ = writeln!(
        s,
        "mass: {} +- {:.2e} kg",
        Num::rounded(c.mass, 7),
        e.std[9]
    );
    if let Some(l) = &c.physical {
        let _ = writeln!(
            s,
            "centre of mass: [{:.6}, {:.6}, {:.6}] m",
            l.com[0], l.com[1], l.com[2]
        );
        let _ = writeln!(s, "inertia about the centre of mass (kg m^2):");
        for row in &l.inertia {
            let _ = writeln!(
                s,
                "  [{:>13.6e}, {:>13.6e}, {:>13.6e}]",
                row[0], row[1], row[2]
            );
        }
    }
    s.push_str(&verdict(c));
    s
}

/// The physical reading's line: consistent or not, with what holds only within the
/// uncertainty, or undetermined, with why and what to do.
fn verdict(c: &Consistency) -> String {
    match c.verdict() {
        Verdict::Consistent if c.within_uncertainty.is_empty() => {
            "physically consistent: yes\n".to_owned()
        }
        Verdict::Consistent => format!(
            "physically consistent: yes, within its uncertainty: {}\n",
            c.within_uncertainty.join("; ")
        ),
        // the checks pass within an uncertainty that any values pass within: five samples
        // said "yes" of a centre of mass 1.7 km away
        Verdict::Undetermined => format!(
            "physically consistent: undetermined, the data cannot tell: {}; record a longer \
             or more exciting trajectory (robid excite designs one), whose wrist motion \
             determines the payload\n",
            c.undetermined.join("; ")
        ),
        Verdict::Inconsistent => {
            // what is within the uncertainty tells too: a mass within it of zero says the
            // data may hold no payload, which explains the rest (it was left out here)
            let notes: Vec<&str> = (c.undetermined.iter())
                .chain(&c.within_uncertainty)
                .chain(&c.problems)
                .map(String::as_str)
                .collect();
            format!("physically consistent: no: {}\n", notes.join("; "))
        }
    }
}

/// The payload as TOML: `[payload]` (the ten values), `[payload.std]`, `[payload.physical]`.
fn toml(p: &Payload) -> String {
    let e = &p.estimate;
    let mut s = String::from(
        "# The payload on the last link, about its frame origin in its frame (robid payload).\n\
         [payload]\n",
    );
    for (k, stem) in Inertial::ALL.iter().map(|i| i.stem()).enumerate() {
        let _ = writeln!(s, "{stem} = {:?}", e.values[k]);
    }
    s.push_str("\n[payload.std]\n");
    let std = p.std();
    for (k, stem) in Inertial::ALL.iter().map(|i| i.stem()).enumerate() {
        let _ = writeln!(s, "{stem} = {:?}", std[k]);
    }
    let c = &p.consistency;
    s.push_str("\n[payload.physical]\n");
    let _ = writeln!(s, "mass = {:?}", c.mass);
    if let Some(l) = &c.physical {
        let _ = writeln!(s, "com = [{:?}, {:?}, {:?}]", l.com[0], l.com[1], l.com[2]);
        let rows: Vec<String> = l
            .inertia
            .iter()
            .map(|r| format!("[{:?}, {:?}, {:?}]", r[0], r[1], r[2]))
            .collect();
        let _ = writeln!(s, "inertia = [{}]", rows.join(", "));
    }
    // `consistent` is true for a determined body alone (a script reads a bool); `verdict`
    // tells an undetermined estimate from one that is no body
    let _ = writeln!(s, "consistent = {}", c.is_consistent());
    let _ = writeln!(s, "verdict = \"{}\"", c.verdict().name());
    s
}

#[cfg(test)]
mod tests {
    use super::verdict;
    use robid_runtime::payload::Consistency;

    /// Data without a payload: a mass of 1e-11 kg (2 standard deviations) and moments that
    /// break the triangle inequality well beyond theirs. The "no" says the data may hold no
    /// payload, as a "yes" does (it was left out).
    #[test]
    fn a_verdict_of_no_keeps_the_hint_of_no_payload() {
        let p = [1e-2, 0.0, 0.0, 1e-3, 0.0, 1e-3, 0.0, 0.0, 0.0, 1e-11];
        let std = [
            1e-9, 1e-9, 1e-9, 1e-9, 1e-9, 1e-9, 1e-12, 1e-12, 1e-12, 5e-12,
        ];
        let c = Consistency::of_estimate(&p, &std);
        assert!(!c.is_consistent());
        let line = verdict(&c);
        assert!(
            line.starts_with("physically consistent: no: ")
                && line.contains("the data may hold no payload")
                && line.contains("triangle inequality"),
            "{line}"
        );
    }
}
