//! `Ur5e`: the model compiled from `descriptions/ur5e.toml` (its code is in `generated/ur5e.rs`).

robid_macros::robot_model!(file = "descriptions/ur5e.toml");
