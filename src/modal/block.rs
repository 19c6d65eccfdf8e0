//! Block linear algebra in the M inner product for the block Lanczos: the M product of a
//! block, small dense products, M-orthonormalisation (Cholesky QR twice, SVQB), the next
//! Krylov block with its coupling, and the random start block.

use super::residual::abs_sym_lower_matvec;
use crate::fem::assembly::sym_lower_matvec;
use crate::linalg::workspace::Workspace;
use crate::random::XorShift64;
use crate::{Error, Result};
use faer::linalg::matmul::matmul;
use faer::sparse::SparseColMat;
use faer::{Accum, Mat, MatMut, MatRef, Par, Side};
use rayon::prelude::*;

/// Deterministic pseudo-random start vector (xorshift), so runs are reproducible; both
/// Lanczos solvers (3D and axisymmetric) start from it.
pub(crate) fn random_vector(n: usize, seed: u64) -> Vec<f64> {
    let mut rng = XorShift64::seeded(seed);
    (0..n).map(|_| rng.centred_uniform()).collect()
}

/// Columns per pass of [`m_block`] over the matrix.
pub(super) const MATVEC_TILE: usize = 8;

/// `out = A v` for a block of columns (column-major, `n` rows each; A symmetric, lower
/// triangle stored). Columns go in tiles of 8, tiles in parallel; a tile is interleaved
/// row-major so that one pass over A's entries updates 8 contiguous values (A is read once
/// per tile instead of once per column). The tiles' row-major copies come from `ws`.
pub(super) fn m_block(
    a: &SparseColMat<usize, f64>,
    v: &[f64],
    out: &mut [f64],
    ws: &mut Workspace,
) {
    tiled_matvec::<false>(a, v, out, ws);
}

/// `out = |A| |v|` for a block of columns, tiled as [`m_block`]: the products of a rounding
/// floor ([`crate::modal::residual`]) for all modes at once, with A read once per tile of
/// columns instead of once per mode.
pub(super) fn abs_block(
    a: &SparseColMat<usize, f64>,
    v: &[f64],
    out: &mut [f64],
    ws: &mut Workspace,
) {
    tiled_matvec::<true>(a, v, out, ws);
}

/// [`m_block`] (`ABS = false`) or [`abs_block`] (`ABS = true`). Tiles go in groups of one per
/// thread, so that only that many tiles' copies are held at once (a block of 163 modes has 21
/// tiles); each tile's result depends on its columns only, so the grouping does not change it.
fn tiled_matvec<const ABS: bool>(
    a: &SparseColMat<usize, f64>,
    v: &[f64],
    out: &mut [f64],
    ws: &mut Workspace,
) {
    let n = a.nrows();
    if n == 0 {
        return;
    }
    const T: usize = MATVEC_TILE;
    let group = rayon::current_num_threads().max(1);
    let mut copies: Vec<(Vec<f64>, Vec<f64>)> = (0..group.min(v.len().div_ceil(n * T)))
        .map(|_| (ws.take(n * T), ws.take(n * T)))
        .collect();
    for (o, x) in out.chunks_mut(n * T * group).zip(v.chunks(n * T * group)) {
        o.par_chunks_mut(n * T)
            .zip(x.par_chunks(n * T))
            .zip(copies.par_iter_mut())
            .for_each(|((o, x), (xr, yr))| tile_matvec::<ABS>(a, x, o, xr, yr));
    }
    for (xr, yr) in copies {
        ws.give(xr);
        ws.give(yr);
    }
}

