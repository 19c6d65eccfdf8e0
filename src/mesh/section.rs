//! Quadrilateral meshes of plane cross-sections (the wheel section in (y, r), the rail section
//! in (y, z)), built from structured blocks: transfinite (Coons) patches and O-grids.
//!
//! Blocks that share an edge are generated with identical node positions on it and then fused
//! by [`SectionMesh::add_node`], which merges points closer than a tolerance.

use std::collections::{BTreeMap, HashMap};

use crate::geometry::curve2d::P2;

/// A plane quad mesh with named node tags.
#[derive(Clone, Debug, Default)]
pub struct SectionMesh {
    /// Node coordinates.
    pub nodes: Vec<P2>,
    /// Quads, counter-clockwise.
    pub quads: Vec<[usize; 4]>,
    /// Part id per quad (material / region).
    pub quad_part: Vec<u32>,
    /// Named node tags.
    pub tags: BTreeMap<String, Vec<usize>>,
    merge_tolerance: f64,
    buckets: HashMap<(i64, i64), Vec<usize>>,
}

impl SectionMesh {
    /// Empty mesh; points closer than `merge_tolerance` are one node.
    pub fn new(merge_tolerance: f64) -> Self {
        SectionMesh {
            merge_tolerance,
            ..Default::default()
        }
    }

    fn bucket(&self, p: P2) -> (i64, i64) {
        let cell = self.merge_tolerance * 16.0;
        ((p[0] / cell).floor() as i64, (p[1] / cell).floor() as i64)
    }

    /// Index of the node at `p`, created if no node lies within the merge tolerance.
    pub fn add_node(&mut self, p: P2) -> usize {
        let (bx, by) = self.bucket(p);
        for dx in -1..=1 {
            for dy in -1..=1 {
                if let Some(list) = self.buckets.get(&(bx + dx, by + dy)) {
                    for &i in list {
                        let q = self.nodes[i];
                        if (q[0] - p[0]).abs() <= self.merge_tolerance
                            && (q[1] - p[1]).abs() <= self.merge_tolerance
                        {
                            return i;
                        }
                    }
                }
            }
        }
        let i = self.nodes.len();
        self.nodes.push(p);
        self.buckets.entry((bx, by)).or_default().push(i);
        i
    }

    /// Add a structured grid `grid[i][j]` (i along the first direction, j along the second) as
    /// quads of `part`; returns the node index grid. Quads are oriented counter-clockwise.
    pub fn add_grid(&mut self, grid: &[Vec<P2>], part: u32) -> Vec<Vec<usize>> {
        let ids: Vec<Vec<usize>> = grid
            .iter()
            .map(|col| col.iter().map(|&p| self.add_node(p)).collect())
            .collect();
        for i in 0..ids.len().saturating_sub(1) {
            for j in 0..ids[i].len().saturating_sub(1) {
                self.add_quad(
                    [ids[i][j], ids[i + 1][j], ids[i + 1][j + 1], ids[i][j + 1]],
                    part,
                );
            }
        }
        ids
    }

    /// Add one quad, reordered counter-clockwise if needed.
    pub fn add_quad(&mut self, mut q: [usize; 4], part: u32) {
        if self.signed_area(q) < 0.0 {
            q.reverse();
        }
        self.quads.push(q);
        self.quad_part.push(part);
    }

    /// Signed area of a quad (positive when counter-clockwise).
    pub fn signed_area(&self, q: [usize; 4]) -> f64 {
        let mut a = 0.0;
        for k in 0..4 {
            let p = self.nodes[q[k]];
            let r = self.nodes[q[(k + 1) % 4]];
            a += p[0] * r[1] - r[0] * p[1];
        }
        0.5 * a
    }

    /// Add node ids to a named tag.
    pub fn tag(&mut self, name: &str, ids: impl IntoIterator<Item = usize>) {
        let list = self.tags.entry(name.to_string()).or_default();
        list.extend(ids);
        list.sort_unstable();
        list.dedup();
    }

