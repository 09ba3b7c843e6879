//! From the joint axes of a chain to a modified-DH table (docs/urdf.md#fitting-the-dh-table).
//!
//! Frame j (Khalil-Kleinfinger / Craig) has z_j along joint j's axis with its sign and x_j
//! along the common normal from axis j to axis j+1; frame 0 is frame 1 at q = 0 and frame
//! n keeps x_(n-1)'s direction. Any serial chain of revolute and prismatic joints has such
//! a table: consecutive frames are Rx(alpha_j) Tx(a_j) Rz(theta_j) Tz(d_j). Where the
//! common normal's foot lies farther from the joint than the chain is long (nearly parallel
//! axes), the origin stays near the joint and the next row's Khalil-Kleinfinger `b` goes
//! back to the foot.

use super::rigid::{Rigid, add, cross, dot, norm, right_angle_multiple, scale, sub};
use std::f64::consts::FRAC_PI_2;

/// Below this sine of the angle between two axes (the angle rule's 1e-9 rad,
/// docs/urdf.md#the-angle-rule), they are parallel.
pub(super) const PARALLEL: f64 = 1e-9;

/// Shorter lengths (m) are zero: axes closer than this meet (the rule of descriptions,
/// `bounds::LENGTH_SNAP`).
pub(super) const ZERO_LENGTH: f64 = super::super::bounds::LENGTH_SNAP;

/// Largest angle (rad, as the sine of it) between two consecutive joint axes, not parallel
/// within [`PARALLEL`], that counts as nearly parallel: such a pair's frame keeps its origin
/// near its joint when the common normal's foot is farther than the chain is long, and is
/// named as the cause of a DH value robid refuses at either joint. Axes `theta` from
/// parallel and a distance `L` apart have their common normal about `L / theta` from the
/// joints, beyond the 1 km of a DH length for `L` up to 10 m; axes farther from parallel
/// have their feet within `1 / theta` (100) times the chain's length of the joints, where
/// the link parameters keep their digits, and are fitted at the feet.
pub(super) const NEAR_PARALLEL: f64 = 1e-2;

/// A foot of a common normal this close (m) to its joint is never moved, whatever the
/// chain's length (`bounds::MIN_LENGTH`: a chain whose joints' points coincide has its feet
/// there, up to rounding).
const NEAR: f64 = 1e-6;

/// One joint axis at q = 0: unit direction and a point, in the base link frame.
#[derive(Clone, Copy, Debug)]
pub(super) struct Axis {
    pub(super) direction: [f64; 3],
    pub(super) point: [f64; 3],
    /// The x axis of the URDF joint frame (to choose among equally good DH frames).
    pub(super) hint: [f64; 3],
}

/// The fitted table: frames 0..n in the base link frame at q = 0 and the rows
/// `[alpha, a, d, theta, b]` of joints 1..n (Khalil-Kleinfinger's `b` along z_(j-1) in
/// front of the DH row, nonzero only after a frame moved off the common normal's foot),
/// angles within the angle rule of k pi/2 made exact, lengths below [`ZERO_LENGTH`] made 0.
pub(super) struct Fit {
    pub(super) frames: Vec<Rigid>,
    pub(super) rows: Vec<[f64; 5]>,
    /// How far (m) the foot of the common normal from axis j to axis j+1 lies from joint
    /// j's own point (its URDF joint origin), for joints 1..n (0 for the last joint and
    /// parallel axes): far only where two consecutive axes are nearly parallel. Row j+1
    /// passes through that foot (its `b` and `d` are about that long) whether or not frame
    /// j's origin is there.
    pub(super) reach: Vec<f64>,
}

fn unit(v: [f64; 3]) -> [f64; 3] {
    scale(v, 1.0 / norm(v))
}

/// The part of `v` perpendicular to unit `z`.
fn perpendicular(v: [f64; 3], z: [f64; 3]) -> [f64; 3] {
    sub(v, scale(z, dot(v, z)))
}

/// The foot of `point` on the line through `on` along unit `z`.
fn project(point: [f64; 3], on: [f64; 3], z: [f64; 3]) -> [f64; 3] {
    add(on, scale(z, dot(sub(point, on), z)))
}

/// A unit vector perpendicular to unit `z`, as close as possible to `hint`.
fn perpendicular_towards(z: [f64; 3], hint: [f64; 3]) -> [f64; 3] {
    for candidate in [hint, cross(z, hint), [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]] {
        let p = perpendicular(candidate, z);
        if norm(p) > 1e-6 {
            return unit(p);
        }
    }
    unit(perpendicular([0.0, 0.0, 1.0], z))
}

fn frame(x: [f64; 3], z: [f64; 3], origin: [f64; 3]) -> Rigid {
    let y = cross(z, x);
    Rigid {
        r: std::array::from_fn(|i| [x[i], y[i], z[i]]),
        p: origin,
    }
}

