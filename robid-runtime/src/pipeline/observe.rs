//! The stacked observation matrix: regressor rows at every sample (in parallel), extra
//! drive columns, parallel low-pass + decimation of every column and of the torque,
//! removal of equations near rest, joint-major stacking.

use crate::EstimateError;
use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;

use crate::Model;
use crate::data::{Config, Decimation};
use crate::error::{Error, Result, num};
use crate::estimate::{Observation, check_names, equations_needed, equations_purpose};
use crate::finite::first_non_finite;
use crate::pipeline::Prepared;
use crate::signal::passes::Forward;
use crate::signal::{Decimator, Signals, moving_samples};

/// Samples per parallel work item when evaluating the regressor.
const BLOCK: usize = 512;
/// Channels filtered together by one task: one lane of the AVX-512 passes. The hour's
/// 202 filtered channels are 13 tasks for two threads rather than 7 of 32 channels, and a
/// prediction's 21 channels two rather than one (user time of the hour's identification
/// 10.68 -> 10.14 s, median of six runs in turn; the same values to the bit: every
/// channel goes through the same operations whatever its group).
const GROUP: usize = 16;
/// Samples at which all-zero regressor channels are probed (then verified on all samples).
const PROBES: usize = 33;

/// Per-thread buffers for one sample.
struct Scratch {
    q: Vec<f64>,
    qd: Vec<f64>,
    qdd: Vec<f64>,
    thetad: Vec<f64>,
    thetadd: Vec<f64>,
    col: Vec<f64>,
}

impl Scratch {
    fn new(dof: usize) -> Self {
        Self {
            q: vec![0.0; dof],
            qd: vec![0.0; dof],
            qdd: vec![0.0; dof],
            thetad: vec![0.0; dof],
            thetadd: vec![0.0; dof],
            col: vec![0.0; dof],
        }
    }
}

/// Channel layout of one sample row: `[Y_b (dof x p, row-major) | extra (e x dof) | tau | qd]`.
struct Layout {
    dof: usize,
    p: usize,
    e: usize,
}

impl Layout {
    fn stride(&self) -> usize {
        self.dof * (self.p + self.e + 2)
    }
    fn column(&self, j: usize, c: usize) -> usize {
        if c < self.p {
            j * self.p + c
        } else {
            self.dof * self.p + (c - self.p) * self.dof + j
        }
    }
    fn tau(&self, j: usize) -> usize {
        self.dof * (self.p + self.e) + j
    }
    fn qd(&self, j: usize) -> usize {
        self.dof * (self.p + self.e + 1) + j
    }
    /// The joint (0-based) and the parameter column (`None`: torque or velocity) of a
    /// channel.
    fn of_channel(&self, c: usize) -> (usize, Option<usize>) {
        let (d, p, e) = (self.dof, self.p, self.e);
        if c < d * p {
            (c / p, Some(c % p))
        } else if c < d * (p + e) {
            ((c - d * p) % d, Some(p + (c - d * p) / d))
        } else {
            ((c - d * (p + e)) % d, None)
        }
    }
}

/// The decimation configured in `[processing]`.
pub fn decimator(config: &Config) -> Result<Decimator> {
    match &config.processing.decimation {
        Decimation::Total(t) => Decimator::with_total(*t),
        Decimation::Stages(s) => Decimator::new(s),
    }
}

/// The decimation configured in `[processing]` for a record `of` (its name) of `n`
/// samples (after `processing.range` and the trims) and `dof` joints that must give at
/// least `needed` equations, for `purpose` (e.g. "the 49 equations the 48 parameters need"):
/// an error at `processing.decimation` naming the record when its filters need more
/// samples or it leaves fewer equations, with the largest factor that fits. Without it the
/// anti-alias filter of the last stage said "3 samples, at least 28 are needed", or the
/// least squares "3 samples, at least 4", with no key. A record too short for `needed`
/// equations even without decimation is left to the error of what it is too short for.
pub(crate) fn decimator_for(
    config: &Config,
    of: &str,
    (n, dof): (usize, usize),
    needed: usize,
    purpose: &str,
) -> Result<Decimator> {
    let dec = decimator(config)?;
    // the settled decimated samples ([`Decimator::settled`]), counted when the factor
    // leaves enough at all
    let enough = |d: &Decimator| {
        let equations = |samples: usize| samples * dof >= needed;
        equations(d.output_len(n)) && equations(d.settled(n).len())
    };
    let filtered = dec.min_len() <= n;
    if filtered && (enough(&dec) || n * dof < needed) {
        return Ok(dec);
    }
    // the largest total factor that fits in some stages: the stages matter, [5, 2] fits
    // where [10] does not, and it said "at most 42" where [7, 7] ran
    let fits =
        |stages: &[usize]| Decimator::new(stages).is_ok_and(|d| d.min_len() <= n && enough(&d));
    // no more than leaves the equations with the first and last decimated samples left
    // out (each carries an end sample's noise, [`Decimator::unsettled`]): ceil(n / t)
    // samples of at least `samples`, which spares the costly count of the unsettled ones
    let samples = needed.div_ceil(dof.max(1)) + 2;
    let most = (n.max(1) - 1) / (samples - 1);
    let as_stages = |s: &[usize]| {
        let list: Vec<String> = s.iter().map(usize::to_string).collect();
        format!("`decimation = [{}]`", list.join(", "))
    };
    let factor = dec.factor();
    // the largest that fits, up to twice the factor asked for (its stages as given may be
    // what does not fit: [10, 10, 2] needs 2701 samples where [2, 10, 10] fits in 2001)
    let best = (2..=(2 * factor).min(most))
        .rev()
        .find_map(|t| stagings(t).into_iter().find(|s| fits(s)));
    let advice = match best {
        None => "lower the factor (at most 1 for this record: no decimation)".to_owned(),
        Some(s) if s.iter().product::<usize>() < factor => format!(
            "lower the factor (at most {} for this record, as {})",
            s.iter().product::<usize>(),
            as_stages(&s)
        ),
        Some(s) => {
            let larger = format!(
                "at most {} for this record, as {}",
                s.iter().product::<usize>(),
                as_stages(&s)
            );
            match stagings(factor).into_iter().find(|s| fits(s)) {
                Some(same) => format!(
                    "give the same factor in other stages, {}, which fit ({larger})",
                    as_stages(&same)
                ),
                None => format!("use another factor ({larger})"),
            }
        }
    };
    let problem = if filtered {
        let (all, m, ends) = (dec.output_len(n), dec.settled(n).len(), dec.unsettled());
        format!(
            "keeps {all} of the {n} samples of {of} used (after processing.range and the \
             trims), {m} without the {ends} at each end that its filter does not settle (they \
             carry an end sample's noise whole): {} equations, fewer than {purpose}",
            m * dof,
        )
    } else {
        format!(
            "needs at least {} samples for its anti-alias filters, but {n} of {of} are used \
             (after processing.range and the trims)",
            dec.min_len()
        )
    };
    Err(Error::setting(
        "Config",
        "processing.decimation",
        format!("a total factor of {factor} {problem}; {advice} or use a longer record"),
    ))
}

/// The stages of at most 10 whose product is `total`: each way to write it as such
/// factors (at most [`STAGINGS`] of them), largest stages first and last (a stage's
/// filter needs more samples the later it runs).
fn stagings(total: usize) -> Vec<Vec<usize>> {
    fn factorisations(
        rest: usize,
        largest: usize,
        now: &mut Vec<usize>,
        out: &mut Vec<Vec<usize>>,
    ) {
        if out.len() >= STAGINGS {
            return;
        }
        if rest == 1 {
            out.push(now.clone());
            return;
        }
        for f in (2..=largest.min(rest)).rev() {
            if rest.is_multiple_of(f) {
                now.push(f);
                factorisations(rest / f, f, now, out);
                now.pop();
            }
        }
    }
    let mut out = Vec::new();
    factorisations(total, 10, &mut Vec::new(), &mut out);
    out.into_iter()
        .flat_map(|s| {
            let mut rising = s.clone();
            rising.reverse();
            // a palindrome once: each staging costs a filter's count of unsettled samples
            let twice = rising != s;
            std::iter::once(s).chain(twice.then_some(rising))
        })
        .collect()
}

