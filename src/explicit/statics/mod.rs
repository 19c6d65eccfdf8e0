//! Static equilibrium of the engine's model by Newton's method, with a sparse Cholesky of the
//! tangent (faer): the implicit static preload the paper uses before its explicit run
//! (docs/physics.md, "Static preload"), and the fast alternative to dynamic relaxation
//! ([`super::preload`]).
//!
//! Unknowns `q`: the engine's constraints as a linear map `u = T q` ([`dofs`]); rigid bodies
//! translate and keep their orientation.
//!
//! Residual: `R(q) = Tᵀ (f_ext - f_int(u) + f_aux(u))`, the very forces the time step
//! integrates (`Solver::gather_forces`, velocities zero), so the equilibrium found is the one
//! the explicit run starts from.
//!
//! Tangent: `K_T = Tᵀ (K_el + K_springs + sum_j k_j b_j b_jᵀ) T + m omega_r^2`: the elements'
//! linearised stiffness at the reference state ([`super::linearised`]), the springs, the rank-one
//! terms of the auxiliary forces (penalty contact of the active slaves,
//! [`super::aux::RankOneStiffness`]), and a regularisation `m omega_r^2` with
//! `omega_r = 2 pi regularisation_hz`, so that a body not yet in contact (a wheelset hanging
//! over its rail) has a finite, capped step instead of a singular matrix.
//!
//! Iteration (modified Newton): `dq = K_T⁻¹ R`; a step the regularisation carries (a falling
//! body) is scaled down so that no node moves more than `max_increment_m`. A body that nothing
//! holds yet is brought down by its translation alone, without a solve ([`approach`]). The
//! factor is
//! kept while the rank-one terms (the contact's active set) stay the same: the rest of `K_T`
//! does not change. Terms left out of `K_T` (geometric stiffness, the contact normal's
//! rotation, the regularisation) only slow the convergence, which is linear at their relative
//! size; the converged state is exact to the tolerance, since the residual is the full one.
//! Measured: 3 iterations on the demo rolling model, where rotations are ~1e-4; about 45 on a
//! slender cantilever bent to a 5.6e-3 rad tip rotation to 1e-10, where the membrane forces of
//! the rotation (`E A theta^2 / 2`, several times the load) are corrected only through the
//! linear tangent. Converged:
//! `|R| / (|f_int| + |f_ext|) < tolerance` over the unknowns (`Solver::residual_norms`'s
//! measure, the one dynamic relaxation stops on).

mod approach;
mod assembly;
mod dofs;
mod element_assembly;
mod forcing;
mod stiffness;

use std::time::Instant;

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::cholesky::{LltRef, SymbolicCholesky};
use faer::{MatMut, Par};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::aux::RankOneStiffness;
use super::model::Elements;
use super::run::StopFlag;
use super::solver::{AuxForces, Solver};
use crate::linalg::factor::{numeric_factor, symbolic_pencil, FactorKind};
use crate::linalg::iterative::{
    conjugate_gradients, BlockMatrix, PcgOptions, TwoLevel, TwoLevelOptions,
};
use crate::mesh::P3;
use crate::{Error, Result};
use approach::Bodies;
use assembly::{
    assemble, base_keys, term_keys, term_signature, update_terms, widened_contact_keys,
};
use dofs::ReducedDofs;
use stiffness::Tangent;

/// Options of the static solve.
#[derive(Clone, Debug)]
pub struct StaticOptions {
    /// Relative residual to reach.
    pub tolerance: f64,
    /// Most Newton iterations (each one force evaluation and one solve).
    pub max_iterations: usize,
    /// Largest displacement increment of any node in an iteration whose step the
    /// regularisation carries (over half the residual): a body falling onto its support (m).
    pub max_increment_m: f64,
    /// Regularisation frequency `omega_r / 2 pi` (Hz), well below the model's lowest static
    /// mode (its convergence factor is `(f_r / f_1)^2`).
    pub regularisation_hz: f64,
    /// Directions of each rigid body's translation held besides its prescribed ones (a body
    /// with no stiffness in a direction, e.g. a wheelset along a frictionless rail).
    pub held_rigid_translations: Vec<[bool; 3]>,
    /// Memory the factorisation may use (bytes); None: what the system reports available
    /// (`MemAvailable`), when it reports it.
    pub memory_limit_bytes: Option<u64>,
    /// How each Newton step's linear system is solved.
    pub linear_solver: LinearSolver,
    /// Move bodies that nothing holds yet (no contact, no support) by their rigid translation,
    /// without a linear solve, while that translation exceeds `max_increment_m` ([`approach`]);
    /// off: every step is a solve of the full tangent, scaled down as needed.
    pub approach_steps: bool,
    /// Print one line per iteration to standard error.
    pub trace: bool,
    /// Give up with [`Error::Interrupted`] when set.
    pub stop: StopFlag,
}

