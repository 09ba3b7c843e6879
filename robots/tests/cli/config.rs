//! `robid identify` with a config: `--example-config` prints a config that works, and the
//! `file` of each `[[source]]` is read (relative to the config) when `--data` is not given.

use crate::common::{fails_with, folder, robid, stderr, stdout, write};
use std::fmt::Write as _;

/// One revolute joint about a horizontal axis (gravity along x of the base).
const PENDULUM: &str = "name = \"pendulum\"\nconvention = \"modified\"\n\
                        gravity = [-9.81, 0, 0]\ndrive = [\"Fv\"]\n[[joints]]\nalpha = 0\n";

/// A log of the pendulum with noise-like torque: the test compares two runs, not values.
fn log() -> String {
    let mut csv = String::from("time,angle,torque\n");
    for k in 0..3000 {
        let t = k as f64 * 2e-3;
        let q = 1.2 * (1.3 * t).sin() + 0.3 * (4.1 * t).cos();
        let tau = 2.0 * q.cos() + 0.4 * (1.3 * t).cos() + 0.05 * (97.0 * t).sin();
        csv.push_str(&format!("{t},{q},{tau}\n"));
    }
    csv
}

const CONFIG: &str = "dof = 1\ntime_column = \"time\"\n[[source]]\nposition = [\"angle\"]\n\
                      torque = [\"torque\"]\n[processing]\nlowpass = { cutoff = 5.0 }\n";

