//! Warnings on a successful identification that should not be trusted blindly: an
//! ill-conditioned observation matrix, parameters known to worse than their own size, a
//! validation that repeats the estimation data. They are returned with the result (never
//! printed by the library): reports carry them, a command line prints them on stderr.

use std::fmt;

use nalgebra::{DMatrix, DVector};

use crate::Num;

use serde::{Deserialize, Serialize};

/// Condition number of the observation matrix W above which an identification is reported
/// as ill-conditioned. Well-excited real recordings give 1e2 to 1e3 (the TX40 and LWR4
/// logs of `data/`: about 1,000); at 1e4 noise in the torques is amplified ten thousand
/// times into the parameters.
pub const CONDITION_WARNING: f64 = 1e4;

/// Relative standard deviation (percent) above which a parameter is reported as poorly
/// identified: its uncertainty is larger than its value.
pub const REL_STD_WARNING: f64 = 100.0;

/// A parameter whose standard deviation moves the torques by less than this fraction of
/// their norm (`std_i ||W_i|| / ||y||`) is known to the data's rounding, and its relative
/// standard deviation, however large, is no warning: in noise-free data (`robid simulate`
/// without noise) a parameter whose value is about 0 has a standard deviation of about
/// 1e-11 and so a relative one of 100 % or more. Measured data are 1e4 times or more above
/// it (docs/identification.md#quality-warnings).
pub const ROUNDING_EFFECT: f64 = 1e-9;

