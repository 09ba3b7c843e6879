//! The stacked linear system y = W beta that the estimators solve.

use crate::EstimateError;
use std::ops::Range;

use nalgebra::{DMatrix, DVector};

use crate::error::{Error, Result};

/// Observation matrix W, measurement vector y, and how the rows are organised.
///
/// Rows are stacked joint-major: all equations of joint 1, then joint 2, ...
/// (`joint_rows[j]` is joint j's block); `sample_of_row` gives each row's (decimated)
/// sample index so that recursive estimators can run in time order.
#[derive(Debug, Clone)]
pub struct Observation {
    /// W (rows x parameters).
    pub w: DMatrix<f64>,
    /// y (rows).
    pub y: DVector<f64>,
    /// Row block of each joint (or of each equation group).
    pub joint_rows: Vec<Range<usize>>,
    /// Sample index of each row.
    pub sample_of_row: Vec<usize>,
    /// Parameter (column) names.
    pub names: Vec<String>,
    /// The sample indices that start a new segment (a run of stacked runs, a piece of
    /// `processing.pieces`), in increasing order: the residuals' correlation is not taken
    /// across them ([`RobustStd`](crate::estimate::RobustStd)). Empty: one segment.
    pub breaks: Vec<usize>,
    /// Samples over which the processing correlates the residuals (the low-pass's
    /// `sample rate / (decimation x cutoff)`; 0 when no filter says): the least lag of
    /// the robust standard deviations ([`robust_lag`](crate::estimate::robust_lag)).
    pub correlated: usize,
}

impl Observation {
    /// Builds and checks an observation: sizes consistent, values finite.
    pub fn new(
        w: DMatrix<f64>,
        y: DVector<f64>,
        joint_rows: Vec<Range<usize>>,
        sample_of_row: Vec<usize>,
        names: Vec<String>,
    ) -> Result<Self> {
        let dim = |what: &str, expected: usize, found: usize| Error::DimensionMismatch {
            what: what.into(),
            expected,
            found,
        };
        if y.len() != w.nrows() {
            return Err(dim("measurement vector y", w.nrows(), y.len()));
        }
        if names.len() != w.ncols() {
            return Err(dim("parameter names", w.ncols(), names.len()));
        }
        if sample_of_row.len() != w.nrows() {
            return Err(dim("sample index of rows", w.nrows(), sample_of_row.len()));
        }
        let covered: usize = joint_rows.iter().map(|r| r.len()).sum();
        if covered != w.nrows() || joint_rows.iter().any(|r| r.end > w.nrows()) {
            return Err(dim("rows covered by the joint blocks", w.nrows(), covered));
        }
        let bad_w = w.iter().position(|v| !v.is_finite());
        let bad_y = y.iter().position(|v| !v.is_finite());
        if bad_w.is_some() || bad_y.is_some() {
            let rows = w.nrows().max(1);
            let (row, parameter, value) = match (bad_w, bad_y) {
                (Some(i), _) => (i % rows, names[i / rows].clone(), w[(i % rows, i / rows)]),
                (None, Some(r)) => (r, "torque".to_string(), y[r]),
                _ => (0, String::new(), f64::NAN),
            };
            let joint = joint_rows
                .iter()
                .position(|b| b.contains(&row))
                .map_or(0, |j| j + 1);
            let sample = sample_of_row[row];
            return Err(Error::Estimate(EstimateError::NonFiniteObservation {
                location: format!("equation {} (sample {sample})", row + 1),
                sample: Some(sample),
                joint,
                parameter,
                value,
            }));
        }
        Ok(Self {
            w,
            y,
            joint_rows,
            sample_of_row,
            names,
            breaks: Vec::new(),
            correlated: 0,
        })
    }

    /// The segment of sample `k`: the number of [`breaks`](Self::breaks) at or before it.
    pub fn segment(&self, k: usize) -> usize {
        self.breaks.partition_point(|&b| b <= k)
    }

    /// The rows whose sample index satisfies `keep`, joint blocks and order kept.
    pub fn select_samples(&self, keep: impl Fn(usize) -> bool) -> Result<Self> {
        let rows: Vec<usize> = (0..self.rows())
            .filter(|&r| keep(self.sample_of_row[r]))
            .collect();
        let w = self.w.select_rows(rows.iter());
        let y = DVector::from_iterator(rows.len(), rows.iter().map(|&r| self.y[r]));
        let mut joint_rows = Vec::with_capacity(self.joint_rows.len());
        let mut start = 0;
        for block in &self.joint_rows {
            let count = rows.iter().filter(|r| block.contains(r)).count();
            joint_rows.push(start..start + count);
            start += count;
        }
        let sample_of_row = rows.iter().map(|&r| self.sample_of_row[r]).collect();
        let mut selected = Self::new(w, y, joint_rows, sample_of_row, self.names.clone())?;
        selected.breaks = self.breaks.clone();
        selected.correlated = self.correlated;
        Ok(selected)
    }

    /// A single-block observation (e.g. one equation per row with no joint structure).
    pub fn single(w: DMatrix<f64>, y: DVector<f64>, names: Vec<String>) -> Result<Self> {
        let n = w.nrows();
        Self::new(
            w,
            y,
            std::iter::once(0..n).collect(),
            (0..n).collect(),
            names,
        )
    }

    /// Number of equations.
    pub fn rows(&self) -> usize {
        self.w.nrows()
    }

    /// Number of parameters.
    pub fn cols(&self) -> usize {
        self.w.ncols()
    }

    /// RMS of y - W beta in each joint block.
    pub fn residual_rms(&self, beta: &DVector<f64>) -> Vec<f64> {
        let r = &self.y - &self.w * beta;
        self.joint_rows
            .iter()
            .map(|b| {
                if b.is_empty() {
                    0.0
                } else {
                    (r.rows(b.start, b.len()).norm_squared() / b.len() as f64).sqrt()
                }
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use nalgebra::{DMatrix, DVector};

    use super::Observation;

    /// A known answer: residuals (1, -1, 3) in joint 1's block and (2) in joint 2's give RMS
    /// sqrt(11 / 3) and 2; an empty block gives 0.
    #[test]
    fn residual_rms_is_per_joint_block() {
        let w = DMatrix::from_row_slice(4, 1, &[1.0, 2.0, 0.0, 1.0]);
        let y = DVector::from_vec(vec![2.0, 1.0, 3.0, 3.0]);
        let o = Observation::new(
            w,
            y,
            vec![0..3, 3..4, 4..4],
            vec![0, 1, 2, 0],
            vec!["a".into()],
        )
        .unwrap();
        let rms = o.residual_rms(&DVector::from_vec(vec![1.0]));
        assert!((rms[0] - (11.0f64 / 3.0).sqrt()).abs() < 1e-15, "{rms:?}");
        assert_eq!(rms[1], 2.0);
        assert_eq!(rms[2], 0.0);
    }
}
