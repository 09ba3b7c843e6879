//! Point-based trajectories (Milella): knot states (position, velocity, acceleration,
//! jerk) at given times joined by seventh-order polynomials, so that position, velocity,
//! acceleration and jerk are continuous everywhere.
//!
//! ## Reference
//! F. Milella, "Direct Estimate of Closed-Form Dynamic Equation Parameters of a Robot:
//! Tools and Methods for Designing Experiments" (docs/references.md#milella), Phase III.

use crate::DataError;
use crate::error::{Error, Result};
use crate::excite::fourier::sample_count;
use crate::excite::polynomial::{Knot, Septic};
use crate::simulate::Trajectory;

/// A trajectory through knot states, one septic segment per joint and interval.
#[derive(Debug, Clone, PartialEq)]
pub struct Points {
    /// Knot times (s), increasing, starting at 0.
    pub times: Vec<f64>,
    /// Knot states per joint: `knots[j][i]` = (q, qd, qdd, jerk) of joint j at `times[i]`.
    pub knots: Vec<Vec<Knot>>,
    segments: Vec<Vec<Septic>>,
}

impl Points {
    /// The trajectory through `knots` (per joint, one state per time) at `times`.
    ///
    /// # Errors
    /// [`Error::Setting`] for times that do not start at 0 and increase (finite), for an
    /// interval [`Septic::new`] refuses (narrower than about 1e-102 s) or a knot state
    /// that is not finite; [`DataError::JointCountMismatch`] for a joint whose knots do
    /// not match the times in number.
    pub fn new(times: Vec<f64>, knots: Vec<Vec<Knot>>) -> Result<Self> {
        if times.len() < 2
            || times[0] != 0.0
            || times.windows(2).any(|w| w[1] <= w[0] || !w[1].is_finite())
        {
            return Err(Error::setting(
                "Points::new",
                "times",
                "they must start at 0 and increase, finite, with at least two points",
            ));
        }
        if let Some(bad) = knots.iter().position(|k| k.len() != times.len()) {
            return Err(Error::Data(DataError::JointCountMismatch {
                context: format!("points of joint {}", bad + 1),
                expected: times.len(),
                found: knots[bad].len(),
            }));
        }
        if knots.iter().flatten().flatten().any(|x| !x.is_finite()) {
            return Err(Error::setting(
                "Points::new",
                "knots",
                "a knot state is not finite",
            ));
        }
        let segments = knots
            .iter()
            .map(|k| {
                k.windows(2)
                    .zip(times.windows(2))
                    .map(|(k, t)| Septic::new(k[0], k[1], t[1] - t[0]))
                    .collect()
            })
            .collect::<Result<_>>()?;
        Ok(Self {
            times,
            knots,
            segments,
        })
    }

    /// Number of joints.
    pub fn dof(&self) -> usize {
        self.knots.len()
    }

    /// The time of the last knot (s).
    pub fn duration(&self) -> f64 {
        self.times[self.times.len() - 1]
    }

    /// (q, qd, qdd, jerk) of joint `j` at time t (held at the end states outside the range).
    pub fn eval(&self, j: usize, t: f64) -> Knot {
        let last = self.times.len() - 1;
        if t <= 0.0 {
            return self.knots[j][0];
        }
        if t >= self.times[last] {
            return self.knots[j][last];
        }
        let i = self.times.partition_point(|&x| x <= t) - 1;
        self.segments[j][i].eval(t - self.times[i])
    }

    /// Writes (q, qd, qdd) of every joint at time t.
    pub fn state(&self, t: f64, q: &mut [f64], qd: &mut [f64], qdd: &mut [f64]) {
        for j in 0..self.dof() {
            let [p, v, a, _] = self.eval(j, t);
            [q[j], qd[j], qdd[j]] = [p, v, a];
        }
    }

    /// Samples the whole trajectory at `rate` Hz (t = 0, 1/rate, ..., duration inclusive);
    /// a duration that is no whole number of sample periods 1 / rate is an error.
    pub fn sample(&self, rate: f64) -> Result<Trajectory> {
        let count = sample_count("Points::sample", self.duration(), rate, self.dof())?;
        let t: Vec<f64> = (0..count)
            .map(|k| (k as f64 / rate).min(self.duration()))
            .collect();
        let mut tr = Trajectory::zeros(self.dof(), t);
        for j in 0..self.dof() {
            for k in 0..count {
                let [p, v, a, _] = self.eval(j, tr.t[k]);
                [tr.q[j][k], tr.qd[j][k], tr.qdd[j][k]] = [p, v, a];
            }
        }
        tr.check_finite("Points::sample")?;
        Ok(tr)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn passes_through_its_knots_with_continuous_jerk() {
        let knots = vec![vec![
            [0.1, 0.0, 0.0, 0.0],
            [0.8, 0.4, -1.0, 0.7],
            [-0.3, -0.2, 0.5, -0.4],
            [0.1, 0.0, 0.0, 0.0],
        ]];
        let p = Points::new(vec![0.0, 1.0, 2.5, 4.0], knots.clone()).unwrap();
        for (i, &t) in p.times.iter().enumerate() {
            for (got, want) in p.eval(0, t).iter().zip(&knots[0][i]) {
                assert!((got - want).abs() < 1e-9);
            }
        }
        // approaching each interior knot from both sides
        for &t in &p.times[1..3] {
            let (l, r) = (p.eval(0, t - 1e-7), p.eval(0, t + 1e-7));
            // continuous: the values 2e-7 s apart differ by 2e-7 times the next derivative
            // (measured at most 2.0e-7 for k < 3 and 4.2e-5 for the jerk)
            for k in 0..4 {
                let bound = if k < 3 { 4e-7 } else { 8.5e-5 };
                assert!((l[k] - r[k]).abs() < bound, "derivative {k} at {t}");
            }
        }
        let tr = p.sample(100.0).unwrap();
        assert_eq!(tr.samples(), 401);
        assert!((tr.q[0][400] - 0.1).abs() < 1e-12 && tr.qd[0][0] == 0.0);
        assert!(Points::new(vec![0.0, 0.0], vec![vec![[0.0; 4]; 2]]).is_err());
        assert!(Points::new(vec![0.0, 1.0], vec![vec![[0.0; 4]; 3]]).is_err());
    }

    /// An infinite time or an interval too narrow for its cube gave segments of NaN
    /// (review 147); both are refused.
    #[test]
    fn refuses_times_whose_segments_would_not_be_finite() {
        let knots = vec![vec![[0.0; 4], [1.0, 0.0, 0.0, 0.0], [0.0; 4]]];
        for times in [vec![0.0, 1.0, f64::INFINITY], vec![0.0, 1e-110, 1.0]] {
            let e = Points::new(times.clone(), knots.clone()).unwrap_err();
            assert!(
                e.to_string().contains("width") || e.to_string().contains("times"),
                "{times:?}: {e}"
            );
        }
    }
}
