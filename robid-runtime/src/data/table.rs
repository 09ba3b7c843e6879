//! Reading selected columns of a CSV file (with header, optionally gzip-compressed).
//!
//! The reader is `csv_core` (the parser of the `csv` crate, driven over the text in
//! memory): fields separated by `,` (or by the one separator the header line uses
//! instead: `;`, a tab or spaces, single as UR's RTDE recorder writes them or in runs that
//! align columns, [`separator`]), optionally quoted with `"`, surrounding spaces trimmed,
//! lines that start with `#` are comments, empty lines are skipped, `\n` or `\r\n` line ends
//! (`\r` alone is refused, naming the conversion), and a UTF-8 byte-order mark is ignored.
//!
//! The text is read in windows of [`WINDOW`] bytes cut at a line end, so that a long record
//! is never held as text beside its values ([`for_each_window`] hands each window's rows on
//! as they are parsed). A window without quote characters is cut at line ends into blocks
//! that the same reader parses in parallel; from the first window with a quote on, the rest
//! of the file is parsed in one block (a quoted field may hold a line end). Every way gives
//! the same table and the same errors. A block of plain lines (numbers between
//! separators, nothing the CSV reader would read otherwise) is split directly instead
//! (`plain.rs`), a quarter less time for a log's body; any other block, and any block with
//! an error, is read by `csv_core`, which gives the same rows and says where the error is.
//!
//! Limits ([`crate::limits`]): the file (after decompression) at most
//! [`MAX_FILE_BYTES`](crate::limits::MAX_FILE_BYTES), its header at most
//! [`MAX_COLUMNS`](crate::limits::MAX_COLUMNS) fields, at most
//! [`MAX_ROWS`](crate::limits::MAX_ROWS) data rows. Every value read must be a finite
//! number; [`Table::check_range`] checks a column against the range of its quantity.

use crate::DataError;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

use flate2::read::MultiGzDecoder;
use rayon::prelude::*;

use crate::Count;
use crate::data::plain::plain_rows;
use crate::error::{Error, Result};
use crate::limits::{MAX_COLUMNS, MAX_FILE_BYTES, MAX_LINE_BYTES, MAX_ROWS, Quantity, check_size};

/// Selected columns of one CSV file, with the file line of every row.
#[derive(Debug, Clone)]
pub struct Table {
    /// The file.
    pub path: PathBuf,
    /// Requested columns in the requested order, each with one value per row.
    pub columns: Vec<Vec<f64>>,
    /// 1-based file line of each row (for error messages).
    pub lines: Vec<u64>,
}

impl Table {
    /// Number of rows.
    pub fn rows(&self) -> usize {
        self.lines.len()
    }

    /// `file:line` of row `k` (0-based), for messages.
    pub fn location(&self, k: usize) -> String {
        format!(
            "{}:{}",
            self.path.display(),
            self.lines.get(k).copied().unwrap_or(0)
        )
    }

    /// Checks that column `index` (named `name` in messages) lies within the range of
    /// `quantity` ([`Quantity::limit`]); the error names the file, line and column.
    pub fn check_range(&self, index: usize, name: &str, quantity: Quantity) -> Result<()> {
        let Some(column) = self.columns.get(index) else {
            return Ok(());
        };
        match crate::data::dataset::first_outside(quantity, column) {
            None => Ok(()),
            Some(k) => Err(Error::Data(DataError::OutOfRange {
                location: self.location(k),
                what: format!("column `{}`", crate::data::error::quoted(name)),
                quantity: quantity.name(),
                value: column[k],
                limit: quantity.limit(),
                lower: quantity.lower(),
            })),
        }
    }
}

/// Where the column names of a read came from: it decides what an error about a missing
/// column tells the user to fix.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
#[non_exhaustive]
pub enum ColumnMapping {
    /// Names passed in code.
    #[default]
    Code,
    /// A fixed file format with this header (e.g. a trajectory file).
    Header {
        /// The header the format requires, e.g. `t,q1..qn,qd1..qdn,qdd1..qddn`.
        expected: String,
    },
    /// robid's default mapping, used when no config file is given: the header
    /// `t,q1..qn,qd1..qdn,qdd1..qddn,tau1..taun` (what `robid simulate` writes).
    Default,
    /// A config file's `[[source]]` table.
    Config {
        /// The config file.
        path: PathBuf,
        /// 1-based line of the key that names the column, when known.
        line: Option<usize>,
        /// The key, e.g. `source[1].torque`.
        key: String,
    },
}

/// A missing column of a file whose columns are fixed (no config maps them) said with the
/// header the file needs, `expected`; other errors as they are.
pub(crate) fn header_needed(e: Error, expected: String) -> Error {
    match e {
        Error::Data(DataError::MissingColumn {
            path,
            column,
            available,
            ..
        }) => Error::Data(DataError::MissingColumn {
            path,
            column,
            available,
            mapping: Box::new(ColumnMapping::Header { expected }),
        }),
        e => e,
    }
}

