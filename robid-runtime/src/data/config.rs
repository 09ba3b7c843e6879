//! The identification config file (TOML): column mapping, units, drive chain, extra
//! regressor columns, processing and estimation options.
//!
//! ```toml
//! dof = 6
//! sample_rate = 5000.0          # Hz; or time_column = "t" (time_scale = 1e-3 for ms)
//!
//! [[source]]                     # one table per file, in the order the files are given
//! file = "data/pos.csv.gz"       # optional, relative to the config file
//! position = "Joint_{}"          # "{}" = joint number 1..dof ("{0}": 0..dof-1), or a list
//! [[source]]
//! file = "data/cur.csv.gz"
//! torque = ["Joint_1", "Joint_2", "Joint_3", "Joint_4", "Joint_5", "Joint_6"]
//! # also: velocity, acceleration, motor_position (motor encoder for rotor compensation),
//! # temperature (deg C, for the nonlinear rotor friction), joint_torque (link side, N m)
//!
//! [units]
//! angle = "rad"                  # or "deg": positions, velocities, accelerations
//! torque_scale = 1.0             # number or one per joint
//! position_offset = [0.0, -1.5708, 0.0, 0.0, 0.0, 0.0]  # rad (m) added to the positions
//!
//! [drive]                        # see `DriveConfig`
//! [[extra_column]]               # see `ExtraColumn`
//!
//! [processing]
//! lowpass = { cutoff = 25.0, order = 4, signals = ["q"] }   # Hz or "auto", zero-phase Butterworth
//! velocity = "auto"              # "data", "differentiate" or "auto" (data when given)
//! acceleration = "auto"
//! differentiation = { method = "savitzky-golay", window = 21, order = 3 }  # or "central" (default)
//! trim = 20                      # samples dropped at each end of the range (at least one
//!                                # settling time of the low-pass at each end of the record)
//! decimation = 100               # total factor (stages of <= 10) or a list [10, 10]
//! rest_velocity = 0.05           # rad/s, number or one per joint
//! range = [0, 24750]             # optional sample range used for estimation (end exclusive)
//! validation_range = [0, 15750]  # optional sample range of each validation file (default: all)
//! pieces = [[1.2, 1.9], [2.6, 3.3]]  # optional: estimate on these windows only (s from the
//!                                # first sample; Milella's piece-wise identification)
//! gaps = "split"                 # or "refuse" (default): a gap in the time stamps cuts the
//!                                # record into segments processed on their own, stacked
//!
//! [estimation]
//! method = "wls"                 # "ols", "wls", "rls", "link-by-link", "energy" or "per-axis"
//! rank_tolerance = 1e-10         # singular values below this times the largest are zero
//! forgetting = 1.0               # RLS forgetting factor, 0.5 <= lambda <= 1
//! energy_window = 0.05           # s, one energy-model equation per window
//! robust_std = true              # OLS and WLS: Newey-West deviations beside the classical
//!                                # ones (false skips them: on a record that streams, they
//!                                # take one more pass over it)
//! known = "masses.toml"          # optional: a [known] table of standard parameters known
//!                                # beforehand (not estimated; their torques move to the
//!                                # right-hand side)
//!
//! [runs]                         # repeated acquisitions of one trajectory (see `Runs`)
//! mode = "stacked"               # or "averaged" (sample-wise mean, same time grid)
//! files = ["run1.csv", "run2.csv"]   # one entry per run, a file per [[source]]
//! ```
//!
//! Without a config file robid uses [`Config::default_mapping`]: the header
//! `t,q1..qn,qd1..qdn,qdd1..qddn,tau1..taun` (what `robid simulate` writes).
//!
//! Every number is checked when the config is checked ([`Config::check`], called by
//! [`crate::data::load`] and the pipeline), and an error names the key at its
//! file:line:column ([`crate::DataError::ConfigKey`]); a config built in code is named by its fields
//! ([`Error::Setting`] with owner `Config`). Ranges (see [`crate::limits`]):
//!
//! | key | accepted |
//! |---|---|
//! | `dof` | the model's joint count |
//! | `sample_rate` | 1e-3 Hz <= rate <= 1e7 Hz (also a rate derived from the time column); not with `time_column`; within 1 % of the rate of a time column the file has but the config does not read (`data::time_name`) |
//! | `time_scale` | 1e-12 <= scale <= 1e6 |
//! | `units.torque_scale`, `drive.gear_ratios`, `drive.torque_constants` | finite, magnitude 1e-12 to 1e6 |
//! | `units.position_offset` | finite, magnitude <= 1e6 |
//! | `drive.position_coupling`, `drive.torque_coupling` | finite, magnitude <= 1e6, invertible |
//! | `drive.rotor.*`, `extra_column[i].terms[k].coefficient` | finite, magnitude <= 1e6 |
//! | `drive.rotor.inertia`, `drive.rotor.viscous`, `drive.rotor.coulomb` | also >= 0 (0 for no rotor or no friction) |
//! | `processing.lowpass.cutoff` | 0 < cutoff < the Nyquist frequency of the data, or `"auto"` |
//! | `processing.lowpass.order` | 1 to 20 |
//! | `processing.decimation` | factors >= 1, product <= 10,000 |
//! | `processing.differentiation` | `method` `"central"` or `"savitzky-golay"`; for the latter `window` odd, 3 to 1,001, and `order` 2 to 10, below the window |
//! | `processing.trim` | <= 50,000,000 |
//! | `processing.rest_velocity` | 0 <= v <= 1e6 |
//! | `processing.range`, `processing.validation_range` | `[start, end]` with start < end <= the samples of the data |
//! | `processing.pieces` | windows `[start, end]` in s, 0 <= start < end; not with the energy method |
//! | `processing.gaps` | `"refuse"` or `"split"`; with `"split"` and a record with gaps, not with `range`, `validation_range`, `pieces` or the energy method |
//! | `estimation.rank_tolerance` | 0 < tol < 1 |
//! | `estimation.forgetting` | 0.5 <= lambda <= 1 |
//! | `estimation.energy_window` | 0 < window <= 1e6 s |
//! | `estimation.known` | a parameter file with a `[known]` table, its names standard parameters of the robot |
//! | `extra_column` | at most 1,000 |
//! | `runs.files` | at least 2 runs, each with one file per `[[source]]`; `mode = "stacked"` not with `method = "energy"` |

use crate::DataError;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::data::ColumnMapping;
use crate::data::TomlFile;
use crate::data::keys::KeyMap;
use crate::drive::{DriveConfig, ExtraColumn};
use crate::error::{Error, Result, num, place};
use crate::limits::{
    MAX_EXTRA_COLUMNS, MAX_FACTOR, MAX_ROWS, MAX_SAMPLE_RATE, MAX_VELOCITY, MIN_FACTOR,
    MIN_SAMPLE_RATE,
};
use crate::signal::SavitzkyGolay;

/// A complete, annotated config: every key with its default or an example value, and what
/// it does (`robid identify --example-config` prints it; README.md shows it). It parses
/// as a [`Config`] (a test checks it).
pub const EXAMPLE_CONFIG: &str = include_str!("example_config.toml");

/// Where a [`Config`] came from: it decides how errors name its keys.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
#[non_exhaustive]
pub enum ConfigOrigin {
    /// Built in code: keys are named as fields of `Config` ([`Error::Setting`]).
    #[default]
    Code,
    /// [`Config::default_mapping`], used when no config file is given.
    DefaultMapping,
    /// Read from a file: keys are named by file:line:column ([`crate::DataError::ConfigKey`]).
    File {
        /// The file.
        path: PathBuf,
        /// Where each key is in it.
        keys: KeyMap,
    },
}

