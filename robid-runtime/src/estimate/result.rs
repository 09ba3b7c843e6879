//! The result every estimator returns.

use nalgebra::DVector;
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::estimate::lstsq::{Condition, InverseGram, norm};
use crate::estimate::quality::{
    QualityWarning, assess, effects, reassess_uncertain, relative_column_norms,
};
use crate::estimate::{Observation, RobustStd};

/// Which estimator produced a result: the config's estimation method, one list for both
/// (the names in reports are its [`Method::name`](crate::data::Method::name)).
pub type Estimator = crate::data::Method;

/// Identified parameters with their uncertainty.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Estimate {
    /// The estimator.
    pub method: Estimator,
    /// Parameter names.
    pub names: Vec<String>,
    /// Values.
    pub values: Vec<f64>,
    /// Standard deviations sqrt(diag(sigma^2 (W'W)^-1)) of the solved (possibly weighted) system.
    pub std: Vec<f64>,
    /// Standard deviations robust to autocorrelated residuals (Newey-West; OLS and WLS
    /// without known parameters, `None` for the other estimators):
    /// docs/identification.md#statistics.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub robust: Option<RobustStd>,
    /// 100 * std / |value| (infinite only for a value that is exactly zero; reports write
    /// null or `-` for it).
    pub rel_std_percent: Vec<f64>,
    /// sigma^2 = ||y - W beta||^2 / (rows - cols) of the solved system.
    pub sigma2: f64,
    /// Condition number of the solved W, `s_max / s_min` (it depends on the parameters'
    /// units; the [`error_bound`](Self::error_bound) is taken with it).
    pub condition_number: f64,
    /// Condition number of the solved W with its columns scaled to unit norm: the same in
    /// any units of the parameters (docs/identification.md#condition-numbers); `None` in an
    /// estimate recorded without it.
    #[serde(default)]
    pub scaled_condition_number: Option<f64>,
    /// Upper bound on the relative estimation error `||d beta|| / ||beta||` of Milella
    /// (after Gautier and Khalil 1992): `cond(W) ||y - W beta|| / ||y||` of the solved
    /// system, as a fraction (1.89 is Milella's 189 %); 0 when the fit is exact
    /// (docs/identification.md#error-bound).
    #[serde(default)]
    pub error_bound: f64,
    /// RMS of the unweighted residual per joint block.
    pub residual_rms: Vec<f64>,
    /// Equations used.
    pub rows: usize,
    /// Per-joint weights 1/sigma_j (WLS only).
    pub weights: Option<Vec<f64>>,
    /// What the user should know before trusting the result (ill conditioning,
    /// parameters with a relative standard deviation above 100 %).
    #[serde(default)]
    pub warnings: Vec<QualityWarning>,
    /// Parameters fixed by known standard parameters, not estimated (their std is 0;
    /// `estimation.known`, [`crate::estimate::KnownParameters`]).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub known: Vec<String>,
}

impl Estimate {
    /// Value of the parameter called `name`.
    pub fn value(&self, name: &str) -> Option<f64> {
        self.names
            .iter()
            .position(|n| n == name)
            .map(|i| self.values[i])
    }

    /// The values as a vector.
    pub fn beta(&self) -> DVector<f64> {
        DVector::from_column_slice(&self.values)
    }

    /// The standard deviation the warnings judge each parameter by: the larger of the
    /// classical and the robust one, the classical one where there is no robust one
    /// (docs/identification.md#robust-standard-deviations: a robust deviation below the
    /// classical one is the estimator's own noise, one above it the residuals'
    /// correlation).
    ///
    /// ```
    /// use nalgebra::{DMatrix, DVector};
    /// use robid_runtime::estimate::{Observation, ols};
    /// # fn main() -> Result<(), robid_runtime::Error> {
    /// let w = DMatrix::from_fn(300, 2, |k, c| if c == 0 { 1.0 } else { (k as f64 * 0.05).sin() });
    /// let y = DVector::from_fn(300, |k, _| 2.0 + (k as f64 * 0.05).sin() + 0.1 * (k as f64 * 0.4).cos());
    /// let e = ols(&Observation::single(w, y, vec!["a".into(), "b".into()])?, 1e-10)?;
    /// let robust = e.robust.as_ref().expect("OLS gives them");
    /// for (j, judged) in e.judged_std().iter().enumerate() {
    ///     assert_eq!(*judged, e.std[j].max(robust.std[j]));
    /// }
    /// # Ok(()) }
    /// ```
    pub fn judged_std(&self) -> Vec<f64> {
        match &self.robust {
            Some(r) => self
                .std
                .iter()
                .zip(&r.std)
                .map(|(c, r)| c.max(*r))
                .collect(),
            None => self.std.clone(),
        }
    }

