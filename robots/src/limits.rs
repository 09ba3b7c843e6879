//! A log beyond a description's limits: positions past the position limits, torques far
//! past the torque limits, and a torque that never changes. What `robid inspect` and
//! `robid identify` warn of
//! (docs/command-line.md#robid-inspect), from the per-joint extremes the loader keeps
//! ([`robid_runtime::data::Record::extremes`]).

use std::path::Path;

use robid_runtime::Num;
use robid_runtime::data::{DEFAULT_REST_VELOCITY, DerivativeAgreement, DerivativeColumn, Extremes};
use robid_symbolic::{Joint, JointKind, Robot};

/// How many times its limit a joint's torque may reach before the data are taken for
/// another unit: a description's torque limit is a drive's peak (or its rated torque,
/// which a peak passes by about 2 to 3), while a unit slip is a factor of 1000 (mN m read
/// as N m) or a torque constant or gear ratio off by tens.
pub const TORQUE_LIMIT_FACTOR: f64 = 5.0;

/// A warning for each joint of `robot` whose data (`extremes`, joint side, as the loader
/// read them) leave its limits in the description `file`: positions past the position
/// limits by more than a tenth of their span (a revolute joint's degrees read as radians, a
/// prismatic one's mm read as m), torques above [`TORQUE_LIMIT_FACTOR`] times the torque
/// limit (mN m read as N m, a missing or wrong `torque_scale`, torque constant or gear
/// ratio), speeds in the fastest [`SPEED_SHARE`] of the record above
/// [`SPEED_LIMIT_FACTOR`] times the velocity limit (time stamps in s read as ms), or data
/// of another robot: identification takes them as they
/// are and fits them without a word. Joints without limits, and joints `extremes` does not cover, are not
/// checked against limits. Whatever the limits, a velocity column in other units than
/// the positions, or an acceleration column in other units than the velocity column, or
/// either column one value throughout while what it derives clearly changes (by more
/// than the default rest velocity: a dead channel), is told too
/// ([`DerivativeAgreement::warning`]).
///
/// [`DerivativeAgreement::warning`]: robid_runtime::data::DerivativeAgreement::warning
///
/// ```
/// use robid_runtime::data::Extremes;
/// use robid_symbolic::Robot;
/// let robot: Robot = robots::Reference::named("ur5e").unwrap().robot();
/// let file = std::path::Path::new("ur5e.toml");
/// // joint 3 (limits [-3.1416, 3.1416] rad) at 90: degrees read as radians; joint 2's
/// // torque (limit 150 N m) at 80000: mN m read as N m
/// let extremes = Extremes {
///     position: vec![[-1.0, 1.0], [-1.0, 1.0], [-90.0, 90.0]],
///     torque: vec![[-10.0, 10.0], [-80000.0, 2000.0], [-5.0, 5.0]],
///     ..Extremes::default()
/// };
/// let warnings = robots::limits::beyond_limits(&robot, &extremes, file);
/// assert_eq!(warnings.len(), 2);
/// assert!(warnings[0].starts_with("joint 2's torques reach -80000 N m"));
/// assert!(warnings[1].starts_with("joint 3's positions span [-90, 90] rad"));
/// // joint 1's torque logged as zeros while it moves
/// let dead = Extremes {
///     position: vec![[-1.0, 1.0]],
///     torque: vec![[0.0, 0.0]],
///     ..Extremes::default()
/// };
/// let warnings = robots::limits::beyond_limits(&robot, &dead, file);
/// assert!(warnings[0].starts_with("joint 1's torque is 0 over the whole record"));
/// ```
///
/// And a joint whose torque is one value over the whole record while the joint moves: a
/// dead channel, or the wrong column (a pendulum's second torque logged as zeros fitted
/// to 3 % with exit 0, its first moment a hundredth of the truth).
pub fn beyond_limits(robot: &Robot, extremes: &Extremes, file: &Path) -> Vec<String> {
    let mut warnings = Vec::new();
    for (j, joint) in robot.joints().iter().enumerate() {
        if let Some(&range) = extremes.torque.get(j) {
            let moves = extremes.position.get(j).is_some_and(|p| p[1] > p[0]);
            if moves && range[0] == range[1] {
                warnings.push(format!(
                    "joint {}'s torque is {} over the whole record while the joint moves: a \
                     dead channel or the wrong column (identification fits the model to it); \
                     check the config's torque columns and the logger",
                    j + 1,
                    Num(range[0])
                ));
            }
            warnings.extend(torque_beyond_limit(j + 1, joint, range, file));
        }
        let positions = extremes
            .position
            .get(j)
            .and_then(|&range| position_beyond_limits(j + 1, joint, range, file, Of::Log));
        // positions in another unit move too fast as well: their warning says why
        let speeds = extremes
            .speed
            .get(j)
            .and_then(|h| h.reached_by(SPEED_SHARE));
        match (positions, speeds) {
            (Some(w), _) => warnings.push(w),
            (None, Some(speed)) => warnings.extend(speed_beyond_limit(j + 1, joint, speed, file)),
            (None, None) => {}
        }
        warnings.extend(derivative_warnings(j, extremes));
    }
    warnings
}

