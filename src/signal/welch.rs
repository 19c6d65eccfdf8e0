//! Welch's power spectral density estimate, with the semantics of `scipy.signal.welch`
//! (`average='mean'`, `return_onesided=True`, and `nfft >= nperseg`: each windowed segment
//! zero-padded to `nfft` samples, which interpolates the spectrum onto finer bins without
//! narrowing its main lobe).
//!
//! Math (Welch 1967; SciPy `csd`/`ShortTimeFFT`):
//! - segments of `nperseg` samples start at `m * hop`, `hop = nperseg - noverlap`, for
//!   `m = 0 .. (n - noverlap) / hop` (integer division): a last partial segment is dropped;
//! - each segment is detrended, then multiplied by the window `w`;
//! - `P_m[k] = |X_m[k]|^2 * scale`, `X_m = DFT(segment padded to nfft)`, k = 0..=nfft/2, with
//!   `scale = 1 / (fs * sum w^2)` for `density` (unit^2/Hz) and `1 / (sum w)^2` for
//!   `spectrum` (unit^2);
//! - one-sided: every bin except DC, and except Nyquist when `nfft` is even, is doubled
//!   (it carries the power of its negative-frequency twin);
//! - the estimate is the mean of `P_m` over segments; frequencies are `k * fs / nfft`.
//!
//! Parseval: with `density` scaling, `sum(P) * df` (df = fs/nfft) equals the mean over
//! segments of `sum((w * x_detrended)^2) / sum(w^2)`, i.e. the window-weighted variance.

use std::sync::Arc;

use ndarray::Array1;
use rayon::prelude::*;
use rustfft::{num_complex::Complex, Fft, FftPlanner};

use super::{detrend::Detrend, window::Window};
use crate::{Error, Result};

/// Normalisation of the PSD (SciPy's `scaling`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum PsdScaling {
    /// Power spectral density, unit^2/Hz (SciPy `scaling='density'`).
    #[default]
    Density,
    /// Power spectrum, unit^2 per bin (SciPy `scaling='spectrum'`): a sinusoid of amplitude A
    /// centred on a bin reads A^2/2 there.
    Spectrum,
}

impl PsdScaling {
    /// The command-line / file name of the scaling.
    pub fn name(self) -> &'static str {
        match self {
            PsdScaling::Density => "density",
            PsdScaling::Spectrum => "spectrum",
        }
    }
}

/// Default segment length of a Welch estimate when none is asked for (shorter signals use
/// their whole length): 4096 samples give 12 Hz bins at the rolling runs' 50 kHz sampling.
pub const DEFAULT_NPERSEG: usize = 4096;

/// Default overlap of consecutive segments, as a fraction of the segment (SciPy's default,
/// `noverlap = nperseg / 2`, as [`WelchParams::new`]).
pub const DEFAULT_OVERLAP_FRACTION: f64 = 0.5;

/// Longest FFT a PSD takes (2^26 points: 1 GiB of complex values in flight).
pub const MAX_NFFT: usize = 1 << 26;

/// Parameters of a Welch estimate.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct WelchParams {
    /// Samples per segment (SciPy `nperseg`); also the FFT length unless `nfft` is set.
    pub nperseg: usize,
    /// Samples shared by consecutive segments (SciPy `noverlap`), `0 <= noverlap < nperseg`.
    pub noverlap: usize,
    /// Window applied to each segment.
    pub window: Window,
    /// Trend removed from each segment before windowing.
    pub detrend: Detrend,
    /// Density (unit^2/Hz) or spectrum (unit^2).
    pub scaling: PsdScaling,
    /// FFT length (SciPy `nfft`), `>= nperseg`: segments are zero-padded to it. None: nperseg.
    #[serde(default)]
    pub nfft: Option<usize>,
}

impl WelchParams {
    /// SciPy's defaults for a given segment length: half overlap, Hann, constant detrend,
    /// density scaling.
    pub fn new(nperseg: usize) -> Self {
        WelchParams {
            nperseg,
            noverlap: nperseg / 2,
            window: Window::Hann,
            detrend: Detrend::Constant,
            scaling: PsdScaling::Density,
            nfft: None,
        }
    }

    /// The FFT length: `nfft`, or `nperseg` when not set.
    pub fn fft_length(&self) -> usize {
        self.nfft.unwrap_or(self.nperseg)
    }

    /// Parameters with the overlap given as a fraction of the segment, `0 <= overlap < 1`;
    /// `noverlap = floor(overlap * nperseg)`.
    pub fn with_overlap_fraction(nperseg: usize, overlap: f64) -> Result<Self> {
        if !(0.0..1.0).contains(&overlap) {
            return Err(Error::input(
                "welch",
                "overlap",
                format!("overlap fraction {overlap} is outside the allowed range [0, 1)"),
            ));
        }
        let noverlap = ((overlap * nperseg as f64).floor() as usize).min(nperseg.saturating_sub(1));
        Ok(WelchParams {
            noverlap,
            ..WelchParams::new(nperseg)
        })
    }

