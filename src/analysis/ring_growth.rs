//! Growth and limit cycle of each nodal-diameter harmonic of a run's rim ring, and the squeal
//! verdict, by the criteria of docs/curving.md ("Criteria fixed before the runs").
//!
//! Method, per direction d (lateral, radial, circumferential) and harmonic n of the ring
//! ([`crate::analysis::per_n`]):
//! - **envelope**: over consecutive windows of [`GrowthCriteria::window_s`] (5 ms) from the
//!   record's first sample, `E(w) = sqrt(mean over w of (c_n^2 + s_n^2))` (m/s; `s_0 = 0`): the
//!   rms of the harmonic's field around the ring times sqrt 2, so that a standing pattern
//!   `A cos(n theta) cos(omega t)` gives `A / sqrt 2` and a travelling one `A` (its rms in time
//!   at the crest);
//! - **build-up**: the end of the creep force's build-up is the end of the first window whose
//!   mean lateral creep force magnitude (`contact_forces.csv`) reaches
//!   [`GrowthCriteria::build_up_fraction`] (90 %) of its mean over the record's last
//!   [`GrowthCriteria::final_span_s`] (50 ms); the harmonic's level there, `E_b`, is the
//!   reference its growth is measured from;
//! - **final level**: the mean of `E` over the last 50 ms, `E_f`, and over the 50 ms before,
//!   `E_p`; the growth factor is `E_f / E_b`;
//! - **growth rate**: the least-squares slope of `ln E` against the windows' mid times, over
//!   the linear phase: from the first window after the build-up where `E > 3 E_b` to the
//!   first window from there where `E >= E_f / 2` (at least 3 windows, else not resolved);
//! - **limit cycle**: reached when `|E_f - E_p| < 10 % E_p`; its amplitude is `E_f`, its
//!   frequency the harmonic's highest peak over the last 50 ms (the per-n PSD), named by the
//!   nearest mode of that n whose family the direction sees, within the identify tolerance;
//! - **squeal**: a harmonic squeals when `E_f / E_b >= 10` and its final peak is named by a
//!   mode of its n; the winning mode is the squealing harmonic with the largest `E_f`.
//!
//! Per-mode envelopes split a harmonic between its modes: the Morlet ridge of `c_n` and of
//! `s_n` in each mode's band (+-5 %, [`crate::analysis::growth`]) combined as
//! `sqrt((A_c^2 + A_s^2) / 2)` and averaged over the same windows, so that a harmonic holding
//! one mode has the same envelope both ways.
//!
//! The criteria's numbers were written down before any curve run was analysed
//! (docs/curving.md); [`GrowthCriteria::default`] holds them, and reported results use it.

use std::path::Path;

use serde::Serialize;

use crate::analysis::growth::{band_growth, Band};
use crate::analysis::identify::ModeRef;
use crate::analysis::per_n::{analyse_harmonics, read_ring, PerNOptions, RingDirection};
use crate::analysis::run::{read_run_modes, AnalysisOptions};
use crate::signal::TimeSeries;
use crate::{Error, Result};

/// The numbers of the criteria (docs/curving.md, fixed on 2026-11-29 before the runs).
#[derive(Clone, Copy, Debug, Serialize)]
pub struct GrowthCriteria {
    /// Envelope window (s): 5 ms.
    pub window_s: f64,
    /// The final span and the span before it (s): 50 ms.
    pub final_span_s: f64,
    /// Fraction of the final mean creep force that ends the build-up: 0.9.
    pub build_up_fraction: f64,
    /// Growth factor from the build-up's level to the final level that counts as squeal: 10.
    pub squeal_factor: f64,
    /// The linear phase starts where the envelope first exceeds this multiple of its build-up
    /// level: 3.
    pub linear_start_factor: f64,
    /// ... and ends where it first reaches this fraction of its final level: 0.5.
    pub linear_end_fraction: f64,
    /// Largest relative change between the last two spans of a limit cycle: 0.1.
    pub limit_cycle_change: f64,
    /// Half width of a mode's band for its per-mode envelope, relative: 0.05 (the identify
    /// tolerance).
    pub mode_band_half_width: f64,
}

impl Default for GrowthCriteria {
    fn default() -> Self {
        GrowthCriteria {
            window_s: 0.005,
            final_span_s: 0.050,
            build_up_fraction: 0.9,
            squeal_factor: 10.0,
            linear_start_factor: 3.0,
            linear_end_fraction: 0.5,
            limit_cycle_change: 0.10,
            mode_band_half_width: 0.05,
        }
    }
}

