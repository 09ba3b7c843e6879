//! Reading inputs: data files, identification configs and parameter files, each problem
//! named by file, line and column (or config key) with the fix.

use super::ColumnMapping;
use crate::Num;
use crate::error::place;
use crate::limits::{MAX_SAMPLE_RATE, MIN_SAMPLE_RATE};
use std::path::PathBuf;

/// Which of robid's TOML files an error is about, as its message names it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum TomlFile {
    /// The identification config ([`crate::data::Config`]): "config".
    Config,
    /// A friction file ([`crate::drive::FrictionModel`]): "friction file".
    Friction,
    /// A joint-flexibility file ([`crate::simulate::Flexibility`]): "joint-flexibility file".
    Flexibility,
    /// A bounds file ([`crate::feasible::Bounds`]): "bounds file".
    Bounds,
}

impl std::fmt::Display for TomlFile {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            TomlFile::Config => "config",
            TomlFile::Friction => "friction file",
            TomlFile::Flexibility => "joint-flexibility file",
            TomlFile::Bounds => "bounds file",
        })
    }
}

/// A data file, a config file or a parameter file cannot be used.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum DataError {
    /// A file could not be opened or read.
    #[error("{}: cannot read: {}", robid_core::names::shortened(&path.display().to_string(), 256), robid_core::names::io_problem(source))]
    Io {
        /// The file.
        path: PathBuf,
        /// The operating-system error.
        source: std::io::Error,
    },
    /// A data file that is a pipe or a socket (`--data /dev/stdin` fed by `cat`, a FIFO):
    /// robid opens a data file more than once (its header, then its rows), which a stream
    /// cannot give twice (the second opening of a FIFO waited forever).
    #[error("{}: a pipe, not a file: robid reads a data file more than once (its header, then its rows), which a pipe cannot give; save the data to a file first (`cat > data.csv`) and give that file", robid_core::names::shortened(&path.display().to_string(), 256))]
    Stream {
        /// The pipe.
        path: PathBuf,
    },
    /// The system's temporary folder (`TMPDIR`, else `/tmp`) could not hold a file robid
    /// keeps there while it works (a long record's samples, rows waiting for standard
    /// output).
    #[error(
        "{dir}: cannot keep a temporary file in this folder ({source}); set TMPDIR to a folder you may write into, with room for the data"
    )]
    Temporary {
        /// The temporary folder.
        dir: PathBuf,
        /// The operating-system error.
        source: std::io::Error,
    },
    /// A file was read but its content is damaged (e.g. a truncated gzip stream).
    #[error(
        "{path}: the file is truncated or corrupt ({reason}); copy or export it again from its source"
    )]
    Corrupt {
        /// The file.
        path: PathBuf,
        /// What the decoder reported.
        reason: String,
    },
    /// A CSV file without a header line (empty, or blank and `#` comment lines only). No
    /// count of rows is said: how many a file needs is its reader's to say (a states file
    /// one, a data set two, a trajectory three), each of which tells a header without rows
    /// with its own count; the CSV reader once said "0 samples, at least 2 are needed"
    /// whatever the caller needed.
    #[error(
        "{path}: the file is empty (no header line, only blank or `#` comment lines if any); it needs a header line and data rows below it"
    )]
    EmptyFile {
        /// The file.
        path: PathBuf,
    },
    /// The CSV structure is broken (e.g. a row with a different number of fields).
    #[error("{path}:{line}: malformed CSV: {reason}; every row needs as many fields as the header")]
    Csv {
        /// The file.
        path: PathBuf,
        /// 1-based line.
        line: u64,
        /// What the CSV reader reported.
        reason: String,
    },
    /// A line longer than [`MAX_LINE_BYTES`](crate::limits::MAX_LINE_BYTES) without its
    /// end: no log's line (a device that never ends, `/dev/zero`, or a binary file).
    #[error(
        "{path}:{line}: no line end in the {limit} bytes read of this line; a log's line holds at most a few hundred kB of text: is this a CSV file (a binary file or a device such as /dev/zero is not)?"
    )]
    LineTooLong {
        /// The file.
        path: PathBuf,
        /// 1-based line.
        line: u64,
        /// The bytes read without a line end.
        limit: usize,
    },
    /// The file's lines end in a carriage return alone (classic Mac OS): a CSV file was
    /// read as one line, the header with every row appended; a TOML file (a config, a
    /// parameter, bounds, friction or joint-flexibility file) was toml's "carriage return
    /// must be followed by newline".
    #[error(
        "{path}: its lines end in a carriage return alone (CR, as classic Mac OS wrote text); robid reads lines ended by a line feed (LF, or CR LF): convert the file, e.g. with `tr '\\r' '\\n' < old{ext} > new{ext}`",
        ext = path.extension().map(|e| format!(".{}", e.to_string_lossy())).unwrap_or_default()
    )]
    CarriageReturnLines {
        /// The file.
        path: PathBuf,
    },
    /// The file separates its fields with something robid does not read (`|`).
    #[error(
        "{path}: the header `{header}` is separated by {separator}; robid reads fields separated by `,`, or by the one of `;`, a tab or spaces that the header uses (optionally quoted with `\"`, `#` starts a comment line): convert the file to commas (with `.` as the decimal point)"
    )]
    UnsupportedSeparator {
        /// The file.
        path: PathBuf,
        /// The header line (shortened).
        header: String,
        /// The separator found, described (e.g. "`;`", "tabs").
        separator: String,
    },
    /// Two columns of the header have a name that is read.
    #[error(
        "{path}: the header names column `{}` twice (fields {first} and {second}); rename one of them so that `{}` means one column",
        quoted(column),
        quoted(column)
    )]
    DuplicateColumn {
        /// The file.
        path: PathBuf,
        /// The name.
        column: String,
        /// 1-based position of the first field with that name.
        first: usize,
        /// 1-based position of the second field with that name.
        second: usize,
    },
    /// A field is not a number.
    #[error(
        "{path}:{line}: column `{}` holds `{}`, which is not a number; write a decimal number such as 1.5e-3{}",
        quoted(column),
        visible(text),
        decimal_comma(text)
    )]
    NotANumber {
        /// The file.
        path: PathBuf,
        /// 1-based line.
        line: u64,
        /// Column name.
        column: String,
        /// The offending text.
        text: String,
    },
    /// A value is NaN or infinite.
    #[error(
        "{path}:{line}: column `{}` is {}; remove or repair this row (robid computes with finite numbers only)",
        quoted(column),
        not_finite(*value, text.as_deref())
    )]
    NotFinite {
        /// The file (or data set).
        path: PathBuf,
        /// 1-based line (or sample number for a data set built in code).
        line: u64,
        /// Column name.
        column: String,
        /// The value.
        value: f64,
        /// The field as written in the file (`1e400`), when read from one.
        text: Option<String>,
    },
    /// A finite value outside the documented range of its quantity (see [`crate::limits`]).
    #[error(
        "{location}: {what} is {}, outside the accepted range {}; repair or remove this row (a value {} is a logging, unit or export error, not a measurement)",
        Num::rounded(*value, 8),
        accepted_range(quantity, *lower, *limit),
        if *value < *lower && *lower != -*limit { "below absolute zero" } else { "this large" }
    )]
    OutOfRange {
        /// Where: `file:line` of a data file, or the data set and sample.
        location: String,
        /// What holds the value (e.g. "column `qdd1`").
        what: String,
        /// The quantity whose range applies (e.g. "acceleration").
        quantity: &'static str,
        /// The value.
        value: f64,
        /// The largest accepted magnitude.
        limit: f64,
        /// The smallest accepted value (`-limit`, or absolute zero for a temperature,
        /// [`crate::limits::Quantity::lower`]).
        lower: f64,
    },
    /// A header line that is not text (control characters, bytes that are not UTF-8): a
    /// binary file, or one compressed otherwise than by gzip. Its bytes are not echoed
    /// (they could be a terminal's escape sequences).
    #[error(
        "{path}:{line}: the header line is not text (it holds control characters or bytes that are not UTF-8): is this a CSV file? A binary log, or a file compressed otherwise than by gzip, is not; export it as CSV"
    )]
    NotText {
        /// The file.
        path: PathBuf,
        /// 1-based line of the header.
        line: u64,
    },
    /// A column named by the column mapping is not in the file's header.
    #[error("{path}: no column `{}` in the header (found: {}); {}{}", quoted(column), listed(available), mapping.fix(), numbered_from_zero(column, available))]
    MissingColumn {
        /// The file.
        path: PathBuf,
        /// The missing column.
        column: String,
        /// The header's columns.
        available: Vec<String>,
        /// Where the column names came from (a config file, the default mapping, code).
        mapping: Box<ColumnMapping>,
    },
    /// Time stamps do not increase.
    #[error(
        "{path}:{line}: time {} does not increase (previous {}); sort the rows by time or remove duplicates",
        Num(*value),
        Num(*previous)
    )]
    NonMonotonicTime {
        /// The file.
        path: PathBuf,
        /// 1-based line of the offending sample.
        line: u64,
        /// Previous time stamp.
        previous: f64,
        /// This time stamp.
        value: f64,
    },
    /// Time stamps whose mean step gives a sample rate outside the rates robid takes,
    /// [[`MIN_SAMPLE_RATE`], [`MAX_SAMPLE_RATE`]] Hz (a time column in other units than
    /// seconds, or absurd stamps).
    #[error(
        "{what}: time stamps {} s apart on average, a sample rate of {} Hz, outside [{MIN_SAMPLE_RATE:e}, {MAX_SAMPLE_RATE:e}] Hz; {fix}",
        Num::rounded_keeping(*step, 4, |s| !super::time::sample_time_accepted(s)),
        Num::rounded_keeping(1.0 / *step, 4, |r| !(MIN_SAMPLE_RATE..=MAX_SAMPLE_RATE).contains(&r))
    )]
    SampleRate {
        /// The time stamps: their file, or what holds them.
        what: String,
        /// The mean step (s).
        step: f64,
        /// What to do.
        fix: &'static str,
    },
    /// A step between two time stamps longer than [`crate::data::GAP_RATIO`] times the
    /// median step: the recording stopped there, and interpolating across the gap would
    /// invent the motion. The time stamps are written to 15 significant digits (those of
    /// a time column in ms, scaled to seconds, end in rounding digits).
    #[error(
        "{location}: the time stamps jump from {} s to {} s, a gap of {} s, {} times the median step of {} s (more than {} is a gap, not jitter): the recording stopped there, and no motion can be interpolated across it; {fix}",
        Num::rounded(*from, 15),
        Num::rounded(*to, 15),
        Num::rounded(*to - *from, 6),
        Num::rounded_keeping((*to - *from) / *median, 3, |r| r > crate::data::GAP_RATIO),
        Num::rounded(*median, 6),
        crate::data::GAP_RATIO
    )]
    TimeGap {
        /// Where: `file:line` of the sample after the gap, or the sample of what holds the
        /// time stamps.
        location: String,
        /// The time stamp before the gap (s).
        from: f64,
        /// The time stamp after it (s).
        to: f64,
        /// The median step (s).
        median: f64,
        /// What to do.
        fix: &'static str,
    },
    /// A trajectory's positions and velocities disagree: over one step a position changes
    /// by far more, or far less, than its velocity integrates to. A closed loop fed such a
    /// reference "tracks" it between the samples and records a state whose positions and
    /// velocities say different things.
    #[error(
        "{location}: q{joint} changes by {} over the step from t = {} s, while qd{joint} integrates to {} over it: the positions and velocities disagree ({}); give the velocities as the time derivatives of the positions (`robid excite` designs such trajectories)",
        Num::rounded(*change, 6),
        Num::rounded(*from, 15),
        Num::rounded(*integral, 6),
        derivative_cause(*ratio, super::DerivativeColumn::Velocity)
    )]
    InconsistentDerivative {
        /// Where: `file:line` of the sample at the end of the step, or the sample of what
        /// holds the trajectory.
        location: String,
        /// The joint, numbered from 1.
        joint: usize,
        /// The time at the start of the step (s).
        from: f64,
        /// The position's change over the step.
        change: f64,
        /// The velocity integrated over the step.
        integral: f64,
        /// Over the whole record, the positions' total change over the velocities'
        /// integrated one (the factor of a unit slip).
        ratio: f64,
    },
    /// A trajectory's accelerations disagree with its velocities: integrated from the first
    /// sample, they drift from the velocities' change by more than
    /// [`crate::simulate::ACCELERATION_DRIFT`] times the velocity's largest magnitude. The
    /// feed-forward of such a reference drives the joint with torques its motion does not
    /// need (a constant `qdd` of -1e6 was simulated for minutes into currents of 1e4 A).
    #[error(
        "{location}: qdd{joint} integrates to {} from t = {} s to t = {} s, while qd{joint} changes by {} over it: the accelerations disagree with the velocities, drifting from them by more than {} times qd{joint}'s largest magnitude {} ({}); give the accelerations as the time derivatives of the velocities (`robid excite` designs such trajectories)",
        Num::rounded(*integral, 6),
        Num::rounded(*from, 15),
        Num::rounded(*to, 15),
        Num::rounded(*change, 6),
        crate::simulate::ACCELERATION_DRIFT,
        Num::rounded(*largest, 6),
        derivative_cause(*ratio, super::DerivativeColumn::Acceleration)
    )]
    InconsistentAcceleration {
        /// Where: `file:line` of the sample where the drift is first too large, or the
        /// sample of what holds the trajectory.
        location: String,
        /// The joint, numbered from 1.
        joint: usize,
        /// The time of the first sample (s).
        from: f64,
        /// The time of the sample named (s).
        to: f64,
        /// The accelerations integrated from `from` to `to` (the trapezoid).
        integral: f64,
        /// The velocity's change from `from` to `to`.
        change: f64,
        /// The velocity's largest magnitude over the record.
        largest: f64,
        /// Over the whole record, the velocities' total change over the accelerations'
        /// integrated one (the factor of a unit slip).
        ratio: f64,
    },
    /// A file joined by time whose median step is more than [`crate::data::GAP_RATIO`]
    /// times that of the first file (its measurements other than temperatures): each of
    /// its steps would be interpolated across that many samples of the first file,
    /// inventing the motion between them, as across a gap (a time column in ms beside
    /// one in s is 1000 times too coarse).
    #[error(
        "{path}: time stamps {} s apart (median), {} times the {} s of {first}, which it is joined to by time: its values would be interpolated across {} samples of {first} per step, inventing what happened between them (more than {} is a gap, not a slower logger); join files recorded at comparable rates, with time stamps of one clock in one unit (seconds: `time_scale` applies to every file)",
        Num::rounded(*step, 6),
        Num::rounded_keeping(*step / *first_step, 3, |r| r > crate::data::GAP_RATIO),
        Num::rounded(*first_step, 6),
        Num::rounded(*step / *first_step, 3),
        crate::data::GAP_RATIO
    )]
    CoarseJoin {
        /// The file joined by time.
        path: PathBuf,
        /// Its median step (s).
        step: f64,
        /// The first file with time stamps, which the others are joined to.
        first: PathBuf,
        /// Its median step (s).
        first_step: f64,
    },
    /// The number of joints in the data does not match the model.
    #[error(
        "{context}: {}, the model has {expected}; list exactly one column per joint",
        crate::Count(*found, "joint")
    )]
    JointCountMismatch {
        /// Where the count was found.
        context: String,
        /// The model's joint count.
        expected: usize,
        /// The count found.
        found: usize,
    },
    /// Two files to be joined sample by sample have different lengths.
    #[error("{first} has {first_rows} rows but {second} has {second_rows}; {fix}")]
    RowCountMismatch {
        /// First file.
        first: PathBuf,
        /// Its rows.
        first_rows: usize,
        /// Second file.
        second: PathBuf,
        /// Its rows.
        second_rows: usize,
        /// What to do.
        fix: String,
    },
    /// A TOML file of robid's (the identification config, a friction, joint-flexibility or
    /// bounds file) is not valid TOML or does not match its format; the message names the
    /// place and the kind of file (`f.toml:3:11: invalid friction file: ..`).
    #[error("{}: invalid {kind}: {reason}", place(path, *line, *column))]
    ConfigSyntax {
        /// The file.
        path: PathBuf,
        /// 1-based line of the mistake, when the parser gives its place.
        line: Option<usize>,
        /// 1-based column (in characters) of the mistake.
        column: Option<usize>,
        /// Which kind of file it is.
        kind: TomlFile,
        /// The parser's message.
        reason: String,
    },
    /// A key of a config file has a value that is out of range or inconsistent (or a
    /// required key is missing: then `line` is `None`).
    #[error("{}: `{}`: {problem}", place(path, *line, *column), robid_core::names::short_key(key))]
    ConfigKey {
        /// The config file.
        path: PathBuf,
        /// 1-based line of the key, when it is in the file.
        line: Option<usize>,
        /// 1-based column of the key, when it is in the file.
        column: Option<usize>,
        /// The key as a dotted path, arrays of tables numbered from 1 (`source[2].torque`);
        /// the message quotes a long part of it short ([`robid_core::names::short_key`]).
        key: String,
        /// What is wrong and what to write instead.
        problem: String,
    },
    /// A parameter file (`[standard]` or `[base]` table, see [`crate::data::ParameterFile`])
    /// is not valid or holds a value that cannot be (`line` is `None` for a problem of the
    /// whole file).
    #[error("{}: {problem}", place(path, *line, *column))]
    ParameterFile {
        /// The parameter file.
        path: PathBuf,
        /// 1-based line of the entry.
        line: Option<usize>,
        /// 1-based column (in characters) of the entry.
        column: Option<usize>,
        /// What is wrong and what to write instead.
        problem: String,
    },
}

