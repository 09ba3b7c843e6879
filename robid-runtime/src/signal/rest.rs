//! Dropping samples where a joint is nearly at rest (the Coulomb sign is undefined there).

use super::Signals;

/// For each joint, the indices of the samples whose velocity magnitude is at least the
/// joint's threshold; `threshold` has one entry per joint.
pub fn moving_samples(qd: &Signals, threshold: &[f64]) -> Vec<Vec<usize>> {
    qd.joints()
        .zip(threshold)
        .map(|(v, &lim)| {
            v.iter()
                .enumerate()
                .filter(|(_, x)| x.abs() >= lim)
                .map(|(k, _)| k)
                .collect()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keeps_only_moving_samples_per_joint() {
        let qd = Signals::new(vec![vec![0.0, 0.2, -0.3, 0.01], vec![1.0, 1.0, 0.0, -1.0]]).unwrap();
        let keep = moving_samples(&qd, &[0.05, 0.5]);
        assert_eq!(keep, vec![vec![1, 2], vec![0, 1, 3]]);
    }
}
