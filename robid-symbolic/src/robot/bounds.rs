//! The limits a robot description must stay within, checked when a
//! [`Robot`](super::Robot) is built (from a file, with each error's line and
//! column, or in code) and named in the errors.
//!
//! Magnitudes have physical ranges wide enough for any arm and narrow enough
//! that the regrouping's numeric rank analysis (regressor columns sampled at
//! random states, independence decided at a relative 1e-11) decides every
//! dependency as it would for nominal values: the tests derive the reference
//! robots with every length, and every gravity component, at each end of its
//! range and find the base-parameter count of the nominal robot.
//!
//! | what | accepted |
//! |---|---|
//! | DH lengths `a`, `d`, `b` | 0 (or a number below [`LENGTH_SNAP`], taken as 0), or [`MIN_LENGTH`] (1 µm) to [`MAX_LENGTH`] (1 km) in magnitude, in metres; `b` and `d` of a [calibrated pair](calibrated_pair) up to [`MAX_CALIBRATED_LENGTH`] (1e9 m) |
//! | DH angles `alpha`, `theta` | at most [`MAX_ANGLE`] (one turn) in magnitude, in radians; exactly `k pi/2` (as `"pi/2"`, `0`, or a number within [`RIGHT_ANGLE_SNAP`] of it, which is taken as it) or at least [`ANGLE_RESOLUTION`] away from every such angle, but for the `alpha` of a [calibrated pair](calibrated_pair), the `theta` of a revolute joint (an offset of its variable, which changes no base parameter: any value) and the angles fitted to a URDF or of a description marked `calibrated = true` (measured, not typed) |
//! | gravity components | 0, or [`MIN_GRAVITY`] to [`MAX_GRAVITY`] m/s^2 in magnitude |
//! | a value with symbols | the above at the `[symbols]` values when all its symbols have one, and at most [`MAX_SAMPLED`] in magnitude for any symbol values in [`SYMBOL_SAMPLES`] |
//! | `[symbols]` values | finite |
//! | position limits | two finite values, lower < upper, at most [`MAX_POSITION`] in magnitude |
//! | velocity, acceleration, torque limits | positive, at most [`MAX_VELOCITY`], [`MAX_ACCELERATION`], [`MAX_TORQUE`] |
//! | joints | 1 to [`MAX_JOINTS`] |
//! | geometric symbols | at most [`MAX_SYMBOLS`] |
//! | a description file | at most [`MAX_DESCRIPTION_LEN`] bytes |
//! | a URDF's elements | nested at most [`MAX_URDF_DEPTH`] deep |
//! | a name (of the robot, a URDF link or joint) | at most [`MAX_NAME_LEN`] characters |
//! | one expression | the limits of [`Arena::parse`](crate::expr::Arena::parse): [`MAX_EXPRESSION_LEN`](crate::expr::MAX_EXPRESSION_LEN) bytes, [`MAX_NESTING`](crate::expr::MAX_NESTING) levels, exponents within ±[`MAX_EXPONENT`](crate::expr::MAX_EXPONENT) |

/// Most joints of a robot (a serial chain; deriving a 32-joint chain takes
/// seconds, the cost grows faster than the square of the count).
pub const MAX_JOINTS: usize = 32;

/// Most geometric symbols of a robot (dependency coefficients that change with the
/// symbols are fitted as polynomials of degree up to four, at most 160 terms, in them
/// and in the sines and cosines of angle symbols, so the fit grows quickly with their
/// number).
pub const MAX_SYMBOLS: usize = 16;

/// Largest magnitude of a DH length `a` or `d` (m).
pub const MAX_LENGTH: f64 = 1e3;

/// Smallest magnitude of a DH length that is not zero (m) (1 µm): anything
/// shorter is a mistake (millimetres?) or is meant to be 0.
pub const MIN_LENGTH: f64 = 1e-6;

/// Largest magnitude of a DH angle `alpha` or `theta` (rad): one turn. A
/// larger angle is usually written in degrees.
pub const MAX_ANGLE: f64 = 2.0 * std::f64::consts::PI;

/// Smallest distance (rad) between a DH angle that is not exactly `k pi/2` and
/// the nearest `k pi/2`. `1.5707963` is 2.7e-8 rad from `pi/2`: an
/// approximation of a right angle that would make axes almost, not exactly,
/// perpendicular (write `"pi/2"`). Not for the `theta` of a revolute joint, which only
/// shifts its variable (a description file warns when one is this near a nonzero right
/// angle).
pub const ANGLE_RESOLUTION: f64 = 1e-5;

/// How close (rad) a numeric angle must be to a multiple of pi/2 to be that multiple
/// exactly, in a description as in a URDF (docs/urdf.md#the-angle-rule): a right angle
/// printed by a program (`1.5707963267948966` is 6e-17 rad from pi/2, the ROS-Industrial
/// files' `1.57079632679` 4.9e-12), nothing coarser (`1.57079` is not pi/2).
pub const RIGHT_ANGLE_SNAP: f64 = 1e-9;

/// Lengths (m) shorter than this are 0, in a description as in a URDF: the rounding of a
/// computed zero (`4.440892098500626e-17` from a script's frame arithmetic), which
/// [`MIN_LENGTH`] would otherwise refuse.
pub const LENGTH_SNAP: f64 = 1e-12;

