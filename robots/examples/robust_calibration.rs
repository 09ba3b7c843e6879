//! The calibration of the robust (Newey-West) standard deviations against the spread of
//! the estimates over records (docs/identification.md#robust-standard-deviations):
//!
//! ```text
//! cargo run --release -p robots --example robust_calibration [-- N [THREADS [POSITION_NOISE]]]
//! ```
//!
//! The README's UR5e chain through the library calls the commands make: the trajectory of
//! `robid excite robots/descriptions/ur5e.toml --drive Fv,Fc` (Fourier, 30 s at 500 Hz,
//! seed 1), simulated `N` times (default 40) as `robid simulate --parameters
//! robots/parameters/ur5e.toml --torque-noise 0.2 --quantization 1e-5 --columns positions
//! --seed S` does (seeds 1 to N; each record written to a CSV file in the system's
//! temporary folder, read back as `robid identify` reads it), and each record identified
//! with WLS under every processing setting of [`SETTINGS`] (a low-pass's `cutoff =
//! "auto"` chosen on each record, as `identify` chooses it), through the dense path
//! (`pipeline::observation`, `pipeline::estimate`; the streaming one gives its figures to
//! 1e-10).
//!
//! For each setting and each rule for the kernel's lag ([`Rule`]: the rule the library
//! applies, and the candidate rules computed here and set as `Observation::correlated`), it
//! prints, over the 36 base parameters, the median and range of
//!
//! - spread / classical: the standard deviation of the estimates over the `N` records
//!   divided by the RMS over the records of the classical `std`;
//! - spread / robust: the same with the RMS of the robust `std`.
//!
//! A ratio of 1 is a calibrated deviation; above 1 the deviation is too small. With `N`
//! records the spread itself is uncertain by about `1 / sqrt(2 (N - 1))` (11 % for 40).
//! The candidate rules were measured with it and not adopted; the tables and the reasons
//! are in docs/identification.md#robust-standard-deviations (`N` = 40: 250 s on one
//! thread, the trajectory's design, some 8 s, included).
//! Nothing is asserted. `THREADS` (default 1) simulates and identifies that many records at
//! once; `POSITION_NOISE` (rad, default 0) adds `--position-noise` to the simulation, noise
//! that the differentiation carries into the regressor.

use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::time::Instant;

use robid_runtime::Model;
use robid_runtime::data::{Config, Cutoff, load};
use robid_runtime::excite::{FourierDesign, JointLimits};
use robid_runtime::inspect::resolve_cutoff;
use robid_runtime::pipeline::{estimate, observation};
use robid_runtime::simulate::{Noise, Simulation, Trajectory};
use robid_symbolic::Drive;
use robid_symbolic::robot::DriveTerm;
use robots::Reference;
use robots::interpreted::Interpreted;

/// The trajectory: `robid excite`'s defaults.
const DURATION: f64 = 30.0;
const RATE: f64 = 500.0;
/// The simulation's noise: `--torque-noise 0.2 --quantization 1e-5`.
const TORQUE_NOISE: f64 = 0.2;
const QUANTIZATION: f64 = 1e-5;

/// The column mapping of a `robid simulate --columns positions` log.
const MAPPING: &str = r#"
dof = 6
time_column = "t"
[[source]]
position = "q{}"
torque = "tau{}"
"#;

/// The processing settings compared: a name and the config's `[processing]` table (every
/// setting identifies with WLS).
const SETTINGS: [(&str, &str); 7] = [
    (
        "no config: low-pass (auto) on q",
        r#"lowpass = { cutoff = "auto", order = 4, signals = ["q"] }"#,
    ),
    (
        "low-pass (auto) on q, decimation 5",
        r#"lowpass = { cutoff = "auto", order = 4, signals = ["q"] }
decimation = 5"#,
    ),
    (
        "low-pass (auto) on q and tau",
        r#"lowpass = { cutoff = "auto", order = 4, signals = ["q", "tau"] }"#,
    ),
    (
        "low-pass (auto) on q and tau, decimation 5",
        r#"lowpass = { cutoff = "auto", order = 4, signals = ["q", "tau"] }
decimation = 5"#,
    ),
    (
        "Savitzky-Golay 51/3, no low-pass",
        r#"differentiation = { method = "savitzky-golay", window = 51, order = 3 }"#,
    ),
    (
        "Savitzky-Golay 51/3, no low-pass, decimation 5",
        r#"differentiation = { method = "savitzky-golay", window = 51, order = 3 }
decimation = 5"#,
    ),
    (
        "low-pass (auto) on q, Savitzky-Golay 51/3, decimation 5",
        r#"lowpass = { cutoff = "auto", order = 4, signals = ["q"] }
differentiation = { method = "savitzky-golay", window = 51, order = 3 }
decimation = 5"#,
    ),
];

