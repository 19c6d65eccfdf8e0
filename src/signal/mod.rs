//! Signal analysis for squeal: power spectral density (Welch), continuous wavelet transform
//! (Morlet, Torrence & Compo 1998), spectral peak picking, resampling and WAV export.
//!
//! One concept per module:
//! - [`window`]: tapering windows (SciPy's periodic definitions);
//! - [`detrend`]: per-segment trend removal;
//! - [`welch`]: Welch's averaged-periodogram PSD, matching `scipy.signal.welch`;
//! - [`wavelet`]: Morlet continuous wavelet transform and its cone of influence;
//! - [`peaks`]: local maxima, prominences, selection and sub-bin refinement;
//! - [`resolution`]: Welch parameters for a requested bin spacing (zero padding);
//! - [`ring`]: nodal-diameter decomposition of a field on a ring of equally spaced points;
//! - [`resample`]: band-limited (windowed-sinc) resampling to another rate;
//! - [`wav`]: 16-bit PCM WAV writing/reading;
//! - [`series`]: uniformly sampled time series read from CSV files.

pub mod detrend;
pub mod peaks;
pub mod resample;
pub mod resolution;
pub mod ring;
pub mod series;
pub mod wav;
pub mod wavelet;
pub mod welch;
pub mod window;

pub use detrend::Detrend;
pub use peaks::{find_spectral_peaks, PeakRanking, PeakSearch, SpectralPeak};
pub use series::TimeSeries;
pub use wavelet::{morlet_cwt, Scales, WaveletPower};
pub use welch::{welch, Psd, PsdScaling, WelchParams};
pub use window::Window;
