//! Torque-prediction metrics (docs/identification.md#validation-metrics).

use serde::{Deserialize, Serialize};

/// How well predicted torques match measured ones.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Fit {
    /// ||tau - tauhat|| / ||tau|| over all joints and samples.
    pub relative_error: f64,
    /// sqrt(mean (tau_j - tauhat_j)^2) per joint.
    pub rms_per_joint: Vec<f64>,
    /// Sum over joints of mean((tau_j - tauhat_j)^2) / mean(|tau_j|) (Madsen's NMSE,
    /// normalised per joint by the mean torque magnitude rather than per sample, which
    /// would divide by torques that cross zero). A joint whose mean |tau_j| is at most
    /// [`EQ22_ZERO`] of the largest joint's is left out, as one of zero torque is (a dead
    /// channel of 5e-324 N m made the sum infinite).
    pub nmse: f64,
    /// Madsen et al.'s NMSE exactly as their eq. 22 writes it, on their scale (N m):
    /// sum over joints and samples of (tau - tauhat)^2 / |tau|. Samples whose measured
    /// torque is zero are left out (they would divide by zero), and so are those within
    /// [`EQ22_ZERO`] of the joint's largest or of the record's (no sensor resolves them:
    /// 2e-308 N m in a log made the sum infinite, and so did a joint whose every torque
    /// was 5e-324); samples near zero otherwise weigh heavily, as in the paper.
    /// Default 0 in reports written before it existed.
    #[serde(default)]
    pub nmse_eq22: f64,
}

impl Fit {
    /// Checks that every metric is finite; `what` names the data in the error.
    pub fn check(&self, what: &str) -> crate::Result<()> {
        if !self.relative_error.is_finite() {
            return Err(crate::Error::NonFiniteResult {
                what: format!("the relative error on {what}"),
                cause: "the measured torques are all zero, or too small for their squares (below about 1e-154, which underflow to zero; it divides by their norm): the data hold no torque to identify from or predict; check the torque columns and their unit (`torque_scale`)".into(),
            });
        }
        if !(self.nmse.is_finite() && self.nmse_eq22.is_finite())
            || self.rms_per_joint.iter().any(|v| !v.is_finite())
        {
            return Err(crate::Error::NonFiniteResult {
                what: format!("the error metrics on {what}"),
                cause: "the prediction error overflowed; check the data's units and outliers"
                    .into(),
            });
        }
        Ok(())
    }
}

/// Measured torques at most this fraction of their joint's largest magnitude count as
/// zero in [`Fit::nmse_eq22`], which divides by them.
pub const EQ22_ZERO: f64 = 1e-12;

