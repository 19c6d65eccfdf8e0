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

    /// The value on the diagonal of reduced node `r`, direction `i`.
    pub(super) fn diagonal(&self, r: usize, i: usize) -> f64 {
        self.values[self.col_ptr[3 * r + i]]
    }

    /// Zeroes the values (the pattern stays).
    pub(super) fn clear(&mut self) {
        self.values.iter_mut().for_each(|v| *v = 0.0);
    }

    /// The lower triangle by 3 x 3 node blocks: column starts, block rows (the diagonal block
    /// first in each column, stored whole) and blocks (`[row direction][column direction]`),
    /// for [`crate::iterative::BlockMatrix::from_lower_columns`].
    pub(super) fn lower_blocks(&self) -> (Vec<usize>, Vec<u32>, Vec<Block>) {
        let n = self.block_ptr.len() - 1;
        let mut blocks = vec![[[0.0; 3]; 3]; self.block_rows.len()];
        for c in 0..n {
            let first = self.block_ptr[c];
            let count = self.block_ptr[c + 1] - first;
            for i in 0..3 {
                let start = self.col_ptr[3 * c + i];
                // Diagonal block: rows i..3 of column i, mirrored above.
                for k in i..3 {
                    let v = self.values[start + k - i];
                    blocks[first][k][i] = v;
                    blocks[first][i][k] = v;
                }
                for p in 1..count {
                    for k in 0..3 {
                        blocks[first + p][k][i] = self.values[start + (3 - i) + 3 * (p - 1) + k];
                    }
                }
            }
        }
        (self.block_ptr.clone(), self.block_rows.clone(), blocks)
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
