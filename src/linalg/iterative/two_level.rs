//! The two-level preconditioner: Chebyshev pre-smoothing, the coarse correction on the
//! aggregates' rigid-body motions, the same smoothing after (a symmetric V-cycle of two
//! levels):
//!
//! `z = S r`; `z <- z + P A_c⁻¹ Pᵀ (r - A z)`; `z <- z + S (r - A z)`,
//!
//! so that the error propagates as `I - B A = (I - S A)(I - P A_c⁻¹ Pᵀ A)(I - S A)`: symmetric in
//! the energy inner product because `S` is symmetric, and `B` positive definite when the
//! smoother converges in the energy norm (the Chebyshev interval covers the top of the
//! spectrum).

use std::time::Instant;

use super::aggregation::Aggregates;
use super::block_matrix::{BlockMatrix, SingleBlockMatrix};
use super::coarse::{CoarseSetupSeconds, CoarseSpace};
use super::pcg::{axpy, Preconditioner};
use super::smoother::Chebyshev;
use crate::Result;

/// Settings of the two-level preconditioner.
#[derive(Clone, Copy, Debug)]
pub struct TwoLevelOptions {
    /// Strength threshold of the aggregation ([`super::aggregation`]).
    pub strength_threshold: f64,
    /// Chebyshev degree (products with `A` per smoothing: about the degree).
    pub smoother_degree: usize,
    /// `lambda_max / lambda_min` of the smoothed interval.
    pub smoother_ratio: f64,
}

impl Default for TwoLevelOptions {
    fn default() -> Self {
        TwoLevelOptions {
            // Vaněk et al. use 0.08 for elasticity: element couplings on graded meshes stay
            // strong, soft springs between bodies do not.
            strength_threshold: 0.08,
            smoother_degree: 3,
            // Adams et al. 2003 smooth the upper 1/30 of the spectrum.
            smoother_ratio: 30.0,
        }
    }
}

/// What the set-up made.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TwoLevelStats {
    /// Aggregates (coarse nodes).
    pub aggregates: usize,
    /// Coarse unknowns.
    pub coarse_unknowns: usize,
    /// Entries of the coarse Cholesky factor.
    pub coarse_factor_entries: usize,
    /// The smoothed interval of `D⁻¹ A`'s spectrum.
    pub smoother_interval: (f64, f64),
    /// Seconds of the set-up.
    pub setup_seconds: f64,
    /// Of which: the single-precision copy and the smoother (its interval's Lanczos steps).
    pub smoother_setup_seconds: f64,
    /// The aggregation.
    pub aggregation_seconds: f64,
    /// The coarse level, by part.
    pub coarse_setup_seconds: CoarseSetupSeconds,
    /// Seconds of the applications so far in smoothing (with its residual products).
    pub smoothing_seconds: f64,
    /// Seconds of the applications so far in the coarse correction (restriction, solve,
    /// prolongation, its residual product).
    pub coarse_seconds: f64,
}

/// The preconditioner and its work vectors.
pub struct TwoLevel {
    /// The matrix in single precision: the smoothing's and the coarse residual's products.
    single: SingleBlockMatrix,
    coarse: CoarseSpace,
    smoother: Chebyshev,
    residual: Vec<f64>,
    correction: Vec<f64>,
    product: Vec<f64>,
    coarse_vector: Vec<f64>,
    stats: TwoLevelStats,
}

impl TwoLevel {
    /// Sets up the preconditioner of `a`: node coordinates (the rigid-body motions) and held
    /// directions (no motion there).
    pub fn new(
        a: &BlockMatrix,
        coords_m: &[[f64; 3]],
        held: &[[bool; 3]],
        opts: &TwoLevelOptions,
    ) -> Result<TwoLevel> {
        let start = Instant::now();
        // The smoother first: it checks every diagonal block.
        let single = a.to_single();
        let smoother = Chebyshev::new(&single, opts.smoother_degree, opts.smoother_ratio)?;
        let smoother_setup_seconds = start.elapsed().as_secs_f64();
        let t = Instant::now();
        let aggregates = Aggregates::new(a, opts.strength_threshold);
        let aggregation_seconds = t.elapsed().as_secs_f64();
        let coarse = CoarseSpace::new(a, &aggregates, coords_m, held)?;
        let n3 = 3 * a.nodes();
        let stats = TwoLevelStats {
            aggregates: coarse.aggregates(),
            coarse_unknowns: coarse.unknowns(),
            coarse_factor_entries: coarse.factor_entries(),
            smoother_interval: smoother.interval(),
            setup_seconds: start.elapsed().as_secs_f64(),
            smoother_setup_seconds,
            aggregation_seconds,
            coarse_setup_seconds: coarse.setup_seconds(),
            smoothing_seconds: 0.0,
            coarse_seconds: 0.0,
        };
        Ok(TwoLevel {
            single,
            coarse_vector: vec![0.0; stats.coarse_unknowns],
            coarse,
            smoother,
            residual: vec![0.0; n3],
            correction: vec![0.0; n3],
            product: vec![0.0; n3],
            stats,
        })
    }

    /// Nodes of the matrix it was made for.
    pub fn nodes(&self) -> usize {
        self.residual.len() / 3
    }

    /// What the set-up made.
    pub fn stats(&self) -> TwoLevelStats {
        self.stats
    }
}

impl Preconditioner for TwoLevel {
    fn apply(&mut self, r: &[f64], z: &mut [f64]) {
        let a = &self.single;
        // Pre-smoothing: z = S r, residual = r - A z.
        let t0 = Instant::now();
        self.smoother
            .smooth_from_zero(a, r, z, Some(&mut self.residual));
        let t1 = Instant::now();
        // Coarse correction.
        self.coarse
            .prolongator()
            .restrict(&self.residual, &mut self.coarse_vector);
        self.coarse.solve(&mut self.coarse_vector);
        self.correction.iter_mut().for_each(|v| *v = 0.0);
        self.coarse
            .prolongator()
            .prolongate_add(&self.coarse_vector, &mut self.correction);
        axpy(1.0, &self.correction, z);
        a.apply(&self.correction, &mut self.product);
        axpy(-1.0, &self.product, &mut self.residual);
        let t2 = Instant::now();
        // Post-smoothing with the same polynomial.
        self.smoother
            .smooth_from_zero(a, &self.residual, &mut self.correction, None);
        axpy(1.0, &self.correction, z);
        self.stats.smoothing_seconds += (t1 - t0).as_secs_f64() + t2.elapsed().as_secs_f64();
        self.stats.coarse_seconds += (t2 - t1).as_secs_f64();
    }
}
