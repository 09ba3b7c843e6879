//! The standard parameters of each rigid body of the chain (docs/urdf.md#inertials):
//! every URDF link of the body, its centre of mass c and inertia I_c moved into robid's
//! frame j, summed as J_O += R I_c R' + m (c'c I3 - c c'), MS += m c, M += m.

use super::super::DescriptionError;
use super::super::bounds::MIN_LENGTH;
use super::super::check::{listed, show};
use super::super::file::Place;
use super::chain::Chain;
use super::rigid::{Mat3, Rigid, dot, mul, transpose};
use super::xml::{Inertial, Urdf};
use std::ops::Range;

/// How far below zero an `<inertia>`'s smallest eigenvalue may be, relative to its largest
/// entry, for rounded published values (as for parameter files).
const INERTIA_TOLERANCE: f64 = 1e-6;

/// Below this an inertia's entries and moments are printing noise of zero (kg m^2): the
/// inertia of the body's mass at [`MIN_LENGTH`] (1 µm) from its centre, below what any
/// description resolves. iCub's `head` writes `ixz="2.40741e-35"` and every other entry 0,
/// an indefinite tensor only by that noise.
fn noise(mass: f64) -> f64 {
    mass * MIN_LENGTH * MIN_LENGTH
}

/// The smallest eigenvalue of the inertia about the centre of mass `inertia` of a link of
/// `mass` when it is too far below zero for a positive semidefinite tensor: beyond
/// [`INERTIA_TOLERANCE`] of the largest entry and beyond the [`noise`]. The one test of
/// the reader (an error) and of the writer, which writes nothing the reader refuses
/// (docs/urdf.md#writing-inertials-back).
pub(super) fn indefinite(mass: f64, inertia: &[f64; 6]) -> Option<f64> {
    let lowest = lowest_eigenvalue(inertia);
    let scale = inertia.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    (lowest.is_nan() || lowest < -(INERTIA_TOLERANCE * scale).max(noise(mass))).then_some(lowest)
}

/// The principal moments of `inertia` (ascending) and by how much the largest exceeds the
/// sum of the other two, when that breaks the triangle inequality: beyond
/// [`TRIANGLE_TOLERANCE`] of the trace and beyond the [`noise`]. Shared by the reader's
/// warning and the writer.
pub(super) fn triangle_broken(mass: f64, inertia: &[f64; 6]) -> Option<([f64; 3], f64)> {
    let [ixx, ixy, ixz, iyy, iyz, izz] = *inertia;
    let m = nalgebra::Matrix3::new(ixx, ixy, ixz, ixy, iyy, iyz, ixz, iyz, izz);
    let mut d: Vec<f64> = m.symmetric_eigenvalues().iter().copied().collect();
    d.sort_by(f64::total_cmp);
    let excess = d[2] - d[0] - d[1];
    let trace = d[0] + d[1] + d[2];
    (excess > (TRIANGLE_TOLERANCE * trace).max(noise(mass))).then_some(([d[0], d[1], d[2]], excess))
}

/// The nearest inertia (about the centre of mass) of a mass distribution: the second
/// moments `tr(I)/2 E - I` with their negative eigenvalues set to 0, taken back to an
/// inertia. Positive semidefinite and within the triangle inequality (the principal
/// moments are sums of two principal second moments); an inertia that is both is returned
/// as it was, to rounding.
pub(super) fn nearest_physical(inertia: &[f64; 6]) -> [f64; 6] {
    let i = nalgebra::Matrix3::from(tensor(inertia));
    let second = nalgebra::Matrix3::identity() * (i.trace() / 2.0) - i;
    let eigen = second.symmetric_eigen();
    let clipped = eigen.eigenvalues.map(|x| x.max(0.0));
    let second = eigen.eigenvectors
        * nalgebra::Matrix3::from_diagonal(&clipped)
        * eigen.eigenvectors.transpose();
    let i = nalgebra::Matrix3::identity() * second.trace() - second;
    [
        i[(0, 0)],
        i[(0, 1)],
        i[(0, 2)],
        i[(1, 1)],
        i[(1, 2)],
        i[(2, 2)],
    ]
}

/// What makes an `<inertial>` impossible, if anything: a negative mass, or an inertia about
/// the centre of mass that is not positive semidefinite. The place, what and the fix.
fn impossible(i: &Inertial) -> Option<(Range<usize>, String, &'static str)> {
    if i.mass < 0.0 {
        return Some((
            i.mass_at.clone(),
            format!("the mass {} is negative", show(i.mass)),
            "a mass is positive or zero (kg)",
        ));
    }
    indefinite(i.mass, &i.inertia).map(|lowest| {
        (
            i.inertia_at.clone(),
            format!(
                "the inertia about the centre of mass is not positive semidefinite (smallest \
                 eigenvalue {lowest:.4e} kg m^2), so no mass distribution has it"
            ),
            "check the values and the signs of the products of inertia (`ixy` is the \
             tensor's entry, -sum m x y)",
        )
    })
}

