//! The report's sections on a run's rim ring ([`crate::analysis::ring_growth`],
//! [`crate::analysis::per_n`]): the squeal verdict that opens the page, and the
//! nodal-diameter section (the frequency x n map, the harmonics' envelopes, the growth and
//! limit-cycle table, and the stability analysis's unstable modes beside the ring's harmonics).

use std::fmt::Write as _;

use super::chart::{write, write_heatmap, Heatmap, LineChart, Series};
use super::page::{Page, Run};
use super::sections::Context;
use crate::analysis::per_n::RingDirection;
use crate::analysis::ring_growth::{table_markdown, HarmonicGrowth, RingGrowth};
use crate::Result;

/// Harmonics drawn in the envelope chart: the largest at the end.
const ENVELOPE_LINES: usize = 6;

/// Rows of the stability comparison.
const STABILITY_ROWS: usize = 12;

/// The page's first section: per run, whether the wheel squeals by the criteria of
/// docs/curving.md, from its ring; runs without a ring say so.
pub(super) fn verdict(page: &mut Page, ctx: &Context) -> Result<()> {
    page.heading("Does the wheel squeal?");
    for r in ctx.runs {
        let line = match &r.ring {
            Some(Ok(g)) => format!("**{}**", g.verdict.summary),
            Some(Err(why)) => format!("**cannot be judged**: {why}. {}", older_measures(r, ctx)),
            None => format!(
                "**cannot be judged**: the run has no rim ring (`output.ring` in its case file, \
                 docs/curving.md), so its modes cannot be told apart by nodal diameter. {}",
                older_measures(r, ctx)
            ),
        };
        let _ = writeln!(page.md, "- `{}`: {line}", r.name);
    }
    let _ = writeln!(
        page.md,
        "\nSqueal: a nodal-diameter harmonic of the rim ring grows at least x10 from the end of \
         the creep force's build-up to its mean over the last 50 ms, at a peak named by a mode \
         of its n (criteria fixed before the curve runs, docs/curving.md).\n"
    );
    Ok(())
}

/// For a run the squeal criterion cannot judge: what the older measures say, in words, and
/// why they do not contradict each other (issue 53, item 17): whether (0,3) and (0,4) are
/// among the dominant lateral peaks (the Summary), and the fastest growth of their wavelet
/// ridges (the section "Squeal modes over time"). A ridge can grow over one 4 ms window from a
/// level far below the dominant peaks; a squeal is a mode that grows until it dominates and
/// settles, which a short record cannot show.
fn older_measures(r: &Run, ctx: &Context) -> String {
    let lateral = r.analyses.iter().find(|a| a.column.starts_with("lateral"));
    let Some(lateral) = lateral else {
        return "The run has no lateral peak analysis (no modes.json): nothing more to say."
            .to_string();
    };
    let dominant: Vec<&str> = ["(0,3)", "(0,4)"]
        .into_iter()
        .filter(|label| {
            lateral
                .identifications
                .iter()
                .any(|p| p.mode.as_ref().is_some_and(|m| m.label() == *label))
        })
        .collect();
    let among = match dominant.as_slice() {
        [] => format!(
            "neither (0,3) nor (0,4) is among the {} dominant lateral peaks (Summary)",
            lateral.identifications.len()
        ),
        [label] => format!(
            "{label} is among the {} dominant lateral peaks (Summary)",
            lateral.identifications.len()
        ),
        labels => format!(
            "{} are among the {} dominant lateral peaks (Summary)",
            labels.join(" and "),
            lateral.identifications.len()
        ),
    };
    // Each n >= 1 band's fastest window: (band, rate, from, to).
    // A run whose ridges cannot be computed says why, rather than reading as one that does
    // not record them (the section "Squeal modes over time" reports the same error).
    let bands = match super::sections::squeal_band_growths(r, ctx.report_options) {
        Ok(bands) => bands,
        Err(e) => return format!("By the older measures, {among}; the wavelet ridges: {e}."),
    };
    let mut fastest: Vec<(String, f64, f64, f64)> = Vec::new();
    for band in bands.iter().filter(|b| b.mode.1 > 0) {
        let Ok(g) = &band.outcome else { continue };
        for b in &g.bands {
            let best = b
                .windows
                .iter()
                .filter_map(|w| w.growth_rate_per_s.map(|rate| (rate, w.from_s, w.to_s)))
                .max_by(|x, y| x.0.total_cmp(&y.0));
            if let Some((rate, from_s, to_s)) = best {
                fastest.push((b.band.name.clone(), rate, from_s, to_s));
            }
        }
    }
    let list = fastest
        .iter()
        .map(|(name, rate, from_s, to_s)| {
            format!(
                "{name} at {rate:+.0} /s over {:.1}-{:.1} ms",
                from_s * 1e3,
                to_s * 1e3
            )
        })
        .collect::<Vec<_>>()
        .join(", ");
    let ridges = if fastest.iter().any(|f| f.1 > 0.0) {
        format!(
            "the wavelet ridges of their bands grow fastest: {list} (section \"Squeal modes over \
             time\"). The two do not contradict each other: a ridge's growth over one 4 ms window \
             says that a band rises, from however low a level; a squeal is a mode that grows \
             until it dominates and settles into a limit cycle, which needs a record of 100 ms or \
             more after the creep force has built up (a rim ring and `squeal growth --per-n` \
             judge it)"
        )
    } else if !fastest.is_empty() {
        format!("no wavelet ridge of their bands grows (fastest: {list})")
    } else if bands.iter().any(|b| b.mode.1 > 0) {
        "their wavelet ridges have no growth rate (too short a record)".to_string()
    } else {
        "the run does not record the rim point less the rim mean, so their wavelet ridges are \
         not followed"
            .to_string()
    };
    format!("By the older measures, {among}; {ridges}.")
}

