//! A loaded, joint-side, uniformly sampled data set.

use crate::DataError;
use std::path::PathBuf;

use crate::data::Warning;
use crate::data::agreement::{DerivativeAgreement, add_agreements};
use crate::data::speed::{SpeedHistogram, count_speeds};
use crate::error::{Error, Result};
use crate::limits::{MAX_JOINTS, Quantity, check_size};
use crate::signal::Signals;

/// The file a data set was read from and the line of each sample, for messages and
/// reports (when files were joined: the first file with a time column, or the first file).
/// After resampling of irregular time stamps, sample k is given the line of row k.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct DataOrigin {
    /// The file.
    pub path: PathBuf,
    /// 1-based file line of each sample.
    pub lines: Vec<u64>,
}

/// Whether the values given to a data set are checked against the ranges of
/// [`crate::limits`] as it is made (the joint counts and lengths always are).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Values {
    /// Each value finite and within the range of its quantity.
    Check,
    /// Taken as they are: the very values were checked before (a block read back from a
    /// record's temporary file, whose samples were checked as they were loaded).
    Checked,
}

/// Joint-side signals on a uniform time grid.
#[derive(Debug, Clone)]
pub struct Dataset {
    /// Name for reports (usually the first file's name).
    pub name: String,
    /// Sample time in seconds.
    pub sample_time: f64,
    /// Joint positions (rad or m).
    pub q: Signals,
    /// Joint velocities, when measured.
    pub qd: Option<Signals>,
    /// Joint accelerations, when measured.
    pub qdd: Option<Signals>,
    /// Joint torques (after torque constants and the drive chain).
    pub tau: Signals,
    /// Motor encoder positions reflected to the link side, for rotor compensation.
    pub motor: Option<Signals>,
    /// Drive temperatures (deg C), for the nonlinear rotor friction.
    pub temperature: Option<Signals>,
    /// Link-side joint torques from a joint-torque sensor (N m), for `robid friction`.
    pub joint_torque: Option<Signals>,
    /// What was repaired while loading.
    pub warnings: Vec<super::Warning>,
    /// How each file was sampled (empty for a data set built in code).
    pub sampling: Vec<super::Sampling>,
    /// The file and lines the samples come from (`None` for a data set built in code).
    pub origin: Option<DataOrigin>,
    /// Per joint the extremes of the positions and torques (joint side), gathered as the
    /// data were loaded ([`crate::data::load`]); empty for a data set built in code and
    /// for a slice. What `robid identify` compares with the description's limits.
    pub extremes: Extremes,
}

impl Dataset {
    /// A data set from positions and torques (the same joints and samples, finite values
    /// within the ranges of [`crate::limits`]).
    pub fn new(
        name: impl Into<String>,
        sample_time: f64,
        q: Signals,
        tau: Signals,
    ) -> Result<Self> {
        Self::new_at(name, sample_time, q, tau, None)
    }

    /// [`Dataset::new`] with the file and lines of the samples.
    pub fn new_at(
        name: impl Into<String>,
        sample_time: f64,
        q: Signals,
        tau: Signals,
        origin: Option<DataOrigin>,
    ) -> Result<Self> {
        Self::new_with(name, sample_time, q, tau, origin, Values::Check)
    }

