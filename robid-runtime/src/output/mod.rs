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
//! folder, a folder that takes no new file, a name too long for it, a file the user may
//! not write, `-`) is refused before a long run rather than after it. A target that is
//! not a
//! regular file (a pipe, `/dev/stdout`, a terminal, a device) is written into directly:
//! it cannot be replaced, and replacing it would destroy it. Inside [`together`] the
//! renames wait until the whole run has succeeded, so that a run's several outputs change
//! together or not at all.
//!
//! ```
//! # let dir = tempfile::tempdir().unwrap();
//! let path = dir.path().join("out.csv");
//! robid_runtime::output::write_bytes(&path, b"t,q1\n0,0\n").unwrap();
//! assert_eq!(std::fs::read_to_string(&path).unwrap(), "t,q1\n0,0\n");
//! ```

mod together;

pub use together::{place_held, together};

use std::io::Write;
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};

/// Writes `path` atomically: `write` fills a temporary file beside `path`, which
/// replaces `path` (keeping its permissions) only when `write` and the flush succeed.
///
/// A symbolic link is followed, so the file it points to is replaced and the link
/// kept. What [`check_file`] refuses, the writer refuses before calling `write` (an
/// existing file it may not write is not replaced, as a shell's `>` would not). On any
/// error the temporary file is removed and `path` is left untouched. After a
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
    let (target, dir, metadata, link) = match target(path)? {
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
            metadata,
            link,
        } => (target, dir, metadata, link),
    };
    // what would make the rename at the end fail (a name too long for the folder, a file
    // the user may not replace) is refused before anything is written
    probe_file(
        path,
        link.then_some(target.as_path()),
        &target,
        &dir,
        metadata.as_deref(),
    )?;
    let existing = metadata.map(|m| m.permissions());
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
    together::place(together::Complete {
        temp,
        target,
        path: path.to_path_buf(),
        #[cfg(unix)]
        owner,
    })
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
/// ([`OutputError::FolderLinkLoop`], [`OutputError::FolderLinkMissing`]); and what would
/// make the writer's rename at the end fail: a file name too long for the folder's file
/// system ([`OutputError::NameTooLong`]), an existing file this user may not write
/// ([`OutputError::FileNotWritable`]) or, in a shared folder with the sticky bit
/// (`/tmp`), another user's file ([`OutputError::SharedFolder`]). `-` is refused
/// ([`OutputError::Dash`]): it is not standard output here. A pipe, `/dev/stdout` or
/// another special file passes. The target is never created, and an existing one is
/// opened for writing only to see whether it can be (neither truncated nor written);
/// whether the folder takes the file is tried by creating a temporary file in it with a
/// name as long as the target's, removed at once. The writer checks again (the folder
/// may change meanwhile).
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
            dir,
            target,
            link,
            metadata,
        } => probe_file(
            path,
            link.then_some(target.as_path()),
            &target,
            &dir,
            metadata.as_deref(),
        ),
    }
}

/// The length in bytes of the name of a temporary file of robid's (`.robid-XXXXXX.tmp`).
const TEMPORARY_NAME_LEN: usize = 17;

