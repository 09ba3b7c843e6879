//! Joint trajectories and simulated records, with their CSV form.
//!
//! A trajectory file has the header `t,q1..qn,qd1..qdn,qdd1..qddn`; a simulated record
//! adds `tau1..taun`. Signals are [`Signals`]: `q[j][k]` is joint j at sample k.

use crate::DataError;
use std::path::Path;

use crate::data::read_columns;
use crate::error::{Error, Result};
use crate::limits::Quantity;
use crate::signal::Signals;

/// Positions, velocities and accelerations on a time grid.
#[derive(Debug, Clone, PartialEq)]
pub struct Trajectory {
    /// Time stamps (s), increasing.
    pub t: Vec<f64>,
    /// Positions per joint.
    pub q: Signals,
    /// Velocities per joint.
    pub qd: Signals,
    /// Accelerations per joint.
    pub qdd: Signals,
}

/// A simulated (or measured) record: the trajectory followed and the joint torques.
#[derive(Debug, Clone, PartialEq)]
pub struct Record {
    /// What the joints did (as measured: with noise and quantization when simulated so).
    pub trajectory: Trajectory,
    /// Joint torques per joint.
    pub tau: Signals,
}

/// The end of the message about time stamps at a sample rate robid does not take (the
/// rule of identification data, `crate::data::check_sample_time`).
const TIME_FIX: &str = "`t` must be in seconds, at a rate identification takes (the data \
     simulated from it would be refused): convert it to seconds, or sample the trajectory at a \
     rate in that range";

/// The end of the message about a gap in a trajectory's time stamps: the data simulated
/// across it would be refused by identification.
const GAP_FIX: &str = "the data simulated from it would be refused: sample the trajectory \
     without the gap (robid excite writes one on a uniform grid), or split it at the gap into \
     two trajectories";

/// How far, in multiples of a joint's largest velocity magnitude, its accelerations
/// integrated from a trajectory's first sample may drift from its velocities' change
/// ([`Trajectory::check_derivatives`]). Loose: a true velocity never changes by more than
/// 2 of them, and the trapezoid's error on the coarsest designs `robid excite` writes
/// (`--method points` at two samples per piece: 3.97 on the Panda at 0.8 Hz, 2.7 on the
/// UR5e at 1 Hz; Fourier at 1.2 Hz 0.35) stays below 4; accelerations in degrees beside
/// velocities in radians drift by about 57 times the velocities' change.
pub const ACCELERATION_DRIFT: f64 = 10.0;

/// Header names `prefix1..prefixn`.
fn names(prefix: &str, n: usize) -> impl Iterator<Item = String> + '_ {
    (1..=n).map(move |j| format!("{prefix}{j}"))
}

impl Trajectory {
    /// An all-zero trajectory of `dof` joints on the time stamps `t`.
    pub fn zeros(dof: usize, t: Vec<f64>) -> Self {
        let n = t.len();
        Self {
            t,
            q: Signals::zeros(dof, n),
            qd: Signals::zeros(dof, n),
            qdd: Signals::zeros(dof, n),
        }
    }

    /// Number of joints.
    pub fn dof(&self) -> usize {
        self.q.dof()
    }

    /// Number of samples.
    pub fn samples(&self) -> usize {
        self.t.len()
    }

    /// Writes joint states of sample `k` into the three slices.
    pub fn state(&self, k: usize, q: &mut [f64], qd: &mut [f64], qdd: &mut [f64]) {
        self.q.sample_into(k, q);
        self.qd.sample_into(k, qd);
        self.qdd.sample_into(k, qdd);
    }

    /// The CSV header `t,q1..,qd1..,qdd1..`.
    pub fn header(dof: usize) -> Vec<String> {
        std::iter::once("t".to_string())
            .chain(names("q", dof))
            .chain(names("qd", dof))
            .chain(names("qdd", dof))
            .collect()
    }

