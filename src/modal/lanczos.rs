//! Shift-invert Lanczos for `K x = w² M x` (see the module docs of [`crate::modal`]).

use std::f64::consts::PI;
use std::time::Instant;

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::matmul::matmul;
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, LdltRef, LltRef, SymbolicCholesky, SymbolicCholeskyRaw,
    SymmetricOrdering,
};
use faer::sparse::SparseColMat;
use faer::{Accum, Mat, MatMut, MatRef, Par, Side};
use rayon::prelude::*;
use serde::Serialize;

use crate::fem::assembly::sym_lower_matvec;
use crate::modal::ordering::nested_dissection;
use crate::{Error, Result};

/// Options of the band solve.
#[derive(Clone, Debug)]
pub struct ModalOptions {
    /// Upper band edge (Hz).
    pub fmax_hz: f64,
    /// Modes below this frequency (Hz) are flagged rigid (free-free rigid-body motion).
    pub rigid_below_hz: f64,
    /// Shift magnitude (Hz): `sigma = -(2 pi shift_hz)²`; `None` chooses `max(fmax / 20, 10)`.
    pub shift_hz: Option<f64>,
    /// Largest relative residual accepted for a returned mode.
    pub residual_tolerance: f64,
    /// Largest Krylov basis (vectors) before giving up.
    pub max_basis: usize,
    /// Block size of the block Lanczos (columns per operator application).
    pub block_size: usize,
    /// Check completeness with a Sturm count: the negative pivots of the LDLᵀ of
    /// `K - w_max² M` (Sylvester's law of inertia, M positive definite) are the eigenvalues
    /// below `fmax`, which must equal the modes found. A second (simplicial) factorisation.
    pub sturm_check: bool,
    /// Slices of the band, one shift each (spectrum slicing): the first below the spectrum,
    /// the others in the middle of their slice (edges equally spaced in frequency). More
    /// slices mean more factorisations but smaller Krylov bases (orthogonalisation grows with
    /// the square of the basis): for wide bands with many modes. 1..=[`MAX_SLICES`].
    pub slices: usize,
}

impl Default for ModalOptions {
    fn default() -> Self {
        ModalOptions {
            fmax_hz: 10_000.0,
            rigid_below_hz: 1.0,
            shift_hz: None,
            // 1e-8: the acceptance bound; purified shift-invert Ritz vectors reach
            // 1e-10..1e-13 on the meshes of the tests.
            residual_tolerance: 1e-8,
            max_basis: 4000,
            // 16: on the 92 k dof wheel at 10 kHz, 29.9 s against 32.5 s with 8 and 44.8 s
            // with 32 (basis 592 / 504 / 832), measured 2026-11-23.
            block_size: 16,
            sturm_check: true,
            slices: 1,
        }
    }
}

/// One mode.
#[derive(Clone, Debug, Serialize)]
pub struct Mode {
    /// Frequency (Hz); negative round-off eigenvalues of rigid modes give `-sqrt(|w²|)/2pi`.
    pub frequency_hz: f64,
    /// Eigenvalue `w²` (rad²/s²).
    pub eigenvalue: f64,
    /// Relative residual (see the module docs).
    pub residual: f64,
    /// Rigid-body mode (frequency below `rigid_below_hz`).
    pub rigid: bool,
    /// Eigenvector in the reduced dofs, M-normalised (`xᵀ M x = 1`).
    #[serde(skip)]
    pub vector: Vec<f64>,
}

/// Result of a band solve.
#[derive(Clone, Debug, Serialize)]
pub struct ModalSolution {
    /// Modes, ascending frequency.
    pub modes: Vec<Mode>,
    /// Shift `sigma` below the spectrum (rad²/s²), the first slice's.
    pub shift: f64,
    /// The shift of every slice solved (rad²/s²; slices without modes are skipped).
    pub shifts: Vec<f64>,
    /// Final Krylov basis size.
    pub basis_size: usize,
    /// Block size.
    pub block_size: usize,
    /// Blocks applied (operator applications of `block_size` columns).
    pub blocks: usize,
    /// Factorisation time (s).
    pub factor_seconds: f64,
    /// Total solve time incl. factorisation (s).
    pub solve_seconds: f64,
    /// Eigenvalues below `fmax` by the Sturm count (None: not checked).
    pub sturm_count: Option<usize>,
}

/// Deterministic pseudo-random start vector (xorshift), so runs are reproducible.
fn random_vector(n: usize, seed: u64) -> Vec<f64> {
    let mut s = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
    (0..n)
        .map(|_| {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        })
        .collect()
}

struct ShiftInvert<'a> {
    m: &'a SparseColMat<usize, f64>,
    symbolic: &'a SymbolicCholesky<usize>,
    l_values: Vec<f64>,
    /// `L Lᵀ` (shift below the spectrum) or `L D Lᵀ` (shift inside the band).
    kind: FactorKind,
}

impl ShiftInvert<'_> {
    /// `W = (K - sigma M)⁻¹ M V` for a block of columns (column-major, `n` rows): the M
    /// products column by column in parallel, then multi-right-hand-side solves, which read the
    /// factor once per group of columns. The block is split into one column group per thread,
    /// each solved sequentially: faer's parallel solve synchronises inside every supernode,
    /// which cost more than it gained here (measured on the 92 k dof wheel, 2 threads).
    fn apply_block(&self, mv: &[f64], w: &mut [f64]) {
        let n = self.m.nrows();
        w.copy_from_slice(mv);
        let cols = w.len() / n;
        let groups = rayon::current_num_threads().clamp(1, cols.max(1));
        let per_group = cols.div_ceil(groups);
        w.par_chunks_mut(n * per_group).for_each(|chunk| {
            let group_cols = chunk.len() / n;
            let mut mem = MemBuffer::new(
                self.symbolic
                    .solve_in_place_scratch::<f64>(group_cols, Par::Seq),
            );
            let rhs = MatMut::from_column_major_slice_mut(chunk, n, group_cols);
            let stack = MemStack::new(&mut mem);
            match self.kind {
                FactorKind::Llt => LltRef::<usize, f64>::new(self.symbolic, &self.l_values)
                    .solve_in_place_with_conj(faer::Conj::No, rhs, Par::Seq, stack),
                FactorKind::Ldlt => LdltRef::<usize, f64>::new(self.symbolic, &self.l_values)
                    .solve_in_place_with_conj(faer::Conj::No, rhs, Par::Seq, stack),
            }
        });
    }
}

