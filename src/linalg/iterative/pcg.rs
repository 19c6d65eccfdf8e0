//! Preconditioned conjugate gradients (Hestenes & Stiefel 1952; Saad, "Iterative methods for
//! sparse linear systems", 2nd ed., algorithm 9.1) for a symmetric positive definite
//! [`BlockMatrix`], stopping at `|b - A x| <= tolerance |b|`.
//!
//! Reductions run over fixed chunks summed in order, so that the iterates do not depend on the
//! thread count.

use rayon::prelude::*;

use super::block_matrix::BlockMatrix;
use crate::{Error, Result};

/// Entries per chunk of a reduction (fixed: the sum's order does not depend on the threads).
const CHUNK: usize = 8192;

/// `aᵀ b`.
pub fn dot(a: &[f64], b: &[f64]) -> f64 {
    let parts: Vec<f64> = a
        .par_chunks(CHUNK)
        .zip(b.par_chunks(CHUNK))
        .map(|(x, y)| x.iter().zip(y).map(|(p, q)| p * q).sum::<f64>())
        .collect();
    parts.iter().sum()
}

/// `y <- y + alpha x`.
pub fn axpy(alpha: f64, x: &[f64], y: &mut [f64]) {
    y.par_chunks_mut(CHUNK)
        .zip(x.par_chunks(CHUNK))
        .for_each(|(yc, xc)| yc.iter_mut().zip(xc).for_each(|(yi, xi)| *yi += alpha * xi));
}

/// A symmetric positive definite approximation `B ≈ A⁻¹` of the matrix it was made for (it
/// keeps what it needs of that matrix).
pub trait Preconditioner {
    /// `z = B r`.
    fn apply(&mut self, r: &[f64], z: &mut [f64]);
}

/// No preconditioning (`B = I`): the reference the preconditioners are compared against.
pub struct Identity;

impl Preconditioner for Identity {
    fn apply(&mut self, r: &[f64], z: &mut [f64]) {
        z.copy_from_slice(r);
    }
}

/// Options of [`conjugate_gradients`].
#[derive(Clone, Copy, Debug)]
pub struct PcgOptions {
    /// Relative residual `|b - A x| / |b|` to reach.
    pub tolerance: f64,
    /// Most iterations.
    pub max_iterations: usize,
}

/// What [`conjugate_gradients`] did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PcgReport {
    /// Iterations (products with `A`, each with one preconditioner application).
    pub iterations: usize,
    /// `|b - A x| / |b|` at the end (the recurrence's residual).
    pub relative_residual: f64,
}

/// Solves `A x = b` from the `x` given (its start).
pub fn conjugate_gradients<P: Preconditioner + ?Sized>(
    a: &BlockMatrix,
    b: &[f64],
    x: &mut [f64],
    preconditioner: &mut P,
    opts: &PcgOptions,
) -> Result<PcgReport> {
    let n3 = 3 * a.nodes();
    if b.len() != n3 || x.len() != n3 {
        return Err(Error::input(
            "conjugate gradients",
            "vectors",
            format!("{} and {} entries for {n3} unknowns", b.len(), x.len()),
        ));
    }
    if !(opts.tolerance > 0.0 && opts.tolerance < 1.0) {
        return Err(Error::input(
            "conjugate gradients",
            "tolerance",
            format!("must lie in (0, 1) (got {})", opts.tolerance),
        ));
    }
    let b_norm = dot(b, b).sqrt();
    if b_norm == 0.0 {
        x.iter_mut().for_each(|v| *v = 0.0);
        return Ok(PcgReport {
            iterations: 0,
            relative_residual: 0.0,
        });
    }
    let mut r = vec![0.0; n3];
    a.apply(x, &mut r);
    r.iter_mut().zip(b).for_each(|(ri, bi)| *ri = bi - *ri);
    let mut z = vec![0.0; n3];
    let mut p = vec![0.0; n3];
    let mut ap = vec![0.0; n3];
    let mut relative = dot(&r, &r).sqrt() / b_norm;
    if relative <= opts.tolerance {
        return Ok(PcgReport {
            iterations: 0,
            relative_residual: relative,
        });
    }
    preconditioner.apply(&r, &mut z);
    p.copy_from_slice(&z);
    let mut rz = dot(&r, &z);
    for iteration in 1..=opts.max_iterations {
        a.apply(&p, &mut ap);
        let pap = dot(&p, &ap);
        if !(pap > 0.0 && rz > 0.0) {
            return Err(Error::Numerical(format!(
                "conjugate gradients broke down at iteration {iteration} (pᵀ A p = {pap:.3e}, \
                 rᵀ B r = {rz:.3e}): the matrix or the preconditioner is not positive definite"
            )));
        }
        let alpha = rz / pap;
        axpy(alpha, &p, x);
        axpy(-alpha, &ap, &mut r);
        relative = dot(&r, &r).sqrt() / b_norm;
        if !relative.is_finite() {
            return Err(Error::Numerical(format!(
                "conjugate gradients: non-finite residual at iteration {iteration}"
            )));
        }
        if relative <= opts.tolerance {
            return Ok(PcgReport {
                iterations: iteration,
                relative_residual: relative,
            });
        }
        preconditioner.apply(&r, &mut z);
        let rz_new = dot(&r, &z);
        let beta = rz_new / rz;
        rz = rz_new;
        p.par_chunks_mut(CHUNK)
            .zip(z.par_chunks(CHUNK))
            .for_each(|(pc, zc)| {
                pc.iter_mut()
                    .zip(zc)
                    .for_each(|(pi, zi)| *pi = zi + beta * *pi)
            });
    }
    Err(Error::Numerical(format!(
        "conjugate gradients did not reach the relative residual {:.1e} in {} iterations \
         (reached {relative:.3e})",
        opts.tolerance, opts.max_iterations
    )))
}
