//! Iterative solution of large symmetric positive definite systems of 3 x 3 node blocks (the
//! static tangent of an elastic model): preconditioned conjugate gradients with a two-level
//! aggregation preconditioner, for models whose sparse Cholesky factor would not fit in memory
//! (the `paper` meshes' static preload: 2.72 G factor entries).
//!
//! - [`block_matrix`]: the matrix, by node blocks, and its product with a vector.
//! - [`aggregation`]: nodes grouped into aggregates along strong couplings.
//! - [`prolongator`]: the coarse space (the six rigid-body motions of each aggregate), its
//!   restriction and prolongation, and the Galerkin coarse matrix `Pᵀ A P`.
//! - [`coarse`]: the coarse matrix's Cholesky factor and solve.
//! - [`smoother`]: Chebyshev smoothing on the block diagonal.
//! - [`two_level`]: the preconditioner, a symmetric two-level V-cycle:
//!   `I - B A = (I - S A)(I - P A_c⁻¹ Pᵀ A)(I - S A)`.
//! - [`pcg`]: conjugate gradients.
//!
//! The method is smoothed-aggregation multigrid reduced to two levels with an unsmoothed
//! prolongator (Vaněk, Mandel & Brezina 1996, "Algebraic multigrid by smoothed aggregation for
//! second and fourth order elliptic problems", Computing 56: near-null space of rigid-body
//! modes per aggregate); the Chebyshev smoother follows Adams, Brezina, Hu & Tuminaro 2003
//! ("Parallel multigrid smoothing: polynomial versus Gauss-Seidel", J. Comput. Phys. 188).

pub mod aggregation;
pub mod block_matrix;
pub mod coarse;
pub mod pcg;
pub mod prolongator;
pub mod smoother;
pub mod two_level;

pub use block_matrix::BlockMatrix;
pub use pcg::{conjugate_gradients, PcgOptions, PcgReport, Preconditioner};
pub use two_level::{TwoLevel, TwoLevelOptions};
