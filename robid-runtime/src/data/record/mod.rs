//! Records read block by block. The streaming stages (OLS, WLS, validation:
//! `pipeline::stream`) take a [`Record`]: a [`Dataset`] in memory, or a [`SpilledRecord`]
//! whose samples wait in a temporary file, so that an hour-long log is never held whole
//! (docs/identification.md#records-kept-on-disk).

use std::borrow::Cow;
use std::fs::File;
use std::io::{BufWriter, Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use crate::DataError;
use crate::data::dataset::{DataOrigin, Extremes, Values, empty_range};
use crate::data::load::{
    SourceColumns, assemble, check_cutoff, check_joints, check_ranges, check_step, load,
    plan_source, slow_warning, source_paths, stale_warning, take_time, unread_time_rows,
};
use crate::data::rate::{Steps, check_rate};
use crate::data::sampling::SamplingScan;
use crate::data::table::for_each_window_of;
use crate::data::time::{Clock, Grid, interpolate, nearest_lines};
use crate::data::unwrap::Unwrap;
use crate::data::{Config, Dataset, Sampling, WINDOW, Warning};
use crate::error::{Error, Result};
use crate::progress::Progress;

mod stored;
use stored::Stored;

/// Samples on a uniform time grid that can be read in blocks.
pub trait Record: Sync {
    /// Name for reports.
    fn name(&self) -> &str;
    /// Sample time in seconds.
    fn sample_time(&self) -> f64;
    /// Number of samples.
    fn samples(&self) -> usize;
    /// Number of joints.
    fn dof(&self) -> usize;
    /// What was repaired while loading.
    fn warnings(&self) -> &[Warning];
    /// The file the samples come from, when they come from one.
    fn file(&self) -> Option<&Path>;
    /// Per joint the extremes of the positions and torques ([`Extremes`]), gathered by the
    /// loader as it read the samples; empty when the samples were not loaded from files.
    /// For samples resampled onto a uniform grid, those of the record kept on disk are of
    /// the samples as read, which the resampled ones lie between.
    fn extremes(&self) -> &Extremes;
    /// The file line of sample `k`, when known.
    fn line(&self, k: usize) -> Option<u64>;
    /// Every file the samples were read from: [`Record::file`] first, then the files
    /// joined to it (several `[[source]]` files, by time or row by row). Empty when the
    /// samples do not come from files.
    fn files(&self) -> Vec<&Path> {
        self.file().into_iter().collect()
    }
    /// The samples `start..end` (`end` clamped to the length) as a data set: borrowed when
    /// they are the whole of a data set in memory. An error when the range is empty.
    fn read(&self, start: usize, end: usize) -> Result<Cow<'_, Dataset>>;

    /// Where sample `k` is: `file:line` when the data came from a file, else the
    /// record's name and the sample (0-based).
    fn location(&self, k: usize) -> String {
        match self.file().zip(self.line(k)) {
            Some((path, line)) => format!("{}:{line}", path.display()),
            None => format!("data set `{}`, sample {k}", self.name()),
        }
    }
}

impl Record for Dataset {
    fn name(&self) -> &str {
        &self.name
    }

    fn sample_time(&self) -> f64 {
        self.sample_time
    }

    fn samples(&self) -> usize {
        Dataset::samples(self)
    }

    fn dof(&self) -> usize {
        Dataset::dof(self)
    }

    fn warnings(&self) -> &[Warning] {
        &self.warnings
    }

    fn file(&self) -> Option<&Path> {
        self.origin.as_ref().map(|o| o.path.as_path())
    }

    fn extremes(&self) -> &Extremes {
        &self.extremes
    }

    fn line(&self, k: usize) -> Option<u64> {
        self.origin.as_ref()?.lines.get(k).copied()
    }

    fn files(&self) -> Vec<&Path> {
        let mut files: Vec<&Path> = self.file().into_iter().collect();
        for s in &self.sampling {
            if !files.contains(&s.path.as_path()) {
                files.push(&s.path);
            }
        }
        files
    }

    fn read(&self, start: usize, end: usize) -> Result<Cow<'_, Dataset>> {
        if start == 0 && end >= Dataset::samples(self) && Dataset::samples(self) > 0 {
            Ok(Cow::Borrowed(self))
        } else {
            self.slice(start, end).map(Cow::Owned)
        }
    }
}

