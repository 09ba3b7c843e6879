//! The validated [`Robot`] of a fitted chain: its name, the DH rows as geometric values,
//! the URDF's joint limits and gravity (docs/urdf.md#the-robot).

use super::super::bounds::{
    ANGLE_RESOLUTION, MAX_CALIBRATED_LENGTH, MAX_JOINTS, MAX_POSITION, MAX_TORQUE, MAX_VELOCITY,
    MIN_GRAVITY, MIN_LENGTH, RIGHT_ANGLE_SNAP, calibrated_pair,
};
use super::super::check::{and_more, measured_twist_consequence, show};
use super::super::file::Place;
use super::super::{DescriptionError, Geometry, Joint, JointKind, Limits, Robot, name_problem};
use super::chain::{Chain, Tree};
use super::frames::{Fit, NEAR_PARALLEL, PARALLEL, angle_text};
use super::rigid::{cross, dot, mat_vec, norm, transpose};
use super::xml::{self, JointType, Urdf};
use std::f64::consts::FRAC_PI_2;

/// Gravity components (m/s^2) smaller than this are rounding of a rotation by a multiple
/// of pi/2 (docs/urdf.md#gravity) and are zero.
const ZERO_GRAVITY: f64 = 1e-9;

/// The robot name of a URDF's name: a Rust identifier (`kuka-lwr` -> `kuka_lwr`), with a
/// warning when more than dashes and spaces had to change.
pub(super) fn robot_name(place: &Place<'_>, urdf: &Urdf, warnings: &mut Vec<String>) -> String {
    let written = urdf.name.as_str();
    let mut name: String = written
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect();
    let mut changed = None;
    if !name.starts_with(|c: char| c.is_ascii_alphabetic()) {
        name = format!("robot_{name}");
        changed = Some("does not start with a letter a-z or A-Z");
    } else if name_problem(&name).is_some() {
        name = format!("{name}_robot");
        changed = Some("is a Rust keyword or makes one");
    }
    if let Some(why) = changed {
        warnings.push(place.warning(
            urdf.name_at.start,
            &format!(
                "the robot name `{written}` {why}, so the robot is named `{name}` (in \
                 generated code and reports); rename it in the URDF for another name"
            ),
        ));
    }
    name
}

/// The robid limits of a URDF joint (`<limit>`): position (not for continuous joints),
/// velocity and effort (as torque). Zero effort or velocity, and equal lower and upper
/// positions, mean "not given" (the URDF defaults).
fn limits(place: &Place<'_>, joint: &xml::Joint) -> Result<Limits, DescriptionError> {
    let mut out = Limits::default();
    let Some(limit) = &joint.limit else {
        return Ok(out);
    };
    let at = || limit.range.clone();
    let describe = format!("`<limit>` of joint `{}`", joint.name);
    if joint.kind != JointType::Continuous && !limit.unbounded {
        let lower = limit.lower.unwrap_or(0.0);
        let upper = limit.upper.unwrap_or(0.0);
        if lower > upper {
            return Err(place.invalid(
                at(),
                format!(
                    "{describe}: lower {} is above upper {}",
                    show(lower),
                    show(upper)
                ),
                "write lower < upper (rad for revolute, m for prismatic joints); PyBullet \
                 reads lower > upper as no limit, which robid does not guess (swapped limits \
                 would lift the bounds an exciting trajectory keeps): for a joint without \
                 position limits leave `lower` and `upper` out, or make it `continuous`",
            ));
        }
        if lower.abs().max(upper.abs()) > MAX_POSITION {
            return Err(place.invalid(
                at(),
                format!(
                    "{describe}: positions [{}, {}] go beyond ±{}",
                    show(lower),
                    show(upper),
                    show(MAX_POSITION)
                ),
                format!(
                    "positions are in radians (revolute) or metres (prismatic); {}",
                    xml::NO_POSITION_LIMITS
                ),
            ));
        }
        if lower < upper {
            out.position = Some([lower, upper]);
        }
    }
    for (value, max, key, unit) in [
        (limit.velocity, MAX_VELOCITY, "velocity", "rad/s or m/s"),
        (limit.effort, MAX_TORQUE, "effort", "N m or N"),
    ] {
        let Some(x) = value.filter(|&x| x != 0.0) else {
            continue;
        };
        if !(x > 0.0 && x <= max) {
            return Err(place.invalid(
                at(),
                format!(
                    "{describe}: {key} {} is not a positive number up to {}",
                    show(x),
                    show(max)
                ),
                format!("{key} is a maximum absolute value in {unit}"),
            ));
        }
        if key == "velocity" {
            out.velocity = Some(x);
        } else {
            out.torque = Some(x);
        }
    }
    Ok(out)
}

