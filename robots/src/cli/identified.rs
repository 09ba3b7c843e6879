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
    /// `gravity` or `mass matrix` for a result of static samples (`identify --static`);
    /// absent for one of a moving log.
    #[serde(default)]
    kind: Option<String>,
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
        // a byte-order mark, as some editors write, is no JSON but no mistake either
        let json = json.strip_prefix('\u{feff}').unwrap_or(&json);
        if json.trim().is_empty() {
            return Err(format!(
                "{}: the file is empty; give the JSON report of `robid identify --json`",
                path.display()
            )
            .into());
        }
        let identified: Identified = serde_json::from_str(json).map_err(|e| {
            format!(
                "{}:{}:{}: not an identification result: {}; expected {{\"parameters\": \
                 [{{\"name\", \"value\", \"std\"}}, ..]}} as `robid identify --json` writes it",
                path.display(),
                e.line(),
                e.column(),
                json_problem(&e)
            )
        })?;
        // static samples determine only the combinations their torques see (a gravity
        // result was refused as a result of another description, "ZZR1 is missing")
        if let Some(kind) = &identified.kind {
            return Err(format!(
                "{}: a result of static samples (`robid identify --static`, {}), which \
                 holds only the {} base parameters its torques determine; feasible needs \
                 every base parameter: give the JSON report of an identification from a \
                 moving log (`robid identify --data` or `--config`)",
                path.display(),
                names::short(kind),
                identified.parameters.len()
            )
            .into());
        }
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

/// serde_json's message in words for people: its type names (`f64`, `struct Identified`,
/// `a sequence`) are Rust's, and a string of the wrong type was quoted whole.
fn json_problem(e: &serde_json::Error) -> String {
    let text = e.to_string();
    let message = text
        .rsplit_once(" at line ")
        .map_or(text.as_str(), |(m, _)| m);
    let form = |expected: &str| -> String {
        let expected = expected.trim();
        if expected.starts_with("struct IdentifiedParameter") {
            "an entry {\"name\": .., \"value\": .., \"std\": ..}".to_owned()
        } else if expected.starts_with("struct Identified") {
            "an object {\"parameters\": [..]}".to_owned()
        } else {
            match expected {
                "f64" => "a number",
                "a string" => "text in quotes",
                "a boolean" => "true or false",
                "a sequence" => "a list [..]",
                other => other,
            }
            .to_owned()
        }
    };
    let found = |given: &str| -> String {
        let given = given.trim();
        match given.strip_prefix("string ") {
            Some(quoted) => format!("the text `{}`", names::short(quoted.trim_matches('"'))),
            None => match given {
                "map" => "an object {..}".to_owned(),
                "sequence" => "a list [..]".to_owned(),
                g if g.starts_with("floating point") || g.starts_with("integer") => {
                    format!("the number {}", g.split('`').nth(1).unwrap_or(g))
                }
                g => g.to_owned(),
            },
        }
    };
    if let Some(rest) = message.strip_prefix("invalid type: ")
        && let Some((given, expected)) = rest.split_once(", expected ")
    {
        return format!("{} where {} belongs", found(given), form(expected));
    }
    if let Some(rest) = message.strip_prefix("invalid length ")
        && let Some((_, expected)) = rest.split_once(", expected ")
    {
        return format!("a list [..] where {} belongs", form(expected));
    }
    if let Some(field) = message.strip_prefix("missing field ") {
        return format!("no key {}", field.replace('`', "\""));
    }
    // the parser's own words for text that is no JSON ("expected ident", "EOF while
    // parsing a string"), said in the file's terms
    if let Some(inside) = message.strip_prefix("EOF while parsing ") {
        let what = match inside {
            "a string" => "text in quotes",
            "an object" => "an object {..}",
            "a list" => "a list [..]",
            _ => "a value",
        };
        return format!("the file ends inside {what}: it is cut short, or not JSON");
    }
    let syntax = match message {
        "expected ident" | "expected value" => {
            Some("this is not JSON (text goes in quotes; the words are true, false and null)")
        }
        "trailing characters" => Some("more text after the JSON's end"),
        "key must be a string" => Some("a key not in quotes"),
        _ => None,
    };
    if let Some(syntax) = syntax {
        return syntax.to_owned();
    }
    names::shortened(message, 200).into_owned()
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

    /// A result of the wrong shape is told at file:line:column in JSON's words, not
    /// serde's Rust types (`expected f64`, `struct Identified with 1 element`); a value of
    /// the wrong type is quoted short; a byte-order mark is read past.
    #[test]
    fn a_result_of_the_wrong_shape_is_told_in_words() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("r.json");
        let long = "Z".repeat(5000);
        let entry = |name: &str, value: &str| {
            format!("{{\"parameters\":[{{\"name\":{name},\"value\":{value},\"std\":0.1}}]}}")
        };
        for (text, want) in [
            (
                entry("\"M1\"", "\"x\""),
                "r.json:1:39: not an identification result: the text `x` where a number belongs",
            ),
            (
                entry("1", "1"),
                "r.json:1:24: not an identification result: the number 1 where text in quotes belongs",
            ),
            (
                "{\"parameters\":{}}".into(),
                "r.json:1:14: not an identification result: an object {..} where a list [..] belongs",
            ),
            (
                "[]".into(),
                "r.json:1:2: not an identification result: a list [..] where an object {\"parameters\": [..]} belongs",
            ),
            (
                "{\"parameters\":[3]}".into(),
                "r.json:1:16: not an identification result: the number 3 where an entry {\"name\": .., \"value\": .., \"std\": ..} belongs",
            ),
            (
                "{}".into(),
                "r.json:1:2: not an identification result: no key \"parameters\"",
            ),
            (
                " \n".into(),
                "r.json: the file is empty; give the JSON report",
            ),
            // no JSON at all, and JSON cut short: the parser's "expected ident" and "EOF
            // while parsing a string" were told as they are
            (
                "nonsense here".into(),
                "r.json:1:2: not an identification result: this is not JSON (text goes in quotes",
            ),
            (
                "{\"parameters\": [{\"name\": \"ab".into(),
                "r.json:1:28: not an identification result: the file ends inside text in quotes: it is cut short",
            ),
            (
                "{\"parameters\": [".into(),
                "the file ends inside a list [..]: it is cut short",
            ),
            (
                "{\"parameters\": []} x".into(),
                "not an identification result: more text after the JSON's end",
            ),
            (
                entry("\"M1\"", &format!("\"{long}\"")),
                "the text `ZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZ.. (5000 characters)` where",
            ),
        ] {
            std::fs::write(&path, &text).unwrap();
            let e = Identified::read(&path).err().expect("an error").to_string();
            assert!(e.contains(want), "{want}\nnot in\n{e}");
            assert!(e.len() < 400, "{e}");
        }
        std::fs::write(&path, format!("\u{feff}{}", entry("\"M1\"", "1.5"))).unwrap();
        let read = Identified::read(&path).unwrap();
        assert_eq!(read.parameters[0].value, 1.5);
    }
}
