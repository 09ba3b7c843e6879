//! Extra regressor columns for drive terms that are not in the symbolic model.
//!
//! An extra column has a name (its parameter) and a list of terms; each term puts
//! `coefficient * f(sum of the listed joints' signal)` into one row of the regressor.
//! With `signal` = `q`, `qd`, `qdd` the function is the identity, with `sign_qd` it is
//! the sign, and `constant` puts the coefficient itself. `theta_d`, `theta_dd` and
//! `sign_theta_d` are the same for the motor encoders' velocities and accelerations
//! reflected to the link side (Madsen et al. 2020, eqs. 14-15: the rotor's friction acts
//! at the rotor velocity), differentiated from the same filtered motor positions as the
//! rotor compensation; they need `motor_position` columns. The Staubli TX40 coupled wrist:
//!
//! ```toml
//! [[extra_column]]
//! name = "Iam6"
//! terms = [{ row = 5, signal = "qdd", joints = [6] }, { row = 6, signal = "qdd", joints = [5] }]
//! [[extra_column]]
//! name = "fvm6"
//! terms = [{ row = 5, signal = "qd", joints = [6] }, { row = 6, signal = "qd", joints = [5] }]
//! [[extra_column]]
//! name = "fsm6"
//! terms = [{ row = 5, signal = "sign_qd", joints = [5, 6] }, { row = 6, signal = "sign_qd", joints = [5, 6] }]
//! ```
//! Rows and joints are numbered from 1.

use serde::{Deserialize, Serialize};

use crate::Real;
use crate::error::{Error, Result};
use crate::limits::{MAX_FACTOR, MIN_FACTOR};

/// The signal a term is built from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TermSignal {
    /// Sum of joint positions.
    Q,
    /// Sum of joint velocities.
    Qd,
    /// Sum of joint accelerations.
    Qdd,
    /// Sign of the sum of joint velocities (Coulomb friction).
    SignQd,
    /// The constant 1 (an offset).
    Constant,
    /// Sum of motor velocities reflected to the link side, thetadot.
    ThetaD,
    /// Sum of motor accelerations reflected to the link side, thetaddot.
    ThetaDd,
    /// Sign of the sum of reflected motor velocities (rotor Coulomb friction).
    SignThetaD,
}

impl TermSignal {
    /// Whether the signal comes from the motor encoders (`theta_d`, `theta_dd`,
    /// `sign_theta_d`).
    pub fn is_rotor(self) -> bool {
        matches!(
            self,
            TermSignal::ThetaD | TermSignal::ThetaDd | TermSignal::SignThetaD
        )
    }
}

/// The reflected motor velocities and accelerations of one sample, per joint.
#[derive(Debug, Clone, Copy)]
pub struct RotorSample<'a> {
    /// thetadot.
    pub thetad: &'a [f64],
    /// thetaddot.
    pub thetadd: &'a [f64],
}

/// One entry of an extra column.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExtraTerm {
    /// Regressor row (joint equation), from 1.
    pub row: usize,
    /// Signal.
    pub signal: TermSignal,
    /// Joints summed, from 1 (empty for `constant`).
    #[serde(default)]
    pub joints: Vec<usize>,
    /// Multiplier.
    #[serde(default = "one")]
    pub coefficient: f64,
}

fn one() -> f64 {
    1.0
}

/// Longest extra-column name (characters).
const MAX_NAME: usize = 64;

/// What is wrong with an extra column's name, if anything: it names a parameter in the
/// reports and the parameter files (a TOML key), so it is a word of ASCII letters, digits
/// and `_` beginning with a letter (`""` was accepted and shown as a blank).
fn name_problem(name: &str) -> Option<String> {
    let fix = "name it with ASCII letters, digits and `_`, beginning with a letter (e.g. `Fv1`, \
               `Iam6`)";
    if name.is_empty() {
        return Some(format!("the name is empty; {fix}"));
    }
    if name.chars().count() > MAX_NAME {
        return Some(format!(
            "the name has {} characters, more than {MAX_NAME}; {fix}",
            name.chars().count()
        ));
    }
    (!robid_core::names::is_word(name)).then(|| format!("`{name}` is not a parameter name; {fix}"))
}

/// A named regressor column appended to the model's base regressor.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExtraColumn {
    /// Parameter name.
    pub name: String,
    /// Terms.
    pub terms: Vec<ExtraTerm>,
}

impl ExtraColumn {
    /// Checks row and joint numbers against `dof`, and the coefficients.
    pub fn check(&self, dof: usize) -> Result<()> {
        self.check_keyed(dof, &format!("extra_column({})", self.name))
    }

