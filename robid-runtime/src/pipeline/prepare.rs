//! Signal preparation: sample range, zero-phase low-pass, velocities and accelerations,
//! rotor-dynamics compensation, trimming.
//!
//! Edges: a log may start or end during motion. The low-pass pads each signal with an
//! odd extension as long as the filter's settling time (not scipy's few samples), so the
//! start-up transient dies out in the padding; what is left near an edge (the extension
//! bends the signal's curvature, which two differentiations amplify) is removed by an
//! automatic trim of one settling time at each real end of the record, on top of
//! `processing.trim`.

use rayon::prelude::*;

use crate::data::{Config, Dataset, Derivative, Signal};
use crate::error::{Error, Result};
use crate::signal::{Sos, butterworth_hz, central_difference};

/// Joint signals ready for the regressor, one vector per joint, all the same length.
#[derive(Debug, Clone)]
pub struct Prepared {
    /// Positions.
    pub q: Vec<Vec<f64>>,
    /// Velocities.
    pub qd: Vec<Vec<f64>>,
    /// Accelerations.
    pub qdd: Vec<Vec<f64>>,
    /// Joint torques (rotor-compensated when configured).
    pub tau: Vec<Vec<f64>>,
    /// Sample time (s).
    pub sample_time: f64,
}

impl Prepared {
    /// Number of samples.
    pub fn samples(&self) -> usize {
        self.q.first().map_or(0, Vec::len)
    }
}

/// Share of the impulse response's absolute sum left after the padding's length.
const PADDING_TOLERANCE: f64 = 1e-4;
/// Share of the impulse response's absolute sum left after the automatic trim (the main
/// lobe of the response: where the bent curvature of the extension still shows in qdd).
const SETTLING_TOLERANCE: f64 = 1e-1;

fn filter_all(sos: Option<&Sos>, pad: usize, x: &[Vec<f64>]) -> Result<Vec<Vec<f64>>> {
    match sos {
        Some(s) => x.par_iter().map(|v| s.filtfilt_padded(v, pad)).collect(),
        None => Ok(x.to_vec()),
    }
}

/// Samples dropped automatically at each real end of a record: one settling time of the
/// low-pass (0 without one).
pub fn automatic_trim(config: &Config, sample_time: f64) -> Result<usize> {
    match &config.processing.lowpass {
        Some(lp) => Ok(butterworth_hz(lp.order, lp.cutoff, 1.0 / sample_time)?
            .settling_samples(SETTLING_TOLERANCE, 1 << 20)),
        None => Ok(0),
    }
}

fn differentiate(x: &[Vec<f64>], dt: f64) -> Vec<Vec<f64>> {
    x.par_iter().map(|v| central_difference(v, dt)).collect()
}

/// Applies the `[processing]` options (range, low-pass, derivatives, trim) and the
/// rotor compensation of `[drive.rotor]` to a data set.
pub fn prepare(data: &Dataset, config: &Config) -> Result<Prepared> {
    let p = &config.processing;
    let dt = data.sample_time;
    let sos = match &p.lowpass {
        Some(lp) => Some(
            butterworth_hz(lp.order, lp.cutoff, 1.0 / dt).map_err(|e| match e {
                Error::InvalidConfig { problem, .. } => Error::InvalidConfig {
                    key: "processing.lowpass".into(),
                    problem,
                },
                e => e,
            })?,
        ),
        None => None,
    };
    let (pad, settle) = match &sos {
        Some(s) => (
            s.settling_samples(PADDING_TOLERANCE, 1 << 20),
            s.settling_samples(SETTLING_TOLERANCE, 1 << 20),
        ),
        None => (0, 0),
    };
    let on = |s: Signal| {
        sos.as_ref()
            .filter(|_| p.lowpass.as_ref().is_some_and(|lp| lp.signals.contains(&s)))
    };
    let q = filter_all(on(Signal::Q), pad, &data.q)?;
    let qd = match (p.velocity, &data.qd) {
        (Derivative::Auto | Derivative::Data, Some(v)) => filter_all(on(Signal::Qd), pad, v)?,
        (Derivative::Data, None) => return Err(missing("processing.velocity", "velocity")),
        _ => differentiate(&q, dt),
    };
    let qdd = match (p.acceleration, &data.qdd) {
        (Derivative::Auto | Derivative::Data, Some(a)) => filter_all(on(Signal::Qdd), pad, a)?,
        (Derivative::Data, None) => return Err(missing("processing.acceleration", "acceleration")),
        _ => differentiate(&qd, dt),
    };
    let mut tau = filter_all(on(Signal::Tau), pad, &data.tau)?;
    if let Some(rotor) = &config.drive.rotor {
        let motor = data
            .motor
            .as_ref()
            .ok_or_else(|| missing("drive.rotor", "motor_position"))?;
        let theta = filter_all(on(Signal::Q), pad, motor)?;
        let thetad = differentiate(&theta, dt);
        let thetadd = differentiate(&thetad, dt);
        rotor.compensate(&mut tau, &thetad, &thetadd)?;
    }
    // the range is cut after filtering and differentiation, so that its ends are free of
    // filter start-up transients (a split of one record into training and test data)
    let (lo, hi) = match p.range {
        Some([a, b]) if a < b && a < data.samples() => (a, b.min(data.samples())),
        Some([a, b]) => {
            return Err(Error::TooFewSamples {
                context: format!("{} rows {a}..{b}", data.name),
                found: 0,
                required: 1,
                hint: "choose processing.range inside the data",
            });
        }
        None => (0, data.samples()),
    };
    // processing.trim inside the range, and at least one settling time from the record's
    // real ends (where the filter saw no data)
    let t = p.trim;
    let total = data.samples();
    let start = (lo + t).max(settle);
    let end = hi.saturating_sub(t).min(total.saturating_sub(settle));
    if end <= start + 1 {
        return Err(Error::TooFewSamples {
            context: format!(
                "{} after trimming {t} samples at each end ({settle} at the record's ends for the low-pass to settle)",
                data.name
            ),
            found: end.saturating_sub(start),
            required: 2,
            hint: "reduce processing.trim, raise the low-pass cutoff or use a longer record",
        });
    }
    let cut = |v: Vec<Vec<f64>>| -> Vec<Vec<f64>> {
        v.into_iter().map(|x| x[start..end].to_vec()).collect()
    };
    Ok(Prepared {
        q: cut(q),
        qd: cut(qd),
        qdd: cut(qdd),
        tau: cut(tau),
        sample_time: dt,
    })
}

fn missing(key: &str, role: &str) -> Error {
    Error::InvalidConfig {
        key: key.into(),
        problem: format!(
            "the data has no `{role}` columns; add them to a [[source]] or let robid differentiate (\"auto\")"
        ),
    }
}