impl ColumnMapping {
    /// What to do about a column that is not in the header.
    pub fn fix(&self) -> String {
        match self {
            ColumnMapping::Code => {
                "pass the names of the file's columns, or rename the file's columns".into()
            }
            ColumnMapping::Header { expected } => {
                format!("this file needs the header {expected}; rename its columns")
            }
            ColumnMapping::Default => "the default column mapping needs the header \
                 t,q1..qn,qd1..qdn,qdd1..qddn,tau1..taun (as `robid simulate` writes it); \
                 rename the file's columns to these names, or map the file's own columns \
                 in a config (`robid identify --example-config` prints one) given with --config"
                .into(),
            ColumnMapping::Config { path, line, key } => match line {
                Some(l) => format!("fix `{key}` at {}:{l} or the file's header", path.display()),
                None => format!("fix `{key}` in {} or the file's header", path.display()),
            },
        }
    }
}

/// Reads the columns `names` from a CSV file. A file whose first bytes are the gzip
/// magic number is decompressed. See the module documentation for the format.
pub fn read_columns(path: &Path, names: &[String]) -> Result<Table> {
    read_columns_in(path, names, Optional::none(names))
}

/// Which of the requested columns are optional, and in how many rows they are read.
///
/// The columns from `from` on are optional: read in the first `rows` data rows of the
/// file only (a table's optional column holds its values for those of its rows, and is
/// empty past them, so that a long file parses them in its first window or two only),
/// each value the field's number where it is a finite number and NaN where it is not (a
/// field that is text, empty, NaN or infinite; a column missing from the header or named
/// twice), never an error.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Optional {
    /// The first optional column.
    pub(crate) from: usize,
    /// The data rows in which optional columns are read.
    pub(crate) rows: usize,
}

impl Optional {
    /// Every one of `names` required.
    pub(crate) fn none(names: &[String]) -> Optional {
        Optional {
            from: names.len(),
            rows: 0,
        }
    }
}

/// [`read_columns`] with optional columns (see [`Optional`]).
pub(crate) fn read_columns_in(path: &Path, names: &[String], optional: Optional) -> Result<Table> {
    let file = open(path)?;
    let size = file.metadata().map_or(0, |m| m.len() as usize);
    collect(file, path, names, optional, size)
}

/// [`for_each_window`] over the file at `path` (refused when larger than
/// [`MAX_FILE_BYTES`]), with optional columns (see [`Optional`]).
pub(crate) fn for_each_window_of(
    path: &Path,
    names: &[String],
    optional: Optional,
    window: usize,
    each: impl FnMut(Table, usize) -> Result<()> + Send,
) -> Result<()> {
    windows_of(open(path)?, path, names, optional, window, each)
}

/// Opens a CSV file, refusing a pipe ([`not_a_stream`]) and one larger than
/// [`MAX_FILE_BYTES`].
fn open(path: &Path) -> Result<std::fs::File> {
    not_a_stream(path)?;
    let file = std::fs::File::open(path).map_err(|source| io(path, source))?;
    let size = file.metadata().map_or(0, |m| m.len());
    check_size(
        || format!("{}: file size in bytes", path.display()),
        size as f64,
        MAX_FILE_BYTES as usize,
        "split the file",
    )?;
    Ok(file)
}

/// Refuses a data file that is a pipe or a socket before it is opened: robid opens a data
/// file more than once, and a pipe gives its data to the first opening only (the next
/// one waited forever for a writer).
pub(crate) fn not_a_stream(path: &Path) -> Result<()> {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt as _;
        if let Ok(kind) = std::fs::metadata(path).map(|m| m.file_type())
            && (kind.is_fifo() || kind.is_socket())
        {
            return Err(Error::Data(DataError::Stream {
                path: path.to_path_buf(),
            }));
        }
    }
    Ok(())
}

