//! Sparse symmetric generalized eigen solver for one harmonic: all eigenpairs of
//! K x = lambda M x with lambda below a bound, by shift-invert Lanczos with full
//! reorthogonalisation, checked by a Sturm count.
//!
//! - Storage: the upper triangles of K and M share one compressed-column pattern (in a
//!   fill-reducing AMD order), so that K - sigma M is a plain combination of the value arrays.
//! - Factorisation: faer's simplicial sparse LDL^T (no pivoting) of K - sigma M.
//! - Lanczos (Ericsson & Ruhe 1980; Parlett, The Symmetric Eigenvalue Problem, ch. 13) on the
//!   operator (K - sigma M)^{-1} M, self-adjoint in the M inner product, with sigma < 0 so that
//!   the factor is positive definite even for a free body (K singular). A Ritz pair (theta, y)
//!   of the tridiagonal T_m gives lambda = sigma + 1/theta; its transformed residual is
//!   |beta_m s_m| (last component of the eigenvector of T_m). Every Lanczos vector is
//!   M-orthogonalised twice (classical Gram-Schmidt, "twice is enough") against all previous
//!   ones and against already accepted eigenvectors (explicit deflation).
//! - Sturm count (Sylvester's law of inertia): the number of negative pivots of the LDL^T of
//!   K - sigma_max M equals the number of eigenvalues below sigma_max (M positive definite).
//!   Lanczos runs are repeated from fresh start vectors, deflating the accepted pairs, until
//!   the accepted count equals that number; exactly repeated eigenvalues (which one Krylov
//!   sequence can see only once) are found that way.

// Index loops follow the compressed-column layout (col_ptr / row_idx / values side by side).
#![allow(clippy::needless_range_loop)]

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::ldlt::factor::LdltRegularization;
use faer::sparse::linalg::amd;
use faer::sparse::linalg::cholesky::simplicial;
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, Mat, MatMut, Par};

use crate::linalg::inertia::simplicial_negative_pivots;
use crate::modal::block::random_vector;
use crate::{Error, Result};

/// Symmetric K and M with one shared upper-triangle pattern.
pub struct PencilMatrices {
    n: usize,
    pat: std::sync::Arc<Pattern>,
    k_val: Vec<f64>,
    m_val: Vec<f64>,
    /// Both triangles row by row (pattern `full_ptr` / `full_col` of [`Pattern`]), for
    /// gather-only products: y_r = sum_c A_rc x_c without scattered writes.
    k_full: Vec<f64>,
    m_full: Vec<f64>,
}

/// The value-independent part of a pencil: order, upper-triangle pattern, symbolic factor and
/// where each input entry lands. Harmonics with the same degree-of-freedom map (all n >= 2, and
/// every n for a section off the axis) share one, so their assembly is a plain scatter.
pub struct Pattern {
    n: usize,
    /// Fill-reducing order: `perm_inv[old] = new`.
    perm_inv: Vec<usize>,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    /// Value slot of each input pair (in the order given to [`Pattern::new`]).
    slot: Vec<usize>,
    symbolic: simplicial::SymbolicSimplicialCholesky<usize>,
    /// Both triangles as rows: row pointers, column of each entry and the stored (upper)
    /// entry it copies.
    full_ptr: Vec<usize>,
    full_col: Vec<usize>,
    full_src: Vec<usize>,
}

