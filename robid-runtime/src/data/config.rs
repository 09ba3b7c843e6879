//! The identification config file (TOML): column mapping, units, drive chain, extra
//! regressor columns, processing and estimation options.
//!
//! ```toml
//! dof = 6
//! sample_rate = 5000.0          # Hz; or time_column = "t" (time_scale = 1e-3 for ms)
//!
//! [[source]]                     # one table per file, in the order the files are given
//! file = "data/pos.csv.gz"       # optional, relative to the config file
//! position = "Joint_{}"          # "{}" = joint number 1..dof, or a list of names
//! [[source]]
//! file = "data/cur.csv.gz"
//! torque = ["Joint_1", "Joint_2", "Joint_3", "Joint_4", "Joint_5", "Joint_6"]
//! # also: velocity, acceleration, motor_position (motor encoder for rotor compensation)
//!
//! [units]
//! angle = "rad"                  # or "deg": positions, velocities, accelerations
//! torque_scale = 1.0             # number or one per joint
//!
//! [drive]                        # see `DriveConfig`
//! [[extra_column]]               # see `ExtraColumn`
//!
//! [processing]
//! lowpass = { cutoff = 25.0, order = 4, signals = ["q"] }   # Hz, zero-phase Butterworth
//! velocity = "auto"              # "data", "differentiate" or "auto" (data when given)
//! acceleration = "auto"
//! trim = 20                      # samples dropped at each end after differentiation
//! decimation = 100               # total factor (stages of <= 10) or a list [10, 10]
//! rest_velocity = 0.05           # rad/s, number or one per joint
//! range = [0, 24750]             # optional sample range used (end exclusive)
//!
//! [estimation]
//! method = "wls"                 # "ols", "wls", "rls" or "energy"
//! rank_tolerance = 1e-10         # singular values below this times the largest are zero
//! forgetting = 1.0               # RLS forgetting factor, 0 < lambda <= 1
//! energy_window = 0.05           # s, one energy-model equation per window
//! ```

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::drive::{DriveConfig, ExtraColumn};
use crate::error::{Error, Result};

/// The whole config file. `Config::default()` equals the config of an empty file.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Config {
    /// Number of joints (checked against the model and the columns).
    pub dof: Option<usize>,
    /// Sample rate in Hz when there is no time column.
    pub sample_rate: Option<f64>,
    /// Name of the time column (in seconds unless `time_scale` says otherwise).
    pub time_column: Option<String>,
    /// Factor from the time column's unit to seconds.
    #[serde(default = "one")]
    pub time_scale: f64,
    /// Files and their columns.
    #[serde(default, rename = "source")]
    pub sources: Vec<Source>,
    /// Units of the raw columns.
    #[serde(default)]
    pub units: Units,
    /// Gear ratios, couplings, torque constants, rotor compensation.
    #[serde(default)]
    pub drive: DriveConfig,
    /// Extra regressor columns that are not in the symbolic model.
    #[serde(default, rename = "extra_column")]
    pub extra_columns: Vec<ExtraColumn>,
    /// Filtering, differentiation, decimation and sample selection.
    #[serde(default)]
    pub processing: Processing,
    /// Estimator options.
    #[serde(default)]
    pub estimation: Estimation,
    /// Folder that relative `file` paths are resolved against (the config file's folder).
    #[serde(skip)]
    pub base_dir: Option<PathBuf>,
}

impl Default for Config {
    /// The same values as an empty config file (serde's defaults): `time_scale = 1`.
    fn default() -> Self {
        Self {
            dof: None,
            sample_rate: None,
            time_column: None,
            time_scale: one(),
            sources: Vec::new(),
            units: Units::default(),
            drive: DriveConfig::default(),
            extra_columns: Vec::new(),
            processing: Processing::default(),
            estimation: Estimation::default(),
            base_dir: None,
        }
    }
}