/// A finite angle as a geometric value (exact text for multiples of pi/2).
fn angle(value: f64) -> Geometry {
    match angle_text(value) {
        Some(text) => Geometry::text(text).unwrap_or_else(|_| Geometry::zero()),
        None => Geometry::number(tidy(value)).unwrap_or_else(|_| Geometry::zero()),
    }
}

/// A finite length as a geometric value (the rows are checked finite first).
fn length(value: f64) -> Geometry {
    Geometry::number(tidy(value)).unwrap_or_else(|_| Geometry::zero())
}

/// The shortest decimal within [`TIDY_ULPS`] units in the last place of `value` or
/// [`TIDY_FLOOR`] of it, else `value`: a fitted value is computed from the URDF's own
/// numbers through rotations and sums, whose rounding would otherwise reach the model (the
/// KUKA iiwa's 0.2045 and 0.2155 gave d = 0.42000000000000004, and the base parameters'
/// expressions then carried 10500000000000001/12500000000000000 instead of 0.84; Kinova's
/// Gen3 gave -0.000350099999999999 for 2 x 0.00017505). A value that needs its digits
/// (farther than that from every shorter decimal) is kept as it is.
pub(super) fn tidy(value: f64) -> f64 {
    let tolerance = (TIDY_ULPS * value.abs() * f64::EPSILON).max(TIDY_FLOOR);
    (1..=15)
        .filter_map(|digits| format!("{value:.*e}", digits - 1).parse::<f64>().ok())
        .find(|short| (short - value).abs() <= tolerance)
        .unwrap_or(value)
}

/// How far (in units in the last place) [`tidy`] may move a value.
const TIDY_ULPS: f64 = 4.0;

/// How far (m or rad) [`tidy`] may move any value: the fit's own rounding, a few units of
/// 2^-52 of the chain's metre-sized numbers, whatever the size of the result.
const TIDY_FLOOR: f64 = 8.0 * f64::EPSILON;

/// Gravity in robid frame 0: `[0, 0, -9.81]` in the root link frame, through the fixed
/// path root -> base (every joint at zero) and frame 0's rotation in the base link frame.
pub(super) fn gravity(base_in_root: &super::rigid::Rigid, fit: &Fit) -> [f64; 3] {
    let in_base = mat_vec(&transpose(&base_in_root.r), [0.0, 0.0, -9.81]);
    let g = mat_vec(&transpose(&fit.frames[0].r), in_base);
    g.map(|x| if x.abs() < ZERO_GRAVITY { 0.0 } else { x })
}

