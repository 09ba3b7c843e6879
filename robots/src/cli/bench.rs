//! `robid bench [--robot NAME] [--json]`: median nanoseconds per call of the compiled
//! reference models (docs/performance.md#what-robid-measures), with a baseline measured in
//! the same run (6 x (sin + cos) through libm) so figures compare across machines, and the
//! batched sines and cosines of six angles (`robid_runtime::trig::sin_cos`, vectorised
//! with AVX2) in the same units. Where `Model::run` takes the models' AVX2 instances
//! (`robid_runtime::fused`), each program is also timed through the plain `f64` code, in
//! turn with them. The criterion benches in the workspace's benches/ measure the same
//! functions.

use super::{Error, out};
use robid_runtime::model::PROGRAMS;
use robid_runtime::{Model, Real};
use serde::Serialize;
use std::collections::BTreeMap;
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
    /// Per program of the table, by name, as `Model::run` calls it.
    programs: BTreeMap<&'static str, f64>,
    /// Whether `Model::run` called the AVX2 instances (`robid_runtime::fused::dispatch`).
    avx2_instances: bool,
    /// With the AVX2 instances, the same programs through the plain `f64` code (what a
    /// processor without AVX2 runs), timed in turn with them.
    #[serde(skip_serializing_if = "Option::is_none")]
    plain: Option<BTreeMap<&'static str, f64>>,
    baseline_trig_ns: f64,
    /// `robid_runtime::trig::sin_cos` of six angles.
    batched_trig_ns: f64,
    /// Whether that call took the vector path (AVX2 and FMA).
    vector_trig: bool,
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

/// A deterministic vector of `n` values of magnitude `scale`.
fn filled(n: usize, scale: f64) -> Vec<f64> {
    (0..n)
        .map(|i| scale * (0.3 + 0.17 * i as f64).sin())
        .collect()
}

fn baseline() -> f64 {
    let q = filled(6, 1.0);
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

/// The sines and cosines of six angles in one call, `robid_runtime::trig::sin_cos`.
fn batched() -> f64 {
    let q: [f64; 6] = filled(6, 1.0).try_into().expect("six angles");
    median_ns(|| {
        black_box(robid_runtime::trig::sin_cos(black_box(q)));
    })
}

/// Times every program of the table on `model` through [`Model::run`] (the slice
/// interface: the length checks are part of the figure); where it takes the AVX2
/// instances, each program again through the plain `f64` code right after.
fn time_robot<M: Model + ?Sized>(
    robot: &'static str,
    model: &M,
    (baseline, batched): (f64, f64),
) -> Timing {
    let sizes = model.sizes();
    let avx2 = robid_runtime::fused::dispatch();
    let mut programs = BTreeMap::new();
    let mut plain = BTreeMap::new();
    for p in &PROGRAMS {
        let inputs: Vec<Vec<f64>> = p
            .inputs
            .iter()
            .enumerate()
            .map(|(i, a)| filled(a.size.len(sizes), 0.7 + 0.3 * i as f64))
            .collect();
        let inputs: Vec<&[f64]> = inputs.iter().map(Vec::as_slice).collect();
        let mut out = vec![0.0; p.output.size.len(sizes)];
        let mut time = || {
            median_ns(|| {
                let result = model.run(p.kind, black_box(&inputs), black_box(&mut out));
                black_box(result).ok();
            })
        };
        programs.insert(p.name, time());
        if avx2 {
            robid_runtime::fused::set_enabled(false);
            plain.insert(p.name, time());
            robid_runtime::fused::set_enabled(true);
        }
    }
    Timing {
        robot,
        programs,
        avx2_instances: avx2,
        plain: avx2.then_some(plain),
        baseline_trig_ns: baseline,
        batched_trig_ns: batched,
        vector_trig: robid_runtime::trig::vector_available(),
    }
}

/// Times the compiled models and prints the figures.
pub(crate) fn run(args: &Args) -> Result<(), Error> {
    let names: Vec<&str> = robots::REFERENCES.iter().map(|r| r.name).collect();
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
    let (base, batch) = (baseline(), batched());
    let mut timings = Vec::new();
    for reference in robots::REFERENCES.iter().filter(|r| wanted(r.name)) {
        timings.push(time_robot(
            reference.name,
            &*reference.model(),
            (base, batch),
        ));
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
        "median ns per call (baseline 6 x (sin + cos) via libm: {base:.1} ns; \
         batched sin_cos of 6 angles{}: {batch:.1} ns)",
        if robid_runtime::trig::vector_available() {
            ", AVX2"
        } else {
            ", libm"
        }
    )?;
    write!(stdout, "{:<10}", "robot")?;
    for p in &PROGRAMS {
        write!(stdout, " {:>w$}", p.name, w = p.name.len().max(8))?;
    }
    writeln!(stdout)?;
    for t in &timings {
        let rows = std::iter::once((t.robot, &t.programs))
            .chain(t.plain.as_ref().map(|plain| ("  plain", plain)));
        for (label, programs) in rows {
            write!(stdout, "{label:<10}")?;
            for p in &PROGRAMS {
                let ns = programs.get(p.name).copied().unwrap_or(f64::NAN);
                write!(stdout, " {:>w$.1}", ns, w = p.name.len().max(8))?;
            }
            writeln!(stdout)?;
        }
    }
    if timings.iter().any(|t| t.avx2_instances) {
        writeln!(
            stdout,
            "(the models' AVX2 and FMA instances, which robid calls on this processor; \
             `plain`: the same programs through the f64 code a processor without them runs)"
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
