//! "CSV file -> identification result" with the compiled UR5e (issue 5: 30 s of 6-DOF data at
//! 1 kHz, 30,000 samples, under 100 ms on one core).
//!
//! At start the bench simulates the UR5e (closed-loop, torque and position noise, encoder
//! quantization) along a sum-of-sines trajectory at 1 kHz for 30 s and writes the record as
//! `robid simulate` does (`t,q1..6,qd1..6,qdd1..6,tau1..6`, 25 columns, about 9 MB). Each
//! iteration then loads that file and identifies, in two configurations:
//!
//! - `simulated_record`: the config of `robid identify` for such files (measured velocities
//!   and accelerations, no filter, no decimation: 180,000 equations x 36 parameters);
//! - `real_log`: what a real log gets (positions and torques only, zero-phase low-pass of
//!   the positions, central differences, decimation by 10, rest samples removed).
//!
//! The number of cores is the process's: run it once with
//! `RAYON_NUM_THREADS=1 taskset -c 0 cargo bench -p robid-benches --bench identify` (one core) and
//! once plainly (all cores). `load_only` and `identify_only` split the real-log figure.

use std::hint::black_box;
use std::path::{Path, PathBuf};

use criterion::{Criterion, criterion_group, criterion_main};
use robid_runtime::Model;
use robid_runtime::data::{Config, load};
use robid_runtime::pipeline::identify;
use robid_runtime::simulate::{Noise, Simulation, Trajectory};
use robots::Ur5e;

const RATE: f64 = 1000.0;
const SAMPLES: usize = 30_000;

/// The reference UR5e base parameters (`parameters/ur5e.toml`, rigid body).
fn truth(model: &Ur5e) -> Vec<f64> {
    robots::Reference::named("ur5e")
        .expect("a reference robot")
        .parameter_file()
        .base_parameters(model)
        .expect("the reference parameters fit the model")
}

/// Sums of three sines per joint (amplitudes within the UR5e's limits).
fn trajectory() -> Trajectory {
    let t: Vec<f64> = (0..SAMPLES).map(|k| k as f64 / RATE).collect();
    let mut tr = Trajectory::zeros(6, t);
    for j in 0..6 {
        for k in 0..SAMPLES {
            let t = tr.t[k];
            let (mut a, mut b, mut c) = (0.0, 0.0, 0.0);
            for h in 1..=3 {
                let w = 0.6 * h as f64 * (1.0 + 0.11 * j as f64);
                let amp = 0.7 / h as f64;
                let ph = 0.8 * j as f64 + h as f64;
                a += amp * (w * t + ph).sin();
                b += amp * w * (w * t + ph).cos();
                c -= amp * w * w * (w * t + ph).sin();
            }
            tr.q[j][k] = a;
            tr.qd[j][k] = b;
            tr.qdd[j][k] = c;
        }
    }
    tr
}

fn setup() -> PathBuf {
    let dir = std::env::temp_dir().join("robid-bench");
    std::fs::create_dir_all(&dir).expect("temp dir");
    let file = dir.join("ur5e_30k_1khz.csv");
    if !file.exists() {
        let model = Ur5e;
        let sim = Simulation {
            noise: Noise {
                torque: vec![0.5, 0.5, 0.3, 0.1, 0.1, 0.05],
                position: 1e-5,
                quantization: std::f64::consts::TAU / f64::from(1 << 20),
                ..Noise::default()
            },
            substeps: 2,
            ..Simulation::default()
        };
        let record = sim
            .run(&model, &truth(&model), &trajectory())
            .expect("simulate");
        let partial = dir.join(format!("ur5e_30k_1khz.{}.tmp", std::process::id()));
        record.measured.write_csv(&partial).expect("write csv");
        std::fs::rename(&partial, &file).expect("rename");
    }
    file
}

/// `robid identify`'s config for a file written by `robid simulate`.
const SIMULATED: &str = r#"
time_column = "t"
[[source]]
position = "q{}"
velocity = "qd{}"
acceleration = "qdd{}"
torque = "tau{}"
"#;

/// A real log's processing: positions and torques only.
const REAL: &str = r#"
time_column = "t"
[[source]]
position = "q{}"
torque = "tau{}"
[processing]
lowpass = { cutoff = 20.0, order = 4, signals = ["q"] }
decimation = 10
rest_velocity = 0.02
"#;

fn run(file: &Path, config: &Config, model: &(dyn Model + Sync)) -> f64 {
    let data = load(config, &[file.to_path_buf()], model.dof()).expect("load");
    let id = identify(model, &data, config).expect("identify");
    id.fit.relative_error
}

fn bench(c: &mut Criterion) {
    let file = setup();
    let model = Ur5e;
    for (name, text) in [("simulated_record", SIMULATED), ("real_log", REAL)] {
        let config = Config::from_toml_str(text, Path::new("bench.toml")).expect("config");
        let e = run(&file, &config, &model);
        assert!(e < 0.05, "{name}: relative error {e}");
        let mut group = c.benchmark_group(format!("ur5e_30k/{name}"));
        group.sample_size(20);
        group.bench_function("csv_to_result", |b| {
            b.iter(|| black_box(run(&file, &config, &model)))
        });
        group.finish();
    }
    let config = Config::from_toml_str(REAL, Path::new("bench.toml")).expect("config");
    let files = [file.clone()];
    c.bench_function("ur5e_30k/real_log/load_only", |b| {
        b.iter(|| black_box(load(&config, &files, 6).expect("load").samples()))
    });
    let data = load(&config, &files, 6).expect("load");
    c.bench_function("ur5e_30k/real_log/identify_only", |b| {
        b.iter(|| black_box(identify(&model, &data, &config).expect("identify").fit.nmse))
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
