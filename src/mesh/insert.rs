//! Refined inserts: a box of a swept structured band (the wheel's tread band, the rail's
//! running band) cut out and filled with a finer block of the same geometry, tied to the hole's
//! walls.
//!
//! Why: a contact patch needs about 1 mm elements only where the snapshots are taken (as the
//! paper's "solution zone"), while a band fine over its whole length and section multiplies the
//! element count. The insert keeps the fine elements to a box around the contact path.
//!
//! Method. The band is a structured grid of section columns `i` x rows `k`, swept over stations
//! `j` (angles or x); its element `(i, k, j)` has index `(i n_k + k) n_j + j` with `n_k`, `n_j`
//! the row and station cell counts (the order of `SectionMesh::add_grid` followed by the revolve
//! or extrude loops). A box of node index ranges is cut out ([`cut_hole`]); the faces the
//! removed elements shared with kept ones are the hole's walls. The insert is the same mapping
//! sampled at subdivided parameters ([`Axis::subdivide`], [`swept_block`]), lowered by the
//! band's mean chord deficit so that it sits at the band's mean height; its boundary lies on the
//! walls within the coarse faces' chord sagitta (micrometres). Every insert node on the box
//! faces except the running surface is a tie slave on the walls ([`tie_insert`],
//! `u_s = sum w_a u_a` as for the bands). The hole leaves the band's own tied nodes (its bottom
//! row and side columns) in place, so that no master is itself a slave (the engine refuses
//! chained ties).

use super::hex::{self, P3};
use super::{tie, Mesh};

/// Node set of an insert's tie slaves (removed when the insert is tied in).
const BOUNDARY_SET: &str = "insert_boundary";

/// Node index ranges (inclusive, `lo < hi`) of the box in a swept band.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BoxRange {
    /// Section columns.
    pub columns: (usize, usize),
    /// Section rows.
    pub rows: (usize, usize),
    /// Stations along the sweep.
    pub stations: (usize, usize),
}

/// Cell counts of a swept band: section columns, section rows, stations (a periodic sweep has as
/// many station cells as stations).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SweptCells {
    /// Column cells.
    pub columns: usize,
    /// Row cells.
    pub rows: usize,
    /// Station cells.
    pub stations: usize,
}

impl SweptCells {
    /// Index of element `(i, k, j)` in the swept band.
    pub fn element(&self, i: usize, k: usize, j: usize) -> usize {
        (i * self.rows + k) * self.stations + j
    }

    /// Element count.
    pub fn len(&self) -> usize {
        self.columns * self.rows * self.stations
    }

    /// Whether the band has no element.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Per element: whether it lies in the box.
    pub fn hole_mask(&self, b: &BoxRange) -> Vec<bool> {
        let mut mask = vec![false; self.len()];
        for i in b.columns.0..b.columns.1 {
            for k in b.rows.0..b.rows.1 {
                for j in b.stations.0..b.stations.1 {
                    mask[self.element(i, k, j)] = true;
                }
            }
        }
        mask
    }
}

/// One direction of an insert: the band's node values it spans (`coarse`, the band's
/// `values[lo..=hi]`) and the insert's (`fine`: each coarse interval split into equal parts),
/// with each fine node's coarse interval and fraction in it.
#[derive(Clone, Debug, PartialEq)]
pub struct Axis {
    /// The band's values over the box.
    pub coarse: Vec<f64>,
    /// The insert's values.
    pub fine: Vec<f64>,
    /// Per fine value: its coarse interval (the last value: the last interval).
    pub cell: Vec<usize>,
    /// Per fine value: its fraction in that interval (0 to 1).
    pub fraction: Vec<f64>,
}

