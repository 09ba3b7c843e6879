//! Ordinary and weighted least squares (IDIM-OLS and IDIM-WLS).
//!
//! WLS weights each joint's equations by 1/sigma_j, with sigma_j^2 = ||rho_j||^2 /
//! (r_j - h_j) the variance of the OLS residual of joint j's r_j equations, `h_j` the sum
//! of their leverages (`tr(W_j (W'W)^-1 W_j')`, the parameters' share of its equations:
//! the `h_j` of all joints add up to the c parameters, as the `r_j - h_j` add up to the
//! `rows - c` of the whole residual), taken in the column-scaled space the solver factors
//! ([`joint_leverages`]).
//! A joint whose residual is (nearly) zero would get an infinite weight: sigma_j has a
//! floor of [`SIGMA_FLOOR`] times the largest sigma of the joints (and all weights are 1
//! when every residual is zero, as for exact data).
//!
//! ## Reference
//! M. Gautier, "Dynamic identification of robots with power model", ICRA 1997;
//! M. Gautier, W. Khalil, "Exciting trajectories for the identification of base
//! inertial parameters of robots", IJRR 1992.

use nalgebra::DVector;

use crate::error::{Error, Result};
use crate::estimate::hac::{Scores, robust_lag};
use crate::estimate::lstsq::{InverseGram, Solution, norm, solve};
use crate::estimate::quality::relative_column_norms;
use crate::estimate::result::assemble;
use crate::estimate::{Estimate, Estimator, Observation, QualityWarning, RobustStd};

/// Floor of the per-joint residual sigma of WLS, relative to the largest joint sigma.
pub const SIGMA_FLOOR: f64 = 1e-6;

/// Checks the relative singular-value threshold of the estimators.
pub(crate) fn check_tolerance(tolerance: f64) -> Result<()> {
    if tolerance > 0.0 && tolerance < 1.0 {
        Ok(())
    } else {
        Err(Error::setting(
            "Config",
            "estimation.rank_tolerance",
            format!("{tolerance} must lie in (0, 1)"),
        ))
    }
}

/// Ordinary least squares; `tolerance` is the relative singular-value threshold. The
/// estimate has robust deviations ([`Estimate::robust`]) beside the classical ones, and
/// its warnings judge each parameter by the larger ([`Estimate::judged_std`]).
pub fn ols(obs: &Observation, tolerance: f64) -> Result<Estimate> {
    ols_with(obs, tolerance, true)
}

/// [`ols`], with the robust deviations only when `robust` (the energy model's windows and
/// static poses are no time series, and `estimation.robust_std = false` leaves them out):
/// an estimate without them is judged by its classical deviations alone.
pub(crate) fn ols_with(obs: &Observation, tolerance: f64, robust: bool) -> Result<Estimate> {
    check_tolerance(tolerance)?;
    let s = solve(&obs.w, &obs.y, &obs.names, tolerance)?;
    let condition = s.condition();
    let deviations = robust.then(|| robust_std(obs, &s.beta, &s.inverse));
    let mut e = assemble(Estimator::Ols, obs, obs, s.beta, &s.inverse, condition)?;
    if let Some(deviations) = deviations {
        e.set_robust(deviations.finite(), &relative_column_norms(&obs.w, &obs.y));
    }
    Ok(e)
}

/// The Newey-West standard deviations ([`RobustStd`]) of the solution `beta` of `solved`
/// (the weighted system for WLS) whose `(W'W)^-1` is `inverse`: each sample's score
/// `W_t' e_t` over its joints' equations, the lags within a segment
/// ([`Observation::breaks`]), the lag [`robust_lag`] of the samples and
/// [`Observation::correlated`]. [`RobustStd::finite`] says whether to keep it.
pub(crate) fn robust_std(
    solved: &Observation,
    beta: &DVector<f64>,
    inverse: &InverseGram,
) -> RobustStd {
    let residual = &solved.y - &solved.w * beta;
    let mut order: Vec<(usize, usize, usize)> = (0..solved.rows())
        .map(|r| {
            let k = solved.sample_of_row[r];
            (solved.segment(k), k, r)
        })
        .collect();
    order.sort_unstable();
    let mut samples = order.iter().map(|&(s, k, _)| (s, k)).collect::<Vec<_>>();
    samples.dedup();
    let lag = robust_lag(samples.len(), solved.correlated);
    let mut scores = Scores::new(inverse.clone(), lag);
    let mut row = vec![0.0; solved.cols()];
    for (segment, k, r) in order {
        row.iter_mut()
            .zip(solved.w.row(r).iter())
            .for_each(|(a, b)| *a = *b);
        scores.add(segment, k, &row, residual[r]);
    }
    scores.finish(solved.rows())
}

