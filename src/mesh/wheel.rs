//! The wheel (and half-axle) hexahedral mesh: the cross-section is meshed with quads (an O-grid
//! for the rim under the S1002 tread, Coons patches for the web, structured blocks for the hub
//! and axle) and revolved about the axle axis. The solid axle core is an O-grid square, so no
//! element degenerates on the axis.
//!
//! Remedy for the time step: the wheel body is revolved with a
//! uniform, coarse circumferential division. When a fine contact arc is wanted, the outer rows
//! of the rim O-grid under the tread are replaced by a separately meshed *tread band*, fine in
//! the section and graded circumferentially (fine on the contact arc, growing to the body's
//! spacing elsewhere), and tied to the body by a [`TiedInterface`] that the explicit solver
//! enforces. The hub elements therefore keep the body's coarse arc length instead of shrinking
//! with the radius ratio (~0.2) of a fine arc carried through the whole section.

use std::collections::BTreeMap;
use std::f64::consts::{PI, TAU};

use serde::{Deserialize, Serialize};

use super::distribute;
use super::section::SectionMesh;
pub use super::tread_insert::TreadInsertSpec;
use super::tread_insert::{arc_within, wrap_deg, BandArc};
use super::wheel_zones::{
    column_point, mesh_axle_ring, mesh_flange, mesh_hub, mesh_tread_block, mesh_web, rim_outline,
    RimOutline, RimRows, BAND_ROWS_IN_BODY,
};
use super::{material, tie, tread_insert, Mesh, P3};
use crate::geometry::s1002;
use crate::input::wheel::{axle_radius_mm, WheelSpec};
use crate::input::Checker;
use crate::Result;

/// Fine tread band settings.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct TreadBandSpec {
    /// Element size in the band, in the section and on the fine arc (mm).
    pub element_size_mm: f64,
    /// Centre of the fine arc, angle from the bottom (contact) point, positive in the sense of
    /// rotation of a wheel rolling in +x (mm of tread arc = angle x radius), degrees.
    pub arc_centre_deg: f64,
    /// Angular width of the fine arc (degrees).
    pub arc_width_deg: f64,
    /// Ratio between neighbouring element sizes away from the arc.
    #[serde(default = "default_growth")]
    pub growth_ratio: f64,
    /// A medium circumferential size on the whole arc that rolls on the rail during a run, with
    /// the fine arc inside it (absent: the band grows from the fine arc to the body's spacing).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub running_arc: Option<RunningArcSpec>,
    /// The band's section fine only on a strip of the tread around the contact path (absent:
    /// fine across the whole tread and over the band's depth).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fine_strip: Option<FineStripSpec>,
    /// A finer block tied into the band where contact patches are resolved (absent: none); see
    /// [`TreadInsertSpec`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub insert: Option<TreadInsertSpec>,
}

/// A strip of the tread, across the rolling direction, where the band's section keeps its fine
/// size; outside it the section's elements grow by the band's `growth_ratio` up to the body's
/// size, across the tread and with depth.
///
/// Why: the contact patch of a wheel rolling on its tread covers about 20 mm of the profile
/// (about 19 mm wide at 110 kN on the 0.46 m wheel, Hertz), and with a 5 mm lateral shift the
/// contact moves by a few millimetres more; the rest of the band (flange root to field-side
/// chamfer, about 95 mm, and the body row's depth) needs no contact resolution. A band fine
/// everywhere holds three times the elements of one fine on a 40 mm strip.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct FineStripSpec {
    /// Start of the strip on the profile's S coordinate (mm, 0 at the tape circle, negative
    /// towards the flange).
    pub s_min_mm: f64,
    /// End of the strip on S (mm).
    pub s_max_mm: f64,
    /// Depth under the tread surface kept at the fine size (mm).
    pub depth_mm: f64,
}

