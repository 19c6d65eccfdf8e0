//! The elimination tree of a symmetric matrix under an ordering, and the ordering renumbered in
//! a postorder of that tree.
//!
//! The elimination tree (Liu, "The role of elimination trees in sparse factorization", SIAM J.
//! Matrix Anal. Appl. 11, 1990): the parent of column `j` of the Cholesky factor is the row of
//! its first off-diagonal nonzero. It is found from the matrix alone, row by row, following
//! each row's entries up the tree built so far with path compression (Liu's algorithm).
//! Renumbering the columns in a depth-first postorder of the tree is an equivalent ordering
//! (the same factor entries, the same work) in which every subtree is a contiguous range of
//! columns ending with its root. The tree-parallel solve ([`crate::linalg::tree_solve`]) needs
//! that: its subtrees' rows are then disjoint slices of the right-hand side. Nested dissection
//! numbers the separators after both halves but leaves its minimum-degree leaves in their own
//! order, so it is not a postorder by itself.

use faer::sparse::SparseColMat;

const NONE: usize = usize::MAX;

/// Parent of each column of the factor of `P A Pᵀ` (`NONE` for a root), where `A` is symmetric
/// with its lower triangle stored and `order[new] = old`.
pub(crate) fn elimination_tree(a: &SparseColMat<usize, f64>, order: &[usize]) -> Vec<usize> {
    let n = a.nrows();
    let mut inverse = vec![0usize; n];
    for (new, &old) in order.iter().enumerate() {
        inverse[old] = new;
    }
    // For each new row k, the new columns i < k with an entry (k, i): a row-wise copy of the
    // permuted lower triangle, by counting.
    let col_ptr = a.symbolic().col_ptr();
    let row_idx = a.symbolic().row_idx();
    let mut count = vec![0usize; n + 1];
    for j in 0..n {
        for &r in &row_idx[col_ptr[j]..col_ptr[j + 1]] {
            let (hi, lo) = (inverse[r].max(inverse[j]), inverse[r].min(inverse[j]));
            if hi != lo {
                count[hi + 1] += 1;
            }
        }
    }
    for k in 0..n {
        count[k + 1] += count[k];
    }
    let row_ptr = count.clone();
    let mut cols = vec![0usize; row_ptr[n]];
    for j in 0..n {
        for &r in &row_idx[col_ptr[j]..col_ptr[j + 1]] {
            let (hi, lo) = (inverse[r].max(inverse[j]), inverse[r].min(inverse[j]));
            if hi != lo {
                cols[count[hi]] = lo;
                count[hi] += 1;
            }
        }
    }
    let mut parent = vec![NONE; n];
    let mut ancestor = vec![NONE; n];
    for k in 0..n {
        for &i in &cols[row_ptr[k]..row_ptr[k + 1]] {
            // Climb from i to the root of its current subtree, pointing the path at k.
            let mut r = i;
            while ancestor[r] != NONE && ancestor[r] != k {
                let next = ancestor[r];
                ancestor[r] = k;
                r = next;
            }
            if ancestor[r] == NONE {
                ancestor[r] = k;
                parent[r] = k;
            }
        }
    }
    parent
}

