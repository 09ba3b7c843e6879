//! `robid bench [--robot NAME] [--json]`: median nanoseconds per call of the compiled
//! reference models (docs/performance.md#what-robid-measures), with a baseline measured in
//! the same run (6 x (sin + cos) through libm) so figures compare across machines. The
//! criterion benches in robots/benches measure the same functions.

use super::{Error, out};
use robid_runtime::Real;
use serde::Serialize;
use std::hint::black_box;
use std::time::Instant;

/// Arguments of `robid bench`.
#[derive(Debug, clap::Args)]
pub(crate) struct Args {
    /// Only this reference robot (default: all).
    #[arg(long)]
    robot: Option<String>,
    /// Print JSON lines instead of a table.
    #[arg(long)]
    json: bool,
}

/// Timings of one robot, nanoseconds per call (medians).
#[derive(Debug, Serialize)]
struct Timing {
    robot: &'static str,
    inverse_dynamics_ns: f64,
    base_regressor_ns: f64,
    mass_matrix_ns: f64,
    gravity_ns: f64,
    baseline_trig_ns: f64,
}

/// Median time per call of `f` over 31 batches of about a millisecond each.
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

/// A deterministic state and parameter vector of the right sizes.
fn filled<const N: usize>(scale: f64) -> [f64; N] {
    core::array::from_fn(|i| scale * (0.3 + 0.17 * i as f64).sin())
}

fn baseline() -> f64 {
    let q: [f64; 6] = filled(1.0);
    median_ns(|| {
        let q = black_box(&q);
        let mut acc = [0.0; 12];
        for j in 0..6 {
            acc[2 * j] = Real::sin(q[j]);
            acc[2 * j + 1] = Real::cos(q[j]);
        }
        black_box(acc);
    })
}

macro_rules! time_robot {
    ($name:literal, $model:ty, $baseline:expr) => {{
        const N: usize = <$model>::DOF;
        const B: usize = <$model>::BASE_PARAMETERS;
        let model = <$model>::default();
        let (q, qd, qdd) = (filled::<N>(1.0), filled::<N>(0.7), filled::<N>(1.3));
        let base = filled::<B>(0.5);
        Timing {
            robot: $name,
            inverse_dynamics_ns: median_ns(|| {
                black_box(model.inverse_dynamics(
                    black_box(&q),
                    black_box(&qd),
                    black_box(&qdd),
                    black_box(&base),
                ));
            }),
            base_regressor_ns: median_ns(|| {
                black_box(model.base_regressor(black_box(&q), black_box(&qd), black_box(&qdd)));
            }),
            mass_matrix_ns: median_ns(|| {
                black_box(model.mass_matrix(black_box(&q), black_box(&base)));
            }),
            gravity_ns: median_ns(|| {
                black_box(model.gravity(black_box(&q), black_box(&base)));
            }),
            baseline_trig_ns: $baseline,
        }
    }};
}

/// Times the compiled models and prints the figures.
pub(crate) fn run(args: &Args) -> Result<(), Error> {
    let names = robots::REFERENCE_ROBOTS;
    if let Some(r) = &args.robot
        && !names.contains(&r.as_str())
    {
        return Err(format!(
            "no compiled robot `{r}`; choose one of: {}",
            names.join(", ")
        )
        .into());
    }
    let wanted = |n: &str| args.robot.as_deref().is_none_or(|r| r == n);
    let base = baseline();
    let mut timings = Vec::new();
    if wanted("ur5e") {
        timings.push(time_robot!("ur5e", robots::Ur5e, base));
    }
    if wanted("puma560") {
        timings.push(time_robot!("puma560", robots::Puma560, base));
    }
    if wanted("rx90") {
        timings.push(time_robot!("rx90", robots::Rx90, base));
    }
    if wanted("tx40") {
        timings.push(time_robot!("tx40", robots::Tx40, base));
    }
    if wanted("lwr4") {
        timings.push(time_robot!("lwr4", robots::Lwr4, base));
    }
    if wanted("panda") {
        timings.push(time_robot!("panda", robots::Panda, base));
    }
    if wanted("stanford") {
        timings.push(time_robot!("stanford", robots::Stanford, base));
    }
    let mut stdout = out::Stdout::new();
    if args.json {
        for t in &timings {
            writeln!(stdout, "{}", serde_json::to_string(t)?)?;
        }
        stdout.flush()?;
        return Ok(());
    }
    writeln!(
        stdout,
        "median ns per call (baseline 6 x (sin + cos) via libm: {base:.1} ns)"
    )?;
    writeln!(
        stdout,
        "{:<10} {:>17} {:>15} {:>12} {:>9}",
        "robot", "inverse_dynamics", "base_regressor", "mass_matrix", "gravity"
    )?;
    for t in &timings {
        writeln!(
            stdout,
            "{:<10} {:>17.1} {:>15.1} {:>12.1} {:>9.1}",
            t.robot, t.inverse_dynamics_ns, t.base_regressor_ns, t.mass_matrix_ns, t.gravity_ns
        )?;
    }
    if cfg!(debug_assertions) {
        writeln!(
            stdout,
            "(dev build: run with --release for meaningful figures)"
        )?;
    }
    stdout.flush()?;
    Ok(())
}