/// `gravity` with its components below [`MIN_GRAVITY`] taken as 0, with one warning: joint
/// 1's axis (frame 0's z) a few µrad off the root's vertical or horizontal is a right angle
/// printed short (the SO-100's `1.57079` for pi/2: 6.3e-6 rad, a component of 6.2e-5 m/s^2),
/// which would give link 1's first moments a gravity torque through that tilt alone, one
/// no data determine. Dropping the components changes each gravity torque by at most their
/// share of g times the torque the links' weight has about a horizontal axis (m g l), not
/// of the torques themselves: on an arm whose axes are all vertical (a SCARA) the tilt is
/// all its gravity torque, and robid's are then 0. The warning says so, and names the
/// element that tilts the axis when one does ([`tilted`]), else joint 1.
pub(super) fn level(
    place: &Place<'_>,
    urdf: &Urdf,
    chain: &Chain,
    gravity: [f64; 3],
    warnings: &mut Vec<String>,
) -> [f64; 3] {
    let small = |x: f64| x != 0.0 && x.abs() < MIN_GRAVITY;
    let Some(&first) = chain.joints.first() else {
        return gravity;
    };
    let Some(smallest) = gravity
        .iter()
        .map(|x| x.abs())
        .filter(|&x| small(x))
        .reduce(f64::max)
    else {
        return gravity;
    };
    let j = &urdf.joints[first];
    let norm = gravity.iter().map(|x| x * x).sum::<f64>().sqrt();
    let tilt = (smallest / norm).asin();
    // what is dropped, as a share of g: a bound on the change of a gravity torque relative
    // to m g l, the torque of the weight about a horizontal axis
    let dropped = gravity
        .iter()
        .filter(|&&x| small(x))
        .map(|x| x * x)
        .sum::<f64>()
        .sqrt()
        / norm;
    let tilted = tilted(urdf, chain);
    let (at, cause) = match tilted.first() {
        Some((at, _, _)) => {
            let elements: Vec<String> = tilted
                .iter()
                .map(|(_, what, angle)| format!("{what} is {angle:.1e} rad from a right angle"))
                .collect();
            let them = if tilted.len() == 1 { "it" } else { "them" };
            (
                at.start,
                format!(
                    "{}; write {them} exactly (`0`, `1.5707963267948966`) or rounded to at \
                     least four decimals (`1.5708`) to say so yourself",
                    elements.join(", and ")
                ),
            )
        }
        None => (
            j.range.start,
            "a right angle on the path from the root to this joint written a few digits \
             short does this; write it exactly (`1.5707963267948966`) or rounded to at least \
             four decimals (`1.5708`) to say so yourself"
                .to_owned(),
        ),
    };
    let axes = ["x", "y", "z"];
    let components: Vec<String> = (0..3)
        .filter(|&k| small(gravity[k]))
        .map(|k| {
            format!(
                "{} = {} m/s^2",
                axes[k],
                show(format!("{:.4e}", gravity[k]).parse().unwrap_or(gravity[k]))
            )
        })
        .collect();
    warnings.push(place.warning(
        at,
        &format!(
            "gravity in robid frame 0, whose z is joint `{}`'s axis, has {} below {} m/s^2: \
             taken as 0, the axis as exactly parallel or perpendicular to the root link's z \
             (it is {tilt:.1e} rad from that, too little for any data to tell from none; a \
             measured mounting tilt this small changes each gravity torque by at most \
             {dropped:.1e} of m g l, the torque of the links' weight about a horizontal axis, \
             which is all the gravity torque of an arm whose axes are vertical, a SCARA's, \
             whose gravity torques are then 0); {cause} (docs/urdf.md#gravity)",
            j.name,
            components.join(" and "),
            show(MIN_GRAVITY)
        ),
    ));
    gravity.map(|x| if small(x) { 0.0 } else { x })
}

