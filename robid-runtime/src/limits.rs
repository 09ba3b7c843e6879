//! The documented limits of every input, checked where the input is read (CSV files,
//! config files, settings given in code) and named in the error that reports a breach.
//!
//! They are generous: no real recording, robot or design comes near them. They exist so
//! that a logging, unit or typing error (a torque of 1e200, `--rate 1e9`) is a clear error
//! naming the row and column or the setting, instead of a hang, an abort on an impossible
//! allocation, or NaN in a result.
//!
//! Magnitudes apply to the raw columns of a data file (in whatever unit it uses: degrees,
//! motor-side angles, mN m, A) and again to the joint-side signals after the config's
//! units and drive chain:
//!
//! | quantity | limit |
//! |---|---|
//! | position (rad, m, deg) | magnitude at most [`MAX_POSITION`] = 1e6 |
//! | velocity | magnitude at most [`MAX_VELOCITY`] = 1e6 |
//! | acceleration | magnitude at most [`MAX_ACCELERATION`] = 1e8 |
//! | torque, force or current | magnitude at most [`MAX_TORQUE`] = 1e7 |
//! | time (s, after `time_scale`) | magnitude at most [`MAX_TIME`] = 1e10 s |
//! | temperature (deg C) | [`MIN_TEMPERATURE`] = -273.15 deg C (absolute zero) to [`MAX_TEMPERATURE`] = 1e3 deg C |
//! | sample rate | [`MIN_SAMPLE_RATE`] = 1e-3 Hz <= rate <= [`MAX_SAMPLE_RATE`] = 1e7 Hz (also for a rate derived from time stamps) |
//! | parameter values and standard deviations given as input | magnitude at most [`MAX_PARAMETER`] = 1e6 |
//! | base parameters of a simulation or a design's torque check (also derived from standard ones) | magnitude at most [`MAX_BASE_PARAMETER`] = 1e14 |
//! | encoder resolution of a simulation (`Noise::quantization`) | 0, or [`MIN_RESOLUTION`] = 1e-12 to [`MAX_POSITION`] |
//! | a joint's limits for an excitation design | velocity, acceleration and torque limits, and the span of the position limits, at least [`MIN_JOINT_LIMIT`] = 1e-6 |
//! | unit and drive factors (`time_scale`, `torque_scale`, gear ratios, couplings, torque constants, rotor terms, extra-column coefficients) | magnitude at most [`MAX_FACTOR`] = 1e6; the factors that scale a signal (`time_scale`, `torque_scale`, gear ratios, torque constants, also those of a joint-flexibility file) also magnitude at least [`MIN_FACTOR`] = 1e-12 |
//!
//! Sizes are checked before anything of that size is allocated:
//!
//! | size | limit |
//! |---|---|
//! | file size (after gzip decompression) | [`MAX_FILE_BYTES`] = 4 GiB |
//! | header fields of a CSV file | [`MAX_COLUMNS`] = 10,000 |
//! | data rows of a CSV file | [`MAX_ROWS`] = 50,000,000 |
//! | joints of a model | [`MAX_JOINTS`] = 64 |
//! | samples of a trajectory or simulation (duration x rate) | [`MAX_SAMPLES`] = 10,000,000 |
//! | values of a trajectory (samples x (3 joints + 1)) | [`MAX_TRAJECTORY_VALUES`] = 2^28 (2 GiB) |
//! | regressor channels x samples before decimation | [`MAX_OBSERVATION_ENTRIES`] = 2^30 (8 GiB) |
//! | extra regressor columns of a config | [`MAX_EXTRA_COLUMNS`] = 1,000 |
//! | total decimation factor | [`MAX_DECIMATION`] = 10,000 |
//! | Savitzky-Golay window and order | window odd, 3 to [`MAX_SAVGOL_WINDOW`] = 1,001; order 2 to [`MAX_SAVGOL_ORDER`] = 10, below the window |
//!
//! Solvers stop at iteration caps ([`SVD_ITERATIONS`] for the SVD of least squares; the
//! optimisers at their documented evaluation and step counts).

