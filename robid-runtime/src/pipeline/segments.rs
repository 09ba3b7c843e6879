//! Identification and validation from the continuous segments of a record whose time
//! stamps have gaps (`[processing] gaps = "split"`, [`crate::data::load_segments`];
//! docs/identification.md#gaps-in-the-time-stamps).
//!
//! Each segment is processed on its own, as each run of stacked `[runs]` is (filters,
//! derivatives, decimation, the equations near rest, trims: never across a gap), and the
//! equations of every segment are stacked into one estimate, through the stacked runs' own
//! code (`runs::stacked_dense`, `stream::stacked_streaming`). Unlike runs, no segment is
//! identified alone: a short piece between two gaps adds its equations without having to
//! determine every parameter by itself. A segment shorter than the processing needs
//! ([`samples_needed`]) is left out, and said so.

use std::borrow::Cow;

use serde::{Deserialize, Serialize};

use crate::Model;
use crate::data::{Config, Dataset, Loaded, Method, SegmentSpan, Segments};
use crate::error::{Error, Result};
use crate::inspect::resolve_cutoff;
use crate::pipeline::identify::estimated_parameters;
use crate::pipeline::prepare::samples_needed;
use crate::pipeline::runs::stacked_dense;
use crate::pipeline::stream::{stacked_streaming, streams};
use crate::pipeline::{Identification, identify, validate};
use crate::validate::{Prediction, UsedRows};

/// A segment left out.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DroppedSegment {
    /// Where it is in the file.
    #[serde(flatten)]
    pub span: SegmentSpan,
    /// The samples the processing needs.
    pub needed: usize,
    /// Why it was left out.
    pub why: String,
}

impl std::fmt::Display for DroppedSegment {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}", self.span, self.why)
    }
}

/// Which segments of a record with gaps were used.
#[derive(Debug, Clone, PartialEq)]
pub struct SegmentUse {
    /// The file.
    pub file: String,
    /// The gaps: the time stamps before and after each (s).
    pub gaps: Vec<[f64; 2]>,
    /// The segments whose equations were used, in order.
    pub used: Vec<SegmentSpan>,
    /// The segments left out, in order.
    pub dropped: Vec<DroppedSegment>,
}

impl SegmentUse {
    /// The warning about the segments left out, `None` when none was.
    pub fn dropped_warning(&self) -> Option<String> {
        if self.dropped.is_empty() {
            return None;
        }
        let list: Vec<String> = self.dropped.iter().map(|d| d.to_string()).collect();
        Some(format!(
            "{}: {} of the {} segments between its gaps left out: {}",
            self.file,
            self.dropped.len(),
            self.dropped.len() + self.used.len(),
            list.join("; ")
        ))
    }
}

/// The result of [`identify_segments`].
#[derive(Debug, Clone)]
pub struct SegmentedIdentification {
    /// The estimate, its fit and prediction (the segments end to end, as stacked runs),
    /// the loading warnings, the rows from the first used segment's first to the last
    /// one's last, the cutoff chosen for `cutoff = "auto"` (on the longest segment).
    pub identification: Identification,
    /// The segments used and left out.
    pub segments: SegmentUse,
}

/// The segments of `segments` long enough for `config`'s processing of equations for
/// `parameters` parameters, and those left out with why.
fn select<'a>(
    segments: &'a Segments,
    config: &Config,
    parameters: usize,
) -> (Vec<(&'a Dataset, &'a SegmentSpan)>, Vec<DroppedSegment>) {
    let mut kept = Vec::new();
    let mut dropped: Vec<DroppedSegment> = segments
        .single
        .iter()
        .map(|span| DroppedSegment {
            span: span.clone(),
            needed: 2,
            why: "a single sample between gaps".into(),
        })
        .collect();
    for (d, span) in segments.segments.iter().zip(&segments.spans) {
        match samples_needed(d, config, parameters) {
            Some(need) if d.samples() < need.samples => dropped.push(DroppedSegment {
                span: span.clone(),
                needed: need.samples,
                why: format!(
                    "{} samples, fewer than the {} the processing takes ({})",
                    d.samples(),
                    need.samples,
                    need.why
                ),
            }),
            _ => kept.push((d, span)),
        }
    }
    dropped.sort_by_key(|d| d.span.samples[0]);
    (kept, dropped)
}

