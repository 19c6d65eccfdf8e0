//! `squeal psd`, `squeal cwt`, `squeal wav`: spectra, wavelet power and audio of one CSV column.
//! Thin glue: parse, call `squeal::signal`, write files.

use std::io::Write;
use std::path::{Path, PathBuf};

use clap::Args;
use squeal::output::{write_file_staged, Commit, StagedDir};
use squeal::signal::peaks::DEFAULT_PEAK_COUNT;
use squeal::signal::wav::{DEFAULT_SAMPLE_RATE_HZ, SAMPLE_RATE_RANGE_HZ};
use squeal::signal::wavelet::DEFAULT_VOICES_PER_OCTAVE;
use squeal::signal::welch::{DEFAULT_NPERSEG, DEFAULT_OVERLAP_FRACTION};
use squeal::signal::{
    morlet_cwt, series::TimeSeries, wav::write_wav, welch, Detrend, PeakRanking, PeakSearch,
    PsdScaling, Scales, WelchParams, Window,
};
use squeal::{Error, Result};

use super::grammar::{input_name, note, out_dir};

/// Input column shared by the signal subcommands.
#[derive(Args, Debug)]
#[command(group(clap::ArgGroup::new("input").required(true).args(["source", "csv"])))]
pub struct InputArgs {
    /// A run directory (its histories.csv is read) or a CSV file with a `time_s` column
    /// (uniform steps) and the signal column.
    pub source: Option<PathBuf>,
    /// Deprecated: the CSV file as SOURCE.
    #[arg(long, hide = true)]
    pub csv: Option<PathBuf>,
    /// Name of the signal column.
    #[arg(long)]
    pub column: String,
    /// Unit of the column for output headers (default: the column name's last `_` token,
    /// e.g. `m` for `uy_m`).
    #[arg(long)]
    pub unit: Option<String>,
}

impl InputArgs {
    /// The CSV file read: SOURCE's histories.csv for a run directory, else SOURCE itself.
    fn csv_path(&self) -> PathBuf {
        match (&self.source, &self.csv) {
            (Some(source), _) if source.is_dir() => source.join("histories.csv"),
            (Some(source), _) => source.clone(),
            (None, Some(csv)) => csv.clone(),
            (None, None) => unreachable!("clap's group requires SOURCE or --csv"),
        }
    }

    /// The name of the input for a default output folder.
    fn name(&self) -> String {
        input_name(
            self.source
                .as_ref()
                .or(self.csv.as_ref())
                .expect("one input"),
        )
    }

