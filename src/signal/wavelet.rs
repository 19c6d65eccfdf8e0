//! Continuous wavelet transform with the complex Morlet wavelet, computed with FFTs as in
//! Torrence & Compo (1998), "A practical guide to wavelet analysis", BAMS 79:61-78 (T&C).
//!
//! Math (T&C eqs. 1-6, Table 1), for a series x_n, n = 0..N-1, spacing dt:
//! - mother wavelet `psi0(eta) = pi^(-1/4) exp(i w0 eta) exp(-eta^2/2)`, `w0 = 6`, whose Fourier
//!   transform (analytic part) is `psi0^(s w) = pi^(-1/4) H(w) exp(-(s w - w0)^2 / 2)`, H the
//!   Heaviside step (the negative-frequency tail of the time-domain Morlet is below
//!   `exp(-w0^2/2) = 1.5e-8` and is dropped, as T&C do);
//! - x^_k = (1/L) sum_n x_n exp(-2 pi i k n / L) on the zero-padded series of length L (eq. 3);
//! - `W_n(s) = sum_k x^_k psi^*(s w_k) exp(i w_k n dt)` (eq. 4) with the unit-energy
//!   normalisation `psi^(s w_k) = (2 pi s / dt)^(1/2) psi0^(s w_k)` (eq. 6) and
//!   `w_k = 2 pi k / (L dt)` for k <= L/2, negative above (eq. 5);
//! - wavelet power `|W_n(s)|^2`; with this normalisation white noise of variance sigma^2 has
//!   expected power sigma^2 at every n and s (T&C section 3, "Wavelet power spectrum");
//! - Fourier period `lambda s`, `lambda = 4 pi / (w0 + sqrt(2 + w0^2))` (Table 1; 1.033 for
//!   w0 = 6); reported frequency `1 / (lambda s)`. For a pure tone, the continuous-scale maximum
//!   of `|W|^2` lies exactly at this frequency (d/ds [s exp(-(s w - w0)^2)] = 0 gives
//!   `s w = (w0 + sqrt(w0^2 + 2)) / 2`);
//! - cone of influence: the e-folding time of the Morlet power at scale s is `sqrt(2) s`
//!   (T&C section 3, "Cone of influence"); at time index n the distance to the nearer end is
//!   `t_edge = min(n, N-1-n) dt` and periods longer than `lambda t_edge / sqrt(2)` are
//!   affected by the ends.
//!
//! The mean is removed before transforming (as T&C's reference code does) so that the zero
//! padding does not introduce a step. Padding: L is the smallest 2^a 3^b 5^c length with
//! `L >= N + min(6 sqrt(2) s_max / dt, 2 N)`: six e-folding times of the largest wavelet
//! (envelope `exp(-36) = 2e-16`), so the circular convolution equals the linear one with
//! zeros outside the record.

use std::f64::consts::PI;
use std::sync::Arc;

use ndarray::{Array1, Array2};
use rayon::prelude::*;
use rustfft::{num_complex::Complex, Fft, FftPlanner};

use crate::{Error, Result};

/// Morlet non-dimensional frequency w0 (T&C use 6, which makes the wavelet admissible to
/// within round-off).
pub const MORLET_OMEGA0: f64 = 6.0;

/// Default scales per octave: 16 voices keep the ridge of a tone within 2 % of its peak power
/// between scales (the growth analysis relies on it, [`crate::analysis::growth`]).
pub const DEFAULT_VOICES_PER_OCTAVE: usize = 16;

/// Most scales per octave accepted.
pub const MAX_VOICES_PER_OCTAVE: usize = 64;

/// Largest wavelet power map computed (bytes of `f64` values): 2 GiB, a tenth of this
/// project's 24 GB machines, so a mistaken band or stride is refused with the size instead of
/// exhausting memory.
pub const MAX_POWER_MAP_BYTES: usize = 2 << 30;

