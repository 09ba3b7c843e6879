//! The repeated-acquisition part of a report (`[runs]`): the mode, each run's figures and
//! the run-to-run spread of every parameter, for the JSON, the text table and the HTML page
//! (docs/identification.md#repeated-acquisitions).

use std::fmt::Write;

use serde::{Deserialize, Serialize};

use crate::pipeline::RepeatedIdentification;
use crate::report::Report;
use crate::report::html::escape;
use crate::validate::UsedRows;

/// One run identified alone.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunEntry {
    /// The rows of the run's file used.
    pub rows: UsedRows,
    /// Its fit's relative error.
    pub relative_error: f64,
    /// The torque that error compares with, as [`FitEntry::torque`](super::FitEntry::torque)
    /// (absent from reports written before it).
    #[serde(default)]
    pub torque: Option<String>,
    /// As [`FitEntry::unfiltered_relative_error`](super::FitEntry::unfiltered_relative_error).
    #[serde(default)]
    pub unfiltered_relative_error: Option<f64>,
    /// Its condition number.
    pub condition_number: f64,
    /// Its bound on the relative estimation error (percent).
    pub error_bound_percent: f64,
}

/// One parameter across the runs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunParameterEntry {
    /// The parameter.
    pub name: String,
    /// Mean of the runs' values.
    pub mean: f64,
    /// Sample standard deviation of the runs' values (the spread seen).
    pub std: f64,
    /// Root mean square of the standard deviations the runs report (the spread one run's
    /// statistics predict).
    pub reported_std: f64,
    /// The value of each run, in order.
    pub values: Vec<f64>,
}

/// The runs of a repeated acquisition.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunsEntry {
    /// `"stacked"` or `"averaged"`.
    pub mode: String,
    /// Each run alone, in order.
    pub runs: Vec<RunEntry>,
    /// Each parameter across the runs, in the order of the report's parameters.
    pub parameters: Vec<RunParameterEntry>,
    /// Per joint, the RMS over the samples of the sample-wise standard deviation of the
    /// measured torque across the runs (null when the runs differ in length).
    pub torque_std_per_joint: Option<Vec<f64>>,
}

impl RunsEntry {
    /// The entry of a repeated identification.
    pub fn new(r: &RepeatedIdentification) -> Self {
        let s = &r.spread;
        Self {
            mode: match r.mode {
                crate::data::RunMode::Stacked => "stacked",
                crate::data::RunMode::Averaged => "averaged",
            }
            .to_string(),
            runs: r
                .runs
                .iter()
                .map(|id| {
                    let fit = super::json::labelled_fit(&id.prediction);
                    RunEntry {
                        rows: id.used.clone(),
                        relative_error: fit.relative_error,
                        torque: fit.torque,
                        unfiltered_relative_error: fit.unfiltered_relative_error,
                        condition_number: id.estimate.condition_number,
                        error_bound_percent: 100.0 * id.estimate.error_bound,
                    }
                })
                .collect(),
            parameters: (0..s.names.len())
                .map(|i| RunParameterEntry {
                    name: s.names[i].clone(),
                    mean: s.mean[i],
                    std: s.std[i],
                    reported_std: s.reported_std[i],
                    values: s.values.iter().map(|v| v[i]).collect(),
                })
                .collect(),
            torque_std_per_joint: s.torque_std.clone(),
        }
    }

    /// Whether every number is finite.
    pub fn is_finite(&self) -> bool {
        self.runs.iter().all(|r| {
            r.relative_error.is_finite()
                && r.unfiltered_relative_error.is_none_or(f64::is_finite)
                && r.condition_number.is_finite()
                && r.error_bound_percent.is_finite()
        }) && self.parameters.iter().all(|p| {
            p.mean.is_finite()
                && p.std.is_finite()
                && p.reported_std.is_finite()
                && p.values.iter().all(|v| v.is_finite())
        }) && self
            .torque_std_per_joint
            .iter()
            .flatten()
            .all(|v| v.is_finite())
    }

