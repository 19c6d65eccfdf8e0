//! The rail's beam model ([`super::rail`]) against the project's FE track: an impulse response
//! of the explicit engine's track model, transformed, against the beam model's transfer
//! function at the same points.
//!
//! The FE track is the rolling model's track without the wheel: the solid 54E1 rail at 1:40 on
//! its pads, the solid sleepers on the ballast, the same fixed directions and springs
//! ([`crate::model::rolling::track_supports`]), the case's mass damping, no gravity (the
//! response is linear about the unloaded track). A force `F(t)`, a Hann pulse of `pulse_s`, is
//! spread over the rail's cross-section at the contact station in proportion to the nodal
//! masses (a resultant through the section's centre of mass, the load a beam element takes);
//! the response is the section's mass-weighted mean displacement (the centre of mass, the
//! beam's deflection). Both are sampled every step of the central-difference loop.
//!
//! The comparison: with `exp(-sigma t)` as a window on both (so that the record of `duration_s`
//! holds the whole windowed response, `sigma T = 8`: the part cut off is below 3.4e-4 of the
//! start), the ratio of the transforms `U(s) / F(s)`, `U(s) = sum_n u(t_n) exp(-s t_n) dt` at
//! `s = sigma + i w`, is the FE track's transfer function there (the Laplace transform of the
//! impulse response; the trapezoidal sum is exact to O((w dt)^2), below 1e-4 at 5 kHz for the
//! steps here), and the beam model gives its own at the same `s` by a direct solve
//! ([`super::rail::BeamModel::transfer`]). The window adds the damping `sigma` to every mode of
//! both models alike, so it smooths peaks but biases neither; it is the exponential window of
//! impact testing (Ewins, Modal Testing, 2000, section 3.11).

use std::collections::BTreeMap;
use std::time::Instant;

use faer::c64;
use serde::Serialize;

use super::rail::{Direction, SectionPoint, Track};
use crate::explicit::model::NodalLoad;
use crate::explicit::{Curve, Formulation, Model, Solver};
use crate::material::Material;
use crate::mesh::track::{rail_body_stations, track_mesh, TrackLayout};
use crate::mesh::{material, Mesh};
use crate::model::case::RollingCase;
use crate::model::rolling::track_supports;
use crate::{Error, Result};

/// How the impulse response is made and windowed.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct ImpulseSettings {
    /// Length of the record (s).
    pub duration_s: f64,
    /// Width of the Hann force pulse (s): its spectrum falls to half at about 1 / pulse_s,
    /// and to zero at 2 / pulse_s.
    pub pulse_s: f64,
    /// Peak force (N): the response is linear, so only rounding sees it.
    pub force_n: f64,
}

impl ImpulseSettings {
    /// The window's decay rate sigma (1/s): `sigma T = 8`.
    pub fn window_decay_per_s(&self) -> f64 {
        8.0 / self.duration_s
    }
}

impl Default for ImpulseSettings {
    /// 20 ms (the window's sigma 400 /s: 1.3 % damping added at 5 kHz, 6 % at 1 kHz) and a
    /// 0.1 ms pulse (flat within 20 % to 5 kHz, zero at 20 kHz, above the band the comparison
    /// covers so that the mesh's highest modes are barely excited).
    fn default() -> Self {
        ImpulseSettings {
            duration_s: 0.02,
            pulse_s: 1e-4,
            force_n: 1e3,
        }
    }
}

/// The two transfer functions at the comparison frequencies.
#[derive(Clone, Debug, Serialize)]
pub struct RailComparison {
    /// Direction of force and response.
    pub direction: Direction,
    /// The station loaded (m along the rail).
    pub x_m: f64,
    /// Frequencies (Hz).
    pub frequencies_hz: Vec<f64>,
    /// The window's decay rate (1/s): both transfer functions are at `sigma + i 2 pi f`.
    pub window_decay_per_s: f64,
    /// FE track (m/N).
    #[serde(skip)]
    pub fe_m_per_n: Vec<c64>,
    /// Beam model (m/N).
    #[serde(skip)]
    pub beam_m_per_n: Vec<c64>,
    /// Elements of the FE track.
    pub elements: usize,
    /// Nodes of the loaded section.
    pub section_nodes: usize,
    /// Time step (s).
    pub time_step_s: f64,
    /// Steps.
    pub steps: usize,
    /// Wall time of the explicit run (s).
    pub seconds: f64,
}