/// Symbolic Cholesky structure of `K - s M`, shared by the shift-invert factorisation and the
/// Sturm count (same pattern for every shift). Two orderings are analysed side by side and the
/// one with the smaller factor kept: faer's AMD, and our nested dissection
/// ([`crate::modal::ordering`]), which wins on the wheel (86.9 M factor entries against 102.4 M
/// at 102 k dofs; METIS through CHOLMOD reaches 55 M) while AMD wins on small or slender models.
fn symbolic_pencil(a: &SparseColMat<usize, f64>) -> Result<SymbolicCholesky<usize>> {
    let analyse = |ordering: SymmetricOrdering<'_, usize>| {
        factorize_symbolic_cholesky(a.symbolic(), Side::Lower, ordering, Default::default())
            .map_err(|e| Error::Numerical(format!("symbolic Cholesky of K - s M failed: {e:?}")))
    };
    let (amd, dissection) = rayon::join(
        || analyse(SymmetricOrdering::Amd),
        || {
            let order = nested_dissection(a);
            let mut inverse = vec![0usize; order.len()];
            for (k, &i) in order.iter().enumerate() {
                inverse[i] = k;
            }
            analyse(SymmetricOrdering::Custom(PermRef::new_checked(
                &order,
                &inverse,
                order.len(),
            )))
        },
    );
    let (amd, dissection) = (amd?, dissection?);
    // Factor entries (supernodal storage): the memory and, closely, the work of the
    // factorisation and of every solve.
    Ok(if dissection.len_val() < amd.len_val() {
        dissection
    } else {
        amd
    })
}

/// Columns per pass of [`m_block`] over the matrix.
const MATVEC_TILE: usize = 8;

/// `out = A v` for a block of columns (column-major, `n` rows each; A symmetric, lower
/// triangle stored). Columns go in tiles of 8, tiles in parallel; a tile is interleaved
/// row-major so that one pass over A's entries updates 8 contiguous values (A is read once
/// per tile instead of once per column).
fn m_block(a: &SparseColMat<usize, f64>, v: &[f64], out: &mut [f64]) {
    let n = a.nrows();
    let col_ptr = a.symbolic().col_ptr();
    let row_idx = a.symbolic().row_idx();
    let val = a.val();
    const T: usize = MATVEC_TILE;
    out.par_chunks_mut(n * T)
        .zip(v.par_chunks(n * T))
        .for_each(|(o, x)| {
            let cols = x.len() / n;
            if cols < T {
                for (oc, xc) in o.chunks_mut(n).zip(x.chunks(n)) {
                    sym_lower_matvec(a, xc, oc);
                }
                return;
            }
            let mut xr = vec![0.0; n * T];
            for c in 0..T {
                for r in 0..n {
                    xr[r * T + c] = x[c * n + r];
                }
            }
            let mut yr = vec![0.0; n * T];
            for j in 0..n {
                let xj: [f64; T] = xr[j * T..(j + 1) * T].try_into().unwrap_or([0.0; T]);
                let mut acc = [0.0; T];
                for p in col_ptr[j]..col_ptr[j + 1] {
                    let i = row_idx[p];
                    let w = val[p];
                    let yi = &mut yr[i * T..(i + 1) * T];
                    for c in 0..T {
                        yi[c] += w * xj[c];
                    }
                    if i != j {
                        let xi = &xr[i * T..(i + 1) * T];
                        for c in 0..T {
                            acc[c] += w * xi[c];
                        }
                    }
                }
                for c in 0..T {
                    yr[j * T + c] += acc[c];
                }
            }
            for c in 0..T {
                for r in 0..n {
                    o[c * n + r] = yr[r * T + c];
                }
            }
        });
}

/// `C = Aᵀ B` (A: n x ka, B: n x kb, column-major slices), parallel dense product.
fn at_b(a: &[f64], b: &[f64], n: usize) -> Mat<f64> {
    let (ka, kb) = (a.len() / n, b.len() / n);
    let mut c = Mat::<f64>::zeros(ka, kb);
    matmul(
        c.as_mut(),
        Accum::Replace,
        MatRef::from_column_major_slice(a, n, ka).transpose(),
        MatRef::from_column_major_slice(b, n, kb),
        1.0,
        Par::rayon(0),
    );
    c
}

/// `B += alpha A C` (A: n x ka column-major, C: ka x kb, B: n x kb column-major).
fn add_a_c(b: &mut [f64], a: &[f64], c: MatRef<'_, f64>, alpha: f64, n: usize) {
    let (ka, kb) = (a.len() / n, b.len() / n);
    matmul(
        MatMut::from_column_major_slice_mut(b, n, kb),
        Accum::Add,
        MatRef::from_column_major_slice(a, n, ka),
        c,
        alpha,
        Par::rayon(0),
    );
}

/// Cholesky `G = Rᵀ R` of a small symmetric positive definite matrix (plain loops, `b <= 32`);
/// `None` when a pivot falls below `rel_floor` times the largest diagonal entry (the block's
/// columns are numerically dependent).
fn small_cholesky_upper(g: &Mat<f64>, rel_floor: f64) -> Option<Mat<f64>> {
    let b = g.nrows();
    let scale = (0..b).map(|i| g[(i, i)]).fold(0.0f64, f64::max);
    if scale.is_nan() || scale <= 0.0 || !scale.is_finite() {
        return None;
    }
    let mut r = Mat::<f64>::zeros(b, b);
    for j in 0..b {
        let mut d = g[(j, j)];
        for k in 0..j {
            d -= r[(k, j)] * r[(k, j)];
        }
        if d.is_nan() || d <= rel_floor * scale {
            return None;
        }
        let rjj = d.sqrt();
        r[(j, j)] = rjj;
        for i in j + 1..b {
            let mut s = 0.5 * (g[(j, i)] + g[(i, j)]);
            for k in 0..j {
                s -= r[(k, j)] * r[(k, i)];
            }
            r[(j, i)] = s / rjj;
        }
    }
    Some(r)
}

/// Inverse of a small upper triangular matrix.
fn upper_inverse(r: &Mat<f64>) -> Mat<f64> {
    let b = r.nrows();
    let mut x = Mat::<f64>::zeros(b, b);
    for j in 0..b {
        x[(j, j)] = 1.0 / r[(j, j)];
        for i in (0..j).rev() {
            let mut s = 0.0;
            for k in i + 1..=j {
                s += r[(i, k)] * x[(k, j)];
            }
            x[(i, j)] = -s / r[(i, i)];
        }
    }
    x
}