/// Refuses what does not apply to a record cut into segments: `key`, a range of samples of
/// one continuous record.
fn refuse_range(config: &Config, key: &str, given: bool) -> Result<()> {
    if given {
        return Err(config.key_error(
            key,
            "a sample range of one continuous record, which a record with gaps cut into \
             segments (gaps = \"split\") is not: remove it, or cut the file to the rows wanted",
        ));
    }
    Ok(())
}

/// The error when no segment is long enough.
fn none_left(segments: &Segments, dropped: &[DroppedSegment], what: &'static str) -> Error {
    let list: Vec<String> = dropped.iter().map(|d| d.to_string()).collect();
    Error::TooFewSamples {
        context: format!(
            "{}: every segment between its {} gaps is too short for {what} ({})",
            segments.file.display(),
            segments.gaps.len(),
            list.join("; ")
        ),
        found: dropped
            .iter()
            .map(|d| d.span.samples[1] - d.span.samples[0])
            .max()
            .unwrap_or(0),
        required: dropped.iter().map(|d| d.needed).min().unwrap_or(2),
        hint: "record longer continuous stretches, or shorten the processing (trims, \
               the low-pass's settling, the decimation)",
    }
}

/// An error of segment `d` (of the stacked ones) said as the segment's, not a run's.
fn in_segment(e: Error, kept: &[(&Dataset, &SegmentSpan)], segments: &Segments) -> Error {
    match e {
        Error::Run { run, error } => match kept.iter().find(|(d, _)| run.contains(&d.name)) {
            Some((_, span)) => Error::Run {
                run: format!("{}, segment {span}", segments.file.display()),
                error,
            },
            None => Error::Run { run, error },
        },
        e => e,
    }
}

/// The rows from the first of `spans` to the last of them, in `file`.
fn spanning(file: &str, spans: &[&SegmentSpan]) -> UsedRows {
    let (first, last) = (spans[0], spans[spans.len() - 1]);
    UsedRows {
        file: file.to_string(),
        samples: [first.samples[0], last.samples[1]],
        lines: Some([first.lines[0], last.lines[1]]),
    }
}

/// Identifies from the segments of a record with gaps: every segment processed on its own
/// with `config`, the equations of all stacked into one estimate (OLS and WLS streaming,
/// as stacked runs). `cutoff = "auto"` is chosen once, on the longest segment. A segment
/// too short for the processing is left out (see [`SegmentUse::dropped`]); none left is
/// an error naming each segment and why. With a single segment left, it is identified as
/// one record ([`identify`]).
pub fn identify_segments(
    model: &(dyn Model + Sync),
    segments: &Segments,
    config: &Config,
) -> Result<SegmentedIdentification> {
    config.check(model.dof()).map_err(|e| config.locate(e))?;
    let p = &config.processing;
    refuse_range(config, "processing.range", p.range.is_some())?;
    refuse_range(config, "processing.pieces", p.pieces.is_some())?;
    let mut config = config.clone();
    // the segments are not runs: an error of one names the segment, not `runs.files`
    config.runs = None;
    let cutoff = match segments.longest() {
        Some(d) => resolve_cutoff(&mut config, d).map_err(|e| config.locate(e))?,
        None => None,
    };
    let parameters = estimated_parameters(model, &config).unwrap_or(0);
    let (kept, dropped) = select(segments, &config, parameters);
    if kept.is_empty() {
        return Err(none_left(segments, &dropped, "the identification"));
    }
    let file = segments.file.display().to_string();
    let spans: Vec<&SegmentSpan> = kept.iter().map(|k| k.1).collect();
    let used = SegmentUse {
        file: file.clone(),
        gaps: segments.gaps.clone(),
        used: spans.iter().map(|s| (*s).clone()).collect(),
        dropped,
    };
    let mut warnings = segments.warnings.clone();
    if let [(d, _)] = kept[..] {
        let mut id = identify(model, d, &config)?;
        warnings.extend(id.warnings.iter().cloned());
        id.warnings = warnings;
        id.cutoff = cutoff.or(id.cutoff);
        return Ok(SegmentedIdentification {
            identification: id,
            segments: used,
        });
    }
    if config.estimation.method == Method::Energy {
        return Err(config.key_error(
            "estimation.method",
            "the energy model integrates the power over windows of one continuous record: \
             with a record cut at its gaps into segments (gaps = \"split\"), use ols, wls, \
             rls, per-axis or link-by-link",
        ));
    }
    let sets: Cow<'_, [Dataset]> = if kept.len() == segments.segments.len() {
        Cow::Borrowed(&segments.segments)
    } else {
        Cow::Owned(kept.iter().map(|(d, _)| (*d).clone()).collect())
    };
    let (estimate, mut prediction) = if streams(&config) {
        stacked_streaming(model, &sets, &config)
    } else {
        stacked_dense(model, &sets, &config)
    }
    .map_err(|e| in_segment(e, &kept, segments))?;
    for d in sets.iter() {
        warnings.extend(d.warnings.iter().cloned());
    }
    let rows = spanning(&file, &spans);
    prediction.used = Some(rows.clone());
    Ok(SegmentedIdentification {
        identification: Identification {
            robot: model.name().to_string(),
            fit: prediction.fit(),
            prediction,
            estimate,
            warnings,
            used: rows,
            cutoff,
        },
        segments: used,
    })
}