/// A rule for the samples over which the residuals are correlated
/// (`Observation::correlated`; the lag is the larger of it and Newey and West's rule).
#[derive(Clone, Copy)]
enum Rule {
    /// What `pipeline::observation` sets (the library's rule: one cutoff period of the
    /// low-pass, `sample rate / (decimation x cutoff)`, 0 without a low-pass).
    Library,
    /// Two cutoff periods of the low-pass.
    TwoPeriods,
    /// One cutoff period plus a Savitzky-Golay window, `window / decimation` (decimated
    /// samples).
    OnePeriodAndWindow,
}

const RULES: [(Rule, &str); 3] = [
    (Rule::Library, "library"),
    (Rule::TwoPeriods, "2 cutoff periods"),
    (Rule::OnePeriodAndWindow, "1 period + S-G window"),
];

impl Rule {
    /// The correlated samples of `config` (its cutoff resolved) at the decimated sample time
    /// `dt`, `library` those the library set.
    fn correlated(self, config: &Config, dt: f64, library: usize) -> usize {
        let factor = (dt * RATE).round().max(1.0);
        let periods = |n: f64| {
            let cutoff = config
                .processing
                .lowpass
                .as_ref()
                .and_then(|lp| match lp.cutoff {
                    Cutoff::Hz(c) => Some(c),
                    Cutoff::Auto => None,
                });
            cutoff.map_or(0, |c| (n / (dt * c)).ceil() as usize)
        };
        let window = || {
            config
                .processing
                .differentiation
                .window
                .map_or(0, |w| (w as f64 / factor).ceil() as usize)
        };
        match self {
            Rule::Library => library,
            Rule::TwoPeriods => periods(2.0),
            Rule::OnePeriodAndWindow => periods(1.0) + window(),
        }
    }
}

/// One record's estimates under one setting: values, classical deviations, and per rule
/// the robust deviations and the lag.
struct Outcome {
    values: Vec<f64>,
    classical: Vec<f64>,
    robust: Vec<(Vec<f64>, usize)>,
}

fn config_of(processing: &str) -> Config {
    let text = format!("{MAPPING}\n[processing]\n{processing}\n[estimation]\nmethod = \"wls\"\n");
    Config::from_toml_str(&text, Path::new("robust_calibration.toml")).expect("the config")
}

/// The trajectory `robid excite robots/descriptions/ur5e.toml --drive Fv,Fc` writes.
fn trajectory() -> Trajectory {
    let mut drive = Drive::NONE;
    drive.add(DriveTerm::Fv);
    drive.add(DriveTerm::Fc);
    let robot = Reference::named("ur5e")
        .expect("the UR5e is a reference robot")
        .robot()
        .with_drive(drive);
    let model = Interpreted::new(&robot).expect("the model");
    let limits: Vec<JointLimits> = robot
        .joints()
        .iter()
        .map(|j| JointLimits {
            position: j.limits.position.expect("position limits"),
            velocity: j.limits.velocity.expect("velocity limits"),
            acceleration: j.limits.acceleration.expect("acceleration limits"),
            torque: j.limits.torque,
        })
        .collect();
    let start = limits
        .iter()
        .map(|l| 0.5 * (l.position[0] + l.position[1]))
        .collect();
    let design = FourierDesign {
        seed: 1,
        start: Some(start),
        ..FourierDesign::default()
    };
    design
        .optimize(&model, &limits, None)
        .expect("the design")
        .fourier
        .sample(DURATION, RATE)
        .expect("the trajectory")
}

/// Simulates record `seed` and identifies it under every setting.
fn record(
    model: &Interpreted,
    base: &[f64],
    reference: &Trajectory,
    seed: u64,
    position_noise: f64,
    folder: &Path,
) -> Vec<Outcome> {
    let sim = Simulation {
        seed,
        noise: Noise {
            torque: vec![TORQUE_NOISE],
            position: position_noise,
            quantization: QUANTIZATION,
            ..Noise::default()
        },
        ..Simulation::default()
    };
    let simulated = sim.run(model, base, reference).expect("the simulation");
    let path = folder.join(format!("ur5e_{seed}.csv"));
    simulated
        .measured
        .write_log_csv(&path, 1, None)
        .expect("write the record");
    let files = [path.clone()];
    let outcomes = SETTINGS
        .iter()
        .map(|(_, processing)| {
            let mut config = config_of(processing);
            let data = load(&config, &files, model.dof()).expect("load");
            resolve_cutoff(&mut config, &data).expect("the cutoff");
            let (mut obs, dt) = observation(model, &data, &config).expect("the observation");
            let library = obs.correlated;
            let e = estimate(&obs, &config).expect("the estimate");
            let robust = RULES
                .iter()
                .map(|(rule, _)| {
                    obs.correlated = rule.correlated(&config, dt, library);
                    let r = estimate(&obs, &config)
                        .expect("the estimate")
                        .robust
                        .expect("robust deviations");
                    (r.std, r.lag)
                })
                .collect();
            Outcome {
                values: e.values,
                classical: e.std,
                robust,
            }
        })
        .collect();
    std::fs::remove_file(&path).expect("remove the record");
    outcomes
}

