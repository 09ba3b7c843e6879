//! The integration tests of robid-symbolic, one module per subject, linked
//! into a single test binary (one link of the crate instead of one per file).

mod common;

mod bounds_extremes;
mod deep_expressions;
mod description_errors;
mod emit_c;
mod fuzz_descriptions;
mod ne_vs_le_quick;
mod regroup;
mod regroup_random;
mod regroup_symbolic;
mod simplify_keeps_value;
mod standard_frames;
mod ur5e_inverse_dynamics_text;
mod zomaya_stanford;
