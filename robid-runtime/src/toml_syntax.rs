//! TOML syntax errors of robid's own files (identification configs, friction, flexibility,
//! bounds, parameters) said for people: toml's message for a key or table given twice is
//! only "duplicate key", so it is named at its second place with what to do; a value nested
//! deeper than toml reads is named at its place with its key (as the descriptions do).

use std::path::Path;

use crate::data::TomlFile;
use crate::error::num;
use crate::limits::MAX_TEXT_BYTES;
use crate::{DataError, Error};

/// The text of a file read whole (a config, a parameter, friction, joint-flexibility or
/// bounds file, an identification result), at most [`MAX_TEXT_BYTES`] bytes: `what` names
/// the kind of file in the error of a longer one (`/dev/zero: size in bytes (read no
/// further): 67108865 is more than the limit of 67108864; parameter files have
/// kilobytes: ..`), which is read no further: a device or a pipe that never ends once filled the
/// memory. A file that is not UTF-8 is named with the offset of its first
/// invalid byte.
pub fn read_text(path: &Path, what: &str) -> crate::Result<String> {
    use std::io::Read as _;
    let io = |source| {
        Error::Data(DataError::Io {
            path: path.to_path_buf(),
            source,
        })
    };
    let file = std::fs::File::open(path).map_err(io)?;
    let mut bytes = Vec::new();
    file.take(MAX_TEXT_BYTES as u64 + 1)
        .read_to_end(&mut bytes)
        .map_err(io)?;
    if bytes.len() > MAX_TEXT_BYTES {
        return Err(Error::TooLarge {
            what: format!("{}: size in bytes (read no further)", path.display()),
            found: bytes.len() as f64,
            limit: MAX_TEXT_BYTES,
            fix: format!("{what}s have kilobytes: give the path of the {what}"),
        });
    }
    String::from_utf8(bytes).map_err(|e| {
        io(std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            format!(
                "it is not UTF-8 text (invalid byte at offset {}); save it as UTF-8",
                e.utf8_error().valid_up_to()
            ),
        ))
    })
}

/// A key or table header given a second time in a TOML text, read from toml's error
/// (parameter files word their message in their own terms from it).
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Duplicate<'a> {
    /// The key as written at its second place (`viscous`, `links.2`).
    pub(crate) key: &'a str,
    /// A table header (`[default]`) rather than a key.
    pub(crate) table: bool,
    /// Byte offset of the second place.
    pub(crate) offset: usize,
}

impl Duplicate<'_> {
    /// What is wrong and what to do, after the key.
    pub(crate) fn problem(&self) -> &'static str {
        if self.table {
            "this table is given a second time; TOML allows each table once: merge the two \
             into one"
        } else {
            "given a second time in this table; each key may be given once: delete the one \
             not meant"
        }
    }
}

/// The key or table that toml's error `e` on `text` finds given twice, if that is the error.
pub(crate) fn duplicate<'a>(text: &'a str, e: &toml::de::Error) -> Option<Duplicate<'a>> {
    if e.message().trim() != "duplicate key" {
        return None;
    }
    let span = e.span()?;
    let key = text.get(span.clone())?;
    let line_start = text.get(..span.start)?.rfind('\n').map_or(0, |i| i + 1);
    let before = &text[line_start..span.start];
    if !before.trim_start().starts_with('[') {
        return Some(Duplicate {
            key,
            table: false,
            offset: span.start,
        });
    }
    // the span of a dotted header ([links.2]) is its last part: the header is named whole
    let start = line_start + before.find('[')? + 1;
    let end = start + text[start..].find(']')?;
    let header = &text[start..end];
    Some(Duplicate {
        key: header.trim(),
        table: true,
        offset: start + (header.len() - header.trim_start().len()),
    })
}

pub(crate) use robid_core::text::line_column;

/// The error of the TOML file `path` (its text `text`, a file of kind `kind`) that toml
/// could not read: a key or table given twice is named at its second place with the fix
/// (`friction.toml:4:1: `viscous`: given a second time in this table; ..`); anything else
/// keeps toml's message after its place and the kind of file
/// (`friction.toml:3:11: invalid friction file: string values must be quoted, ..`), without
/// toml's copy of the whole line.
pub(crate) fn syntax_error(text: &str, path: &Path, kind: TomlFile, e: &toml::de::Error) -> Error {
    match not_toml(text, e) {
        Some(NotToml::CarriageReturns) => {
            return Error::Data(DataError::CarriageReturnLines {
                path: path.to_path_buf(),
            });
        }
        Some(NotToml::Json { offset }) => {
            let (line, column) = line_column(text, offset);
            return Error::Data(DataError::ConfigSyntax {
                path: path.to_path_buf(),
                line: None,
                column: None,
                kind,
                reason: format!(
                    "the file is JSON (its `{{` at line {line}, column {column}), not TOML: a \
                     {kind} is TOML, `key = value` lines under `[table]` headers; write it in TOML"
                ),
            });
        }
        None => {}
    }
    if let Some(e) = too_deep(text, path, e) {
        return e;
    }
    if let Some(e) = shape_error(text, path, e) {
        return e;
    }
    match duplicate(text, e) {
        Some(d) => {
            let (line, column) = line_column(text, d.offset);
            Error::Data(DataError::ConfigKey {
                path: path.to_path_buf(),
                line: Some(line),
                column: Some(column),
                key: if d.table {
                    format!("[{}]", d.key)
                } else {
                    d.key.to_owned()
                },
                problem: d.problem().to_owned(),
            })
        }
        // at its file:line:column, as descriptions are: toml's own message repeats the
        // whole line under a row of carets (2 MB of stderr for a 1 MB line)
        None => {
            let (line, column) = match e.span() {
                Some(span) => {
                    let (line, column) = line_column(text, span.start);
                    (Some(line), Some(column))
                }
                None => (None, None),
            };
            Error::Data(DataError::ConfigSyntax {
                path: path.to_path_buf(),
                line,
                column,
                kind,
                reason: short_numbers(e.message().trim()),
            })
        }
    }
}

