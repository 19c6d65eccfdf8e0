//! The static preload of the rolling model: frictionless dynamic relaxation in stages, with the
//! sprung mass put back over the sinking axle box between them, until the wheel carries its
//! static load.

use super::build::RollingModel;
use crate::explicit::preload::{relax, PreloadOptions, PreloadReport};
use crate::explicit::run::StopFlag;
use crate::explicit::statics::{solve_static, LinearSolver, StaticOptions, StaticReport};
use crate::model::case;
use crate::{Error, Result};

/// Static preload (frictionless dynamic relaxation with the case's damping) in stages. The
/// sprung mass starts at its static position over the unloaded axle box; as the wheel sinks
/// into the track the axle box follows, and the suspension would carry `k d` less than the
/// sprung weight (about 2 kN for 1.7 mm) until the 1-2 Hz bounce settles, which dynamic
/// relaxation cannot wait for. So after each stage but the last the sprung mass is put back at
/// its static offset from the current axle box (`u_s = u_box - W / k`, at rest), and the next
/// stage relaxes that small disturbance: the wheel then carries the full static load.
///
/// Converged means three things: the relative residual below the case's tolerance, the sprung
/// mass in place (within 1 µm), and the wheel carrying its static load: the vertical contact
/// force within `load_tolerance` of the wheelset and sprung weight. The last is needed because
/// the residual is a norm over all nodes: the wheelset still sinking slowly into the track as
/// one body (an overdamped mode) leaves a few kN spread over thousands of nodes, which that
/// norm does not see (measured on the 1 mm model: residual 9e-4 with 8 % of the load missing).
fn staged_preload(
    m: &mut RollingModel,
    preload: &case::PreloadSpec,
    stop: &StopFlag,
) -> Result<PreloadReport> {
    // Stages of a tenth of the step budget: the axle box moves little within one, so each
    // put-back disturbs the wheel by a few hundred newtons at most.
    let per_stage = (preload.max_steps / 10).max(1);
    let mut total_steps = 0;
    let mut last: Option<PreloadReport> = None;
    let mut stage = 0;
    while total_steps < preload.max_steps {
        let steps = per_stage.min(preload.max_steps - total_steps);
        let report = relax(
            &mut m.solver,
            &mut m.contact,
            PreloadOptions {
                tolerance: preload.tolerance,
                max_steps: steps,
                fixed_damping_per_s: Some(preload.damping_per_s),
                require_convergence: false,
                // A stage ends early once the residual is small; the relaxation goes on in the
                // next (velocities are zeroed below, when it is over).
                keep_velocities: true,
                stop: stop.clone(),
                ..Default::default()
            },
        )?;
        total_steps += report.steps;
        let final_stage = total_steps >= preload.max_steps;
        let load_error = preload_load_error(m);
        m.info.preload_load_error = load_error;
        let target = m.solver.u[m.axle_box_node][2] - m.suspension_static_compression_m;
        let moved = (m.solver.u[m.sprung_node][2] - target).abs();
        if std::env::var_os("SQUEAL_PRELOAD_TRACE").is_some() {
            eprintln!(
                "preload stage {stage}: {} steps (total {total_steps}), residual {:.2e}, \
                 wheel load error {:+.3} %, sprung mass {:.2e} m from its place",
                report.steps,
                report.relative_residual,
                100.0 * load_error,
                moved
            );
        }
        let converged =
            report.converged && moved < 1e-6 && load_error.abs() < preload.load_tolerance;
        last = Some(PreloadReport {
            converged,
            ..report
        });
        if converged || final_stage {
            break;
        }
        m.solver.u[m.sprung_node][2] = target;
        m.solver.v[m.sprung_node] = [0.0; 3];
        stage += 1;
    }
    // The run starts from rest (a stage that stopped early kept its velocities).
    m.solver.v.iter_mut().for_each(|v| *v = [0.0; 3]);
    m.solver.zero_rigid_velocities();
    let mut report = last.ok_or_else(|| {
        Error::input(
            "scenario",
            "preload.max_steps",
            "must be at least 1".to_string(),
        )
    })?;
    report.steps = total_steps;
    Ok(report)
}

