//! The point-based design of Milella: optimal position, velocity and acceleration
//! points (OPVA) under the joint limits, joined by seventh-order polynomials.
//!
//! Decision variables, per joint and interior point, are z_q, z_v, z_a with the
//! sin-substitution of Milella (eq. 9): q = c + r sin z_q (c, r the middle and `safety` times
//! the half range of the position limits), qd = `safety` qd_max sin z_v, qdd = `safety`
//! qdd_max sin z_a, so every point lies within its limits whatever the z. The trajectory
//! starts and ends at rest at the start position (chosen the same way, unless fixed). The
//! jerk at an interior point is the central difference of its neighbours' accelerations (Milella
//! draws it at random; a deterministic value keeps the design reproducible and smooth) and zero
//! at the ends. The polynomials can overshoot between points, so each joint's excursion from the
//! start is scaled, after interpolation, by the largest factor <= 1 that keeps the position
//! range, |qd| and |qdd| within `safety` times their limits on a fine grid: the interpolated
//! trajectory respects every limit by construction (the scaled points stay within their limits
//! because the start does and the scale is at most 1).
//!
//! The criterion is evaluated on the extended regressor (eq. 14): rows at every interior point
//! and at `around` samples on each side of it, spread over `window` times the neighbouring
//! interval widths. With reference parameters, torques are checked on a grid of
//! `torque_samples` per interval and their excess over `safety` times the limits penalised,
//! as in the Fourier design (torques are the one limit not held by construction). The
//! minimisation is a Nelder-Mead over each point's 3 n variables in turn (block coordinate
//! descent: tens of variables per block instead of hundreds at once), for several sweeps,
//! from random starts run in parallel.
//!
//! ## Reference
//! F. Milella, "Direct Estimate of Closed-Form Dynamic Equation Parameters of a Robot:
//! Tools and Methods for Designing Experiments" (docs/references.md#milella), Phases II
//! and III: OPVA points (eq. 8), sine substitution (eq. 9), extended regressor
//! (eqs. 13-15); see also docs/experiments.md#point-method.

use rayon::prelude::*;

use crate::Model;
use crate::error::{Error, Result};
use crate::excite::design::{check_count, check_design_cost, check_joint_vectors};
use crate::excite::limits::{TorquePenalty, check_reference};
use crate::excite::polynomial::{Knot, Septic};
use crate::excite::{Criterion, Information, JointLimits, Points, check_limits};
use crate::excite::{MAX_EVALUATIONS, MAX_POINTS, MAX_RESTARTS};
use crate::limits::MAX_SAMPLES;
use crate::nelder_mead::NelderMead;
use crate::progress::Progress;
use crate::rng::Rng;

/// Settings of a point-based design.
#[derive(Debug, Clone, PartialEq)]
pub struct PointDesign {
    /// Duration of the trajectory (s).
    pub duration: f64,
    /// Number of equal intervals between the points (the interior points are optimised).
    pub intervals: usize,
    /// Extended-regressor samples on each side of a point.
    pub around: usize,
    /// Fraction of the neighbouring interval the extended samples span on each side (0..=1).
    pub window: f64,
    /// Fine-grid samples per interval on which the limits are enforced.
    pub fine: usize,
    /// Samples per interval on which the torques are checked (with reference parameters).
    pub torque_samples: usize,
    /// The criterion minimised.
    pub criterion: Criterion,
    /// Per-joint weights of the regressor rows (e.g. 1 / expected noise sigma, what weighted
    /// least squares sees); `None` = unweighted.
    pub weights: Option<Vec<f64>>,
    /// Random starts.
    pub restarts: usize,
    /// Sweeps over the points per start.
    pub sweeps: usize,
    /// Function evaluations per point and sweep.
    pub evaluations: usize,
    /// Seed of the random starts.
    pub seed: u64,
    /// Fraction of every limit the design may use (0 < safety <= 1).
    pub safety: f64,
    /// Fixed start (and end) position; `None` lets the optimiser choose it.
    pub start: Option<Vec<f64>>,
    /// Show the progress on standard error: a bar on a terminal, else a line every 10 s
    /// ([`crate::progress`]).
    pub progress: bool,
}