/// One data file and the roles of its columns.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Source {
    /// The file (CSV, optionally gzip-compressed); relative to the config file.
    pub file: Option<PathBuf>,
    /// Joint (or motor, see `drive.position_side`) positions.
    pub position: Option<Columns>,
    /// Joint velocities.
    pub velocity: Option<Columns>,
    /// Joint accelerations.
    pub acceleration: Option<Columns>,
    /// Torques (or currents, see `units.torque_scale` and `drive.torque_constants`).
    pub torque: Option<Columns>,
    /// Motor-side encoder positions, for rotor-dynamics compensation.
    pub motor_position: Option<Columns>,
}

/// Column names for one signal: a template with `{}` for the joint number, or a list.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum Columns {
    /// e.g. `"q{}"` -> q1, q2, ...
    Template(String),
    /// One name per joint.
    List(Vec<String>),
}

impl Columns {
    /// The column names for `dof` joints.
    pub fn names(&self, dof: usize) -> Vec<String> {
        match self {
            Columns::Template(t) if t.contains("{}") => {
                (1..=dof).map(|j| t.replace("{}", &j.to_string())).collect()
            }
            Columns::Template(t) => vec![t.clone()],
            Columns::List(v) => v.clone(),
        }
    }
}

/// A number for all joints or one per joint.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum PerJoint {
    /// The same value for every joint.
    All(f64),
    /// One value per joint.
    Each(Vec<f64>),
}

impl PerJoint {
    /// One value per joint; `key` names the config entry in the error.
    pub fn values(&self, dof: usize, key: &str) -> Result<Vec<f64>> {
        let v = match self {
            PerJoint::All(x) => vec![*x; dof],
            PerJoint::Each(v) if v.len() == dof => v.clone(),
            PerJoint::Each(v) => {
                return Err(Error::JointCountMismatch {
                    context: format!("config `{key}`"),
                    expected: dof,
                    found: v.len(),
                });
            }
        };
        if let Some(x) = v.iter().find(|x| !x.is_finite()) {
            return Err(Error::InvalidConfig {
                key: key.into(),
                problem: format!("{x} is not a finite number"),
            });
        }
        Ok(v)
    }
}

/// Angle unit of the position, velocity and acceleration columns.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum AngleUnit {
    /// Radians.
    #[default]
    Rad,
    /// Degrees.
    Deg,
}

/// Units of the raw columns.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Units {
    /// Angle unit.
    #[serde(default)]
    pub angle: AngleUnit,
    /// Factor applied to the torque columns (e.g. to N m from mN m).
    pub torque_scale: Option<PerJoint>,
}

/// Which signal a low-pass filter is applied to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Signal {
    /// Positions (and motor positions).
    Q,
    /// Velocities from the data.
    Qd,
    /// Accelerations from the data.
    Qdd,
    /// Torques.
    Tau,
}

/// Zero-phase Butterworth low-pass.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Lowpass {
    /// Cutoff in Hz.
    pub cutoff: f64,
    /// Filter order (applied twice by the forward-backward pass).
    #[serde(default = "four")]
    pub order: usize,
    /// Signals filtered.
    #[serde(default = "default_signals")]
    pub signals: Vec<Signal>,
}

/// Where velocities or accelerations come from.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Derivative {
    /// From the data when given, else by central differences.
    #[default]
    Auto,
    /// From the data (an error if missing).
    Data,
    /// Central differences of the (filtered) lower derivative.
    Differentiate,
}

/// A total decimation factor or explicit stages.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum Decimation {
    /// Total factor, split into stages of at most 10.
    Total(usize),
    /// Explicit stages.
    Stages(Vec<usize>),
}

impl Default for Decimation {
    fn default() -> Self {
        Decimation::Total(1)
    }
}

