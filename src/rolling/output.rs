//! What a rolling run writes besides the engine's own files: `contact_forces.csv`, the patch
//! snapshots, and the wheel-vibration and contact columns of `histories.csv` (in the frame that
//! moves and turns with the wheelset), as the contact's [`AuxForces`] hooks.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use super::instruments::{contact_kinematics, ContactKinematics, ContactPointRecord};
use super::ring::RingRecorder;
use super::wheel_frame::{deformation_velocity, dot3, wheelset_motion, WheelFrame};
use crate::contact::{patch, ContactPair};
use crate::explicit::run::{push_num, resume_csv, RunSummary};
use crate::explicit::solver::OutputFields;
use crate::explicit::AuxForces;
use crate::mesh::P3;
use crate::{Error, Result};

pub use crate::model::rolling::RimAndHub;

/// Contact plus the rolling outputs: `contact_forces.csv`, patch snapshots and the wheel
/// vibration columns of `histories.csv`.
pub struct RollingContact {
    /// The wheel-rail contact pair.
    pub pair: ContactPair,
    pub(super) rim_node: usize,
    pub(super) rim_nodes: Vec<usize>,
    pub hub_nodes: Vec<usize>,
    pub(super) patch_times_s: Vec<f64>,
    pub(super) slip_threshold_m_per_s: f64,
    pub(super) writer: Option<BufWriter<File>>,
    pub(super) out_dir: PathBuf,
    /// The run resumes from a checkpoint: `contact_forces.csv` is cut at the first sample.
    pub(super) resuming: bool,
    /// Start of the current loss of contact (s), if the wheel is off the rail.
    pub(super) lost_since_s: Option<f64>,
    /// Longest loss of contact so far (s).
    pub(super) longest_loss_s: f64,
    /// The axle-end rigid body (its reaction is the forward guide's force).
    pub(super) axle_body: usize,
    /// Reference lateral position of the wheel's tape circle (m).
    pub(super) tape_circle_y_m: f64,
    /// The wheel's frame: its axis and rolling direction ([`WheelFrame`]).
    pub(super) frame: WheelFrame,
    /// Per slave: how far the angle of attack moved its reference position sideways (m; empty
    /// for an upright wheelset), so that the contact point on the wheel profile and the
    /// lateral offset are read in the wheel's own frame.
    pub(super) slave_yaw_shift_y_m: Vec<f64>,
    /// Tape-circle position of first flange contact from the profiles (m), if any.
    pub(super) flange_contact_wheel_y_m: Option<f64>,
    /// Contact kinematics of the last sample.
    pub(super) kinematics: Option<ContactKinematics>,
    /// Contact point and flange clearance over the run.
    pub contact_point: Option<ContactPointRecord>,
    /// Longitudinal force of the forward guide on the axle at the last sample (N).
    pub(super) forward_guide_force_n: f64,
    /// Writes the run's record at each periodic checkpoint (set by the rolling run).
    pub(super) checkpoint_record: Option<CheckpointRecord>,
    /// The ring of rim nodes recorded by nodal diameter (`ring.csv`), when the case asks.
    pub(super) ring: Option<RingRecorder>,
}

/// What writes a rolling run's record at a checkpoint: the engine's summary then, and the
/// contact's monitors.
pub(super) type CheckpointRecord =
    Box<dyn FnMut(&RunSummary, &RollingContact) -> Result<()> + Send + Sync>;

