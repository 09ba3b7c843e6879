//! `Panda`: the model compiled from `descriptions/panda.toml` (its code is in `generated/panda.rs`).

robid_macros::robot_model!(file = "descriptions/panda.toml");