    /// Sets the robust deviations and, when there are some, judges the parameters
    /// uncertain by more than their size again by [`judged_std`](Self::judged_std);
    /// `relative_column_norms` are `||W_i|| / ||y||` of the solved system (what a
    /// deviation moves the torques by, [`ROUNDING_EFFECT`](crate::estimate::ROUNDING_EFFECT)).
    pub(crate) fn set_robust(&mut self, robust: Option<RobustStd>, relative_column_norms: &[f64]) {
        self.robust = robust;
        if self.robust.is_none() {
            return;
        }
        let judged = self.judged_std();
        let rel = relative_deviations(&judged, &self.values);
        let effect = effects(&judged, relative_column_norms);
        self.warnings = reassess_uncertain(&self.warnings, &self.names, &rel, &effect, true);
    }
}

/// `100 std / |value|` of each parameter, infinite for a value of exactly zero.
fn relative_deviations(std: &[f64], values: &[f64]) -> Vec<f64> {
    std.iter()
        .zip(values)
        .map(|(s, v)| {
            if *v == 0.0 {
                f64::INFINITY
            } else {
                100.0 * s / v.abs()
            }
        })
        .collect()
}

/// Assembles statistics: `solved` is the system actually solved (weighted for WLS),
/// `original` the unweighted one for the residual RMS per joint. Every number returned is
/// checked finite (an exactly zero value has an infinite relative deviation).
pub(crate) fn assemble(
    method: Estimator,
    solved: &Observation,
    original: &Observation,
    beta: DVector<f64>,
    inverse: &InverseGram,
    condition: Condition,
) -> Result<Estimate> {
    let m = solved.rows();
    let r = &solved.y - &solved.w * &beta;
    let residual_rms = original.residual_rms(&beta)?;
    let bound = error_bound(condition.raw, &r, &solved.y);
    let relative_column_norms = relative_column_norms(&solved.w, &solved.y);
    assemble_parts(
        method,
        original.names.clone(),
        beta,
        inverse,
        condition,
        Residual {
            norm: norm(r.iter().copied()),
            rows: m,
            per_joint_rms: residual_rms,
            error_bound: bound,
            relative_column_norms,
        },
    )
}

/// What the statistics need of the residual of a solution, however it was computed
/// (from the rows, [`assemble`], or from R factors, the streaming accumulator).
pub(crate) struct Residual {
    /// ||y - W beta|| of the solved system (infinite when it overflowed), taken without
    /// squaring the entries ([`norm`]): the standard deviations come from it.
    pub(crate) norm: f64,
    /// Equations of the solved system.
    pub(crate) rows: usize,
    /// RMS of the unweighted residual per joint block.
    pub(crate) per_joint_rms: Vec<f64>,
    /// [`error_bound`] of the solved system.
    pub(crate) error_bound: f64,
    /// `||W_i|| / ||y||` of each column of the solved system (for [`ROUNDING_EFFECT`](crate::estimate::ROUNDING_EFFECT)).
    pub(crate) relative_column_norms: Vec<f64>,
}

/// The statistics of a solution from its residual: sigma^2, the standard deviations, the
/// relative ones, the warnings; every number checked finite.
pub(crate) fn assemble_parts(
    method: Estimator,
    names: Vec<String>,
    beta: DVector<f64>,
    inverse: &InverseGram,
    condition: Condition,
    residual: Residual,
) -> Result<Estimate> {
    let condition_number = condition.raw;
    let (m, n) = (residual.rows, beta.len());
    // as many equations as parameters fit any data exactly: sigma^2 would be the rounding
    // error's, and every standard deviation a thousandth of a percent of nonsense
    if m < super::equations_needed(n) {
        return Err(Error::TooFewSamples {
            context: format!(
                "the standard deviations of the {} estimate of {} (counted in equations)",
                method.name(),
                crate::Count(n, "parameter")
            ),
            found: m,
            required: n + 1,
            hint: "as many equations as parameters fit any data exactly and leave no residual to estimate the noise from; use a longer record",
        });
    }
    // sigma from the norm, not from sigma^2: the squares of residuals below about 1e-154
    // underflow, and every deviation read 0 (exact) for torques of 1e-170 (sigma2 itself
    // may then underflow; the deviations stay right)
    let sigma = residual.norm / ((m - n) as f64).sqrt();
    let sigma2 = sigma * sigma;
    // sigma sqrt((W'W)^-1_ii), the second from the scaled factors: the product
    // sigma^2 (W'W)^-1_ii underflowed to 0 for a column near 1e200
    let std: Vec<f64> = inverse.root_diagonal().iter().map(|r| sigma * r).collect();
    let rel = relative_deviations(&std, beta.as_slice());
    let residual_rms = residual.per_joint_rms;
    let not_finite = |what: String, cause: &str| Error::NonFiniteResult {
        what,
        cause: cause.to_string(),
    };
    let name = |i: usize| names.get(i).cloned().unwrap_or_default();
    if let Some(i) = beta.iter().position(|v| !v.is_finite()) {
        return Err(not_finite(
            format!("the {} estimate of `{}`", method.name(), name(i)),
            "the estimator diverged; use ols or wls, or (rls) a forgetting factor closer to 1",
        ));
    }
    if let Some(i) = std.iter().position(|v| !v.is_finite()) {
        return Err(not_finite(
            format!("the standard deviation of `{}`", name(i)),
            "the residual or the covariance overflowed: the torques are far from what the parameters can explain; check the data's units and outliers",
        ));
    }
    if !sigma2.is_finite() || residual_rms.iter().any(|v| !v.is_finite()) {
        return Err(not_finite(
            "the residual of the fit".into(),
            "the prediction overflowed: check the data's units and outliers",
        ));
    }
    if !condition_number.is_finite() {
        return Err(not_finite(
            "the condition number".into(),
            "the observation matrix is numerically singular; use a richer trajectory",
        ));
    }
    let error_bound = residual.error_bound;
    if !error_bound.is_finite() {
        return Err(not_finite(
            "the upper bound on the relative estimation error".into(),
            "the torques are negligible next to the residual: check the data's units",
        ));
    }
    let effect = effects(&std, &residual.relative_column_norms);
    let warnings = assess(condition_number, &names, &rel, &effect);
    Ok(Estimate {
        method,
        names,
        residual_rms,
        values: beta.iter().copied().collect(),
        std,
        robust: None,
        rel_std_percent: rel,
        sigma2,
        condition_number,
        scaled_condition_number: Some(condition.scaled),
        error_bound,
        rows: m,
        weights: None,
        warnings,
        known: Vec::new(),
    })
}

