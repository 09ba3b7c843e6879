//! Identification of one joint's rotor friction from samples `(w, tl, T, f)` by nonlinear
//! least squares (docs/identification.md#nonlinear-rotor-friction).
//!
//! The variables are `x = (Fc, Fl, Fs, ln ws, Fv, kc, kv)`; `T0` and `eps` are fixed (`T0`
//! by default the mean temperature of the samples). The logarithm keeps `ws` positive. For
//! fixed `ws` and `kc = kv = 0` the model is linear in `(Fc, Fl, Fs, Fv)`: the start is the
//! best non-negative linear least-squares fit over a log-spaced grid of `ws` across the
//! samples' velocities. From there argmin's trust-region method with Steihaug's
//! conjugate-gradient subproblem refines every free variable on the Gauss-Newton Hessian
//! `2 J'J` (analytic `J`), the variables scaled so that the columns of `J` have unit norm at
//! the start. `Fc`, `Fl`, `Fs`, `Fv` cannot be negative: one the data pull below 0 is fixed
//! at 0 and the rest refitted (an active set), and the result says so.
//!
//! What the samples cannot tell is fixed, not guessed: `kc` and `kv` at 0 when the
//! temperature spans less than [`TEMPERATURE_SPREAD`], `Fl` at 0 when `|tl|` spans less
//! than [`LOAD_SPREAD`]; [`FrictionFit::fixed`] lists each with the reason.

use argmin::core::{CostFunction, Executor, Gradient, Hessian};
use argmin::solver::trustregion::{Steihaug, TrustRegion};
use nalgebra::{DMatrix, DVector, Matrix4, Vector4};

use super::{DEFAULT_SMOOTHING, JointFriction};
use crate::Num;
use crate::error::{Error, Result, num};

/// The temperature span (K) below which `kc` and `kv` are fixed at 0: over less than a
/// Kelvin `exp(-k dT)` differs from 1 by about `0.01 k`, which noise and the Coulomb and
/// viscous levels absorb (and temperature sensors of drives resolve 0.1 to 1 K).
pub const TEMPERATURE_SPREAD: f64 = 1.0;

/// The span of `|tl|` (N m) below which `Fl` is fixed at 0: `Fl |tl|` is then a constant,
/// which `Fc` holds (0.1 N m is the resolution of a typical joint-torque estimate).
pub const LOAD_SPREAD: f64 = 0.1;

/// The number of variables.
const PARAMETERS: usize = 7;
/// Points of the start's grid of Stribeck velocities.
const STRIBECK_GRID: usize = 16;
/// Trust-region iterations per solver run, and runs at most: the fit stops earlier when a
/// run lowers the sum of squares by less than [`STALL`] of itself.
const CHUNK: u64 = 25;
/// See [`CHUNK`].
const RUNS: usize = 20;
/// See [`CHUNK`]: a relative fall that changes no digit a fit to noisy data can tell.
const STALL: f64 = 1e-12;
/// Conjugate-gradient steps per trust-region subproblem (more than the 7 variables, for
/// rounding).
const STEIHAUG_ITERATIONS: u64 = 50;

/// One sample of a joint's rotor friction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrictionSample {
    /// `w`, the rotor velocity reflected to the link side, rad/s.
    pub velocity: f64,
    /// `tl`, the load (joint) torque, N m.
    pub load: f64,
    /// `T`, the temperature, deg C.
    pub temperature: f64,
    /// `f`, the friction torque measured, N m.
    pub friction: f64,
}

/// Settings of [`identify_friction`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrictionFitOptions {
    /// `T0`, deg C; `None`: the mean temperature of the samples.
    pub reference_temperature: Option<f64>,
    /// `eps` of the smooth sign, rad/s (the model's, so that simulation and
    /// identification agree).
    pub smoothing: f64,
}

impl Default for FrictionFitOptions {
    fn default() -> FrictionFitOptions {
        FrictionFitOptions {
            reference_temperature: None,
            smoothing: DEFAULT_SMOOTHING,
        }
    }
}

/// A parameter of [`JointFriction`] that the fit estimates.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FrictionParameter {
    /// `Fc`.
    Coulomb,
    /// `Fl`.
    Load,
    /// `Fs`.
    Stribeck,
    /// `ws`.
    StribeckVelocity,
    /// `Fv`.
    Viscous,
    /// `kc`.
    CoulombTemperature,
    /// `kv`.
    ViscousTemperature,
}

impl FrictionParameter {
    /// In the order of the fit's variables.
    pub const ALL: [FrictionParameter; PARAMETERS] = [
        FrictionParameter::Coulomb,
        FrictionParameter::Load,
        FrictionParameter::Stribeck,
        FrictionParameter::StribeckVelocity,
        FrictionParameter::Viscous,
        FrictionParameter::CoulombTemperature,
        FrictionParameter::ViscousTemperature,
    ];

    /// The field of [`JointFriction`] (and of the TOML file).
    pub fn name(self) -> &'static str {
        match self {
            FrictionParameter::Coulomb => "coulomb",
            FrictionParameter::Load => "load",
            FrictionParameter::Stribeck => "stribeck",
            FrictionParameter::StribeckVelocity => "stribeck_velocity",
            FrictionParameter::Viscous => "viscous",
            FrictionParameter::CoulombTemperature => "coulomb_temperature",
            FrictionParameter::ViscousTemperature => "viscous_temperature",
        }
    }

    fn index(self) -> usize {
        self as usize
    }
}

/// A parameter the fit did not estimate.
#[derive(Debug, Clone, PartialEq)]
pub struct FixedParameter {
    /// Which.
    pub parameter: FrictionParameter,
    /// The value it was held at.
    pub value: f64,
    /// Why the data cannot tell it.
    pub reason: String,
}

