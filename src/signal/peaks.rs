//! Peak picking on a spectrum.
//!
//! The building blocks follow `scipy.signal` exactly so they can be checked against it:
//! - [`local_maxima`]: samples strictly higher than both neighbours; a flat top (plateau) counts
//!   once, at its middle sample rounded down; the first and last samples are never peaks
//!   (`scipy.signal.find_peaks` without conditions);
//! - [`peak_prominences`]: from the peak walk left (right) while samples are not higher than
//!   the peak, up to the array end; the lowest sample passed is the left (right) base; the
//!   prominence is `height - max(left minimum, right minimum)`
//!   (`scipy.signal.peak_prominences`, no `wlen`);
//! - [`select_by_distance`]: visiting peaks from the highest priority down, discard every
//!   lower-priority peak closer than `distance` samples (`find_peaks(distance=...)`).
//!
//! [`find_spectral_peaks`] combines them for a PSD: band limits, minimum separation in Hz,
//! the N dominant peaks by prominence or height, and a sub-bin frequency from a parabola
//! through the **natural log** of the PSD at the three bins around the peak. The log is used
//! because a window's main lobe is close to a Gaussian, whose log is exactly a parabola, so the
//! bias is much smaller than for a parabola on linear power (J. O. Smith, *Spectral Audio
//! Signal Processing*, "Quadratic Interpolation of Spectral Peaks"): vertex offset
//! `p = (a - c) / (2 (a - 2b + c))` bins, log height `b - (a - c) p / 4`, with a, b, c the log
//! PSD at bins k-1, k, k+1.

use ndarray::{ArrayView1, AsArray};

use crate::{Error, Result};

/// Indices of local maxima (SciPy `_local_maxima_1d`, see the module documentation).
pub fn local_maxima(x: &[f64]) -> Vec<usize> {
    let mut peaks = Vec::new();
    if x.len() < 3 {
        return peaks;
    }
    let last = x.len() - 1;
    let mut i = 1;
    while i < last {
        if x[i - 1] < x[i] {
            let mut ahead = i + 1;
            while ahead < last && x[ahead] == x[i] {
                ahead += 1;
            }
            if x[ahead] < x[i] {
                peaks.push((i + ahead - 1) / 2);
                i = ahead;
            }
        }
        i += 1;
    }
    peaks
}

/// Prominence of one peak and where its bases are.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Prominence {
    /// Height above the higher of the two bases (same unit as the data).
    pub prominence: f64,
    /// Index of the lowest sample between the peak and the first higher sample on the left.
    pub left_base: usize,
    /// Index of the lowest sample between the peak and the first higher sample on the right.
    pub right_base: usize,
}

/// Prominences of `peaks` in `x` (SciPy `peak_prominences`, see the module documentation).
/// Indices out of range are an input error.
pub fn peak_prominences(x: &[f64], peaks: &[usize]) -> Result<Vec<Prominence>> {
    let mut result = Vec::with_capacity(peaks.len());
    for &peak in peaks {
        if peak >= x.len() {
            return Err(Error::input(
                "peaks",
                "peaks",
                format!("peak index {peak} is outside 0..{}", x.len()),
            ));
        }
        let height = x[peak];
        let (mut left_min, mut left_base) = (height, peak);
        let mut i = peak as isize;
        while i >= 0 && x[i as usize] <= height {
            if x[i as usize] < left_min {
                left_min = x[i as usize];
                left_base = i as usize;
            }
            i -= 1;
        }
        let (mut right_min, mut right_base) = (height, peak);
        let mut i = peak;
        while i < x.len() && x[i] <= height {
            if x[i] < right_min {
                right_min = x[i];
                right_base = i;
            }
            i += 1;
        }
        result.push(Prominence {
            prominence: height - left_min.max(right_min),
            left_base,
            right_base,
        });
    }
    Ok(result)
}

/// Which peaks to keep so that no two are closer than `distance_samples`, higher `priority`
/// winning (SciPy `_select_by_peak_distance`; ties: the later peak wins, as NumPy's sort does
/// for short arrays). `peaks` must be increasing. Returns one flag per peak.
pub fn select_by_distance(peaks: &[usize], priority: &[f64], distance_samples: usize) -> Vec<bool> {
    let mut keep = vec![true; peaks.len()];
    let mut order: Vec<usize> = (0..peaks.len()).collect();
    order.sort_by(|&a, &b| priority[a].total_cmp(&priority[b])); // stable, ascending
    for &j in order.iter().rev() {
        if !keep[j] {
            continue;
        }
        let mut k = j;
        while k > 0 && peaks[j] - peaks[k - 1] < distance_samples {
            keep[k - 1] = false;
            k -= 1;
        }
        let mut k = j + 1;
        while k < peaks.len() && peaks[k] - peaks[j] < distance_samples {
            keep[k] = false;
            k += 1;
        }
    }
    keep
}