/// The DH frames and table of a chain with these axes (at least one).
pub(super) fn fit(axes: &[Axis]) -> Fit {
    let n = axes.len();
    let size = chain_size(axes);
    let mut origins: Vec<[f64; 3]> = Vec::with_capacity(n);
    let mut xs: Vec<[f64; 3]> = Vec::with_capacity(n);
    let mut moved = vec![false; n];
    let mut reach = vec![0.0; n];
    for j in 0..n {
        let z = axes[j].direction;
        let previous_x = xs.last().copied();
        // where the previous x line meets this axis (first axis: the base origin's foot)
        let foot = project(
            origins.last().copied().unwrap_or([0.0; 3]),
            axes[j].point,
            z,
        );
        let keep = |x: Option<[f64; 3]>| match x {
            Some(x) => unit(perpendicular(x, z)),
            None => perpendicular_towards(z, axes[j].hint),
        };
        let (origin, x) = match axes.get(j + 1) {
            None => (foot, keep(previous_x)),
            Some(next) => {
                let w = next.direction;
                let normal = cross(z, w);
                let between = sub(next.point, axes[j].point);
                if norm(normal) <= PARALLEL {
                    let to_next = perpendicular(sub(next.point, foot), z);
                    if norm(to_next) > ZERO_LENGTH {
                        (foot, unit(to_next))
                    } else {
                        (foot, keep(previous_x))
                    }
                } else {
                    let nn = dot(normal, normal);
                    let s = dot(cross(between, w), normal) / nn;
                    let t = dot(cross(between, z), normal) / nn;
                    let here = add(axes[j].point, scale(z, s));
                    let there = add(next.point, scale(w, t));
                    let gap = sub(there, here);
                    reach[j] = norm(sub(here, axes[j].point));
                    // the feet lie |s| and |t| from the joints' points, and their
                    // difference keeps only that many ulps: a gap within them is axes that
                    // meet (nearly parallel ones far away), not a direction
                    let rounding = 16.0
                        * f64::EPSILON
                        * (s.abs() + t.abs() + norm(axes[j].point) + norm(next.point));
                    let x = if norm(gap) > ZERO_LENGTH.max(rounding) {
                        unit(gap)
                    } else {
                        let x = unit(normal);
                        let reference = previous_x.unwrap_or(axes[j].hint);
                        if dot(x, reference) < 0.0 {
                            scale(x, -1.0)
                        } else {
                            x
                        }
                    };
                    if norm(normal) < NEAR_PARALLEL && reach[j] > size.max(NEAR) {
                        // nearly parallel axes: the foot is about their distance over
                        // their angle away; keep the origin near the joint
                        moved[j] = true;
                        let near = if norm(sub(foot, axes[j].point)) <= size {
                            foot
                        } else {
                            axes[j].point
                        };
                        (near, x)
                    } else {
                        (here, x)
                    }
                }
            }
        };
        origins.push(origin);
        xs.push(x);
    }
    let mut frames = Vec::with_capacity(n + 1);
    frames.push(frame(xs[0], axes[0].direction, origins[0]));
    for j in 0..n {
        frames.push(frame(xs[j], axes[j].direction, origins[j]));
    }
    let rows = (1..=n)
        .map(|j| {
            let t = frames[j - 1].inverse().then(&frames[j]);
            if j >= 2 && moved[j - 2] {
                general_row(&t, reach[j - 2])
            } else {
                let [alpha, a, d, theta] = row(&t);
                [alpha, a, d, theta, 0.0]
            }
        })
        .collect();
    Fit {
        frames,
        rows,
        reach,
    }
}

/// The length of the chain: the sum of the distances between consecutive joints' points
/// (m). A frame origin farther than this from its joint is moved to it.
fn chain_size(axes: &[Axis]) -> f64 {
    axes.windows(2)
        .map(|pair| norm(sub(pair[1].point, pair[0].point)))
        .sum()
}

/// `[alpha, a, d, theta, b]` of Tz(b) Rx(alpha) Tx(a) Rz(theta) Tz(d) = `t`, for a frame
/// j-1 whose origin was moved off the foot of the common normal: `b` takes it back there
/// along z_(j-1), `d` comes from the foot on axis j to frame j's origin. The feet lie
/// `reach` (m) from the joints, and `a`, the common normal's length, keeps only about 2^-52
/// times that: below 16 times that it is the 0 of axes that meet.
fn general_row(t: &Rigid, reach: f64) -> [f64; 5] {
    let alpha = snap(f64::atan2(-t.r[1][2], t.r[2][2]));
    let theta = snap(f64::atan2(-t.r[0][1], t.r[0][0]));
    let (s, c) = super::rigid::sin_cos(alpha);
    let a = t.p[0];
    if s == 0.0 {
        // parallel after all (within the angle rule): all of it along z
        return [alpha, zero_small(a), zero_small(t.p[2] * c), theta, 0.0];
    }
    let d = -t.p[1] / s;
    let b = t.p[2] - c * d;
    let a = if a.abs() < 16.0 * f64::EPSILON * reach {
        0.0
    } else {
        zero_small(a)
    };
    [alpha, a, zero_small(d), theta, zero_small(b)]
}

/// `[alpha, a, d, theta]` of Rx(alpha) Tx(a) Rz(theta) Tz(d) = `t`.
fn row(t: &Rigid) -> [f64; 4] {
    let alpha = snap(f64::atan2(-t.r[1][2], t.r[2][2]));
    let theta = snap(f64::atan2(-t.r[0][1], t.r[0][0]));
    let (s, c) = super::rigid::sin_cos(alpha);
    let a = t.p[0];
    let d = -t.p[1] * s + t.p[2] * c;
    [alpha, zero_small(a), zero_small(d), theta]
}

/// Exactly k pi/2 within the angle rule; -pi becomes pi.
fn snap(angle: f64) -> f64 {
    match right_angle_multiple(angle) {
        Some(-2) => 2.0 * FRAC_PI_2,
        Some(k) => k as f64 * FRAC_PI_2,
        None => angle,
    }
}

fn zero_small(length: f64) -> f64 {
    if length.abs() < ZERO_LENGTH {
        0.0
    } else {
        length
    }
}

/// The exact text of an angle that is a multiple of pi/2 within the angle rule.
pub(super) fn angle_text(angle: f64) -> Option<&'static str> {
    Some(match right_angle_multiple(angle)? {
        0 => "0",
        1 => "pi/2",
        -1 => "-pi/2",
        2 | -2 => "pi",
        3 => "3*pi/2",
        -3 => "-3*pi/2",
        4 => "2*pi",
        -4 => "-2*pi",
        _ => return None,
    })
}