/// The result of [`identify_friction`].
#[derive(Debug, Clone, PartialEq)]
pub struct FrictionFit {
    /// The parameters.
    pub friction: JointFriction,
    /// Root mean square of the residuals `f(w, tl, T) - f_measured`, N m.
    pub rms: f64,
    /// The largest residual in magnitude, N m.
    pub max_residual: f64,
    /// The samples fitted.
    pub samples: usize,
    /// The parameters held fixed, each with its reason (empty: all seven estimated).
    pub fixed: Vec<FixedParameter>,
    /// The standard deviation of each parameter, in the order of [`FrictionParameter::ALL`]
    /// and in its unit: `sqrt(diag(s^2 (J'J)^-1))` at the fit, `J` the model's Jacobian in
    /// the estimated parameters, `s^2` the residuals' sum of squares over the samples less
    /// the parameters estimated (`ws` by the delta method from `ln ws`). `None` for a
    /// parameter held fixed, or for all when the samples are no more than the parameters or
    /// `J'J` is singular. They assume independent residuals: samples from a filtered log
    /// are correlated, so read them as lower bounds.
    pub std_dev: [Option<f64>; PARAMETERS],
    /// Trust-region iterations used.
    pub iterations: usize,
}

impl FrictionFit {
    /// Whether `parameter` was held fixed.
    pub fn is_fixed(&self, parameter: FrictionParameter) -> bool {
        self.fixed.iter().any(|f| f.parameter == parameter)
    }

    /// The standard deviation of `parameter` (see [`FrictionFit::std_dev`]).
    pub fn std_dev_of(&self, parameter: FrictionParameter) -> Option<f64> {
        self.std_dev[parameter.index()]
    }
}

/// The parameters of x (`ln ws` in place of `ws`).
fn friction_of(x: &[f64; PARAMETERS], t0: f64, eps: f64) -> JointFriction {
    JointFriction {
        coulomb: x[0],
        load: x[1],
        stribeck: x[2],
        stribeck_velocity: x[3].exp(),
        viscous: x[4],
        coulomb_temperature: x[5],
        viscous_temperature: x[6],
        reference_temperature: t0,
        smoothing: eps,
    }
}

/// The model at one sample and its gradient in x.
fn model_row(f: &JointFriction, s: &FrictionSample) -> (f64, [f64; PARAMETERS]) {
    let dt = s.temperature - f.reference_temperature;
    let sign = (s.velocity / f.smoothing).tanh();
    let c = (-f.coulomb_temperature * dt).exp();
    let v = (-f.viscous_temperature * dt).exp();
    let r2 = (s.velocity / f.stribeck_velocity).powi(2);
    let e = (-r2).exp();
    let tl = s.load.abs();
    let level = f.coulomb + f.load * tl + f.stribeck * e;
    let viscous = f.viscous * s.velocity * v;
    let value = sign * level * c + viscous;
    let gradient = [
        sign * c,
        sign * tl * c,
        sign * e * c,
        // d e / d ln ws = 2 (w/ws)^2 e
        sign * c * f.stribeck * 2.0 * r2 * e,
        s.velocity * v,
        -dt * sign * level * c,
        -dt * viscous,
    ];
    (value, gradient)
}

/// The least-squares problem in the scaled free variables z (`x[free[k]] = scale[k] z[k]`).
#[derive(Clone)]
struct Fit<'a> {
    samples: &'a [FrictionSample],
    t0: f64,
    eps: f64,
    /// The fixed values, and the free ones at the start.
    base: [f64; PARAMETERS],
    free: Vec<usize>,
    scale: Vec<f64>,
}

impl Fit<'_> {
    fn full(&self, z: &DVector<f64>) -> [f64; PARAMETERS] {
        let mut x = self.base;
        for (k, &i) in self.free.iter().enumerate() {
            x[i] = self.scale[k] * z[k];
        }
        x
    }

    fn start(&self) -> DVector<f64> {
        DVector::from_iterator(
            self.free.len(),
            self.free
                .iter()
                .zip(&self.scale)
                .map(|(&i, s)| self.base[i] / s),
        )
    }

    /// The residuals at z and their Jacobian in z.
    fn linearise(&self, z: &DVector<f64>) -> (DVector<f64>, DMatrix<f64>) {
        let f = friction_of(&self.full(z), self.t0, self.eps);
        let mut r = DVector::zeros(self.samples.len());
        let mut j = DMatrix::zeros(self.samples.len(), self.free.len());
        for (k, s) in self.samples.iter().enumerate() {
            let (value, gradient) = model_row(&f, s);
            r[k] = value - s.friction;
            for (c, &i) in self.free.iter().enumerate() {
                j[(k, c)] = gradient[i] * self.scale[c];
            }
        }
        (r, j)
    }

    fn sum_of_squares(&self, z: &DVector<f64>) -> f64 {
        let f = friction_of(&self.full(z), self.t0, self.eps);
        let sum: f64 = self
            .samples
            .iter()
            .map(|s| (f.evaluate(s.velocity, s.load, s.temperature) - s.friction).powi(2))
            .sum();
        // a wild trial step (an overflowing exponential) is refused by the trust region
        if sum.is_finite() { sum } else { f64::INFINITY }
    }
}

type ArgminResult<T> = std::result::Result<T, argmin::core::Error>;

impl CostFunction for Fit<'_> {
    type Param = DVector<f64>;
    type Output = f64;

    fn cost(&self, z: &DVector<f64>) -> ArgminResult<f64> {
        Ok(self.sum_of_squares(z))
    }
}

impl Gradient for Fit<'_> {
    type Param = DVector<f64>;
    type Gradient = DVector<f64>;

    fn gradient(&self, z: &DVector<f64>) -> ArgminResult<DVector<f64>> {
        let (r, j) = self.linearise(z);
        Ok(j.tr_mul(&r) * 2.0)
    }
}