impl Pattern {
    /// Pattern of the input pairs (i, j), i <= j (original numbering), under `perm_inv`.
    pub fn new(n: usize, pairs: &[(usize, usize)], perm_inv: Vec<usize>) -> Result<Pattern> {
        // Permuted upper position (col = max, row = min) of each input, sorted once.
        let keys: Vec<u64> = pairs
            .iter()
            .map(|&(i, j)| {
                let (a, b) = (perm_inv[i], perm_inv[j]);
                ((a.max(b) as u64) << 32) | a.min(b) as u64
            })
            .collect();
        let mut order: Vec<u32> = (0..keys.len() as u32).collect();
        order.sort_unstable_by_key(|&t| keys[t as usize]);
        let mut slot = vec![0usize; keys.len()];
        let mut uniq: Vec<(usize, usize)> = Vec::new();
        let mut last = u64::MAX;
        for &t in &order {
            let key = keys[t as usize];
            if key != last {
                uniq.push(((key >> 32) as usize, (key & 0xffff_ffff) as usize));
                last = key;
            }
            slot[t as usize] = uniq.len() - 1;
        }
        let (col_ptr, row_idx) = compress(n, &uniq);
        let symbolic = {
            let sym = SymbolicSparseColMatRef::new_checked(n, n, &col_ptr, None, &row_idx);
            let mut mem = MemBuffer::new(StackReq::any_of(&[
                simplicial::prefactorize_symbolic_cholesky_scratch::<usize>(n, row_idx.len()),
                simplicial::factorize_simplicial_symbolic_cholesky_scratch::<usize>(n),
            ]));
            let stack = MemStack::new(&mut mem);
            let mut etree = vec![0isize; n];
            let mut col_counts = vec![0usize; n];
            simplicial::prefactorize_symbolic_cholesky(&mut etree, &mut col_counts, sym, stack);
            simplicial::factorize_simplicial_symbolic_cholesky(
                sym,
                // SAFETY: `etree` was filled by `prefactorize_symbolic_cholesky` for this pattern.
                unsafe { simplicial::EliminationTreeRef::from_inner(&etree) },
                &col_counts,
                stack,
            )
            .map_err(|e| faer_err("symbolic factorisation", e))?
        };
        // Both triangles, row by row.
        let mut counts = vec![0usize; n + 1];
        for j in 0..n {
            for &i in &row_idx[col_ptr[j]..col_ptr[j + 1]] {
                counts[i + 1] += 1;
                if i != j {
                    counts[j + 1] += 1;
                }
            }
        }
        for r in 0..n {
            counts[r + 1] += counts[r];
        }
        let full_ptr = counts.clone();
        let mut fill = counts;
        let total = full_ptr[n];
        let mut full_col = vec![0usize; total];
        let mut full_src = vec![0usize; total];
        for j in 0..n {
            for p in col_ptr[j]..col_ptr[j + 1] {
                let i = row_idx[p];
                full_col[fill[i]] = j;
                full_src[fill[i]] = p;
                fill[i] += 1;
                if i != j {
                    full_col[fill[j]] = i;
                    full_src[fill[j]] = p;
                    fill[j] += 1;
                }
            }
        }
        Ok(Pattern {
            n,
            perm_inv,
            col_ptr,
            row_idx,
            slot,
            symbolic,
            full_ptr,
            full_col,
            full_src,
        })
    }
}

/// An LDL^T factor of K - sigma M.
pub struct ShiftedFactor<'a> {
    pencil: &'a PencilMatrices,
    l_values: Vec<f64>,
    /// Number of negative pivots (= eigenvalues below sigma).
    pub negative_pivots: usize,
}

fn faer_err(what: &str, e: impl std::fmt::Debug) -> Error {
    Error::Numerical(format!("axisymmetric eigen solver: {what}: {e:?}"))
}

impl PencilMatrices {
    /// Scatter entry values (in the order of the pairs the pattern was built from; duplicates
    /// summed) onto a shared pattern.
    pub fn from_values(pat: std::sync::Arc<Pattern>, k: &[f64], m: &[f64]) -> Self {
        assert_eq!(k.len(), pat.slot.len());
        assert_eq!(m.len(), pat.slot.len());
        let nnz = pat.row_idx.len();
        let mut k_val = vec![0.0; nnz];
        let mut m_val = vec![0.0; nnz];
        for ((&s, &kv), &mv) in pat.slot.iter().zip(k).zip(m) {
            k_val[s] += kv;
            m_val[s] += mv;
        }
        let k_full = pat.full_src.iter().map(|&p| k_val[p]).collect();
        let m_full = pat.full_src.iter().map(|&p| m_val[p]).collect();
        PencilMatrices {
            n: pat.n,
            pat,
            k_val,
            m_val,
            k_full,
            m_full,
        }
    }

    /// Dimension.
    pub fn dim(&self) -> usize {
        self.n
    }

    /// Entries stored (upper triangle).
    pub fn nnz(&self) -> usize {
        self.pat.row_idx.len()
    }

    /// Entries of the LDL^T factor.
    pub fn factor_nnz(&self) -> usize {
        self.pat.symbolic.len_val()
    }

