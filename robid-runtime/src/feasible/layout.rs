//! Where each link's ten inertial parameters and each drive term sit in the standard
//! parameter vector, found from the parameter names
//! (docs/conventions.md#standard-parameters).

use crate::{Error, Result};

/// Names of the ten inertial slots of a link, in the order of
/// docs/conventions.md#standard-parameters.
pub const INERTIAL: [&str; 10] = ["XX", "XY", "XZ", "YY", "YZ", "ZZ", "MX", "MY", "MZ", "M"];

/// A drive term of one joint.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DriveKind {
    /// Rotor inertia `Ia` (non-negative).
    Ia,
    /// Viscous friction `Fv` (non-negative).
    Fv,
    /// Coulomb friction `Fc` (non-negative).
    Fc,
    /// Constant offset `Fo` (any sign).
    Fo,
}

impl DriveKind {
    /// Whether the term must be non-negative to be physical.
    pub fn non_negative(self) -> bool {
        !matches!(self, DriveKind::Fo)
    }

    fn parse(stem: &str) -> Option<DriveKind> {
        Some(match stem {
            "Ia" => DriveKind::Ia,
            "Fv" => DriveKind::Fv,
            "Fc" => DriveKind::Fc,
            "Fo" => DriveKind::Fo,
            _ => return None,
        })
    }
}

/// One drive term: its joint (0-based), kind and index in the standard vector.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Drive {
    /// Joint, 0-based.
    pub joint: usize,
    /// Which term.
    pub kind: DriveKind,
    /// Index into the standard parameters.
    pub index: usize,
}

/// The layout of a standard parameter vector.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Layout {
    /// Per link (0-based), the indices of `XX YY .. M` in [`INERTIAL`] order.
    pub links: Vec<[usize; 10]>,
    /// The drive terms.
    pub drives: Vec<Drive>,
    /// Free terms of any sign outside the rigid-body and drive model, such as the extra
    /// columns of an identification config (e.g. a coupled wrist's `Iam6`): each is its own
    /// base parameter, see [`Problem::with_extra_columns`](super::Problem::with_extra_columns).
    pub extra: Vec<usize>,
}

impl Layout {
    /// Reads the layout from standard parameter names such as `XX1`, `MZ3`, `Fv2`.
    ///
    /// Every link must have all ten inertial parameters; an unknown name is an error.
    pub fn from_names(names: &[String]) -> Result<Layout> {
        let mut links: Vec<[Option<usize>; 10]> = Vec::new();
        let mut drives = Vec::new();
        for (index, name) in names.iter().enumerate() {
            let digits_at = name
                .find(|c: char| c.is_ascii_digit())
                .ok_or_else(|| unknown(name))?;
            let (stem, digits) = name.split_at(digits_at);
            let link: usize = digits.parse().map_err(|_| unknown(name))?;
            if link == 0 {
                return Err(unknown(name));
            }
            let link = link - 1;
            if let Some(slot) = INERTIAL.iter().position(|s| *s == stem) {
                if links.len() <= link {
                    links.resize(link + 1, [None; 10]);
                }
                links[link][slot] = Some(index);
            } else if let Some(kind) = DriveKind::parse(stem) {
                drives.push(Drive {
                    joint: link,
                    kind,
                    index,
                });
            } else {
                return Err(unknown(name));
            }
        }
        let links = links
            .into_iter()
            .enumerate()
            .map(|(j, slots)| {
                let mut out = [0; 10];
                for (s, slot) in slots.iter().enumerate() {
                    out[s] = slot.ok_or_else(|| {
                        Error::setting(
                            "Layout::from_names",
                            "names",
                            format!(
                                "link {} lacks the standard parameter {}{}; every link needs all ten inertial parameters",
                                j + 1,
                                INERTIAL[s],
                                j + 1
                            ),
                        )
                    })?;
                }
                Ok(out)
            })
            .collect::<Result<Vec<_>>>()?;
        Ok(Layout {
            links,
            drives,
            extra: Vec::new(),
        })
    }

    /// Number of standard parameters described.
    pub fn len(&self) -> usize {
        10 * self.links.len() + self.drives.len() + self.extra.len()
    }

    /// Whether there are no parameters at all.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The ten inertial values of link `j` taken from a standard vector.
    pub fn link_values(&self, j: usize, standard: &[f64]) -> [f64; 10] {
        self.links[j].map(|i| standard[i])
    }
}

fn unknown(name: &str) -> Error {
    Error::setting(
        "Layout::from_names",
        "names",
        format!(
            "`{name}` is not a standard parameter name (XXj XYj XZj YYj YZj ZZj MXj MYj MZj Mj Iaj Fvj Fcj Foj)"
        ),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_links_and_drives() {
        let mut names: Vec<String> = INERTIAL.iter().map(|s| format!("{s}1")).collect();
        names.push("Fv1".into());
        let layout = Layout::from_names(&names).unwrap();
        assert_eq!(layout.links, vec![[0, 1, 2, 3, 4, 5, 6, 7, 8, 9]]);
        assert_eq!(layout.drives[0].kind, DriveKind::Fv);
        assert_eq!(layout.len(), 11);
    }

    #[test]
    fn rejects_unknown_and_incomplete() {
        assert!(Layout::from_names(&["QQ1".to_owned()]).is_err());
        assert!(Layout::from_names(&["XX1".to_owned()]).is_err());
    }
}
