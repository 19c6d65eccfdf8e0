//! Per-nodal-diameter spectra of a run's rim ring (`ring.csv`, [`crate::rolling::ring`]): a
//! frequency x n map like a Campbell diagram, each harmonic's dominant peaks named from the
//! modes of that n only, and the per-n check of required modes.
//!
//! Method:
//! - the ring's harmonic n in one direction is the pair `c_n(t)`, `s_n(t)` (its cosine and
//!   sine parts around the wheel); its power spectral density is `PSD(c_n) + PSD(s_n)` (Welch,
//!   the same segments and bins for every n, [`crate::signal::resolution`]): the power of the
//!   harmonic whatever its orientation on the wheel. A mode with n nodal diameters appears in
//!   the harmonic n only, so (1,0) at 1767 Hz and (0,4) at 1839 Hz of the default wheel fall in
//!   different harmonics however close their peaks;
//! - each harmonic's peaks are ranked by prominence in the band and named by the nearest mode
//!   of that n whose family the direction sees (lateral: axial; radial: radial;
//!   circumferential: circumferential; the axle's modes in all three), within the identify
//!   tolerance ([`crate::analysis::identify::Tolerance`]);
//! - the per-n check: a required (m, n) passes when the harmonic n has a local maximum within
//!   [`REQUIRED_WINDOW`] of the mode's frequency that stands at least [`PER_N_MARGIN_DB`] above
//!   the median of that harmonic's PSD over the band. The maximum's frequency and level are
//!   those of the parabola through the log PSD of its bin and the two beside it, as the peak
//!   finder refines them ([`crate::signal::peaks::log_parabola_maximum`]): the window of a low mode
//!   (+-11.5 Hz at 231 Hz) is narrower than a short record's bins (24.4 Hz for 40 ms), and a
//!   peak at +2.5 % whose top bin lies just outside it would otherwise go unseen.
//!
//! The ring's records are in the wheel's turning frame, where the wheel's modes keep their own
//! frequencies (a standing pattern fixed in space would be split by `+-n Omega`, a few hertz at
//! curve speeds).

use std::path::Path;

use serde::Serialize;

use crate::analysis::identify::{ModeFamily, ModeRef};
use crate::analysis::run::{
    read_csv_headers, read_run_modes, window_range, AnalysisOptions, AnalysisWindow,
    DEFAULT_FMAX_HZ,
};
use crate::signal::resolution::{describe, welch_for_resolution};
use crate::signal::{find_spectral_peaks, welch, PeakSearch, TimeSeries};
use crate::{Error, Result};

/// The margin (dB) by which a required mode's peak must stand above the median of its
/// harmonic's PSD, fixed before any run was judged by it (issue 57, item 6). Why 10 dB: a
/// Welch estimate of a flat spectrum from K segments scatters as chi-square with 2K degrees of
/// freedom; with a single segment (the least averaging the analysis uses) the 99.9th
/// percentile of `chi2_2 / 2` is `ln 1000 = 6.9` (8.4 dB), so a bin of broadband noise passes 10
/// dB less than once in a thousand bins, and a resonance must stand a factor 10 in power above
/// the harmonic's typical level.
pub const PER_N_MARGIN_DB: f64 = 10.0;

/// Relative distance from a required mode's frequency within which its peak is looked for
/// (issue 57, item 6: 5 %, the identify tolerance).
pub const REQUIRED_WINDOW: f64 = 0.05;

/// A direction of the ring's motion.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum RingDirection {
    /// Along the axle (out of the wheel's plane).
    #[default]
    Lateral,
    /// Away from the axle, in the wheel's plane.
    Radial,
    /// Around the wheel, in its plane.
    Circumferential,
}

impl RingDirection {
    /// The word used in `ring.csv`'s columns.
    pub fn word(self) -> &'static str {
        match self {
            RingDirection::Lateral => "lateral",
            RingDirection::Radial => "radial",
            RingDirection::Circumferential => "circumferential",
        }
    }

    /// The mode families this direction sees.
    pub fn families(self) -> &'static [ModeFamily] {
        match self {
            RingDirection::Lateral => &[ModeFamily::Axial, ModeFamily::Axle],
            RingDirection::Radial => &[ModeFamily::Radial, ModeFamily::Axle],
            RingDirection::Circumferential => &[ModeFamily::Circumferential, ModeFamily::Axle],
        }
    }
}

