//! From config + files to a joint-side, uniformly sampled [`Dataset`].
//!
//! Every value read is checked at load time: finite ([`crate::DataError::NotFinite`]) and within the
//! range of its quantity ([`crate::limits`], [`crate::DataError::OutOfRange`] naming file:line and
//! column), both as read and after the units and the drive chain. Errors about the config
//! name its keys at their file:line ([`Config::locate`]).

use crate::DataError;
use crate::data::GAP_RATIO;
use std::borrow::Cow;
use std::path::{Path, PathBuf};

use crate::Num;
use crate::data::dataset::{DataOrigin, Extremes, Values};
use crate::data::rate::{
    Steps, UnreadTime, check_rate, differing_time_columns, unread_time_column,
    with_found_time_column,
};
use crate::data::table::{Optional, read_columns_in};
use crate::data::time::{
    check_gaps, check_monotonic, check_sample_time, interpolate, nearest_lines, regularity,
};
use crate::data::unwrap::Unwrap;
use crate::data::{
    AngleUnit, Config, Dataset, Gaps, STALE_SHARE, Sampling, Source, Table, Warning, read_header,
};
use crate::drive::DriveChain;
use crate::error::{Error, Result};
use crate::limits::{MAX_JOINTS, Quantity, check_size};
use crate::signal::Signals;

/// The roles a column block can have, in the order of [`assemble`]'s blocks.
pub(crate) const ROLES: [&str; 7] = [
    "position",
    "velocity",
    "acceleration",
    "torque",
    "motor_position",
    "temperature",
    "joint_torque",
];

/// The quantity of each role.
const QUANTITIES: [Quantity; 7] = [
    Quantity::Position,
    Quantity::Velocity,
    Quantity::Acceleration,
    Quantity::Torque,
    Quantity::Position,
    Quantity::Temperature,
    Quantity::Torque,
];

fn role_columns(s: &Source, role: usize) -> Option<&crate::data::Columns> {
    [
        &s.position,
        &s.velocity,
        &s.acceleration,
        &s.torque,
        &s.motor_position,
        &s.temperature,
        &s.joint_torque,
    ][role]
        .as_ref()
}

/// Loads a data set for a `dof`-joint model. `files` pair with the config's
/// `[[source]]` tables in order; when empty, the sources' own `file` entries are used.
pub fn load(config: &Config, files: &[PathBuf], dof: usize) -> Result<Dataset> {
    load_checked(config, files, dof).map_err(|e| config.locate(e))
}

/// Checks the model's joint count against [`MAX_JOINTS`].
pub(crate) fn check_joints(dof: usize) -> Result<()> {
    check_size(
        || "joints of the model".into(),
        dof as f64,
        MAX_JOINTS,
        "use a description with fewer joints",
    )
}

fn load_checked(config: &Config, files: &[PathBuf], dof: usize) -> Result<Dataset> {
    let (config, read) = read_sources(config, files, dof, Gaps::Refuse)?;
    finish(&config, dof, read)
}

/// The columns of every `[[source]]` read and joined, on the first file's time stamps
/// (when it has them), before they are made uniform: what [`load`] makes a data set of
/// ([`finish`]), or `load_segments` cuts at its gaps first.
pub(crate) struct ReadSources {
    /// Each role's columns (in [`ROLES`] order).
    pub(crate) blocks: [Option<Vec<Vec<f64>>>; 7],
    /// The time stamps of the first file joined by time, the file and its lines.
    pub(crate) reference: Option<(Vec<f64>, PathBuf, Vec<u64>)>,
    /// The rows, the first file and its lines of files joined row by row.
    pub(crate) rows: Option<(usize, PathBuf, Vec<u64>)>,
    /// What was repaired.
    pub(crate) warnings: Vec<Warning>,
    /// The sampling of each file.
    pub(crate) samplings: Vec<Sampling>,
    /// The name of the data set: the first file's.
    pub(crate) name: String,
    /// When the files were joined row by row because their time columns have different
    /// names (`data::rate::differing_time_columns`): what to do, naming each file's column.
    pub(crate) time_names: Option<String>,
}

