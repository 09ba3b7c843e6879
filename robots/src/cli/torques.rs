//! `robid torques ROBOT.toml --parameters PARAMS.toml --states STATES.csv [-o OUT.csv]`:
//! inverse dynamics row by row (DESIGN.md 10). PARAMS.toml holds a `[standard]` table
//! (name = value, missing names are 0) or a `[base]` table; STATES.csv has the columns
//! `q1..qn,qd1..qdn,qdd1..qddn`; the output has `tau1..taun`.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use robid_runtime::data::read_columns;
use robots::interpreted::Chosen;

use super::Error;

/// Arguments of `robid torques`.
#[derive(Debug, clap::Args)]
pub(crate) struct Args {
    /// Robot description file (TOML).
    robot: PathBuf,
    /// Parameter file with a [standard] or a [base] table.
    #[arg(long)]
    parameters: PathBuf,
    /// States, header q1..qn,qd1..qdn,qdd1..qddn.
    #[arg(long)]
    states: PathBuf,
    /// Output CSV (stdout when absent).
    #[arg(short, long)]
    output: Option<PathBuf>,
}

/// Values of `names` from `table` (missing = 0); unknown keys are an error.
fn values(
    table: &toml::Table,
    names: &[String],
    path: &Path,
    what: &str,
) -> Result<Vec<f64>, Error> {
    for (key, v) in table {
        if !names.contains(key) {
            return Err(format!(
                "{}: [{what}] has `{key}`, which is not a {what} parameter of this robot (they are: {})",
                path.display(),
                names.join(", ")
            )
            .into());
        }
        let x = v.as_float().or_else(|| v.as_integer().map(|i| i as f64));
        if !x.is_some_and(f64::is_finite) {
            return Err(format!(
                "{}: [{what}] `{key}` = {v} is not a finite number",
                path.display()
            )
            .into());
        }
    }
    Ok(names
        .iter()
        .map(|n| {
            table
                .get(n)
                .and_then(|v| v.as_float().or_else(|| v.as_integer().map(|i| i as f64)))
                .unwrap_or(0.0)
        })
        .collect())
}

/// The base parameters of a parameter file.
pub(crate) fn base_parameters(chosen: &Chosen, path: &Path) -> Result<Vec<f64>, Error> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("{}: cannot read: {e}", path.display()))?;
    let doc: toml::Table = toml::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
    let table = |key: &str| doc.get(key).and_then(toml::Value::as_table);
    match (table("standard"), table("base")) {
        (Some(s), None) => {
            let standard = values(s, &chosen.standard, path, "standard")?;
            let mut base = vec![0.0; chosen.base.len()];
            chosen.model.base_from_standard(&standard, &mut base);
            Ok(base)
        }
        (None, Some(b)) => {
            let names: Vec<String> = chosen.base.iter().map(|b| b.name.clone()).collect();
            values(b, &names, path, "base")
        }
        _ => Err(format!(
            "{}: needs exactly one of the tables [standard] or [base]",
            path.display()
        )
        .into()),
    }
}

/// Computes and writes the torques.
pub(crate) fn run(args: &Args) -> Result<(), Error> {
    let chosen = super::identify::robot_model(&args.robot)?;
    let model = chosen.model.as_ref();
    let n = model.dof();
    let base = base_parameters(&chosen, &args.parameters)?;
    let names: Vec<String> = ["q", "qd", "qdd"]
        .iter()
        .flat_map(|p| (1..=n).map(move |j| format!("{p}{j}")))
        .collect();
    let table = read_columns(&args.states, &names)?;
    let header: Vec<String> = (1..=n).map(|j| format!("tau{j}")).collect();
    let mut out = header.join(",") + "\n";
    let (mut q, mut qd, mut qdd, mut tau) =
        (vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    for k in 0..table.rows() {
        for j in 0..n {
            q[j] = table.columns[j][k];
            qd[j] = table.columns[n + j][k];
            qdd[j] = table.columns[2 * n + j][k];
        }
        model.inverse_dynamics(&q, &qd, &qdd, &base, &mut tau);
        let row: Vec<String> = tau.iter().map(|t| format!("{t:e}")).collect();
        let _ = writeln!(out, "{}", row.join(","));
    }
    match &args.output {
        Some(p) => {
            std::fs::write(p, out).map_err(|e| format!("{}: cannot write: {e}", p.display()))?
        }
        None => print!("{out}"),
    }
    Ok(())
}
