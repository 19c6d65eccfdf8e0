//! Wheel-rail rolling contact: the half wheelset with its sprung mass
//! on the 54E1 track, rolled by the explicit engine with penalty contact and friction.
//!
//! The model (Yang & Li 2019; docs/physics.md, "Rolling model"):
//! - wheel, half axle, tread band, rail, rail band and sleepers are the scenario's hexahedra,
//!   the bands tied to their bodies;
//! - the two axle end faces form one rigid body that turns only about the axle (y), as in its
//!   bearings: it gets the prescribed lateral motion (so the angle of attack stays zero) and
//!   the driving torque; the outer face's centre (the axle box) carries the primary suspension
//!   to the sprung mass node;
//! - rail pads are spring-dampers from each rail-foot node over a sleeper to the nearest
//!   sleeper-top node (the pad's totals shared equally); ballast is a vertical spring-damper
//!   from each sleeper-bottom node to the ground, whose lateral and longitudinal motion is
//!   fixed, as is that of the rail ends;
//! - the sprung mass starts at its static position (the suspension carries its weight from the
//!   first step): its 1-2 Hz bounce would otherwise need seconds of relaxation;
//! - static preload by dynamic relaxation; then the wheelset gets its rolling velocity
//!   `v = V e_x + (V / R) e_y x r` (R: tread radius at the tape circle) and the run starts.
//!
//! Outputs in the run directory: `histories.csv` (wheel vibration: rim point and rim average,
//! lateral / vertical / longitudinal velocity in the frame that moves and turns with the
//! wheelset, so the rolling motion itself is not in the signal), `contact_forces.csv`,
//! `patches/patch_*.csv|json`, `energy.csv`, `status.json`, `run.json`, VTU snapshots.

pub mod bench;
pub mod build;
mod drive;
pub mod identity;
pub mod instruments;
pub mod output;
mod preload;
pub mod record;
pub mod ring;
pub mod stepping;
pub mod wheel_frame;
pub mod wheel_modes;

use std::path::{Path, PathBuf};

use serde::Serialize;

use crate::explicit::preload::PreloadReport;
use crate::explicit::run::{run, HistoryProbe, Quantity, RunOptions, RunSummary};
use crate::explicit::statics::StaticReport;
use crate::model::case::{MultiRateMode, PreloadMethod};
use crate::{Error, Result};
use drive::{hold_forward_speed, loaded_centre_and_radius, prescribe_creepage};
use instruments::ContactPointRecord;
use preload::{implicit_preload, linear_solver_of, relaxation_preload};

pub use crate::explicit::run::StopFlag;
pub use crate::model::case::{embedded_default_case, load_case, LoadedCase, RollingCase};
pub use crate::model::{case, lateral};
pub use build::{build, preload_scaling, ModelInfo, RollingModel, StepLevels, INITIAL_GAP_LIMIT_M};
pub use output::{
    RollingContact, CONTACT_FORCE_COLUMNS, CONTACT_HISTORY_COLUMNS, VIBRATION_COLUMNS,
};

/// Options of [`simulate`].
#[derive(Clone, Debug)]
pub struct SimulateOptions {
    /// Output directory.
    pub out_dir: PathBuf,
    /// Resume from the checkpoint in `out_dir`.
    pub resume: bool,
    /// Replace the run in a non-empty `out_dir` (cleared first). Without it (and without
    /// `resume`) a non-empty `out_dir` is refused, so that no run is overwritten by mistake
    /// and no old file is left beside a new run.
    pub overwrite: bool,
    /// Progress bar.
    pub progress: bool,
    /// Override of the case's end time (s), e.g. for quick checks.
    pub end_time_s: Option<f64>,
    /// Stop cleanly when set: during the rolling run a checkpoint is written and the record's
    /// status is `interrupted` (resume goes on); during the preload the result is
    /// [`Error::Interrupted`].
    pub stop: StopFlag,
    /// Check every step that the contact's region of interest holds every slave the full
    /// search would test (a panic names the step otherwise): the guard of the region, for
    /// tests. Debug builds check every 64 steps anyway.
    pub verify_contact_region: bool,
    /// Multi-rate stepping of the rolling run ([`crate::explicit::multirate`]; the contact's
    /// nodes at the finest) instead of the case's `time_stepping.multi_rate`, when set
    /// ([`stepping`]). The preload always runs single rate.
    pub multi_rate: Option<MultiRateMode>,
    /// The preload method instead of the case's, when set.
    pub preload_method: Option<PreloadMethod>,
}

