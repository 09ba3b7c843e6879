//! Joint states read from CSV files (`torques --states`, `simulate --trajectory`),
//! checked against their documented range: every position, velocity and acceleration
//! (`q`, `qd`, `qdd` columns; rad, rad/s, rad/s^2 or m, m/s, m/s^2) within
//! +-[`STATE_LIMIT`], so that a stray value (1e308) is named where it is instead of
//! turning the results into inf or NaN.

use std::path::Path;

use robid_runtime::data::{Table, read_columns};

use super::Error;

/// The largest magnitude of a joint state value.
pub(crate) const STATE_LIMIT: f64 = 1e6;

/// Reads the columns `names` of `path` (the runtime's CSV reader: numbers, finite) and
/// checks the state columns (`q*`, `qd*`, `qdd*`) against [`STATE_LIMIT`].
pub(crate) fn read(path: &Path, names: &[String]) -> Result<Table, Error> {
    let table = read_columns(path, names)?;
    check(&table, names)?;
    Ok(table)
}

/// Checks the state columns of `table` (columns in the order of `names`).
pub(crate) fn check(table: &Table, names: &[String]) -> Result<(), Error> {
    for (column, name) in table.columns.iter().zip(names) {
        if !name.starts_with('q') {
            continue;
        }
        if let Some((k, x)) = column
            .iter()
            .enumerate()
            .find(|(_, x)| !x.is_finite() || x.abs() > STATE_LIMIT)
        {
            let line = table.lines.get(k).copied().unwrap_or(0);
            return Err(format!(
                "{}:{line}: column `{name}` is {x:e}, outside the range of a joint state \
                 (+-{STATE_LIMIT:e} rad, rad/s, rad/s^2 or m, m/s, m/s^2); repair or remove this row",
                table.path.display()
            )
            .into());
        }
    }
    Ok(())
}