/// The nodal-diameter section of every run with a ring.
pub(super) fn per_n(page: &mut Page, ctx: &Context) -> Result<()> {
    let with_ring: Vec<&Run> = ctx
        .runs
        .iter()
        .filter(|r| matches!(r.ring, Some(Ok(_))))
        .collect();
    if with_ring.is_empty() {
        return Ok(());
    }
    page.heading("Nodal diameters: the rim ring by harmonic");
    for r in with_ring {
        let Some(Ok(g)) = &r.ring else { continue };
        let _ = writeln!(page.md, "### {}\n", r.name);
        let mut row = String::new();
        if let Some(map) = &r.ring_map {
            let stem = format!("per_n_map_{}", r.name);
            write_heatmap(
                &per_n_heatmap(&r.name, map),
                Some(&ctx.out_dir.join(format!("{stem}.png"))),
                Some(&ctx.out_dir.join(format!("{stem}.svg"))),
            )?;
            let _ = write!(row, "![{stem}]({stem}.png) ");
            page.files.push(format!("{stem}.png"));
        }
        let stem = format!("ring_envelopes_{}", r.name);
        write(
            &envelope_chart(&r.name, g),
            Some(&ctx.out_dir.join(format!("{stem}.png"))),
            Some(&ctx.out_dir.join(format!("{stem}.svg"))),
        )?;
        let _ = write!(row, "![{stem}]({stem}.png)");
        page.files.push(format!("{stem}.png"));
        let _ = writeln!(
            page.md,
            "{row}\n\nLeft: the PSD of each lateral harmonic (`PSD(c_n) + PSD(s_n)`) after the \
             creep force's build-up, in dB below the map's maximum. Right: the envelopes (rms over \
             {:.0} ms windows) of the {ENVELOPE_LINES} harmonics largest at the end.\n\n{}",
            g.windows.window_s * 1e3,
            table_markdown(g)
        );
        if let Some(st) = &r.stability {
            stability_beside_ring(page, st, g);
        }
    }
    Ok(())
}

/// The lateral per-n map as a heatmap (n across, frequency up).
fn per_n_heatmap(name: &str, map: &crate::analysis::per_n::PerNAnalysis) -> Heatmap {
    let rows: Vec<usize> = (0..map.frequencies_hz.len())
        .filter(|&k| {
            map.frequencies_hz[k] >= map.band_hz.0 && map.frequencies_hz[k] <= map.band_hz.1
        })
        .collect();
    let mut values = Vec::with_capacity(map.spectra.len() * rows.len());
    for spectrum in &map.spectra {
        values.extend(rows.iter().map(|&k| spectrum.psd_per_hz[k]));
    }
    Heatmap {
        title: format!("{name}: lateral velocity by nodal diameters"),
        x_label: "nodal diameters n".into(),
        y_label: "frequency (Hz)".into(),
        x: map.spectra.iter().map(|s| s.n as f64).collect(),
        y: rows.iter().map(|&k| map.frequencies_hz[k]).collect(),
        values,
        range_db: 50.0,
        linear_range: None,
        log_y: false,
        overlay: Vec::new(),
        size_px: Some((760, 520)),
    }
}

