// A value for a symbol that no joint uses names the nearest symbol that is used.
robid_macros::robot_model!(file = "descriptions/unused_symbol.toml");

fn main() {}
