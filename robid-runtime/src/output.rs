//! Files written for users: never damaged, never written over an input.
//!
//! Every output of robid (CSV, JSON, TOML, URDF, Rust code, plots, reports) goes
//! through [`write_atomically`]: the bytes are written to a temporary file in the
//! target's folder, flushed to disk, and renamed over the target only when complete.
//! A failed or killed run therefore leaves an existing file exactly as it was, and a
//! reader never sees half a file. [`refuse_inputs`] is called before any work starts,
//! so that `robid excite robot.toml -o robot.toml` fails instead of replacing the
//! description, or two outputs of one run on the same file; and so are [`check_file`]
//! and [`check_folder`], so that an output the writer would refuse (a folder, a missing
//! folder, a folder that takes no new file) is refused before a long run rather than
//! after it. A target that is not a
//! regular file (a pipe, `/dev/stdout`, a terminal, a device) is written into directly:
//! it cannot be replaced, and replacing it would destroy it.
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
/// kept. On any error the temporary file is removed and `path` is left untouched. After a
/// write, the temporary files that killed runs left in the folder are removed once they
/// are [`STALE_TEMPORARY`] old (on Unix; nothing else is touched). A
/// target that exists and is neither a file nor a folder (a pipe, `/dev/stdout`, a
/// device) is opened and written into, as a shell's `>` would, once `write` has
/// succeeded (the text waits in a temporary file until then, so that a reader sees all
/// of it or nothing).
pub fn write_atomically(
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<()> {
    let err = |e: &std::io::Error| {
        Error::Output(OutputError::Write {
            path: path.to_path_buf(),
            reason: e.to_string(),
            fix: write_fix(e),
        })
    };
    let (target, dir, existing, link) = match target(path)? {
        Target::Special(target) => {
            // a reader that stops early (`-o /dev/stdout | head`) closes a pipe: not a
            // problem of the path, so not `Write`'s "check that the folder exists"
            let failed = |e: std::io::Error| match e.kind() {
                std::io::ErrorKind::BrokenPipe => Error::Output(OutputError::Closed {
                    path: path.to_path_buf(),
                }),
                _ => err(&e),
            };
            // the text waits in a temporary file until `write` has succeeded: a reader of
            // the pipe got the rows before a refused one, then the error
            let temporary = |source| {
                Error::Data(crate::DataError::Temporary {
                    dir: std::env::temp_dir(),
                    source,
                })
            };
            let mut held = std::io::BufWriter::new(tempfile::tempfile().map_err(temporary)?);
            if let Err(e) = write(&mut held) {
                close_unwritten(&target);
                return Err(err(&e));
            }
            let mut held = held.into_inner().map_err(|e| temporary(e.into_error()))?;
            std::io::Seek::rewind(&mut held).map_err(temporary)?;
            let file = std::fs::OpenOptions::new()
                .write(true)
                .open(&target)
                .map_err(failed)?;
            let mut w = std::io::BufWriter::new(file);
            std::io::copy(&mut held, &mut w).map_err(failed)?;
            return w.flush().map_err(failed);
        }
        Target::File {
            target,
            dir,
            permissions,
            link,
        } => (target, dir, permissions, link),
    };
    // the error names the temporary file ("at path \"dir/.robid-Z2mU1l.tmp\""), which
    // the user never asked for: name the folder instead
    let mut temp = temp_builder()
        .prefix(".robid-")
        .suffix(".tmp")
        .tempfile_in(&dir)
        .map_err(|e| not_writable(path, link.then_some(target.as_path()), &dir, &e))?;
    {
        let mut w = std::io::BufWriter::new(temp.as_file_mut());
        write(&mut w).map_err(|e| err(&e))?;
        w.flush().map_err(|e| err(&e))?;
    }
    temp.as_file().sync_all().map_err(|e| err(&e))?;
    if let Some(p) = existing {
        temp.as_file().set_permissions(p).map_err(|e| err(&e))?;
    }
    #[cfg(unix)]
    let owner = {
        use std::os::unix::fs::MetadataExt;
        temp.as_file().metadata().map(|m| m.uid()).ok()
    };
    temp.persist(&target).map_err(|e| err(&e.error))?;
    #[cfg(unix)]
    if let Some(owner) = owner {
        sweep(&dir, owner);
    }
    Ok(())
}

/// Opens the special file `target` and closes it at once, without waiting for a reader
/// (on Unix): a reader of a named pipe that robid was to write gets the end of the text
/// instead of waiting for ever when the write failed before anything was sent.
fn close_unwritten(target: &Path) {
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        let _ = std::fs::OpenOptions::new()
            .write(true)
            .custom_flags(libc::O_NONBLOCK)
            .open(target);
    }
    #[cfg(not(unix))]
    let _ = target;
}

/// How old a temporary file of robid's (`.robid-XXXXXX.tmp`) must be for
/// [`write_atomically`] to remove it from the folder it writes into: a run killed while
/// writing (SIGKILL, a power cut) leaves its temporary file there, as no code of its
/// runs again. A write takes seconds and touches its file all along, so a day without a
/// change means the run is gone, and a run suspended for that long (`kill -STOP`) is
/// not the concern of a later one.
pub const STALE_TEMPORARY: std::time::Duration = std::time::Duration::from_secs(24 * 3600);

/// Whether `name` is that of a temporary file of robid's: `.robid-`, the six letters
/// or digits `tempfile` draws, `.tmp`.
fn is_temporary_name(name: &std::ffi::OsStr) -> bool {
    let name = name.as_encoded_bytes();
    name.len() == 17
        && name.starts_with(b".robid-")
        && name.ends_with(b".tmp")
        && name[7..13].iter().all(u8::is_ascii_alphanumeric)
}

/// Removes from `dir`, once per process, the temporary files that killed runs of robid
/// left there: a regular file (not a link, not a folder, with no other name) named as
/// robid names them ([`is_temporary_name`]), of the same owner as this run's own temporary
/// file, unchanged for [`STALE_TEMPORARY`]. Nothing else is touched; a file that cannot be read or
/// removed is left as it is (not the output's concern).
#[cfg(unix)]
fn sweep(dir: &Path, owner: u32) {
    use std::os::unix::fs::MetadataExt;
    static SWEPT: std::sync::Mutex<Vec<PathBuf>> = std::sync::Mutex::new(Vec::new());
    {
        let Ok(mut swept) = SWEPT.lock() else {
            return;
        };
        if swept.iter().any(|d| d == dir) {
            return;
        }
        swept.push(dir.to_path_buf());
    }
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    let now = std::time::SystemTime::now();
    for entry in entries.flatten() {
        if !is_temporary_name(&entry.file_name()) {
            continue;
        }
        let path = entry.path();
        let Ok(m) = std::fs::symlink_metadata(&path) else {
            continue;
        };
        let stale = m
            .modified()
            .ok()
            .and_then(|t| now.duration_since(t).ok())
            .is_some_and(|age| age >= STALE_TEMPORARY);
        // one name only: a hard link named like a temporary is some other file's too
        if m.file_type().is_file() && m.nlink() == 1 && m.uid() == owner && stale {
            std::fs::remove_file(&path).ok();
        }
    }
}

/// Refuses, before any work, a file output that its writer ([`write_atomically`]) would
/// refuse, with the writer's message: an existing folder ([`OutputError::Folder`]), a
/// path whose folder does not exist ([`OutputError::NoFolder`]), is a file
/// ([`OutputError::NotAFolder`]) or takes no new file ([`OutputError::NotWritable`]: no
/// permission, a read-only file system, /proc; [`OutputError::LinkNotWritable`] for an
/// output that is a link), or is reached through a link that loops or points to nothing
/// ([`OutputError::FolderLinkLoop`], [`OutputError::FolderLinkMissing`]). A pipe,
/// `/dev/stdout` or another special file
/// passes. The target is never created or opened; whether the folder takes a file is
/// tried by creating a temporary file in it, removed at once. The writer checks again
/// (the folder may change meanwhile).
///
/// ```
/// use robid_runtime::{Error, OutputError, output::check_file};
/// # let dir = tempfile::tempdir().unwrap();
/// assert!(check_file(&dir.path().join("out.csv")).is_ok());
/// let e = check_file(&dir.path().join("missing/out.csv")).unwrap_err();
/// assert!(matches!(e, Error::Output(OutputError::NoFolder { .. })));
/// ```
pub fn check_file(path: &Path) -> Result<()> {
    match target(path)? {
        Target::Special(_) => Ok(()),
        Target::File {
            dir, target, link, ..
        } => probe(path, link.then_some(target.as_path()), &dir),
    }
}

