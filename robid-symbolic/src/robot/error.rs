//! Errors in robot descriptions.

/// Most mistakes reported for one description; the rest are counted.
pub(crate) const MAX_ERRORS: usize = 50;

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
    /// The text is not valid TOML.
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
    /// A value in a file is missing, of the wrong type or not acceptable.
    #[error("{file}:{line}:{column}: {message}; {help}")]
    Invalid {
        /// Path of the file (or `<inline>`).
        file: String,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// What is wrong.
        message: String,
        /// How to fix it.
        help: String,
        /// Byte range in the text, when known (for compiler spans).
        span: Option<(usize, usize)>,
    },
    /// A value given in code (not read from a file) is not acceptable.
    #[error("{argument}: {message}; {help}")]
    Argument {
        /// The argument, e.g. `` `joints[2].a` `` or `the robot name`.
        argument: String,
        /// What is wrong.
        message: String,
        /// How to fix it.
        help: String,
    },
    /// Several problems, in the order of the text: every one found at once.
    #[error("{}", .0.iter().map(ToString::to_string).collect::<Vec<_>>().join("\n"))]
    Several(Vec<DescriptionError>),
}

impl DescriptionError {
    /// The byte range of the offending text, when known.
    pub fn span(&self) -> Option<(usize, usize)> {
        match self {
            DescriptionError::Invalid { span, .. } => *span,
            _ => None,
        }
    }

    /// Each problem on its own (one for every variant but [`DescriptionError::Several`]).
    pub fn errors(&self) -> Vec<&DescriptionError> {
        match self {
            DescriptionError::Several(all) => all.iter().flat_map(|e| e.errors()).collect(),
            one => vec![one],
        }
    }

    /// One error for a list of them: the error itself when there is one,
    /// [`DescriptionError::Several`] otherwise, of at most [`MAX_ERRORS`] problems and a
    /// count of the rest at the place of the first not shown (a generated URDF of 5000
    /// broken `<mimic>` elements wrote 867 kB of errors).
    pub(crate) fn from_errors(mut errors: Vec<DescriptionError>) -> DescriptionError {
        if errors.len() > MAX_ERRORS {
            let rest = errors.split_off(MAX_ERRORS);
            let message = format!("{} more mistakes from here on are not shown", rest.len());
            let help = "fix the ones above and read the file again".to_owned();
            errors.push(match rest.into_iter().next() {
                Some(DescriptionError::Invalid {
                    file,
                    line,
                    column,
                    span,
                    ..
                }) => DescriptionError::Invalid {
                    file,
                    line,
                    column,
                    message,
                    help,
                    span: span.map(|(start, _)| (start, start)),
                },
                _ => DescriptionError::Argument {
                    argument: "the description".to_owned(),
                    message,
                    help,
                },
            });
        }
        if errors.len() == 1 {
            errors.remove(0)
        } else {
            DescriptionError::Several(errors)
        }
    }
}
