//! The identification inputs under mutation (issue 11): the bundled configs, CSV files
//! made from a good UR5e record and the real logs' headers, mutated by a seeded loop
//! (`tests/src/fuzz_data.rs`), through the config parser, the CSV reader and `identify` end
//! to end (load, identification, report, validation). No case may panic, hang (a watchdog
//! fails the test when a case takes more than 30 s) or succeed with a non-finite number.
//! The long run is `cargo run --release -p tests --example fuzz_identify -- N [SEED]`.

use tests::fuzz_data;
use tests::scratch::Scratch;

use std::sync::Arc;
use std::time::{Duration, Instant};

use fuzz_data::{Plan, Progress, run};

/// Seconds without progress after which a case counts as a hang.
const HANG: u64 = 30;

#[test]
fn mutated_configs_csvs_and_identifications_never_panic_hang_or_give_nan() {
    // the panics are caught and counted; their messages would only clutter the output
    std::panic::set_hook(Box::new(|_| {}));
    let tmp = Scratch::new();
    let dir = tmp.dir().to_path_buf();
    let plan = Plan {
        configs: 8000,
        csvs: 8000,
        identifications: 800,
        seed: 20_261_123,
        rows: 400,
    };
    let progress = Arc::new(Progress::default());
    let worker = {
        let (dir, progress) = (dir.clone(), progress.clone());
        std::thread::spawn(move || run(plan, &dir, &progress))
    };
    let start = Instant::now();
    let mut seen = (0, Instant::now());
    while !worker.is_finished() {
        std::thread::sleep(Duration::from_millis(100));
        let done = progress.done.load(std::sync::atomic::Ordering::Relaxed);
        if done != seen.0 {
            seen = (done, Instant::now());
        } else if seen.1.elapsed() > Duration::from_secs(HANG) {
            let case = progress
                .current
                .lock()
                .map(|c| c.clone())
                .unwrap_or_default();
            let _ = std::panic::take_hook();
            panic!("no progress for {HANG} s: {case} hangs");
        }
    }
    let _ = std::panic::take_hook();
    let tally = worker.join().expect("the fuzz loop itself does not panic");
    println!(
        "{} config, {} csv, {} identify cases in {:.1} s; slowest {:.2} s ({})",
        tally.count("config"),
        tally.count("csv"),
        tally.count("identify"),
        start.elapsed().as_secs_f64(),
        tally.slowest.0.as_secs_f64(),
        tally.slowest.1
    );
    for (key, n) in &tally.outcomes {
        let message = tally.messages.get(key).map_or("", String::as_str);
        println!("  {:9} {:?}: {n}  {message}", key.0, key.1);
    }
    assert!(
        tally.violations.is_empty(),
        "{} violations, first: {:?}",
        tally.violations.len(),
        tally.violations.first()
    );
    // the loop reaches the estimator: mutations are not all fatal
    assert!(tally.successes("identify") >= 150, "{:?}", tally.outcomes);
    assert!(tally.successes("csv") >= 100 && tally.successes("config") >= 100);
}