    /// Laplacian smoothing of the interior nodes (boundary nodes, those on an edge used by one
    /// quad, stay fixed): each node moves to the mean of its edge neighbours, a move being kept
    /// only if it does not lower the worst scaled corner angle of the quads around the node.
    /// Evens out the slivers an O-grid leaves at its core corners.
    pub fn smooth(&mut self, iterations: usize) {
        let n = self.nodes.len();
        let mut edge_count: HashMap<(usize, usize), u32> = HashMap::new();
        let mut neighbours: Vec<Vec<usize>> = vec![Vec::new(); n];
        let mut quads_of: Vec<Vec<usize>> = vec![Vec::new(); n];
        for (qi, q) in self.quads.iter().enumerate() {
            for k in 0..4 {
                let (a, b) = (q[k], q[(k + 1) % 4]);
                *edge_count.entry((a.min(b), a.max(b))).or_insert(0) += 1;
                neighbours[a].push(b);
                neighbours[b].push(a);
                quads_of[a].push(qi);
            }
        }
        let mut fixed = vec![false; n];
        for (&(a, b), &c) in &edge_count {
            if c == 1 {
                fixed[a] = true;
                fixed[b] = true;
            }
        }
        for list in &mut neighbours {
            list.sort_unstable();
            list.dedup();
        }
        let quality = |nodes: &[P2], q: &[usize; 4]| -> f64 {
            let mut worst = f64::INFINITY;
            for k in 0..4 {
                let p = nodes[q[k]];
                let a = nodes[q[(k + 1) % 4]];
                let b = nodes[q[(k + 3) % 4]];
                let cross = (a[0] - p[0]) * (b[1] - p[1]) - (a[1] - p[1]) * (b[0] - p[0]);
                worst = worst.min(
                    cross
                        / ((a[0] - p[0]).hypot(a[1] - p[1]) * (b[0] - p[0]).hypot(b[1] - p[1]))
                            .max(1e-300),
                );
            }
            worst
        };
        for _ in 0..iterations {
            for i in 0..n {
                if fixed[i] || neighbours[i].is_empty() {
                    continue;
                }
                let m = neighbours[i].len() as f64;
                let target = [
                    neighbours[i].iter().map(|&j| self.nodes[j][0]).sum::<f64>() / m,
                    neighbours[i].iter().map(|&j| self.nodes[j][1]).sum::<f64>() / m,
                ];
                let before = quads_of[i]
                    .iter()
                    .map(|&qi| quality(&self.nodes, &self.quads[qi]))
                    .fold(f64::INFINITY, f64::min);
                let old = self.nodes[i];
                self.nodes[i] = target;
                let after = quads_of[i]
                    .iter()
                    .map(|&qi| quality(&self.nodes, &self.quads[qi]))
                    .fold(f64::INFINITY, f64::min);
                if after < before.min(0.3) {
                    self.nodes[i] = old;
                }
            }
        }
    }

    /// Drop nodes that no quad uses (e.g. outline nodes of cells left out for a band),
    /// renumbering quads and tags.
    pub fn remove_unused_nodes(&mut self) {
        let mut used = vec![false; self.nodes.len()];
        for q in &self.quads {
            for &i in q {
                used[i] = true;
            }
        }
        let mut new_id = vec![usize::MAX; self.nodes.len()];
        let mut kept = Vec::new();
        for (i, p) in self.nodes.iter().enumerate() {
            if used[i] {
                new_id[i] = kept.len();
                kept.push(*p);
            }
        }
        self.nodes = kept;
        for q in &mut self.quads {
            *q = q.map(|i| new_id[i]);
        }
        for ids in self.tags.values_mut() {
            *ids = ids
                .iter()
                .filter(|&&i| used[i])
                .map(|&i| new_id[i])
                .collect();
        }
        self.buckets.clear();
        let nodes = std::mem::take(&mut self.nodes);
        for (i, p) in nodes.iter().enumerate() {
            let key = self.bucket(*p);
            self.buckets.entry(key).or_default().push(i);
        }
        self.nodes = nodes;
    }

    /// Total area.
    pub fn area(&self) -> f64 {
        self.quads.iter().map(|q| self.signed_area(*q)).sum()
    }
}

/// A polyline with arc-length parametrisation.
#[derive(Clone, Debug)]
pub struct Polyline {
    points: Vec<P2>,
    cumulative: Vec<f64>,
}