impl Axis {
    /// `values[lo..=hi]` with each interval split into `pieces(a, b)` (at least 1) equal parts.
    pub fn subdivide(
        values: &[f64],
        lo: usize,
        hi: usize,
        pieces: impl Fn(f64, f64) -> usize,
    ) -> Axis {
        let coarse = values[lo..=hi].to_vec();
        let mut axis = Axis {
            fine: vec![coarse[0]],
            cell: vec![0],
            fraction: vec![0.0],
            coarse,
        };
        for q in 0..axis.coarse.len() - 1 {
            let (a, b) = (axis.coarse[q], axis.coarse[q + 1]);
            let n = pieces(a, b).max(1);
            for p in 1..=n {
                let f = p as f64 / n as f64;
                axis.fine.push(a + (b - a) * f);
                axis.cell.push(q);
                axis.fraction.push(f);
            }
        }
        axis
    }

    /// Coarse intervals.
    fn cells(&self) -> usize {
        self.coarse.len() - 1
    }

    /// The coarse intervals fine node `n` samples, with its trapezoid weight in each: 1 inside an
    /// interval, 1/2 in each of the two it ends and starts.
    fn memberships(&self, n: usize) -> [(usize, f64); 2] {
        let (c, f) = (self.cell[n], self.fraction[n]);
        if f == 0.0 {
            [(c, 0.5), (c, 0.0)]
        } else if f == 1.0 && c + 1 < self.cells() {
            [(c, 0.5), (c + 1, 0.5)]
        } else if f == 1.0 {
            [(c, 0.5), (c, 0.0)]
        } else {
            [(c, 1.0), (c, 0.0)]
        }
    }

    /// The neighbouring coarse intervals whose centres bracket fine node `n`, with the weight
    /// of the second (linear between interval centres, constant beyond the outer centres).
    fn between_centres(&self, n: usize) -> (usize, usize, f64) {
        let (c, f) = (self.cell[n], self.fraction[n]);
        if f < 0.5 && c > 0 {
            (c - 1, c, f + 0.5)
        } else if f >= 0.5 && c + 1 < self.cells() {
            (c, c + 1, f - 0.5)
        } else {
            (c, c, 0.0)
        }
    }
}

/// Checks an insert's sizes against its band's element size `band_mm` (`field` names the insert
/// in errors): the section size in [0.2, band], the length along the sweep in [size, band], the
/// depth in [size, 100] mm.
pub fn check_sizes(
    c: &crate::input::Checker,
    field: &str,
    (size_mm, length_mm, depth_mm): (f64, f64, f64),
    band_mm: f64,
) -> crate::Result<()> {
    c.within(&format!("{field}.element_size_mm"), size_mm, 0.2, band_mm)?;
    c.within(
        &format!("{field}.element_length_mm"),
        length_mm,
        size_mm,
        band_mm,
    )?;
    c.within(&format!("{field}.depth_mm"), depth_mm, size_mm, 100.0)
}

/// How many parts of about `size` a length takes: `floor(1.1 length / size)`, at least 1, so
/// that no part is shorter than `size / 1.1` (the insert's elements set the model's time step)
/// and, for two parts or more, none longer than `1.36 size` (a 5 mm row at 2 mm: two 2.5 mm
/// parts, where three would be 1.67 mm and cut the time step by a sixth).
pub fn pieces_of(length: f64, size: f64) -> usize {
    ((1.1 * length.abs() / size).floor() as usize).max(1)
}