/// [`beyond_limits`]' warnings of joint `j`'s (from 0) velocity and acceleration columns:
/// a column is dead only beside clear motion, the positions' fastest [`SPEED_SHARE`] (for
/// the velocities) or the velocity column's span (for the accelerations) above the
/// default rest velocity: a joint held still may log a velocity of exactly 0 beside an
/// encoder that flickers by a count.
fn derivative_warnings(j: usize, extremes: &Extremes) -> Vec<String> {
    let clearly = |v: f64| v > DEFAULT_REST_VELOCITY;
    let speed = extremes
        .speed
        .get(j)
        .and_then(|h| h.reached_by(SPEED_SHARE));
    let velocity = extremes.velocity.get(j);
    let span = velocity
        .and_then(DerivativeAgreement::range)
        .map(|[lo, hi]| hi - lo);
    let acceleration = extremes.acceleration.get(j);
    [
        (
            velocity,
            DerivativeColumn::Velocity,
            speed.is_some_and(clearly),
        ),
        (
            acceleration,
            DerivativeColumn::Acceleration,
            span.is_some_and(clearly),
        ),
    ]
    .into_iter()
    .filter_map(|(a, column, moves)| a?.warning(j + 1, column, moves))
    .collect()
}

/// The share of a record whose speed is checked against the velocity limit: the fastest
/// 1 % (a joint at rest most of the record still moves in it; a glitch in the positions
/// is less).
pub const SPEED_SHARE: f64 = 0.01;

/// How many times its velocity limit the speed that [`SPEED_SHARE`] of a record reaches
/// may be before the time stamps are taken for another unit: no joint passes its limit
/// at all, the speed is known to a factor of 2 ([`SpeedHistogram::reached_by`]: never
/// above it), and a unit slip in the time is a factor of 1000.
///
/// [`SpeedHistogram::reached_by`]: robid_runtime::data::SpeedHistogram::reached_by
pub const SPEED_LIMIT_FACTOR: f64 = 2.0;

/// [`beyond_limits`] for the speeds of joint `number`, `joint`, which reach `speed` in
/// [`SPEED_SHARE`] of the record.
fn speed_beyond_limit(number: usize, joint: &Joint, speed: f64, file: &Path) -> Option<String> {
    let limit = joint.limits.velocity.filter(|&v| v > 0.0)?;
    if speed <= SPEED_LIMIT_FACTOR * limit {
        return None;
    }
    let unit = if joint.kind == JointKind::Prismatic {
        "m/s"
    } else {
        "rad/s"
    };
    Some(format!(
        "joint {number}'s positions move faster than {} {unit} in {} % of the record, more \
         than {} times its velocity limit {} {unit} in {}: time stamps in another unit than \
         the config says? `time_scale` turns them into seconds (1 for seconds, 1e-3 for \
         milliseconds), or check `sample_rate`; or positions in another unit, or the data \
         are another robot's",
        Num::rounded(speed, 2),
        Num(100.0 * SPEED_SHARE),
        (speed / limit).floor(),
        Num(limit),
        file.display()
    ))
}

