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
        self.rename().map(Placed::sweep)
    }

    /// Renames the temporary file over the target; the folder is swept later
    /// ([`Placed::sweep`]), once every file of the run is in place, so that no sweep
    /// touches the old files [`Old::keep`] holds meanwhile.
    fn rename(self) -> Result<Placed> {
        let dir = self.temp.path().parent().map(Path::to_path_buf);
        self.temp.persist(&self.target).map_err(|e| {
            Error::Output(OutputError::Write {
                path: self.path.clone(),
                reason: e.error.to_string(),
                fix: super::write_fix(&e.error),
            })
        })?;
        Ok(Placed {
            dir,
            #[cfg(unix)]
            owner: self.owner,
        })
    }
}

/// A file put in place: the folder to sweep of stale temporary files, and their owner.
struct Placed {
    dir: Option<PathBuf>,
    #[cfg(unix)]
    owner: Option<u32>,
}

impl Placed {
    /// Removes the temporary files killed runs left in the folder ([`super::sweep`]).
    fn sweep(self) {
        #[cfg(unix)]
        if let (Some(owner), Some(dir)) = (self.owner, self.dir) {
            super::sweep(&dir, owner);
        }
        #[cfg(not(unix))]
        let _ = self.dir;
    }
}

/// What a target held before the run's file replaced it, for putting it back when a later
/// rename of the same run fails.
enum Old {
    /// The old file, under a second name (a hard link, `.robid-XXXXXX.tmp`) in its
    /// folder; the name is removed when dropped.
    Kept(NamedTempFile<()>),
    /// There was no file: the run's file is removed to restore that.
    Missing,
    /// Not kept: the last file of the run (nothing follows it that could fail), or a
    /// file system that takes no hard link. Such a target cannot be restored.
    Unkept,
}

impl Old {
    /// Gives the existing `target` a second name in its folder, so that its old file
    /// survives the rename over it.
    fn keep(target: &Path) -> Old {
        if std::fs::symlink_metadata(target).is_err() {
            return Old::Missing;
        }
        tempfile::Builder::new()
            .prefix(".robid-")
            .suffix(".tmp")
            .make_in(super::folder_of(target), |name| {
                std::fs::hard_link(target, name)
            })
            .map_or(Old::Unkept, Old::Kept)
    }

    /// Puts the old file back at `target` (or removes the file created there); a failure
    /// here is not reported over the rename's own error.
    fn restore(self, target: &Path) {
        match self {
            Old::Kept(old) => {
                old.persist(target).ok();
            }
            Old::Missing => {
                std::fs::remove_file(target).ok();
            }
            Old::Unkept => {}
        }
    }
}

/// Puts `files` in place in order. When a rename fails (another user's file in a shared
/// folder, a name the file system refuses, a folder changed meanwhile), the files put in
/// place before it are taken back: each replaced target gets its old file again (kept
/// under a second name until every rename has succeeded), each created one is removed;
/// the failing one and those after it were never renamed.
fn place_all(files: Vec<Complete>) -> Result<()> {
    let count = files.len();
    let mut placed: Vec<(PathBuf, Old, Placed)> = Vec::with_capacity(count);
    for (k, file) in files.into_iter().enumerate() {
        let target = file.target.clone();
        let old = if k + 1 < count {
            Old::keep(&target)
        } else {
            Old::Unkept
        };
        match file.rename() {
            Ok(done) => placed.push((target, old, done)),
            Err(e) => {
                // the old file of this target was never replaced: its second name goes
                drop(old);
                for (target, old, _) in placed.into_iter().rev() {
                    old.restore(&target);
                }
                return Err(e);
            }
        }
    }
    for (_, old, done) in placed {
        drop(old);
        done.sweep();
    }
    Ok(())
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
    place_all(files.unwrap_or_default())
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
/// What would make a rename fail is refused when each file is written (a name too long
/// for its folder, a file the user may not replace: see
/// [`check_file`](super::check_file)); a rename that fails all the same (the folder
/// changed meanwhile) takes back the renames before it: every target is left as it was,
/// but for the rare one whose old file could not be kept under a second name (a file
/// system without hard links), or a second failure while putting one back. Nested calls
/// hold until the outermost ends.
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
    place_all(files)?;
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

    /// A rename that fails after others of the run succeeded (its target became a folder
    /// after the write) takes them back: the replaced file has its old text again, the
    /// created one is gone, and neither a temporary file nor a kept old file is left. It
    /// left them new.
    #[test]
    fn a_failed_rename_takes_back_the_renames_before_it() {
        let dir = tempfile::tempdir().unwrap();
        let (a, b, c) = (
            dir.path().join("a"),
            dir.path().join("b"),
            dir.path().join("c"),
        );
        std::fs::write(&a, "old").unwrap();
        let failed: Result<(), Error> = together(|| {
            write_bytes(&a, b"new")?;
            write_bytes(&b, b"new")?;
            write_bytes(&c, b"new")?;
            std::fs::create_dir(&c).unwrap();
            Ok(())
        });
        assert!(failed.is_err());
        assert_eq!(std::fs::read_to_string(&a).unwrap(), "old");
        assert!(!b.exists());
        assert_eq!(names(dir.path()), ["a", "c"]);
        // a run that succeeds keeps no old file either
        std::fs::remove_dir(&c).unwrap();
        together(|| {
            write_bytes(&a, b"new")?;
            write_bytes(&b, b"new")
        })
        .unwrap();
        assert_eq!(std::fs::read_to_string(&a).unwrap(), "new");
        assert_eq!(names(dir.path()), ["a", "b"]);
    }
}