fn io(path: &Path, source: std::io::Error) -> Error {
    Error::Data(DataError::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// The column names of a CSV file (gzip-compressed or not), as the reader of its columns
/// sees them: the first record after blank and `#` comment lines, quotes removed, fields
/// trimmed (a quoted header or a blank first line once gave other names here than there,
/// and so another default mapping). Reads at most the first MiB of text.
pub fn read_header(path: &Path) -> Result<Vec<String>> {
    use std::io::BufRead as _;
    let io = |source| {
        Error::Data(DataError::Io {
            path: path.to_path_buf(),
            source,
        })
    };
    not_a_stream(path)?;
    let mut file = std::io::BufReader::new(std::fs::File::open(path).map_err(io)?);
    let gzip = file.fill_buf().map_err(io)?.starts_with(&[0x1f, 0x8b]);
    let reader: Box<dyn Read> = if gzip {
        Box::new(MultiGzDecoder::new(file))
    } else {
        Box::new(file)
    };
    let mut text = Vec::new();
    // a gzip stream that does not decode is a damaged file, as for the columns: "cannot
    // read: incomplete deflate stream; check the path and permissions" sent the user to
    // the permissions
    reader
        .take(1 << 20)
        .read_to_end(&mut text)
        .map_err(|source| {
            if gzip {
                Error::Data(DataError::Corrupt {
                    path: path.to_path_buf(),
                    reason: format!("gzip: {source}"),
                })
            } else {
                io(source)
            }
        })?;
    let text = text.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(&text);
    let mut records = Records::new(text, separator(text));
    if records.next_record().is_none() {
        return Ok(Vec::new());
    }
    Ok((0..records.len())
        .map(|i| String::from_utf8_lossy(records.field(i)).into_owned())
        .collect())
}

/// Reads the columns `names` from any reader (gzip-compressed or not); `path` is used
/// in messages.
pub fn read_columns_from(reader: impl Read + Send, path: &Path, names: &[String]) -> Result<Table> {
    collect(reader, path, names, Optional::none(names), 0)
}

/// The windows of [`for_each_window`] gathered into one table (`size`: the file's size
/// when known, to allocate the required columns once; `optional`: see [`Optional`]).
fn collect(
    reader: impl Read + Send,
    path: &Path,
    names: &[String],
    optional: Optional,
    size: usize,
) -> Result<Table> {
    let mut table = Table {
        path: path.to_path_buf(),
        columns: vec![Vec::new(); names.len()],
        lines: Vec::new(),
    };
    let mut first = true;
    windows_of(reader, path, names, optional, WINDOW, |part, read| {
        if std::mem::take(&mut first) && size > read && read > 0 {
            // the whole file at the first window's bytes per row, and a little more
            let rows = part.rows() as f64 * (size as f64 / read as f64) * 1.02;
            let rows = (rows as usize).min(MAX_ROWS);
            table.lines.reserve(rows);
            let required = optional.from.min(names.len());
            table.columns[..required]
                .iter_mut()
                .for_each(|c| c.reserve(rows));
        }
        table.lines.extend(&part.lines);
        for (c, v) in table.columns.iter_mut().zip(part.columns) {
            c.extend(v);
        }
        Ok(())
    })?;
    Ok(table)
}

/// Bytes of text read and parsed at a time.
pub const WINDOW: usize = 16 << 20;

/// Reads the columns `names` window by window: `each` gets the rows of each window of
/// about `window` bytes of text (whole lines, in order, lines numbered in the file) and
/// the bytes of text read up to that window's end. The header must come first; the first
/// error (of the text or of `each`) stops the reading. A gzip stream (recognised by its
/// magic number) is decompressed as it is read. Each window is handed to `each` while the
/// next one is read and parsed (both in parallel), so a slow `each` (a record written to
/// disk) costs little more than the parsing.
pub fn for_each_window(
    reader: impl Read + Send,
    path: &Path,
    names: &[String],
    window: usize,
    each: impl FnMut(Table, usize) -> Result<()> + Send,
) -> Result<()> {
    windows_of(reader, path, names, Optional::none(names), window, each)
}

/// [`for_each_window`] with optional columns (see [`Optional`]).
fn windows_of(
    reader: impl Read + Send,
    path: &Path,
    names: &[String],
    optional: Optional,
    window: usize,
    mut each: impl FnMut(Table, usize) -> Result<()> + Send,
) -> Result<()> {
    let mut windows = Windows::new(reader, path, names, optional, window)?;
    let mut pending = None;
    loop {
        let (handed, next) = rayon::join(
            || {
                pending
                    .take()
                    .map_or(Ok(()), |(table, read)| each(table, read))
            },
            || windows.next(),
        );
        // the earlier window's error first, as if they had run in turn
        handed?;
        match next? {
            Some(w) => pending = Some(w),
            None => return Ok(()),
        }
    }
}

/// A file's text read and parsed window by window ([`for_each_window`]).
struct Windows<'a> {
    source: Box<dyn Read + Send + 'a>,
    text: Text<'a>,
    names: &'a [String],
    /// Which of `names` are optional, and in how many rows they are read.
    optional: Optional,
    /// Bytes of text wanted per window (doubled while a line does not fit).
    window: usize,
    header: Option<Header>,
    /// A quote was seen: the rest of the file is one block.
    quoted: bool,
    /// Data rows parsed so far.
    rows: AtomicUsize,
    /// The last window was handed out.
    done: bool,
    /// The buffer of the text before the last window's, kept for the next window's text.
    spare: Vec<u8>,
    /// The error of reading ahead the next window's text, given where that reading would
    /// have been (at the next window).
    ahead_error: Option<Error>,
}

impl<'a> Windows<'a> {
    fn new(
        reader: impl Read + Send + 'a,
        path: &'a Path,
        names: &'a [String],
        optional: Optional,
        window: usize,
    ) -> Result<Self> {
        use std::io::BufRead as _;
        let mut input = std::io::BufReader::new(reader);
        let gzip = input
            .fill_buf()
            .map_err(|source| io(path, source))?
            .starts_with(&[0x1f, 0x8b]);
        let source: Box<dyn Read + Send> = if gzip {
            Box::new(MultiGzDecoder::new(input))
        } else {
            Box::new(input)
        };
        Ok(Self {
            source,
            text: Text {
                bytes: Vec::new(),
                read: 0,
                end: false,
                gzip,
                path,
            },
            names,
            optional: Optional {
                from: optional.from.min(names.len()),
                rows: optional.rows,
            },
            window: window.max(1),
            header: None,
            quoted: false,
            rows: AtomicUsize::new(0),
            done: false,
            spare: Vec::new(),
            ahead_error: None,
        })
    }

    /// The next window's rows and the bytes of text read up to its end; `None` after the
    /// last window (a file with a header and no rows gives one empty window).
    fn next(&mut self) -> Result<Option<(Table, usize)>> {
        if self.done {
            return Ok(None);
        }
        if let Some(e) = self.ahead_error.take() {
            return Err(e);
        }
        let (path, names) = (self.text.path, self.names);
        let text = &mut self.text;
        loop {
            text.fill(&mut self.source, self.window)?;
            if self.header.is_none() {
                match Header::read(&text.bytes, text.end, path, names, self.optional.from)? {
                    Some(h) => {
                        text.bytes.drain(..h.body_start);
                        self.header = Some(h);
                    }
                    // the header line goes past the window: read more
                    None => {
                        let line = line_ends(&text.bytes) + 1;
                        grow(&mut self.window, text, line)?;
                        continue;
                    }
                }
            }
            let Some(h) = self.header.as_mut() else {
                continue;
            };
            self.quoted = self.quoted || text.bytes.contains(&b'"');
            if self.quoted {
                text.fill(&mut self.source, usize::MAX)?;
            }
            let cut = if text.end {
                text.bytes.len()
            } else {
                match text.bytes.iter().rposition(|&b| b == b'\n') {
                    Some(i) => i + 1,
                    // one line longer than the window: read more
                    None => {
                        grow(&mut self.window, text, h.base)?;
                        continue;
                    }
                }
            };
            let body = &text.bytes[..cut];
            let cuts = if self.quoted {
                vec![0, body.len()]
            } else {
                cuts(body)
            };
            let rows = &self.rows;
            // the optional columns are read while the rows before the window are fewer
            // than their rows, and cut to them
            let before = rows.load(Ordering::Relaxed);
            let optional = before < self.optional.rows;
            let read = text.read - (text.bytes.len() - cut);
            self.done = text.end && text.bytes.len() == cut;
            // the next window's text (the rest of this one's, then read) is read while
            // this one is parsed, into the buffer before this one's; a quoted file is
            // read whole above
            let mut next = std::mem::take(&mut self.spare);
            next.clear();
            next.extend_from_slice(&text.bytes[cut..]);
            let mut ahead = Text {
                bytes: next,
                read: text.read,
                end: text.end,
                gzip: text.gzip,
                path,
            };
            let source = &mut self.source;
            let window = self.window;
            let (parts, filled) = rayon::join(
                || -> Vec<Part> {
                    cuts.par_windows(2)
                        .map(|w| block(body, w[0], w[1], h, optional, rows))
                        .collect()
                },
                || ahead.fill(source, window),
            );
            let mut table = join_parts(parts, path, names, h)?;
            let keep = self.optional.rows.saturating_sub(before);
            for column in table.columns.iter_mut().skip(h.required) {
                column.truncate(keep);
            }
            check_size(
                || format!("{}: data rows", path.display()),
                rows.load(Ordering::Relaxed) as f64,
                MAX_ROWS,
                "split the file",
            )?;
            self.ahead_error = filled.err();
            (text.read, text.end) = (ahead.read, ahead.end);
            self.spare = std::mem::replace(&mut text.bytes, ahead.bytes);
            return Ok(Some((table, read)));
        }
    }
}

/// Doubles `window` for a line (1-based `line`) that has not ended in `text`, or refuses
/// a line that has not ended in [`MAX_LINE_BYTES`].
fn grow(window: &mut usize, text: &Text<'_>, line: u64) -> Result<()> {
    if text.bytes.len() >= MAX_LINE_BYTES {
        return Err(Error::Data(DataError::LineTooLong {
            path: text.path.to_path_buf(),
            line,
            limit: text.bytes.len(),
        }));
    }
    *window = (*window * 2).min(MAX_LINE_BYTES);
    Ok(())
}

/// Line ends in `bytes`.
fn line_ends(bytes: &[u8]) -> u64 {
    bytes.iter().filter(|&&b| b == b'\n').count() as u64
}

/// The parts of a window joined into its table, in file order, the columns side by side
/// (in parallel); the first part's error instead when a part has one. `h.base` moves to
/// the line after the window.
fn join_parts(
    mut parts: Vec<Part>,
    path: &Path,
    names: &[String],
    h: &mut Header,
) -> Result<Table> {
    let mut bases = Vec::with_capacity(parts.len());
    for part in &mut parts {
        if let Some(e) = part.error.take() {
            return Err(e.locate(path, names, h.base));
        }
        bases.push(h.base);
        h.base += part.newlines;
    }
    let total: usize = parts.iter().map(|p| p.lines.len()).sum();
    let mut columns: Vec<Vec<f64>> = (0..names.len())
        .map(|_| Vec::with_capacity(total))
        .collect();
    let mut lines = Vec::with_capacity(total);
    rayon::join(
        || {
            columns.par_iter_mut().enumerate().for_each(|(c, column)| {
                for part in &parts {
                    column.extend_from_slice(&part.columns[c]);
                }
            })
        },
        || {
            for (part, base) in parts.iter().zip(&bases) {
                lines.extend(part.lines.iter().map(|l| l + base));
            }
        },
    );
    Ok(Table {
        path: path.to_path_buf(),
        columns,
        lines,
    })
}

/// The text of a file read so far and not yet parsed.
struct Text<'p> {
    bytes: Vec<u8>,
    /// Bytes of text read in all.
    read: usize,
    /// The end was reached.
    end: bool,
    gzip: bool,
    path: &'p Path,
}

