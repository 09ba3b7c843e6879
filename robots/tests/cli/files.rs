//! Files `robid` writes: an output that is the same file as an input is refused before
//! any work (the same path, the path spelt with `./`, a hard link, a symbolic link), for
//! every subcommand that writes; so is an output that cannot be written where it is
//! given (a missing folder, an existing folder, a path through a file, a folder that
//! takes no new file, a `--plot` folder that is a file); and a failed or killed write leaves an existing file exactly as it
//! was (every output goes through a temporary file and a rename).

use crate::common;

use std::path::{Path, PathBuf};

use common::{
    asset, fails_with, folder, robid, robid_in, sine_trajectory, stderr, stdout, ur5e_states, write,
};

/// The inputs of the cases, copied into a fresh folder.
struct Inputs {
    dir: tempfile::TempDir,
}

impl Inputs {
    fn new() -> Self {
        let dir = folder();
        let copy = |from: &str, to: &str| {
            std::fs::copy(asset(from), dir.path().join(to)).expect("input copied");
        };
        copy("descriptions/ur5e.toml", "robot.toml");
        copy("parameters/ur5e.toml", "params.toml");
        copy("configs/tx40_robot.toml", "tx40.toml");
        copy("tests/fixtures/tx40_identified.json", "identified.json");
        copy("tests/fixtures/tx40_bounds.toml", "bounds.toml");
        copy("parameters/tx40.toml", "prior.toml");
        ur5e_states(dir.path(), 20);
        write(dir.path(), "data.csv", "t,q1\n0,0\n");
        write(dir.path(), "validation.csv", "t,q1\n0,0\n");
        write(dir.path(), "config.toml", "time_column = \"t\"\n");
        Self { dir }
    }

    fn path(&self, name: &str) -> PathBuf {
        self.dir.path().join(name)
    }

    /// `template` with `{name}` replaced by the absolute path of input `name` and
    /// `{out}` by `out`.
    fn args(&self, template: &[&str], out: &str) -> Vec<String> {
        template
            .iter()
            .map(
                |a| match a.strip_prefix('{').and_then(|a| a.strip_suffix('}')) {
                    Some("out") => out.to_string(),
                    Some(name) => self.path(name).display().to_string(),
                    None => a.to_string(),
                },
            )
            .collect()
    }
}

/// Every writer of [`file_outputs`], and identify's `--plot` folder, with each of its
/// inputs as the victim.
fn cases() -> Vec<(Vec<&'static str>, &'static str)> {
    let plot = vec![
        "identify",
        "{robot.toml}",
        "--config",
        "{config.toml}",
        "--data",
        "{data.csv}",
        "--validate",
        "{validation.csv}",
        "--plot",
        "{out}",
    ];
    let mut cases = Vec::new();
    // (the C writer refuses an output not ending in `.c`, so an input never reaches it)
    let c_code = |t: &Vec<&str>| t.contains(&"--lang");
    for template in file_outputs()
        .into_iter()
        .filter(|t| !c_code(t))
        .chain([plot])
    {
        let inputs: Vec<&'static str> = template
            .iter()
            .filter_map(|a| a.strip_prefix('{').and_then(|a| a.strip_suffix('}')))
            .filter(|name| *name != "out")
            .collect();
        cases.extend(inputs.into_iter().map(|victim| (template.clone(), victim)));
    }
    cases
}

/// Runs `args` (from `dir`) and checks that it was refused naming the output as an input
/// and that `victim` is byte for byte what it was.
#[track_caller]
fn refused(dir: &Path, args: &[String], victim: &Path) {
    let before = std::fs::read(victim).unwrap();
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let o = robid_in(dir, &args);
    fails_with(&o, &["is also an input of this run"]);
    assert!(
        std::fs::read(victim).unwrap() == before,
        "{args:?}: {} changed",
        victim.display()
    );
}

#[test]
fn an_output_that_is_an_input_is_refused_by_every_writer() {
    let inputs = Inputs::new();
    let dir = inputs.dir.path();
    for (template, victim) in cases() {
        let target = inputs.path(victim);
        // the same path as given for the input
        refused(
            dir,
            &inputs.args(&template, &target.display().to_string()),
            &target,
        );
        // another spelling of it: relative, with `./`
        refused(
            dir,
            &inputs.args(&template, &format!("./{victim}")),
            &target,
        );
        // a hard link: another name of the same file
        let hard = dir.join(format!("hard-{victim}"));
        std::fs::hard_link(&target, &hard).unwrap();
        refused(
            dir,
            &inputs.args(&template, &hard.display().to_string()),
            &target,
        );
        std::fs::remove_file(&hard).unwrap();
        #[cfg(unix)]
        {
            let link = dir.join(format!("link-{victim}"));
            std::os::unix::fs::symlink(&target, &link).unwrap();
            refused(
                dir,
                &inputs.args(&template, &link.display().to_string()),
                &target,
            );
            assert!(std::fs::symlink_metadata(&link).unwrap().is_symlink());
            std::fs::remove_file(&link).unwrap();
        }
    }
}

