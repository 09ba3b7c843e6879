//! Recursive least squares with a forgetting factor 0.5 <= lambda <= 1 ([`MIN_FORGETTING`]).
//!
//! For each equation (phi, y): L = P phi / (lambda + phi' P phi),
//! beta += L (y - phi' beta), P = (I - L phi') P / lambda.
//!
//! ## Reference
//! A. Y. Zomaya, "Extraction and computation of identifiable parameters in robot dynamic
//! models: theory and application", IEE Proceedings - Control Theory and Applications
//! 141(1), 1994 (Table 1: RLS with a forgetting factor); L. Ljung, "System
//! Identification: Theory for the User", 2nd ed., 1999; see
//! docs/identification.md#recursive-least-squares.

use nalgebra::{DMatrix, DVector};

use crate::error::{Error, Result};
use crate::estimate::least_squares::check_tolerance;
use crate::estimate::lstsq::{InverseGram, column_scales, condition_number, solve};
use crate::estimate::result::assemble;
use crate::estimate::{Estimate, Estimator, Observation};
use crate::online::{OnlineRlsError, P_LIMIT, update_state};

/// The smallest forgetting factor accepted (`estimation.forgetting`): defined with the
/// on-line estimator ([`crate::online::MIN_FORGETTING`]), so that every recursive least
/// squares of robid takes the same factors.
pub use crate::online::MIN_FORGETTING;

/// Checks a forgetting factor against `[MIN_FORGETTING, 1]`; the error names the config
/// key `estimation.forgetting` (an [`Error::Setting`] of `Config`, which
/// [`crate::data::Config::locate`] places at its file:line).
pub fn check_forgetting(lambda: f64) -> Result<()> {
    if crate::online::forgetting_in_range(lambda) {
        return Ok(());
    }
    Err(Error::setting(
        "Config",
        "estimation.forgetting",
        format!(
            "{} is outside [{MIN_FORGETTING}, 1]; the recursion keeps about 1 / (1 - lambda) \
             equations in memory (1 keeps every equation; 0.95 to 0.999 track slow changes)",
            crate::Num(lambda)
        ),
    ))
}

/// Recursive least-squares state.
#[derive(Debug, Clone)]
pub struct Rls {
    beta: DVector<f64>,
    p: DMatrix<f64>,
    lambda: f64,
    ph: DVector<f64>,
}

impl Rls {
    /// `n` parameters starting at zero with P = p0 I; `lambda` within
    /// [`MIN_FORGETTING`, 1] ([`check_forgetting`]).
    ///
    /// # Errors
    ///
    /// [`Error::Setting`] for a forgetting factor outside `[MIN_FORGETTING, 1]` or a `p0`
    /// outside `(0, P_LIMIT]` (as [`OnlineRls::new`](crate::online::OnlineRls::new): a
    /// larger one would refuse every update as wind-up, [`P_LIMIT`]).
    pub fn new(n: usize, lambda: f64, p0: f64) -> Result<Self> {
        check_forgetting(lambda)?;
        if !(p0 > 0.0 && p0 <= P_LIMIT) {
            return Err(Error::setting(
                "Rls::new",
                "p0",
                format!("{p0} must be positive and at most {P_LIMIT:e}"),
            ));
        }
        Ok(Self {
            beta: DVector::zeros(n),
            p: DMatrix::identity(n, n) * p0,
            lambda,
            ph: DVector::zeros(n),
        })
    }