    /// Reads a trajectory CSV of `dof` joints (header `t,q1..,qd1..,qdd1..`, any column order,
    /// extra columns ignored); time must increase and there must be at least 2 samples,
    /// whose mean step gives a sample rate that identification takes (the loader's rule,
    /// [`crate::limits::MIN_SAMPLE_RATE`] to [`crate::limits::MAX_SAMPLE_RATE`]).
    /// Every value must lie within the range of its quantity ([`crate::limits`]); an error
    /// names the file, line and column.
    pub fn read_csv(path: &Path, dof: usize) -> Result<Self> {
        crate::data::check_joints(dof)?;
        let header = Self::header(dof);
        let mut table = read_columns(path, &header)
            .map_err(|e| crate::data::header_needed(e, "t,q1..qn,qd1..qdn,qdd1..qddn".into()))?;
        for (i, name) in header.iter().enumerate() {
            let quantity = match i {
                0 => Quantity::Time,
                i if i <= dof => Quantity::Position,
                i if i <= 2 * dof => Quantity::Velocity,
                _ => Quantity::Acceleration,
            };
            table.check_range(i, name, quantity)?;
        }
        let mut cols = std::mem::take(&mut table.columns).into_iter();
        let t = cols.next().unwrap_or_default();
        if t.len() < 2 {
            return Err(Error::TooFewSamples {
                context: path.display().to_string(),
                found: t.len(),
                required: 2,
                hint: "a trajectory needs at least two time stamps",
            });
        }
        crate::data::check_monotonic(&t, &table.lines, path)?;
        crate::data::check_time_stamps(&t, || path.display().to_string(), TIME_FIX)?;
        crate::data::check_gaps(&t, |k| table.location(k), GAP_FIX)?;
        let mut take = || Signals::new((0..dof).map(|_| cols.next().unwrap_or_default()).collect());
        let (q, qd, qdd) = (take()?, take()?, take()?);
        let trajectory = Self { t, q, qd, qdd };
        trajectory.check_derivatives(|k| table.location(k))?;
        Ok(trajectory)
    }

