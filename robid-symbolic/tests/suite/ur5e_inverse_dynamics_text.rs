//! The UR5e inverse dynamics program (customised Newton-Euler with base
//! parameters) in its text form, as a reviewed snapshot: any change to the
//! lowering or to the customised Newton-Euler that changes this program fails
//! here until the new text is accepted (`cargo insta review`, or
//! `INSTA_UPDATE=always` and a look at the diff).
use robid_symbolic::Robot;
use robid_symbolic::program::RobotPrograms;

#[test]
fn ur5e_inverse_dynamics_program_text() {
    let text = include_str!("../../../robots/descriptions/ur5e.toml");
    let robot = Robot::from_toml(text, "ur5e.toml").unwrap();
    let programs = RobotPrograms::derive(&robot).unwrap();
    insta::assert_snapshot!(programs[robid_core::ProgramKind::InverseDynamics].to_string());
}
