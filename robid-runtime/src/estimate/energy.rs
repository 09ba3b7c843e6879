//! The energy (power balance) identification model.
//!
//! Over a window [t_a, t_b]: H(t_b) - H(t_a) + integral of the dissipated power
//! = integral of tau . qd dt, where H = h(q, qd) . beta (kinetic plus potential energy,
//! linear in the parameters) and the dissipated power d(q, qd) . beta holds the friction
//! terms (Fv_j qd_j^2, Fc_j |qd_j|, Fo_j qd_j). No accelerations are needed.
//! Integrals use a rule exact for cubics on the samples ([`quadrature`]).
//!
//! ## Reference
//! M. Gautier, "Dynamic identification of robots with power model", ICRA 1997.

use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;

use crate::LengthError;
use crate::Model;
use crate::error::{Error, Result};
use crate::estimate::{Estimate, Observation, ols_with};
use crate::model::{DriveTerm, ParameterId, ParameterKind};
use crate::pipeline::Prepared;
use crate::signal::Signals;

/// The energy regressor: writes h(q, qd) (one entry per parameter) into the last argument.
pub trait EnergyRegressor: Fn(&[f64], &[f64], &mut [f64]) + Sync {}
impl<F: Fn(&[f64], &[f64], &mut [f64]) + Sync> EnergyRegressor for F {}

/// Builds the energy observation: one equation per window of `window` samples.
/// `signals` are prepared joint signals (positions, velocities, torques; accelerations
/// are not used), e.g. from [`crate::pipeline::prepare`]; `h` is the energy regressor,
/// `dissipation` the dissipated-power regressor (see [`friction_power`]).
pub fn energy_observation(
    signals: &Prepared,
    window: usize,
    names: Vec<String>,
    h: &impl EnergyRegressor,
    dissipation: &impl EnergyRegressor,
) -> Result<Observation> {
    let (q, qd, tau, dt) = (&signals.q, &signals.qd, &signals.tau, signals.sample_time);
    let (dof, n) = (q.dof(), q.samples());
    let p = names.len();
    let same = |x: &Signals| x.dof() == dof && x.samples() == n;
    if window == 0 || n < window + 1 || !same(qd) || !same(tau) {
        return Err(Error::TooFewSamples {
            context: "energy model".into(),
            found: n,
            required: window.max(1) + 1,
            hint: "use a window shorter than the record and one signal per joint",
        });
    }
    let sample = |k: usize, x: &Signals| x.sample(k);
    let power = |k: usize| (0..dof).map(|j| tau[j][k] * qd[j][k]).sum::<f64>();
    let windows = (n - 1) / window;
    let weights = quadrature(window, dt);
    let rows: Vec<(Vec<f64>, f64)> = (0..windows)
        .into_par_iter()
        .map(|i| {
            let (a, b) = (i * window, (i + 1) * window);
            let mut ha = vec![0.0; p];
            let mut hb = vec![0.0; p];
            h(&sample(a, q), &sample(a, qd), &mut ha);
            h(&sample(b, q), &sample(b, qd), &mut hb);
            let mut row: Vec<f64> = hb.iter().zip(&ha).map(|(x, y)| x - y).collect();
            let mut d = vec![0.0; p];
            let mut y = 0.0;
            for (k, wgt) in (a..=b).zip(&weights) {
                dissipation(&sample(k, q), &sample(k, qd), &mut d);
                for (r, v) in row.iter_mut().zip(&d) {
                    *r += wgt * v;
                }
                y += wgt * power(k);
            }
            Ok((row, y))
        })
        .collect::<std::result::Result<_, LengthError>>()?;
    let w = DMatrix::from_fn(windows, p, |r, c| rows[r].0[c]);
    let y = DVector::from_iterator(windows, rows.iter().map(|r| r.1));
    Observation::single(w, y, names)
}

