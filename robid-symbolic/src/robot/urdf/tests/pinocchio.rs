//! robid's Newton-Euler torques of the chains read from the URDFs equal Pinocchio 4.1.0's
//! (the CSVs of tests/reference/urdf, whose README gives their provenance). The Panda is not
//! compared: Pinocchio moves its finger joints, which robid holds at zero.

use super::*;
use crate::Derivation;

/// The largest difference between robid's torques and Pinocchio's over the file's states.
fn largest_difference(path: &str, csv: &str) -> f64 {
    let chain = Robot::from_urdf(&repository_file(path), path, &ChainSelection::default()).unwrap();
    let mut d = Derivation::new(&chain.robot);
    let symbols = d.parameter_symbols();
    let tau = d.inverse_dynamics(&symbols);
    let names: Vec<String> = d
        .standard_parameters()
        .iter()
        .map(ToString::to_string)
        .collect();
    let parameters: Vec<f64> = chain.links.iter().flat_map(|l| l.inertial).collect();
    let text = repository_file(&format!("tests/reference/urdf/{csv}.csv"));
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let mut worst = 0.0_f64;
    let mut states = 0;
    for line in lines {
        let v: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
        let get = |key: String| v[header.iter().position(|h| *h == key).unwrap()];
        let mut pairs: Vec<(String, f64)> = names
            .iter()
            .cloned()
            .zip(parameters.iter().copied())
            .collect();
        for (j, l) in chain.links.iter().enumerate() {
            for p in ["q", "qd", "qdd"] {
                pairs.push((format!("{p}{}", j + 1), get(format!("{p}:{}", l.joint))));
            }
        }
        let refs: Vec<(&str, f64)> = pairs.iter().map(|(a, b)| (a.as_str(), *b)).collect();
        let values = d.arena.values(&refs);
        let got = d.arena.eval(&tau, &values).unwrap();
        for (j, l) in chain.links.iter().enumerate() {
            worst = worst.max((got[j] - get(format!("tau:{}", l.joint))).abs());
        }
        states += 1;
    }
    assert_eq!(states, 20);
    worst
}

#[test]
fn torques_equal_pinocchios() {
    // The LWR4's chain has no rotation written as a rounded right angle: agreement to
    // rounding. The UR5 and TX40 files write 1.57079632679 (4.9e-12 rad from pi/2), which
    // robid takes as pi/2 (docs/urdf.md#the-angle-rule) and Pinocchio as written: torques
    // of up to 57 N m then differ by a few 1e-10 (observed 3.0e-10 and 2.2e-11).
    assert!(largest_difference(LWR4, "kuka_lwr4") < 1e-12);
    assert!(largest_difference(UR5, "ur5") < 1e-9);
    assert!(largest_difference(TX40, "tx40") < 1e-9);
}
