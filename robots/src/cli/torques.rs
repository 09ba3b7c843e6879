//! `robid torques ROBOT.toml --parameters PARAMS.toml --states STATES.csv [-o OUT.csv]`:
//! inverse dynamics row by row (docs/command-line.md#robid-torques). PARAMS.toml holds a
//! `[standard]` table (name = value, missing names are 0) or a `[base]` table; STATES.csv
//! has the columns `q1..qn,qd1..qdn,qdd1..qddn`; the output has `tau1..taun`. A torque that
//! is not a finite number (states or parameters too large for f64) is an error naming the
//! row of STATES.csv; nothing is written then. STATES.csv is read window by window and each
//! window's torques written as they are computed (to the output's temporary file, or to an
//! anonymous temporary file copied to standard output at the end), so a long file is never
//! held in memory.

use std::fmt::Write as _;
use std::io::{Read as _, Seek as _, Write};
use std::path::{Path, PathBuf};

use robid_runtime::data::{Table, WINDOW, for_each_window};
use robid_runtime::limits::MAX_FILE_BYTES;
use robid_runtime::{DataError, Error as RuntimeError, Model};

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
        files::refuse(&inputs, &[("--output", output)])?;
    }
    let description = description::load(&args.robot, &args.description)?;
    let chosen = super::identify::model_of(&description.robot)?;
    let model = chosen.model.as_ref();
    let n = model.dof();
    let base = description.base_parameters(args.parameters.as_deref(), model)?;
    match &args.parameters {
        None => description.warn_unloaded(
            &args.robot,
            "with the URDF's own inertials",
            "in every row",
            "or give --parameters PARAMS.toml (a [standard] or [base] parameter file)",
        ),
        Some(file) => warn_idle(args, &description, file, model, &base)?,
    }
    let names: Vec<String> = ["q", "qd", "qdd"]
        .iter()
        .flat_map(|p| (1..=n).map(move |j| format!("{p}{j}")))
        .collect();
    super::states::refuse_surplus(&args.states, n)?;
    let compute = |w: &mut dyn Write| stream(model, &base, &args.states, &names, WINDOW, w);
    match &args.output {
        Some(p) => {
            // an error of the states stops the writer, which leaves the output untouched
            let mut failed = None;
            let written = robid_runtime::output::write_atomically(p, |w| {
                compute(w).map_err(|e| match e {
                    Failure::Input(e) => {
                        failed = Some(e);
                        std::io::Error::other("the states were refused")
                    }
                    Failure::Output(e) => e,
                })
            });
            if let Some(e) = failed {
                return Err(e);
            }
            written?;
        }
        None => {
            // nothing on standard output unless every row gives torques: they wait in a
            // temporary file (deleted when closed)
            let io = |source| {
                RuntimeError::Data(DataError::Temporary {
                    dir: std::env::temp_dir(),
                    source,
                })
            };
            let mut file = std::io::BufWriter::new(tempfile::tempfile().map_err(io)?);
            compute(&mut file).map_err(|e| match e {
                Failure::Input(e) => e,
                Failure::Output(e) => io(e).into(),
            })?;
            let mut file = file.into_inner().map_err(|e| io(e.into_error()))?;
            file.rewind().map_err(io)?;
            let mut stdout = out::Stdout::new();
            let mut chunk = vec![0u8; 1 << 20];
            loop {
                let read = file.read(&mut chunk).map_err(io)?;
                if read == 0 {
                    break;
                }
                // the text is ASCII, so any cut is between characters
                stdout.write_str(&String::from_utf8_lossy(&chunk[..read]))?;
            }
            stdout.flush()?;
        }
    }
    Ok(())
}

/// Why [`stream`] stopped: the states (or the torques they give), or the output.
enum Failure {
    Input(Error),
    Output(std::io::Error),
}

