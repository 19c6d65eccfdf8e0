//! A run of the explicit engine with output: time histories streamed to CSV at a fixed sample
//! rate (never held in memory), an energy CSV, VTU snapshots at chosen times, a progress bar,
//! checkpoints every N steps and resume from the last one.
//!
//! The time step is set to `sample_interval / ceil(sample_interval / dt_stable)` so that the
//! samples fall exactly on steps and the histories are uniformly sampled (what the PSD needs).
//!
//! Failure keeps the work: on an instability (non-finite value, inverted element, energy
//! balance beyond the threshold) the run writes `status.json` with the diagnosis, flushes every
//! file written so far, and returns the error.

// Index loops mirror the tensor notation of the equations (the project's style for kernels);
// `!(x > 0.0)` is meant: it also rejects NaN.
#![allow(clippy::needless_range_loop, clippy::neg_cmp_op_on_partial_ord)]

use std::fmt::Write as _;
use std::fs::File;
use std::io::{BufRead, BufReader, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Instant;

use serde::{Deserialize, Serialize};

use super::checkpoint::check_stamp;
pub use super::checkpoint::{
    model_fingerprint, read_checkpoint, read_checkpoint_stamped, write_checkpoint,
    write_checkpoint_stamped, RunStamp,
};
use super::solver::{AuxForces, Solver};
pub use super::state::RunSummary;
use crate::mesh::vtu::{self, PointVectorField};
use crate::mesh::P3;
use crate::{Error, Result};

/// The checkpoint a run writes into its directory (and `--resume` reads).
pub const CHECKPOINT_FILE: &str = "checkpoint.bin";
/// Sampled quantity.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Quantity {
    /// Displacement (m).
    Displacement,
    /// Velocity (m/s).
    Velocity,
    /// Acceleration (m/s^2).
    Acceleration,
}

/// One history column: a node or the average over a node set, one quantity, one direction.
#[derive(Clone, Debug, PartialEq)]
pub struct HistoryProbe {
    /// CSV column name (e.g. `lateral_rim_velocity_m_per_s`).
    pub column: String,
    /// Nodes averaged.
    pub nodes: Vec<usize>,
    /// Quantity.
    pub quantity: Quantity,
    /// Direction 0 = x, 1 = y, 2 = z.
    pub direction: usize,
}

/// A request to stop a run cleanly at the next step, set from a signal handler (the `squeal`
/// binary sets it on Ctrl-C / SIGTERM) or another thread. The run then flushes its files, writes
/// a checkpoint of the step it reached and `status.json` with status `interrupted`, so that
/// `--resume` goes on from there: a stopped run loses no work. Clones share the flag.
#[derive(Clone, Debug, Default)]
pub struct StopFlag(Arc<AtomicBool>);

impl StopFlag {
    /// A flag that is not set.
    pub fn new() -> StopFlag {
        StopFlag::default()
    }

    /// Asks every run holding this flag (or a clone) to stop.
    pub fn request(&self) {
        self.0.store(true, Ordering::Relaxed);
    }

    /// Whether a stop was asked for. One relaxed load: cheap enough to test every step.
    pub fn is_requested(&self) -> bool {
        self.0.load(Ordering::Relaxed)
    }
}

/// Options of a run.
#[derive(Clone, Debug)]
pub struct RunOptions {
    /// End time (s).
    pub end_time_s: f64,
    /// History sample interval (s).
    pub sample_interval_s: f64,
    /// Energy report every this many samples.
    pub energy_every_samples: u64,
    /// History columns.
    pub probes: Vec<HistoryProbe>,
    /// Times of VTU snapshots (s).
    pub snapshot_times_s: Vec<f64>,
    /// Checkpoint every this many steps (0 = never).
    pub checkpoint_every_steps: u64,
    /// Output directory.
    pub out_dir: PathBuf,
    /// Resume from `out_dir/checkpoint.bin`.
    pub resume: bool,
    /// Show a progress bar.
    pub progress: bool,
    /// Stop when the energy balance error exceeds this fraction of the energy.
    pub balance_threshold: f64,
    /// Stop cleanly (checkpoint, status `interrupted`) when this is set.
    pub stop: StopFlag,
    /// What the run computes with, stored in each checkpoint; a resume refuses a checkpoint
    /// whose stamp differs (None: none stored, none checked).
    pub stamp: Option<RunStamp>,
}

