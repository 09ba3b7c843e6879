//! The crate's error type: every variant names where the problem is and how to fix it.
//!
//! The kind of input is part of the variant, so that a caller can say it in its own terms:
//! a data file is named by file:line and column ([`Error::NotFinite`], [`Error::OutOfRange`]
//! ...), a key of a config file by file:line:column ([`Error::ConfigKey`]), and a setting
//! given in code (a field of a settings struct, or a function argument) by its Rust name
//! ([`Error::InvalidConfig`], which a command line maps to its flag).

use std::path::PathBuf;

use crate::data::ColumnMapping;

/// Everything that can go wrong between a data file and an identified model.
///
/// Locations are given as precisely as the input allows: `path` is the file (or a
/// description such as `<memory>`), `line` is the 1-based line in that file (the header
/// is line 1), `column` the column name.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A file could not be opened or read.
    #[error("{path}: cannot read: {source}; check the path and permissions")]
    Io {
        /// The file.
        path: PathBuf,
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
    /// A file could not be written.
    #[error("{path}: cannot write: {reason}; check that the folder exists and is writable")]
    Write {
        /// The file.
        path: PathBuf,
        /// What the writer reported.
        reason: String,
    },
    /// An output would replace one of the run's inputs.
    #[error("{output} is also an input of this run ({input}); write the output to another file")]
    OutputIsInput {
        /// The output path as given.
        output: PathBuf,
        /// The input it is the same file as.
        input: PathBuf,
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
    /// The file separates its fields with something other than a comma.
    #[error(
        "{path}: the header `{header}` is separated by {separator}; robid reads comma-separated files (fields separated by `,`, optionally quoted with `\"`, `#` starts a comment line): convert the file to commas (with `.` as the decimal point)"
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
        "{path}: the header names column `{column}` twice (fields {first} and {second}); rename one of them so that `{column}` means one column"
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
        "{path}:{line}: column `{column}` holds `{text}`, which is not a number; write a decimal number such as 1.5e-3"
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
        "{path}:{line}: column `{column}` is {value}; remove or repair this row (NaN and infinite values cannot be identified from)"
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
    },
    /// A finite value outside the documented range of its quantity (see [`crate::limits`]).
    #[error(
        "{location}: {what} is {value:e}, outside the accepted range |{quantity}| <= {limit:e}; repair or remove this row (a value this large is a logging, unit or export error, not a measurement)"
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
    },
    /// A column named by the column mapping is not in the file's header.
    #[error("{path}: no column `{column}` in the header (found: {}); {}", available.join(", "), mapping.fix())]
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
        "{path}:{line}: time {value} does not increase (previous {previous}); sort the rows by time or remove duplicates"
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
    /// Not enough samples for the requested processing.
    #[error("{context}: {found} samples, at least {required} are needed; {hint}")]
    TooFewSamples {
        /// Which data (file or processing step).
        context: String,
        /// Samples available.
        found: usize,
        /// Samples required.
        required: usize,
        /// What to change.
        hint: &'static str,
    },
    /// A size (rows, columns, joints, samples, matrix entries) above its documented limit
    /// ([`crate::limits`]), found before anything of that size is allocated.
    #[error("{what}: {} is more than the limit of {limit}; {fix}", count(*found))]
    TooLarge {
        /// What is counted, and where.
        what: String,
        /// The size asked for (a float: it may not fit an integer).
        found: f64,
        /// The limit.
        limit: usize,
        /// What to change.
        fix: String,
    },
    /// The number of joints in the data does not match the model.
    #[error(
        "{context}: {found} joints, the model has {expected}; list exactly one column per joint"
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
    #[error(
        "{first} has {first_rows} rows but {second} has {second_rows}; give both files the same rows, or a time column in each so they can be joined by time"
    )]
    RowCountMismatch {
        /// First file.
        first: PathBuf,
        /// Its rows.
        first_rows: usize,
        /// Second file.
        second: PathBuf,
        /// Its rows.
        second_rows: usize,
    },
    /// The config file is not valid TOML or does not match the expected format.
    #[error("{path}: invalid config: {reason}")]
    ConfigSyntax {
        /// The config file.
        path: PathBuf,
        /// The parser's message (with line and column).
        reason: String,
    },
    /// A key of a config file has a value that is out of range or inconsistent (or a
    /// required key is missing: then `line` is `None`).
    #[error("{}: `{key}`: {problem}", place(path, *line, *column))]
    ConfigKey {
        /// The config file.
        path: PathBuf,
        /// 1-based line of the key, when it is in the file.
        line: Option<usize>,
        /// 1-based column of the key, when it is in the file.
        column: Option<usize>,
        /// The key as a dotted path, arrays of tables numbered from 1 (`source[2].torque`).
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
    /// A setting given in code is out of range or inconsistent: a field of a settings
    /// struct (`Simulation::bandwidth`, a [`crate::data::Config`] built in code) or a
    /// function argument (`rate` of [`crate::excite::Fourier::sample`]). `owner` is the
    /// Rust type or function, `key` the field or argument (a dotted path inside a
    /// `Config`); a command line maps `key` to its flag. A key read from a config file
    /// is an [`Error::ConfigKey`] instead.
    #[error("{owner} `{key}`: {problem}")]
    InvalidConfig {
        /// The settings type or function, e.g. `Simulation`, `Fourier::sample`.
        owner: String,
        /// The field or argument, e.g. `bandwidth`, `processing.lowpass.cutoff`.
        key: String,
        /// What is wrong and what to write instead.
        problem: String,
    },
    /// A matrix or vector has the wrong size.
    #[error("{what}: expected {expected} entries, found {found}")]
    DimensionMismatch {
        /// Which quantity.
        what: String,
        /// Expected size.
        expected: usize,
        /// Actual size.
        found: usize,
    },
    /// The data do not excite every parameter: the observation matrix is rank deficient.
    #[error("rank-deficient data: rank {rank} of {columns} parameters; not excited: {}; use a richer trajectory or remove these parameters", unexcited.join(", "))]
    RankDeficient {
        /// Numerical rank found.
        rank: usize,
        /// Number of parameters (columns).
        columns: usize,
        /// The parameters that make up the unexcited directions, most affected first.
        unexcited: Vec<String>,
    },
    /// One or a few equations dominate the column of a parameter the data do not otherwise
    /// determine: an outlier in the data, not a poor trajectory.
    #[error(
        "{location}: an outlier: {:.1} % of column `{parameter}` comes from the equations around this row, which hides the rest of the record; repair or remove the row (check its velocities and accelerations)",
        100.0 * share
    )]
    Outlier {
        /// Where the largest equation comes from (file:line when known).
        location: String,
        /// The parameter whose column it dominates.
        parameter: String,
        /// The share of the column's squared norm held by the largest equations.
        share: f64,
    },
    /// The observation matrix (or the torque vector) holds NaN or an infinite value.
    #[error(
        "the observation matrix is {value} at {location}, joint {joint}, column `{parameter}`: the regressor overflowed there; check that row's positions, velocities and accelerations (and the extra column's definition)"
    )]
    NonFiniteObservation {
        /// Where the equation comes from: `file:line` when known, else the sample.
        location: String,
        /// 0-based sample index in the data set (after any resampling), when known.
        sample: Option<usize>,
        /// 1-based joint (equation row of the regressor).
        joint: usize,
        /// The parameter (column), or `torque` for the measurement.
        parameter: String,
        /// The value found.
        value: f64,
    },
    /// An iterative solver stopped at its iteration cap without converging.
    #[error("{what} did not converge in {iterations} iterations; {hint}")]
    NoConvergence {
        /// Which solver, on what.
        what: String,
        /// The cap reached.
        iterations: usize,
        /// What to change.
        hint: &'static str,
    },
    /// A result came out NaN or infinite (checked before it is returned).
    #[error("{what} is not finite: {cause}")]
    NonFiniteResult {
        /// Which result.
        what: String,
        /// The likely cause and the fix.
        cause: String,
    },
    /// A closed-loop simulation left the reference trajectory (tracking error or torque
    /// ran away, or a state became non-finite).
    #[error(
        "the simulation diverged at t = {time} s (trajectory sample {sample}): {reason}; {fix}"
    )]
    Diverged {
        /// Time stamp of the reference sample where it was detected.
        time: f64,
        /// 0-based reference sample.
        sample: usize,
        /// What ran away.
        reason: String,
        /// The likely cause and what to change.
        fix: String,
    },
    /// A matrix required to be invertible or positive definite is not.
    #[error("{what} is singular or not positive definite; {hint}")]
    Singular {
        /// Which matrix.
        what: String,
        /// What to change.
        hint: &'static str,
    },
    /// No physically consistent parameter set satisfies the bounds (or the solver failed).
    #[error("no feasible link parameters: {reason}")]
    NoFeasibleParameters {
        /// What excluded every solution and what to change.
        reason: String,
    },
    /// A method that this build does not include.
    #[error("{what} is not in this build: {fix}")]
    Unavailable {
        /// The method.
        what: String,
        /// How to get it.
        fix: String,
    },
}