/// `--plot DIR`: the files that will be written in DIR count as outputs. An input named
/// like one of them (`fit_joint2.svg`, `validation1_joint6.svg`) is refused before any
/// data is read, and so is DIR when it is an input file itself.
#[test]
fn the_plot_files_count_as_outputs() {
    let inputs = Inputs::new();
    let dir = inputs.dir.path();
    let plots = dir.join("plots");
    std::fs::create_dir(&plots).unwrap();
    for name in ["fit_joint2.svg", "validation1_joint6.svg"] {
        let data = write(&plots, name, "t,q1\n0,0\n");
        let args = inputs.args(
            &[
                "identify",
                "{robot.toml}",
                "--data",
                &data.display().to_string(),
                "--validate",
                "{data.csv}",
                "--plot",
                "{out}",
            ],
            &plots.display().to_string(),
        );
        refused(dir, &args, &data);
    }
    let args = inputs.args(
        &[
            "identify",
            "{robot.toml}",
            "--data",
            "{data.csv}",
            "--plot",
            "{out}",
        ],
        "./data.csv",
    );
    refused(dir, &args, &inputs.path("data.csv"));
}

/// The refusal comes before any other input is read: with a broken parameter file and
/// the output on the states, the message is about the output.
#[test]
fn the_refusal_comes_before_any_work() {
    let inputs = Inputs::new();
    let dir = inputs.dir.path();
    write(dir, "params.toml", "[standard\n");
    for template in [
        &[
            "torques",
            "{robot.toml}",
            "--parameters",
            "{params.toml}",
            "--states",
            "{states.csv}",
            "-o",
            "{out}",
        ][..],
        &[
            "excite",
            "{robot.toml}",
            "--parameters",
            "{params.toml}",
            "-o",
            "{out}",
        ][..],
    ] {
        let victim = if template[0] == "torques" {
            "states.csv"
        } else {
            "robot.toml"
        };
        let target = inputs.path(victim);
        refused(
            dir,
            &inputs.args(template, &target.display().to_string()),
            &target,
        );
    }
}

