//! What one criterion evaluation of the Fourier design costs (docs/performance.md#excitation),
//! the old path beside the new one in the same run, on the UR5e with viscous and Coulomb
//! friction (`robid excite ur5e.toml --drive Fv,Fc`, an interpreted model):
//! - the base regressor: `Program::run` (operands matched by kind, the geometry group and
//!   the flat inputs collected on every call) against the compact register form
//!   `Interpreted` runs now;
//! - the criterion of the 48 x 48 information matrix of 100 samples: nalgebra's full
//!   symmetric eigendecomposition (eigenvectors included) against the eigenvalues alone.

use criterion::{Criterion, criterion_group, criterion_main};
use robid_runtime::Model;
use robid_runtime::excite::{Fourier, Information, JointSeries};
use robid_runtime::model::ProgramKind;
use robid_symbolic::program::RobotPrograms;
use robid_symbolic::{Drive, Robot};
use robots::interpreted::Interpreted;
use std::hint::black_box;

fn excite(c: &mut Criterion) {
    let robot = Robot::from_toml(
        include_str!("../robots/descriptions/ur5e.toml"),
        "ur5e.toml",
    )
    .unwrap()
    .with_drive(Drive {
        ia: false,
        fv: true,
        fc: true,
        fo: false,
    });
    let programs = RobotPrograms::derive(&robot).unwrap();
    let model = Interpreted::from_programs(programs.clone()).unwrap();
    let n = model.dof();
    let p = model.base_parameter_count();
    let fourier = Fourier {
        base_frequency: 0.1,
        joints: (0..n)
            .map(|j| {
                let free = [0.3, -0.2, 0.1, 0.05, 0.25, -0.1, 0.1, 0.02];
                JointSeries::from_free(0.1 * j as f64, &free)
            })
            .collect(),
    };
    let (mut q, mut qd, mut qdd) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    fourier.state(1.3, &mut q, &mut qd, &mut qdd);
    let mut y = vec![0.0; n * p];
    let program = &programs[ProgramKind::BaseRegressor];
    assert!(
        programs.geometry.is_empty(),
        "the UR5e has no geometric symbol"
    );
    let mut temps = Vec::new();
    c.bench_function("excite base_regressor Program::run (old)", |b| {
        b.iter(|| {
            let inputs: Vec<&[f64]> = vec![black_box(&q), black_box(&qd), black_box(&qdd)];
            program.run(&inputs, &mut [&mut y], &mut temps).unwrap();
        })
    });
    c.bench_function("excite base_regressor Compact (new)", |b| {
        b.iter(|| {
            model
                .base_regressor_into(black_box(&q), black_box(&qd), black_box(&qdd), &mut y)
                .unwrap()
        })
    });
    let mut info = Information::new(&model);
    for k in 0..100 {
        fourier.state(k as f64 / 10.0, &mut q, &mut qd, &mut qdd);
        info.add(&model, &q, &qd, &qdd).unwrap();
    }
    let g = &info.gram;
    c.bench_function("excite condition SymmetricEigen (old)", |b| {
        b.iter(|| {
            let full = g.clone().lower_triangle() + g.clone().lower_triangle().transpose()
                - nalgebra::DMatrix::from_diagonal(&g.diagonal());
            let e =
                nalgebra::SymmetricEigen::try_new(black_box(full), f64::EPSILON, 10_000).unwrap();
            e.eigenvalues.max() / e.eigenvalues.min()
        })
    });
    c.bench_function("excite condition eigenvalues only (new)", |b| {
        b.iter(|| black_box(&info).condition_number())
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .sample_size(20)
        .measurement_time(std::time::Duration::from_secs(2));
    targets = excite
}
criterion_main!(benches);
