//! `Tx40`: the model compiled from `descriptions/tx40.toml` (its code is in `generated/tx40.rs`).

robid_macros::robot_model!(file = "descriptions/tx40.toml");
