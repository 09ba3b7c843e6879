//! Rigid transforms (rotation and translation) and the angle rule of the URDF reader:
//! a value within [`SNAP`] of a multiple of pi/2 is that multiple exactly, and its sine
//! and cosine are exact (docs/urdf.md#the-angle-rule).

use super::super::Pose;
use std::f64::consts::FRAC_PI_2;

/// A 3 x 3 matrix, row-major.
pub(super) type Mat3 = [[f64; 3]; 3];

/// How close (rad) an angle must be to a multiple of pi/2 to be that multiple: the rule
/// of descriptions (`bounds::RIGHT_ANGLE_SNAP`).
pub(super) const SNAP: f64 = super::super::bounds::RIGHT_ANGLE_SNAP;

/// The multiple k of pi/2 that `angle` is within [`SNAP`] of, if any.
pub(super) fn right_angle_multiple(angle: f64) -> Option<i64> {
    let k = (angle / FRAC_PI_2).round();
    ((angle - k * FRAC_PI_2).abs() <= SNAP && k.abs() < 1e6).then_some(k as i64)
}

/// How close (rad) an `rpy` value must be to a multiple of pi/2 to be taken as that
/// multiple with a warning (docs/urdf.md#the-angle-rule): right angles computed from pi
/// printed to 8 decimals (xacro's `pi = 3.14159265` in ROS-Industrial's UR files gives
/// `1.570796325`, 1.8e-9 rad short) are within 7.2e-9 rad up to 2 pi. A real skew this
/// small is a thousand times below what a calibration resolves (the 1e-5 rad of
/// `bounds::ANGLE_RESOLUTION`), while 2e-8 rad already is not such a rounding.
pub(super) const NEAR_RIGHT_ANGLE: f64 = 1e-8;

/// The multiple k of pi/2 within [`NEAR_RIGHT_ANGLE`] of `angle` (|k| at most 4) but not
/// within [`SNAP`], and the distance to it.
pub(super) fn near_right_angle(angle: f64) -> Option<(i64, f64)> {
    let k = (angle / FRAC_PI_2).round();
    let off = (angle - k * FRAC_PI_2).abs();
    (off > SNAP && off <= NEAR_RIGHT_ANGLE && k.abs() <= 4.0).then_some((k as i64, off))
}

/// Sine and cosine, exact (0, ±1) for an angle within [`SNAP`] of a multiple of pi/2.
pub(super) fn sin_cos(angle: f64) -> (f64, f64) {
    match right_angle_multiple(angle) {
        Some(k) => match k.rem_euclid(4) {
            0 => (0.0, 1.0),
            1 => (1.0, 0.0),
            2 => (0.0, -1.0),
            _ => (-1.0, 0.0),
        },
        None => angle.sin_cos(),
    }
}

/// A rigid transform: x -> r x + p.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Rigid {
    /// Rotation.
    pub(super) r: Mat3,
    /// Translation.
    pub(super) p: [f64; 3],
}

pub(super) const I3: Mat3 = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

impl Rigid {
    pub(super) const IDENTITY: Rigid = Rigid { r: I3, p: [0.0; 3] };

