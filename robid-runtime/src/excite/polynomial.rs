//! Seventh-order (septic) polynomials between two states: the interpolation of Milella.
//!
//! A segment of width T joins the knot states (q, qd, qdd, jerk) at u = 0 and at u = T. Eight
//! boundary values fix the eight coefficients, so consecutive segments that share a knot are
//! continuous in position, velocity, acceleration and jerk. With s = u / T:
//!   q(s) = c0 + c1 s + ... + c7 s^7,
//!   c0 = q_a, c1 = T qd_a, c2 = T^2 qdd_a / 2, c3 = T^3 j_a / 6,
//! and (c4..c7) = M^-1 r, where r holds the end conditions at s = 1 less the contribution of
//! c0..c3 and M the rows of d^k/ds^k [s^4..s^7] at s = 1 for k = 0..3.
//!
//! ## Reference
//! F. Milella, "Direct Estimate of Closed-Form Dynamic Equation Parameters of a Robot:
//! Tools and Methods for Designing Experiments" (docs/references.md#milella), Phase III:
//! interpolation with 7th-order polynomials (eqs. 10-11), jerk imposed at the points
//! (eq. 12); see also docs/experiments.md#interpolation-with-seventh-order-polynomials.

use crate::error::{Error, Result, num};

/// A state at a knot: position, velocity, acceleration and jerk.
pub type Knot = [f64; 4];

/// M^-1 for M = [[1,1,1,1],[4,5,6,7],[12,20,30,42],[24,60,120,210]].
const INVERSE: [[f64; 4]; 4] = [
    [35.0, -15.0, 2.5, -1.0 / 6.0],
    [-84.0, 39.0, -7.0, 0.5],
    [70.0, -34.0, 6.5, -0.5],
    [-20.0, 10.0, -2.0, 1.0 / 6.0],
];

/// One septic segment of width `width` (in normalised time s = u / width).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Septic {
    /// Coefficients c0..c7 of q(s).
    pub c: [f64; 8],
    /// Width T (s).
    pub width: f64,
}

impl Septic {
    /// The segment from state `a` at u = 0 to state `b` at u = `width`.
    ///
    /// # Errors
    /// [`Error::Setting`] when `width` is not positive or its cube is not a normal
    /// number (a width outside about 1e-102..1e102 s, NaN or infinite): the coefficients
    /// and [`Septic::eval`] divide by powers of it and would be NaN or infinite.
    pub fn new(a: Knot, b: Knot, width: f64) -> Result<Self> {
        let t = width;
        let (t2, t3) = (t * t, t * t * t);
        if !(t > 0.0 && t3.is_normal()) {
            return Err(Error::setting(
                "Septic::new",
                "width",
                format!(
                    "{} s must be positive and finite, its cube a normal number (about 1e-102 to 1e102 s)",
                    num(width)
                ),
            ));
        }
        let c0 = a[0];
        let c1 = t * a[1];
        let c2 = t2 * a[2] / 2.0;
        let c3 = t3 * a[3] / 6.0;
        let r = [
            b[0] - (c0 + c1 + c2 + c3),
            t * b[1] - (c1 + 2.0 * c2 + 3.0 * c3),
            t2 * b[2] - (2.0 * c2 + 6.0 * c3),
            t3 * b[3] - 6.0 * c3,
        ];
        let mut c = [c0, c1, c2, c3, 0.0, 0.0, 0.0, 0.0];
        for (k, row) in INVERSE.iter().enumerate() {
            c[4 + k] = row.iter().zip(&r).map(|(m, r)| m * r).sum();
        }
        Ok(Self { c, width })
    }

    /// (q, qd, qdd, jerk) at u in [0, width] (seconds from the segment's start).
    pub fn eval(&self, u: f64) -> Knot {
        let s = u / self.width;
        let mut d = [0.0; 4];
        // Horner's rule for q and its first three derivatives in s.
        for k in (0..8).rev() {
            let c = self.c[k];
            d[3] = d[3] * s + d[2];
            d[2] = d[2] * s + d[1];
            d[1] = d[1] * s + d[0];
            d[0] = d[0] * s + c;
        }
        // d[k] = q^(k)(s) / k!, back to derivatives in u.
        let t = self.width;
        [
            d[0],
            d[1] / t,
            2.0 * d[2] / (t * t),
            6.0 * d[3] / (t * t * t),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn meets_both_end_states_and_its_derivatives_are_consistent() {
        let (a, b) = ([0.3, -1.2, 4.0, 10.0], [-0.7, 0.5, -2.0, -3.0]);
        let seg = Septic::new(a, b, 1.7).unwrap();
        for (got, want) in seg.eval(0.0).iter().zip(&a) {
            assert!((got - want).abs() < 1e-12, "{got} vs {want}");
        }
        for (got, want) in seg.eval(1.7).iter().zip(&b) {
            assert!((got - want).abs() < 1e-9, "{got} vs {want}");
        }
        let (u, h) = (0.63, 1e-5);
        let (p, m, mid) = (seg.eval(u + h), seg.eval(u - h), seg.eval(u));
        for k in 0..3 {
            let fd = (p[k] - m[k]) / (2.0 * h);
            // central differences, h = 1e-5: measured 6.4e-11, 3.8e-10 and 4.2e-10 relative
            assert!(
                (fd - mid[k + 1]).abs() < 8.5e-10 * (1.0 + fd.abs()),
                "{k}: {fd}"
            );
        }
    }

    #[test]
    fn consecutive_segments_are_continuous_up_to_jerk() {
        let knots = [
            [0.0, 0.0, 0.0, 0.0],
            [0.5, 0.3, -1.0, 2.0],
            [-0.2, -0.8, 0.4, -1.5],
        ];
        let first = Septic::new(knots[0], knots[1], 1.0).unwrap();
        let second = Septic::new(knots[1], knots[2], 2.5).unwrap();
        let (end, start) = (first.eval(1.0), second.eval(0.0));
        for k in 0..4 {
            assert!((end[k] - start[k]).abs() < 1e-9, "derivative {k}");
        }
    }

    /// A zero width gave a segment whose every value was NaN (review 147); widths that
    /// are not positive and finite, or whose cube leaves the normal range, are refused.
    #[test]
    fn refuses_a_width_that_is_not_positive_and_finite() {
        let b = [1.0, 0.0, 0.0, 0.0];
        for w in [0.0, -1.0, f64::NAN, f64::INFINITY, 1e-200, 1e200] {
            let e = Septic::new([0.0; 4], b, w).unwrap_err().to_string();
            assert!(e.contains("width"), "{w}: {e}");
        }
        let seg = Septic::new([0.0; 4], b, 1e-100).unwrap();
        assert!(seg.eval(0.5e-100).iter().all(|x| x.is_finite()));
    }
}