/// `", joined with b.csv and c.csv"` when the samples of `data` were joined from several
/// files (the files after its [`Record::file`]), else nothing: what a message about the
/// record's length adds to the first file it names, so that none of the files is left out.
pub(crate) fn joined_with(data: &dyn Record) -> String {
    let others: Vec<String> = data
        .files()
        .iter()
        .skip(1)
        .map(|p| p.display().to_string())
        .collect();
    match others.split_last() {
        None => String::new(),
        Some((last, [])) => format!(", joined with {last}"),
        Some((last, rest)) => format!(", joined with {} and {last}", rest.join(", ")),
    }
}

/// A data set loaded as [`load`] loads it, whose samples are kept in a temporary file
/// (deleted when the record is dropped) instead of memory: each block read from it is
/// the same, value for value, as the same samples of the data set `load` gives.
///
/// The file is read once, window by window ([`WINDOW`] bytes of text): each window is
/// checked and converted as `load` does it (ranges, time stamps, units, the drive chain),
/// its signals, lines and time stamps written to the temporary file, and the sampling
/// statistics gathered on the way. In memory stay the time steps while loading (for their
/// median), and where each window's samples are. Irregular time stamps (jitter, a few lost
/// ticks: what `load` resamples) are resampled as each block is read: the block's grid
/// times interpolated between the same two stamps as `load` interpolates them.
#[derive(Debug)]
pub struct SpilledRecord {
    name: String,
    path: PathBuf,
    sample_time: f64,
    dof: usize,
    /// Which of the loader's roles the samples have.
    roles: [bool; 7],
    chunks: Vec<Chunk>,
    /// The rows kept (the chunks' samples, as written).
    rows: usize,
    /// The record's samples: the rows, or the samples of `grid`.
    samples: usize,
    /// The grid of irregular stamps ([`Clock::grid`]): the samples are then its samples,
    /// interpolated when a block is read.
    grid: Option<Grid>,
    /// The config: units and the drive chain, applied to each block read.
    config: Config,
    spill: Mutex<File>,
    warnings: Vec<Warning>,
    sampling: Sampling,
    /// Per joint the smallest and largest position of the samples as read (joint side).
    extremes: Extremes,
}

/// Where one window's samples are in the temporary file: every signal the record has
/// (in the loader's role order (positions, velocities, accelerations, torques, motor
/// positions, temperatures, joint torques), joint by joint, `len` values each), then their
/// `len` file lines, then their `len` time stamps when the file has a time column; each
/// column as its decimal digits when they give its values back to the bit, else each
/// value's 8 bytes as they are in memory (the file is this process's own, written and
/// read on the same machine; [`stored`]).
#[derive(Debug, Clone)]
struct Chunk {
    start: usize,
    len: usize,
    /// Each column's place and form in the file.
    columns: Vec<Stored>,
    /// The window's first and last time stamps (0 without a time column).
    first_time: f64,
    last_time: f64,
}

impl SpilledRecord {
    /// How the file was sampled.
    pub fn sampling(&self) -> &Sampling {
        &self.sampling
    }

    /// The record of the files `files` (or the config's own) for a `dof`-joint model:
    /// `None` when it cannot be kept on disk (several sources, which are joined in
    /// memory; time stamps that go back or pause, which `load` refuses naming the line;
    /// too few rows). An error is the first
    /// problem found reading the file window by window, which need not be the one
    /// [`load`] reports first; [`load_record`] reports `load`'s.
    pub fn open(config: &Config, files: &[PathBuf], dof: usize) -> Result<Option<Self>> {
        Self::open_in(config, files, dof, WINDOW)
    }