/// The envelope windows shared by every harmonic and the creep force.
#[derive(Clone, Debug, Serialize)]
pub struct EnvelopeWindows {
    /// Window length (s).
    pub window_s: f64,
    /// Start of each window (s).
    pub start_s: Vec<f64>,
    /// Mean lateral creep force magnitude per window (N).
    pub creep_force_n: Vec<f64>,
    /// The window that ends the build-up.
    pub build_up_window: usize,
    /// End of the build-up (s).
    pub build_up_end_s: f64,
    /// Windows of the final span and of the span before it.
    pub final_windows: std::ops::Range<usize>,
    /// Windows of the span before the final one (empty when the record is too short).
    pub previous_windows: std::ops::Range<usize>,
}

/// Growth and limit cycle of one harmonic in one direction.
#[derive(Clone, Debug, Serialize)]
pub struct HarmonicGrowth {
    /// Direction of the ring's motion.
    pub direction: RingDirection,
    /// Nodal diameters.
    pub n: usize,
    /// Envelope per window (m/s).
    pub envelope_m_per_s: Vec<f64>,
    /// Level at the end of the build-up, `E_b` (m/s).
    pub build_up_level_m_per_s: f64,
    /// Mean over the final span, `E_f` (m/s).
    pub final_level_m_per_s: f64,
    /// Mean over the span before, `E_p` (m/s; NaN when the record is too short).
    pub previous_level_m_per_s: f64,
    /// `E_f / E_b`.
    pub growth_factor: f64,
    /// Growth rate over the linear phase (1/s); None when not resolved.
    pub growth_rate_per_s: Option<f64>,
    /// The linear phase (s), when resolved.
    pub linear_phase_s: Option<(f64, f64)>,
    /// `(E_f - E_p) / E_p`.
    pub final_change: f64,
    /// Whether the growth has stopped (a limit cycle, or a steady level that never grew).
    pub limit_cycle: bool,
    /// The harmonic's highest peak over the final span (Hz).
    pub final_peak_hz: Option<f64>,
    /// The mode of this n that names it.
    pub final_mode: Option<ModeRef>,
    /// Whether the harmonic squeals by the criteria.
    pub squeals: bool,
}

impl HarmonicGrowth {
    /// "(0,3) axial" or "n = 3 (unnamed)".
    pub fn mode_name(&self) -> String {
        match &self.final_mode {
            Some(m) => format!("{} {}", m.label(), m.family.word()),
            None => format!("n = {} (unnamed)", self.n),
        }
    }
}

/// The envelope of one mode of one harmonic.
#[derive(Clone, Debug, Serialize)]
pub struct ModeEnvelope {
    /// Direction.
    pub direction: RingDirection,
    /// The mode.
    pub mode: ModeRef,
    /// Envelope per window (m/s; NaN where the window lies in the wavelet's cone of influence).
    pub envelope_m_per_s: Vec<f64>,
}

/// The verdict of a run.
#[derive(Clone, Debug, Serialize)]
pub struct SquealVerdict {
    /// Whether any harmonic squeals.
    pub squeals: bool,
    /// Index into [`RingGrowth::harmonics`] of the winner (the squealing harmonic with the
    /// largest final level), or of the harmonic with the largest final level when none squeals.
    pub leading: Option<usize>,
    /// One sentence.
    pub summary: String,
}

/// Result of [`ring_growth`].
#[derive(Clone, Debug, Serialize)]
pub struct RingGrowth {
    /// The criteria applied.
    pub criteria: GrowthCriteria,
    /// The windows.
    pub windows: EnvelopeWindows,
    /// Per direction and harmonic.
    pub harmonics: Vec<HarmonicGrowth>,
    /// Per mode (of the directions' families, below the band's top).
    pub modes: Vec<ModeEnvelope>,
    /// The verdict.
    pub verdict: SquealVerdict,
}

/// The directions in the order they are analysed.
pub const DIRECTIONS: [RingDirection; 3] = [
    RingDirection::Lateral,
    RingDirection::Radial,
    RingDirection::Circumferential,
];

/// Growth, limit cycle and verdict of the ring of `run_dir` (its `ring.csv`,
/// `contact_forces.csv` and `modes.json`, or `modes_file`), over the record up to `to_s` (the
/// whole record when None: a longer run's first part set against a shorter one's).
pub fn ring_growth(
    run_dir: &Path,
    modes_file: Option<&Path>,
    criteria: &GrowthCriteria,
    to_s: Option<f64>,
) -> Result<RingGrowth> {
    // The ring first: a run without one is told so before anything else is missing.
    let mut records = Vec::new();
    for d in DIRECTIONS {
        records.push(read_ring(run_dir, d)?);
    }
    let modes = read_run_modes(run_dir, modes_file)?;
    let forces_path = run_dir.join("contact_forces.csv");
    if !forces_path.exists() {
        return Err(Error::input(
            run_dir.display().to_string(),
            "contact_forces.csv",
            "a growth analysis needs the run's creep force to find the end of its build-up",
        ));
    }
    let mut force = TimeSeries::from_csv(&forces_path, "lateral_creep_force_n")?;
    if let Some(t) = to_s {
        if !(t.is_finite() && t > 0.0) {
            return Err(Error::input(
                "command line",
                "--to-ms",
                format!("must be a positive time (got {} ms)", t * 1e3),
            ));
        }
        crop(&mut force, t);
        for r in &mut records {
            for p in &mut r.parts {
                crop(p, t);
            }
        }
    }
    growth_of_records(&records, &force, &modes, criteria)
}

