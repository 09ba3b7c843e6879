//! The program against the arena's evaluation on the UR5e.

use super::{Group, Program};
use crate::sample::Rng;
use crate::{Derivation, Robot};

const UR5E: &str = include_str!("../../../robots/descriptions/ur5e.toml");

#[test]
fn regressor_program_equals_arena_eval() {
    let robot = Robot::from_toml(UR5E, "ur5e.toml").unwrap();
    let mut d = Derivation::new(&robot);
    let y = d.regressor();
    let entries = y.entries();
    let groups: Vec<Group> = ["q", "qd", "qdd"]
        .iter()
        .map(|g| Group::new(g, (1..=6).map(|j| format!("{g}{j}")).collect()))
        .collect();
    let out = Group::new("y", (0..entries.len()).map(|i| format!("y{i}")).collect());
    let program = Program::build(&d.arena, groups, vec![(out, entries.clone())]).unwrap();
    eprintln!("{}", program.operations());
    let mut rng = Rng::new(7);
    for _ in 0..20 {
        let x: Vec<Vec<f64>> = (0..3)
            .map(|_| (0..6).map(|_| rng.uniform(-3.0, 3.0)).collect())
            .collect();
        let mut pairs = Vec::new();
        let names: Vec<String> = ["q", "qd", "qdd"]
            .iter()
            .flat_map(|g| (1..=6).map(move |j| format!("{g}{j}")))
            .collect();
        for (k, name) in names.iter().enumerate() {
            pairs.push((name.as_str(), x[k / 6][k % 6]));
        }
        let values = d.arena.values(&pairs);
        let expected = d.arena.eval(&entries, &values).unwrap();
        let got = program.eval(&[&x[0], &x[1], &x[2]]).unwrap();
        for (e, g) in expected.iter().zip(&got[0]) {
            assert!((e - g).abs() <= 1e-12 * (1.0 + e.abs()), "{e} vs {g}");
        }
    }
}

/// Guards the operation counts against regressions of the lowering (the
/// figures reached when this was written: inverse dynamics 519 flops with
/// the customised Newton-Euler, base regressor 658 with the link wrenches
/// projected on the joint axes).
#[test]
fn ur5e_programs_counts() {
    let robot = Robot::from_toml(UR5E, "ur5e.toml").unwrap();
    let t = std::time::Instant::now();
    let p = super::RobotPrograms::derive(&robot).unwrap();
    eprintln!("derive {:?}", t.elapsed());
    for (name, prog) in [
        ("id", &p.inverse_dynamics),
        ("yb", &p.base_regressor),
        ("y", &p.standard_regressor),
        ("m", &p.mass_matrix),
        ("g", &p.gravity),
        ("c", &p.coriolis),
        ("k", &p.base_from_standard),
    ] {
        eprintln!(
            "{name}: {} flops {}",
            prog.operations(),
            prog.operations().flops()
        );
    }
    assert!(p.inverse_dynamics.operations().flops() <= 519);
    assert!(p.base_regressor.operations().flops() <= 658);
    assert!(p.mass_matrix.operations().flops() <= 458);
    assert!(p.gravity.operations().flops() <= 78);
}

#[test]
#[ignore]
fn print_ur5e_inverse_dynamics() {
    let robot = Robot::from_toml(UR5E, "ur5e.toml").unwrap();
    let p = super::RobotPrograms::derive(&robot).unwrap();
    eprintln!("{}", p.inverse_dynamics);
}

#[test]
#[ignore]
fn print_ur5e_emitted() {
    let robot = Robot::from_toml(UR5E, "ur5e.toml").unwrap();
    eprintln!("{}", crate::emit::emit_robot(&robot).unwrap());
}

#[test]
#[ignore]
fn derive_all_reference_robots() {
    for name in [
        "ur5e", "puma560", "rx90", "tx40", "lwr4", "panda", "stanford",
    ] {
        let path = format!(
            "{}/../robots/descriptions/{name}.toml",
            env!("CARGO_MANIFEST_DIR")
        );
        let robot = Robot::from_file(std::path::Path::new(&path)).unwrap();
        for drive in [crate::Drive::NONE, crate::Drive::ALL] {
            let r = robot.clone().with_drive(drive);
            let t = std::time::Instant::now();
            let p = super::RobotPrograms::derive(&r);
            let el = t.elapsed();
            match p {
                Ok(p) => eprintln!(
                    "{name} drive={} {:?}: base {} id {} yb {} m {}",
                    drive.ia,
                    el,
                    p.base.len(),
                    p.inverse_dynamics.operations().flops(),
                    p.base_regressor.operations().flops(),
                    p.mass_matrix.operations().flops()
                ),
                Err(e) => eprintln!("{name}: {e}"),
            }
        }
    }
}