    /// Reads the column (each command once; the deprecated `--csv FILE` says so here, once).
    fn read(&self) -> Result<TimeSeries> {
        squeal::output::protect_inputs(self.source.iter().chain(&self.csv));
        if self.source.is_none() && self.csv.is_some() {
            note("--csv FILE", "FILE (a positional SOURCE)");
        }
        TimeSeries::from_csv(&self.csv_path(), &self.column)
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
                    self.csv_path().display(),
                    self.column
                ),
                // The Welch parameters a user sets are options of this command: name them so.
                match field.as_str() {
                    "nperseg" | "overlap" | "window" | "detrend" => format!("--{field}"),
                    _ => field,
                },
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
    /// Samples per segment. Default: the library's segment length, or the whole signal if
    /// shorter.
    #[arg(long)]
    pub nperseg: Option<usize>,
    /// Segment overlap as a fraction of nperseg, in [0, 1).
    #[arg(long, default_value_t = DEFAULT_OVERLAP_FRACTION)]
    pub overlap: f64,
    /// Window: hann, hamming, boxcar.
    #[arg(long, default_value_t = Window::default().name().to_string())]
    pub window: String,
    /// Detrend per segment: constant, linear, none.
    #[arg(long, default_value_t = WelchParams::new(1).detrend.name().to_string())]
    pub detrend: String,
    /// Scaling: density (unit^2/Hz) or spectrum (unit^2).
    #[arg(long, default_value_t = PsdScaling::default().name().to_string())]
    pub scaling: String,
    /// Number of dominant peaks to report.
    #[arg(long, default_value_t = DEFAULT_PEAK_COUNT)]
    pub peaks: usize,
    /// Rank peaks by `prominence` or `height`.
    #[arg(long, default_value_t = PeakRanking::default().name().to_string())]
    pub rank: String,
    /// Lowest peak frequency, Hz.
    #[arg(long = "fmin-hz", alias = "peak-fmin", default_value_t = PeakSearch::default().min_frequency_hz)]
    pub fmin_hz: f64,
    /// Highest peak frequency, Hz (default: Nyquist).
    #[arg(long = "fmax-hz", alias = "peak-fmax")]
    pub fmax_hz: Option<f64>,
    /// Minimum separation between reported peaks, Hz.
    #[arg(long, default_value_t = PeakSearch::default().min_separation_hz)]
    pub min_separation_hz: f64,
    /// Output folder (psd.csv, peaks.json). Default: out/psd/<source name>/<column>.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// Morlet wavelet power.
#[derive(Args, Debug)]
pub struct CwtArgs {
    #[command(flatten)]
    pub input: InputArgs,
    /// Lowest frequency, Hz.
    #[arg(long = "fmin-hz", alias = "fmin")]
    pub fmin_hz: f64,
    /// Highest frequency, Hz (at most Nyquist).
    #[arg(long = "fmax-hz", alias = "fmax")]
    pub fmax_hz: f64,
    /// Scales per octave.
    #[arg(long, default_value_t = DEFAULT_VOICES_PER_OCTAVE)]
    pub voices: usize,
    /// Write every n-th time sample (the transform uses all samples).
    #[arg(long, default_value_t = 1)]
    pub time_stride: usize,
    /// Output folder (cwt_power.csv, cwt_coi.csv, cwt.json). Default: out/cwt/<source
    /// name>/<column>.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// Audio export.
#[derive(Args, Debug)]
pub struct WavArgs {
    #[command(flatten)]
    pub input: InputArgs,
    /// Audio sample rate, Hz.
    #[arg(long = "sample-rate-hz", alias = "rate", default_value_t = DEFAULT_SAMPLE_RATE_HZ)]
    pub sample_rate_hz: u32,
    /// Output folder: the file is <column>.wav. Default: out/wav/<source name>.
    #[arg(long)]
    pub out: Option<PathBuf>,
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
    let nperseg = args
        .nperseg
        .unwrap_or(series.values.len().min(DEFAULT_NPERSEG));
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
    if !(args.fmin_hz >= 0.0 && args.fmin_hz < nyquist_hz) {
        return Err(cli(
            "--fmin-hz",
            format!(
                "must be in [0, {nyquist_hz}) Hz (the Nyquist frequency of the {} Hz sampled \
                 column), got {}",
                series.sample_rate_hz, args.fmin_hz
            ),
        ));
    }
    if let Some(fmax) = args.fmax_hz {
        if !(fmax > args.fmin_hz && fmax <= nyquist_hz) {
            return Err(cli(
                "--fmax-hz",
                format!(
                    "must be in ({}, {nyquist_hz}] Hz (above --fmin-hz, at most the Nyquist \
                     frequency), got {fmax}",
                    args.fmin_hz
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
        min_frequency_hz: args.fmin_hz,
        max_frequency_hz: args.fmax_hz.unwrap_or(f64::INFINITY),
        min_separation_hz: args.min_separation_hz,
        max_peaks: args.peaks,
        ranking,
    };
    let peaks = psd.find_peaks(&search)?;

    let out = out_dir(
        args.out.clone(),
        "psd",
        &format!("{}/{}", args.input.name(), args.input.column),
    );
    // Written beside the output folder and moved into it when complete.
    let stage = StagedDir::new(&out)?;
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
            "source": args.input.csv_path().display().to_string(),
            "column": args.input.column,
            "unit": unit,
            "sample_rate_hz": series.sample_rate_hz,
            "welch": psd.params,
            "frequency_resolution_hz": psd.frequency_resolution_hz,
            "segment_count": psd.segment_count,
            "peak_search": { "min_frequency_hz": search.min_frequency_hz,
                             "max_frequency_hz": args.fmax_hz,
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
        out.display()
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
    let scales = Scales::from_frequency_band(args.fmin_hz, args.fmax_hz, args.voices)
        .map_err(|e| args.input.in_context(e))?;
    let cwt = morlet_cwt(&series.values, series.sample_rate_hz, &scales)
        .map_err(|e| args.input.in_context(e))?;

    let out = out_dir(
        args.out.clone(),
        "cwt",
        &format!("{}/{}", args.input.name(), args.input.column),
    );
    // Written beside the output folder and moved into it when complete.
    let stage = StagedDir::new(&out)?;
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
            "source": args.input.csv_path().display().to_string(),
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
        args.fmin_hz,
        args.fmax_hz,
        out.display()
    );
    stage.commit(Commit::Merge)?;
    Ok(())
}

/// `squeal wav`.
pub fn run_wav(args: WavArgs) -> Result<()> {
    let series = args.input.read()?;
    // Checked before the output folder is made: a refused rate leaves nothing behind.
    let (lo, hi) = SAMPLE_RATE_RANGE_HZ;
    if !(lo..=hi).contains(&args.sample_rate_hz) {
        return Err(Error::input(
            "command line",
            "--sample-rate-hz",
            format!(
                "must be in [{lo}, {hi}] Hz, e.g. {DEFAULT_SAMPLE_RATE_HZ}, got {}",
                args.sample_rate_hz
            ),
        ));
    }
    // The previous release took the WAV file itself in --out: still accepted, with the note.
    let file = match &args.out {
        Some(out) if out.extension().is_some_and(|e| e == "wav") => {
            note("--out FILE.wav", "--out DIR (the file is DIR/<column>.wav)");
            out.clone()
        }
        _ => out_dir(args.out.clone(), "wav", &args.input.name())
            .join(format!("{}.wav", args.input.column)),
    };
    if let Some(dir) = file.parent().filter(|d| !d.as_os_str().is_empty()) {
        squeal::output::check_folder_target(dir)?;
        std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    }
    let count = write_file_staged(&file, |p| {
        write_wav(
            p,
            &series.values,
            series.sample_rate_hz,
            args.sample_rate_hz,
        )
    })
    .map_err(|e| args.input.in_context(e))?;
    println!(
        "wav: {count} samples at {} Hz -> {}",
        args.sample_rate_hz,
        file.display()
    );
    Ok(())
}
