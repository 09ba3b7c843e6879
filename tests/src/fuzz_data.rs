//! Shared data of the bad-input tests and of the identification fuzzer: a known-good UR5e
//! record as CSV, the bundled identification configs and the headers of the real logs as
//! seeds, a seeded mutation of texts, and the cases (config parser, CSV reader, `identify`
//! end to end) with the checks every outcome must pass: no panic, no hang, and an `Ok`
//! never holds NaN or an infinity.
//!
//! Used by `tests/tests/suite/fuzz_identify.rs` (a short run in the test suite) and by the
//! long run `cargo run --release -p tests --example fuzz_identify -- N [SEED]`, so they run
//! the same code. The bad-input tests use the record.

use std::collections::BTreeMap;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use robid_runtime::Model;
use robid_runtime::data::{Config, load, read_columns, read_columns_from};
use robid_runtime::pipeline::{identify, validate};
use robid_runtime::report::{Report, text_table};
use robid_runtime::rng::Rng;
use robid_runtime::signal::Signals;
use robots::Ur5e;

/// Sample rate of the generated record (Hz).
pub const RATE: f64 = 100.0;

/// The repository root.
pub fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// The UR5e reference base parameters (`robots/parameters/ur5e.toml`, rigid body).
pub fn ur5e_base() -> Vec<f64> {
    let model = Ur5e;
    let file = crate::reference::by_name("ur5e").parameter_file();
    let standard: Vec<f64> = robid_runtime::model::standard_parameter_names(&model)
        .iter()
        .map(|name| file.get(name).unwrap_or(0.0))
        .collect();
    let mut base = vec![0.0; model.base_parameter_count()];
    Model::base_from_standard_into(&model, &standard, &mut base)
        .expect("the standard vector has the model's length");
    base
}

/// A smooth UR5e motion of `rows` samples at [`RATE`] and its torques (inverse dynamics of
/// the reference parameters plus a small deterministic noise), per joint.
#[derive(Debug, Clone)]
pub struct Motion {
    /// Time stamps (s).
    pub t: Vec<f64>,
    /// Positions, velocities, accelerations and torques, `[signal][joint][sample]`.
    pub signals: [Signals; 4],
}

/// The motion (two sines per joint, different frequencies, within the UR5e's limits).
pub fn motion(rows: usize) -> Motion {
    motion_scaled(rows, [1.0; 6])
}

/// [`motion`] with joint j's excursion multiplied by `scale[j]` (the torques follow).
pub fn motion_scaled(rows: usize, scale: [f64; 6]) -> Motion {
    let model = Ur5e;
    let base = ur5e_base();
    let n = 6;
    let t: Vec<f64> = (0..rows).map(|k| k as f64 / RATE).collect();
    let mut s: [Signals; 4] = std::array::from_fn(|_| Signals::zeros(n, rows));
    let mut rng = Rng::new(5);
    let (mut q, mut qd, mut qdd, mut tau) = ([0.0; 6], [0.0; 6], [0.0; 6], [0.0; 6]);
    for (k, &time) in t.iter().enumerate() {
        for j in 0..n {
            let w = 0.9 + 0.23 * j as f64;
            let (a, b) = (0.8 * scale[j], 0.35 * scale[j]);
            let (w2, p) = (2.7 * w, 0.4 * j as f64);
            q[j] = a * (w * time + p).sin() + b * (w2 * time).sin();
            qd[j] = a * w * (w * time + p).cos() + b * w2 * (w2 * time).cos();
            qdd[j] = -a * w * w * (w * time + p).sin() - b * w2 * w2 * (w2 * time).sin();
        }
        Model::inverse_dynamics_into(&model, &q, &qd, &qdd, &base, &mut tau)
            .expect("the reference state and parameters have the model's lengths");
        for j in 0..n {
            s[0][j][k] = q[j];
            s[1][j][k] = qd[j];
            s[2][j][k] = qdd[j];
            s[3][j][k] = tau[j] + 0.05 * rng.normal();
        }
    }
    Motion { t, signals: s }
}