/// How far the largest principal moment of an `<inertia>` may exceed the sum of the other
/// two, relative to their sum (the trace), before the triangle inequality counts as
/// broken: the tolerance of [`INERTIA_TOLERANCE`], so that a flat body's moments, which
/// sit on the bound, printed to six digits are not flagged.
const TRIANGLE_TOLERANCE: f64 = 1e-6;

/// A mass or inertia of a URDF's chain counts as 0 below this share of the largest of its
/// kind among the chain's links ([`negligible`]): 1e-12 is far below any real ratio
/// between the links of one robot (a gripper's finger beside a shoulder is about 1e-3 to
/// 1e-4 of its mass), and far above the rounding of f64 (1e-16), so that a value written
/// as 1e-320 or 1e-20 to mean 0 next to real ones is told as 0, as an exact 0 is. The same
/// share as the torques of `robid torques --parameters` (docs/robustness.md).
pub const NEGLIGIBLE_SHARE: f64 = 1e-12;

/// Whether `x` counts as 0 beside `largest`, the largest magnitude of its kind (masses,
/// inertias) among the chain's links: below [`NEGLIGIBLE_SHARE`] of it, or a subnormal
/// number (below 2.2e-308, `f64::MIN_POSITIVE`), which carries no digits, whatever the
/// others are. Relative, so that a robot given in other units, or a small one, is judged
/// alike; 0 is negligible.
pub fn negligible(x: f64, largest: f64) -> bool {
    let x = x.abs();
    x < f64::MIN_POSITIVE || x < NEGLIGIBLE_SHARE * largest.abs()
}

/// The largest mass and the largest magnitude of an `<inertia>` entry among `inertials`:
/// what [`negligible`] compares a link's values with.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Largest {
    mass: f64,
    inertia: f64,
}

impl Largest {
    fn of<'a>(inertials: impl Iterator<Item = &'a Inertial>) -> Largest {
        inertials.fold(Largest::default(), |l, i| Largest {
            mass: l.mass.max(i.mass.abs()),
            inertia: i.inertia.iter().fold(l.inertia, |m, x| m.max(x.abs())),
        })
    }
}

/// The two kinds of `<inertial>` that no body has but that robid reads with a warning
/// ([`unphysical`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Unphysical {
    /// A zero mass with a nonzero inertia.
    MasslessInertia,
    /// Principal moments breaking the triangle inequality.
    Triangle,
}

/// A value computed from a URDF's numbers, to four significant digits.
fn short(v: f64) -> String {
    show(format!("{v:.3e}").parse().unwrap_or(v))
}

/// What makes a possible `<inertial>` (no negative mass, inertia positive semidefinite, see
/// [`impossible`]) that of no body, if anything: a zero mass with a nonzero inertia (each
/// judged by [`negligible`] beside the `largest` of the chain: a mass of 1e-320 with an
/// inertia of 0.01 kg m^2 is one), or principal moments of the inertia about the centre of
/// mass that break the triangle inequality (the largest exceeds the sum of the other two by
/// more than [`TRIANGLE_TOLERANCE`] of the trace, and more than the [`noise`]). The kind,
/// where, and what, with the values.
fn unphysical(i: &Inertial, largest: Largest) -> Option<(Unphysical, Range<usize>, String)> {
    let [ixx, ixy, ixz, iyy, iyz, izz] = i.inertia;
    if negligible(i.mass, largest.mass)
        && i.inertia.iter().any(|&x| !negligible(x, largest.inertia))
    {
        let mass = if i.mass == 0.0 {
            "the mass is 0".to_owned()
        } else {
            format!(
                "the mass {} kg is negligible (below {NEGLIGIBLE_SHARE:e} of the chain's \
                 largest, {} kg, or subnormal), as good as 0,",
                show(i.mass),
                show(largest.mass)
            )
        };
        return Some((
            Unphysical::MasslessInertia,
            i.mass_at.clone(),
            format!(
                "{mass} but the inertia is not (ixx {}, ixy {}, ixz {}, iyy {}, iyz {}, izz {} \
                 kg m^2)",
                show(ixx),
                show(ixy),
                show(ixz),
                show(iyy),
                show(iyz),
                show(izz)
            ),
        ));
    }
    triangle_broken(i.mass, &i.inertia).map(|(d, excess)| {
        let diagonal = [ixy, ixz, iyz].iter().all(|&x| x == 0.0);
        (
            Unphysical::Triangle,
            i.inertia_at.clone(),
            format!(
                "the principal moments {}, {}, {} kg m^2 of the inertia about the centre of \
                 mass break the triangle inequality: the largest exceeds the sum of the other \
                 two by {} kg m^2{}",
                short(d[0]),
                short(d[1]),
                short(d[2]),
                short(excess),
                if diagonal {
                    ""
                } else {
                    " (the moments of `ixx` to `izz` with the products of inertia)"
                }
            ),
        )
    })
}