impl Polyline {
    /// Polyline through `points` (at least 2).
    pub fn new(points: Vec<P2>) -> Self {
        let mut cumulative = vec![0.0];
        for w in points.windows(2) {
            let last = *cumulative.last().unwrap_or(&0.0);
            cumulative.push(last + (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]));
        }
        Polyline { points, cumulative }
    }
    /// Straight segment.
    pub fn segment(a: P2, b: P2) -> Self {
        Polyline::new(vec![a, b])
    }
    /// Total length.
    pub fn length(&self) -> f64 {
        *self.cumulative.last().unwrap_or(&0.0)
    }
    /// First point.
    pub fn start(&self) -> P2 {
        self.points[0]
    }
    /// Last point.
    pub fn end(&self) -> P2 {
        self.points[self.points.len() - 1]
    }
    /// Point at arc length `s` (clamped).
    pub fn at_length(&self, s: f64) -> P2 {
        let s = s.clamp(0.0, self.length());
        let k = match self.cumulative.binary_search_by(|c| c.total_cmp(&s)) {
            Ok(k) => return self.points[k],
            Err(k) => k.clamp(1, self.points.len() - 1),
        };
        let (s0, s1) = (self.cumulative[k - 1], self.cumulative[k]);
        let t = if s1 > s0 { (s - s0) / (s1 - s0) } else { 0.0 };
        let (a, b) = (self.points[k - 1], self.points[k]);
        [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]
    }
    /// Point at fraction `t` of the length.
    pub fn at_fraction(&self, t: f64) -> P2 {
        self.at_length(t * self.length())
    }
    /// Arc length of the point of the polyline nearest to `p`.
    pub fn length_at_nearest(&self, p: P2) -> f64 {
        let mut best = (f64::INFINITY, 0.0);
        for (k, w) in self.points.windows(2).enumerate() {
            let d = [w[1][0] - w[0][0], w[1][1] - w[0][1]];
            let len2 = d[0] * d[0] + d[1] * d[1];
            let t = if len2 > 0.0 {
                (((p[0] - w[0][0]) * d[0] + (p[1] - w[0][1]) * d[1]) / len2).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let q = [w[0][0] + t * d[0], w[0][1] + t * d[1]];
            let dist = (q[0] - p[0]).hypot(q[1] - p[1]);
            if dist < best.0 {
                best = (dist, self.cumulative[k] + t * len2.sqrt());
            }
        }
        best.1
    }
    /// Concatenate polylines (end of one = start of the next).
    pub fn join(parts: &[Polyline]) -> Polyline {
        let mut pts: Vec<P2> = Vec::new();
        for part in parts {
            for &p in &part.points {
                if pts
                    .last()
                    .is_none_or(|q: &P2| (q[0] - p[0]).hypot(q[1] - p[1]) > 1e-15)
                {
                    pts.push(p);
                }
            }
        }
        Polyline::new(pts)
    }
    /// The part between arc lengths `s0 < s1`.
    pub fn slice(&self, s0: f64, s1: f64) -> Polyline {
        let mut pts = vec![self.at_length(s0)];
        for (k, &c) in self.cumulative.iter().enumerate() {
            if c > s0 && c < s1 {
                pts.push(self.points[k]);
            }
        }
        pts.push(self.at_length(s1));
        Polyline::new(pts)
    }
    /// Points at the given fractions of the length.
    pub fn sample(&self, fractions: &[f64]) -> Vec<P2> {
        fractions.iter().map(|&t| self.at_fraction(t)).collect()
    }
}

fn lerp(a: P2, b: P2, t: f64) -> P2 {
    [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]
}

/// Normalised cumulative chord length of a point list (0 .. 1).
fn chord_fractions(points: &[P2]) -> Vec<f64> {
    let mut c = vec![0.0];
    for w in points.windows(2) {
        let last = *c.last().unwrap_or(&0.0);
        c.push(last + (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]));
    }
    let total = c.last().copied().unwrap_or(1.0).max(1e-300);
    c.iter().map(|v| v / total).collect()
}

/// Transfinite (Coons) patch from four boundary point lists: `bottom` and `top` left to right
/// (same length), `left` and `right` bottom to top (same length); corners must coincide.
/// Returns `grid[i][j]`, i along bottom/top, j along left/right.
pub fn coons_patch(bottom: &[P2], top: &[P2], left: &[P2], right: &[P2]) -> Vec<Vec<P2>> {
    let ni = bottom.len();
    let nj = left.len();
    let (fb, ft) = (chord_fractions(bottom), chord_fractions(top));
    let (fl, fr) = (chord_fractions(left), chord_fractions(right));
    let (p00, p10, p01, p11) = (bottom[0], bottom[ni - 1], top[0], top[ni - 1]);
    let mut grid = vec![vec![[0.0; 2]; nj]; ni];
    for i in 0..ni {
        for j in 0..nj {
            if j == 0 {
                grid[i][j] = bottom[i];
                continue;
            }
            if j == nj - 1 {
                grid[i][j] = top[i];
                continue;
            }
            if i == 0 {
                grid[i][j] = left[j];
                continue;
            }
            if i == ni - 1 {
                grid[i][j] = right[j];
                continue;
            }
            // Blend parameters: the side fractions interpolated across the patch, so that
            // graded boundary distributions carry into the interior.
            let v = (1.0 - fb[i]) * fl[j] + fb[i] * fr[j];
            let u = (1.0 - v) * fb[i] + v * ft[i];
            let v = (1.0 - u) * fl[j] + u * fr[j];
            let mut p = [0.0; 2];
            for d in 0..2 {
                p[d] = (1.0 - v) * bottom[i][d]
                    + v * top[i][d]
                    + (1.0 - u) * left[j][d]
                    + u * right[j][d]
                    - ((1.0 - u) * (1.0 - v) * p00[d]
                        + u * (1.0 - v) * p10[d]
                        + (1.0 - u) * v * p01[d]
                        + u * v * p11[d]);
            }
            grid[i][j] = p;
        }
    }
    grid
}

