//! Growth of wheel vibration in mode bands over time, from wavelet ridges: does a squeal mode
//! grow, and how fast.
//!
//! Method: the Morlet wavelet power `|W(t, f)|^2` of a signal ([`crate::signal::wavelet`], 16
//! voices per octave over the bands) gives, per band `[f_lo, f_hi]` and time sample, the ridge:
//! the scale `s` of largest power in the band, read as the amplitude of the tone that would
//! give that power, `A(t) = 2 pi^(1/4) sqrt(dt / (2 pi s)) |W|` (a tone `A cos(w t)` has
//! `|W| = (A / 2) (2 pi s / dt)^(1/2) pi^(-1/4) exp(-(s w - w0)^2 / 2)` in the normalisation
//! of Torrence & Compo, and the exponential is within 2 % of 1 on the ridge at 16 voices per
//! octave); units of the signal; only samples inside the cone of influence of the band's
//! lowest frequency count. Over consecutive
//! windows the growth rate is the least-squares slope of `ln A` against time,
//!
//! `sigma = sum (t - t_mean)(ln A - mean) / sum (t - t_mean)^2` (1/s),
//!
//! positive when the band grows: an unstable mode with `x ~ exp(sigma t) cos(omega t)` has
//! exactly this slope in its ridge (the Morlet transform of such a signal scales with the
//! envelope when the envelope changes slowly over a wavelet's duration, `sigma << 2 pi f / w0`).
//! The bands are the modes' frequencies +- a relative width (default 5 %, the identification's
//! tolerance).

use std::path::Path;

use serde::Serialize;

use crate::analysis::identify::ModeRef;
use crate::signal::{morlet_cwt, Scales, TimeSeries, WaveletPower};
use crate::{Error, Result};

/// Wavelet voices per octave over the bands.
pub const VOICES_PER_OCTAVE: usize = crate::signal::wavelet::DEFAULT_VOICES_PER_OCTAVE;

/// What a growth analysis follows when nothing else is asked: the (0,3) and (0,4) axial bands
/// that Yang & Li (2019) find in squeal, on the n >= 1 part of the rim's lateral vibration (the
/// rim point less the rim mean: the hub's lateral motion cannot drive it), each band +- 5 %
/// (the identification's tolerance), rates fitted over 4 ms windows (several periods of a
/// 1 kHz mode, short beside the 10-20 ms over which a squeal mode grows).
#[derive(Clone, Debug, Serialize)]
pub struct GrowthOptions {
    /// Column of histories.csv.
    pub column: String,
    /// The modes whose bands to follow, (nodal circles, nodal diameters).
    pub modes: Vec<(u32, u32)>,
    /// Half width of each band, relative to the mode's frequency.
    pub half_width: f64,
    /// Window of each growth-rate fit (s).
    pub window_s: f64,
}

impl Default for GrowthOptions {
    fn default() -> Self {
        GrowthOptions {
            column: "rim_point_minus_mean_lateral_velocity_m_per_s".into(),
            modes: vec![(0, 3), (0, 4)],
            half_width: 0.05,
            window_s: 0.004,
        }
    }
}

/// One frequency band to follow.
#[derive(Clone, Debug, Serialize)]
pub struct Band {
    /// Name (e.g. the mode label "(0,3)").
    pub name: String,
    /// Lower edge (Hz).
    pub low_hz: f64,
    /// Upper edge (Hz).
    pub high_hz: f64,
}

/// Growth of one band over one window.
#[derive(Clone, Debug, Serialize)]
pub struct WindowGrowth {
    /// Window start (s).
    pub from_s: f64,
    /// Window end (s).
    pub to_s: f64,
    /// Mean ridge amplitude over the window (signal unit); None when no sample of the window
    /// lies outside the band's cone of influence (a window shorter than the wavelet's reach from
    /// the record's ends, e.g. 4 ms at the (0,0) mode's 230 Hz).
    pub mean_amplitude: Option<f64>,
    /// Least-squares growth rate of the ridge amplitude (1/s); None when fewer than 8 samples
    /// of the window lie inside the cone of influence.
    pub growth_rate_per_s: Option<f64>,
}

