//! The wheel's tread insert: a box of the tread band (an arc of the tread, a strip of the
//! profile, a depth under it) meshed finer and tied in (`mesh::insert`), where the contact
//! patches of a run's snapshots are resolved.

use serde::{Deserialize, Serialize};

use super::insert::{self, pieces_of, Axis, BoxRange, SweptCells};
use super::{material, Mesh, P3};
use crate::geometry::s1002;
use crate::input::wheel::WheelSpec;
use crate::input::Checker;
use crate::Result;

/// A finer block in the tread band: element sizes and the box it fills. The box is widened to
/// the band's nodes around it, and capped so that it leaves the band's first and last columns
/// and its bottom row (tied to the wheel body) in place.
///
/// Why: the contact patch at 110-120 kN is about 17 mm long and 7.6 mm wide (Hertz semi-axes
/// about 8.3 and 3.6 mm on the default wheel and rail), so 8 nodes across its width need about
/// 1 mm elements; only the tread that rolls through the rail's insert while snapshots are taken
/// needs them.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct TreadInsertSpec {
    /// Element size in the section, across the tread and with depth (mm).
    pub element_size_mm: f64,
    /// Element length along the tread (mm).
    pub element_length_mm: f64,
    /// Centre of the insert's arc, degrees from the bottom point (as the band's
    /// `arc_centre_deg`).
    pub arc_centre_deg: f64,
    /// Angular width of the insert (degrees), inside the band's fine arc.
    pub arc_width_deg: f64,
    /// Start of the insert on the profile's S coordinate (mm, 0 at the tape circle, negative
    /// towards the flange).
    pub s_min_mm: f64,
    /// End of the insert on S (mm).
    pub s_max_mm: f64,
    /// Depth under the tread (mm).
    pub depth_mm: f64,
}

/// What an insert is checked against: its band's element size and fine arc, and where the
/// band starts on the profile (the flange root).
#[derive(Clone, Copy, Debug)]
pub struct BandArc {
    /// The band's element size (mm).
    pub element_size_mm: f64,
    /// Centre of the band's fine arc (degrees from the bottom point).
    pub arc_centre_deg: f64,
    /// Width of the band's fine arc (degrees).
    pub arc_width_deg: f64,
    /// S of the band's first column (mm).
    pub flange_root_s_mm: f64,
}

/// Whether the arc `inner_width_deg` wide about `inner_centre_deg` lies within the arc
/// `outer_width_deg` wide about `outer_centre_deg` (centres compared modulo 360 degrees; 1e-9
/// degrees of slack for arcs that share an end).
pub fn arc_within(
    inner_centre_deg: f64,
    inner_width_deg: f64,
    outer_centre_deg: f64,
    outer_width_deg: f64,
) -> bool {
    let offset_deg = wrap_deg(inner_centre_deg - outer_centre_deg);
    offset_deg.abs() + 0.5 * inner_width_deg <= 0.5 * outer_width_deg + 1e-9
}

/// `angle_deg` wrapped into (-180, 180].
pub fn wrap_deg(angle_deg: f64) -> f64 {
    let a = angle_deg.rem_euclid(360.0);
    if a > 180.0 {
        a - 360.0
    } else {
        a
    }
}

impl TreadInsertSpec {
    /// Check the insert against its band (`field` names it in errors).
    pub fn validate(&self, c: &Checker, field: &str, band: &BandArc) -> Result<()> {
        let h_band = band.element_size_mm;
        let sizes = (self.element_size_mm, self.element_length_mm, self.depth_mm);
        insert::check_sizes(c, field, sizes, h_band)?;
        c.within(
            &format!("{field}.arc_width_deg"),
            self.arc_width_deg,
            1e-3,
            band.arc_width_deg,
        )?;
        c.require(
            arc_within(
                self.arc_centre_deg,
                self.arc_width_deg,
                band.arc_centre_deg,
                band.arc_width_deg,
            ),
            &format!("{field}.arc_centre_deg"),
            || {
                format!(
                    "the insert ({} deg wide about {} deg) must lie in the band's fine arc ({} \
                     deg wide about {} deg)",
                    self.arc_width_deg,
                    self.arc_centre_deg,
                    band.arc_width_deg,
                    band.arc_centre_deg
                )
            },
        )?;
        c.within(
            &format!("{field}.s_min_mm"),
            self.s_min_mm,
            band.flange_root_s_mm + h_band,
            s1002::S_CHAMFER_START_MM - 2.0 * h_band,
        )?;
        c.within(
            &format!("{field}.s_max_mm"),
            self.s_max_mm,
            self.s_min_mm + self.element_size_mm,
            s1002::S_CHAMFER_START_MM - h_band,
        )
    }
}

