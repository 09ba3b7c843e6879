//! Per-axis identification (Milella): each joint's equation identified on its own, from
//! the wrist down, and each parameter taken from the axis that determines it best
//! (docs/identification.md#per-axis-identification).
//!
//! Axis j's equation involves only the parameters whose columns are nonzero in its rows.
//! From those rows alone some of them may not be separable (their columns dependent within
//! the axis), so each axis solves its rows by a rank-revealing least squares (column
//! scaling, QR, SVD of R) and keeps the parameters it determines uniquely: those whose unit
//! vector lies in the row space of the axis's regressor (no component in its null space).
//! A parameter determined by several axes takes the estimate with the smallest relative
//! standard deviation; one that no axis determines alone is an error naming it.
//!
//! ## Reference
//! F. Milella, "Direct Estimate of Closed-Form Dynamic Equation Parameters of a Robot:
//! Tools and Methods for Designing Experiments" (per-axis identification of the COMAU
//! SMART 3S, Table 1: "for the parameters which are in more than one axis dynamic equation
//! the best estimation is considered").

use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};

use crate::EstimateError;
use crate::error::{Error, Result};
use crate::estimate::least_squares::check_tolerance;
use crate::estimate::lstsq::{Condition, column_scales, condition_number};
use crate::estimate::quality::{assess, effects, relative_column_norms};
use crate::estimate::{Estimate, Estimator, Observation, error_bound};
use crate::limits::SVD_ITERATIONS;

/// A parameter counts as determined by an axis when its unit vector has less than this
/// component in the null space of the axis's column-scaled regressor.
const DETERMINED: f64 = 1e-6;

/// A column counts as absent from an axis when its norm there is below this times the
/// largest column norm of the axis (the generated regressor writes exact zeros).
const ABSENT: f64 = 1e-12;

/// What one axis's own identification gave.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AxisFit {
    /// The joint (1-based).
    pub joint: usize,
    /// Equations used.
    pub rows: usize,
    /// Parameters in the axis's equation.
    pub parameters: usize,
    /// The numeric rank of the axis's regressor.
    pub rank: usize,
    /// Condition number of the axis's regressor over the parameters it determines.
    pub condition_number: f64,
    /// The same with the regressor's columns scaled to unit norm (independent of the
    /// parameters' units); 0 in a fit recorded without it.
    #[serde(default)]
    pub scaled_condition_number: f64,
    /// RMS of the axis's residual.
    pub residual_rms: f64,
    /// The parameters the axis determines (names), in column order.
    pub determined: Vec<String>,
}

/// The result of [`per_axis`]: the combined estimate, each axis's fit, and the joint each
/// parameter was taken from (1-based, in the estimate's order).
#[derive(Debug, Clone)]
pub struct PerAxis {
    /// The combined estimate: each parameter from its best axis.
    pub estimate: Estimate,
    /// The axes, from the wrist down (joint n first).
    pub axes: Vec<AxisFit>,
    /// The joint each parameter's estimate comes from.
    pub source: Vec<usize>,
}

/// One axis's estimates: (column, value, standard deviation) of the determined columns.
struct AxisSolution {
    fit: AxisFit,
    values: Vec<(usize, f64, f64)>,
}