/// What a text toml could not read is instead, when it can be told: toml's own messages
/// were "carriage return must be followed by newline" and "invalid key-value pair,
/// expected key" (every TOML file robid reads is checked by this one function).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum NotToml {
    /// Lines ended by a carriage return alone (classic Mac OS).
    CarriageReturns,
    /// JSON: the first character is `{`, at byte `offset`.
    Json {
        /// Byte offset of the `{`.
        offset: usize,
    },
}

/// What `text`, which toml refused with `e`, is instead of TOML, if robid can tell.
pub(crate) fn not_toml(text: &str, e: &toml::de::Error) -> Option<NotToml> {
    let lone_cr = text
        .as_bytes()
        .windows(2)
        .any(|w| w[0] == b'\r' && w[1] != b'\n')
        || text.ends_with('\r') && !text.ends_with("\r\n");
    if lone_cr && e.message().contains("carriage return") {
        return Some(NotToml::CarriageReturns);
    }
    // a TOML file never starts with `{` (a key or a `[table]` does)
    let first = text.find(|c: char| !c.is_whitespace() && c != '\u{feff}')?;
    text[first..]
        .starts_with('{')
        .then_some(NotToml::Json { offset: first })
}

/// What a value nested deeper than toml's reader follows is told: toml's own message
/// ("cannot recurse further; max recursion depth met") came after the whole line, 5,000
/// brackets of it, in toml's multi-line form.
pub(crate) const TOO_DEEP: &str = "arrays or inline tables are nested deeper than the TOML \
     reader follows; a robid file nests them two or three deep (`friction = { coulomb = 1.0 \
     }`, `position = [-3, 3]`): close the brackets this value opens";

/// The error of a value nested deeper than toml reads (toml's limit on its recursion):
/// `path:line:column: `key`: ...` ([`TOO_DEEP`]), the key being the one the line assigns,
/// the place where toml stopped.
pub(crate) fn too_deep(text: &str, path: &Path, e: &toml::de::Error) -> Option<Error> {
    if !e.message().contains("recursion depth") {
        return None;
    }
    let offset = e.span().map_or(0, |s| s.start);
    let (line, column) = line_column(text, offset);
    let line_start = text
        .get(..offset)
        .unwrap_or(text)
        .rfind('\n')
        .map_or(0, |i| i + 1);
    let assigned = text.get(line_start..offset).and_then(|l| l.split_once('='));
    let key = match assigned {
        Some((key, _)) if !key.trim().is_empty() && !key.trim_start().starts_with('[') => {
            key.trim().trim_matches('"').to_owned()
        }
        _ => "(value)".to_owned(),
    };
    Some(Error::Data(DataError::ConfigKey {
        path: path.to_path_buf(),
        line: Some(line),
        column: Some(column),
        key,
        problem: TOO_DEEP.to_owned(),
    }))
}

/// The error of a TOML text that reads as TOML but not as the file's shape (a value of
/// the wrong type, a list of the wrong length, an unknown or missing key), at the value's
/// `path:line:column` with its key, in words for people: serde's own said "invalid value:
/// integer `-1`, expected usize" and "data did not match any variant of untagged enum
/// Decimation" (robid's enums of two forms name them with `#[serde(expecting)]`).
fn shape_error(text: &str, path: &Path, e: &toml::de::Error) -> Option<Error> {
    // a syntax error is not a shape error; the spanned reader takes any integer, so a
    // value of 20 digits (no i64, no u64) is a shape error at its key
    if toml::de::DeTable::parse(text).is_err() {
        return None;
    }
    let span = e.span()?;
    let (line, column) = line_column(text, span.start);
    let value = text.get(span.clone()).map(shown).unwrap_or_default();
    let message = e.message().trim();
    // an unknown key is itself the place
    let key = match message.strip_prefix("unknown field ") {
        Some(_) => value.clone(),
        None => key_before(text, span.start),
    };
    // the key's whole path, as the checks after parsing name it (`order` was told where
    // `processing.lowpass.order` is meant, and 0 and -1 read as two different keys)
    let key = if key.starts_with('[') || key == "(value)" {
        key
    } else {
        crate::data::KeyMap::parse(text)
            .path_at(text, span.start, &key)
            .unwrap_or(key)
    };
    // a key missing from the file's top level has no key before it: the missing one is
    // the place (an empty file was told "`(value)`: missing key `temperature`"). toml
    // places it at an empty span at the start, a key missing from a table at the table's
    // header: a file that starts with a header (`[[joint]]` on line 1) had the top-level
    // `[temperature]` blamed on it
    let top_level = span.is_empty() && span.start == 0;
    let (key, problem) = match message.strip_prefix("missing field ") {
        Some(field) if key == "(value)" || top_level => (
            field.trim_matches('`').to_owned(),
            "missing from the file: add it".to_owned(),
        ),
        _ => (key, shape_problem(message, &value)),
    };
    Some(Error::Data(DataError::ConfigKey {
        path: path.to_path_buf(),
        line: Some(line),
        column: Some(column),
        key,
        problem,
    }))
}

