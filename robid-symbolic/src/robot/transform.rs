//! A constant rigid transform written as URDF writes one: a translation `xyz` and fixed-axis
//! roll, pitch, yaw angles `rpy`, R = Rz(yaw) Ry(pitch) Rx(roll)
//! (docs/conventions.md#base-and-tool-frames). The description's `[base]` (frame 0 in the
//! world frame) and `[tool]` (the end-effector frame in frame n) are transforms.

use super::{Geometry, GeometryError};
use crate::dynamics::vector::Mat3;
use crate::expr::{Arena, Id};

/// A constant transform: translation `xyz` (m) then rotation `rpy` (rad), each value a
/// [`Geometry`] (a number, an exact angle such as `"pi/2"`, or a symbol expression). Plain
/// data, checked when a [`Robot`](super::Robot) is built with it.
#[derive(Clone, Debug, PartialEq)]
pub struct Transform {
    /// Translation x, y, z (m).
    pub xyz: [Geometry; 3],
    /// Roll, pitch, yaw (rad): R = Rz(yaw) Ry(pitch) Rx(roll).
    pub rpy: [Geometry; 3],
}

impl Default for Transform {
    fn default() -> Transform {
        Transform::identity()
    }
}

impl Transform {
    /// No translation, no rotation.
    pub fn identity() -> Transform {
        Transform {
            xyz: [Geometry::zero(), Geometry::zero(), Geometry::zero()],
            rpy: [Geometry::zero(), Geometry::zero(), Geometry::zero()],
        }
    }

    /// A transform of numbers; fails on a NaN or infinite value.
    ///
    /// ```
    /// use robid_symbolic::Transform;
    /// let t = Transform::numbers([0.0, 0.0, 0.1], [0.0, 0.0, 0.0])?;
    /// assert_eq!(t.xyz[2].as_str(), "0.1");
    /// assert!(Transform::numbers([f64::NAN, 0.0, 0.0], [0.0; 3]).is_err());
    /// # Ok::<(), robid_symbolic::robot::GeometryError>(())
    /// ```
    pub fn numbers(xyz: [f64; 3], rpy: [f64; 3]) -> Result<Transform, GeometryError> {
        let g = |v: [f64; 3]| -> Result<[Geometry; 3], GeometryError> {
            Ok([
                Geometry::number(v[0])?,
                Geometry::number(v[1])?,
                Geometry::number(v[2])?,
            ])
        };
        Ok(Transform {
            xyz: g(xyz)?,
            rpy: g(rpy)?,
        })
    }

    /// True when every rotation angle is exactly zero (the rotation is the identity).
    pub fn rotation_is_identity(&self) -> bool {
        self.rpy.iter().all(Geometry::is_zero)
    }

    /// The rotation R = Rz(yaw) Ry(pitch) Rx(roll) as expressions in `arena` (exact for
    /// multiples of pi/2, whose sines and cosines fold to 0 and +-1).
    pub(crate) fn rotation(&self, arena: &mut Arena) -> Mat3 {
        let [r, p, y] = [0, 1, 2].map(|i| self.rpy[i].to_expr(arena));
        let (sr, cr) = (arena.sin(r), arena.cos(r));
        let (sp, cp) = (arena.sin(p), arena.cos(p));
        let (sy, cy) = (arena.sin(y), arena.cos(y));
        let m = |arena: &mut Arena, f: &[Id]| arena.mul(f);
        // Rz(y) Ry(p) Rx(r), written out
        let r00 = m(arena, &[cy, cp]);
        let r01 = {
            let a = m(arena, &[cy, sp, sr]);
            let b = m(arena, &[sy, cr]);
            arena.sub(a, b)
        };
        let r02 = {
            let a = m(arena, &[cy, sp, cr]);
            let b = m(arena, &[sy, sr]);
            arena.add2(a, b)
        };
        let r10 = m(arena, &[sy, cp]);
        let r11 = {
            let a = m(arena, &[sy, sp, sr]);
            let b = m(arena, &[cy, cr]);
            arena.add2(a, b)
        };
        let r12 = {
            let a = m(arena, &[sy, sp, cr]);
            let b = m(arena, &[cy, sr]);
            arena.sub(a, b)
        };
        let r20 = arena.neg(sp);
        let r21 = m(arena, &[cp, sr]);
        let r22 = m(arena, &[cp, cr]);
        [[r00, r01, r02], [r10, r11, r12], [r20, r21, r22]]
    }
}
