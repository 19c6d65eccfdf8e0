//! Tied interfaces between non-matching meshes (the fine tread band on the coarser wheel body).
//!
//! Each slave node is bound to a point of a master quad face: its displacement is the bilinear
//! interpolation `u_s = sum_i N_i(xi, eta) u_i` of the face's four nodes. This module only finds
//! the pairs (geometry); the explicit solver enforces the constraint and distributes the slave
//! node's force and mass back to the master nodes with the same weights.

use std::collections::HashMap;

use super::hex::P3;

/// One slave node bound to a master face.
#[derive(Clone, Debug, PartialEq)]
pub struct TiePair {
    /// Slave node.
    pub slave: usize,
    /// Master face nodes.
    pub master: [usize; 4],
    /// Bilinear weights of the master nodes (sum to 1).
    pub weights: [f64; 4],
    /// Distance from the slave node to its projection on the face (m): the geometric offset
    /// kept by the tie.
    pub gap_m: f64,
}

/// A tied interface.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TiedInterface {
    /// Name (e.g. "tread_band").
    pub name: String,
    /// Pairs.
    pub pairs: Vec<TiePair>,
}

impl TiedInterface {
    pub(crate) fn shifted(mut self, offset: usize) -> Self {
        for p in &mut self.pairs {
            p.slave += offset;
            p.master = p.master.map(|n| n + offset);
        }
        self
    }
    pub(crate) fn renumber(&mut self, new_id: &[usize]) {
        for p in &mut self.pairs {
            p.slave = new_id[p.slave];
            p.master = p.master.map(|n| new_id[n]);
        }
    }
    /// Largest slave-to-face distance (m).
    pub fn max_gap_m(&self) -> f64 {
        self.pairs.iter().map(|p| p.gap_m).fold(0.0, f64::max)
    }
}

fn bilinear(face: &[P3; 4], xi: f64, eta: f64) -> (P3, [f64; 4], [P3; 2]) {
    let n = [
        0.25 * (1.0 - xi) * (1.0 - eta),
        0.25 * (1.0 + xi) * (1.0 - eta),
        0.25 * (1.0 + xi) * (1.0 + eta),
        0.25 * (1.0 - xi) * (1.0 + eta),
    ];
    let dxi = [
        -0.25 * (1.0 - eta),
        0.25 * (1.0 - eta),
        0.25 * (1.0 + eta),
        -0.25 * (1.0 + eta),
    ];
    let deta = [
        -0.25 * (1.0 - xi),
        -0.25 * (1.0 + xi),
        0.25 * (1.0 + xi),
        0.25 * (1.0 - xi),
    ];
    let mut p = [0.0; 3];
    let mut t = [[0.0; 3]; 2];
    for k in 0..4 {
        for d in 0..3 {
            p[d] += n[k] * face[k][d];
            t[0][d] += dxi[k] * face[k][d];
            t[1][d] += deta[k] * face[k][d];
        }
    }
    (p, n, t)
}

/// Closest point of a bilinear face to `x` by Gauss-Newton on (xi, eta), clamped to the face.
/// Returns (xi, eta, weights, distance).
pub fn project_on_face(face: &[P3; 4], x: P3) -> (f64, f64, [f64; 4], f64) {
    let (mut xi, mut eta) = (0.0f64, 0.0f64);
    for _ in 0..30 {
        let (p, _, t) = bilinear(face, xi, eta);
        let r = [x[0] - p[0], x[1] - p[1], x[2] - p[2]];
        let g0 = t[0][0] * r[0] + t[0][1] * r[1] + t[0][2] * r[2];
        let g1 = t[1][0] * r[0] + t[1][1] * r[1] + t[1][2] * r[2];
        let a00 = t[0].iter().map(|v| v * v).sum::<f64>();
        let a11 = t[1].iter().map(|v| v * v).sum::<f64>();
        let a01 = t[0][0] * t[1][0] + t[0][1] * t[1][1] + t[0][2] * t[1][2];
        let det = a00 * a11 - a01 * a01;
        if det.abs() < 1e-300 {
            break;
        }
        let dxi = (a11 * g0 - a01 * g1) / det;
        let deta = (a00 * g1 - a01 * g0) / det;
        let (xi_new, eta_new) = ((xi + dxi).clamp(-1.0, 1.0), (eta + deta).clamp(-1.0, 1.0));
        // Stop on the actual (clamped) step: a point beyond the face edge converges to the edge.
        let moved = (xi_new - xi).abs() + (eta_new - eta).abs();
        xi = xi_new;
        eta = eta_new;
        if moved < 1e-12 {
            break;
        }
    }
    let (p, n, _) = bilinear(face, xi, eta);
    let d = ((x[0] - p[0]).powi(2) + (x[1] - p[1]).powi(2) + (x[2] - p[2]).powi(2)).sqrt();
    (xi, eta, n, d)
}

