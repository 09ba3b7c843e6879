//! Parameter files, the one reader: a `[standard]` table (name = value; missing names are
//! 0, or have no prior), a `[base]` table (every base parameter) or a `[known]` table
//! (standard parameters known beforehand, such as weighed masses, which identification
//! moves to the right-hand side: `estimation.known`, docs/identification.md#known-parameters).
//! `robid feasible` writes this format; `torques`, `simulate`, `excite`, `feasible --prior`,
//! `identify` (known parameters), the reference robots, the tests and the benches read it here.
//!
//! What is checked, each mistake an [`crate::DataError::ParameterFile`] at `file:line:column` with the
//! fix. When the file is read:
//! - exactly one table, `[standard]`, `[base]` or `[known]`; any other table or key is an
//!   error, but for the `[[links]]` summary that `robid feasible` writes after its
//!   `[standard]` table (mass, centre of mass and inertia per link, for people) and its
//!   `[extra]` table (the values of an identification config's extra columns, which are
//!   not the robot's parameters: [`ParameterFile::extra`], read by `identify --reference`),
//!   which the robot's readers pass over;
//! - every value is a number, finite and within +-[`PARAMETER_LIMIT`];
//! - no key or table is given twice (a TOML error, which names the key at its second place).
//!
//! When its values are taken for a model ([`ParameterFile::base_parameters`],
//! [`ParameterFile::prior`], [`ParameterFile::known`]):
//! - every key is a parameter of the robot (the nearest name is suggested);
//! - in `[standard]`: masses `Mj`, rotor inertias `Iaj` and friction coefficients `Fvj`,
//!   `Fcj` are not negative; a first moment `MXj MYj MZj` needs a positive mass `Mj`;
//!   each link's inertia tensor `XXj XYj XZj YYj YZj ZZj` (about the frame origin, `XYj`
//!   the tensor's entry) and, with a mass, the tensor about the centre of mass are
//!   positive semidefinite (smallest eigenvalue at least -[`INERTIA_TOLERANCE`] times the
//!   largest entry, for rounded published values). Missing values count as 0; for a prior,
//!   links with missing values are not checked as a whole.
//!
//! ```
//! use robid_runtime::data::{ParameterFile, ParameterTable};
//!
//! let text = "[standard]\nM1 = 2.5\nMX1 = 0.5  # kg m\nFv1 = 0.1\n";
//! let file = ParameterFile::parse(text, "arm.toml".as_ref()).unwrap();
//! assert_eq!(file.table(), ParameterTable::Standard);
//! assert_eq!(file.get("MX1"), Some(0.5));
//! let names: Vec<String> = ["M1", "MX1", "Fv1", "Fc1"].map(String::from).to_vec();
//! assert_eq!(file.prior(&names).unwrap(), [Some(2.5), Some(0.5), Some(0.1), None]);
//!
//! let negative = ParameterFile::parse("[standard]\nM1 = -1\n", "arm.toml".as_ref()).unwrap();
//! let e = negative.prior(&names).unwrap_err();
//! assert!(e.to_string().starts_with("arm.toml:2:1: `M1` = -1 is negative"));
//! ```

use crate::DataError;
use crate::toml_syntax::line_column;
use std::collections::BTreeMap;
use std::fmt;
use std::path::{Path, PathBuf};

use toml::de::{DeTable, DeValue};

use crate::Model;
use crate::Num;
use crate::error::{Error, Result};
use crate::feasible::inertia_at_origin;
use crate::model::{Inertial, ParameterId, ParameterKind};
use nalgebra::Vector3;

/// The largest magnitude of a value in a parameter file (SI units: kg, kg m, kg m^2,
/// N m s/rad, N m).
pub const PARAMETER_LIMIT: f64 = 1e6;

/// How negative (relative to the largest entry) the smallest eigenvalue of a link's
/// inertia tensor may be: room for rounded published values.
pub const INERTIA_TOLERANCE: f64 = 1e-6;

/// Which table a parameter file holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ParameterTable {
    /// `[standard]`: standard parameters, any subset.
    Standard,
    /// `[base]`: every base parameter of the model.
    Base,
    /// `[known]`: standard parameters known beforehand (any subset), which identification
    /// does not estimate.
    Known,
}

impl fmt::Display for ParameterTable {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            ParameterTable::Standard => "standard",
            ParameterTable::Base => "base",
            ParameterTable::Known => "known",
        })
    }
}

/// One `name = value` of the table, with the place of its name.
#[derive(Debug, Clone, Copy)]
struct Entry {
    value: f64,
    line: usize,
    column: usize,
}

/// A parameter file, read and checked for syntax, table and values.
#[derive(Debug, Clone)]
pub struct ParameterFile {
    path: PathBuf,
    table: ParameterTable,
    /// In file order.
    entries: Vec<(String, Entry)>,
    /// The `[extra]` table `robid feasible` writes, in file order: the values of an
    /// identification config's extra columns.
    extra: Vec<(String, Entry)>,
}

impl ParameterFile {
    /// Reads the file at `path` (see the module documentation for the checks).
    pub fn read(path: &Path) -> Result<ParameterFile> {
        let text = crate::data::read_text(path, "parameter file")?;
        ParameterFile::parse(&text, path)
    }

    /// Reads `text`, naming it `path` in errors.
    pub fn parse(text: &str, path: &Path) -> Result<ParameterFile> {
        parse(text, path)
    }

    /// The table the file holds.
    pub fn table(&self) -> ParameterTable {
        self.table
    }