/// The robot: modified DH, numeric, no drive terms, the URDF's limits. A DH value or
/// gravity outside robid's bounds is an error at the joint (or the robot name).
pub(super) fn robot(
    place: &Place<'_>,
    urdf: &Urdf,
    chain: &Chain,
    fit: &Fit,
    gravity: [f64; 3],
    name: &str,
    warnings: &mut Vec<String>,
) -> Result<Robot, DescriptionError> {
    let mut joints = Vec::new();
    let mut errors = Vec::new();
    // DH lengths below MIN_LENGTH: (joint, key, value), taken as 0
    let mut tiny: Vec<(usize, &str, f64)> = Vec::new();
    for (k, &j) in chain.joints.iter().enumerate() {
        let urdf_joint = &urdf.joints[j];
        let [alpha, mut a, mut d, theta, mut b] = fit.rows[k];
        if !fit.rows[k].iter().all(|x| x.is_finite()) {
            errors.push(place.invalid(
                urdf_joint.range.clone(),
                format!(
                    "the DH row robid fits at joint `{}` is not finite ({:?})",
                    urdf_joint.name, fit.rows[k]
                ),
                "check the origins and axes of the chain's joints (are two axes almost parallel?)",
            ));
            continue;
        }
        let kind = if urdf_joint.kind == JointType::Prismatic {
            JointKind::Prismatic
        } else {
            JointKind::Revolute
        };
        // the next row's b and d reach the foot of the common normal (frame k's origin
        // stays near the joint, docs/urdf.md#fitting-the-dh-table); one error for a run of
        // such joints: they have one cause, a pair of axes
        let far = fit.reach[k] > MAX_CALIBRATED_LENGTH;
        if far && k > 0 && fit.reach[k - 1] > MAX_CALIBRATED_LENGTH {
            continue;
        }
        if far {
            let help = nearly_parallel(urdf, chain, fit, k).unwrap_or_else(|| {
                "check the origins and axes of the chain's joints (are two axes almost \
                 parallel?)"
                    .to_owned()
            });
            errors.push(place.invalid(
                urdf_joint.range.clone(),
                format!(
                    "the common normal from joint `{}`'s axis to the next lies {} m from the \
                     joint along its axis, and the next DH row passes through it (its `b` and \
                     `d` are about that long), beyond the ±{} m that robid keeps the digits of",
                    urdf_joint.name,
                    show(format!("{:.4e}", fit.reach[k]).parse().unwrap_or(fit.reach[k])),
                    show(MAX_CALIBRATED_LENGTH),
                ),
                help,
            ));
            continue;
        }
        for (key, value) in [("a", &mut a), ("d", &mut d), ("b", &mut b)] {
            if *value != 0.0 && value.abs() < MIN_LENGTH {
                tiny.push((k, key, *value));
                *value = 0.0;
            }
        }
        let mut joint = Joint::new(kind, angle(alpha), length(a), length(d), angle(theta));
        if b != 0.0 {
            joint = joint.with_gamma_b(Geometry::zero(), length(b));
        }
        match limits(place, urdf_joint) {
            Ok(l) => joint.limits = l,
            Err(e) => errors.push(e),
        }
        joints.push(joint);
    }
    if !errors.is_empty() {
        return Err(DescriptionError::from_errors(errors));
    }
    if let Some(&(k, key, value)) = tiny.first() {
        let more = and_more(tiny.len() - 1, "", "");
        let joint = &urdf.joints[chain.joints[k]];
        warnings.push(place.warning(
            joint.range.start,
            &format!(
                "the DH table robid fits has, at joint `{}`, `{key}` = {} m{more}: taken as \
                 0, a length below {} m is no robot's geometry but the rounding of the file's \
                 printed values (the torques change by about that length over the links' \
                 size); write the origins so that the offset is exactly 0 to say so yourself",
                joint.name,
                show(format!("{value:.4e}").parse().unwrap_or(value)),
                show(MIN_LENGTH)
            ),
        ));
    }
    let g = gravity.map(|x| Geometry::number(tidy(x)).unwrap_or_else(|_| Geometry::zero()));
    Robot::new_calibrated(name, super::super::Convention::Modified, Some(g), joints).map_err(|e| {
        let located = e
            .errors()
            .into_iter()
            .map(|one| locate(place, urdf, chain, fit, one))
            .collect();
        DescriptionError::from_errors(located)
    })
}

