//! `squeal psd`, `squeal cwt`, `squeal wav`: spectra, wavelet power and audio of one CSV column.
//! Thin glue: parse, call `squeal::signal`, write files.

use std::io::Write;
use std::path::{Path, PathBuf};

use clap::Args;
use squeal::output::{write_file_staged, Commit, StagedDir};
use squeal::signal::{
    morlet_cwt, series::TimeSeries, wav::write_wav, welch, Detrend, PeakRanking, PeakSearch,
    PsdScaling, Scales, WelchParams, Window,
};
use squeal::{Error, Result};

/// Input column shared by the signal subcommands.
#[derive(Args, Debug)]
pub struct InputArgs {
    /// CSV file with a `time_s` column (uniform steps) and the signal column.
    #[arg(long)]
    pub csv: PathBuf,
    /// Name of the signal column.
    #[arg(long)]
    pub column: String,
    /// Unit of the column for output headers (default: the column name's last `_` token,
    /// e.g. `m` for `uy_m`).
    #[arg(long)]
    pub unit: Option<String>,
}

impl InputArgs {
    fn read(&self) -> Result<TimeSeries> {
        TimeSeries::from_csv(&self.csv, &self.column)
    }

    fn unit(&self) -> String {
        self.unit
            .clone()
            .unwrap_or_else(|| match self.column.rsplit_once('_') {
                Some((_, unit)) if !unit.is_empty() => unit.to_string(),
                _ => "unit".to_string(),
            })
    }

    /// Re-labels a library input error with the file and column it concerns.
    fn in_context(&self, error: Error) -> Error {
        match error {
            Error::Input {
                source_name,
                field,
                message,
            } => Error::input(
                format!(
                    "{} column `{}` ({source_name})",
                    self.csv.display(),
                    self.column
                ),
                field,
                message,
            ),
            other => other,
        }
    }
}

/// Welch PSD and dominant peaks.
#[derive(Args, Debug)]
pub struct PsdArgs {
    #[command(flatten)]
    pub input: InputArgs,
    /// Samples per segment (default: min(4096, signal length)).
    #[arg(long)]
    pub nperseg: Option<usize>,
    /// Segment overlap as a fraction of nperseg, in [0, 1).
    #[arg(long, default_value_t = 0.5)]
    pub overlap: f64,
    /// Window: hann, hamming, boxcar.
    #[arg(long, default_value = "hann")]
    pub window: String,
    /// Detrend per segment: constant, linear, none.
    #[arg(long, default_value = "constant")]
    pub detrend: String,
    /// Scaling: density (unit^2/Hz) or spectrum (unit^2).
    #[arg(long, default_value = "density")]
    pub scaling: String,
    /// Number of dominant peaks to report.
    #[arg(long, default_value_t = 5)]
    pub peaks: usize,
    /// Rank peaks by `prominence` or `height`.
    #[arg(long, default_value = "prominence")]
    pub rank: String,
    /// Lowest peak frequency, Hz.
    #[arg(long, default_value_t = 0.0)]
    pub peak_fmin: f64,
    /// Highest peak frequency, Hz (default: Nyquist).
    #[arg(long)]
    pub peak_fmax: Option<f64>,
    /// Minimum separation between reported peaks, Hz.
    #[arg(long, default_value_t = 0.0)]
    pub min_separation_hz: f64,
    /// Output directory (psd.csv, peaks.json).
    #[arg(long)]
    pub out: PathBuf,
}

/// Morlet wavelet power.
#[derive(Args, Debug)]
pub struct CwtArgs {
    #[command(flatten)]
    pub input: InputArgs,
    /// Lowest frequency, Hz.
    #[arg(long)]
    pub fmin: f64,
    /// Highest frequency, Hz (at most Nyquist).
    #[arg(long)]
    pub fmax: f64,
    /// Scales per octave.
    #[arg(long, default_value_t = 16)]
    pub voices: usize,
    /// Write every n-th time sample (the transform uses all samples).
    #[arg(long, default_value_t = 1)]
    pub time_stride: usize,
    /// Output directory (cwt_power.csv, cwt_coi.csv, cwt.json).
    #[arg(long)]
    pub out: PathBuf,
}

/// Audio export.
#[derive(Args, Debug)]
pub struct WavArgs {
    #[command(flatten)]
    pub input: InputArgs,
    /// Audio sample rate, Hz.
    #[arg(long, default_value_t = 44_100)]
    pub rate: u32,
    /// Output WAV file.
    #[arg(long)]
    pub out: PathBuf,
}