    /// [`SpilledRecord::open`] with windows of `window` bytes of text.
    pub(crate) fn open_in(
        config: &Config,
        files: &[PathBuf],
        dof: usize,
        window: usize,
    ) -> Result<Option<Self>> {
        check_joints(dof)?;
        config.check(dof)?;
        let paths = source_paths(config, files)?;
        let config = &*crate::data::rate::with_found_time_column(config, &paths, dof)?;
        let ([source], [path]) = (config.sources.as_slice(), paths.as_slice()) else {
            return Ok(None);
        };
        let SourceColumns {
            names,
            spans,
            unread_time,
        } = plan_source(config, source, 0, path, dof)?;
        let optional = unread_time_rows(&names, unread_time.as_ref());
        // the steps of a time column the config does not read (checked against
        // `sample_rate`, block by block)
        let mut steps = Steps::default();
        let mut roles = [false; 7];
        spans.iter().for_each(|&(r, _)| roles[r] = true);
        let temporary = |source| {
            Error::Data(DataError::Temporary {
                dir: std::env::temp_dir(),
                source,
            })
        };
        let mut spill = BufWriter::with_capacity(1 << 20, tempfile::tempfile().map_err(temporary)?);
        let mut chunks = Vec::new();
        let mut offset = 0u64;
        let mut digits = Vec::new();
        let mut clock = Clock::default();
        let mut scan = SamplingScan::new(spans.len() * dof);
        let mut extremes = Extremes::default();
        let mut unwrap = Unwrap::new(config, dof);
        // the sample time only matters at the end: windows are checked at the config's rate
        // or at 1 kHz, which the limits always allow
        let checked_at = config.sample_rate.map_or(1e-3, |fs| 1.0 / fs);
        let progress = Progress::new(
            config.progress,
            format!("identify: reading {}", path.display()),
            text_megabytes(path),
            "MB",
        );
        let mut megabytes = 0;
        for_each_window_of(path, &names, optional, window, |mut table, read| {
            let read = (read / 1_000_000) as u64;
            progress.add(read.saturating_sub(megabytes));
            megabytes = megabytes.max(read);
            if table.rows() == 0 {
                return Ok(());
            }
            check_ranges(&table, &names, &spans, dof)?;
            let time = take_time(config, &mut table)?;
            if unread_time.is_some() {
                steps.push(&table.columns.pop().unwrap_or_default(), &table.lines);
            }
            let mut columns = std::mem::take(&mut table.columns);
            // angles logged modulo a turn, unwrapped as `load` unwraps them
            unwrap.apply(&spans, &mut columns, &table.lines);
            // a step back between windows is an irregular step: such a file is then
            // loaded in memory, where `load` names the line
            if let Some(t) = &time {
                clock.push(t);
            }
            scan.push(time.as_deref(), &columns, Some(&table.lines));
            let mut blocks: [Option<Vec<Vec<f64>>>; 7] = Default::default();
            for &(role, start) in &spans {
                blocks[role] = Some(
                    columns[start..start + dof]
                        .iter_mut()
                        .map(std::mem::take)
                        .collect(),
                );
            }
            let lines = std::mem::take(&mut table.lines);
            let stamps = time.as_deref().unwrap_or_default();
            let start = chunks.last().map_or(0, |c: &Chunk| c.start + c.len);
            // each column's values as read (units and the drive chain are applied to each
            // block read, after the resampling of an irregular clock, as `load` applies
            // them), as their digits or the bytes they are in memory, written at once
            let mut out = Spill {
                file: &mut spill,
                offset: &mut offset,
                digits: &mut digits,
            };
            let mut stored = Vec::with_capacity(spans.len() * dof + 2);
            for x in blocks.iter().flatten().flatten() {
                stored.push(out.values(x).map_err(temporary)?);
            }
            stored.push(out.lines(&lines).map_err(temporary)?);
            if time.is_some() {
                stored.push(out.values(stamps).map_err(temporary)?);
            }
            chunks.push(Chunk {
                start,
                len: lines.len(),
                columns: stored,
                first_time: stamps.first().copied().unwrap_or_default(),
                last_time: stamps.last().copied().unwrap_or_default(),
            });
            // every value checked as `load` checks it, and the joint-side positions'
            // extremes kept
            let origin = DataOrigin {
                path: path.clone(),
                lines,
            };
            let window = assemble(
                config,
                dof,
                String::new(),
                checked_at,
                blocks,
                origin,
                Values::Check,
            )?;
            // the time stamps as read (scaled), else the config's rate
            let at = |k: usize| stamps.get(k).copied().unwrap_or(k as f64 * checked_at);
            let derivatives = [window.qd.as_ref(), window.qdd.as_ref()];
            extremes.widen(&window.q, derivatives, &window.tau, &at);
            Ok(())
        })?;
        progress.finish();
        let rows = chunks.last().map_or(0, |c| c.start + c.len);
        if rows < 2 {
            return Ok(None);
        }
        let first_stale = scan.first_stale_line();
        let sampling = scan.finish(path.clone());
        let mut warnings: Vec<Warning> = unwrap.warnings(path);
        warnings.extend(stale_warning(&sampling, first_stale));
        warnings.extend(slow_warning(&sampling, &spans));
        let mut grid = None;
        let sample_time = match (&config.time_column, config.sample_rate) {
            (Some(_), _) => {
                if clock.irregular() {
                    // a stamp going back between windows, or a gap: `load` names the line
                    let Some(steps) = sampling.steps() else {
                        return Ok(None);
                    };
                    if !clock.resamplable(steps.median) {
                        return Ok(None);
                    }
                    let resampled = clock.grid(&steps);
                    check_step(config, resampled.step, path)?;
                    warnings.push(clock.irregular_warning(&steps, &resampled, path));
                    grid = Some(resampled);
                    resampled.step
                } else {
                    let step = clock.mean_step();
                    check_step(config, step, path)?;
                    step
                }
            }
            (None, Some(fs)) => 1.0 / fs,
            (None, None) => return Ok(None),
        };
        if let Some(column) = &unread_time {
            check_rate(config, path, column, steps)?;
        }
        check_cutoff(config, sample_time)?;
        let spill = spill.into_inner().map_err(|e| temporary(e.into_error()))?;
        Ok(Some(Self {
            name: path
                .file_name()
                .map_or_else(String::new, |n| n.to_string_lossy().into_owned()),
            path: path.clone(),
            sample_time,
            dof,
            roles,
            chunks,
            rows,
            samples: grid.map_or(rows, |g| g.samples),
            grid,
            config: config.clone(),
            spill: Mutex::new(spill),
            warnings,
            sampling,
            extremes,
        }))
    }

