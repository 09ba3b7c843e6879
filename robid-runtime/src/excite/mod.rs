//! Exciting trajectories (DESIGN 7): finite Fourier series optimised for a low condition
//! number (or D-optimality) of the stacked base regressor within the joint limits
//! (Swevers et al. 1997), and the point-based design of Milella (optimal position, velocity
//! and acceleration points, 7th-order polynomial interpolation with continuous jerk, and the
//! regressor extended over intervals around the points).

mod assess;
mod criterion;
mod design;
mod fourier;
mod limits;
mod point_design;
mod points;
mod polynomial;
mod progress;

pub use assess::{Assessment, assess};
pub use criterion::{Criterion, Information};
pub use design::{FourierDesign, FourierResult};
pub use fourier::{Fourier, JointSeries};
pub use limits::{JointLimits, Margin, check_limits, margins};
pub use point_design::{PointDesign, PointResult};
pub use points::Points;
pub use polynomial::{Knot, Septic};
