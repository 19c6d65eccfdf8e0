//! The prolongator of the two-level preconditioner: on each aggregate, the six rigid-body
//! motions of its nodes (three translations, three rotations about its centroid), zero in held
//! directions and orthonormalised (modified Gram-Schmidt, twice; a motion the aggregate cannot
//! distinguish from the others, such as the rotation about the line through two nodes, is
//! dropped). `P` maps an aggregate's coarse unknowns to its nodes; with it come the
//! restriction `Pᵀ r`, the prolongation `P e` and the Galerkin coarse matrix `A_c = Pᵀ A P`.
//!
//! `A_c` is positive definite when `A` is and `P` has full column rank, which the
//! orthonormalisation ensures.

use faer::sparse::{SparseColMat, SymbolicSparseColMat};
use rayon::prelude::*;

use super::aggregation::Aggregates;
use super::block_matrix::BlockMatrix;
use crate::{Error, Result};

/// Most coarse unknowns per aggregate (three translations, three rotations).
pub const MODES: usize = 6;

/// Relative norm below which a motion counts as dependent on the ones before it.
const DEPENDENT: f64 = 1e-8;

/// The prolongator `P`, one 3 x 6 block per node (its aggregate's motions at that node).
pub struct Prolongator {
    /// Aggregate of each node.
    of_node: Vec<u32>,
    /// Nodes of each aggregate.
    members: Vec<Vec<u32>>,
    /// First coarse unknown of each aggregate (and the total at the end).
    start: Vec<usize>,
    /// Per node: its rows of `P` (`p[node][d][j]`, direction `d`, the aggregate's motion `j`).
    p: Vec<[[f64; MODES]; 3]>,
}

impl Prolongator {
    /// The prolongator of `aggregates` for nodes at `coords_m` with held directions `held`,
    /// for a matrix of `a`'s nodes.
    pub fn new(
        a: &BlockMatrix,
        aggregates: &Aggregates,
        coords_m: &[[f64; 3]],
        held: &[[bool; 3]],
    ) -> Result<Prolongator> {
        let n = a.nodes();
        if coords_m.len() != n || held.len() != n || aggregates.of_node.len() != n {
            return Err(Error::input(
                "prolongator",
                "nodes",
                format!(
                    "{} coordinates, {} held flags and {} aggregate numbers for {n} nodes",
                    coords_m.len(),
                    held.len(),
                    aggregates.of_node.len()
                ),
            ));
        }
        let members = aggregates.members();
        let mut p = vec![[[0.0; MODES]; 3]; n];
        let kept: Vec<usize> = {
            // Each aggregate's block of P, computed aside and written to its nodes' rows.
            let blocks: Vec<(Vec<f64>, usize)> = members
                .par_iter()
                .map(|nodes| rigid_modes(nodes, coords_m, held))
                .collect();
            let mut kept = Vec::with_capacity(members.len());
            for (nodes, (q, k)) in members.iter().zip(&blocks) {
                let rows = 3 * nodes.len();
                for (m, &nd) in nodes.iter().enumerate() {
                    for d in 0..3 {
                        for j in 0..*k {
                            p[nd as usize][d][j] = q[j * rows + 3 * m + d];
                        }
                    }
                }
                kept.push(*k);
            }
            kept
        };
        let mut start = Vec::with_capacity(kept.len() + 1);
        start.push(0);
        for k in &kept {
            start.push(start.last().copied().unwrap_or(0) + k);
        }
        Ok(Prolongator {
            of_node: aggregates.of_node.clone(),
            members,
            start,
            p,
        })
    }

    /// Coarse unknowns.
    pub fn unknowns(&self) -> usize {
        self.start.last().copied().unwrap_or(0)
    }

    /// Aggregates.
    pub fn aggregates(&self) -> usize {
        self.members.len()
    }

    fn kept(&self, g: usize) -> usize {
        self.start[g + 1] - self.start[g]
    }

