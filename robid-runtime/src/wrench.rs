//! The wrench a link needs, linear in its ten standard parameters:
//! `w = A(omega, omegadot, vdot, g) phi` (docs/dynamics.md#link-wrench-matrix).
//!
//! `phi` is `XX XY XZ YY YZ ZZ MX MY MZ M` in the link frame about its origin
//! (docs/conventions.md#standard-parameters); the wrench is the force, then the moment
//! about the frame origin, in the link frame:
//!
//! ```text
//! f = M (vdot - g) + omegadot x MS + omega x (omega x MS)
//! n = J omegadot + omega x (J omega) + MS x (vdot - g)
//! ```
//!
//! This is eq. 2 of the post "Dynamic modelling of robots: parameters identification (I)"
//! (docs/references.md#dynamic-modelling-of-robots-i) with its
//! block rows swapped (force first) and its columns in robid's order; Atkeson, An and
//! Hollerbach 1986 (docs/references.md#atkeson-an-and-hollerbach-1986) use it for payloads.
//! Pure arithmetic on `[f64; 3]`, so it compiles for `no_std` firmware.

/// Rows of the matrix: force x, y, z, then moment x, y, z.
pub const WRENCH_ROWS: usize = 6;
/// Columns of the matrix: the ten standard parameters of one link.
pub const LINK_PARAMETERS: usize = 10;

/// The 6x10 matrix `A` with `[f; n] = A phi` for a link moving with angular velocity
/// `omega`, angular acceleration `omegadot` and frame-origin acceleration `vdot` under
/// gravity `gravity`, all four in the link frame.
///
/// `vdot` is the kinematic acceleration of the frame origin (no gravity in it): the link
/// feels `vdot - gravity`, as with robid's `vd_0 = -g` (docs/dynamics.md#forward-recursion).
/// Row-major: `A[r][k]` is the row-`r` wrench component per unit of parameter `k`.
///
/// ```
/// use robid_runtime::wrench::{apply, wrench_matrix};
/// // A link at rest under gravity: 2 kg with its centre of mass 0.1 m along x.
/// let phi = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.2, 0.0, 0.0, 2.0];
/// let a = wrench_matrix(&[0.0; 3], &[0.0; 3], &[0.0; 3], &[0.0, 0.0, -9.81]);
/// let w = apply(&a, &phi);
/// // It must be held up by 2 x 9.81 N, with a moment about -y of 0.2 x 9.81 N m.
/// assert!((w[2] - 19.62).abs() < 1e-12);
/// assert!((w[4] + 1.962).abs() < 1e-12);
/// ```
pub fn wrench_matrix(
    omega: &[f64; 3],
    omegadot: &[f64; 3],
    vdot: &[f64; 3],
    gravity: &[f64; 3],
) -> [[f64; LINK_PARAMETERS]; WRENCH_ROWS] {
    let a = [
        vdot[0] - gravity[0],
        vdot[1] - gravity[1],
        vdot[2] - gravity[2],
    ];
    // Khalil's U = skew(omegadot) + skew(omega)^2: the force per unit first moment.
    let sw = skew(omega);
    let sw2 = mul33(&sw, &sw);
    let swd = skew(omegadot);
    // J x = L(x) l(J) (the post's eq. 3), so the inertia columns are
    // L(omegadot) + skew(omega) L(omega).
    let lwd = l_operator(omegadot);
    let lw = l_operator(omega);
    let mut out = [[0.0; LINK_PARAMETERS]; WRENCH_ROWS];
    for r in 0..3 {
        for k in 0..3 {
            out[r][6 + k] = swd[r][k] + sw2[r][k];
            // MS x a = -skew(a) MS.
            out[3 + r][6 + k] = -skew(&a)[r][k];
        }
        out[r][9] = a[r];
        for k in 0..6 {
            let gyro: f64 = (0..3).map(|i| sw[r][i] * lw[i][k]).sum();
            out[3 + r][k] = lwd[r][k] + gyro;
        }
    }
    out
}

/// The wrench `A phi` (force, then moment about the frame origin).
pub fn apply(
    a: &[[f64; LINK_PARAMETERS]; WRENCH_ROWS],
    phi: &[f64; LINK_PARAMETERS],
) -> [f64; WRENCH_ROWS] {
    let mut w = [0.0; WRENCH_ROWS];
    for (wr, row) in w.iter_mut().zip(a) {
        *wr = row.iter().zip(phi).map(|(x, p)| x * p).sum();
    }
    w
}

/// `skew(v) x = v x x`.
fn skew(v: &[f64; 3]) -> [[f64; 3]; 3] {
    [[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]]
}

fn mul33(a: &[[f64; 3]; 3], b: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    let mut c = [[0.0; 3]; 3];
    for (i, row) in c.iter_mut().enumerate() {
        for (k, x) in row.iter_mut().enumerate() {
            *x = (0..3).map(|j| a[i][j] * b[j][k]).sum();
        }
    }
    c
}

/// `L(x)` with `J x = L(x) (XX, XY, XZ, YY, YZ, ZZ)` for the symmetric tensor `J`.
fn l_operator(x: &[f64; 3]) -> [[f64; 6]; 3] {
    [
        [x[0], x[1], x[2], 0.0, 0.0, 0.0],
        [0.0, x[0], 0.0, x[1], x[2], 0.0],
        [0.0, 0.0, x[0], 0.0, x[1], x[2]],
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_mass_feels_the_specific_force() {
        let a = wrench_matrix(&[0.0; 3], &[0.0; 3], &[1.0, 2.0, 3.0], &[0.0, 0.0, -9.81]);
        assert_eq!([a[0][9], a[1][9], a[2][9]], [1.0, 2.0, 12.81]);
        // A point mass at the origin has no moment about it.
        assert_eq!([a[3][9], a[4][9], a[5][9]], [0.0; 3]);
    }
}