impl SimulateOptions {
    /// A fresh run into `out_dir`: no resume, no overwrite, no progress bar, the case's end
    /// time, a stop flag of its own, no per-step contact guard, the case's time stepping.
    pub fn new(out_dir: PathBuf) -> Self {
        SimulateOptions {
            out_dir,
            resume: false,
            overwrite: false,
            progress: false,
            end_time_s: None,
            stop: StopFlag::new(),
            verify_contact_region: false,
            multi_rate: None,
            preload_method: None,
        }
    }
}

/// `run.json`: what was run and what came out.
#[derive(Clone, Debug, Serialize)]
pub struct RunRecord {
    /// Case name.
    pub case: String,
    /// Case file.
    pub case_file: String,
    /// Model scenario name.
    pub scenario: String,
    /// The case as read.
    pub settings: RollingCase,
    /// The model scenario with its wheel, as run (less labels: [`identity`]); a resume
    /// compares it with its own.
    pub model_settings: serde_json::Value,
    /// The numerics version of the binary ([`identity::NUMERICS_VERSION`]).
    pub numerics_version: u64,
    /// Model facts.
    pub model: ModelInfo,
    /// Preload result (None when resumed).
    pub preload: Option<PreloadReport>,
    /// The implicit static preload, when it was used.
    pub static_preload: Option<StaticReport>,
    /// Engine summary.
    pub run: RunSummary,
    /// Mean traction coefficient (longitudinal / normal force) over the last quarter of the
    /// run, measured.
    pub measured_traction_coefficient: Option<f64>,
    /// Mean normal force over the first 5 ms after preload (N).
    pub initial_normal_force_n: Option<f64>,
    /// Longest time without any contact node (s); above [`LIFT_OFF_LIMIT_S`] the run is
    /// reported as lift-off or derailment.
    pub longest_contact_loss_s: f64,
    /// Largest `|f_T| / (mu f_N)` over every contact node and every rolling step (of this
    /// segment; `run.json` merges the segments of a resumed run, [`record`]): at most 1 up to
    /// rounding.
    pub largest_node_shear_over_bound: f64,
    /// Deepest penetration over every contact node and every rolling step (m), same span.
    pub deepest_penetration_m: f64,
    /// Where the contact sat on both profiles, its angle, and the flange clearance, at the
    /// start of rolling (or the resume) and over the run (`run.json` merges the segments).
    pub contact_point: Option<ContactPointRecord>,
    /// Exact contact's solver over this segment (absent for a penalty contact).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub exact_contact: Option<ExactContactRecord>,
}

/// What the exact contact's solve did over a segment (`contact::exact`).
#[derive(Clone, Copy, Debug, Serialize)]
pub struct ExactContactRecord {
    /// The most projected Gauss-Seidel sweeps a step took.
    pub largest_sweeps: usize,
    /// Steps that stopped at the sweep limit unconverged.
    pub unconverged_steps: usize,
    /// Contact node-steps held for want of a free motion (fixed, prescribed, tied, rigid).
    pub held_node_steps: usize,
    /// The deepest penetration at the last step (m): what is left of the preload's penalty
    /// penetration, which relaxes with `contact::exact::GAP_RELAXATION_S`.
    pub final_deepest_penetration_m: f64,
}

/// Longest loss of contact accepted as a bounce (s); longer is lift-off or derailment.
pub const LIFT_OFF_LIMIT_S: f64 = 0.002;