/// The most ways to stage one total factor that [`stagings`] lists.
const STAGINGS: usize = 32;

/// An error naming the record `data` (its file and the rows used, and the files joined to
/// it, which used to be left out) when its samples `kept`
/// (after `processing.range` and the trims) of `dof` joints give no more equations than
/// the `needed` parameters to estimate, one per joint and sample (as many fit any data
/// exactly, leaving no residual for the standard deviations), whatever the decimation and
/// the rest removal (which [`decimator_for`] and [`RestCount::check`] name when they are
/// why). Without it the least squares said "least squares with 36 parameters: 12 samples,
/// at least 36 are needed", counting equations as samples, with no file.
pub(crate) fn long_enough(
    data: &dyn crate::data::Record,
    kept: &std::ops::Range<usize>,
    dof: usize,
    needed: usize,
) -> Result<()> {
    let n = kept.len();
    if dof == 0 || n.saturating_mul(dof) >= equations_needed(needed) {
        return Ok(());
    }
    let trimmed = if n < data.samples() {
        format!(
            ", after processing.range and the trims of its {} samples,",
            data.samples()
        )
    } else {
        String::new()
    };
    Err(Error::TooFewSamples {
        context: format!(
            "{}{}: too short{trimmed} for the {needed} parameters of the model (each sample \
             gives {dof} equations, one per joint, and the fit needs more equations than \
             parameters)",
            crate::validate::UsedRows::of(data, kept.clone()),
            crate::data::joined_with(data),
        ),
        found: n,
        required: equations_needed(needed).div_ceil(dof),
        hint: "record a longer trajectory",
    })
}

/// What building the rows of a record needs, checked once: the model, the prepared
/// signals, the extra columns, the channel layout and the parameter names. Shared by the
/// dense observation ([`observe`]) and the streaming one (`pipeline::stream`).
pub(crate) struct Observer<'a> {
    pub(crate) model: &'a (dyn Model + Sync),
    pub(crate) signals: &'a Prepared,
    extra: Vec<crate::drive::ExtraColumn>,
    lay: Layout,
    /// Parameter names: the base parameters, then the extra columns.
    pub(crate) names: Vec<String>,
}

impl<'a> Observer<'a> {
    /// Checks the signals and the config's extra columns against `model`.
    pub(crate) fn new(
        model: &'a (dyn Model + Sync),
        signals: &'a Prepared,
        config: &Config,
    ) -> Result<Self> {
        let dof = model.dof();
        signals.check(dof, "data")?;
        let extra = config.extra_columns_for(dof)?;
        for c in &extra {
            c.check(dof)?;
        }
        let rotor = signals.rotor.as_ref();
        if rotor.is_none() && extra.iter().any(|c| c.rotor_term().is_some()) {
            return Err(Error::setting(
                "Config",
                "extra_column",
                "a rotor-side column (theta_d, theta_dd, sign_theta_d or drive.rotor.residual) \
                 needs the motor encoders' signals, which these prepared signals do not have; add \
                 motor_position = [...] to a [[source]]",
            ));
        }
        let lay = Layout {
            dof,
            p: model.base_parameter_count(),
            e: extra.len(),
        };
        let mut names = crate::model::base_parameter_names(model);
        if let Some(r) = config
            .drive
            .rotor
            .as_ref()
            .and_then(|r| r.residual.as_ref())
        {
            r.check_against(dof, &names)?;
        }
        // a standard parameter's name too: regrouped into a base parameter (ZZ1 into ZZR1),
        // it is not a column, but `robid feasible` reads the name as the link's parameter
        let standard = crate::model::standard_parameter_names(model);
        for (i, c) in extra.iter().enumerate() {
            if names.contains(&c.name) || standard.contains(&c.name) {
                let key = if i < config.extra_columns.len() {
                    format!("extra_column[{}].name", i + 1)
                } else {
                    "drive.rotor.residual".to_string()
                };
                return Err(Error::setting(
                    "Config",
                    &key,
                    format!(
                        "`{}` is already a parameter (a standard or base parameter of the model, or an earlier extra column); rename the extra column or remove it (drop the drive term from the description if the model has it)",
                        c.name
                    ),
                ));
            }
            names.push(c.name.clone());
        }
        check_names(&names)?;
        Ok(Self {
            model,
            signals,
            extra,
            lay,
            names,
        })
    }

    /// Channels per processed sample (regressor columns of every joint, torques,
    /// velocities).
    pub(crate) fn channels(&self) -> usize {
        self.lay.stride()
    }

    /// Fills `row` (`stride` values) with sample k's channels.
    /// [`Observer::row_at`], with NaN in every channel when the model refuses the sample.
    fn full_row(&self, k: usize, st: &mut Scratch, row: &mut [f64]) {
        if self.row_at(k, st, row).is_err() {
            row.iter_mut().for_each(|v| *v = f64::NAN);
        }
    }

    /// The predicted torque `W beta`, the torque and the velocity of each joint at
    /// processed sample `k` (`out`: three blocks of `dof` values, or one for the predicted
    /// torque alone): the model's inverse
    /// dynamics with the base parameters of `beta`, plus its extra columns, which is the
    /// row's `W beta` to rounding at half the cost of the whole regressor row.
    fn prediction_at(
        &self,
        k: usize,
        st: &mut Scratch,
        beta: &[f64],
        out: &mut [f64],
    ) -> std::result::Result<(), crate::LengthError> {
        let (lay, dof) = (&self.lay, self.lay.dof);
        self.load_sample(k, st);
        let (predicted, measured) = out.split_at_mut(dof);
        self.model
            .inverse_dynamics_into(&st.q, &st.qd, &st.qdd, &beta[..lay.p], predicted)?;
        self.extra_columns(st, |c, column| {
            for (p, v) in predicted.iter_mut().zip(column) {
                *p += v * beta[lay.p + c];
            }
        });
        if !measured.is_empty() {
            for j in 0..dof {
                measured[j] = self.signals.tau[j][k];
                measured[dof + j] = st.qd[j];
            }
        }
        Ok(())
    }

    fn row_at(
        &self,
        k: usize,
        st: &mut Scratch,
        row: &mut [f64],
    ) -> std::result::Result<(), crate::LengthError> {
        let (lay, dof) = (&self.lay, self.lay.dof);
        self.load_sample(k, st);
        self.model
            .base_regressor_into(&st.q, &st.qd, &st.qdd, &mut row[..dof * lay.p])?;
        self.extra_columns(st, |c, column| {
            let start = lay.column(0, lay.p + c);
            row[start..start + dof].copy_from_slice(column);
        });
        for j in 0..dof {
            row[lay.tau(j)] = self.signals.tau[j][k];
            row[lay.qd(j)] = st.qd[j];
        }
        Ok(())
    }

    /// Processed sample `k`'s positions, velocities and accelerations (and the reflected
    /// motor signals, when the data have them) into `st`, velocities and accelerations at
    /// the rounding of their positions as 0 ([`at_rest_to_rounding`]).
    fn load_sample(&self, k: usize, st: &mut Scratch) {
        let signals = self.signals;
        signals.q.sample_into(k, &mut st.q);
        signals.qd.sample_into(k, &mut st.qd);
        signals.qdd.sample_into(k, &mut st.qdd);
        at_rest_to_rounding(&st.q, &mut st.qd, &mut st.qdd, signals.sample_time);
        if let Some(r) = &signals.rotor {
            r.thetad.sample_into(k, &mut st.thetad);
            r.thetadd.sample_into(k, &mut st.thetadd);
        }
    }

    /// Calls `each(c, values)` with extra column `c`'s value for every joint at the sample
    /// [`Observer::load_sample`] put in `st`.
    fn extra_columns(&self, st: &mut Scratch, mut each: impl FnMut(usize, &[f64])) {
        let rotor = self.signals.rotor.is_some();
        for (c, x) in self.extra.iter().enumerate() {
            let r = rotor.then_some(crate::drive::RotorSample {
                thetad: &st.thetad,
                thetadd: &st.thetadd,
            });
            x.fill_with_rotor(&st.q, &st.qd, &st.qdd, r, &mut st.col);
            each(c, &st.col);
        }
    }
}

