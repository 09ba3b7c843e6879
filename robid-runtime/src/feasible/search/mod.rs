//! The global search of Gaz et al.: C. Gaz, F. Flacco, A. De Luca, "Extracting feasible
//! robot parameters from dynamic coefficients using nonlinear optimization methods",
//! IEEE ICRA 2016.
//!
//! Minimise f(x) = ||L^-1 (K p(x) - beta)||^2 + penalty(x) over a box of link
//! variables x (masses, centres of mass, inertias, parametrised so every point is
//! physically consistent, see `parametrise`), by simulated annealing from random
//! starting points ("random restarts"), each followed by a Nelder-Mead local search; the
//! best result wins. The penalty (Gaz et al.'s delta term) holds the total mass in its range,
//! the principal moments and the tensor elements in theirs and the equalities; the best
//! point is then polished under a rising penalty until they all hold (`impose`). Variables with no effect on f are fixed at the
//! stated don't-care values (centre of the bounds) and left out of the search. Drive terms
//! (Ia, Fv, Fc, Fo) and extra columns enter linearly and are solved for at every evaluation
//! (least squares in their columns, then Ia, Fv, Fc clamped at zero). Each Nelder-Mead result is
//! polished by a bounded Levenberg-Marquardt (the objective is a sum of squares), then
//! improved by "hops" (iterated local search, Lourenco, Martin, Stuetzle 2003): one link's
//! variables are drawn afresh, the point polished again, and kept when better. The
//! parametrisation has spurious local minima where a link sits in a corner of its box (second
//! moments at their lower bound, centre of mass on a face); without hops about half the seeds
//! ended there on the simulated UR5e (chi^2 40-170 against 36 base parameters), with 12 hops
//! none of 16 did.

mod anneal;
mod data;
mod equality;
mod levenberg;
mod parametrise;
mod towards_prior;
mod two_step;

use crate::FeasibleError;
use std::cell::RefCell;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use nalgebra::{DMatrix, DVector, DVectorView};
use rayon::prelude::*;

use super::bounds::{Bounds, TENSOR_ELEMENTS};
use super::prior::{Prior, Pull};
use super::problem::Problem;
use super::solution::{Method, Solution};
use crate::nelder_mead::NelderMead;
use crate::progress::Progress;
use crate::rng::Rng;
use crate::{Error, Num, Result};
use anneal::{AnnealSettings, reflect};
use data::{Data, Scratch};
use parametrise::{PER_LINK, link_box, link_centre, link_of};

pub use equality::{Equality, MAX_EQUALITY_FACTORS, Quantity, Variable};
pub use two_step::{TwoStep, solve_gravity_step, solve_two_step};

/// Settings of the global search.
#[derive(Debug, Clone, PartialEq)]
pub struct AnnealOptions {
    /// Random restarts (each: annealing, then Nelder-Mead), run in parallel (Gaz et al.'s K,
    /// 1000 in their paper).
    pub restarts: usize,
    /// Annealing steps per restart.
    pub iterations: usize,
    /// Nelder-Mead evaluations per restart.
    pub local_evaluations: usize,
    /// Seed of the random generator (results are reproducible).
    pub seed: u64,
    /// Stop starting new restarts once chi^2 falls below this (default: 1e-3 per base parameter).
    pub target_chi2: Option<f64>,
    /// Weight of the bound penalty (Gaz et al.'s delta).
    pub penalty: f64,
    /// Levenberg-Marquardt steps that polish each Nelder-Mead result (0: none).
    pub polish_iterations: usize,
    /// Hops per restart: one link (in turn) drawn afresh and polished, kept when better.
    pub hops: usize,
    /// The user's prior (e.g. CAD values), pulled towards as in the other methods, and
    /// as in them the default prior (at [`DEFAULT_PRIOR_WEIGHT`]) for the parameters it
    /// does not give; without a prior, what the data leave free stays where the search
    /// leaves it (within the bounds).
    ///
    /// [`DEFAULT_PRIOR_WEIGHT`]: crate::feasible::DEFAULT_PRIOR_WEIGHT
    pub prior: Option<Prior>,
    /// Masses and centre-of-mass coordinates held at given values (the second step of
    /// [`solve_two_step`] holds those the gravity step found).
    pub fixed: Vec<(Variable, f64)>,
    /// Equality constraints in the form of Gaz et al.'s eq. 15, each a penalty row weighted
    /// like the bounds (`penalty`).
    pub equalities: Vec<Equality>,
    /// Gaz et al.'s step penalty on the total mass (their delta, 10 in the paper): this much
    /// is added to the cost when the total mass is outside its range, instead of the
    /// penalty proportional to the excess. `None`: the proportional penalty.
    pub mass_step: Option<f64>,
    /// Show the progress on standard error, in restarts: a bar on a terminal, else a line
    /// every 10 s ([`crate::progress`]).
    pub progress: bool,
}

