//! The zones of the wheel body's cross-section (flange, tread block, hub, web, axle ring), one
//! phase each of [`super::wheel::mesh_section`]. The zones are meshed along one outline, each
//! reusing its neighbour's edge nodes: what they share travels as small values ([`RimOutline`]
//! for the rim's stations, [`RimRows`] for its rows, [`HubTop`] for the hub's edge under the
//! web), in the order the zones are added to the section mesh (which numbers their quads).

use std::collections::BTreeMap;

use super::distribute;
use super::material;
use super::section::{OGrid, Polyline, SectionMesh};
use crate::geometry::s1002;
use crate::input::wheel::{axle_radius_mm, WheelSpec};

/// Rows of the rim's tread block that a tread band replaces.
pub(super) const BAND_ROWS_IN_BODY: usize = 1;

/// The rim's bottom stations and where the zones meet along them.
pub(super) struct RimOutline {
    /// Rim depth from the rim bottom to the tape circle (mm).
    pub(super) depth: f64,
    /// Lateral position of the flange root (S, mm), where the flange O-grid and the tread
    /// block meet.
    pub(super) root: f64,
    /// Where the tread band ends (S, mm; the field face without a band).
    pub(super) band_end: f64,
    /// Bottom stations of the whole rim (S, mm).
    pub(super) bottom_s: Vec<f64>,
    /// Index of the flange root among the bottom stations.
    pub(super) i_root: usize,
    /// Index of the web's left face among the bottom stations.
    pub(super) i_web_left: usize,
    /// Index of the band end among the bottom stations.
    pub(super) i_band_end: usize,
    /// Bottom intervals across the web.
    pub(super) n_web: usize,
}

/// The rim's rows, shared by the flange O-grid's root line, the tread block and the band.
pub(super) struct RimRows {
    /// Row fractions of the rim depth from the rim bottom (0) to the tread (1).
    pub(super) row_v: Vec<f64>,
    /// Row intervals.
    pub(super) n_rows: usize,
}

/// The hub's top edge, on which the web stands.
pub(super) struct HubTop {
    /// The hub's columns (S, mm), the web footprint's included; the axle's stations under the
    /// hub.
    pub(super) stations: Vec<f64>,
    /// Left end of the web footprint (S, mm).
    pub(super) left_end: f64,
    /// Right end of the web footprint (S, mm).
    pub(super) right_start: f64,
}

/// Point of a tread-block column at S = `s` and fraction `v` of the way from the rim bottom to
/// the tread.
pub(super) fn column_point(spec: &WheelSpec, s: f64, v: f64) -> [f64; 2] {
    let r_in = spec.rim_inner_radius_mm;
    [s, r_in + v * (spec.tread_radius_mm(s) - r_in)]
}

/// The rim's bottom stations (with the web faces, the flange root `root` and the band end as
/// nodes) and the flange profile, O-grid side 2. Under the flange the stations are denser, so
/// that the O-grid's bottom matches its profile side.
pub(super) fn rim_outline(
    spec: &WheelSpec,
    h: f64,
    root: f64,
    band_end: f64,
) -> (RimOutline, Polyline) {
    let r_nom = spec.nominal_radius_mm;
    let r_in = spec.rim_inner_radius_mm;
    let (s_fb, s_ff) = (s1002::S_FLANGE_BACK_MM, s1002::S_FIELD_FACE_MM);
    let (web_rim_centre, web_rim_thickness) = spec.web_at(1.0);
    let depth = r_nom - r_in;
    let r_top = |s: f64| spec.tread_radius_mm(s);
    let web_left = web_rim_centre - 0.5 * web_rim_thickness;
    let web_right = web_rim_centre + 0.5 * web_rim_thickness;
    // Flange profile (O-grid side 2): from the root over the flange face, tip and back arc to
    // the top of the back face.
    let dense = 0.02;
    let mut profile_pts = Vec::new();
    let mut s = root;
    while s > s_fb {
        profile_pts.push([s, r_top(s)]);
        s -= if s < -60.0 { dense * 0.25 } else { dense };
    }
    profile_pts.push([s_fb, r_top(s_fb)]);
    let flange_side2 = Polyline::new(profile_pts);
    // Bottom stations of the whole rim, with the web junction and the flange root as nodes;
    // under the flange they are denser so the O-grid's bottom matches its profile side.
    let h_under_flange = h.min((root - s_fb) / (flange_side2.length() / h).ceil());
    let mut breaks = vec![s_fb, web_left, root, web_right, band_end, s_ff];
    breaks.sort_by(|a, b| a.total_cmp(b));
    breaks.dedup_by(|a, b| (*a - *b).abs() < 1e-6);
    let mut bottom_s = vec![s_fb];
    for w in breaks.windows(2) {
        let size = if w[1] <= root + 1e-9 {
            h_under_flange
        } else {
            h
        };
        let n = (((w[1] - w[0]) / size).round() as usize).max(1);
        for i in 1..=n {
            bottom_s.push(w[0] + (w[1] - w[0]) * i as f64 / n as f64);
        }
    }
    let index_of = |s: f64| {
        bottom_s
            .iter()
            .position(|&v| (v - s).abs() < 1e-6)
            .expect("breakpoint is a station")
    };
    let (i_root, i_web_left, i_web_right, i_band_end) = (
        index_of(root),
        index_of(web_left),
        index_of(web_right),
        index_of(band_end),
    );
    let n_web = i_web_right - i_web_left;
    let outline = RimOutline {
        depth,
        root,
        band_end,
        bottom_s,
        i_root,
        i_web_left,
        i_band_end,
        n_web,
    };
    (outline, flange_side2)
}

