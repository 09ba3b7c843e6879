//! Link-by-link identification from the last link backwards, with recursive least squares
//! at each step (docs/identification.md#link-by-link-identification).
//!
//! The torque of joint j depends only on the parameters of links j..n. So the rows of
//! joint n determine link n's parameters; with those known, their columns move to the
//! right-hand side of joint n-1's rows, which then determine link n-1's; and so on down
//! to joint 1. Which parameters a step estimates is read from the observation itself: step
//! j takes every parameter not yet estimated whose column is not zero in joint j's rows.
//! For base parameters that is link j's (the regrouped ones belong to the link of the
//! parameter they are built on); a parameter that joint j's torque does not see waits for
//! the first joint below that does.
//!
//! ## Reference
//! A. Y. Zomaya, "Extraction and computation of identifiable parameters in robot dynamic
//! models: theory and application", IEE Proceedings - Control Theory and Applications
//! 141(1), 1994 (section 6.2: link 3 first, then links 2 and 1, each by the RLS of
//! Table 1).

use nalgebra::{DMatrix, DVector};

use crate::EstimateError;
use crate::error::{Error, Result};
use crate::estimate::least_squares::check_tolerance;
use crate::estimate::lstsq::{InverseGram, condition_number};
use crate::estimate::result::assemble;
use crate::estimate::rls::recursion;
use crate::estimate::{Estimate, Estimator, Observation};

/// The parameters (columns of `obs`) each step estimates, by joint (`steps[j]` for the
/// rows of joint j + 1; the steps run from the last joint to the first). A column is zero
/// in a joint's rows when none of its entries there exceeds `tolerance` times its largest
/// entry. A column zero in every joint's rows is a rank-deficiency error naming it.
///
/// ```
/// use nalgebra::{DMatrix, DVector};
/// use robid_runtime::estimate::{Observation, link_by_link_steps};
/// // joint 1 sees a and b, joint 2 only b: b is estimated from joint 2, then a from joint 1
/// let w = DMatrix::from_row_slice(4, 2, &[1.0, 2.0, 3.0, 1.0, 0.0, 1.0, 0.0, 2.0]);
/// let obs = Observation::new(
///     w, DVector::zeros(4), vec![0..2, 2..4], vec![0, 1, 0, 1], vec!["a".into(), "b".into()],
/// ).unwrap();
/// assert_eq!(link_by_link_steps(&obs, 1e-10).unwrap(), vec![vec![0], vec![1]]);
/// ```
pub fn link_by_link_steps(obs: &Observation, tolerance: f64) -> Result<Vec<Vec<usize>>> {
    check_tolerance(tolerance)?;
    let cols = obs.cols();
    let largest: Vec<f64> = (0..cols).map(|c| obs.w.column(c).amax()).collect();
    let mut known = vec![false; cols];
    let mut steps = vec![Vec::new(); obs.joint_rows.len()];
    for (j, rows) in obs.joint_rows.iter().enumerate().rev() {
        for c in 0..cols {
            let seen = rows
                .clone()
                .any(|r| obs.w[(r, c)].abs() > tolerance * largest[c]);
            if !known[c] && seen {
                known[c] = true;
                steps[j].push(c);
            }
        }
    }
    let unseen: Vec<String> = (0..cols)
        .filter(|&c| !known[c])
        .map(|c| obs.names[c].clone())
        .collect();
    if !unseen.is_empty() {
        return Err(Error::Estimate(EstimateError::RankDeficient {
            rank: cols - unseen.len(),
            columns: cols,
            unexcited: unseen,
        }));
    }
    Ok(steps)
}

/// Identifies the parameters link by link from the last joint's torque backwards
/// ([`link_by_link_steps`]), each step by recursive least squares with forgetting factor
/// `lambda` over its joint's equations in time order, the estimates of the steps before it
/// subtracted from the torques. `obs` must hold joint torques, stacked joint by joint (as
/// the pipeline's observation does). A step whose parameters its joint's rows do not
/// excite is a rank-deficiency error naming them, even when the whole system would not be.
///
/// A joint with fewer equations than its step's parameters while another joint has more
/// lost them (in the pipeline to `processing.rest_velocity`): that is
/// [`EstimateError::AxisLacksEquations`] naming the joint, as is a joint with none when
/// parameters are left unseen, rather than "too few samples" or a rank deficiency.
///
/// The statistics are those of the whole system at the combined estimate (residual,
/// sigma^2, condition number); the standard deviations take each step's estimates of the
/// later links as exact, so they understate the uncertainty of the first links.
pub fn link_by_link(obs: &Observation, lambda: f64, tolerance: f64) -> Result<Estimate> {
    // a joint with too few equations while another has more lost its equations (to
    // processing.rest_velocity): the record is not too short, nor the trajectory poor
    let most = obs.joint_rows.iter().map(|r| r.len()).max().unwrap_or(0);
    let lacks = |joint: usize, found: usize, required: usize| {
        Error::Estimate(EstimateError::AxisLacksEquations {
            method: Estimator::LinkByLink,
            joint,
            found,
            required,
            most,
        })
    };
    let steps = link_by_link_steps(obs, tolerance).map_err(|e| {
        // the parameters only an empty joint's equations would see are left unseen
        match obs.joint_rows.iter().rposition(|r| r.is_empty()) {
            Some(j)
                if most > 0
                    && matches!(e, Error::Estimate(EstimateError::RankDeficient { .. })) =>
            {
                lacks(j + 1, 0, 1)
            }
            _ => e,
        }
    })?;
    let cols = obs.cols();
    let mut beta = DVector::<f64>::zeros(cols);
    let mut p = DMatrix::zeros(cols, cols);
    let mut known: Vec<usize> = Vec::new();
    for (j, unknown) in steps.iter().enumerate().rev() {
        if unknown.is_empty() {
            continue;
        }
        let rows: Vec<usize> = obs.joint_rows[j].clone().collect();
        if rows.len() < unknown.len() && rows.len() < most {
            return Err(lacks(j + 1, rows.len(), unknown.len()));
        }
        let w = obs.w.select_rows(&rows);
        let mut y = DVector::from_iterator(rows.len(), rows.iter().map(|&r| obs.y[r]));
        for &c in &known {
            y.axpy(-beta[c], &w.column(c), 1.0);
        }
        let step = Observation::new(
            w.select_columns(unknown),
            y,
            std::iter::once(0..rows.len()).collect(),
            rows.iter().map(|&r| obs.sample_of_row[r]).collect(),
            unknown.iter().map(|&c| obs.names[c].clone()).collect(),
        )?;
        let (b, pj) = recursion(&step, lambda, tolerance)?;
        for (i, &c) in unknown.iter().enumerate() {
            beta[c] = b[i];
            for (k, &d) in unknown.iter().enumerate() {
                p[(c, d)] = pj[(i, k)];
            }
        }
        known.extend(unknown);
    }
    let cond = condition_number(&obs.w, &obs.names)?;
    assemble(
        Estimator::LinkByLink,
        obs,
        obs,
        beta,
        &InverseGram::unscaled(p),
        cond,
    )
}

#[cfg(test)]
mod tests;
