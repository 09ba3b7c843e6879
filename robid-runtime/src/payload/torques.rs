//! A payload from joint torques with the robot's model known: the payload adds to the last
//! link's ten standard parameters, so with `tau_model` the model's torques (its base
//! parameters, drive terms included) and `Y_last` the last link's ten columns of the
//! standard regressor, `tau - tau_model(q, qd, qdd) = Y_last(q, qd, qdd) phi`.

use nalgebra::{DMatrix, DVector};

use super::{Payload, PayloadOptions, estimate};
use crate::Count;
use crate::error::{Error, Result};
use crate::model::{Inertial, Model};

/// One sample of the robot: joint positions, velocities, accelerations and the measured
/// torques, one entry per joint each.
#[derive(Debug, Clone, PartialEq)]
pub struct JointSample {
    /// Positions.
    pub q: Vec<f64>,
    /// Velocities.
    pub qd: Vec<f64>,
    /// Accelerations.
    pub qdd: Vec<f64>,
    /// Measured torques (with the payload on).
    pub tau: Vec<f64>,
}

/// Where the last link's `XXn .. Mn` sit in `model`'s standard parameters, in the
/// standard order; an error when the model has no such parameters.
pub fn last_link_columns(model: &dyn Model) -> Result<[usize; 10]> {
    let n = model.dof();
    let names = crate::model::standard_parameter_names(model);
    let mut out = [0; 10];
    for (slot, p) in out.iter_mut().zip(Inertial::ALL) {
        let name = format!("{}{n}", p.stem());
        *slot = names.iter().position(|s| *s == name).ok_or_else(|| {
            Error::setting(
                "payload::from_torques",
                "model",
                format!(
                    "the model `{}` has no standard parameter `{name}` (its last link's \
                     inertial parameters); describe the robot with its last link",
                    model.name()
                ),
            )
        })?;
    }
    Ok(out)
}

/// The payload on the last link of `model` whose torques `samples` record, `base` being
/// the model's base parameters without the payload (identified, or from a parameter file).
///
/// Rows are joint-major (every sample of joint 1, then joint 2 ...), so weighted least
/// squares weights each joint by its own noise. A sample with the wrong number of
/// entries is an error naming it; motion that does not excite the payload (a wrist that
/// does not turn, for one) is a rank-deficiency error naming the unexcited parameters.
///
/// ```
/// use robid_runtime::Model;
/// use robid_runtime::payload::{JointSample, PayloadOptions, Verdict, from_torques};
///
/// /// The payload's mass and its standard deviation, or why the data cannot give it.
/// fn payload_mass(
///     model: &dyn Model,
///     base: &[f64],
///     samples: &[JointSample],
/// ) -> robid_runtime::Result<(f64, f64)> {
///     let payload = from_torques(model, base, samples, &PayloadOptions::default())?;
///     let c = &payload.consistency;
///     match c.verdict() {
///         Verdict::Consistent => {}
///         Verdict::Inconsistent => eprintln!("no body: {}", c.problems.join("; ")),
///         Verdict::Undetermined => eprintln!("cannot tell: {}", c.undetermined.join("; ")),
///     }
///     Ok((payload.parameters()[9], payload.std()[9]))
/// }
/// ```
pub fn from_torques(
    model: &dyn Model,
    base: &[f64],
    samples: &[JointSample],
    options: &PayloadOptions,
) -> Result<Payload> {
    let columns = last_link_columns(model)?;
    let (dof, count) = (model.dof(), model.standard_parameter_count());
    let n = samples.len();
    let mut w = DMatrix::zeros(dof * n, 10);
    let mut y = DVector::zeros(dof * n);
    let mut regressor = vec![0.0; dof * count];
    let mut tau_model = vec![0.0; dof];
    for (k, s) in samples.iter().enumerate() {
        let at = |e: crate::model::LengthError| Error::DimensionMismatch {
            what: format!("payload sample {}: `{}`", k + 1, e.argument),
            expected: e.expected,
            found: e.found,
        };
        crate::model::check_length("tau", &s.tau, dof).map_err(at)?;
        model
            .standard_regressor_into(&s.q, &s.qd, &s.qdd, &mut regressor)
            .map_err(at)?;
        model
            .inverse_dynamics_into(&s.q, &s.qd, &s.qdd, base, &mut tau_model)
            .map_err(at)?;
        for j in 0..dof {
            let i = j * n + k;
            for (c, &col) in columns.iter().enumerate() {
                w[(i, c)] = regressor[j * count + col];
            }
            y[i] = s.tau[j] - tau_model[j];
        }
    }
    let groups = (0..dof).map(|j| j * n..(j + 1) * n).collect();
    let sample_of_row = (0..dof * n).map(|i| i % n.max(1)).collect();
    estimate(w, y, groups, sample_of_row, options, || {
        let rank = rank_of_torques(model, &columns)?;
        let fix = if rank == 10 {
            "use a richer trajectory: move the last joints through their range with varied \
             velocities and accelerations (robid excite designs one)"
                .to_owned()
        } else {
            format!(
                "the joint torques of `{}` ({}) determine at most {} of the ten whatever \
                 the motion, so no trajectory gives them all (and a payload has no parameter \
                 to leave out): measure the payload with a force-torque sensor at the wrist \
                 (`payload::from_wrenches` of the robid-runtime library takes its \
                 wrenches), or identify the robot \
                 with the payload on (robid identify), whose base parameters hold {}",
                model.name(),
                Count(dof, "joint"),
                Count(rank, "combination"),
                if rank == 1 { "it" } else { "them" }
            )
        };
        Ok((rank, fix))
    })
}

/// How many combinations of the payload's ten parameters (the last link's standard
/// parameters at `columns`) the joint torques of `model` determine under any motion: the
/// rank of their columns of the map from standard to base parameters (a direction of the
/// ten that no base parameter holds acts on no torque). Ten for a robot whose wrist turns
/// about three axes; three (`ZZ`, `MX`, `MY`) for one revolute joint under gravity across
/// its axis.
fn rank_of_torques(model: &dyn Model, columns: &[usize; 10]) -> Result<usize> {
    let (count, nb) = (
        model.standard_parameter_count(),
        model.base_parameter_count(),
    );
    let mut k = DMatrix::zeros(nb, 10);
    let mut standard = vec![0.0; count];
    let mut base = vec![0.0; nb];
    for (c, &col) in columns.iter().enumerate() {
        standard.fill(0.0);
        standard[col] = 1.0;
        model
            .base_from_standard_into(&standard, &mut base)
            .map_err(|e| Error::DimensionMismatch {
                what: format!("payload: `{}` of the base from standard map", e.argument),
                expected: e.expected,
                found: e.found,
            })?;
        k.column_mut(c).copy_from_slice(&base);
    }
    let s = k.singular_values();
    let largest = s.max();
    Ok(s.iter().filter(|&&v| v > 1e-9 * largest).count())
}
