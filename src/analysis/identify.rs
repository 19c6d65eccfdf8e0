//! Mode-to-peak identification: which wheel mode explains each dominant peak of a vibration
//! spectrum.
//!
//! A peak is explained by the mode, of a family the signal direction can see, whose frequency is
//! closest to the peak and within the tolerance `max(relative x f_mode, absolute_hz)`:
//! - lateral (axial, out-of-plane) vibration -> axial modes;
//! - vertical and longitudinal (in-plane) vibration -> radial and circumferential modes.
//!
//! Default tolerance: 5 % or 25 Hz, whichever is larger. Why: the explicit (one-point hex) mesh
//! and the modal model of the same wheel differ by a few per cent at the squeal frequencies
//! (docs/architecture.md, "Element technology"), and a 40 ms demo history resolves
//! frequencies only to ~25 Hz. A peak with no mode inside the tolerance is reported as
//! unexplained, never forced onto a mode.
//!
//! Labels follow the paper: (nodal circles, nodal diameters), e.g. (0,3).
//!
//! Nodal diameters from the rim: when the run also records the rim-averaged velocity (the mean
//! over every node of the rim face, in the frame that turns with the wheel), the ratio
//! `PSD(rim mean) / PSD(rim point)` at a peak tells what kind of motion the peak is. A mode with
//! n nodal diameters moves the rim as `cos(n theta)`: along the axle (lateral) the mean over
//! the circle keeps n = 0 and cancels every n >= 1; in the wheel plane (vertical,
//! longitudinal) the components of radial and circumferential motion along a fixed axis go as
//! `cos(theta) cos(n theta)`, and the mean keeps n = 1 only. So a ratio near 1 shows the rim
//! moving as one (n = 0 laterally, n = 1 in-plane), a ratio near 0 shows nodal diameters that
//! the mean cancels. Two modes 70 Hz apart, (1,0) at 1767 Hz and (0,4) at 1839 Hz on the
//! default wheel, fall in one peak of a 24 ms record; the ratio still tells them apart.
//! A peak is given only modes its ratio allows: at or above [`COMMON_MOTION_RATIO`] only the
//! n the mean keeps, at or below [`DIAMETRAL_MOTION_RATIO`] only the others, and in between
//! none (reported as mixed).

use serde::{Deserialize, Serialize};

pub use crate::modal::mode::{ModeFamily, ModeRef};
use crate::signal::SpectralPeak;
use crate::{Error, Result};

/// Direction of a vibration signal.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Direction {
    /// y, along the wheel axis.
    Lateral,
    /// z.
    Vertical,
    /// x.
    Longitudinal,
}

/// `PSD(rim mean) / PSD(rim point)` at or above which the rim moves as one. Why 0.5: at
/// least half the power at the peak is common motion of the whole rim, which only the n that
/// the mean keeps can give (the rim point and the mean see an n = 0 axial mode alike up to
/// the mode's variation over the rim face, 10-20 % on the demo wheel).
pub const COMMON_MOTION_RATIO: f64 = 0.5;

/// Ratio at or below which the peak is nodal-diameter motion: at most a fifth of its power is
/// common motion (the squeal check's bound for (0,3) and (0,4)).
pub const DIAMETRAL_MOTION_RATIO: f64 = 0.2;

/// What the rim-mean/rim-point ratio shows at a peak.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum RimMotion {
    /// The rim moves as one: the n the rim mean keeps (0 laterally, 1 in-plane).
    Common,
    /// Nodal-diameter motion that the rim mean cancels.
    Diametral,
    /// Neither clearly: no mode is assigned.
    Mixed,
}

impl RimMotion {
    /// Classifies a ratio.
    pub fn from_ratio(ratio: f64) -> RimMotion {
        if ratio >= COMMON_MOTION_RATIO {
            RimMotion::Common
        } else if ratio <= DIAMETRAL_MOTION_RATIO {
            RimMotion::Diametral
        } else {
            RimMotion::Mixed
        }
    }
}

impl Direction {
    /// Nodal diameters whose rim motion survives the mean over the rim in this direction.
    pub fn rim_mean_diameters(self) -> u32 {
        match self {
            Direction::Lateral => 0,
            Direction::Vertical | Direction::Longitudinal => 1,
        }
    }

    /// Whether a mode with `n` nodal diameters can make a peak whose rim motion is `motion`.
    pub fn allows(self, motion: Option<RimMotion>, n: u32) -> bool {
        match motion {
            None => true,
            Some(RimMotion::Common) => n == self.rim_mean_diameters(),
            Some(RimMotion::Diametral) => n != self.rim_mean_diameters(),
            Some(RimMotion::Mixed) => false,
        }
    }