/// Fourier period / scale for the Morlet wavelet, `4 pi / (w0 + sqrt(2 + w0^2))` (T&C Table 1).
pub fn morlet_fourier_factor(omega0: f64) -> f64 {
    4.0 * PI / (omega0 + (2.0 + omega0 * omega0).sqrt())
}

/// Which scales to compute.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum Scales {
    /// `s_j = s0 2^(j dj)`, j = 0..=J (T&C eqs. 9-10).
    LogSpaced {
        /// Smallest scale s0, s.
        smallest_scale_s: f64,
        /// Spacing dj in octaves (1/dj voices per octave).
        octaves_per_step: f64,
        /// Largest index J (J + 1 scales).
        largest_index: usize,
    },
    /// Scales whose Fourier frequency `1 / (lambda s)` is each of these, Hz.
    Frequencies(Vec<f64>),
}

impl Scales {
    /// Log-spaced scales covering `[min_frequency_hz, max_frequency_hz]` with
    /// `voices_per_octave` scales per octave, starting at `max_frequency_hz` (smallest scale).
    pub fn from_frequency_band(
        min_frequency_hz: f64,
        max_frequency_hz: f64,
        voices_per_octave: usize,
    ) -> Result<Self> {
        if !(min_frequency_hz.is_finite() && min_frequency_hz > 0.0) {
            return Err(Error::input(
                "cwt",
                "fmin",
                format!("{min_frequency_hz} Hz must be finite and > 0"),
            ));
        }
        if !(max_frequency_hz.is_finite() && max_frequency_hz > min_frequency_hz) {
            return Err(Error::input(
                "cwt",
                "fmax",
                format!("{max_frequency_hz} Hz must be finite and > fmin = {min_frequency_hz} Hz"),
            ));
        }
        // 64 voices resolve a ridge 1.1 % in frequency, far finer than the Morlet's own
        // bandwidth; more only multiplies the memory (scales x samples x 8 bytes).
        if !(1..=MAX_VOICES_PER_OCTAVE).contains(&voices_per_octave) {
            return Err(Error::input(
                "cwt",
                "--voices",
                format!(
                    "voices per octave must be in [1, {MAX_VOICES_PER_OCTAVE}], got \
                     {voices_per_octave}"
                ),
            ));
        }
        let octaves_per_step = 1.0 / voices_per_octave as f64;
        let octaves = (max_frequency_hz / min_frequency_hz).log2();
        // Small tolerance so that an exact number of octaves does not gain a spurious scale.
        let largest_index = (octaves / octaves_per_step - 1e-9).ceil().max(0.0) as usize;
        Ok(Scales::LogSpaced {
            smallest_scale_s: 1.0 / (morlet_fourier_factor(MORLET_OMEGA0) * max_frequency_hz),
            octaves_per_step,
            largest_index,
        })
    }

    /// The scales in seconds.
    pub fn scales_s(&self) -> Vec<f64> {
        match self {
            Scales::LogSpaced {
                smallest_scale_s,
                octaves_per_step,
                largest_index,
            } => (0..=*largest_index)
                .map(|j| smallest_scale_s * 2f64.powf(j as f64 * octaves_per_step))
                .collect(),
            Scales::Frequencies(frequencies_hz) => {
                let lambda = morlet_fourier_factor(MORLET_OMEGA0);
                frequencies_hz.iter().map(|f| 1.0 / (lambda * f)).collect()
            }
        }
    }
}

/// Morlet wavelet power of a series.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct WaveletPower {
    /// Sample rate of the series, Hz.
    pub sample_rate_hz: f64,
    /// Number of time samples N.
    pub time_count: usize,
    /// Scales s_j, s.
    pub scale_s: Array1<f64>,
    /// Fourier frequency of each scale, `1 / (lambda s_j)`, Hz (the column axis of `power`).
    pub frequency_hz: Array1<f64>,
    /// `|W_n(s_j)|^2` in signal unit^2, shape **time x frequency**: `power[[n, j]]` is time
    /// sample n (t = n / fs) and scale j.
    pub power: Array2<f64>,
    /// Cone of influence per time sample: Fourier periods longer than this are affected by the
    /// record ends, s (0 at the first and last sample).
    pub coi_period_s: Array1<f64>,
}