/// The arc of the tread that rolls on the rail during a run, meshed at a medium size.
///
/// Why: the contact sees the wheel through its slave nodes, so the tread is a polygon of side
/// `L` whose centre rises and falls by the sagitta `L^2 / (8 R)` as it rolls: 88 um for the
/// 18 mm body spacing of the `paper` wheel (R = 460 mm), the same order as the Hertz approach
/// (about 0.1 mm at 110 kN), and the normal force bounces (110 to 159 kN within 0.2 ms in a
/// `paper` run before this arc existed); at 6 mm the sagitta is 10 um (demo: +-3.5 %).
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RunningArcSpec {
    /// Circumferential element size on the arc (mm), between the band size and the body size.
    pub element_size_mm: f64,
    /// Centre of the arc, degrees from the bottom point, as `arc_centre_deg`.
    pub arc_centre_deg: f64,
    /// Angular width (degrees); it must contain the fine arc.
    pub arc_width_deg: f64,
}

fn default_growth() -> f64 {
    1.15
}

impl TreadBandSpec {
    /// Validate the band settings against the wheel.
    pub fn validate(&self, source_name: &str, field: &str, wheel: &WheelSpec) -> Result<()> {
        let c = Checker { source_name };
        c.within(
            &format!("{field}.element_size_mm"),
            self.element_size_mm,
            0.2,
            wheel.mesh.element_size_mm,
        )?;
        c.within(
            &format!("{field}.arc_width_deg"),
            self.arc_width_deg,
            0.0,
            360.0,
        )?;
        c.within(
            &format!("{field}.arc_centre_deg"),
            self.arc_centre_deg,
            -360.0,
            360.0,
        )?;
        c.within(
            &format!("{field}.growth_ratio"),
            self.growth_ratio,
            1.01,
            2.0,
        )?;
        if let Some(strip) = &self.fine_strip {
            let f = format!("{field}.fine_strip");
            c.within(
                &format!("{f}.s_min_mm"),
                strip.s_min_mm,
                FLANGE_ROOT_S_MM,
                s1002::S_CHAMFER_START_MM,
            )?;
            c.within(
                &format!("{f}.s_max_mm"),
                strip.s_max_mm,
                strip.s_min_mm + self.element_size_mm,
                s1002::S_CHAMFER_START_MM,
            )?;
            c.within(
                &format!("{f}.depth_mm"),
                strip.depth_mm,
                self.element_size_mm,
                wheel.nominal_radius_mm - wheel.rim_inner_radius_mm,
            )?;
        }
        if let Some(insert) = &self.insert {
            let arc = BandArc {
                element_size_mm: self.element_size_mm,
                arc_centre_deg: self.arc_centre_deg,
                arc_width_deg: self.arc_width_deg,
                flange_root_s_mm: FLANGE_ROOT_S_MM,
            };
            insert.validate(&c, &format!("{field}.insert"), &arc)?;
        }
        if let Some(run) = &self.running_arc {
            let f = format!("{field}.running_arc");
            c.within(
                &format!("{f}.element_size_mm"),
                run.element_size_mm,
                self.element_size_mm,
                wheel.mesh.element_size_mm,
            )?;
            c.within(
                &format!("{f}.arc_width_deg"),
                run.arc_width_deg,
                self.arc_width_deg,
                350.0,
            )?;
            // Offset of the running arc's centre from the fine arc's centre.
            let offset_deg = wrap_deg(run.arc_centre_deg - self.arc_centre_deg);
            c.require(
                arc_within(
                    self.arc_centre_deg,
                    self.arc_width_deg,
                    run.arc_centre_deg,
                    run.arc_width_deg,
                ),
                &format!("{f}.arc_centre_deg"),
                || {
                    format!(
                        "the running arc ({} deg wide about {} deg) must contain the fine arc \
                         ({} deg wide about {} deg)",
                        run.arc_width_deg,
                        run.arc_centre_deg,
                        self.arc_width_deg,
                        self.arc_centre_deg
                    )
                },
            )?;
            c.require(
                offset_deg.abs() + 0.5 * run.arc_width_deg < 180.0,
                &format!("{f}.arc_width_deg"),
                || {
                    format!(
                        "the running arc must not reach the point opposite the fine arc's \
                         centre ({} deg); at most {:.1} deg wide about {} deg",
                        self.arc_centre_deg + 180.0,
                        2.0 * (180.0 - offset_deg.abs()),
                        run.arc_centre_deg
                    )
                },
            )?;
        }
        Ok(())
    }
}