impl Text<'_> {
    /// Reads until `bytes` holds `window` bytes or the text ends, within
    /// [`MAX_FILE_BYTES`]; a decoding error is a corrupt file.
    fn fill(&mut self, source: &mut dyn Read, window: usize) -> Result<()> {
        while !self.end && self.bytes.len() < window {
            let want = (window - self.bytes.len()).min(1 << 22);
            let before = self.bytes.len();
            let got = source
                .take(want as u64)
                .read_to_end(&mut self.bytes)
                .map_err(|source| {
                    if self.gzip {
                        Error::Data(DataError::Corrupt {
                            path: self.path.to_path_buf(),
                            reason: format!("gzip: {source}"),
                        })
                    } else {
                        io(self.path, source)
                    }
                })?;
            debug_assert_eq!(got, self.bytes.len() - before);
            if got == 0 {
                self.end = true;
            }
            self.read += got;
            check_size(
                || {
                    format!(
                        "{}: {}size in bytes",
                        self.path.display(),
                        if self.gzip { "decompressed " } else { "" }
                    )
                },
                self.read as f64,
                MAX_FILE_BYTES as usize,
                "split the file",
            )?;
        }
        Ok(())
    }
}

/// The header of a file: where each requested column is, and where the body starts.
struct Header {
    /// Field index of each requested column (`usize::MAX` for an optional column that is
    /// not in the header once).
    want: Vec<usize>,
    /// The field separator ([`separator`]).
    separator: u8,
    /// The requested columns before this one are required, the others optional.
    required: usize,
    /// Fields per row.
    fields: usize,
    /// Bytes of the text before the body (byte-order mark, comments, header).
    body_start: usize,
    /// The 1-based line of the next window's first line.
    base: u64,
}

