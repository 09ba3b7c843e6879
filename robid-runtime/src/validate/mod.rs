//! Validation on data not used for estimation (docs/identification.md#validation-metrics):
//! relative error, RMS per joint, NMSE, improvement against a reference model; and
//! per-joint predictions.

mod metrics;

pub use metrics::{EQ22_ZERO, Fit, fit, relative_improvement};

use serde::{Deserialize, Serialize};

use crate::data::Record;
use crate::error::{Error, Result};
use crate::estimate::{Observation, QualityWarning};

/// Which rows of which file a fit or a validation used.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct UsedRows {
    /// The file (the first file of a joined data set), or the data set's name when it was
    /// not read from a file.
    pub file: String,
    /// The samples used, `[start, end)`, 0-based in the data set (after joining and
    /// resampling; ranges, trimming and filter settling applied).
    pub samples: [usize; 2],
    /// The 1-based file lines of the first and the last sample used, when read from a file.
    pub lines: Option<[u64; 2]>,
    /// The samples the equations were taken at, when they are not every sample of
    /// `samples` (a decimation takes every factor-th, and its filter's settling leaves a
    /// few out at each end); absent otherwise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub equations: Option<EquationSamples>,
}

/// The samples of a fit's equations: from `first` to `last` (0-based in the data set, as
/// [`UsedRows::samples`]), every `step`-th.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct EquationSamples {
    /// The first sample of an equation.
    pub first: usize,
    /// The last sample of an equation.
    pub last: usize,
    /// Samples from one equation's sample to the next (the decimation factor).
    pub step: usize,
    /// The 1-based file lines of `first` and `last`, when read from a file.
    pub lines: Option<[u64; 2]>,
}

impl UsedRows {
    /// The samples `range` of `data`.
    pub fn of(data: &dyn Record, range: std::ops::Range<usize>) -> UsedRows {
        let lines = data.file().and_then(|_| {
            let first = data.line(range.start)?;
            let last = data.line(range.end.checked_sub(1)?)?;
            Some([first, last])
        });
        UsedRows {
            file: data
                .file()
                .map_or_else(|| data.name().to_string(), |p| p.display().to_string()),
            samples: [range.start, range.end],
            lines,
            equations: None,
        }
    }

    /// The rows with the equations at samples `first` to `last` of `data`, every `step`-th
    /// (not said when they are every sample of the rows).
    pub(crate) fn with_equations(
        mut self,
        data: &dyn Record,
        first: usize,
        last: usize,
        step: usize,
    ) -> Self {
        let every = step == 1 && first == self.samples[0] && last + 1 == self.samples[1];
        if !every {
            let lines = data
                .file()
                .and_then(|_| Some([data.line(first)?, data.line(last)?]));
            self.equations = Some(EquationSamples {
                first,
                last,
                step,
                lines,
            });
        }
        self
    }

    /// Whether two uses share rows of the same file: the same name, or two names of one
    /// file (`data.csv` and `./data.csv`, an absolute path, a symbolic or hard link, found
    /// by [`crate::output::same_file`]).
    pub fn overlaps(&self, other: &UsedRows) -> bool {
        if self.file != other.file
            && !crate::output::same_file(
                std::path::Path::new(&self.file),
                std::path::Path::new(&other.file),
            )
        {
            return false;
        }
        match (self.lines, other.lines) {
            (Some(a), Some(b)) => a[0] <= b[1] && b[0] <= a[1],
            _ => self.samples[0] < other.samples[1] && other.samples[0] < self.samples[1],
        }
    }
}

impl std::fmt::Display for UsedRows {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.lines {
            Some([a, b]) => write!(
                f,
                "{} lines {a}-{b} (samples {}..{})",
                self.file, self.samples[0], self.samples[1]
            )?,
            None => write!(
                f,
                "{} samples {}..{}",
                self.file, self.samples[0], self.samples[1]
            )?,
        }
        if let Some(e) = &self.equations {
            write!(f, "; equations at samples {} to {}", e.first, e.last)?;
            if e.step > 1 {
                write!(f, ", every {}", ordinal(e.step))?;
            }
            if let Some([a, b]) = e.lines {
                write!(f, " (lines {a}-{b})")?;
            }
        }
        Ok(())
    }
}

