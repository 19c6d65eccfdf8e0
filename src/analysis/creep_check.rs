//! The quasi-steady creep forces of a yawed wheelset's run against Kalker's exact theory
//! (issue 57, item 1).
//!
//! Method: over a window of `contact_forces.csv`, the means of the normal force, the
//! longitudinal and lateral creep forces and the contact's position and angle; the lateral
//! creep force's means over the window's two halves say whether it is quasi-steady. Kalker's
//! exact theory is then solved at the run's own contact ([`kalker_forces_at_sample`]): its
//! normal force, the profiles' curvatures and the spin at its contact point, the lateral
//! creepage `eta = sin(psi)` of the angle of attack, and the longitudinal creepage that gives
//! the run's longitudinal force. The run's lateral creep force over Kalker's is the check;
//! `|F| / (mu N)` says how saturated the contact is.

use std::path::Path;

use serde::Serialize;

use crate::kalker::Creepages;
use crate::material::Material;
use crate::model::case::LoadedCase;
use crate::stability::operating::{kalker_forces_at_sample, RunSample};
use crate::table::Table;
use crate::{Error, Result};

/// A run's creep forces over a window against Kalker's.
#[derive(Clone, Debug, Serialize)]
pub struct CreepCheck {
    /// The window (ms).
    pub window_ms: [f64; 2],
    /// Mean normal force (N).
    pub normal_force_n: f64,
    /// Mean creep forces (Fx, Fy) of the run on the wheel (N).
    pub run_creep_force_n: [f64; 2],
    /// Mean lateral creep force over each half of the window (N).
    pub lateral_halves_n: [f64; 2],
    /// Whether the two halves' means lie within [`QUASI_STEADY_TOLERANCE`] of each other.
    pub quasi_steady: bool,
    /// Mean contact angle (deg).
    pub contact_angle_deg: f64,
    /// Kalker's creepages (eta of the angle of attack, xi for the run's Fx, the spin).
    pub creepages: Creepages,
    /// Kalker's creep forces (N).
    pub kalker_creep_force_n: [f64; 2],
    /// mu of the case's law at the Kalker slip speed.
    pub mu: f64,
    /// Run's lateral creep force over Kalker's.
    pub lateral_ratio: f64,
    /// `|F_run| / (mu N)`.
    pub saturation: f64,
}

/// Relative difference between the window's halves' mean lateral forces within which the force
/// counts as quasi-steady (fixed in docs/curving.md before the runs).
pub const QUASI_STEADY_TOLERANCE: f64 = 0.05;

/// The creep check of the run in `run_dir` of the case `loaded` over `[from_ms, to_ms]`;
/// `nominal_radius_m` is the wheel's tread radius at the tape circle.
pub fn check_creep_forces(
    loaded: &LoadedCase,
    run_dir: &Path,
    from_ms: f64,
    to_ms: f64,
    nominal_radius_m: f64,
    material: Material,
) -> Result<CreepCheck> {
    let path = run_dir.join("contact_forces.csv");
    let table = Table::read(&path)?;
    let col = |name: &str| {
        table.column(name).ok_or_else(|| {
            Error::input(
                path.display().to_string(),
                name,
                "missing column (a run of `squeal simulate` writes it)",
            )
        })
    };
    let t = col("time_s")?;
    let inside: Vec<usize> = (0..t.len())
        .filter(|&k| t[k] * 1e3 >= from_ms && t[k] * 1e3 <= to_ms)
        .collect();
    if inside.len() < 4 {
        return Err(Error::input(
            path.display().to_string(),
            "window",
            format!(
                "needs at least 4 samples in [{from_ms}, {to_ms}] ms, got {}",
                inside.len()
            ),
        ));
    }
    let mean = |name: &str, ks: &[usize]| -> Result<f64> {
        let c = col(name)?;
        Ok(ks.iter().map(|&k| c[k]).sum::<f64>() / ks.len() as f64)
    };
    let normal = mean("normal_force_n", &inside)?;
    let fx = mean("longitudinal_creep_force_n", &inside)?;
    let fy = mean("lateral_creep_force_n", &inside)?;
    let half = inside.len() / 2;
    let halves = [
        mean("lateral_creep_force_n", &inside[..half])?,
        mean("lateral_creep_force_n", &inside[half..])?,
    ];
    let quasi_steady = (halves[0] - halves[1]).abs()
        <= QUASI_STEADY_TOLERANCE * halves[0].abs().max(halves[1].abs());
    let angle = mean("contact_angle_deg", &inside)?;
    let sample = RunSample {
        run_dir: run_dir.to_path_buf(),
        time_ms: 0.5 * (from_ms + to_ms),
        normal_force_n: normal,
        creep_force_n: [fx, fy],
        contact: Some((
            mean("contact_wheel_s_mm", &inside)?,
            mean("contact_rail_y_mm", &inside)? * 1e-3,
            angle,
        )),
        wheel_y_displacement_m: 0.0,
        wheel_x_m: loaded.scenario.scenario.wheel_position.x_m,
    };
    let eta = loaded.case.angle_of_attack_rad().sin();
    let (creepages, kalker, mu) =
        kalker_forces_at_sample(loaded, &sample, nominal_radius_m, material, eta)?;
    Ok(CreepCheck {
        window_ms: [from_ms, to_ms],
        normal_force_n: normal,
        run_creep_force_n: [fx, fy],
        lateral_halves_n: halves,
        quasi_steady,
        contact_angle_deg: angle,
        creepages,
        kalker_creep_force_n: kalker,
        mu,
        lateral_ratio: fy / kalker[1],
        saturation: fx.hypot(fy) / (mu * normal),
    })
}
