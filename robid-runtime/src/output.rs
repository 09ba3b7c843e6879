//! Files written for users: never damaged, never written over an input.
//!
//! Every output of robid (CSV, JSON, TOML, URDF, Rust code, plots, reports) goes
//! through [`write_atomically`]: the bytes are written to a temporary file in the
//! target's folder, flushed to disk, and renamed over the target only when complete.
//! A failed or killed run therefore leaves an existing file exactly as it was, and a
//! reader never sees half a file. [`refuse_inputs`] is called before any work starts,
//! so that `robid excite robot.toml -o robot.toml` fails instead of replacing the
//! description.
//!
//! ```
//! # let dir = tempfile::tempdir().unwrap();
//! let path = dir.path().join("out.csv");
//! robid_runtime::output::write_bytes(&path, b"t,q1\n0,0\n").unwrap();
//! assert_eq!(std::fs::read_to_string(&path).unwrap(), "t,q1\n0,0\n");
//! ```

use std::io::Write;
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};

/// Writes `path` atomically: `write` fills a temporary file beside `path`, which
/// replaces `path` (keeping its permissions) only when `write` and the flush succeed.
///
/// A symbolic link is followed, so the file it points to is replaced and the link
/// kept. On any error the temporary file is removed and `path` is left untouched.
pub fn write_atomically(
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<()> {
    let err = |e: &dyn std::fmt::Display| {
        Error::Output(OutputError::Write {
            path: path.to_path_buf(),
            reason: e.to_string(),
        })
    };
    // Write beside the file a link points to, so the rename replaces that file.
    let target = std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf());
    let dir = match target.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    if target.is_dir() {
        return Err(err(&"it is a folder; give a file name"));
    }
    let existing = std::fs::metadata(&target).ok().map(|m| m.permissions());
    let mut temp = temp_builder()
        .prefix(".robid-")
        .suffix(".tmp")
        .tempfile_in(&dir)
        .map_err(|e| err(&e))?;
    {
        let mut w = std::io::BufWriter::new(temp.as_file_mut());
        write(&mut w).map_err(|e| err(&e))?;
        w.flush().map_err(|e| err(&e))?;
    }
    temp.as_file().sync_all().map_err(|e| err(&e))?;
    if let Some(p) = existing {
        temp.as_file().set_permissions(p).map_err(|e| err(&e))?;
    }
    temp.persist(&target).map_err(|e| err(&e.error))?;
    Ok(())
}

/// New files get the permissions an ordinary file would (0o666 less the umask), not
/// the private 0o600 of a temporary file.
fn temp_builder() -> tempfile::Builder<'static, 'static> {
    #[allow(unused_mut)]
    let mut b = tempfile::Builder::new();
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        b.permissions(std::fs::Permissions::from_mode(0o666));
    }
    b
}

/// Writes `bytes` to `path` atomically (see [`write_atomically`]).
pub fn write_bytes(path: &Path, bytes: &[u8]) -> Result<()> {
    write_atomically(path, |w| w.write_all(bytes))
}

/// Creates the folder `dir` (and its parents) for outputs.
pub fn create_folder(dir: &Path) -> Result<()> {
    std::fs::create_dir_all(dir).map_err(|e| {
        Error::Output(OutputError::Write {
            path: dir.to_path_buf(),
            reason: format!("cannot create the folder: {e}"),
        })
    })
}

/// Refuses, before any work, an output that is the same file as an input (the same
/// file under another name or through a link included). Outputs that do not exist
/// yet cannot be an input and pass.
pub fn refuse_inputs(inputs: &[&Path], outputs: &[&Path]) -> Result<()> {
    for output in outputs {
        for input in inputs {
            if same_file::is_same_file(output, input).unwrap_or(false) {
                return Err(Error::Output(OutputError::OutputIsInput {
                    output: output.to_path_buf(),
                    input: input.to_path_buf(),
                }));
            }
        }
    }
    Ok(())
}

/// An output cannot be written.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum OutputError {
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
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_failed_write_leaves_the_old_file_whole() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("data.csv");
        std::fs::write(&path, "old contents\n").unwrap();
        let result = write_atomically(&path, |w| {
            w.write_all(b"new, half wri")?;
            Err(std::io::Error::other("disk full"))
        });
        assert!(
            matches!(result, Err(Error::Output(OutputError::Write { .. }))),
            "{result:?}"
        );
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "old contents\n");
        // no temporary file is left behind
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    }

    #[test]
    fn a_successful_write_replaces_and_keeps_permissions() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("out.json");
        std::fs::write(&path, "{}").unwrap();
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o640)).unwrap();
        }
        write_bytes(&path, b"[1]").unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "[1]");
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            let mode = std::fs::metadata(&path).unwrap().permissions().mode();
            assert_eq!(mode & 0o777, 0o640);
        }
    }

    #[test]
    #[cfg(unix)]
    fn a_link_is_kept_and_its_target_replaced() {
        let dir = tempfile::tempdir().unwrap();
        let real = dir.path().join("real.csv");
        let link = dir.path().join("link.csv");
        std::fs::write(&real, "a").unwrap();
        std::os::unix::fs::symlink(&real, &link).unwrap();
        write_bytes(&link, b"b").unwrap();
        assert!(std::fs::symlink_metadata(&link).unwrap().is_symlink());
        assert_eq!(std::fs::read_to_string(&real).unwrap(), "b");
    }

    #[test]
    fn a_folder_is_not_a_target() {
        let dir = tempfile::tempdir().unwrap();
        assert!(matches!(
            write_bytes(dir.path(), b"x"),
            Err(Error::Output(OutputError::Write { .. }))
        ));
    }

    #[test]
    fn an_output_that_is_an_input_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let input = dir.path().join("desc.toml");
        std::fs::write(&input, "name = \"x\"").unwrap();
        let other_name = dir.path().join(".").join("desc.toml");
        let fresh = dir.path().join("new.csv");
        assert!(matches!(
            refuse_inputs(&[&input], &[&fresh, &other_name]),
            Err(Error::Output(OutputError::OutputIsInput { .. }))
        ));
        assert!(refuse_inputs(&[&input], &[&fresh]).is_ok());
        #[cfg(unix)]
        {
            let link = dir.path().join("alias.toml");
            std::os::unix::fs::symlink(&input, &link).unwrap();
            assert!(refuse_inputs(&[&input], &[&link]).is_err());
        }
    }
}
