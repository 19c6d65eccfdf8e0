//! Analysis of a run directory: PSD of a wheel vibration history, its dominant peaks, and the
//! wheel modes that explain them.
//!
//! A run directory holds (written by `squeal simulate`, or by hand from other tools):
//! - `histories.csv`: a `time_s` column (uniform steps) and vibration columns whose names
//!   start with their direction, e.g. `lateral_velocity_m_per_s`, `vertical_...`,
//!   `longitudinal_...`;
//! - `modes.json`: the wheel modes, a JSON array of
//!   `{"frequency_hz", "family", "nodal_circles", "nodal_diameters"}` (family: axial, radial,
//!   circumferential or rigid).
//!
//! The spectrum is taken over a window of the record: by default, for a rolling run whose
//! `run.json` names a lateral motion, from its onset to the end (the start-up before it is a
//! different vibration), else the whole record; with bins no wider than the requested
//! resolution (default 50 Hz), by zero padding where the window is short
//! ([`crate::signal::resolution`]). When the run also has the rim-averaged column
//! (`rim_mean_<column>`), each peak carries `PSD(rim mean) / PSD(rim point)`, summed over the
//! peak's bin and its two neighbours, which decides the nodal diameters a peak may be given
//! ([`crate::analysis::identify`]).

use std::path::{Path, PathBuf};

use serde::Serialize;

use crate::analysis::identify::{identify, Direction, ModeRef, PeakIdentification, Tolerance};
use crate::input::read_json;
use crate::signal::resolution::{describe, welch_for_resolution};
use crate::signal::{welch, PeakSearch, Psd, TimeSeries};
use crate::{Error, Result};

/// Options of a run analysis.
#[derive(Clone, Debug, Serialize)]
pub struct AnalysisOptions {
    /// Signal: a direction (`lateral`, `vertical`, `longitudinal`) or an exact column name.
    pub signal: String,
    /// Number of dominant peaks.
    pub peaks: usize,
    /// Band for the peaks (Hz); an infinite upper edge means [`DEFAULT_FMAX_HZ`] or the
    /// history's Nyquist frequency, whichever is lower.
    pub band_hz: (f64, f64),
    /// Welch segment length (None: chosen for the resolution, see
    /// [`crate::signal::resolution`]).
    pub nperseg: Option<usize>,
    /// Largest bin spacing (Hz).
    pub resolution_hz: f64,
    /// Start of the analysed window (s); None: the lateral-motion onset of a rolling run, else
    /// the first sample.
    pub from_s: Option<f64>,
    /// End of the analysed window (s); None: the last sample.
    pub to_s: Option<f64>,
    /// Minimum separation between peaks (Hz).
    pub min_separation_hz: f64,
    /// Matching tolerance.
    pub tolerance: Tolerance,
    /// Modes file (None: `RUN_DIR/modes.json`).
    pub modes_file: Option<PathBuf>,
}

impl Default for AnalysisOptions {
    fn default() -> Self {
        AnalysisOptions {
            signal: "lateral".into(),
            peaks: 3,
            band_hz: (50.0, f64::INFINITY),
            nperseg: None,
            resolution_hz: DEFAULT_RESOLUTION_HZ,
            from_s: None,
            to_s: None,
            min_separation_hz: 50.0,
            tolerance: Tolerance::default(),
            modes_file: None,
        }
    }
}

/// Default largest bin spacing (Hz): fine enough to put (1,0) at 1767 Hz and (0,4) at 1839 Hz
/// of the default wheel on different bins.
pub const DEFAULT_RESOLUTION_HZ: f64 = 50.0;

/// Default upper edge of the peak band (Hz): wheel squeal lies below it (Thompson, Railway
/// Noise and Vibration, 2009, ch. 9: 1-10 kHz at most).
pub const DEFAULT_FMAX_HZ: f64 = 10_000.0;

/// The analysed span of a record.
#[derive(Clone, Debug, Serialize)]
pub struct AnalysisWindow {
    /// Start (s).
    pub from_s: f64,
    /// End (s).
    pub to_s: f64,
    /// Where the start came from.
    pub start_from: String,
    /// What the spectrum is (segments, padding, bins, main lobe).
    pub spectrum: String,
}

/// Result of a run analysis.
#[derive(Clone, Debug, Serialize)]
pub struct RunAnalysis {
    /// Column analysed.
    pub column: String,
    /// Direction of the signal.
    pub direction: Direction,
    /// Sample rate (Hz).
    pub sample_rate_hz: f64,
    /// Welch PSD.
    pub psd: Psd,
    /// The analysed window and how the spectrum was taken.
    pub window: AnalysisWindow,
    /// The rim-mean column and its PSD (same parameters), when the run has it.
    pub rim_mean: Option<(String, Psd)>,
    /// Dominant peaks with their modes.
    pub identifications: Vec<PeakIdentification>,
    /// The modes used.
    pub modes: Vec<ModeRef>,
}

