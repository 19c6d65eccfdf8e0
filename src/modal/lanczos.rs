//! Shift-invert Lanczos for `K x = w² M x` (see the module docs of [`crate::modal`]).

use std::f64::consts::PI;
use std::time::Instant;

use faer::linalg::solvers::Solve;
use faer::sparse::linalg::solvers::{Llt, SymbolicLlt};
use faer::sparse::SparseColMat;
use faer::{Mat, Side};
use rayon::prelude::*;
use serde::Serialize;

use crate::fem::assembly::sym_lower_matvec;
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
    /// Check completeness with a Sturm count: the negative pivots of the LDLᵀ of
    /// `K - w_max² M` (Sylvester's law of inertia, M positive definite) are the eigenvalues
    /// below `fmax`, which must equal the modes found. A second (simplicial) factorisation.
    pub sturm_check: bool,
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
            sturm_check: true,
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
    /// Shift `sigma` (rad²/s²).
    pub shift: f64,
    /// Final Krylov basis size.
    pub basis_size: usize,
    /// Lanczos runs (1 + restarts).
    pub runs: usize,
    /// Factorisation time (s).
    pub factor_seconds: f64,
    /// Total solve time incl. factorisation (s).
    pub solve_seconds: f64,
    /// Eigenvalues below `fmax` by the Sturm count (None: not checked).
    pub sturm_count: Option<usize>,
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.par_iter().zip(b.par_iter()).map(|(x, y)| x * y).sum()
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
    llt: Llt<usize, f64>,
}

impl ShiftInvert<'_> {
    /// `y = (K - sigma M)⁻¹ M x`.
    fn apply(&self, x: &[f64]) -> Vec<f64> {
        let mut y = vec![0.0; x.len()];
        sym_lower_matvec(self.m, x, &mut y);
        let n = y.len();
        self.llt
            .solve_in_place(faer::MatMut::from_column_major_slice_mut(&mut y, n, 1));
        y
    }
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
/// the negative pivots of the LDLᵀ of `K - lambda_max M` (Sylvester's law of inertia), by the
/// AMD-ordered simplicial factorisation of the axisymmetric solver.
pub fn sturm_count(
    k: &SparseColMat<usize, f64>,
    m: &SparseColMat<usize, f64>,
    lambda_max: f64,
) -> Result<usize> {
    let n = k.nrows();
    // (row <= column) entries of the upper triangle, K and M values side by side.
    let mut t: Vec<(usize, usize, f64, f64)> = Vec::with_capacity(k.val().len() + m.val().len());
    for (a, is_k) in [(k, true), (m, false)] {
        let cp = a.symbolic().col_ptr();
        let ri = a.symbolic().row_idx();
        let v = a.val();
        for j in 0..n {
            for p in cp[j]..cp[j + 1] {
                let (kv, mv) = if is_k { (v[p], 0.0) } else { (0.0, v[p]) };
                // Stored lower (row >= column): the transposed pair is in the upper triangle.
                t.push((j, ri[p], kv, mv));
            }
        }
    }
    let pencil = crate::axisym::eigen::PencilMatrices::from_triplets(n, &t)?;
    Ok(pencil.factor(lambda_max)?.negative_pivots)
}

