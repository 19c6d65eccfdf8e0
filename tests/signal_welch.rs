//! Welch PSD against `scipy.signal.welch` (fixture from tests/fixtures/make_welch_fixture.py)
//! and Parseval checks.

use squeal::signal::{welch, Detrend, PsdScaling, WelchParams, Window};

fn fixture() -> serde_json::Value {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/fixtures/welch_scipy.json"
    ))
    .expect("fixture present");
    serde_json::from_str(&text).unwrap()
}

fn floats(value: &serde_json::Value) -> Vec<f64> {
    value
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect()
}

/// Every fixture case agrees with SciPy to 1e-10 of the case's largest PSD value.
///
/// Why relative to the maximum rather than elementwise: the FFT's round-off is an absolute error
/// of about eps * log2(n) * (largest |X|), so bins 10-12 orders of magnitude below the peak
/// (window sidelobe valleys) carry relative errors far above 1e-10 in *both* implementations.
/// Elementwise agreement is additionally checked at 1e-10 on bins above 1e-4 of the maximum.
#[test]
fn welch_matches_scipy_on_all_fixture_cases() {
    let fixture = fixture();
    let signal = floats(&fixture["signal"]);
    let sample_rate_hz = fixture["sample_rate_hz"].as_f64().unwrap();
    let cases = fixture["welch_cases"].as_array().unwrap();
    assert!(cases.len() >= 12);
    assert!(cases.iter().filter(|c| c["nfft"].is_u64()).count() >= 3);
    let mut worst_of_max = 0.0f64;
    let mut worst_elementwise = 0.0f64;
    for case in cases {
        let length = case["signal_length"].as_u64().unwrap() as usize;
        let params = WelchParams {
            nperseg: case["nperseg"].as_u64().unwrap() as usize,
            noverlap: case["noverlap"].as_u64().unwrap() as usize,
            window: case["window"].as_str().unwrap().parse::<Window>().unwrap(),
            detrend: case["detrend"]
                .as_str()
                .unwrap()
                .parse::<Detrend>()
                .unwrap(),
            scaling: match case["scaling"].as_str().unwrap() {
                "density" => PsdScaling::Density,
                _ => PsdScaling::Spectrum,
            },
            nfft: case["nfft"].as_u64().map(|n| n as usize),
        };
        let psd = welch(&signal[..length], sample_rate_hz, &params).unwrap();
        let expected_frequency_hz = floats(&case["frequency_hz"]);
        let expected_psd = floats(&case["psd"]);
        assert_eq!(
            psd.frequency_hz.len(),
            expected_frequency_hz.len(),
            "{params:?}"
        );
        for (f, g) in psd.frequency_hz.iter().zip(&expected_frequency_hz) {
            assert!(
                (f - g).abs() <= 1e-12 * sample_rate_hz,
                "{params:?}: {f} vs {g}"
            );
        }
        let peak = expected_psd.iter().cloned().fold(0.0, f64::max);
        for (k, (p, q)) in psd.psd_per_hz.iter().zip(&expected_psd).enumerate() {
            let of_max = (p - q).abs() / peak;
            worst_of_max = worst_of_max.max(of_max);
            assert!(of_max < 1e-10, "{params:?} bin {k}: {p} vs {q}");
            if *q > 1e-4 * peak {
                let elementwise = (p - q).abs() / q;
                worst_elementwise = worst_elementwise.max(elementwise);
                assert!(elementwise < 1e-10, "{params:?} bin {k}: {p} vs {q}");
            }
        }
    }
    println!("worst |error| / max PSD = {worst_of_max:.3e}; worst elementwise (bins > 1e-4 max) = {worst_elementwise:.3e}");
}

/// Deterministic standard normal samples (SplitMix64 + Box-Muller), so tests need no RNG crate.
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
            (-2.0 * u.ln()).sqrt() * (2.0 * std::f64::consts::PI * v).cos()
        })
        .collect()
}

/// Parseval. With a boxcar window, no overlap, no detrending and nperseg dividing N, the
/// one-sided density integrates *exactly* (DFT Parseval, DC and Nyquist counted once, the other
/// bins twice) to the mean square of the signal: checked to 1e-10. Against the variance the
/// difference is the squared sample mean, ~ sigma^2 / N = 1e-6 relative here, far inside 1 %.
#[test]
fn boxcar_density_integrates_to_the_variance() {
    let sample_rate_hz = 2000.0;
    let x: Vec<f64> = white_noise(1 << 20, 7)
        .iter()
        .map(|v| 1.5 * v + 0.01)
        .collect();
    let params = WelchParams {
        nperseg: 1024,
        noverlap: 0,
        window: Window::Boxcar,
        detrend: Detrend::None,
        scaling: PsdScaling::Density,
        nfft: None,
    };
    let psd = welch(&x, sample_rate_hz, &params).unwrap();
    let integral: f64 = psd.psd_per_hz.iter().sum::<f64>() * psd.frequency_resolution_hz;
    let n = x.len() as f64;
    let mean_square = x.iter().map(|v| v * v).sum::<f64>() / n;
    let mean = x.iter().sum::<f64>() / n;
    let variance = mean_square - mean * mean;
    let exact_error = (integral - mean_square).abs() / mean_square;
    let variance_error = (integral - variance).abs() / variance;
    println!("Parseval boxcar: |int - mean square| / mean square = {exact_error:.3e}; vs variance {variance_error:.3e}");
    assert!(exact_error < 1e-10);
    assert!(variance_error < 0.01);
}

/// With SciPy's defaults (Hann, 50 % overlap, constant detrend) the integral is a
/// window-weighted average of the segment variances; for 2047 segments of white noise its
/// statistical scatter is ~ 1/sqrt(2047 * 1024 / 2) ~ 0.1 % and the detrend bias ~ -0.07 %, so
/// 1 % is a safe bound that still catches any scaling error (the smallest, a missing one-sided
/// doubling, is 50 %).
#[test]
fn hann_density_integrates_to_the_variance_within_one_percent() {
    let x: Vec<f64> = white_noise(1 << 20, 11).iter().map(|v| 0.3 * v).collect();
    let psd = welch(&x, 1.0, &WelchParams::new(1024)).unwrap();
    let integral: f64 = psd.psd_per_hz.iter().sum::<f64>() * psd.frequency_resolution_hz;
    let n = x.len() as f64;
    let mean = x.iter().sum::<f64>() / n;
    let variance = x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n;
    let error = (integral - variance).abs() / variance;
    println!("Parseval Hann: |int - variance| / variance = {error:.3e}");
    assert!(error < 0.01);
}
