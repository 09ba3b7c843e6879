//! A simulation that left its trajectory.

/// A closed-loop simulation failed.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SimulateError {
    /// A closed-loop simulation left the reference trajectory (tracking error or torque
    /// ran away, or a state became non-finite).
    #[error(
        "the simulation diverged at t = {} s (trajectory sample {sample}): {reason}; {fix}",
        crate::Num(*time)
    )]
    Diverged {
        /// Time stamp of the reference sample where it was detected.
        time: f64,
        /// 0-based reference sample.
        sample: usize,
        /// What ran away.
        reason: String,
        /// The likely cause and what to change.
        fix: String,
    },
}
