//! The machine-readable identification report (the `robid identify --json` shape of
//! docs/command-line.md#robid-identify).

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::estimate::{Estimate, QualityWarning};
use crate::inspect::CutoffSuggestion;
use crate::pipeline::Identification;
use crate::report::{RunsEntry, SegmentsEntry};
use crate::validate::{Fit, Prediction, UsedRows, relative_improvement};

/// A warning in the report: machine-readable kind and parameters, and the message a
/// person reads (also what a command line prints on stderr).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ReportWarning {
    /// [`QualityWarning::kind`](crate::estimate::QualityWarning::kind): `ill_conditioned`,
    /// `uncertain`, `outlier`, `validation_repeats_estimation`, `poor_fit`, ...
    pub kind: String,
    /// The parameters concerned (empty for a warning about the whole run).
    pub parameters: Vec<String>,
    /// What it means and what to do.
    pub message: String,
}

impl ReportWarning {
    /// A warning about the data themselves, of kind `data`, concerning no parameter: what
    /// the loader says of a record (a clock resampled, a gap) and what a command finds
    /// beyond the description's limits or between its columns (a unit slip, a dead
    /// channel, a velocity column in other units).
    ///
    /// ```
    /// use robid_runtime::report::ReportWarning;
    /// let w = ReportWarning::data("joint 1's torque is 0 over the whole record".into());
    /// assert_eq!((w.kind.as_str(), w.parameters.len()), ("data", 0));
    /// ```
    pub fn data(message: String) -> Self {
        Self {
            kind: "data".to_string(),
            parameters: Vec::new(),
            message,
        }
    }
}

impl From<&QualityWarning> for ReportWarning {
    fn from(w: &QualityWarning) -> Self {
        Self {
            kind: w.kind().to_string(),
            parameters: w.parameters(),
            message: w.to_string(),
        }
    }
}

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
    /// Standard deviation robust to autocorrelated residuals (Newey-West, over
    /// [`Report::robust_lag`] samples; docs/identification.md#statistics); absent where the
    /// estimator gives none (rls, per-axis, link-by-link, energy, known parameters).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub robust_std: Option<f64>,
    /// Fixed by known standard parameters (`estimation.known`), not estimated.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub known: bool,
}

/// Fit metrics of the estimation data.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FitEntry {
    /// ||tau - tauhat|| / ||tau||.
    pub relative_error: f64,
    /// RMS per joint.
    pub rms_per_joint: Vec<f64>,
    /// NMSE per joint normalised by the mean torque magnitude ([`Fit::nmse`]).
    pub nmse: f64,
    /// Madsen et al.'s NMSE of their eq. 22, on their scale ([`Fit::nmse_eq22`]).
    #[serde(default)]
    pub nmse_eq22: f64,
    /// The torque the metrics above compare with: `"measured"`, or `"filtered"` when the
    /// processing low-passes the torque (`[processing] lowpass` on `tau`, or a
    /// decimation); null when not known.
    #[serde(default)]
    pub torque: Option<String>,
    /// With a filtered torque: the relative error against the torque as measured (before
    /// any low-pass) at the same samples.
    #[serde(default)]
    pub unfiltered_relative_error: Option<f64>,
}

/// Fit metrics of one validation file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ValidationEntry {
    /// The file (or data set name).
    pub file: String,
    /// The rows of the file used (null when not known).
    #[serde(default)]
    pub rows: Option<UsedRows>,
    /// ||tau - tauhat|| / ||tau||.
    pub relative_error: f64,
    /// RMS per joint.
    pub rms_per_joint: Vec<f64>,
    /// As [`FitEntry::nmse`].
    pub nmse: f64,
    /// As [`FitEntry::nmse_eq22`].
    #[serde(default)]
    pub nmse_eq22: f64,
    /// The same data predicted by a reference model (`robid identify --reference`), as in
    /// Madsen et al.'s Table 5; null without one.
    #[serde(default)]
    pub reference: Option<ReferenceFit>,
    /// As [`FitEntry::torque`].
    #[serde(default)]
    pub torque: Option<String>,
    /// As [`FitEntry::unfiltered_relative_error`].
    #[serde(default)]
    pub unfiltered_relative_error: Option<f64>,
    /// The file's segments when its time stamps have gaps and the config cuts it there
    /// (`gaps = "split"`); absent otherwise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub segments: Option<SegmentsEntry>,
}