/// Where the wheel sits in the global frame.
#[derive(Clone, Copy, Debug)]
pub struct WheelPlacement {
    /// Axle axis point in the plane of the tape circle (m): x along the track, y lateral, z up.
    pub tape_circle_centre_m: P3,
}

impl Default for WheelPlacement {
    fn default() -> Self {
        WheelPlacement {
            tape_circle_centre_m: [0.0, 0.0, 0.0],
        }
    }
}

/// The meshed cross-section, kept for reports and tests.
pub struct WheelSection {
    /// Body section (rim, web, hub, axle ring), (S, r) in mm.
    pub body: SectionMesh,
    /// Tread band section, if any.
    pub band: Option<SectionMesh>,
    /// The band section's columns (S, mm) and rows (fractions of the rim depth from the rim
    /// bottom, as the tread block's rows): its structured grid, for an insert.
    pub band_grid: Option<(Vec<f64>, Vec<f64>)>,
    /// Axle core parameter per body node (None: on an exact circle).
    pub axle_eta: BTreeMap<usize, f64>,
    /// Axle stations (S, mm).
    pub axle_stations_mm: Vec<f64>,
    /// Per body quad: true for the inner zone (hub, lower web, axle).
    pub quad_in_inner_zone: Vec<bool>,
}

/// Lateral position of the flange root (mm), where the tread side of the rim O-grid ends: the
/// S1002 breakpoint between the tread polynomial (B) and the flange-root polynomial (C).
pub const FLANGE_ROOT_S_MM: f64 = -26.0;

/// Fraction of the axle radius at which the O-grid core square sits (half-width).
const AXLE_CORE_ETA: f64 = 0.5;

/// Mesh the cross-section.
///
/// The zones are meshed along one outline, each reusing its neighbour's edge nodes, in the
/// order that numbers their quads: flange and tread block (the rim), hub, web, axle ring
/// (`wheel_zones.rs`); then the tread band's own section and the zones' labels.
pub fn mesh_section(spec: &WheelSpec, band: Option<&TreadBandSpec>) -> WheelSection {
    let h = spec.mesh.element_size_mm;
    let tol = 1e-7;
    let mut body = SectionMesh::new(tol);
    let s_ff = s1002::S_FIELD_FACE_MM;

    // ---- Rim: a column-mapped tread block (S from the flange root to the field face, rows
    // from the rim bottom to the S1002 profile) and an O-grid for the flange (root to back face),
    // joined along the vertical line S = FLANGE_ROOT_S_MM.
    // The band stops short of the field-side chamfer; the last body column, under the chamfer,
    // is at least one band element wide so that it does not undercut the band's time step.
    let band_end = match band {
        Some(b) => {
            s1002::S_CHAMFER_START_MM.min(s_ff - b.element_size_mm.max(s1002::FIELD_CHAMFER_MM))
        }
        None => s_ff,
    };
    let (outline, flange_side2) = rim_outline(spec, h, FLANGE_ROOT_S_MM, band_end);
    let rows = mesh_flange(&mut body, spec, h, &outline, flange_side2);
    let rim_bottom = mesh_tread_block(&mut body, spec, &outline, &rows, band.is_some());
    let rim_quads_end = body.quads.len();

    let hub_top = mesh_hub(&mut body, spec, h, outline.n_web);
    let hub_quads_end = body.quads.len();

    let (outer_quads_end, inner_quads_start) =
        mesh_web(&mut body, spec, h, &outline, &rim_bottom, &hub_top);
    // The hub was added before the rim bottom was known to the web; move its quads to the
    // inner zone by recording the ranges: [0, rim_end) rim, [rim_end, hub_end) hub.

    let (axle_eta, axle_stations_mm) =
        mesh_axle_ring(&mut body, spec, h, &hub_top.stations, AXLE_CORE_ETA);

    // ---- Tread band (separate section mesh over side 2, fine).
    let (band_section, band_grid) = match band {
        Some(b) => {
            let (m, grid) = mesh_band_section(b, spec, &outline, &rows, h, tol);
            (Some(m), Some(grid))
        }
        None => (None, None),
    };

    // Zones, by the order the quads were added: rim [0, rim_end), hub [rim_end, hub_end),
    // upper web [hub_end, inner_start), then lower web and axle. Outer = rim + upper web;
    // inner = hub + lower web + axle.
    debug_assert_eq!(outer_quads_end, hub_quads_end);
    let quad_in_inner_zone: Vec<bool> = (0..body.quads.len())
        .map(|q| q >= inner_quads_start || (rim_quads_end..hub_quads_end).contains(&q))
        .collect();
    WheelSection {
        body,
        band: band_section,
        band_grid,
        axle_eta,
        axle_stations_mm,
        quad_in_inner_zone,
    }
}

