//! What settles the directions the identified base parameters leave free: a user's prior
//! (CAD values) where given, weighed on each link's own prior mass ([`Prior::weight`],
//! docs/experiments.md#priors), else the default prior. The default prior models each link as
//! a solid cylinder along its segment of the kinematic chain ([`LinkShape`]), all links of
//! one density fitted to the identified base parameters, so that a link the data cannot
//! weigh (the first link of most arms) gets the mass of a solid of its size at the density
//! the other links show. Without shapes, or with shapes that give the solids no sensible
//! size ([`Unsized`]: a chain without length, or lengths far too short for the identified
//! inertias), it is the centre of the bounds.
//! (docs/experiments.md#feasible-parameters)

use nalgebra::DVector;

use super::bounds::Bounds;
use super::centre::centre;
use super::inertial::LinkInertial;
use super::layout::Layout;
use super::problem::Problem;
use crate::{Error, Result};

/// A prior (e.g. CAD values) the fit is pulled towards.
///
/// The data decide what they determine; the prior decides the rest (the directions the
/// base parameters leave free) and, with a firm weight, competes with the data.
#[derive(Debug, Clone, PartialEq)]
pub struct Prior {
    /// Standard parameter values, in the problem's order; `None` where there is no prior
    /// (that parameter gets the default prior).
    pub standard: Vec<Option<f64>>,
    /// Weight of the pull: a deviation of one parameter scale costs this many chi^2 units,
    /// so the prior counts as a measurement of each parameter to `1 / sqrt(weight)` of its
    /// scale. For a link whose mass the prior gives, the scales are that mass (at least 1 %
    /// of the heaviest prior link's), that mass times the link's size (its default solid's
    /// length; without shapes, the reach of its centre-of-mass bounds) for the first
    /// moments, and times the size squared for the inertias: [`Prior::DEFAULT_WEIGHT`],
    /// 100, trusts the mass to 10 %, the centre of mass to a tenth of the link's size and
    /// the inertias to a tenth of mass times size squared.
    pub weight: f64,
}

impl Prior {
    /// The weight of a user's prior (CAD values, a URDF's inertials) unless told: 100, each
    /// link's values trusted to 10 % of its own mass (its mass times its size, ...), about
    /// a CAD model's accuracy (cables, screws and gearboxes are missing from it). The data
    /// decide the directions they determine better than that, and the prior holds the rest
    /// near it. On simulated UR5, Kinova, xArm7 and Panda data, with the URDF's own
    /// inertials as the prior, every mass comes within 4.4 % of the URDF's and every centre
    /// of mass within 27 mm; with every inertial 1.3 times too large, every base parameter
    /// stays within 2.6 standard deviations of its identified value, as with the true
    /// inertials. A weight of 1 per solid-cylinder scale (the old default) let the noise of
    /// the identified values carry poorly determined directions to a bound: the UR5's wrist
    /// flange of 0.188 kg became 1.3 g with its centre of mass 1.15 m away
    /// (docs/experiments.md#priors).
    pub const DEFAULT_WEIGHT: f64 = 100.0;
}

/// The default prior's weight unless told (see [`Prior::weight`]): weak, so that it
/// settles what the data leave free and barely moves what they determine. Every method
/// pulls the values a user's prior does not give towards the default prior with it.
pub const DEFAULT_PRIOR_WEIGHT: f64 = 1e-2;

/// A link's extent in its own frame: the segment from the joint it turns about to the
/// next joint (both ends in the link frame, m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinkShape {
    /// One end of the segment.
    pub from: [f64; 3],
    /// The other end.
    pub to: [f64; 3],
}

/// A segment shorter than this share of the whole chain's length is given that length
/// (a wrist link whose frames coincide is still a body).
const MIN_LENGTH_SHARE: f64 = 0.1;
/// A chain shorter than this (m) gives the solids no size: a one-joint robot with
/// a = d = 0 had specks of 1 mm, whose density the identified ZZ1 blew up to 8e15 kg/m^3
/// and the link's mass to 9.5e5 kg.
const MIN_CHAIN_LENGTH: f64 = 1e-3;
/// The densest solids the default prior takes, kg/m^3: four times osmium's, room for a
/// link bulkier than its cylinder. A denser fit means the links are too short for the
/// identified inertias, and the masses it gives are not a body's.
pub const MAX_DENSITY: f64 = 1e5;
/// The default prior's weight on a drive term, relative to its weight on link parameters.
const DRIVE_WEIGHT_SHARE: f64 = 1e-4;
/// The smallest mass scale of a link with a prior mass, relative to the heaviest prior
/// link's: a token mass of 1 g in a URDF (a sensor frame's placeholder) is not held to a
/// tenth of a gram by the prior's weight.
const MIN_MASS_SCALE_SHARE: f64 = 1e-2;
/// The smallest mass scale of a link with a prior mass, kg, the least mass bound a link may
/// have: a prior of specks (every mass 1e-300 kg) gave weights of 1e600, and the fit "left
/// the consistent set".
const MIN_MASS_SCALE: f64 = super::bounds::MIN_LINK_MASS;
/// Radius of the solid, relative to its length.
const RADIUS_SHARE: f64 = 0.25;

/// Why the default prior cannot size the links from their shapes
/// ([`Problem::unsized_links`]); they then take the centre of their bounds, as without
/// shapes. `Display` says why, without the fix (the caller knows what can be given).
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub enum Unsized {
    /// The whole chain is shorter than 1 mm: the joints' frames lie at one point and no
    /// tool extends the last link (a single joint with a = d = 0).
    NoLength,
    /// Solids along the links would need this density (kg/m^3), above [`MAX_DENSITY`], to
    /// have the identified inertias: the links are too short for them.
    Density(f64),
}

impl std::fmt::Display for Unsized {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match *self {
            Unsized::NoLength => write!(
                f,
                "the robot's links have no length (every joint frame at one point, no tool), so \
                 the default prior's solid links have no size"
            ),
            Unsized::Density(rho) => write!(
                f,
                "solid links along the description's segments would need a density of {rho:.1e} \
                 kg/m^3 (more than {MAX_DENSITY:e}) to have the identified inertias: the links \
                 are too short for them (check the description's lengths, in m, and give a prismatic \
                 joint its position limits: its travel sizes its link), so the default \
                 prior's solids have no sensible size"
            ),
        }
    }
}

