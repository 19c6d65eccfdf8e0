//! Shift-invert Lanczos for `K x = w² M x` (see the module docs of [`crate::modal`]).

use super::dense::{solve_dense, DENSE_BELOW_DOFS};
use super::memory::{release_free_heap, resident_note};
use super::residual::FLOOR_FACTOR;
pub use super::slice::{check_slices, MAX_SLICES};
use super::slice::{solve_slice, Slice, SliceResult};
pub use super::solution::{ModalOptions, ModalSolution, Mode};
pub use crate::linalg::factor::sturm_count;
use crate::linalg::factor::{
    numeric_factor, shifted, sturm_count_with, symbolic_pencil, FactorKind, ShiftInvert,
};
use crate::linalg::tree_solve::TreePlan;
use crate::{Error, Result};
use faer::sparse::linalg::cholesky::SymbolicCholesky;
use faer::sparse::SparseColMat;
use std::f64::consts::PI;
use std::time::Instant;

/// All modes with `f <= fmax_hz` of `K x = w² M x` (K, M: lower triangles, symmetric, M positive
/// definite, K positive semi-definite), by block shift-invert Lanczos (module docs), over
/// `opts.slices` slices of the band.
///
/// The band solve's steps in order (checks, symbolic analysis, Sturm counts, slices,
/// purification, residual check), each delegating to factor.rs, slice.rs or dense.rs.
pub fn solve(
    k: &SparseColMat<usize, f64>,
    m: &SparseColMat<usize, f64>,
    opts: &ModalOptions,
) -> Result<ModalSolution> {
    let started = Instant::now();
    let n = k.nrows();
    check_request(opts, n)?;
    let shift_hz = opts.shift_hz.unwrap_or((opts.fmax_hz / 20.0).max(10.0));
    let sigma = -(2.0 * PI * shift_hz).powi(2);
    let lambda_max = (2.0 * PI * opts.fmax_hz).powi(2);
    let trace = std::env::var_os("SQUEAL_MODAL_TRACE").is_some();
    if n < DENSE_BELOW_DOFS {
        return solve_dense(k, m, opts, sigma, lambda_max, started);
    }
    let (first, symbolic) = analyse(k, m, sigma, trace, started)?;
    let mut a = Some(first);
    let band = Band {
        k,
        m,
        opts,
        symbolic: &symbolic,
        sigma,
        lambda_max,
        edges: slice_edges(opts),
        trace,
        started,
    };
    let slices = opts.slices;
    let counts = band.sturm_counts()?;
    let mut factor_seconds = 0.0;
    let mut modes: Vec<Mode> = Vec::new();
    let (mut basis_size, mut blocks) = (0, 0);
    let mut shifts = Vec::with_capacity(slices);
    for s in 0..slices {
        let count = counts.as_ref().map(|c| c[s + 1] - c[s]);
        if count == Some(0) {
            continue;
        }
        let (slice, res, slice_factor_seconds) = band.run_slice(s, count, &mut a)?;
        factor_seconds += slice_factor_seconds;
        shifts.push(slice.sigma);
        basis_size = basis_size.max(res.basis);
        blocks += res.blocks;
        modes.extend(res.modes);
    }
    modes.sort_by(|a, b| a.eigenvalue.total_cmp(&b.eigenvalue));
    check_residuals(&modes, opts)?;
    if trace {
        trace_modes(&modes, basis_size, blocks, started);
    }
    Ok(ModalSolution {
        modes,
        shift: sigma,
        shifts,
        basis_size,
        block_size: opts.block_size.clamp(1, n),
        blocks,
        factor_seconds,
        solve_seconds: started.elapsed().as_secs_f64(),
        sturm_count: counts.map(|c| c[slices]),
    })
}

/// The first slice's matrix `K - sigma M` and the one symbolic analysis every shift and Sturm
/// count shares, the analysis's freed memory handed back to the system before the factors
/// and the basis arrive.
fn analyse(
    k: &SparseColMat<usize, f64>,
    m: &SparseColMat<usize, f64>,
    sigma: f64,
    trace: bool,
    started: Instant,
) -> Result<(SparseColMat<usize, f64>, SymbolicCholesky<usize>)> {
    // The first slice's matrix; taken (and freed) by its factorisation, before the Lanczos
    // basis grows.
    let first = shifted(k, m, sigma)?;
    // One symbolic analysis for every shift and Sturm count: `K - s M` has the same pattern.
    let symbolic = symbolic_pencil(&first)?;
    // The analysis's freed graphs back to the system before the factor and the basis arrive
    // (memory.rs): 293 MB of the peak at 294 k dofs.
    release_free_heap();
    if trace {
        eprintln!(
            "trace: symbolic at {:.2} s, factor entries {}{}",
            started.elapsed().as_secs_f64(),
            symbolic.len_val(),
            resident_note()
        );
    }
    Ok((first, symbolic))
}