/// The tread band's own section (fine, over the flange root to the band end, on the rim's top
/// rows it replaces), with its tread and its interface to the body tagged; and its grid's
/// columns (S, mm) and rows (fractions of the rim depth from the rim bottom), for an insert.
fn mesh_band_section(
    b: &TreadBandSpec,
    spec: &WheelSpec,
    outline: &RimOutline,
    rows: &RimRows,
    h: f64,
    tol: f64,
) -> (SectionMesh, (Vec<f64>, Vec<f64>)) {
    let (root, band_end, depth) = (outline.root, outline.band_end, outline.depth);
    let mut m = SectionMesh::new(tol);
    let v_b = rows.row_v[rows.n_rows - BAND_ROWS_IN_BODY];
    let (columns_s, row_fractions) = band_stations(b, root, band_end, (1.0 - v_b) * depth, h);
    let band_grid: (Vec<f64>, Vec<f64>) = (
        columns_s.clone(),
        row_fractions
            .iter()
            .map(|f| v_b + (1.0 - v_b) * f)
            .collect(),
    );
    let (n_axial, n_band_rows) = (columns_s.len() - 1, row_fractions.len() - 1);
    let grid: Vec<Vec<[f64; 2]>> = columns_s
        .iter()
        .map(|&s| {
            row_fractions
                .iter()
                .map(|&f| column_point(spec, s, v_b + (1.0 - v_b) * f))
                .collect()
        })
        .collect();
    let ids = m.add_grid(&grid, material::TREAD_BAND);
    m.tag("tread", ids.iter().map(|col| col[n_band_rows]));
    let mut iface: Vec<usize> = ids.iter().map(|col| col[0]).collect();
    iface.extend(ids[0].iter().copied());
    iface.extend(ids[n_axial].iter().copied());
    m.tag("band_interface", iface);
    (m, band_grid)
}

/// The band section's columns (S from `root` to `band_end`, mm) and rows (fractions of the
/// band's depth `band_depth_mm`, 0 at its bottom, 1 at the tread): uniform at the band's size,
/// or with a fine strip ([`FineStripSpec`]) fine on the strip and near the surface, growing by
/// the band's ratio up to `body_size_mm` away from them.
///
/// Uniform counts are rounded down (with 10 % slack) so band elements are never much smaller
/// than the requested size: the band must set the time step, not undercut it. The graded
/// distribution rounds its count to the nearest, which keeps elements within about 10 % of the
/// size for the 5 or more intervals a band has.
fn band_stations(
    b: &TreadBandSpec,
    root: f64,
    band_end: f64,
    band_depth_mm: f64,
    body_size_mm: f64,
) -> (Vec<f64>, Vec<f64>) {
    let hb = b.element_size_mm;
    let Some(strip) = &b.fine_strip else {
        let n_axial = distribute::count_at_least(band_end - root, hb).max(2);
        let n_rows = distribute::count_at_least(band_depth_mm, hb);
        let columns = distribute::uniform(root, band_end, n_axial);
        return (columns, distribute::uniform(0.0, 1.0, n_rows));
    };
    let coarse = body_size_mm.max(hb);
    let across = distribute::graded_size(
        strip.s_min_mm - root,
        strip.s_max_mm - root,
        hb,
        coarse,
        b.growth_ratio,
    );
    let columns = distribute::by_size_function(band_end - root, across, 2)
        .into_iter()
        .map(|x| root + x)
        .collect();
    // Depth measured from the tread surface down.
    let down = distribute::graded_size(0.0, strip.depth_mm, hb, coarse, b.growth_ratio);
    let mut rows: Vec<f64> = distribute::by_size_function(band_depth_mm, down, 1)
        .into_iter()
        .map(|d| 1.0 - d / band_depth_mm)
        .collect();
    rows.reverse();
    (columns, rows)
}