/// `robid torques` with a file size limit (`ulimit -f`) far below its output: killed by
/// SIGXFSZ in the middle of writing, or (with the signal ignored) stopped by the write
/// error, it leaves the previous output exactly as it was; with the error, also no
/// temporary file. (The old writer left the first 512 bytes of the new output.) The killed
/// run's temporary file breaks no later run, and once a day old it is removed by the next
/// write into its folder (it used to stay for ever).
#[cfg(unix)]
#[test]
fn a_failed_or_killed_write_leaves_the_old_file_whole() {
    use std::os::unix::process::ExitStatusExt;
    use std::process::Command;

    let dir = folder();
    let states = ur5e_states(dir.path(), 2000);
    let output = write(dir.path(), "torques.csv", "the previous output\n");
    let run = |ignore_signal: bool| {
        let script = if ignore_signal {
            "trap '' XFSZ; ulimit -f 1; exec \"$0\" \"$@\""
        } else {
            "ulimit -f 1; exec \"$0\" \"$@\""
        };
        Command::new("sh")
            .arg("-c")
            .arg(script)
            .arg(env!("CARGO_BIN_EXE_robid"))
            .args([
                "torques",
                &asset("descriptions/ur5e.toml"),
                "--parameters",
                &asset("parameters/ur5e.toml"),
                "--states",
                states.to_str().unwrap(),
                "-o",
                output.to_str().unwrap(),
            ])
            .output()
            .expect("sh runs")
    };
    let temporary = || {
        std::fs::read_dir(dir.path())
            .unwrap()
            .filter(|e| {
                let name = e.as_ref().unwrap().file_name();
                name.to_string_lossy().ends_with(".tmp")
            })
            .count()
    };
    let killed = run(false);
    assert_eq!(killed.status.signal(), Some(25), "SIGXFSZ: {killed:?}");
    assert_eq!(
        std::fs::read_to_string(&output).unwrap(),
        "the previous output\n"
    );
    // a killed program cannot clean up: its temporary file stays beside the target
    let after_kill = temporary();
    let failed = run(true);
    fails_with(&failed, &["torques.csv: cannot write"]);
    assert_eq!(
        std::fs::read_to_string(&output).unwrap(),
        "the previous output\n"
    );
    assert_eq!(
        temporary(),
        after_kill,
        "the failed write removes its temporary file"
    );
    assert_eq!(after_kill, 1);
    // a day later, without the limit, the output is replaced as a whole and the killed
    // run's temporary file removed
    let day_ago = std::time::SystemTime::now() - std::time::Duration::from_secs(25 * 3600);
    for entry in std::fs::read_dir(dir.path()).unwrap() {
        let path = entry.unwrap().path();
        if path.to_string_lossy().ends_with(".tmp") {
            let file = std::fs::File::open(&path).unwrap();
            file.set_modified(day_ago).unwrap();
        }
    }
    let o = robid(&[
        "torques",
        "descriptions/ur5e.toml",
        "--parameters",
        "parameters/ur5e.toml",
        "--states",
        states.to_str().unwrap(),
        "-o",
        output.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        std::fs::read_to_string(&output).unwrap().lines().count(),
        2001
    );
    assert_eq!(temporary(), 0, "the stale temporary file is removed");
}

/// Two outputs of one run on the same file (under any spelling) are refused before any
/// work: one would silently replace the other.
#[test]
fn two_outputs_on_one_file_are_refused() {
    let inputs = Inputs::new();
    let dir = inputs.dir.path();
    let both = |first: &str, second: &str, out: &str| {
        let identify = [
            "identify",
            "{robot.toml}",
            "--config",
            "{config.toml}",
            "--data",
            "{data.csv}",
            first,
            "{out}",
            second,
            out,
        ];
        let args = inputs.args(&identify, "result.out");
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        robid_in(dir, &args)
    };
    for out in ["result.out", "./result.out"] {
        let o = both("--json", "--report", out);
        fails_with(
            &o,
            &[&format!(
                "--json and --report name the same file (result.out{}), so one output would \
                 replace the other; give them different names",
                if out == "result.out" {
                    String::new()
                } else {
                    format!(" and {out}")
                }
            )],
        );
        assert!(!dir.join("result.out").exists());
    }
    let o = robid_in(
        dir,
        &[
            "excite",
            "robot.toml",
            "-o",
            "trajectory.csv",
            "--pieces",
            "./trajectory.csv",
        ],
    );
    fails_with(
        &o,
        &["--output and --pieces name the same file (trajectory.csv and ./trajectory.csv)"],
    );
    // a report on a plot that `--plot` writes in the same run, either way round
    std::fs::create_dir(dir.join("plots")).unwrap();
    for (file, flag) in [("fit_joint1.svg", "--json"), ("fit_joint2.svg", "--report")] {
        let o = robid_in(
            dir,
            &[
                "identify",
                "robot.toml",
                "--config",
                "config.toml",
                "--data",
                "data.csv",
                "--plot",
                "plots",
                flag,
                &format!("plots/{file}"),
            ],
        );
        fails_with(
            &o,
            &[&format!(
                "{flag} and --plot name the same file (plots/{file})"
            )],
        );
        assert_eq!(std::fs::read_dir(dir.join("plots")).unwrap().count(), 0);
    }
    // a report and a JSON in the folder --plot creates are written there (each was "the
    // folder plots2 does not exist; create it first": the JSON was written before the
    // plots created the folder); one folder deeper is still refused
    let plots = dir.join("plots2");
    let identify = |report: &Path| {
        robid(&[
            "identify",
            "configs/tx40_robot.toml",
            "--config",
            "configs/tx40.toml",
            "--plot",
            plots.to_str().unwrap(),
            "--report",
            report.to_str().unwrap(),
            "--json",
            plots.join("fit.json").to_str().unwrap(),
        ])
    };
    let o = identify(&plots.join("deeper/report.html"));
    fails_with(&o, &["deeper does not exist; create it first"]);
    assert!(!plots.exists());
    let o = identify(&plots.join("report.html"));
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(plots.join("report.html").exists());
    assert!(plots.join("fit.json").exists());
    assert!(plots.join("fit_joint1.svg").exists());
}

/// The files a config names besides the data (`estimation.known`, `[drive.rotor]
/// friction`) are inputs too: a report written over one is refused, the file intact.
#[test]
fn the_files_a_config_names_are_inputs() {
    let inputs = Inputs::new();
    let dir = inputs.dir.path();
    write(dir, "known.toml", "[known]\nM1 = 1.0\n");
    write(dir, "friction.toml", "# a friction model\n");
    let configs = [
        ("known.toml", "[estimation]\nknown = \"known.toml\"\n"),
        (
            "friction.toml",
            "[drive.rotor]\ninertia = [0, 0, 0, 0, 0, 0]\nfriction = \"friction.toml\"\n",
        ),
    ];
    for (victim, table) in configs {
        write(dir, "named.toml", &format!("time_column = \"t\"\n{table}"));
        for flag in ["--json", "--report"] {
            let args = inputs.args(
                &[
                    "identify",
                    "{robot.toml}",
                    "--config",
                    "{named.toml}",
                    "--data",
                    "{data.csv}",
                    flag,
                    "{out}",
                ],
                &format!("./{victim}"),
            );
            refused(dir, &args, &inputs.path(victim));
        }
    }
}

/// An output that is a pipe is written into, not replaced by a file, and checking it
/// against the inputs does not wait for a writer (it is never opened for reading).
#[test]
#[cfg(unix)]
fn a_pipe_is_written_into() {
    let dir = folder();
    let fifo = dir.path().join("code.fifo");
    if !std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .is_ok_and(|s| s.success())
    {
        return; // no mkfifo here
    }
    let (sent, read) = std::sync::mpsc::channel();
    let reader = fifo.clone();
    std::thread::spawn(move || sent.send(std::fs::read_to_string(reader).unwrap()));
    let o = robid(&[
        "emit",
        "descriptions/ur5e.toml",
        "-o",
        fifo.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    // a writer that never opens the pipe fails the test instead of hanging it
    let code = read
        .recv_timeout(std::time::Duration::from_secs(60))
        .unwrap();
    assert!(code.contains("pub struct Ur5e;"));
    let kind = std::fs::symlink_metadata(&fifo).unwrap().file_type();
    assert!(std::os::unix::fs::FileTypeExt::is_fifo(&kind));
}

/// An output on a full disk (`-o /dev/full`) says so and asks for space, not that the
/// folder be checked (what it said before).
#[cfg(target_os = "linux")]
#[test]
fn a_full_disk_asks_for_space() {
    let o = robid(&["emit", "descriptions/ur5e.toml", "-o", "/dev/full"]);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(
        e.starts_with("error: /dev/full: cannot write: ")
            && e.contains("free space on that disk, or write to another one")
            && !e.contains("folder"),
        "{e}"
    );
}

/// The outputs of one run change together: when the last of them fails (a full disk),
/// the earlier ones keep their old contents (a C header beside no new source, a
/// description beside no parameter file); when every one succeeds, all are new.
#[cfg(target_os = "linux")]
#[test]
fn the_outputs_of_a_failed_run_are_all_left_as_they_were() {
    let dir = folder();
    let old = |name: &str| write(dir.path(), name, "old\n");
    let header = old("ur.h");
    let source = dir.path().join("ur.c");
    std::os::unix::fs::symlink("/dev/full", &source).unwrap();
    let description = old("d.toml");
    let runs: [(&[&str], &PathBuf); 2] = [
        (
            &[
                "emit",
                "descriptions/ur5e.toml",
                "--lang",
                "c",
                "-o",
                source.to_str().unwrap(),
            ],
            &header,
        ),
        (
            &[
                "model",
                "../data/example_robot_data/ur5/ur5_robot.urdf",
                "--write-description",
                description.to_str().unwrap(),
                "--standard-parameters",
                "/dev/full",
            ],
            &description,
        ),
    ];
    for (args, earlier) in runs {
        let o = robid(args);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {}", stderr(&o));
        assert!(stderr(&o).contains("No space left"), "{}", stderr(&o));
        assert_eq!(
            std::fs::read_to_string(earlier).unwrap(),
            "old\n",
            "{args:?}"
        );
    }
    // no temporary file is left behind
    let mut names: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names, ["d.toml", "ur.c", "ur.h"]);
    // both outputs of a run that succeeds are new
    let parameters = old("p.toml");
    let o = robid(&[
        "model",
        "../data/example_robot_data/ur5/ur5_robot.urdf",
        "--write-description",
        description.to_str().unwrap(),
        "--standard-parameters",
        parameters.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    for written in [&description, &parameters] {
        assert_ne!(std::fs::read_to_string(written).unwrap(), "old\n");
    }
}

/// One run of every writer that reaches its write, with the output `out`: emit, torques,
/// excite (a short design), simulate, identify --json and feasible. The trajectory and
/// the simulated data they need are written into `dir` first.
fn writers(dir: &Path, out: &str) -> Vec<Vec<String>> {
    let trajectory = dir.join("trajectory.csv").display().to_string();
    let simulated = dir.join("simulated.csv").display().to_string();
    let excite = |out: &str| {
        [
            "excite",
            "descriptions/ur5e.toml",
            "--duration",
            "10",
            "--rate",
            "50",
            "--harmonics",
            "2",
            "--restarts",
            "1",
            "--evaluations",
            "50",
            "-o",
            out,
        ]
        .map(String::from)
        .to_vec()
    };
    let simulate = |out: &str| {
        [
            "simulate",
            "descriptions/ur5e.toml",
            "--parameters",
            "parameters/ur5e.toml",
            "--trajectory",
            &trajectory,
            "-o",
            out,
        ]
        .map(String::from)
        .to_vec()
    };
    if !Path::new(&simulated).exists() {
        for args in [excite(&trajectory), simulate(&simulated)] {
            let args: Vec<&str> = args.iter().map(String::as_str).collect();
            let o = robid(&args);
            assert!(o.status.success(), "{args:?}: {}", stderr(&o));
        }
    }
    let states = ur5e_states(dir, 20).display().to_string();
    let rest: [&[&str]; 4] = [
        &["emit", "descriptions/ur5e.toml", "-o", out],
        &[
            "torques",
            "descriptions/ur5e.toml",
            "--parameters",
            "parameters/ur5e.toml",
            "--states",
            &states,
            "-o",
            out,
        ],
        &[
            "identify",
            "descriptions/ur5e.toml",
            "--data",
            &simulated,
            "--json",
            out,
        ],
        &[
            "feasible",
            "configs/tx40_robot.toml",
            "--identified",
            "tests/fixtures/tx40_identified.json",
            "--bounds",
            "tests/fixtures/tx40_bounds.toml",
            "-o",
            out,
        ],
    ];
    let mut runs = vec![excite(out), simulate(out)];
    runs.extend(
        rest.iter()
            .map(|a| a.iter().map(|s| s.to_string()).collect()),
    );
    runs
}

/// An output that is a folder (`-o /tmp/results`) is named as one, with a file in it as
/// the fix, by every writer; it used to end "cannot write: it is a folder; give a file
/// name; check that the folder exists and is writable".
#[test]
fn a_folder_as_output_is_named_as_one_by_every_writer() {
    let dir = folder();
    let target = dir.path().join("results");
    std::fs::create_dir(&target).unwrap();
    let out = target.display().to_string();
    let expected = format!("error: {out}: is a folder; give a file name, e.g. {out}/out\n");
    for args in writers(dir.path(), &out) {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let o = robid(&args);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {}", stderr(&o));
        assert_eq!(stderr(&o), expected, "{args:?}");
        assert_eq!(std::fs::read_dir(&target).unwrap().count(), 0, "{args:?}");
    }
}

/// An output in a folder that does not exist names the output as given and its folder,
/// by every writer; it used to name the temporary file: "/nonexistent/dir/f.toml: cannot
/// write: No such file or directory (os error 2) at path
/// \"/nonexistent/dir/.robid-2MkxLu.tmp\"; check that the folder exists and is writable".
#[test]
fn a_missing_folder_is_named_by_every_writer() {
    let dir = folder();
    let missing = dir.path().join("missing").join("dir");
    let out = missing.join("f.toml").display().to_string();
    let expected = format!(
        "error: {out}: the folder {} does not exist; create it first\n",
        missing.display()
    );
    for args in writers(dir.path(), &out) {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let o = robid(&args);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {}", stderr(&o));
        assert_eq!(stderr(&o), expected, "{args:?}");
    }
    assert!(!dir.path().join("missing").exists());
}

/// Every writer of a file, with its output `{out}` (for [`Inputs::args`]): `-o` of each
/// subcommand (C code too), `--json` and `--report` of identify, `--json` of
/// `identify --static`, `--pieces` of excite.
fn file_outputs() -> Vec<Vec<&'static str>> {
    let identify = |flag: &'static str| {
        vec![
            "identify",
            "{robot.toml}",
            "--config",
            "{config.toml}",
            "--data",
            "{data.csv}",
            "--validate",
            "{validation.csv}",
            flag,
            "{out}",
        ]
    };
    vec![
        vec!["emit", "{robot.toml}", "-o", "{out}"],
        vec!["emit", "{robot.toml}", "--lang", "c", "-o", "{out}"],
        vec![
            "torques",
            "{robot.toml}",
            "--parameters",
            "{params.toml}",
            "--states",
            "{states.csv}",
            "-o",
            "{out}",
        ],
        vec![
            "excite",
            "{robot.toml}",
            "--parameters",
            "{params.toml}",
            "-o",
            "{out}",
        ],
        vec![
            "excite",
            "{robot.toml}",
            "--method",
            "points",
            "-o",
            "trajectory.csv",
            "--pieces",
            "{out}",
        ],
        vec![
            "simulate",
            "{robot.toml}",
            "--parameters",
            "{params.toml}",
            "--trajectory",
            "{states.csv}",
            "-o",
            "{out}",
        ],
        identify("--json"),
        identify("--report"),
        vec![
            "identify",
            "{robot.toml}",
            "--static",
            "{data.csv}",
            "--json",
            "{out}",
        ],
        vec![
            "feasible",
            "{tx40.toml}",
            "--identified",
            "{identified.json}",
            "--bounds",
            "{bounds.toml}",
            "--prior",
            "{prior.toml}",
            "-o",
            "{out}",
        ],
        vec![
            "payload",
            "{robot.toml}",
            "--parameters",
            "{params.toml}",
            "--data",
            "{data.csv}",
            "-o",
            "{out}",
        ],
        vec![
            "friction",
            "{robot.toml}",
            "--config",
            "{config.toml}",
            "--data",
            "{data.csv}",
            "-o",
            "{out}",
        ],
    ]
}

/// `inputs` with every input a run reads after checking its outputs made unreadable (the
/// config stays: identify and friction read it to find their data files): a run that
/// started its work would fail on the first of them.
fn broken(inputs: &Inputs) {
    for name in [
        "robot.toml",
        "params.toml",
        "states.csv",
        "data.csv",
        "validation.csv",
        "tx40.toml",
        "identified.json",
        "bounds.toml",
        "prior.toml",
    ] {
        write(inputs.dir.path(), name, "[broken\n");
    }
}

/// The names in `dir` and in its folders, sorted.
fn listing(dir: &Path) -> Vec<PathBuf> {
    let mut names = Vec::new();
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            names.extend(listing(&path));
        }
        names.push(path);
    }
    names.sort();
    names
}

