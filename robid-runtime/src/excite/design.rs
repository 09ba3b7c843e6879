//! Optimisation of a Fourier trajectory (Swevers et al. 1997) for a design criterion under
//! position, velocity, acceleration and (optionally) torque limits.
//!
//! Limits hold by construction rather than as penalties: the decision variables of a joint
//! are its free coefficients (shape), an amplitude variable z_a and, unless the start is
//! fixed, an offset variable z_o. The start q0 = c + r sin(z_o) lies inside the position
//! range (the sin-substitution of Milella); the shape is evaluated on a fine grid and scaled
//! by (1 + sin z_a) / 2 times the largest factor that keeps the position range, |qd| and
//! |qdd| within `safety` times each limit. Torque limits (with reference parameters) are a
//! penalty. Random restarts from a seed run in parallel, each a Nelder-Mead minimisation;
//! the best is polished by one more run.

use crate::Num;
use std::f64::consts::FRAC_PI_2;

use rayon::prelude::*;

use crate::Count;
use crate::Model;
use crate::error::{Error, Result, num};
use crate::estimate::SIGMA_FLOOR;
use crate::excite::limits::{TorquePenalty, check_reference};
use crate::excite::{Criterion, Fourier, Information, JointLimits, JointSeries, check_limits};
use crate::excite::{
    MAX_BASE_FREQUENCY, MAX_EVALUATIONS, MAX_HARMONICS, MAX_POINTS, MAX_RESTARTS, MAX_WEIGHT,
};
use crate::nelder_mead::NelderMead;
use crate::progress::Progress;
use crate::rng::Rng;

/// Settings of a Fourier design.
#[derive(Debug, Clone, PartialEq)]
pub struct FourierDesign {
    /// Harmonics per joint (at least 2).
    pub harmonics: usize,
    /// Base frequency (Hz).
    pub base_frequency: f64,
    /// Samples per period at which the criterion is evaluated.
    pub points: usize,
    /// The criterion minimised.
    pub criterion: Criterion,
    /// Per-joint weights of the regressor rows (e.g. 1 / expected noise sigma, what weighted
    /// least squares sees); `None` = unweighted.
    pub weights: Option<Vec<f64>>,
    /// Random starts.
    pub restarts: usize,
    /// Function evaluations per start.
    pub evaluations: usize,
    /// Seed of the random starts.
    pub seed: u64,
    /// Fraction of every limit the design may use (0 < safety <= 1).
    pub safety: f64,
    /// Fixed start position; `None` lets the optimiser choose it.
    pub start: Option<Vec<f64>>,
    /// Show the progress on standard error: a bar on a terminal, else a line every 10 s
    /// ([`crate::progress`]).
    pub progress: bool,
}

impl Default for FourierDesign {
    fn default() -> Self {
        Self {
            harmonics: 5,
            base_frequency: 0.1,
            points: 100,
            criterion: Criterion::Condition,
            weights: None,
            restarts: 8,
            evaluations: 3000,
            seed: 1,
            safety: 0.98,
            start: None,
            progress: false,
        }
    }
}

/// The result of a design.
#[derive(Debug, Clone)]
pub struct FourierResult {
    /// The trajectory.
    pub fourier: Fourier,
    /// The criterion's value on the design grid.
    pub cost: f64,
    /// Function evaluations used.
    pub evaluations: usize,
}

/// Turns decision variables into a Fourier trajectory within the limits.
struct Decoder<'a> {
    design: &'a FourierDesign,
    limits: &'a [JointLimits],
    /// sin and cos of harmonic l at each fine-grid phase.
    table: Vec<(f64, f64)>,
    fine: usize,
}

