//! The files `robid` writes: every output goes through `robid_runtime::output` (a
//! temporary file beside the target, renamed into place when complete), so a failed or
//! killed run leaves an existing file exactly as it was; and an output that is the same
//! file as an input of the run (the same path, another spelling of it, a hard or
//! symbolic link) is refused before any work starts, and so is an output its writer would
//! refuse (an existing folder, a missing folder, a path through a file, a folder that
//! takes no new file: no permission, a read-only file system), with the writer's message:
//! a long run does not end in that error. The writer checks again.

use std::path::{Path, PathBuf};

use robid_runtime::output::{check_file, check_folder, refuse_inputs, write_bytes};
use robid_runtime::{Error as RuntimeError, OutputError};

use super::Error;

/// Refuses, before any work, every file output that is the same file as one of the
/// inputs or as another output, or that cannot be written where it is given. Each output
/// comes with the flag that names it (`("--json", path)`), for the message when two are
/// one file.
pub(crate) fn refuse(inputs: &[&Path], outputs: &[(&str, &Path)]) -> Result<(), Error> {
    refuse_with_folders(inputs, outputs, &[])
}

/// [`refuse`], with folder outputs too: `(flag, folder)`, a folder that files are
/// written into (`identify --plot`), created if missing, refused when it is a file, lies
/// under one, or takes no new file (or, when missing, the folder it would be created in).
/// A file output directly in a missing folder output (`--report plots/report.html` with
/// `--plot plots`) is written after that folder is created.
pub(crate) fn refuse_with_folders(
    inputs: &[&Path],
    outputs: &[(&str, &Path)],
    folders: &[(&str, &Path)],
) -> Result<(), Error> {
    let mut all: Vec<(&str, &Path)> = outputs.to_vec();
    all.extend(folders);
    distinct(inputs, &all)?;
    let in_new_folder = |path: &Path| {
        folders.iter().any(|(_, dir)| {
            !dir.exists()
                && path
                    .parent()
                    .is_some_and(|parent| parent.components().eq(dir.components()))
        })
    };
    for (_, path) in outputs {
        if !in_new_folder(path) {
            check_file(path)?;
        }
    }
    for (flag, dir) in folders {
        check_folder(dir).map_err(|e| match e {
            RuntimeError::Output(OutputError::FileNotFolder { path }) => RuntimeError::Argument {
                flag: flag.to_string(),
                problem: format!(
                    "{} is a file, but {flag} takes a folder to write its files into (a \
                     missing one is created); give the path of a folder, or move the file away",
                    path.display()
                ),
            },
            // `--plot /dev/null`: not a file that could be moved away
            RuntimeError::Output(OutputError::SpecialNotFolder { path, what }) => {
                RuntimeError::Argument {
                    flag: flag.to_string(),
                    problem: format!(
                        "{} is {what}, not a folder, but {flag} takes a folder to write its \
                         files into (a missing one is created); give the path of a folder",
                        path.display()
                    ),
                }
            }
            e => e,
        })?;
    }
    Ok(())
}

/// Refuses an output that is one of the inputs, or the same file as another output
/// (`(flag, path)`: the message names both flags), without checking that they can be
/// written: `identify --plot`'s files, in a folder that may not exist yet.
pub(crate) fn distinct(inputs: &[&Path], all: &[(&str, &Path)]) -> Result<(), Error> {
    let paths: Vec<&Path> = all.iter().map(|(_, p)| *p).collect();
    refuse_inputs(inputs, &paths).map_err(|e| match e {
        RuntimeError::Output(OutputError::TwoOutputs { first, second }) => {
            // which two: the first pair the same check refuses
            let pair = (0..all.len())
                .flat_map(|j| (0..j).map(move |i| (i, j)))
                .find(|&(i, j)| refuse_inputs(&[], &[all[i].1, all[j].1]).is_err());
            let (a, b) = pair.map_or(("an output", "another"), |(i, j)| (all[i].0, all[j].0));
            let named = if first == second {
                first.display().to_string()
            } else {
                format!("{} and {}", first.display(), second.display())
            };
            format!(
                "{a} and {b} name the same file ({named}), so one output would replace the \
                 other; give them different names"
            )
            .into()
        }
        e => Error::from(e),
    })?;
    Ok(())
}

/// Writes `text` to `path` atomically.
pub(crate) fn write(path: &Path, text: &str) -> Result<(), Error> {
    Ok(write_bytes(path, text.as_bytes())?)
}

/// Refuses, before any work, a file of fixed name (`files`, which `owner` writes into its
/// folder) that cannot be written where it would go: an existing folder of that name, a
/// folder that takes no new file. The names cannot be chosen, so the fix is to move the
/// folder away (it said "give a file name" after writing the files before it), or to
/// make a file there that the user may not write writable, or move it away. Nothing
/// is checked in a folder that does not exist yet: it is created empty.
pub(crate) fn check_named_files(files: &[PathBuf], owner: &str) -> Result<(), Error> {
    for path in files {
        if !path.parent().is_some_and(Path::is_dir) {
            continue;
        }
        check_file(path).map_err(|e| match e {
            RuntimeError::Output(OutputError::Folder { path }) => Error::from(format!(
                "{}: is a folder, where {owner} writes a file of that name; move or rename \
                 the folder, or write into another folder",
                path.display()
            )),
            // no other path can be given either
            RuntimeError::Output(OutputError::FileNotWritable { path }) => Error::from(format!(
                "{}: the file is not writable (read-only or another user's), and {owner} \
                 writes a file of that name; make it writable, or move it away",
                path.display()
            )),
            e => e.into(),
        })?;
    }
    Ok(())
}

/// The files of a `--plot` folder named as this run names its plots (`fit_joint1.svg`,
/// `validation2_joint3.svg`) that it does not write (`plots`): an earlier run's, which
/// would be read as this one's beside its own (a validation plot left by a run with
/// `--validate`). Empty when the folder does not exist or cannot be read.
pub(crate) fn stale_plots(dir: &Path, plots: &[PathBuf]) -> Vec<PathBuf> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    let ours = |name: &str| {
        let Some((prefix, rest)) = name.split_once("_joint") else {
            return false;
        };
        let numbered = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
        let prefix_ok = prefix == "fit" || prefix.strip_prefix("validation").is_some_and(numbered);
        prefix_ok && rest.strip_suffix(".svg").is_some_and(numbered)
    };
    let mut stale: Vec<PathBuf> = entries
        .filter_map(|e| e.ok())
        .map(|e| e.path())
        .filter(|p| p.file_name().and_then(|n| n.to_str()).is_some_and(ours))
        .filter(|p| p.is_file() && !plots.iter().any(|q| q.file_name() == p.file_name()))
        .collect();
    stale.sort();
    stale
}

/// The files `robid_runtime::report::plot_torques` writes into `dir` for each prefix:
/// `{prefix}_joint{j}.svg`, j = 1..=dof.
pub(crate) fn plot_files(dir: &Path, prefixes: &[String], dof: usize) -> Vec<PathBuf> {
    prefixes
        .iter()
        .flat_map(|p| (1..=dof).map(move |j| dir.join(format!("{p}_joint{j}.svg"))))
        .collect()
}
