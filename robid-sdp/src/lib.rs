//! The solver of robid's semidefinite feasible-parameter method
//! (`robid_runtime::feasible::solve_sdp`): Clarabel's interior-point method, whose PSD cones
//! need BLAS and LAPACK from the system OpenBLAS, which a machine with only the Rust
//! toolchain does not have. Built with the `clarabel` feature (`robid`'s `sdp` feature turns
//! it on), [`solver`] gives it; built without, [`solver`] says how to get it.
//!
//! ```
//! use robid_runtime::feasible::{Bounds, Problem, SdpOptions, solve_sdp};
//! # fn main() -> Result<(), robid_runtime::Error> {
//! # let problem = Problem::new(
//! #     ["XX1", "XY1", "XZ1", "YY1", "YZ1", "ZZ1", "MX1", "MY1", "MZ1", "M1"]
//! #         .map(String::from).to_vec(),
//! #     vec!["M1".into()],
//! #     nalgebra::DMatrix::from_fn(1, 10, |_, c| if c == 9 { 1.0 } else { 0.0 }),
//! # )?;
//! match robid_sdp::solver() {
//!     Ok(solver) => {
//!         let solution = solve_sdp(&problem, &Bounds::wide(1), &SdpOptions::default(), solver)?;
//!         assert!(solution.chi2.is_finite());
//!     }
//!     // without the feature: how to enable it
//!     Err(e) => assert!(e.to_string().contains("--features sdp")),
//! }
//! # Ok(()) }
//! ```

#[cfg(feature = "clarabel")]
mod clarabel;

#[cfg(feature = "clarabel")]
pub use clarabel::Clarabel;

use robid_runtime::feasible::ConicSolver;

/// The conic solver of the semidefinite method: `Clarabel` where this crate is built with
/// its `clarabel` feature.
///
/// # Errors
/// Built without the feature: [`FeasibleError::Unavailable`](robid_runtime::FeasibleError)
/// naming how to get it and the methods that need nothing more.
pub fn solver() -> robid_runtime::Result<&'static dyn ConicSolver> {
    #[cfg(feature = "clarabel")]
    return Ok(&Clarabel);
    #[cfg(not(feature = "clarabel"))]
    Err(robid_runtime::Error::Feasible(
        robid_runtime::FeasibleError::Unavailable {
            what: "the semidefinite (sdp) method".to_owned(),
            fix: "install OpenBLAS (`bash .ci/install-deps.sh`) and build with `--features sdp`, or use `--method interior-point` (the default, the same optimum), `cholesky` or `anneal`".to_owned(),
        },
    ))
}

#[cfg(test)]
mod tests {
    /// Without its feature the method says how to get it instead of failing silently (the
    /// test follows this crate's feature, whichever crate turned it on).
    #[cfg(not(feature = "clarabel"))]
    #[test]
    fn without_the_feature_it_says_how_to_enable_it() {
        match super::solver() {
            Err(
                e @ robid_runtime::Error::Feasible(robid_runtime::FeasibleError::Unavailable {
                    ..
                }),
            ) => assert!(e.to_string().contains("--features sdp"), "{e}"),
            other => panic!("expected Error::Unavailable, got {other:?}"),
        }
    }
}
