//! The stacked linear system y = W beta that the estimators solve.

use crate::EstimateError;
use std::ops::Range;

use nalgebra::{DMatrix, DVector};

use crate::error::{Error, Result};
use crate::estimate::lstsq::norm;

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
    ///
    /// # Errors
    ///
    /// [`Error::DimensionMismatch`] when `y`, `names` or `sample_of_row` do not have one
    /// entry per row (per column for `names`); [`Error::Setting`] when the joint blocks
    /// are not disjoint, in increasing order and covering every row (`0..3, 3..7, 7..10`
    /// for 10 rows; empty blocks allowed) or when two columns share a name
    /// ([`check_names`](crate::estimate::check_names));
    /// [`EstimateError::NonFiniteObservation`] for a NaN or infinite entry.
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
        check_blocks(&joint_rows, w.nrows())?;
        crate::estimate::check_names(&names)?;
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

    /// RMS of y - W beta in each joint block (0 for an empty block), taken without
    /// squaring the residuals, which underflow below about 1e-154.
    ///
    /// # Errors
    ///
    /// [`Error::DimensionMismatch`] when `beta` does not have one entry per column.
    pub fn residual_rms(&self, beta: &DVector<f64>) -> Result<Vec<f64>> {
        if beta.len() != self.cols() {
            return Err(Error::DimensionMismatch {
                what: "the parameters of Observation::residual_rms (one per column)".into(),
                expected: self.cols(),
                found: beta.len(),
            });
        }
        let r = &self.y - &self.w * beta;
        Ok(self
            .joint_rows
            .iter()
            .map(|b| {
                if b.is_empty() {
                    0.0
                } else {
                    norm(r.rows(b.start, b.len()).iter().copied()) / (b.len() as f64).sqrt()
                }
            })
            .collect())
    }
}

/// Checks that the joint blocks are disjoint, in increasing order and cover `0..rows`:
/// WLS weighs each block by its own residual, and a row in two blocks (or in none) was
/// weighed twice (or not at all) without a word.
fn check_blocks(blocks: &[Range<usize>], rows: usize) -> Result<()> {
    let mut end = 0;
    for (j, b) in blocks.iter().enumerate() {
        let problem = if b.start != end {
            Some(format!(
                "block {} ({}..{}) starts at row {}, where the previous block ends at row {end}",
                j + 1,
                b.start,
                b.end,
                b.start
            ))
        } else if b.end < b.start {
            Some(format!(
                "block {} ({}..{}) ends before it starts",
                j + 1,
                b.start,
                b.end
            ))
        } else {
            None
        };
        if let Some(problem) = problem {
            return Err(blocks_error(problem, rows));
        }
        end = b.end;
    }
    if end != rows {
        return Err(blocks_error(
            format!("the blocks cover rows 0..{end}, not the observation's 0..{rows}"),
            rows,
        ));
    }
    Ok(())
}

fn blocks_error(problem: String, rows: usize) -> Error {
    Error::setting(
        "Observation::new",
        "joint_rows",
        format!(
            "{problem}; give each joint's rows as consecutive ranges that cover every row once              (for {rows} rows: 0..a, a..b, ..., c..{rows}; an empty block is a..a)"
        ),
    )
}

#[cfg(test)]
mod tests {
    use nalgebra::{DMatrix, DVector};

    use std::ops::Range;

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
        let rms = o.residual_rms(&DVector::from_vec(vec![1.0])).unwrap();
        assert!((rms[0] - (11.0f64 / 3.0).sqrt()).abs() < 1e-15, "{rms:?}");
        assert_eq!(rms[1], 2.0);
        assert_eq!(rms[2], 0.0);
    }

    fn new(blocks: Vec<Range<usize>>, names: &[&str]) -> crate::Result<Observation> {
        Observation::new(
            DMatrix::from_fn(10, names.len(), |r, c| (r + c) as f64),
            DVector::zeros(10),
            blocks,
            (0..10).collect(),
            names.iter().map(|n| n.to_string()).collect(),
        )
    }

    /// Overlapping blocks, a row left out, a reversed range and a gap are refused with the
    /// block named (0..5, 0..5 for 10 rows was accepted, and WLS weighed rows twice).
    #[test]
    fn joint_blocks_must_partition_the_rows() {
        for (blocks, said) in [
            (vec![0..5, 0..5], "block 2 (0..5) starts at row 0"),
            (
                vec![0..10, Range { start: 7, end: 3 }],
                "block 2 (7..3) starts at row 7",
            ),
            (
                vec![0..3, Range { start: 3, end: 1 }],
                "block 2 (3..1) ends before it starts",
            ),
            (vec![0..4, 5..10], "block 2 (5..10) starts at row 5"),
            (
                vec![0..4, 4..9],
                "cover rows 0..9, not the observation's 0..10",
            ),
            (vec![], "cover rows 0..0"),
        ] {
            let e = new(blocks.clone(), &["a"]).unwrap_err().to_string();
            assert!(
                e.contains("joint_rows") && e.contains(said),
                "{blocks:?}: {e}"
            );
        }
        assert!(new(vec![0..4, 4..4, 4..10], &["a"]).is_ok());
    }

    /// Two columns of one name are refused ([`check_names`](crate::estimate::check_names)).
    #[test]
    fn a_repeated_name_is_refused() {
        let e = new(std::iter::once(0..10).collect(), &["a", "a"])
            .unwrap_err()
            .to_string();
        assert!(e.contains("`a` appears twice"), "{e}");
    }

    /// A parameter vector of the wrong length is an error, not a panic in the product;
    /// residuals of 1e-170 give their RMS (their squares underflowed to 0).
    #[test]
    fn residual_rms_checks_beta_and_does_not_underflow() {
        let o = new(std::iter::once(0..10).collect(), &["a", "b"]).unwrap();
        let e = o.residual_rms(&DVector::zeros(5)).unwrap_err().to_string();
        assert!(e.contains("expected 2 entries, found 5"), "{e}");
        let tiny = Observation::single(
            DMatrix::zeros(4, 1),
            DVector::from_vec(vec![1e-170, -1e-170, 1e-170, -1e-170]),
            vec!["a".into()],
        )
        .unwrap();
        let rms = tiny.residual_rms(&DVector::zeros(1)).unwrap();
        assert!((rms[0] / 1e-170 - 1.0).abs() < 1e-15, "{rms:?}");
    }
}
