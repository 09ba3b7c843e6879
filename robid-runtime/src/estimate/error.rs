//! What the data cannot give an estimator: unexcited parameters, outliers, non-finite rows.

/// The observation matrix cannot be solved as given.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum EstimateError {
    /// The data do not excite every parameter: the observation matrix is rank deficient.
    #[error("rank-deficient data: rank {rank} of {columns} parameters; not excited: {}; use a richer trajectory or remove these parameters", unexcited.join(", "))]
    RankDeficient {
        /// Numerical rank found.
        rank: usize,
        /// Number of parameters (columns).
        columns: usize,
        /// The parameters that make up the unexcited directions, most affected first.
        unexcited: Vec<String>,
    },
    /// Per-axis identification: some parameters are determined by no single joint's equation.
    #[error(
        "per-axis identification: no joint's equation alone determines {} (they are separable only across joints, or not excited); use ols or wls, or a trajectory that separates them within one axis",
        parameters.join(", ")
    )]
    NotPerAxis {
        /// The parameters no axis determines.
        parameters: Vec<String>,
    },
    /// Per-axis or link-by-link identification, which solve joint by joint: a joint has
    /// fewer equations than the parameters it is solved for while another joint has more,
    /// so its equations were removed, not the record too short (in the pipeline by
    /// `processing.rest_velocity`, where the joint is at rest or slower than the threshold).
    #[error("{} identification: {}", method.name(), lacks_equations(*method, *joint, *found, *required, *most))]
    AxisLacksEquations {
        /// The method ([`Estimator::PerAxis`](crate::estimate::Estimator::PerAxis) or
        /// [`Estimator::LinkByLink`](crate::estimate::Estimator::LinkByLink)).
        method: crate::estimate::Estimator,
        /// The joint (1-based).
        joint: usize,
        /// Its equations.
        found: usize,
        /// The parameters it is solved for (per axis: of its own equation, which needs
        /// more equations than them; link by link: of its step, at least as many).
        required: usize,
        /// The most equations any joint has.
        most: usize,
    },
    /// One or a few equations dominate the column of a parameter the data do not otherwise
    /// determine: an outlier in the data, not a poor trajectory.
    #[error(
        "{location}: an outlier: {:.1} % of column `{parameter}` comes from the equations around this row, which hides the rest of the record; repair or remove the row (check its velocities and accelerations)",
        100.0 * share
    )]
    Outlier {
        /// Where the largest equation comes from (file:line when known).
        location: String,
        /// The parameter whose column it dominates.
        parameter: String,
        /// The share of the column's squared norm held by the largest equations.
        share: f64,
    },
    /// The observation matrix (or the torque vector) holds NaN or an infinite value.
    #[error(
        "the observation matrix is {value} at {location}, joint {joint}, column `{parameter}`: the regressor overflowed there; check that row's positions, velocities and accelerations (and the extra column's definition)"
    )]
    NonFiniteObservation {
        /// Where the equation comes from: `file:line` when known, else the sample.
        location: String,
        /// 0-based sample index in the data set (after any resampling), when known.
        sample: Option<usize>,
        /// 1-based joint (equation row of the regressor).
        joint: usize,
        /// The parameter (column), or `torque` for the measurement.
        parameter: String,
        /// The value found.
        value: f64,
    },
}

/// How `found` equations fall short of `required` parameters: fewer, or as many (which
/// fit any data exactly, leaving no residual for the standard deviations), before "the 3".
pub(crate) fn short_of(found: usize, required: usize) -> &'static str {
    if found < required {
        "fewer than"
    } else {
        "only as many as"
    }
}

/// What a joint's equations are solved for by `method` (per axis or link by link), after
/// "fewer than the 3".
pub(crate) fn own_parameters(method: crate::estimate::Estimator) -> &'static str {
    match method {
        crate::estimate::Estimator::LinkByLink => "parameters its step estimates",
        _ => "parameters of its own equation",
    }
}

/// How `method` (per axis or link by link) uses each joint's equations, after
/// "per-axis identification ".
pub(crate) fn solves_alone(method: crate::estimate::Estimator) -> &'static str {
    match method {
        crate::estimate::Estimator::LinkByLink => {
            "estimates each link's parameters from its own joint's equations"
        }
        _ => "solves each joint's equations on their own",
    }
}

/// The message of [`EstimateError::AxisLacksEquations`], after "per-axis identification: ".
fn lacks_equations(
    method: crate::estimate::Estimator,
    joint: usize,
    found: usize,
    required: usize,
    most: usize,
) -> String {
    let what = if found == 0 {
        format!(
            "joint {joint} has no equations, while another joint has {most}: all of them were \
             removed, as processing.rest_velocity removes a joint's equations where its \
             |velocity| is below it (the joint is at rest in the whole record, or slower than \
             that)"
        )
    } else {
        format!(
            "joint {joint} has {found} equations, {} the {required} {}, while another \
             joint has {most}: the others were removed, as processing.rest_velocity removes a \
             joint's equations where its |velocity| is below it",
            short_of(found, required),
            own_parameters(method)
        )
    };
    format!(
        "{what}; it {}: move joint {joint} in the trajectory, or lower \
         processing.rest_velocity for it",
        solves_alone(method)
    )
}