    /// Appends `len` values at byte `at` of the temporary file to `out`.
    fn read_into<T: bytemuck::Pod>(
        file: &mut File,
        at: u64,
        len: usize,
        out: &mut Vec<T>,
    ) -> Result<()> {
        let old = out.len();
        out.resize(old + len, T::zeroed());
        file.seek(SeekFrom::Start(at))
            .and_then(|_| file.read_exact(bytemuck::cast_slice_mut(&mut out[old..])))
            .map_err(|source| {
                Error::Data(DataError::Temporary {
                    dir: std::env::temp_dir(),
                    source,
                })
            })
    }

    /// The `len` bytes at byte `at` of the temporary file, read into `scratch` (grown,
    /// and so zeroed, only when it is shorter: one buffer serves every column of a block).
    fn read_bytes<'s>(
        file: &mut File,
        at: u64,
        len: usize,
        scratch: &'s mut Vec<u8>,
    ) -> Result<&'s [u8]> {
        if scratch.len() < len {
            scratch.resize(len, 0);
        }
        file.seek(SeekFrom::Start(at))
            .and_then(|_| file.read_exact(&mut scratch[..len]))
            .map_err(|source| {
                Error::Data(DataError::Temporary {
                    dir: std::env::temp_dir(),
                    source,
                })
            })?;
        Ok(&scratch[..len])
    }

    /// The chunks holding samples `start..end`, with the part of each.
    fn parts(&self, start: usize, end: usize) -> impl Iterator<Item = (&Chunk, usize, usize)> {
        let first = self.chunks.partition_point(|c| c.start + c.len <= start);
        self.chunks[first..]
            .iter()
            .take_while(move |c| c.start < end)
            .map(move |c| {
                (
                    c,
                    start.max(c.start) - c.start,
                    end.min(c.start + c.len) - c.start,
                )
            })
    }

    fn roles_kept(&self) -> usize {
        self.roles.iter().filter(|&&r| r).count()
    }

    /// Appends values `lo..hi` of column `column` of chunk `c` (see [`Chunk`]: the
    /// signals' columns, then the time stamps') to `out`.
    fn read_column(
        file: &mut File,
        c: &Chunk,
        column: usize,
        (lo, hi): (usize, usize),
        out: &mut Vec<f64>,
        scratch: &mut Vec<u8>,
    ) -> Result<()> {
        match c.columns[column] {
            Stored::Raw { at } => Self::read_into(file, at + 8 * lo as u64, hi - lo, out),
            Stored::Decimal { at, places } => {
                let digits = Self::read_bytes(file, at + 4 * lo as u64, 4 * (hi - lo), scratch)?;
                stored::values(digits, places, out);
                Ok(())
            }
            // only lines are stored so
            Stored::Consecutive { .. } => unreachable!("a column of values"),
        }
    }

    /// Appends lines `lo..hi` of chunk `c` to `out`.
    fn read_lines(
        &self,
        file: &mut File,
        c: &Chunk,
        (lo, hi): (usize, usize),
        out: &mut Vec<u64>,
    ) -> Result<()> {
        match c.columns[self.lines_column()] {
            Stored::Consecutive { first } => {
                out.extend((lo..hi).map(|k| first + k as u64));
                Ok(())
            }
            Stored::Raw { at } => Self::read_into(file, at + 8 * lo as u64, hi - lo, out),
            Stored::Decimal { .. } => unreachable!("lines are integers"),
        }
    }

    /// The signals of samples `start..end` as written (before any resampling), in the
    /// loader's roles, and their file lines when `lines` is given.
    fn read_samples(
        &self,
        file: &mut File,
        start: usize,
        end: usize,
        mut lines: Option<&mut Vec<u64>>,
    ) -> Result<[Option<Vec<Vec<f64>>>; 7]> {
        let mut blocks: [Option<Vec<Vec<f64>>>; 7] = Default::default();
        for (role, block) in blocks.iter_mut().enumerate() {
            if self.roles[role] {
                *block = Some(vec![Vec::with_capacity(end - start); self.dof]);
            }
        }
        let mut scratch = Vec::new();
        for (c, lo, hi) in self.parts(start, end) {
            for (column, x) in blocks.iter_mut().flatten().flatten().enumerate() {
                Self::read_column(file, c, column, (lo, hi), x, &mut scratch)?;
            }
            if let Some(lines) = lines.as_mut() {
                self.read_lines(file, c, (lo, hi), lines)?;
            }
        }
        Ok(blocks)
    }

    /// The column of a chunk that holds the file lines (after the signals).
    fn lines_column(&self) -> usize {
        self.roles_kept() * self.dof
    }

    /// The column of a chunk that holds the time stamps (after the signals and lines).
    fn stamps_column(&self) -> usize {
        self.lines_column() + 1
    }

    /// The time stamps of chunk `c`.
    fn stamps(&self, file: &mut File, c: &Chunk) -> Result<Vec<f64>> {
        let mut t = Vec::with_capacity(c.len);
        Self::read_column(
            file,
            c,
            self.stamps_column(),
            (0, c.len),
            &mut t,
            &mut Vec::new(),
        )?;
        Ok(t)
    }

    /// Samples `start..end` of `grid` (`load`'s grid, [`Clock::grid`]): each signal
    /// interpolated onto it from the rows around it, and, when `lines` is given, the line
    /// of the row nearest each sample ([`nearest_lines`], as `load` gives).
    fn resampled(
        &self,
        file: &mut File,
        grid: &Grid,
        start: usize,
        end: usize,
        lines: Option<&mut Vec<u64>>,
    ) -> Result<[Option<Vec<Vec<f64>>>; 7]> {
        let at = grid.times(start..end);
        let (a, b) = self.bracket(file, at[0], at[at.len() - 1])?;
        let mut rows = Vec::with_capacity(b + 1 - a);
        let mut blocks = self.read_samples(file, a, b + 1, Some(&mut rows))?;
        let mut t = Vec::with_capacity(b + 1 - a);
        for (c, lo, hi) in self.parts(a, b + 1) {
            Self::read_column(
                file,
                c,
                self.stamps_column(),
                (lo, hi),
                &mut t,
                &mut Vec::new(),
            )?;
        }
        for x in blocks.iter_mut().flatten().flatten() {
            *x = interpolate(&t, x, &at);
        }
        if let Some(lines) = lines {
            lines.extend(nearest_lines(&t, &rows, &at));
        }
        Ok(blocks)
    }

    /// The samples `a..=b` whose stamps bracket the times `s0..=s1` as [`interpolate`]
    /// brackets them over the whole record: `a` the last sample stamped before `s0` (the
    /// first sample when none is), `b` the first stamped after `s1` (the last when none
    /// is). Between them, every time of `s0..=s1` falls between the same two stamps as
    /// in the whole record, and only at the record's ends is a value held.
    fn bracket(&self, file: &mut File, s0: f64, s1: f64) -> Result<(usize, usize)> {
        let before = self.chunks.partition_point(|c| c.first_time < s0);
        let a = match before.checked_sub(1) {
            None => 0,
            Some(i) => {
                let c = &self.chunks[i];
                c.start + self.stamps(file, c)?.partition_point(|&t| t < s0) - 1
            }
        };
        let after = self.chunks.partition_point(|c| c.last_time <= s1);
        let b = match self.chunks.get(after) {
            None => self.rows - 1,
            Some(c) => c.start + self.stamps(file, c)?.partition_point(|&t| t <= s1),
        };
        Ok((a, b))
    }
}

