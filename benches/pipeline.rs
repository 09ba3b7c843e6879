//! CSV to identified parameters: 30 s of 6-DOF data at 1 kHz (30,000 samples) with the
//! synthetic 48-parameter model, on one core and on all cores; on one core also the
//! dense path (the whole observation matrix) that OLS took before it streamed.

use std::hint::black_box;
use std::path::{Path, PathBuf};

use criterion::{Criterion, criterion_group, criterion_main};
use robid_runtime::Model;
#[allow(unused_imports)]
use robid_runtime::Real;
use robid_runtime::data::{Config, load};
#[allow(unused_imports)]
use robid_runtime::model::{LengthError, ProgramKind, check_arguments, check_length};
use robid_runtime::pipeline::{estimate, identify, observation};
use robid_runtime::validate::Prediction;

#[path = "../robid-runtime/src/pipeline/synthetic.rs"]
mod synthetic;

fn setup() -> (PathBuf, Config) {
    let dir = std::env::temp_dir().join("robid-bench");
    std::fs::create_dir_all(&dir).expect("temp dir");
    let file = dir.join("synthetic_30k.csv");
    if !file.exists() {
        std::fs::write(&file, synthetic::csv(30_000, 1000.0, 0.05)).expect("write csv");
    }
    let text = synthetic::CONFIG.replace("decimation = 10", "decimation = 20");
    let config = Config::from_toml_str(&text, Path::new("bench.toml")).expect("config");
    (file, config)
}

fn run(file: &Path, config: &Config, model: &(dyn Model + Sync)) -> f64 {
    let data = load(config, &[file.to_path_buf()], model.dof()).expect("load");
    let id = identify(model, &data, config).expect("identify");
    id.fit.relative_error
}

fn bench(c: &mut Criterion) {
    let (file, config) = setup();
    let model = synthetic::Synthetic::default();
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("pool");
    let mut group = c.benchmark_group("csv_to_result_30k_6dof");
    group.sample_size(20);
    group.bench_function("one_core", |b| {
        b.iter(|| one.install(|| black_box(run(&file, &config, &model))))
    });
    group.bench_function("all_cores", |b| {
        b.iter(|| black_box(run(&file, &config, &model)))
    });
    group.finish();
    let data = load(&config, std::slice::from_ref(&file), 6).expect("load");
    let stages = |b: &mut criterion::Bencher<'_>| {
        b.iter(|| {
            one.install(|| {
                black_box(
                    load(&config, std::slice::from_ref(&file), 6)
                        .expect("load")
                        .samples(),
                )
            })
        })
    };
    c.bench_function("load_csv_30k_one_core", stages);
    c.bench_function("identify_30k_one_core", |b| {
        b.iter(|| {
            one.install(|| black_box(identify(&model, &data, &config).expect("identify").fit.nmse))
        })
    });
    // OLS streams (identify); the dense path builds the whole observation matrix
    // (observation + estimate + prediction), the path every OLS run took before
    let dense = |b: &mut criterion::Bencher<'_>| {
        b.iter(|| {
            one.install(|| {
                let (obs, dt) = observation(&model, &data, &config).expect("observation");
                let e = estimate(&obs, &config).expect("estimate");
                black_box(Prediction::new(&obs, &e.values, dt).unwrap().fit().nmse)
            })
        })
    };
    c.bench_function("identify_30k_one_core_dense", dense);
}

criterion_group!(benches, bench);
criterion_main!(benches);
