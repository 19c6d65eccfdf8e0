//! Solves with a supernodal Cholesky factor (faer's `L Lᵀ` or `L D Lᵀ` storage) for a block of
//! right-hand sides, parallel over the elimination tree.
//!
//! Method. faer's supernodes are postordered: a subtree's supernodes are consecutive, its
//! columns a contiguous range that ends with its root's. Forward, `L y = b`: supernode `s`
//! solves its diagonal block, `y_s = L_ss⁻¹ b_s`, then updates the rows of its pattern (all
//! in its ancestors), `b_p -= L_ps y_s`; with `L D Lᵀ`, `y_s` is then scaled by `D_s⁻¹`.
//! Backward, `Lᵀ x = y`: `x_s = L_ssᵀ⁻¹ (y_s - L_psᵀ x_p)`, reading only ancestors' rows.
//! Sibling subtrees share no rows but their ancestors', so they run in parallel: forward, each
//! writes its own rows in place and its ancestors' rows into a private accumulator, added in a
//! fixed order after both end; backward, each reads a copy of its ancestors' rows. Where a
//! subtree is split depends on the tree and the factor's sizes only, so the result does not
//! depend on the number of threads.
//!
//! Why: a solve with 16 right-hand sides streams the whole factor (2.56 GB at 294 k dofs) and
//! is limited by memory bandwidth. Splitting the columns among threads (one faer solve per
//! thread) streams it once per thread: two threads gained 10 % over one (1.7 s against 1.9 s a
//! block, measured 2026-11-27). Splitting the tree streams it once in all.

use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_unit_lower_triangular_in_place,
    solve_unit_upper_triangular_in_place, solve_upper_triangular_in_place,
};
use faer::sparse::linalg::cholesky::supernodal::SymbolicSupernodalCholesky;
use faer::sparse::linalg::cholesky::{SymbolicCholesky, SymbolicCholeskyRaw};
use faer::{Accum, MatMut, MatRef, Par};

use super::workspace::Workspace;

/// Deepest nesting of parallel splits (2^8 tasks at most: enough for work stealing to even
/// out unequal subtrees on a few cores, few enough that the accumulators stay small).
const MAX_DEPTH: usize = 8;

/// A subtree is split only when it holds at least this share of the factor's entries: below,
/// a task's fixed costs (its accumulator, the merge) are no longer small against its work.
const MIN_SPLIT_SHARE: f64 = 1.0 / 256.0;

/// Which numeric factorisation of a pencil matrix, so which factor the values hold.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum FactorKind {
    /// `L Lᵀ`, `L` with its diagonal (positive definite: the shift below the spectrum).
    Llt,
    /// `L D Lᵀ`, no pivoting, `L` unit lower, `D` stored on its diagonal (indefinite: a shift
    /// inside the band, the Sturm count at a band edge).
    Ldlt,
}

/// The elimination tree of a supernodal factor, with what the parallel solve needs.
pub(crate) struct TreePlan<'a> {
    sn: &'a SymbolicSupernodalCholesky<usize>,
    /// Forward and inverse fill-reducing permutation (`x_perm[i] = x[fwd[i]]`).
    perm_fwd: Option<&'a [usize]>,
    /// Children of each supernode, ascending (their subtrees are consecutive).
    child_ptr: Vec<usize>,
    child_idx: Vec<usize>,
    /// Lowest supernode of each subtree.
    first: Vec<usize>,
    /// Factor entries in each subtree.
    work: Vec<usize>,
    roots: Vec<usize>,
    /// Longest off-diagonal pattern of a supernode (scratch rows).
    max_pattern: usize,
}