/// Options of the per-n analysis: the direction of the ring's motion, and the spectrum,
/// window, peak and tolerance settings of [`AnalysisOptions`] (its `signal` is not used; its
/// `modes_file` names the modes instead of the run's `modes.json`).
#[derive(Clone, Debug, Default, Serialize)]
pub struct PerNOptions {
    /// Direction of the ring's motion.
    pub direction: RingDirection,
    /// Spectrum, window, peaks and tolerance.
    pub spectrum: AnalysisOptions,
}

/// The PSD of one harmonic.
#[derive(Clone, Debug, Serialize)]
pub struct HarmonicSpectrum {
    /// Nodal diameters.
    pub n: usize,
    /// `PSD(c_n) + PSD(s_n)` per bin ((m/s)^2/Hz).
    pub psd_per_hz: Vec<f64>,
    /// Median of the PSD over the band ((m/s)^2/Hz).
    pub median_in_band: f64,
}

/// One peak of one harmonic and the mode of that n that explains it.
#[derive(Clone, Debug, Serialize)]
pub struct HarmonicPeak {
    /// Nodal diameters (the harmonic).
    pub n: usize,
    /// Rank within the harmonic (1: the most prominent).
    pub rank: usize,
    /// Peak frequency (refined, Hz).
    pub frequency_hz: f64,
    /// PSD at the peak ((m/s)^2/Hz).
    pub psd: f64,
    /// Level above the harmonic's median (dB).
    pub over_median_db: f64,
    /// The explaining mode (of this n), if any within the tolerance.
    pub mode: Option<ModeRef>,
    /// (peak - mode) / mode (%).
    pub difference_percent: Option<f64>,
}

/// The per-n analysis of a run.
#[derive(Clone, Debug, Serialize)]
pub struct PerNAnalysis {
    /// Direction analysed.
    pub direction: RingDirection,
    /// Bin frequencies (Hz).
    pub frequencies_hz: Vec<f64>,
    /// The band of the peaks and medians (Hz).
    pub band_hz: (f64, f64),
    /// One spectrum per harmonic, n = 0..=n_max.
    pub spectra: Vec<HarmonicSpectrum>,
    /// Peaks of every harmonic, by n then rank.
    pub peaks: Vec<HarmonicPeak>,
    /// The analysed window.
    pub window: AnalysisWindow,
    /// The modes used.
    pub modes: Vec<ModeRef>,
}

/// The highest harmonic of a `ring.csv` header (columns `n{n}_...`).
fn ring_n_max(headers: &[String], path: &Path) -> Result<usize> {
    headers
        .iter()
        .filter_map(|h| {
            h.strip_prefix('n')?
                .split('_')
                .next()?
                .parse::<usize>()
                .ok()
        })
        .max()
        .ok_or_else(|| {
            Error::input(
                path.display().to_string(),
                "header",
                "no ring columns (n0_lateral_cos_m_per_s, ...): not a ring.csv",
            )
        })
}

/// The per-n spectra and peaks of the ring of `run_dir` (its `ring.csv` and `modes.json`, or
/// the options' modes file).
pub fn analyse_ring(run_dir: &Path, options: &PerNOptions) -> Result<PerNAnalysis> {
    let ring = read_ring(run_dir, options.direction)?;
    let modes = read_run_modes(run_dir, options.spectrum.modes_file.as_deref())?;
    analyse_harmonics(&ring, modes, options)
}

/// One direction of a run's ring record: per harmonic n = 0..=n_max its cosine part and (n >=
/// 1) its sine part, in that order.
#[derive(Clone, Debug)]
pub struct RingRecord {
    /// The file read.
    pub path: std::path::PathBuf,
    /// The direction.
    pub direction: RingDirection,
    /// Highest harmonic.
    pub n_max: usize,
    /// `c_0, c_1, s_1, c_2, s_2, ...` (m/s).
    pub parts: Vec<TimeSeries>,
}

impl RingRecord {
    /// The cosine and (n >= 1) sine parts of harmonic `n`.
    pub fn harmonic(&self, n: usize) -> &[TimeSeries] {
        let start = if n == 0 { 0 } else { 2 * n - 1 };
        let count = if n == 0 { 1 } else { 2 };
        &self.parts[start..start + count]
    }
}

