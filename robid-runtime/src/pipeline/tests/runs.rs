//! Repeated acquisitions (`[runs]`) of the synthetic trajectory with different noise.

use std::path::Path;

use super::milella::relative_error;
use super::synthetic::{CONFIG, DOF, Synthetic, csv_seeded};
use crate::data::{Config, RunMode, load_runs};
use crate::error::Error;
use crate::pipeline::{average, identify_runs};
use crate::report::{Report, text_table};

/// Runs of the synthetic trajectory (`samples` each, torque noise 0.5) written to a fresh
/// folder, and a config listing them with `mode`.
fn runs_config(samples: &[usize], mode: &str) -> (Config, tempfile::TempDir) {
    let folder = tempfile::tempdir().unwrap();
    let dir = folder.path();
    let mut files = Vec::new();
    for (r, &n) in samples.iter().enumerate() {
        let file = format!("run{}.csv", r + 1);
        std::fs::write(
            dir.join(&file),
            csv_seeded(n, 1000.0, [0.5; DOF], 100 + r as u64),
        )
        .unwrap();
        files.push(format!("\"{file}\""));
    }
    let text = format!(
        "{CONFIG}\n[runs]\nmode = \"{mode}\"\nfiles = [{}]\n",
        files.join(", ")
    );
    std::fs::write(dir.join("runs.toml"), &text).unwrap();
    let config = Config::from_toml_str(&text, &dir.join("runs.toml")).unwrap();
    (config, folder)
}

/// Eight runs identified alone: the spread of their values agrees with the standard
/// deviation each run reports, and stacking them divides it by sqrt(8).
#[test]
fn milella_run_spread_agrees_with_the_reported_std() {
    let r = 8;
    let (config, dir) = runs_config(&[20_000; 8], "stacked");
    let data = load_runs(&config, DOF).unwrap();
    drop(dir);
    assert_eq!(data.len(), r);
    let id = identify_runs(&Synthetic::default(), &data, &config).unwrap();
    assert_eq!(id.mode, RunMode::Stacked);
    assert_eq!(id.runs.len(), r);
    let s = &id.spread;
    let mut ratios: Vec<f64> = s
        .std
        .iter()
        .zip(&s.reported_std)
        .map(|(a, b)| a / b)
        .collect();
    ratios.sort_by(f64::total_cmp);
    let median = ratios[ratios.len() / 2];
    // the sample std of 8 values over the true std is sqrt(chi^2_7 / 7): within
    // [0.376, 1.70] with probability 99 % (measured median 1.007 over the 48 parameters, range 0.49 to 1.55)
    eprintln!(
        "run spread / reported std: median {median:.3}, range {:.3} to {:.3}",
        ratios[0],
        ratios[ratios.len() - 1]
    );
    assert!((0.376..1.70).contains(&median), "{median}");
    // stacked: 8 times the equations of one run with the same noise, the std falls by
    // sqrt(8) up to the scatter of the residual variance (measured 1 + 8.5e-5 for every
    // parameter)
    let mut stacked: Vec<f64> = id
        .estimate
        .std
        .iter()
        .zip(&s.reported_std)
        .map(|(a, b)| a * (r as f64).sqrt() / b)
        .collect();
    stacked.sort_by(f64::total_cmp);
    eprintln!(
        "stacked std x sqrt(8) / reported std: {:.4} to {:.4}",
        stacked[0],
        stacked[stacked.len() - 1]
    );
    assert!(
        stacked[0] > 1.0 - 1.7e-4 && stacked[stacked.len() - 1] < 1.0 + 1.7e-4,
        "{stacked:?}"
    );
    // the torque spread is the noise's: uniform of amplitude 0.5, std 0.5 / sqrt(12) =
    // 0.144 on every joint (the drive chain is the identity), pooled over 20 000 samples
    // of 7 degrees of freedom: 4 standard errors of a normal sample's std, sigma /
    // sqrt(2 dof), bound it (the uniform's lighter tails only narrow it; measured 2.5e-4
    // at worst)
    let t = s.torque_std.as_ref().unwrap();
    let sigma = 0.5 / 12f64.sqrt();
    let se = sigma / (2.0 * 20_000.0 * 7.0f64).sqrt();
    for v in t {
        assert!((v - sigma).abs() < 4.0 * se, "{t:?}");
    }
    // the report carries it all
    let report = Report::from_runs(&id, |_| None);
    report.check().unwrap();
    let runs = report.runs.as_ref().unwrap();
    assert_eq!((runs.mode.as_str(), runs.runs.len()), ("stacked", r));
    assert_eq!(
        runs.parameters[3].values,
        s.values.iter().map(|v| v[3]).collect::<Vec<_>>()
    );
    let json: serde_json::Value = serde_json::from_str(&report.to_json()).unwrap();
    assert_eq!(json["runs"]["parameters"][0]["std"], s.std[0]);
    assert!(report.estimation.is_none());
    let table = text_table(&report);
    assert!(table.contains("runs: 8 (stacked)"), "{table}");
    assert!(table.contains("torque spread across the runs"), "{table}");
    let html = crate::report::html_report(&report, &[]).unwrap();
    assert!(html.contains("Repeated acquisitions"));
}

