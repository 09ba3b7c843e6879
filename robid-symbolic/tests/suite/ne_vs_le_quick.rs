//! Quick cross-check of Newton-Euler against Lagrange-Euler on the UR5e.
use robid_core::rng::Rng;
use robid_symbolic::{Derivation, Robot};

#[test]
fn ur5e_ne_equals_le() {
    let text = include_str!("../../../robots/descriptions/ur5e.toml");
    let robot = Robot::from_toml(text, "ur5e.toml")
        .unwrap()
        .with_drive(robid_symbolic::Drive::ALL);
    let mut d = Derivation::new(&robot);
    let t0 = std::time::Instant::now();
    let ne = d.regressor();
    eprintln!("NE {:?} nodes {}", t0.elapsed(), d.arena.len());
    let t0 = std::time::Instant::now();
    let le = d.lagrange_regressor();
    eprintln!("LE {:?} nodes {}", t0.elapsed(), d.arena.len());
    let mut rng = Rng::from_state(1);
    let n = robot.dof();
    for _ in 0..5 {
        let mut pairs = Vec::new();
        let names: Vec<String> = (1..=n)
            .flat_map(|j| [format!("q{j}"), format!("qd{j}"), format!("qdd{j}")])
            .collect();
        for name in &names {
            pairs.push((name.as_str(), rng.uniform(-2.0, 2.0)));
        }
        let values = d.arena.values(&pairs);
        let a = d.arena.eval(&ne.entries(), &values).unwrap();
        let b = d.arena.eval(&le.entries(), &values).unwrap();
        for (i, (x, y)) in a.iter().zip(&b).enumerate() {
            assert!(
                (x - y).abs() < 1e-9 * (1.0 + x.abs()),
                "entry {i}: {x} vs {y}"
            );
        }
    }
}
