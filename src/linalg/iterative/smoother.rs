//! Chebyshev smoothing on the block diagonal (Adams, Brezina, Hu & Tuminaro 2003): with
//! `D` the matrix's 3 x 3 diagonal blocks, the smoother is `S = p(D⁻¹ A) D⁻¹`, where the
//! polynomial `p` of degree `k` makes `1 - t p(t)` smallest on `[lambda_max / ratio,
//! lambda_max]` of `D⁻¹ A`'s spectrum: the upper part of the spectrum, which the coarse space
//! cannot represent, is damped, and the lower part is left to the coarse correction. `S` is
//! symmetric (`p(D⁻¹ A) D⁻¹ = D^-1/2 p(D^-1/2 A D^-1/2) D^-1/2`), so the two-level
//! preconditioner built on it is too.
//!
//! The products use the single-precision copy of the matrix ([`SingleBlockMatrix`]), the block
//! diagonal its double-precision blocks: `S` stays symmetric (both triangles are rounded alike).
//!
//! `lambda_max` is estimated from the Lanczos tridiagonal of a few block-Jacobi conjugate
//! gradient steps (as PETSc's Chebyshev does) and raised by [`SAFETY`]: an estimate below the
//! true value would let the smoother amplify the top of the spectrum.

// `!(x > 0.0)` is meant: it also rejects NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::block_matrix::{Block3, SingleBlockMatrix};
use super::pcg::{axpy, dot};
use crate::random::XorShift64;
use crate::{Error, Result};
use rayon::prelude::*;

/// Conjugate gradient steps of the `lambda_max` estimate.
const ESTIMATE_STEPS: usize = 12;
/// Factor on the estimate (the Lanczos value lies below the true one; PETSc uses 1.1).
pub const SAFETY: f64 = 1.1;

/// The block-Jacobi Chebyshev smoother.
pub struct Chebyshev {
    inverse_diagonal: Vec<Block3>,
    degree: usize,
    lower: f64,
    upper: f64,
    /// Work vectors (residual, direction).
    r: Vec<f64>,
    d: Vec<f64>,
    ad: Vec<f64>,
}

fn invert(b: &Block3) -> Option<Block3> {
    let det = b[0][0] * (b[1][1] * b[2][2] - b[1][2] * b[2][1])
        - b[0][1] * (b[1][0] * b[2][2] - b[1][2] * b[2][0])
        + b[0][2] * (b[1][0] * b[2][1] - b[1][1] * b[2][0]);
    if !(det.is_finite() && det > 0.0) {
        return None;
    }
    let c = |i: usize, j: usize| {
        let (i1, i2) = ((i + 1) % 3, (i + 2) % 3);
        let (j1, j2) = ((j + 1) % 3, (j + 2) % 3);
        b[i1][j1] * b[i2][j2] - b[i1][j2] * b[i2][j1]
    };
    Some(std::array::from_fn(|i| {
        std::array::from_fn(|j| c(j, i) / det)
    }))
}

fn apply_blocks(blocks: &[Block3], x: &[f64], y: &mut [f64]) {
    y.par_chunks_mut(3)
        .zip(x.par_chunks(3))
        .zip(blocks.par_iter())
        .for_each(|((yn, xn), b)| {
            for d in 0..3 {
                yn[d] = b[d][0] * xn[0] + b[d][1] * xn[1] + b[d][2] * xn[2];
            }
        });
}

impl Chebyshev {
    /// The smoother of degree `degree` (>= 1) on `[lambda_max / ratio, lambda_max]`.
    pub fn new(a: &SingleBlockMatrix, degree: usize, ratio: f64) -> Result<Chebyshev> {
        if degree == 0 || !(ratio > 1.0) {
            return Err(Error::input(
                "Chebyshev smoother",
                "degree / ratio",
                format!("degree must be at least 1 and ratio above 1 (got {degree}, {ratio})"),
            ));
        }
        let n = a.nodes();
        let mut inverse_diagonal = Vec::with_capacity(n);
        for r in 0..n {
            let Some(inv) = invert(a.diagonal_block(r)) else {
                return Err(Error::Numerical(format!(
                    "the diagonal block of node {r} is not positive definite: the matrix is \
                     not symmetric positive definite"
                )));
            };
            inverse_diagonal.push(inv);
        }
        let upper = SAFETY * largest_eigenvalue_estimate(a, &inverse_diagonal)?;
        Ok(Chebyshev {
            inverse_diagonal,
            degree,
            lower: upper / ratio,
            upper,
            r: vec![0.0; 3 * n],
            d: vec![0.0; 3 * n],
            ad: vec![0.0; 3 * n],
        })
    }

    /// The interval the polynomial damps: `(lower, upper)` of `D⁻¹ A`'s spectrum.
    pub fn interval(&self) -> (f64, f64) {
        (self.lower, self.upper)
    }

