robid_macros::robot_model! {
    name = "arm",
    convention = "modified",
    jionts = [revolute(0, 0, 0, 0)],
}

fn main() {}