    /// Checks that each velocity column is the derivative of its position column: over
    /// every step the position must change by what its velocity integrates to (Hermite's
    /// rule with the accelerations, exact for cubics), within half the largest change the
    /// velocity allows in that step (`max |qd| dt / 2`), plus the precision of the values
    /// written (1e-6 of the position's magnitude, 1e-3 of its range: positions written to
    /// a few decimals). A reference that breaks this (a constant position beside a velocity
    /// of 1 rad/s; a 2 rad spike in one sample) was simulated without a word, the record's
    /// positions and velocities disagreeing.
    ///
    /// The accelerations are checked against the velocities over the whole record, not
    /// step by step: a design's seventh-order pieces sampled at two or three points each
    /// vary too much between samples for a rule without the jerk (`robid excite --method
    /// points` writes such files). From the first sample on, the accelerations integrated
    /// by the trapezoid must not drift from the velocities' change by more than
    /// [`ACCELERATION_DRIFT`] times the velocity's largest magnitude (plus 1e-6 of it and
    /// 1e-6, the values' precision): a velocity cannot change by more than twice that, and
    /// the trapezoid's error on the coarsest points design robid writes stays below 4 of
    /// them. A reference whose `qdd4` was a constant -1e6 beside moderate positions and
    /// velocities was simulated for minutes into a log of 1e4 A currents with exit 0.
    /// `at` names sample k in the error.
    ///
    /// # Errors
    /// [`Error::DimensionMismatch`] when `q`, `qd` or `qdd` do not hold one sample per
    /// time stamp for every joint; [`DataError::InconsistentDerivative`] as above.
    pub fn check_derivatives(&self, at: impl Fn(usize) -> String) -> Result<()> {
        // the fields are public: a block shorter than `t` was indexed out of bounds
        self.check_shapes("Trajectory::check_derivatives")?;
        let largest = |v: &[f64]| v.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        for j in 0..self.dof() {
            let (q, qd, qdd) = (&self.q[j], &self.qd[j], &self.qdd[j]);
            let bound = 0.5 * largest(qd);
            let lowest = q.iter().fold(f64::INFINITY, |m, x| m.min(*x));
            let range = q.iter().fold(f64::NEG_INFINITY, |m, x| m.max(*x)) - lowest;
            let integral = |k: usize| {
                let dt = self.t[k] - self.t[k - 1];
                0.5 * (qd[k - 1] + qd[k]) * dt + (qdd[k - 1] - qdd[k]) * dt * dt / 12.0
            };
            let bad = (1..self.samples()).find(|&k| {
                let dt = self.t[k] - self.t[k - 1];
                let precision = 1e-6 * (1.0 + q[k].abs()) + 1e-3 * range;
                (q[k] - q[k - 1] - integral(k)).abs() > bound * dt + precision
            });
            if let Some(k) = bad {
                // the ratio over the whole record names a unit slip, not one step's; by the
                // trapezoid, as the accelerations' term grows with the square of a wrong
                // time unit
                let (moved, integrated) = (1..self.samples()).fold((0.0, 0.0), |(m, i), k| {
                    let dt = self.t[k] - self.t[k - 1];
                    let trapezoid = 0.5 * (qd[k - 1] + qd[k]) * dt;
                    (m + (q[k] - q[k - 1]).abs(), i + trapezoid.abs())
                });
                return Err(Error::Data(DataError::InconsistentDerivative {
                    location: at(k),
                    joint: j + 1,
                    from: self.t[k - 1],
                    change: q[k] - q[k - 1],
                    integral: integral(k),
                    ratio: moved / integrated,
                }));
            }
        }
        for j in 0..self.dof() {
            self.check_accelerations(j, &at)?;
        }
        Ok(())
    }

    /// The accelerations of joint `j` against its velocities over the record
    /// ([`Trajectory::check_derivatives`]).
    fn check_accelerations(&self, j: usize, at: impl Fn(usize) -> String) -> Result<()> {
        let (qd, qdd) = (&self.qd[j], &self.qdd[j]);
        let largest = qd.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        let allowed = ACCELERATION_DRIFT * largest + 1e-6 * (1.0 + largest);
        let trapezoid = |k: usize| 0.5 * (qdd[k - 1] + qdd[k]) * (self.t[k] - self.t[k - 1]);
        let mut integral = 0.0;
        for k in 1..self.samples() {
            integral += trapezoid(k);
            let change = qd[k] - qd[0];
            // `!(<=)`: a sum that overflowed to infinity or NaN is refused too
            if !((integral - change).abs() <= allowed) {
                // the ratio over the whole record names a unit slip
                let (changed, integrated) = (1..self.samples()).fold((0.0, 0.0), |(c, i), k| {
                    (c + (qd[k] - qd[k - 1]).abs(), i + trapezoid(k).abs())
                });
                return Err(Error::Data(DataError::InconsistentAcceleration {
                    location: at(k),
                    joint: j + 1,
                    from: self.t[0],
                    to: self.t[k],
                    integral,
                    change,
                    largest,
                    ratio: changed / integrated,
                }));
            }
        }
        Ok(())
    }

    /// Checks that every value is finite (a result about to be returned); `owner` names the
    /// function in the error.
    pub(crate) fn check_finite(&self, owner: &str) -> Result<()> {
        let bad = [&self.q, &self.qd, &self.qdd]
            .iter()
            .any(|x| x.first_non_finite().is_some())
            || self.t.iter().any(|x| !x.is_finite());
        if bad {
            return Err(Error::NonFiniteResult {
                what: format!("the trajectory of {owner}"),
                cause: "its coefficients overflowed; check the design's limits and settings".into(),
            });
        }
        Ok(())
    }

