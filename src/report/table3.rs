//! The paper's operating point beside ours: Table 3 of Yang & Li (2019) (docs/operating-point.md) against a rolling run of the same case.
//!
//! For each instant the paper lists for the run's case: normal force Fn, lateral and
//! longitudinal creep forces Fy and Fx (magnitudes: the paper gives no signs), the creep force
//! over the traction bound `sqrt(Fx^2 + Fy^2) / (mu Fn)`, and the creepages that Kalker's
//! theory returns when given the forces. Ours come from `contact_forces.csv`, interpolated
//! linearly between the two samples around the instant (the paper gives its instants to
//! 10 us, our samples are 20 us apart) and, for the creepages, from the patch snapshot nearest it
//! (`patches/patch_*.json`, within [`SNAPSHOT_MATCH_S`]) given to the exact half-space solver on
//! the S1002/54E1 profiles at the wheel's lateral position then (as CONTACT does, with the
//! snapshot's spin), see [`crate::kalker::snapshot::compare_snapshot_on_profiles`]. The time of
//! first saturation is the first sample after the lateral-motion onset (else after 10 ms, past
//! the torque ramp) at which the creep force reaches 0.99 of the bound.

use std::path::Path;

use serde::Serialize;

use crate::table::{interpolate, Table};
use crate::Result;

/// Friction coefficient of cases 1-4 (Yang & Li 2019).
pub const PAPER_MU: f64 = 0.45;

/// Ratio of creep force to traction bound counted as saturated.
pub const SATURATION_RATIO: f64 = 0.99;

/// Largest distance between an instant and the snapshot used for its creepages (s).
pub const SNAPSHOT_MATCH_S: f64 = 3e-5;

/// One row of the paper's Table 3.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct PaperInstant {
    /// Case number (1-5).
    pub case: u32,
    /// Time (ms).
    pub time_ms: f64,
    /// Normal force (kN).
    pub normal_kn: f64,
    /// Lateral creep force (kN).
    pub lateral_kn: f64,
    /// Longitudinal creep force (kN).
    pub longitudinal_kn: f64,
    /// Lateral creepage from CONTACT (%); None where saturated.
    pub eta_percent: Option<f64>,
    /// Longitudinal creepage from CONTACT (%); None where saturated.
    pub xi_percent: Option<f64>,
}

impl PaperInstant {
    /// `sqrt(Fx^2 + Fy^2) / (mu Fn)`.
    pub fn creep_over_bound(&self) -> f64 {
        self.lateral_kn.hypot(self.longitudinal_kn) / (PAPER_MU * self.normal_kn)
    }
}

/// Yang & Li (2019), Table 3 (Yang & Li 2019).
pub const PAPER_TABLE3: [PaperInstant; 6] = [
    PaperInstant {
        case: 1,
        time_ms: 17.58,
        normal_kn: 126.68,
        lateral_kn: 2.19,
        longitudinal_kn: 39.46,
        eta_percent: Some(0.019),
        xi_percent: Some(0.304),
    },
    PaperInstant {
        case: 2,
        time_ms: 17.58,
        normal_kn: 125.61,
        lateral_kn: 9.30,
        longitudinal_kn: 39.19,
        eta_percent: Some(0.080),
        xi_percent: Some(0.308),
    },
    PaperInstant {
        case: 3,
        time_ms: 17.58,
        normal_kn: 123.87,
        lateral_kn: 20.27,
        longitudinal_kn: 38.12,
        eta_percent: Some(0.185),
        xi_percent: Some(0.317),
    },
    PaperInstant {
        case: 4,
        time_ms: 17.07,
        normal_kn: 102.60,
        lateral_kn: 18.41,
        longitudinal_kn: 33.59,
        eta_percent: Some(0.199),
        xi_percent: Some(0.331),
    },
    PaperInstant {
        case: 3,
        time_ms: 18.54,
        normal_kn: 116.19,
        lateral_kn: 36.83,
        longitudinal_kn: 34.01,
        eta_percent: Some(0.440),
        xi_percent: Some(0.326),
    },
    PaperInstant {
        case: 4,
        time_ms: 17.94,
        normal_kn: 106.46,
        lateral_kn: 47.04,
        longitudinal_kn: 6.09,
        eta_percent: None,
        xi_percent: None,
    },
];