/// Reads one direction of the ring of `run_dir` (`ring.csv`); a run without a ring is an input
/// error naming it.
pub fn read_ring(run_dir: &Path, direction: RingDirection) -> Result<RingRecord> {
    let path = run_dir.join(crate::rolling::ring::RING_CSV);
    if !path.exists() {
        return Err(Error::input(
            run_dir.display().to_string(),
            "ring.csv",
            "the run has no ring: a per-n analysis needs a run made with output.ring in its \
             case file (docs/curving.md)",
        ));
    }
    let headers = read_csv_headers(&path)?;
    let n_max = ring_n_max(&headers, &path)?;
    let dir = direction.word();
    let mut names = Vec::new();
    for n in 0..=n_max {
        names.push(crate::rolling::ring::ring_column(n, dir, "cos"));
        if n > 0 {
            names.push(crate::rolling::ring::ring_column(n, dir, "sin"));
        }
    }
    let name_refs: Vec<&str> = names.iter().map(String::as_str).collect();
    let parts = TimeSeries::columns_from_csv(&path, &name_refs)?;
    Ok(RingRecord {
        path,
        direction,
        n_max,
        parts,
    })
}

/// The per-n spectra and peaks of a ring record, its peaks named from `modes` (the record's
/// direction, not the options', says which families name them).
pub fn analyse_harmonics(
    ring: &RingRecord,
    modes: Vec<ModeRef>,
    options: &PerNOptions,
) -> Result<PerNAnalysis> {
    let spectrum = &options.spectrum;
    let path = &ring.path;
    let first = &ring.parts[0];
    let fs = first.sample_rate_hz;
    let nyquist = 0.5 * fs;
    let band = match spectrum.band_hz {
        (lo, hi) if hi.is_infinite() && hi > 0.0 => (lo, DEFAULT_FMAX_HZ.min(nyquist)),
        b => b,
    };
    if !(band.0 >= 0.0 && band.1 > band.0 && band.1 <= nyquist) {
        return Err(Error::input(
            path.display().to_string(),
            "--fmin-hz/--fmax-hz",
            format!(
                "need 0 <= fmin < fmax <= {nyquist:.1} Hz (the Nyquist frequency), got [{}, {}]",
                band.0, band.1
            ),
        ));
    }
    let from_s = spectrum.from_s.unwrap_or(first.start_time_s);
    let range = window_range(first, from_s, spectrum.to_s, path)?;
    let params = welch_for_resolution(range.len(), fs, spectrum.resolution_hz, spectrum.nperseg)?;
    let mut spectra = Vec::new();
    let mut frequencies_hz = Vec::new();
    let mut segments = 0;
    for n in 0..=ring.n_max {
        let mut sum: Vec<f64> = Vec::new();
        for s in ring.harmonic(n) {
            let psd = welch(&s.values[range.clone()], fs, &params)?;
            if sum.is_empty() {
                sum = psd.psd_per_hz.to_vec();
                frequencies_hz = psd.frequency_hz.to_vec();
                segments = psd.segment_count;
            } else {
                for (a, b) in sum.iter_mut().zip(psd.psd_per_hz.iter()) {
                    *a += b;
                }
            }
        }
        let median_in_band = median_over(&frequencies_hz, &sum, band);
        spectra.push(HarmonicSpectrum {
            n,
            psd_per_hz: sum,
            median_in_band,
        });
    }
    let peaks = harmonic_peaks(
        &frequencies_hz,
        &spectra,
        &modes,
        ring.direction,
        options,
        band,
    )?;
    let window = AnalysisWindow {
        from_s: first.start_time_s + range.start as f64 / fs,
        to_s: first.start_time_s + (range.end - 1) as f64 / fs,
        start_from: if spectrum.from_s.is_some() {
            "--from-ms".into()
        } else {
            "the first sample".into()
        },
        spectrum: describe(&params, fs, segments),
    };
    Ok(PerNAnalysis {
        direction: ring.direction,
        frequencies_hz,
        band_hz: band,
        spectra,
        peaks,
        window,
        modes,
    })
}

/// Median of `psd` over the bins in `band` (NaN without bins).
fn median_over(frequencies_hz: &[f64], psd: &[f64], band: (f64, f64)) -> f64 {
    let mut inside: Vec<f64> = frequencies_hz
        .iter()
        .zip(psd)
        .filter(|(f, _)| **f >= band.0 && **f <= band.1)
        .map(|(_, p)| *p)
        .collect();
    if inside.is_empty() {
        return f64::NAN;
    }
    inside.sort_by(f64::total_cmp);
    let m = inside.len();
    if m % 2 == 1 {
        inside[m / 2]
    } else {
        0.5 * (inside[m / 2 - 1] + inside[m / 2])
    }
}