impl Default for StaticOptions {
    fn default() -> Self {
        StaticOptions {
            tolerance: 1e-6,
            max_iterations: 60,
            max_increment_m: 2e-4,
            regularisation_hz: 0.1,
            held_rigid_translations: Vec::new(),
            memory_limit_bytes: None,
            linear_solver: LinearSolver::Direct,
            approach_steps: true,
            trace: false,
            stop: StopFlag::new(),
        }
    }
}

/// How the Newton steps' linear systems `K_T dq = R` are solved.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LinearSolver {
    /// Sparse Cholesky (faer): exact, with a factor whose memory grows fastest with the model.
    #[default]
    Direct,
    /// Conjugate gradients with the two-level aggregation preconditioner
    /// ([`crate::linalg::iterative`]): memory linear in the model, for models whose factor does not
    /// fit. Each step is solved to its forcing term ([`forcing_term`]: between
    /// [`LINEAR_TOLERANCE`] and [`FORCING_MAX`], tighter as the residual falls faster); the
    /// converged state is the direct solver's to the Newton tolerance.
    Iterative,
}

pub use forcing::{forcing_term, FORCING_MAX, LINEAR_TOLERANCE};

/// What the static solve did.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StaticReport {
    /// Newton iterations (solves).
    pub iterations: usize,
    /// Numeric factorisations.
    pub factorisations: usize,
    /// Symbolic analyses (one per new sparsity pattern).
    pub symbolic_analyses: usize,
    /// Final relative residual.
    pub relative_residual: f64,
    /// Unknowns of the reduced problem.
    pub unknowns: usize,
    /// Entries of the Cholesky factor (the iterative solver: of its coarse matrix's factor).
    pub factor_entries: usize,
    /// Rank-one (contact) terms in the last tangent.
    pub contact_terms: usize,
    /// Energy stored at equilibrium (J).
    pub stored_energy_j: f64,
    /// Per rigid body: the force that holds its held and prescribed translations (N).
    pub held_reactions_n: Vec<P3>,
    /// Wall time (s): total, and the share of the factorisations.
    pub seconds: f64,
    /// Seconds spent in assembly, symbolic analyses and numeric factorisations (the
    /// factorisations' share includes the other two).
    pub factor_seconds: f64,
    /// Seconds of assembly.
    pub assembly_seconds: f64,
    /// Seconds of symbolic analyses.
    pub symbolic_seconds: f64,
    /// The linear solver used.
    #[serde(default)]
    pub linear_solver: LinearSolver,
    /// Iterative solver: conjugate gradient iterations over all Newton steps.
    #[serde(default)]
    pub cg_iterations: usize,
    /// Iterative solver: coarse unknowns of the last preconditioner.
    #[serde(default)]
    pub coarse_unknowns: usize,
    /// Iterative solver: preconditioners set up (the others were kept from a previous step).
    #[serde(default)]
    pub preconditioner_setups: usize,
    /// Iterations that moved free bodies by their translation alone, without a solve
    /// ([`StaticOptions::approach_steps`]).
    #[serde(default)]
    pub approach_steps: usize,
}

/// The factorisation in use, or the iterative solver's matrix and preconditioner.
enum Factor {
    Cholesky {
        symbolic: SymbolicCholesky<usize>,
        l_values: Vec<f64>,
    },
    Iterative {
        matrix: BlockMatrix,
        preconditioner: Box<TwoLevel>,
        /// Contact terms in the tangent the preconditioner was made from.
        preconditioner_contact_terms: usize,
        /// Whether the preconditioner was made from this matrix.
        fresh: bool,
    },
}