fn create_file(path: &Path) -> Result<std::io::BufWriter<std::fs::File>> {
    Ok(std::io::BufWriter::new(
        std::fs::File::create(path).map_err(|e| Error::io(path, e))?,
    ))
}

fn write_json(path: &Path, value: &serde_json::Value) -> Result<()> {
    let text = serde_json::to_string_pretty(value).map_err(|e| Error::Numerical(e.to_string()))?;
    std::fs::write(path, text + "\n").map_err(|e| Error::io(path, e))
}

/// `squeal psd`.
pub fn run_psd(args: PsdArgs) -> Result<()> {
    let series = args.input.read()?;
    let cli = |field: &str, message: String| Error::input("command line", field, message);
    let nperseg = args.nperseg.unwrap_or(series.values.len().min(4096));
    let mut params = WelchParams::with_overlap_fraction(nperseg, args.overlap)
        .map_err(|e| args.input.in_context(e))?;
    params.window = args.window.parse::<Window>()?;
    params.detrend = args.detrend.parse::<Detrend>()?;
    params.scaling = match args.scaling.as_str() {
        "density" => PsdScaling::Density,
        "spectrum" => PsdScaling::Spectrum,
        other => {
            return Err(cli(
                "scaling",
                format!("unknown scaling `{other}`; allowed: density, spectrum"),
            ))
        }
    };
    let ranking = match args.rank.as_str() {
        "prominence" => PeakRanking::Prominence,
        "height" => PeakRanking::Height,
        other => {
            return Err(cli(
                "rank",
                format!("unknown ranking `{other}`; allowed: prominence, height"),
            ))
        }
    };
    let nyquist_hz = 0.5 * series.sample_rate_hz;
    if !(args.peak_fmin >= 0.0 && args.peak_fmin < nyquist_hz) {
        return Err(cli(
            "--peak-fmin",
            format!(
                "must be in [0, {nyquist_hz}) Hz (the Nyquist frequency of the {} Hz sampled \
                 column), got {}",
                series.sample_rate_hz, args.peak_fmin
            ),
        ));
    }
    if let Some(fmax) = args.peak_fmax {
        if !(fmax > args.peak_fmin && fmax <= nyquist_hz) {
            return Err(cli(
                "--peak-fmax",
                format!(
                    "must be in ({}, {nyquist_hz}] Hz (above --peak-fmin, at most the Nyquist \
                     frequency), got {fmax}",
                    args.peak_fmin
                ),
            ));
        }
    }
    if !(1..=1000).contains(&args.peaks) {
        return Err(cli(
            "--peaks",
            format!("must be in [1, 1000], got {}", args.peaks),
        ));
    }
    if !(args.min_separation_hz >= 0.0 && args.min_separation_hz.is_finite()) {
        return Err(cli(
            "--min-separation-hz",
            format!("must be in [0, inf) Hz, got {}", args.min_separation_hz),
        ));
    }
    let psd = welch(&series.values, series.sample_rate_hz, &params)
        .map_err(|e| args.input.in_context(e))?;
    let search = PeakSearch {
        min_frequency_hz: args.peak_fmin,
        max_frequency_hz: args.peak_fmax.unwrap_or(f64::INFINITY),
        min_separation_hz: args.min_separation_hz,
        max_peaks: args.peaks,
        ranking,
    };
    let peaks = psd.find_peaks(&search)?;

    // Written beside the output folder and moved into it when complete.
    let stage = StagedDir::new(&args.out)?;
    let dir = stage.path().to_path_buf();
    let unit = args.input.unit();
    let psd_path = dir.join("psd.csv");
    let mut file = create_file(&psd_path)?;
    let value_header = match params.scaling {
        PsdScaling::Density => format!("psd_{unit}^2_per_hz"),
        PsdScaling::Spectrum => format!("power_{unit}^2"),
    };
    let io = |e| Error::io(&psd_path, e);
    writeln!(file, "frequency_hz,{value_header}").map_err(io)?;
    for (f, p) in psd.frequency_hz.iter().zip(&psd.psd_per_hz) {
        writeln!(file, "{f},{p:e}").map_err(io)?;
    }
    file.flush().map_err(io)?;
    write_json(
        &dir.join("peaks.json"),
        &serde_json::json!({
            "source": args.input.csv.display().to_string(),
            "column": args.input.column,
            "unit": unit,
            "sample_rate_hz": series.sample_rate_hz,
            "welch": psd.params,
            "frequency_resolution_hz": psd.frequency_resolution_hz,
            "segment_count": psd.segment_count,
            "peak_search": { "min_frequency_hz": search.min_frequency_hz,
                             "max_frequency_hz": args.peak_fmax,
                             "min_separation_hz": search.min_separation_hz,
                             "max_peaks": search.max_peaks, "ranking": search.ranking },
            "refinement": "parabola through ln(PSD) at bins k-1, k, k+1",
            "peaks": peaks,
        }),
    )?;
    println!(
        "psd: {} bins, df = {} Hz, {} segments -> {}",
        psd.frequency_hz.len(),
        psd.frequency_resolution_hz,
        psd.segment_count,
        args.out.display()
    );
    for peak in &peaks {
        println!(
            "  peak {:.3} Hz  psd {:.4e}  prominence {:.4e}",
            peak.refined_frequency_hz, peak.psd, peak.prominence
        );
    }
    stage.commit(Commit::Merge)?;
    Ok(())
}