/// The default header `t,q1..q6,qd1..qd6,qdd1..qdd6,tau1..tau6`.
pub fn default_header() -> Vec<String> {
    let mut h = vec!["t".to_string()];
    for p in ["q", "qd", "qdd", "tau"] {
        h.extend((1..=6).map(|j| format!("{p}{j}")));
    }
    h
}

/// The motion as CSV with the default header.
pub fn motion_csv(m: &Motion) -> String {
    let mut out = default_header().join(",");
    out.push('\n');
    for (k, t) in m.t.iter().enumerate() {
        out.push_str(&format!("{t}"));
        for block in &m.signals {
            for joint in block {
                out.push_str(&format!(",{}", joint[k]));
            }
        }
        out.push('\n');
    }
    out
}

/// The motion as CSV with the given column names: a name is filled by its role in
/// `roles` (0 position, 1 velocity, 2 acceleration, 3 torque; joint from 0), the time
/// column by the time, any other name by a constant.
pub fn csv_with(m: &Motion, columns: &[(String, Option<(usize, usize)>)], time: &str) -> String {
    let mut out = columns
        .iter()
        .map(|c| c.0.clone())
        .collect::<Vec<_>>()
        .join(",");
    out.push('\n');
    for k in 0..m.t.len() {
        let row: Vec<String> = columns
            .iter()
            .map(|(name, role)| match role {
                Some((s, j)) => format!("{}", m.signals[*s][*j % 6][k]),
                None if name == time => format!("{}", m.t[k]),
                None => "0.5".to_string(),
            })
            .collect();
        out.push_str(&row.join(","));
        out.push('\n');
    }
    out
}

/// Seeds of the mutation: the bundled identification configs and the real logs' headers.
#[derive(Debug, Clone)]
pub struct Seeds {
    /// (file name, text) of `robots/configs/*.toml` and `data/*/identify.toml`, plus small
    /// configs written for the generated record.
    pub configs: Vec<(String, String)>,
    /// Header column names of the real logs (`data/*/data/*.csv.gz`).
    pub headers: Vec<Vec<String>>,
}

/// Configs written for the generated record (default header), each exercising options.
pub const RECORD_CONFIGS: [&str; 6] = [
    "time_column = \"t\"\n[[source]]\nposition = \"q{}\"\nvelocity = \"qd{}\"\nacceleration = \"qdd{}\"\ntorque = \"tau{}\"\n",
    "dof = 6\ntime_column = \"t\"\n[[source]]\nposition = \"q{}\"\ntorque = \"tau{}\"\n[processing]\nlowpass = { cutoff = 10.0, order = 4, signals = [\"q\", \"tau\"] }\ndecimation = 2\nrest_velocity = 0.01\n[estimation]\nmethod = \"wls\"\n",
    "sample_rate = 100.0\n[[source]]\nposition = \"q{}\"\nvelocity = \"qd{}\"\nacceleration = \"qdd{}\"\ntorque = [\"tau1\", \"tau2\", \"tau3\", \"tau4\", \"tau5\", \"tau6\"]\n[processing]\nrange = [10, 350]\nvalidation_range = [0, 300]\ntrim = 5\n[estimation]\nmethod = \"rls\"\nforgetting = 0.999\n",
    "time_column = \"t\"\ntime_scale = 1.0\n[[source]]\nposition = \"q{}\"\nvelocity = \"qd{}\"\ntorque = \"tau{}\"\n[units]\nangle = \"rad\"\ntorque_scale = 1.0\n[processing]\nacceleration = \"differentiate\"\nlowpass = { cutoff = 20.0 }\n[estimation]\nmethod = \"energy\"\nenergy_window = 0.1\n",
    "time_column = \"t\"\n[[source]]\nposition = \"q{}\"\nvelocity = \"qd{}\"\nacceleration = \"qdd{}\"\ntorque = \"tau{}\"\n[drive]\ngear_ratios = [1, 1, 1, 1, 1, 1]\ntorque_constants = 1.0\n[[extra_column]]\nname = \"Fv1\"\nterms = [{ row = 1, signal = \"qd\", joints = [1] }]\n[[extra_column]]\nname = \"Fo2\"\nterms = [{ row = 2, signal = \"constant\" }]\n",
    "time_column = \"t\"\n[[source]]\nposition = \"q{}\"\nacceleration = \"qdd{}\"\ntorque = \"tau{}\"\n[processing]\nvelocity = \"differentiate\"\ndecimation = [2, 2]\n[estimation]\nmethod = \"ols\"\nrank_tolerance = 1e-12\n",
];

