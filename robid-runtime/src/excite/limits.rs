//! Joint limits and the margins a trajectory keeps to them.

use crate::Count;
use crate::error::{Error, Result, num};
use crate::limits::{
    MAX_ACCELERATION, MAX_BASE_PARAMETER, MAX_POSITION, MAX_TORQUE, MAX_VELOCITY, MIN_JOINT_LIMIT,
};
use crate::simulate::Trajectory;
use crate::{LengthError, Model};

/// The limits of one joint.
#[derive(Debug, Clone, PartialEq)]
pub struct JointLimits {
    /// Lowest and highest position (rad or m).
    pub position: [f64; 2],
    /// Largest speed |qd|.
    pub velocity: f64,
    /// Largest acceleration |qdd|.
    pub acceleration: f64,
    /// Largest torque |tau| (checked only when reference parameters are given).
    pub torque: Option<f64>,
}

impl JointLimits {
    /// Checks that the limits are finite, ordered, positive and within the ranges of
    /// [`crate::limits`] (at least [`MIN_JOINT_LIMIT`]: a joint held to less cannot be
    /// excited); `joint` is 1-based.
    pub fn check(&self, joint: usize) -> Result<()> {
        let [lo, hi] = self.position;
        let bad = |what: &str, problem: String| {
            Err(Error::setting(
                "JointLimits",
                what,
                format!("joint {joint}: {problem}"),
            ))
        };
        if !(lo.abs() <= MAX_POSITION && hi.abs() <= MAX_POSITION && hi - lo >= MIN_JOINT_LIMIT) {
            return bad(
                "position",
                format!(
                    "[{}, {}] must be finite within +-{MAX_POSITION:e}, with high - low at \
                     least {MIN_JOINT_LIMIT:e}",
                    num(lo),
                    num(hi)
                ),
            );
        }
        for (what, x, limit) in [
            ("velocity", self.velocity, MAX_VELOCITY),
            ("acceleration", self.acceleration, MAX_ACCELERATION),
            ("torque", self.torque.unwrap_or(1.0), MAX_TORQUE),
        ] {
            if !(x >= MIN_JOINT_LIMIT && x <= limit) {
                return bad(
                    what,
                    format!(
                        "{} must lie in [{MIN_JOINT_LIMIT:e}, {limit:e}] (a smaller limit leaves \
                         the joint nothing to excite)",
                        num(x)
                    ),
                );
            }
        }
        Ok(())
    }
}

/// The room (below, above) a design's position may use on either side of its start `q0`
/// within the position limits `[lo, hi]`: the band of `safety` times the half range around
/// the middle, and, on the side of the nearer limit, at least `safety` times the distance
/// from the start to that limit. A start in the outer (1 - safety) of the range (accepted:
/// it lies strictly inside the limits, e.g. `robid excite --start 6.2` on a UR5e joint of
/// range ±6.2832) left the band no room on that side: every trajectory shape, which moves
/// both ways from the start, was scaled to nothing, and both designs failed with an
/// infinite criterion blaming the limits. A start at the middle keeps the band to the bit.
pub(crate) fn position_room(position: [f64; 2], safety: f64, q0: f64) -> (f64, f64) {
    let [lo, hi] = position;
    let (mid, half) = (0.5 * (lo + hi), 0.5 * (hi - lo) * safety);
    let mut below = (q0 - (mid - half)).max(0.0);
    let mut above = (mid + half - q0).max(0.0);
    if q0 > mid {
        above = above.max(safety * (hi - q0));
    } else if q0 < mid {
        below = below.max(safety * (q0 - lo));
    }
    (below, above)
}

/// Checks a set of limits against the model's joint count.
pub fn check_limits(limits: &[JointLimits], dof: usize) -> Result<()> {
    if limits.len() != dof {
        return Err(Error::setting(
            "design",
            "limits",
            format!(
                "{} for a model of {}; give one per joint",
                Count(limits.len(), "joint limit"),
                Count(dof, "joint")
            ),
        ));
    }
    limits
        .iter()
        .enumerate()
        .try_for_each(|(j, l)| l.check(j + 1))
}

/// The torque-limit penalty that both designs add to their criterion (torques are the one
/// limit not held by construction). Per joint, the excess of |tau| over `safety` times the
/// limit, relative to it, is taken at its worst over the states added (what must end at zero)
/// plus its mean (so that every state that exceeds, not only the worst, is pushed back: the
/// point design improves one point at a time).
pub(crate) struct TorquePenalty<'a> {
    limits: &'a [JointLimits],
    safety: f64,
    base: &'a [f64],
    worst: Vec<f64>,
    total: Vec<f64>,
    states: usize,
    tau: Vec<f64>,
}

