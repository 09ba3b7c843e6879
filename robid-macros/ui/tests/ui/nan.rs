robid_macros::robot_model! {
    name = "arm",
    convention = "modified",
    joints = [revolute(0, f64::NAN, 0, 0)],
}

fn main() {}
