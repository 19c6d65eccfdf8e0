//! Peak picking against `scipy.signal.find_peaks` / `peak_prominences` (fixture) and on
//! synthetic spectra.

use std::f64::consts::PI;

use squeal::signal::peaks::{local_maxima, peak_prominences, select_by_distance};
use squeal::signal::{welch, PeakRanking, PeakSearch, WelchParams};

fn floats(value: &serde_json::Value) -> Vec<f64> {
    value
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect()
}

fn indices(value: &serde_json::Value) -> Vec<usize> {
    value
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_u64().unwrap() as usize)
        .collect()
}

#[test]
fn peaks_and_prominences_match_scipy() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/fixtures/welch_scipy.json"
    ))
    .unwrap();
    let fixture: serde_json::Value = serde_json::from_str(&text).unwrap();
    let cases = fixture["peak_cases"].as_array().unwrap();
    assert!(cases.len() >= 7);
    for case in cases {
        let name = case["name"].as_str().unwrap();
        let x = floats(&case["x"]);
        let mut peaks = local_maxima(&x);
        if let Some(distance) = case["distance_samples"].as_u64() {
            let heights: Vec<f64> = peaks.iter().map(|&k| x[k]).collect();
            let keep = select_by_distance(&peaks, &heights, distance as usize);
            peaks = peaks
                .iter()
                .zip(&keep)
                .filter(|(_, keep)| **keep)
                .map(|(k, _)| *k)
                .collect();
        }
        assert_eq!(peaks, indices(&case["peaks"]), "{name}");
        let prominences = peak_prominences(&x, &peaks).unwrap();
        let expected = floats(&case["prominences"]);
        let scale = x.iter().map(|v| v.abs()).fold(0.0, f64::max);
        for ((p, q), (left, right)) in prominences.iter().zip(&expected).zip(
            indices(&case["left_bases"])
                .into_iter()
                .zip(indices(&case["right_bases"])),
        ) {
            // Differences of the same stored values: exact up to JSON parsing (1 ulp).
            assert!(
                (p.prominence - q).abs() <= 1e-14 * scale,
                "{name}: {} vs {q}",
                p.prominence
            );
            assert_eq!((p.left_base, p.right_base), (left, right), "{name}");
        }
    }
}

/// A Hann-windowed tone between bins: the log-parabola puts it within 0.1 bin (measured
/// worst case printed; the theoretical bias for Hann without zero padding is a few hundredths).
#[test]
fn tone_between_bins_is_refined_to_a_tenth_of_a_bin() {
    let sample_rate_hz = 1024.0;
    let nperseg = 256; // 4 Hz bins
    let mut worst_bins = 0.0f64;
    for tenth in 0..=10 {
        let tone_hz = 4.0 * (50.0 + tenth as f64 / 10.0);
        let x: Vec<f64> = (0..16_384)
            .map(|i| (2.0 * PI * tone_hz * i as f64 / sample_rate_hz + 0.4).sin())
            .collect();
        let psd = welch(&x, sample_rate_hz, &WelchParams::new(nperseg)).unwrap();
        let search = PeakSearch {
            max_peaks: 1,
            ..PeakSearch::default()
        };
        let peak = psd.find_peaks(&search).unwrap()[0];
        let error_bins = (peak.refined_frequency_hz - tone_hz).abs() / psd.frequency_resolution_hz;
        worst_bins = worst_bins.max(error_bins);
        assert!(
            error_bins < 0.1,
            "tone {tone_hz} Hz -> {} Hz",
            peak.refined_frequency_hz
        );
    }
    println!("worst refinement error: {worst_bins:.4} bin");
}

/// Three tones in noise (like the paper's (0,0), (0,3), (0,4) peaks): the three dominant peaks
/// by prominence are the tones; a band excludes one; a separation removes the weaker of two
/// close tones; ranking by height is selectable.
#[test]
fn dominant_peaks_band_and_separation() {
    let sample_rate_hz = 8192.0;
    let tones = [(240.0, 1.0), (1010.0, 0.5), (2030.0, 0.3), (1060.0, 0.05)];
    let mut state = 12345u64;
    let x: Vec<f64> = (0..65_536)
        .map(|i| {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let noise = ((state >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 0.02;
            let t = i as f64 / sample_rate_hz;
            noise
                + tones
                    .iter()
                    .map(|(f, a)| a * (2.0 * PI * f * t).sin())
                    .sum::<f64>()
        })
        .collect();
    let psd = welch(&x, sample_rate_hz, &WelchParams::new(2048)).unwrap();
    let found = |search: PeakSearch| -> Vec<f64> {
        psd.find_peaks(&search)
            .unwrap()
            .iter()
            .map(|p| p.refined_frequency_hz)
            .collect()
    };
    let near = |a: f64, b: f64| (a - b).abs() < 1.0;

    let top3 = found(PeakSearch {
        max_peaks: 3,
        ..PeakSearch::default()
    });
    assert!(
        near(top3[0], 240.0) && near(top3[1], 1010.0) && near(top3[2], 2030.0),
        "{top3:?}"
    );

    let band = found(PeakSearch {
        max_peaks: 3,
        min_frequency_hz: 500.0,
        max_frequency_hz: 3000.0,
        ..PeakSearch::default()
    });
    assert!(
        near(band[0], 1010.0) && near(band[1], 2030.0) && near(band[2], 1060.0),
        "{band:?}"
    );

    let separated = found(PeakSearch {
        max_peaks: 4,
        min_separation_hz: 100.0,
        ..PeakSearch::default()
    });
    assert!(!separated.iter().any(|f| near(*f, 1060.0)), "{separated:?}");

    let by_height = found(PeakSearch {
        max_peaks: 2,
        ranking: PeakRanking::Height,
        ..PeakSearch::default()
    });
    assert!(
        near(by_height[0], 240.0) && near(by_height[1], 1010.0),
        "{by_height:?}"
    );
}