/// Ridge and growth of one band.
#[derive(Clone, Debug, Serialize)]
pub struct BandGrowth {
    /// The band.
    pub band: Band,
    /// Ridge amplitude per time sample (NaN outside the cone of influence).
    #[serde(skip)]
    pub ridge: Vec<f64>,
    /// Frequency of the ridge per time sample (Hz).
    #[serde(skip)]
    pub ridge_frequency_hz: Vec<f64>,
    /// Growth per window.
    pub windows: Vec<WindowGrowth>,
}

/// Result of [`band_growth`].
#[derive(Clone, Debug, Serialize)]
pub struct GrowthAnalysis {
    /// Column analysed.
    pub column: String,
    /// Time of each sample (s).
    #[serde(skip)]
    pub time_s: Vec<f64>,
    /// Per band.
    pub bands: Vec<BandGrowth>,
}

/// Bands of `half_width` (relative) around the modes with the given (m, n) labels of a family
/// the lateral signal sees.
pub fn bands_for_modes(
    modes: &[ModeRef],
    labels: &[(u32, u32)],
    half_width: f64,
) -> Result<Vec<Band>> {
    let mut out = Vec::new();
    for &(m, n) in labels {
        let mode = modes
            .iter()
            .find(|md| {
                md.nodal_circles == m
                    && md.nodal_diameters == n
                    && md.family == crate::analysis::identify::ModeFamily::Axial
            })
            .ok_or_else(|| {
                Error::input(
                    "modes.json",
                    "--mode",
                    format!("no axial mode ({m},{n}) in the modal results"),
                )
            })?;
        out.push(Band {
            name: format!("({m},{n}) {:.0} Hz", mode.frequency_hz),
            low_hz: mode.frequency_hz * (1.0 - half_width),
            high_hz: mode.frequency_hz * (1.0 + half_width),
        });
    }
    Ok(out)
}

/// Ridges and growth rates of `bands` in `series` from `from_s` on, over windows of
/// `window_s`.
///
/// The phases: checks of the request, one wavelet power over all the bands (the FFT is shared),
/// then per band its ridge and the growth fitted over each window of it.
pub fn band_growth(
    series: &TimeSeries,
    bands: &[Band],
    from_s: f64,
    window_s: f64,
) -> Result<GrowthAnalysis> {
    let start = check_growth_request(series, bands, from_s, window_s)?;
    let fs = series.sample_rate_hz;
    let values = &series.values[start..];
    let f_lo = bands.iter().map(|b| b.low_hz).fold(f64::INFINITY, f64::min);
    let f_hi = bands.iter().map(|b| b.high_hz).fold(0.0, f64::max);
    let scales = Scales::from_frequency_band(0.95 * f_lo, 1.05 * f_hi, VOICES_PER_OCTAVE)?;
    let power = morlet_cwt(values, fs, &scales)?;
    let time_s: Vec<f64> = (0..values.len())
        .map(|k| series.start_time_s + (start + k) as f64 / fs)
        .collect();
    let mut out = Vec::new();
    for b in bands {
        let (ridge, ridge_f) = band_ridge(&power, b, values.len(), fs);
        let windows = window_growth(&time_s, &ridge, window_s);
        out.push(BandGrowth {
            band: b.clone(),
            ridge,
            ridge_frequency_hz: ridge_f,
            windows,
        });
    }
    Ok(GrowthAnalysis {
        column: series.column.clone(),
        time_s,
        bands: out,
    })
}

