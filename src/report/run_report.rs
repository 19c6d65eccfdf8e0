//! `squeal report RUN_DIR...`: one report (markdown + HTML, charts as PNG and SVG, WAV files)
//! over one or more run directories, laid out like the paper's figures:
//! - wheel vibration time histories and PSDs of all runs on one figure each (paper fig. 9);
//! - wavelet power spectra of lateral, vertical and longitudinal vibration for up to two runs
//!   side by side (paper fig. 10);
//! - contact force histories per run (when `contact_forces.csv` is present);
//! - modal chart (frequency against nodal diameters per family) when `modes.json` is present;
//! - mode-to-peak tables; run metadata from `run.json`; a WAV of the lateral vibration.
//!
//! Files read from each run directory (see [`crate::analysis`]): `histories.csv` (required),
//! `modes.json`, `contact_forces.csv`, `run.json` (optional).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use serde::Serialize;

use super::chart::{write, write_heatmap, Heatmap, LineChart, Series, Stroke};
use crate::analysis::{analyse_run, AnalysisOptions, RunAnalysis};
use crate::identify::{to_markdown, ModeRef};
use crate::signal::{morlet_cwt, wav::write_wav, Scales};
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

struct Run {
    name: String,
    dir: PathBuf,
    histories: Table,
    analyses: Vec<RunAnalysis>,
    modes: Option<Vec<ModeRef>>,
}

fn run_name(dir: &Path) -> String {
    dir.file_name()
        .map(|s| s.to_string_lossy().to_string())
        .unwrap_or_else(|| "run".into())
}

/// Wavelet power of one signal as a heatmap (time in ms, frequency log axis, COI overlay).
fn wavelet_chart(
    title: &str,
    time_s: &[f64],
    signal: &[f64],
    sample_rate_hz: f64,
    fmax_hz: f64,
) -> Result<Heatmap> {
    let fmin = (4.0 * sample_rate_hz / signal.len() as f64).max(20.0);
    let fmax = fmax_hz.min(0.4 * sample_rate_hz).max(2.0 * fmin);
    let scales = Scales::from_frequency_band(fmin, fmax, 8)?;
    let wp = morlet_cwt(signal, sample_rate_hz, &scales)?;
    // Columns: at most 400 time bins (mean power per bin); rows ascending in frequency.
    let nt = wp.time_count;
    let bins = nt.clamp(1, 400);
    let nf = wp.frequency_count();
    let mut order: Vec<usize> = (0..nf).collect();
    order.sort_by(|&a, &b| wp.frequency_hz[a].total_cmp(&wp.frequency_hz[b]));
    let mut x = Vec::with_capacity(bins);
    let mut values = vec![0.0; bins * nf];
    for b in 0..bins {
        let (t0, t1) = (b * nt / bins, ((b + 1) * nt / bins).max(b * nt / bins + 1));
        x.push(1e3 * time_s[(t0 + t1) / 2]);
        for (row, &j) in order.iter().enumerate() {
            let mut acc = 0.0;
            for t in t0..t1 {
                acc += wp.power_at(t, j);
            }
            values[b * nf + row] = acc / (t1 - t0) as f64;
        }
    }
    let coi = wp.coi_frequency_hz();
    let coi_series = Series {
        label: "cone of influence".into(),
        x: time_s
            .iter()
            .step_by((nt / 400).max(1))
            .map(|t| 1e3 * t)
            .collect(),
        y: coi.iter().step_by((nt / 400).max(1)).copied().collect(),
        stroke: Stroke::Dotted,
        color: 6,
    };
    Ok(Heatmap {
        title: title.to_string(),
        x_label: "time (ms)".into(),
        y_label: "frequency (Hz)".into(),
        x,
        y: order.iter().map(|&j| wp.frequency_hz[j]).collect(),
        values,
        range_db: 40.0,
        log_y: true,
        overlay: vec![coi_series],
        size_px: Some((760, 520)),
    })
}

