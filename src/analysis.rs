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

use std::path::{Path, PathBuf};

use serde::Serialize;

use crate::identify::{identify, Direction, ModeRef, PeakIdentification, Tolerance};
use crate::input::read_json;
use crate::signal::{find_spectral_peaks, welch, PeakSearch, Psd, TimeSeries, WelchParams};
use crate::{Error, Result};

/// Options of a run analysis.
#[derive(Clone, Debug, Serialize)]
pub struct AnalysisOptions {
    /// Signal: a direction (`lateral`, `vertical`, `longitudinal`) or an exact column name.
    pub signal: String,
    /// Number of dominant peaks.
    pub peaks: usize,
    /// Band for the peaks (Hz).
    pub band_hz: (f64, f64),
    /// Welch segment length (None: largest power of two giving at least 3 half-overlapping
    /// segments).
    pub nperseg: Option<usize>,
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
            band_hz: (50.0, 10_000.0),
            nperseg: None,
            min_separation_hz: 50.0,
            tolerance: Tolerance::default(),
            modes_file: None,
        }
    }
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
    /// Dominant peaks with their modes.
    pub identifications: Vec<PeakIdentification>,
    /// The modes used.
    pub modes: Vec<ModeRef>,
}

/// Resolve a signal name to a column of the histories file: an exact column name, or the one
/// column whose name starts with `<signal>_`.
pub fn resolve_column(path: &Path, signal: &str) -> Result<String> {
    let file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
    let mut reader = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .from_reader(file);
    let headers: Vec<String> = reader
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
        .collect();
    if headers.iter().any(|h| h == signal) {
        return Ok(signal.to_string());
    }
    let prefix = format!("{signal}_");
    let matches: Vec<&String> = headers.iter().filter(|h| h.starts_with(&prefix)).collect();
    match matches.len() {
        1 => Ok(matches[0].clone()),
        0 => Err(Error::input(
            path.display().to_string(),
            "--signal",
            format!(
                "no column `{signal}` or `{prefix}*`; available: {}",
                headers.join(", ")
            ),
        )),
        _ => Err(Error::input(
            path.display().to_string(),
            "--signal",
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

/// Analyse one signal of a run directory.
pub fn analyse_run(run_dir: &Path, options: &AnalysisOptions) -> Result<RunAnalysis> {
    if !run_dir.is_dir() {
        return Err(Error::input(
            run_dir.display().to_string(),
            "RUN_DIR",
            "is not a directory",
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
        Error::input(histories.display().to_string(), "--signal", format!("column `{column}` does not start with lateral, vertical or longitudinal, so its modes cannot be chosen"))
    })?;
    let series = TimeSeries::from_csv(&histories, &column)?;
    let nyquist = 0.5 * series.sample_rate_hz;
    let (f_lo, f_hi) = options.band_hz;
    if !(f_lo >= 0.0 && f_hi > f_lo) {
        return Err(Error::input(
            "command line",
            "--fmin/--fmax",
            format!("need 0 <= fmin < fmax, got [{f_lo}, {f_hi}]"),
        ));
    }
    if f_hi > nyquist {
        return Err(Error::input(
            histories.display().to_string(),
            "--fmax",
            format!("{f_hi} Hz is above the Nyquist frequency {nyquist:.1} Hz of the {:.1} Hz sampled history; lower --fmax or sample faster", series.sample_rate_hz),
        ));
    }
    let n = series.values.len();
    let nperseg = match options.nperseg {
        Some(v) => v,
        None => {
            let mut p = 64usize;
            while p * 2 <= n / 2 {
                p *= 2;
            }
            p.min(n)
        }
    };
    let params = WelchParams::new(nperseg);
    let psd = welch(&series.values, series.sample_rate_hz, &params)?;
    let search = PeakSearch {
        min_frequency_hz: f_lo,
        max_frequency_hz: f_hi,
        min_separation_hz: options.min_separation_hz,
        max_peaks: options.peaks,
        ..Default::default()
    };
    let peaks = find_spectral_peaks(&psd.frequency_hz, &psd.psd_per_hz, &search)?;
    let modes_path = options
        .modes_file
        .clone()
        .unwrap_or_else(|| run_dir.join("modes.json"));
    if !modes_path.exists() {
        return Err(Error::input(
            modes_path.display().to_string(),
            "modes",
            "no modal results: run `squeal modes ... --out RUN_DIR` or pass --modes FILE",
        ));
    }
    let modes: Vec<ModeRef> = read_json(&modes_path)?;
    let identifications = identify(&peaks, &modes, direction, options.tolerance);
    Ok(RunAnalysis {
        column,
        direction,
        sample_rate_hz: series.sample_rate_hz,
        psd,
        identifications,
        modes,
    })
}
