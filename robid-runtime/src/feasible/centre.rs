//! The stated don't-care values (centre of the bounds) and per-parameter scales.

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

/// A typical magnitude of each standard parameter under the bounds.
#[cfg(feature = "sdp")]
pub(super) fn scales(layout: &Layout, bounds: &Bounds) -> Vec<f64> {
    let mut s = vec![1.0; layout.len()];
    for (j, idx) in layout.links.iter().enumerate() {
        let b = &bounds.links[j];
        let m = b.mass[1].max(1e-9);
        let r = b
            .com
            .iter()
            .flatten()
            .fold(0.0f64, |a, v| a.max(v.abs()))
            .max(1e-3);
        let inertia = (b.inertia[1] + m * r * r).max(1e-9);
        for (k, &i) in idx.iter().enumerate() {
            s[i] = match k {
                0..=5 => inertia,
                6..=8 => m * r,
                _ => m,
            };
        }
    }
    s
}