/// Weighted least squares with per-joint weights from the OLS residuals; robust
/// deviations and warnings as [`ols`]'s.
pub fn wls(obs: &Observation, tolerance: f64) -> Result<Estimate> {
    wls_with(obs, tolerance, true)
}

/// [`wls`], with the robust deviations only when `robust` (as [`ols_with`]).
pub(crate) fn wls_with(obs: &Observation, tolerance: f64, robust: bool) -> Result<Estimate> {
    check_tolerance(tolerance)?;
    let first = solve(&obs.w, &obs.y, &obs.names, tolerance)?;
    let r = &obs.y - &obs.w * &first.beta;
    let leverages = joint_leverages(obs, &first);
    let sigma: Vec<f64> = obs
        .joint_rows
        .iter()
        .zip(&leverages)
        .map(|(b, &(rows, leverage))| {
            joint_sigma(
                norm(r.rows(b.start, b.len()).iter().copied()),
                rows,
                leverage,
            )
        })
        .collect();
    let weights = checked_weights(&sigma)?;
    let mut weighted = obs.clone();
    let mut row_weight = DVector::from_element(obs.rows(), 1.0);
    for (b, w) in obs.joint_rows.iter().zip(&weights) {
        row_weight.rows_mut(b.start, b.len()).fill(*w);
    }
    for mut col in weighted.w.column_iter_mut() {
        col.component_mul_assign(&row_weight);
    }
    weighted.y.component_mul_assign(&row_weight);
    let s = solve(&weighted.w, &weighted.y, &weighted.names, tolerance)?;
    let condition = s.condition();
    let deviations = robust.then(|| robust_std(&weighted, &s.beta, &s.inverse));
    let mut e = assemble(
        Estimator::Wls,
        &weighted,
        obs,
        s.beta,
        &s.inverse,
        condition,
    )?;
    e.weights = Some(weights);
    if let Some(deviations) = deviations {
        e.set_robust(
            deviations.finite(),
            &relative_column_norms(&weighted.w, &weighted.y),
        );
    }
    e.warnings.extend(weights_without_noise(&leverages));
    Ok(e)
}

/// Each joint's equations: their count and the sum of their leverages
/// `tr(W_j (W'W)^-1 W_j')` under the fit `s` of the whole observation, taken in the
/// column-scaled space the solver factors ([`Solution::leverage`]):
/// they add up to the parameters whatever the columns' magnitudes.
pub(crate) fn joint_leverages(obs: &Observation, s: &Solution) -> Vec<(usize, f64)> {
    let units = vec![1.0; obs.w.ncols()];
    obs.joint_rows
        .iter()
        .map(|b| (b.len(), s.leverage(obs.w.rows(b.start, b.len()), &units)))
        .collect()
}

/// [`QualityWarning::WeightWithoutNoise`] for each joint whose equations, given as their
/// count and the sum of their leverages, leave less than one degree of freedom: its sigma
/// is then its residual over 1 ([`joint_sigma`]), not an estimate of its noise. A joint
/// without equations has its own warning (`JointWithoutEquations`).
pub(crate) fn weights_without_noise(leverages: &[(usize, f64)]) -> Vec<QualityWarning> {
    leverages
        .iter()
        .enumerate()
        .filter(|&(_, &(rows, leverage))| rows > 0 && (rows as f64 - leverage) < 1.0)
        .map(
            |(j, &(rows, leverage))| QualityWarning::WeightWithoutNoise {
                joint: j + 1,
                rows,
                freedom: (rows as f64 - leverage).max(0.0),
            },
        )
        .collect()
}

