//! What `squeal stability` writes: `stability.json` (operating point, settings, model sizes,
//! the linearised contact, every eigenvalue with its participating modes, the sweep) and
//! `stability.csv` (one row per eigenvalue, per sweep point).

use std::fmt::Write as _;

use std::path::Path;

use serde::{Deserialize, Serialize};

use super::model::{PointAnalysis, Settings, StabilityModel};
use super::operating::OperatingPoint;
use super::rail_modes::RailModalModel;
use super::sweep::SweepResult;
use super::system::SystemEigen;
use super::wheel::family_name;

/// Sizes of the wheel's modal model.
#[derive(Clone, Debug, Serialize)]
pub struct WheelSummary {
    /// Axisymmetric modes below fmax (a pair counted once).
    pub modes: usize,
    /// Modal coordinates (pairs counted twice).
    pub coordinates: usize,
    /// Band (Hz).
    pub fmax_hz: f64,
    /// Wheel and half axle (kg).
    pub mass_kg: f64,
    /// Modal solve (s).
    pub solve_seconds: f64,
}

/// Sizes of the rail's modal model per direction.
#[derive(Clone, Debug, Serialize)]
pub struct RailSummary {
    /// Direction.
    pub direction: &'static str,
    /// Terms (modes kept plus lumped octaves).
    pub terms: usize,
    /// Modes kept explicitly up to (Hz).
    pub truncation_hz: f64,
    /// Static flexibility at the contact (m/N).
    pub static_flexibility_m_per_n: f64,
}

/// An unstable eigenvalue in brief.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Unstable {
    /// Frequency (Hz).
    pub frequency_hz: f64,
    /// Growth rate (1/s).
    pub growth_rate_per_s: f64,
    /// Dominant mode.
    pub dominant: String,
    /// Its energy share.
    pub share: f64,
}

/// What the run report shows of a `stability.json`: where the operating point came from, the
/// band, and the unstable eigenvalues.
#[derive(Clone, Debug)]
pub struct StabilityBrief {
    /// The file read.
    pub path: String,
    /// The operating point's origin (case file or run and time).
    pub origin: String,
    /// Eigenvalues were analysed up to this frequency (Hz).
    pub fmax_hz: f64,
    /// Unstable eigenvalues, largest growth first.
    pub unstable: Vec<Unstable>,
}

/// Read the brief of a `stability.json` written by `squeal stability`; errors name the file
/// and the field.
pub fn read_brief(path: &Path) -> crate::Result<StabilityBrief> {
    let name = path.display().to_string();
    let value: serde_json::Value = crate::input::read_json(path)?;
    let missing = |field: &str| {
        crate::Error::input(
            &name,
            field,
            "missing or of the wrong type (a stability.json of `squeal stability` has it)",
        )
    };
    let origin = value["operating_point"]["origin"]
        .as_str()
        .ok_or_else(|| missing("operating_point.origin"))?
        .to_string();
    let fmax_hz = value["settings"]["fmax_hz"]
        .as_f64()
        .ok_or_else(|| missing("settings.fmax_hz"))?;
    let unstable: Vec<Unstable> = serde_json::from_value(value["unstable"].clone())
        .map_err(|e| crate::Error::input(&name, "unstable", e.to_string()))?;
    Ok(StabilityBrief {
        path: name,
        origin,
        fmax_hz,
        unstable,
    })
}

/// The whole output.
#[derive(Clone, Debug, Serialize)]
pub struct StabilityReport {
    /// The operating point.
    pub operating_point: OperatingPoint,
    /// Settings.
    pub settings: Settings,
    /// Wheel model.
    pub wheel: WheelSummary,
    /// Rail model.
    pub rail: Vec<RailSummary>,
    /// The operating point analysed.
    pub point: PointAnalysis,
    /// Its unstable eigenvalues, largest growth first.
    pub unstable: Vec<Unstable>,
    /// The sweep, if any.
    pub sweep: Option<SweepResult>,
}

impl StabilityReport {
    /// Assemble the report.
    pub fn new(
        model: &StabilityModel,
        op: &OperatingPoint,
        rail: &[RailModalModel],
        wheel_coordinates: usize,
        point: PointAnalysis,
        sweep: Option<SweepResult>,
    ) -> StabilityReport {
        let unstable = point
            .unstable()
            .iter()
            .map(|e| Unstable {
                frequency_hz: e.frequency_hz,
                growth_rate_per_s: e.growth_rate_per_s,
                dominant: e.dominant().label.clone(),
                share: e.participation[0].share,
            })
            .collect();
        StabilityReport {
            operating_point: op.clone(),
            settings: model.settings,
            wheel: WheelSummary {
                modes: model
                    .wheel
                    .modes
                    .iter()
                    .filter(|m| m.frequency_hz <= model.settings.fmax_hz)
                    .count(),
                coordinates: wheel_coordinates,
                fmax_hz: model.settings.fmax_hz,
                mass_kg: model.wheel.mass_kg,
                solve_seconds: model.wheel.solve_seconds,
            },
            rail: rail
                .iter()
                .map(|r| RailSummary {
                    direction: r.direction.name(),
                    terms: r.modes.len(),
                    truncation_hz: r.truncation_hz,
                    static_flexibility_m_per_n: r.static_flexibility_m_per_n,
                })
                .collect(),
            point,
            unstable,
            sweep,
        }
    }

