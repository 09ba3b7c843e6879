//! A record whose time stamps have gaps (steps of more than [`GAP_RATIO`](crate::data::GAP_RATIO) median steps: a
//! paused logger, a lost connection) cut at every gap into continuous segments, with
//! `[processing] gaps = "split"` (docs/identification.md#gaps-in-the-time-stamps). Each
//! segment is a data set of its own, resampled onto its own uniform grid when its stamps
//! are irregular; nothing is interpolated across a gap. The pipeline processes each on its
//! own and stacks their equations (`pipeline::identify_segments`).

use std::path::PathBuf;

use serde::{Deserialize, Serialize};

use crate::data::load::{ReadSources, finish, read_sources};
use crate::data::time::find_gaps;
use crate::data::{Config, Dataset, Extremes, Gaps, Record, SpilledRecord, Warning, load_record};
use crate::error::Result;

/// Where a segment is in its file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SegmentSpan {
    /// The samples of the record, `[start, end)`, 0-based (after joining files).
    pub samples: [usize; 2],
    /// The 1-based file lines of its first and its last sample.
    pub lines: [u64; 2],
    /// The time stamps of its first and its last sample (s, as in the file after
    /// `time_scale`).
    pub seconds: [f64; 2],
}

impl std::fmt::Display for SegmentSpan {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "lines {} to {} ({} to {} s, {} samples)",
            self.lines[0],
            self.lines[1],
            crate::Num::rounded(self.seconds[0], 6),
            crate::Num::rounded(self.seconds[1], 6),
            self.samples[1] - self.samples[0]
        )
    }
}

/// A record cut at its gaps ([`load_segments`]).
#[derive(Debug, Clone)]
pub struct Segments {
    /// The first file.
    pub file: PathBuf,
    /// The segments of at least 2 samples, in order, each a data set (its lines are the
    /// file's).
    pub segments: Vec<Dataset>,
    /// Where each segment of `segments` is in the file.
    pub spans: Vec<SegmentSpan>,
    /// The segments of a single sample between two gaps (or a gap and an end): no data
    /// set, no step to take a sample time from.
    pub single: Vec<SegmentSpan>,
    /// The gaps: the time stamps before and after each (s).
    pub gaps: Vec<[f64; 2]>,
    /// What was repaired while loading the files (each segment's own warnings, such as its
    /// resampling, are in its data set).
    pub warnings: Vec<Warning>,
}

impl Segments {
    /// Every warning: the files', then each segment's.
    pub fn all_warnings(&self) -> Vec<Warning> {
        let mut all = self.warnings.clone();
        for s in &self.segments {
            all.extend(s.warnings.iter().cloned());
        }
        all
    }

    /// The longest segment (the first of the longest), `None` without one.
    pub fn longest(&self) -> Option<&Dataset> {
        self.segments.iter().rev().max_by_key(|s| s.samples())
    }
}

/// Loads the data of `config` as [`crate::data::load`] does, but for time stamps with gaps:
/// the first file joined by time (or the only one) is cut at every gap ([`GAP_RATIO`](crate::data::GAP_RATIO)) into
/// segments, each checked, resampled when irregular and converted on its own. A gap in
/// another file joined by time is refused. Without a gap: one segment, the data set `load`
/// gives.
pub fn load_segments(config: &Config, files: &[PathBuf], dof: usize) -> Result<Segments> {
    load_segments_checked(config, files, dof).map_err(|e| config.locate(e))
}

fn load_segments_checked(config: &Config, files: &[PathBuf], dof: usize) -> Result<Segments> {
    let (config, read) = read_sources(config, files, dof, Gaps::Split)?;
    let file = read
        .reference
        .as_ref()
        .map(|r| r.1.clone())
        .or_else(|| read.rows.as_ref().map(|r| r.1.clone()))
        .unwrap_or_default();
    let cuts = read
        .reference
        .as_ref()
        .map_or_else(Vec::new, |(t, _, _)| find_gaps(t));
    if cuts.is_empty() {
        let stamps = read
            .reference
            .as_ref()
            .map(|(t, _, _)| [t[0], t[t.len() - 1]]);
        let data = finish(&config, dof, read)?;
        let span = whole_span(&data, stamps);
        return Ok(Segments {
            file,
            segments: vec![data],
            spans: vec![span],
            single: Vec::new(),
            gaps: Vec::new(),
            warnings: Vec::new(),
        });
    }
    let ReadSources {
        blocks,
        reference,
        rows,
        warnings,
        samplings,
        name,
        ..
    } = read;
    let Some((t, path, lines)) = reference else {
        unreachable!("cuts come from the time stamps")
    };
    let n = t.len();
    let bounds: Vec<usize> = std::iter::once(0)
        .chain(cuts.iter().copied())
        .chain(std::iter::once(n))
        .collect();
    let gaps = cuts.iter().map(|&k| [t[k - 1], t[k]]).collect();
    let (mut segments, mut spans) = (Vec::new(), Vec::new());
    let mut single = Vec::new();
    for (i, w) in bounds.windows(2).enumerate() {
        let r = w[0]..w[1];
        let span = SegmentSpan {
            samples: [r.start, r.end],
            lines: [lines[r.start], lines[r.end - 1]],
            seconds: [t[r.start], t[r.end - 1]],
        };
        if r.len() < 2 {
            single.push(span);
            continue;
        }
        let slice = |x: &Vec<f64>| {
            if x.len() == n {
                x[r.clone()].to_vec()
            } else {
                x.clone()
            }
        };
        let part = ReadSources {
            blocks: std::array::from_fn(|b| {
                blocks[b]
                    .as_ref()
                    .map(|cols| cols.iter().map(slice).collect())
            }),
            reference: Some((
                t[r.clone()].to_vec(),
                path.clone(),
                lines[r.clone()].to_vec(),
            )),
            rows: rows.clone(),
            time_names: None,
            warnings: Vec::new(),
            samplings: samplings.clone(),
            name: format!(
                "{name} segment {} (lines {} to {})",
                i + 1,
                span.lines[0],
                span.lines[1]
            ),
        };
        let data = finish(&config, dof, part)?;
        segments.push(data);
        spans.push(span);
    }
    Ok(Segments {
        file,
        segments,
        spans,
        single,
        gaps,
        warnings,
    })
}

