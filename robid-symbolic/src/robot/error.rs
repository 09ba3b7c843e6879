//! Errors in robot descriptions.

/// A description that cannot be used, with where it is wrong and how to fix it.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum DescriptionError {
    /// The file could not be read.
    #[error("{file}: cannot read the file: {reason}")]
    Read {
        /// Path of the file.
        file: String,
        /// The operating system's reason.
        reason: String,
    },
    /// The text is not valid TOML or does not have the expected shape.
    #[error("{file}:{line}:{column}: {message}")]
    Syntax {
        /// Path of the file (or `<inline>`).
        file: String,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// What is wrong and what is expected.
        message: String,
    },
    /// A value has the right shape but is not acceptable.
    #[error("{file}:{line}:{column}: {message}; {help}")]
    Invalid {
        /// Path of the file (or `<inline>` / `<code>`).
        file: String,
        /// 1-based line (0 when built in code).
        line: usize,
        /// 1-based column (0 when built in code).
        column: usize,
        /// What is wrong.
        message: String,
        /// How to fix it.
        help: String,
        /// Byte range in the text, when known (for compiler spans).
        span: Option<(usize, usize)>,
    },
}

impl DescriptionError {
    /// The byte range of the offending text, when known.
    pub fn span(&self) -> Option<(usize, usize)> {
        match self {
            DescriptionError::Invalid { span, .. } => *span,
            _ => None,
        }
    }
}
