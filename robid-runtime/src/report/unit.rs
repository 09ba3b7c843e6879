//! The units of the joint torques: N m for a revolute joint, N for a prismatic one (a
//! joint's "torque" is the generalised force along its coordinate).

/// The unit of a revolute joint's torque, and of a joint a report does not name.
pub const REVOLUTE: &str = "N m";

/// The unit of a prismatic joint's force.
pub const PRISMATIC: &str = "N";

/// The unit of each of `dof` joints' torques, of which `prismatic` flags the prismatic
/// ones (a joint not listed is revolute).
///
/// ```
/// use robid_runtime::report::joint_units;
/// assert_eq!(joint_units(&[false, true], 3), ["N m", "N", "N m"]);
/// ```
pub fn joint_units(prismatic: &[bool], dof: usize) -> Vec<&'static str> {
    (0..dof)
        .map(|j| {
            if prismatic.get(j) == Some(&true) {
                PRISMATIC
            } else {
                REVOLUTE
            }
        })
        .collect()
}

/// The unit of the torques of joints of `units` together (of the RMS errors and of
/// eq. 22's NMSE): "N m", "N" (forces only) or "N m and N" (eq. 22's NMSE of a
/// prismatic-only robot was labelled N m); "N m" for none.
///
/// ```
/// use robid_runtime::report::{joint_units, torque_unit};
/// assert_eq!(torque_unit(&joint_units(&[], 6)), "N m");
/// assert_eq!(torque_unit(&joint_units(&[true, true], 2)), "N");
/// assert_eq!(torque_unit(&joint_units(&[true], 2)), "N m and N");
/// ```
pub fn torque_unit<S: AsRef<str>>(units: &[S]) -> &'static str {
    let forces = units.iter().filter(|u| u.as_ref() == PRISMATIC).count();
    match forces {
        0 => REVOLUTE,
        f if f == units.len() => PRISMATIC,
        _ => "N m and N",
    }
}