/// Reads the files of `config`'s sources (see [`load`]) for a `dof`-joint model, with the
/// config that reads them (a time column found in the files). With [`Gaps::Split`], the
/// time stamps of the first file joined by time may have gaps (the caller cuts there);
/// a gap elsewhere is refused.
pub(crate) fn read_sources<'a>(
    config: &'a Config,
    files: &[PathBuf],
    dof: usize,
    gaps: Gaps,
) -> Result<(Cow<'a, Config>, ReadSources)> {
    check_joints(dof)?;
    config.check(dof)?;
    let paths = source_paths(config, files)?;
    let found = with_found_time_column(config, &paths, dof)?;
    let config = &*found;
    let mut blocks: [Option<Vec<Vec<f64>>>; 7] = Default::default();
    let mut reference: Option<(Vec<f64>, PathBuf, Vec<u64>)> = None;
    let mut rows: Option<(usize, PathBuf, Vec<u64>)> = None;
    let mut warnings = Vec::new();
    let mut samplings = Vec::new();
    // the samples of the reference that every file joined to it by time covers
    let mut overlap = 0..usize::MAX;
    // the median step of the reference's time stamps
    let mut reference_step: Option<f64> = None;

    for (index, (src, path)) in config.sources.iter().zip(&paths).enumerate() {
        let SourceColumns {
            names,
            spans,
            unread_time,
        } = plan_source(config, src, index, path, dof)?;
        let optional = unread_time_rows(&names, unread_time.as_ref());
        let mut table = read_columns_in(path, &names, optional).map_err(|e| match e {
            Error::Data(DataError::MissingColumn {
                path,
                column,
                available,
                ..
            }) => {
                let key = spans
                    .iter()
                    .find(|(_, start)| names[*start..*start + dof].contains(&column))
                    .map_or_else(
                        || "time_column".to_string(),
                        |(r, _)| format!("source[{}].{}", index + 1, ROLES[*r]),
                    );
                let mapping = config.mapping(&key);
                Error::Data(DataError::MissingColumn {
                    path,
                    column,
                    available,
                    mapping: Box::new(mapping),
                })
            }
            e => e,
        })?;
        if table.rows() < 2 {
            return Err(Error::TooFewSamples {
                context: path.display().to_string(),
                found: table.rows(),
                required: 2,
                hint: "the file needs a header and data rows",
            });
        }
        check_ranges(&table, &names, &spans, dof)?;
        let time = take_time(config, &mut table)?;
        // a file kept on disk (`SpilledRecord`) with a gap is loaded here instead: its
        // clock is irregular
        if let Some(t) = &time {
            match (gaps, &reference) {
                (Gaps::Split, None) => {}
                (Gaps::Split, Some(_)) => check_gaps(t, |k| table.location(k), GAP_FIX_JOINED)?,
                (Gaps::Refuse, _) => {
                    let fix = match config.processing.gaps {
                        Gaps::Split => GAP_FIX_WHOLE,
                        Gaps::Refuse => GAP_FIX,
                    };
                    check_gaps(t, |k| table.location(k), fix)?
                }
            }
        }
        if let Some(column) = &unread_time {
            let mut steps = Steps::default();
            steps.push(&table.columns.pop().unwrap_or_default(), &table.lines);
            check_rate(config, path, column, steps)?;
        }
        let mut columns = std::mem::take(&mut table.columns);
        // angles logged modulo a turn, unwrapped before any interpolation
        let mut unwrap = Unwrap::new(config, dof);
        unwrap.apply(&spans, &mut columns, &table.lines);
        warnings.extend(unwrap.warnings(path));
        let sampling = Sampling::of(path.clone(), time.as_deref(), &columns);
        let first_stale = sampling
            .stale_rows
            .first()
            .and_then(|&k| table.lines.get(k));
        warnings.extend(stale_warning(&sampling, first_stale.copied()));
        warnings.extend(slow_warning(&sampling, &spans));
        let step = sampling.step;
        samplings.push(sampling);
        match time {
            Some(t) => match &reference {
                None => {
                    reference_step = step;
                    reference = Some((t, path.clone(), table.lines.clone()))
                }
                Some((tref, first, _)) => {
                    // a temperature may be logged slowly; a measurement of the motion not
                    let measured = measures_motion(&spans);
                    if let (Some(step), Some(first_step)) = (step, reference_step)
                        && measured
                        && step > GAP_RATIO * first_step
                    {
                        return Err(Error::Data(DataError::CoarseJoin {
                            path: path.clone(),
                            step,
                            first: first.clone(),
                            first_step,
                        }));
                    }
                    columns = columns.iter().map(|x| interpolate(&t, x, tref)).collect();
                    // the samples of the reference within this file's time stamps: outside
                    // them the interpolation holds its first or last value, which is no
                    // measurement, so they are dropped below
                    let (t0, t1) = (t[0], t[t.len() - 1]);
                    let covered =
                        tref.partition_point(|&s| s < t0)..tref.partition_point(|&s| s <= t1);
                    overlap = overlap.start.max(covered.start)..overlap.end.min(covered.end);
                    if overlap.len() < 2 {
                        return Err(no_overlap(path, (t0, t1), first, tref, overlap.len()));
                    }
                    let dropped = tref.len() - covered.len();
                    if dropped > 0 {
                        warnings.push(Warning::PartialOverlap {
                            path: path.clone(),
                            dropped,
                        });
                    }
                    let (s0, s1) = (tref[0], tref[tref.len() - 1]);
                    let unused =
                        t.partition_point(|&s| s < s0) + t.len() - t.partition_point(|&s| s <= s1);
                    if unused > 0 {
                        warnings.push(Warning::JoinedRowsUnused {
                            path: path.clone(),
                            unused,
                            rows: t.len(),
                            first: first.clone(),
                        });
                    }
                }
            },
            None => check_rows(&mut rows, &table).map_err(|mut e| {
                // each file has a time column, under different names: none was read
                if let Error::Data(DataError::RowCountMismatch { fix, .. }) = &mut e
                    && let Some(names) = differing_time_columns(config, &paths, dof)
                {
                    *fix = names;
                }
                e
            })?,
        }
        for (role, start) in spans {
            if blocks[role].is_some() {
                return Err(Error::setting(
                    "Config",
                    &format!("source[{}].{}", index + 1, ROLES[role]),
                    format!(
                        "`{}` columns are given by more than one [[source]]; keep them in one",
                        ROLES[role]
                    ),
                ));
            }
            // moved, not copied: a long record is held once
            blocks[role] = Some(
                columns[start..start + dof]
                    .iter_mut()
                    .map(std::mem::take)
                    .collect(),
            );
        }
    }

    if let Some((t, _, lines)) = &mut reference
        && overlap.end < usize::MAX
        && overlap.len() < t.len()
    {
        let n = t.len();
        // blocks of files joined row by row have the reference's rows, else `assemble`
        // names the mismatch
        for x in blocks.iter_mut().flatten().flatten() {
            if x.len() == n {
                *x = x[overlap.clone()].to_vec();
            }
        }
        *t = t[overlap.clone()].to_vec();
        *lines = lines[overlap.clone()].to_vec();
    }
    let name = paths
        .first()
        .and_then(|p| p.file_name())
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    // joined row by row, the same length: a time column in every file, under different
    // names, was told "the data has no time column"
    let time_names = match reference {
        None => differing_time_columns(config, &paths, dof),
        Some(_) => None,
    };
    let read = ReadSources {
        blocks,
        reference,
        rows,
        warnings,
        samplings,
        name,
        time_names,
    };
    Ok((found, read))
}