    /// Checks that `q`, `qd` and `qdd` (public fields) have one joint each per joint and
    /// one sample each per time stamp; `what` names the trajectory in the error.
    fn check_shapes(&self, what: &str) -> Result<()> {
        let n = self.samples();
        for (name, block) in [("q", &self.q), ("qd", &self.qd), ("qdd", &self.qdd)] {
            if block.dof() != self.dof() {
                return Err(Error::DimensionMismatch {
                    what: format!("{what}: joints of the `{name}` signals"),
                    expected: self.dof(),
                    found: block.dof(),
                });
            }
            if block.dof() > 0 && block.samples() != n {
                return Err(Error::DimensionMismatch {
                    what: format!("{what}: samples of the `{name}` signals (one per time stamp)"),
                    expected: n,
                    found: block.samples(),
                });
            }
        }
        Ok(())
    }

    /// Checks a trajectory given as input: shapes consistent, time increasing at a sample
    /// rate that identification takes (as [`Trajectory::read_csv`]), every value
    /// finite and within the range of its quantity ([`crate::limits`]). `what` names it in
    /// errors, which give the sample and its time.
    pub fn check(&self, what: &str) -> Result<()> {
        self.check_shapes(what)?;
        let n = self.samples();
        if n < 2 {
            return Err(Error::TooFewSamples {
                context: what.to_string(),
                found: n,
                required: 2,
                hint: "a trajectory needs at least two time stamps",
            });
        }
        let at = |k: usize| format!("{what}, sample {k} (t = {})", crate::Num(self.t[k]));
        if let Some(k) = Quantity::Time.first_outside(&self.t) {
            return Err(Error::Data(DataError::OutOfRange {
                location: format!("{what}, sample {k}"),
                what: "time".into(),
                quantity: "time",
                value: self.t[k],
                limit: Quantity::Time.limit(),
                lower: Quantity::Time.lower(),
            }));
        }
        if let Some(k) = (1..n).find(|&k| self.t[k] <= self.t[k - 1]) {
            return Err(Error::setting(
                "Trajectory",
                "t",
                format!(
                    "{}: time does not increase (previous {})",
                    at(k),
                    crate::Num(self.t[k - 1])
                ),
            ));
        }
        crate::data::check_time_stamps(&self.t, || what.to_string(), TIME_FIX)?;
        crate::data::check_gaps(&self.t, at, GAP_FIX)?;
        for (name, block, quantity) in [
            ("q", &self.q, Quantity::Position),
            ("qd", &self.qd, Quantity::Velocity),
            ("qdd", &self.qdd, Quantity::Acceleration),
        ] {
            for (j, v) in block.joints().enumerate() {
                if let Some(k) = quantity.first_outside(v) {
                    return Err(Error::Data(DataError::OutOfRange {
                        location: at(k),
                        what: format!("{name}{}", j + 1),
                        quantity: quantity.name(),
                        value: v[k],
                        limit: quantity.limit(),
                        lower: quantity.lower(),
                    }));
                }
            }
        }
        Ok(())
    }

    /// Writes the trajectory as CSV.
    pub fn write_csv(&self, path: &Path) -> Result<()> {
        write_rows(path, Self::header(self.dof()), self.samples(), |k, row| {
            self.push_row(k, row)
        })
    }

    fn push_row(&self, k: usize, row: &mut Vec<f64>) {
        row.push(self.t[k]);
        for block in [&self.q, &self.qd, &self.qdd] {
            row.extend(block.joints().map(|v| v[k]));
        }
    }
}

impl Record {
    /// The CSV header `t,q1..,qd1..,qdd1..,tau1..`.
    pub fn header(dof: usize) -> Vec<String> {
        let mut h = Trajectory::header(dof);
        h.extend(names("tau", dof));
        h
    }

