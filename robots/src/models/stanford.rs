//! `Stanford`: the model compiled from `descriptions/stanford.toml` (its code is in `generated/stanford.rs`).

robid_macros::robot_model!(file = "descriptions/stanford.toml");