/// The seeds (reads the bundled files; the real logs' headers come from the reader's
/// own message about a column that is not there, which lists the header).
pub fn seeds() -> Seeds {
    let root = repo();
    let mut configs = Vec::new();
    let mut files: Vec<PathBuf> = std::fs::read_dir(root.join("robots/configs"))
        .map(|d| d.flatten().map(|e| e.path()).collect())
        .unwrap_or_default();
    for d in ["data/staubli_tx40", "data/kuka_lwr4"] {
        files.push(root.join(d).join("identify.toml"));
    }
    files.sort();
    for f in files {
        if f.extension().is_some_and(|e| e == "toml")
            && let Ok(text) = std::fs::read_to_string(&f)
        {
            configs.push((f.display().to_string(), text));
        }
    }
    for (i, c) in RECORD_CONFIGS.iter().enumerate() {
        configs.push((format!("record{i}.toml"), c.to_string()));
    }
    let mut headers = Vec::new();
    for f in [
        "data/staubli_tx40/data/pos_read_data.csv.gz",
        "data/staubli_tx40/data/curr_data.csv.gz",
        "data/kuka_lwr4/data/measurements_1.csv.gz",
    ] {
        if let Err(robid_runtime::Error::Data(robid_runtime::DataError::MissingColumn {
            available,
            ..
        })) = read_columns(&root.join(f), &["\u{1}".to_string()])
        {
            headers.push(available);
        }
    }
    Seeds { configs, headers }
}

/// Replacements for a number.
const NUMBERS: [&str; 24] = [
    "1e200",
    "-1e200",
    "NaN",
    "inf",
    "-inf",
    "1e308",
    "0",
    "-0",
    "1e-320",
    "",
    "x",
    "1,5",
    "99999999999999999999999",
    "1e8",
    "5e7",
    "-1e6",
    "2e7",
    "1e-12",
    "0.0",
    "3",
    "-1",
    "1e9",
    "4294967296",
    "\"",
];

/// Replacements for a number in TOML (valid TOML values and some that are not).
const TOML_VALUES: [&str; 20] = [
    "nan",
    "inf",
    "-inf",
    "1e308",
    "0",
    "-1",
    "1e9",
    "4294967296",
    "18446744073709551615",
    "1e-320",
    "0.5",
    "[]",
    "[1, 2]",
    "\"x\"",
    "true",
    "-0.0",
    "100000",
    "2",
    "1e6",
    "",
];

/// Lines inserted into a TOML config.
const TOML_LINES: [&str; 16] = [
    "validation_range = [5, 2]",
    "[processing]\nrange = [0, 100000000000]",
    "[processing]\ndecimation = [1000, 1000]",
    "[processing]\ntrim = 99999999999",
    "[processing]\nlowpass = { cutoff = 1e9, order = 0 }",
    "[processing]\nlowpass = { cutoff = 49.9, order = 20 }",
    "[estimation]\nmethod = \"rls\"\nforgetting = 0.5",
    "[estimation]\nmethod = \"energy\"",
    "sample_rate = 1e300",
    "time_scale = 1e-9",
    "[drive]\ngear_ratios = [0, 1, 1, 1, 1, 1]",
    "[drive]\nposition_side = \"motor\"",
    "[[extra_column]]\nname = \"Fv1\"\nterms = [{ row = 7, signal = \"qd\", joints = [0] }]",
    "[[extra_column]]\nname = \"q\"\nterms = [{ row = 1, signal = \"sign_qd\", joints = [1, 2], coefficient = 1e300 }]",
    "dof = 7",
    "[units]\ntorque_scale = [1e6, 1e6, 1e6, 1e6, 1e6, 0]",
];