/// The data set of the sources `read` with `config`: the time stamps checked and, when
/// irregular, resampled onto a uniform grid; units and the drive chain applied.
pub(crate) fn finish(config: &Config, dof: usize, read: ReadSources) -> Result<Dataset> {
    let ReadSources {
        mut blocks,
        reference,
        rows,
        mut warnings,
        samplings,
        name,
        time_names,
    } = read;
    let (sample_time, origin) = match (&reference, config.sample_rate) {
        (Some((t, path, lines)), _) => {
            let (step, resampled) = regularity(t, path);
            check_step(config, step, path)?;
            let mut lines = lines.clone();
            if let Some((grid, w)) = resampled {
                let at = grid.times(0..grid.samples);
                for b in blocks.iter_mut().flatten() {
                    *b = b.iter().map(|x| interpolate(t, x, &at)).collect();
                }
                lines = nearest_lines(t, &lines, &at);
                warnings.push(w);
            }
            (
                step,
                DataOrigin {
                    path: path.clone(),
                    lines,
                },
            )
        }
        (None, Some(fs)) => {
            let (_, path, lines) = rows.clone().unwrap_or_default();
            (1.0 / fs, DataOrigin { path, lines })
        }
        (None, None) => {
            if let Some(names) = time_names {
                return Err(config.key_error(
                    "sample_rate",
                    format!("{names}, or set `sample_rate = ...` (Hz)"),
                ));
            }
            return Err(config.key_error(
                "sample_rate",
                "the data has no time column; set `sample_rate = ...` (Hz) or `time_column = \"...\"`",
            ));
        }
    };

    check_cutoff(config, sample_time)?;
    let mut data = assemble(
        config,
        dof,
        name,
        sample_time,
        blocks,
        origin,
        Values::Check,
    )?;
    data.warnings = warnings;
    data.sampling = samplings;
    // the joint-side extremes, while they are at hand (`Record::extremes`)
    let mut extremes = Extremes::default();
    let dt = data.sample_time;
    let derivatives = [data.qd.as_ref(), data.qdd.as_ref()];
    extremes.widen(&data.q, derivatives, &data.tau, &|k| k as f64 * dt);
    data.extremes = extremes;
    Ok(data)
}