/// The energy observation of a [`Model`] in its base parameters, one equation per window
/// of `window` samples of the prepared signals (accelerations are not used):
///
/// T(t_b) - T(t_a) + integral of g(q).qd dt + friction integrals = integral of tau.qd dt,
///
/// with everything linear in the base parameters and taken from the base regressor, the
/// only thing the [`Model`] trait offers per parameter: M(q) qd = Y_b(q, 0, qd) - Y_b(q, 0, 0)
/// gives the kinetic energy T = 1/2 qd' M(q) qd (rotor inertias included), and
/// Y_b(q, 0, 0) gives the gravity torques, so that U(t_b) - U(t_a) = integral of g(q).qd dt
/// (and the offsets Fo_j, constant torques, integrate to Fo_j (q_j(t_b) - q_j(t_a))). The
/// base parameters named `Fv{j}` and `Fc{j}` dissipate Fv_j qd_j^2 and Fc_j |qd_j| (see
/// [`friction_power`]). Integrals use [`quadrature`]'s weights.
pub fn model_energy_observation(
    model: &(dyn Model + Sync),
    signals: &Prepared,
    window: usize,
) -> Result<Observation> {
    let dof = model.dof();
    let p = model.base_parameter_count();
    let names = crate::model::base_parameter_names(model);
    signals.check(dof, "energy model: data")?;
    let friction = friction_power(&names);
    // columns whose power is the friction term (Fv, Fc; Fo is in the potential part)
    let mut probe = vec![0.0; p];
    friction(&vec![0.0; dof], &vec![1.0; dof], &mut probe);
    let dissipative: Vec<bool> = names
        .iter()
        .zip(&probe)
        .map(|(n, v)| {
            let offset = ParameterKind::Drive(DriveTerm::Fo);
            *v != 0.0 && n.parse::<ParameterId>().map_or(true, |p| p.kind != offset)
        })
        .collect();
    let zeros = vec![0.0; dof];
    // per sample: the kinetic energy per parameter (window ends only) and the power
    // g(q).qd + friction per parameter, both from at most two regressor calls
    let energy_at = |q: &[f64], qd: &[f64], y0: &mut [f64], y1: &mut [f64], out: &mut [f64]| {
        model.base_regressor_into(q, &zeros, &zeros, y0)?;
        model.base_regressor_into(q, &zeros, qd, y1)?;
        for (i, o) in out.iter_mut().enumerate() {
            *o = 0.5
                * (0..dof)
                    .map(|j| qd[j] * (y1[j * p + i] - y0[j * p + i]))
                    .sum::<f64>();
        }
        Ok::<(), LengthError>(())
    };
    let power_at = |q: &[f64], qd: &[f64], y0: &mut [f64], d: &mut [f64], out: &mut [f64]| {
        model.base_regressor_into(q, &zeros, &zeros, y0)?;
        friction(q, qd, d);
        for (i, o) in out.iter_mut().enumerate() {
            *o = if dissipative[i] {
                d[i]
            } else {
                (0..dof).map(|j| qd[j] * y0[j * p + i]).sum::<f64>()
            };
        }
        Ok::<(), LengthError>(())
    };
    let n = signals.samples();
    if window == 0 || n < window + 1 {
        return Err(Error::TooFewSamples {
            context: "energy model".into(),
            found: n,
            required: window.max(1) + 1,
            hint: "use a window shorter than the record (estimation.energy_window)",
        });
    }
    let windows = (n - 1) / window;
    let weights = quadrature(window, signals.sample_time);
    let rows: Vec<(Vec<f64>, f64)> = (0..windows)
        .into_par_iter()
        .map(|w| {
            let (a, b) = (w * window, (w + 1) * window);
            let (mut q, mut qd) = (vec![0.0; dof], vec![0.0; dof]);
            let mut y0 = vec![0.0; dof * p];
            let mut y1 = vec![0.0; dof * p];
            let mut d = vec![0.0; p];
            let mut cur = vec![0.0; p];
            let mut row = vec![0.0; p];
            let mut y = 0.0;
            let load = |k: usize, q: &mut [f64], qd: &mut [f64]| {
                signals.q.sample_into(k, q);
                signals.qd.sample_into(k, qd);
            };
            for (k, sign) in [(a, -1.0), (b, 1.0)] {
                load(k, &mut q, &mut qd);
                energy_at(&q, &qd, &mut y0, &mut y1, &mut cur)?;
                for (r, v) in row.iter_mut().zip(&cur) {
                    *r += sign * v;
                }
            }
            for (k, wgt) in (a..=b).zip(&weights) {
                load(k, &mut q, &mut qd);
                power_at(&q, &qd, &mut y0, &mut d, &mut cur)?;
                for (r, v) in row.iter_mut().zip(&cur) {
                    *r += wgt * v;
                }
                y += wgt * (0..dof).map(|j| signals.tau[j][k] * qd[j]).sum::<f64>();
            }
            Ok((row, y))
        })
        .collect::<std::result::Result<_, LengthError>>()?;
    let w = DMatrix::from_fn(windows, p, |r, c| rows[r].0[c]);
    let y = DVector::from_iterator(windows, rows.iter().map(|r| r.1));
    Observation::single(w, y, names)
}

