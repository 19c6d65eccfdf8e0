//! The one-command pipeline: wheel modes, a rolling case,
//! its analysis and the report, into one folder.
//!
//! Layout of `out_dir`: `index.html` / `index.md` (the report over the run), `runs/<case>/`
//! (the run directory: histories, contact forces, patches, energy, `modes.json`).

use std::path::PathBuf;

use serde::Serialize;

use crate::report::run_report::build_report;
use crate::rolling::{simulate, LoadedCase, SimulateOptions};
use crate::{Error, Result};

/// Options of [`run_pipeline`].
#[derive(Clone, Debug)]
pub struct PipelineOptions {
    /// Report folder.
    pub out_dir: PathBuf,
    /// Override of the case's end time (s).
    pub end_time_s: Option<f64>,
    /// Progress bars.
    pub progress: bool,
}

/// What the pipeline produced.
#[derive(Clone, Debug, Serialize)]
pub struct PipelineSummary {
    /// The report's HTML page.
    pub report_html: PathBuf,
    /// The run directory.
    pub run_dir: PathBuf,
    /// Report sections.
    pub sections: Vec<String>,
    /// Wall time of each stage (s): modes, simulation, report.
    pub stage_wall_s: Vec<(String, f64)>,
}

/// Runs the case (replacing an earlier run of it in the report folder; the run writes its
/// wheel modes, [`crate::rolling::wheel_modes`]) and the report.
pub fn run_pipeline(case: &LoadedCase, opts: &PipelineOptions) -> Result<PipelineSummary> {
    let run_dir = opts.out_dir.join("runs").join(&case.case.name);
    let mut stages = Vec::new();
    let t = std::time::Instant::now();
    // The pipeline owns its report folder: a new default run replaces the old run whole, so
    // no file of it is left beside the new one.
    let record = simulate(
        case,
        &SimulateOptions {
            overwrite: true,
            progress: opts.progress,
            end_time_s: opts.end_time_s,
            ..SimulateOptions::new(run_dir.clone())
        },
    )?;
    stages.push((
        "wheel modes and rolling simulation".to_string(),
        t.elapsed().as_secs_f64(),
    ));
    if record.run.status != "completed" {
        return Err(Error::Numerical(format!(
            "the default case stopped: {} (output kept in {})",
            record.run.diagnosis.unwrap_or_default(),
            run_dir.display()
        )));
    }
    let t = std::time::Instant::now();
    let summary = build_report(
        std::slice::from_ref(&run_dir),
        &opts.out_dir,
        &format!("squeal default run: {}", case.case.name),
        &Default::default(),
    )?;
    stages.push(("analysis and report".to_string(), t.elapsed().as_secs_f64()));
    Ok(PipelineSummary {
        report_html: opts.out_dir.join("index.html"),
        run_dir,
        sections: summary.sections,
        stage_wall_s: stages,
    })
}