/// Computes the metrics from per-joint measured and predicted torques (same lengths).
/// Joints with no samples contribute nothing; the relative error is infinite when every
/// measured torque is zero ([`Fit::check`] reports it).
///
/// # Errors
///
/// [`Error::DimensionMismatch`](crate::Error::DimensionMismatch) when the two have not the
/// same number of joints, or a joint not the same number of samples in both (a joint left
/// out gave a relative error of 0, and samples beyond the shorter were dropped unsaid).
pub fn fit(measured: &[Vec<f64>], predicted: &[Vec<f64>]) -> crate::Result<Fit> {
    if measured.len() != predicted.len() {
        return Err(crate::Error::DimensionMismatch {
            what: "the joints of the predicted torques (one per measured joint)".into(),
            expected: measured.len(),
            found: predicted.len(),
        });
    }
    if let Some(j) = (0..measured.len()).find(|&j| measured[j].len() != predicted[j].len()) {
        return Err(crate::Error::DimensionMismatch {
            what: format!(
                "the predicted torques of joint {} (one per measured sample)",
                j + 1
            ),
            expected: measured[j].len(),
            found: predicted[j].len(),
        });
    }
    let (mut err2, mut norm2, mut nmse, mut nmse_eq22) = (0.0, 0.0, 0.0, 0.0);
    let mut rms = Vec::with_capacity(measured.len());
    let mean_abs = |m: &[f64], n: usize| m[..n].iter().map(|a| a.abs()).sum::<f64>() / n as f64;
    let largest = measured
        .iter()
        .filter(|m| !m.is_empty())
        .fold(0.0_f64, |x, m| x.max(mean_abs(m, m.len())));
    let peak = |m: &[f64]| m.iter().fold(0.0_f64, |x, a| x.max(a.abs()));
    let record_peak = measured.iter().fold(0.0_f64, |x, m| x.max(peak(m)));
    for (m, p) in measured.iter().zip(predicted) {
        let n = m.len();
        if n == 0 {
            rms.push(0.0);
            continue;
        }
        let e2: f64 = m.iter().zip(p).map(|(a, b)| (a - b) * (a - b)).sum();
        let mean_abs = mean_abs(m, n);
        let zero = EQ22_ZERO * record_peak;
        nmse_eq22 += m
            .iter()
            .zip(p)
            .filter(|(a, _)| a.abs() > zero)
            .map(|(a, b)| (a - b) * (a - b) / a.abs())
            .sum::<f64>();
        err2 += e2;
        norm2 += m.iter().map(|a| a * a).sum::<f64>();
        rms.push((e2 / n as f64).sqrt());
        if mean_abs > EQ22_ZERO * largest {
            nmse += e2 / n as f64 / mean_abs;
        }
    }
    let relative_error = if norm2 > 0.0 {
        (err2 / norm2).sqrt()
    } else {
        f64::INFINITY
    };
    Ok(Fit {
        relative_error,
        rms_per_joint: rms,
        nmse,
        nmse_eq22,
    })
}

