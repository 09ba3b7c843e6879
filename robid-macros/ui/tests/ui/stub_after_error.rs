// After an error, `robot_model!` emits a placeholder of the robot's type: the code that
// uses it reports nothing more, and its functions keep their argument and result lengths.
robid_macros::robot_model! {
    name = "arm",
    convention = "modified",
    joints = [revolute(0, f64::NAN, 0, 0)],
}

fn main() {
    let arm = Arm::default();
    let tau: [f64; 1] = arm.inverse_dynamics(&[0.0; 1], &[0.0; 1], &[0.0; 1], &[0.0; 3]);
    let _ = (tau, Arm::DOF, Arm::NAME);
}
