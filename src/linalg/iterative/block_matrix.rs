//! A symmetric matrix of 3 x 3 node blocks in compressed rows, both triangles stored: the
//! product `y = A x` is a gather per block row (`y_r = sum_c A_rc x_c`), so rows run in parallel
//! and each `y_r` is summed in the same order whatever the thread count. Storing both triangles
//! doubles the memory of a lower-triangle copy and streams the same bytes per product.
//!
//! [`SingleBlockMatrix`] is the same matrix with its blocks rounded to single precision (the
//! products still in double): the preconditioner's products, which need the matrix only to the
//! accuracy of an approximate inverse, stream half the bytes (the products are limited by
//! memory bandwidth: 40 bytes a block against 76).

use rayon::prelude::*;

use crate::{Error, Result};

/// A 3 x 3 block: `block[k][i]` couples direction `k` of the row node to direction `i` of the
/// column node.
pub type Block3 = [[f64; 3]; 3];

/// A block entry type of the product: double or single precision.
trait Entry: Copy + Send + Sync {
    fn wide(self) -> f64;
}

impl Entry for f64 {
    #[inline(always)]
    fn wide(self) -> f64 {
        self
    }
}

impl Entry for f32 {
    #[inline(always)]
    fn wide(self) -> f64 {
        self as f64
    }
}

/// `y = A x` over compressed block rows (the one product of both precisions).
fn block_product<T: Entry>(
    row_ptr: &[usize],
    cols: &[u32],
    blocks: &[[[T; 3]; 3]],
    x: &[f64],
    y: &mut [f64],
) {
    y.par_chunks_mut(3 * ROWS_PER_TASK)
        .enumerate()
        .for_each(|(task, out)| {
            let first = task * ROWS_PER_TASK;
            for (k, yr) in out.chunks_exact_mut(3).enumerate() {
                let r = first + k;
                let mut sum = [0.0f64; 3];
                for p in row_ptr[r]..row_ptr[r + 1] {
                    let c = 3 * cols[p] as usize;
                    let (x0, x1, x2) = (x[c], x[c + 1], x[c + 2]);
                    let b = &blocks[p];
                    for d in 0..3 {
                        sum[d] += b[d][0].wide() * x0 + b[d][1].wide() * x1 + b[d][2].wide() * x2;
                    }
                }
                yr.copy_from_slice(&sum);
            }
        });
}

/// Rows per parallel task of the product (fixed, so that the work split never depends on the
/// thread count; the result does not either, being a gather).
const ROWS_PER_TASK: usize = 2048;

/// Symmetric block matrix (both triangles, rows sorted by column).
#[derive(Clone, Debug)]
pub struct BlockMatrix {
    row_ptr: Vec<usize>,
    cols: Vec<u32>,
    blocks: Vec<Block3>,
    /// Position of each row's diagonal block in `blocks`.
    diagonal: Vec<usize>,
}

/// `bᵀ`: the block of the transposed coupling (column node to row node).
pub fn transpose(b: &Block3) -> Block3 {
    std::array::from_fn(|k| std::array::from_fn(|i| b[i][k]))
}

impl BlockMatrix {
    /// From the lower triangle by block columns: column `c`'s blocks are
    /// `lower_blocks[col_ptr[c]..col_ptr[c + 1]]` at block rows `rows[..]` (each `>= c`, the
    /// diagonal block `(c, c)` among them, stored whole). Refuses a row above the diagonal, a
    /// row out of range, a repeated row or a missing diagonal block.
    pub fn from_lower_columns(
        n: usize,
        col_ptr: &[usize],
        rows: &[u32],
        lower_blocks: &[Block3],
    ) -> Result<BlockMatrix> {
        if rows.len() != lower_blocks.len() {
            return Err(Error::input(
                "block matrix",
                "pattern",
                format!("{} rows, {} blocks", rows.len(), lower_blocks.len()),
            ));
        }
        let mut matrix = BlockMatrix::from_lower_pattern(n, col_ptr, rows)?;
        matrix.refill(|r, c| {
            let (low, high) = if r >= c { (c, r) } else { (r, c) };
            let column = &rows[col_ptr[low]..col_ptr[low + 1]];
            let p = column.binary_search(&(high as u32)).ok()?;
            let b = &lower_blocks[col_ptr[low] + p];
            Some(if r >= c { *b } else { transpose(b) })
        })?;
        Ok(matrix)
    }