/// Solves for static equilibrium under the model's loads (gravity, nodal loads, springs, the
/// auxiliary forces at the current time). Time does not advance; velocities end at zero and
/// the energy bookkeeping restarts from the equilibrium.
///
/// Each iteration ([`Newton`]): the residual and its convergence test; an approach step for
/// bodies nothing holds yet; else the tangent (re)built and factored when the contact's active
/// set changed; the linear solve; the increment, capped where the regularisation carries it.
pub fn solve_static<A: AuxForces + ?Sized>(
    solver: &mut Solver,
    aux: &mut A,
    opts: &StaticOptions,
) -> Result<StaticReport> {
    let start = Instant::now();
    check_options(opts)?;
    if !matches!(solver.model.elements, Elements::OnePoint(_)) || solver.model.viscous_hourglass {
        return Err(Error::input(
            "static solve",
            "formulation",
            "the static solve needs the one-point element with stiffness hourglass control",
        ));
    }
    solver.v.iter_mut().for_each(|v| *v = [0.0; 3]);
    solver.zero_rigid_velocities();
    let dofs = ReducedDofs::new(solver, &opts.held_rigid_translations)?;
    let mut newton = Newton::new(solver, &dofs, opts);
    let (t0, dt) = (solver.time_s, solver.dt_s);
    loop {
        solver.gather_forces(aux, t0, dt);
        let Some(relative) = newton.residual_or_done(solver, &dofs, opts, start)? else {
            break;
        };
        newton.terms.clear();
        aux.stiffness_terms(&mut newton.terms);
        if newton.approach_step(solver, &dofs, opts) {
            continue;
        }
        newton.update_factor(solver, &dofs, opts)?;
        newton.solve_increment(solver, &dofs, opts, relative)?;
        newton.apply_increment(solver, &dofs, opts, relative);
    }
    Ok(newton.finish(solver, &dofs, start))
}

/// The state of the Newton iteration of [`solve_static`] between its phases.
struct Newton {
    /// Unknowns (reduced nodes, 3 each).
    n: usize,
    /// The element and spring pattern, kept between iterations.
    element_keys: Vec<u64>,
    residual: Vec<f64>,
    /// The residual with held directions zeroed: the right-hand side of every solve.
    rhs: Vec<f64>,
    increment: Vec<f64>,
    terms: Vec<RankOneStiffness>,
    tangent: Option<Tangent>,
    /// The rank-one terms in the tangent's values (None: nothing assembled yet).
    assembled_terms: Option<Vec<RankOneStiffness>>,
    factor: Option<Factor>,
    /// The rank-one terms' nodes in the factor in use: a factor is reused only on the same
    /// active set (a slave that came into contact since has no stiffness in it, and the step
    /// would let its body fly off on the regularisation).
    factor_signature: Vec<[usize; 5]>,
    /// The previous iteration's relative residual (the forcing terms follow its fall).
    previous_relative: Option<f64>,
    omega_r2: f64,
    bodies: Option<Bodies>,
    report: StaticReport,
}

impl Newton {
    fn new(solver: &Solver, dofs: &ReducedDofs, opts: &StaticOptions) -> Newton {
        let n = dofs.len();
        let omega_r2 = (2.0 * std::f64::consts::PI * opts.regularisation_hz).powi(2);
        Newton {
            n,
            element_keys: base_keys(solver, dofs),
            residual: vec![0.0; 3 * n],
            rhs: vec![0.0; 3 * n],
            increment: vec![0.0; 3 * n],
            terms: Vec::new(),
            tangent: None,
            assembled_terms: None,
            factor: None,
            factor_signature: Vec::new(),
            previous_relative: None,
            omega_r2,
            bodies: opts
                .approach_steps
                .then(|| Bodies::new(solver, dofs, omega_r2, opts.max_increment_m)),
            report: StaticReport {
                iterations: 0,
                factorisations: 0,
                symbolic_analyses: 0,
                relative_residual: f64::INFINITY,
                unknowns: dofs.held.iter().flatten().filter(|h| !**h).count(),
                factor_entries: 0,
                contact_terms: 0,
                stored_energy_j: 0.0,
                held_reactions_n: Vec::new(),
                seconds: 0.0,
                factor_seconds: 0.0,
                assembly_seconds: 0.0,
                symbolic_seconds: 0.0,
                linear_solver: opts.linear_solver,
                cg_iterations: 0,
                coarse_unknowns: 0,
                preconditioner_setups: 0,
                approach_steps: 0,
            },
        }
    }

