//! Outputs that are put in place together: a command that writes several files (a C source
//! and its header, a JSON result and an HTML report) and fails at the last of them must
//! leave the earlier ones as they were, or the folder holds a header that fits no source
//! (docs/robustness.md#outputs-of-one-run-together).

use std::cell::RefCell;
use std::path::{Path, PathBuf};

use tempfile::NamedTempFile;

use crate::error::{Error, OutputError, Result};

/// A complete temporary file, flushed to disk, waiting to replace its target.
pub(super) struct Complete {
    /// The temporary file, beside the target.
    pub(super) temp: NamedTempFile,
    /// The file it replaces (a link's target).
    pub(super) target: PathBuf,
    /// The output as the user named it, for errors.
    pub(super) path: PathBuf,
    /// The owner of the temporary file, whose stale files the folder is swept of.
    #[cfg(unix)]
    pub(super) owner: Option<u32>,
}

impl Complete {
    /// Renames the temporary file over the target, then sweeps the folder of the
    /// temporary files killed runs left there.
    fn place(self) -> Result<()> {
        let dir = self.temp.path().parent().map(Path::to_path_buf);
        self.temp.persist(&self.target).map_err(|e| {
            Error::Output(OutputError::Write {
                path: self.path.clone(),
                reason: e.error.to_string(),
                fix: super::write_fix(&e.error),
            })
        })?;
        #[cfg(unix)]
        if let (Some(owner), Some(dir)) = (self.owner, dir) {
            super::sweep(&dir, owner);
        }
        #[cfg(not(unix))]
        let _ = dir;
        Ok(())
    }
}

thread_local! {
    /// The files held back while [`together`] runs on this thread; `None` outside it.
    /// Per thread, so that two threads' runs (tests in parallel) never hold each other's
    /// files.
    static HELD: RefCell<Option<Vec<Complete>>> = const { RefCell::new(None) };
}

/// Puts `file` in place now, or holds it until [`together`]'s work has succeeded.
pub(super) fn place(file: Complete) -> Result<()> {
    let file = HELD.with_borrow_mut(|held| match held {
        Some(list) => {
            list.push(file);
            None
        }
        None => Some(file),
    });
    file.map_or(Ok(()), Complete::place)
}

/// Puts in place now the files held so far by the [`together`] under way (nothing outside
/// one), in the order written: for outputs that stand whatever follows, as a trajectory
/// kept for inspection beside the error that it breaks a limit, or a report written before
/// a reader closed standard output.
pub fn place_held() -> Result<()> {
    let files = HELD.with_borrow_mut(|held| held.as_mut().map(std::mem::take));
    files
        .unwrap_or_default()
        .into_iter()
        .try_for_each(Complete::place)
}

/// Drops whatever is still held when [`together`] ends, however it ends (a panic
/// included): the temporary files are removed and the targets untouched.
struct Release;

impl Drop for Release {
    fn drop(&mut self) {
        HELD.with_borrow_mut(Option::take);
    }
}

/// Runs `work`, holding back every file that
/// [`write_atomically`](super::write_atomically) writes meanwhile on this thread: each
/// waits complete in its temporary file beside its target. When `work` succeeds they
/// replace their targets, in the order written; when it fails (or panics) they are removed
/// and every target is left as it was. So the outputs of a run change together or not at
/// all. A special file (a pipe, `/dev/stdout`) cannot wait: it is written as before, at its
/// write, and a failure there (`/dev/full`) fails `work` before any file is put in place.
/// A rename that fails leaves the files renamed before it in place (renames within a
/// folder do not fail short of the disk's own failure). Nested calls hold until the
/// outermost ends.
///
/// ```
/// use robid_runtime::output::{together, write_bytes};
/// # let dir = tempfile::tempdir().unwrap();
/// let (a, b) = (dir.path().join("a.txt"), dir.path().join("b.txt"));
/// std::fs::write(&a, "old").unwrap();
/// let failed: Result<(), robid_runtime::Error> = together(|| {
///     write_bytes(&a, b"new")?;
///     write_bytes(&dir.path().join("missing/b.txt"), b"new")
/// });
/// assert!(failed.is_err());
/// assert_eq!(std::fs::read_to_string(&a).unwrap(), "old");
/// together(|| write_bytes(&a, b"new").and_then(|()| write_bytes(&b, b"new"))).unwrap();
/// assert_eq!(std::fs::read_to_string(&a).unwrap(), "new");
/// ```
pub fn together<T, E: From<Error>>(
    work: impl FnOnce() -> std::result::Result<T, E>,
) -> std::result::Result<T, E> {
    // a run inside a run: the outermost holds
    let nested = HELD.with_borrow_mut(|held| {
        let nested = held.is_some();
        held.get_or_insert_with(Vec::new);
        nested
    });
    if nested {
        return work();
    }
    let release = Release;
    let value = work()?;
    let files = HELD.with_borrow_mut(Option::take).unwrap_or_default();
    drop(release);
    for file in files {
        file.place()?;
    }
    Ok(value)
}

#[cfg(test)]
mod tests {
    use super::{place_held, together};
    use crate::Error;
    use crate::output::write_bytes;
    use std::path::Path;

    fn names(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }

    /// A panic in the work leaves every target as it was and no temporary file; what
    /// `place_held` put in place before a failure stands; a nested run holds until the
    /// outermost ends.
    #[test]
    fn held_files_wait_for_the_whole_run() {
        let dir = tempfile::tempdir().unwrap();
        let (a, b) = (dir.path().join("a"), dir.path().join("b"));
        std::fs::write(&a, "old").unwrap();
        let panicked = std::panic::catch_unwind(|| {
            together(|| -> Result<(), Error> {
                write_bytes(&a, b"new")?;
                panic!("the work fails after a write")
            })
        });
        assert!(panicked.is_err());
        assert_eq!(std::fs::read_to_string(&a).unwrap(), "old");
        assert_eq!(names(dir.path()), ["a"]);

        let failed: Result<(), Error> = together(|| {
            write_bytes(&a, b"kept")?;
            place_held()?;
            write_bytes(&b, b"dropped")?;
            Err(Error::Output(crate::OutputError::Closed {
                path: b.clone(),
            }))
        });
        assert!(failed.is_err());
        assert_eq!(std::fs::read_to_string(&a).unwrap(), "kept");
        assert_eq!(names(dir.path()), ["a"]);

        let nested: Result<(), Error> = together(|| {
            together(|| write_bytes(&b, b"inner"))?;
            assert!(!b.exists(), "the inner run put its file in place");
            write_bytes(&dir.path().join("missing/c"), b"")
        });
        assert!(nested.is_err());
        assert!(!b.exists());
        // outside a run, a write is in place at once
        write_bytes(&b, b"now").unwrap();
        assert_eq!(std::fs::read_to_string(&b).unwrap(), "now");
    }
}