impl<'a> TorquePenalty<'a> {
    /// Weight of the penalty: a 1 % excess costs as much as 10 units of the criterion.
    const WEIGHT: f64 = 1e3;

    /// For `limits` (one per joint) with reference base parameters `base`.
    pub(crate) fn new(limits: &'a [JointLimits], safety: f64, base: &'a [f64]) -> Self {
        let n = limits.len();
        Self {
            limits,
            safety,
            base,
            worst: vec![0.0; n],
            total: vec![0.0; n],
            states: 0,
            tau: vec![0.0; n],
        }
    }

    /// Forgets every state added (keeping the buffers).
    pub(crate) fn reset(&mut self) {
        self.worst.fill(0.0);
        self.total.fill(0.0);
        self.states = 0;
    }

    /// Adds one state.
    pub(crate) fn add<M: Model + ?Sized>(
        &mut self,
        model: &M,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
    ) -> std::result::Result<(), LengthError> {
        model.inverse_dynamics_into(q, qd, qdd, self.base, &mut self.tau)?;
        for (j, l) in self.limits.iter().enumerate() {
            if let Some(t) = l.torque {
                let excess = (self.tau[j].abs() / (self.safety * t) - 1.0).max(0.0);
                self.worst[j] = self.worst[j].max(excess);
                self.total[j] += excess;
            }
        }
        self.states += 1;
        Ok(())
    }

    /// The penalty: WEIGHT times the sum over joints of the worst and the mean excess (zero
    /// within every limit).
    pub(crate) fn value(&self) -> f64 {
        let states = self.states.max(1) as f64;
        let excess: f64 = self
            .worst
            .iter()
            .zip(&self.total)
            .map(|(w, t)| w + t / states)
            .sum();
        Self::WEIGHT * excess
    }
}

/// Checks that reference base parameters (enabling the torque limits) fit the model.
pub(crate) fn check_reference<M: Model + ?Sized>(model: &M, base: Option<&[f64]>) -> Result<()> {
    match base {
        Some(b) if b.len() != model.base_parameter_count() => Err(Error::DimensionMismatch {
            what: "reference base parameters".into(),
            expected: model.base_parameter_count(),
            found: b.len(),
        }),
        Some(b) => check_parameters("design", "torque", model, b),
        None => Ok(()),
    }
}

/// Checks base-parameter values given as input: finite, magnitude at most
/// [`MAX_BASE_PARAMETER`]; the error names the parameter.
pub(crate) fn check_parameters<M: Model + ?Sized>(
    owner: &str,
    key: &str,
    model: &M,
    base: &[f64],
) -> Result<()> {
    match base.iter().position(|v| !(v.abs() <= MAX_BASE_PARAMETER)) {
        Some(i) => Err(Error::setting(
            owner,
            key,
            format!(
                "base parameter `{}` is {}; parameter values must be finite with magnitude at most {MAX_BASE_PARAMETER:e}",
                model.base_parameter_name(i).unwrap_or("?"),
                num(base[i])
            ),
        )),
        None => Ok(()),
    }
}

/// How far a trajectory stays from each limit of one joint (positive = inside).
#[derive(Debug, Clone, PartialEq)]
pub struct Margin {
    /// min over samples of q - q_min.
    pub position_low: f64,
    /// min over samples of q_max - q.
    pub position_high: f64,
    /// velocity limit - max |qd|.
    pub velocity: f64,
    /// acceleration limit - max |qdd|.
    pub acceleration: f64,
    /// torque limit - max |tau|, when torques were computed and a limit is given.
    pub torque: Option<f64>,
    /// The largest |tau| (when computed).
    pub peak_torque: Option<f64>,
}

impl Margin {
    /// True when no limit is exceeded.
    pub fn respected(&self) -> bool {
        self.position_low >= 0.0
            && self.position_high >= 0.0
            && self.velocity >= 0.0
            && self.acceleration >= 0.0
            && self.torque.is_none_or(|t| t >= 0.0)
    }