impl RollingContact {
    /// The outputs of a rolling run over `pair`: `axle_body` is the rigid body whose reaction is
    /// the forward guide's force; `wheel_centre_m` the wheel centre at the tape circle and
    /// `axis` the axle's axis ([`crate::model::rolling::yawed_axle_axis`]); `reference` the
    /// mesh's node positions (the yawed wheelset's).
    pub fn new(
        pair: ContactPair,
        nodes: RimAndHub,
        output: &crate::model::case::OutputSpec,
        axle_body: usize,
        wheel_centre_m: P3,
        axis: P3,
        reference: &[P3],
    ) -> Result<RollingContact> {
        let tape_circle_y_m = wheel_centre_m[1];
        // From the profiles: where the flange would touch the rail if the wheel moved towards
        // the field side (the flange clearance is measured against it).
        let flange_contact_wheel_y_m =
            crate::kalker::profiles::flange_contact_wheel_y_m(tape_circle_y_m);
        let frame = WheelFrame::new(axis);
        let slave_yaw_shift_y_m = if frame.is_upright() {
            Vec::new()
        } else {
            // Un-yawed, a node's lateral offset from the centre is its axial coordinate.
            pair.slaves
                .iter()
                .map(|&n| {
                    let r: P3 = [0, 1, 2].map(|i| reference[n][i] - wheel_centre_m[i]);
                    r[1] - dot3(r, axis)
                })
                .collect()
        };
        let ring = nodes.ring.clone().map(RingRecorder::new).transpose()?;
        Ok(RollingContact {
            pair,
            rim_node: nodes.rim_node,
            rim_nodes: nodes.rim_nodes,
            hub_nodes: nodes.hub_nodes,
            patch_times_s: output.patch_times_s.clone(),
            slip_threshold_m_per_s: output.slip_threshold_m_per_s,
            writer: None,
            out_dir: PathBuf::new(),
            resuming: false,
            lost_since_s: None,
            longest_loss_s: 0.0,
            axle_body,
            tape_circle_y_m,
            frame,
            slave_yaw_shift_y_m,
            flange_contact_wheel_y_m,
            kinematics: None,
            contact_point: None,
            forward_guide_force_n: 0.0,
            checkpoint_record: None,
            ring,
        })
    }

    /// Flange clearance (mm) for the lateral offset of the tread at the contact; NaN when the
    /// profiles give no flange contact.
    fn flange_clearance_mm(&self, k: &ContactKinematics) -> f64 {
        match self.flange_contact_wheel_y_m {
            Some(y) => (y - (self.tape_circle_y_m + k.lateral_offset_m)) * 1e3,
            None => f64::NAN,
        }
    }
}

/// Header of `contact_forces.csv`: forces on the wheel (N) in track axes: the totals
/// (normal plus friction parts) per axis, the friction parts alone (`*_creep_force_n`), their
/// magnitude (`creep_force_n`) and the traction bound `sum mu |f_N|`.
/// Then where the contact sits (see [`instruments`]): wheel profile coordinate S, rail lateral
/// position, contact angle, and the flange clearance.
pub const CONTACT_FORCE_COLUMNS: &str = "time_s,normal_force_n,longitudinal_force_n,lateral_force_n,vertical_force_n,creep_force_n,traction_bound_n,traction_coefficient,contact_nodes,max_penetration_m,longitudinal_creep_force_n,lateral_creep_force_n,contact_wheel_s_mm,contact_rail_y_mm,contact_angle_deg,flange_clearance_mm";

impl RollingContact {
    fn write_forces(&mut self, time_s: f64) -> Result<()> {
        let path = self.out_dir.join("contact_forces.csv");
        if self.writer.is_none() {
            // On resume, the first sample is the first after the checkpoint: rows from its time
            // on are rewritten.
            let append = self.resuming;
            if append {
                resume_csv(&path, time_s)?;
            }
            let file = std::fs::OpenOptions::new()
                .create(true)
                .write(true)
                .append(append)
                .truncate(!append)
                .open(&path)
                .map_err(|e| Error::io(&path, e))?;
            let mut w = BufWriter::new(file);
            if !append {
                writeln!(w, "{CONTACT_FORCE_COLUMNS}").map_err(|e| Error::io(&path, e))?;
            }
            self.writer = Some(w);
        }
        let (normal, tangential, bound) = self.pair.resultants();
        let mut n_mag = 0.0;
        let mut count = 0usize;
        let mut deepest: f64 = 0.0;
        for s in &self.pair.state {
            if s.active {
                n_mag += s.normal_force_n;
                count += 1;
                deepest = deepest.max(s.penetration_m);
            }
        }
        // Lift-off bookkeeping: a wheel off the rail for long (or derailed) is reported.
        if count == 0 {
            let since = *self.lost_since_s.get_or_insert(time_s);
            self.longest_loss_s = self.longest_loss_s.max(time_s - since);
        } else {
            self.lost_since_s = None;
        }
        let total = [0, 1, 2].map(|i| normal[i] + tangential[i]);
        let creep = (tangential[0].powi(2) + tangential[1].powi(2) + tangential[2].powi(2)).sqrt();
        let coefficient = if n_mag > 0.0 { total[0] / n_mag } else { 0.0 };
        let mut row = String::with_capacity(256);
        push_num(&mut row, time_s);
        for x in [
            n_mag,
            total[0],
            total[1],
            total[2],
            creep,
            bound,
            coefficient,
        ] {
            row.push(',');
            push_num(&mut row, x);
        }
        row.push_str(&format!(",{count},"));
        push_num(&mut row, deepest);
        // The tangential (friction) parts alone: the totals above also hold the normal force's
        // components along the inclined contact normal.
        for x in [tangential[0], tangential[1]] {
            row.push(',');
            push_num(&mut row, x);
        }
        let point = match (count > 0, self.kinematics) {
            (true, Some(k)) => [
                k.wheel_s_mm,
                k.rail_y_mm,
                k.contact_angle_deg,
                self.flange_clearance_mm(&k),
            ],
            _ => [f64::NAN; 4],
        };
        for x in point {
            row.push(',');
            push_num(&mut row, x);
        }
        row.push('\n');
        if let Some(w) = self.writer.as_mut() {
            w.write_all(row.as_bytes())
                .map_err(|e| Error::io(&path, e))?;
        }
        Ok(())
    }