impl WaveletPower {
    /// Number of scales (frequencies).
    pub fn frequency_count(&self) -> usize {
        self.frequency_hz.len()
    }

    /// `|W|^2` at time sample `time_index` and scale `frequency_index`.
    pub fn power_at(&self, time_index: usize, frequency_index: usize) -> f64 {
        self.power[[time_index, frequency_index]]
    }

    /// Cone of influence as a frequency per time sample: frequencies below it are affected by
    /// the record ends, Hz (infinite at the first and last sample).
    pub fn coi_frequency_hz(&self) -> Vec<f64> {
        self.coi_period_s.iter().map(|p| 1.0 / p).collect()
    }

    /// Whether (time sample, scale) lies outside the cone of influence (unaffected by the ends).
    pub fn is_reliable(&self, time_index: usize, frequency_index: usize) -> bool {
        1.0 / self.frequency_hz[frequency_index] <= self.coi_period_s[time_index]
    }
}

/// Smallest `2^a 3^b 5^c >= n` (lengths rustfft transforms fastest).
fn fast_fft_length(n: usize) -> usize {
    let mut best = n.next_power_of_two();
    let mut p5 = 1usize;
    while p5 < best {
        let mut p35 = p5;
        while p35 < best {
            let mut candidate = p35;
            while candidate < n {
                candidate *= 2;
            }
            best = best.min(candidate);
            p35 *= 3;
        }
        p5 *= 5;
    }
    best
}

/// Morlet CWT power of `signal` sampled at `sample_rate_hz` (see the module documentation).
///
/// The phases: checks of the signal and the scales, the padded length, the signal's FFT
/// (shared by every scale), one inverse transform per scale, and the result's layout.
pub fn morlet_cwt(signal: &[f64], sample_rate_hz: f64, scales: &Scales) -> Result<WaveletPower> {
    check_signal(signal, sample_rate_hz)?;
    let n = signal.len();
    let dt = 1.0 / sample_rate_hz;
    let lambda = morlet_fourier_factor(MORLET_OMEGA0);
    let scale_s = scales.scales_s();
    check_scales(&scale_s, lambda, sample_rate_hz, n)?;
    let padded_length = fft_length_for(&scale_s, dt, n);

    let mut planner = FftPlanner::<f64>::new();
    let forward: Arc<dyn Fft<f64>> = planner.plan_fft_forward(padded_length);
    let inverse: Arc<dyn Fft<f64>> = planner.plan_fft_inverse(padded_length);

    let signal_hat = signal_spectrum(signal, padded_length, &*forward);
    let power_by_scale = power_rows(&signal_hat, &scale_s, dt, n, &*inverse);
    let power = time_by_frequency(&power_by_scale, n);

    let coi_period_s =
        Array1::from_shape_fn(n, |i| lambda * (i.min(n - 1 - i) as f64 * dt) / 2f64.sqrt());
    let frequency_hz = scale_s.iter().map(|s| 1.0 / (lambda * s)).collect();
    Ok(WaveletPower {
        sample_rate_hz,
        time_count: n,
        scale_s: Array1::from_vec(scale_s),
        frequency_hz,
        power,
        coi_period_s,
    })
}

/// The series must be usable: a finite positive sample rate, at least two samples, every
/// sample finite (one NaN would spread through every FFT bin).
fn check_signal(signal: &[f64], sample_rate_hz: f64) -> Result<()> {
    if !(sample_rate_hz.is_finite() && sample_rate_hz > 0.0) {
        return Err(Error::input(
            "cwt",
            "sample_rate_hz",
            format!("{sample_rate_hz} Hz must be finite and > 0"),
        ));
    }
    let n = signal.len();
    if n < 2 {
        return Err(Error::input(
            "cwt",
            "signal",
            format!("{n} samples; need at least 2"),
        ));
    }
    if let Some(index) = signal.iter().position(|v| !v.is_finite()) {
        return Err(Error::input(
            "cwt",
            "signal",
            format!("sample {index} is not finite"),
        ));
    }
    Ok(())
}