/// Measured and predicted (filtered, decimated) torques per joint.
#[derive(Debug, Clone)]
pub struct Prediction {
    /// Measured torque per joint.
    pub measured: Vec<Vec<f64>>,
    /// Predicted torque per joint.
    pub predicted: Vec<Vec<f64>>,
    /// Time (s) of each entry per joint (samples near rest are absent).
    pub time: Vec<Vec<f64>>,
    /// The measured torque before any low-pass at the same samples, when `measured` is
    /// filtered (a low-pass on the torque or a decimation's anti-alias filter); `None`
    /// when `measured` is the torque as measured.
    pub unfiltered: Option<Vec<Vec<f64>>>,
    /// The rows of the data used, when known (set by the pipeline).
    pub used: Option<UsedRows>,
}

impl Prediction {
    /// Prediction W beta of an observation; `sample_time` is the decimated sample time.
    ///
    /// # Errors
    ///
    /// [`Error::DimensionMismatch`] when `beta` has not one entry per column of the
    /// observation; [`Error::Setting`] when `sample_time` is not positive and finite (a
    /// NaN made every time stamp NaN).
    pub fn new(obs: &Observation, beta: &[f64], sample_time: f64) -> Result<Self> {
        if beta.len() != obs.cols() {
            return Err(Error::DimensionMismatch {
                what: "the parameters of Prediction::new (one per column of the observation)"
                    .into(),
                expected: obs.cols(),
                found: beta.len(),
            });
        }
        Error::positive_and_finite(
            "Prediction::new",
            "sample_time",
            "the time between two equations' samples",
            sample_time,
            "s",
        )?;
        let b = nalgebra::DVector::from_column_slice(beta);
        let pred = &obs.w * b;
        let block = |v: &nalgebra::DVector<f64>| -> Vec<Vec<f64>> {
            obs.joint_rows
                .iter()
                .map(|r| v.rows(r.start, r.len()).iter().copied().collect())
                .collect()
        };
        let time = obs
            .joint_rows
            .iter()
            .map(|r| {
                obs.sample_of_row[r.clone()]
                    .iter()
                    .map(|&k| k as f64 * sample_time)
                    .collect()
            })
            .collect();
        Ok(Self {
            measured: block(&obs.y),
            predicted: block(&pred),
            time,
            unfiltered: None,
            used: None,
        })
    }

    /// Checks that every predicted torque and every metric is finite, and that the
    /// measured and predicted torques agree in joints and samples (as
    /// [`Prediction::new`] makes them); `what` names the data in the error.
    ///
    /// # Errors
    ///
    /// [`Error::DimensionMismatch`] for torques that differ in joints or samples
    /// ([`fit`]); [`Error::NonFiniteResult`] for a predicted torque or a metric that is
    /// not finite.
    pub fn check(&self, what: &str) -> Result<()> {
        let fit = fit(&self.measured, &self.predicted)?;
        if let Some((j, _)) = self
            .predicted
            .iter()
            .enumerate()
            .find(|(_, p)| p.iter().any(|v| !v.is_finite()))
        {
            return Err(Error::NonFiniteResult {
                what: format!("the predicted torque of joint {} on {what}", j + 1),
                cause: "the identified values times the regressor overflowed; check the data's units and outliers".into(),
            });
        }
        fit.check(what)
    }

    /// What the fit says about the estimate it comes from: a fit worse than no model, and
    /// joints without equations ([`QualityWarning::PoorFit`],
    /// [`QualityWarning::JointWithoutEquations`]).
    ///
    /// # Panics
    ///
    /// As [`fit`](Self::fit).
    pub fn warnings(&self) -> Vec<QualityWarning> {
        let mut out: Vec<QualityWarning> = self
            .measured
            .iter()
            .enumerate()
            .filter(|(_, m)| m.is_empty())
            .map(|(j, _)| QualityWarning::JointWithoutEquations { joint: j + 1 })
            .collect();
        let relative_error = self.fit().relative_error;
        if relative_error > 1.0 {
            out.push(QualityWarning::PoorFit { relative_error });
        }
        out
    }

    /// The prediction with its times moved by `start` seconds: the pipeline places them on
    /// the log's own time axis (from its first sample), not from the first sample used.
    pub fn starting_at(mut self, start: f64) -> Self {
        for t in &mut self.time {
            t.iter_mut().for_each(|v| *v += start);
        }
        self
    }