impl Decoder<'_> {
    fn per_joint(&self) -> usize {
        2 * (self.design.harmonics - 1) + 1 + usize::from(self.design.start.is_none())
    }

    fn decode(&self, x: &[f64]) -> Fourier {
        let d = self.design;
        let m = self.per_joint();
        let w = std::f64::consts::TAU * d.base_frequency;
        let joints = self
            .limits
            .iter()
            .enumerate()
            .map(|(j, l)| {
                let v = &x[j * m..(j + 1) * m];
                let free = &v[..2 * (d.harmonics - 1)];
                let mut s = JointSeries::from_free(0.0, free);
                let [lo, hi] = l.position;
                let (mid, half) = (0.5 * (lo + hi), 0.5 * (hi - lo) * d.safety);
                s.q0 = match &d.start {
                    Some(q0) => q0[j],
                    None => mid + half * v[m - 1].sin(),
                };
                // per harmonic: a, b, w_l, a / w_l, b / w_l (the same values the loop
                // below would compute at every point)
                let mut terms = [[0.0; 5]; MAX_HARMONICS];
                for (i, ((a, b), t)) in s.a.iter().zip(&s.b).zip(&mut terms).enumerate() {
                    let wl = w * (i + 1) as f64;
                    *t = [*a, *b, wl, a / wl, b / wl];
                }
                let terms = &terms[..s.a.len()];
                let (mut gmax, mut gmin, mut vmax, mut amax) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
                for k in 0..self.fine {
                    let (mut g, mut gd, mut gdd) = (0.0, 0.0, 0.0);
                    for (i, &[a, b, wl, a_w, b_w]) in terms.iter().enumerate() {
                        let (sn, cs) = self.table[i * self.fine + k];
                        g += a_w * sn - b_w * (cs - 1.0);
                        gd += a * cs + b * sn;
                        gdd += wl * (-a * sn + b * cs);
                    }
                    gmax = gmax.max(g);
                    gmin = gmin.min(g);
                    vmax = vmax.max(gd.abs());
                    amax = amax.max(gdd.abs());
                }
                let (room_lo, room_hi) =
                    crate::excite::limits::position_room(l.position, d.safety, s.q0);
                let mut smax = f64::INFINITY;
                for (limit, peak) in [
                    (d.safety * l.velocity, vmax),
                    (d.safety * l.acceleration, amax),
                    (room_hi, gmax),
                    (room_lo, -gmin),
                ] {
                    if peak > 0.0 {
                        smax = smax.min(limit / peak);
                    }
                }
                if !smax.is_finite() {
                    smax = 0.0;
                }
                s.scale(smax * 0.5 * (1.0 + v[2 * (d.harmonics - 1)].sin()));
                s
            })
            .collect();
        Fourier {
            base_frequency: d.base_frequency,
            joints,
        }
    }
}

impl FourierDesign {
    /// Checks the settings for a model of `dof` joints (ranges in
    /// [`crate::excite`]'s documentation).
    pub fn check(&self, dof: usize) -> Result<()> {
        let bad = |key: &str, problem: String| Err(Error::setting("FourierDesign", key, problem));
        if !(2..=MAX_HARMONICS).contains(&self.harmonics) {
            return bad(
                "harmonics",
                format!("{} must lie between 2 and {MAX_HARMONICS}", self.harmonics),
            );
        }
        if !(self.base_frequency > 0.0 && self.base_frequency <= MAX_BASE_FREQUENCY) {
            return bad(
                "base_frequency",
                format!(
                    "{} Hz must lie in (0, {MAX_BASE_FREQUENCY}] Hz",
                    num(self.base_frequency)
                ),
            );
        }
        if !(self.safety > 0.0 && self.safety <= 1.0) {
            return bad("safety", format!("{} must lie in (0, 1]", num(self.safety)));
        }
        check_count("FourierDesign", "points", self.points, 1, MAX_POINTS)?;
        check_count("FourierDesign", "restarts", self.restarts, 1, MAX_RESTARTS)?;
        check_count(
            "FourierDesign",
            "evaluations",
            self.evaluations,
            1,
            MAX_EVALUATIONS,
        )?;
        check_joint_vectors(
            "FourierDesign",
            dof,
            self.start.as_deref(),
            self.weights.as_deref(),
        )
    }