    /// [`Dataset::new_at`], the values checked as `values` says.
    pub(crate) fn new_with(
        name: impl Into<String>,
        sample_time: f64,
        q: Signals,
        tau: Signals,
        origin: Option<DataOrigin>,
        values: Values,
    ) -> Result<Self> {
        let name = name.into();
        if !super::sample_time_accepted(sample_time) {
            return Err(Error::setting(
                "Dataset::new",
                "sample_time",
                format!(
                    "{name}: {} s gives a sample rate outside [{:e}, {:e}] Hz",
                    crate::error::num(sample_time),
                    crate::limits::MIN_SAMPLE_RATE,
                    crate::limits::MAX_SAMPLE_RATE
                ),
            ));
        }
        check_size(
            || format!("{name}: joints"),
            q.dof() as f64,
            MAX_JOINTS,
            "use a description with fewer joints",
        )?;
        let n = q.samples();
        let mut data = Self {
            name,
            sample_time,
            q: Signals::default(),
            qd: None,
            qdd: None,
            tau: Signals::default(),
            motor: None,
            temperature: None,
            joint_torque: None,
            warnings: Vec::<Warning>::new(),
            sampling: Vec::new(),
            origin,
            extremes: Extremes::default(),
        };
        let dof = q.dof();
        data.check_block("torque", Quantity::Torque, &tau, dof, n, values)?;
        data.check_block("position", Quantity::Position, &q, dof, n, values)?;
        data.q = q;
        data.tau = tau;
        Ok(data)
    }

    /// Where sample `k` is: `file:line` when the data came from a file, else the data
    /// set's name and the sample (0-based).
    pub fn location(&self, k: usize) -> String {
        super::Record::location(self, k)
    }

    /// Adds measured velocities.
    pub fn with_velocities(self, qd: Signals) -> Result<Self> {
        self.with_velocities_as(qd, Values::Check)
    }

    /// [`Dataset::with_velocities`], the values checked as `values` says.
    pub(crate) fn with_velocities_as(mut self, qd: Signals, values: Values) -> Result<Self> {
        self.check_block(
            "velocity",
            Quantity::Velocity,
            &qd,
            self.dof(),
            self.samples(),
            values,
        )?;
        self.qd = Some(qd);
        Ok(self)
    }

    /// Adds measured accelerations.
    pub fn with_accelerations(self, qdd: Signals) -> Result<Self> {
        self.with_accelerations_as(qdd, Values::Check)
    }

    /// [`Dataset::with_accelerations`], the values checked as `values` says.
    pub(crate) fn with_accelerations_as(mut self, qdd: Signals, values: Values) -> Result<Self> {
        self.check_block(
            "acceleration",
            Quantity::Acceleration,
            &qdd,
            self.dof(),
            self.samples(),
            values,
        )?;
        self.qdd = Some(qdd);
        Ok(self)
    }

    /// Adds motor encoder positions (link side).
    pub fn with_motor_positions(self, motor: Signals) -> Result<Self> {
        self.with_motor_positions_as(motor, Values::Check)
    }

    /// [`Dataset::with_motor_positions`], the values checked as `values` says.
    pub(crate) fn with_motor_positions_as(
        mut self,
        motor: Signals,
        values: Values,
    ) -> Result<Self> {
        self.check_block(
            "motor position",
            Quantity::Position,
            &motor,
            self.dof(),
            self.samples(),
            values,
        )?;
        self.motor = Some(motor);
        Ok(self)
    }

    /// Adds drive temperatures (deg C).
    pub fn with_temperatures(self, temperature: Signals) -> Result<Self> {
        self.with_temperatures_as(temperature, Values::Check)
    }

    /// [`Dataset::with_temperatures`], the values checked as `values` says.
    pub(crate) fn with_temperatures_as(
        mut self,
        temperature: Signals,
        values: Values,
    ) -> Result<Self> {
        self.check_block(
            "temperature",
            Quantity::Temperature,
            &temperature,
            self.dof(),
            self.samples(),
            values,
        )?;
        self.temperature = Some(temperature);
        Ok(self)
    }

    /// Adds link-side joint torques measured by a joint-torque sensor (N m).
    pub fn with_joint_torques(self, joint_torque: Signals) -> Result<Self> {
        self.with_joint_torques_as(joint_torque, Values::Check)
    }

    /// [`Dataset::with_joint_torques`], the values checked as `values` says.
    pub(crate) fn with_joint_torques_as(
        mut self,
        joint_torque: Signals,
        values: Values,
    ) -> Result<Self> {
        self.check_block(
            "joint torque",
            Quantity::Torque,
            &joint_torque,
            self.dof(),
            self.samples(),
            values,
        )?;
        self.joint_torque = Some(joint_torque);
        Ok(self)
    }