/// The weights of the integral over `intervals` steps of `dt` from the `intervals + 1`
/// samples at their ends, exact for cubics from two steps on: Simpson's rule (two or four
/// steps), its three-eighths rule (three), and from five steps the extended rule whose
/// weights are 1 but for three at each end, `3/8, 7/6, 23/24` (Press et al., *Numerical
/// Recipes*, eq. 4.1.14), which weighs the samples' noise almost evenly; one step is the
/// trapezoid. The trapezoidal rule throughout made the energy model's estimates wrong by
/// 1.9 % on exact 100 Hz data (0.05 s windows of five steps), an error of order `dt^2`.
///
/// ```
/// use robid_runtime::estimate::quadrature;
/// // the integral of t^3 over [0, 1] from six samples
/// let w = quadrature(5, 0.2);
/// let i: f64 = w.iter().enumerate().map(|(k, w)| w * (0.2 * k as f64).powi(3)).sum();
/// assert!((i - 0.25).abs() < 1e-15);
/// ```
pub fn quadrature(intervals: usize, dt: f64) -> Vec<f64> {
    let units: Vec<f64> = match intervals {
        0 => vec![0.0],
        1 => vec![0.5, 0.5],
        3 => vec![3.0 / 8.0, 9.0 / 8.0, 9.0 / 8.0, 3.0 / 8.0],
        2 | 4 => (0..=intervals)
            .map(|k| match k {
                0 => 1.0 / 3.0,
                k if k == intervals => 1.0 / 3.0,
                k if k % 2 == 1 => 4.0 / 3.0,
                _ => 2.0 / 3.0,
            })
            .collect(),
        _ => {
            let mut w = vec![1.0; intervals + 1];
            for (k, e) in [3.0 / 8.0, 7.0 / 6.0, 23.0 / 24.0].into_iter().enumerate() {
                w[k] = e;
                w[intervals - k] = e;
            }
            w
        }
    };
    units.into_iter().map(|w| w * dt).collect()
}

/// The energy model solved by least squares.
pub fn energy(obs: &Observation, tolerance: f64) -> Result<Estimate> {
    // the windows' integrals overlap no lag rule's samples: no robust deviations (as
    // documented)
    let mut e = ols_with(obs, tolerance, false)?;
    e.method = crate::estimate::Estimator::Energy;
    Ok(e)
}