/// An output its writer would refuse (in a folder that does not exist, an existing folder,
/// under a file) is refused before any work, with the writer's message, by every writer:
/// with every input broken, the message is about the output, not the first input read
/// (it used to be refused only when written, after the work: an excite design of ten
/// seconds, a simulation, an identification), and nothing is written.
#[test]
fn a_bad_output_is_refused_before_any_work_by_every_writer() {
    let inputs = Inputs::new();
    broken(&inputs);
    let dir = inputs.dir.path();
    let notes = write(dir, "notes.txt", "mine\n");
    // `.c`: `emit --lang c` takes no other name
    let results = dir.join("results.c");
    std::fs::create_dir(&results).unwrap();
    let missing = dir.join("missing").join("dir");
    let (out, folder) = (missing.join("out.c"), missing.display());
    let under = notes.join("out.c");
    let bad = [
        (
            out.display().to_string(),
            format!("the folder {folder} does not exist; create it first"),
        ),
        (
            results.display().to_string(),
            format!(
                "is a folder; give a file name, e.g. {}/out",
                results.display()
            ),
        ),
        (
            under.display().to_string(),
            format!(
                "{} is not a folder (it, or one above it, is a file); give a path in an \
                 existing folder",
                notes.display()
            ),
        ),
    ];
    let before = listing(dir);
    for template in file_outputs() {
        for (out, problem) in &bad {
            let args = inputs.args(&template, out);
            let args: Vec<&str> = args.iter().map(String::as_str).collect();
            let o = robid_in(dir, &args);
            assert_eq!(o.status.code(), Some(1), "{args:?}: {}", stderr(&o));
            assert_eq!(stderr(&o), format!("error: {out}: {problem}\n"), "{args:?}");
            assert_eq!(listing(dir), before, "{args:?}");
        }
    }
    assert_eq!(std::fs::read_to_string(&notes).unwrap(), "mine\n");
}