impl Default for AnnealOptions {
    fn default() -> AnnealOptions {
        AnnealOptions {
            restarts: 8,
            iterations: 20_000,
            local_evaluations: 20_000,
            seed: 1,
            target_chi2: None,
            penalty: 1e10,
            polish_iterations: 200,
            hops: 12,
            prior: None,
            fixed: Vec::new(),
            equalities: Vec::new(),
            mass_step: None,
            progress: false,
        }
    }
}

impl AnnealOptions {
    /// Checks the settings: counts within their caps (every loop of the search is bounded
    /// by them: annealing steps, Nelder-Mead evaluations, Levenberg-Marquardt steps, hops),
    /// a positive finite penalty, a finite non-negative target.
    pub fn check(&self) -> Result<()> {
        let count = |key: &str, v: usize, lo: usize, hi: usize| {
            if (lo..=hi).contains(&v) {
                Ok(())
            } else {
                Err(Error::setting(
                    "AnnealOptions",
                    key,
                    format!("{v} must lie between {lo} and {hi}"),
                ))
            }
        };
        count("restarts", self.restarts, 1, 10_000)?;
        count("iterations", self.iterations, 0, 1_000_000_000)?;
        count(
            "local_evaluations",
            self.local_evaluations,
            0,
            1_000_000_000,
        )?;
        count("polish_iterations", self.polish_iterations, 0, 1_000_000)?;
        count("hops", self.hops, 0, 1_000_000)?;
        if !(self.penalty > 0.0 && self.penalty <= 1e20) {
            return Err(Error::setting(
                "AnnealOptions",
                "penalty",
                format!("{} must lie in (0, 1e20]", self.penalty),
            ));
        }
        if let Some(d) = self.mass_step
            && !(d > 0.0 && d <= 1e20)
        {
            return Err(Error::setting(
                "AnnealOptions",
                "mass_step",
                format!("{d} must lie in (0, 1e20]"),
            ));
        }
        for (v, value) in &self.fixed {
            if v.index().is_none() {
                return Err(Error::setting(
                    "AnnealOptions",
                    "fixed",
                    format!("{v}: only masses and centre-of-mass coordinates can be held fixed"),
                ));
            }
            if !(value.abs() <= crate::limits::MAX_PARAMETER) {
                return Err(Error::setting(
                    "AnnealOptions",
                    "fixed",
                    format!("{v} = {value}: write a finite value of magnitude at most 1e6"),
                ));
            }
        }
        if let Some(t) = self.target_chi2
            && !(t >= 0.0 && t.is_finite())
        {
            return Err(Error::setting(
                "AnnealOptions",
                "target_chi2",
                format!("{t} must be finite and non-negative"),
            ));
        }
        Ok(())
    }
}

/// The objective over the free variables.
struct Objective<'a> {
    problem: &'a Problem,
    bounds: &'a Bounds,
    /// Whitened K and target, the drive terms and extra columns solved for.
    data: Data,
    /// Full variable vector with the fixed (don't-care) values.
    fixed: Vec<f64>,
    /// Which full variables are searched.
    free: Vec<usize>,
    penalty: f64,
    /// The pull towards the user's prior (weight zero where it gives no value).
    pull: Option<Pull>,
    /// Equality constraints (penalty rows).
    equalities: &'a [Equality],
    /// Gaz et al.'s step penalty on the total mass, if chosen.
    mass_step: Option<f64>,
    /// The links whose mass is neither searched nor held (it has no effect on the fit),
    /// with the box of that mass.
    loose: Vec<(usize, [f64; 2])>,
    /// Every pseudo-inertia is at least this times the identity ([`Objective::lift`]).
    margin: f64,
}

