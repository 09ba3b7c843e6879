//! `Lwr4`: the model compiled from `descriptions/lwr4.toml` (its code is in `generated/lwr4.rs`).

robid_macros::robot_model!(file = "descriptions/lwr4.toml");