/// A URDF link of the chain's bodies whose `<inertial>` no body has: a zero mass with a
/// nonzero inertia, or principal moments that break the triangle inequality. The model's
/// kinematics and identification do not use a URDF's inertials, so robid reads such a file
/// with a warning (docs/urdf.md#inertials); where the inertials are the parameters, a
/// simulation must not use them.
#[derive(Clone, Debug, PartialEq)]
pub struct UnphysicalInertial {
    /// The URDF link.
    pub link: String,
    /// What is wrong, with the values: "the mass is 0 but the inertia is not (...)".
    pub problem: String,
}

/// Checks the inertials the model uses, those of the links of the chain's bodies: an
/// impossible one (a negative mass, an inertia that is not positive semidefinite) is an
/// error naming its link; one that is possible but no body's (a zero mass with an inertia,
/// moments breaking the triangle inequality) is warned about, one warning per kind naming
/// the links, and returned. The other links' inertials (the fixed base, links beside or
/// above the base) are not used, so an impossible one there gets one warning
/// (docs/urdf.md#inertials): TIAGo's antennas, fixed to its base, have products of inertia
/// too large for their moments.
pub(super) fn check(
    place: &Place<'_>,
    urdf: &Urdf,
    chain: &Chain,
    warnings: &mut Vec<String>,
) -> Result<Vec<UnphysicalInertial>, DescriptionError> {
    let mut used = vec![false; urdf.links.len()];
    for &l in chain.bodies.iter().flatten() {
        used[l] = true;
    }
    let mut errors = Vec::new();
    let mut unused = Vec::new();
    for (link, &used) in urdf.links.iter().zip(&used) {
        let Some((at, what, help)) = link.inertial.as_ref().and_then(impossible) else {
            continue;
        };
        if used {
            errors.push(place.invalid(at, format!("link `{}`: {what}", link.name), help));
        } else {
            unused.push((link, at, what));
        }
    }
    if !errors.is_empty() {
        return Err(DescriptionError::from_errors(errors));
    }
    let largest = Largest::of(
        urdf.links
            .iter()
            .zip(&used)
            .filter(|&(_, &used)| used)
            .filter_map(|(link, _)| link.inertial.as_ref()),
    );
    let mut found = Vec::new();
    for kind in [Unphysical::MasslessInertia, Unphysical::Triangle] {
        let links: Vec<(&str, Range<usize>, String)> = urdf
            .links
            .iter()
            .zip(&used)
            .filter(|&(_, &used)| used)
            .filter_map(|(link, _)| {
                let (k, at, what) = unphysical(link.inertial.as_ref()?, largest)?;
                (k == kind).then_some((link.name.as_str(), at, what))
            })
            .collect();
        let Some((first, at, what)) = links.first() else {
            continue;
        };
        let fix = match kind {
            Unphysical::MasslessInertia => {
                "give the link its mass, or write its inertia as zeros (a massless link)"
            }
            Unphysical::Triangle => {
                "correct the `<inertia>` (no principal moment of a body exceeds the sum of the \
                 other two; a placeholder such as 1, 100, 1 breaks it)"
            }
        };
        let others = match &links[1..] {
            [] => String::new(),
            [(name, ..)] => format!(" (link `{name}` has such an inertial too)"),
            rest => {
                let names: Vec<String> =
                    rest.iter().map(|(name, ..)| format!("`{name}`")).collect();
                format!(" (links {} have such inertials too)", listed(names))
            }
        };
        warnings.push(place.warning(
            at.start,
            &format!(
                "link `{first}`: {what}, so no body has this inertial; robid's kinematics and \
                 identification do not use it, but where the URDF's inertials are the \
                 parameters (`robid torques`, `excite` and `simulate` without --parameters, \
                 the prior of `robid feasible`) it is used as written, and their results are \
                 those of the file, not of a robot; {fix}, or give parameters of your \
                 own{others}"
            ),
        ));
        found.extend(links.iter().map(|(name, _, what)| UnphysicalInertial {
            link: (*name).to_owned(),
            problem: what.clone(),
        }));
    }
    if let Some((first, at, what)) = unused.first() {
        let others = if unused.len() > 1 {
            let names: Vec<String> = unused[1..]
                .iter()
                .map(|(l, ..)| format!("`{}`", l.name))
                .collect();
            format!(
                " ({} {} {} an impossible inertial too, also unused)",
                if names.len() == 1 { "link" } else { "links" },
                listed(names.iter().cloned()),
                if names.len() == 1 { "has" } else { "have" }
            )
        } else {
            String::new()
        };
        warnings.push(place.warning(
            at.start,
            &format!(
                "link `{}`: {what}; the link is fixed to the base or lies outside the chain, \
                 so the model does not use its inertial; correct it where the file is used \
                 with that link{others}",
                first.name
            ),
        ));
    }
    Ok(found)
}