/// Something a caller should tell the user about an identification that succeeded.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
#[non_exhaustive]
pub enum QualityWarning {
    /// cond(W) is above [`CONDITION_WARNING`].
    IllConditioned {
        /// cond(W).
        condition_number: f64,
        /// The threshold.
        threshold: f64,
    },
    /// Parameters whose relative standard deviation is above [`REL_STD_WARNING`] percent
    /// (or whose value is exactly zero), unless their standard deviation is at the data's
    /// rounding ([`ROUNDING_EFFECT`]).
    Uncertain {
        /// Their names, in parameter order.
        parameters: Vec<String>,
        /// Their relative standard deviations in percent (`None` for a zero value).
        rel_std_percent: Vec<Option<f64>>,
        /// The threshold in percent.
        threshold_percent: f64,
        /// Whether each relative deviation is the larger of the classical and the robust
        /// (Newey-West) one, as when the estimate has robust deviations; else the
        /// classical one (docs/identification.md#robust-standard-deviations).
        #[serde(default)]
        robust: bool,
    },
    /// The energy model's observation is ill-conditioned, or much worse conditioned than
    /// the torque model's on the same data (by more than [`ENERGY_CONDITION_RATIO`]).
    EnergyIllConditioned {
        /// cond of the energy observation.
        energy: f64,
        /// cond of the torque observation of the same samples.
        torque: f64,
        /// Energy equations (one per window, all joints together).
        energy_equations: usize,
        /// Torque equations (one per joint and sample).
        torque_equations: usize,
    },
    /// Validation data that are the estimation data: the validation repeats the fit.
    ValidationRepeatsEstimation {
        /// The validation file (or data set).
        file: String,
    },
    /// The fit on the estimation data is worse than no model at all (relative error above
    /// 100 %: predicting zero torque would do better): the estimate is not usable, as a
    /// recursive estimate that diverged (a forgetting factor too small for the noise).
    PoorFit {
        /// The relative error of the fit (1 = 100 %).
        relative_error: f64,
    },
    /// A joint none of whose equations was kept (every sample excluded, for instance by
    /// `processing.rest_velocity`): its fit figures say nothing.
    JointWithoutEquations {
        /// The joint, from 1.
        joint: usize,
    },
    /// A WLS weight that estimates no noise: the joint's equations leave less than one
    /// degree of freedom once the parameters' share of them (the sum of their leverages)
    /// is taken, so its sigma is its residual sum of squares over 1
    /// (docs/identification.md#weighted-least-squares).
    WeightWithoutNoise {
        /// The joint, from 1.
        joint: usize,
        /// Its equations.
        rows: usize,
        /// Its equations less the sum of their leverages (below 1).
        freedom: f64,
    },
    /// A parameter's column is dominated by a few equations (the largest
    /// [`OUTLIER_ROWS`] hold more than [`OUTLIER_SHARE`] of its squared norm): an outlier
    /// in the data, which the fit follows instead of the rest of the record.
    Outlier {
        /// The parameter.
        parameter: String,
        /// Where the largest equation comes from (file:line when known).
        location: String,
        /// The share of the column's squared norm held by those equations.
        share: f64,
    },
    /// Joint positions differentiated by central differences with no low-pass on them
    /// (`[processing] lowpass` absent or without `"q"`): each differentiation multiplies
    /// the positions' noise by up to twice the sample rate, and noise in the regressor
    /// biases least squares (a real 5 kHz log: fit error 44 % against 15 % filtered,
    /// a first moment twice its value).
    UnfilteredDerivatives {
        /// What was differentiated: "velocities", "accelerations", or both.
        derived: String,
    },
    /// Known standard parameters (`estimation.known`) that fix nothing: each enters the
    /// base parameters only alongside unknown ones that can stand for it, so its value
    /// changes no estimate ([`KnownParameters::without_effect`](crate::estimate::KnownParameters::without_effect)).
    KnownWithoutEffect {
        /// Their names.
        parameters: Vec<String>,
    },
    /// A parameter whose sign every physical robot fixes (a sum of masses, moments of
    /// inertia, rotor inertias or frictions, derived from its expression:
    /// [`base_signs`](crate::estimate::base_signs), [`extra_column_sign`](crate::estimate::extra_column_sign)),
    /// estimated on the other side of zero by more than
    /// [`NOT_PHYSICAL_Z`](crate::estimate::NOT_PHYSICAL_Z) standard deviations: no physical
    /// robot has the identified values, so the model or the data are wrong.
    NotPhysical {
        /// The parameter.
        parameter: String,
        /// Its identified value.
        value: f64,
        /// Its standard deviation: the larger of the classical and the robust one.
        std: f64,
        /// Whether [`std`](QualityWarning::NotPhysical::std) is the robust (Newey-West)
        /// deviation, larger than the classical one.
        #[serde(default)]
        robust: bool,
        /// The side of zero every physical robot keeps it on.
        sign: crate::estimate::Sign,
        /// What it is: the standard parameters it sums, or an extra column's terms.
        expression: String,
        /// Whether it is an extra column of the config.
        extra_column: bool,
    },
    /// Every friction term of a joint (`Fv`, `Fc` of the model or the config's extra
    /// columns of those names) is [`NotPhysical`](QualityWarning::NotPhysical): what a
    /// torque or a position read with the opposite sign of the description's convention
    /// gives.
    OppositeSign {
        /// The joint, from 1.
        joint: usize,
        /// Its friction terms, each below zero.
        parameters: Vec<String>,
    },
}

/// How much worse than the torque model's the energy model's condition number may be
/// before [`QualityWarning::EnergyIllConditioned`] is raised.
pub const ENERGY_CONDITION_RATIO: f64 = 4.0;

/// Number of equations whose share of a column is tested for an outlier.
pub const OUTLIER_ROWS: usize = 3;
/// Share of a column's squared norm above which its largest [`OUTLIER_ROWS`] equations
/// are an outlier (checked when there are at least 100 equations).
pub const OUTLIER_SHARE: f64 = 0.9;