/// The temporary file being written, the bytes written so far, and a buffer for a
/// column's digits.
struct Spill<'a> {
    file: &'a mut BufWriter<File>,
    offset: &'a mut u64,
    digits: &'a mut Vec<i32>,
}

impl Spill<'_> {
    /// Writes `bytes`, returning where they start.
    fn write(&mut self, bytes: &[u8]) -> std::io::Result<u64> {
        let at = *self.offset;
        self.file.write_all(bytes)?;
        *self.offset += bytes.len() as u64;
        Ok(at)
    }

    /// Writes a column of values: its digits when they give them back, else their bytes.
    fn values(&mut self, x: &[f64]) -> std::io::Result<Stored> {
        match stored::digits(x, self.digits) {
            Some(places) => {
                let digits = std::mem::take(self.digits);
                let at = self.write(bytemuck::cast_slice::<i32, u8>(&digits));
                *self.digits = digits;
                Ok(Stored::Decimal { at: at?, places })
            }
            None => Ok(Stored::Raw {
                at: self.write(bytemuck::cast_slice::<f64, u8>(x))?,
            }),
        }
    }

    /// Writes a column of file lines: nothing when they follow each other.
    fn lines(&mut self, lines: &[u64]) -> std::io::Result<Stored> {
        Ok(match stored::consecutive(lines) {
            Some(first) => Stored::Consecutive { first },
            None => Stored::Raw {
                at: self.write(bytemuck::cast_slice::<u64, u8>(lines))?,
            },
        })
    }
}

