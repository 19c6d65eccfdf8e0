//! Contact-patch charts from a `patches/patch_<t>us.csv` snapshot (written by the rolling
//! simulator): the patch map with shear-stress arrows and adhesion / slip by the stress
//! criterion (shear at the traction bound), the map with micro-slip arrows and adhesion / slip
//! by the velocity criterion, and pressure, shear and traction bound `mu p` along the
//! longitudinal centre line (as the paper's patch figures). Every chart states its resolution
//! (loaded nodes along and across the patch through its centre) and its peak pressure against
//! Hertz's for the same normal force, so that a coarse mesh's map is not read as a resolved one.

use std::path::Path;

use super::chart::{write, LineChart, Series, Stroke};
use crate::kalker::hertz::HertzContact;
use crate::table::Table;
use crate::{Error, Result};

/// One node of a patch snapshot, in patch coordinates (mm, relative to the pressure centre).
struct Node {
    x_mm: f64,
    y_mm: f64,
    pressure_mpa: f64,
    shear_mpa: [f64; 2],
    slip_m_per_s: [f64; 2],
    slip_by_bound: bool,
    slip_by_velocity: bool,
}

fn read_nodes(csv: &Path) -> Result<Vec<Node>> {
    let t = Table::read_numeric(csv)?;
    let name = csv.display().to_string();
    let col = |h: &str| -> Result<&[f64]> {
        t.column(h)
            .ok_or_else(|| Error::input(&name, h, "column missing from the patch snapshot"))
    };
    let (x, y, p) = (col("x_m")?, col("y_m")?, col("pressure_pa")?);
    let (sx, sy) = (col("shear_x_pa")?, col("shear_y_pa")?);
    let (vx, vy) = (col("slip_vx_m_per_s")?, col("slip_vy_m_per_s")?);
    let (b, v) = (col("slip_by_bound")?, col("slip_by_velocity")?);
    let total: f64 = p.iter().sum();
    if x.is_empty() || total.is_nan() || total <= 0.0 {
        return Err(Error::input(
            &name,
            "pressure_pa",
            "the snapshot holds no loaded node",
        ));
    }
    // Pressure centre: the patch origin.
    let cx = x.iter().zip(p).map(|(a, w)| a * w).sum::<f64>() / total;
    let cy = y.iter().zip(p).map(|(a, w)| a * w).sum::<f64>() / total;
    Ok((0..x.len())
        .map(|k| Node {
            x_mm: (x[k] - cx) * 1e3,
            y_mm: (y[k] - cy) * 1e3,
            pressure_mpa: p[k] * 1e-6,
            shear_mpa: [sx[k] * 1e-6, sy[k] * 1e-6],
            slip_m_per_s: [vx[k], vy[k]],
            slip_by_bound: b[k] > 0.5,
            slip_by_velocity: v[k] > 0.5,
        })
        .collect())
}

/// Arrows (shaft and two head strokes) as unlabelled series; `scale` maps the vector to mm.
fn arrows(
    nodes: &[Node],
    vector: impl Fn(&Node) -> [f64; 2],
    scale: f64,
    color: usize,
) -> Vec<Series> {
    let mut out = Vec::with_capacity(nodes.len());
    for n in nodes {
        let v = vector(n);
        let (dx, dy) = (v[0] * scale, v[1] * scale);
        let len = (dx * dx + dy * dy).sqrt();
        if len.is_nan() || len <= 1e-9 {
            continue;
        }
        let (tx, ty) = (n.x_mm + dx, n.y_mm + dy);
        // Head: two strokes at +-25 degrees, a quarter of the shaft long.
        let (ux, uy) = (dx / len, dy / len);
        let h = 0.25 * len;
        let (c, s) = (25f64.to_radians().cos(), 25f64.to_radians().sin());
        let left = (tx - h * (ux * c - uy * s), ty - h * (uy * c + ux * s));
        let right = (tx - h * (ux * c + uy * s), ty - h * (uy * c - ux * s));
        out.push(Series {
            label: String::new(),
            x: vec![n.x_mm, tx, left.0, tx, right.0],
            y: vec![n.y_mm, ty, left.1, ty, right.1],
            stroke: Stroke::Solid,
            color,
        });
    }
    out
}

/// Largest vector length, for arrow scaling.
fn max_len(nodes: &[Node], vector: impl Fn(&Node) -> [f64; 2]) -> f64 {
    nodes
        .iter()
        .map(|n| {
            let v = vector(n);
            (v[0] * v[0] + v[1] * v[1]).sqrt()
        })
        .fold(0.0, f64::max)
}

