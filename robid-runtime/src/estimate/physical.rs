//! Identified parameters whose sign every physical robot fixes, estimated on the other side
//! of zero (docs/identification.md#quality-warnings, warning `not_physical`).
//!
//! A base parameter is a linear combination `beta_b = K_b p` of the standard parameters.
//! Its sign is fixed for every physically consistent robot when the combination is one of
//! quantities that no body or drive makes negative, whatever its geometry. That is derived
//! from `K`, never from the name:
//!
//! - a link's ten inertial parameters enter through its pseudo-inertia `J` (4 x 4, positive
//!   semidefinite for every physically consistent body; Wensing, Kim and Slotine 2018):
//!   `J = [[S, h], [h', m]]` with `S = tr(I)/2 I3 - I` the second moments, `h = (MX, MY,
//!   MZ)`. A linear function of the parameters is `tr(A J)` for one symmetric `A`, and it is
//!   `>= 0` for every positive semidefinite `J` exactly when `A` is positive semidefinite
//!   (the cone is self-dual; a point mass reaches every rank-one `J`). So `YY1 + ZZ2` (a
//!   sum of moments of inertia about axes), `ZZ3 - 0.8 MY3 + 0.16 M3` (`ZZ3` moved by 0.4 m,
//!   the parallel-axis theorem) and the masses qualify; `XX7 - YY7`, a first moment or a
//!   product of inertia does not;
//! - the drive terms `Ia`, `Fv`, `Fc` are `>= 0` (docs/conventions.md#drive-parameters:
//!   a rotor inertia, frictions that dissipate), an offset `Fo` has no sign;
//! - an extra column of the config (its terms, [`ExtraColumn`]) is a friction or an inertia
//!   when its velocity terms dissipate for every motion (`qd' D qd >= 0`), its Coulomb terms
//!   act along the velocity they take the sign of, and its acceleration terms form a
//!   symmetric positive semidefinite matrix; a position or constant term leaves it without
//!   a sign.
//!
//! A combination that is `>= 0` for every physical robot and is estimated below zero by
//! more than [`NOT_PHYSICAL_Z`] standard deviations (or `<= 0` and estimated above) is no
//! noise: no physical robot gives these values, and the model (friction or drive terms it
//! lacks) or the data (units, column order, a joint's sign) are wrong.

use nalgebra::{DMatrix, SymmetricEigen};
use serde::{Deserialize, Serialize};

use crate::drive::{ExtraColumn, TermSignal};
use crate::model::{Inertial, Model, ParameterId, ParameterKind};
use crate::{Num, Result};

use super::QualityWarning;

/// Standard deviations beyond zero on the forbidden side from which a sign-definite
/// parameter is reported as not physical (`3`: a value of a physical robot lands there by
/// noise with probability 0.13 %).
pub const NOT_PHYSICAL_Z: f64 = 3.0;

/// A value whose magnitude is below this fraction of the largest identified value is at
/// the rounding of the data (noise-free data leave a parameter of value 0 at about 1e-13
/// with a deviation ten times smaller) and never reported.
const ROUNDING_VALUE: f64 = 1e-9;

/// The most joints an extra column is judged for ([`extra_column_sign`]).
const MAX_JOINTS: usize = 1000;

/// The side of zero every physical robot keeps a parameter on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Sign {
    /// `>= 0` (masses, moments of inertia, rotor inertias, frictions and their sums).
    NonNegative,
    /// `<= 0` (the negative of such a sum).
    NonPositive,
}

impl Sign {
    /// How many standard deviations `value` lies on the forbidden side of zero (negative
    /// or zero when it lies on the allowed side).
    ///
    /// ```
    /// use robid_runtime::estimate::Sign;
    /// assert_eq!(Sign::NonNegative.beyond(-1.0, 0.25), 4.0);
    /// assert_eq!(Sign::NonPositive.beyond(-1.0, 0.25), -4.0);
    /// ```
    pub fn beyond(self, value: f64, std: f64) -> f64 {
        match self {
            Sign::NonNegative => -value / std,
            Sign::NonPositive => value / std,
        }
    }

    /// The forbidden side in words: `negative` for [`Sign::NonNegative`].
    pub fn forbidden(self) -> &'static str {
        match self {
            Sign::NonNegative => "negative",
            Sign::NonPositive => "positive",
        }
    }
}

