//! Times the derivation steps for a robot description (default: the Panda
//! with every drive term), in whatever profile it is built:
//! `cargo run --release -p robid-symbolic --example derive_timing [FILE]`.

use robid_symbolic::{Derivation, Drive, Robot};
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let robot = match std::env::args().nth(1) {
        Some(path) => Robot::from_file(path.as_ref())?,
        None => Robot::from_toml(
            include_str!("../../robots/descriptions/panda.toml"),
            "panda.toml",
        )?,
    }
    .with_drive(Drive::ALL);
    let runs = 5;
    let mut best = [f64::INFINITY; 3];
    for _ in 0..runs {
        let t = Instant::now();
        let mut d = Derivation::new(&robot);
        let kinematics = t.elapsed().as_secs_f64();
        let t = Instant::now();
        let _ = d.regressor();
        let regressor = t.elapsed().as_secs_f64();
        let mut d = Derivation::new(&robot);
        let t = Instant::now();
        let b = d.base_parameters()?;
        let regroup = t.elapsed().as_secs_f64();
        assert!(!b.base.is_empty());
        for (slot, v) in best.iter_mut().zip([kinematics, regressor, regroup]) {
            *slot = slot.min(v);
        }
    }
    let profile = if cfg!(debug_assertions) {
        "dev"
    } else {
        "release"
    };
    println!(
        "{} ({} DOF, all drive terms), {profile} profile, best of {runs}:",
        robot.name(),
        robot.dof()
    );
    println!("  kinematics               {:8.2} ms", best[0] * 1e3);
    println!("  Newton-Euler regressor   {:8.2} ms", best[1] * 1e3);
    println!(
        "  kinematics + regressor   {:8.2} ms",
        (best[0] + best[1]) * 1e3
    );
    println!("  base parameters (regroup){:8.2} ms", best[2] * 1e3);
    Ok(())
}
