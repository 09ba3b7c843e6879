//! Names in messages: the nearest names to one that names nothing, for "did you mean"
//! help, and any text a user wrote, quoted short.

use std::borrow::Cow;
use std::borrow::ToOwned;
use std::format;
use std::string::{String, ToString};
use std::vec::Vec;

/// Whether `name` can name a parameter: a word of ASCII letters, digits and `_` that
/// begins with a letter. Such a name is a bare TOML key and an identifier in generated
/// code; a name with a space or `=` written as a key changes the file's meaning.
///
/// ```
/// use robid_core::names::is_word;
/// assert!(is_word("Iam6") && is_word("fv_m6"));
/// assert!(!is_word("Iam 6") && !is_word("6Iam") && !is_word(""));
/// ```
pub fn is_word(name: &str) -> bool {
    name.starts_with(|c: char| c.is_ascii_alphabetic())
        && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
}

/// Longest text quoted whole by [`short`].
const QUOTED: usize = 40;

/// Text a user wrote (a name, a key, a setting's value), for a message: as written up to
/// 40 characters, else its first 32 and its length. A file can hold a megabyte-long key,
/// and a message that quotes it whole buries what it says.
///
/// ```
/// use robid_core::names::short;
/// assert_eq!(short("modified"), "modified");
/// let long = "x".repeat(5000);
/// assert_eq!(short(&long), format!("{}.. (5000 characters)", "x".repeat(32)));
/// ```
pub fn short(text: &str) -> Cow<'_, str> {
    shortened(text, QUOTED)
}

/// [`short`] for text that may be longer (an expression of many terms): as written up to
/// `limit` characters, else its first `limit * 4 / 5` and its length.
///
/// ```
/// use robid_core::names::shortened;
/// assert_eq!(shortened("XX2 - YY2 + ZZ3", 10), "XX2 - YY.. (15 characters)");
/// ```
pub fn shortened(text: &str, limit: usize) -> Cow<'_, str> {
    if text.char_indices().nth(limit).is_none() {
        return Cow::Borrowed(text);
    }
    let head: String = text.chars().take(limit * 4 / 5).collect();
    Cow::Owned(format!("{head}.. ({} characters)", text.chars().count()))
}

/// [`short`] for a dotted key (`links.<name>.mass`): each part quoted as [`short`] quotes
/// it, so that a long part keeps the ones after it (the key that is wrong), and at most
/// 160 characters in all.
///
/// ```
/// use robid_core::names::short_key;
/// assert_eq!(short_key("source[2].torque"), "source[2].torque");
/// let long = format!("links.{}.mass", "x".repeat(5000));
/// assert_eq!(short_key(&long), format!("links.{}.. (5000 characters).mass", "x".repeat(32)));
/// ```
pub fn short_key(key: &str) -> Cow<'_, str> {
    let whole = 4 * QUOTED;
    if key
        .split('.')
        .all(|part| matches!(short(part), Cow::Borrowed(_)))
    {
        return shortened(key, whole);
    }
    let parts: Vec<Cow<'_, str>> = key.split('.').map(short).collect();
    Cow::Owned(shortened(&parts.join("."), whole).into_owned())
}

/// How many leading characters of each name are compared. A name read from a file can
/// be megabytes long and the edit distance costs the product of the two lengths; 64
/// characters tell any two real names apart.
const COMPARED: usize = 64;

/// The Levenshtein distance between the first 64 characters of `a` and of `b`.
///
/// ```
/// use robid_core::names::distance;
/// assert_eq!(distance("MX2", "MY2"), 1);
/// assert_eq!(distance("l2", "L2"), 1);
/// ```
pub fn distance(a: &str, b: &str) -> usize {
    levenshtein(a.chars(), b.chars())
}

/// [`distance`] between the lower-case forms of `a` and `b`.
///
/// ```
/// use robid_core::names::distance_ignoring_case;
/// assert_eq!(distance_ignoring_case("Base_Link", "base_link"), 0);
/// ```
pub fn distance_ignoring_case(a: &str, b: &str) -> usize {
    levenshtein(
        a.chars().flat_map(char::to_lowercase),
        b.chars().flat_map(char::to_lowercase),
    )
}