/// Traces each mode's residual and the solve's totals (`SQUEAL_MODAL_TRACE`).
fn trace_modes(modes: &[Mode], basis_size: usize, blocks: usize, started: Instant) {
    for md in modes {
        eprintln!(
            "trace: {:.4} Hz residual {:.2e}",
            md.frequency_hz, md.residual
        );
    }
    eprintln!(
        "trace: done at {:.2} s (largest basis {basis_size}, {blocks} blocks){}",
        started.elapsed().as_secs_f64(),
        resident_note()
    );
}

/// The request must be solvable before any work: a finite positive top frequency, a valid
/// slice count, and at least one free degree of freedom (`n`).
fn check_request(opts: &ModalOptions, n: usize) -> Result<()> {
    if !(opts.fmax_hz.is_finite() && opts.fmax_hz > 0.0) {
        return Err(Error::input(
            "command line",
            "fmax-hz",
            format!("{} must be a finite frequency > 0 Hz", opts.fmax_hz),
        ));
    }
    check_slices(opts.slices)?;
    if n == 0 {
        return Err(Error::Numerical(
            "the model has no free degree of freedom (everything is clamped)".into(),
        ));
    }
    Ok(())
}

/// The slices' edges (eigenvalues `w²`, from 0 to the top frequency's).
fn slice_edges(opts: &ModalOptions) -> Vec<f64> {
    // Slice edges equally spaced in frequency: a wheel's mode count grows about linearly with
    // frequency (plate-like: 73 modes below 5 kHz, 161 below 10 kHz on the 16 mm wheel), so
    // equal widths hold about equal numbers of modes.
    let slices = opts.slices;
    (0..=slices)
        .map(|i| (2.0 * PI * opts.fmax_hz * i as f64 / slices as f64).powi(2))
        .collect()
}

/// No mode may have a residual above both the tolerance and its rounding floor.
fn check_residuals(modes: &[Mode], opts: &ModalOptions) -> Result<()> {
    // A mode is refused only where its residual is above both the tolerance and what double
    // precision lets it reach (modal::residual).
    if let Some(bad) = modes.iter().find(|m| {
        m.residual.is_nan()
            || m.residual >= opts.residual_tolerance.max(FLOOR_FACTOR * m.residual_floor)
    }) {
        return Err(Error::Numerical(format!(
            "mode at {:.3} Hz has relative residual {:.2e} above the tolerance {:.0e} and above \
             {FLOOR_FACTOR} times its rounding floor {:.1e}; the mesh may be badly conditioned \
             (check element quality) or the band too wide",
            bad.frequency_hz, bad.residual, opts.residual_tolerance, bad.residual_floor
        )));
    }
    Ok(())
}

/// What the slices of one band solve share: the pencil, the options, the one symbolic
/// analysis, the first shift, the slices' edges, and the trace switch and clock.
struct Band<'a> {
    k: &'a SparseColMat<usize, f64>,
    m: &'a SparseColMat<usize, f64>,
    opts: &'a ModalOptions,
    symbolic: &'a SymbolicCholesky<usize>,
    /// The first slice's shift, below the spectrum.
    sigma: f64,
    /// The largest eigenvalue wanted, `(2 pi fmax)²`.
    lambda_max: f64,
    /// The slices' edges (`w²`).
    edges: Vec<f64>,
    trace: bool,
    started: Instant,
}