impl Hessian for Fit<'_> {
    type Param = DVector<f64>;
    type Hessian = DMatrix<f64>;

    /// Gauss-Newton: `2 J'J`, positive semidefinite.
    fn hessian(&self, z: &DVector<f64>) -> ArgminResult<DMatrix<f64>> {
        let (_, j) = self.linearise(z);
        Ok(j.tr_mul(&j) * 2.0)
    }
}

/// Identifies the rotor friction of one joint from `samples` (see the module
/// documentation): the parameters, the fit's residuals and what was held fixed and why.
///
/// Errors: fewer than seven samples; a sample that is not finite (named by its index in
/// `samples`); no velocity reversal (friction from one direction cannot be told from a
/// torque offset); velocities of one magnitude only (Coulomb cannot be told from viscous
/// friction); a fitted value out of range (then the samples are not rotor friction).
pub fn identify_friction(
    samples: &[FrictionSample],
    options: &FrictionFitOptions,
) -> Result<FrictionFit> {
    let eps = options.smoothing;
    if !(eps.is_finite() && eps > 0.0) {
        return Err(Error::setting(
            "FrictionFitOptions",
            "smoothing",
            format!("{} rad/s must be positive, e.g. 1e-3", num(eps)),
        ));
    }
    check_samples(samples, eps)?;
    let n = samples.len() as f64;
    let t0 = match options.reference_temperature {
        Some(t) if t.is_finite() => t,
        Some(t) => {
            return Err(Error::setting(
                "FrictionFitOptions",
                "reference_temperature",
                format!("{t} is not a finite temperature; give deg C, or None for the mean"),
            ));
        }
        None => samples.iter().map(|s| s.temperature).sum::<f64>() / n,
    };

    let mut fixed = Vec::new();
    let (t_low, t_high) = span(samples.iter().map(|s| s.temperature));
    if t_high - t_low < TEMPERATURE_SPREAD {
        for p in [
            FrictionParameter::CoulombTemperature,
            FrictionParameter::ViscousTemperature,
        ] {
            fixed.push(FixedParameter {
                parameter: p,
                value: 0.0,
                reason: format!(
                    "the temperature spans {} K, less than {TEMPERATURE_SPREAD} K: its effect \
                     cannot be told from the Coulomb and viscous levels",
                    Num::rounded_keeping(t_high - t_low, 3, |s| s < TEMPERATURE_SPREAD)
                ),
            });
        }
    }
    let (l_low, l_high) = span(samples.iter().map(|s| s.load.abs()));
    if l_high - l_low < LOAD_SPREAD {
        fixed.push(FixedParameter {
            parameter: FrictionParameter::Load,
            value: 0.0,
            reason: format!(
                "|load torque| spans {} N m, less than {LOAD_SPREAD} N m: Fl |tl| cannot be \
                 told from Fc",
                Num::rounded_keeping(l_high - l_low, 3, |s| s < LOAD_SPREAD)
            ),
        });
    }

    let mut x = start(samples, eps, &fixed)?;
    let mut iterations = 0;
    // the active set: at most one more bound per round, four bounds in all
    for _ in 0..=4 {
        let free: Vec<usize> = (0..PARAMETERS)
            .filter(|&i| !fixed.iter().any(|f| f.parameter.index() == i))
            .collect();
        for f in &fixed {
            x[f.parameter.index()] = f.value;
        }
        let (next, used) = refine(samples, t0, eps, x, free)?;
        x = next;
        iterations += used;
        let negative = [0, 1, 2, 4]
            .into_iter()
            .filter(|&i| !fixed.iter().any(|f| f.parameter.index() == i) && x[i] < 0.0)
            .min_by(|&a, &b| x[a].total_cmp(&x[b]));
        let Some(i) = negative else { break };
        let parameter = FrictionParameter::ALL[i];
        fixed.push(FixedParameter {
            parameter,
            value: 0.0,
            reason: format!(
                "the data pull it below 0 (to {}), which friction cannot be; held at 0",
                Num::rounded(x[i], 3)
            ),
        });
        if parameter == FrictionParameter::Stribeck {
            fixed.push(FixedParameter {
                parameter: FrictionParameter::StribeckVelocity,
                value: x[3],
                reason: "the Stribeck term is 0, so its velocity has no effect".into(),
            });
        }
    }
    let friction = friction_of(&x, t0, eps);
    if let Some((field, problem)) = friction.fitted_problem() {
        // key `fit`: the samples made a fit no friction has (a caller that made them can
        // name what did), where the checks of the samples themselves are `samples`'
        return Err(Error::setting(
            "identify_friction",
            "fit",
            format!(
                "the fitted `{field}` is out of range: {problem}; check that the samples are \
                 rotor friction (signs, units, link-side velocities)"
            ),
        ));
    }
    let residuals: Vec<f64> = samples
        .iter()
        .map(|s| friction.evaluate(s.velocity, s.load, s.temperature) - s.friction)
        .collect();
    let rms = (residuals.iter().map(|r| r * r).sum::<f64>() / n).sqrt();
    let max_residual = residuals.iter().fold(0.0_f64, |m, r| m.max(r.abs()));
    if !rms.is_finite() {
        return Err(Error::NonFiniteResult {
            what: "the friction fit's residuals".into(),
            cause: "the samples are too large for the model; check their units".into(),
        });
    }
    let std_dev = standard_deviations(samples, &friction, &x, &fixed, &residuals);
    // the ln ws of a fixed Stribeck velocity is reported as the velocity
    for f in &mut fixed {
        if f.parameter == FrictionParameter::StribeckVelocity {
            f.value = f.value.exp();
        }
    }
    Ok(FrictionFit {
        friction,
        rms,
        max_residual,
        samples: samples.len(),
        fixed,
        iterations,
        std_dev,
    })
}