/// `identify --plot` takes a folder: a missing one is created (not refused: the run goes
/// on to the data), while an existing file, or a path under one, is refused before any
/// work; a file says plainly that --plot takes a folder (it used to say "cannot write:
/// cannot create the folder: File exists (os error 17)", after the identification).
#[test]
fn a_plot_folder_that_cannot_be_one_is_refused_before_any_work() {
    let inputs = Inputs::new();
    broken(&inputs);
    let dir = inputs.dir.path();
    let notes = write(dir, "plots.svg", "mine\n");
    let identify = [
        "identify",
        "{robot.toml}",
        "--config",
        "{config.toml}",
        "--data",
        "{data.csv}",
        "--plot",
        "{out}",
    ];
    let run = |out: &Path| {
        let args = inputs.args(&identify, &out.display().to_string());
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        robid_in(dir, &args)
    };
    let before = listing(dir);
    let o = run(&notes);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert_eq!(
        stderr(&o),
        format!(
            "error: --plot: {} is a file, but --plot takes a folder to write its files into \
             (a missing one is created); give the path of a folder, or move the file away\n",
            notes.display()
        )
    );
    let under = notes.join("plots");
    let o = run(&under);
    assert_eq!(
        stderr(&o),
        format!(
            "error: {}: {} is not a folder (it, or one above it, is a file); give a path in \
             an existing folder\n",
            under.display(),
            notes.display()
        )
    );
    assert_eq!(listing(dir), before);
    assert_eq!(std::fs::read_to_string(&notes).unwrap(), "mine\n");
    // a device is named as one, without "move the file away" (it said "/dev/null is a
    // file")
    #[cfg(unix)]
    {
        let o = run(Path::new("/dev/null"));
        assert_eq!(
            stderr(&o),
            "error: --plot: /dev/null is a device, not a folder, but --plot takes a folder to \
             write its files into (a missing one is created); give the path of a folder\n"
        );
    }
    // a missing folder passes the check: the run fails on the data it reads next
    let o = run(&dir.join("new").join("plots"));
    fails_with(&o, &["robot.toml"]);
    assert!(!stderr(&o).contains("plots"), "{}", stderr(&o));
}