impl Objective<'_> {
    /// The full variable vector of the searched values `y`, lifted to the margin.
    fn full(&self, y: &[f64]) -> Vec<f64> {
        let mut x = self.unlifted(y);
        self.lift(&mut x);
        x
    }

    /// The full variable vector of the searched values `y` as the box holds them.
    fn unlifted(&self, y: &[f64]) -> Vec<f64> {
        let mut x = self.fixed.clone();
        self.place(y, &mut x);
        x
    }

    /// Writes the searched values `y` into the full variable vector `x`.
    fn place(&self, y: &[f64], x: &mut [f64]) {
        for (&i, &v) in self.free.iter().zip(y) {
            x[i] = v;
        }
    }

    /// `x` lifted to the margin ([`lift`]).
    fn lift(&self, x: &mut [f64]) {
        lift(x, self.margin);
    }

    /// Buffers for evaluations of this objective.
    fn scratch(&self) -> Scratch {
        self.data.scratch(&self.problem.layout)
    }

    /// Puts the full variables of the searched values `y` into `s.x`.
    fn fill(&self, y: &[f64], s: &mut Scratch) {
        s.x.copy_from_slice(&self.fixed);
        self.place(y, &mut s.x);
        self.lift(&mut s.x);
    }

    /// Evaluates the data term at the searched values `y` into `s` ([`Data::evaluate`]).
    fn evaluate(&self, y: &[f64], s: &mut Scratch) {
        self.fill(y, s);
        self.data.evaluate(&self.problem.layout, s);
    }

    /// Standard parameters of a full variable vector, drive terms solved for.
    fn standard(&self, x: &[f64]) -> Vec<f64> {
        let mut s = self.scratch();
        s.x.copy_from_slice(x);
        self.data.evaluate_exact(&self.problem.layout, &mut s);
        s.p
    }

    /// The objective's value at the searched values `y`.
    fn value(&self, y: &[f64]) -> f64 {
        self.value_in(y, &mut self.scratch())
    }

    /// [`Objective::value`] in the buffers `s`, with the search's old roundings
    /// ([`Data::evaluate_exact`], the rows summed by nalgebra's norm).
    fn value_in(&self, y: &[f64], s: &mut Scratch) -> f64 {
        self.fill(y, s);
        self.data.evaluate_exact(&self.problem.layout, s);
        let mut rows = std::mem::take(&mut s.rows);
        rows.clear();
        self.rows(s, |v| rows.push(v));
        let value = DVectorView::from_slice(&rows, rows.len()).norm_squared();
        s.rows = rows;
        value
    }

    /// The whitened misfit and the pull, followed by the weighted relative bound
    /// violations, with the search's old roundings ([`Data::evaluate_exact`]).
    fn residual(&self, y: &[f64]) -> DVector<f64> {
        let mut s = self.scratch();
        self.fill(y, &mut s);
        self.data.evaluate_exact(&self.problem.layout, &mut s);
        let mut r = Vec::with_capacity(s.r.len() + s.p.len());
        self.rows(&s, |v| r.push(v));
        DVector::from_vec(r)
    }

    /// Gives `row` each residual row of the evaluation `s` in turn: the whitened misfit,
    /// the pull, the weighted relative bound violations and the mass step.
    fn rows(&self, s: &Scratch, mut row: impl FnMut(f64)) {
        self.misfit_rows(s, &mut row);
        self.bound_rows(&s.x, &mut row);
    }

    /// The weighted relative bound violations and the mass step at the full variables `x`.
    fn bound_rows(&self, x: &[f64], row: &mut impl FnMut(f64)) {
        let w = self.penalty.sqrt();
        self.for_each_violation(x, |e| row(w * e));
        if let Some(step) = self.mass_step_row(x) {
            row(step);
        }
    }

    /// The whitened misfit and the pull towards the prior of the evaluation `s`.
    fn misfit_rows(&self, s: &Scratch, row: &mut impl FnMut(f64)) {
        for &v in &s.r {
            row(v);
        }
        if let Some(pull) = &self.pull {
            for (k, &v) in s.p.iter().enumerate() {
                if let Some(weight) = self.pull_weight(k) {
                    row(weight.sqrt() * (v - pull.target[k]) / pull.scale[k]);
                }
            }
        }
    }

    /// The weight of standard parameter `k`'s pull row, if it has one: the one test of
    /// both the rows ([`Objective::misfit_rows`]) and the Jacobian's
    /// ([`Objective::pulled_rows`]), so that their counts agree.
    fn pull_weight(&self, k: usize) -> Option<f64> {
        let weight = self.pull.as_ref()?.weight[k];
        (weight > 0.0).then_some(weight)
    }

    /// The Jacobian of [`Objective::residual`] at `y` by forward differences with the
    /// polish's steps ([`levenberg::step`]): a step changes one link's variables, so only
    /// that link is re-evaluated, and the changes of the misfit and the pull are formed
    /// directly ([`Data::step_link`]); the bound rows are differences of values.
    fn jacobian(&self, y: &[f64], lo: &[f64], hi: &[f64]) -> DMatrix<f64> {
        let mut at = self.scratch();
        self.evaluate(y, &mut at);
        let pulled = self.pulled_rows(&at);
        let start = at.r.len() + pulled.iter().flatten().count();
        let mut bounds = Vec::new();
        self.bound_rows(&at.x, &mut |v| bounds.push(v));
        let mut moved = at.clone();
        let mut unlifted = self.unlifted(y);
        let layout = &self.problem.layout;
        let mut jac = DMatrix::zeros(start + bounds.len(), y.len());
        for (i, &full) in self.free.iter().enumerate() {
            let step = levenberg::step(y[i], lo[i], hi[i]);
            let link = full / PER_LINK;
            let range = link * PER_LINK..(link + 1) * PER_LINK;
            moved.copy_from(&at);
            unlifted[full] = y[i] + step;
            moved.x[range.clone()].copy_from_slice(&unlifted[range.clone()]);
            self.lift(&mut moved.x[range]);
            unlifted[full] = y[i];
            self.data.step_link(layout, link, &mut moved);
            let mut column = jac.column_mut(i);
            for (c, d) in column.iter_mut().zip(&moved.delta) {
                *c = d / step;
            }
            // the pull changes where the standard vector does: the link and the linear terms
            if let Some(pull) = &self.pull {
                let linear = self.data.linear.iter().map(|&(index, _)| index);
                for k in layout.links[link].iter().copied().chain(linear) {
                    if let Some(row) = pulled[k] {
                        let change = moved.p[k] - at.p[k];
                        column[row] = pull.weight[k].sqrt() * change / pull.scale[k] / step;
                    }
                }
            }
            let mut k = 0;
            self.bound_rows(&moved.x, &mut |v| {
                column[start + k] = (v - bounds[k]) / step;
                k += 1;
            });
        }
        jac
    }

    /// Per standard parameter, its row among the residual rows of `s` if the pull has one.
    fn pulled_rows(&self, s: &Scratch) -> Vec<Option<usize>> {
        let mut next = s.r.len();
        (0..s.p.len())
            .map(|k| {
                self.pull_weight(k).map(|_| {
                    next += 1;
                    next - 1
                })
            })
            .collect()
    }

    /// Gaz et al.'s step: sqrt(delta) when the total mass is outside its range, else zero
    /// (so the cost grows by delta); no row without a range or without the step.
    fn mass_step_row(&self, x: &[f64]) -> Option<f64> {
        let delta = self.mass_step?;
        let excess = self.mass_excess(x)?;
        Some(if excess > 0.0 { delta.sqrt() } else { 0.0 })
    }

    /// How far (kg) the total mass misses its range; a loose mass (no effect on the fit)
    /// counts as anything in its box, since [`Objective::settle_masses`] sets it afterwards.
    fn mass_excess(&self, x: &[f64]) -> Option<f64> {
        let t = self.bounds.total_mass?;
        let (lo, hi) = self.total_mass_span(x);
        Some((t[0] - hi).max(lo - t[1]).max(0.0))
    }

    /// The least and the largest total mass with the loose masses anywhere in their boxes.
    fn total_mass_span(&self, x: &[f64]) -> (f64, f64) {
        let (mut lo, mut hi) = (0.0, 0.0);
        for j in 0..self.bounds.links.len() {
            match self.loose.iter().find(|(l, _)| *l == j) {
                Some((_, b)) => {
                    lo += b[0];
                    hi += b[1];
                }
                None => {
                    lo += x[j * PER_LINK];
                    hi += x[j * PER_LINK];
                }
            }
        }
        (lo, hi)
    }

    /// Moves the loose masses from their don't-care values, by one share of each box, just
    /// far enough to bring the total mass into its range (nothing else changes: they have no
    /// effect on the fit).
    fn settle_masses(&self, x: &mut [f64]) {
        let Some(t) = self.bounds.total_mass else {
            return;
        };
        if self.loose.is_empty() {
            return;
        }
        let (lo, hi) = self.total_mass_span(x);
        let now: f64 = (0..self.bounds.links.len()).map(|j| x[j * PER_LINK]).sum();
        let wanted = now.clamp(t[0], t[1]).clamp(lo, hi);
        if (wanted - now).abs() == 0.0 || hi <= lo {
            return;
        }
        let share = (wanted - lo) / (hi - lo);
        for (j, b) in &self.loose {
            x[j * PER_LINK] = b[0] + share * (b[1] - b[0]);
        }
    }

    /// Relative violations of the total-mass range, the principal-moment and tensor-element
    /// ranges and the equalities.
    fn violations(&self, x: &[f64]) -> Vec<f64> {
        let mut v = Vec::new();
        self.for_each_violation(x, |e| v.push(e));
        v
    }

    /// Gives `violation` each of [`Objective::violations`] in turn.
    fn for_each_violation(&self, x: &[f64], mut violation: impl FnMut(f64)) {
        let out =
            |value: f64, r: [f64; 2], scale: f64| (r[0] - value).max(value - r[1]).max(0.0) / scale;
        if let (Some(t), None) = (self.bounds.total_mass, self.mass_step) {
            violation(self.mass_excess(x).unwrap_or(0.0) / t[1].max(1e-9));
        }
        for (j, b) in self.bounds.links.iter().enumerate() {
            let d = &x[j * PER_LINK + 4..j * PER_LINK + 7];
            for m in [d[1] + d[2], d[0] + d[2], d[0] + d[1]] {
                violation(out(m, b.inertia, b.inertia[1].max(1e-9)));
            }
            if b.tensor.iter().any(Option::is_some) {
                let inertia = link_of(&x[j * PER_LINK..(j + 1) * PER_LINK]).inertia;
                for (range, (_, row, column)) in b.tensor.iter().zip(TENSOR_ELEMENTS) {
                    if let Some(r) = *range {
                        let scale = r[0].abs().max(r[1].abs()).max(1e-9);
                        violation(out(inertia[row][column], r, scale));
                    }
                }
            }
        }
        for e in self.equalities {
            violation(e.violation(x, &self.bounds.links));
        }
    }
}

