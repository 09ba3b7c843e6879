//! The identification result `robid feasible --identified RESULT.json` reads: the JSON
//! report of `robid identify`, checked before use. Every value finite and within
//! +-[`VALUE_LIMIT`], every standard deviation finite, positive and at most
//! [`VALUE_LIMIT`] (0 for an entry marked `known`: fixed by `[known]` parameters, an exact
//! value), each name once; and each base parameter's expression that of the description
//! given (a result of another robot whose parameters have the same names was used as
//! this one's).

use std::path::Path;

use robid_runtime::feasible::Problem;
use robid_runtime::{Num, names};
use robots::figaroh::combination;
use serde::Deserialize;

use super::Error;
use super::flags::short;

/// The largest magnitude of an identified value or standard deviation in RESULT.json.
pub(crate) const VALUE_LIMIT: f64 = 1e6;

/// The identified parameters of RESULT.json.
#[derive(Deserialize)]
pub(super) struct Identified {
    pub(super) parameters: Vec<IdentifiedParameter>,
}

/// One entry of RESULT.json's `parameters`.
#[derive(Deserialize)]
pub(super) struct IdentifiedParameter {
    pub(super) name: String,
    /// The base parameter in the standard ones (`ZZ1 + Ia1 + 0.07*MZ3`); empty for an
    /// extra column of the identification config.
    #[serde(default)]
    pub(super) expression: String,
    pub(super) value: f64,
    pub(super) std: f64,
    /// Fixed by known standard parameters (`estimation.known`): std 0, an exact value.
    #[serde(default)]
    pub(super) known: bool,
}

impl Identified {
    /// RESULT.json read and its entries checked.
    pub(super) fn read(path: &Path) -> Result<Identified, Error> {
        let json = robid_runtime::data::read_text(path, "identification result")?;
        let identified: Identified = serde_json::from_str(&json).map_err(|e| {
            format!(
                "{}: not an identification result: {e}; expected {{\"parameters\": \
                 [{{\"name\", \"value\", \"std\"}}]}}",
                path.display()
            )
        })?;
        identified.check(path)?;
        Ok(identified)
    }

    /// Refuses an entry whose value or standard deviation is not finite or out of range,
    /// or whose name an earlier entry has, naming the entry.
    fn check(&self, path: &Path) -> Result<(), Error> {
        if self.parameters.is_empty() {
            return Err(format!(
                "{}: `parameters` is empty; give the JSON report of `robid identify --json`",
                path.display()
            )
            .into());
        }
        for (i, p) in self.parameters.iter().enumerate() {
            let problem = if !names::is_word(&p.name) {
                // written back as a TOML key by `robid feasible` (`Iam 6 = ..` was written,
                // and a name with `=` or a line end could add keys of its own)
                Some(
                    "the name is not a parameter name (ASCII letters, digits and `_`, \
                     beginning with a letter, as `robid identify` writes them)"
                        .to_owned(),
                )
            } else if !p.value.is_finite() || p.value.abs() > VALUE_LIMIT {
                Some(format!(
                    "value {} is outside +-{VALUE_LIMIT:e}",
                    short(p.value)
                ))
            } else if p.std == 0.0 && !p.known {
                Some(
                    "std 0 claims an exact value, but the entry is not `\"known\": true` (a \
                     parameter `robid identify` fixed by [known] values); give its deviation"
                        .to_owned(),
                )
            } else if !(p.std >= 0.0 && p.std <= VALUE_LIMIT) {
                Some(format!(
                    "std {} is outside [0, {VALUE_LIMIT:e}]; a standard deviation is positive \
                     (0 for a known parameter)",
                    short(p.std)
                ))
            } else {
                None
            };
            let problem = problem.or_else(|| {
                self.parameters[..i]
                    .iter()
                    .position(|q| q.name == p.name)
                    .map(|first| format!("the name is also entry {first}; keep one of them"))
            });
            if let Some(problem) = problem {
                return Err(format!(
                    "{}: parameters[{i}] `{}`: {problem}; repair the entry or identify again",
                    path.display(),
                    names::short(&p.name)
                )
                .into());
            }
        }
        Ok(())
    }