impl RunOptions {
    /// Defaults: 10 kHz-ish sampling is the caller's choice; energy every 10 samples,
    /// checkpoint every 20 000 steps, 5 % balance threshold.
    pub fn new(out_dir: &Path, end_time_s: f64, sample_interval_s: f64) -> RunOptions {
        RunOptions {
            end_time_s,
            sample_interval_s,
            energy_every_samples: 10,
            probes: Vec::new(),
            snapshot_times_s: Vec::new(),
            checkpoint_every_steps: 20_000,
            out_dir: out_dir.to_path_buf(),
            resume: false,
            progress: false,
            balance_threshold: 0.05,
            stop: StopFlag::new(),
            stamp: None,
        }
    }
}

fn io(path: &Path) -> impl Fn(std::io::Error) -> Error + '_ {
    move |e| Error::io(path, e)
}

/// Sets the solver's step so that samples fall on steps; returns steps per sample.
pub fn align_time_step(solver: &mut Solver, sample_interval_s: f64) -> Result<u64> {
    if !(sample_interval_s > 0.0 && sample_interval_s.is_finite()) {
        return Err(Error::input(
            "run",
            "sample_interval_s",
            format!("must be > 0 (got {sample_interval_s})"),
        ));
    }
    let per_sample = (sample_interval_s / solver.dt_s).ceil().max(1.0) as u64;
    solver.dt_s = sample_interval_s / per_sample as f64;
    Ok(per_sample)
}