    /// `stability.csv`: the operating point's eigenvalues (parameter `none`), then every sweep
    /// point's.
    pub fn csv(&self) -> String {
        let mut out = String::from(
            "parameter,value,frequency_hz,growth_rate_per_s,damping_ratio,dominant,body,family,nodal_circles,nodal_diameters,share,second,second_share\n",
        );
        for e in &self.point.eigen {
            push_row(&mut out, "none", f64::NAN, e);
        }
        if let Some(s) = &self.sweep {
            for p in &s.points {
                for e in &p.eigen {
                    push_row(&mut out, s.spec.parameter.name(), p.value, e);
                }
            }
        }
        out
    }

    /// A short text summary for the terminal and docs.
    pub fn summary(&self) -> String {
        let op = &self.operating_point;
        let law = &self.point.law;
        let mut s = String::new();
        let _ = writeln!(s, "operating point: {}", op.origin);
        let _ = writeln!(
            s,
            "  Fn {:.1} kN, Fx {:.1} kN, Fy {:.1} kN, creep/bound {:.3}; xi {:.4} %, eta {:.4} %, spin {:.4} 1/m; mu {:.3}, dmu/dv {:.3} s/m",
            op.normal_force_n * 1e-3,
            law.force_n[0] * 1e-3,
            law.force_n[1] * 1e-3,
            law.creep_over_bound(),
            100.0 * op.creepages.xi,
            100.0 * op.creepages.eta,
            op.creepages.phi_per_m,
            op.mu,
            op.friction_slope_s_per_m
        );
        let _ = writeln!(
            s,
            "  contact: wheel S {:.2} mm, rail y {:.2} mm, angle {:.2} deg, wheel at x = {:.3} m; Hertz k {:.3e} N/m",
            op.contact_s_mm,
            op.contact_rail_y_m * 1e3,
            op.contact_angle_deg,
            op.wheel_x_m,
            law.normal_stiffness_n_per_m
        );
        let _ = writeln!(
            s,
            "model: {} wheel modes ({} coordinates) to {:.0} Hz, rail {} terms; {} coordinates; {:.3} s",
            self.wheel.modes,
            self.wheel.coordinates,
            self.wheel.fmax_hz,
            self.rail.iter().map(|r| r.terms).sum::<usize>(),
            self.point.coordinates,
            self.point.seconds
        );
        if self.unstable.is_empty() {
            let least = self
                .point
                .eigen
                .iter()
                .max_by(|a, b| a.growth_rate_per_s.total_cmp(&b.growth_rate_per_s));
            let _ = writeln!(
                s,
                "stable: no eigenvalue grows below {:.0} Hz",
                self.wheel.fmax_hz
            );
            if let Some(e) = least {
                let _ = writeln!(
                    s,
                    "  least stable: {:.1} Hz, growth {:+.3} /s, {}",
                    e.frequency_hz,
                    e.growth_rate_per_s,
                    e.dominant().label
                );
            }
        } else {
            let _ = writeln!(s, "unstable ({}):", self.unstable.len());
            for u in &self.unstable {
                let _ = writeln!(
                    s,
                    "  {:8.1} Hz  growth {:+9.3} /s  {} ({:.0} %)",
                    u.frequency_hz,
                    u.growth_rate_per_s,
                    u.dominant,
                    100.0 * u.share
                );
            }
        }
        if let Some(sw) = &self.sweep {
            let _ = writeln!(
                s,
                "sweep {} {}..{} ({} points, {:.2} s): curves with positive growth:",
                sw.spec.parameter.name(),
                sw.spec.from,
                sw.spec.to,
                sw.spec.points,
                sw.seconds
            );
            for c in sw.curves.iter().filter(|c| c.peak_growth() > 0.0) {
                let first = c
                    .growth_rate_per_s
                    .iter()
                    .position(|g| g.is_some_and(|g| g > 0.0))
                    .map(|k| sw.points[k].value);
                let _ = writeln!(
                    s,
                    "  {}: largest growth {:+.3} /s, first unstable at {}",
                    c.label,
                    c.peak_growth(),
                    first.map_or("-".into(), |v| format!("{v:.6}"))
                );
            }
        }
        s
    }
}

fn push_row(out: &mut String, parameter: &str, value: f64, e: &SystemEigen) {
    let d = e.dominant();
    let (m, n) = d
        .circles_diameters
        .map_or((String::new(), String::new()), |(m, n)| {
            (m.to_string(), n.to_string())
        });
    let second = e.participation.get(1);
    let _ = writeln!(
        out,
        "{parameter},{},{:.6},{:.6},{:.6e},\"{}\",{:?},{},{m},{n},{:.4},\"{}\",{}",
        if value.is_nan() {
            String::new()
        } else {
            format!("{value}")
        },
        e.frequency_hz,
        e.growth_rate_per_s,
        e.damping_ratio,
        d.label,
        d.body,
        d.family.map_or("", family_name),
        e.participation[0].share,
        second.map_or(String::new(), |p| p.tag.label.clone()),
        second.map_or(String::new(), |p| format!("{:.4}", p.share)),
    );
}