impl Default for PointDesign {
    fn default() -> Self {
        Self {
            duration: 30.0,
            intervals: 12,
            around: 3,
            window: 0.5,
            fine: 40,
            torque_samples: 8,
            criterion: Criterion::Condition,
            weights: None,
            restarts: 4,
            sweeps: 4,
            evaluations: 120,
            seed: 1,
            safety: 0.98,
            start: None,
            progress: false,
        }
    }
}

/// The result of a point-based design.
#[derive(Debug, Clone)]
pub struct PointResult {
    /// The trajectory.
    pub points: Points,
    /// The value minimised: the criterion on the extended regressor, plus the torque penalty
    /// when reference parameters were given (zero within the torque limits).
    pub cost: f64,
    /// The criterion's value at the best random start (before optimisation).
    pub initial_cost: f64,
    /// Function evaluations used.
    pub evaluations: usize,
}

impl PointDesign {
    /// Checks the settings for a model of `dof` joints (ranges in [`crate::excite`]'s
    /// documentation).
    pub fn check(&self, dof: usize) -> Result<()> {
        let owner = "PointDesign";
        let bad = |key: &str, problem: String| Err(Error::setting(owner, key, problem));
        if !(self.duration > 0.0 && self.duration <= MAX_SAMPLES as f64) {
            return bad(
                "duration",
                format!(
                    "{} s must lie in (0, {MAX_SAMPLES}] s",
                    crate::error::num(self.duration)
                ),
            );
        }
        check_count(owner, "intervals", self.intervals, 2, MAX_POINTS)?;
        if !(self.window > 0.0 && self.window <= 1.0) {
            return bad("window", format!("{} must lie in (0, 1]", self.window));
        }
        if !(self.safety > 0.0 && self.safety <= 1.0) {
            return bad("safety", format!("{} must lie in (0, 1]", self.safety));
        }
        check_count(owner, "around", self.around, 0, MAX_POINTS)?;
        check_count(owner, "fine", self.fine, 2, MAX_POINTS)?;
        check_count(owner, "torque_samples", self.torque_samples, 1, MAX_POINTS)?;
        check_count(owner, "restarts", self.restarts, 1, MAX_RESTARTS)?;
        check_count(owner, "sweeps", self.sweeps, 1, MAX_RESTARTS)?;
        check_count(owner, "evaluations", self.evaluations, 1, MAX_EVALUATIONS)?;
        check_joint_vectors(owner, dof, self.start.as_deref(), self.weights.as_deref())
    }

    /// Designs a trajectory for `model` within `limits`; `torque` = reference base
    /// parameters enables the torque limits.
    pub fn optimize<M: Model + Sync + ?Sized>(
        &self,
        model: &M,
        limits: &[JointLimits],
        torque: Option<&[f64]>,
    ) -> Result<PointResult> {
        let n = model.dof();
        self.check(n)?;
        check_limits(limits, n)?;
        crate::excite::design::check_start(self.start.as_deref(), limits)?;
        check_reference(model, torque)?;
        let decoder = Decoder::new(self, limits);
        let m = decoder.per_joint();
        let cost = |x: &[f64]| match decoder.decode(x) {
            Ok(points) => {
                self.cost(model, &points)
                    + torque.map_or(0.0, |b| self.penalty(model, limits, b, &points))
            }
            Err(_) => f64::INFINITY,
        };
        let interior = self.intervals - 1;
        let blocks = interior + usize::from(self.start.is_none());
        // evaluations; a run that stops before its budget counts the whole budget, so
        // that the share shown is the share of the work done
        let progress = Progress::new(
            self.progress,
            "excite: point design",
            (self.restarts * self.sweeps * blocks * self.evaluations) as u64,
            "evaluations",
        );
        let nm = NelderMead {
            max_evaluations: self.evaluations,
            tolerance: 1e-10,
            absolute_tolerance: 1e-10,
            step: vec![0.4],
        };
        let root = Rng::new(self.seed);
        let runs: Vec<_> = (0..self.restarts)
            .into_par_iter()
            .map(|r| {
                let mut x = decoder.start_point(&mut root.fork(r as u64), n * m);
                let initial = cost(&x);
                let (mut value, mut evaluations) = (initial, 1);
                let counter = progress.counter();
                for _ in 0..self.sweeps {
                    for b in 0..blocks {
                        // the variables of point b of every joint (or the start offsets)
                        let index: Vec<usize> = (0..n)
                            .flat_map(|j| {
                                let first = j * m + 3 * b;
                                if b < interior {
                                    first..first + 3
                                } else {
                                    j * m + 3 * interior..j * m + 3 * interior + 1
                                }
                            })
                            .collect();
                        let x0: Vec<f64> = index.iter().map(|&i| x[i]).collect();
                        let mut trial = x.clone();
                        let found = nm.minimize(&x0, |y| {
                            counter.tick();
                            for (&i, &v) in index.iter().zip(y) {
                                trial[i] = v;
                            }
                            cost(&trial)
                        })?;
                        counter.add(self.evaluations.saturating_sub(found.evaluations) as u64);
                        evaluations += found.evaluations;
                        if found.value < value {
                            value = found.value;
                            for (&i, &v) in index.iter().zip(&found.x) {
                                x[i] = v;
                            }
                        }
                    }
                }
                Ok((x, value, initial, evaluations))
            })
            .collect::<Result<Vec<_>>>()?;
        progress.finish();
        let evaluations = runs.iter().map(|r| r.3).sum();
        let initial_cost = runs.iter().map(|r| r.2).fold(f64::INFINITY, f64::min);
        let (x, cost, _, _) = runs
            .into_iter()
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .ok_or_else(|| Error::setting("PointDesign", "restarts", "no start was run"))?;
        check_design_cost(cost, self.criterion, limits, self.duration, self.safety)?;
        Ok(PointResult {
            points: decoder.decode(&x)?,
            cost,
            initial_cost,
            evaluations,
        })
    }