/// Averaging eight runs: the noise of the estimate falls by sqrt(8), and with one time
/// grid the averaged estimate equals the stacked one (the processing is linear in the
/// torque and the positions of the runs are the same).
#[test]
fn milella_averaged_runs_lower_the_noise_by_sqrt_r() {
    let r = 8.0f64;
    let (config, dir) = runs_config(&[20_000; 8], "averaged");
    let data = load_runs(&config, DOF).unwrap();
    drop(dir);
    let averaged = identify_runs(&Synthetic::default(), &data, &config).unwrap();
    assert_eq!(averaged.mode, RunMode::Averaged);
    assert!(averaged.used.is_some());
    // the mean of 8 noises has 1 / sqrt(8) of their std, and so has the estimate's std
    // (measured (1 - 3.0e-3) / sqrt(8) of one run's, for every parameter)
    let mut ratios: Vec<f64> = averaged
        .estimate
        .std
        .iter()
        .zip(&averaged.spread.reported_std)
        .map(|(a, b)| a * r.sqrt() / b)
        .collect();
    ratios.sort_by(f64::total_cmp);
    eprintln!(
        "averaged std x sqrt(8) / one run's: {:.4} to {:.4}",
        ratios[0],
        ratios[ratios.len() - 1]
    );
    assert!(
        ratios[0] > 1.0 - 6e-3 && ratios[ratios.len() - 1] < 1.0 + 6e-3,
        "{ratios:?}"
    );
    // the distance to the truth: one run's against the mean's, about 1 / sqrt(8) = 0.354
    // (measured 5.56e-4 against 1.60e-3, 0.348, seeded); the bound is twice that
    let single: f64 = averaged
        .runs
        .iter()
        .map(|id| relative_error(&id.estimate.values))
        .sum::<f64>()
        / r;
    let mean = relative_error(&averaged.estimate.values);
    eprintln!("relative error: one run {single:.3e} on average, the averaged runs {mean:.3e}");
    assert!(mean < 0.69 * single, "{mean} vs {single}");
    let mut stacked_config = config.clone();
    stacked_config.runs.as_mut().unwrap().mode = RunMode::Stacked;
    let stacked = identify_runs(&Synthetic::default(), &data, &stacked_config).unwrap();
    for (a, b) in averaged
        .estimate
        .values
        .iter()
        .zip(&stacked.estimate.values)
    {
        // rounding only (measured 5.3e-12 relative at worst)
        assert!((a - b).abs() < 1e-11 * a.abs().max(1.0), "{a} vs {b}");
    }
}

