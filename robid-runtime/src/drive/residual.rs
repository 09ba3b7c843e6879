//! Rotor-side residual columns, `[drive.rotor] residual` (Madsen et al. 2020, eqs. 14-15;
//! docs/identification.md#rotor-dynamics-compensation): what the rotor compensation leaves
//! of the rotor's friction and inertia is identified at the rotor's own velocity and
//! acceleration, `diag(sgn(thetadot)) Fc~ + diag(thetadot) Fv~ (+ diag(thetaddot) B~)`,
//! not at the link side's.
//!
//! ```toml
//! [drive.rotor]
//! inertia = 0.0
//! residual = ["Fc", "Fv"]                  # every joint
//! # residual = [["Fc", "Fv", "Ia"], [], ...] # or one list per joint
//! ```
//!
//! Each term of joint j is one extra column named `Fc{j}_rotor`, `Fv{j}_rotor`,
//! `Ia{j}_rotor` (link-side units: the motor signals are reflected through the gear).
//! A joint whose model also has the link-side `Fc{j}`, `Fv{j}` or `Ia{j}` is refused: the
//! two columns differ only by the joint's deflection, so they are nearly collinear and
//! their split is noise.

use serde::{Deserialize, Serialize};

use super::{ExtraColumn, ExtraTerm, TermSignal};
use crate::Count;
use crate::error::{Error, Result};

/// The config key of the shorthand.
const KEY: &str = "drive.rotor.residual";

/// A rotor-side term.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum ResidualTerm {
    /// Coulomb friction, `sgn(thetadot)`.
    Fc,
    /// Viscous friction, `thetadot`.
    Fv,
    /// Rotor inertia, `thetaddot`.
    Ia,
}

impl ResidualTerm {
    /// The name of the link-side drive term (and of its parameter, with the joint number).
    pub fn name(self) -> &'static str {
        match self {
            ResidualTerm::Fc => "Fc",
            ResidualTerm::Fv => "Fv",
            ResidualTerm::Ia => "Ia",
        }
    }

    fn signal(self) -> TermSignal {
        match self {
            ResidualTerm::Fc => TermSignal::SignThetaD,
            ResidualTerm::Fv => TermSignal::ThetaD,
            ResidualTerm::Ia => TermSignal::ThetaDd,
        }
    }

    /// The parameter name of joint `joint` (from 1): `Fv3_rotor`.
    pub fn parameter(self, joint: usize) -> String {
        format!("{}{joint}_rotor", self.name())
    }
}

/// `residual = [..]`: the same terms for every joint, or one list per joint.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(
    untagged,
    expecting = "a list of residual terms for every joint or one list per joint"
)]
pub enum Residual {
    /// The same terms for every joint.
    All(Vec<ResidualTerm>),
    /// One list per joint.
    Each(Vec<Vec<ResidualTerm>>),
}

impl Residual {
    /// The terms of each of `dof` joints; errors name the key and the fix.
    pub fn terms(&self, dof: usize) -> Result<Vec<Vec<ResidualTerm>>> {
        let per_joint = match self {
            Residual::All(t) => vec![t.clone(); dof],
            Residual::Each(t) if t.len() == dof => t.clone(),
            Residual::Each(t) => {
                return Err(Error::setting(
                    "Config",
                    KEY,
                    format!(
                        "{} for a model of {}; give one list for all joints \
                         ([\"Fc\", \"Fv\"]) or one per joint ([[\"Fc\"], [], ..])",
                        Count(t.len(), "list"),
                        Count(dof, "joint")
                    ),
                ));
            }
        };
        for (j, terms) in per_joint.iter().enumerate() {
            if let Some((_, t)) = terms
                .iter()
                .enumerate()
                .find(|(k, t)| terms[..*k].contains(t))
            {
                return Err(Error::setting(
                    "Config",
                    KEY,
                    format!("joint {} lists `{}` twice; list it once", j + 1, t.name()),
                ));
            }
        }
        Ok(per_joint)
    }

