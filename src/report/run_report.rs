//! `squeal report RUN_DIR...`: one report (markdown + HTML, charts as PNG and SVG, WAV files)
//! over one or more run directories, laid out like the paper's figures:
//! - wheel vibration time histories and PSDs of all runs on one figure each (paper fig. 9);
//! - wavelet power spectra of lateral, vertical and longitudinal vibration for up to two runs
//!   side by side (paper fig. 10);
//! - contact force histories per run (when `contact_forces.csv` is present);
//! - modal chart (frequency against nodal diameters per family) when `modes.json` is present;
//! - mode-to-peak tables; the predicted unstable modes beside the PSD peaks when the run has a
//!   `stability.json` (or one is given); run metadata from `run.json`; a WAV of the lateral vibration.
//!
//! - with a rim ring (`ring.csv`): first the squeal verdict by the criteria of docs/curving.md,
//!   then the frequency x n map, the harmonics' envelopes, the growth and limit-cycle table and
//!   the stability analysis beside the ring ([`super::ring_sections`]).
//!
//! Files read from each run directory (see [`crate::analysis`]): `histories.csv` (required),
//! `modes.json`, `contact_forces.csv`, `run.json`, `stability.json`, `ring.csv` (optional).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use serde::Serialize;

pub use super::html::markdown_to_html;
pub use super::page::ReportOptions;
use super::page::{Page, Run};
use super::{ring_sections, sections};
use crate::analysis::identify::ModeRef;
use crate::analysis::per_n::{analyse_ring, PerNAnalysis, PerNOptions, RingDirection};
use crate::analysis::ring_growth::{ring_growth, GrowthCriteria, RingGrowth};
use crate::analysis::{analyse_run, AnalysisOptions};
use crate::stability::output::read_brief;
use crate::table::Table;
use crate::{Error, Result};

/// What a report contains (also written as report.json).
#[derive(Clone, Debug, Serialize)]
pub struct ReportSummary {
    /// Output directory.
    pub directory: PathBuf,
    /// Runs included.
    pub runs: Vec<String>,
    /// Files written.
    pub files: Vec<String>,
    /// Section headings of index.md.
    pub sections: Vec<String>,
}

/// One name per run, unique within the report, that its sections and chart files go by: the
/// folder's name; where two runs share it (`a/run`, `b/run`), with as many of its parent
/// folders as tell them apart (`a-run`, `b-run`); the same folder given twice gets a count
/// (`run`, `run-2`). Without this the second run's charts would replace the first's.
fn unique_run_names(dirs: &[PathBuf]) -> Vec<String> {
    // The folders' components from the last, of the absolute path where it resolves (so that
    // `.` and `..` name the folder they mean).
    let parts: Vec<Vec<String>> = dirs
        .iter()
        .map(|d| {
            let resolved = d.canonicalize().unwrap_or_else(|_| d.clone());
            let mut names: Vec<String> = resolved
                .components()
                .filter_map(|c| match c {
                    std::path::Component::Normal(s) => Some(s.to_string_lossy().to_string()),
                    _ => None,
                })
                .collect();
            names.reverse();
            if names.is_empty() {
                names.push("run".into());
            }
            names
        })
        .collect();
    let suffix = |p: &[String], depth: usize| -> String {
        let mut kept: Vec<&str> = p.iter().take(depth).map(String::as_str).collect();
        kept.reverse();
        kept.join("-")
    };
    let mut names: Vec<String> = Vec::with_capacity(dirs.len());
    for (i, p) in parts.iter().enumerate() {
        let depth = (1..=p.len())
            .find(|&d| {
                let mine = suffix(p, d);
                parts
                    .iter()
                    .enumerate()
                    .all(|(j, q)| j == i || suffix(q, d) != mine)
            })
            .unwrap_or(1);
        let base = suffix(p, depth);
        let mut name = base.clone();
        let mut count = 2;
        while names.contains(&name) {
            name = format!("{base}-{count}");
            count += 1;
        }
        names.push(name);
    }
    names
}