/// Largest magnitude of the `b` and `d` of a [calibrated pair](calibrated_pair) (m): f64
/// keeps their sum to 2^-52 of them, 2.2e-7 m, below [`MIN_LENGTH`].
pub const MAX_CALIBRATED_LENGTH: f64 = 1e9;

/// Whether a modified-DH row with these numeric `alpha`, `b` and `d` is a calibrated pair of
/// nearly parallel axes: a twist within 1e-2 rad of 0 or pi (its sine below 1e-2), `b` or `d`
/// beyond [`MAX_LENGTH`] and both at most [`MAX_CALIBRATED_LENGTH`] in magnitude, nearly
/// cancelling, so that the row's frame origin lies within [`MAX_LENGTH`] of the previous
/// one (`|b + d cos(alpha)|` and `|d sin(alpha)|`; one of them may then be just within
/// [`MAX_LENGTH`], by the frame's offset along the axes). Two axes `theta` rad from parallel and
/// `L` apart have their common normal about `L / theta` from the joints, so a calibration
/// of an arm's parallel axes (skews of 1e-6 to 1e-3 rad, as a URDF fitted to a measured
/// robot writes them) has such rows; robid fits them from a URDF
/// (docs/urdf.md#fitting-the-dh-table). Their `b` and `d` may reach
/// [`MAX_CALIBRATED_LENGTH`], and their `alpha` may be nearer 0 or pi than
/// [`ANGLE_RESOLUTION`]: it is measured, not a rounded right angle.
///
/// ```
/// use robid_symbolic::robot::bounds::calibrated_pair;
/// // axes 0.4 m apart and 1e-6 rad from parallel: the common normal 4e5 m away
/// assert!(calibrated_pair(1e-6, -4e5, 4e5 + 0.05));
/// // a length typed in millimetres is no pair
/// assert!(!calibrated_pair(0.0, 0.0, 425.0e1));
/// assert!(!calibrated_pair(1e-6, 4e5, 4e5));
/// ```
pub fn calibrated_pair(alpha: f64, b: f64, d: f64) -> bool {
    let (s, c) = alpha.sin_cos();
    let kept = |x: f64| x.abs() <= MAX_CALIBRATED_LENGTH;
    s.abs() < 1e-2
        && (b.abs() > MAX_LENGTH || d.abs() > MAX_LENGTH)
        && kept(b)
        && kept(d)
        && (b + d * c).abs() <= MAX_LENGTH
        && (d * s).abs() <= MAX_LENGTH
}

/// Largest magnitude of a gravity component (m/s^2) (100 g).
pub const MAX_GRAVITY: f64 = 1e3;

/// Smallest magnitude of a gravity component that is not zero (m/s^2): a
/// tilt of 1e-4 rad under 9.81 m/s^2. Smaller components are not told apart
/// from zero by the regrouping; write 0.
pub const MIN_GRAVITY: f64 = 1e-3;

/// The interval in which the regrouping samples geometric symbols (all of
/// them, with or without a value), to find the base parameters.
pub const SYMBOL_SAMPLES: [f64; 2] = [0.2, 1.0];

/// Largest magnitude of a value with symbols, for symbols anywhere in
/// [`SYMBOL_SAMPLES`] (the regrouping samples them there).
pub const MAX_SAMPLED: f64 = 1e3;

/// Largest magnitude of a position limit (rad or m).
pub const MAX_POSITION: f64 = 1e3;

/// Largest length of a description (m) taken without a warning: arms and their links are
/// shorter; beyond it a length is likely millimetres read as metres (the UR5's `a = 425`),
/// read, with the warning ([`MAX_LENGTH`] is the error).
pub const MAX_ARM_LENGTH: f64 = 10.0;

/// Largest revolute position limit (rad) taken without a warning: a turn and a quarter
/// (multi-turn wrists reach ±450 degrees, 7.85 rad), and a hundredth more for rounding.
/// Beyond it a limit is likely degrees read as radians (`[-170, 170]`), which `robid
/// excite` would design within; a larger one is read, with the warning.
pub const MAX_TURNING: f64 = 2.5 * std::f64::consts::PI + 0.01;

/// Largest velocity limit (rad/s or m/s).
pub const MAX_VELOCITY: f64 = 1e4;

/// Largest acceleration limit (rad/s^2 or m/s^2).
pub const MAX_ACCELERATION: f64 = 1e6;

/// Largest torque or force limit (N m or N).
pub const MAX_TORQUE: f64 = 1e7;

/// Largest description text read (bytes) (the reference descriptions are
/// about 2 kB).
pub const MAX_DESCRIPTION_LEN: usize = 1 << 20;

/// Deepest nesting of a URDF's elements (`<robot>` is 1). A URDF nests five or six deep
/// (`<robot><link><visual><geometry><mesh>`), a simulator's extensions a few more; 149 000
/// nested elements took 22 s to read.
pub const MAX_URDF_DEPTH: usize = 64;

/// Most characters of a name: the robot's, or a URDF link's or joint's. Names are
/// quoted in messages and compared to find the nearest; a longer one is a mistake
/// (a pasted file, a generator gone wrong).
pub const MAX_NAME_LEN: usize = 256;
