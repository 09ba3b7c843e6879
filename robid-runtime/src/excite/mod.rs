//! Exciting trajectories (docs/experiments.md#exciting-trajectories): finite Fourier series
//! optimised for a low condition number (or D-optimality) of the stacked base regressor
//! within the joint limits (Swevers et al. 1997), and the point-based design of Milella
//! (optimal position, velocity and acceleration points, 7th-order polynomial interpolation
//! with continuous jerk, and the regressor extended over intervals around the points).
//!
//! Settings are checked before any work ([`FourierDesign::check`], [`PointDesign::check`]);
//! an error names the setting by its field ([`crate::Error::Setting`], owner
//! `FourierDesign` or `PointDesign`). Limits: harmonics 2 to [`MAX_HARMONICS`], base
//! frequency up to [`MAX_BASE_FREQUENCY`] Hz, at most [`MAX_POINTS`] criterion points or
//! intervals, [`MAX_RESTARTS`] restarts and sweeps, [`MAX_EVALUATIONS`] evaluations per
//! start (the optimisers stop there), weights in (0, [`MAX_WEIGHT`]]. A sampled trajectory
//! has at most [`crate::limits::MAX_SAMPLES`] samples (duration x rate, checked before it
//! is allocated) at a rate of at most [`crate::limits::MAX_SAMPLE_RATE`]. A design whose
//! best criterion is infinite (no trajectory tried excites every parameter) is an error.

mod assess;
mod criterion;
mod design;
mod fourier;
mod limits;
mod pieces;
mod point_design;
mod points;
mod polynomial;

pub use assess::{Assessment, assess};
pub use criterion::{Criterion, Information, floor_weights};
pub use design::{FourierDesign, FourierResult, weights_from_sigma};
pub use fourier::{Fourier, JointSeries};
pub(crate) use limits::check_parameters;
pub use limits::{JointLimits, Margin, check_limits, margins};
pub use pieces::{PieceDesign, Pieces};
pub use point_design::{PointDesign, PointResult};
pub use points::Points;
pub use polynomial::{Knot, Septic};

/// Largest number of harmonics of a Fourier design.
pub const MAX_HARMONICS: usize = 100;
/// Largest base frequency of a Fourier design (Hz).
pub const MAX_BASE_FREQUENCY: f64 = 1e3;
/// Largest number of criterion points (Fourier) or intervals, extended samples and fine-grid
/// samples (points).
pub const MAX_POINTS: usize = 1_000_000;
/// Largest number of random starts or sweeps.
pub const MAX_RESTARTS: usize = 10_000;
/// Largest number of function evaluations per start (or per point and sweep).
pub const MAX_EVALUATIONS: usize = 100_000_000;
/// Largest regressor-row weight (1 / the smallest expected torque noise).
pub const MAX_WEIGHT: f64 = 1e9;
