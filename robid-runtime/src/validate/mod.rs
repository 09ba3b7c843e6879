//! Validation on data not used for estimation (DESIGN 6.5): relative error, RMS per
//! joint, NMSE, improvement against a reference model; and per-joint predictions.

mod metrics;

pub use metrics::{Fit, fit, relative_improvement};

use crate::estimate::Observation;

/// Measured and predicted (filtered, decimated) torques per joint.
#[derive(Debug, Clone)]
pub struct Prediction {
    /// Measured torque per joint.
    pub measured: Vec<Vec<f64>>,
    /// Predicted torque per joint.
    pub predicted: Vec<Vec<f64>>,
    /// Time (s) of each entry per joint (samples near rest are absent).
    pub time: Vec<Vec<f64>>,
}

impl Prediction {
    /// Prediction W beta of an observation; `sample_time` is the decimated sample time.
    pub fn new(obs: &Observation, beta: &[f64], sample_time: f64) -> Self {
        let b = nalgebra::DVector::from_column_slice(beta);
        let pred = &obs.w * b;
        let block = |v: &nalgebra::DVector<f64>| -> Vec<Vec<f64>> {
            obs.joint_rows
                .iter()
                .map(|r| v.rows(r.start, r.len()).iter().copied().collect())
                .collect()
        };
        let time = obs
            .joint_rows
            .iter()
            .map(|r| {
                obs.sample_of_row[r.clone()]
                    .iter()
                    .map(|&k| k as f64 * sample_time)
                    .collect()
            })
            .collect();
        Self {
            measured: block(&obs.y),
            predicted: block(&pred),
            time,
        }
    }

    /// The metrics of this prediction.
    pub fn fit(&self) -> Fit {
        fit(&self.measured, &self.predicted)
    }
}