/// Runs of different lengths cannot be averaged (the error names the run), can be
/// stacked; a single run or a wrong file count is refused by the config check.
#[test]
fn milella_runs_bad_input() {
    let (config, dir) = runs_config(&[20_000, 20_000, 18_000], "averaged");
    let data = load_runs(&config, DOF).unwrap();
    let e = identify_runs(&Synthetic::default(), &data, &config).unwrap_err();
    assert!(
        e.to_string().contains("runs.files[3]") && e.to_string().contains("18000 samples"),
        "{e}"
    );
    assert!(
        matches!(average(&data[1..]), Err(Error::Setting { key, .. }) if key == "runs.files[2]")
    );
    let mut stacked = config.clone();
    stacked.runs.as_mut().unwrap().mode = RunMode::Stacked;
    let id = identify_runs(&Synthetic::default(), &data, &stacked).unwrap();
    assert!(id.spread.torque_std.is_none());
    let text = std::fs::read_to_string(dir.path().join("runs.toml")).unwrap();
    drop(dir);
    for (bad, key) in [
        (
            text.replace("files = [\"run1.csv\", ", "files = [")
                .replace(", \"run3.csv\"", ""),
            "runs.files",
        ),
        (
            text.replace("\"run2.csv\"", "[\"run2.csv\", \"x.csv\"]"),
            "runs.files[2]",
        ),
        (
            text.replace("mode = \"averaged\"", "mode = \"stacked\"")
                .replace("[runs]", "[estimation]\nmethod = \"energy\"\n[runs]"),
            "runs.mode",
        ),
    ] {
        let cfg = Config::from_toml_str(&bad, Path::new("r.toml")).unwrap();
        let e = cfg.check(DOF).unwrap_err();
        assert!(
            matches!(&e, Error::Data(crate::DataError::ConfigKey { key: k, line: Some(_), .. }) if k == key),
            "{key}: {e}"
        );
    }
    let e = identify_runs(&Synthetic::default(), &data[..1], &config).unwrap_err();
    assert!(e.to_string().contains("at least two"), "{e}");
}

/// An error that arises from one run's data names the run, its entry `runs.files[i]` at its
/// line and column and its file, whichever way the runs are combined (a short run among
/// long ones used to give "rank-deficient data" alone); an error of loading does too.
#[test]
fn an_error_of_one_run_names_the_run() {
    // `files = [...]` is the last line of the config; "run3.csv" its third entry
    let named = |e: &Error, dir: &tempfile::TempDir| {
        let text = std::fs::read_to_string(dir.path().join("runs.toml")).unwrap();
        let line = text.lines().count();
        let column = text.lines().last().unwrap().find("\"run3.csv\"").unwrap() + 1;
        let at = format!("runs.toml:{line}:{column}: `runs.files[3]` (run3.csv): ");
        matches!(e, Error::Run { error, .. } if !matches!(**error, Error::Run { .. }))
            && e.to_string().contains(&at)
    };
    // too short to excite every parameter alone, not in the stack
    let (config, dir) = runs_config(&[20_000, 20_000, 600], "stacked");
    let data = load_runs(&config, DOF).unwrap();
    let e = identify_runs(&Synthetic::default(), &data, &config).unwrap_err();
    assert!(named(&e, &dir), "{e}");
    let Error::Run { error, .. } = &e else {
        unreachable!()
    };
    // the run's own error is kept, for programs that act on its kind
    assert!(error.to_string().starts_with("rank-deficient data"), "{e}");
    // too short for the trim: the stacked equations alone, dense and streaming
    let (config, dir) = runs_config(&[20_000, 20_000, 300], "stacked");
    let data = load_runs(&config, DOF).unwrap();
    let e = crate::pipeline::runs::stacked_dense(&Synthetic::default(), &data, &config)
        .err()
        .unwrap();
    assert!(named(&e, &dir), "{e}");
    let e = crate::pipeline::stream::stacked_streaming(&Synthetic::default(), &data, &config)
        .err()
        .unwrap();
    assert!(named(&e, &dir), "{e}");
    // a run in which no joint moves: every equation removed by processing.rest_velocity
    let mut still = data.clone();
    let q = crate::signal::Signals::from_fn(DOF, 3000, |j, _| 0.1 * j as f64);
    let tau = crate::signal::Signals::from_fn(DOF, 3000, |_, _| 1.0);
    still[2] = crate::data::Dataset::new("run3.csv", 1e-3, q, tau).unwrap();
    let e = identify_runs(&Synthetic::default(), &still, &config).unwrap_err();
    assert!(named(&e, &dir), "{e}");
    assert!(
        e.to_string()
            .contains("`processing.rest_velocity`: no joint moves in these data"),
        "{e}"
    );
    // loading: a run whose file is not there
    std::fs::remove_file(dir.path().join("run3.csv")).unwrap();
    let e = load_runs(&config, DOF).unwrap_err();
    assert!(named(&e, &dir), "{e}");
}

