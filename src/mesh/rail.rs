//! Quad mesh of the 54E1 rail section (section coordinates y, z in mm, crown top at the origin,
//! upright; the 1:40 inclination is applied by the track placement).
//!
//! Blocks: the head is an O-grid (its outline is smooth all round, so a ring of quads around a
//! core rectangle avoids degenerate corners), graded towards the running surface; the web is a
//! Coons patch; the foot is column-mapped between its bottom and top outlines (both graphs of y,
//! fillets included). The web-foot junction is a parabola that meets the R16 fillets at right
//! angles.

use super::distribute;
use super::section::{coons_patch, geometric_fractions, OGrid, OGridNodes, Polyline, SectionMesh};
use crate::geometry::curve2d::{sample_chain, Segment, P2};
use crate::geometry::rail54e1;

/// Rail section mesh settings (mm).
#[derive(Clone, Copy, Debug)]
pub struct RailSectionSizes {
    /// Element size on the running surface (crown) and in the outer rows of the head.
    pub running_surface_mm: f64,
    /// Element size in the web and foot.
    pub body_mm: f64,
    /// Fewest rows in the running band (1 unless an insert needs a row under it: the insert
    /// leaves the band's bottom row, which is tied to the head, in place).
    pub band_rows_at_least: usize,
}

/// Half-width of the finely meshed crown band (mm): wheel contact on the paper's cases stays
/// well inside it (patch semi-axis ~5 mm, lateral shifts of a few mm).
pub const CROWN_BAND_HALF_WIDTH_MM: f64 = 15.0;
/// With a tied running band the band covers the whole crown (R300 and R80 arcs end at
/// |y| = 24.86 mm), which also balances the head O-grid's sides.
pub const BANDED_CROWN_HALF_WIDTH_MM: f64 = 24.5;
const HEAD_CORE_HALF_WIDTH_MM: f64 = 20.0;
const HEAD_CORE_BOTTOM_Z_MM: f64 = -29.0;
const HEAD_CORE_TOP_Z_MM: f64 = -10.0;

/// Height of the straight head-web junction (mm), on the R22 fillet arc.
const HEAD_JUNCTION_Z_MM: f64 = -52.0;
/// Angle below the horizontal, on the R16 web-foot fillet, of the web-foot junction point.
const FOOT_JUNCTION_ANGLE_DEG: f64 = 30.0;

fn mirror(p: P2) -> P2 {
    [-p[0], p[1]]
}

fn reversed(p: &Polyline, s0: f64, s1: f64, mirror_it: bool) -> Polyline {
    let part = p.slice(s0, s1);
    let n = 2000;
    let mut pts: Vec<P2> = (0..=n)
        .map(|i| part.at_fraction(1.0 - i as f64 / n as f64))
        .collect();
    if mirror_it {
        pts.iter_mut().for_each(|q| *q = mirror(*q));
    }
    Polyline::new(pts)
}

fn mirrored(p: &Polyline) -> Polyline {
    let n = 2000;
    Polyline::new(
        (0..=n)
            .map(|i| mirror(p.at_fraction(i as f64 / n as f64)))
            .collect(),
    )
}

/// The meshed rail section: the body and, when the running surface is finer than the body,
/// a fine running band over the crown (tied to the body by the track builder).
pub struct RailSection {
    /// Head, web and foot at the body size. Tags: `running_surface` (contact-capable outline
    /// nodes: crown when there is no band, gauge corners and side faces), `foot_bottom`, and with
    /// a band `band_interface_body`.
    pub body: SectionMesh,
    /// Running band over the crown (tags `running_surface`, `band_interface`).
    pub band: Option<SectionMesh>,
    /// The band's map from grid parameters to section points, for an insert.
    pub band_map: Option<RailBandMap>,
}

