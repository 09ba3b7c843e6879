//! The Cholesky parametrisation of a link's pseudo-inertia: ten unconstrained numbers
//! theta = (u, d1, d2, d3, s12, s23, s13, t1, t2, t3) give
//!
//! ```text
//! P = margin I + U U',   U = [[d1, s12, s13, t1],
//!                             [0,  d2,  s23, t2],
//!                             [0,  0,   d3,  t3],
//!                             [0,  0,   0,   u ]]
//! ```
//!
//! so every theta is a physically consistent link (P >= margin I) and every consistent
//! link has a theta, the singular ones (P = margin I on some direction) at finite theta.
//! It is the log-Cholesky parametrisation of Rucker and Wensing ("Smooth parameterization
//! of rigid-body inertia", IEEE RA-L 7(2), 2022; docs/experiments.md#feasible-parameters)
//! without the exponentials on the diagonal, which put the boundary at infinity. The ten
//! standard parameters are linear in P (`m = P44`, `h = P[0..3, 3]`, `J = tr(S) I - S`
//! with `S = P[0..3, 0..3]`) and so quadratic in theta.

use nalgebra::{Matrix4, SymmetricEigen};

use super::inertial::pseudo_inertia;

/// Parameters per link.
pub(super) const PER_LINK: usize = 10;

/// The factor U of `theta` (upper triangular, entries as they are).
fn factor(theta: &[f64; PER_LINK]) -> Matrix4<f64> {
    let [u, d1, d2, d3, s12, s23, s13, t1, t2, t3] = *theta;
    Matrix4::new(
        d1, s12, s13, t1, 0.0, d2, s23, t2, 0.0, 0.0, d3, t3, 0.0, 0.0, 0.0, u,
    )
}

/// The ten standard values `XX XY XZ YY YZ ZZ MX MY MZ M` of a pseudo-inertia (linear).
fn standard_of_matrix(p: &Matrix4<f64>) -> [f64; PER_LINK] {
    let s = |i: usize, k: usize| p[(i, k)];
    [
        s(1, 1) + s(2, 2),
        -s(0, 1),
        -s(0, 2),
        s(0, 0) + s(2, 2),
        -s(1, 2),
        s(0, 0) + s(1, 1),
        s(0, 3),
        s(1, 3),
        s(2, 3),
        s(3, 3),
    ]
}

/// The standard values of `theta` with P >= `margin` I.
pub(super) fn standard_of(theta: &[f64; PER_LINK], margin: f64) -> [f64; PER_LINK] {
    let u = factor(theta);
    let p = u * u.transpose() + Matrix4::identity() * margin;
    standard_of_matrix(&p)
}

/// The entry (i, k) of U behind each variable t: `(t, i, k)`.
pub(super) const ENTRIES: [(usize, usize, usize); PER_LINK] = [
    (0, 3, 3),
    (1, 0, 0),
    (2, 1, 1),
    (3, 2, 2),
    (4, 0, 1),
    (5, 1, 2),
    (6, 0, 2),
    (7, 0, 3),
    (8, 1, 3),
    (9, 2, 3),
];

/// The second derivative of `sum_s g[s] standard_s(U U')` by U_ik and U_ml (zero unless
/// k == l, then the functional at E_im + E_mi): constant, as P is quadratic in U.
pub(super) fn second_derivative(g: &[f64; PER_LINK], i: usize, m: usize) -> f64 {
    let e = Matrix4::from_fn(|a, b| {
        f64::from(u8::from(a == i && b == m)) + f64::from(u8::from(a == m && b == i))
    });
    standard_of_matrix(&e)
        .iter()
        .zip(g)
        .map(|(d, w)| d * w)
        .sum()
}

/// d standard / d theta: `out[s][t]` is the derivative of standard value `s` by `theta[t]`.
pub(super) fn jacobian(theta: &[f64; PER_LINK]) -> [[f64; PER_LINK]; PER_LINK] {
    let v = factor(theta);
    let mut out = [[0.0; PER_LINK]; PER_LINK];
    for (t, i, k) in ENTRIES {
        // d(U U') = E_ik U' + U E_ki
        let dp = Matrix4::from_fn(|a, b| {
            let left = if a == i { v[(b, k)] } else { 0.0 };
            let right = if b == i { v[(a, k)] } else { 0.0 };
            left + right
        });
        for (s, d) in standard_of_matrix(&dp).into_iter().enumerate() {
            out[s][t] = d;
        }
    }
    out
}

/// The theta of ten standard values whose pseudo-inertia exceeds `margin` I; `None` when
/// it does not (the link is not strictly inside the consistent set).
pub(super) fn theta_of(standard: &[f64; PER_LINK], margin: f64) -> Option<[f64; PER_LINK]> {
    let a = pseudo_inertia(standard) - Matrix4::identity() * margin;
    if a.iter().any(|v| !v.is_finite()) {
        return None;
    }
    // U U' = A with U upper triangular: the Cholesky factor of A with rows and columns
    // reversed, reversed back
    let flip = |m: &Matrix4<f64>| Matrix4::from_fn(|i, k| m[(3 - i, 3 - k)]);
    let l = flip(&a).cholesky()?.l();
    let u = flip(&l);
    let theta: [f64; PER_LINK] = [
        u[(3, 3)],
        u[(0, 0)],
        u[(1, 1)],
        u[(2, 2)],
        u[(0, 1)],
        u[(1, 2)],
        u[(0, 2)],
        u[(0, 3)],
        u[(1, 3)],
        u[(2, 3)],
    ];
    theta.iter().all(|x| x.is_finite()).then_some(theta)
}

