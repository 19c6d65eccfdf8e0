//! Nodes grouped into aggregates along strong couplings (Vaněk, Mandel & Brezina 1996, the
//! three passes of their greedy aggregation).
//!
//! A coupling `i - j` is strong when `|A_ij|_F > theta sqrt(|A_ii|_F |A_jj|_F)` (Frobenius norms
//! of the 3 x 3 blocks): on an elastic mesh every element neighbour is strong, while a soft
//! spring between two bodies (a ballast spring) is not, and an aggregate does not straddle it.
//!
//! 1. A node whose strong neighbours are all free starts an aggregate of itself and them (on a
//!    hexahedral mesh about 27 nodes, 3 x 3 x 3).
//! 2. A node left over joins the aggregate of its strongest neighbour from pass 1.
//! 3. Nodes still left form aggregates with their free strong neighbours; a node with no strong
//!    neighbour at all (a node whose every direction is held) is an aggregate of its own.

// The passes index several per-node arrays by the node number.
#![allow(clippy::needless_range_loop)]

use super::block_matrix::{Block3, BlockMatrix};

/// The aggregate of each node.
#[derive(Clone, Debug)]
pub struct Aggregates {
    /// Aggregate of each node.
    pub of_node: Vec<u32>,
    /// Number of aggregates.
    pub count: usize,
}

const FREE: u32 = u32::MAX;

fn frobenius(b: &Block3) -> f64 {
    b.iter().flatten().map(|v| v * v).sum::<f64>().sqrt()
}

impl Aggregates {
    /// Aggregates of the matrix's node graph with strength threshold `theta` (>= 0).
    pub fn new(a: &BlockMatrix, theta: f64) -> Aggregates {
        let n = a.nodes();
        let diagonal: Vec<f64> = (0..n).map(|r| frobenius(a.diagonal_block(r))).collect();
        // Strong neighbours of each node, with their strength (compressed rows).
        let mut ptr = vec![0usize];
        let mut neighbours: Vec<(u32, f64)> = Vec::new();
        for r in 0..n {
            let (cols, blocks) = a.row(r);
            for (&c, b) in cols.iter().zip(blocks) {
                let c_us = c as usize;
                if c_us == r {
                    continue;
                }
                let s = frobenius(b);
                let scale = (diagonal[r] * diagonal[c_us]).sqrt();
                if s > theta * scale && s > 0.0 {
                    neighbours.push((c, s / scale.max(f64::MIN_POSITIVE)));
                }
            }
            ptr.push(neighbours.len());
        }
        let strong = |r: usize| &neighbours[ptr[r]..ptr[r + 1]];
        let mut of_node = vec![FREE; n];
        let mut count = 0u32;
        // Pass 1: whole neighbourhoods.
        for r in 0..n {
            if of_node[r] != FREE || strong(r).is_empty() {
                continue;
            }
            if strong(r).iter().all(|&(c, _)| of_node[c as usize] == FREE) {
                of_node[r] = count;
                for &(c, _) in strong(r) {
                    of_node[c as usize] = count;
                }
                count += 1;
            }
        }
        // Pass 2: join the strongest neighbour's pass-1 aggregate.
        let first_pass = of_node.clone();
        for r in 0..n {
            if of_node[r] != FREE {
                continue;
            }
            let best = strong(r)
                .iter()
                .filter(|&&(c, _)| first_pass[c as usize] != FREE)
                .max_by(|x, y| x.1.total_cmp(&y.1));
            if let Some(&(c, _)) = best {
                of_node[r] = first_pass[c as usize];
            }
        }
        // Pass 3: what is left.
        for r in 0..n {
            if of_node[r] != FREE {
                continue;
            }
            of_node[r] = count;
            for &(c, _) in strong(r) {
                if of_node[c as usize] == FREE {
                    of_node[c as usize] = count;
                }
            }
            count += 1;
        }
        Aggregates {
            of_node,
            count: count as usize,
        }
    }

    /// Nodes of each aggregate, in increasing order.
    pub fn members(&self) -> Vec<Vec<u32>> {
        let mut out = vec![Vec::new(); self.count];
        for (r, &g) in self.of_node.iter().enumerate() {
            out[g as usize].push(r as u32);
        }
        out
    }
}
