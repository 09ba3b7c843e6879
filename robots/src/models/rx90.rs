//! `Rx90`: the model compiled from `descriptions/rx90.toml` (its code is in `generated/rx90.rs`).

robid_macros::robot_model!(file = "descriptions/rx90.toml");