/// Processing options.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Processing {
    /// Low-pass filter (none when absent).
    pub lowpass: Option<Lowpass>,
    /// Velocity source.
    #[serde(default)]
    pub velocity: Derivative,
    /// Acceleration source.
    #[serde(default)]
    pub acceleration: Derivative,
    /// Samples dropped at each end after filtering and differentiation.
    #[serde(default)]
    pub trim: usize,
    /// Low-pass + decimation of every regressor column and of the torque.
    #[serde(default)]
    pub decimation: Decimation,
    /// Equations of joint j are dropped where |qd_j| is below this (rad/s).
    pub rest_velocity: Option<PerJoint>,
    /// Sample range used, `[start, end)`, cut after filtering and differentiation (so a
    /// split of one record has no filter transients at its ends), before `trim`.
    pub range: Option<[usize; 2]>,
}

/// Estimation method of the pipeline.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Method {
    /// Ordinary least squares.
    #[default]
    Ols,
    /// Weighted least squares, weights from the OLS residuals per joint.
    Wls,
    /// Recursive least squares with forgetting factor.
    Rls,
    /// The energy (power balance) model: one equation per window of
    /// `estimation.energy_window` seconds, no accelerations needed.
    Energy,
}

/// Estimator options.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Estimation {
    /// Method.
    #[serde(default)]
    pub method: Method,
    /// Relative singular-value threshold for the rank decision.
    #[serde(default = "default_tolerance")]
    pub rank_tolerance: f64,
    /// RLS forgetting factor.
    #[serde(default = "one")]
    pub forgetting: f64,
    /// Window of the energy model (s): one equation per window.
    #[serde(default = "default_energy_window")]
    pub energy_window: f64,
}

impl Default for Estimation {
    fn default() -> Self {
        Self {
            method: Method::Ols,
            rank_tolerance: default_tolerance(),
            forgetting: 1.0,
            energy_window: default_energy_window(),
        }
    }
}

fn one() -> f64 {
    1.0
}
fn four() -> usize {
    4
}
fn default_energy_window() -> f64 {
    0.05
}
fn default_tolerance() -> f64 {
    1e-10
}
fn default_signals() -> Vec<Signal> {
    vec![Signal::Q]
}

impl Config {
    /// Parses a config from TOML text; `base_dir` resolves relative file paths.
    pub fn from_toml_str(text: &str, path: &Path) -> Result<Self> {
        let mut cfg: Config = toml::from_str(text).map_err(|e| Error::ConfigSyntax {
            path: path.to_path_buf(),
            reason: e.to_string(),
        })?;
        cfg.base_dir = path.parent().map(Path::to_path_buf);
        Ok(cfg)
    }

    /// Reads and parses a config file.
    pub fn from_file(path: impl AsRef<Path>) -> Result<Self> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path).map_err(|source| Error::Io {
            path: path.to_path_buf(),
            source,
        })?;
        Self::from_toml_str(&text, path)
    }

    /// Resolves a path from the config against its folder.
    pub fn resolve(&self, file: &Path) -> PathBuf {
        match &self.base_dir {
            Some(dir) if file.is_relative() => dir.join(file),
            _ => file.to_path_buf(),
        }
    }

    /// Checks value ranges that serde cannot; `dof` is the model's joint count.
    pub fn check(&self, dof: usize) -> Result<()> {
        if let Some(n) = self.dof
            && n != dof
        {
            return Err(Error::JointCountMismatch {
                context: "config `dof`".into(),
                expected: dof,
                found: n,
            });
        }
        if let Some(fs) = self.sample_rate
            && !(fs > 0.0 && fs.is_finite())
        {
            return Err(invalid("sample_rate", format!("{fs} Hz must be positive")));
        }
        if !(self.time_scale > 0.0 && self.time_scale.is_finite()) {
            return Err(invalid("time_scale", "must be positive".into()));
        }
        if let Some(lp) = &self.processing.lowpass
            && !(lp.cutoff > 0.0 && lp.cutoff.is_finite())
        {
            return Err(invalid(
                "processing.lowpass.cutoff",
                format!("{} Hz must be positive", lp.cutoff),
            ));
        }
        if let Some(r) = &self.processing.rest_velocity {
            r.values(dof, "processing.rest_velocity")?;
        }
        if let Some([a, b]) = self.processing.range
            && a >= b
        {
            return Err(invalid(
                "processing.range",
                format!("[{a}, {b}] is empty; write [start, end] with start < end"),
            ));
        }
        let e = &self.estimation;
        if !(e.forgetting > 0.0 && e.forgetting <= 1.0) {
            return Err(invalid(
                "estimation.forgetting",
                format!("{} must satisfy 0 < lambda <= 1", e.forgetting),
            ));
        }
        if !(e.energy_window > 0.0 && e.energy_window.is_finite()) {
            return Err(invalid(
                "estimation.energy_window",
                format!("{} s must be positive", e.energy_window),
            ));
        }
        if !(e.rank_tolerance > 0.0 && e.rank_tolerance < 1.0) {
            return Err(invalid(
                "estimation.rank_tolerance",
                format!("{} must lie in (0, 1)", e.rank_tolerance),
            ));
        }
        self.drive.check(dof)?;
        for c in &self.extra_columns {
            c.check(dof)?;
        }
        Ok(())
    }
}