/// The span of the whole of `data`, whose first and last time stamps are `stamps` when
/// it has them (else its grid from 0).
fn whole_span(data: &Dataset, stamps: Option<[f64; 2]>) -> SegmentSpan {
    let n = data.samples();
    let last = n.saturating_sub(1);
    let line = |k: usize| data.line(k).unwrap_or(k as u64 + 1);
    SegmentSpan {
        samples: [0, n],
        lines: [line(0), line(last)],
        seconds: stamps.unwrap_or([0.0, last as f64 * data.sample_time]),
    }
}

/// What [`load_or_split`] gives.
#[allow(missing_debug_implementations)]
pub enum Loaded {
    /// One continuous record (kept on disk when it can be, [`load_record`]).
    Record(Box<dyn Record>),
    /// A record with gaps, cut into segments (`gaps = "split"`).
    Segments(Segments),
}

impl Loaded {
    /// What was repaired while loading (for segments: the files', then each segment's).
    pub fn warnings(&self) -> Vec<Warning> {
        match self {
            Loaded::Record(r) => r.warnings().to_vec(),
            Loaded::Segments(s) => s.all_warnings(),
        }
    }

    /// Per joint the extremes of the positions and torques the loader kept
    /// ([`Record::extremes`]): the record's, or over every segment (a segment of a single
    /// sample, no data set, is not counted).
    pub fn extremes(&self) -> Extremes {
        match self {
            Loaded::Record(r) => r.extremes().clone(),
            Loaded::Segments(s) => {
                let mut all = Extremes::default();
                for d in &s.segments {
                    all.join(&d.extremes);
                }
                all
            }
        }
    }

    /// The record, or the longest segment: the data to choose `cutoff = "auto"` from.
    pub fn longest(&self) -> Option<&dyn Record> {
        match self {
            Loaded::Record(r) => Some(r.as_ref()),
            Loaded::Segments(s) => s.longest().map(|d| d as &dyn Record),
        }
    }
}

