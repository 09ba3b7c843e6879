//! A payload from a wrist force-torque sensor: each sample gives six equations
//! `wrench = A(omega, omegadot, vdot, g) phi` ([`crate::wrench::wrench_matrix`]).

use nalgebra::{DMatrix, DVector};

use super::{Payload, PayloadOptions, estimate};
use crate::error::Result;
use crate::wrench::wrench_matrix;

/// One sample of the sensor with the motion of its frame, everything in the sensor
/// frame (the frame the payload's parameters are wanted in).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WrenchSample {
    /// Angular velocity, rad/s.
    pub omega: [f64; 3],
    /// Angular acceleration, rad/s^2.
    pub omegadot: [f64; 3],
    /// Acceleration of the frame origin, without gravity, m/s^2.
    pub vdot: [f64; 3],
    /// Gravity, m/s^2 (`R' (0, 0, -9.81)` with `R` the frame's orientation in the base).
    pub gravity: [f64; 3],
    /// The wrench the sensor applies to the payload: force (N), then moment about the
    /// frame origin (N m). A sensor that reports the payload's wrench on it gives the
    /// opposite sign; negate it first.
    pub wrench: [f64; 6],
}

/// The payload whose wrenches the samples record.
///
/// Rows are grouped forces first, then moments, so that weighted least squares weights
/// the two units by their own noise. Fewer than two samples, a sample that is not finite,
/// or motion that does not excite all ten parameters (a payload held still, for one,
/// shows only its mass and first moments) are errors.
///
/// ```
/// use robid_runtime::feasible::LinkInertial;
/// use robid_runtime::payload::{PayloadOptions, WrenchSample, from_wrenches};
/// use robid_runtime::rng::Rng;
/// use robid_runtime::wrench::{apply, wrench_matrix};
///
/// // A 1 kg tool, centre of mass 0.1 m out along z.
/// let inertia = [[0.002, 0.0, 0.0], [0.0, 0.003, 0.0], [0.0, 0.0, 0.004]];
/// let truth = LinkInertial { mass: 1.0, com: [0.0, 0.0, 0.1], inertia }.to_standard();
/// let mut rng = Rng::new(1);
/// let samples: Vec<WrenchSample> = (0..50)
///     .map(|_| {
///         let mut v = || [0; 3].map(|_| rng.uniform(-2.0, 2.0));
///         let (omega, omegadot, vdot, gravity) = (v(), v(), v(), [0.0, 0.0, -9.81]);
///         let a = wrench_matrix(&omega, &omegadot, &vdot, &gravity);
///         let wrench = apply(&a, &truth);
///         WrenchSample { omega, omegadot, vdot, gravity, wrench }
///     })
///     .collect();
/// let payload = from_wrenches(&samples, &PayloadOptions::default()).unwrap();
/// assert!((payload.consistency.mass - 1.0).abs() < 1e-9);
/// assert!(payload.consistency.is_consistent());
/// ```
pub fn from_wrenches(samples: &[WrenchSample], options: &PayloadOptions) -> Result<Payload> {
    let n = samples.len();
    let mut w = DMatrix::zeros(6 * n, 10);
    let mut y = DVector::zeros(6 * n);
    for (k, s) in samples.iter().enumerate() {
        let a = wrench_matrix(&s.omega, &s.omegadot, &s.vdot, &s.gravity);
        for (r, row) in a.iter().enumerate() {
            // Forces in rows 0..3n, moments in 3n..6n.
            let i = (r / 3) * 3 * n + 3 * k + r % 3;
            for (c, x) in row.iter().enumerate() {
                w[(i, c)] = *x;
            }
            y[i] = s.wrench[r];
        }
    }
    let sample_of_row = (0..6 * n).map(|i| (i % (3 * n)) / 3).collect();
    estimate(
        w,
        y,
        vec![0..3 * n, 3 * n..6 * n],
        sample_of_row,
        options,
        || {
            Ok((
                10,
                "use a richer motion of the sensor: turn it about every axis and accelerate \
                 it in every direction"
                    .to_owned(),
            ))
        },
    )
}