    /// The symmetric pattern of a lower triangle given by block columns (as
    /// [`BlockMatrix::from_lower_columns`]), every block zero: fill it with
    /// [`BlockMatrix::refill`]. Refuses what `from_lower_columns` refuses.
    pub fn from_lower_pattern(n: usize, col_ptr: &[usize], rows: &[u32]) -> Result<BlockMatrix> {
        let bad = |what: String| Err(Error::input("block matrix", "pattern", what));
        if col_ptr.len() != n + 1 || col_ptr[n] != rows.len() {
            return bad(format!(
                "{} column starts for {n} columns, {} rows",
                col_ptr.len(),
                rows.len(),
            ));
        }
        let mut count = vec![0usize; n + 1];
        for c in 0..n {
            if col_ptr[c] > col_ptr[c + 1] {
                return bad(format!("column {c} ends before it starts"));
            }
            let mut has_diagonal = false;
            for &r in &rows[col_ptr[c]..col_ptr[c + 1]] {
                let r = r as usize;
                if r < c || r >= n {
                    return bad(format!(
                        "column {c} has block row {r}: rows must lie in [{c}, {n})"
                    ));
                }
                has_diagonal |= r == c;
                count[r + 1] += 1;
                if r != c {
                    count[c + 1] += 1;
                }
            }
            if !has_diagonal {
                return bad(format!("column {c} has no diagonal block"));
            }
        }
        for r in 0..n {
            count[r + 1] += count[r];
        }
        let row_ptr = count.clone();
        let total = row_ptr[n];
        let mut next = count;
        let mut cols = vec![0u32; total];
        // Columns in increasing order: each row receives its columns sorted (the upper
        // triangle's entries of row c, from its own column c, come after its lower ones).
        for c in 0..n {
            for &r in &rows[col_ptr[c]..col_ptr[c + 1]] {
                let r = r as usize;
                cols[next[r]] = c as u32;
                next[r] += 1;
                if r != c {
                    cols[next[c]] = r as u32;
                    next[c] += 1;
                }
            }
        }
        let mut diagonal = vec![0usize; n];
        for r in 0..n {
            let row = &cols[row_ptr[r]..row_ptr[r + 1]];
            if row.windows(2).any(|w| w[0] >= w[1]) {
                return bad(format!("block row {r} has a repeated column"));
            }
            diagonal[r] = row_ptr[r] + row.partition_point(|&c| (c as usize) < r);
        }
        Ok(BlockMatrix {
            row_ptr,
            cols,
            blocks: vec![[[0.0; 3]; 3]; total],
            diagonal,
        })
    }

    /// From a dense symmetric matrix of `3 n` rows (column major): every block with a non-zero
    /// entry, and the diagonal blocks (tests and small problems).
    pub fn from_dense(n: usize, a: &[f64]) -> Result<BlockMatrix> {
        if a.len() != 9 * n * n {
            return Err(Error::input(
                "block matrix",
                "dense",
                format!("{} entries for {} rows", a.len(), 3 * n),
            ));
        }
        let at = |i: usize, j: usize| a[i + 3 * n * j];
        let (mut col_ptr, mut rows, mut blocks) = (vec![0usize], Vec::new(), Vec::new());
        for c in 0..n {
            for r in c..n {
                let b: Block3 =
                    std::array::from_fn(|k| std::array::from_fn(|i| at(3 * r + k, 3 * c + i)));
                if r == c || b.iter().flatten().any(|&v| v != 0.0) {
                    rows.push(r as u32);
                    blocks.push(b);
                }
            }
            col_ptr.push(rows.len());
        }
        BlockMatrix::from_lower_columns(n, &col_ptr, &rows, &blocks)
    }