/// Feasible link parameters by the global search of Gaz et al. (see the module docs).
pub fn solve_anneal(
    problem: &Problem,
    bounds: &Bounds,
    options: &AnnealOptions,
) -> Result<Solution> {
    search(problem, bounds, options, "feasible: anneal").map(|(solution, _)| solution)
}

/// [`solve_anneal`], and the searched variables (indices into the full variable vector);
/// `title` names the search in its progress.
fn search(
    problem: &Problem,
    bounds: &Bounds,
    options: &AnnealOptions,
    title: &str,
) -> Result<(Solution, Vec<usize>)> {
    let start = Instant::now();
    let layout = &problem.layout;
    let nl = layout.links.len();
    bounds.check_for(nl)?;
    options.check()?;
    let a = &problem.whitening * &problem.k;
    let b = &problem.whitening * &problem.target;
    let linear: Vec<(usize, bool)> = layout
        .drives
        .iter()
        .map(|d| (d.index, d.kind.non_negative()))
        .chain(layout.extra.iter().map(|&i| (i, false)))
        .collect();
    let data = Data::new(a, b, layout, linear);
    let pull = match &options.prior {
        Some(prior) => Some(Pull::new(
            problem,
            bounds,
            Some(prior),
            super::prior::DEFAULT_PRIOR_WEIGHT,
        )?),
        None => None,
    };
    let margin = bounds.margin_for(layout, pull.as_ref().map(|p| p.target.as_slice()))?;
    let mut lo = Vec::with_capacity(nl * PER_LINK);
    let mut hi = Vec::with_capacity(nl * PER_LINK);
    let mut fixed = Vec::with_capacity(nl * PER_LINK);
    for lb in &bounds.links {
        let (l, h) = link_box(lb, margin);
        // the don't-care values inside the box too: a mass the fit does not see stayed at
        // the middle of its bounds, half a margin for a bound of [0, 1.1 margin]
        let centre = link_centre(lb);
        fixed.extend((0..PER_LINK).map(|i| centre[i].clamp(l[i], h[i].max(l[i]))));
        lo.extend(l);
        hi.extend(h);
    }
    let mut objective = Objective {
        problem,
        bounds,
        data,
        fixed,
        free: (0..nl * PER_LINK).collect(),
        penalty: options.penalty,
        pull,
        equalities: &options.equalities,
        mass_step: options.mass_step,
        loose: Vec::new(),
        margin,
    };
    // a link beyond the robot, named by its own setting (`robid feasible` tells an
    // equality's as its --equal flag)
    if let Some((v, _)) = options.fixed.iter().find(|(v, _)| v.link >= nl) {
        return Err(Error::setting(
            "AnnealOptions",
            "fixed",
            format!(
                "link {} named in a fixed value: the robot has {nl} links",
                v.link + 1
            ),
        ));
    }
    for equality in &options.equalities {
        if let Some(link) = equality.links().find(|&link| link >= nl) {
            return Err(Error::setting(
                "AnnealOptions",
                "equalities",
                format!(
                    "`{}` names link {}, but the robot has {nl} links; number the links from \
                     1 to {nl}",
                    equality.quoted(),
                    link + 1
                ),
            ));
        }
        // a constant outside its variable's range: no search can meet it
        if let (true, Some(r)) = (
            equality.factors.is_empty(),
            equality.left.range(&bounds.links[equality.left.link]),
        ) && !(r[0]..=r[1]).contains(&equality.coefficient)
        {
            return Err(Error::setting(
                "AnnealOptions",
                "equalities",
                format!(
                    "`{}` sets {} outside its bounds [{}, {}]; write a value inside them or \
                     widen the bounds",
                    equality.quoted(),
                    equality.left,
                    Num(r[0]),
                    Num(r[1])
                ),
            ));
        }
    }
    let held: Vec<usize> = options
        .fixed
        .iter()
        .filter_map(|(v, _)| v.index())
        .collect();
    for (v, value) in &options.fixed {
        if let Some(i) = v.index() {
            objective.fixed[i] = *value;
        }
    }
    objective.free = effective_variables(&objective, &lo, &hi, options.seed);
    // variables in an equality matter even where the fit does not see them
    for e in &options.equalities {
        for v in std::iter::once(&e.left).chain(&e.factors) {
            let at = v.link * PER_LINK;
            let own: Vec<usize> = match v.index() {
                Some(i) => vec![i],
                None => (at + 4..at + PER_LINK).collect(),
            };
            objective.free.extend(own);
        }
    }
    objective.free.sort_unstable();
    objective.free.dedup();
    objective.free.retain(|i| !held.contains(i));
    objective.loose = (0..nl)
        .filter(|j| !objective.free.contains(&(j * PER_LINK)) && !held.contains(&(j * PER_LINK)))
        .map(|j| (j, [lo[j * PER_LINK], hi[j * PER_LINK]]))
        .collect();
    let lo: Vec<f64> = objective.free.iter().map(|&i| lo[i]).collect();
    let hi: Vec<f64> = objective.free.iter().map(|&i| hi[i]).collect();
    let target = options
        .target_chi2
        .unwrap_or(1e-3 * problem.base_names.len() as f64);
    let mut searched_links: Vec<usize> = objective.free.iter().map(|i| i / PER_LINK).collect();
    searched_links.dedup();
    let done = AtomicBool::new(false);
    let settings = AnnealSettings {
        iterations: options.iterations,
        final_ratio: 1e-9,
    };
    // runs until the values agree to 1e-15 relative (1e-30 absolute), in practice to the budget
    let local = NelderMead {
        max_evaluations: options.local_evaluations,
        tolerance: 1e-15,
        absolute_tolerance: 1e-30,
        step: lo.iter().zip(&hi).map(|(l, h)| 0.05 * (h - l)).collect(),
    };

    // in restarts, each counted when it ends (or is skipped); its evaluations are beats,
    // so that a line falls due during a restart
    let progress = Progress::new(options.progress, title, options.restarts as u64, "restarts");
    let runs: Vec<(Vec<f64>, f64)> = (0..options.restarts)
        .into_par_iter()
        .map(|k| {
            let counter = progress.counter();
            if done.load(Ordering::Relaxed) {
                return None;
            }
            let mut rng = Rng::new(options.seed.wrapping_mul(1_000_003).wrapping_add(k as u64));
            let x0: Vec<f64> = lo
                .iter()
                .zip(&hi)
                .map(|(l, h)| rng.uniform(*l, *h))
                .collect();
            // one set of buffers for the restart's evaluations
            let scratch = RefCell::new(objective.scratch());
            let f = |y: &[f64]| {
                counter.beat();
                objective.value_in(y, &mut scratch.borrow_mut())
            };
            let (xa, _) = anneal::anneal(&f, &lo, &hi, &x0, settings, &mut rng);
            // Nelder-Mead on the box: evaluate at the reflected point.
            let reflected = RefCell::new(vec![0.0; lo.len()]);
            let g = |y: &[f64]| {
                let mut z = reflected.borrow_mut();
                for (i, (z, v)) in z.iter_mut().zip(y).enumerate() {
                    *z = reflect(*v, lo[i], hi[i]);
                }
                counter.beat();
                objective.value_in(&z, &mut scratch.borrow_mut())
            };
            let found = match local.minimize(&xa, g) {
                Ok(m) => m,
                Err(e) => return Some(Err(e)),
            };
            let xn: Vec<f64> = found
                .x
                .iter()
                .enumerate()
                .map(|(i, v)| reflect(*v, lo[i], hi[i]))
                .collect();
            let r = |y: &[f64]| {
                counter.beat();
                objective.residual(y)
            };
            let jacobian = |y: &[f64], _: &DVector<f64>| {
                counter.beat();
                objective.jacobian(y, &lo, &hi)
            };
            let polish = |y: &[f64]| {
                levenberg::polish_with(&r, &jacobian, &lo, &hi, y, options.polish_iterations)
            };
            let mut xn = polish(&xn);
            let mut fx = objective.value(&xn);
            for &link in searched_links.iter().cycle().take(options.hops) {
                if fx <= target {
                    break;
                }
                let mut y = xn.clone();
                for (yi, (&full, (l, h))) in y
                    .iter_mut()
                    .zip(objective.free.iter().zip(lo.iter().zip(&hi)))
                {
                    if full / PER_LINK == link {
                        *yi = rng.uniform(*l, *h);
                    }
                }
                let y = polish(&y);
                let fy = objective.value(&y);
                if fy < fx {
                    (xn, fx) = (y, fy);
                }
            }
            if fx <= target {
                done.store(true, Ordering::Relaxed);
            }
            Some(Ok((xn, fx)))
        })
        .inspect(|_| progress.tick())
        .flatten()
        .collect::<Result<_>>()?;
    progress.finish();
    let restarts_run = runs.len();
    let (best, _) = runs
        .into_iter()
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .ok_or_else(|| {
            Error::Feasible(FeasibleError::NoFeasibleParameters {
                reason: "the search ran no restart".to_owned(),
            })
        })?;
    let best = impose(&mut objective, &lo, &hi, best, options.polish_iterations);
    // the masses settle before the lift, which depends on them
    let mut x = objective.unlifted(&best);
    objective.settle_masses(&mut x);
    objective.lift(&mut x);
    let mut p = objective.standard(&x);
    // what the data do not see, to the prior (values held or tied by equalities stay the
    // search's)
    if let Some(pull) = &objective.pull
        && options.equalities.is_empty()
        && options.fixed.is_empty()
    {
        p = towards_prior::towards_prior(problem, bounds, &objective.data.a, pull, margin, p);
    }
    let mut solution = Solution::assemble(problem, bounds, Method::Anneal, p, start.elapsed())?;
    solution.iterations = restarts_run;
    if let Some(pull) = &objective.pull {
        solution.unpulled = super::prior::unpulled(problem, pull);
    }
    for text in options
        .equalities
        .iter()
        .filter_map(|e| e.unmet(&x, &bounds.links))
    {
        solution.violations.push(text.clone());
        solution.unmet.push(text);
    }
    Ok((solution, objective.free))
}

