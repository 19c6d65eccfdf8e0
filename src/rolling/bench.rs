//! Where a rolling step's time goes: the model of a case built as `simulate` builds it (no
//! preload), a few warm-up steps so that the wheel presses on the rail, then the element
//! forces, the contact forces and whole steps timed apart; the rest of a step (integration,
//! rigid body, springs, ties) is the difference; the same steps run again with the solver's
//! phase clock on break the whole step down by phase. The projection multiplies the whole
//! step by the case's number of steps: the time loop's wall time without output or preload.
//!
//! [`preload_profile`] times the static preload alone, by either method.

use std::time::Instant;

use serde::Serialize;

use super::build::build;
use super::stepping::{apply_stepping, choose_stepping, contact_nodes};
use crate::explicit::phase_clock::STEP_PHASES;
use crate::explicit::solver::AuxForces;
use crate::model::case::{LoadedCase, MultiRateMode};
use crate::{Error, Result};

/// Warm-up steps before timing: the contact engages and the caches fill.
const WARM_UP_STEPS: usize = 50;

/// The figures of one rolling step.
#[derive(Clone, Debug, Serialize)]
pub struct StepProfile {
    /// Nodes.
    pub nodes: usize,
    /// Elements.
    pub elements: usize,
    /// Contact slave nodes.
    pub contact_slaves: usize,
    /// Of those, the ones searched each step (the region of interest; all with the full
    /// search).
    pub searched_slaves: usize,
    /// One rebuild of the region of interest (ms): a rolling run pays it each time a slave
    /// has moved a median face size.
    pub region_rebuild_ms: f64,
    /// Threads (rayon).
    pub threads: usize,
    /// Time step (s) of the built model (before the preload).
    pub time_step_s: f64,
    /// What limits it.
    pub time_step_limited_by: String,
    /// Steps timed per part.
    pub steps: usize,
    /// A whole step (ms).
    pub step_ms: f64,
    /// Element forces (ms).
    pub elements_ms: f64,
    /// Contact forces (ms).
    pub contact_ms: f64,
    /// The rest: integration, rigid body, springs, ties (ms).
    pub rest_ms: f64,
    /// Element forces per element and step (ns).
    pub ns_per_element_step: f64,
    /// Contact's share of a whole step.
    pub contact_share: f64,
    /// Steps of the case's time loop (end time / step).
    pub case_steps: usize,
    /// Projected wall time of the case's time loop (s).
    pub projected_time_loop_s: f64,
    /// Elements per power-of-two step level (contact nodes at the finest;
    /// [`crate::explicit::levels`]).
    pub level_counts: Vec<usize>,
    /// Element work of multi-rate stepping over these levels, relative to single-rate.
    pub element_work_fraction: f64,
    /// The same without holding the contact's nodes at the finest level.
    pub element_work_fraction_free_contact: f64,
    /// Whether the steps were timed with multi-rate stepping on.
    pub multi_rate: bool,
    /// How the steps were timed, and why (`rolling::stepping`).
    pub time_stepping: String,
    /// Blocks of elements per colour of the single-rate element loop (each colour is one
    /// parallel loop, so few blocks in a colour leave threads idle).
    pub colour_blocks: Vec<usize>,
    /// A whole step's wall time by phase (ms a step; [`crate::explicit::phase_clock`]), from
    /// a second run of the timed steps with the phase clock on.
    pub phase_ms: Vec<(String, f64)>,
    /// With multi-rate stepping: the element forces of each level alone, per element of the
    /// level and evaluation (ns).
    pub level_ns_per_element_step: Vec<f64>,
}