    /// Number of joints.
    pub fn dof(&self) -> usize {
        self.q.dof()
    }

    /// Number of samples.
    pub fn samples(&self) -> usize {
        self.q.samples()
    }

    /// The samples `start..end` (end clamped to the length).
    pub fn slice(&self, start: usize, end: usize) -> Result<Self> {
        let end = end.min(self.samples());
        if start >= end {
            return Err(empty_range(&self.name, start, end));
        }
        let cut = |v: &Signals| v.range(start..end);
        Ok(Self {
            name: format!("{}[{start}..{end}]", self.name),
            sample_time: self.sample_time,
            q: cut(&self.q),
            qd: self.qd.as_ref().map(cut),
            qdd: self.qdd.as_ref().map(cut),
            tau: cut(&self.tau),
            motor: self.motor.as_ref().map(cut),
            temperature: self.temperature.as_ref().map(cut),
            joint_torque: self.joint_torque.as_ref().map(cut),
            warnings: self.warnings.clone(),
            sampling: self.sampling.clone(),
            origin: self.origin.as_ref().map(|o| DataOrigin {
                path: o.path.clone(),
                lines: o.lines.get(start..end).unwrap_or_default().to_vec(),
            }),
            // the whole record's, not the slice's
            extremes: Extremes::default(),
        })
    }
}

/// Per joint the smallest and largest joint-side position (rad or m) and torque (N m or N,
/// after the drive chain) of a record, gathered by the loader as it read the samples (no
/// pass of its own over them): what the description's limits are checked against (data in
/// another unit, of another robot). Empty when the samples were not loaded from files.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Extremes {
    /// `[smallest, largest]` position per joint.
    pub position: Vec<[f64; 2]>,
    /// `[smallest, largest]` torque per joint.
    pub torque: Vec<[f64; 2]>,
    /// How fast each joint's positions move ([`SpeedHistogram`]), checked against the
    /// velocity limits (a wrong `time_scale`).
    pub speed: Vec<SpeedHistogram>,
    /// Whether each joint's velocity column is its positions' derivative
    /// ([`DerivativeAgreement`]); empty when the record has no velocity columns.
    pub velocity: Vec<DerivativeAgreement>,
    /// Whether each joint's acceleration column is its velocity column's derivative;
    /// empty when the record has no velocity or no acceleration columns.
    pub acceleration: Vec<DerivativeAgreement>,
}

impl Extremes {
    /// Widened to the positions `q` and torques `tau` of a block of the same joints,
    /// sample k at `time(k)` seconds (for the speeds).
    /// With the velocities `qd`, when the record has them, their agreement with `q`, and
    /// with the accelerations `qdd` too, theirs with `qd`.
    pub(crate) fn widen(
        &mut self,
        q: &Signals,
        [qd, qdd]: [Option<&Signals>; 2],
        tau: &Signals,
        time: &dyn Fn(usize) -> f64,
    ) {
        for (ranges, x) in [(&mut self.position, q), (&mut self.torque, tau)] {
            ranges.resize(x.dof(), [f64::INFINITY, f64::NEG_INFINITY]);
            for (r, [lo, hi]) in ranges.iter_mut().zip(x.extremes()) {
                *r = [r[0].min(lo), r[1].max(hi)];
            }
        }
        count_speeds(&mut self.speed, q, time);
        if let Some(qd) = qd {
            add_agreements(&mut self.velocity, q, qd, time);
            if let Some(qdd) = qdd {
                add_agreements(&mut self.acceleration, qd, qdd, time);
            }
        }
    }