impl QualityWarning {
    /// A short machine-readable name (`ill_conditioned`, `energy_ill_conditioned`,
    /// `uncertain`, `outlier`, `validation_repeats_estimation`, `poor_fit`,
    /// `joint_without_equations`, `weight_without_noise`, `unfiltered_derivatives`,
    /// `known_without_effect`,
    /// `not_physical`, `opposite_sign`).
    pub fn kind(&self) -> &'static str {
        match self {
            QualityWarning::IllConditioned { .. } => "ill_conditioned",
            QualityWarning::EnergyIllConditioned { .. } => "energy_ill_conditioned",
            QualityWarning::Uncertain { .. } => "uncertain",
            QualityWarning::ValidationRepeatsEstimation { .. } => "validation_repeats_estimation",
            QualityWarning::Outlier { .. } => "outlier",
            QualityWarning::PoorFit { .. } => "poor_fit",
            QualityWarning::JointWithoutEquations { .. } => "joint_without_equations",
            QualityWarning::WeightWithoutNoise { .. } => "weight_without_noise",
            QualityWarning::UnfilteredDerivatives { .. } => "unfiltered_derivatives",
            QualityWarning::KnownWithoutEffect { .. } => "known_without_effect",
            QualityWarning::NotPhysical { .. } => "not_physical",
            QualityWarning::OppositeSign { .. } => "opposite_sign",
        }
    }

    /// The parameters concerned (empty when the warning is about the whole run).
    pub fn parameters(&self) -> Vec<String> {
        match self {
            QualityWarning::Uncertain { parameters, .. } => parameters.clone(),
            QualityWarning::Outlier { parameter, .. } => vec![parameter.clone()],
            QualityWarning::KnownWithoutEffect { parameters } => parameters.clone(),
            QualityWarning::NotPhysical { parameter, .. } => vec![parameter.clone()],
            QualityWarning::OppositeSign { parameters, .. } => parameters.clone(),
            _ => Vec::new(),
        }
    }
}

