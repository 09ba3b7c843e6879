//! Parameter files, as read by `torques`, `simulate`, `excite` and `feasible --prior`:
//! a `[standard]` table (name = value; missing names are 0, or have no prior) or a
//! `[base]` table (every base parameter). `robid feasible` writes this format.

use std::path::Path;

use robid_runtime::Model;

use super::Error;

/// The one table of a parameter file.
enum Table {
    Standard(toml::Table),
    Base(toml::Table),
}

fn read(path: &Path) -> Result<Table, Error> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("{}: cannot read: {e}", path.display()))?;
    let mut doc: toml::Table =
        toml::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut take = |key: &str| match doc.remove(key) {
        Some(toml::Value::Table(t)) => Ok(Some(t)),
        Some(_) => Err(format!(
            "{}: `{key}` must be a table [{key}]",
            path.display()
        )),
        None => Ok(None),
    };
    match (take("standard")?, take("base")?) {
        (Some(s), None) => Ok(Table::Standard(s)),
        (None, Some(b)) => Ok(Table::Base(b)),
        _ => Err(format!(
            "{}: needs exactly one of the tables [standard] or [base]",
            path.display()
        )
        .into()),
    }
}

/// The values of `names` in `table` (`None` where missing); unknown keys and values that
/// are not finite numbers are errors.
fn values(
    table: &toml::Table,
    names: &[String],
    path: &Path,
    what: &str,
) -> Result<Vec<Option<f64>>, Error> {
    for (key, v) in table {
        if !names.contains(key) {
            return Err(format!(
                "{}: [{what}] has `{key}`, which is not a {what} parameter of this robot (they are: {}; drive terms need the matching --drive or `drive` key)",
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
        })
        .collect())
}

/// The base parameters of `model` from a parameter file.
pub(crate) fn base_parameters(path: &Path, model: &dyn Model) -> Result<Vec<f64>, Error> {
    match read(path)? {
        Table::Standard(t) => {
            let names = robid_runtime::model::standard_parameter_names(model);
            let standard: Vec<f64> = values(&t, &names, path, "standard")?
                .into_iter()
                .map(|v| v.unwrap_or(0.0))
                .collect();
            let mut base = vec![0.0; model.base_parameter_count()];
            model.base_from_standard(&standard, &mut base)?;
            Ok(base)
        }
        Table::Base(t) => {
            let names = robid_runtime::model::base_parameter_names(model);
            values(&t, &names, path, "base")?
                .into_iter()
                .zip(&names)
                .map(|(v, n)| {
                    v.ok_or_else(|| {
                        format!(
                            "{}: [base] has no `{n}`; list every base parameter",
                            path.display()
                        )
                        .into()
                    })
                })
                .collect()
        }
    }
}

/// The standard parameters `names` from a file with a `[standard]` table (`None` where
/// missing).
pub(crate) fn standard_parameters(
    path: &Path,
    names: &[String],
) -> Result<Vec<Option<f64>>, Error> {
    match read(path)? {
        Table::Standard(t) => values(&t, names, path, "standard"),
        Table::Base(_) => Err(format!(
            "{}: a prior needs standard parameters, a [standard] table (base parameters leave the link parameters undetermined)",
            path.display()
        )
        .into()),
    }
}