/// Whose positions are checked: a log's (read through a config, whose `[units]` fix a
/// unit) or a reference trajectory's (`robid simulate`: radians and metres as written).
#[derive(Clone, Copy, PartialEq, Eq)]
enum Of {
    Log,
    Trajectory,
}

/// A warning for each joint of `robot` whose positions in a reference trajectory
/// (`position`: `[smallest, largest]` per joint) leave its position limits in the
/// description `file` by more than a tenth of their span, as [`beyond_limits`] does for a
/// log: `robid simulate` follows the trajectory wherever it goes (degrees written as
/// radians, a trajectory of another robot), and the simulated data then identify a robot
/// at positions it never reaches.
///
/// ```
/// let robot: robid_symbolic::Robot = robots::Reference::named("ur5e").unwrap().robot();
/// let file = std::path::Path::new("ur5e.toml");
/// let w = robots::limits::trajectory_beyond_limits(&robot, &[[-1.0, 1.0], [-90.0, 90.0]], file);
/// assert!(w[0].starts_with("joint 2's positions span [-90, 90] rad") && w[0].contains("write them in radians"));
/// ```
pub fn trajectory_beyond_limits(robot: &Robot, position: &[[f64; 2]], file: &Path) -> Vec<String> {
    robot
        .joints()
        .iter()
        .zip(position)
        .enumerate()
        .filter_map(|(j, (joint, &range))| {
            position_beyond_limits(j + 1, joint, range, file, Of::Trajectory)
        })
        .collect()
}