/// Refuses output `path` when no file can be created in `dir`, as the writer would find:
/// a temporary file is created there and removed. `link` is the file that `path`, a
/// symbolic link, points to.
fn probe(path: &Path, link: Option<&Path>, dir: &Path) -> Result<()> {
    let temp = tempfile::Builder::new()
        .prefix(".robid-")
        .suffix(".tmp")
        .tempfile_in(dir)
        .map_err(|e| not_writable(path, link, dir, &e))?;
    // removed now, not at the end of the run; a failure to remove it is not the output's
    temp.close().ok();
    Ok(())
}

/// The error of output `path` whose folder `dir` takes no new file; `link` is the file
/// that `path`, a symbolic link, points to (in `dir`).
fn not_writable(path: &Path, link: Option<&Path>, dir: &Path, e: &std::io::Error) -> Error {
    // the kind, not the error: that names the temporary file, which the user never asked
    // for
    let reason = match e.kind() {
        // a folder that exists yet has no room for a name: a file system of the kernel
        std::io::ErrorKind::NotFound if dir.is_dir() => NO_NEW_FILES.to_owned(),
        kind => kind.to_string(),
    };
    let (path, folder) = (path.to_path_buf(), dir.to_path_buf());
    Error::Output(match link {
        Some(target) => OutputError::LinkNotWritable {
            path,
            target: target.to_path_buf(),
            folder,
            reason,
        },
        None => OutputError::NotWritable {
            path,
            folder,
            reason,
        },
    })
}

/// The reason given for an existing folder in which creating a file fails with "not
/// found": the kernel's /proc and /sys take no file that the kernel does not make.
const NO_NEW_FILES: &str = "the system refuses new files there, as in /proc and /sys";

/// The fix of an output whose folder takes no new file for `reason`: making the folder
/// writable is a fix for a permission or a read-only mount, not for /proc.
/// The fix [`OutputError::Write`] gives when nothing more is known: the folder.
pub const CHECK_FOLDER: &str = "check that the folder exists and is writable";

/// The fix for a write that failed with `e`: a full disk or quota has nothing to do with
/// the folder (it told `/dev/full`'s "No space left on device" to check that the folder
/// is writable).
pub fn write_fix(e: &std::io::Error) -> &'static str {
    use std::io::ErrorKind;
    match e.kind() {
        ErrorKind::StorageFull | ErrorKind::QuotaExceeded => {
            "free space on that disk, or write to another one"
        }
        ErrorKind::FileTooLarge => "its file system takes no file this large: write to another",
        _ => CHECK_FOLDER,
    }
}

fn not_writable_fix(reason: &str) -> &'static str {
    if reason == NO_NEW_FILES {
        "give a path in a folder you may write into"
    } else {
        "give a path in a folder you may write into, or make this one writable"
    }
}

/// Refuses, before any work, a folder output ([`create_folder`]: created with its
/// parents when missing, files written into it) that cannot be one: an existing file
/// ([`OutputError::FileNotFolder`]), a path through a file ([`OutputError::NotAFolder`]),
/// or a folder that takes no new file, or for a missing one the nearest existing folder
/// above it ([`OutputError::NotWritable`]). A missing folder passes otherwise. No folder
/// is created; whether a folder takes a file is tried by creating a temporary file in
/// it, removed at once. [`create_folder`] checks again. A symbolic link to a folder not
/// created yet stands for the folder it points to, which is checked (and created) in its
/// place, the link kept.
pub fn check_folder(dir: &Path) -> Result<()> {
    let target = folder_target(dir)?;
    let problem = match std::fs::metadata(&target) {
        Ok(m) if m.is_dir() => return probe(dir, None, &target),
        Ok(_) => OutputError::FileNotFolder {
            path: dir.to_path_buf(),
        },
        // a link on the way that loops or points to nothing: no folder can be made there
        Err(e)
            if e.kind() != std::io::ErrorKind::NotADirectory
                && broken_link(dir, &target).is_some() =>
        {
            broken_link(dir, &target).unwrap_or(OutputError::LinkLoop {
                path: dir.to_path_buf(),
            })
        }
        // a missing path whose every existing part is a folder: created with its parents
        // in the nearest existing one
        Err(e) if e.kind() != std::io::ErrorKind::NotADirectory => {
            return match target.ancestors().skip(1).find(|a| a.is_dir()) {
                Some(existing) => probe(dir, None, existing),
                // a relative path, which is created in the working folder
                None => probe(dir, None, Path::new(".")),
            };
        }
        Err(_) => OutputError::NotAFolder {
            path: dir.to_path_buf(),
            folder: folder_of(&target).to_path_buf(),
        },
    };
    Err(Error::Output(problem))
}

/// The folder that folder output `dir` names: for a symbolic link to nothing yet, the
/// path it points to (see [`follow_links`]), else `dir` itself.
fn folder_target(dir: &Path) -> Result<PathBuf> {
    if std::fs::metadata(dir).is_err() && is_link(dir) {
        follow_links(dir)
    } else {
        Ok(dir.to_path_buf())
    }
}

/// Where [`write_atomically`] writes an output.
enum Target {
    /// An existing file that is neither a regular file nor a folder (a pipe,
    /// `/dev/stdout`, a device), links resolved: written into.
    Special(PathBuf),
    /// A regular file, existing or new, links resolved: replaced by a temporary file
    /// written in `dir`, which gets the old file's permissions.
    File {
        target: PathBuf,
        dir: PathBuf,
        permissions: Option<std::fs::Permissions>,
        /// Whether the output is a symbolic link (to `target`).
        link: bool,
    },
}

/// Where `path` is written, or why it cannot be: it is a folder, or its folder does not
/// exist or is a file. Looks, never creates or opens.
fn target(path: &Path) -> Result<Target> {
    let metadata = std::fs::metadata(path).ok();
    // Write beside the file a link points to, so the rename replaces that file, or
    // creates it when the link points to no file yet: replacing the link itself would
    // lose it.
    let (target, link) = if metadata.is_some() {
        let target = std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf());
        (target, false)
    } else if is_link(path) {
        let target = follow_links(path)?;
        if names_folder(&target) {
            return Err(Error::Output(OutputError::LinkToFolder {
                path: path.to_path_buf(),
                target,
            }));
        }
        (target, true)
    } else if names_folder(path) {
        // `out.csv/`: no file can have that name (the writer's rename would fail at the
        // end of the run with "not a directory")
        return Err(Error::Output(OutputError::FolderName {
            path: path.to_path_buf(),
        }));
    } else {
        (path.to_path_buf(), false)
    };
    if metadata.as_ref().is_some_and(std::fs::Metadata::is_dir) {
        return Err(Error::Output(OutputError::Folder {
            path: path.to_path_buf(),
        }));
    }
    if metadata.as_ref().is_some_and(|m| !m.is_file()) {
        return Ok(Target::Special(target));
    }
    let dir = folder_of(&target).to_path_buf();
    check_parent(path, link.then_some(target.as_path()), &dir)?;
    Ok(Target::File {
        target,
        dir,
        permissions: metadata.map(|m| m.permissions()),
        // an existing file through a link too: the folder named is the target's
        link: is_link(path),
    })
}

/// The longest chain of symbolic links followed, as Linux's own limit: a longer one is
/// taken for a loop.
const MAX_LINKS: usize = 40;

