// A robot name that is a Rust keyword cannot name the generated type.
robid_macros::robot_model! {
    name = "self",
    convention = "modified",
    joints = [revolute(0, 0.3, 0, 0)],
}

fn main() {}