    /// Checks the parameters against a signal of `signal_length` samples.
    pub fn validate(&self, signal_length: usize) -> Result<()> {
        if signal_length == 0 {
            return Err(Error::input(
                "welch",
                "signal",
                "the signal is empty; need at least 1 sample",
            ));
        }
        // Two samples at least: a one-sample segment's window is zero (Hann, Hamming at its
        // end) and its spectrum has no frequency but DC.
        if self.nperseg < 2 || self.nperseg > signal_length {
            return Err(Error::input(
                "welch",
                "nperseg",
                format!(
                    "segment length {} is outside the allowed range 2..={signal_length} (the signal length in samples)",
                    self.nperseg
                ),
            ));
        }
        if let Some(nfft) = self.nfft {
            if nfft < self.nperseg || nfft > MAX_NFFT {
                return Err(Error::input(
                    "welch",
                    "nfft",
                    format!(
                        "FFT length {nfft} is outside the allowed range {}..=67108864 (at least \
                         the segment length nperseg)",
                        self.nperseg
                    ),
                ));
            }
        }
        if self.noverlap >= self.nperseg {
            return Err(Error::input(
                "welch",
                "noverlap",
                format!(
                    "overlap of {} samples is outside the allowed range 0..{} (must be less than nperseg)",
                    self.noverlap, self.nperseg
                ),
            ));
        }
        Ok(())
    }

    /// Number of full segments Welch averages (a last partial segment is dropped).
    pub fn segment_count(&self, signal_length: usize) -> usize {
        let hop = self.nperseg - self.noverlap;
        (signal_length - self.noverlap) / hop
    }
}

/// A one-sided Welch spectrum.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Psd {
    /// Bin frequencies `k * fs / nfft`, k = 0..=nfft/2, in Hz (the axis of `psd_per_hz`).
    pub frequency_hz: Array1<f64>,
    /// PSD in signal unit^2/Hz (with [`PsdScaling::Spectrum`]: power per bin, unit^2), one value
    /// per entry of `frequency_hz`.
    pub psd_per_hz: Array1<f64>,
    /// Bin spacing `fs / nfft`, Hz (finer than the main lobe `~ 2 fs / nperseg` of a Hann
    /// window when the segments are zero-padded).
    pub frequency_resolution_hz: f64,
    /// Number of segments averaged.
    pub segment_count: usize,
    /// The parameters used.
    pub params: WelchParams,
}

impl Psd {
    /// The dominant peaks of this spectrum ([`super::find_spectral_peaks`] on its own axes).
    pub fn find_peaks(&self, search: &super::PeakSearch) -> Result<Vec<super::SpectralPeak>> {
        super::find_spectral_peaks(&self.frequency_hz, &self.psd_per_hz, search)
    }
}

/// Segments per deterministic partial sum: the sum order never depends on the thread count.
const SEGMENTS_PER_CHUNK: usize = 32;

