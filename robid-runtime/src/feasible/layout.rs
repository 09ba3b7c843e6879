//! Where each link's ten inertial parameters and each drive term sit in the standard
//! parameter vector, found from the parameter names
//! (docs/conventions.md#standard-parameters).

use crate::model::{DriveTerm, Inertial, ParameterId, ParameterKind};
use crate::{Error, Result};

/// One drive term: its joint (0-based), kind and index in the standard vector.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Drive {
    /// Joint, 0-based.
    pub joint: usize,
    /// Which term.
    pub kind: DriveTerm,
    /// Index into the standard parameters.
    pub index: usize,
}

/// The layout of a standard parameter vector.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Layout {
    /// Per link (0-based), the indices of `XX XY .. M` in [`Inertial::ALL`] order.
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
            let id: ParameterId = name.parse().map_err(|_| unknown(name))?;
            match id.kind {
                ParameterKind::Inertial(slot) => {
                    if links.len() <= id.link {
                        links.resize(id.link + 1, [None; 10]);
                    }
                    links[id.link][slot.index()] = Some(index);
                }
                ParameterKind::Drive(kind) => drives.push(Drive {
                    joint: id.link,
                    kind,
                    index,
                }),
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
                                Inertial::ALL[s].stem(),
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
        let mut names: Vec<String> = Inertial::ALL
            .iter()
            .map(|s| format!("{}1", s.stem()))
            .collect();
        names.push("Fv1".into());
        let layout = Layout::from_names(&names).unwrap();
        assert_eq!(layout.links, vec![[0, 1, 2, 3, 4, 5, 6, 7, 8, 9]]);
        assert_eq!(layout.drives[0].kind, DriveTerm::Fv);
        assert_eq!(layout.len(), 11);
    }

    #[test]
    fn rejects_unknown_and_incomplete() {
        let unknown = Layout::from_names(&["QQ1".to_owned()]).unwrap_err();
        assert!(unknown.to_string().contains("`QQ1` is not"), "{unknown}");
        let lacking = Layout::from_names(&["XX2".to_owned()]).unwrap_err();
        assert!(
            lacking
                .to_string()
                .contains("link 1 lacks the standard parameter XX1"),
            "{lacking}"
        );
    }

    /// Links, drive terms and extra columns all count; no names, no parameters.
    #[test]
    fn the_length_counts_every_kind_of_parameter() {
        let mut names = crate::feasible::fixture::link_names(2);
        names.extend(["Ia2", "Fc1"].map(String::from));
        let mut layout = Layout::from_names(&names).unwrap();
        assert_eq!((layout.len(), layout.is_empty()), (22, false));
        assert_eq!(
            layout.drives[1],
            Drive {
                joint: 0,
                kind: DriveTerm::Fc,
                index: 21
            }
        );
        layout.extra = vec![22, 23, 24];
        assert_eq!(layout.len(), 25);
        let empty = Layout::from_names(&[]).unwrap();
        assert_eq!((empty.len(), empty.is_empty()), (0, true));
        let drives_only = Layout::from_names(&["Fv1".to_owned()]).unwrap();
        assert_eq!((drives_only.len(), drives_only.is_empty()), (1, false));
    }
}
