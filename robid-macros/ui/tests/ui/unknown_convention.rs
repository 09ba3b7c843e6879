robid_macros::robot_model! {
    name = "arm",
    convention = "craig",
    joints = [revolute(0, 0, 0, 0)],
}

fn main() {}
