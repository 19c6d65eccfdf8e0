//! Spectrum slicing: the band cut into slices, one shift per slice (`L D Lᵀ` inside the band),
//! and the block Lanczos of one slice, which returns exactly the slice's Sturm count.

use super::block::{abs_block, m_block, m_orthogonalise_lanczos, next_block, start_block};
use super::dense::ritz;
use super::memory::resident_note;
use super::residual::floor_from_products;
use super::solution::{ModalOptions, Mode};
use crate::linalg::factor::ShiftInvert;
use crate::linalg::workspace::Workspace;
use crate::{Error, Result};
use faer::linalg::matmul::matmul;
use faer::sparse::SparseColMat;
use faer::{Accum, Mat, MatRef, Par};
use rayon::prelude::*;
use std::f64::consts::PI;
use std::time::Instant;

/// One slice of the band and the shift that serves it: the modes with `lambda_lo < w² <=
/// lambda_hi` from Lanczos on `Op = (K - sigma M)⁻¹ M`, whose eigenvalues are
/// `theta = 1 / (w² - sigma)`. The slice is `theta >= theta_hi = 1 / (lambda_hi - sigma)`, and,
/// for a shift inside the band (`lambda_lo < sigma`), also `theta <= theta_lo = 1 / (lambda_lo -
/// sigma) < 0`: Lanczos converges from both ends of the operator's spectrum at once.
#[derive(Clone, Copy, Debug)]
pub(super) struct Slice {
    pub(super) sigma: f64,
    pub(super) lambda_lo: f64,
    pub(super) lambda_hi: f64,
}

impl Slice {
    pub(super) fn theta_hi(&self) -> f64 {
        1.0 / (self.lambda_hi - self.sigma)
    }
    pub(super) fn theta_lo(&self) -> f64 {
        // The first slice has no lower edge (and its shift lies below the spectrum): no
        // negative side.
        if self.lambda_lo.is_finite() && self.lambda_lo < self.sigma {
            1.0 / (self.lambda_lo - self.sigma)
        } else {
            f64::NEG_INFINITY
        }
    }
    /// `theta` inside the slice, with a relative margin `rel` (> 0 widens it).
    pub(super) fn contains_theta(&self, theta: f64, rel: f64) -> bool {
        theta >= self.theta_hi() * (1.0 - rel) || theta <= self.theta_lo() * (1.0 - rel)
    }
}

