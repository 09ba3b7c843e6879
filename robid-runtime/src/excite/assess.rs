//! What a designed trajectory achieves: the condition number of its stacked base regressor
//! and its margin to every limit.

use crate::excite::{Information, JointLimits, Margin, margins};
use crate::simulate::Trajectory;
use crate::{LengthError, Model};

/// The properties of a trajectory reported with a design.
#[derive(Debug, Clone)]
pub struct Assessment {
    /// cond_2 of the stacked base regressor over the samples used (columns unscaled).
    pub condition_number: f64,
    /// Samples stacked.
    pub samples: usize,
    /// Margin to the limits, per joint (torques when reference parameters were given).
    pub margins: Vec<Margin>,
}

impl Assessment {
    /// True when every limit is respected.
    pub fn within_limits(&self) -> bool {
        self.margins.iter().all(Margin::respected)
    }
}

/// Assesses `trajectory`: the regressor is stacked over every `stride`-th sample, the
/// limits are checked on every sample; `torque` = reference base parameters.
pub fn assess<M: Model + ?Sized>(
    model: &M,
    trajectory: &Trajectory,
    limits: &[JointLimits],
    torque: Option<&[f64]>,
    stride: usize,
) -> Result<Assessment, LengthError> {
    let mut info = Information::new(model);
    info.add_trajectory(model, trajectory, stride)?;
    Ok(Assessment {
        condition_number: info.condition_number(),
        samples: info.samples,
        margins: margins(trajectory, limits, torque.map(|b| (model, b)))?,
    })
}