/// Vertex of the parabola through (-1, a), (0, b), (1, c): (offset in bins, value).
/// Returns (0, b) when the three points are not a strict maximum (flat or convex).
pub fn parabolic_vertex(a: f64, b: f64, c: f64) -> (f64, f64) {
    let curvature = a - 2.0 * b + c;
    if curvature.is_nan() || curvature >= 0.0 {
        return (0.0, b);
    }
    let offset = (0.5 * (a - c) / curvature).clamp(-0.5, 0.5);
    (offset, b - 0.25 * (a - c) * offset)
}

/// The maximum at bin `k` (`0 < k < len - 1`) refined by the parabola through the log PSD of
/// bins `k - 1, k, k + 1`: (offset in bins, PSD at the vertex); the bin itself when a
/// neighbour is not positive. The peak finder and the per-n check read peaks this way.
pub fn log_parabola_maximum(psd: &[f64], k: usize) -> (f64, f64) {
    if psd[k - 1] > 0.0 && psd[k] > 0.0 && psd[k + 1] > 0.0 {
        let (offset, log_value) = parabolic_vertex(psd[k - 1].ln(), psd[k].ln(), psd[k + 1].ln());
        (offset, log_value.exp())
    } else {
        (0.0, psd[k])
    }
}

/// How the dominant peaks are ranked (and which peak wins a separation conflict).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum PeakRanking {
    /// By prominence (stands out from its surroundings).
    #[default]
    Prominence,
    /// By PSD value.
    Height,
}

impl PeakRanking {
    /// The command-line / file name of the ranking.
    pub fn name(self) -> &'static str {
        match self {
            PeakRanking::Prominence => "prominence",
            PeakRanking::Height => "height",
        }
    }
}

/// Default number of peaks a spectrum's summary lists.
pub const DEFAULT_PEAK_COUNT: usize = 5;

/// What peaks to look for in a spectrum.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PeakSearch {
    /// Lowest peak frequency, Hz (inclusive).
    pub min_frequency_hz: f64,
    /// Highest peak frequency, Hz (inclusive).
    pub max_frequency_hz: f64,
    /// Peaks closer than this keep only the higher-ranked one, Hz (0: no limit). Converted to
    /// `ceil(separation / df)` bins as SciPy does with `distance`.
    pub min_separation_hz: f64,
    /// Keep at most this many peaks (the highest ranked).
    pub max_peaks: usize,
    /// Ranking key.
    pub ranking: PeakRanking,
}

impl Default for PeakSearch {
    fn default() -> Self {
        PeakSearch {
            min_frequency_hz: 0.0,
            max_frequency_hz: f64::INFINITY,
            min_separation_hz: 0.0,
            max_peaks: usize::MAX,
            ranking: PeakRanking::Prominence,
        }
    }
}

/// One spectral peak.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SpectralPeak {
    /// Bin index of the local maximum.
    pub index: usize,
    /// Bin frequency, Hz.
    pub frequency_hz: f64,
    /// Frequency refined by the log-parabola (module documentation), Hz.
    pub refined_frequency_hz: f64,
    /// PSD at the bin (input unit).
    pub psd: f64,
    /// PSD at the log-parabola vertex (input unit).
    pub refined_psd: f64,
    /// Prominence (input unit).
    pub prominence: f64,
    /// Frequency of the left base, Hz.
    pub left_base_hz: f64,
    /// Frequency of the right base, Hz.
    pub right_base_hz: f64,
}

