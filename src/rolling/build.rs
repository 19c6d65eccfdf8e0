//! The rolling model of a case: the scenario's meshes, materials, track supports (pads,
//! ballast, fixed ends), the axle ends as one rigid body with the lateral motion and the torque,
//! the sprung mass on the primary suspension, the wheel-rail contact pair and its checks before
//! the preload, and the inertia that lets the preload run at its own step.

use std::collections::BTreeMap;

use serde::Serialize;

use super::case::{LoadedCase, RollingCase};
use super::output::{RimAndHub, RollingContact};
use crate::contact::ContactPair;
use crate::explicit::model::{RigidBodySpec, TorqueLoad};
use crate::explicit::solver::COURANT_FACTOR;
use crate::explicit::{Curve, ElasticMaterial, Formulation, Model, Solver, Spring};
use crate::mesh::{material, P3};
use crate::{Error, Result};

/// Standard gravity (m/s^2).
pub(super) const G_M_PER_S2: f64 = 9.81;

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

/// Steel or concrete as the engine's material.
pub(super) fn elastic(e: f64, nu: f64, rho: f64) -> ElasticMaterial {
    ElasticMaterial {
        density_kg_per_m3: rho,
        youngs_modulus_pa: e,
        poisson_ratio: nu,
    }
}

/// The engine's materials per mesh material id: the wheel file's steel for wheel, axle, bands
/// and rail, the case's concrete for the sleepers. Returns the steel as well.
fn materials(loaded: &LoadedCase) -> (ElasticMaterial, BTreeMap<u32, ElasticMaterial>) {
    let steel_spec = loaded.scenario.wheel.material;
    let steel = elastic(
        steel_spec.youngs_modulus_pa,
        steel_spec.poisson_ratio,
        steel_spec.density_kg_per_m3,
    );
    let concrete = loaded.case.sleeper_material;
    let concrete = elastic(
        concrete.youngs_modulus_pa,
        concrete.poisson_ratio,
        concrete.density_kg_per_m3,
    );
    let materials = [
        (material::WHEEL, steel),
        (material::AXLE, steel),
        (material::TREAD_BAND, steel),
        (material::RAIL, steel),
        (material::RAIL_BAND, steel),
        (material::SLEEPER, concrete),
    ]
    .into_iter()
    .collect();
    (steel, materials)
}

/// Track supports (Yang & Li 2019): rail ends and sleeper bottoms held laterally and
/// longitudinally, optionally the sleepers' track-centre faces laterally; ballast as vertical
/// spring-dampers from each sleeper bottom to the ground; rail pads as spring-dampers from each
/// rail-foot node over a sleeper to its nearest sleeper-top node, the pad's totals shared
/// equally, in shear a fraction of the vertical values.
fn add_track_supports(
    model: &mut Model,
    case: &RollingCase,
    sleeper_count: usize,
    source: &str,
) -> Result<()> {
    model.fix_set("rail_ends", [true, true, false])?;
    model.fix_set("sleeper_bottoms", [true, true, false])?;
    if case.track_centre_symmetry {
        model.fix_set("sleeper_centre_faces", [false, true, false])?;
    }
    let pad = case.rail_pad;
    let shear = pad.shear_fraction;
    for k in 0..sleeper_count {
        let tops = model.node_set(&format!("sleeper_top_{k}"))?;
        let bottoms = format!("sleeper_bottom_{k}");
        model.add_ground_springs(
            &bottoms,
            [0.0, 0.0, case.ballast.stiffness_n_per_m],
            [0.0, 0.0, case.ballast.damping_n_s_per_m],
        )?;
        let pad_nodes = model.node_set(&format!("rail_pad_{k}"))?;
        let share = 1.0 / pad_nodes.len() as f64;
        for &n in &pad_nodes {
            let x = model.mesh.nodes[n];
            let nearest = *tops
                .iter()
                .min_by(|&&a, &&b| {
                    dist2(model.mesh.nodes[a], x).total_cmp(&dist2(model.mesh.nodes[b], x))
                })
                .ok_or_else(|| {
                    Error::input(source, "model_scenario", "a sleeper has no top nodes")
                })?;
            let (kz, cz) = (pad.stiffness_n_per_m * share, pad.damping_n_s_per_m * share);
            model.add_spring(Spring {
                name: format!("rail_pad_{k}"),
                node_a: n,
                node_b: Some(nearest),
                stiffness_n_per_m: [shear * kz, shear * kz, kz],
                damping_n_s_per_m: [shear * cz, shear * cz, cz],
            })?;
        }
    }
    Ok(())
}