    /// Largest diagonal entry of K (a stiffness scale).
    pub fn max_k_diagonal(&self) -> f64 {
        let mut m = 0.0f64;
        for j in 0..self.n {
            for p in self.pat.col_ptr[j]..self.pat.col_ptr[j + 1] {
                if self.pat.row_idx[p] == j {
                    m = m.max(self.k_val[p].abs());
                }
            }
        }
        m
    }

    fn sym_mul(&self, full_vals: &[f64], x: &[f64], y: &mut [f64]) {
        let (ptr, col) = (&self.pat.full_ptr, &self.pat.full_col);
        for (r, yr) in y.iter_mut().enumerate() {
            let mut acc = 0.0;
            for q in ptr[r]..ptr[r + 1] {
                acc += full_vals[q] * x[col[q]];
            }
            *yr = acc;
        }
    }

    /// y = K x (permuted numbering).
    pub fn k_mul(&self, x: &[f64], y: &mut [f64]) {
        self.sym_mul(&self.k_full, x, y)
    }

    /// y = M x (permuted numbering).
    pub fn m_mul(&self, x: &[f64], y: &mut [f64]) {
        self.sym_mul(&self.m_full, x, y)
    }

    /// x^T M x split by the component (0, 1, 2) that owns each dof (`owner`, permuted
    /// numbering); exact when M couples only dofs of one component. One pass over M.
    pub fn component_energies(&self, x: &[f64], owner: &[usize]) -> [f64; 3] {
        let mut e = [0.0; 3];
        for j in 0..self.n {
            for p in self.pat.col_ptr[j]..self.pat.col_ptr[j + 1] {
                let i = self.pat.row_idx[p];
                let c = owner[j];
                if owner[i] == c && c < 3 {
                    let v = self.m_val[p] * x[i] * x[j];
                    e[c] += if i == j { v } else { 2.0 * v };
                }
            }
        }
        e
    }

    /// Vector in the permuted numbering -> original numbering.
    pub fn unpermute(&self, x: &[f64]) -> Vec<f64> {
        (0..self.n).map(|old| x[self.pat.perm_inv[old]]).collect()
    }

    /// Vector in the original numbering -> permuted numbering.
    pub fn permute(&self, x: &[f64]) -> Vec<f64> {
        let mut y = vec![0.0; self.n];
        for (old, &new) in self.pat.perm_inv.iter().enumerate() {
            y[new] = x[old];
        }
        y
    }

    /// LDL^T of K - sigma M.
    pub fn factor(&self, sigma: f64) -> Result<ShiftedFactor<'_>> {
        let vals: Vec<f64> = self
            .k_val
            .iter()
            .zip(&self.m_val)
            .map(|(k, m)| k - sigma * m)
            .collect();
        let sym = SymbolicSparseColMatRef::new_checked(
            self.n,
            self.n,
            &self.pat.col_ptr,
            None,
            &self.pat.row_idx,
        );
        let a = SparseColMatRef::new(sym, &vals);
        let mut l_values = vec![0.0f64; self.pat.symbolic.len_val()];
        let mut mem = MemBuffer::new(simplicial::factorize_simplicial_numeric_ldlt_scratch::<
            usize,
            f64,
        >(self.n));
        simplicial::factorize_simplicial_numeric_ldlt::<usize, f64>(
            &mut l_values,
            a,
            LdltRegularization::default(),
            &self.pat.symbolic,
            MemStack::new(&mut mem),
        )
        .map_err(|e| faer_err(&format!("LDL^T of K - sigma M at sigma = {sigma:.6e}"), e))?;
        let negative = simplicial_negative_pivots(&self.pat.symbolic, &l_values, sigma)?;
        Ok(ShiftedFactor {
            pencil: self,
            l_values,
            negative_pivots: negative,
        })
    }
}