impl<'a> TreePlan<'a> {
    /// The plan of `symbolic`'s factor, or `None` when it is simplicial or its supernodes are
    /// not postordered (faer's solve is used then).
    pub(crate) fn new(symbolic: &'a SymbolicCholesky<usize>) -> Option<TreePlan<'a>> {
        let SymbolicCholeskyRaw::Supernodal(sn) = symbolic.raw() else {
            return None;
        };
        let ns = sn.n_supernodes();
        let begin = sn.supernode_begin();
        let end = sn.supernode_end();
        let n = sn.nrows();
        // Column -> supernode.
        let mut col_sn = vec![0usize; n];
        for s in 0..ns {
            col_sn[begin[s]..end[s]].fill(s);
        }
        let mut parent = vec![usize::MAX; ns];
        let mut max_pattern = 0;
        for (s, p) in parent.iter_mut().enumerate() {
            let pattern = sn.supernode(s).pattern();
            max_pattern = max_pattern.max(pattern.len());
            if let Some(&row) = pattern.first() {
                *p = col_sn[row];
                if *p <= s {
                    return None;
                }
            }
        }
        let mut count = vec![0usize; ns + 1];
        for &p in &parent {
            if p != usize::MAX {
                count[p + 1] += 1;
            }
        }
        for s in 0..ns {
            count[s + 1] += count[s];
        }
        let child_ptr = count.clone();
        let mut child_idx = vec![0usize; child_ptr[ns]];
        let mut roots = Vec::new();
        for (s, &p) in parent.iter().enumerate() {
            if p == usize::MAX {
                roots.push(s);
            } else {
                child_idx[count[p]] = s;
                count[p] += 1;
            }
        }
        let vals = sn.col_ptr_for_val();
        let mut first: Vec<usize> = (0..ns).collect();
        let mut work: Vec<usize> = (0..ns).map(|s| vals[s + 1] - vals[s]).collect();
        for s in 0..ns {
            // Children come before their parent: their subtrees are complete here.
            let kids = &child_idx[child_ptr[s]..child_ptr[s + 1]];
            // Postorder: the children's subtrees tile first(s)..s.
            let mut next = kids.first().map_or(s, |&c| first[c]);
            for &c in kids {
                if first[c] != next {
                    return None;
                }
                next = c + 1;
                work[s] += work[c];
            }
            if next != s {
                return None;
            }
            first[s] = kids.first().map_or(s, |&c| first[c]);
        }
        let mut next = 0;
        for &r in &roots {
            if first[r] != next {
                return None;
            }
            next = r + 1;
        }
        Some(TreePlan {
            sn,
            perm_fwd: symbolic.perm().map(|p| p.arrays().0),
            child_ptr,
            child_idx,
            first,
            work,
            roots,
            max_pattern,
        })
    }

    fn children(&self, s: usize) -> &[usize] {
        &self.child_idx[self.child_ptr[s]..self.child_ptr[s + 1]]
    }

    fn col_begin(&self, s: usize) -> usize {
        self.sn.supernode_begin()[s]
    }

    fn col_end(&self, s: usize) -> usize {
        self.sn.supernode_end()[s]
    }

    /// `rhs = A⁻¹ rhs` with `A = L Lᵀ` or `L D Lᵀ` from `values` (the factor's entries in
    /// faer's supernodal layout), `rhs` column-major `n x k`; the row-major copy from `ws`.
    pub(crate) fn solve_in_place(
        &self,
        values: &[f64],
        kind: FactorKind,
        rhs: &mut [f64],
        ws: &mut Workspace,
    ) {
        let n = self.sn.nrows();
        let k = rhs.len() / n;
        // Permuted and row-major: a row's k values are adjacent, so the scatter and gather of a
        // supernode's pattern rows touch two cache lines per row instead of k. Every entry is
        // written here, so a stale buffer will do.
        let mut x = ws.take(n * k);
        for j in 0..k {
            let col = &rhs[j * n..(j + 1) * n];
            for i in 0..n {
                x[i * k + j] = col[self.perm_fwd.map_or(i, |f| f[i])];
            }
        }
        let task = Task {
            plan: self,
            values,
            kind,
            k,
            min_split: (values.len() as f64 * MIN_SPLIT_SHARE) as usize,
        };
        let mut none = Ancestors::empty();
        let mut tmp = task.scratch();
        task.forward_siblings(&self.roots, &mut x, 0, &mut none, &mut tmp, 0);
        task.backward_siblings(&self.roots, &mut x, 0, &none, &mut tmp, 0);
        for j in 0..k {
            let col = &mut rhs[j * n..(j + 1) * n];
            for i in 0..n {
                col[self.perm_fwd.map_or(i, |f| f[i])] = x[i * k + j];
            }
        }
        ws.give(x);
    }
}

/// The rows of a chain of ancestors, outside a task's own rows: column ranges (ascending) and
/// their values, stacked in that order, row-major.
struct Ancestors {
    /// `(first column, past-the-end column, first row in vals)`.
    ranges: Vec<(usize, usize, usize)>,
    vals: Vec<f64>,
}

impl Ancestors {
    fn empty() -> Ancestors {
        Ancestors {
            ranges: Vec::new(),
            vals: Vec::new(),
        }
    }