    /// A random, non-optimised point trajectory within the same limits (the first start of
    /// [`PointDesign::optimize`] with this seed).
    ///
    /// # Errors
    /// [`crate::error::Error::Setting`] for the settings [`PointDesign::optimize`]
    /// refuses, a start outside the limits included.
    pub fn random(&self, limits: &[JointLimits]) -> Result<Points> {
        self.check(limits.len())?;
        check_limits(limits, limits.len())?;
        crate::excite::design::check_start(self.start.as_deref(), limits)?;
        let decoder = Decoder::new(self, limits);
        let len = limits.len() * decoder.per_joint();
        decoder.decode(&decoder.start_point(&mut Rng::new(self.seed).fork(0), len))
    }

    /// The times at which the criterion stacks the regressor: every interior point and
    /// `around` samples on each side within `window` times the neighbouring intervals.
    pub fn criterion_times(&self) -> Vec<f64> {
        let h = self.duration / self.intervals as f64;
        let a = self.around as isize;
        (1..self.intervals)
            .flat_map(|i| {
                (-a..=a).map(move |k| {
                    let step = if a == 0 {
                        0.0
                    } else {
                        self.window * h / a as f64
                    };
                    i as f64 * h + k as f64 * step
                })
            })
            .collect()
    }

    /// The criterion on the extended regressor of `points`.
    pub fn cost<M: Model + ?Sized>(&self, model: &M, points: &Points) -> f64 {
        let n = model.dof();
        let mut info = Information::new(model);
        if let Some(w) = &self.weights {
            info = info.with_weights(w);
        }
        let (mut q, mut qd, mut qdd) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        for t in self.criterion_times() {
            points.state(t, &mut q, &mut qd, &mut qdd);
            // Sizes are checked on entry; a model that still refuses makes the point infinitely bad.
            if info.add(model, &q, &qd, &qdd).is_err() {
                return f64::INFINITY;
            }
        }
        info.cost(self.criterion)
    }

    /// The torque-limit penalty of `points` with reference base parameters `base`.
    fn penalty<M: Model + ?Sized>(
        &self,
        model: &M,
        limits: &[JointLimits],
        base: &[f64],
        points: &Points,
    ) -> f64 {
        let n = model.dof();
        let mut penalty = TorquePenalty::new(limits, self.safety, base);
        let (mut q, mut qd, mut qdd) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        let samples = self.intervals * self.torque_samples;
        for k in 0..=samples {
            points.state(
                self.duration * k as f64 / samples as f64,
                &mut q,
                &mut qd,
                &mut qdd,
            );
            if penalty.add(model, &q, &qd, &qdd).is_err() {
                return f64::INFINITY;
            }
        }
        penalty.value()
    }
}