/// Level of `psd` over `reference` in dB (`-inf` for a zero PSD).
fn decibels(psd: f64, reference: f64) -> f64 {
    10.0 * (psd / reference).log10()
}

/// Each harmonic's most prominent peaks in the band, named by the nearest mode of that n.
fn harmonic_peaks(
    frequencies_hz: &[f64],
    spectra: &[HarmonicSpectrum],
    modes: &[ModeRef],
    direction: RingDirection,
    options: &PerNOptions,
    band: (f64, f64),
) -> Result<Vec<HarmonicPeak>> {
    let families = direction.families();
    let spectrum_options = &options.spectrum;
    let search = PeakSearch {
        min_frequency_hz: band.0,
        max_frequency_hz: band.1,
        min_separation_hz: spectrum_options.min_separation_hz,
        max_peaks: spectrum_options.peaks,
        ..Default::default()
    };
    let mut out = Vec::new();
    for spectrum in spectra {
        let found = find_spectral_peaks(frequencies_hz, &spectrum.psd_per_hz[..], &search)?;
        for (rank, p) in found.iter().enumerate() {
            let f = p.refined_frequency_hz;
            let best = modes
                .iter()
                .filter(|m| m.nodal_diameters as usize == spectrum.n && m.frequency_hz > 0.0)
                .filter(|m| families.contains(&m.family))
                .filter(|m| {
                    (f - m.frequency_hz).abs()
                        <= spectrum_options.tolerance.window_hz(m.frequency_hz)
                })
                .min_by(|a, b| {
                    (f - a.frequency_hz)
                        .abs()
                        .total_cmp(&(f - b.frequency_hz).abs())
                });
            out.push(HarmonicPeak {
                n: spectrum.n,
                rank: rank + 1,
                frequency_hz: f,
                psd: p.refined_psd,
                over_median_db: decibels(p.refined_psd, spectrum.median_in_band),
                mode: best.cloned(),
                difference_percent: best.map(|m| 100.0 * (f - m.frequency_hz) / m.frequency_hz),
            });
        }
    }
    Ok(out)
}

/// The outcome of one required mode in the per-n check.
#[derive(Clone, Debug, Serialize)]
pub struct RequiredOutcome {
    /// (nodal circles, nodal diameters).
    pub label: (u32, u32),
    /// The mode's frequency (Hz), when the modal results have it in a family the direction
    /// sees.
    pub mode_frequency_hz: Option<f64>,
    /// The highest local maximum of the harmonic within the window (Hz).
    pub peak_frequency_hz: Option<f64>,
    /// Its level above the harmonic's median (dB).
    pub over_median_db: Option<f64>,
    /// Whether it passes.
    pub passed: bool,
    /// Why, in one line.
    pub reason: String,
}