/// How the report analyses the vibration.
#[derive(Clone, Debug, Default)]
pub struct ReportOptions {
    /// Start of the analysed window (s); None: each run's lateral-motion onset, else its first
    /// sample (see [`crate::analysis`]).
    pub from_s: Option<f64>,
    /// End of the analysed window (s); None: the last sample.
    pub to_s: Option<f64>,
    /// Largest PSD bin spacing (Hz); None: [`crate::analysis::DEFAULT_RESOLUTION_HZ`].
    pub resolution_hz: Option<f64>,
}

/// Bands followed in the squeal section: the zero-nodal-circle axial modes the paper finds,
/// (0,0) on the rim mean (n = 0 motion), (0,3) and (0,4) on the rim point less the rim mean
/// (n >= 1 motion: the hub's lateral motion cannot drive it).
const SQUEAL_BANDS: [(u32, u32, &str); 3] = [
    (0, 0, "rim_mean_lateral_velocity_m_per_s"),
    (0, 3, "rim_point_minus_mean_lateral_velocity_m_per_s"),
    (0, 4, "rim_point_minus_mean_lateral_velocity_m_per_s"),
];

/// Window of the growth-rate fits in the squeal section (s).
const GROWTH_WINDOW_S: f64 = 0.004;

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
    for dir in run_dirs {
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
            Some(crate::input::read_json(&modes_path)?)
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
        runs.push(Run {
            name: run_name(dir),
            dir: dir.clone(),
            histories,
            analyses,
            modes,
        });
    }

    let mut md = String::new();
    let mut sections = Vec::new();
    let mut files = Vec::new();
    let mut heading = |md: &mut String, text: &str| {
        let _ = writeln!(md, "\n## {text}\n");
        sections.push(text.to_string());
    };
    let _ = writeln!(md, "# {title}\n\nRuns: {}. Axes: x along the track, y lateral (field side), z up. Mode labels: (nodal circles, nodal diameters).", runs.iter().map(|r| format!("`{}`", r.name)).collect::<Vec<_>>().join(", "));

    // ---- Vibration histories and PSDs of all runs (paper fig. 9).
    heading(
        &mut md,
        "Wheel vibration: time histories and PSDs (all runs)",
    );
    for d in ["lateral", "vertical", "longitudinal"] {
        let mut hist = Vec::new();
        let mut psds = Vec::new();
        let mut psd_note = String::new();
        let mut unit = String::new();
        for (k, r) in runs.iter().enumerate() {
            let Some((col, v)) = r.histories.column_starting(&format!("{d}_")) else {
                continue;
            };
            unit = col
                .rsplit_once("_m_per_s")
                .map(|_| "m/s".to_string())
                .unwrap_or_else(|| col.split('_').next_back().unwrap_or("").to_string());
            let t: Vec<f64> = r
                .histories
                .column("time_s")
                .unwrap_or(&[])
                .iter()
                .map(|t| 1e3 * t)
                .collect();
            let step = (t.len() / 4000).max(1);
            hist.push(Series::line(
                &r.name,
                t.iter().step_by(step).copied().collect(),
                v.iter().step_by(step).copied().collect(),
                k,
            ));
            if let Some(a) = r.analyses.iter().find(|a| a.column == col) {
                // The chart says what spectrum it shows (window, padding, bins): the first
                // run's; every run's is listed under the chart.
                if psd_note.is_empty() {
                    let p = &a.psd.params;
                    psd_note = format!(
                        "{:.1}-{:.1} ms, {}{:.1} Hz bins",
                        a.window.from_s * 1e3,
                        a.window.to_s * 1e3,
                        if p.fft_length() > p.nperseg {
                            "zero-padded, "
                        } else {
                            ""
                        },
                        a.psd.frequency_resolution_hz
                    );
                }
                psds.push(Series::line(
                    &r.name,
                    a.psd.frequency_hz.clone(),
                    a.psd.psd_per_hz.clone(),
                    k,
                ));
                let peaks: Vec<(f64, f64)> = a
                    .identifications
                    .iter()
                    .map(|i| (i.peak_frequency_hz, i.peak_psd))
                    .collect();
                psds.push(Series {
                    label: String::new(),
                    x: peaks.iter().map(|p| p.0).collect(),
                    y: peaks.iter().map(|p| p.1).collect(),
                    stroke: Stroke::Points,
                    color: k,
                });
            } else {
                let tt = r.histories.column("time_s").unwrap_or(&[]);
                if tt.len() > 64 {
                    let fs = (tt.len() - 1) as f64 / (tt[tt.len() - 1] - tt[0]);
                    let mut p = 64;
                    while p * 2 <= v.len() / 2 {
                        p *= 2;
                    }
                    let psd = crate::signal::welch(v, fs, &crate::signal::WelchParams::new(p))?;
                    psds.push(Series::line(&r.name, psd.frequency_hz, psd.psd_per_hz, k));
                }
            }
        }
        if hist.is_empty() {
            continue;
        }
        let stem = format!("vibration_{d}");
        write(
            &LineChart {
                title: format!("Wheel {d} vibration"),
                x_label: "time (ms)".into(),
                y_label: format!("{d} vibration ({unit})"),
                series: hist,
                ..Default::default()
            },
            Some(&out_dir.join(format!("{stem}.png"))),
            Some(&out_dir.join(format!("{stem}.svg"))),
        )?;
        write(
            &LineChart {
                title: if psd_note.is_empty() {
                    format!("PSD of the wheel {d} vibration")
                } else {
                    format!("{d} PSD, {psd_note}; dots: peaks")
                },
                x_label: "frequency (Hz)".into(),
                y_label: format!("PSD (({unit})^2/Hz)"),
                series: psds,
                log_y: true,
                ..Default::default()
            },
            Some(&out_dir.join(format!("{stem}_psd.png"))),
            Some(&out_dir.join(format!("{stem}_psd.svg"))),
        )?;
        let _ = writeln!(
            md,
            "![{d} history]({stem}.png)\n![{d} PSD]({stem}_psd.png)\n"
        );
        for r in &runs {
            if let Some(a) = r.analyses.iter().find(|a| a.column.starts_with(d)) {
                let _ = writeln!(
                    md,
                    "- PSD of {}: {:.2}-{:.2} ms (from {}); {}",
                    r.name,
                    a.window.from_s * 1e3,
                    a.window.to_s * 1e3,
                    a.window.start_from,
                    a.window.spectrum
                );
            }
        }
        let _ = writeln!(md);
        files.extend([format!("{stem}.png"), format!("{stem}_psd.png")]);
    }

    // ---- Wavelet power spectra for up to two runs (paper fig. 10).
    heading(&mut md, "Wavelet power spectra (Morlet)");
    for r in runs.iter().take(2) {
        let t = r.histories.column("time_s").unwrap_or(&[]);
        if t.len() < 64 {
            continue;
        }
        let fs = (t.len() - 1) as f64 / (t[t.len() - 1] - t[0]);
        let mut row = String::new();
        for d in ["lateral", "vertical", "longitudinal"] {
            let Some((col, v)) = r.histories.column_starting(&format!("{d}_")) else {
                continue;
            };
            let map = wavelet_chart(&format!("{}: {d} ({col})", r.name), t, v, fs, 10_000.0)?;
            let stem = format!("wps_{}_{d}", r.name);
            write_heatmap(
                &map,
                Some(&out_dir.join(format!("{stem}.png"))),
                Some(&out_dir.join(format!("{stem}.svg"))),
            )?;
            let _ = write!(row, "![{stem}]({stem}.png) ");
            files.push(format!("{stem}.png"));
        }
        let _ = writeln!(md, "{row}\n\nColour: wavelet power in dB below its maximum (40 dB shown); dashed: cone of influence.\n");
    }

    // ---- Contact forces.
    let with_forces: Vec<&Run> = runs
        .iter()
        .filter(|r| r.dir.join("contact_forces.csv").exists())
        .collect();
    if !with_forces.is_empty() {
        heading(&mut md, "Contact forces");
        for r in with_forces {
            let table = Table::read(&r.dir.join("contact_forces.csv"))?;
            let t: Vec<f64> = table
                .column("time_s")
                .unwrap_or(&[])
                .iter()
                .map(|v| 1e3 * v)
                .collect();
            let series: Vec<Series> = table
                .headers
                .iter()
                .zip(&table.columns)
                // Forces only (columns in newtons); counts and ratios have other units.
                .filter(|(h, _)| h.ends_with("_n"))
                .enumerate()
                .map(|(k, (h, c))| {
                    let label = h.trim_end_matches("_n").replace('_', " ");
                    Series::line(&label, t.clone(), c.iter().map(|v| v * 1e-3).collect(), k)
                })
                .collect();
            let stem = format!("contact_forces_{}", r.name);
            write(
                &LineChart {
                    title: format!("Contact forces: {}", r.name),
                    x_label: "time (ms)".into(),
                    y_label: "force (kN)".into(),
                    series,
                    ..Default::default()
                },
                Some(&out_dir.join(format!("{stem}.png"))),
                Some(&out_dir.join(format!("{stem}.svg"))),
            )?;
            let _ = writeln!(md, "![{stem}]({stem}.png)\n");
            files.push(format!("{stem}.png"));
        }
    }
    // ---- The paper's operating point (Table 3) beside ours.
    let mut points = Vec::new();
    for r in &runs {
        if let Some(op) = super::table3::operating_point(&r.dir)? {
            points.push((r.name.clone(), op));
        }
    }
    if !points.is_empty() {
        heading(&mut md, "Operating point against the paper's Table 3");
        md.push_str(&super::table3::to_markdown(&points));
        let path = out_dir.join("table3.json");
        let json = serde_json::to_string_pretty(&points)
            .map_err(|e| Error::Numerical(format!("table3.json: {e}")))?;
        std::fs::write(&path, json).map_err(|e| Error::io(&path, e))?;
        files.push("table3.json".into());
    }
    // Contact-patch snapshots (rolling runs): maps and centre line.
    let mut patch_md = String::new();
    for r in &runs {
        let dir = r.dir.join("patches");
        let Ok(entries) = std::fs::read_dir(&dir) else {
            continue;
        };
        let mut csvs: Vec<PathBuf> = entries
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|x| x == "csv"))
            .collect();
        csvs.sort();
        for csv in csvs.iter().take(6) {
            let snapshot: Option<crate::kalker::snapshot::PatchSnapshot> =
                crate::input::read_json(&csv.with_extension("json")).ok();
            let (mu, time_ms) = snapshot
                .map(|s| (s.mu, s.time_s * 1e3))
                .unwrap_or((f64::NAN, f64::NAN));
            let file_stem = csv
                .file_stem()
                .map(|s| s.to_string_lossy().to_string())
                .unwrap_or_default();
            let stem = format!("{}_{}", file_stem, r.name);
            match super::patch_maps::write_patch_maps(csv, mu, time_ms, out_dir, &stem) {
                Ok(pngs) => {
                    let _ = writeln!(patch_md, "**{} at {time_ms:.1} ms**\n", r.name);
                    for f in pngs {
                        let _ = writeln!(patch_md, "![{f}]({f})");
                        files.push(f);
                    }
                    let _ = writeln!(patch_md);
                }
                Err(e) => {
                    let _ = writeln!(patch_md, "- {}: {e}", csv.display());
                }
            }
        }
    }
    if !patch_md.is_empty() {
        heading(&mut md, "Contact patches");
        md.push_str(&patch_md);
    }

    // ---- Modal chart (frequency against nodal diameters per family; measured from an
    // optional RUN_DIR/hammer.csv).
    if let Some((dir, modes)) = runs
        .iter()
        .find_map(|r| r.modes.as_ref().map(|m| (&r.dir, m)))
    {
        heading(&mut md, "Wheel modes");
        let hammer_path = dir.join("hammer.csv");
        let measured = if hammer_path.exists() {
            Some(crate::hammer::read_hammer_csv(&hammer_path)?)
        } else {
            None
        };
        super::modal_chart::write_modal_chart(
            modes,
            measured.as_deref(),
            Some(&out_dir.join("modes.png")),
            Some(&out_dir.join("modes.svg")),
        )?;
        let _ = writeln!(md, "![modes](modes.png)\n");
        if let Some(meas) = &measured {
            let _ = writeln!(md, "{}", crate::hammer::compare(meas, modes).to_markdown());
        }
        files.push("modes.png".into());
    }

    // ---- Mode-to-peak tables.
    if runs.iter().any(|r| !r.analyses.is_empty()) {
        heading(&mut md, "Dominant frequencies and wheel modes");
        for r in &runs {
            for a in &r.analyses {
                let _ = writeln!(
                    md,
                    "### {} ({})\n\n{}",
                    r.name,
                    a.column,
                    to_markdown(&a.identifications, a.direction, Default::default())
                );
            }
        }
    }

    // ---- Squeal: do the zero-nodal-circle modes grow?
    let mut squeal_md = String::new();
    for r in &runs {
        let Some(modes) = &r.modes else { continue };
        let mut series_out = Vec::new();
        let mut tables = String::new();
        for (k, &(m, n, column)) in SQUEAL_BANDS.iter().enumerate() {
            if r.histories.column(column).is_none() {
                continue;
            }
            let Ok(bands) = crate::growth::bands_for_modes(modes, &[(m, n)], 0.05) else {
                continue;
            };
            let series = crate::growth::read_column(&r.dir, column)?;
            let from_s = report_options
                .from_s
                .or_else(|| crate::analysis::lateral_onset_s(&r.dir))
                .unwrap_or(series.start_time_s);
            let g = crate::growth::band_growth(&series, &bands, from_s, GROWTH_WINDOW_S)?;
            tables.push_str(&crate::growth::to_markdown(&g));
            tables.push('\n');
            for b in &g.bands {
                let pts: Vec<(f64, f64)> = g
                    .time_s
                    .iter()
                    .zip(&b.ridge)
                    .filter(|(_, a)| a.is_finite() && **a > 0.0)
                    .map(|(t, a)| (t * 1e3, *a))
                    .collect();
                series_out.push(Series::line(
                    &format!(
                        "{} ({})",
                        b.band.name,
                        if n == 0 {
                            "rim mean"
                        } else {
                            "rim point - mean"
                        }
                    ),
                    pts.iter().map(|p| p.0).collect(),
                    pts.iter().map(|p| p.1).collect(),
                    k,
                ));
            }
        }
        if series_out.is_empty() {
            continue;
        }
        let stem = format!("squeal_ridges_{}", r.name);
        write(
            &LineChart {
                title: format!(
                    "{}: wavelet ridge amplitude in the bands of (0,0), (0,3), (0,4)",
                    r.name
                ),
                x_label: "time (ms)".into(),
                y_label: "ridge amplitude (m/s)".into(),
                series: series_out,
                log_y: true,
                ..Default::default()
            },
            Some(&out_dir.join(format!("{stem}.png"))),
            Some(&out_dir.join(format!("{stem}.svg"))),
        )?;
        files.push(format!("{stem}.png"));
        let _ = writeln!(
            squeal_md,
            "### {}\n\n![{stem}]({stem}.png)\n\n{tables}",
            r.name
        );
    }
    // rms of the rim's lateral vibration against the hub's lateral motion, per run.
    let mut rms_md = String::new();
    for r in &runs {
        let t = r.histories.column("time_s").unwrap_or(&[]);
        let cols = [
            "lateral_velocity_m_per_s",
            "rim_mean_lateral_velocity_m_per_s",
            "rim_point_minus_mean_lateral_velocity_m_per_s",
            "wheel_centre_y_velocity_m_per_s",
        ];
        let Some(values) = cols
            .iter()
            .map(|c| r.histories.column(c))
            .collect::<Option<Vec<&[f64]>>>()
        else {
            continue;
        };
        let from_s = report_options
            .from_s
            .or_else(|| crate::analysis::lateral_onset_s(&r.dir))
            .unwrap_or(t.first().copied().unwrap_or(0.0));
        let to_s = report_options.to_s.unwrap_or(f64::INFINITY);
        let rms = |v: &[f64]| {
            let (sum, count) = t
                .iter()
                .zip(v)
                .filter(|(tt, _)| **tt >= from_s && **tt <= to_s)
                .fold((0.0, 0usize), |a, (_, x)| (a.0 + x * x, a.1 + 1));
            if count > 0 {
                (sum / count as f64).sqrt()
            } else {
                f64::NAN
            }
        };
        let _ = writeln!(
            rms_md,
            "| {} | {:.1}- ms | {:.4} | {:.4} | {:.4} | {:.4} |",
            r.name,
            from_s * 1e3,
            rms(values[0]),
            rms(values[1]),
            rms(values[2]),
            rms(values[3])
        );
    }
    if !rms_md.is_empty() {
        heading(&mut md, "Lateral wheel vibration: rim against hub");
        md.push_str("rms lateral velocity (m/s) in the frame that moves with the wheelset, from the lateral-motion onset (or --from-ms): rim point, rim mean (n = 0 motion, which the hub's lateral motion drives), rim point less rim mean (n >= 1 motion, driven only from the contact), and the hub's own lateral velocity (track frame).\n\n| run | window | rim point | rim mean (n = 0) | rim point - mean (n >= 1) | hub |\n|---|---|---|---|---|---|\n");
        md.push_str(&rms_md);
        md.push('\n');
    }
    if !squeal_md.is_empty() {
        heading(&mut md, "Squeal modes over time (wavelet ridges)");
        md.push_str("Ridge amplitude of the Morlet wavelet power in each mode's band (+-5 %) and its growth rate per 4 ms window (slope of ln A). (0,0) is followed on the rim mean, (0,3) and (0,4) on the rim point less the rim mean: the n >= 1 motion, which the hub's lateral motion does not drive.\n\n");
        md.push_str(&squeal_md);
    }

    // ---- Sound.
    heading(&mut md, "Listen");
    for r in &runs {
        let t = r.histories.column("time_s").unwrap_or(&[]);
        if let (Some((_, v)), true) = (r.histories.column_starting("lateral_"), t.len() > 64) {
            let fs = (t.len() - 1) as f64 / (t[t.len() - 1] - t[0]);
            let name = format!("{}_lateral.wav", r.name);
            write_wav(&out_dir.join(&name), v, fs, 44_100)?;
            let _ = writeln!(
                md,
                "- [{}: lateral wheel vibration]({name}) (resampled to 44.1 kHz, normalised)",
                r.name
            );
            files.push(name);
        }
    }

    // ---- Metadata.
    heading(&mut md, "Run metadata");
    for r in &runs {
        let _ = writeln!(md, "### {}\n", r.name);
        let meta = r.dir.join("run.json");
        if meta.exists() {
            let v: serde_json::Value = crate::input::read_json(&meta)?;
            if let Some(obj) = v.as_object() {
                let _ = writeln!(md, "| item | value |\n|---|---|");
                for (k, val) in obj {
                    let _ = writeln!(md, "| {k} | {} |", val.to_string().trim_matches('"'));
                }
            }
        } else {
            let _ = writeln!(md, "(no run.json)");
        }
        let t = r.histories.column("time_s").unwrap_or(&[]);
        let _ = writeln!(
            md,
            "\nhistories: {} samples, {:.1} ms, columns {}",
            t.len(),
            1e3 * (t.last().copied().unwrap_or(0.0) - t.first().copied().unwrap_or(0.0)),
            r.histories.headers.join(", ")
        );
    }

    let index_md = out_dir.join("index.md");
    std::fs::write(&index_md, &md).map_err(|e| Error::io(&index_md, e))?;
    let index_html = out_dir.join("index.html");
    std::fs::write(&index_html, markdown_to_html(title, &md))
        .map_err(|e| Error::io(&index_html, e))?;
    files.extend(["index.md".to_string(), "index.html".to_string()]);
    let summary = ReportSummary {
        directory: out_dir.to_path_buf(),
        runs: runs.iter().map(|r| r.name.clone()).collect(),
        files,
        sections,
    };
    let json = out_dir.join("report.json");
    std::fs::write(
        &json,
        serde_json::to_string_pretty(&summary).unwrap_or_default(),
    )
    .map_err(|e| Error::io(&json, e))?;
    Ok(summary)
}

