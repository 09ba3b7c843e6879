// A bad convention and a bad joint are both reported, and uses of the
// placeholder type add no errors of their own.
robid_macros::robot_model! {
    name = "arm",
    convention = "sideways",
    joints = [revolute(0, 0, 0, 0), rotary(0, 0, 0, 0)],
}

fn main() {
    let q = [0.0_f64; 2];
    let _tau: [f64; 2] = Arm.inverse_dynamics(&q, &q, &q, &[0.0; 3]);
}