/// The error for a file `path` whose time stamps, from `span.0` to `span.1`, leave fewer
/// than 2 (`found`) samples of the first file joined by time, `first`, whose time
/// stamps are `tref`, with every file joined to it.
fn no_overlap(path: &Path, span: (f64, f64), first: &Path, tref: &[f64], found: usize) -> Error {
    Error::TooFewSamples {
        context: format!(
            "{} (time stamps {} s to {} s) joined by time with {} ({} s to {} s), in the \
             time every file covers",
            path.display(),
            Num::rounded(span.0, 15),
            Num::rounded(span.1, 15),
            first.display(),
            Num::rounded(tref[0], 15),
            Num::rounded(tref[tref.len() - 1], 15)
        ),
        found,
        required: 2,
        hint: "join files recorded at the same time, with time stamps of one clock (the same \
               origin and unit)",
    }
}

/// The sample rate (Hz) below which a log's time stamps are warned about: a robot's
/// dynamics (its excitation reaches a few hertz, the low-pass tens) need more, and a time
/// column in ms read as seconds gives a thousandth of the real rate (a 100 Hz log read at
/// 0.1 Hz was refused by the rest removal, which named the velocities' units).
pub const SLOW_SAMPLE_RATE: f64 = 10.0;

/// Whether a source's columns (`spans`, as [`SourceColumns::spans`]) hold any role
/// but temperatures: positions, velocities, torques or currents, which follow the
/// motion. Temperatures alone vary slowly and may be logged slowly.
pub(crate) fn measures_motion(spans: &[(usize, usize)]) -> bool {
    spans.iter().any(|(r, _)| ROLES[*r] != "temperature")
}

/// The warning about time stamps whose median step gives a rate below
/// [`SLOW_SAMPLE_RATE`], for a file that measures the motion (`spans`, see
/// [`measures_motion`]): a file of temperatures alone may be that slow.
pub(crate) fn slow_warning(sampling: &Sampling, spans: &[(usize, usize)]) -> Option<Warning> {
    let step = sampling.step?;
    let slow = step > 0.0 && 1.0 / step < SLOW_SAMPLE_RATE;
    (slow && measures_motion(spans)).then(|| Warning::SlowSampling {
        path: sampling.path.clone(),
        step,
    })
}

/// The warning about stale rows when there are more than [`STALE_SHARE`] of them
/// (`first_line`: the file line of the first).
pub(crate) fn stale_warning(sampling: &Sampling, first_line: Option<u64>) -> Option<Warning> {
    (!sampling.stale_rows.is_empty()
        && sampling.stale_rows.len() as f64 > STALE_SHARE * sampling.rows as f64)
        .then(|| Warning::StaleRows {
            path: sampling.path.clone(),
            stale: sampling.stale_rows.len(),
            rows: sampling.rows,
            first_line: first_line.unwrap_or(0),
        })
}

/// What a `[[source]]` reads from its file.
pub(crate) struct SourceColumns {
    /// The columns: each role's in [`ROLES`] order, then the time column, then the
    /// unread time column (an optional column: NaN where it is not a number).
    pub(crate) names: Vec<String>,
    /// Each role and where its columns start in `names`.
    pub(crate) spans: Vec<(usize, usize)>,
    /// The time column that the config does not read, checked against `sample_rate`
    /// ([`unread_time_column`]): the last of `names` when there is one.
    pub(crate) unread_time: Option<UnreadTime>,
}

