//! Acceptance (issue 6), Franka Panda with its published joint limits (Franka Control
//! Interface specifications, in `robots/descriptions/panda.toml`) and all drive terms (Ia, Fv,
//! Fc, Fo), 30 s at 100 Hz:
//! - the Fourier design (Swevers) respects every limit and starts and ends at rest; its
//!   condition number (columns unscaled, 2-norm) is reported and stays below 150;
//! - the point design (Milella) lowers its criterion, respects every limit and reaches a
//!   condition number of at most 70 (the UR5e's bar; the reduced-budget Fourier design used
//!   here for speed reaches about 72, the full `robid excite` budget about 60);
//! - identification (WLS) on a noisy simulation of the Fourier design predicts another
//!   trajectory within 10 % of the noise floor, and recovers the true base parameters better
//!   than random, non-optimised trajectories of the same family and length (empirical
//!   parameter error over two noise seeds and expected parameter error).
//!
//! Drive values are plausible for the Panda's joints (Gaz et al. 2019 report Coulomb friction
//! of a few tenths of a newton metre); torque noise follows its joint torque sensors.

use crate::simulation_model;

use std::sync::OnceLock;

use robid_symbolic::Drive;
use robid_symbolic::robot::DriveTerm;
use simulation_model::excitation::Setup;

fn setup() -> &'static Setup {
    static SETUP: OnceLock<Setup> = OnceLock::new();
    SETUP.get_or_init(|| {
        let ia = [0.05, 0.05, 0.05, 0.05, 0.02, 0.02, 0.02];
        let fv = [0.1, 0.1, 0.1, 0.1, 0.05, 0.05, 0.05];
        let fc = [0.5, 0.4, 0.35, 0.4, 0.3, 0.2, 0.15];
        let fo = [0.05, -0.1, 0.02, -0.05, 0.01, 0.02, -0.01];
        let value = |t: DriveTerm, j: usize| match t {
            DriveTerm::Ia => ia[j],
            DriveTerm::Fv => fv[j],
            DriveTerm::Fc => fc[j],
            DriveTerm::Fo => fo[j],
        };
        let sigma = [0.2, 0.2, 0.2, 0.2, 0.05, 0.05, 0.05];
        Setup::new("panda", Drive::ALL, value, &sigma, 3)
    })
}

/// Measured: cond 71.9 (3001 samples); the bound is 1.4x that.
#[test]
fn panda_fourier_design_has_condition_at_most_100_within_every_limit_starting_and_ending_at_rest() {
    setup().check_design(Some(100.0));
}

#[test]
fn panda_fourier_design_beats_random_trajectories_in_condition_and_parameter_error() {
    setup().check_identification(&[3, 4]);
}

/// Measured: cond 60.6 (3001 samples); the bound is 1.2x that.
#[test]
fn panda_point_design_lowers_its_criterion_and_has_condition_at_most_70_within_every_limit() {
    let cond = setup().check_point_design(2);
    assert!(cond <= 70.0, "condition number {cond}");
}