/// The whole config file. `Config::default()` equals the config of an empty file.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Config {
    /// Number of joints (checked against the model and the columns).
    pub dof: Option<usize>,
    /// Sample rate in Hz when there is no time column.
    pub sample_rate: Option<f64>,
    /// Name of the time column (in seconds unless `time_scale` or a unit in its name,
    /// such as `t_ms`, says otherwise).
    pub time_column: Option<String>,
    /// Factor from the time column's unit to seconds, when the config gives it; `None`
    /// reads seconds, or the unit the column's name gives (`t_ms`). A factor the config
    /// gives wins over the name's unit, 1 included (an explicit `time_scale = 1` was taken
    /// as not given, and a column named `t_ms` holding seconds was read at 1000 times its
    /// rate): [`Config::seconds_per_time_unit`] is the factor applied.
    #[serde(default)]
    pub time_scale: Option<f64>,
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
    /// Repeated acquisitions of one trajectory, identified together or averaged (none
    /// when absent).
    pub runs: Option<Runs>,
    /// Folder that relative `file` paths are resolved against (the config file's folder).
    #[serde(skip)]
    pub base_dir: Option<PathBuf>,
    /// Where this config came from (file, default mapping or code).
    #[serde(skip)]
    pub origin: ConfigOrigin,
    /// Show the progress of the long steps of identification on standard error
    /// ([`crate::progress`]): reading a record kept on disk ([`crate::data::load_record`])
    /// and the passes of streaming least squares and of validation over it. Not a key of
    /// the file: false (silent) unless set in code, as `robid identify` does.
    #[serde(skip)]
    pub progress: bool,
    /// The joints whose positions are lengths, the robot's prismatic joints (one flag per
    /// joint, from the first; missing ones are revolute): `units.angle = "deg"` converts
    /// the positions, velocities and accelerations of every other joint, and the motor
    /// positions of all (a motor turns, whatever its joint does). Not a key of the file:
    /// the robot's, set in code, as every `robid` subcommand does from its description.
    #[serde(skip)]
    pub prismatic: Vec<bool>,
    /// The keys a front end set from its command line, each with the flag as given
    /// (`estimation.method`, `--method energy`; see [`Config::set_by_flag`]). Not keys of
    /// the file: an error about one names the flag (it named the file's line of the value
    /// the flag replaced, or a key the file never gave).
    #[serde(skip)]
    pub flags: Vec<(String, String)>,
}

impl Default for Config {
    /// The same values as an empty config file (serde's defaults): no `time_scale`.
    fn default() -> Self {
        Self {
            dof: None,
            sample_rate: None,
            time_column: None,
            time_scale: None,
            sources: Vec::new(),
            units: Units::default(),
            drive: DriveConfig::default(),
            extra_columns: Vec::new(),
            processing: Processing::default(),
            estimation: Estimation::default(),
            runs: None,
            base_dir: None,
            origin: ConfigOrigin::Code,
            progress: false,
            prismatic: Vec::new(),
            flags: Vec::new(),
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
    /// Drive temperatures (deg C), for the nonlinear rotor friction model
    /// (`[drive.rotor] friction`, `robid friction`).
    pub temperature: Option<Columns>,
    /// Link-side joint torques (N m) from a joint-torque sensor (or a simulator's truth),
    /// used by `robid friction`; not scaled by `units` or the drive chain.
    pub joint_torque: Option<Columns>,
}

/// Column names for one signal: a template with `{}` for the joint number (from 1) or
/// `{0}` for the joint's index (from 0, as UR's RTDE recorder numbers `actual_q_0` ..),
/// or a list.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(
    untagged,
    expecting = "a column name template such as \"q{}\" or a list of one column name per joint"
)]
pub enum Columns {
    /// e.g. `"q{}"` -> q1, q2, ...; `"actual_q_{0}"` -> actual_q_0, actual_q_1, ...
    Template(String),
    /// One name per joint.
    List(Vec<String>),
}

impl Columns {
    /// The column names for `dof` joints.
    ///
    /// ```
    /// use robid_runtime::data::Columns;
    /// let q = Columns::Template("q{}".into());
    /// assert_eq!(q.names(2), ["q1", "q2"]);
    /// let rtde = Columns::Template("actual_q_{0}".into());
    /// assert_eq!(rtde.names(2), ["actual_q_0", "actual_q_1"]);
    /// ```
    pub fn names(&self, dof: usize) -> Vec<String> {
        match self {
            Columns::Template(t) if t.contains("{}") => {
                (1..=dof).map(|j| t.replace("{}", &j.to_string())).collect()
            }
            Columns::Template(t) if t.contains("{0}") => {
                (0..dof).map(|j| t.replace("{0}", &j.to_string())).collect()
            }
            Columns::Template(t) => vec![t.clone()],
            Columns::List(v) => v.clone(),
        }
    }
}

/// A number for all joints or one per joint.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(untagged)]
pub enum PerJoint {
    /// The same value for every joint.
    All(f64),
    /// One value per joint.
    Each(Vec<f64>),
}

/// By hand, not `untagged`: an element of a list that is no number is told at its place
/// (`drive.gear_ratios[2]`), where an untagged enum could only say the whole value is wrong.
impl<'de> Deserialize<'de> for PerJoint {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        struct Visitor;
        impl<'de> serde::de::Visitor<'de> for Visitor {
            type Value = PerJoint;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str("a number for every joint or a list of one number per joint")
            }
            fn visit_f64<E>(self, v: f64) -> std::result::Result<PerJoint, E> {
                Ok(PerJoint::All(v))
            }
            fn visit_i64<E>(self, v: i64) -> std::result::Result<PerJoint, E> {
                Ok(PerJoint::All(v as f64))
            }
            fn visit_u64<E>(self, v: u64) -> std::result::Result<PerJoint, E> {
                Ok(PerJoint::All(v as f64))
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(
                self,
                mut seq: A,
            ) -> std::result::Result<PerJoint, A::Error> {
                let mut values = Vec::new();
                while let Some(v) = seq.next_element::<f64>()? {
                    values.push(v);
                }
                Ok(PerJoint::Each(values))
            }
        }
        d.deserialize_any(Visitor)
    }
}