    /// Writes the record as CSV; a value beyond what robid's readers accept is refused
    /// first ([`crate::SimulateError::Unreadable`]), with nothing written.
    pub fn write_csv(&self, path: &Path) -> Result<()> {
        let n = self.trajectory.dof();
        let header = Self::header(n);
        let fill = |k: usize, row: &mut Vec<f64>| {
            self.trajectory.push_row(k, row);
            row.extend(self.tau.joints().map(|v| v[k]));
        };
        let quantities = column_quantities(
            n,
            &[
                Quantity::Position,
                Quantity::Velocity,
                Quantity::Acceleration,
                Quantity::Torque,
            ],
        );
        check_rows(
            path,
            &header,
            &quantities,
            self.trajectory.samples(),
            fill,
            |_| SIMULATED_FIX.to_string(),
        )?;
        write_rows(path, header, self.trajectory.samples(), fill)
    }

    /// Writes what a real log holds: every `every`-th sample of the time, the measured
    /// positions and the torques (`t,q1..,tau1..`), or with `currents` the motor currents
    /// `tau_j / currents[j]` (`t,q1..,i1..`; `currents` are the torque constants times
    /// the gear ratios, N m per A at the joint). No velocities or accelerations: who reads
    /// it must differentiate, as on real data.
    ///
    /// A value beyond what robid's readers accept is refused first
    /// ([`crate::SimulateError::Unreadable`]), with nothing written: a current is the
    /// torque over its torque per ampere, and a tiny one turns a torque the readers take
    /// into a current they refuse.
    pub fn write_log_csv(&self, path: &Path, every: usize, currents: Option<&[f64]>) -> Result<()> {
        let n = self.trajectory.dof();
        let every = every.max(1);
        let mut header = vec!["t".to_string()];
        header.extend(names("q", n));
        header.extend(names(if currents.is_some() { "i" } else { "tau" }, n));
        let rows = self.trajectory.samples().div_ceil(every);
        let fill = |r: usize, row: &mut Vec<f64>| {
            let k = r * every;
            row.push(self.trajectory.t[k]);
            row.extend(self.trajectory.q.joints().map(|v| v[k]));
            match currents {
                Some(c) => row.extend(self.tau.joints().zip(c).map(|(v, c)| v[k] / c)),
                None => row.extend(self.tau.joints().map(|v| v[k])),
            }
        };
        let quantities = column_quantities(n, &[Quantity::Position, Quantity::Torque]);
        check_rows(path, &header, &quantities, rows, fill, |column| {
            let j = column.checked_sub(1 + n).filter(|j| *j < n);
            match (currents, j) {
                (Some(c), Some(j)) => {
                    let largest = self.largest_torque(j, every);
                    format!(
                        "the torque of joint {} reaches {} N m (its noise included), over a \
                         torque per ampere of {} N m/A: give joint {} a torque per ampere of \
                         magnitude at least {} N m/A, or less torque noise",
                        j + 1,
                        crate::Num::rounded(largest, 4),
                        crate::Num(c[j]),
                        j + 1,
                        crate::Num::rounded(largest / Quantity::Torque.limit(), 3)
                    )
                }
                _ => SIMULATED_FIX.to_string(),
            }
        })?;
        write_rows(path, header, rows, fill)
    }

    /// The largest |torque| of joint `j` (0-based) over every `every`-th sample.
    pub fn largest_torque(&self, j: usize, every: usize) -> f64 {
        self.tau[j]
            .iter()
            .step_by(every.max(1))
            .fold(0.0, |m: f64, t| m.max(t.abs()))
    }

    /// The record as a data set for the identification pipeline (uniform sample time
    /// taken from the first two time stamps; velocities and accelerations included).
    pub fn dataset(&self, name: &str) -> Result<crate::data::Dataset> {
        let tr = &self.trajectory;
        let dt = tr.t.get(1).copied().unwrap_or(0.0) - tr.t.first().copied().unwrap_or(0.0);
        crate::data::Dataset::new(name, dt, tr.q.clone(), self.tau.clone())?
            .with_velocities(tr.qd.clone())?
            .with_accelerations(tr.qdd.clone())
    }
}