impl Problem {
    /// Why the default prior cannot size this problem's links from their shapes, if it
    /// cannot (`None` also without shapes: the prior is then the centre of the bounds by
    /// the caller's choice). Callers that can ask for bounds or a prior should: the centre
    /// of default bounds is no knowledge of the robot.
    pub fn unsized_links(&self) -> Option<Unsized> {
        self.shapes
            .as_deref()
            .and_then(|shapes| Solids::of(self, shapes).err())
    }
}

/// The pull on each standard parameter: towards `target`, with `weight` per unit of
/// `scale`.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Pull {
    /// Target per standard parameter.
    pub target: Vec<f64>,
    /// Weight per standard parameter.
    pub weight: Vec<f64>,
    /// Typical magnitude per standard parameter.
    pub scale: Vec<f64>,
}

impl Pull {
    /// The pull of `prior` where it gives a value, else of the default prior with
    /// `default_weight`.
    pub(super) fn new(
        problem: &Problem,
        bounds: &Bounds,
        prior: Option<&Prior>,
        default_weight: f64,
    ) -> Result<Pull> {
        let layout = &problem.layout;
        let ns = layout.len();
        let solids = problem
            .shapes
            .as_deref()
            .and_then(|shapes| Solids::of(problem, shapes).ok());
        let (mut target, mut scale) = match solids {
            Some(solids) => solid_prior(problem, bounds, &solids),
            None => (centre(layout, bounds), bounds_scales(layout, bounds)),
        };
        let mut weight = vec![default_weight; ns];
        // Drive terms have no geometric prior: a far weaker pull towards zero lets the data
        // and the links' solids settle them (a rotor inertia regrouped with its link's
        // inertia takes what the solid leaves of the identified sum).
        for d in &layout.drives {
            weight[d.index] *= DRIVE_WEIGHT_SHARE;
        }
        if let Some(prior) = prior {
            if prior.standard.len() != ns {
                return Err(Error::DimensionMismatch {
                    what: "prior standard parameters".to_owned(),
                    expected: ns,
                    found: prior.standard.len(),
                });
            }
            if prior
                .standard
                .iter()
                .flatten()
                .any(|v| !(v.abs() <= crate::limits::MAX_PARAMETER))
                || !(prior.weight >= 0.0 && prior.weight <= 1e12)
            {
                return Err(Error::setting(
                    "Prior",
                    "prior",
                    "holds NaN, an infinite or huge value, or a weight outside [0, 1e12]",
                ));
            }
            for (s, v) in prior.standard.iter().enumerate() {
                if let Some(v) = v {
                    target[s] = *v;
                    weight[s] = prior.weight;
                }
            }
            prior_scales(layout, prior, &mut scale);
        }
        Ok(Pull {
            target,
            weight,
            scale,
        })
    }
}

/// Each link whose mass `prior` gives (above zero) is weighed on that mass: its scales
/// (mass, mass times size, mass times size squared, the sizes those of the default prior)
/// are rescaled to the prior's mass, at least [`MIN_MASS_SCALE_SHARE`] of the heaviest prior
/// link's and [`MIN_MASS_SCALE`]. So a weight `w` trusts every link's prior to `1 / sqrt(w)` of its own mass (its
/// mass times its size, ...), not of the mass of the default prior's solid: the UR5's
/// wrist flange of 0.188 kg, whose solid weighs 1 kg, was trusted to 500 % of its mass at
/// weight 1. A link the prior gives no mass (or a mass of 0: no size to scale to) keeps the
/// default prior's scales.
fn prior_scales(layout: &Layout, prior: &Prior, scale: &mut [f64]) {
    let mass = |idx: &[usize; 10]| prior.standard[idx[9]].filter(|m| *m > 0.0 && m.is_finite());
    let heaviest = layout.links.iter().filter_map(mass).fold(0.0f64, f64::max);
    for idx in &layout.links {
        if let Some(m) = mass(idx) {
            let ratio = m.max(MIN_MASS_SCALE_SHARE * heaviest).max(MIN_MASS_SCALE) / scale[idx[9]];
            for &s in idx {
                scale[s] *= ratio;
            }
        }
    }
}

/// The length of each link for the default prior: its segment, at least
/// [`MIN_LENGTH_SHARE`] of the chain's total; `None` for a chain shorter than
/// [`MIN_CHAIN_LENGTH`], which sizes nothing.
fn lengths(shapes: &[LinkShape]) -> Option<Vec<f64>> {
    let raw: Vec<f64> = shapes
        .iter()
        .map(|s| {
            (0..3)
                .map(|i| (s.to[i] - s.from[i]).powi(2))
                .sum::<f64>()
                .sqrt()
        })
        .collect();
    let total: f64 = raw.iter().sum();
    if !(total >= MIN_CHAIN_LENGTH) {
        return None;
    }
    let floor = MIN_LENGTH_SHARE * total;
    Some(raw.iter().map(|l| l.max(floor)).collect())
}

/// A link's centre of mass farther than this many link sizes from its segment lies outside
/// any body of that size: a link's bulk (motors, housings) reaches about one size around
/// its segment, so three leave room for offset links and attached tools. The UR5e flange
/// identified by the energy model came back 15 g at 0.87 m (8.4 sizes) with nothing said;
/// the simulated reference robots and the real TX40 and LWR logs stay within it, but for
/// the TX40's flange, which the real log leaves at 88 g, 0.21 m out (CAD: 0.2 kg, 4 cm).
const COM_REACH: f64 = 3.0;
/// A link lighter than this share of the robot's mass whose radius of gyration about its
/// centre of mass exceeds [`COM_REACH`] sizes is no body of its size: a speck with the
/// inertia of a beam (the KR 6 R900's first link by `anneal` without a prior: 11.6 mg with
/// 0.29 kg m^2, a radius of gyration of 157 m). Heavier links are spared: a first link
/// whose inertia takes the gearboxes' (a real log's ZZR1) is a body the data weigh.
const LIGHT_SHARE: f64 = 1e-2;

