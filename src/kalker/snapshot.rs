//! Comparison of an FE contact-patch snapshot with Kalker's theory, as the paper does with
//! CONTACT: the FE normal and creep forces go in as prescribed forces, the creepages and
//! Kalker's adhesion/slip map come out, drawn beside the FE map on the same axes and scale,
//! each with its orientation angle.
//!
//! Orientation angle of a patch solution: the angle from the rolling direction (x) of the
//! principal axis of the adhesion region, from the second moments of the adhesion points
//! (`0.5 atan2(2 Ixy, Ixx - Iyy)`, area-weighted, about their centroid). Lateral creepage
//! turns the adhesion zone, and the angle grows with it (PAPER.md).

use std::path::Path;

use serde::{Deserialize, Serialize};

use super::hertz::HertzContact;
use super::inverse::{solve_force_prescribed, ForcePrescribedResult};
use super::rolling::{Method, RollingSolver};
use super::tangential::ElementState;
use super::Material;
use crate::report::chart::{write, LineChart, Series, Stroke};
use crate::{Error, Result};

/// One slave node of an FE contact patch.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct PatchPoint {
    /// Position in the patch, rolling direction (m), relative to the patch centre.
    pub x_m: f64,
    /// Lateral position in the patch (m).
    pub y_m: f64,
    /// Contact pressure (Pa).
    pub pressure_pa: f64,
    /// True where the node slips (by the stress criterion: shear at the traction bound).
    pub slip: bool,
}

/// An FE contact-patch snapshot (what the rolling-contact simulator writes per instant).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct PatchSnapshot {
    /// Time of the snapshot (s).
    pub time_s: f64,
    /// Normal force (N).
    pub normal_force_n: f64,
    /// Longitudinal creep force on the wheel (N).
    pub force_x_n: f64,
    /// Lateral creep force on the wheel (N).
    pub force_y_n: f64,
    /// Friction coefficient.
    pub mu: f64,
    /// Lateral (y) component of the unit resultant normal force on the wheel: the sine of the
    /// contact angle. The wheel's spin `V / R` about its axle (y) projected on this normal
    /// gives the contact's spin creepage `phi = normal_lateral_fraction / R` (1/m), which
    /// `squeal kalker compare` uses when `--phi` is not given. Absent in snapshots from
    /// elsewhere (spin 0 then).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub normal_lateral_fraction: Option<f64>,
    /// Patch points.
    pub points: Vec<PatchPoint>,
}

/// Result of the comparison.
#[derive(Clone, Debug, Serialize)]
pub struct SnapshotComparison {
    /// Kalker's force-prescribed solution (creepages, uniqueness, fields).
    pub kalker: ForcePrescribedResult,
    /// Orientation angle of the FE adhesion zone (degrees from x).
    pub fe_orientation_deg: Option<f64>,
    /// Orientation angle of Kalker's adhesion zone (degrees from x).
    pub kalker_orientation_deg: Option<f64>,
    /// Adhesion area fraction of the FE patch (by point count).
    pub fe_adhesion_fraction: f64,
    /// Adhesion area fraction of Kalker's patch.
    pub kalker_adhesion_fraction: f64,
}

/// Principal-axis angle (degrees, in (-90, 90]) of a weighted point cloud; None for fewer than
/// three points or an isotropic cloud.
pub fn orientation_deg(points: &[(f64, f64, f64)]) -> Option<f64> {
    let w: f64 = points.iter().map(|p| p.2).sum();
    if points.len() < 3 || w <= 0.0 {
        return None;
    }
    let cx = points.iter().map(|p| p.0 * p.2).sum::<f64>() / w;
    let cy = points.iter().map(|p| p.1 * p.2).sum::<f64>() / w;
    let (mut ixx, mut iyy, mut ixy) = (0.0, 0.0, 0.0);
    for &(x, y, m) in points {
        ixx += m * (x - cx) * (x - cx);
        iyy += m * (y - cy) * (y - cy);
        ixy += m * (x - cx) * (y - cy);
    }
    if (ixx - iyy).abs() + ixy.abs() < 1e-30 * (ixx + iyy).max(1e-300) {
        return None;
    }
    Some(0.5 * (2.0 * ixy).atan2(ixx - iyy).to_degrees())
}

/// Compare an FE snapshot with Kalker's theory for the given contact (curvatures from the
/// profiles or the crown radii) and method. The FE forces are prescribed together with the
/// spin creepage `spin_per_m` (1/m; for a wheel rolling at a contact angle `gamma` about
/// `sin(gamma) / R`), and Kalker returns the longitudinal and lateral creepages. With spin left
/// at zero, a lateral force that the FE contact's spin produces is read as lateral creepage.
pub fn compare_snapshot(
    snapshot: &PatchSnapshot,
    hertz_curvatures_per_m: (f64, f64),
    material: Material,
    method: Method,
    elements_per_axis: usize,
    spin_per_m: f64,
) -> Result<SnapshotComparison> {
    if snapshot.points.is_empty() {
        return Err(Error::input(
            "snapshot",
            "points",
            "the FE patch has no contact points",
        ));
    }
    let hertz = HertzContact::from_curvatures(
        hertz_curvatures_per_m.0,
        hertz_curvatures_per_m.1,
        snapshot.normal_force_n,
        material,
    )?;
    let solver = RollingSolver::new(&hertz, snapshot.mu, method, elements_per_axis)?;
    let kalker = solve_force_prescribed(
        &solver,
        (hertz.semi_axis_a_m, hertz.semi_axis_b_m),
        snapshot.force_x_n,
        snapshot.force_y_n,
        spin_per_m,
    )?;
    let fe_adhesion: Vec<(f64, f64, f64)> = snapshot
        .points
        .iter()
        .filter(|p| !p.slip && p.pressure_pa > 0.0)
        .map(|p| (p.x_m, p.y_m, 1.0))
        .collect();
    let s = &kalker.solution;
    let k_adhesion: Vec<(f64, f64, f64)> = (0..s.x_m.len())
        .filter(|&k| s.state[k] == ElementState::Adhesion)
        .map(|k| (s.x_m[k], s.y_m[k], s.area_m2[k]))
        .collect();
    let loaded = snapshot
        .points
        .iter()
        .filter(|p| p.pressure_pa > 0.0)
        .count()
        .max(1);
    Ok(SnapshotComparison {
        fe_orientation_deg: orientation_deg(&fe_adhesion),
        kalker_orientation_deg: orientation_deg(&k_adhesion),
        fe_adhesion_fraction: fe_adhesion.len() as f64 / loaded as f64,
        kalker_adhesion_fraction: s.adhesion_area_fraction(),
        kalker,
    })
}