/// A parameter whose sign every physical robot fixes, and what it is.
#[derive(Debug, Clone, PartialEq)]
pub struct SignDefinite {
    /// The side of zero it keeps.
    pub sign: Sign,
    /// What it is: the standard parameters it sums (`YY1 + ZZ2`), or an extra column's
    /// terms (`qd5 in row 5`).
    pub expression: String,
    /// Whether it is an extra column of the config (not a base parameter of the model).
    pub extra_column: bool,
}

/// Whether the symmetric matrix `a` is positive and negative semidefinite (both for a
/// zero matrix), to `1e-9` of its largest entry.
fn semidefinite(a: &DMatrix<f64>) -> (bool, bool) {
    let big = a.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    if big == 0.0 {
        return (true, true);
    }
    if !big.is_finite() {
        return (false, false);
    }
    let eigen = SymmetricEigen::new(a / big).eigenvalues;
    let tol = 1e-9;
    (
        eigen.iter().all(|&l| l >= -tol),
        eigen.iter().all(|&l| l <= tol),
    )
}

/// The pseudo-inertia weights `A` (4 x 4) of a linear function `sum c_k p_k` of a link's
/// ten inertial parameters (`c` in [`Inertial::ALL`] order): the function is `tr(A J)`.
fn pseudo_inertia_weights(c: &[f64; 10]) -> DMatrix<f64> {
    let at = |i: Inertial| c[i.index()];
    let (xx, yy, zz) = (at(Inertial::XX), at(Inertial::YY), at(Inertial::ZZ));
    let mut a = DMatrix::zeros(4, 4);
    // XX = S_yy + S_zz, YY = S_xx + S_zz, ZZ = S_xx + S_yy
    a[(0, 0)] = yy + zz;
    a[(1, 1)] = xx + zz;
    a[(2, 2)] = xx + yy;
    // XY = -S_xy (the tensor's entry), MX = h_x, M = m
    let off = [
        (0, 1, -at(Inertial::XY)),
        (0, 2, -at(Inertial::XZ)),
        (1, 2, -at(Inertial::YZ)),
        (0, 3, at(Inertial::MX)),
        (1, 3, at(Inertial::MY)),
        (2, 3, at(Inertial::MZ)),
    ];
    for (i, j, v) in off {
        a[(i, j)] = 0.5 * v;
        a[(j, i)] = 0.5 * v;
    }
    a[(3, 3)] = at(Inertial::M);
    a
}

/// `sum c_k name_k` as text (`YY1 + ZZ2`, `ZZ2 - 0.8*MY3 + 0.16*M3`), coefficients to six
/// digits.
fn expression(terms: &[(f64, &str)]) -> String {
    let mut out = String::new();
    for (k, (c, name)) in terms.iter().enumerate() {
        let sign = match (k, *c < 0.0) {
            (0, true) => "-",
            (0, false) => "",
            (_, true) => " - ",
            (_, false) => " + ",
        };
        let magnitude = Num::rounded(c.abs(), 6);
        if magnitude.0 == 1.0 {
            out += &format!("{sign}{name}");
        } else {
            out += &format!("{sign}{magnitude}*{name}");
        }
    }
    out
}