/// Refuses file output `path`, written as `target` in `dir`, when the writer's rename at
/// the end would fail: no file can be created in `dir` ([`not_writable`]); the target's
/// name is too long for the folder's file system ([`OutputError::NameTooLong`]: the
/// temporary file tried has a name of the same length in bytes, so the system's own
/// limit answers); or the existing target (`existing`, its metadata) may not be replaced
/// by this user ([`replaceable`]). `link` is the file that `path`, a symbolic link,
/// points to. The temporary file is removed at once.
fn probe_file(
    path: &Path,
    link: Option<&Path>,
    target: &Path,
    dir: &Path,
    existing: Option<&std::fs::Metadata>,
) -> Result<()> {
    let length = target.file_name().map_or(0, |n| n.len());
    let suffix = format!(
        "{}.tmp",
        "x".repeat(length.saturating_sub(TEMPORARY_NAME_LEN))
    );
    let temp = tempfile::Builder::new()
        .prefix(".robid-")
        .suffix(&suffix)
        .tempfile_in(dir)
        .map_err(|e| {
            if e.kind() == std::io::ErrorKind::InvalidFilename {
                Error::Output(OutputError::NameTooLong {
                    path: path.to_path_buf(),
                    bytes: length,
                    folder: dir.to_path_buf(),
                })
            } else {
                not_writable(path, link, dir, &e)
            }
        })?;
    #[cfg(unix)]
    let owner = {
        use std::os::unix::fs::MetadataExt;
        temp.as_file().metadata().ok().map(|m| m.uid())
    };
    #[cfg(not(unix))]
    let owner = None;
    // removed now, not at the end of the run; a failure to remove it is not the output's
    temp.close().ok();
    match existing {
        Some(existing) => replaceable(path, target, dir, existing, owner),
        None => Ok(()),
    }
}

/// Refuses the existing regular file `target` (output `path`, in `dir`) that this user
/// may not replace, as a shell's `>` would refuse it: one that cannot be opened for
/// writing (read-only, or another user's without write permission:
/// [`OutputError::FileNotWritable`]; it is opened without being created or truncated,
/// and closed at once), or another user's file in a shared folder with the sticky bit
/// (`/tmp`), which only its owner may rename over ([`OutputError::SharedFolder`]).
/// `owner` is the user id of a file this run created in `dir` (root, 0, may replace
/// anything).
fn replaceable(
    path: &Path,
    target: &Path,
    dir: &Path,
    existing: &std::fs::Metadata,
    owner: Option<u32>,
) -> Result<()> {
    if !existing.is_file() {
        return Ok(());
    }
    let opened = std::fs::OpenOptions::new().write(true).open(target);
    if opened.is_err_and(|e| e.kind() == std::io::ErrorKind::PermissionDenied) {
        return Err(Error::Output(OutputError::FileNotWritable {
            path: path.to_path_buf(),
        }));
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        let shared = std::fs::metadata(dir).is_ok_and(|folder| {
            folder.mode() & 0o1000 != 0
                && owner.is_some_and(|o| o != 0 && o != existing.uid() && o != folder.uid())
        });
        if shared {
            return Err(Error::Output(OutputError::SharedFolder {
                path: path.to_path_buf(),
                folder: dir.to_path_buf(),
            }));
        }
    }
    #[cfg(not(unix))]
    let _ = (dir, owner);
    Ok(())
}

/// Refuses output `path` when no file can be created in `dir`, as the writer would find:
/// a temporary file is created there and removed. `link` is the file that `path`, a
/// symbolic link, points to.
fn probe_folder(path: &Path, link: Option<&Path>, dir: &Path) -> Result<()> {
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

/// The fix for a name too long for its file system (`ENAMETOOLONG`).
pub const SHORTER_NAME: &str =
    "give a shorter name (most file systems take at most 255 bytes in a file name)";

/// The fix for a write that failed with `e`: a full disk or quota has nothing to do with
/// the folder (it told `/dev/full`'s "No space left on device" to check that the folder
/// is writable), nor has a name too long for the file system ([`SHORTER_NAME`]; it said
/// to check that the folder exists and is writable).
pub fn write_fix(e: &std::io::Error) -> &'static str {
    use std::io::ErrorKind;
    match e.kind() {
        ErrorKind::StorageFull | ErrorKind::QuotaExceeded => {
            "free space on that disk, or write to another one"
        }
        ErrorKind::FileTooLarge => "its file system takes no file this large: write to another",
        // ENAMETOOLONG on Unix: the folder is not the problem
        ErrorKind::InvalidFilename => SHORTER_NAME,
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
        Ok(m) if m.is_dir() => return probe_folder(dir, None, &target),
        Ok(m) if m.is_file() => OutputError::FileNotFolder {
            path: dir.to_path_buf(),
        },
        Ok(m) => OutputError::SpecialNotFolder {
            path: dir.to_path_buf(),
            what: special_kind(&m),
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
                Some(existing) => probe_folder(dir, None, existing),
                // a relative path, which is created in the working folder
                None => probe_folder(dir, None, Path::new(".")),
            };
        }
        Err(_) => OutputError::NotAFolder {
            path: dir.to_path_buf(),
            folder: folder_of(&target).to_path_buf(),
        },
    };
    Err(Error::Output(problem))
}