/// The run directory before a run: for `--resume` it must hold a checkpoint; otherwise it
/// must be new or empty, or with `overwrite` a folder squeal made, which is set aside
/// ([`crate::output::SetAside`]) until the new run has started writing, and restored if it
/// fails before. Checked before anything is written, so a refused run leaves the folder as it
/// was. The folder is marked as squeal's ([`crate::output::OUTPUT_MARKER`]).
/// Returns the set-aside old run and the topmost folder this created (None: the folder
/// existed).
fn prepare_run_directory(
    opts: &SimulateOptions,
) -> Result<(Option<crate::output::SetAside>, Option<PathBuf>)> {
    let dir = &opts.out_dir;
    let shown = dir.display().to_string();
    if opts.resume {
        if !dir.join(crate::explicit::run::CHECKPOINT_FILE).exists() {
            return Err(Error::input(
                shown,
                "--resume",
                format!(
                    "no {} in this folder: --resume continues a run that wrote a checkpoint; \
                     start the run without --resume",
                    crate::explicit::run::CHECKPOINT_FILE
                ),
            ));
        }
        return Ok((None, None));
    }
    let mut aside = None;
    if crate::output::has_entries(dir) {
        if !opts.overwrite {
            return Err(Error::input(
                shown,
                "--out",
                "the folder is not empty (an earlier run?): give --overwrite to replace it, \
                 --resume to continue its run, or a new or empty folder",
            ));
        }
        aside = Some(crate::output::SetAside::new(dir, "--overwrite")?);
    }
    let created = crate::output::create_dir_recording(dir)?;
    crate::output::mark_output(dir)?;
    Ok((aside, created))
}

/// Runs one case into `opts.out_dir`.
///
/// The run's stages in order, each a function of its own: the case as run, the run folder,
/// the model, the preload and rolling start (or the resume), the run's stepping, then the time
/// loop with its records.
pub fn simulate(loaded: &LoadedCase, opts: &SimulateOptions) -> Result<RunRecord> {
    let (case, loaded_case) = case_for_run(loaded, opts)?;
    // A run still writing into the folder (a resume started beside it) keeps it: checked
    // before an `--overwrite` could clear it, and held from here to the end of this run.
    crate::output::FolderLock::refuse_if_held(&opts.out_dir)?;
    // A new or empty folder that this run fills: a run that fails before its time loop leaves
    // it as it found it (a replaced run is put back by its `SetAside` instead).
    let existed = opts.out_dir.exists();
    let fresh = !opts.resume && !crate::output::has_entries(&opts.out_dir);
    let (replaced, created_parent) = prepare_run_directory(opts)?;
    let claim = crate::output::FolderLock::acquire(&opts.out_dir)?;
    let started = start_run(loaded, &loaded_case, case, opts);
    let (mut m, parts, run_opts, earlier) = match started {
        Ok(s) => s,
        Err(e) => {
            if fresh {
                drop(claim);
                let _ = std::fs::remove_dir_all(&opts.out_dir);
                if existed {
                    let _ = std::fs::create_dir_all(&opts.out_dir);
                } else if let (Some(top), Some(parent)) = (&created_parent, opts.out_dir.parent()) {
                    // The parent folders this run created go too (the run folder itself is
                    // gone already).
                    if top.as_path() != opts.out_dir.as_path() {
                        crate::output::remove_created(parent, top);
                    }
                }
            }
            return Err(e);
        }
    };
    // The new run is built, preloaded and about to write its own record: the run it replaces
    // goes now (until here, any failure put it back).
    if let Some(old) = replaced {
        old.discard()?;
    }
    let record = run_and_record(&mut m, parts, &run_opts, &opts.out_dir, earlier);
    drop(claim);
    record
}