/// The sign every physical robot gives each base parameter, from `k` (`base x standard`,
/// base = K standard) and the standard parameters' names (`XX1`, .., `Fv2`; a name that
/// is no standard parameter, such as a free term `fvm6`, is of any sign): `None` for a
/// parameter of either sign.
///
/// ```
/// use nalgebra::DMatrix;
/// use robid_runtime::estimate::{Sign, base_signs};
/// // two links' inertial parameters, then Fv1 and Fo1
/// let mut names: Vec<String> = Vec::new();
/// for link in 1..=2 {
///     for stem in ["XX", "XY", "XZ", "YY", "YZ", "ZZ", "MX", "MY", "MZ", "M"] {
///         names.push(format!("{stem}{link}"));
///     }
/// }
/// names.extend(["Fv1".to_string(), "Fo1".to_string()]);
/// let row = |entries: &[(&str, f64)]| {
///     let mut r = vec![0.0; names.len()];
///     for (n, c) in entries {
///         r[names.iter().position(|x| x == n).unwrap()] = *c;
///     }
///     r
/// };
/// let rows = [
///     row(&[("YY1", 1.0), ("ZZ2", 1.0)]),                 // ZZR1: >= 0
///     row(&[("XX2", 1.0), ("YY2", -1.0)]),                // XXR2: either sign
///     row(&[("ZZ2", 1.0), ("MY2", -0.8), ("M2", 0.16)]), // ZZ2 moved by 0.4 m: >= 0
///     row(&[("Fv1", 1.0)]),
///     row(&[("Fo1", 1.0)]),
///     row(&[("MX2", -1.0)]),
/// ];
/// let k = DMatrix::from_fn(rows.len(), names.len(), |b, s| rows[b][s]);
/// let signs = base_signs(&k, &names);
/// assert_eq!(signs[0].as_ref().map(|s| (s.sign, s.expression.as_str())),
///            Some((Sign::NonNegative, "YY1 + ZZ2")));
/// assert!(signs[1].is_none());
/// assert_eq!(signs[2].as_ref().map(|s| s.sign), Some(Sign::NonNegative));
/// assert_eq!(signs[3].as_ref().map(|s| s.sign), Some(Sign::NonNegative));
/// assert!(signs[4].is_none() && signs[5].is_none());
/// ```
pub fn base_signs(k: &DMatrix<f64>, standard_names: &[String]) -> Vec<Option<SignDefinite>> {
    let ids: Vec<Option<ParameterId>> = (0..k.ncols())
        .map(|s| standard_names.get(s).and_then(|n| n.parse().ok()))
        .collect();
    (0..k.nrows())
        .map(|b| {
            let row: Vec<f64> = k.row(b).iter().copied().collect();
            row_sign(&row, &ids, standard_names)
        })
        .collect()
}

/// [`base_signs`] of one row of K.
fn row_sign(row: &[f64], ids: &[Option<ParameterId>], names: &[String]) -> Option<SignDefinite> {
    let big = row.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    if !(big > 0.0 && big.is_finite()) {
        return None;
    }
    // coefficients of rounding size are zeros
    let nonzero = |c: f64| c.abs() > 1e-12 * big;
    let (mut nonnegative, mut nonpositive) = (true, true);
    let mut links: Vec<[f64; 10]> = Vec::new();
    let mut terms: Vec<(f64, &str)> = Vec::new();
    for (s, &c) in row.iter().enumerate() {
        if !nonzero(c) {
            continue;
        }
        terms.push((c, names.get(s).map_or("?", String::as_str)));
        match ids.get(s).copied().flatten()?.kind {
            ParameterKind::Inertial(i) => {
                let link = ids[s].map_or(0, |id| id.link);
                if links.len() <= link {
                    links.resize(link + 1, [0.0; 10]);
                }
                links[link][i.index()] += c;
            }
            ParameterKind::Drive(d) if d.non_negative() => {
                nonnegative &= c > 0.0;
                nonpositive &= c < 0.0;
            }
            // an offset has no sign
            ParameterKind::Drive(_) => return None,
        }
    }
    for c in &links {
        let (psd, nsd) = semidefinite(&pseudo_inertia_weights(c));
        nonnegative &= psd;
        nonpositive &= nsd;
    }
    let sign = match (nonnegative, nonpositive) {
        (true, false) => Sign::NonNegative,
        (false, true) => Sign::NonPositive,
        _ => return None,
    };
    Some(SignDefinite {
        sign,
        expression: expression(&terms),
        extra_column: false,
    })
}

/// The text of one term's signal: `qd5`, `sign(qd5 + qd6)`, `theta_d2`.
fn signal_text(signal: TermSignal, joints: &[usize]) -> String {
    let (stem, sign) = match signal {
        TermSignal::Q => ("q", false),
        TermSignal::Qd => ("qd", false),
        TermSignal::Qdd => ("qdd", false),
        TermSignal::SignQd => ("qd", true),
        TermSignal::Constant => return "1".to_owned(),
        TermSignal::ThetaD => ("theta_d", false),
        TermSignal::ThetaDd => ("theta_dd", false),
        TermSignal::SignThetaD => ("theta_d", true),
    };
    let sum: Vec<String> = joints.iter().map(|j| format!("{stem}{j}")).collect();
    match (sign, sum.len()) {
        (true, _) => format!("sign({})", sum.join(" + ")),
        (false, 1) => sum.join(""),
        (false, _) => format!("({})", sum.join(" + ")),
    }
}