/// Spans of number-like tokens in a text.
fn number_spans(text: &str) -> Vec<(usize, usize)> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        if b[i].is_ascii_digit() || (b[i] == b'-' && b.get(i + 1).is_some_and(u8::is_ascii_digit)) {
            let start = i;
            i += 1;
            while i < b.len() && (b[i].is_ascii_alphanumeric() || b"+-.".contains(&b[i])) {
                i += 1;
            }
            out.push((start, i));
        } else {
            i += 1;
        }
    }
    out
}

fn pick<'a, T>(rng: &mut Rng, v: &'a [T]) -> &'a T {
    &v[rng.below(v.len())]
}

/// One random edit of a CSV text.
fn mutate_csv_once(text: &str, rng: &mut Rng) -> String {
    let mut lines: Vec<String> = text.split('\n').map(str::to_string).collect();
    let n = lines.len().max(1);
    match rng.below(13) {
        0..=2 => {
            let spans = number_spans(text);
            if spans.is_empty() {
                return text.to_string();
            }
            let (a, b) = *pick(rng, &spans);
            format!("{}{}{}", &text[..a], pick(rng, &NUMBERS), &text[b..])
        }
        3 => {
            lines.remove(rng.below(n).min(lines.len().saturating_sub(1)));
            lines.join("\n")
        }
        4 => {
            let i = rng.below(n).min(lines.len() - 1);
            let l = lines[i].clone();
            lines.insert(i, l);
            lines.join("\n")
        }
        5 => {
            let (i, k) = (rng.below(n), rng.below(n));
            lines.swap(i.min(n - 1), k.min(n - 1));
            lines.join("\n")
        }
        6 => {
            let extra = pick(
                rng,
                &[
                    "",
                    "#",
                    "\"a\",\"b\"",
                    ";",
                    "\t",
                    "1,2",
                    ",,,",
                    "\u{feff}",
                    "\"",
                    "t,t",
                ],
            );
            lines.insert(rng.below(n), extra.to_string());
            lines.join("\n")
        }
        7 => {
            let mut b = text.as_bytes().to_vec();
            if !b.is_empty() {
                let i = rng.below(b.len());
                b[i] = pick(
                    rng,
                    &[b',', b'\n', b'"', b';', b'\t', 0xff, b'e', b'-', b' ', b'#'],
                )
                .to_owned();
            }
            String::from_utf8_lossy(&b).into_owned()
        }
        8 => {
            let cut = rng.below(text.len().max(1));
            text.get(..cut).unwrap_or(text).to_string()
        }
        9 => {
            let i = rng.below(n).min(lines.len() - 1);
            let sep = pick(rng, &[";", "\t", " "]);
            lines[i] = lines[i].replace(',', sep);
            lines.join("\n")
        }
        10 => match rng.below(3) {
            0 => format!("\u{feff}{text}"),
            1 => text.replace('\n', "\r\n"),
            _ => {
                let i = rng.below(n).min(lines.len() - 1);
                let fields: Vec<String> = lines[i]
                    .split(',')
                    .map(|f| {
                        if rng.below(3) == 0 {
                            format!("\"{f}\"")
                        } else {
                            f.to_string()
                        }
                    })
                    .collect();
                lines[i] = fields.join(",");
                lines.join("\n")
            }
        },
        11 => {
            // the header: a column renamed or a name duplicated
            let mut fields: Vec<String> = lines[0].split(',').map(str::to_string).collect();
            let i = rng.below(fields.len());
            let k = rng.below(fields.len());
            fields[i] = if rng.below(2) == 0 {
                fields[k].clone()
            } else {
                format!("{}x", fields[i])
            };
            lines[0] = fields.join(",");
            lines.join("\n")
        }
        _ => {
            // a whole column of one row set to a value
            let i = 1 + rng.below(n.saturating_sub(1).max(1));
            if let Some(line) = lines.get_mut(i.min(n - 1)) {
                let mut fields: Vec<String> = line.split(',').map(str::to_string).collect();
                let k = rng.below(fields.len());
                fields[k] = pick(rng, &NUMBERS).to_string();
                *line = fields.join(",");
            }
            lines.join("\n")
        }
    }
}