/// The structured block over `columns` x `rows` x `stations` (a section grid swept, open),
/// node `(i, k, j)` at `point(column, row, station)` (the band's exact geometry) less the band's
/// mean chord deficit there (below). Nodes of row `surface_row` (the first or the last) are put
/// in node set `surface_set`; nodes on the other five faces of the box in the insert's
/// tie-slave set.
///
/// Why the deficit: the band's running surface between its nodes is its elements' flat faces,
/// which lie below the curved profile by up to the chord sagitta `L^2 / (8 R)` (10 um for 6 mm
/// along the 460 mm wheel, 15 um across the R300 crown), on average two thirds of it. An insert
/// on the exact profile would stand that much proud of the band, and a wheel rolling onto it
/// meets a step: +22 % of normal force entering and leaving (measured on the default model).
/// So each insert node is lowered by the band's mean deficit `m`: the mean of `exact - faceted`
/// over the insert's surface nodes in each band cell of the surface (faceted: the band cell's
/// trilinear interpolation), interpolated linearly between cell centres, applied in full at the
/// surface and fading linearly to nothing at the box's deep face. The insert keeps the
/// profile's shape (the snapshots resolve it) at the band's mean height.
pub fn swept_block(
    columns: &Axis,
    rows: &Axis,
    stations: &Axis,
    point: impl Fn(f64, f64, f64) -> P3,
    material: u32,
    surface_row: usize,
    surface_set: &str,
) -> Mesh {
    let (ni, nk, nj) = (columns.fine.len(), rows.fine.len(), stations.fine.len());
    let id = |i: usize, k: usize, j: usize| (i * nk + k) * nj + j;
    let deep_row = if surface_row == 0 { nk - 1 } else { 0 };
    // The band's nodes over the box, and the faceted position of a fine node.
    let (ci, ck, cj) = (
        columns.coarse.len(),
        rows.coarse.len(),
        stations.coarse.len(),
    );
    let mut corner = vec![[0.0; 3]; ci * ck * cj];
    for a in 0..ci {
        for b in 0..ck {
            for c in 0..cj {
                corner[(a * ck + b) * cj + c] =
                    point(columns.coarse[a], rows.coarse[b], stations.coarse[c]);
            }
        }
    }
    let faceted = |i: usize, k: usize, j: usize| -> P3 {
        let (a, b, c) = (columns.cell[i], rows.cell[k], stations.cell[j]);
        let (fa, fb, fc) = (columns.fraction[i], rows.fraction[k], stations.fraction[j]);
        let mut p = [0.0; 3];
        for (da, wa) in [(0, 1.0 - fa), (1, fa)] {
            for (db, wb) in [(0, 1.0 - fb), (1, fb)] {
                for (dc, wc) in [(0, 1.0 - fc), (1, fc)] {
                    let q = corner[((a + da) * ck + b + db) * cj + c + dc];
                    for d in 0..3 {
                        p[d] += wa * wb * wc * q[d];
                    }
                }
            }
        }
        p
    };
    let mut exact = vec![[0.0; 3]; ni * nk * nj];
    for i in 0..ni {
        for k in 0..nk {
            for j in 0..nj {
                exact[id(i, k, j)] = point(columns.fine[i], rows.fine[k], stations.fine[j]);
            }
        }
    }
    // Mean deficit per band surface cell.
    let (cells_i, cells_j) = (columns.cells(), stations.cells());
    // Trapezoid rule over each cell's nodes (the deficit is zero at the band's own nodes).
    let mut sum = vec![[0.0; 3]; cells_i * cells_j];
    let mut weight = vec![0.0; cells_i * cells_j];
    for i in 0..ni {
        for j in 0..nj {
            let f = faceted(i, surface_row, j);
            let e = exact[id(i, surface_row, j)];
            for (a, wa) in columns.memberships(i) {
                for (c, wc) in stations.memberships(j) {
                    let cell = a * cells_j + c;
                    for d in 0..3 {
                        sum[cell][d] += wa * wc * (e[d] - f[d]);
                    }
                    weight[cell] += wa * wc;
                }
            }
        }
    }
    let mean: Vec<P3> = sum
        .iter()
        .zip(&weight)
        .map(|(s, &w)| s.map(|v| if w > 0.0 { v / w } else { 0.0 }))
        .collect();
    let mut mesh = Mesh {
        nodes: vec![[0.0; 3]; ni * nk * nj],
        ..Mesh::default()
    };
    for i in 0..ni {
        let (a0, a1, wa) = columns.between_centres(i);
        for j in 0..nj {
            let (c0, c1, wc) = stations.between_centres(j);
            let m = |a: usize, c: usize| mean[a * cells_j + c];
            let deficit: P3 = std::array::from_fn(|d| {
                (1.0 - wa) * ((1.0 - wc) * m(a0, c0)[d] + wc * m(a0, c1)[d])
                    + wa * ((1.0 - wc) * m(a1, c0)[d] + wc * m(a1, c1)[d])
            });
            for k in 0..nk {
                // 1 at the surface row, 0 at the deep one.
                let depth = (k as f64 - surface_row as f64).abs() / (nk - 1) as f64;
                let e = exact[id(i, k, j)];
                mesh.nodes[id(i, k, j)] =
                    std::array::from_fn(|d| e[d] - (1.0 - depth) * deficit[d]);
            }
        }
    }
    for i in 0..ni - 1 {
        for k in 0..nk - 1 {
            for j in 0..nj - 1 {
                mesh.elements.push(hex::structured(i, k, j, id));
                mesh.material.push(material);
            }
        }
    }
    let mut surface = Vec::new();
    let mut boundary = Vec::new();
    for i in 0..ni {
        for k in 0..nk {
            for j in 0..nj {
                if k == surface_row {
                    surface.push(id(i, k, j));
                }
                let on_side = i == 0 || i == ni - 1 || j == 0 || j == nj - 1 || k == deep_row;
                if on_side {
                    boundary.push(id(i, k, j));
                }
            }
        }
    }
    mesh.add_node_set(surface_set, surface);
    mesh.add_node_set(BOUNDARY_SET, boundary);
    mesh.orient_elements();
    mesh
}