/// Units in the last place of a position that its differences may leave in a velocity
/// or an acceleration ([`at_rest_to_rounding`]).
const POSITION_ROUNDING_ULPS: f64 = 8.0;

/// Sets to 0 the velocity and the acceleration of a joint at rest to the rounding of its
/// positions `q` differentiated at sample time `dt`: both smaller than `8 eps (|q| + 1)
/// / dt` (the acceleration over `dt^2`), `|q| + 1` in rad or m. A joint at rest whose
/// positions differ in their last bits moves at about 1e-13 rad/s at 1 kHz; scaled to
/// unit norm for the least squares, such a column is a column of noise, the sign of the
/// noise a Coulomb column of +-1, and they counted as excitation: with `rest_velocity =
/// 0`, six samples at rest were identified at a condition number of 1.8e17 with values of
/// 1e15. As 0 they are what they are, no motion, and the joint's drive parameters are
/// named as not excited. Both, not each: a moving joint passes through a small velocity
/// (turning back) or a small acceleration, measured, and at 100 kHz with positions near
/// 1e4 rad the floor of an acceleration is 0.18 rad/s^2 (each alone zeroed 2 % of a
/// moving joint's accelerations, and its fit lost 0.2 %).
fn at_rest_to_rounding(q: &[f64], qd: &mut [f64], qdd: &mut [f64], dt: f64) {
    for ((q, v), a) in q.iter().zip(qd).zip(qdd) {
        let floor = POSITION_ROUNDING_ULPS * f64::EPSILON * (q.abs() + 1.0) / dt;
        if v.abs() < floor && a.abs() < floor / dt {
            (*v, *a) = (0.0, 0.0);
        }
    }
}

/// The decimation filter's forward states carried from one block of a stream to the
/// next ([`Observer::window`], [`Decimator::apply_gathered_from`]).
#[derive(Debug)]
pub(crate) struct Carry {
    /// Sections of the filter.
    sections: usize,
    /// `sections` pairs per channel of a sample row, the states before the next block's
    /// first sample; none before the first block.
    states: Vec<[f64; 2]>,
}

impl Carry {
    /// No states yet, for a filter of `sections` sections.
    pub(crate) fn new(sections: usize) -> Self {
        Self {
            sections,
            states: Vec::new(),
        }
    }

    /// Whether a block has handed its states on.
    pub(crate) fn started(&self) -> bool {
        !self.states.is_empty()
    }
}

/// The equations of some decimated samples, in sample order (for each sample, the joints
/// that move at it, in joint order).
#[derive(Debug, Default)]
pub(crate) struct Equations {
    /// Values per regressor row (parameters + extra columns).
    pub(crate) cols: usize,
    /// Regressor rows, row-major.
    pub(crate) w: Vec<f64>,
    /// Torques.
    pub(crate) y: Vec<f64>,
    /// Joint (0-based) of each equation.
    pub(crate) joint: Vec<usize>,
    /// Decimated sample of each equation.
    pub(crate) sample: Vec<usize>,
    /// The equations before the removal of those near rest, and the fastest velocity.
    pub(crate) rest: RestCount,
}

/// A predicted equation: joint, decimated sample, measured and predicted torque.
pub(crate) type Predicted = (usize, usize, f64, f64);

/// What removing the equations near rest (`processing.rest_velocity`) left of a record's
/// equations: summed over blocks, checked once at the end ([`RestCount::check`]).
#[derive(Debug, Default, Clone, PartialEq)]
pub(crate) struct RestCount {
    /// Equations (joint and decimated sample) before the removal.
    pub(crate) before: usize,
    /// Equations kept.
    pub(crate) kept: usize,
    /// The largest |velocity| of any joint at any decimated sample.
    pub(crate) fastest: f64,
    /// Per joint (0-based; empty when not counted): its equations before the removal,
    /// those kept and its largest |velocity| ([`RestCount::rank_cause`]).
    pub(crate) joints: Vec<JointRest>,
}

/// What the removal of the equations near rest left of one joint's.
#[derive(Debug, Default, Clone, Copy, PartialEq)]
pub(crate) struct JointRest {
    /// Equations before the removal.
    pub(crate) before: usize,
    /// Equations kept.
    pub(crate) kept: usize,
    /// The largest |velocity| at any decimated sample.
    pub(crate) fastest: f64,
}

/// The share of a joint's equations the removal near rest may leave for it to be named as
/// the cause of a rank deficiency ("all or nearly all removed"): 5 %.
const NEARLY_ALL_REMOVED: f64 = 0.05;

impl RestCount {
    /// Adds `other`'s counts to these.
    pub(crate) fn add(&mut self, other: &RestCount) {
        self.before += other.before;
        self.kept += other.kept;
        self.fastest = self.fastest.max(other.fastest);
        if self.joints.len() < other.joints.len() {
            self.joints.resize(other.joints.len(), JointRest::default());
        }
        for (a, b) in self.joints.iter_mut().zip(&other.joints) {
            a.before += b.before;
            a.kept += b.kept;
            a.fastest = a.fastest.max(b.fastest);
        }
    }

    /// Counts joint `j`'s equation of one decimated sample at |velocity| `speed`, kept or
    /// not.
    pub(crate) fn count(&mut self, j: usize, speed: f64, kept: bool) {
        self.before += 1;
        self.fastest = self.fastest.max(speed);
        if self.joints.len() <= j {
            self.joints.resize(j + 1, JointRest::default());
        }
        let joint = &mut self.joints[j];
        joint.before += 1;
        joint.fastest = joint.fastest.max(speed);
        if kept {
            self.kept += 1;
            joint.kept += 1;
        }
    }

    /// A rank deficiency `e` ([`EstimateError::RankDeficient`]) said as the removal of the
    /// equations near rest (thresholds `rest` per joint) when it removed all or nearly all
    /// ([`NEARLY_ALL_REMOVED`]) of a joint's equations while others kept theirs: a joint
    /// slower than the threshold (a prismatic joint in m/s under the default 0.05, which is
    /// in rad/s for a revolute one) loses the equations that determine its parameters, and
    /// the least squares' "use a richer trajectory or remove these parameters" named
    /// neither the threshold nor the joint. Other errors, and rank deficiencies the removal
    /// does not explain, as they are.
    /// `in_file`: the config is a file (else the default column mapping, and the fix says
    /// how to write one).
    /// `prismatic`: which joints are prismatic ([`Config::prismatic`](crate::data::Config)),
    /// whose speeds and thresholds are in m/s (the others' in rad/s).
    pub(crate) fn rank_cause(
        &self,
        rest: Option<&[f64]>,
        e: Error,
        in_file: bool,
        prismatic: &[bool],
    ) -> Error {
        // joints that do not move at all, beside others that do, are the cause whatever
        // the threshold
        if let Error::Estimate(EstimateError::RankDeficient {
            rank,
            columns,
            unexcited,
        }) = &e
        {
            let still: Vec<usize> = (self.joints.iter().enumerate())
                .filter(|(_, c)| c.before > 0 && c.fastest == 0.0)
                .map(|(j, _)| j + 1)
                .collect();
            if !still.is_empty() && still.len() < self.joints.len() {
                return Error::Estimate(EstimateError::StillJoints {
                    rank: *rank,
                    columns: *columns,
                    unexcited: unexcited.clone(),
                    joints: still,
                });
            }
        }
        let (
            Some(rest),
            Error::Estimate(EstimateError::RankDeficient {
                rank,
                columns,
                unexcited,
            }),
        ) = (rest, &e)
        else {
            return e;
        };
        let starved: Vec<(usize, &JointRest)> = self
            .joints
            .iter()
            .enumerate()
            .filter(|(j, c)| {
                // a joint that never moves is not the threshold's doing
                rest.get(*j).is_some_and(|&t| t > 0.0)
                    && c.before > 0
                    && c.fastest > 0.0
                    && (c.kept as f64) <= NEARLY_ALL_REMOVED * c.before as f64
            })
            .collect();
        // a record in which every joint is (nearly) at rest is a poor record, not a
        // threshold for one joint (RestCount::check tells too few equations overall)
        if starved.is_empty() || starved.len() == self.joints.len() {
            return e;
        }
        let lowered: Vec<String> = rest
            .iter()
            .enumerate()
            .map(|(j, &t)| match starved.iter().find(|(s, _)| *s == j) {
                // a tenth of the joint's largest speed keeps most of its equations
                Some((_, c)) => num(three_digits(c.fastest / 10.0)),
                None => num(t),
            })
            .collect();
        let joints: Vec<String> = starved
            .iter()
            .map(|(j, c)| {
                let unit = speed_unit(prismatic, *j);
                format!(
                    "joint {} keeps {} of its {} equations (its |velocity| reaches at most {} \
                     {unit}; its threshold {} {unit})",
                    j + 1,
                    c.kept,
                    c.before,
                    num(three_digits(c.fastest)),
                    num(rest[*j])
                )
            })
            .collect();
        Error::setting(
            "Config",
            "processing.rest_velocity",
            format!(
                "rank-deficient data (rank {rank} of {columns} parameters; {}) \
                 because rest_velocity removed all or nearly all of {} equations: {}; lower \
                 `rest_velocity` (default 0.05) in the config's [processing] for {}, e.g. \
                 `rest_velocity = [{}]`, or 0 to keep every equation (a joint that does not \
                 move in the record needs a trajectory that moves it instead){}",
                crate::estimate::not_excited(*rank, *columns, unexcited),
                if starved.len() == 1 {
                    "a joint's"
                } else {
                    "some joints'"
                },
                joints.join("; "),
                if starved.len() == 1 { "it" } else { "them" },
                lowered.join(", "),
                if in_file {
                    ""
                } else {
                    " (without --config the defaults apply: `robid identify --example-config` \
                     prints a config with every key, to give with --config)"
                }
            ),
        )
    }