/// Resolve a signal name to a column of the histories file: an exact column name, or the one
/// column whose name starts with `<signal>_`.
pub fn resolve_column(path: &Path, signal: &str) -> Result<String> {
    let headers = read_csv_headers(path)?;
    if headers.iter().any(|h| h == signal) {
        return Ok(signal.to_string());
    }
    let prefix = format!("{signal}_");
    let matches: Vec<&String> = headers.iter().filter(|h| h.starts_with(&prefix)).collect();
    match matches.len() {
        1 => Ok(matches[0].clone()),
        0 => Err(Error::input(
            path.display().to_string(),
            "--direction/--column",
            format!(
                "no column `{signal}` or `{prefix}*`; available: {}",
                headers.join(", ")
            ),
        )),
        _ => Err(Error::input(
            path.display().to_string(),
            "--direction/--column",
            format!(
                "`{signal}` is ambiguous ({}); give the exact column name",
                matches
                    .iter()
                    .map(|s| s.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        )),
    }
}

/// The column names of a CSV file's header line.
pub fn read_csv_headers(path: &Path) -> Result<Vec<String>> {
    let file = std::fs::File::open(path).map_err(|e| Error::reading(path, e))?;
    let mut reader = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .from_reader(file);
    Ok(reader
        .headers()
        .map_err(|e| {
            Error::input(
                path.display().to_string(),
                "header",
                format!("cannot read the CSV header: {e}"),
            )
        })?
        .iter()
        .map(str::to_string)
        .collect())
}

/// Analyse one signal of a run directory.
pub fn analyse_run(run_dir: &Path, options: &AnalysisOptions) -> Result<RunAnalysis> {
    if !run_dir.is_dir() {
        return Err(Error::input(
            run_dir.display().to_string(),
            "RUN_DIR",
            "is not a directory: expected a run directory with histories.csv (from `squeal simulate`)",
        ));
    }
    let histories = run_dir.join("histories.csv");
    if !histories.exists() {
        return Err(Error::input(
            run_dir.display().to_string(),
            "histories.csv",
            "the run directory has no histories.csv (run `squeal simulate` first)",
        ));
    }
    let column = resolve_column(&histories, &options.signal)?;
    let direction = Direction::from_signal_name(&column).ok_or_else(|| {
        Error::input(histories.display().to_string(), "--column", format!("column `{column}` does not start with lateral, vertical or longitudinal, so its modes cannot be chosen"))
    })?;
    let series = TimeSeries::from_csv(&histories, &column)?;
    let nyquist = 0.5 * series.sample_rate_hz;
    // An infinite upper edge asks for the default: 10 kHz or the Nyquist frequency.
    let (f_lo, f_hi) = match options.band_hz {
        (lo, hi) if hi.is_infinite() && hi > 0.0 => (lo, DEFAULT_FMAX_HZ.min(nyquist)),
        band => band,
    };
    if !(f_lo >= 0.0 && f_hi > f_lo) {
        return Err(Error::input(
            "command line",
            "--fmin-hz/--fmax-hz",
            format!("need 0 <= fmin < fmax, got [{f_lo}, {f_hi}]"),
        ));
    }
    if f_hi > nyquist {
        return Err(Error::input(
            histories.display().to_string(),
            "--fmax-hz",
            format!("{f_hi} Hz is outside the allowed range (fmin, {nyquist:.1}] Hz: the Nyquist frequency of the {:.1} Hz sampled history; lower --fmax-hz or sample faster", series.sample_rate_hz),
        ));
    }
    let (from_s, start_from) = match options.from_s {
        Some(t) => (t, "--from-ms".to_string()),
        None => match lateral_onset_s(run_dir)? {
            Some(t) => (t, "the lateral-motion onset (run.json)".to_string()),
            None => (series.start_time_s, "the first sample".to_string()),
        },
    };
    let range = window_range(&series, from_s, options.to_s, &histories)?;
    let values = &series.values[range.clone()];
    let params = welch_for_resolution(
        values.len(),
        series.sample_rate_hz,
        options.resolution_hz,
        options.nperseg,
    )?;
    let psd = welch(values, series.sample_rate_hz, &params)?;
    let window = AnalysisWindow {
        from_s: series.start_time_s + range.start as f64 / series.sample_rate_hz,
        to_s: series.start_time_s + (range.end - 1) as f64 / series.sample_rate_hz,
        start_from,
        spectrum: describe(&params, series.sample_rate_hz, psd.segment_count),
    };
    let rim_column = format!("rim_mean_{column}");
    let rim_mean = if resolve_column(&histories, &rim_column).is_ok_and(|c| c == rim_column) {
        let rim = TimeSeries::from_csv(&histories, &rim_column)?;
        let rim_psd = welch(&rim.values[range], rim.sample_rate_hz, &params)?;
        Some((rim_column, rim_psd))
    } else {
        None
    };
    let search = PeakSearch {
        min_frequency_hz: f_lo,
        max_frequency_hz: f_hi,
        min_separation_hz: options.min_separation_hz,
        max_peaks: options.peaks,
        ..Default::default()
    };
    let peaks = psd.find_peaks(&search)?;
    let modes = read_run_modes(run_dir, options.modes_file.as_deref())?;
    // The rim point less the rim mean has no rim-mean part by construction: ratio 0, so that
    // its peaks get only modes with nodal diameters the mean cancels.
    let ratios: Option<Vec<f64>> = if column.starts_with("rim_point_minus_mean_") {
        Some(vec![0.0; peaks.len()])
    } else {
        rim_mean.as_ref().map(|(_, rim_psd)| {
            peaks
                .iter()
                .map(|p| rim_ratio(&psd, rim_psd, p.refined_frequency_hz))
                .collect()
        })
    };
    let identifications = identify(
        &peaks,
        ratios.as_deref(),
        &modes,
        direction,
        options.tolerance,
    );
    Ok(RunAnalysis {
        column,
        direction,
        sample_rate_hz: series.sample_rate_hz,
        psd,
        window,
        rim_mean,
        identifications,
        modes,
    })
}

/// The modes that label a run's peaks: `modes_file`, or the run's own `modes.json`.
pub fn read_run_modes(run_dir: &Path, modes_file: Option<&Path>) -> Result<Vec<ModeRef>> {
    let modes_path = modes_file
        .map(Path::to_path_buf)
        .unwrap_or_else(|| run_dir.join("modes.json"));
    if !modes_path.exists() {
        return Err(Error::input(
            modes_path.display().to_string(),
            "modes",
            "no modal results: run `squeal modes ... --out RUN_DIR` or pass --modes FILE",
        ));
    }
    crate::modal::mode::read_modes_json(&modes_path)
}

/// `PSD(rim mean) / PSD(rim point)` summed over the bin nearest `f_hz` and its two neighbours.
pub fn rim_ratio(point: &Psd, mean: &Psd, f_hz: f64) -> f64 {
    let df = point.frequency_resolution_hz;
    let k = (f_hz / df).round().max(0.0) as usize;
    let last = point.psd_per_hz.len().saturating_sub(1);
    let band = ndarray::s![k.saturating_sub(1).min(last)..=(k + 1).min(last)];
    let num: f64 = mean.psd_per_hz.slice(band).sum();
    let den: f64 = point.psd_per_hz.slice(band).sum();
    if den > 0.0 {
        num / den
    } else {
        f64::NAN
    }
}

/// The lateral-motion onset of a rolling run, from `run.json` (`settings.lateral_motion`):
/// None when the directory has no `run.json` (a history from elsewhere) or the run has no
/// lateral motion. A `run.json` that is not JSON, or whose lateral motion does not read, is an
/// input error naming it: analysing from the first sample instead would silently change the
/// window (issue 53, item 11).
pub fn lateral_onset_s(run_dir: &Path) -> Result<Option<f64>> {
    let path = run_dir.join("run.json");
    if !path.exists() {
        return Ok(None);
    }
    let record: serde_json::Value = read_json(&path)?;
    let motion = match record.get("settings").and_then(|s| s.get("lateral_motion")) {
        None | Some(serde_json::Value::Null) => return Ok(None),
        Some(m) => m,
    };
    match serde_json::from_value::<crate::model::lateral::LateralMotion>(motion.clone()) {
        Ok(motion) => Ok(Some(motion.onset_s())),
        // Runs written before the motion had shapes (data/runs/case*-paper*) record
        // `{start_s, velocity_m_per_s}`: the motion starts at `start_s`.
        Err(e) => match motion.get("start_s").and_then(serde_json::Value::as_f64) {
            Some(start_s) if start_s.is_finite() && motion.get("shape").is_none() => {
                Ok(Some(start_s))
            }
            _ => Err(Error::input(
                path.display().to_string(),
                "settings.lateral_motion",
                format!("does not read as a lateral motion: {e}"),
            )),
        },
    }
}

/// Sample indices of the window `[from_s, to_s]` of a series; errors name the option.
pub(crate) fn window_range(
    series: &TimeSeries,
    from_s: f64,
    to_s: Option<f64>,
    path: &Path,
) -> Result<std::ops::Range<usize>> {
    let n = series.values.len();
    let fs = series.sample_rate_hz;
    let first_s = series.start_time_s;
    let last_s = first_s + (n.saturating_sub(1)) as f64 / fs;
    let name = path.display().to_string();
    if !(from_s.is_finite() && from_s >= first_s - 0.5 / fs && from_s < last_s) {
        return Err(Error::input(
            name,
            "--from-ms",
            format!(
                "the window must start within the record, [{:.3}, {:.3}) ms (got {:.3} ms)",
                first_s * 1e3,
                last_s * 1e3,
                from_s * 1e3
            ),
        ));
    }
    let to = to_s.unwrap_or(last_s);
    if !(to.is_finite() && to > from_s && to <= last_s + 0.5 / fs) {
        return Err(Error::input(
            name,
            "--to-ms",
            format!(
                "the window must end after its start ({:.3} ms) and within the record (up to \
                 {:.3} ms); got {:.3} ms",
                from_s * 1e3,
                last_s * 1e3,
                to * 1e3
            ),
        ));
    }
    let start = (((from_s - first_s) * fs) - 1e-6).ceil().max(0.0) as usize;
    let end = ((((to - first_s) * fs) + 1e-6).floor() as usize + 1).min(n);
    Ok(start..end)
}