/// M-orthonormalises the block `w` (already M-orthogonal to the basis) in place by Cholesky QR,
/// twice ("CholQR2": the second pass restores orthogonality to rounding). Returns `R` with
/// `w_in = w_out R`, or `None` when the block is numerically rank deficient.
fn m_cholqr2(w: &mut [f64], mw: &mut [f64], n: usize) -> Option<Mat<f64>> {
    let b = w.len() / n;
    let mut r_total = Mat::<f64>::identity(b, b);
    for pass in 0..2 {
        let g = at_b(w, mw, n);
        // First pass: columns whose M-norm dropped below 1e-10 of the largest are dependent.
        let r = small_cholesky_upper(&g, if pass == 0 { 1e-20 } else { 1e-30 })?;
        let rinv = upper_inverse(&r);
        // W R⁻¹ and (M W) R⁻¹ = M (W R⁻¹): the M product follows the columns without a sparse
        // product (exact up to rounding of the same order as the update of W itself).
        for v in [&mut *w, &mut *mw] {
            let mut out = vec![0.0; v.len()];
            add_a_c(&mut out, v, rinv.as_ref(), 1.0, n);
            v.copy_from_slice(&out);
        }
        let mut next = Mat::<f64>::zeros(b, b);
        matmul(
            next.as_mut(),
            Accum::Replace,
            r.as_ref(),
            r_total.as_ref(),
            1.0,
            Par::Seq,
        );
        r_total = next;
    }
    Some(r_total)
}

/// Completes one block Lanczos step: `w` (already M-orthogonalised against `q`, with
/// coefficients `c`: `Op V = Q c + w`) is replaced by an M-orthonormal block `V_next`, orthogonal
/// to `q`, with `Op V = Q c' + V_next B`; `c` is updated to `c'` and `B` returned.
///
/// Near convergence the residual block is ill-conditioned: some of its directions have
/// converged (tiny norm), others not. Cholesky QR alone would square its condition number and
/// amplify what rounding left along `Q`. So: SVQB (Stathopoulos & Wu 2002: scale the columns,
/// eigen-decompose the Gram matrix, `W V Λ^{-1/2}`), with numerically null directions (singular
/// value below 1e-13 of `scale`, the norm of `Op V`) replaced by random vectors (their rows of
/// `B` are zero: the Krylov space is invariant there), then a second Gram-Schmidt against `q`
/// and Cholesky QR, whose corrections enter `c` and `B`.
#[allow(clippy::too_many_arguments)]
fn next_block(
    m: &SparseColMat<usize, f64>,
    q: &[f64],
    mq: &[f64],
    w: &mut [f64],
    mw: &mut [f64],
    c: &mut Mat<f64>,
    scale: f64,
    n: usize,
    seed: u64,
) -> Result<Mat<f64>> {
    let b = w.len() / n;
    m_block(m, w, mw);
    let g = at_b(w, mw, n);
    let null_col = (1e-13 * scale).powi(2);
    let d: Vec<f64> = (0..b)
        .map(|i| {
            if g[(i, i)] > null_col {
                1.0 / g[(i, i)].sqrt()
            } else {
                0.0
            }
        })
        .collect();
    let gs = Mat::<f64>::from_fn(b, b, |i, j| d[i] * 0.5 * (g[(i, j)] + g[(j, i)]) * d[j]);
    let evd = gs
        .self_adjoint_eigen(Side::Lower)
        .map_err(|e| Error::Numerical(format!("block Gram matrix eigen solve failed: {e:?}")))?;
    let lam = evd.S().column_vector();
    let v = evd.U();
    let lam_max = (0..b).map(|i| lam[i]).fold(0.0f64, f64::max);
    // Transform T (W_new = W T) and B1 (W = W_new B1 on the kept directions).
    let mut t = Mat::<f64>::zeros(b, b);
    let mut b1 = Mat::<f64>::zeros(b, b);
    let mut null = Vec::new();
    for i in 0..b {
        // Directions with a singular value below 1e-10 of the block's largest are replaced
        // (their residual is below what the convergence test resolves; the Sturm count and the
        // final residuals check the result).
        if lam[i] > 1e-20 * lam_max && lam_max > 0.0 {
            let s = lam[i].sqrt();
            for r in 0..b {
                t[(r, i)] = d[r] * v[(r, i)] / s;
                // B1 = Λ^{1/2} Vᵀ D^{-1}
                if d[r] > 0.0 {
                    b1[(i, r)] = s * v[(r, i)] / d[r];
                }
            }
        } else {
            null.push(i);
        }
    }
    let mut w1 = vec![0.0; w.len()];
    add_a_c(&mut w1, w, t.as_ref(), 1.0, n);
    for &i in &null {
        let r = random_vector(n, seed.wrapping_mul(31).wrapping_add(i as u64));
        w1[i * n..(i + 1) * n].copy_from_slice(&r);
    }
    let mut mw1 = vec![0.0; w.len()];
    // Second round against Q, needed when SVQB amplified what rounding left along Q: by the
    // block's condition number kappa (orthogonality loss ~ eps kappa). Skipped below kappa =
    // 1e4 (loss <= 1e-12) with no replaced direction: it is two more sweeps over the basis.
    let lam_min_kept = (0..b)
        .filter(|i| !null.contains(i))
        .map(|i| lam[i])
        .fold(f64::INFINITY, f64::min);
    let d_max = d.iter().cloned().fold(0.0f64, f64::max);
    let d_min = d.iter().cloned().fold(f64::INFINITY, f64::min);
    let kappa = (lam_max / lam_min_kept).sqrt() * d_max / d_min;
    let c3 = if null.is_empty() && kappa.is_finite() && kappa < 1e4 {
        // M W1 = (M W) T: well conditioned (kappa < 1e4), the update loses no more than the
        // orthogonality bound above.
        add_a_c(&mut mw1, mw, t.as_ref(), 1.0, n);
        Mat::<f64>::zeros(q.len() / n, b)
    } else {
        let c3 = m_orthogonalise(q, mq, &mut w1, n);
        m_block(m, &w1, &mut mw1);
        c3
    };
    let r2 = m_cholqr2(&mut w1, &mut mw1, n).ok_or_else(|| {
        Error::Numerical(
            "block Lanczos: the Krylov basis cannot be extended (basis spans the space)".into(),
        )
    })?;
    // Op V = Q c + W1 B1 = Q (c + c3 B1) + V_next (R2 B1).
    matmul(
        c.as_mut(),
        Accum::Add,
        c3.as_ref(),
        b1.as_ref(),
        1.0,
        Par::Seq,
    );
    let mut beta = Mat::<f64>::zeros(b, b);
    matmul(
        beta.as_mut(),
        Accum::Replace,
        r2.as_ref(),
        b1.as_ref(),
        1.0,
        Par::Seq,
    );
    w.copy_from_slice(&w1);
    mw.copy_from_slice(&mw1);
    Ok(beta)
}