/// The header's names for a message: the first [`LISTED`] (each cut to 40 characters),
/// then how many more; a header of thousands of columns was written out in full.
fn listed(names: &[String]) -> String {
    const LISTED: usize = 30;
    let mut shown: Vec<String> = names.iter().take(LISTED).map(|n| quoted(n)).collect();
    if names.len() > LISTED {
        shown.push(format!("and {} more", names.len() - LISTED));
    }
    shown.join(", ")
}

/// What a missing column `stem<n>` adds when the header numbers the same columns from 0
/// (`stem0` .. `stem<n-1>`, as UR's RTDE recorder writes `actual_q_0` .. `actual_q_5`):
/// the config's template for that, `stem{0}`. Empty otherwise.
fn numbered_from_zero(column: &str, available: &[String]) -> String {
    let stem = column.trim_end_matches(|c: char| c.is_ascii_digit());
    let Ok(n) = column[stem.len()..].parse::<usize>() else {
        return String::new();
    };
    let has = |k: usize| available.iter().any(|a| *a == format!("{stem}{k}"));
    if n == 0 || !(0..n).all(has) {
        return String::new();
    }
    format!(
        "; the file numbers these columns from 0 (`{stem}0` to `{stem}{}`): a config's \
         template `\"{stem}{{0}}\"` names them so (`{{}}` counts from 1)",
        n - 1
    )
}

