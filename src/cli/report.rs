//! `squeal report RUN_DIR...`: the report over run directories.

use std::path::{Path, PathBuf};

use clap::Args;
use squeal::output::{Commit, StagedDir};
use squeal::report::run_report::{build_report, ReportOptions};
use squeal::Result;

use super::grammar::{input_name, note, REPORTS_ROOT};

/// Arguments of `squeal report`.
#[derive(Args, Debug)]
pub struct ReportArgs {
    /// Run directories (each with histories.csv; optional modes.json, contact_forces.csv,
    /// run.json).
    #[arg(required = true)]
    pub run_dirs: Vec<PathBuf>,
    /// Folder of the report (index.html, index.md, charts); replaced whole. Default:
    /// reports/<run name> (several runs: their names joined by `+`).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Deprecated: --out REPORTS/NAME.
    #[arg(long, hide = true, conflicts_with = "out")]
    pub name: Option<String>,
    /// Deprecated: --out REPORTS/NAME.
    #[arg(long, hide = true, conflicts_with = "out")]
    pub reports: Option<PathBuf>,
    /// Start of the analysed window (ms). Default: each run's lateral-motion onset (run.json),
    /// else its first sample.
    #[arg(long, allow_negative_numbers = true)]
    pub from_ms: Option<f64>,
    /// End of the analysed window (ms). Default: the last sample.
    #[arg(long, allow_negative_numbers = true)]
    pub to_ms: Option<f64>,
    /// Largest PSD bin spacing (Hz); short windows are zero-padded to reach it.
    #[arg(long, allow_negative_numbers = true)]
    pub resolution_hz: Option<f64>,
    /// A stability.json of `squeal stability` for the runs without one of their own: the
    /// report lists its predicted unstable modes beside the PSD peaks.
    #[arg(long)]
    pub stability: Option<PathBuf>,
    /// PSD charts up to the Nyquist frequency instead of the squeal band (0-5 kHz).
    #[arg(long)]
    pub full_range: bool,
}

/// Run `squeal report`.
pub fn run(args: ReportArgs) -> Result<()> {
    squeal::output::protect_inputs(args.run_dirs.iter().chain(&args.stability));
    let out = match (args.out, &args.name, &args.reports) {
        (Some(out), _, _) => out,
        (None, None, None) => {
            let names: Vec<String> = args.run_dirs.iter().map(|d| input_name(d)).collect();
            Path::new(REPORTS_ROOT).join(names.join("+"))
        }
        (None, name, reports) => {
            note("--name/--reports", "--out REPORTS/NAME");
            let name = name.clone().unwrap_or_else(|| "report".into());
            squeal::output::check_plain_name("--name", &name)?;
            reports
                .clone()
                .unwrap_or_else(|| PathBuf::from(REPORTS_ROOT))
                .join(name)
        }
    };
    let title = input_name(&out);
    // Written beside the final folder and moved into place only when complete.
    let stage = StagedDir::new(&out)?;
    let options = ReportOptions {
        from_s: args.from_ms.map(|t| t * 1e-3),
        to_s: args.to_ms.map(|t| t * 1e-3),
        resolution_hz: args.resolution_hz,
        stability: args.stability,
        full_frequency_range: args.full_range,
    };
    let summary = build_report(
        &args.run_dirs,
        stage.path(),
        &format!("squeal report: {title}"),
        &options,
    )?;
    stage.commit(Commit::Replace)?;
    println!(
        "report with {} files and sections: {}",
        summary.files.len(),
        summary.sections.join("; ")
    );
    println!("report: {}", out.join("index.html").display());
    Ok(())
}
