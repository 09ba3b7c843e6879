//! An hour of a 7-joint robot at 1 kHz (3.6 M samples), identified end to end from CSV
//! (issue 19): samples per second and peak memory, against a baseline measured in the
//! same run (reading the CSV alone).
//!
//! ```text
//! cargo run --release -p robots --example hour_identify [-- SECONDS [FOLDER]]
//! ```
//!
//! It writes `FOLDER/panda_SECONDS.csv` once (default: an hour, in the system's temporary
//! folder): the Panda's positions along sums of sines and its torques from the reference
//! base parameters (`parameters/panda.toml`) with noise and quantisation, as a real log's
//! `t,q1..7,tau1..7`. Then it runs itself once per stage, so that each stage's peak
//! resident memory (`VmHWM` of /proc/self/status) is its own:
//!
//! - `parse`: reading the CSV into a data set (the baseline);
//! - `identify`: reading it (`data::load_record`: checked and converted window by window,
//!   its samples kept in a temporary file) and identifying with the config of a real log
//!   (zero-phase low-pass of the positions, central differences, decimation by 10, rest
//!   samples removed, WLS), which streams (`pipeline::stream`) block by block;
//! - `dense`: the same through the whole observation matrix (`pipeline::observation`,
//!   `pipeline::estimate`), on a record of the first `min(SECONDS, 300)` seconds of the
//!   same motion (`panda_300.csv`) only, since the hour does not fit in memory that way;
//!   the streaming identification and the parsing of that record are run too.
//!
//! Figures are printed, never asserted: they depend on the machine and its load.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

use robid_runtime::Model;
use robid_runtime::data::{Config, load, load_record};
use robid_runtime::pipeline::{estimate, identify, observation};
use robid_runtime::rng::Rng;
use robots::Panda;

/// The `robid` binary's allocator (`src/main.rs`), so that the figures are the tool's.
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

const RATE: f64 = 1000.0;
const DOF: usize = 7;

const CONFIG: &str = r#"
dof = 7
time_column = "t"
[[source]]
position = "q{}"
torque = "tau{}"
[processing]
lowpass = { cutoff = 20.0, order = 4, signals = ["q"] }
decimation = 10
rest_velocity = 0.02
[estimation]
method = "wls"
"#;

/// Centre and amplitude of each joint's motion (inside the Panda's limits).
const CENTRE: [f64; DOF] = [0.0, 0.0, 0.0, -1.57, 0.0, 1.87, 0.0];
const AMPLITUDE: [f64; DOF] = [1.2, 0.8, 1.2, 0.9, 1.2, 0.9, 1.2];

fn truth(model: &Panda) -> Vec<f64> {
    robots::Reference::named("panda")
        .expect("the Panda is a reference robot")
        .parameter_file()
        .base_parameters(model)
        .expect("the reference parameters fit the model")
}

/// Writes `seconds` of the Panda at 1 kHz to `path`.
fn write(seconds: f64, path: &Path) -> std::io::Result<()> {
    let model = Panda;
    let beta = truth(&model);
    let p = model.base_parameter_count();
    let n = (seconds * RATE).round() as usize;
    let tmp = path.with_extension("partial");
    let mut out = std::io::BufWriter::with_capacity(1 << 20, std::fs::File::create(&tmp)?);
    write!(out, "t")?;
    for j in 1..=DOF {
        write!(out, ",q{j}")?;
    }
    for j in 1..=DOF {
        write!(out, ",tau{j}")?;
    }
    writeln!(out)?;
    let mut rng = Rng::new(19);
    let (mut q, mut qd, mut qdd) = ([0.0; DOF], [0.0; DOF], [0.0; DOF]);
    let mut y = vec![0.0; DOF * p];
    for k in 0..n {
        let t = k as f64 / RATE;
        for j in 0..DOF {
            let (mut a, mut b, mut c) = (0.0, 0.0, 0.0);
            for h in 1..=4 {
                let w = 0.35 * h as f64 * (1.0 + 0.13 * j as f64);
                let amp = AMPLITUDE[j] / (2.0 * h as f64);
                let ph = 0.9 * j as f64 + 1.7 * h as f64;
                a += amp * (w * t + ph).sin();
                b += amp * w * (w * t + ph).cos();
                c -= amp * w * w * (w * t + ph).sin();
            }
            (q[j], qd[j], qdd[j]) = (CENTRE[j] + a, b, c);
        }
        model
            .base_regressor_into(&q, &qd, &qdd, &mut y)
            .expect("sizes");
        write!(out, "{t:.3}")?;
        for v in q {
            // an encoder of 2^20 counts per turn
            let step = std::f64::consts::TAU / (1u64 << 20) as f64;
            write!(out, ",{:.8}", (v / step).round() * step)?;
        }
        for j in 0..DOF {
            let tau: f64 = y[j * p..(j + 1) * p]
                .iter()
                .zip(&beta)
                .map(|(a, b)| a * b)
                .sum();
            write!(out, ",{:.5}", tau + 0.05 * rng.normal())?;
        }
        writeln!(out)?;
    }
    out.into_inner().map_err(|e| e.into_error())?.sync_all()?;
    std::fs::rename(&tmp, path)
}