/// `squeal cwt`.
pub fn run_cwt(args: CwtArgs) -> Result<()> {
    let series = args.input.read()?;
    if args.time_stride == 0 {
        return Err(Error::input("command line", "time-stride", "must be >= 1"));
    }
    let scales = Scales::from_frequency_band(args.fmin, args.fmax, args.voices)
        .map_err(|e| args.input.in_context(e))?;
    let cwt = morlet_cwt(&series.values, series.sample_rate_hz, &scales)
        .map_err(|e| args.input.in_context(e))?;

    // Written beside the output folder and moved into it when complete.
    let stage = StagedDir::new(&args.out)?;
    let dir = stage.path().to_path_buf();
    let unit = args.input.unit();
    let time_s = |n: usize| series.start_time_s + n as f64 / series.sample_rate_hz;
    let power_path = dir.join("cwt_power.csv");
    let mut file = create_file(&power_path)?;
    let io = |e| Error::io(&power_path, e);
    writeln!(file, "time_s,frequency_hz,power_{unit}^2").map_err(io)?;
    for n in (0..cwt.time_count).step_by(args.time_stride) {
        for (j, f) in cwt.frequency_hz.iter().enumerate() {
            writeln!(file, "{},{f},{:e}", time_s(n), cwt.power_at(n, j)).map_err(io)?;
        }
    }
    file.flush().map_err(io)?;

    let coi_path = dir.join("cwt_coi.csv");
    let mut file = create_file(&coi_path)?;
    let io = |e| Error::io(&coi_path, e);
    writeln!(file, "time_s,coi_period_s,coi_frequency_hz").map_err(io)?;
    for n in (0..cwt.time_count).step_by(args.time_stride) {
        let period = cwt.coi_period_s[n];
        writeln!(file, "{},{period},{}", time_s(n), 1.0 / period).map_err(io)?;
    }
    file.flush().map_err(io)?;
    write_json(
        &dir.join("cwt.json"),
        &serde_json::json!({
            "source": args.input.csv.display().to_string(),
            "column": args.input.column,
            "unit": unit,
            "wavelet": "Morlet, omega0 = 6, Torrence & Compo (1998) normalisation",
            "sample_rate_hz": series.sample_rate_hz,
            "time_count": cwt.time_count,
            "time_stride": args.time_stride,
            "frequency_hz": cwt.frequency_hz,
            "scale_s": cwt.scale_s,
            "power_file": "cwt_power.csv",
            "coi_file": "cwt_coi.csv (frequencies below coi_frequency_hz are affected by the record ends)",
        }),
    )?;
    println!(
        "cwt: {} times x {} frequencies ({:.3}..{:.3} Hz) -> {}",
        cwt.time_count,
        cwt.frequency_count(),
        args.fmin,
        args.fmax,
        args.out.display()
    );
    stage.commit(Commit::Merge)?;
    Ok(())
}

/// `squeal wav`.
pub fn run_wav(args: WavArgs) -> Result<()> {
    let series = args.input.read()?;
    let count = write_file_staged(&args.out, |p| {
        write_wav(p, &series.values, series.sample_rate_hz, args.rate)
    })
    .map_err(|e| args.input.in_context(e))?;
    println!(
        "wav: {count} samples at {} Hz -> {}",
        args.rate,
        args.out.display()
    );
    Ok(())
}
