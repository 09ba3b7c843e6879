//! `robid torques ROBOT.toml --parameters PARAMS.toml --states STATES.csv [-o OUT.csv]`:
//! inverse dynamics row by row (docs/command-line.md#robid-torques). PARAMS.toml holds a
//! `[standard]` table (name = value, missing names are 0) or a `[base]` table; STATES.csv
//! has the columns `q1..qn,qd1..qdn,qdd1..qddn`; the output has `tau1..taun`. A torque that
//! is not a finite number (states or parameters too large for f64) is an error naming the
//! row of STATES.csv; nothing is written then.

use std::fmt::Write as _;
use std::path::PathBuf;

use robid_runtime::Model;
use robid_runtime::data::Table;

use super::description::{self, Description, DescriptionFlags, torque_names};
use super::idle::Idle;
use super::{Error, files, out};

/// Arguments of `robid torques`.
#[derive(Debug, clap::Args)]
pub(crate) struct Args {
    #[arg(help = description::robot_help!())]
    robot: PathBuf,
    #[command(flatten)]
    description: DescriptionFlags,
    /// Parameter file with a `[standard]` or a `[base]` table (values within +-1e6, see
    /// README "Parameter files"); default for a URDF: its own `<inertial>` elements.
    #[arg(long)]
    parameters: Option<PathBuf>,
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
        let mut inputs = vec![args.robot.as_path(), &args.states];
        inputs.extend(args.parameters.as_deref());
        files::refuse(&inputs, &[output])?;
    }
    let description = description::load(&args.robot, &args.description)?;
    let chosen = super::identify::model_of(&description.robot)?;
    let model = chosen.model.as_ref();
    let n = model.dof();
    let base = description.base_parameters(args.parameters.as_deref(), model)?;
    match &args.parameters {
        None => warn_unloaded(args, &description),
        Some(file) => warn_idle(args, &description, file, model, &base)?,
    }
    let names: Vec<String> = ["q", "qd", "qdd"]
        .iter()
        .flat_map(|p| (1..=n).map(move |j| format!("{p}{j}")))
        .collect();
    let table = super::states::read(&args.states, &names, n)?;
    let text = torques(model, &base, &table)?;
    match &args.output {
        Some(p) => files::write(p, &text)?,
        None => out::print(&text)?,
    }
    Ok(())
}

/// With a URDF's own inertials: warns about the joints whose torque they leave 0 (they
/// move only links without mass or inertia) or without gravity (links without mass).
/// The torques are written all the same: they are those of the URDF as written.
fn warn_unloaded(args: &Args, description: &Description) {
    let unloaded = description.urdf_unloaded();
    let fix = "or give --parameters PARAMS.toml (a [standard] or [base] parameter file)";
    if !unloaded.massless.is_empty() {
        let joints = &unloaded.massless;
        let (its, is) = its_is(joints);
        let holds = if is == "is" { "holds" } else { "hold" };
        out::warn(format_args!(
            "warning: {}, so with the URDF's own inertials {its} {} {holds} no gravity, only \
             the inertia of these links; give them their masses in their `<inertial>` \
             elements, {fix}",
            description.unloaded_cause(&args.robot, joints, false),
            torque_names(joints)
        ));
    }
    if !unloaded.empty.is_empty() {
        let joints = &unloaded.empty;
        let (its, is) = its_is(joints);
        out::warn(format_args!(
            "warning: {}, so with the URDF's own inertials {its} {} {is} 0 in every row; give \
             these links `<inertial>` elements with their mass and inertia, {fix}",
            description.unloaded_cause(&args.robot, joints, true),
            torque_names(joints)
        ));
    }
}

/// With a parameter file: warns about the joints whose torque its parameters leave 0 at
/// every state ([`Idle::find`]), as [`warn_unloaded`] does for a URDF's own inertials. The
/// torques are written all the same: they are those of the file as written.
fn warn_idle(
    args: &Args,
    description: &Description,
    file: &std::path::Path,
    model: &dyn Model,
    base: &[f64],
) -> Result<(), Error> {
    let idle = Idle::find(model, base, &|_| true)?;
    if idle.joints.is_empty() {
        return Ok(());
    }
    let (its, is) = its_is(&idle.joints);
    out::warn(format_args!(
        "warning: {}, so {its} {} {is} {} in every row; {}",
        idle.cause(description, &args.robot, file),
        torque_names(&idle.joints),
        idle.zero(),
        idle.fix(file)
    ));
    Ok(())
}

/// `("its torque", "is")` for one joint, `("their torques", "are")` for more.
fn its_is(joints: &[usize]) -> (&'static str, &'static str) {
    if joints.len() == 1 {
        ("its torque", "is")
    } else {
        ("their torques", "are")
    }
}

/// The torques of every row of `table` (columns `q1..qn,qd1..qdn,qdd1..qddn`) as CSV
/// text with the header `tau1..taun`; a torque that is not finite is an error naming the
/// row of the states file.
fn torques(model: &dyn Model, base: &[f64], table: &Table) -> Result<String, Error> {
    let n = model.dof();
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
        model.inverse_dynamics_into(&q, &qd, &qdd, base, &mut tau)?;
        if let Some(j) = tau.iter().position(|t| !t.is_finite()) {
            return Err(format!(
                "{}:{line}: tau{} = {} from this row's states: the states or the parameters are \
                 too large for f64 arithmetic; check this row and the parameter values",
                table.path.display(),
                j + 1,
                tau[j],
            )
            .into());
        }
        let row: Vec<String> = tau.iter().map(|t| format!("{t:e}")).collect();
        let _ = writeln!(text, "{}", row.join(","));
    }
    Ok(text)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    /// Two rows of the UR5e from lines 2 and 7 of a states file.
    fn table(qd: f64) -> Table {
        let mut columns = vec![vec![0.1, 0.2]; 18];
        columns[6] = vec![0.0, qd];
        Table {
            path: Path::new("states.csv").to_path_buf(),
            columns,
            lines: vec![2, 7],
        }
    }

    #[test]
    fn every_row_gives_a_line_of_finite_torques() {
        let model = robots::Ur5e;
        let base = vec![0.5; robots::Ur5e::BASE_PARAMETERS];
        let text = torques(&model, &base, &table(1.0)).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[0], "tau1,tau2,tau3,tau4,tau5,tau6");
        assert_eq!(lines.len(), 3);
    }

    /// States and parameters that overflow f64 (1e300 each) give no output but the row.
    #[test]
    fn a_non_finite_torque_is_an_error_naming_the_row() {
        let model = robots::Ur5e;
        let base = vec![1e300; robots::Ur5e::BASE_PARAMETERS];
        let e = torques(&model, &base, &table(1e300))
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("states.csv:7: tau"), "{e}");
        assert!(e.contains("too large for f64"), "{e}");
    }
}
