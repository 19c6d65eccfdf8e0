//! The static tangent `Tᵀ K T` in faer's lower-triangular compressed columns, assembled by
//! 3 x 3 blocks of reduced nodes ([`super::dofs`]).
//!
//! The pattern is a node graph: reduced node `c`'s column holds the reduced nodes `r >= c` it
//! shares an element, a spring or a rank-one term with. Scalar column `3c + i` then holds, in
//! order, rows `3c + i .. 3c + 2` of the diagonal block and the three rows of each off-diagonal
//! block, so an entry's place is found by one binary search in the node column.
//!
//! Held directions get no coupling and a unit diagonal scaled to the matrix (their increment
//! is zero because their residual is).

// Index loops mirror the block layout (direction indices i, k).
#![allow(clippy::needless_range_loop)]

use faer::sparse::{SparseColMat, SymbolicSparseColMat};

use super::dofs::ReducedDofs;
use crate::linalg::iterative::block_matrix::transpose;
use crate::{Error, Result};

/// A 3 x 3 block (row direction, column direction).
pub(super) type Block = [[f64; 3]; 3];

/// Packs the node pair `(row, column)` with `row >= column` as a sort key (column major).
pub(super) fn pair_key(a: u32, b: u32) -> u64 {
    let (r, c) = if a >= b { (a, b) } else { (b, a) };
    ((c as u64) << 32) | r as u64
}

/// The block pattern and the scalar matrix built on it.
pub(super) struct Tangent {
    /// Per reduced node column: start of its rows in `block_rows`.
    block_ptr: Vec<usize>,
    /// Rows (reduced nodes `>= column`, ascending; the first is the column itself).
    block_rows: Vec<u32>,
    /// Scalar column starts.
    col_ptr: Vec<usize>,
    /// Scalar values on the pattern.
    pub(super) values: Vec<f64>,
}

impl Tangent {
    /// The pattern of the sorted, deduplicated pair keys `keys` (diagonals added) for `n`
    /// reduced nodes.
    pub(super) fn from_keys(n: usize, keys: &[u64]) -> Tangent {
        let mut block_ptr = vec![0usize; n + 1];
        let mut block_rows = Vec::with_capacity(keys.len() + n);
        let mut k = 0;
        for c in 0..n {
            block_rows.push(c as u32);
            while k < keys.len() && (keys[k] >> 32) as usize == c {
                let r = (keys[k] & 0xffff_ffff) as u32;
                if r as usize != c {
                    block_rows.push(r);
                }
                k += 1;
            }
            block_ptr[c + 1] = block_rows.len();
        }
        let mut col_ptr = Vec::with_capacity(3 * n + 1);
        col_ptr.push(0);
        for c in 0..n {
            let off_diagonal = block_ptr[c + 1] - block_ptr[c] - 1;
            for i in 0..3 {
                let last = *col_ptr.last().unwrap_or(&0);
                col_ptr.push(last + (3 - i) + 3 * off_diagonal);
            }
        }
        let nnz = *col_ptr.last().unwrap_or(&0);
        Tangent {
            block_ptr,
            block_rows,
            col_ptr,
            values: vec![0.0; nnz],
        }
    }

    /// Whether the pattern holds the pair key `key`.
    pub(super) fn contains(&self, key: u64) -> bool {
        let (c, r) = ((key >> 32) as usize, (key & 0xffff_ffff) as u32);
        self.block_rows[self.block_ptr[c]..self.block_ptr[c + 1]]
            .binary_search(&r)
            .is_ok()
    }

    /// Adds `block` (row direction, column direction) to the lower node block `(row r, column
    /// c)`, `r >= c`; a diagonal block adds its lower triangle. Entries in held directions are
    /// skipped.
    pub(super) fn add(&mut self, dofs: &ReducedDofs, r: u32, c: u32, block: &Block) {
        let mut values = std::mem::take(&mut self.values);
        self.add_to(&mut values, 0, dofs, r, c, block);
        self.values = values;
    }

    /// The values of reduced-node columns `c0..c1`: a range of the value array (columns are
    /// stored one after another).
    pub(super) fn value_range(&self, c0: usize, c1: usize) -> std::ops::Range<usize> {
        self.col_ptr[3 * c0]..self.col_ptr[3 * c1]
    }