    /// Flushes `contact_forces.csv` and `ring.csv`.
    pub fn flush(&mut self) -> Result<()> {
        if let Some(ring) = self.ring.as_mut() {
            ring.flush()?;
        }
        let path = self.out_dir.join("contact_forces.csv");
        if let Some(w) = self.writer.as_mut() {
            w.flush().map_err(|e| Error::io(&path, e))?;
        }
        Ok(())
    }
}

/// Wheel vibration columns of `histories.csv`.
pub const VIBRATION_COLUMNS: [&str; 7] = [
    "lateral_velocity_m_per_s",
    "vertical_velocity_m_per_s",
    "longitudinal_velocity_m_per_s",
    "rim_mean_lateral_velocity_m_per_s",
    "rim_mean_vertical_velocity_m_per_s",
    "rim_mean_longitudinal_velocity_m_per_s",
    "wheel_spin_rad_per_s",
];

/// Contact and guide columns of `histories.csv` (after [`VIBRATION_COLUMNS`]); none starts
/// with a direction word, so `--signal lateral` still names one column:
/// - the n >= 1 part of the rim's lateral vibration: rim point minus rim mean (an n = 0 mode
///   moves every rim point alike and cancels);
/// - the lateral velocities of tread and rail head at the contact, and the pressure-weighted
///   lateral and longitudinal micro-slip velocities (divided by the rolling speed: creepages),
///   see [`instruments`];
/// - the longitudinal force of the forward guide on the axle (0 without it).
pub const CONTACT_HISTORY_COLUMNS: [&str; 6] = [
    "rim_point_minus_mean_lateral_velocity_m_per_s",
    "contact_tread_lateral_velocity_m_per_s",
    "contact_rail_lateral_velocity_m_per_s",
    "microslip_lateral_m_per_s",
    "microslip_longitudinal_m_per_s",
    "forward_guide_force_n",
];

impl AuxForces for RollingContact {
    fn add_forces(&mut self, time_s: f64, dt_s: f64, u: &[P3], v: &[P3], force: &mut [P3]) {
        self.pair.add_forces(time_s, dt_s, u, v, force);
    }

    fn add_forces_predicted(
        &mut self,
        time_s: f64,
        dt_s: f64,
        u: &[P3],
        v: &[P3],
        force: &mut [P3],
        predictor: &crate::explicit::aux::StepPredictor,
    ) {
        self.pair
            .add_forces_predicted(time_s, dt_s, u, v, force, predictor);
    }

    fn force_nodes(&self) -> Option<Vec<usize>> {
        self.pair.force_nodes()
    }

    fn stiffness_terms(&self, out: &mut Vec<crate::explicit::aux::RankOneStiffness>) {
        self.pair.stiffness_terms(out);
    }