/// The columns `[[source]]` `src` (number `index`, from 0) reads from its file `path`,
/// after the checks of the file's header ([`check_surplus_joint`]). The header is read
/// (its first MiB) when a template or the time-column check needs it.
pub(crate) fn plan_source(
    config: &Config,
    src: &Source,
    index: usize,
    path: &Path,
    dof: usize,
) -> Result<SourceColumns> {
    let rate_check = config.sample_rate.is_some() && config.time_column.is_none();
    let header = if rate_check || !templates(src).is_empty() {
        read_header(path)?
    } else {
        Vec::new()
    };
    check_surplus_joint(config, src, index, path, &header, dof)?;
    let (mut names, spans) = source_columns(config, src, dof);
    let unread_time = unread_time_column(config, &header, &names);
    if let Some(t) = &unread_time {
        names.push(t.name.clone());
    }
    Ok(SourceColumns {
        names,
        spans,
        unread_time,
    })
}

/// How the columns `names` of a source are read: the unread time column (when there is
/// one, the last) as an optional column (NaN where a field is not a number), in every row.
pub(crate) fn unread_time_rows(names: &[String], unread_time: Option<&UnreadTime>) -> Optional {
    match unread_time {
        Some(_) => Optional {
            from: names.len() - 1,
            rows: usize::MAX,
        },
        None => Optional::none(names),
    }
}

/// The columns a `[[source]]` reads: each role's columns in [`ROLES`] order (with where
/// they start), then the time column.
pub(crate) fn source_columns(
    config: &Config,
    src: &Source,
    dof: usize,
) -> (Vec<String>, Vec<(usize, usize)>) {
    let mut names = Vec::new();
    let mut spans = Vec::new();
    for role in 0..ROLES.len() {
        if let Some(cols) = role_columns(src, role) {
            let n = cols.names(dof);
            spans.push((role, names.len()));
            names.extend(n);
        }
    }
    if let Some(t) = &config.time_column {
        names.push(t.clone());
    }
    (names, spans)
}

/// Refuses a `[[source]]` (number `index`, from 0) whose file `path` has a column for one
/// joint more than the model's `dof`, by a template of the source (`q7` for a 6-joint
/// model read through `"q{}"`): the data and the description are then of different
/// robots, and reading the first columns only would identify nonsense without a word. A
/// source that lists its columns has chosen them and is not checked. `header`: the
/// file's column names.
fn check_surplus_joint(
    config: &Config,
    src: &Source,
    index: usize,
    path: &Path,
    header: &[String],
    dof: usize,
) -> Result<()> {
    for (role, template) in templates(src) {
        if let Some(column) = surplus_joint(header, template, dof) {
            let key = format!("source[{}].{}", index + 1, ROLES[role]);
            return Err(config.key_error(
                &key,
                format!(
                    "{}: has a column `{}`, for joint {} of a model with {}; \
                     give the description of the robot that recorded the data, or list the \
                     {} to read ({} = [\"{}\", ...])",
                    path.display(),
                    crate::data::error::quoted(&column),
                    dof + 1,
                    crate::Count(dof, "joint"),
                    crate::Count(dof, "column"),
                    ROLES[role],
                    template.replace("{}", "1"),
                ),
            ));
        }
    }
    Ok(())
}

/// The templates with a joint number (`"q{}"`) of a `[[source]]`, with their roles.
fn templates(src: &Source) -> Vec<(usize, &str)> {
    (0..ROLES.len())
        .filter_map(|r| match role_columns(src, r) {
            Some(crate::data::Columns::Template(t)) if t.contains("{}") => Some((r, t.as_str())),
            _ => None,
        })
        .collect()
}

/// The column of `header` that `template` (`"q{}"`) names for joint `dof + 1`, if any:
/// a sign that the file holds more joints than a `dof`-joint model.
///
/// ```
/// use robid_runtime::data::surplus_joint;
/// let header = ["t", "q1", "q2", "q3"].map(String::from);
/// assert_eq!(surplus_joint(&header, "q{}", 2), Some("q3".to_string()));
/// assert_eq!(surplus_joint(&header, "q{}", 3), None);
/// ```
pub fn surplus_joint(header: &[String], template: &str, dof: usize) -> Option<String> {
    let next = template.replace("{}", &(dof + 1).to_string());
    header.contains(&next).then_some(next)
}

/// Checks every role's columns of `table` against the range of its quantity.
pub(crate) fn check_ranges(
    table: &Table,
    names: &[String],
    spans: &[(usize, usize)],
    dof: usize,
) -> Result<()> {
    for &(role, start) in spans {
        for (k, name) in names[start..start + dof].iter().enumerate() {
            table.check_range(start + k, name, QUANTITIES[role])?;
        }
    }
    Ok(())
}

