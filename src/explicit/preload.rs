//! Static preload by dynamic relaxation.
//!
//! The model is integrated with mass-proportional damping `alpha` set near critical for its
//! lowest active mode, `alpha = 2 omega_1`. `omega_1` is estimated from the Rayleigh quotient of
//! the current displacement, `omega^2 ~ (u . f_int) / (u . M u)`, which the slowest mode
//! dominates as the relaxation converges (Underwood's adaptive dynamic relaxation); `alpha` is
//! kept above `min_damping_per_s`, since a body in flight over a one-sided contact shows no
//! stiffness and the estimate would collapse, letting it bounce for ever. It stops
//! when the out-of-balance force `|f_ext - f_int|` falls below `tolerance x |f_ext|`; then the
//! velocities are zeroed and the energy bookkeeping restarts, so that the energy balance of the
//! run that follows starts at zero.

// Index loops mirror the tensor notation of the equations (the project's style for kernels);
// `!(x > 0.0)` is meant: it also rejects NaN.
#![allow(clippy::needless_range_loop, clippy::neg_cmp_op_on_partial_ord)]

use serde::{Deserialize, Serialize};

use super::run::StopFlag;
use super::solver::{AuxForces, Solver};
use crate::mesh::P3;
use crate::{Error, Result};

/// Largest `alpha dt` used. The damping force `-alpha m v_{n-1/2}` lags half a step, and the
/// central-difference recurrence `x+ - 2x + x- = -(w h)^2 x - alpha h (x - x-)` is stable only
/// while `(w h)^2 <= 4 - 2 alpha h`. The engine runs at `w_max h <= 1.8` (0.9 of the critical
/// step), so `alpha h <= 0.38`; 0.1 keeps a margin for an underestimated `w_max` (e.g. a stiff
/// contact penalty) since `w h <= 1.95` remains stable.
const MAX_ALPHA_DT: f64 = 0.1;

/// Options of the relaxation.
#[derive(Clone, Debug)]
pub struct PreloadOptions {
    /// Relative residual `|f_ext - f_int| / |f_ext|` to reach.
    pub tolerance: f64,
    /// Step limit.
    pub max_steps: u64,
    /// Damping re-estimated every this many steps.
    pub adapt_every_steps: u64,
    /// Smallest damping coefficient (1/s), `2 x 2 pi x` the lowest frequency expected to matter.
    pub min_damping_per_s: f64,
    /// A fixed damping coefficient (1/s) instead of the adaptive one. Use it with contact: the
    /// penalty springs dominate the Rayleigh quotient of the increments, and the estimate then
    /// damps the slow mode (the body settling on its contact) far too much to converge.
    pub fixed_damping_per_s: Option<f64>,
    /// Return an error when the tolerance is not reached (else a report with
    /// `converged: false`, for runs that accept a partly relaxed start).
    pub require_convergence: bool,
    /// Leave the velocities as they are at the end, so that a relaxation done in stages (with
    /// changes between them) goes on as one; by default the model is stopped.
    pub keep_velocities: bool,
    /// Give up with [`Error::Interrupted`] when set (the relaxation has no checkpoint).
    pub stop: StopFlag,
}

impl Default for PreloadOptions {
    fn default() -> Self {
        PreloadOptions {
            tolerance: 1e-4,
            max_steps: 200_000,
            adapt_every_steps: 100,
            // Critical damping of a 20 Hz mode (a wheel bouncing on its track is ~50-100 Hz).
            min_damping_per_s: 2.0 * 2.0 * std::f64::consts::PI * 20.0,
            fixed_damping_per_s: None,
            require_convergence: true,
            keep_velocities: false,
            stop: StopFlag::new(),
        }
    }
}

/// Result of the relaxation.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct PreloadReport {
    /// Steps taken.
    pub steps: u64,
    /// Final relative residual.
    pub relative_residual: f64,
    /// Last damping coefficient used (1/s).
    pub damping_per_s: f64,
    /// Energy stored at equilibrium (J), booked as preload work.
    pub stored_energy_j: f64,
    /// Whether the tolerance was reached.
    pub converged: bool,
}