    /// Zeros over the same rows.
    fn zeros_like(&self) -> Ancestors {
        Ancestors {
            ranges: self.ranges.clone(),
            vals: vec![0.0; self.vals.len()],
        }
    }

    /// Rows `cols` (a contiguous column range, below every range of `outer`) followed by
    /// `outer`'s rows; the first part holds `head` (zeros if `None`), the second `outer`'s
    /// values (zeros if `head` is `None`: an accumulator).
    fn stacked(
        cols: (usize, usize),
        head: Option<&[f64]>,
        outer: &Ancestors,
        k: usize,
    ) -> Ancestors {
        let width = cols.1 - cols.0;
        let mut ranges = Vec::with_capacity(outer.ranges.len() + 1);
        ranges.push((cols.0, cols.1, 0));
        ranges.extend(outer.ranges.iter().map(|&(b, e, o)| (b, e, o + width)));
        let vals = match head {
            Some(head) => {
                let mut v = Vec::with_capacity(head.len() + outer.vals.len());
                v.extend_from_slice(head);
                v.extend_from_slice(&outer.vals);
                v
            }
            None => vec![0.0; width * k + outer.vals.len()],
        };
        Ancestors { ranges, vals }
    }

    /// Row of `vals` holding column `col` (an ancestor row: inside one of the ranges).
    /// `hint` is the range index to start from (rows are visited in ascending order).
    fn locate(&self, col: usize, hint: &mut usize) -> usize {
        while self.ranges[*hint].1 <= col {
            *hint += 1;
        }
        let (b, _, o) = self.ranges[*hint];
        debug_assert!(col >= b, "row {col} is not an ancestor's");
        o + col - b
    }
}

/// One solve's shared inputs.
struct Task<'p, 'v> {
    plan: &'p TreePlan<'p>,
    values: &'v [f64],
    kind: FactorKind,
    k: usize,
    min_split: usize,
}

impl Task<'_, '_> {
    /// Diagonal block and off-diagonal rows of supernode `s`.
    fn blocks(&self, s: usize) -> (MatRef<'_, f64>, MatRef<'_, f64>, &[usize]) {
        let sn = self.plan.sn;
        let vals = sn.col_ptr_for_val();
        let size = self.plan.col_end(s) - self.plan.col_begin(s);
        let pattern = sn.supernode(s).pattern();
        let ls = MatRef::from_column_major_slice(
            &self.values[vals[s]..vals[s + 1]],
            size + pattern.len(),
            size,
        );
        let (top, bot) = ls.split_at_row(size);
        (top, bot, pattern)
    }

    /// Forward step of supernode `s`; `x` holds the task's own rows from row `base` on
    /// (row-major), `outside` the task's ancestors' rows (every pattern row at or past
    /// `own_end`).
    fn forward_node(
        &self,
        s: usize,
        x: &mut [f64],
        base: usize,
        own_end: usize,
        outside: &mut Ancestors,
        tmp: &mut [f64],
    ) {
        let k = self.k;
        let (top, bot, pattern) = self.blocks(s);
        let start = self.plan.col_begin(s) - base;
        let size = top.ncols();
        let own = start * k..(start + size) * k;
        {
            let xs = MatMut::from_row_major_slice_mut(&mut x[own.clone()], size, k);
            match self.kind {
                FactorKind::Llt => solve_lower_triangular_in_place(top, xs, Par::Seq),
                FactorKind::Ldlt => solve_unit_lower_triangular_in_place(top, xs, Par::Seq),
            }
        }
        let np = pattern.len();
        if np > 0 {
            matmul(
                MatMut::from_row_major_slice_mut(&mut tmp[..np * k], np, k),
                Accum::Replace,
                bot,
                MatRef::from_row_major_slice(&x[own.clone()], size, k),
                1.0,
                Par::Seq,
            );
            let inside = pattern.partition_point(|&i| i < own_end);
            for (idx, &row) in pattern[..inside].iter().enumerate() {
                let dst = &mut x[(row - base) * k..(row - base + 1) * k];
                for (d, t) in dst.iter_mut().zip(&tmp[idx * k..(idx + 1) * k]) {
                    *d -= t;
                }
            }
            let mut hint = 0;
            for (idx, &row) in pattern.iter().enumerate().skip(inside) {
                let r = outside.locate(row, &mut hint);
                let dst = &mut outside.vals[r * k..(r + 1) * k];
                for (d, t) in dst.iter_mut().zip(&tmp[idx * k..(idx + 1) * k]) {
                    *d -= t;
                }
            }
        }
        if self.kind == FactorKind::Ldlt {
            for i in 0..size {
                let d_inv = 1.0 / top[(i, i)];
                for v in &mut x[(start + i) * k..(start + i + 1) * k] {
                    *v *= d_inv;
                }
            }
        }
    }

