//! User bounds on each link's mass, centre of mass and inertia, and on the total
//! mass (Gaz et al. 2016, Tables I and III), read from TOML:
//!
//! ```toml
//! total_mass = [15.0, 17.0]           # optional
//! margin = 1e-6                       # optional: pseudo-inertia >= margin * I (default:
//!                                     # 1e-6, or 1 % of the prior's smallest eigenvalue)
//!
//! [default]                           # every link without its own table
//! mass = [0.0, 10.0]                  # kg
//! com = [[-0.5, 0.5], [-0.5, 0.5], [-0.5, 0.5]]   # box in the link frame, m
//! inertia = [0.0, 1.0]                # inertia about the centre of mass, kg m^2: its diagonal
//!                                     # (imposed), its principal moments (checked)
//!
//! [links.3]                           # link 3 (1-based); missing keys come from [default]
//! mass = [2.0, 4.0]
//! # elements of the inertia about the centre of mass in the link frame (Gaz et al.'s
//! # Table III), each optional
//! inertia_tensor = { xx = [0.01, 0.05], yy = [0.01, 0.05], zz = [0.0, 0.02], xy = [-0.01, 0.01] }
//! ```

use crate::DataError;
use crate::FeasibleError;
use std::collections::BTreeMap;

use serde::Deserialize;

use crate::data::{KeyMap, TomlFile};
use crate::limits::MAX_PARAMETER;
use crate::{Error, Result, num};

/// Bounds of one link.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinkBounds {
    /// Mass range, kg.
    pub mass: [f64; 2],
    /// Centre-of-mass box in the link frame, per axis, m.
    pub com: [[f64; 2]; 3],
    /// Range of the inertia about the centre of mass, kg m^2: the solvers impose it on the
    /// diagonal elements in the link frame; the principal moments are checked against it
    /// after the solve (the largest can exceed the largest diagonal element), and one
    /// outside is reported as a bound not met.
    pub inertia: [f64; 2],
    /// Ranges of the elements of the inertia tensor about the centre of mass, in the link
    /// frame, in the order of [`TENSOR_ELEMENTS`] (kg m^2); `None`: not bounded.
    pub tensor: [Option<[f64; 2]>; 6],
}

/// The elements of an inertia tensor a bound may name: key, row, column.
pub const TENSOR_ELEMENTS: [(&str, usize, usize); 6] = [
    ("xx", 0, 0),
    ("yy", 1, 1),
    ("zz", 2, 2),
    ("xy", 0, 1),
    ("xz", 0, 2),
    ("yz", 1, 2),
];

impl Default for LinkBounds {
    /// Wide bounds for an arm of ordinary size: 0..50 kg, a 2 m box, moments up to 5 kg m^2.
    fn default() -> LinkBounds {
        LinkBounds {
            mass: [0.0, 50.0],
            com: [[-1.0, 1.0]; 3],
            inertia: [0.0, 5.0],
            tensor: [None; 6],
        }
    }
}

impl LinkBounds {
    /// The centre of the bounds: mid mass, mid box, and an isotropic inertia at mid range.
    /// This is the stated value of everything the base parameters do not determine.
    pub fn centre(&self) -> ([f64; 3], f64, f64) {
        let mid = |r: [f64; 2]| 0.5 * (r[0] + r[1]);
        (self.com.map(mid), mid(self.mass), mid(self.inertia))
    }
}

