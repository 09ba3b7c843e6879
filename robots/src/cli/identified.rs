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
use robid_symbolic::{Arena, Id, Node, Robot, Values};
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
    /// The robust (Newey-West) standard deviation, when the identification had them.
    #[serde(default)]
    pub(super) robust_std: Option<f64>,
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
                p.robust_std
                    .filter(|r| !(*r >= 0.0 && *r <= VALUE_LIMIT))
                    .map(|r| {
                        format!(
                            "robust_std {} is outside [0, {VALUE_LIMIT:e}]; a standard \
                             deviation is positive (or leave robust_std out)",
                            short(r)
                        )
                    })
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
    /// than `problem`'s (the description `robot`'s, read from `robot_path`): a result of
    /// another robot, or of another version of this one's description, whose parameters
    /// have the same names. Each expression is read by robid's expression reader and taken
    /// as a linear combination of the standard parameters ([`linear_form`]), its
    /// coefficients evaluated at the description's geometric values; one that is no
    /// expression, not linear in the standard parameters, or names none of them or another
    /// name is refused as not written by `robid identify` for this description. An entry
    /// without an expression (a result written by hand with name, value and std) is not
    /// compared.
    pub(super) fn check_expressions(
        &self,
        path: &Path,
        problem: &Problem,
        robot: &Robot,
        robot_path: &Path,
    ) -> Result<(), Error> {
        for (i, p) in self.parameters.iter().enumerate() {
            let Some(b) = problem.base_names.iter().position(|n| *n == p.name) else {
                continue;
            };
            if p.expression.trim().is_empty() {
                continue;
            }
            let written = linear_form(&p.expression, &problem.standard_names, robot.symbols())
                .map_err(|problem| {
                    format!(
                        "{}: parameters[{i}] `{}`: the expression `{}` {problem}: the file was \
                         not written by robid identify for this description ({}); give the \
                         result identify wrote with it (and --drive), or identify again",
                        path.display(),
                        names::short(&p.name),
                        names::shortened(&p.expression, 400),
                        robot_path.display()
                    )
                })?;
            let row = problem.k.row(b);
            let same = row
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
                    robot_path.display()
                )
                .into());
            }
        }
        Ok(())
    }
}