impl RailComparison {
    /// `|H_fe - H_beam| / |H_beam|` at each frequency.
    pub fn relative_difference(&self) -> Vec<f64> {
        self.fe_m_per_n
            .iter()
            .zip(&self.beam_m_per_n)
            .map(|(a, b)| (a - b).norm() / b.norm())
            .collect()
    }

    /// `20 log10 |H_fe / H_beam|` (dB) at each frequency.
    pub fn level_difference_db(&self) -> Vec<f64> {
        self.fe_m_per_n
            .iter()
            .zip(&self.beam_m_per_n)
            .map(|(a, b)| 20.0 * (a.norm() / b.norm()).log10())
            .collect()
    }
}

/// The explicit model of the track of `layout` with the case's supports and materials (rail
/// in `rail_material`), without gravity.
pub fn fe_track_model(
    layout: &TrackLayout,
    case: &RollingCase,
    rail_material: Material,
    source: &str,
) -> Result<Model> {
    let mesh: Mesh = track_mesh(layout);
    let materials: BTreeMap<u32, Material> = [
        (material::RAIL, rail_material),
        (material::RAIL_BAND, rail_material),
        (material::SLEEPER, case.sleeper_material),
    ]
    .into_iter()
    .collect();
    let (fixed_sets, springs) = track_supports(&mesh, case, source)?;
    let mut model = Model::from_mesh(mesh, &materials, Formulation::default(), source)?;
    model.mass_damping_per_s = case.mass_damping_per_s;
    for (set, directions) in &fixed_sets {
        model.fix_set(set, *directions)?;
    }
    for spring in springs {
        model.add_spring(spring)?;
    }
    Ok(model)
}

/// The rail nodes of the rail body's station nearest `x_m` (a plane of nodes of the extruded
/// rail; the body's stations, since a finer running band, tied on, has stations the body
/// lacks), with the band's nodes where they share the station.
fn section_nodes(model: &Model, layout: &TrackLayout, x_m: f64) -> Result<(f64, Vec<usize>)> {
    let station = rail_body_stations(layout)
        .into_iter()
        .min_by(|a, b| (a - x_m).abs().total_cmp(&(b - x_m).abs()))
        .ok_or_else(|| Error::Mesh("the track has no rail stations".into()))?;
    let mesh = &model.mesh;
    let mut on = vec![false; mesh.nodes.len()];
    for (e, conn) in mesh.elements.iter().enumerate() {
        if matches!(mesh.material[e], material::RAIL | material::RAIL_BAND) {
            for &n in conn {
                if (mesh.nodes[n][0] - station).abs() < 1e-9 {
                    on[n] = true;
                }
            }
        }
    }
    let nodes: Vec<usize> = (0..on.len()).filter(|&n| on[n]).collect();
    if nodes.is_empty() {
        return Err(Error::Mesh(format!(
            "no rail nodes at the station x = {station} m"
        )));
    }
    Ok((station, nodes))
}

/// `sum_n v_n exp(-s t_n) dt` (trapezoidal, the samples starting at t = 0 from rest).
fn transform(t_s: &[f64], values: &[f64], s: c64, dt_s: f64) -> c64 {
    t_s.iter()
        .zip(values)
        .map(|(&t, &v)| (-s * t).exp() * v)
        .fold(c64::new(0.0, 0.0), |a, b| a + b)
        * dt_s
}