/// The sign every physical drive gives an extra column's parameter, from its terms (see
/// the module): `Some` for a friction that dissipates for every motion or an inertia,
/// `None` for a column of either sign (an offset, a position term, a coupling that does
/// not dissipate on its own).
///
/// ```
/// use robid_runtime::drive::ExtraColumn;
/// use robid_runtime::estimate::{Sign, extra_column_sign};
/// let column = |text: &str| -> ExtraColumn { toml::from_str(text).unwrap() };
/// let fv5 = column(r#"name = "Fv5"
///     terms = [{ row = 5, signal = "qd", joints = [5] }]"#);
/// let s = extra_column_sign(&fv5).unwrap();
/// assert_eq!((s.sign, s.expression.as_str()), (Sign::NonNegative, "qd5 in row 5"));
/// // a coupled wrist's rotor Coulomb friction: sign(qd5 + qd6) in both rows, >= 0
/// let fsm6 = column(r#"name = "fsm6"
///     terms = [{ row = 5, signal = "sign_qd", joints = [5, 6] },
///              { row = 6, signal = "sign_qd", joints = [5, 6] }]"#);
/// assert_eq!(extra_column_sign(&fsm6).map(|s| s.sign), Some(Sign::NonNegative));
/// // qd6 in row 5 and qd5 in row 6 dissipates for no sign on its own
/// let fvm6 = column(r#"name = "fvm6"
///     terms = [{ row = 5, signal = "qd", joints = [6] }, { row = 6, signal = "qd", joints = [5] }]"#);
/// assert!(extra_column_sign(&fvm6).is_none());
/// let offset = column(r#"name = "Fo1"
///     terms = [{ row = 1, signal = "constant" }]"#);
/// assert!(extra_column_sign(&offset).is_none());
/// ```
pub fn extra_column_sign(column: &ExtraColumn) -> Option<SignDefinite> {
    let n = column
        .terms
        .iter()
        .flat_map(|t| t.joints.iter().copied().chain([t.row]))
        .max()?;
    // a column checked against its model has rows and joints up to the model's joints; one
    // numbered beyond any arm is judged of no sign rather than given matrices of its size
    if n > MAX_JOINTS {
        return None;
    }
    // velocity and acceleration matrices (link side, rotor side): row r, joint j
    let mut velocity: [DMatrix<f64>; 2] = [DMatrix::zeros(n, n), DMatrix::zeros(n, n)];
    let mut acceleration: [DMatrix<f64>; 2] = [DMatrix::zeros(n, n), DMatrix::zeros(n, n)];
    // Coulomb terms: (rotor side, multiplicity of each joint in the sign) -> row weights
    let mut coulomb: Vec<(bool, Vec<f64>, Vec<f64>)> = Vec::new();
    let mut text = Vec::new();
    for t in &column.terms {
        let row = t.row.checked_sub(1)?;
        let rotor = usize::from(t.signal.is_rotor());
        let c = t.coefficient;
        if !c.is_finite() {
            return None;
        }
        let factor = if c == 1.0 {
            String::new()
        } else {
            format!("{}*", Num::rounded(c, 6))
        };
        text.push(format!(
            "{factor}{} in row {}",
            signal_text(t.signal, &t.joints),
            t.row
        ));
        match t.signal {
            TermSignal::Q | TermSignal::Constant => return None,
            TermSignal::Qd | TermSignal::ThetaD => {
                for &j in &t.joints {
                    velocity[rotor][(row, j.checked_sub(1)?)] += c;
                }
            }
            TermSignal::Qdd | TermSignal::ThetaDd => {
                for &j in &t.joints {
                    acceleration[rotor][(row, j.checked_sub(1)?)] += c;
                }
            }
            TermSignal::SignQd | TermSignal::SignThetaD => {
                let mut multiplicity = vec![0.0; n];
                for &j in &t.joints {
                    multiplicity[j.checked_sub(1)?] += 1.0;
                }
                let at = match coulomb
                    .iter()
                    .position(|(r, m, _)| *r == (rotor == 1) && *m == multiplicity)
                {
                    Some(at) => at,
                    None => {
                        coulomb.push((rotor == 1, multiplicity, vec![0.0; n]));
                        coulomb.len() - 1
                    }
                };
                coulomb[at].2[row] += c;
            }
        }
    }
    let (mut nonnegative, mut nonpositive, mut any) = (true, true, false);
    let mut side = |psd: bool, nsd: bool| {
        nonnegative &= psd;
        nonpositive &= nsd;
    };
    for d in &velocity {
        // the power qd' D qd is that of the symmetric part
        let symmetric = (d + d.transpose()) * 0.5;
        any |= symmetric.iter().any(|v| *v != 0.0);
        let (psd, nsd) = semidefinite(&symmetric);
        side(psd, nsd);
    }
    for d in &acceleration {
        let big = d.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        if (d - d.transpose()).iter().any(|v| v.abs() > 1e-12 * big) {
            return None;
        }
        any |= big > 0.0;
        let (psd, nsd) = semidefinite(d);
        side(psd, nsd);
    }
    // c_r sign(m' qd) dissipates for every qd exactly when c = k m
    for (_, m, c) in &coulomb {
        let (r, &mr) = m.iter().enumerate().find(|(_, v)| **v > 0.0)?;
        let k = c[r] / mr;
        let big = c.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        if k == 0.0
            || c.iter()
                .zip(m)
                .any(|(c, m)| (c - k * m).abs() > 1e-12 * big)
        {
            return None;
        }
        any = true;
        side(k > 0.0, k < 0.0);
    }
    let sign = match (any, nonnegative, nonpositive) {
        (true, true, false) => Sign::NonNegative,
        (true, false, true) => Sign::NonPositive,
        _ => return None,
    };
    Some(SignDefinite {
        sign,
        expression: text.join(", "),
        extra_column: true,
    })
}