fn revolute_unit() -> String {
    super::unit::REVOLUTE.to_string()
}

/// A relative error below which a model predicts its data to rounding (noise-free torques
/// predicted by the parameters that made them differ by 1e-15 to 1e-13 of their norm).
pub(crate) const PREDICTS_TO_ROUNDING: f64 = 1e-9;

/// A validation file predicted by a reference model (parameters from CAD, a data sheet or
/// an earlier identification) next to the identified one (Madsen et al. 2020, Table 5).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ReferenceFit {
    /// The reference parameter file.
    pub file: String,
    /// The reference model's relative error `||tau - tauhat|| / ||tau||` on the same
    /// samples (a figure that torques near zero do not dominate, unlike eq. 22's).
    pub relative_error: f64,
    /// The reference model's NMSE of eq. 22 on the same samples.
    pub nmse_eq22: f64,
    /// 100 (reference - identified) / reference of the eq. 22 NMSE: positive when the
    /// identified model predicts better; null when the reference predicts the data to
    /// rounding (a relative error below 1e-9: the ratio of two rounding errors, -13 %, said
    /// nothing).
    pub relative_improvement_percent: Option<f64>,
}

/// The fit of a prediction with the torque it compares with (see [`FitEntry::torque`]).
pub(crate) fn labelled_fit(prediction: &Prediction) -> FitEntry {
    let unfiltered = prediction.unfiltered_fit();
    FitEntry {
        torque: Some(
            if unfiltered.is_some() {
                "filtered"
            } else {
                "measured"
            }
            .to_string(),
        ),
        unfiltered_relative_error: unfiltered.map(|f| f.relative_error),
        ..FitEntry::from(&prediction.fit())
    }
}

/// The identification report.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Report {
    /// Robot name.
    pub robot: String,
    /// "ols", "wls", "rls", "link-by-link", "energy" or "per-axis".
    pub method: String,
    /// Equations used (rows of W).
    pub samples: usize,
    /// Condition number of W, `s_max / s_min` of the observation matrix as solved (it
    /// depends on the parameters' units; `error_bound_percent` is taken with it).
    pub condition_number: f64,
    /// Condition number of W with its columns scaled to unit norm: the same in any units
    /// of the parameters (docs/identification.md#condition-numbers); null in a report
    /// written before it was recorded.
    #[serde(default)]
    pub scaled_condition_number: Option<f64>,
    /// Milella's upper bound on the relative estimation error, `100 cond(W) ||rho|| /
    /// ||y||` percent ([`Estimate::error_bound`], docs/identification.md#error-bound).
    #[serde(default)]
    pub error_bound_percent: f64,
    /// The rows of the file used for estimation (null when not known).
    #[serde(default)]
    pub estimation: Option<UsedRows>,
    /// The lag, in (decimated) samples, of the Newey-West kernel of the parameters'
    /// `robust_std`; absent with them.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub robust_lag: Option<usize>,
    /// The parameters.
    pub parameters: Vec<ParameterEntry>,
    /// Fit on the estimation data.
    pub fit: FitEntry,
    /// Fits on validation data.
    pub validation: Vec<ValidationEntry>,
    /// The low-pass cutoff chosen for `cutoff = "auto"`, with its reason (null otherwise).
    #[serde(default)]
    pub cutoff: Option<CutoffSuggestion>,
    /// What to know before trusting the result (ill conditioning, parameters with a
    /// relative standard deviation above 100 %, an outlier, a validation that repeats the
    /// fit; docs/identification.md#quality-warnings).
    #[serde(default)]
    pub warnings: Vec<ReportWarning>,
    /// Repeated acquisitions (`[runs]`): each run alone and the run-to-run spread (null
    /// for one data set).
    #[serde(default)]
    pub runs: Option<RunsEntry>,
    /// The estimation record's segments when its time stamps have gaps and the config cuts
    /// it there (`gaps = "split"`); absent otherwise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub segments: Option<SegmentsEntry>,
    /// The windows, in s from the record's first sample, that the estimate used
    /// (`processing.pieces`, Milella's piece-wise estimation), within the estimation rows,
    /// all of which the fit covers; absent without pieces.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pieces: Option<Vec<[f64; 2]>>,
    /// The unit of the joint torques, of the RMS errors and of eq. 22's NMSE
    /// ([`torque_unit`](super::torque_unit)): "N m" for revolute joints (the default of a report without it),
    /// "N" for prismatic ones, "N m and N" for both.
    #[serde(default = "revolute_unit")]
    pub torque_unit: String,
    /// The unit of each joint's torque ([`joint_units`](super::joint_units)): "N m" or
    /// "N"; empty in a report written before it was recorded (revolute joints).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub joint_units: Vec<String>,
}