/// The residual sigma of a joint from the norm `rss` of its OLS residual (the square root
/// of its sum of squares, taken scaled: [`norm`]) over `rows`
/// equations whose leverages (the diagonal of the hat matrix `W (W'W)^-1 W'` on its rows)
/// sum to `leverage`: over `rows - leverage` degrees of freedom, at least 1.
///
/// The joint OLS fit spends its `c` degrees of freedom across all joints' equations, each
/// joint's share being its leverage, so that the joints' `rows - leverage` add up to the
/// `rows - c` of the whole residual. Taking `c` from every joint (`rows - c`, as until
/// 7 December 2026) removed the parameters once per joint: on a UR5e record decimated to
/// 84 to 94 equations per joint (58 parameters) the sigmas came out 1.5 to 2.0 times the
/// noise, unevenly across the joints, where these are within 3.5 % (but for one joint, 24 %).
pub(crate) fn joint_sigma(rss: f64, rows: usize, leverage: f64) -> f64 {
    let dof = (rows as f64 - leverage).max(1.0);
    rss / dof.sqrt()
}

/// [`joint_weights`], refusing sigmas that overflowed.
pub(crate) fn checked_weights(sigma: &[f64]) -> Result<Vec<f64>> {
    let largest = sigma.iter().copied().fold(0.0f64, f64::max);
    if !largest.is_finite() {
        return Err(Error::NonFiniteResult {
            what: "the WLS weights".into(),
            cause: "the OLS residual overflowed: check the data's units and outliers".into(),
        });
    }
    Ok(joint_weights(sigma))
}

/// Weights 1 / sigma_j with the floor [`SIGMA_FLOOR`] x the largest sigma (all 1 when every
/// sigma is zero).
fn joint_weights(sigma: &[f64]) -> Vec<f64> {
    let largest = sigma.iter().copied().fold(0.0f64, f64::max);
    sigma
        .iter()
        .map(|s| {
            if largest > 0.0 {
                1.0 / s.max(SIGMA_FLOOR * largest)
            } else {
                1.0
            }
        })
        .collect()
}