    /// Families this direction sees.
    pub fn families(self) -> &'static [ModeFamily] {
        match self {
            Direction::Lateral => &[ModeFamily::Axial, ModeFamily::Axle],
            Direction::Vertical | Direction::Longitudinal => &[
                ModeFamily::Radial,
                ModeFamily::Circumferential,
                ModeFamily::Axle,
            ],
        }
    }
    /// Parse "lateral" / "vertical" / "longitudinal" (also as a prefix of a column name).
    /// The rim-averaged columns (`rim_mean_...`) and the rim point less the rim mean
    /// (`rim_point_minus_mean_...`, the n >= 1 motion) carry their direction after the prefix.
    pub fn from_signal_name(name: &str) -> Option<Direction> {
        let lower = name.to_ascii_lowercase();
        let n = lower
            .strip_prefix("rim_point_minus_mean_")
            .or_else(|| lower.strip_prefix("rim_mean_"))
            .unwrap_or(&lower);
        if n.starts_with("lateral") {
            Some(Direction::Lateral)
        } else if n.starts_with("vertical") {
            Some(Direction::Vertical)
        } else if n.starts_with("longitudinal") {
            Some(Direction::Longitudinal)
        } else {
            None
        }
    }
}

/// Matching tolerance.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Tolerance {
    /// Relative to the modal frequency.
    pub relative: f64,
    /// Absolute floor (Hz).
    pub absolute_hz: f64,
}

impl Default for Tolerance {
    fn default() -> Self {
        Tolerance {
            relative: 0.05,
            absolute_hz: 25.0,
        }
    }
}

impl Tolerance {
    /// Allowed distance (Hz) from a mode at `f_mode_hz`.
    pub fn window_hz(&self, f_mode_hz: f64) -> f64 {
        (self.relative * f_mode_hz).max(self.absolute_hz)
    }
}

/// One dominant peak and the mode that explains it (if any).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PeakIdentification {
    /// Rank of the peak (1 = most dominant).
    pub rank: usize,
    /// Peak frequency (refined, Hz).
    pub peak_frequency_hz: f64,
    /// PSD at the peak (signal unit^2/Hz).
    pub peak_psd: f64,
    /// The explaining mode.
    pub mode: Option<ModeRef>,
    /// (peak - mode) / mode in per cent.
    pub difference_percent: Option<f64>,
    /// `PSD(rim mean) / PSD(rim point)` at the peak (None: the run has no rim mean).
    #[serde(default)]
    pub rim_mean_over_point: Option<f64>,
    /// What the ratio shows.
    #[serde(default)]
    pub rim_motion: Option<RimMotion>,
}

/// Identify each peak (ranked list, most dominant first) with a mode. `rim_ratios` holds, per
/// peak, `PSD(rim mean) / PSD(rim point)` (see the module documentation), or is None when the
/// run has no rim mean; a peak then gets any mode of the right family.
pub fn identify(
    peaks: &[SpectralPeak],
    rim_ratios: Option<&[f64]>,
    modes: &[ModeRef],
    direction: Direction,
    tolerance: Tolerance,
) -> Vec<PeakIdentification> {
    let families = direction.families();
    peaks
        .iter()
        .enumerate()
        .map(|(k, p)| {
            let f = p.refined_frequency_hz;
            let ratio = rim_ratios.and_then(|r| r.get(k).copied());
            let motion = ratio.map(RimMotion::from_ratio);
            let best = modes
                .iter()
                .filter(|m| families.contains(&m.family) && m.frequency_hz > 0.0)
                .filter(|m| direction.allows(motion, m.nodal_diameters))
                .filter(|m| (f - m.frequency_hz).abs() <= tolerance.window_hz(m.frequency_hz))
                .min_by(|a, b| {
                    (f - a.frequency_hz)
                        .abs()
                        .total_cmp(&(f - b.frequency_hz).abs())
                });
            PeakIdentification {
                rank: k + 1,
                peak_frequency_hz: f,
                peak_psd: p.refined_psd,
                mode: best.cloned(),
                difference_percent: best.map(|m| 100.0 * (f - m.frequency_hz) / m.frequency_hz),
                rim_mean_over_point: ratio,
                rim_motion: motion,
            }
        })
        .collect()
}

/// Parse a required mode "m,n" (nodal circles, nodal diameters).
pub fn parse_required(text: &str) -> Result<(u32, u32)> {
    parse_mode_label(text, "--require")
}

/// A mode label `m,n` (or `(m,n)`) given in the command-line option `field`.
pub fn parse_mode_label(text: &str, field: &str) -> Result<(u32, u32)> {
    let bad = || {
        Error::input("command line", field, format!("`{text}` is not a mode label: write nodal circles and nodal diameters as two non-negative integers, e.g. 0,3"))
    };
    let parts: Vec<&str> = text
        .trim()
        .trim_start_matches('(')
        .trim_end_matches(')')
        .split(',')
        .map(str::trim)
        .collect();
    if parts.len() != 2 {
        return Err(bad());
    }
    let m = parts[0].parse::<u32>().map_err(|_| bad())?;
    let n = parts[1].parse::<u32>().map_err(|_| bad())?;
    Ok((m, n))
}