/// The fix of a simulated value beyond the readers' range that no setting of the writer
/// explains (a run checks its states and torques against the same limits).
const SIMULATED_FIX: &str = "the simulation produced it: check the parameters, the \
     reference and the noise settings";

/// The quantity of every column of a file `t` then, for each of `groups`, `n` joints.
pub(super) fn column_quantities(n: usize, groups: &[Quantity]) -> Vec<Quantity> {
    std::iter::once(Quantity::Time)
        .chain(groups.iter().flat_map(|q| std::iter::repeat_n(*q, n)))
        .collect()
}

/// Refuses the rows `fill` gives (as [`write_rows`] writes them to `path` under `header`)
/// at the first value beyond the range robid's readers accept for its column's quantity
/// (`quantities`, one per column): [`crate::SimulateError::Unreadable`] at the line the
/// file would hold it, with `fix(column)`. A file the readers refuse is no output: `identify`
/// read a current of -6.6e11 A that `simulate` had written with exit 0.
pub(super) fn check_rows(
    path: &Path,
    header: &[String],
    quantities: &[Quantity],
    rows: usize,
    mut fill: impl FnMut(usize, &mut Vec<f64>),
    fix: impl Fn(usize) -> String,
) -> Result<()> {
    let mut row = Vec::with_capacity(header.len());
    for r in 0..rows {
        row.clear();
        fill(r, &mut row);
        let outside = row
            .iter()
            .zip(quantities)
            .position(|(x, q)| !(x.abs() <= q.limit()));
        if let Some(c) = outside {
            let quantity = quantities[c];
            return Err(Error::Simulate(crate::SimulateError::Unreadable {
                path: path.to_path_buf(),
                line: r + 2,
                time: row[0],
                column: header[c].clone(),
                value: row[c],
                quantity: quantity.name(),
                limit: quantity.limit(),
                fix: fix(c),
            }));
        }
    }
    Ok(())
}