/// Turns decision variables into a point trajectory within the limits.
struct Decoder<'a> {
    design: &'a PointDesign,
    limits: &'a [JointLimits],
    times: Vec<f64>,
}

impl<'a> Decoder<'a> {
    fn new(design: &'a PointDesign, limits: &'a [JointLimits]) -> Self {
        let h = design.duration / design.intervals as f64;
        let times = (0..=design.intervals).map(|i| i as f64 * h).collect();
        Self {
            design,
            limits,
            times,
        }
    }

    /// 3 variables per interior point, then the start offset when it is free.
    fn per_joint(&self) -> usize {
        3 * (self.design.intervals - 1) + usize::from(self.design.start.is_none())
    }

    /// Random points: positions anywhere in range, velocities and accelerations around half
    /// their limits, start offset anywhere.
    fn start_point(&self, rng: &mut Rng, len: usize) -> Vec<f64> {
        let m = self.per_joint();
        let interior = 3 * (self.design.intervals - 1);
        (0..len)
            .map(|i| match i % m {
                k if k >= interior => rng.uniform(-1.5, 1.5),
                k if k % 3 == 0 => rng.uniform(-1.5, 1.5),
                _ => 0.6 * rng.normal(),
            })
            .collect()
    }

    fn decode(&self, x: &[f64]) -> Result<Points> {
        let d = self.design;
        let m = self.per_joint();
        let interior = d.intervals - 1;
        let knots = self
            .limits
            .iter()
            .enumerate()
            .map(|(j, l)| {
                let v = &x[j * m..(j + 1) * m];
                let [lo, hi] = l.position;
                let (mid, half) = (0.5 * (lo + hi), 0.5 * (hi - lo) * d.safety);
                let q0 = match &d.start {
                    Some(q0) => q0[j],
                    None => mid + half * v[3 * interior].sin(),
                };
                // excursions from the start: (q - q0, qd, qdd, jerk)
                let mut k: Vec<Knot> = vec![[0.0; 4]; d.intervals + 1];
                for i in 0..interior {
                    k[i + 1] = [
                        mid + half * v[3 * i].sin() - q0,
                        d.safety * l.velocity * v[3 * i + 1].sin(),
                        d.safety * l.acceleration * v[3 * i + 2].sin(),
                        0.0,
                    ];
                }
                for i in 1..=interior {
                    k[i][3] = (k[i + 1][2] - k[i - 1][2]) / (self.times[i + 1] - self.times[i - 1]);
                }
                let scale = self.scale(&k, l, q0)?;
                Ok(k.iter()
                    .map(|k| [q0 + scale * k[0], scale * k[1], scale * k[2], scale * k[3]])
                    .collect())
            })
            .collect::<Result<_>>()?;
        Points::new(self.times.clone(), knots)
    }