/// For each required (nodal circles, nodal diameters): whether it explains one of the peaks.
/// Returns the list of reasons for the missing ones (empty: all present).
pub fn missing_required(
    ids: &[PeakIdentification],
    required: &[(u32, u32)],
    modes: &[ModeRef],
    direction: Direction,
) -> Vec<String> {
    let mut reasons = Vec::new();
    for &(m, n) in required {
        let found = ids.iter().any(|i| {
            i.mode
                .as_ref()
                .is_some_and(|md| md.nodal_circles == m && md.nodal_diameters == n)
        });
        if found {
            continue;
        }
        let candidates: Vec<&ModeRef> = modes
            .iter()
            .filter(|md| md.nodal_circles == m && md.nodal_diameters == n)
            .collect();
        let reason = if candidates.is_empty() {
            format!("({m},{n}): no such mode in the modal results")
        } else if !candidates
            .iter()
            .any(|md| direction.families().contains(&md.family))
        {
            format!("({m},{n}): the modal results have it only as {:?}, which {:?} vibration does not see", candidates.iter().map(|c| c.family).collect::<Vec<_>>(), direction)
        } else if let Some(gated) = ids.iter().find(|i| {
            i.rim_motion.is_some()
                && candidates.iter().any(|c| {
                    direction.families().contains(&c.family)
                        && (i.peak_frequency_hz - c.frequency_hz).abs()
                            <= Tolerance::default().window_hz(c.frequency_hz)
                        && !direction.allows(i.rim_motion, c.nodal_diameters)
                })
        }) {
            format!(
                "({m},{n}): the peak at {:.1} Hz lies near it, but its rim-mean/rim-point PSD \
                 ratio {:.2} shows {} motion, which a mode with {n} nodal diameters does not make",
                gated.peak_frequency_hz,
                gated.rim_mean_over_point.unwrap_or(f64::NAN),
                match gated.rim_motion {
                    Some(RimMotion::Common) => "common (whole-rim)",
                    Some(RimMotion::Diametral) => "nodal-diameter",
                    _ => "mixed",
                }
            )
        } else {
            let f: Vec<String> = candidates
                .iter()
                .map(|c| format!("{:.1} Hz", c.frequency_hz))
                .collect();
            format!(
                "({m},{n}) at {} is not among the {} dominant peaks (peaks at {})",
                f.join(", "),
                ids.len(),
                ids.iter()
                    .map(|i| format!("{:.1}", i.peak_frequency_hz))
                    .collect::<Vec<_>>()
                    .join(", ")
            )
        };
        reasons.push(reason);
    }
    reasons
}

/// The paper-style table in markdown.
pub fn to_markdown(
    ids: &[PeakIdentification],
    direction: Direction,
    tolerance: Tolerance,
) -> String {
    let mut s = format!(
        "Dominant peaks of the {direction:?} vibration and the wheel modes that explain them (tolerance {:.0} % or {:.0} Hz). Mode = (nodal circles, nodal diameters). Rim mean/point: PSD of the rim-averaged over the rim-point vibration at the peak (>= {COMMON_MOTION_RATIO}: the whole rim moves as one, n = {}; <= {DIAMETRAL_MOTION_RATIO}: nodal diameters; between: mixed, no mode assigned).\n\n",
        100.0 * tolerance.relative,
        tolerance.absolute_hz,
        direction.rim_mean_diameters()
    );
    s.push_str("| rank | dominant frequency (Hz) | rim mean/point | modal frequency (Hz) | mode | family | difference (%) |\n|---|---|---|---|---|---|---|\n");
    for i in ids {
        let ratio = i
            .rim_mean_over_point
            .map_or("-".to_string(), |r| format!("{r:.2}"));
        match &i.mode {
            Some(m) => s.push_str(&format!(
                "| {} | {:.1} | {ratio} | {:.1} | {} | {:?} | {:+.2} |\n",
                i.rank,
                i.peak_frequency_hz,
                m.frequency_hz,
                m.label(),
                m.family,
                i.difference_percent.unwrap_or(0.0)
            )),
            None => s.push_str(&format!(
                "| {} | {:.1} | {ratio} | - | {} | - | - |\n",
                i.rank,
                i.peak_frequency_hz,
                if i.rim_motion == Some(RimMotion::Mixed) {
                    "mixed"
                } else {
                    "unexplained"
                }
            )),
        }
    }
    s
}

/// The same table as CSV text.
pub fn to_csv(ids: &[PeakIdentification]) -> String {
    let mut s = String::from("rank,dominant_frequency_hz,peak_psd,rim_mean_over_point,modal_frequency_hz,nodal_circles,nodal_diameters,family,difference_percent\n");
    for i in ids {
        let ratio = i
            .rim_mean_over_point
            .map_or(String::new(), |r| r.to_string());
        match &i.mode {
            Some(m) => s.push_str(&format!(
                "{},{},{},{ratio},{},{},{},{:?},{}\n",
                i.rank,
                i.peak_frequency_hz,
                i.peak_psd,
                m.frequency_hz,
                m.nodal_circles,
                m.nodal_diameters,
                m.family,
                i.difference_percent.unwrap_or(f64::NAN)
            )),
            None => s.push_str(&format!(
                "{},{},{},{ratio},,,,{},\n",
                i.rank,
                i.peak_frequency_hz,
                i.peak_psd,
                if i.rim_motion == Some(RimMotion::Mixed) {
                    "mixed"
                } else {
                    "unexplained"
                }
            )),
        }
    }
    s
}