    fn on_sample(&mut self, time_s: f64, _out_dir: &Path) -> Result<()> {
        self.write_forces(time_s)
    }

    fn snapshot_fields(&self, node_count: usize) -> Vec<(String, Vec<P3>)> {
        self.pair.snapshot_fields(node_count)
    }

    fn history_columns(&self) -> Vec<String> {
        VIBRATION_COLUMNS
            .iter()
            .chain(CONTACT_HISTORY_COLUMNS.iter())
            .map(|s| s.to_string())
            .collect()
    }

    fn push_history_values(
        &mut self,
        time_s: f64,
        reference: &[P3],
        output: &OutputFields,
        row: &mut String,
    ) -> Result<()> {
        let axis = self.frame.axis;
        let motion = wheelset_motion(&self.hub_nodes, reference, output, axis);
        let omega = motion.2;
        let point = deformation_velocity(self.rim_node, reference, output, motion, axis);
        let mut mean = [0.0; 3];
        for &nd in &self.rim_nodes {
            let d = deformation_velocity(nd, reference, output, motion, axis);
            for i in 0..3 {
                mean[i] += d[i] / self.rim_nodes.len() as f64;
            }
        }
        // Lateral (along the axle), vertical, longitudinal (the rolling direction).
        let point = self.frame.components(point);
        let mean = self.frame.components(mean);
        if let Some(ring) = self.ring.as_mut() {
            let out = (self.out_dir.as_path(), self.resuming);
            ring.record(time_s, reference, output, motion, &self.frame, out)?;
        }
        for x in [
            point[0], point[1], point[2], mean[0], mean[1], mean[2], omega,
        ] {
            row.push(',');
            push_num(row, x);
        }
        self.kinematics = contact_kinematics(
            &self.pair,
            reference,
            output,
            self.tape_circle_y_m,
            &self.slave_yaw_shift_y_m,
        );
        self.forward_guide_force_n = output
            .rigid_reaction_force_n
            .get(self.axle_body)
            .map_or(0.0, |r| r[0]);
        let k = self.kinematics.unwrap_or_default();
        if let Some(kin) = self.kinematics {
            let clearance = self.flange_clearance_mm(&kin);
            let flange_y_mm = self.flange_contact_wheel_y_m.map_or(f64::NAN, |y| y * 1e3);
            match self.contact_point.as_mut() {
                Some(record) => record.update(&kin, clearance),
                None => {
                    self.contact_point =
                        Some(ContactPointRecord::start(&kin, clearance, flange_y_mm))
                }
            }
        }
        for x in [
            point[0] - mean[0],
            k.tread_lateral_velocity_m_per_s,
            k.rail_lateral_velocity_m_per_s,
            k.lateral_microslip_m_per_s,
            k.longitudinal_microslip_m_per_s,
            self.forward_guide_force_n,
        ] {
            row.push(',');
            push_num(row, x);
        }
        // A resumed run does not repeat the snapshots before its restart.
        if self.resuming {
            self.patch_times_s.retain(|&t| t >= time_s - 1e-9);
        }
        // Patch snapshots at the first sample at or after each requested time.
        while let Some(&t) = self.patch_times_s.first() {
            if t > time_s + 1e-12 {
                break;
            }
            let dir = self.out_dir.join("patches");
            std::fs::create_dir_all(&dir).map_err(|e| Error::io(&dir, e))?;
            patch::write_snapshot(
                &self.pair,
                reference,
                &output.displacement,
                time_s,
                self.slip_threshold_m_per_s,
                &dir,
            )?;
            self.patch_times_s.remove(0);
        }
        Ok(())
    }

    fn on_checkpoint(&mut self, summary: &RunSummary) -> Result<()> {
        // The record reads `contact_forces.csv` as written so far.
        self.flush()?;
        let Some(mut write) = self.checkpoint_record.take() else {
            return Ok(());
        };
        let written = write(summary, self);
        self.checkpoint_record = Some(write);
        written
    }

    fn checkpoint_state(&self) -> Vec<f64> {
        self.pair.checkpoint_state()
    }

    fn restore_state(&mut self, state: &[f64]) -> Result<()> {
        self.pair.restore_state(state)
    }
}