    /// The residual of the gathered forces and its relative size; None when it is below the
    /// tolerance (converged). A non-finite residual, a stop request or the iteration limit
    /// end the solve with an error.
    fn residual_or_done(
        &mut self,
        solver: &Solver,
        dofs: &ReducedDofs,
        opts: &StaticOptions,
        start: Instant,
    ) -> Result<Option<f64>> {
        let reference = dofs.residual(solver, &mut self.residual);
        for ((b, r), h) in self
            .rhs
            .iter_mut()
            .zip(&self.residual)
            .zip(dofs.held.iter().flatten())
        {
            *b = if *h { 0.0 } else { *r };
        }
        let report = &mut self.report;
        let free_norm = self.rhs.iter().map(|r| r * r).sum::<f64>().sqrt();
        if !free_norm.is_finite() {
            return Err(Error::Numerical(format!(
                "static solve diverged after {} iterations (non-finite residual)",
                report.iterations
            )));
        }
        let relative = free_norm / reference.max(1e-300);
        report.relative_residual = relative;
        if opts.trace {
            eprintln!(
                "static iteration {}: relative residual {relative:.3e}, {} contact terms, {} \
                 factorisations; {:.1} s (assembly {:.1}, symbolic {:.1}, all factor work {:.1})",
                report.iterations,
                report.contact_terms,
                report.factorisations,
                start.elapsed().as_secs_f64(),
                report.assembly_seconds,
                report.symbolic_seconds,
                report.factor_seconds
            );
        }
        if relative < opts.tolerance {
            return Ok(None);
        }
        if opts.stop.is_requested() {
            return Err(Error::Interrupted(format!(
                "stopped on request during the static solve (the implicit preload), after {} \
                 iterations; it keeps no checkpoint: start the run again (without --resume)",
                report.iterations
            )));
        }
        if report.iterations >= opts.max_iterations {
            return Err(Error::Numerical(format!(
                "static solve did not converge in {} iterations: relative residual {relative:.3e} \
                 (tolerance {:.1e}), {} contact terms at the end; raise the iteration limit, or \
                 use dynamic relaxation (preload.method = \"dynamic_relaxation\")",
                report.iterations, opts.tolerance, report.contact_terms
            )));
        }
        Ok(Some(relative))
    }

    /// Moves the free bodies by their translation alone, without a solve, while that is
    /// longer than the step cap ([`approach`]); whether it did.
    fn approach_step(
        &mut self,
        solver: &mut Solver,
        dofs: &ReducedDofs,
        opts: &StaticOptions,
    ) -> bool {
        let approach = self.bodies.as_ref().and_then(|b| {
            b.approach_step(solver, dofs, &self.terms, &self.rhs, &mut self.increment)
        });
        let Some(step) = approach else {
            return false;
        };
        if opts.trace {
            eprintln!(
                "  approach step: free bodies {}, the fastest would move {:.3e} m; moved \
                 {:.1e} m by their translation, without a solve",
                step.bodies_moved, step.free_translation_m, opts.max_increment_m
            );
        }
        dofs.apply_increment(solver, &self.increment);
        // Not a Newton step: the next forcing term starts afresh (as after a capped step).
        self.previous_relative = None;
        self.report.iterations += 1;
        self.report.approach_steps += 1;
        true
    }

