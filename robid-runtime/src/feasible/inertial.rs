//! One link's inertial parameters in the physical form (mass, centre of mass,
//! inertia about the centre of mass) and the 4x4 pseudo-inertia matrix.
//!
//! With J the inertia about the frame origin, h = m c the first moment and
//! Sigma = 0.5 tr(J) I3 - J the second moment of the mass distribution, the
//! pseudo-inertia is P = [[Sigma, h], [h', m]]. A set of ten parameters comes
//! from a real mass distribution exactly when P is positive semidefinite
//! (Wensing, Kim, Slotine, "Linear matrix inequalities for physically consistent
//! inertial parameter identification: a statistical perspective on the mass
//! distribution", IEEE RA-L 3(1), pp. 60-67, 2018); P positive semidefinite means
//! m >= 0, the inertia about the centre of mass positive semidefinite and its principal
//! moments satisfying the triangle inequalities
//! (docs/experiments.md#physical-consistency-and-the-pseudo-inertia).

use nalgebra::{Matrix3, Matrix4, SymmetricEigen, Vector3};
use serde::{Deserialize, Serialize};

/// A link's mass, centre of mass (link frame) and inertia about the centre of mass
/// (axes of the link frame).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct LinkInertial {
    /// Mass, kg.
    pub mass: f64,
    /// Centre of mass in the link frame, m.
    pub com: [f64; 3],
    /// Inertia tensor about the centre of mass, kg m^2, row-major symmetric.
    pub inertia: [[f64; 3]; 3],
}

/// The inertia tensor about the frame origin from the ten standard values
/// `XX XY XZ YY YZ ZZ MX MY MZ M` (XY is the tensor's (1,2) entry).
pub fn inertia_at_origin(p: &[f64; 10]) -> Matrix3<f64> {
    Matrix3::new(p[0], p[1], p[2], p[1], p[3], p[4], p[2], p[4], p[5])
}

/// The pseudo-inertia matrix P = [[0.5 tr(J) I - J, h], [h', m]] of ten standard values.
pub fn pseudo_inertia(p: &[f64; 10]) -> Matrix4<f64> {
    let j = inertia_at_origin(p);
    let sigma = Matrix3::identity() * (0.5 * j.trace()) - j;
    let mut out = Matrix4::zeros();
    out.fixed_view_mut::<3, 3>(0, 0).copy_from(&sigma);
    for i in 0..3 {
        out[(i, 3)] = p[6 + i];
        out[(3, i)] = p[6 + i];
    }
    out[(3, 3)] = p[9];
    out
}

/// Iteration cap of the symmetric eigenvalue solver.
const EIGEN_ITERATIONS: usize = 1000;

/// The smallest eigenvalue of the pseudo-inertia: positive means physically consistent
/// with some margin. NaN when `p` is not finite (the solver is capped, so it cannot loop).
pub fn pseudo_inertia_min_eigenvalue(p: &[f64; 10]) -> f64 {
    if p.iter().any(|v| !v.is_finite()) {
        return f64::NAN;
    }
    SymmetricEigen::try_new(pseudo_inertia(p), f64::EPSILON, EIGEN_ITERATIONS)
        .map_or(f64::NAN, |e| e.eigenvalues.min())
}

impl LinkInertial {
    /// The physical form of ten standard values; `None` when the mass is not positive
    /// (the centre of mass is then undefined).
    pub fn from_standard(p: &[f64; 10]) -> Option<LinkInertial> {
        let m = p[9];
        if m.is_nan() || m <= 0.0 {
            return None;
        }
        let c = Vector3::new(p[6], p[7], p[8]) / m;
        let shift = (Matrix3::identity() * c.norm_squared() - c * c.transpose()) * m;
        let ic = inertia_at_origin(p) - shift;
        Some(LinkInertial {
            mass: m,
            com: [c.x, c.y, c.z],
            inertia: [
                [ic[(0, 0)], ic[(0, 1)], ic[(0, 2)]],
                [ic[(1, 0)], ic[(1, 1)], ic[(1, 2)]],
                [ic[(2, 0)], ic[(2, 1)], ic[(2, 2)]],
            ],
        })
    }

    /// The ten standard values (about the frame origin, parallel-axis theorem).
    pub fn to_standard(&self) -> [f64; 10] {
        let m = self.mass;
        let c = Vector3::from(self.com);
        let ic = Matrix3::from_fn(|i, k| self.inertia[i][k]);
        let j = ic + (Matrix3::identity() * c.norm_squared() - c * c.transpose()) * m;
        [
            j[(0, 0)],
            j[(0, 1)],
            j[(0, 2)],
            j[(1, 1)],
            j[(1, 2)],
            j[(2, 2)],
            m * c.x,
            m * c.y,
            m * c.z,
            m,
        ]
    }

    /// Principal moments of the inertia about the centre of mass, ascending (NaN when the
    /// inertia is not finite).
    pub fn principal_moments(&self) -> [f64; 3] {
        let ic = Matrix3::from_fn(|i, k| self.inertia[i][k]);
        if ic.iter().any(|v| !v.is_finite()) {
            return [f64::NAN; 3];
        }
        let Some(eig) = SymmetricEigen::try_new(ic, f64::EPSILON, EIGEN_ITERATIONS) else {
            return [f64::NAN; 3];
        };
        let mut e: Vec<f64> = eig.eigenvalues.iter().copied().collect();
        e.sort_by(f64::total_cmp);
        [e[0], e[1], e[2]]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_and_consistency() {
        let link = LinkInertial {
            mass: 2.0,
            com: [0.1, -0.2, 0.3],
            inertia: [[0.03, 0.001, 0.0], [0.001, 0.02, 0.002], [0.0, 0.002, 0.04]],
        };
        let p = link.to_standard();
        let back = LinkInertial::from_standard(&p).unwrap();
        for i in 0..3 {
            assert!((back.com[i] - link.com[i]).abs() < 1e-12);
            for k in 0..3 {
                assert!((back.inertia[i][k] - link.inertia[i][k]).abs() < 1e-12);
            }
        }
        assert!(pseudo_inertia_min_eigenvalue(&p) > 0.0);
    }

    #[test]
    fn triangle_inequality_violation_is_not_consistent() {
        // Principal moments 1, 1, 3 about the centre of mass: 1 + 1 < 3.
        let link = LinkInertial {
            mass: 1.0,
            com: [0.0; 3],
            inertia: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 3.0]],
        };
        assert!(pseudo_inertia_min_eigenvalue(&link.to_standard()) < 0.0);
    }
}