/// Loads as [`load_record`] does, and with `[processing] gaps = "split"` a record whose
/// time stamps have gaps as segments ([`load_segments`]; a record without a gap is still
/// one record, kept on disk when it can be).
pub fn load_or_split(config: &Config, files: &[PathBuf], dof: usize) -> Result<Loaded> {
    if config.processing.gaps == Gaps::Refuse {
        return load_record(config, files, dof).map(Loaded::Record);
    }
    // a file with a gap is not kept on disk (its clock is irregular): `open` gives none
    if let Ok(Some(r)) = SpilledRecord::open(config, files, dof) {
        return Ok(Loaded::Record(Box::new(r)));
    }
    let mut s = load_segments(config, files, dof)?;
    if s.gaps.is_empty() {
        let data = s.segments.remove(0);
        return Ok(Loaded::Record(Box::new(data)));
    }
    Ok(Loaded::Segments(s))
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;
    use crate::DataError;
    use crate::data::load;
    use crate::error::Error;

    const SPLIT: &str = "time_column = \"t\"\n[[source]]\nposition = \"q{}\"\ntorque = \"tau{}\"\n[processing]\ngaps = \"split\"\n";

    fn cfg(text: &str) -> Config {
        Config::from_toml_str(text, Path::new("c.toml")).unwrap()
    }

    /// A 1 kHz log `t,q1,tau1` of the times `t` (ms, jittered by `jitter` of a step at
    /// every row).
    fn log(times: impl Iterator<Item = usize>, jitter: f64) -> String {
        let mut csv = String::from("t,q1,tau1\n");
        for k in times {
            let wobble = jitter * ((k * 7919) % 13) as f64 / 12.0;
            let t = (k as f64 + wobble) * 1e-3;
            csv.push_str(&format!("{t},{},{}\n", (3.0 * t).sin(), 2.0 * t));
        }
        csv
    }

    /// Gaps cut the record: each segment a data set of its own with its file lines, a
    /// clock jittered by 3 % resampled onto each segment's own grid (from its first stamp,
    /// its own mean step: nothing interpolated across a gap), a lone sample between two
    /// gaps set apart; the default refuses the same file naming the setting, and a file
    /// without a gap is the data set `load` gives.
    #[test]
    fn gaps_cut_the_record_into_segments_each_resampled_on_its_own() {
        let dir = tempfile::tempdir().unwrap();
        let times = (0..1000).chain(3000..3001).chain(5000..5600);
        let file = dir.path().join("paused.csv");
        std::fs::write(&file, log(times, 0.03)).unwrap();
        let s = load_segments(&cfg(SPLIT), std::slice::from_ref(&file), 1).unwrap();
        assert_eq!(s.gaps.len(), 2);
        assert_eq!(s.segments.len(), 2);
        let lines: Vec<[u64; 2]> = s.spans.iter().map(|s| s.lines).collect();
        assert_eq!(lines, vec![[2, 1001], [1003, 1602]]);
        let [single] = &s.single[..] else {
            panic!("{:?}", s.single)
        };
        assert_eq!((single.lines, single.samples), ([1002, 1002], [1000, 1001]));
        for (d, span) in s.segments.iter().zip(&s.spans) {
            let n = span.samples[1] - span.samples[0];
            assert_eq!(d.samples(), n);
            let step = (span.seconds[1] - span.seconds[0]) / (n - 1) as f64;
            assert!((d.sample_time - step).abs() < 1e-15, "{}", d.sample_time);
            assert!(matches!(d.warnings[..], [Warning::IrregularTime { .. }]));
            // tau = 2 t: on the segment's grid from its first stamp, not across the gap
            for k in [0, n / 2, n - 1] {
                let t = span.seconds[0] + k as f64 * d.sample_time;
                assert!((d.tau[0][k] - 2.0 * t).abs() < 1e-12, "{k}");
            }
        }
        assert_eq!(s.all_warnings().len(), 2);
        // the default refuses it, naming the setting
        let refuse = SPLIT.replace("gaps = \"split\"", "");
        let e = load(&cfg(&refuse), std::slice::from_ref(&file), 1).unwrap_err();
        assert!(matches!(e, Error::Data(DataError::TimeGap { .. })), "{e}");
        assert!(e.to_string().contains("set `gaps = \"split\"`"), "{e}");
        // `load` (one continuous record) with the setting says where it applies
        let e = load(&cfg(SPLIT), std::slice::from_ref(&file), 1)
            .unwrap_err()
            .to_string();
        assert!(e.contains("applies to the data of `robid identify`"), "{e}");
        // without a gap: one segment, `load`'s data set
        let plain = dir.path().join("plain.csv");
        std::fs::write(&plain, log(0..500, 0.03)).unwrap();
        let s = load_segments(&cfg(SPLIT), std::slice::from_ref(&plain), 1).unwrap();
        let whole = load(&cfg(SPLIT), std::slice::from_ref(&plain), 1).unwrap();
        assert!(s.gaps.is_empty() && s.single.is_empty());
        assert_eq!(s.segments[0].tau, whole.tau);
        assert_eq!(s.spans[0].lines, [2, 501]);
        assert_eq!(s.spans[0].seconds[0], 0.0);
        assert!(matches!(
            load_or_split(&cfg(SPLIT), &[plain], 1).unwrap(),
            Loaded::Record(_)
        ));
        assert!(matches!(
            load_or_split(&cfg(SPLIT), &[file], 1).unwrap(),
            Loaded::Segments(_)
        ));
    }

    /// A gap in a file joined by time to the first is refused, naming what the setting
    /// cuts; gaps in the first file are cut with the other file interpolated in each
    /// segment.
    #[test]
    fn a_gap_in_a_file_joined_by_time_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let write = |name: &str, times: Vec<usize>, column: &str| {
            let mut csv = format!("t,{column}\n");
            for k in times {
                let t = k as f64 * 1e-3;
                csv.push_str(&format!("{t},{}\n", 2.0 * t));
            }
            let path = dir.path().join(name);
            std::fs::write(&path, csv).unwrap();
            path
        };
        let text = "time_column = \"t\"\n[[source]]\nposition = \"q{}\"\n[[source]]\ntorque = \"tau{}\"\n[processing]\ngaps = \"split\"\n";
        let whole: Vec<usize> = (0..2000).collect();
        let paused: Vec<usize> = (0..800).chain(1200..2000).collect();
        let q = write("q.csv", paused.clone(), "q1");
        let tau = write("tau.csv", whole, "tau1");
        let s = load_segments(&cfg(text), &[q.clone(), tau.clone()], 1).unwrap();
        assert_eq!(s.segments.len(), 2);
        assert!((s.segments[1].tau[0][0] - 2.4).abs() < 1e-12);
        let tau_paused = write("tau2.csv", paused, "tau1");
        let q_whole = write("q2.csv", (0..2000).collect(), "q1");
        let e = load_segments(&cfg(text), &[q_whole, tau_paused], 1)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("cuts the first file joined by time at its gaps"),
            "{e}"
        );
    }
}
