//! A loaded, joint-side, uniformly sampled data set.

use crate::data::Warning;
use crate::error::{Error, Result};

/// Joint-side signals on a uniform time grid, one vector per joint.
#[derive(Debug, Clone)]
pub struct Dataset {
    /// Name for reports (usually the first file's name).
    pub name: String,
    /// Sample time in seconds.
    pub sample_time: f64,
    /// Joint positions (rad or m).
    pub q: Vec<Vec<f64>>,
    /// Joint velocities, when measured.
    pub qd: Option<Vec<Vec<f64>>>,
    /// Joint accelerations, when measured.
    pub qdd: Option<Vec<Vec<f64>>>,
    /// Joint torques (after torque constants and the drive chain).
    pub tau: Vec<Vec<f64>>,
    /// Motor encoder positions reflected to the link side, for rotor compensation.
    pub motor: Option<Vec<Vec<f64>>>,
    /// What was repaired while loading.
    pub warnings: Vec<super::Warning>,
}

impl Dataset {
    /// A data set from positions and torques (per joint, equal lengths, finite values).
    pub fn new(
        name: impl Into<String>,
        sample_time: f64,
        q: Vec<Vec<f64>>,
        tau: Vec<Vec<f64>>,
    ) -> Result<Self> {
        let name = name.into();
        if !(sample_time > 0.0 && sample_time.is_finite()) {
            return Err(Error::InvalidConfig {
                key: "sample_rate".into(),
                problem: format!("{name}: sample time {sample_time} s must be positive"),
            });
        }
        check_block(
            &name,
            "torque",
            &tau,
            q.len(),
            q.first().map_or(0, Vec::len),
        )?;
        check_block(
            &name,
            "position",
            &q,
            q.len(),
            q.first().map_or(0, Vec::len),
        )?;
        Ok(Self {
            name,
            sample_time,
            q,
            qd: None,
            qdd: None,
            tau,
            motor: None,
            warnings: Vec::<Warning>::new(),
        })
    }

    /// Adds measured velocities.
    pub fn with_velocities(mut self, qd: Vec<Vec<f64>>) -> Result<Self> {
        check_block(&self.name, "velocity", &qd, self.dof(), self.samples())?;
        self.qd = Some(qd);
        Ok(self)
    }

    /// Adds measured accelerations.
    pub fn with_accelerations(mut self, qdd: Vec<Vec<f64>>) -> Result<Self> {
        check_block(&self.name, "acceleration", &qdd, self.dof(), self.samples())?;
        self.qdd = Some(qdd);
        Ok(self)
    }

    /// Adds motor encoder positions (link side).
    pub fn with_motor_positions(mut self, motor: Vec<Vec<f64>>) -> Result<Self> {
        check_block(
            &self.name,
            "motor position",
            &motor,
            self.dof(),
            self.samples(),
        )?;
        self.motor = Some(motor);
        Ok(self)
    }

    /// Number of joints.
    pub fn dof(&self) -> usize {
        self.q.len()
    }

    /// Number of samples.
    pub fn samples(&self) -> usize {
        self.q.first().map_or(0, Vec::len)
    }

    /// The samples `start..end` (end clamped to the length).
    pub fn slice(&self, start: usize, end: usize) -> Result<Self> {
        let end = end.min(self.samples());
        if start >= end {
            return Err(Error::TooFewSamples {
                context: format!("{} rows {start}..{end}", self.name),
                found: 0,
                required: 1,
                hint: "choose a range inside the data",
            });
        }
        let cut = |v: &Vec<Vec<f64>>| v.iter().map(|x| x[start..end].to_vec()).collect::<Vec<_>>();
        Ok(Self {
            name: format!("{}[{start}..{end}]", self.name),
            sample_time: self.sample_time,
            q: cut(&self.q),
            qd: self.qd.as_ref().map(cut),
            qdd: self.qdd.as_ref().map(cut),
            tau: cut(&self.tau),
            motor: self.motor.as_ref().map(cut),
            warnings: self.warnings.clone(),
        })
    }
}

fn check_block(name: &str, what: &str, x: &[Vec<f64>], dof: usize, n: usize) -> Result<()> {
    if x.len() != dof {
        return Err(Error::JointCountMismatch {
            context: format!("{name}: {what} signals"),
            expected: dof,
            found: x.len(),
        });
    }
    for (j, v) in x.iter().enumerate() {
        if v.len() != n {
            return Err(Error::DimensionMismatch {
                what: format!("{name}: {what} of joint {}", j + 1),
                expected: n,
                found: v.len(),
            });
        }
        if let Some(k) = v.iter().position(|x| !x.is_finite()) {
            return Err(Error::NotFinite {
                path: name.into(),
                line: k as u64,
                column: format!("{what} {}", j + 1),
                value: v[k],
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn checks_shapes_and_values() {
        let d = Dataset::new("m", 0.01, vec![vec![0.0; 5]; 2], vec![vec![1.0; 5]; 2]).unwrap();
        assert_eq!((d.dof(), d.samples()), (2, 5));
        assert!(matches!(
            d.clone().with_velocities(vec![vec![0.0; 5]; 3]),
            Err(Error::JointCountMismatch { .. })
        ));
        assert!(matches!(
            d.clone().with_accelerations(vec![vec![0.0; 4]; 2]),
            Err(Error::DimensionMismatch { .. })
        ));
        assert!(matches!(
            Dataset::new("m", 0.01, vec![vec![f64::NAN]], vec![vec![0.0]]),
            Err(Error::NotFinite { .. })
        ));
        assert!(Dataset::new("m", 0.0, vec![vec![0.0]], vec![vec![0.0]]).is_err());
        let s = d.slice(1, 3).unwrap();
        assert_eq!(s.samples(), 2);
        assert!(d.slice(4, 2).is_err());
    }
}