/// What a file that is neither a regular file nor a folder is, for a message: "a device"
/// (`/dev/null`), "a named pipe", "a socket".
pub fn special_kind(m: &std::fs::Metadata) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        let t = m.file_type();
        if t.is_char_device() || t.is_block_device() {
            return "a device";
        }
        if t.is_fifo() {
            return "a named pipe";
        }
        if t.is_socket() {
            return "a socket";
        }
    }
    let _ = m;
    "neither a regular file nor a folder"
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
        /// The existing file's metadata (its permissions are kept), `None` for a new one.
        metadata: Option<Box<std::fs::Metadata>>,
        /// Whether the output is a symbolic link (to `target`).
        link: bool,
    },
}

/// Where `path` is written, or why it cannot be: it is a folder, or its folder does not
/// exist or is a file. Looks, never creates or opens.
fn target(path: &Path) -> Result<Target> {
    // `-` is standard output for many tools, but robid would write a file named `-` (which
    // a later `--states -` then read)
    if path.as_os_str() == "-" {
        return Err(Error::Output(OutputError::Dash {
            path: path.to_path_buf(),
        }));
    }
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
        metadata: metadata.map(Box::new),
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
    /// A folder output is an existing file that is not a regular file (`--plot
    /// /dev/null`): a device, a named pipe, a socket.
    #[error(
        "{path}: is {what}, not a folder; give the path of a folder (a missing one is created)"
    )]
    SpecialNotFolder {
        /// The output, as given.
        path: PathBuf,
        /// What it is ([`special_kind`]).
        what: &'static str,
    },
    /// The output is `-` (`-o -`), which many tools take for standard output; robid takes
    /// it for a file named `-` nowhere, so that a file of that name is not written (and
    /// then read by a later `--states -`) without a word.
    #[error(
        "{path}: robid does not take `-` for standard output, and would write a file named `-`; write ./- for a file of that name, or /dev/stdout for standard output"
    )]
    Dash {
        /// The output, as given (`-`).
        path: PathBuf,
    },
    /// The output's file name is longer than the file system of its folder takes (255
    /// bytes on most): the rename at the end of the run would fail.
    #[error(
        "{path}: the file name ({bytes} bytes) is too long for the file system of the folder {folder}; {}",
        SHORTER_NAME
    )]
    NameTooLong {
        /// The output, as given.
        path: PathBuf,
        /// The length of its file name (of the file a link points to), in bytes.
        bytes: usize,
        /// Its folder.
        folder: PathBuf,
    },
    /// The output is an existing file that this user may not write (read-only, or
    /// another user's): replacing it would do what a shell's `>` refuses.
    #[error(
        "{path}: the file is not writable (read-only or another user's); make it writable or give another path"
    )]
    FileNotWritable {
        /// The output, as given.
        path: PathBuf,
    },
    /// The output is another user's file in a folder with the sticky bit (`/tmp`), where
    /// only the file's owner (or the folder's) may replace it.
    #[error(
        "{path}: is another user's file in {folder}, a shared folder (sticky, as /tmp) where only its owner may replace it; give another path"
    )]
    SharedFolder {
        /// The output, as given.
        path: PathBuf,
        /// Its folder.
        folder: PathBuf,
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
mod tests;