    /// One equation y = phi' beta; returns the prediction error `y - phi' beta` before
    /// the update. The update of [`OnlineRls::update`](crate::online::OnlineRls::update),
    /// with its refusals; a refused update changes nothing.
    ///
    /// # Errors
    ///
    /// [`OnlineRlsError::Length`] when `phi` does not have one entry per parameter,
    /// [`OnlineRlsError::NonFinite`] for a NaN or infinite input,
    /// [`OnlineRlsError::Denominator`] when `lambda + phi' P phi` is not positive and finite
    /// (it overflowed, or rounding took P's positive definiteness),
    /// [`OnlineRlsError::WindUp`] when P would grow beyond [`P_LIMIT`],
    /// [`OnlineRlsError::PredictionError`] when `phi' beta` overflowed.
    pub fn update(&mut self, phi: &[f64], y: f64) -> std::result::Result<f64, OnlineRlsError> {
        update_state(
            self.beta.as_mut_slice(),
            self.p.as_mut_slice(),
            self.ph.as_mut_slice(),
            self.lambda,
            phi,
            y,
        )
    }

    /// Current estimate.
    pub fn beta(&self) -> &DVector<f64> {
        &self.beta
    }

    /// Current P (an estimate of (W'W)^-1 for lambda = 1).
    pub fn covariance(&self) -> &DMatrix<f64> {
        &self.p
    }
}

/// Runs RLS over the equations in sample order (joints interleaved) and returns the final
/// estimate with statistics; standard deviations use sigma^2 P. Rank-deficient data is an
/// error, as for [`crate::estimate::ols`].
///
/// The recursion runs on column-scaled equations (each column divided by its RMS, so that
/// P0 = 1e8 I is large against every column) and is unscaled exactly at the end. It visits
/// every equation once: no iteration to cap. A state that overflowed (possible with a
/// forgetting factor below 1 on poorly excited data) is an error, not NaN.
pub fn rls(obs: &Observation, lambda: f64, tolerance: f64) -> Result<Estimate> {
    let (beta, p) = recursion(obs, lambda, tolerance)?;
    let cond = condition_number(&obs.w, &obs.names)?;
    assemble(
        Estimator::Rls,
        obs,
        obs,
        beta,
        &InverseGram::unscaled(p),
        cond,
    )
}

/// The recursion of [`rls`] without the statistics: the final estimate and `P`, checked
/// (tolerance, rank, finite result).
pub(crate) fn recursion(
    obs: &Observation,
    lambda: f64,
    tolerance: f64,
) -> Result<(DVector<f64>, DMatrix<f64>)> {
    check_forgetting(lambda)?;
    check_tolerance(tolerance)?;
    // the batch solution checks the rank
    solve(&obs.w, &obs.y, &obs.names, tolerance)?;
    let rows = obs.rows().max(1) as f64;
    let d: Vec<f64> = column_scales(&obs.w, &obs.names)?
        .into_iter()
        .map(|n| n / rows.sqrt())
        .collect();
    let mut state = Rls::new(obs.cols(), lambda, 1e8)?;
    let mut order: Vec<usize> = (0..obs.rows()).collect();
    order.sort_by_key(|&r| obs.sample_of_row[r]);
    let mut phi = vec![0.0; obs.cols()];
    for r in order {
        for (c, v) in phi.iter_mut().enumerate() {
            *v = obs.w[(r, c)] / d[c];
        }
        state
            .update(&phi, obs.y[r])
            .map_err(|e| lost_state(e, lambda, obs.cols()))?;
    }
    let n = obs.cols();
    let beta = DVector::from_iterator(n, (0..n).map(|j| state.beta[j] / d[j]));
    let p = DMatrix::from_fn(n, n, |i, j| state.p[(i, j)] / d[i] / d[j]);
    if beta
        .iter()
        .chain(p.diagonal().iter())
        .any(|v| !v.is_finite())
    {
        return Err(Error::NonFiniteResult {
            what: "the recursive least-squares state".into(),
            cause: format!(
                "it overflowed with the forgetting factor {}: the data do not excite every parameter all the time; set estimation.forgetting closer to 1 or use ols or wls",
                crate::Num(lambda)
            ),
        });
    }
    // P is positive definite in exact arithmetic; a diagonal entry at or below zero is
    // rounding that swamped it (P divided by lambda at every equation grows without bound
    // in directions the recent equations do not excite), and its standard deviation
    // would read 0: an exact value, for an estimate that diverged
    // (the scaled state's: unscaled, a column of 1e200 takes its entry to 0 by underflow)
    if let Some(i) = state.p.diagonal().iter().position(|v| *v <= 0.0) {
        return Err(Error::Singular {
            what: format!(
                "the recursive least-squares covariance P with the forgetting factor {} (which \
                 keeps about {} equations, against {n} parameters: its entry of {} came out {})",
                crate::Num(lambda),
                crate::Num::rounded(1.0 / (1.0 - lambda).max(f64::MIN_POSITIVE), 3),
                obs.names[i],
                crate::Num::rounded(p[(i, i)], 3)
            ),
            hint: "rounding swamped it in directions the recent equations do not excite, and the \
                   estimate it gives diverged; set estimation.forgetting closer to 1, or use ols \
                   or wls",
        });
    }
    Ok((beta, p))
}

