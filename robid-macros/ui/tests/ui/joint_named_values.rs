robid_macros::robot_model! {
    name = "arm",
    convention = "modified",
    joints = [
        revolute(0, 0, 0.1625, 0, gamma = "pi/4", gama = 0.1),
        revolute("pi/2", 0, 0, 0, b = 0.1, b = 0.2),
        revolute(0, 0.4, 0, gamma = 0.3, 0),
    ],
}

robid_macros::robot_model! {
    name = "classic",
    convention = "standard",
    joints = [revolute(0, 0.3, 0, 0), revolute(0, 0.2, 0, 0, gamma = 0.3)],
}

fn main() {}