    /// [`ExtraColumn::check`] with errors on the `Config` key `key` (e.g. `extra_column[2]`).
    pub(crate) fn check_keyed(&self, dof: usize, key: &str) -> Result<()> {
        let name = &self.name;
        let bad = |sub: String, problem: String| {
            Err(Error::setting("Config", &format!("{key}{sub}"), problem))
        };
        if let Some(problem) = name_problem(name) {
            return bad(".name".to_owned(), problem);
        }
        if self.terms.is_empty() {
            return bad(
                String::new(),
                format!(
                    "extra column `{name}` has no terms; add terms = [{{ row = .., signal = .., joints = [..] }}]"
                ),
            );
        }
        for (k, t) in self.terms.iter().enumerate() {
            let at = format!(".terms[{}]", k + 1);
            if t.row == 0 || t.row > dof {
                return bad(
                    format!("{at}.row"),
                    format!(
                        "row {} of `{name}` is outside 1..={dof}; rows and joints are numbered from 1",
                        t.row
                    ),
                );
            }
            if let Some(&j) = t.joints.iter().find(|&&j| j == 0 || j > dof) {
                return bad(
                    format!("{at}.joints"),
                    format!(
                        "joint {j} of `{name}` is outside 1..={dof}; rows and joints are numbered from 1"
                    ),
                );
            }
            if t.signal != TermSignal::Constant && t.joints.is_empty() {
                return bad(
                    format!("{at}.joints"),
                    format!(
                        "a {} term of `{name}` needs `joints = [..]`",
                        signal_name(t.signal)
                    ),
                );
            }
            if t.coefficient == 0.0 {
                return bad(
                    format!("{at}.coefficient"),
                    format!(
                        "a coefficient of 0 removes this term of `{name}` (a column of zeros \
                         is a parameter no data can identify); delete the term, or give its \
                         factor"
                    ),
                );
            }
            // a factor below 1e-12 scales the column's parameter by 1e12 and more (1e-20 gave
            // an `Iam` of -1e17, 1e-300 a least squares that was not finite)
            if !(MIN_FACTOR..=MAX_FACTOR).contains(&t.coefficient.abs()) {
                return bad(
                    format!("{at}.coefficient"),
                    format!(
                        "{} must be of magnitude {MIN_FACTOR:e} to {MAX_FACTOR:e}",
                        crate::error::num(t.coefficient)
                    ),
                );
            }
        }
        Ok(())
    }

    /// Whether this column is `other` times a constant factor: the same terms (rows,
    /// signals and joints, in any order) with proportional coefficients. Two such columns
    /// are one parameter identified twice, which no data can tell apart.
    pub fn same_column_as(&self, other: &ExtraColumn) -> bool {
        let sorted = |c: &ExtraColumn| {
            let mut terms: Vec<(usize, u8, Vec<usize>, f64)> = c
                .terms
                .iter()
                .map(|t| {
                    let mut joints = t.joints.clone();
                    joints.sort_unstable();
                    (t.row, t.signal as u8, joints, t.coefficient)
                })
                .collect();
            terms.sort_by(|a, b| (a.0, a.1, &a.2).cmp(&(b.0, b.1, &b.2)));
            terms
        };
        let (a, b) = (sorted(self), sorted(other));
        if a.len() != b.len() || a.is_empty() {
            return false;
        }
        let ratio = a[0].3 / b[0].3;
        a.iter().zip(&b).all(|(x, y)| {
            (x.0, x.1, &x.2) == (y.0, y.1, &y.2)
                && (x.3 - ratio * y.3).abs() <= 1e-12 * x.3.abs().max(1e-300)
        })
    }

    /// The first term built from the motor encoders, as (term index from 0, signal).
    pub fn rotor_term(&self) -> Option<(usize, TermSignal)> {
        self.terms
            .iter()
            .enumerate()
            .find(|(_, t)| t.signal.is_rotor())
            .map(|(k, t)| (k, t.signal))
    }

    /// Writes this column's entries for one sample into `out` (one per row, `dof` long,
    /// zeroed first). Terms of the motor encoders (see [`TermSignal::is_rotor`]) put 0: use
    /// [`ExtraColumn::fill_with_rotor`] for them.
    pub fn fill(&self, q: &[f64], qd: &[f64], qdd: &[f64], out: &mut [f64]) {
        self.fill_with_rotor(q, qd, qdd, None, out);
    }