/// The megabytes (1e6 bytes) of text in the file at `path`: its size when it is not
/// compressed, else 0 (not known before it is read: [`Progress`] then counts without a
/// total).
fn text_megabytes(path: &Path) -> u64 {
    if crate::data::table::not_a_stream(path).is_err() {
        return 0;
    }
    let mut magic = [0u8; 2];
    let gzip = File::open(path)
        .and_then(|mut f| f.read_exact(&mut magic))
        .is_ok_and(|()| magic == [0x1f, 0x8b]);
    match std::fs::metadata(path) {
        Ok(m) if !gzip => m.len().div_ceil(1_000_000),
        _ => 0,
    }
}

impl Record for SpilledRecord {
    fn name(&self) -> &str {
        &self.name
    }

    fn sample_time(&self) -> f64 {
        self.sample_time
    }

    fn samples(&self) -> usize {
        self.samples
    }

    fn dof(&self) -> usize {
        self.dof
    }

    fn warnings(&self) -> &[Warning] {
        &self.warnings
    }

    fn file(&self) -> Option<&Path> {
        Some(&self.path)
    }

    fn extremes(&self) -> &Extremes {
        &self.extremes
    }

    fn line(&self, k: usize) -> Option<u64> {
        if k >= self.samples {
            return None;
        }
        let mut file = self.spill.lock().ok()?;
        let mut line = Vec::with_capacity(1);
        match self.grid {
            None => {
                let (c, lo, _) = self.parts(k, k + 1).next()?;
                self.read_lines(&mut file, c, (lo, lo + 1), &mut line)
                    .ok()?;
            }
            Some(grid) => {
                self.resampled(&mut file, &grid, k, k + 1, Some(&mut line))
                    .ok()?;
            }
        }
        line.first().copied()
    }

