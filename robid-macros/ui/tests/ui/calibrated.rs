// `calibrated`: a flag, not a string; with `file` it belongs in the file; and without it a
// twist a few microradians off a right angle is refused as the right angle mistyped.
robid_macros::robot_model! {
    name = "arm",
    convention = "modified",
    calibrated = "yes",
    joints = [revolute(0, 0, 0, 0)],
}

mod with_file {
    robid_macros::robot_model!(file = "descriptions/planar2.urdf", calibrated = true);
}

mod typed {
    robid_macros::robot_model! {
        name = "typed",
        convention = "modified",
        joints = [revolute(0, 0, 0, 0), revolute(1.5707995, 0, 0, 0)],
    }
}

fn main() {}
