//! Modal analysis: the generalized symmetric eigen problem `K x = w² M x` for every mode in a
//! frequency band, and the classification of wheel modes.
//!
//! Method (shift-invert Lanczos with full reorthogonalisation in the M inner product):
//! - shift `sigma = -(2 pi f_s)²` below the band, so `A = K - sigma M` is symmetric positive
//!   definite for clamped and free-free bodies alike (a free body's rigid modes have `w² = 0 >
//!   sigma`); one sparse Cholesky `A = L Lᵀ` (faer, AMD ordering);
//! - operator `Op = A⁻¹ M`, self-adjoint in `<u, v>_M = uᵀ M v`, with eigenvalues
//!   `theta = 1 / (w² - sigma)`: the lowest frequencies are the largest, best separated `theta`;
//! - block Krylov basis `Q` (blocks of 8 columns: one multi-right-hand-side solve reads the
//!   factor once per block; multiplicities up to 8, rigid modes and sin/cos pairs, are found
//!   without restarts), M-orthonormal: two passes of block classical Gram-Schmidt against all
//!   of `Q` (dense products), then SVQB and Cholesky QR inside the block; projected matrix
//!   `H = Qᵀ M Op Q`, Ritz pairs from a dense symmetric eigen solve of `H`, residual estimate
//!   `||B u_last||` from the last block's coupling `B`; stop when every Ritz value in the band
//!   and one past it have converged;
//! - completeness: the Sturm count, the negative pivots of a supernodal LDLᵀ of
//!   `K - w_max² M`, must equal the modes found;
//! - models under 200 dofs take a dense solve;
//! - each Ritz vector is purified by one more application of `Op` (damps the components along
//!   high modes that rounding leaves), its eigenvalue is the Rayleigh quotient, and its relative
//!   residual `||K x - w² M x|| / ||K x||` (rigid modes: `/ (|sigma| ||M x||)`) must be below
//!   the tolerance, else the solve fails with a message.

pub mod classify;
pub mod lanczos;

pub use lanczos::{solve, ModalOptions, ModalSolution, Mode};