/// Remove the elements flagged in `remove` and the nodes no kept element uses (node sets,
/// surfaces and ties renumbered; a tie pair whose slave or masters go is dropped). Returns the
/// faces the removed elements shared with kept ones (the hole's walls), in the new numbering.
pub fn cut_hole(mesh: &mut Mesh, remove: &[bool]) -> Vec<[usize; 4]> {
    let key = |f: [usize; 4]| {
        let mut s = f;
        s.sort_unstable();
        s
    };
    let mut removed_faces: Vec<[usize; 4]> = Vec::new();
    for (e, conn) in mesh.elements.iter().enumerate() {
        if remove[e] {
            for f in hex::FACES {
                removed_faces.push(key(f.map(|n| conn[n])));
            }
        }
    }
    removed_faces.sort_unstable();
    let mut walls = Vec::new();
    for (e, conn) in mesh.elements.iter().enumerate() {
        if !remove[e] {
            for f in hex::FACES {
                let face = f.map(|n| conn[n]);
                if removed_faces.binary_search(&key(face)).is_ok() {
                    walls.push(face);
                }
            }
        }
    }
    let mut used = vec![false; mesh.nodes.len()];
    let mut elements = Vec::with_capacity(mesh.elements.len());
    let mut material = Vec::with_capacity(mesh.elements.len());
    for (e, conn) in mesh.elements.iter().enumerate() {
        if !remove[e] {
            conn.iter().for_each(|&n| used[n] = true);
            elements.push(*conn);
            material.push(mesh.material[e]);
        }
    }
    mesh.elements = elements;
    mesh.material = material;
    let mut new_id = vec![usize::MAX; mesh.nodes.len()];
    let mut nodes = Vec::with_capacity(mesh.nodes.len());
    for (n, p) in mesh.nodes.iter().enumerate() {
        if used[n] {
            new_id[n] = nodes.len();
            nodes.push(*p);
        }
    }
    mesh.nodes = nodes;
    for ids in mesh.node_sets.values_mut() {
        ids.retain(|&n| used[n]);
    }
    for faces in mesh.surfaces.values_mut() {
        faces.retain(|f| f.iter().all(|&n| used[n]));
    }
    for t in &mut mesh.ties {
        t.pairs
            .retain(|p| used[p.slave] && p.master.iter().all(|&m| used[m]));
    }
    mesh.renumber(&new_id);
    walls.iter().map(|f| f.map(|n| new_id[n])).collect()
}