impl ShiftedFactor<'_> {
    /// Solve (K - sigma M) x = b in place (permuted numbering).
    pub fn solve_in_place(&self, b: &mut [f64]) {
        self.solve_block_in_place(b, 1)
    }

    /// Solve for `ncols` right-hand sides stored column-major in `b` (permuted numbering).
    pub fn solve_block_in_place(&self, b: &mut [f64], ncols: usize) {
        let n = self.pencil.n;
        assert_eq!(b.len(), n * ncols);
        let ldlt = simplicial::SimplicialLdltRef::<'_, usize, f64>::new(
            &self.pencil.pat.symbolic,
            &self.l_values,
        );
        let mut mem = MemBuffer::new(
            self.pencil
                .pat
                .symbolic
                .solve_in_place_scratch::<f64>(ncols),
        );
        let rhs = MatMut::from_column_major_slice_mut(b, n, ncols);
        ldlt.solve_in_place_with_conj(Conj::No, rhs, Par::Seq, MemStack::new(&mut mem));
    }
}

/// One step of subspace iteration with Rayleigh-Ritz (Bathe, Finite Element Procedures,
/// sec. 11.6): Y = (K - sigma M)^{-1} M X, then the k x k pencil (Y^T K Y, Y^T M Y) is solved
/// densely (Cholesky of Y^T M Y, symmetric eigen of L^{-1} (Y^T K Y) L^{-T}) and X = Y L^{-T} Q.
/// The inverse step damps every error component along an eigenvector j outside the set by
/// (lambda_i - sigma) / (lambda_j - sigma); the Lanczos vectors' leftover errors lie mostly
/// along the stiffest (discretisation-scale) modes, which is what the relative residual
/// ||K x - lambda M x|| / ||K x|| amplifies, so one step brings it down by orders of magnitude.
fn polish(
    p: &PencilMatrices,
    fac: &ShiftedFactor<'_>,
    x: &[Vec<f64>],
) -> Result<(Vec<f64>, Vec<Vec<f64>>)> {
    let (n, k) = (p.dim(), x.len());
    if k == 0 {
        return Ok((Vec::new(), Vec::new()));
    }
    // All k right-hand sides in one column-major block: one pass over the factor.
    let mut block = vec![0.0; n * k];
    for (xi, col) in x.iter().zip(block.chunks_exact_mut(n)) {
        p.m_mul(xi, col);
    }
    fac.solve_block_in_place(&mut block, k);
    let mut y: Vec<Vec<f64>> = Vec::with_capacity(k);
    let mut tmp = vec![0.0; n];
    for col in block.chunks_exact(n) {
        let mut w = col.to_vec();
        p.m_mul(&w, &mut tmp);
        let nm = m_dot(&tmp, &w).sqrt();
        w.iter_mut().for_each(|v| *v /= nm);
        y.push(w);
    }
    let mut ky = Vec::with_capacity(k);
    let mut my = Vec::with_capacity(k);
    for yi in &y {
        let mut a = vec![0.0; n];
        p.k_mul(yi, &mut a);
        ky.push(a);
        let mut b = vec![0.0; n];
        p.m_mul(yi, &mut b);
        my.push(b);
    }
    let a = Mat::<f64>::from_fn(k, k, |i, j| {
        0.5 * (m_dot(&ky[i], &y[j]) + m_dot(&ky[j], &y[i]))
    });
    let b = Mat::<f64>::from_fn(k, k, |i, j| {
        0.5 * (m_dot(&my[i], &y[j]) + m_dot(&my[j], &y[i]))
    });
    let llt = b
        .llt(faer::Side::Lower)
        .map_err(|e| faer_err("Rayleigh-Ritz: Y^T M Y is not positive definite", e))?;
    let l = llt.L().to_owned();
    // C = L^{-1} A L^{-T}.
    let mut c = a.clone();
    faer::linalg::triangular_solve::solve_lower_triangular_in_place(
        l.as_ref(),
        c.as_mut(),
        Par::Seq,
    );
    let mut ct = c.transpose().to_owned();
    faer::linalg::triangular_solve::solve_lower_triangular_in_place(
        l.as_ref(),
        ct.as_mut(),
        Par::Seq,
    );
    let c = Mat::<f64>::from_fn(k, k, |i, j| 0.5 * (ct[(i, j)] + ct[(j, i)]));
    let eig = c
        .self_adjoint_eigen(faer::Side::Lower)
        .map_err(|e| faer_err("Rayleigh-Ritz eigen", e))?;
    // Coefficients G = L^{-T} Q.
    let mut g = eig.U().to_owned();
    faer::linalg::triangular_solve::solve_upper_triangular_in_place(
        l.transpose(),
        g.as_mut(),
        Par::Seq,
    );
    let s = eig.S().column_vector();
    let values: Vec<f64> = (0..k).map(|i| s[i]).collect();
    let vectors: Vec<Vec<f64>> = (0..k)
        .map(|col| {
            let mut v = vec![0.0; n];
            for (j, yj) in y.iter().enumerate() {
                let cj = g[(j, col)];
                v.iter_mut().zip(yj).for_each(|(a, b)| *a += cj * b);
            }
            v
        })
        .collect();
    Ok((values, vectors))
}