/// The FE track's and the beam model's transfer functions in `direction` at the rail station
/// nearest `x_m`, at `sigma + i 2 pi f` for each of `frequencies_hz` (see the module docs).
pub fn compare(
    layout: &TrackLayout,
    case: &RollingCase,
    rail_material: Material,
    x_m: f64,
    direction: Direction,
    settings: &ImpulseSettings,
    frequencies_hz: &[f64],
) -> Result<RailComparison> {
    let source = "rail against the FE track";
    if !(settings.duration_s > 0.0
        && settings.pulse_s > 0.0
        && settings.pulse_s < settings.duration_s)
    {
        return Err(Error::input(
            source,
            "impulse",
            format!(
                "need 0 < pulse_s < duration_s, got {} and {}",
                settings.pulse_s, settings.duration_s
            ),
        ));
    }
    let mut model = fe_track_model(layout, case, rail_material, source)?;
    let elements = model.mesh.elements.len();
    let (station, nodes) = section_nodes(&model, layout, x_m)?;
    let masses: Vec<f64> = nodes.iter().map(|&n| model.nodal_mass_kg[n]).collect();
    let total_mass: f64 = masses.iter().sum();
    // The Hann pulse sin^2(pi t / tau) on 41 points (the curve is linear between them).
    let tau = settings.pulse_s;
    let (times, values): (Vec<f64>, Vec<f64>) = (0..=40)
        .map(|i| {
            let t = tau * i as f64 / 40.0;
            (t, (std::f64::consts::PI * t / tau).sin().powi(2))
        })
        .chain(std::iter::once((settings.duration_s + 1.0, 0.0)))
        .unzip();
    let curve = Curve::new(times, values, "impulse")?;
    let axis = direction.axis();
    for (&n, &m) in nodes.iter().zip(&masses) {
        let mut f = [0.0; 3];
        f[axis] = settings.force_n * m / total_mass;
        model.loads.push(NodalLoad {
            name: format!("impulse_{n}"),
            nodes: vec![n],
            total_force_n: f,
            curve: curve.clone(),
        });
    }
    let mut solver = Solver::new(model, None)?;
    let dt = solver.dt_s;
    let steps = (settings.duration_s / dt).ceil() as usize;
    let t0 = Instant::now();
    let mut t = Vec::with_capacity(steps + 1);
    let mut u = Vec::with_capacity(steps + 1);
    let mut f = Vec::with_capacity(steps + 1);
    let record = |s: &Solver, t: &mut Vec<f64>, u: &mut Vec<f64>, f: &mut Vec<f64>| {
        let mean = nodes
            .iter()
            .zip(&masses)
            .map(|(&n, &m)| m * s.u[n][axis])
            .sum::<f64>()
            / total_mass;
        t.push(s.time_s);
        u.push(mean);
        f.push(settings.force_n * curve.value(s.time_s));
    };
    record(&solver, &mut t, &mut u, &mut f);
    for _ in 0..steps {
        solver.step()?;
        record(&solver, &mut t, &mut u, &mut f);
    }
    let seconds = t0.elapsed().as_secs_f64();
    let sigma = settings.window_decay_per_s();
    let s: Vec<c64> = frequencies_hz
        .iter()
        .map(|&fr| c64::new(sigma, std::f64::consts::TAU * fr))
        .collect();
    let fe: Vec<c64> = s
        .iter()
        .map(|&s| transform(&t, &u, s, dt) / transform(&t, &f, s, dt))
        .collect();
    let track = Track::from_layout(layout, case, rail_material, source)?;
    let beam = track.beam_model(direction, station)?.transfer(
        &s,
        case.mass_damping_per_s,
        SectionPoint::Centroid,
    )?;
    Ok(RailComparison {
        direction,
        x_m: station,
        frequencies_hz: frequencies_hz.to_vec(),
        window_decay_per_s: sigma,
        fe_m_per_n: fe,
        beam_m_per_n: beam,
        elements,
        section_nodes: nodes.len(),
        time_step_s: dt,
        steps,
        seconds,
    })
}
