//! The rows of a block of plain lines, read without the CSV reader: a log's body is
//! nearly always numbers between separators, one row per line. Splitting such a line at
//! its separators while its digits are read, each byte looked at once, spares the CSV
//! state machine's copy of every field and the second pass that parses it: reading the
//! hour's CSV into memory (`hour_identify`'s baseline) took 0.75 s instead of 1.0 s
//! (docs/performance.md#streaming-identification).
//!
//! A line the CSV reader could read differently is not read here: a block holding a quote,
//! a `\r` other than a line's last byte, a blank line or a `#` comment, a row with a field
//! count other than the header's or a required value that is not a finite number gives
//! `None`, and the CSV reader reads the whole block again (with its errors, located as
//! always). So every block gives the same rows and errors either way; a block given up
//! costs the plain reading up to its first such line besides (a file whose body has
//! comments or blank lines throughout reads a little slower than with the CSV reader
//! alone).

use super::table::{Part, decimal_prefix, number, trim};

/// The rows of `text` (whole lines, the last one's end optional) with `fields` fields
/// separated by `separator` (not a space: runs of spaces are the CSV reader's), the
/// requested columns at field indices `want` (`usize::MAX`: not in the file), the first
/// `required` of them required to be finite numbers, the others (up to `read`) taken as
/// NaN where they are not; `None` where the CSV reader must read the block.
pub(super) fn plain_rows(
    text: &[u8],
    separator: u8,
    fields: usize,
    want: &[usize],
    required: usize,
    read: usize,
) -> Option<Part> {
    if separator == b' ' {
        return None;
    }
    // the column each field goes to, if any (a field requested twice: the CSV reader)
    let mut slot = vec![usize::MAX; fields];
    for (k, &f) in want.iter().enumerate().take(read) {
        match slot.get_mut(f) {
            Some(s) if *s == usize::MAX => *s = k,
            Some(_) => return None,
            None => {}
        }
    }
    let mut part = Part::empty(text.len(), fields, want.len(), read);
    let mut values = vec![f64::NAN; read];
    let mut at = 0;
    let mut line = 0;
    while at < text.len() {
        if matches!(text[at], b'#' | b'\n' | b'\r') {
            // a comment or a blank line
            return None;
        }
        values.fill(f64::NAN);
        let mut field = 0;
        loop {
            let k = slot.get(field).copied().unwrap_or(usize::MAX);
            let (value, end) = if k == usize::MAX {
                (None, field_end(text, at, separator)?)
            } else {
                read_field(text, at, separator)?
            };
            if k != usize::MAX {
                match value {
                    Some(v) if v.is_finite() => values[k] = v,
                    _ if k < required => return None,
                    _ => {}
                }
            }
            field += 1;
            at = end + 1;
            match text.get(end) {
                Some(&b) if b == separator => {}
                Some(b'\r') if text.get(end + 1) == Some(&b'\n') => {
                    at += 1;
                    break;
                }
                Some(b'\n') | None => break,
                Some(_) => return None,
            }
        }
        if field != fields {
            return None;
        }
        for (column, &v) in part.columns.iter_mut().zip(&values) {
            column.push(v);
        }
        part.lines.push(line);
        line += 1;
    }
    part.newlines = line - u64::from(text.last().is_some_and(|&b| b != b'\n'));
    Some(part)
}

/// Where the field starting at `at` ends: the index of the separator, `\n` or `\r` after
/// it (or the text's length); `None` for a quote.
#[inline]
fn field_end(text: &[u8], at: usize, separator: u8) -> Option<usize> {
    let rest = &text[at..];
    let len = rest
        .iter()
        .position(|&b| b == separator || b == b'\n' || b == b'\r' || b == b'"')
        .unwrap_or(rest.len());
    (rest.get(len) != Some(&b'"')).then_some(at + len)
}

/// The value of the field starting at `at` ([`number`] of its trimmed text, `None` if
/// not a number) and where it ends ([`field_end`]). A plain decimal right up to its end
/// is read as its digits go by ([`decimal_prefix`]).
#[inline]
fn read_field(text: &[u8], at: usize, separator: u8) -> Option<(Option<f64>, usize)> {
    if let Some((v, len)) = decimal_prefix(&text[at..]) {
        let end = at + len;
        if text
            .get(end)
            .is_none_or(|&c| c == separator || c == b'\n' || c == b'\r')
        {
            return Some((Some(v), end));
        }
    }
    let end = field_end(text, at, separator)?;
    Some((number(trim(&text[at..end])), end))
}
