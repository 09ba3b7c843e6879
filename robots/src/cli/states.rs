//! Joint states read from CSV files (`torques --states`, `simulate --trajectory`),
//! checked against their documented range: every position, velocity and acceleration
//! (`q`, `qd`, `qdd` columns; rad, rad/s, rad/s^2 or m, m/s, m/s^2) within
//! +-[`STATE_LIMIT`], so that a stray value (1e308) is named where it is instead of
//! turning the results into inf or NaN.

use std::path::Path;

use robid_runtime::Count;
use robid_runtime::data::{
    ColumnMapping, DataError, Table, read_columns, read_header, surplus_joint,
};
use robid_runtime::limits::MAX_TORQUE;

use super::Error;

/// The largest magnitude of a joint state value.
pub(crate) const STATE_LIMIT: f64 = 1e6;

/// Reads the columns `names` of `path` (the runtime's CSV reader: numbers, finite) and
/// checks the state columns (`q*`, `qd*`, `qdd*`) against [`STATE_LIMIT`]. A file with a
/// position column for one joint more than the robot's `dof` is refused: it holds the
/// states of another robot. `remedy` (empty, or "; ...") ends the message for a file of
/// positions alone with the command's own way (see [`with_header`]).
pub(crate) fn read_with(
    path: &Path,
    names: &[String],
    dof: usize,
    remedy: &str,
) -> Result<Table, Error> {
    refuse_surplus(path, dof)?;
    let table = read_columns(path, names).map_err(|e| with_header(e, names, remedy))?;
    check(&table, names)?;
    Ok(table)
}

/// A column missing from a states file, told with the header the file needs
/// (`q1..q6,qd1..qd6,qdd1..qdd6`): the reader's own advice, "pass the names of the file's
/// columns", is for a caller in code, and no flag of `robid` passes column names. A file
/// with positions and no velocities or accelerations at all (a log of positions) is told
/// so, not to "rename its columns": this command reads them and does not differentiate;
/// `remedy` (empty, or "; ..." ) adds the command's other way.
pub(crate) fn with_header(e: robid_runtime::Error, names: &[String], remedy: &str) -> Error {
    match e {
        robid_runtime::Error::Data(DataError::MissingColumn {
            path,
            column,
            available,
            ..
        }) => match no_derivatives(&path, &column, &available, names, remedy) {
            Some(message) => message.into(),
            None => robid_runtime::Error::Data(DataError::MissingColumn {
                path,
                column,
                available,
                mapping: Box::new(ColumnMapping::Header {
                    expected: header_pattern(names),
                }),
            })
            .into(),
        },
        e => e.into(),
    }
}

/// The message of [`with_header`] for a missing velocity or acceleration column `column`
/// when the file has position columns and no column of that kind at all.
fn no_derivatives(
    path: &Path,
    column: &str,
    available: &[String],
    names: &[String],
    remedy: &str,
) -> Option<String> {
    // whether the header has a column `{stem}{number}`
    let has = |stem: &str| {
        available.iter().any(|a| {
            a.strip_prefix(stem)
                .is_some_and(|r| !r.is_empty() && r.chars().all(|c| c.is_ascii_digit()))
        })
    };
    let stem = column.trim_end_matches(|c: char| c.is_ascii_digit());
    if !matches!(stem, "qd" | "qdd") || !has("q") || has(stem) {
        return None;
    }
    let lacking = match (has("qd"), has("qdd")) {
        (false, false) => "velocities (`qd1`..) or accelerations (`qdd1`..)",
        (true, _) => "accelerations (`qdd1`..)",
        (false, true) => "velocities (`qd1`..)",
    };
    // columns that might hold them under other names
    let known = |a: &str| {
        a == "t"
            || ["q", "qd", "qdd", "tau"].iter().any(|s| {
                a.strip_prefix(s)
                    .is_some_and(|r| !r.is_empty() && r.chars().all(|c| c.is_ascii_digit()))
            })
    };
    let others: Vec<String> = available
        .iter()
        .filter(|a| !known(a))
        .map(|a| format!("`{a}`"))
        .collect();
    let rename = if others.is_empty() {
        String::new()
    } else {
        format!(
            "; if its columns {} hold them, rename them to these names",
            others.join(", ")
        )
    };
    Some(format!(
        "{}: no column `{column}`: the file has joint positions but no {lacking} (found: {}); \
         this command reads them from the file, it does not differentiate positions: add \
         them, computed from the positions (e.g. central differences of the positions \
         low-passed above the motion's frequencies), under the header {}{remedy}{rename}",
        path.display(),
        available.join(", "),
        header_pattern(names)
    ))
}

