//! The rolling model of a case on the explicit engine: the model stage's description
//! ([`crate::model::rolling`]) applied to an engine model, the wheel-rail contact pair and its
//! checks before the preload, and the inertia that lets the preload run at its own step.

use std::collections::BTreeMap;

use serde::Serialize;

use super::output::RollingContact;
use crate::contact::ContactPair;
use crate::explicit::model::{RigidBodySpec, TorqueLoad};
use crate::explicit::solver::COURANT_FACTOR;
use crate::explicit::{Formulation, Model, Solver, Spring};
use crate::material::Material;
use crate::mesh::P3;
use crate::model::case::LoadedCase;
use crate::model::rolling::{describe, RollingDescription, G_M_PER_S2};
use crate::{Error, Result};

/// What the builder found, for `run.json`.
#[derive(Clone, Debug, Serialize)]
pub struct ModelInfo {
    /// Nodes and elements.
    pub nodes: usize,
    /// Elements.
    pub elements: usize,
    /// Contact slave nodes and master faces.
    pub contact_slaves: usize,
    /// Master faces.
    pub contact_faces: usize,
    /// Time step (s) and what limits it.
    pub time_step_s: f64,
    /// What limits the step.
    pub time_step_limited_by: String,
    /// Wheel centre (m) and rolling radius (m).
    pub wheel_centre_m: P3,
    /// Rolling radius (m).
    pub rolling_radius_m: f64,
    /// Total static wheel load: sprung mass + wheelset (N).
    pub static_wheel_load_n: f64,
    /// After the preload: `(F_z - W) / W`, the vertical contact force against the static wheel
    /// load.
    pub preload_load_error: f64,
    /// Rim node used for the point histories.
    pub rim_node: usize,
    /// Inertia added for the preload at its own step (kg), if any.
    pub preload_added_mass_kg: f64,
    /// Slaves whose penalty was capped at `m / dt^2` (see `ContactPair::cap_stiffness_for_step`).
    pub contact_slaves_with_capped_penalty: usize,
    /// The largest penalty scale this mesh and step can carry
    /// (`ContactPair::largest_penalty_scale`).
    pub largest_penalty_scale: f64,
    /// Smallest wheel-rail gap measured on the meshes before the preload (m; negative:
    /// penetrating by the meshes' faceting).
    pub initial_gap_m: f64,
    /// How the rolling run steps, and why (`rolling::stepping`).
    pub time_stepping: String,
    /// Multi-rate stepping of the rolling run, when on.
    pub step_levels: Option<StepLevels>,
}

/// The power-of-two step levels of a multi-rate run ([`crate::explicit::multirate`]).
#[derive(Clone, Debug, Serialize)]
pub struct StepLevels {
    /// Elements per level (level k steps at 2^k times the finest step).
    pub elements_per_level: Vec<usize>,
    /// Element work relative to single-rate stepping.
    pub element_work_fraction: f64,
}

/// A built rolling model, ready to run.
pub struct RollingModel {
    /// The engine.
    pub solver: Solver,
    /// Contact and its outputs.
    pub contact: RollingContact,
    /// Nodes of the wheelset (wheel, axle, band), which get the rolling velocity.
    pub wheelset_nodes: Vec<usize>,
    /// The sprung mass node.
    pub sprung_node: usize,
    /// The axle-box node the primary suspension joins to the sprung mass.
    pub axle_box_node: usize,
    /// The rigid body of both axle end faces (index into the model's rigid bodies).
    pub axle_body: usize,
    /// Static compression of the primary suspension under the sprung weight (m).
    pub suspension_static_compression_m: f64,
    /// Facts for `run.json`.
    pub info: ModelInfo,
    /// Inertia added per node for the preload step (empty: none).
    pub preload_added_mass_kg: Vec<f64>,
}

/// The contact against the step, before the preload (20 minutes on the paper model): the
/// penalty of light slaves capped so that contact does not lower the elements' step, a scale
/// the step cannot carry anywhere refused (an input error, not a silent change of the
/// penalty), the wheel required to start on the rail, and the contact's own step bound
/// registered. Returns the number of capped slaves and the clearance found.
fn check_contact_before_preload(
    model: &mut Model,
    pair: &mut ContactPair,
    source: &str,
) -> Result<(usize, crate::contact::Clearance)> {
    let element_step_s = crate::explicit::multirate::element_transits_s(model)
        .into_iter()
        .fold(f64::INFINITY, f64::min);
    let capped = pair.cap_stiffness_for_step(&model.nodal_mass_kg, element_step_s);
    pair.check_penalty_scale_against_step(source, "penalty_scale")?;
    let clearance = pair.check_initial_clearance(
        INITIAL_GAP_LIMIT_M,
        source,
        "model_scenario: wheel_position.initial_gap_mm",
    )?;
    let bound = pair.time_step_bound_s(&model.nodal_mass_kg);
    model.register_time_step_bound("contact penalty", bound);
    Ok((capped, clearance))
}