/// The cause and fix of a DH value refused at chain joint `k` when its axis and a
/// neighbour's are nearly parallel (docs/urdf.md#fitting-the-dh-table): the pair, their
/// angle, and how to write them. `None` when no neighbour is that close to parallel.
fn nearly_parallel(urdf: &Urdf, chain: &Chain, fit: &Fit, k: usize) -> Option<String> {
    // the axis of chain joint i is the z of frame i + 1
    let axis = |i: usize| {
        let r = &fit.frames[i + 1].r;
        [r[0][2], r[1][2], r[2][2]]
    };
    let off = |i: usize| {
        let (a, b) = (axis(i), axis(i + 1));
        norm(cross(a, b)).atan2(dot(a, b).abs())
    };
    let pairs = [k.checked_sub(1), (k + 1 < chain.joints.len()).then_some(k)];
    let (i, angle) = pairs
        .into_iter()
        .flatten()
        .map(|i| (i, off(i)))
        .filter(|&(_, angle)| angle > PARALLEL && angle < NEAR_PARALLEL)
        .min_by(|x, y| x.1.total_cmp(&y.1))?;
    let (first, second) = (
        &urdf.joints[chain.joints[i]].name,
        &urdf.joints[chain.joints[i + 1]].name,
    );
    Some(format!(
        "the axes of joints `{first}` and `{second}` are {angle:.1e} rad from parallel; \
         robid's DH table follows such a pair along its common normal, about their distance \
         divided by that angle from the joints, and holds it when that normal lies within \
         1e9 m of them and, for an angle below 1e-5 rad, farther than 1 km (nearer, the \
         angle is not told from 0): if they are meant to be parallel (a skew this small \
         changes the torques by about {angle:.0e} of their size), write the `<origin>` \
         rotations and `<axis>` elements of the chain up to `{second}` so that the \
         two axes are exactly parallel (docs/urdf.md#fitting-the-dh-table)"
    ))
}

/// Largest angle (rad) by which an origin's rotation or joint 1's axis may be off a
/// right angle to be named as the cause of a gravity component too small to accept: such
/// a component (below `MIN_GRAVITY`, 1e-3 m/s^2) comes from a tilt below 1e-4 rad, and
/// several tilts may add up.
const TILT_SUSPECT: f64 = 1e-3;

/// How far (rad) `r` is from the nearest rotation by right angles (a signed permutation
/// matrix), when it is near one at all (its entries round to one).
fn off_right_angles(r: &super::rigid::Mat3) -> Option<f64> {
    let p = r.map(|row| row.map(f64::round));
    let signed_permutation = (0..3).all(|i| {
        p[i].iter().map(|x| x.abs()).sum::<f64>() == 1.0
            && (0..3).map(|k| p[k][i].abs()).sum::<f64>() == 1.0
    });
    if !signed_permutation {
        return None;
    }
    // a rotation by theta is 2 sqrt(2) sin(theta / 2) from the identity (Frobenius norm)
    let distance = (0..3)
        .flat_map(|i| (0..3).map(move |k| (i, k)))
        .map(|(i, k)| (r[i][k] - p[i][k]).powi(2))
        .sum::<f64>()
        .sqrt();
    Some(
        2.0 * (distance / (2.0 * std::f64::consts::SQRT_2))
            .min(1.0)
            .asin(),
    )
}

/// The elements that tilt joint 1's axis by a few µrad from the root's axes: the origins
/// of the joints from the root to joint 1 (joint 1's included) whose rotation is a little
/// off a right-angle rotation, and joint 1's `<axis>` when it is a little off a coordinate
/// axis. Each with its joint's place, what it is and its angle; empty when no single
/// element is near but not at a right angle (several larger angles that almost cancel).
fn tilted(urdf: &Urdf, chain: &Chain) -> Vec<(std::ops::Range<usize>, String, f64)> {
    let first = chain.joints[0];
    let path: Vec<usize> = chain.above.iter().copied().chain([first]).collect();
    tilting(urdf, &path, &[first])
}