/// A states file without a row of states, `why` (empty, or its header alone): both told
/// the same way, with the header the file needs. `robid torques` needs one row; an empty
/// file was told "0 samples, at least 2 are needed" while a header alone was taken, and
/// wrote a header without torques.
pub(crate) fn no_rows(path: &Path, names: &[String], why: &str) -> Error {
    format!(
        "{}: no rows of joint states ({why}); write the header {} and one row per state \
         below it",
        path.display(),
        header_pattern(names)
    )
    .into()
}

/// `names` written short: each run `q1, q2, .., q6` as `q1..q6`, joined by commas.
fn header_pattern(names: &[String]) -> String {
    // a name's prefix and joint number, when it ends in one
    let split = |name: &str| {
        let digits = name.len() - name.trim_end_matches(|c: char| c.is_ascii_digit()).len();
        let (prefix, number) = name.split_at(name.len() - digits);
        Some((prefix.to_owned(), number.parse::<usize>().ok()?))
    };
    let mut parts: Vec<String> = Vec::new();
    let mut k = 0;
    while k < names.len() {
        let Some((prefix, first)) = split(&names[k]) else {
            parts.push(names[k].clone());
            k += 1;
            continue;
        };
        let mut last = k;
        while names
            .get(last + 1)
            .and_then(|n| split(n))
            .is_some_and(|(p, j)| p == prefix && j == first + (last + 1 - k))
        {
            last += 1;
        }
        parts.push(if last > k {
            format!("{}..{}", names[k], names[last])
        } else {
            names[k].clone()
        });
        k = last + 1;
    }
    parts.join(",")
}

/// Refuses a file with a position column for one joint more than the robot's `dof` (what
/// [`read_with`] checks first): it holds the states of another robot.
pub(crate) fn refuse_surplus(path: &Path, dof: usize) -> Result<(), Error> {
    if let Some(column) = surplus_joint(&read_header(path)?, "q{}", dof) {
        return Err(format!(
            "{}: has a column `{column}`, for joint {} of a robot with {}; give \
             the description of the robot these states are of",
            path.display(),
            dof + 1,
            Count(dof, "joint")
        )
        .into());
    }
    Ok(())
}

/// Checks the state columns of `table` (columns in the order of `names`), and the torque
/// columns (`tau*`, `robid payload`'s data) against the torque limit of every data file,
/// [`MAX_TORQUE`]: a torque of 1e308 was read and ended the weighted fit with "the WLS
/// weights is not finite", naming neither the row nor the column.
pub(crate) fn check(table: &Table, names: &[String]) -> Result<(), Error> {
    match out_of_range(table, names) {
        Some((_, _, e)) => Err(e),
        None => Ok(()),
    }
}

/// The first value of `table` outside its range, in the first column that has one (the
/// error of [`check`]), with its column and row.
pub(crate) fn out_of_range(table: &Table, names: &[String]) -> Option<(usize, usize, Error)> {
    for (c, (column, name)) in table.columns.iter().zip(names).enumerate() {
        let (limit, range) = if name.starts_with("tau") {
            (MAX_TORQUE, "of a joint torque (+-1e7 N m or N)")
        } else if name.starts_with('q') {
            (
                STATE_LIMIT,
                "of a joint state (+-1e6 rad, rad/s, rad/s^2 or m, m/s, m/s^2)",
            )
        } else {
            continue;
        };
        if let Some((k, x)) = column
            .iter()
            .enumerate()
            .find(|(_, x)| !x.is_finite() || x.abs() > limit)
        {
            let line = table.lines.get(k).copied().unwrap_or(0);
            return Some((
                c,
                k,
                format!(
                    "{}:{line}: column `{name}` is {x:e}, outside the range {range}; repair or \
                     remove this row",
                    table.path.display()
                )
                .into(),
            ));
        }
    }
    None
}
