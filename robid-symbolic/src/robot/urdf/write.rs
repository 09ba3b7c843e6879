//! Writing standard parameters back into a URDF (docs/urdf.md#writing-inertials-back):
//! each chain link's `<inertial>` replaced, every other byte untouched.

use super::super::DescriptionError;
use super::super::file::Place;
use super::UrdfChain;
use super::inertial::{
    indefinite, moved, nearest_physical, parameters, physical, sum, triangle_broken,
};
use super::rigid::Rigid;
use super::xml::{self, Link};

/// Relative size (of the largest parameter of the body) of a change that is rounding: a
/// negative mass below it is 0, and an inertia about the centre of mass that is
/// indefinite, or breaks the triangle inequality, by less is moved to the nearest physical
/// one. A body computed as a whole (`robid feasible`'s pseudo-inertia) minus attached links
/// written separately leaves such a remainder: a 50 kg point mass's was indefinite by
/// 1.7e-8 kg m^2 beside a 53 kg body. Far below what identification resolves, far above
/// f64's rounding (1e-16).
const ROUNDING: f64 = 1e-9;

/// What is physical about standard parameters.
enum Body {
    /// Nothing (every value within rounding of zero).
    Empty,
    /// Mass, centre of mass and inertia about it (`ixx ixy ixz iyy iyz izz`).
    Solid(f64, [f64; 3], [f64; 6]),
    /// Zero mass and first moment, an inertia about the origin (a rotor-like body).
    Massless([f64; 6]),
    /// Negative mass, or an inertia that is not positive semi-definite.
    NotPhysical,
}

/// The inertia to write for `inertia` about the centre of mass of `mass`, judged by the
/// reader's own tests ([`indefinite`], [`triangle_broken`]) so that the written file reads
/// back: as it is when they pass; else the nearest physical inertia when that is within
/// `tolerance` (rounding) of it; else as it is when only the triangle inequality is broken
/// (the reader warns, as of the file it came from); else `None`, not physical.
fn settled(mass: f64, inertia: &[f64; 6], tolerance: f64) -> Option<[f64; 6]> {
    let semidefinite = indefinite(mass, inertia).is_none();
    if semidefinite && triangle_broken(mass, inertia).is_none() {
        return Some(*inertia);
    }
    let nearest = nearest_physical(inertia);
    let change = nearest
        .iter()
        .zip(inertia)
        .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
    if change <= tolerance && indefinite(mass, &nearest).is_none() {
        return Some(nearest);
    }
    semidefinite.then_some(*inertia)
}

fn classify(p: &[f64; 10], scale: f64) -> Body {
    let tolerance = ROUNDING * scale.max(f64::MIN_POSITIVE);
    if p.iter().any(|x| !x.is_finite()) {
        return Body::NotPhysical;
    }
    if p.iter().all(|x| x.abs() <= tolerance) {
        return Body::Empty;
    }
    if p[9].abs() <= tolerance {
        let j = [p[0], p[1], p[2], p[3], p[4], p[5]];
        if p[6..9].iter().all(|x| x.abs() <= tolerance) {
            return settled(0.0, &j, tolerance).map_or(Body::NotPhysical, Body::Massless);
        }
        return Body::NotPhysical;
    }
    match physical(p) {
        Some((m, c, i)) => {
            settled(m, &i, tolerance).map_or(Body::NotPhysical, |i| Body::Solid(m, c, i))
        }
        None => Body::NotPhysical,
    }
}

/// The text of an `<inertial>` for `body`, its lines indented by `indent`.
fn element(body: &Body, indent: &str) -> String {
    let (m, c, i) = match body {
        Body::Solid(m, c, i) => (*m, *c, *i),
        Body::Massless(j) => (0.0, [0.0; 3], *j),
        Body::Empty | Body::NotPhysical => return String::new(),
    };
    format!(
        "<inertial>\n{indent}  <origin xyz=\"{:?} {:?} {:?}\" rpy=\"0 0 0\"/>\n{indent}  <mass value=\"{m:?}\"/>\n{indent}  <inertia ixx=\"{:?}\" ixy=\"{:?}\" ixz=\"{:?}\" iyy=\"{:?}\" iyz=\"{:?}\" izz=\"{:?}\"/>\n{indent}</inertial>",
        c[0], c[1], c[2], i[0], i[1], i[2], i[3], i[4], i[5]
    )
}

/// The indentation of the line holding byte `at`.
fn indentation(text: &str, at: usize) -> String {
    let start = text[..at].rfind('\n').map_or(0, |k| k + 1);
    text[start..at]
        .chars()
        .take_while(|c| c.is_whitespace())
        .collect()
}

/// The splice that puts `body` as the `<inertial>` of `link`.
fn splice(text: &str, link: &Link, body: &Body) -> (std::ops::Range<usize>, String) {
    if let Some(i) = &link.inertial {
        let indent = indentation(text, i.range.start);
        return (i.range.clone(), element(body, &indent));
    }
    let inner = format!("{}  ", indentation(text, link.range.start));
    let new = element(body, &inner);
    if new.is_empty() {
        return (link.range.start..link.range.start, String::new());
    }
    let element_text = &text[link.range.clone()];
    if link.empty {
        // `<link name="x"/>` -> `<link name="x">` inertial `</link>`
        let slash = link.range.start + element_text.rfind("/>").unwrap_or(element_text.len());
        let closing = indentation(text, link.range.start);
        (
            slash..link.range.end,
            format!(">\n{inner}{new}\n{closing}</link>"),
        )
    } else {
        let close = link.range.start + element_text.rfind("</").unwrap_or(element_text.len());
        (
            close..close,
            format!("  {new}\n{}", indentation(text, link.range.start)),
        )
    }
}