    /// The metrics of this prediction against `measured` (filtered when the processing
    /// filters the torque).
    ///
    /// # Panics
    ///
    /// When `measured` and `predicted` differ in joints or samples, which
    /// [`Prediction::new`] never gives: only fields edited by hand can (the pipeline and
    /// the reports, which take the fit of its predictions without a `Result`, rely on it;
    /// [`check`](Self::check) returns the error, and [`fit`] takes any torques).
    pub fn fit(&self) -> Fit {
        fit(&self.measured, &self.predicted).unwrap_or_else(|e| panic!("Prediction::fit: {e}"))
    }

    /// The metrics against the torque before any low-pass, when `measured` is filtered.
    ///
    /// # Panics
    ///
    /// When `unfiltered` and `predicted` differ in joints or samples (as [`fit`](Self::fit)).
    pub fn unfiltered_fit(&self) -> Option<Fit> {
        self.unfiltered.as_ref().map(|u| {
            fit(u, &self.predicted).unwrap_or_else(|e| panic!("Prediction::unfiltered_fit: {e}"))
        })
    }
}

/// `n` as an English ordinal: 1st, 2nd, 3rd, 4th, 11th, 12th, 13th, 21st, ...
fn ordinal(n: usize) -> String {
    let suffix = match (n % 10, n % 100) {
        (_, 11..=13) => "th",
        (1, _) => "st",
        (2, _) => "nd",
        (3, _) => "rd",
        _ => "th",
    };
    format!("{n}{suffix}")
}

#[cfg(test)]
mod tests {
    use super::{Prediction, UsedRows};

    /// A non-finite predicted torque is an error naming the joint; finite ones pass.
    #[test]
    fn check_refuses_a_non_finite_prediction() {
        let mut p = Prediction {
            measured: vec![vec![1.0, 2.0], vec![3.0, 4.0]],
            predicted: vec![vec![1.1, 2.1], vec![2.9, 4.2]],
            time: vec![vec![0.0, 0.1], vec![0.0, 0.1]],
            unfiltered: None,
            used: None,
        };
        assert!(p.check("run.csv").is_ok());
        p.predicted[1][0] = f64::INFINITY;
        let e = p.check("run.csv").unwrap_err().to_string();
        assert!(e.contains("joint 2") && e.contains("run.csv"), "{e}");
        // torques edited to differ in samples: an error, not a panic
        p.predicted[1].pop();
        let e = p.check("run.csv").unwrap_err().to_string();
        assert!(e.contains("joint 2") && e.contains("found 1"), "{e}");
    }

    /// A parameter vector of the wrong length, or a sample time that is not positive and
    /// finite, is an error (a panic in the product; NaN time stamps `check` passed).
    #[test]
    fn new_checks_the_parameters_and_the_sample_time() {
        use nalgebra::{DMatrix, DVector};
        let obs = crate::estimate::Observation::single(
            DMatrix::from_element(3, 2, 1.0),
            DVector::from_element(3, 2.0),
            vec!["a".into(), "b".into()],
        )
        .unwrap();
        let e = Prediction::new(&obs, &[1.0], 0.01).unwrap_err().to_string();
        assert!(e.contains("expected 2 entries, found 1"), "{e}");
        for dt in [f64::NAN, 0.0, -0.01, f64::INFINITY] {
            let e = Prediction::new(&obs, &[1.0, 1.0], dt)
                .unwrap_err()
                .to_string();
            assert!(e.contains("sample_time"), "{dt}: {e}");
        }
        let p = Prediction::new(&obs, &[1.0, 1.0], 0.01).unwrap();
        assert_eq!(p.time, [vec![0.0, 0.01, 0.02]]);
        assert!(p.check("run.csv").is_ok());
    }