/// Median, lowest and highest of `v`.
fn summary(mut v: Vec<f64>) -> (f64, f64, f64) {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    let median = if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    };
    (median, v[0], v[n - 1])
}

/// Per parameter: the spread of the estimates over the records divided by the RMS of
/// `deviation` over the records.
fn ratios(outcomes: &[&Outcome], deviation: impl Fn(&Outcome) -> &[f64]) -> Vec<f64> {
    let n = outcomes.len() as f64;
    let p = outcomes[0].values.len();
    (0..p)
        .map(|i| {
            let mean = outcomes.iter().map(|o| o.values[i]).sum::<f64>() / n;
            let spread = (outcomes
                .iter()
                .map(|o| (o.values[i] - mean).powi(2))
                .sum::<f64>()
                / (n - 1.0))
                .sqrt();
            let rms = (outcomes
                .iter()
                .map(|o| deviation(o)[i].powi(2))
                .sum::<f64>()
                / n)
                .sqrt();
            spread / rms
        })
        .collect()
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let n: u64 = args.first().and_then(|v| v.parse().ok()).unwrap_or(40);
    let threads: u64 = args.get(1).and_then(|v| v.parse().ok()).unwrap_or(1).max(1);
    let position_noise: f64 = args.get(2).and_then(|v| v.parse().ok()).unwrap_or(0.0);
    assert!(n >= 2, "N: at least 2 records");
    let start = Instant::now();
    let folder: PathBuf =
        std::env::temp_dir().join(format!("robid-robust-calibration-{}", std::process::id()));
    std::fs::create_dir_all(&folder).expect("the temporary folder");
    // through its CSV file, as `robid simulate` reads what `robid excite` wrote
    let traj = folder.join("traj.csv");
    trajectory().write_csv(&traj).expect("write the trajectory");
    let reference = Trajectory::read_csv(&traj, 6).expect("read the trajectory");
    std::fs::remove_file(&traj).expect("remove the trajectory");
    eprintln!(
        "trajectory designed in {:.1} s",
        start.elapsed().as_secs_f64()
    );
    let ur5e = Reference::named("ur5e").expect("the UR5e is a reference robot");
    let model = Interpreted::new(&ur5e.robot()).expect("the model");
    let base = ur5e
        .parameter_file()
        .base_parameters(&model)
        .expect("the reference parameters fit the model");
    let results: Mutex<Vec<(u64, Vec<Outcome>)>> = Mutex::new(Vec::new());
    std::thread::scope(|scope| {
        for t in 0..threads {
            let (model, base, reference, folder, results) =
                (&model, &base, &reference, &folder, &results);
            scope.spawn(move || {
                for seed in (1..=n).filter(|s| (s - 1) % threads == t) {
                    let outcomes = record(model, base, reference, seed, position_noise, folder);
                    let mut r = results.lock().expect("no thread panicked");
                    r.push((seed, outcomes));
                    eprintln!(
                        "record {seed} ({} of {n}) at {:.0} s",
                        r.len(),
                        start.elapsed().as_secs_f64()
                    );
                }
            });
        }
    });
    std::fs::remove_dir(&folder).ok();
    let mut results = results.into_inner().expect("no thread panicked");
    results.sort_by_key(|(seed, _)| *seed);
    println!(
        "{n} records (seeds 1 to {n}, position noise {position_noise} rad), {} base parameters, \
         WLS; median (lowest to highest) over the parameters; lag: the kernel's, lowest to \
         highest over the records",
        results[0].1[0].values.len()
    );
    println!();
    println!("| processing | lag rule | lag | spread / classical std | spread / robust std |");
    println!("|---|---|---|---|---|");
    for (s, (name, _)) in SETTINGS.iter().enumerate() {
        let outcomes: Vec<&Outcome> = results.iter().map(|(_, o)| &o[s]).collect();
        let (cm, clo, chi) = summary(ratios(&outcomes, |o| &o.classical));
        for (r, (_, rule)) in RULES.iter().enumerate() {
            let (rm, rlo, rhi) = summary(ratios(&outcomes, |o| &o.robust[r].0));
            let lags: Vec<usize> = outcomes.iter().map(|o| o.robust[r].1).collect();
            let (lo, hi) = (
                lags.iter().min().copied().unwrap_or(0),
                lags.iter().max().copied().unwrap_or(0),
            );
            let lag = if lo == hi {
                format!("{lo}")
            } else {
                format!("{lo}-{hi}")
            };
            println!(
                "| {name} | {rule} | {lag} | {cm:.2} ({clo:.2}-{chi:.2}) | {rm:.2} ({rlo:.2}-{rhi:.2}) |"
            );
        }
    }
    eprintln!("{:.0} s in all", start.elapsed().as_secs_f64());
}
