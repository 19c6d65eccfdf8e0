//! `squeal report RUN_DIR...`: the report over run directories.

use std::path::PathBuf;

use clap::Args;
use squeal::report::run_report::build_report;
use squeal::Result;

/// Arguments of `squeal report`.
#[derive(Args, Debug)]
pub struct ReportArgs {
    /// Run directories (each with histories.csv; optional modes.json, contact_forces.csv,
    /// run.json).
    #[arg(required = true)]
    pub run_dirs: Vec<PathBuf>,
    /// Report name: written to <reports>/<name>/.
    #[arg(long, default_value = "report")]
    pub name: String,
    /// Root folder of reports.
    #[arg(long, default_value = "reports")]
    pub reports: PathBuf,
}

/// Run `squeal report`.
pub fn run(args: ReportArgs) -> Result<()> {
    let out = args.reports.join(&args.name);
    let summary = build_report(
        &args.run_dirs,
        &out,
        &format!("squeal report: {}", args.name),
    )?;
    println!(
        "report with {} files and sections: {}",
        summary.files.len(),
        summary.sections.join("; ")
    );
    println!("report: {}", out.join("index.html").display());
    Ok(())
}