/// Relaxes the model to static equilibrium under its loads (gravity, nodal loads, springs,
/// auxiliary forces held at the current time). Time does not advance.
pub fn relax<A: AuxForces + ?Sized>(
    solver: &mut Solver,
    aux: &mut A,
    opts: PreloadOptions,
) -> Result<PreloadReport> {
    let saved_alpha = solver.model.mass_damping_per_s;
    let t0 = solver.time_s;
    let step0 = solver.step;
    // Start with damping for a 1 kHz mode; adapted below.
    let mut alpha = opts
        .fixed_damping_per_s
        .unwrap_or(2.0 * 2.0 * std::f64::consts::PI * 1000.0)
        .min(MAX_ALPHA_DT / solver.dt_s);
    let mut residual = f64::INFINITY;
    let mut steps = 0;
    // Rayleigh quotient on increments between adaptations, so constant loads cancel:
    // omega^2 ~ (du . d(f_int - f_aux)) / (du . M du).
    let mut previous: Option<(Vec<P3>, Vec<P3>)> = None;
    while steps < opts.max_steps {
        if opts.stop.is_requested() {
            solver.model.mass_damping_per_s = saved_alpha;
            return Err(Error::Interrupted(format!(
                "stopped on request during the static preload, after {steps} steps of a stage; \
                 the preload keeps no checkpoint: start the run again (without --resume)"
            )));
        }
        solver.model.mass_damping_per_s = alpha;
        solver.step_with(aux, false, false)?;
        solver.time_s = t0; // loads held at t0
        steps += 1;
        if steps % opts.adapt_every_steps.max(1) == 0 {
            let (res, reference) = solver.residual_norms();
            if !res.is_finite() {
                solver.model.mass_damping_per_s = saved_alpha;
                return Err(Error::Numerical(format!(
                    "preload diverged after {steps} steps (non-finite residual)"
                )));
            }
            residual = res / reference.max(1e-300);
            let (f_int, f_aux) = solver.force_arrays();
            let net: Vec<P3> = f_int
                .iter()
                .zip(f_aux)
                .map(|(a, b)| [a[0] - b[0], a[1] - b[1], a[2] - b[2]])
                .collect();
            if let Some((u_prev, net_prev)) = &previous {
                let mass = solver.effective_mass();
                let (mut num, mut den) = (0.0, 0.0);
                for i in 0..net.len() {
                    for c in 0..3 {
                        let du = solver.u[i][c] - u_prev[i][c];
                        num += du * (net[i][c] - net_prev[i][c]);
                        den += mass[i] * du * du;
                    }
                }
                if num > 0.0 && den > 0.0 && opts.fixed_damping_per_s.is_none() {
                    alpha = (2.0 * (num / den).sqrt())
                        .max(opts.min_damping_per_s)
                        .min(MAX_ALPHA_DT / solver.dt_s);
                }
            }
            previous = Some((solver.u.clone(), net));
            if residual < opts.tolerance {
                break;
            }
        }
    }
    solver.model.mass_damping_per_s = saved_alpha;
    if !opts.keep_velocities {
        for v in solver.v.iter_mut() {
            *v = [0.0; 3];
        }
        solver.zero_rigid_velocities();
    }
    solver.step = step0;
    solver.time_s = t0;
    let (el, _) = solver.element_energy();
    let stored = el.strain_j + el.hourglass_j + solver.spring_energy_j();
    // Restart the bookkeeping from the preloaded state: its stored energy becomes the initial
    // energy of the run that follows.
    solver.rebase_energy();
    let converged = residual < opts.tolerance;
    if !converged && opts.require_convergence {
        return Err(Error::Numerical(format!(
            "preload did not converge in {steps} steps: relative residual {residual:.3e} (tolerance {:.1e})",
            opts.tolerance
        )));
    }
    Ok(PreloadReport {
        steps,
        relative_residual: residual,
        damping_per_s: alpha,
        stored_energy_j: stored,
        converged,
    })
}