/// Drops the samples of `x` after `to_s`.
fn crop(x: &mut TimeSeries, to_s: f64) {
    let keep = (((to_s - x.start_time_s) * x.sample_rate_hz + 1e-6).floor() as usize + 1)
        .min(x.values.len());
    x.values.truncate(keep);
}

/// [`ring_growth`] on records in memory: the phases are the windows and the build-up, each
/// harmonic's envelope and growth, its final peak, the per-mode envelopes, the verdict.
pub fn growth_of_records(
    records: &[crate::analysis::per_n::RingRecord],
    creep_force: &TimeSeries,
    modes: &[ModeRef],
    criteria: &GrowthCriteria,
) -> Result<RingGrowth> {
    let first = records
        .first()
        .ok_or_else(|| Error::Numerical("a growth analysis needs a ring record".into()))?;
    let windows = envelope_windows(&first.parts[0], creep_force, criteria, &first.path)?;
    let mut harmonics = Vec::new();
    let mut mode_envelopes = Vec::new();
    for ring in records {
        let end_s = ring.parts[0].start_time_s
            + (ring.parts[0].values.len() - 1) as f64 / ring.parts[0].sample_rate_hz;
        let options = PerNOptions {
            direction: ring.direction,
            spectrum: AnalysisOptions {
                from_s: Some(end_s - criteria.final_span_s),
                ..AnalysisOptions::default()
            },
        };
        let finals = analyse_harmonics(ring, modes.to_vec(), &options)?;
        for n in 0..=ring.n_max {
            let envelope = harmonic_envelope(ring.harmonic(n), &windows);
            let peak = finals.peaks.iter().find(|p| p.n == n && p.rank == 1);
            harmonics.push(judge_harmonic(
                ring.direction,
                n,
                envelope,
                &windows,
                peak.map(|p| p.frequency_hz),
                peak.and_then(|p| p.mode.clone()),
                criteria,
            ));
            mode_envelopes.extend(mode_envelopes_of(
                ring,
                n,
                modes,
                &windows,
                finals.band_hz,
                criteria,
            )?);
        }
    }
    let verdict = verdict(&harmonics, criteria);
    Ok(RingGrowth {
        criteria: *criteria,
        windows,
        harmonics,
        modes: mode_envelopes,
        verdict,
    })
}

/// The windows of the record, the creep force's mean per window, the build-up's end and the
/// final spans.
fn envelope_windows(
    grid: &TimeSeries,
    creep_force: &TimeSeries,
    criteria: &GrowthCriteria,
    path: &Path,
) -> Result<EnvelopeWindows> {
    let fs = grid.sample_rate_hz;
    let per_window = (criteria.window_s * fs).round() as usize;
    let count = grid.values.len().checked_div(per_window).unwrap_or(0);
    let final_count = (criteria.final_span_s / criteria.window_s).round() as usize;
    if per_window < 2 || count < final_count + 1 {
        return Err(Error::input(
            path.display().to_string(),
            "time_s",
            format!(
                "a growth analysis needs at least {:.0} ms of record (the final span of {:.0} ms \
                 and one {:.0} ms window before it) sampled at least every {:.2} ms; the record \
                 holds {:.1} ms",
                (criteria.final_span_s + criteria.window_s) * 1e3,
                criteria.final_span_s * 1e3,
                criteria.window_s * 1e3,
                criteria.window_s * 0.5e3,
                grid.values.len() as f64 / fs * 1e3
            ),
        ));
    }
    let window_s = per_window as f64 / fs;
    let start_s: Vec<f64> = (0..count)
        .map(|w| grid.start_time_s + (w * per_window) as f64 / fs)
        .collect();
    let creep_force_n: Vec<f64> = start_s
        .iter()
        .map(|&t0| mean_magnitude_between(creep_force, t0, t0 + window_s))
        .collect();
    let final_windows = count - final_count..count;
    let previous_windows = count.saturating_sub(2 * final_count)..count - final_count;
    let previous_windows = if previous_windows.len() == final_count {
        previous_windows
    } else {
        0..0
    };
    let final_force = mean(&creep_force_n[final_windows.clone()]);
    let build_up_window = creep_force_n
        .iter()
        .position(|&f| f >= criteria.build_up_fraction * final_force)
        .unwrap_or(0);
    Ok(EnvelopeWindows {
        window_s,
        build_up_end_s: start_s[build_up_window] + window_s,
        start_s,
        creep_force_n,
        build_up_window,
        final_windows,
        previous_windows,
    })
}