/// Welch PSD of `signal` sampled at `sample_rate_hz` (see the module documentation).
pub fn welch(signal: &[f64], sample_rate_hz: f64, params: &WelchParams) -> Result<Psd> {
    if !(sample_rate_hz.is_finite() && sample_rate_hz > 0.0) {
        return Err(Error::input(
            "welch",
            "sample_rate_hz",
            format!("sample rate {sample_rate_hz} Hz must be finite and > 0"),
        ));
    }
    params.validate(signal.len())?;
    if let Some(index) = signal.iter().position(|v| !v.is_finite()) {
        return Err(Error::input(
            "welch",
            "signal",
            format!("sample {index} is not finite"),
        ));
    }

    let nperseg = params.nperseg;
    let nfft = params.fft_length();
    let hop = nperseg - params.noverlap;
    let segment_count = params.segment_count(signal.len());
    let bin_count = nfft / 2 + 1;
    let window = params.window.samples(nperseg);
    let fft: Arc<dyn Fft<f64>> = FftPlanner::new().plan_fft_forward(nfft);

    // Sum of |X_m[k]|^2 over segments, in fixed chunks summed in order (reproducible).
    let chunk_count = segment_count.div_ceil(SEGMENTS_PER_CHUNK);
    let chunk_sums: Vec<Vec<f64>> = (0..chunk_count)
        .into_par_iter()
        .map(|chunk| {
            let mut sums = vec![0.0; bin_count];
            let mut segment = vec![0.0; nperseg];
            let mut spectrum = vec![Complex::new(0.0, 0.0); nfft];
            let mut scratch = vec![Complex::new(0.0, 0.0); fft.get_inplace_scratch_len()];
            let first = chunk * SEGMENTS_PER_CHUNK;
            let last = (first + SEGMENTS_PER_CHUNK).min(segment_count);
            for m in first..last {
                let start = m * hop;
                segment.copy_from_slice(&signal[start..start + nperseg]);
                params.detrend.apply(&mut segment);
                for ((z, x), w) in spectrum.iter_mut().zip(&segment).zip(&window) {
                    *z = Complex::new(x * w, 0.0);
                }
                for z in &mut spectrum[nperseg..] {
                    *z = Complex::new(0.0, 0.0);
                }
                fft.process_with_scratch(&mut spectrum, &mut scratch);
                for (sum, z) in sums.iter_mut().zip(&spectrum[..bin_count]) {
                    *sum += z.norm_sqr();
                }
            }
            sums
        })
        .collect();
    let mut psd_per_hz = vec![0.0; bin_count];
    for sums in &chunk_sums {
        for (total, value) in psd_per_hz.iter_mut().zip(sums) {
            *total += value;
        }
    }

    let scale = match params.scaling {
        PsdScaling::Density => 1.0 / (sample_rate_hz * window.iter().map(|w| w * w).sum::<f64>()),
        PsdScaling::Spectrum => 1.0 / window.iter().sum::<f64>().powi(2),
    };
    // One-sided doubling: all bins but DC and, for even nfft, Nyquist (which has no twin).
    let doubled_end = if nfft.is_multiple_of(2) {
        bin_count - 1
    } else {
        bin_count
    };
    for (k, value) in psd_per_hz.iter_mut().enumerate() {
        let one_sided = if k >= 1 && k < doubled_end { 2.0 } else { 1.0 };
        *value *= scale * one_sided / segment_count as f64;
    }

    // Finite samples near the largest double (1e308) overflow in the detrend's mean or the
    // squared spectrum: an `inf` or NaN PSD is refused rather than written as a result.
    if psd_per_hz.iter().any(|p| !p.is_finite()) {
        let largest = signal.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        return Err(Error::input(
            "welch",
            "signal",
            format!(
                "its power spectral density overflows a double (samples up to {largest:.3e} in \
                 magnitude; the PSD must stay below 1.8e308): scale the signal first"
            ),
        ));
    }
    let frequency_resolution_hz = sample_rate_hz / nfft as f64;
    let frequency_hz = Array1::from_shape_fn(bin_count, |k| k as f64 * frequency_resolution_hz);
    Ok(Psd {
        frequency_hz,
        psd_per_hz: Array1::from_vec(psd_per_hz),
        frequency_resolution_hz,
        segment_count,
        params: *params,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn samples_whose_psd_overflows_are_refused() {
        let signal: Vec<f64> = (0..64)
            .map(|k| if k % 2 == 0 { 1e308 } else { -1e308 })
            .collect();
        let err = welch(&signal, 100.0, &WelchParams::new(16)).unwrap_err();
        assert_eq!(err.exit_code(), 2);
        assert!(err.to_string().contains("overflows"), "{err}");
        // The same shape at an ordinary scale is fine.
        let small: Vec<f64> = signal.iter().map(|v| v * 1e-300).collect();
        assert!(welch(&small, 100.0, &WelchParams::new(16)).is_ok());
    }

    #[test]
    fn segment_longer_than_signal_is_an_input_error_naming_nperseg() {
        let err = welch(&[1.0; 10], 100.0, &WelchParams::new(16)).unwrap_err();
        assert_eq!(err.exit_code(), 2);
        let text = err.to_string();
        assert!(
            text.contains("nperseg") && text.contains("2..=10"),
            "{text}"
        );
        // A one-sample segment has no spectrum (its window is zero): refused the same way.
        let err = welch(&[1.0; 10], 100.0, &WelchParams::new(1)).unwrap_err();
        assert!(err.to_string().contains("2..=10"), "{err}");
    }

    #[test]
    fn overlap_fraction_outside_unit_interval_is_an_input_error() {
        for overlap in [-0.1, 1.0, 1.5, f64::NAN] {
            let err = WelchParams::with_overlap_fraction(64, overlap).unwrap_err();
            assert_eq!(err.exit_code(), 2);
            assert!(err.to_string().contains("[0, 1)"));
        }
        assert_eq!(
            WelchParams::with_overlap_fraction(64, 0.5)
                .unwrap()
                .noverlap,
            32
        );
    }

    #[test]
    fn bad_sample_rate_and_non_finite_samples_are_input_errors() {
        assert!(welch(&[1.0; 10], 0.0, &WelchParams::new(4)).is_err());
        let mut x = vec![0.0; 10];
        x[3] = f64::NAN;
        let err = welch(&x, 1.0, &WelchParams::new(4)).unwrap_err();
        assert!(err.to_string().contains("sample 3"));
    }

    #[test]
    fn centred_tone_with_spectrum_scaling_reads_half_amplitude_squared() {
        // A sinusoid of amplitude 2 exactly on bin 8 of a 64-sample boxcar segment: A^2/2 = 2.
        let n = 640;
        let x: Vec<f64> = (0..n)
            .map(|i| 2.0 * (2.0 * std::f64::consts::PI * 8.0 * i as f64 / 64.0).cos())
            .collect();
        let params = WelchParams {
            window: Window::Boxcar,
            scaling: PsdScaling::Spectrum,
            ..WelchParams::new(64)
        };
        let psd = welch(&x, 64.0, &params).unwrap();
        assert!((psd.psd_per_hz[8] - 2.0).abs() < 1e-12);
        assert!((psd.frequency_hz[8] - 8.0).abs() < 1e-12);
    }
}