/// Two passes of block classical Gram-Schmidt of `w` against the M-orthonormal basis `q`
/// (column-major, `n` rows) in the M inner product, with `mq = M q` kept beside the basis so
/// that a pass is two dense products and no sparse one; returns the summed coefficients
/// `Qᵀ M w`.
fn m_orthogonalise(q: &[f64], mq: &[f64], w: &mut [f64], n: usize) -> Mat<f64> {
    let (k, b) = (q.len() / n, w.len() / n);
    let mut total = Mat::<f64>::zeros(k, b);
    if k == 0 {
        return total;
    }
    for _ in 0..2 {
        let c = at_b(mq, w, n);
        add_a_c(w, q, c.as_ref(), -1.0, n);
        total += &c;
    }
    total
}

/// Gram-Schmidt of a Lanczos residual block `w = Op V` against `q`: first against the last
/// `recent` columns of `q` (in exact arithmetic `Op V` has components only along the current
/// and the previous block: the three-term block recurrence, and they are large), then one pass
/// against all of `q`, which removes what rounding left along the older columns. After the
/// large components are gone that pass loses little norm, so one pass reaches working
/// precision where [`m_orthogonalise`] needs two full ones ("twice is enough", Parlett,
/// The Symmetric Eigenvalue Problem, section 6.9). Returns the summed coefficients `Qᵀ M w`.
fn m_orthogonalise_lanczos(
    q: &[f64],
    mq: &[f64],
    w: &mut [f64],
    n: usize,
    recent: usize,
) -> Mat<f64> {
    let (k, b) = (q.len() / n, w.len() / n);
    let first = k.saturating_sub(recent);
    let local = at_b(&mq[first * n..], w, n);
    add_a_c(w, &q[first * n..], local.as_ref(), -1.0, n);
    let mut total = at_b(mq, w, n);
    add_a_c(w, q, total.as_ref(), -1.0, n);
    for j in 0..b {
        for i in first..k {
            total[(i, j)] += local[(i - first, j)];
        }
    }
    total
}

/// `A = K - sigma M` (lower triangles of both; same or different patterns).
fn shifted(
    k: &SparseColMat<usize, f64>,
    m: &SparseColMat<usize, f64>,
    sigma: f64,
) -> Result<SparseColMat<usize, f64>> {
    let n = k.nrows();
    let mut t = Vec::with_capacity(k.val().len() + m.val().len());
    for (a, s) in [(k, 1.0), (m, -sigma)] {
        let cp = a.symbolic().col_ptr();
        let ri = a.symbolic().row_idx();
        let v = a.val();
        for j in 0..n {
            for p in cp[j]..cp[j + 1] {
                t.push(faer::sparse::Triplet::new(ri[p], j, s * v[p]));
            }
        }
    }
    SparseColMat::try_new_from_triplets(n, n, &t)
        .map_err(|e| Error::Numerical(format!("shifted matrix: {e:?}")))
}

/// Number of eigenvalues of `K x = lambda M x` below `lambda_max` (K, M: lower triangles):
/// the negative pivots of the LDLᵀ of `K - lambda_max M` (Sylvester's law of inertia: `L D Lᵀ`
/// is congruent to `K - lambda_max M`, whose negative eigenvalues are the eigenvalues of the
/// pencil below `lambda_max` because M is positive definite). faer's supernodal LDLᵀ (AMD
/// ordering, no pivoting, no regularisation): a zero pivot (lambda_max on an eigenvalue) is an
/// error that names the remedy.
pub fn sturm_count(
    k: &SparseColMat<usize, f64>,
    m: &SparseColMat<usize, f64>,
    lambda_max: f64,
) -> Result<usize> {
    let a = shifted(k, m, lambda_max)?;
    let symbolic = symbolic_pencil(&a)?;
    sturm_count_with(&a, &symbolic)
}

/// Which numeric factorisation of a pencil matrix.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum FactorKind {
    /// `L Lᵀ` (positive definite: the shift below the spectrum).
    Llt,
    /// `L D Lᵀ`, no pivoting (indefinite: the Sturm count at the band edge).
    Ldlt,
}

/// Numeric factor values of `a` on its symbolic structure; the faer error as text on failure.
fn numeric_factor(
    a: &SparseColMat<usize, f64>,
    symbolic: &SymbolicCholesky<usize>,
    kind: FactorKind,
) -> std::result::Result<Vec<f64>, String> {
    let mut l_values = vec![0.0f64; symbolic.len_val()];
    let par = Par::rayon(0);
    match kind {
        FactorKind::Llt => {
            let mut mem = MemBuffer::new(
                symbolic.factorize_numeric_llt_scratch::<f64>(par, Default::default()),
            );
            symbolic
                .factorize_numeric_llt(
                    &mut l_values,
                    a.as_ref(),
                    Side::Lower,
                    Default::default(),
                    par,
                    MemStack::new(&mut mem),
                    Default::default(),
                )
                .map(|_| ())
                .map_err(|e| format!("{e:?}"))?;
        }
        FactorKind::Ldlt => {
            let mut mem = MemBuffer::new(
                symbolic.factorize_numeric_ldlt_scratch::<f64>(par, Default::default()),
            );
            symbolic
                .factorize_numeric_ldlt(
                    &mut l_values,
                    a.as_ref(),
                    Side::Lower,
                    Default::default(),
                    par,
                    MemStack::new(&mut mem),
                    Default::default(),
                )
                .map(|_| ())
                .map_err(|e| format!("{e:?}"))?;
        }
    }
    Ok(l_values)
}

/// [`sturm_count`] for `a = K - lambda_max M` with its symbolic structure already analysed.
fn sturm_count_with(
    a: &SparseColMat<usize, f64>,
    symbolic: &SymbolicCholesky<usize>,
) -> Result<usize> {
    let l_values = numeric_factor(a, symbolic, FactorKind::Ldlt).map_err(|e| {
        Error::Numerical(format!(
            "LDLᵀ of K - w_max² M for the Sturm count failed ({e}): the band edge lies on an \
             eigenvalue; move --fmax-hz slightly"
        ))
    })?;
    // D is the diagonal of the unit lower factor's storage: the diagonal entry of each column
    // (simplicial) or of each supernode's dense block (supernodal).
    let mut negative = 0;
    match symbolic.raw() {
        SymbolicCholeskyRaw::Simplicial(s) => {
            let cp = s.col_ptr();
            let ri = s.row_idx();
            for j in 0..s.ncols() {
                for p in cp[j]..cp[j + 1] {
                    if ri[p] == j && l_values[p] < 0.0 {
                        negative += 1;
                    }
                }
            }
        }
        SymbolicCholeskyRaw::Supernodal(s) => {
            let begin = s.supernode_begin();
            let end = s.supernode_end();
            let val_ptr = s.col_ptr_for_val();
            for sn in 0..s.n_supernodes() {
                let cols = end[sn] - begin[sn];
                let rows = (val_ptr[sn + 1] - val_ptr[sn]) / cols.max(1);
                for c in 0..cols {
                    if l_values[val_ptr[sn] + c * rows + c] < 0.0 {
                        negative += 1;
                    }
                }
            }
        }
    }
    Ok(negative)
}