/// The dominant peaks of `psd` over `frequency_hz` (uniform bins), highest ranked first.
///
/// Both axes are anything that views as a 1-D array: a [`crate::signal::Psd`]'s `Array1`s
/// (see [`crate::signal::Psd::find_peaks`]), a slice or a `Vec`.
pub fn find_spectral_peaks<'a>(
    frequency_hz: impl AsArray<'a, f64>,
    psd: impl AsArray<'a, f64>,
    search: &PeakSearch,
) -> Result<Vec<SpectralPeak>> {
    let frequency_hz: ArrayView1<'a, f64> = frequency_hz.into();
    // The building blocks work on contiguous samples; a strided view is copied once.
    let psd: Vec<f64> = psd.into().to_vec();
    if frequency_hz.len() != psd.len() {
        return Err(Error::input(
            "peaks",
            "psd",
            format!(
                "{} PSD values for {} frequencies",
                psd.len(),
                frequency_hz.len()
            ),
        ));
    }
    if search.min_frequency_hz.is_nan()
        || search.max_frequency_hz.is_nan()
        || search.min_frequency_hz > search.max_frequency_hz
    {
        return Err(Error::input(
            "peaks",
            "band",
            format!(
                "band [{}, {}] Hz is empty; need min_frequency_hz <= max_frequency_hz",
                search.min_frequency_hz, search.max_frequency_hz
            ),
        ));
    }
    if !(search.min_separation_hz.is_finite() && search.min_separation_hz >= 0.0) {
        return Err(Error::input(
            "peaks",
            "min_separation_hz",
            format!("{} Hz must be finite and >= 0", search.min_separation_hz),
        ));
    }
    if psd.len() < 3 {
        return Ok(Vec::new());
    }
    let bin_hz = (frequency_hz[psd.len() - 1] - frequency_hz[0]) / (psd.len() - 1) as f64;

    let maxima = local_maxima(&psd);
    let prominences = peak_prominences(&psd, &maxima)?;
    let in_band: Vec<(usize, Prominence)> = maxima
        .into_iter()
        .zip(prominences)
        .filter(|(k, _)| {
            (search.min_frequency_hz..=search.max_frequency_hz).contains(&frequency_hz[*k])
        })
        .collect();
    let rank = |(k, p): &(usize, Prominence)| match search.ranking {
        PeakRanking::Prominence => p.prominence,
        PeakRanking::Height => psd[*k],
    };
    let priority: Vec<f64> = in_band.iter().map(rank).collect();
    // 1e-9 guards against round-off pushing an exact multiple of the bin up one bin.
    let distance_samples = if bin_hz > 0.0 {
        (search.min_separation_hz / bin_hz - 1e-9).ceil().max(1.0) as usize
    } else {
        1
    };
    let indices: Vec<usize> = in_band.iter().map(|(k, _)| *k).collect();
    let keep = select_by_distance(&indices, &priority, distance_samples);

    let mut kept: Vec<(f64, SpectralPeak)> = in_band
        .iter()
        .zip(&keep)
        .zip(&priority)
        .filter(|((_, keep), _)| **keep)
        .map(|(((k, p), _), priority)| {
            let k = *k;
            let (offset_bins, refined_psd) = log_parabola_maximum(&psd, k);
            let peak = SpectralPeak {
                index: k,
                frequency_hz: frequency_hz[k],
                refined_frequency_hz: frequency_hz[k] + offset_bins * bin_hz,
                psd: psd[k],
                refined_psd,
                prominence: p.prominence,
                left_base_hz: frequency_hz[p.left_base],
                right_base_hz: frequency_hz[p.right_base],
            };
            (*priority, peak)
        })
        .collect();
    kept.sort_by(|a, b| b.0.total_cmp(&a.0));
    kept.truncate(search.max_peaks);
    Ok(kept.into_iter().map(|(_, peak)| peak).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plateau_peak_is_its_middle_rounded_down_and_edges_are_not_peaks() {
        assert_eq!(
            local_maxima(&[5.0, 1.0, 3.0, 3.0, 0.0, 2.0, 2.0, 2.0, 1.0, 9.0]),
            vec![2, 6]
        );
    }

    #[test]
    fn prominence_of_a_peak_between_two_valleys_uses_the_higher_valley() {
        let x = [0.0, 4.0, 1.0, 3.0, 2.0, 5.0, 0.5];
        let p = peak_prominences(&x, &[3]).unwrap()[0];
        assert_eq!((p.prominence, p.left_base, p.right_base), (1.0, 2, 4)); // 3 - max(1, 2)
    }

    #[test]
    fn empty_band_is_an_input_error() {
        let search = PeakSearch {
            min_frequency_hz: 10.0,
            max_frequency_hz: 5.0,
            ..PeakSearch::default()
        };
        let err =
            find_spectral_peaks(&[0.0, 1.0, 2.0][..], &[0.0, 1.0, 0.0][..], &search).unwrap_err();
        assert_eq!(err.exit_code(), 2);
    }
}
