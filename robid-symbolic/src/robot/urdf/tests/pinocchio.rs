//! robid's Newton-Euler torques of the chains read from the URDFs equal Pinocchio 4.1.0's
//! (the CSVs of tests/reference/urdf, whose README gives their provenance). The Panda is not
//! compared: Pinocchio moves its finger joints, which robid holds at zero.

use super::*;

/// The largest difference between robid's torques and Pinocchio's over the file's states.
fn largest_difference(path: &str, csv: &str) -> f64 {
    let chain = Robot::from_urdf(&repository_file(path), path, &ChainSelection::default()).unwrap();
    let mut torques = own_inertials_torques(&chain);
    let text = repository_file(&format!("tests/reference/urdf/{csv}.csv"));
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let mut worst = 0.0_f64;
    let mut states = 0;
    for line in lines {
        let v: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
        let get = |key: String| v[header.iter().position(|h| *h == key).unwrap()];
        let state = |p: &str| -> Vec<f64> {
            chain
                .links
                .iter()
                .map(|l| get(format!("{p}:{}", l.joint)))
                .collect()
        };
        let got = torques(&state("q"), &state("qd"), &state("qdd"));
        for (j, l) in chain.links.iter().enumerate() {
            worst = worst.max((got[j] - get(format!("tau:{}", l.joint))).abs());
        }
        states += 1;
    }
    assert_eq!(states, 20);
    worst
}

/// The chains compared, with the CSV name of their Pinocchio torques.
const ROBOTS: [(&str, &str); 6] = [
    (LWR4, "kuka_lwr4"),
    (UR5, "ur5"),
    (TX40, "tx40"),
    (KINOVA, "kinova"),
    (XARM7, "xarm7"),
    (SO101, "so101"),
];

#[test]
fn torques_equal_pinocchios() {
    // Pinocchio's model of each file as robid reads it (its right angles printed to a few
    // decimals written exactly, `<robot>_right_angles.csv`): equal to rounding (measured
    // at most 2.8e-14 N m)
    for (path, csv) in ROBOTS {
        let d = largest_difference(path, &format!("{csv}_right_angles"));
        assert!(d < 1e-12, "{csv}: {d:e} N m");
    }
    // the files as written: Pinocchio turns by the printed values, robid by the right
    // angles (docs/urdf.md#the-angle-rule). The LWR4 prints none; the UR5, TX40 and Kinova
    // write 1.57079632679 (4.9e-12 rad from pi/2): a few 1e-10 N m (measured 3.0e-10,
    // 2.2e-11, 3.1e-11); the xArm7's 1.5708 (3.7e-6 rad) and the SO-101's 3.14159
    // (2.7e-6 rad) of torques up to tens of N m and about 1 N m: 1.1e-4 and 3.0e-6 N m
    for ((path, csv), most) in ROBOTS
        .into_iter()
        .zip([1e-12, 1e-9, 1e-9, 1e-9, 1e-3, 1e-4])
    {
        let d = largest_difference(path, csv);
        assert!(d < most, "{csv}: {d:e} N m");
    }
}