/// The flange: an O-grid between the rim bottom, the root line, the flange profile
/// (`flange_side2`) and the back face, whose profile side is tagged as tread (contact-capable).
/// Returns the rim's rows, set by the longer of the root line and the back face.
pub(super) fn mesh_flange(
    body: &mut SectionMesh,
    spec: &WheelSpec,
    h: f64,
    outline: &RimOutline,
    flange_side2: Polyline,
) -> RimRows {
    let r_nom = spec.nominal_radius_mm;
    let r_in = spec.rim_inner_radius_mm;
    let s_fb = s1002::S_FLANGE_BACK_MM;
    let (root, depth) = (outline.root, outline.depth);
    let r_top = |s: f64| spec.tread_radius_mm(s);
    // Flange O-grid sides (counter-clockwise): bottom, root line, profile, back face.
    let flange_side3 = Polyline::segment([s_fb, r_top(s_fb)], [s_fb, r_in]);
    let flange_side1 = Polyline::segment([root, r_in], [root, r_top(root)]);
    let n_rows = ((flange_side1.length().max(flange_side3.length()) / h).ceil() as usize).max(2);
    let row_v = distribute::uniform(0.0, 1.0, n_rows);
    let flange_bottom: Vec<f64> = outline.bottom_s[..=outline.i_root]
        .iter()
        .map(|&s| (s - s_fb) / (root - s_fb))
        .collect();
    let n_flange_bottom = flange_bottom.len() - 1;
    let flange = OGrid {
        sides: [
            Polyline::segment([s_fb, r_in], [root, r_in]),
            flange_side1,
            flange_side2,
            flange_side3,
        ],
        core: [
            [s_fb + 8.0, r_in + 0.2 * depth],
            [root - 8.0, r_in + 0.2 * depth],
            [root - 8.0, r_nom - 0.12 * depth],
            [s_fb + 8.0, r_nom - 0.03 * depth],
        ],
        side_fractions: [
            flange_bottom,
            row_v.clone(),
            distribute::uniform(0.0, 1.0, n_flange_bottom),
            distribute::uniform(0.0, 1.0, n_rows),
        ],
        ring_fractions: std::array::from_fn(|_| {
            distribute::uniform(0.0, 1.0, ((10.0 / h).round() as usize).max(1))
        }),
    };
    let og = flange.mesh(body, material::WHEEL, |_, _, _| false);
    // Contact-capable flange surface: side 2 (face, tip, back arc).
    let a2 = og.side_start[2];
    let a3 = og.side_start[3];
    body.tag("tread", (a2..=a3).map(|i| og.ring[i][0]));
    RimRows { row_v, n_rows }
}