/// The torques of every row of the states file `path` (columns `names`:
/// `q1..qn,qd1..qdn,qdd1..qddn`), read `window` bytes of text at a time, written to `w`
/// under the header `tau1..taun` as they are computed. The errors are those of the file
/// read whole: an unreadable row first (the reader stops there), then the first value out
/// of its range in the first column that has one, then the first row whose torque is not
/// finite; the rows after an error are read for the errors that come before it, and not
/// written.
fn stream(
    model: &dyn Model,
    base: &[f64],
    path: &Path,
    names: &[String],
    window: usize,
    w: &mut dyn Write,
) -> Result<(), Failure> {
    let input = |e: RuntimeError| Failure::Input(e.into());
    let file = std::fs::File::open(path).map_err(|source| {
        input(RuntimeError::Data(DataError::Io {
            path: path.to_path_buf(),
            source,
        }))
    })?;
    let size = file.metadata().map_or(0, |m| m.len());
    if size > MAX_FILE_BYTES {
        return Err(input(RuntimeError::TooLarge {
            what: format!("{}: file size in bytes", path.display()),
            found: size as f64,
            limit: MAX_FILE_BYTES as usize,
            fix: "split the file".to_string(),
        }));
    }
    let n = model.dof();
    let header: Vec<String> = (1..=n).map(|j| format!("tau{j}")).collect();
    writeln!(w, "{}", header.join(",")).map_err(Failure::Output)?;
    // the first value out of range in the first column that has one so far
    let mut range: Option<(usize, Error)> = None;
    let mut torque: Option<Error> = None;
    let mut output = None;
    let mut rows = 0;
    let mut text = String::new();
    // the windows are read and parsed on another thread (the reader's work is Send, the
    // model and the output need not be) and handed over one at a time
    let (windows, received) = std::sync::mpsc::sync_channel::<Table>(1);
    let read = std::thread::scope(|scope| {
        let reader = scope.spawn(move || {
            for_each_window(file, path, names, window, |table, _| {
                // the receiver reads every window; should it be gone, nothing is left to do
                let _ = windows.send(table);
                Ok(())
            })
        });
        for table in received {
            rows += table.rows();
            if let Some((c, _, e)) = super::states::out_of_range(&table, names)
                && range.as_ref().is_none_or(|(first, _)| c < *first)
            {
                range = Some((c, e));
            }
            if range.is_some() || torque.is_some() || output.is_some() {
                continue;
            }
            text.clear();
            match torques(model, base, &table, &mut text) {
                Ok(()) => {
                    if let Err(e) = w.write_all(text.as_bytes()) {
                        output = Some(e);
                    }
                }
                Err(e) => torque = Some(e),
            }
        }
        reader
            .join()
            .unwrap_or_else(|panic| std::panic::resume_unwind(panic))
    });
    read.map_err(|e| match e {
        // a states file needs one row, and one without any is told as one with its header
        // alone is
        RuntimeError::Data(DataError::EmptyFile { .. }) => {
            Failure::Input(super::states::no_rows(path, names, "the file is empty"))
        }
        e => Failure::Input(super::states::with_header(e, names, "")),
    })?;
    if rows == 0 {
        return Err(Failure::Input(super::states::no_rows(
            path,
            names,
            "the file has its header alone",
        )));
    }
    match (range, torque, output) {
        (Some((_, e)), _, _) => Err(Failure::Input(e)),
        (None, Some(e), _) => Err(Failure::Input(e)),
        (None, None, Some(e)) => Err(Failure::Output(e)),
        (None, None, None) => Ok(()),
    }
}