/// Ours at one paper instant.
#[derive(Clone, Debug, Serialize)]
pub struct OurInstant {
    /// The paper's row.
    pub paper: PaperInstant,
    /// The instant (ms).
    pub time_ms: f64,
    /// Normal force (kN).
    pub normal_kn: f64,
    /// |lateral creep force| (kN).
    pub lateral_kn: f64,
    /// |longitudinal creep force| (kN).
    pub longitudinal_kn: f64,
    /// Creep force over traction bound.
    pub creep_over_bound: f64,
    /// |eta| (%) from Kalker on the snapshot, if one lies at the instant and the force is below
    /// the bound.
    pub eta_percent: Option<f64>,
    /// |xi| (%), likewise.
    pub xi_percent: Option<f64>,
    /// Why there are no creepages, or Kalker's note.
    pub creepage_note: String,
}

/// The operating point of one run against the paper.
#[derive(Clone, Debug, Serialize)]
pub struct OperatingPoint {
    /// Paper case (1-5).
    pub case: u32,
    /// Rows at the paper's instants for this case.
    pub instants: Vec<OurInstant>,
    /// First saturation (ms), if any.
    pub first_saturation_ms: Option<f64>,
    /// From where saturation was searched (ms).
    pub saturation_searched_from_ms: f64,
}

/// Paper case number of a run: from `run.json`'s case name (`case3-demo` -> 3), else the
/// directory name.
pub fn paper_case(run_dir: &Path) -> Option<u32> {
    let from_name = |name: &str| -> Option<u32> {
        let rest = name.split("case").nth(1)?;
        let digit = rest.chars().next()?.to_digit(10)?;
        (1..=5).contains(&digit).then_some(digit)
    };
    let record: Option<serde_json::Value> = crate::input::read_json(&run_dir.join("run.json")).ok();
    record
        .as_ref()
        .and_then(|r| r.get("case")?.as_str().and_then(from_name))
        .or_else(|| from_name(&run_dir.file_name()?.to_string_lossy()))
}

/// The operating point of a run (None when it has no contact forces or no paper case).
pub fn operating_point(run_dir: &Path) -> Result<Option<OperatingPoint>> {
    let Some(case) = paper_case(run_dir) else {
        return Ok(None);
    };
    let path = run_dir.join("contact_forces.csv");
    if !path.exists() {
        return Ok(None);
    }
    let table = Table::read(&path)?;
    let col = |name: &str| table.column(name).unwrap_or(&[]);
    let (t, normal, fx, fy, creep, bound) = (
        col("time_s"),
        col("normal_force_n"),
        col("longitudinal_creep_force_n"),
        col("lateral_creep_force_n"),
        col("creep_force_n"),
        col("traction_bound_n"),
    );
    if t.is_empty()
        || [normal, fx, fy, creep, bound]
            .iter()
            .any(|c| c.len() != t.len())
    {
        return Ok(None);
    }
    let flange_y_mm = flange_contact_wheel_y_mm(run_dir);
    let clearance = table.column("flange_clearance_mm");
    let ratio = |k: usize| {
        if bound[k] > 0.0 {
            creep[k] / bound[k]
        } else {
            0.0
        }
    };
    let nearest = |time_s: f64| {
        (0..t.len())
            .min_by(|&a, &b| (t[a] - time_s).abs().total_cmp(&(t[b] - time_s).abs()))
            .unwrap_or(0)
    };
    let at = |column: &[f64], time_s: f64| interpolate(t, column, time_s);
    let snapshots = snapshot_times(run_dir);
    let mut instants = Vec::new();
    for paper in PAPER_TABLE3.iter().filter(|p| p.case == case) {
        let time_s = paper.time_ms * 1e-3;
        let k = nearest(time_s);
        let mut row = OurInstant {
            paper: *paper,
            time_ms: paper.time_ms,
            normal_kn: at(normal, time_s) * 1e-3,
            lateral_kn: at(fy, time_s).abs() * 1e-3,
            longitudinal_kn: at(fx, time_s).abs() * 1e-3,
            creep_over_bound: at(creep, time_s) / at(bound, time_s).max(f64::MIN_POSITIVE),
            eta_percent: None,
            xi_percent: None,
            creepage_note: String::new(),
        };
        let snapshot = snapshots
            .iter()
            .filter(|(ts, _)| (ts - time_s).abs() <= SNAPSHOT_MATCH_S)
            .min_by(|a, b| (a.0 - time_s).abs().total_cmp(&(b.0 - time_s).abs()));
        let wheel_y_m = wheel_y_from(flange_y_mm, clearance, k);
        match (snapshot, wheel_y_m) {
            (None, _) => row.creepage_note = "no patch snapshot at this instant".into(),
            (Some(_), None) => {
                row.creepage_note = "no wheel position in run.json / contact_forces.csv".into()
            }
            (Some((_, file)), Some(y)) => match kalker_creepages(file, y) {
                Ok((xi, eta, unique, note)) => {
                    if unique {
                        row.xi_percent = Some(100.0 * xi.abs());
                        row.eta_percent = Some(100.0 * eta.abs());
                    }
                    row.creepage_note = note;
                }
                Err(e) => row.creepage_note = format!("Kalker: {e}"),
            },
        }
        instants.push(row);
    }
    let onset_s = crate::analysis::lateral_onset_s(run_dir)
        .ok()
        .flatten()
        .unwrap_or(0.01);
    let first_saturation_ms = (0..t.len())
        .find(|&k| t[k] >= onset_s && ratio(k) >= SATURATION_RATIO)
        .map(|k| t[k] * 1e3);
    Ok(Some(OperatingPoint {
        case,
        instants,
        first_saturation_ms,
        saturation_searched_from_ms: onset_s * 1e3,
    }))
}