impl PerJoint {
    /// One value per joint, each finite with magnitude at most
    /// [`MAX_FACTOR`](crate::limits::MAX_FACTOR); `key` names the config entry in the error
    /// (an [`Error::Setting`] of owner `Config`, which [`Config::locate`] places in
    /// its file).
    pub fn values(&self, dof: usize, key: &str) -> Result<Vec<f64>> {
        let v = match self {
            PerJoint::All(x) => vec![*x; dof],
            PerJoint::Each(v) if v.len() == dof => v.clone(),
            PerJoint::Each(v) => {
                return Err(Error::setting(
                    "Config",
                    key,
                    format!(
                        "{} for a model of {}; give one number for all joints or one per joint",
                        crate::Count(v.len(), "value"),
                        crate::Count(dof, "joint")
                    ),
                ));
            }
        };
        if let Some(x) = v.iter().find(|x| !(x.abs() <= MAX_FACTOR)) {
            return Err(Error::setting(
                "Config",
                key,
                format!(
                    "{} is not a finite number of magnitude at most {MAX_FACTOR:e}",
                    num(*x)
                ),
            ));
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
    /// Angle unit of the revolute joints' positions, velocities and accelerations and of
    /// motor positions; a prismatic joint's are metres whatever it says
    /// ([`Config::prismatic`]).
    #[serde(default, deserialize_with = "crate::toml_syntax::word")]
    pub angle: AngleUnit,
    /// Factor applied to the torque columns (e.g. to N m from mN m).
    pub torque_scale: Option<PerJoint>,
    /// Added to each joint's position once converted (to radians, or metres for a
    /// prismatic joint, whatever `angle` says) and taken to the joint side: the model's
    /// zero where the encoder's is elsewhere (`q_model = q_read + offset`). Velocities,
    /// accelerations and motor positions are not changed.
    pub position_offset: Option<PerJoint>,
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

/// A low-pass cutoff: a frequency, or `"auto"`, chosen from the estimation data by
/// [`crate::inspect::suggest_cutoff`] (docs/identification.md#choosing-the-cutoff).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Cutoff {
    /// The cutoff in Hz.
    Hz(f64),
    /// Chosen from the data.
    Auto,
}

impl Cutoff {
    /// The frequency, when one is given.
    pub fn hz(self) -> Option<f64> {
        match self {
            Cutoff::Hz(c) => Some(c),
            Cutoff::Auto => None,
        }
    }
}

impl Serialize for Cutoff {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        match self {
            Cutoff::Hz(c) => s.serialize_f64(*c),
            Cutoff::Auto => s.serialize_str("auto"),
        }
    }
}

impl<'de> Deserialize<'de> for Cutoff {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        struct Visitor;
        impl serde::de::Visitor<'_> for Visitor {
            type Value = Cutoff;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str("a cutoff in Hz (a number) or \"auto\"")
            }
            fn visit_f64<E: serde::de::Error>(self, v: f64) -> std::result::Result<Cutoff, E> {
                Ok(Cutoff::Hz(v))
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> std::result::Result<Cutoff, E> {
                Ok(Cutoff::Hz(v as f64))
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> std::result::Result<Cutoff, E> {
                Ok(Cutoff::Hz(v as f64))
            }
            fn visit_str<E: serde::de::Error>(self, v: &str) -> std::result::Result<Cutoff, E> {
                match v {
                    "auto" => Ok(Cutoff::Auto),
                    _ => Err(E::invalid_value(serde::de::Unexpected::Str(v), &self)),
                }
            }
        }
        d.deserialize_any(Visitor)
    }
}

/// Zero-phase Butterworth low-pass.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Lowpass {
    /// Cutoff in Hz, or `"auto"`.
    pub cutoff: Cutoff,
    /// Filter order (applied twice by the forward-backward pass).
    #[serde(default = "four")]
    pub order: usize,
    /// Signals filtered.
    #[serde(default = "default_signals")]
    pub signals: Vec<Signal>,
}

/// `[start, end]`: exactly two values (an array of `[T; 2]` took the first two of
/// `[1, 2, 3]` and said nothing of the third).
fn pair<'de, D, T>(d: D) -> std::result::Result<Option<[T; 2]>, D::Error>
where
    D: serde::Deserializer<'de>,
    T: Deserialize<'de>,
{
    let values: Option<Vec<T>> = Option::deserialize(d)?;
    values.map(two).transpose()
}

/// A list of `[start, end]` pairs, each of exactly two values ([`pair`]).
fn pairs<'de, D, T>(d: D) -> std::result::Result<Option<Vec<[T; 2]>>, D::Error>
where
    D: serde::Deserializer<'de>,
    T: Deserialize<'de>,
{
    let lists: Option<Vec<Vec<T>>> = Option::deserialize(d)?;
    lists.map(|l| l.into_iter().map(two).collect()).transpose()
}

/// The two values of `v`, or an error saying how many there are.
fn two<E: serde::de::Error, T>(v: Vec<T>) -> std::result::Result<[T; 2], E> {
    let n = v.len();
    <[T; 2]>::try_from(v).map_err(|_| {
        let values = if n == 1 { "value" } else { "values" };
        E::custom(format!("{n} {values} given; write two, [start, end]"))
    })
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

/// How velocities and accelerations are differentiated (`processing.differentiation`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum DifferentiationMethod {
    /// Central differences of the (filtered) lower derivative.
    #[default]
    Central,
    /// The derivative of a local least-squares polynomial (Savitzky and Golay 1964,
    /// Milella's least-squares-fit estimator), `window` and `order` required.
    SavitzkyGolay,
}

/// `processing.differentiation`: the method, and for `"savitzky-golay"` its window
/// (odd, samples) and polynomial order (2 or more, below the window)
/// (docs/identification.md#savitzky-golay-derivatives).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Differentiation {
    /// The method.
    #[serde(default, deserialize_with = "crate::toml_syntax::word")]
    pub method: DifferentiationMethod,
    /// Window length in samples (Savitzky-Golay only).
    pub window: Option<usize>,
    /// Polynomial order (Savitzky-Golay only).
    pub order: Option<usize>,
}

impl Differentiation {
    /// The Savitzky-Golay differentiator, `None` for central differences; errors name the
    /// key `processing.differentiation.*` (owner `Config`).
    pub fn savitzky_golay(&self) -> Result<Option<SavitzkyGolay>> {
        let key = |k: &str| format!("processing.differentiation.{k}");
        match self.method {
            DifferentiationMethod::Central => {
                if let Some(k) = [("window", self.window), ("order", self.order)]
                    .iter()
                    .find_map(|(k, v)| v.map(|_| k))
                {
                    return Err(Error::setting(
                        "Config",
                        &key(k),
                        "applies to method = \"savitzky-golay\" only; remove it or choose that method",
                    ));
                }
                Ok(None)
            }
            DifferentiationMethod::SavitzkyGolay => {
                let (Some(window), Some(order)) = (self.window, self.order) else {
                    return Err(Error::setting(
                        "Config",
                        &key(if self.window.is_none() {
                            "window"
                        } else {
                            "order"
                        }),
                        "method = \"savitzky-golay\" needs a window (odd, samples) and an order, e.g. { method = \"savitzky-golay\", window = 21, order = 3 }",
                    ));
                };
                SavitzkyGolay::new(window, order)
                    .map(Some)
                    .map_err(|e| match e {
                        Error::Setting {
                            key: k, problem, ..
                        } => Error::setting("Config", &key(&k), problem),
                        e => e,
                    })
            }
        }
    }
}

/// A total decimation factor or explicit stages.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(
    untagged,
    expecting = "a whole number of at least 1 (the total factor) or a list of stage factors such as [10, 10]"
)]
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
    #[serde(default, deserialize_with = "crate::toml_syntax::word")]
    pub velocity: Derivative,
    /// Acceleration source.
    #[serde(default, deserialize_with = "crate::toml_syntax::word")]
    pub acceleration: Derivative,
    /// How velocities and accelerations are differentiated: central differences (default)
    /// or Savitzky-Golay.
    #[serde(default)]
    pub differentiation: Differentiation,
    /// Samples dropped at each end of the used range after filtering and differentiation.
    /// With a low-pass, at least one settling time is dropped at each real end of the
    /// record in any case: there the larger of the two counts applies (they do not add).
    #[serde(default)]
    pub trim: usize,
    /// Low-pass + decimation of every regressor column and of the torque; the decimated
    /// samples at each end that its filter does not settle are left out
    /// ([`crate::signal::Decimator::settled`]).
    #[serde(default)]
    pub decimation: Decimation,
    /// Equations of joint j are dropped where |qd_j| is below this (rad/s or m/s);
    /// [`DEFAULT_REST_VELOCITY`] when absent ([`Processing::rest_velocities`]), 0 keeps
    /// every equation.
    pub rest_velocity: Option<PerJoint>,
    /// Sample range used for estimation, `[start, end)`, cut after filtering and
    /// differentiation (so a split of one record has no filter transients at its ends),
    /// before `trim`. It does not apply to validation files.
    #[serde(default, deserialize_with = "pair")]
    pub range: Option<[usize; 2]>,
    /// Sample range of each validation file, `[start, end)`, cut like `range` (default:
    /// the whole file). Validation files are processed on their own: `range` does not
    /// apply to them.
    #[serde(default, deserialize_with = "pair")]
    pub validation_range: Option<[usize; 2]>,
    /// Piece-wise estimation (Milella): only the samples within these `[start, end]` windows
    /// (seconds from the record's first sample; `robid excite --method points --pieces`
    /// designs them) enter the estimation; the fit is still reported on the whole range.
    #[serde(default, deserialize_with = "pairs")]
    pub pieces: Option<Vec<[f64; 2]>>,
    /// What a gap in a file's time stamps does (a step of more than
    /// [`crate::data::GAP_RATIO`] median steps): refused (the default) or the record cut
    /// there into continuous segments ([`Gaps::Split`], [`crate::data::load_segments`]).
    #[serde(default, deserialize_with = "crate::toml_syntax::word")]
    pub gaps: Gaps,
}