/// The standard deviations of the parameters not in `fixed` at the fit `x` (see
/// [`FrictionFit::std_dev`]).
fn standard_deviations(
    samples: &[FrictionSample],
    friction: &JointFriction,
    x: &[f64; PARAMETERS],
    fixed: &[FixedParameter],
    residuals: &[f64],
) -> [Option<f64>; PARAMETERS] {
    let mut out = [None; PARAMETERS];
    let free: Vec<usize> = (0..PARAMETERS)
        .filter(|&i| !fixed.iter().any(|f| f.parameter.index() == i))
        .collect();
    let Some(dof) = samples.len().checked_sub(free.len()).filter(|&d| d > 0) else {
        return out;
    };
    let mut gram = DMatrix::<f64>::zeros(free.len(), free.len());
    for s in samples {
        let (_, gradient) = model_row(friction, s);
        for (a, &i) in free.iter().enumerate() {
            for (b, &k) in free.iter().enumerate() {
                gram[(a, b)] += gradient[i] * gradient[k];
            }
        }
    }
    // the unit-diagonal scaling keeps the Cholesky test about the columns' directions, not
    // their units (Fc in N m against kc in 1/K)
    let scale: Vec<f64> = (0..free.len()).map(|a| gram[(a, a)].sqrt()).collect();
    if scale.iter().any(|v| !(v.is_finite() && *v > 0.0)) {
        return out;
    }
    let scaled = DMatrix::from_fn(free.len(), free.len(), |a, b| {
        gram[(a, b)] / (scale[a] * scale[b])
    });
    let Some(inverse) = scaled.cholesky().map(|c| c.inverse()) else {
        return out;
    };
    let s2 = residuals.iter().map(|r| r * r).sum::<f64>() / dof as f64;
    for (a, &i) in free.iter().enumerate() {
        let std = (s2 * inverse[(a, a)]).sqrt() / scale[a];
        // ws = exp(ln ws): d ws = ws d ln ws
        let std = if i == 3 { std * x[3].exp() } else { std };
        out[i] = std.is_finite().then_some(std);
    }
    out
}

/// The smallest and largest of `values`.
fn span(values: impl Iterator<Item = f64>) -> (f64, f64) {
    values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
        (lo.min(v), hi.max(v))
    })
}

/// The fastest speed of `samples` forward and backward, rad/s (0 for a direction none
/// moves in).
fn fastest(samples: &[FrictionSample]) -> (f64, f64) {
    samples.iter().fold((0.0, 0.0), |(f, b), s| {
        (f64::max(f, s.velocity), f64::max(b, -s.velocity))
    })
}

/// The smoothing `eps` below which `samples` move both ways in the fit's sense (faster than
/// `10 eps` forward and backward, where the smooth sign is within 4e-9 of +-1): a tenth of
/// the smaller of their fastest speeds each way, rad/s; 0 when they move one way only. A
/// wider smoothing is refused by [`identify_friction`] as the smoothing's, not the data's.
pub fn widest_smoothing(samples: &[FrictionSample]) -> f64 {
    let (forward, backward) = fastest(samples);
    forward.min(backward) / 10.0
}

/// Enough finite samples, moving both ways at several speeds.
fn check_samples(samples: &[FrictionSample], eps: f64) -> Result<()> {
    if samples.len() < PARAMETERS {
        return Err(Error::TooFewSamples {
            context: "friction identification".into(),
            found: samples.len(),
            required: PARAMETERS,
            hint: "the model has 7 parameters; give samples of motion in both directions at \
                   several speeds",
        });
    }
    for (k, s) in samples.iter().enumerate() {
        for (name, v) in [
            ("velocity", s.velocity),
            ("load", s.load),
            ("temperature", s.temperature),
            ("friction", s.friction),
        ] {
            if !v.is_finite() {
                return Err(Error::setting(
                    "identify_friction",
                    &format!("samples[{k}].{name}"),
                    format!("is {v}; remove or repair sample {k} (counted from 0)"),
                ));
            }
        }
    }
    // moving: beyond the smoothing, where the smooth sign is within 4e-9 of +-1
    let moving = 10.0 * eps;
    let forward = samples.iter().filter(|s| s.velocity > moving).count();
    let backward = samples.iter().filter(|s| s.velocity < -moving).count();
    // when the samples do reverse beyond the default smoothing's threshold, the smoothing
    // is what hides it (`--smoothing 1` counts motion from 10 rad/s, which no robot's joint
    // reaches: the message said to record motion in both directions, which the data held)
    let widest = widest_smoothing(samples);
    if (forward == 0 || backward == 0) && widest > DEFAULT_SMOOTHING {
        let (fastest_forward, fastest_backward) = fastest(samples);
        return Err(Error::setting(
            "identify_friction",
            "smoothing",
            format!(
                "{} rad/s is too wide for these samples: motion counts from ten times it, {} \
                 rad/s (where the smooth sign tanh(w / eps) is within 4e-9 of +-1), but they \
                 reach {} rad/s forward and {} rad/s backward; give a smoothing below {} \
                 rad/s (the default is {})",
                Num(eps),
                Num::rounded(moving, 6),
                Num::rounded(fastest_forward, 3),
                Num::rounded(fastest_backward, 3),
                Num::rounded_keeping(widest, 2, |v| v < widest),
                Num(DEFAULT_SMOOTHING)
            ),
        ));
    }
    if forward == 0 || backward == 0 {
        return Err(Error::setting(
            "identify_friction",
            "samples",
            format!(
                "no velocity reversal: {forward} samples move forward and {backward} backward \
                 (faster than {} rad/s); friction from one direction cannot be told from a \
                 torque offset, record motion in both directions",
                // ten times the smoothing: 0.011000000000000001 for 0.0011
                Num::rounded(moving, 6)
            ),
        ));
    }
    // Coulomb and viscous columns independent: the velocities have several magnitudes
    let a = DMatrix::from_fn(samples.len(), 2, |k, c| {
        let w = samples[k].velocity;
        if c == 0 { (w / eps).tanh() } else { w }
    });
    let norms: Vec<f64> = a.column_iter().map(|c| c.norm()).collect();
    let a = DMatrix::from_fn(a.nrows(), 2, |k, c| {
        a[(k, c)] / norms[c].max(f64::MIN_POSITIVE)
    });
    let sv = a.singular_values();
    if !(sv.min() > 1e-6 * sv.max()) {
        return Err(Error::Singular {
            what: "the friction samples' Coulomb and viscous columns".into(),
            hint: "the velocities have one magnitude only; record motion at several speeds \
                   (e.g. from 0.01 to 3 rad/s) in both directions",
        });
    }
    Ok(())
}