    /// Sets every stored block `(r, c)` to `block_of(r, c)`, the pattern kept: a matrix whose
    /// values changed on the same pattern (the next Newton step's tangent) without building
    /// its rows again. Rows are filled in parallel, each block by its own call, so the result
    /// does not depend on the thread count. Fails, naming the block, if `block_of` has none.
    pub fn refill<F>(&mut self, block_of: F) -> Result<()>
    where
        F: Fn(usize, usize) -> Option<Block3> + Sync,
    {
        let n = self.nodes();
        // Carve the blocks into the rows of fixed row ranges (disjoint slices).
        let mut parts: Vec<(usize, &mut [Block3])> = Vec::new();
        let mut rest: &mut [Block3] = &mut self.blocks;
        for first in (0..n).step_by(ROWS_PER_TASK) {
            let last = (first + ROWS_PER_TASK).min(n);
            let (head, tail) =
                std::mem::take(&mut rest).split_at_mut(self.row_ptr[last] - self.row_ptr[first]);
            parts.push((first, head));
            rest = tail;
        }
        let (row_ptr, cols) = (&self.row_ptr, &self.cols);
        let missing: Option<(usize, usize)> = parts
            .into_par_iter()
            .map(|(first, blocks)| {
                let base = row_ptr[first];
                let last = (first + ROWS_PER_TASK).min(n);
                for r in first..last {
                    for p in row_ptr[r]..row_ptr[r + 1] {
                        let c = cols[p] as usize;
                        match block_of(r, c) {
                            Some(b) => blocks[p - base] = b,
                            None => return Some((r, c)),
                        }
                    }
                }
                None
            })
            .reduce(|| None, |a, b| a.or(b));
        match missing {
            None => Ok(()),
            Some((r, c)) => Err(Error::input(
                "block matrix",
                "refill",
                format!("no block ({r}, {c}) for the stored pattern"),
            )),
        }
    }

    /// Number of block rows (nodes); the matrix has `3 n` rows.
    pub fn nodes(&self) -> usize {
        self.row_ptr.len() - 1
    }

    /// Stored blocks (both triangles).
    pub fn stored_blocks(&self) -> usize {
        self.blocks.len()
    }

    /// Bytes held by the matrix.
    pub fn bytes(&self) -> usize {
        self.blocks.len() * std::mem::size_of::<Block3>()
            + self.cols.len() * 4
            + (self.row_ptr.len() + self.diagonal.len()) * std::mem::size_of::<usize>()
    }

    /// Column nodes of block row `r` (sorted) and their blocks.
    pub fn row(&self, r: usize) -> (&[u32], &[Block3]) {
        let range = self.row_ptr[r]..self.row_ptr[r + 1];
        (&self.cols[range.clone()], &self.blocks[range])
    }

    /// The diagonal block of node `r`.
    pub fn diagonal_block(&self, r: usize) -> &Block3 {
        &self.blocks[self.diagonal[r]]
    }

    /// `y = A x` (`3 n` entries each).
    pub fn apply(&self, x: &[f64], y: &mut [f64]) {
        debug_assert_eq!(x.len(), 3 * self.nodes());
        block_product(&self.row_ptr, &self.cols, &self.blocks, x, y);
    }

    /// The matrix with its blocks in single precision (its diagonal blocks kept in double).
    pub fn to_single(&self) -> SingleBlockMatrix {
        SingleBlockMatrix {
            row_ptr: self.row_ptr.clone(),
            cols: self.cols.clone(),
            blocks: self
                .blocks
                .par_iter()
                .map(|b| b.map(|row| row.map(|v| v as f32)))
                .collect(),
            diagonal: self.diagonal.iter().map(|&p| self.blocks[p]).collect(),
        }
    }
}

/// A [`BlockMatrix`] with single-precision blocks, for the preconditioner's products.
#[derive(Clone, Debug)]
pub struct SingleBlockMatrix {
    row_ptr: Vec<usize>,
    cols: Vec<u32>,
    blocks: Vec<[[f32; 3]; 3]>,
    /// The diagonal blocks in double precision.
    diagonal: Vec<Block3>,
}

impl SingleBlockMatrix {
    /// A matrix of no nodes (a placeholder while a new copy is made).
    pub fn empty() -> SingleBlockMatrix {
        SingleBlockMatrix {
            row_ptr: vec![0],
            cols: Vec::new(),
            blocks: Vec::new(),
            diagonal: Vec::new(),
        }
    }

    /// Number of block rows (nodes).
    pub fn nodes(&self) -> usize {
        self.row_ptr.len() - 1
    }

    /// The diagonal block of node `r` (double precision).
    pub fn diagonal_block(&self, r: usize) -> &Block3 {
        &self.diagonal[r]
    }

    /// `y = Ã x` with the rounded blocks, summed in double precision.
    pub fn apply(&self, x: &[f64], y: &mut [f64]) {
        debug_assert_eq!(x.len(), 3 * self.nodes());
        block_product(&self.row_ptr, &self.cols, &self.blocks, x, y);
    }
}