/// One tile of [`tiled_matvec`]: `o = A x` (or `|A| |x|`) for up to [`MATVEC_TILE`] columns,
/// through the row-major copies `xr`, `yr` (`n x MATVEC_TILE`, contents on entry unused).
fn tile_matvec<const ABS: bool>(
    a: &SparseColMat<usize, f64>,
    x: &[f64],
    o: &mut [f64],
    xr: &mut [f64],
    yr: &mut [f64],
) {
    let n = a.nrows();
    let col_ptr = a.symbolic().col_ptr();
    let row_idx = a.symbolic().row_idx();
    let val = a.val();
    const T: usize = MATVEC_TILE;
    let cols = x.len() / n;
    if cols < T {
        for (oc, xc) in o.chunks_mut(n).zip(x.chunks(n)) {
            if ABS {
                abs_sym_lower_matvec(a, xc, oc);
            } else {
                sym_lower_matvec(a, xc, oc);
            }
        }
        return;
    }
    for c in 0..T {
        for r in 0..n {
            xr[r * T + c] = if ABS {
                x[c * n + r].abs()
            } else {
                x[c * n + r]
            };
        }
    }
    yr.fill(0.0);
    for j in 0..n {
        let xj: [f64; T] = xr[j * T..(j + 1) * T].try_into().unwrap_or([0.0; T]);
        let mut acc = [0.0; T];
        for p in col_ptr[j]..col_ptr[j + 1] {
            let i = row_idx[p];
            let w = if ABS { val[p].abs() } else { val[p] };
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
}

/// `C = Aᵀ B` (A: n x ka, B: n x kb, column-major slices), parallel dense product.
pub(super) fn at_b(a: &[f64], b: &[f64], n: usize) -> Mat<f64> {
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

/// `B = alpha A C` (A: n x ka column-major, C: ka x kb, B: n x kb column-major), B not read:
/// for freshly allocated B. Accumulating into new zeroed memory would read each page first (the
/// shared zero page) and then write it: a copy-on-write fault with a TLB shootdown to the other
/// cores per page, 10-15 % of a 294 k dof solve (measured 2026-11-26 with perf).
pub(super) fn a_c(b: &mut [f64], a: &[f64], c: MatRef<'_, f64>, alpha: f64, n: usize) {
    product_a_c(b, a, c, alpha, n, Accum::Replace);
}

/// `B += alpha A C` (A: n x ka column-major, C: ka x kb, B: n x kb column-major).
pub(super) fn add_a_c(b: &mut [f64], a: &[f64], c: MatRef<'_, f64>, alpha: f64, n: usize) {
    product_a_c(b, a, c, alpha, n, Accum::Add);
}

fn product_a_c(b: &mut [f64], a: &[f64], c: MatRef<'_, f64>, alpha: f64, n: usize, accum: Accum) {
    let (ka, kb) = (a.len() / n, b.len() / n);
    matmul(
        MatMut::from_column_major_slice_mut(b, n, kb),
        accum,
        MatRef::from_column_major_slice(a, n, ka),
        c,
        alpha,
        Par::rayon(0),
    );
}

/// Cholesky `G = Rᵀ R` of a small symmetric positive definite matrix (plain loops, `b <= 32`);
/// `None` when a pivot falls below `rel_floor` times the largest diagonal entry (the block's
/// columns are numerically dependent).
pub(super) fn small_cholesky_upper(g: &Mat<f64>, rel_floor: f64) -> Option<Mat<f64>> {
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
pub(super) fn upper_inverse(r: &Mat<f64>) -> Mat<f64> {
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
pub(super) fn m_cholqr2(
    w: &mut Vec<f64>,
    mw: &mut Vec<f64>,
    n: usize,
    ws: &mut Workspace,
) -> Option<Mat<f64>> {
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
            let mut out = ws.take(v.len());
            a_c(&mut out, v, rinv.as_ref(), 1.0, n);
            // The product replaces the block; the old storage goes back to the workspace.
            std::mem::swap(v, &mut out);
            ws.give(out);
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
pub(super) fn next_block(
    m: &SparseColMat<usize, f64>,
    q: &[f64],
    w: &mut Vec<f64>,
    mw: &mut Vec<f64>,
    c: &mut Mat<f64>,
    scale: f64,
    n: usize,
    seed: u64,
    ws: &mut Workspace,
) -> Result<Mat<f64>> {
    let b = w.len() / n;
    m_block(m, w, mw, ws);
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
    let mut w1 = ws.take(w.len());
    a_c(&mut w1, w, t.as_ref(), 1.0, n);
    // The residual block is read no more: its storage serves the products below (one n x b
    // buffer less at the step's peak; `w` takes V_next at the end).
    ws.give(std::mem::take(w));
    for &i in &null {
        let r = random_vector(n, seed.wrapping_mul(31).wrapping_add(i as u64));
        w1[i * n..(i + 1) * n].copy_from_slice(&r);
    }
    let mut mw1 = ws.take(w1.len());
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
        a_c(&mut mw1, mw, t.as_ref(), 1.0, n);
        ws.give(std::mem::take(mw));
        Mat::<f64>::zeros(q.len() / n, b)
    } else {
        ws.give(std::mem::take(mw));
        let c3 = m_orthogonalise(q, m, &mut w1, n, ws);
        m_block(m, &w1, &mut mw1, ws);
        c3
    };
    let r2 = m_cholqr2(&mut w1, &mut mw1, n, ws).ok_or_else(|| {
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
    // The new block takes the residual's place (whose storage went back to the workspace).
    *w = w1;
    *mw = mw1;
    Ok(beta)
}

/// Two passes of block classical Gram-Schmidt of `w` against the M-orthonormal basis `q`
/// (column-major, `n` rows) in the M inner product: each pass forms `M w` (one sparse product
/// of the block) and the coefficients `Qᵀ (M w)`, so no `M Q` is kept beside the basis (it
/// would double the basis's memory); returns the summed coefficients `Qᵀ M w`.
pub(super) fn m_orthogonalise(
    q: &[f64],
    m: &SparseColMat<usize, f64>,
    w: &mut [f64],
    n: usize,
    ws: &mut Workspace,
) -> Mat<f64> {
    let (k, b) = (q.len() / n, w.len() / n);
    let mut total = Mat::<f64>::zeros(k, b);
    if k == 0 {
        return total;
    }
    let mut mw = ws.take(w.len());
    for _ in 0..2 {
        m_block(m, w, &mut mw, ws);
        let c = at_b(q, &mw, n);
        add_a_c(w, q, c.as_ref(), -1.0, n);
        total += &c;
    }
    ws.give(mw);
    total
}

/// Gram-Schmidt of a Lanczos residual block `w = Op V` against `q`: first against the last
/// blocks of `q` (in exact arithmetic `Op V` has components only along the current and the
/// previous block: the three-term block recurrence, and they are large), using their `M Q`
/// (`mq_recent`: one slice per block, oldest first, kept for these blocks only; all their
/// coefficients are formed before any is subtracted), then one pass against all of `q` with
/// the coefficients `Qᵀ (M w)` (one sparse product of the block), which removes what rounding
/// left along the older columns. After the large components are gone that pass loses little
/// norm, so one pass reaches working precision where [`m_orthogonalise`] needs two full ones
/// ("twice is enough", Parlett, The Symmetric Eigenvalue Problem, section 6.9). Returns the
/// summed coefficients `Qᵀ M w`.
pub(super) fn m_orthogonalise_lanczos(
    q: &[f64],
    mq_recent: &[&[f64]],
    m: &SparseColMat<usize, f64>,
    w: &mut [f64],
    n: usize,
    ws: &mut Workspace,
) -> Mat<f64> {
    let (k, b) = (q.len() / n, w.len() / n);
    let recent: usize = mq_recent.iter().map(|mq| mq.len() / n).sum();
    let first = k - recent;
    let locals: Vec<Mat<f64>> = mq_recent.iter().map(|mq| at_b(mq, w, n)).collect();
    let mut col = first;
    for local in &locals {
        let cols = local.nrows();
        add_a_c(w, &q[col * n..(col + cols) * n], local.as_ref(), -1.0, n);
        col += cols;
    }
    let mut mw = ws.take(w.len());
    m_block(m, w, &mut mw, ws);
    let mut total = at_b(q, &mw, n);
    ws.give(mw);
    add_a_c(w, q, total.as_ref(), -1.0, n);
    let mut col = first;
    for local in &locals {
        for j in 0..b {
            for i in 0..local.nrows() {
                total[(col + i, j)] += local[(i, j)];
            }
        }
        col += local.nrows();
    }
    total
}

/// A random block (seeded) M-orthogonal to `q` and M-orthonormal.
pub(super) fn start_block(
    m: &SparseColMat<usize, f64>,
    q: &[f64],
    n: usize,
    b: usize,
    seed: u64,
    ws: &mut Workspace,
) -> Result<(Vec<f64>, Vec<f64>)> {
    for attempt in 0..4 {
        let mut w = random_vector(n * b, seed * 16 + attempt);
        m_orthogonalise(q, m, &mut w, n, ws);
        let mut mw = vec![0.0; w.len()];
        m_block(m, &w, &mut mw, ws);
        if m_cholqr2(&mut w, &mut mw, n, ws).is_some() {
            return Ok((w, mw));
        }
    }
    Err(Error::Numerical(
        "could not extend the Krylov basis: the basis spans the whole space".into(),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tiled_products_match_the_column_by_column_ones() {
        // A random symmetric lower triangle with signed values; blocks of 1, 8 (one tile), 11,
        // 19 and 40 columns (whole tiles and a remainder). The column-by-column products
        // (fem::assembly and modal::residual) are the references; the same terms summed in
        // another order: 1e-13 relative to the sum of magnitudes.
        let n = 150;
        let mut rng = crate::random::XorShift64::seeded(5);
        let mut t = Vec::new();
        for j in 0..n {
            t.push(faer::sparse::Triplet::new(j, j, rng.centred_uniform()));
            for i in j + 1..n {
                if rng.centred_uniform().abs() < 0.1 {
                    t.push(faer::sparse::Triplet::new(i, j, rng.centred_uniform()));
                }
            }
        }
        let a = SparseColMat::try_new_from_triplets(n, n, &t).expect("valid triplets");
        // One workspace for all products, its buffers poisoned with NaN first: a tile that
        // used a stale copy without overwriting or zeroing it would show.
        let mut ws = Workspace::new();
        for _ in 0..8 {
            ws.give(vec![f64::NAN; n * MATVEC_TILE]);
        }
        // 1, 2 and 3 threads: tiles go in groups of one per thread.
        for (threads, cols) in [(2, 1), (2, 8), (1, 11), (2, 19), (3, 19), (3, 40)] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .expect("thread pool");
            let v = random_vector(n * cols, 3 + cols as u64);
            let (mut tiled, mut tiled_abs) = (vec![0.0; n * cols], vec![0.0; n * cols]);
            pool.install(|| {
                m_block(&a, &v, &mut tiled, &mut ws);
                abs_block(&a, &v, &mut tiled_abs, &mut ws);
            });
            for c in 0..cols {
                let (mut plain, mut plain_abs) = (vec![0.0; n], vec![0.0; n]);
                sym_lower_matvec(&a, &v[c * n..(c + 1) * n], &mut plain);
                abs_sym_lower_matvec(&a, &v[c * n..(c + 1) * n], &mut plain_abs);
                for r in 0..n {
                    let scale = plain_abs[r].max(1e-300);
                    assert!(
                        (tiled[c * n + r] - plain[r]).abs() <= 1e-13 * scale,
                        "{cols} columns, A v at ({r}, {c}): {} against {}",
                        tiled[c * n + r],
                        plain[r]
                    );
                    assert!(
                        (tiled_abs[c * n + r] - plain_abs[r]).abs() <= 1e-13 * scale,
                        "{cols} columns, |A| |v| at ({r}, {c}): {} against {}",
                        tiled_abs[c * n + r],
                        plain_abs[r]
                    );
                }
            }
        }
    }
}