/// Whether `path` is a symbolic link (which may point to nothing).
fn is_link(path: &Path) -> bool {
    std::fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_symlink())
}

/// The path that the symbolic link `path` leads to: each link of a chain replaced by its
/// target, taken from the link's folder when relative, up to a path that is not a link
/// (for a link that points to nothing, the file to create). Nothing is created or
/// opened; the path is not simplified (`a/../b` is left to the system, which follows a
/// link `a` before `..`). A chain longer than [`MAX_LINKS`] (a loop) is refused.
fn follow_links(path: &Path) -> Result<PathBuf> {
    let mut at = path.to_path_buf();
    for _ in 0..=MAX_LINKS {
        if !is_link(&at) {
            return Ok(at);
        }
        let to = std::fs::read_link(&at).map_err(|e| {
            Error::Output(OutputError::Write {
                path: path.to_path_buf(),
                reason: format!("cannot read the symbolic link {}: {e}", at.display()),
                fix: CHECK_FOLDER,
            })
        })?;
        // an absolute target replaces the folder; a bare name's folder is left unsaid
        at = at.parent().unwrap_or(Path::new("")).join(to);
    }
    Err(Error::Output(OutputError::LinkLoop {
        path: path.to_path_buf(),
    }))
}

/// Whether the text of `path` names a folder: it ends in a separator, or its last part is
/// `.` or `..` (which `Path` would drop or take for a name: `results/` has the file name
/// `results`, yet no file can be created by that name).
fn names_folder(path: &Path) -> bool {
    let text = path.as_os_str().as_encoded_bytes();
    let last = text
        .rsplit(|&b| b.is_ascii() && std::path::is_separator(char::from(b)))
        .next()
        .unwrap_or_default();
    last.is_empty() || last == b"." || last == b".."
}

/// The folder `path` lies in: its parent, or `.` for a bare name.
fn folder_of(path: &Path) -> &Path {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    }
}

/// Refuses an output whose folder `dir` does not exist or is a file, naming the output
/// `path` as given, the folder, and for a symbolic link to no file yet the file it
/// points to, `link`.
fn check_parent(path: &Path, link: Option<&Path>, dir: &Path) -> Result<()> {
    use std::io::ErrorKind::{NotADirectory, NotFound};
    let missing = match std::fs::metadata(dir) {
        Ok(m) if m.is_dir() => return Ok(()),
        Err(e) if e.kind() == NotFound || is_loop(&e) => {
            if let Some(problem) = broken_link(path, dir) {
                return Err(Error::Output(problem));
            }
            if e.kind() != NotFound {
                return Ok(()); // the writer says what failed
            }
            true
        }
        Err(e) if e.kind() != NotADirectory => return Ok(()), // the writer says what failed
        _ => false,
    };
    let (path, folder) = (path.to_path_buf(), dir.to_path_buf());
    let problem = match (link, missing) {
        (None, true) => OutputError::NoFolder { path, folder },
        (None, false) => OutputError::NotAFolder { path, folder },
        (Some(target), true) => OutputError::LinkNoFolder {
            path,
            target: target.to_path_buf(),
            folder,
        },
        (Some(target), false) => OutputError::LinkNotAFolder {
            path,
            target: target.to_path_buf(),
            folder,
        },
    };
    Err(Error::Output(problem))
}

/// Whether `e` says that a path leads through a loop of symbolic links (or a chain longer
/// than the system follows). `ErrorKind::FilesystemLoop` is not stable, so the kind is
/// told by its name, the same on every system.
fn is_loop(e: &std::io::Error) -> bool {
    format!("{:?}", e.kind()) == "FilesystemLoop"
}

/// Why the folder `dir` of output `path`, which cannot be reached, is not there, when a
/// symbolic link on its way is the cause: the first folder on the way (from the root)
/// that is a link leading back to itself ([`OutputError::FolderLinkLoop`]) or to nothing
/// ([`OutputError::FolderLinkMissing`]). `None` when every link on the way leads to a
/// folder (a plain folder is missing).
fn broken_link(path: &Path, dir: &Path) -> Option<OutputError> {
    let mut at = PathBuf::new();
    for part in dir.components() {
        at.push(part);
        match std::fs::metadata(&at) {
            Ok(m) if m.is_dir() => continue,
            // a file (not a folder, told by the caller), or a plain folder missing
            Ok(_) => return None,
            Err(_) if !is_link(&at) => return None,
            Err(e) if is_loop(&e) => {
                return Some(OutputError::FolderLinkLoop {
                    path: path.to_path_buf(),
                    folder: dir.to_path_buf(),
                    link: at,
                });
            }
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                let target = match follow_links(&at) {
                    Ok(target) => target,
                    Err(_) => {
                        return Some(OutputError::FolderLinkLoop {
                            path: path.to_path_buf(),
                            folder: dir.to_path_buf(),
                            link: at,
                        });
                    }
                };
                return Some(OutputError::FolderLinkMissing {
                    path: path.to_path_buf(),
                    folder: dir.to_path_buf(),
                    link: at,
                    target,
                });
            }
            Err(_) => return None,
        }
    }
    None
}