    /// The text-table lines.
    pub fn text(&self) -> String {
        let mut s = String::new();
        let _ = writeln!(
            s,
            "runs: {} ({}), each identified alone:",
            self.runs.len(),
            self.mode
        );
        for (k, r) in self.runs.iter().enumerate() {
            let against = r.unfiltered_relative_error.map_or_else(String::new, |e| {
                format!(
                    " (filtered torque; {:.2} % against the measured torque)",
                    100.0 * e
                )
            });
            let _ = writeln!(
                s,
                "  run {} {}: relative error {:.2} %{against}, cond(W) {:.1}, error bound {:.1} %",
                k + 1,
                r.rows,
                100.0 * r.relative_error,
                r.condition_number,
                r.error_bound_percent
            );
        }
        let width = super::table::name_width(self.parameters.iter().map(|p| p.name.as_str()));
        let _ = writeln!(
            s,
            "{:<width$}  {:>14}  {:>12}  {:>12}",
            "parameter", "mean of runs", "run spread", "reported std"
        );
        for p in &self.parameters {
            let _ = writeln!(
                s,
                "{:<width$}  {:>14}  {:>12.3e}  {:>12.3e}",
                p.name,
                super::table::value(p.mean),
                p.std,
                p.reported_std
            );
        }
        if let Some(t) = &self.torque_std_per_joint {
            let joints: Vec<String> = t.iter().map(|v| format!("{v:.3}")).collect();
            let _ = writeln!(
                s,
                "torque spread across the runs per joint (RMS of the sample-wise std): [{}]",
                joints.join(" ")
            );
        }
        s
    }

    /// The HTML section, torques in `unit` ([`Report::torque_unit`]).
    pub fn html(&self, unit: &str) -> String {
        let mut h = String::new();
        let _ = writeln!(
            h,
            "<h2>Repeated acquisitions</h2>\n<p>{} runs, identified {} and each alone.</p>",
            self.runs.len(),
            escape(&self.mode)
        );
        h.push_str(
            "<table>\n<tr><th>run</th><th>rows</th><th>relative error</th>\
             <th>condition number</th><th>error bound</th></tr>\n",
        );
        for (k, r) in self.runs.iter().enumerate() {
            let _ = writeln!(
                h,
                "<tr><td>{}</td><td class=\"name\">{}</td><td>{:.2} %</td><td>{:.1}</td><td>{:.1} %</td></tr>",
                k + 1,
                escape(&r.rows.to_string()),
                100.0 * r.relative_error,
                r.condition_number,
                r.error_bound_percent
            );
        }
        h.push_str(
            "</table>\n<table>\n<tr><th>parameter</th><th>mean of runs</th>\
             <th>run spread (std)</th><th>reported std</th></tr>\n",
        );
        for p in &self.parameters {
            let _ = writeln!(
                h,
                "<tr><td class=\"name\">{}</td><td>{}</td><td>{:.3e}</td><td>{:.3e}</td></tr>",
                escape(&p.name),
                super::table::value(p.mean),
                p.std,
                p.reported_std
            );
        }
        h.push_str("</table>\n");
        if let Some(t) = &self.torque_std_per_joint {
            let joints: Vec<String> = t.iter().map(|v| format!("{v:.3}")).collect();
            let _ = writeln!(
                h,
                "<p>Torque spread across the runs per joint (RMS of the sample-wise standard deviation): [{}] {unit}.</p>",
                joints.join(" ")
            );
        }
        h
    }
}

impl Report {
    /// A report of repeated acquisitions: the combined estimate and fit, and the runs
    /// (`runs`); `expressions` as in [`Report::new`].
    pub fn from_runs(
        r: &RepeatedIdentification,
        expressions: impl Fn(&str) -> Option<String>,
    ) -> Self {
        let mut report = Self::new(&r.robot, &r.estimate, &r.fit, expressions);
        report.estimation = r.used.clone();
        report.fit = super::json::labelled_fit(&r.prediction);
        report.cutoff = r.cutoff.clone();
        report.runs = Some(RunsEntry::new(r));
        report.set_units(&r.joint_units);
        report
    }
}