/// Deserialises a key that takes one word of a unit-only enum `T` (`gaps = "split"`) from
/// text in quotes alone: `#[serde(default, deserialize_with = "crate::toml_syntax::word")]`.
/// serde's enums also read a table, `{ split = {} }` as `split` without a word, and told
/// `{}` as "wanted exactly 1 element, found 0 elements"; any value that is not text is now
/// "`{}` is not one word in quotes: give `refuse` or `split`", the words of `T` itself.
pub(crate) fn word<'de, D, T>(deserializer: D) -> Result<T, D::Error>
where
    D: serde::Deserializer<'de>,
    T: serde::Deserialize<'de>,
{
    deserializer.deserialize_any(Word(std::marker::PhantomData))
}

struct Word<T>(std::marker::PhantomData<T>);

impl<'de, T: serde::Deserialize<'de>> serde::de::Visitor<'de> for Word<T> {
    type Value = T;

    fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let words = variants::<T>();
        let last = words.len().saturating_sub(1);
        let listed: Vec<String> = words
            .iter()
            .enumerate()
            .map(|(i, w)| match i {
                0 => format!("`{w}`"),
                i if i == last => format!(" or `{w}`"),
                _ => format!(", `{w}`"),
            })
            .collect();
        write!(f, "one word in quotes: give {}", listed.concat())
    }

    fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<T, E> {
        use serde::de::IntoDeserializer as _;
        T::deserialize(v.into_deserializer())
    }
}

/// The words a unit-only enum `T` reads: the list its derived `Deserialize` hands to
/// `deserialize_enum`, caught by a deserialiser that reads nothing else.
fn variants<'de, T: serde::Deserialize<'de>>() -> &'static [&'static str] {
    struct Catch<'a>(&'a mut &'static [&'static str]);
    impl<'de> serde::Deserializer<'de> for Catch<'_> {
        type Error = serde::de::value::Error;
        fn deserialize_any<V: serde::de::Visitor<'de>>(
            self,
            _: V,
        ) -> Result<V::Value, Self::Error> {
            Err(serde::de::Error::custom("not an enum"))
        }
        fn deserialize_enum<V: serde::de::Visitor<'de>>(
            self,
            _: &'static str,
            variants: &'static [&'static str],
            _: V,
        ) -> Result<V::Value, Self::Error> {
            *self.0 = variants;
            Err(serde::de::Error::custom("variants caught"))
        }
        serde::forward_to_deserialize_any! {
            bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string bytes
            byte_buf option unit unit_struct newtype_struct seq tuple tuple_struct map
            struct identifier ignored_any
        }
    }
    let mut words: &'static [&'static str] = &[];
    let _ = T::deserialize(Catch(&mut words));
    words
}

/// The key a value at byte `offset` of `text` is given to: the name before the last `=`
/// ahead of it (`cutoff` in `lowpass = { cutoff = "x" }`, `rest_velocity` for an element
/// of its list, across lines); the table header when the error is on a whole table.
fn key_before(text: &str, offset: usize) -> String {
    let before = text.get(..offset).unwrap_or(text);
    let line = &before[before.rfind('\n').map_or(0, |i| i + 1)..];
    let at = text.get(offset..).unwrap_or_default();
    if line.trim().is_empty() && at.starts_with('[') {
        let header = at.lines().next().unwrap_or_default();
        return header
            .split('#')
            .next()
            .unwrap_or_default()
            .trim()
            .to_owned();
    }
    let Some(eq) = before.rfind('=') else {
        return "(value)".to_owned();
    };
    let name = before[..eq].trim_end();
    let start = name.rfind(['{', ',', '\n', '[']).map_or(0, |i| i + 1);
    match name[start..].trim().trim_matches('"') {
        "" => "(value)".to_owned(),
        key => key.to_owned(),
    }
}

/// A value as written, for a message: at most 40 characters (a 1 MB string or array was
/// quoted whole), a long number written short.
pub(crate) fn shown(value: &str) -> String {
    let value = value.trim();
    match value.parse::<f64>() {
        Ok(x) if value.len() > 24 => num(x),
        _ => robid_core::names::short(value).into_owned(),
    }
}

