//! 3-vectors and 3x3 matrices of expressions.

use crate::expr::{Arena, Id};

/// A 3-vector of expressions.
pub type Vec3 = [Id; 3];
/// A 3x3 matrix of expressions, row-major.
pub type Mat3 = [[Id; 3]; 3];

/// The zero vector.
pub fn zero(arena: &mut Arena) -> Vec3 {
    let z = arena.zero();
    [z; 3]
}

/// a + b.
pub fn add(arena: &mut Arena, a: Vec3, b: Vec3) -> Vec3 {
    [0, 1, 2].map(|i| arena.add2(a[i], b[i]))
}

/// Sum of several vectors.
pub fn sum(arena: &mut Arena, vectors: &[Vec3]) -> Vec3 {
    [0, 1, 2].map(|i| {
        let terms: Vec<Id> = vectors.iter().map(|v| v[i]).collect();
        arena.add(&terms)
    })
}

/// s * a for an expression s.
pub fn scale(arena: &mut Arena, s: Id, a: Vec3) -> Vec3 {
    a.map(|x| arena.mul2(s, x))
}

/// a x b.
pub fn cross(arena: &mut Arena, a: Vec3, b: Vec3) -> Vec3 {
    let mut component = |i: usize, j: usize| {
        let p = arena.mul2(a[i], b[j]);
        let q = arena.mul2(a[j], b[i]);
        arena.sub(p, q)
    };
    [component(1, 2), component(2, 0), component(0, 1)]
}

/// a . b.
pub fn dot(arena: &mut Arena, a: Vec3, b: Vec3) -> Id {
    let terms: Vec<Id> = (0..3).map(|i| arena.mul2(a[i], b[i])).collect();
    arena.add(&terms)
}

/// R a.
pub fn mat_vec(arena: &mut Arena, r: &Mat3, a: Vec3) -> Vec3 {
    [0, 1, 2].map(|i| dot(arena, r[i], a))
}

/// R' a.
pub fn mat_t_vec(arena: &mut Arena, r: &Mat3, a: Vec3) -> Vec3 {
    let t = transpose(r);
    mat_vec(arena, &t, a)
}

/// R'.
pub fn transpose(r: &Mat3) -> Mat3 {
    [0, 1, 2].map(|i| [r[0][i], r[1][i], r[2][i]])
}

/// A B.
pub fn mat_mul(arena: &mut Arena, a: &Mat3, b: &Mat3) -> Mat3 {
    let bt = transpose(b);
    [0, 1, 2].map(|i| [0, 1, 2].map(|j| dot(arena, a[i], bt[j])))
}

/// The symmetric matrix of inertia entries [XX, XY, XZ, YY, YZ, ZZ].
pub fn symmetric(j: &[Id; 6]) -> Mat3 {
    [[j[0], j[1], j[2]], [j[1], j[3], j[4]], [j[2], j[4], j[5]]]
}

/// Rx(alpha) Rz(theta) from the sine and cosine of each angle.
pub fn rot_x_rot_z(arena: &mut Arena, sa: Id, ca: Id, st: Id, ct: Id) -> Mat3 {
    let zero = arena.zero();
    let nst = arena.neg(st);
    let nsa = arena.neg(sa);
    [
        [ct, nst, zero],
        [arena.mul2(ca, st), arena.mul2(ca, ct), nsa],
        [arena.mul2(sa, st), arena.mul2(sa, ct), ca],
    ]
}

/// Rz(angle).
pub fn rot_z(arena: &mut Arena, angle: Id) -> Mat3 {
    let (s, c) = (arena.sin(angle), arena.cos(angle));
    let zero = arena.zero();
    let one = arena.one();
    let ns = arena.neg(s);
    [[c, ns, zero], [s, c, zero], [zero, zero, one]]
}