/// Approximate minimum degree order (faer's AMD) of the symmetric pattern given by index
/// pairs (i, j) (either triangle, duplicates allowed); returns `perm_inv[old] = new`.
pub fn amd_order(n: usize, pairs: Vec<(usize, usize)>) -> Result<Vec<usize>> {
    let mut pairs: Vec<(usize, usize)> = pairs
        .into_iter()
        .map(|(i, j)| (i.max(j), i.min(j)))
        .collect();
    pairs.sort_unstable();
    pairs.dedup();
    // Column-major: col = j (first of the sorted pair), rows i <= j.
    let (col_ptr, row_idx) = compress(n, &pairs);
    let mut perm = vec![0usize; n];
    let mut perm_inv = vec![0usize; n];
    let sym = SymbolicSparseColMatRef::new_checked(n, n, &col_ptr, None, &row_idx);
    let mut mem = MemBuffer::new(amd::order_scratch::<usize>(n, row_idx.len()));
    amd::order(
        &mut perm,
        &mut perm_inv,
        sym,
        amd::Control::default(),
        MemStack::new(&mut mem),
    )
    .map_err(|e| faer_err("ordering", e))?;
    Ok(perm_inv)
}

/// Compress sorted unique (col, row) pairs into CSC arrays.
fn compress(n: usize, pairs: &[(usize, usize)]) -> (Vec<usize>, Vec<usize>) {
    let mut col_ptr = vec![0usize; n + 1];
    for &(c, _) in pairs {
        col_ptr[c + 1] += 1;
    }
    for j in 0..n {
        col_ptr[j + 1] += col_ptr[j];
    }
    let row_idx = pairs.iter().map(|&(_, r)| r).collect();
    (col_ptr, row_idx)
}

/// Settings of [`solve_below`].
#[derive(Clone, Copy, Debug)]
pub struct EigenSettings {
    /// Upper bound of the wanted eigenvalues (omega^2, rad^2/s^2).
    pub lambda_max: f64,
    /// Lanczos shift (negative: K - sigma M positive definite for a free body).
    pub sigma: f64,
    /// Accept a Ritz pair when |beta_m s_m| <= tol * theta (transformed problem).
    pub ritz_tolerance: f64,
}

/// Eigenpairs (lambda ascending, vectors M-normalised, permuted numbering) and the Sturm count.
pub struct EigenResult {
    /// Eigenvalues (omega^2).
    pub values: Vec<f64>,
    /// Eigenvectors (permuted numbering; use [`PencilMatrices::unpermute`]).
    pub vectors: Vec<Vec<f64>>,
    /// Sturm count: eigenvalues below `lambda_max`.
    pub sturm_count: usize,
    /// Lanczos steps taken in all runs.
    pub lanczos_steps: usize,
}

/// Euclidean dot product (with `M x` as one argument: the M inner product). Eight partial
/// sums so that the compiler can vectorise (a single running sum is latency-bound, and the
/// full reorthogonalisation is made of these).
pub fn m_dot(mx: &[f64], y: &[f64]) -> f64 {
    let mut acc = [0.0f64; 8];
    let (a8, b8) = (mx.chunks_exact(8), y.chunks_exact(8));
    let tail: f64 = a8
        .remainder()
        .iter()
        .zip(b8.remainder())
        .map(|(a, b)| a * b)
        .sum();
    for (a, b) in a8.zip(b8) {
        for k in 0..8 {
            acc[k] += a[k] * b[k];
        }
    }
    acc.iter().sum::<f64>() + tail
}