    /// An error naming `processing.rest_velocity` (thresholds `rest` per joint, `None`
    /// without the removal) when the removal is why fewer than `needed` equations are
    /// left (`purpose`: what they are for, e.g. "the 4 parameters"). Without it, the least
    /// squares said "0 samples, at least 4 are needed" and blamed the record's length.
    /// `config` says which joints are prismatic (their thresholds and speeds in m/s, the
    /// others' in rad/s), whether the thresholds are its own or the default, and the
    /// decimation, named too when it left few equations before the removal.
    pub(crate) fn check(
        &self,
        config: &Config,
        rest: Option<&[f64]>,
        needed: usize,
        purpose: &str,
    ) -> Result<()> {
        let Some(rest) = rest else { return Ok(()) };
        if self.kept >= needed || self.before < needed {
            return Ok(());
        }
        let prismatic = &config.prismatic;
        let default = if config.processing.rest_velocity.is_none() {
            " (the default: the config sets no rest_velocity)"
        } else {
            ""
        };
        // a decimation that left barely enough equations before the removal is the larger
        // cause
        let factor = decimator(config).map_or(1, |d| d.factor());
        let decimation = if factor > 1 && self.before < 2 * needed {
            format!(
                ", or lower processing.decimation (its factor of {factor} leaves {} equations \
                 before the removal)",
                self.before
            )
        } else {
            String::new()
        };
        let units: Vec<&str> = (0..rest.len()).map(|j| speed_unit(prismatic, j)).collect();
        let value = match (rest.split_first(), units.split_first()) {
            (Some((first, others)), Some((unit, kinds)))
                if others.iter().all(|v| v == first) && kinds.iter().all(|u| u == unit) =>
            {
                format!("{} {unit}", num(*first))
            }
            _ => format!(
                "[{}]",
                rest.iter()
                    .zip(&units)
                    .map(|(&v, unit)| format!("{} {unit}", num(v)))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        };
        // the fastest joint, whose speed is told in its unit
        let fastest = self
            .joints
            .iter()
            .enumerate()
            .max_by(|a, b| a.1.fastest.total_cmp(&b.1.fastest))
            .map_or(0, |(j, _)| j);
        let kinds = match (units.contains(&"rad/s"), units.contains(&"m/s")) {
            (true, true) => "rad/s or m/s",
            (false, true) => "m/s",
            _ => "rad/s",
        };
        if self.fastest == 0.0 {
            // nothing moves: the data are the cause, whatever the threshold
            return Err(Error::setting(
                "Config",
                "processing.rest_velocity",
                format!(
                    "no joint moves in these data (every joint velocity is 0 {kinds}), so \
                     {value}{default} removes all {} equations, leaving 0, fewer than {purpose}, \
                     and no threshold would leave motion to identify the dynamics from: use a \
                     record in which the joints move, or check the velocity columns and their \
                     units (joint side: units.angle, the drive chain)",
                    self.before
                ),
            ));
        }
        Err(Error::setting(
            "Config",
            "processing.rest_velocity",
            format!(
                "{value}{default} removes {} of the {} equations (a joint's samples where its \
                 |velocity| is below it), leaving {}, fewer than {purpose}; the fastest joint \
                 velocity is {} {}: lower rest_velocity below the joints' speeds, check the \
                 velocity columns and their units (joint side, {}: units.angle, the drive \
                 chain), or use a record in which the joints move{decimation}",
                self.before - self.kept,
                self.before,
                self.kept,
                num(three_digits(self.fastest)),
                speed_unit(prismatic, fastest),
                kinds,
            ),
        ))
    }
}

/// The unit of joint `j`'s (0-based) velocity and of its `rest_velocity`: m/s for a
/// prismatic joint (`prismatic[j]`, [`Config::prismatic`](crate::data::Config)), rad/s for
/// a revolute one (a joint not listed).
pub(crate) fn speed_unit(prismatic: &[bool], j: usize) -> &'static str {
    if prismatic.get(j).copied().unwrap_or(false) {
        "m/s"
    } else {
        "rad/s"
    }
}

/// `x` rounded to three significant digits: a measured value for a message.
fn three_digits(x: f64) -> f64 {
    if x == 0.0 || !x.is_finite() {
        return x;
    }
    let scale = 10f64.powi(2 - x.abs().log10().floor() as i32);
    (x * scale).round() / scale
}

impl Equations {
    /// Equation i's regressor row.
    pub(crate) fn row(&self, i: usize) -> &[f64] {
        &self.w[i * self.cols..(i + 1) * self.cols]
    }
}