/// `processing.gaps`: what a gap in the time stamps does
/// (docs/identification.md#gaps-in-the-time-stamps).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Gaps {
    /// A gap is an error naming its line ([`crate::DataError::TimeGap`]).
    #[default]
    Refuse,
    /// The record is cut at every gap into continuous segments, each processed on its own
    /// (filters, derivatives, decimation, trims never cross a gap), their equations
    /// stacked into one estimate; a segment too short for the processing is left out with
    /// a warning.
    Split,
}

/// Velocity below which a joint's equations are dropped when the config gives no
/// `processing.rest_velocity` (rad/s or m/s): Coulomb friction `Fc sign(qd)` is
/// undefined at rest and wrong near it, where a velocity differentiated from noisy or
/// quantised positions has either sign.
pub const DEFAULT_REST_VELOCITY: f64 = 0.05;

impl Processing {
    /// The thresholds of `processing.rest_velocity`, one per joint of a `dof`-joint model:
    /// the config's, else [`DEFAULT_REST_VELOCITY`] for every joint.
    pub fn rest_velocities(&self, dof: usize) -> Result<Vec<f64>> {
        match &self.rest_velocity {
            Some(r) => r.values(dof, "processing.rest_velocity"),
            None => Ok(vec![DEFAULT_REST_VELOCITY; dof]),
        }
    }
}

/// How repeated acquisitions of one trajectory are combined (`runs.mode`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum RunMode {
    /// The runs' equations stacked into one system (each run processed on its own).
    #[default]
    Stacked,
    /// The sample-wise mean of the runs (the same time grid), processed as one record:
    /// the noise of the mean is that of one run over sqrt(runs).
    Averaged,
}

/// The files of one run: one file, or one file per `[[source]]` table.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(
    untagged,
    expecting = "a file path in quotes or a list of one path per [[source]]"
)]
pub enum RunFiles {
    /// The file of a config with one `[[source]]`.
    One(PathBuf),
    /// One file per `[[source]]`, in their order.
    Each(Vec<PathBuf>),
}

impl RunFiles {
    /// The files, in `[[source]]` order.
    pub fn paths(&self) -> Vec<PathBuf> {
        match self {
            RunFiles::One(p) => vec![p.clone()],
            RunFiles::Each(v) => v.clone(),
        }
    }
}

/// `[runs]`: repeated acquisitions of the same trajectory (Milella's ten acquisitions),
/// identified together and each on its own, with the run-to-run spread reported
/// (docs/identification.md#repeated-acquisitions).
///
/// ```toml
/// [runs]
/// mode = "averaged"            # or "stacked" (default)
/// files = ["run1.csv", "run2.csv", "run3.csv"]   # or [["pos1.csv", "cur1.csv"], ...]
/// ```
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Runs {
    /// Stacked or averaged.
    #[serde(default, deserialize_with = "crate::toml_syntax::word")]
    pub mode: RunMode,
    /// The runs: at least two, each with one file per `[[source]]` (relative to the config).
    pub files: Vec<RunFiles>,
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
    /// Link by link from the last joint's torque backwards, each step by recursive least
    /// squares with `estimation.forgetting` (Zomaya 1994).
    #[serde(rename = "link-by-link")]
    LinkByLink,
    /// The energy (power balance) model: one equation per window of
    /// `estimation.energy_window` seconds, no accelerations needed.
    Energy,
    /// Per-axis least squares (Milella): each joint's equation on its own, each parameter
    /// from the joint that determines it with the smallest relative deviation.
    #[serde(rename = "per-axis")]
    PerAxis,
}

impl Method {
    /// The name in configs and reports (`ols`, `link-by-link`, ..).
    pub fn name(self) -> &'static str {
        match self {
            Method::Ols => "ols",
            Method::Wls => "wls",
            Method::Rls => "rls",
            Method::LinkByLink => "link-by-link",
            Method::Energy => "energy",
            Method::PerAxis => "per-axis",
        }
    }
}

/// Estimator options.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Estimation {
    /// Method.
    #[serde(default, deserialize_with = "crate::toml_syntax::word")]
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
    /// A parameter file with a `[known]` table (relative to the config's folder): standard
    /// parameters known beforehand, which are not estimated (their torques move to the
    /// right-hand side; docs/identification.md#known-parameters).
    #[serde(default)]
    pub known: Option<PathBuf>,
    /// Whether OLS and WLS give the autocorrelation-robust (Newey-West) standard deviations
    /// beside the classical ones (docs/identification.md#robust-standard-deviations); on a
    /// record that streams they take one more pass over its equations.
    #[serde(default = "yes")]
    pub robust_std: bool,
}

impl Default for Estimation {
    fn default() -> Self {
        Self {
            method: Method::Ols,
            rank_tolerance: default_tolerance(),
            forgetting: 1.0,
            energy_window: default_energy_window(),
            known: None,
            robust_std: true,
        }
    }
}

