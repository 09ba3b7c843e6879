robid_macros::robot_model!(file = "descriptions/missing.toml");

fn main() {}