impl Error {
    /// An [`Error::InvalidConfig`] for the setting `key` of `owner`.
    pub fn setting(owner: &str, key: &str, problem: impl Into<String>) -> Error {
        Error::InvalidConfig {
            owner: owner.to_string(),
            key: key.to_string(),
            problem: problem.into(),
        }
    }
}

/// `path:line:column`, with what is known.
fn place(path: &std::path::Path, line: Option<usize>, column: Option<usize>) -> String {
    match (line, column) {
        (Some(l), Some(c)) => format!("{}:{l}:{c}", path.display()),
        (Some(l), None) => format!("{}:{l}", path.display()),
        _ => path.display().to_string(),
    }
}

/// A number for a message: plain while short, else in scientific notation (so that 1e308
/// does not print as 309 digits).
pub(crate) fn num(x: f64) -> String {
    if x == 0.0 || (x.abs() >= 1e-4 && x.abs() < 1e15) || !x.is_finite() {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// A count for a message: exact while it is an integer of reasonable size.
fn count(x: f64) -> String {
    if x.is_finite() && x.fract() == 0.0 && x.abs() < 1e15 {
        format!("{x:.0}")
    } else {
        format!("{x:.3e}")
    }
}

/// The crate's result type.
pub type Result<T> = std::result::Result<T, Error>;