/// serde's message `message` on the value written `value`, in words for people.
fn shape_problem(message: &str, value: &str) -> String {
    let words = |expected: &str| -> String {
        let expected = expected.trim();
        match expected {
            "usize" | "u64" | "u32" | "u16" | "u8" => "a whole number of at least 0".to_owned(),
            "i64" | "i32" | "isize" => "a whole number".to_owned(),
            "f64" | "f32" => "a number".to_owned(),
            "a boolean" => "true or false".to_owned(),
            "a string" | "a borrowed string" => "text in quotes".to_owned(),
            "a sequence" => "a list `[..]`".to_owned(),
            "path string" => "a file path in quotes".to_owned(),
            e if e.starts_with("struct ") || e == "a map" => "a table".to_owned(),
            e => short_numbers(e),
        }
    };
    let not = |expected: &str| format!("`{value}` is not {}", words(expected));
    // toml reads an integer beyond 64 bits as i128, which no setting takes
    if message.starts_with("invalid type: integer") && message.contains("as i128") {
        return format!(
            "`{value}` is a whole number beyond 64 bits, larger than any setting takes; check \
             the value (a size meant this large is written with an exponent, 1e20)"
        );
    }
    // toml's own words for `3e400` said nothing of the fix
    if message == "floating-point number overflowed" {
        return format!(
            "`{value}` is beyond the largest floating-point number (1.8e308), larger than any \
             setting takes; check the value and its exponent"
        );
    }
    if let Some(rest) = message
        .strip_prefix("invalid type: ")
        .or_else(|| message.strip_prefix("invalid value: "))
    {
        return match rest.split_once(", expected ") {
            Some((_, expected)) => not(expected),
            None => format!("`{value}`: {}", short_numbers(rest)),
        };
    }
    if let Some(rest) = message.strip_prefix("invalid length ") {
        return match rest.split_once(", expected ") {
            Some((n, expected)) => format!(
                "`{value}` has {n} {}: give {}",
                if n == "1" { "value" } else { "values" },
                words(expected)
            ),
            None => format!("`{value}`: invalid length {rest}"),
        };
    }
    if let Some(rest) = message.strip_prefix("unknown field ") {
        return match rest.split_once(", expected ") {
            Some((_, keys)) => format!(
                "not a key of this table; the keys here are {}",
                keys.trim_start_matches("one of ")
            ),
            None => "not a key of this table".to_owned(),
        };
    }
    if let Some(rest) = message.strip_prefix("missing field ") {
        return format!("missing key {rest}: add it");
    }
    if let Some(rest) = message.strip_prefix("unknown variant `") {
        // serde quotes the value whole (a 2 MB value was echoed)
        if let Some((given, choices)) = rest.split_once("`, expected ") {
            return format!(
                "unknown value `{}`, give {}",
                robid_core::names::short(given),
                choices
            );
        }
    }
    if message == "wanted string or table" {
        return not("text in quotes or a table");
    }
    if message.starts_with("data did not match any variant") {
        return format!("`{value}` is not of a form this key takes");
    }
    // a form named by `#[serde(expecting)]`, or a check of robid's own
    if message.starts_with("a ") || message.starts_with("an ") {
        return not(message);
    }
    short_numbers(message)
}