/// Per link that no body of its size can be: a centre of mass more than [`COM_REACH`]
/// sizes from its segment, or a mass below [`LIGHT_SHARE`] of the robot's with a radius of
/// gyration beyond that reach. A link's size is the longer of its own and the previous
/// link's default-prior length ([`lengths`]): a body can run back along its joint's axis
/// over the previous link's offset (the TX40's forearm lies between the elbow and the
/// wrist frame it turns in). Each entry names the link, the figures and the bound that
/// settles it; empty without shapes (a library caller that gives none) or when the chain
/// sizes nothing. The fit cannot tell such a link from a plausible one where the data
/// barely see its mass and centre of mass (a light link far away changes the base
/// parameters as little as a heavy one near), so only a bound or a prior settles it.
pub(super) fn implausible(
    problem: &Problem,
    bounds: &Bounds,
    links: &[Option<LinkInertial>],
) -> Vec<String> {
    let Some(shapes) = problem.shapes.as_deref() else {
        return Vec::new();
    };
    let Some(lengths) = lengths(shapes) else {
        return Vec::new();
    };
    let total: f64 = links.iter().flatten().map(|l| l.mass).sum();
    let r = |v: f64| crate::Num::rounded(v, 3);
    let mut found = Vec::new();
    for (j, (link, shape)) in links.iter().zip(shapes).enumerate() {
        let Some(l) = link else { continue };
        let size = lengths[j].max(if j > 0 { lengths[j - 1] } else { 0.0 });
        let reach = COM_REACH * size;
        let away = distance_to_segment(l.com, shape);
        let moment = l.principal_moments().into_iter().fold(0.0f64, f64::max);
        let gyration = (moment / l.mass).sqrt();
        let light = l.mass < LIGHT_SHARE * total;
        let far = away > reach;
        if !(far || (light && gyration > reach)) {
            continue;
        }
        // the segment's box widened by the link's size: room for any body of that size
        let lo = |i: usize| r(shape.from[i].min(shape.to[i]) - size);
        let hi = |i: usize| r(shape.from[i].max(shape.to[i]) + size);
        let bound = if far {
            format!(
                "com = [[{}, {}], [{}, {}], [{}, {}]]",
                lo(0),
                hi(0),
                lo(1),
                hi(1),
                lo(2),
                hi(2)
            )
        } else {
            // a speck with a beam's inertia: a least mass settles it
            let upper = bounds.links.get(j).map_or(f64::INFINITY, |b| b.mass[1]);
            format!("mass = [{}, {}]", r(LIGHT_SHARE * total), r(upper))
        };
        found.push(format!(
            "link {}: no body of its size (about {} m): mass {} kg ({} % of the robot's {} \
             kg), centre of mass [{}, {}, {}] m, {} m from the link's segment, radius of \
             gyration {} m about it; the data barely see it there, so bound it (bounds \
             `[links.{}] {bound}`) or give a prior of the link",
            j + 1,
            r(size),
            r(l.mass),
            r(100.0 * l.mass / total),
            r(total),
            r(l.com[0]),
            r(l.com[1]),
            r(l.com[2]),
            r(away),
            r(gyration),
            j + 1,
        ));
    }
    found
}