/// Raises each link's second moments about its centre of mass in the variables `x` so
/// that its pseudo-inertia `J` is at least `mu` times the identity wherever the box puts
/// the link. Second moments of at least `mu` (the box) are not enough: the first moment
/// couples them to the mass, and by the Schur complement of the mass in `J - mu I`, that
/// is at least zero when the mass exceeds `mu` and `Sigma_c - mu I - mu m / (m - mu) c
/// c^T` is, which second moments of at least `mu + mu m |c|^2 / (m - mu)` ensure (the
/// search kept the box alone: a margin of 1e-3 left smallest eigenvalues of 6.7e-4).
fn lift(x: &mut [f64], mu: f64) {
    if mu <= 0.0 {
        return;
    }
    for link in x.chunks_exact_mut(PER_LINK) {
        let (m, c) = (link[0], [link[1], link[2], link[3]]);
        let c2 = c.iter().map(|v| v * v).sum::<f64>();
        // and the rounding of the pseudo-inertia's entries, so that its smallest
        // eigenvalue, computed, is not a rounding below the margin (4.99999999999999e-2
        // for 0.05)
        let lift = mu * m * c2 / (m - mu).max(1e-9 * mu) + 8.0 * f64::EPSILON * m * (1.0 + c2);
        for d in &mut link[4..7] {
            *d += lift;
        }
    }
}