/// One random edit of a TOML text.
fn mutate_toml_once(text: &str, rng: &mut Rng) -> String {
    let mut lines: Vec<String> = text.split('\n').map(str::to_string).collect();
    let n = lines.len().max(1);
    match rng.below(8) {
        0..=2 => {
            let spans = number_spans(text);
            if spans.is_empty() {
                return text.to_string();
            }
            let (a, b) = *pick(rng, &spans);
            format!("{}{}{}", &text[..a], pick(rng, &TOML_VALUES), &text[b..])
        }
        3 => {
            lines.remove(rng.below(n).min(lines.len() - 1));
            lines.join("\n")
        }
        4 => {
            let i = rng.below(n).min(lines.len() - 1);
            let l = lines[i].clone();
            lines.insert(i, l);
            lines.join("\n")
        }
        5 => format!("{text}\n{}\n", pick(rng, &TOML_LINES)),
        6 => {
            let i = rng.below(n).min(lines.len() - 1);
            lines[i] = lines[i]
                .replace("q{}", "x{}")
                .replace("\"t\"", "\"time\"")
                .replace("wls", "gls");
            lines.join("\n")
        }
        _ => {
            let cut = rng.below(text.len().max(1));
            text.get(..cut).unwrap_or(text).to_string()
        }
    }
}

/// `rounds` random edits of a CSV text.
pub fn mutate_csv(text: &str, rng: &mut Rng, rounds: usize) -> String {
    (0..rounds).fold(text.to_string(), |t, _| mutate_csv_once(&t, rng))
}

/// `rounds` random edits of a TOML text.
pub fn mutate_toml(text: &str, rng: &mut Rng, rounds: usize) -> String {
    (0..rounds).fold(text.to_string(), |t, _| mutate_toml_once(&t, rng))
}

/// What a case ended with.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
pub enum Outcome {
    /// Succeeded (and passed the checks).
    Ok,
    /// A located error: its variant's name.
    Error(String),
}

thread_local! {
    /// The message of the last error a case ended with.
    static LAST_MESSAGE: std::cell::RefCell<String> = const { std::cell::RefCell::new(String::new()) };
}

/// A broken promise: a panic, a non-finite number in a success, an empty message.
#[derive(Debug, Clone)]
pub struct Violation {
    /// The case.
    pub case: String,
    /// What went wrong.
    pub what: String,
}

/// The innermost variant's name (`ConfigSyntax` for `Data(ConfigSyntax { .. })`).
fn variant(e: &robid_runtime::Error) -> String {
    let d = format!("{e:?}");
    let mut rest = d.as_str();
    loop {
        let name = rest.split([' ', '{', '(']).next().unwrap_or("");
        match rest[name.len()..].strip_prefix('(') {
            Some(inner) if inner.starts_with(|c: char| c.is_ascii_uppercase()) => rest = inner,
            _ => return name.to_string(),
        }
    }
}

fn error(e: &robid_runtime::Error) -> Result<Outcome, String> {
    let text = e.to_string();
    if text.trim().is_empty() {
        return Err(format!("empty message for {e:?}"));
    }
    LAST_MESSAGE.with(|m| *m.borrow_mut() = text);
    Ok(Outcome::Error(variant(e)))
}

fn all_finite<'a>(what: &str, v: impl IntoIterator<Item = &'a f64>) -> Result<(), String> {
    match v.into_iter().find(|x| !x.is_finite()) {
        Some(x) => Err(format!("{what} holds {x}")),
        None => Ok(()),
    }
}

/// The config parser and checks on one text.
pub fn config_case(text: &str, dir: &Path) -> Result<Outcome, String> {
    match Config::from_toml_str(text, &dir.join("case.toml")) {
        Err(e) => error(&e),
        Ok(c) => {
            for dof in [6, 7] {
                if let Err(e) = c.check(dof) {
                    return error(&e);
                }
            }
            Ok(Outcome::Ok)
        }
    }
}

