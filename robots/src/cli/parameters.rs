//! Parameter files, as read by `torques`, `simulate`, `excite` and `feasible --prior`:
//! a `[standard]` table (name = value; missing names are 0, or have no prior) or a
//! `[base]` table (every base parameter). `robid feasible` writes this format.
//!
//! What is checked, each mistake reported as `file:line:column` with the fix:
//! - exactly one table, `[standard]` or `[base]`; any other table or key is an error;
//! - every key is a parameter of the robot (the nearest name is suggested);
//! - every value is a number, finite and within +-[`PARAMETER_LIMIT`];
//! - in `[standard]`: masses `Mj`, rotor inertias `Iaj` and friction coefficients `Fvj`,
//!   `Fcj` are not negative; a first moment `MXj MYj MZj` needs a positive mass `Mj`;
//!   each link's inertia tensor `XXj XYj XZj YYj YZj ZZj` (about the frame origin, `XYj`
//!   the tensor's entry) and, with a mass, the tensor about the centre of mass are
//!   positive semidefinite (smallest eigenvalue at least -[`INERTIA_TOLERANCE`] times the
//!   largest entry, for rounded published values). Missing values count as 0; for a prior,
//!   links with missing values are not checked as a whole.

use std::collections::BTreeMap;
use std::fmt;
use std::path::Path;

use robid_runtime::Model;
use robid_runtime::feasible::{INERTIAL, LinkInertial, inertia_at_origin};
use toml::de::{DeTable, DeValue};

use super::Error;

/// The largest magnitude of a value in a parameter file (SI units: kg, kg m, kg m^2,
/// N m s/rad, N m).
pub(crate) const PARAMETER_LIMIT: f64 = 1e6;

/// How negative (relative to the largest entry) the smallest eigenvalue of a link's
/// inertia tensor may be: room for rounded published values.
pub(crate) const INERTIA_TOLERANCE: f64 = 1e-6;

/// Which table a file holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    Standard,
    Base,
}

impl fmt::Display for Kind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Kind::Standard => "standard",
            Kind::Base => "base",
        })
    }
}

/// One `name = value` of the table, with the place of its name.
#[derive(Debug, Clone, Copy)]
struct Entry {
    value: f64,
    line: usize,
    column: usize,
}

/// A parameter file read and checked for syntax, table and values.
struct File<'a> {
    path: &'a Path,
    kind: Kind,
    entries: BTreeMap<String, Entry>,
}

impl File<'_> {
    /// `file:line:column: message`.
    fn at(&self, e: &Entry, message: String) -> Error {
        format!("{}:{}:{}: {message}", self.path.display(), e.line, e.column).into()
    }
}

/// 1-based line and column (in characters) of byte `offset` of `text`.
fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let before = text.get(..offset).unwrap_or(text);
    let line = before.matches('\n').count() + 1;
    let start = before.rfind('\n').map_or(0, |i| i + 1);
    (line, before[start..].chars().count() + 1)
}

fn read(path: &Path) -> Result<File<'_>, Error> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("{}: cannot read: {e}", path.display()))?;
    let located = |offset: usize, message: &str| -> Error {
        let (line, column) = line_column(&text, offset);
        format!("{}:{line}:{column}: {message}", path.display()).into()
    };
    let doc = DeTable::parse(&text).map_err(|e| {
        let offset = e.span().map_or(0, |s| s.start);
        located(offset, &format!("not valid TOML: {}", e.message().trim()))
    })?;
    let mut found: Option<(Kind, BTreeMap<String, Entry>)> = None;
    for (key, value) in doc.get_ref() {
        let name: &str = key.get_ref();
        let at = key.span().start;
        let kind = match name {
            "standard" => Kind::Standard,
            "base" => Kind::Base,
            other => {
                return Err(located(
                    at,
                    &format!(
                        "unknown table or key `{other}`; a parameter file holds one table, \
                         [standard] or [base]"
                    ),
                ));
            }
        };
        let DeValue::Table(table) = value.get_ref() else {
            return Err(located(at, &format!("`{name}` must be a table [{name}]")));
        };
        if found.is_some() {
            return Err(located(
                at,
                &format!(
                    "a second table [{name}]; a parameter file needs exactly one of the tables \
                     [standard] or [base]"
                ),
            ));
        }
        let mut entries = BTreeMap::new();
        for (k, v) in table {
            let key: &str = k.get_ref();
            let (line, column) = line_column(&text, k.span().start);
            let source = text.get(v.span()).unwrap_or("?").trim();
            let value = number(v.get_ref())
                .filter(|x| x.is_finite())
                .ok_or_else(|| {
                    located(
                        k.span().start,
                        &format!("[{name}] `{key}` = {source} is not a finite number"),
                    )
                })?;
            if value.abs() > PARAMETER_LIMIT {
                return Err(located(
                    k.span().start,
                    &format!(
                        "[{name}] `{key}` = {source} is outside +-{PARAMETER_LIMIT:e}; give it \
                         in SI units (kg, m, kg m^2, N m)"
                    ),
                ));
            }
            entries.insert(
                key.to_owned(),
                Entry {
                    value,
                    line,
                    column,
                },
            );
        }
        found = Some((kind, entries));
    }
    let (kind, entries) = found.ok_or_else(|| {
        format!(
            "{}: needs exactly one of the tables [standard] or [base]",
            path.display()
        )
    })?;
    Ok(File {
        path,
        kind,
        entries,
    })
}