    /// `A_c = Pᵀ A P`, lower triangle. Column block `H` (an aggregate) gathers the blocks
    /// `A_cr` of its nodes `c` for nodes `r` of aggregates `G >= H`: each column block is
    /// computed by one task, in a fixed order.
    pub fn galerkin(&self, a: &BlockMatrix) -> Result<SparseColMat<usize, f64>> {
        let count = self.members.len();
        // Per aggregate H: the aggregates G >= H it couples to (sorted) and the dense block
        // column (rows: G's unknowns in turn; columns: H's), column major.
        let columns: Vec<(Vec<u32>, Vec<f64>)> = (0..count)
            .into_par_iter()
            .map(|h| {
                let mut coupled: Vec<u32> = Vec::new();
                for &c in &self.members[h] {
                    let (cols, _) = a.row(c as usize);
                    coupled.extend(
                        cols.iter()
                            .map(|&r| self.of_node[r as usize])
                            .filter(|&g| g as usize >= h),
                    );
                }
                coupled.sort_unstable();
                coupled.dedup();
                let mut offset = Vec::with_capacity(coupled.len() + 1);
                offset.push(0usize);
                for &g in &coupled {
                    offset.push(offset.last().copied().unwrap_or(0) + self.kept(g as usize));
                }
                let rows = offset.last().copied().unwrap_or(0);
                let kh = self.kept(h);
                let mut dense = vec![0.0; rows * kh];
                for &c in &self.members[h] {
                    let pc = &self.p[c as usize];
                    let (cols, blocks) = a.row(c as usize);
                    for (&r, b) in cols.iter().zip(blocks) {
                        let g = self.of_node[r as usize] as usize;
                        if g < h {
                            continue;
                        }
                        let Ok(slot) = coupled.binary_search(&(g as u32)) else {
                            continue;
                        };
                        let pr = &self.p[r as usize];
                        let kg = self.kept(g);
                        // (P_cᵀ A_cr P_r)ᵀ = P_rᵀ A_rc P_c, added at rows of G, columns of H.
                        // A_cr P_r first (3 x kg).
                        let mut ap = [[0.0; MODES]; 3];
                        for d in 0..3 {
                            for i in 0..kg {
                                ap[d][i] =
                                    b[d][0] * pr[0][i] + b[d][1] * pr[1][i] + b[d][2] * pr[2][i];
                            }
                        }
                        for j in 0..kh {
                            let col =
                                &mut dense[j * rows + offset[slot]..j * rows + offset[slot] + kg];
                            for (i, v) in col.iter_mut().enumerate() {
                                *v +=
                                    pc[0][j] * ap[0][i] + pc[1][j] * ap[1][i] + pc[2][j] * ap[2][i];
                            }
                        }
                    }
                }
                (coupled, dense)
            })
            .collect();
        // Scalar lower compressed columns.
        let n = self.unknowns();
        let mut col_ptr = Vec::with_capacity(n + 1);
        col_ptr.push(0usize);
        let mut row_idx = Vec::new();
        let mut values = Vec::new();
        for (h, (coupled, dense)) in columns.iter().enumerate() {
            let kh = self.kept(h);
            let rows = dense.len() / kh.max(1);
            for j in 0..kh {
                let mut local = 0;
                for &g in coupled {
                    let g = g as usize;
                    for i in 0..self.kept(g) {
                        if g > h || i >= j {
                            row_idx.push(self.start[g] + i);
                            values.push(dense[j * rows + local + i]);
                        }
                    }
                    local += self.kept(g);
                }
                col_ptr.push(row_idx.len());
            }
        }
        let symbolic = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);
        Ok(SparseColMat::new(symbolic, values))
    }

    /// `out = Pᵀ r` (`r`: 3 per node).
    pub fn restrict(&self, r: &[f64], out: &mut [f64]) {
        let parts: Vec<[f64; MODES]> = self
            .members
            .par_iter()
            .map(|nodes| {
                let mut s = [0.0; MODES];
                for &nd in nodes {
                    let pn = &self.p[nd as usize];
                    let rn = &r[3 * nd as usize..3 * nd as usize + 3];
                    for j in 0..MODES {
                        s[j] += pn[0][j] * rn[0] + pn[1][j] * rn[1] + pn[2][j] * rn[2];
                    }
                }
                s
            })
            .collect();
        for (g, s) in parts.iter().enumerate() {
            let k = self.kept(g);
            out[self.start[g]..self.start[g] + k].copy_from_slice(&s[..k]);
        }
    }

    /// `x += P e` (`e`: the coarse unknowns).
    pub fn prolongate_add(&self, e: &[f64], x: &mut [f64]) {
        x.par_chunks_mut(3).enumerate().for_each(|(nd, xn)| {
            let g = self.of_node[nd] as usize;
            let (s, k) = (self.start[g], self.kept(g));
            let pn = &self.p[nd];
            for d in 0..3 {
                let mut v = 0.0;
                for j in 0..k {
                    v += pn[d][j] * e[s + j];
                }
                xn[d] += v;
            }
        });
    }
}

/// The orthonormalised rigid-body motions of an aggregate: `(q, k)` with `q` column major,
/// `3 m` rows (node-major, direction-minor) and `k <= 6` kept columns.
fn rigid_modes(nodes: &[u32], coords_m: &[[f64; 3]], held: &[[bool; 3]]) -> (Vec<f64>, usize) {
    let m = nodes.len();
    let rows = 3 * m;
    let mut centre = [0.0; 3];
    for &nd in nodes {
        for d in 0..3 {
            centre[d] += coords_m[nd as usize][d] / m as f64;
        }
    }
    let mut q = vec![0.0; MODES * rows];
    for (i, &nd) in nodes.iter().enumerate() {
        let x = coords_m[nd as usize];
        let rel = [x[0] - centre[0], x[1] - centre[1], x[2] - centre[2]];
        // Translations; rotations `e_a x rel` about the centroid.
        let motion: [[f64; 3]; MODES] = [
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [0.0, -rel[2], rel[1]],
            [rel[2], 0.0, -rel[0]],
            [-rel[1], rel[0], 0.0],
        ];
        for (j, v) in motion.iter().enumerate() {
            for d in 0..3 {
                if !held[nd as usize][d] {
                    q[j * rows + 3 * i + d] = v[d];
                }
            }
        }
    }
    // Modified Gram-Schmidt, each column twice against the kept ones ("twice is enough").
    let mut kept = 0;
    for j in 0..MODES {
        let mut col: Vec<f64> = q[j * rows..(j + 1) * rows].to_vec();
        let original = col.iter().map(|v| v * v).sum::<f64>().sqrt();
        if original == 0.0 {
            continue;
        }
        for _ in 0..2 {
            for k in 0..kept {
                let basis = &q[k * rows..(k + 1) * rows];
                let dot: f64 = basis.iter().zip(&col).map(|(b, c)| b * c).sum();
                col.iter_mut().zip(basis).for_each(|(c, b)| *c -= dot * b);
            }
        }
        let norm = col.iter().map(|v| v * v).sum::<f64>().sqrt();
        if norm <= DEPENDENT * original {
            continue;
        }
        col.iter_mut().for_each(|c| *c /= norm);
        q[kept * rows..(kept + 1) * rows].copy_from_slice(&col);
        kept += 1;
    }
    (q, kept)
}