/// The running band's structured grid: column `i` at fraction `i / columns` along the crown
/// (from the field side, `y = +BANDED_CROWN_HALF_WIDTH_MM`, to the gauge side), row `k` at ring
/// fraction `ring_fraction * k / rows` under it (row 0 on the running surface).
pub struct RailBandMap {
    head: OGrid,
    /// Column cells.
    pub columns: usize,
    /// Row cells.
    pub rows: usize,
    /// Ring fraction of the band's bottom.
    pub ring_fraction: f64,
    /// The band's depth at the crown's centre (mm).
    pub depth_mm: f64,
    /// Length of the crown along the band (mm).
    pub width_mm: f64,
}

impl RailBandMap {
    /// Section point (y, z in mm) at fraction `t` along the crown and ring fraction `s`.
    pub fn point(&self, t: f64, s: f64) -> P2 {
        self.head.point(2, t, s)
    }
}

/// Build the rail section mesh (see [`RailSection`]).
///
/// Why a band: in an O-grid the core's cells are as many as the outline nodes of the opposite
/// sides, so a crown meshed at the running-surface size would leave core cells about half that
/// size and halve the explicit time step. As for the wheel tread, the fine crown layer is meshed
/// on its own and tied; the head keeps the body size.
///
/// The head, web and foot blocks are meshed along one outline (`RailOutline`), each reusing
/// its neighbour's edge nodes: the head O-grid first (its underside's junction nodes are the
/// web's top), the crown band, the foot (its junction nodes are the web's bottom), then the web
/// between them.
pub fn rail_section(sizes: RailSectionSizes) -> RailSection {
    let sizing = RailSizing::new(&sizes);
    let outline = RailOutline::new(sizing.crown_half);
    let mut mesh = SectionMesh::new(1e-7);
    let head = head_grid(&outline, &sizing);
    let og = mesh_head(&mut mesh, &head.grid, sizing.banded);
    let mut band_map = None;
    let band = sizing.banded.then(|| {
        let (band, map) = mesh_crown_band(&mut mesh, &head.grid, &og, &sizes);
        band_map = Some(map);
        band
    });
    let junction_nodes: Vec<P2> = (0..=head.n_junction)
        .map(|i| og.ring[og.side_start[0] + head.n_under + i][0])
        .map(|id| mesh.nodes[id])
        .collect();
    let foot_junction_nodes = mesh_foot(&mut mesh, &outline, sizing.h_body, head.n_junction);
    mesh_web(
        &mut mesh,
        &outline,
        sizing.h_body,
        &foot_junction_nodes,
        &junction_nodes,
    );
    mesh.remove_unused_nodes();
    // Smooth the body; nodes on the band interface stay put (they are boundary nodes of the
    // body once the band's cells are left out).
    mesh.smooth(20);
    let head = head.grid;
    let band_map = band_map.map(
        |(columns, rows, ring_fraction, depth_mm, width_mm)| RailBandMap {
            head,
            columns,
            rows,
            ring_fraction,
            depth_mm,
            width_mm,
        },
    );
    RailSection {
        body: mesh,
        band,
        band_map,
    }
}

/// The element sizes of a section and whether it gets a running band.
struct RailSizing {
    /// Element size on the running surface (mm).
    h_fine: f64,
    /// Element size of the body (mm), at least the running surface's.
    h_body: f64,
    /// Whether the crown is a separately meshed, tied band.
    banded: bool,
    /// Half-width of the crown band, the head O-grid's side 2 (mm).
    crown_half: f64,
}

impl RailSizing {
    /// The body size (never finer than the running surface) and the band decision.
    fn new(sizes: &RailSectionSizes) -> Self {
        let h_fine = sizes.running_surface_mm;
        let h_body = sizes.body_mm.max(h_fine);
        // A band pays off once the body is clearly coarser than the running surface.
        let banded = h_body >= 1.5 * h_fine;
        let crown_half = if banded {
            BANDED_CROWN_HALF_WIDTH_MM
        } else {
            CROWN_BAND_HALF_WIDTH_MM
        };
        RailSizing {
            h_fine,
            h_body,
            banded,
            crown_half,
        }
    }
}

