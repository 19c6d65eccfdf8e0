//! `squeal identify` and `squeal check-modes`: dominant peaks of a run's vibration and the
//! wheel modes that explain them.

use std::path::PathBuf;

use clap::Args;
use squeal::analysis::identify::{
    missing_required, parse_required, to_csv, to_markdown, Tolerance,
};
use squeal::analysis::per_n::{
    analyse_ring, check_required, map_csv, peaks_csv, peaks_markdown, PerNAnalysis, PerNOptions,
    RingDirection, PER_N_MARGIN_DB,
};
use squeal::analysis::{analyse_run, AnalysisOptions};
use squeal::output::{Commit, StagedDir};

use super::grammar::{input_name, note, out_dir};
use squeal::{Error, Result};

/// The direction of a run's wheel signal.
#[derive(Clone, Copy, Debug, clap::ValueEnum)]
pub enum DirectionArg {
    /// Lateral (along the wheel axis): histories.csv and the ring.
    Lateral,
    /// Vertical (z): histories.csv.
    Vertical,
    /// Longitudinal (along the track): histories.csv.
    Longitudinal,
    /// Radial, in the wheel's turning frame: the ring (--per-n).
    Radial,
    /// Circumferential, in the wheel's turning frame: the ring (--per-n).
    Circumferential,
}

impl DirectionArg {
    fn word(self) -> &'static str {
        match self {
            DirectionArg::Lateral => "lateral",
            DirectionArg::Vertical => "vertical",
            DirectionArg::Longitudinal => "longitudinal",
            DirectionArg::Radial => "radial",
            DirectionArg::Circumferential => "circumferential",
        }
    }

    /// The ring's direction, for --per-n.
    fn ring(self) -> Result<RingDirection> {
        match self {
            DirectionArg::Lateral => Ok(RingDirection::Lateral),
            DirectionArg::Radial => Ok(RingDirection::Radial),
            DirectionArg::Circumferential => Ok(RingDirection::Circumferential),
            DirectionArg::Vertical | DirectionArg::Longitudinal => Err(Error::input(
                "command line",
                "--direction",
                format!(
                    "`{}` is a direction of histories.csv; allowed with --per-n (the rim ring): \
                     lateral, radial, circumferential",
                    self.word()
                ),
            )),
        }
    }
}

/// Options shared by both commands.
#[derive(Args, Debug)]
pub struct CommonArgs {
    /// Run directory with histories.csv and modes.json.
    pub run_dir: PathBuf,
    /// Direction of the wheel signal: the one column of histories.csv whose name starts with
    /// it. Default: lateral.
    #[arg(long, value_enum, conflicts_with = "column")]
    pub direction: Option<DirectionArg>,
    /// An exact column of histories.csv, instead of a direction.
    #[arg(long)]
    pub column: Option<String>,
    /// Deprecated: --direction or --column.
    #[arg(long, hide = true, conflicts_with_all = ["direction", "column"])]
    pub signal: Option<String>,
    /// Number of dominant peaks.
    #[arg(long, default_value_t = AnalysisOptions::default().peaks)]
    pub peaks: usize,
    /// Lowest peak frequency (Hz).
    #[arg(long = "fmin-hz", alias = "fmin", default_value_t = AnalysisOptions::default().band_hz.0)]
    pub fmin_hz: f64,
    /// Highest peak frequency (Hz); must not exceed the Nyquist frequency of the history.
    /// Default: the library's upper band edge or the Nyquist frequency, whichever is lower.
    #[arg(long = "fmax-hz", alias = "fmax")]
    pub fmax_hz: Option<f64>,
    /// Welch segment length (default: chosen for --resolution-hz: one zero-padded segment of
    /// a short window, averaged segments of a long one).
    #[arg(long)]
    pub nperseg: Option<usize>,
    /// Largest PSD bin spacing (Hz); short windows are zero-padded to reach it.
    #[arg(long, default_value_t = AnalysisOptions::default().resolution_hz, allow_negative_numbers = true)]
    pub resolution_hz: f64,
    /// Start of the analysed window (ms). Default: the lateral-motion onset of a rolling run
    /// (from run.json), else the first sample.
    #[arg(long, allow_negative_numbers = true)]
    pub from_ms: Option<f64>,
    /// End of the analysed window (ms). Default: the last sample.
    #[arg(long, allow_negative_numbers = true)]
    pub to_ms: Option<f64>,
    /// Relative matching tolerance.
    #[arg(long, default_value_t = Tolerance::default().relative)]
    pub tolerance: f64,
    /// Absolute matching tolerance floor (Hz).
    #[arg(long, default_value_t = Tolerance::default().absolute_hz)]
    pub tolerance_hz: f64,
    /// Modes file (default RUN_DIR/modes.json).
    #[arg(long)]
    pub modes: Option<PathBuf>,
    /// Per nodal diameter: analyse the run's rim ring (ring.csv) harmonic by harmonic, each
    /// harmonic's peaks named from the modes of its n only (docs/curving.md#per-n-analysis).
    #[arg(long, conflicts_with_all = ["column", "signal"])]
    pub per_n: bool,
}

