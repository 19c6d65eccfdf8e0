//! Band-limited resampling by windowed-sinc interpolation.
//!
//! Output sample m sits at time `t_m = m / f_out` (same start as the input), m = 0..M-1 with
//! `M = floor((N - 1) f_out / f_in) + 1`, so the output never extrapolates past the record.
//! In units of input samples, `tau = t f_in`, the interpolating kernel is a low-pass
//! `h(tau) = 2 nu sinc(2 nu tau) w(tau / H)` with cutoff `nu = 0.45 min(f_in, f_out) / f_in`
//! cycles per input sample (10 % below the lower Nyquist, for the transition band), a Blackman
//! window `w(u) = 0.42 + 0.5 cos(pi u) + 0.08 cos(2 pi u)` (|u| <= 1, stopband about -74 dB)
//! and a half-width `H = 32 / (2 nu)` input samples (32 sinc zero crossings each side; the
//! Blackman transition width, about 5.5 / (2H) cycles/sample, then ends below the lower
//! Nyquist). `y_m = sum_n x_n h(tau_m - n) / sum_n h(tau_m - n)`: dividing by the weight sum
//! makes the DC gain exactly 1, including near the ends where the kernel is cut.

use std::f64::consts::PI;

use rayon::prelude::*;

use crate::{Error, Result};

/// Fraction of the lower Nyquist frequency kept by the anti-alias / interpolation filter.
const CUTOFF_FRACTION_OF_NYQUIST: f64 = 0.9;
/// Sinc zero crossings on each side of the kernel.
const ZERO_CROSSINGS: f64 = 32.0;

fn sinc(x: f64) -> f64 {
    if x.abs() < 1e-12 {
        1.0
    } else {
        (PI * x).sin() / (PI * x)
    }
}

/// Resamples `signal` from `input_rate_hz` to `output_rate_hz` (module documentation).
pub fn resample(signal: &[f64], input_rate_hz: f64, output_rate_hz: f64) -> Result<Vec<f64>> {
    for (field, rate) in [
        ("input_rate_hz", input_rate_hz),
        ("output_rate_hz", output_rate_hz),
    ] {
        if !(rate.is_finite() && rate > 0.0) {
            return Err(Error::input(
                "resample",
                field,
                format!("{rate} Hz must be finite and > 0"),
            ));
        }
    }
    if signal.is_empty() {
        return Err(Error::input(
            "resample",
            "signal",
            "the signal is empty; need at least 1 sample",
        ));
    }
    let n = signal.len();
    let output_count =
        ((n - 1) as f64 * output_rate_hz / input_rate_hz + 1e-9).floor() as usize + 1;
    let nu = 0.5 * CUTOFF_FRACTION_OF_NYQUIST * input_rate_hz.min(output_rate_hz) / input_rate_hz;
    let half_width = ZERO_CROSSINGS / (2.0 * nu);
    let step = input_rate_hz / output_rate_hz;

    let output = (0..output_count)
        .into_par_iter()
        .map(|m| {
            let tau = m as f64 * step;
            let first = ((tau - half_width).ceil().max(0.0)) as usize;
            let last = ((tau + half_width).floor() as usize).min(n - 1);
            let (mut weighted, mut weight_sum) = (0.0, 0.0);
            for (i, x) in signal.iter().enumerate().take(last + 1).skip(first) {
                let distance = tau - i as f64;
                let u = distance / half_width;
                let window = 0.42 + 0.5 * (PI * u).cos() + 0.08 * (2.0 * PI * u).cos();
                let weight = 2.0 * nu * sinc(2.0 * nu * distance) * window;
                weighted += weight * x;
                weight_sum += weight;
            }
            if weight_sum.abs() > 1e-300 {
                weighted / weight_sum
            } else {
                0.0
            }
        })
        .collect();
    Ok(output)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn constant_is_preserved_and_length_follows_the_rate_ratio() {
        let y = resample(&[2.5; 1000], 10_000.0, 44_100.0).unwrap();
        assert_eq!(y.len(), (999.0f64 * 4.41).floor() as usize + 1);
        assert!(y.iter().all(|v| (v - 2.5).abs() < 1e-12));
    }

    #[test]
    fn in_band_tone_is_reproduced_away_from_the_ends() {
        let (fi, fo, f) = (48_000.0, 44_100.0, 1_000.0);
        let x: Vec<f64> = (0..4800)
            .map(|i| (2.0 * PI * f * i as f64 / fi).sin())
            .collect();
        let y = resample(&x, fi, fo).unwrap();
        let max_error = (200..y.len() - 200)
            .map(|m| (y[m] - (2.0 * PI * f * m as f64 / fo).sin()).abs())
            .fold(0.0, f64::max);
        assert!(max_error < 1e-3, "{max_error}");
    }

    #[test]
    fn bad_rates_are_input_errors() {
        assert!(resample(&[1.0], 0.0, 1.0).is_err());
        assert!(resample(&[1.0], 1.0, f64::NAN).is_err());
        assert!(resample(&[], 1.0, 1.0).is_err());
    }
}
