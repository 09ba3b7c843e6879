// The chain of a URDF: a tip that names no link, and `tip` with an inline description.
robid_macros::robot_model!(file = "descriptions/planar2.urdf", tip = "forearm");

robid_macros::robot_model! {
    name = "arm",
    convention = "modified",
    tip = "fore",
    joints = [revolute(0, 0, 0, 0)],
}

fn main() {}
