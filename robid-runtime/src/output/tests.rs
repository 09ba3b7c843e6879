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

/// A file name too long for the folder's file system (256 bytes; ext4 and tmpfs take
/// 255) is refused by the check before the work and by the writer, naming the cause and
/// the fix, and a run that writes it beside another output leaves that output as it was.
/// The check created a temporary file of a short name, which passed, and the run failed
/// at the rename with "check that the folder exists and is writable" after the other
/// output was replaced.
#[test]
#[cfg(target_os = "linux")]
fn a_name_too_long_for_the_folder_is_refused_before_the_work() {
    let dir = tempfile::tempdir().unwrap();
    let long = dir.path().join(format!("{}.html", "a".repeat(256)));
    let expected = format!(
        "{}: the file name (261 bytes) is too long for the file system of the folder {}; give \
         a shorter name (most file systems take at most 255 bytes in a file name)",
        long.display(),
        dir.path().display()
    );
    assert_eq!(check_file(&long).unwrap_err().to_string(), expected);
    let fit = dir.path().join("fit.json");
    std::fs::write(&fit, "old").unwrap();
    let failed = together(|| {
        write_bytes(&fit, b"new")?;
        write_bytes(&long, b"<html>")
    });
    assert_eq!(failed.unwrap_err().to_string(), expected);
    assert_eq!(std::fs::read_to_string(&fit).unwrap(), "old");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    // a name of 255 bytes is taken
    let longest = dir.path().join("b".repeat(255));
    check_file(&longest).unwrap();
    write_bytes(&longest, b"x").unwrap();
    assert_eq!(std::fs::read_to_string(&longest).unwrap(), "x");
    // a write that fails for the name says to shorten it, not to check the folder
    let e = std::io::Error::from_raw_os_error(36); // ENAMETOOLONG
    assert_eq!(write_fix(&e), SHORTER_NAME);
}

/// An existing file the user may not write (their own, made read-only) is refused by the
/// check and by the writer, and left as it was; it was replaced with exit 0 where the
/// shell's `>` refuses. A writable file is replaced as before (skipped as root, who may
/// write any file).
#[test]
#[cfg(unix)]
fn a_file_the_user_may_not_write_is_not_replaced() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("keep.csv");
    std::fs::write(&path, "precious\n").unwrap();
    std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o444)).unwrap();
    if std::fs::OpenOptions::new().write(true).open(&path).is_ok() {
        return; // run as root: every file is writable
    }
    let expected = format!(
        "{}: the file is not writable (read-only or another user's); make it writable or \
         give another path",
        path.display()
    );
    assert_eq!(check_file(&path).unwrap_err().to_string(), expected);
    let e = write_bytes(&path, b"t,q1\n").unwrap_err();
    assert!(
        matches!(&e, Error::Output(OutputError::FileNotWritable { path: p }) if *p == path),
        "{e:?}"
    );
    assert_eq!(std::fs::read_to_string(&path).unwrap(), "precious\n");
    let mode = std::fs::metadata(&path).unwrap().permissions().mode();
    assert_eq!(mode & 0o777, 0o444);
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    // through a symbolic link too
    let link = dir.path().join("link.csv");
    std::os::unix::fs::symlink(&path, &link).unwrap();
    assert!(matches!(
        check_file(&link),
        Err(Error::Output(OutputError::FileNotWritable { .. }))
    ));
}

/// `-o -` is refused by the check and by the writer, with the two things it may have
/// meant; `./-` writes a file of that name. It wrote a file named `-` with exit 0.
#[test]
fn a_dash_is_refused_as_an_output() {
    let expected = "-: robid does not take `-` for standard output, and would write a file \
                    named `-`; write ./- for a file of that name, or /dev/stdout for standard \
                    output";
    assert_eq!(
        check_file(Path::new("-")).unwrap_err().to_string(),
        expected
    );
    assert_eq!(
        write_bytes(Path::new("-"), b"x").unwrap_err().to_string(),
        expected
    );
    assert!(!Path::new("-").exists());
    let dir = tempfile::tempdir().unwrap();
    let dash = dir.path().join("-");
    write_bytes(&dash, b"x").unwrap();
    assert_eq!(std::fs::read_to_string(&dash).unwrap(), "x");
}

/// A device given for a folder output is named as a device, without "move the file
/// away" (it said `/dev/null` "is a file").
#[test]
#[cfg(unix)]
fn a_device_for_a_folder_is_named_as_one() {
    let e = check_folder(Path::new("/dev/null")).unwrap_err();
    assert_eq!(
        e.to_string(),
        "/dev/null: is a device, not a folder; give the path of a folder (a missing one is \
         created)"
    );
}