/// The start: for each Stribeck velocity of a log-spaced grid over the moving samples'
/// speeds, the best fit with `kc = kv = 0` of the linear `(Fc, Fl, Fs, Fv)`, none negative
/// (every subset of them tried, the others at 0); the best over the grid.
fn start(samples: &[FrictionSample], eps: f64, fixed: &[FixedParameter]) -> Result<[f64; 7]> {
    let moving = 10.0 * eps;
    let (low, high) = span(
        samples
            .iter()
            .map(|s| s.velocity.abs())
            .filter(|w| *w > moving),
    );
    let load_free = !fixed.iter().any(|f| f.parameter == FrictionParameter::Load);
    let ff: f64 = samples.iter().map(|s| s.friction * s.friction).sum();
    let mut best: Option<(f64, [f64; PARAMETERS])> = None;
    for g in 0..STRIBECK_GRID {
        let ws = low * (high / low).powf(g as f64 / (STRIBECK_GRID - 1) as f64);
        // columns Fc, Fl, Fs, Fv, scaled to unit norm
        let column = |s: &FrictionSample| {
            let sign = (s.velocity / eps).tanh();
            let e = (-(s.velocity / ws).powi(2)).exp();
            Vector4::new(sign, sign * s.load.abs(), sign * e, s.velocity)
        };
        let mut norm = Vector4::zeros();
        for s in samples {
            norm += column(s).map(|v| v * v);
        }
        let norm = norm.map(|v| if v > 0.0 { v.sqrt() } else { 1.0 });
        let mut gram = Matrix4::zeros();
        let mut b = Vector4::zeros();
        for s in samples {
            let a = column(s).component_div(&norm);
            gram += a * a.transpose();
            b += a * s.friction;
        }
        // every subset of the columns (Fl only where it is free)
        for mask in 1u8..16 {
            if mask & 2 != 0 && !load_free {
                continue;
            }
            let keep: Vec<usize> = (0..4).filter(|i| mask & (1 << i) != 0).collect();
            let sub = DMatrix::from_fn(keep.len(), keep.len(), |i, k| gram[(keep[i], keep[k])]);
            let rhs = DVector::from_fn(keep.len(), |i, _| b[keep[i]]);
            let Ok(y) = sub.clone().svd(true, true).solve(&rhs, 1e-12) else {
                continue;
            };
            if y.iter().any(|v| !(v.is_finite() && *v >= 0.0)) {
                continue;
            }
            let cost = ff - 2.0 * y.dot(&rhs) + (sub * &y).dot(&y);
            if best.as_ref().is_some_and(|(c, _)| *c <= cost) {
                continue;
            }
            let mut x = [0.0, 0.0, 0.0, ws.ln(), 0.0, 0.0, 0.0];
            for (i, &c) in keep.iter().enumerate() {
                // Fc Fl Fs Fv are variables 0 1 2 4
                let at = [0, 1, 2, 4][c];
                x[at] = y[i] / norm[c];
            }
            best = Some((cost, x));
        }
    }
    best.map(|(_, x)| x).ok_or_else(|| Error::Singular {
        what: "the friction samples' linear fit".into(),
        hint: "no fit with non-negative Coulomb, Stribeck and viscous friction exists; check \
               the sign convention of the friction samples (friction opposes the motion)",
    })
}

/// Refines the free variables from x by the trust-region method; the best x and the
/// iterations used.
fn refine(
    samples: &[FrictionSample],
    t0: f64,
    eps: f64,
    x: [f64; PARAMETERS],
    free: Vec<usize>,
) -> Result<([f64; PARAMETERS], usize)> {
    let stopped = |why: String| Error::NonFiniteResult {
        what: "the friction fit".into(),
        cause: format!("the solver stopped: {why}; check the samples' units"),
    };
    if free.is_empty() {
        return Ok((x, 0));
    }
    // unit columns of J at the start (a zero column, e.g. ln ws with Fs = 0, keeps scale 1)
    let mut fit = Fit {
        samples,
        t0,
        eps,
        base: x,
        scale: vec![1.0; free.len()],
        free,
    };
    let (_, j) = fit.linearise(&fit.start());
    fit.scale = j
        .column_iter()
        .map(|c| {
            let n = c.norm();
            if n > 0.0 && n.is_finite() {
                1.0 / n
            } else {
                1.0
            }
        })
        .collect();
    let mut z = fit.start();
    let mut now = fit.sum_of_squares(&z);
    if !now.is_finite() {
        return Err(stopped("the start has no finite residuals".into()));
    }
    // in unit-column variables a step of length r changes the residuals by at most r
    let radius = now.sqrt().max(1e-12);
    let mut used = 0;
    for _ in 0..RUNS {
        let solver = TrustRegion::new(Steihaug::new().with_max_iters(STEIHAUG_ITERATIONS))
            .with_radius(radius)
            .and_then(|s| s.with_max_radius(1e3 * (radius + z.norm())))
            .map_err(|e| stopped(e.to_string()))?;
        let z0 = z.clone();
        let result = Executor::new(fit.clone(), solver)
            .configure(|state| state.param(z0).max_iters(CHUNK))
            .run()
            .map_err(|e| stopped(e.to_string()))?;
        used += usize::try_from(result.state.iter).unwrap_or(usize::MAX);
        let cost = result.state.best_cost;
        if let Some(best) = result.state.best_param
            && cost < now
        {
            z = best;
        }
        let fell = now - cost;
        now = now.min(cost);
        if !(fell > STALL * now) {
            break;
        }
    }
    Ok((fit.full(&z), used))
}