/// The scales must be some, each finite and positive, with a Fourier frequency `1 / (lambda
/// s)` at most the Nyquist frequency (above it the wavelet is not resolved by the sampling),
/// and their power map over `n` samples within [`MAX_POWER_MAP_BYTES`].
fn check_scales(scale_s: &[f64], lambda: f64, sample_rate_hz: f64, n: usize) -> Result<()> {
    if scale_s.is_empty() {
        return Err(Error::input("cwt", "scales", "no scales requested"));
    }
    let map_bytes = scale_s.len().saturating_mul(n).saturating_mul(8);
    if map_bytes > MAX_POWER_MAP_BYTES {
        return Err(Error::input(
            "cwt",
            "scales",
            format!(
                "{} scales x {n} samples need {:.1} GiB for the power map, more than the {} GiB \
                 allowed: narrow the band, use fewer voices or a shorter record",
                scale_s.len(),
                map_bytes as f64 / (1u64 << 30) as f64,
                MAX_POWER_MAP_BYTES >> 30
            ),
        ));
    }
    let nyquist_hz = sample_rate_hz / 2.0;
    for &s in scale_s {
        let frequency_hz = 1.0 / (lambda * s);
        if !(s.is_finite() && s > 0.0) {
            return Err(Error::input(
                "cwt",
                "frequency_hz",
                format!("scale {s} s is not finite and > 0"),
            ));
        }
        if frequency_hz > nyquist_hz * (1.0 + 1e-12) {
            return Err(Error::input(
                "cwt",
                "fmax",
                format!(
                    "frequency {frequency_hz} Hz is above the Nyquist frequency {nyquist_hz} Hz of the \
                     {sample_rate_hz} Hz sample rate; allowed: (0, {nyquist_hz}] Hz"
                ),
            ));
        }
    }
    Ok(())
}

/// The FFT length L: the record plus the zero padding, rounded up to a fast length.
fn fft_length_for(scale_s: &[f64], dt: f64, n: usize) -> usize {
    // Zero padding (module documentation): six e-folding times of the largest wavelet, capped.
    let largest_scale_s = scale_s.iter().cloned().fold(0.0, f64::max);
    let halfwidth_samples = ((6.0 * 2f64.sqrt() * largest_scale_s / dt).ceil() as usize).min(2 * n);
    fast_fft_length(n + halfwidth_samples)
}

/// The spectrum `x^_k` of the mean-removed series, zero-padded to `padded_length`: computed
/// once and shared by every scale's product.
fn signal_spectrum(
    signal: &[f64],
    padded_length: usize,
    forward: &dyn Fft<f64>,
) -> Vec<Complex<f64>> {
    // x^_k of the mean-removed, zero-padded series (eq. 3, including the 1/L).
    let n = signal.len();
    let mean = signal.iter().sum::<f64>() / n as f64;
    let mut signal_hat = vec![Complex::new(0.0, 0.0); padded_length];
    for (z, x) in signal_hat.iter_mut().zip(signal) {
        *z = Complex::new(x - mean, 0.0);
    }
    forward.process(&mut signal_hat);
    let inv_length = 1.0 / padded_length as f64;
    for z in signal_hat.iter_mut() {
        *z *= inv_length;
    }
    signal_hat
}

