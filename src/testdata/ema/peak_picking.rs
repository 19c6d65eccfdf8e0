//! Peak picking: each resonance is a peak of the mean FRF magnitude (a mode indicator), its
//! frequency the vertex of a parabola through the log magnitude at the three lines around the
//! peak (as [`crate::signal::find_spectral_peaks`] refines spectral peaks), its damping from the
//! half-power bandwidth and its shape the FRFs' values at the peak (quadrature picking).
//!
//! Half-power bandwidth (Ewins, *Modal Testing*, 2nd ed. 2000, section 4.3.3): the magnitude
//! falls to `|H|max / sqrt(2)` at `f1 < f_r < f2`, and for light damping
//! `zeta = (f2 - f1) / (2 f_r)`. f1 and f2 are interpolated linearly between lines.
//!
//! A peak counts as a resonance when it stands at least a factor 2 (6 dB) above the higher of
//! its two bases (its prominence is at least half its height): smaller ripples are noise or the
//! skirts of neighbouring modes. The method assumes well-separated modes; LSCF ([`super::lscf`])
//! does not.

use super::frf::FrfSet;
use super::test_mode::{EstimationMethod, TestMode};
use crate::signal::{find_spectral_peaks, PeakRanking, PeakSearch};
use crate::Result;

/// A peak must stand this factor above its higher base (6 dB in magnitude).
pub const MIN_PEAK_TO_BASE: f64 = 2.0;

/// Modes of `set` between `fmin_hz` and `fmax_hz` by peak picking (module documentation).
pub fn peak_picking(set: &FrfSet, fmin_hz: f64, fmax_hz: f64) -> Result<Vec<TestMode>> {
    let magnitude = set.mean_magnitude();
    let search = PeakSearch {
        min_frequency_hz: fmin_hz,
        max_frequency_hz: fmax_hz,
        min_separation_hz: 0.0,
        max_peaks: usize::MAX,
        ranking: PeakRanking::Prominence,
    };
    let mut peaks = find_spectral_peaks(&set.frequency_hz, &magnitude, &search)?;
    peaks.retain(|p| p.prominence >= p.psd * (1.0 - 1.0 / MIN_PEAK_TO_BASE));
    peaks.sort_by(|a, b| a.refined_frequency_hz.total_cmp(&b.refined_frequency_hz));
    let f = &set.frequency_hz;
    let mut modes = Vec::with_capacity(peaks.len());
    for p in peaks {
        let level = p.refined_psd / std::f64::consts::SQRT_2;
        let k = p.index;
        // The first line below the half-power level on each side, then linear interpolation.
        let left = (0..k).rev().find(|&j| magnitude[j] < level).map(|j| {
            f[j] + (level - magnitude[j]) / (magnitude[j + 1] - magnitude[j]) * (f[j + 1] - f[j])
        });
        let right = (k + 1..magnitude.len())
            .find(|&j| magnitude[j] < level)
            .map(|j| {
                f[j - 1]
                    + (magnitude[j - 1] - level) / (magnitude[j - 1] - magnitude[j])
                        * (f[j] - f[j - 1])
            });
        let damping_ratio = match (left, right) {
            (Some(f1), Some(f2)) => (f2 - f1) / (2.0 * p.refined_frequency_hz),
            _ => f64::NAN, // the half-power points lie outside the measured band
        };
        modes.push(TestMode {
            frequency_hz: p.refined_frequency_hz,
            damping_ratio,
            shape: set.frf.iter().map(|h| h[k]).collect(),
            method: EstimationMethod::PeakPicking,
            stable_orders: 0,
        });
    }
    Ok(modes)
}
