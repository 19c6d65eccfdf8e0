//! Sparse linear algebra shared by every solver stage: the modal eigen solvers (3D and
//! axisymmetric), the static preload of the explicit engine and the stability analysis.
//!
//! - Direct: a supernodal Cholesky / `L D Lᵀ` of a symmetric pencil `K - sigma M` (faer, with
//!   the smaller of AMD and our nested dissection, renumbered in a postorder of its elimination
//!   tree), and its solves over that tree with sibling subtrees in parallel.
//!   Files: [`factor`] (symbolic analysis, numeric factor, the shift-invert operator),
//!   [`ordering`] (nested dissection on the node graph), `separator` (multilevel vertex
//!   separators), `postorder` (the elimination tree and its postorder), `tree_solve` (the
//!   factor's solves over the tree), `workspace` (buffers reused across solves).
//! - Inertia: [`inertia`], the Sturm count (negative pivots of `L D Lᵀ`), which says how many
//!   eigenvalues lie below a shift (Sylvester's law of inertia).
//! - Iterative: [`iterative`], conjugate gradients with a two-level aggregation preconditioner
//!   for systems whose factor does not fit in memory.
//!
//! Nothing here knows what a wheel or a mode is: the stages above hand it matrices.

pub mod factor;
pub mod inertia;
pub mod iterative;
pub mod ordering;
mod postorder;
mod separator;
pub(crate) mod tree_solve;
pub(crate) mod workspace;