/// One slice of the band and the shift that serves it: the modes with `lambda_lo < w² <=
/// lambda_hi` from Lanczos on `Op = (K - sigma M)⁻¹ M`, whose eigenvalues are
/// `theta = 1 / (w² - sigma)`. The slice is `theta >= theta_hi = 1 / (lambda_hi - sigma)`, and,
/// for a shift inside the band (`lambda_lo < sigma`), also `theta <= theta_lo = 1 / (lambda_lo -
/// sigma) < 0`: Lanczos converges from both ends of the operator's spectrum at once.
#[derive(Clone, Copy, Debug)]
struct Slice {
    sigma: f64,
    lambda_lo: f64,
    lambda_hi: f64,
}

impl Slice {
    fn theta_hi(&self) -> f64 {
        1.0 / (self.lambda_hi - self.sigma)
    }
    fn theta_lo(&self) -> f64 {
        // The first slice has no lower edge (and its shift lies below the spectrum): no
        // negative side.
        if self.lambda_lo.is_finite() && self.lambda_lo < self.sigma {
            1.0 / (self.lambda_lo - self.sigma)
        } else {
            f64::NEG_INFINITY
        }
    }
    /// `theta` inside the slice, with a relative margin `rel` (> 0 widens it).
    fn contains_theta(&self, theta: f64, rel: f64) -> bool {
        theta >= self.theta_hi() * (1.0 - rel) || theta <= self.theta_lo() * (1.0 - rel)
    }
}

/// Lanczos iterations and purification over one slice (see [`solve`]).
struct SliceResult {
    modes: Vec<Mode>,
    basis: usize,
    blocks: usize,
}

/// All modes with `f <= fmax_hz` of `K x = w² M x` (K, M: lower triangles, symmetric, M positive
/// definite, K positive semi-definite), by block shift-invert Lanczos (module docs), over
/// `opts.slices` slices of the band.
pub fn solve(
    k: &SparseColMat<usize, f64>,
    m: &SparseColMat<usize, f64>,
    opts: &ModalOptions,
) -> Result<ModalSolution> {
    let started = Instant::now();
    let n = k.nrows();
    if !(opts.fmax_hz.is_finite() && opts.fmax_hz > 0.0) {
        return Err(Error::input(
            "command line",
            "fmax-hz",
            format!("{} must be a finite frequency > 0 Hz", opts.fmax_hz),
        ));
    }
    check_slices(opts.slices)?;
    if n == 0 {
        return Err(Error::Numerical(
            "the model has no free degree of freedom (everything is clamped)".into(),
        ));
    }
    let shift_hz = opts.shift_hz.unwrap_or((opts.fmax_hz / 20.0).max(10.0));
    let sigma = -(2.0 * PI * shift_hz).powi(2);
    let lambda_max = (2.0 * PI * opts.fmax_hz).powi(2);
    let trace = std::env::var_os("SQUEAL_MODAL_TRACE").is_some();
    if n < DENSE_BELOW_DOFS {
        return solve_dense(k, m, opts, sigma, lambda_max, started);
    }

    let a = shifted(k, m, sigma)?;
    // One symbolic analysis for every shift and Sturm count: `K - s M` has the same pattern.
    let symbolic = symbolic_pencil(&a)?;
    if trace {
        eprintln!(
            "trace: symbolic at {:.2} s, factor entries {}",
            started.elapsed().as_secs_f64(),
            symbolic.len_val()
        );
    }
    // Slice edges equally spaced in frequency: a wheel's mode count grows about linearly with
    // frequency (plate-like: 73 modes below 5 kHz, 161 below 10 kHz on the 16 mm wheel), so
    // equal widths hold about equal numbers of modes.
    let slices = opts.slices;
    let edges: Vec<f64> = (0..=slices)
        .map(|i| (2.0 * PI * opts.fmax_hz * i as f64 / slices as f64).powi(2))
        .collect();
    // Sturm counts first (the same symbolic analysis; each LDLᵀ is freed before the next
    // factor is made): with the number of modes in each slice known, each iteration stops on the
    // block where the last of them converges. Several slices need the counts to partition the
    // band, so they are taken whatever `sturm_check` says.
    let counts: Option<Vec<usize>> = if opts.sturm_check || slices > 1 {
        let mut c = vec![0usize];
        for &edge in &edges[1..] {
            c.push(sturm_count_with(&shifted(k, m, edge)?, &symbolic)?);
        }
        if trace {
            eprintln!(
                "trace: sturm counts {c:?} at {:.2} s",
                started.elapsed().as_secs_f64()
            );
        }
        if c[slices] == 0 {
            return Err(Error::Numerical(format!(
                "no mode below {} Hz (Sturm count 0): raise --fmax-hz",
                opts.fmax_hz
            )));
        }
        Some(c)
    } else {
        None
    };
    let mut factor_seconds = 0.0;
    let mut modes: Vec<Mode> = Vec::new();
    let (mut basis_size, mut blocks) = (0, 0);
    let mut shifts = Vec::with_capacity(slices);
    for s in 0..slices {
        let count = counts.as_ref().map(|c| c[s + 1] - c[s]);
        if count == Some(0) {
            continue;
        }
        // The first slice takes the shift below the spectrum (positive definite, L Lᵀ); the
        // others one in their middle (indefinite, L D Lᵀ: its inertia is not needed, the edge
        // counts are taken above).
        let slice = if s == 0 {
            Slice {
                sigma,
                lambda_lo: f64::NEG_INFINITY,
                lambda_hi: edges[1],
            }
        } else {
            Slice {
                sigma: 0.5 * (edges[s] + edges[s + 1]),
                lambda_lo: edges[s],
                lambda_hi: edges[s + 1],
            }
        };
        let t0 = Instant::now();
        let a_slice = if s == 0 {
            None
        } else {
            Some(shifted(k, m, slice.sigma)?)
        };
        let kind = if s == 0 {
            FactorKind::Llt
        } else {
            FactorKind::Ldlt
        };
        let l_values =
            numeric_factor(a_slice.as_ref().unwrap_or(&a), &symbolic, kind).map_err(|e| {
                if s == 0 {
                    Error::Numerical(format!(
                        "Cholesky of K - sigma M (sigma = {sigma:.6e}) failed ({e}): K is not \
                         positive semi-definite or M not positive definite (inverted elements? \
                         negative density?)"
                    ))
                } else {
                    Error::Numerical(format!(
                        "LDLᵀ of K - sigma M at the shift of slice {} ({:.1} Hz) failed ({e}): \
                         the shift lies on an eigenvalue; change --slices",
                        s + 1,
                        slice.sigma.sqrt() / (2.0 * PI)
                    ))
                }
            })?;
        drop(a_slice);
        factor_seconds += t0.elapsed().as_secs_f64();
        let op = ShiftInvert {
            m,
            symbolic: &symbolic,
            l_values,
            kind,
        };
        let res = solve_slice(
            k,
            m,
            &op,
            &slice,
            count,
            opts,
            s,
            lambda_max.max(sigma.abs()),
        )?;
        if trace {
            eprintln!(
                "trace: slice {} ({:.1}..{:.1} Hz, shift {:.3e}): {} modes, basis {}, at {:.2} s",
                s + 1,
                edges[s].sqrt() / (2.0 * PI),
                edges[s + 1].sqrt() / (2.0 * PI),
                slice.sigma,
                res.modes.len(),
                res.basis,
                started.elapsed().as_secs_f64()
            );
        }
        if let Some(count) = count {
            if count != res.modes.len() {
                return Err(Error::Numerical(format!(
                    "the Sturm counts find {count} eigenvalues in {:.1}..{:.1} Hz but Lanczos \
                     returned {} modes (basis {}, {} blocks of {}): raise the basis limit or \
                     split the band (--slices)",
                    edges[s].sqrt() / (2.0 * PI),
                    edges[s + 1].sqrt() / (2.0 * PI),
                    res.modes.len(),
                    res.basis,
                    res.blocks,
                    opts.block_size
                )));
            }
        }
        shifts.push(slice.sigma);
        basis_size = basis_size.max(res.basis);
        blocks += res.blocks;
        modes.extend(res.modes);
    }
    drop(a);
    modes.sort_by(|a, b| a.eigenvalue.total_cmp(&b.eigenvalue));
    if let Some(bad) = modes
        .iter()
        .find(|m| m.residual.is_nan() || m.residual >= opts.residual_tolerance)
    {
        return Err(Error::Numerical(format!(
            "mode at {:.3} Hz has relative residual {:.2e} above the tolerance {:.0e}; \
             the mesh may be badly conditioned (check element quality) or the band too wide",
            bad.frequency_hz, bad.residual, opts.residual_tolerance
        )));
    }
    if trace {
        for md in &modes {
            eprintln!(
                "trace: {:.4} Hz residual {:.2e}",
                md.frequency_hz, md.residual
            );
        }
        eprintln!(
            "trace: done at {:.2} s (largest basis {basis_size}, {blocks} blocks)",
            started.elapsed().as_secs_f64()
        );
    }
    Ok(ModalSolution {
        modes,
        shift: sigma,
        shifts,
        basis_size,
        block_size: opts.block_size.clamp(1, n),
        blocks,
        factor_seconds,
        solve_seconds: started.elapsed().as_secs_f64(),
        sturm_count: counts.map(|c| c[slices]),
    })
}