/// Node spacing estimate (mm): median distance to the nearest other node.
fn spacing_mm(nodes: &[Node]) -> f64 {
    let mut d: Vec<f64> = nodes
        .iter()
        .enumerate()
        .map(|(i, a)| {
            nodes
                .iter()
                .enumerate()
                .filter(|(j, _)| *j != i)
                .map(|(_, b)| ((a.x_mm - b.x_mm).powi(2) + (a.y_mm - b.y_mm).powi(2)).sqrt())
                .fold(f64::INFINITY, f64::min)
        })
        .filter(|x| x.is_finite())
        .collect();
    d.sort_by(f64::total_cmp);
    d.get(d.len() / 2).copied().unwrap_or(1.0)
}

fn markers(nodes: &[Node], slip: impl Fn(&Node) -> bool, criterion: &str) -> Vec<Series> {
    let pick = |want: bool| -> (Vec<f64>, Vec<f64>) {
        nodes
            .iter()
            .filter(|n| slip(n) == want)
            .map(|n| (n.x_mm, n.y_mm))
            .unzip()
    };
    let (ax, ay) = pick(false);
    let (sx, sy) = pick(true);
    vec![
        Series {
            label: format!("adhesion ({criterion})"),
            x: ax,
            y: ay,
            stroke: Stroke::Points,
            color: 2,
        },
        Series {
            label: format!("slip ({criterion})"),
            x: sx,
            y: sy,
            stroke: Stroke::Points,
            color: 1,
        },
    ]
}

/// One patch map: the vector drawn as arrows and the slip criterion of the markers.
struct MapSpec {
    suffix: &'static str,
    what: &'static str,
    vector: fn(&Node) -> [f64; 2],
    slips: fn(&Node) -> bool,
    criterion: &'static str,
    arrow_label: &'static str,
}

/// Fewest nodes across a patch for its map and peak pressure to mean something (issue 24: a
/// patch resolved by at least 8 nodes across).
pub const RESOLVED_NODES_ACROSS: usize = 8;

/// How finely a snapshot resolves its patch.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PatchResolution {
    /// Loaded nodes along the rolling direction, on the row through the pressure centre.
    pub nodes_along_x: usize,
    /// Loaded nodes across, on the column through the pressure centre.
    pub nodes_across_y: usize,
    /// Median distance between neighbouring nodes (mm).
    pub node_spacing_mm: f64,
    /// Largest nodal pressure (MPa).
    pub peak_pressure_mpa: f64,
}

impl PatchResolution {
    /// The fewer of the two node counts.
    pub fn nodes_across(&self) -> usize {
        self.nodes_along_x.min(self.nodes_across_y)
    }

    /// One line: the nodes across, the peak pressure and, when given, Hertz's peak for the same
    /// normal force with the ratio.
    pub fn statement(&self, hertz_peak_mpa: Option<f64>) -> String {
        let mut s = format!(
            "{} x {} nodes across the patch, peak p {:.0} MPa",
            self.nodes_along_x, self.nodes_across_y, self.peak_pressure_mpa
        );
        if let Some(p0) = hertz_peak_mpa {
            s.push_str(&format!(
                " (Hertz p0 {p0:.0} MPa, ratio {:.2})",
                self.peak_pressure_mpa / p0
            ));
        }
        s
    }

    /// The same, short enough for a chart's axis label.
    pub fn short_statement(&self, hertz_peak_mpa: Option<f64>) -> String {
        let hertz = hertz_peak_mpa.map_or(String::new(), |p0| format!(", Hertz p0 {p0:.0} MPa"));
        format!(
            "{} x {} nodes across, peak p {:.0} MPa{hertz}",
            self.nodes_along_x, self.nodes_across_y, self.peak_pressure_mpa
        )
    }
}

/// Loaded nodes (pressure above zero) on the row and column through the pressure centre.
fn resolution(nodes: &[Node], h_mm: f64) -> PatchResolution {
    let nearest_zero = |v: &dyn Fn(&Node) -> f64| {
        nodes
            .iter()
            .map(v)
            .min_by(|a, b| a.abs().total_cmp(&b.abs()))
            .unwrap_or(0.0)
    };
    let (y_row, x_column) = (nearest_zero(&|n| n.y_mm), nearest_zero(&|n| n.x_mm));
    let loaded = |on: &dyn Fn(&Node) -> bool| {
        nodes
            .iter()
            .filter(|n| n.pressure_mpa > 0.0 && on(n))
            .count()
    };
    PatchResolution {
        nodes_along_x: loaded(&|n| (n.y_mm - y_row).abs() < 0.5 * h_mm),
        nodes_across_y: loaded(&|n| (n.x_mm - x_column).abs() < 0.5 * h_mm),
        node_spacing_mm: h_mm,
        peak_pressure_mpa: nodes.iter().map(|n| n.pressure_mpa).fold(0.0, f64::max),
    }
}