/// The run up to its time loop: the wheel modes, the model, the preload and rolling start (or
/// the resume), and the run's stepping. Returns the model, the record's parts, the engine's
/// options and the earlier record of a resume.
fn start_run(
    loaded: &LoadedCase,
    loaded_case: &LoadedCase,
    case: RollingCase,
    opts: &SimulateOptions,
) -> Result<(
    RollingModel,
    RecordParts,
    RunOptions,
    Option<serde_json::Value>,
)> {
    let source = loaded.source.display().to_string();
    // Read and checked before anything of the resume is written: a resume goes on with the
    // values its run started with, or not at all.
    let identity = identity::RunIdentity::of(&case, &loaded_case.scenario)?;
    let earlier = opts
        .resume
        .then(|| earlier_record(&opts.out_dir.join("run.json")))
        .flatten();
    if let Some(earlier) = &earlier {
        identity::check_resume(earlier, &identity, &source)?;
    }
    // The modes that label the run's peaks, before its minutes or hours of stepping.
    wheel_modes::write_run_wheel_modes(&loaded.scenario.wheel, &opts.out_dir, opts.resume)?;
    let mut m = build_for_run(loaded_case, &case, opts, &source)?;
    let (preload, static_preload) = if !opts.resume {
        let reports = run_preload(&mut m, &case, opts, &source)?;
        start_rolling(&mut m, &case)?;
        reports
    } else {
        if case.hold_forward_speed {
            hold_forward_speed(&mut m, case.speed_m_per_s())?;
        }
        (None, None)
    };
    let mut run_opts = run_options(&m, &case, opts);
    run_opts.stamp = Some(identity.stamp());
    // After the preload and the prescribed motions, so that their nodes stay fine.
    let choice = stepping::choose_stepping(&m, &case.time_stepping, opts.multi_rate, &source)?;
    stepping::apply_stepping(&mut m, &choice)?;
    m.contact.resuming = opts.resume;
    // The invariants are the rolling run's: the frictionless preload's steps are left out.
    m.contact.pair.reset_monitors();
    let parts = RecordParts {
        case: case.name.clone(),
        case_file: loaded.source.display().to_string(),
        scenario: loaded.scenario.scenario.name.clone(),
        settings: case,
        model_settings: identity.model,
        model: m.info.clone(),
        preload,
        static_preload,
    };
    Ok((m, parts, run_opts, earlier))
}

/// The case as this run runs it: the end time overridden by `opts` (within 1 s; later patch
/// and VTU times dropped), with the loaded case around it. A resume of a run with a prescribed
/// creepage is refused.
fn case_for_run(loaded: &LoadedCase, opts: &SimulateOptions) -> Result<(RollingCase, LoadedCase)> {
    let mut case = loaded.case.clone();
    if let Some(t) = opts.end_time_s {
        if !(t > 0.0 && t <= 1.0) {
            return Err(Error::input(
                "command line",
                "--end-time-ms",
                format!("must lie in (0, 1000] ms (got {})", t * 1e3),
            ));
        }
        case.end_time_s = t;
        case.output.patch_times_s.retain(|&x| x <= t);
        case.output.vtu_times_s.retain(|&x| x <= t);
    }
    let loaded_case = LoadedCase {
        case: case.clone(),
        scenario: loaded.scenario.clone(),
        source: loaded.source.clone(),
    };
    if opts.resume && case.creepage.is_some() {
        // The spin history depends on the loaded rolling radius measured after the preload,
        // which a checkpoint does not hold.
        return Err(Error::input(
            loaded.source.display().to_string(),
            "creepage",
            "runs with a prescribed creepage cannot be resumed; start them again",
        ));
    }
    Ok((case, loaded_case))
}

/// The rolling model of the run, writing into the run folder, and an early check that its
/// stepping request can be met (`source` names the case file).
fn build_for_run(
    loaded_case: &LoadedCase,
    case: &RollingCase,
    opts: &SimulateOptions,
    source: &str,
) -> Result<RollingModel> {
    let mut m = build(loaded_case)?;
    m.contact.out_dir = opts.out_dir.clone();
    if opts.verify_contact_region {
        m.contact.pair.verify_region_every_steps = 1;
    }
    // A refused subcycling request stops here, before the preload's minutes (decided again
    // below, once the prescribed motions have their nodes).
    stepping::choose_stepping(&m, &case.time_stepping, opts.multi_rate, source)?;
    Ok(m)
}

