//! Joint limits and the margins a trajectory keeps to them.

use crate::Model;
use crate::error::{Error, Result};
use crate::simulate::Trajectory;

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
    /// Checks that the limits are finite, ordered and positive; `joint` is 1-based.
    pub fn check(&self, joint: usize) -> Result<()> {
        let [lo, hi] = self.position;
        let bad = |what: &str, problem: String| Error::InvalidConfig {
            key: format!("joint {joint} {what} limit"),
            problem,
        };
        if !(lo.is_finite() && hi.is_finite() && lo < hi) {
            return Err(bad(
                "position",
                format!("[{lo}, {hi}] must be finite with low < high"),
            ));
        }
        for (what, x) in [
            ("velocity", self.velocity),
            ("acceleration", self.acceleration),
        ] {
            if !(x > 0.0 && x.is_finite()) {
                return Err(bad(what, format!("{x} must be positive and finite")));
            }
        }
        if let Some(t) = self.torque.filter(|t| !(*t > 0.0 && t.is_finite())) {
            return Err(bad("torque", format!("{t} must be positive and finite")));
        }
        Ok(())
    }
}

/// Checks a set of limits against the model's joint count.
pub fn check_limits(limits: &[JointLimits], dof: usize) -> Result<()> {
    if limits.len() != dof {
        return Err(Error::JointCountMismatch {
            context: "joint limits".into(),
            expected: dof,
            found: limits.len(),
        });
    }
    limits
        .iter()
        .enumerate()
        .try_for_each(|(j, l)| l.check(j + 1))
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
}

/// The margins of `trajectory` to `limits`; with `torques` = (model, base parameters)
/// the inverse-dynamics torques are checked too.
pub fn margins<M: Model + ?Sized>(
    trajectory: &Trajectory,
    limits: &[JointLimits],
    torques: Option<(&M, &[f64])>,
) -> Vec<Margin> {
    let n = trajectory.dof();
    let peak = torques.map(|(model, base)| {
        let mut peak = vec![0.0f64; n];
        let (mut q, mut qd, mut qdd, mut tau) =
            (vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        for k in 0..trajectory.samples() {
            trajectory.state(k, &mut q, &mut qd, &mut qdd);
            model.inverse_dynamics(&q, &qd, &qdd, base, &mut tau);
            for j in 0..n {
                peak[j] = peak[j].max(tau[j].abs());
            }
        }
        peak
    });
    let max_abs = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    (0..n)
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
        .collect()
}