/// Mean of `|x|` over the samples in `[t0, t1)` (NaN without samples).
fn mean_magnitude_between(x: &TimeSeries, t0: f64, t1: f64) -> f64 {
    let fs = x.sample_rate_hz;
    let k0 = (((t0 - x.start_time_s) * fs) - 1e-6).ceil().max(0.0) as usize;
    let k1 = ((((t1 - x.start_time_s) * fs) - 1e-6).ceil().max(0.0) as usize).min(x.values.len());
    if k1 <= k0 {
        return f64::NAN;
    }
    x.values[k0..k1].iter().map(|v| v.abs()).sum::<f64>() / (k1 - k0) as f64
}

/// Mean of a slice (NaN when empty or when every value is NaN; NaN values skipped).
fn mean(x: &[f64]) -> f64 {
    let finite: Vec<f64> = x.iter().copied().filter(|v| v.is_finite()).collect();
    if finite.is_empty() {
        f64::NAN
    } else {
        finite.iter().sum::<f64>() / finite.len() as f64
    }
}

/// `sqrt(mean(c^2 + s^2))` per window (module docs).
fn harmonic_envelope(parts: &[TimeSeries], windows: &EnvelopeWindows) -> Vec<f64> {
    let fs = parts[0].sample_rate_hz;
    let per_window = (windows.window_s * fs).round() as usize;
    (0..windows.start_s.len())
        .map(|w| {
            let range = w * per_window..(w + 1) * per_window;
            let sum: f64 = parts
                .iter()
                .map(|p| p.values[range.clone()].iter().map(|v| v * v).sum::<f64>())
                .sum();
            (sum / per_window as f64).sqrt()
        })
        .collect()
}

/// The growth, limit cycle and squeal of one harmonic from its envelope (module docs).
fn judge_harmonic(
    direction: RingDirection,
    n: usize,
    envelope: Vec<f64>,
    windows: &EnvelopeWindows,
    final_peak_hz: Option<f64>,
    final_mode: Option<ModeRef>,
    criteria: &GrowthCriteria,
) -> HarmonicGrowth {
    let e_b = envelope[windows.build_up_window];
    let e_f = mean(&envelope[windows.final_windows.clone()]);
    let e_p = mean(&envelope[windows.previous_windows.clone()]);
    let growth_factor = e_f / e_b;
    let (growth_rate_per_s, linear_phase_s) = linear_phase(&envelope, windows, e_b, e_f, criteria);
    let final_change = (e_f - e_p) / e_p;
    let squeals = growth_factor >= criteria.squeal_factor && final_mode.is_some();
    HarmonicGrowth {
        direction,
        n,
        build_up_level_m_per_s: e_b,
        final_level_m_per_s: e_f,
        previous_level_m_per_s: e_p,
        growth_factor,
        growth_rate_per_s,
        linear_phase_s,
        final_change,
        limit_cycle: final_change.abs() < criteria.limit_cycle_change,
        final_peak_hz,
        final_mode,
        squeals,
        envelope_m_per_s: envelope,
    }
}

/// The growth rate over the linear phase and the phase's span (module docs).
fn linear_phase(
    envelope: &[f64],
    windows: &EnvelopeWindows,
    e_b: f64,
    e_f: f64,
    criteria: &GrowthCriteria,
) -> (Option<f64>, Option<(f64, f64)>) {
    let after = windows.build_up_window + 1;
    let Some(start) =
        (after..envelope.len()).find(|&w| envelope[w] > criteria.linear_start_factor * e_b)
    else {
        return (None, None);
    };
    let Some(end) =
        (start..envelope.len()).find(|&w| envelope[w] >= criteria.linear_end_fraction * e_f)
    else {
        return (None, None);
    };
    if end < start + 2 {
        return (None, None);
    }
    let half = 0.5 * windows.window_s;
    let points: Vec<(f64, f64)> = (start..=end)
        .filter(|&w| envelope[w] > 0.0)
        .map(|w| (windows.start_s[w] + half, envelope[w].ln()))
        .collect();
    let span = (
        windows.start_s[start],
        windows.start_s[end] + windows.window_s,
    );
    (Some(least_squares_slope(&points)), Some(span))
}

/// Least-squares slope of y against x.
fn least_squares_slope(points: &[(f64, f64)]) -> f64 {
    let count = points.len() as f64;
    let mx = points.iter().map(|p| p.0).sum::<f64>() / count;
    let my = points.iter().map(|p| p.1).sum::<f64>() / count;
    let sxy: f64 = points.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let sxx: f64 = points.iter().map(|p| (p.0 - mx) * (p.0 - mx)).sum();
    sxy / sxx
}

