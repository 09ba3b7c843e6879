//! The joints whose torque a parameter file leaves 0 at every state: the one check behind
//! the warnings of `robid torques --parameters` (their torque is 0 in every row) and `robid
//! excite --parameters` (their torque limit constrains nothing), and the one wording of its
//! cause and fix (docs/command-line.md#robid-torques).

use std::path::Path;

use robid_runtime::Model;

use super::Error;
use super::description::Description;

/// Joints (numbered from 1) whose torque is 0 at every state with some base parameters,
/// found by [`Idle::find`].
#[derive(Debug, Default, PartialEq, Eq)]
pub(crate) struct Idle {
    /// The joints, in order.
    pub(crate) joints: Vec<usize>,
    /// The names of the base parameters the torques of `joints` depend on, in the model's
    /// order.
    pub(crate) parameters: Vec<String>,
}

impl Idle {
    /// The joints among those `keep` accepts (numbered from 1) whose torque is 0 at every
    /// state with the base parameters `base`, and the names of the base parameters their
    /// torques depend on: a joint's torque is its row of the base regressor times `base`,
    /// so it is 0 at every state when every base parameter with a nonzero entry in that row
    /// is 0. The rows are taken at a few states of no special pose (every entry that is not
    /// structurally zero is nonzero there), entries below 1e-10 of the row's largest
    /// counting as zero. The criterion holds for every source of parameters (a URDF's
    /// inertials, a `[standard]` or `[base]` table) and counts drive terms: a joint with
    /// friction has a torque.
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
        let mut joints = Vec::new();
        let mut parameters: Vec<usize> = Vec::new();
        for j in (0..n).filter(|j| keep(j + 1)) {
            let row = &largest[j * b..(j + 1) * b];
            let top = row.iter().copied().fold(0.0, f64::max);
            let used: Vec<usize> = (0..b).filter(|&k| row[k] > 1e-10 * top).collect();
            if used.iter().all(|&k| base.get(k) == Some(&0.0)) {
                joints.push(j + 1);
                for k in used {
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
        Ok(Idle { joints, parameters })
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
        format!(
            "with the parameters of {}, {named} of {} {moves} no mass or inertia: every base \
             parameter {its} {depends} on{list} is 0",
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
            "give the links from link {lowest} on their masses and inertias in {file} (a \
             standard parameter it does not name counts as 0)"
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
    }
}
