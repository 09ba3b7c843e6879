//! Joint signals on one time grid: the type every stage from loading to the observation
//! matrix passes along.

use std::ops::{Index, IndexMut, Range};

use rayon::prelude::*;

use crate::error::{Error, Result};

/// One signal per joint, all with the same number of samples: `s[j][k]` is joint `j` at
/// sample `k`.
///
/// Stored per joint (the layout filters and differentiation work on); the equal lengths
/// are checked once, when the signals are made, so that no stage has to.
///
/// ```
/// use robid_runtime::signal::Signals;
///
/// let q = Signals::new(vec![vec![0.0, 0.1, 0.2], vec![1.0, 1.0, 1.0]])?;
/// assert_eq!((q.dof(), q.samples()), (2, 3));
/// assert_eq!(q[0][2], 0.2);
/// assert_eq!(q.sample(1), vec![0.1, 1.0]);
/// assert_eq!(q.range(1..3)[1], [1.0, 1.0]);
/// assert!(Signals::new(vec![vec![0.0; 3], vec![0.0; 2]]).is_err());
/// # Ok::<(), robid_runtime::Error>(())
/// ```
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Signals {
    joints: Vec<Vec<f64>>,
}

impl Signals {
    /// Signals from one vector per joint; an error names the first joint whose length
    /// differs from joint 1's.
    pub fn new(joints: Vec<Vec<f64>>) -> Result<Self> {
        let n = joints.first().map_or(0, Vec::len);
        if let Some((j, v)) = joints.iter().enumerate().find(|(_, v)| v.len() != n) {
            return Err(Error::DimensionMismatch {
                what: format!("samples of joint {} (as many as joint 1's)", j + 1),
                expected: n,
                found: v.len(),
            });
        }
        Ok(Self { joints })
    }

    /// `dof` joints of `samples` zeros.
    pub fn zeros(dof: usize, samples: usize) -> Self {
        Self {
            joints: vec![vec![0.0; samples]; dof],
        }
    }

    /// `dof` joints of `samples` values `f(joint, sample)`.
    pub fn from_fn(dof: usize, samples: usize, mut f: impl FnMut(usize, usize) -> f64) -> Self {
        Self {
            joints: (0..dof)
                .map(|j| (0..samples).map(|k| f(j, k)).collect())
                .collect(),
        }
    }

    /// Number of joints.
    pub fn dof(&self) -> usize {
        self.joints.len()
    }

    /// Number of samples of each joint.
    pub fn samples(&self) -> usize {
        self.joints.first().map_or(0, Vec::len)
    }

    /// The signals of the joints in order.
    pub fn joints(&self) -> impl ExactSizeIterator<Item = &[f64]> {
        self.into_iter()
    }

    /// The signals of the joints in order, mutable (their lengths are fixed).
    pub fn joints_mut(&mut self) -> impl ExactSizeIterator<Item = &mut [f64]> {
        self.joints.iter_mut().map(Vec::as_mut_slice)
    }

    /// The joints' values at sample `k`.
    pub fn sample(&self, k: usize) -> Vec<f64> {
        self.joints.iter().map(|v| v[k]).collect()
    }

    /// Writes the joints' values at sample `k` into `out` (one entry per joint).
    pub fn sample_into(&self, k: usize, out: &mut [f64]) {
        for (o, v) in out.iter_mut().zip(&self.joints) {
            *o = v[k];
        }
    }

    /// `[smallest, largest]` value of each joint (`[inf, -inf]` for a joint without
    /// samples; NaN is passed over).
    ///
    /// ```
    /// let s = robid_runtime::signal::Signals::new(vec![vec![1.0, -2.0, 3.0], vec![0.5, f64::NAN, 0.0]])
    ///     .unwrap();
    /// assert_eq!(s.extremes(), vec![[-2.0, 3.0], [0.0, 0.5]]);
    /// ```
    pub fn extremes(&self) -> Vec<[f64; 2]> {
        self.joints
            .iter()
            .map(|v| {
                v.iter()
                    .fold([f64::INFINITY, f64::NEG_INFINITY], |[lo, hi], &a| {
                        [lo.min(a), hi.max(a)]
                    })
            })
            .collect()
    }

    /// The samples `range` of every joint (clamped to the samples there are).
    pub fn range(&self, range: Range<usize>) -> Self {
        let n = self.samples();
        let (start, end) = (range.start.min(n), range.end.min(n));
        let start = start.min(end);
        Self {
            joints: self.joints.iter().map(|v| v[start..end].to_vec()).collect(),
        }
    }

