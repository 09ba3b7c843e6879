//! The joints whose torque a parameter file leaves 0 at every state: the one check behind
//! the warnings of `robid torques --parameters` (their torque is 0 in every row) and `robid
//! excite --parameters` (their torque limit constrains nothing), and the one wording of its
//! cause and fix (docs/command-line.md#robid-torques).

use std::path::Path;

use robid_runtime::{Model, num};

use super::Error;
use super::description::Description;

/// A joint's torque that is below this share of the largest joint's counts as 0
/// ([`Idle::find`]): 1e-12 is far below any real ratio between the joints of one robot (a
/// wrist's torque is 1e-3 to 1e-6 of a shoulder's), and far above the rounding of f64
/// (1e-16), so that parameters written as 1e-320 or 1e-20 to mean 0 next to real ones are
/// told as 0.
pub(crate) const NEGLIGIBLE_SHARE: f64 = 1e-12;

/// A joint's torque below this many N m (at the states of [`Idle::find`], of about 0.6 rad,
/// rad/s and rad/s^2) counts as 0 even when every joint's is as small ([`Idle::find`]): a
/// femtonewton-metre, twelve orders below the resolution of a small servo's torque (about
/// 1e-3 N m), but far above denormal numbers (below 2.2e-308), which parameters of 1e-320
/// give and which carry no digits.
pub(crate) const NEGLIGIBLE_TORQUE: f64 = 1e-15;

/// Joints (numbered from 1) whose torque is 0 at every state with some base parameters, or
/// negligible, found by [`Idle::find`].
#[derive(Debug, Default, PartialEq, Eq)]
pub(crate) struct Idle {
    /// The joints, in order.
    pub(crate) joints: Vec<usize>,
    /// The names of the base parameters the torques of `joints` depend on, in the model's
    /// order.
    pub(crate) parameters: Vec<String>,
    /// Whether each of those parameters is exactly 0 (else some are only negligible).
    pub(crate) exact: bool,
}

impl Idle {
    /// The joints among those `keep` accepts (numbered from 1) whose torque is 0 at every
    /// state with the base parameters `base`, or negligible, and the names of the base
    /// parameters their torques depend on: a joint's torque is its row of the base
    /// regressor times `base`, so it is 0 at every state when every base parameter with a
    /// nonzero entry in that row is 0. The rows are taken at a few states of no special
    /// pose (every entry that is not structurally zero is nonzero there), entries below
    /// 1e-10 of the row's largest counting as zero. A joint's torque is measured by its
    /// largest term (entry times parameter, at any of the states, so that terms cannot
    /// cancel), and counts as negligible below [`NEGLIGIBLE_SHARE`] of the largest joint's
    /// or below [`NEGLIGIBLE_TORQUE`]: parameters of 1e-320 give torques of no digits
    /// (denormal numbers), which are 0 in all but name. The criterion holds for every
    /// source of parameters (a URDF's inertials, a `[standard]` or `[base]` table) and
    /// counts drive terms: a joint with friction has a torque.
    pub(crate) fn find(
        model: &dyn Model,
        base: &[f64],
        keep: &dyn Fn(usize) -> bool,
    ) -> Result<Idle, Error> {
        let (n, b) = (model.dof(), model.base_parameter_count());
        // the largest magnitude of each entry of the regressor over the states
        let mut largest = vec![0.0f64; n * b];
        let mut y = vec![0.0; n * b];
        for state in 0..3 {
            let value = |kind: usize, j: usize| {
                let x = (1 + j + 7 * kind + 31 * state) as f64;
                0.3 + 0.6 * (1.618_033_988_75 * x).fract()
            };
            let q: Vec<f64> = (0..n).map(|j| value(0, j)).collect();
            let qd: Vec<f64> = (0..n).map(|j| value(1, j)).collect();
            let qdd: Vec<f64> = (0..n).map(|j| value(2, j)).collect();
            model
                .base_regressor_into(&q, &qd, &qdd, &mut y)
                .map_err(robid_runtime::Error::from)?;
            for (l, v) in largest.iter_mut().zip(&y) {
                *l = l.max(v.abs());
            }
        }
        // the parameters each joint's torque depends on, and its largest term
        let (used, torque): (Vec<Vec<usize>>, Vec<f64>) = (0..n)
            .map(|j| {
                let row = &largest[j * b..(j + 1) * b];
                let top = row.iter().copied().fold(0.0, f64::max);
                let used: Vec<usize> = (0..b).filter(|&k| row[k] > 1e-10 * top).collect();
                let value = |k: usize| base.get(k).copied().unwrap_or(0.0).abs();
                let torque = used.iter().map(|&k| row[k] * value(k)).fold(0.0, f64::max);
                (used, torque)
            })
            .unzip();
        let largest_torque = torque.iter().copied().fold(0.0, f64::max);
        let floor = NEGLIGIBLE_TORQUE.max(NEGLIGIBLE_SHARE * largest_torque);
        let mut joints = Vec::new();
        let mut parameters: Vec<usize> = Vec::new();
        let mut exact = true;
        for j in (0..n).filter(|j| keep(j + 1)) {
            let used = &used[j];
            // a torque that is not a number is no torque to judge (refused where computed)
            if torque[j] < floor {
                exact &= used.iter().all(|&k| base.get(k) == Some(&0.0));
                joints.push(j + 1);
                for &k in used {
                    if !parameters.contains(&k) {
                        parameters.push(k);
                    }
                }
            }
        }
        parameters.sort_unstable();
        let parameters = parameters
            .into_iter()
            .map(|k| model.base_parameter_name(k).unwrap_or("?").to_owned())
            .collect();
        Ok(Idle {
            joints,
            parameters,
            exact,
        })
    }