#[test]
fn the_sources_files_are_read_relative_to_the_config() {
    let dir = folder();
    let d = dir.path();
    let robot = write(d, "pendulum.toml", PENDULUM);
    std::fs::create_dir(d.join("logs")).unwrap();
    let data = write(&d.join("logs"), "run.csv", &log());
    std::fs::create_dir(d.join("jobs")).unwrap();
    let with_file = CONFIG.replace("[[source]]\n", "[[source]]\nfile = \"../logs/run.csv\"\n");
    let job = write(&d.join("jobs"), "job.toml", &with_file);
    let plain = write(d, "plain.toml", CONFIG);
    let (robot, job, plain, data) = (
        robot.to_str().unwrap(),
        job.to_str().unwrap(),
        plain.to_str().unwrap(),
        data.to_str().unwrap(),
    );
    let from_config = robid(&["identify", robot, "--config", job]);
    assert!(from_config.status.success(), "{}", stderr(&from_config));
    assert!(stdout(&from_config).contains("fit: relative error"));
    let explicit = robid(&["identify", robot, "--config", plain, "--data", data]);
    assert!(explicit.status.success(), "{}", stderr(&explicit));
    // the same rows of the same file, named through the config's folder
    assert_eq!(
        stdout(&from_config).replace("jobs/../", ""),
        stdout(&explicit)
    );
    // --data overrides the config's files
    let full = log();
    let shorter = full.lines().take(2001).collect::<Vec<_>>().join("\n");
    let other = write(d, "other.csv", &shorter);
    let o = robid(&[
        "identify",
        robot,
        "--config",
        job,
        "--data",
        other.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_ne!(stdout(&o), stdout(&from_config));
    // without files anywhere, the message says where to put them
    let o = robid(&["identify", robot, "--config", plain]);
    assert!(!o.status.success());
    let e = stderr(&o);
    assert!(
        e.contains("plain.toml:3:1: `source[1].file`: no file given") && e.contains("--data"),
        "{e}"
    );
    let o = robid(&["identify", robot]);
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains("--data: give the data file"),
        "{}",
        stderr(&o)
    );
}

/// A `[[source]]` whose `file` does not exist is named at its key in the config
/// (file:line:column), with the path as resolved against the config's folder and the fix,
/// by every command that reads the config's files (the loader's one check): it was a bare
/// "jobs/../logs/missing.csv: cannot read: no such file" naming neither the config nor the key.
#[test]
fn a_missing_source_file_is_named_at_its_key_with_the_resolved_path() {
    let dir = folder();
    let d = dir.path();
    let robot = write(d, "pendulum.toml", PENDULUM);
    std::fs::create_dir(d.join("jobs")).unwrap();
    let missing = CONFIG.replace(
        "[[source]]\n",
        "[[source]]\nfile = \"../logs/missing.csv\"\n",
    );
    let job = write(&d.join("jobs"), "job.toml", &missing);
    let with_rotor = format!("{missing}[drive.rotor]\ninertia = [0]\n");
    let rotor_job = write(&d.join("jobs"), "rotor.toml", &with_rotor);
    let params = write(d, "p.toml", "[standard]\nZZ1 = 1\nFv1 = 0.1\n");
    let (robot, job, rotor_job) = (
        robot.to_str().unwrap(),
        job.to_str().unwrap(),
        rotor_job.to_str().unwrap(),
    );
    let out = d.join("friction.toml");
    let resolved = d.join("jobs").join("../logs/missing.csv");
    let resolved = resolved.display().to_string();
    let folder = d.join("jobs").display().to_string();
    for (args, config) in [
        (vec!["identify", robot, "--config", job], "job.toml"),
        (vec!["inspect", robot, "--config", job], "job.toml"),
        (
            vec![
                "payload",
                robot,
                "--parameters",
                params.to_str().unwrap(),
                "--config",
                job,
            ],
            "job.toml",
        ),
        (
            vec![
                "friction",
                robot,
                "--config",
                rotor_job,
                "--output",
                out.to_str().unwrap(),
            ],
            "rotor.toml",
        ),
    ] {
        let o = robid(&args);
        fails_with(
            &o,
            &[
                &format!("{config}:4:1: `source[1].file`: the file {resolved} does not exist"),
                &format!("read from the config's folder {folder}"),
                "fix the path",
                "--data",
            ],
        );
    }
}

/// A config's `sample_rate` is checked against a time column of the log that it does not
/// read: `identify` and `inspect` refuse 1000 Hz for the log stamped every 2 ms, naming
/// the key, the file, the column, both rates and the fixes, and take 500 Hz.
#[test]
fn a_sample_rate_that_the_logs_time_column_contradicts_is_refused() {
    let dir = folder();
    let d = dir.path();
    let robot = write(d, "pendulum.toml", PENDULUM);
    let data = write(d, "run.csv", &log());
    let config =
        |rate: &str| CONFIG.replace("time_column = \"time\"", &format!("sample_rate = {rate}"));
    let wrong = write(d, "wrong.toml", &config("1000"));
    let right = write(d, "right.toml", &config("500"));
    let (robot, wrong, right, data) = (
        robot.to_str().unwrap(),
        wrong.to_str().unwrap(),
        right.to_str().unwrap(),
        data.to_str().unwrap(),
    );
    for command in ["identify", "inspect"] {
        let o = robid(&[command, robot, "--config", wrong, "--data", data]);
        fails_with(
            &o,
            &[&format!(
                "{wrong}:2:1: `sample_rate`: 1000 Hz, but the time column `time` of {data} \
                 steps at 500 Hz (median step 0.002 s, read as seconds): every derivative and \
                 filter would be off by a factor of 2; replace `sample_rate` by \
                 `time_column = \"time\"` to use the time stamps, or correct `sample_rate` (to \
                 500 if the time stamps are right)"
            )],
        );
        let o = robid(&[command, robot, "--config", right, "--data", data]);
        assert!(o.status.success(), "{command}: {}", stderr(&o));
    }
}

/// A forgetting factor too small to keep two equations in memory (1e-320, a subnormal
/// meant as 0, passed the config's check `0 < lambda <= 1` and overflowed the recursion
/// after the processing, naming the key but not the place) is refused with the key at its
/// file:line and the range, before any data are read.
#[test]
fn a_tiny_forgetting_factor_is_refused_at_its_key() {
    let dir = folder();
    let d = dir.path();
    let robot = write(d, "pendulum.toml", PENDULUM);
    let data = write(d, "run.csv", &log());
    let (robot, data) = (robot.to_str().unwrap(), data.to_str().unwrap());
    for (lambda, shown) in [("1e-320", "1e-320"), ("1e-3", "0.001"), ("0.4", "0.4")] {
        let text = format!("{CONFIG}[estimation]\nmethod = \"rls\"\nforgetting = {lambda}\n");
        let config = write(d, "rls.toml", &text);
        let config = config.to_str().unwrap();
        for command in ["identify", "inspect"] {
            let o = robid(&[command, robot, "--config", config, "--data", data]);
            fails_with(
                &o,
                &[&format!(
                    "{config}:10:1: `estimation.forgetting`: {shown} is outside [0.5, 1]"
                )],
            );
        }
    }
    let text = format!("{CONFIG}[estimation]\nmethod = \"rls\"\nforgetting = 0.99\n");
    let config = write(d, "rls.toml", &text);
    let o = robid(&[
        "identify",
        robot,
        "--config",
        config.to_str().unwrap(),
        "--data",
        data,
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
}

/// The printed example is a working config for a six-joint robot's log.
#[test]
fn the_example_config_is_printed_and_works() {
    let o = robid(&["identify", "--example-config"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    assert_eq!(text, robid_runtime::data::EXAMPLE_CONFIG);
    for key in [
        "[[source]]",
        "[units]",
        "[drive]",
        "[processing]",
        "[estimation]",
        "lowpass",
    ] {
        assert!(text.contains(key), "{key}");
    }
    // the README shows the same text
    let readme = std::fs::read_to_string(crate::common::manifest().join("../README.md")).unwrap();
    assert!(
        readme.contains(text.trim_end()),
        "README.md does not show the example config"
    );
    // flags other than --example-config are refused with it
    let o = robid(&["identify", "--example-config", "--method", "ols"]);
    assert!(!o.status.success());
}

/// `robid inspect` reads the same config and files as `identify` and suggests a cutoff;
/// `cutoff = "auto"` in the config makes `identify` use that cutoff and say so, and the
/// JSON report carries it.
#[test]
fn inspect_suggests_the_cutoff_that_auto_uses() {
    let dir = folder();
    let d = dir.path();
    let robot = write(d, "pendulum.toml", PENDULUM);
    write(d, "run.csv", &log());
    let auto = CONFIG
        .replace("cutoff = 5.0", "cutoff = \"auto\"")
        .replace("[[source]]\n", "[[source]]\nfile = \"run.csv\"\n");
    let config = write(d, "auto.toml", &auto);
    let (robot, config) = (robot.to_str().unwrap(), config.to_str().unwrap());
    let o = robid(&["inspect", robot, "--config", config]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    assert!(text.contains("suggested low-pass cutoff:"), "{text}");
    let o = robid(&["inspect", robot, "--config", config, "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let json: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    let cutoff = json["cutoff"]["cutoff"].as_f64().unwrap();
    assert!(cutoff > 0.0 && cutoff < 250.0, "{cutoff}");
    assert_eq!(json["joints"].as_array().unwrap().len(), 1);
    assert_eq!(json["sampling"][0]["rows"], 3000);
    let report = d.join("report.json");
    let o = robid(&[
        "identify",
        robot,
        "--config",
        config,
        "--json",
        report.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stdout(&o).contains(&format!("low-pass cutoff (auto): {cutoff} Hz")),
        "{}",
        stdout(&o)
    );
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(report).unwrap()).unwrap();
    assert_eq!(report["cutoff"]["cutoff"].as_f64(), Some(cutoff));
}

/// `simulate --currents` of a tiny torque per ampere beside a large torque noise, each
/// within its flag's range: the currents, up to 1e12 A, are beyond what robid's readers
/// accept (|current| <= 1e7, the limit `identify` applies), so the run is refused before
/// anything is written, naming the column, the flags and the value that fits; it wrote
/// the log with exit 0, which `identify` then refused. An earlier file of that name is
/// left as it was; the same flags with a fitting torque per ampere write a log that
/// `identify` reads.
#[test]
fn simulate_refuses_currents_beyond_what_the_readers_accept() {
    let dir = folder();
    let d = dir.path();
    let robot = write(d, "pendulum.toml", PENDULUM);
    let params = write(
        d,
        "p.toml",
        "[standard]\nXX1 = 0.2\nYY1 = 0.2\nZZ1 = 0.2\nMY1 = 0.5\nM1 = 2.0\n",
    );
    let mut traj = String::from("t,q1,qd1,qdd1\n");
    for k in 0..=500 {
        let t = k as f64 * 4e-3;
        traj.push_str(&format!("{t},{},{},{}\n", t.sin(), t.cos(), -t.sin()));
    }
    let traj = write(d, "traj.csv", &traj);
    let output = write(d, "log.csv", "an earlier file\n");
    let run = |currents: &str| {
        robid(&[
            "simulate",
            robot.to_str().unwrap(),
            "--parameters",
            params.to_str().unwrap(),
            "--trajectory",
            traj.to_str().unwrap(),
            "--columns",
            "positions",
            &format!("--currents={currents}"),
            "--torque-noise",
            "1e6",
            "-o",
            output.to_str().unwrap(),
        ])
    };
    for currents in ["1e-6", "-1e-6"] {
        let o = run(currents);
        fails_with(
            &o,
            &[
                "log.csv:2: column `i1` would be ",
                "outside the range |torque| <= 1e7 that robid's readers accept, so the file \
                 would be refused as data; nothing was written; the torque of joint 1 reaches ",
                &format!(
                    "(--torque-noise 1e6 N m included), and --currents gives it {currents} N m/A"
                ),
                "give --currents a value of magnitude at least ",
                "or a smaller --torque-noise",
            ],
        );
        assert_eq!(
            std::fs::read_to_string(&output).unwrap(),
            "an earlier file\n"
        );
    }
    // 1 N m/A: currents within the range, read back by identify
    let o = run("1");
    assert!(o.status.success(), "{}", stderr(&o));
    let config = write(
        d,
        "cfg.toml",
        "dof = 1\ntime_column = \"t\"\n[[source]]\nfile = \"log.csv\"\nposition = \"q{}\"\n\
         torque = \"i{}\"\n",
    );
    let o = robid(&[
        "identify",
        robot.to_str().unwrap(),
        "--config",
        config.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
}

/// `simulate --columns positions` writes t, q and torques (or currents) at a fraction of
/// the trajectory's rate, the same samples as the full record; a rate that is not a whole
/// fraction, and log flags with `--columns all`, are refused by name.
#[test]
fn simulate_writes_a_log_of_positions_and_currents() {
    let dir = folder();
    let d = dir.path();
    let robot = write(d, "pendulum.toml", PENDULUM);
    let params = write(
        d,
        "p.toml",
        "[standard]\nXX1 = 0.2\nYY1 = 0.2\nZZ1 = 0.2\nMY1 = 0.5\nM1 = 2.0\nFv1 = 0.3\n",
    );
    let mut traj = String::from("t,q1,qd1,qdd1\n");
    for k in 0..=2000 {
        let t = k as f64 * 1e-3;
        let w = 2.0;
        traj.push_str(&format!(
            "{t},{},{},{}\n",
            (w * t).sin(),
            w * (w * t).cos(),
            -w * w * (w * t).sin()
        ));
    }
    let traj = write(d, "traj.csv", &traj);
    let run = |extra: &[&str], out: &str| {
        let out = d.join(out);
        let mut args = vec![
            "simulate",
            robot.to_str().unwrap(),
            "--parameters",
            params.to_str().unwrap(),
            "--trajectory",
            traj.to_str().unwrap(),
            "--torque-noise",
            "0.01",
            "-o",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        (robid(&args), out)
    };
    let rows = |path: &std::path::Path| -> Vec<Vec<f64>> {
        std::fs::read_to_string(path)
            .unwrap()
            .lines()
            .skip(1)
            .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
            .collect()
    };
    let (o, all) = run(&[], "all.csv");
    assert!(o.status.success(), "{}", stderr(&o));
    let (o, log) = run(
        &["--columns", "positions", "--rate", "250", "--currents", "2"],
        "log.csv",
    );
    assert!(o.status.success(), "{}", stderr(&o));
    // the message counts the rows the file has, not only the samples simulated
    assert!(
        stdout(&o).contains("2001 samples simulated, 501 rows written to"),
        "{}",
        stdout(&o)
    );
    let header = std::fs::read_to_string(&log).unwrap();
    assert!(header.starts_with("t,q1,i1\n"), "{}", &header[..20]);
    let (all, log) = (rows(&all), rows(&log));
    assert_eq!(log.len(), 501);
    for (r, row) in log.iter().enumerate() {
        let full = &all[4 * r];
        assert_eq!(row[0], full[0]);
        assert_eq!(row[1], full[1]);
        // `all` is t,q1,qd1,qdd1,tau1; the current is tau / 2 (printed to 10 digits)
        assert!(
            (row[2] - full[4] / 2.0).abs() <= 1e-9 * full[4].abs().max(1.0),
            "row {r}"
        );
    }
    let (o, _) = run(&["--columns", "positions", "--rate", "300"], "bad.csv");
    assert!(
        stderr(&o).contains("--rate 300 Hz is not a whole fraction"),
        "{}",
        stderr(&o)
    );
    let (o, _) = run(&["--rate", "250"], "bad.csv");
    assert!(
        stderr(&o).contains("--rate is an option of --columns positions"),
        "{}",
        stderr(&o)
    );
    let (o, _) = run(&["--columns", "positions", "--currents", "1,2"], "bad.csv");
    assert!(
        stderr(&o).contains("--currents has 2 values"),
        "{}",
        stderr(&o)
    );
    // a motor wired the other way round: a negative torque constant, the current's sign
    // flipped; 0 is refused with the range
    let (o, flipped) = run(&["--columns", "positions", "--currents=-2"], "flipped.csv");
    assert!(o.status.success(), "{}", stderr(&o));
    for (row, full) in rows(&flipped).iter().zip(&all) {
        assert!((row[2] + full[4] / 2.0).abs() <= 1e-9 * full[4].abs().max(1.0));
    }
    let (o, _) = run(&["--columns", "positions", "--currents", "0"], "bad.csv");
    assert!(
        stderr(&o).contains("0 is outside [-1e6, -1e-6] or [1e-6, 1e6] N m/A"),
        "{}",
        stderr(&o)
    );
}

/// `identify --report` writes one self-contained HTML page; when a Chromium is installed
/// (Debian's `chromium`), it renders it headless to a screenshot that holds a drawing, not
/// an empty page. Without a browser the rendering is skipped, saying so.
#[test]
fn the_html_report_renders_in_a_browser() {
    let dir = folder();
    let d = dir.path();
    let robot = write(d, "pendulum.toml", PENDULUM);
    let data = write(d, "run.csv", &log());
    let config = write(d, "job.toml", CONFIG);
    let html = d.join("report.html");
    let o = robid(&[
        "identify",
        robot.to_str().unwrap(),
        "--config",
        config.to_str().unwrap(),
        "--data",
        data.to_str().unwrap(),
        "--validate",
        data.to_str().unwrap(),
        "--report",
        html.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).contains("HTML report:"));
    let page = std::fs::read_to_string(&html).unwrap();
    assert!(page.starts_with("<!DOCTYPE html>") && page.ends_with("</html>\n"));
    // the fit and the validation, one joint each; parameters and figures
    assert_eq!(page.matches("<svg").count(), 2);
    assert!(page.contains("ZZ1") && page.contains("relative error"));
    let Some(browser) = ["chromium", "chromium-browser", "google-chrome"]
        .into_iter()
        .find(|b| {
            std::process::Command::new(b)
                .arg("--version")
                .output()
                .is_ok_and(|o| o.status.success())
        })
    else {
        eprintln!("the_html_report_renders_in_a_browser: no Chromium installed, rendering skipped");
        return;
    };
    let shot = d.join("shot.png");
    let o = std::process::Command::new(browser)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--hide-scrollbars",
            "--window-size=1000,2400",
            &format!("--screenshot={}", shot.display()),
        ])
        .arg(format!("file://{}", html.display()))
        .output()
        .unwrap();
    assert!(shot.exists(), "{}", String::from_utf8_lossy(&o.stderr));
    // a PNG of a page with tables and plots: a blank page compresses to a few kB
    let png = std::fs::read(&shot).unwrap();
    assert!(png.starts_with(b"\x89PNG"), "not a PNG");
    assert!(
        png.len() > 30_000,
        "the screenshot is {} bytes: an empty page?",
        png.len()
    );
}

/// The pendulum log with a different noise per run (a seeded pseudo-random sequence).
fn noisy_log(seed: u64) -> String {
    let mut rng = robid_runtime::rng::Rng::new(seed);
    let mut csv = String::from("time,angle,torque\n");
    for k in 0..3000 {
        let t = k as f64 * 2e-3;
        let q = 1.2 * (1.3 * t).sin() + 0.3 * (4.1 * t).cos();
        let tau = 2.0 * q.cos() + 0.4 * (1.3 * t).cos() + 0.05 * rng.normal();
        csv.push_str(&format!("{t},{q},{tau}\n"));
    }
    csv
}

/// `[runs]` end to end: three runs averaged, each identified alone, the spread and the
/// error bound in the table and the JSON; `--data` beside `[runs]` is refused.
#[test]
fn milella_identify_repeated_runs_end_to_end() {
    let dir = folder();
    let d = dir.path();
    let robot = write(d, "pendulum.toml", PENDULUM);
    for r in 1..=3 {
        write(d, &format!("run{r}.csv"), &noisy_log(r));
    }
    let runs = format!(
        "{CONFIG}[runs]\nmode = \"averaged\"\nfiles = [\"run1.csv\", \"run2.csv\", \"run3.csv\"]\n"
    );
    let job = write(d, "runs.toml", &runs);
    let json = d.join("report.json");
    let (robot, job) = (robot.to_str().unwrap(), job.to_str().unwrap());
    let o = robid(&[
        "identify",
        robot,
        "--config",
        job,
        "--json",
        json.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let table = stdout(&o);
    assert!(table.contains("runs: 3 (averaged)"), "{table}");
    assert!(table.contains("error bound"), "{table}");
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(v["runs"]["runs"].as_array().unwrap().len(), 3);
    assert_eq!(v["runs"]["mode"], "averaged");
    // each run's fit says which torque it compares with, as the report's does (it did
    // not), and the mean record names every run's file (the first alone was named)
    for run in v["runs"]["runs"].as_array().unwrap() {
        assert!(
            run["torque"].is_string() && run["torque"] == v["fit"]["torque"],
            "{run}"
        );
    }
    let mean = v["estimation"]["file"].as_str().unwrap();
    assert!(
        mean.starts_with("the mean of ") && (1..=3).all(|r| mean.contains(&format!("run{r}.csv"))),
        "{mean}"
    );
    let bound = v["error_bound_percent"].as_f64().unwrap();
    assert!(bound > 0.0 && bound.is_finite(), "{bound}");
    let p = &v["runs"]["parameters"][0];
    assert_eq!(p["values"].as_array().unwrap().len(), 3);
    assert!(p["std"].as_f64().unwrap() > 0.0);
    // the torque spread is the noise's std, 0.05 (RMS of the sample-wise std of 3 runs)
    let t = v["runs"]["torque_std_per_joint"][0].as_f64().unwrap();
    assert!((t - 0.05).abs() < 0.005, "{t}");
    let data = d.join("run1.csv");
    let o = robid(&[
        "identify",
        robot,
        "--config",
        job,
        "--data",
        data.to_str().unwrap(),
    ]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("[runs]"), "{}", stderr(&o));
}

/// A revolute joint and a prismatic one (a slider on a turning arm).
const SLIDER: &str = "name = \"slider\"\nconvention = \"modified\"\ngravity = [0, 0, -9.81]\n\
                      drive = [\"Fv\"]\n[[joints]]\nalpha = \"pi/2\"\n[[joints]]\n\
                      type = \"prismatic\"\nalpha = \"-pi/2\"\n";

/// `units.angle = "deg"` converts the revolute joints' columns, not a prismatic joint's
/// (metres): a simulated log with joint 1 written in degrees identifies to the same
/// parameters as the log in radians, through `identify`, `inspect` (the ranges) alike. The
/// prismatic joint's 0.1 m motion was divided by 57.3 and its equations dropped as at rest.
#[test]
fn degrees_convert_the_revolute_joints_only() {
    let dir = folder();
    let d = dir.path();
    let robot = write(d, "slider.toml", SLIDER);
    let mut trajectory = String::from("t,q1,q2,qd1,qd2,qdd1,qdd2\n");
    for k in 0..2000 {
        let t = k as f64 * 0.005;
        let (s1, c1, s2, c2) = (
            (1.3 * t).sin(),
            (1.3 * t).cos(),
            (2.1 * t).sin(),
            (2.1 * t).cos(),
        );
        let row = [0.3 + 0.1 * s2, 1.3 * c1, 0.21 * c2, -1.69 * s1, -0.441 * s2];
        trajectory.push_str(&format!(
            "{t},{s1},{}\n",
            row.map(|x| x.to_string()).join(",")
        ));
    }
    let trajectory = write(d, "trajectory.csv", &trajectory);
    let parameters = write(
        d,
        "parameters.toml",
        "[standard]\nZZ1 = 0.2\nXX2 = 0.1\nYY2 = 0.1\nZZ2 = 0.02\nMZ2 = 0.3\nM2 = 2.0\nFv1 = 0.5\nFv2 = 3.0\n",
    );
    let radians = d.join("radians.csv");
    let o = robid(&[
        "simulate",
        robot.to_str().unwrap(),
        "--parameters",
        parameters.to_str().unwrap(),
        "--trajectory",
        trajectory.to_str().unwrap(),
        "-o",
        radians.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    // joint 1's columns in degrees
    let text = std::fs::read_to_string(&radians).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap();
    let names: Vec<&str> = header.split(',').collect();
    let mut degrees = format!("{header}\n");
    for line in lines {
        let row: Vec<String> = line
            .split(',')
            .zip(&names)
            .map(|(v, name)| match *name {
                "q1" | "qd1" | "qdd1" => v.parse::<f64>().unwrap().to_degrees().to_string(),
                _ => v.to_owned(),
            })
            .collect();
        degrees.push_str(&(row.join(",") + "\n"));
    }
    let degrees = write(d, "degrees.csv", &degrees);
    let config = |angle: &str| {
        write(
            d,
            &format!("{angle}.toml"),
            &format!(
                "dof = 2\ntime_column = \"t\"\n[[source]]\nposition = \"q{{}}\"\n\
                 velocity = \"qd{{}}\"\nacceleration = \"qdd{{}}\"\ntorque = \"tau{{}}\"\n\
                 [units]\nangle = \"{angle}\"\n"
            ),
        )
    };
    let identified = |config: &std::path::Path, data: &std::path::Path| {
        let report = d.join("report.json");
        let o = robid(&[
            "identify",
            robot.to_str().unwrap(),
            "--config",
            config.to_str().unwrap(),
            "--data",
            data.to_str().unwrap(),
            "--json",
            report.to_str().unwrap(),
            "--plot",
            d.join("plots").to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        // the revolute joint's figure in N m, the prismatic one's in N (both were N m)
        let svg = |j: usize| std::fs::read_to_string(d.join(format!("plots/fit_joint{j}.svg")));
        let (one, two) = (svg(1).unwrap(), svg(2).unwrap());
        assert!(one.contains("torque [N m]") && one.contains("residual [N m]"));
        assert!(two.contains("force [N]") && two.contains("residual [N]") && !two.contains("N m"));
        let report: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(report).unwrap()).unwrap();
        assert_eq!(report["joint_units"], serde_json::json!(["N m", "N"]));
        assert_eq!(report["torque_unit"], "N m and N");
        report["parameters"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| {
                (
                    p["name"].as_str().unwrap().to_owned(),
                    p["value"].as_f64().unwrap(),
                )
            })
            .collect::<Vec<_>>()
    };
    let (rad, deg) = (config("rad"), config("deg"));
    let expected = identified(&rad, &radians);
    let got = identified(&deg, &degrees);
    for ((name, e), (_, g)) in expected.iter().zip(&got) {
        assert!(
            (e - g).abs() <= 1e-6 * e.abs().max(1.0),
            "{name}: {g} against {e}"
        );
    }
    let m2 = expected.iter().find(|(n, _)| n == "M2").unwrap().1;
    assert!((m2 - 2.0).abs() < 1e-6, "{m2}");
    let o = robid(&[
        "inspect",
        robot.to_str().unwrap(),
        "--config",
        deg.to_str().unwrap(),
        "--data",
        degrees.to_str().unwrap(),
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let json: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    let range = |j: usize| json["joints"][j]["position_range"][1].as_f64().unwrap();
    assert!(
        (range(0) - 1.0).abs() < 1e-3 && (range(1) - 0.4).abs() < 1e-3,
        "{json}"
    );
}

/// `inspect` warns of positions far beyond the description's limits, naming the joint,
/// both ranges and the likely cause (degrees read as radians); within them it says nothing.
#[test]
fn inspect_warns_of_positions_beyond_the_limits() {
    let dir = folder();
    let d = dir.path();
    let limited = PENDULUM.replace(
        "alpha = 0\n",
        "alpha = 0\nlimits = { position = [-2, 2] }\n",
    );
    let robot = write(d, "pendulum.toml", &limited);
    let config = write(d, "config.toml", CONFIG);
    let radians = write(d, "radians.csv", &log());
    let degrees: String = log()
        .lines()
        .enumerate()
        .map(|(k, l)| {
            if k == 0 {
                return format!("{l}\n");
            }
            let f: Vec<&str> = l.split(',').collect();
            let q: f64 = f[1].parse().unwrap();
            format!("{},{},{}\n", f[0], q.to_degrees(), f[2])
        })
        .collect();
    let degrees = write(d, "degrees.csv", &degrees);
    let inspect = |data: &std::path::Path| {
        robid(&[
            "inspect",
            robot.to_str().unwrap(),
            "--config",
            config.to_str().unwrap(),
            "--data",
            data.to_str().unwrap(),
        ])
    };
    let o = inspect(&radians);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!stderr(&o).contains("beyond its limits"), "{}", stderr(&o));
    let o = inspect(&degrees);
    assert!(o.status.success(), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        e.contains("joint 1's positions span [")
            && e.contains("beyond its limits [-2, 2] rad")
            && e.contains("angle = \"deg\""),
        "{e}"
    );
}

/// `identify` and `inspect` warn of a joint whose positions move far beyond its velocity
/// limit: time stamps in seconds under `time_scale = 1e-3` (taken for milliseconds) made
/// the pendulum's 500 Hz log one of 500 kHz, its speeds a thousand times its own, and the
/// parameters came out 1e-6 of the truth without a word. Also when the joint rests most
/// of the record (three quarters here; a median of the speeds missed half). At the right
/// scale nothing is said.
#[test]
fn speeds_past_the_velocity_limit_are_told() {
    let dir = folder();
    let d = dir.path();
    let limited = PENDULUM.replace("alpha = 0\n", "alpha = 0\nlimits = { velocity = 3 }\n");
    let robot = write(d, "pendulum.toml", &limited);
    let right = write(d, "right.toml", CONFIG);
    let wrong = write(
        d,
        "wrong.toml",
        &CONFIG.replace("time_column", "time_scale = 1e-3\ntime_column"),
    );
    // the log after three times its length at rest (1e-5 rad of noise)
    let mut rested = String::from("time,angle,torque\n");
    for k in 0..9000 {
        let t = k as f64 * 2e-3;
        let _ = writeln!(
            rested,
            "{t},{},{}",
            0.3 + 1e-5 * (37.0 * t).sin(),
            2.0 * 0.3f64.cos()
        );
    }
    for line in log().lines().skip(1) {
        let (t, rest) = line.split_once(',').unwrap();
        let _ = writeln!(rested, "{},{rest}", t.parse::<f64>().unwrap() + 18.0);
    }
    let data = write(d, "log.csv", &rested);
    for command in ["identify", "inspect"] {
        let run = |config: &std::path::Path| {
            robid(&[
                command,
                robot.to_str().unwrap(),
                "--config",
                config.to_str().unwrap(),
                "--data",
                data.to_str().unwrap(),
            ])
        };
        let o = run(&right);
        assert!(o.status.success(), "{}", stderr(&o));
        assert!(!stderr(&o).contains("move faster than"), "{}", stderr(&o));
        let e = stderr(&run(&wrong));
        assert!(
            e.contains("warning: joint 1's positions move faster than ")
                && e.contains("times its velocity limit 3 rad/s in ")
                && e.contains("`time_scale`"),
            "{command}: {e}"
        );
    }
}

/// `identify` and `inspect` warn of a velocity column in other units than the positions:
/// the pendulum's velocities in degrees per second beside positions in radians (the
/// viscous friction came out 57 times too small without a word), and negated, also over
/// the segments of a record cut at a gap. The derivative itself passes.
#[test]
fn a_velocity_column_in_other_units_is_told() {
    let dir = folder();
    let d = dir.path();
    let robot = write(d, "pendulum.toml", PENDULUM);
    let config = write(
        d,
        "config.toml",
        &CONFIG.replace("torque = ", "velocity = [\"rate\"]\ntorque = "),
    );
    // the log with a velocity column `rate(t, qd)`, qd the positions' derivative
    let with_column =
        |rate: &dyn Fn(f64, f64) -> f64| log_with("rate", &|t, [qd, _]| vec![rate(t, qd)]);
    let with_velocity = |scale: f64| with_column(&|_, qd| scale * qd);
    for command in ["identify", "inspect"] {
        let run = |name: &str, scale: f64| {
            let data = write(d, name, &with_velocity(scale));
            robid(&[
                command,
                robot.to_str().unwrap(),
                "--config",
                config.to_str().unwrap(),
                "--data",
                data.to_str().unwrap(),
            ])
        };
        let o = run("radians.csv", 1.0);
        assert!(o.status.success(), "{}", stderr(&o));
        assert!(!stderr(&o).contains("velocity column"), "{}", stderr(&o));
        let o = run("degrees.csv", 1f64.to_degrees());
        assert!(o.status.success(), "{}", stderr(&o));
        let e = stderr(&o);
        assert!(
            e.contains(
                "warning: joint 1's velocity column is 57.3 times the derivative of its positions"
            ) && e.contains("are the velocities in degrees per second")
                && e.contains("`velocity = \"differentiate\"`"),
            "{command}: {e}"
        );
        let e = stderr(&run("negated.csv", -1.0));
        assert!(
            e.contains("joint 1's velocity column is -1 times the derivative")
                && e.contains("of the opposite sign"),
            "{command}: {e}"
        );
    }
    // identify's JSON and HTML reports hold the data's warnings too, told once on stderr
    let (json, html) = (d.join("degrees.json"), d.join("degrees.html"));
    let data = write(d, "degrees.csv", &with_velocity(1f64.to_degrees()));
    let o = robid(&[
        "identify",
        robot.to_str().unwrap(),
        "--config",
        config.to_str().unwrap(),
        "--data",
        data.to_str().unwrap(),
        "--json",
        json.to_str().unwrap(),
        "--report",
        html.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let told = "joint 1's velocity column is 57.3 times";
    assert_eq!(stderr(&o).matches(told).count(), 1, "{}", stderr(&o));
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let warnings = report["warnings"].as_array().unwrap();
    let data = warnings
        .iter()
        .find(|w| w["message"].as_str().unwrap().contains(told));
    assert_eq!(
        data.map(|w| &w["kind"]),
        Some(&"data".into()),
        "{warnings:?}"
    );
    assert!(std::fs::read_to_string(&html).unwrap().contains(told));
    // inspect's table and JSON show each column's scale and correlation
    let inspect = |name: &str, column: &str, json: bool| {
        let data = write(d, name, column);
        let (robot, config, data) = (robot.to_str(), config.to_str(), data.to_str());
        let mut args = vec!["inspect", robot.unwrap(), "--config", config.unwrap()];
        args.extend(["--data", data.unwrap()]);
        if json {
            args.push("--json");
        }
        let o = robid(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        stdout(&o)
    };
    let joint_line = |table: &str| {
        let line = table.lines().find(|l| l.trim_start().starts_with("1  yes"));
        line.unwrap_or_else(|| panic!("{table}")).to_string()
    };
    assert!(joint_line(&inspect("radians.csv", &with_velocity(1.0), false)).ends_with("  1"));
    let degrees = inspect("degrees.csv", &with_velocity(1f64.to_degrees()), false);
    assert!(joint_line(&degrees).ends_with("  57.3"), "{degrees}");
    let unrelated = with_column(&|t, _| (7.3 * t).sin());
    let table = inspect("unrelated.csv", &unrelated, false);
    assert!(joint_line(&table).contains("  r "), "{table}");
    let json: serde_json::Value = serde_json::from_str(&inspect(
        "degrees.csv",
        &with_velocity(1f64.to_degrees()),
        true,
    ))
    .unwrap();
    let joint = &json["joints"][0];
    let scale = joint["velocity_scale"].as_f64().unwrap();
    assert!((scale / 1f64.to_degrees() - 1.0).abs() < 1e-3, "{joint}");
    assert!(
        joint["velocity_correlation"].as_f64().unwrap() > 0.999,
        "{joint}"
    );
    let json = inspect("unrelated.csv", &unrelated, true);
    let json: serde_json::Value = serde_json::from_str(&json).unwrap();
    let correlation = json["joints"][0]["velocity_correlation"].as_f64().unwrap();
    assert!(correlation.abs() < 0.5, "{json}");
    // a record cut at a gap (`gaps = "split"`): the segments' sums joined
    let config = std::fs::read_to_string(&config).unwrap();
    let e = identify_split_at_a_gap(
        d,
        robot.to_str().unwrap(),
        &config,
        &with_velocity(1f64.to_degrees()),
    );
    assert_eq!(
        e.matches("joint 1's velocity column is 57.3 times").count(),
        1,
        "{e}"
    );
}

/// An acceleration column in degrees per second squared beside velocities in radians per
/// second, or of zeros beside a velocity that changes (a dead channel: an inertia of 1e13
/// was fitted to such a column with exit 0), is told by identify and inspect; the log's
/// own derivatives are not.
#[test]
fn an_acceleration_column_in_other_units_or_dead_is_told() {
    let dir = folder();
    let d = dir.path();
    let robot = write(d, "pendulum.toml", PENDULUM);
    let columns = "velocity = [\"rate\"]\nacceleration = [\"rate2\"]\ntorque = ";
    let config = write(d, "config.toml", &CONFIG.replace("torque = ", columns));
    let with_acceleration =
        |scale: f64| log_with("rate,rate2", &|_, [qd, qdd]| vec![qd, scale * qdd]);
    for command in ["identify", "inspect"] {
        let run = |name: &str, scale: f64| {
            let data = write(d, name, &with_acceleration(scale));
            let (robot, config, data) = (robot.to_str(), config.to_str(), data.to_str());
            let o = robid(
                &[command, robot.unwrap(), "--config", config.unwrap()]
                    .into_iter()
                    .chain(["--data", data.unwrap()])
                    .collect::<Vec<_>>(),
            );
            // identify refuses the dead column's data (rank deficient: ZZ1 unexcited)
            assert!(o.status.success() || scale == 0.0, "{}", stderr(&o));
            stderr(&o)
        };
        let e = run("radians.csv", 1.0);
        assert!(!e.contains("column"), "{command}: {e}");
        let e = run("degrees.csv", 1f64.to_degrees());
        assert!(
            e.contains(
                "joint 1's acceleration column is 57.3 times the derivative of its velocity column"
            ) && e.contains("are the accelerations in degrees per second squared")
                && e.contains("`acceleration = \"differentiate\"`"),
            "{command}: {e}"
        );
        let e = run("dead.csv", 0.0);
        assert!(
            e.contains("joint 1's acceleration column is 0 over the whole record while its velocity column changes: a dead channel"),
            "{command}: {e}"
        );
    }
}

/// [`log`] with the columns `names` (comma-separated) between the angle and the torque,
/// `columns(t, [qd, qdd])` at each time t, qd and qdd the angle's exact derivatives.
fn log_with(names: &str, columns: &dyn Fn(f64, [f64; 2]) -> Vec<f64>) -> String {
    let mut csv = format!("time,angle,{names},torque\n");
    for line in log().lines().skip(1) {
        let f: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
        let t = f[0];
        let qd = 1.2 * 1.3 * (1.3 * t).cos() - 0.3 * 4.1 * (4.1 * t).sin();
        let qdd = -1.2 * 1.3 * 1.3 * (1.3 * t).sin() - 0.3 * 4.1 * 4.1 * (4.1 * t).cos();
        let values: Vec<String> = columns(t, [qd, qdd]).iter().map(f64::to_string).collect();
        let _ = writeln!(csv, "{t},{},{},{}", f[1], values.join(","), f[2]);
    }
    csv
}

/// `identify` of the pendulum `robot` (a path) with `config` (its text) and `gaps =
/// "split"`, on `log` (a CSV's text) less rows 1001 to 1400: the record cut at that gap
/// into segments. Its standard error, the run checked to succeed over segments.
fn identify_split_at_a_gap(dir: &std::path::Path, robot: &str, config: &str, log: &str) -> String {
    let gapped: String = log
        .lines()
        .enumerate()
        .filter(|(k, _)| !(1001..1401).contains(k))
        .map(|(_, l)| format!("{l}\n"))
        .collect();
    let gapped = write(dir, "gapped.csv", &gapped);
    let split = write(
        dir,
        "split.toml",
        &config.replace("[processing]\n", "[processing]\ngaps = \"split\"\n"),
    );
    let o = robid(&[
        "identify",
        robot,
        "--config",
        split.to_str().unwrap(),
        "--data",
        gapped.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).contains("segment"), "{}", stdout(&o));
    stderr(&o)
}

/// `identify` warns of positions far beyond the description's limits as `inspect` does
/// (the same words), from the extremes the loader keeps: the record kept on disk (one
/// file), a record cut at its gaps (`gaps = "split"`, over its segments), each run of
/// `[runs]` (loaded in memory, named with its file) and each `--validate` data set; the
/// identification goes on. Within the limits it says nothing.
#[test]
fn identify_warns_of_positions_beyond_the_limits() {
    let dir = folder();
    let d = dir.path();
    let limited = PENDULUM.replace(
        "alpha = 0\n",
        "alpha = 0\nlimits = { position = [-2, 2] }\n",
    );
    let robot = write(d, "pendulum.toml", &limited);
    let config = write(d, "config.toml", CONFIG);
    let radians = write(d, "radians.csv", &log());
    let degrees: String = log()
        .lines()
        .enumerate()
        .map(|(k, l)| {
            if k == 0 {
                return format!("{l}\n");
            }
            let f: Vec<&str> = l.split(',').collect();
            let q: f64 = f[1].parse().unwrap();
            format!("{},{},{}\n", f[0], q.to_degrees(), f[2])
        })
        .collect();
    let degrees = write(d, "degrees.csv", &degrees);
    write(
        d,
        "degrees2.csv",
        &std::fs::read_to_string(&degrees).unwrap(),
    );
    let runs = write(
        d,
        "runs.toml",
        &format!("{CONFIG}[runs]\nfiles = [\"radians.csv\", \"degrees2.csv\"]\n"),
    );
    let (robot, config, radians, degrees, runs) = (
        robot.to_str().unwrap(),
        config.to_str().unwrap(),
        radians.to_str().unwrap(),
        degrees.to_str().unwrap(),
        runs.to_str().unwrap(),
    );
    let warned = |e: &str| {
        e.contains("joint 1's positions span [")
            && e.contains("beyond its limits [-2, 2] rad in ")
            && e.contains("angle = \"deg\"")
    };
    let o = robid(&["identify", robot, "--config", config, "--data", radians]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!stderr(&o).contains("beyond its limits"), "{}", stderr(&o));
    // the record kept on disk
    let o = robid(&["identify", robot, "--config", config, "--data", degrees]);
    assert!(o.status.success(), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        warned(&e) && e.contains("warning: joint 1's positions"),
        "{e}"
    );
    assert_eq!(e.matches("beyond its limits").count(), 1, "{e}");
    // validation data
    let o = robid(&[
        "identify",
        robot,
        "--config",
        config,
        "--data",
        radians,
        "--validate",
        degrees,
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        warned(&e) && e.contains(&format!("warning: --validate {degrees}: joint 1's")),
        "{e}"
    );
    assert_eq!(e.matches("beyond its limits").count(), 1, "{e}");
    // a record cut at its gaps (`gaps = "split"`): over its segments
    let e = identify_split_at_a_gap(d, robot, CONFIG, &std::fs::read_to_string(degrees).unwrap());
    assert!(
        warned(&e) && e.contains("warning: joint 1's positions"),
        "{e}"
    );
    assert_eq!(e.matches("beyond its limits").count(), 1, "{e}");
    // the second of two runs
    let o = robid(&["identify", robot, "--config", runs]);
    assert!(o.status.success(), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        warned(&e) && e.contains("warning: run 2 (") && e.contains("degrees2.csv): joint 1's"),
        "{e}"
    );
    assert_eq!(e.matches("beyond its limits").count(), 1, "{e}");
}

/// `simulate` keeps a light link with Coulomb friction on its reference: the planar 2R
/// pendulum (`tests/fixtures/pendulum2.toml`) whose second link is a gripper's jaw (12 g,
/// 1.6e-5 kg m^2 about its joint, `Fc2` 0.07 N m, as the SO-101's), both joints out and back
/// and then at rest. The controller fed the Coulomb friction forward at the reference's
/// velocity, and the jaw chattered about zero velocity wherever the two velocities differed
/// in sign (the SO-101's jaw ended 0.14 rad off its resting reference at 2.4 rad/s, with
/// accelerations of 16,833 rad/s^2); it is fed forward at the joint's own velocity now.
#[test]
fn simulate_keeps_a_light_link_with_coulomb_friction_on_its_reference() {
    let dir = folder();
    let d = dir.path();
    let params = write(
        d,
        "p.toml",
        "[standard]\nXX1 = 0.01\nYY1 = 0.3\nZZ1 = 0.3\nMX1 = 0.5\nM1 = 2.0\nFv1 = 0.3\nFc1 = 0.5\n\
         XX2 = 1e-6\nYY2 = 1.6e-5\nZZ2 = 1.6e-5\nMX2 = 1e-4\nM2 = 0.012\nFv2 = 0.002\n\
         Fc2 = 0.07\n",
    );
    // 0.25 a (1 - cos(2 pi t / 3))^2 over 3 s, then 1 s at rest, at 500 Hz
    let w = std::f64::consts::TAU / 3.0;
    let mut traj = String::from("t,q1,q2,qd1,qd2,qdd1,qdd2\n");
    let mut largest = [0.0_f64; 2];
    for k in 0..2000 {
        let t = k as f64 / 500.0;
        let (s, c) = if t < 3.0 {
            (w * t).sin_cos()
        } else {
            (0.0, 1.0)
        };
        let state = |a: f64| {
            [
                0.25 * a * (1.0 - c).powi(2),
                0.5 * a * w * (1.0 - c) * s,
                0.5 * a * w * w * (s * s + (1.0 - c) * c),
            ]
        };
        let (a, b) = (state(0.6), state(-0.9));
        largest[0] = largest[0].max(a[2].abs());
        largest[1] = largest[1].max(b[2].abs());
        traj.push_str(&format!(
            "{t},{},{},{},{},{},{}\n",
            a[0], b[0], a[1], b[1], a[2], b[2]
        ));
    }
    let reference = write(d, "traj.csv", &traj);
    let out = d.join("sim.csv");
    let o = robid(&[
        "simulate",
        &crate::common::asset("tests/fixtures/pendulum2.toml"),
        "--parameters",
        params.to_str().unwrap(),
        "--trajectory",
        reference.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let rows = |text: &str| -> Vec<Vec<f64>> {
        text.lines()
            .skip(1)
            .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
            .collect()
    };
    let (sim, traj) = (rows(&std::fs::read_to_string(&out).unwrap()), rows(&traj));
    assert_eq!(sim.len(), 2000);
    // columns t, q1, q2, qd1, qd2, qdd1, qdd2 (and tau1, tau2 in the simulation)
    for j in 0..2 {
        let error = sim
            .iter()
            .zip(&traj)
            .map(|(s, r)| (s[1 + j] - r[1 + j]).abs())
            .fold(0.0, f64::max);
        let qdd = sim.iter().map(|s| s[5 + j].abs()).fold(0.0, f64::max);
        let rest = sim[1999][3 + j].abs();
        // measured 5.0e-11 rad off (as written, 10 digits), |qdd| the reference's, 4e-39
        // rad/s at rest; with the friction fed forward at the reference's velocity joint 2
        // was 0.071 rad off, |qdd| 4,566 rad/s^2 for 3.95, 0.15 rad/s at rest (joint 1,
        // 1.5e-5 rad off)
        assert!(
            error < 1e-8 && qdd < 1.01 * largest[j] && rest < 1e-6,
            "joint {}: {error} rad off, |qdd| up to {qdd} for the reference's {}, at {rest} \
             rad/s at rest",
            j + 1,
            largest[j]
        );
    }
}

/// An extra column named like a standard parameter of the model (the pendulum's `XX1`,
/// which no base parameter is named after: it has no effect on one joint about z) is
/// refused at its key: identify accepted it, and `robid feasible` then read the result's
/// `XX1` as the link's inertia and refused it. A base parameter's name (`Fv1`) was refused
/// already; a name the model does not have is an extra column.
#[test]
fn an_extra_column_named_like_a_standard_parameter_is_refused() {
    let dir = folder();
    let d = dir.path();
    let robot = write(d, "pendulum.toml", PENDULUM);
    let data = write(d, "run.csv", &log());
    let extra = |name: &str| {
        format!(
            "{CONFIG}[[extra_column]]\nname = \"{name}\"\n\
             terms = [{{ row = 1, signal = \"constant\" }}]\n"
        )
    };
    let identify = |name: &str| {
        let config = write(d, "extra.toml", &extra(name));
        robid(&[
            "identify",
            robot.to_str().unwrap(),
            "--config",
            config.to_str().unwrap(),
            "--data",
            data.to_str().unwrap(),
        ])
    };
    for name in ["XX1", "Fv1"] {
        fails_with(
            &identify(name),
            &[&format!(
                "`extra_column[1].name`: `{name}` is already a parameter (a standard or base \
                 parameter of the model"
            )],
        );
    }
    let o = identify("offset1");
    assert!(o.status.success(), "{}", stderr(&o));
}

/// An error about the method set by `--method` names the flag: the energy model with an
/// extra column blamed `estimation.method` at the config's line of `method = "wls"`, the
/// value the flag replaced (and at no line when the file gave no method).
#[test]
fn an_error_about_the_method_of_the_flag_names_the_flag() {
    let dir = folder();
    let d = dir.path();
    let robot = write(d, "pendulum.toml", PENDULUM);
    let data = write(d, "run.csv", &log());
    let extra = "[[extra_column]]\nname = \"offset1\"\n\
                 terms = [{ row = 1, signal = \"constant\" }]\n";
    for method in ["", "[estimation]\nmethod = \"wls\"\n"] {
        let config = write(d, "extra.toml", &format!("{CONFIG}{extra}{method}"));
        let o = robid(&[
            "identify",
            robot.to_str().unwrap(),
            "--config",
            config.to_str().unwrap(),
            "--data",
            data.to_str().unwrap(),
            "--method",
            "energy",
        ]);
        fails_with(
            &o,
            &[
                "error: --method energy: the energy model has no power term for the extra \
               column `offset1`",
            ],
        );
        assert!(!stderr(&o).contains("estimation.method"), "{}", stderr(&o));
    }
}

/// `processing.validation_range` with no `--validate` file applies to nothing: said at its
/// place (it was silent), and not said when validation files are given.
#[test]
fn a_validation_range_without_validation_files_is_said() {
    let dir = folder();
    let config = write(
        dir.path(),
        "c.toml",
        "time_column = \"t\"\n[processing]\nvalidation_range = [0, 100]\n",
    );
    let data = write(dir.path(), "d.csv", "t,q1\n0,0\n");
    let run = |extra: &[&str]| {
        let mut args = vec![
            "identify",
            "descriptions/ur5e.toml",
            "--config",
            config.to_str().unwrap(),
            "--data",
            data.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        stderr(&robid(&args))
    };
    let said = "c.toml:3:1: `processing.validation_range` is not applied by `robid identify` \
                (it cuts the --validate files, and none is given)";
    assert!(run(&[]).contains(said), "{}", run(&[]));
    let e = run(&["--validate", data.to_str().unwrap()]);
    assert!(!e.contains("is not applied"), "{e}");
}

/// `inspect` on a record too short for its spectra says what it needs at the first try: a
/// file of one row said "at least 2 are needed", and of two rows then "at least 64".
#[test]
fn inspect_asks_for_the_samples_its_spectra_need_at_once() {
    let dir = folder();
    let header = "t,q1,qd1,qdd1,tau1\n";
    for rows in [1, 2, 3] {
        let text: String = (0..rows)
            .map(|k| format!("{},0.1,0,0,1\n", 0.01 * k as f64))
            .collect();
        let data = write(dir.path(), "short.csv", &(header.to_owned() + &text));
        let robot = write(dir.path(), "pendulum.toml", PENDULUM);
        let o = robid(&[
            "inspect",
            robot.to_str().unwrap(),
            "--data",
            data.to_str().unwrap(),
        ]);
        fails_with(
            &o,
            &[
                "short.csv",
                &format!("{rows} sample"),
                "at least 64 are needed",
            ],
        );
    }
}

/// A TOML syntax error in a config (and in every TOML file of robid's but descriptions,
/// which were already told so) is told at its file:line:column, as descriptions are,
/// without toml's copy of the line: a `trim = 5 xxx..` line of 100,000 characters made
/// 200 kB of stderr (the line, then as many carets), "TOML parse error at line 7, column 8"
/// its only place.
#[test]
fn a_syntax_error_is_told_at_its_place_without_the_line() {
    let dir = folder();
    let d = dir.path();
    let robot = write(d, "pendulum.toml", PENDULUM);
    write(d, "log.csv", &log());
    let long = format!("{CONFIG}trim = 5 {}\n", "x".repeat(100_000));
    let cfg = write(d, "cfg.toml", &long);
    let o = robid(&[
        "identify",
        robot.to_str().unwrap(),
        "--config",
        cfg.to_str().unwrap(),
        "--data",
        d.join("log.csv").to_str().unwrap(),
    ]);
    let place = format!("{}:8:8: invalid config: ", cfg.display());
    fails_with(&o, &[&place]);
    let e = stderr(&o);
    assert!(e.len() < 1000, "{} bytes: {}", e.len(), &e[..300]);
}
