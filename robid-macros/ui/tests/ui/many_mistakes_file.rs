// Every mistake of a description file is reported, not only the first.
robid_macros::robot_model!(file = "descriptions/many_mistakes.toml");

fn main() {}
