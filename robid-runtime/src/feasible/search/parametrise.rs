//! The search variables of one link, chosen so that every point of the box is
//! physically consistent (Gaz et al. search over bounded masses, centres of mass
//! and inertias; here the inertia is parametrised so the triangle inequalities hold):
//!
//! `x = [m, cx, cy, cz, d1, d2, d3, r1, r2, r3]`, with d the second moments of the mass
//! about the centre of mass along the principal axes (d_i >= 0), principal moments
//! (d2 + d3, d1 + d3, d1 + d2), and r a rotation vector giving the principal axes.

use nalgebra::{Matrix3, Rotation3, Vector3};

use crate::feasible::bounds::LinkBounds;
use crate::feasible::inertial::LinkInertial;

/// Variables per link.
pub(crate) const PER_LINK: usize = 10;

/// The box of one link's variables: mass range, centre-of-mass box, second moments in
/// [margin, upper moment] and rotation vectors in [-pi, pi]^3. The mass stays at least
/// twice the margin (where the upper mass bound leaves room): the second moments a
/// pseudo-inertia of at least the margin needs grow as `m / (m - margin)` near a mass of
/// the margin (see `search::lift`), which held at most 2 stays smooth; at the margin
/// itself no centre of mass off the origin has such a pseudo-inertia.
pub(crate) fn link_box(b: &LinkBounds, margin: f64) -> ([f64; PER_LINK], [f64; PER_LINK]) {
    let pi = std::f64::consts::PI;
    let dlo = margin.max(0.0);
    let dhi = b.inertia[1].max(2.0 * dlo + 1e-12);
    let least_mass = (2.0 * dlo).min(0.5 * (dlo + b.mass[1])).max(dlo);
    (
        [
            b.mass[0].max(least_mass),
            b.com[0][0],
            b.com[1][0],
            b.com[2][0],
            dlo,
            dlo,
            dlo,
            -pi,
            -pi,
            -pi,
        ],
        [
            b.mass[1],
            b.com[0][1],
            b.com[1][1],
            b.com[2][1],
            dhi,
            dhi,
            dhi,
            pi,
            pi,
            pi,
        ],
    )
}

/// The stated don't-care values: mid mass, mid box, isotropic inertia at mid range
/// (the same centre the semidefinite formulation is weakly pulled to), no rotation.
pub(crate) fn link_centre(b: &LinkBounds) -> [f64; PER_LINK] {
    let (com, mass, moment) = b.centre();
    let d = 0.5 * moment;
    [mass, com[0], com[1], com[2], d, d, d, 0.0, 0.0, 0.0]
}

/// The link of a variable vector.
pub(crate) fn link_of(x: &[f64]) -> LinkInertial {
    let d = [x[4], x[5], x[6]];
    let moments = Vector3::new(d[1] + d[2], d[0] + d[2], d[0] + d[1]);
    let r = Rotation3::new(Vector3::new(x[7], x[8], x[9]));
    let ic = r.matrix() * Matrix3::from_diagonal(&moments) * r.matrix().transpose();
    LinkInertial {
        mass: x[0],
        com: [x[1], x[2], x[3]],
        inertia: [
            [ic[(0, 0)], ic[(0, 1)], ic[(0, 2)]],
            [ic[(1, 0)], ic[(1, 1)], ic[(1, 2)]],
            [ic[(2, 0)], ic[(2, 1)], ic[(2, 2)]],
        ],
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::feasible::inertial::pseudo_inertia_min_eigenvalue;

    #[test]
    fn every_point_of_the_box_is_consistent() {
        let b = LinkBounds::default();
        let (lo, hi) = link_box(&b, 1e-6);
        let mut rng = crate::rng::Rng::new(3);
        for _ in 0..200 {
            let x: Vec<f64> = (0..PER_LINK).map(|i| rng.uniform(lo[i], hi[i])).collect();
            let p = link_of(&x).to_standard();
            assert!(pseudo_inertia_min_eigenvalue(&p) > 0.0);
        }
    }

    /// The don't-care values: mid mass, mid box, no rotation, and second moments at half
    /// the mid moment, so that each principal moment (d_j + d_k) is the range's middle.
    #[test]
    fn the_centre_is_mid_box_with_the_mid_moment() {
        let b = LinkBounds {
            mass: [1.0, 3.0],
            com: [[-0.1, 0.3], [0.0, 0.2], [-0.4, 0.0]],
            inertia: [0.0, 0.5],
            ..LinkBounds::default()
        };
        let x = link_centre(&b);
        let want = [2.0, 0.1, 0.1, -0.2, 0.125, 0.125, 0.125, 0.0, 0.0, 0.0];
        for (i, (got, want)) in x.iter().zip(want).enumerate() {
            assert!((got - want).abs() < 1e-15, "{i}: {got} against {want}");
        }
        let l = link_of(&x);
        for (a, row) in l.inertia.iter().enumerate() {
            for (c, v) in row.iter().enumerate() {
                let want = if a == c { 0.25 } else { 0.0 };
                assert!((v - want).abs() < 1e-15, "I[{a}][{c}] = {v}");
            }
        }
    }

    /// An upper inertia bound below twice the margin still leaves each second moment a
    /// range whose top is just above twice its bottom (the margin).
    #[test]
    fn a_tight_inertia_bound_keeps_the_moment_range_open() {
        let b = LinkBounds {
            inertia: [0.0, 1e-7],
            ..LinkBounds::default()
        };
        let (lo, hi) = link_box(&b, 1e-6);
        for i in 4..7 {
            assert_eq!(lo[i], 1e-6);
            assert!(hi[i] > 2e-6 && hi[i] < 2e-6 + 1e-11, "{}", hi[i]);
        }
    }
}