    /// Widened to `other`'s extremes (those of another part of the same record).
    pub fn join(&mut self, other: &Extremes) {
        for (mine, theirs) in [
            (&mut self.position, &other.position),
            (&mut self.torque, &other.torque),
        ] {
            let joints = mine.len().max(theirs.len());
            mine.resize(joints, [f64::INFINITY, f64::NEG_INFINITY]);
            for (a, b) in mine.iter_mut().zip(theirs) {
                *a = [a[0].min(b[0]), a[1].max(b[1])];
            }
        }
        self.speed.resize(
            self.speed.len().max(other.speed.len()),
            SpeedHistogram::default(),
        );
        for (a, b) in self.speed.iter_mut().zip(&other.speed) {
            a.join(b);
        }
        for (mine, theirs) in [
            (&mut self.velocity, &other.velocity),
            (&mut self.acceleration, &other.acceleration),
        ] {
            mine.resize(mine.len().max(theirs.len()), DerivativeAgreement::default());
            for (a, b) in mine.iter_mut().zip(theirs) {
                a.join(b);
            }
        }
    }
}

/// The error for the samples `start..end` of the data named `name`, which hold none.
pub(crate) fn empty_range(name: &str, start: usize, end: usize) -> Error {
    Error::TooFewSamples {
        context: format!("{name} rows {start}..{end}"),
        found: 0,
        required: 1,
        hint: "choose a range inside the data",
    }
}

impl Dataset {
    /// Checks a block of signals: `dof` joints of `n` samples, each value finite and within
    /// the range of `quantity` (unless `values` says they were checked); errors name the
    /// file line when known.
    fn check_block(
        &self,
        what: &str,
        quantity: Quantity,
        x: &Signals,
        dof: usize,
        n: usize,
        values: Values,
    ) -> Result<()> {
        let name = &self.name;
        if x.dof() != dof {
            return Err(Error::Data(DataError::JointCountMismatch {
                context: format!("{name}: {what} signals"),
                expected: dof,
                found: x.dof(),
            }));
        }
        if x.samples() != n && dof > 0 {
            return Err(Error::DimensionMismatch {
                what: format!("{name}: samples of the {what} signals"),
                expected: n,
                found: x.samples(),
            });
        }
        if values == Values::Checked {
            return Ok(());
        }
        for (j, v) in x.joints().enumerate() {
            if let Some(k) = first_outside(quantity, v) {
                let what = format!("joint {} {what} (after units and drive chain)", j + 1);
                return Err(if v[k].is_finite() {
                    Error::Data(DataError::OutOfRange {
                        location: self.location(k),
                        what,
                        quantity: quantity.name(),
                        value: v[k],
                        limit: quantity.limit(),
                        lower: quantity.lower(),
                    })
                } else {
                    let at = self
                        .origin
                        .as_ref()
                        .and_then(|o| Some((o.path.clone(), *o.lines.get(k)?)));
                    let (path, line) = at.unwrap_or_else(|| (name.into(), k as u64));
                    Error::Data(DataError::NotFinite {
                        path,
                        line,
                        column: what,
                        value: v[k],
                        text: None,
                    })
                });
            }
        }
        Ok(())
    }
}