/// Most slices of a band (each is a factorisation and a Sturm count).
pub const MAX_SLICES: usize = 32;

/// The number of slices is in `1..=MAX_SLICES` (checked by [`solve`]; the command line checks it
/// before any work).
pub fn check_slices(slices: usize) -> Result<()> {
    if !(1..=MAX_SLICES).contains(&slices) {
        return Err(Error::input(
            "command line",
            "--slices",
            format!("{slices} is outside the allowed range 1..={MAX_SLICES}"),
        ));
    }
    Ok(())
}

/// Block Lanczos on `op` until the modes of `slice` have converged (`count` of them when the
/// Sturm counts are known), then purification, Rayleigh quotients and residuals. `rigid_scale`
/// is the band's stiffness scale for the residual of rigid modes.
#[allow(clippy::too_many_arguments)]
fn solve_slice(
    k: &SparseColMat<usize, f64>,
    m: &SparseColMat<usize, f64>,
    op: &ShiftInvert<'_>,
    slice: &Slice,
    count: Option<usize>,
    opts: &ModalOptions,
    slice_index: usize,
    rigid_scale: f64,
) -> Result<SliceResult> {
    let started = Instant::now();
    let n = k.nrows();
    let trace = std::env::var_os("SQUEAL_MODAL_TRACE").is_some();
    let in_band = |theta: f64| slice.contains_theta(theta, 0.0);
    // Block size: larger than any eigenvalue multiplicity expected (6 rigid modes at w² = 0,
    // pairs for bodies of revolution), and a multi-column solve reads the factor once per
    // block.
    let b = opts.block_size.clamp(1, n);
    // Whole blocks only.
    let max_basis = (opts.max_basis.min(n) / b).max(1) * b;
    // Relative Ritz residual ||Op x - theta x||_M / |theta| for "converged": 1e-10 gives final
    // residuals below 1.5e-10 after purification on the 102 k dof wheel at 10 kHz (1e-9 gave
    // 9.3e-10, too close to the 1e-8 bound; 1e-11 cost one more block in ten), measured
    // 2026-11-23.
    let ritz_tol = 1e-10;

    // Basis Q (M-orthonormal, column-major n x k), columns of H = Qᵀ M Op Q (upper part: the
    // coefficients of column c against columns 0..=end of its block).
    let mut q: Vec<f64> = Vec::new();
    let mut mq: Vec<f64> = Vec::new();
    let mut h_cols: Vec<Vec<f64>> = Vec::new();
    let (mut block, mut block_m) = start_block(m, &q, &mq, n, b, 1 + 97 * slice_index as u64)?;
    // Null-direction scale: ||Op v||_M <= 1 / |sigma| for M-normalised v below the spectrum
    // (K semi-definite); inside it ||Op|| is larger, so this threshold only gets stricter.
    let scale = 1.0 / slice.sigma.abs().max(1e-300);
    let mut blocks = 0;
    let mut next_check = 2;
    let mut phase_s = [0.0f64; 4]; // solve, orthogonalise, next block, Ritz
    let dim = loop {
        let j0 = q.len() / n;
        q.extend_from_slice(&block);
        mq.extend_from_slice(&block_m);
        let k_dim = j0 + b;
        blocks += 1;
        let mut w = vec![0.0; n * b];
        let t0 = Instant::now();
        op.apply_block(&block_m, &mut w);
        let t1 = Instant::now();
        let mut c = m_orthogonalise_lanczos(&q, &mq, &mut w, n, 2 * b);
        let t2 = Instant::now();
        // With the basis spanning the whole space the residual block is zero.
        let beta = if k_dim >= n {
            Mat::<f64>::zeros(b, b)
        } else {
            next_block(
                m,
                &q,
                &mq,
                &mut w,
                &mut block_m,
                &mut c,
                scale,
                n,
                blocks as u64 + 7 + 1000 * slice_index as u64,
            )?
        };
        phase_s[0] += (t1 - t0).as_secs_f64();
        phase_s[1] += (t2 - t1).as_secs_f64();
        phase_s[2] += t2.elapsed().as_secs_f64();
        for col in 0..b {
            h_cols.push((0..k_dim).map(|i| c[(i, col)]).collect());
        }
        let next_block = w;
        let exhausted = k_dim + b > max_basis;
        if blocks >= next_check || exhausted {
            let t3 = Instant::now();
            let (theta, u) = ritz(&h_cols, k_dim)?;
            phase_s[3] += t3.elapsed().as_secs_f64();
            // est_i = ||B u_i(last block)||: the M-norm of Op x_i - theta_i x_i.
            let est: Vec<f64> = (0..k_dim)
                .map(|i| {
                    (0..b)
                        .map(|r| {
                            (0..b)
                                .map(|cc| beta[(r, cc)] * u[(j0 + cc, i)])
                                .sum::<f64>()
                                .powi(2)
                        })
                        .sum::<f64>()
                        .sqrt()
                })
                .collect();
            let conv = |i: usize| est[i] <= ritz_tol * theta[i].abs();
            let all_in_band = (0..k_dim).filter(|&i| in_band(theta[i])).all(conv);
            // A converged Ritz value past the band edge: the band's Ritz values have passed
            // theirs (interlacing); only used without a Sturm count (a single slice below the
            // spectrum, where all theta are positive).
            let beyond = (0..k_dim).any(|i| !in_band(theta[i]) && theta[i] > 0.0 && conv(i));
            let n_band = (0..k_dim).filter(|&i| in_band(theta[i])).count();
            let n_conv = (0..k_dim).filter(|&i| in_band(theta[i]) && conv(i)).count();
            if trace {
                eprintln!(
                    "trace: {:.2} s basis {k_dim}: {n_conv}/{n_band} in band converged",
                    started.elapsed().as_secs_f64()
                );
            }
            let done = match count {
                // Exactly the counted modes in the band, all converged.
                Some(count) => all_in_band && n_band == count,
                // No count: a converged Ritz value past the band edge means the band's have
                // passed theirs (interlacing).
                None => all_in_band && beyond,
            };
            if done {
                break k_dim;
            }
            if exhausted || k_dim >= n {
                // No room for another block: accept a converged band (the Sturm count checks
                // that it is complete).
                if all_in_band {
                    break k_dim;
                }
                return Err(Error::Numerical(format!(
                    "block Lanczos did not converge for all modes in {:.1}..{:.1} Hz within {} \
                     basis vectors; lower --fmax-hz, coarsen the mesh or split the band \
                     (--slices)",
                    slice.lambda_lo.max(0.0).sqrt() / (2.0 * PI),
                    slice.lambda_hi.sqrt() / (2.0 * PI),
                    max_basis
                )));
            }
            // Check again after ~15 % more basis (the dense eigen solve of H costs k³, 0.2 s
            // in all for a 592-vector basis), or on every block once three quarters of the
            // counted modes have converged.
            let closing = count.is_some_and(|count| 4 * n_conv >= 3 * count);
            next_check = if closing {
                blocks + 1
            } else {
                blocks + 1.max(blocks * 3 / 20)
            };
        }
        block = next_block;
    };

    if trace {
        eprintln!(
            "trace: phases (s): solve {:.2}, orthogonalise {:.2}, next block {:.2}, Ritz {:.2}",
            phase_s[0], phase_s[1], phase_s[2], phase_s[3]
        );
    }
    // Ritz pairs of the final H.
    let (theta, u) = ritz(&h_cols, dim)?;
    // Ritz vectors in the band, purified by one more application of Op (damps what rounding
    // left along unwanted modes), Rayleigh quotients, residuals.
    let wanted: Vec<usize> = (0..dim)
        .filter(|&i| slice.contains_theta(theta[i], 1e-9))
        .collect();
    let n_wanted = wanted.len();
    let u_wanted = Mat::<f64>::from_fn(dim, n_wanted, |r, c| u[(r, wanted[c])]);
    let mut x = vec![0.0; n * n_wanted];
    add_a_c(&mut x, &q[..n * dim], u_wanted.as_ref(), 1.0, n);
    drop(q);
    drop(mq);
    let mut y = vec![0.0; n * n_wanted];
    if n_wanted > 0 {
        let mut mx = vec![0.0; x.len()];
        m_block(m, &x, &mut mx);
        op.apply_block(&mx, &mut y);
    }
    drop(x);
    let mut ky = vec![0.0; y.len()];
    let mut my = vec![0.0; y.len()];
    m_block(k, &y, &mut ky);
    m_block(m, &y, &mut my);
    let modes: Vec<Mode> = (0..n_wanted)
        .into_par_iter()
        .map(|c| {
            let (yc, kyc, myc) = (
                &y[c * n..(c + 1) * n],
                &ky[c * n..(c + 1) * n],
                &my[c * n..(c + 1) * n],
            );
            let ymy: f64 = yc.iter().zip(myc).map(|(a, b)| a * b).sum();
            let yky: f64 = yc.iter().zip(kyc).map(|(a, b)| a * b).sum();
            let nrm = ymy.max(0.0).sqrt();
            let lambda = yky / ymy;
            let r: f64 = kyc
                .iter()
                .zip(myc)
                .map(|(a, b)| (a - lambda * b).powi(2))
                .sum::<f64>()
                .sqrt();
            let ky_norm = kyc.iter().map(|a| a * a).sum::<f64>().sqrt();
            let my_norm = myc.iter().map(|a| a * a).sum::<f64>().sqrt();
            let freq = lambda.signum() * lambda.abs().sqrt() / (2.0 * PI);
            let rigid = freq.abs() < opts.rigid_below_hz;
            // ||K x|| for flexible modes. For rigid modes ||K x|| is itself round-off, so the
            // scale is the band's stiffness, max(w_max², |sigma|) ||M x||: a backward error of
            // the size the band's modes are held to.
            let denom = if rigid {
                ky_norm.max(rigid_scale * my_norm)
            } else {
                ky_norm
            };
            Mode {
                frequency_hz: freq,
                eigenvalue: lambda,
                residual: r / denom,
                rigid,
                vector: yc.iter().map(|v| v / nrm).collect(),
            }
        })
        .filter(|mode| mode.eigenvalue > slice.lambda_lo && mode.eigenvalue <= slice.lambda_hi)
        .collect();
    Ok(SliceResult {
        modes,
        basis: dim,
        blocks,
    })
}