/// All eigenpairs with lambda < `lambda_max`.
///
/// `known`: exact eigenvectors known beforehand (permuted numbering; here the rigid-body
/// motions of a free body, K x = 0), locked before the Lanczos runs so that the runs need not
/// resolve their (repeated) zero eigenvalue. They are M-orthonormalised; those with a
/// Rayleigh quotient at or above `lambda_max` are ignored.
///
/// Kept in one piece: the restarted Lanczos runs with deflation and their bookkeeping share one
/// state; the factor, the dot products and the polish are functions of their own.
pub fn solve_below(
    p: &PencilMatrices,
    s: &EigenSettings,
    known: &[Vec<f64>],
) -> Result<EigenResult> {
    let n = p.dim();
    let sturm = p.factor(s.lambda_max)?;
    let wanted = sturm.negative_pivots;
    drop(sturm);
    let fac = p.factor(s.sigma)?;
    if fac.negative_pivots != 0 {
        return Err(Error::Numerical(format!(
            "axisymmetric eigen solver: K - sigma M is not positive definite at sigma = {:.3e} \
             ({} negative pivots): the model has {} eigenvalues below the shift",
            s.sigma, fac.negative_pivots, fac.negative_pivots
        )));
    }
    let mut values: Vec<f64> = Vec::new();
    let mut vectors: Vec<Vec<f64>> = Vec::new();
    let mut locked_m: Vec<Vec<f64>> = Vec::new(); // M y of accepted vectors
    let mut steps_total = 0usize;
    let mut round = 0u64;
    let mut tmp = vec![0.0; n];
    for x in known {
        let mut y = x.clone();
        for _ in 0..2 {
            for (z, mz) in vectors.iter().zip(&locked_m) {
                let c = m_dot(mz, &y);
                y.iter_mut().zip(z).for_each(|(a, b)| *a -= c * b);
            }
        }
        let mut my = vec![0.0; n];
        p.m_mul(&y, &mut my);
        let nm = m_dot(&my, &y).sqrt();
        if nm.is_nan() || nm <= 0.0 || values.len() >= wanted {
            continue;
        }
        y.iter_mut().for_each(|a| *a /= nm);
        my.iter_mut().for_each(|a| *a /= nm);
        p.k_mul(&y, &mut tmp);
        let lambda = m_dot(&tmp, &y);
        if lambda >= s.lambda_max {
            continue;
        }
        values.push(lambda);
        vectors.push(y);
        locked_m.push(my);
    }
    while values.len() < wanted {
        round += 1;
        if round > 8 {
            return Err(Error::Numerical(format!(
                "axisymmetric eigen solver: found {} of the {} eigenvalues below {:.6e} \
                 (Sturm count) after {} Lanczos runs",
                values.len(),
                wanted,
                s.lambda_max,
                round - 1
            )));
        }
        let missing = wanted - values.len();
        let max_steps = (n - vectors.len()).max(1);
        let mut q: Vec<Vec<f64>> = Vec::new();
        let mut mq: Vec<Vec<f64>> = Vec::new();
        let mut alpha: Vec<f64> = Vec::new();
        let mut beta: Vec<f64> = Vec::new();
        let mut v = random_vector(n, round);
        let mut accepted_this_round = false;
        let mut next_check = (missing + 10).min(max_steps);
        // Checks in a row at which every wanted Ritz value had converged but no new one had
        // appeared: the sequence has found all it can see (an exactly repeated eigenvalue shows
        // once per Krylov sequence); the next run, deflated, finds the other copies.
        let (mut stall, mut prev_seen) = (0usize, usize::MAX);
        loop {
            // Orthogonalise v against locked and current Lanczos vectors, twice.
            for _ in 0..2 {
                for (y, my) in vectors.iter().zip(&locked_m) {
                    let c = m_dot(my, &v);
                    v.iter_mut().zip(y).for_each(|(a, b)| *a -= c * b);
                }
                for (qi, mqi) in q.iter().zip(&mq) {
                    let c = m_dot(mqi, &v);
                    v.iter_mut().zip(qi).for_each(|(a, b)| *a -= c * b);
                }
            }
            p.m_mul(&v, &mut tmp);
            let norm = m_dot(&tmp, &v).max(0.0).sqrt();
            let j = q.len();
            if j > 0 {
                beta.push(norm);
            }
            let breakdown = norm <= 1e-12 * (1.0 + beta.iter().fold(0.0f64, |m, b| m.max(*b)));
            let at_check = j >= next_check || j >= max_steps || breakdown;
            if at_check && j > 0 {
                // Ritz pairs of T_j.
                let t = Mat::<f64>::from_fn(j, j, |a, b| {
                    if a == b {
                        alpha[a]
                    } else if a + 1 == b {
                        beta[a]
                    } else if b + 1 == a {
                        beta[b]
                    } else {
                        0.0
                    }
                });
                let eig = t
                    .self_adjoint_eigen(faer::Side::Lower)
                    .map_err(|e| faer_err("tridiagonal eigen", e))?;
                let th = eig.S().column_vector();
                let sv = eig.U();
                let beta_j = if breakdown { 0.0 } else { norm };
                let mut cands: Vec<(f64, usize)> = Vec::new();
                let mut all_wanted_converged = true;
                let mut n_wanted_seen = 0;
                for i in 0..j {
                    let theta = th[i];
                    if theta <= 0.0 {
                        continue;
                    }
                    let lambda = s.sigma + 1.0 / theta;
                    if lambda >= s.lambda_max {
                        continue;
                    }
                    n_wanted_seen += 1;
                    let est = (beta_j * sv[(j - 1, i)]).abs();
                    if est <= s.ritz_tolerance * theta {
                        cands.push((lambda, i));
                    } else {
                        all_wanted_converged = false;
                    }
                }
                if all_wanted_converged && n_wanted_seen == prev_seen {
                    stall += 1;
                } else {
                    stall = 0;
                }
                prev_seen = n_wanted_seen;
                let done = (all_wanted_converged && (n_wanted_seen >= missing || stall >= 2))
                    || breakdown
                    || j >= max_steps;
                if done {
                    for &(lambda, i) in &cands {
                        let mut y = vec![0.0; n];
                        for (k, qk) in q.iter().enumerate() {
                            let c = sv[(k, i)];
                            y.iter_mut().zip(qk).for_each(|(a, b)| *a += c * b);
                        }
                        // Re-orthogonalise against the locked set and normalise.
                        for _ in 0..2 {
                            for (z, mz) in vectors.iter().zip(&locked_m) {
                                let c = m_dot(mz, &y);
                                y.iter_mut().zip(z).for_each(|(a, b)| *a -= c * b);
                            }
                        }
                        let mut my = vec![0.0; n];
                        p.m_mul(&y, &mut my);
                        let nm = m_dot(&my, &y).sqrt();
                        if nm <= 1e-8 {
                            continue;
                        }
                        y.iter_mut().for_each(|a| *a /= nm);
                        my.iter_mut().for_each(|a| *a /= nm);
                        values.push(lambda);
                        vectors.push(y);
                        locked_m.push(my);
                        accepted_this_round = true;
                    }
                    steps_total += j;
                    break;
                }
                // Checks are cheap (a j x j tridiagonal eigen); frequent ones stop the run
                // soon after the last wanted pair converges.
                next_check = (j + (j / 8).max(4)).min(max_steps);
            }
            if breakdown {
                steps_total += j;
                break;
            }
            // Next Lanczos vector.
            let inv = 1.0 / norm;
            v.iter_mut().for_each(|a| *a *= inv);
            tmp.iter_mut().for_each(|a| *a *= inv);
            let mut w = tmp.clone();
            fac.solve_in_place(&mut w);
            let a = m_dot(&tmp, &w);
            q.push(v);
            mq.push(tmp.clone());
            alpha.push(a);
            v = w;
        }
        if !accepted_this_round && values.len() < wanted && vectors.len() + 1 >= n {
            break;
        }
    }
    if values.len() != wanted {
        return Err(Error::Numerical(format!(
            "axisymmetric eigen solver: {} eigenvalues accepted but the Sturm count below \
             {:.6e} is {}",
            values.len(),
            s.lambda_max,
            wanted
        )));
    }
    let (values, vectors) = polish(p, &fac, &vectors)?;
    let mut order: Vec<usize> = (0..values.len()).collect();
    order.sort_by(|&a, &b| values[a].total_cmp(&values[b]));
    Ok(EigenResult {
        values: order.iter().map(|&i| values[i]).collect(),
        vectors: order.iter().map(|&i| vectors[i].clone()).collect(),
        sturm_count: wanted,
        lanczos_steps: steps_total,
    })
}
