//! Places in a text, for messages that point into a file.

/// The 1-based line and column (in characters) of byte `offset` of `text`, as an editor
/// numbers them: an offset inside a character is that character's, one beyond the end is
/// the end, and a byte-order mark at the start of the text is no column (with it counted,
/// every place on a first line written by a Windows editor was one column off).
///
/// ```
/// use robid_core::text::line_column;
/// assert_eq!(line_column("a = 1\nb = x", 10), (2, 5));
/// assert_eq!(line_column("\u{feff}name = 1", 10), (1, 8));
/// assert_eq!(line_column("é = 1", 1), (1, 1));
/// ```
pub fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let mut offset = offset.min(text.len());
    while !text.is_char_boundary(offset) {
        offset -= 1;
    }
    let before = &text[..offset];
    let line = before.matches('\n').count() + 1;
    let start = before.rfind('\n').map_or(0, |i| i + 1);
    let mut this_line = &before[start..];
    if start == 0 {
        this_line = this_line.strip_prefix('\u{feff}').unwrap_or(this_line);
    }
    (line, this_line.chars().count() + 1)
}

#[cfg(test)]
mod tests {
    use super::line_column;

    /// Lines and columns count characters, after the last line break; a mark at the start
    /// of the text only is skipped; offsets beyond the text or inside a character do not
    /// panic.
    #[test]
    fn places_are_counted_as_an_editor_counts_them() {
        let text = "\u{feff}ab\ncé\u{feff}d\n";
        assert_eq!(line_column(text, 0), (1, 1));
        assert_eq!(line_column(text, 3), (1, 1));
        assert_eq!(line_column(text, 4), (1, 2));
        assert_eq!(line_column(text, 6), (2, 1));
        // `d` after `c`, `é` and a mark inside the text, which is a character there
        assert_eq!(line_column(text, 12), (2, 4));
        assert_eq!(line_column(text, 8), (2, 2));
        assert_eq!(line_column(text, 9), (2, 3));
        assert_eq!(line_column(text, 100), (3, 1));
    }
}
