//! The part of a report about a record with gaps cut into segments (`[processing] gaps =
//! "split"`): the gaps, the segments used and those left out, for the JSON, the text table
//! and the HTML page (docs/identification.md#gaps-in-the-time-stamps).

use std::fmt::Write;

use serde::{Deserialize, Serialize};

use crate::data::SegmentSpan;
use crate::pipeline::{DroppedSegment, SegmentUse, SegmentedIdentification};
use crate::report::html::escape;
use crate::report::{Report, ReportWarning};

/// The segments of a record with gaps.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SegmentsEntry {
    /// The file.
    pub file: String,
    /// Each gap: the time stamps before and after it (s).
    pub gaps: Vec<[f64; 2]>,
    /// The segments whose equations were used: samples of the record `[start, end)`, file
    /// lines of the first and last sample, their time stamps (s).
    pub used: Vec<SegmentSpan>,
    /// The segments left out, with the samples needed and why.
    pub dropped: Vec<DroppedSegment>,
}

impl From<&SegmentUse> for SegmentsEntry {
    fn from(u: &SegmentUse) -> Self {
        Self {
            file: u.file.clone(),
            gaps: u.gaps.clone(),
            used: u.used.clone(),
            dropped: u.dropped.clone(),
        }
    }
}

impl SegmentsEntry {
    /// Whether every number is finite.
    pub fn is_finite(&self) -> bool {
        let spans = self.used.iter().chain(self.dropped.iter().map(|d| &d.span));
        self.gaps.iter().flatten().all(|v| v.is_finite())
            && spans.flat_map(|s| s.seconds).all(f64::is_finite)
    }

    /// The text-table lines, for the data `what` ("estimation", "validation").
    pub fn text(&self, what: &str) -> String {
        let mut s = String::new();
        let _ = writeln!(
            s,
            "{what} segments of {} ({}): {} used, {} left out",
            self.file,
            crate::Count(self.gaps.len(), "gap"),
            self.used.len(),
            self.dropped.len()
        );
        for u in &self.used {
            let _ = writeln!(s, "  used {u}");
        }
        for d in &self.dropped {
            let _ = writeln!(s, "  left out {d}");
        }
        s
    }

    /// The HTML section, for the data `what`.
    pub fn html(&self, what: &str) -> String {
        let mut h = String::new();
        let _ = writeln!(
            h,
            "<p>{} segments of {} between its {} gaps in the time stamps: {} used, {} left out.</p>\n<ul>",
            escape(what),
            escape(&self.file),
            self.gaps.len(),
            self.used.len(),
            self.dropped.len()
        );
        for u in &self.used {
            let _ = writeln!(h, "<li>used {}</li>", escape(&u.to_string()));
        }
        for d in &self.dropped {
            let _ = writeln!(h, "<li>left out {}</li>", escape(&d.to_string()));
        }
        h.push_str("</ul>\n");
        h
    }
}

/// The report warning about segments left out, if any.
fn dropped_warning(u: &SegmentUse) -> Option<ReportWarning> {
    u.dropped_warning().map(|message| ReportWarning {
        kind: "segments_left_out".into(),
        parameters: Vec::new(),
        message,
    })
}

impl Report {
    /// A report of an identification from the segments of a record with gaps; `expressions`
    /// as in [`Report::new`].
    pub fn from_segments(
        s: &SegmentedIdentification,
        expressions: impl Fn(&str) -> Option<String>,
    ) -> Self {
        let mut report = Self::from_identification(&s.identification, expressions);
        report.segments = Some(SegmentsEntry::from(&s.segments));
        report.warnings.extend(dropped_warning(&s.segments));
        report
    }

    /// Gives the last validation entry the segments of its record with gaps.
    pub fn with_validation_segments(mut self, u: &SegmentUse) -> Self {
        if let Some(v) = self.validation.last_mut() {
            v.segments = Some(SegmentsEntry::from(u));
        }
        self.warnings.extend(dropped_warning(u));
        self
    }
}
