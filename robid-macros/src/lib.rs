//! `robot_model!`: emits straight-line Rust for a robot description.
