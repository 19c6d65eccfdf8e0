//! WAV export: header, level and that a resampled tone keeps its frequency.

use std::f64::consts::PI;

use squeal::signal::wav::{read_pcm16_wav, write_wav, PEAK_FRACTION_OF_FULL_SCALE};
use squeal::signal::{welch, PeakSearch, WelchParams};

#[test]
fn resampled_tone_reads_back_with_its_header_level_and_frequency() {
    let (input_rate_hz, tone_hz) = (20_000.0, 1234.5);
    // A static offset (removed) plus the tone, 1 s.
    let x: Vec<f64> = (0..20_000)
        .map(|i| 3.0 + 1e-4 * (2.0 * PI * tone_hz * i as f64 / input_rate_hz).sin())
        .collect();
    let path = std::env::temp_dir().join(format!("squeal-wav-test-{}.wav", std::process::id()));
    let written = write_wav(&path, &x, input_rate_hz, 44_100).unwrap();
    let wav = read_pcm16_wav(&path).unwrap();
    std::fs::remove_file(&path).ok();

    assert_eq!(wav.sample_rate_hz, 44_100);
    assert_eq!(wav.samples.len(), written);
    assert_eq!(written, (19_999.0f64 * 2.205).floor() as usize + 1);
    let peak = wav.samples.iter().map(|s| (*s as i32).abs()).max().unwrap();
    assert_eq!(peak, (PEAK_FRACTION_OF_FULL_SCALE * 32767.0).round() as i32);

    // Zero crossings over the interior: 2 per period.
    let audio: Vec<f64> = wav.samples.iter().map(|s| *s as f64).collect();
    let interior = &audio[2_000..audio.len() - 2_000];
    let crossings = interior
        .windows(2)
        .filter(|w| (w[0] < 0.0) != (w[1] < 0.0))
        .count();
    let crossing_hz = crossings as f64 / 2.0 / (interior.len() as f64 / 44_100.0);
    // Counting resolves +-1 crossing over ~0.9 s, i.e. about 0.6 Hz.
    assert!((crossing_hz - tone_hz).abs() < 1.5, "{crossing_hz}");

    // Spectral peak, refined: within 1 Hz (bins are 44100 / 8192 = 5.4 Hz).
    let psd = welch(&audio, 44_100.0, &WelchParams::new(8192)).unwrap();
    let search = PeakSearch {
        max_peaks: 1,
        ..PeakSearch::default()
    };
    let found = psd.find_peaks(&search).unwrap()[0];
    println!(
        "WAV tone: zero crossings {crossing_hz:.2} Hz, spectral peak {:.3} Hz (true {tone_hz})",
        found.refined_frequency_hz
    );
    assert!((found.refined_frequency_hz - tone_hz).abs() < 1.0);
}

#[test]
fn non_wav_file_is_an_input_error() {
    let path = std::env::temp_dir().join(format!("squeal-not-wav-{}.wav", std::process::id()));
    std::fs::write(
        &path,
        b"not a wav file at all, just some bytes padding it out",
    )
    .unwrap();
    let err = read_pcm16_wav(&path).unwrap_err();
    std::fs::remove_file(&path).ok();
    assert_eq!(err.exit_code(), 2);
}