    /// `x <- x + S (b - A x)` from `x = 0` (so `x = S b`); returns with `residual = b - A x`
    /// when `want_residual` (one more product).
    pub fn smooth_from_zero(
        &mut self,
        a: &SingleBlockMatrix,
        b: &[f64],
        x: &mut [f64],
        residual: Option<&mut [f64]>,
    ) {
        // Chebyshev iteration (Saad, "Iterative methods for sparse linear systems", 2nd ed.,
        // algorithm 12.1) on the system preconditioned by D.
        let theta = 0.5 * (self.upper + self.lower);
        let delta = 0.5 * (self.upper - self.lower);
        let sigma = theta / delta;
        let mut rho = 1.0 / sigma;
        self.r.copy_from_slice(b);
        apply_blocks(&self.inverse_diagonal, &self.r, &mut self.d);
        self.d.iter_mut().for_each(|v| *v /= theta);
        x.copy_from_slice(&self.d);
        let last = self.degree - 1;
        for step in 0..self.degree {
            if step == last && residual.is_none() {
                break;
            }
            a.apply(&self.d, &mut self.ad);
            axpy(-1.0, &self.ad, &mut self.r);
            if step == last {
                break;
            }
            let rho_new = 1.0 / (2.0 * sigma - rho);
            let (c_old, c_new) = (rho_new * rho, 2.0 * rho_new / delta);
            // d <- c_old d + c_new D⁻¹ r
            let inv = &self.inverse_diagonal;
            self.d
                .par_chunks_mut(3)
                .zip(self.r.par_chunks(3))
                .zip(inv.par_iter())
                .for_each(|((dn, rn), bi)| {
                    for k in 0..3 {
                        let z = bi[k][0] * rn[0] + bi[k][1] * rn[1] + bi[k][2] * rn[2];
                        dn[k] = c_old * dn[k] + c_new * z;
                    }
                });
            axpy(1.0, &self.d, x);
            rho = rho_new;
        }
        if let Some(res) = residual {
            res.copy_from_slice(&self.r);
        }
    }
}

/// Largest eigenvalue of `D⁻¹ A` from the Lanczos tridiagonal of block-Jacobi conjugate
/// gradients on a seeded random right-hand side (Saad, section 6.7.3: the CG coefficients give
/// the tridiagonal `T`; its largest eigenvalue approaches `lambda_max` from below).
fn largest_eigenvalue_estimate(a: &SingleBlockMatrix, inverse_diagonal: &[Block3]) -> Result<f64> {
    let n3 = 3 * a.nodes();
    let mut rng = XorShift64::seeded(0x5eed_c4eb);
    let mut r: Vec<f64> = (0..n3).map(|_| rng.centred_uniform()).collect();
    let mut z = vec![0.0; n3];
    let mut p = vec![0.0; n3];
    let mut ap = vec![0.0; n3];
    apply_blocks(inverse_diagonal, &r, &mut z);
    p.copy_from_slice(&z);
    let mut rz = dot(&r, &z);
    let (mut alphas, mut betas) = (Vec::new(), Vec::new());
    for _ in 0..ESTIMATE_STEPS.min(n3) {
        a.apply(&p, &mut ap);
        let pap = dot(&p, &ap);
        if !(pap > 0.0) || !(rz > 0.0) {
            break;
        }
        let alpha = rz / pap;
        axpy(-alpha, &ap, &mut r);
        apply_blocks(inverse_diagonal, &r, &mut z);
        let rz_new = dot(&r, &z);
        let beta = rz_new / rz;
        alphas.push(alpha);
        betas.push(beta);
        if !(rz_new > 0.0) {
            break;
        }
        p.par_iter_mut()
            .zip(z.par_iter())
            .for_each(|(pi, zi)| *pi = zi + beta * *pi);
        rz = rz_new;
    }
    if alphas.is_empty() {
        return Err(Error::Numerical(
            "the matrix is not positive definite (a conjugate gradient step found pᵀ A p <= 0)"
                .to_string(),
        ));
    }
    // T: diagonal 1/alpha_j + beta_{j-1}/alpha_{j-1}, off-diagonal sqrt(beta_{j-1})/alpha_{j-1}.
    let m = alphas.len();
    let mut t = nalgebra::DMatrix::<f64>::zeros(m, m);
    for j in 0..m {
        t[(j, j)] = 1.0 / alphas[j]
            + if j > 0 {
                betas[j - 1] / alphas[j - 1]
            } else {
                0.0
            };
        if j > 0 {
            let off = betas[j - 1].sqrt() / alphas[j - 1];
            t[(j, j - 1)] = off;
            t[(j - 1, j)] = off;
        }
    }
    let eig = t.symmetric_eigenvalues();
    Ok(eig.iter().copied().fold(0.0f64, f64::max))
}