    /// [`Tangent::add`] into `values`, the part of the value array that starts at `base` (it
    /// must hold column `c`'s values).
    pub(super) fn add_to(
        &self,
        values: &mut [f64],
        base: usize,
        dofs: &ReducedDofs,
        r: u32,
        c: u32,
        block: &Block,
    ) {
        debug_assert!(r >= c, "the tangent stores lower blocks");
        let (r, c) = (r as usize, c as usize);
        let rows = &self.block_rows[self.block_ptr[c]..self.block_ptr[c + 1]];
        let Ok(p) = rows.binary_search(&(r as u32)) else {
            // The pattern was built from the same pairs: a missing block is a bug.
            panic!("static tangent: block ({r}, {c}) is not in the pattern");
        };
        let (held_r, held_c) = (dofs.held[r], dofs.held[c]);
        for i in 0..3 {
            if held_c[i] {
                continue;
            }
            let start = self.col_ptr[3 * c + i] - base;
            for k in 0..3 {
                if held_r[k] || (p == 0 && k < i) {
                    continue;
                }
                let offset = if p == 0 {
                    k - i
                } else {
                    (3 - i) + 3 * (p - 1) + k
                };
                values[start + offset] += block[k][i];
            }
        }
    }

    /// Adds `value` to the diagonal of reduced node `r`, direction `i`.
    pub(super) fn add_diagonal(&mut self, r: usize, i: usize, value: f64) {
        self.values[self.col_ptr[3 * r + i]] += value;
    }

    /// Sets the diagonal of reduced node `r`, direction `i`, to `value`.
    pub(super) fn set_diagonal(&mut self, r: usize, i: usize, value: f64) {
        self.values[self.col_ptr[3 * r + i]] = value;
    }

    /// The value on the diagonal of reduced node `r`, direction `i`.
    pub(super) fn diagonal(&self, r: usize, i: usize) -> f64 {
        self.values[self.col_ptr[3 * r + i]]
    }

    /// Zeroes the values (the pattern stays).
    pub(super) fn clear(&mut self) {
        self.values.iter_mut().for_each(|v| *v = 0.0);
    }

    /// The pattern of the node blocks of the lower triangle by node columns (column starts,
    /// rows; the diagonal block first in each column), for
    /// [`crate::linalg::iterative::BlockMatrix::from_lower_pattern`].
    pub(super) fn lower_pattern(&self) -> (&[usize], &[u32]) {
        (&self.block_ptr, &self.block_rows)
    }

    /// The lower triangle by 3 x 3 node blocks: column starts, block rows (the diagonal block
    /// first in each column, stored whole) and blocks (`[row direction][column direction]`),
    /// for [`crate::linalg::iterative::BlockMatrix::from_lower_columns`] (the tests' second way to
    /// the block matrix).
    #[cfg(test)]
    pub(super) fn lower_blocks(&self) -> (Vec<usize>, Vec<u32>, Vec<Block>) {
        let n = self.block_ptr.len() - 1;
        let mut blocks = Vec::with_capacity(self.block_rows.len());
        for c in 0..n {
            for p in 0..self.block_ptr[c + 1] - self.block_ptr[c] {
                blocks.push(self.block_at(c, p));
            }
        }
        (self.block_ptr.clone(), self.block_rows.clone(), blocks)
    }

    /// The node block `(r, c)` (`[row direction][column direction]`), either triangle: the
    /// stored lower block, transposed above the diagonal, the diagonal block whole. None when
    /// the pattern lacks it.
    pub(super) fn block(&self, r: usize, c: usize) -> Option<Block> {
        let (low, high) = if r >= c { (c, r) } else { (r, c) };
        let rows = &self.block_rows[self.block_ptr[low]..self.block_ptr[low + 1]];
        let p = rows.binary_search(&(high as u32)).ok()?;
        let b = self.block_at(low, p);
        Some(if r >= c { b } else { transpose(&b) })
    }

    /// The `p`-th lower block of node column `c` (`p = 0`: the diagonal block, mirrored).
    fn block_at(&self, c: usize, p: usize) -> Block {
        let mut b = [[0.0; 3]; 3];
        for i in 0..3 {
            let start = self.col_ptr[3 * c + i];
            if p == 0 {
                // Rows i..3 of column i, mirrored above.
                for k in i..3 {
                    let v = self.values[start + k - i];
                    b[k][i] = v;
                    b[i][k] = v;
                }
            } else {
                for k in 0..3 {
                    b[k][i] = self.values[start + (3 - i) + 3 * (p - 1) + k];
                }
            }
        }
        b
    }