/// The left half of the 54E1 outline as one polyline and the key points along it where the
/// blocks meet (arc lengths from the crown centre, mm).
struct RailOutline {
    /// The sampled left half, from the crown centre round to the foot's centre.
    chain: Polyline,
    /// The straight head-web junction's left end.
    head_junction: P2,
    /// The web-foot junction point on the R16 fillet.
    foot_junction: P2,
    /// End of the crown band.
    s_side_top: f64,
    /// Middle of the gauge corner arc.
    s_head_corner: f64,
    /// The head-web junction.
    s_head_junction: f64,
    /// The web-foot junction.
    s_foot_junction: f64,
    /// Top of the foot's edge.
    s_edge_top: f64,
    /// Bottom of the foot's edge.
    s_edge_bottom: f64,
}

impl RailOutline {
    /// Samples the outline and locates the key points, the crown band ending at
    /// `y = -crown_half`.
    fn new(crown_half: f64) -> Self {
        let segs = rail54e1::left_half_segments();
        let chain = Polyline::new(sample_chain(&segs, 0.01));
        let arc_mid = |seg: &Segment| seg.point_at(0.5);
        // Key points on the left half (indices follow rail54e1::left_half_segments).
        // O-grid anchors at y = -/+ CROWN_BAND_HALF_WIDTH_MM on the crown: side 2 (the fine side)
        // is only the crown band where wheel contact happens; the gauge corners and side faces
        // belong to sides 1 and 3, which are coarser. This keeps the core cells (whose count is
        // tied to the fine side's) at least one running-surface element wide.
        let p_side_top = [
            -crown_half,
            rail54e1::top_surface_z_mm(-crown_half).unwrap_or(0.0),
        ];
        let p_head_corner = arc_mid(&segs[4]);
        let head_junction = {
            if let Segment::Arc { centre, radius, .. } = segs[7] {
                let dz = HEAD_JUNCTION_Z_MM - centre[1];
                [
                    centre[0] + (radius * radius - dz * dz).sqrt(),
                    HEAD_JUNCTION_Z_MM,
                ]
            } else {
                unreachable!("segment 7 is the R22 arc")
            }
        };
        let foot_junction = {
            if let Segment::Arc { centre, radius, .. } = segs[9] {
                let a = -FOOT_JUNCTION_ANGLE_DEG.to_radians();
                [centre[0] + radius * a.cos(), centre[1] + radius * a.sin()]
            } else {
                unreachable!("segment 9 is the R16 arc")
            }
        };
        let s_side_top = chain.length_at_nearest(p_side_top);
        let s_head_corner = chain.length_at_nearest(p_head_corner);
        let s_head_junction = chain.length_at_nearest(head_junction);
        let s_foot_junction = chain.length_at_nearest(foot_junction);
        let s_edge_top = chain.length_at_nearest(segs[14].start());
        let s_edge_bottom = chain.length_at_nearest(segs[14].end());
        RailOutline {
            chain,
            head_junction,
            foot_junction,
            s_side_top,
            s_head_corner,
            s_head_junction,
            s_foot_junction,
            s_edge_top,
            s_edge_bottom,
        }
    }
}

/// The head O-grid and the node counts of its underside, which the web reuses.
struct HeadGrid {
    /// The O-grid (sides, core, fractions).
    grid: OGrid,
    /// Intervals of each fillet half of the underside (side 0).
    n_under: usize,
    /// Intervals of the straight head-web junction, the web's width in cells.
    n_junction: usize,
}

