//! Milella's piece-wise identification trajectories: around each optimal point of a point
//! trajectory, a piece of the measured record whose widths to the left and to the right
//! are chosen by minimising the condition number of the extended regressor (eq. 15), so
//! that estimation uses thousands of samples near the optimal points instead of the points
//! alone (docs/experiments.md#piece-wise-identification).
//!
//! The decision variables are, for every interior point `i`, the widths to its left and to
//! its right as fractions `f` of the neighbouring interval, `f = minimum + (0.5 - minimum)
//! sin^2 x`, so every piece stays within its half-intervals (pieces never overlap) and at
//! least `minimum` wide whatever `x`. The extended regressor stacks the rows at the point and
//! at `around` equally spaced samples on each side within its widths (eq. 14); a Nelder-Mead
//! search minimises its condition number.
//!
//! ## Reference
//! F. Milella, "Direct Estimate of Closed-Form Dynamic Equation Parameters of a Robot:
//! Tools and Methods for Designing Experiments", Phase III, eqs. 13-15 (COMAU SMART 3S: 3070
//! samples for axis 1 with the condition number going from 64 to 66.3).

use crate::Model;
use crate::error::{Error, Result};
use crate::excite::{Information, Points};
use crate::nelder_mead::NelderMead;

/// Settings of the piece widths' search.
#[derive(Debug, Clone, PartialEq)]
pub struct PieceDesign {
    /// Samples of the extended regressor on each side of a point.
    pub around: usize,
    /// Smallest width on each side, as a fraction of the neighbouring interval (0 to 0.5).
    pub minimum: f64,
    /// Largest number of evaluations of the condition number.
    pub evaluations: usize,
}

impl Default for PieceDesign {
    fn default() -> Self {
        Self {
            around: 4,
            minimum: 0.1,
            evaluations: 4000,
        }
    }
}

/// The pieces around the interior points of a point trajectory.
#[derive(Debug, Clone, PartialEq)]
pub struct Pieces {
    /// `[start, end]` of each piece in seconds from the trajectory's start, in time order.
    pub windows: Vec<[f64; 2]>,
    /// Condition number of the extended regressor with the chosen widths.
    pub condition_number: f64,
    /// The same with every width at `minimum` (the search's baseline).
    pub initial_condition_number: f64,
}

impl Pieces {
    /// The share of a trajectory of `duration` seconds the pieces cover.
    pub fn coverage(&self, duration: f64) -> f64 {
        self.windows.iter().map(|w| w[1] - w[0]).sum::<f64>() / duration
    }
}

impl PieceDesign {
    /// Checks the settings.
    pub fn check(&self) -> Result<()> {
        if !(self.minimum >= 0.0 && self.minimum <= 0.5) {
            return Err(Error::setting(
                "PieceDesign",
                "minimum",
                format!(
                    "{} must lie in [0, 0.5] (a fraction of the interval)",
                    self.minimum
                ),
            ));
        }
        if self.around == 0 || self.around > 1000 {
            return Err(Error::setting(
                "PieceDesign",
                "around",
                format!("{} must lie in 1..=1000", self.around),
            ));
        }
        if self.evaluations == 0 {
            return Err(Error::setting(
                "PieceDesign",
                "evaluations",
                "give at least one evaluation".to_owned(),
            ));
        }
        Ok(())
    }

    /// The widths minimising the condition number of the extended regressor of `points`.
    pub fn optimise<M: Model + ?Sized>(&self, model: &M, points: &Points) -> Result<Pieces> {
        self.check()?;
        if points.dof() != model.dof() {
            return Err(Error::DimensionMismatch {
                what: "point trajectory joints".into(),
                expected: model.dof(),
                found: points.dof(),
            });
        }
        let interior = points.times.len().saturating_sub(2);
        if interior == 0 {
            return Err(Error::setting(
                "PieceDesign",
                "points",
                "the trajectory has no interior point to build pieces around; use at least two \
                 intervals"
                    .to_owned(),
            ));
        }
        let condition = |x: &[f64]| self.condition(model, points, &self.windows(points, x));
        let start = vec![0.0; 2 * interior];
        let initial = condition(&start);
        let search = NelderMead {
            max_evaluations: self.evaluations,
            step: vec![0.5],
            ..NelderMead::default()
        };
        let best = search.minimize(&start, condition)?;
        let (x, cond) = if best.value < initial {
            (best.x, best.value)
        } else {
            (start, initial)
        };
        if !cond.is_finite() {
            return Err(Error::NonFiniteResult {
                what: "the condition number of the extended regressor".into(),
                cause: "the points do not excite every base parameter; design them again with \
                        more intervals"
                    .into(),
            });
        }
        Ok(Pieces {
            windows: self.windows(points, &x),
            condition_number: cond,
            initial_condition_number: initial,
        })
    }

    /// The pieces of decision variables `x` (left and right of each interior point).
    fn windows(&self, points: &Points, x: &[f64]) -> Vec<[f64; 2]> {
        let t = &points.times;
        let fraction = |v: f64| self.minimum + (0.5 - self.minimum) * v.sin().powi(2);
        (1..t.len() - 1)
            .map(|i| {
                let (left, right) = (fraction(x[2 * (i - 1)]), fraction(x[2 * (i - 1) + 1]));
                [
                    t[i] - left * (t[i] - t[i - 1]),
                    t[i] + right * (t[i + 1] - t[i]),
                ]
            })
            .collect()
    }

    /// cond of the extended regressor on `windows` (infinite when a model call fails).
    fn condition<M: Model + ?Sized>(
        &self,
        model: &M,
        points: &Points,
        windows: &[[f64; 2]],
    ) -> f64 {
        let n = model.dof();
        let (mut q, mut qd, mut qdd) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        let mut info = Information::new(model);
        let a = self.around as f64;
        for (i, w) in windows.iter().enumerate() {
            let centre = points.times[i + 1];
            let samples = (0..self.around)
                .map(|k| centre - (centre - w[0]) * (k + 1) as f64 / a)
                .chain(std::iter::once(centre))
                .chain((0..self.around).map(|k| centre + (w[1] - centre) * (k + 1) as f64 / a));
            for t in samples {
                points.state(t, &mut q, &mut qd, &mut qdd);
                if info.add(model, &q, &qd, &qdd).is_err() {
                    return f64::INFINITY;
                }
            }
        }
        info.condition_number()
    }
}