/// The tread block from the flange root to the field face (columns at the rim's bottom
/// stations, rows at the rim's rows) and the rim bottom's nodes. With a band (`with_band`) the
/// block's top rows up to the band end are left to the band, and the interface the band is
/// tied to is tagged; without, the block's top is the tread. Returns the rim bottom's node ids.
pub(super) fn mesh_tread_block(
    body: &mut SectionMesh,
    spec: &WheelSpec,
    outline: &RimOutline,
    rows: &RimRows,
    with_band: bool,
) -> Vec<usize> {
    let r_in = spec.rim_inner_radius_mm;
    let root = outline.root;
    let (row_v, n_rows) = (&rows.row_v, rows.n_rows);
    // Tread block: columns at the bottom stations, rows at fractions of the rim depth.
    let tread_columns: Vec<f64> = outline.bottom_s[outline.i_root..].to_vec();
    let tread_grid: Vec<Vec<[f64; 2]>> = tread_columns
        .iter()
        .map(|&s| row_v.iter().map(|&v| column_point(spec, s, v)).collect())
        .collect();
    // With a band, the band replaces the top rows between the flange root and the chamfer;
    // the chamfer column (45-degree top) stays in the body so that no sheared band element
    // undercuts the intended contact-zone size.
    let keep_rows = if with_band {
        n_rows - BAND_ROWS_IN_BODY
    } else {
        n_rows
    };
    let split = outline.i_band_end - outline.i_root;
    let body_grid: Vec<Vec<[f64; 2]>> = tread_grid[..=split]
        .iter()
        .map(|col| col[..=keep_rows].to_vec())
        .collect();
    let tread_ids = body.add_grid(&body_grid, material::WHEEL);
    let chamfer_ids = body.add_grid(&tread_grid[split..], material::WHEEL);
    body.tag("tread", chamfer_ids.iter().map(|col| col[n_rows]));
    if !with_band {
        body.tag("tread", tread_ids.iter().map(|col| col[n_rows]));
    } else {
        let mut iface: Vec<usize> = tread_ids.iter().map(|col| col[keep_rows]).collect();
        // The root line and the chamfer column's side above the interface row.
        iface.extend(
            (keep_rows..=n_rows).map(|k| body.add_node(column_point(spec, root, row_v[k]))),
        );
        iface.extend(chamfer_ids[0][keep_rows..].iter().copied());
        body.tag("band_interface_body", iface);
    }
    outline
        .bottom_s
        .iter()
        .map(|&s| body.add_node([s, r_in]))
        .collect()
}

/// The hub: a structured rectangle with the web footprint (`n_web` intervals, as on the rim)
/// on its top edge; its bore is tagged. Returns the hub's top edge for the web and the axle.
pub(super) fn mesh_hub(body: &mut SectionMesh, spec: &WheelSpec, h: f64, n_web: usize) -> HubTop {
    let (web_hub_centre, web_hub_thickness) = spec.web_at(0.0);
    // ---- Hub: structured rectangle with the web footprint on its top edge.
    let hub = &spec.hub;
    let hub_left_end = web_hub_centre - 0.5 * web_hub_thickness;
    let hub_right_start = web_hub_centre + 0.5 * web_hub_thickness;
    let mut hub_stations = distribute::uniform(
        hub.s_min_mm,
        hub_left_end,
        ((hub_left_end - hub.s_min_mm) / h).round().max(1.0) as usize,
    );
    hub_stations.pop();
    hub_stations.extend(distribute::uniform(hub_left_end, hub_right_start, n_web));
    hub_stations.pop();
    hub_stations.extend(distribute::uniform(
        hub_right_start,
        hub.s_max_mm,
        ((hub.s_max_mm - hub_right_start) / h).round().max(1.0) as usize,
    ));
    let hub_rows = distribute::uniform(
        hub.bore_radius_mm,
        hub.outer_radius_mm,
        ((hub.outer_radius_mm - hub.bore_radius_mm) / h)
            .round()
            .max(1.0) as usize,
    );
    let hub_grid: Vec<Vec<[f64; 2]>> = hub_stations
        .iter()
        .map(|&s| hub_rows.iter().map(|&r| [s, r]).collect())
        .collect();
    let hub_ids = body.add_grid(&hub_grid, material::WHEEL);
    body.tag("hub_bore", hub_ids.iter().map(|col| col[0]));
    HubTop {
        stations: hub_stations,
        left_end: hub_left_end,
        right_start: hub_right_start,
    }
}

