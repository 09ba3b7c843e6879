//! Recursive least squares that runs sample by sample on a controller: fixed-size arrays,
//! no allocation, `no_std` (docs/identification.md#online-recursive-least-squares).
//!
//! The same recursion as the batch estimator of the pipeline (`estimate::Rls`), after
//! Zomaya's Table 1: for each equation `y = phi' beta`,
//!
//! ```text
//! L    = P phi / (lambda + phi' P phi)
//! beta = beta + L (y - phi' beta)
//! P    = (P - L (P phi)') / lambda          kept symmetric
//! ```
//!
//! with `MIN_FORGETTING = 0.5 <= lambda <= 1` the forgetting factor (the bound of the
//! batch estimator and of the config's `estimation.forgetting`, [`MIN_FORGETTING`]) and
//! `P(0) = p0 I`, `p0 > 0`.
//!
//! ## Reference
//! A. Y. Zomaya, "Extraction and computation of identifiable parameters in robot dynamic
//! models: theory and application", IEE Proceedings - Control Theory and Applications
//! 141(1), 1994 (Table 1: recursive least squares with a forgetting factor).

use core::fmt;

use crate::model::LengthError;

/// The smallest forgetting factor accepted, by [`OnlineRls::new`], by the batch estimator
/// (`estimate::Rls`, which re-exports it as `estimate::MIN_FORGETTING`) and by the config's
/// `estimation.forgetting`: the one bound of every recursive least squares of robid. The
/// recursion keeps about `1 / (1 - lambda)` equations in memory, so below 0.5 it keeps
/// fewer than two and forgets each equation before the next arrives, whatever the parameter
/// count; every update also divides `P` by `lambda`, and a factor written as `1e-320` (meant
/// as 0, or a unit mistake) made the state overflow at the first equation (on line, it winds
/// up to [`P_LIMIT`] within a few updates and stops). Practical factors lie between 0.95 and
/// 1.
pub const MIN_FORGETTING: f64 = 0.5;

/// Whether `lambda` is a forgetting factor robid accepts: `MIN_FORGETTING <= lambda <= 1`
/// (NaN is not). The one check behind [`OnlineRls::new`], `estimate::check_forgetting` and
/// the config's `estimation.forgetting`.
///
/// ```
/// use robid_runtime::online::forgetting_in_range;
/// assert!(forgetting_in_range(1.0) && forgetting_in_range(0.5));
/// assert!(!forgetting_in_range(0.3) && !forgetting_in_range(1.5) && !forgetting_in_range(f64::NAN));
/// ```
pub fn forgetting_in_range(lambda: f64) -> bool {
    (MIN_FORGETTING..=1.0).contains(&lambda)
}

/// The largest diagonal entry of `P` an update may produce. `P` after an update is at most
/// `P / lambda` (in the order of positive semidefinite matrices), so an update whose
/// `max diag(P) / lambda` exceeds this is refused before it changes anything: the state
/// never overflows, it stops (estimator wind-up with a forgetting factor and no excitation).
pub const P_LIMIT: f64 = 1e150;

/// What an [`OnlineRls`] refused.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum OnlineRlsError {
    /// The forgetting factor is not in `[MIN_FORGETTING, 1]` ([`MIN_FORGETTING`] = 0.5).
    Forgetting(f64),
    /// `p0` is not positive and finite.
    InitialCovariance(f64),
    /// An input value is NaN or infinite; `what` is `phi` or `y`, `index` its entry.
    NonFinite {
        /// `phi` or `y`.
        what: &'static str,
        /// The entry.
        index: usize,
    },
    /// `lambda + phi' P phi` is not positive and finite: `P` lost its positive
    /// definiteness to rounding (restart with [`OnlineRls::reset`]).
    Denominator(f64),
    /// The update would push `P` beyond [`P_LIMIT`]: the data do not excite every
    /// parameter and the forgetting factor inflates `P`; use a forgetting factor closer to 1.
    WindUp(f64),
    /// A slice has the wrong length.
    Length(LengthError),
    /// The prediction error `y - phi' beta` overflowed (the inputs are finite, their
    /// product is not): the state is unchanged.
    PredictionError(f64),
}