    /// The value of `name`, if the file has it.
    pub fn get(&self, name: &str) -> Option<f64> {
        self.entries
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, e)| e.value)
    }

    /// Every `(name, value)`, in file order.
    pub fn entries(&self) -> impl Iterator<Item = (&str, f64)> {
        self.entries.iter().map(|(n, e)| (n.as_str(), e.value))
    }

    /// Every `(name, value)` of the `[extra]` table (the values of an identification
    /// config's extra columns that `robid feasible` writes beside the robot's parameters),
    /// in file order; none without one.
    ///
    /// ```
    /// use robid_runtime::data::ParameterFile;
    ///
    /// let text = "[standard]\nM1 = 2.5\n[extra]\nIam6 = 0.01\n";
    /// let file = ParameterFile::parse(text, "arm.toml".as_ref()).unwrap();
    /// assert_eq!(file.extra().collect::<Vec<_>>(), [("Iam6", 0.01)]);
    /// assert_eq!(file.get("Iam6"), None);
    /// ```
    pub fn extra(&self) -> impl Iterator<Item = (&str, f64)> {
        self.extra.iter().map(|(n, e)| (n.as_str(), e.value))
    }

    /// The values of `names` (`None` where missing); a key that is not one of `names` is an
    /// error naming the nearest name. The values are not checked for physical consistency
    /// (see [`ParameterFile::base_parameters`] and [`ParameterFile::prior`]).
    pub fn values(&self, names: &[String]) -> Result<Vec<Option<f64>>> {
        // a parameter of a link the robot does not have: another robot's file, which is
        // what to say (a PUMA's file for a two-link arm was told to add `Ia1`'s drive term)
        let link = |name: &str| name.parse::<ParameterId>().ok().map(|id| id.link);
        let links = names
            .iter()
            .filter_map(|n| link(n))
            .max()
            .map_or(0, |l| l + 1);
        let beyond = self
            .entries
            .iter()
            .find(|(key, _)| !names.contains(key) && link(key).is_some_and(|l| l >= links));
        if let Some((key, entry)) = beyond {
            return Err(self.at(
                entry,
                format!(
                    "[{}] has `{key}`, of link {}, but this robot has {}: is the file \
                     another robot's? Give the parameter file of this robot",
                    self.table,
                    link(key).map_or(0, |l| l + 1),
                    crate::Count(links, "link")
                ),
            ));
        }
        for (key, entry) in &self.entries {
            if names.contains(key) {
                continue;
            }
            let drive = matches!(
                key.parse::<ParameterId>(),
                Ok(ParameterId {
                    kind: ParameterKind::Drive(_),
                    ..
                })
            );
            let same_but_case = names.iter().any(|n| n.eq_ignore_ascii_case(key));
            let hint = match nearest(key, names) {
                Some(n) if same_but_case || !drive => format!("did you mean `{n}`?"),
                _ if drive => format!(
                    "`{key}` is a drive term, which this robot does not model: {}",
                    crate::model::drive_terms_mismatch(
                        "the file",
                        &self
                            .entries
                            .iter()
                            .map(|(n, _)| n.as_str())
                            .collect::<Vec<_>>(),
                        names,
                    )
                    .unwrap_or_else(|| {
                        "add it to the description's `drive` key (or --drive \
                                         where the subcommand has it)"
                            .to_owned()
                    })
                ),
                _ => format!("they are: {}", names.join(", ")),
            };
            return Err(self.at(
                entry,
                format!(
                    "[{what}] has `{}`, which is not a {what} parameter of this robot; {hint}",
                    robid_core::names::short(key),
                    what = self.table
                ),
            ));
        }
        Ok(names.iter().map(|n| self.get(n)).collect())
    }

    /// The base parameters of `model`: from a `[base]` table, every one; from a
    /// `[standard]` table, through the model's map (missing values are 0).
    pub fn base_parameters(&self, model: &dyn Model) -> Result<Vec<f64>> {
        match self.table {
            ParameterTable::Standard => {
                let names = crate::model::standard_parameter_names(model);
                let standard: Vec<f64> = self
                    .values(&names)?
                    .into_iter()
                    .map(|v| v.unwrap_or(0.0))
                    .collect();
                self.check_physical(true)?;
                let mut base = vec![0.0; model.base_parameter_count()];
                model.base_from_standard_into(&standard, &mut base)?;
                if let Some(i) = base.iter().position(|b| !b.is_finite()) {
                    return Err(self.whole(format!(
                        "base parameter {} = {} is not a finite number; check the values of \
                         its standard parameters",
                        model.base_parameter_name(i).unwrap_or("?"),
                        base[i]
                    )));
                }
                Ok(base)
            }
            ParameterTable::Base => {
                let names = crate::model::base_parameter_names(model);
                self.values(&names)?
                    .into_iter()
                    .zip(&names)
                    .map(|(v, n)| {
                        v.ok_or_else(|| {
                            let keys: Vec<&str> =
                                self.entries.iter().map(|(k, _)| k.as_str()).collect();
                            let is_drive = |m: &str| {
                                matches!(
                                    m.parse::<ParameterId>(),
                                    Ok(ParameterId {
                                        kind: ParameterKind::Drive(_),
                                        ..
                                    })
                                )
                            };
                            // a missing link parameter is not a matter of drive terms (a
                            // `[base]` of ZZR1 alone was told to drop the robot's Fv, Fc),
                            // nor is a drive term missing beside link parameters
                            let links_complete =
                                (names.iter()).all(|m| is_drive(m) || keys.contains(&m.as_str()));
                            let mismatch = (is_drive(n) && links_complete)
                                .then(|| {
                                    crate::model::drive_terms_mismatch("the file", &keys, &names)
                                })
                                .flatten();
                            self.whole(match mismatch {
                                Some(fix) => format!("[base] has no `{n}`: {fix}"),
                                None => {
                                    let missing: Vec<&String> = names
                                        .iter()
                                        .filter(|m| !keys.contains(&m.as_str()))
                                        .collect();
                                    let shown: Vec<String> =
                                        missing.iter().take(8).map(|m| format!("`{m}`")).collect();
                                    let more = if missing.len() > 8 { ", ..." } else { "" };
                                    format!(
                                        "[base] has no {}{more} ({} of the model's {}); list every \
                                         base parameter (`robid model` lists them)",
                                        shown.join(", "),
                                        missing.len(),
                                        names.len()
                                    )
                                }
                            })
                        })
                    })
                    .collect()
            }
            ParameterTable::Known => Err(self.whole(
                "a [known] table lists only the parameters known beforehand, for \
                 `estimation.known` of an identification; give the robot's parameters in a \
                 [standard] or [base] table"
                    .to_owned(),
            )),
        }
    }

    /// The known standard parameters of a `[known]` table: `(index into names, value)` in
    /// the order of `names`. Every key must be one of `names`, and the values pass the
    /// physical checks of the module documentation (links with missing inertial values are
    /// not checked as a whole). At least one parameter must be listed.
    pub fn known(&self, names: &[String]) -> Result<Vec<(usize, f64)>> {
        if self.table != ParameterTable::Known {
            return Err(self.whole(format!(
                "known parameters need a [known] table (this file has [{}]); write the \
                 parameters known beforehand as `[known]` with name = value",
                self.table
            )));
        }
        if self.entries.is_empty() {
            return Err(self.whole(
                "[known] is empty; list the standard parameters known beforehand (name = \
                 value), or leave `estimation.known` out"
                    .to_owned(),
            ));
        }
        let values = self.values(names)?;
        self.check_physical(false)?;
        Ok(values
            .into_iter()
            .enumerate()
            .filter_map(|(i, v)| v.map(|v| (i, v)))
            .collect())
    }

    /// The standard parameters `names` as a prior (`None` where missing): needs a
    /// `[standard]` table; links with missing inertial values are not checked as a whole.
    pub fn prior(&self, names: &[String]) -> Result<Vec<Option<f64>>> {
        match self.table {
            ParameterTable::Standard => {
                let values = self.values(names)?;
                self.check_physical(false)?;
                Ok(values)
            }
            ParameterTable::Base | ParameterTable::Known => Err(self.whole(
                "a prior needs standard parameters, a [standard] table (base parameters leave \
                 the link parameters undetermined)"
                    .to_owned(),
            )),
        }
    }

    /// An error at `entry`.
    fn at(&self, e: &Entry, problem: String) -> Error {
        Error::Data(DataError::ParameterFile {
            path: self.path.clone(),
            line: Some(e.line),
            column: Some(e.column),
            problem,
        })
    }

    /// An error about the whole file.
    fn whole(&self, problem: String) -> Error {
        Error::Data(DataError::ParameterFile {
            path: self.path.clone(),
            line: None,
            column: None,
            problem,
        })
    }

    /// The physical checks of a `[standard]` table (see the module documentation);
    /// `missing_is_zero`: a missing value counts as 0 (else a link with a missing inertial
    /// value is not checked as a whole). Names that are not standard parameters (extra
    /// columns) are left to [`ParameterFile::values`].
    fn check_physical(&self, missing_is_zero: bool) -> Result<()> {
        let mut links: BTreeMap<usize, [Option<(f64, Entry)>; 10]> = BTreeMap::new();
        for (name, entry) in &self.entries {
            let Ok(id) = name.parse::<ParameterId>() else {
                continue;
            };
            let meaning = match id.kind {
                ParameterKind::Inertial(Inertial::M) => Some("a mass"),
                ParameterKind::Drive(d) if d.non_negative() => Some(d.meaning()),
                _ => None,
            };
            if let Some(what) = meaning
                && entry.value < 0.0
            {
                return Err(self.at(
                    entry,
                    format!(
                        "`{name}` = {} is negative; {what} cannot be negative",
                        entry.value
                    ),
                ));
            }
            if let ParameterKind::Inertial(slot) = id.kind {
                links.entry(id.link + 1).or_insert([None; 10])[slot.index()] =
                    Some((entry.value, *entry));
            }
        }
        for (link, slots) in &links {
            if !missing_is_zero && slots.iter().any(Option::is_none) {
                self.check_diagonal(*link, slots)?;
                continue;
            }
            self.check_link(*link, slots)?;
        }
        Ok(())
    }

    /// A link of a prior with missing values: whatever they are, its moments about the
    /// centre of mass (the diagonal of that tensor, which the products of inertia do not
    /// enter; a missing first moment at its most favourable, 0) must not be negative. A
    /// prior with `M2 = 3`, `MX2 = 0.6`, `YY2 = 0.001` (a moment of -0.119 kg m^2 about the
    /// centre of mass) was taken, where every other reader refused it. Needs the mass and
    /// the three moments.
    fn check_diagonal(&self, link: usize, slots: &[Option<(f64, Entry)>; 10]) -> Result<()> {
        let value = |i: usize| slots[i].map(|(v, _)| v);
        let Some(first) = first_entry(slots) else {
            return Ok(());
        };
        let missing: Vec<String> = Inertial::ALL
            .iter()
            .zip(slots)
            .filter(|(_, slot)| slot.is_none())
            .map(|(s, _)| format!("{}{link}", s.stem()))
            .collect();
        let missing = missing.join(" ");
        let h = [6, 7, 8].map(|i| value(i).unwrap_or(0.0));
        let diagonal = [0, 3, 5].map(value);
        // about the origin, whatever the mass: XX + YY - ZZ is twice the spread along z
        if let [Some(xx), Some(yy), Some(zz)] = diagonal {
            let spread = [yy + zz - xx, xx + zz - yy, xx + yy - zz];
            let scale = xx.abs().max(yy.abs()).max(zz.abs());
            if let Some(axis) = (0..3).find(|&a| spread[a] < -INERTIA_TOLERANCE * scale) {
                return Err(self.at(
                    &first,
                    format!(
                        "link {link}'s moments XX{link} YY{link} ZZ{link} = {}, {}, {} break the \
                         triangle inequality about the frame origin ({} exceeds the sum of the \
                         other two), whatever the missing {missing} are: no body has them",
                        Num(xx),
                        Num(yy),
                        Num(zz),
                        ["XX", "YY", "ZZ"][axis]
                    ),
                ));
            }
        }
        let Some(mass) = value(9) else {
            return Ok(());
        };
        if mass == 0.0 && h.iter().any(|x| *x != 0.0) {
            return Err(self.at(
                &first,
                format!("link {link} has a first moment but no mass M{link}; give its mass"),
            ));
        }
        if mass <= 0.0 {
            return Ok(());
        }
        // mass times each given moment about the centre of mass (no division by the
        // mass), a missing first moment at its most favourable, 0
        let scale = h.iter().map(|x| x * x).sum::<f64>();
        let bad = (0..3).find_map(|axis| {
            let moment = diagonal[axis]?;
            let (b, c) = ((axis + 1) % 3, (axis + 2) % 3);
            let about = moment * mass - (h[b] * h[b] + h[c] * h[c]);
            (about < -INERTIA_TOLERANCE * (moment.abs() * mass).max(scale))
                .then_some((axis, moment, about))
        });
        let Some((axis, moment, about)) = bad else {
            return Ok(());
        };
        let stem = ["XX", "YY", "ZZ"][axis];
        Err(self.at(
            &first,
            format!(
                "link {link}'s moment {stem}{link} about its centre of mass would be {} kg m^2 \
                 whatever the missing {missing} are: the first moments place the centre of \
                 mass too far from the origin for {stem}{link} = {}, so no body has these \
                 values; check them and M{link}",
                Num::rounded(about / mass, 5),
                Num(moment)
            ),
        ))
    }

    /// The links whose values are possible (the checks of the module documentation pass)
    /// but no body's: principal moments about the centre of mass that break the triangle
    /// inequality (the largest exceeds the sum of the other two by more than
    /// [`INERTIA_TOLERANCE`] of it), missing values counted as 0 (for a link without
    /// products of inertia in the file, no missing values could mend it: the moments on
    /// the diagonal keep the inequality in every frame, and a first moment only narrows it). A warning each,
    /// at the link's first value, as a URDF's such `<inertial>` is warned about: the
    /// torques of such values are computed, but no robot has them.
    /// With `missing_is_zero` false (a prior, whose missing values are free), links with
    /// missing values are left out.
    pub fn unphysical(&self, missing_is_zero: bool) -> Vec<String> {
        let mut links: BTreeMap<usize, ([f64; 10], Option<Entry>)> = BTreeMap::new();
        let mut given: BTreeMap<usize, usize> = BTreeMap::new();
        for (name, entry) in &self.entries {
            let Ok(ParameterId {
                link,
                kind: ParameterKind::Inertial(slot),
            }) = name.parse::<ParameterId>()
            else {
                continue;
            };
            *given.entry(link + 1).or_default() += 1;
            let (p, first) = links.entry(link + 1).or_insert(([0.0; 10], None));
            p[slot.index()] = entry.value;
            if first.is_none_or(|f| entry.line < f.line) {
                *first = Some(*entry);
            }
        }
        links
            .into_iter()
            .filter(|(link, _)| missing_is_zero || given.get(link) == Some(&10))
            .filter_map(|(link, (p, first))| {
                let moments = crate::feasible::LinkInertial::from_standard(&p)?.principal_moments();
                let excess = moments[2] - moments[0] - moments[1];
                let tolerance = INERTIA_TOLERANCE * moments[2].abs();
                // a negative moment is impossible, the readers' error (a prior's missing
                // values may yet make it possible)
                (moments[0] >= -tolerance && excess > tolerance).then(|| {
                    let at = first.map_or(0, |e| e.line);
                    let [a, b, c] = moments.map(|m| Num::rounded(m, 4));
                    format!(
                        "{}:{at}: link {link}: the principal moments {a}, {b}, {c} kg m^2 of \
                             its inertia about the centre of mass break the triangle inequality \
                             (the largest exceeds the sum of the other two by {} kg m^2), so no \
                             body has these values; check the moments of link {link}",
                        self.path.display(),
                        Num::rounded(excess, 4)
                    )
                })
            })
            .collect()
    }

    /// The inertia tensor of link `link` (1-based), about its origin and its centre of
    /// mass, is positive semidefinite; a first moment has a mass.
    fn check_link(&self, link: usize, slots: &[Option<(f64, Entry)>; 10]) -> Result<()> {
        let p: [f64; 10] = std::array::from_fn(|i| slots[i].map_or(0.0, |(v, _)| v));
        // the place of the link: its first entry in the file
        let Some(first) = first_entry(slots) else {
            return Ok(());
        };
        let names = |stems: &[Inertial]| -> String {
            stems
                .iter()
                .map(|s| format!("{}{link}", s.stem()))
                .collect::<Vec<_>>()
                .join(" ")
        };
        let tensor = names(&Inertial::ALL[..6]);
        let moments = names(&Inertial::ALL[6..9]);
        let scale = p[..6].iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        let lowest = inertia_at_origin(&p).symmetric_eigenvalues().min();
        if lowest < -INERTIA_TOLERANCE * scale {
            return Err(self.at(
                &first,
                format!(
                    "the inertia tensor of link {link} ({tensor}, about the frame origin) is \
                     not positive semidefinite (smallest eigenvalue {lowest:.4e} kg m^2), so no \
                     mass distribution has it; check these values and the sign of the products \
                     of inertia (XY{link} is the tensor's entry, -sum m x y)"
                ),
            ));
        }
        let mass = p[9];
        if mass == 0.0 && p[6..9].iter().any(|h| *h != 0.0) {
            return Err(self.at(
                &first,
                format!(
                    "link {link} has a first moment ({moments}) but no mass M{link}; give its mass"
                ),
            ));
        }
        if mass > 0.0 {
            // m I_c = m I_o - S(h)' S(h) (h the first moments): no division by the mass, so
            // a speck of mass with a first moment (its centre of mass 1e200 m away) is
            // judged rather than lost to overflow
            let origin = inertia_at_origin(&p);
            let h = Vector3::new(p[6], p[7], p[8]);
            let spread = h.cross_matrix().transpose() * h.cross_matrix();
            let scaled = origin * mass - spread;
            let scale = (origin.abs().max() * mass).max(h.norm_squared());
            let lowest = scaled.symmetric_eigenvalues().min();
            if lowest < -INERTIA_TOLERANCE * scale {
                let [x, y, z] = [p[6], p[7], p[8]].map(|h| Num::rounded(h / mass, 5));
                return Err(self.at(
                    &first,
                    format!(
                        "the inertia of link {link} about its centre of mass ({x}, {y}, {z}) m \
                         is not positive semidefinite (smallest principal moment {} kg m^2): \
                         the first moments place the centre of mass too far from the origin \
                         for the inertias {tensor}; check {moments} and M{link}",
                        Num::rounded(lowest / mass, 5)
                    ),
                ));
            }
        }
        Ok(())
    }
}