/// The request must be analysable: at least one band, each below the Nyquist frequency, a
/// positive window, and at least 16 samples from `from_s` to the record's end. Returns the
/// first sample analysed.
fn check_growth_request(
    series: &TimeSeries,
    bands: &[Band],
    from_s: f64,
    window_s: f64,
) -> Result<usize> {
    if bands.is_empty() {
        return Err(Error::input(
            "command line",
            "--mode",
            "give at least one band",
        ));
    }
    let fs = series.sample_rate_hz;
    let nyquist = 0.5 * fs;
    for b in bands {
        if !(b.low_hz > 0.0 && b.high_hz > b.low_hz && b.high_hz < nyquist) {
            return Err(Error::input(
                "command line",
                "--mode",
                format!(
                    "band {} [{:.1}, {:.1}] Hz must lie in (0, {nyquist:.1}) Hz (Nyquist)",
                    b.name, b.low_hz, b.high_hz
                ),
            ));
        }
    }
    if !(window_s.is_finite() && window_s > 0.0) {
        return Err(Error::input(
            "command line",
            "--window-ms",
            format!("must be > 0 (got {} ms)", window_s * 1e3),
        ));
    }
    let record_end_s = series.start_time_s + (series.values.len() as f64 - 1.0) / fs;
    if !(from_s.is_finite() && from_s >= series.start_time_s - 0.5 / fs) {
        return Err(Error::input(
            "command line",
            "--from-ms",
            format!(
                "{} ms lies before the record: must lie in [{:.3}, {:.3}] ms (16 samples before its end)",
                from_s * 1e3,
                series.start_time_s * 1e3,
                (record_end_s - 15.0 / fs) * 1e3
            ),
        ));
    }
    let start = ((from_s - series.start_time_s) * fs - 1e-6).ceil().max(0.0) as usize;
    if start + 16 > series.values.len() {
        return Err(Error::input(
            "command line",
            "--from-ms",
            format!(
                "the analysis must start at least 16 samples before the record ends ({:.3} ms)",
                (series.start_time_s + series.values.len() as f64 / fs) * 1e3
            ),
        ));
    }
    // Each growth rate is fitted over one window: a window longer than the record analysed
    // would leave an empty table that reads as "nothing grows".
    let analysed_s = record_end_s - (series.start_time_s + start as f64 / fs);
    if window_s > analysed_s {
        return Err(Error::input(
            "command line",
            "--window-ms",
            format!(
                "{} ms is longer than the record analysed ({:.3} ms, from {:.3} ms to its end): \
                 must lie in (0, {:.3}] ms",
                window_s * 1e3,
                analysed_s * 1e3,
                (series.start_time_s + start as f64 / fs) * 1e3,
                analysed_s * 1e3
            ),
        ));
    }
    Ok(start)
}

/// The ridge of band `b` in `power` over its `n_values` time samples: per sample, the
/// amplitude of the tone that gives the band's largest power (module docs) and the frequency
/// where it lies; NaN outside the cone of influence of the band's lowest frequency.
fn band_ridge(power: &WaveletPower, b: &Band, n_values: usize, fs: f64) -> (Vec<f64>, Vec<f64>) {
    let js: Vec<usize> = (0..power.frequency_count())
        .filter(|&j| power.frequency_hz[j] >= b.low_hz && power.frequency_hz[j] <= b.high_hz)
        .collect();
    // The band's lowest frequency has the widest cone.
    let widest = js
        .iter()
        .copied()
        .min_by(|&a, &c| power.frequency_hz[a].total_cmp(&power.frequency_hz[c]));
    let mut ridge = vec![f64::NAN; n_values];
    let mut ridge_f = vec![f64::NAN; n_values];
    for n in 0..n_values {
        if js.is_empty() || widest.is_some_and(|w| !power.is_reliable(n, w)) {
            continue;
        }
        let (j, p) = js.iter().map(|&j| (j, power.power_at(n, j))).fold(
            (js[0], f64::NEG_INFINITY),
            |a, c| if c.1 > a.1 { c } else { a },
        );
        let scale_s = power.scale_s[j];
        ridge[n] = 2.0
            * std::f64::consts::PI.powf(0.25)
            * (1.0 / (fs * std::f64::consts::TAU * scale_s)).sqrt()
            * p.max(0.0).sqrt();
        ridge_f[n] = power.frequency_hz[j];
    }
    (ridge, ridge_f)
}

