//! Parameters given in standard-DH link frames (at the distal end of each link, twisted by
//! alpha) are moved into the modified frames the derivation works in: a known answer.

use robid_symbolic::{Derivation, Robot};

/// One revolute joint, standard DH with a = 0.4 and alpha = pi/2, gravity along -y of the
/// base. The centre of mass at c in frame 1 sits at Rz(q) ((a, 0, 0) + Rx(pi/2) c) in the
/// base, so the potential energy is g (sin q (M a + MX) - cos q MZ) and the gravity torque
/// g (cos q (M a + MX) + sin q MZ); MY (along the joint axis once twisted) has no effect.
/// The first moments as if they were in the modified frame (no transfer) would miss M a and
/// swap MZ for MY.
#[test]
fn a_standard_frame_parameter_reaches_the_torque_through_a_and_alpha() {
    let robot = Robot::from_toml(
        "name = \"one\"\nconvention = \"standard\"\ngravity = [0, -9.81, 0]\n\
         [[joints]]\nalpha = \"pi/2\"\na = 0.4\nd = 0\n",
        "one.toml",
    )
    .unwrap();
    let mut d = Derivation::new(&robot);
    let symbols = d.parameter_symbols();
    let tau = d.inverse_dynamics(&symbols);
    let (m, mx, my, mz, q) = (2.0, 0.5, 0.3, 0.7, 0.3f64);
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
    let want = 9.81 * (q.cos() * (m * 0.4 + mx) + q.sin() * mz);
    assert!((got - want).abs() < 1e-12, "{got} vs {want}");
}