/// Runs from the solver's current state to `opts.end_time_s`.
///
/// Kept in one piece: the time loop with its output, checkpoint, progress and diagnosis hooks in
/// the order they happen each step.
pub fn run<A: AuxForces + ?Sized>(
    solver: &mut Solver,
    aux: &mut A,
    opts: &RunOptions,
) -> Result<RunSummary> {
    for p in &opts.probes {
        if p.nodes.is_empty() || p.direction > 2 || p.nodes.iter().any(|&n| n >= solver.u.len()) {
            return Err(Error::input(
                "run",
                &p.column,
                "history probe needs nodes of the model and a direction 0..2",
            ));
        }
    }
    if !(opts.end_time_s > 0.0 && opts.end_time_s.is_finite()) {
        return Err(Error::input(
            "run",
            "end_time_s",
            format!("must be > 0 (got {})", opts.end_time_s),
        ));
    }
    std::fs::create_dir_all(&opts.out_dir).map_err(io(&opts.out_dir))?;
    let (_, limited_by) = solver.stable_time_step_s()?;
    let per_sample = align_time_step(solver, opts.sample_interval_s)?;
    let hist_path = opts.out_dir.join("histories.csv");
    let energy_path = opts.out_dir.join("energy.csv");
    let ckpt_path = opts.out_dir.join(CHECKPOINT_FILE);
    let mut resumed_from = None;
    if opts.resume {
        let (aux_state, stamp) = read_checkpoint_stamped(solver, &ckpt_path)?;
        check_stamp(stamp, opts.stamp, &ckpt_path)?;
        aux.restore_state(&aux_state)?;
        resumed_from = Some(solver.time_s);
        resume_csv(&hist_path, solver.time_s)?;
        resume_csv(&energy_path, solver.time_s)?;
    }
    let append = opts.resume;
    let open = |p: &Path| -> Result<BufWriter<File>> {
        let f = std::fs::OpenOptions::new()
            .create(true)
            .write(true)
            .append(append)
            .truncate(!append)
            .open(p)
            .map_err(io(p))?;
        Ok(BufWriter::new(f))
    };
    let mut energy_header = String::from(
        "time_s,kinetic_j,strain_j,hourglass_j,spring_j,damping_j,contact_j,external_work_j,balance_error_j,balance_ratio,min_det_f",
    );
    // Multi-rate runs: where the energy sits, level by level (multirate.rs).
    let levels = solver.multi_rate().map_or(0, |m| m.levels());
    for k in 0..levels {
        energy_header.push_str(&format!(",kinetic_level{k}_j,internal_level{k}_j"));
    }
    // ... and each level's energy balance (multirate.rs, "Energy by level").
    for k in 0..levels {
        energy_header.push_str(&format!(",balance_level{k}_j"));
    }
    // A run resumed in another stepping mode keeps one table: the columns of both.
    let energy_columns = if append {
        reconcile_csv_header(&energy_path, &energy_header)?
    } else {
        ColumnPlacement::AS_WRITTEN
    };
    let mut hist = open(&hist_path)?;
    let mut energy_csv = open(&energy_path)?;
    if !append {
        let mut header = String::from("time_s");
        for p in &opts.probes {
            header.push(',');
            header.push_str(&p.column);
        }
        for c in aux.history_columns() {
            header.push(',');
            header.push_str(&c);
        }
        writeln!(hist, "{header}").map_err(io(&hist_path))?;
        writeln!(energy_csv, "{energy_header}").map_err(io(&energy_path))?;
    }
    let total_steps = ((opts.end_time_s - solver.time_s) / solver.dt_s)
        .round()
        .max(0.0) as u64;
    let start_step = solver.step;
    let bar = if opts.progress {
        let b = indicatif::ProgressBar::new(total_steps);
        b.set_style(
            indicatif::ProgressStyle::with_template(
                "{bar:30} {pos}/{len} steps  {msg}  elapsed {elapsed_precise}  eta {eta_precise}",
            )
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        b
    } else {
        indicatif::ProgressBar::hidden()
    };
    let segment = Segment {
        limited_by,
        wall: Instant::now(),
        start_step,
        resumed_from,
    };
    let status_path = opts.out_dir.join("status.json");
    let mut snapshots: Vec<f64> = opts
        .snapshot_times_s
        .iter()
        .copied()
        .filter(|&t| t >= solver.time_s)
        .collect();
    snapshots.sort_by(f64::total_cmp);
    let mut next_snapshot = 0;
    let mut max_ratio: f64 = 0.0;
    // One energy row, built then placed in the table's columns (allocated once).
    let mut energy_row = String::with_capacity(512);
    let mut row = String::with_capacity(32 * (opts.probes.len() + 1));
    let mut failure: Option<Error> = None;
    let mut interrupted = false;
    for k in 0..total_steps {
        if opts.stop.is_requested() {
            interrupted = true;
            break;
        }
        let n = solver.step;
        let sample = n.is_multiple_of(per_sample);
        let energy = sample && (n / per_sample).is_multiple_of(opts.energy_every_samples.max(1));
        solver.step_with(aux, sample, energy)?;
        let t_n = solver.time_s - solver.dt_s;
        if sample {
            row.clear();
            push_num(&mut row, t_n);
            for p in &opts.probes {
                let mut acc = 0.0;
                for &nd in &p.nodes {
                    acc += match p.quantity {
                        Quantity::Displacement => solver.output.displacement[nd][p.direction],
                        Quantity::Velocity => solver.output.velocity[nd][p.direction],
                        Quantity::Acceleration => solver.output.acceleration[nd][p.direction],
                    };
                }
                row.push(',');
                push_num(&mut row, acc / p.nodes.len() as f64);
            }
            aux.push_history_values(t_n, &solver.model.mesh.nodes, &solver.output, &mut row)?;
            row.push('\n');
            hist.write_all(row.as_bytes()).map_err(io(&hist_path))?;
            aux.on_sample(t_n, &opts.out_dir)?;
        }
        if energy {
            if let Some(e) = solver.last_energy() {
                max_ratio = max_ratio.max(e.balance_ratio);
                energy_row.clear();
                write!(
                    energy_row,
                    "{},{},{},{},{},{},{},{},{},{},{}",
                    e.time_s,
                    e.kinetic_j,
                    e.strain_j,
                    e.hourglass_j,
                    e.spring_j,
                    e.damping_j,
                    e.contact_j,
                    e.external_work_j,
                    e.balance_error_j,
                    e.balance_ratio,
                    e.min_det_f
                )
                .expect("writing to a String");
                let levels = solver.level_energies().unwrap_or_default();
                for level in &levels {
                    write!(energy_row, ",{},{}", level.kinetic_j, level.internal_j)
                        .expect("writing to a String");
                }
                for error in solver.level_balance_errors(&levels).unwrap_or_default() {
                    write!(energy_row, ",{error}").expect("writing to a String");
                }
                let placed = energy_columns.place(&energy_row);
                writeln!(energy_csv, "{placed}").map_err(io(&energy_path))?;
                if let Err(err) = solver.check_state(&e, opts.balance_threshold) {
                    failure = Some(err);
                    break;
                }
            }
            bar.set_message(format!(
                "t = {:.3} ms, {:.0} steps/s",
                solver.time_s * 1e3,
                segment.steps_per_second(solver, segment.wall.elapsed().as_secs_f64())
            ));
        }
        while next_snapshot < snapshots.len()
            && snapshots[next_snapshot] <= solver.time_s + 0.5 * solver.dt_s
        {
            let extra = aux.snapshot_fields(solver.model.mesh.nodes.len());
            write_snapshot(solver, &opts.out_dir, snapshots[next_snapshot], &extra)?;
            next_snapshot += 1;
        }
        if opts.checkpoint_every_steps > 0 && (k + 1) % opts.checkpoint_every_steps == 0 {
            hist.flush().map_err(io(&hist_path))?;
            energy_csv.flush().map_err(io(&energy_path))?;
            write_checkpoint_stamped(solver, &aux.checkpoint_state(), opts.stamp, &ckpt_path)?;
            // The record of the run so far, in step with the checkpoint: if the process is
            // killed before its end, `status.json` says where a resume goes on from, and the
            // auxiliary module's record (a rolling run's `run.json`) keeps this segment's wall
            // time and extremes for the resume to merge.
            let diagnosis = format!(
                "running; checkpoint at t = {:.6} ms (step {}) in {}: if no process is running \
                 it, it ended after this checkpoint and a resume goes on from it",
                solver.time_s * 1e3,
                solver.step,
                ckpt_path.display()
            );
            let summary = segment.summary(solver, "running", Some(diagnosis), max_ratio);
            crate::output::write_json_staged(&status_path, &summary)?;
            aux.on_checkpoint(&summary)?;
        }
        if k % 64 == 0 {
            bar.set_position(k);
        }
    }
    bar.finish_and_clear();
    hist.flush().map_err(io(&hist_path))?;
    energy_csv.flush().map_err(io(&energy_path))?;
    // An interrupted run always gets its checkpoint: that is what makes stopping safe.
    if failure.is_none() && (opts.checkpoint_every_steps > 0 || interrupted) {
        write_checkpoint_stamped(solver, &aux.checkpoint_state(), opts.stamp, &ckpt_path)?;
    }
    let status = if failure.is_some() {
        "unstable"
    } else if interrupted {
        "interrupted"
    } else {
        "completed"
    };
    let diagnosis = match &failure {
        Some(e) => Some(e.to_string()),
        None if interrupted => Some(format!(
            "stopped on request at t = {:.6} ms (step {}); checkpoint written to {}, \
             a resume goes on from it",
            solver.time_s * 1e3,
            solver.step,
            ckpt_path.display()
        )),
        None => None,
    };
    let summary = segment.summary(solver, status, diagnosis, max_ratio);
    crate::output::write_json_staged(&status_path, &summary)?;
    match failure {
        Some(e) => Err(e),
        None => Ok(summary),
    }
}

/// This invocation of a run: what its summary needs besides the solver's state.
struct Segment {
    limited_by: String,
    wall: Instant,
    start_step: u64,
    resumed_from: Option<f64>,
}

impl Segment {
    /// Steps of this invocation per second of `wall_s`.
    fn steps_per_second(&self, solver: &Solver, wall_s: f64) -> f64 {
        (solver.step - self.start_step) as f64 / wall_s.max(1e-9)
    }

    /// The run's summary now, with `status` and `diagnosis`.
    fn summary(
        &self,
        solver: &Solver,
        status: &str,
        diagnosis: Option<String>,
        max_balance_ratio: f64,
    ) -> RunSummary {
        let wall_s = self.wall.elapsed().as_secs_f64();
        RunSummary {
            status: status.to_string(),
            diagnosis,
            steps: solver.step,
            time_s: solver.time_s,
            time_step_s: solver.dt_s,
            time_step_limited_by: self.limited_by.clone(),
            wall_s,
            steps_per_second: self.steps_per_second(solver, wall_s),
            max_balance_ratio,
            last_energy: solver.last_energy(),
            resumed_from_s: self.resumed_from,
        }
    }
}

pub(crate) fn push_num(s: &mut String, x: f64) {
    use std::fmt::Write as _;
    let _ = write!(s, "{x:.9e}");
}

/// Writes `snapshot_<time in us>.vtu` with the displacement and velocity fields and the
/// `extra` point vector fields (e.g. the contact force per node).
pub fn write_snapshot(
    solver: &Solver,
    dir: &Path,
    time_s: f64,
    extra: &[(String, Vec<P3>)],
) -> Result<PathBuf> {
    let path = dir.join(format!("snapshot_{:09.1}us.vtu", time_s * 1e6));
    let n = solver.model.mesh.nodes.len();
    let mut fields = vec![
        PointVectorField {
            name: "displacement_m".into(),
            values: &solver.u[..n],
        },
        PointVectorField {
            name: "velocity_m_per_s".into(),
            values: &solver.v[..n],
        },
    ];
    for (name, values) in extra {
        fields.push(PointVectorField {
            name: name.clone(),
            values: &values[..n.min(values.len())],
        });
    }
    vtu::write(&solver.model.mesh, &path, &fields)?;
    write_snapshot_collection(dir)?;
    Ok(path)
}

/// The run's snapshots as one ParaView time series: `snapshots.pvd` over every
/// `snapshot_<time in us>.vtu` in `dir` (rewritten after each snapshot, so that a resumed or
/// interrupted run's collection lists what is there).
fn write_snapshot_collection(dir: &Path) -> Result<()> {
    let entries = std::fs::read_dir(dir).map_err(io(dir))?;
    let mut files = Vec::new();
    for entry in entries.flatten() {
        let name = entry.file_name().to_string_lossy().to_string();
        let time_us = name
            .strip_prefix("snapshot_")
            .and_then(|r| r.strip_suffix("us.vtu"))
            .and_then(|t| t.parse::<f64>().ok());
        if let Some(t) = time_us {
            files.push((t * 1e-6, name));
        }
    }
    crate::mesh::pvd::write_collection(&dir.join("snapshots.pvd"), &files)
}

/// Drops the rows of a CSV whose first column exceeds `time_s` (for resume).
/// Where a row's fields go in a table whose header may hold more columns than the row's writer
/// knows (a run resumed in another stepping mode, [`reconcile_csv_header`]).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct ColumnPlacement {
    /// The column of each of the writer's fields and the table's width; None: the table's
    /// columns are the writer's.
    spread: Option<(Vec<usize>, usize)>,
}