/// `|W_n(s)|^2` for n < `n`, one row per scale (eq. 4): the spectrum times the scaled
/// wavelet's, transformed back. The scales run in parallel, each worker with its own buffers.
fn power_rows(
    signal_hat: &[Complex<f64>],
    scale_s: &[f64],
    dt: f64,
    n: usize,
    inverse: &dyn Fft<f64>,
) -> Vec<Vec<f64>> {
    let padded_length = signal_hat.len();
    // One row of |W|^2 per scale, in parallel; each worker owns its buffers.
    let angular_step = 2.0 * PI / (padded_length as f64 * dt);
    let positive_end = padded_length / 2; // w_k > 0 for k = 1..=L/2 (eq. 5)
    let quarter_root_pi = PI.powf(-0.25);
    scale_s
        .par_iter()
        .map_init(
            || {
                let scratch = vec![Complex::new(0.0, 0.0); inverse.get_inplace_scratch_len()];
                (vec![Complex::new(0.0, 0.0); padded_length], scratch)
            },
            |(product, scratch), &s| {
                let norm = (2.0 * PI * s / dt).sqrt() * quarter_root_pi; // eq. 6 x Table 1
                product.iter_mut().for_each(|z| *z = Complex::new(0.0, 0.0));
                for k in 1..=positive_end {
                    let offset = s * angular_step * k as f64 - MORLET_OMEGA0;
                    // exp(-x) underflows to 0 for x > ~745; skip the far tail.
                    if offset * offset > 1400.0 {
                        if offset > 0.0 {
                            break;
                        }
                        continue;
                    }
                    product[k] = signal_hat[k] * (norm * (-0.5 * offset * offset).exp());
                }
                inverse.process_with_scratch(product, scratch);
                product[..n]
                    .iter()
                    .map(|w| w.norm_sqr())
                    .collect::<Vec<f64>>()
            },
        )
        .collect()
}

/// The rows of [`power_rows`] transposed to time x frequency (`power[[n, j]]`).
fn time_by_frequency(power_by_scale: &[Vec<f64>], n: usize) -> Array2<f64> {
    // Transpose to time x frequency.
    let frequency_count = power_by_scale.len();
    let mut power = Array2::zeros((n, frequency_count));
    for (j, row) in power_by_scale.iter().enumerate() {
        for (time_index, value) in row.iter().enumerate() {
            power[[time_index, j]] = *value;
        }
    }
    power
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fourier_factor_matches_torrence_compo_table_1() {
        assert!((morlet_fourier_factor(6.0) - 1.0330).abs() < 1e-4);
    }

    #[test]
    fn fast_length_is_a_5_smooth_number_at_least_n() {
        assert_eq!(fast_fft_length(1000), 1000);
        assert_eq!(fast_fft_length(1001), 1024);
        assert_eq!(fast_fft_length(97), 100);
        assert_eq!(fast_fft_length(1), 1);
    }

    #[test]
    fn frequency_above_nyquist_is_an_input_error_naming_the_range() {
        let scales = Scales::from_frequency_band(10.0, 600.0, 8).unwrap();
        let err = morlet_cwt(&vec![0.0; 1000], 1000.0, &scales).unwrap_err();
        assert_eq!(err.exit_code(), 2);
        let text = err.to_string();
        assert!(
            text.contains("fmax") && text.contains("Nyquist") && text.contains("500"),
            "{text}"
        );
    }

    #[test]
    fn bad_band_is_an_input_error() {
        assert!(Scales::from_frequency_band(0.0, 10.0, 4).is_err());
        assert!(Scales::from_frequency_band(20.0, 10.0, 4).is_err());
        assert!(Scales::from_frequency_band(1.0, 10.0, 0).is_err());
    }

    #[test]
    fn band_scales_span_the_band() {
        let scales = Scales::from_frequency_band(100.0, 800.0, 4).unwrap();
        let lambda = morlet_fourier_factor(MORLET_OMEGA0);
        let f: Vec<f64> = scales
            .scales_s()
            .iter()
            .map(|s| 1.0 / (lambda * s))
            .collect();
        assert_eq!(f.len(), 13);
        assert!((f[0] - 800.0).abs() < 1e-9 && (f[12] - 100.0).abs() < 1e-9);
    }
}