/// With a parameter file: warns about the joints whose torque its parameters leave 0 at
/// every state ([`Idle::find`]), as [`Description::warn_unloaded`] does for a URDF's own
/// inertials. The
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
/// lines appended to `text`; a torque that is not finite is an error naming the row of the
/// states file.
fn torques(model: &dyn Model, base: &[f64], table: &Table, text: &mut String) -> Result<(), Error> {
    let n = model.dof();
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
        // adding zero turns -0 into 0
        let row: Vec<String> = tau.iter().map(|t| format!("{:e}", t + 0.0)).collect();
        let _ = writeln!(text, "{}", row.join(","));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

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
        let mut text = String::new();
        torques(&model, &base, &table(1.0), &mut text).unwrap();
        assert_eq!(text.lines().count(), 2);
        assert!(text.lines().all(|l| l.split(',').count() == 6), "{text}");
    }

    /// States and parameters that overflow f64 (1e300 each) give no output but the row.
    #[test]
    fn a_non_finite_torque_is_an_error_naming_the_row() {
        let model = robots::Ur5e;
        let base = vec![1e300; robots::Ur5e::BASE_PARAMETERS];
        let e = torques(&model, &base, &table(1e300), &mut String::new())
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("states.csv:7: tau"), "{e}");
        assert!(e.contains("too large for f64"), "{e}");
    }

    /// A change to the fields of a row of a states file, given the row.
    type Edit = dyn Fn(usize, &mut Vec<String>);

    /// The UR5e's state names.
    fn names() -> Vec<String> {
        ["q", "qd", "qdd"]
            .iter()
            .flat_map(|p| (1..=6).map(move |j| format!("{p}{j}")))
            .collect()
    }

    /// A states file of `rows` rows, with `edit(row, fields)` applied to each.
    fn states(dir: &Path, rows: usize, edit: impl Fn(usize, &mut Vec<String>)) -> PathBuf {
        let path = dir.join("states.csv");
        let mut text = names().join(",") + "\n";
        for r in 0..rows {
            let mut fields: Vec<String> = (0..18)
                .map(|c| format!("{}", ((r * 18 + c) as f64 * 0.37).sin()))
                .collect();
            edit(r, &mut fields);
            text += &(fields.join(",") + "\n");
        }
        std::fs::write(&path, text).unwrap();
        path
    }

    /// The torques streamed window by window: the text, or the error.
    fn streamed(path: &Path, window: usize, base: &[f64]) -> Result<String, String> {
        let mut out = Vec::new();
        match stream(&robots::Ur5e, base, path, &names(), window, &mut out) {
            Ok(()) => Ok(String::from_utf8(out).unwrap()),
            Err(Failure::Input(e)) => Err(e.to_string()),
            Err(Failure::Output(e)) => panic!("{e}"),
        }
    }

    /// The torques of the file read whole (as `robid torques` computed them before it
    /// streamed): the text, or the error.
    fn whole(path: &Path, base: &[f64]) -> Result<String, String> {
        let table =
            crate::cli::states::read_with(path, &names(), 6, "").map_err(|e| e.to_string())?;
        let mut text = "tau1,tau2,tau3,tau4,tau5,tau6\n".to_string();
        torques(&robots::Ur5e, base, &table, &mut text).map_err(|e| e.to_string())?;
        Ok(text)
    }

    /// The states read in windows of a few rows give the torques and the errors of the
    /// file read whole: the first value out of range in the first column that has one,
    /// even when a later column's comes in an earlier window; an unreadable row after a
    /// value out of range; a value out of range after a torque that is not finite.
    #[test]
    fn torques_streamed_window_by_window_are_those_of_the_whole_file() {
        let dir = tempfile::tempdir().unwrap();
        let base = vec![0.5; robots::Ur5e::BASE_PARAMETERS];
        let rows = 500;
        let good = states(dir.path(), rows, |_, _| {});
        let want = whole(&good, &base).unwrap();
        assert_eq!(want.lines().count(), rows + 1);
        for window in [1, 300, 1000, 4096, 1 << 20] {
            assert_eq!(streamed(&good, window, &base), Ok(want.clone()), "{window}");
        }
        let cases: Vec<(&str, Box<Edit>, Vec<f64>)> = vec![
            (
                "a later row in an earlier column",
                Box::new(|r, f| match r {
                    10 => f[7] = "1e7".into(),
                    400 => f[2] = "2e6".into(),
                    450 => f[2] = "3e6".into(),
                    _ => {}
                }),
                base.clone(),
            ),
            (
                "an unreadable row after a value out of range",
                Box::new(|r, f| match r {
                    10 => f[0] = "1e7".into(),
                    480 => f[5] = "x".into(),
                    _ => {}
                }),
                base.clone(),
            ),
            (
                "a value out of range after a torque that is not finite",
                Box::new(|r, f| match r {
                    10 => f[6] = "1e6".into(),
                    470 => f[17] = "5e6".into(),
                    _ => {}
                }),
                vec![1e300; robots::Ur5e::BASE_PARAMETERS],
            ),
        ];
        for (what, edit, base) in cases {
            let bad = states(dir.path(), rows, edit);
            let want = whole(&bad, &base).unwrap_err();
            for window in [1, 300, 1000, 1 << 20] {
                assert_eq!(
                    streamed(&bad, window, &base),
                    Err(want.clone()),
                    "{what}, {window}"
                );
            }
        }
    }

    /// A states file without a row is told the same way whether it is empty or holds its
    /// header alone (the empty one was "0 samples, at least 2 are needed", the header alone
    /// gave a header of torques and no row), with the header it needs; one row is enough.
    #[test]
    fn a_states_file_without_rows_is_told_so_empty_or_not() {
        let dir = tempfile::tempdir().unwrap();
        let base = vec![0.5; robots::Ur5e::BASE_PARAMETERS];
        let header = states(dir.path(), 0, |_, _| {});
        let e = streamed(&header, 1 << 20, &base).unwrap_err();
        let wanted = "no rows of joint states (the file has its header alone); write the \
                      header q1..q6,qd1..qd6,qdd1..qdd6 and one row per state below it";
        assert!(e.ends_with(wanted), "{e}");
        let empty = dir.path().join("empty.csv");
        std::fs::write(&empty, "").unwrap();
        let e = streamed(&empty, 1 << 20, &base).unwrap_err();
        assert!(
            e.ends_with(&wanted.replace("the file has its header alone", "the file is empty")),
            "{e}"
        );
        let one = states(dir.path(), 1, |_, _| {});
        assert_eq!(streamed(&one, 1 << 20, &base).unwrap().lines().count(), 2);
    }
}