fn invalid(key: &str, problem: String) -> Error {
    Error::InvalidConfig {
        key: key.into(),
        problem,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const EXAMPLE: &str = r#"
dof = 2
sample_rate = 100.0
[[source]]
position = "q{}"
torque = ["t1", "t2"]
[units]
angle = "deg"
torque_scale = [1.0, 2.0]
[processing]
lowpass = { cutoff = 5.0 }
decimation = [2, 2]
rest_velocity = 0.1
[estimation]
method = "wls"
"#;

    #[test]
    fn parses_the_documented_format() {
        let cfg = Config::from_toml_str(EXAMPLE, Path::new("/x/cfg.toml")).unwrap();
        cfg.check(2).unwrap();
        assert_eq!(
            cfg.sources[0].position.as_ref().unwrap().names(2),
            vec!["q1", "q2"]
        );
        assert_eq!(cfg.units.angle, AngleUnit::Deg);
        assert_eq!(cfg.processing.lowpass.as_ref().unwrap().order, 4);
        assert_eq!(cfg.processing.decimation, Decimation::Stages(vec![2, 2]));
        assert_eq!(cfg.estimation.method, Method::Wls);
        assert_eq!(cfg.resolve(Path::new("a.csv")), PathBuf::from("/x/a.csv"));
    }

    #[test]
    fn default_equals_an_empty_file() {
        let empty = Config::from_toml_str("", Path::new("empty.toml")).unwrap();
        let default = Config::default();
        assert_eq!(default.time_scale, 1.0);
        assert_eq!(
            serde_json::to_string(&default).unwrap(),
            serde_json::to_string(&empty).unwrap()
        );
        default.check(6).unwrap();
    }

    #[test]
    fn syntax_errors_name_the_file() {
        let err = Config::from_toml_str("dof = [", Path::new("bad.toml")).unwrap_err();
        assert!(err.to_string().starts_with("bad.toml"), "{err}");
        let err = Config::from_toml_str("colour = 1", Path::new("bad.toml")).unwrap_err();
        assert!(err.to_string().contains("colour"), "{err}");
    }

    #[test]
    fn range_checks() {
        let cfg = Config::from_toml_str(EXAMPLE, Path::new("c.toml")).unwrap();
        assert!(matches!(
            cfg.check(3),
            Err(Error::JointCountMismatch { .. })
        ));
        let bad = EXAMPLE.replace("method = \"wls\"", "forgetting = 1.5");
        let cfg = Config::from_toml_str(&bad, Path::new("c.toml")).unwrap();
        assert!(matches!(cfg.check(2), Err(Error::InvalidConfig { .. })));
        let bad = EXAMPLE.replace("rest_velocity = 0.1", "rest_velocity = [0.1]");
        let cfg = Config::from_toml_str(&bad, Path::new("c.toml")).unwrap();
        assert!(matches!(
            cfg.check(2),
            Err(Error::JointCountMismatch { .. })
        ));
    }
}
