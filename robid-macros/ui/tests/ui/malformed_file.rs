robid_macros::robot_model!(file = "descriptions/malformed.toml");

fn main() {}