/// The explicit engine's model of a description: elements, gravity and damping, fixed sets,
/// track springs, the axle body, the sprung mass and its suspension. Returns the model, the
/// axle body's index and the sprung-mass node.
/// The description's mesh moves into the model.
fn engine_model(d: &mut RollingDescription, source: &str) -> Result<(Model, usize, usize)> {
    let mesh = std::mem::take(&mut d.mesh);
    let mut model = Model::from_mesh(mesh, &d.materials, Formulation::default(), source)?;
    model.gravity_m_per_s2 = d.gravity_m_per_s2;
    model.mass_damping_per_s = d.mass_damping_per_s;
    for (set, directions) in &d.fixed_sets {
        model.fix_set(set, *directions)?;
    }
    for spring in &d.track_springs {
        model.add_spring(spring.clone())?;
    }
    let axle = model.add_rigid_body(&d.axle.node_set)?;
    let rb: &mut RigidBodySpec = &mut model.rigid_bodies[axle];
    rb.prescribed_translation_m[1] = Some(d.axle.lateral_m.clone());
    rb.rotation_axis = Some(d.axle.axis);
    rb.torque = Some(TorqueLoad {
        axis: d.axle.axis,
        curve_n_m: d.axle.torque_n_m.clone(),
    });
    let sm = &d.sprung_mass;
    let sprung_node = model.add_point_mass("sprung_mass", sm.position_m, sm.mass_kg)?;
    model.add_spring(Spring {
        name: "primary_suspension".into(),
        node_a: sm.axle_box_node,
        node_b: Some(sprung_node),
        stiffness_n_per_m: [sm.stiffness_n_per_m; 3],
        damping_n_s_per_m: [sm.damping_n_s_per_m; 3],
    })?;
    Ok((model, axle, sprung_node))
}

/// Builds the model of a case (no preload yet).
pub fn build(loaded: &LoadedCase) -> Result<RollingModel> {
    let case = &loaded.case;
    let source = loaded.source.display().to_string();
    let mut d = describe(loaded)?;
    let c = &d.contact;
    let mut pair = ContactPair::new(
        "wheel_on_rail",
        &d.mesh,
        c.slaves.clone(),
        c.faces.clone(),
        c.penalty_scale,
        c.bulk_modulus_pa,
        c.friction,
    )
    .map_err(|e| Error::input(&source, "penalty_scale / friction", e.to_string()))?;
    pair.slip_speed = case.friction_slip_speed;
    pair.enforcement = case.contact_enforcement;
    if let Some(length_mm) = case.penalty_length_mm {
        pair.use_area_penalty(c.bulk_modulus_pa, length_mm * 1e-3);
    }
    let (mut model, axle, sprung_node) = engine_model(&mut d, &source)?;
    let wheelset_mass: f64 = d
        .wheelset_nodes
        .iter()
        .map(|&n| model.nodal_mass_kg[n])
        .sum();
    let static_wheel_load_n = (wheelset_mass + case.sprung_mass_kg) * G_M_PER_S2;
    let (capped, clearance) = check_contact_before_preload(&mut model, &mut pair, &source)?;
    let preload_added_mass_kg = match case.preload.time_step_s {
        Some(dt) => preload_scaling(&model, &d.materials, &pair, dt),
        None => Vec::new(),
    };
    let mut solver = Solver::new(model, None)?;
    solver.scale_time_step(case.time_stepping.step_scale)?;
    // The sprung mass sits at its static position: the suspension carries its weight.
    let suspension_static_compression_m = d.sprung_mass.static_compression_m;
    solver.u[sprung_node][2] = -suspension_static_compression_m;
    let (dt, limited) = solver.stable_time_step_s()?;
    let info = ModelInfo {
        nodes: solver.model.node_count(),
        elements: solver.model.elements.len(),
        contact_slaves: pair.slaves.len(),
        contact_faces: pair.faces.len(),
        time_step_s: dt,
        time_step_limited_by: limited,
        wheel_centre_m: d.wheel_centre_m,
        rolling_radius_m: d.rolling_radius_m,
        static_wheel_load_n,
        preload_load_error: f64::NAN,
        rim_node: d.rim_and_hub.rim_node,
        preload_added_mass_kg: preload_added_mass_kg.iter().sum(),
        contact_slaves_with_capped_penalty: capped,
        largest_penalty_scale: pair.largest_penalty_scale(),
        initial_gap_m: clearance.smallest_gap_m,
        time_stepping: "single rate".into(),
        step_levels: None,
    };
    let contact = RollingContact::new(
        pair,
        d.rim_and_hub,
        &case.output,
        axle,
        d.wheel_centre_m,
        d.axle.axis,
        &solver.model.mesh.nodes,
    )?;
    // The contact acts on its slaves and master faces only: the step zeroes and reads the
    // auxiliary forces there (explicit::aux_nodes).
    solver.declare_aux_forces_of(&contact)?;
    Ok(RollingModel {
        solver,
        contact,
        wheelset_nodes: d.wheelset_nodes,
        sprung_node,
        axle_box_node: d.sprung_mass.axle_box_node,
        axle_body: axle,
        suspension_static_compression_m,
        info,
        preload_added_mass_kg,
    })
}