/// Lanczos iterations and purification over one slice (see [`solve`]).
pub(super) struct SliceResult {
    pub(super) modes: Vec<Mode>,
    pub(super) basis: usize,
    pub(super) blocks: usize,
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
///
/// Kept in one piece: the Lanczos loop of one slice, whose state (basis, projected matrix,
/// convergence bookkeeping) lives across iterations; the algebra it calls is in block.rs and
/// dense.rs.
#[allow(clippy::too_many_arguments)]
pub(super) fn solve_slice(
    k: &SparseColMat<usize, f64>,
    m: &SparseColMat<usize, f64>,
    op: ShiftInvert<'_>,
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
    // M Q of the last two blocks only (the local pass of the Lanczos orthogonalisation): the
    // full pass forms Qᵀ (M w) instead, so the basis is stored once. The current block's is
    // `block_m`, the previous one's `m_prev` (moved, not copied, from block to block).
    let mut m_prev: Option<Vec<f64>> = None;
    let mut h_cols: Vec<Vec<f64>> = Vec::new();
    // B of every block (`Op V_j = Q c_j + V_(j+1) B_j`): with the columns of H they give
    // `Op Q` from the basis, which purifies the Ritz vectors without another solve.
    let mut betas: Vec<Mat<f64>> = Vec::new();
    // The step's n x b buffers, reused from block to block (see `workspace`).
    let mut ws = Workspace::new();
    let (mut block, mut block_m) = start_block(m, &q, n, b, 1 + 97 * slice_index as u64, &mut ws)?;
    // Null-direction scale: ||Op v||_M <= 1 / |sigma| for M-normalised v below the spectrum
    // (K semi-definite); inside it ||Op|| is larger, so this threshold only gets stricter.
    let scale = 1.0 / slice.sigma.abs().max(1e-300);
    let mut blocks = 0;
    let mut next_check = 2;
    let mut phase_s = [0.0f64; 4]; // solve, orthogonalise, next block, Ritz
    let (dim, last_block) = loop {
        let j0 = q.len() / n;
        q.extend_from_slice(&block);
        // The block is in the basis now: its storage serves this step's products (one n x b
        // buffer less at the step's peak).
        ws.give(std::mem::take(&mut block));
        let k_dim = j0 + b;
        blocks += 1;
        // Overwritten by the solve.
        let mut w = ws.take(n * b);
        let t0 = Instant::now();
        op.apply_block(&block_m, &mut w, &mut ws);
        let t1 = Instant::now();
        let recent: Vec<&[f64]> = m_prev
            .iter()
            .map(|p| p.as_slice())
            .chain([block_m.as_slice()])
            .collect();
        let mut c = m_orthogonalise_lanczos(&q, &recent, m, &mut w, n, &mut ws);
        let t2 = Instant::now();
        // With the basis spanning the whole space the residual block is zero.
        let beta = if k_dim >= n {
            Mat::<f64>::zeros(b, b)
        } else {
            // The current block's M product becomes the previous one's; the next block's is
            // written into a buffer from the workspace.
            let current_m = std::mem::replace(&mut block_m, ws.take(n * b));
            if let Some(older) = m_prev.replace(current_m) {
                ws.give(older);
            }
            next_block(
                m,
                &q,
                &mut w,
                &mut block_m,
                &mut c,
                scale,
                n,
                blocks as u64 + 7 + 1000 * slice_index as u64,
                &mut ws,
            )?
        };
        phase_s[0] += (t1 - t0).as_secs_f64();
        phase_s[1] += (t2 - t1).as_secs_f64();
        phase_s[2] += t2.elapsed().as_secs_f64();
        for col in 0..b {
            h_cols.push((0..k_dim).map(|i| c[(i, col)]).collect());
        }
        betas.push(beta.clone());
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
                    "trace: {:.2} s basis {k_dim}: {n_conv}/{n_band} in band converged{}",
                    started.elapsed().as_secs_f64(),
                    resident_note()
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
                break (k_dim, next_block);
            }
            if exhausted || k_dim >= n {
                // No room for another block: accept a converged band (the Sturm count checks
                // that it is complete).
                if all_in_band {
                    break (k_dim, next_block);
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
    // Released before the vectors are formed: the post-loop work has its own.
    ws = Workspace::new();

    if trace {
        eprintln!(
            "trace: phases (s): solve {:.2}, orthogonalise {:.2}, next block {:.2}, Ritz {:.2}{}",
            phase_s[0],
            phase_s[1],
            phase_s[2],
            phase_s[3],
            resident_note()
        );
    }
    // Ritz pairs of the final H.
    let (theta, u) = ritz(&h_cols, dim)?;
    // Ritz vectors in the band, purified by one more application of Op (damps what rounding
    // left along unwanted modes: the start block's high-frequency content survives in the
    // basis, and K would amplify it in the residual), Rayleigh quotients, residuals.
    let wanted: Vec<usize> = (0..dim)
        .filter(|&i| slice.contains_theta(theta[i], 1e-9))
        .collect();
    let n_wanted = wanted.len();
    drop((m_prev, block_m));
    // Peak memory is the factor and the basis: the vectors are formed in the basis's own
    // storage, after the factor's last use.
    let y = if opts.purify_by_solve {
        // y = Op (Q u), by a solve of M x.
        drop(last_block);
        let u_wanted = Mat::<f64>::from_fn(dim, n_wanted, |r, c| u[(r, wanted[c])]);
        let x = ritz_vectors_in_place(q, dim, u_wanted.as_ref(), n);
        let mut mx = vec![0.0; x.len()];
        m_block(m, &x, &mut mx, &mut ws);
        drop(x);
        let mut y = vec![0.0; n * n_wanted];
        if n_wanted > 0 {
            op.apply_block(&mx, &mut y, &mut ws);
        }
        drop(op);
        y
    } else {
        // y = Op (Q u) = [Q V_next] (H~ u), no solve: the Lanczos relation holds column by
        // column for the vectors the solves returned, `Op Q = [Q V_next] H~`, with H~ the
        // coefficients actually subtracted (block upper Hessenberg: the columns of H, then B_j
        // below block j). The combination is that of the solves' outputs, so the basis's
        // high-frequency content (the random start block's, which K amplifies in a residual)
        // cancels in it as it does there; what is left is rounding of the solve's own size.
        drop(op);
        let z = purifying_coefficients(&h_cols, &betas, &u, &wanted, b);
        q.reserve_exact(n * b);
        q.extend_from_slice(&last_block);
        drop(last_block);
        ritz_vectors_in_place(q, dim + b, z.as_ref(), n)
    };
    let mut ky = vec![0.0; y.len()];
    let mut my = vec![0.0; y.len()];
    m_block(k, &y, &mut ky, &mut ws);
    m_block(m, &y, &mut my, &mut ws);
    // Per mode: Rayleigh quotient, residual, ||K y||, ||M y||, ||y||_M.
    let stats: Vec<[f64; 5]> = (0..n_wanted)
        .into_par_iter()
        .map(|c| {
            let (yc, kyc, myc) = (
                &y[c * n..(c + 1) * n],
                &ky[c * n..(c + 1) * n],
                &my[c * n..(c + 1) * n],
            );
            let ymy: f64 = yc.iter().zip(myc).map(|(a, b)| a * b).sum();
            let yky: f64 = yc.iter().zip(kyc).map(|(a, b)| a * b).sum();
            let lambda = yky / ymy;
            let r: f64 = kyc
                .iter()
                .zip(myc)
                .map(|(a, b)| (a - lambda * b).powi(2))
                .sum::<f64>()
                .sqrt();
            let ky_norm = kyc.iter().map(|a| a * a).sum::<f64>().sqrt();
            let my_norm = myc.iter().map(|a| a * a).sum::<f64>().sqrt();
            [lambda, r, ky_norm, my_norm, ymy.max(0.0).sqrt()]
        })
        .collect();
    // The rounding floors' |K| |y| and |M| |y|, in the buffers of K y and M y.
    abs_block(k, &y, &mut ky, &mut ws);
    abs_block(m, &y, &mut my, &mut ws);
    let modes: Vec<Mode> = (0..n_wanted)
        .into_par_iter()
        .map(|c| {
            let [lambda, r, ky_norm, my_norm, nrm] = stats[c];
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
            let columns = c * n..(c + 1) * n;
            Mode {
                frequency_hz: freq,
                eigenvalue: lambda,
                residual: r / denom,
                residual_floor: floor_from_products(
                    &ky[columns.clone()],
                    &my[columns.clone()],
                    lambda,
                    denom,
                ),
                rigid,
                vector: y[columns].iter().map(|v| v / nrm).collect(),
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

/// `Z = H~ U` for the wanted Ritz vectors (columns `wanted` of `u`): `H~` is the `(dim + b) x
/// dim` block upper Hessenberg matrix of the Lanczos relation `Op Q = [Q V_next] H~`, column
/// `j` holding `h_cols[j]` (rows up to the end of its block) and, in the rows of the next
/// block, column `j mod b` of `B` of its block (`betas`).
fn purifying_coefficients(
    h_cols: &[Vec<f64>],
    betas: &[Mat<f64>],
    u: &Mat<f64>,
    wanted: &[usize],
    b: usize,
) -> Mat<f64> {
    let dim = h_cols.len();
    let mut z = Mat::<f64>::zeros(dim + b, wanted.len());
    for (c, &w) in wanted.iter().enumerate() {
        for (j, col) in h_cols.iter().enumerate() {
            let ujc = u[(j, w)];
            for (i, h) in col.iter().enumerate() {
                z[(i, c)] += h * ujc;
            }
            let (block, local) = (j / b, j % b);
            for r in 0..b {
                z[((block + 1) * b + r, c)] += betas[block][(r, local)] * ujc;
            }
        }
    }
    z
}

/// `X = Q U` (Q: the basis, `dim` columns of `n` rows, column-major; U: `dim` x `k`) written
/// over the first `k` columns of Q's storage, which is then shrunk to them: no second buffer
/// the size of X beside the basis. Row blocks are independent (block `r` of X reads only block
/// `r` of Q), so each is formed in a small buffer and copied back before the next is read.
fn ritz_vectors_in_place(mut q: Vec<f64>, dim: usize, u: MatRef<'_, f64>, n: usize) -> Vec<f64> {
    const ROWS: usize = 4096;
    let k = u.ncols();
    let mut block = Mat::<f64>::zeros(ROWS.min(n), k);
    let mut r0 = 0;
    while r0 < n {
        let rows = ROWS.min(n - r0);
        matmul(
            block.as_mut().subrows_mut(0, rows),
            Accum::Replace,
            MatRef::from_column_major_slice(&q[..n * dim], n, dim).subrows(r0, rows),
            u,
            1.0,
            Par::rayon(0),
        );
        for c in 0..k {
            for r in 0..rows {
                q[c * n + r0 + r] = block[(r, c)];
            }
        }
        r0 += rows;
    }
    q.truncate(n * k);
    q.shrink_to_fit();
    q
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random::XorShift64;

    #[test]
    fn ritz_vectors_in_place_match_a_plain_product() {
        // n spans several row blocks (4096 rows each) and ends in a partial one; the plain
        // triple loop is the reference. Same products in another order: 1e-12 relative.
        let (n, dim, k) = (9000, 12, 5);
        let mut rng = XorShift64::seeded(7);
        let q: Vec<f64> = (0..n * dim).map(|_| rng.centred_uniform()).collect();
        let u = Mat::<f64>::from_fn(dim, k, |_, _| rng.centred_uniform());
        let x = ritz_vectors_in_place(q.clone(), dim, u.as_ref(), n);
        assert_eq!(x.len(), n * k);
        for c in 0..k {
            for r in 0..n {
                let plain: f64 = (0..dim).map(|j| q[j * n + r] * u[(j, c)]).sum();
                assert!(
                    (x[c * n + r] - plain).abs() <= 1e-12 * (1.0 + plain.abs()),
                    "row {r}, column {c}: {} against {plain}",
                    x[c * n + r]
                );
            }
        }
    }
}