#[cfg(test)]
mod tests {
    use super::super::tests::truth;
    use super::*;
    use crate::rng::Rng;

    fn variables(f: &JointFriction) -> [f64; PARAMETERS] {
        [
            f.coulomb,
            f.load,
            f.stribeck,
            f.stribeck_velocity.ln(),
            f.viscous,
            f.coulomb_temperature,
            f.viscous_temperature,
        ]
    }

    /// Samples of `truth` with normal noise of `sigma` N m: velocities of both signs from
    /// 0.01 to 3 rad/s (log-uniform), load -50..50 N m, temperature 25..45 deg C.
    fn synthetic(
        truth: &JointFriction,
        count: usize,
        sigma: f64,
        seed: u64,
    ) -> Vec<FrictionSample> {
        let mut rng = Rng::new(seed);
        (0..count)
            .map(|_| {
                let sign = if rng.unit() < 0.5 { -1.0 } else { 1.0 };
                let w = sign * (0.01_f64.ln() + rng.unit() * (300.0_f64).ln()).exp();
                let tl = rng.uniform(-50.0, 50.0);
                let t = rng.uniform(25.0, 45.0);
                FrictionSample {
                    velocity: w,
                    load: tl,
                    temperature: t,
                    friction: truth.evaluate(w, tl, t) + sigma * rng.normal(),
                }
            })
            .collect()
    }

    /// The analytic gradient equals central differences in x (error O(h^2) with h = 1e-6
    /// relative).
    #[test]
    fn jacobian_matches_finite_differences() {
        let mut rng = Rng::new(5);
        let mut worst = 0.0_f64;
        for _ in 0..200 {
            let f = JointFriction {
                coulomb: rng.uniform(0.0, 5.0),
                load: rng.uniform(0.0, 0.1),
                stribeck: rng.uniform(0.0, 3.0),
                stribeck_velocity: rng.uniform(0.02, 1.0),
                viscous: rng.uniform(0.0, 5.0),
                coulomb_temperature: rng.uniform(-0.03, 0.03),
                viscous_temperature: rng.uniform(-0.03, 0.03),
                reference_temperature: 35.0,
                smoothing: 0.05, // wide, so that the smooth sign's slope shows too
            };
            let s = FrictionSample {
                velocity: rng.uniform(-1.0, 1.0),
                load: rng.uniform(-50.0, 50.0),
                temperature: rng.uniform(20.0, 50.0),
                friction: 0.0,
            };
            let x = variables(&f);
            let (_, g) = model_row(&f, &s);
            for i in 0..PARAMETERS {
                let h = 1e-6 * (1.0 + x[i].abs());
                let (mut up, mut down) = (x, x);
                up[i] += h;
                down[i] -= h;
                let at = |x: &[f64; PARAMETERS]| model_row(&friction_of(x, 35.0, 0.05), &s).0;
                let fd = (at(&up) - at(&down)) / (2.0 * h);
                worst = worst.max((fd - g[i]).abs() / (1.0 + g[i].abs()));
            }
        }
        // measured 7.7e-10 relative, against entries up to ~2e3 (dT times the level)
        assert!(worst < 1.5e-9, "{worst}");
    }

    /// Synthetic data: the fit reproduces the true curve within 3.4e-4 of the largest
    /// friction over the excited range, and the parameters lie near the truth.
    #[test]
    fn identifies_synthetic_friction() {
        let truth = truth();
        let samples = synthetic(&truth, 3000, 0.02, 17);
        let options = FrictionFitOptions {
            reference_temperature: Some(35.0),
            ..Default::default()
        };
        let fit = identify_friction(&samples, &options).unwrap();
        assert!(fit.fixed.is_empty(), "{:?}", fit.fixed);
        assert_eq!(fit.samples, 3000);
        // the noise: rms 0.02 N m, to 4 standard errors 0.02 / sqrt(2 n) (measured 0.02009)
        let se = 0.02 / (2.0 * 3000.0f64).sqrt();
        assert!((fit.rms - 0.02).abs() < 4.0 * se, "rms {}", fit.rms);
        let f = fit.friction;
        let (mut worst, mut largest) = (0.0_f64, 0.0_f64);
        for i in 0..=60 {
            let w = (0.01_f64.ln() + i as f64 / 60.0 * 300.0_f64.ln()).exp();
            for sign in [-1.0, 1.0] {
                for tl in [0.0, 25.0, 50.0] {
                    for t in [25.0, 35.0, 45.0] {
                        let exact = truth.evaluate(sign * w, tl, t);
                        largest = largest.max(exact.abs());
                        worst = worst.max((f.evaluate(sign * w, tl, t) - exact).abs());
                    }
                }
            }
        }
        // measured 2.3e-3 N m of a largest 13.8 N m (1.7e-4), rms 0.0201 N m, 50 iterations
        assert!(worst < 3.4e-4 * largest, "{worst} of {largest}");
        let near = |name: &str, got: f64, want: f64, tolerance: f64| {
            assert!(
                (got - want).abs() <= tolerance * want.abs(),
                "{name}: {got} vs {want}"
            );
        };
        // measured relative errors (seeded): Fc 2.3e-4, Fl 1.2e-3, Fs 8.2e-4, ws 1.7e-3,
        // Fv 1.8e-4, kc 1.8e-3, kv 7.7e-4; each bound is twice its own
        near("Fc", f.coulomb, truth.coulomb, 4.5e-4);
        near("Fl", f.load, truth.load, 2.4e-3);
        near("Fs", f.stribeck, truth.stribeck, 1.6e-3);
        near("ws", f.stribeck_velocity, truth.stribeck_velocity, 3.3e-3);
        near("Fv", f.viscous, truth.viscous, 3.5e-4);
        near(
            "kc",
            f.coulomb_temperature,
            truth.coulomb_temperature,
            3.5e-3,
        );
        near(
            "kv",
            f.viscous_temperature,
            truth.viscous_temperature,
            1.5e-3,
        );
        // the default reference: the mean temperature; the same curve
        let by_mean = identify_friction(&samples, &FrictionFitOptions::default()).unwrap();
        let mean = samples.iter().map(|s| s.temperature).sum::<f64>() / 3000.0;
        assert_eq!(by_mean.friction.reference_temperature, mean);
        let (a, b) = (
            by_mean.friction.evaluate(0.5, 10.0, 30.0),
            f.evaluate(0.5, 10.0, 30.0),
        );
        // one curve, two parametrisations: measured 5.6e-11 N m apart (the fits' convergence)
        assert!((a - b).abs() < 1.1e-10, "{a} vs {b}");
    }