/// What a field that is a number with a decimal comma (`1,5`, as a spreadsheet in many
/// locales writes with `;` between fields) adds to its error: the decimal point is `.`.
fn decimal_comma(text: &str) -> &'static str {
    let one_comma = text.matches(',').count() == 1;
    if one_comma && text.replacen(',', ".", 1).parse::<f64>().is_ok() {
        " (the decimal point is `.`, not `,`: export the file with `.` as the decimal separator)"
    } else {
        ""
    }
}

/// The likely cause of a derivative `column` that disagrees with what it derives (the
/// velocities with the positions, the accelerations with the velocities), from `ratio`,
/// the derived signal's total change over the column's integrated one: the factor of a unit
/// slip names it (within 2 %: a time column in minutes, 60 times apart, is not degrees,
/// 57.3), else the causes in general.
pub(crate) fn derivative_cause(ratio: f64, column: super::DerivativeColumn) -> &'static str {
    use super::DerivativeColumn::{Acceleration, Velocity};
    let near = |r: f64| (ratio / r - 1.0).abs() < 0.02;
    match column {
        _ if near(1e-3) => match column {
            Velocity => {
                "1000 times apart: is the time column in milliseconds (or are the velocities \
                 in mrad/s)? write seconds and radians"
            }
            Acceleration => {
                "1000 times apart: is the time column in milliseconds (or are the \
                 accelerations in mrad/s^2)? write seconds and radians"
            }
        },
        Velocity if near(std::f64::consts::PI / 180.0) => {
            "57.3 times apart: are the velocities in degrees per second and the positions in \
             radians?"
        }
        Velocity if near(180.0 / std::f64::consts::PI) => {
            "57.3 times apart: are the positions in degrees and the velocities in radians per \
             second?"
        }
        Acceleration if near(std::f64::consts::PI / 180.0) => {
            "57.3 times apart: are the accelerations in degrees per second squared and the \
             velocities in radians per second?"
        }
        Acceleration if near(180.0 / std::f64::consts::PI) => {
            "57.3 times apart: are the velocities in degrees per second and the accelerations \
             in radians per second squared?"
        }
        _ if near(60.0) => "60 times apart: is the time column in minutes? write it in seconds",
        Velocity => {
            "a column in other units, shifted by some samples, or not the derivative of the \
             positions"
        }
        Acceleration => {
            "a column in other units, shifted by some samples, or not the derivative of the \
             velocities"
        }
    }
}