/// Runs `preload` with the contact enforced by its penalty, then puts the case's enforcement
/// back: the static equilibrium the run starts from is the penalty's (the implicit solver's
/// tangent is the penalty's stiffness), and an exact run relaxes the penetration left
/// (`contact::exact`).
fn with_penalty<T>(m: &mut RollingModel, preload: impl FnOnce(&mut RollingModel) -> T) -> T {
    let enforcement = std::mem::replace(
        &mut m.contact.pair.enforcement,
        crate::contact::Enforcement::Penalty,
    );
    let outcome = preload(m);
    m.contact.pair.enforcement = enforcement;
    outcome
}

/// The static preload by dynamic relaxation, with the preload's inertia scaling.
pub(super) fn relaxation_preload(
    m: &mut RollingModel,
    case: &case::RollingCase,
    opts: &super::SimulateOptions,
) -> Result<PreloadReport> {
    if let Some(dt) = case.preload.time_step_s {
        m.solver.set_inertia_scaling(&m.preload_added_mass_kg, dt)?;
    }
    let report = with_penalty(m, |m| staged_preload(m, &case.preload, &opts.stop));
    m.solver.clear_inertia_scaling();
    let report = report?;
    if opts.progress {
        eprintln!(
            "preload: {} steps, relative residual {:.2e}{}",
            report.steps,
            report.relative_residual,
            if report.converged {
                ""
            } else {
                " (step limit reached; run continues)"
            }
        );
    }
    Ok(report)
}

/// The linear solver of an implicit preload method (`implicit`: Cholesky; `implicit_iterative`:
/// conjugate gradients; dynamic relaxation solves nothing and gets the default).
pub(super) fn linear_solver_of(method: case::PreloadMethod) -> LinearSolver {
    match method {
        case::PreloadMethod::ImplicitIterative => LinearSolver::Iterative,
        _ => LinearSolver::Direct,
    }
}

/// Static preload by Newton's method ([`crate::explicit::statics`]), frictionless like the
/// relaxation. The wheelset's translation along the rail is held: on frictionless contact
/// nothing but the faceting of the meshes resists it (its reaction is reported, and small), and
/// its rotation about the axle is held likewise. The sprung mass needs no staging: its spring
/// is in the tangent, so the equilibrium carries the full static load at once. Converged: the
/// relative residual below the case's tolerance and the vertical contact force within
/// `load_tolerance` of the static wheel load, as for the relaxation.
pub(super) fn implicit_preload(
    m: &mut RollingModel,
    preload: &case::PreloadSpec,
    linear_solver: LinearSolver,
    stop: &StopFlag,
) -> Result<StaticReport> {
    let mut held = vec![[false; 3]; m.solver.model.rigid_bodies.len()];
    held[m.axle_body][0] = true;
    let report = with_penalty(m, |m| {
        solve_static(
            &mut m.solver,
            &mut m.contact,
            &StaticOptions {
                tolerance: preload.tolerance,
                held_rigid_translations: held,
                linear_solver,
                trace: std::env::var_os("SQUEAL_PRELOAD_TRACE").is_some(),
                stop: stop.clone(),
                ..Default::default()
            },
        )
    })?;
    let load_error = preload_load_error(m);
    m.info.preload_load_error = load_error;
    if load_error.abs() >= preload.load_tolerance {
        return Err(Error::Numerical(format!(
            "static preload converged (relative residual {:.2e}) but the wheel carries {:+.2} % \
             of its static load (tolerance {:.2} %): lower preload.tolerance",
            report.relative_residual,
            100.0 * load_error,
            100.0 * preload.load_tolerance
        )));
    }
    Ok(report)
}

/// `(F_z - W) / W`: the vertical contact force on the wheel against the static wheel load
/// (wheelset and sprung weight).
pub(super) fn preload_load_error(m: &RollingModel) -> f64 {
    let (normal, tangential, _) = m.contact.pair.resultants();
    let load = m.info.static_wheel_load_n;
    (normal[2] + tangential[2] - load) / load
}
