//! Timing of the stability analysis (`squeal bench stability`): one operating point with a
//! given number of wheel modal coordinates, and a sweep of the lateral creepage.
//!
//! What is timed is what a user waits for once the wheel's modes are known: the contact
//! linearisation (Kalker's exact theory, central differences) and the coupled system's dense
//! eigen-decomposition with eigenvectors (participation). The wheel's modal solve and the
//! rail's modal model are set-up, reported apart. The wheel's coordinates are its 3D modes (an
//! n >= 1 pair counts twice, as the 3D solver finds it twice); with more than the labelled band
//! (10 kHz) holds, the wheel is solved further ([`WheelModes::solve_band`]), which changes only
//! the count, not what is timed.

use std::time::Instant;

use serde::Serialize;

use super::contact::linearise;
use super::model::{wheel_file, Settings, StabilityModel};
use super::operating::from_case;
use super::rail::Track;
use super::sweep::{run_sweep, SweepParameter, SweepSpec};
use super::wheel::WheelModes;
use crate::input::wheel::WheelSpec;
use crate::model::case::LoadedCase;
use crate::{Error, Result};

/// What the benchmark measured.
#[derive(Clone, Debug, Serialize)]
pub struct StabilityBench {
    /// Wheel modal coordinates in the coupled system.
    pub wheel_coordinates: usize,
    /// Rail modal coordinates.
    pub rail_coordinates: usize,
    /// Highest wheel frequency kept (Hz).
    pub wheel_fmax_hz: f64,
    /// Wall time of the wheel's modal solve (s), set-up.
    pub wheel_solve_seconds: f64,
    /// Wall time of the rail's modal model (s), set-up.
    pub rail_model_seconds: f64,
    /// One operating point, linearisation + eigenvalues (s): the median of the repeats.
    pub point_seconds: f64,
    /// The linearisation alone (s), median.
    pub linearise_seconds: f64,
    /// Repeats of the single point.
    pub repeats: usize,
    /// Sweep points.
    pub sweep_points: usize,
    /// Wall time of the sweep (s).
    pub sweep_seconds: f64,
    /// Rayon threads the sweep ran on.
    pub threads: usize,
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// The wheel's modes from `fmax_hz` up, the band grown by 1.25 until it holds
/// `wheel_coordinates` coordinates (an n >= 1 mode gives two), with the solves' total time (s).
fn wheel_with_coordinates(
    spec: &WheelSpec,
    fmax_hz: f64,
    wheel_coordinates: usize,
) -> Result<(WheelModes, f64)> {
    let coordinates =
        |w: &WheelModes| -> usize { w.modes.iter().map(|m| 1 + (m.harmonic >= 1) as usize).sum() };
    let mut fmax_hz = fmax_hz;
    let mut solve_seconds = 0.0;
    loop {
        let t = Instant::now();
        let w = WheelModes::solve_band(spec, fmax_hz)?;
        solve_seconds += t.elapsed().as_secs_f64();
        if coordinates(&w) >= wheel_coordinates {
            return Ok((w, solve_seconds));
        }
        fmax_hz *= 1.25;
        if fmax_hz > 50_000.0 {
            return Err(Error::input(
                "command line",
                "--wheel-modes",
                format!(
                    "the wheel has only {} coordinates below 50 kHz",
                    coordinates(&w)
                ),
            ));
        }
    }
}

/// Time the analysis of `loaded`'s case-file operating point with at least
/// `wheel_coordinates` wheel coordinates (`repeats` times), and an eta sweep of `sweep_points`
/// points over 0..1 % (through the onset of the case-3 mode coupling).
pub fn run(
    loaded: &LoadedCase,
    wheel_coordinates: usize,
    repeats: usize,
    sweep_points: usize,
) -> Result<StabilityBench> {
    if !(1..=2000).contains(&wheel_coordinates) {
        return Err(Error::input(
            "command line",
            "--wheel-modes",
            format!("must be in 1..=2000, got {wheel_coordinates}"),
        ));
    }
    if !(1..=100).contains(&repeats) {
        return Err(Error::input(
            "command line",
            "--repeats",
            format!("must be in 1..=100, got {repeats}"),
        ));
    }
    let settings = Settings::default();
    let path = wheel_file(loaded);
    let spec: WheelSpec = crate::input::read_json(&path)?;
    spec.validate(&path.display().to_string())?;
    let (wheel, solve_seconds) =
        wheel_with_coordinates(&spec, settings.fmax_hz, wheel_coordinates)?;
    let model = StabilityModel {
        wheel,
        track: Track::from_case(loaded)?,
        material: spec.material,
        settings,
    };
    let mut op = from_case(
        loaded,
        model.wheel.mass_kg,
        model.wheel.nominal_radius_m,
        None,
        model.material,
    )?;
    let t = Instant::now();
    let (rail, _) = model.rail(op.wheel_x_m, op.contact_rail_y_m)?;
    let rail_model_seconds = t.elapsed().as_secs_f64();
    // The lowest `wheel_coordinates` coordinates (by frequency).
    let mut wheel = model.wheel.contact_body(
        op.contact_s_mm,
        model.wheel.fmax_hz,
        &settings.wheel_damping,
        None,
    )?;
    wheel
        .dofs
        .sort_by(|a, b| a.omega_rad_per_s.total_cmp(&b.omega_rad_per_s));
    wheel.dofs.truncate(wheel_coordinates);
    let wheel_fmax_hz = wheel
        .dofs
        .last()
        .map_or(0.0, |d| d.omega_rad_per_s / std::f64::consts::TAU);
    // Eigenvalues reported up to the wheel's highest kept frequency.
    let model = StabilityModel {
        settings: Settings {
            fmax_hz: wheel_fmax_hz,
            ..settings
        },
        ..model
    };
    let mut point = Vec::new();
    let mut lin = Vec::new();
    for _ in 0..repeats {
        let t = Instant::now();
        let a = model.analyse(&op, &wheel, &rail)?;
        point.push(t.elapsed().as_secs_f64());
        std::hint::black_box(a);
        let t = Instant::now();
        std::hint::black_box(linearise(
            &op.contact_state(model.material),
            model.settings.tangential,
        )?);
        lin.push(t.elapsed().as_secs_f64());
    }
    op.creepages.eta = 0.0;
    let sweep = if sweep_points >= 2 {
        let spec = SweepSpec {
            parameter: SweepParameter::Eta,
            from: 0.0,
            to: 0.01,
            points: sweep_points,
        };
        Some(run_sweep(&model, &op, &wheel, &rail, &spec)?)
    } else {
        None
    };
    Ok(StabilityBench {
        wheel_coordinates: wheel.dofs.len(),
        rail_coordinates: rail.dofs.len(),
        wheel_fmax_hz,
        wheel_solve_seconds: solve_seconds,
        rail_model_seconds,
        point_seconds: median(point),
        linearise_seconds: median(lin),
        repeats,
        sweep_points: if sweep.is_some() { sweep_points } else { 0 },
        sweep_seconds: sweep.map_or(0.0, |s| s.seconds),
        threads: rayon::current_num_threads(),
    })
}
