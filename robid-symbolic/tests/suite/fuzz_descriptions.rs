//! The description fuzzer (`examples/fuzz_descriptions.rs`) in the test
//! suite: a few thousand mutated descriptions read, the robots among them
//! derived and emitted, with no panic, no case over its time budget and no
//! non-finite number in base parameters or programs. The long run is
//! `cargo run --release -p robid-symbolic --example fuzz_descriptions -- 1000000`.

#[path = "../../examples/fuzz_descriptions.rs"]
mod fuzz;

use std::time::Duration;

#[test]
fn fuzz_descriptions_quick() {
    let config = fuzz::Config {
        cases: 4000,
        seed: 2026,
        derive_time: Duration::from_secs(10),
    };
    let report = fuzz::run(&config);
    assert!(
        report.findings.is_empty(),
        "{} findings:\n{}",
        report.findings.len(),
        report.findings.join("\n\n")
    );
    // The mutations reach every stage.
    assert_eq!(report.cases, config.cases);
    assert!(report.robots > 200, "{report:?}");
    assert!(report.derived >= 5 && report.emitted >= 5, "{report:?}");
}