/// The largest penalty [`impose`] raises to: the cap of [`AnnealOptions::penalty`].
const MAX_PENALTY: f64 = 1e20;

/// Relative violation (of [`Objective::violations`]) below which the bounds and equalities
/// count as met: well inside the check of the result (1e-6 of each bound's size).
const MET: f64 = 1e-9;

/// Imposes the bounds and equalities on the search's best point `y`: while one is missed,
/// the penalty is raised a hundredfold (to [`MAX_PENALTY`]) and the point polished again
/// (a sequential penalty method, Nocedal and Wright 2006, sec. 17.1), with the total mass
/// under the proportional penalty in place of Gaz et al.'s step (flat outside the range,
/// it cannot lead back into it). The search's penalty weighs the bounds against the data:
/// where they pull apart the best point sat just outside (an element bound 0.05 missed by
/// 4e-4, a closed total mass by 1e-5, an equality by a quarter of its value).
fn impose(
    objective: &mut Objective<'_>,
    lo: &[f64],
    hi: &[f64],
    mut y: Vec<f64>,
    iterations: usize,
) -> Vec<f64> {
    // after the step, the proportional penalty at the search's weight first: a jump to a
    // hundredfold weight left a closed total mass [5, 5] of the two-link arm from 11.3 kg
    // at chi^2 1.7e5, where 5e-26 is reachable
    let mut raise = objective.mass_step.take().is_none();
    let worst = |objective: &Objective<'_>, y: &[f64]| {
        objective
            .violations(&objective.full(y))
            .iter()
            .fold(0.0_f64, |m, v| m.max(v.abs()))
    };
    while worst(objective, &y) > MET && (objective.penalty < MAX_PENALTY || !raise) {
        if raise {
            objective.penalty = (objective.penalty * 100.0).min(MAX_PENALTY);
        }
        raise = true;
        let r = |z: &[f64]| objective.residual(z);
        let jacobian = |z: &[f64], _: &DVector<f64>| objective.jacobian(z, lo, hi);
        y = levenberg::polish_with(&r, &jacobian, lo, hi, &y, iterations.max(50));
    }
    y
}