/// Below this many dofs the band is taken from a dense solve (a Krylov basis of whole blocks
/// would span most of the space anyway).
const DENSE_BELOW_DOFS: usize = 200;

/// Dense reference path for small models: `L⁻¹ K L⁻ᵀ z = w² z` with `M = L Lᵀ`.
fn solve_dense(
    k: &SparseColMat<usize, f64>,
    m: &SparseColMat<usize, f64>,
    opts: &ModalOptions,
    sigma: f64,
    lambda_max: f64,
    started: Instant,
) -> Result<ModalSolution> {
    let n = k.nrows();
    let dense = |s: &SparseColMat<usize, f64>| {
        let mut d = Mat::<f64>::zeros(n, n);
        let cp = s.symbolic().col_ptr();
        let ri = s.symbolic().row_idx();
        for j in 0..n {
            for p in cp[j]..cp[j + 1] {
                d[(ri[p], j)] = s.val()[p];
                d[(j, ri[p])] = s.val()[p];
            }
        }
        d
    };
    let (kd, md) = (dense(k), dense(m));
    let l = md
        .llt(Side::Lower)
        .map_err(|e| Error::Numerical(format!("M is not positive definite ({e:?})")))?
        .L()
        .to_owned();
    // L⁻¹ by forward substitution (n < 200).
    let mut linv = Mat::<f64>::identity(n, n);
    faer::linalg::triangular_solve::solve_lower_triangular_in_place(
        l.as_ref(),
        linv.as_mut(),
        Par::Seq,
    );
    let c = &linv * &kd * linv.transpose();
    let cs = Mat::<f64>::from_fn(n, n, |i, j| 0.5 * (c[(i, j)] + c[(j, i)]));
    let (eigenvalues, vectors) = symmetric_eigen_qr(&cs)?;
    let z = linv.transpose() * &vectors;
    let rigid_scale = lambda_max.max(sigma.abs());
    let mut modes = Vec::new();
    for i in 0..n {
        let lambda = eigenvalues[i];
        if lambda > lambda_max {
            break;
        }
        let x: Vec<f64> = (0..n).map(|r| z[(r, i)]).collect();
        let mut kx = vec![0.0; n];
        let mut mx = vec![0.0; n];
        sym_lower_matvec(k, &x, &mut kx);
        sym_lower_matvec(m, &x, &mut mx);
        let r = kx
            .iter()
            .zip(&mx)
            .map(|(a, b)| (a - lambda * b).powi(2))
            .sum::<f64>()
            .sqrt();
        let kn = kx.iter().map(|a| a * a).sum::<f64>().sqrt();
        let mn = mx.iter().map(|a| a * a).sum::<f64>().sqrt();
        let freq = lambda.signum() * lambda.abs().sqrt() / (2.0 * PI);
        let rigid = freq.abs() < opts.rigid_below_hz;
        let denom = if rigid { kn.max(rigid_scale * mn) } else { kn };
        modes.push(Mode {
            frequency_hz: freq,
            eigenvalue: lambda,
            residual: r / denom,
            rigid,
            vector: x,
        });
    }
    let count = modes.len();
    Ok(ModalSolution {
        modes,
        shift: sigma,
        shifts: vec![sigma],
        basis_size: n,
        block_size: 0,
        blocks: 0,
        factor_seconds: 0.0,
        solve_seconds: started.elapsed().as_secs_f64(),
        sturm_count: opts.sturm_check.then_some(count),
    })
}