/// Tie each of `slaves` (node ids into `nodes`) to the nearest of `master_faces`.
pub fn build(
    name: &str,
    nodes: &[P3],
    slaves: &[usize],
    master_faces: &[[usize; 4]],
) -> TiedInterface {
    if master_faces.is_empty() || slaves.is_empty() {
        return TiedInterface {
            name: name.to_string(),
            pairs: vec![],
        };
    }
    // Bucket each face into every cell its bounding box (grown by a margin for the geometric
    // offsets a tie bridges) overlaps; the cell size is the median face size, so graded meshes
    // (1 mm faces beside 100 mm ones) keep buckets short. A slave then looks in its own cell only.
    let mut sizes: Vec<f64> = master_faces
        .iter()
        .map(|f| {
            let (a, b) = (nodes[f[0]], nodes[f[2]]);
            ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
        })
        .collect();
    sizes.sort_by(|a, b| a.total_cmp(b));
    let cell = sizes[sizes.len() / 2].max(1e-9);
    let margin = 0.25 * cell;
    let key = |p: P3| {
        (
            (p[0] / cell).floor() as i64,
            (p[1] / cell).floor() as i64,
            (p[2] / cell).floor() as i64,
        )
    };
    let mut buckets: HashMap<(i64, i64, i64), Vec<usize>> = HashMap::new();
    for (fi, f) in master_faces.iter().enumerate() {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for &n in f {
            for d in 0..3 {
                lo[d] = lo[d].min(nodes[n][d] - margin);
                hi[d] = hi[d].max(nodes[n][d] + margin);
            }
        }
        let (k0, k1) = (key(lo), key(hi));
        for i in k0.0..=k1.0 {
            for j in k0.1..=k1.1 {
                for k in k0.2..=k1.2 {
                    buckets.entry((i, j, k)).or_default().push(fi);
                }
            }
        }
    }
    let mut pairs = Vec::with_capacity(slaves.len());
    for &s in slaves {
        let x = nodes[s];
        let mut best: Option<(f64, usize, [f64; 4])> = None;
        if let Some(list) = buckets.get(&key(x)) {
            for &fi in list {
                let coords = master_faces[fi].map(|n| nodes[n]);
                // Cheap rejection: the point must be within the face's grown bounding box.
                let outside = (0..3).any(|d| {
                    let lo = coords.iter().map(|c| c[d]).fold(f64::INFINITY, f64::min) - margin;
                    let hi = coords
                        .iter()
                        .map(|c| c[d])
                        .fold(f64::NEG_INFINITY, f64::max)
                        + margin;
                    x[d] < lo || x[d] > hi
                });
                if outside {
                    continue;
                }
                let (_, _, w, d) = project_on_face(&coords, x);
                if best.is_none_or(|b| d < b.0) {
                    best = Some((d, fi, w));
                }
            }
        }
        if let Some((d, fi, w)) = best {
            pairs.push(TiePair {
                slave: s,
                master: master_faces[fi],
                weights: w,
                gap_m: d,
            });
        }
    }
    TiedInterface {
        name: name.to_string(),
        pairs,
    }
}
