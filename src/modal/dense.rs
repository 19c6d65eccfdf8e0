//! Dense eigen solves: small models solved whole (`K` and `M` dense, Cholesky of `M`,
//! symmetric QR), and the Ritz values and vectors of the projected Lanczos matrix.

use super::residual::rounding_floor;
use super::solution::{ModalOptions, ModalSolution, Mode};
use crate::fem::assembly::sym_lower_matvec;
use crate::{Error, Result};
use faer::sparse::SparseColMat;
use faer::{Mat, Par, Side};
use std::f64::consts::PI;
use std::time::Instant;

/// Below this many dofs the band is taken from a dense solve (a Krylov basis of whole blocks
/// would span most of the space anyway).
pub(super) const DENSE_BELOW_DOFS: usize = 200;

/// Dense reference path for small models: `L⁻¹ K L⁻ᵀ z = w² z` with `M = L Lᵀ`.
pub(super) fn solve_dense(
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
            residual_floor: rounding_floor(k, m, &x, lambda, denom),
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

/// Ritz values (ascending) and vectors of the projected matrix `H` (`dim` x `dim`, from the
/// upper parts of its columns).
pub(super) fn ritz(h_cols: &[Vec<f64>], dim: usize) -> Result<(Vec<f64>, Mat<f64>)> {
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
pub(super) fn symmetric_eigen_qr(a: &Mat<f64>) -> Result<(Vec<f64>, Mat<f64>)> {
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