    /// The largest factor <= 1 that keeps the interpolated excursions `k` within the limits.
    fn scale(&self, k: &[Knot], l: &JointLimits, q0: f64) -> Result<f64> {
        let d = self.design;
        let (mut gmax, mut gmin, mut vmax, mut amax) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
        for (w, t) in k.windows(2).zip(self.times.windows(2)) {
            let seg = Septic::new(w[0], w[1], t[1] - t[0])?;
            for s in 0..=d.fine {
                let [g, gd, gdd, _] = seg.eval(seg.width * s as f64 / d.fine as f64);
                gmax = gmax.max(g);
                gmin = gmin.min(g);
                vmax = vmax.max(gd.abs());
                amax = amax.max(gdd.abs());
            }
        }
        let (below, above) = crate::excite::limits::position_room(l.position, d.safety, q0);
        let mut scale = 1.0f64;
        for (room, peak) in [
            (d.safety * l.velocity, vmax),
            (d.safety * l.acceleration, amax),
            (above, gmax),
            (below, -gmin),
        ] {
            if peak > 0.0 {
                scale = scale.min(room / peak);
            }
        }
        Ok(scale)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::excite::margins;
    use crate::simulate::tests::Pendulum;

    use crate::simulate::tests::pendulum_limits as limits;

    /// Weights given in code are floored as the command line floors sigmas (each weight at
    /// most 1e6 times the smallest, `floor_weights`): a point design and a Fourier design
    /// weighted 1e9 to 1 are those weighted as the command line weighs sigmas 1e-9 and 1
    /// (1e6 to 1), to the bit.
    #[test]
    fn design_weights_given_in_code_are_floored_as_the_command_line_floors_them() {
        use crate::excite::{FourierDesign, weights_from_sigma};
        let p = Pendulum::default();
        let points = |weights: Vec<f64>| PointDesign {
            duration: 8.0,
            intervals: 4,
            restarts: 1,
            sweeps: 1,
            evaluations: 40,
            weights: Some(weights),
            ..PointDesign::default()
        };
        let fourier = |weights: Vec<f64>| FourierDesign {
            restarts: 1,
            evaluations: 40,
            points: 30,
            weights: Some(weights),
            ..FourierDesign::default()
        };
        let same = |apart: f64, floored: f64| {
            assert_eq!(apart.to_bits(), floored.to_bits(), "{apart} {floored}");
        };
        let cli = weights_from_sigma(&[1e-9, 1.0], "excite", "sigma").unwrap();
        assert_eq!(cli, vec![1e6, 1.0]);
        let floored = points(cli.clone()).optimize(&p, &limits(), None).unwrap();
        let apart = points(vec![1e9, 1.0])
            .optimize(&p, &limits(), None)
            .unwrap();
        same(apart.cost, floored.cost);
        let cli = weights_from_sigma(&[1.0, 1e-9], "excite", "sigma").unwrap();
        let floored = fourier(cli).optimize(&p, &limits(), None).unwrap();
        let apart = fourier(vec![1.0, 1e9])
            .optimize(&p, &limits(), None)
            .unwrap();
        same(apart.cost, floored.cost);
    }

    #[test]
    fn random_points_respect_every_limit_by_construction() {
        for seed in 0..20 {
            let design = PointDesign {
                duration: 8.0,
                intervals: 4,
                seed,
                ..PointDesign::default()
            };
            let tr = design.random(&limits()).unwrap().sample(200.0).unwrap();
            let m = margins::<Pendulum>(&tr, &limits(), None).unwrap();
            assert!(m.iter().all(|m| m.respected()), "seed {seed}: {m:?}");
            for j in 0..2 {
                assert!(tr.qd[j][0] == 0.0 && tr.qdd[j][0] == 0.0);
                assert!((tr.q[j][0] - tr.q[j][tr.samples() - 1]).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn optimisation_lowers_the_condition_number_within_the_limits() {
        let p = Pendulum::default();
        let design = PointDesign {
            duration: 8.0,
            intervals: 4,
            restarts: 2,
            sweeps: 2,
            evaluations: 80,
            start: Some(vec![0.2, -0.1]),
            ..PointDesign::default()
        };
        let r = design.optimize(&p, &limits(), None).unwrap();
        // measured 0.65 of the initial cost
        assert!(
            r.cost < 0.9 * r.initial_cost,
            "{} vs {}",
            r.cost,
            r.initial_cost
        );
        assert!((r.cost - design.cost(&p, &r.points)).abs() < 1e-9 * r.cost);
        let tr = r.points.sample(200.0).unwrap();
        assert!(
            margins::<Pendulum>(&tr, &limits(), None)
                .unwrap()
                .iter()
                .all(|m| m.respected())
        );
        assert!((tr.q[0][0] - 0.2).abs() < 1e-12);
        let bad = PointDesign {
            start: Some(vec![5.0, 0.0]),
            ..design.clone()
        };
        assert!(bad.optimize(&p, &limits(), None).is_err());
    }

    /// As `FourierDesign::random`: a start outside the limits is refused, not sampled.
    #[test]
    fn random_refuses_a_start_outside_the_limits() {
        let mut start: Vec<f64> = limits()
            .iter()
            .map(|l| 0.5 * (l.position[0] + l.position[1]))
            .collect();
        let design = |start: Vec<f64>| PointDesign {
            start: Some(start),
            ..PointDesign::default()
        };
        assert!(design(start.clone()).random(&limits()).is_ok());
        start[1] = limits()[1].position[1] + 0.5;
        let e = design(start).random(&limits()).unwrap_err().to_string();
        assert!(
            e.contains("joint 2:") && e.contains("is outside the limits"),
            "{e}"
        );
    }
}
