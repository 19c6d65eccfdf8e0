//! Modal analysis: the generalized symmetric eigen problem `K x = w² M x` for every mode in a
//! frequency band, and the classification of wheel modes.
//!
//! Method (shift-invert Lanczos with full reorthogonalisation in the M inner product):
//! - shift `sigma = -(2 pi f_s)²` below the band, so `A = K - sigma M` is symmetric positive
//!   definite for clamped and free-free bodies alike (a free body's rigid modes have `w² = 0 >
//!   sigma`); one sparse Cholesky `A = L Lᵀ` (faer, AMD ordering);
//! - operator `Op = A⁻¹ M`, self-adjoint in `<u, v>_M = uᵀ M v`, with eigenvalues
//!   `theta = 1 / (w² - sigma)`: the lowest frequencies are the largest, best separated `theta`;
//! - Krylov basis `Q` (M-orthonormal, two passes of classical Gram-Schmidt against all of `Q`),
//!   projected matrix `H = Qᵀ M Op Q`, Ritz pairs from a dense symmetric eigen solve of `H`;
//! - repeated eigenvalues (rigid modes, sin/cos pairs of a body of revolution) are found by
//!   restarting with a fresh random vector orthogonal to all of `Q` until a restart finds no
//!   new mode in the band;
//! - each Ritz vector is purified by one more application of `Op` (damps the components along
//!   high modes that rounding leaves), its eigenvalue is the Rayleigh quotient, and its relative
//!   residual `||K x - w² M x|| / ||K x||` (rigid modes: `/ (|sigma| ||M x||)`) must be below
//!   the tolerance, else the solve fails with a message.

pub mod classify;
pub mod lanczos;

pub use lanczos::{solve, ModalOptions, ModalSolution, Mode};