/// "the folder F is a symbolic link that WHAT", or for a folder under the link "the
/// folder F lies under L, a symbolic link that WHAT".
fn through_link(folder: &Path, link: &Path, what: &str) -> String {
    if folder == link {
        format!(
            "the folder {} is a symbolic link that {what}",
            folder.display()
        )
    } else {
        format!(
            "the folder {} lies under {}, a symbolic link that {what}",
            folder.display(),
            link.display()
        )
    }
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

/// Creates the folder `dir` (and its parents) for outputs; an existing folder is kept,
/// and a file there is refused as in [`check_folder`]. A symbolic link to a folder not
/// created yet is kept, and the folder it points to created.
pub fn create_folder(dir: &Path) -> Result<()> {
    check_folder(dir)?;
    std::fs::create_dir_all(folder_target(dir)?).map_err(|e| {
        Error::Output(OutputError::Write {
            path: dir.to_path_buf(),
            reason: format!("cannot create the folder: {e}"),
            fix: write_fix(&e),
        })
    })
}

/// Refuses, before any work, an output that is the same file as an input (the same
/// file under another name or through a link included), and two outputs that are the
/// same file (one would silently replace the other). Outputs that do not exist yet
/// cannot be an input and pass. No file is opened (opening a pipe would wait for its
/// writer).
pub fn refuse_inputs(inputs: &[&Path], outputs: &[&Path]) -> Result<()> {
    let inputs: Vec<(&Path, Option<FileId>)> = inputs.iter().map(|p| (*p, file_id(p))).collect();
    let outputs: Vec<(&Path, Option<FileId>)> = outputs.iter().map(|p| (*p, file_id(p))).collect();
    for (k, (output, id)) in outputs.iter().enumerate() {
        let Some(id) = id else { continue };
        if let Some((input, _)) = inputs.iter().find(|(_, i)| i.as_ref() == Some(id)) {
            return Err(Error::Output(OutputError::OutputIsInput {
                output: output.to_path_buf(),
                input: input.to_path_buf(),
            }));
        }
        if let Some((other, _)) = outputs[..k].iter().find(|(_, i)| i.as_ref() == Some(id)) {
            return Err(Error::Output(OutputError::TwoOutputs {
                first: other.to_path_buf(),
                second: output.to_path_buf(),
            }));
        }
    }
    Ok(())
}

/// Which file a path names, found without opening it.
#[derive(Debug, PartialEq)]
enum FileId {
    /// An existing file: its device and inode, shared by all its names and links.
    #[cfg(unix)]
    Inode(u64, u64),
    /// An existing file: its canonical path (links resolved).
    #[cfg(not(unix))]
    Canonical(PathBuf),
    /// A file not created yet: its folder's canonical path and its name.
    New(PathBuf),
}

/// Whether `a` and `b` name one existing file (under two spellings, a hard or symbolic
/// link), found without opening either; `false` when either does not exist.
///
/// ```
/// # let dir = tempfile::tempdir().unwrap();
/// let a = dir.path().join("run.csv");
/// std::fs::write(&a, "t,q1\n").unwrap();
/// let b = dir.path().join(".").join("run.csv");
/// assert!(robid_runtime::output::same_file(&a, &b));
/// assert!(!robid_runtime::output::same_file(&a, &dir.path().join("other.csv")));
/// ```
pub fn same_file(a: &Path, b: &Path) -> bool {
    a.exists() && b.exists() && file_id(a).is_some_and(|id| file_id(b) == Some(id))
}

/// The [`FileId`] of `path`, or `None` when neither it nor its folder can be resolved
/// (writing there fails later with its own error).
fn file_id(path: &Path) -> Option<FileId> {
    match std::fs::metadata(path) {
        #[cfg(unix)]
        Ok(m) => {
            use std::os::unix::fs::MetadataExt;
            Some(FileId::Inode(m.dev(), m.ino()))
        }
        #[cfg(not(unix))]
        Ok(_) => Some(FileId::Canonical(std::fs::canonicalize(path).ok()?)),
        Err(_) => {
            // a symbolic link to no file yet is the file it would create
            let path = follow_links(path).ok()?;
            Some(FileId::New(
                std::fs::canonicalize(folder_of(&path))
                    .ok()?
                    .join(path.file_name()?),
            ))
        }
    }
}

/// An output cannot be written.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum OutputError {
    /// A file could not be written.
    #[error("{path}: cannot write: {reason}; {fix}")]
    Write {
        /// The file.
        path: PathBuf,
        /// What the writer reported.
        reason: String,
        /// What to do about it ([`CHECK_FOLDER`], or for a full disk or file system
        /// what [`write_fix`] says).
        fix: &'static str,
    },
    /// The output is an existing folder (`-o /tmp`): a file in it was meant.
    #[error("{path}: is a folder; give a file name, e.g. {}", path.join("out").display())]
    Folder {
        /// The output, as given.
        path: PathBuf,
    },
    /// The output names a folder, not a file: it ends in a path separator, `.` or `..`
    /// (`-o out.csv/`), and does not exist.
    #[error(
        "{path}: names a folder (it ends in `/`, `.` or `..`), not a file; give a file name, without the `/` at the end"
    )]
    FolderName {
        /// The output, as given.
        path: PathBuf,
    },
    /// A folder output (files are written into it) is a file (`--plot results.svg`).
    #[error(
        "{path}: is a file, not a folder; give the path of a folder (a missing one is created), or move the file away"
    )]
    FileNotFolder {
        /// The output, as given.
        path: PathBuf,
    },
    /// The folder of the output does not exist (`-o /nonexistent/dir/f.toml`); robid
    /// creates no folders for a file.
    #[error("{path}: the folder {folder} does not exist; create it first")]
    NoFolder {
        /// The output, as given.
        path: PathBuf,
        /// Its folder.
        folder: PathBuf,
    },
    /// The folder of the output exists but takes no new file (`-o /proc/f.csv`, a folder
    /// without write permission, a read-only file system); for a folder output, the
    /// nearest existing folder above it, where it would be created.
    #[error(
        "{path}: cannot create a file in the folder {folder} ({reason}); {}",
        not_writable_fix(reason)
    )]
    NotWritable {
        /// The output, as given.
        path: PathBuf,
        /// The folder that takes no file.
        folder: PathBuf,
        /// Why, as the system says it (`permission denied`).
        reason: String,
    },
    /// The output is a symbolic link to a file (existing or not) in a folder that takes no
    /// new file (`v.txt -> /proc/version`): the writer writes a new file there to replace
    /// or create the file it points to.
    #[error(
        "{path}: is a symbolic link to {target}, which robid would replace (or create) by writing a new file in its folder {folder}, but that folder takes no new file ({reason}); remove the link to write a file in its place, or give another path"
    )]
    LinkNotWritable {
        /// The output, as given.
        path: PathBuf,
        /// The file the link points to, through every link of a chain.
        target: PathBuf,
        /// Its folder.
        folder: PathBuf,
        /// Why, as the system says it (`permission denied`).
        reason: String,
    },
    /// The folder of the output is, or lies under, a symbolic link that leads back to
    /// itself (`loopdir -> loopdir`, `-o loopdir/out.csv`), or a chain of more than the
    /// system follows.
    #[error(
        "{path}: {}; point the link to a folder, or give another path",
        through_link(
            folder,
            link,
            "leads back to itself (a loop of links, or a chain of more than 40)"
        )
    )]
    FolderLinkLoop {
        /// The output, as given.
        path: PathBuf,
        /// Its folder.
        folder: PathBuf,
        /// The link on the way to the folder that loops.
        link: PathBuf,
    },
    /// The folder of the output is, or lies under, a symbolic link to something that does
    /// not exist (`dang -> missing`, `-o dang/out.csv`).
    #[error(
        "{path}: {}; create the folder {}, or point the link to an existing folder",
        through_link(folder, link, &format!("points to {}, which does not exist", target.display())),
        target.display()
    )]
    FolderLinkMissing {
        /// The output, as given.
        path: PathBuf,
        /// Its folder.
        folder: PathBuf,
        /// The link on the way to the folder that points to nothing.
        link: PathBuf,
        /// What it points to, through every link of a chain.
        target: PathBuf,
    },
    /// The folder of the output is a file, or lies under one (`-o notes.txt/f.toml`).
    #[error(
        "{path}: {folder} is not a folder (it, or one above it, is a file); give a path in an existing folder"
    )]
    NotAFolder {
        /// The output, as given.
        path: PathBuf,
        /// Its folder.
        folder: PathBuf,
    },
    /// The output is a symbolic link to a file that does not exist yet (which the writer
    /// would create, keeping the link), in a folder that does not exist.
    #[error(
        "{path}: is a symbolic link to {target}, whose folder {folder} does not exist; create the folder, or remove the link to write a file in its place"
    )]
    LinkNoFolder {
        /// The output, as given.
        path: PathBuf,
        /// The file the link points to, through every link of a chain.
        target: PathBuf,
        /// Its folder.
        folder: PathBuf,
    },
    /// The output is a symbolic link to a file that does not exist yet, in a folder that
    /// is a file or lies under one.
    #[error(
        "{path}: is a symbolic link to {target}, but {folder} is not a folder (it, or one above it, is a file); remove the link to write a file in its place, or point it into a folder"
    )]
    LinkNotAFolder {
        /// The output, as given.
        path: PathBuf,
        /// The file the link points to, through every link of a chain.
        target: PathBuf,
        /// Its folder.
        folder: PathBuf,
    },
    /// The output is a symbolic link to nothing whose target names a folder (it ends in
    /// `/`, or in `/.` or `/..`: `out.csv -> results/`, `results` missing): no file can be
    /// created there.
    #[error(
        "{path}: is a symbolic link to {target}, which names a folder, and that folder does not exist; point the link to a file (or create the folder and give the path of a file in it), or remove the link to write a file in its place"
    )]
    LinkToFolder {
        /// The output, as given.
        path: PathBuf,
        /// What the link points to, through every link of a chain.
        target: PathBuf,
    },
    /// The output is a symbolic link that leads back to itself (`a -> b`, `b -> a`), or
    /// a chain of more than 40 links.
    #[error(
        "{path}: is a symbolic link that leads back to itself (a loop of links, or a chain of more than 40); remove the link, or give another path"
    )]
    LinkLoop {
        /// The output, as given.
        path: PathBuf,
    },
    /// The output is a pipe (`-o /dev/stdout | head -1`) whose reader closed it before
    /// the output was complete: the end of the conversation, not a fault of the path. A
    /// command line ends quietly on it, as on a closed standard output.
    #[error("{path}: output closed early by its reader (a broken pipe)")]
    Closed {
        /// The output, as given.
        path: PathBuf,
    },
    /// Two outputs of one run are the same file.
    #[error(
        "{first} and {second} are the same file, so one output would replace the other; give them different names"
    )]
    TwoOutputs {
        /// The first output, as given.
        first: PathBuf,
        /// The second output, as given.
        second: PathBuf,
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

/// A named pipe `name` made in `dir` by `mkfifo`, for the tests of pipes; `None` where the
/// system has no `mkfifo`.
#[cfg(all(test, unix))]
pub(crate) fn fifo(dir: &std::path::Path, name: &str) -> Option<std::path::PathBuf> {
    let path = dir.join(name);
    let status = std::process::Command::new("mkfifo").arg(&path).status();
    status.is_ok_and(|s| s.success()).then_some(path)
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
        assert!(
            result.unwrap_err().to_string().ends_with(CHECK_FOLDER),
            "an unknown cause points at the folder"
        );
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "old contents\n");
        // no temporary file is left behind
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    }

    #[test]
    fn a_full_disk_says_so_not_that_the_folder_is_wrong() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("data.csv");
        for (kind, fix) in [
            (std::io::ErrorKind::StorageFull, "free space on that disk"),
            (std::io::ErrorKind::QuotaExceeded, "free space on that disk"),
            (std::io::ErrorKind::FileTooLarge, "no file this large"),
            (std::io::ErrorKind::PermissionDenied, CHECK_FOLDER),
        ] {
            let e = write_atomically(&path, |_| Err(kind.into())).unwrap_err();
            let text = e.to_string();
            assert!(text.contains(fix), "{kind:?}: {text}");
            assert_eq!(text.contains(CHECK_FOLDER), fix == CHECK_FOLDER, "{text}");
        }
        assert!(!path.exists());
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

    /// A link to a file that does not exist yet (`w.h -> ../include/q.h`) creates that
    /// file and stays a link, whether its target is absolute or relative (to the link's
    /// folder), and through a chain of links; before, the link was replaced by a file.
    /// The check before the work passes it, and it is the same output as its target.
    #[test]
    #[cfg(unix)]
    fn a_link_to_no_file_yet_creates_its_target_and_is_kept() {
        use std::os::unix::fs::symlink;
        let dir = tempfile::tempdir().unwrap();
        let (here, there) = (dir.path().join("here"), dir.path().join("there"));
        std::fs::create_dir(&here).unwrap();
        std::fs::create_dir(&there).unwrap();
        let absolute = here.join("absolute.h");
        symlink(there.join("a.h"), &absolute).unwrap();
        let relative = here.join("relative.h");
        symlink("../there/r.h", &relative).unwrap();
        // chain.h -> middle.h -> ../there/c.h
        let chain = here.join("chain.h");
        symlink("middle.h", &chain).unwrap();
        symlink(
            Path::new("..").join("there").join("c.h"),
            here.join("middle.h"),
        )
        .unwrap();
        for (link, file) in [(&absolute, "a.h"), (&relative, "r.h"), (&chain, "c.h")] {
            check_file(link).unwrap();
            let fresh = there.join(file);
            assert!(matches!(
                refuse_inputs(&[], &[link, &fresh]),
                Err(Error::Output(OutputError::TwoOutputs { .. }))
            ));
            write_bytes(link, file.as_bytes()).unwrap();
            assert!(is_link(link), "{}", link.display());
            assert_eq!(std::fs::read_to_string(there.join(file)).unwrap(), file);
            // written again: the file is replaced, the link still kept
            write_bytes(link, b"again").unwrap();
            assert!(is_link(link), "{}", link.display());
            assert_eq!(std::fs::read_to_string(there.join(file)).unwrap(), "again");
        }
        // no temporary file left, no file created beside the links
        assert_eq!(std::fs::read_dir(&here).unwrap().count(), 4);
        assert_eq!(std::fs::read_dir(&there).unwrap().count(), 3);
    }

    /// A link to no file yet in a folder that does not exist, or that is a file, is
    /// refused naming the link, the file it points to and the folder, before the work and
    /// by the writer; the link is kept and nothing is created.
    #[test]
    #[cfg(unix)]
    fn a_link_into_no_folder_is_refused() {
        use std::os::unix::fs::symlink;
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        std::fs::write(d.join("notes.txt"), "x").unwrap();
        symlink(d.join("missing").join("q.h"), d.join("missing.h")).unwrap();
        symlink("notes.txt/q.h", d.join("file.h")).unwrap();
        // a chain whose last link points into a missing folder
        symlink("missing.h", d.join("chain.h")).unwrap();
        let cases = [
            (
                "missing.h",
                d.join("missing/q.h"),
                "does not exist; create the folder, or remove the link to write a file in \
                 its place",
            ),
            (
                "file.h",
                d.join("notes.txt/q.h"),
                "is not a folder (it, or one above it, is a file); remove the link to write \
                 a file in its place, or point it into a folder",
            ),
            (
                "chain.h",
                d.join("missing/q.h"),
                "does not exist; create the folder, or remove the link to write a file in \
                 its place",
            ),
        ];
        for (name, target, end) in cases {
            let link = d.join(name);
            let e = write_bytes(&link, b"x").unwrap_err();
            assert!(
                matches!(&e,
                    Error::Output(OutputError::LinkNoFolder { path, target: t, .. }
                        | OutputError::LinkNotAFolder { path, target: t, .. })
                    if *path == link && *t == target),
                "{e:?}"
            );
            let folder = target.parent().unwrap();
            let text = e.to_string();
            let start = format!(
                "{}: is a symbolic link to {}, ",
                link.display(),
                target.display()
            );
            assert!(text.starts_with(&start), "{text}");
            assert!(text.contains(&format!(" {} ", folder.display())), "{text}");
            assert!(text.ends_with(end), "{text}");
            assert_eq!(check_file(&link).unwrap_err().to_string(), text);
            assert!(is_link(&link));
        }
        assert!(!d.join("missing").exists());
        assert_eq!(std::fs::read_to_string(d.join("notes.txt")).unwrap(), "x");
        assert_eq!(std::fs::read_dir(d).unwrap().count(), 4);
    }

    /// A link to nothing whose target names a folder (`out.csv -> results/`, `results`
    /// missing) is refused naming the link and its target, before the work and by the
    /// writer, the link kept and nothing created; it used to pass the check and fail only
    /// when the finished file was renamed onto the target. A folder output through such a
    /// link is still created there.
    #[test]
    #[cfg(unix)]
    fn a_link_to_a_missing_folder_is_refused_as_a_file_output() {
        use std::os::unix::fs::symlink;
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        symlink(d.join("results/"), d.join("out.csv")).unwrap();
        symlink("results/.", d.join("dot.csv")).unwrap();
        symlink("out.csv", d.join("chain.csv")).unwrap();
        for (name, target) in [
            ("out.csv", format!("{}/results/", d.display())),
            ("dot.csv", format!("{}/results/.", d.display())),
            ("chain.csv", format!("{}/results/", d.display())),
        ] {
            let link = d.join(name);
            let e = check_file(&link).unwrap_err();
            assert!(
                matches!(&e, Error::Output(OutputError::LinkToFolder { path, target: t })
                    if *path == link && t.as_os_str() == target.as_str()),
                "{e:?}"
            );
            assert_eq!(
                e.to_string(),
                format!(
                    "{}: is a symbolic link to {target}, which names a folder, and that folder \
                     does not exist; point the link to a file (or create the folder and give \
                     the path of a file in it), or remove the link to write a file in its place",
                    link.display()
                )
            );
            let written = write_bytes(&link, b"x").unwrap_err();
            assert_eq!(written.to_string(), e.to_string());
            assert!(is_link(&link));
        }
        assert_eq!(std::fs::read_dir(d).unwrap().count(), 3);
        // as a folder output, the folder it points to is created, the link kept
        create_folder(&d.join("out.csv")).unwrap();
        assert!(d.join("results").is_dir() && is_link(&d.join("out.csv")));
    }

    /// A loop of links is refused as one, and kept; a link to a folder is a folder.
    #[test]
    #[cfg(unix)]
    fn a_loop_of_links_and_a_link_to_a_folder_are_refused() {
        use std::os::unix::fs::symlink;
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        symlink("b.h", d.join("a.h")).unwrap();
        symlink("a.h", d.join("b.h")).unwrap();
        let link = d.join("a.h");
        let e = write_bytes(&link, b"x").unwrap_err();
        assert!(
            matches!(&e, Error::Output(OutputError::LinkLoop { path }) if *path == link),
            "{e:?}"
        );
        assert_eq!(
            e.to_string(),
            format!(
                "{}: is a symbolic link that leads back to itself (a loop of links, or a chain \
                 of more than 40); remove the link, or give another path",
                link.display()
            )
        );
        assert_eq!(check_file(&link).unwrap_err().to_string(), e.to_string());
        assert!(is_link(&link) && is_link(&d.join("b.h")));
        std::fs::create_dir(d.join("sub")).unwrap();
        symlink("sub", d.join("out")).unwrap();
        let e = write_bytes(&d.join("out"), b"x").unwrap_err();
        assert!(
            matches!(&e, Error::Output(OutputError::Folder { .. })),
            "{e:?}"
        );
        assert!(is_link(&d.join("out")));
        assert_eq!(std::fs::read_dir(d.join("sub")).unwrap().count(), 0);
        assert_eq!(std::fs::read_dir(d).unwrap().count(), 4);
    }

    /// An output that names a folder (`-o out.csv/`) and does not exist is refused before
    /// any work, with the fix; the writer used to fail after it ("Not a directory").
    #[test]
    fn an_output_ending_in_a_separator_is_refused_up_front() {
        let dir = tempfile::tempdir().unwrap();
        for name in ["out.csv/", "new/."] {
            let path = dir.path().join(name);
            let e = check_file(&path).unwrap_err();
            assert!(
                matches!(&e, Error::Output(OutputError::FolderName { .. })),
                "{name}: {e:?}"
            );
            assert!(e.to_string().contains("give a file name"), "{e}");
            assert!(write_bytes(&path, b"x").is_err());
        }
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
        assert!(check_file(&dir.path().join("out.csv")).is_ok());
    }

    /// A folder output (`--plot DIR`) that is a link to a folder not created yet: the
    /// folder it points to is created (with its parents), the link kept, and files are
    /// written into it through the link; before, creating it failed after the work ("File
    /// exists"). A link into a file is refused before the work.
    #[test]
    #[cfg(unix)]
    fn a_link_to_a_folder_not_created_yet_is_created_through() {
        use std::os::unix::fs::symlink;
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        std::fs::create_dir(d.join("runs")).unwrap();
        symlink("runs/today/plots", d.join("plots")).unwrap();
        let plots = d.join("plots");
        check_folder(&plots).unwrap();
        assert!(!d.join("runs/today").exists());
        create_folder(&plots).unwrap();
        assert!(is_link(&plots));
        assert!(d.join("runs/today/plots").is_dir());
        write_bytes(&plots.join("fit_joint1.svg"), b"<svg/>").unwrap();
        assert_eq!(
            std::fs::read_to_string(d.join("runs/today/plots/fit_joint1.svg")).unwrap(),
            "<svg/>"
        );
        // created again: kept as it is
        create_folder(&plots).unwrap();
        std::fs::write(d.join("notes.txt"), "x").unwrap();
        symlink("notes.txt/plots", d.join("into-a-file")).unwrap();
        let e = check_folder(&d.join("into-a-file")).unwrap_err();
        assert!(
            matches!(&e, Error::Output(OutputError::NotAFolder { folder, .. })
                if *folder == d.join("notes.txt")),
            "{e:?}"
        );
        assert_eq!(
            create_folder(&d.join("into-a-file"))
                .unwrap_err()
                .to_string(),
            e.to_string()
        );
    }

    /// A folder is named as one, with a file in it as the fix, not "check that the folder
    /// exists".
    #[test]
    fn a_folder_is_not_a_target() {
        let dir = tempfile::tempdir().unwrap();
        let e = write_bytes(dir.path(), b"x").unwrap_err();
        assert!(
            matches!(&e, Error::Output(OutputError::Folder { path }) if path == dir.path()),
            "{e:?}"
        );
        let expected = format!(
            "{}: is a folder; give a file name, e.g. {}",
            dir.path().display(),
            dir.path().join("out").display()
        );
        assert_eq!(e.to_string(), expected);
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
    }

    /// An output in a folder that does not exist names the output and its folder, never
    /// the temporary file (it used to end "No such file or directory (os error 2) at path
    /// \"/nonexistent/dir/.robid-Z2mU1l.tmp\"; check that the folder exists and is
    /// writable").
    #[test]
    fn a_missing_folder_is_named() {
        let dir = tempfile::tempdir().unwrap();
        let folder = dir.path().join("missing").join("dir");
        let path = folder.join("f.toml");
        let e = write_bytes(&path, b"x").unwrap_err();
        assert!(
            matches!(&e, Error::Output(OutputError::NoFolder { path: p, folder: f })
                if *p == path && *f == folder),
            "{e:?}"
        );
        let expected = format!(
            "{}: the folder {} does not exist; create it first",
            path.display(),
            folder.display()
        );
        assert_eq!(e.to_string(), expected);
        assert!(!dir.path().join("missing").exists());
        // a relative path names the folder as given
        let e = write_bytes(Path::new("robid-no-such-folder/f.csv"), b"x").unwrap_err();
        assert_eq!(
            e.to_string(),
            "robid-no-such-folder/f.csv: the folder robid-no-such-folder does not exist; \
             create it first"
        );
    }

    /// A file where the folder should be is named as not a folder.
    #[test]
    fn a_file_as_the_folder_is_named() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("notes.txt");
        std::fs::write(&file, "x").unwrap();
        for folder in [file.clone(), file.join("sub")] {
            let path = folder.join("f.toml");
            let e = write_bytes(&path, b"x").unwrap_err();
            assert!(
                matches!(&e, Error::Output(OutputError::NotAFolder { folder: f, .. }) if *f == folder),
                "{e:?}"
            );
            let text = e.to_string();
            assert!(text.starts_with(&format!("{}: ", path.display())), "{text}");
            assert!(!text.contains(".robid-"), "{text}");
        }
        assert_eq!(std::fs::read_to_string(&file).unwrap(), "x");
    }

    /// A folder no file can be created in is named, not the temporary file (whoever runs
    /// the test), by the writer and by the checks before the work, and a folder output
    /// there is refused too, existing or to be created.
    #[test]
    #[cfg(target_os = "linux")]
    fn a_folder_that_takes_no_file_is_named() {
        if !Path::new("/proc/self").is_dir() {
            return; // no procfs here
        }
        let path = Path::new("/proc/robid-never-written.csv");
        let e = write_bytes(path, b"x").unwrap_err();
        let text = e.to_string();
        assert_eq!(
            text,
            "/proc/robid-never-written.csv: cannot create a file in the folder /proc (the \
             system refuses new files there, as in /proc and /sys); give a path in a folder \
             you may write into"
        );
        assert_eq!(check_file(path).unwrap_err().to_string(), text);
        for dir in ["/proc", "/proc/robid-never-written/plots"] {
            let e = check_folder(Path::new(dir)).unwrap_err();
            assert!(
                matches!(&e, Error::Output(OutputError::NotWritable { path, folder, .. })
                    if path == Path::new(dir) && folder == Path::new("/proc")),
                "{e:?}"
            );
            assert_eq!(
                create_folder(Path::new(dir)).unwrap_err().to_string(),
                e.to_string()
            );
        }
    }

    /// An output that is a link to a file in /proc, existing or not, names the link, the
    /// file and the folder, with a fix that holds (remove the link, another path): it used
    /// to end in "make this one writable", which /proc cannot be. The link is kept.
    #[test]
    #[cfg(target_os = "linux")]
    fn a_link_into_a_folder_that_takes_no_file_is_named() {
        use std::os::unix::fs::symlink;
        if !Path::new("/proc/version").is_file() {
            return; // no procfs here
        }
        let dir = tempfile::tempdir().unwrap();
        for (name, target) in [
            ("v.txt", "/proc/version"),
            ("new.csv", "/proc/robid-never-written.csv"),
        ] {
            let link = dir.path().join(name);
            symlink(target, &link).unwrap();
            let e = write_bytes(&link, b"x").unwrap_err();
            assert!(
                matches!(&e, Error::Output(OutputError::LinkNotWritable { path, folder, .. })
                    if *path == link && folder == Path::new("/proc")),
                "{e:?}"
            );
            assert_eq!(
                e.to_string(),
                format!(
                    "{}: is a symbolic link to {target}, which robid would replace (or create) \
                     by writing a new file in its folder /proc, but that folder takes no new \
                     file (the system refuses new files there, as in /proc and /sys); remove \
                     the link to write a file in its place, or give another path",
                    link.display()
                )
            );
            assert_eq!(check_file(&link).unwrap_err().to_string(), e.to_string());
            assert!(is_link(&link));
        }
    }

    /// A folder that is a link leading back to itself (`loopdir -> loopdir`) or to nothing
    /// (`dang -> missing`), or that lies under one, is named as such with the link and what
    /// it points to, by the writer, the check before the work and the folder check: they
    /// used to say "cannot create a file in the folder loopdir (filesystem loop ..); .. make
    /// this one writable" and "the folder dang does not exist; create it first" (it is a
    /// link). Nothing is created.
    #[test]
    #[cfg(unix)]
    fn a_folder_through_a_broken_link_is_named() {
        use std::os::unix::fs::symlink;
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        symlink("loopdir", d.join("loopdir")).unwrap();
        symlink("missing", d.join("dang")).unwrap();
        let (looping, dangling) = (d.join("loopdir"), d.join("dang"));
        let loop_text = |folder: &Path, under: bool| {
            let place = if under {
                format!(
                    "the folder {} lies under {}, a symbolic link",
                    folder.display(),
                    looping.display()
                )
            } else {
                format!("the folder {} is a symbolic link", looping.display())
            };
            format!(
                "{place} that leads back to itself (a loop of links, or a chain of more than \
                 40); point the link to a folder, or give another path"
            )
        };
        let missing_text = |folder: &Path, under: bool| {
            let place = if under {
                format!(
                    "the folder {} lies under {}, a symbolic link",
                    folder.display(),
                    dangling.display()
                )
            } else {
                format!("the folder {} is a symbolic link", dangling.display())
            };
            format!(
                "{place} that points to {}, which does not exist; create the folder {}, or \
                 point the link to an existing folder",
                d.join("missing").display(),
                d.join("missing").display()
            )
        };
        for (folder, under, text) in [
            (looping.clone(), false, loop_text(&looping, false)),
            (
                looping.join("sub"),
                true,
                loop_text(&looping.join("sub"), true),
            ),
            (dangling.clone(), false, missing_text(&dangling, false)),
            (
                dangling.join("sub"),
                true,
                missing_text(&dangling.join("sub"), true),
            ),
        ] {
            let out = folder.join("out.csv");
            let e = write_bytes(&out, b"x").unwrap_err();
            assert_eq!(
                e.to_string(),
                format!("{}: {text}", out.display()),
                "{under}"
            );
            assert!(
                matches!(
                    &e,
                    Error::Output(
                        OutputError::FolderLinkLoop { .. } | OutputError::FolderLinkMissing { .. }
                    )
                ),
                "{e:?}"
            );
            assert_eq!(check_file(&out).unwrap_err().to_string(), e.to_string());
            if under {
                // a folder output under the link: refused the same way, not created
                let e = check_folder(&folder).unwrap_err();
                assert_eq!(e.to_string(), format!("{}: {text}", folder.display()));
                assert_eq!(
                    create_folder(&folder).unwrap_err().to_string(),
                    e.to_string()
                );
            }
        }
        assert_eq!(std::fs::read_dir(d).unwrap().count(), 2);
    }

    /// Temporary files that killed runs left in an output's folder break no later write
    /// (each write draws a new name), and those unchanged for a day are removed by the
    /// next write there, once per process; nothing that is not unmistakably one is
    /// touched: another name, a fresh one (a run may be writing it), a folder or a link
    /// of that name. They used to stay for ever.
    #[test]
    #[cfg(unix)]
    fn temporary_files_left_by_killed_runs_are_removed_when_stale() {
        use std::os::unix::fs::symlink;
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        let old = std::time::SystemTime::now() - STALE_TEMPORARY * 2;
        let age = |path: &Path| {
            std::fs::File::open(path)
                .unwrap()
                .set_modified(old)
                .unwrap();
        };
        let stale = [".robid-AbC123.tmp", ".robid-zzzzzz.tmp"];
        let kept = [
            ".robid-AbC12.tmp",
            ".robid-AbC1234.tmp",
            ".robid-AbC-23.tmp",
            "robid-AbC123.tmp",
            ".robid-AbC123.tmp.csv",
        ];
        for name in stale.iter().chain(&kept) {
            std::fs::write(d.join(name), "left").unwrap();
            age(&d.join(name));
        }
        std::fs::write(d.join(".robid-FrEsH1.tmp"), "being written").unwrap();
        std::fs::create_dir(d.join(".robid-FoLdEr.tmp")).unwrap();
        age(&d.join(".robid-FoLdEr.tmp"));
        symlink("robid-AbC123.tmp", d.join(".robid-LiNk00.tmp")).unwrap();
        // a second name of a user's file
        std::fs::hard_link(d.join("robid-AbC123.tmp"), d.join(".robid-HaRd00.tmp")).unwrap();
        let out = d.join("out.csv");
        write_bytes(&out, b"x").unwrap();
        assert_eq!(std::fs::read_to_string(&out).unwrap(), "x");
        for name in stale {
            assert!(!d.join(name).exists(), "{name} is still there");
        }
        for name in kept.iter().chain(&[
            ".robid-FrEsH1.tmp",
            ".robid-FoLdEr.tmp",
            ".robid-LiNk00.tmp",
            ".robid-HaRd00.tmp",
        ]) {
            assert!(
                std::fs::symlink_metadata(d.join(name)).is_ok(),
                "{name} was removed"
            );
        }
        // once per process: a stale file left now stays until the next run
        std::fs::write(d.join(".robid-later1.tmp"), "left").unwrap();
        age(&d.join(".robid-later1.tmp"));
        write_bytes(&out, b"y").unwrap();
        assert!(d.join(".robid-later1.tmp").exists());
        assert_eq!(std::fs::read_to_string(&out).unwrap(), "y");
    }

    /// A folder robid may not write into is named, not the temporary file.
    #[test]
    #[cfg(unix)]
    fn a_folder_without_permission_is_named() {
        use std::os::unix::fs::PermissionsExt;
        let dir = tempfile::tempdir().unwrap();
        let locked = dir.path().join("locked");
        std::fs::create_dir(&locked).unwrap();
        std::fs::set_permissions(&locked, std::fs::Permissions::from_mode(0o555)).unwrap();
        let path = locked.join("f.csv");
        let result = write_bytes(&path, b"x");
        let checked = check_file(&path);
        let folder = check_folder(&locked.join("plots"));
        let left = std::fs::read_dir(&locked).unwrap().count();
        std::fs::set_permissions(&locked, std::fs::Permissions::from_mode(0o755)).unwrap();
        if result.is_ok() {
            return; // run as root: every folder is writable
        }
        let text = result.unwrap_err().to_string();
        let expected = format!(
            "{}: cannot create a file in the folder {} (permission denied); give a path in a \
             folder you may write into, or make this one writable",
            path.display(),
            locked.display()
        );
        assert_eq!(text, expected);
        assert_eq!(checked.unwrap_err().to_string(), expected);
        assert!(
            matches!(&folder, Err(Error::Output(OutputError::NotWritable { folder, .. }))
                if *folder == locked),
            "{folder:?}"
        );
        assert_eq!(left, 0);
    }

    /// The check before the work refuses what the writer refuses, with the same message,
    /// and creates nothing.
    #[test]
    fn the_check_before_the_work_gives_the_writers_message() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("notes.txt");
        std::fs::write(&file, "x").unwrap();
        let bad = [
            dir.path().to_path_buf(),
            dir.path().join("missing/dir/f.csv"),
            file.join("f.csv"),
            file.join("sub/f.csv"),
        ];
        for path in &bad {
            let before = check_file(path).unwrap_err().to_string();
            let at_write = write_bytes(path, b"x").unwrap_err().to_string();
            assert_eq!(before, at_write, "{}", path.display());
        }
        for good in [dir.path().join("new.csv"), file.clone()] {
            check_file(&good).unwrap();
        }
        // the check of the folder leaves nothing in it
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
        #[cfg(unix)]
        check_file(Path::new("/dev/null")).unwrap();
        assert!(!dir.path().join("missing").exists());
        assert!(!dir.path().join("new.csv").exists());
        assert_eq!(std::fs::read_to_string(&file).unwrap(), "x");
    }

    /// A folder output may be missing (it is created with its parents) but not a file or
    /// under one; the check creates nothing, and `create_folder` says the same.
    #[test]
    fn a_folder_output_is_checked_before_the_work() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("plots.svg");
        std::fs::write(&file, "x").unwrap();
        check_folder(dir.path()).unwrap();
        check_folder(&dir.path().join("new/plots")).unwrap();
        assert!(!dir.path().join("new").exists());
        let e = check_folder(&file).unwrap_err();
        assert!(
            matches!(&e, Error::Output(OutputError::FileNotFolder { path }) if *path == file),
            "{e:?}"
        );
        assert_eq!(
            e.to_string(),
            format!(
                "{}: is a file, not a folder; give the path of a folder (a missing one is \
                 created), or move the file away",
                file.display()
            )
        );
        assert_eq!(create_folder(&file).unwrap_err().to_string(), e.to_string());
        for under in [file.join("sub"), file.join("a/b")] {
            let e = check_folder(&under).unwrap_err();
            assert!(
                matches!(&e, Error::Output(OutputError::NotAFolder { .. })),
                "{e:?}"
            );
            assert_eq!(
                create_folder(&under).unwrap_err().to_string(),
                e.to_string()
            );
        }
        assert_eq!(std::fs::read_to_string(&file).unwrap(), "x");
        create_folder(&dir.path().join("new/plots")).unwrap();
        assert!(dir.path().join("new/plots").is_dir());
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

    /// Two outputs on one file are refused whether the file exists or not, under any
    /// spelling; distinct outputs pass.
    #[test]
    fn two_outputs_on_one_file_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        let new = dir.path().join("report.html");
        let same_new = dir.path().join(".").join("report.html");
        let other = dir.path().join("result.json");
        let two = |a: &Path, b: &Path| refuse_inputs(&[], &[a, b]);
        assert!(matches!(
            two(&new, &same_new),
            Err(Error::Output(OutputError::TwoOutputs { .. }))
        ));
        assert!(two(&new, &other).is_ok());
        // the same name in two folders is two files
        for sub in ["a", "b"] {
            std::fs::create_dir(dir.path().join(sub)).unwrap();
        }
        let (a, b) = (dir.path().join("a/r.csv"), dir.path().join("b/r.csv"));
        assert!(two(&a, &b).is_ok());
        // a bare name is a file of the working folder, as `./` and the name
        let bare = Path::new("robid-test-never-written.out");
        assert!(two(bare, &Path::new(".").join(bare)).is_err());
        std::fs::write(&new, "x").unwrap();
        assert!(two(&same_new, &new).is_err());
        assert!(two(&new, &other).is_ok());
    }

    /// A pipe whose reader has gone is an output closed early, not a folder to check.
    #[test]
    #[cfg(unix)]
    fn a_pipe_closed_by_its_reader_is_an_output_closed_early() {
        let dir = tempfile::tempdir().unwrap();
        let Some(fifo) = fifo(dir.path(), "out.fifo") else {
            return; // no mkfifo on this system
        };
        // a reader that takes one byte and closes the pipe; the Rust runtime ignores
        // SIGPIPE, so the writer sees EPIPE
        let reader = fifo.clone();
        let read = std::thread::spawn(move || {
            use std::io::Read;
            let mut byte = [0u8; 1];
            let mut f = std::fs::File::open(reader).unwrap();
            f.read_exact(&mut byte).unwrap();
        });
        let e = write_atomically(&fifo, |w| {
            // more than a pipe's buffer, written until the reader has gone
            let line = [b'x'; 4096];
            for _ in 0..100_000 {
                w.write_all(&line)?;
            }
            Ok(())
        })
        .unwrap_err();
        read.join().unwrap();
        assert!(
            matches!(&e, Error::Output(OutputError::Closed { path }) if *path == fifo),
            "{e}"
        );
        let text = e.to_string();
        assert!(
            text.ends_with("output closed early by its reader (a broken pipe)"),
            "{text}"
        );
        assert!(!text.contains("folder"), "{text}");
    }

    /// A pipe is written into, not replaced, and never opened for reading: checking it
    /// against the inputs does not wait for a writer.
    #[test]
    #[cfg(unix)]
    fn a_pipe_is_written_into() {
        let dir = tempfile::tempdir().unwrap();
        let Some(fifo) = fifo(dir.path(), "out.fifo") else {
            return; // no mkfifo on this system
        };
        let input = dir.path().join("in.toml");
        std::fs::write(&input, "x").unwrap();
        refuse_inputs(&[&input], &[&fifo]).unwrap();
        let (sent, read) = std::sync::mpsc::channel();
        let reader = fifo.clone();
        std::thread::spawn(move || sent.send(std::fs::read_to_string(reader).unwrap()));
        write_bytes(&fifo, b"through the pipe").unwrap();
        // a writer that never opens the pipe fails the test instead of hanging it
        let text = read.recv_timeout(std::time::Duration::from_secs(20));
        assert_eq!(text.as_deref(), Ok("through the pipe"));
        let kind = std::fs::symlink_metadata(&fifo).unwrap().file_type();
        assert!(std::os::unix::fs::FileTypeExt::is_fifo(&kind));
    }

    /// A write that fails after some rows sends nothing into a pipe (its reader got the
    /// rows before the refused one, then the error), and its reader gets the end of the
    /// text instead of waiting for a writer; without a reader the failure does not wait.
    #[test]
    #[cfg(unix)]
    fn a_failed_write_sends_nothing_into_a_pipe() {
        let dir = tempfile::tempdir().unwrap();
        let Some(fifo) = fifo(dir.path(), "out.fifo") else {
            return; // no mkfifo on this system
        };
        let failing = |w: &mut dyn Write| {
            // more than the writer's buffer and a pipe's, then the refusal
            for _ in 0..10_000 {
                w.write_all(b"1.0,2.0,3.0\n")?;
            }
            Err(std::io::Error::other("row 10001 refused"))
        };
        let (sent, read) = std::sync::mpsc::channel();
        let reader = fifo.clone();
        std::thread::spawn(move || sent.send(std::fs::read_to_string(reader).unwrap()));
        let e = write_atomically(&fifo, failing).unwrap_err();
        assert!(e.to_string().contains("row 10001 refused"), "{e}");
        // a reader that came to the pipe after the failure is let go the same way
        let mut text = read.recv_timeout(std::time::Duration::from_millis(500));
        for _ in 0..40 {
            if text.is_ok() {
                break;
            }
            close_unwritten(&fifo);
            text = read.recv_timeout(std::time::Duration::from_millis(500));
        }
        assert_eq!(text.as_deref(), Ok(""));
        // no reader: the failure returns at once
        assert!(write_atomically(&fifo, failing).is_err());
    }
}