    /// [`ExtraColumn::fill`] with the reflected motor signals of the sample (`None`: the
    /// data have no motor encoders, and rotor terms put 0; the pipeline refuses such a
    /// column before it gets here).
    pub fn fill_with_rotor(
        &self,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
        rotor: Option<RotorSample<'_>>,
        out: &mut [f64],
    ) {
        out.iter_mut().for_each(|v| *v = 0.0);
        for t in &self.terms {
            let sum = |x: &[f64]| t.joints.iter().map(|&j| x[j - 1]).sum::<f64>();
            let v = match (t.signal, rotor) {
                (TermSignal::Q, _) => sum(q),
                (TermSignal::Qd, _) => sum(qd),
                (TermSignal::Qdd, _) => sum(qdd),
                (TermSignal::SignQd, _) => Real::sign(sum(qd)),
                (TermSignal::Constant, _) => 1.0,
                (TermSignal::ThetaD, Some(r)) => sum(r.thetad),
                (TermSignal::ThetaDd, Some(r)) => sum(r.thetadd),
                (TermSignal::SignThetaD, Some(r)) => Real::sign(sum(r.thetad)),
                (_, None) => 0.0,
            };
            out[t.row - 1] += t.coefficient * v;
        }
    }

    /// The three coupled-wrist drive columns of a wrist whose joint `b` motor drives
    /// through joint `a` (Staubli TX40: a = 5, b = 6): `Iam{b}`, `fvm{b}`, `fsm{b}`.
    pub fn coupled_wrist(a: usize, b: usize) -> Vec<ExtraColumn> {
        let cross = |name: &str, signal| ExtraColumn {
            name: format!("{name}{b}"),
            terms: vec![
                ExtraTerm {
                    row: a,
                    signal,
                    joints: vec![b],
                    coefficient: 1.0,
                },
                ExtraTerm {
                    row: b,
                    signal,
                    joints: vec![a],
                    coefficient: 1.0,
                },
            ],
        };
        let sign = ExtraColumn {
            name: format!("fsm{b}"),
            terms: [a, b]
                .iter()
                .map(|&row| ExtraTerm {
                    row,
                    signal: TermSignal::SignQd,
                    joints: vec![a, b],
                    coefficient: 1.0,
                })
                .collect(),
        };
        vec![
            cross("Iam", TermSignal::Qdd),
            cross("fvm", TermSignal::Qd),
            sign,
        ]
    }
}

