//! `robid torques ROBOT.toml --parameters PARAMS.toml --states STATES.csv [-o OUT.csv]`:
//! inverse dynamics row by row (DESIGN.md 10). PARAMS.toml holds a `[standard]` table
//! (name = value, missing names are 0) or a `[base]` table; STATES.csv has the columns
//! `q1..qn,qd1..qdn,qdd1..qddn`; the output has `tau1..taun`. A torque that is not a
//! finite number (states or parameters too large for f64) is an error naming the row of
//! STATES.csv; nothing is written then.

use std::fmt::Write as _;
use std::path::PathBuf;

use super::{Error, files, out};

/// Arguments of `robid torques`.
#[derive(Debug, clap::Args)]
pub(crate) struct Args {
    /// Robot description file (TOML).
    robot: PathBuf,
    /// Parameter file with a `[standard]` or a `[base]` table (values within +-1e6, see
    /// README "Parameter files").
    #[arg(long)]
    parameters: PathBuf,
    /// States, header q1..qn,qd1..qdn,qdd1..qddn.
    #[arg(long)]
    states: PathBuf,
    /// Output CSV (stdout when absent).
    #[arg(short, long)]
    output: Option<PathBuf>,
}

/// Computes and writes the torques.
pub(crate) fn run(args: &Args) -> Result<(), Error> {
    if let Some(output) = &args.output {
        files::refuse(&[&args.robot, &args.parameters, &args.states], &[output])?;
    }
    let chosen = super::identify::robot_model(&args.robot)?;
    let model = chosen.model.as_ref();
    let n = model.dof();
    let base = super::parameters::base_parameters(&args.parameters, model)?;
    let names: Vec<String> = ["q", "qd", "qdd"]
        .iter()
        .flat_map(|p| (1..=n).map(move |j| format!("{p}{j}")))
        .collect();
    let table = super::states::read(&args.states, &names)?;
    let header: Vec<String> = (1..=n).map(|j| format!("tau{j}")).collect();
    let mut text = header.join(",") + "\n";
    let (mut q, mut qd, mut qdd, mut tau) =
        (vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    for (k, line) in table.lines.iter().enumerate() {
        for j in 0..n {
            q[j] = table.columns[j][k];
            qd[j] = table.columns[n + j][k];
            qdd[j] = table.columns[2 * n + j][k];
        }
        model.inverse_dynamics(&q, &qd, &qdd, &base, &mut tau);
        if let Some(j) = tau.iter().position(|t| !t.is_finite()) {
            return Err(format!(
                "{}:{line}: tau{} = {} from this row's states: the states or the parameters of \
                 {} are too large for f64 arithmetic; check this row and the parameter values",
                args.states.display(),
                j + 1,
                tau[j],
                args.parameters.display()
            )
            .into());
        }
        let row: Vec<String> = tau.iter().map(|t| format!("{t:e}")).collect();
        let _ = writeln!(text, "{}", row.join(","));
    }
    match &args.output {
        Some(p) => files::write(p, &text)?,
        None => out::print(&text)?,
    }
    Ok(())
}
