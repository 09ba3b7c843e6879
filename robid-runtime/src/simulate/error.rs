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
    /// The plant is stiffer than the explicit integration can follow: at a state of the
    /// run its fastest rate needs each substep split into more Runge-Kutta steps than the
    /// most a substep takes (1,000), beyond which the classical Runge-Kutta method is
    /// unstable and the run diverged after minutes, with advice about the bandwidth. The
    /// run stops at once, naming what makes the plant this fast (a large viscous friction
    /// on a light link, the transmission damping of a flexible joint, ...) and its fix;
    /// nothing is written.
    #[error(
        "the simulation cannot follow the plant at t = {} s (trajectory sample {sample}): \
         its fastest rate, {} 1/s, needs each substep of {} s split into {} Runge-Kutta \
         steps, more than the limit of {limit} beyond which the explicit integration is \
         unstable; nothing was written; {cause}",
        crate::Num(*time),
        crate::Num::rounded(*rate, 3),
        crate::Num::rounded(*step, 3),
        crate::Num(*needed)
    )]
    TooStiff {
        /// Time stamp of the reference sample whose interval it was reached in, s.
        time: f64,
        /// 0-based reference sample.
        sample: usize,
        /// The bound on the plant's fastest rate at that state, 1/s.
        rate: f64,
        /// The substep, s.
        step: f64,
        /// The Runge-Kutta steps the substep needs (`step * rate / 2.5`, rounded up).
        needed: f64,
        /// The most Runge-Kutta steps a substep is split into.
        limit: usize,
        /// What makes the plant this fast, with its value, and what to change.
        cause: String,
    },
    /// The mass matrix is singular because joints move no mass or inertia (a zero diagonal
    /// entry of M(q)): the parameters leave the bodies they move empty, as a URDF's links
    /// without `<inertial>` are, and no torque accelerates them. Not a question of
    /// physical consistency.
    #[error("{}", no_inertia(what, joints, *dof))]
    NoInertia {
        /// The mass matrix: of which model, at which state.
        what: String,
        /// The joints that move nothing, numbered from 1.
        joints: Vec<usize>,
        /// The model's number of joints.
        dof: usize,
    },
    /// The mass matrix is singular although positive semidefinite to its rounding, as
    /// physically consistent parameters make it (only inconsistent ones make it
    /// indefinite): joints whose motions coincide (two joints on one axis with nothing
    /// massive between them) move the same bodies the same way, and no torque decides how
    /// that motion is shared between them. A question of the joints' arrangement, not of
    /// the parameters' consistency.
    #[error("{}", coinciding(what, joints, motion))]
    Coinciding {
        /// The mass matrix: of which model, at which state.
        what: String,
        /// The joints that share the motion, numbered from 1, at least two.
        joints: Vec<usize>,
        /// Joint velocities, one per joint (rad/s or m/s), that move no mass: the null
        /// vector of M(q), its largest component 1.
        motion: Vec<f64>,
    },
    /// A value a simulated record would write lies beyond what robid's readers accept
    /// ([`crate::limits::Quantity::limit`], the one limit the readers apply): `identify`
    /// would refuse the file, so nothing is written (a current of 1e12 A, a torque noise
    /// over a tiny torque per ampere, was written with exit 0).
    #[error(
        "{}:{line}: column `{column}` would be {} (t = {} s), outside the range |{quantity}| \
         <= {limit:e} that robid's readers accept, so the file would be refused as data; \
         nothing was written; {fix}",
        path.display(),
        crate::Num::rounded(*value, 4),
        crate::Num(*time)
    )]
    Unreadable {
        /// The output file.
        path: std::path::PathBuf,
        /// Its line that would hold the value (the header is line 1).
        line: usize,
        /// The time stamp of that line, s.
        time: f64,
        /// The column's name (`i1`, `theta2`, ...).
        column: String,
        /// The value.
        value: f64,
        /// The quantity the readers take the column as (`torque` for a current).
        quantity: &'static str,
        /// The largest magnitude they accept.
        limit: f64,
        /// What makes the value this large, and what to change.
        fix: String,
    },
}

/// `joint 2` or `joints 1, 2 and 3`.
pub(crate) fn joint_list(joints: &[usize]) -> String {
    match joints {
        [j] => format!("joint {j}"),
        [first @ .., last] => {
            let first: Vec<String> = first.iter().map(usize::to_string).collect();
            format!("joints {} and {last}", first.join(", "))
        }
        [] => "no joint".to_owned(),
    }
}

/// The message of [`SimulateError::Coinciding`].
fn coinciding(what: &str, joints: &[usize], motion: &[f64]) -> String {
    let lowest = joints.first().copied().unwrap_or(1);
    let highest = joints.last().copied().unwrap_or(lowest);
    // the links from the lowest joint's to the one before the highest's lie between them
    let between = if highest <= lowest + 1 {
        format!("link {lowest}")
    } else {
        format!("links {lowest} to {}", highest - 1)
    };
    let velocities: Vec<String> = motion
        .iter()
        .map(|v| crate::Num::rounded(*v, 3).to_string())
        .collect();
    format!(
        "{what} is singular: {} move the same bodies the same way (the joint velocities [{}] \
         move no mass), so no torque decides how that motion is shared between them and the \
         robot cannot be simulated; the parameters are physically possible, the joints' \
         arrangement is the cause: nothing with mass or inertia lies between them ({between}), \
         or what they move has none about the line they share; give {between} a mass and \
         inertia (in a URDF, an `<inertial>` element), or describe {} as {}",
        joint_list(joints),
        velocities.join(", "),
        if joints.len() == 2 {
            "the two joints"
        } else {
            "these joints"
        },
        if joints.len() == 2 { "one" } else { "fewer" },
    )
}

/// The message of [`SimulateError::NoInertia`].
fn no_inertia(what: &str, joints: &[usize], dof: usize) -> String {
    let one = joints.len() == 1;
    let entries: Vec<String> = joints.iter().map(|j| format!("M{j}{j}")).collect();
    let lowest = joints.first().copied().unwrap_or(1);
    let (links, those) = if lowest == dof {
        (format!("link {dof} (the last)"), "that link its")
    } else {
        (format!("links {lowest} to {dof}"), "those links their")
    };
    format!(
        "{what} is singular: {} {} no mass or inertia ({} = 0), so no torque accelerates {} \
         and the robot cannot be simulated; the parameters give {links} no mass, or none \
         about {} axis: give {those} mass and inertia (in a URDF, `<inertial>` \
         elements; in a parameter file, their values)",
        joint_list(joints),
        if one { "moves" } else { "move" },
        entries.join(" = "),
        if one { "it" } else { "them" },
        if one { "its" } else { "their" },
    )
}