/// Patch snapshots of a run: (time s, JSON path), from their own `time_s`.
fn snapshot_times(run_dir: &Path) -> Vec<(f64, std::path::PathBuf)> {
    let Ok(entries) = std::fs::read_dir(run_dir.join("patches")) else {
        return Vec::new();
    };
    let mut out = Vec::new();
    for p in entries.filter_map(|e| e.ok().map(|e| e.path())) {
        if p.extension().is_some_and(|x| x == "json") {
            if let Ok(s) = crate::input::read_json::<crate::kalker::snapshot::PatchSnapshot>(&p) {
                out.push((s.time_s, p));
            }
        }
    }
    out
}

/// The tape circle's radius (m) of the paper's wheel, for the profiles' contact geometry.
const TAPE_CIRCLE_RADIUS_M: f64 = 0.46;

/// The wheel and rail steel of the contact geometry (E 210 GPa, nu 0.3).
fn contact_steel() -> Result<crate::kalker::Material> {
    crate::kalker::Material::validated(210e9, 0.3, "report")
}

/// The profiles' flange-contact position of the wheel (mm), from `run.json`.
fn flange_contact_wheel_y_mm(run_dir: &Path) -> Option<f64> {
    let record: serde_json::Value = crate::input::read_json(&run_dir.join("run.json")).ok()?;
    record
        .get("contact_point")?
        .get("flange_contact_wheel_y_mm")?
        .as_f64()
}

/// The wheel's tape-circle position on the rail (m) at sample `k`: the profiles' flange
/// position less the flange clearance then (both measured, see rolling::instruments).
fn wheel_y_from(flange_y_mm: Option<f64>, clearance_mm: Option<&[f64]>, k: usize) -> Option<f64> {
    match (flange_y_mm, clearance_mm) {
        (Some(f), Some(c)) if c.get(k).is_some_and(|c| c.is_finite()) => Some((f - c[k]) * 1e-3),
        _ => None,
    }
}

/// Hertz's solution on the S1002 / 54E1 profiles for a patch snapshot of `run_dir`: the
/// wheel's position at the contact-force sample nearest the snapshot, the snapshot's normal
/// force. None when the run does not record the wheel's position.
pub fn hertz_of_snapshot(
    run_dir: &Path,
    snapshot: &crate::kalker::snapshot::PatchSnapshot,
) -> Result<Option<crate::kalker::hertz::HertzContact>> {
    let table = Table::read(&run_dir.join("contact_forces.csv"))?;
    let t = table.column("time_s").unwrap_or(&[]);
    let Some(k) = (0..t.len()).min_by(|&a, &b| {
        (t[a] - snapshot.time_s)
            .abs()
            .total_cmp(&(t[b] - snapshot.time_s).abs())
    }) else {
        return Ok(None);
    };
    let clearance = table.column("flange_clearance_mm");
    let Some(wheel_y_m) = wheel_y_from(flange_contact_wheel_y_mm(run_dir), clearance, k) else {
        return Ok(None);
    };
    let contact = crate::kalker::profiles::s1002_on_54e1(wheel_y_m, TAPE_CIRCLE_RADIUS_M)?;
    crate::kalker::hertz::HertzContact::from_curvatures(
        contact.curvature_x_per_m,
        contact.curvature_y_per_m,
        snapshot.normal_force_n,
        contact_steel()?,
    )
    .map(Some)
}