/// A run too short for the processing among long ones is refused before any run is
/// identified, named with its file and rows and the samples the processing needs (and
/// what takes them), in both modes. It used to fail only when its turn came, after the
/// runs before it, by the first step that ran out ("run3.csv after trimming 200 samples
/// at each end ...: 0 samples, at least 2 are needed"), or here by the first run's
/// rank deficiency.
#[test]
fn a_run_too_short_for_the_processing_is_named_with_its_rows_first() {
    // run 1 is too short to excite every parameter (an error of its identification),
    // run 3 too short for the processing
    for mode in ["stacked", "averaged"] {
        let (config, dir) = runs_config(&[600, 20_000, 3], mode);
        let data = load_runs(&config, DOF).unwrap();
        let e = identify_runs(&Synthetic::default(), &data, &config).unwrap_err();
        let Error::Run { error, .. } = &e else {
            panic!("{e}")
        };
        // 200 trimmed at each end (the 20 Hz low-pass settles in fewer), then 9 samples
        // of 6 equations for more than 48 parameters, one in 10 kept by the decimation,
        // whose filter leaves one unsettled at each end: 101
        assert!(
            matches!(
                **error,
                Error::TooFewSamples {
                    found: 3,
                    required: 501,
                    ..
                }
            ),
            "{mode}: {e}"
        );
        let file = dir.path().join("run3.csv");
        let expected = format!(
            "`runs.files[3]` (run3.csv): {} lines 2-4 (samples 0..3): too short for the \
             processing of every run, which takes 200 samples at each end (processing.trim, \
             within which the low-pass settles in ",
            file.display()
        );
        let text = e.to_string();
        assert!(text.contains(&expected), "{mode}: {text}");
        assert!(
            text.ends_with(
                ") and 101 between them for more equations than the 48 parameters at 6 \
                 equations per sample, one sample in 10 kept by processing.decimation less 1 \
                 at each end that its filter does not settle: 3 samples, at least 501 are \
                 needed; remove the run from runs.files or record it in full (all runs are \
                 processed alike)"
            ),
            "{mode}: {text}"
        );
    }
}

/// Stacked runs whose equations `processing.rest_velocity` removes (nearly) all of a
/// moving joint's are told as the single-run path tells them (`rest_cause`): the key at
/// its line, the joint, the equations it kept over the runs, its top speed and a
/// per-joint `rest_velocity` that keeps them, in the dense (RLS) and the streaming (OLS)
/// stacked path; it was the least squares' plain "rank-deficient data: ...; use a richer
/// trajectory or remove these parameters". Each speed in its joint's unit: m/s for a
/// prismatic joint (`Config::prismatic`).
#[test]
fn stacked_runs_name_the_rest_velocity_that_removed_a_joints_equations() {
    let (config, dir) = runs_config(&[3000, 3000], "stacked");
    let path = dir.path().join("runs.toml");
    // joint 2 moves at up to 0.843 rad/s: a threshold of 100 for it removes its equations
    let text = std::fs::read_to_string(&path).unwrap().replace(
        "rest_velocity = 0.02",
        "rest_velocity = [0.02, 100, 0.02, 0.02, 0.02, 0.02]",
    );
    let line = text
        .lines()
        .position(|l| l.starts_with("rest_velocity"))
        .unwrap()
        + 1;
    drop(config);
    let ols = Config::from_toml_str(&text, &path).unwrap();
    let data = load_runs(&ols, DOF).unwrap();
    let mut rls = ols.clone();
    rls.estimation.method = crate::data::Method::Rls;
    let model = Synthetic::default();
    for prismatic in [false, true] {
        let (mut ols, mut rls) = (ols.clone(), rls.clone());
        ols.prismatic = vec![false, prismatic];
        rls.prismatic = ols.prismatic.clone();
        let unit = if prismatic { "m/s" } else { "rad/s" };
        let streamed = crate::pipeline::stream::stacked_streaming(&model, &data, &ols)
            .err()
            .unwrap();
        let dense = crate::pipeline::runs::stacked_dense(&model, &data, &rls)
            .err()
            .unwrap();
        for e in [&streamed, &dense] {
            assert!(
                matches!(e, Error::Data(crate::DataError::ConfigKey { key, line: Some(l), .. })
                    if key == "processing.rest_velocity" && *l == line),
                "{e}"
            );
            let message = e.to_string();
            for part in [
                "rank-deficient data (rank 44 of 48 parameters; not excited: ",
                "because rest_velocity removed all or nearly all of a joint's equations: \
                 joint 2 keeps 0 of its 516 equations (its |velocity| reaches at most 0.845 ",
                &format!("{unit}; its threshold 100 {unit})"),
                "lower `rest_velocity` (default 0.05) in the config's [processing] for it, \
                 e.g. `rest_velocity = [0.02, 0.0845, 0.02, 0.02, 0.02, 0.02]`",
            ] {
                assert!(message.contains(part), "`{part}` in {message}");
            }
            assert!(!message.contains("remove these parameters"), "{message}");
            let other = if prismatic { "rad/s" } else { "m/s" };
            assert!(!message.contains(other), "{message}");
        }
    }
}