impl Band<'_> {
    /// Slice `s` (holding `count` modes when the Sturm counts were taken): its factor, its
    /// Lanczos run and the check of its result. Returns the slice, its modes and the seconds
    /// its factorisation took.
    fn run_slice(
        &self,
        s: usize,
        count: Option<usize>,
        first_matrix: &mut Option<SparseColMat<usize, f64>>,
    ) -> Result<(Slice, SliceResult, f64)> {
        let slice = self.slice(s);
        let t0 = Instant::now();
        let (l_values, kind) = self.factor_slice(s, &slice, first_matrix)?;
        let factor_seconds = t0.elapsed().as_secs_f64();
        let op = ShiftInvert {
            m: self.m,
            symbolic: self.symbolic,
            l_values,
            kind,
            plan: TreePlan::new(self.symbolic),
        };
        let res = solve_slice(
            self.k,
            self.m,
            op,
            &slice,
            count,
            self.opts,
            s,
            self.lambda_max.max(self.sigma.abs()),
        )?;
        self.check_slice(s, &slice, count, &res)?;
        Ok((slice, res, factor_seconds))
    }

    /// The number of eigenvalues below each edge (None when neither the check nor the slices
    /// need them); an error when none lies below the top edge.
    fn sturm_counts(&self) -> Result<Option<Vec<usize>>> {
        let (k, m, opts, edges) = (self.k, self.m, self.opts, &self.edges);
        let slices = opts.slices;
        // Sturm counts first (the same symbolic analysis; each LDLᵀ is freed before the next
        // factor is made): with the number of modes in each slice known, each iteration stops on
        // the block where the last of them converges. Several slices need the counts to
        // partition the band, so they are taken whatever `sturm_check` says.
        Ok(if opts.sturm_check || slices > 1 {
            let mut c = vec![0usize];
            for &edge in &edges[1..] {
                c.push(sturm_count_with(
                    &shifted(k, m, edge)?,
                    self.symbolic,
                    edge,
                )?);
            }
            if self.trace {
                eprintln!(
                    "trace: sturm counts {c:?} at {:.2} s{}",
                    self.started.elapsed().as_secs_f64(),
                    resident_note()
                );
            }
            if c[slices] == 0 {
                return Err(Error::Numerical(format!(
                    "no mode below {} Hz (Sturm count 0): raise --fmax-hz",
                    opts.fmax_hz
                )));
            }
            Some(c)
        } else {
            None
        })
    }

    /// Slice `s`: its shift and its edges.
    fn slice(&self, s: usize) -> Slice {
        let edges = &self.edges;
        // The first slice takes the shift below the spectrum (positive definite, L Lᵀ); the
        // others one in their middle (indefinite, L D Lᵀ: its inertia is not needed, the edge
        // counts are taken above).
        if s == 0 {
            Slice {
                sigma: self.sigma,
                lambda_lo: f64::NEG_INFINITY,
                lambda_hi: edges[1],
            }
        } else {
            Slice {
                sigma: 0.5 * (edges[s] + edges[s + 1]),
                lambda_lo: edges[s],
                lambda_hi: edges[s + 1],
            }
        }
    }

    /// The numeric factor of slice `s`'s shifted matrix and its kind; the first slice takes
    /// the matrix already built (`first_matrix`, left unused by an empty first slice), and the
    /// matrix is freed as soon as it is factored.
    fn factor_slice(
        &self,
        s: usize,
        slice: &Slice,
        first_matrix: &mut Option<SparseColMat<usize, f64>>,
    ) -> Result<(Vec<f64>, FactorKind)> {
        let sigma = self.sigma;
        // The first slice's matrix is already built (an empty first slice leaves it unused).
        let a_slice = match (s, first_matrix.take()) {
            (0, Some(first)) => first,
            _ => shifted(self.k, self.m, slice.sigma)?,
        };
        let kind = if s == 0 {
            FactorKind::Llt
        } else {
            FactorKind::Ldlt
        };
        let l_values = numeric_factor(&a_slice, self.symbolic, kind).map_err(|e| {
            if s == 0 {
                Error::Numerical(format!(
                    "Cholesky of K - sigma M (sigma = {sigma:.6e}) failed ({e}): K is not \
                         positive semi-definite or M not positive definite (inverted elements? \
                         negative density?)"
                ))
            } else {
                Error::Numerical(format!(
                    "LDLᵀ of K - sigma M at the shift of slice {} ({:.1} Hz) failed ({e}): \
                         the shift lies on an eigenvalue; change --slices",
                    s + 1,
                    slice.sigma.sqrt() / (2.0 * PI)
                ))
            }
        })?;
        drop(a_slice);
        Ok((l_values, kind))
    }

    /// Traces slice `s`'s result, and checks it found as many modes as the Sturm counts put in
    /// the slice (`count`, when taken).
    fn check_slice(
        &self,
        s: usize,
        slice: &Slice,
        count: Option<usize>,
        res: &SliceResult,
    ) -> Result<()> {
        let edges = &self.edges;
        if self.trace {
            eprintln!(
                "trace: slice {} ({:.1}..{:.1} Hz, shift {:.3e}): {} modes, basis {}, at {:.2} s",
                s + 1,
                edges[s].sqrt() / (2.0 * PI),
                edges[s + 1].sqrt() / (2.0 * PI),
                slice.sigma,
                res.modes.len(),
                res.basis,
                self.started.elapsed().as_secs_f64()
            );
        }
        if let Some(count) = count {
            if count != res.modes.len() {
                return Err(Error::Numerical(format!(
                    "the Sturm counts find {count} eigenvalues in {:.1}..{:.1} Hz but Lanczos \
                     returned {} modes (basis {}, {} blocks of {}): raise the basis limit or \
                     split the band (--slices)",
                    edges[s].sqrt() / (2.0 * PI),
                    edges[s + 1].sqrt() / (2.0 * PI),
                    res.modes.len(),
                    res.basis,
                    res.blocks,
                    self.opts.block_size
                )));
            }
        }
        Ok(())
    }
}
