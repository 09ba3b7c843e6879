//! The workspace-level integration tests, one module per subject, in one test binary (one
//! link instead of one per file: the suite builds and starts much faster).
//!
//! Run one subject with `cargo test -p tests --test suite MODULE::`, e.g.
//! `cargo test -p tests --test suite emitted_vs_rnea::`.

mod bad_input_csv;
mod bad_input_hang;
mod bad_input_load;
mod bad_input_messages;
mod bad_input_results;
mod bad_input_validation;
mod bad_input_warnings;
mod cutoff_auto;
mod emitted_vs_rnea;
mod excitation_panda;
mod excitation_pieces;
mod excitation_torque_limits;
mod excitation_ur5e;
mod feasible_bad_input;
mod feasible_sdp_real_data;
mod feasible_sdp_tx40_report;
mod feasible_simulated;
mod flexible_ur5e;
mod fuzz_identify;
mod gaz_lwr;
mod general_frames;
mod identify_bad_input;
mod identify_energy;
mod identify_gaps;
mod identify_known;
mod identify_lwr4;
mod identify_per_axis;
mod identify_tx40;
mod identify_ur5e_simulated;
mod mass_matrix_spd;
mod model_equation;
mod ne_equals_le;
mod payload_identify;
mod positions_beyond_limits;
mod power_balance;
mod reference_files;
mod rnea_agrees;
mod simulation_model;
mod standard_vs_modified;
mod urdf_models;
mod urdf_reference;
mod wrench_link;
mod zomaya_link_by_link;