impl ColumnPlacement {
    /// Fields where the writer puts them.
    const AS_WRITTEN: ColumnPlacement = ColumnPlacement { spread: None };

    fn new(positions: Vec<usize>, width: usize) -> Self {
        let as_written =
            width == positions.len() && positions.iter().enumerate().all(|(i, &p)| i == p);
        ColumnPlacement {
            spread: (!as_written).then_some((positions, width)),
        }
    }

    /// The row (the writer's comma-separated fields) in the table's columns, empty where the
    /// writer has no value.
    pub(crate) fn place<'a>(&self, row: &'a str) -> std::borrow::Cow<'a, str> {
        let Some((positions, width)) = &self.spread else {
            return std::borrow::Cow::Borrowed(row);
        };
        let mut cells = vec![""; *width];
        for (field, &p) in row.split(',').zip(positions) {
            cells[p] = field;
        }
        std::borrow::Cow::Owned(cells.join(","))
    }
}

/// Makes the CSV table at `path` hold `header`'s columns: when its own header differs, the
/// table's columns become its own followed by `header`'s new ones, the rows already written are
/// padded with empty fields, and the returned placement puts a row written for `header` into
/// them. Why: a run resumed in another stepping mode writes other per-level energy columns;
/// one table with the union of both keeps every row readable under its header.
pub(crate) fn reconcile_csv_header(path: &Path, header: &str) -> Result<ColumnPlacement> {
    let wanted: Vec<&str> = header.split(',').collect();
    let Ok(text) = std::fs::read_to_string(path) else {
        return Ok(ColumnPlacement::AS_WRITTEN);
    };
    let mut lines = text.lines();
    let Some(old_header) = lines.next() else {
        return Ok(ColumnPlacement::AS_WRITTEN);
    };
    if old_header == header {
        return Ok(ColumnPlacement::AS_WRITTEN);
    }
    let mut columns: Vec<&str> = old_header.split(',').collect();
    let old_width = columns.len();
    for c in &wanted {
        if !columns.contains(c) {
            columns.push(c);
        }
    }
    let positions = wanted
        .iter()
        .map(|c| columns.iter().position(|x| x == c).expect("in the union"))
        .collect();
    let mut out = columns.join(",");
    out.push('\n');
    let pad = ",".repeat(columns.len() - old_width);
    for line in lines {
        out.push_str(line);
        out.push_str(&pad);
        out.push('\n');
    }
    std::fs::write(path, out).map_err(io(path))?;
    Ok(ColumnPlacement::new(positions, columns.len()))
}