/// The per-n check of each required (m, n) (module docs), with the margin `margin_db`.
pub fn check_required(
    analysis: &PerNAnalysis,
    required: &[(u32, u32)],
    margin_db: f64,
) -> Vec<RequiredOutcome> {
    let families = analysis.direction.families();
    let n_max = analysis.spectra.len().saturating_sub(1);
    required
        .iter()
        .map(|&(m, n)| {
            let label = (m, n);
            let fail = |reason: String, f: Option<f64>| RequiredOutcome {
                label,
                mode_frequency_hz: f,
                peak_frequency_hz: None,
                over_median_db: None,
                passed: false,
                reason,
            };
            let Some(mode) = analysis
                .modes
                .iter()
                .filter(|md| md.nodal_circles == m && md.nodal_diameters == n)
                .filter(|md| families.contains(&md.family) && md.frequency_hz > 0.0)
                .min_by(|a, b| a.frequency_hz.total_cmp(&b.frequency_hz))
            else {
                return fail(
                    format!(
                        "({m},{n}): the modal results have no such mode that {} motion sees",
                        analysis.direction.word()
                    ),
                    None,
                );
            };
            let f_mode = mode.frequency_hz;
            if n as usize > n_max {
                return fail(
                    format!("({m},{n}): the ring records n up to {n_max} only"),
                    Some(f_mode),
                );
            }
            let spectrum = &analysis.spectra[n as usize];
            let (lo, hi) = (
                f_mode * (1.0 - REQUIRED_WINDOW),
                f_mode * (1.0 + REQUIRED_WINDOW),
            );
            let psd = &spectrum.psd_per_hz;
            let f = &analysis.frequencies_hz;
            let best = (1..psd.len().saturating_sub(1))
                .filter(|&k| psd[k] > psd[k - 1] && psd[k] >= psd[k + 1])
                .map(|k| refined_maximum(f, psd, k))
                .filter(|&(f_peak, _)| f_peak >= lo && f_peak <= hi)
                .max_by(|a, b| a.1.total_cmp(&b.1));
            let Some((f_peak, psd_peak)) = best else {
                return fail(
                    format!(
                        "({m},{n}) at {f_mode:.1} Hz: harmonic {n} has no peak within {:.0} % \
                         ({lo:.1}-{hi:.1} Hz)",
                        100.0 * REQUIRED_WINDOW
                    ),
                    Some(f_mode),
                );
            };
            let level = decibels(psd_peak, spectrum.median_in_band);
            let passed = level >= margin_db;
            RequiredOutcome {
                label,
                mode_frequency_hz: Some(f_mode),
                peak_frequency_hz: Some(f_peak),
                over_median_db: Some(level),
                passed,
                reason: format!(
                    "({m},{n}) at {f_mode:.1} Hz: harmonic {n} peaks at {:.1} Hz, {level:.1} dB \
                     above its median ({} {margin_db:.0} dB)",
                    f_peak,
                    if passed { "at least" } else { "less than" }
                ),
            }
        })
        .collect()
}

/// The frequency (Hz) and PSD of the local maximum at bin `k`, refined as the peak finder
/// refines its peaks.
fn refined_maximum(frequencies_hz: &[f64], psd: &[f64], k: usize) -> (f64, f64) {
    let (offset_bins, value) = crate::signal::peaks::log_parabola_maximum(psd, k);
    let bin_hz = frequencies_hz[k + 1] - frequencies_hz[k];
    (frequencies_hz[k] + offset_bins * bin_hz, value)
}

/// The frequency x n map as CSV: `frequency_hz`, then the PSD of each harmonic
/// (`n{n}_psd_m2_per_s2_per_hz`).
pub fn map_csv(a: &PerNAnalysis) -> String {
    let mut s = String::from("frequency_hz");
    for sp in &a.spectra {
        s.push_str(&format!(",n{}_psd_m2_per_s2_per_hz", sp.n));
    }
    s.push('\n');
    for (k, f) in a.frequencies_hz.iter().enumerate() {
        s.push_str(&format!("{f:.6e}"));
        for sp in &a.spectra {
            s.push_str(&format!(",{:.6e}", sp.psd_per_hz[k]));
        }
        s.push('\n');
    }
    s
}

/// The peaks as a markdown table.
pub fn peaks_markdown(a: &PerNAnalysis) -> String {
    let mut s = format!(
        "Peaks of each nodal-diameter harmonic of the ring's {} velocity, {:.0}-{:.0} Hz, \
         named from the modes of that n only. Level: above the harmonic's median PSD in the \
         band.\n\n| n | rank | frequency (Hz) | level (dB) | mode | family | modal frequency \
         (Hz) | difference (%) |\n|---|---|---|---|---|---|---|---|\n",
        a.direction.word(),
        a.band_hz.0,
        a.band_hz.1
    );
    for p in &a.peaks {
        let (label, family, f_mode, diff) = match &p.mode {
            Some(m) => (
                format!("({},{})", m.nodal_circles, m.nodal_diameters),
                m.family.word().to_string(),
                format!("{:.1}", m.frequency_hz),
                format!("{:+.2}", p.difference_percent.unwrap_or(f64::NAN)),
            ),
            None => ("-".into(), "-".into(), "-".into(), "-".into()),
        };
        s.push_str(&format!(
            "| {} | {} | {:.1} | {:.1} | {label} | {family} | {f_mode} | {diff} |\n",
            p.n, p.rank, p.frequency_hz, p.over_median_db
        ));
    }
    s
}