/// The per-mode envelopes of harmonic `n` of `ring`: every mode of that n whose family the
/// direction sees, with its band inside `band_hz` (module docs).
fn mode_envelopes_of(
    ring: &crate::analysis::per_n::RingRecord,
    n: usize,
    modes: &[ModeRef],
    windows: &EnvelopeWindows,
    band_hz: (f64, f64),
    criteria: &GrowthCriteria,
) -> Result<Vec<ModeEnvelope>> {
    let families = ring.direction.families();
    let h = criteria.mode_band_half_width;
    // The wavelet's scales reach 5 % beyond a band (crate::analysis::growth), and stay below
    // the Nyquist frequency.
    let top_hz = band_hz.1.min(0.5 * ring.parts[0].sample_rate_hz / 1.05);
    let chosen: Vec<&ModeRef> = modes
        .iter()
        .filter(|m| m.nodal_diameters as usize == n && families.contains(&m.family))
        .filter(|m| m.frequency_hz * (1.0 - h) >= band_hz.0 && m.frequency_hz * (1.0 + h) <= top_hz)
        .collect();
    if chosen.is_empty() {
        return Ok(Vec::new());
    }
    let bands: Vec<Band> = chosen
        .iter()
        .map(|m| Band {
            name: m.label(),
            low_hz: m.frequency_hz * (1.0 - h),
            high_hz: m.frequency_hz * (1.0 + h),
        })
        .collect();
    let parts = ring.harmonic(n);
    let start_s = parts[0].start_time_s;
    let ridges: Vec<_> = parts
        .iter()
        .map(|p| band_growth(p, &bands, start_s, windows.window_s))
        .collect::<Result<_>>()?;
    let fs = parts[0].sample_rate_hz;
    let per_window = (windows.window_s * fs).round() as usize;
    let mut out = Vec::new();
    for (b, mode) in chosen.iter().enumerate() {
        let amplitude: Vec<f64> = (0..parts[0].values.len())
            .map(|k| {
                let sum: f64 = ridges.iter().map(|g| g.bands[b].ridge[k].powi(2)).sum();
                (0.5 * sum).sqrt()
            })
            .collect();
        let envelope = (0..windows.start_s.len())
            .map(|w| mean(&amplitude[w * per_window..(w + 1) * per_window]))
            .collect();
        out.push(ModeEnvelope {
            direction: ring.direction,
            mode: (*mode).clone(),
            envelope_m_per_s: envelope,
        });
    }
    Ok(out)
}

/// The verdict: the squealing harmonic with the largest final level, else the harmonic with
/// the largest final level.
fn verdict(harmonics: &[HarmonicGrowth], criteria: &GrowthCriteria) -> SquealVerdict {
    let largest = |squealing: bool| {
        (0..harmonics.len())
            .filter(|&i| !squealing || harmonics[i].squeals)
            .filter(|&i| harmonics[i].final_level_m_per_s.is_finite())
            .max_by(|&a, &b| {
                harmonics[a]
                    .final_level_m_per_s
                    .total_cmp(&harmonics[b].final_level_m_per_s)
            })
    };
    let winner = largest(true);
    let leading = winner.or_else(|| largest(false));
    let summary = match (winner, leading) {
        (Some(i), _) => {
            let h = &harmonics[i];
            format!(
                "squeals: {} at {:.1} Hz, {} n = {}, limit-cycle amplitude {:.3e} m/s ({}), \
                 grown x{:.0} since the creep force built up{}",
                h.mode_name(),
                h.final_peak_hz.unwrap_or(f64::NAN),
                h.direction.word(),
                h.n,
                h.final_level_m_per_s,
                if h.limit_cycle {
                    "limit cycle reached".to_string()
                } else if h.final_change.is_nan() {
                    "no span before the last to tell a limit cycle: the record is shorter than \
                     two final spans"
                        .to_string()
                } else {
                    format!(
                        "still changing: {:+.0} % over the last span",
                        100.0 * h.final_change
                    )
                },
                h.growth_factor,
                match h.growth_rate_per_s {
                    Some(r) => format!(", growth rate {r:+.0} /s"),
                    None => ", growth rate not resolved".into(),
                }
            )
        }
        (None, Some(i)) => {
            let h = &harmonics[i];
            let most = harmonics
                .iter()
                .filter(|h| h.growth_factor.is_finite())
                .max_by(|a, b| a.growth_factor.total_cmp(&b.growth_factor));
            format!(
                "no squeal: no harmonic grew x{:.0} to a named mode{}; the largest at the end is \
                 {} n = {} ({} at {:.1} Hz, {:.3e} m/s)",
                criteria.squeal_factor,
                most.map(|m| format!(
                    " (the most: {} n = {}, x{:.1})",
                    m.direction.word(),
                    m.n,
                    m.growth_factor
                ))
                .unwrap_or_default(),
                h.direction.word(),
                h.n,
                h.mode_name(),
                h.final_peak_hz.unwrap_or(f64::NAN),
                h.final_level_m_per_s
            )
        }
        (None, None) => "no squeal: no harmonic has a final level".into(),
    };
    SquealVerdict {
        squeals: winner.is_some(),
        leading,
        summary,
    }
}