impl CommonArgs {
    fn options(&self) -> Result<AnalysisOptions> {
        squeal::output::protect_inputs(std::iter::once(&self.run_dir).chain(&self.modes));
        if !(self.tolerance > 0.0 && self.tolerance < 1.0) {
            return Err(Error::input(
                "command line",
                "--tolerance",
                format!("must be in (0, 1), got {}", self.tolerance),
            ));
        }
        if self.tolerance_hz.is_nan() || self.tolerance_hz < 0.0 {
            return Err(Error::input(
                "command line",
                "--tolerance-hz",
                format!("must be >= 0, got {}", self.tolerance_hz),
            ));
        }
        if self.peaks == 0 {
            return Err(Error::input(
                "command line",
                "--peaks",
                "must be at least 1",
            ));
        }
        let signal = match (&self.direction, &self.column, &self.signal) {
            (Some(DirectionArg::Radial | DirectionArg::Circumferential), _, _) if !self.per_n => {
                return Err(Error::input(
                    "command line",
                    "--direction",
                    "radial and circumferential need --per-n (the rim ring's directions); without it: \
                     lateral, vertical, longitudinal",
                ))
            }
            (Some(d), _, _) => d.word().to_string(),
            (None, Some(c), _) => c.clone(),
            (None, None, Some(old)) => {
                let is_direction = ["lateral", "vertical", "longitudinal"].contains(&old.as_str());
                note(
                    "--signal",
                    if is_direction {
                        "--direction"
                    } else {
                        "--column"
                    },
                );
                old.clone()
            }
            (None, None, None) => AnalysisOptions::default().signal,
        };
        Ok(AnalysisOptions {
            signal,
            peaks: self.peaks,
            band_hz: (self.fmin_hz, self.fmax_hz.unwrap_or(f64::INFINITY)),
            nperseg: self.nperseg,
            resolution_hz: self.resolution_hz,
            from_s: self.from_ms.map(|t| t * 1e-3),
            to_s: self.to_ms.map(|t| t * 1e-3),
            tolerance: Tolerance {
                relative: self.tolerance,
                absolute_hz: self.tolerance_hz,
            },
            modes_file: self.modes.clone(),
            ..Default::default()
        })
    }
}

impl CommonArgs {
    /// The options of a per-n analysis (`--per-n`).
    fn per_n_options(&self) -> Result<PerNOptions> {
        // The shared checks (tolerances, peaks) and the inputs' protection.
        let spectrum = self.options()?;
        let direction = self.direction.unwrap_or(DirectionArg::Lateral).ring()?;
        Ok(PerNOptions {
            direction,
            spectrum,
        })
    }
}

/// `squeal identify --per-n`: the frequency x n map and each harmonic's named peaks.
fn run_identify_per_n(args: &IdentifyArgs) -> Result<()> {
    let options = args.common.per_n_options()?;
    let analysis = analyse_ring(&args.common.run_dir, &options)?;
    print_ring_window(&analysis);
    let md = peaks_markdown(&analysis);
    println!("{md}");
    let out = out_dir(
        args.out.clone(),
        "identify",
        &input_name(&args.common.run_dir),
    );
    let stage = StagedDir::new(&out)?;
    let dir = stage.path().to_path_buf();
    let write = |name: &str, text: String| -> Result<()> {
        let p = dir.join(name);
        std::fs::write(&p, text).map_err(|e| Error::io(&p, e))
    };
    let word = analysis.direction.word();
    write(&format!("per_n_map_{word}.csv"), map_csv(&analysis))?;
    write(&format!("per_n_peaks_{word}.csv"), peaks_csv(&analysis))?;
    write(&format!("per_n_peaks_{word}.md"), md)?;
    write(
        &format!("per_n_{word}.json"),
        serde_json::to_string_pretty(&analysis)
            .map_err(|e| Error::Numerical(format!("JSON encoding: {e}")))?,
    )?;
    stage.commit(Commit::Merge)?;
    println!(
        "wrote {}/per_n_map_{word}.csv, per_n_peaks_{word}.{{csv,md}}, per_n_{word}.json",
        out.display()
    );
    Ok(())
}

/// The ring's analysed window and spectrum, one line.
fn print_ring_window(a: &PerNAnalysis) {
    let w = &a.window;
    println!(
        "ring, {} harmonics n = 0..{} ({}): {:.2}-{:.2} ms (from {}); {}\n",
        a.direction.word(),
        a.spectra.len().saturating_sub(1),
        a.direction.word(),
        w.from_s * 1e3,
        w.to_s * 1e3,
        w.start_from,
        w.spectrum
    );
}

