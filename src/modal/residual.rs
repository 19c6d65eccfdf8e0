//! What a computed mode's residual can reach in double precision.
//!
//! A mode's relative residual is `||K x - lambda M x|| / ||K x||` (rigid modes: over the band's
//! stiffness scale). Forming `K x` in floating point alone errs by up to `gamma_n |K| |x|` per
//! row (Higham, Accuracy and Stability of Numerical Algorithms, 2nd ed., 2002, sec. 3.5), so
//! no method brings the residual below about
//!
//! ```text
//! floor = u (|| |K| |x| || + |lambda| || |M| |x| ||) / ||K x||,   u = 2^-53,
//! ```
//!
//! For a low mode of a stiff or badly graded mesh `|K| |x|` is many times `|K x|` (the
//! element forces nearly cancel), and the floor rises above any fixed tolerance: the
//! low modes of a 22 k-element linear-tet wheelset reach only 3e-8, as SciPy's ARPACK does on
//! the same matrices. A mode is accepted when its residual is below
//! `max(tolerance, FLOOR_FACTOR floor)`, so a refusal means a wrong mode, not the arithmetic.

use faer::sparse::SparseColMat;

/// How far above its rounding floor an accepted residual may lie. Shift-invert vectors come
/// from solves whose own backward error is of the floor's size, and the residual is formed
/// once more in floating point, so where the floor dominates correct modes land at about the
/// floor (1.0 to 2.2 times it on graded random pencils of 8 to 12 decades of stiffness,
/// tests/eigen_reference.rs); ten times leaves room for that and still refuses a mode whose
/// error is more than rounding.
pub const FLOOR_FACTOR: f64 = 10.0;

/// `y = |A| |x|` for a symmetric `A` stored as its lower triangle.
pub fn abs_sym_lower_matvec(a: &SparseColMat<usize, f64>, x: &[f64], y: &mut [f64]) {
    y.iter_mut().for_each(|v| *v = 0.0);
    let col_ptr = a.symbolic().col_ptr();
    let row_idx = a.symbolic().row_idx();
    let val = a.val();
    for j in 0..a.ncols() {
        let xj = x[j].abs();
        let mut acc = 0.0;
        for p in col_ptr[j]..col_ptr[j + 1] {
            let i = row_idx[p];
            let v = val[p].abs();
            y[i] += v * xj;
            if i != j {
                acc += v * x[i].abs();
            }
        }
        y[j] += acc;
    }
}

/// The rounding floor of a mode's relative residual (module docs); `denominator` is the one
/// its residual was divided by.
pub fn rounding_floor(
    k: &SparseColMat<usize, f64>,
    m: &SparseColMat<usize, f64>,
    x: &[f64],
    lambda: f64,
    denominator: f64,
) -> f64 {
    let mut kx = vec![0.0; x.len()];
    let mut mx = vec![0.0; x.len()];
    abs_sym_lower_matvec(k, x, &mut kx);
    abs_sym_lower_matvec(m, x, &mut mx);
    floor_from_products(&kx, &mx, lambda, denominator)
}

/// [`rounding_floor`] from the products `|K| |x|` and `|M| |x|` (formed for many modes at once
/// by the caller).
pub fn floor_from_products(abs_k_x: &[f64], abs_m_x: &[f64], lambda: f64, denominator: f64) -> f64 {
    let norm = |v: &[f64]| v.iter().map(|a| a * a).sum::<f64>().sqrt();
    0.5 * f64::EPSILON * (norm(abs_k_x) + lambda.abs() * norm(abs_m_x)) / denominator
}