/// The place of a link in the file: the first of its entries (`None` without one).
fn first_entry(slots: &[Option<(f64, Entry)>; 10]) -> Option<Entry> {
    slots
        .iter()
        .flatten()
        .map(|(_, e)| *e)
        .min_by_key(|e| e.line)
}

/// The tables of a parameter file, each with what it is for: the file's errors name the
/// one a command needs (they offered [known] where only the robot's parameters do).
const TABLES: &str = "one table: [standard] (standard parameters) or [base] (base \
                      parameters) for the robot's parameters, or [known] for the parameters \
                      known beforehand of an identification's `estimation.known`";

/// Syntax, table and values (not the physical checks).
fn parse(text: &str, path: &Path) -> Result<ParameterFile> {
    let located = |offset: usize, problem: String| -> Error {
        let (line, column) = line_column(text, offset);
        Error::Data(DataError::ParameterFile {
            path: path.to_owned(),
            line: Some(line),
            column: Some(column),
            problem,
        })
    };
    let doc = DeTable::parse(text).map_err(|e| {
        // a value nested too deep is told as in robid's other TOML files
        // (`path:line:column: `key`: ...`), not in toml's words
        if let Some(deep) = crate::toml_syntax::too_deep(text, path, &e) {
            return deep;
        }
        // JSON (robid identify's report, most likely) given where TOML goes: said so, with
        // what to give instead, not as toml's "invalid key-value pair"; lines ended by a
        // carriage return alone as in every TOML file robid reads
        match crate::toml_syntax::not_toml(text, &e) {
            Some(crate::toml_syntax::NotToml::Json { offset }) => {
                return located(offset, json_message(text, path));
            }
            Some(crate::toml_syntax::NotToml::CarriageReturns) => {
                return Error::Data(DataError::CarriageReturnLines {
                    path: path.to_owned(),
                });
            }
            None => {}
        }
        let offset = e.span().map_or(0, |s| s.start);
        located(offset, syntax_message(text, &e))
    })?;
    let mut found: Option<(ParameterTable, Vec<(String, Entry)>)> = None;
    // The tables in the order of the file (the parsed table is sorted by name): the second
    // of two tables is the one named, at its own place, whichever way round they are written.
    let mut tables: Vec<_> = doc.get_ref().iter().collect();
    tables.sort_by_key(|(key, _)| key.span().start);
    let mut first: Option<(&str, usize)> = None;
    let mut extra = Vec::new();
    for (key, value) in tables {
        let name: &str = key.get_ref();
        let at = key.span().start;
        let table = match name {
            "standard" => ParameterTable::Standard,
            "base" => ParameterTable::Base,
            "known" => ParameterTable::Known,
            // robid feasible's per-link summary: the [standard] table holds the same values
            "links" if matches!(value.get_ref(), DeValue::Array(_)) => continue,
            // robid feasible's values of an identification config's extra columns: not the
            // robot's parameters, kept apart
            "extra" => {
                let DeValue::Table(items) = value.get_ref() else {
                    return Err(located(at, "`extra` must be a table [extra]".to_string()));
                };
                extra = entries_of(text, "extra", items, &located)?;
                continue;
            }
            other => {
                return Err(located(
                    at,
                    format!(
                        "unknown table or key `{}`; a parameter file holds {TABLES}",
                        robid_core::names::short(other)
                    ),
                ));
            }
        };
        let DeValue::Table(items) = value.get_ref() else {
            return Err(located(at, format!("`{name}` must be a table [{name}]")));
        };
        if let Some((before, line)) = first {
            return Err(located(
                at,
                format!(
                    "a second table [{name}], after [{before}] on line {line}; a parameter file \
                     holds {TABLES}: keep one"
                ),
            ));
        }
        first = Some((name, line_column(text, at).0));
        let entries = entries_of(text, name, items, &located)?;
        found = Some((table, entries));
    }
    let (table, entries) = found.ok_or_else(|| {
        Error::Data(DataError::ParameterFile {
            path: path.to_owned(),
            line: None,
            column: None,
            problem: format!("has no table; a parameter file holds {TABLES}"),
        })
    })?;
    Ok(ParameterFile {
        path: path.to_owned(),
        table,
        entries,
        extra,
    })
}

