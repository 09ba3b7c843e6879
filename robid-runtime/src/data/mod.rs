//! Loading measured data (docs/identification.md#data-and-configuration and
//! docs/identification.md#time-stamps-and-resampling): CSV files with a header (optionally gzip),
//! a TOML config mapping columns and units, time stamps checked and resampled,
//! several files joined, the drive chain applied.

mod agreement;
mod config;
mod dataset;
mod error;
mod keys;
mod load;
mod parameters;
mod plain;
mod rate;
mod record;
mod sampling;
mod segments;
mod speed;
mod table;
mod time;
mod unwrap;

pub use crate::toml_syntax::read_text;
pub use agreement::{
    AGREEMENT_CORRELATION, AGREEMENT_SCALES, DerivativeAgreement, DerivativeColumn,
};
pub(crate) use config::nonzero;
pub use config::{
    AngleUnit, Columns, Config, ConfigOrigin, Cutoff, DEFAULT_REST_VELOCITY, Decimation,
    Derivative, Differentiation, DifferentiationMethod, EXAMPLE_CONFIG, Estimation, Gaps, Lowpass,
    Method, PerJoint, Processing, RunFiles, RunMode, Runs, Signal, Source, Units,
};
pub use dataset::{DataOrigin, Dataset, Extremes};
pub use error::{DataError, TomlFile};
pub use keys::KeyMap;
pub(crate) use load::check_joints;
pub use load::{
    SLOW_SAMPLE_RATE, load, load_config_files, load_from_config_file, load_runs, surplus_joint,
};
pub use parameters::{INERTIA_TOLERANCE, PARAMETER_LIMIT, ParameterFile, ParameterTable};
pub use rate::{RATE_CHECK_ROWS, RATE_TOLERANCE, REGULAR_SHARE, REGULAR_SPREAD, time_name};
pub(crate) use record::joined_with;
pub use record::{Record, SpilledRecord, load_record};
pub use sampling::{SKIP_RATIO, STALE_SHARE, Sampling};
pub use segments::{Loaded, SegmentSpan, Segments, load_or_split, load_segments};
pub use speed::{SPEED_STRIDE, SpeedHistogram};
pub(crate) use table::header_needed;
pub use table::{
    ColumnMapping, Table, WINDOW, for_each_window, read_columns, read_columns_from, read_header,
};
pub use time::{
    GAP_RATIO, Grid, IRREGULAR_TOLERANCE, Warning, check_monotonic, interpolate, nearest_lines,
    regularity,
};
pub(crate) use time::{check_gaps, check_time_stamps, sample_time_accepted};
pub use unwrap::WRAP_TOLERANCE;

#[cfg(test)]
mod tests;