/// Writes `<stem>_shear.png|svg`, `<stem>_slip.png|svg` and `<stem>_centreline.png|svg` into
/// `out_dir` from the snapshot `csv` with friction coefficient `mu` (for the traction bound);
/// each chart states the patch's resolution and peak pressure against `hertz` (Hertz's solution
/// for the snapshot's normal force on the profiles, when known), and the centre line shows
/// Hertz's pressure beside the FE's. Returns the PNG file names and the resolution.
pub fn write_patch_maps(
    csv: &Path,
    mu: f64,
    time_ms: f64,
    hertz: Option<&HertzContact>,
    out_dir: &Path,
    stem: &str,
) -> Result<(Vec<String>, PatchResolution)> {
    let nodes = read_nodes(csv)?;
    let h = spacing_mm(&nodes);
    let patch = resolution(&nodes, h);
    let statement = patch.short_statement(hertz.map(|c| c.peak_pressure_pa * 1e-6));
    let mut files = Vec::new();
    let size = Some((900, 700));
    // The two maps: markers by a slip criterion, arrows scaled so that the longest is 1.5
    // node spacings.
    let maps = [
        MapSpec {
            suffix: "shear",
            what: "shear stress, adhesion / slip by stress",
            vector: |n| n.shear_mpa,
            slips: |n| n.slip_by_bound,
            criterion: "shear at mu p",
            arrow_label: "shear stress (longest {} MPa)",
        },
        MapSpec {
            suffix: "slip",
            what: "micro-slip, adhesion / slip by velocity",
            vector: |n| n.slip_m_per_s,
            slips: |n| n.slip_by_velocity,
            criterion: "micro-slip",
            arrow_label: "micro-slip velocity (longest {} m/s)",
        },
    ];
    for MapSpec {
        suffix,
        what,
        vector,
        slips,
        criterion,
        arrow_label,
    } in maps
    {
        let longest = max_len(&nodes, vector).max(1e-12);
        let mut series = markers(&nodes, slips, criterion);
        series.extend(arrows(&nodes, vector, 1.5 * h / longest, 0));
        if let Some(s) = series.get_mut(2) {
            s.label = arrow_label.replace("{}", &format!("{longest:.3}"));
        }
        let name = format!("{stem}_{suffix}");
        write(
            &LineChart {
                title: format!("Contact patch at {time_ms:.1} ms: {what}"),
                x_label: format!("x, rolling (mm); {statement}"),
                y_label: "y, lateral (mm)".into(),
                series,
                size_px: size,
                stroke_width: Some(1),
                ..Default::default()
            },
            Some(&out_dir.join(format!("{name}.png"))),
            Some(&out_dir.join(format!("{name}.svg"))),
        )?;
        files.push(format!("{name}.png"));
    }
    // Centre line: the row of nodes closest to y = 0.
    let y_row = nodes
        .iter()
        .map(|n| n.y_mm)
        .min_by(|a, b| a.abs().total_cmp(&b.abs()))
        .unwrap_or(0.0);
    let mut row: Vec<&Node> = nodes
        .iter()
        .filter(|n| (n.y_mm - y_row).abs() < 0.5 * h)
        .collect();
    row.sort_by(|a, b| a.x_mm.total_cmp(&b.x_mm));
    let x: Vec<f64> = row.iter().map(|n| n.x_mm).collect();
    let line = |label: &str, y: Vec<f64>, color: usize| Series {
        label: label.into(),
        x: x.clone(),
        y,
        stroke: Stroke::SolidWithPoints,
        color,
    };
    let name = format!("{stem}_centreline");
    let mut series = vec![
        line(
            "pressure p",
            row.iter().map(|n| n.pressure_mpa).collect(),
            0,
        ),
        line(
            "shear |tau|",
            row.iter()
                .map(|n| n.shear_mpa[0].hypot(n.shear_mpa[1]))
                .collect(),
            1,
        ),
        line(
            &format!("traction bound mu p (mu = {mu:.2})"),
            row.iter().map(|n| mu * n.pressure_mpa).collect(),
            2,
        ),
    ];
    if let Some(c) = hertz {
        // Hertz's pressure along x through the centre, sampled finely.
        let a_mm = c.semi_axis_a_m * 1e3;
        let xs: Vec<f64> = (0..=100)
            .map(|i| -a_mm + 2.0 * a_mm * i as f64 / 100.0)
            .collect();
        series.push(Series {
            label: format!("Hertz p (a = {a_mm:.2} mm)"),
            y: xs
                .iter()
                .map(|&x| c.pressure_pa(x * 1e-3, 0.0) * 1e-6)
                .collect(),
            x: xs,
            stroke: Stroke::Solid,
            color: 3,
        });
    }
    write(
        &LineChart {
            title: format!("Patch centre line at {time_ms:.1} ms (y = {y_row:.1} mm)"),
            x_label: format!("x, rolling (mm); {statement}"),
            y_label: "stress (MPa)".into(),
            series,
            size_px: size,
            ..Default::default()
        },
        Some(&out_dir.join(format!("{name}.png"))),
        Some(&out_dir.join(format!("{name}.svg"))),
    )?;
    files.push(format!("{name}.png"));
    Ok((files, patch))
}