/// The elements among the `<origin>` rotations of the joints of `path` and the `<axis>`
/// of the joints of `axes` that are a little off a right angle (at most
/// [`TILT_SUSPECT`]), each with its joint's place, what it is and its angle.
fn tilting(
    urdf: &Urdf,
    path: &[usize],
    axes: &[usize],
) -> Vec<(std::ops::Range<usize>, String, f64)> {
    let suspect = |angle: f64| angle > 1e-12 && angle <= TILT_SUSPECT;
    let mut out = Vec::new();
    for &j in path {
        let joint = &urdf.joints[j];
        if let Some(angle) = off_right_angles(&joint.origin.r).filter(|&a| suspect(a)) {
            let kind = match joint.kind {
                JointType::Fixed => "fixed joint",
                _ => "joint",
            };
            out.push((
                joint.range.clone(),
                format!("the `<origin>` rotation of {kind} `{}`", joint.name),
                angle,
            ));
        }
    }
    for &j in axes {
        // the sine of the axis's angle to the nearest coordinate axis: its two smaller
        // components (the unit axis's largest is near 1, where 1 - x^2 loses the digits)
        let mut axis = urdf.joints[j].axis.map(f64::abs);
        axis.sort_by(f64::total_cmp);
        let angle = axis[0].hypot(axis[1]).min(1.0).asin();
        if suspect(angle) {
            let joint = &urdf.joints[j];
            out.push((
                joint.range.clone(),
                format!("the `<axis>` of joint `{}`", joint.name),
                angle,
            ));
        }
    }
    out
}

/// The warning for the calibrated pairs of the fitted table
/// ([`calibrated_pair`], docs/urdf.md#fitting-the-dh-table): two consecutive axes so
/// near parallel that their common normal lies beyond [`MAX_LENGTH`](super::super::bounds::MAX_LENGTH) of the joints. Such a
/// pair is exact (the torques are the file's), but it is what a calibration writes, or a
/// right angle mistyped on the way from one axis to the other (the Minitaur's `1.57075`
/// for pi/2, 4.6e-5 rad off): the warning names the pair, its angle and distance, what it
/// does to the base parameters, and the elements between the two axes that are a little
/// off a right angle, if any. One warning, at the first pair.
pub(super) fn calibrated_pairs(
    place: &Place<'_>,
    urdf: &Urdf,
    tree: &Tree,
    chain: &Chain,
    fit: &Fit,
) -> Option<String> {
    let pairs: Vec<usize> = (1..fit.rows.len())
        .filter(|&k| {
            let [alpha, _, d, _, b] = fit.rows[k];
            calibrated_pair(alpha, b, d)
        })
        .collect();
    let (&k, rest) = pairs.split_first()?;
    let (before, joint) = (chain.joints[k - 1], chain.joints[k]);
    let alpha = fit.rows[k][0];
    let angle = alpha.sin().abs().min(1.0).asin();
    let parallel = if alpha.cos() > 0.0 {
        "parallel"
    } else {
        "antiparallel"
    };
    let path = tree
        .path(tree.ends[before].1, tree.ends[joint].1)
        .unwrap_or_default();
    let elements: Vec<String> = tilting(urdf, &path, &[before, joint])
        .iter()
        .map(|(_, what, angle)| format!("{what} is {angle:.1e} rad from a right angle"))
        .collect();
    let fix = match elements.len() {
        0 => "write the `<origin>` rotations and `<axis>` elements between them so that the \
              axes are exactly parallel"
            .to_owned(),
        n => format!(
            "{}; write {} exactly (`0`, `1.5707963267948966`) or rounded to at least four \
             decimals (`1.5708`)",
            elements.join(", and "),
            if n == 1 { "it" } else { "them" }
        ),
    };
    let reach = fit.reach[k - 1];
    let more = and_more(rest.len(), " pair", " pairs");
    Some(place.warning(
        urdf.joints[joint].range.start,
        &format!(
            "the axes of joints `{}` and `{}` are {angle:.1e} rad from {parallel}{more}: \
             their common normal lies {} m from the joints, and robid's DH table holds them \
             as a calibrated pair (`b` and `d` about that long at joint `{}`: exact, the \
             torques are the file's); {}; if this is a calibration, nothing is wrong; if the \
             axes are meant to be {parallel}, {fix} (docs/urdf.md#fitting-the-dh-table)",
            urdf.joints[before].name,
            urdf.joints[joint].name,
            show(format!("{reach:.4e}").parse().unwrap_or(reach)),
            urdf.joints[joint].name,
            measured_twist_consequence(true),
        ),
    ))
}