/// Ten standard values moved, if needed, just inside the consistent set: the pseudo-inertia's
/// eigenvalues are raised to at least `floor` (a starting point for the solver).
pub(super) fn inside(standard: &[f64; PER_LINK], floor: f64) -> [f64; PER_LINK] {
    let p = pseudo_inertia(standard);
    let Some(e) = SymmetricEigen::try_new(p, f64::EPSILON, 1000) else {
        return *standard;
    };
    if e.eigenvalues.min() >= floor {
        return *standard;
    }
    let raised = e.eigenvalues.map(|v| v.max(floor));
    let p = e.eigenvectors * Matrix4::from_diagonal(&raised) * e.eigenvectors.transpose();
    standard_of_matrix(&p)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::feasible::{LinkInertial, pseudo_inertia_min_eigenvalue};

    fn link() -> [f64; PER_LINK] {
        LinkInertial {
            mass: 2.5,
            com: [0.1, -0.05, 0.2],
            inertia: [
                [0.03, 0.002, -0.001],
                [0.002, 0.025, 0.003],
                [-0.001, 0.003, 0.02],
            ],
        }
        .to_standard()
    }

    #[test]
    fn round_trip_through_theta() {
        let p = link();
        for margin in [0.0, 1e-6] {
            let theta = theta_of(&p, margin).unwrap();
            let back = standard_of(&theta, margin);
            for (a, b) in p.iter().zip(back) {
                assert!((a - b).abs() < 1e-12 * (1.0 + a.abs()), "{a} vs {b}");
            }
        }
        // not strictly consistent: no theta
        let mut bad = p;
        bad[9] = -1.0;
        assert!(theta_of(&bad, 0.0).is_none());
    }

    #[test]
    fn every_theta_is_consistent() {
        let mut rng = crate::rng::Rng::new(7);
        for _ in 0..200 {
            let theta: [f64; PER_LINK] = std::array::from_fn(|_| rng.uniform(-3.0, 3.0));
            let p = standard_of(&theta, 1e-6);
            assert!(
                pseudo_inertia_min_eigenvalue(&p) >= 1e-6 * (1.0 - 1e-6),
                "{p:?}"
            );
        }
    }

    /// The analytic Jacobian equals central differences (error O(h^2), h = 1e-6).
    #[test]
    fn jacobian_matches_finite_differences() {
        let mut rng = crate::rng::Rng::new(11);
        for _ in 0..20 {
            let theta: [f64; PER_LINK] = std::array::from_fn(|_| rng.uniform(-1.5, 1.5));
            let j = jacobian(&theta);
            for t in 0..PER_LINK {
                let h = 1e-6;
                let (mut up, mut down) = (theta, theta);
                up[t] += h;
                down[t] -= h;
                let (a, b) = (standard_of(&up, 0.0), standard_of(&down, 0.0));
                for s in 0..PER_LINK {
                    let fd = (a[s] - b[s]) / (2.0 * h);
                    // measured largest difference 2e-9 against entries up to ~1e2
                    assert!(
                        (fd - j[s][t]).abs() < 1e-7 * (1.0 + fd.abs()),
                        "d{s}/d{t}: {fd} vs {}",
                        j[s][t]
                    );
                }
            }
        }
    }

    /// The second derivatives of a weighted sum of the standard values equal central
    /// differences of the analytic Jacobian (exact up to rounding: the Jacobian is linear).
    #[test]
    fn second_derivatives_match_the_jacobian() {
        let mut rng = crate::rng::Rng::new(13);
        let g: [f64; PER_LINK] = std::array::from_fn(|_| rng.uniform(-1.0, 1.0));
        let theta: [f64; PER_LINK] = std::array::from_fn(|_| rng.uniform(-1.5, 1.5));
        let h = 1e-3;
        for (a, (_, i, k)) in ENTRIES.iter().enumerate() {
            for (b, (_, m, l)) in ENTRIES.iter().enumerate() {
                let (mut up, mut down) = (theta, theta);
                up[b] += h;
                down[b] -= h;
                let (ju, jd) = (jacobian(&up), jacobian(&down));
                let fd: f64 = (0..PER_LINK)
                    .map(|s| g[s] * (ju[s][a] - jd[s][a]) / (2.0 * h))
                    .sum();
                let exact = if k == l {
                    second_derivative(&g, *i, *m)
                } else {
                    0.0
                };
                assert!((fd - exact).abs() < 1e-9, "({a}, {b}): {fd} vs {exact}");
            }
        }
    }

    #[test]
    fn inside_raises_only_what_is_needed() {
        let p = link();
        assert_eq!(inside(&p, 1e-9), p);
        let mut flat = p;
        flat[9] = 0.0; // no mass but a first moment: not consistent
        let raised = inside(&flat, 1e-6);
        assert!(pseudo_inertia_min_eigenvalue(&raised) >= 1e-6 * (1.0 - 1e-9));
    }
}