/// [`beyond_limits`] for the positions of joint `number`, `joint`, which span `range`.
fn position_beyond_limits(
    number: usize,
    joint: &Joint,
    range: [f64; 2],
    file: &Path,
    of: Of,
) -> Option<String> {
    let [lower, upper] = joint.limits.position?;
    let margin = 0.1 * (upper - lower);
    if range[0] >= lower - margin && range[1] <= upper + margin {
        return None;
    }
    let prismatic = joint.kind == JointKind::Prismatic;
    // the unit slip that the range fits: degrees read as radians, mm as m; else none known
    let (unit, per_unit) = if prismatic {
        ("m", 1e-3)
    } else {
        ("rad", std::f64::consts::PI / 180.0)
    };
    let fits =
        |scale: f64| range[0] * scale >= lower - margin && range[1] * scale <= upper + margin;
    // a range no wider than the limits' fits them once shifted
    let shifted = range[1] - range[0] <= upper - lower + 2.0 * margin;
    // an angle logged modulo a turn is unwrapped from its first sample's turn (within
    // [-pi, 2 pi]), which may be a turn away from the one the limits hold
    let turn = std::f64::consts::TAU;
    let turned = (of == Of::Log && !prismatic && range[0] <= turn && range[1] >= -0.5 * turn)
        .then(|| {
            [-turn, turn]
                .into_iter()
                .find(|&t| range[0] + t >= lower - margin && range[1] + t <= upper + margin)
        })
        .flatten();
    if let Some(t) = turned {
        return Some(format!(
            "joint {number}'s positions span [{}, {}] rad, beyond its limits [{}, {}] rad in {}: \
             an angle logged modulo a turn (a single-turn encoder) and unwrapped from its \
             first sample's turn? {} they span [{}, {}] rad, within the limits, where the \
             dynamics are the same: nothing to change; or the data are another robot's",
            Num::rounded(range[0], 4),
            Num::rounded(range[1], 4),
            Num(lower),
            Num(upper),
            file.display(),
            if t > 0.0 {
                "a turn higher"
            } else {
                "a turn lower"
            },
            Num::rounded(range[0] + t, 4),
            Num::rounded(range[1] + t, 4),
        ));
    }
    let hint = match (of, prismatic, fits(per_unit), shifted) {
        (_, true, true, _) => "positions in mm? they are read in metres",
        (Of::Log, false, true, _) => {
            "positions in degrees, or motor angles? set `angle = \"deg\"` in [units], or \
             `position_side = \"motor\"` and `gear_ratios` in [drive], of the config given \
             with --config (`robid identify --example-config` prints one)"
        }
        (Of::Trajectory, false, true, _) => "positions in degrees? write them in radians",
        (Of::Log, _, false, true) => {
            "positions off by an offset (the encoders' zero elsewhere than the model's, or \
             a `position_offset` the config sets)? set or correct `position_offset` in [units] \
             of the config given with --config"
        }
        (Of::Trajectory, _, false, true) => {
            "positions off by an offset (another zero than the model's)? shift them"
        }
        // wider than the limits, and neither degrees nor mm: counts, a wrong gear ratio
        (Of::Log, _, false, false) => {
            "positions in another unit (encoder counts, motor side: see [drive] \
             position_side and gear_ratios)?"
        }
        (Of::Trajectory, _, false, false) => "positions in another unit?",
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

/// [`beyond_limits`] for the torques of joint `number`, `joint`, which span `range`.
fn torque_beyond_limit(
    number: usize,
    joint: &Joint,
    range: [f64; 2],
    file: &Path,
) -> Option<String> {
    let limit = joint.limits.torque?;
    // the larger magnitude, with its sign
    let peak = if range[0].abs() > range[1].abs() {
        range[0]
    } else {
        range[1]
    };
    // the loader keeps finite values only
    if peak.abs() <= TORQUE_LIMIT_FACTOR * limit {
        return None;
    }
    let unit = if joint.kind == JointKind::Prismatic {
        "N"
    } else {
        "N m"
    };
    Some(format!(
        "joint {number}'s torques reach {} {unit}, {} times its limit {} {unit} in {}: \
         torques in another unit (mN m, or currents)? set `torque_scale` in the config's \
         [units], or the drive chain's `torque_constants` and `gear_ratios`; or the data are \
         another robot's",
        Num::rounded(peak, 4),
        Num::rounded(peak.abs() / limit, 3),
        Num(limit),
        file.display()
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The hint names the slip the range fits: degrees read as radians when the range in
    /// degrees fits the limits, mm read as m likewise, an offset when the range fits
    /// shifted; positions that fit none (encoder counts, a motor-side angle) are not told
    /// to be degrees.
    #[test]
    fn the_hint_is_the_unit_slip_the_range_fits() {
        let robot = crate::Reference::named("ur5e").unwrap().robot();
        let file = Path::new("ur5e.toml");
        let warn = |position: Vec<[f64; 2]>| {
            let extremes = Extremes {
                position,
                ..Extremes::default()
            };
            beyond_limits(&robot, &extremes, file)
        };
        // joint 3's limits: [-3.1416, 3.1416] rad; 170 degrees fit them
        let degrees = warn(vec![[0.0, 1.0], [0.0, 1.0], [-170.0, 170.0]]);
        assert!(
            degrees[0].contains("positions in degrees, or motor angles?"),
            "{degrees:?}"
        );
        // 40000 counts do not fit as degrees
        let counts = warn(vec![[0.0, 1.0], [0.0, 1.0], [-40000.0, 40000.0]]);
        assert!(
            counts[0].contains("another unit (encoder counts") && !counts[0].contains("degrees"),
            "{counts:?}"
        );
        // 400 to 405 rad: not degrees (7 to 7.1 rad), but 5 rad wide, within the 6.3 rad
        // the limits span
        let shifted = warn(vec![[0.0, 1.0], [0.0, 1.0], [400.0, 405.0]]);
        assert!(
            shifted[0].contains("off by an offset") && shifted[0].contains("position_offset"),
            "{shifted:?}"
        );
        // a single-turn [0, 2 pi) log unwrapped from a first sample just below 2 pi: a turn
        // lower it lies within the limits (it was told to be in degrees)
        let turned = warn(vec![[0.0, 1.0], [0.0, 1.0], [5.83, 8.5]]);
        assert!(
            turned[0].contains("modulo a turn")
                && turned[0].contains("a turn lower they span [-0.4532, 2.217] rad")
                && !turned[0].contains("degrees"),
            "{turned:?}"
        );
    }

    /// A joint whose fastest 1 % moves above twice its velocity limit is named with the
    /// time stamps' unit slip, also when it rests most of the record; one at its limit or
    /// at rest is not, nor one whose positions leave their limits (their own warning names
    /// the unit).
    #[test]
    fn speeds_past_the_velocity_limit_are_named() {
        use robid_runtime::data::SpeedHistogram;
        let robot = crate::Reference::named("ur5e").unwrap().robot();
        let file = Path::new("ur5e.toml");
        let limit = robot.joints()[0].limits.velocity.unwrap();
        // 98 % of the record at rest, 2 % at `speed`
        let warn = |speed: f64| {
            let mut h = SpeedHistogram::default();
            for k in 0..100 {
                h.add(if k < 98 { 0.0 } else { speed });
            }
            let extremes = Extremes {
                speed: vec![h],
                ..Extremes::default()
            };
            beyond_limits(&robot, &extremes, file)
        };
        let fast = warn(1000.0 * limit);
        assert_eq!(fast.len(), 1, "{fast:?}");
        assert!(
            fast[0].starts_with("joint 1's positions move faster than ")
                && fast[0].contains(" rad/s in 1 % of the record, more than ")
                && fast[0].contains("times its velocity limit")
                && fast[0].contains("`time_scale`"),
            "{fast:?}"
        );
        assert!(warn(limit).is_empty());
        assert!(warn(0.0).is_empty());
        // positions in degrees move too fast as well: the positions' warning alone
        let mut h = SpeedHistogram::default();
        h.add(1000.0 * limit);
        let degrees = Extremes {
            position: vec![[-170.0, 170.0]],
            speed: vec![h],
            ..Extremes::default()
        };
        let w = beyond_limits(&robot, &degrees, file);
        assert!(
            w.len() == 1 && w[0].contains("positions in degrees, or motor angles?"),
            "{w:?}"
        );
    }

    /// A velocity column of zeros is a dead channel beside positions that clearly move
    /// (their fastest 1 % above the default rest velocity), not beside an encoder that
    /// flickers by a count; an acceleration column of zeros likewise beside a velocity
    /// column whose span passes the rest velocity.
    #[test]
    fn a_dead_derivative_column_is_told_beside_clear_motion() {
        use robid_runtime::data::{DerivativeAgreement, SpeedHistogram};
        let robot = crate::Reference::named("ur5e").unwrap().robot();
        let file = Path::new("ur5e.toml");
        let time = |k: usize| k as f64 * 1e-3;
        let zeros = [0.0; 200];
        let warn = |speed: f64, velocities: &[f64]| {
            let q: Vec<f64> = (0..200).map(|k| speed * time(k)).collect();
            let mut h = SpeedHistogram::default();
            h.add(speed);
            let (mut velocity, mut acceleration) = Default::default();
            DerivativeAgreement::add(&mut velocity, &q, velocities, &time);
            DerivativeAgreement::add(&mut acceleration, velocities, &zeros, &time);
            let extremes = Extremes {
                speed: vec![h],
                velocity: vec![velocity],
                acceleration: vec![acceleration],
                ..Extremes::default()
            };
            beyond_limits(&robot, &extremes, file)
        };
        let w = warn(0.5, &zeros);
        assert!(
            w.len() == 1
                && w[0].starts_with("joint 1's velocity column is 0 over the whole record while its positions change"),
            "{w:?}"
        );
        assert!(warn(0.01, &zeros).is_empty());
        // a velocity column that spans 0.5 rad/s beside accelerations of 0
        let ramp: Vec<f64> = (0..200).map(|k| 0.5 * k as f64 / 199.0).collect();
        let w = warn(0.5, &ramp);
        let dead = "joint 1's acceleration column is 0 over the whole record while its velocity column changes";
        assert!(w.iter().any(|w| w.starts_with(dead)), "{w:?}");
        let slow: Vec<f64> = ramp.iter().map(|v| v * 0.05).collect();
        assert!(!warn(0.5, &slow).iter().any(|w| w.contains("acceleration")));
    }
}
