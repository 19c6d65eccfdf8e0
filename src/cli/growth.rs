//! `squeal growth RUN_DIR`: wavelet-ridge amplitude and growth rate of wheel vibration in the
//! bands of chosen wheel modes.

use std::path::PathBuf;

use clap::Args;
use squeal::analysis::growth::{
    band_growth, bands_for_modes, read_column, ridges_csv, to_markdown, GrowthOptions,
};
use squeal::analysis::identify::{parse_mode_label, ModeRef};
use squeal::output::{Commit, StagedDir};

use super::grammar::{input_name, out_dir};
use squeal::{Error, Result};

/// Arguments of `squeal growth`.
#[derive(Args, Debug)]
pub struct GrowthArgs {
    /// Run directory with histories.csv and modes.json.
    pub run_dir: PathBuf,
    /// Column of histories.csv.
    #[arg(long, alias = "signal", default_value_t = GrowthOptions::default().column)]
    pub column: String,
    /// Axial mode whose band to follow, "nodal circles,nodal diameters" (repeatable).
    #[arg(long = "mode", default_values_t = default_mode_labels(), allow_hyphen_values = true)]
    pub modes: Vec<String>,
    /// Half width of each band, relative to the mode's frequency.
    #[arg(long, default_value_t = GrowthOptions::default().half_width)]
    pub half_width: f64,
    /// Start (ms); default: the lateral-motion onset from run.json, else the first sample.
    #[arg(long, allow_negative_numbers = true)]
    pub from_ms: Option<f64>,
    /// Window over which each growth rate is fitted (ms).
    #[arg(long, default_value_t = GrowthOptions::default().window_s * 1e3, allow_negative_numbers = true)]
    pub window_ms: f64,
    /// Write growth.md, growth.json and ridges.csv here (default: out/growth/<run name>).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// The rim ring's harmonics instead of a histories column: each nodal-diameter harmonic's
    /// envelope, growth rate and limit cycle, and whether the wheel squeals, by the criteria
    /// fixed before the curve runs (docs/curving.md#criteria-fixed-before-the-runs). Writes
    /// ring_growth.{md,json}, ring_envelopes.csv and ring_mode_envelopes.csv.
    #[arg(long, conflicts_with_all = ["column", "modes", "half_width", "from_ms", "window_ms"])]
    pub per_n: bool,
    /// With --per-n: modes file that names the harmonics' peaks (default RUN_DIR/modes.json).
    #[arg(long = "modes", requires = "per_n")]
    pub modes_file: Option<PathBuf>,
    /// With --per-n: judge the record up to this time (ms) only, e.g. a long run's first part
    /// against a shorter run (default: the whole record).
    #[arg(long, requires = "per_n", allow_negative_numbers = true)]
    pub to_ms: Option<f64>,
}

/// The library's default modes as command-line labels ("0,3").
fn default_mode_labels() -> Vec<String> {
    GrowthOptions::default()
        .modes
        .iter()
        .map(|(m, n)| format!("{m},{n}"))
        .collect()
}

/// Run `squeal growth`.
pub fn run(args: GrowthArgs) -> Result<()> {
    squeal::output::protect_inputs([&args.run_dir]);
    if args.per_n {
        return run_per_n(&args);
    }
    if !(args.half_width > 0.0 && args.half_width < 0.5) {
        return Err(Error::input(
            "command line",
            "--half-width",
            format!("must lie in (0, 0.5) (got {})", args.half_width),
        ));
    }
    if !(args.window_ms > 0.0 && args.window_ms <= 1000.0) {
        return Err(Error::input(
            "command line",
            "--window-ms",
            format!("must lie in (0, 1000] ms (got {})", args.window_ms),
        ));
    }
    let labels: Vec<(u32, u32)> = args
        .modes
        .iter()
        .map(|m| parse_mode_label(m, "--mode"))
        .collect::<Result<_>>()?;
    let modes_path = args.run_dir.join("modes.json");
    if !modes_path.exists() {
        return Err(Error::input(
            modes_path.display().to_string(),
            "modes",
            "no modal results: run `squeal axisym ... --out RUN_DIR` first",
        ));
    }
    let modes: Vec<ModeRef> = squeal::modal::mode::read_modes_json(&modes_path)?;
    let bands = bands_for_modes(&modes, &labels, args.half_width)?;
    let series = read_column(&args.run_dir, &args.column)?;
    let onset_s = squeal::analysis::lateral_onset_s(&args.run_dir)?;
    let from_s = match args.from_ms {
        Some(t) => t * 1e-3,
        None => onset_s.unwrap_or(series.start_time_s),
    };
    let g = band_growth(&series, &bands, from_s, args.window_ms * 1e-3).map_err(|e| match e {
        // Without --from-ms the start was the default's: say so rather than blame an option
        // the user did not give (issue 53, item 13).
        Error::Input {
            source_name,
            field,
            message,
        } if field == "--from-ms" && args.from_ms.is_none() => Error::input(
            source_name,
            "--from-ms (not given)",
            format!(
                "the analysis started by default at {} ({:.3} ms): {message}; give an earlier \
                 --from-ms",
                if onset_s.is_some() {
                    "the lateral-motion onset in run.json"
                } else {
                    "the record's first sample"
                },
                from_s * 1e3
            ),
        ),
        other => other,
    })?;
    let md = to_markdown(&g);
    println!("{md}");
    let out = out_dir(args.out, "growth", &input_name(&args.run_dir));
    let json = serde_json::to_string_pretty(&g).map_err(|e| Error::Numerical(e.to_string()))?;
    write_outputs(
        &out,
        &[
            ("growth.md", md),
            ("growth.json", json),
            ("ridges.csv", ridges_csv(&g)),
        ],
    )
}

/// Writes `files` (name, text) into the folder `out`: beside it first, moved into it when all
/// are written; says what it wrote.
fn write_outputs(out: &std::path::Path, files: &[(&str, String)]) -> Result<()> {
    let stage = StagedDir::new(out)?;
    for (name, text) in files {
        let p = stage.path().join(name);
        std::fs::write(&p, text).map_err(|e| Error::io(&p, e))?;
    }
    let names: Vec<&str> = files.iter().map(|f| f.0).collect();
    println!("wrote {} into {}", names.join(", "), out.display());
    stage.commit(Commit::Merge)?;
    Ok(())
}

/// `squeal growth --per-n`: the ring's harmonics judged by the fixed criteria.
fn run_per_n(args: &GrowthArgs) -> Result<()> {
    use squeal::analysis::ring_growth::{
        envelopes_csv, mode_envelopes_csv, ring_growth, to_markdown, GrowthCriteria,
    };
    let g = ring_growth(
        &args.run_dir,
        args.modes_file.as_deref(),
        &GrowthCriteria::default(),
        args.to_ms.map(|t| t * 1e-3),
    )?;
    let md = to_markdown(&g);
    println!("{md}");
    let out = out_dir(args.out.clone(), "growth", &input_name(&args.run_dir));
    let json = serde_json::to_string_pretty(&g).map_err(|e| Error::Numerical(e.to_string()))?;
    write_outputs(
        &out,
        &[
            ("ring_growth.md", md),
            ("ring_growth.json", json),
            ("ring_envelopes.csv", envelopes_csv(&g)),
            ("ring_mode_envelopes.csv", mode_envelopes_csv(&g)),
        ],
    )
}