/// The error of [`recursion`] for an update [`Rls::update`] refused (the equations are
/// finite and of the right length, checked by [`Observation::new`]): `P` lost its positive
/// definiteness to rounding, or the state would have overflowed.
fn lost_state(e: OnlineRlsError, lambda: f64, n: usize) -> Error {
    match e {
        OnlineRlsError::Denominator(d) => Error::Singular {
            what: format!(
                "the recursive least-squares covariance P with the forgetting factor {} (which \
                 keeps about {} equations, against {n} parameters: lambda + phi' P phi came out {})",
                crate::Num(lambda),
                crate::Num::rounded(1.0 / (1.0 - lambda).max(f64::MIN_POSITIVE), 3),
                crate::Num::rounded(d, 3)
            ),
            hint: "rounding swamped it in directions the recent equations do not excite, and the \
                   estimate it gives diverged; set estimation.forgetting closer to 1, or use ols \
                   or wls",
        },
        e => Error::NonFiniteResult {
            what: "the recursive least-squares state".into(),
            cause: format!(
                "it overflowed with the forgetting factor {} ({e}): the data do not excite every parameter all the time; set estimation.forgetting closer to 1 or use ols or wls",
                crate::Num(lambda)
            ),
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::estimate::ols;

    fn line(n: usize, slope: impl Fn(usize) -> f64) -> Observation {
        let mut w = DMatrix::zeros(n, 2);
        let mut y = DVector::zeros(n);
        for k in 0..n {
            let x = (k as f64 * 0.37).sin();
            w[(k, 0)] = x;
            w[(k, 1)] = 1.0;
            y[k] = slope(k) * x + 0.5 + 1e-3 * (k as f64 * 1.7).cos();
        }
        Observation::single(w, y, vec!["slope".into(), "offset".into()]).unwrap()
    }

    #[test]
    fn lambda_one_matches_ols() {
        let obs = line(300, |_| 2.0);
        let r = rls(&obs, 1.0, 1e-10).unwrap();
        let o = ols(&obs, 1e-10).unwrap();
        for i in 0..2 {
            assert!(
                (r.values[i] - o.values[i]).abs() < 1.5e-10,
                "{:?} vs {:?}",
                r.values,
                o.values
            );
            // measured 6.6e-11 in value and 1.7e-11 relative in std (the regularised start)
            assert!((r.std[i] - o.std[i]).abs() < 3.5e-11 * o.std[i]);
        }
    }

    #[test]
    fn forgetting_tracks_a_change() {
        let obs = line(600, |k| if k < 300 { 2.0 } else { 3.0 });
        let tracked = rls(&obs, 0.95, 1e-10).unwrap();
        let averaged = rls(&obs, 1.0, 1e-10).unwrap();
        assert!(
            (tracked.values[0] - 3.0).abs() < 1.2e-4,
            "{:?}",
            tracked.values
        );
        // measured 5.8e-5 from 3 with forgetting, 3.5e-3 from the average 2.5 without
        assert!((averaged.values[0] - 2.5).abs() < 7e-3);
    }

    #[test]
    fn bad_lambda_is_an_error() {
        assert!(Rls::new(2, 0.0, 1.0).is_err());
        assert!(Rls::new(2, 1.1, 1.0).is_err());
        assert!(Rls::new(2, 1.0, -1.0).is_err());
        // tiny and subnormal factors overflowed the state at the first equation: refused
        // by their key, with the range
        for lambda in [1e-320, 1e-300, 1e-3, 0.49] {
            let e = Rls::new(2, lambda, 1.0).unwrap_err().to_string();
            assert!(
                e.contains("estimation.forgetting") && e.contains("is outside [0.5, 1]"),
                "{e}"
            );
        }
        assert!(Rls::new(2, 0.5, 1.0).is_ok());
        // beyond the wind-up limit every update would be refused: refused here
        assert!(Rls::new(2, 1.0, 1e300).is_err());
    }

    /// The refusals of `OnlineRls::update`: a row of the wrong length (a panic in the
    /// product), a NaN (the state became NaN), an overflow of `phi' P phi` (NaN too); each
    /// leaves the state as it was.
    #[test]
    fn update_refuses_what_online_rls_refuses() {
        let mut rls = Rls::new(2, 1.0, 1e8).unwrap();
        rls.update(&[1.0, 0.5], 2.0).unwrap();
        let before = rls.clone();
        let same = |r: &Rls| r.beta() == before.beta() && r.covariance() == before.covariance();
        let e = rls.update(&[1.0, 2.0, 3.0], 1.0).unwrap_err();
        assert!(matches!(e, OnlineRlsError::Length(_)), "{e}");
        assert!(e.to_string().contains("`phi` has 3 entries"), "{e}");
        let e = rls.update(&[f64::NAN, 1.0], 1.0).unwrap_err();
        assert_eq!(
            e,
            OnlineRlsError::NonFinite {
                what: "phi",
                index: 0
            }
        );
        let e = rls.update(&[1.0, 1.0], f64::INFINITY).unwrap_err();
        assert_eq!(
            e,
            OnlineRlsError::NonFinite {
                what: "y",
                index: 0
            }
        );
        let e = rls.update(&[1e300, 1e300], 1.0).unwrap_err();
        assert!(matches!(e, OnlineRlsError::Denominator(_)), "{e}");
        assert!(same(&rls));
        assert!(rls.update(&[0.5, 1.0], 1.0).is_ok());
    }
}

#[cfg(test)]
mod lost_covariance {
    use super::*;

    /// Six parameters, the forgetting factor 0.5 (about 2 equations kept): P, divided by
    /// lambda at every equation, grows where the last equations do not look, and rounding
    /// takes its diagonal to zero or below, where the standard deviation read 0 (an exact
    /// value) for an estimate that had diverged. It is an error naming the factor.
    #[test]
    fn a_covariance_that_lost_its_diagonal_is_an_error() {
        let (n, c) = (2000, 6);
        let mut w = DMatrix::zeros(n, c);
        let mut y = DVector::zeros(n);
        for k in 0..n {
            let t = k as f64 * 0.01;
            for j in 0..c {
                w[(k, j)] = (t * (1.0 + j as f64 * 0.7) + j as f64).sin();
            }
            y[k] = (0..c).map(|j| w[(k, j)] * (j as f64 + 1.0)).sum::<f64>()
                + 1e-3 * (k as f64 * 1.3).cos();
        }
        let names = (0..c).map(|j| format!("p{j}")).collect();
        let obs = Observation::single(w, y, names).unwrap();
        let e = rls(&obs, 0.5, 1e-10).unwrap_err().to_string();
        assert!(
            e.contains("not positive definite") && e.contains("forgetting factor 0.5"),
            "{e}"
        );
        assert!(rls(&obs, 1.0, 1e-10).is_ok());
    }
}