/// Peak resident memory of this process so far, in MiB.
fn peak_mib() -> f64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    status
        .lines()
        .find_map(|l| l.strip_prefix("VmHWM:"))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse::<f64>().ok())
        .map_or(f64::NAN, |kb| kb / 1024.0)
}

/// One stage in this process: prints `stage seconds samples peak_mib detail`.
fn stage(name: &str, path: &Path) {
    let mut config = Config::from_toml_str(CONFIG, Path::new("hour.toml")).expect("config");
    // the identification without the robust deviations' pass (the classical statistics)
    config.estimation.robust_std = name != "identify-classical";
    let model = Panda;
    let start = Instant::now();
    let files = [path.to_path_buf()];
    let (samples, detail) = match name {
        "parse" => {
            let data = load(&config, &files, DOF).expect("load");
            (data.samples(), format!("{} samples", data.samples()))
        }
        "identify" | "identify-classical" => {
            let record = load_record(&config, &files, DOF).expect("load");
            let id = identify(&model, record.as_ref(), &config).expect("identify");
            if let Some(out) = std::env::var_os("HOUR_ESTIMATE") {
                dump(&id.estimate, Some(&id.fit), Path::new(&out)).expect("write the estimate");
            }
            let truth = truth(&model);
            let err = relative_error(&id.estimate.values, &truth);
            let detail = format!(
                "cond {:.1}, relative parameter error {err:.2e}, NMSE {:.3e}, {} equations",
                id.estimate.condition_number, id.fit.nmse, id.estimate.rows
            );
            (record.samples(), detail)
        }
        "dense" => {
            let data = load(&config, &files, DOF).expect("load");
            let (obs, _) = observation(&model, &data, &config).expect("observation");
            let e = estimate(&obs, &config).expect("estimate");
            if let Some(out) = std::env::var_os("HOUR_ESTIMATE") {
                dump(&e, None, Path::new(&out)).expect("write the estimate");
            }
            if let Some(out) = std::env::var_os("HOUR_FOLDED") {
                dump(
                    &folded(&obs, config.estimation.rank_tolerance),
                    None,
                    Path::new(&out),
                )
                .expect("write the estimate");
            }
            let err = relative_error(&e.values, &truth(&model));
            let detail = format!(
                "cond {:.1}, relative parameter error {err:.2e}, {} equations",
                e.condition_number, e.rows
            );
            (data.samples(), detail)
        }
        other => panic!("unknown stage {other}"),
    };
    let elapsed = start.elapsed().as_secs_f64();
    println!("{name} {elapsed} {samples} {} {detail}", peak_mib());
}

/// Writes the estimate's values, standard deviations, weights, residuals and the fit
/// (when there is one), one number a line with its name (`HOUR_ESTIMATE=FILE` in the
/// identify and dense stages): the figures two builds must agree on.
fn dump(
    e: &robid_runtime::estimate::Estimate,
    fit: Option<&robid_runtime::validate::Fit>,
    path: &Path,
) -> std::io::Result<()> {
    let mut out = std::io::BufWriter::new(std::fs::File::create(path)?);
    for (i, name) in e.names.iter().enumerate() {
        writeln!(out, "value {name} {:e}", e.values[i])?;
        writeln!(out, "std {name} {:e}", e.std[i])?;
    }
    for (j, r) in e.residual_rms.iter().enumerate() {
        writeln!(out, "residual_rms {j} {r:e}")?;
    }
    for (j, w) in e.weights.iter().flatten().enumerate() {
        writeln!(out, "weight {j} {w:e}")?;
    }
    writeln!(out, "sigma2 - {:e}", e.sigma2)?;
    writeln!(out, "condition - {:e}", e.condition_number)?;
    writeln!(out, "rows - {}", e.rows)?;
    if let Some(fit) = fit {
        writeln!(out, "nmse - {:e}", fit.nmse)?;
        writeln!(out, "relative_error - {:e}", fit.relative_error)?;
        for (j, r) in fit.rms_per_joint.iter().enumerate() {
            writeln!(out, "fit_rms {j} {r:e}")?;
        }
    }
    out.flush()
}