    /// Backward step of supernode `s` (rows as in [`Task::forward_node`]).
    fn backward_node(
        &self,
        s: usize,
        x: &mut [f64],
        base: usize,
        own_end: usize,
        outside: &Ancestors,
        tmp: &mut [f64],
    ) {
        let k = self.k;
        let (top, bot, pattern) = self.blocks(s);
        let start = self.plan.col_begin(s) - base;
        let size = top.ncols();
        let own = start * k..(start + size) * k;
        let np = pattern.len();
        if np > 0 {
            let inside = pattern.partition_point(|&i| i < own_end);
            for (idx, &row) in pattern[..inside].iter().enumerate() {
                tmp[idx * k..(idx + 1) * k]
                    .copy_from_slice(&x[(row - base) * k..(row - base + 1) * k]);
            }
            let mut hint = 0;
            for (idx, &row) in pattern.iter().enumerate().skip(inside) {
                let r = outside.locate(row, &mut hint);
                tmp[idx * k..(idx + 1) * k].copy_from_slice(&outside.vals[r * k..(r + 1) * k]);
            }
            matmul(
                MatMut::from_row_major_slice_mut(&mut x[own.clone()], size, k),
                Accum::Add,
                bot.transpose(),
                MatRef::from_row_major_slice(&tmp[..np * k], np, k),
                -1.0,
                Par::Seq,
            );
        }
        let xs = MatMut::from_row_major_slice_mut(&mut x[own], size, k);
        match self.kind {
            FactorKind::Llt => solve_upper_triangular_in_place(top.transpose(), xs, Par::Seq),
            FactorKind::Ldlt => solve_unit_upper_triangular_in_place(top.transpose(), xs, Par::Seq),
        }
    }

    fn scratch(&self) -> Vec<f64> {
        vec![0.0; self.plan.max_pattern * self.k]
    }

    /// Rows of the subtrees of `sibs` (consecutive siblings): from the first one's first
    /// column to the last one's end.
    fn rows_of(&self, sibs: &[usize]) -> (usize, usize) {
        let first = sibs[0];
        let last = sibs[sibs.len() - 1];
        (
            self.plan.col_begin(self.plan.first[first]),
            self.plan.col_end(last),
        )
    }

    /// Splits `sibs` where the work before the cut is closest to half.
    fn halves<'s>(&self, sibs: &'s [usize]) -> (&'s [usize], &'s [usize]) {
        let total: usize = sibs.iter().map(|&c| self.plan.work[c]).sum();
        let mut acc = 0;
        let mut cut = 1;
        for (i, &c) in sibs.iter().enumerate().take(sibs.len() - 1) {
            acc += self.plan.work[c];
            cut = i + 1;
            if 2 * acc >= total {
                break;
            }
        }
        sibs.split_at(cut)
    }

    /// The single-child chain below `c`: the highest descendant `d` with other than one child
    /// (`c` itself when it has none or several); `d..=c` are consecutive.
    fn chain_bottom(&self, c: usize) -> usize {
        let mut d = c;
        while self.plan.children(d).len() == 1 {
            d = self.plan.children(d)[0];
        }
        d
    }

    fn splits(&self, sibs: usize, work: usize, depth: usize) -> bool {
        sibs >= 2 && depth < MAX_DEPTH && work >= self.min_split
    }