/// The number a TOML value holds (`None` for a string, a table, ..).
fn number(v: &DeValue<'_>) -> Option<f64> {
    match v {
        DeValue::Float(f) => f.as_str().parse().ok(),
        DeValue::Integer(i) => i64::from_str_radix(i.as_str(), i.radix())
            .ok()
            .map(|i| i as f64),
        _ => None,
    }
}

/// The values of `names` in the file (`None` where missing); an unknown key is an error
/// naming the nearest name.
fn values(file: &File<'_>, names: &[String]) -> Result<Vec<Option<f64>>, Error> {
    for (key, entry) in &file.entries {
        if !names.contains(key) {
            let drive =
                split(key).is_some_and(|(stem, _)| ["Ia", "Fv", "Fc", "Fo"].contains(&stem));
            let same_but_case = names.iter().any(|n| n.eq_ignore_ascii_case(key));
            let hint = match nearest(key, names) {
                Some(n) if same_but_case || !drive => format!("did you mean `{n}`?"),
                _ if drive => format!(
                    "`{key}` is a drive term, which this robot does not model: add it to the \
                     description's `drive` key (or --drive where the subcommand has it)"
                ),
                _ => format!("they are: {}", names.join(", ")),
            };
            return Err(file.at(
                entry,
                format!(
                    "[{what}] has `{key}`, which is not a {what} parameter of this robot; {hint}",
                    what = file.kind
                ),
            ));
        }
    }
    Ok(names
        .iter()
        .map(|n| file.entries.get(n).map(|e| e.value))
        .collect())
}

/// The name of `names` closest to `key`: the same but for case, or one edit away.
fn nearest<'a>(key: &str, names: &'a [String]) -> Option<&'a str> {
    if let Some(n) = names.iter().find(|n| n.eq_ignore_ascii_case(key)) {
        return Some(n);
    }
    names
        .iter()
        .map(|n| (edits(key, n), n))
        .filter(|(d, _)| *d <= 1)
        .min_by_key(|(d, _)| *d)
        .map(|(_, n)| n.as_str())
}

/// Levenshtein distance.
fn edits(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut diagonal = row[0];
        row[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let above = row[j + 1];
            row[j + 1] = (diagonal + usize::from(ca != *cb))
                .min(row[j] + 1)
                .min(above + 1);
            diagonal = above;
        }
    }
    row[b.len()]
}

/// `(stem, link)` of a standard parameter name such as `MZ3` or `Fv2`.
fn split(name: &str) -> Option<(&str, usize)> {
    let at = name.find(|c: char| c.is_ascii_digit())?;
    let link = name[at..].parse().ok()?;
    Some((&name[..at], link))
}