fn one() -> f64 {
    1.0
}
fn yes() -> bool {
    true
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
    /// The factor from the time column's unit to seconds that is applied: `time_scale`,
    /// or 1 when the config leaves it out (the column's name may give the unit when the
    /// data are read: `t_ms`).
    pub fn seconds_per_time_unit(&self) -> f64 {
        self.time_scale.unwrap_or(1.0)
    }

    /// Parses a config from TOML text; `path` names it in errors and its folder resolves
    /// relative file paths.
    pub fn from_toml_str(text: &str, path: &Path) -> Result<Self> {
        // the reader of robid's other TOML files (friction, flexibility, bounds): a key
        // given twice and a value nested too deep are named at their file:line:column
        // with what to do, not in toml's words
        let mut cfg: Config = toml::from_str(text)
            .map_err(|e| crate::toml_syntax::syntax_error(text, path, TomlFile::Config, &e))?;
        cfg.base_dir = path.parent().map(Path::to_path_buf);
        cfg.origin = ConfigOrigin::File {
            path: path.to_path_buf(),
            keys: KeyMap::parse(text),
        };
        Ok(cfg)
    }

    /// Reads and parses a config file.
    pub fn from_file(path: impl AsRef<Path>) -> Result<Self> {
        let path = path.as_ref();
        let text = crate::data::read_text(path, "config")?;
        Self::from_toml_str(&text, path)
    }

    /// The mapping used when no config file is given: a time column `t` and one source
    /// with the columns `q{}`, `qd{}`, `qdd{}` and `tau{}` (the header
    /// `t,q1..qn,qd1..qdn,qdd1..qddn,tau1..taun` that `robid simulate` writes). Errors
    /// about its columns say so instead of pointing at a config file.
    pub fn default_mapping() -> Self {
        let template = |t: &str| Some(Columns::Template(t.into()));
        Config {
            time_column: Some("t".into()),
            sources: vec![Source {
                file: None,
                position: template("q{}"),
                velocity: template("qd{}"),
                acceleration: template("qdd{}"),
                torque: template("tau{}"),
                motor_position: None,
                temperature: None,
                joint_torque: None,
            }],
            origin: ConfigOrigin::DefaultMapping,
            ..Config::default()
        }
    }

    /// The default mapping for a file with the column names `header`:
    /// [`Config::default_mapping`] when it has velocities (`qd1`), else the mapping of a
    /// log of positions and torques (`t,q1..qn,tau1..taun`, what `robid simulate
    /// --columns positions` writes): velocities and accelerations differentiated from the
    /// positions, low-passed at `cutoff = "auto"`.
    pub fn default_mapping_for(header: &[String]) -> Self {
        let mut config = Self::default_mapping();
        if !header.iter().any(|n| n == "qd1") {
            let source = &mut config.sources[0];
            source.velocity = None;
            source.acceleration = None;
            config.processing.lowpass = Some(Lowpass {
                cutoff: Cutoff::Auto,
                order: four(),
                signals: default_signals(),
            });
        }
        config
    }

    /// The extra regressor columns of a `dof`-joint model: the `[[extra_column]]` tables,
    /// then the rotor-side residual columns of `[drive.rotor] residual`.
    pub fn extra_columns_for(&self, dof: usize) -> Result<Vec<ExtraColumn>> {
        let mut columns = self.extra_columns.clone();
        if let Some(r) = self.drive.rotor.as_ref().and_then(|r| r.residual.as_ref()) {
            columns.extend(r.columns(dof)?);
        }
        Ok(columns)
    }

    /// Whether an extra column (or the residual shorthand) uses the motor encoders.
    pub fn uses_rotor_signals(&self) -> bool {
        self.extra_columns.iter().any(|c| c.rotor_term().is_some())
            || self
                .drive
                .rotor
                .as_ref()
                .is_some_and(|r| r.residual.is_some())
    }

    /// The `[[source]]` columns an identification reads and then leaves out of the fit,
    /// each with its key (`source[1].motor_position`) and what would use it: motor
    /// encoders without `[drive.rotor]` or an extra column of their signals, temperatures
    /// without the nonlinear rotor friction, joint torques without `[drive.rotor]` (which
    /// `robid friction`, their one user, needs). A two-encoder log identified without the
    /// rotor's terms fits badly, and nothing else says why.
    pub fn unused_columns(&self) -> Vec<(String, &'static str)> {
        let rotor = self.drive.rotor.as_ref();
        let unused = [
            (
                "motor_position",
                rotor.is_none() && !self.uses_rotor_signals(),
                "the motor encoders enter the fit through `[drive.rotor]` (the rotors' \
                 inertia and friction between motor and joint torque, \
                 docs/identification.md#rotor-dynamics-compensation) or an \
                 [[extra_column]] of theta_d, theta_dd or sign_theta_d",
            ),
            (
                "temperature",
                rotor.is_none_or(|r| r.friction.is_none()),
                "temperatures enter the fit through the nonlinear rotor friction only \
                 (`[drive.rotor] friction`, the file `robid friction` writes)",
            ),
            (
                "joint_torque",
                rotor.is_none(),
                "joint torques are read by `robid friction`, with `[drive.rotor]`; \
                 `robid identify` fits the torque columns",
            ),
        ];
        self.sources
            .iter()
            .enumerate()
            .flat_map(|(i, s)| {
                let given = [
                    s.motor_position.is_some(),
                    s.temperature.is_some(),
                    s.joint_torque.is_some(),
                ];
                unused
                    .iter()
                    .zip(given)
                    .filter(|((_, unused, _), given)| *unused && *given)
                    .map(move |((role, _, why), _)| (format!("source[{}].{role}", i + 1), *why))
            })
            .collect()
    }

    /// Every file the config names, resolved against its folder: the sources' and runs'
    /// data, the known parameters (`estimation.known`) and the rotor friction
    /// (`[drive.rotor] friction`). A command refuses to write over any of them
    /// (docs/robustness.md#outputs-that-are-inputs), read for this run or not.
    pub fn referenced_files(&self) -> Vec<PathBuf> {
        let sources = self.sources.iter().filter_map(|s| s.file.clone());
        let runs = self
            .runs
            .iter()
            .flat_map(|r| r.files.iter().flat_map(RunFiles::paths));
        let known = self.estimation.known.clone();
        let friction = self.drive.rotor.as_ref().and_then(|r| r.friction.clone());
        sources
            .chain(runs)
            .chain(known)
            .chain(friction)
            .map(|f| self.resolve(&f))
            .collect()
    }

    /// The key of the first path the config gives as `""`.
    fn empty_path(&self) -> Option<String> {
        let empty = |p: &Path| p.as_os_str().is_empty();
        let sources = self
            .sources
            .iter()
            .enumerate()
            .filter(|(_, s)| s.file.as_deref().is_some_and(empty))
            .map(|(i, _)| format!("source[{}].file", i + 1));
        let runs = self.runs.iter().flat_map(|r| {
            r.files
                .iter()
                .enumerate()
                .filter(|(_, f)| f.paths().iter().any(|p| empty(p)))
                .map(|(i, _)| format!("runs.files[{}]", i + 1))
        });
        let known = self
            .estimation
            .known
            .as_deref()
            .is_some_and(empty)
            .then(|| "estimation.known".to_owned());
        let friction = self
            .drive
            .rotor
            .as_ref()
            .and_then(|r| r.friction.as_deref())
            .is_some_and(empty)
            .then(|| "drive.rotor.friction".to_owned());
        sources.chain(runs).chain(known).chain(friction).next()
    }

    /// Resolves a path from the config against its folder.
    pub fn resolve(&self, file: &Path) -> PathBuf {
        match &self.base_dir {
            Some(dir) if file.is_relative() => dir.join(file),
            _ => file.to_path_buf(),
        }
    }

    /// `e`, which arose from the data of run `index` (from 0) alone, as an [`Error::Run`]
    /// naming the run: its entry `runs.files[i]` (at file:line:column for a config file)
    /// and its files, or, when the config lists no runs, its number and `name` (the run's
    /// data set). Without it an error of one run among ten (rank-deficient data, too few
    /// samples) would not say which run to repeat.
    pub fn run_error(&self, index: usize, name: &str, e: Error) -> Error {
        if matches!(e, Error::Run { .. }) {
            return e;
        }
        let key = format!("runs.files[{}]", index + 1);
        let listed = self.runs.as_ref().and_then(|r| r.files.get(index));
        let run = match (listed, &self.origin) {
            (Some(files), origin) => {
                let files: Vec<String> = files
                    .paths()
                    .iter()
                    .map(|f| f.display().to_string())
                    .collect();
                let files = files.join(", ");
                match origin {
                    ConfigOrigin::File { path, keys } => {
                        let at = keys.find(&key);
                        let at = place(path, at.map(|a| a.0), at.map(|a| a.1));
                        format!("{at}: `{key}` ({files})")
                    }
                    _ => format!("Config `{key}` ({files})"),
                }
            }
            (None, _) => format!("run {} ({name})", index + 1),
        };
        Error::Run {
            run,
            error: Box::new(e),
        }
    }

    /// Records that the front end set `key` (a dotted path, with everything under it)
    /// from its command line as `flag` (e.g. `--method energy`): errors about it name the
    /// flag ([`Config::key_error`]).
    pub fn set_by_flag(&mut self, key: &str, flag: impl Into<String>) {
        self.flags.retain(|(k, _)| k != key);
        self.flags.push((key.to_string(), flag.into()));
    }

    /// The error for the key `key` (a dotted path, arrays numbered from 1): an
    /// [`Error::Argument`] naming the flag when a command line set it
    /// ([`Config::set_by_flag`]), else located in the file when the config was read from
    /// one, else named as a field of `Config`.
    pub fn key_error(&self, key: &str, problem: impl Into<String>) -> Error {
        let under = |k: &str| {
            key == k
                || key
                    .strip_prefix(k)
                    .is_some_and(|rest| rest.starts_with('.'))
        };
        if let Some((_, flag)) = self.flags.iter().find(|(k, _)| under(k)) {
            return Error::Argument {
                flag: flag.clone(),
                problem: problem.into(),
            };
        }
        match &self.origin {
            ConfigOrigin::File { path, keys } => {
                let at = keys.find(key);
                Error::Data(DataError::ConfigKey {
                    path: path.clone(),
                    line: at.map(|a| a.0),
                    column: at.map(|a| a.1),
                    key: key.to_string(),
                    problem: problem.into(),
                })
            }
            ConfigOrigin::DefaultMapping => Error::setting("the default config", key, problem),
            ConfigOrigin::Code => Error::setting("Config", key, problem),
        }
    }

    /// Those of `keys` (dotted paths, each with everything under it) that the config's
    /// file gives, with their place: for a command that applies only part of a config
    /// to say what it leaves out. Empty for a config not read from a file.
    pub fn given(&self, keys: &[&str]) -> Vec<(String, usize, usize)> {
        let ConfigOrigin::File { keys: map, .. } = &self.origin else {
            return Vec::new();
        };
        keys.iter()
            .filter_map(|k| {
                map.given(k)
                    .map(|(line, column)| (k.to_string(), line, column))
            })
            .collect()
    }

    /// Places an error about a `Config` field (an [`Error::Setting`] of owner
    /// `Config`) at its key in the config file; other errors pass unchanged.
    pub fn locate(&self, e: Error) -> Error {
        match e {
            Error::Setting {
                owner,
                key,
                problem,
            } if owner == "Config" => self.key_error(&key, problem),
            e => e,
        }
    }

    /// Where the column names of the key `key` (e.g. `source[2].torque`, `time_column`)
    /// came from: for errors about a column missing from a file.
    pub fn mapping(&self, key: &str) -> ColumnMapping {
        match &self.origin {
            ConfigOrigin::Code => ColumnMapping::Code,
            ConfigOrigin::DefaultMapping => ColumnMapping::Default,
            ConfigOrigin::File { path, keys } => ColumnMapping::Config {
                path: path.clone(),
                line: keys.find(key).map(|a| a.0),
                key: key.to_string(),
            },
        }
    }

    /// Checks value ranges that serde cannot (see the module documentation); `dof` is the
    /// model's joint count. Errors name the key (file:line:column for a config file).
    pub fn check(&self, dof: usize) -> Result<()> {
        self.check_fields(dof).map_err(|e| self.locate(e))
    }

    fn check_fields(&self, dof: usize) -> Result<()> {
        let bad = |key: &str, problem: String| Err(Error::setting("Config", key, problem));
        if let Some(key) = self.empty_path() {
            return bad(
                &key,
                "the path is empty (it named the config's folder); give the file's path, \
                 relative to the config's folder or absolute"
                    .to_owned(),
            );
        }
        if let Some(n) = self.dof
            && n != dof
        {
            return bad(
                "dof",
                format!(
                    "{}, but the model has {dof}; write dof = {dof} or use the matching robot description",
                    crate::Count(n, "joint")
                ),
            );
        }
        if self.sample_rate.is_some() && self.time_column.is_some() {
            return bad(
                "sample_rate",
                "is given with time_column, whose time stamps set the rate; keep one of them \
                 (time_column for a log with time stamps)"
                    .to_owned(),
            );
        }
        if let Some(fs) = self.sample_rate
            && !(MIN_SAMPLE_RATE..=MAX_SAMPLE_RATE).contains(&fs)
        {
            return bad(
                "sample_rate",
                format!(
                    "{} Hz is outside [{MIN_SAMPLE_RATE:e}, {MAX_SAMPLE_RATE:e}] Hz; write the rate the data were sampled at",
                    num(fs)
                ),
            );
        }
        if let Some(scale) = self.time_scale
            && !(MIN_FACTOR..=MAX_FACTOR).contains(&scale)
        {
            return bad(
                "time_scale",
                format!(
                    "{} is outside [{MIN_FACTOR:e}, {MAX_FACTOR:e}]; write the factor from the time column's unit to seconds (1e-3 for ms)",
                    num(scale)
                ),
            );
        }
        for (i, s) in self.sources.iter().enumerate() {
            // each column read by one role of the source: (name, role)
            let mut read: Vec<(String, &str)> = Vec::new();
            for (role, c) in [
                ("position", &s.position),
                ("velocity", &s.velocity),
                ("acceleration", &s.acceleration),
                ("torque", &s.torque),
                ("motor_position", &s.motor_position),
                ("temperature", &s.temperature),
                ("joint_torque", &s.joint_torque),
            ] {
                if let Some(c) = c {
                    let names = c.names(dof);
                    let n = names.len();
                    for name in names {
                        if let Some((_, first)) = read.iter().find(|(r, _)| *r == name) {
                            let also = if *first == role {
                                "twice".to_owned()
                            } else {
                                format!("as source[{}].{first} does", i + 1)
                            };
                            return bad(
                                &format!("source[{}].{role}", i + 1),
                                format!(
                                    "reads column `{name}` {also}: a column holds one \
                                     quantity of one joint; name the {role} columns"
                                ),
                            );
                        }
                        read.push((name, role));
                    }
                    if n != dof {
                        return bad(
                            &format!("source[{}].{role}", i + 1),
                            format!(
                                "{} for a model of {}; list one per joint or write a template such as \"{role}{{}}\"",
                                crate::Count(n, "column name"),
                                crate::Count(dof, "joint")
                            ),
                        );
                    }
                }
            }
        }
        if let Some(s) = &self.units.torque_scale {
            nonzero(s.values(dof, "units.torque_scale")?, "units.torque_scale")?;
        }
        if let Some(o) = &self.units.position_offset {
            o.values(dof, "units.position_offset")?;
        }
        let p = &self.processing;
        if let Some(lp) = &p.lowpass {
            if let Cutoff::Hz(c) = lp.cutoff
                && !(c > 0.0 && c.is_finite())
            {
                return bad(
                    "processing.lowpass.cutoff",
                    format!("{} Hz must be a positive number", num(c)),
                );
            }
            if !(1..=20).contains(&lp.order) {
                return bad(
                    "processing.lowpass.order",
                    format!("{} is outside 1 to 20", lp.order),
                );
            }
            if lp.signals.is_empty() {
                return bad(
                    "processing.lowpass.signals",
                    "lists no signal to filter; name them (\"q\", \"qd\", \"qdd\", \"tau\"), or \
                     remove processing.lowpass for no low-pass"
                        .into(),
                );
            }
            if let Some((i, s)) = lp
                .signals
                .iter()
                .enumerate()
                .find(|(i, s)| lp.signals[..*i].contains(s))
            {
                let name = format!("{s:?}").to_lowercase();
                return bad(
                    "processing.lowpass.signals",
                    format!(
                        "\"{name}\" is listed twice (entry {}); list each signal once",
                        i + 1
                    ),
                );
            }
        }
        p.differentiation.savitzky_golay()?;
        if p.trim > MAX_ROWS {
            return bad(
                "processing.trim",
                format!(
                    "{} samples is more than the {MAX_ROWS} rows a file may have",
                    p.trim
                ),
            );
        }
        let factors: Vec<usize> = match &p.decimation {
            Decimation::Total(t) => vec![*t],
            Decimation::Stages(s) => s.clone(),
        };
        if factors.is_empty() {
            return bad(
                "processing.decimation",
                "an empty list of stages; write 1 for no decimation, or the factors \
                 ([10, 10])"
                    .into(),
            );
        }
        if factors.contains(&0) {
            return bad(
                "processing.decimation",
                "a decimation factor of 0 is meaningless; use 1 for none".into(),
            );
        }
        if let Some(problem) = crate::signal::decimation_too_large(&factors) {
            return bad("processing.decimation", problem);
        }
        if let Some(r) = &p.rest_velocity {
            let v = r.values(dof, "processing.rest_velocity")?;
            if let Some(x) = v.iter().find(|x| !(**x >= 0.0 && **x <= MAX_VELOCITY)) {
                return bad(
                    "processing.rest_velocity",
                    format!("{} rad/s must lie in [0, {MAX_VELOCITY:e}]", num(*x)),
                );
            }
        }
        for (key, range) in [
            ("processing.range", p.range),
            ("processing.validation_range", p.validation_range),
        ] {
            if let Some([a, b]) = range
                && a >= b
            {
                return bad(
                    key,
                    format!(
                        "[{a}, {b}] is empty; write [start, end] with start < end (end excluded)"
                    ),
                );
            }
        }
        if let Some(pieces) = &p.pieces {
            if pieces.is_empty() {
                return bad(
                    "processing.pieces",
                    "no window given; list [start, end] windows in seconds, or leave the key out"
                        .into(),
                );
            }
            if let Some([a, b]) = pieces
                .iter()
                .find(|[a, b]| !(a.is_finite() && b.is_finite() && *a >= 0.0 && a < b))
            {
                return bad(
                    "processing.pieces",
                    format!(
                        "[{}, {}] is not a window; write [start, end] in seconds from the \
                         record's first sample, 0 <= start < end",
                        num(*a),
                        num(*b)
                    ),
                );
            }
            if self.estimation.method == Method::Energy {
                return bad(
                    "processing.pieces",
                    "the energy model integrates over contiguous windows of its own; use \
                     pieces with ols, wls, rls, link-by-link or per-axis"
                        .into(),
                );
            }
        }
        let e = &self.estimation;
        if !crate::online::forgetting_in_range(e.forgetting) {
            return bad(
                "estimation.forgetting",
                format!(
                    "{} must lie in [{}, 1]: the recursion keeps about 1 / (1 - lambda) \
                     equations in memory (1 keeps every equation; 0.95 to 0.999 track slow \
                     changes)",
                    num(e.forgetting),
                    crate::estimate::MIN_FORGETTING
                ),
            );
        }
        if !(e.energy_window > 0.0 && e.energy_window <= MAX_FACTOR) {
            return bad(
                "estimation.energy_window",
                format!(
                    "{} s must lie in (0, {MAX_FACTOR:e}] s",
                    num(e.energy_window)
                ),
            );
        }
        if !(e.rank_tolerance > 0.0 && e.rank_tolerance < 1.0) {
            return bad(
                "estimation.rank_tolerance",
                format!("{} must lie in (0, 1)", num(e.rank_tolerance)),
            );
        }
        if let Some(runs) = &self.runs {
            self.check_runs(runs)?;
        }
        self.drive.check(dof)?;
        if self.extra_columns.len() > MAX_EXTRA_COLUMNS {
            return bad(
                "extra_column",
                format!(
                    "{} extra columns is more than the limit of {MAX_EXTRA_COLUMNS}",
                    self.extra_columns.len()
                ),
            );
        }
        for (i, c) in self.extra_columns.iter().enumerate() {
            c.check_keyed(dof, &format!("extra_column[{}]", i + 1))?;
            if let Some(k) = self.extra_columns[..i]
                .iter()
                .position(|earlier| c.same_column_as(earlier))
            {
                return bad(
                    &format!("extra_column[{}].terms", i + 1),
                    format!(
                        "`{}` has the terms of `{}` (extra_column[{}]), up to a factor: the \
                         two are one parameter, which no data can split; remove one",
                        c.name,
                        self.extra_columns[k].name,
                        k + 1
                    ),
                );
            }
        }
        Ok(())
    }
}