    /// A URDF `<origin xyz rpy>`: R = Rz(yaw) Ry(pitch) Rx(roll), sines and cosines by
    /// [`sin_cos`].
    pub(super) fn from_xyz_rpy(xyz: [f64; 3], rpy: [f64; 3]) -> Rigid {
        let (sr, cr) = sin_cos(rpy[0]);
        let (sp, cp) = sin_cos(rpy[1]);
        let (sy, cy) = sin_cos(rpy[2]);
        let r = [
            [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
            [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
            [-sp, cp * sr, cp * cr],
        ];
        Rigid { r, p: xyz }
    }

    /// `self` then `other` (`self * other`).
    pub(super) fn then(&self, other: &Rigid) -> Rigid {
        Rigid {
            r: mul(&self.r, &other.r),
            p: add(self.apply_vector(other.p), self.p),
        }
    }

    /// The inverse transform.
    pub(super) fn inverse(&self) -> Rigid {
        let rt = transpose(&self.r);
        Rigid {
            r: rt,
            p: scale(mat_vec(&rt, self.p), -1.0),
        }
    }

    /// The rotation applied to a vector.
    pub(super) fn apply_vector(&self, v: [f64; 3]) -> [f64; 3] {
        mat_vec(&self.r, v)
    }

    /// The 4 x 4 homogeneous matrix.
    pub(super) fn pose(&self) -> Pose {
        let mut m = [[0.0, 0.0, 0.0, 1.0]; 4];
        for (row, (r, p)) in m.iter_mut().zip(self.r.iter().zip(self.p)) {
            *row = [r[0], r[1], r[2], p];
        }
        m
    }

    /// From a 4 x 4 homogeneous matrix.
    pub(super) fn from_pose(m: &Pose) -> Rigid {
        Rigid {
            r: std::array::from_fn(|i| [m[i][0], m[i][1], m[i][2]]),
            p: [m[0][3], m[1][3], m[2][3]],
        }
    }

    /// A rotation about unit axis `u` by `angle` (Rodrigues), no translation; sine and
    /// cosine by [`sin_cos`].
    pub(super) fn rotation(u: [f64; 3], angle: f64) -> Rigid {
        let (s, c) = sin_cos(angle);
        let k = 1.0 - c;
        let [x, y, z] = u;
        Rigid {
            r: [
                [c + x * x * k, x * y * k - z * s, x * z * k + y * s],
                [y * x * k + z * s, c + y * y * k, y * z * k - x * s],
                [z * x * k - y * s, z * y * k + x * s, c + z * z * k],
            ],
            p: [0.0; 3],
        }
    }

    /// A translation by `v`.
    pub(super) fn translation(v: [f64; 3]) -> Rigid {
        Rigid { r: I3, p: v }
    }
}

pub(super) fn mul(a: &Mat3, b: &Mat3) -> Mat3 {
    std::array::from_fn(|i| std::array::from_fn(|k| (0..3).map(|m| a[i][m] * b[m][k]).sum()))
}

pub(super) fn transpose(a: &Mat3) -> Mat3 {
    std::array::from_fn(|i| std::array::from_fn(|k| a[k][i]))
}

pub(super) fn mat_vec(a: &Mat3, v: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|i| a[i][0] * v[0] + a[i][1] * v[1] + a[i][2] * v[2])
}

pub(super) fn add(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

pub(super) fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

pub(super) fn scale(a: [f64; 3], s: f64) -> [f64; 3] {
    [a[0] * s, a[1] * s, a[2] * s]
}

pub(super) fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub(super) fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

pub(super) fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    #[allow(clippy::approx_constant)] // the printed values of files
    fn printed_right_angles_snap_and_coarser_ones_do_not() {
        assert_eq!(right_angle_multiple(1.57079632679), Some(1));
        assert_eq!(right_angle_multiple(-3.14159265359), Some(-2));
        assert_eq!(right_angle_multiple(1.57079), None);
        assert_eq!(sin_cos(1.57079), 1.57079_f64.sin_cos());
        assert_eq!(sin_cos(3.14159265359), (0.0, -1.0));
        assert_eq!(sin_cos(-1.5707963267948966), (-1.0, 0.0));
        // within 1e-8 rad: the multiple and how far; within 1e-9 or beyond 1e-8: none
        let (k, off) = near_right_angle(1.570796325).unwrap();
        assert_eq!(k, 1);
        assert!((off - 1.7949e-9).abs() < 1e-13, "{off}");
        assert_eq!(near_right_angle(-3.14159265).map(|n| n.0), Some(-2));
        assert_eq!(near_right_angle(4e-9), Some((0, 4e-9)));
        assert_eq!(near_right_angle(1.57079632679), None);
        assert_eq!(near_right_angle(1.5707963468), None);
        assert_eq!(near_right_angle(10.0 * FRAC_PI_2 + 5e-9), None);
        let r = Rigid::from_xyz_rpy([0.0; 3], [FRAC_PI_2, 0.0, 0.0]);
        assert_eq!(r.r, [[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]]);
    }
}