/// Predicts the torques of the segments of a record with gaps with identified `values`, as
/// [`validate`] predicts one record: each segment processed on its own
/// (`processing.validation_range` does not apply), the predictions one after the other at
/// their times from the record's first sample (the gaps stay gaps). A segment too short
/// for the processing is left out.
pub fn validate_segments(
    model: &(dyn Model + Sync),
    segments: &Segments,
    config: &Config,
    values: &[f64],
) -> Result<(Prediction, SegmentUse)> {
    config.check(model.dof()).map_err(|e| config.locate(e))?;
    refuse_range(
        config,
        "processing.validation_range",
        config.processing.validation_range.is_some(),
    )?;
    let (kept, dropped) = select(segments, config, 0);
    if kept.is_empty() {
        return Err(none_left(segments, &dropped, "the validation"));
    }
    let dof = model.dof();
    let origin = segments.spans.first().map_or(0.0, |s| s.seconds[0]).min(
        segments
            .single
            .first()
            .map_or(f64::INFINITY, |s| s.seconds[0]),
    );
    let mut all = Prediction {
        measured: vec![Vec::new(); dof],
        predicted: vec![Vec::new(); dof],
        time: vec![Vec::new(); dof],
        unfiltered: Some(vec![Vec::new(); dof]),
        used: None,
    };
    for (d, span) in &kept {
        let p = validate(model, *d, config, values).map_err(|e| Error::Run {
            run: format!("{}, segment {span}", segments.file.display()),
            error: Box::new(e),
        })?;
        let p = p.starting_at(span.seconds[0] - origin);
        for j in 0..dof {
            all.measured[j].extend(&p.measured[j]);
            all.predicted[j].extend(&p.predicted[j]);
            all.time[j].extend(&p.time[j]);
        }
        match (&mut all.unfiltered, &p.unfiltered) {
            (Some(a), Some(u)) => a.iter_mut().zip(u).for_each(|(a, u)| a.extend(u)),
            (a, _) => *a = None,
        }
    }
    let file = segments.file.display().to_string();
    let spans: Vec<&SegmentSpan> = kept.iter().map(|k| k.1).collect();
    let rows = spanning(&file, &spans);
    all.check(&format!("the validation data ({rows})"))?;
    all.used = Some(rows);
    let used = SegmentUse {
        file,
        gaps: segments.gaps.clone(),
        used: spans.iter().map(|s| (*s).clone()).collect(),
        dropped,
    };
    Ok((all, used))
}

/// [`validate`] of a record, or [`validate_segments`] of a record cut at its gaps, with the
/// segments used.
pub fn validate_loaded(
    model: &(dyn Model + Sync),
    data: &Loaded,
    config: &Config,
    values: &[f64],
) -> Result<(Prediction, Option<SegmentUse>)> {
    match data {
        Loaded::Record(r) => Ok((validate(model, r.as_ref(), config, values)?, None)),
        Loaded::Segments(s) => {
            validate_segments(model, s, config, values).map(|(p, u)| (p, Some(u)))
        }
    }
}
