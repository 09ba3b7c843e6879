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
/// [margin, upper moment] and rotation vectors in [-pi, pi]^3.
pub(crate) fn link_box(b: &LinkBounds, margin: f64) -> ([f64; PER_LINK], [f64; PER_LINK]) {
    let pi = std::f64::consts::PI;
    let dlo = margin.max(0.0);
    let dhi = b.inertia[1].max(2.0 * dlo + 1e-12);
    (
        [
            b.mass[0].max(margin),
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
}
