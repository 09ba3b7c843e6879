//! The machine-readable identification report (the `robid identify --json` shape of
//! DESIGN 10).

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::error::Result;
use crate::estimate::Estimate;
use crate::pipeline::Identification;
use crate::validate::Fit;

/// One identified parameter.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ParameterEntry {
    /// Name (base parameter or extra column).
    pub name: String,
    /// Expression in standard parameters (empty when unknown, e.g. for extra columns).
    pub expression: String,
    /// Identified value.
    pub value: f64,
    /// Standard deviation.
    pub std: f64,
    /// Relative standard deviation in percent (null when the value is zero).
    pub rel_std_percent: Option<f64>,
}

/// Fit metrics of the estimation data.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FitEntry {
    /// ||tau - tauhat|| / ||tau||.
    pub relative_error: f64,
    /// RMS per joint.
    pub rms_per_joint: Vec<f64>,
    /// NMSE (Madsen's metric).
    pub nmse: f64,
}

/// Fit metrics of one validation file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ValidationEntry {
    /// The file (or data set name).
    pub file: String,
    /// ||tau - tauhat|| / ||tau||.
    pub relative_error: f64,
    /// RMS per joint.
    pub rms_per_joint: Vec<f64>,
    /// NMSE.
    pub nmse: f64,
}

/// The identification report.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Report {
    /// Robot name.
    pub robot: String,
    /// "ols", "wls", "rls" or "energy".
    pub method: String,
    /// Equations used (rows of W).
    pub samples: usize,
    /// Condition number of W.
    pub condition_number: f64,
    /// The parameters.
    pub parameters: Vec<ParameterEntry>,
    /// Fit on the estimation data.
    pub fit: FitEntry,
    /// Fits on validation data.
    pub validation: Vec<ValidationEntry>,
}

impl From<&Fit> for FitEntry {
    fn from(f: &Fit) -> Self {
        Self {
            relative_error: f.relative_error,
            rms_per_joint: f.rms_per_joint.clone(),
            nmse: f.nmse,
        }
    }
}

impl Report {
    /// A report from an estimate and its fit; `expressions` gives the expression of a
    /// parameter by name (return `None` when unknown).
    pub fn new(
        robot: &str,
        estimate: &Estimate,
        fit: &Fit,
        expressions: impl Fn(&str) -> Option<String>,
    ) -> Self {
        let parameters = (0..estimate.values.len())
            .map(|i| ParameterEntry {
                name: estimate.names[i].clone(),
                expression: expressions(&estimate.names[i]).unwrap_or_default(),
                value: estimate.values[i],
                std: estimate.std[i],
                rel_std_percent: Some(estimate.rel_std_percent[i]).filter(|v| v.is_finite()),
            })
            .collect();
        Self {
            robot: robot.to_string(),
            method: estimate.method.name().to_string(),
            samples: estimate.rows,
            condition_number: estimate.condition_number,
            parameters,
            fit: fit.into(),
            validation: Vec::new(),
        }
    }

    /// A report of a pipeline result.
    pub fn from_identification(
        id: &Identification,
        expressions: impl Fn(&str) -> Option<String>,
    ) -> Self {
        Self::new(&id.robot, &id.estimate, &id.fit, expressions)
    }

    /// Adds the fit of a validation file.
    pub fn with_validation(mut self, file: &str, fit: &Fit) -> Self {
        self.validation.push(ValidationEntry {
            file: file.to_string(),
            relative_error: fit.relative_error,
            rms_per_joint: fit.rms_per_joint.clone(),
            nmse: fit.nmse,
        });
        self
    }

    /// Pretty-printed JSON.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).unwrap_or_else(|e| format!("{{\"error\": \"{e}\"}}"))
    }

    /// Writes the JSON to a file.
    pub fn write_json(&self, path: &Path) -> Result<()> {
        crate::output::write_bytes(path, self.to_json().as_bytes())
    }
}