/// `order` renumbered in a depth-first postorder of the elimination tree of `P A Pᵀ` (children
/// in increasing order): `result[new] = old`, an equivalent ordering in which every subtree is
/// contiguous and ends with its root.
pub(crate) fn postordered(a: &SparseColMat<usize, f64>, order: &[usize]) -> Vec<usize> {
    let n = order.len();
    let parent = elimination_tree(a, order);
    let mut child_ptr = vec![0usize; n + 1];
    for &p in &parent {
        if p != NONE {
            child_ptr[p + 1] += 1;
        }
    }
    for k in 0..n {
        child_ptr[k + 1] += child_ptr[k];
    }
    let mut fill = child_ptr.clone();
    let mut children = vec![0usize; child_ptr[n]];
    for (c, &p) in parent.iter().enumerate() {
        if p != NONE {
            children[fill[p]] = c;
            fill[p] += 1;
        }
    }
    let mut result = Vec::with_capacity(n);
    // Iterative depth-first search: (node, next child to visit).
    let mut stack: Vec<(usize, usize)> = Vec::new();
    for root in (0..n).filter(|&k| parent[k] == NONE) {
        stack.push((root, child_ptr[root]));
        while let Some(top) = stack.last_mut() {
            let (node, next) = *top;
            if next < child_ptr[node + 1] {
                top.1 += 1;
                let child = children[next];
                stack.push((child, child_ptr[child]));
            } else {
                result.push(order[node]);
                stack.pop();
            }
        }
    }
    result
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random::XorShift64;

    /// Lower triangle of a random sparse symmetric pattern (diagonal always present).
    fn random_pattern(n: usize, density: f64, seed: u64) -> SparseColMat<usize, f64> {
        let mut rng = XorShift64::seeded(seed);
        let mut t = Vec::new();
        for j in 0..n {
            t.push(faer::sparse::Triplet::new(j, j, 4.0));
            for i in j + 1..n {
                if rng.centred_uniform().abs() < density {
                    t.push(faer::sparse::Triplet::new(i, j, -0.1));
                }
            }
        }
        SparseColMat::try_new_from_triplets(n, n, &t).expect("valid triplets")
    }

    /// Parent of each column from the factor's pattern itself: symbolic elimination on a dense
    /// boolean matrix (the slow, obvious reference).
    fn tree_by_elimination(a: &SparseColMat<usize, f64>, order: &[usize]) -> Vec<usize> {
        let n = a.nrows();
        let mut inverse = vec![0usize; n];
        for (new, &old) in order.iter().enumerate() {
            inverse[old] = new;
        }
        let mut nz = vec![vec![false; n]; n];
        let (cp, ri) = (a.symbolic().col_ptr(), a.symbolic().row_idx());
        for j in 0..n {
            for &r in &ri[cp[j]..cp[j + 1]] {
                let (x, y) = (inverse[r], inverse[j]);
                nz[x][y] = true;
                nz[y][x] = true;
            }
        }
        let mut parent = vec![NONE; n];
        for j in 0..n {
            let below: Vec<usize> = (j + 1..n).filter(|&i| nz[i][j]).collect();
            if let Some(&p) = below.first() {
                parent[j] = p;
            }
            // Eliminating j connects all its later neighbours.
            for &x in &below {
                for &y in &below {
                    nz[x][y] = true;
                }
            }
        }
        parent
    }

    #[test]
    fn the_tree_matches_symbolic_elimination_and_the_postorder_keeps_subtrees_contiguous() {
        for (n, density, seed) in [(1, 0.0, 1), (30, 0.1, 2), (80, 0.04, 3), (120, 0.02, 4)] {
            let a = random_pattern(n, density, seed);
            // A scrambled ordering (seeded shuffle).
            let mut order: Vec<usize> = (0..n).collect();
            let mut rng = XorShift64::seeded(seed + 100);
            for i in (1..n).rev() {
                let j = ((rng.centred_uniform() + 0.5) * (i + 1) as f64) as usize;
                order.swap(i, j.min(i));
            }
            assert_eq!(
                elimination_tree(&a, &order),
                tree_by_elimination(&a, &order),
                "n = {n}"
            );
            let post = postordered(&a, &order);
            let mut sorted = post.clone();
            sorted.sort_unstable();
            assert_eq!(sorted, (0..n).collect::<Vec<_>>(), "a permutation");
            // Postorder: each parent after its children, each subtree a contiguous range that
            // ends with its root, so a node's descendants are exactly the `size - 1` columns
            // just before it.
            let parent = elimination_tree(&a, &post);
            let mut size = vec![1usize; n];
            for j in 0..n {
                if parent[j] != NONE {
                    assert!(parent[j] > j, "n = {n}: parent before child");
                    size[parent[j]] += size[j];
                }
            }
            for j in 0..n {
                let mut k = j;
                while parent[k] != NONE {
                    k = parent[k];
                    assert!(
                        k + 1 - size[k] <= j,
                        "n = {n}: {j} outside the range of {k}"
                    );
                }
            }
        }
    }
}
