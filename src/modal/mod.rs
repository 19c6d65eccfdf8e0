//! Modal analysis: the generalized symmetric eigen problem `K x = w² M x` for every mode in a
//! frequency band, and the classification of wheel modes.
//!
//! Method (shift-invert Lanczos with full reorthogonalisation in the M inner product):
//! - shift `sigma = -(2 pi f_s)²` below the band, so `A = K - sigma M` is symmetric positive
//!   definite for clamped and free-free bodies alike (a free body's rigid modes have `w² = 0 >
//!   sigma`); one sparse Cholesky `A = L Lᵀ` (faer, supernodal, with the smaller factor of
//!   AMD and our nested dissection, [`ordering`], renumbered in a postorder of its elimination
//!   tree, `postorder`); its solves run over the elimination tree, sibling subtrees in
//!   parallel (`tree_solve`: the factor is streamed once per block of right-hand sides, where
//!   one solve per thread streamed it once per thread);
//! - operator `Op = A⁻¹ M`, self-adjoint in `<u, v>_M = uᵀ M v`, with eigenvalues
//!   `theta = 1 / (w² - sigma)`: the lowest frequencies are the largest, best separated `theta`;
//! - completeness first: the Sturm count, the negative pivots of a supernodal LDLᵀ of
//!   `K - w_max² M` (same symbolic analysis), is the number of modes in the band;
//! - block Krylov basis `Q` (blocks of 16 columns: one multi-right-hand-side solve reads the
//!   factor once per column group; multiplicities up to 16, rigid modes and sin/cos pairs, are
//!   found without restarts), M-orthonormal, with `M Q` kept beside it: block Gram-Schmidt
//!   against the last two blocks, then one pass against all of `Q` (dense products), then
//!   SVQB and Cholesky QR inside the block; projected matrix `H = Qᵀ M Op Q`, Ritz pairs from a
//!   dense symmetric eigen solve of `H`, residual estimate `||B u_last||` from the last block's
//!   coupling `B`; stop on the block where as many Ritz values in the band as the Sturm count
//!   have converged (without the count: every one in the band and one past it), and check
//!   that the modes returned match the count;
//! - spectrum slicing (`ModalOptions::slices` > 1): the band cut into slices equally wide in
//!   frequency, a Sturm count at every edge, the first slice solved as above and each other one
//!   with a shift `sigma` in its middle (indefinite `L D Lᵀ`; the slice is `theta >= 1 /
//!   (w_hi² - sigma)` or `theta <= 1 / (w_lo² - sigma) < 0`, both ends of the operator's
//!   spectrum), each returning exactly its count;
//! - models under 200 dofs take a dense solve;
//! - each Ritz vector `x = Q u` is purified by one more application of `Op` (damps the
//!   components along high modes that the random start block leaves in the basis), formed from
//!   the basis through the Lanczos relation `Op Q = [Q V_next] H~` (the coefficients actually
//!   subtracted, and each block's `B`), so without a solve ([`slice`];
//!   `ModalOptions::purify_by_solve` does the solve, for comparison); its eigenvalue is the
//!   Rayleigh quotient, and its relative
//!   residual `||K x - w² M x|| / ||K x||` (rigid modes: `/ (|sigma| ||M x||)`) must be below
//!   the tolerance or within [`residual::FLOOR_FACTOR`] times what double precision lets it
//!   reach ([`residual`]), else the solve fails with a message.
//!
//! Files, one job each: [`lanczos`] (the band solve), [`solution`] (options and results),
//! [`factor`] (the shifted pencil, its symbolic analysis and factors, the shift-invert
//! operator), [`inertia`] (the Sturm count from `L D Lᵀ`, shared with [`axisym`]), [`block`]
//! (block linear algebra in the M inner product), [`slice`] (spectrum slicing and the Lanczos
//! of one slice), [`dense`] (small models and the projected matrix), [`ordering`] (nested
//! dissection), `postorder` (the elimination tree and its postorder), `tree_solve` (the
//! factor's solves over the tree), `workspace` (buffers reused across Lanczos steps), `memory` (resident memory for the
//! trace), [`mode`] (the mode types every stage shares), [`classify`] (families and
//! nodal counts), [`pipeline`] (solve and classify a `model::modal` model), [`axisym`] (the
//! axisymmetric solver), [`hammer`] (hammer-test data).

pub mod axisym;
pub mod block;
pub mod classify;
pub mod dense;
pub mod lanczos;
mod memory;
pub mod mode;
pub mod pipeline;
pub mod residual;
pub mod slice;
pub mod solution;

pub use lanczos::{solve, ModalOptions, ModalSolution, Mode};
pub use memory::release_free_heap;