impl Header {
    /// The header at the start of `text` (`None`: its line is not complete yet and more
    /// text follows).
    fn read(
        text: &[u8],
        end: bool,
        path: &Path,
        names: &[String],
        required: usize,
    ) -> Result<Option<Header>> {
        let bom = if text.starts_with(b"\xEF\xBB\xBF") {
            3
        } else {
            0
        };
        let text = &text[bom..];
        // (a separator chosen from a header line not yet whole is not used: the line's
        // end is waited for below)
        let separator = separator(text);
        let mut records = Records::new(text, separator);
        let Some(header_line) = records.next_record() else {
            if !end {
                return Ok(None);
            }
            // no count: how many rows a file needs is the caller's to say
            return Err(Error::Data(DataError::EmptyFile {
                path: path.to_path_buf(),
            }));
        };
        // the body starts on the line after the header's
        let after = records.consumed;
        // csv_core ends a record at a lone CR too, but the body is cut at LFs: a file of
        // CR line ends was its header and nothing else ("no data rows")
        if after > 0
            && text[after - 1] == b'\r'
            && text.get(after).is_some_and(|&b| b != b'\n')
            && !text[after..].contains(&b'\n')
        {
            return Err(Error::Data(DataError::CarriageReturnLines {
                path: path.to_path_buf(),
            }));
        }
        let body_start = if after > 0 && text.get(after - 1) == Some(&b'\n') {
            Some(after)
        } else {
            text[after.min(text.len())..]
                .iter()
                .position(|&b| b == b'\n')
                .map(|i| after + i + 1)
        };
        let body_start = match body_start {
            Some(b) => b,
            None if end => text.len(),
            None => return Ok(None),
        };
        check_size(
            || format!("{}: fields in the header", path.display()),
            records.len() as f64,
            MAX_COLUMNS,
            "keep only the columns needed in the file",
        )?;
        let header: Vec<String> = (0..records.len())
            .map(|i| String::from_utf8_lossy(records.field(i)).into_owned())
            .collect();
        let want = wanted(&header, names, required, path, text, header_line)?;
        Ok(Some(Header {
            want,
            separator,
            required,
            fields: header.len(),
            body_start: bom + body_start,
            base: header_line + 1,
        }))
    }
}

/// Bytes per parallel block of an unquoted body.
const CHUNK: usize = 1 << 20;

/// The field separator of a file whose text starts with `text`, from its header line (the
/// first line that is neither blank nor a `#` comment): `,` when that line holds one, else
/// `;`, else a tab, else a space (UR's RTDE recorder separates its fields by single
/// spaces; runs of them align columns, [`Records`]), else `,` (one column). A header names its columns once, so the separator it
/// uses is not a guess; the data rows must use the same.
fn separator(text: &[u8]) -> u8 {
    let line = text
        .split(|&b| b == b'\n')
        .map(trim)
        .find(|l| !l.is_empty() && !l.starts_with(b"#"))
        .unwrap_or_default();
    SEPARATORS
        .into_iter()
        .find(|s| line.contains(s))
        .unwrap_or(b',')
}