/// Keeps the header and the rows of the CSV at `path` before `time_s` (first column): the rows
/// a resume from `time_s` writes again are dropped. The times are printed with 10 significant
/// digits ([`push_num`]), up to 5e-10 of the time away from the exact one, so a row of the
/// sample at `time_s` may read just below it: a row within 1e-9 of `time_s` (relative) counts as
/// at `time_s`. Samples are always much further apart than that (20 us at 40 ms: 5e-4).
/// Returns the times of the last two rows kept (None where there are fewer).
pub(crate) fn truncate_csv_after(path: &Path, time_s: f64) -> Result<[Option<f64>; 2]> {
    let Ok(f) = File::open(path) else {
        return Ok([None, None]);
    };
    let mut kept = String::new();
    let mut last = [None, None];
    for (k, line) in BufReader::new(f).lines().enumerate() {
        let line = line.map_err(io(path))?;
        let row_time = line.split(',').next().and_then(|t| t.parse::<f64>().ok());
        let before =
            row_time.is_some_and(|t| t < time_s - PRINTED_TIME_TOLERANCE * time_s.abs().max(1e-6));
        if k == 0 || before {
            kept.push_str(&line);
            kept.push('\n');
        }
        if k > 0 && before {
            last = [last[1], row_time];
        }
    }
    std::fs::write(path, kept).map_err(io(path))?;
    Ok([last[1], last[0]])
}