/// An error of [`Robot::new`] (naming `joints[k]`) at the URDF joint it concerns.
fn locate(
    place: &Place<'_>,
    urdf: &Urdf,
    chain: &Chain,
    fit: &Fit,
    error: &DescriptionError,
) -> DescriptionError {
    let DescriptionError::Argument {
        argument,
        message,
        help,
    } = error
    else {
        return error.clone();
    };
    let index = argument
        .split("joints[")
        .nth(1)
        .and_then(|rest| rest.split(']').next())
        .and_then(|k| k.parse::<usize>().ok())
        .filter(|&k| k < chain.joints.len());
    let joint = index.map(|k| &urdf.joints[chain.joints[k]]);
    let skew = index
        .filter(|_| {
            [".alpha`", ".a`", ".d`", ".b`"]
                .iter()
                .any(|v| argument.ends_with(v))
        })
        .and_then(|k| nearly_parallel(urdf, chain, fit, k));
    match joint {
        Some(j) => place.invalid(
            j.range.clone(),
            format!(
                "the DH table robid fits to the URDF has, at joint `{}`, a value robid does not accept ({argument}): {message}",
                j.name
            ),
            match skew {
                Some(skew) => format!("{help}; {skew}"),
                None => format!(
                    "{help}; a URDF's lengths and angles are used as written (docs/urdf.md#the-angle-rule): \
                     write right angles to within 1e-9 rad and offsets of at least 1 µm or exactly 0"
                ),
            },
        ),
        None => place.invalid(
            urdf.name_at.clone(),
            format!("the robot robid builds from the URDF is not accepted ({argument}): {message}"),
            // too many joints: the chain is the user's choice
            if argument == "`joints`" && chain.joints.len() > MAX_JOINTS {
                format!(
                    "robid derives serial chains of at most {MAX_JOINTS} joints: choose a part \
                     of the robot with at most {MAX_JOINTS} movable joints with --base LINK \
                     and --tip LINK"
                )
            } else {
                help.clone()
            },
        ),
    }
}

/// The warning for the twists fitted within [`ANGLE_RESOLUTION`] of a right angle but
/// not at it (within 1e-9 rad they are the right angle): measured, so taken as written,
/// but where the exact angle would let the regrouping fold more, the base parameters
/// then hold combinations that only the small angle separates.
pub(super) fn measured_twists(
    place: &Place<'_>,
    urdf: &Urdf,
    chain: &Chain,
    fit: &Fit,
) -> Option<String> {
    let near: Vec<(usize, f64, bool)> = fit
        .rows
        .iter()
        .enumerate()
        // a calibrated pair's twist is told by `calibrated_pairs`
        .filter(|(_, row)| !calibrated_pair(row[0], row[4], row[2]))
        .filter_map(|(k, row)| {
            let quarter = (row[0] / FRAC_PI_2).round();
            let off = (row[0] - quarter * FRAC_PI_2).abs();
            (off > RIGHT_ANGLE_SNAP && off < ANGLE_RESOLUTION).then_some((
                k,
                off,
                quarter as i64 % 2 == 0,
            ))
        })
        .collect();
    let (&(k, off, parallel), rest) = near.split_first()?;
    let joint = &urdf.joints[chain.joints[k]];
    let more = and_more(rest.len(), " joint", " joints");
    Some(place.warning(
        joint.range.start,
        &format!(
            "joint `{}`'s axis is {off:.1e} rad from {} the previous one's{more}: taken as \
             measured; {}; to identify the nominal set, write the origins and axes so that \
             the angle is exact",
            joint.name,
            if parallel {
                "parallel to"
            } else {
                "perpendicular to"
            },
            measured_twist_consequence(parallel),
        ),
    ))
}