/// Largest |position| accepted (rad, m, or degrees; joint or motor side).
pub const MAX_POSITION: f64 = 1e6;
/// Largest |velocity| accepted.
pub const MAX_VELOCITY: f64 = 1e6;
/// Largest |acceleration| accepted.
pub const MAX_ACCELERATION: f64 = 1e8;
/// Largest |torque|, |force| or |current| accepted (raw column or joint side).
pub const MAX_TORQUE: f64 = 1e7;
/// Largest |time| accepted, in seconds (after `time_scale`; a Unix time stamp fits).
pub const MAX_TIME: f64 = 1e10;
/// Largest |temperature| (deg C): beyond any drive, while a temperature in Kelvin or
/// Fahrenheit still passes (its coefficients are then per K or per deg F).
pub const MAX_TEMPERATURE: f64 = 1e3;
/// Smallest temperature (deg C): absolute zero. A colder value is no measurement (a sensor
/// fault, an offset), and a friction model's temperature term would extrapolate to it.
pub const MIN_TEMPERATURE: f64 = -273.15;
/// Largest sample rate (Hz), given or derived from time stamps.
pub const MAX_SAMPLE_RATE: f64 = 1e7;
/// Smallest sample rate (Hz), given or derived from time stamps (one sample per 1000 s).
pub const MIN_SAMPLE_RATE: f64 = 1e-3;
/// Largest |factor| of a unit or drive-chain setting.
pub const MAX_FACTOR: f64 = 1e6;
/// Smallest |factor| of a unit or drive-chain setting that scales a signal (`time_scale`,
/// `torque_scale`, gear ratios, torque constants): a smaller one erases the signal.
pub const MIN_FACTOR: f64 = 1e-12;
/// Smallest velocity, acceleration or torque limit of a joint, and smallest span of its
/// position limits, that an excitation design takes: below it the joint cannot move or
/// push enough for its trajectory to excite anything (a limit of 1e-320 gave a criterion
/// that is not finite and an error naming no joint).
pub const MIN_JOINT_LIMIT: f64 = 1e-6;
/// Smallest encoder resolution (rad or m per count) a simulation quantizes to; 0 turns
/// quantization off. The finest encoders count about 2^32 per turn (1.5e-9 rad); a
/// resolution of 1e-320, meant as 0, overflowed `q / resolution` and made the simulation
/// "diverge" at its first sample. From 1e-12 on, `q / resolution` stays below 1e18 for every
/// position within [`MAX_POSITION`].
pub const MIN_RESOLUTION: f64 = 1e-12;
/// Largest |value| and standard deviation of a base or standard parameter given as input
/// (identified values for the feasible search, reference parameters of a simulation or a
/// design): kg, kg m, kg m^2, N m s/rad, N m.
pub const MAX_PARAMETER: f64 = 1e6;
/// Largest |value| of a base parameter that a simulation or an excitation design's torque
/// check takes. Base parameters are sums of standard ones, each at most
/// [`MAX_PARAMETER`], weighted by up to two lengths of a description (up to 1 km each),
/// so valid standard values can give base values far above [`MAX_PARAMETER`]
/// (`ZZR1 = ZZ1 + YY2 + 0.35 M4 + ...` of 2.4e6 from three values of 1e6); the
/// arithmetic stays finite far beyond this cap, and the torques are checked on their own.
pub const MAX_BASE_PARAMETER: f64 = 1e14;

/// Largest file read (bytes, after decompression).
pub const MAX_FILE_BYTES: u64 = 4 << 30;

/// Largest text file read whole (bytes): identification configs, parameter, friction,
/// joint-flexibility and bounds files, and identification results (JSON) given back to
/// `robid feasible`. Such a file has kilobytes; the limit keeps a device or a pipe that
/// never ends (`--parameters /dev/zero`) from filling the memory: it took 8 to 14 GB and
/// did not end ([`crate::data::read_text`]).
pub const MAX_TEXT_BYTES: usize = 64 << 20;
/// Longest line of a CSV file (bytes): the windows of its text grow to hold a line whole,
/// and a device or a binary file without line ends (`--states /dev/zero`) took 8 GB
/// before the file limit stopped it. A log's line of [`MAX_COLUMNS`] fields has a few
/// hundred kB.
pub const MAX_LINE_BYTES: usize = 16 << 20;
/// Largest number of fields in a CSV header.
pub const MAX_COLUMNS: usize = 10_000;
/// Largest number of data rows in a CSV file.
pub const MAX_ROWS: usize = 50_000_000;
/// Largest number of joints.
pub const MAX_JOINTS: usize = 64;
/// Largest number of samples of a trajectory or a simulation (duration x rate).
pub const MAX_SAMPLES: usize = 10_000_000;
/// Largest number of values of a trajectory or simulated record (samples x (3 joints + 1)).
pub const MAX_TRAJECTORY_VALUES: usize = 1 << 28;
/// Largest number of regressor values held before decimation (channels x samples).
pub const MAX_OBSERVATION_ENTRIES: usize = 1 << 30;
/// Largest number of extra regressor columns.
pub const MAX_EXTRA_COLUMNS: usize = 1_000;
/// Largest total decimation factor.
pub const MAX_DECIMATION: usize = 10_000;
/// Longest Savitzky-Golay window (samples): its edge coefficients are window^2 numbers.
pub const MAX_SAVGOL_WINDOW: usize = 1_001;
/// Highest polynomial order of a Savitzky-Golay fit.
pub const MAX_SAVGOL_ORDER: usize = 10;

