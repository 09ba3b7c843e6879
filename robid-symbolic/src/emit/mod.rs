//! Rust code emission.