impl fmt::Display for QualityWarning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            QualityWarning::IllConditioned {
                condition_number,
                threshold,
            } => write!(
                f,
                "the observation matrix is ill-conditioned (condition number {condition_number:.3e} > {threshold:e}): \
                 the estimates are sensitive to noise; excite the robot with a richer trajectory \
                 (robid excite) or remove parameters the motion cannot separate"
            ),
            QualityWarning::EnergyIllConditioned {
                energy,
                torque,
                energy_equations,
                torque_equations,
            } => write!(
                f,
                "the energy model's observation is ill-conditioned (condition number {energy:.3e}, \
                 against {torque:.3e} for the torque model on the same samples): it has one \
                 equation per window for all joints together ({energy_equations} here, against \
                 {torque_equations} torque equations), so parameters that the power balance \
                 mixes are poorly separated and the noise reaches them; use --method wls or ols \
                 (robid differentiates the positions for the accelerations) unless the \
                 accelerations cannot be had, or change estimation.energy_window"
            ),
            QualityWarning::Uncertain {
                parameters,
                rel_std_percent,
                threshold_percent,
                robust,
            } => {
                let list: Vec<String> = parameters
                    .iter()
                    .zip(rel_std_percent)
                    .map(|(n, r)| match r {
                        // never rounded onto the threshold (100.13 read "100 %")
                        Some(r) => format!(
                            "{n} ({} %)",
                            if *r >= 10.0 * threshold_percent {
                                format!("{r:.0}")
                            } else {
                                crate::Num::rounded_keeping(*r, 3, |s| s > *threshold_percent)
                                    .to_string()
                            }
                        ),
                        None => format!("{n} (value 0)"),
                    })
                    .collect();
                write!(
                    f,
                    "{} with a relative standard deviation above {threshold_percent} % \
                     ({} by more than its own size{}): {}",
                    crate::Count(parameters.len(), "parameter"),
                    if parameters.len() == 1 {
                        "uncertain"
                    } else {
                        "each uncertain"
                    },
                    if *robust {
                        "; the larger of the classical and the robust deviation"
                    } else {
                        ""
                    },
                    list.join(", ")
                )
            }
            QualityWarning::Outlier {
                parameter,
                location,
                share,
            } => write!(
                f,
                "column `{parameter}` is dominated by a few equations ({:.1} % of its squared norm, the largest from {location}): an outlier in the data; repair or remove that row (check its velocities and accelerations)",
                100.0 * share
            ),
            QualityWarning::PoorFit { relative_error } => write!(
                f,
                "the fit on the estimation data is worse than no model (relative error {:.3e} %, \
                 above 100 %): the estimate is not usable; if the observation matrix is \
                 ill-conditioned (its own warning), the data do not separate the parameters: \
                 excite the robot more or estimate fewer (drive) parameters; with \
                 estimation.method = \"rls\", bring estimation.forgetting closer to 1; else \
                 check the torque columns, their units and signs",
                100.0 * relative_error
            ),
            QualityWarning::JointWithoutEquations { joint } => write!(
                f,
                "joint {joint} has no equations (every sample of it was excluded, for instance \
                 by processing.rest_velocity): its fit figures (RMS 0) say nothing; check the \
                 exclusions"
            ),
            QualityWarning::WeightWithoutNoise {
                joint,
                rows,
                freedom,
            } => write!(
                f,
                "joint {joint}'s WLS weight estimates no noise: its {rows} equations leave \
                 {freedom:.2} degrees of freedom once the parameters' share of them (their \
                 leverages) is taken, so its sigma is its residual over 1; give the joint \
                 more equations (a longer record, a lower processing.rest_velocity, less \
                 decimation) or use estimation.method = \"ols\""
            ),
            QualityWarning::UnfilteredDerivatives { derived } => write!(
                f,
                "the {derived} are differentiated from positions that no low-pass filtered \
                 (the config's [processing] has no lowpass on \"q\"): differentiation \
                 amplifies the positions' noise, which biases the estimates and inflates the \
                 fit error; add lowpass = {{ cutoff = \"auto\", signals = [\"q\"] }} to \
                 [processing] (robid inspect shows the cutoff it chooses), or differentiate \
                 with method = \"savitzky-golay\" over a window wider than its order + 1"
            ),
            QualityWarning::KnownWithoutEffect { parameters } => {
                let one = parameters.len() == 1;
                write!(
                    f,
                    "the known {} {} nothing: {} the base parameters only together with \
                     unknown standard parameters that stand for {} (or not at all), so {} \
                     no estimate (only the error bound, relative to the \
                     torques the known values leave); leave {} out, or give as known too \
                     the standard parameters grouped with {} (`robid model` shows the \
                     groups)",
                    parameters.join(", "),
                    if one { "fixes" } else { "fix" },
                    if one { "it enters" } else { "each enters" },
                    if one { "it" } else { "them" },
                    if one {
                        "its value changes"
                    } else {
                        "their values change"
                    },
                    if one { "it" } else { "them" },
                    if one { "it" } else { "them" },
                )
            }
            QualityWarning::NotPhysical {
                parameter,
                value,
                std,
                robust,
                sign,
                expression,
                extra_column,
            } => {
                let what = if *extra_column {
                    format!(
                        "its extra column ({expression}) is a friction or an inertia of the \
                         drives"
                    )
                } else {
                    format!("it is {expression}")
                };
                write!(
                    f,
                    "`{parameter}` = {} +- {} is {} by {:.1} {}standard deviations, but {what}, \
                     which is {} 0 for every physical robot (masses, moments of inertia about \
                     an axis, rotor inertias and frictions are >= 0): no physical robot has \
                     these values, and the model or the data are wrong; check the model \
                     (friction or drive terms it lacks, such as Fv, Fc or Ia per joint, or a \
                     coupling of the drives) and the data (the torques' units and gear \
                     ratios, the column order, the sign of each joint's position and torque)",
                    Num::rounded(*value, 3),
                    Num::rounded(*std, 3),
                    sign.forbidden(),
                    sign.beyond(*value, *std),
                    if *robust { "robust " } else { "" },
                    match sign {
                        crate::estimate::Sign::NonNegative => ">=",
                        crate::estimate::Sign::NonPositive => "<=",
                    }
                )
            }
            QualityWarning::OppositeSign { joint, parameters } => write!(
                f,
                "joint {joint}'s friction is negative ({}, each beyond {} standard deviations), \
                 as when its torque (or its position) is read with the opposite sign of the \
                 description's convention; check joint {joint}'s torque and position columns, \
                 and if its torque is reversed give it a negative factor in `[units] \
                 torque_scale` (one per joint)",
                parameters.join(", "),
                crate::estimate::NOT_PHYSICAL_Z
            ),
            QualityWarning::ValidationRepeatsEstimation { file } => write!(
                f,
                "validation on {file} uses rows that were used for estimation: it repeats the fit \
                 instead of testing the model; validate on other rows or another file"
            ),
        }
    }
}