/// All modes with `f <= fmax_hz` of `K x = w² M x` (K, M: lower triangles, symmetric, M positive
/// definite, K positive semi-definite).
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
    let shift_hz = opts.shift_hz.unwrap_or((opts.fmax_hz / 20.0).max(10.0));
    let sigma = -(2.0 * PI * shift_hz).powi(2);
    let lambda_max = (2.0 * PI * opts.fmax_hz).powi(2);
    let theta_min = 1.0 / (lambda_max - sigma);

    let a = shifted(k, m, sigma)?;
    let symbolic = SymbolicLlt::try_new(a.symbolic(), Side::Lower)
        .map_err(|e| Error::Numerical(format!("symbolic Cholesky of K - sigma M failed: {e:?}")))?;
    let llt = Llt::try_new_with_symbolic(symbolic, a.as_ref(), Side::Lower).map_err(|e| {
        Error::Numerical(format!(
            "Cholesky of K - sigma M (sigma = {sigma:.6e}) failed ({e:?}): K is not positive \
             semi-definite or M not positive definite (inverted elements? negative density?)"
        ))
    })?;
    drop(a);
    let factor_seconds = started.elapsed().as_secs_f64();
    let op = ShiftInvert { m, llt };

    let m_norm = |v: &[f64]| -> f64 {
        let mut mv = vec![0.0; v.len()];
        sym_lower_matvec(m, v, &mut mv);
        dot(v, &mv).max(0.0).sqrt()
    };

    // Basis Q (M-orthonormal), MQ (M q_j, kept to make Gram-Schmidt one pass of dot products),
    // upper triangle of H = Qᵀ M Op Q.
    let mut q: Vec<Vec<f64>> = Vec::new();
    let mut mq: Vec<Vec<f64>> = Vec::new();
    let mut h: Vec<Vec<f64>> = Vec::new(); // h[j][i] = q_iᵀ M Op q_j, i <= j
                                           // Finished runs: (last index of the run, its residual vector beta q_next, kept
                                           // M-orthogonal to the growing basis so that its norm bounds what is still unexplained).
    let mut pending: Vec<(usize, Vec<f64>)> = Vec::new();
    let max_basis = opts.max_basis.min(n);
    // Relative Ritz residual estimate ||Op x - theta x||_M / theta for "converged": 1e-11 leaves
    // two orders of margin to the 1e-8 residual bound after purification (measured).
    let ritz_tol = 1e-11;
    let mut runs = 0;
    let mut previous_count = usize::MAX;
    let mut first_run_len = 0;

    // M-orthogonalise v against Q twice ("twice is enough"); returns the coefficients.
    let orthogonalise = |v: &mut Vec<f64>, q: &[Vec<f64>], mq: &[Vec<f64>]| -> Vec<f64> {
        let mut total = vec![0.0; q.len()];
        for _ in 0..2 {
            let c: Vec<f64> = mq.par_iter().map(|mqi| dot(mqi, v)).collect();
            for (t, ci) in total.iter_mut().zip(&c) {
                *t += ci;
            }
            v.par_iter_mut().enumerate().for_each(|(r, x)| {
                let mut s = 0.0;
                for (i, qi) in q.iter().enumerate() {
                    s += c[i] * qi[r];
                }
                *x -= s;
            });
        }
        total
    };

    let ritz = |h: &[Vec<f64>],
                run_ends: &[(usize, f64)],
                dim: usize|
     -> Result<(Vec<f64>, Mat<f64>, Vec<f64>)> {
        let hm = Mat::<f64>::from_fn(dim, dim, |i, j| if i <= j { h[j][i] } else { h[i][j] });
        let evd = hm
            .self_adjoint_eigen(Side::Upper)
            .map_err(|e| Error::Numerical(format!("projected eigen problem failed: {e:?}")))?;
        let s = evd.S().column_vector();
        let u = evd.U().to_owned();
        let theta: Vec<f64> = (0..dim).map(|i| s[i]).collect();
        let est: Vec<f64> = (0..dim)
            .map(|i| {
                run_ends
                    .iter()
                    .filter(|(end, _)| *end < dim)
                    .map(|&(end, beta)| (beta * u[(end, i)]).abs())
                    .sum::<f64>()
            })
            .collect();
        Ok((theta, u, est))
    };

    loop {
        if q.len() >= max_basis {
            break;
        }
        runs += 1;
        let run_start = q.len();
        let mut v = random_vector(n, runs as u64);
        orthogonalise(&mut v, &q, &mq);
        let norm = m_norm(&v);
        if norm < 1e-8 {
            break; // basis spans the space
        }
        v.iter_mut().for_each(|x| *x /= norm);
        let mut next_check = run_start + 20.max(first_run_len * 3 / 5);
        let converged_run;
        let last_count;
        loop {
            let j = q.len();
            let mut mv = vec![0.0; n];
            sym_lower_matvec(m, &v, &mut mv);
            for (_, r) in pending.iter_mut() {
                let c = dot(&mv, r);
                r.par_iter_mut()
                    .zip(v.par_iter())
                    .for_each(|(a, b)| *a -= c * b);
            }
            q.push(std::mem::take(&mut v));
            mq.push(mv);
            let mut z = op.apply(&q[j]);
            let c = orthogonalise(&mut z, &q, &mq);
            h.push(c);
            let beta = m_norm(&z);
            let exhausted = q.len() >= max_basis || beta <= 1e-13 * h[j][j].abs().max(1e-300);
            if q.len() >= next_check || exhausted {
                let dim = q.len();
                let mut ends: Vec<(usize, f64)> =
                    pending.iter().map(|(e, r)| (*e, m_norm(r))).collect();
                ends.push((dim - 1, beta));
                let (theta, _, est) = ritz(&h, &ends, dim)?;
                let conv = |i: usize| est[i] <= ritz_tol * theta[i].abs();
                let in_band: Vec<usize> = (0..dim).filter(|&i| theta[i] >= theta_min).collect();
                let all_conv = in_band.iter().all(|&i| conv(i));
                let beyond = (0..dim).any(|i| theta[i] < theta_min && theta[i] > 0.0 && conv(i));
                if (all_conv && beyond) || exhausted {
                    last_count = in_band.len();
                    converged_run = all_conv;
                    pending.push((dim - 1, z));
                    break;
                }
                next_check = dim + 10.max(dim / 5);
            }
            v = z.into_iter().map(|x| x / beta).collect();
        }
        if runs == 1 {
            first_run_len = q.len();
        }
        if !converged_run && q.len() >= max_basis {
            return Err(Error::Numerical(format!(
                "Lanczos did not converge for all modes below {} Hz within {} basis vectors; \
                 lower --fmax-hz or coarsen the mesh",
                opts.fmax_hz, max_basis
            )));
        }
        if last_count == previous_count || q.len() >= n {
            break;
        }
        previous_count = last_count;
    }

    // Ritz vectors in the band, purified, Rayleigh quotients, residuals.
    let dim = q.len();
    let (theta, u, _) = ritz(&h, &[], dim)?;
    let wanted: Vec<usize> = (0..dim)
        .filter(|&i| theta[i] >= theta_min * (1.0 - 1e-9))
        .collect();
    let mut modes: Vec<Mode> = wanted
        .par_iter()
        .map(|&i| {
            let mut x = vec![0.0; n];
            for (jj, qj) in q.iter().enumerate() {
                let c = u[(jj, i)];
                for r in 0..n {
                    x[r] += c * qj[r];
                }
            }
            x
        })
        .collect::<Vec<_>>()
        .into_iter()
        .map(|x| {
            let y = op.apply(&x);
            let nrm = m_norm(&y);
            let y: Vec<f64> = y.into_iter().map(|v| v / nrm).collect();
            let mut ky = vec![0.0; n];
            let mut my = vec![0.0; n];
            sym_lower_matvec(k, &y, &mut ky);
            sym_lower_matvec(m, &y, &mut my);
            let lambda = dot(&y, &ky) / dot(&y, &my);
            let r: f64 = ky
                .iter()
                .zip(&my)
                .map(|(a, b)| (a - lambda * b).powi(2))
                .sum::<f64>()
                .sqrt();
            let freq = lambda.signum() * lambda.abs().sqrt() / (2.0 * PI);
            let rigid = freq.abs() < opts.rigid_below_hz;
            // ||K x|| for flexible modes; for rigid and near-rigid modes (w² below |sigma|)
            // ||K x|| is itself round-off, so the scale is the shifted operator's, |sigma| ||M x||.
            let denom = dot(&ky, &ky).sqrt().max(sigma.abs() * dot(&my, &my).sqrt());
            Mode {
                frequency_hz: freq,
                eigenvalue: lambda,
                residual: r / denom,
                rigid,
                vector: y,
            }
        })
        .filter(|mode| mode.eigenvalue <= lambda_max)
        .collect();
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
    let sturm_count = if opts.sturm_check {
        let count = sturm_count(k, m, lambda_max)?;
        if count != modes.len() {
            return Err(Error::Numerical(format!(
                "the Sturm count finds {count} eigenvalues below {} Hz but Lanczos returned {} \
                 modes (basis {dim}, {runs} runs): raise the basis limit or split the band",
                opts.fmax_hz,
                modes.len()
            )));
        }
        Some(count)
    } else {
        None
    };
    Ok(ModalSolution {
        modes,
        shift: sigma,
        basis_size: dim,
        runs,
        factor_seconds,
        solve_seconds: started.elapsed().as_secs_f64(),
        sturm_count,
    })
}