/// An O-grid: a ring of quads between a closed outline and an inner rectangle ("core"), plus
/// the core itself. The outline is given as four sides (counter-clockwise, side k from anchor k
/// to anchor k+1); the core corners `core[k]` correspond to the anchors. Opposite sides must
/// have the same node count.
pub struct OGrid {
    /// Outline sides as polylines.
    pub sides: [Polyline; 4],
    /// Core rectangle corners (counter-clockwise, matching the anchors).
    pub core: [P2; 4],
    /// Node fractions along each side (0..1, both ends included).
    pub side_fractions: [Vec<f64>; 4],
    /// Ring rows, per side, as fractions of the way from the outline (0) to the core (1), both
    /// included; all four lists have the same length. Different sides may grade differently
    /// (fine rows only under a running surface).
    pub ring_fractions: [Vec<f64>; 4],
}

/// Node indices of a meshed O-grid.
pub struct OGridNodes {
    /// `ring[i][k]`: perimeter position i (all sides concatenated, periodic, first = anchor 0),
    /// ring row k (0 = outline).
    pub ring: Vec<Vec<usize>>,
    /// Perimeter index of the first node of each side.
    pub side_start: [usize; 4],
}

impl OGrid {
    /// Outline point and matching core point at fraction `t` of side `k`.
    pub fn outline_and_core(&self, side: usize, t: f64) -> (P2, P2) {
        (
            self.sides[side].at_fraction(t),
            lerp(self.core[side], self.core[(side + 1) % 4], t),
        )
    }

    /// Point of the map at side `k`, fraction `t` along it, ring fraction `s` (0 outline).
    pub fn point(&self, side: usize, t: f64, s: f64) -> P2 {
        let (o, c) = self.outline_and_core(side, t);
        lerp(o, c, s)
    }

    /// Mesh the O-grid into `mesh` with part id `part`. Cells for which `skip_ring_cell(side,
    /// index_in_side, row)` is true are left out (to make room for a separately meshed band).
    pub fn mesh(
        &self,
        mesh: &mut SectionMesh,
        part: u32,
        skip_ring_cell: impl Fn(usize, usize, usize) -> bool,
    ) -> OGridNodes {
        let rows = self.ring_fractions[0].len();
        let mut ring: Vec<Vec<usize>> = Vec::new();
        let mut side_start = [0usize; 4];
        let mut cell_owner: Vec<(usize, usize)> = Vec::new();
        for (side, start) in side_start.iter_mut().enumerate() {
            *start = ring.len();
            let fr = &self.side_fractions[side];
            for (idx, &t) in fr.iter().enumerate().take(fr.len() - 1) {
                let column: Vec<usize> = self.ring_fractions[side]
                    .iter()
                    .map(|&s| mesh.add_node(self.point(side, t, s)))
                    .collect();
                ring.push(column);
                cell_owner.push((side, idx));
            }
        }
        let n = ring.len();
        for i in 0..n {
            let (side, idx) = cell_owner[i];
            for k in 0..rows - 1 {
                if skip_ring_cell(side, idx, k) {
                    continue;
                }
                let a = ring[i][k];
                let b = ring[(i + 1) % n][k];
                let c = ring[(i + 1) % n][k + 1];
                let d = ring[i][k + 1];
                mesh.add_quad([a, b, c, d], part);
            }
        }
        // Core: Coons patch of the rectangle with the side distributions.
        let bottom: Vec<P2> = self.side_fractions[0]
            .iter()
            .map(|&t| lerp(self.core[0], self.core[1], t))
            .collect();
        let right: Vec<P2> = self.side_fractions[1]
            .iter()
            .map(|&t| lerp(self.core[1], self.core[2], t))
            .collect();
        let top: Vec<P2> = self.side_fractions[2]
            .iter()
            .rev()
            .map(|&t| lerp(self.core[2], self.core[3], t))
            .collect();
        let left: Vec<P2> = self.side_fractions[3]
            .iter()
            .rev()
            .map(|&t| lerp(self.core[3], self.core[0], t))
            .collect();
        let grid = coons_patch(&bottom, &top, &left, &right);
        mesh.add_grid(&grid, part);
        OGridNodes { ring, side_start }
    }
}

/// Fractions (0..1) for `n` intervals with geometric growth `ratio` from the start
/// (ratio > 1: fine at the start).
pub fn geometric_fractions(n: usize, ratio: f64) -> Vec<f64> {
    let n = n.max(1);
    let mut sizes: Vec<f64> = (0..n).map(|k| ratio.powi(k as i32)).collect();
    let total: f64 = sizes.iter().sum();
    sizes.iter_mut().for_each(|s| *s /= total);
    let mut out = vec![0.0];
    for s in sizes {
        let last = *out.last().unwrap_or(&0.0);
        out.push(last + s);
    }
    if let Some(last) = out.last_mut() {
        *last = 1.0;
    }
    out
}
