//! The `robid` command line end to end, one module per subject, in one test binary.
//!
//! Run one subject with `cargo test -p robots --test cli MODULE::`, e.g.
//! `cargo test -p robots --test cli stdout::`.

mod bad_input;
mod common;
mod config;
mod drive;
mod feasible;
mod files;
mod flexible;
mod friction;
mod gaps;
mod message_defects;
mod not_physical;
mod one_joint;
mod payload;
mod reference;
mod schedule;
mod sequence;
mod static_samples;
mod stdout;
mod subcommands;
mod urdf;
