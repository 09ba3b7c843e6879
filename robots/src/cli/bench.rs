//! `robid bench [--robot NAME] [--json]`: median nanoseconds per call of the compiled
//! reference models (docs/performance.md#what-robid-measures), each also as a multiple of a
//! baseline timed in turn with it (6 x (sin + cos) through libm) so figures compare across
//! machines and hold when the load changes during the run, and the
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

/// Timings of one robot, nanoseconds per call (medians), and each as a multiple of the
/// baseline timed alongside it ([`paired`]).
#[derive(Debug, Serialize)]
struct Timing {
    robot: &'static str,
    /// The same times as `programs`, flat as `<program>_ns` (`inverse_dynamics_ns`,
    /// `mass_matrix_ns`, ...): the stable form scripts read (docs/command-line.md).
    #[serde(flatten)]
    flat_ns: BTreeMap<String, f64>,
    /// Per program of the table, by name, as `Model::run` calls it.
    programs: BTreeMap<&'static str, f64>,
    /// The same as multiples of the baseline timed in turn with each.
    ratios: BTreeMap<&'static str, f64>,
    /// Whether `Model::run` called the AVX2 instances (`robid_runtime::fused::dispatch`).
    avx2_instances: bool,
    /// With the AVX2 instances, the same programs through the plain `f64` code (what a
    /// processor without AVX2 runs), timed right after them.
    #[serde(skip_serializing_if = "Option::is_none")]
    plain: Option<BTreeMap<&'static str, f64>>,
    /// Those as multiples of the baseline timed in turn with each.
    #[serde(skip_serializing_if = "Option::is_none")]
    plain_ratios: Option<BTreeMap<&'static str, f64>>,
    /// 6 x (sin + cos) through libm: the median of the baselines timed with this robot's
    /// programs.
    baseline_trig_ns: f64,
    /// `robid_runtime::trig::sin_cos` of six angles.
    batched_trig_ns: f64,
    /// That as a multiple of the baseline timed in turn with it.
    batched_trig_ratio: f64,
    /// Whether that call took the vector path (AVX2 and FMA).
    vector_trig: bool,
}

/// A batch size for `f`: calls that take about a millisecond together.
fn batch_size(f: &mut impl FnMut()) -> usize {
    let mut batch = 1usize;
    loop {
        let t = Instant::now();
        for _ in 0..batch {
            f();
        }
        if t.elapsed().as_secs_f64() > 1e-3 || batch >= 1 << 24 {
            return batch;
        }
        batch *= 2;
    }
}

/// Nanoseconds per call of `f` over one batch of `batch` calls.
fn time_batch(f: &mut impl FnMut(), batch: usize) -> f64 {
    let t = Instant::now();
    for _ in 0..batch {
        f();
    }
    t.elapsed().as_secs_f64() * 1e9 / batch as f64
}

fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}

/// Batches of about a millisecond that [`paired`] times in turn.
const ROUNDS: usize = 31;