/// The harmonics' envelopes as CSV: `time_s` (window mid), `creep_force_n`, then
/// `{direction}_n{n}_m_per_s`.
pub fn envelopes_csv(g: &RingGrowth) -> String {
    let mut s = String::from("time_s,lateral_creep_force_n");
    for h in &g.harmonics {
        s.push_str(&format!(",{}_n{}_m_per_s", h.direction.word(), h.n));
    }
    s.push('\n');
    let half = 0.5 * g.windows.window_s;
    for (w, t0) in g.windows.start_s.iter().enumerate() {
        s.push_str(&format!(
            "{:.6e},{:.6e}",
            t0 + half,
            g.windows.creep_force_n[w]
        ));
        for h in &g.harmonics {
            s.push_str(&format!(",{:.6e}", h.envelope_m_per_s[w]));
        }
        s.push('\n');
    }
    s
}

/// The per-mode envelopes as CSV: `time_s`, then `{direction}_{m}_{n}_{family}_{f}hz_m_per_s`
/// (the axle's labels repeat; the modal frequency, in hertz, tells them apart).
pub fn mode_envelopes_csv(g: &RingGrowth) -> String {
    let mut s = String::from("time_s");
    for m in &g.modes {
        s.push_str(&format!(
            ",{}_{}_{}_{}_{:.0}hz_m_per_s",
            m.direction.word(),
            m.mode.nodal_circles,
            m.mode.nodal_diameters,
            m.mode.family.word(),
            m.mode.frequency_hz
        ));
    }
    s.push('\n');
    let half = 0.5 * g.windows.window_s;
    for (w, t0) in g.windows.start_s.iter().enumerate() {
        s.push_str(&format!("{:.6e}", t0 + half));
        for m in &g.modes {
            s.push_str(&format!(",{:.6e}", m.envelope_m_per_s[w]));
        }
        s.push('\n');
    }
    s
}

/// The verdict and the table of harmonics (those that grew at least x3, or the five largest at
/// the end, whichever are more), as markdown.
pub fn to_markdown(g: &RingGrowth) -> String {
    format!("**{}**\n\n{}", g.verdict.summary, table_markdown(g))
}