impl From<&Fit> for FitEntry {
    fn from(f: &Fit) -> Self {
        Self {
            relative_error: f.relative_error,
            rms_per_joint: f.rms_per_joint.clone(),
            nmse: f.nmse,
            nmse_eq22: f.nmse_eq22,
            torque: None,
            unfiltered_relative_error: None,
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
                robust_std: estimate.robust.as_ref().and_then(|r| r.std.get(i).copied()),
                known: estimate.known.contains(&estimate.names[i]),
            })
            .collect();
        Self {
            robot: robot.to_string(),
            method: estimate.method.name().to_string(),
            samples: estimate.rows,
            condition_number: estimate.condition_number,
            scaled_condition_number: estimate.scaled_condition_number,
            error_bound_percent: 100.0 * estimate.error_bound,
            estimation: None,
            robust_lag: estimate.robust.as_ref().map(|r| r.lag),
            parameters,
            fit: fit.into(),
            validation: Vec::new(),
            cutoff: None,
            warnings: estimate.warnings.iter().map(ReportWarning::from).collect(),
            runs: None,
            segments: None,
            pieces: None,
            torque_unit: revolute_unit(),
            joint_units: Vec::new(),
        }
    }

    /// The unit of joint `j`'s (0-based) torque: "N m" where the report does not say.
    pub fn joint_unit(&self, j: usize) -> &str {
        self.joint_units
            .get(j)
            .map_or(super::unit::REVOLUTE, String::as_str)
    }

    /// Records the unit of each joint's torque, and of them together.
    pub(crate) fn set_units(&mut self, units: &[&str]) {
        self.torque_unit = super::torque_unit(units).to_string();
        self.joint_units = units.iter().map(|u| u.to_string()).collect();
    }

    /// A report of a pipeline result.
    pub fn from_identification(
        id: &Identification,
        expressions: impl Fn(&str) -> Option<String>,
    ) -> Self {
        let mut report = Self::new(&id.robot, &id.estimate, &id.fit, expressions);
        report.estimation = Some(id.used.clone());
        report.fit = labelled_fit(&id.prediction);
        report.cutoff = id.cutoff.clone();
        report.set_units(&id.joint_units);
        report
    }

    /// Adds the fit of a validation file (rows unknown).
    pub fn with_validation(mut self, file: &str, fit: &Fit) -> Self {
        self.validation.push(ValidationEntry {
            file: file.to_string(),
            rows: None,
            relative_error: fit.relative_error,
            rms_per_joint: fit.rms_per_joint.clone(),
            nmse: fit.nmse,
            nmse_eq22: fit.nmse_eq22,
            reference: None,
            torque: None,
            unfiltered_relative_error: None,
            segments: None,
        });
        self
    }

    /// Adds a validation from its prediction ([`crate::pipeline::validate`]), with the file
    /// and rows it used; when they overlap the estimation rows of the same file, a
    /// `validation_repeats_estimation` warning is added.
    pub fn with_prediction(mut self, prediction: &Prediction) -> Self {
        let fit = labelled_fit(prediction);
        let rows = prediction.used.clone();
        let file = rows.as_ref().map_or_else(String::new, |r| r.file.clone());
        if let (Some(r), Some(e)) = (&rows, &self.estimation)
            && r.overlaps(e)
        {
            self.warnings.push(ReportWarning::from(
                &QualityWarning::ValidationRepeatsEstimation {
                    file: r.to_string(),
                },
            ));
        }
        self.validation.push(ValidationEntry {
            file,
            rows,
            relative_error: fit.relative_error,
            rms_per_joint: fit.rms_per_joint,
            nmse: fit.nmse,
            nmse_eq22: fit.nmse_eq22,
            reference: None,
            torque: fit.torque,
            unfiltered_relative_error: fit.unfiltered_relative_error,
            segments: None,
        });
        self
    }

    /// Adds to validation entry `index` the fit of the same data (the same rows: `validate`
    /// with the same config) predicted by the reference model of parameter file `file`.
    pub fn with_reference(mut self, index: usize, file: &str, fit: &Fit) -> Self {
        if let Some(v) = self.validation.get_mut(index) {
            let nmse_eq22 = fit.nmse_eq22;
            v.reference = Some(ReferenceFit {
                file: file.to_string(),
                relative_error: fit.relative_error,
                nmse_eq22,
                relative_improvement_percent: (fit.relative_error > PREDICTS_TO_ROUNDING)
                    .then(|| relative_improvement(nmse_eq22, v.nmse_eq22))
                    .flatten(),
            });
        }
        self
    }

    /// Checks that every number of the report is finite (a relative deviation may be
    /// null): a report is never written with NaN or infinity.
    pub fn check(&self) -> Result<()> {
        let bad = |what: String| {
            Err(Error::NonFiniteResult {
                what,
                cause: "the report was built from an unchecked estimate or fit".into(),
            })
        };
        if !self.condition_number.is_finite() {
            return bad("the report's condition number".into());
        }
        if self.scaled_condition_number.is_some_and(|c| !c.is_finite()) {
            return bad("the report's condition number with unit-norm columns".into());
        }
        if !self.error_bound_percent.is_finite() {
            return bad("the report's bound on the relative estimation error".into());
        }
        let segments = self.segments.iter();
        if segments
            .chain(self.validation.iter().flat_map(|v| &v.segments))
            .any(|s| !s.is_finite())
        {
            return bad("the report's segments of a record with gaps".into());
        }
        if self.runs.as_ref().is_some_and(|r| !r.is_finite()) {
            return bad("the report's figures of the repeated runs".into());
        }
        for p in &self.parameters {
            if !(p.value.is_finite() && p.std.is_finite())
                || p.rel_std_percent.is_some_and(|r| !r.is_finite())
            {
                return bad(format!("the report's entry for `{}`", p.name));
            }
        }
        let unfiltered = std::iter::once(self.fit.unfiltered_relative_error)
            .chain(self.validation.iter().map(|v| v.unfiltered_relative_error));
        if unfiltered.flatten().any(|r| !r.is_finite()) {
            return bad("the report's relative error against the unfiltered torque".into());
        }
        let fits = std::iter::once((
            &self.fit.rms_per_joint,
            self.fit.relative_error,
            [self.fit.nmse, self.fit.nmse_eq22, 0.0, 0.0, 0.0],
        ))
        .chain(self.validation.iter().map(|v| {
            let reference = v.reference.as_ref().map_or([0.0; 3], |r| {
                [
                    r.nmse_eq22,
                    r.relative_improvement_percent.unwrap_or(0.0),
                    r.relative_error,
                ]
            });
            (
                &v.rms_per_joint,
                v.relative_error,
                [
                    v.nmse,
                    v.nmse_eq22,
                    reference[0],
                    reference[1],
                    reference[2],
                ],
            )
        }));
        for (rms, rel, figures) in fits {
            if !(rel.is_finite()
                && figures.iter().all(|v| v.is_finite())
                && rms.iter().all(|v| v.is_finite()))
            {
                return bad("the report's fit metrics".into());
            }
        }
        Ok(())
    }

    /// Pretty-printed JSON.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).unwrap_or_else(|e| format!("{{\"error\": \"{e}\"}}"))
    }

    /// Writes the JSON to a file, after [`Report::check`].
    pub fn write_json(&self, path: &Path) -> Result<()> {
        self.check()?;
        crate::output::write_bytes(path, self.to_json().as_bytes())
    }
}