impl fmt::Display for OnlineRlsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Forgetting(l) => write!(
                f,
                "the forgetting factor {} must satisfy {MIN_FORGETTING} <= lambda <= 1: the \
                 recursion keeps about 1 / (1 - lambda) equations in memory (1 keeps every \
                 equation; 0.95 to 0.999 track slow changes)",
                crate::Num(*l)
            ),
            Self::InitialCovariance(p) => write!(
                f,
                "P(0) = p0 I needs p0 > 0 and finite, not {p0}; a large p0 (1e6 to 1e8 times \
                 1 / |phi|^2) trusts the data over the zero start",
                p0 = crate::Num(*p)
            ),
            Self::NonFinite { what, index } => write!(
                f,
                "{what}[{index}] is NaN or infinite; the update was skipped and the state is unchanged"
            ),
            Self::Denominator(d) => write!(
                f,
                "lambda + phi' P phi = {} is not positive: P lost its positive definiteness \
                 to rounding; reset the estimator",
                crate::Num(*d)
            ),
            Self::WindUp(p) => write!(
                f,
                "the update would make P as large as {p:e} (limit {P_LIMIT:e}): the data do not \
                 excite every parameter; use a forgetting factor closer to 1"
            ),
            Self::Length(e) => e.fmt(f),
            Self::PredictionError(e) => write!(
                f,
                "the prediction error y - phi' beta is {}: phi' beta overflowed; the update was \
                 skipped and the state is unchanged (check the units of phi and y)",
                crate::Num(*e)
            ),
        }
    }
}

impl core::error::Error for OnlineRlsError {}

impl From<LengthError> for OnlineRlsError {
    fn from(e: LengthError) -> Self {
        Self::Length(e)
    }
}

/// Recursive least squares for `N` parameters in fixed arrays: no allocation, `no_std`.
///
/// Every refused update leaves the state as it was, so the estimate is never NaN.
///
/// ```
/// use robid_runtime::online::OnlineRls;
/// // y = 2 x + 1, one equation at a time
/// let mut rls = OnlineRls::<2>::new(1.0, 1e8).unwrap();
/// for k in 0..50 {
///     let x = (k as f64 * 0.3).sin();
///     rls.update(&[x, 1.0], 2.0 * x + 1.0).unwrap();
/// }
/// let [slope, offset] = *rls.estimate();
/// assert!((slope - 2.0).abs() < 1e-6 && (offset - 1.0).abs() < 1e-6);
/// ```
///
/// With a model compiled by `robot_model!`, the base regressor's rows (row-major, one row
/// per joint) and the measured torques are one update per sample:
///
/// ```
/// use robid_runtime::Model;
/// use robid_runtime::online::{OnlineRls, OnlineRlsError};
///
/// /// One control period: the regressor of the measured state, then one update.
/// fn step<const B: usize>(
///     model: &dyn Model,
///     rls: &mut OnlineRls<B>,
///     state: (&[f64], &[f64], &[f64]),
///     tau: &[f64],
///     regressor: &mut [f64], // dof * B entries, kept between calls: nothing is allocated
/// ) -> Result<(), OnlineRlsError> {
///     model.base_regressor_into(state.0, state.1, state.2, regressor)?;
///     rls.update_rows(regressor, tau)
/// }
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct OnlineRls<const N: usize> {
    beta: [f64; N],
    p: [[f64; N]; N],
    lambda: f64,
    p0: f64,
    updates: u64,
}

impl<const N: usize> OnlineRls<N> {
    /// `beta = 0`, `P = p0 I`, forgetting factor `lambda` in `[MIN_FORGETTING, 1]`
    /// ([`forgetting_in_range`]; [`OnlineRlsError::Forgetting`] otherwise, as the batch
    /// estimator and the config refuse it), `p0` in `(0, P_LIMIT]`
    /// ([`OnlineRlsError::InitialCovariance`] otherwise).
    pub fn new(lambda: f64, p0: f64) -> Result<Self, OnlineRlsError> {
        if !forgetting_in_range(lambda) {
            return Err(OnlineRlsError::Forgetting(lambda));
        }
        if !(p0 > 0.0 && p0 <= P_LIMIT) {
            return Err(OnlineRlsError::InitialCovariance(p0));
        }
        let mut s = Self {
            beta: [0.0; N],
            p: [[0.0; N]; N],
            lambda,
            p0,
            updates: 0,
        };
        s.reset();
        Ok(s)
    }

    /// Back to `beta = 0`, `P = p0 I`.
    pub fn reset(&mut self) {
        self.beta = [0.0; N];
        self.p = [[0.0; N]; N];
        for (i, row) in self.p.iter_mut().enumerate() {
            row[i] = self.p0;
        }
        self.updates = 0;
    }

