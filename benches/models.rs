//! Speed of the compiled UR5e model (docs/performance.md#what-robid-measures), with a
//! baseline measured in the same run: 6 x (sin + cos) through libm, the floor of any model
//! that evaluates the joint angles' trigonometry; and the batched sines and cosines alone
//! (`robid_runtime::trig`), vectorised and through libm. The `x2` and `x4` figures run
//! two and four states side by side in one call (`robid_runtime::lanes::Lanes`): divide
//! them by the states for a per-state cost.

use criterion::{Criterion, criterion_group, criterion_main};
use robid_runtime::Real;
use robid_runtime::lanes::Lanes;
use robots::Ur5e;
use std::hint::black_box;

/// The UR5e's arguments: q, qd, qdd, base parameters.
type State<T> = ([T; 6], [T; 6], [T; 6], [T; 36]);

fn state() -> State<f64> {
    let q = [0.3, -1.2, 0.8, 0.4, -0.7, 1.9];
    let qd = [0.5, -0.3, 0.9, -1.1, 0.2, 0.7];
    let qdd = [1.5, -0.4, 0.2, 0.8, -1.3, 0.6];
    let mut base = [0.0; 36];
    for (i, b) in base.iter_mut().enumerate() {
        *b = 0.1 + 0.05 * i as f64;
    }
    (q, qd, qdd, base)
}

fn ur5e(c: &mut Criterion) {
    let (q, qd, qdd, base) = state();
    let model = Ur5e;
    c.bench_function("baseline 6 x (sin + cos) libm", |b| {
        b.iter(|| {
            let q = black_box(&q);
            let mut acc = [0.0; 12];
            for j in 0..6 {
                acc[2 * j] = libm::sin(q[j]);
                acc[2 * j + 1] = libm::cos(q[j]);
            }
            acc
        })
    });
    c.bench_function("trig::sin_cos of 6 angles (AVX2 when available)", |b| {
        b.iter(|| robid_runtime::trig::sin_cos(black_box(q)))
    });
    c.bench_function("trig::sin_cos_libm of 6 angles", |b| {
        b.iter(|| robid_runtime::trig::sin_cos_libm(black_box(q)))
    });
    dynamics(c, "", (q, qd, qdd, base));
    c.bench_function("ur5e mass_matrix", |b| {
        b.iter(|| model.mass_matrix(black_box(&q), black_box(&base)))
    });
    c.bench_function("ur5e gravity", |b| {
        b.iter(|| model.gravity(black_box(&q), black_box(&base)))
    });
    lanes::<2>(c, " x2");
    lanes::<4>(c, " x4");
}

/// The UR5e's inverse dynamics and base regressor at one state of scalar `T` (`label`
/// after their names).
fn dynamics<T: Real>(c: &mut Criterion, label: &str, (q, qd, qdd, base): State<T>) {
    let model = Ur5e;
    c.bench_function(&format!("ur5e inverse_dynamics{label}"), |b| {
        b.iter(|| {
            model.inverse_dynamics(
                black_box(&q),
                black_box(&qd),
                black_box(&qdd),
                black_box(&base),
            )
        })
    });
    c.bench_function(&format!("ur5e base_regressor{label}"), |b| {
        b.iter(|| model.base_regressor(black_box(&q), black_box(&qd), black_box(&qdd)))
    });
}

/// [`dynamics`] of `W` states in one call: the state of [`state`] with each value moved
/// by 0.1 per lane (the base parameters the same in every lane).
fn lanes<const W: usize>(c: &mut Criterion, label: &str) {
    let (q, qd, qdd, base) = state();
    let spread = |x: [f64; 6]| x.map(|v| Lanes::<W>(std::array::from_fn(|l| v + 0.1 * l as f64)));
    let base = base.map(|v| Lanes::<W>([v; W]));
    dynamics(c, label, (spread(q), spread(qd), spread(qdd), base));
}

criterion_group!(benches, ur5e);
criterion_main!(benches);