/// Inertia to add per node so that the preload can run at step `dt_s` (with the engine's 0.9
/// safety factor): an element whose transit `L / c` is below `dt / 0.9` gets its density
/// raised by `(dt c / (0.9 L))^2` (the wave speed then gives exactly that transit); a node with
/// springs of total stiffness `sum k` gets at least `2 sum k (dt / 1.8)^2` (then
/// `2 / sqrt(k (1/m_a + 1/m_b)) >= dt / 0.9`); a contact slave at least `k (dt / 0.9)^2` and a
/// master-face node `4 k (dt / 0.9)^2` (up to four slaves press on it).
pub fn preload_scaling(
    model: &Model,
    materials: &BTreeMap<u32, Material>,
    pair: &ContactPair,
    dt_s: f64,
) -> Vec<f64> {
    let n = model.nodal_mass_kg.len();
    let mut added = vec![0.0; n];
    let mesh = &model.mesh;
    let transits = crate::explicit::multirate::element_transits_s(model);
    for (e, conn) in mesh.elements.iter().enumerate() {
        let x: [P3; 8] = std::array::from_fn(|a| mesh.nodes[conn[a]]);
        let ratio = (dt_s / (COURANT_FACTOR * transits[e])).powi(2);
        if ratio <= 1.0 {
            continue;
        }
        let Some(mat) = materials.get(&mesh.material[e]) else {
            continue;
        };
        if let Some(m) = crate::explicit::element::lumped_masses(&x, mat.density_kg_per_m3) {
            for a in 0..8 {
                added[conn[a]] += (ratio - 1.0) * m[a];
            }
        }
    }
    let mut spring_k = vec![0.0; n];
    for s in &model.springs {
        let k = s.stiffness_n_per_m.iter().fold(0.0f64, |m, &k| m.max(k));
        spring_k[s.node_a] += k;
        if let Some(b) = s.node_b {
            spring_k[b] += k;
        }
    }
    let need = |m: f64, required: f64| (required - m).max(0.0);
    for i in 0..n {
        if spring_k[i] > 0.0 {
            let m = model.nodal_mass_kg[i] + added[i];
            added[i] += need(
                m,
                2.0 * spring_k[i] * (dt_s / (2.0 * COURANT_FACTOR)).powi(2),
            );
        }
    }
    let k_max = pair
        .face_stiffness_n_per_m
        .iter()
        .fold(0.0f64, |m, &k| m.max(k));
    let contact_mass = k_max * (dt_s / COURANT_FACTOR).powi(2);
    for &s in &pair.slaves {
        let m = model.nodal_mass_kg[s] + added[s];
        added[s] += need(m, contact_mass);
    }
    for f in &pair.faces {
        for &v in f {
            let m = model.nodal_mass_kg[v] + added[v];
            added[v] += need(m, 4.0 * contact_mass);
        }
    }
    added
}

/// Largest wheel-rail gap accepted before the preload (m): the static preload settles a wheel
/// that starts on the rail; a wheel dropped from higher falls for
/// `sqrt(2 h / g)` (14 ms from 1 mm) under the preload's damping and inertia scaling.
pub const INITIAL_GAP_LIMIT_M: f64 = 1e-3;