/// The time column of `table` when the config has one (its last column, taken from
/// it): scaled to seconds, checked in range and increasing.
pub(crate) fn take_time(config: &Config, table: &mut Table) -> Result<Option<Vec<f64>>> {
    let Some(name) = &config.time_column else {
        return Ok(None);
    };
    let mut t = table.columns.pop().unwrap_or_default();
    let scale = config.seconds_per_time_unit();
    t.iter_mut().for_each(|v| *v *= scale);
    // checked as a table of its own, whose lines locate an error
    let mut columns = std::mem::replace(&mut table.columns, vec![t]);
    let checked = table.check_range(0, name, Quantity::Time);
    std::mem::swap(&mut table.columns, &mut columns);
    checked?;
    let t = columns.pop().unwrap_or_default();
    check_monotonic(&t, &table.lines, &table.path)?;
    Ok(Some(t))
}

/// The end of the message about a gap in a data file's time stamps.
const GAP_FIX: &str = "set `gaps = \"split\"` in [processing] to cut the record at every gap \
     and identify from the continuous segments together (each processed on its own), or \
     delete the rows on one side of the gap";

/// The end of the message about a gap in a data file's time stamps read where
/// `gaps = "split"` does not apply.
const GAP_FIX_WHOLE: &str = "`gaps = \"split\"` applies to the data of `robid identify` (the \
     estimation record and each --validate record) and `robid inspect`, not to the runs of \
     [runs] nor to the commands that read one continuous record: split the file at this line into files \
     recorded without a pause, or delete the rows on one side of the gap";

/// The end of the message about a gap in the time stamps of a file joined by time to
/// the first file, which `gaps = "split"` does not cut.
const GAP_FIX_JOINED: &str = "`gaps = \"split\"` cuts the first file joined by time at its \
     gaps, not the files interpolated onto its time stamps: give the file with the gaps \
     first among the [[source]] tables if the others have the same gaps, or delete the rows \
     on one side of the gap in every file";

/// Checks the mean time step of `path` against the sample rates robid takes
/// ([`check_sample_time`], the rule trajectories share), at the `time_scale` key.
pub(crate) fn check_step(config: &Config, step: f64, path: &Path) -> Result<()> {
    check_sample_time(
        step,
        || path.display().to_string(),
        "the time column must be in seconds: convert it, or give its unit with time_scale \
         (1e-3 for ms, 1e-9 for ns)",
    )
    .map_err(|e| config.key_error("time_scale", e.to_string()))
}

/// Checks the low-pass cutoff against the sample time.
pub(crate) fn check_cutoff(config: &Config, sample_time: f64) -> Result<()> {
    if let Some(cutoff) = config
        .processing
        .lowpass
        .as_ref()
        .and_then(|lp| lp.cutoff.hz())
    {
        let nyquist = 0.5 / sample_time;
        let min = crate::signal::MIN_CUTOFF * nyquist;
        let max = crate::signal::MAX_CUTOFF * nyquist;
        if !(cutoff <= max && cutoff >= min) {
            return Err(config.key_error(
                "processing.lowpass.cutoff",
                // the cutoff as typed; the bounds, computed from a sample time that may
                // be measured from time stamps, rounded, but never onto the cutoff
                format!(
                    "{} Hz is outside [{}, {}] Hz for data sampled at {} Hz: the filter can be represented from {:e} of the Nyquist frequency ({} Hz) to {:e} of it below it; choose a cutoff in that range",
                    crate::error::num(cutoff),
                    Num::rounded_keeping(min, 6, |m| (cutoff < m) == (cutoff < min)),
                    Num::rounded_keeping(max, 6, |m| (cutoff > m) == (cutoff > max)),
                    Num::rounded(1.0 / sample_time, 6),
                    crate::signal::MIN_CUTOFF,
                    Num::rounded(nyquist, 6),
                    crate::signal::MIN_CUTOFF
                ),
            ));
        }
    }
    Ok(())
}