    /// Designs a trajectory for `model` within `limits`; `torque` = reference base
    /// parameters enables the torque limits.
    pub fn optimize<M: Model + Sync + ?Sized>(
        &self,
        model: &M,
        limits: &[JointLimits],
        torque: Option<&[f64]>,
    ) -> Result<FourierResult> {
        let n = model.dof();
        self.check(n)?;
        check_limits(limits, n)?;
        check_start(self.start.as_deref(), limits)?;
        check_reference(model, torque)?;
        let decoder = self.decoder(limits);
        let basis = DesignBasis::new(self.harmonics, self.points);
        let cost =
            |x: &[f64], scratch: &mut Scratch<'_>| self.cost(model, &decoder.decode(x), scratch);
        let m = decoder.per_joint();
        // evaluations; a run that stops before its budget counts the whole budget, so
        // that the share shown is the share of the work done
        let progress = Progress::new(
            self.progress,
            "excite: fourier design",
            ((self.restarts + 1) * self.evaluations) as u64,
            "evaluations",
        );
        let nm = NelderMead {
            max_evaluations: self.evaluations,
            tolerance: 1e-10,
            absolute_tolerance: 1e-10,
            step: vec![0.4],
        };
        let run = |x0: &[f64], scratch: &mut Scratch<'_>| -> Result<crate::nelder_mead::Minimum> {
            let counter = progress.counter();
            let found = nm.minimize(x0, |x| {
                counter.tick();
                cost(x, scratch)
            })?;
            counter.add(self.evaluations.saturating_sub(found.evaluations) as u64);
            Ok(found)
        };
        let root = Rng::new(self.seed);
        let runs: Vec<crate::nelder_mead::Minimum> = (0..self.restarts)
            .into_par_iter()
            .map(|r| {
                let x0 = self.start_point(&mut root.fork(r as u64), n * m, m);
                run(&x0, &mut self.scratch(model, limits, torque, &basis))
            })
            .collect::<Result<_>>()?;
        let best = runs
            .iter()
            .min_by(|a, b| a.value.total_cmp(&b.value))
            .ok_or_else(|| Error::setting("FourierDesign", "restarts", "no start was run"))?;
        let polished = run(&best.x, &mut self.scratch(model, limits, torque, &basis))?;
        progress.finish();
        let evaluations = runs.iter().map(|r| r.evaluations).sum::<usize>() + polished.evaluations;
        let x = if polished.value <= best.value {
            &polished.x
        } else {
            &best.x
        };
        let cost = polished.value.min(best.value);
        check_design_cost(
            cost,
            self.criterion,
            limits,
            1.0 / self.base_frequency,
            self.safety,
        )?;
        Ok(FourierResult {
            fourier: decoder.decode(x),
            cost,
            evaluations,
        })
    }

    /// A random start of the optimisation (free coefficients ~ N(0, 1/l), full amplitude,
    /// random offset) for `len` variables, `m` per joint.
    fn start_point(&self, rng: &mut Rng, len: usize, m: usize) -> Vec<f64> {
        let h = self.harmonics - 1;
        (0..len)
            .map(|i| match i % m {
                k if k < 2 * h => rng.normal() / (2 + k % h) as f64,
                k if k == 2 * h => FRAC_PI_2 + 0.1 * rng.normal(),
                _ => rng.uniform(-1.0, 1.0),
            })
            .collect()
    }

    /// A random, non-optimised trajectory of the same family and within the same limits
    /// (the first start of [`FourierDesign::optimize`] with this seed): the baseline a
    /// design is compared with.
    ///
    /// # Errors
    /// [`Error::Setting`] for the settings [`FourierDesign::optimize`] refuses, a start
    /// outside the limits included (the trajectory would sit there, unmoving).
    pub fn random(&self, limits: &[JointLimits]) -> Result<Fourier> {
        self.check(limits.len())?;
        check_limits(limits, limits.len())?;
        check_start(self.start.as_deref(), limits)?;
        let decoder = self.decoder(limits);
        let m = decoder.per_joint();
        let x = self.start_point(&mut Rng::new(self.seed).fork(0), limits.len() * m, m);
        Ok(decoder.decode(&x))
    }

    /// Points per period of the grid on which the design holds the position, velocity and
    /// acceleration limits (64 per harmonic).
    pub fn fine_points(&self) -> usize {
        64 * self.harmonics
    }

    fn decoder<'a>(&'a self, limits: &'a [JointLimits]) -> Decoder<'a> {
        let fine = self.fine_points();
        let table = (1..=self.harmonics)
            .flat_map(|l| {
                (0..fine)
                    .map(move |k| (std::f64::consts::TAU * (l * k) as f64 / fine as f64).sin_cos())
            })
            .collect();
        Decoder {
            design: self,
            limits,
            table,
            fine,
        }
    }

    /// The criterion on the design grid, plus a torque-limit penalty, with the work
    /// buffers of `scratch` (one per search: nothing is allocated per evaluation).
    fn cost<M: Model + ?Sized>(
        &self,
        model: &M,
        fourier: &Fourier,
        scratch: &mut Scratch<'_>,
    ) -> f64 {
        let Scratch {
            basis,
            info,
            penalty,
            q,
            qd,
            qdd,
            lanes,
        } = scratch;
        info.reset();
        if let Some(p) = penalty.as_mut() {
            p.reset();
        }
        let w = fourier.omega();
        let n = q.len();
        for first in (0..self.points).step_by(LANES) {
            let count = LANES.min(self.points - first);
            for l in 0..count {
                basis.state(fourier, w, first + l, q, qd, qdd);
                for (lane, state) in lanes.chunks_exact_mut(n * count).zip([&*q, qd, qdd]) {
                    for (i, v) in state.iter().enumerate() {
                        lane[i * count + l] = *v;
                    }
                }
                // The sizes were checked on entry: a model that still refuses a state
                // makes this candidate infinitely bad rather than silently wrong.
                if let Some(p) = penalty.as_mut()
                    && p.add(model, q, qd, qdd).is_err()
                {
                    return f64::INFINITY;
                }
            }
            let (ql, rest) = lanes[..3 * n * count].split_at(n * count);
            let (qdl, qddl) = rest.split_at(n * count);
            if info.add_lanes(model, count, ql, qdl, qddl).is_err() {
                return f64::INFINITY;
            }
        }
        info.cost(self.criterion) + penalty.as_ref().map_or(0.0, |p| p.value())
    }

    /// The work buffers of one search.
    fn scratch<'a, M: Model + ?Sized>(
        &self,
        model: &M,
        limits: &'a [JointLimits],
        torque: Option<&'a [f64]>,
        basis: &DesignBasis,
    ) -> Scratch<'a> {
        let n = model.dof();
        let mut info = Information::new(model);
        if let Some(w) = &self.weights {
            info = info.with_weights(w);
        }
        Scratch {
            basis: basis.clone(),
            info,
            penalty: torque.map(|base| TorquePenalty::new(limits, self.safety, base)),
            q: vec![0.0; n],
            qd: vec![0.0; n],
            qdd: vec![0.0; n],
            lanes: vec![0.0; 3 * n * LANES],
        }
    }
}