/// The axle ends: both end faces of the half axle move as one rigid body (the half axle's ends
/// driven as one body) that turns only about the axle axis, as in its bearings, and carries the
/// prescribed lateral motion and the driving torque. With the two ends free to move apart in x
/// and to turn about z, the half wheelset would yaw under the single wheel's traction, and the
/// yaw angle is a lateral creepage (Yang & Li 2019: the same lateral motion at both ends so
/// that "the angle of attack stays about zero"). Returns the rigid body's index.
fn add_axle_body(model: &mut Model, case: &RollingCase) -> Result<usize> {
    let lateral = lateral_curve(case)?;
    let mut both_ends: Vec<usize> = model.node_set("axle_inner_end")?;
    both_ends.extend(model.node_set("axle_outer_end")?);
    model.mesh.add_node_set("axle_ends", both_ends);
    let axle = model.add_rigid_body("axle_ends")?;
    let rb: &mut RigidBodySpec = &mut model.rigid_bodies[axle];
    rb.prescribed_translation_m[1] = Some(lateral);
    rb.rotation_axis = Some([0.0, 1.0, 0.0]);
    rb.torque = Some(TorqueLoad {
        axis: [0.0, 1.0, 0.0],
        curve_n_m: Curve::new(
            vec![
                0.0,
                case.torque.ramp_end_s,
                case.end_time_s.max(case.torque.ramp_end_s) + 1.0,
            ],
            vec![0.0, case.torque.max_n_m, case.torque.max_n_m],
            "torque",
        )?,
    });
    Ok(axle)
}

/// The sprung mass on the primary suspension, joined to the axle-box node nearest the axis:
/// (axle-box node, sprung-mass node).
fn add_sprung_mass(
    model: &mut Model,
    case: &RollingCase,
    centre: P3,
    source: &str,
) -> Result<(usize, usize)> {
    let outer_nodes = model.node_set("axle_outer_end")?;
    let axle_box = *outer_nodes
        .iter()
        .min_by(|&&a, &&b| {
            let da = axis_distance2(model.mesh.nodes[a], centre);
            let db = axis_distance2(model.mesh.nodes[b], centre);
            da.total_cmp(&db)
        })
        .ok_or_else(|| Error::input(source, "model_scenario", "empty axle_outer_end set"))?;
    let box_x = model.mesh.nodes[axle_box];
    let sprung_node = model.add_point_mass(
        "sprung_mass",
        [box_x[0], box_x[1], box_x[2] + 0.5],
        case.sprung_mass_kg,
    )?;
    let ps = case.primary_suspension;
    model.add_spring(Spring {
        name: "primary_suspension".into(),
        node_a: axle_box,
        node_b: Some(sprung_node),
        stiffness_n_per_m: [ps.stiffness_n_per_m; 3],
        damping_n_s_per_m: [ps.damping_n_s_per_m; 3],
    })?;
    Ok((axle_box, sprung_node))
}