/// Iteration cap of the SVD in least squares (nalgebra's `try_svd`).
pub const SVD_ITERATIONS: usize = 10_000;

/// Which physical quantity a signal holds: it selects the range checked.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum Quantity {
    /// Position (rad, m or degrees).
    Position,
    /// Velocity.
    Velocity,
    /// Acceleration.
    Acceleration,
    /// Torque, force or current.
    Torque,
    /// Time (s).
    Time,
    /// Temperature (deg C).
    Temperature,
    /// An entry of a mass matrix (kg m^2, or kg for a prismatic joint).
    Inertia,
}

impl Quantity {
    /// The largest accepted magnitude.
    pub fn limit(self) -> f64 {
        match self {
            Quantity::Position => MAX_POSITION,
            Quantity::Velocity => MAX_VELOCITY,
            Quantity::Acceleration => MAX_ACCELERATION,
            Quantity::Torque => MAX_TORQUE,
            Quantity::Time => MAX_TIME,
            Quantity::Temperature => MAX_TEMPERATURE,
            Quantity::Inertia => MAX_PARAMETER,
        }
    }

    /// The smallest accepted value: `-limit`, but absolute zero for a temperature.
    pub fn lower(self) -> f64 {
        match self {
            Quantity::Temperature => MIN_TEMPERATURE,
            q => -q.limit(),
        }
    }

    /// The word used in messages.
    pub fn name(self) -> &'static str {
        match self {
            Quantity::Position => "position",
            Quantity::Velocity => "velocity",
            Quantity::Acceleration => "acceleration",
            Quantity::Torque => "torque",
            Quantity::Time => "time",
            Quantity::Temperature => "temperature",
            Quantity::Inertia => "mass-matrix entry",
        }
    }

    /// Index of the first value outside the range [`Quantity::lower`] to
    /// [`Quantity::limit`] (NaN included), if any.
    pub fn first_outside(self, values: &[f64]) -> Option<usize> {
        let (lower, limit) = (self.lower(), self.limit());
        values.iter().position(|&v| !(lower <= v && v <= limit))
    }
}

/// Checks the size of a trajectory of `duration` s at `rate` Hz for `dof` joints before it
/// is allocated; `owner` names the function in errors. Returns the number of samples,
/// both ends included.
pub(crate) fn trajectory_samples(
    owner: &str,
    duration: f64,
    rate: f64,
    dof: usize,
) -> crate::Result<usize> {
    if !(duration > 0.0 && duration.is_finite()) {
        return Err(crate::Error::setting(
            owner,
            "duration",
            format!(
                "{} s must be positive and finite",
                crate::error::num(duration)
            ),
        ));
    }
    if !(MIN_SAMPLE_RATE..=MAX_SAMPLE_RATE).contains(&rate) {
        return Err(crate::Error::setting(
            owner,
            "rate",
            format!(
                "{} Hz must lie in [{MIN_SAMPLE_RATE:e}, {MAX_SAMPLE_RATE:e}] Hz",
                crate::error::num(rate)
            ),
        ));
    }
    // t = 0, 1 / rate, .., duration inclusive: a duration of no whole number of sample
    // periods ended a period past it or short of it, off the rest at its end
    let periods = duration * rate;
    if periods.is_finite() && (periods - periods.round()).abs() > 1e-9 * periods.max(1.0) {
        return Err(crate::Error::setting(
            owner,
            "duration",
            format!(
                "{} s at a rate of {} Hz is {} sample periods, not a whole number, so the \
                 last sample would miss its end; choose a multiple of 1 / rate ({} s)",
                crate::error::num(duration),
                crate::error::num(rate),
                crate::error::num(periods),
                crate::error::num(1.0 / rate)
            ),
        ));
    }
    let samples = periods.round() + 1.0;
    check_size(
        || {
            format!(
                "trajectory samples ({} s at {} Hz)",
                crate::error::num(duration),
                crate::error::num(rate)
            )
        },
        samples,
        MAX_SAMPLES,
        "shorten the duration or lower the rate",
    )?;
    check_size(
        || {
            format!(
                "trajectory values ({samples} samples x {} signals)",
                3 * dof + 1
            )
        },
        samples * (3 * dof + 1) as f64,
        MAX_TRAJECTORY_VALUES,
        "shorten the duration or lower the rate",
    )?;
    Ok(samples as usize)
}

/// Checks that `count` (computed in floating point, so that an overflow is seen) is at
/// most `limit`.
pub(crate) fn check_size(
    what: impl FnOnce() -> String,
    count: f64,
    limit: usize,
    fix: &str,
) -> crate::Result<()> {
    if count.is_finite() && count <= limit as f64 {
        Ok(())
    } else {
        Err(crate::Error::TooLarge {
            what: what(),
            found: count,
            limit,
            fix: fix.to_string(),
        })
    }
}
