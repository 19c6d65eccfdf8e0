//! The rail's insert: a box of the rail's running band (a stretch along the track, a strip of
//! the crown, a depth under it) meshed finer and tied in (`mesh::insert`), where the contact
//! patches of a run's snapshots are resolved.

use serde::{Deserialize, Serialize};

use super::insert::{self, pieces_of, Axis, BoxRange, SweptCells};
use super::rail::{RailBandMap, BANDED_CROWN_HALF_WIDTH_MM};
use super::{material, Mesh, P3};
use crate::input::Checker;
use crate::Result;

/// A finer block in the rail's running band: element sizes and the box it fills. The box is
/// widened to the band's nodes around it, and capped so that it leaves the band's first and
/// last columns and its bottom row (tied to the rail head) in place. The rail must have a
/// running band (`section_element_mm` at least 1.5 x `running_surface_element_mm`).
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RailInsertSpec {
    /// Start along the track (m).
    pub start_m: f64,
    /// Length along the track (m).
    pub length_m: f64,
    /// Element size in the section, across the crown and with depth (mm).
    pub element_size_mm: f64,
    /// Element length along the track (mm).
    pub element_length_mm: f64,
    /// Start of the insert across the crown (mm, upright section, 0 at the crown's centre,
    /// negative towards the gauge side, as `wheel_position.tape_circle_y_mm`).
    pub y_min_mm: f64,
    /// End of the insert across the crown (mm).
    pub y_max_mm: f64,
    /// Depth under the running surface (mm).
    pub depth_mm: f64,
}

impl RailInsertSpec {
    /// Check the insert (`field` names it in errors) against the rail's section sizes and the
    /// track length.
    pub fn validate(
        &self,
        c: &Checker,
        field: &str,
        running_surface_element_mm: f64,
        section_element_mm: f64,
        track_length_m: f64,
    ) -> Result<()> {
        let h_band = running_surface_element_mm;
        c.require(
            section_element_mm >= 1.5 * h_band,
            &format!("{field}.element_size_mm"),
            || {
                format!(
                    "an insert needs the rail's running band, which is made when \
                     track.rail.section_element_mm ({section_element_mm}) is at least 1.5 x \
                     track.rail.running_surface_element_mm ({h_band})"
                )
            },
        )?;
        let sizes = (self.element_size_mm, self.element_length_mm, self.depth_mm);
        insert::check_sizes(c, field, sizes, h_band)?;
        c.within(
            &format!("{field}.length_m"),
            self.length_m,
            1e-3 * self.element_length_mm,
            track_length_m,
        )?;
        c.within(
            &format!("{field}.start_m"),
            self.start_m,
            0.0,
            track_length_m - self.length_m,
        )?;
        let edge = BANDED_CROWN_HALF_WIDTH_MM - h_band;
        c.within(
            &format!("{field}.y_min_mm"),
            self.y_min_mm,
            -edge,
            edge - self.element_size_mm,
        )?;
        c.within(
            &format!("{field}.y_max_mm"),
            self.y_max_mm,
            self.y_min_mm + self.element_size_mm,
            edge,
        )
    }
}

/// Cut the insert's hole out of the extruded running band `band_mesh` (grid `map`, swept over
/// `stations`) and build the insert, its section point `(y, z)` at station `x` placed at
/// `place([y, z], x)` (the track's inclination). Returns the hole's walls (in `band_mesh`'s
/// numbering) and the insert, for `insert::tie_insert` once the band has joined the rail.
pub(super) fn cut(
    band_mesh: &mut Mesh,
    ins: &RailInsertSpec,
    map: &RailBandMap,
    stations: &[f64],
    place: impl Fn([f64; 2], f64) -> P3,
) -> (Vec<[usize; 4]>, Mesh) {
    let cells = SweptCells {
        columns: map.columns,
        rows: map.rows,
        stations: stations.len() - 1,
    };
    assert_eq!(
        band_mesh.elements.len(),
        cells.len(),
        "band is a swept grid"
    );
    let t: Vec<f64> = (0..=map.columns)
        .map(|i| i as f64 / map.columns as f64)
        .collect();
    let s: Vec<f64> = (0..=map.rows)
        .map(|k| map.ring_fraction * k as f64 / map.rows as f64)
        .collect();
    let range = box_range(ins, map, &t, stations);
    let walls = insert::cut_hole(band_mesh, &cells.hole_mask(&range));
    let h = ins.element_size_mm;
    let t_axis = Axis::subdivide(&t, range.columns.0, range.columns.1, |a, b| {
        pieces_of((b - a) * map.width_mm, h)
    });
    let s_axis = Axis::subdivide(&s, range.rows.0, range.rows.1, |a, b| {
        pieces_of((b - a) / map.ring_fraction * map.depth_mm, h)
    });
    let x_axis = Axis::subdivide(stations, range.stations.0, range.stations.1, |a, b| {
        pieces_of((b - a) * 1e3, ins.element_length_mm)
    });
    let block = insert::swept_block(
        &t_axis,
        &s_axis,
        &x_axis,
        |t, s, x| place(map.point(t, s), x),
        material::RAIL_BAND,
        0,
        "rail_running_surface",
    );
    (walls, block)
}

/// The band's node ranges the insert fills: widened to the band's nodes around the asked box,
/// capped to leave the first and last columns and the bottom row.
fn box_range(ins: &RailInsertSpec, map: &RailBandMap, t: &[f64], stations: &[f64]) -> BoxRange {
    let tol = 1e-9;
    // Columns run from the field side (y > 0) to the gauge side: y falls with i.
    let y: Vec<f64> = t.iter().map(|&t| map.point(t, 0.0)[0]).collect();
    let last_column = map.columns;
    let i0 = (0..last_column)
        .find(|&i| y[i + 1] < ins.y_max_mm - tol)
        .unwrap_or(0)
        .clamp(1, last_column - 2);
    let i1 = (0..last_column)
        .rev()
        .find(|&i| y[i] > ins.y_min_mm + tol)
        .map_or(last_column, |i| i + 1)
        .clamp(i0 + 1, last_column - 1);
    // The first row at least `depth_mm` under the running surface.
    let k1 = (0..=map.rows)
        .find(|&k| map.depth_mm * k as f64 / map.rows as f64 >= ins.depth_mm - tol)
        .unwrap_or(map.rows)
        .clamp(1, map.rows - 1);
    let last_station = stations.len() - 1;
    let j0 = stations
        .iter()
        .rposition(|&x| x <= ins.start_m + tol)
        .unwrap_or(0);
    let j1 = stations
        .iter()
        .position(|&x| x >= ins.start_m + ins.length_m - tol)
        .unwrap_or(last_station)
        .clamp(j0 + 1, last_station);
    BoxRange {
        columns: (i0, i1),
        rows: (0, k1),
        stations: (j0, j1),
    }
}
