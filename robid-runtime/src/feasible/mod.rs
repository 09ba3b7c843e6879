//! Physically feasible link parameters from identified base parameters
//! (docs/experiments.md#feasible-parameters).
//!
//! Identification gives base parameters beta = K p (K from the regrouping, p the standard
//! parameters) with a covariance. Simulators and Newton-Euler controllers need a complete
//! p: per link a mass m, a centre of mass c and an inertia I_c about it, physically
//! consistent. The fit is convex: p enters linearly and consistency is the linear matrix
//! inequality "pseudo-inertia P = [[0.5 tr(J) I - J, h], [h', m]] is positive
//! (semi)definite" (Wensing, Kim, Slotine, "Linear matrix inequalities for physically
//! consistent inertial parameter identification", IEEE RA-L 3(1), 2018). What the data
//! leave free is settled by a prior (the user's, else solids along the links). Four
//! methods find a p that reproduces beta:
//!
//! - [`solve_interior`] (the command line's default): min ||L^-1 (K p - beta)||^2 plus the
//!   prior's pull by a log-barrier interior-point method in p, every iterate consistent;
//!   global optimum, pure Rust.
//! - [`solve_smooth`]: the same objective over the Cholesky factors of every link's
//!   pseudo-inertia (Rucker and Wensing's parametrisation without its logarithms), every
//!   point consistent, by argmin's trust-region Newton method; the same optimum, slower
//!   where it lies on the boundary of the consistent set.
//! - [`solve_sdp`]: the same fit as a semidefinite program ([`ConicProgram`]) for a
//!   [`ConicSolver`] (the `robid-sdp` crate's Clarabel, which needs OpenBLAS);
//!   [`consistent_least_squares`] applies the same constraints
//!   directly to the least-squares fit on data.
//! - [`solve_anneal`]: the method of Gaz, Flacco, De Luca ("Extracting feasible robot
//!   parameters from dynamic coefficients using nonlinear optimization methods", ICRA 2016):
//!   simulated annealing with random restarts, each followed by Nelder-Mead, over bounded
//!   masses, centres of mass and inertias, with a total-mass range; [`solve_two_step`] is
//!   their two-step extraction (gravity parameters from the [`GravityCoefficients`] first,
//!   then the rest with those held), with equalities ([`Equality`]) and their step penalty
//!   on the total mass.
//!
//! Bounds come from TOML ([`Bounds`]); the result ([`Solution`]) is written as TOML or as
//! a complete URDF robot ([`to_toml`], [`to_urdf`]).

mod bounds;
mod centre;
mod cholesky;
mod conic;
mod error;
#[cfg(test)]
mod fixture;
mod gravity;
mod inertial;
mod interior;
mod layout;
mod objective;
mod output;
mod prior;
mod problem;
mod sdp;
mod search;
mod smooth;
mod solution;

pub use bounds::{Bounds, DEFAULT_MARGIN, LinkBounds, MIN_LINK_MASS, TENSOR_ELEMENTS};
pub use centre::centre;
pub use conic::{Cone, ConicFailure, ConicProgram, ConicSolver};
pub use error::FeasibleError;
pub use gravity::GravityCoefficients;
pub use inertial::{
    LinkInertial, inertia_at_origin, pseudo_inertia, pseudo_inertia_min_eigenvalue,
};
pub use interior::solve_interior;
pub use layout::{Drive, Layout};
pub use output::{STANDARD_GRAVITY, UrdfJoint, to_toml, to_urdf};
pub use prior::{DEFAULT_PRIOR_WEIGHT, LinkShape, MAX_DENSITY, Prior, Unsized};
pub use problem::Problem;
pub use sdp::{SdpOptions, consistent_least_squares, solve_sdp};
pub use search::{
    AnnealOptions, Equality, MAX_EQUALITY_FACTORS, Quantity, TwoStep, Variable, solve_anneal,
    solve_gravity_step, solve_two_step,
};
pub use smooth::{SmoothOptions, solve_smooth};
pub use solution::{Method, SHORT_SHARE, Solution};