/// Prepares an output CSV of a run for its resume from `time_s`: the file must exist and
/// reach the checkpoint (its last row no more than one row spacing, with 1 % to spare, before
/// `time_s`); then its rows from `time_s` on are dropped, as [`truncate_csv_after`] does. A
/// file that was deleted, cut or replaced would otherwise be written again with the resumed
/// rows only, and the run would look complete while its record begins at the resume.
pub(crate) fn resume_csv(path: &Path, time_s: f64) -> Result<()> {
    let refuse = |why: String| {
        Error::input(
            path.display().to_string(),
            "--resume",
            format!(
                "{why}: the run cannot go on from its checkpoint at {time_s:.6} s without its \
                 rows up to there; restore the file, or start the run again without --resume"
            ),
        )
    };
    if !path.exists() {
        return Err(refuse("the file is missing".into()));
    }
    let [last, previous] = truncate_csv_after(path, time_s)?;
    let reaches = match (last, previous) {
        (Some(l), Some(p)) => l >= time_s - 1.01 * (l - p).max(0.0),
        // One row, before the checkpoint: no spacing to judge the gap by.
        (Some(_), None) => true,
        (None, _) => time_s <= 0.0,
    };
    if !reaches {
        return Err(refuse(format!(
            "the file's rows end at {} s",
            last.map_or("(no row)".to_string(), |t| format!("{t:.6}"))
        )));
    }
    Ok(())
}