    /// The tangent and its factor (or preconditioner), made again when the contact's active
    /// set changed: a new pattern (and symbolic analysis) only when a contact term falls
    /// outside the pattern, else new values of the rank-one terms on the same pattern.
    fn update_factor(
        &mut self,
        solver: &Solver,
        dofs: &ReducedDofs,
        opts: &StaticOptions,
    ) -> Result<()> {
        let signature = term_signature(&self.terms);
        if self.factor.is_some() && signature == self.factor_signature {
            return Ok(());
        }
        let t = Instant::now();
        self.factor_signature = signature;
        self.report.contact_terms = self.terms.len();
        let contact_keys = term_keys(solver, dofs, &self.terms);
        let rebuild = match &self.tangent {
            None => true,
            Some(tg) => contact_keys.iter().any(|&k| !tg.contains(k)),
        };
        if rebuild {
            let mut keys = self.element_keys.clone();
            keys.extend_from_slice(&contact_keys);
            if !self.terms.is_empty() {
                // Room for the active set to grow by a ring of nodes without a new symbolic
                // analysis: a slave next to a contact slave meets a face next to the contact
                // faces.
                keys.extend(widened_contact_keys(
                    &self.element_keys,
                    self.n,
                    solver,
                    dofs,
                    &self.terms,
                ));
            }
            keys.par_sort_unstable();
            keys.dedup();
            self.tangent = Some(Tangent::from_keys(self.n, &keys));
            if opts.linear_solver == LinearSolver::Direct {
                // A new pattern needs a new symbolic analysis; the iterative solver's
                // aggregates stay (they follow the elements, which do not change).
                self.factor = None;
            }
        }
        let Some(tg) = self.tangent.as_mut() else {
            unreachable!("the tangent was built above")
        };
        let ta = Instant::now();
        match self.assembled_terms.as_deref() {
            // The same pattern: only the rank-one terms change.
            Some(old) if !rebuild => update_terms(solver, dofs, old, &self.terms, tg),
            _ => assemble(solver, dofs, &self.terms, opts.regularisation_hz, tg),
        }
        self.assembled_terms = Some(self.terms.clone());
        self.report.assembly_seconds += ta.elapsed().as_secs_f64();
        let report = &mut self.report;
        self.factor = Some(match opts.linear_solver {
            LinearSolver::Direct => {
                direct_factor(tg, self.factor.take(), opts.memory_limit_bytes, report)?
            }
            LinearSolver::Iterative => iterative_factor(
                solver,
                dofs,
                tg,
                self.factor.take(),
                TangentChange {
                    pattern_changed: rebuild,
                    contact_terms: self.terms.len(),
                },
                opts,
                report,
            )?,
        });
        report.factorisations += 1;
        report.factor_seconds += t.elapsed().as_secs_f64();
        Ok(())
    }

    /// Solves `K_T dq = R` for the increment: with the factor, or by conjugate gradients to
    /// the forcing term (a kept preconditioner that no longer fits is made again once).
    fn solve_increment(
        &mut self,
        solver: &Solver,
        dofs: &ReducedDofs,
        opts: &StaticOptions,
        relative: f64,
    ) -> Result<()> {
        let Some(f) = self.factor.as_mut() else {
            unreachable!("a factor was made above")
        };
        let (rhs, increment, report) = (&self.rhs, &mut self.increment, &mut self.report);
        match f {
            Factor::Cholesky { symbolic, l_values } => {
                increment.copy_from_slice(rhs);
                solve(symbolic, l_values, increment);
            }
            Factor::Iterative {
                matrix,
                preconditioner,
                preconditioner_contact_terms,
                fresh,
            } => {
                let cg_start = Instant::now();
                let cg_options = PcgOptions {
                    tolerance: forcing_term(relative, self.previous_relative, opts.tolerance),
                    max_iterations: CG_ITERATIONS,
                };
                increment.iter_mut().for_each(|v| *v = 0.0);
                let mut pcg = conjugate_gradients(
                    matrix,
                    rhs,
                    increment,
                    preconditioner.as_mut(),
                    &cg_options,
                );
                if pcg.is_err() && !*fresh {
                    // A kept preconditioner that no longer fits: a new one, and again.
                    *preconditioner = new_preconditioner(solver, dofs, matrix, opts, report)?;
                    *preconditioner_contact_terms = self.terms.len();
                    *fresh = true;
                    increment.iter_mut().for_each(|v| *v = 0.0);
                    pcg = conjugate_gradients(
                        matrix,
                        rhs,
                        increment,
                        preconditioner.as_mut(),
                        &cg_options,
                    );
                }
                let pcg = pcg.map_err(|e| {
                    Error::Numerical(format!(
                        "static solve, Newton iteration {}: {e}; use the direct solver or \
                         dynamic relaxation",
                        report.iterations + 1
                    ))
                })?;
                report.cg_iterations += pcg.iterations;
                if opts.trace {
                    let st = preconditioner.stats();
                    eprintln!(
                        "  conjugate gradients: {} iterations to {:.2e} (asked {:.2e}), {:.1} s \
                         (preconditioner so far: smoothing {:.1} s, coarse correction {:.1} s)",
                        pcg.iterations,
                        pcg.relative_residual,
                        cg_options.tolerance,
                        cg_start.elapsed().as_secs_f64(),
                        st.smoothing_seconds,
                        st.coarse_seconds
                    );
                }
            }
        }
        Ok(())
    }