/// Relative improvement of a metric in percent: 100 (reference - new) / reference
/// (positive when `new` is better, as in Madsen et al. 2020, Table 5); `None` when it is
/// not a finite number: a reference of 0 (a perfect reference leaves nothing to improve
/// on; it gave -inf, and 0 against 0 NaN) or a metric that is not finite.
pub fn relative_improvement(reference: f64, new: f64) -> Option<f64> {
    let percent = 100.0 * (reference - new) / reference;
    percent.is_finite().then_some(percent)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Torques too small to square are said to be so, with their unit's setting, not as
    /// all zero (torques of 1e-300 N m were "all zero").
    #[test]
    fn torques_too_small_to_square_are_named() {
        let e = fit(&[vec![1e-300, -2e-300, 3e-300]], &[vec![0.0; 3]])
            .unwrap()
            .check("data")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("too small for their squares") && e.contains("torque_scale"),
            "{e}"
        );
    }

    /// A joint whose torque is a subnormal number throughout (a dead channel written as
    /// 5e-324) is left out of the NMSE, as a joint of zeros is: it was infinite, and the
    /// identification failed with "the prediction error overflowed".
    #[test]
    fn a_joint_of_negligible_torque_is_left_out_of_the_nmse() {
        let p = vec![vec![0.2, -0.1, 0.3], vec![1.0, -1.0, 2.0]];
        let with = |t: f64| fit(&[vec![t; 3], vec![1.0, -1.0, 2.5]], &p).unwrap();
        let (zero, tiny) = (with(0.0), with(5e-324));
        assert!(tiny.check("data").is_ok(), "{tiny:?}");
        assert_eq!(zero.nmse, tiny.nmse);
        // joint 2 alone: 0.5^2 / 3 over its mean |tau|, 4.5 / 3
        assert!((zero.nmse - 0.25 / 3.0 / 1.5).abs() < 1e-15, "{zero:?}");
        // a small torque that is no rounding counts
        assert!(with(1e-3).nmse > 10.0, "{:?}", with(1e-3));
    }

    #[test]
    fn known_values() {
        let m = vec![vec![1.0, -1.0, 2.0, -2.0], vec![0.5, 0.5]];
        let p = vec![vec![1.0, -1.0, 2.0, -1.0], vec![0.5, 0.0]];
        let f = fit(&m, &p).unwrap();
        // errors: joint 1 one error of 1, joint 2 one error of 0.5
        assert!((f.relative_error - (1.25f64 / 10.5).sqrt()).abs() < 1e-12);
        assert!((f.rms_per_joint[0] - 0.5).abs() < 1e-12);
        assert!((f.rms_per_joint[1] - (0.125f64).sqrt()).abs() < 1e-12);
        // nmse = (1/4)/1.5 + (0.25/2)/0.5
        assert!((f.nmse - (0.25 / 1.5 + 0.125 / 0.5)).abs() < 1e-12);
        // eq. 22: 1^2 / |-2| + 0.5^2 / |0.5|, per sample
        assert!((f.nmse_eq22 - (0.5 + 0.5)).abs() < 1e-12);
        // a torque no sensor resolves counts as zero there, not as a divisor of 1e300
        let tiny = fit(&[vec![2.0, 2.2e-308, 1e-11]], &[vec![1.0, 1.0, 0.0]]).unwrap();
        assert!((tiny.nmse_eq22 - (0.5 + 1e-11)).abs() < 1e-15, "{tiny:?}");
        assert_eq!(fit(&m, &m).unwrap().relative_error, 0.0);
    }

    /// Every metric must be finite: all-zero measured torques (an infinite relative error)
    /// and an overflowed NMSE or RMS are errors naming the data.
    #[test]
    fn check_refuses_each_non_finite_metric() {
        let good = fit(&[vec![1.0, 2.0]], &[vec![1.5, 2.0]]).unwrap();
        assert!(good.check("run.csv").is_ok());
        // a joint whose measured torque is zero adds nothing to the NMSE
        let with_still = fit(
            &[vec![1.0, 2.0], vec![0.0, 0.0]],
            &[vec![1.5, 2.0], vec![0.1, 0.0]],
        )
        .unwrap();
        assert_eq!(with_still.nmse, good.nmse);
        assert_eq!(with_still.nmse_eq22, good.nmse_eq22);
        assert!(with_still.check("run.csv").is_ok());
        let zero = fit(&[vec![0.0, 0.0]], &[vec![1.0, 0.0]]).unwrap();
        assert!(!zero.relative_error.is_finite());
        assert!(
            zero.check("run.csv")
                .unwrap_err()
                .to_string()
                .contains("relative error on run.csv")
        );
        for bad in [
            Fit {
                nmse: f64::NAN,
                ..good.clone()
            },
            Fit {
                nmse_eq22: f64::INFINITY,
                ..good.clone()
            },
            Fit {
                rms_per_joint: vec![f64::INFINITY],
                ..good.clone()
            },
        ] {
            let e = bad.check("run.csv").unwrap_err().to_string();
            assert!(e.contains("error metrics on run.csv"), "{e}");
        }
    }

    #[test]
    fn improvement() {
        // 81.3536 to two decimals: half a unit is 0.005
        assert!((relative_improvement(506.8, 94.5).unwrap() - 81.35).abs() < 0.005);
        assert!(relative_improvement(1.0, 2.0).unwrap() < 0.0);
        // a perfect reference leaves no improvement to give: none, not -inf or NaN
        assert_eq!(relative_improvement(0.0, 1.0), None);
        assert_eq!(relative_improvement(0.0, 0.0), None);
        assert_eq!(relative_improvement(1.0, f64::INFINITY), None);
    }

    /// Joints or samples that differ in number are an error naming them: a missing joint
    /// gave a relative error of 0 (and `check` passed), a short one mixed 5 and 10 samples.
    #[test]
    fn differing_joints_or_samples_are_an_error() {
        let e = fit(&[vec![1.0; 10], vec![5.0; 10]], &[vec![1.0; 10]])
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("joints of the predicted") && e.contains("expected 2 entries, found 1"),
            "{e}"
        );
        let e = fit(&[vec![1.0; 10]], &[vec![0.0; 5]])
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("joint 1") && e.contains("expected 10 entries, found 5"),
            "{e}"
        );
        assert!(fit(&[vec![1.0; 10]], &[vec![0.0; 10]]).is_ok());
    }
}