    fn read(&self, start: usize, end: usize) -> Result<Cow<'_, Dataset>> {
        let end = end.min(self.samples);
        if start >= end {
            return Err(empty_range(&self.name, start, end));
        }
        let mut file = self.spill.lock().map_err(|_| {
            Error::setting(
                "SpilledRecord",
                "read",
                "an earlier read panicked; load the record again".to_string(),
            )
        })?;
        let mut lines = Vec::with_capacity(end - start);
        // the samples as they were loaded are the values checked then: the same units and
        // drive chain give the same values, which are not checked again; resampled ones
        // are new values
        let (blocks, values) = match &self.grid {
            None => (
                self.read_samples(&mut file, start, end, Some(&mut lines))?,
                Values::Checked,
            ),
            Some(grid) => (
                self.resampled(&mut file, grid, start, end, Some(&mut lines))?,
                Values::Check,
            ),
        };
        drop(file);
        let name = format!("{}[{start}..{end}]", self.name);
        let origin = DataOrigin {
            path: self.path.clone(),
            lines,
        };
        let data = assemble(
            &self.config,
            self.dof,
            name,
            self.sample_time,
            blocks,
            origin,
            values,
        )?;
        Ok(Cow::Owned(data))
    }
}

/// Loads like [`load`], keeping the samples in a temporary file when that is possible
/// (a [`SpilledRecord`]: one source, with `sample_rate` or time stamps that increase without a
/// gap, resampled as `load` resamples them when irregular) and in memory
/// otherwise. Every error is [`load`]'s: when the file cannot be kept on disk for any
/// reason, [`load`] reads it.
///
/// ```no_run
/// use robid_runtime::data::{Config, Record, load_record};
///
/// let config = Config::from_file(std::path::Path::new("identify.toml"))?;
/// let record = load_record(&config, &[], 6)?;
/// let first_second = record.read(0, (1.0 / record.sample_time()) as usize)?;
/// println!("{} samples; the first second: {:?}", record.samples(), first_second.q);
/// # Ok::<(), robid_runtime::Error>(())
/// ```
pub fn load_record(config: &Config, files: &[PathBuf], dof: usize) -> Result<Box<dyn Record>> {
    load_record_in(config, files, dof, WINDOW)
}

/// [`load_record`] with windows of `window` bytes of text.
pub(crate) fn load_record_in(
    config: &Config,
    files: &[PathBuf],
    dof: usize,
    window: usize,
) -> Result<Box<dyn Record>> {
    match SpilledRecord::open_in(config, files, dof, window) {
        Ok(Some(record)) => Ok(Box::new(record)),
        _ => Ok(Box::new(load(config, files, dof)?)),
    }
}

#[cfg(test)]
mod tests;