/// The envelopes of the harmonics largest at the end, against time, on a log axis.
fn envelope_chart(name: &str, g: &RingGrowth) -> LineChart {
    let mut order: Vec<&HarmonicGrowth> = g.harmonics.iter().collect();
    order.sort_by(|a, b| b.final_level_m_per_s.total_cmp(&a.final_level_m_per_s));
    let half = 0.5 * g.windows.window_s;
    let t_ms: Vec<f64> = g.windows.start_s.iter().map(|t| 1e3 * (t + half)).collect();
    let series = order
        .iter()
        .take(ENVELOPE_LINES)
        .enumerate()
        .map(|(k, h)| {
            Series::line(
                &format!("{} n = {}", h.direction.word(), h.n),
                t_ms.clone(),
                h.envelope_m_per_s.clone(),
                k,
            )
        })
        .collect();
    LineChart {
        title: format!("{name}: ring harmonics' envelopes"),
        x_label: "time (ms)".into(),
        y_label: "envelope (m/s)".into(),
        series,
        log_y: true,
        size_px: Some((760, 520)),
        ..Default::default()
    }
}

/// The stability analysis's unstable eigenvalues beside the ring harmonic of each one's
/// dominant wheel mode.
fn stability_beside_ring(
    page: &mut Page,
    st: &crate::stability::output::StabilityBrief,
    g: &RingGrowth,
) {
    let _ = writeln!(
        page.md,
        "\nThe stability analysis `{}` ({}) beside the ring: each predicted unstable eigenvalue \
         and the harmonic of its dominant wheel mode's n, in the direction of its family.\n",
        st.path, st.origin
    );
    if st.unstable.is_empty() {
        let _ = writeln!(
            page.md,
            "It predicts no unstable eigenvalue below {:.0} Hz.\n",
            st.fmax_hz
        );
        return;
    }
    let _ = writeln!(
        page.md,
        "| predicted (Hz) | growth (1/s) | dominant mode | harmonic | its final peak (Hz) | its \
         growth x | its growth rate (1/s) | squeals |\n|---|---|---|---|---|---|---|---|"
    );
    for u in st.unstable.iter().take(STABILITY_ROWS) {
        let harmonic = mode_direction_and_n(&u.dominant).and_then(|(d, n)| {
            g.harmonics
                .iter()
                .find(|h| h.direction == d && h.n == n as usize)
        });
        let measured = match harmonic {
            Some(h) => format!(
                "{} n = {} | {} | {:.1} | {} | {}",
                h.direction.word(),
                h.n,
                h.final_peak_hz
                    .map(|f| format!("{f:.1}"))
                    .unwrap_or_else(|| "-".into()),
                h.growth_factor,
                h.growth_rate_per_s
                    .map(|r| format!("{r:+.0}"))
                    .unwrap_or_else(|| "not resolved".into()),
                if h.squeals { "yes" } else { "no" }
            ),
            None => "- | - | - | - | -".into(),
        };
        let _ = writeln!(
            page.md,
            "| {:.1} | {:+.2} | {} ({:.0} %) | {measured} |",
            u.frequency_hz,
            u.growth_rate_per_s,
            u.dominant,
            100.0 * u.share
        );
    }
    let _ = writeln!(page.md);
}

/// The ring direction and nodal diameters of a stability analysis's dominant-mode text, e.g.
/// "(0,5) axial 2770 Hz" -> (lateral, 5); None for the rail's or the axle's modes.
fn mode_direction_and_n(dominant: &str) -> Option<(RingDirection, u32)> {
    let mut words = dominant.split_whitespace();
    let label = words.next()?;
    let family = words.next()?;
    let (_, n) = crate::analysis::identify::parse_mode_label(label, "dominant").ok()?;
    let direction = match family {
        "axial" => RingDirection::Lateral,
        "radial" => RingDirection::Radial,
        "circumferential" => RingDirection::Circumferential,
        _ => return None,
    };
    Some((direction, n))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_dominant_wheel_mode_gives_its_ring_harmonic() {
        assert_eq!(
            mode_direction_and_n("(0,5) axial 2770 Hz"),
            Some((RingDirection::Lateral, 5))
        );
        assert_eq!(
            mode_direction_and_n("(1,2) circumferential 900 Hz"),
            Some((RingDirection::Circumferential, 2))
        );
        assert_eq!(mode_direction_and_n("rail lateral 1006 Hz"), None);
        assert_eq!(mode_direction_and_n("(2,0) axle 300 Hz"), None);
    }
}