/// The entries of the table `name`, each a finite number within +-[`PARAMETER_LIMIT`], in
/// file order; `located` makes an error at a byte offset of `text`.
fn entries_of(
    text: &str,
    name: &str,
    items: &DeTable<'_>,
    located: &dyn Fn(usize, String) -> Error,
) -> Result<Vec<(String, Entry)>> {
    let mut entries = Vec::with_capacity(items.len());
    for (k, v) in items {
        let key: &str = k.get_ref();
        let (line, column) = line_column(text, k.span().start);
        let source = crate::toml_syntax::shown(text.get(v.span()).unwrap_or("?"));
        let value = number(v.get_ref())
            .filter(|x| x.is_finite())
            .ok_or_else(|| {
                located(
                    k.span().start,
                    format!("[{name}] `{key}` = {source} is not a finite number"),
                )
            })?;
        if value.abs() > PARAMETER_LIMIT {
            return Err(located(
                k.span().start,
                format!(
                    "[{name}] `{key}` = {source} is outside +-{PARAMETER_LIMIT:e}; give it \
                     in SI units (kg, m, kg m^2, N m)"
                ),
            ));
        }
        entries.push((
            key.to_owned(),
            Entry {
                value,
                line,
                column,
            },
        ));
    }
    // the parser's table is sorted by name; keep the file's order
    entries.sort_by_key(|(_, e)| (e.line, e.column));
    Ok(entries)
}