    /// Applies the increment. A step the regularisation carries (a body with nothing under it
    /// yet) is as long as `g / omega_r^2`: it is capped. It is recognised by its energy:
    /// `dqᵀ M omega_r^2 dq` over half of `dqᵀ R = dqᵀ K_T dq`. A step the stiffness carries is
    /// a Newton step: kept.
    fn apply_increment(
        &mut self,
        solver: &mut Solver,
        dofs: &ReducedDofs,
        opts: &StaticOptions,
        relative: f64,
    ) {
        let (n, increment) = (self.n, &mut self.increment);
        let (mut regularisation_energy, mut step_energy) = (0.0, 0.0);
        for r in 0..n {
            for i in 0..3 {
                let d = increment[3 * r + i];
                regularisation_energy += dofs.mass_kg[r] * self.omega_r2 * d * d;
                step_energy += d * self.rhs[3 * r + i];
            }
        }
        if opts.trace {
            let length = |r: usize| {
                (0..3)
                    .map(|i| increment[3 * r + i].powi(2))
                    .sum::<f64>()
                    .sqrt()
            };
            let at = (0..n)
                .max_by(|&a, &b| length(a).total_cmp(&length(b)))
                .unwrap_or(0);
            let largest = length(at);
            eprintln!(
                "  step: largest node increment {largest:.3e} m at reduced node {at} (mesh node \
                 {:?}, {:?}); energy {step_energy:.3e} J, of which the regularisation's \
                 {regularisation_energy:.3e} J",
                dofs.free_nodes
                    .get(at)
                    .map(|&nd| (nd, solver.model.mesh.nodes[nd])),
                &increment[3 * at..3 * at + 3]
            );
        }
        let capped = regularisation_energy > 0.5 * step_energy
            && cap_increment(increment, opts.max_increment_m);
        dofs.apply_increment(solver, increment);
        // A capped step is no Newton step: the residual's fall across it says nothing of the
        // iteration's convergence, so the next forcing term starts afresh, as the first does.
        self.previous_relative = if capped { None } else { Some(relative) };
        self.report.iterations += 1;
    }

    /// The report at equilibrium: the reactions of held rigid translations (the out-of-balance
    /// force the constraint takes) and the stored energy; velocities zeroed and the energy
    /// bookkeeping restarted.
    fn finish(mut self, solver: &mut Solver, dofs: &ReducedDofs, start: Instant) -> StaticReport {
        let free = dofs.free_nodes.len();
        let residual = &self.residual;
        self.report.held_reactions_n = (0..solver.rigid.len())
            .map(|b| {
                std::array::from_fn(|i| {
                    if dofs.held[free + b][i] {
                        -residual[3 * (free + b) + i]
                    } else {
                        0.0
                    }
                })
            })
            .collect();
        let (el, _) = solver.element_energy();
        self.report.stored_energy_j = el.strain_j + el.hourglass_j + solver.spring_energy_j();
        solver.v.iter_mut().for_each(|v| *v = [0.0; 3]);
        solver.zero_rigid_velocities();
        solver.rebase_energy();
        self.report.seconds = start.elapsed().as_secs_f64();
        self.report
    }
}