/// The ridge's growth over consecutive windows of `window_s` (the last one shorter, down to
/// half a window): the mean amplitude of its reliable samples and the least-squares slope of
/// `ln A` against time, from 8 positive samples on.
fn window_growth(time_s: &[f64], ridge: &[f64], window_s: f64) -> Vec<WindowGrowth> {
    let mut windows = Vec::new();
    let mut w0 = time_s[0];
    let end = *time_s.last().unwrap_or(&w0);
    while w0 + 0.5 * window_s < end {
        let w1 = (w0 + window_s).min(end);
        let pts: Vec<(f64, f64)> = time_s
            .iter()
            .zip(ridge)
            .filter(|(t, a)| **t >= w0 && **t < w1 && a.is_finite() && **a > 0.0)
            .map(|(t, a)| (*t, a.ln()))
            .collect();
        let all: Vec<f64> = time_s
            .iter()
            .zip(ridge)
            .filter(|(t, a)| **t >= w0 && **t < w1 && a.is_finite())
            .map(|(_, a)| *a)
            .collect();
        let mean_amplitude = (!all.is_empty()).then(|| all.iter().sum::<f64>() / all.len() as f64);
        windows.push(WindowGrowth {
            from_s: w0,
            to_s: w1,
            mean_amplitude,
            growth_rate_per_s: (pts.len() >= 8).then(|| slope(&pts)),
        });
        w0 = w1;
    }
    windows
}

/// Least-squares slope of y against x.
fn slope(pts: &[(f64, f64)]) -> f64 {
    let n = pts.len() as f64;
    let mx = pts.iter().map(|p| p.0).sum::<f64>() / n;
    let my = pts.iter().map(|p| p.1).sum::<f64>() / n;
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx) * (p.0 - mx)).sum();
    if sxx > 0.0 {
        sxy / sxx
    } else {
        0.0
    }
}

/// Markdown table of the growth rates.
pub fn to_markdown(g: &GrowthAnalysis) -> String {
    let mut md = format!(
        "Wavelet-ridge amplitude and growth rate (slope of ln A, 1/s; > 0 grows) of `{}` per \
         band and window (-: too few samples of the window outside the cone of influence):\n\n| band | window (ms) | mean ridge amplitude | growth rate (1/s) |\n|---|---|---|---|\n",
        g.column
    );
    for b in &g.bands {
        for w in &b.windows {
            md.push_str(&format!(
                "| {} | {:.1}-{:.1} | {} | {} |\n",
                b.band.name,
                w.from_s * 1e3,
                w.to_s * 1e3,
                w.mean_amplitude
                    .map_or("-".to_string(), |a| format!("{a:.3e}")),
                w.growth_rate_per_s
                    .map_or("-".to_string(), |s| format!("{s:+.0}"))
            ));
        }
    }
    md
}

/// CSV of the ridges: `time_s` then one amplitude column per band.
pub fn ridges_csv(g: &GrowthAnalysis) -> String {
    let mut s = String::from("time_s");
    for b in &g.bands {
        s.push_str(&format!(",ridge_{}", sanitize(&b.band.name)));
    }
    s.push('\n');
    for (k, t) in g.time_s.iter().enumerate() {
        s.push_str(&format!("{t:.9e}"));
        for b in &g.bands {
            s.push_str(&format!(",{:.6e}", b.ridge[k]));
        }
        s.push('\n');
    }
    s
}

/// A band name as a column name: letters, digits and underscores.
fn sanitize(name: &str) -> String {
    name.chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect::<String>()
        .trim_matches('_')
        .to_string()
}