/// The separators a file may use, in the order [`separator`] looks for them.
const SEPARATORS: [u8; 4] = [b',', b';', b'\t', b' '];

/// The csv reader over text in memory: records as fields, with the line each ends on.
/// It is `csv_core`, the state machine of the `csv` crate, with the crate's defaults (`"`
/// quotes, `\n` or `\r\n` line ends), the file's separator and `#` comment lines, driven
/// over the slice directly (no buffer copy). Where the separator is a space, a run of
/// spaces is one separator and spaces before the first field or after the last are none
/// (columns aligned by a text export or `printf`): the empty fields they give are dropped,
/// and a line of spaces alone is a blank line. A space-separated file cannot express an
/// empty field, so none is lost.
struct Records<'a> {
    core: csv_core::Reader,
    input: &'a [u8],
    consumed: usize,
    out: Vec<u8>,
    ends: Vec<usize>,
    fields: usize,
    /// Runs of spaces separate fields ([`Records`]).
    collapse: bool,
}

impl<'a> Records<'a> {
    fn new(input: &'a [u8], separator: u8) -> Self {
        Self {
            core: csv_core::ReaderBuilder::new()
                .delimiter(separator)
                .comment(Some(b'#'))
                .build(),
            input,
            consumed: 0,
            out: vec![0; 4096],
            ends: vec![0; 64],
            fields: 0,
            collapse: separator == b' ',
        }
    }

    /// Reads the next record; returns the 1-based line (in `input`) it ends on.
    fn next_record(&mut self) -> Option<u64> {
        use csv_core::ReadRecordResult as R;
        let (mut outlen, mut endlen) = (0, 0);
        loop {
            let (res, nin, nout, nend) = self.core.read_record(
                &self.input[self.consumed..],
                &mut self.out[outlen..],
                &mut self.ends[endlen..],
            );
            self.consumed += nin;
            outlen += nout;
            endlen += nend;
            match res {
                // an empty input, passed on the next round, tells the reader it is the end
                R::InputEmpty => {}
                R::OutputFull => {
                    let n = self.out.len();
                    self.out.resize(2 * n, 0);
                }
                R::OutputEndsFull => {
                    let n = self.ends.len();
                    self.ends.resize(2 * n, 0);
                }
                R::Record => {
                    self.fields = endlen;
                    if self.collapse {
                        self.drop_empty_fields();
                        if self.fields == 0 {
                            // a line of spaces
                            (outlen, endlen) = (0, 0);
                            continue;
                        }
                    }
                    let consumed_newline =
                        self.consumed > 0 && self.input[self.consumed - 1] == b'\n';
                    return Some(self.core.line() - u64::from(consumed_newline));
                }
                R::End => return None,
            }
        }
    }

    /// Removes the last record's empty fields (the ends of the fields kept, in order).
    fn drop_empty_fields(&mut self) {
        let mut kept = 0;
        let mut start = 0;
        for i in 0..self.fields {
            let end = self.ends[i];
            if !trim(&self.out[start..end]).is_empty() {
                // the field keeps its start: the previous kept end, or a dropped field's
                // (empty after trimming, so the same trimmed text)
                self.ends[kept] = end;
                kept += 1;
            }
            start = end;
        }
        self.fields = kept;
    }

    /// Fields of the last record.
    fn len(&self) -> usize {
        self.fields
    }

    /// Field `i` of the last record (trimmed of ASCII whitespace).
    fn field(&self, i: usize) -> &[u8] {
        if i >= self.fields {
            return &[];
        }
        let start = if i == 0 { 0 } else { self.ends[i - 1] };
        trim(&self.out[start..self.ends[i]])
    }

    /// Line ends read so far.
    fn newlines(&self) -> u64 {
        self.core.line() - 1
    }
}

/// ASCII whitespace trimmed from both ends (what every field gets).
pub(super) fn trim(mut b: &[u8]) -> &[u8] {
    while let [first, rest @ ..] = b
        && first.is_ascii_whitespace()
    {
        b = rest;
    }
    while let [rest @ .., last] = b
        && last.is_ascii_whitespace()
    {
        b = rest;
    }
    b
}

/// A number field (the standard library's parser: correctly rounded). A plain decimal of
/// at most 15 significant digits and 22 decimals (`-12.345678`, a log's usual field)
/// takes the exact fast path first: its digits as an integer `m < 2^53` and `10^d`
/// are exact doubles, so `m / 10^d`, rounded once, is the correctly rounded value, the
/// standard library's to the bit (Clinger's fast path, which the standard library takes
/// too, after checking the text as UTF-8 and as any float syntax: reading the hour's CSV
/// spent 6 % of the identification's time there).
pub(super) fn number(b: &[u8]) -> Option<f64> {
    plain_decimal(b).or_else(|| std::str::from_utf8(b).ok()?.parse::<f64>().ok())
}

