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