/// Build the report for `run_dirs` into `out_dir`.
pub fn build_report(
    run_dirs: &[PathBuf],
    out_dir: &Path,
    title: &str,
    report_options: &ReportOptions,
) -> Result<ReportSummary> {
    if run_dirs.is_empty() {
        return Err(Error::input(
            "command line",
            "RUN_DIR",
            "give at least one run directory",
        ));
    }
    std::fs::create_dir_all(out_dir).map_err(|e| Error::io(out_dir, e))?;
    let mut runs = Vec::new();
    for (dir, name) in run_dirs.iter().zip(unique_run_names(run_dirs)) {
        let hist_path = dir.join("histories.csv");
        if !hist_path.exists() {
            return Err(Error::input(
                dir.display().to_string(),
                "histories.csv",
                "the run directory has no histories.csv",
            ));
        }
        let histories = Table::read(&hist_path)?;
        let modes_path = dir.join("modes.json");
        let modes: Option<Vec<ModeRef>> = if modes_path.exists() {
            Some(crate::modal::mode::read_modes_json(&modes_path)?)
        } else {
            None
        };
        let mut analyses = Vec::new();
        if modes.is_some() {
            for d in ["lateral", "vertical", "longitudinal"] {
                if let Some((col, _)) = histories.column_starting(&format!("{d}_")) {
                    let t = histories.column("time_s").unwrap_or(&[]);
                    let fs = if t.len() > 1 {
                        (t.len() - 1) as f64 / (t[t.len() - 1] - t[0])
                    } else {
                        1.0
                    };
                    let options = AnalysisOptions {
                        signal: col.to_string(),
                        peaks: 3,
                        band_hz: (50.0_f64.min(0.1 * fs), (0.45 * fs).min(10_000.0)),
                        from_s: report_options.from_s,
                        to_s: report_options.to_s,
                        resolution_hz: report_options
                            .resolution_hz
                            .unwrap_or(crate::analysis::DEFAULT_RESOLUTION_HZ),
                        ..Default::default()
                    };
                    analyses.push(analyse_run(dir, &options)?);
                }
            }
        }
        let own = dir.join("stability.json");
        let stability = match (own.exists(), &report_options.stability) {
            (true, _) => Some(read_brief(&own)?),
            (false, Some(path)) => Some(read_brief(path)?),
            (false, None) => None,
        };
        let (ring, ring_map) = read_ring_analyses(dir, report_options);
        runs.push(Run {
            name,
            dir: dir.clone(),
            histories,
            analyses,
            modes,
            stability,
            ring,
            ring_map,
        });
    }

    let mut page = Page::new();
    let ctx = sections::Context {
        runs: &runs,
        out_dir,
        report_options,
    };
    let _ = writeln!(page.md, "# {title}\n\nRuns: {}. Axes: x along the track, y lateral (field side), z up. Mode labels: (nodal circles, nodal diameters).", runs.iter().map(|r| format!("`{}`", r.name)).collect::<Vec<_>>().join(", "));
    ring_sections::verdict(&mut page, &ctx)?;
    ring_sections::per_n(&mut page, &ctx)?;
    sections::summary(&mut page, &ctx)?;
    sections::vibration(&mut page, &ctx)?;
    sections::wavelets(&mut page, &ctx)?;
    sections::contact_forces(&mut page, &ctx)?;
    sections::operating_point(&mut page, &ctx)?;
    sections::patches(&mut page, &ctx)?;
    sections::modes_chart(&mut page, &ctx)?;
    sections::identification(&mut page, &ctx)?;
    sections::stability(&mut page, &ctx)?;
    sections::squeal(&mut page, &ctx)?;
    sections::listen(&mut page, &ctx)?;
    sections::metadata(&mut page, &ctx)?;
    let index_md = out_dir.join("index.md");
    std::fs::write(&index_md, &page.md).map_err(|e| Error::io(&index_md, e))?;
    let index_html = out_dir.join("index.html");
    std::fs::write(&index_html, markdown_to_html(title, &page.md))
        .map_err(|e| Error::io(&index_html, e))?;
    page.files
        .extend(["index.md".to_string(), "index.html".to_string()]);
    let summary = ReportSummary {
        directory: out_dir.to_path_buf(),
        runs: runs.iter().map(|r| r.name.clone()).collect(),
        files: page.files,
        sections: page.sections,
    };
    let json = out_dir.join("report.json");
    std::fs::write(
        &json,
        serde_json::to_string_pretty(&summary).unwrap_or_default(),
    )
    .map_err(|e| Error::io(&json, e))?;
    Ok(summary)
}

/// The growth analysis of a run's rim ring by the fixed criteria, and its lateral per-n map
/// over the report's window (default: from the end of the creep force's build-up); (None, None)
/// without a `ring.csv`.
fn read_ring_analyses(
    dir: &Path,
    report_options: &ReportOptions,
) -> (
    Option<std::result::Result<RingGrowth, String>>,
    Option<PerNAnalysis>,
) {
    if !dir.join(crate::rolling::ring::RING_CSV).exists() {
        return (None, None);
    }
    let growth = ring_growth(dir, None, &GrowthCriteria::default(), report_options.to_s)
        .map_err(|e| e.to_string());
    let from_s = report_options
        .from_s
        .or_else(|| growth.as_ref().ok().map(|g| g.windows.build_up_end_s));
    let options = PerNOptions {
        direction: RingDirection::Lateral,
        spectrum: AnalysisOptions {
            from_s,
            to_s: report_options.to_s,
            ..AnalysisOptions::default()
        },
    };
    let map = growth
        .is_ok()
        .then(|| analyse_ring(dir, &options).ok())
        .flatten();
    (Some(growth), map)
}

#[cfg(test)]
mod tests {
    use super::unique_run_names;
    use std::path::PathBuf;

    #[test]
    fn runs_that_share_a_folder_name_get_names_of_their_own() {
        let names =
            |dirs: &[&str]| unique_run_names(&dirs.iter().map(PathBuf::from).collect::<Vec<_>>());
        // Paths that do not exist keep their components as given.
        assert_eq!(names(&["/x/a/run", "/x/b/run"]), ["a-run", "b-run"]);
        assert_eq!(
            names(&["/x/a/run", "/y/a/run", "/z/c"]),
            ["x-a-run", "y-a-run", "c"]
        );
        assert_eq!(names(&["/x/run", "/x/run"]), ["run", "run-2"]);
        assert_eq!(names(&["/p/case3", "/p/case5"]), ["case3", "case5"]);
    }
}