    /// "0", or when some of the parameters are not exactly 0, "0 or negligible".
    pub(crate) fn zero(&self) -> &'static str {
        if self.exact { "0" } else { "0 or negligible" }
    }

    /// The cause, as in "with the parameters of FILE, joint 2 (`j2`) of ROBOT moves no
    /// mass or inertia: every base parameter its torque depends on (XX2R, ..) is 0": the
    /// joints (with their URDF names) of the description read from `robot`, and at most
    /// eight of the parameters. Empty when there are no joints.
    pub(crate) fn cause(&self, description: &Description, robot: &Path, file: &Path) -> String {
        let named: Vec<String> = self
            .joints
            .iter()
            .map(|&j| {
                let urdf = description.urdf.as_ref();
                match urdf.and_then(|c| c.links.get(j - 1)) {
                    Some(link) => format!("{j} (`{}`)", link.joint),
                    None => j.to_string(),
                }
            })
            .collect();
        let its = if self.joints.len() == 1 {
            "its torque"
        } else {
            "their torques"
        };
        let (named, moves, depends) = match named.split_last() {
            Some((last, [])) => (format!("joint {last}"), "moves", "depends"),
            Some((last, first)) => (
                format!("joints {} and {last}", first.join(", ")),
                "move",
                "depend",
            ),
            None => return String::new(),
        };
        // the base parameters, at most SHOWN of them
        const SHOWN: usize = 8;
        let list = match self.parameters.len() {
            0 => String::new(),
            k if k <= SHOWN => format!(" ({})", self.parameters.join(", ")),
            k => format!(
                " ({} and {} more)",
                self.parameters[..SHOWN].join(", "),
                k - SHOWN
            ),
        };
        // "that its torque feels": mass on a revolute joint's axis moves with it unfelt
        // (with `M2` given and the link's length 0 it said "moves no mass")
        let feels = if self.joints.len() == 1 {
            "that its torque feels"
        } else {
            "that their torques feel"
        };
        let (mass, zero) = if self.exact {
            (format!("no mass or inertia {feels}"), String::from("0"))
        } else {
            (
                format!("no mass or inertia to speak of {feels}"),
                format!(
                    "0 or negligible: {its} {} below {} of the largest joint's, or below {} N m",
                    if self.joints.len() == 1 {
                        "stays"
                    } else {
                        "stay"
                    },
                    num(NEGLIGIBLE_SHARE),
                    num(NEGLIGIBLE_TORQUE)
                ),
            )
        };
        format!(
            "with the parameters of {}, {named} of {} {moves} {mass}: every base parameter \
             {its} {depends} on{list} is {zero}",
            file.display(),
            robot.display(),
        )
    }

    /// The fix, as in "give the links from link 2 on their masses and inertias in FILE (a
    /// standard parameter it does not name counts as 0)".
    pub(crate) fn fix(&self, file: &Path) -> String {
        let lowest = self.joints.first().copied().unwrap_or(1);
        let file = file.display();
        format!(
            "give the links from link {lowest} on their masses and inertias in {file}, mass \
             off a revolute joint's axis or inertia about it (a standard parameter it does not \
             name counts as 0)"
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use robid_runtime::model::standard_parameter_names;

    /// The base parameters of the UR5e with the standard parameter `name` = `value(name)`.
    fn base_of(value: &dyn Fn(&str) -> f64) -> Vec<f64> {
        let model = robots::Ur5e;
        let names = standard_parameter_names(&model);
        let standard: Vec<f64> = names.iter().map(|n| value(n)).collect();
        let mut base = vec![0.0; model.base_parameter_count()];
        model.base_from_standard_into(&standard, &mut base).unwrap();
        base
    }

    /// The joints whose torque is 0 at every state are found from the regressor, for
    /// parameters from any source: standard parameters of the last two links all 0 leave
    /// joints 5 and 6 nothing to move (and name only their base parameters), all 0 every
    /// joint, none 0 no joint; `keep` leaves joints out of the check and their parameters
    /// out of the list.
    #[test]
    fn joints_with_nothing_to_move_are_found_from_the_regressor() {
        let model = robots::Ur5e;
        let all = |_: usize| true;
        let last_two_empty = base_of(&|n: &str| {
            if n.ends_with(['5', '6']) { 0.0 } else { 0.1 }
        });
        let idle = Idle::find(&model, &last_two_empty, &all).unwrap();
        assert_eq!(idle.joints, [5, 6]);
        assert!(!idle.parameters.is_empty());
        assert!(
            idle.parameters.iter().all(|p| p.ends_with(['5', '6'])),
            "{:?}",
            idle.parameters
        );
        let sixth = Idle::find(&model, &last_two_empty, &|j| j == 6).unwrap();
        assert_eq!(sixth.joints, [6]);
        assert!(sixth.parameters.len() < idle.parameters.len());
        let idle = Idle::find(&model, &base_of(&|_: &str| 0.1), &all).unwrap();
        assert!(idle.joints.is_empty());
        let idle = Idle::find(&model, &base_of(&|_: &str| 0.0), &all).unwrap();
        assert_eq!(idle.joints, [1, 2, 3, 4, 5, 6]);
        assert!(idle.exact);
    }

    /// Parameters written as 1e-320 (denormal torques, no digits) or 1e-13 next to real
    /// ones count as 0: below 1e-12 of the largest joint's torque (1e-13 gives torques
    /// above 1e-15 N m: the share decides); so do 1e-320 everywhere (below 1e-15 N m: the
    /// floor decides). They used to count as a load, as every value but an exact 0 did.
    /// Light links are not negligible: the last two at 1e-7 of the others, or every link
    /// at a milligram.
    #[test]
    fn negligible_parameters_leave_a_joint_idle() {
        let model = robots::Ur5e;
        let all = |_: usize| true;
        let last_two = |tiny: f64| {
            base_of(&|n: &str| {
                if n.ends_with(['5', '6']) { tiny } else { 10.0 }
            })
        };
        for tiny in [1e-320, 1e-13] {
            let idle = Idle::find(&model, &last_two(tiny), &all).unwrap();
            assert_eq!(idle.joints, [5, 6], "{tiny:e}");
            assert!(!idle.exact);
            assert!(
                idle.parameters.iter().all(|p| p.ends_with(['5', '6'])),
                "{:?}",
                idle.parameters
            );
        }
        let idle = Idle::find(&model, &base_of(&|_: &str| 1e-320), &all).unwrap();
        assert_eq!(idle.joints, [1, 2, 3, 4, 5, 6]);
        let idle = Idle::find(&model, &last_two(1e-6), &all).unwrap();
        assert!(idle.joints.is_empty(), "{idle:?}");
        let idle = Idle::find(&model, &base_of(&|_: &str| 1e-6), &all).unwrap();
        assert!(idle.joints.is_empty(), "{idle:?}");
    }
}
