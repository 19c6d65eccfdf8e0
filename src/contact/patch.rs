//! Contact-patch snapshots: per slave node in contact its
//! position in the patch, pressure, shear stress vector, micro-slip velocity vector, and
//! adhesion/slip by two criteria (shear at the traction bound; micro-slip above a threshold).
//! Written as CSV (every field) and as the JSON the Kalker comparison reads
//! ([`crate::kalker::snapshot::PatchSnapshot`]).

use std::path::Path;

use serde::Serialize;

use super::ContactPair;
use crate::kalker::snapshot::{PatchPoint, PatchSnapshot};
use crate::mesh::P3;
use crate::{Error, Result};

/// One node of a patch snapshot.
#[derive(Clone, Debug, Serialize)]
pub struct PatchNode {
    /// Node id.
    pub node: usize,
    /// Current position (m).
    pub position_m: P3,
    /// Pressure `f_N / A` (Pa).
    pub pressure_pa: f64,
    /// Shear stress vector `f_T / A` (Pa).
    pub shear_pa: P3,
    /// Micro-slip velocity (m/s).
    pub slip_velocity_m_per_s: P3,
    /// Shear at the traction bound.
    pub slip_by_bound: bool,
    /// Micro-slip speed above the threshold.
    pub slip_by_velocity: bool,
}

/// Nodes of the pair currently in contact.
pub fn patch_nodes(
    pair: &ContactPair,
    reference: &[P3],
    u: &[P3],
    slip_threshold_m_per_s: f64,
) -> Vec<PatchNode> {
    let mut out = Vec::new();
    for (k, s) in pair.state.iter().enumerate() {
        if !s.active {
            continue;
        }
        let n = pair.slaves[k];
        let area = pair.slave_area_m2[k].max(1e-300);
        let speed = s
            .slip_velocity_m_per_s
            .iter()
            .map(|c| c * c)
            .sum::<f64>()
            .sqrt();
        out.push(PatchNode {
            node: n,
            position_m: [0, 1, 2].map(|d| reference[n][d] + u[n][d]),
            pressure_pa: s.normal_force_n / area,
            shear_pa: s.tangential_force_n.map(|f| f / area),
            slip_velocity_m_per_s: s.slip_velocity_m_per_s,
            slip_by_bound: s.at_bound,
            slip_by_velocity: speed > slip_threshold_m_per_s,
        });
    }
    out
}

/// Writes `patch_<t>.csv` and `patch_<t>.json` into `dir`; returns the JSON path.
pub fn write_snapshot(
    pair: &ContactPair,
    reference: &[P3],
    u: &[P3],
    time_s: f64,
    slip_threshold_m_per_s: f64,
    dir: &Path,
) -> Result<std::path::PathBuf> {
    let nodes = patch_nodes(pair, reference, u, slip_threshold_m_per_s);
    let stem = format!("patch_{:09.1}us", time_s * 1e6);
    let mut csv = String::from(
        "node,x_m,y_m,z_m,pressure_pa,shear_x_pa,shear_y_pa,shear_z_pa,slip_vx_m_per_s,slip_vy_m_per_s,slip_vz_m_per_s,slip_by_bound,slip_by_velocity\n",
    );
    for p in &nodes {
        csv.push_str(&format!(
            "{},{},{},{},{},{},{},{},{},{},{},{},{}\n",
            p.node,
            p.position_m[0],
            p.position_m[1],
            p.position_m[2],
            p.pressure_pa,
            p.shear_pa[0],
            p.shear_pa[1],
            p.shear_pa[2],
            p.slip_velocity_m_per_s[0],
            p.slip_velocity_m_per_s[1],
            p.slip_velocity_m_per_s[2],
            p.slip_by_bound as u8,
            p.slip_by_velocity as u8
        ));
    }
    let csv_path = dir.join(format!("{stem}.csv"));
    std::fs::write(&csv_path, csv).map_err(|e| Error::io(&csv_path, e))?;
    let (normal, tangential, bound) = pair.resultants();
    let normal_force =
        (normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]).sqrt();
    let snapshot = PatchSnapshot {
        time_s,
        normal_force_n: normal_force,
        force_x_n: tangential[0],
        force_y_n: tangential[1],
        mu: if normal_force > 0.0 {
            bound / normal_force
        } else {
            0.0
        },
        normal_lateral_fraction: (normal_force > 0.0).then(|| normal[1] / normal_force),
        points: nodes
            .iter()
            .map(|p| PatchPoint {
                x_m: p.position_m[0],
                y_m: p.position_m[1],
                pressure_pa: p.pressure_pa,
                slip: p.slip_by_bound,
            })
            .collect(),
    };
    let json_path = dir.join(format!("{stem}.json"));
    let text =
        serde_json::to_string_pretty(&snapshot).map_err(|e| Error::Numerical(e.to_string()))?;
    std::fs::write(&json_path, text).map_err(|e| Error::io(&json_path, e))?;
    Ok(json_path)
}
