//! The sections of the run report ([`super::run_report`]), one function each, in the order
//! of the page.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::chart::{write, write_heatmap, Heatmap, LineChart, Series, Stroke};
use super::page::{Page, ReportOptions, Run, SQUEAL_BAND_TOP_HZ};

/// What every section reads.
#[derive(Clone, Copy)]
pub(super) struct Context<'a> {
    /// The runs.
    pub(super) runs: &'a [Run],
    /// The report folder.
    pub(super) out_dir: &'a Path,
    /// How to analyse.
    pub(super) report_options: &'a ReportOptions,
}
use crate::analysis::identify::to_markdown;
use crate::signal::{morlet_cwt, wav::write_wav, Scales};
use crate::table::Table;
use crate::{Error, Result};

/// Bands followed in the squeal section: the zero-nodal-circle axial modes the paper finds,
/// (0,0) on the rim mean (n = 0 motion), (0,3) and (0,4) on the rim point less the rim mean
/// (n >= 1 motion: the hub's lateral motion cannot drive it).
const SQUEAL_BANDS: [(u32, u32, &str); 3] = [
    (0, 0, "rim_mean_lateral_velocity_m_per_s"),
    (0, 3, "rim_point_minus_mean_lateral_velocity_m_per_s"),
    (0, 4, "rim_point_minus_mean_lateral_velocity_m_per_s"),
];

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
        linear_range: None,
        log_y: true,
        overlay: vec![coi_series],
        size_px: Some((760, 520)),
    })
}

/// Wheel vibration histories and PSDs of all runs on one figure per direction (paper fig. 9); the PSD chart states its window and padding.
///
/// Kept in one piece: one report section, written top to bottom as it reads.
/// The page's first section: per run, what was simulated, the contact forces' extremes, the
/// dominant lateral peaks with their modes and whether the squeal modes (0,3) and (0,4) are
/// among them; the details follow in the sections below.
pub(super) fn summary(page: &mut Page, ctx: &Context) -> Result<()> {
    page.heading("Summary");
    let mut md = String::from(
        "| run | simulated (ms) | largest Fn (kN) | largest abs Fy (kN) | dominant lateral peaks | (0,3) / (0,4) among them |\n|---|---|---|---|---|---|\n",
    );
    for r in ctx.runs {
        let time = r.histories.column("time_s").unwrap_or(&[]);
        let span = match (time.first(), time.last()) {
            (Some(a), Some(b)) => format!("{:.1}-{:.1}", a * 1e3, b * 1e3),
            _ => "-".into(),
        };
        let forces = Table::read(&r.dir.join("contact_forces.csv")).ok();
        let largest = |name: &str| -> String {
            forces
                .as_ref()
                .and_then(|t| t.column(name))
                .map(|c| c.iter().fold(0.0f64, |m, v| m.max(v.abs())))
                .map_or("-".into(), |v| format!("{:.1}", v * 1e-3))
        };
        let lateral = r.analyses.iter().find(|a| a.column.starts_with("lateral"));
        let (peaks, squeal) = match lateral {
            Some(a) => {
                let peaks: Vec<String> = a
                    .identifications
                    .iter()
                    .map(|p| match &p.mode {
                        Some(m) => format!("{:.0} Hz {}", p.peak_frequency_hz, m.label()),
                        None => format!("{:.0} Hz (no mode)", p.peak_frequency_hz),
                    })
                    .collect();
                let has = |label: &str| {
                    a.identifications
                        .iter()
                        .any(|p| p.mode.as_ref().is_some_and(|m| m.label() == label))
                };
                let yes_no = |b: bool| if b { "yes" } else { "no" };
                (
                    peaks.join(", "),
                    format!("{} / {}", yes_no(has("(0,3)")), yes_no(has("(0,4)"))),
                )
            }
            None => ("(no modes.json)".into(), "-".into()),
        };
        let _ = writeln!(
            md,
            "| `{}` | {span} | {} | {} | {peaks} | {squeal} |",
            r.name,
            largest("normal_force_n"),
            largest("lateral_force_n")
        );
    }
    page.md.push_str(&md);
    page.md.push('\n');
    Ok(())
}