/// sin and cos of every harmonic at every point of the design grid, t_k = k T / K: the
/// phases l w t_k = 2 pi l k / K are constants of the design, so the series is evaluated
/// there without a sine or cosine (docs/performance.md#excitation).
#[derive(Debug, Clone)]
struct DesignBasis {
    /// (sin, cos) of harmonic l (0-based index) at point k, at `l * points + k`.
    table: Vec<(f64, f64)>,
    points: usize,
}

impl DesignBasis {
    fn new(harmonics: usize, points: usize) -> Self {
        let table = (1..=harmonics)
            .flat_map(|l| {
                (0..points).map(move |k| {
                    (std::f64::consts::TAU * ((l * k) % points) as f64 / points as f64).sin_cos()
                })
            })
            .collect();
        Self { table, points }
    }

    /// (q, qd, qdd) of every joint at design point k ([`JointSeries::eval`] at t_k).
    fn state(
        &self,
        fourier: &Fourier,
        w: f64,
        k: usize,
        q: &mut [f64],
        qd: &mut [f64],
        qdd: &mut [f64],
    ) {
        for (j, s) in fourier.joints.iter().enumerate() {
            let mut out = [s.q0, 0.0, 0.0];
            for (i, (a, b)) in s.a.iter().zip(&s.b).enumerate() {
                let wl = w * (i + 1) as f64;
                let (sn, c) = self.table[i * self.points + k];
                out[0] += a / wl * sn - b / wl * (c - 1.0);
                out[1] += a * c + b * sn;
                out[2] += wl * (-a * sn + b * c);
            }
            [q[j], qd[j], qdd[j]] = out;
        }
    }
}