/// A real design whose trajectory cannot be written: refused before the design, so that
/// `--pieces` (written first, after minutes of design with real settings) is not written
/// either.
#[test]
fn an_excite_design_with_a_bad_output_writes_nothing() {
    let dir = folder();
    let pieces = dir.path().join("pieces.toml");
    let output = dir.path().join("missing").join("p.csv");
    let o = robid(&[
        "excite",
        "descriptions/ur5e.toml",
        "--method",
        "points",
        "--intervals",
        "6",
        "--duration",
        "12",
        "--rate",
        "100",
        "--restarts",
        "1",
        "--sweeps",
        "1",
        "--evaluations",
        "20",
        "--pieces",
        pieces.to_str().unwrap(),
        "-o",
        output.to_str().unwrap(),
    ]);
    assert_eq!(
        stderr(&o),
        format!(
            "error: {}: the folder {} does not exist; create it first\n",
            output.display(),
            dir.path().join("missing").display()
        )
    );
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
    assert!(stdout(&o).is_empty(), "{}", stdout(&o));
}

/// The message of an output in `folder`, a folder no file can be created in for `reason`:
/// making it writable is a fix for a permission, not for /proc.
fn not_writable(out: &str, folder: &str, reason: &str) -> String {
    let fix = if reason == PROC {
        ""
    } else {
        ", or make this one writable"
    };
    format!(
        "error: {out}: cannot create a file in the folder {folder} ({reason}); give a path in a \
         folder you may write into{fix}\n"
    )
}

/// Why /proc takes no new file, as a message says it.
const PROC: &str = "the system refuses new files there, as in /proc and /sys";

/// An output in a folder that exists but takes no file (/proc, even for root) is refused
/// before any work by every writer, naming the output and the folder; it used to be found
/// only at the write, after the work ("cannot write: cannot create a file in /proc: entity
/// not found; check that the folder exists and is writable"). A `--plot` folder there,
/// existing or to be created, likewise. Nothing is left in the inputs' folder.
#[test]
#[cfg(target_os = "linux")]
fn an_output_in_a_folder_that_takes_no_file_is_refused_before_any_work() {
    if !Path::new("/proc/self").is_dir() {
        return; // no procfs here
    }
    let inputs = Inputs::new();
    broken(&inputs);
    let dir = inputs.dir.path();
    let before = listing(dir);
    // `.c`: `emit --lang c` takes no other name
    let out = "/proc/robid-never-written.c";
    for template in file_outputs() {
        let args = inputs.args(&template, out);
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let o = robid_in(dir, &args);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {}", stderr(&o));
        assert_eq!(stderr(&o), not_writable(out, "/proc", PROC), "{args:?}");
        assert_eq!(listing(dir), before, "{args:?}");
    }
    for plot in ["/proc", "/proc/robid-never-written/plots"] {
        let args = inputs.args(
            &[
                "identify",
                "{robot.toml}",
                "--config",
                "{config.toml}",
                "--data",
                "{data.csv}",
                "--plot",
                plot,
            ],
            "",
        );
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let o = robid_in(dir, &args);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {}", stderr(&o));
        assert_eq!(stderr(&o), not_writable(plot, "/proc", PROC), "{args:?}");
    }
    assert_eq!(listing(dir), before);
}

/// A folder without write permission is refused before any work, naming the output and
/// the folder, and nothing is left in it (skipped as root, whom permissions do not stop).
#[test]
#[cfg(unix)]
fn an_output_in_a_read_only_folder_is_refused_before_any_work() {
    use std::os::unix::fs::PermissionsExt;
    let inputs = Inputs::new();
    broken(&inputs);
    let dir = inputs.dir.path();
    let locked = dir.join("locked");
    std::fs::create_dir(&locked).unwrap();
    std::fs::set_permissions(&locked, std::fs::Permissions::from_mode(0o555)).unwrap();
    let writable = std::fs::File::create(locked.join("probe")).is_ok();
    if writable {
        return; // run as root: every folder is writable
    }
    let out = locked.join("out.c").display().to_string();
    let folder = locked.display().to_string();
    for template in file_outputs() {
        let args = inputs.args(&template, &out);
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let o = robid_in(dir, &args);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {}", stderr(&o));
        assert_eq!(
            stderr(&o),
            not_writable(&out, &folder, "permission denied"),
            "{args:?}"
        );
    }
    assert_eq!(std::fs::read_dir(&locked).unwrap().count(), 0);
    std::fs::set_permissions(&locked, std::fs::Permissions::from_mode(0o755)).unwrap();
}