/// [`Quantity::first_outside`], every value inside the range (the common case: each
/// column of every window loaded and of every block read back is checked) found first by
/// one pass without an early exit, which the compiler vectorises.
pub(crate) fn first_outside(quantity: Quantity, values: &[f64]) -> Option<usize> {
    let (lower, limit) = (quantity.lower(), quantity.limit());
    let outside = values
        .iter()
        .fold(false, |any, &v| any | !(lower <= v && v <= limit));
    if outside {
        quantity.first_outside(values)
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn s(joints: Vec<Vec<f64>>) -> Signals {
        Signals::new(joints).unwrap()
    }

    /// `first_outside` is `Quantity::first_outside`: the first value beyond the limit, NaN
    /// or infinite, wherever it is; the limit itself is inside.
    #[test]
    fn first_outside_is_the_quantitys() {
        for quantity in [Quantity::Position, Quantity::Torque, Quantity::Time] {
            let limit = quantity.limit();
            let odd = [
                limit,
                -limit,
                limit * (1.0 + f64::EPSILON),
                -limit * (1.0 + f64::EPSILON),
                f64::NAN,
                f64::INFINITY,
                f64::NEG_INFINITY,
                0.5,
            ];
            for x in odd {
                for len in [1, 3, 17] {
                    for at in 0..len {
                        let mut v = vec![-0.25; len];
                        v[at] = x;
                        if len > 2 && at + 1 < len {
                            v[len - 1] = f64::NAN;
                        }
                        assert_eq!(
                            first_outside(quantity, &v),
                            quantity.first_outside(&v),
                            "{x} at {at} of {len}"
                        );
                    }
                }
            }
        }
        assert_eq!(first_outside(Quantity::Torque, &[]), None);
    }

    #[test]
    fn checks_shapes_and_values() {
        let d = Dataset::new(
            "m",
            0.01,
            s(vec![vec![0.0; 5]; 2]),
            s(vec![vec![1.0; 5]; 2]),
        )
        .unwrap();
        assert_eq!((d.dof(), d.samples()), (2, 5));
        assert!(matches!(
            d.clone().with_velocities(s(vec![vec![0.0; 5]; 3])),
            Err(Error::Data(DataError::JointCountMismatch { .. }))
        ));
        assert!(matches!(
            d.clone().with_accelerations(s(vec![vec![0.0; 4]; 2])),
            Err(Error::DimensionMismatch { .. })
        ));
        assert!(matches!(
            Dataset::new("m", 0.01, s(vec![vec![f64::NAN]]), s(vec![vec![0.0]])),
            Err(Error::Data(DataError::NotFinite { .. }))
        ));
        assert!(Dataset::new("m", 0.0, s(vec![vec![0.0]]), s(vec![vec![0.0]])).is_err());
        let e =
            Dataset::new("m", 0.01, s(vec![vec![0.0, 2e6]]), s(vec![vec![0.0; 2]])).unwrap_err();
        assert!(
            matches!(e, Error::Data(DataError::OutOfRange { ref location, .. }) if location == "data set `m`, sample 1"),
            "{e}"
        );
        let e = Dataset::new_at(
            "m",
            0.01,
            s(vec![vec![0.0; 2]]),
            s(vec![vec![0.0, 1e300]]),
            Some(DataOrigin {
                path: "f.csv".into(),
                lines: vec![2, 3],
            }),
        )
        .unwrap_err();
        assert!(e.to_string().starts_with("f.csv:3: joint 1 torque"), "{e}");
        let s = d.slice(1, 3).unwrap();
        assert_eq!(s.samples(), 2);
        assert!(d.slice(4, 2).is_err());
    }

    /// Values made `Values::Checked` (a block read back from a record's temporary file,
    /// whose values were checked as they were loaded) are taken as they are; made
    /// `Values::Check`, the same values are refused; the joint counts and lengths are
    /// checked either way.
    #[test]
    fn values_checked_before_are_not_checked_again() {
        let q = || s(vec![vec![0.1, 0.2], vec![0.3, f64::NAN]]);
        let tau = || s(vec![vec![1.0, 2.0], vec![3.0, 4.0]]);
        let far = || s(vec![vec![1.0, 1e300], vec![3.0, 4.0]]);
        let made = |values| Dataset::new_with("d", 0.01, q(), tau(), None, values);
        assert!(made(Values::Check).is_err());
        let d = made(Values::Checked).unwrap();
        assert!(d.q[1][1].is_nan());
        assert!(d.clone().with_velocities_as(far(), Values::Check).is_err());
        let d = d.with_velocities_as(far(), Values::Checked).unwrap();
        assert_eq!(d.qd.as_ref().unwrap()[0][1], 1e300);
        let short = s(vec![vec![1.0], vec![3.0]]);
        assert!(
            d.clone()
                .with_accelerations_as(short, Values::Checked)
                .is_err()
        );
        let one = s(vec![vec![1.0, 2.0]]);
        assert!(d.with_joint_torques_as(one, Values::Checked).is_err());
    }
}
