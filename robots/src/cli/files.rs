//! The files `robid` writes: every output goes through `robid_runtime::output` (a
//! temporary file beside the target, renamed into place when complete), so a failed or
//! killed run leaves an existing file exactly as it was; and an output that is the same
//! file as an input of the run (the same path, another spelling of it, a hard or
//! symbolic link) is refused before any work starts.

use std::path::{Path, PathBuf};

use robid_runtime::output::{refuse_inputs, write_bytes};

use super::Error;

/// Refuses every output that is the same file as one of the inputs.
pub(crate) fn refuse(inputs: &[&Path], outputs: &[&Path]) -> Result<(), Error> {
    Ok(refuse_inputs(inputs, outputs)?)
}

/// Writes `text` to `path` atomically.
pub(crate) fn write(path: &Path, text: &str) -> Result<(), Error> {
    Ok(write_bytes(path, text.as_bytes())?)
}

/// The files `robid_runtime::report::plot_torques` writes into `dir` for each prefix:
/// `{prefix}_joint{j}.svg`, j = 1..=dof.
pub(crate) fn plot_files(dir: &Path, prefixes: &[String], dof: usize) -> Vec<PathBuf> {
    prefixes
        .iter()
        .flat_map(|p| (1..=dof).map(move |j| dir.join(format!("{p}_joint{j}.svg"))))
        .collect()
}