/// The message of a TOML syntax error: a key or table given twice is named with what to
/// do ([`crate::toml_syntax::duplicate`]), toml saying only "duplicate key".
/// What a JSON file given as a parameter file is and what to give instead: for `robid
/// identify`'s report (a `"parameters"` list with `"method"`), its base parameters as a
/// `[base]` table (a `jq` line) or physically consistent ones from `robid feasible`.
fn json_message(text: &str, path: &Path) -> String {
    let report = text.contains("\"parameters\"") && text.contains("\"method\"");
    let what = "a parameter file is TOML with one table, [standard] or [base] \
                (docs/command-line.md#parameter-files)";
    if !report {
        return format!("the file is JSON, not a parameter file: {what}");
    }
    let name = path.display();
    format!(
        "the file is JSON: `robid identify`'s report (--json), not a parameter file: {what}; \
         its identified base parameters as a [base] file: `jq -r '\"[base]\", (.parameters[] \
         | \"\\(.name) = \\(.value)\")' {name} > base.toml` (with the --drive it was \
         identified with), or physically consistent [standard] parameters from them: `robid \
         feasible ROBOT --identified {name} -o params.toml`"
    )
}

fn syntax_message(text: &str, e: &toml::de::Error) -> String {
    match crate::toml_syntax::duplicate(text, e) {
        Some(d) if d.table => format!(
            "not valid TOML: the table [{}] is given a second time; a parameter file holds \
             one table: merge the two into one",
            d.key
        ),
        Some(d) => format!(
            "not valid TOML: `{}` is given a second time in this table; each parameter may \
             be given once: delete the one not meant",
            d.key
        ),
        None => format!("not valid TOML: {}", e.message().trim()),
    }
}