    /// Refuses a result whose base parameters are other combinations of the standard ones
    /// than `problem`'s (the description `robot`'s): a result of another robot, or of
    /// another version of this one's description, whose parameters have the same names.
    /// Expressions that are not sums of numbers times standard parameters (a description
    /// with symbols) are not compared.
    pub(super) fn check_expressions(
        &self,
        path: &Path,
        problem: &Problem,
        robot: &Path,
    ) -> Result<(), Error> {
        for p in &self.parameters {
            let Some(b) = problem.base_names.iter().position(|n| *n == p.name) else {
                continue;
            };
            let Some(terms) = linear_terms(&p.expression) else {
                continue;
            };
            let mut written = vec![0.0; problem.standard_names.len()];
            let mut known = true;
            for (name, c) in terms {
                match problem.standard_names.iter().position(|n| *n == name) {
                    Some(s) => written[s] += c,
                    None => known = false,
                }
            }
            let row = problem.k.row(b);
            let same = known
                && row
                    .iter()
                    .zip(&written)
                    .all(|(k, w)| (k - w).abs() <= 1e-6 * k.abs().max(1e-6));
            if !same {
                return Err(format!(
                    "{}: `{}` is {} in the result, but {} for {}: the result was identified \
                     with another robot, or another version of this description; give the \
                     description (and --drive) it was identified with, or identify again",
                    path.display(),
                    names::short(&p.name),
                    names::shortened(&p.expression, 400),
                    expression(row.iter().copied(), &problem.standard_names),
                    robot.display()
                )
                .into());
            }
        }
        Ok(())
    }
}

/// `expression` as (standard parameter, coefficient) terms, when it is a sum of terms
/// `c*NAME`, `NAME` or their negatives (as `robid identify` writes them), read by
/// [`combination`].
fn linear_terms(expression: &str) -> Option<Vec<(String, f64)>> {
    if expression.trim().is_empty() {
        return None;
    }
    let terms = combination(expression, str::to_owned)?;
    let word = |name: &str| {
        name.starts_with(|ch: char| ch.is_ascii_alphabetic())
            && name.chars().all(|ch| ch.is_ascii_alphanumeric())
    };
    terms
        .into_iter()
        .map(|(name, c)| word(&name).then_some((name, c)))
        .collect()
}

/// A row of K as `robid identify` writes an expression.
fn expression(row: impl Iterator<Item = f64>, names: &[String]) -> String {
    let mut text = String::new();
    for (c, name) in row.zip(names).filter(|(c, _)| *c != 0.0) {
        let sign = if c < 0.0 { "-" } else { "+" };
        if text.is_empty() {
            text += if c < 0.0 { "-" } else { "" };
        } else {
            text += &format!(" {sign} ");
        }
        if (c.abs() - 1.0).abs() > 1e-12 {
            text += &format!("{}*", Num::rounded(c.abs(), 6));
        }
        text += name;
    }
    if text.is_empty() {
        "0".to_owned()
    } else {
        text
    }
}

/// An error of the identified result `path` read into the problem: its message names the
/// entries; the library's argument (`names`, `std`) is no place in the file.
pub(super) fn about_identified(path: &Path, e: robid_runtime::Error) -> Error {
    match e {
        robid_runtime::Error::Setting { problem, .. } => {
            format!("{}: {problem}", path.display()).into()
        }
        other => other.into(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn expressions_are_read_as_sums_of_terms() {
        let terms = linear_terms("XX2 - 0.050625*M4 + 0.225*M3 - YY2").unwrap();
        assert_eq!(
            terms,
            [
                ("M3".to_owned(), 0.225),
                ("M4".to_owned(), -0.050625),
                ("XX2".to_owned(), 1.0),
                ("YY2".to_owned(), -1.0)
            ]
        );
        assert_eq!(linear_terms("-MZ4").unwrap(), [("MZ4".to_owned(), -1.0)]);
        assert_eq!(linear_terms("M2/L2"), None);
        assert_eq!(linear_terms("L2^2*M2"), None);
        assert_eq!(linear_terms("sin(q)*M2"), None);
        assert_eq!(linear_terms(""), None);
        let names = ["XX2", "M3", "YY2"].map(String::from);
        assert_eq!(
            expression([1.0, 0.225, -1.0].into_iter(), &names),
            "XX2 + 0.225*M3 - YY2"
        );
        assert_eq!(expression([-2.0, 0.0, 0.0].into_iter(), &names), "-2*XX2");
    }
}