impl Observer<'_> {
    /// The error for a non-finite value of channel `c` at processed sample `k`.
    fn bad_channel(&self, k: usize, c: usize, value: f64) -> Error {
        let (j, col) = self.lay.of_channel(c);
        Error::Estimate(EstimateError::NonFiniteObservation {
            location: format!("processed sample {k}"),
            sample: Some(k),
            joint: j + 1,
            parameter: col.map_or_else(
                || "torque or velocity".to_string(),
                |i| self.names[i].clone(),
            ),
            value,
        })
    }

    /// Runs `fill(sample, scratch, full row, out)` for the processed samples `lo..hi` in
    /// parallel (`full row`: a buffer of a whole row, [`Observer::row_at`]'s), into `rows` (resized to rows of `width` values; `fill` writes every value
    /// of its row, so a buffer reused from the last block is not cleared: a block's
    /// channels are up to 64 MiB, which the allocator would otherwise map and zero
    /// afresh for every block); returns whether a call reported a miss, and the first
    /// non-finite value reported (sample, channel, value).
    fn rows_in_parallel(
        &self,
        lo: usize,
        hi: usize,
        width: usize,
        rows: &mut Vec<f64>,
        fill: impl Fn(usize, &mut Scratch, &mut [f64], &mut [f64]) -> (bool, Option<(usize, f64)>)
        + Sync,
    ) -> (bool, Option<(usize, usize, f64)>) {
        let dof = self.lay.dof;
        let stride = self.lay.stride();
        rows.resize((hi - lo) * width, 0.0);
        let (missed, bad) = rows
            .par_chunks_mut((width * BLOCK).max(1))
            .enumerate()
            .map(|(b, chunk)| {
                let mut st = Scratch::new(dof);
                let mut full = vec![0.0; stride];
                let mut missed = false;
                let mut bad = None;
                for (i, out) in chunk.chunks_exact_mut(width.max(1)).enumerate() {
                    let k = lo + b * BLOCK + i;
                    let (m, x) = fill(k, &mut st, &mut full, out);
                    missed |= m;
                    if bad.is_none()
                        && let Some((c, v)) = x
                    {
                        bad = Some((k, c, v));
                    }
                }
                (missed, bad)
            })
            .reduce(|| (false, None), |x, y| (x.0 || y.0, x.1.or(y.1)));
        (missed, bad)
    }

    /// The samples `lo..hi` of the channels `channels` of every sample row (in parallel),
    /// decimated: groups of [`GROUP`] channels, each left in its buffer of `groups`
    /// ([`InGroup`]: where, and the row width), row-major, one row per decimated sample. A channel outside `channels` that is not zero is a miss (reported
    /// as `Ok(None)`). `groups` are the buffers of the groups before decimation, reused
    /// from block to block: each row's channels are written straight into their group's
    /// buffer, in the layout the decimator filters in place ([`Decimator::apply_gathered`]),
    /// so the channels are never copied between the regressor and the filter.
    ///
    /// With `carry`, the filter's forward pass goes on from the states `carry` holds (from
    /// the first of the samples when it holds none yet), and the states before sample
    /// `hand` (counted from `lo`) replace them: a channel outside `channels` is zero
    /// throughout, and so are its states.
    fn decimated_channels(
        &self,
        dec: &Decimator,
        lo: usize,
        hi: usize,
        channels: &[usize],
        groups: &mut Vec<Vec<f64>>,
        carry: Option<(&mut Carry, usize)>,
    ) -> Result<Option<Vec<InGroup>>> {
        let (dof, stride) = (self.lay.dof, self.lay.stride());
        let mut inside = vec![false; stride];
        for &c in channels {
            inside[c] = true;
        }
        let inactive = runs(&(0..stride).filter(|&c| !inside[c]).collect::<Vec<_>>());
        let (n, pad) = (hi - lo, dec.first_pad());
        let sets: Vec<&[usize]> = channels.chunks(GROUP).collect();
        // each group's row: its channels, then channels of zeros to whole lanes of the
        // filter's passes ([`Decimator::padded_width`]: no partial lane to copy row by row)
        let widths: Vec<usize> = sets.iter().map(|set| dec.padded_width(set.len())).collect();
        // where each value of a group's row comes from in the sample's row, the zeros at
        // `stride` (one past the row): a gather by index, not a copy per run of
        // consecutive channels (a call to copy a few values, and one to zero the pad)
        let gathers: Vec<Vec<usize>> = sets
            .iter()
            .zip(&widths)
            .map(|(set, &g)| {
                (0..g)
                    .map(|i| set.get(i).copied().unwrap_or(stride))
                    .collect()
            })
            .collect();
        // a value above its channel's limit, or NaN, is either a non-finite value of a
        // group or a non-zero value of a channel taken as zero (found in one pass)
        let limit: Vec<f64> = inside
            .iter()
            .map(|&inside| if inside { f64::MAX } else { 0.0 })
            .collect();
        groups.resize_with(sets.len(), Vec::new);
        groups.truncate(sets.len());
        // each group's samples cut into the chunks of rows the threads fill: chunk b holds
        // rows b * BLOCK.. of every group (the pads are the filter's)
        let mut chunks: Vec<Vec<&mut [f64]>> = (0..n.div_ceil(BLOCK)).map(|_| Vec::new()).collect();
        for (buffer, &g) in groups.iter_mut().zip(&widths) {
            buffer.resize((n + 2 * pad) * g, 0.0);
            let body = &mut buffer[pad * g..(pad + n) * g];
            for (chunk, part) in chunks.iter_mut().zip(body.chunks_mut(BLOCK * g)) {
                chunk.push(part);
            }
        }
        let (missed, bad) = chunks
            .into_par_iter()
            .enumerate()
            .map(|(b, mut parts)| {
                let mut st = Scratch::new(dof);
                let mut full = vec![0.0; stride + 1];
                let (mut missed, mut bad) = (false, None);
                for i in 0..BLOCK.min(n - b * BLOCK) {
                    let k = lo + b * BLOCK + i;
                    self.full_row(k, &mut st, &mut full[..stride]);
                    for ((part, gather), &g) in parts.iter_mut().zip(&gathers).zip(&widths) {
                        let row = &mut part[i * g..(i + 1) * g];
                        for (value, &from) in row.iter_mut().zip(gather) {
                            *value = full[from];
                        }
                    }
                    if !any_above(&full[..stride], &limit) {
                        continue;
                    }
                    // a non-finite inactive channel is not zero: the block is taken again
                    // with every channel, which finds it
                    missed |= inactive
                        .iter()
                        .any(|run| any_nonzero(&full[run.from..run.from + run.len]));
                    // the row's first non-finite value (its other channels are zero when
                    // none was missed)
                    if bad.is_none()
                        && channels.iter().any(|&c| !full[c].is_finite())
                        && let Some((c, v)) = first_non_finite(&full)
                    {
                        bad = Some((k, c, v));
                    }
                }
                (missed, bad)
            })
            .reduce(|| (false, None), |x, y| (x.0 || y.0, x.1.or(y.1)));
        // missed first: a non-finite value in a channel outside the groups, before the
        // first found in them, is then found taking every channel (the record's first
        // non-finite value in any channel, as the check of every whole row found it)
        if missed {
            return Ok(None);
        }
        if let Some((k, c, v)) = bad {
            return Err(self.bad_channel(k, c, v));
        }
        let Some((carry, hand)) = carry else {
            return groups
                .par_iter_mut()
                .zip(&widths)
                .map(|(buffer, &g)| Ok((dec.apply_gathered_in(buffer, g, Forward::whole())?, g)))
                .collect::<Result<Vec<_>>>()
                .map(Some);
        };
        // each group's states: those carried, and a buffer for those handed on
        let ns = carry.sections;
        let started = carry.started();
        // (the channels of zeros that pad a group have states of zeros)
        let starts: Vec<Vec<[f64; 2]>> = sets
            .iter()
            .zip(&widths)
            .map(|(set, &g)| {
                let mut states: Vec<[f64; 2]> = set
                    .iter()
                    .filter(|_| started)
                    .flat_map(|&c| carry.states[c * ns..(c + 1) * ns].iter().copied())
                    .collect();
                if started {
                    states.resize(g * ns, [0.0; 2]);
                }
                states
            })
            .collect();
        let mut handed: Vec<Vec<[f64; 2]>> =
            widths.iter().map(|&g| vec![[0.0; 2]; g * ns]).collect();
        let decimated = groups
            .par_iter_mut()
            .zip(&widths)
            .zip(&starts)
            .zip(&mut handed)
            .map(|(((buffer, &g), start), out)| {
                let forward = Forward {
                    from: if started { pad } else { 0 },
                    start: started.then_some(start.as_slice()),
                    hand: Some((pad + hand, out.as_mut_slice())),
                };
                Ok((dec.apply_gathered_in(buffer, g, forward)?, g))
            })
            .collect::<Result<Vec<_>>>()?;
        carry.states.clear();
        carry.states.resize(stride * ns, [0.0; 2]);
        for (set, out) in sets.iter().zip(&handed) {
            for (&c, states) in set.iter().zip(out.chunks_exact(ns)) {
                carry.states[c * ns..(c + 1) * ns].copy_from_slice(states);
            }
        }
        Ok(Some(decimated))
    }

    /// The equations of the decimated samples whose processed samples lie in `core`
    /// (`core.start` a multiple of the total factor): the regressor rows of `core` and
    /// `overlap` samples on each side (a multiple of the factor, at least
    /// [`Decimator::settling`]), decimated as a block, then the samples of `core` kept
    /// and those near rest (`rest`, per joint) removed. The same equations as [`observe`]
    /// gives for these samples, to the decimation filter's settling tolerance. Channels
    /// that are zero at a few probed samples are assumed zero (checked on every sample,
    /// then all channels taken if one is not), as in [`observe`]. `groups` are buffers for
    /// the channels before decimation, reused from block to block.
    ///
    /// With `carry` (a decimator with one filtering stage: [`Decimator::carried_sections`]),
    /// the decimation filter's forward pass goes on from the states the previous block
    /// handed on, with no overlap on the left (the samples start at `core.start`), and
    /// hands its states before `core.end` on to the next block; the first block (`carry`
    /// holds no states yet) starts as without it.
    pub(crate) fn window(
        &self,
        dec: &Decimator,
        overlap: usize,
        rest: Option<&[f64]>,
        core: std::ops::Range<usize>,
        groups: &mut Vec<Vec<f64>>,
        mut carry: Option<&mut Carry>,
    ) -> Result<Equations> {
        let (lay, dof) = (&self.lay, self.lay.dof);
        let n = self.signals.samples();
        let f = dec.factor();
        let lo = if carry.as_ref().is_some_and(|c| c.started()) {
            core.start
        } else {
            core.start.saturating_sub(overlap)
        };
        let hi = (core.end + overlap).min(n);
        let stride = lay.stride();
        let mut st = Scratch::new(dof);
        let mut probe = vec![0.0; stride];
        let mut active = vec![false; stride];
        for i in 0..PROBES {
            let k = lo + i * (hi - lo).saturating_sub(1) / (PROBES - 1);
            if self.row_at(k, &mut st, &mut probe).is_ok() {
                for (a, v) in active.iter_mut().zip(&probe) {
                    *a |= *v != 0.0;
                }
            }
        }
        for j in 0..dof {
            active[lay.tau(j)] = true;
            active[lay.qd(j)] = true;
        }
        let mut channels: Vec<usize> = (0..stride).filter(|&c| active[c]).collect();
        let hand = core.end - lo;
        let first = self.decimated_channels(
            dec,
            lo,
            hi,
            &channels,
            groups,
            carry.as_deref_mut().map(|c| (c, hand)),
        )?;
        let decimated = match first {
            Some(g) => g,
            None => {
                channels = (0..stride).collect();
                self.decimated_channels(dec, lo, hi, &channels, groups, carry.map(|c| (c, hand)))?
                    .unwrap_or_default()
            }
        };
        let decimated: Vec<(&[f64], usize)> = decimated
            .into_iter()
            .zip(groups.iter())
            .map(|((range, width), buffer)| (&buffer[range], width))
            .collect();
        let mut place: Vec<Option<(usize, usize)>> = vec![None; stride];
        for (i, &c) in channels.iter().enumerate() {
            place[c] = Some((i / GROUP, i % GROUP));
        }
        let value = |i: usize, c: usize| -> f64 {
            place[c].map_or(0.0, |(g, k)| {
                let (v, width) = decimated[g];
                v[i * width + k]
            })
        };
        let cols = lay.p + lay.e;
        // each joint's columns among the decimated channels: (column, group, place in the
        // group's row); its other columns are zero
        let placed: Vec<Vec<(usize, usize, usize)>> = (0..dof)
            .map(|j| {
                (0..cols)
                    .filter_map(|c| place[lay.column(j, c)].map(|(g, k)| (c, g, k)))
                    .collect()
            })
            .collect();
        // at most one equation per joint and decimated sample
        let most = (core.end.div_ceil(f) - core.start / f) * dof;
        let mut eq = Equations {
            cols,
            w: Vec::with_capacity(most * cols),
            y: Vec::with_capacity(most),
            joint: Vec::with_capacity(most),
            sample: Vec::with_capacity(most),
            rest: RestCount::default(),
        };
        let first = lo / f;
        for k in core.start / f..core.end.div_ceil(f) {
            let i = k - first;
            for j in 0..dof {
                let speed = value(i, lay.qd(j)).abs();
                let moving = rest.is_none_or(|t| speed >= t[j]);
                eq.rest.count(j, speed, moving);
                if !moving {
                    continue;
                }
                let y = value(i, lay.tau(j));
                let start = eq.w.len();
                eq.w.resize(start + cols, 0.0);
                let row = &mut eq.w[start..];
                for &(c, g, at) in &placed[j] {
                    let (v, width) = decimated[g];
                    row[c] = v[i * width + at];
                }
                let bad = first_non_finite(row)
                    .map(|(c, v)| (self.names[c].clone(), v))
                    .or((!y.is_finite()).then(|| ("torque".to_string(), y)));
                if let Some((parameter, value)) = bad {
                    return Err(Error::Estimate(EstimateError::NonFiniteObservation {
                        location: format!("processed sample {}", k * f),
                        sample: Some(k * f),
                        joint: j + 1,
                        parameter,
                        value,
                    }));
                }
                eq.y.push(y);
                eq.joint.push(j);
                eq.sample.push(k);
            }
        }
        Ok(eq)
    }

    /// The measured and predicted torques of the decimated samples of `core` with the
    /// parameter values `beta`, as [`window`](Self::window) would give them (`y` and
    /// `W beta`) but cheaper: the decimation filter is linear, so the prediction is the
    /// decimated `Y(t) beta`, and only three channels per joint (prediction, torque,
    /// velocity) are filtered. Returns `(joint, decimated sample, measured, predicted)`,
    /// and what the removal of the equations near rest left.
    pub(crate) fn window_prediction(
        &self,
        dec: &Decimator,
        overlap: usize,
        rest: Option<&[f64]>,
        core: std::ops::Range<usize>,
        beta: &[f64],
    ) -> Result<(Vec<Predicted>, RestCount)> {
        let dof = self.lay.dof;
        let f = dec.factor();
        let (groups, first) = self.prediction_channels(dec, overlap, &core, beta, true)?;
        let value = |i: usize, c: usize| group_value(&groups, f, i, c);
        let mut out = Vec::new();
        let mut count = RestCount::default();
        for k in core.start / f..core.end.div_ceil(f) {
            let i = k - first;
            for j in 0..dof {
                let speed = value(i, 2 * dof + j).abs();
                let moving = rest.is_none_or(|t| speed >= t[j]);
                count.count(j, speed, moving);
                if moving {
                    out.push((j, k, value(i, dof + j), value(i, j)));
                }
            }
        }
        Ok((out, count))
    }

    /// The predicted torques with the parameter values `beta` of the equations an
    /// estimation pass kept among the decimated samples of `core` (`kept(joint, decimated
    /// sample)`): [`window_prediction`](Self::window_prediction)'s, but the measured
    /// torques and the removal of the equations near rest are the estimation's (its `y`
    /// and its equations, as the dense prediction takes them from the observation), so
    /// that only the predicted channel of each joint is filtered. Returns `(joint,
    /// decimated sample, predicted)`.
    pub(crate) fn window_predicted(
        &self,
        dec: &Decimator,
        overlap: usize,
        core: std::ops::Range<usize>,
        beta: &[f64],
        kept: impl Fn(usize, usize) -> bool,
    ) -> Result<Vec<(usize, usize, f64)>> {
        let dof = self.lay.dof;
        let f = dec.factor();
        let (groups, first) = self.prediction_channels(dec, overlap, &core, beta, false)?;
        let mut out = Vec::new();
        for k in core.start / f..core.end.div_ceil(f) {
            for j in (0..dof).filter(|&j| kept(j, k)) {
                out.push((j, k, group_value(&groups, f, k - first, j)));
            }
        }
        Ok(out)
    }

    /// The channels of the prediction over the samples of `core` and `overlap` on each
    /// side, decimated: the predicted torque of each joint, then, `measured`, its torque
    /// and its velocity; and the first decimated sample they hold.
    fn prediction_channels(
        &self,
        dec: &Decimator,
        overlap: usize,
        core: &std::ops::Range<usize>,
        beta: &[f64],
        measured: bool,
    ) -> Result<(Vec<Decimated>, usize)> {
        let (lay, dof) = (&self.lay, self.lay.dof);
        let n = self.signals.samples();
        let f = dec.factor();
        let lo = core.start.saturating_sub(overlap);
        let hi = (core.end + overlap).min(n);
        let cols = lay.p + lay.e;
        let width = if measured { 3 * dof } else { dof };
        let mut rows = Vec::new();
        // each joint's channels of the parameters, in the parameters' order
        let columns: Vec<Vec<usize>> = (0..dof)
            .map(|j| (0..cols).map(|c| lay.column(j, c)).collect())
            .collect();
        let (_, bad) = self.rows_in_parallel(lo, hi, width, &mut rows, |k, st, full, out| {
            match self.prediction_at(k, st, beta, out) {
                Ok(()) if first_non_finite(out).is_none() => (false, None),
                // the whole row, as the dense prediction takes it, and the channel to blame
                _ => {
                    self.full_row(k, st, full);
                    for (j, channels) in columns.iter().enumerate() {
                        out[j] = channels.iter().zip(beta).map(|(&c, b)| full[c] * b).sum();
                        if measured {
                            out[dof + j] = full[lay.tau(j)];
                            out[2 * dof + j] = full[lay.qd(j)];
                        }
                    }
                    (false, first_non_finite(full))
                }
            }
        });
        if let Some((k, c, v)) = bad {
            return Err(self.bad_channel(k, c, v));
        }
        Ok((decimate_rows(dec, &mut rows, width)?, lo / f))
    }
}