/// The CSV reader on one text with the given names.
pub fn csv_case(text: &str, names: &[String]) -> Result<Outcome, String> {
    match read_columns_from(text.as_bytes(), Path::new("case.csv"), names) {
        Err(e) => error(&e),
        Ok(t) => {
            all_finite("a column", t.columns.iter().flatten())?;
            if t.columns.iter().any(|c| c.len() != t.rows()) {
                return Err("columns of different lengths".into());
            }
            Ok(Outcome::Ok)
        }
    }
}

/// `identify` end to end: the config text (or the default mapping when `None`), the data
/// files written into `dir`, then identification, the report, and a validation file.
pub fn identify_case(
    config: Option<&str>,
    data: &[String],
    validation: &[String],
    dir: &Path,
) -> Result<Outcome, String> {
    let config = match config {
        None => Config::default_mapping(),
        Some(text) => match Config::from_toml_str(text, &{
            // kept beside the data, so that a replayed case can be read
            let _ = std::fs::write(dir.join("case.toml"), text);
            dir.join("case.toml")
        }) {
            Ok(c) => c,
            Err(e) => return error(&e),
        },
    };
    let write = |prefix: &str, texts: &[String]| -> Vec<PathBuf> {
        texts
            .iter()
            .enumerate()
            .map(|(i, t)| {
                let p = dir.join(format!("{prefix}{i}.csv"));
                std::fs::write(&p, t).expect("temporary file");
                p
            })
            .collect()
    };
    let files = write("data", data);
    let data = match load(&config, &files, 6) {
        Ok(d) => d,
        Err(e) => return error(&e),
    };
    let model = Ur5e;
    let id = match identify(&model, &data, &config) {
        Ok(id) => id,
        Err(e) => return error(&e),
    };
    let e = &id.estimate;
    all_finite("values", &e.values)?;
    all_finite("std", &e.std)?;
    all_finite("residual RMS", &e.residual_rms)?;
    all_finite("sigma2 and condition", [&e.sigma2, &e.condition_number])?;
    match e.scaled_condition_number {
        Some(c) if c.is_finite() && c >= 1.0 => {}
        other => return Err(format!("condition number with unit-norm columns {other:?}")),
    }
    for (r, v) in e.rel_std_percent.iter().zip(&e.values) {
        if !r.is_finite() && *v != 0.0 {
            return Err(format!("relative std {r} for the value {v}"));
        }
    }
    all_finite(
        "fit",
        id.fit
            .rms_per_joint
            .iter()
            .chain([&id.fit.relative_error, &id.fit.nmse]),
    )?;
    let p = &id.prediction;
    all_finite("measured torques", p.measured.iter().flatten())?;
    all_finite("predicted torques", p.predicted.iter().flatten())?;
    all_finite("prediction times", p.time.iter().flatten())?;
    let mut report = Report::from_identification(&id, |_| None);
    // every number of the table comes from the report, which is checked
    let _ = text_table(&report);
    report.check().map_err(|e| format!("report: {e}"))?;
    if !validation.is_empty() {
        let files = write("validation", validation);
        match load(&config, &files, 6).and_then(|d| validate(&model, &d, &config, &e.values)) {
            Ok(v) => {
                all_finite("validation", v.predicted.iter().flatten())?;
                report = report.with_prediction(&v);
                report.check().map_err(|e| format!("report: {e}"))?;
            }
            Err(e) => {
                error(&e)?;
            }
        }
    }
    Ok(Outcome::Ok)
}

/// Counts of a run.
#[derive(Debug, Clone, Default)]
pub struct Tally {
    /// Cases per kind (`config`, `csv`, `identify`) and outcome.
    pub outcomes: BTreeMap<(String, Outcome), usize>,
    /// Broken promises.
    pub violations: Vec<Violation>,
    /// The slowest case and its time.
    pub slowest: (Duration, String),
    /// The first message of each kind and error variant (what the user reads).
    pub messages: BTreeMap<(String, Outcome), String>,
}

