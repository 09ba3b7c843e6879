//! Dropping samples where a joint is nearly at rest (the Coulomb sign is undefined there).

use super::Signals;
use crate::error::{Error, Result, num};

/// For each joint, the indices of the samples whose velocity magnitude is at least the
/// joint's threshold; `threshold` has one entry per joint.
///
/// # Errors
///
/// `DimensionMismatch` for a `threshold` of another length than the joints (the joints
/// beyond it were dropped without a word), and a threshold that is not finite and at least
/// 0 (NaN kept no sample).
pub fn moving_samples(qd: &Signals, threshold: &[f64]) -> Result<Vec<Vec<usize>>> {
    let dof = qd.joints().len();
    if threshold.len() != dof {
        return Err(Error::DimensionMismatch {
            what: "rest-velocity thresholds (one per joint)".into(),
            expected: dof,
            found: threshold.len(),
        });
    }
    if let Some((j, lim)) = threshold
        .iter()
        .enumerate()
        .find(|(_, l)| !(l.is_finite() && **l >= 0.0))
    {
        return Err(Error::setting(
            "moving_samples",
            "threshold",
            format!(
                "joint {}: the rest-velocity threshold {} must be finite and at least 0",
                j + 1,
                num(*lim)
            ),
        ));
    }
    Ok(qd
        .joints()
        .zip(threshold)
        .map(|(v, &lim)| {
            v.iter()
                .enumerate()
                .filter(|(_, x)| x.abs() >= lim)
                .map(|(k, _)| k)
                .collect()
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keeps_only_moving_samples_per_joint() {
        let qd = Signals::new(vec![vec![0.0, 0.2, -0.3, 0.01], vec![1.0, 1.0, 0.0, -1.0]]).unwrap();
        let keep = moving_samples(&qd, &[0.05, 0.5]).unwrap();
        assert_eq!(keep, vec![vec![1, 2], vec![0, 1, 3]]);
    }

    /// A threshold per joint, finite and at least 0: one too few dropped the second joint
    /// without a word, NaN kept no sample.
    #[test]
    fn thresholds_of_another_count_or_not_finite_are_refused() {
        let qd = Signals::new(vec![vec![0.0, 0.2], vec![1.0, 1.0]]).unwrap();
        for t in [&[0.1][..], &[0.1, 0.1, 0.1], &[]] {
            let e = moving_samples(&qd, t).unwrap_err().to_string();
            assert!(e.contains("one per joint"), "{t:?}: {e}");
        }
        for t in [[0.1, f64::NAN], [-0.1, 0.1], [0.1, f64::INFINITY]] {
            let e = moving_samples(&qd, &t).unwrap_err().to_string();
            assert!(e.contains("must be finite and at least 0"), "{t:?}: {e}");
        }
        assert_eq!(
            moving_samples(&qd, &[0.0, 0.0]).unwrap(),
            vec![vec![0, 1]; 2]
        );
    }
}