/// Channel `c` of decimated sample `i` of [`decimate_rows`]'s groups (total factor `f`).
fn group_value(groups: &[Decimated], f: usize, i: usize, c: usize) -> f64 {
    let (g, k) = if f == 1 {
        (0, c)
    } else {
        (c / GROUP, c % GROUP)
    };
    let (v, width) = &groups[g];
    v[i * width + k]
}

/// Consecutive indices of a list: the `len` values from index `from` go to position
/// `at` of the list's values, so that they are copied as one slice.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Run {
    from: usize,
    at: usize,
    len: usize,
}

/// The runs of consecutive values of `indices`, in order.
fn runs(indices: &[usize]) -> Vec<Run> {
    let mut out: Vec<Run> = Vec::new();
    for (at, &from) in indices.iter().enumerate() {
        match out.last_mut() {
            Some(run) if run.from + run.len == from => run.len += 1,
            _ => out.push(Run { from, at, len: 1 }),
        }
    }
    out
}

/// Whether a value of `x` is not zero (`v != 0.0`: NaN is not zero, -0 is), as one pass
/// of integer ORs, which the compiler vectorises: the check that the channels taken as
/// zero are zero, for every sample row of a block (an early exit per value, which the
/// compiler does not vectorise, took a quarter of the fill's own time in a profile of
/// the hour).
fn any_nonzero(x: &[f64]) -> bool {
    // the bits but the sign: zero for +0 and -0 only
    x.iter().fold(0u64, |any, v| any | (v.to_bits() << 1)) != 0
}