/// Writes `rows` rows that `fill` gives under `header` to `path` (atomically): the first
/// column, the time, in the shortest form that reads back as the same number (Rust's `{}`),
/// every other value to ten significant digits (`{:.9e}`). Ten digits of the time repeated
/// stamps that robid's readers refuse: Unix time stamps (1.7336e9 s) at 500 Hz, or 1e6 s
/// at 2 kHz, were written as runs of one value, and `robid identify` refused the log
/// ("time 1733600000 does not increase") that `simulate` had written with exit 0. Written
/// exactly, a time column is as increasing as the reference the run was given.
pub(super) fn write_rows(
    path: &Path,
    header: Vec<String>,
    rows: usize,
    mut fill: impl FnMut(usize, &mut Vec<f64>),
) -> Result<()> {
    use std::fmt::Write as _;
    crate::output::write_atomically(path, |w| {
        writeln!(w, "{}", header.join(","))?;
        let mut row = Vec::with_capacity(header.len());
        let mut line = String::new();
        for k in 0..rows {
            row.clear();
            fill(k, &mut row);
            line.clear();
            for (i, x) in row.iter().enumerate() {
                if i > 0 {
                    line.push(',');
                }
                // adding zero turns -0 into 0 (a velocity of -0 was written -0.000000000e0)
                if i == 0 {
                    let _ = write!(line, "{}", x + 0.0);
                } else {
                    let _ = write!(line, "{:.9e}", x + 0.0);
                }
            }
            writeln!(w, "{line}")?;
        }
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One joint along `q = sin(t)` at 100 Hz for 2 s, its derivatives exact.
    fn sine() -> Trajectory {
        let t: Vec<f64> = (0..200).map(|k| k as f64 / 100.0).collect();
        let signal = |f: fn(f64) -> f64| Signals::new(vec![t.iter().map(|&t| f(t)).collect()]);
        Trajectory {
            q: signal(f64::sin).unwrap(),
            qd: signal(f64::cos).unwrap(),
            qdd: signal(|t| -t.sin()).unwrap(),
            t,
        }
    }

    /// `qd` of 10 samples against `t` of 100 (public fields) panicked out of bounds,
    /// though the check returns Result (review 147).
    #[test]
    fn blocks_not_matching_the_time_stamps_are_refused_not_indexed() {
        let mut short = sine();
        short.qd = Signals::new(vec![vec![0.0; 10]]).unwrap();
        let e = problem(&short).unwrap();
        assert!(e.contains("samples of the `qd` signals"), "{e}");
        let mut wide = sine();
        wide.qdd = Signals::new(vec![vec![0.0; 200]; 2]).unwrap();
        let e = problem(&wide).unwrap();
        assert!(e.contains("joints of the `qdd` signals"), "{e}");
    }

    fn problem(trajectory: &Trajectory) -> Option<String> {
        let e = trajectory
            .check_derivatives(|k| format!("sample {k}"))
            .err()?;
        Some(e.to_string())
    }

    /// Positions and velocities that are each other's derivatives pass; a constant
    /// position beside a velocity and a one-sample spike are refused at the step, a unit
    /// named where the whole record's ratio tells it (and only then: minutes are not
    /// degrees); jitter at the values' precision, and accelerations that the velocities
    /// do not follow between samples (a design's pieces sampled at two points each), pass.
    #[test]
    fn positions_that_disagree_with_their_velocities_are_refused_at_the_step() {
        assert_eq!(problem(&sine()), None);
        let mut still = sine();
        still.q = Signals::new(vec![vec![0.0; 200]]).unwrap();
        let e = problem(&still).unwrap();
        assert!(
            e.starts_with("sample 1: q1 changes by 0 over the step from t = 0 s, while qd1")
                && e.contains("the positions and velocities disagree (a column in other units"),
            "{e}"
        );
        let mut spike = sine();
        spike.q[0][120] += 0.05;
        assert!(problem(&spike).unwrap().starts_with("sample 120: q1"));
        for (factor, told) in [
            (
                180.0 / std::f64::consts::PI,
                "velocities in degrees per second",
            ),
            (std::f64::consts::PI / 180.0, "positions in degrees"),
            (1e3, "is the time column in milliseconds"),
            (1.0 / 60.0, "is the time column in minutes"),
            (1.0 / 50.0, "a column in other units"),
        ] {
            let mut other = sine();
            for v in other.qd[0].iter_mut() {
                *v *= factor;
            }
            let e = problem(&other).unwrap();
            assert!(e.contains(told), "{factor}: {e}");
        }
        // within half of the largest step the velocity allows: a 1 mrad error passes, and
        // at rest a jitter at the precision of the values
        let mut noisy = sine();
        noisy.q[0][120] += 1e-3;
        assert_eq!(problem(&noisy), None);
        let mut rest = sine();
        rest.q = Signals::new(vec![
            (0..200).map(|k| 0.5 + 1e-9 * (k % 2) as f64).collect(),
        ])
        .unwrap();
        rest.qd = Signals::new(vec![vec![0.0; 200]]).unwrap();
        rest.qdd = Signals::new(vec![vec![0.0; 200]]).unwrap();
        assert_eq!(problem(&rest), None);
        let mut flat = sine();
        flat.qdd = Signals::new(vec![vec![0.0; 200]]).unwrap();
        assert_eq!(problem(&flat), None);
    }

    /// Accelerations whose integral from the first sample drifts from the velocities'
    /// change by more than ACCELERATION_DRIFT times the largest velocity are refused at
    /// the sample where it does, with the unit the record's ratio suggests: a constant
    /// -1e6 beside moderate positions and velocities at the first step, accelerations in
    /// degrees, a constant offset once its integral leaves the bound. Loose: an offset
    /// within the bound, a design's pieces sampled at two or three points each, and
    /// accelerations left at 0 (within the swing of the velocities) pass.
    #[test]
    fn accelerations_that_drift_from_their_velocities_are_refused() {
        let mut wild = sine();
        wild.qdd = Signals::new(vec![vec![-1e6; 200]]).unwrap();
        let e = problem(&wild).unwrap();
        assert!(
            e.starts_with(
                "sample 1: qdd1 integrates to -10000 from t = 0 s to t = 0.01 s, while qd1 \
                 changes by -4.99996e-5"
            ) && e.contains("disagree with the velocities, drifting from them by more than 10 times qd1's largest magnitude 1 (a column")
                && e.ends_with(
                    "give the accelerations as the time derivatives of the velocities \
                     (`robid excite` designs such trajectories)"
                ),
            "{e}"
        );
        let mut degrees = sine();
        degrees.qdd[0]
            .iter_mut()
            .for_each(|a| *a *= 180.0 / std::f64::consts::PI);
        let e = problem(&degrees).unwrap();
        assert!(
            e.contains("accelerations in degrees per second squared"),
            "{e}"
        );
        // an offset of 6 drifts by 6 t: beyond 10 (the largest velocity is 1) at t = 1.67 s
        for (offset, refused) in [(4.0, None), (6.0, Some("sample 167: qdd1"))] {
            let mut off = sine();
            off.qdd[0].iter_mut().for_each(|a| *a += offset);
            let e = problem(&off);
            match refused {
                None => assert_eq!(e, None),
                Some(start) => assert!(e.as_deref().unwrap().starts_with(start), "{e:?}"),
            }
        }
        // seventh-order pieces of 1 s and 1.5 s at 2 Hz: two and three samples each
        let knots = vec![vec![
            [0.1, 0.0, 0.0, 0.0],
            [0.8, 0.4, -1.0, 0.7],
            [-0.3, -0.2, 0.5, -0.4],
            [0.1, 0.0, 0.0, 0.0],
        ]];
        let points = crate::excite::Points::new(vec![0.0, 1.0, 2.5, 4.0], knots).unwrap();
        assert_eq!(problem(&points.sample(2.0).unwrap()), None);
    }

    /// A record whose currents (torque over torque per ampere) or torques lie beyond what
    /// robid's readers accept is refused at the first such row, naming its line, column and
    /// the readers' limit, and nothing is written; within the range it is written.
    #[test]
    fn values_the_readers_refuse_are_not_written() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("log.csv");
        let torque: Vec<f64> = (0..200).map(|k| 5.0 + k as f64).collect();
        let record = Record {
            trajectory: sine(),
            tau: Signals::new(vec![torque]).unwrap(),
        };
        // 5 + k N m over 1e-6 N m/A: beyond 1e7 A from k = 6 (line 8)
        let e = record
            .write_log_csv(&path, 1, Some(&[1e-6]))
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with(&format!(
                "{}:8: column `i1` would be 1.1e7 (t = 0.06 s), outside the range |torque| <= \
                 1e7 that robid's readers accept",
                path.display()
            )) && e
                .contains("give joint 1 a torque per ampere of magnitude at least 2.04e-5 N m/A"),
            "{e}"
        );
        assert!(!path.exists());
        // every other row: line 5 holds sample 6
        let e = record
            .write_log_csv(&path, 2, Some(&[1e-6]))
            .unwrap_err()
            .to_string();
        assert!(e.contains("log.csv:5: column `i1`"), "{e}");
        record.write_log_csv(&path, 1, Some(&[1e-4])).unwrap();
        std::fs::remove_file(&path).unwrap();
        let mut heavy = record.clone();
        heavy.tau[0][3] = -2e7;
        let e = heavy.write_csv(&path).unwrap_err().to_string();
        assert!(e.contains("log.csv:5: column `tau1` would be -2e7"), "{e}");
        assert!(!path.exists());
    }
}
