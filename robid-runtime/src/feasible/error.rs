//! Physically consistent parameters that cannot be found, or a method this build lacks.

/// No feasible parameters can be given.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum FeasibleError {
    /// No physically consistent parameter set satisfies the bounds (or the solver failed).
    #[error("no feasible link parameters: {reason}")]
    NoFeasibleParameters {
        /// What excluded every solution and what to change.
        reason: String,
    },
    /// A method that this build does not include.
    #[error("{what} is not in this build: {fix}")]
    Unavailable {
        /// The method.
        what: String,
        /// How to get it.
        fix: String,
    },
}