/// The distance from `point` to the segment of `shape`.
fn distance_to_segment(point: [f64; 3], shape: &LinkShape) -> f64 {
    let d: [f64; 3] = std::array::from_fn(|i| shape.to[i] - shape.from[i]);
    let w: [f64; 3] = std::array::from_fn(|i| point[i] - shape.from[i]);
    let dd: f64 = d.iter().map(|v| v * v).sum();
    let t = if dd > 0.0 {
        (d.iter().zip(&w).map(|(a, b)| a * b).sum::<f64>() / dd).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (0..3)
        .map(|i| (w[i] - t * d[i]).powi(2))
        .sum::<f64>()
        .sqrt()
}

/// A solid cylinder of density 1 along a link's segment (a zero segment: along z about
/// the origin), with the given length and a radius of [`RADIUS_SHARE`] of it.
fn solid(shape: &LinkShape, length: f64) -> LinkInertial {
    let d: Vec<f64> = (0..3).map(|i| shape.to[i] - shape.from[i]).collect();
    let norm = d.iter().map(|v| v * v).sum::<f64>().sqrt();
    let axis = if norm > 1e-9 {
        [d[0] / norm, d[1] / norm, d[2] / norm]
    } else {
        [0.0, 0.0, 1.0]
    };
    let r = RADIUS_SHARE * length;
    let mass = std::f64::consts::PI * r * r * length;
    let across = mass * (3.0 * r * r + length * length) / 12.0;
    let along = 0.5 * mass * r * r;
    let inertia: [[f64; 3]; 3] = std::array::from_fn(|i| {
        std::array::from_fn(|k| {
            let uu = axis[i] * axis[k];
            let id = if i == k { 1.0 } else { 0.0 };
            across * (id - uu) + along * uu
        })
    });
    LinkInertial {
        mass,
        com: std::array::from_fn(|i| 0.5 * (shape.from[i] + shape.to[i])),
        inertia,
    }
}

/// The default prior from the link solids: each link's mass and centre of mass held
/// inside its bounds; drive terms zero. Also the scales of the pull: per link its prior
/// mass, mass times length and mass times length squared.
fn solid_prior(problem: &Problem, bounds: &Bounds, solids: &Solids) -> (Vec<f64>, Vec<f64>) {
    let layout = &problem.layout;
    let ns = layout.len();
    let mut target = vec![0.0; ns];
    let mut scale = vec![1.0; ns];
    for (j, idx) in layout.links.iter().enumerate() {
        let b = &bounds.links[j];
        let link = solids.unit[j];
        let inside = |v: f64, r: [f64; 2]| {
            let pad = 0.05 * (r[1] - r[0]);
            v.clamp(r[0] + pad, r[1] - pad)
        };
        let mass = inside(solids.density * link.mass, b.mass);
        let com = std::array::from_fn(|i| inside(link.com[i], b.com[i]));
        let ratio = mass / link.mass;
        let inertia = link.inertia.map(|row| row.map(|v| v * ratio));
        let prior = LinkInertial { mass, com, inertia };
        let l = solids.lengths[j];
        for (k, (s, v)) in idx.iter().zip(prior.to_standard()).enumerate() {
            target[*s] = v;
            scale[*s] = match k {
                0..=5 => mass * l * l,
                6..=8 => mass * l,
                _ => mass,
            };
        }
    }
    (target, scale)
}

/// The solids of the default prior: per link a solid of density 1 along its segment
/// ([`solid`]) and its length, and the one density that fits them to the identified base
/// parameters.
struct Solids {
    unit: Vec<LinkInertial>,
    lengths: Vec<f64>,
    density: f64,
}

impl Solids {
    /// The solids along `shapes` with the density of the data (weighted least squares in
    /// the density alone), or why they have no sensible size.
    fn of(problem: &Problem, shapes: &[LinkShape]) -> std::result::Result<Solids, Unsized> {
        let layout = &problem.layout;
        let lengths = lengths(shapes).ok_or(Unsized::NoLength)?;
        let unit: Vec<LinkInertial> = shapes
            .iter()
            .zip(&lengths)
            .map(|(s, l)| solid(s, *l))
            .collect();
        let mut p = vec![0.0; layout.len()];
        for (idx, link) in layout.links.iter().zip(&unit) {
            for (s, v) in idx.iter().zip(link.to_standard()) {
                p[*s] = v;
            }
        }
        // density: minimise || L^-1 (K rho p - beta) || over rho
        let a = &problem.whitening * (&problem.k * DVector::from_column_slice(&p));
        let b = &problem.whitening * &problem.target;
        let rho = a.dot(&b) / a.norm_squared();
        if rho > MAX_DENSITY {
            return Err(Unsized::Density(rho));
        }
        // a density the data cannot give (a robot without gravity terms, or a poor fit):
        // that of a hollow aluminium structure
        let density = if rho.is_finite() && rho > 0.0 {
            rho
        } else {
            1000.0
        };
        Ok(Solids {
            unit,
            lengths,
            density,
        })
    }
}

/// Each link as the prior sees it, before any bounds: the values of `prior` where it gives
/// all ten of the link's, else the solid of the density the data give (when the problem
/// has shapes that size it); `None` for a link that has neither or whose values are not a
/// body.
pub(super) fn prior_links(problem: &Problem, prior: Option<&Prior>) -> Vec<Option<LinkInertial>> {
    let layout = &problem.layout;
    let solids = problem
        .shapes
        .as_deref()
        .and_then(|shapes| Solids::of(problem, shapes).ok())
        .map(|solids| {
            let rho = solids.density;
            solids
                .unit
                .into_iter()
                .map(|l| LinkInertial {
                    mass: rho * l.mass,
                    com: l.com,
                    inertia: l.inertia.map(|row| row.map(|v| v * rho)),
                })
                .collect::<Vec<_>>()
        });
    (0..layout.links.len())
        .map(|j| {
            let given: Option<Vec<f64>> = prior.and_then(|p| {
                layout.links[j]
                    .iter()
                    .map(|&s| p.standard.get(s).copied().flatten())
                    .collect()
            });
            match given {
                Some(v) => LinkInertial::from_standard(&std::array::from_fn(|k| v[k])),
                None => solids.as_ref().map(|s| s[j]),
            }
        })
        .collect()
}

/// The names of the standard parameters that have no effect on the base parameters
/// ([`Problem::no_effect`]) and that `pull` does not pull (a weight of 0): see
/// [`super::solution::Solution::unpulled`].
pub(super) fn unpulled(problem: &Problem, pull: &Pull) -> Vec<String> {
    problem
        .no_effect()
        .into_iter()
        .filter(|&s| pull.weight.get(s).is_some_and(|w| *w == 0.0))
        .map(|s| problem.standard_names[s].clone())
        .collect()
}

/// The share of each standard parameter that the data determine, in [0, 1]: the diagonal
/// of the resolution matrix (F_data + F_prior)^-1 F_data, with F_data = (L^-1 K)' (L^-1 K)
/// the information of the identified base parameters and F_prior that of the pull. 1: the
/// data alone fix it; 0: only the prior does.
pub(super) fn determined(problem: &Problem, pull: &Pull) -> Vec<f64> {
    let ns = problem.layout.len();
    // in units of each parameter's scale, so that the weights compare
    let s = DVector::from_column_slice(&pull.scale);
    let a = (&problem.whitening * &problem.k) * nalgebra::DMatrix::from_diagonal(&s);
    let data = a.transpose() * &a;
    let top = data.diagonal().max().max(1.0);
    let mut total = data.clone();
    for i in 0..ns {
        total[(i, i)] += pull.weight[i] + 1e-12 * top;
    }
    match total.cholesky() {
        Some(c) => c
            .solve(&data)
            .diagonal()
            .iter()
            .map(|v| v.clamp(0.0, 1.0))
            .collect(),
        None => vec![f64::NAN; ns],
    }
}

/// A typical magnitude of each standard parameter under the bounds (no shapes known).
pub(super) fn bounds_scales(layout: &Layout, bounds: &Bounds) -> Vec<f64> {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::feasible::LinkBounds;
    use crate::feasible::fixture;

    #[test]
    fn a_solid_cylinder_has_the_textbook_inertia() {
        let shape = LinkShape {
            from: [0.0, 0.0, 0.0],
            to: [0.4, 0.0, 0.0],
        };
        let s = solid(&shape, 0.4);
        let r: f64 = 0.1;
        let m = std::f64::consts::PI * r * r * 0.4;
        assert!((s.mass - m).abs() < 1e-15);
        assert_eq!(s.com, [0.2, 0.0, 0.0]);
        // about the axis m r^2 / 2, across m (3 r^2 + L^2) / 12
        assert!((s.inertia[0][0] - 0.5 * m * r * r).abs() < 1e-15);
        assert!((s.inertia[1][1] - m * (3.0 * r * r + 0.16) / 12.0).abs() < 1e-15);
        assert!(s.inertia[0][1].abs() < 1e-18);
    }

    /// A one-link arm along x (0.5 m) whose identified ZZ1 and MX1 (columns 5 and 6) are
    /// those of a solid of density `rho` along its segment; also that solid.
    fn solid_arm(rho: f64) -> (Problem, LinkInertial) {
        let names: Vec<String> = crate::model::Inertial::ALL
            .iter()
            .map(|s| format!("{}1", s.stem()))
            .collect();
        let mut k = nalgebra::DMatrix::zeros(2, 10);
        k[(0, 5)] = 1.0;
        k[(1, 6)] = 1.0;
        let shape = LinkShape {
            from: [0.0; 3],
            to: [0.5, 0.0, 0.0],
        };
        let unit = solid(&shape, 0.5);
        let p = unit.to_standard();
        let problem = Problem::new(names, vec!["ZZ1".into(), "MX1".into()], k)
            .unwrap()
            .with_target(&[rho * p[5], rho * p[6]], &[1e-3, 1e-3])
            .unwrap()
            .with_shapes(vec![shape])
            .unwrap();
        (problem, unit)
    }

    /// A steel link of 191 kg, known from the data alone (no prior): the default bounds
    /// are widened to twice its solid's mass, so the solid prior is not clamped to 47.5 kg.
    #[test]
    fn the_default_bounds_make_room_for_a_heavy_link() {
        let rho = 7800.0;
        let (problem, unit) = solid_arm(rho);
        let heavy = rho * unit.mass;
        assert!(heavy > 190.0 && heavy < 192.0, "{heavy}");
        let narrow = Pull::new(&problem, &Bounds::wide(1), None, 1.0).unwrap();
        assert_eq!(narrow.target[9], 47.5);
        let bounds = Bounds::wide_for(&problem, None);
        assert!((bounds.links[0].mass[1] - 2.0 * heavy).abs() < 1e-9 * heavy);
        // its centre of mass, 0.25 m out, fits the default box; its largest moment (across
        // the cylinder of radius 0.125 m, 4.74 kg m^2) gets twice its value
        assert_eq!(bounds.links[0].com, [[-1.0, 1.0]; 3]);
        let across = heavy * (3.0 * 0.125f64.powi(2) + 0.25) / 12.0;
        assert!(
            (bounds.links[0].inertia[1] - 2.0 * across).abs() < 1e-9,
            "{:?}",
            bounds.links[0].inertia
        );
        let pull = Pull::new(&problem, &bounds, None, 1.0).unwrap();
        assert!(
            (pull.target[9] - heavy).abs() < 1e-9 * heavy,
            "{}",
            pull.target[9]
        );
    }

    /// A one-link arm whose identified ZZ1 and MX1 are those of a solid of density 500
    /// along its segment: the default prior finds that density, so the link's mass (which
    /// no base parameter holds alone) is the solid's.
    #[test]
    fn the_default_prior_finds_the_density_of_the_data() {
        let rho = 500.0;
        let (problem, truth) = solid_arm(rho);
        let bounds = Bounds::wide(1);
        let pull = Pull::new(&problem, &bounds, None, 1.0).unwrap();
        let mass = pull.target[9];
        // rounding only (measured 0 for both)
        assert!((mass - rho * truth.mass).abs() < 1e-15 * mass, "{mass}");
        assert!((pull.scale[9] - mass).abs() < 1e-15 * mass);
        // ZZ1 and MX1 are measured to 1e-3 against a pull of weight 1 per scale: the data
        // fix them; the mass and XX1 have no data at all
        let share = determined(&problem, &pull);
        assert!(share[5] > 0.999 && share[6] > 0.999, "{share:?}");
        assert!(share[9] == 0.0 && share[0] == 0.0, "{share:?}");
        let weak = Pull::new(&problem, &bounds, None, 1e12).unwrap();
        // measured 3.8e-5: a pull of 1e12 per scale outweighs the data
        assert!(determined(&problem, &weak)[6] < 7.5e-5);
        // a user prior replaces the values it gives, with its weight
        let prior = Prior {
            standard: (0..10).map(|i| (i == 9).then_some(3.0)).collect(),
            weight: 5.0,
        };
        let pull = Pull::new(&problem, &bounds, Some(&prior), 1.0).unwrap();
        assert_eq!(
            (pull.target[9], pull.weight[9], pull.weight[0]),
            (3.0, 5.0, 1.0)
        );
    }

    /// A one-link arm whose link has the segment `to` and whose identified ZZ1 (the only
    /// base parameter, as for one joint about the vertical with a = d = 0) is `zz`.
    fn spinning_link(to: [f64; 3], zz: f64) -> Problem {
        let names: Vec<String> = crate::model::Inertial::ALL
            .iter()
            .map(|s| format!("{}1", s.stem()))
            .collect();
        let mut k = nalgebra::DMatrix::zeros(1, 10);
        k[(0, 5)] = 1.0;
        Problem::new(names, vec!["ZZ1".into()], k)
            .unwrap()
            .with_target(&[zz], &[1e-4])
            .unwrap()
            .with_shapes(vec![LinkShape { from: [0.0; 3], to }])
            .unwrap()
    }

    /// A chain without length sizes no solid: the link takes the centre of its bounds (and
    /// the default bounds are not widened by it). Specks of 1 mm used to get the density
    /// the identified ZZ1 asks of them, 8e15 kg/m^3, and the link 9.5e5 kg.
    #[test]
    fn a_chain_without_length_gives_the_centre_of_the_bounds() {
        let problem = spinning_link([0.0; 3], 0.05);
        assert_eq!(problem.unsized_links(), Some(Unsized::NoLength));
        let wide = Bounds::wide_for(&problem, None);
        assert_eq!(wide, Bounds::wide(1));
        let pull = Pull::new(&problem, &wide, None, 1e-2).unwrap();
        assert_eq!(pull.target, centre(&problem.layout, &wide));
        assert_eq!(pull.target[9], 25.0);
        assert_eq!(pull.scale, bounds_scales(&problem.layout, &wide));
        assert_eq!(prior_links(&problem, None), [None]);
        // given bounds: their centre
        let mut bounds = Bounds::wide(1);
        bounds.links[0].mass = [1.0, 3.0];
        let pull = Pull::new(&problem, &bounds, None, 1e-2).unwrap();
        assert_eq!(pull.target[9], 2.0);
        // the same link 1 mm long (the shortest chain that sizes) is a solid again, with an
        // inertia its size can hold (6e-15 kg m^2: 980 kg/m^3)
        assert_eq!(spinning_link([0.0, 0.0, 1e-3], 6e-15).unsized_links(), None);
        assert_eq!(
            spinning_link([0.0, 0.0, 0.999e-3], 6e-15).unsized_links(),
            Some(Unsized::NoLength)
        );
        let text = Unsized::NoLength.to_string();
        assert!(text.contains("links have no length"), "{text}");
    }

    /// Solids denser than MAX_DENSITY are refused as a size: a link 1 cm long with the
    /// identified ZZ1 of 0.05 kg m^2 needs 8.1e10 kg/m^3 (it would weigh 1.6e4 kg) and takes
    /// the centre of its bounds; a 0.5 m link along x has a believable one (350 kg/m^3 for
    /// 0.75 kg m^2).
    #[test]
    fn solids_too_dense_to_be_a_body_size_nothing() {
        let problem = spinning_link([0.0, 0.0, 0.01], 0.05);
        // along z: ZZ1 about the axis, m r^2 / 2 of the unit solid
        let unit = solid(&problem.shapes.as_ref().unwrap()[0], 0.01);
        let rho = 0.05 / unit.inertia[2][2];
        assert!(rho > 8e10 && rho < 8.2e10, "{rho}");
        match problem.unsized_links() {
            Some(Unsized::Density(d)) => assert!((d / rho - 1.0).abs() < 1e-12, "{d}"),
            other => panic!("{other:?}"),
        }
        let pull = Pull::new(&problem, &Bounds::wide(1), None, 1e-2).unwrap();
        assert_eq!(pull.target[9], 25.0);
        assert_eq!(prior_links(&problem, None), [None]);
        let text = Unsized::Density(rho).to_string();
        assert!(text.contains("8.1e10 kg/m^3 (more than 1e5)"), "{text}");
        // 0.5 m along x: ZZ1 across the cylinder, m (3 r^2 + L^2) / 12 + m (L/2)^2; an
        // identified 0.75 kg m^2 is a solid of 350 kg/m^3, 8.6 kg
        let problem = spinning_link([0.5, 0.0, 0.0], 0.75);
        assert_eq!(problem.unsized_links(), None);
        let pull = Pull::new(&problem, &Bounds::wide(1), None, 1e-2).unwrap();
        let unit = solid(&problem.shapes.as_ref().unwrap()[0], 0.5);
        let mass = 0.75 / unit.to_standard()[5] * unit.mass;
        assert!(mass > 8.5 && mass < 8.7, "{mass}");
        assert!((pull.target[9] - mass).abs() < 1e-12, "{}", pull.target[9]);
    }

    #[test]
    fn short_links_get_a_share_of_the_chain() {
        let seg = |l: f64| LinkShape {
            from: [0.0; 3],
            to: [0.0, 0.0, l],
        };
        let l = lengths(&[seg(1.0), seg(0.0), seg(0.5)]).unwrap();
        assert_eq!(l[0], 1.0);
        assert!((l[1] - 0.15).abs() < 1e-15 && l[2] == 0.5, "{l:?}");
    }

    /// A user prior of the wrong length, with a value past the limits or a weight outside
    /// [0, 1e12] is refused; the limits themselves are accepted.
    #[test]
    fn a_user_prior_is_checked() {
        let problem = fixture::problem(&[0.0; 11]);
        let bounds = Bounds::wide(1);
        let pull = |standard: Vec<Option<f64>>, weight: f64| {
            Pull::new(&problem, &bounds, Some(&Prior { standard, weight }), 1.0)
        };
        let short = pull(vec![None; 10], 1.0);
        assert!(
            matches!(
                short,
                Err(Error::DimensionMismatch {
                    expected: 11,
                    found: 10,
                    ..
                })
            ),
            "{short:?}"
        );
        let limit = crate::limits::MAX_PARAMETER;
        for (value, weight) in [
            (f64::NAN, 1.0),
            (1.01 * limit, 1.0),
            (1.0, -1e-9),
            (1.0, 1.01e12),
        ] {
            let mut standard = vec![None; 11];
            standard[2] = Some(value);
            let refused = pull(standard, weight);
            assert!(
                matches!(&refused, Err(Error::Setting { owner, .. }) if owner == "Prior"),
                "{value} {weight}: {refused:?}"
            );
        }
        for (value, weight) in [(-limit, 0.0), (limit, 1e12)] {
            let mut standard = vec![None; 11];
            standard[2] = Some(value);
            let kept = pull(standard, weight).unwrap();
            assert_eq!((kept.target[2], kept.weight[2]), (value, weight));
        }
    }

    /// A user prior's links are weighed on their own masses: the scales of a link whose mass
    /// the prior gives are that mass, mass times the solid's length and times its square
    /// (a token mass held at 1 % of the heaviest prior link's), so that
    /// [`Prior::DEFAULT_WEIGHT`] trusts a link's mass to 10 %: data that weigh it to 10 %
    /// determine half of it. A link without a prior mass (none, or 0) keeps the solid's.
    #[test]
    fn a_user_prior_weighs_each_link_on_its_own_mass() {
        let lengths = [0.5, 0.3, 0.2];
        let shapes: Vec<LinkShape> = lengths
            .iter()
            .map(|&l| LinkShape {
                from: [0.0; 3],
                to: [l, 0.0, 0.0],
            })
            .collect();
        let names = crate::feasible::fixture::link_names(3);
        // every standard parameter its own base parameter, with the values of solids of
        // 1000 kg/m^3; the mass of link 1 measured to 0.6 kg, everything else to 1e-3
        let units: Vec<LinkInertial> = shapes
            .iter()
            .zip(lengths)
            .map(|(s, l)| solid(s, l))
            .collect();
        let values: Vec<f64> = units
            .iter()
            .flat_map(|u| u.to_standard().map(|v| 1000.0 * v))
            .collect();
        let mut std = vec![1e-3; 30];
        std[9] = 0.6;
        let problem = Problem::new(names.clone(), names, nalgebra::DMatrix::identity(30, 30))
            .unwrap()
            .with_target(&values, &std)
            .unwrap()
            .with_shapes(shapes)
            .unwrap();
        let bounds = Bounds::wide(3);
        let solids = Pull::new(&problem, &bounds, None, 1.0).unwrap();
        let mut standard = vec![None; 30];
        standard[9] = Some(6.0);
        standard[19] = Some(1e-3);
        standard[29] = Some(0.0);
        let prior = Prior {
            standard,
            weight: Prior::DEFAULT_WEIGHT,
        };
        let pull = Pull::new(&problem, &bounds, Some(&prior), 1.0).unwrap();
        // link 1 on its 6 kg, link 2 (1 g) on 1 % of it, link 3 (no mass) on its solid
        for (j, (mass, l)) in [(6.0, 0.5), (0.06, 0.3)].into_iter().enumerate() {
            let scale = &pull.scale[10 * j..10 * j + 10];
            assert!((scale[9] - mass).abs() < 1e-12 * mass, "{j}: {scale:?}");
            assert!((scale[6] - mass * l).abs() < 1e-12 * mass, "{j}: {scale:?}");
            assert!(
                (scale[0] - mass * l * l).abs() < 1e-12 * mass,
                "{j}: {scale:?}"
            );
        }
        assert_eq!(pull.scale[20..], solids.scale[20..]);
        // the solid of link 1: 0.5 m long, 0.125 m in radius, 1000 kg/m^3
        let solid_mass = 1000.0 * std::f64::consts::PI * 0.125f64.powi(2) * 0.5;
        assert!(
            (solids.scale[9] - solid_mass).abs() < 1e-9,
            "{}",
            solids.scale[9]
        );
        // the prior's mass of link 1 counts as a measurement to 10 %: as firm as the data's
        // 0.6 kg, so each determines half (on its solid's 24.5 kg the prior would count as a
        // measurement to 2.45 kg, and the data would determine 94 %); measured 0.49999994
        // (the 1e-12 regularisation of the other parameters' far firmer data)
        let share = determined(&problem, &pull)[9];
        assert!((share - 0.5).abs() < 1e-6, "{share}");
        // a prior of specks (1e-300 kg) is weighed on 1 mg, not on 1e-300 kg (weights of
        // 1e600 made the fit fail)
        let mut specks = vec![None; 30];
        specks[9] = Some(1e-300);
        specks[19] = Some(1e-300);
        let specks = Prior {
            standard: specks,
            weight: Prior::DEFAULT_WEIGHT,
        };
        let pull = Pull::new(&problem, &bounds, Some(&specks), 1.0).unwrap();
        for j in 0..2 {
            let scale = pull.scale[10 * j + 9];
            assert!((scale - MIN_MASS_SCALE).abs() < 1e-18, "{j}: {scale}");
        }
    }

    /// Without shapes the prior is the centre of the bounds with the bounds' scales; drive
    /// terms are pulled 1e-4 as hard as link parameters.
    #[test]
    fn without_shapes_the_prior_is_the_centre_of_the_bounds() {
        let problem = fixture::problem(&[0.0; 11]);
        let mut bounds = Bounds::wide(1);
        bounds.links[0] = LinkBounds {
            mass: [1.0, 4.0],
            com: [[-0.1, 0.2], [-0.05, 0.05], [0.0, 0.1]],
            inertia: [0.0, 0.05],
            tensor: [None; 6],
        };
        let pull = Pull::new(&problem, &bounds, None, 2.0).unwrap();
        assert_eq!(pull.target, centre(&problem.layout, &bounds));
        assert_eq!(pull.weight[..10], [2.0; 10]);
        assert_eq!(pull.weight[10], 2.0 * DRIVE_WEIGHT_SHARE);
        // 4 kg at up to 0.2 m: inertia 0.05 + 4 x 0.2^2, first moments 4 x 0.2
        let inertia = 0.05 + 4.0 * 0.04;
        let expected = [[inertia; 6].as_slice(), &[0.8; 3], &[4.0, 1.0]].concat();
        for (s, e) in pull.scale.iter().zip(&expected) {
            assert!((s - e).abs() < 1e-15, "{:?}", pull.scale);
        }
        // bounds of zero size: the floors 1e-9 kg and 1 mm
        let mut point = bounds.clone();
        point.links[0] = LinkBounds {
            mass: [0.0, 0.0],
            com: [[0.0; 2]; 3],
            inertia: [0.0, 0.0],
            tensor: [None; 6],
        };
        let scale = bounds_scales(&problem.layout, &point);
        assert_eq!(scale[9], 1e-9);
        assert_eq!(scale[6], 1e-9 * 1e-3);
        assert_eq!(scale[0], 1e-9);
    }

    /// A solid along a slanted segment has its axis there (the tensor maps the axis to
    /// m r^2 / 2 times it); a zero segment stands along z.
    #[test]
    fn a_solid_lies_along_its_segment() {
        // along (2, 3, 6) / 7: the axis maps to along x it, a perpendicular (3, -2, 0) to
        // across x it
        let slanted = LinkShape {
            from: [0.1, 0.0, 0.0],
            to: [0.3, 0.3, 0.6],
        };
        let s = solid(&slanted, 0.5);
        let r: f64 = 0.125;
        let along = 0.5 * s.mass * r * r;
        let across = s.mass * (3.0 * r * r + 0.25) / 12.0;
        let axis = [2.0 / 7.0, 3.0 / 7.0, 6.0 / 7.0];
        let normal = [3.0, -2.0, 0.0];
        for i in 0..3 {
            let image: f64 = (0..3).map(|k| s.inertia[i][k] * axis[k]).sum();
            assert!((image - along * axis[i]).abs() < 1e-15, "{i}");
            let image: f64 = (0..3).map(|k| s.inertia[i][k] * normal[k]).sum();
            assert!((image - across * normal[i]).abs() < 1e-15, "{i}");
        }
        assert_eq!(s.com, [0.2, 0.15, 0.3]);
        let point = LinkShape {
            from: [0.2; 3],
            to: [0.2; 3],
        };
        let s = solid(&point, 0.5);
        assert!((s.inertia[2][2] - along).abs() < 1e-15);
        assert!((s.inertia[0][0] - across).abs() < 1e-15 && s.inertia[0][2] == 0.0);
        assert_eq!(s.com, [0.2; 3]);
        // a chain of zero length sizes nothing
        assert_eq!(lengths(&[point, point]), None);
    }

    /// The default prior of a problem whose shapes size its solids.
    fn solids_prior(problem: &Problem, bounds: &Bounds) -> (Vec<f64>, Vec<f64>) {
        let shapes = problem.shapes.as_deref().unwrap();
        solid_prior(problem, bounds, &Solids::of(problem, shapes).unwrap())
    }

    /// The solid's mass and centre of mass are held 5 % of their ranges inside the bounds
    /// (the inertia scaled with the mass); a density the data cannot give (a negative fit)
    /// is that of a hollow aluminium structure, 1000 kg/m^3.
    #[test]
    fn the_solid_prior_stays_inside_the_bounds() {
        let shape = LinkShape {
            from: [0.0; 3],
            to: [0.0, 0.0, 0.4],
        };
        let unit = solid(&shape, 0.4);
        // the data weigh a solid of density `rho`
        let with_target = |rho: f64| {
            let mut values = [0.0; 11];
            for (v, u) in values.iter_mut().zip(unit.to_standard()) {
                *v = rho * u;
            }
            fixture::problem(&values).with_shapes(vec![shape]).unwrap()
        };
        let mut bounds = Bounds::wide(1);
        // the data weigh the link at 1000 solids: held at 2 - 0.05 x 1 kg, the centre 0.2 m
        // at 0.1 - 0.05 x 0.2 m
        bounds.links[0].mass = [1.0, 2.0];
        bounds.links[0].com[2] = [-0.1, 0.1];
        let (target, scale) = solids_prior(&with_target(1000.0), &bounds);
        assert_eq!(target[9], 1.95);
        assert!((target[8] - 1.95 * 0.09).abs() < 1e-15, "{}", target[8]);
        let ratio = 1.95 / unit.mass;
        let zz = unit.inertia[2][2] * ratio + 1.95 * (0.0 + 0.0);
        assert!(
            (target[5] - zz).abs() < 1e-15 * zz.abs().max(1.0),
            "{}",
            target[5]
        );
        assert_eq!(scale[9], 1.95);
        assert!((scale[6] - 1.95 * 0.4).abs() < 1e-15);
        assert!((scale[0] - 1.95 * 0.16).abs() < 1e-15);
        assert_eq!(target[10], 0.0);
        // from below: a density of 1 kg/m^3 is held at 1 + 0.05 kg, the centre at 0.3 + 0.01 m
        bounds.links[0].com[2] = [0.3, 0.5];
        let (target, _) = solids_prior(&with_target(1.0), &bounds);
        assert_eq!(target[9], 1.05);
        assert!((target[8] - 1.05 * 0.31).abs() < 1e-15, "{}", target[8]);
        // a negative weighing or none at all (a zero density): the default density
        let wide = Bounds::wide(1);
        for rho in [-1.0, 0.0] {
            let (target, _) = solids_prior(&with_target(rho), &wide);
            assert!(
                (target[9] - 1000.0 * unit.mass).abs() < 1e-12,
                "{}",
                target[9]
            );
        }
        // the fitted density, unclamped in wide bounds
        let (target, _) = solids_prior(&with_target(300.0), &wide);
        assert!(
            (target[9] - 300.0 * unit.mass).abs() < 1e-12,
            "{}",
            target[9]
        );
    }

    /// The shares are the resolution matrix's diagonal, data / (data + pull) per parameter
    /// when K = I: within 1e-9 of 1 under a negligible pull, and the known fraction under a
    /// firm one (the data's information in units of each scale: (scale / 1e-3)^2).
    #[test]
    fn the_determined_share_is_the_data_fraction() {
        let problem = fixture::problem(&[0.0; 11]);
        let pull = Pull::new(&problem, &Bounds::wide(1), None, 1e-9).unwrap();
        for weight in [1e-9, 1e6] {
            let pull = Pull {
                weight: vec![weight; 11],
                ..pull.clone()
            };
            let data: Vec<f64> = pull.scale.iter().map(|s| (s / 1e-3).powi(2)).collect();
            let top = data.iter().copied().fold(1.0, f64::max);
            let share = determined(&problem, &pull);
            for (d, v) in data.iter().zip(&share) {
                let expected = d / (d + weight + 1e-12 * top);
                assert!((v - expected).abs() < 1e-12, "{v} vs {expected} ({weight})");
            }
        }
    }

    /// Two links along x, 0.5 m each: a consistent fit can still put a light link's centre
    /// of mass far outside it, or give a speck a beam's inertia (the UR5e flange fitted at
    /// 15 g, 0.87 m away; a KR 6 R900 first link of 11.6 mg with 0.29 kg m^2); each is named
    /// with the bound that settles it, a link of its size is not.
    #[test]
    fn a_link_no_body_of_its_size_can_be_is_named() {
        let names = crate::feasible::fixture::link_names(2);
        let mut k = nalgebra::DMatrix::zeros(2, 20);
        k[(0, 5)] = 1.0;
        k[(1, 15)] = 1.0;
        let shape = LinkShape {
            from: [0.0; 3],
            to: [0.5, 0.0, 0.0],
        };
        let problem = Problem::new(names, vec!["ZZ1".into(), "ZZ2".into()], k)
            .unwrap()
            .with_target(&[1.0, 1.0], &[1e-3, 1e-3])
            .unwrap()
            .with_shapes(vec![shape; 2])
            .unwrap();
        let body = |mass: f64, com: [f64; 3], moment: f64| {
            Some(LinkInertial {
                mass,
                com,
                inertia: [[moment, 0.0, 0.0], [0.0, moment, 0.0], [0.0, 0.0, moment]],
            })
        };
        let bounds = Bounds::wide(2);
        let arm = body(10.0, [0.25, 0.0, 0.0], 0.2);
        // within three sizes of its segment (1.5 m), light, of a body's inertia: plausible
        let near = body(0.05, [1.9, 0.0, 0.0], 1e-4);
        assert!(implausible(&problem, &bounds, &[arm, near]).is_empty());
        let far = body(0.05, [0.25, 1.6, 0.0], 1e-4);
        let found = implausible(&problem, &bounds, &[arm, far]);
        assert_eq!(found.len(), 1, "{found:?}");
        assert!(
            found[0].starts_with(
                "link 2: no body of its size (about 0.5 m): mass 0.05 kg (0.498 % of the robot's \
                 10.1 kg), centre of mass [0.25, 1.6, 0] m, 1.6 m from the link's segment"
            ) && found[0]
                .contains("bounds `[links.2] com = [[-0.5, 1], [-0.5, 0.5], [-0.5, 0.5]]`"),
            "{found:?}"
        );
        // a speck (under 1 % of the robot) with a radius of gyration of 2 m
        let speck = body(0.05, [0.25, 0.0, 0.0], 0.2);
        let found = implausible(&problem, &bounds, &[arm, speck]);
        assert_eq!(found.len(), 1, "{found:?}");
        assert!(
            found[0].contains("radius of gyration 2 m about it"),
            "{found:?}"
        );
        assert!(
            found[0].contains("`[links.2] mass = [0.101, 50]`"),
            "{found:?}"
        );
        // the same inertia on a heavy link is a body the data weigh
        let heavy = body(5.0, [0.25, 0.0, 0.0], 0.2);
        assert!(implausible(&problem, &bounds, &[arm, heavy]).is_empty());
        // and it reaches the written result
        let solution = crate::feasible::Solution::assemble(
            &problem,
            &bounds,
            crate::feasible::Method::Interior,
            [arm, far]
                .iter()
                .flat_map(|l| l.unwrap().to_standard())
                .collect(),
            std::time::Duration::ZERO,
        )
        .unwrap();
        assert_eq!(solution.implausible.len(), 1);
        let text = crate::feasible::to_toml(&solution, "arm");
        assert!(
            text.contains("# warning: link 2: no body of its size"),
            "{text}"
        );
    }
}