/// The variables that change the objective somewhere in the box (checked by finite
/// differences at random points); the others keep their don't-care values.
fn effective_variables(objective: &Objective<'_>, lo: &[f64], hi: &[f64], seed: u64) -> Vec<usize> {
    let n = lo.len();
    let mut rng = Rng::new(seed ^ 0x00D0_C42E);
    let mut effective = vec![false; n];
    for _ in 0..4 {
        let x: Vec<f64> = (0..n).map(|i| rng.uniform(lo[i], hi[i])).collect();
        let base = misfit(objective, &x);
        for i in 0..n {
            if effective[i] {
                continue;
            }
            let mut y = x.clone();
            let h = 1e-4 * (hi[i] - lo[i]).max(1e-12);
            y[i] = if y[i] + h <= hi[i] {
                y[i] + h
            } else {
                y[i] - h
            };
            let r = misfit(objective, &y);
            let change = (&r - &base).norm();
            if change > 1e-9 * (1.0 + base.norm()) {
                effective[i] = true;
            }
        }
    }
    (0..n).filter(|&i| effective[i]).collect()
}

/// The misfit of a full variable vector and its pull towards the prior, bounds ignored.
fn misfit(objective: &Objective<'_>, x: &[f64]) -> DVector<f64> {
    let mut s = objective.scratch();
    s.x.copy_from_slice(x);
    objective
        .data
        .evaluate_exact(&objective.problem.layout, &mut s);
    let mut r = Vec::with_capacity(s.r.len() + s.p.len());
    objective.misfit_rows(&s, &mut |v| r.push(v));
    DVector::from_vec(r)
}

#[cfg(test)]
mod tests;