/// The head O-grid: its four sides cut from the outline (underside, gauge corner, crown band,
/// side face), their node counts, and the ring rows graded under the running surface.
fn head_grid(outline: &RailOutline, sizing: &RailSizing) -> HeadGrid {
    let chain = &outline.chain;
    let (s_side_top, s_head_corner, s_head_junction) = (
        outline.s_side_top,
        outline.s_head_corner,
        outline.s_head_junction,
    );
    let head_junction = outline.head_junction;
    let (h_fine, h_body, banded, crown_half) = (
        sizing.h_fine,
        sizing.h_body,
        sizing.banded,
        sizing.crown_half,
    );
    let h_rs = if banded { h_body } else { h_fine };

    // ---- Head O-grid.
    let crown_left = chain.slice(0.0, s_side_top);
    let side2 = Polyline::join(&[reversed(chain, 0.0, s_side_top, true), crown_left]);
    let side3 = chain.slice(s_side_top, s_head_corner);
    let left_under = chain.slice(s_head_corner, s_head_junction);
    let junction = Polyline::segment(head_junction, mirror(head_junction));
    let right_under = reversed(chain, s_head_corner, s_head_junction, true);
    let side0 = Polyline::join(&[left_under.clone(), junction.clone(), right_under]);
    let side1 = reversed(chain, s_side_top, s_head_corner, true);
    // Side 0 (underside, fillets, junction) needs enough nodes for its chords to follow the
    // concave R8/R22 fillets (at least 3 per half); side 2 (crown band) gets the same count,
    // at least the running-surface resolution.
    let n_under = ((left_under.length() / (1.5 * h_body)).ceil() as usize).max(3);
    let n_junction = ((junction.length() / h_body).round() as usize).max(2);
    let n_fine = ((side2.length() / h_rs).ceil() as usize).max(4);
    let n_under = n_under.max((n_fine.saturating_sub(n_junction)).div_ceil(2));
    let n2 = 2 * n_under + n_junction;
    // Sides 1 and 3 (gauge corner and side face) are limited so that the core's vertical cells,
    // whose count they set, stay >= 0.6 h_rs; the chords then follow the R13 arc less closely on
    // coarse meshes (measured area loss 0.5 % at 6 mm, see tests/track_mesh.rs).
    // With a band the limit is the contact size (the band's), not the body's.
    let (side_size, core_cell_min) = if banded {
        (h_body, 0.9 * h_fine)
    } else {
        (1.5 * h_fine, 0.6 * h_fine)
    };
    let n13 = ((side3.length() / side_size).ceil() as usize)
        .min(((HEAD_CORE_TOP_Z_MM - HEAD_CORE_BOTTOM_Z_MM) / core_cell_min).floor() as usize)
        .max(2);
    let ring_depth_mm = -HEAD_CORE_TOP_Z_MM;
    let ratio = 1.25f64;
    let mut rows = 1usize;
    while rows < 40 && ring_depth_mm * geometric_fractions(rows, ratio)[1] > h_rs {
        rows += 1;
    }
    let len0 = side0.length();
    let b0 = left_under.length() / len0;
    let b1 = (left_under.length() + junction.length()) / len0;
    let mut f0 = Vec::new();
    for i in 0..=n_under {
        f0.push(b0 * i as f64 / n_under as f64);
    }
    for i in 1..=n_junction {
        f0.push(b0 + (b1 - b0) * i as f64 / n_junction as f64);
    }
    for i in 1..=n_under {
        f0.push(b1 + (1.0 - b1) * i as f64 / n_under as f64);
    }
    let grid = OGrid {
        sides: [side0, side1, side2, side3],
        core: [
            [-HEAD_CORE_HALF_WIDTH_MM, HEAD_CORE_BOTTOM_Z_MM],
            [HEAD_CORE_HALF_WIDTH_MM, HEAD_CORE_BOTTOM_Z_MM],
            // Top corners straight below the crown band ends: the core's top cells are then as
            // wide as the crown band's elements.
            [crown_half, HEAD_CORE_TOP_Z_MM],
            [-crown_half, HEAD_CORE_TOP_Z_MM],
        ],
        side_fractions: [
            f0,
            distribute::uniform(0.0, 1.0, n13),
            distribute::uniform(0.0, 1.0, n2),
            distribute::uniform(0.0, 1.0, n13),
        ],
        // Graded rows only under the running surface (side 2); uniform rows elsewhere keep the
        // underside elements from becoming the smallest of the model.
        ring_fractions: [
            distribute::uniform(0.0, 1.0, rows),
            distribute::uniform(0.0, 1.0, rows),
            if banded {
                distribute::uniform(0.0, 1.0, rows)
            } else {
                geometric_fractions(rows, ratio)
            },
            distribute::uniform(0.0, 1.0, rows),
        ],
    };
    HeadGrid {
        grid,
        n_under,
        n_junction,
    }
}