/// The buffers one search reuses for every evaluation of the criterion.
struct Scratch<'a> {
    basis: DesignBasis,
    info: Information,
    penalty: Option<TorquePenalty<'a>>,
    q: Vec<f64>,
    qd: Vec<f64>,
    qdd: Vec<f64>,
    /// Up to [`LANES`] states, lane-major: q, then qd, then qdd ([`Information::add_lanes`]).
    lanes: Vec<f64>,
}

/// Design points evaluated in one call of the model: an interpreted model dispatches each
/// operation once for all of them, and 8 lanes of its registers stay in the cache
/// (docs/performance.md#excitation).
const LANES: usize = 8;

/// Checks that a fixed start position lies strictly inside the position limits.
pub(crate) fn check_start(start: Option<&[f64]>, limits: &[JointLimits]) -> Result<()> {
    for (j, (q, l)) in start.unwrap_or_default().iter().zip(limits).enumerate() {
        if !(l.position[0] < *q && *q < l.position[1]) {
            return Err(Error::setting(
                "design",
                "start",
                format!(
                    "joint {}: {q} is outside the limits {:?}; choose a start inside them",
                    j + 1,
                    l.position
                ),
            ));
        }
    }
    Ok(())
}

/// Checks a count setting against `lo..=hi`.
pub(crate) fn check_count(
    owner: &str,
    key: &str,
    value: usize,
    lo: usize,
    hi: usize,
) -> Result<()> {
    if (lo..=hi).contains(&value) {
        Ok(())
    } else {
        Err(Error::setting(
            owner,
            key,
            format!("{value} must lie between {lo} and {hi}"),
        ))
    }
}

/// Checks the per-joint start and weights of a design: one per joint, weights positive
/// and finite (a weight is 1 / the joint's expected torque noise).
pub(crate) fn check_joint_vectors(
    owner: &str,
    dof: usize,
    start: Option<&[f64]>,
    weights: Option<&[f64]>,
) -> Result<()> {
    for (key, v) in [("start", start), ("weights", weights)] {
        if let Some(v) = v.filter(|v| v.len() != dof) {
            return Err(Error::setting(
                owner,
                key,
                format!(
                    "{} for a model of {}; give one per joint",
                    Count(v.len(), "value"),
                    Count(dof, "joint")
                ),
            ));
        }
    }
    if let Some(j) = weights.and_then(|w| w.iter().position(|w| !(*w > 0.0 && *w <= MAX_WEIGHT))) {
        return Err(Error::setting(
            owner,
            "weights",
            format!(
                "the weight of joint {} is {}; a weight is 1 / the joint's expected torque noise and must lie in (0, {MAX_WEIGHT:e}] (see excite::weights_from_sigma)",
                j + 1,
                num(weights.map_or(0.0, |w| w[j]))
            ),
        ));
    }
    Ok(())
}

/// Regressor-row weights 1 / sigma_j from the expected torque noise `sigma` of each joint
/// (N m): what weighted least squares will see, so each sigma is floored, as there, at
/// [`SIGMA_FLOOR`] (1e-6) of the largest. Without the floor, sigmas each in range but 1e8
/// apart (`robid excite --sigma 1,1,1,1,1,1e-8`) made every trajectory's criterion
/// infinite, and the design ended blaming the joint limits. A sigma must be positive and
/// finite: a joint without noise would get an infinite weight (and one with a sigma below
/// 1 / [`MAX_WEIGHT`] a weight beyond the limit). `owner` and `key` name the setting in
/// the error (e.g. `"excite"`, `"sigma"`).
pub fn weights_from_sigma(sigma: &[f64], owner: &str, key: &str) -> Result<Vec<f64>> {
    let largest = sigma.iter().copied().fold(0.0, f64::max);
    sigma
        .iter()
        .enumerate()
        .map(|(j, &s)| {
            if s > 0.0 && s.is_finite() && 1.0 / s <= MAX_WEIGHT {
                Ok(1.0 / s.max(SIGMA_FLOOR * largest))
            } else {
                Err(Error::setting(
                    owner,
                    key,
                    format!(
                        "joint {} has {}; give each joint's expected torque noise as a positive number (at least {:e} N m): a noise of zero would make its weight 1 / sigma infinite",
                        j + 1,
                        num(s),
                        1.0 / MAX_WEIGHT
                    ),
                ))
            }
        })
        .collect()
}

