robid_macros::robot_model! {
    name = "arm",
    convention = "modified",
    base = pose(xyz = [0, 0], rpy = [0, 0, 0], rpy = [0, 0, 0], scale = 2),
    joints = [revolute(0, 0, 0.1625, 0)],
}

robid_macros::robot_model! {
    name = "linked",
    convention = "modified",
    base = "world",
    joints = [revolute(0, 0, 0.1625, 0)],
}

fn main() {}