/// Milella's upper bound on the relative estimation error (the bound of Gautier and Khalil
/// 1992 that Milella reports, 189 % for 30 OPVA points against 65 % for the extended
/// trajectories): `cond(W) ||rho|| / ||y||` with `rho = y - W beta` the residual of the
/// solved system (docs/identification.md#error-bound). The norms are taken scaled by the
/// largest entry, so that neither overflows; 0 for an exact fit (also when `y` is zero),
/// infinite for a residual with a zero `y` (which least squares never returns).
///
/// F. Milella, "Direct Estimate of Closed-Form Dynamic Equation Parameters of a Robot:
/// Tools and Methods for Designing Experiments" (docs/references.md#milella).
pub fn error_bound(condition_number: f64, residual: &DVector<f64>, y: &DVector<f64>) -> f64 {
    let big = residual
        .iter()
        .chain(y.iter())
        .fold(0.0f64, |m, v| m.max(v.abs()));
    let scaled = |x: &DVector<f64>| x.iter().map(|v| (v / big).powi(2)).sum::<f64>().sqrt();
    if big == 0.0 {
        return 0.0;
    }
    if !big.is_finite() {
        return f64::INFINITY;
    }
    let rho = scaled(residual);
    if rho == 0.0 {
        return 0.0;
    }
    condition_number * rho / scaled(y)
}

#[cfg(test)]
mod tests {
    use nalgebra::{DMatrix, DVector};

    use super::{Estimator, assemble};
    use crate::estimate::lstsq::{Condition, InverseGram};

    const ONE: Condition = Condition {
        raw: 1.0,
        scaled: 1.0,
    };
    use crate::estimate::Observation;

    fn observation(y: &[f64]) -> Observation {
        let rows = y.len();
        Observation::new(
            DMatrix::from_element(rows, 1, 1.0),
            DVector::from_column_slice(y),
            std::iter::once(0..rows).collect(),
            (0..rows).collect(),
            vec!["a".into()],
        )
        .unwrap()
    }

    /// The weighted system can be tame while the unweighted residual overflows (weights of
    /// 1e-308 on torques of 1.5e308, whose RMS is beyond f64): the residual RMS is checked
    /// on its own.
    #[test]
    fn an_overflowing_residual_is_refused_even_when_the_weighted_fit_is_finite() {
        let solved = observation(&[1.0, 2.0, 3.0]);
        let original = observation(&[1.5e308, -1.5e308, 1.5e308]);
        let beta = DVector::from_vec(vec![2.0]);
        let gram = InverseGram::unscaled(DMatrix::from_element(1, 1, 1.0 / 3.0));
        let fine = assemble(Estimator::Wls, &solved, &solved, beta.clone(), &gram, ONE);
        assert!(fine.is_ok());
        let e = assemble(Estimator::Wls, &solved, &original, beta, &gram, ONE).unwrap_err();
        assert!(e.to_string().contains("residual of the fit"), "{e}");
    }

