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
            let start = self.col_ptr[3 * c + i];
            for k in 0..3 {
                if held_r[k] || (p == 0 && k < i) {
                    continue;
                }
                let offset = if p == 0 {
                    k - i
                } else {
                    (3 - i) + 3 * (p - 1) + k
                };
                self.values[start + offset] += block[k][i];
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