/// Cut the insert's hole out of the revolved band `band_mesh` (columns and rows `grid`, the
/// band section's, swept over `angles`; its fine arc centred at `band_centre_deg`) and build the
/// insert, its node `(S, r, theta)` at `place(S, r, theta)` (the band's revolution). Returns the
/// hole's walls (in `band_mesh`'s numbering) and the insert, for `insert::tie_insert` once the
/// band has joined the body.
pub(super) fn cut(
    band_mesh: &mut Mesh,
    ins: &TreadInsertSpec,
    band_centre_deg: f64,
    wheel: &WheelSpec,
    grid: &(Vec<f64>, Vec<f64>),
    angles: &[f64],
    place: impl Fn(f64, f64, f64) -> P3,
) -> (Vec<[usize; 4]>, Mesh) {
    let (columns_s, rows_v) = grid;
    let cells = SweptCells {
        columns: columns_s.len() - 1,
        rows: rows_v.len() - 1,
        stations: angles.len(),
    };
    assert_eq!(
        band_mesh.elements.len(),
        cells.len(),
        "band is a swept grid"
    );
    let range = box_range(ins, wheel, grid, angles, band_centre_deg);
    let walls = insert::cut_hole(band_mesh, &cells.hole_mask(&range));
    let r_in = wheel.rim_inner_radius_mm;
    let r_top = |s: f64| wheel.tread_radius_mm(s);
    let (i0, i1) = range.columns;
    let (k0, k1) = range.rows;
    let (j0, j1) = range.stations;
    let s = Axis::subdivide(columns_s, i0, i1, |a, b| {
        pieces_of(b - a, ins.element_size_mm)
    });
    let rim_depth_mm = r_top(0.5 * (columns_s[i0] + columns_s[i1])) - r_in;
    let v = Axis::subdivide(rows_v, k0, k1, |a, b| {
        pieces_of((b - a) * rim_depth_mm, ins.element_size_mm)
    });
    let theta = Axis::subdivide(angles, j0, j1, |a, b| {
        pieces_of((b - a) * wheel.nominal_radius_mm, ins.element_length_mm)
    });
    let surface_row = v.fine.len() - 1;
    let block = insert::swept_block(
        &s,
        &v,
        &theta,
        |s, v, th| place(s, r_in + v * (r_top(s) - r_in), th),
        material::TREAD_BAND,
        surface_row,
        "tread",
    );
    (walls, block)
}

/// The band's node ranges the insert fills: widened to the band's nodes around the asked box,
/// capped to leave the first and last columns and the bottom row.
fn box_range(
    ins: &TreadInsertSpec,
    wheel: &WheelSpec,
    (columns_s, rows_v): &(Vec<f64>, Vec<f64>),
    angles: &[f64],
    band_centre_deg: f64,
) -> BoxRange {
    let tol = 1e-9;
    let last_column = columns_s.len() - 1;
    let i0 = columns_s
        .iter()
        .rposition(|&s| s <= ins.s_min_mm + tol)
        .unwrap_or(0)
        .clamp(1, last_column - 2);
    let i1 = columns_s
        .iter()
        .position(|&s| s >= ins.s_max_mm - tol)
        .unwrap_or(last_column)
        .clamp(i0 + 1, last_column - 1);
    let s_mid = 0.5 * (columns_s[i0] + columns_s[i1]);
    let rim_depth_mm = wheel.tread_radius_mm(s_mid) - wheel.rim_inner_radius_mm;
    let top_row = rows_v.len() - 1;
    // The highest row at least `depth_mm` under the tread.
    let k0 = rows_v
        .iter()
        .rposition(|&v| (1.0 - v) * rim_depth_mm >= ins.depth_mm - tol)
        .unwrap_or(0)
        .clamp(1, top_row - 1);
    // The band's angles rise from the point opposite its fine arc's centre, which is at
    // `band_centre_deg` itself; the insert (validated to lie in the fine arc) is written in the
    // same turn.
    let mid = (band_centre_deg + wrap_deg(ins.arc_centre_deg - band_centre_deg)).to_radians();
    let half = 0.5 * ins.arc_width_deg.to_radians();
    let last_angle = angles.len() - 1;
    let j0 = angles
        .iter()
        .rposition(|&a| a <= mid - half + tol)
        .unwrap_or(0);
    let j1 = angles
        .iter()
        .position(|&a| a >= mid + half - tol)
        .unwrap_or(last_angle)
        .clamp(j0 + 1, last_angle);
    BoxRange {
        columns: (i0, i1),
        rows: (k0, top_row),
        stations: (j0, j1),
    }
}