/// The name of `signal` in the config (`theta_d`).
pub fn signal_name(signal: TermSignal) -> &'static str {
    match signal {
        TermSignal::Q => "q",
        TermSignal::Qd => "qd",
        TermSignal::Qdd => "qdd",
        TermSignal::SignQd => "sign_qd",
        TermSignal::Constant => "constant",
        TermSignal::ThetaD => "theta_d",
        TermSignal::ThetaDd => "theta_dd",
        TermSignal::SignThetaD => "sign_theta_d",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coupled_wrist_entries() {
        let cols = ExtraColumn::coupled_wrist(5, 6);
        let q = [0.0; 6];
        let qd = [0.0, 0.0, 0.0, 0.0, 0.5, -2.0];
        let qdd = [0.0, 0.0, 0.0, 0.0, 3.0, 7.0];
        let mut out = [0.0; 6];
        cols[0].fill(&q, &qd, &qdd, &mut out);
        assert_eq!(out, [0.0, 0.0, 0.0, 0.0, 7.0, 3.0]);
        cols[1].fill(&q, &qd, &qdd, &mut out);
        assert_eq!(out, [0.0, 0.0, 0.0, 0.0, -2.0, 0.5]);
        cols[2].fill(&q, &qd, &qdd, &mut out);
        assert_eq!(out, [0.0, 0.0, 0.0, 0.0, -1.0, -1.0]);
        assert_eq!(cols[2].name, "fsm6");
    }

    /// A blank or spaced name, a coefficient of 0, and two columns of the same terms are
    /// refused at their key: they were accepted, and the zero or repeated column was blamed
    /// on the trajectory as rank deficiency.
    #[test]
    fn names_zero_coefficients_and_repeated_columns_are_refused() {
        use crate::data::Config;
        let config = |columns: &str| {
            let text = format!("dof = 2\n{columns}");
            let config = Config::from_toml_str(&text, "c.toml".as_ref()).unwrap();
            config.check(2).map_err(|e| e.to_string())
        };
        let column = |name: &str, terms: &str| {
            format!("[[extra_column]]\nname = \"{name}\"\nterms = [{terms}]\n")
        };
        let qd = "{ row = 1, signal = \"qd\", joints = [1] }, { row = 2, signal = \"qd\", joints = [2] }";
        assert_eq!(config(&column("Fv", qd)), Ok(()));
        for (name, want) in [
            (
                "",
                "c.toml:3:1: `extra_column[1].name`: the name is empty; name it with ASCII",
            ),
            ("F v", "`F v` is not a parameter name"),
            ("1F", "`1F` is not a parameter name"),
        ] {
            let e = config(&column(name, qd)).unwrap_err();
            assert!(e.contains(want), "{e}");
        }
        let e = config(&column(
            "Fv",
            &qd.replacen("joints = [1] }", "joints = [1], coefficient = 0 }", 1),
        ))
        .unwrap_err();
        assert!(
            e.contains("`extra_column[1].terms[1].coefficient`: a coefficient of 0 removes this term of `Fv`"),
            "{e}"
        );
        for tiny in ["1e-13", "-1e-300", "5e-324"] {
            let e = config(&column(
                "Fv",
                &qd.replacen(
                    "joints = [1] }",
                    &format!("joints = [1], coefficient = {tiny} }}"),
                    1,
                ),
            ))
            .unwrap_err();
            assert!(
                e.contains("`extra_column[1].terms[1].coefficient`: ")
                    && e.contains("must be of magnitude 1e-12 to 1e6"),
                "{e}"
            );
        }
        // the same terms in another order, each twice as large: the same parameter
        let twice = "{ row = 2, signal = \"qd\", joints = [2], coefficient = 2 }, { row = 1, signal = \"qd\", joints = [1], coefficient = 2 }";
        let e = config(&(column("Fv", qd) + &column("Fw", twice))).unwrap_err();
        assert!(
            e.contains("`extra_column[2].terms`: `Fw` has the terms of `Fv` (extra_column[1]), up to a factor"),
            "{e}"
        );
        // not proportional, or other joints: columns of their own
        let other = twice.replacen("coefficient = 2 }", "coefficient = 3 }", 1);
        assert_eq!(config(&(column("Fv", qd) + &column("Fw", &other))), Ok(()));
        let joints = qd.replace("joints = [2]", "joints = [1, 2]");
        assert_eq!(config(&(column("Fv", qd) + &column("Fw", &joints))), Ok(()));
    }

    #[test]
    fn parses_from_toml_and_checks_rows() {
        let text = r#"
name = "off2"
terms = [{ row = 2, signal = "constant", coefficient = 2.0 }]
"#;
        let c: ExtraColumn = toml::from_str(text).unwrap();
        c.check(2).unwrap();
        let mut out = [9.0; 2];
        c.fill(&[0.0; 2], &[0.0; 2], &[0.0; 2], &mut out);
        assert_eq!(out, [0.0, 2.0]);
        assert!(c.check(1).is_err());
        let bad: ExtraColumn =
            toml::from_str("name = \"x\"\nterms = [{ row = 1, signal = \"qd\" }]").unwrap();
        assert!(bad.check(2).is_err());
        // joints are numbered 1..=dof
        for joints in ["[0]", "[3]"] {
            let c: ExtraColumn = toml::from_str(&format!(
                "name = \"x\"\nterms = [{{ row = 1, signal = \"qd\", joints = {joints} }}]"
            ))
            .unwrap();
            let e = c.check(2).unwrap_err().to_string();
            assert!(e.contains("outside 1..=2"), "{joints}: {e}");
        }
        // without a coefficient, a term counts once
        let plain: ExtraColumn =
            toml::from_str("name = \"fv\"\nterms = [{ row = 1, signal = \"qd\", joints = [2] }]")
                .unwrap();
        plain.check(2).unwrap();
        let mut out = [9.0; 2];
        plain.fill(&[0.0; 2], &[0.0, -1.5], &[0.0; 2], &mut out);
        assert_eq!(out, [-1.5, 0.0]);
    }

    #[test]
    fn rotor_signals_use_the_reflected_motor_states() {
        let text = r#"
name = "x"
terms = [
  { row = 1, signal = "theta_d", joints = [2] },
  { row = 2, signal = "theta_dd", joints = [1], coefficient = 2.0 },
  { row = 2, signal = "sign_theta_d", joints = [1, 2] },
]
"#;
        let c: ExtraColumn = toml::from_str(text).unwrap();
        c.check(2).unwrap();
        assert_eq!(c.rotor_term(), Some((0, TermSignal::ThetaD)));
        let (q, qd, qdd) = ([0.3, 0.4], [5.0, 6.0], [7.0, 8.0]);
        let rotor = RotorSample {
            thetad: &[0.5, -1.5],
            thetadd: &[3.0, 4.0],
        };
        let mut out = [9.0; 2];
        c.fill_with_rotor(&q, &qd, &qdd, Some(rotor), &mut out);
        // row 1: thetad_2; row 2: 2 thetadd_1 + sign(thetad_1 + thetad_2)
        assert_eq!(out, [-1.5, 2.0 * 3.0 - 1.0]);
        // without motor states the rotor terms are 0, never a link-side stand-in
        c.fill(&q, &qd, &qdd, &mut out);
        assert_eq!(out, [0.0, 0.0]);
        let plain = ExtraColumn::coupled_wrist(1, 2);
        assert!(plain.iter().all(|c| c.rotor_term().is_none()));
        let e = toml::from_str::<ExtraColumn>(
            "name = \"x\"\nterms = [{ row = 1, signal = \"theta_d\" }]",
        )
        .unwrap()
        .check(2)
        .unwrap_err()
        .to_string();
        assert!(e.contains("theta_d term"), "{e}");
    }
}
