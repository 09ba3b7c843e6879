//! Signal processing: zero-phase low-pass filters, differentiation, decimation and
//! removal of samples near rest, spectra (docs/identification.md#signal-processing).

mod decimate;
mod design;
mod diff;
pub(crate) mod passes;
mod rest;
mod savgol;
mod signals;
mod sos;
mod spectrum;

pub(crate) use decimate::decimation_too_large;
pub use decimate::{Decimator, split_factor};
pub use design::{
    MAX_CUTOFF, MAX_RIPPLE, MIN_CUTOFF, MIN_RIPPLE, butterworth, butterworth_hz, chebyshev1,
};
pub use diff::central_difference;
pub use rest::moving_samples;
pub use savgol::{SavitzkyGolay, SavitzkyGolayKernel};
pub use signals::Signals;
pub use sos::Sos;
pub use spectrum::{MIN_SPECTRUM_SAMPLES, Spectrum, Welch};
