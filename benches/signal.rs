//! Signal-analysis timings: `CARGO_BUILD_JOBS=1 cargo bench --bench signal`.
//! Targets: Welch PSD of 10^6 samples < 50 ms; 100-scale CWT of 10^5 samples < 1 s.

use std::f64::consts::PI;
use std::time::{Duration, Instant};

use squeal::signal::{morlet_cwt, welch, Scales, WelchParams};

fn test_signal(count: usize, sample_rate_hz: f64) -> Vec<f64> {
    let mut state = 0x1234_5678u64;
    (0..count)
        .map(|i| {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let noise = (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
            let t = i as f64 / sample_rate_hz;
            (2.0 * PI * 1000.0 * t).sin() + 0.5 * (2.0 * PI * 2100.0 * t).sin() + 0.1 * noise
        })
        .collect()
}

/// Runs `work` `repeats` times after one warm-up; returns (minimum, median).
fn time(repeats: usize, mut work: impl FnMut()) -> (Duration, Duration) {
    work();
    let mut times: Vec<Duration> = (0..repeats)
        .map(|_| {
            let start = Instant::now();
            work();
            start.elapsed()
        })
        .collect();
    times.sort();
    (times[0], times[repeats / 2])
}

fn main() {
    println!("rayon threads: {}", rayon::current_num_threads());

    let sample_rate_hz = 50_000.0;
    let x = test_signal(1_000_000, sample_rate_hz);
    for nperseg in [1024, 4096, 16_384] {
        let params = WelchParams::new(nperseg);
        let (min, median) = time(11, || {
            std::hint::black_box(welch(&x, sample_rate_hz, &params).unwrap());
        });
        println!(
            "welch 1e6 samples, nperseg {nperseg}, hann, 50 % overlap: min {:.2} ms, median {:.2} ms (target < 50 ms)",
            min.as_secs_f64() * 1e3,
            median.as_secs_f64() * 1e3
        );
    }

    let x = test_signal(100_000, sample_rate_hz);
    // 100 log-spaced scales, 20 per octave from 20 kHz down: 20 kHz .. ~645 Hz.
    let scales = Scales::LogSpaced {
        smallest_scale_s: 1.0 / (1.033 * 20_000.0),
        octaves_per_step: 0.05,
        largest_index: 99,
    };
    let (min, median) = time(5, || {
        std::hint::black_box(morlet_cwt(&x, sample_rate_hz, &scales).unwrap());
    });
    println!(
        "morlet cwt 1e5 samples x 100 scales: min {:.1} ms, median {:.1} ms (target < 1 s)",
        min.as_secs_f64() * 1e3,
        median.as_secs_f64() * 1e3
    );
    let scales = Scales::from_frequency_band(20.0, 20_000.0, 10).unwrap();
    let (min, median) = time(3, || {
        std::hint::black_box(morlet_cwt(&x, sample_rate_hz, &scales).unwrap());
    });
    println!(
        "morlet cwt 1e5 samples x {} scales down to 20 Hz (max padding): min {:.1} ms, median {:.1} ms",
        scales.scales_s().len(),
        min.as_secs_f64() * 1e3,
        median.as_secs_f64() * 1e3
    );
}