/// The peaks as CSV.
pub fn peaks_csv(a: &PerNAnalysis) -> String {
    let mut s = String::from(
        "n,rank,frequency_hz,psd_m2_per_s2_per_hz,over_median_db,mode,family,mode_frequency_hz,difference_percent\n",
    );
    for p in &a.peaks {
        let (label, family, f_mode, diff) = match &p.mode {
            Some(m) => (
                format!("\"({},{})\"", m.nodal_circles, m.nodal_diameters),
                m.family.word().to_string(),
                format!("{}", m.frequency_hz),
                format!("{}", p.difference_percent.unwrap_or(f64::NAN)),
            ),
            None => (String::new(), String::new(), String::new(), String::new()),
        };
        s.push_str(&format!(
            "{},{},{},{},{},{label},{family},{f_mode},{diff}\n",
            p.n, p.rank, p.frequency_hz, p.psd, p.over_median_db
        ));
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_of_the_band_only() {
        let f = [0.0, 10.0, 20.0, 30.0, 40.0];
        let p = [100.0, 1.0, 3.0, 2.0, 100.0];
        assert_eq!(median_over(&f, &p, (5.0, 35.0)), 2.0);
        assert_eq!(median_over(&f, &p, (5.0, 25.0)), 2.0);
        assert!(median_over(&f, &p, (50.0, 60.0)).is_nan());
    }

    /// A (0,0) mode at 230.8 Hz and a 40 ms record at 50 kHz (the demo runs'): the harmonic's
    /// tone at 236.6 Hz (+2.5 %) has its top bin at 244.1 Hz, outside the +-5 % window
    /// (219.3-242.3 Hz), and no bin inside the window is a local maximum. The check reads the
    /// refined maximum (the parabola through the log PSD) and passes, with the peak within
    /// a tenth of a bin of the tone (a Hann window's log-parabola error for a tone: a few
    /// per cent of a bin).
    #[test]
    fn a_peak_within_the_window_between_two_bins_is_found() {
        let (fs, f_tone, f_mode) = (50_000.0, 236.6, 230.8);
        let samples = 2000;
        let tone: Vec<f64> = (0..samples)
            .map(|i| (2.0 * std::f64::consts::PI * f_tone * i as f64 / fs).sin())
            .collect();
        let series = |values: Vec<f64>| TimeSeries {
            column: "n0_lateral_cos_m_per_s".into(),
            start_time_s: 0.0,
            sample_rate_hz: fs,
            values,
        };
        // n = 0 carries the tone; n = 1 (cos and sin) a weak one elsewhere.
        let weak: Vec<f64> = tone.iter().map(|x| 1e-3 * x).collect();
        let ring = RingRecord {
            path: "ring.csv".into(),
            direction: RingDirection::Lateral,
            n_max: 1,
            parts: vec![series(tone), series(weak.clone()), series(weak)],
        };
        let modes = vec![ModeRef {
            frequency_hz: f_mode,
            family: ModeFamily::Axial,
            nodal_circles: 0,
            nodal_diameters: 0,
        }];
        let options = PerNOptions {
            direction: RingDirection::Lateral,
            spectrum: AnalysisOptions::default(),
        };
        let a = analyse_harmonics(&ring, modes, &options).unwrap();
        let (f, psd) = (&a.frequencies_hz, &a.spectra[0].psd_per_hz);
        let bin_hz = f[1] - f[0];
        // The premise: no bin inside the window is a local maximum.
        let (lo, hi) = (f_mode * 0.95, f_mode * 1.05);
        assert!(bin_hz > hi - lo, "bins of {bin_hz} Hz");
        assert!(!(1..psd.len() - 1)
            .any(|k| f[k] >= lo && f[k] <= hi && psd[k] > psd[k - 1] && psd[k] >= psd[k + 1]));
        let outcome = &check_required(&a, &[(0, 0)], PER_N_MARGIN_DB)[0];
        assert!(outcome.passed, "{}", outcome.reason);
        let found = outcome.peak_frequency_hz.unwrap();
        assert!((found - f_tone).abs() < 0.1 * bin_hz, "{found} Hz");
    }

    #[test]
    fn ring_columns_give_their_highest_harmonic() {
        let h: Vec<String> = crate::rolling::ring::ring_columns(7);
        let mut headers = vec!["time_s".to_string()];
        headers.extend(h);
        assert_eq!(ring_n_max(&headers, Path::new("ring.csv")).unwrap(), 7);
        assert!(ring_n_max(&["time_s".into()], Path::new("x.csv")).is_err());
    }
}