/// Reads a column of a run's `histories.csv`.
pub fn read_column(run_dir: &Path, column: &str) -> Result<TimeSeries> {
    let path = run_dir.join("histories.csv");
    let column = crate::analysis::run::resolve_column(&path, column)?;
    TimeSeries::from_csv(&path, &column)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A record `x` sampled at `fs` from t = 0.
    fn sampled_at(fs: f64, values: Vec<f64>) -> TimeSeries {
        TimeSeries {
            column: "x".into(),
            start_time_s: 0.0,
            sample_rate_hz: fs,
            values,
        }
    }

    /// A tone at 700 Hz growing as exp(100 t) and one at 1800 Hz decaying as exp(-50 t): the
    /// ridge slopes return both rates within 5 %. Why 5 %: the ridge of a slowly varying
    /// envelope is exact to `(sigma w0 / 2 pi f)^2` (1e-5 here), but each band also holds the
    /// other tone's leakage through the Morlet window, `exp(-(w0 (1 - 700/1800))^2 / 2)` =
    /// 1.2e-3 of the 700 Hz amplitude at 1800 Hz, up to 1 % of the decayed tone at 40 ms.
    #[test]
    fn ridge_slopes_return_the_growth_rates_of_synthetic_tones() {
        let fs = 50_000.0;
        let n = 2500; // 50 ms
        let values: Vec<f64> = (0..n)
            .map(|k| {
                let t = k as f64 / fs;
                (100.0 * t).exp() * (std::f64::consts::TAU * 700.0 * t).sin()
                    + 50.0 * (-50.0 * t).exp() * (std::f64::consts::TAU * 1800.0 * t).cos()
            })
            .collect();
        let series = sampled_at(fs, values);
        let bands = vec![
            Band {
                name: "a".into(),
                low_hz: 665.0,
                high_hz: 735.0,
            },
            Band {
                name: "b".into(),
                low_hz: 1710.0,
                high_hz: 1890.0,
            },
        ];
        let g = band_growth(&series, &bands, 0.0, 0.01).unwrap();
        // The ridge reads the tone's amplitude: 50 exp(-50 t) at 25 ms, within 3 %.
        let k = 1250;
        let expected = 50.0 * (-50.0f64 * 0.025).exp();
        assert!(
            (g.bands[1].ridge[k] - expected).abs() < 0.03 * expected,
            "{}",
            g.bands[1].ridge[k]
        );
        for (b, rate) in g.bands.iter().zip([100.0, -50.0]) {
            let inner: Vec<f64> = b
                .windows
                .iter()
                .filter(|w| w.from_s >= 0.01 && w.to_s <= 0.04)
                .filter_map(|w| w.growth_rate_per_s)
                .collect();
            assert!(inner.len() >= 3, "{:?}", b.windows);
            for r in inner {
                assert!(
                    (r - rate).abs() < 0.05 * rate.abs(),
                    "{} {r} vs {rate}",
                    b.band.name
                );
            }
        }
    }

    /// A 230 Hz tone (the (0,0) mode's band) over 24 ms in 4 ms windows: the Morlet wavelet at
    /// 230 Hz reaches sqrt(2) w0 / (2 pi f) = 5.9 ms from either end of the record (the cone of
    /// influence), so the first and last windows have no reliable sample and no mean amplitude;
    /// the inner ones read the tone's amplitude 2.0 within 3 % (as the test above). The table
    /// shows "-" for the missing values, never NaN.
    #[test]
    fn windows_inside_the_cone_of_influence_have_no_amplitude() {
        let fs = 50_000.0;
        let values: Vec<f64> = (0..1200)
            .map(|k| 2.0 * (std::f64::consts::TAU * 230.0 * k as f64 / fs).sin())
            .collect();
        let series = sampled_at(fs, values);
        let band = Band {
            name: "(0,0)".into(),
            low_hz: 218.5,
            high_hz: 241.5,
        };
        let g = band_growth(&series, &[band], 0.0, 0.004).unwrap();
        let windows = &g.bands[0].windows;
        assert_eq!(windows.len(), 6, "{windows:?}");
        for w in [&windows[0], &windows[5]] {
            assert!(w.mean_amplitude.is_none(), "{w:?}");
            assert!(w.growth_rate_per_s.is_none(), "{w:?}");
        }
        for w in &windows[2..4] {
            let a = w
                .mean_amplitude
                .expect("an inner window has reliable samples");
            assert!((a - 2.0).abs() < 0.06, "{w:?}");
        }
        let table = to_markdown(&g);
        assert!(!table.contains("NaN"), "{table}");
        assert!(table.contains("| (0,0) | 0.0-4.0 | - | - |"), "{table}");
    }
}