/// Checks that the columns are named uniquely (an error names the duplicate).
pub fn check_names(names: &[String]) -> Result<()> {
    for (i, n) in names.iter().enumerate() {
        if names[..i].contains(n) {
            return Err(Error::setting(
                "Config",
                "extra_column",
                format!(
                    "the parameter name `{n}` appears twice (an extra column with the name of a model parameter, or two extra columns of that name); rename the extra column"
                ),
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
#[allow(clippy::needless_range_loop)]
mod tests {
    use super::*;
    use nalgebra::DMatrix;

    /// Two joints, 3 parameters, deterministic pseudo-noise: joint 2 is 10x noisier.
    fn problem() -> (Observation, [f64; 3]) {
        let beta = [2.0, -1.0, 0.5];
        let n = 400;
        let mut w = DMatrix::zeros(2 * n, 3);
        let mut y = DVector::zeros(2 * n);
        let mut seed = 12345u64;
        let mut noise = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((seed >> 11) as f64 / (1u64 << 53) as f64) - 0.5
        };
        for k in 0..n {
            let t = k as f64 * 0.01;
            for j in 0..2 {
                let row = j * n + k;
                let x = [(t * (j + 1) as f64).sin(), (1.3 * t).cos(), 1.0];
                for c in 0..3 {
                    w[(row, c)] = x[c];
                }
                let scale = if j == 0 { 0.01 } else { 0.1 };
                y[row] = x.iter().zip(beta).map(|(a, b)| a * b).sum::<f64>() + scale * noise();
            }
        }
        let names = vec!["a".into(), "b".into(), "c".into()];
        (
            Observation::new(
                w,
                y,
                vec![0..n, n..2 * n],
                (0..n).chain(0..n).collect(),
                names,
            )
            .unwrap(),
            beta,
        )
    }

    #[test]
    fn ols_recovers_known_parameters_with_honest_std() {
        let (obs, beta) = problem();
        let e = ols(&obs, 1e-10).unwrap();
        for i in 0..3 {
            assert!(
                (e.values[i] - beta[i]).abs() < 4.0 * e.std[i] + 1e-12,
                "{i}: {} +- {}",
                e.values[i],
                e.std[i]
            );
            // measured 8.6e-4 to 1.24e-3
            assert!(e.std[i] > 4.3e-4 && e.std[i] < 2.4e-3);
        }
        assert_eq!(e.residual_rms.len(), 2);
        // the second output is ten times noisier (measured ratio 8.8)
        assert!(e.residual_rms[1] > 5.0 * e.residual_rms[0]);
        assert!((e.rel_std_percent[0] - 100.0 * e.std[0] / e.values[0].abs()).abs() < 1e-12);
    }

    #[test]
    fn wls_weights_follow_the_noise_and_reduce_std() {
        let (obs, beta) = problem();
        let o = ols(&obs, 1e-10).unwrap();
        let w = wls(&obs, 1e-10).unwrap();
        let weights = w.weights.clone().unwrap();
        // measured ratio 8.8
        assert!(weights[0] > 5.0 * weights[1], "{weights:?}");
        // each weight is 1 / sigma_j, sigma_j^2 = joint j's OLS residual sum of squares over
        // its rows minus their leverages (which add up to the 3 parameters over the joints)
        let gram = (obs.w.transpose() * &obs.w).try_inverse().unwrap();
        let mut leverages = 0.0;
        for (j, rows) in obs.joint_rows.iter().enumerate() {
            let (mut rss, mut leverage) = (0.0, 0.0);
            for k in rows.clone() {
                let x = obs.w.row(k).transpose();
                rss += (obs.y[k] - (0..3).map(|c| x[c] * o.values[c]).sum::<f64>()).powi(2);
                leverage += (x.transpose() * &gram * &x)[(0, 0)];
            }
            leverages += leverage;
            let expected = 1.0 / (rss / (rows.len() as f64 - leverage)).sqrt();
            assert!((weights[j] / expected - 1.0).abs() < 1e-9, "joint {j}");
        }
        assert!((leverages - 3.0).abs() < 1e-9, "{leverages}");
        for i in 0..3 {
            assert!((w.values[i] - beta[i]).abs() < 4.0 * w.std[i]);
        }
        assert!(w.std[0] < o.std[0]);
        // measured 0.895: the quiet joint's weight comes from its OLS residual, which also
        // carries the noisy joint's parameter error, and WLS removes that part
        assert!(
            (w.sigma2 - 1.0).abs() < 0.2,
            "weighted residual variance ~ 1: {}",
            w.sigma2
        );
    }

    /// A joint whose residual is (exactly or nearly) zero gets a finite weight (the floor),
    /// not an infinite one.
    #[test]
    fn a_zero_residual_joint_gets_a_floored_weight() {
        assert_eq!(
            joint_weights(&[0.0, 2.0]),
            vec![1.0 / (SIGMA_FLOOR * 2.0), 0.5]
        );
        assert_eq!(joint_weights(&[0.0, 0.0]), vec![1.0, 1.0]);
        // joint 1 alone determines `a` and is exact; joint 2 is noisy
        let n = 200;
        let mut w = DMatrix::zeros(2 * n, 3);
        let mut y = DVector::zeros(2 * n);
        for k in 0..n {
            let t = k as f64 * 0.05;
            w[(k, 0)] = t.sin();
            y[k] = 2.0 * t.sin();
            w[(n + k, 1)] = t.cos();
            w[(n + k, 2)] = 1.0;
            y[n + k] = -t.cos() + 0.5 + 0.1 * (k as f64 * 7.3).sin();
        }
        let names = vec!["a".into(), "b".into(), "c".into()];
        let obs = Observation::new(
            w,
            y,
            vec![0..n, n..2 * n],
            (0..n).chain(0..n).collect(),
            names,
        )
        .unwrap();
        let e = wls(&obs, 1e-10).unwrap();
        let weights = e.weights.clone().unwrap();
        assert!(weights.iter().all(|v| v.is_finite()), "{weights:?}");
        assert!(
            (weights[0] / weights[1] * SIGMA_FLOOR - 1.0).abs() < 1e-9,
            "{weights:?}"
        );
        assert!(e.values.iter().chain(&e.std).all(|v| v.is_finite()));
        assert!((e.values[0] - 2.0).abs() < 1e-12);
    }

    #[test]
    fn the_rank_tolerance_must_lie_strictly_between_0_and_1() {
        let (obs, _) = problem();
        for bad in [0.0, 1.0, -1e-10, 1.5, f64::NAN, f64::INFINITY] {
            for e in [ols(&obs, bad), wls(&obs, bad)] {
                let e = e.unwrap_err().to_string();
                assert!(e.contains("estimation.rank_tolerance"), "{bad}: {e}");
            }
        }
        assert!(ols(&obs, 0.5).is_ok() && wls(&obs, f64::MIN_POSITIVE).is_ok());
    }

    /// A joint with no more equations than parameters still has residual degrees of
    /// freedom when the fit is shared: its sigma is taken over its rows less their
    /// leverages (not divided by zero), so WLS stays finite.
    #[test]
    fn a_joint_with_as_many_rows_as_parameters_gets_a_finite_weight() {
        let n = 100;
        let rows = n + 3;
        let mut w = DMatrix::zeros(rows, 3);
        let mut y = DVector::zeros(rows);
        for k in 0..rows {
            let t = k as f64 * 0.1;
            w[(k, 0)] = t.sin();
            w[(k, 1)] = t.cos();
            w[(k, 2)] = 1.0;
            y[k] = 2.0 * t.sin() - t.cos() + 0.5 + 0.01 * (k as f64 * 7.3).sin();
        }
        let names = vec!["a".into(), "b".into(), "c".into()];
        let obs = Observation::new(
            w,
            y,
            vec![0..n, n..rows],
            (0..n).chain(0..3).collect(),
            names,
        )
        .unwrap();
        let e = wls(&obs, 1e-10).unwrap();
        let weights = e.weights.clone().unwrap();
        assert!(
            weights.iter().all(|v| v.is_finite() && *v > 0.0),
            "{weights:?}"
        );
        // the three rows of joint 2 still leave a residual (the fit is shared), so its
        // sigma is theirs: sum of squares over 3 rows less their leverages
        let first = ols(&obs, 1e-10).unwrap();
        let gram = (obs.w.transpose() * &obs.w).try_inverse().unwrap();
        let (mut rss, mut leverage) = (0.0, 0.0);
        for k in n..rows {
            let x = obs.w.row(k).transpose();
            let r = obs.y[k] - (0..3).map(|c| x[c] * first.values[c]).sum::<f64>();
            rss += r * r;
            leverage += (x.transpose() * &gram * &x)[(0, 0)];
        }
        assert!(leverage > 0.0 && leverage < 1.0, "{leverage}");
        let sigma2 = (rss / (3.0 - leverage)).sqrt();
        let largest = weights.iter().map(|w| 1.0 / w).fold(0.0, f64::max);
        let expected = 1.0 / sigma2.max(SIGMA_FLOOR * largest);
        assert!(
            (weights[1] / expected - 1.0).abs() < 1e-9,
            "{} vs {expected}",
            weights[1]
        );
    }

    /// Each joint's sigma takes the degrees of freedom its own equations lose to the fit
    /// (their leverages), not all the parameters once per joint: with every joint's
    /// equations in parameters of their own, the joint OLS is each joint's own fit, and
    /// joint j's residual has `r_j - 2` degrees of freedom. Taking `r_j - c` (c = 6),
    /// as before, made every sigma sqrt(38 / 34) = 1.057 times too large, and more for
    /// a joint with fewer equations (sqrt(18 / 14) = 1.13): weights uneven by 7 %.
    #[test]
    fn each_joint_loses_the_degrees_of_freedom_of_its_own_leverage() {
        let counts = [40, 40, 20];
        let rows: usize = counts.iter().sum();
        let mut w = DMatrix::zeros(rows, 6);
        let mut y = DVector::zeros(rows);
        let mut blocks = Vec::new();
        let mut row = 0;
        for (j, &count) in counts.iter().enumerate() {
            for k in 0..count {
                let t = k as f64 * 0.13 + j as f64;
                w[(row + k, 2 * j)] = t.sin();
                w[(row + k, 2 * j + 1)] = 1.0 + 0.3 * t.cos();
                y[row + k] = 1.5 * t.sin() - 0.5 + (j + 1) as f64 * 0.01 * (t * 17.1).sin();
            }
            blocks.push(row..row + count);
            row += count;
        }
        let names = (0..6).map(|i| format!("p{i}")).collect();
        let sample_of_row = blocks.iter().flat_map(|b| 0..b.len()).collect();
        let obs = Observation::new(w, y, blocks.clone(), sample_of_row, names).unwrap();
        let first = ols(&obs, 1e-10).unwrap();
        let weights = wls(&obs, 1e-10).unwrap().weights.unwrap();
        for (j, b) in blocks.iter().enumerate() {
            let rss: f64 = b
                .clone()
                .map(|k| {
                    let r = obs.y[k] - (0..6).map(|c| obs.w[(k, c)] * first.values[c]).sum::<f64>();
                    r * r
                })
                .sum();
            let sigma = (rss / (b.len() - 2) as f64).sqrt();
            assert!(
                (weights[j] * sigma - 1.0).abs() < 1e-9,
                "joint {}: weight {} against 1 / sigma {}",
                j + 1,
                weights[j],
                1.0 / sigma
            );
        }
    }

    /// A standard normal draw from a seeded generator (Box-Muller on a 64-bit LCG).
    fn normal(seed: &mut u64) -> f64 {
        let mut uniform = || {
            *seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((*seed >> 11) as f64 + 0.5) / (1u64 << 53) as f64
        };
        let (a, b) = (uniform(), uniform());
        (-2.0 * a.ln()).sqrt() * (std::f64::consts::TAU * b).cos()
    }

    /// The robust deviations are the spread of the estimates over repeated records of
    /// AR(1) noise (coefficient 0.8, each joint's own), where the classical ones are
    /// about three times too small (sqrt((1 + 0.8) / (1 - 0.8)) = 3 for regressors that
    /// vary slowly against the noise's correlation): 300 seeded records of two joints of
    /// 1,500 samples, OLS and WLS, the lag from the noise's correlation time (20 samples:
    /// 0.8^20 = 0.012). Measured: classical over the spread 0.32 to 0.36, robust 0.84 to
    /// 0.93 (the Bartlett weights at lag 20 take 7.2 of the long-run variance's 9 times
    /// the noise's: 0.89 of its square root).
    #[test]
    fn robust_deviations_are_the_spread_over_records_of_correlated_noise() {
        let (n, records, phi) = (1500, 300, 0.8);
        let x = |j: usize, k: usize, c: usize| {
            let t = k as f64 * 0.01;
            match c {
                0 => (t * (1.0 + j as f64)).sin(),
                1 => (0.7 * t + j as f64).cos(),
                _ => 1.0,
            }
        };
        let beta = [1.0, -2.0, 0.5];
        let w = DMatrix::from_fn(2 * n, 3, |r, c| x(r / n, r % n, c));
        let mut seed = 2026u64;
        // the estimates, the classical and the robust deviations of one record
        type Fit = (Vec<f64>, Vec<f64>, Vec<f64>);
        let mut fits: [Vec<Fit>; 2] = [Vec::new(), Vec::new()];
        for _ in 0..records {
            let mut y = DVector::zeros(2 * n);
            for j in 0..2 {
                // the stationary start, then e_k = phi e_(k-1) + innovation
                let scale = if j == 0 { 0.1 } else { 0.3 };
                let mut e = normal(&mut seed) / (1.0f64 - phi * phi).sqrt();
                for k in 0..n {
                    if k > 0 {
                        e = phi * e + normal(&mut seed);
                    }
                    let r = j * n + k;
                    y[r] = (0..3).map(|c| w[(r, c)] * beta[c]).sum::<f64>() + scale * e;
                }
            }
            let mut obs = Observation::new(
                w.clone(),
                y,
                vec![0..n, n..2 * n],
                (0..n).chain(0..n).collect(),
                vec!["a".into(), "b".into(), "c".into()],
            )
            .unwrap();
            obs.correlated = 20;
            for (m, e) in [ols(&obs, 1e-10), wls(&obs, 1e-10)].into_iter().enumerate() {
                let e = e.unwrap();
                let robust = e.robust.clone().unwrap();
                assert_eq!((robust.lag, robust.samples), (20, n));
                fits[m].push((e.values, e.std, robust.std));
            }
        }
        for (m, fits) in fits.iter().enumerate() {
            for i in 0..3 {
                let mean = fits.iter().map(|f| f.0[i]).sum::<f64>() / records as f64;
                let spread = (fits.iter().map(|f| (f.0[i] - mean).powi(2)).sum::<f64>()
                    / (records - 1) as f64)
                    .sqrt();
                let rms = |s: &dyn Fn(&Fit) -> f64| {
                    (fits.iter().map(|f| s(f).powi(2)).sum::<f64>() / records as f64).sqrt()
                };
                let classical = rms(&|f| f.1[i]) / spread;
                let robust = rms(&|f| f.2[i]) / spread;
                eprintln!(
                    "method {m}, parameter {i}: classical {classical:.3}, robust {robust:.3}"
                );
                assert!(
                    classical < 0.5,
                    "method {m}, parameter {i}: classical {classical}"
                );
                assert!(
                    (0.75..1.15).contains(&robust),
                    "method {m}, parameter {i}: robust {robust}"
                );
            }
        }
    }

    /// A parameter known to 60 % by the classical deviation and to 170 % by the robust
    /// one (AR(1) noise, coefficient 0.8: the robust deviations three times the
    /// classical) is uncertain, in OLS and WLS alike, and the warning says it judged by
    /// the larger; the value is placed at the geometric mean of the two deviations (the
    /// deviations and the noise's error do not depend on it).
    #[test]
    fn uncertainty_is_judged_by_the_larger_deviation() {
        let n = 1500;
        let w = DMatrix::from_fn(2 * n, 2, |r, c| match c {
            0 => (r as f64 * 0.01 * (1.0 + (r / n) as f64)).sin(),
            _ => 1.0,
        });
        let mut seed = 7u64;
        let noise = DVector::from_iterator(
            2 * n,
            (0..2 * n).scan(0.0, |e, k| {
                *e = if k % n == 0 { 0.0 } else { 0.8 * *e } + normal(&mut seed);
                Some(0.3 * *e)
            }),
        );
        let record = |c: f64| {
            let mut obs = Observation::new(
                w.clone(),
                &w * DVector::from_vec(vec![1.0, c]) + &noise,
                vec![0..n, n..2 * n],
                (0..n).chain(0..n).collect(),
                vec!["a".into(), "c".into()],
            )
            .unwrap();
            obs.correlated = 20;
            obs
        };
        for fit in [ols, wls] {
            let pilot = fit(&record(0.5), 1e-10).unwrap();
            let (std, robust) = (pilot.std[1], pilot.robust.as_ref().unwrap().std[1]);
            assert!(robust > 2.0 * std, "{std} {robust}");
            let target = (std * robust).sqrt();
            let e = fit(&record(target - (pilot.values[1] - 0.5)), 1e-10).unwrap();
            assert!((e.values[1] - target).abs() < 1e-9 * target);
            assert!(e.rel_std_percent[1] < 100.0, "{:?}", e.rel_std_percent);
            let uncertain: Vec<_> = e
                .warnings
                .iter()
                .filter(|w| w.kind() == "uncertain")
                .collect();
            assert_eq!(uncertain.len(), 1, "{:?}", e.warnings);
            assert_eq!(uncertain[0].parameters(), ["c"]);
            let said = uncertain[0].to_string();
            let rel = 100.0 * robust / target;
            assert!(
                said.contains("uncertain by more than its own size; the larger of the classical and the robust deviation): c ("),
                "{said}"
            );
            assert!(said.ends_with(&format!("c ({rel:.0} %)")), "{said} {rel}");
            assert_eq!(e.judged_std()[1], e.robust.as_ref().unwrap().std[1]);
        }
        // without the robust deviations (the energy model, static poses, robust_std =
        // false) the classical ones judge: nothing uncertain
        let c = {
            let pilot = ols(&record(0.5), 1e-10).unwrap();
            let (std, robust) = (pilot.std[1], pilot.robust.as_ref().unwrap().std[1]);
            (std * robust).sqrt() - (pilot.values[1] - 0.5)
        };
        for e in [
            ols_with(&record(c), 1e-10, false).unwrap(),
            wls_with(&record(c), 1e-10, false).unwrap(),
        ] {
            assert!(e.robust.is_none());
            assert!(
                e.warnings.iter().all(|w| w.kind() != "uncertain"),
                "{:?}",
                e.warnings
            );
        }
    }

    /// The deviations of a column near 1e200 (a parameter of about 1e-200 units) or of a
    /// problem in 1e100 units are those of the same problem in units, scaled: the
    /// classical ones came out 0 (sigma^2 (W'W)^-1_jj underflowed: 0 % of the value) and
    /// the robust ones none (their scores squared to infinity), where each is now taken
    /// with the column scales apart. OLS and WLS, to 1e-10.
    #[test]
    fn huge_columns_keep_their_deviations() {
        let n = 200;
        let w = DMatrix::from_fn(n, 2, |k, c| match c {
            0 => 1.0 + 0.1 * (k as f64).sin(),
            _ => (k as f64 * 0.37).cos(),
        });
        let y = DVector::from_fn(n, |k, _| {
            0.5 + (k as f64 * 1.7).cos() + 0.3 * (k as f64 * 0.9).sin()
        });
        let names = vec!["a".to_string(), "b".to_string()];
        let units = Observation::single(w.clone(), y.clone(), names.clone()).unwrap();
        // column b in 1e200 times its units (its parameter 1e-200 times); the whole problem
        // in 1e100 times them
        let mut huge_b = w.clone();
        huge_b.column_mut(1).scale_mut(1e200);
        let huge_b = Observation::single(huge_b, y.clone(), names.clone()).unwrap();
        let all = Observation::single(&w * 1e100, &y * 1e100, names).unwrap();
        for fit in [ols, wls] {
            let e = fit(&units, 1e-10).unwrap();
            let robust = e.robust.clone().unwrap().std;
            for (other, scale) in [(&huge_b, [1.0, 1e-200]), (&all, [1.0, 1.0])] {
                let h = fit(other, 1e-10).unwrap();
                let h_robust = h.robust.clone().expect("robust deviations").std;
                for j in 0..2 {
                    for (got, want) in [(h.std[j], e.std[j]), (h_robust[j], robust[j])] {
                        assert!(
                            (got / scale[j] / want - 1.0).abs() < 1e-10,
                            "{j}: {got:e} against {want:e} x {:e}",
                            scale[j]
                        );
                    }
                    assert!((h.rel_std_percent[j] / e.rel_std_percent[j] - 1.0).abs() < 1e-10);
                }
            }
        }
    }

    /// Torques of 1e-170 (and W and y both scaled by 1e-200) have the deviations of the
    /// same problem in units, scaled: the squared residuals underflowed and OLS and WLS
    /// reported deviations of exactly 0, no warning. To 1e-12.
    #[test]
    fn tiny_torques_keep_their_deviations() {
        let w = DMatrix::from_fn(10, 2, |r, c| ((r + 1) as f64).powi(c as i32 + 1));
        let y = DVector::from_fn(10, |r, _| r as f64 - 3.0);
        let names = vec!["A".to_string(), "B".to_string()];
        let units = Observation::single(w.clone(), y.clone(), names.clone()).unwrap();
        let tiny_y = Observation::single(w.clone(), &y * 1e-170, names.clone()).unwrap();
        let tiny_all = Observation::single(&w * 1e-200, &y * 1e-200, names).unwrap();
        for fit in [ols, wls] {
            let e = fit(&units, 1e-10).unwrap();
            // (the deviations' scale, the torques')
            for (other, scale, torque) in [(&tiny_y, 1e-170, 1e-170), (&tiny_all, 1.0, 1e-200)] {
                let t = fit(other, 1e-10).unwrap();
                for j in 0..2 {
                    assert!(
                        (t.std[j] / scale / e.std[j] - 1.0).abs() < 1e-12,
                        "{j}: {:e} against {:e} x {scale:e}",
                        t.std[j],
                        e.std[j]
                    );
                }
                let rms = t.residual_rms[0] / (torque * e.residual_rms[0]);
                assert!((rms - 1.0).abs() < 1e-12, "{rms}");
            }
        }
    }

    #[test]
    fn duplicate_names_are_an_error() {
        assert!(check_names(&["a".into(), "b".into(), "a".into()]).is_err());
        assert!(check_names(&["a".into(), "b".into()]).is_ok());
    }
}