/// The wheel-rail contact pair: the wheel's tread nodes (slaves) on the rail's top faces
/// (masters), with the penalty `k = s K A^2 / V` from the steel's bulk modulus and the case's
/// friction law.
fn new_contact_pair(
    mesh: &crate::mesh::Mesh,
    case: &RollingCase,
    steel: ElasticMaterial,
    source: &str,
) -> Result<ContactPair> {
    let slaves = mesh
        .node_set("wheel_tread")
        .ok_or_else(|| {
            Error::input(
                source,
                "model_scenario",
                "the wheel mesh has no `wheel_tread` node set",
            )
        })?
        .to_vec();
    let faces = mesh
        .surfaces
        .get("rail_top")
        .ok_or_else(|| {
            Error::input(
                source,
                "model_scenario",
                "the track mesh has no `rail_top` surface",
            )
        })?
        .clone();
    let bulk_pa = steel.youngs_modulus_pa / (3.0 * (1.0 - 2.0 * steel.poisson_ratio));
    ContactPair::new(
        "wheel_on_rail",
        mesh,
        slaves,
        faces,
        case.penalty_scale,
        bulk_pa,
        case.friction,
    )
    .map_err(|e| Error::input(source, "penalty_scale / friction", e.to_string()))
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
    let element_step_s = element_transits_s(model)
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

/// Builds the model of a case (no preload yet).
pub fn build(loaded: &LoadedCase) -> Result<RollingModel> {
    let case = &loaded.case;
    let source = loaded.source.display().to_string();
    let sc = &loaded.scenario;
    let mesh = sc.model_mesh();
    let (steel, materials) = materials(loaded);
    // Wheelset nodes: those of wheel, axle and band elements.
    let mut in_wheelset = vec![false; mesh.nodes.len()];
    for (e, el) in mesh.elements.iter().enumerate() {
        if matches!(
            mesh.material[e],
            material::WHEEL | material::AXLE | material::TREAD_BAND
        ) {
            for &n in el {
                in_wheelset[n] = true;
            }
        }
    }
    let wheelset_nodes: Vec<usize> = (0..mesh.nodes.len()).filter(|&n| in_wheelset[n]).collect();
    let placement = sc.wheel_placement();
    let centre = placement.tape_circle_centre_m;
    let rolling_radius_m = sc.wheel.tread_radius_mm(0.0) * 1e-3;
    let mut pair = new_contact_pair(&mesh, case, steel, &source)?;
    // Rim point: the top node of the field-side rim face.
    let rim_nodes = rim_face_nodes(&mesh.nodes, &wheelset_nodes, centre);
    let rim_node = *rim_nodes
        .iter()
        .max_by(|&&a, &&b| mesh.nodes[a][2].total_cmp(&mesh.nodes[b][2]))
        .ok_or_else(|| Error::input(&source, "model_scenario", "no rim nodes found"))?;
    let hub_nodes = mesh
        .node_set("hub_bore")
        .ok_or_else(|| {
            Error::input(
                &source,
                "model_scenario",
                "the wheel mesh has no `hub_bore` node set",
            )
        })?
        .to_vec();
    let sleeper_count = mesh
        .node_sets
        .keys()
        .filter(|k| k.starts_with("sleeper_top_"))
        .count();

    let mut model = Model::from_mesh(mesh, &materials, Formulation::default(), &source)?;
    model.gravity_m_per_s2 = [0.0, 0.0, -G_M_PER_S2];
    model.mass_damping_per_s = case.mass_damping_per_s;
    add_track_supports(&mut model, case, sleeper_count, &source)?;
    let axle = add_axle_body(&mut model, case)?;
    let (axle_box, sprung_node) = add_sprung_mass(&mut model, case, centre, &source)?;
    let wheelset_mass: f64 = wheelset_nodes.iter().map(|&n| model.nodal_mass_kg[n]).sum();
    let static_wheel_load_n = (wheelset_mass + case.sprung_mass_kg) * G_M_PER_S2;
    let (capped, clearance) = check_contact_before_preload(&mut model, &mut pair, &source)?;
    let preload_added_mass_kg = match case.preload.time_step_s {
        Some(dt) => preload_scaling(&model, &materials, &pair, dt),
        None => Vec::new(),
    };
    let mut solver = Solver::new(model, None)?;
    // The sprung mass sits at its static position: the suspension carries its weight.
    let suspension_static_compression_m =
        case.sprung_mass_kg * G_M_PER_S2 / case.primary_suspension.stiffness_n_per_m;
    solver.u[sprung_node][2] = -suspension_static_compression_m;
    let (dt, limited) = solver.stable_time_step_s()?;
    let info = ModelInfo {
        nodes: solver.model.node_count(),
        elements: solver.model.elements.len(),
        contact_slaves: pair.slaves.len(),
        contact_faces: pair.faces.len(),
        time_step_s: dt,
        time_step_limited_by: limited,
        wheel_centre_m: centre,
        rolling_radius_m,
        static_wheel_load_n,
        preload_load_error: f64::NAN,
        rim_node,
        preload_added_mass_kg: preload_added_mass_kg.iter().sum(),
        contact_slaves_with_capped_penalty: capped,
        largest_penalty_scale: pair.largest_penalty_scale(),
        initial_gap_m: clearance.smallest_gap_m,
    };
    let contact = RollingContact::new(
        pair,
        RimAndHub {
            rim_node,
            rim_nodes,
            hub_nodes,
        },
        &case.output,
        axle,
        centre[1],
    );
    Ok(RollingModel {
        solver,
        contact,
        wheelset_nodes,
        sprung_node,
        axle_box_node: axle_box,
        axle_body: axle,
        suspension_static_compression_m,
        info,
        preload_added_mass_kg,
    })
}

/// Transit time `L / c` of every element (s): the elements' own stable steps.
pub(super) fn element_transits_s(model: &Model) -> Vec<f64> {
    let mesh = &model.mesh;
    mesh.elements
        .iter()
        .enumerate()
        .map(|(e, conn)| {
            let x: [P3; 8] = std::array::from_fn(|a| mesh.nodes[conn[a]]);
            crate::mesh::hex::characteristic_length(&x) / model.element_wave_speed_m_per_s[e]
        })
        .collect()
}

/// Inertia to add per node so that the preload can run at step `dt_s` (with the engine's 0.9
/// safety factor): an element whose transit `L / c` is below `dt / 0.9` gets its density
/// raised by `(dt c / (0.9 L))^2` (the wave speed then gives exactly that transit); a node with
/// springs of total stiffness `sum k` gets at least `2 sum k (dt / 1.8)^2` (then
/// `2 / sqrt(k (1/m_a + 1/m_b)) >= dt / 0.9`); a contact slave at least `k (dt / 0.9)^2` and a
/// master-face node `4 k (dt / 0.9)^2` (up to four slaves press on it).
pub fn preload_scaling(
    model: &Model,
    materials: &BTreeMap<u32, ElasticMaterial>,
    pair: &ContactPair,
    dt_s: f64,
) -> Vec<f64> {
    let n = model.nodal_mass_kg.len();
    let mut added = vec![0.0; n];
    let mesh = &model.mesh;
    let transits = element_transits_s(model);
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

pub(super) fn dist2(a: P3, b: P3) -> f64 {
    (0..3).map(|i| (a[i] - b[i]) * (a[i] - b[i])).sum()
}

pub(super) fn axis_distance2(x: P3, centre: P3) -> f64 {
    (x[0] - centre[0]).powi(2) + (x[2] - centre[2]).powi(2)
}

/// Nodes of the field-side face of the rim: wheelset nodes within 1 mm of the largest y among
/// nodes beyond 90 % of the largest radius.
pub(super) fn rim_face_nodes(nodes: &[P3], wheelset: &[usize], centre: P3) -> Vec<usize> {
    let r_max = wheelset
        .iter()
        .map(|&n| axis_distance2(nodes[n], centre).sqrt())
        .fold(0.0, f64::max);
    let outer: Vec<usize> = wheelset
        .iter()
        .copied()
        .filter(|&n| axis_distance2(nodes[n], centre).sqrt() > 0.9 * r_max)
        .collect();
    let y_max = outer
        .iter()
        .map(|&n| nodes[n][1])
        .fold(f64::NEG_INFINITY, f64::max);
    outer
        .into_iter()
        .filter(|&n| nodes[n][1] > y_max - 1e-3)
        .collect()
}

/// Lateral displacement of the axle ends against time (C1, see [`lateral`]).
pub(super) fn lateral_curve(case: &RollingCase) -> Result<Curve> {
    match &case.lateral_motion {
        None => Ok(Curve::constant(0.0)),
        Some(l) => l.curve(),
    }
}

/// Largest wheel-rail gap accepted before the preload (m): the static preload settles a wheel
/// that starts on the rail; a wheel dropped from higher falls for
/// `sqrt(2 h / g)` (14 ms from 1 mm) under the preload's damping and inertia scaling.
pub const INITIAL_GAP_LIMIT_M: f64 = 1e-3;