/// Per-axis identification of `obs` (its `joint_rows` are the axes); `tolerance` is the
/// relative singular-value threshold of each axis's rank.
///
/// ```
/// use nalgebra::{DMatrix, DVector};
/// use robid_runtime::estimate::{Observation, per_axis};
///
/// // axis 1 sees a and b, axis 2 sees b alone (each with more equations than parameters)
/// let w = DMatrix::from_row_slice(
///     5,
///     2,
///     &[1.0, 0.5, 2.0, -1.0, 1.0, 1.0, 0.0, 1.0, 0.0, 3.0],
/// );
/// let y = &w * DVector::from_vec(vec![2.0, -1.0]);
/// let names = vec!["a".into(), "b".into()];
/// let obs = Observation::new(w, y, vec![0..3, 3..5], vec![0, 1, 2, 0, 1], names).unwrap();
/// let p = per_axis(&obs, 1e-10).unwrap();
/// assert!((p.estimate.values[0] - 2.0).abs() < 1e-12);
/// assert_eq!(p.axes[0].joint, 2);
/// ```
pub fn per_axis(obs: &Observation, tolerance: f64) -> Result<PerAxis> {
    check_tolerance(tolerance)?;
    let n = obs.cols();
    // an axis with too few equations while another has more lost its equations (to
    // processing.rest_velocity): the record is not too short
    let most = obs.joint_rows.iter().map(|r| r.len()).max().unwrap_or(0);
    let mut solutions = Vec::with_capacity(obs.joint_rows.len());
    for (j, rows) in obs.joint_rows.iter().enumerate().rev() {
        solutions.push(solve_axis(obs, j, rows.clone(), tolerance, most)?);
    }
    // each parameter from the axis with the smallest relative deviation
    let mut best: Vec<Option<(f64, f64, usize)>> = vec![None; n];
    for s in &solutions {
        for &(c, value, std) in &s.values {
            let rel = if value == 0.0 {
                f64::INFINITY
            } else {
                std / value.abs()
            };
            let better = match best[c] {
                None => true,
                Some((v, sd, _)) => {
                    let old = if v == 0.0 {
                        f64::INFINITY
                    } else {
                        sd / v.abs()
                    };
                    rel < old
                }
            };
            if better {
                best[c] = Some((value, std, s.fit.joint));
            }
        }
    }
    let missing: Vec<String> = (0..n)
        .filter(|&c| best[c].is_none())
        .map(|c| obs.names[c].clone())
        .collect();
    if !missing.is_empty() {
        return Err(Error::Estimate(EstimateError::NotPerAxis {
            parameters: missing,
        }));
    }
    let chosen: Vec<(f64, f64, usize)> = best.into_iter().flatten().collect();
    let beta = DVector::from_iterator(n, chosen.iter().map(|c| c.0));
    let std: Vec<f64> = chosen.iter().map(|c| c.1).collect();
    let rel: Vec<f64> = chosen
        .iter()
        .map(|&(v, s, _)| {
            if v == 0.0 {
                f64::INFINITY
            } else {
                100.0 * s / v.abs()
            }
        })
        .collect();
    let r = &obs.y - &obs.w * &beta;
    let sigma2 = r.norm_squared() / obs.rows().saturating_sub(n).max(1) as f64;
    let axes: Vec<AxisFit> = solutions.into_iter().map(|s| s.fit).collect();
    let condition_number = axes
        .iter()
        .map(|a| a.condition_number)
        .fold(1.0f64, f64::max);
    let scaled_condition_number = axes
        .iter()
        .map(|a| a.scaled_condition_number)
        .fold(1.0f64, f64::max);
    if !sigma2.is_finite() || beta.iter().chain(&std).any(|v| !v.is_finite()) {
        return Err(Error::NonFiniteResult {
            what: "the per-axis estimate".into(),
            cause:
                "the data overflowed the least squares of an axis: check their units and outliers"
                    .into(),
        });
    }
    let effect = effects(&std, &relative_column_norms(&obs.w, &obs.y));
    let warnings = assess(condition_number, &obs.names, &rel, &effect);
    // Milella's bound with the worst axis's condition number and the combined residual
    let bound = error_bound(condition_number, &r, &obs.y);
    if !bound.is_finite() {
        return Err(Error::NonFiniteResult {
            what: "the error bound of the per-axis estimate".into(),
            cause: "the residual or the condition number overflowed: check the data".into(),
        });
    }
    let estimate = Estimate {
        method: Estimator::PerAxis,
        names: obs.names.clone(),
        residual_rms: obs.residual_rms(&beta)?,
        values: beta.iter().copied().collect(),
        std,
        rel_std_percent: rel,
        sigma2,
        condition_number,
        scaled_condition_number: Some(scaled_condition_number),
        rows: obs.rows(),
        weights: None,
        warnings,
        known: Vec::new(),
        robust: None,
        error_bound: bound,
    };
    Ok(PerAxis {
        estimate,
        axes,
        source: chosen.iter().map(|c| c.2).collect(),
    })
}