/// `emit --lang c -o x.c` also writes `x.h`, a name the user did not type: a header path
/// that cannot be written is refused before any work naming it as the header of `-o x.c`,
/// with a fix that holds for it (another `-o`, or moving it away), not "give a file name,
/// e.g. x.h/out" nor an input that seems to be the output. A missing folder names the
/// folder and the source as given, once.
#[test]
fn the_c_header_is_named_as_the_header_of_the_source() {
    let dir = folder();
    let d = dir.path();
    std::fs::create_dir(d.join("y.h")).unwrap();
    std::fs::copy(asset("descriptions/ur5e.toml"), d.join("z.h")).unwrap();
    let ur5e = asset("descriptions/ur5e.toml");
    let before = listing(d);
    let cases = [
        (
            vec!["emit", &ur5e, "--lang", "c", "-o", "y.c"],
            "error: y.h: is a folder, and `-o y.c` writes the C header there; give `-o` \
             another name, or move y.h away\n"
                .to_string(),
        ),
        (
            vec!["emit", "z.h", "--lang", "c", "-o", "z.c"],
            "error: z.h, the C header that `-o z.c` writes, is also an input of this run \
             (z.h); give `-o` another name\n"
                .to_string(),
        ),
        (
            vec!["emit", &ur5e, "--lang", "c", "-o", "missing/x.c"],
            "error: missing/x.c: the folder missing does not exist; create it first\n".to_string(),
        ),
    ];
    for (args, expected) in cases {
        let o = robid_in(d, &args);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {}", stderr(&o));
        assert_eq!(stderr(&o), expected, "{args:?}");
        assert_eq!(listing(d), before, "{args:?}");
    }
}