/// A finished design's cost must be finite: infinite means that no trajectory tried
/// excites every base parameter. The joints move within `limits`, scaled by `safety`,
/// over a trajectory of `period` seconds: a joint that cannot move a milliradian (or a
/// millimetre) in it is named with the limit that holds it.
pub(crate) fn check_design_cost(
    cost: f64,
    criterion: Criterion,
    limits: &[JointLimits],
    period: f64,
    safety: f64,
) -> Result<()> {
    if cost.is_finite() {
        return Ok(());
    }
    let confined = most_confined(limits, period, safety)
        .filter(|(_, reach, _)| *reach < CONFINED)
        .map(|(j, reach, by)| {
            format!(
                "joint {} can move at most about {} over the trajectory's period of {} s, \
                 held by {by}: raise it (velocity limits from a description or \
                 --velocity-limits, acceleration limits likewise), or ",
                j + 1,
                Num::rounded(reach, 3),
                Num::rounded(period, 4)
            )
        })
        .unwrap_or_default();
    Err(Error::NonFiniteResult {
        what: format!(
            "the design criterion ({}) of the best trajectory",
            match criterion {
                Criterion::Condition => "the condition number",
                Criterion::DOptimal => "D-optimality",
            }
        ),
        cause: format!(
            "every trajectory tried leaves some base parameter unexcited (or exceeds the \
             torque limits without bound): {confined}check the joint limits (a joint with \
             almost no range, speed or acceleration cannot excite its parameters) and the \
             start position (one at the edge of a joint's range leaves it no room to move), \
             or give the search more restarts and evaluations"
        ),
    })
}

/// A joint's reach below which it is named as the cause of an unexcited design: 1e-3 (rad
/// or m).
const CONFINED: f64 = 1e-3;