/// Point of the section (S, r in mm) revolved to angle theta, in metres.
fn revolve_point(placement: &WheelPlacement, s_mm: f64, r_mm: f64, theta: f64) -> P3 {
    let c = placement.tape_circle_centre_m;
    let r = r_mm * 1e-3;
    [
        c[0] + r * theta.sin(),
        c[1] + s_mm * 1e-3,
        c[2] - r * theta.cos(),
    ]
}

/// Angular node positions of the tread band: fine on the arc, growing geometrically to the
/// body's spacing away from it; periodic (the last point, equal to the first + 2 pi, dropped).
pub fn band_angles(band: &TreadBandSpec, tread_radius_mm: f64, body_divisions: usize) -> Vec<f64> {
    let fine = band.element_size_mm / tread_radius_mm;
    let coarse = (TAU / body_divisions as f64).max(fine);
    let half = 0.5 * band.arc_width_deg.to_radians();
    // Parametrise the circle from the point opposite the arc centre, so the arc sits in the
    // middle; the running arc (validated to contain the fine arc and not to reach that point)
    // then lies inside (0, 2 pi) too.
    let running = band.running_arc.as_ref().map(|run| {
        let centre = PI + wrap_deg(run.arc_centre_deg - band.arc_centre_deg).to_radians();
        let half_run = 0.5 * run.arc_width_deg.to_radians();
        (
            centre - half_run,
            centre + half_run,
            (run.element_size_mm / tread_radius_mm).min(coarse),
        )
    });
    let size = distribute::nested_graded_size(
        (PI - half, PI + half, fine),
        running,
        coarse,
        band.growth_ratio,
    );
    let mut pos = distribute::by_size_function(TAU, size, 8);
    pos.pop();
    let start = band.arc_centre_deg.to_radians() - PI;
    pos.iter().map(|p| p + start).collect()
}