/// Arguments of `squeal identify`.
#[derive(Args, Debug)]
pub struct IdentifyArgs {
    #[command(flatten)]
    pub common: CommonArgs,
    /// Write identification.md, .csv and .json here (default: out/identify/<run name>).
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// Run `squeal identify`.
pub fn run_identify(args: IdentifyArgs) -> Result<()> {
    if args.common.per_n {
        return run_identify_per_n(&args);
    }
    let options = args.common.options()?;
    let analysis = analyse_run(&args.common.run_dir, &options)?;
    print_window(&analysis);
    let md = to_markdown(
        &analysis.identifications,
        analysis.direction,
        options.tolerance,
    );
    println!("{md}");
    let out = out_dir(args.out, "identify", &input_name(&args.common.run_dir));
    // Written beside the output folder and moved into it when complete.
    let stage = StagedDir::new(&out)?;
    let dir = stage.path().to_path_buf();
    let write = |name: &str, text: String| -> Result<()> {
        let p = dir.join(name);
        std::fs::write(&p, text).map_err(|e| Error::io(&p, e))
    };
    write("identification.md", md)?;
    write("identification.csv", to_csv(&analysis.identifications))?;
    write(
        "identification.json",
        serde_json::to_string_pretty(&analysis.identifications)
            .map_err(|e| Error::Numerical(format!("JSON encoding: {e}")))?,
    )?;
    stage.commit(Commit::Merge)?;
    println!("wrote {}/identification.{{md,csv,json}}", out.display());
    Ok(())
}

/// Arguments of `squeal check-modes`.
#[derive(Args, Debug)]
pub struct CheckModesArgs {
    #[command(flatten)]
    pub common: CommonArgs,
    /// Required mode as "nodal circles,nodal diameters" (repeatable), e.g. --require 0,3.
    #[arg(long, required = true, allow_hyphen_values = true)]
    pub require: Vec<String>,
    /// With --per-n: how far (dB) a required mode's peak must stand above the median of its
    /// harmonic's PSD (default fixed before any run was judged, docs/curving.md#per-n-analysis).
    #[arg(long, default_value_t = PER_N_MARGIN_DB, requires = "per_n")]
    pub margin_db: f64,
}

/// Run `squeal check-modes`: exit 0 only if every required mode explains a dominant peak.
pub fn run_check_modes(args: CheckModesArgs) -> Result<bool> {
    let required: Vec<(u32, u32)> = args
        .require
        .iter()
        .map(|r| parse_required(r))
        .collect::<Result<_>>()?;
    if args.common.per_n {
        return check_modes_per_n(&args, &required);
    }
    let options = args.common.options()?;
    let analysis = analyse_run(&args.common.run_dir, &options)?;
    print_window(&analysis);
    println!(
        "{}",
        to_markdown(
            &analysis.identifications,
            analysis.direction,
            options.tolerance
        )
    );
    let missing = missing_required(
        &analysis.identifications,
        &required,
        &analysis.modes,
        analysis.direction,
    );
    if missing.is_empty() {
        println!(
            "check-modes: all {} required modes identified in `{}`",
            required.len(),
            analysis.column
        );
        Ok(true)
    } else {
        for m in &missing {
            eprintln!("check-modes: missing {m}");
        }
        Ok(false)
    }
}

/// `squeal check-modes --per-n`: each required (m, n) against its own harmonic.
fn check_modes_per_n(args: &CheckModesArgs, required: &[(u32, u32)]) -> Result<bool> {
    if !(args.margin_db.is_finite() && args.margin_db >= 0.0) {
        return Err(Error::input(
            "command line",
            "--margin-db",
            format!("must be a finite number >= 0, got {}", args.margin_db),
        ));
    }
    let options = args.common.per_n_options()?;
    let analysis = analyse_ring(&args.common.run_dir, &options)?;
    print_ring_window(&analysis);
    let outcomes = check_required(&analysis, required, args.margin_db);
    for o in &outcomes {
        let verdict = if o.passed { "pass" } else { "FAIL" };
        println!("check-modes --per-n: {verdict} {}", o.reason);
    }
    Ok(outcomes.iter().all(|o| o.passed))
}

/// The analysed window and spectrum, one line.
fn print_window(analysis: &squeal::analysis::RunAnalysis) {
    let w = &analysis.window;
    println!(
        "{}: {:.2}-{:.2} ms (from {}); {}\n",
        analysis.column,
        w.from_s * 1e3,
        w.to_s * 1e3,
        w.start_from,
        w.spectrum
    );
}