/// `[+-]digits[.digits]` with at least one digit, at most 15 of them in all and at most
/// 22 after the point, as the correctly rounded double; `None` for anything else.
fn plain_decimal(b: &[u8]) -> Option<f64> {
    decimal_prefix(b).and_then(|(v, len)| (len == b.len()).then_some(v))
}

/// The longest `[+-]digits[.digits]` at the start of `b` (at least one digit) and its
/// length in bytes, when it has at most 15 digits in all and at most 22 after the point:
/// its correctly rounded value if it is the whole field, `None` past those bounds.
pub(super) fn decimal_prefix(b: &[u8]) -> Option<(f64, usize)> {
    const POWERS: [f64; 23] = [
        1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
        1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
    ];
    let (negative, sign) = match b.first() {
        Some(b'-') => (true, 1),
        Some(b'+') => (false, 1),
        _ => (false, 0),
    };
    let rest = &b[sign..];
    // the digits before the point, then those after it (wrapping: more than 15 digits
    // are refused below)
    let mut m = 0u64;
    let digits = |from: usize, m: &mut u64| {
        let mut i = from;
        while let Some(&c) = rest.get(i).filter(|c| c.is_ascii_digit()) {
            *m = m.wrapping_mul(10).wrapping_add(u64::from(c - b'0'));
            i += 1;
        }
        i
    };
    let point = digits(0, &mut m);
    let end = match rest.get(point) {
        Some(b'.') => digits(point + 1, &mut m),
        _ => point,
    };
    let decimals = end.saturating_sub(point + 1);
    let total = point + decimals;
    if total == 0 || total > 15 || decimals >= POWERS.len() {
        return None;
    }
    // m < 10^15 < 2^53 and 10^decimals are exact: one rounding, the correct one
    let v = m as f64 / POWERS[decimals];
    Some((if negative { -v } else { v }, sign + end))
}

/// Field index of every requested name; a missing, duplicated or badly separated header
/// is an error for the first `required` names, `usize::MAX` (no field) for the others.
fn wanted(
    header: &[String],
    names: &[String],
    required: usize,
    path: &Path,
    text: &[u8],
    header_line: u64,
) -> Result<Vec<usize>> {
    names
        .iter()
        .enumerate()
        .map(|(k, name)| {
            let mut at = header.iter().enumerate().filter(|(_, h)| *h == name);
            match (at.next(), at.next()) {
                (Some((i, _)), None) => Ok(i),
                _ if k >= required => Ok(usize::MAX),
                (Some((i, _)), Some((k, _))) => Err(Error::Data(DataError::DuplicateColumn {
                    path: path.to_path_buf(),
                    column: name.clone(),
                    first: i + 1,
                    second: k + 1,
                })),
                (None, _) => Err(missing(header, name, path, text, header_line)),
            }
        })
        .collect()
}

/// The error for a name that is not in the header: a separator robid does not read when
/// the header splits into the name with one (`|`, or `;` or a tab beside the commas it is
/// read by), else a missing column.
fn missing(header: &[String], name: &str, path: &Path, text: &[u8], header_line: u64) -> Error {
    let raw = text
        .split(|&b| b == b'\n')
        .nth(header_line.saturating_sub(1) as usize)
        .unwrap_or_default();
    let control = |b: &u8| b.is_ascii_control() && !matches!(b, b'\t' | b'\r');
    if std::str::from_utf8(raw).is_err() || raw.iter().any(control) {
        return Error::Data(DataError::NotText {
            path: path.to_path_buf(),
            line: header_line,
        });
    }
    let line = String::from_utf8_lossy(raw).trim().to_string();
    for (sep, described) in [(';', "`;`"), ('\t', "tabs"), ('|', "`|`")] {
        if line.contains(sep) && line.split(sep).any(|f| f.trim().trim_matches('"') == name) {
            let shown: String = line.chars().take(60).collect();
            return Error::Data(DataError::UnsupportedSeparator {
                path: path.to_path_buf(),
                header: shown,
                separator: described.into(),
            });
        }
    }
    Error::Data(DataError::MissingColumn {
        path: path.to_path_buf(),
        column: name.to_string(),
        available: header.to_vec(),
        mapping: Box::new(ColumnMapping::Code),
    })
}

/// Block boundaries of `body`: after a line end every [`CHUNK`] bytes.
fn cuts(body: &[u8]) -> Vec<usize> {
    let mut cuts = vec![0];
    while let Some(&last) = cuts.last() {
        let target = last + CHUNK;
        if target >= body.len() {
            break;
        }
        match body[target..].iter().position(|&b| b == b'\n') {
            Some(i) if target + i + 1 < body.len() => cuts.push(target + i + 1),
            _ => break,
        }
    }
    cuts.push(body.len());
    cuts
}

/// What a block gave: its columns, the lines of its rows relative to the block (the
/// block's first line is 0), and its first error (lines relative too).
pub(super) struct Part {
    pub(super) columns: Vec<Vec<f64>>,
    pub(super) lines: Vec<u64>,
    /// Line ends in the block (when it was read to its end).
    pub(super) newlines: u64,
    error: Option<BlockError>,
}

