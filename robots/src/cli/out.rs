//! Standard output and standard error of `robid`: writes that report their errors
//! instead of panicking as `print!` does.
//!
//! Everything a subcommand prints goes through [`Stdout`] (`writeln!(out, ..)?`), whose
//! failures are a [`StdoutError`]. [`stdout_failure`] turns them into the end of the program:
//! a closed pipe (`robid torques .. | head -1`) ends it quietly with the conventional
//! status 141 (128 + SIGPIPE), any other failure (a full disk) with a one-line message
//! naming standard output and status 1. An output file that is a pipe closed by its reader
//! (`-o /dev/stdout | head -1`, `--report /dev/stdout | head`: `OutputError::Closed`)
//! ends the same quiet way. Messages for the user go to standard error
//! through [`warn`] and [`error`], which never fail: there is nowhere left to report
//! a failing standard error.

use std::fmt;
use std::io::{self, Write};
use std::process::ExitCode;

/// The exit status of a program ended by a closed pipe (128 + SIGPIPE).
pub(crate) const BROKEN_PIPE: u8 = 141;

/// A write to standard output failed: the reader closed the pipe, or the disk is full.
#[derive(Debug)]
pub(crate) struct StdoutError(io::Error);

impl fmt::Display for StdoutError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "cannot write to standard output: {}", self.0)
    }
}

impl std::error::Error for StdoutError {}

/// Standard output, locked and buffered; call [`Stdout::flush`] at the end, since an
/// error of the final flush is reported only there.
pub(crate) struct Stdout {
    inner: io::BufWriter<io::StdoutLock<'static>>,
}

impl Stdout {
    /// Locks standard output for the rest of the subcommand.
    pub(crate) fn new() -> Self {
        Self {
            inner: io::BufWriter::with_capacity(1 << 16, io::stdout().lock()),
        }
    }

    /// What `write!` and `writeln!` call.
    pub(crate) fn write_fmt(&mut self, args: fmt::Arguments<'_>) -> Result<(), StdoutError> {
        self.inner.write_fmt(args).map_err(StdoutError)
    }

    /// Writes `text` as it is.
    pub(crate) fn write_str(&mut self, text: &str) -> Result<(), StdoutError> {
        self.inner.write_all(text.as_bytes()).map_err(StdoutError)
    }

    /// Writes what is buffered.
    pub(crate) fn flush(&mut self) -> Result<(), StdoutError> {
        self.inner.flush().map_err(StdoutError)
    }
}

/// Writes `text` to standard output and flushes it.
pub(crate) fn print(text: &str) -> Result<(), StdoutError> {
    let mut out = Stdout::new();
    out.write_str(text)?;
    out.flush()
}

/// Writes one line to standard error (a message for the user next to the results).
pub(crate) fn warn(line: fmt::Arguments<'_>) {
    let _ = writeln!(io::stderr().lock(), "{line}");
}

/// The exit status for an error that ends a subcommand, after reporting it: quietly 141
/// for a closed standard output, else the message on standard error and status 1.
pub(crate) fn error(e: &(dyn std::error::Error + 'static)) -> ExitCode {
    if let Some(StdoutError(io)) = e.downcast_ref::<StdoutError>() {
        return stdout_failure(io);
    }
    if closed_early(e) {
        return ExitCode::from(BROKEN_PIPE);
    }
    warn(format_args!("error: {e}"));
    ExitCode::FAILURE
}

/// Whether `e` is a failure of standard output, or of an output pipe its reader closed:
/// not of the run's files, which stand (`robid_runtime::output::place_held`).
pub(crate) fn stdout_or_reader_failed(e: &(dyn std::error::Error + 'static)) -> bool {
    e.is::<StdoutError>() || closed_early(e)
}

/// Whether `e` (or an error it wraps, e.g. of one run) is an output pipe closed by its
/// reader.
fn closed_early(e: &(dyn std::error::Error + 'static)) -> bool {
    let mut next = Some(e);
    while let Some(e) = next {
        let output = match e.downcast_ref::<robid_runtime::Error>() {
            Some(robid_runtime::Error::Output(o)) => Some(o),
            _ => e.downcast_ref::<robid_runtime::OutputError>(),
        };
        if matches!(output, Some(robid_runtime::OutputError::Closed { .. })) {
            return true;
        }
        next = e.source();
    }
    false
}

/// The exit status after standard output failed with `e` (see [`error`]).
pub(crate) fn stdout_failure(e: &io::Error) -> ExitCode {
    if e.kind() == io::ErrorKind::BrokenPipe {
        return ExitCode::from(BROKEN_PIPE);
    }
    warn(format_args!("error: cannot write to standard output: {e}"));
    ExitCode::FAILURE
}