    /// As many equations as parameters fit any data exactly: the statistics are refused
    /// (sigma^2 was the rounding error over one degree of freedom, and every standard
    /// deviation 0.00 % of values a thousand times the truth), by every estimator that
    /// assembles them, RLS included; one equation more gives them.
    #[test]
    fn no_more_equations_than_parameters_leave_no_statistics() {
        let one = observation(&[2.0]);
        let gram = InverseGram::unscaled(DMatrix::from_element(1, 1, 1.0));
        let beta = DVector::from_vec(vec![2.0]);
        let e = assemble(Estimator::Ols, &one, &one, beta, &gram, ONE).unwrap_err();
        assert!(
            matches!(
                e,
                crate::Error::TooFewSamples {
                    found: 1,
                    required: 2,
                    ..
                }
            ) && e
                .to_string()
                .contains("no residual to estimate the noise from"),
            "{e}"
        );
        assert!(crate::estimate::rls(&one, 1.0, 1e-10).is_err());
        let two = observation(&[2.0, 2.5]);
        let e = crate::estimate::ols(&two, 1e-10).unwrap();
        // sigma^2 = (0.25^2 + 0.25^2) / 1, std = sigma / sqrt(2)
        assert!((e.std[0] - 0.25).abs() < 1e-15, "{:?}", e.std);
    }

    /// The same fit with its noise scaled has about the same relative standard deviations
    /// (670 and 673 %), but only the one whose deviations move the torques by more than the data's rounding
    /// (`ROUNDING_EFFECT`) warns about them (dense least squares).
    #[test]
    fn the_same_relative_deviation_warns_only_above_the_rounding() {
        let n = 200;
        let w = DMatrix::from_fn(n, 2, |i, j| match j {
            0 => (0.1 * i as f64).sin(),
            _ => (0.37 * i as f64).cos(),
        });
        let fit = |noise: f64| {
            let y = DVector::from_fn(n, |i, _| {
                2.0 * w[(i, 0)] + noise * (1.3 * i as f64 + 0.5).sin()
            });
            let names = vec!["a".into(), "b".into()];
            let obs = Observation::new(
                w.clone(),
                y,
                std::iter::once(0..n).collect(),
                (0..n).collect(),
                names,
            )
            .unwrap();
            crate::estimate::ols(&obs, 1e-12).unwrap()
        };
        let (quiet, noisy) = (fit(1e-11), fit(1e-3));
        let rel = |e: &super::Estimate| e.rel_std_percent[1];
        assert!(rel(&quiet) > 100.0, "{}", rel(&quiet));
        assert!(rel(&noisy) > 100.0, "{}", rel(&noisy));
        assert!(quiet.warnings.is_empty(), "{:?}", quiet.warnings);
        assert_eq!(noisy.warnings.len(), 1, "{:?}", noisy.warnings);
        assert_eq!(noisy.warnings[0].parameters(), vec!["b"]);
    }

    /// Milella's bound on a system small enough to compute by hand: cond(W) from the
    /// singular values, the residual from the normal equations, against what `ols` reports.
    #[test]
    fn milella_error_bound_matches_a_direct_computation() {
        let w = DMatrix::from_row_slice(5, 2, &[1.0, 0.0, 1.0, 1.0, 1.0, 2.0, 1.0, 3.0, 1.0, 4.0]);
        let y = DVector::from_column_slice(&[1.1, 2.9, 5.2, 6.8, 9.1]);
        let obs = Observation::new(
            w.clone(),
            y.clone(),
            std::iter::once(0..5).collect(),
            (0..5).collect(),
            vec!["a".into(), "b".into()],
        )
        .unwrap();
        let e = crate::estimate::ols(&obs, 1e-12).unwrap();
        let s = w.clone().svd(false, false).singular_values;
        let cond = s.max() / s.min();
        let gram = w.transpose() * &w;
        let beta = gram.lu().solve(&(w.transpose() * &y)).unwrap();
        let direct = cond * (&y - &w * &beta).norm() / y.norm();
        // the line through the five points (numpy): beta = (1.04, 1.99), residual 0.3271,
        // |y| 12.87, cond 4.739: the bound is 0.12041 (agreement to rounding, 1e-12 relative)
        assert!(
            (e.error_bound - direct).abs() < 1e-12 * direct,
            "{} vs {direct}",
            e.error_bound
        );
        // 0.1204144 to six decimals: half a unit is 5e-7
        assert!((direct - 0.120414).abs() < 5e-7, "{direct}");
        // exact data: no residual, no bound
        let exact = Observation::new(
            w.clone(),
            &w * DVector::from_column_slice(&[1.0, 2.0]),
            std::iter::once(0..5).collect(),
            (0..5).collect(),
            vec!["a".into(), "b".into()],
        )
        .unwrap();
        assert!(crate::estimate::ols(&exact, 1e-12).unwrap().error_bound < 1e-14);
    }
}