/// The data set of the columns read for each role (in [`ROLES`] order): angles in
/// radians, torques scaled, the drive chain applied, every value checked (unless
/// `values` says the same values were checked before).
pub(crate) fn assemble(
    config: &Config,
    dof: usize,
    name: String,
    sample_time: f64,
    blocks: [Option<Vec<Vec<f64>>>; 7],
    origin: DataOrigin,
    values: Values,
) -> Result<Dataset> {
    let [q, qd, qdd, tau, motor, temperature, joint_torque] = blocks;
    let missing = |role: &str| {
        config.key_error(
            "source",
            format!("no [[source]] gives `{role}` columns; add e.g. {role} = \"{role}{{}}\""),
        )
    };
    let (q, tau) = (
        q.ok_or_else(|| missing("position"))?,
        tau.ok_or_else(|| missing("torque"))?,
    );
    let chain = DriveChain::new(&config.drive, dof)?;
    // columns of one role to signals in radians; a prismatic joint's are lengths, unless
    // they are a motor's (`turns`)
    let angle_of = |x: Vec<Vec<f64>>, turns: bool| {
        Signals::new(match config.units.angle {
            AngleUnit::Rad => x,
            AngleUnit::Deg => {
                let mut x = x;
                for (j, v) in x.iter_mut().enumerate() {
                    if turns || !config.prismatic.get(j).copied().unwrap_or(false) {
                        v.iter_mut().for_each(|a| *a = a.to_radians());
                    }
                }
                x
            }
        })
    };
    let angle = |x| angle_of(x, false);
    let mut tau = tau;
    if let Some(s) = &config.units.torque_scale {
        for (t, s) in tau.iter_mut().zip(s.values(dof, "units.torque_scale")?) {
            t.iter_mut().for_each(|v| *v *= s);
        }
    }
    let mut q = chain.joint_positions(angle(q)?);
    if let Some(o) = &config.units.position_offset {
        // (a joint without an offset left as read: no pass over a long record)
        for (x, o) in q.joints_mut().zip(o.values(dof, "units.position_offset")?) {
            if o != 0.0 {
                x.iter_mut().for_each(|v| *v += o);
            }
        }
    }
    let mut data = Dataset::new_with(
        name,
        sample_time,
        q,
        chain.joint_torques(Signals::new(tau)?),
        Some(origin),
        values,
    )?;
    if let Some(v) = qd {
        data = data.with_velocities_as(chain.joint_positions(angle(v)?), values)?;
    }
    if let Some(a) = qdd {
        data = data.with_accelerations_as(chain.joint_positions(angle(a)?), values)?;
    }
    if let Some(m) = motor {
        data = data
            .with_motor_positions_as(chain.reflected_motor_positions(angle_of(m, true)?), values)?;
    }
    // temperatures and joint torques are used as read: deg C and link-side N m
    if let Some(t) = temperature {
        data = data.with_temperatures_as(Signals::new(t)?, values)?;
    }
    if let Some(t) = joint_torque {
        data = data.with_joint_torques_as(Signals::new(t)?, values)?;
    }
    if config.drive.rotor.is_some() && data.motor.is_none() {
        return Err(config.key_error(
            "drive.rotor",
            "rotor compensation needs motor encoder columns: add motor_position = [...] to a [[source]]",
        ));
    }
    Ok(data)
}

/// The files the data are read from: `files` when given (one per `[[source]]` table),
/// else the config's own ([`Config::source_files`]).
pub(crate) fn source_paths(config: &Config, files: &[PathBuf]) -> Result<Vec<PathBuf>> {
    if config.sources.is_empty() {
        return Err(config.key_error(
            "source",
            "no [[source]] table; add one per file with its position and torque columns",
        ));
    }
    if !files.is_empty() {
        if files.len() != config.sources.len() {
            return Err(config.key_error(
                "source",
                format!(
                    "{} given but there {} {}; give one file per table",
                    crate::Count(files.len(), "file"),
                    if config.sources.len() == 1 {
                        "is"
                    } else {
                        "are"
                    },
                    crate::Count(config.sources.len(), "[[source]] table")
                ),
            ));
        }
        return Ok(files.to_vec());
    }
    config.source_files()
}