/// The coefficients, one per name of `standard`, of `text` read as a linear combination
/// of the standard parameters (`ZZ1 + Ia1 + 0.07*MZ3`, `XX2 - 81/1600*M4`,
/// `L3^2*M4 + ZZ3`), its coefficients evaluated at the values of the description's
/// geometric `symbols`; else what is wrong with it, to follow "the expression `text`": it
/// is no expression robid reads, names something that is neither a standard parameter
/// nor a symbol, names no standard parameter, or is not linear in them (a coefficient or a
/// term that holds one, a constant term, a coefficient that is no finite number there).
fn linear_form(
    text: &str,
    standard: &[String],
    symbols: &[(String, Option<f64>)],
) -> Result<Vec<f64>, String> {
    let mut arena = Arena::new();
    let root = arena
        .parse(text)
        .map_err(|e| format!("is not an expression robid reads ({e})"))?;
    let mut unknown = Vec::new();
    // (index in `standard`, symbol) of the standard parameters it names
    let mut named = Vec::new();
    let mut values = Values::new();
    for symbol in arena.free_symbols(&[root]) {
        let name = arena.symbol_name(symbol);
        if let Some(s) = standard.iter().position(|n| n == name) {
            named.push((s, symbol));
        } else if let Some((_, value)) = symbols.iter().find(|(n, _)| n == name) {
            match value {
                Some(v) => values.set(symbol, *v),
                None => return Err(format!("holds the symbol `{name}`, which has no value")),
            }
        } else {
            unknown.push(format!("`{}`", names::short(name)));
        }
    }
    if !unknown.is_empty() {
        return Err(format!(
            "names {}, neither a standard parameter nor a geometric symbol of the description",
            unknown.join(", ")
        ));
    }
    if named.is_empty() {
        return Err("names no standard parameter".to_owned());
    }
    let is_standard = |arena: &Arena, id: Id| {
        arena
            .free_symbols(&[id])
            .iter()
            .any(|s| named.iter().any(|(_, n)| n == s))
    };
    // sign() is differentiated as 0: a standard parameter inside it is no linear term
    let mask = arena.reachable(&[root]);
    for (index, _) in mask.iter().enumerate().filter(|(_, reached)| **reached) {
        if let Node::Sign(x) = arena.node_at(index)
            && is_standard(&arena, *x)
        {
            return Err("is not linear in the standard parameters (one is inside sign())".into());
        }
    }
    let mut row = vec![0.0; standard.len()];
    for &(s, symbol) in &named {
        let coefficient = arena.diff(root, symbol);
        if is_standard(&arena, coefficient) {
            return Err(format!(
                "is not linear in the standard parameters: its coefficient of `{}` is `{}`",
                standard[s],
                names::shortened(&arena.display(coefficient), 100)
            ));
        }
        row[s] = arena
            .eval(&[coefficient], &values)
            .map_err(|e| format!("cannot be evaluated: {e}"))?[0];
        if !row[s].is_finite() {
            return Err(format!(
                "has a coefficient of `{}` that is not a finite number at the description's \
                 values",
                standard[s]
            ));
        }
    }
    // linear, not affine: nothing is left with every standard parameter at zero
    for &(_, symbol) in &named {
        values.set(symbol, 0.0);
    }
    let constant = arena
        .eval(&[root], &values)
        .map_err(|e| format!("cannot be evaluated: {e}"))?[0];
    if constant.is_nan() || constant.abs() > 1e-9 {
        return Err(format!(
            "is not linear in the standard parameters: it has the constant term {}",
            short(constant)
        ));
    }
    Ok(row)
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

    /// Expressions are read by robid's expression reader as linear combinations of the
    /// standard parameters, exact coefficients `n/d` and the description's symbols
    /// included; anything else is refused with what is wrong.
    #[test]
    fn expressions_are_read_as_linear_combinations() {
        let standard = ["M3", "M4", "XX2", "YY2", "MZ4"].map(String::from);
        let symbols = [("L3".to_owned(), Some(0.5)), ("L9".to_owned(), None)];
        let form = |text: &str| linear_form(text, &standard, &symbols);
        assert_eq!(
            form("XX2 - 0.050625*M4 + 0.225*M3 - YY2").unwrap(),
            [0.225, -0.050625, 1.0, -1.0, 0.0]
        );
        assert_eq!(form("-MZ4").unwrap(), [0.0, 0.0, 0.0, 0.0, -1.0]);
        assert_eq!(
            form("XX2 - 81/1600*M4").unwrap(),
            [0.0, -0.050625, 1.0, 0.0, 0.0]
        );
        assert_eq!(
            form("L3^2*M4 + 2*L3*(M3 - MZ4)").unwrap(),
            [1.0, 0.25, 0.0, 0.0, -1.0]
        );
        for (text, want) in [
            (
                "#### garbage ###",
                "is not an expression robid reads (at character 0",
            ),
            (
                "XX1 + 0.5*M4 + )",
                "is not an expression robid reads (at character",
            ),
            (
                "null*M4",
                "names `null`, neither a standard parameter nor a geometric symbol",
            ),
            ("XX1 + M4", "names `XX1`, neither"),
            ("L3^2", "names no standard parameter"),
            ("", "is not an expression robid reads"),
            (
                "M3*M4",
                "not linear in the standard parameters: its coefficient of `M3` is `M4`",
            ),
            (
                "M4^2",
                "not linear in the standard parameters: its coefficient of `M4` is `2*M4`",
            ),
            (
                "sin(M4)",
                "not linear in the standard parameters: its coefficient of `M4`",
            ),
            ("XX2/M4", "not linear in the standard parameters"),
            ("sign(M4) + M3", "one is inside sign()"),
            ("M4 + 1", "it has the constant term 1"),
            ("L9*M4", "holds the symbol `L9`, which has no value"),
        ] {
            let e = form(text).unwrap_err();
            assert!(e.contains(want), "{text}: {want}\nnot in\n{e}");
        }
        let names = ["XX2", "M3", "YY2"].map(String::from);
        assert_eq!(
            expression([1.0, 0.225, -1.0].into_iter(), &names),
            "XX2 + 0.225*M3 - YY2"
        );
        assert_eq!(expression([-2.0, 0.0, 0.0].into_iter(), &names), "-2*XX2");
    }

    /// The expressions `robid identify` writes (a reference robot's compiled ones, the
    /// derivation's for other descriptions: symbols, every drive term, a URDF's chain with
    /// and without --base/--tip) are read back as the rows of K the check compares with.
    #[test]
    fn the_expressions_identify_writes_are_the_rows_of_k() {
        use super::super::description::{DescriptionFlags, read};
        use super::super::identify::model_of;
        let every_term = || ["Ia", "Fv", "Fc", "Fo"].map(String::from).to_vec();
        let urdf = "../data/example_robot_data/ur5/ur5_robot.urdf";
        let mut descriptions: Vec<(String, DescriptionFlags)> = robots::models::REFERENCES
            .iter()
            .map(|r| {
                (
                    format!("descriptions/{}.toml", r.name),
                    DescriptionFlags::default(),
                )
            })
            .collect();
        descriptions.extend([
            (
                "tests/fixtures/symbolic_drive_arm.toml".to_owned(),
                DescriptionFlags::default(),
            ),
            (
                "tests/fixtures/calibrated_arm.toml".to_owned(),
                DescriptionFlags::default(),
            ),
            (
                "tests/fixtures/general_frames_arm.toml".to_owned(),
                DescriptionFlags::default(),
            ),
            (
                "descriptions/kr6r900.toml".to_owned(),
                DescriptionFlags::default(),
            ),
            (
                "configs/tx40_robot.toml".to_owned(),
                DescriptionFlags::default(),
            ),
            (
                urdf.to_owned(),
                DescriptionFlags {
                    drive: every_term(),
                    ..DescriptionFlags::default()
                },
            ),
            (
                urdf.to_owned(),
                DescriptionFlags {
                    drive: every_term(),
                    base_link: Some("shoulder_link".into()),
                    tip_link: Some("wrist_2_link".into()),
                },
            ),
        ]);
        for (path, flags) in &descriptions {
            let robot = read(Path::new(path), flags).unwrap();
            let chosen = model_of(&robot).unwrap();
            let problem = robots::extraction::problem(&robot).unwrap();
            assert_eq!(chosen.base.len(), problem.base_names.len(), "{path}");
            for (b, base) in chosen.base.iter().enumerate() {
                let row = linear_form(&base.expression, &problem.standard_names, robot.symbols())
                    .unwrap_or_else(|e| panic!("{path}: {} {e}", base.expression));
                for (k, w) in problem.k.row(b).iter().zip(&row) {
                    assert!(
                        (k - w).abs() <= 1e-9 * k.abs().max(1.0),
                        "{path}: {}: {k} {w}",
                        base.expression
                    );
                }
            }
        }
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
        assert_eq!(read.parameters[0].robust_std, None);
    }

    /// A robust deviation, when the entry has one, is read and checked as the classical
    /// one is.
    #[test]
    fn robust_deviations_are_read_and_checked() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("r.json");
        let entry = |robust: &str| {
            format!(
                "{{\"parameters\":[{{\"name\":\"M1\",\"value\":1.5,\"std\":0.1,\"robust_std\":{robust}}}]}}"
            )
        };
        std::fs::write(&path, entry("0.4")).unwrap();
        assert_eq!(
            Identified::read(&path).unwrap().parameters[0].robust_std,
            Some(0.4)
        );
        for bad in ["-0.4", "1e300"] {
            std::fs::write(&path, entry(bad)).unwrap();
            let e = Identified::read(&path).err().expect("an error").to_string();
            assert!(
                e.contains("parameters[0] `M1`: robust_std") && e.contains("is outside [0,"),
                "{bad}: {e}"
            );
        }
    }
}