/// A value that is not finite as the message gives it: a field that reads as infinite
/// without saying so (`1e400`) is quoted, not called `inf`.
fn not_finite(value: f64, text: Option<&str>) -> String {
    let written = text.map(str::trim).filter(|t| {
        let t = t.trim_start_matches(['+', '-']).to_ascii_lowercase();
        !(t.is_empty() || t.starts_with("inf") || t.starts_with("nan"))
    });
    // a field that is not a word (`inf`, `NaN`) is not finite only by overflow
    match written {
        Some(t) => format!(
            "`{}`, beyond the largest number a double holds (1.8e308), so it reads as infinite",
            visible(t)
        ),
        _ => format!("{value}"),
    }
}

/// `text` with the characters a message would not show escaped: control characters
/// (`\0`, `\t`, `\u{1b}`), invisible ones ([`invisible`]: `\u{200b}`, a byte-order mark
/// `\u{feff}`) and spaces other than the ASCII space (`\u{a0}`). A field holding a NUL
/// byte was quoted as "`2.848129118e-3`, which is not a number", the NUL invisible.
fn visible(text: &str) -> String {
    text.chars()
        .map(|c| {
            if c.is_control() || invisible(c) || (c.is_whitespace() && c != ' ') {
                c.escape_default().collect()
            } else {
                c.to_string()
            }
        })
        .collect()
}

