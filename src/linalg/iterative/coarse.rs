//! The coarse level of the two-level preconditioner: the Galerkin coarse matrix
//! `A_c = Pᵀ A P` of the [`Prolongator`], factorised once by sparse Cholesky (faer), and its
//! solve.

use std::time::Instant;

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::cholesky::{LltRef, SymbolicCholesky};
use faer::{MatMut, Par};

use super::aggregation::Aggregates;
use super::block_matrix::BlockMatrix;
use super::prolongator::Prolongator;
use crate::linalg::factor::{numeric_factor, symbolic_pencil, FactorKind, TreePlan, Workspace};
use crate::{Error, Result};

/// Seconds of each part of the coarse level's set-up.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CoarseSetupSeconds {
    /// The prolongator (the aggregates' rigid-body motions).
    pub prolongator: f64,
    /// The Galerkin product `Pᵀ A P`.
    pub galerkin: f64,
    /// The fill-reducing ordering and symbolic analysis of `A_c`.
    pub symbolic: f64,
    /// The numeric Cholesky factorisation of `A_c`.
    pub numeric: f64,
}

/// The prolongator and the factorised coarse matrix.
pub struct CoarseSpace {
    prolongator: Prolongator,
    setup_seconds: CoarseSetupSeconds,
    symbolic: SymbolicCholesky<usize>,
    l_values: Vec<f64>,
    /// Buffers of the parallel solve.
    workspace: Workspace,
}

impl CoarseSpace {
    /// The coarse space of `aggregates` for nodes at `coords_m` with held directions `held`,
    /// and the Cholesky factor of `Pᵀ A P`.
    pub fn new(
        a: &BlockMatrix,
        aggregates: &Aggregates,
        coords_m: &[[f64; 3]],
        held: &[[bool; 3]],
    ) -> Result<CoarseSpace> {
        let t0 = Instant::now();
        let prolongator = Prolongator::new(a, aggregates, coords_m, held)?;
        let t1 = Instant::now();
        let coarse = prolongator.galerkin(a)?;
        let t2 = Instant::now();
        let symbolic = symbolic_pencil(&coarse)?;
        let t3 = Instant::now();
        let l_values = numeric_factor(&coarse, &symbolic, FactorKind::Llt).map_err(|e| {
            Error::Numerical(format!(
                "the coarse matrix of the two-level preconditioner is not positive definite \
                 ({e}): the matrix has a free motion"
            ))
        })?;
        let setup_seconds = CoarseSetupSeconds {
            prolongator: (t1 - t0).as_secs_f64(),
            galerkin: (t2 - t1).as_secs_f64(),
            symbolic: (t3 - t2).as_secs_f64(),
            numeric: t3.elapsed().as_secs_f64(),
        };
        Ok(CoarseSpace {
            prolongator,
            setup_seconds,
            symbolic,
            l_values,
            workspace: Workspace::new(),
        })
    }

    /// The prolongator `P`.
    pub fn prolongator(&self) -> &Prolongator {
        &self.prolongator
    }

    /// Seconds of each part of the set-up.
    pub fn setup_seconds(&self) -> CoarseSetupSeconds {
        self.setup_seconds
    }

    /// Coarse unknowns.
    pub fn unknowns(&self) -> usize {
        self.prolongator.unknowns()
    }

    /// Entries of the coarse Cholesky factor.
    pub fn factor_entries(&self) -> usize {
        self.symbolic.len_val()
    }

    /// Aggregates.
    pub fn aggregates(&self) -> usize {
        self.prolongator.aggregates()
    }

    /// `e <- A_c⁻¹ e`: over the factor's elimination tree, sibling subtrees in parallel
    /// ([`crate::linalg::factor::TreePlan`], the modal solver's solve), when the factor is
    /// supernodal and postordered (the nested dissection); faer's sequential solve otherwise.
    pub fn solve(&mut self, e: &mut [f64]) {
        if let Some(plan) = TreePlan::new(&self.symbolic) {
            plan.solve_in_place(&self.l_values, FactorKind::Llt, e, &mut self.workspace);
            return;
        }
        let n = e.len();
        let mut mem = MemBuffer::new(self.symbolic.solve_in_place_scratch::<f64>(1, Par::Seq));
        LltRef::<usize, f64>::new(&self.symbolic, &self.l_values).solve_in_place_with_conj(
            faer::Conj::No,
            MatMut::from_column_major_slice_mut(e, n, 1),
            Par::Seq,
            MemStack::new(&mut mem),
        );
    }
}