/// The physical checks of a `[standard]` table (see the module documentation);
/// `missing_is_zero`: a missing value counts as 0 (else a link with a missing inertial
/// value is not checked as a whole).
fn check_physical(file: &File<'_>, missing_is_zero: bool) -> Result<(), Error> {
    let mut links: BTreeMap<usize, [Option<(f64, Entry)>; 10]> = BTreeMap::new();
    for (name, entry) in &file.entries {
        let Some((stem, link)) = split(name) else {
            continue;
        };
        let what = match stem {
            "M" => Some("a mass"),
            "Ia" => Some("a rotor inertia"),
            "Fv" => Some("a viscous friction coefficient"),
            "Fc" => Some("a Coulomb friction coefficient"),
            _ => None,
        };
        if let Some(what) = what
            && entry.value < 0.0
        {
            return Err(file.at(
                entry,
                format!(
                    "`{name}` = {} is negative; {what} cannot be negative",
                    entry.value
                ),
            ));
        }
        if let Some(slot) = INERTIAL.iter().position(|s| *s == stem) {
            links.entry(link).or_insert([None; 10])[slot] = Some((entry.value, *entry));
        }
    }
    for (link, slots) in &links {
        if !missing_is_zero && slots.iter().any(Option::is_none) {
            continue;
        }
        let p: [f64; 10] = std::array::from_fn(|i| slots[i].map_or(0.0, |(v, _)| v));
        // the place of the link: its first entry in the file
        let Some(first) = slots
            .iter()
            .flatten()
            .map(|(_, e)| *e)
            .min_by_key(|e| e.line)
        else {
            continue;
        };
        let names = |stems: &[&str]| -> String {
            stems
                .iter()
                .map(|s| format!("{s}{link}"))
                .collect::<Vec<_>>()
                .join(" ")
        };
        let tensor = names(&INERTIAL[..6]);
        let scale = p[..6].iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        let lowest = inertia_at_origin(&p).symmetric_eigenvalues().min();
        if lowest < -INERTIA_TOLERANCE * scale {
            return Err(file.at(
                &first,
                format!(
                    "the inertia tensor of link {link} ({tensor}, about the frame origin) is \
                     not positive semidefinite (smallest eigenvalue {lowest:.4e} kg m^2), so no \
                     mass distribution has it; check these values and the sign of the products \
                     of inertia (XY{link} is the tensor's entry, -sum m x y)"
                ),
            ));
        }
        let mass = p[9];
        if mass == 0.0 && p[6..9].iter().any(|h| *h != 0.0) {
            return Err(file.at(
                &first,
                format!(
                    "link {link} has a first moment ({}) but no mass M{link}; give its mass",
                    names(&INERTIAL[6..9])
                ),
            ));
        }
        if let Some(l) = LinkInertial::from_standard(&p) {
            let lowest = l.principal_moments()[0];
            if lowest < -INERTIA_TOLERANCE * scale {
                let [x, y, z] = l.com;
                return Err(file.at(
                    &first,
                    format!(
                        "the inertia of link {link} about its centre of mass ({x:.4}, {y:.4}, \
                         {z:.4}) m is not positive semidefinite (smallest principal moment \
                         {lowest:.4e} kg m^2): the first moments place the centre of mass too \
                         far from the origin for the inertias {tensor}; check {} and M{link}",
                        names(&INERTIAL[6..9])
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// The base parameters of `model` from a parameter file.
pub(crate) fn base_parameters(path: &Path, model: &dyn Model) -> Result<Vec<f64>, Error> {
    let file = read(path)?;
    match file.kind {
        Kind::Standard => {
            let names = robid_runtime::model::standard_parameter_names(model);
            let standard: Vec<f64> = values(&file, &names)?
                .into_iter()
                .map(|v| v.unwrap_or(0.0))
                .collect();
            check_physical(&file, true)?;
            let mut base = vec![0.0; model.base_parameter_count()];
            model.base_from_standard_into(&standard, &mut base)?;
            if let Some(i) = base.iter().position(|b| !b.is_finite()) {
                return Err(format!(
                    "{}: base parameter {} = {} is not a finite number; check the values of \
                     its standard parameters",
                    path.display(),
                    model.base_parameter_name(i).unwrap_or("?"),
                    base[i]
                )
                .into());
            }
            Ok(base)
        }
        Kind::Base => {
            let names = robid_runtime::model::base_parameter_names(model);
            values(&file, &names)?
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
    let file = read(path)?;
    match file.kind {
        Kind::Standard => {
            let v = values(&file, names)?;
            check_physical(&file, false)?;
            Ok(v)
        }
        Kind::Base => Err(format!(
            "{}: a prior needs standard parameters, a [standard] table (base parameters leave the link parameters undetermined)",
            path.display()
        )
        .into()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn places_are_lines_and_columns_of_characters() {
        let text = "a = 1\n[standard]\nµM1 = 2\n";
        assert_eq!(line_column(text, 0), (1, 1));
        assert_eq!(line_column(text, 6), (2, 1));
        let at = text.find("M1").unwrap();
        assert_eq!(line_column(text, at), (3, 2));
    }

    #[test]
    fn the_nearest_name_is_suggested() {
        let names: Vec<String> = ["M1", "MX1", "ZZ2", "Fv1"].map(String::from).to_vec();
        assert_eq!(nearest("m1", &names), Some("M1"));
        assert_eq!(nearest("ZZ3", &names), Some("ZZ2"));
        assert_eq!(nearest("Fv", &names), Some("Fv1"));
        assert_eq!(nearest("Fc1", &names), Some("Fv1"));
        assert_eq!(nearest("Ia1", &names), None);
        assert_eq!(nearest("inertia", &names), None);
        assert_eq!(edits("kitten", "sitting"), 3);
        assert_eq!(edits("", "ab"), 2);
    }

    #[test]
    fn names_split_into_stem_and_link() {
        assert_eq!(split("MZ3"), Some(("MZ", 3)));
        assert_eq!(split("Fv12"), Some(("Fv", 12)));
        assert_eq!(split("Iam6"), Some(("Iam", 6)));
        assert_eq!(split("total"), None);
    }
}