/// When every run is too short for the processing, the error says to ask less of the
/// processing, not to remove the run (which named the first run only, as if the others
/// were fine, and never the decimation that took the samples).
#[test]
fn runs_all_too_short_for_the_processing_point_at_it() {
    for mode in ["stacked", "averaged"] {
        let (config, _dir) = runs_config(&[450, 480], mode);
        let data = load_runs(&config, DOF).unwrap();
        let e = identify_runs(&Synthetic::default(), &data, &config).unwrap_err();
        let text = e.to_string();
        assert!(
            text.contains(
                "at least 501 are needed; every run is this short: ask less of \
                 [processing] (a lower decimation or trim, a higher low-pass cutoff) or record \
                 longer runs"
            ),
            "{mode}: {text}"
        );
    }
    // one run long enough: the short one is the problem
    let (config, _dir) = runs_config(&[450, 20_000], "stacked");
    let data = load_runs(&config, DOF).unwrap();
    let e = identify_runs(&Synthetic::default(), &data, &config).unwrap_err();
    assert!(
        e.to_string().contains("remove the run from runs.files"),
        "{e}"
    );
}

/// A recording listed as two runs (by its name twice, or under another spelling) is
/// refused at `runs.files`, naming both runs and the file: it gave a spread of exactly 0
/// between runs, and an average that claimed less noise.
#[test]
fn a_file_two_runs_share_is_refused() {
    let (config, dir) = runs_config(&[2_000, 2_000], "stacked");
    assert!(load_runs(&config, DOF).is_ok());
    let text = std::fs::read_to_string(dir.path().join("runs.toml")).unwrap();
    for twice in ["\"run1.csv\"", "\"./run1.csv\""] {
        let bad = text.replace("\"run2.csv\"", twice);
        let config = Config::from_toml_str(&bad, &dir.path().join("runs.toml")).unwrap();
        let e = load_runs(&config, DOF).unwrap_err();
        let m = e.to_string();
        assert!(
            matches!(&e, Error::Data(crate::DataError::ConfigKey { key, line: Some(_), .. }) if key == "runs.files")
                && m.contains("runs 1 and 2 both read")
                && m.contains("run1.csv"),
            "{m}"
        );
    }
    // a byte-for-byte copy under another name holds the same samples: refused too
    std::fs::copy(dir.path().join("run1.csv"), dir.path().join("run2.csv")).unwrap();
    let e = load_runs(&config, DOF).unwrap_err().to_string();
    assert!(
        e.contains("runs 1 and 2 hold the same samples (run1.csv and run2.csv)"),
        "{e}"
    );
}

/// Stacked runs whose torques the decimation filters keep the torques before the filter,
/// as one record does: run by run, those of each run's own identification (the fit said
/// "measured torque" of the decimated torques, with no figure against the measured ones),
/// streaming (ols) and through the whole matrix (rls).
#[test]
fn stacked_runs_keep_the_torques_before_the_filter() {
    let (config, dir) = runs_config(&[3000, 3500], "stacked");
    let data = load_runs(&config, DOF).unwrap();
    drop(dir);
    let model = Synthetic::default();
    for method in [crate::data::Method::Ols, crate::data::Method::Rls] {
        let mut config = config.clone();
        config.estimation.method = method;
        let id = identify_runs(&model, &data, &config).unwrap();
        let stacked = id
            .prediction
            .unfiltered
            .as_ref()
            .expect("unfiltered torques");
        let mut at = [0; DOF];
        for run in &data {
            let alone = crate::pipeline::identify(&model, run, &config).unwrap();
            let own = alone.prediction.unfiltered.as_ref().unwrap();
            for j in 0..DOF {
                let n = own[j].len();
                assert!(n > 100, "{method:?}: joint {j}: {n}");
                assert_eq!(stacked[j][at[j]..at[j] + n], own[j][..], "{method:?}: {j}");
                at[j] += n;
            }
        }
        for j in 0..DOF {
            assert_eq!(at[j], stacked[j].len());
            assert_eq!(at[j], id.prediction.measured[j].len());
        }
    }
}
