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
use crate::pipeline::identify::{estimated_parameters, not_physical_warnings};
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
            "{}: every segment around its {} is too short for {what} ({})",
            segments.file.display(),
            crate::Count(segments.gaps.len(), "gap"),
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
        equations: None,
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
    let (mut estimate, mut prediction) = if streams(&config) {
        stacked_streaming(model, &sets, &config)
    } else {
        stacked_dense(model, &sets, &config)
    }
    .map_err(|e| in_segment(e, &kept, segments))?;
    let unphysical = not_physical_warnings(model, &config, &estimate)?;
    estimate.warnings.extend(unphysical);
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
            joint_units: crate::report::joint_units(&config.prismatic, model.dof()),
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

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;
    use crate::data::{Config, load, load_segments};
    use crate::pipeline::tests::synthetic::{CONFIG, DOF, Synthetic, csv_with_noise};

    /// The synthetic trajectory at 1 kHz (60 s, torque noise 0.5 N m) without the data
    /// rows `cut` (0-based `[start, end)`), written to `dir/name`.
    fn without_rows(dir: &Path, name: &str, cut: &[[usize; 2]]) -> std::path::PathBuf {
        let text = csv_with_noise(60_000, 1000.0, [0.5; DOF]);
        let mut lines = text.lines();
        let mut out = format!("{}\n", lines.next().unwrap());
        for (k, l) in lines.enumerate() {
            if !cut.iter().any(|[a, b]| (*a..*b).contains(&k)) {
                out.push_str(l);
                out.push('\n');
            }
        }
        let path = dir.join(name);
        std::fs::write(&path, out).unwrap();
        path
    }

    fn config(method: &str, gaps: &str) -> Config {
        let text = format!("{CONFIG}gaps = \"{gaps}\"\n[estimation]\nmethod = \"{method}\"\n");
        Config::from_toml_str(&text, Path::new("gaps.toml")).unwrap()
    }

    /// Largest difference between two estimates' values, relative to each value (at least
    /// its standard deviation).
    fn difference(a: &crate::estimate::Estimate, b: &crate::estimate::Estimate) -> f64 {
        assert_eq!(a.names, b.names);
        (0..a.values.len())
            .map(|i| (a.values[i] - b.values[i]).abs() / a.values[i].abs().max(a.std[i]))
            .fold(0.0, f64::max)
    }

    /// A 2 s gap in the middle: the record is cut there, each side processed on its own
    /// and their equations stacked, the same estimate to 1e-10 as the two sides given by
    /// hand as two data sets and stacked (streaming WLS and dense RLS), with the same
    /// equations; the truth lies within 3 of the stated standard deviations.
    #[test]
    fn a_gap_cuts_the_record_into_segments_stacked_as_two_data_sets() {
        let dir = tempfile::tempdir().unwrap();
        let gapped = without_rows(dir.path(), "gapped.csv", &[[30_000, 32_000]]);
        let before = without_rows(dir.path(), "before.csv", &[[30_000, 60_000]]);
        let after = without_rows(dir.path(), "after.csv", &[[0, 32_000]]);
        let model = Synthetic::default();
        for method in ["wls", "rls"] {
            let config = config(method, "split");
            let segments = load_segments(&config, std::slice::from_ref(&gapped), DOF).unwrap();
            assert_eq!(segments.gaps, vec![[29.999, 32.0]]);
            let lines: Vec<[u64; 2]> = segments.spans.iter().map(|s| s.lines).collect();
            assert_eq!(lines, vec![[2, 30_001], [30_002, 58_001]]);
            let id = identify_segments(&model, &segments, &config).unwrap();
            assert!(id.segments.dropped.is_empty());
            assert_eq!(id.segments.used.len(), 2);
            let by_hand = [
                load(&config, std::slice::from_ref(&before), DOF).unwrap(),
                load(&config, std::slice::from_ref(&after), DOF).unwrap(),
            ];
            let (stacked, prediction) = if streams(&config) {
                stacked_streaming(&model, &by_hand, &config).unwrap()
            } else {
                stacked_dense(&model, &by_hand, &config).unwrap()
            };
            let e = &id.identification.estimate;
            let d = difference(e, &stacked);
            eprintln!("{method}: segments against two data sets stacked: {d:.2e}");
            assert!(d < 1e-10, "{method}: {d}");
            assert_eq!(e.rows, stacked.rows);
            assert!(
                id.identification.prediction.measured == prediction.measured,
                "{method}: the predictions' measured torques differ"
            );
            let truth = crate::pipeline::tests::synthetic::true_parameters();
            let outside = (0..truth.len())
                .filter(|&i| (e.values[i] - truth[i]).abs() > 3.0 * e.std[i])
                .count();
            assert!(
                outside <= truth.len() / 20,
                "{method}: {outside} outside 3 std"
            );
        }
    }

    /// A third segment shorter than the processing takes is left out, said with its lines
    /// and why, and the estimate is the other two's; with every segment too short, an
    /// error names them.
    #[test]
    fn a_short_segment_is_left_out_and_said() {
        let dir = tempfile::tempdir().unwrap();
        let three = without_rows(
            dir.path(),
            "three.csv",
            &[[30_000, 32_000], [50_000, 59_700]],
        );
        let two = without_rows(dir.path(), "two.csv", &[[30_000, 32_000], [50_000, 60_000]]);
        let model = Synthetic::default();
        let config = config("wls", "split");
        let segments = load_segments(&config, &[three], DOF).unwrap();
        assert_eq!(segments.segments.len(), 3);
        let id = identify_segments(&model, &segments, &config).unwrap();
        assert_eq!(id.segments.used.len(), 2);
        let [dropped] = &id.segments.dropped[..] else {
            panic!("{:?}", id.segments.dropped)
        };
        assert_eq!(dropped.span.lines, [48_002, 48_301]);
        assert_eq!(dropped.span.samples, [48_000, 48_300]);
        assert!(dropped.needed > 300, "{dropped}");
        let warning = id.segments.dropped_warning().unwrap();
        assert!(
            warning.contains("1 of the 3 segments between its gaps left out: lines 48002 to 48301 (59.7 to 59.999 s, 300 samples): 300 samples, fewer than the"),
            "{warning}"
        );
        let reference = load_segments(&config, &[two], DOF).unwrap();
        let reference = identify_segments(&model, &reference, &config).unwrap();
        let d = difference(
            &id.identification.estimate,
            &reference.identification.estimate,
        );
        assert!(d < 1e-12, "{d}");
        let report = crate::report::Report::from_segments(&id, |_| None);
        assert!(
            report
                .warnings
                .iter()
                .any(|w| w.kind == "segments_left_out")
        );
        let json: serde_json::Value = serde_json::from_str(&report.to_json()).unwrap();
        assert_eq!(json["segments"]["dropped"][0]["lines"][0], 48_002);
        assert_eq!(json["segments"]["used"][1]["seconds"][0], 32.0);
        let text = crate::report::text_table(&report);
        assert!(
            text.contains("estimation segments of") && text.contains("left out lines 48002"),
            "{text}"
        );

        // only short segments
        let short = without_rows(dir.path(), "short.csv", &[[300, 30_000], [30_300, 60_000]]);
        let segments = load_segments(&config, &[short], DOF).unwrap();
        let e = identify_segments(&model, &segments, &config).unwrap_err();
        assert!(matches!(e, Error::TooFewSamples { .. }), "{e:?}");
        let e = e.to_string();
        assert!(
            e.contains("every segment around its 1 gap is too short for the identification")
                && e.contains("lines 2 to 301")
                && e.contains("lines 302 to 601"),
            "{e}"
        );
    }

    /// A validation record with a gap is predicted segment by segment, at the times of
    /// the record (the gap stays a gap), as the two sides predicted alone.
    #[test]
    fn a_validation_record_with_a_gap_is_predicted_by_segments() {
        let dir = tempfile::tempdir().unwrap();
        let gapped = without_rows(dir.path(), "gapped.csv", &[[30_000, 32_000]]);
        let before = without_rows(dir.path(), "before.csv", &[[30_000, 60_000]]);
        let model = Synthetic::default();
        let config = config("wls", "split");
        let values = crate::pipeline::tests::synthetic::true_parameters();
        let segments = load_segments(&config, &[gapped], DOF).unwrap();
        let (p, used) = validate_segments(&model, &segments, &config, &values).unwrap();
        assert_eq!(used.used.len(), 2);
        let alone = validate(
            &model,
            &load(&config, &[before], DOF).unwrap(),
            &config,
            &values,
        )
        .unwrap();
        let n = alone.measured[0].len();
        assert!(
            p.measured[0][..n] == alone.measured[0][..],
            "the first segment's torques differ from its own file's"
        );
        assert!(
            p.time[0][..n] == alone.time[0][..],
            "the first segment's times differ from its own file's"
        );
        // the second segment's times start after the gap
        assert!(p.time[0][n] > 32.0, "{}", p.time[0][n]);
    }
}
