//! The crate's error type: every variant names where the problem is and how to fix it.

use std::path::PathBuf;

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
        /// The file.
        path: PathBuf,
        /// 1-based line.
        line: u64,
        /// Column name.
        column: String,
        /// The value.
        value: f64,
    },
    /// A column named in the config is not in the file's header.
    #[error("{path}: no column `{column}` in the header (found: {}); fix the column name in the config", available.join(", "))]
    MissingColumn {
        /// The file.
        path: PathBuf,
        /// The missing column.
        column: String,
        /// The header's columns.
        available: Vec<String>,
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
    /// The number of joints in the data or config does not match the model.
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
    /// A config value is out of range or inconsistent.
    #[error("config `{key}`: {problem}")]
    InvalidConfig {
        /// The key, e.g. `processing.lowpass_cutoff`.
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

/// The crate's result type.
pub type Result<T> = std::result::Result<T, Error>;
