//! Prints the time to derive the complete Newton-Euler regressor (all drive terms) of every
//! reference robot, and of the Lagrange-Euler regressor for comparison. Run with
//! `cargo run -p tests --example derivation_time [--release]`; nothing is asserted.

use robid_symbolic::{Derivation, Drive};
use std::time::Instant;
use tests::reference::ROBOTS;

fn main() {
    let profile = if cfg!(debug_assertions) {
        "dev"
    } else {
        "release"
    };
    println!("profile: {profile}");
    for r in &ROBOTS {
        let robot = r.robot().with_drive(Drive::ALL);
        // Median of a few runs for NE (fast), one run for LE.
        let mut ne_times = Vec::new();
        let mut nodes = 0;
        for _ in 0..5 {
            let start = Instant::now();
            let mut d = Derivation::new(&robot);
            let ne = d.regressor();
            ne_times.push(start.elapsed().as_secs_f64());
            nodes = d.arena.len();
            std::hint::black_box(ne);
        }
        ne_times.sort_by(f64::total_cmp);
        let start = Instant::now();
        let mut d = Derivation::new(&robot);
        let le = d.lagrange_regressor();
        let le_time = start.elapsed().as_secs_f64();
        std::hint::black_box(le);
        println!(
            "{:9} NE regressor {:3} columns: {:8.2} ms (median of 5, {} nodes); LE regressor: {:8.1} ms ({} nodes)",
            r.name,
            robot.standard_parameters().len(),
            1e3 * ne_times[2],
            nodes,
            1e3 * le_time,
            d.arena.len()
        );
    }
}