/// The table of harmonics of [`to_markdown`] without the verdict.
pub fn table_markdown(g: &RingGrowth) -> String {
    let w = &g.windows;
    let mut s = format!(
        "The creep force built up by {:.1} ms ({:.0} % of its final {:.1} kN); \
         envelopes over {:.0} ms windows, final span the last {:.0} ms (docs/curving.md).\n\n",
        w.build_up_end_s * 1e3,
        100.0 * g.criteria.build_up_fraction,
        mean(&w.creep_force_n[w.final_windows.clone()]) * 1e-3,
        g.criteria.window_s * 1e3,
        g.criteria.final_span_s * 1e3
    );
    s.push_str(
        "| direction | n | at build-up (m/s) | final (m/s) | growth x | growth rate (1/s) | \
         linear phase (ms) | last span change (%) | limit cycle | final peak (Hz) | mode | \
         squeals |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    let mut order: Vec<usize> = (0..g.harmonics.len()).collect();
    order.sort_by(|&a, &b| {
        g.harmonics[b]
            .final_level_m_per_s
            .total_cmp(&g.harmonics[a].final_level_m_per_s)
    });
    for (rank, &i) in order.iter().enumerate() {
        let h = &g.harmonics[i];
        if rank >= 5 && h.growth_factor < g.criteria.linear_start_factor {
            continue;
        }
        s.push_str(&format!(
            "| {} | {} | {:.2e} | {:.2e} | {:.1} | {} | {} | {} | {} | {} | {} | {} |\n",
            h.direction.word(),
            h.n,
            h.build_up_level_m_per_s,
            h.final_level_m_per_s,
            h.growth_factor,
            h.growth_rate_per_s
                .map(|r| format!("{r:+.0}"))
                .unwrap_or_else(|| "-".into()),
            h.linear_phase_s
                .map(|(a, b)| format!("{:.0}-{:.0}", a * 1e3, b * 1e3))
                .unwrap_or_else(|| "-".into()),
            if h.final_change.is_nan() {
                "-".to_string()
            } else {
                format!("{:+.0}", 100.0 * h.final_change)
            },
            if h.limit_cycle { "yes" } else { "no" },
            h.final_peak_hz
                .map(|f| format!("{f:.1}"))
                .unwrap_or_else(|| "-".into()),
            h.final_mode
                .as_ref()
                .map(|_| h.mode_name())
                .unwrap_or_else(|| "-".into()),
            if h.squeals { "**yes**" } else { "no" }
        ));
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::identify::ModeFamily;
    use crate::analysis::per_n::RingRecord;

    const FS_HZ: f64 = 20_000.0;

    fn series(name: &str, values: Vec<f64>) -> TimeSeries {
        TimeSeries {
            column: name.into(),
            start_time_s: 0.0,
            sample_rate_hz: FS_HZ,
            values,
        }
    }

    fn axial(m: u32, n: u32, f: f64) -> ModeRef {
        ModeRef {
            frequency_hz: f,
            family: ModeFamily::Axial,
            nodal_circles: m,
            nodal_diameters: n,
        }
    }

    /// A lateral ring record of `duration_s` whose harmonics 0..=4 hold small steady tones,
    /// except harmonic `n_grow`, whose cosine part is `grow(t)` alone (its sine part zero).
    fn record(duration_s: f64, n_grow: usize, grow: impl Fn(f64) -> f64) -> RingRecord {
        let count = (duration_s * FS_HZ).round() as usize;
        let t = |k: usize| k as f64 / FS_HZ;
        let mut parts = Vec::new();
        for n in 0..=4usize {
            let steady = |k: usize, phase: f64| {
                1e-6 * (std::f64::consts::TAU * (300.0 + 170.0 * n as f64) * t(k) + phase).cos()
            };
            let (c, s): (Vec<f64>, Vec<f64>) = if n == n_grow {
                ((0..count).map(|k| grow(t(k))).collect(), vec![0.0; count])
            } else {
                (
                    (0..count).map(|k| steady(k, 0.0)).collect(),
                    (0..count).map(|k| steady(k, 1.0)).collect(),
                )
            };
            parts.push(series(&format!("n{n}_cos"), c));
            if n > 0 {
                parts.push(series(&format!("n{n}_sin"), s));
            }
        }
        RingRecord {
            path: "ring.csv".into(),
            direction: RingDirection::Lateral,
            n_max: 4,
            parts,
        }
    }

    /// A lateral creep force that ramps from 0 to 30 kN over the first 20 ms.
    fn creep_force(duration_s: f64) -> TimeSeries {
        let count = (duration_s * FS_HZ).round() as usize;
        series(
            "lateral_creep_force_n",
            (0..count)
                .map(|k| -30e3 * (k as f64 / FS_HZ / 0.020).min(1.0))
                .collect(),
        )
    }

    /// The growth analysis of a 250 ms record whose harmonic 3 follows `grow`, against
    /// `modes`, by the fixed criteria.
    fn judge(grow: impl Fn(f64) -> f64, modes: &[ModeRef]) -> RingGrowth {
        growth_of_records(
            &[record(0.25, 3, grow)],
            &creep_force(0.25),
            modes,
            &GrowthCriteria::default(),
        )
        .unwrap()
    }

    /// `A0 exp(sigma t) cos(2 pi f t)` until it reaches `a_sat`, then `a_sat cos(2 pi f t)`.
    fn exponential_then_saturated(sigma: f64, f_hz: f64, t_sat: f64) -> impl Fn(f64) -> f64 {
        let a_sat = 1e-2;
        move |t: f64| {
            let a = a_sat * (sigma * (t.min(t_sat) - t_sat)).exp();
            a * (std::f64::consts::TAU * f_hz * t).cos()
        }
    }

    #[test]
    fn the_build_up_ends_with_the_first_window_at_90_percent_of_the_final_force() {
        let g = growth_of_records(
            &[record(0.25, 3, |_| 0.0)],
            &creep_force(0.25),
            &[axial(0, 3, 1000.0)],
            &GrowthCriteria::default(),
        )
        .unwrap();
        // Window [15, 20) ms averages 87.5 % of the final force; [20, 25) ms 100 %.
        assert_eq!(g.windows.build_up_window, 4);
        assert!((g.windows.build_up_end_s - 0.025).abs() < 1e-12);
        assert_eq!(g.windows.final_windows, 40..50);
        assert_eq!(g.windows.previous_windows, 30..40);
    }

    #[test]
    fn an_exponential_growth_to_a_limit_cycle_is_a_squeal_at_its_rate() {
        let sigma = 100.0;
        let record = record(0.25, 3, exponential_then_saturated(sigma, 1000.0, 0.120));
        let g = growth_of_records(
            &[record],
            &creep_force(0.25),
            // (1,3) at 9.8 kHz lies too near the Nyquist frequency for a per-mode envelope.
            &[axial(0, 3, 1000.0), axial(0, 2, 600.0), axial(1, 3, 9800.0)],
            &GrowthCriteria::default(),
        )
        .unwrap();
        let h = g.harmonics.iter().find(|h| h.n == 3).unwrap();
        // The linear phase (its windows all before the saturation at 120 ms) holds whole
        // periods of the 1 kHz tone per window, so each window's rms is exp(sigma 5 ms) times
        // the one before exactly: the fit returns sigma to rounding.
        let rate = h.growth_rate_per_s.unwrap();
        assert!((rate - sigma).abs() < 1e-6 * sigma, "rate {rate}");
        let (a, b) = h.linear_phase_s.unwrap();
        assert!(a > 0.025 && b <= 0.120 + 1e-12, "phase {a} {b}");
        // Saturated from 120 ms: the last two 50 ms spans are equal; a standing cos of
        // amplitude 1e-2 has the envelope 1e-2 / sqrt 2 (whole periods per window: exact).
        assert!(h.limit_cycle && h.final_change.abs() < 1e-12);
        assert!((h.final_level_m_per_s - 1e-2 / 2f64.sqrt()).abs() < 1e-12);
        assert!(h.squeals);
        assert_eq!(h.final_mode.as_ref().unwrap().label(), "(0,3)");
        assert!((h.final_peak_hz.unwrap() - 1000.0).abs() < 10.0);
        assert!(g.verdict.squeals);
        assert_eq!(g.harmonics[g.verdict.leading.unwrap()].n, 3);
        assert!(
            g.verdict.summary.starts_with("squeals: (0,3) axial"),
            "{}",
            g.verdict.summary
        );
        // The per-mode envelope of the harmonic's one mode is its envelope (the Morlet ridge
        // reads a tone's amplitude within 2 % at 16 voices per octave).
        let m = g
            .modes
            .iter()
            .find(|m| m.mode.nodal_diameters == 3)
            .unwrap();
        assert_eq!(g.modes.len(), 2);
        let last = mean(&m.envelope_m_per_s[40..49]);
        assert!((last / h.final_level_m_per_s - 1.0).abs() < 0.02, "{last}");
        // Steady harmonics neither grow nor squeal.
        let steady = g.harmonics.iter().find(|h| h.n == 1).unwrap();
        assert!(!steady.squeals && steady.growth_rate_per_s.is_none());
        assert!((steady.growth_factor - 1.0).abs() < 0.05);
    }

    #[test]
    fn a_growth_still_under_way_is_no_limit_cycle() {
        // Saturating at 220 ms, the last span still grows past the one before.
        let g = judge(
            exponential_then_saturated(100.0, 1000.0, 0.220),
            &[axial(0, 3, 1000.0)],
        );
        let h = g.harmonics.iter().find(|h| h.n == 3).unwrap();
        assert!(!h.limit_cycle && h.final_change > 0.1);
        assert!(
            g.verdict.summary.contains("still changing"),
            "{}",
            g.verdict.summary
        );
    }

    #[test]
    fn a_growth_at_no_mode_of_its_n_is_no_squeal() {
        // The same growth at 1500 Hz, where harmonic 3 has no mode (only (0,3) at 1000 Hz).
        let g = judge(
            exponential_then_saturated(100.0, 1500.0, 0.120),
            &[axial(0, 3, 1000.0)],
        );
        let h = g.harmonics.iter().find(|h| h.n == 3).unwrap();
        assert!(h.growth_factor > 10.0 && h.final_mode.is_none() && !h.squeals);
        assert!(!g.verdict.squeals);
        assert!(
            g.verdict.summary.starts_with("no squeal"),
            "{}",
            g.verdict.summary
        );
    }

    /// An 80 ms record holds the final span (30-80 ms) but no span before it: no limit cycle
    /// can be told, and the verdict and the table say so rather than print NaN.
    #[test]
    fn a_record_without_a_span_before_the_last_says_so() {
        let g = growth_of_records(
            &[record(
                0.08,
                3,
                exponential_then_saturated(100.0, 1000.0, 0.070),
            )],
            &creep_force(0.08),
            &[axial(0, 3, 1000.0)],
            &GrowthCriteria::default(),
        )
        .unwrap();
        let h = g.harmonics.iter().find(|h| h.n == 3).unwrap();
        assert!(h.final_change.is_nan() && !h.limit_cycle);
        let text = to_markdown(&g);
        assert!(!text.contains("NaN"), "{text}");
        assert!(text.contains("no span before the last"), "{text}");
    }

    #[test]
    fn a_record_shorter_than_the_final_span_is_refused() {
        let err = growth_of_records(
            &[record(0.04, 3, |_| 0.0)],
            &creep_force(0.04),
            &[axial(0, 3, 1000.0)],
            &GrowthCriteria::default(),
        )
        .unwrap_err()
        .to_string();
        assert!(err.contains("time_s") && err.contains("55 ms"), "{err}");
    }
}