/// Build the 3D wheel mesh (see the module documentation).
pub fn wheel_mesh(
    spec: &WheelSpec,
    band: Option<&TreadBandSpec>,
    placement: &WheelPlacement,
) -> Mesh {
    let section = mesh_section(spec, band);
    let n = spec.mesh.circumferential_divisions;
    let n_inner = spec.mesh.inner_circumferential_divisions;
    let uniform_angles =
        |count: usize| -> Vec<f64> { (0..count).map(|j| TAU * j as f64 / count as f64).collect() };
    let axle_special = |id: usize, s: f64, theta: f64| {
        section
            .axle_eta
            .get(&id)
            .map(|&eta| axle_point(spec, placement, s, eta, theta))
    };
    let mut body = revolve(
        &section.body,
        &uniform_angles(n_inner),
        placement,
        |q| section.quad_in_inner_zone[q],
        axle_special,
    );
    if spec.axle.is_some() {
        add_axle_core(
            &mut body,
            spec,
            placement,
            &section.axle_stations_mm,
            n_inner,
        );
        let s = &section.axle_stations_mm;
        let y0 = placement.tape_circle_centre_m[1] + s[0] * 1e-3;
        let y1 = placement.tape_circle_centre_m[1] + s[s.len() - 1] * 1e-3;
        let inner: Vec<usize> = (0..body.nodes.len())
            .filter(|&i| (body.nodes[i][1] - y0).abs() < 1e-9)
            .collect();
        let outer: Vec<usize> = (0..body.nodes.len())
            .filter(|&i| (body.nodes[i][1] - y1).abs() < 1e-9)
            .collect();
        body.add_node_set("axle_inner_end", inner);
        body.add_node_set("axle_outer_end", outer);
    }
    body.merge_coincident_nodes(1e-9);
    body.orient_elements();
    // Outer zone (rim and upper web), tied to the inner zone along the web split line.
    let mut outer = revolve(
        &section.body,
        &uniform_angles(n),
        placement,
        |q| !section.quad_in_inner_zone[q],
        axle_special,
    );
    outer.merge_coincident_nodes(1e-9);
    outer.orient_elements();
    let inner_node_count = body.nodes.len();
    let inner_split = body.node_sets.remove("web_split").unwrap_or_default();
    body.append(outer);
    let outer_split = body.node_sets.remove("web_split").unwrap_or_default();
    let outer_split: Vec<usize> = outer_split
        .into_iter()
        .filter(|&i| i >= inner_node_count)
        .collect();
    let masters = faces_on(&body, &inner_split, |_, f| {
        f.iter().all(|&i| i < inner_node_count)
    });
    body.ties
        .push(tie::build("web_zones", &body.nodes, &outer_split, &masters));
    if let Some(band_section) = &section.band {
        let band_spec = band.expect("band section implies band spec");
        let angles = band_angles(band_spec, spec.nominal_radius_mm, n);
        let mut band_mesh = revolve(band_section, &angles, placement, |_| true, |_, _, _| None);
        // The insert's hole is cut before the band joins the body (the band's element order is
        // the swept grid's there).
        let insert = band_spec.insert.as_ref().map(|ins| {
            let grid = section.band_grid.as_ref().expect("band grid with the band");
            let place = |s: f64, r: f64, th: f64| revolve_point(placement, s, r, th);
            let centre_deg = band_spec.arc_centre_deg;
            tread_insert::cut(&mut band_mesh, ins, centre_deg, spec, grid, &angles, place)
        });
        let offset = body.nodes.len();
        body.append(band_mesh);
        body.orient_elements();
        let slaves: Vec<usize> = body
            .node_sets
            .get("band_interface")
            .cloned()
            .unwrap_or_default();
        let iface_body = body
            .node_sets
            .get("band_interface_body")
            .cloned()
            .unwrap_or_default();
        let masters = faces_on(&body, &iface_body, |e, f| {
            body.material[e] != material::TREAD_BAND && f.iter().all(|&i| i < offset)
        });
        let tie = tie::build("tread_band", &body.nodes, &slaves, &masters);
        body.ties.push(tie);
        if let Some((walls, block)) = insert {
            let walls: Vec<[usize; 4]> = walls.iter().map(|f| f.map(|n| n + offset)).collect();
            super::insert::tie_insert(&mut body, &walls, block, "tread_insert");
        }
    }
    body.surface_from_node_set("tread", "tread", None);
    body
}

/// Boundary faces of `mesh` whose nodes all lie in `set` and that pass `keep(element, face)`.
fn faces_on(
    mesh: &Mesh,
    set: &[usize],
    keep: impl Fn(usize, &[usize; 4]) -> bool,
) -> Vec<[usize; 4]> {
    let mut member = vec![false; mesh.nodes.len()];
    for &i in set {
        member[i] = true;
    }
    mesh.boundary_faces()
        .into_iter()
        .filter(|(f, e)| f.iter().all(|&i| member[i]) && keep(*e, f))
        .map(|(f, _)| f)
        .collect()
}

