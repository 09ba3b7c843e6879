// The chain of a URDF: a tip that names no link, `tip` with an inline description, and a
// base and a tip with no movable joint between them (the pair is at fault: the error spans
// both and names both links).
robid_macros::robot_model!(file = "descriptions/planar2.urdf", tip = "forearm");

robid_macros::robot_model! {
    name = "arm",
    convention = "modified",
    tip = "fore",
    joints = [revolute(0, 0, 0, 0)],
}

mod pair {
    robid_macros::robot_model!(file = "descriptions/planar2.urdf", base = "fore", tip = "fore");
}

// the same, the tip written first
mod reversed {
    robid_macros::robot_model!(file = "descriptions/planar2.urdf", tip = "upper", base = "upper");
}

fn main() {}