    /// One equation `y = phi' beta`; returns the prediction error `y - phi' beta` before
    /// the update. A refused update changes nothing.
    pub fn update(&mut self, phi: &[f64; N], y: f64) -> Result<f64, OnlineRlsError> {
        let mut ph = [0.0; N];
        let err = update_state(
            &mut self.beta,
            self.p.as_flattened_mut(),
            &mut ph,
            self.lambda,
            phi,
            y,
        )?;
        self.updates += 1;
        Ok(err)
    }

    /// One sample of a robot: `rows` is the base regressor row-major (one row of `N` per
    /// joint, as [`crate::Model::base_regressor_into`] writes it) and `tau` the joint
    /// torques; one update per joint in joint order. The lengths are checked before any
    /// update; an update refused stops there (earlier joints of the sample are kept).
    pub fn update_rows(&mut self, rows: &[f64], tau: &[f64]) -> Result<(), OnlineRlsError> {
        crate::model::check_length("out", rows, tau.len() * N)?;
        for (row, &y) in rows.chunks_exact(N).zip(tau) {
            let phi: &[f64; N] = crate::model::fixed("out", row)?;
            self.update(phi, y)?;
        }
        Ok(())
    }

    /// The current estimate.
    pub fn estimate(&self) -> &[f64; N] {
        &self.beta
    }

    /// The current `P` (for `lambda = 1`, `(p0^-1 I + W'W)^-1`, which tends to `(W'W)^-1`).
    pub fn covariance(&self) -> &[[f64; N]; N] {
        &self.p
    }

    /// The forgetting factor.
    pub fn forgetting(&self) -> f64 {
        self.lambda
    }

    /// Updates accepted since the start or the last [`reset`](Self::reset).
    pub fn updates(&self) -> u64 {
        self.updates
    }
}

/// One equation `y = phi' beta` on a state of `n = beta.len()` parameters, `p` holding
/// `P` (`n x n`, symmetric: row- and column-major alike) and `ph` scratch of `n` entries;
/// returns the prediction error before the update. The one update of [`OnlineRls`] and of
/// the batch `estimate::Rls`, with the same refusals: a wrong length, a non-finite input, a
/// denominator that is not positive and finite, wind-up beyond [`P_LIMIT`], an overflowed
/// prediction. A refused update changes nothing.
pub(crate) fn update_state(
    beta: &mut [f64],
    p: &mut [f64],
    ph: &mut [f64],
    lambda: f64,
    phi: &[f64],
    y: f64,
) -> Result<f64, OnlineRlsError> {
    let n = beta.len();
    crate::model::check_length("phi", phi, n)?;
    if let Some(index) = phi.iter().position(|v| !v.is_finite()) {
        return Err(OnlineRlsError::NonFinite { what: "phi", index });
    }
    if !y.is_finite() {
        return Err(OnlineRlsError::NonFinite {
            what: "y",
            index: 0,
        });
    }
    // ph = P phi
    for (out, row) in ph.iter_mut().zip(p.chunks_exact(n.max(1))) {
        *out = dot(row, phi);
    }
    let denom = lambda + dot(phi, ph);
    if !(denom > 0.0 && denom.is_finite()) {
        return Err(OnlineRlsError::Denominator(denom));
    }
    let largest = (0..n).map(|i| p[i * n + i]).fold(0.0, f64::max);
    if !(largest / lambda <= P_LIMIT) {
        return Err(OnlineRlsError::WindUp(largest / lambda));
    }
    let err = y - dot(phi, beta);
    if !err.is_finite() {
        return Err(OnlineRlsError::PredictionError(err));
    }
    for (b, h) in beta.iter_mut().zip(ph.iter()) {
        *b += h / denom * err;
    }
    // P = (P - ph ph' / denom) / lambda, computed on the upper triangle and mirrored;
    // ph_k / denom first: ph_i ph_k alone can overflow where the quotient is at most
    // sqrt(P_ii P_kk)
    for i in 0..n {
        for k in i..n {
            let v = (0.5 * (p[i * n + k] + p[k * n + i]) - ph[i] * (ph[k] / denom)) / lambda;
            p[i * n + k] = v;
            p[k * n + i] = v;
        }
    }
    Ok(err)
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

#[cfg(all(test, feature = "std"))]
mod tests;
