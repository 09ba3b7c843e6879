//! `Puma560`: the model compiled from `descriptions/puma560.toml` (its code is in `generated/puma560.rs`).

robid_macros::robot_model!(file = "descriptions/puma560.toml");