    /// The tighter of two margins of one joint, limit by limit (the samples' and a finer
    /// evaluation's): the smaller margins and the larger peak torque.
    ///
    /// ```
    /// use robid_runtime::excite::Margin;
    /// let at = |velocity: f64| Margin {
    ///     position_low: 1.0,
    ///     position_high: 1.0,
    ///     velocity,
    ///     acceleration: 2.0,
    ///     torque: None,
    ///     peak_torque: None,
    /// };
    /// assert_eq!(at(0.294).tighter(&at(0.072)).velocity, 0.072);
    /// ```
    pub fn tighter(&self, other: &Margin) -> Margin {
        Margin {
            position_low: self.position_low.min(other.position_low),
            position_high: self.position_high.min(other.position_high),
            velocity: self.velocity.min(other.velocity),
            acceleration: self.acceleration.min(other.acceleration),
            torque: self.torque.zip(other.torque).map(|(x, y)| x.min(y)),
            peak_torque: self
                .peak_torque
                .zip(other.peak_torque)
                .map(|(x, y)| x.max(y)),
        }
    }
}

/// The margins of `trajectory` to `limits`; with `torques` = (model, base parameters)
/// the inverse-dynamics torques are checked too.
pub fn margins<M: Model + ?Sized>(
    trajectory: &Trajectory,
    limits: &[JointLimits],
    torques: Option<(&M, &[f64])>,
) -> std::result::Result<Vec<Margin>, LengthError> {
    let n = trajectory.dof();
    let mut peak = None;
    if let Some((model, base)) = torques {
        let mut p = vec![0.0f64; n];
        let (mut q, mut qd, mut qdd, mut tau) =
            (vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        for k in 0..trajectory.samples() {
            trajectory.state(k, &mut q, &mut qd, &mut qdd);
            model.inverse_dynamics_into(&q, &qd, &qdd, base, &mut tau)?;
            for j in 0..n {
                p[j] = p[j].max(tau[j].abs());
            }
        }
        peak = Some(p);
    }
    let max_abs = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    Ok((0..n)
        .map(|j| {
            let l = &limits[j];
            let q = &trajectory.q[j];
            let lo = q.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = q.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            let peak_torque = peak.as_ref().map(|p| p[j]);
            Margin {
                position_low: lo - l.position[0],
                position_high: l.position[1] - hi,
                velocity: l.velocity - max_abs(&trajectory.qd[j]),
                acceleration: l.acceleration - max_abs(&trajectory.qdd[j]),
                torque: l.torque.zip(peak_torque).map(|(t, p)| t - p),
                peak_torque,
            }
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn joint() -> JointLimits {
        JointLimits {
            position: [-1.0, 1.0],
            velocity: 2.0,
            acceleration: 5.0,
            torque: Some(10.0),
        }
    }

    /// Limits too small to excite anything (a denormal velocity gave a criterion that is
    /// not finite and an error naming no joint) are refused naming the joint and the
    /// limit; the floor itself is accepted.
    #[test]
    fn limits_below_the_floor_are_refused_by_joint() {
        assert!(joint().check(1).is_ok());
        type Edit = fn(&mut JointLimits, f64);
        let edits: [(&str, Edit); 4] = [
            ("velocity", |l, x| l.velocity = x),
            ("acceleration", |l, x| l.acceleration = x),
            ("torque", |l, x| l.torque = Some(x)),
            ("position", |l, x| l.position = [0.5, 0.5 + x]),
        ];
        for (what, edit) in edits {
            for tiny in [1e-320, 1e-9, 0.0] {
                let mut l = joint();
                edit(&mut l, tiny);
                let e = l.check(3).unwrap_err().to_string();
                assert!(
                    e.contains(what) && e.contains("joint 3"),
                    "{what} {tiny}: {e}"
                );
            }
            let mut l = joint();
            edit(&mut l, 2.0 * MIN_JOINT_LIMIT);
            assert!(l.check(3).is_ok(), "{what} at the floor");
        }
    }

    /// Base parameters above the standard values' cap pass, as sums of valid standard
    /// values can give them (`ZZR1` of 2.4e6 from three values of 1e6 was refused by the
    /// simulation while `robid torques` took it); beyond MAX_BASE_PARAMETER, or not
    /// finite, one is refused by name.
    #[test]
    fn base_parameters_are_capped_beyond_sums_of_standard_ones() {
        let model = crate::simulate::tests::Pendulum::default();
        let mut base = model.base();
        base[1] = 2.4e6;
        assert!(check_parameters("design", "torque", &model, &base).is_ok());
        base[1] = MAX_BASE_PARAMETER;
        assert!(check_parameters("design", "torque", &model, &base).is_ok());
        for bad in [
            2.0 * MAX_BASE_PARAMETER,
            -2.0 * MAX_BASE_PARAMETER,
            f64::NAN,
        ] {
            base[1] = bad;
            let e = check_parameters("design", "torque", &model, &base)
                .unwrap_err()
                .to_string();
            let name = model.base_parameter_name(1).unwrap();
            assert!(e.contains(&format!("`{name}`")), "{bad}: {e}");
        }
    }
}