    /// A fit worse than predicting zero, and a joint with no equation, are warned about;
    /// a good fit of every joint gives no warning.
    #[test]
    fn a_useless_fit_and_a_joint_without_equations_are_warned_about() {
        let kinds = |measured: Vec<Vec<f64>>, predicted: Vec<Vec<f64>>| {
            let time = measured.iter().map(|m| vec![0.0; m.len()]).collect();
            let p = Prediction {
                measured,
                predicted,
                time,
                unfiltered: None,
                used: None,
            };
            p.warnings().iter().map(|w| w.kind()).collect::<Vec<_>>()
        };
        let good = kinds(vec![vec![1.0, 2.0]; 2], vec![vec![1.1, 2.0]; 2]);
        assert!(good.is_empty(), "{good:?}");
        // exactly as bad as no model: not yet warned
        assert!(kinds(vec![vec![1.0, -1.0]], vec![vec![0.0, 0.0]]).is_empty());
        assert_eq!(
            kinds(vec![vec![1.0, -1.0]], vec![vec![-1.0, 1.0]]),
            ["poor_fit"]
        );
        let dropped = kinds(vec![vec![1.0, 2.0], vec![]], vec![vec![1.0, 2.0], vec![]]);
        assert_eq!(dropped, ["joint_without_equations"]);
    }

    fn rows(file: &str, samples: [usize; 2], lines: Option<[u64; 2]>) -> UsedRows {
        UsedRows {
            file: file.into(),
            samples,
            lines,
            equations: None,
        }
    }

    /// Sample ranges are half-open, line ranges closed; another file never overlaps.
    /// Two names of one file are one file: `./a.csv`, its absolute path, a symbolic and a
    /// hard link overlap `a.csv` (they were compared as strings and never did); a copy
    /// does not.
    #[test]
    fn overlaps_knows_a_file_under_another_name() {
        let dir = tempfile::tempdir().unwrap();
        let a = dir.path().join("a.csv");
        std::fs::write(&a, "t,q1\n0,0\n").unwrap();
        let copy = dir.path().join("copy.csv");
        std::fs::write(&copy, "t,q1\n0,0\n").unwrap();
        let dotted = dir.path().join(".").join("a.csv");
        let hard = dir.path().join("hard.csv");
        std::fs::hard_link(&a, &hard).unwrap();
        let mut names = vec![dotted, hard];
        #[cfg(unix)]
        {
            let soft = dir.path().join("soft.csv");
            std::os::unix::fs::symlink(&a, &soft).unwrap();
            names.push(soft);
        }
        let used = |p: &std::path::Path, samples| rows(&p.display().to_string(), samples, None);
        let estimation = used(&a, [0, 20]);
        for name in &names {
            assert!(
                used(name, [5, 10]).overlaps(&estimation),
                "{}",
                name.display()
            );
            assert!(
                estimation.overlaps(&used(name, [5, 10])),
                "{}",
                name.display()
            );
            assert!(
                !used(name, [20, 30]).overlaps(&estimation),
                "{}",
                name.display()
            );
        }
        assert!(!used(&copy, [5, 10]).overlaps(&estimation));
    }

    #[test]
    fn overlaps_is_sharing_a_row_of_the_same_file() {
        let a = rows("a.csv", [10, 20], None);
        for (other, expected) in [
            ([0, 10], false),
            ([0, 11], true),
            ([19, 30], true),
            ([20, 30], false),
            ([12, 15], true),
            ([0, 40], true),
        ] {
            let b = rows("a.csv", other, None);
            assert_eq!(a.overlaps(&b), expected, "{other:?}");
            assert_eq!(b.overlaps(&a), expected, "{other:?} (reversed)");
        }
        assert!(!a.overlaps(&rows("b.csv", [10, 20], None)));
        let l = rows("a.csv", [0, 1], Some([100, 200]));
        for (other, expected) in [
            ([50, 99], false),
            ([50, 100], true),
            ([200, 300], true),
            ([201, 300], false),
            ([120, 130], true),
        ] {
            let m = rows("a.csv", [5, 6], Some(other));
            assert_eq!(l.overlaps(&m), expected, "lines {other:?}");
            assert_eq!(m.overlaps(&l), expected, "lines {other:?} (reversed)");
        }
    }

    #[test]
    fn ordinals_are_english() {
        let said: Vec<String> = [1, 2, 3, 4, 10, 11, 12, 13, 21, 22, 23, 101, 111, 112]
            .into_iter()
            .map(super::ordinal)
            .collect();
        assert_eq!(
            said,
            [
                "1st", "2nd", "3rd", "4th", "10th", "11th", "12th", "13th", "21st", "22nd", "23rd",
                "101st", "111th", "112th"
            ]
        );
    }
}