impl Config {
    fn check_runs(&self, runs: &Runs) -> Result<()> {
        if runs.files.len() < 2 {
            return Err(Error::setting(
                "Config",
                "runs.files",
                format!(
                    "{}: repeated acquisitions need at least two; list one entry per run or remove [runs]",
                    crate::Count(runs.files.len(), "run")
                ),
            ));
        }
        let per_run = self.sources.len().max(1);
        for (i, r) in runs.files.iter().enumerate() {
            let n = r.paths().len();
            if n != per_run {
                return Err(Error::setting(
                    "Config",
                    &format!("runs.files[{}]", i + 1),
                    format!(
                        "{} for a config with {}; give one file per table, in their order",
                        crate::Count(n, "file"),
                        crate::Count(per_run, "[[source]] table")
                    ),
                ));
            }
        }
        if runs.mode == RunMode::Stacked && self.estimation.method == Method::Energy {
            return Err(Error::setting(
                "Config",
                "runs.mode",
                "the energy model is built from each record's signals and cannot stack runs; use mode = \"averaged\" or another estimation.method",
            ));
        }
        Ok(())
    }
}

/// Checks that no factor is too small to keep its signal: |x| >= [`MIN_FACTOR`].
pub(crate) fn nonzero(values: Vec<f64>, key: &str) -> Result<Vec<f64>> {
    match values.iter().position(|v| !(v.abs() >= MIN_FACTOR)) {
        Some(j) => Err(Error::setting(
            "Config",
            key,
            format!(
                "joint {} has {}, which would erase its signal; give a factor of magnitude {MIN_FACTOR:e} to {MAX_FACTOR:e}",
                j + 1,
                num(values[j])
            ),
        )),
        None => Ok(values),
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
        assert_eq!(default.time_scale, None);
        assert_eq!(default.seconds_per_time_unit(), 1.0);
        assert_eq!(
            serde_json::to_string(&default).unwrap(),
            serde_json::to_string(&empty).unwrap()
        );
        default.check(6).unwrap();
    }

    /// A path given as `""` is named at its key: it resolved to the config's folder and
    /// was told as "cannot read: Is a directory", naming the folder.
    #[test]
    fn an_empty_path_is_named_at_its_key() {
        for (text, want) in [
            (
                "[[source]]\nfile = \"\"\n",
                "c.toml:2:1: `source[1].file`: the path is empty",
            ),
            (
                "[estimation]\nknown = \"\"\n",
                "c.toml:2:1: `estimation.known`: the path is empty",
            ),
            (
                "[runs]\nfiles = [\"a.csv\", \"\"]\n",
                "`runs.files[2]`: the path is empty",
            ),
        ] {
            let config = Config::from_toml_str(text, Path::new("c.toml")).unwrap();
            let e = config.check(6).unwrap_err().to_string();
            assert!(e.starts_with(want) || e.contains(want), "{e}");
        }
    }

    /// Showing progress is a setting of the caller, not a key of the file: silent by
    /// default and from any file, and `progress = true` in a file is an unknown key.
    #[test]
    fn progress_is_not_a_key_of_the_file() {
        assert!(!Config::default().progress);
        assert!(
            !Config::from_toml_str(EXAMPLE, Path::new("a.toml"))
                .unwrap()
                .progress
        );
        let err = Config::from_toml_str("progress = true", Path::new("a.toml")).unwrap_err();
        assert!(
            err.to_string().starts_with(
                "a.toml:1:1: `progress`: not a key of this table; the keys here are `dof`"
            ),
            "{err}"
        );
    }

    #[test]
    fn syntax_errors_name_the_file() {
        let err = Config::from_toml_str("dof = [", Path::new("bad.toml")).unwrap_err();
        assert!(err.to_string().starts_with("bad.toml"), "{err}");
        let err = Config::from_toml_str("colour = 1", Path::new("bad.toml")).unwrap_err();
        assert!(err.to_string().contains("colour"), "{err}");
    }

    /// A range, a validation range or a piece of three values was read as its first two.
    #[test]
    fn ranges_and_pieces_take_exactly_two_values() {
        for bad in [
            "[processing]\nrange = [1, 2, 3]\n",
            "[processing]\nvalidation_range = [1]\n",
            "[processing]\npieces = [[0.0, 1.0], [2.0, 3.0, 4.0]]\n",
        ] {
            let e = Config::from_toml_str(bad, Path::new("c.toml"))
                .unwrap_err()
                .to_string();
            assert!(e.contains("write two, [start, end]"), "{bad}: {e}");
        }
        let good = "[processing]\nrange = [1, 20]\npieces = [[0.0, 1.0]]\n";
        let cfg = Config::from_toml_str(good, Path::new("c.toml")).unwrap();
        assert_eq!(cfg.processing.range, Some([1, 20]));
        assert_eq!(cfg.processing.pieces, Some(vec![[0.0, 1.0]]));
        assert_eq!(Config::default().processing.range, None);
    }

    #[test]
    fn range_checks() {
        let cfg = Config::from_toml_str(EXAMPLE, Path::new("c.toml")).unwrap();
        let e = cfg.check(3).unwrap_err();
        assert!(
            e.to_string()
                .starts_with("c.toml:2:1: `dof`: 2 joints, but the model has 3"),
            "{e}"
        );
        let bad = EXAMPLE.replace("method = \"wls\"", "forgetting = 1.5");
        let cfg = Config::from_toml_str(&bad, Path::new("c.toml")).unwrap();
        let e = cfg.check(2).unwrap_err();
        assert!(
            matches!(&e, Error::Data(DataError::ConfigKey { line: Some(15), key, .. }) if key == "estimation.forgetting"),
            "{e}"
        );
        // below the floor: the config's own check, as the recursion's (1e-320 passed it)
        for tiny in ["1e-320", "0.3"] {
            let bad = EXAMPLE.replace("method = \"wls\"", &format!("forgetting = {tiny}"));
            let cfg = Config::from_toml_str(&bad, Path::new("c.toml")).unwrap();
            let e = cfg.check(2).unwrap_err().to_string();
            assert!(
                e.starts_with("c.toml:15:1: `estimation.forgetting`") && e.contains("[0.5, 1]"),
                "{e}"
            );
        }
        let bad = EXAMPLE.replace("rest_velocity = 0.1", "rest_velocity = [0.1]");
        let cfg = Config::from_toml_str(&bad, Path::new("c.toml")).unwrap();
        let e = cfg.check(2).unwrap_err();
        assert!(
            e.to_string().starts_with(
                "c.toml:13:1: `processing.rest_velocity`: 1 value for a model of 2 joints"
            ),
            "{e}"
        );
        // the factor as written, not 2e4 (nor 9.223372036854776e18 for the largest
        // 64-bit factor); a product beyond every integer is said so
        for (stages, total) in [
            ("[100, 200]", "20000"),
            ("9223372036854775807", "9223372036854775807"),
            (
                "[4294967296, 4294967296, 4294967296, 4294967296, 4294967296]",
                "beyond 3.4e38",
            ),
        ] {
            let bad = EXAMPLE.replace("decimation = [2, 2]", &format!("decimation = {stages}"));
            let e = Config::from_toml_str(&bad, Path::new("c.toml"))
                .unwrap()
                .check(2)
                .unwrap_err();
            assert!(
                e.to_string().contains(&format!(
                    "a total factor of {total} is more than the limit of 10000"
                )),
                "{e}"
            );
        }
        // an empty or repeated list is a mistake, told with its fix
        for (from, to, says) in [
            (
                "decimation = [2, 2]",
                "decimation = []",
                "write 1 for no decimation",
            ),
            (
                "lowpass = { cutoff = 5.0 }",
                "lowpass = { cutoff = 5.0, signals = [] }",
                "lists no signal to filter",
            ),
            (
                "lowpass = { cutoff = 5.0 }",
                "lowpass = { cutoff = 5.0, signals = [\"q\", \"tau\", \"q\"] }",
                "`processing.lowpass.signals`: \"q\" is listed twice (entry 3)",
            ),
        ] {
            let bad = EXAMPLE.replace(from, to);
            assert_ne!(bad, EXAMPLE, "{to}");
            let e = Config::from_toml_str(&bad, Path::new("c.toml"))
                .unwrap()
                .check(2)
                .unwrap_err();
            assert!(e.to_string().contains(says), "{to}: {e}");
        }
        let fine = EXAMPLE.replace(
            "lowpass = { cutoff = 5.0 }",
            "lowpass = { cutoff = 5.0, signals = [\"q\", \"tau\"] }",
        );
        let cfg = Config::from_toml_str(&fine, Path::new("c.toml")).unwrap();
        assert!(cfg.check(2).is_ok());
        // a config built in code is named by its fields, never as a file
        let mut code = Config::default();
        code.processing.lowpass = Some(Lowpass {
            cutoff: Cutoff::Hz(-1.0),
            order: 4,
            signals: vec![Signal::Q],
        });
        let e = code.check(2).unwrap_err();
        assert_eq!(
            e.to_string(),
            "Config `processing.lowpass.cutoff`: -1 Hz must be a positive number"
        );
    }

    /// `processing.differentiation`: the Savitzky-Golay settings are checked and every
    /// mistake names its key at its line.
    #[test]
    fn milella_differentiation_settings_are_checked() {
        let with = |d: &str| {
            let text = EXAMPLE.replace("rest_velocity = 0.1", &format!("differentiation = {d}"));
            Config::from_toml_str(&text, Path::new("c.toml")).unwrap()
        };
        let good = with("{ method = \"savitzky-golay\", window = 21, order = 3 }");
        good.check(2).unwrap();
        let sg = good
            .processing
            .differentiation
            .savitzky_golay()
            .unwrap()
            .unwrap();
        assert_eq!((sg.window(), sg.order()), (21, 3));
        assert!(with("{ method = \"central\" }").check(2).is_ok());
        for (d, key, says) in [
            (
                "{ method = \"savitzky-golay\", window = 20, order = 3 }",
                "window",
                "odd",
            ),
            (
                "{ method = \"savitzky-golay\", window = 5, order = 5 }",
                "order",
                "not below the window",
            ),
            (
                "{ method = \"savitzky-golay\", window = 21, order = 1 }",
                "order",
                "2 at least",
            ),
            (
                "{ method = \"savitzky-golay\", window = 21 }",
                "order",
                "needs a window",
            ),
            (
                "{ method = \"central\", window = 21 }",
                "window",
                "savitzky-golay\" only",
            ),
        ] {
            let e = with(d).check(2).unwrap_err();
            assert!(
                matches!(&e, Error::Data(DataError::ConfigKey { line: Some(13), key: k, problem, .. })
                    if *k == format!("processing.differentiation.{key}") && problem.contains(says)),
                "{d}: {e}"
            );
        }
        let e = Config::from_toml_str(
            &EXAMPLE.replace(
                "rest_velocity = 0.1",
                "differentiation = { method = \"spline\" }",
            ),
            Path::new("c.toml"),
        )
        .unwrap_err();
        assert!(e.to_string().contains("spline"), "{e}");
    }
}