/// The sign-definite parameters of an identification of `model` with the extra columns
/// `extra`, by name: the base parameters from the model's `base_from_standard` (K read
/// column by column), then the extra columns from their terms.
///
/// # Errors
/// The model's [`LengthError`](crate::LengthError) if its `base_from_standard` refuses
/// its own sizes.
///
/// ```
/// use robid_runtime::estimate::{Sign, signs_of};
/// # fn check(model: &dyn robid_runtime::Model) -> robid_runtime::Result<()> {
/// for (name, s) in signs_of(model, &[])? {
///     println!("{name} = {} is {}", s.expression, match s.sign {
///         Sign::NonNegative => ">= 0",
///         Sign::NonPositive => "<= 0",
///     });
/// }
/// # Ok(()) }
/// ```
pub fn signs_of(model: &dyn Model, extra: &[ExtraColumn]) -> Result<Vec<(String, SignDefinite)>> {
    let k = crate::model::base_map(model)?;
    let standard = crate::model::standard_parameter_names(model);
    let base = crate::model::base_parameter_names(model);
    let mut out: Vec<(String, SignDefinite)> = base
        .into_iter()
        .zip(base_signs(&k, &standard))
        .filter_map(|(n, s)| Some((n, s?)))
        .collect();
    out.extend(
        extra
            .iter()
            .filter_map(|c| Some((c.name.clone(), extra_column_sign(c)?))),
    );
    Ok(out)
}

