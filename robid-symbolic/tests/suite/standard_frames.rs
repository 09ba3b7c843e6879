//! Parameters given in standard-DH link frames (at the distal end of each link, twisted by
//! alpha) are moved into the modified frames the derivation works in: a known answer.

use robid_symbolic::{Derivation, Robot};

/// One revolute joint, standard DH with a = 0.4, gravity along -y of the base. The centre
/// of mass at c in frame 1 sits at Rz(q) ((a, 0, 0) + Rx(alpha) c) in the base. With
/// alpha = pi/2 the potential energy is g (sin q (M a + MX) - cos q MZ), the gravity torque
/// g (cos q (M a + MX) + sin q MZ), and MY (along the joint axis once twisted) has no
/// effect; with alpha = 0 the torque is g (cos q (M a + MX) - sin q MY). The first moments
/// taken as if in the modified frame (no transfer) would miss M a and mix up MY and MZ.
#[test]
fn a_standard_frame_parameter_reaches_the_torque_through_a_and_alpha() {
    let (m, mx, my, mz, q) = (2.0, 0.5, 0.3, 0.7, 0.3f64);
    let twisted = 9.81 * (q.cos() * (m * 0.4 + mx) + q.sin() * mz);
    let straight = 9.81 * (q.cos() * (m * 0.4 + mx) - q.sin() * my);
    for (alpha, want) in [("pi/2", twisted), ("0", straight)] {
        gravity_torque(alpha, [m, mx, my, mz, q], want);
    }
}

fn gravity_torque(alpha: &str, [m, mx, my, mz, q]: [f64; 5], want: f64) {
    let robot = Robot::from_toml(
        &format!(
            "name = \"one\"\nconvention = \"standard\"\ngravity = [0, -9.81, 0]\n\
             [[joints]]\nalpha = \"{alpha}\"\na = 0.4\nd = 0\n"
        ),
        "one.toml",
    )
    .unwrap();
    let mut d = Derivation::new(&robot);
    let symbols = d.parameter_symbols();
    let tau = d.inverse_dynamics(&symbols);
    let values = d.arena.values(&[
        ("q1", q),
        ("qd1", 0.0),
        ("qdd1", 0.0),
        ("M1", m),
        ("MX1", mx),
        ("MY1", my),
        ("MZ1", mz),
        ("XX1", 0.0),
        ("XY1", 0.0),
        ("XZ1", 0.0),
        ("YY1", 0.0),
        ("YZ1", 0.0),
        ("ZZ1", 0.0),
    ]);
    let got = d.arena.eval(&tau, &values).unwrap()[0];
    assert!((got - want).abs() < 1e-12, "alpha {alpha}: {got} vs {want}");
}