    /// The samples `range` of every joint, as [`range`](Self::range) gives them, cut in
    /// place: no copy of the signals is made (the memory of a long record is not doubled).
    pub fn into_range(mut self, range: Range<usize>) -> Self {
        let n = self.samples();
        let (start, end) = (range.start.min(n), range.end.min(n));
        let start = start.min(end);
        for v in &mut self.joints {
            v.truncate(end);
            v.drain(..start);
        }
        self
    }

    /// Applies `f` to every joint's signal (in parallel); the results must have equal
    /// lengths, as filters, differentiation and decimation give.
    pub fn map(&self, f: impl Fn(&[f64]) -> Vec<f64> + Sync) -> Result<Self> {
        self.try_map(|v| Ok(f(v)))
    }

    /// [`Signals::map`] with a fallible `f`; the first error is returned.
    pub fn try_map(&self, f: impl Fn(&[f64]) -> Result<Vec<f64>> + Sync) -> Result<Self> {
        let joints = self
            .joints
            .par_iter()
            .map(|v| f(v))
            .collect::<Result<Vec<_>>>()?;
        Self::new(joints)
    }

    /// The first non-finite value, as (joint, sample).
    pub fn first_non_finite(&self) -> Option<(usize, usize)> {
        self.joints
            .iter()
            .enumerate()
            .find_map(|(j, v)| Some((j, crate::finite::first_non_finite(v)?.0)))
    }
}

impl Index<usize> for Signals {
    type Output = [f64];

    /// The signal of joint `j` (0-based).
    fn index(&self, j: usize) -> &[f64] {
        &self.joints[j]
    }
}

impl IndexMut<usize> for Signals {
    fn index_mut(&mut self, j: usize) -> &mut [f64] {
        &mut self.joints[j]
    }
}

impl<'a> IntoIterator for &'a Signals {
    type Item = &'a [f64];
    type IntoIter = std::iter::Map<std::slice::Iter<'a, Vec<f64>>, fn(&Vec<f64>) -> &[f64]>;

    /// The signals of the joints in order.
    fn into_iter(self) -> Self::IntoIter {
        self.joints.iter().map(Vec::as_slice)
    }
}

impl TryFrom<Vec<Vec<f64>>> for Signals {
    type Error = Error;

    fn try_from(joints: Vec<Vec<f64>>) -> Result<Self> {
        Self::new(joints)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `try_from` is `new`: the joints' values kept, unequal lengths refused.
    #[test]
    fn try_from_keeps_the_values() {
        let s = Signals::try_from(vec![vec![1.0, 2.0], vec![3.0, 4.0]]).unwrap();
        assert_eq!((s.dof(), s.samples()), (2, 2));
        assert_eq!(s[1], [3.0, 4.0]);
        assert!(Signals::try_from(vec![vec![1.0], vec![]]).is_err());
    }

    #[test]
    fn keeps_lengths_equal() {
        let e = Signals::new(vec![vec![0.0; 4], vec![0.0; 4], vec![0.0; 3]]).unwrap_err();
        assert!(e.to_string().contains("joint 3"), "{e}");
        let s = Signals::from_fn(2, 4, |j, k| (10 * j + k) as f64);
        assert_eq!(s[1], [10.0, 11.0, 12.0, 13.0]);
        assert_eq!(s.range(3..9).samples(), 1);
        assert_eq!(s.range(5..9).samples(), 0);
        let (from, to) = (2, 1);
        assert_eq!(s.range(from..to).samples(), 0);
        // cut in place: the same samples as a copy, also out of bounds or reversed
        let (from, to) = (3, 1);
        for r in [0..4, 1..3, 3..9, 5..9, 0..0, from..to] {
            assert_eq!(s.clone().into_range(r.clone()), s.range(r.clone()), "{r:?}");
        }
        let mut out = [0.0; 2];
        s.sample_into(2, &mut out);
        assert_eq!(out, [2.0, 12.0]);
        assert!(
            s.map(|v| v[..if v[0] == 0.0 { 2 } else { 3 }].to_vec())
                .is_err()
        );
        assert_eq!(s.map(|v| v[1..].to_vec()).unwrap().samples(), 3);
        let mut t = s.clone();
        t[1][2] = f64::NAN;
        assert_eq!(t.first_non_finite(), Some((1, 2)));
        assert_eq!(s.first_non_finite(), None);
        assert_eq!(Signals::zeros(0, 5).samples(), 0);
    }
}
