//! The Sturm count of a shifted pencil from its `L D Lᵀ` factor, shared by the 3D band solver
//! (supernodal factor) and the axisymmetric solver (simplicial factor).
//!
//! Sylvester's law of inertia: `L D Lᵀ` is congruent to `A = K - sigma M`, so `D` has as many
//! negative entries as `A` has negative eigenvalues; with `M` positive definite these are the
//! eigenvalues of the pencil `K x = lambda M x` below `sigma` (Parlett, The Symmetric
//! Eigenvalue Problem, sec. 3.3). The factors here are unpivoted, so `D` is the diagonal of the
//! stored unit lower factor: the diagonal entry of each column (simplicial) or of each
//! supernode's dense diagonal block (supernodal).

use faer::sparse::linalg::cholesky::simplicial::SymbolicSimplicialCholesky;
use faer::sparse::linalg::cholesky::supernodal::SymbolicSupernodalCholesky;
use faer::sparse::linalg::cholesky::{SymbolicCholesky, SymbolicCholeskyRaw};

use crate::{Error, Result};

/// Counts the negative pivots; a non-finite pivot (a shift on an eigenvalue, or a broken
/// factorisation) is an error, since the count would be meaningless.
fn count(pivots: impl Iterator<Item = f64>, sigma: f64) -> Result<usize> {
    let mut negative = 0;
    for d in pivots {
        if !d.is_finite() {
            return Err(Error::Numerical(format!(
                "non-finite pivot in the LDLᵀ of K - sigma M at sigma = {sigma:.6e}: the shift \
                 lies on an eigenvalue or the matrices are not finite"
            )));
        }
        if d < 0.0 {
            negative += 1;
        }
    }
    Ok(negative)
}

/// Negative pivots of a simplicial `L D Lᵀ` (values `l_values` on `symbolic`).
pub fn simplicial_negative_pivots(
    symbolic: &SymbolicSimplicialCholesky<usize>,
    l_values: &[f64],
    sigma: f64,
) -> Result<usize> {
    let cp = symbolic.col_ptr();
    let ri = symbolic.row_idx();
    let diagonal = (0..symbolic.ncols()).filter_map(|j| (cp[j]..cp[j + 1]).find(|&p| ri[p] == j));
    count(diagonal.map(|p| l_values[p]), sigma)
}

/// Negative pivots of a supernodal `L D Lᵀ`: each supernode stores its columns as a dense
/// column-major block whose leading square holds the diagonal.
pub fn supernodal_negative_pivots(
    symbolic: &SymbolicSupernodalCholesky<usize>,
    l_values: &[f64],
    sigma: f64,
) -> Result<usize> {
    let begin = symbolic.supernode_begin();
    let end = symbolic.supernode_end();
    let val_ptr = symbolic.col_ptr_for_val();
    let diagonal = (0..symbolic.n_supernodes()).flat_map(|sn| {
        let cols = end[sn] - begin[sn];
        let rows = (val_ptr[sn + 1] - val_ptr[sn]) / cols.max(1);
        (0..cols).map(move |c| val_ptr[sn] + c * rows + c)
    });
    count(diagonal.map(|p| l_values[p]), sigma)
}

/// Negative pivots of an `L D Lᵀ` in either storage.
pub fn negative_pivots(
    symbolic: &SymbolicCholesky<usize>,
    l_values: &[f64],
    sigma: f64,
) -> Result<usize> {
    match symbolic.raw() {
        SymbolicCholeskyRaw::Simplicial(s) => simplicial_negative_pivots(s, l_values, sigma),
        SymbolicCholeskyRaw::Supernodal(s) => supernodal_negative_pivots(s, l_values, sigma),
    }
}
