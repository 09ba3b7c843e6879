//! The centre of the bounds: the default prior when the links' shapes are unknown.

use super::bounds::Bounds;
use super::inertial::LinkInertial;
use super::layout::Layout;

/// The standard vector at the centre of the bounds: each link at its mid mass, with its
/// centre of mass at the middle of its box and an isotropic inertia at mid range; drive
/// terms zero. Parameters the base parameters do not determine are given these values.
pub fn centre(layout: &Layout, bounds: &Bounds) -> Vec<f64> {
    let mut p = vec![0.0; layout.len()];
    for (j, idx) in layout.links.iter().enumerate() {
        let (com, mass, moment) = bounds.links[j].centre();
        let link = LinkInertial {
            mass,
            com,
            inertia: [[moment, 0.0, 0.0], [0.0, moment, 0.0], [0.0, 0.0, moment]],
        };
        for (s, v) in idx.iter().zip(link.to_standard()) {
            p[*s] = v;
        }
    }
    p
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::feasible::LinkBounds;
    use crate::feasible::fixture::problem_with;

    /// The centre of the bounds as standard parameters: the link at its mid mass, centre of
    /// mass and moment (moved to the frame origin), drive terms zero.
    #[test]
    fn the_centre_is_a_solid_at_mid_bounds() {
        let layout = problem_with(&[0.0; 11], &["Fv"]).layout;
        let bounds = Bounds {
            links: vec![LinkBounds {
                mass: [1.0, 3.0],
                com: [[0.0, 0.2], [-0.1, 0.1], [0.2, 0.4]],
                inertia: [0.01, 0.03],
                tensor: [None; 6],
            }],
            ..Bounds::wide(1)
        };
        let p = centre(&layout, &bounds);
        // m = 2, c = (0.1, 0, 0.3), I_c = 0.02 I; J_O = I_c + m (c'c I - c c')
        let want = [
            0.02 + 2.0 * 0.09,
            0.0,
            -2.0 * 0.03,
            0.02 + 2.0 * 0.1,
            0.0,
            0.02 + 2.0 * 0.01,
            0.2,
            0.0,
            0.6,
            2.0,
            0.0,
            0.0,
        ];
        assert_eq!(p.len(), 12);
        for (i, (a, b)) in p.iter().zip(want).enumerate() {
            assert!((a - b).abs() < 1e-15, "{i}: {p:?}");
        }
    }
}