/// The rank-revealing least squares of axis `j` (rows `rows` of `obs`; `most`: the most
/// rows any axis has).
fn solve_axis(
    obs: &Observation,
    j: usize,
    rows: std::ops::Range<usize>,
    tolerance: f64,
    most: usize,
) -> Result<AxisSolution> {
    let w = obs.w.rows(rows.start, rows.len()).into_owned();
    let y = obs.y.rows(rows.start, rows.len()).into_owned();
    if let Some(r) = y.iter().position(|v| !v.is_finite()) {
        return Err(Error::Estimate(EstimateError::NonFiniteObservation {
            location: format!("equation {}", rows.start + r + 1),
            sample: None,
            joint: j,
            parameter: "torque".into(),
            value: y[r],
        }));
    }
    // overflow-safe column norms (1 for an all-zero column)
    let norms = column_scales(&w, &obs.names)?;
    let zero = |c: usize| w.column(c).iter().all(|v| *v == 0.0);
    let largest = (0..w.ncols())
        .filter(|&c| !zero(c))
        .map(|c| norms[c])
        .fold(0.0f64, f64::max);
    let present: Vec<usize> = (0..w.ncols())
        .filter(|&c| !zero(c) && norms[c] > ABSENT * largest)
        .collect();
    let k = present.len();
    // one equation more than parameters at least: as many fit any data exactly, leaving no
    // residual for the axis's standard deviations
    let required = super::equations_needed(k);
    if rows.len() < required && rows.len() < most {
        return Err(Error::Estimate(EstimateError::AxisLacksEquations {
            method: Estimator::PerAxis,
            joint: j + 1,
            found: rows.len(),
            required: k.max(1),
            most,
        }));
    }
    if rows.len() < required {
        return Err(Error::TooFewSamples {
            context: format!("the per-axis identification of joint {}", j + 1),
            found: rows.len(),
            required,
            hint: "use more data or less decimation",
        });
    }
    // column-scaled regressor of the parameters present
    let a = DMatrix::from_fn(rows.len(), k, |r, c| w[(r, present[c])] / norms[present[c]]);
    let svd = a
        .clone()
        .try_svd(true, true, f64::EPSILON, SVD_ITERATIONS)
        .ok_or_else(|| Error::NoConvergence {
            what: format!("the SVD of joint {}'s regressor", j + 1),
            iterations: SVD_ITERATIONS,
            hint: "the data hold values of wildly different magnitudes; check them for outliers",
        })?;
    let (Some(u), Some(vt)) = (svd.u.as_ref(), svd.v_t.as_ref()) else {
        return Err(Error::Singular {
            what: format!("joint {}'s regressor (SVD failed)", j + 1),
            hint: "check the data for extreme values",
        });
    };
    let s = &svd.singular_values;
    let smax = s.iter().copied().fold(0.0f64, f64::max);
    let kept: Vec<usize> = (0..s.len()).filter(|&i| s[i] > tolerance * smax).collect();
    let rank = kept.len();
    // minimum-norm solution and (A'A)^+ over the rank part
    let uty = u.transpose() * &y;
    let mut gamma = DVector::zeros(k);
    let mut pinv_gram = DMatrix::zeros(k, k);
    for &i in &kept {
        let v = vt.row(i).transpose();
        gamma.axpy(uty[i] / s[i], &v, 1.0);
        pinv_gram += &v * v.transpose() / (s[i] * s[i]);
    }
    let fitted = &a * &gamma;
    let residual = &y - fitted;
    let dof = rows.len().saturating_sub(rank).max(1);
    // from the overflow-safe norm: the residual's squares underflow below about 1e-154,
    // and every deviation of torques near 1e-170 read 0 (exact)
    let residual_norm = super::lstsq::norm(residual.iter().copied());
    let sigma = residual_norm / (dof as f64).sqrt();
    let null_share = |c: usize| -> f64 {
        (0..s.len())
            .filter(|i| !kept.contains(i))
            .map(|i| vt[(i, c)] * vt[(i, c)])
            .sum::<f64>()
            .sqrt()
    };
    let mut values = Vec::new();
    let mut determined = Vec::new();
    for (c, &col) in present.iter().enumerate() {
        if null_share(c) < DETERMINED {
            let d = norms[col];
            values.push((
                col,
                gamma[c] / d,
                sigma * pinv_gram[(c, c)].max(0.0).sqrt() / d,
            ));
            determined.push(obs.names[col].clone());
        }
    }
    // the condition number of the axis's own regressor over the columns it determines (as
    // the other estimators report cond(W): of W itself, not of its column-scaled form)
    let columns: Vec<usize> = values.iter().map(|v| v.0).collect();
    let condition = if columns.is_empty() {
        Condition {
            raw: 1.0,
            scaled: 1.0,
        }
    } else {
        let names: Vec<String> = columns.iter().map(|&c| obs.names[c].clone()).collect();
        condition_number(&w.select_columns(columns.iter()), &names)?
    };
    Ok(AxisSolution {
        fit: AxisFit {
            joint: j + 1,
            rows: rows.len(),
            parameters: k,
            rank,
            condition_number: condition.raw,
            scaled_condition_number: condition.scaled,
            residual_rms: residual_norm / (rows.len().max(1) as f64).sqrt(),
            determined,
        },
        values,
    })
}

#[cfg(test)]
mod tests;