/// The `not_physical` warnings of the identified `values` (with standard deviations
/// `std`, and the robust ones `robust` when the estimate has them) of the parameters
/// `names`: one per parameter of `signs` estimated on its forbidden side of zero by more
/// than [`NOT_PHYSICAL_Z`] of the larger of its two deviations (the classical one alone
/// understates a filtered record's noise, docs/identification.md#robust-standard-deviations).
/// A parameter known exactly (deviation 0) or of a value at the data's rounding (below
/// 1e-9 of the largest value) is not judged.
///
/// ```
/// use robid_runtime::estimate::{Sign, SignDefinite, not_physical};
/// let names = ["ZZR1".to_string(), "MX2".to_string()];
/// let zz = SignDefinite {
///     sign: Sign::NonNegative,
///     expression: "YY1 + ZZ2".into(),
///     extra_column: false,
/// };
/// let signs = [("ZZR1".to_string(), zz)];
/// let w = not_physical(&names, &[-1.02, 0.3], &[0.033, 0.01], None, &signs);
/// assert_eq!(w.len(), 1);
/// assert!(w[0].to_string().contains("ZZR1"), "{}", w[0]);
/// // two standard deviations below zero: noise
/// assert!(not_physical(&names, &[-0.066, 0.3], &[0.033, 0.01], None, &signs).is_empty());
/// // 31 classical deviations, but 2.8 robust ones: noise of a filtered record
/// let robust = [0.36, 0.01];
/// assert!(not_physical(&names, &[-1.02, 0.3], &[0.033, 0.01], Some(&robust), &signs).is_empty());
/// ```
pub fn not_physical(
    names: &[String],
    values: &[f64],
    std: &[f64],
    robust: Option<&[f64]>,
    signs: &[(String, SignDefinite)],
) -> Vec<QualityWarning> {
    let largest = values
        .iter()
        .filter(|v| v.is_finite())
        .fold(0.0f64, |m, v| m.max(v.abs()));
    let mut out = Vec::new();
    for (i, name) in names.iter().enumerate() {
        let (Some(&value), Some(&classical)) = (values.get(i), std.get(i)) else {
            continue;
        };
        let larger = robust.and_then(|r| r.get(i)).filter(|r| **r > classical);
        let s = larger.copied().unwrap_or(classical);
        let Some((_, definite)) = signs.iter().find(|(n, _)| n == name) else {
            continue;
        };
        if !(s > 0.0) || !(value.abs() > ROUNDING_VALUE * largest) {
            continue;
        }
        if definite.sign.beyond(value, s) > NOT_PHYSICAL_Z {
            out.push(QualityWarning::NotPhysical {
                parameter: name.clone(),
                value,
                std: s,
                robust: larger.is_some(),
                sign: definite.sign,
                expression: definite.expression.clone(),
                extra_column: definite.extra_column,
            });
        }
    }
    out
}

