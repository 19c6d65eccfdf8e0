//! Morlet CWT (Torrence & Compo 1998) checks: direct time-domain summation, tone, chirp,
//! switch localisation and white-noise normalisation.

use std::f64::consts::PI;

use squeal::signal::wavelet::{morlet_fourier_factor, MORLET_OMEGA0};
use squeal::signal::{morlet_cwt, Scales};

/// Deterministic standard normal samples (SplitMix64 + Box-Muller).
fn white_noise(count: usize, seed: u64) -> Vec<f64> {
    let mut state = seed;
    let mut next_uniform = move || {
        state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        ((z >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    };
    (0..count)
        .map(|_| {
            let (u, v) = (next_uniform(), next_uniform());
            (-2.0 * u.ln()).sqrt() * (2.0 * PI * v).cos()
        })
        .collect()
}

/// Slow trusted reference: T&C eq. 2 with the eq. 6 normalisation, summed directly over the
/// record (zeros outside): W_n(s) = sum_n' x_n' (dt/s)^(1/2) psi0*((n' - n) dt / s).
fn direct_power(x: &[f64], dt: f64, scale_s: f64, n: usize) -> f64 {
    let (mut re, mut im) = (0.0, 0.0);
    for (m, value) in x.iter().enumerate() {
        let eta = (m as f64 - n as f64) * dt / scale_s;
        let envelope = PI.powf(-0.25) * (-0.5 * eta * eta).exp() * (dt / scale_s).sqrt();
        // conj(exp(i w0 eta)) = exp(-i w0 eta)
        re += value * envelope * (MORLET_OMEGA0 * eta).cos();
        im -= value * envelope * (MORLET_OMEGA0 * eta).sin();
    }
    re * re + im * im
}

/// The FFT CWT equals the direct summation at every sample (the padding makes the circular
/// convolution linear). The only modelling difference is T&C's Heaviside cut of the wavelet
/// spectrum at w <= 0, where the time-domain Morlet has at most exp(-w0^2/2) = 1.5e-8 of its
/// peak; the test signal is mean-free tones whose spectrum near w = 0 is ~1e-2 of the tones',
/// so the expected difference is ~1e-10 of the maximum power, inside the 1e-9 tolerance
/// (measured: 1.8e-10). Scales stay below 0.42 Nyquist: closer to Nyquist the two *differ by
/// design* (measured 4e-4 at 400 Hz for fs = 1 kHz): the sampled time-domain wavelet aliases the
/// part of its spectrum above Nyquist while the FFT form drops it.
#[test]
fn fft_cwt_equals_direct_summation() {
    let sample_rate_hz = 1000.0;
    let dt = 1.0 / sample_rate_hz;
    let x: Vec<f64> = (0..600)
        .map(|i| {
            let t = i as f64 * dt;
            (2.0 * PI * 37.0 * t).sin()
                + 0.6 * (2.0 * PI * 95.0 * t + 0.5).cos()
                + 0.3 * (2.0 * PI * 210.0 * t).sin()
        })
        .collect();
    let mean = x.iter().sum::<f64>() / x.len() as f64;
    let centred: Vec<f64> = x.iter().map(|v| v - mean).collect();
    let cwt = morlet_cwt(
        &x,
        sample_rate_hz,
        &Scales::Frequencies(vec![20.0, 37.0, 95.0, 150.0, 210.0]),
    )
    .unwrap();
    // The power is an Array2 of time x frequency, with the scale and frequency axes beside it.
    assert_eq!(cwt.power.dim(), (x.len(), 5));
    assert_eq!((cwt.scale_s.len(), cwt.frequency_hz.len()), (5, 5));
    assert_eq!(cwt.coi_period_s.len(), x.len());
    let max_power = cwt.power.iter().cloned().fold(0.0, f64::max);
    let mut worst = 0.0f64;
    for (j, &s) in cwt.scale_s.iter().enumerate() {
        let mut worst_here = 0.0f64;
        for n in 0..x.len() {
            let error = (cwt.power[[n, j]] - direct_power(&centred, dt, s, n)).abs() / max_power;
            worst_here = worst_here.max(error);
        }
        println!("  {} Hz: {worst_here:.3e}", cwt.frequency_hz[j]);
        worst = worst.max(worst_here);
    }
    println!("FFT vs direct CWT power: worst |error| / max power = {worst:.3e}");
    assert!(worst < 1e-9, "{worst}");
}

/// A pure tone's time-averaged power (inside the cone of influence) peaks at the tone
/// frequency within one scale step (T&C's Fourier factor puts the continuous maximum exactly
/// on it; the discrete scales add at most half a step).
#[test]
fn tone_power_peaks_at_the_tone_frequency() {
    let sample_rate_hz = 1000.0;
    let tone_hz = 73.0;
    let x: Vec<f64> = (0..4000)
        .map(|i| (2.0 * PI * tone_hz * i as f64 / sample_rate_hz).sin())
        .collect();
    let voices = 16;
    let cwt = morlet_cwt(
        &x,
        sample_rate_hz,
        &Scales::from_frequency_band(20.0, 400.0, voices).unwrap(),
    )
    .unwrap();
    let mean_power: Vec<f64> = (0..cwt.frequency_count())
        .map(|j| {
            let reliable: Vec<usize> = (0..cwt.time_count)
                .filter(|&n| cwt.is_reliable(n, j))
                .collect();
            reliable.iter().map(|&n| cwt.power_at(n, j)).sum::<f64>() / reliable.len().max(1) as f64
        })
        .collect();
    let best = (0..mean_power.len())
        .max_by(|&a, &b| mean_power[a].total_cmp(&mean_power[b]))
        .unwrap();
    let error_octaves = (cwt.frequency_hz[best] / tone_hz).log2().abs();
    println!(
        "tone: peak at {} Hz, {error_octaves:.4} octave from {tone_hz} Hz",
        cwt.frequency_hz[best]
    );
    assert!(error_octaves <= 1.0 / voices as f64);
}

/// The ridge (frequency of maximum power at each time) of a linear chirp 50 -> 250 Hz over
/// 4 s follows the instantaneous frequency within one scale step (2^(1/32) - 1 = 2.2 %) in the
/// central half: the chirp changes by < 1 Hz over a wavelet's e-folding time, so the ridge
/// bias from the sweep is far below the scale quantisation.
#[test]
fn chirp_ridge_follows_the_instantaneous_frequency() {
    let (sample_rate_hz, duration_s, f0, f1) = (2000.0, 4.0, 50.0, 250.0);
    let count = (sample_rate_hz * duration_s) as usize;
    let rate = (f1 - f0) / duration_s;
    let x: Vec<f64> = (0..count)
        .map(|i| {
            let t = i as f64 / sample_rate_hz;
            (2.0 * PI * (f0 * t + 0.5 * rate * t * t)).sin()
        })
        .collect();
    let voices = 32;
    let cwt = morlet_cwt(
        &x,
        sample_rate_hz,
        &Scales::from_frequency_band(30.0, 400.0, voices).unwrap(),
    )
    .unwrap();
    let mut worst = 0.0f64;
    for n in (count / 4..3 * count / 4).step_by(10) {
        let ridge = (0..cwt.frequency_count())
            .max_by(|&a, &b| cwt.power_at(n, a).total_cmp(&cwt.power_at(n, b)))
            .unwrap();
        let instantaneous_hz = f0 + rate * n as f64 / sample_rate_hz;
        worst = worst.max((cwt.frequency_hz[ridge] / instantaneous_hz - 1.0).abs());
    }
    println!("chirp: worst ridge relative error {worst:.4}");
    assert!(worst < 2f64.powf(1.0 / voices as f64) - 1.0);
}

/// A switch from 40 Hz to 120 Hz at sample 2000 (fs = 1 kHz): at each frequency the power,
/// normalised by its plateau, crosses 1/4 (|W| at half its plateau: half the wavelet envelope
/// overlaps the tone) within 3 samples of the switch, i.e. well inside one period of the
/// higher tone (8.3 samples) and the e-folding time sqrt(2) s (11.4 samples at 120 Hz).
#[test]
fn tone_switch_is_localised_in_time() {
    let sample_rate_hz = 1000.0;
    let switch = 2000usize;
    let x: Vec<f64> = (0..4000)
        .map(|i| {
            let t = i as f64 / sample_rate_hz;
            if i < switch {
                (2.0 * PI * 40.0 * t).sin()
            } else {
                (2.0 * PI * 120.0 * t).sin()
            }
        })
        .collect();
    let cwt = morlet_cwt(&x, sample_rate_hz, &Scales::Frequencies(vec![40.0, 120.0])).unwrap();
    let plateau = |j: usize, range: std::ops::Range<usize>| {
        let len = range.len() as f64;
        range.map(|n| cwt.power_at(n, j)).sum::<f64>() / len
    };
    let low_plateau = plateau(0, 500..1500);
    let high_plateau = plateau(1, 2500..3500);
    let low_end = (1000..3000)
        .find(|&n| cwt.power_at(n, 0) < 0.25 * low_plateau)
        .unwrap();
    let high_start = (1000..3000)
        .find(|&n| cwt.power_at(n, 1) > 0.25 * high_plateau)
        .unwrap();
    println!(
        "switch at {switch}: 40 Hz power drops at {low_end}, 120 Hz power rises at {high_start}"
    );
    assert!(low_end.abs_diff(switch) <= 3 && high_start.abs_diff(switch) <= 3);
}

/// T&C section 3 ("Wavelet power spectrum"): with the eq. 6 normalisation the expected power of white noise is sigma^2
/// at every scale. Each scale's time average inside the cone of influence of 2^17 samples is
/// checked within 10 %: |W|^2 is exponentially distributed with a correlation time of about
/// 2.5 s/dt samples, so the largest scale here (s ~ 31 dt) averages ~1700 independent values
/// (relative standard deviation 2.4 %); 10 % is about 4 sigma yet would catch a normalisation
/// error such as a missing sqrt(2 pi) (factor 2.5).
#[test]
fn white_noise_power_equals_the_variance_at_every_scale() {
    let sigma = 2.0;
    let x: Vec<f64> = white_noise(1 << 17, 3).iter().map(|v| sigma * v).collect();
    let n = x.len() as f64;
    let mean = x.iter().sum::<f64>() / n;
    let variance = x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n;
    // Periods 4 to 32 samples (fs = 1 Hz), well inside Nyquist so the wavelet spectrum is whole.
    let cwt = morlet_cwt(
        &x,
        1.0,
        &Scales::from_frequency_band(1.0 / 32.0, 0.25, 4).unwrap(),
    )
    .unwrap();
    let mut worst = 0.0f64;
    for j in 0..cwt.frequency_count() {
        let reliable: Vec<usize> = (0..cwt.time_count)
            .filter(|&t| cwt.is_reliable(t, j))
            .collect();
        let average =
            reliable.iter().map(|&t| cwt.power_at(t, j)).sum::<f64>() / reliable.len() as f64;
        worst = worst.max((average / variance - 1.0).abs());
    }
    println!("white noise: worst |mean power / variance - 1| = {worst:.4}");
    assert!(worst < 0.1);
    assert!((morlet_fourier_factor(MORLET_OMEGA0) - 1.033).abs() < 1e-3);
}