/// Columns of W dominated by a few equations: (column, row of the largest entry, share of
/// the squared norm held by the largest [`OUTLIER_ROWS`] entries), for W with at least 100
/// rows.
pub(crate) fn dominated_columns(w: &nalgebra::DMatrix<f64>) -> Vec<(usize, usize, f64)> {
    if w.nrows() < 100 {
        return Vec::new();
    }
    let mut out = Vec::new();
    for (j, col) in w.column_iter().enumerate() {
        // one pass on the squares; a column whose squares overflow is scaled first
        let mut share = top_share(col.iter().copied(), 1.0);
        if !share.1.is_finite() {
            let big = col.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            if !(big > 0.0 && big.is_finite()) {
                continue;
            }
            share = top_share(col.iter().copied(), 1.0 / big);
        }
        let (row, fraction) = share;
        if fraction > OUTLIER_SHARE {
            out.push((j, row, fraction));
        }
    }
    out
}

/// The row of the largest |x| and the share of the squared norm held by the largest
/// [`OUTLIER_ROWS`] entries of `x * scale` (NaN for a zero column).
fn top_share(x: impl Iterator<Item = f64>, scale: f64) -> (usize, f64) {
    let mut top = [(0.0f64, 0usize); OUTLIER_ROWS];
    let mut total = 0.0;
    for (i, v) in x.enumerate() {
        let s = (v * scale) * (v * scale);
        total += s;
        if s > top[OUTLIER_ROWS - 1].0 {
            top[OUTLIER_ROWS - 1] = (s, i);
            top.sort_by(|a, b| b.0.total_cmp(&a.0));
        }
    }
    (top[0].1, top.iter().map(|t| t.0).sum::<f64>() / total)
}

/// `||W_i|| / ||y||` of every column of `w` (each norm taken scaled by the largest entry,
/// so that neither overflows); infinite when `y` is zero.
pub(crate) fn relative_column_norms(w: &DMatrix<f64>, y: &DVector<f64>) -> Vec<f64> {
    let big = w.iter().chain(y.iter()).fold(0.0f64, |m, v| m.max(v.abs()));
    if !(big > 0.0 && big.is_finite()) {
        return vec![f64::INFINITY; w.ncols()];
    }
    let norm = |x: &mut dyn Iterator<Item = &f64>| x.map(|v| (v / big).powi(2)).sum::<f64>().sqrt();
    let y_norm = norm(&mut y.iter());
    w.column_iter()
        .map(|c| norm(&mut c.iter()) / y_norm)
        .collect()
}

/// How far each parameter's standard deviation `std` moves the torques, as a fraction of
/// their norm: `std * norm` with `norm` from [`relative_column_norms`]. A deviation of 0
/// moves nothing, also when the torques are all zero (their norms infinite: the product
/// was NaN, and a payload estimated from torques the model explains exactly, every value
/// and deviation 0, was "uncertain by more than its own size" in all ten parameters).
pub(crate) fn effects(std: &[f64], norms: &[f64]) -> Vec<f64> {
    std.iter()
        .zip(norms)
        .map(|(s, c)| if *s == 0.0 { 0.0 } else { s * c })
        .collect()
}

