//! Central differences for velocities and accelerations (the Savitzky-Golay alternative is
//! `savgol.rs`).

use crate::error::{Error, Result};

/// Derivative of a uniformly sampled signal by central differences
/// (`(x[k+1] - x[k-1]) / 2 dt` inside, one-sided at both ends, as `numpy.gradient`).
///
/// Returns an empty vector for an empty input and zeros for a single sample.
///
/// # Errors
///
/// A sample time `dt` that is not positive and finite, as
/// [`SavitzkyGolay::derivative`](crate::signal::SavitzkyGolay::derivative) refuses it
/// (0 gave infinite derivatives, NaN NaN ones).
pub fn central_difference(x: &[f64], dt: f64) -> Result<Vec<f64>> {
    Error::positive_and_finite("central_difference", "dt", "the sample time", dt, "s")?;
    let n = x.len();
    if n < 2 {
        return Ok(vec![0.0; n]);
    }
    // appended, not written over zeros (a block's derivatives are a few MB)
    let mut d = Vec::with_capacity(n);
    d.push((x[1] - x[0]) / dt);
    let h = 0.5 / dt;
    d.extend(x[2..].iter().zip(&x[..n - 2]).map(|(a, b)| (a - b) * h));
    d.push((x[n - 1] - x[n - 2]) / dt);
    Ok(d)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_on_a_parabola_inside() {
        let dt = 0.01;
        // an offset, so that no sample is zero and a sum cannot pass for a difference
        let x: Vec<f64> = (0..50)
            .map(|k| 3.0 * (k as f64 * dt).powi(2) - (k as f64 * dt) + 0.7)
            .collect();
        let d = central_difference(&x, dt).unwrap();
        for (k, v) in d.iter().enumerate().take(49).skip(1) {
            let t = k as f64 * dt;
            assert!((v - (6.0 * t - 1.0)).abs() < 1e-9);
        }
        // one-sided at the ends: the forward and the backward difference, each the exact
        // derivative of the parabola half a step inside (6 t - 1 at t = dt/2, 48.5 dt)
        assert!((d[0] - (6.0 * 0.5 * dt - 1.0)).abs() < 1e-9, "{}", d[0]);
        assert!((d[49] - (6.0 * 48.5 * dt - 1.0)).abs() < 1e-9, "{}", d[49]);
    }

    /// Two samples: the one difference there is, at both.
    #[test]
    fn two_samples_give_their_difference() {
        assert_eq!(
            central_difference(&[1.0, 1.5], 0.1).unwrap(),
            vec![5.0, 5.0]
        );
    }

    #[test]
    fn sine_derivative() {
        let dt = 1e-3;
        let x: Vec<f64> = (0..2000).map(|k| (k as f64 * dt * 2.0).sin()).collect();
        let d = central_difference(&x, dt).unwrap();
        let err = (1000..1010)
            .map(|k| (d[k] - 2.0 * (k as f64 * dt * 2.0).cos()).abs())
            .fold(0.0, f64::max);
        // truncation error dt^2 |x'''| / 6 = 1e-6 * 8 / 6 (measured 5.8e-7)
        assert!(err < dt * dt * 8.0 / 6.0, "{err}");
    }

    #[test]
    fn degenerate_lengths() {
        assert!(central_difference(&[], 0.1).unwrap().is_empty());
        assert_eq!(central_difference(&[1.0], 0.1).unwrap(), vec![0.0]);
    }

    /// A sample time that is not positive and finite is refused as the Savitzky-Golay
    /// derivative refuses it (0 gave inf, NaN NaN), whatever the length.
    #[test]
    fn a_sample_time_that_is_not_positive_and_finite_is_refused() {
        for dt in [0.0, -0.01, f64::NAN, f64::INFINITY] {
            for x in [&[0.0, 1.0, 2.0][..], &[1.0], &[]] {
                let e = central_difference(x, dt).unwrap_err().to_string();
                assert!(e.contains("must be positive and finite"), "{dt}: {e}");
            }
        }
    }
}