/// toml's message with every number it quotes in backticks written short ([`num`]): serde
/// writes a value of the wrong type in full, and `range = [1e-320, 1]` was told as
/// "invalid type: floating point `0.000...01`, expected usize" with 320 digits. Only
/// quoted numbers longer than 24 characters are rewritten; the rest is toml's.
fn short_numbers(reason: &str) -> String {
    let mut out = String::with_capacity(reason.len());
    let mut rest = reason;
    while let Some(open) = rest.find('`') {
        out.push_str(&rest[..=open]);
        rest = &rest[open + 1..];
        let Some(close) = rest.find('`') else { break };
        let quoted = &rest[..close];
        match quoted.parse::<f64>() {
            Ok(x) if quoted.len() > 24 => out.push_str(&num(x)),
            _ => out.push_str(quoted),
        }
        out.push('`');
        rest = &rest[close + 1..];
    }
    out.push_str(rest);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn error(text: &str) -> toml::de::Error {
        toml::from_str::<toml::Table>(text).unwrap_err()
    }

    /// A key or a table given twice is found at its second place; other errors are not
    /// duplicates.
    #[test]
    fn a_key_or_table_given_twice_is_found_at_its_second_place() {
        let text = "[default]\nmass = [0, 1]\ninertia = [0, 1]\nmass = [0, 2]\n";
        let d = duplicate(text, &error(text)).unwrap();
        assert_eq!((d.key, d.table), ("mass", false));
        assert_eq!(line_column(text, d.offset), (4, 1));
        let e = syntax_error(text, "b.toml".as_ref(), TomlFile::Bounds, &error(text)).to_string();
        assert_eq!(
            e,
            "b.toml:4:1: `mass`: given a second time in this table; each key may be given \
             once: delete the one not meant"
        );
        let text = "[links.2]\nmass = [0, 1]\n[links.2]\ncom = [0, 1]\n";
        let d = duplicate(text, &error(text)).unwrap();
        assert!(d.table, "{d:?}");
        let e = syntax_error(text, "b.toml".as_ref(), TomlFile::Bounds, &error(text)).to_string();
        assert!(
            e.starts_with("b.toml:3:")
                && e.contains("`[links.2]`: this table is given a second time"),
            "{e}"
        );
        let text = "[default]\nmass = \n";
        assert_eq!(duplicate(text, &error(text)), None);
        let e = syntax_error(text, "b.toml".as_ref(), TomlFile::Bounds, &error(text)).to_string();
        assert!(e.starts_with("b.toml:2:8: invalid bounds file: "), "{e}");
        // a number of the wrong type is quoted short, not with its 320 digits
        #[derive(Debug, serde::Deserialize)]
        #[allow(dead_code)]
        struct Range {
            range: Vec<usize>,
        }
        let text = "range = [1e-320, 1e300]\n";
        let e = toml::from_str::<Range>(text).unwrap_err();
        let e = syntax_error(text, "c.toml".as_ref(), TomlFile::Config, &e).to_string();
        assert_eq!(
            e,
            "c.toml:1:10: `range[1]`: `1e-320` is not a whole number of at least 0"
        );
        // a number beyond a float's range, at its key with the fix (it was toml's
        // "floating-point number overflowed" alone)
        let text = "[processing]\ntrim = 3e400\n";
        let e = crate::data::Config::from_toml_str(text, "c.toml".as_ref())
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "c.toml:2:8: `processing.trim`: `3e400` is beyond the largest floating-point \
             number (1.8e308), larger than any setting takes; check the value and its exponent"
        );
        assert_eq!(short_numbers("`12` and `x` and `"), "`12` and `x` and `");
        let text = "a = 1\nµb = 2\n";
        assert_eq!(line_column(text, text.find('b').unwrap()), (2, 2));
    }

    /// A file that is not TOML is named by its kind, not as the identification config
    /// (friction, joint-flexibility and bounds files said "invalid config"); the config
    /// keeps its wording.
    #[test]
    fn a_syntax_error_names_the_kind_of_file() {
        use crate::data::Config;
        use crate::drive::FrictionModel;
        use crate::feasible::Bounds;
        use crate::simulate::Flexibility;
        let text = "[[friction]]\njoint = 1\ncoulomb = \n";
        let cases: [(Error, &str); 4] = [
            (
                FrictionModel::from_toml_str(text, "f.toml".as_ref()).unwrap_err(),
                "f.toml:3:11: invalid friction file: ",
            ),
            (
                Flexibility::from_toml_str(text, "flex.toml".as_ref()).unwrap_err(),
                "flex.toml:3:11: invalid joint-flexibility file: ",
            ),
            (
                Bounds::from_toml(text, "b.toml", 1).unwrap_err(),
                "b.toml:3:11: invalid bounds file: ",
            ),
            (
                Config::from_toml_str(text, "c.toml".as_ref()).unwrap_err(),
                "c.toml:3:11: invalid config: ",
            ),
        ];
        for (e, want) in cases {
            let e = e.to_string();
            assert!(e.starts_with(want), "{e}\nexpected {want:?}");
        }
        // a file of the right syntax but the wrong shape is named at the value's place
        let e = FrictionModel::from_toml_str("[[friction]]\njoint = \"one\"\n", "f.toml".as_ref())
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "f.toml:2:9: `friction[1].joint`: `\"one\"` is not a whole number of at least 0"
        );
        // a key missing at the top of the file (here an empty one): the key is the place (it
        // was "`(value)`: missing key `temperature`")
        let e = crate::simulate::Flexibility::from_toml_str("", "x.toml".as_ref())
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "x.toml:1:1: `temperature`: missing from the file: add it"
        );
        // so in a file that starts with a table: the table is not blamed (it was
        // "`[[joint]]`: missing key `temperature`", and `temperature` in it "not a key")
        let joint = "[[joint]]\njoint = 1\ngear_ratio = 100.0\nrotor_inertia = 1e-4\n\
                     torque_constant = 0.1\nstiffness = 1e4\nfriction = { coulomb = 1.0, load = 0.0, \
                     stribeck = 0.0, stribeck_velocity = 0.05, viscous = 2.0, \
                     coulomb_temperature = 0.0, viscous_temperature = 0.0, \
                     reference_temperature = 25.0 }\n";
        let e = crate::simulate::Flexibility::from_toml_str(joint, "x.toml".as_ref())
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "x.toml:1:1: `temperature`: missing from the file: add it"
        );
        // a key missing from that table is still the table's
        let e = crate::simulate::Flexibility::from_toml_str(
            &joint.replace("stiffness = 1e4\n", ""),
            "x.toml".as_ref(),
        )
        .unwrap_err()
        .to_string();
        assert_eq!(
            e,
            "x.toml:1:1: `[[joint]]`: missing key `stiffness`: add it"
        );
    }

    /// A value of the wrong shape is named at its place with its key, in words: serde said
    /// "data did not match any variant of untagged enum Decimation" and "invalid value:
    /// integer `-1`, expected usize", after toml's copy of the line.
    /// A key that takes one word, given a table, a number or a list, is told with its
    /// words as `gaps = "x"` is: serde said "wanted exactly 1 element, found 0 elements",
    /// "expected table, found integer", and read `{ split = {} }` as `split`.
    #[test]
    fn a_key_of_one_word_given_anything_else_is_told_its_words() {
        use crate::data::Config;
        let config = |text: &str| {
            Config::from_toml_str(text, "c.toml".as_ref())
                .unwrap_err()
                .to_string()
        };
        let gaps = "is not one word in quotes: give `refuse` or `split`";
        for (text, want) in [
            ("[processing]\ngaps = {}\n", format!("c.toml:2:8: `processing.gaps`: `{{}}` {gaps}")),
            (
                "[processing]\ngaps = { a = 1, b = 2 }\n",
                format!("c.toml:2:8: `processing.gaps`: `{{ a = 1, b = 2 }}` {gaps}"),
            ),
            (
                "[processing]\ngaps = { refuse = 1 }\n",
                format!("c.toml:2:8: `processing.gaps`: `{{ refuse = 1 }}` {gaps}"),
            ),
            (
                "[processing]\ngaps = { split = {} }\n",
                format!("c.toml:2:8: `processing.gaps`: `{{ split = {{}} }}` {gaps}"),
            ),
            ("[processing]\ngaps = 1\n", format!("c.toml:2:8: `processing.gaps`: `1` {gaps}")),
            (
                "[processing]\ngaps = \"x\"\n",
                "c.toml:2:8: `processing.gaps`: unknown value `x`, give `refuse` or `split`".to_owned(),
            ),
            (
                "[units]\nangle = { deg = true }\n",
                "c.toml:2:9: `units.angle`: `{ deg = true }` is not one word in quotes: give `rad` or `deg`"
                    .to_owned(),
            ),
            (
                "[estimation]\nmethod = {}\n",
                "c.toml:2:10: `estimation.method`: `{}` is not one word in quotes: give".to_owned(),
            ),
            (
                "[drive]\ntorque_side = [\"motor\"]\n",
                "c.toml:2:15: `drive.torque_side`: `[\"motor\"]` is not one word in quotes: give `joint` or `motor`"
                    .to_owned(),
            ),
            (
                "[processing]\nvelocity = { column = 1 }\n",
                "c.toml:2:12: `processing.velocity`: `{ column = 1 }` is not one word in quotes: give"
                    .to_owned(),
            ),
            (
                "[processing]\ndifferentiation = { method = {} }\n",
                "`processing.differentiation.method`: `{}` is not one word in quotes: give `central` or `savitzky-golay`"
                    .to_owned(),
            ),
            (
                "[runs]\nmode = 2\nfiles = [\"a.csv\", \"b.csv\"]\n",
                "c.toml:2:8: `runs.mode`: `2` is not one word in quotes: give".to_owned(),
            ),
        ] {
            let e = config(text);
            assert!(e.contains(&want), "{text}: {e}\nexpected {want:?}");
        }
        // the words themselves still read
        let c = Config::from_toml_str(
            "[processing]\ngaps = \"split\"\n[units]\nangle = \"deg\"\n",
            "c.toml".as_ref(),
        )
        .unwrap();
        assert_eq!(c.processing.gaps, crate::data::Gaps::Split);
    }

    /// A TOML file of CR line ends or of JSON is told so, the same for every kind of file:
    /// toml said "carriage return must be followed by newline" and "invalid key-value
    /// pair, expected key".
    #[test]
    fn a_file_of_cr_lines_or_json_is_told_so_in_every_toml_file() {
        use crate::data::{Config, ParameterFile};
        use crate::drive::FrictionModel;
        use crate::feasible::Bounds;
        use crate::simulate::Flexibility;
        let all = |text: &str| -> Vec<String> {
            vec![
                FrictionModel::from_toml_str(text, "f.toml".as_ref())
                    .unwrap_err()
                    .to_string(),
                Flexibility::from_toml_str(text, "f.toml".as_ref())
                    .unwrap_err()
                    .to_string(),
                Bounds::from_toml(text, "f.toml", 1)
                    .unwrap_err()
                    .to_string(),
                Config::from_toml_str(text, "f.toml".as_ref())
                    .unwrap_err()
                    .to_string(),
                ParameterFile::parse(text, "f.toml".as_ref())
                    .unwrap_err()
                    .to_string(),
            ]
        };
        for e in all("dof = 6\r[estimation]\rmethod = \"ols\"\r") {
            assert!(
                e.starts_with("f.toml: its lines end in a carriage return alone")
                    && e.contains("`tr '\\r' '\\n' < old.toml > new.toml`"),
                "{e}"
            );
        }
        let json = all("\n {\"dof\": 6}\n");
        for e in &json[..4] {
            assert!(
                e.contains(": the file is JSON (its `{` at line 2, column 2), not TOML: a ")
                    && e.contains(" is TOML, `key = value` lines under `[table]` headers"),
                "{e}"
            );
        }
        assert!(
            json[4].starts_with("f.toml:2:2: the file is JSON"),
            "{}",
            json[4]
        );
        // CR LF is TOML's own line end: read as usual
        assert!(
            Config::from_toml_str(
                "dof = 6\r\n[estimation]\r\nmethod = \"ols\"\r\n",
                "c.toml".as_ref()
            )
            .is_ok()
        );
    }

    #[test]
    fn values_of_the_wrong_shape_are_told_in_words() {
        use crate::data::Config;
        use crate::feasible::Bounds;
        let config = |text: &str| {
            Config::from_toml_str(text, "c.toml".as_ref())
                .unwrap_err()
                .to_string()
        };
        let bounds = |text: &str| {
            Bounds::from_toml(text, "b.toml", 2)
                .unwrap_err()
                .to_string()
        };
        for (got, want) in [
            (
                config("[processing]\ndecimation = \"x\"\n"),
                "c.toml:2:14: `processing.decimation`: `\"x\"` is not a whole number of at least 1 (the total \
                 factor) or a list of stage factors such as [10, 10]",
            ),
            (
                config("[processing]\ntrim = -1\n"),
                "c.toml:2:8: `processing.trim`: `-1` is not a whole number of at least 0",
            ),
            // an integer beyond 64 bits is a shape error at its key, not toml's raw report
            (
                config("dof = 99999999999999999999\n"),
                "c.toml:1:7: `dof`: `99999999999999999999` is a whole number beyond 64 bits, larger \
                 than any setting takes; check the value (a size meant this large is written \
                 with an exponent, 1e20)",
            ),
            (
                bounds("total_mass = [0, 99999999999999999999]\n"),
                "b.toml:1:18: `total_mass[2]`: `99999999999999999999` is a whole number beyond 64 \
                 bits, larger than any setting takes; check the value (a size meant this large \
                 is written with an exponent, 1e20)",
            ),
            (
                config("dof = 2\n[[source]]\nfile = \"a.csv\"\nposition = 3\n"),
                "c.toml:4:12: `source[1].position`: `3` is not a column name template such as \"q{}\" or a \
                 list of one column name per joint",
            ),
            (
                config("[drive]\ngear_ratios = [\n  1,\n  \"a\",\n]\n"),
                "c.toml:4:3: `drive.gear_ratios[2]`: `\"a\"` is not a number",
            ),
            // one number for all joints or a list (gear ratios were lists only), an
            // element that is no number told at its place (the whole list was)
            (
                config("[drive]\ntorque_constants = [0.1, true]\n"),
                "c.toml:2:26: `drive.torque_constants[2]`: `true` is not a number",
            ),
            (
                config("[drive]\ngear_ratios = \"101\"\n"),
                "c.toml:2:15: `drive.gear_ratios`: `\"101\"` is not a number for every joint or a \
                 list of one number per joint",
            ),
            (
                config("[processing]\nlowpass = { cutoff = \"x\" }\n"),
                "c.toml:2:22: `processing.lowpass.cutoff`: `\"x\"` is not a cutoff in Hz (a number) or \"auto\"",
            ),
            // a key missing at the top of the file: the key is the place (it was
            // "`(value)`: missing key `dof`")
            (
                config("[[extra_column]]\nname = \"a\"\n"),
                "c.toml:1:1: `[[extra_column]]`: missing key `terms`: add it",
            ),
            (
                config("[estimation]\nmethod = \"olz\"\n"),
                "c.toml:2:10: `estimation.method`: unknown value `olz`, give one of `ols`, `wls`, `rls`, \
                 `link-by-link`, `energy`, `per-axis`",
            ),
            // toml read `[1, 2, 3]` into a pair without a word, and `[[0, 1]]` was "invalid
            // length 1, expected an array of length 3"
            (
                bounds("total_mass = [1, 2, 3]\n"),
                "b.toml:1:14: `total_mass`: `[1, 2, 3]` has 3 values: give two values [lo, hi]",
            ),
            (
                bounds("[default]\ncom = [[0, 1]]\n"),
                "b.toml:2:7: `default.com`: `[[0, 1]]` has 1 value: give three ranges [lo, hi], of x, y \
                 and z",
            ),
            (
                bounds("[default]\ncom = [[0, 1], [0, 1], [0, 1, 2]]\n"),
                "b.toml:2:7: `default.com`: the z range has 3 values; give two, [lo, hi]",
            ),
        ] {
            assert_eq!(got, want);
        }
    }

    /// Each file read through [`syntax_error`] names a key given twice at its place (they
    /// showed toml's bare "duplicate key").
    #[test]
    fn robids_files_name_a_key_given_twice() {
        use crate::drive::FrictionModel;
        use crate::feasible::Bounds;
        use crate::simulate::Flexibility;
        let friction = "[[friction]]\njoint = 1\ncoulomb = 1.0\nload = 0.0\nstribeck = 0.0\n\
                        stribeck_velocity = 1.0\nviscous = 0.5\ncoulomb_temperature = 0.0\n\
                        viscous_temperature = 0.0\nviscous = 0.7\nreference_temperature = 25.0\n";
        let flexibility = "[temperature]\nstart = 25.0\nend = 40.0\ntime_constant = 600.0\n\
                           [[joint]]\njoint = 1\ngear_ratio = 101.0\nrotor_inertia = 0.2\n\
                           torque_constant = 0.12\nstiffness = 3.0e4\nhardening = 2.0e9\n\
                           damping = 30.0\nfriction = { coulomb = 4.0, load = 0.02, \
                           stribeck = 1.0, stribeck_velocity = 0.05, viscous = 6.0, \
                           coulomb_temperature = 0.005, viscous_temperature = 0.01, \
                           reference_temperature = 25.0, viscous = 7.0 }\n";
        let bounds = "[default]\nmass = [0.0, 1.0]\n[links.1]\nmass = [0.0, 2.0]\n\
                      [default]\ninertia = [0.0, 1.0]\n";
        let config = "dof = 2\nsample_rate = 500\n[processing]\nlowpass = { cutoff = 5.0 }\n\
                      lowpass = { cutoff = 6.0 }\n";
        let cases: [(&str, Error, &str); 4] = [
            (
                "config",
                crate::data::Config::from_toml_str(config, "c.toml".as_ref()).unwrap_err(),
                "c.toml:5:1: `lowpass`: given a second time in this table",
            ),
            (
                "friction",
                FrictionModel::from_toml_str(friction, "f.toml".as_ref()).unwrap_err(),
                "f.toml:10:1: `viscous`: given a second time in this table",
            ),
            (
                "flexibility",
                Flexibility::from_toml_str(flexibility, "flex.toml".as_ref()).unwrap_err(),
                "flex.toml:13:186: `viscous`: given a second time in this table",
            ),
            (
                "bounds",
                Bounds::from_toml(bounds, "b.toml", 1).unwrap_err(),
                "b.toml:5:2: `[default]`: this table is given a second time",
            ),
        ];
        for (file, e, want) in cases {
            let e = e.to_string();
            assert!(e.starts_with(want), "{file}: {e}");
        }
    }

    /// A device that never ends (`--parameters /dev/zero`) is read to [`MAX_TEXT_BYTES`]
    /// and no further by every reader of a whole text file: it took 8 to 14 GB of memory
    /// and did not end. A file that is not UTF-8 is named with its first bad byte.
    #[cfg(unix)]
    #[test]
    fn a_text_file_is_read_to_its_limit_and_no_further() {
        use crate::data::{Config, ParameterFile};
        use crate::drive::FrictionModel;
        use crate::simulate::Flexibility;
        let zero = Path::new("/dev/zero");
        if !zero.exists() {
            return;
        }
        let errors = [
            ("config", Config::from_file(zero).unwrap_err()),
            ("parameter file", ParameterFile::read(zero).unwrap_err()),
            ("friction file", FrictionModel::read(zero).unwrap_err()),
            (
                "joint-flexibility file",
                Flexibility::read(zero).unwrap_err(),
            ),
        ];
        for (what, e) in errors {
            assert!(matches!(e, Error::TooLarge { limit, .. } if limit == MAX_TEXT_BYTES));
            let e = e.to_string();
            assert!(
                e.starts_with("/dev/zero: size in bytes (read no further): 67108865 is more")
                    && e.ends_with(&format!(
                        "{what}s have kilobytes: give the path of the {what}"
                    )),
                "{e}"
            );
        }
        let dir = tempfile::tempdir().unwrap();
        let latin = dir.path().join("p.toml");
        std::fs::write(&latin, b"[base]\nM\xfc1 = 1\n").unwrap();
        let e = ParameterFile::read(&latin).unwrap_err().to_string();
        assert!(
            e.contains("it is not UTF-8 text (invalid byte at offset 8); save it as UTF-8"),
            "{e}"
        );
    }

    /// A key 5,000 characters long is quoted short, and the parts of a dotted key after it
    /// are kept, in each of robid's TOML files (a bounds file's `[links.<key>]` was echoed
    /// whole).
    #[test]
    fn robids_files_quote_a_long_key_short() {
        use crate::data::{Config, ParameterFile};
        use crate::drive::FrictionModel;
        use crate::feasible::Bounds;
        use crate::simulate::Flexibility;
        let long = "y".repeat(5000);
        let errors: [Error; 6] = [
            Config::from_toml_str(
                &format!("dof = 2\n[estimation]\n{long} = 1\n"),
                "c.toml".as_ref(),
            )
            .unwrap_err(),
            Config::from_toml_str(&format!("dof = 2\n[{long}]\nx = 1\n"), "c.toml".as_ref())
                .unwrap_err(),
            ParameterFile::parse(&format!("[standard]\n{long} = 1\n"), "p.toml".as_ref())
                .unwrap()
                .values(&["M1".to_owned()])
                .unwrap_err(),
            FrictionModel::from_toml_str(&format!("[[friction]]\n{long} = 1\n"), "f.toml".as_ref())
                .unwrap_err(),
            Flexibility::from_toml_str(&format!("[{long}]\nx = 1\n"), "flex.toml".as_ref())
                .unwrap_err(),
            Bounds::from_toml(&format!("[links.{long}]\nmass = [1, 2]\n"), "b.toml", 1)
                .unwrap_err(),
        ];
        for e in errors {
            let e = e.to_string();
            assert!(
                e.contains("(5000 characters)") && e.chars().count() < 600,
                "{}",
                robid_core::names::shortened(&e, 600)
            );
        }
    }

    /// A value nested 5,000 deep is told at its file:line:column with its key and what to
    /// do, in each file read through [`syntax_error`] or [`too_deep`] (it was toml's "cannot
    /// recurse further; max recursion depth met" after the whole line of brackets; the
    /// identification config and the parameter files said so until they were read
    /// through them too).
    #[test]
    fn robids_files_name_a_value_nested_too_deep() {
        use crate::data::{Config, ParameterFile};
        use crate::drive::FrictionModel;
        use crate::feasible::Bounds;
        use crate::simulate::Flexibility;
        let deep = format!("\ncoulomb = {}{}\n", "[".repeat(5000), "]".repeat(5000));
        let cases: [(Error, &str); 5] = [
            (
                Config::from_toml_str(&format!("dof = 2{deep}"), "c.toml".as_ref()).unwrap_err(),
                "c.toml:2:",
            ),
            (
                ParameterFile::parse(&format!("[standard]{deep}"), "p.toml".as_ref()).unwrap_err(),
                "p.toml:2:",
            ),
            (
                FrictionModel::from_toml_str(&format!("[[friction]]{deep}"), "f.toml".as_ref())
                    .unwrap_err(),
                "f.toml:2:",
            ),
            (
                Flexibility::from_toml_str(&format!("[temperature]{deep}"), "flex.toml".as_ref())
                    .unwrap_err(),
                "flex.toml:2:",
            ),
            (
                Bounds::from_toml(&format!("[default]{deep}"), "b.toml", 1).unwrap_err(),
                "b.toml:2:",
            ),
        ];
        for (e, want) in cases {
            let e = e.to_string();
            assert!(
                e.starts_with(want) && e.ends_with(&format!("`coulomb`: {TOO_DEEP}")),
                "{e}"
            );
            assert!(!e.contains("[[[[") && !e.contains("recurse"), "{e}");
        }
    }
}
