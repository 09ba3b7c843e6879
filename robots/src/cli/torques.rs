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
/// every state ([`idle_joints`]: every base parameter in the joint's row of the regressor
/// is 0), as [`warn_unloaded`] does for a URDF's own inertials. The torques are written
/// all the same: they are those of the file as written.
fn warn_idle(
    args: &Args,
    description: &Description,
    file: &std::path::Path,
    model: &dyn Model,
    base: &[f64],
) -> Result<(), Error> {
    let (joints, parameters) = idle_joints(model, base)?;
    let Some(&lowest) = joints.first() else {
        return Ok(());
    };
    let named: Vec<String> = joints
        .iter()
        .map(|&j| {
            let urdf = description.urdf.as_ref();
            match urdf.and_then(|c| c.links.get(j - 1)) {
                Some(link) => format!("{j} (`{}`)", link.joint),
                None => j.to_string(),
            }
        })
        .collect();
    let (its, is) = its_is(&joints);
    let (named, moves, depends) = match named.split_last() {
        Some((last, [])) => (format!("joint {last}"), "moves", "depends"),
        Some((last, first)) => (
            format!("joints {} and {last}", first.join(", ")),
            "move",
            "depend",
        ),
        None => (String::new(), "moves", "depends"),
    };
    // the base parameters, at most SHOWN of them
    const SHOWN: usize = 8;
    let list = match parameters.len() {
        0 => String::new(),
        k if k <= SHOWN => format!(" ({})", parameters.join(", ")),
        k => format!(
            " ({} and {} more)",
            parameters[..SHOWN].join(", "),
            k - SHOWN
        ),
    };
    let file = file.display();
    out::warn(format_args!(
        "warning: with the parameters of {file}, {named} of {} {moves} no mass or inertia: \
         every base parameter {its} {depends} on{list} is 0, so {its} {} {is} 0 in every \
         row; give the links from link {lowest} on their masses and inertias in {file} (a \
         standard parameter it does not name counts as 0)",
        args.robot.display(),
        torque_names(&joints),
    ));
    Ok(())
}

/// The joints (numbered from 1) whose torque is 0 at every state with the base parameters
/// `base`, and the names of the base parameters their torques depend on: a joint's
/// torque is its row of the base regressor times `base`, so it is 0 at every state when
/// every base parameter with a nonzero entry in that row is 0. The rows are taken at a
/// few states of no special pose (every entry that is not structurally zero is nonzero
/// there), entries below 1e-10 of the row's largest counting as zero. The criterion
/// holds for every source of parameters (a URDF's inertials, a `[standard]` or `[base]`
/// table) and counts drive terms: a joint with friction has a torque.
fn idle_joints(model: &dyn Model, base: &[f64]) -> Result<(Vec<usize>, Vec<String>), Error> {
    let (n, b) = (model.dof(), model.base_parameter_count());
    // the largest magnitude of each entry of the regressor over the states
    let mut largest = vec![0.0f64; n * b];
    let mut y = vec![0.0; n * b];
    for state in 0..3 {
        let value = |kind: usize, j: usize| {
            let x = (1 + j + 7 * kind + 31 * state) as f64;
            0.3 + 0.6 * (1.618_033_988_75 * x).fract()
        };
        let q: Vec<f64> = (0..n).map(|j| value(0, j)).collect();
        let qd: Vec<f64> = (0..n).map(|j| value(1, j)).collect();
        let qdd: Vec<f64> = (0..n).map(|j| value(2, j)).collect();
        model
            .base_regressor_into(&q, &qd, &qdd, &mut y)
            .map_err(robid_runtime::Error::from)?;
        for (l, v) in largest.iter_mut().zip(&y) {
            *l = l.max(v.abs());
        }
    }
    let mut joints = Vec::new();
    let mut parameters: Vec<usize> = Vec::new();
    for j in 0..n {
        let row = &largest[j * b..(j + 1) * b];
        let top = row.iter().copied().fold(0.0, f64::max);
        let used: Vec<usize> = (0..b).filter(|&k| row[k] > 1e-10 * top).collect();
        if used.iter().all(|&k| base.get(k) == Some(&0.0)) {
            joints.push(j + 1);
            for k in used {
                if !parameters.contains(&k) {
                    parameters.push(k);
                }
            }
        }
    }
    parameters.sort_unstable();
    let names = parameters
        .into_iter()
        .map(|k| model.base_parameter_name(k).unwrap_or("?").to_owned())
        .collect();
    Ok((joints, names))
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

    /// The joints whose torque is 0 at every state are found from the regressor, for
    /// parameters from any source: standard parameters of the last two links all 0 leave
    /// joints 5 and 6 nothing to move (and name only their base parameters), all 0 every
    /// joint, none 0 no joint.
    #[test]
    fn joints_with_nothing_to_move_are_found_from_the_regressor() {
        use robid_runtime::model::standard_parameter_names;
        let model = robots::Ur5e;
        let names = standard_parameter_names(&model);
        let base_of = |value: &dyn Fn(&str) -> f64| {
            let standard: Vec<f64> = names.iter().map(|n| value(n)).collect();
            let mut base = vec![0.0; model.base_parameter_count()];
            model.base_from_standard_into(&standard, &mut base).unwrap();
            base
        };
        let last_two_empty = base_of(&|n: &str| {
            if n.ends_with(['5', '6']) { 0.0 } else { 0.1 }
        });
        let (joints, parameters) = idle_joints(&model, &last_two_empty).unwrap();
        assert_eq!(joints, [5, 6]);
        assert!(!parameters.is_empty());
        assert!(
            parameters.iter().all(|p| p.ends_with(['5', '6'])),
            "{parameters:?}"
        );
        let (joints, _) = idle_joints(&model, &base_of(&|_: &str| 0.1)).unwrap();
        assert!(joints.is_empty());
        let (joints, _) = idle_joints(&model, &base_of(&|_: &str| 0.0)).unwrap();
        assert_eq!(joints, [1, 2, 3, 4, 5, 6]);
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