/// An output that is a symbolic link to a file not created yet (`x.h -> include/q.h`, as a
/// build tree links a generated header into place) is written through the link, which is
/// kept: the C header of `emit --lang c` and the source alike, with a relative target
/// taken from the link's folder. A link into a folder that does not exist is refused
/// before any work, naming the link, its target and the folder (it used to be replaced by
/// a file, the link lost).
#[test]
#[cfg(unix)]
fn a_link_to_a_file_not_created_yet_is_written_through() {
    use std::os::unix::fs::symlink;
    let dir = folder();
    let d = dir.path();
    std::fs::create_dir(d.join("include")).unwrap();
    std::fs::create_dir(d.join("src")).unwrap();
    symlink("include/q.h", d.join("x.h")).unwrap();
    symlink(d.join("src/q.c"), d.join("x.c")).unwrap();
    let ur5e = asset("descriptions/ur5e.toml");
    let o = robid_in(d, &["emit", &ur5e, "--lang", "c", "-o", "x.c"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    for (link, file) in [("x.h", "include/q.h"), ("x.c", "src/q.c")] {
        let kind = std::fs::symlink_metadata(d.join(link)).unwrap().file_type();
        assert!(kind.is_symlink(), "{link} is no longer a link");
        let text = std::fs::read_to_string(d.join(file)).unwrap();
        assert!(text.contains("ur5e"), "{file}: {text}");
    }
    // into a folder that does not exist: refused before any work, nothing created
    symlink("missing/q.h", d.join("y.h")).unwrap();
    let before = listing(d);
    let o = robid_in(d, &["emit", &ur5e, "--lang", "c", "-o", "y.c"]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert_eq!(
        stderr(&o),
        "error: y.h: is a symbolic link to missing/q.h, whose folder missing does not exist; \
         create the folder, or remove the link to write a file in its place (the C header \
         that `-o y.c` writes)\n"
    );
    assert_eq!(listing(d), before);
}

/// `demo` takes no path, so a file named like its report's folder is told with what the
/// demo can do: move the file, or run elsewhere (it said "give the path of a folder").
#[test]
fn demo_beside_a_file_named_like_its_folder_says_what_to_do() {
    let dir = folder();
    write(dir.path(), "robid-demo", "not a folder");
    let o = robid_in(dir.path(), &["demo"]);
    fails_with(
        &o,
        &[
            "robid-demo: is a file, and the demo writes its report into the folder ./robid-demo; \
           move the file away, or run the demo from another folder",
        ],
    );
    assert!(stdout(&o).is_empty(), "{}", stdout(&o));
}

/// `demo` takes no path, so a report folder it may not write into is told with what the
/// demo can do: run it from a folder the user may write into (it said "give a path in a
/// folder you may write into"; skipped as root, whom permissions do not stop).
#[test]
#[cfg(unix)]
fn demo_in_a_folder_it_may_not_write_says_what_to_do() {
    use std::os::unix::fs::PermissionsExt;
    let dir = folder();
    let report = dir.path().join("robid-demo");
    std::fs::create_dir(&report).unwrap();
    std::fs::set_permissions(&report, std::fs::Permissions::from_mode(0o555)).unwrap();
    let writable = std::fs::File::create(report.join("probe")).is_ok();
    if !writable {
        let o = robid_in(dir.path(), &["demo"]);
        fails_with(
            &o,
            &[
                "robid-demo: cannot create a file in the folder robid-demo (permission denied), \
                 where the demo writes its report; run the demo from a folder you may write into",
            ],
        );
        assert!(!stderr(&o).contains("give a path"), "{}", stderr(&o));
    }
    std::fs::set_permissions(&report, std::fs::Permissions::from_mode(0o755)).unwrap();
}

/// `-o -` is refused before any work with the two things it may have meant, and no file
/// named `-` is written (it was, with exit 0, and a later `--states -` read it).
#[test]
fn a_dash_as_output_is_refused() {
    let dir = folder();
    let states = ur5e_states(dir.path(), 5).display().to_string();
    let torques = |out: &str| {
        robid_in(
            dir.path(),
            &[
                "torques",
                &asset("descriptions/ur5e.toml"),
                "--parameters",
                &asset("parameters/ur5e.toml"),
                "--states",
                &states,
                "-o",
                out,
            ],
        )
    };
    let o = torques("-");
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert_eq!(
        stderr(&o),
        "error: -: robid does not take `-` for standard output, and would write a file named \
         `-`; write ./- for a file of that name, or /dev/stdout for standard output\n"
    );
    assert!(stdout(&o).is_empty(), "{}", stdout(&o));
    assert!(!dir.path().join("-").exists());
    // `./-` is a file of that name
    let o = torques("./-");
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        std::fs::read_to_string(dir.path().join("-"))
            .unwrap()
            .starts_with("tau1")
    );
}

/// A report name too long for its folder's file system (256 letters and `.html`) is
/// refused before any work, naming the cause and the fix, and the JSON of the same run
/// keeps the earlier run's text: the check passed it (its temporary file had a short
/// name), and the run ended at the report's rename with "File name too long; check that
/// the folder exists and is writable" after `fit.json` was replaced.
#[cfg(target_os = "linux")]
#[test]
fn a_report_name_too_long_leaves_the_json_as_it_was() {
    let dir = folder();
    let d = dir.path();
    let trajectory = sine_trajectory(d, "trajectory.csv", 6, 20.0, 1.0);
    let data = d.join("data.csv").display().to_string();
    let o = robid(&[
        "simulate",
        "descriptions/ur5e.toml",
        "--parameters",
        "parameters/ur5e.toml",
        "--trajectory",
        &trajectory,
        "-o",
        &data,
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let fit = write(d, "fit.json", "OLD JSON\n");
    let report = format!("{}.html", "a".repeat(256));
    let identify = |report: &str| {
        robid_in(
            d,
            &[
                "identify",
                &asset("descriptions/ur5e.toml"),
                "--data",
                &data,
                "--json",
                "fit.json",
                "--report",
                report,
            ],
        )
    };
    let o = identify(&report);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert_eq!(
        stderr(&o),
        format!(
            "error: {report}: the file name (261 bytes) is too long for the file system of the \
             folder .; give a shorter name (most file systems take at most 255 bytes in a file \
             name)\n"
        )
    );
    assert!(stdout(&o).is_empty(), "{}", stdout(&o));
    assert_eq!(std::fs::read_to_string(&fit).unwrap(), "OLD JSON\n");
    // the same run with a name the file system takes writes both
    let o = identify("report.html");
    assert!(o.status.success(), "{}", stderr(&o));
    assert_ne!(std::fs::read_to_string(&fit).unwrap(), "OLD JSON\n");
    assert!(d.join("report.html").exists());
}

/// A folder given where a file belongs is told so with the fix, by every reader (it was
/// "cannot read: Is a directory (os error 21); check the path and permissions").
#[test]
fn a_folder_given_for_a_file_is_told_so() {
    let dir = folder();
    let d = dir.path().to_str().unwrap();
    for args in [
        vec!["model", d],
        vec!["identify", "descriptions/ur5e.toml", "--data", d],
        vec![
            "feasible",
            "tests/fixtures/two_link.toml",
            "--identified",
            d,
            "-o",
            "unused.toml",
        ],
    ] {
        let o = robid(&args);
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {e}");
        assert!(
            e.contains("it is a folder, not a file; give the path of a file")
                && !e.contains("os error"),
            "{args:?}: {e}"
        );
    }
}

/// Files of fixed names in `--plot`'s folder and in the demo's: a folder of such a name
/// is refused before any work (the plots before it, or the demo's JSON files and figures,
/// were written first, and the fix "give a file name" could not be followed); plots an
/// earlier run left that this run does not write are named in a warning, others not.
#[test]
fn fixed_names_taken_by_folders_are_refused_before_any_work() {
    let dir = folder();
    let plots = dir.path().join("plots");
    std::fs::create_dir_all(plots.join("fit_joint2.svg")).unwrap();
    let json = dir.path().join("fit.json");
    let identify = || {
        robid(&[
            "identify",
            "configs/tx40_robot.toml",
            "--config",
            "configs/tx40.toml",
            "--plot",
            plots.to_str().unwrap(),
            "--json",
            json.to_str().unwrap(),
        ])
    };
    let o = identify();
    fails_with(
        &o,
        &[
            "fit_joint2.svg: is a folder, where --plot writes a file of that name; move or \
           rename the folder, or write into another folder",
        ],
    );
    assert!(stdout(&o).is_empty(), "{}", stdout(&o));
    assert!(!json.exists() && !plots.join("fit_joint1.svg").exists());
    std::fs::remove_dir(plots.join("fit_joint2.svg")).unwrap();
    for name in [
        "validation1_joint3.svg",
        "fit_joint9.svg",
        "fit_joint1.svg",
        "mine.svg",
    ] {
        write(&plots, name, "<svg/>");
    }
    let o = identify();
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains(
            "2 files named as robid's plots that this run does not write, left by an earlier \
             run: fit_joint9.svg, validation1_joint3.svg; remove them, or plot into an empty \
             folder"
        ),
        "{}",
        stderr(&o)
    );
    let demo = folder();
    std::fs::create_dir_all(demo.path().join("robid-demo/report.html")).unwrap();
    let o = robid_in(demo.path(), &["demo"]);
    fails_with(
        &o,
        &["robid-demo/report.html: is a folder, where robid demo writes a file of that name"],
    );
    assert!(stdout(&o).is_empty(), "{}", stdout(&o));
    assert_eq!(
        std::fs::read_dir(demo.path().join("robid-demo"))
            .unwrap()
            .count(),
        1
    );
}