fn check_options(opts: &StaticOptions) -> Result<()> {
    let checks = [
        ("tolerance", opts.tolerance, 1.0, "(0, 1)"),
        (
            "max_increment_m",
            opts.max_increment_m,
            f64::INFINITY,
            "> 0",
        ),
        (
            "regularisation_hz",
            opts.regularisation_hz,
            f64::INFINITY,
            "> 0",
        ),
    ];
    for (field, value, upper, range) in checks {
        if !(value > 0.0 && value < upper) {
            return Err(Error::input(
                "static solve",
                field,
                format!("must lie in {range} (got {value})"),
            ));
        }
    }
    if opts.max_iterations == 0 {
        return Err(Error::input(
            "static solve",
            "max_iterations",
            "must be at least 1",
        ));
    }
    Ok(())
}

/// Refuses a factorisation that would not fit: its values, the numeric phase's work space and
/// `extra_bytes` (copies of the matrix) against `limit` (or the system's available memory),
/// before anything is allocated.
fn check_factor_memory(
    symbolic: &SymbolicCholesky<usize>,
    extra_bytes: usize,
    limit: Option<u64>,
) -> Result<()> {
    let scratch = symbolic
        .factorize_numeric_llt_scratch::<f64>(Par::rayon(0), Default::default())
        .size_bytes();
    let need = (symbolic.len_val() * std::mem::size_of::<f64>() + scratch + extra_bytes) as u64;
    let Some(available) = limit.or_else(available_memory_bytes) else {
        return Ok(());
    };
    if need > available {
        let gb = |b: u64| b as f64 / 1e9;
        return Err(Error::Numerical(format!(
            "the static tangent's Cholesky factor needs {:.1} GB ({} entries) and {:.1} GB of \
             memory is available: use dynamic relaxation for this model \
             (preload.method = \"dynamic_relaxation\" in the case, or --preload dynamic-relaxation)",
            gb(need),
            symbolic.len_val(),
            gb(available)
        )));
    }
    Ok(())
}

/// `MemAvailable` of /proc/meminfo (bytes), where the system has it.
fn available_memory_bytes() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// Most conjugate gradient iterations of one Newton step (the demo model's steps take tens).
const CG_ITERATIONS: usize = 5000;

/// The Cholesky factor of the tangent (its symbolic analysis from `previous` when it has one).
fn direct_factor(
    tg: &Tangent,
    previous: Option<Factor>,
    memory_limit_bytes: Option<u64>,
    report: &mut StaticReport,
) -> Result<Factor> {
    let a = tg.matrix()?;
    let symbolic = match previous {
        Some(Factor::Cholesky { symbolic, .. }) => symbolic,
        _ => {
            let ts = Instant::now();
            report.symbolic_analyses += 1;
            let symbolic = symbolic_pencil(&a)?;
            report.symbolic_seconds += ts.elapsed().as_secs_f64();
            // The matrix is copied once more into the factorisation's input.
            let matrix_bytes =
                a.val().len() * (std::mem::size_of::<f64>() + std::mem::size_of::<usize>());
            check_factor_memory(&symbolic, matrix_bytes, memory_limit_bytes)?;
            symbolic
        }
    };
    let l_values = numeric_factor(&a, &symbolic, FactorKind::Llt).map_err(|e| {
        Error::Numerical(format!(
            "Cholesky factorisation of the static tangent failed ({e}): the model has a free \
             motion no constraint, spring or contact holds"
        ))
    })?;
    report.factor_entries = symbolic.len_val();
    Ok(Factor::Cholesky { symbolic, l_values })
}

/// What the tangent of a new factor is, against the previous one's.
struct TangentChange {
    /// A new pattern (the contact reached nodes outside the reserved ring): the block matrix is
    /// built anew; otherwise its values are refilled in place.
    pattern_changed: bool,
    /// Rank-one (contact) terms in the tangent.
    contact_terms: usize,
}