/// Relative tolerance of a time read back from a CSV row (10 significant digits printed).
const PRINTED_TIME_TOLERANCE: f64 = 1e-9;

#[cfg(test)]
mod tests {
    use super::*;

    /// A resume from sample times of a 40 ms run sampled at 50 kHz (the paper cases: 155 steps
    /// of 129 ns a sample, times summed step by step as the solver does): the truncated file
    /// ends with the sample before, whichever way the printed time of the sample itself rounded.
    #[test]
    fn truncation_drops_the_row_of_the_resumed_sample_however_its_time_was_printed() {
        let dir = std::env::temp_dir().join(format!("squeal-truncate-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("forces.csv");
        let dt_s = 2e-5 / 155.0;
        let mut times = Vec::with_capacity(2000);
        let mut t = 0.0;
        for step in 0..2000 * 155 {
            if step % 155 == 0 {
                times.push(t);
            }
            t += dt_s;
        }
        let sample_time = |k: u64| times[k as usize];
        let mut whole = String::from("time_s,force_n\n");
        for k in 0..2000 {
            push_num(&mut whole, sample_time(k));
            whole.push_str(",1.0\n");
        }
        let mut printed_below = 0;
        for k in (1..2000).step_by(7) {
            std::fs::write(&path, &whole).unwrap();
            truncate_csv_after(&path, sample_time(k)).unwrap();
            let text = std::fs::read_to_string(&path).unwrap();
            let last: f64 = text
                .lines()
                .last()
                .unwrap()
                .split(',')
                .next()
                .unwrap()
                .parse()
                .unwrap();
            assert_eq!(text.lines().count() as u64, k + 1, "resume at sample {k}");
            assert!(
                (last - sample_time(k - 1)).abs() < 1e-12,
                "sample {k}: last row {last}"
            );
            let mut row = String::new();
            push_num(&mut row, sample_time(k));
            if row.parse::<f64>().unwrap() < sample_time(k) - 1e-15 {
                printed_below += 1;
            }
        }
        // The case that left a repeated row in `paper` case 2 (2026-11-28) is among them.
        assert!(printed_below > 0);
        let _ = std::fs::remove_dir_all(&dir);
    }
}