/// Writes `text` back with the `<inertial>` of each chain link replaced by `inertials[j]`
/// (standard parameters in robid frame j), in the URDF link's own frame (origin at the
/// centre of mass, rpy 0, inertia about the centre of mass in the link frame), every other
/// byte untouched; a link without `<inertial>` gets one (`<link .../>` is expanded).
///
/// Attached links keep their inertials and the chain link gets the difference. What is
/// written passes the reader's tests, so the file reads back: a difference that fails them
/// by rounding (1e-9 of the body's largest parameter) is moved to the nearest physical
/// inertia; one that is not physical beyond that (negative mass, or inertia about its
/// centre of mass not positive semi-definite) puts the whole body on the chain link and
/// removes the attached links' inertials, with a warning naming them. Numbers are written
/// in Rust's shortest round-trip form. Returns the text and the warnings.
///
/// # Errors
/// `text` is not the URDF `chain` was read from (a chain link is missing), the number of
/// parameter sets differs from the chain's joints, or a body's parameters are not
/// physical (identified parameters can be made physical with `robid feasible`).
///
/// # Examples
/// ```
/// use robid_symbolic::robot::{write_inertials, ChainSelection};
/// use robid_symbolic::Robot;
/// let urdf = r#"<robot name="arm"><link name="base"/><link name="upper"/>
///   <joint name="shoulder" type="revolute"><parent link="base"/><child link="upper"/>
///     <axis xyz="0 0 1"/></joint></robot>"#;
/// let chain = Robot::from_urdf(urdf, "arm.urdf", &ChainSelection::default())?;
/// let identified = [[0.3, 0.0, 0.0, 0.3, 0.0, 0.1, 0.2, 0.0, 0.0, 2.0]];
/// let (written, _) = write_inertials(urdf, "arm.urdf", &chain, &identified)?;
/// let again = Robot::from_urdf(&written, "arm.urdf", &ChainSelection::default())?;
/// assert!((again.links[0].inertial[6] - 0.2).abs() < 1e-15);
/// # Ok::<(), robid_symbolic::DescriptionError>(())
/// ```
pub fn write_inertials(
    text: &str,
    file: &str,
    chain: &UrdfChain,
    inertials: &[[f64; 10]],
) -> Result<(String, Vec<String>), DescriptionError> {
    if inertials.len() != chain.links.len() {
        return Err(DescriptionError::Argument {
            argument: "`inertials` of `write_inertials`".to_owned(),
            message: format!(
                "{} parameter sets for a chain of {} joints",
                inertials.len(),
                chain.links.len()
            ),
            help: "give one set of ten standard parameters per joint, base to tip".to_owned(),
        });
    }
    let place = Place { file, text };
    let urdf = xml::read(&place)?;
    let find = |name: &str| {
        urdf.links
            .iter()
            .find(|l| l.name == name)
            .ok_or_else(|| DescriptionError::Argument {
                argument: "`text` of `write_inertials`".to_owned(),
                message: format!("the URDF has no link `{name}` of the chain"),
                help: "give the URDF the chain was read from".to_owned(),
            })
    };
    let mut splices = Vec::new();
    let mut warnings = Vec::new();
    for (k, (link, target)) in chain.links.iter().zip(inertials).enumerate() {
        let frame = Rigid::from_pose(&link.frame);
        let scale = target.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        let not_physical = || DescriptionError::Argument {
            argument: format!("`inertials[{k}]` of `write_inertials`"),
            message: format!(
                "the parameters of link `{}` {target:?} are not physical (negative mass, or an inertia about the centre of mass that is not positive semi-definite)",
                link.link
            ),
            help:
                "a URDF holds physical links: make the parameters physical first (robid feasible)"
                    .to_owned(),
        };
        if matches!(classify(target, scale), Body::NotPhysical) {
            return Err(not_physical());
        }
        let mut attached_sum = [0.0; 10];
        let mut carrying = Vec::new();
        for a in &link.attached {
            let urdf_link = find(&a.name)?;
            if let Some(i) = &urdf_link.inertial {
                let in_frame = frame.then(&Rigid::from_pose(&a.frame));
                attached_sum = sum(attached_sum, parameters(&in_frame, i));
                carrying.push(urdf_link);
            }
        }
        let difference: [f64; 10] = std::array::from_fn(|i| target[i] - attached_sum[i]);
        let in_link = frame.inverse();
        let own = classify(&moved(&in_link, &difference), scale);
        let (own, removed) = if matches!(own, Body::NotPhysical) {
            (classify(&moved(&in_link, target), scale), carrying)
        } else {
            (own, Vec::new())
        };
        if matches!(own, Body::NotPhysical) {
            return Err(not_physical());
        }
        let chain_link = find(&link.link)?;
        splices.push(splice(text, chain_link, &own));
        if !removed.is_empty() {
            let names: Vec<String> = removed.iter().map(|l| format!("`{}`", l.name)).collect();
            warnings.push(place.warning(
                chain_link.range.start,
                &format!(
                    "the parameters of link `{}` minus the inertials of its attached links {} \
                     are not physical, so the whole body's inertial is written on `{}` and \
                     theirs are removed; check the attached links' inertials if they matter \
                     on their own",
                    link.link,
                    names.join(", "),
                    link.link
                ),
            ));
            for l in removed {
                if let Some(i) = &l.inertial {
                    splices.push((i.range.clone(), String::new()));
                }
            }
        }
    }
    splices.sort_by_key(|(range, _)| range.start);
    let mut out = String::with_capacity(text.len() + 512 * splices.len());
    let mut at = 0;
    for (range, replacement) in splices {
        out.push_str(&text[at..range.start]);
        out.push_str(&replacement);
        at = range.end;
    }
    out.push_str(&text[at..]);
    Ok((out, warnings))
}