/// Meshes the head O-grid into `mesh` (with a band, the crown's outer ring row is left to the
/// band) and tags the body's running surface.
fn mesh_head(mesh: &mut SectionMesh, head: &OGrid, banded: bool) -> OGridNodes {
    let og = head.mesh(mesh, RAIL_PART, |side, _, row| {
        banded && side == 2 && row == 0
    });
    let a2 = og.side_start[2];
    let a3 = og.side_start[3];
    // Running surface: crown, R80 and R13 arcs plus the side faces (gauge faces); with a band
    // the crown's outline nodes are the band's.
    let (a1, a0_end) = (og.side_start[1], og.ring.len());
    let body_running: Vec<usize> = (a1..a0_end)
        .filter(|&i| !banded || i <= a2 || i >= a3)
        .map(|i| og.ring[i][0])
        .collect();
    mesh.tag("running_surface", body_running);
    og
}

/// The crown band: tags the body's interface under it, and meshes the band itself on the head
/// O-grid's map over the left-out ring row (running-surface size along the crown and through
/// its depth). Returns the band and its map's data (columns, rows, ring fraction, depth and
/// width in mm).
fn mesh_crown_band(
    mesh: &mut SectionMesh,
    head: &OGrid,
    og: &OGridNodes,
    sizes: &RailSectionSizes,
) -> (SectionMesh, (usize, usize, f64, f64, f64)) {
    let h_fine = sizes.running_surface_mm;
    let a2 = og.side_start[2];
    let a3 = og.side_start[3];
    let mut iface: Vec<usize> = (a2..=a3).map(|i| og.ring[i][1]).collect();
    iface.extend([og.ring[a2][0], og.ring[a3][0]]);
    mesh.tag("band_interface_body", iface);
    let s_band = head.ring_fractions[2][1];
    let n_t = distribute::count_at_least(head.sides[2].length(), h_fine).max(2);
    let (o, c) = head.outline_and_core(2, 0.5);
    let depth = s_band * (o[0] - c[0]).hypot(o[1] - c[1]);
    let n_rows = distribute::count_at_least(depth, h_fine).max(sizes.band_rows_at_least);
    let map = (n_t, n_rows, s_band, depth, head.sides[2].length());
    let grid: Vec<Vec<P2>> = (0..=n_t)
        .map(|i| {
            (0..=n_rows)
                .map(|k| head.point(2, i as f64 / n_t as f64, s_band * k as f64 / n_rows as f64))
                .collect()
        })
        .collect();
    let mut band = SectionMesh::new(1e-7);
    let ids = band.add_grid(&grid, RAIL_BAND_PART);
    band.tag("running_surface", ids.iter().map(|col| col[0]));
    let mut iface: Vec<usize> = ids.iter().map(|col| col[n_rows]).collect();
    iface.extend(ids[0].iter().copied());
    iface.extend(ids[n_t].iter().copied());
    band.tag("band_interface", iface);
    (band, map)
}