impl Tally {
    /// Cases of a kind.
    pub fn count(&self, kind: &str) -> usize {
        self.outcomes
            .iter()
            .filter(|((k, _), _)| k == kind)
            .map(|(_, n)| n)
            .sum()
    }

    /// Successful cases of a kind.
    pub fn successes(&self, kind: &str) -> usize {
        self.outcomes
            .get(&(kind.to_string(), Outcome::Ok))
            .copied()
            .unwrap_or(0)
    }
}

/// What a run does: how many cases of each kind.
#[derive(Debug, Clone, Copy)]
pub struct Plan {
    /// Config-parser cases.
    pub configs: usize,
    /// CSV-reader cases.
    pub csvs: usize,
    /// End-to-end identification cases.
    pub identifications: usize,
    /// Seed.
    pub seed: u64,
    /// Rows of the generated record.
    pub rows: usize,
}

/// A run's shared progress, for the hang watchdog.
#[derive(Debug, Default)]
pub struct Progress {
    /// Cases finished.
    pub done: AtomicUsize,
    /// The case running.
    pub current: Mutex<String>,
}

/// Runs a plan (cases interleaved) and returns the tally. `progress` is updated before and
/// after every case so that a watchdog can tell a hang from slowness.
pub fn run(plan: Plan, dir: &Path, progress: &Arc<Progress>) -> Tally {
    let inputs = Inputs::new(plan);
    let mut tally = Tally::default();
    for (case, &kind) in inputs.kinds.iter().enumerate() {
        let label = format!("seed {} case {case} ({kind})", plan.seed);
        if let Ok(mut cur) = progress.current.lock() {
            cur.clone_from(&label);
        }
        let start = Instant::now();
        let result = catch_unwind(AssertUnwindSafe(|| inputs.case(case, dir)));
        let elapsed = start.elapsed();
        if elapsed > tally.slowest.0 {
            tally.slowest = (elapsed, label.clone());
        }
        let outcome = match result {
            Ok(Ok(o)) => o,
            Ok(Err(what)) => {
                tally.violations.push(Violation {
                    case: label.clone(),
                    what,
                });
                Outcome::Error("violation".into())
            }
            Err(panic) => {
                let what = panic
                    .downcast_ref::<String>()
                    .cloned()
                    .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
                    .unwrap_or_default();
                tally.violations.push(Violation {
                    case: label.clone(),
                    what: format!("panic: {what}"),
                });
                Outcome::Error("panic".into())
            }
        };
        if matches!(outcome, Outcome::Error(_)) {
            let message = LAST_MESSAGE.with(|m| m.borrow().clone());
            tally
                .messages
                .entry((kind.to_string(), outcome.clone()))
                .or_insert(message);
        }
        *tally
            .outcomes
            .entry((kind.to_string(), outcome))
            .or_default() += 1;
        progress.done.fetch_add(1, Ordering::Relaxed);
    }
    tally
}

/// Everything the cases of a plan are made from; case `k` is a pure function of the plan
/// and `k`, so a finding can be replayed alone ([`Inputs::case`]).
#[derive(Debug)]
pub struct Inputs {
    seeds: Seeds,
    record: Motion,
    base_csv: String,
    header: Vec<String>,
    root: Rng,
    /// The kind of every case, shuffled so that a run of any length mixes them.
    pub kinds: Vec<&'static str>,
}

impl Inputs {
    /// The inputs of a plan.
    pub fn new(plan: Plan) -> Self {
        let record = motion(plan.rows);
        let root = Rng::new(plan.seed);
        let mut kinds: Vec<&'static str> = std::iter::repeat_n("config", plan.configs)
            .chain(std::iter::repeat_n("csv", plan.csvs))
            .chain(std::iter::repeat_n("identify", plan.identifications))
            .collect();
        let mut shuffle = root.fork(u64::MAX);
        for k in (1..kinds.len()).rev() {
            kinds.swap(k, shuffle.below(k + 1));
        }
        Self {
            seeds: seeds(),
            base_csv: motion_csv(&record),
            record,
            header: default_header(),
            root,
            kinds,
        }
    }