/// The static preload by the case's (or the options') method, without friction; the wheel
/// must be in contact afterwards. Returns the dynamic relaxation's or the implicit solve's
/// report.
fn run_preload(
    m: &mut RollingModel,
    case: &RollingCase,
    opts: &SimulateOptions,
    source: &str,
) -> Result<(Option<PreloadReport>, Option<StaticReport>)> {
    let mut preload = None;
    let mut static_preload = None;
    // Frictionless preload: while the wheel settles its rim turns a little and the contact
    // points creep sideways; with friction that path would leave the lateral stick forces
    // saturated at the bound before the wheel has even started rolling.
    let friction = m.contact.pair.suspend_friction();
    let method = opts.preload_method.unwrap_or(case.preload.method);
    let outcome = match method {
        PreloadMethod::DynamicRelaxation => {
            relaxation_preload(m, case, opts).map(|r| preload = Some(r))
        }
        PreloadMethod::Implicit | PreloadMethod::ImplicitIterative => {
            implicit_preload(m, &case.preload, linear_solver_of(method), &opts.stop).map(|r| {
                static_preload = Some(r);
            })
        }
    };
    m.contact.pair.resume_friction(friction);
    outcome?;
    if !m.contact.pair.state.iter().any(|s| s.active) {
        return Err(no_contact_after_preload(preload.as_ref(), case, source));
    }
    if opts.progress {
        if let Some(r) = &static_preload {
            eprintln!(
                "preload (implicit): {} iterations, {} factorisations, relative residual {:.2e}, {:.1} s",
                r.iterations, r.factorisations, r.relative_residual, r.seconds
            );
        }
    }
    Ok((preload, static_preload))
}

/// The error when the wheel is off the rail after the preload. The initial clearance was
/// checked before it (`check_contact_before_preload`), so a relaxation that stopped at its step
/// limit is the likelier cause: the wheel had not come down yet, and the field to change is
/// `preload.max_steps`, not the gap.
fn no_contact_after_preload(
    preload: Option<&PreloadReport>,
    case: &RollingCase,
    source: &str,
) -> Error {
    match preload {
        Some(r) if !r.converged => Error::input(
            source,
            "preload.max_steps",
            format!(
                "the dynamic-relaxation preload stopped at its step limit ({} steps, relative \
                 residual {:.2e}) before the wheel came down onto the rail: raise \
                 preload.max_steps (allowed range 2..=100000000, now {}), use preload.method \
                 implicit, or start closer (model_scenario: wheel_position.initial_gap_mm)",
                r.steps, r.relative_residual, case.preload.max_steps
            ),
        ),
        _ => Error::input(
            source,
            "model_scenario: wheel_position.initial_gap_mm",
            "the wheel is not in contact with the rail after a converged preload: the initial \
             gap is too large or the contact surfaces do not face each other",
        ),
    }
}

/// The rolling start on the preloaded model: the wheelset's rolling velocity about the loaded
/// centre, the sprung mass moving with it, the prescribed creepage or forward speed, and the
/// energy bookkeeping rebased there.
fn start_rolling(m: &mut RollingModel, case: &RollingCase) -> Result<()> {
    // Rolling: v = V e_x + (V / R) e_y x (x - centre) on the wheelset; the sprung mass
    // moves with it.
    // The preloaded wheel has sunk into its track: take the centre from the hub nodes and
    // the rolling radius from it to the loaded contact nodes (force-weighted), so that the
    // contact points start without slip.
    let speed = case.speed_m_per_s();
    let (centre, radius) = loaded_centre_and_radius(m);
    m.info.rolling_radius_m = radius;
    m.info.wheel_centre_m = centre;
    // A yawed wheel (angle of attack psi) rolls freely at the spin `V cos(psi) / R` about its
    // axis a, and slides sideways at `V sin(psi)` (the steady lateral creepage).
    let psi = case.angle_of_attack_rad();
    let axis = crate::model::rolling::yawed_axle_axis(psi);
    let spin = speed * psi.cos() / radius;
    let omega = axis.map(|a| a * spin);
    let nodes = m.wheelset_nodes.clone();
    m.solver
        .set_initial_velocity(Some(&nodes), [speed, 0.0, 0.0], omega, centre);
    m.solver.v[m.sprung_node] = [speed, 0.0, 0.0];
    if let Some(ramp) = case.creepage {
        prescribe_creepage(m, &ramp, speed, radius, psi)?;
    } else if case.hold_forward_speed {
        hold_forward_speed(m, speed)?;
    }
    m.solver.rebase_energy();
    Ok(())
}

