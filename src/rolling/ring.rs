//! The ring of rim nodes a run records by nodal diameter: `ring.csv` and `ring.json`.
//!
//! At each output sample, every ring node's deformation velocity (its velocity less the
//! wheelset's rigid motion, [`super::wheel_frame::deformation_velocity`]) is split in the wheel's
//! turning frame into
//! - lateral: along the axle axis `a`,
//! - radial: along `e_r = r_perp / |r_perp|`, `r_perp` the node's position from the wheel
//!   centre across the axis,
//! - circumferential: along `e_theta = a x e_r`,
//!
//! and each of the three fields around the ring is decomposed into its harmonics `n =
//! 0..=n_max` by the ring's discrete Fourier series ([`crate::signal::ring`]) over the nodes'
//! material angles. A mode of n nodal diameters moves the harmonic n only, whatever its
//! orientation on the wheel or the wheel's turn; n = 0 is the mean of the ring.
//!
//! `ring.csv`: `time_s`, then per n the columns `n{n}_{direction}_{cos|sin}_m_per_s` (n = 0
//! has no sine part), in the order lateral, radial, circumferential. `ring.json`: the nodes,
//! their angles, the radius and the column layout.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use serde::Serialize;

use super::wheel_frame::{deformation_velocity, dot3, WheelFrame};
use crate::explicit::run::resume_csv;
use crate::explicit::solver::OutputFields;
use crate::mesh::P3;
use crate::model::rolling::RingNodes;
use crate::signal::ring::RingDft;
use crate::{Error, Result};

/// File name of the ring's harmonics.
pub const RING_CSV: &str = "ring.csv";
/// File name of the ring's description.
pub const RING_JSON: &str = "ring.json";

/// The three directions of the ring's velocities, in the order of `ring.csv`.
pub const RING_DIRECTIONS: [&str; 3] = ["lateral", "radial", "circumferential"];

/// The column name of harmonic `n`, direction `direction`, part `cos` or `sin`.
pub fn ring_column(n: usize, direction: &str, part: &str) -> String {
    format!("n{n}_{direction}_{part}_m_per_s")
}

/// The columns of `ring.csv` after `time_s`, for harmonics `0..=n_max`.
pub fn ring_columns(n_max: usize) -> Vec<String> {
    let mut columns = Vec::new();
    for n in 0..=n_max {
        for direction in RING_DIRECTIONS {
            columns.push(ring_column(n, direction, "cos"));
            if n > 0 {
                columns.push(ring_column(n, direction, "sin"));
            }
        }
    }
    columns
}

/// `ring.json`.
#[derive(Clone, Debug, Serialize)]
pub struct RingDescription {
    /// Mesh node numbers of the ring, in order of angle.
    pub nodes: Vec<usize>,
    /// Their material angles (rad): `atan2(x - x_c, z - z_c)` on the upright wheel.
    pub angles_rad: Vec<f64>,
    /// Radius of the ring (m).
    pub radius_m: f64,
    /// Highest harmonic recorded.
    pub n_max: usize,
    /// The directions, in column order.
    pub directions: Vec<String>,
    /// How the columns are named and what they hold.
    pub columns: String,
}

/// Records the ring's harmonics at each output sample (allocation-free after the first).
pub struct RingRecorder {
    ring: RingNodes,
    dft: RingDft,
    /// Per direction, the values around the ring (scratch).
    values: [Vec<f64>; 3],
    /// Per direction, the harmonics' cosine and sine parts (scratch).
    cos_parts: [Vec<f64>; 3],
    sin_parts: [Vec<f64>; 3],
    row: String,
    writer: Option<BufWriter<File>>,
    /// `ring.csv` once opened (for the errors of its writes).
    path: PathBuf,
}

impl RingRecorder {
    /// A recorder of `ring`.
    pub fn new(ring: RingNodes) -> Result<RingRecorder> {
        let count = ring.nodes.len();
        let dft = RingDft::new(count, ring.theta0_rad, ring.n_max)?;
        let n_max = ring.n_max;
        Ok(RingRecorder {
            ring,
            dft,
            values: [vec![0.0; count], vec![0.0; count], vec![0.0; count]],
            cos_parts: std::array::from_fn(|_| vec![0.0; n_max + 1]),
            sin_parts: std::array::from_fn(|_| vec![0.0; n_max + 1]),
            row: String::with_capacity(64 * (6 * n_max + 4)),
            writer: None,
            path: PathBuf::new(),
        })
    }