impl Part {
    /// No rows yet of a block of `bytes` bytes with `fields` fields per row: `columns`
    /// columns, the first `read` with room for the rows such a block likely holds (8 bytes
    /// a field), the others (not read) left empty.
    pub(super) fn empty(bytes: usize, fields: usize, columns: usize, read: usize) -> Part {
        let estimate = bytes / (fields.max(1) * 8) + 1;
        Part {
            columns: (0..columns)
                .map(|k| Vec::with_capacity(if k < read { estimate } else { 0 }))
                .collect(),
            lines: Vec::with_capacity(estimate),
            newlines: 0,
            error: None,
        }
    }
}

/// An error inside a block, located relative to the block.
enum BlockError {
    Csv {
        line: u64,
        reason: String,
    },
    Value {
        line: u64,
        want: usize,
        text: String,
    },
    NotFinite {
        line: u64,
        want: usize,
        value: f64,
        text: String,
    },
    Rows,
}

impl BlockError {
    fn locate(self, path: &Path, names: &[String], base: u64) -> Error {
        let path = path.to_path_buf();
        let name = |k: usize| names.get(k).cloned().unwrap_or_default();
        match self {
            BlockError::Csv { line, reason } => Error::Data(DataError::Csv {
                path,
                line: line + base,
                reason,
            }),
            BlockError::Value { line, want, text } => Error::Data(DataError::NotANumber {
                path,
                line: line + base,
                column: name(want),
                text,
            }),
            BlockError::NotFinite {
                line,
                want,
                value,
                text,
            } => Error::Data(DataError::NotFinite {
                path,
                line: line + base,
                column: name(want),
                value,
                text: Some(text),
            }),
            BlockError::Rows => Error::TooLarge {
                what: format!("{}: data rows", path.display()),
                found: (MAX_ROWS + 1) as f64,
                limit: MAX_ROWS,
                fix: "split the file".into(),
            },
        }
    }
}

/// Parses the records of `body[from..to]` (whole lines, or the whole body): the
/// columns of `header`, the optional ones when `optional` (NaN where they are not a
/// finite number; left empty otherwise). Plain lines are split directly
/// ([`plain_rows`]); a block that has anything else goes through the CSV reader, which
/// gives the same rows and locates the errors.
fn block(
    body: &[u8],
    from: usize,
    to: usize,
    header: &Header,
    optional: bool,
    rows: &AtomicUsize,
) -> Part {
    let text = &body[from..to];
    let read = if optional {
        header.want.len()
    } else {
        header.required
    };
    let plain = (rows.load(Ordering::Relaxed) <= MAX_ROWS)
        .then(|| {
            let (separator, fields) = (header.separator, header.fields);
            plain_rows(text, separator, fields, &header.want, header.required, read)
        })
        .flatten();
    let Some(plain) = plain else {
        return csv_block(text, header, optional, rows);
    };
    rows.fetch_add(plain.lines.len(), Ordering::Relaxed);
    plain
}

/// [`block`] by the CSV reader (`text`: the block's text).
fn csv_block(text: &[u8], header: &Header, optional: bool, rows: &AtomicUsize) -> Part {
    let fields = header.fields;
    let (want, optional_want) = header.want.split_at(header.required);
    let optional_want = if optional { optional_want } else { &[] };
    let read = want.len() + optional_want.len();
    let mut part = Part::empty(text.len(), fields, header.want.len(), read);
    if rows.load(Ordering::Relaxed) > MAX_ROWS {
        part.error = Some(BlockError::Rows);
        return part;
    }
    let (columns, optional_columns) = part.columns.split_at_mut(want.len());
    let mut records = Records::new(text, header.separator);
    while let Some(line) = records.next_record() {
        // 0-based line within the block
        let line = line - 1;
        if records.len() != fields {
            part.error = Some(BlockError::Csv {
                line,
                reason: format!(
                    "found a row with {}, but the header has {}",
                    Count(records.len(), "field"),
                    Count(fields, "field")
                ),
            });
            break;
        }
        for (k, (&i, col)) in want.iter().zip(columns.iter_mut()).enumerate() {
            match number(records.field(i)) {
                Some(v) if v.is_finite() => col.push(v),
                Some(value) => {
                    part.error = Some(BlockError::NotFinite {
                        line,
                        want: k,
                        value,
                        text: String::from_utf8_lossy(records.field(i))
                            .chars()
                            .take(40)
                            .collect(),
                    });
                    return part;
                }
                None => {
                    let bytes = records.field(i);
                    part.error = Some(BlockError::Value {
                        line,
                        want: k,
                        text: String::from_utf8_lossy(bytes).chars().take(40).collect(),
                    });
                    return part;
                }
            }
        }
        for (&i, col) in optional_want.iter().zip(optional_columns.iter_mut()) {
            let parsed = number(records.field(i)).filter(|v| v.is_finite());
            col.push(parsed.unwrap_or(f64::NAN));
        }
        part.lines.push(line);
    }
    part.newlines = records.newlines();
    rows.fetch_add(part.lines.len(), Ordering::Relaxed);
    part
}

#[cfg(test)]
mod tests;