/// Bounds of every link plus the total mass and the consistency margin.
#[derive(Debug, Clone, PartialEq)]
pub struct Bounds {
    /// Per link (0-based).
    pub links: Vec<LinkBounds>,
    /// Total mass range, kg.
    pub total_mass: Option<[f64; 2]>,
    /// Every pseudo-inertia must be at least `margin` times the identity; `None`: the
    /// default for the robot ([`Bounds::margin_for`]).
    pub margin: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawLink {
    #[serde(default, deserialize_with = "range")]
    mass: Option<[f64; 2]>,
    #[serde(default, deserialize_with = "com_ranges")]
    com: Option<[[f64; 2]; 3]>,
    #[serde(default, deserialize_with = "range")]
    inertia: Option<[f64; 2]>,
    inertia_tensor: Option<RawTensor>,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct RawTensor {
    #[serde(default, deserialize_with = "range")]
    xx: Option<[f64; 2]>,
    #[serde(default, deserialize_with = "range")]
    yy: Option<[f64; 2]>,
    #[serde(default, deserialize_with = "range")]
    zz: Option<[f64; 2]>,
    #[serde(default, deserialize_with = "range")]
    xy: Option<[f64; 2]>,
    #[serde(default, deserialize_with = "range")]
    xz: Option<[f64; 2]>,
    #[serde(default, deserialize_with = "range")]
    yz: Option<[f64; 2]>,
}

impl RawTensor {
    /// In the order of [`TENSOR_ELEMENTS`].
    fn elements(&self) -> [Option<[f64; 2]>; 6] {
        [self.xx, self.yy, self.zz, self.xy, self.xz, self.yz]
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Raw {
    #[serde(default, deserialize_with = "range")]
    total_mass: Option<[f64; 2]>,
    margin: Option<f64>,
    default: Option<RawLink>,
    #[serde(default)]
    links: BTreeMap<String, RawLink>,
}

/// A `[lo, hi]` range, refused unless it has two values: toml read `[1, 2, 3]` into a
/// `[f64; 2]` without a word.
fn range<'de, D: serde::Deserializer<'de>>(
    d: D,
) -> std::result::Result<Option<[f64; 2]>, D::Error> {
    Option::<Vec<f64>>::deserialize(d)?.map(two).transpose()
}

/// The `com` ranges of x, y and z, each `[lo, hi]` ([`range`]).
fn com_ranges<'de, D: serde::Deserializer<'de>>(
    d: D,
) -> std::result::Result<Option<[[f64; 2]; 3]>, D::Error> {
    let Some(axes) = Option::<Vec<Vec<f64>>>::deserialize(d)? else {
        return Ok(None);
    };
    let n = axes.len();
    let pairs = axes
        .into_iter()
        .zip(["x", "y", "z"].iter().chain(std::iter::repeat(&"next")))
        .map(|(v, axis)| {
            let n = v.len();
            <[f64; 2]>::try_from(v).map_err(|_| {
                serde::de::Error::custom(format!(
                    "the {axis} range has {}; give two, [lo, hi]",
                    crate::Count(n, "value")
                ))
            })
        })
        .collect::<std::result::Result<Vec<_>, _>>()?;
    <[[f64; 2]; 3]>::try_from(pairs)
        .map(Some)
        .map_err(|_| serde::de::Error::invalid_length(n, &"three ranges [lo, hi], of x, y and z"))
}

fn two<E: serde::de::Error>(v: Vec<f64>) -> std::result::Result<[f64; 2], E> {
    let n = v.len();
    <[f64; 2]>::try_from(v).map_err(|_| E::invalid_length(n, &"two values [lo, hi]"))
}

/// The least upper bound of a link's mass, kg: one milligram. Below it a link carries
/// nothing a robot's torques could tell from nothing, and the fits' scales lose their
/// digits (`mass = [0, 1e-100]` made the interior-point fit leave the consistent set).
pub const MIN_LINK_MASS: f64 = 1e-6;

/// Default pseudo-inertia margin (kg, kg m^2) of links of ordinary size.
pub const DEFAULT_MARGIN: f64 = 1e-6;

/// The default margin is at most this share of the smallest eigenvalue of the prior links'
/// pseudo-inertias, so that it never holds a small link (a 12 g gripper jaw's is 2.6e-7)
/// away from a consistent prior.
const MARGIN_SHARE: f64 = 1e-2;

/// The least default margin: a prior link flat to rounding (its smallest eigenvalue about
/// 1e-20) lowered the margin to about 1e-22, and results had eigenvalues of -1e-17.
const MIN_DEFAULT_MARGIN: f64 = 1e-12;

impl Bounds {
    /// The default bounds ([`LinkBounds::default`]) for `links` links, no total-mass range.
    pub fn wide(links: usize) -> Bounds {
        Bounds {
            links: vec![LinkBounds::default(); links],
            total_mass: None,
            margin: None,
        }
    }

    /// [`Bounds::wide`] widened for a robot larger than an ordinary arm: each range reaches
    /// at least twice the largest value among the prior links (the values of `prior`, else
    /// solids of the density the identified parameters give; see
    /// docs/command-line.md#robid-feasible): their masses, centre-of-mass coordinates and
    /// principal moments about the centre of mass. A 250 kg link is not held at 50 kg; an
    /// ordinary arm keeps the wide bounds.
    ///
    /// ```
    /// use robid_runtime::feasible::{Bounds, Problem};
    /// use nalgebra::DMatrix;
    /// let names: Vec<String> = ["XX1", "XY1", "XZ1", "YY1", "YZ1", "ZZ1", "MX1", "MY1", "MZ1", "M1"]
    ///     .map(String::from)
    ///     .to_vec();
    /// let problem = Problem::new(names.clone(), names, DMatrix::identity(10, 10))
    ///     .unwrap()
    ///     // 400 kg, centre of mass 0.5 m up z, 10 kg m^2 about it on every axis
    ///     .with_target(&[110.0, 0.0, 0.0, 110.0, 0.0, 10.0, 0.0, 0.0, 200.0, 400.0], &[1e-3; 10])
    ///     .unwrap();
    /// let prior = robid_runtime::feasible::Prior {
    ///     standard: problem.target.iter().map(|&v| Some(v)).collect(),
    ///     weight: 1.0,
    /// };
    /// let bounds = Bounds::wide_for(&problem, Some(&prior));
    /// assert_eq!(bounds.links[0].mass, [0.0, 800.0]);
    /// assert!((bounds.links[0].inertia[1] - 20.0).abs() < 1e-9);
    /// assert_eq!(bounds.links[0].com, [[-1.0, 1.0]; 3]);
    /// assert_eq!(Bounds::wide_for(&problem, None), Bounds::wide(1));
    /// ```
    pub fn wide_for(problem: &super::Problem, prior: Option<&super::Prior>) -> Bounds {
        let mut b = LinkBounds::default();
        let widen = |r: &mut [f64; 2], v: f64| {
            if v.is_finite() {
                r[1] = r[1].max((2.0 * v).min(MAX_PARAMETER));
            }
        };
        for l in super::prior::prior_links(problem, prior).iter().flatten() {
            widen(&mut b.mass, l.mass);
            let far = l.com.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            for axis in &mut b.com {
                widen(axis, far);
                axis[0] = -axis[1];
            }
            let top = l.principal_moments().iter().fold(0.0f64, |a, v| a.max(*v));
            widen(&mut b.inertia, top);
        }
        Bounds {
            links: vec![b; problem.layout.links.len()],
            ..Bounds::wide(problem.layout.links.len())
        }
    }

    /// Reads bounds for a robot with `links` links; `path` names the file in errors, which
    /// give a wrong value's key at its file:line:column ([`crate::DataError::ConfigKey`]).
    pub fn from_toml(text: &str, path: &str, links: usize) -> Result<Bounds> {
        Self::parse(text, path, links).map_err(|e| Self::locate(text, path, e))
    }

    /// An error about bounds (owner `Bounds`, such as those of [`Bounds::margin_for`])
    /// placed in the bounds file `text` read from `path`: at its key's file:line:column,
    /// a link's key at `[default]` when the link's own table does not give it; other
    /// errors unchanged.
    pub fn locate(text: &str, path: &str, e: Error) -> Error {
        let Error::Setting {
            owner,
            mut key,
            problem,
        } = e
        else {
            return e;
        };
        if owner != "Bounds" {
            return Error::Setting {
                owner,
                key,
                problem,
            };
        }
        let keys = KeyMap::parse(text);
        let mut at = keys.find(&key);
        if at.is_none()
            && let Some((_, rest)) = key.strip_prefix("links.").and_then(|k| k.split_once('.'))
        {
            let inherited = format!("default.{rest}");
            if let Some(found) = keys.find(&inherited) {
                (key, at) = (inherited, Some(found));
            }
        }
        Error::Data(DataError::ConfigKey {
            path: path.into(),
            line: at.map(|a| a.0),
            column: at.map(|a| a.1),
            key,
            problem,
        })
    }

    fn parse(text: &str, path: &str, links: usize) -> Result<Bounds> {
        let raw: Raw = toml::from_str(text).map_err(|e| {
            crate::toml_syntax::syntax_error(text, path.as_ref(), TomlFile::Bounds, &e)
        })?;
        // each table's ranges at their own keys first: a mistake in [default] is not a
        // mistake of the first link that inherits it
        if let Some(d) = &raw.default {
            d.check("default", d.tensor())?;
        }
        for (key, link) in &raw.links {
            link.check(&format!("links.{key}"), link.tensor())?;
        }
        let base = merge(LinkBounds::default(), raw.default.as_ref());
        let mut out = vec![base; links];
        // in file order, so that of one link given twice (`[links.1]`, `[links.01]`: two
        // keys for toml, one link here) the second table is named
        let keys = KeyMap::parse(text);
        let mut given: Vec<(&String, &RawLink)> = raw.links.iter().collect();
        given.sort_by_key(|(key, _)| keys.find(&format!("links.{key}")));
        let mut seen: Vec<Option<&str>> = vec![None; links];
        for (key, link) in given {
            let j: usize = key
                .parse()
                .ok()
                .filter(|j| (1..=links).contains(j))
                .ok_or_else(|| {
                    Error::setting(
                        "Bounds",
                        &format!("links.{key}"),
                        format!("not a link number; write 1 to {links}"),
                    )
                })?;
            if let Some(first) = seen[j - 1] {
                let line = keys
                    .find(&format!("links.{first}"))
                    .map_or(String::new(), |(line, _)| format!(" on line {line}"));
                return Err(Error::setting(
                    "Bounds",
                    &format!("links.{key}"),
                    format!(
                        "link {j} is given twice, as [links.{}]{line} and here; give one \
                         table per link",
                        crate::names::short(first)
                    ),
                ));
            }
            seen[j - 1] = Some(key);
            out[j - 1] = merge(base, Some(link));
        }
        let bounds = Bounds {
            links: out,
            total_mass: raw.total_mass,
            margin: raw.margin,
        };
        bounds.validate()?;
        Ok(bounds)
    }

    /// The margin the solvers impose: the one given, else [`DEFAULT_MARGIN`], lowered to
    /// 1 % of the smallest eigenvalue of the links' pseudo-inertias in `prior` (standard
    /// parameters laid out by `layout`) when that is smaller and positive, but not below
    /// 1e-12: links of a few grams, whose pseudo-inertias are near 1e-6, are not held away
    /// from their prior.
    ///
    /// ```
    /// use robid_runtime::feasible::{Bounds, DEFAULT_MARGIN, Problem};
    /// use nalgebra::DMatrix;
    /// let names: Vec<String> = ["XX1", "XY1", "XZ1", "YY1", "YZ1", "ZZ1", "MX1", "MY1", "MZ1", "M1"]
    ///     .map(String::from)
    ///     .to_vec();
    /// let problem = Problem::new(names.clone(), names, DMatrix::identity(10, 10)).unwrap();
    /// // a 12 g link, centre of mass at the origin, inertia 1e-6 I: its pseudo-inertia's
    /// // second moments are tr(I) / 2 - 1e-6 = 0.5e-6, its smallest eigenvalue
    /// let jaw = [1e-6, 0.0, 0.0, 1e-6, 0.0, 1e-6, 0.0, 0.0, 0.0, 0.012];
    /// let margin = Bounds::wide(1).margin_for(&problem.layout, Some(&jaw)).unwrap();
    /// assert!((margin - 0.5e-8).abs() < 1e-20);
    /// assert_eq!(Bounds::wide(1).margin_for(&problem.layout, None).unwrap(), DEFAULT_MARGIN);
    /// ```
    ///
    /// An error when a link's bounds lie below what the margin allows: a pseudo-inertia at
    /// least `margin` times the identity has a mass of at least the margin and moments
    /// about its centre of mass of at least twice it (`mass = [0, 1e-300]` failed as "the
    /// interior-point fit left the consistent set", naming nothing).
    pub fn margin_for(&self, layout: &super::Layout, prior: Option<&[f64]>) -> Result<f64> {
        let margin = self.margin.unwrap_or_else(|| {
            let smallest = prior.map_or(f64::INFINITY, |p| {
                (0..layout.links.len())
                    .map(|j| super::pseudo_inertia_min_eigenvalue(&layout.link_values(j, p)))
                    .filter(|&e| e > 0.0)
                    .fold(f64::INFINITY, f64::min)
            });
            DEFAULT_MARGIN
                .min(MARGIN_SHARE * smallest)
                .max(MIN_DEFAULT_MARGIN)
        });
        self.check_margin(margin)?;
        Ok(margin)
    }

    /// Refuses a link whose mass, principal moments or inertia tensor's diagonal cannot
    /// reach what a pseudo-inertia at least `margin` times the identity needs.
    fn check_margin(&self, margin: f64) -> Result<()> {
        for (j, l) in self.links.iter().enumerate() {
            let n = j + 1;
            let diagonal = l
                .tensor
                .iter()
                .zip(TENSOR_ELEMENTS)
                .filter(|(_, (_, row, column))| row == column)
                .filter_map(|(r, (name, _, _))| {
                    r.map(|r| (format!("inertia_tensor.{name}"), r[1], 2.0 * margin))
                });
            let ranges = [
                ("mass".to_owned(), l.mass[1], margin),
                ("inertia".to_owned(), l.inertia[1], 2.0 * margin),
            ];
            if let Some((key, high, least)) = ranges
                .into_iter()
                .chain(diagonal)
                .find(|(_, high, least)| high < least)
            {
                let unit = if key == "mass" { "kg" } else { "kg m^2" };
                return Err(Error::setting(
                    "Bounds",
                    &format!("links.{n}.{key}"),
                    format!(
                        "link {n}'s upper bound {} {unit} is below {} {unit}, the least that the consistency margin {} allows (a \
                         pseudo-inertia at least margin x I has a mass of at least the margin \
                         and moments about its centre of mass of at least twice it); raise \
                         the bound, or set a smaller `margin`",
                        num(high),
                        num(least),
                        num(margin)
                    ),
                ));
            }
        }
        Ok(())
    }

    /// [`Bounds::validate`], and that there are bounds for each of `links` links.
    pub fn check_for(&self, links: usize) -> Result<()> {
        self.validate()?;
        if self.links.len() != links {
            return Err(Error::DimensionMismatch {
                what: "links in the bounds".to_owned(),
                expected: links,
                found: self.links.len(),
            });
        }
        Ok(())
    }

    /// Checks every range (finite with magnitude at most
    /// [`MAX_PARAMETER`](crate::limits::MAX_PARAMETER), ordered, masses and moments
    /// non-negative) and that the total-mass range meets the sum of the link mass ranges.
    pub fn validate(&self) -> Result<()> {
        if self.margin.is_some_and(|m| !(0.0..=1.0).contains(&m)) {
            return Err(Error::setting(
                "Bounds",
                "margin",
                "must be a number in [0, 1], e.g. 1e-6",
            ));
        }
        for (j, l) in self.links.iter().enumerate() {
            let given = RawLink {
                mass: Some(l.mass),
                com: Some(l.com),
                inertia: Some(l.inertia),
                inertia_tensor: None,
            };
            given.check(&format!("links.{}", j + 1), l.tensor)?;
        }
        if let Some(t) = self.total_mass {
            check_range("total_mass".into(), t, true)?;
            let lo: f64 = self.links.iter().map(|l| l.mass[0]).sum();
            let hi: f64 = self.links.iter().map(|l| l.mass[1]).sum();
            if t[1] < lo || t[0] > hi {
                return Err(Error::Feasible(FeasibleError::NoFeasibleParameters {
                    reason: format!(
                        "the total mass range [{}, {}] kg does not meet the sum of the link mass ranges [{}, {}] kg; widen one of them",
                        num(t[0]),
                        num(t[1]),
                        num(lo),
                        num(hi)
                    ),
                }));
            }
        }
        Ok(())
    }
}

impl RawLink {
    /// The inertia tensor elements given, in the order of [`TENSOR_ELEMENTS`].
    fn tensor(&self) -> [Option<[f64; 2]>; 6] {
        self.inertia_tensor
            .as_ref()
            .map(RawTensor::elements)
            .unwrap_or_default()
    }

    /// Checks the ranges given (with `tensor` for the inertia tensor's elements), named
    /// under `table` (`default`, `links.2`): finite with magnitude at most
    /// [`MAX_PARAMETER`], ordered, masses and moments not negative, and a mass that can
    /// be positive.
    fn check(&self, table: &str, tensor: [Option<[f64; 2]>; 6]) -> Result<()> {
        if let Some(m) = self.mass {
            let key = format!("{table}.mass");
            check_range(key.clone(), m, true)?;
            if m[1] < MIN_LINK_MASS {
                return Err(Error::setting(
                    "Bounds",
                    &key,
                    format!(
                        "the upper bound {} kg is below {MIN_LINK_MASS:e} kg (1 mg); a link \
                         has mass: raise it",
                        num(m[1])
                    ),
                ));
            }
        }
        if let Some(i) = self.inertia {
            check_range(format!("{table}.inertia"), i, true)?;
        }
        for (a, r) in self.com.iter().flatten().enumerate() {
            check_range(format!("{table}.com[{}]", a + 1), *r, false)?;
        }
        for (r, (name, row, column)) in tensor.iter().zip(TENSOR_ELEMENTS) {
            if let Some(r) = r {
                check_range(format!("{table}.inertia_tensor.{name}"), *r, row == column)?;
            }
        }
        Ok(())
    }
}

/// Checks one range `[low, high]` named `key`: finite with magnitude at most
/// [`MAX_PARAMETER`], ordered, and not negative when `non_negative`.
fn check_range(key: String, r: [f64; 2], non_negative: bool) -> Result<()> {
    let bad = |problem: &str| Err(Error::setting("Bounds", &key, problem));
    if !(r[0].abs() <= MAX_PARAMETER && r[1].abs() <= MAX_PARAMETER) {
        return bad("holds NaN, an infinite value or a magnitude above 1e6; write finite numbers");
    }
    if r[0] > r[1] {
        return bad("lower bound above the upper bound; write [low, high]");
    }
    if non_negative && r[0] < 0.0 {
        return bad("must not be negative");
    }
    Ok(())
}

fn merge(base: LinkBounds, raw: Option<&RawLink>) -> LinkBounds {
    let Some(raw) = raw else { return base };
    let given = raw.tensor();
    LinkBounds {
        mass: raw.mass.unwrap_or(base.mass),
        com: raw.com.unwrap_or(base.com),
        inertia: raw.inertia.unwrap_or(base.inertia),
        tensor: std::array::from_fn(|e| given[e].or(base.tensor[e])),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_defaults_and_overrides() {
        let text = "total_mass = [1, 20]\n[default]\nmass = [0, 5]\n[links.2]\nmass = [1, 2]\n";
        let b = Bounds::from_toml(text, "b.toml", 3).unwrap();
        assert_eq!(b.links[0].mass, [0.0, 5.0]);
        assert_eq!(b.links[1].mass, [1.0, 2.0]);
        assert_eq!(b.total_mass, Some([1.0, 20.0]));
    }

    /// One link given twice under two spellings of its number (`1` and `01`, `"+1"`): the
    /// second table in the file is named, with the first (one table was silently dropped:
    /// `[links.1] mass = [0, 50]` then `[links.01] mass = [10, 11]` fitted 2.5 kg). A
    /// spelling alone still names its link.
    #[test]
    fn a_link_given_twice_under_two_spellings_is_named_at_the_second() {
        for (text, at) in [
            (
                "[links.1]\nmass = [0.0, 50.0]\n[links.01]\nmass = [10.0, 11.0]\n",
                "b.toml:3:8: `links.01`: link 1 is given twice, as [links.1] on line 1 and \
                 here; give one table per link",
            ),
            (
                "[links.001]\ncom = [[0, 1], [0, 1], [0, 1]]\n\n[links.1]\nmass = [1, 2]\n",
                "b.toml:4:8: `links.1`: link 1 is given twice, as [links.001] on line 1",
            ),
            (
                "[links.3]\nmass = [1, 2]\n[links.\"+3\"]\nmass = [1, 2]\n",
                "b.toml:3:8: `links.+3`: link 3 is given twice, as [links.3] on line 1",
            ),
        ] {
            let e = Bounds::from_toml(text, "b.toml", 3)
                .unwrap_err()
                .to_string();
            assert!(e.starts_with(at), "{text}: {e}");
        }
        let b = Bounds::from_toml("[links.01]\nmass = [10, 11]\n", "b.toml", 3).unwrap();
        assert_eq!(b.links[0].mass, [10.0, 11.0]);
    }

    #[test]
    fn errors_name_the_key_at_its_line() {
        let e = Bounds::from_toml(
            "[default]\nmass = [0, 5]\n[links.2]\nmass = [3, 1]\n",
            "b.toml",
            3,
        )
        .unwrap_err();
        assert!(
            e.to_string().starts_with("b.toml:4:1: `links.2.mass`"),
            "{e}"
        );
    }

    /// A mistake in `[default]` is named there, at its line and column, not as the first
    /// link that inherits it (it was `links.1.mass` with no line); one in a link's table
    /// over a sound default is named in that table, and a centre-of-mass axis by its
    /// element (1-based, as the key map counts).
    #[test]
    fn errors_name_the_table_the_value_is_written_in() {
        for (text, at) in [
            (
                "[default]\nmass = [5.0, 1.0]\n",
                "b.toml:2:1: `default.mass`: lower bound",
            ),
            (
                "[default]\nmass = [0, inf]\n",
                "b.toml:2:1: `default.mass`: holds NaN",
            ),
            (
                "[default]\nmass = [-1, 0]\n",
                "b.toml:2:1: `default.mass`: must not",
            ),
            (
                "[default]\nmass = [0, 0]\n",
                "b.toml:2:1: `default.mass`: the upper bound",
            ),
            (
                "[default]\nmass = [0, 1e-300]\n",
                "b.toml:2:1: `default.mass`: the upper bound 1e-300 kg is below 1e-6 kg (1 mg)",
            ),
            (
                "[default]\ninertia_tensor = { zz = [-1, 1] }\n",
                "b.toml:2:20: `default.inertia_tensor.zz`: must not",
            ),
            (
                "[default]\ncom = [[0, 1], [2, 1], [0, 1]]\n[links.2]\nmass = [0, 1]\n",
                "b.toml:2:16: `default.com[2]`: lower bound",
            ),
            (
                "[default]\nmass = [0, 5]\n[links.3]\ninertia = [1, nan]\n",
                "b.toml:4:1: `links.3.inertia`: holds NaN",
            ),
        ] {
            let e = Bounds::from_toml(text, "b.toml", 3)
                .unwrap_err()
                .to_string();
            assert!(e.starts_with(at), "{text}: {e}");
        }
    }

    #[test]
    fn reads_inertia_tensor_elements_per_link_over_the_default() {
        let text = "[default]\ninertia_tensor = { xx = [0, 1], xy = [-0.1, 0.1] }\n\
                    [links.2]\ninertia_tensor = { xy = [-0.2, 0.3], zz = [0.5, 2] }\n";
        let b = Bounds::from_toml(text, "b.toml", 2).unwrap();
        assert_eq!(b.links[0].tensor[0], Some([0.0, 1.0]));
        assert_eq!(b.links[0].tensor[3], Some([-0.1, 0.1]));
        assert_eq!(b.links[0].tensor[2], None);
        assert_eq!(b.links[1].tensor[0], Some([0.0, 1.0]));
        assert_eq!(b.links[1].tensor[2], Some([0.5, 2.0]));
        assert_eq!(b.links[1].tensor[3], Some([-0.2, 0.3]));
        // a diagonal element is a moment: not negative; a product of inertia may be
        let e = Bounds::from_toml(
            "[links.1]\ninertia_tensor = { yy = [-1, 1] }\n",
            "b.toml",
            2,
        )
        .unwrap_err();
        assert!(e.to_string().contains("`links.1.inertia_tensor.yy`"), "{e}");
        let e = Bounds::from_toml("[links.1]\ninertia_tensor = { xw = [0, 1] }\n", "b.toml", 2)
            .unwrap_err();
        assert!(e.to_string().contains("xw"), "{e}");
    }

    #[test]
    fn the_centre_is_mid_box_mid_mass_and_mid_moment() {
        let l = LinkBounds {
            mass: [1.0, 4.0],
            com: [[-0.5, 0.1], [0.2, 0.4], [-3.0, -1.0]],
            inertia: [0.5, 1.5],
            tensor: [None; 6],
        };
        assert_eq!(l.centre(), ([-0.2, 0.30000000000000004, -2.0], 2.5, 1.0));
    }

    #[test]
    fn check_for_wants_valid_bounds_for_every_link() {
        let b = Bounds::wide(3);
        assert!(b.check_for(3).is_ok());
        assert!(matches!(
            b.check_for(4),
            Err(Error::DimensionMismatch {
                expected: 4,
                found: 3,
                ..
            })
        ));
        let mut bad = b.clone();
        bad.links[1].mass = [2.0, 1.0];
        assert!(bad.check_for(3).is_err());
    }

    /// The margin imposed: the one given; else 1e-6, or 1 % of the prior's smallest
    /// positive pseudo-inertia eigenvalue when smaller (an inconsistent link is ignored).
    #[test]
    fn the_default_margin_follows_the_smallest_prior_link() {
        use crate::feasible::fixture::{link, problem, target};
        use crate::feasible::{LinkInertial, pseudo_inertia_min_eigenvalue};
        let layout = problem(&target(link(), 0.0)).layout;
        let wide = Bounds::wide(1);
        let ordinary = target(link(), 0.0);
        assert_eq!(wide.margin_for(&layout, None).unwrap(), DEFAULT_MARGIN);
        assert_eq!(
            wide.margin_for(&layout, Some(&ordinary)).unwrap(),
            DEFAULT_MARGIN
        );
        let jaw = LinkInertial {
            mass: 0.012,
            com: [0.0; 3],
            inertia: [[2e-6, 0.0, 0.0], [0.0, 5e-6, 0.0], [0.0, 0.0, 6e-6]],
        }
        .to_standard();
        let small = pseudo_inertia_min_eigenvalue(&jaw);
        assert!(small < 1e-6);
        let m = wide.margin_for(&layout, Some(&target(jaw, 0.0))).unwrap();
        assert!((m - 1e-2 * small).abs() < 1e-20, "{m} {small}");
        let mut broken = jaw;
        broken[0] = -1.0;
        assert_eq!(
            wide.margin_for(&layout, Some(&target(broken, 0.0)))
                .unwrap(),
            DEFAULT_MARGIN
        );
        // a point mass: its pseudo-inertia's smallest eigenvalue is exactly 0, no scale
        let mut point = [0.0; 10];
        point[9] = 1.0;
        assert_eq!(pseudo_inertia_min_eigenvalue(&point), 0.0);
        assert_eq!(
            wide.margin_for(&layout, Some(&target(point, 0.0))).unwrap(),
            DEFAULT_MARGIN
        );
        let given = Bounds {
            margin: Some(0.5),
            ..Bounds::wide(1)
        };
        assert_eq!(
            given.margin_for(&layout, Some(&target(jaw, 0.0))).unwrap(),
            0.5
        );
    }

    /// Each default range reaches twice the prior's largest value where that is beyond it,
    /// and is left as it is otherwise.
    #[test]
    fn the_default_bounds_reach_twice_the_prior() {
        use crate::feasible::fixture::{link, problem, target};
        use crate::feasible::{LinkInertial, Prior};
        let long = LinkInertial {
            mass: 80.0,
            com: [0.0, -0.8, 0.1],
            inertia: [[6.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 6.0]],
        }
        .to_standard();
        let prior = |l: [f64; 10]| Prior {
            standard: target(l, 0.0).iter().map(|&v| Some(v)).collect(),
            weight: 1.0,
        };
        let p = problem(&target(long, 0.0));
        let b = Bounds::wide_for(&p, Some(&prior(long))).links[0];
        assert_eq!(b.mass, [0.0, 160.0]);
        assert_eq!(b.com, [[-1.6, 1.6]; 3]);
        assert!((b.inertia[1] - 12.0).abs() < 1e-12, "{:?}", b.inertia);
        let ordinary = Bounds::wide_for(&p, Some(&prior(link())));
        assert_eq!(ordinary, Bounds::wide(1));
    }

    /// Bounds below what the margin allows (a mass under the margin, principal moments or
    /// a diagonal element of the inertia tensor under twice it) are refused at their key,
    /// at `[default]` when the link inherits them; the margin's least values are allowed.
    #[test]
    fn bounds_below_the_margin_are_refused_at_their_key() {
        let names: Vec<String> = [
            "XX1", "XY1", "XZ1", "YY1", "YZ1", "ZZ1", "MX1", "MY1", "MZ1",
        ]
        .into_iter()
        .chain(["M1"])
        .map(String::from)
        .collect();
        let problem =
            super::super::Problem::new(names.clone(), names, nalgebra::DMatrix::identity(10, 10))
                .unwrap();
        for (text, error) in [
            (
                "margin = 1e-3\n[default]\nmass = [0, 1e-4]\n",
                Some(
                    "b.toml:3:1: `default.mass`: link 1's upper bound 0.0001 kg is below 0.001 kg",
                ),
            ),
            ("margin = 1e-3\n[default]\nmass = [0, 1e-3]\n", None),
            (
                "margin = 1e-3\n[links.1]\ninertia = [0, 1e-3]\n",
                Some(
                    "b.toml:3:1: `links.1.inertia`: link 1's upper bound 0.001 kg m^2 is below 0.002 kg m^2",
                ),
            ),
            ("margin = 1e-3\n[links.1]\ninertia = [0, 2e-3]\n", None),
            (
                "margin = 1e-3\n[default]\ninertia_tensor = { yy = [0, 1e-3], xy = [0, 1e-9] }\n",
                Some("b.toml:3:20: `default.inertia_tensor.yy`: link 1's upper bound"),
            ),
            (
                "margin = 1e-3\n[default]\ninertia_tensor = { xy = [0, 1e-9] }\n",
                None,
            ),
        ] {
            let bounds = Bounds::from_toml(text, "b.toml", 1).unwrap();
            let got = bounds
                .margin_for(&problem.layout, None)
                .map_err(|e| Bounds::locate(text, "b.toml", e).to_string());
            match error {
                Some(e) => assert!(got.as_ref().unwrap_err().starts_with(e), "{got:?}"),
                None => assert_eq!(got, Ok(1e-3)),
            }
        }
    }

    #[test]
    fn the_margin_is_within_zero_and_one() {
        for (margin, ok) in [(0.0, true), (1.0, true), (-1e-9, false), (1.5, false)] {
            let b = Bounds {
                margin: Some(margin),
                ..Bounds::wide(2)
            };
            assert_eq!(b.validate().is_ok(), ok, "{margin}");
        }
        assert!(Bounds::from_toml("margin = nan\n", "b", 2).is_err());
    }

    #[test]
    fn a_total_mass_range_that_touches_the_links_sum_is_met() {
        let text = "[default]\nmass = [1, 2]\n";
        let with =
            |total: &str| Bounds::from_toml(&format!("total_mass = {total}\n{text}"), "b", 2);
        // the links' masses sum to [2, 4]
        for (total, ok) in [
            ("[0, 2]", true),
            ("[4, 10]", true),
            ("[0, 1.9]", false),
            ("[4.1, 10]", false),
        ] {
            assert_eq!(with(total).is_ok(), ok, "{total}");
        }
    }

    #[test]
    fn equal_bounds_fix_a_value() {
        let b = Bounds::from_toml(
            "[links.1]\nmass = [2, 2]\ncom = [[0, 0], [0.1, 0.1], [0, 0]]\n",
            "b",
            2,
        );
        assert_eq!(b.unwrap().links[0].mass, [2.0, 2.0]);
    }

    #[test]
    fn rejects_bad_ranges() {
        assert!(Bounds::from_toml("[links.4]\nmass = [0, 1]\n", "b", 3).is_err());
        assert!(Bounds::from_toml("[default]\nmass = [2, 1]\n", "b", 3).is_err());
        assert!(Bounds::from_toml("[default]\nmass = [0, nan]\n", "b", 3).is_err());
        let e = Bounds::from_toml(
            "total_mass = [100, 200]\n[default]\nmass = [0, 1]\n",
            "b",
            3,
        );
        assert!(matches!(
            e,
            Err(Error::Feasible(FeasibleError::NoFeasibleParameters { .. }))
        ));
    }
}