/// The web: a Coons patch between the hub's top (the web footprint) and the rim bottom's
/// nodes (`rim_bottom`), split at the zone boundary row into an upper part (outer zone) and a
/// lower part (inner zone), the split row tagged. Returns the quad counts before each part:
/// where the outer web starts and where the inner zone starts.
pub(super) fn mesh_web(
    body: &mut SectionMesh,
    spec: &WheelSpec,
    h: f64,
    outline: &RimOutline,
    rim_bottom: &[usize],
    hub_top: &HubTop,
) -> (usize, usize) {
    let hub = &spec.hub;
    let r_in = spec.rim_inner_radius_mm;
    let (hub_left_end, hub_right_start) = (hub_top.left_end, hub_top.right_start);
    let (n_left, n_web) = (outline.i_web_left, outline.n_web);
    // ---- Web: Coons patch between the hub top and the rim bottom.
    let n_vertical = (((r_in - hub.outer_radius_mm) / h).round() as usize).max(1);
    let web_side = |sign: f64| -> Vec<[f64; 2]> {
        (0..=n_vertical)
            .map(|j| {
                let t = j as f64 / n_vertical as f64;
                let (c, th) = spec.web_at(t);
                [
                    c + sign * 0.5 * th,
                    hub.outer_radius_mm + t * (r_in - hub.outer_radius_mm),
                ]
            })
            .collect()
    };
    let web_bottom: Vec<[f64; 2]> = (0..=n_web)
        .map(|i| {
            [
                hub_left_end + (hub_right_start - hub_left_end) * i as f64 / n_web as f64,
                hub.outer_radius_mm,
            ]
        })
        .collect();
    let web_top: Vec<[f64; 2]> = rim_bottom[n_left..=n_left + n_web]
        .iter()
        .map(|&id| body.nodes[id])
        .collect();
    let web_grid =
        super::section::coons_patch(&web_bottom, &web_top, &web_side(-1.0), &web_side(1.0));
    // Split the web at the zone boundary (the row nearest to the requested fraction).
    let split_row = ((spec.mesh.web_split_fraction * n_vertical as f64).round() as usize)
        .clamp(1, n_vertical.max(2) - 1)
        .min(n_vertical);
    let outer_quads_end = body.quads.len();
    let upper: Vec<Vec<[f64; 2]>> = web_grid
        .iter()
        .map(|col| col[split_row..].to_vec())
        .collect();
    body.add_grid(&upper, material::WHEEL);
    let inner_quads_start = body.quads.len();
    let lower: Vec<Vec<[f64; 2]>> = web_grid
        .iter()
        .map(|col| col[..=split_row].to_vec())
        .collect();
    let lower_ids = body.add_grid(&lower, material::WHEEL);
    body.tag("web_split", lower_ids.iter().map(|col| col[split_row]));
    (outer_quads_end, inner_quads_start)
}

/// The axle ring outside the O-grid core square (from `core_eta` of the axle radius to the
/// surface), structured in (S, eta), with the hub's stations under the hub (`hub_stations`) so
/// that the hub bore and the wheel seat share their nodes. Returns the eta of each ring node
/// not on the axle surface (the 3D revolve places those between square and circle) and the
/// axle's stations (S, mm); both empty without an axle.
pub(super) fn mesh_axle_ring(
    body: &mut SectionMesh,
    spec: &WheelSpec,
    h: f64,
    hub_stations: &[f64],
    core_eta: f64,
) -> (BTreeMap<usize, f64>, Vec<f64>) {
    let hub = &spec.hub;
    // ---- Axle ring (outside the core square), structured in (S, eta).
    let mut axle_eta = BTreeMap::new();
    let mut axle_stations_mm = Vec::new();
    if let Some(axle) = &spec.axle {
        let p = &axle.profile_mm;
        let (s_start, s_end) = (p[0][0], p[p.len() - 1][0]);
        let mut stations = distribute::uniform(
            s_start,
            hub.s_min_mm,
            ((hub.s_min_mm - s_start) / (1.5 * h)).round().max(1.0) as usize,
        );
        stations.pop();
        stations.extend(hub_stations.iter().copied());
        stations.pop();
        stations.extend(distribute::uniform(
            hub.s_max_mm,
            s_end,
            ((s_end - hub.s_max_mm) / h).round().max(1.0) as usize,
        ));
        let radial = core_eta * hub.bore_radius_mm;
        let etas = distribute::uniform(core_eta, 1.0, ((radial / h).round() as usize).max(1));
        let mut grid = Vec::new();
        for &s in &stations {
            let r_axle = axle_radius_mm(p, s);
            grid.push(
                etas.iter()
                    .map(|&eta| [s, eta * r_axle])
                    .collect::<Vec<_>>(),
            );
        }
        let ids = body.add_grid(&grid, material::AXLE);
        for col in &ids {
            for (k, &id) in col.iter().enumerate() {
                if k + 1 < etas.len() {
                    axle_eta.insert(id, etas[k]);
                }
            }
        }
        axle_stations_mm = stations;
    }
    (axle_eta, axle_stations_mm)
}