/// Whether a value of `x` is above its `limit` in magnitude or NaN, as one pass without
/// an early exit, which the compiler vectorises.
fn any_above(x: &[f64], limit: &[f64]) -> bool {
    x.iter()
        .zip(limit)
        .fold(false, |any, (v, l)| any | !(v.abs() <= *l))
}

/// A group of decimated channels: values (row-major, one row per decimated sample) and
/// the row width.
type Decimated = (Vec<f64>, usize);

/// A group of decimated channels left in the buffer it was filtered in: the values' place
/// in it ([`Decimator::apply_gathered_in`]; row-major, one row per decimated sample) and
/// the row width.
type InGroup = (std::ops::Range<usize>, usize);

/// Decimates every channel of row-major `rows` (`width` values per row): groups of
/// [`GROUP`] channels in parallel, each `(values, width)` row-major with one row per
/// decimated sample (its rows padded with channels of zeros to
/// [`Decimator::padded_width`]); the rows themselves as one group without decimation
/// (taken from `rows`).
fn decimate_rows(dec: &Decimator, rows: &mut Vec<f64>, width: usize) -> Result<Vec<Decimated>> {
    if dec.factor() == 1 {
        return Ok(vec![(std::mem::take(rows), width)]);
    }
    let local: Vec<usize> = (0..width).collect();
    local
        .par_chunks(GROUP)
        .map(|g| dec.apply_block_padded(rows, width, g))
        .collect()
}

/// Builds W and y from prepared signals: `model`'s base regressor plus the config's
/// extra columns, filtered and decimated, with rest samples removed per joint.
pub fn observe(
    model: &(dyn Model + Sync),
    signals: &Prepared,
    config: &Config,
) -> Result<Observation> {
    observe_counted(model, signals, config, "the data").map(|(obs, _)| obs)
}

/// Refuses an observation of `n` samples of `stride` regressor channels beyond
/// [`MAX_OBSERVATION_ENTRIES`](crate::limits::MAX_OBSERVATION_ENTRIES): the methods that
/// hold the matrix reach this (OLS and WLS stream). Checked before the record is read
/// with the fewest samples and channels it can have, and again with the exact ones.
pub(crate) fn check_observation_size(n: usize, stride: usize) -> Result<()> {
    crate::limits::check_size(
        || format!("regressor values before decimation ({n} samples x {stride} channels)"),
        n as f64 * stride as f64,
        crate::limits::MAX_OBSERVATION_ENTRIES,
        "use a shorter record or identify it in parts (processing.range), or by WLS or OLS \
         (`--method wls`, `method = \"wls\"`) without `known` parameters, which stream a \
         record of any length",
    )
}

