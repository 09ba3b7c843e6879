//! Every reference description and parameter file loads, has joint limits, and names only
//! parameters the robot has.

use robid_symbolic::robot::{Inertial, ParameterKind};
use robid_symbolic::{Drive, JointKind};
use tests::reference::ROBOTS;

#[test]
fn descriptions_load_with_limits_on_every_joint() {
    let expected = [
        ("ur5e", 6),
        ("puma560", 6),
        ("rx90", 6),
        ("tx40", 6),
        ("lwr4", 7),
        ("panda", 7),
        ("stanford", 3),
    ];
    assert_eq!(ROBOTS.len(), expected.len());
    for (r, (name, dof)) in ROBOTS.iter().zip(expected) {
        assert_eq!(r.name, name);
        let robot = r.robot().with_drive(Drive::NONE);
        assert_eq!(robot.name(), name, "name inside {name}.toml");
        assert_eq!(robot.dof(), dof, "{name}");
        for (j, joint) in robot.joints().iter().enumerate() {
            let [lo, hi] = joint
                .limits
                .position
                .unwrap_or_else(|| panic!("{name} joint {}: no position limits", j + 1));
            assert!(lo < hi);
        }
    }
}

#[test]
fn stanford_arm_covers_a_prismatic_joint() {
    let robot = tests::reference::by_name("stanford")
        .robot()
        .with_drive(Drive::NONE);
    let kinds: Vec<JointKind> = robot.joints().iter().map(|j| j.kind).collect();
    assert_eq!(
        kinds,
        [
            JointKind::Revolute,
            JointKind::Revolute,
            JointKind::Prismatic
        ]
    );
}

#[test]
fn parameter_files_name_only_standard_parameters_with_sane_masses() {
    for r in &ROBOTS {
        let robot = r.robot().with_drive(Drive::ALL);
        let names: Vec<String> = robot
            .standard_parameters()
            .into_iter()
            .map(|p| p.to_string())
            .collect();
        let file = r.parameter_file();
        assert!(
            file.entries().next().is_some(),
            "{}: empty [standard] table",
            r.name
        );
        // names, physical consistency (and, by the TOML reader, no name twice)
        file.prior(&names).unwrap_or_else(|e| panic!("{e}"));
        let values = r.parameter_values(&robot);
        let total_mass: f64 = robot
            .standard_parameters()
            .iter()
            .zip(&values)
            .filter(|(p, _)| p.kind == ParameterKind::Inertial(Inertial::M))
            .map(|(_, v)| {
                assert!(*v >= 0.0, "{}: negative mass", r.name);
                *v
            })
            .sum();
        assert!(
            (1.0..200.0).contains(&total_mass),
            "{}: total mass {total_mass} kg",
            r.name
        );
    }
}
