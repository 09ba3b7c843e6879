//! The crate's error type: every variant names where the problem is and how to fix it.
//!
//! Each module that reads, writes or solves something has its own error under this one
//! ([`DataError`], [`OutputError`], [`EstimateError`], [`SimulateError`],
//! [`FeasibleError`]); what any module can meet (a size, too few samples, a solver's cap, a
//! non-finite result) is a variant of its own here. The kind of input is part of the
//! variant, so that a caller can say it in its own terms: a data file is named by
//! file:line and column ([`DataError::NotFinite`]), a key of a config file by
//! file:line:column ([`DataError::ConfigKey`]), a setting given in code (a field of a
//! settings struct, or a function argument) by its Rust name ([`Error::Setting`]), and a
//! front end's flag by the flag ([`Error::Argument`], see [`Error::on_flags`]).

pub use crate::data::DataError;
pub use crate::estimate::EstimateError;
pub use crate::feasible::FeasibleError;
pub use crate::output::OutputError;
pub use crate::simulate::SimulateError;

/// Everything that can go wrong between a data file and an identified model.
///
/// Locations are given as precisely as the input allows: `path` is the file (or a
/// description such as `<memory>`), `line` is the 1-based line in that file (the header
/// is line 1), `column` the column name.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A data file, a config file or a parameter file cannot be used.
    #[error(transparent)]
    Data(#[from] DataError),
    /// An output cannot be written.
    #[error(transparent)]
    Output(#[from] OutputError),
    /// The observation matrix cannot be solved as given.
    #[error(transparent)]
    Estimate(#[from] EstimateError),
    /// The data of a payload's identification ([`crate::payload`]) do not determine all
    /// ten of its parameters. A payload has exactly ten, none of which can be left out, so
    /// the fix is in the data or in what is measured (the estimator's own
    /// [`EstimateError::RankDeficient`] advised to "remove these parameters").
    /// Where the measurement itself determines fewer than ten (`most`), the directions are
    /// "not determined", not "not excited": no motion excites them.
    #[error("rank-deficient data: rank {rank} of the payload's 10 parameters; {}; {fix}", crate::estimate::undetermined(*rank, 10, unexcited, if *most < 10 { "not determined" } else { "not excited" }))]
    PayloadNotExcited {
        /// Numerical rank found.
        rank: usize,
        /// The most combinations of the ten the measurement determines whatever the motion.
        most: usize,
        /// The parameters that make up the unexcited directions, most affected first.
        unexcited: Vec<String>,
        /// What to do: a richer motion, or, when the robot's joint torques cannot
        /// determine them whatever the motion, another measurement.
        fix: String,
    },
    /// A closed-loop simulation failed.
    #[error(transparent)]
    Simulate(#[from] SimulateError),
    /// No feasible parameters can be given.
    #[error(transparent)]
    Feasible(#[from] FeasibleError),
    /// Not enough samples for the requested processing.
    #[error("{context}: {}, at least {required} {} needed; {hint}", crate::Count(*found, "sample"), if *required == 1 { "is" } else { "are" })]
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
    /// A setting given in code is out of range or inconsistent: a field of a settings
    /// struct (`Simulation::bandwidth`, a [`crate::data::Config`] built in code) or a
    /// function argument (`rate` of [`crate::excite::Fourier::sample`]). `owner` is the
    /// Rust type or function, `key` the field or argument (a dotted path inside a
    /// `Config`); a command line maps `key` to its flag. A key read from a config file
    /// is a [`DataError::ConfigKey`] instead.
    #[error("{owner} `{key}`: {problem}")]
    Setting {
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
    /// A matrix required to be invertible or positive definite is not.
    #[error("{what} is singular or not positive definite; {hint}")]
    Singular {
        /// Which matrix.
        what: String,
        /// What to change.
        hint: &'static str,
    },
    /// A problem that arose from the data of one of several runs (`[runs]` of a config,
    /// [`crate::pipeline::identify_runs`], [`crate::data::load_runs`]): `error` is what it
    /// would be for that run alone, `run` names the run, so that a rank-deficient or too
    /// short run among ten can be found.
    #[error("{run}: {error}")]
    Run {
        /// The run: its entry `runs.files[i]` at file:line:column and its files for a
        /// config file with `[runs]`, else its number (from 1) and its data set's name.
        run: String,
        /// The problem itself.
        #[source]
        error: Box<Error>,
    },
    /// A command-line argument is out of range or inconsistent: a front end's flag, named
    /// as the user wrote it (a setting of the library given through a flag is first an
    /// [`Error::Setting`], which the front end maps with [`Error::on_flags`]).
    #[error("{flag}: {problem}")]
    Argument {
        /// The flag, e.g. `--bandwidth`.
        flag: String,
        /// What is wrong and what to write instead.
        problem: String,
    },
}

impl Error {
    /// A non-finite observation found at sample `k` of a part (a block, the decimated
    /// samples) placed in the whole: `to(k)` gives its sample there and where that is
    /// (`file:line`, or "processed sample N"); `Err` with any other error, as it is.
    pub(crate) fn placed(self, to: impl FnOnce(usize) -> (usize, String)) -> Result<Error> {
        match self {
            Error::Estimate(crate::EstimateError::NonFiniteObservation {
                sample: Some(k),
                joint,
                parameter,
                value,
                ..
            }) => {
                let (sample, location) = to(k);
                Ok(Error::Estimate(
                    crate::EstimateError::NonFiniteObservation {
                        location,
                        sample: Some(sample),
                        joint,
                        parameter,
                        value,
                    },
                ))
            }
            e => Err(e),
        }
    }

    /// An [`Error::Setting`] for the setting `key` of `owner`.
    pub fn setting(owner: &str, key: &str, problem: impl Into<String>) -> Error {
        Error::Setting {
            owner: owner.to_string(),
            key: key.to_string(),
            problem: problem.into(),
        }
    }

    /// Refuses a `value` of setting `key` that is not positive and finite: "{what} {value}
    /// {unit} must be positive and finite" (a sample time, a rate, a cutoff: 0 or NaN
    /// there gave infinite or NaN outputs).
    pub(crate) fn positive_and_finite(
        owner: &str,
        key: &str,
        what: &str,
        value: f64,
        unit: &str,
    ) -> Result<()> {
        if value > 0.0 && value.is_finite() {
            return Ok(());
        }
        Err(Error::setting(
            owner,
            key,
            format!("{what} {} {unit} must be positive and finite", num(value)),
        ))
    }

    /// The error as a front end shows it: a setting that the front end fills from a flag
    /// (`flags` maps a setting's key, e.g. `bandwidth`, to its flag, e.g. `--bandwidth`)
    /// becomes an [`Error::Argument`] naming the flag; any other error is unchanged.
    ///
    /// ```
    /// use robid_runtime::Error;
    ///
    /// let e = Error::setting("Simulation", "bandwidth", "must be positive; give e.g. 10 Hz");
    /// let e = e.on_flags(&[("bandwidth", "--bandwidth")]);
    /// assert_eq!(e.to_string(), "--bandwidth: must be positive; give e.g. 10 Hz");
    /// ```
    pub fn on_flags(self, flags: &[(&str, &str)]) -> Error {
        match self {
            Error::Setting {
                key,
                problem,
                owner,
            } => match flags.iter().find(|(k, _)| *k == key) {
                Some((_, flag)) => Error::Argument {
                    flag: (*flag).to_owned(),
                    problem,
                },
                None => Error::Setting {
                    owner,
                    key,
                    problem,
                },
            },
            other => other,
        }
    }
}

/// `path:line:column`, with what is known.
pub(crate) fn place(path: &std::path::Path, line: Option<usize>, column: Option<usize>) -> String {
    match (line, column) {
        (Some(l), Some(c)) => format!("{}:{l}:{c}", path.display()),
        (Some(l), None) => format!("{}:{l}", path.display()),
        _ => path.display().to_string(),
    }
}

/// A number for a message, as [`Num`](crate::Num) writes it: `0.5`, `100`, `1e308`,
/// `1e-320` (never 309 or 320 digits).
///
/// ```
/// use robid_runtime::num;
/// assert_eq!(num(0.5), "0.5");
/// assert_eq!(num(1e-320), "1e-320");
/// assert_eq!(num(-1e308), "-1e308");
/// ```
pub fn num(x: f64) -> String {
    crate::Num(x).to_string()
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

#[cfg(test)]
mod tests {
    use super::{DataError, Error, SimulateError, num};

    /// Ordinary values read as written; very large and very small ones in exponent form,
    /// every value in at most 24 characters and reading back exactly.
    #[test]
    fn num_is_short_and_exact() {
        for (x, text) in [
            (0.0, "0"),
            (0.5, "0.5"),
            (100.0, "100"),
            (1e-3, "0.001"),
            (-0.13, "-0.13"),
            (123456.789, "123456.789"),
            (1e-300, "1e-300"),
            (1e-320, "1e-320"),
            (1e30, "1e30"),
            (1e308, "1e308"),
            (-f64::MAX, "-1.7976931348623157e308"),
            (f64::NAN, "NaN"),
            (f64::INFINITY, "inf"),
        ] {
            assert_eq!(num(x), text);
        }
        let mut x = f64::MIN_POSITIVE / 3.0;
        while x < f64::MAX / 3.0 {
            for v in [x, -x / 7.0] {
                let t = num(v);
                assert!(t.len() <= 24, "{t}");
                assert_eq!(t.parse::<f64>().unwrap(), v, "{t}");
            }
            x *= 3.7;
        }
    }

    /// Messages that show a value from the input write it short: a time stamp of 1e-320
    /// printed as 0.000...0001 with 320 digits.
    #[test]
    fn messages_write_extreme_values_short() {
        let e = Error::Data(DataError::NonMonotonicTime {
            path: "log.csv".into(),
            line: 3,
            previous: 1e-320,
            value: 0.0,
        });
        assert_eq!(
            e.to_string(),
            "log.csv:3: time 0 does not increase (previous 1e-320); sort the rows by time or \
             remove duplicates"
        );
        let e = Error::Simulate(SimulateError::Diverged {
            time: 2.5,
            sample: 250,
            reason: "r".into(),
            fix: "f".into(),
        });
        assert!(e.to_string().contains("at t = 2.5 s"), "{e}");
    }
}