/// The number a TOML value holds (`None` for a string, a table, ..).
fn number(v: &DeValue<'_>) -> Option<f64> {
    match v {
        DeValue::Float(f) => f.as_str().parse().ok(),
        DeValue::Integer(i) => {
            let (text, radix) = (i.as_str(), i.radix());
            i64::from_str_radix(text, radix)
                .ok()
                .map(|i| i as f64)
                .or_else(|| integer_beyond_i64(text, radix))
        }
        _ => None,
    }
}

/// The value of a TOML integer beyond i64 (TOML allows any number of digits): as a float,
/// so that the range check names it as out of range rather than "not a finite number"
/// (`ZZ1 = 99999999999999999999` was told so).
fn integer_beyond_i64(text: &str, radix: u32) -> Option<f64> {
    let (sign, digits) = match text.strip_prefix('-') {
        Some(rest) => (-1.0, rest),
        None => (1.0, text.strip_prefix('+').unwrap_or(text)),
    };
    digits
        .chars()
        .filter(|c| *c != '_')
        .try_fold(0.0f64, |acc, c| {
            Some(acc * f64::from(radix) + f64::from(c.to_digit(radix)?))
        })
        .map(|v| sign * v)
}

/// The name of `names` closest to `key`: the same but for case, or one edit away.
fn nearest<'a>(key: &str, names: &'a [String]) -> Option<&'a str> {
    robid_core::names::nearest(key, names.iter().map(String::as_str))
        .into_iter()
        .next()
        .filter(|n| n.eq_ignore_ascii_case(key) || robid_core::names::distance(key, n) <= 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// What `robid feasible` writes is a parameter file: its `[[links]]` summary is read
    /// over; a `links` key that is not that array of tables is still an error.
    #[test]
    fn the_feasible_output_is_a_parameter_file() {
        let text = "[standard]\nM1 = 2.5\nMX1 = 0.5\n\n[[links]]\nlink = 1\nmass = 2.5\n\
                    com = [0.2, 0.0, 0.0]\n";
        let file = ParameterFile::parse(text, "out.toml".as_ref()).unwrap();
        assert_eq!(file.table(), ParameterTable::Standard);
        assert_eq!(file.get("MX1"), Some(0.5));
        let stray = ParameterFile::parse("links = 3\n[standard]\nM1 = 1\n", "x.toml".as_ref());
        assert!(
            stray
                .unwrap_err()
                .to_string()
                .contains("unknown table or key `links`")
        );
    }

    /// The inertia about the centre of mass, m I_c = m I_o - S(h)' S(h): a link of 2 kg
    /// whose centre of mass is 0.25 m out along x has I_c = I_o - diag(0, 0.125, 0.125);
    /// with I_o = diag(0.01, 0.13, 0.2) the smallest principal moment is 0.005 (accepted),
    /// with YY = 0.12 it is -0.005 (refused, the moment and the centre of mass given),
    /// within the tolerance of 1e-6 of the largest entry it is accepted. A speck of mass
    /// with a first moment is refused (it was lost to overflow below 1e-160 kg).
    #[test]
    fn the_inertia_about_the_centre_of_mass_is_checked_without_dividing() {
        let check = |text: &str| {
            ParameterFile::parse(text, "p.toml".as_ref())
                .unwrap()
                .check_physical(true)
        };
        let link = |yy: &str, mass: &str, mx: &str| {
            format!("[standard]\nXX1 = 0.01\nYY1 = {yy}\nZZ1 = 0.2\nMX1 = {mx}\nM1 = {mass}\n")
        };
        check(&link("0.13", "2", "0.5")).unwrap();
        let e = check(&link("0.12", "2", "0.5")).unwrap_err().to_string();
        assert!(
            e.starts_with(
                "p.toml:2:1: the inertia of link 1 about its centre of mass (0.25, 0, 0) m"
            ) && e.contains("smallest principal moment -0.005 kg m^2"),
            "{e}"
        );
        // -1.5e-7 below zero, within 1e-6 of the largest entry (0.2): rounding of a CAD file
        check(&link("0.12499985", "2", "0.5")).unwrap();
        check(&link("0.1249997", "2", "0.5")).unwrap_err();
        let e = check(&link("0.13", "1e-200", "0.8"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("(8e199, 0, 0) m"), "{e}");
    }

    /// A prior's link with missing values is refused when no missing values can make it
    /// a body's: a moment about the centre of mass below zero (`YY1 = 0.12` with the
    /// centre of mass 0.25 m out along x: -0.005 whatever the products and `MY1`, `MZ1`;
    /// also without `ZZ1`), moments that break the triangle inequality about the origin
    /// (whatever the mass), a first moment without mass; one that they can is taken.
    /// Links whose values are possible but break the triangle inequality about the
    /// centre of mass are warned about, missing values counted as 0 (for a prior, links
    /// with missing values are not judged).
    #[test]
    fn a_prior_s_incomplete_link_and_the_triangle_inequality() {
        let names: Vec<String> = Inertial::ALL
            .iter()
            .map(|s| format!("{}1", s.stem()))
            .collect();
        let file = |text: &str| ParameterFile::parse(text, "p.toml".as_ref()).unwrap();
        let link =
            |yy: &str| format!("[standard]\nXX1 = 0.2\nYY1 = {yy}\nZZ1 = 0.2\nMX1 = 0.5\nM1 = 2\n");
        let refused = |text: &str| file(text).prior(&names).unwrap_err().to_string();
        let e = refused(&link("0.12"));
        assert!(
            e.starts_with("p.toml:2:1: link 1's moment YY1 about its centre of mass would be -0.005 kg m^2 whatever the missing XY1 XZ1 YZ1 MY1 MZ1 are"),
            "{e}"
        );
        let e = refused("[standard]\nXX1 = 0.2\nYY1 = 0.12\nMX1 = 0.5\nM1 = 2\n");
        assert!(
            e.contains("moment YY1 about its centre of mass would be -0.005"),
            "{e}"
        );
        let e = refused("[standard]\nXX1 = 0.01\nYY1 = 0.01\nZZ1 = 0.05\n");
        assert!(
            e.contains("XX1 YY1 ZZ1 = 0.01, 0.01, 0.05 break the triangle inequality about the frame origin (ZZ exceeds"),
            "{e}"
        );
        for (moments, axis) in [("0.05, 0.01, 0.01", "XX"), ("0.01, 0.05, 0.01", "YY")] {
            let [xx, yy, zz] = [0, 1, 2].map(|i| moments.split(", ").nth(i).unwrap());
            let e = refused(&format!("[standard]\nXX1 = {xx}\nYY1 = {yy}\nZZ1 = {zz}\n"));
            assert!(e.contains(&format!("({axis} exceeds the sum")), "{e}");
        }
        let e = refused("[standard]\nM1 = 0\nMX1 = 0.3\n");
        assert!(
            e.contains("link 1 has a first moment but no mass M1"),
            "{e}"
        );
        file(&link("0.13")).prior(&names).unwrap();
        // a flat body (ZZ = XX + YY), and rounding within 1e-6 of the largest moment
        file("[standard]\nXX1 = 100\nYY1 = 100\nZZ1 = 200\n")
            .prior(&names)
            .unwrap();
        file("[standard]\nXX1 = 100\nYY1 = 100\nZZ1 = 200.00001\n")
            .prior(&names)
            .unwrap();
        // no mass and no first moment: nothing to refuse
        file("[standard]\nM1 = 0\nXX1 = 0.1\n")
            .prior(&names)
            .unwrap();
        // the mass or a moment missing: nothing to judge by
        file("[standard]\nYY1 = 0.001\nMX1 = 0.5\n")
            .prior(&names)
            .unwrap();
        // possible values of no body: 0.001 + 0.001 < 0.5 (a warning at the link's first
        // value); none for a body's, or for impossible ones (the readers' error)
        let thin = file("[standard]\nM2 = 3\nXX2 = 0.001\nYY2 = 0.001\nZZ2 = 0.5\n");
        let w = thin.unphysical(true);
        assert_eq!(w.len(), 1);
        assert!(
            w[0].starts_with("p.toml:2: link 2: the principal moments 0.001, 0.001, 0.5 kg m^2")
                && w[0].contains("exceeds the sum of the other two by 0.498 kg m^2"),
            "{w:?}"
        );
        // a prior's missing values are free: not judged
        assert!(thin.unphysical(false).is_empty());
        // 0.01 kg m^2 about every axis through the centre of mass
        let ball = "[standard]\nXX1 = 0.01\nYY1 = 0.135\nZZ1 = 0.135\nMX1 = 0.5\nM1 = 2\n";
        assert!(file(ball).unphysical(true).is_empty());
        assert_eq!(
            file(&link("0.13")).unphysical(true).len(),
            1,
            "0.2 > 0.005 + 0.075"
        );
        assert!(file(&link("0.12")).unphysical(true).is_empty());
    }

    /// JSON given as a parameter file is said to be JSON, and `robid identify`'s report
    /// with what to give instead; toml said "invalid key-value pair, expected key".
    #[test]
    fn json_is_named_and_identify_s_report_told_what_to_give() {
        let report = "\n  {\"robot\": \"ur5e\", \"method\": \"wls\", \"parameters\": []}";
        let e = ParameterFile::parse(report, "id.json".as_ref())
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("id.json:2:3: the file is JSON: `robid identify`'s report (--json)"),
            "{e}"
        );
        for fix in [
            "[standard] or [base] (docs/command-line.md#parameter-files)",
            "(.parameters[] | \"\\(.name) = \\(.value)\")' id.json > base.toml",
            "`robid feasible ROBOT --identified id.json -o params.toml`",
        ] {
            assert!(e.contains(fix), "{e}");
        }
        let e = ParameterFile::parse("{\"M1\": 1}", "p.json".as_ref())
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with(
                "p.json:1:1: the file is JSON, not a parameter file: a parameter file is TOML"
            ),
            "{e}"
        );
        assert!(!e.contains("identify"), "{e}");
    }

    /// A drive term the model lacks names the `--drive` of the file's terms.
    #[test]
    fn drive_terms_the_model_lacks_name_the_drive_to_give() {
        let file = ParameterFile::parse(
            "[standard]\nM1 = 1\nFv1 = 0.1\nFc1 = 0.2\n",
            "p.toml".as_ref(),
        )
        .unwrap();
        let names: Vec<String> = ["M1", "MX1"].map(String::from).to_vec();
        let e = file.values(&names).unwrap_err().to_string();
        assert!(
            e.contains(
                "`Fv1` is a drive term, which this robot does not model: the file has the \
                 drive terms Fv, Fc (`Fv1`, `Fc1`, ...), while the robot models none (no --drive, no `drive` \
                 key): give `--drive Fv,Fc`"
            ),
            "{e}"
        );
    }

    /// A parameter of a link the robot does not have says the file is another robot's (a
    /// six-link arm's file for a two-link one was told to model `Ia1`'s drive term).
    #[test]
    fn another_robots_file_is_named_as_such() {
        let file = ParameterFile::parse(
            "[standard]\nIa1 = 0.1\nM1 = 1\nM2 = 2\nXX3 = 0.1\n",
            "p.toml".as_ref(),
        )
        .unwrap();
        let names: Vec<String> = ["M1", "MX1", "M2", "MX2"].map(String::from).to_vec();
        let e = file.values(&names).unwrap_err().to_string();
        assert!(
            e.starts_with(
                "p.toml:5:1: [standard] has `XX3`, of link 3, but this robot has 2 links"
            ) && e.contains("is the file another robot's?"),
            "{e}"
        );
    }

    /// A parameter or table given twice is named at its second place; toml itself says
    /// only "duplicate key".
    #[test]
    fn a_key_given_twice_is_named_at_its_place() {
        let error = |text: &str| {
            ParameterFile::parse(text, "p.toml".as_ref())
                .unwrap_err()
                .to_string()
        };
        let e = error("[standard]\nM1 = 2\nMX1 = 0.1\nM1 = 3\n");
        assert!(
            e.starts_with("p.toml:4:1: not valid TOML: `M1` is given a second time in this table"),
            "{e}"
        );
        let e = error("[standard]\nM1 = 2\n[standard]\nM2 = 3\n");
        assert!(
            e.starts_with(
                "p.toml:3:2: not valid TOML: the table [standard] is given a second time"
            ),
            "{e}"
        );
        // other syntax errors keep toml's message
        let e = error("[standard]\nM1 = \n");
        assert!(e.starts_with("p.toml:2:6: not valid TOML: "), "{e}");
    }

    /// Two tables: the second in the file is named at its place, with the first. The
    /// tables were taken in the order of their names, so `[standard]` then `[base]` was
    /// reported as "p.toml:1:2: a second table [standard]", at the first table.
    #[test]
    fn the_second_of_two_tables_is_named_at_its_place() {
        let error = |text: &str| {
            ParameterFile::parse(text, "p.toml".as_ref())
                .unwrap_err()
                .to_string()
        };
        let e = error("[standard]\nM1 = 1\n[base]\nZZR1 = 1\n");
        assert!(
            e.starts_with("p.toml:3:2: a second table [base], after [standard] on line 1;"),
            "{e}"
        );
        let e = error("[base]\nZZR1 = 1\n[standard]\nM1 = 1\n");
        assert!(
            e.starts_with("p.toml:3:2: a second table [standard], after [base] on line 1;"),
            "{e}"
        );
        let e = error("[standard]\nM1 = 1\n\n[known]\nM2 = 1\n");
        assert!(
            e.starts_with("p.toml:4:2: a second table [known], after [standard] on line 1;"),
            "{e}"
        );
    }

    /// An integer beyond i64 is out of range, not "not a finite number"; a long value is
    /// quoted short.
    #[test]
    fn a_value_is_told_by_its_size_and_quoted_short() {
        let error = |text: &str| {
            ParameterFile::parse(text, "p.toml".as_ref())
                .unwrap_err()
                .to_string()
        };
        for big in [
            "99999999999999999999",
            "-99999999999999999999",
            "0xffffffffffffffffff",
        ] {
            let e = error(&format!("[base]\nZZ1 = {big}\n"));
            assert_eq!(
                e,
                format!(
                    "p.toml:2:1: [base] `ZZ1` = {big} is outside +-1e6; give it in SI units \
                     (kg, m, kg m^2, N m)"
                )
            );
        }
        assert_eq!(integer_beyond_i64("1_000", 10), Some(1000.0));
        assert_eq!(integer_beyond_i64("+ff", 16), Some(255.0));
        let e = error(&format!("[base]\nZZ1 = \"{}\"\n", "a".repeat(100_000)));
        assert!(
            e.ends_with("`ZZ1` = \"aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa.. (100002 characters) is not a finite number"),
            "{e}"
        );
    }

    #[test]
    fn places_are_lines_and_columns_of_characters() {
        let text = "a = 1\n[standard]\nµM1 = 2\n";
        assert_eq!(line_column(text, 0), (1, 1));
        assert_eq!(line_column(text, 6), (2, 1));
        let at = text.find("M1").unwrap();
        assert_eq!(line_column(text, at), (3, 2));
        // a file saved with a byte-order mark: its first line's places are where an
        // editor shows them (`p.toml:1:2` before)
        let e = ParameterFile::parse("\u{feff}ZZR1 = \"x\"\n", "p.toml".as_ref())
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("p.toml:1:1: unknown table or key `ZZR1`"),
            "{e}"
        );
    }

    #[test]
    fn the_nearest_name_is_suggested() {
        let names: Vec<String> = ["M1", "MX1", "ZZ2", "Fv1"].map(String::from).to_vec();
        assert_eq!(nearest("m1", &names), Some("M1"));
        assert_eq!(nearest("ZZ3", &names), Some("ZZ2"));
        assert_eq!(nearest("Fv", &names), Some("Fv1"));
        assert_eq!(nearest("Fc1", &names), Some("Fv1"));
        assert_eq!(nearest("Ia1", &names), None);
        assert_eq!(nearest("inertia", &names), None);
    }

    #[test]
    fn entries_keep_the_file_order() {
        let file =
            ParameterFile::parse("[standard]\nZZ2 = 1\nM1 = 2\n", Path::new("p.toml")).unwrap();
        let names: Vec<&str> = file.entries().map(|(n, _)| n).collect();
        assert_eq!(names, ["ZZ2", "M1"]);
    }
}
