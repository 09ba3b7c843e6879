//! The ten inertial parameters of a payload rigidly attached to the last link
//! (docs/identification.md#payload-identification), two ways:
//!
//! - [`from_wrenches`]: from a wrist force-torque sensor, whose wrench is
//!   `A(omega, omegadot, vdot, g) phi` of the payload alone ([`crate::wrench`]);
//! - [`from_torques`]: from joint torques with the robot's model known, since the payload
//!   adds to the last link's standard parameters: `tau - tau_model = Y_last phi`.
//!
//! Both stack the equations and solve them with the crate's least squares
//! ([`crate::estimate::ols`] or [`crate::estimate::wls`]), so the values come with
//! standard deviations `sqrt(diag(sigma^2 (W'W)^-1))` and data that do not excite the
//! payload are a rank-deficiency error naming the unexcited parameters. The result is then
//! checked for physical consistency ([`Consistency`]).

mod consistency;
mod sensor;
mod torques;

pub use consistency::{Consistency, Verdict};
pub use sensor::{WrenchSample, from_wrenches};
pub use torques::{JointSample, from_torques, last_link_columns};

use nalgebra::DMatrix;
use nalgebra::DVector;
use std::ops::Range;

use crate::error::{Error, EstimateError, Result};
use crate::estimate::{Estimate, Observation, ols, wls};
use crate::model::Inertial;

/// How a payload is estimated.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PayloadOptions {
    /// Weighted least squares (each group of equations weighted by its own residual
    /// noise: the joints, or the sensor's forces and moments) instead of ordinary.
    pub weighted: bool,
    /// Relative singular-value threshold of the rank decision, in (0, 1).
    pub rank_tolerance: f64,
}

impl Default for PayloadOptions {
    fn default() -> Self {
        Self {
            weighted: true,
            rank_tolerance: 1e-10,
        }
    }
}

/// An identified payload: the estimate of `XX XY XZ YY YZ ZZ MX MY MZ M` (about the
/// last link's frame origin, in that frame) and its physical consistency.
#[derive(Debug, Clone)]
pub struct Payload {
    /// Values, standard deviations and the fit's statistics; parameters named by their
    /// stems (`XX` .. `M`).
    pub estimate: Estimate,
    /// Mass, centre of mass, inertia about it, and the verdict.
    pub consistency: Consistency,
}

impl Payload {
    /// The ten values in the standard order.
    pub fn parameters(&self) -> [f64; 10] {
        std::array::from_fn(|k| self.estimate.values[k])
    }

    /// The ten standard deviations in the standard order: each the larger of the classical
    /// and the robust one ([`Estimate::judged_std`]), what the warnings and the
    /// [`Consistency`] judge by.
    pub fn std(&self) -> [f64; 10] {
        let judged = self.estimate.judged_std();
        std::array::from_fn(|k| judged[k])
    }
}

/// The payload's column names: the ten stems.
fn names() -> Vec<String> {
    Inertial::ALL.iter().map(|p| p.stem().to_string()).collect()
}

/// Solves the stacked system and checks the result; rank-deficient data are an
/// [`Error::PayloadNotExcited`] whose advice `fix` gives, with the most combinations the
/// measurement can determine whatever the motion (the rank reported is at most that: noise
/// gave "rank 9" where the joint torques determine 8).
fn estimate(
    w: DMatrix<f64>,
    y: DVector<f64>,
    groups: Vec<Range<usize>>,
    sample_of_row: Vec<usize>,
    options: &PayloadOptions,
    fix: impl FnOnce() -> Result<(usize, String)>,
) -> Result<Payload> {
    let obs = Observation::new(w, y, groups, sample_of_row, names())?;
    let solved = if options.weighted {
        wls(&obs, options.rank_tolerance)
    } else {
        ols(&obs, options.rank_tolerance)
    };
    let estimate = match solved {
        Err(Error::Estimate(EstimateError::RankDeficient {
            rank, unexcited, ..
        })) => {
            let (most, fix) = fix()?;
            return Err(Error::PayloadNotExcited {
                rank: rank.min(most),
                most,
                unexcited,
                fix,
            });
        }
        // the estimators' advice (less decimation, fewer parameters) is not the payload's:
        // it has neither
        Err(Error::TooFewSamples { context, .. }) => {
            // the least squares count equations; the user counts samples (rows of the file)
            let mut distinct = obs.sample_of_row.clone();
            distinct.sort_unstable();
            distinct.dedup();
            let samples = distinct.len();
            let per = obs.w.nrows().div_ceil(samples.max(1)).max(1);
            return Err(Error::TooFewSamples {
                context,
                found: samples,
                required: crate::estimate::equations_needed(10).div_ceil(per),
                hint: "give more samples (each gives one equation per joint, or six per \
                       wrench): the payload's ten parameters need one equation more than \
                       ten",
            });
        }
        other => other?,
    };
    if let Some(k) = estimate.values.iter().position(|v| !v.is_finite()) {
        return Err(Error::NonFiniteResult {
            what: format!("the payload's {}", estimate.names[k]),
            cause: "the data are too large for f64 arithmetic; check their units".into(),
        });
    }
    let judged = estimate.judged_std();
    let consistency = Consistency::of_estimate(
        &std::array::from_fn(|k| estimate.values[k]),
        &std::array::from_fn(|k| judged[k]),
    );
    Ok(Payload {
        estimate,
        consistency,
    })
}
