//! Kalker's adhesion/slip map beside the FE patch's ([`crate::kalker::snapshot`]): the
//! `squeal kalker compare` charts.

use std::path::Path;

use super::chart::{write, LineChart, Series, Stroke};
use crate::kalker::snapshot::{PatchPoint, PatchSnapshot, SnapshotComparison};
use crate::kalker::tangential::ElementState;
use crate::Result;

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