/// [`observe`], with what the removal of the equations near rest left of each joint's;
/// `of` names the signals' record in the errors about it.
pub(crate) fn observe_counted(
    model: &(dyn Model + Sync),
    signals: &Prepared,
    config: &Config,
    of: &str,
) -> Result<(Observation, RestCount)> {
    let observer = Observer::new(model, signals, config)?;
    let (lay, names) = (&observer.lay, &observer.names);
    let dof = lay.dof;
    let n = signals.samples();
    let stride = lay.stride();
    check_observation_size(n, stride)?;
    let row_at = |k: usize, st: &mut Scratch, row: &mut [f64]| observer.row_at(k, st, row);
    // channels that are not identically zero, probed at a few samples; verified below
    let mut st = Scratch::new(dof);
    let mut probe = vec![0.0; stride];
    let mut active = vec![false; stride];
    for i in 0..PROBES {
        row_at(i * n.saturating_sub(1) / (PROBES - 1), &mut st, &mut probe)?;
        for (a, v) in active.iter_mut().zip(&probe) {
            *a |= *v != 0.0;
        }
    }
    for j in 0..dof {
        active[lay.tau(j)] = true;
        active[lay.qd(j)] = true;
    }
    let mut channels: Vec<usize> = (0..stride).filter(|&c| active[c]).collect();
    let inactive: Vec<usize> = (0..stride).filter(|&c| !active[c]).collect();
    let mut rows = Vec::new();
    // the first sample whose regressor row holds NaN or an infinite value
    let mut bad: Option<(usize, usize, f64)> = None;
    for attempt in 0..2 {
        if attempt == 1 {
            channels = (0..stride).collect();
        }
        let a = channels.len();
        rows = vec![0.0; n * a];
        let (missed, first_bad) = rows
            .par_chunks_mut(a * BLOCK)
            .enumerate()
            .map(|(b, chunk)| {
                let mut st = Scratch::new(dof);
                let mut full = vec![0.0; stride];
                let mut missed = false;
                let mut first_bad = None;
                for (i, out) in chunk.chunks_exact_mut(a).enumerate() {
                    let k = b * BLOCK + i;
                    // the probes above passed, so the sizes are right; a model that
                    // still refuses leaves NaN, which is reported by row below
                    if row_at(k, &mut st, &mut full).is_err() {
                        full.iter_mut().for_each(|v| *v = f64::NAN);
                    }
                    // whether the row holds NaN or an infinity, in the copy loop
                    let mut poison = false;
                    for (o, &c) in out.iter_mut().zip(&channels) {
                        *o = full[c];
                        poison |= !full[c].is_finite();
                    }
                    let outside: f64 = inactive.iter().map(|&c| full[c].abs()).sum();
                    // a non-finite inactive channel makes `outside` NaN: `missed` then
                    // brings the second attempt with every channel
                    missed |= outside != 0.0;
                    if poison
                        && first_bad.is_none()
                        && let Some(c) = full.iter().position(|v| !v.is_finite())
                    {
                        first_bad = Some((k, c, full[c]));
                    }
                }
                (missed, first_bad)
            })
            .reduce(
                || (false, None),
                |x, y| {
                    let first = match (x.1, y.1) {
                        (Some(a), Some(b)) => Some(if a.0 <= b.0 { a } else { b }),
                        (a, b) => a.or(b),
                    };
                    (x.0 || y.0, first)
                },
            );
        bad = first_bad;
        if bad.is_some() || !missed || attempt == 1 {
            break;
        }
    }
    if let Some((k, c, value)) = bad {
        return Err(observer.bad_channel(k, c, value));
    }
    let a = channels.len();

    // decimated channels: row-major groups (`width` channels per row, one row per
    // decimated sample); without decimation the regressor rows are used as they are
    let cols = lay.p + lay.e;
    let dec = decimator_for(
        config,
        of,
        (n, dof),
        equations_needed(cols),
        &equations_purpose(cols),
    )?;
    let (groups, width) = if dec.factor() == 1 {
        (vec![rows], a)
    } else {
        let local: Vec<usize> = (0..a).collect();
        let groups: Vec<Vec<f64>> = local
            .par_chunks(GROUP)
            .map(|g| dec.apply_block(&rows, a, g))
            .collect::<Result<_>>()?;
        drop(rows);
        (groups, GROUP)
    };
    // where each channel is: (group, index in group, group width); None = all zero
    let mut place: Vec<Option<(usize, usize, usize)>> = vec![None; stride];
    for (i, &c) in channels.iter().enumerate() {
        let (g, k) = (i / width, i % width);
        let w = if dec.factor() == 1 {
            a
        } else {
            GROUP.min(a - g * GROUP)
        };
        place[c] = Some((g, k, w));
    }
    let series = |ch: usize| -> Option<(&[f64], usize, usize)> {
        place[ch].map(|(g, k, w)| (groups[g].as_slice(), k, w))
    };

    // the decimated samples the anti-alias filter settled ([`Decimator::settled`]): those
    // at the record's ends carry an end sample's noise whole; `first` is the first
    let settled = dec.settled(n);
    let (first, m) = (settled.start, settled.len());
    let qd_dec = Signals::new(
        (0..dof)
            .map(|j| match series(lay.qd(j)) {
                Some((v, k, w)) => v
                    .iter()
                    .skip(k + first * w)
                    .step_by(w)
                    .take(m)
                    .copied()
                    .collect(),
                None => vec![0.0; m],
            })
            .collect(),
    )?;
    let rest = Some(config.processing.rest_velocities(dof)?);
    // decimated samples counted from `first`
    let keep: Vec<Vec<usize>> = match &rest {
        Some(t) => moving_samples(&qd_dec, t)?,
        None => vec![(0..m).collect(); dof],
    };
    let total: usize = keep.iter().map(Vec::len).sum();
    let fastest = |v: &[f64]| v.iter().fold(0.0, |a: f64, x| a.max(x.abs()));
    let count = RestCount {
        before: m * dof,
        kept: total,
        fastest: qd_dec.joints().map(fastest).fold(0.0, f64::max),
        joints: qd_dec
            .joints()
            .zip(&keep)
            .map(|(v, k)| JointRest {
                before: m,
                kept: k.len(),
                fastest: fastest(v),
            })
            .collect(),
    };
    count.check(
        config,
        rest.as_deref(),
        equations_needed(cols),
        &equations_purpose(cols),
    )?;
    let mut w = DMatrix::zeros(total, cols);
    let mut y = DVector::zeros(total);
    let mut joint_rows = Vec::with_capacity(dof);
    let mut sample_of_row = Vec::with_capacity(total);
    let mut start = 0;
    let wdata = w.as_mut_slice();
    for (j, ks) in keep.iter().enumerate() {
        // (column, source, index, width) of the non-zero channels of joint j's rows
        let sources: Vec<(usize, &[f64], usize, usize)> = (0..cols)
            .filter_map(|c| series(lay.column(j, c)).map(|(v, k, wd)| (c, v, k, wd)))
            .collect();
        let tau = series(lay.tau(j));
        for (r, &k) in ks.iter().enumerate() {
            let (row, k) = (start + r, first + k);
            if let Some((v, i, wd)) = tau {
                y[row] = v[k * wd + i];
            }
            for &(c, v, i, wd) in &sources {
                wdata[c * total + row] = v[k * wd + i];
            }
            sample_of_row.push(k);
        }
        joint_rows.push(start..start + ks.len());
        start += ks.len();
    }
    let obs = Observation::new(w, y, joint_rows, sample_of_row, names.clone()).map_err(|e| {
        // a decimated sample k is processed sample k * factor
        let at = |k: usize| k * dec.factor();
        e.placed(|k| (at(k), format!("processed sample {}", at(k))))
            .unwrap_or_else(|e| e)
    })?;
    Ok((obs, count))
}

#[cfg(test)]
mod tests {
    use super::{Run, runs};

    /// A joint at rest to the rounding of its positions has no velocity nor acceleration;
    /// a moving joint keeps its small velocity where it turns back and its small
    /// acceleration where it coasts, however coarse the floor (positions near 1e4 rad at
    /// 100 kHz: 1.8e-6 rad/s and 0.18 rad/s^2).
    #[test]
    fn only_a_joint_at_rest_to_rounding_loses_its_motion() {
        let dt = 1e-5;
        let q = [1e4; 5];
        let mut qd = [1e-13, 1e-7, 1.0, 1e-5, -1e-6];
        let mut qdd = [1e-3, 5.0, 1e-3, 1e-3, -0.1];
        super::at_rest_to_rounding(&q, &mut qd, &mut qdd, dt);
        assert_eq!(qd, [0.0, 1e-7, 1.0, 1e-5, 0.0]);
        assert_eq!(qdd, [0.0, 5.0, 1e-3, 1e-3, 0.0]);
        // the floor grows with the position: at 0 it is 1.8e-10 rad/s and 1.8e-5 rad/s^2
        let mut qd = [1e-9, 1e-11];
        let mut qdd = [1e-6, 1e-6];
        super::at_rest_to_rounding(&[0.0; 2], &mut qd, &mut qdd, dt);
        assert_eq!((qd, qdd), ([1e-9, 0.0], [1e-6, 0.0]));
    }

    /// `any_nonzero` is `any(|v| v != 0.0)`: -0 is zero, NaN and the smallest subnormal
    /// are not, wherever they are in a slice.
    #[test]
    fn any_nonzero_is_any_value_unequal_to_zero() {
        for odd in [0.0, -0.0, f64::NAN, 5e-324, -5e-324, 1.0, f64::INFINITY] {
            for len in [1, 2, 7, 33] {
                for at in 0..len {
                    let mut x = vec![-0.0; len];
                    x[at] = odd;
                    assert_eq!(
                        super::any_nonzero(&x),
                        x.iter().any(|&v| v != 0.0),
                        "{odd} at {at} of {len}"
                    );
                }
            }
        }
        assert!(!super::any_nonzero(&[]));
    }

    #[test]
    fn runs_cover_every_index_once_in_order() {
        let r = |from, at, len| Run { from, at, len };
        assert_eq!(runs(&[]), vec![]);
        assert_eq!(runs(&[4]), vec![r(4, 0, 1)]);
        assert_eq!(
            runs(&[0, 1, 2, 5, 6, 9, 3]),
            vec![r(0, 0, 3), r(5, 3, 2), r(9, 5, 1), r(3, 6, 1)]
        );
    }
}