/// Revolve the quads of a section mesh selected by `use_quad` over the given angles
/// (periodic). `special(id, s_mm, theta)` may return a position for nodes that are not on exact
/// circles (the axle core blend). Only nodes used by the selected quads are created.
fn revolve(
    section: &SectionMesh,
    thetas: &[f64],
    placement: &WheelPlacement,
    use_quad: impl Fn(usize) -> bool,
    special: impl Fn(usize, f64, f64) -> Option<P3>,
) -> Mesh {
    let n = thetas.len();
    let mut mesh = Mesh::default();
    let mut local = vec![usize::MAX; section.nodes.len()];
    let mut used = 0usize;
    for (q, quad) in section.quads.iter().enumerate() {
        if use_quad(q) {
            for &id in quad {
                if local[id] == usize::MAX {
                    local[id] = used;
                    used += 1;
                }
            }
        }
    }
    mesh.nodes = vec![[0.0; 3]; used * n];
    for (id, p) in section.nodes.iter().enumerate() {
        if local[id] == usize::MAX {
            continue;
        }
        for (j, &theta) in thetas.iter().enumerate() {
            mesh.nodes[local[id] * n + j] = special(id, p[0], theta)
                .unwrap_or_else(|| revolve_point(placement, p[0], p[1], theta));
        }
    }
    let node = |id: usize, j: usize| local[id] * n + (j % n);
    for (q, quad) in section.quads.iter().enumerate() {
        if !use_quad(q) {
            continue;
        }
        for j in 0..n {
            mesh.elements.push(super::hex::swept(*quad, j, node));
            mesh.material.push(section.quad_part[q]);
        }
    }
    for (name, ids) in &section.tags {
        let members: Vec<usize> = ids
            .iter()
            .copied()
            .filter(|&id| local[id] != usize::MAX)
            .collect();
        if !members.is_empty() {
            mesh.add_node_set(
                name,
                members
                    .iter()
                    .flat_map(|&id| (0..n).map(move |j| node(id, j))),
            );
        }
    }
    mesh
}

/// Axle ring node: blend between the core square (eta = AXLE_CORE_ETA) and the circle (eta = 1).
fn axle_point(spec: &WheelSpec, placement: &WheelPlacement, s_mm: f64, eta: f64, theta: f64) -> P3 {
    let axle = spec.axle.as_ref().expect("axle nodes imply an axle");
    let r_axle = axle_radius_mm(&axle.profile_mm, s_mm) * 1e-3;
    let w = (eta - AXLE_CORE_ETA) / (1.0 - AXLE_CORE_ETA);
    let (sn, cs) = theta.sin_cos();
    let m = sn.abs().max(cs.abs());
    let u = r_axle * ((1.0 - w) * AXLE_CORE_ETA * sn / m + w * sn);
    let v = r_axle * ((1.0 - w) * AXLE_CORE_ETA * (-cs) / m + w * (-cs));
    let c = placement.tape_circle_centre_m;
    [c[0] + u, c[1] + s_mm * 1e-3, c[2] + v]
}

/// The solid core of the axle: a structured square grid at each axle station whose boundary
/// coincides with the ring's innermost nodes (fused afterwards by node merging).
fn add_axle_core(
    mesh: &mut Mesh,
    spec: &WheelSpec,
    placement: &WheelPlacement,
    stations_mm: &[f64],
    n: usize,
) {
    let axle = spec.axle.as_ref().expect("axle");
    let q = n / 4;
    // Square coordinates tan(theta) at the ring angles of one side (theta in [-45, 45] degrees).
    let a: Vec<f64> = (0..=q)
        .map(|i| (TAU * (i as f64 - (q / 2) as f64) / n as f64).tan())
        .collect();
    let c = placement.tape_circle_centre_m;
    let base = mesh.nodes.len();
    for &s in stations_mm {
        let half = AXLE_CORE_ETA * axle_radius_mm(&axle.profile_mm, s) * 1e-3;
        for &ai in &a {
            for &ak in &a {
                mesh.nodes
                    .push([c[0] + half * ai, c[1] + s * 1e-3, c[2] + half * ak]);
            }
        }
    }
    let id = |st: usize, i: usize, k: usize| base + st * (q + 1) * (q + 1) + i * (q + 1) + k;
    for st in 0..stations_mm.len() - 1 {
        for i in 0..q {
            for k in 0..q {
                mesh.elements.push(super::hex::structured(st, i, k, id));
                mesh.material.push(material::AXLE);
            }
        }
    }
}