    /// The ring's description (`ring.json`).
    pub fn description(&self) -> RingDescription {
        let count = self.ring.nodes.len();
        RingDescription {
            nodes: self.ring.nodes.clone(),
            angles_rad: (0..count)
                .map(|k| self.ring.theta0_rad + std::f64::consts::TAU * k as f64 / count as f64)
                .collect(),
            radius_m: self.ring.radius_m,
            n_max: self.ring.n_max,
            directions: RING_DIRECTIONS.iter().map(|s| s.to_string()).collect(),
            columns: "n{n}_{direction}_{cos|sin}_m_per_s: the harmonic n of the ring's \
                      deformation velocity in that direction, f(theta) = sum_n c_n cos(n theta) \
                      + s_n sin(n theta) (n = 0: the ring's mean)"
                .into(),
        }
    }

    /// Opens `ring.csv` (and writes `ring.json`) in `out_dir`; on a resume, keeps the rows
    /// before `time_s` and appends.
    fn open(&mut self, out_dir: &Path, time_s: f64, resuming: bool) -> Result<()> {
        let path = out_dir.join(RING_CSV);
        if resuming {
            resume_csv(&path, time_s)?;
        } else {
            let json_path = out_dir.join(RING_JSON);
            let text = serde_json::to_string_pretty(&self.description())
                .map_err(|e| Error::io(&json_path, std::io::Error::other(e)))?;
            std::fs::write(&json_path, text).map_err(|e| Error::io(&json_path, e))?;
        }
        let file = std::fs::OpenOptions::new()
            .create(true)
            .write(true)
            .append(resuming)
            .truncate(!resuming)
            .open(&path)
            .map_err(|e| Error::io(&path, e))?;
        let mut w = BufWriter::new(file);
        if !resuming {
            let header = ring_columns(self.ring.n_max).join(",");
            writeln!(w, "time_s,{header}").map_err(|e| Error::io(&path, e))?;
        }
        self.writer = Some(w);
        self.path = path;
        Ok(())
    }

    /// One sample: the ring's harmonics at `time_s` from the output fields, given the
    /// wheelset's rigid motion and frame.
    pub fn record(
        &mut self,
        time_s: f64,
        reference: &[P3],
        output: &OutputFields,
        motion: (P3, P3, f64),
        frame: &WheelFrame,
        out: (&Path, bool),
    ) -> Result<()> {
        if self.writer.is_none() {
            self.open(out.0, time_s, out.1)?;
        }
        let axis = frame.axis;
        let centre = motion.0;
        for (k, &nd) in self.ring.nodes.iter().enumerate() {
            let d = deformation_velocity(nd, reference, output, motion, axis);
            let r: P3 =
                [0, 1, 2].map(|i| reference[nd][i] + output.displacement[nd][i] - centre[i]);
            let along = dot3(r, axis);
            let r_perp: P3 = [0, 1, 2].map(|i| r[i] - along * axis[i]);
            let length = dot3(r_perp, r_perp).sqrt().max(f64::MIN_POSITIVE);
            let e_r = r_perp.map(|x| x / length);
            let e_theta = [
                axis[1] * e_r[2] - axis[2] * e_r[1],
                axis[2] * e_r[0] - axis[0] * e_r[2],
                axis[0] * e_r[1] - axis[1] * e_r[0],
            ];
            self.values[0][k] = dot3(d, axis);
            self.values[1][k] = dot3(d, e_r);
            self.values[2][k] = dot3(d, e_theta);
        }
        for dir in 0..3 {
            self.dft.transform(
                &self.values[dir],
                &mut self.cos_parts[dir],
                &mut self.sin_parts[dir],
            );
        }
        self.row.clear();
        push_short(&mut self.row, time_s, 9);
        for n in 0..=self.ring.n_max {
            for dir in 0..3 {
                self.row.push(',');
                push_short(&mut self.row, self.cos_parts[dir][n], 6);
                if n > 0 {
                    self.row.push(',');
                    push_short(&mut self.row, self.sin_parts[dir][n], 6);
                }
            }
        }
        self.row.push('\n');
        if let Some(w) = self.writer.as_mut() {
            w.write_all(self.row.as_bytes())
                .map_err(|e| Error::io(&self.path, e))?;
        }
        Ok(())
    }

    /// Flushes `ring.csv`.
    pub fn flush(&mut self) -> Result<()> {
        if let Some(w) = self.writer.as_mut() {
            w.flush().map_err(|e| Error::io(&self.path, e))?;
        }
        Ok(())
    }
}

/// `x` in scientific notation with `digits` digits after the point (7 significant digits
/// for the velocities: the ring's file is the largest of a long run's).
fn push_short(s: &mut String, x: f64, digits: usize) {
    use std::fmt::Write as _;
    let _ = write!(s, "{x:.digits$e}");
}