/// The engine's options of the rolling run: the case's end time, sampling, snapshots and
/// checkpoints, the wheel centre's probes, and the options' folder, resume, progress and stop.
fn run_options(m: &RollingModel, case: &RollingCase, opts: &SimulateOptions) -> RunOptions {
    let sample_interval_s = 1.0 / case.output.sample_rate_hz;
    RunOptions {
        end_time_s: case.end_time_s,
        sample_interval_s,
        energy_every_samples: 10,
        probes: centre_probes(&m.contact.hub_nodes),
        snapshot_times_s: case.output.vtu_times_s.clone(),
        checkpoint_every_steps: case.output.checkpoint_every_steps,
        out_dir: opts.out_dir.clone(),
        resume: opts.resume,
        progress: opts.progress,
        balance_threshold: 0.05,
        stop: opts.stop.clone(),
        stamp: None,
    }
}

/// The time loop and its records: `run.json` at each periodic checkpoint and at the end,
/// merged with the `earlier` segments' record on a resume.
fn run_and_record(
    m: &mut RollingModel,
    parts: RecordParts,
    run_opts: &RunOptions,
    out_dir: &Path,
    earlier: Option<serde_json::Value>,
) -> Result<RunRecord> {
    let record_path = out_dir.join("run.json");
    // `run.json` with each periodic checkpoint (status `running`): a process killed later
    // leaves the record of its run up to its last checkpoint, which the resume merges.
    let at_checkpoint = (parts.clone(), record_path.clone(), earlier.clone());
    m.contact.checkpoint_record = Some(Box::new(move |summary, contact| {
        let (parts, path, earlier) = &at_checkpoint;
        write_record(
            &parts.record(summary.clone(), contact),
            path,
            earlier.as_ref(),
        )
    }));
    let summary = run(&mut m.solver, &mut m.contact, run_opts)?;
    m.contact.checkpoint_record = None;
    m.contact.flush()?;
    let record = parts.record(summary, &m.contact);
    write_record(&record, &record_path, earlier.as_ref())?;
    Ok(record)
}

/// What `run.json` says of a run that does not change while it rolls.
#[derive(Clone)]
struct RecordParts {
    case: String,
    case_file: String,
    scenario: String,
    settings: RollingCase,
    model_settings: serde_json::Value,
    model: ModelInfo,
    preload: Option<PreloadReport>,
    static_preload: Option<StaticReport>,
}

