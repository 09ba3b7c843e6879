// An expression nested deeper than 64 levels is an error, not a stack overflow.
robid_macros::robot_model! {
    name = "arm",
    convention = "modified",
    joints = [revolute("(((((((((((((((((((((((((((((((((((((((((((((((((((((((((((((((((0.5)))))))))))))))))))))))))))))))))))))))))))))))))))))))))))))))))", 0.3, 0, 0)],
}

fn main() {}