    /// The standard deviations the fit reports are those of its estimates: over 60 noise
    /// draws of one design, each parameter's spread across the draws matches the mean
    /// reported standard deviation, and the truth lies within 4.5 of them in every draw.
    #[test]
    fn standard_deviations_are_the_spread_of_the_estimates() {
        let truth = truth();
        let want = variables(&truth);
        let options = FrictionFitOptions {
            reference_temperature: Some(35.0),
            ..Default::default()
        };
        const DRAWS: usize = 60;
        let mut estimates = vec![[0.0; PARAMETERS]; DRAWS];
        let mut reported = [0.0; PARAMETERS];
        for (draw, estimate) in estimates.iter_mut().enumerate() {
            // one design (seed 3), a fresh noise of 0.05 N m per draw
            let mut samples = synthetic(&truth, 600, 0.0, 3);
            let mut noise = Rng::new(1000 + draw as u64);
            for s in &mut samples {
                s.friction += 0.05 * noise.normal();
            }
            let fit = identify_friction(&samples, &options).unwrap();
            assert!(fit.fixed.is_empty(), "draw {draw}: {:?}", fit.fixed);
            let got = [
                fit.friction.coulomb,
                fit.friction.load,
                fit.friction.stribeck,
                fit.friction.stribeck_velocity,
                fit.friction.viscous,
                fit.friction.coulomb_temperature,
                fit.friction.viscous_temperature,
            ];
            for p in FrictionParameter::ALL {
                let i = p.index();
                let std = fit.std_dev_of(p).unwrap();
                let exact = if i == 3 { want[3].exp() } else { want[i] };
                assert!(
                    (got[i] - exact).abs() < 4.5 * std,
                    "draw {draw}: {} = {} against {exact}, std {std}",
                    p.name(),
                    got[i]
                );
                reported[i] += std / DRAWS as f64;
            }
            *estimate = got;
        }
        for p in FrictionParameter::ALL {
            let i = p.index();
            let mean = estimates.iter().map(|e| e[i]).sum::<f64>() / DRAWS as f64;
            let spread = (estimates.iter().map(|e| (e[i] - mean).powi(2)).sum::<f64>()
                / (DRAWS - 1) as f64)
                .sqrt();
            // 60 draws know a spread to about 9 %: 0.7..1.4 is beyond 3.5 of that (measured
            // 0.90 for Fv to 1.12 for Fl)
            let ratio = spread / reported[i];
            assert!(
                (0.7..1.4).contains(&ratio),
                "{}: spread {spread} against a reported {} (ratio {ratio})",
                p.name(),
                reported[i]
            );
        }
    }

    #[test]
    fn what_the_data_cannot_tell_is_fixed_and_said() {
        let truth = truth();
        let mut samples = synthetic(&truth, 1000, 0.01, 23);
        for s in &mut samples {
            s.temperature = 30.0;
            s.load = 12.0;
            s.friction = truth.evaluate(s.velocity, s.load, s.temperature);
        }
        let fit = identify_friction(&samples, &FrictionFitOptions::default()).unwrap();
        for p in [
            FrictionParameter::CoulombTemperature,
            FrictionParameter::ViscousTemperature,
            FrictionParameter::Load,
        ] {
            assert!(fit.is_fixed(p), "{p:?}: {:?}", fit.fixed);
            let held = fit.fixed.iter().find(|f| f.parameter == p).unwrap();
            assert!(held.reason.contains("spans 0 "), "{}", held.reason);
        }
        assert_eq!(fit.friction.coulomb_temperature, 0.0);
        assert_eq!(fit.friction.viscous_temperature, 0.0);
        assert_eq!(fit.friction.load, 0.0);
        // a held parameter has no standard deviation, each estimated one has
        for p in FrictionParameter::ALL {
            let std = fit.std_dev_of(p);
            assert_eq!(std.is_none(), fit.is_fixed(p), "{p:?}: {:?}", fit.std_dev);
        }
        // Fc takes Fl |tl| at this load and temperature: the curve is kept
        let at = |f: &JointFriction| f.evaluate(0.5, 12.0, 30.0);
        // noise-free: equal to rounding (measured 0)
        assert!((at(&fit.friction) - at(&truth)).abs() < 1e-12);
        // measured 4e-16 N m without noise
        assert!(fit.rms < 1e-9, "{}", fit.rms);
    }