impl RecordParts {
    /// The record with the engine's `summary` and the contact's monitors now (forces from
    /// `contact_forces.csv` as written so far).
    fn record(&self, summary: RunSummary, contact: &RollingContact) -> RunRecord {
        let (traction, initial_n) = force_statistics(
            &contact.out_dir.join("contact_forces.csv"),
            self.settings.end_time_s,
        );
        RunRecord {
            case: self.case.clone(),
            case_file: self.case_file.clone(),
            scenario: self.scenario.clone(),
            settings: self.settings.clone(),
            model_settings: self.model_settings.clone(),
            numerics_version: identity::NUMERICS_VERSION,
            model: self.model.clone(),
            preload: self.preload,
            static_preload: self.static_preload.clone(),
            run: summary,
            measured_traction_coefficient: traction,
            initial_normal_force_n: initial_n,
            longest_contact_loss_s: contact.longest_loss_s,
            largest_node_shear_over_bound: contact.pair.largest_shear_over_bound,
            deepest_penetration_m: contact.pair.deepest_penetration_m,
            contact_point: contact.contact_point,
            exact_contact: (contact.pair.enforcement == crate::contact::Enforcement::Exact).then(
                || {
                    let (largest_sweeps, unconverged_steps, held_node_steps) =
                        contact.pair.exact_statistics();
                    ExactContactRecord {
                        largest_sweeps,
                        unconverged_steps,
                        held_node_steps,
                        final_deepest_penetration_m: contact
                            .pair
                            .state
                            .iter()
                            .filter(|s| s.active)
                            .map(|s| s.penetration_m)
                            .fold(0.0, f64::max),
                    }
                },
            ),
        }
    }
}

/// The `run.json` an earlier segment of a resumed run wrote; None (with a warning) when it is
/// missing or unreadable, e.g. after a kill that left only a periodic checkpoint: the resumed
/// record then describes its own segment only.
fn earlier_record(path: &Path) -> Option<serde_json::Value> {
    match crate::input::read_json(path) {
        Ok(value) => Some(value),
        Err(e) => {
            eprintln!(
                "warning: {e}: the record of this resume covers its own segment only (no \
                 preload, extremes since the resume)"
            );
            None
        }
    }
}

/// Writes `run.json`: the record with its segments, merged with the earlier segments' record
/// when the run resumed ([`record`]).
fn write_record(
    record: &RunRecord,
    path: &Path,
    earlier: Option<&serde_json::Value>,
) -> Result<()> {
    let value = serde_json::to_value(record).map_err(|e| Error::Numerical(e.to_string()))?;
    let merged = match earlier {
        Some(before) => record::merge_resumed(before, value),
        None => record::with_segments(value),
    };
    crate::output::write_json_staged(path, &merged)
}

/// Wheel centre (mean of the hub bore nodes) displacement and velocity, x / y / z.
fn centre_probes(hub: &[usize]) -> Vec<HistoryProbe> {
    let mut out = Vec::new();
    for (quantity, name, unit) in [
        (Quantity::Displacement, "displacement", "m"),
        (Quantity::Velocity, "velocity", "m_per_s"),
    ] {
        for (d, axis) in ["x", "y", "z"].iter().enumerate() {
            out.push(HistoryProbe {
                column: format!("wheel_centre_{axis}_{name}_{unit}"),
                nodes: hub.to_vec(),
                quantity,
                direction: d,
            });
        }
    }
    out
}

/// Mean traction coefficient over the last quarter of the run and the mean normal force over
/// the first 5 ms, from `contact_forces.csv`.
fn force_statistics(path: &Path, end_time_s: f64) -> (Option<f64>, Option<f64>) {
    let Ok(table) = crate::table::Table::read(path) else {
        return (None, None);
    };
    let col = |name: &str| {
        table
            .headers
            .iter()
            .position(|h| h == name)
            .map(|k| &table.columns[k])
    };
    let (Some(t), Some(n), Some(fx)) = (
        col("time_s"),
        col("normal_force_n"),
        col("longitudinal_force_n"),
    ) else {
        return (None, None);
    };
    let mut sum = (0.0, 0.0);
    let mut first = (0.0, 0usize);
    for k in 0..t.len() {
        if t[k] >= 0.75 * end_time_s {
            sum.0 += fx[k];
            sum.1 += n[k];
        }
        if t[k] <= 0.005 {
            first.0 += n[k];
            first.1 += 1;
        }
    }
    let traction = if sum.1 > 0.0 {
        Some(sum.0 / sum.1)
    } else {
        None
    };
    let initial = if first.1 > 0 {
        Some(first.0 / first.1 as f64)
    } else {
        None
    };
    (traction, initial)
}