/// [`QualityWarning::OppositeSign`] for each of the `dof` joints whose viscous and Coulomb
/// friction (`Fv` and `Fc` of the joint among `names`, drive terms or extra columns; both
/// needed) are both among the [`NotPhysical`](QualityWarning::NotPhysical) warnings
/// `unphysical`: friction below zero on every term of a joint is what a torque (or a
/// position) of the opposite sign gives, where one negative term alone has other causes
/// (the LWR4 log's `Fv7` below zero beside `Fc7` above it: a viscous friction the Coulomb
/// term over-explains), and so does a joint with one friction term only.
///
/// ```
/// use robid_runtime::estimate::{QualityWarning, Sign, SignDefinite, not_physical, opposite_signs};
/// let names: Vec<String> = ["Fv6", "Fc6", "Fv5", "Fc5"].map(String::from).to_vec();
/// let friction = SignDefinite { sign: Sign::NonNegative, expression: String::new(), extra_column: false };
/// let signs: Vec<_> = names.iter().map(|n| (n.clone(), friction.clone())).collect();
/// let w = not_physical(&names, &[-0.6, -0.99, -0.4, 0.2], &[0.005, 0.01, 0.02, 0.01], None, &signs);
/// assert_eq!(w.len(), 3);
/// let flipped = opposite_signs(&w, &names, 6);
/// assert_eq!(flipped.len(), 1);
/// assert_eq!(flipped[0].parameters(), ["Fv6", "Fc6"]);
/// assert!(flipped[0].to_string().contains("torque_scale"));
/// // no joint 6 on a five-joint robot, and Fv6 alone says too little
/// assert!(opposite_signs(&w, &names, 5).is_empty());
/// assert!(opposite_signs(&w[..1], &names[..1], 6).is_empty());
/// ```
pub fn opposite_signs(
    unphysical: &[QualityWarning],
    names: &[String],
    dof: usize,
) -> Vec<QualityWarning> {
    let negative: Vec<String> = unphysical
        .iter()
        .filter(|w| matches!(w, QualityWarning::NotPhysical { .. }))
        .flat_map(|w| w.parameters())
        .collect();
    let joint_of = |n: &str| {
        ["Fv", "Fc"]
            .iter()
            .find_map(|p| n.strip_prefix(p))
            .and_then(|j| j.parse::<usize>().ok())
            .filter(|j| (1..=dof).contains(j))
    };
    let mut joints: Vec<usize> = names.iter().filter_map(|n| joint_of(n)).collect();
    joints.sort_unstable();
    joints.dedup();
    joints
        .into_iter()
        .filter_map(|joint| {
            let friction: Vec<String> = names
                .iter()
                .filter(|n| joint_of(n) == Some(joint))
                .cloned()
                .collect();
            (friction.len() >= 2 && friction.iter().all(|n| negative.contains(n))).then_some(
                QualityWarning::OppositeSign {
                    joint,
                    parameters: friction,
                },
            )
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names() -> Vec<String> {
        let mut n = Vec::new();
        for link in 1..=2 {
            for i in Inertial::ALL {
                n.push(format!("{}{link}", i.stem()));
            }
        }
        n.extend(["Ia1", "Fv1", "Fc1", "Fo1"].map(String::from));
        n
    }

    fn sign_of(entries: &[(&str, f64)]) -> Option<Sign> {
        let names = names();
        let mut row = vec![0.0; names.len()];
        for (n, c) in entries {
            row[names.iter().position(|x| x == n).unwrap()] = *c;
        }
        let k = DMatrix::from_row_slice(1, names.len(), &row);
        base_signs(&k, &names)[0].as_ref().map(|s| s.sign)
    }

    /// The sign comes from the pseudo-inertia, not from the names: sums of moments about
    /// axes, masses, moments about a shifted axis (exactly the parallel-axis square) and
    /// drive terms are signed; differences of moments, first moments, products of inertia,
    /// an offset or a shift that is not a square are not.
    #[test]
    fn signs_follow_the_pseudo_inertia() {
        let plus = Some(Sign::NonNegative);
        assert_eq!(sign_of(&[("YY1", 1.0), ("ZZ2", 1.0)]), plus);
        assert_eq!(sign_of(&[("XX1", 1.0), ("YY1", 1.0)]), plus);
        assert_eq!(sign_of(&[("M1", 1.0), ("M2", 0.16)]), plus);
        assert_eq!(sign_of(&[("ZZ1", 1.0), ("Ia1", 1.0), ("Fv1", 0.0)]), plus);
        assert_eq!(sign_of(&[("Fc1", 2.0)]), plus);
        // YY2 + ZZ3 - 0.8 MY3 + 0.16 M3: the LWR4's ZZR2
        assert_eq!(
            sign_of(&[("YY1", 1.0), ("ZZ2", 1.0), ("MY2", -0.8), ("M2", 0.16)]),
            plus
        );
        // the shift's square too small: a body below the axis makes it negative
        assert_eq!(sign_of(&[("ZZ2", 1.0), ("MY2", -0.8), ("M2", 0.15)]), None);
        assert_eq!(sign_of(&[("XX1", 1.0), ("YY1", -1.0)]), None);
        assert_eq!(sign_of(&[("XX2", 1.0), ("ZZ1", 1.0), ("ZZ2", -1.0)]), None);
        assert_eq!(sign_of(&[("MX1", 1.0)]), None);
        assert_eq!(sign_of(&[("XY1", 1.0)]), None);
        assert_eq!(sign_of(&[("Fo1", 1.0)]), None);
        assert_eq!(sign_of(&[("ZZ1", 1.0), ("Fo1", 1.0)]), None);
        assert_eq!(
            sign_of(&[("M1", -1.0), ("ZZ2", -2.0)]),
            Some(Sign::NonPositive)
        );
        assert_eq!(sign_of(&[("M1", -1.0), ("ZZ2", 2.0)]), None);
        // a single moment is >= 0 with its own link's XX + YY >= ZZ unneeded
        assert_eq!(sign_of(&[("ZZ2", 1.0)]), plus);
        // a free term of no standard name
        let mut n = names();
        n.push("fvm6".into());
        let mut k = DMatrix::zeros(1, n.len());
        k[(0, n.len() - 1)] = 1.0;
        assert!(base_signs(&k, &n)[0].is_none());
    }

    #[test]
    fn the_expression_names_what_is_summed() {
        let names = names();
        let mut k = DMatrix::zeros(1, names.len());
        k[(0, 15)] = 1.0; // ZZ2
        k[(0, 17)] = -0.8000000000000002; // MY2
        k[(0, 19)] = 0.16000000000000003; // M2
        let s = base_signs(&k, &names)[0].clone().unwrap();
        assert_eq!(s.expression, "ZZ2 - 0.8*MY2 + 0.16*M2");
    }

    fn column(text: &str) -> ExtraColumn {
        toml::from_str(text).unwrap()
    }

    #[test]
    fn extra_columns_are_signed_by_what_they_dissipate() {
        let sign = |t: &str| extra_column_sign(&column(t)).map(|s| s.sign);
        let plus = Some(Sign::NonNegative);
        assert_eq!(
            sign(
                r#"name = "a"
                terms = [{ row = 2, signal = "sign_qd", joints = [2] }]"#
            ),
            plus
        );
        assert_eq!(
            sign(
                r#"name = "a"
                terms = [{ row = 2, signal = "qd", joints = [2], coefficient = -2 }]"#
            ),
            Some(Sign::NonPositive)
        );
        assert_eq!(
            sign(
                r#"name = "a"
                terms = [{ row = 1, signal = "theta_d", joints = [1] }, { row = 1, signal = "sign_theta_d", joints = [1] }]"#
            ),
            plus
        );
        assert_eq!(
            sign(
                r#"name = "a"
                terms = [{ row = 1, signal = "qdd", joints = [1] }]"#
            ),
            plus
        );
        // rotor inertia of a coupled wrist: qdd5 + qdd6 in both rows, symmetric, >= 0
        assert_eq!(
            sign(
                r#"name = "a"
                terms = [{ row = 5, signal = "qdd", joints = [5, 6] }, { row = 6, signal = "qdd", joints = [5, 6] }]"#
            ),
            plus
        );
        // a torque on joint 1 from joint 2's velocity alone dissipates for no sign
        assert_eq!(
            sign(
                r#"name = "a"
                terms = [{ row = 1, signal = "qd", joints = [2] }]"#
            ),
            None
        );
        assert_eq!(
            sign(
                r#"name = "a"
                terms = [{ row = 1, signal = "sign_qd", joints = [1, 2] }]"#
            ),
            None
        );
        assert_eq!(
            sign(
                r#"name = "a"
                terms = [{ row = 1, signal = "qdd", joints = [2] }]"#
            ),
            None
        );
        assert_eq!(
            sign(
                r#"name = "a"
                terms = [{ row = 1, signal = "qd", joints = [1] }, { row = 1, signal = "q", joints = [1] }]"#
            ),
            None
        );
        // opposite signs in one column
        assert_eq!(
            sign(
                r#"name = "a"
                terms = [{ row = 1, signal = "qd", joints = [1] }, { row = 1, signal = "sign_qd", joints = [1], coefficient = -1 }]"#
            ),
            None
        );
    }

    #[test]
    fn only_values_beyond_three_deviations_on_the_wrong_side_warn() {
        let signs = vec![(
            "Fv5".to_string(),
            SignDefinite {
                sign: Sign::NonNegative,
                expression: "qd5 in row 5".into(),
                extra_column: true,
            },
        )];
        let names = ["Fv5".to_string(), "M1".to_string()];
        let warn = |v: f64, s: f64| not_physical(&names, &[v, 10.0], &[s, 1.0], None, &signs);
        assert_eq!(warn(-0.66, 0.0315).len(), 1);
        assert!(warn(-0.09, 0.0315).is_empty()); // 2.9 deviations
        assert!(warn(0.66, 0.0315).is_empty());
        assert!(warn(-0.66, 0.0).is_empty()); // known exactly
        assert!(warn(-1e-13, 1e-15).is_empty()); // at the rounding
        let w = &warn(-0.661026, 0.03153)[0];
        assert_eq!(w.kind(), "not_physical");
        assert_eq!(w.parameters(), ["Fv5"]);
        let text = w.to_string();
        for part in [
            "`Fv5` = -0.661 +- 0.0315 is negative",
            "21.0 standard deviations",
            "qd5 in row 5",
        ] {
            assert!(text.contains(part), "{part}: {text}");
        }
        // judged by the larger of the classical and the robust deviation
        let robust = |v: f64, s: f64, r: f64| {
            not_physical(&names, &[v, 10.0], &[s, 1.0], Some(&[r, 1.0]), &signs)
        };
        assert!(robust(-0.66, 0.0315, 0.3).is_empty()); // 2.2 robust deviations
        let w = &robust(-0.661026, 0.03153, 0.1)[0];
        let text = w.to_string();
        assert!(
            text.contains("`Fv5` = -0.661 +- 0.1 is negative by 6.6 robust standard deviations"),
            "{text}"
        );
        let w = &robust(-0.661026, 0.03153, 0.01)[0]; // a robust deviation below the classical
        let text = w.to_string();
        assert!(
            text.contains("`Fv5` = -0.661 +- 0.0315 is negative by 21.0"),
            "{text}"
        );
    }
}