/// The dense observation's equations through the streaming least squares (WLS, the
/// joints' factors folded as the streaming path folds them, one block of equations per
/// joint): against the dense estimate it shows what the fold order alone moves, against
/// the streaming estimate what the streaming equations (the filters' settling at the
/// blocks' edges) move (`HOUR_FOLDED=FILE` in the dense stage).
fn folded(
    obs: &robid_runtime::estimate::Observation,
    tolerance: f64,
) -> robid_runtime::estimate::Estimate {
    let mut ls = robid_runtime::estimate::StreamingLeastSquares::new(
        obs.names.clone(),
        obs.joint_rows.len(),
    )
    .expect("names");
    for (j, rows) in obs.joint_rows.iter().enumerate() {
        for i in rows.clone() {
            let row: Vec<f64> = obs.w.row(i).iter().copied().collect();
            ls.push(j, &row, obs.y[i]).expect("finite equations");
        }
    }
    ls.wls(tolerance).expect("the folded estimate")
}

fn relative_error(values: &[f64], truth: &[f64]) -> f64 {
    let d: f64 = values.iter().zip(truth).map(|(v, t)| (v - t).powi(2)).sum();
    let t: f64 = truth.iter().map(|t| t * t).sum();
    (d / t).sqrt()
}

/// Runs a stage in a child process and returns (seconds, samples, peak MiB, detail).
fn child(name: &str, path: &Path) -> (f64, usize, f64, String) {
    let mut cmd = Command::new(std::env::current_exe().expect("this program"));
    cmd.arg("--stage").arg(name).arg(path);
    let out = cmd.output().expect("run a stage");
    assert!(
        out.status.success(),
        "stage {name}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    let line = text.lines().last().expect("a result line");
    let mut f = line.splitn(5, ' ');
    let _ = f.next();
    let secs = f.next().and_then(|v| v.parse().ok()).expect("seconds");
    let samples = f.next().and_then(|v| v.parse().ok()).expect("samples");
    let peak = f.next().and_then(|v| v.parse().ok()).expect("peak");
    (secs, samples, peak, f.next().unwrap_or("").to_string())
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.first().map(String::as_str) == Some("--stage") {
        stage(&args[1], Path::new(&args[2]));
        return;
    }
    let seconds: f64 = args.first().and_then(|v| v.parse().ok()).unwrap_or(3600.0);
    let folder = args
        .get(1)
        .map(PathBuf::from)
        .unwrap_or_else(std::env::temp_dir);
    let record = |seconds: f64| {
        let path = folder.join(format!("panda_{}.csv", seconds as u64));
        if !path.exists() {
            let start = Instant::now();
            write(seconds, &path).expect("write the record");
            eprintln!(
                "wrote {} in {:.1} s",
                path.display(),
                start.elapsed().as_secs_f64()
            );
        }
        path
    };
    let path = record(seconds);
    // the dense path's record: the first minutes of the same motion, in a file of its own
    let dense_limit = seconds.min(300.0);
    let short = record(dense_limit);
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    println!(
        "{} ({:.0} MB), {threads} threads",
        path.display(),
        std::fs::metadata(&path).map_or(0, |m| m.len()) as f64 / 1e6
    );
    let (parse_s, n, parse_mib, _) = child("parse", &path);
    let (id_s, _, id_mib, detail) = child("identify", &path);
    let (classical_s, _, classical_mib, _) = child("identify-classical", &path);
    let (dense_s, dense_n, dense_mib, dense_detail) = child("dense", &short);
    let (short_s, short_n, short_mib, short_detail) = child("identify", &short);
    let (short_parse_s, _, short_parse_mib, _) = child("parse", &short);
    // the baseline: parsing time per sample; each stage's time per sample is a multiple
    let parse_per_sample = parse_s / n as f64;
    println!(
        "| stage | samples | time (s) | samples/s | peak RSS (MiB) | time per sample / parse's |"
    );
    println!("|---|---|---|---|---|---|");
    let row = |name: &str, n: usize, s: f64, mib: f64| {
        println!(
            "| {name} | {n} | {s:.2} | {:.3e} | {mib:.0} | {:.2} |",
            n as f64 / s,
            s / n as f64 / parse_per_sample
        )
    };
    row("parse CSV into memory (baseline)", n, parse_s, parse_mib);
    row(
        "read + identify, streaming, record on disk",
        n,
        id_s,
        id_mib,
    );
    row(
        "the same without the robust deviations (robust_std = false)",
        n,
        classical_s,
        classical_mib,
    );
    row(
        &format!("parse CSV, first {dense_limit} s"),
        short_n,
        short_parse_s,
        short_parse_mib,
    );
    row(
        &format!("read + identify, streaming, record on disk, first {dense_limit} s"),
        short_n,
        short_s,
        short_mib,
    );
    row(
        &format!("parse + identify, dense, first {dense_limit} s"),
        dense_n,
        dense_s,
        dense_mib,
    );
    println!("streaming, whole record: {detail}");
    println!("streaming, first {dense_limit} s: {short_detail}");
    println!("dense, first {dense_limit} s: {dense_detail}");
}
