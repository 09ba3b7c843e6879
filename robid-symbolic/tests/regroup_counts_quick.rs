//! Quick base-parameter counts of the UR5e.
use robid_symbolic::{Derivation, Drive, Robot};

fn count(robot: &Robot) -> (usize, Vec<String>) {
    let mut d = Derivation::new(robot);
    let t = std::time::Instant::now();
    let b = d.base_parameters().unwrap();
    eprintln!("regroup {:?}", t.elapsed());
    (
        b.base.len(),
        b.base
            .iter()
            .map(|p| format!("{} = {}", p.name, d.arena.display(p.expression)))
            .collect(),
    )
}

#[test]
fn ur5e_counts() {
    let text = include_str!("../../robots/descriptions/ur5e.toml");
    let robot = Robot::from_toml(text, "ur5e.toml").unwrap();
    let (n, names) = count(&robot);
    for x in &names {
        eprintln!("{x}");
    }
    assert_eq!(n, 36);
    let ia = Drive {
        ia: true,
        ..Drive::NONE
    };
    assert_eq!(count(&robot.clone().with_drive(ia)).0, 40);
    let f = Drive {
        ia: true,
        fv: true,
        fc: true,
        fo: false,
    };
    assert_eq!(count(&robot.clone().with_drive(f)).0, 52);
    assert_eq!(count(&robot.clone().with_drive(Drive::ALL)).0, 58);
    assert_eq!(count(&robot.clone().with_gravity([0.0, 4.9, -8.5])).0, 38);
}