/// `warnings` with their parameters uncertain by more than their size judged again for the
/// parameters `names` (relative deviations `rel`, effects `effect`, as [`assess`] takes
/// them; `robust` when each deviation is the larger of the classical and the robust one),
/// in the place the old judgement had (after the condition warning when there was none):
/// the other warnings are kept as they are.
pub(crate) fn reassess_uncertain(
    warnings: &[QualityWarning],
    names: &[String],
    rel: &[f64],
    effect: &[f64],
    robust: bool,
) -> Vec<QualityWarning> {
    let uncertain = |w: &QualityWarning| matches!(w, QualityWarning::Uncertain { .. });
    let at = warnings.iter().position(uncertain).unwrap_or_else(|| {
        warnings
            .iter()
            .take_while(|w| matches!(w, QualityWarning::IllConditioned { .. }))
            .count()
    });
    let mut out: Vec<QualityWarning> = warnings.iter().filter(|w| !uncertain(w)).cloned().collect();
    for (k, w) in uncertain_parameters(names, rel, effect, robust)
        .into_iter()
        .enumerate()
    {
        out.insert(at + k, w);
    }
    out
}

/// The warnings of an estimate with condition number `condition` and relative standard
/// deviations `rel` (percent, infinite for a zero value) of the parameters `names`, whose
/// standard deviations move the torques by `effect` of their norm ([`ROUNDING_EFFECT`];
/// infinite or NaN where unknown).
pub(crate) fn assess(
    condition: f64,
    names: &[String],
    rel: &[f64],
    effect: &[f64],
) -> Vec<QualityWarning> {
    let mut out = Vec::new();
    if condition > CONDITION_WARNING {
        out.push(QualityWarning::IllConditioned {
            condition_number: condition,
            threshold: CONDITION_WARNING,
        });
    }
    out.extend(uncertain_parameters(names, rel, effect, false));
    out
}