/// The inertia tensor of a URDF `<inertia>` (`ixy` is the tensor entry, as robid's `XY`,
/// docs/conventions.md#standard-parameters).
pub(super) fn tensor(i: &[f64; 6]) -> Mat3 {
    [[i[0], i[1], i[2]], [i[1], i[3], i[4]], [i[2], i[4], i[5]]]
}

/// The smallest eigenvalue of the symmetric tensor `ixx ixy ixz iyy iyz izz`.
pub(super) fn lowest_eigenvalue(i: &[f64; 6]) -> f64 {
    let m = nalgebra::Matrix3::new(i[0], i[1], i[2], i[1], i[3], i[4], i[2], i[4], i[5]);
    m.symmetric_eigenvalues().min()
}

/// Standard parameters `[XX XY XZ YY YZ ZZ MX MY MZ M]` of one `<inertial>` of a link whose
/// frame is `link` in the target frame.
pub(super) fn parameters(link: &Rigid, inertial: &Inertial) -> [f64; 10] {
    let com = link.then(&inertial.origin);
    let m = inertial.mass;
    let c = com.p;
    let rotated = mul(&mul(&com.r, &tensor(&inertial.inertia)), &transpose(&com.r));
    let cc = dot(c, c);
    let j = |a: usize, b: usize| {
        let identity = if a == b { cc } else { 0.0 };
        rotated[a][b] + m * (identity - c[a] * c[b])
    };
    [
        j(0, 0),
        j(0, 1),
        j(0, 2),
        j(1, 1),
        j(1, 2),
        j(2, 2),
        m * c[0],
        m * c[1],
        m * c[2],
        m,
    ]
}

/// The sum of standard parameters.
pub(super) fn sum(a: [f64; 10], b: [f64; 10]) -> [f64; 10] {
    std::array::from_fn(|k| a[k] + b[k])
}

/// The mass, centre of mass and inertia about it (`ixx ixy ixz iyy iyz izz`) of standard
/// parameters (`None` when the mass is not positive).
pub(super) fn physical(p: &[f64; 10]) -> Option<(f64, [f64; 3], [f64; 6])> {
    let m = p[9];
    if m <= 0.0 || !m.is_finite() {
        return None;
    }
    let c = [p[6] / m, p[7] / m, p[8] / m];
    let cc = dot(c, c);
    let about = |value: f64, a: usize, b: usize| {
        let identity = if a == b { cc } else { 0.0 };
        value - m * (identity - c[a] * c[b])
    };
    Some((
        m,
        c,
        [
            about(p[0], 0, 0),
            about(p[1], 0, 1),
            about(p[2], 0, 2),
            about(p[3], 1, 1),
            about(p[4], 1, 2),
            about(p[5], 2, 2),
        ],
    ))
}

fn skew(v: [f64; 3]) -> Mat3 {
    [[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]]
}

/// Standard parameters expressed in another frame, exactly (they move linearly): `p` in
/// frame b, `b_in_a` frame b in frame a (R, t); the result in frame a:
/// J_a = R J_b R' - S(t) S(R MS) - S(R MS) S(t) - M S(t) S(t), MS_a = R MS + M t
/// (S the cross-product matrix, J = -integral S(r) S(r) dm).
pub(super) fn moved(b_in_a: &Rigid, p: &[f64; 10]) -> [f64; 10] {
    let r = &b_in_a.r;
    let t = b_in_a.p;
    let m = p[9];
    let ms = b_in_a.apply_vector([p[6], p[7], p[8]]);
    let j = mul(
        &mul(r, &tensor(&[p[0], p[1], p[2], p[3], p[4], p[5]])),
        &transpose(r),
    );
    let (st, sm) = (skew(t), skew(ms));
    let (a, b, c) = (mul(&st, &sm), mul(&sm, &st), mul(&st, &st));
    let e = |i: usize, k: usize| j[i][k] - a[i][k] - b[i][k] - m * c[i][k];
    [
        e(0, 0),
        e(0, 1),
        e(0, 2),
        e(1, 1),
        e(1, 2),
        e(2, 2),
        ms[0] + m * t[0],
        ms[1] + m * t[1],
        ms[2] + m * t[2],
        m,
    ]
}