    /// Forward solve of the subtrees of `sibs` (consecutive siblings), whose rows are `x`
    /// (first row `base`); their ancestors' rows go to `outside`.
    fn forward_siblings(
        &self,
        sibs: &[usize],
        x: &mut [f64],
        base: usize,
        outside: &mut Ancestors,
        tmp: &mut [f64],
        depth: usize,
    ) {
        let work: usize = sibs.iter().map(|&c| self.plan.work[c]).sum();
        if self.splits(sibs.len(), work, depth) {
            let (g1, g2) = self.halves(sibs);
            let (_, mid) = self.rows_of(g1);
            let (x1, x2) = x.split_at_mut((mid - base) * self.k);
            // The second half accumulates its ancestors' updates apart; added after both end,
            // in this order whatever the threads.
            let mut acc2 = outside.zeros_like();
            rayon::join(
                || self.forward_siblings(g1, x1, base, outside, tmp, depth + 1),
                || {
                    let mut tmp2 = self.scratch();
                    self.forward_siblings(g2, x2, mid, &mut acc2, &mut tmp2, depth + 1)
                },
            );
            for (o, a) in outside.vals.iter_mut().zip(&acc2.vals) {
                *o += a;
            }
            return;
        }
        for &c in sibs {
            let (lo, hi) = self.rows_of(&[c]);
            let xc = &mut x[(lo - base) * self.k..(hi - base) * self.k];
            self.forward_subtree(c, xc, lo, outside, tmp, depth);
        }
    }

    fn forward_subtree(
        &self,
        c: usize,
        x: &mut [f64],
        base: usize,
        outside: &mut Ancestors,
        tmp: &mut [f64],
        depth: usize,
    ) {
        let k = self.k;
        let own_end = self.plan.col_end(c);
        let d = self.chain_bottom(c);
        let kids = self.plan.children(d);
        if self.splits(kids.len(), self.plan.work[c], depth) {
            // The children's subtrees in parallel, their updates of the chain d..=c and of
            // the ancestors in `inner`; then the chain.
            let chain_begin = self.plan.col_begin(d);
            let mut inner = Ancestors::stacked((chain_begin, own_end), None, outside, k);
            let (xk, xc) = x.split_at_mut((chain_begin - base) * k);
            self.forward_siblings(kids, xk, base, &mut inner, tmp, depth + 1);
            let width = (own_end - chain_begin) * k;
            for (v, a) in xc.iter_mut().zip(&inner.vals[..width]) {
                *v += a;
            }
            for (o, a) in outside.vals.iter_mut().zip(&inner.vals[width..]) {
                *o += a;
            }
            for s in d..=c {
                self.forward_node(s, x, base, own_end, outside, tmp);
            }
        } else {
            for s in self.plan.first[c]..=c {
                self.forward_node(s, x, base, own_end, outside, tmp);
            }
        }
    }

    /// Backward solve of the subtrees of `sibs` (rows as in [`Task::forward_siblings`]);
    /// `outside` holds their ancestors' rows, final.
    fn backward_siblings(
        &self,
        sibs: &[usize],
        x: &mut [f64],
        base: usize,
        outside: &Ancestors,
        tmp: &mut [f64],
        depth: usize,
    ) {
        let work: usize = sibs.iter().map(|&c| self.plan.work[c]).sum();
        if self.splits(sibs.len(), work, depth) {
            let (g1, g2) = self.halves(sibs);
            let (_, mid) = self.rows_of(g1);
            let (x1, x2) = x.split_at_mut((mid - base) * self.k);
            rayon::join(
                || self.backward_siblings(g1, x1, base, outside, tmp, depth + 1),
                || {
                    let mut tmp2 = self.scratch();
                    self.backward_siblings(g2, x2, mid, outside, &mut tmp2, depth + 1)
                },
            );
            return;
        }
        for &c in sibs {
            let (lo, hi) = self.rows_of(&[c]);
            let xc = &mut x[(lo - base) * self.k..(hi - base) * self.k];
            self.backward_subtree(c, xc, lo, outside, tmp, depth);
        }
    }

