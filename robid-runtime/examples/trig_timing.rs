//! Times the batched sines and cosines (`robid_runtime::trig`) against libm, in the same
//! run, as multiples of the baseline `robid bench` uses (6 x (sin + cos) through libm):
//! `cargo run --release -p robid-runtime --example trig_timing`. Add
//! `RUSTFLAGS="-C target-feature=+avx2,+fma"` to see the inlined vector path in
//! `sin_cos_static`.

use robid_runtime::trig;
use std::hint::black_box;
use std::time::Instant;

/// Median nanoseconds per call of `f` over 31 batches of about a millisecond each.
fn median_ns(mut f: impl FnMut()) -> f64 {
    let mut batch = 1usize;
    loop {
        let t = Instant::now();
        for _ in 0..batch {
            f();
        }
        if t.elapsed().as_secs_f64() > 1e-3 || batch >= 1 << 24 {
            break;
        }
        batch *= 2;
    }
    let mut samples: Vec<f64> = (0..31)
        .map(|_| {
            let t = Instant::now();
            for _ in 0..batch {
                f();
            }
            t.elapsed().as_secs_f64() * 1e9 / batch as f64
        })
        .collect();
    samples.sort_by(f64::total_cmp);
    samples[samples.len() / 2]
}

/// The three functions of `trig` on `N` angles, nanoseconds per call.
fn time<const N: usize>() -> [f64; 3] {
    let q: [f64; N] = core::array::from_fn(|i| 2.5 * (0.3 + 0.17 * i as f64).sin());
    [
        median_ns(|| {
            black_box(trig::sin_cos_libm(black_box(q)));
        }),
        median_ns(|| {
            black_box(trig::sin_cos(black_box(q)));
        }),
        median_ns(|| {
            black_box(trig::sin_cos_static(black_box(q)));
        }),
    ]
}

fn main() {
    let q = [0.3, -1.2, 0.8, 0.4, -0.7, 1.9];
    let base = median_ns(|| {
        let q = black_box(&q);
        let mut acc = [0.0; 12];
        for j in 0..6 {
            acc[2 * j] = libm::sin(q[j]);
            acc[2 * j + 1] = libm::cos(q[j]);
        }
        black_box(acc);
    });
    println!(
        "baseline 6 x (sin + cos) via libm: {base:.1} ns; vector path available: {}",
        trig::vector_available()
    );
    println!(
        "angles  sin_cos_libm  sin_cos (run-time)  sin_cos_static   (multiples of the baseline)"
    );
    for (n, t) in [
        (5, time::<5>()),
        (6, time::<6>()),
        (8, time::<8>()),
        (16, time::<16>()),
        (64, time::<64>()),
    ] {
        println!(
            "{n:>6}  {:>12.2}  {:>18.2}  {:>14.2}",
            t[0] / base,
            t[1] / base,
            t[2] / base
        );
    }
}