/// Kalker's creepages for a snapshot on the profiles at `wheel_y_m` (tape-circle radius 0.46
/// m, spin from the snapshot's contact normal): (xi, eta, unique, note).
fn kalker_creepages(file: &Path, wheel_y_m: f64) -> Result<(f64, f64, bool, String)> {
    use crate::kalker::snapshot::{compare_snapshot_on_profiles, PatchSnapshot};
    let snapshot: PatchSnapshot = crate::input::read_json(file)?;
    let radius_m = TAPE_CIRCLE_RADIUS_M;
    let spin = snapshot.normal_lateral_fraction.unwrap_or(0.0) / radius_m;
    let material = contact_steel()?;
    let cmp = compare_snapshot_on_profiles(&snapshot, wheel_y_m, radius_m, material, 40, spin)?;
    Ok((
        cmp.kalker.creepages.xi,
        cmp.kalker.creepages.eta,
        cmp.kalker.unique,
        cmp.kalker.note.clone(),
    ))
}

/// The markdown page section for the runs' operating points.
pub fn to_markdown(points: &[(String, OperatingPoint)]) -> String {
    let mut md = String::from(
        "The paper's Table 3 (Yang & Li 2019: contact forces of its explicit FE model at the \
         instants of its patch figures, and the creepages CONTACT returns for them) beside ours: \
         forces from `contact_forces.csv` interpolated at the paper's instants, creepages from Kalker's exact \
         half-space solution (the S1002/54E1 profiles at the wheel's position then) given the \
         patch snapshot's forces and spin. Magnitudes (the paper gives no signs); creep/bound = \
         sqrt(Fx^2 + Fy^2) / (mu Fn).\n\n\
         | run | case, time (ms) | Fn (kN) paper / ours | Fy (kN) paper / ours | Fx (kN) paper / ours | creep/bound paper / ours | eta (%) paper / ours | xi (%) paper / ours |\n\
         |---|---|---|---|---|---|---|---|\n",
    );
    let pct = |v: Option<f64>| v.map_or("sat.".to_string(), |x| format!("{x:.3}"));
    let ours = |v: Option<f64>, note: &str| {
        v.map_or_else(
            || {
                if note.is_empty() {
                    "-".to_string()
                } else {
                    format!("- ({note})")
                }
            },
            |x| format!("{x:.3}"),
        )
    };
    for (name, op) in points {
        for r in &op.instants {
            let p = &r.paper;
            md.push_str(&format!(
                "| {name} | {}, {:.2} | {:.1} / {:.1} | {:.1} / {:.1} | {:.1} / {:.1} | {:.2} / {:.2} | {} / {} | {} / {} |\n",
                p.case,
                p.time_ms,
                p.normal_kn,
                r.normal_kn,
                p.lateral_kn,
                r.lateral_kn,
                p.longitudinal_kn,
                r.longitudinal_kn,
                p.creep_over_bound(),
                r.creep_over_bound,
                pct(p.eta_percent),
                ours(r.eta_percent, &r.creepage_note),
                pct(p.xi_percent),
                ours(r.xi_percent, &r.creepage_note),
            ));
        }
        if op.instants.is_empty() {
            md.push_str(&format!(
                "| {name} | {} (no Table 3 row) | | | | | | |\n",
                op.case
            ));
        }
    }
    md.push_str("\nFirst saturation (creep force >= 0.99 of the bound; paper: case 3 at about 19 ms, case 4 by 17.94 ms):\n\n");
    for (name, op) in points {
        md.push_str(&format!(
            "- {name} (case {}): {} (searched from {:.1} ms)\n",
            op.case,
            op.first_saturation_ms
                .map_or("never".to_string(), |t| format!("{t:.2} ms")),
            op.saturation_searched_from_ms
        ));
    }
    md
}