/// Append `insert` (from [`swept_block`]) to `mesh` and tie its box faces onto `walls` (faces of
/// `mesh`, from [`cut_hole`]) as tie `name`. Returns the largest slave-to-wall distance (m)
/// before the slaves are snapped (the chord sagitta of the coarse faces).
pub fn tie_insert(mesh: &mut Mesh, walls: &[[usize; 4]], mut insert: Mesh, name: &str) -> f64 {
    let slaves_local = insert.node_sets.remove(BOUNDARY_SET).unwrap_or_default();
    let offset = mesh.nodes.len();
    mesh.append(insert);
    let slaves: Vec<usize> = slaves_local.iter().map(|&n| n + offset).collect();
    let interface = tie::build(name, &mesh.nodes, &slaves, walls);
    let gap = interface.max_gap_m();
    mesh.ties.push(interface);
    gap
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit-spaced 4 x 3 x 5 block (columns along y, rows along z, stations along x), as a
    /// swept band would be numbered.
    fn band() -> (Mesh, SweptCells) {
        let unit = |n: usize| {
            let values: Vec<f64> = (0..=n).map(|v| v as f64).collect();
            Axis::subdivide(&values, 0, n, |_, _| 1)
        };
        let (columns, rows, stations) = (unit(4), unit(3), unit(5));
        let mut m = swept_block(&columns, &rows, &stations, |y, z, x| [x, y, z], 7, 3, "top");
        m.node_sets.remove(BOUNDARY_SET);
        let cells = SweptCells {
            columns: 4,
            rows: 3,
            stations: 5,
        };
        (m, cells)
    }

    #[test]
    fn the_element_index_follows_the_swept_order() {
        let (m, cells) = band();
        assert_eq!(m.elements.len(), cells.len());
        // Element (i, k, j) has its first corner at (x, y, z) = (j, i, k).
        for (i, k, j) in [(0, 0, 0), (3, 2, 4), (1, 2, 3), (2, 0, 1)] {
            let e = cells.element(i, k, j);
            let lo = m.elements[e]
                .iter()
                .map(|&n| m.nodes[n])
                .fold([f64::MAX; 3], |a, p| [0, 1, 2].map(|d| a[d].min(p[d])));
            assert_eq!(lo, [j as f64, i as f64, k as f64]);
        }
    }

    /// On a band around a cylinder (radius 0.46 m, 6 mm chords, as the wheel's running arc),
    /// the insert's surface keeps the circle's shape at the faceted band's mean radius
    /// `R - 2/3 s` (s the chords' sagitta): within s / 7, the trapezoid rule over a chord's
    /// four nodes giving 0.59 s, not the continuous 2/3 s; on the exact circle the mean would
    /// be off by 2/3 s. The shape: all surface nodes at one radius (2 % of s: rounding and the
    /// cells' turning normals).
    #[test]
    fn the_insert_sits_at_the_bands_mean_height_on_a_curved_band() {
        let radius = 0.46;
        let chord = 0.006;
        let step = chord / radius;
        let point = |y: f64, r: f64, th: f64| [r * th.sin(), y, -r * th.cos()];
        let size = |a: f64, b: f64| pieces_of(b - a, 0.002);
        let cols = Axis::subdivide(&[0.0, 0.006, 0.012], 0, 2, size);
        let rows = Axis::subdivide(&[radius - 0.012, radius - 0.006, radius], 0, 2, size);
        let angles: Vec<f64> = (0..=4).map(|j| j as f64 * step).collect();
        let stations = Axis::subdivide(&angles, 0, 4, |a, b| pieces_of((b - a) * radius, 0.002));
        let top = rows.fine.len() - 1;
        let m = swept_block(&cols, &rows, &stations, point, 1, top, "top");
        let radii: Vec<f64> = m
            .node_set("top")
            .unwrap()
            .iter()
            .map(|&n| m.nodes[n][0].hypot(m.nodes[n][2]))
            .collect();
        let sagitta = chord * chord / (8.0 * radius);
        let mean = radii.iter().sum::<f64>() / radii.len() as f64;
        let spread = radii.iter().fold(f64::MIN, |a, &r| a.max(r))
            - radii.iter().fold(f64::MAX, |a, &r| a.min(r));
        assert!(
            (mean - (radius - 2.0 / 3.0 * sagitta)).abs() < sagitta / 7.0,
            "mean radius {mean}, sagitta {sagitta}"
        );
        assert!(spread < 0.05 * sagitta, "spread {spread}");
        // The deep face is not moved (it is tied to the band's rows below).
        let deep: Vec<f64> = (0..m.nodes.len())
            .filter(|&n| n % (rows.fine.len() * stations.fine.len()) < stations.fine.len())
            .map(|n| m.nodes[n][0].hypot(m.nodes[n][2]))
            .collect();
        assert!(deep.iter().all(|&r| (r - (radius - 0.012)).abs() < 1e-12));
    }

    #[test]
    fn a_tied_insert_refills_the_hole_and_ties_every_box_face_but_the_surface() {
        let (mut m, cells) = band();
        let volume = m.volume();
        let b = BoxRange {
            columns: (1, 3),
            rows: (1, 3),
            stations: (1, 4),
        };
        let walls = cut_hole(&mut m, &cells.hole_mask(&b));
        // 2 x 2 x 3 elements cut; the walls: two side walls (2 x 3 faces each), the bottom
        // (2 x 3), the two end walls (2 x 2 each); the top is open.
        assert_eq!(m.elements.len(), 60 - 12);
        assert_eq!(walls.len(), 6 + 6 + 6 + 4 + 4);
        // The nodes strictly inside the top of the hole went with their elements.
        let surface_nodes_inside = m
            .nodes
            .iter()
            .filter(|p| p[2] == 3.0 && p[1] == 2.0 && (p[0] == 2.0 || p[0] == 3.0))
            .count();
        assert_eq!(surface_nodes_inside, 0);
        // The insert: the box at a third of the spacing.
        let third = |a: f64, b: f64| pieces_of(b - a, 0.34);
        let cols = Axis::subdivide(&[0.0, 1.0, 2.0, 3.0, 4.0], 1, 3, third);
        let rows = Axis::subdivide(&[0.0, 1.0, 2.0, 3.0], 1, 3, third);
        let stations = Axis::subdivide(&[0.0, 1.0, 2.0, 3.0, 4.0, 5.0], 1, 4, third);
        assert_eq!(
            (cols.fine.len(), rows.fine.len(), stations.fine.len()),
            (7, 7, 10)
        );
        assert_eq!(cols.cell, [0, 0, 0, 0, 1, 1, 1]);
        let last = rows.fine.len() - 1;
        let insert = swept_block(&cols, &rows, &stations, |y, z, x| [x, y, z], 8, last, "top");
        let gap = tie_insert(&mut m, &walls, insert, "insert");
        assert!(gap < 1e-12, "gap {gap}");
        assert!((m.volume() - volume).abs() < 1e-9 * volume);
        // Slaves: every insert node on the five tied faces, none inside or on the open top
        // only: 7 x 7 x 10 nodes less the (5 x 5 x 8) interior less the top's interior (5 x 8).
        let tie = m.ties.last().unwrap();
        assert_eq!(tie.pairs.len(), 7 * 7 * 10 - 5 * 5 * 8 - 5 * 8);
        // No master is a slave (the engine's rule), and each slave sits where its weights say.
        let slaves: std::collections::HashSet<usize> = tie.pairs.iter().map(|p| p.slave).collect();
        for p in &tie.pairs {
            assert!(p.master.iter().all(|mm| !slaves.contains(mm)));
            let x: P3 =
                [0, 1, 2].map(|d| (0..4).map(|a| p.weights[a] * m.nodes[p.master[a]][d]).sum());
            let s = m.nodes[p.slave];
            assert!((0..3).all(|d| (x[d] - s[d]).abs() < 1e-12));
        }
        // The running surface: the coarse top less the two nodes inside the hole, and the
        // insert's top (coincident nodes at the hole's rim are kept apart).
        assert_eq!(m.node_set("top").unwrap().len(), 5 * 6 - 2 + 7 * 10);
    }
}