    /// One extra column per joint and term, joint 1 first, in the order listed.
    pub fn columns(&self, dof: usize) -> Result<Vec<ExtraColumn>> {
        Ok(self
            .terms(dof)?
            .iter()
            .enumerate()
            .flat_map(|(j, terms)| {
                terms.iter().map(move |t| ExtraColumn {
                    name: t.parameter(j + 1),
                    terms: vec![ExtraTerm {
                        row: j + 1,
                        signal: t.signal(),
                        joints: vec![j + 1],
                        coefficient: 1.0,
                    }],
                })
            })
            .collect())
    }

    /// Refuses a term whose link-side parameter (`Fv1` for `Fv` of joint 1) is among the
    /// model's parameter `names`: the two columns would be nearly collinear.
    pub fn check_against(&self, dof: usize, names: &[String]) -> Result<()> {
        for (j, terms) in self.terms(dof)?.iter().enumerate() {
            for t in terms {
                let link = format!("{}{}", t.name(), j + 1);
                if names.contains(&link) {
                    return Err(Error::setting(
                        "Config",
                        KEY,
                        format!(
                            "joint {} has both the rotor-side `{}` and the model's link-side \
                             `{link}`, whose columns differ only by the joint's deflection \
                             (nearly collinear); remove `{}` from the description's drive \
                             terms of joint {} (or --drive), or from `residual`",
                            j + 1,
                            t.parameter(j + 1),
                            t.name(),
                            j + 1
                        ),
                    ));
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Deserialize)]
    struct Holder {
        residual: Residual,
    }

    fn parse(text: &str) -> Residual {
        toml::from_str::<Holder>(text).unwrap().residual
    }

    #[test]
    fn shorthand_gives_named_rotor_columns() {
        let all = parse("residual = [\"Fc\", \"Fv\"]");
        let cols = all.columns(2).unwrap();
        let names: Vec<&str> = cols.iter().map(|c| c.name.as_str()).collect();
        assert_eq!(names, ["Fc1_rotor", "Fv1_rotor", "Fc2_rotor", "Fv2_rotor"]);
        // never read as the link-side drive term (parameter files, energy model, reports)
        for n in names {
            assert!(n.parse::<crate::model::ParameterId>().is_err(), "{n}");
        }
        let rotor = super::super::extra::RotorSample {
            thetad: &[-0.25, 2.0],
            thetadd: &[5.0, 7.0],
        };
        let (q, qd, qdd) = ([1.0; 2], [1.0; 2], [1.0; 2]);
        let mut out = [0.0; 2];
        // Fc2_rotor: sgn(thetadot_2) in row 2 only
        cols[2].fill_with_rotor(&q, &qd, &qdd, Some(rotor), &mut out);
        assert_eq!(out, [0.0, 1.0]);
        // Fv1_rotor: thetadot_1 in row 1 only
        cols[1].fill_with_rotor(&q, &qd, &qdd, Some(rotor), &mut out);
        assert_eq!(out, [-0.25, 0.0]);
        let each = parse("residual = [[\"Ia\"], []]");
        let cols = each.columns(2).unwrap();
        assert_eq!(cols.len(), 1);
        assert_eq!(cols[0].name, "Ia1_rotor");
        cols[0].fill_with_rotor(&q, &qd, &qdd, Some(rotor), &mut out);
        assert_eq!(out, [5.0, 0.0]);
        // the wrong number of lists, a term twice, a link-side twin: errors naming the fix
        let e = each.columns(3).unwrap_err().to_string();
        assert!(e.contains("2 lists for a model of 3 joints"), "{e}");
        let e = parse("residual = [\"Fv\", \"Fv\"]")
            .columns(1)
            .unwrap_err()
            .to_string();
        assert!(e.contains("lists `Fv` twice"), "{e}");
        let names = ["Ia1".to_string(), "Fv1".to_string()];
        let e = all.check_against(2, &names).unwrap_err().to_string();
        assert!(
            e.contains("`Fv1_rotor`") && e.contains("link-side `Fv1`"),
            "{e}"
        );
        each.check_against(2, &["Fv1".to_string()]).unwrap();
        assert!(toml::from_str::<Holder>("residual = [\"Fo\"]").is_err());
    }
}