/// Nanoseconds per call of `f` and its multiple of the baseline ([`baseline_call`]), from
/// [`ROUNDS`] rounds of a batch of the baseline then a batch of `f`: the median time of
/// `f`, the median of each round's ratio, and the median time of the baseline. A ratio of
/// batches a millisecond apart holds when the machine's load changes during the run,
/// which a baseline timed once at the start does not.
fn paired(mut f: impl FnMut()) -> (f64, f64, f64) {
    let mut base = baseline_call();
    let (nb, nf) = (batch_size(&mut base), batch_size(&mut f));
    let (mut times, mut ratios, mut bases) = (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..ROUNDS {
        let b = time_batch(&mut base, nb);
        let t = time_batch(&mut f, nf);
        times.push(t);
        ratios.push(t / b);
        bases.push(b);
    }
    (median(times), median(ratios), median(bases))
}

/// A deterministic vector of `n` values of magnitude `scale`.
fn filled(n: usize, scale: f64) -> Vec<f64> {
    (0..n)
        .map(|i| scale * (0.3 + 0.17 * i as f64).sin())
        .collect()
}

/// The baseline: 6 x (sin + cos) through libm.
fn baseline_call() -> impl FnMut() {
    let q = filled(6, 1.0);
    move || {
        let q = black_box(&q);
        let mut acc = [0.0; 12];
        for j in 0..6 {
            acc[2 * j] = Real::sin(q[j]);
            acc[2 * j + 1] = Real::cos(q[j]);
        }
        black_box(acc);
    }
}

/// The sines and cosines of six angles in one call, `robid_runtime::trig::sin_cos`,
/// paired with the baseline ([`paired`]).
fn batched() -> (f64, f64, f64) {
    let q: [f64; 6] = filled(6, 1.0).try_into().expect("six angles");
    paired(|| {
        black_box(robid_runtime::trig::sin_cos(black_box(q)));
    })
}

/// Times every program of the table on `model` through [`Model::run`] (the slice
/// interface: the length checks are part of the figure), each in turn with the baseline
/// ([`paired`]); where it takes the AVX2 instances, each program again through the plain
/// `f64` code right after. `batched` is the batched trigonometry's timing.
fn time_robot<M: Model + ?Sized>(
    robot: &'static str,
    model: &M,
    batched: (f64, f64, f64),
) -> Timing {
    let sizes = model.sizes();
    let avx2 = robid_runtime::fused::dispatch();
    let (mut programs, mut ratios) = (BTreeMap::new(), BTreeMap::new());
    let (mut plain, mut plain_ratios) = (BTreeMap::new(), BTreeMap::new());
    let mut baselines = Vec::new();
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
            paired(|| {
                let result = model.run(p.kind, black_box(&inputs), black_box(&mut out));
                black_box(result).ok();
            })
        };
        let (ns, ratio, base) = time();
        programs.insert(p.name, ns);
        ratios.insert(p.name, ratio);
        baselines.push(base);
        if avx2 {
            robid_runtime::fused::set_enabled(false);
            let (ns, ratio, base) = time();
            robid_runtime::fused::set_enabled(true);
            plain.insert(p.name, ns);
            plain_ratios.insert(p.name, ratio);
            baselines.push(base);
        }
    }
    Timing {
        robot,
        flat_ns: programs
            .iter()
            .map(|(name, &ns)| (format!("{name}_ns"), ns))
            .collect(),
        programs,
        ratios,
        avx2_instances: avx2,
        plain: avx2.then_some(plain),
        plain_ratios: avx2.then_some(plain_ratios),
        baseline_trig_ns: median(baselines),
        batched_trig_ns: batched.0,
        batched_trig_ratio: batched.1,
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
            "no compiled robot `{}`; choose one of: {}",
            robid_runtime::names::short(r),
            names.join(", ")
        )
        .into());
    }
    let wanted = |n: &str| args.robot.as_deref().is_none_or(|r| r == n);
    let batched = batched();
    let mut timings = Vec::new();
    for reference in robots::REFERENCES.iter().filter(|r| wanted(r.name)) {
        timings.push(time_robot(reference.name, &*reference.model(), batched));
    }
    let mut stdout = out::Stdout::new();
    if args.json {
        for t in &timings {
            writeln!(stdout, "{}", serde_json::to_string(t)?)?;
        }
        stdout.flush()?;
        return Ok(());
    }
    let base = median(timings.iter().map(|t| t.baseline_trig_ns).collect());
    writeln!(
        stdout,
        "median ns per call, and (below) multiples of the baseline timed in turn with each \
         (6 x (sin + cos) via libm: {base:.1} ns; batched sin_cos of 6 angles{}: {:.1} ns, \
         {:.2} x)",
        if robid_runtime::trig::vector_available() {
            ", AVX2"
        } else {
            ", libm"
        },
        batched.0,
        batched.1
    )?;
    for ratio in [false, true] {
        write!(stdout, "{:<10}", if ratio { "x baseline" } else { "robot" })?;
        for p in &PROGRAMS {
            write!(stdout, " {:>w$}", p.name, w = p.name.len().max(8))?;
        }
        writeln!(stdout)?;
        for t in &timings {
            let (programs, plain) = if ratio {
                (&t.ratios, t.plain_ratios.as_ref())
            } else {
                (&t.programs, t.plain.as_ref())
            };
            let rows =
                std::iter::once((t.robot, programs)).chain(plain.map(|plain| ("  plain", plain)));
            for (label, programs) in rows {
                write!(stdout, "{label:<10}")?;
                for p in &PROGRAMS {
                    let v = programs.get(p.name).copied().unwrap_or(f64::NAN);
                    if ratio {
                        write!(stdout, " {:>w$.2}", v, w = p.name.len().max(8))?;
                    } else {
                        write!(stdout, " {:>w$.1}", v, w = p.name.len().max(8))?;
                    }
                }
                writeln!(stdout)?;
            }
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