/// The tangent as a block matrix and its two-level preconditioner (coordinates: the reduced
/// nodes' current positions, a rigid body's at its centre).
///
/// A previous preconditioner is kept while the contact holds: once the tangent it was made
/// from had contact terms, a new contact set changes the matrix only near the patch, which the
/// conjugate gradients (run on the new matrix) absorb in a few iterations, where a new set-up
/// (coarse factor, smoother) costs the time of many (`paper`: 15 s against 1.2 s an
/// iteration). One made without contact (a wheel held by the regularisation alone) is made
/// anew once contact appears: it does not know the wheel rests on the rail. A solve that fails
/// with a kept preconditioner is retried with a new one (see the Newton loop).
fn iterative_factor(
    solver: &Solver,
    dofs: &ReducedDofs,
    tg: &Tangent,
    previous: Option<Factor>,
    change: TangentChange,
    opts: &StaticOptions,
    report: &mut StaticReport,
) -> Result<Factor> {
    // The previous matrix goes before a new one is made (or is refilled, on the same
    // pattern); its preconditioner may stay.
    let (kept, previous_matrix) = match previous {
        Some(Factor::Iterative {
            matrix,
            preconditioner,
            preconditioner_contact_terms,
            ..
        }) => {
            let matrix = if change.pattern_changed {
                drop(matrix);
                None
            } else {
                Some(matrix)
            };
            let kept = (preconditioner_contact_terms > 0 && change.contact_terms > 0)
                .then_some((preconditioner, preconditioner_contact_terms));
            (kept, matrix)
        }
        other => {
            drop(other);
            (None, None)
        }
    };
    let conversion = Instant::now();
    let matrix = match previous_matrix {
        Some(mut matrix) => {
            matrix.refill(|r, c| tg.block(r, c))?;
            matrix
        }
        None => {
            // The pattern first, then the values gathered in parallel (no copy of the lower
            // blocks, no serial scatter of 72-byte blocks).
            let (col_ptr, rows) = tg.lower_pattern();
            let mut matrix = BlockMatrix::from_lower_pattern(dofs.len(), col_ptr, rows)?;
            matrix.refill(|r, c| tg.block(r, c))?;
            matrix
        }
    };
    if opts.trace {
        eprintln!(
            "  block matrix from the tangent: {:.2} s",
            conversion.elapsed().as_secs_f64()
        );
    }
    let (preconditioner, preconditioner_contact_terms, fresh) = match kept {
        Some(k) if k.0.nodes() == matrix.nodes() => (k.0, k.1, false),
        _ => (
            new_preconditioner(solver, dofs, &matrix, opts, report)?,
            change.contact_terms,
            true,
        ),
    };
    let stats = preconditioner.stats();
    report.coarse_unknowns = stats.coarse_unknowns;
    report.factor_entries = stats.coarse_factor_entries;
    Ok(Factor::Iterative {
        matrix,
        preconditioner,
        preconditioner_contact_terms,
        fresh,
    })
}

/// A two-level preconditioner of `matrix`.
fn new_preconditioner(
    solver: &Solver,
    dofs: &ReducedDofs,
    matrix: &BlockMatrix,
    opts: &StaticOptions,
    report: &mut StaticReport,
) -> Result<Box<TwoLevel>> {
    let mesh = &solver.model.mesh.nodes;
    let mut coords: Vec<P3> = dofs
        .free_nodes
        .iter()
        .map(|&nd| std::array::from_fn(|i| mesh[nd][i] + solver.u[nd][i]))
        .collect();
    coords.extend(solver.rigid.iter().map(|b| b.centre_m));
    let p = TwoLevel::new(matrix, &coords, &dofs.held, &TwoLevelOptions::default())?;
    report.preconditioner_setups += 1;
    if opts.trace {
        eprintln!("  two-level preconditioner: {:?}", p.stats());
    }
    Ok(Box::new(p))
}

/// `x <- K_T⁻¹ x` with the factor.
fn solve(symbolic: &SymbolicCholesky<usize>, l_values: &[f64], x: &mut [f64]) {
    let n = x.len();
    let mut mem = MemBuffer::new(symbolic.solve_in_place_scratch::<f64>(1, Par::Seq));
    let rhs = MatMut::from_column_major_slice_mut(x, n, 1);
    LltRef::<usize, f64>::new(symbolic, l_values).solve_in_place_with_conj(
        faer::Conj::No,
        rhs,
        Par::Seq,
        MemStack::new(&mut mem),
    );
}

/// Scales the increment so that no reduced node moves more than `limit_m`; true if it did.
fn cap_increment(dq: &mut [f64], limit_m: f64) -> bool {
    let largest = dq
        .chunks(3)
        .map(|d| (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt())
        .fold(0.0f64, f64::max);
    if largest > limit_m {
        let s = limit_m / largest;
        dq.iter_mut().for_each(|x| *x *= s);
        return true;
    }
    false
}
