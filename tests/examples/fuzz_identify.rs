//! The long run of the identification fuzzer (issue 11): `N` end-to-end identifications
//! (load, identify, report, validation) and `N` cases each of the config parser and the CSV
//! reader, from mutated bundled configs, CSV files made from a good UR5e record and the real
//! logs' headers (`tests/src/fuzz_data.rs`, the code of the in-suite test
//! `tests/tests/suite/fuzz_identify.rs`), on two threads with seeds `SEED` and `SEED + 1`.
//!
//! ```sh
//! cargo run --release -p tests --example fuzz_identify -- 100000 [SEED]
//! cargo run --release -p tests --example fuzz_identify -- replay N SEED CASE   # one finding
//! cargo run --release -p tests --example fuzz_identify -- find N SEED VARIANT   # its cases
//! ```
//!
//! Prints the outcomes by kind and error variant, the slowest case, and every broken
//! promise (a panic, a success holding NaN or an infinity); a case that makes no progress
//! for 120 s is reported as a hang and ends the run. Exit status 1 when anything broke.

use tests::fuzz_data;

use std::sync::Arc;
use std::sync::atomic::Ordering;
use std::time::{Duration, Instant};

use fuzz_data::{Plan, Progress, Tally, run};

/// Seconds without progress after which a case counts as a hang.
const HANG: u64 = 120;

/// Runs one case of a run of `n` (thread seed `seed`) without catching its panic, printing
/// what it did.
fn replay(n: usize, seed: u64, case: usize) {
    let plan = Plan {
        configs: n / 2,
        csvs: n / 2,
        identifications: n / 2,
        seed,
        rows: 400,
    };
    let dir = std::env::temp_dir().join(format!("robid-fuzz-replay-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temporary folder");
    let inputs = fuzz_data::Inputs::new(plan);
    println!("case {case}: {}", inputs.kinds[case]);
    println!("{:?}", inputs.case(case, &dir));
    println!("files in {}", dir.display());
}

/// Prints the first cases of a run of `n` (thread seed `seed`) that end with the error
/// variant `variant` (e.g. `Outlier`), to replay them.
fn find(n: usize, seed: u64, variant: &str) {
    let plan = Plan {
        configs: n / 2,
        csvs: n / 2,
        identifications: n / 2,
        seed,
        rows: 400,
    };
    let dir = std::env::temp_dir().join(format!("robid-fuzz-find-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temporary folder");
    let inputs = fuzz_data::Inputs::new(plan);
    let mut found = 0;
    for case in 0..inputs.kinds.len() {
        if let Ok(fuzz_data::Outcome::Error(v)) = inputs.case(case, &dir)
            && v == variant
        {
            println!("case {case} ({})", inputs.kinds[case]);
            found += 1;
            if found == 5 {
                break;
            }
        }
    }
    let _ = std::fs::remove_dir_all(dir);
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.first().is_some_and(|a| a == "find") {
        let num = |i: usize| args.get(i).and_then(|a| a.parse().ok()).unwrap_or(0);
        find(
            num(1),
            num(2) as u64,
            args.get(3).map_or("", String::as_str),
        );
        return;
    }
    if args.first().is_some_and(|a| a == "replay") {
        let num = |i: usize| args.get(i).and_then(|a| a.parse().ok()).unwrap_or(0);
        replay(num(1), num(2) as u64, num(3));
        return;
    }
    let n: usize = args.first().and_then(|a| a.parse().ok()).unwrap_or(1000);
    let seed: u64 = args.get(1).and_then(|a| a.parse().ok()).unwrap_or(1);
    std::panic::set_hook(Box::new(|_| {}));
    let start = Instant::now();
    let threads = 2;
    let workers: Vec<_> = (0..threads)
        .map(|w| {
            let share = n / threads + usize::from(w < n % threads);
            let plan = Plan {
                configs: share,
                csvs: share,
                identifications: share,
                seed: seed + w as u64,
                rows: 400,
            };
            let dir =
                std::env::temp_dir().join(format!("robid-fuzz-long-{}-{w}", std::process::id()));
            std::fs::create_dir_all(&dir).expect("temporary folder");
            let progress = Arc::new(Progress::default());
            let handle = {
                let (dir, progress) = (dir.clone(), progress.clone());
                std::thread::spawn(move || run(plan, &dir, &progress))
            };
            (handle, progress, dir)
        })
        .collect();
    let mut seen: Vec<(usize, Instant)> = vec![(0, Instant::now()); threads];
    let mut last_report = Instant::now();
    while workers.iter().any(|w| !w.0.is_finished()) {
        std::thread::sleep(Duration::from_millis(200));
        for (k, (handle, progress, _)) in workers.iter().enumerate() {
            let done = progress.done.load(Ordering::Relaxed);
            if done != seen[k].0 || handle.is_finished() {
                seen[k] = (done, Instant::now());
            } else if seen[k].1.elapsed() > Duration::from_secs(HANG) {
                let case = progress
                    .current
                    .lock()
                    .map(|c| c.clone())
                    .unwrap_or_default();
                println!("HANG: no progress for {HANG} s in {case}");
                std::process::exit(1);
            }
        }
        if last_report.elapsed() > Duration::from_secs(60) {
            let done: usize = workers
                .iter()
                .map(|w| w.1.done.load(Ordering::Relaxed))
                .sum();
            eprintln!(
                "{done} of {} cases, {:.0} s",
                3 * n,
                start.elapsed().as_secs_f64()
            );
            last_report = Instant::now();
        }
    }
    let _ = std::panic::take_hook();
    let mut total = Tally::default();
    for (handle, _, dir) in workers {
        let t = handle.join().expect("the fuzz loop itself does not panic");
        for (k, v) in t.outcomes {
            *total.outcomes.entry(k).or_default() += v;
        }
        total.violations.extend(t.violations);
        for (k, m) in t.messages {
            total.messages.entry(k).or_insert(m);
        }
        if t.slowest.0 > total.slowest.0 {
            total.slowest = t.slowest;
        }
        let _ = std::fs::remove_dir_all(dir);
    }
    println!(
        "{} config, {} csv, {} identify cases (seed {seed}) in {:.0} s; slowest case {:.2} s ({})",
        total.count("config"),
        total.count("csv"),
        total.count("identify"),
        start.elapsed().as_secs_f64(),
        total.slowest.0.as_secs_f64(),
        total.slowest.1
    );
    for (key, count) in &total.outcomes {
        let message = total.messages.get(key).map_or("", String::as_str);
        println!("  {:9} {:?}: {count}\n      e.g. {message}", key.0, key.1);
    }
    println!("{} violations", total.violations.len());
    for v in total.violations.iter().take(50) {
        println!("  {}: {}", v.case, v.what);
    }
    if !total.violations.is_empty() {
        std::process::exit(1);
    }
}
