robid_macros::robot_model! {
    name = "arm",
    convention = "modified",
    joints = [revolute(0, 0, 0.1625, 0), revolute("pi/2", 0, 0)],
}

fn main() {}