    /// Runs case `case` (files go to `dir`).
    pub fn case(&self, case: usize, dir: &Path) -> Result<Outcome, String> {
        let mut rng = self.root.fork(case as u64);
        match self.kinds.get(case).copied().unwrap_or("identify") {
            "config" => {
                let (_, text) = pick(&mut rng, &self.seeds.configs);
                let rounds = rng.below(4);
                config_case(&mutate_toml(text, &mut rng, rounds), dir)
            }
            "csv" => {
                let names: Vec<String> = if rng.below(3) == 0 && !self.seeds.headers.is_empty() {
                    pick(&mut rng, &self.seeds.headers).clone()
                } else {
                    self.header.clone()
                };
                let source = if names == self.header {
                    self.base_csv.clone()
                } else {
                    let cols: Vec<(String, Option<(usize, usize)>)> = names
                        .iter()
                        .enumerate()
                        .map(|(k, n)| (n.clone(), Some((k % 4, k % 6))))
                        .collect();
                    csv_with(&self.record, &cols, "")
                };
                let rounds = 1 + rng.below(4);
                let wanted: Vec<String> = names
                    .iter()
                    .filter(|_| rng.below(2) == 0)
                    .cloned()
                    .collect();
                csv_case(&mutate_csv(&source, &mut rng, rounds), &wanted)
            }
            _ => identify_one(&self.seeds, &self.record, &self.base_csv, &mut rng, dir),
        }
    }
}

/// One end-to-end case: a config (none, one for the record, or a bundled one with data
/// made for its columns), mutated data, and a validation file.
fn identify_one(
    seeds: &Seeds,
    record: &Motion,
    base_csv: &str,
    rng: &mut Rng,
    dir: &Path,
) -> Result<Outcome, String> {
    // light mutation, so that many cases get through to the estimate
    let rounds = [0, 0, 1, 1, 1, 2, 3][rng.below(7)];
    let validation_rounds = rng.below(2);
    let validation = vec![mutate_csv(base_csv, rng, validation_rounds)];
    match rng.below(4) {
        0 => identify_case(None, &[mutate_csv(base_csv, rng, rounds)], &validation, dir),
        1 | 2 => {
            let text = RECORD_CONFIGS[rng.below(RECORD_CONFIGS.len())];
            let config_rounds = rng.below(2);
            let text = mutate_toml(text, rng, config_rounds);
            identify_case(
                Some(&text),
                &[mutate_csv(base_csv, rng, rounds)],
                &validation,
                dir,
            )
        }
        _ => {
            // a bundled identification config with data made for its columns
            let usable: Vec<&(String, String)> = seeds
                .configs
                .iter()
                .filter(|(_, t)| {
                    Config::from_toml_str(t, Path::new("x.toml"))
                        .is_ok_and(|c| !c.sources.is_empty())
                })
                .collect();
            let (_, text) = *pick(rng, &usable);
            let Ok(config) = Config::from_toml_str(text, &dir.join("bundled.toml")) else {
                return Ok(Outcome::Error("ConfigSyntax".into()));
            };
            let time = config.time_column.clone().unwrap_or_default();
            let data: Vec<String> = config
                .sources
                .iter()
                .map(|s| {
                    let mut cols: Vec<(String, Option<(usize, usize)>)> = Vec::new();
                    for (role, c) in [&s.position, &s.velocity, &s.acceleration, &s.torque]
                        .into_iter()
                        .enumerate()
                    {
                        if let Some(c) = c {
                            for (j, n) in c.names(6).into_iter().enumerate() {
                                cols.push((n, Some((role, j))));
                            }
                        }
                    }
                    if !time.is_empty() {
                        cols.push((time.clone(), None));
                    }
                    let mut seen = std::collections::BTreeSet::new();
                    cols.retain(|c| seen.insert(c.0.clone()));
                    mutate_csv(&csv_with(record, &cols, &time), rng, rounds)
                })
                .collect();
            let config_rounds = rng.below(2);
            let text = mutate_toml(text, rng, config_rounds);
            identify_case(Some(&text), &data, &[], dir)
        }
    }
}