/// The joint with the smallest reach (the amplitude of a sine at the trajectory's lowest
/// frequency, 1 / `period`, within its position range, velocity and acceleration limits,
/// scaled by `safety`), with that reach and the limit that sets it.
fn most_confined(limits: &[JointLimits], period: f64, safety: f64) -> Option<(usize, f64, String)> {
    let w = std::f64::consts::TAU / period;
    limits
        .iter()
        .enumerate()
        .map(|(j, l)| {
            let by = [
                (
                    0.5 * (l.position[1] - l.position[0]),
                    format!(
                        "its position range [{}, {}]",
                        Num(l.position[0]),
                        Num(l.position[1])
                    ),
                ),
                (
                    l.velocity / w,
                    format!("its velocity limit {}", Num(l.velocity)),
                ),
                (
                    l.acceleration / (w * w),
                    format!("its acceleration limit {}", Num(l.acceleration)),
                ),
            ];
            let (reach, limit) = by
                .into_iter()
                .min_by(|a, b| a.0.total_cmp(&b.0))
                .unwrap_or_default();
            (j, safety * reach, limit)
        })
        .min_by(|a, b| a.1.total_cmp(&b.1))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simulate::tests::Pendulum;

    /// The condition number of the weighted W of `fourier` on its design grid, from the
    /// SVD of W itself.
    fn weighted_condition(p: &Pendulum, fourier: &Fourier, points: usize, w: &[f64]) -> f64 {
        let (n, b) = (p.dof(), p.base_parameter_count());
        let (mut q, mut qd, mut qdd) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        let mut y = vec![0.0; n * b];
        let mut rows = Vec::new();
        for k in 0..points {
            fourier.state(
                k as f64 * fourier.period() / points as f64,
                &mut q,
                &mut qd,
                &mut qdd,
            );
            p.base_regressor_into(&q, &qd, &qdd, &mut y).unwrap();
            for (j, row) in y.chunks(b).enumerate() {
                rows.extend(row.iter().map(|v| v * w[j]));
            }
        }
        let s = nalgebra::DMatrix::from_row_slice(points * n, b, &rows)
            .svd(false, false)
            .singular_values;
        s.max() / s.min()
    }

    /// A start inside the limits but in their outer 2 % (outside the band of `safety` =
    /// 0.98 times the half range around the middle) left no room on that side: no
    /// trajectory moved and both designs failed with an infinite criterion. Now each
    /// designs a trajectory that moves and keeps every limit, from the start at rest (a
    /// start a hair from its limit still cannot move that way: that error now names the
    /// start).
    /// An unexcited design names the joint that cannot move and the limit that holds it
    /// (a velocity limit of 1e-6 was told as "a joint with almost no range"); the reach
    /// is the amplitude of a sine at the lowest frequency within every limit.
    #[test]
    fn an_unexcited_design_names_the_confining_limit() {
        let mut limits = crate::simulate::tests::pendulum_limits();
        limits[1].velocity = 1e-6;
        let (j, reach, by) = most_confined(&limits, 10.0, 0.5).unwrap();
        let w = std::f64::consts::TAU / 10.0;
        assert_eq!((j, by.as_str()), (1, "its velocity limit 1e-6"));
        assert!((reach - 0.5 * 1e-6 / w).abs() < 1e-18, "{reach}");
        // the acceleration limit holds when it binds first; the position range of joint 1
        limits[1].velocity = 1.5;
        limits[0].acceleration = 1e-6;
        let (j, reach, by) = most_confined(&limits, 10.0, 1.0).unwrap();
        assert_eq!((j, by.as_str()), (0, "its acceleration limit 1e-6"));
        assert!((reach - 1e-6 / (w * w)).abs() < 1e-18, "{reach}");
        limits[0].acceleration = 4.0;
        limits[0].position = [0.5, 0.5 + 1e-5];
        let (j, reach, by) = most_confined(&limits, 10.0, 1.0).unwrap();
        assert_eq!((j, by.as_str()), (0, "its position range [0.5, 0.50001]"));
        assert!((reach - 5e-6).abs() < 1e-15, "{reach}");
        let e = check_design_cost(f64::INFINITY, Criterion::Condition, &limits, 10.0, 1.0)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("joint 1 can move at most about 5e-6 over the trajectory's period of 10 s, held by its position range"),
            "{e}"
        );
        // joints that can move: the general advice alone
        let e = check_design_cost(
            f64::INFINITY,
            Criterion::Condition,
            &crate::simulate::tests::pendulum_limits(),
            10.0,
            1.0,
        )
        .unwrap_err()
        .to_string();
        assert!(
            !e.contains("can move at most") && e.contains("check the joint limits"),
            "{e}"
        );
        assert!(check_design_cost(3.0, Criterion::Condition, &limits, 10.0, 1.0).is_ok());
        // a reach of CONFINED itself is not named: the joint can move a milliradian
        limits[0].position = [0.0, 2.0 * CONFINED];
        let e = check_design_cost(f64::INFINITY, Criterion::Condition, &limits, 10.0, 1.0)
            .unwrap_err()
            .to_string();
        assert!(!e.contains("can move at most"), "{e}");
    }

    #[test]
    fn a_start_near_a_limit_still_gets_a_design() {
        use crate::excite::{PointDesign, margins};
        let p = Pendulum::default();
        let limits = crate::simulate::tests::pendulum_limits();
        for start in [[1.995, 0.5], [-0.99, 1.99]] {
            let fourier = FourierDesign {
                restarts: 1,
                evaluations: 60,
                points: 30,
                start: Some(start.to_vec()),
                ..FourierDesign::default()
            };
            let r = fourier.optimize(&p, &limits, None).unwrap();
            let tr = r.fourier.sample(10.0, 100.0).unwrap();
            let points = PointDesign {
                duration: 8.0,
                intervals: 4,
                restarts: 1,
                sweeps: 1,
                evaluations: 40,
                start: Some(start.to_vec()),
                ..PointDesign::default()
            };
            let rp = points.optimize(&p, &limits, None).unwrap();
            let tp = rp.points.sample(100.0).unwrap();
            for (what, tr, cost) in [("fourier", &tr, r.cost), ("points", &tp, rp.cost)] {
                assert!(cost.is_finite(), "{what} {start:?}");
                let m = margins::<Pendulum>(tr, &limits, None).unwrap();
                assert!(m.iter().all(|m| m.respected()), "{what} {start:?}: {m:?}");
                for j in 0..2 {
                    assert_eq!(tr.q[j][0], start[j], "{what} {start:?}");
                    let (lo, hi) = tr.q[j]
                        .iter()
                        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), q| {
                            (a.min(*q), b.max(*q))
                        });
                    // a motion of its own, not a hair's breadth
                    assert!(
                        hi - lo > 0.1,
                        "{what} {start:?}: joint {j} moves {}",
                        hi - lo
                    );
                }
            }
        }
    }

    /// Weights 1e6 to 1 on the first joint of the pendulum (`--sigma 1e-6,1`): the weighted
    /// W has a condition number near 1e8 whatever the trajectory, beyond what the eigenvalues
    /// of W'W resolve, so every criterion was infinite and the design failed ("no finite
    /// criterion in 40 evaluations") while the unweighted one takes cond 35. The criteria
    /// now go through the equilibrated W'W there: the design succeeds with either
    /// criterion, and its cost is the condition number of the weighted W by its SVD.
    #[test]
    fn a_design_weighted_far_apart_finds_a_finite_criterion() {
        let p = Pendulum::default();
        let limits = crate::simulate::tests::pendulum_limits();
        let weights = vec![1e6, 1.0];
        for criterion in [Criterion::Condition, Criterion::DOptimal] {
            let design = FourierDesign {
                restarts: 1,
                evaluations: 40,
                points: 30,
                criterion,
                weights: Some(weights.clone()),
                ..FourierDesign::default()
            };
            let r = design.optimize(&p, &limits, None).unwrap();
            assert!(r.cost.is_finite(), "{criterion:?}");
            let cond = weighted_condition(&p, &r.fourier, design.points, &weights);
            eprintln!("{criterion:?}: cost {:e}, cond(W) by SVD {cond:e}", r.cost);
            // measured: cond 2.5e7 (condition) and 2.9e7 (D-optimality), where the
            // direct computation gave up
            assert!(cond > 1e7, "{cond}");
            if criterion == Criterion::Condition {
                // measured: 4e-16 relative (the grid's sines from a table there, from
                // sin_cos here)
                assert!((r.cost - cond).abs() < 1e-6 * cond, "{} vs {cond}", r.cost);
            }
        }
    }

    /// Sigmas are floored at 1e-6 of the largest, as weighted least squares floors them: a
    /// sigma of 1e-8 beside 1 weighs 1e6, not 1e8 (which made every trajectory's criterion
    /// infinite); sigmas within the floor keep 1 / sigma.
    #[test]
    fn weights_floor_a_sigma_as_least_squares_does() {
        let w = weights_from_sigma(&[1.0, 1e-8, 0.5], "excite", "sigma").unwrap();
        assert_eq!(w, vec![1.0, 1e6, 2.0]);
        let w = weights_from_sigma(&[1e-6, 1.0], "excite", "sigma").unwrap();
        assert_eq!(w, vec![1e6, 1.0]);
    }

    /// `random` with a start outside the limits gave a trajectory that sat there, unmoving
    /// (review 147); it now refuses the start as `optimize` does.
    #[test]
    fn random_refuses_a_start_outside_the_limits() {
        let lim = JointLimits {
            position: [-2.0, 2.0],
            velocity: 3.0,
            acceleration: 10.0,
            torque: None,
        };
        let design = |q| FourierDesign {
            start: Some(vec![q]),
            ..FourierDesign::default()
        };
        let e = design(2.5)
            .random(std::slice::from_ref(&lim))
            .unwrap_err()
            .to_string();
        assert!(e.contains("joint 1: 2.5 is outside the limits"), "{e}");
        assert!(design(1.0).random(&[lim]).is_ok());
    }
}