pub(super) fn vibration(page: &mut Page, ctx: &Context) -> Result<()> {
    let Context { runs, out_dir, .. } = *ctx;
    // ---- Vibration histories and PSDs of all runs (paper fig. 9).
    page.heading("Wheel vibration: time histories and PSDs (all runs)");
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
                    a.psd.frequency_hz.to_vec(),
                    a.psd.psd_per_hz.to_vec(),
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
                    psds.push(Series::line(
                        &r.name,
                        psd.frequency_hz.to_vec(),
                        psd.psd_per_hz.to_vec(),
                        k,
                    ));
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
                // The squeal band unless the whole spectrum is asked for (--full-range).
                x_range: if ctx.report_options.full_frequency_range {
                    None
                } else {
                    Some((0.0, SQUEAL_BAND_TOP_HZ))
                },
                ..Default::default()
            },
            Some(&out_dir.join(format!("{stem}_psd.png"))),
            Some(&out_dir.join(format!("{stem}_psd.svg"))),
        )?;
        let _ = writeln!(
            page.md,
            "![{d} history]({stem}.png)\n![{d} PSD]({stem}_psd.png)\n"
        );
        for r in runs {
            if let Some(a) = r.analyses.iter().find(|a| a.column.starts_with(d)) {
                let _ = writeln!(
                    page.md,
                    "- PSD of {}: {:.2}-{:.2} ms (from {}); {}",
                    r.name,
                    a.window.from_s * 1e3,
                    a.window.to_s * 1e3,
                    a.window.start_from,
                    a.window.spectrum
                );
            }
        }
        let _ = writeln!(page.md);
        page.files
            .extend([format!("{stem}.png"), format!("{stem}_psd.png")]);
    }

    Ok(())
}

/// Wavelet power spectra of lateral, vertical and longitudinal vibration for up to two runs (paper fig. 10).
pub(super) fn wavelets(page: &mut Page, ctx: &Context) -> Result<()> {
    let Context { runs, out_dir, .. } = *ctx;
    // ---- Wavelet power spectra for up to two runs (paper fig. 10).
    page.heading("Wavelet power spectra (Morlet)");
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
            page.files.push(format!("{stem}.png"));
        }
        let _ = writeln!(page.md, "{row}\n\nColour: wavelet power in dB below its maximum (40 dB shown); dashed: cone of influence.\n");
    }

    Ok(())
}

/// Contact force histories per run.
pub(super) fn contact_forces(page: &mut Page, ctx: &Context) -> Result<()> {
    let Context { runs, out_dir, .. } = *ctx;
    // ---- Contact forces.
    let with_forces: Vec<&Run> = runs
        .iter()
        .filter(|r| r.dir.join("contact_forces.csv").exists())
        .collect();
    if !with_forces.is_empty() {
        page.heading("Contact forces");
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
            // Consecutive lines: one paragraph, the runs' charts side by side.
            let _ = writeln!(page.md, "![{stem}]({stem}.png)");
            page.files.push(format!("{stem}.png"));
        }
        page.md.push('\n');
    }
    Ok(())
}

/// The paper's operating point (Table 3) beside each run's ([`super::table3`]).
pub(super) fn operating_point(page: &mut Page, ctx: &Context) -> Result<()> {
    let Context { runs, out_dir, .. } = *ctx;
    // ---- The paper's operating point (Table 3) beside ours.
    let mut points = Vec::new();
    for r in runs {
        if let Some(op) = super::table3::operating_point(&r.dir)? {
            points.push((r.name.clone(), op));
        }
    }
    if !points.is_empty() {
        page.heading("Operating point against the paper's Table 3");
        page.md.push_str(&super::table3::to_markdown(&points));
        let path = out_dir.join("table3.json");
        let json = serde_json::to_string_pretty(&points)
            .map_err(|e| Error::Numerical(format!("table3.json: {e}")))?;
        std::fs::write(&path, json).map_err(|e| Error::io(&path, e))?;
        page.files.push("table3.json".into());
    }
    Ok(())
}