    /// The spans in the reasons are written to three digits (they were written with
    /// every digit of the subtraction: "spans 0.32323208000000037 K"), or more where three
    /// would reach the limit they fall short of.
    #[test]
    fn the_spans_are_written_short() {
        let truth = truth();
        let reasons = |temperature: f64, load: f64| {
            let mut samples = synthetic(&truth, 400, 0.0, 41);
            for (k, s) in samples.iter_mut().enumerate() {
                let end = (k % 2) as f64;
                s.temperature = 30.0 + temperature * end;
                s.load = 12.0 + load * end;
                s.friction = truth.evaluate(s.velocity, s.load, s.temperature);
            }
            let fit = identify_friction(&samples, &FrictionFitOptions::default()).unwrap();
            fit.fixed
                .iter()
                .map(|f| f.reason.clone())
                .collect::<Vec<_>>()
        };
        // 30 + 0.32323208 - 30 = 0.32323208000000037
        let r = reasons(0.32323208, 0.0323232);
        assert!(
            r[0].starts_with("the temperature spans 0.323 K, less than 1 K"),
            "{r:?}"
        );
        assert!(
            r[2].starts_with("|load torque| spans 0.0323 N m, less than 0.1 N m"),
            "{r:?}"
        );
        let r = reasons(0.99996, 0.099996);
        assert!(
            r[0].starts_with("the temperature spans 0.99996 K, less"),
            "{r:?}"
        );
        assert!(
            r[2].starts_with("|load torque| spans 0.099996 N m, less"),
            "{r:?}"
        );
    }

    #[test]
    fn friction_pulled_below_zero_is_held_at_zero() {
        // no Stribeck term in the data, and noise: Fs came out at -0.055 and is held at 0
        // (measured Fc 2.0009, Fv 3.0059)
        let truth = JointFriction {
            stribeck: 0.0,
            ..truth()
        };
        let samples = synthetic(&truth, 1500, 0.05, 29);
        let fit = identify_friction(&samples, &FrictionFitOptions::default()).unwrap();
        assert!(fit.is_fixed(FrictionParameter::Stribeck), "{:?}", fit.fixed);
        assert!(fit.is_fixed(FrictionParameter::StribeckVelocity));
        // the value it was pulled to, to three digits (it had every digit; measured
        // -0.0548)
        let held = &fit.fixed[0];
        assert_eq!(held.parameter, FrictionParameter::Stribeck);
        let to = held
            .reason
            .strip_prefix("the data pull it below 0 (to ")
            .and_then(|r| r.split_once(')'))
            .map(|(v, _)| v)
            .unwrap_or_else(|| panic!("{}", held.reason));
        let digits = to.trim_start_matches(['-', '0', '.']).len();
        let value: f64 = to.parse().unwrap();
        assert!(
            digits <= 3 && (-0.06..-0.05).contains(&value),
            "{}",
            held.reason
        );
        assert_eq!(fit.friction.stribeck, 0.0);
        assert!(fit.friction.coulomb >= 0.0 && fit.friction.viscous >= 0.0);
        assert!(
            (fit.friction.coulomb - 2.0).abs() < 1.75e-3,
            "{:?}",
            fit.friction
        );
    }

    #[test]
    fn bad_samples_are_refused_by_name() {
        let good = synthetic(&truth(), 100, 0.01, 31);
        let options = FrictionFitOptions::default();
        let e = identify_friction(&good[..6], &options).unwrap_err();
        assert!(
            matches!(
                e,
                Error::TooFewSamples {
                    found: 6,
                    required: 7,
                    ..
                }
            ),
            "{e}"
        );
        let mut nan = good.clone();
        nan[42].load = f64::NAN;
        let e = identify_friction(&nan, &options).unwrap_err().to_string();
        assert!(e.contains("samples[42].load") && e.contains("NaN"), "{e}");
        let forward: Vec<FrictionSample> = good
            .iter()
            .map(|s| FrictionSample {
                velocity: s.velocity.abs(),
                ..*s
            })
            .collect();
        let e = identify_friction(&forward, &options)
            .unwrap_err()
            .to_string();
        assert!(e.contains("no velocity reversal"), "{e}");
        let fine = FrictionFitOptions {
            smoothing: 0.0011,
            ..options
        };
        let e = identify_friction(&forward, &fine).unwrap_err().to_string();
        assert!(e.contains("(faster than 0.011 rad/s)"), "{e}");
        // samples that reverse, under a smoothing wider than their speeds: the smoothing's
        // error, with the widest that fits (it was "no velocity reversal")
        let widest = widest_smoothing(&good);
        let (f, b) = fastest(&good);
        assert!(
            widest > DEFAULT_SMOOTHING && widest == f.min(b) / 10.0,
            "{widest}"
        );
        assert_eq!(widest_smoothing(&forward), 0.0);
        let wide = FrictionFitOptions {
            smoothing: 10.0 * widest,
            ..options
        };
        let e = identify_friction(&good, &wide).unwrap_err();
        assert!(
            matches!(&e, Error::Setting { key, .. } if key == "smoothing"),
            "{e}"
        );
        let e = e.to_string();
        assert!(
            e.contains("is too wide for these samples") && !e.contains("no velocity reversal"),
            "{e}"
        );
        let fitting = FrictionFitOptions {
            smoothing: 0.9 * widest,
            ..options
        };
        assert!(identify_friction(&good, &fitting).is_ok());
        let one_speed: Vec<FrictionSample> = good
            .iter()
            .map(|s| FrictionSample {
                velocity: s.velocity.signum() * 0.5,
                ..*s
            })
            .collect();
        let e = identify_friction(&one_speed, &options)
            .unwrap_err()
            .to_string();
        assert!(e.contains("one magnitude"), "{e}");
        let bad_eps = FrictionFitOptions {
            smoothing: 0.0,
            ..options
        };
        assert!(identify_friction(&good, &bad_eps).is_err());
    }
}