/// The [`QualityWarning::Uncertain`] of the parameters `names` whose relative deviation
/// `rel` is above [`REL_STD_WARNING`] and whose `effect` is not at the data's rounding
/// ([`assess`]), `robust` saying which deviations they are; `None` when there is none.
fn uncertain_parameters(
    names: &[String],
    rel: &[f64],
    effect: &[f64],
    robust: bool,
) -> Option<QualityWarning> {
    let poor: Vec<(String, Option<f64>)> = names
        .iter()
        .zip(rel)
        .zip(effect.iter().chain(std::iter::repeat(&f64::INFINITY)))
        .filter(|((_, r), e)| **r > REL_STD_WARNING && !(**e < ROUNDING_EFFECT))
        .map(|((n, r), _)| (n.clone(), Some(*r).filter(|r| r.is_finite())))
        .collect();
    (!poor.is_empty()).then(|| {
        let (parameters, rel_std_percent) = poor.into_iter().unzip();
        QualityWarning::Uncertain {
            parameters,
            rel_std_percent,
            threshold_percent: REL_STD_WARNING,
            robust,
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_column_held_by_a_few_rows_is_found_whatever_its_magnitude() {
        let w = nalgebra::DMatrix::from_fn(200, 3, |i, j| match j {
            0 => (i as f64 * 0.3).sin(),
            1 if i == 57 => 1e3,
            2 if i == 91 => 1e200,
            _ => 1e-3 * (i as f64).cos(),
        });
        let d = dominated_columns(&w);
        assert_eq!(d.len(), 2, "{d:?}");
        assert_eq!((d[0].0, d[0].1), (1, 57));
        assert_eq!((d[1].0, d[1].1), (2, 91));
        // a spike 1e6 times the column dominates it: measured share 1 - 1e-10
        assert!(d.iter().all(|x| x.2 > 1.0 - 2e-10));
        // too few rows to tell
        assert!(dominated_columns(&w.rows(0, 99).into_owned()).is_empty());
    }

    /// The share is that of the squares, and "dominated" means more than
    /// [`OUTLIER_SHARE`]: a 100-row column of 29, 4, 4 and 97 ones has its three largest
    /// squares 873 of 970, exactly 0.9, and is not flagged; with one of the ones halved
    /// (873 of 969.25) it is.
    #[test]
    fn the_share_of_the_squares_decides_from_100_rows() {
        let column = |fourth: f64| {
            nalgebra::DMatrix::from_fn(100, 1, |i, _| match i {
                10 => 29.0,
                20 | 30 => 4.0,
                40 => fourth,
                _ => 1.0,
            })
        };
        assert_eq!(top_share(column(1.0).iter().copied(), 1.0), (10, 0.9));
        assert!(dominated_columns(&column(1.0)).is_empty());
        let d = dominated_columns(&column(0.5));
        assert_eq!(d, vec![(0, 10, 873.0 / 969.25)]);
    }

    #[test]
    fn an_outlier_names_its_parameter() {
        let w = QualityWarning::Outlier {
            parameter: "XX2".into(),
            location: "run.csv:12".into(),
            share: 0.95,
        };
        assert_eq!(w.parameters(), vec!["XX2"]);
    }

    #[test]
    fn thresholds_decide_and_name_the_parameters() {
        let names: Vec<String> = ["a", "b", "c"].iter().map(|s| s.to_string()).collect();
        let unknown = [f64::INFINITY; 3];
        assert!(assess(CONDITION_WARNING, &names, &[1.0, 100.0, 5.0], &unknown).is_empty());
        let w = assess(6.9e9, &names, &[1.0, 45.5, 250.0], &unknown);
        assert_eq!(w.len(), 2);
        assert_eq!(w[0].kind(), "ill_conditioned");
        assert_eq!(w[1].parameters(), vec!["c"]);
        assert!(w[1].to_string().contains("c (250 %)"), "{}", w[1]);
        let w = assess(10.0, &names, &[f64::INFINITY, 1.0, 1.0], &unknown);
        assert!(w[0].to_string().contains("a (value 0)"), "{}", w[0]);
    }

    /// A parameter whose standard deviation is at the data's rounding is no warning,
    /// whatever its relative one; one just above it is.
    #[test]
    fn uncertainty_at_the_rounding_level_is_no_warning() {
        let names: Vec<String> = ["a", "b", "c"].iter().map(|s| s.to_string()).collect();
        let rel = [250.0, 250.0, f64::INFINITY];
        let w = assess(10.0, &names, &rel, &[0.5e-9, 2e-9, 1e-12]);
        assert_eq!(w.len(), 1);
        assert_eq!(w[0].parameters(), vec!["b"]);
        // unknown effects keep the rule on the relative deviation alone
        let w = assess(10.0, &names, &rel, &[f64::NAN, f64::INFINITY, f64::NAN]);
        assert_eq!(w[0].parameters(), vec!["a", "b", "c"]);
    }

    #[test]
    fn column_norms_are_relative_to_the_torques_and_do_not_overflow() {
        let w = DMatrix::from_row_slice(2, 2, &[3e300, 0.0, 4e300, 1e-300]);
        let y = DVector::from_column_slice(&[0.0, 1e300]);
        let r = relative_column_norms(&w, &y);
        assert!((r[0] - 5.0).abs() < 1e-12 && r[1] < 1e-300, "{r:?}");
        assert!(relative_column_norms(&w, &DVector::zeros(2))[0].is_infinite());
    }

    /// The uncertain parameters are counted in words: "1 parameter ... (uncertain by more
    /// than its own size)", "2 parameters ... (each uncertain ...)"; it was "1 parameter(s)"
    /// whatever the count.
    /// Torques all zero and explained exactly (a payload of nothing): every value and
    /// deviation is 0, and no parameter is "uncertain by more than its own size".
    #[test]
    fn exact_zeros_are_not_uncertain() {
        let names = ["M".to_string(), "MX".to_string()];
        let norms = relative_column_norms(
            &nalgebra::DMatrix::from_element(3, 2, 1.0),
            &DVector::zeros(3),
        );
        let effect = effects(&[0.0, 0.0], &norms);
        assert_eq!(effect, [0.0, 0.0]);
        assert!(assess(1.0, &names, &[f64::INFINITY; 2], &effect).is_empty());
        // a deviation that is not zero, with zero torques, still warns
        let effect = effects(&[1e-3, 0.0], &norms);
        assert_eq!(assess(1.0, &names, &[f64::INFINITY; 2], &effect).len(), 1);
    }

    /// The uncertain parameters judged again take the place of the old judgement, or,
    /// without one, follow the condition warning; the other warnings keep their order.
    #[test]
    fn reassessed_uncertainty_keeps_its_place() {
        let ill = QualityWarning::IllConditioned {
            condition_number: 1e9,
            threshold: CONDITION_WARNING,
        };
        let poor = QualityWarning::PoorFit {
            relative_error: 2.0,
        };
        let names = vec!["a".to_string(), "b".to_string()];
        let kinds = |w: &[QualityWarning]| w.iter().map(|w| w.kind()).collect::<Vec<_>>();
        let old = assess(1e9, &names, &[500.0, 1.0], &[1.0; 2]);
        assert_eq!(kinds(&old), ["ill_conditioned", "uncertain"]);
        let mut before = old.clone();
        before.push(poor.clone());
        let again = reassess_uncertain(&before, &names, &[1.0, 300.0], &[1.0; 2], false);
        assert_eq!(kinds(&again), ["ill_conditioned", "uncertain", "poor_fit"]);
        assert!(
            again[1].to_string().ends_with(": b (300 %)"),
            "{}",
            again[1]
        );
        // none before: after the condition warning
        let again = reassess_uncertain(&[ill, poor], &names, &[1.0, 300.0], &[1.0; 2], false);
        assert_eq!(kinds(&again), ["ill_conditioned", "uncertain", "poor_fit"]);
        // none after: removed
        let again = reassess_uncertain(&before, &names, &[1.0, 1.0], &[1.0; 2], false);
        assert_eq!(kinds(&again), ["ill_conditioned", "poor_fit"]);
    }

    /// A relative deviation just above the threshold is not rounded onto it (100.13 read
    /// "100 %"); a large one is written whole.
    #[test]
    fn uncertain_figures_stay_above_the_threshold() {
        let said = |r: f64| {
            QualityWarning::Uncertain {
                parameters: vec!["XY2".into()],
                rel_std_percent: vec![Some(r)],
                threshold_percent: REL_STD_WARNING,
                robust: false,
            }
            .to_string()
        };
        assert!(said(100.13).ends_with("XY2 (100.1 %)"), "{}", said(100.13));
        assert!(
            said(100.004).ends_with("XY2 (100.004 %)"),
            "{}",
            said(100.004)
        );
        assert!(said(145.8).ends_with("XY2 (146 %)"), "{}", said(145.8));
        assert!(
            said(124255.3).ends_with("XY2 (124255 %)"),
            "{}",
            said(124255.3)
        );
    }

    #[test]
    fn uncertain_parameters_are_counted_in_words() {
        let warning = |names: &[&str]| QualityWarning::Uncertain {
            parameters: names.iter().map(|n| n.to_string()).collect(),
            rel_std_percent: names.iter().map(|_| Some(250.0)).collect(),
            threshold_percent: REL_STD_WARNING,
            robust: false,
        };
        let one = warning(&["ZZR1"]).to_string();
        assert!(
            one.starts_with(
                "1 parameter with a relative standard deviation above 100 % \
                             (uncertain by more than its own size): ZZR1 (250 %)"
            ),
            "{one}"
        );
        let two = warning(&["ZZR1", "MXR2"]).to_string();
        assert!(
            two.starts_with(
                "2 parameters with a relative standard deviation above 100 % \
                             (each uncertain by more than its own size): ZZR1 (250 %), MXR2"
            ),
            "{two}"
        );
    }
}