/// Times `steps` steps of each part of the case's rolling step, with the contact search
/// `search`, stepping as the case's `time_stepping` says or as `multi_rate` overrides it
/// ([`super::stepping`]; multi-rate: `steps` is rounded up to whole cycles of the coarsest
/// level, and the element part is the mean over a cycle).
pub fn step_profile(
    loaded: &LoadedCase,
    steps: usize,
    search: crate::contact::ContactSearch,
    multi_rate: Option<MultiRateMode>,
) -> Result<StepProfile> {
    if !(1..=1_000_000).contains(&steps) {
        return Err(Error::input(
            "command line",
            "--steps",
            format!("must be in [1, 1000000], got {steps}"),
        ));
    }
    let mut m = build(loaded)?;
    m.contact.pair.search = search;
    let mut steps = steps;
    let mut level_ns_per_element_step = Vec::new();
    let source = loaded.source.display().to_string();
    let choice = choose_stepping(&m, &loaded.case.time_stepping, multi_rate, &source)?;
    apply_stepping(&mut m, &choice)?;
    for _ in 0..WARM_UP_STEPS {
        m.solver.step_with(&mut m.contact, false, false)?;
    }
    let elements_s = if let Some(mr) = m.solver.multi_rate().cloned() {
        let cycle = mr.full_cycle_steps() as usize;
        steps = steps.div_ceil(cycle) * cycle;
        // Each level alone, then the element work of a step as the cycle's mean.
        let mut per_step = 0.0;
        for (level, &count) in mr.partition.counts.iter().enumerate() {
            if count == 0 {
                level_ns_per_element_step.push(0.0);
                continue;
            }
            let started = Instant::now();
            for _ in 0..steps {
                m.solver.compute_level_forces(level);
            }
            let s = started.elapsed().as_secs_f64() / steps as f64;
            level_ns_per_element_step.push(s * 1e9 / count as f64);
            per_step += s / (1u64 << level) as f64;
        }
        per_step
    } else {
        let started = Instant::now();
        for _ in 0..steps {
            m.solver.compute_internal_forces();
        }
        started.elapsed().as_secs_f64() / steps as f64
    };
    // The contact's forces into a scratch array: the same search and force evaluation as in a
    // step, without moving the model.
    let mut force = vec![[0.0; 3]; m.solver.u.len()];
    let started = Instant::now();
    for _ in 0..steps {
        let (t, dt) = (m.solver.time_s, m.solver.dt_s);
        m.contact
            .add_forces(t, dt, &m.solver.u, &m.solver.v, &mut force);
    }
    let contact_s = started.elapsed().as_secs_f64() / steps as f64;
    // One rebuild of the region: a contact evaluation with the region invalidated, less a
    // plain one.
    m.contact.pair.invalidate_region();
    let started = Instant::now();
    let (t, dt) = (m.solver.time_s, m.solver.dt_s);
    m.contact
        .add_forces(t, dt, &m.solver.u, &m.solver.v, &mut force);
    let region_rebuild_s = (started.elapsed().as_secs_f64() - contact_s).max(0.0);
    let searched_slaves = m.contact.pair.searched_slaves();
    let started = Instant::now();
    for _ in 0..steps {
        m.solver.step_with(&mut m.contact, false, false)?;
    }
    let step_s = started.elapsed().as_secs_f64() / steps as f64;
    // The same steps again with the phase clock on: where a whole step's time goes.
    m.solver.time_phases(true);
    for _ in 0..steps {
        m.solver.step_with(&mut m.contact, false, false)?;
    }
    let phase_ms: Vec<(String, f64)> = m
        .solver
        .phase_clock()
        .map(|clock| {
            STEP_PHASES
                .iter()
                .map(|&p| (p.name().to_string(), clock.seconds(p) * 1e3 / steps as f64))
                .collect()
        })
        .unwrap_or_default();
    m.solver.time_phases(false);
    let elements = m.solver.model.elements.len();
    // The engine's levels (module docs of `explicit::multirate`), with and without the
    // contact's nodes held at the finest.
    let finest = contact_nodes(&m);
    let levels = m.solver.plan_multi_rate(choice.scheme, &finest)?;
    let free_contact = m.solver.plan_multi_rate(choice.scheme, &[])?;
    let case_steps = (loaded.case.end_time_s / m.solver.dt_s).ceil() as usize;
    Ok(StepProfile {
        nodes: m.solver.u.len(),
        elements,
        contact_slaves: m.info.contact_slaves,
        searched_slaves,
        region_rebuild_ms: region_rebuild_s * 1e3,
        threads: rayon::current_num_threads(),
        time_step_s: m.solver.dt_s,
        time_step_limited_by: m.info.time_step_limited_by.clone(),
        steps,
        step_ms: step_s * 1e3,
        elements_ms: elements_s * 1e3,
        contact_ms: contact_s * 1e3,
        rest_ms: (step_s - elements_s - contact_s) * 1e3,
        ns_per_element_step: elements_s * 1e9 / elements as f64,
        contact_share: contact_s / step_s,
        case_steps,
        projected_time_loop_s: step_s * case_steps as f64,
        level_counts: levels.counts,
        element_work_fraction: levels.element_work_fraction,
        element_work_fraction_free_contact: free_contact.element_work_fraction,
        multi_rate: choice.multi_rate,
        time_stepping: choice.reason.clone(),
        level_ns_per_element_step,
        colour_blocks: m.solver.colour_blocks(),
        phase_ms,
    })
}

/// The figures of one static preload.
#[derive(Clone, Debug, Serialize)]
pub struct PreloadProfile {
    /// Elements of the model.
    pub elements: usize,
    /// The method used.
    pub method: crate::model::case::PreloadMethod,
    /// Building the model (s).
    pub build_s: f64,
    /// The preload (s).
    pub preload_s: f64,
    /// Newton iterations (implicit) or steps (relaxation).
    pub iterations_or_steps: u64,
    /// Entries of the Cholesky factor (implicit; 0 for relaxation).
    pub factor_entries: usize,
    /// Final relative residual.
    pub relative_residual: f64,
    /// `(F_z - W) / W` after the preload.
    pub load_error: f64,
}

/// Builds the case's model and times its static preload by `method` (no rolling run).
pub fn preload_profile(
    loaded: &LoadedCase,
    method: crate::model::case::PreloadMethod,
) -> Result<PreloadProfile> {
    use crate::model::case::PreloadMethod;
    let t0 = Instant::now();
    let mut m = build(loaded)?;
    let build_s = t0.elapsed().as_secs_f64();
    let t1 = Instant::now();
    let friction = m.contact.pair.suspend_friction();
    let stop = super::StopFlag::new();
    let outcome = match method {
        PreloadMethod::Implicit | PreloadMethod::ImplicitIterative => {
            let linear_solver = super::preload::linear_solver_of(method);
            super::preload::implicit_preload(&mut m, &loaded.case.preload, linear_solver, &stop)
                .map(|r| (r.iterations as u64, r.factor_entries, r.relative_residual))
        }
        PreloadMethod::DynamicRelaxation => {
            let opts = super::SimulateOptions::new(std::env::temp_dir());
            super::preload::relaxation_preload(&mut m, &loaded.case, &opts)
                .map(|r| (r.steps, 0, r.relative_residual))
        }
    };
    m.contact.pair.resume_friction(friction);
    let (iterations_or_steps, factor_entries, relative_residual) = outcome?;
    Ok(PreloadProfile {
        elements: m.info.elements,
        method,
        build_s,
        preload_s: t1.elapsed().as_secs_f64(),
        iterations_or_steps,
        factor_entries,
        relative_residual,
        load_error: m.info.preload_load_error,
    })
}