/// Whether `c` prints as nothing: a zero-width or formatting character (zero-width space,
/// joiners, direction marks, the byte-order mark, word joiner, soft hyphen, variation
/// selectors, tags, Hangul fillers).
fn invisible(c: char) -> bool {
    matches!(
        c,
        '\u{ad}'
            | '\u{34f}'
            | '\u{61c}'
            | '\u{115f}'..='\u{1160}'
            | '\u{17b4}'..='\u{17b5}'
            | '\u{180b}'..='\u{180f}'
            | '\u{200b}'..='\u{200f}'
            | '\u{202a}'..='\u{202e}'
            | '\u{2060}'..='\u{206f}'
            | '\u{3164}'
            | '\u{fe00}'..='\u{fe0f}'
            | '\u{feff}'
            | '\u{ffa0}'
            | '\u{fff0}'..='\u{fffb}'
            | '\u{1d173}'..='\u{1d17a}'
            | '\u{e0000}'..='\u{e0fff}'
    )
}

/// A name from a header (or any name a user wrote) for a message, between backquotes:
/// short ([`robid_core::names::short`]) and with the characters it would not show escaped
/// ([`visible`]). A header's `q1` followed by a zero-width space was listed as `q1`, beside
/// "no column `q1` in the header"; it is now `q1\u{200b}`.
pub(crate) fn quoted(name: &str) -> String {
    visible(&robid_core::names::short(name))
}

/// The range of [`DataError::OutOfRange`] in words: `|torque| <= 1e7`, or both ends when
/// they differ (`-273.15 <= temperature <= 1e3`).
fn accepted_range(quantity: &str, lower: f64, limit: f64) -> String {
    if lower == -limit {
        format!("|{quantity}| <= {limit:e}")
    } else {
        format!("{} <= {quantity} <= {limit:e}", Num(lower))
    }
}