/// A random block (seeded) M-orthogonal to `q` and M-orthonormal.
fn start_block(
    m: &SparseColMat<usize, f64>,
    q: &[f64],
    mq: &[f64],
    n: usize,
    b: usize,
    seed: u64,
) -> Result<(Vec<f64>, Vec<f64>)> {
    for attempt in 0..4 {
        let mut w = random_vector(n * b, seed * 16 + attempt);
        m_orthogonalise(q, mq, &mut w, n);
        let mut mw = vec![0.0; w.len()];
        m_block(m, &w, &mut mw);
        if m_cholqr2(&mut w, &mut mw, n).is_some() {
            return Ok((w, mw));
        }
    }
    Err(Error::Numerical(
        "could not extend the Krylov basis: the basis spans the whole space".into(),
    ))
}

/// Ritz values (ascending) and vectors of the projected matrix `H` (`dim` x `dim`, from the
/// upper parts of its columns).
fn ritz(h_cols: &[Vec<f64>], dim: usize) -> Result<(Vec<f64>, Mat<f64>)> {
    let hm = Mat::<f64>::from_fn(
        dim,
        dim,
        |i, j| {
            if i <= j {
                h_cols[j][i]
            } else {
                h_cols[i][j]
            }
        },
    );
    symmetric_eigen_qr(&hm)
}

/// Eigenvalues (ascending) and eigenvectors of a dense symmetric matrix by Householder
/// tridiagonalisation and the implicit QR algorithm (faer's `self_adjoint_evd` with the
/// divide-and-conquer stage switched off). Why: on the wheel's projected matrices (eigenvalues
/// spanning 400x, near-degenerate pairs) faer's default divide and conquer returned eigenvectors
/// with `|H u - theta u|` near 1e-9 ||H||, far from the 1e-16 ||H|| of a backward-stable
/// solver: the 10 kHz band of the 40 mm wheel failed its residual bound through it (residuals
/// up to 1.5e-6; with this routine all 149 modes are below 7e-11), and the noisy estimates
/// delayed convergence (basis 864 instead of 440). Measured 2026-11-23.
fn symmetric_eigen_qr(a: &Mat<f64>) -> Result<(Vec<f64>, Mat<f64>)> {
    use faer::dyn_stack::{MemBuffer, MemStack};
    use faer::linalg::evd::{self_adjoint_evd, self_adjoint_evd_scratch, ComputeEigenvectors};
    let n = a.nrows();
    let mut params: faer::linalg::evd::SelfAdjointEvdParams = faer::Auto::<f64>::auto();
    params.recursion_threshold = usize::MAX;
    let par = Par::rayon(0);
    let mut s = faer::diag::Diag::<f64>::zeros(n);
    let mut u = Mat::<f64>::zeros(n, n);
    let mut mem = MemBuffer::new(self_adjoint_evd_scratch::<f64>(
        n,
        ComputeEigenvectors::Yes,
        par,
        params.into(),
    ));
    self_adjoint_evd(
        a.as_ref(),
        s.as_mut(),
        Some(u.as_mut()),
        par,
        MemStack::new(&mut mem),
        params.into(),
    )
    .map_err(|e| Error::Numerical(format!("projected eigen problem failed: {e:?}")))?;
    let sv = s.column_vector();
    Ok(((0..n).map(|i| sv[i]).collect(), u))
}