    fn backward_subtree(
        &self,
        c: usize,
        x: &mut [f64],
        base: usize,
        outside: &Ancestors,
        tmp: &mut [f64],
        depth: usize,
    ) {
        let k = self.k;
        let own_end = self.plan.col_end(c);
        let d = self.chain_bottom(c);
        let kids = self.plan.children(d);
        if self.splits(kids.len(), self.plan.work[c], depth) {
            // The chain d..=c, then the children's subtrees in parallel, each reading the
            // chain's and the ancestors' rows from `inner`.
            for s in (d..=c).rev() {
                self.backward_node(s, x, base, own_end, outside, tmp);
            }
            let chain_begin = self.plan.col_begin(d);
            let (xk, xc) = x.split_at_mut((chain_begin - base) * k);
            let inner = Ancestors::stacked((chain_begin, own_end), Some(xc), outside, k);
            self.backward_siblings(kids, xk, base, &inner, tmp, depth + 1);
        } else {
            for s in (self.plan.first[c]..=c).rev() {
                self.backward_node(s, x, base, own_end, outside, tmp);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::ordering::nested_dissection;
    use crate::linalg::postorder::postordered;
    use crate::random::XorShift64;
    use faer::dyn_stack::{MemBuffer, MemStack};
    use faer::perm::PermRef;
    use faer::sparse::linalg::cholesky::{
        factorize_symbolic_cholesky, CholeskySymbolicParams, LdltRef, LltRef, SymmetricOrdering,
    };
    use faer::sparse::linalg::SupernodalThreshold;
    use faer::sparse::SparseColMat;
    use faer::Side;
    use FactorKind::{Ldlt, Llt};

    /// Lower triangle of the 7-point Laplacian on an `m^3` grid (Dirichlet), minus `shift`
    /// on the diagonal: positive definite for `shift < 0`, indefinite inside (0, 12).
    fn grid(m: usize, shift: f64) -> SparseColMat<usize, f64> {
        let id = |i: usize, j: usize, k: usize| (k * m + j) * m + i;
        let mut t = Vec::new();
        for k in 0..m {
            for j in 0..m {
                for i in 0..m {
                    let p = id(i, j, k);
                    t.push(faer::sparse::Triplet::new(p, p, 6.0 - shift));
                    for q in [
                        (i + 1 < m).then(|| id(i + 1, j, k)),
                        (j + 1 < m).then(|| id(i, j + 1, k)),
                        (k + 1 < m).then(|| id(i, j, k + 1)),
                    ]
                    .into_iter()
                    .flatten()
                    {
                        t.push(faer::sparse::Triplet::new(q, p, -1.0));
                    }
                }
            }
        }
        SparseColMat::try_new_from_triplets(m * m * m, m * m * m, &t).expect("valid triplets")
    }

    /// Factor values of `a` (faer's supernodal numeric factorisation, no pivoting).
    fn factor(
        a: &SparseColMat<usize, f64>,
        sym: &SymbolicCholesky<usize>,
        kind: FactorKind,
    ) -> Vec<f64> {
        let mut values = vec![0.0; sym.len_val()];
        let par = Par::Seq;
        match kind {
            Llt => {
                let mut mem = MemBuffer::new(
                    sym.factorize_numeric_llt_scratch::<f64>(par, Default::default()),
                );
                sym.factorize_numeric_llt(
                    &mut values,
                    a.as_ref(),
                    Side::Lower,
                    Default::default(),
                    par,
                    MemStack::new(&mut mem),
                    Default::default(),
                )
                .expect("positive definite");
            }
            Ldlt => {
                let mut mem = MemBuffer::new(
                    sym.factorize_numeric_ldlt_scratch::<f64>(par, Default::default()),
                );
                sym.factorize_numeric_ldlt(
                    &mut values,
                    a.as_ref(),
                    Side::Lower,
                    Default::default(),
                    par,
                    MemStack::new(&mut mem),
                    Default::default(),
                )
                .expect("no zero pivot");
            }
        }
        values
    }

    /// The supernodal symbolic factor under the postordered nested dissection.
    fn symbolic(a: &SparseColMat<usize, f64>) -> SymbolicCholesky<usize> {
        let order = postordered(a, &nested_dissection(a));
        let mut inverse = vec![0usize; order.len()];
        for (k, &i) in order.iter().enumerate() {
            inverse[i] = k;
        }
        let params = CholeskySymbolicParams {
            supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
            ..Default::default()
        };
        factorize_symbolic_cholesky(
            a.symbolic(),
            Side::Lower,
            SymmetricOrdering::Custom(PermRef::new_checked(&order, &inverse, order.len())),
            params,
        )
        .expect("symbolic analysis")
    }

    #[test]
    fn tree_solves_match_faers_solve_for_any_thread_count() {
        // L Lᵀ (positive definite) and L D Lᵀ (indefinite, no pivoting) on 3D grids; blocks
        // of 1, 5 and 16 seeded random right-hand sides. faer's sequential supernodal solve is
        // the reference: the same factor, the same operations in another order, so the two
        // differ by rounding amplified by the matrix's condition number (from the grid's
        // analytic eigenvalues): 64 eps cond relative to the solution's largest entry. One,
        // two and three threads must give the same bits: the splits depend on the tree only.
        for (m, shift, kind) in [(9, -0.5, Llt), (12, -0.01, Llt), (11, 2.9, Ldlt)] {
            let a = grid(m, shift);
            let n = a.nrows();
            // Eigenvalues of the grid: sum over the axes of 2 - 2 cos(pi i / (m + 1)).
            let axis: Vec<f64> = (1..=m)
                .map(|i| 2.0 - 2.0 * (std::f64::consts::PI * i as f64 / (m + 1) as f64).cos())
                .collect();
            let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
            for x in &axis {
                for y in &axis {
                    for z in &axis {
                        let d = (x + y + z - shift).abs();
                        lo = lo.min(d);
                        hi = hi.max(d);
                    }
                }
            }
            let tolerance = 64.0 * f64::EPSILON * hi / lo;
            let sym = symbolic(&a);
            let values = factor(&a, &sym, kind);
            let plan = TreePlan::new(&sym).expect("postordered supernodal factor");
            for cols in [1, 5, 16] {
                let mut rng = XorShift64::seeded((m * 100 + cols) as u64);
                let b: Vec<f64> = (0..n * cols).map(|_| rng.centred_uniform()).collect();
                let mut reference = b.clone();
                let mut mem = MemBuffer::new(sym.solve_in_place_scratch::<f64>(cols, Par::Seq));
                let rhs = MatMut::from_column_major_slice_mut(&mut reference, n, cols);
                match kind {
                    Llt => LltRef::<usize, f64>::new(&sym, &values).solve_in_place_with_conj(
                        faer::Conj::No,
                        rhs,
                        Par::Seq,
                        MemStack::new(&mut mem),
                    ),
                    Ldlt => LdltRef::<usize, f64>::new(&sym, &values).solve_in_place_with_conj(
                        faer::Conj::No,
                        rhs,
                        Par::Seq,
                        MemStack::new(&mut mem),
                    ),
                }
                let scale = reference.iter().fold(0.0f64, |a, v| a.max(v.abs()));
                let mut first: Option<Vec<f64>> = None;
                // The solve's row-major copy comes from a workspace; poisoned, so that a row
                // the scatter missed would show.
                let mut ws = Workspace::new();
                ws.give(vec![f64::NAN; n * cols]);
                for threads in [1, 2, 3] {
                    let pool = rayon::ThreadPoolBuilder::new()
                        .num_threads(threads)
                        .build()
                        .expect("thread pool");
                    let mut x = b.clone();
                    pool.install(|| plan.solve_in_place(&values, kind, &mut x, &mut ws));
                    for (i, (v, r)) in x.iter().zip(&reference).enumerate() {
                        assert!(
                            (v - r).abs() <= tolerance * scale,
                            "m {m}, {kind:?}, {cols} columns, {threads} threads, entry {i}: \
                             {v} against faer's {r} (tolerance {tolerance:.1e})"
                        );
                    }
                    match &first {
                        None => first = Some(x),
                        Some(f) => assert!(
                            f.iter().zip(&x).all(|(a, b)| a.to_bits() == b.to_bits()),
                            "m {m}, {kind:?}, {cols} columns: {threads} threads changed bits"
                        ),
                    }
                }
            }
        }
    }

    #[test]
    fn a_factor_whose_supernodes_are_not_postordered_gets_no_plan() {
        // The grid in a seeded random numbering: its elimination tree's subtrees are not
        // contiguous, which the tree solve cannot cut into row ranges; faer's solve takes
        // over (ShiftInvert::apply_block).
        let a = grid(7, -0.5);
        let n = a.nrows();
        let mut order: Vec<usize> = (0..n).collect();
        let mut rng = XorShift64::seeded(17);
        for i in (1..n).rev() {
            let j = (((rng.centred_uniform() + 0.5) * (i + 1) as f64) as usize).min(i);
            order.swap(i, j);
        }
        let mut inverse = vec![0usize; order.len()];
        for (k, &i) in order.iter().enumerate() {
            inverse[i] = k;
        }
        let params = CholeskySymbolicParams {
            supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
            ..Default::default()
        };
        let sym = factorize_symbolic_cholesky(
            a.symbolic(),
            Side::Lower,
            SymmetricOrdering::Custom(PermRef::new_checked(&order, &inverse, order.len())),
            params,
        )
        .expect("symbolic analysis");
        assert!(TreePlan::new(&sym).is_none());
    }
}