impl Config {
    /// The data files that the `[[source]]` tables name, in their order, each resolved
    /// against the config's folder ([`Config::resolve`]). A table without `file`, and a
    /// file that does not exist, are refused naming the key `source[i].file` (at its
    /// file:line:column for a config file) with the path as resolved and the fix: the
    /// reader's own error named the resolved path alone, not the key nor the folder it
    /// was read from.
    pub fn source_files(&self) -> Result<Vec<PathBuf>> {
        if self.sources.is_empty() {
            return Err(self.key_error(
                "source",
                "no [[source]] table; add one per file with its position and torque columns",
            ));
        }
        self.sources
            .iter()
            .enumerate()
            .map(|(i, s)| {
                let key = format!("source[{}].file", i + 1);
                let Some(file) = s.file.as_deref() else {
                    return Err(self.key_error(
                        &key,
                        "no file given; set `file = \"...\"` (relative to the config's \
                         folder) or pass the data files explicitly (robid: --data)",
                    ));
                };
                let path = self.resolve(file);
                match std::fs::metadata(&path) {
                    Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                        let read = match &self.base_dir {
                            Some(dir) if file.is_relative() => format!(
                                " (`{}` is read from the config's folder {})",
                                file.display(),
                                if dir.as_os_str().is_empty() {
                                    Path::new(".")
                                } else {
                                    dir
                                }
                                .display()
                            ),
                            _ => String::new(),
                        };
                        Err(self.key_error(
                            &key,
                            format!(
                                "the file {} does not exist{read}; fix the path (relative to \
                                 the config's folder, or absolute) or pass the data files \
                                 explicitly (robid: --data)",
                                path.display()
                            ),
                        ))
                    }
                    // a file that cannot be read otherwise is named by its reader
                    _ => Ok(path),
                }
            })
            .collect()
    }
}

fn check_rows(rows: &mut Option<(usize, PathBuf, Vec<u64>)>, table: &Table) -> Result<()> {
    match rows {
        None => *rows = Some((table.rows(), table.path.clone(), table.lines.clone())),
        Some((n, first, _)) if *n != table.rows() => {
            return Err(Error::Data(DataError::RowCountMismatch {
                first: first.clone(),
                first_rows: *n,
                second: table.path.clone(),
                second_rows: table.rows(),
                fix: "give both files the same rows, or a time column in each so they can \
                      be joined by time"
                    .into(),
            }));
        }
        _ => {}
    }
    Ok(())
}

/// Refuses a file that two runs of `[runs]` share: repeated acquisitions are separate
/// recordings, and a run listed twice gave a run-to-run spread of exactly 0 (and an
/// average claiming less noise) with no warning.
fn refuse_shared_run_files(config: &Config, runs: &crate::data::Runs) -> Result<()> {
    let files: Vec<Vec<PathBuf>> = runs
        .files
        .iter()
        .map(|r| r.paths().iter().map(|f| config.resolve(f)).collect())
        .collect();
    for (i, run) in files.iter().enumerate() {
        for (k, earlier) in files[..i].iter().enumerate() {
            let shared = run
                .iter()
                .find(|f| earlier.iter().any(|e| crate::output::same_file(f, e)));
            if let Some(f) = shared {
                return Err(config.key_error(
                    "runs.files",
                    format!(
                        "runs {} and {} both read {}: repeated acquisitions are separate \
                         recordings (a run given twice shows no spread between runs); list \
                         each recording once",
                        k + 1,
                        i + 1,
                        f.display()
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// Loads every run of `[runs]` (files relative to the config file), in order; an error
/// when the config has no `[runs]`. Each run is loaded like [`load`] with its files.
pub fn load_runs(config: &Config, dof: usize) -> Result<Vec<Dataset>> {
    let runs = config.runs.as_ref().ok_or_else(|| {
        config.key_error(
            "runs",
            "no [runs] table; list the runs' files in [runs] files = [...]",
        )
    })?;
    config.check(dof)?;
    refuse_shared_run_files(config, runs)?;
    let loaded: Vec<Dataset> = runs
        .files
        .iter()
        .enumerate()
        .map(|(i, r)| {
            let files: Vec<PathBuf> = r.paths().iter().map(|f| config.resolve(f)).collect();
            load(config, &files, dof).map_err(|e| config.run_error(i, "", e))
        })
        .collect::<Result<_>>()?;
    // a copy of a recording under another name is no repeated acquisition either (its
    // spread was exactly 0)
    for (i, run) in loaded.iter().enumerate() {
        if let Some(k) = loaded[..i]
            .iter()
            .position(|e| e.q == run.q && e.tau == run.tau)
        {
            return Err(config.key_error(
                "runs.files",
                format!(
                    "runs {} and {} hold the same samples ({} and {}): copies of one \
                     recording show no spread between runs; list each recording once",
                    k + 1,
                    i + 1,
                    loaded[k].name,
                    run.name
                ),
            ));
        }
    }
    Ok(loaded)
}

/// Loads with the sources' own `file` entries (relative to the config file).
pub fn load_config_files(config: &Config, dof: usize) -> Result<Dataset> {
    load(config, &[], dof)
}

/// Convenience: reads the config at `path` and loads its files.
pub fn load_from_config_file(path: &Path, dof: usize) -> Result<Dataset> {
    load(&Config::from_file(path)?, &[], dof)
}