/// Draw the FE map and Kalker's map side by side on the same axes and scale (two PNG/SVG
/// pairs with identical ranges): adhesion and slip points, orientation angle in the title.
pub fn write_comparison_charts(
    snapshot: &PatchSnapshot,
    cmp: &SnapshotComparison,
    out_dir: &Path,
) -> Result<()> {
    let s = &cmp.kalker.solution;
    let mut lo = (f64::INFINITY, f64::INFINITY);
    let mut hi = (f64::NEG_INFINITY, f64::NEG_INFINITY);
    let fe_pts: Vec<&PatchPoint> = snapshot
        .points
        .iter()
        .filter(|p| p.pressure_pa > 0.0)
        .collect();
    let k_pts: Vec<usize> = (0..s.x_m.len())
        .filter(|&k| s.state[k] != ElementState::Exterior)
        .collect();
    // The FE points are in model coordinates (the patch metres away from the origin), Kalker's
    // grid about the patch centre: draw the FE points about their pressure centroid, so both
    // maps show the patch at the same scale.
    let pressure: f64 = fe_pts
        .iter()
        .map(|p| p.pressure_pa)
        .sum::<f64>()
        .max(1e-300);
    let centre = (
        fe_pts.iter().map(|p| p.x_m * p.pressure_pa).sum::<f64>() / pressure,
        fe_pts.iter().map(|p| p.y_m * p.pressure_pa).sum::<f64>() / pressure,
    );
    let fe_local = |p: &PatchPoint| (p.x_m - centre.0, p.y_m - centre.1);
    for (x, y) in fe_pts
        .iter()
        .map(|p| fe_local(p))
        .chain(k_pts.iter().map(|&k| (s.x_m[k], s.y_m[k])))
    {
        lo = (lo.0.min(x), lo.1.min(y));
        hi = (hi.0.max(x), hi.1.max(y));
    }
    let pad = 0.1 * (hi.0 - lo.0).max(hi.1 - lo.1).max(1e-6);
    let x_range = Some((1e3 * (lo.0 - pad), 1e3 * (hi.0 + pad)));
    let y_range = Some((1e3 * (lo.1 - pad), 1e3 * (hi.1 + pad)));
    let angle = |a: Option<f64>| {
        a.map(|v| format!("{v:.1} deg"))
            .unwrap_or_else(|| "n/a".into())
    };
    let map = |title: String, adhesion: Vec<(f64, f64)>, slip: Vec<(f64, f64)>| LineChart {
        title,
        x_label: "x - x_centre, rolling direction (mm)".into(),
        y_label: "y - y_centre, lateral (mm)".into(),
        series: vec![
            Series {
                label: "adhesion".into(),
                x: adhesion.iter().map(|p| 1e3 * p.0).collect(),
                y: adhesion.iter().map(|p| 1e3 * p.1).collect(),
                stroke: Stroke::Points,
                color: 0,
            },
            Series {
                label: "slip".into(),
                x: slip.iter().map(|p| 1e3 * p.0).collect(),
                y: slip.iter().map(|p| 1e3 * p.1).collect(),
                stroke: Stroke::Points,
                color: 1,
            },
        ],
        x_range,
        y_range,
        size_px: Some((720, 600)),
        ..Default::default()
    };
    let fe = map(
        format!(
            "FE, {:.2} ms: adhesion at {}",
            1e3 * snapshot.time_s,
            angle(cmp.fe_orientation_deg)
        ),
        fe_pts
            .iter()
            .filter(|p| !p.slip)
            .map(|p| fe_local(p))
            .collect(),
        fe_pts
            .iter()
            .filter(|p| p.slip)
            .map(|p| fe_local(p))
            .collect(),
    );
    let kal = map(
        format!(
            "Kalker {}: adhesion at {}{}",
            s.method.name(),
            angle(cmp.kalker_orientation_deg),
            if cmp.kalker.unique {
                ""
            } else {
                " (not unique)"
            }
        ),
        k_pts
            .iter()
            .filter(|&&k| s.state[k] == ElementState::Adhesion)
            .map(|&k| (s.x_m[k], s.y_m[k]))
            .collect(),
        k_pts
            .iter()
            .filter(|&&k| s.state[k] == ElementState::Slip)
            .map(|&k| (s.x_m[k], s.y_m[k]))
            .collect(),
    );
    write(
        &fe,
        Some(&out_dir.join("patch_fe.png")),
        Some(&out_dir.join("patch_fe.svg")),
    )?;
    write(
        &kal,
        Some(&out_dir.join("patch_kalker.png")),
        Some(&out_dir.join("patch_kalker.svg")),
    )
}