/// `names` ordered from the nearest to `wanted`: by [`distance_ignoring_case`], then by
/// [`distance`], then alphabetically.
///
/// ```
/// use robid_core::names::nearest;
/// let links = ["base_link", "shoulder_link", "upper_arm_link"];
/// assert_eq!(nearest("Shoulder_lnk", links)[0], "shoulder_link");
/// ```
pub fn nearest<'a>(wanted: &str, names: impl IntoIterator<Item = &'a str>) -> Vec<&'a str> {
    let mut ranked: Vec<_> = names
        .into_iter()
        .map(|n| (distance_ignoring_case(n, wanted), distance(n, wanted), n))
        .collect();
    ranked.sort_unstable();
    ranked.into_iter().map(|(_, _, n)| n).collect()
}

fn levenshtein(a: impl Iterator<Item = char>, b: impl Iterator<Item = char>) -> usize {
    let b: Vec<char> = b.take(COMPARED).collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.take(COMPARED).enumerate() {
        let mut diagonal = row[0];
        row[0] = i + 1;
        for (j, &cb) in b.iter().enumerate() {
            let above = row[j + 1];
            row[j + 1] = (diagonal + usize::from(ca != cb))
                .min(row[j] + 1)
                .min(above + 1);
            diagonal = above;
        }
    }
    row[b.len()]
}

/// An operating-system error on a file in the user's terms, with the fix: a folder given
/// for a file was told "Is a directory (os error 21)". A file whose content cannot be read
/// (`InvalidData`: not UTF-8 text, a damaged compressed stream) is at fault itself, not its
/// path or permissions: its error is given with its own fix alone (a parameter file that
/// is not UTF-8 said "save it as UTF-8; check the path and permissions"); one without a
/// fix (std's "stream did not contain valid UTF-8") is told to check the file.
///
/// ```
/// use robid_core::names::io_problem;
/// let e = std::fs::read(std::env::temp_dir()).unwrap_err();
/// assert_eq!(io_problem(&e), "it is a folder, not a file; give the path of a file");
/// let e = std::fs::read("/no/such/file").unwrap_err();
/// assert_eq!(io_problem(&e), "no such file; check the path");
/// ```
pub fn io_problem(e: &std::io::Error) -> String {
    use std::io::ErrorKind;
    match e.kind() {
        ErrorKind::IsADirectory => "it is a folder, not a file; give the path of a file".into(),
        ErrorKind::NotFound => "no such file; check the path".into(),
        ErrorKind::PermissionDenied => {
            "permission denied; check the file's permissions or run as its owner".into()
        }
        ErrorKind::InvalidData => {
            let text = e.to_string();
            if text.contains("; ") {
                text
            } else {
                format!("{text}; check that it is the file meant, and not damaged")
            }
        }
        _ => {
            let text = e.to_string();
            // the error number is the system's, not the user's
            let text = match text.rfind(" (os error ") {
                Some(at) if text.ends_with(')') => text[..at].to_owned(),
                _ => text,
            };
            format!("{text}; check the path and permissions")
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Content that cannot be read keeps its own fix, without "check the path and
    /// permissions"; other errors keep that advice.
    #[test]
    fn unreadable_content_is_not_blamed_on_the_path() {
        let e = std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            "it is not UTF-8 text (invalid byte at offset 20); save it as UTF-8",
        );
        assert_eq!(
            io_problem(&e),
            "it is not UTF-8 text (invalid byte at offset 20); save it as UTF-8"
        );
        let e = std::io::Error::other("the disk went away");
        assert_eq!(
            io_problem(&e),
            "the disk went away; check the path and permissions"
        );
    }

    #[test]
    fn edits_count_insertions_deletions_and_substitutions() {
        assert_eq!(distance("", "abc"), 3);
        assert_eq!(distance("kitten", "sitting"), 3);
        assert_eq!(distance("MX1", "MX1"), 0);
        assert_eq!(distance_ignoring_case("ZZR1", "zzr1"), 0);
    }

    /// A 400 000-character name is compared on its first 64 characters: the answer is
    /// immediate (the full distance took 47 s against a few thousand links).
    #[test]
    fn a_huge_name_costs_no_more_than_a_long_one() {
        let huge = "a".repeat(400_000);
        let names: Vec<std::string::String> = (0..5000).map(|i| std::format!("link_{i}")).collect();
        let order = nearest(&huge, names.iter().map(|s| s.as_str()));
        assert_eq!(order.len(), 5000);
        assert_eq!(distance(&huge, "a"), COMPARED - 1);
    }
}