/// Patch snapshots drawn per run: every snapshot a case file asks for (the paper cases ask
/// for 8, the paper's five instants and three later ones), with room to spare; a run with more
/// says how many were left out.
const PATCHES_DRAWN: usize = 12;

/// Contact-patch snapshots (rolling runs): maps and centre-line stresses.
pub(super) fn patches(page: &mut Page, ctx: &Context) -> Result<()> {
    let Context { runs, out_dir, .. } = *ctx;
    // Contact-patch snapshots (rolling runs): maps and centre line.
    let mut patch_md = String::new();
    for r in runs {
        let dir = r.dir.join("patches");
        let Ok(entries) = std::fs::read_dir(&dir) else {
            continue;
        };
        let mut csvs: Vec<PathBuf> = entries
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|x| x == "csv"))
            .collect();
        csvs.sort();
        if csvs.len() > PATCHES_DRAWN {
            let _ = writeln!(
                patch_md,
                "{} of {}'s {} snapshots drawn (the first by time); the others are in `{}`.\n",
                PATCHES_DRAWN,
                r.name,
                csvs.len(),
                dir.display()
            );
        }
        for csv in csvs.iter().take(PATCHES_DRAWN) {
            let snapshot: Option<crate::kalker::snapshot::PatchSnapshot> =
                crate::input::read_json(&csv.with_extension("json")).ok();
            let (mu, time_ms) = snapshot
                .as_ref()
                .map(|s| (s.mu, s.time_s * 1e3))
                .unwrap_or((f64::NAN, f64::NAN));
            // Hertz on the profiles at the wheel's position then, when the run records it.
            let hertz = snapshot
                .as_ref()
                .and_then(|s| super::table3::hertz_of_snapshot(&r.dir, s).ok().flatten());
            let file_stem = csv
                .file_stem()
                .map(|s| s.to_string_lossy().to_string())
                .unwrap_or_default();
            let stem = format!("{}_{}", file_stem, r.name);
            match super::patch_maps::write_patch_maps(
                csv,
                mu,
                time_ms,
                hertz.as_ref(),
                out_dir,
                &stem,
            ) {
                Ok((pngs, patch)) => {
                    let _ = writeln!(patch_md, "**{} at {time_ms:.1} ms**\n", r.name);
                    let hertz_peak = hertz.map(|c| c.peak_pressure_pa * 1e-6);
                    let _ = write!(
                        patch_md,
                        "Resolution: {}, node spacing {:.1} mm.",
                        patch.statement(hertz_peak),
                        patch.node_spacing_mm
                    );
                    if patch.nodes_across() < super::patch_maps::RESOLVED_NODES_ACROSS {
                        let _ = write!(
                            patch_md,
                            " **Coarse**: fewer than {} nodes across; the maps show where \
                             the contact is, not its stress distribution, and the peak \
                             pressure is not the patch's.",
                            super::patch_maps::RESOLVED_NODES_ACROSS
                        );
                    }
                    let _ = writeln!(patch_md, "\n");
                    for f in pngs {
                        let _ = writeln!(patch_md, "![{f}]({f})");
                        page.files.push(f);
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
        page.heading("Contact patches");
        page.md.push_str(&patch_md);
    }

    Ok(())
}

/// The hammer test beside a run, if any: `RUN_DIR/hammer.csv` (labelled modes) or
/// `RUN_DIR/hammer.uff` (FRFs analysed by LSCF, or mode shapes; paired with the run's FE modes
/// by frequency, since the run keeps no FE shapes). The measured modes and the comparison table.
fn hammer_of_run(
    dir: &std::path::Path,
    modes: &[crate::modal::mode::ModeRef],
) -> Result<Option<(Vec<crate::testdata::hammer::MeasuredMode>, String)>> {
    use crate::testdata::ema::{fe_comparison::compare_with_fe, uff_modes};
    let csv = dir.join("hammer.csv");
    let uff = dir.join("hammer.uff");
    if csv.exists() {
        let measured = crate::testdata::hammer::read_hammer_csv(&csv)?;
        let table = crate::testdata::hammer::compare(&measured, modes).to_markdown();
        Ok(Some((measured, table)))
    } else if uff.exists() {
        let name = uff.display().to_string();
        let fmax_hz = modes.iter().map(|m| m.frequency_hz).fold(0.0, f64::max);
        let test = uff_modes::test_from_uff(
            &crate::testdata::uff::read_uff(&uff)?,
            &name,
            fmax_hz,
            uff_modes::DEFAULT_MAX_ORDER,
        )?;
        let cmp = compare_with_fe(&test, &name, modes, None);
        Ok(Some((cmp.measured, cmp.table.to_markdown())))
    } else {
        Ok(None)
    }
}

/// The modal chart (frequency against nodal diameters per family), with measured lines from an
/// optional hammer test beside the run ([`hammer_of_run`]).
pub(super) fn modes_chart(page: &mut Page, ctx: &Context) -> Result<()> {
    let Context { runs, out_dir, .. } = *ctx;
    // ---- Modal chart (frequency against nodal diameters per family; measured from an
    // optional hammer test beside the run).
    if let Some((dir, modes)) = runs
        .iter()
        .find_map(|r| r.modes.as_ref().map(|m| (&r.dir, m)))
    {
        page.heading("Wheel modes");
        let (measured, table) = hammer_of_run(dir, modes)?.unzip();
        super::modal_chart::write_modal_chart(
            modes,
            measured.as_deref(),
            Some(&out_dir.join("modes.png")),
            Some(&out_dir.join("modes.svg")),
        )?;
        let _ = writeln!(page.md, "![modes](modes.png)\n");
        if let Some(table) = &table {
            let _ = writeln!(page.md, "{table}");
        }
        page.files.push("modes.png".into());
    }

    Ok(())
}

/// Mode-to-peak tables.
pub(super) fn identification(page: &mut Page, ctx: &Context) -> Result<()> {
    let Context { runs, .. } = *ctx;
    // ---- Mode-to-peak tables.
    if runs.iter().any(|r| !r.analyses.is_empty()) {
        page.heading("Dominant frequencies and wheel modes");
        for r in runs {
            for a in &r.analyses {
                let _ = writeln!(
                    page.md,
                    "### {} ({})\n\n{}",
                    r.name,
                    a.column,
                    to_markdown(&a.identifications, a.direction, Default::default())
                );
            }
        }
    }

    Ok(())
}

/// Rows of the stability table: the predicted unstable eigenvalues with the largest growth.
const STABILITY_ROWS: usize = 12;

/// The predicted unstable modes of the run's stability analysis beside the run's PSD peaks: for
/// each unstable eigenvalue the nearest dominant peak of any direction, matched when it lies
/// within the identification's tolerance ([`crate::analysis::identify::Tolerance`], 5 % or 25 Hz); then
/// the peaks no unstable eigenvalue explains.
pub(super) fn stability(page: &mut Page, ctx: &Context) -> Result<()> {
    let Context { runs, .. } = *ctx;
    if runs.iter().all(|r| r.stability.is_none()) {
        return Ok(());
    }
    page.heading("Predicted unstable modes beside the PSD peaks");
    let tolerance = crate::analysis::identify::Tolerance::default();
    for r in runs {
        let Some(st) = &r.stability else { continue };
        let _ = writeln!(
            page.md,
            "### {}

Stability analysis `{}` (operating point: {}; eigenvalues up to {:.0} Hz).
",
            r.name, st.path, st.origin, st.fmax_hz
        );
        // Every direction's dominant peaks: (frequency, direction, rank).
        let peaks: Vec<(f64, String, usize)> = r
            .analyses
            .iter()
            .flat_map(|a| {
                a.identifications.iter().map(move |p| {
                    (
                        p.peak_frequency_hz,
                        a.column.split('_').next().unwrap_or("").to_string(),
                        p.rank,
                    )
                })
            })
            .collect();
        if st.unstable.is_empty() {
            let _ = writeln!(
                page.md,
                "No eigenvalue grows below {:.0} Hz: the analysis predicts no squeal at this operating point.\n",
                st.fmax_hz
            );
        } else {
            let _ = writeln!(
                page.md,
                "| predicted (Hz) | growth (1/s) | dominant mode (share) | nearest PSD peak | difference | within {:.0} % |\n|---|---|---|---|---|---|",
                100.0 * tolerance.relative
            );
            for u in st.unstable.iter().take(STABILITY_ROWS) {
                let nearest = peaks.iter().min_by(|a, b| {
                    (a.0 - u.frequency_hz)
                        .abs()
                        .total_cmp(&(b.0 - u.frequency_hz).abs())
                });
                let (peak, diff, within) = match nearest {
                    Some((f, d, rank)) => (
                        format!("{f:.0} Hz {d} (rank {rank})"),
                        format!("{:+.1} %", 100.0 * (f - u.frequency_hz) / u.frequency_hz),
                        if (f - u.frequency_hz).abs() <= tolerance.window_hz(u.frequency_hz) {
                            "yes"
                        } else {
                            "no"
                        },
                    ),
                    None => ("-".into(), "-".into(), "-"),
                };
                let _ = writeln!(
                    page.md,
                    "| {:.1} | {:+.2} | {} ({:.0} %) | {peak} | {diff} | {within} |",
                    u.frequency_hz,
                    u.growth_rate_per_s,
                    u.dominant,
                    100.0 * u.share
                );
            }
            if st.unstable.len() > STABILITY_ROWS {
                let _ = writeln!(
                    page.md,
                    "\n{} more unstable eigenvalues in the file.",
                    st.unstable.len() - STABILITY_ROWS
                );
            }
            let _ = writeln!(page.md);
        }
        let unexplained: Vec<String> = peaks
            .iter()
            .filter(|(f, ..)| {
                !st.unstable
                    .iter()
                    .any(|u| (f - u.frequency_hz).abs() <= tolerance.window_hz(u.frequency_hz))
            })
            .map(|(f, d, rank)| format!("{f:.0} Hz {d} (rank {rank})"))
            .collect();
        if !peaks.is_empty() {
            let _ = writeln!(
                page.md,
                "PSD peaks with no predicted unstable mode within the tolerance: {}.\n",
                if unexplained.is_empty() {
                    "none".to_string()
                } else {
                    unexplained.join(", ")
                }
            );
        }
    }
    Ok(())
}

/// One squeal band's wavelet-ridge analysis of a run (the section "Squeal modes over time").
pub(super) struct SquealBand {
    /// Its place in [`SQUEAL_BANDS`] (the chart colour).
    pub(super) index: usize,
    /// The mode (m, n) it follows.
    pub(super) mode: (u32, u32),
    /// The ridges and their growth rates, or why there are none (a record shorter than one
    /// growth window after its start).
    pub(super) outcome: std::result::Result<crate::analysis::growth::GrowthAnalysis, String>,
}

/// The wavelet ridges of the squeal bands (0,0), (0,3), (0,4) of a run with modes, from the
/// lateral-motion onset (or `--from-ms`), per 4 ms window; bands whose column or mode the run
/// lacks are left out.
pub(super) fn squeal_band_growths(
    r: &Run,
    report_options: &ReportOptions,
) -> Result<Vec<SquealBand>> {
    let Some(modes) = &r.modes else {
        return Ok(Vec::new());
    };
    let growth_options = crate::analysis::growth::GrowthOptions::default();
    let mut out = Vec::new();
    for (index, &(m, n, column)) in SQUEAL_BANDS.iter().enumerate() {
        if r.histories.column(column).is_none() {
            continue;
        }
        let Ok(bands) =
            crate::analysis::growth::bands_for_modes(modes, &[(m, n)], growth_options.half_width)
        else {
            continue;
        };
        let series = crate::analysis::growth::read_column(&r.dir, column)?;
        let from_s = report_options
            .from_s
            .or_else(|| crate::analysis::lateral_onset_s(&r.dir).ok().flatten())
            .unwrap_or(series.start_time_s);
        // A record that ends within one growth window of its start has no growth rate to
        // give: the section says so instead of failing the whole report.
        let end_s =
            series.start_time_s + (series.values.len() as f64 - 1.0) / series.sample_rate_hz;
        let outcome = if end_s - from_s < growth_options.window_s {
            Err(format!(
                "({m},{n}): the record from {:.2} ms to its end ({:.2} ms) is shorter than the \
                 {:.0} ms growth window: no growth rate.",
                from_s * 1e3,
                end_s * 1e3,
                growth_options.window_s * 1e3
            ))
        } else {
            Ok(crate::analysis::growth::band_growth(
                &series,
                &bands,
                from_s,
                growth_options.window_s,
            )?)
        };
        out.push(SquealBand {
            index,
            mode: (m, n),
            outcome,
        });
    }
    Ok(out)
}

/// Do the zero-nodal-circle modes grow: rms of the rim against the hub, and wavelet ridges of the squeal modes' bands with their growth rates.
///
/// Kept in one piece: one report section, written top to bottom as it reads.
pub(super) fn squeal(page: &mut Page, ctx: &Context) -> Result<()> {
    let Context {
        runs,
        out_dir,
        report_options,
    } = *ctx;
    // ---- Squeal: do the zero-nodal-circle modes grow?
    let mut squeal_md = String::new();
    for r in runs {
        let mut series_out = Vec::new();
        let mut tables = String::new();
        for band in squeal_band_growths(r, report_options)? {
            let (k, (_, n)) = (band.index, band.mode);
            let g = match band.outcome {
                Ok(g) => g,
                Err(why) => {
                    let _ = writeln!(tables, "{why}\n");
                    continue;
                }
            };
            tables.push_str(&crate::analysis::growth::to_markdown(&g));
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
            if !tables.is_empty() {
                let _ = writeln!(squeal_md, "### {}\n\n{tables}", r.name);
            }
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
        page.files.push(format!("{stem}.png"));
        let _ = writeln!(
            squeal_md,
            "### {}\n\n![{stem}]({stem}.png)\n\n{tables}",
            r.name
        );
    }
    // rms of the rim's lateral vibration against the hub's lateral motion, per run.
    let mut rms_md = String::new();
    for r in runs {
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
            .or_else(|| crate::analysis::lateral_onset_s(&r.dir).ok().flatten())
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
        // The window's end: the report's --to-ms, else the record's last sample.
        let end_s = to_s.min(t.last().copied().unwrap_or(from_s));
        let _ = writeln!(
            rms_md,
            "| {} | {:.1}-{:.1} ms | {:.4} | {:.4} | {:.4} | {:.4} |",
            r.name,
            from_s * 1e3,
            end_s * 1e3,
            rms(values[0]),
            rms(values[1]),
            rms(values[2]),
            rms(values[3])
        );
    }
    if !rms_md.is_empty() {
        page.heading("Lateral wheel vibration: rim against hub");
        page.md.push_str("rms lateral velocity (m/s) in the frame that moves with the wheelset, from the lateral-motion onset (or --from-ms): rim point, rim mean (n = 0 motion, which the hub's lateral motion drives), rim point less rim mean (n >= 1 motion, driven only from the contact), and the hub's own lateral velocity (track frame).\n\n| run | window | rim point | rim mean (n = 0) | rim point - mean (n >= 1) | hub |\n|---|---|---|---|---|---|\n");
        page.md.push_str(&rms_md);
        page.md.push('\n');
    }
    if !squeal_md.is_empty() {
        page.heading("Squeal modes over time (wavelet ridges)");
        page.md.push_str("Ridge amplitude of the Morlet wavelet power in each mode's band (+-5 %) and its growth rate per 4 ms window (slope of ln A). (0,0) is followed on the rim mean, (0,3) and (0,4) on the rim point less the rim mean: the n >= 1 motion, which the hub's lateral motion does not drive.\n\n");
        page.md.push_str(&squeal_md);
    }

    Ok(())
}

/// A WAV of each run's lateral vibration.
pub(super) fn listen(page: &mut Page, ctx: &Context) -> Result<()> {
    let Context { runs, out_dir, .. } = *ctx;
    // ---- Sound.
    page.heading("Listen");
    for r in runs {
        let t = r.histories.column("time_s").unwrap_or(&[]);
        if let (Some((_, v)), true) = (r.histories.column_starting("lateral_"), t.len() > 64) {
            let fs = (t.len() - 1) as f64 / (t[t.len() - 1] - t[0]);
            let name = format!("{}_lateral.wav", r.name);
            write_wav(&out_dir.join(&name), v, fs, 44_100)?;
            let _ = writeln!(
                page.md,
                "- [{}: lateral wheel vibration]({name}) (resampled to 44.1 kHz, normalised)",
                r.name
            );
            page.files.push(name);
        }
    }

    Ok(())
}

/// Each run's `run.json` and history columns.
pub(super) fn metadata(page: &mut Page, ctx: &Context) -> Result<()> {
    let Context { runs, .. } = *ctx;
    // ---- Metadata.
    page.heading("Run metadata");
    for r in runs {
        let _ = writeln!(page.md, "### {}\n", r.name);
        let meta = r.dir.join("run.json");
        if meta.exists() {
            let v: serde_json::Value = crate::input::read_json(&meta)?;
            if v.is_object() {
                let _ = writeln!(page.md, "| item | value |\n|---|---|");
                let mut rows = Vec::new();
                json_rows("", &v, &mut rows);
                let cell = |s: &str| s.replace('|', "\\|").replace('\n', " ");
                for (k, val) in rows {
                    let _ = writeln!(page.md, "| {} | {} |", cell(&k), cell(&val));
                }
            }
        } else {
            let _ = writeln!(page.md, "(no run.json)");
        }
        let t = r.histories.column("time_s").unwrap_or(&[]);
        let _ = writeln!(
            page.md,
            "\nhistories: {} samples, {:.1} ms, columns {}",
            t.len(),
            1e3 * (t.last().copied().unwrap_or(0.0) - t.first().copied().unwrap_or(0.0)),
            r.histories.headers.join(", ")
        );
    }

    Ok(())
}

/// A JSON value as rows of the metadata table, so that no cell runs off the page: one per
/// leaf, nested keys joined with dots (`model.nodes`), strings unquoted, arrays on one line
/// with a space after each comma (where a page can wrap them).
fn json_rows(key: &str, v: &serde_json::Value, rows: &mut Vec<(String, String)>) {
    match v {
        serde_json::Value::Object(o) if !o.is_empty() => {
            for (k, x) in o {
                let key = if key.is_empty() {
                    k.clone()
                } else {
                    format!("{key}.{k}")
                };
                json_rows(&key, x, rows);
            }
        }
        serde_json::Value::String(s) => rows.push((key.to_string(), s.clone())),
        other => rows.push((key.to_string(), spaced_json(other))),
    }
}

/// JSON on one line with a space after each comma and colon.
fn spaced_json(v: &serde_json::Value) -> String {
    let joined = |items: Vec<String>| items.join(", ");
    match v {
        serde_json::Value::Array(a) => format!("[{}]", joined(a.iter().map(spaced_json).collect())),
        serde_json::Value::Object(o) => format!(
            "{{{}}}",
            joined(
                o.iter()
                    .map(|(k, x)| format!("{k}: {}", spaced_json(x)))
                    .collect()
            )
        ),
        other => other.to_string(),
    }
}