/// The foot: column-mapped between its bottom and top outlines (graphs of y), with a parabolic
/// web-foot junction of `n_junction` cells (the web's width) between the wings. Returns the
/// junction's top nodes, the web's bottom edge.
fn mesh_foot(
    mesh: &mut SectionMesh,
    outline: &RailOutline,
    h_body: f64,
    n_junction: usize,
) -> Vec<P2> {
    let chain = &outline.chain;
    let foot_junction = outline.foot_junction;
    // ---- Foot: column-mapped between bottom and top graphs.
    // junction -> edge top, y decreasing
    let foot_top_left = chain.slice(outline.s_foot_junction, outline.s_edge_top);
    // edge bottom -> centre, y increasing
    let foot_bottom_left = chain.slice(outline.s_edge_bottom, chain.length());
    let graph = |poly: &Polyline, y: f64| -> f64 {
        // Interpolate z(y) on a polyline monotonic in y.
        let n = 4000;
        let mut prev = poly.at_fraction(0.0);
        for i in 1..=n {
            let p = poly.at_fraction(i as f64 / n as f64);
            let (lo, hi) = if prev[0] <= p[0] {
                (prev, p)
            } else {
                (p, prev)
            };
            if y >= lo[0] - 1e-12 && y <= hi[0] + 1e-12 {
                let t = if hi[0] > lo[0] {
                    (y - lo[0]) / (hi[0] - lo[0])
                } else {
                    0.0
                };
                return lo[1] + t * (hi[1] - lo[1]);
            }
            prev = p;
        }
        prev[1]
    };
    let yj = foot_junction[0].abs();
    // Parabolic junction perpendicular to the fillet: slope at the ends = -cot(angle).
    let slope_end = 1.0 / FOOT_JUNCTION_ANGLE_DEG.to_radians().tan();
    let junction_z = |y: f64| foot_junction[1] - slope_end * (yj * yj - y * y) / (2.0 * yj);
    let z_top = |y: f64| {
        if y.abs() <= yj {
            junction_z(y)
        } else {
            graph(&foot_top_left, -y.abs())
        }
    };
    let z_bottom = |y: f64| graph(&foot_bottom_left, -y.abs());
    let half_foot = rail54e1::FOOT_WIDTH_MM / 2.0;
    let n_wing = (((half_foot - yj) / h_body).round() as usize).max(1);
    let mut stations = distribute::uniform(-half_foot, -yj, n_wing);
    stations.pop();
    stations.extend(distribute::uniform(-yj, yj, n_junction));
    stations.pop();
    stations.extend(distribute::uniform(yj, half_foot, n_wing));
    // Rows across the foot: the outer edge is only ~6.4 mm tall between its fillets, and uniform
    // rows must not make it the smallest element of the rail.
    let edge_height = z_top(-half_foot) - z_bottom(-half_foot);
    let n_foot_rows = ((edge_height / h_body).floor() as usize).max(1);
    let foot_grid: Vec<Vec<P2>> = stations
        .iter()
        .map(|&y| {
            (0..=n_foot_rows)
                .map(|j| {
                    let v = j as f64 / n_foot_rows as f64;
                    [y, z_bottom(y) + v * (z_top(y) - z_bottom(y))]
                })
                .collect()
        })
        .collect();
    let foot_ids = mesh.add_grid(&foot_grid, RAIL_PART);
    mesh.tag("foot_bottom", foot_ids.iter().map(|col| col[0]));
    foot_ids[n_wing..=n_wing + n_junction]
        .iter()
        .map(|col| mesh.nodes[col[n_foot_rows]])
        .collect()
}

/// The web: a Coons patch between the foot's junction nodes (bottom) and the head's junction
/// nodes (top), its sides following the outline's web faces.
fn mesh_web(
    mesh: &mut SectionMesh,
    outline: &RailOutline,
    h_body: f64,
    foot_junction_nodes: &[P2],
    junction_nodes: &[P2],
) {
    let chain = &outline.chain;
    // ---- Web: Coons patch between the two junctions.
    // foot -> head
    let web_left_poly = reversed(
        chain,
        outline.s_head_junction,
        outline.s_foot_junction,
        false,
    );
    let web_right_poly = mirrored(&web_left_poly);
    let n_web_rows =
        (((HEAD_JUNCTION_Z_MM - outline.foot_junction[1]).abs() / h_body).round() as usize).max(2);
    let web_left = web_left_poly.sample(&distribute::uniform(0.0, 1.0, n_web_rows));
    let web_right = web_right_poly.sample(&distribute::uniform(0.0, 1.0, n_web_rows));
    let web_grid = coons_patch(foot_junction_nodes, junction_nodes, &web_left, &web_right);
    mesh.add_grid(&web_grid, RAIL_PART);
}

/// Part id used in rail sections.
pub const RAIL_PART: u32 = super::material::RAIL;
/// Part id of the running band.
pub const RAIL_BAND_PART: u32 = super::material::RAIL_BAND;