/// Dissipated-power regressor from parameter names: `Fv{j}` -> qd_j^2,
/// `Fc{j}` -> |qd_j|, `Fo{j}` -> qd_j (joints from 1); other parameters, and friction
/// terms that were regrouped with others, -> 0.
pub fn friction_power(names: &[String]) -> impl EnergyRegressor + use<> {
    let terms: Vec<(usize, DriveTerm, usize)> = names
        .iter()
        .enumerate()
        .filter_map(|(i, n)| match n.parse::<ParameterId>().ok()? {
            ParameterId {
                link,
                kind: ParameterKind::Drive(t @ (DriveTerm::Fv | DriveTerm::Fc | DriveTerm::Fo)),
            } => Some((i, t, link)),
            _ => None,
        })
        .collect();
    move |_q: &[f64], qd: &[f64], out: &mut [f64]| {
        out.iter_mut().for_each(|v| *v = 0.0);
        for &(i, kind, j) in &terms {
            let v = qd.get(j).copied().unwrap_or(0.0);
            out[i] = match kind {
                DriveTerm::Fv => v * v,
                DriveTerm::Fc => v.abs(),
                _ => v,
            };
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simulate::tests::Pendulum;

    /// The energy observation of a model (the planar 2R arm with viscous and Coulomb
    /// friction), on an exact motion with the inverse-dynamics torques, gives back every
    /// base parameter: the kinetic, potential and dissipated parts are all checked.
    #[test]
    fn model_energy_recovers_every_base_parameter_of_a_2r_arm() {
        let model = Pendulum::default();
        let (rate, n) = (2000.0, 20_000);
        let signals = swinging_2r(&model, rate, n);
        let truth = model.base();
        let obs = model_energy_observation(&model, &signals, 100).unwrap();
        assert_eq!(obs.rows(), 199);
        let e = energy(&obs, 1e-12).unwrap();
        for (i, (v, t)) in e.values.iter().zip(&truth).enumerate() {
            // the only error is the integrals': measured largest 2.2e-11 (Fc1), against
            // parameters of 0.05 to 3 (8.4e-7 with the trapezoidal rule)
            assert!((v - t).abs() < 1e-9, "{}: {v} vs {t}", e.names[i]);
        }
        // the window must fit in the record (one window plus a sample: n - 1 fits, n does
        // not, and the refusal says how many samples it needs), and the data must have the
        // model's joints
        assert_eq!(
            model_energy_observation(&model, &signals, n - 1)
                .unwrap()
                .rows(),
            1
        );
        match model_energy_observation(&model, &signals, n) {
            Err(crate::Error::TooFewSamples {
                found, required, ..
            }) => assert_eq!((found, required), (n, n + 1)),
            other => panic!("{other:?}"),
        }
        let mut one = signals.clone();
        one.q = one.q.range(0..0);
        assert!(model_energy_observation(&model, &one, 100).is_err());
    }

    /// At 100 Hz, with windows of two to nine steps (the default 0.05 s is five), the
    /// estimates are the parameters to 1e-6: with the trapezoidal rule the integrals' error
    /// of order dt^2 took them 2.3e-4 away on this arm (1.9 % on a random 6-joint arm at
    /// 100 Hz in an independent review), for every window length.
    #[test]
    fn model_energy_is_accurate_at_a_low_sample_rate() {
        let model = Pendulum::default();
        let truth = model.base();
        let signals = swinging_2r(&model, 100.0, 3000);
        let worst = |window: usize| {
            let e = energy(
                &model_energy_observation(&model, &signals, window).unwrap(),
                1e-12,
            )
            .unwrap();
            e.values
                .iter()
                .zip(&truth)
                .map(|(v, t)| (v - t).abs())
                .fold(0.0, f64::max)
        };
        // one step is the trapezoid: measured 2.3e-4, as every window had (2.3e-4)
        assert!(worst(1) > 1e-4, "{}", worst(1));
        for window in 2..10 {
            // measured 1.4e-7 (two and four steps) to 5.6e-7 (nine)
            assert!(worst(window) < 1e-6, "{window} steps: {}", worst(window));
        }
    }

    /// The weights of every window length integrate polynomials as their rule promises:
    /// cubics exactly from two steps on, lines with one; they sum to the window's length.
    #[test]
    fn quadrature_is_exact_for_cubics() {
        for intervals in 1..14 {
            let dt = 0.37;
            let w = quadrature(intervals, dt);
            assert_eq!(w.len(), intervals + 1);
            let degree = if intervals == 1 { 1 } else { 3 };
            for p in 0..=degree {
                let sum: f64 = w
                    .iter()
                    .enumerate()
                    .map(|(k, w)| w * (dt * k as f64).powi(p))
                    .sum();
                let exact = (dt * intervals as f64).powi(p + 1) / f64::from(p + 1);
                assert!(
                    (sum - exact).abs() < 1e-13 * exact.max(1.0),
                    "{intervals} steps, t^{p}: {sum} vs {exact}"
                );
            }
        }
    }

    /// The 2R arm of [`Pendulum`] swinging through gravity with velocity reversals, `n`
    /// samples at `rate`, torques from its inverse dynamics at the true parameters.
    fn swinging_2r(model: &Pendulum, rate: f64, n: usize) -> Prepared {
        let truth = model.base();
        let (mut q, mut qd, mut qdd) = (
            Signals::zeros(2, n),
            Signals::zeros(2, n),
            Signals::zeros(2, n),
        );
        let mut qdd_k = [0.0; 2];
        let mut tau = Signals::zeros(2, n);
        let mut out = [0.0; 2];
        for k in 0..n {
            let t = k as f64 / rate;
            for j in 0..2 {
                let w = 1.1 + 0.9 * j as f64;
                let (a, b) = (0.9 / (j + 1) as f64, 0.4);
                // velocities change sign (Coulomb) and the arm swings through gravity
                q[j][k] = a * (w * t).sin() + b * (2.7 * w * t).cos();
                qd[j][k] = a * w * (w * t).cos() - b * 2.7 * w * (2.7 * w * t).sin();
                qdd_k[j] = -a * w * w * (w * t).sin() - b * (2.7 * w).powi(2) * (2.7 * w * t).cos();
                qdd[j][k] = qdd_k[j];
            }
            let (x, v) = (q.sample(k), qd.sample(k));
            model
                .inverse_dynamics_into(&x, &v, &qdd_k, &truth, &mut out)
                .unwrap();
            tau[0][k] = out[0];
            tau[1][k] = out[1];
        }
        Prepared {
            q,
            qd,
            qdd,
            tau,
            rotor: None,
            sample_time: 1.0 / rate,
        }
    }

    /// The signals must agree with the positions in joints and samples, and the record must
    /// hold one window plus a sample: each mismatch alone is refused, the smallest record
    /// accepted.
    #[test]
    fn energy_observation_checks_its_signals() {
        let names: Vec<String> = vec!["ZZ1".into()];
        let h = |_: &[f64], qd: &[f64], out: &mut [f64]| out[0] = 0.5 * qd[0] * qd[0];
        let d = |_: &[f64], _: &[f64], out: &mut [f64]| out[0] = 0.0;
        let one = |n: usize| Signals::new(vec![vec![1.0; n]]).unwrap();
        let two = |n: usize| Signals::new(vec![vec![1.0; n]; 2]).unwrap();
        let prepared = |qd: Signals, tau: Signals| Prepared {
            q: one(11),
            qd,
            qdd: Signals::zeros(1, 11),
            tau,
            rotor: None,
            sample_time: 0.01,
        };
        let run = |p: &Prepared, window: usize| {
            energy_observation(p, window, names.clone(), &h, &d).map(|o| o.rows())
        };
        assert_eq!(run(&prepared(one(11), one(11)), 10).unwrap(), 1);
        match run(&prepared(one(11), one(11)), 11) {
            Err(crate::Error::TooFewSamples {
                found, required, ..
            }) => assert_eq!((found, required), (11, 12)),
            other => panic!("{other:?}"),
        }
        assert!(run(&prepared(one(11), one(11)), 0).is_err());
        for (qd, tau) in [
            (one(10), one(11)),
            (one(11), one(10)),
            (two(11), one(11)),
            (one(11), two(11)),
        ] {
            assert!(run(&prepared(qd, tau), 5).is_err());
        }
    }

    /// Known rows: with qd_k = k, H = qd^2 / 2 and tau = 1, the windows [0, 5] and [5, 10]
    /// give H differences 12.5 and 37.5 and power integrals (dt = 0.01, exact for a line
    /// under every rule) 0.125 and 0.375.
    #[test]
    fn energy_rows_are_the_windows_differences_and_integrals() {
        let names: Vec<String> = vec!["ZZ1".into()];
        let h = |_: &[f64], qd: &[f64], out: &mut [f64]| out[0] = 0.5 * qd[0] * qd[0];
        let d = |_: &[f64], _: &[f64], out: &mut [f64]| out[0] = 0.0;
        let ramp: Vec<f64> = (0..11).map(f64::from).collect();
        let p = Prepared {
            q: Signals::new(vec![vec![0.0; 11]]).unwrap(),
            qd: Signals::new(vec![ramp]).unwrap(),
            qdd: Signals::zeros(1, 11),
            tau: Signals::new(vec![vec![1.0; 11]]).unwrap(),
            rotor: None,
            sample_time: 0.01,
        };
        let o = energy_observation(&p, 5, names, &h, &d).unwrap();
        assert_eq!(o.rows(), 2);
        for (r, (w, y)) in [(12.5, 0.125), (37.5, 0.375)].into_iter().enumerate() {
            assert!((o.w[(r, 0)] - w).abs() < 1e-12, "{}", o.w);
            assert!((o.y[r] - y).abs() < 1e-12, "{}", o.y);
        }
    }

    /// A pendulum with viscous friction: H = 1/2 I qd^2 + m g l (1 - cos q).
    #[test]
    fn pendulum_energy_recovers_inertia_gravity_and_friction() {
        let (inertia, mgl, fv) = (0.8, 3.0, 0.2);
        let dt = 1e-4;
        let n = 200_000;
        let (mut q, mut qd) = (vec![0.0; n], vec![0.0; n]);
        let mut tau = vec![0.0; n];
        let (mut x, mut v) = (0.3f64, 0.0f64);
        for k in 0..n {
            let t = k as f64 * dt;
            let u = 2.0 * (1.3 * t).sin() + 1.5 * (3.1 * t).cos();
            q[k] = x;
            qd[k] = v;
            tau[k] = u;
            let acc = (u - mgl * x.sin() - fv * v) / inertia;
            // semi-implicit Euler at a fine step, the data are the states
            v += acc * dt;
            x += v * dt;
        }
        let names: Vec<String> = vec!["ZZ1".into(), "MGL".into(), "Fv1".into()];
        let h = |q: &[f64], qd: &[f64], out: &mut [f64]| {
            out[0] = 0.5 * qd[0] * qd[0];
            out[1] = 1.0 - q[0].cos();
            out[2] = 0.0;
        };
        let signals = Prepared {
            q: Signals::new(vec![q]).unwrap(),
            qd: Signals::new(vec![qd]).unwrap(),
            qdd: Signals::zeros(1, n),
            tau: Signals::new(vec![tau]).unwrap(),
            rotor: None,
            sample_time: dt,
        };
        let obs =
            energy_observation(&signals, 500, names.clone(), &h, &friction_power(&names)).unwrap();
        let e = energy(&obs, 1e-10).unwrap();
        // no robust deviations for the energy model (as documented)
        assert!(e.robust.is_none());
        // measured relative errors 9.7e-6 and 1.6e-5, and 6.4e-5 N m s/rad for fv
        assert!(
            (e.values[0] - inertia).abs() < 2e-5 * inertia,
            "{:?}",
            e.values
        );
        assert!((e.values[1] - mgl).abs() < 3e-5 * mgl, "{:?}", e.values);
        assert!((e.values[2] - fv).abs() < 1.3e-4, "{:?}", e.values);
    }

    #[test]
    fn friction_power_terms() {
        let names: Vec<String> = ["XX1", "Fv2", "Fc1", "Fo2"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        let d = friction_power(&names);
        let mut out = [9.0; 4];
        d(&[0.0, 0.0], &[-2.0, 3.0], &mut out);
        assert_eq!(out, [0.0, 9.0, 2.0, 3.0]);
    }

    #[test]
    fn too_short_record_is_an_error() {
        let h = |_: &[f64], _: &[f64], _: &mut [f64]| {};
        let short = Prepared {
            q: Signals::zeros(1, 5),
            qd: Signals::zeros(1, 5),
            qdd: Signals::zeros(1, 5),
            tau: Signals::zeros(1, 5),
            rotor: None,
            sample_time: 0.1,
        };
        let e = energy_observation(&short, 10, vec!["a".into()], &h, &h);
        assert!(matches!(e, Err(Error::TooFewSamples { .. })));
    }
}
