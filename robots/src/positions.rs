//! Positions of a log beyond a description's position limits: what `robid inspect` and
//! `robid identify` warn of (docs/command-line.md#robid-inspect), from the per-joint
//! extremes the loader keeps ([`robid_runtime::data::Record::position_ranges`]).

use std::path::Path;

use robid_runtime::Num;
use robid_symbolic::{Joint, JointKind, Robot};

/// A warning for each joint of `robot` whose positions (`ranges`, per joint the smallest and
/// largest as read, joint side) pass its position limits in the description `file` by more
/// than a tenth of their span: data of another unit (a revolute joint's in degrees read as
/// radians, a prismatic one's in mm read as m) or of another robot, which identification
/// takes as they are and fits without a word. Joints without limits, and joints `ranges`
/// does not cover, are not checked.
///
/// ```
/// use robid_symbolic::Robot;
/// let robot: Robot = robots::Reference::named("ur5e").unwrap().robot();
/// let file = std::path::Path::new("ur5e.toml");
/// // joint 3 (limits [-3.1416, 3.1416] rad) at 90: degrees read as radians
/// let ranges = [[-1.0, 1.0], [-1.0, 1.0], [-90.0, 90.0]];
/// let warnings = robots::positions::beyond_limits(&robot, &ranges, file);
/// assert_eq!(warnings.len(), 1);
/// assert!(warnings[0].starts_with("joint 3's positions span [-90, 90] rad"));
/// ```
pub fn beyond_limits(robot: &Robot, ranges: &[[f64; 2]], file: &Path) -> Vec<String> {
    robot
        .joints()
        .iter()
        .zip(ranges)
        .enumerate()
        .filter_map(|(j, (joint, &range))| joint_beyond_limits(j + 1, joint, range, file))
        .collect()
}

/// [`beyond_limits`] for joint `number`, `joint`, whose positions span `range`.
fn joint_beyond_limits(
    number: usize,
    joint: &Joint,
    range: [f64; 2],
    file: &Path,
) -> Option<String> {
    let [lower, upper] = joint.limits.position?;
    let margin = 0.1 * (upper - lower);
    if range[0] >= lower - margin && range[1] <= upper + margin {
        return None;
    }
    let prismatic = joint.kind == JointKind::Prismatic;
    let (unit, hint) = if prismatic {
        ("m", "positions in mm? they are read in metres")
    } else {
        (
            "rad",
            "positions in degrees? set `angle = \"deg\"` in the config's [units]",
        )
    };
    Some(format!(
        "joint {number}'s positions span [{}, {}] {unit}, beyond its limits [{}, {}] {unit} in {}: \
         {hint}; or the data are another robot's",
        Num::rounded(range[0], 4),
        Num::rounded(range[1], 4),
        Num(lower),
        Num(upper),
        file.display()
    ))
}
