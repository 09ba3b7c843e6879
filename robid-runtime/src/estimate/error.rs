//! What the data cannot give an estimator: unexcited parameters, outliers, non-finite rows.

/// The observation matrix cannot be solved as given.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum EstimateError {
    /// The data do not excite every parameter: the observation matrix is rank deficient.
    #[error("rank-deficient data: rank {rank} of {columns} parameters; {}; use a richer trajectory or remove these parameters", not_excited(*rank, *columns, unexcited))]
    RankDeficient {
        /// Numerical rank found.
        rank: usize,
        /// Number of parameters (columns).
        columns: usize,
        /// The parameters that make up the unexcited directions, most affected first.
        unexcited: Vec<String>,
    },
    /// Rank-deficient data in which some joints do not move at all (velocity 0 at every
    /// equation, to the rounding of their positions): the cause named, where "use a
    /// richer trajectory" did not say which joint stood still.
    #[error(
        "rank-deficient data: rank {rank} of {columns} parameters; {}; {} not move in the equations used (velocity 0 at every sample, to the rounding of the positions): use a record in which {} move{}, or remove the parameters that only {} motion determines",
        not_excited(*rank, *columns, unexcited),
        still_joints(joints),
        if joints.len() == 1 { "it" } else { "they" },
        if joints.len() == 1 { "s" } else { "" },
        if joints.len() == 1 { "its" } else { "their" },
    )]
    StillJoints {
        /// Numerical rank found.
        rank: usize,
        /// Number of parameters (columns).
        columns: usize,
        /// The parameters that make up the unexcited directions, most affected first.
        unexcited: Vec<String>,
        /// The joints (1-based) that do not move.
        joints: Vec<usize>,
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

/// The unexcited directions of a rank-`rank` matrix of `columns` parameters, said by the
/// parameters that make them up (`unexcited`, most affected first): "not excited: a, b"
/// when each direction is one parameter, else "3 combinations of 40 parameters not
/// excited (a, b, ..., and 30 more)": the whole list was given as "not excited" (61 names
/// for a rank of 23), though any 23 of them could be determined.
pub(crate) fn not_excited(rank: usize, columns: usize, unexcited: &[String]) -> String {
    undetermined(rank, columns, unexcited, "not excited")
}

/// [`not_excited`] with the state of the directions said by `state` ("not excited" by
/// the data, or "not determined" where no motion could excite them).
pub(crate) fn undetermined(
    rank: usize,
    columns: usize,
    unexcited: &[String],
    state: &str,
) -> String {
    const SHOWN: usize = 10;
    let directions = columns.saturating_sub(rank);
    if unexcited.len() <= directions.max(1) {
        return format!("{state}: {}", unexcited.join(", "));
    }
    let mut names = unexcited[..unexcited.len().min(SHOWN)].join(", ");
    if unexcited.len() > SHOWN {
        names += &format!(", and {} more", unexcited.len() - SHOWN);
    }
    format!(
        "{} of {} parameters {state} ({names})",
        crate::Count(directions, "combination"),
        unexcited.len()
    )
}

/// "joint 2 does" or "joints 1 and 3 do".
fn still_joints(joints: &[usize]) -> String {
    match joints {
        [one] => format!("joint {one} does"),
        [rest @ .., last] => format!(
            "joints {} and {last} do",
            rest.iter()
                .map(usize::to_string)
                .collect::<Vec<_>>()
                .join(", ")
        ),
        [] => "no joint does".to_owned(),
    }
}

#[cfg(test)]
mod tests {
    use super::{not_excited, undetermined};

    /// One parameter per unexcited direction is listed as not excited; more, as the count
    /// of combinations among them (all 61 names were "not excited" for a rank of 23).
    #[test]
    fn unexcited_directions_are_counted_when_they_mix_parameters() {
        let names = |n: usize| (1..=n).map(|i| format!("p{i}")).collect::<Vec<_>>();
        assert_eq!(not_excited(4, 6, &names(2)), "not excited: p1, p2");
        assert_eq!(not_excited(5, 6, &names(1)), "not excited: p1");
        assert_eq!(
            not_excited(4, 6, &names(3)),
            "2 combinations of 3 parameters not excited (p1, p2, p3)"
        );
        let e = not_excited(23, 61, &names(61));
        assert!(
            e.starts_with("38 combinations of 61 parameters not excited (p1, p2,")
                && e.ends_with("p10, and 51 more)"),
            "{e}"
        );
        assert_eq!(
            not_excited(9, 10, &names(10)),
            "1 combination of 10 parameters not excited (p1, p2, p3, p4, p5, p6, p7, p8, p9, p10)"
        );
        assert_eq!(
            undetermined(3, 10, &names(7), "not determined"),
            "not determined: p1, p2, p3, p4, p5, p6, p7"
        );
    }
}