    /// The lower triangle as a faer matrix (its pattern and a copy of the values).
    pub(super) fn matrix(&self) -> Result<SparseColMat<usize, f64>> {
        let n = self.col_ptr.len() - 1;
        let mut row_idx = Vec::with_capacity(self.values.len());
        for c in 0..self.block_ptr.len() - 1 {
            let rows = &self.block_rows[self.block_ptr[c]..self.block_ptr[c + 1]];
            for i in 0..3 {
                for k in i..3 {
                    row_idx.push(3 * c + k);
                }
                for &r in &rows[1..] {
                    for k in 0..3 {
                        row_idx.push(3 * r as usize + k);
                    }
                }
            }
        }
        if row_idx.len() != self.values.len() {
            return Err(Error::Numerical(format!(
                "static tangent: {} row indices for {} values",
                row_idx.len(),
                self.values.len()
            )));
        }
        let symbolic = SymbolicSparseColMat::new_checked(n, n, self.col_ptr.clone(), None, row_idx);
        Ok(SparseColMat::new(symbolic, self.values.clone()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::iterative::BlockMatrix;

    /// A tangent on a banded node graph (couplings at distances 1, 7 and 50) with seeded
    /// pseudo-random values.
    fn tangent(n: usize, seed: u64) -> Tangent {
        let mut keys: Vec<u64> = Vec::new();
        for c in 0..n {
            for d in [0, 1, 7, 50] {
                if c + d < n {
                    keys.push(pair_key((c + d) as u32, c as u32));
                }
            }
        }
        keys.sort_unstable();
        keys.dedup();
        let mut tg = Tangent::from_keys(n, &keys);
        let mut state = seed;
        for v in tg.values.iter_mut() {
            // Knuth's MMIX linear congruential generator, top bits to [-1, 1).
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            *v = (state >> 11) as f64 / (1u64 << 52) as f64 - 1.0;
        }
        tg
    }

    fn build(tg: &Tangent) -> BlockMatrix {
        let (col_ptr, rows, blocks) = tg.lower_blocks();
        BlockMatrix::from_lower_columns(col_ptr.len() - 1, &col_ptr, &rows, &blocks).unwrap()
    }

    /// The Newton loop's refill of a kept block matrix (`Tangent::block` for each stored
    /// block, rows in parallel tasks of 2048) against building the matrix of the new values
    /// afresh: bit for bit, over more rows than one task holds.
    #[test]
    fn refilled_block_matrix_is_the_rebuilt_one_bit_for_bit() {
        let n = 5000;
        let (first, second) = (tangent(n, 1), tangent(n, 2));
        let mut refilled = build(&first);
        refilled.refill(|r, c| second.block(r, c)).unwrap();
        let rebuilt = build(&second);
        assert_eq!(refilled.stored_blocks(), rebuilt.stored_blocks());
        let mut compared = 0;
        for r in 0..n {
            let (cols_a, blocks_a) = refilled.row(r);
            let (cols_b, blocks_b) = rebuilt.row(r);
            assert_eq!(cols_a, cols_b, "row {r}");
            for (a, b) in blocks_a.iter().zip(blocks_b) {
                let same = a
                    .iter()
                    .flatten()
                    .zip(b.iter().flatten())
                    .all(|(x, y)| x.to_bits() == y.to_bits());
                assert!(same, "row {r}: {a:?} against {b:?}");
                compared += 1;
            }
        }
        assert_eq!(compared, rebuilt.stored_blocks());
        // The refill changed the values: the first tangent's matrix differs.
        let original = build(&first);
        assert_ne!(original.row(10).1, refilled.row(10).1);
    }

    #[test]
    fn blocks_outside_the_pattern_are_refused() {
        let tg = tangent(100, 3);
        assert!(tg.block(0, 2).is_none());
        assert!(tg.block(2, 0).is_none());
        assert!(tg.block(57, 7).is_some());
        // Above the diagonal: the transpose of the stored lower block.
        let (low, high) = (tg.block(8, 1).unwrap(), tg.block(1, 8).unwrap());
        assert_eq!(low[2][0], high[0][2]);
        let mut matrix = build(&tg);
        let err = matrix
            .refill(|r, c| {
                if (r, c) == (8, 1) {
                    None
                } else {
                    tg.block(r, c)
                }
            })
            .unwrap_err()
            .to_string();
        assert!(err.contains("no block (8, 1)"), "{err}");
    }
}