/// Minimal markdown -> HTML for the report's own markdown (headings, images, links, tables,
/// lists, paragraphs).
pub fn markdown_to_html(title: &str, md: &str) -> String {
    let esc = |s: &str| {
        s.replace('&', "&amp;")
            .replace('<', "&lt;")
            .replace('>', "&gt;")
    };
    let inline = |s: &str| -> String {
        // Images ![alt](src) and links [text](href); everything else escaped.
        let mut out = String::new();
        let mut rest = s;
        while let Some(start) = rest.find('[') {
            let is_img = start > 0 && rest.as_bytes()[start - 1] == b'!';
            let (before, after) = rest.split_at(if is_img { start - 1 } else { start });
            out.push_str(&esc(before));
            let after = if is_img { &after[1..] } else { after };
            if let (Some(close), Some(paren)) = (after.find("]("), after.find(')')) {
                if close < paren {
                    let text = &after[1..close];
                    let href = &after[close + 2..paren];
                    if is_img {
                        out.push_str(&format!(
                            "<img src=\"{}\" alt=\"{}\" style=\"max-width:48%\">",
                            esc(href),
                            esc(text)
                        ));
                    } else {
                        out.push_str(&format!("<a href=\"{}\">{}</a>", esc(href), esc(text)));
                    }
                    rest = &after[paren + 1..];
                    continue;
                }
            }
            out.push_str(&esc(&after[..1]));
            rest = &after[1..];
        }
        out.push_str(&esc(rest));
        out
    };
    let mut html = format!("<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>{}</title><style>body{{font-family:sans-serif;max-width:1400px;margin:auto}}table{{border-collapse:collapse}}td,th{{border:1px solid #bbb;padding:3px 8px}}</style></head><body>\n", esc(title));
    let mut in_table = false;
    let mut in_list = false;
    for line in md.lines() {
        let l = line.trim_end();
        if l.starts_with('|') {
            if l.contains("---") {
                continue;
            }
            if !in_table {
                html.push_str("<table>\n");
                in_table = true;
            }
            let cells: Vec<&str> = l.trim_matches('|').split('|').collect();
            html.push_str("<tr>");
            for c in cells {
                html.push_str(&format!("<td>{}</td>", inline(c.trim())));
            }
            html.push_str("</tr>\n");
            continue;
        } else if in_table {
            html.push_str("</table>\n");
            in_table = false;
        }
        if let Some(item) = l.strip_prefix("- ") {
            if !in_list {
                html.push_str("<ul>\n");
                in_list = true;
            }
            html.push_str(&format!("<li>{}</li>\n", inline(item)));
            continue;
        } else if in_list {
            html.push_str("</ul>\n");
            in_list = false;
        }
        if let Some(h) = l.strip_prefix("### ") {
            html.push_str(&format!("<h3>{}</h3>\n", inline(h)));
        } else if let Some(h) = l.strip_prefix("## ") {
            html.push_str(&format!("<h2>{}</h2>\n", inline(h)));
        } else if let Some(h) = l.strip_prefix("# ") {
            html.push_str(&format!("<h1>{}</h1>\n", inline(h)));
        } else if !l.is_empty() {
            html.push_str(&format!("<p>{}</p>\n", inline(l)));
        }
    }
    if in_table {
        html.push_str("</table>\n");
    }
    if in_list {
        html.push_str("</ul>\n");
    }
    html.push_str("</body></html>\n");
    html
}
