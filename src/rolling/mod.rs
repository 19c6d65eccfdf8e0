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

pub mod case;
pub mod instruments;
pub mod lateral;

use std::collections::BTreeMap;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use serde::Serialize;

use crate::contact::{patch, ContactPair};
use crate::explicit::model::{RigidBodySpec, TorqueLoad};
use crate::explicit::preload::{relax, PreloadOptions, PreloadReport};
use crate::explicit::run::{
    push_num, run, truncate_csv_after, HistoryProbe, Quantity, RunOptions, RunSummary,
};
use crate::explicit::solver::{OutputFields, COURANT_FACTOR};
use crate::explicit::{AuxForces, Curve, ElasticMaterial, Formulation, Model, Solver, Spring};
use crate::mesh::{material, P3};
use crate::{Error, Result};
use instruments::{contact_kinematics, ContactKinematics, ContactPointRecord};

pub use crate::explicit::run::StopFlag;
pub use case::{embedded_default_case, load_case, LoadedCase, RollingCase};

/// Standard gravity (m/s^2).
const G_M_PER_S2: f64 = 9.81;

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
fn elastic(e: f64, nu: f64, rho: f64) -> ElasticMaterial {
    ElasticMaterial {
        density_kg_per_m3: rho,
        youngs_modulus_pa: e,
        poisson_ratio: nu,
    }
}

/// Builds the model of a case (no preload yet).
pub fn build(loaded: &LoadedCase) -> Result<RollingModel> {
    let case = &loaded.case;
    let source = loaded.source.display().to_string();
    let sc = &loaded.scenario;
    let mesh = sc.model_mesh();
    let steel_spec = sc.wheel.material;
    let steel = elastic(
        steel_spec.youngs_modulus_pa,
        steel_spec.poisson_ratio,
        steel_spec.density_kg_per_m3,
    );
    let concrete = elastic(
        case.sleeper_material.youngs_modulus_pa,
        case.sleeper_material.poisson_ratio,
        case.sleeper_material.density_kg_per_m3,
    );
    let materials: BTreeMap<u32, ElasticMaterial> = [
        (material::WHEEL, steel),
        (material::AXLE, steel),
        (material::TREAD_BAND, steel),
        (material::RAIL, steel),
        (material::RAIL_BAND, steel),
        (material::SLEEPER, concrete),
    ]
    .into_iter()
    .collect();
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
    // Contact: wheel tread nodes (slaves) on the rail top faces (masters).
    let slaves = mesh
        .node_set("wheel_tread")
        .ok_or_else(|| {
            Error::input(
                &source,
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
                &source,
                "model_scenario",
                "the track mesh has no `rail_top` surface",
            )
        })?
        .clone();
    let bulk_pa = steel.youngs_modulus_pa / (3.0 * (1.0 - 2.0 * steel.poisson_ratio));
    let pair = ContactPair::new(
        "wheel_on_rail",
        &mesh,
        slaves,
        faces,
        case.penalty_scale,
        bulk_pa,
        case.friction,
    )
    .map_err(|e| Error::input(&source, "penalty_scale / friction", e.to_string()))?;
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
    // Track supports.
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
                    Error::input(&source, "model_scenario", "a sleeper has no top nodes")
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
    // Axle ends: both end faces of the half axle move as one rigid body (the half axle's ends
    // driven as one body) that turns only about the axle axis, as in its bearings,
    // and carries the prescribed lateral motion and the driving torque. With the two ends
    // free to move apart in x and to turn about z, the half wheelset would yaw under the
    // single wheel's traction, and the yaw angle is a lateral creepage (Yang & Li 2019: the same
    // lateral motion at both ends so that "the angle of attack stays about zero").
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
    // Sprung mass on the primary suspension, joined to the axle-box node nearest the axis.
    let outer_nodes = model.node_set("axle_outer_end")?;
    let axle_box = *outer_nodes
        .iter()
        .min_by(|&&a, &&b| {
            let da = axis_distance2(model.mesh.nodes[a], centre);
            let db = axis_distance2(model.mesh.nodes[b], centre);
            da.total_cmp(&db)
        })
        .ok_or_else(|| Error::input(&source, "model_scenario", "empty axle_outer_end set"))?;
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
    let wheelset_mass: f64 = wheelset_nodes.iter().map(|&n| model.nodal_mass_kg[n]).sum();
    let static_wheel_load_n = (wheelset_mass + case.sprung_mass_kg) * G_M_PER_S2;
    // The penalty of light slaves is capped so that contact does not lower the elements' step.
    let mut pair = pair;
    let element_step_s = element_transits_s(&model)
        .into_iter()
        .fold(f64::INFINITY, f64::min);
    let capped = pair.cap_stiffness_for_step(&model.nodal_mass_kg, element_step_s);
    // The cap keeps the step; a scale the step cannot carry anywhere is an input error, not
    // a silent change of the penalty.
    pair.check_penalty_scale_against_step(&source, "penalty_scale")?;
    // Before the preload (20 minutes on the paper model): the wheel must start on the rail,
    // seen from the rail's outer side.
    let clearance = pair.check_initial_clearance(
        INITIAL_GAP_LIMIT_M,
        &source,
        "model_scenario: wheel_position.initial_gap_mm",
    )?;
    let bound = pair.time_step_bound_s(&model.nodal_mass_kg);
    model.register_time_step_bound("contact penalty", bound);
    let preload_added_mass_kg = match case.preload.time_step_s {
        Some(dt) => preload_scaling(&model, &materials, &pair, dt),
        None => Vec::new(),
    };
    let mut solver = Solver::new(model, None)?;
    // The sprung mass sits at its static position: the suspension carries its weight.
    let suspension_static_compression_m = case.sprung_mass_kg * G_M_PER_S2 / ps.stiffness_n_per_m;
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
    // From the profiles: where the flange would touch the rail if the wheel moved towards the
    // field side (the flange clearance is measured against it).
    let flange_contact_wheel_y_m = crate::kalker::profiles::flange_contact_wheel_y_m(centre[1]);
    let contact = RollingContact {
        pair,
        rim_node,
        rim_nodes,
        hub_nodes,
        patch_times_s: case.output.patch_times_s.clone(),
        slip_threshold_m_per_s: case.output.slip_threshold_m_per_s,
        writer: None,
        out_dir: PathBuf::new(),
        resuming: false,
        lost_since_s: None,
        longest_loss_s: 0.0,
        axle_body: axle,
        tape_circle_y_m: centre[1],
        flange_contact_wheel_y_m,
        kinematics: None,
        contact_point: None,
        forward_guide_force_n: 0.0,
    };
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

/// Static preload (frictionless dynamic relaxation with the case's damping) in stages. The
/// sprung mass starts at its static position over the unloaded axle box; as the wheel sinks
/// into the track the axle box follows, and the suspension would carry `k d` less than the
/// sprung weight (about 2 kN for 1.7 mm) until the 1-2 Hz bounce settles, which dynamic
/// relaxation cannot wait for. So after each stage but the last the sprung mass is put back at
/// its static offset from the current axle box (`u_s = u_box - W / k`, at rest), and the next
/// stage relaxes that small disturbance: the wheel then carries the full static load.
///
/// Converged means three things: the relative residual below the case's tolerance, the sprung
/// mass in place (within 1 µm), and the wheel carrying its static load: the vertical contact
/// force within `load_tolerance` of the wheelset and sprung weight. The last is needed because
/// the residual is a norm over all nodes: the wheelset still sinking slowly into the track as
/// one body (an overdamped mode) leaves a few kN spread over thousands of nodes, which that
/// norm does not see (measured on the 1 mm model: residual 9e-4 with 8 % of the load missing).
fn staged_preload(
    m: &mut RollingModel,
    preload: &case::PreloadSpec,
    stop: &StopFlag,
) -> Result<PreloadReport> {
    // Stages of a tenth of the step budget: the axle box moves little within one, so each
    // put-back disturbs the wheel by a few hundred newtons at most.
    let per_stage = (preload.max_steps / 10).max(1);
    let mut total_steps = 0;
    let mut last: Option<PreloadReport> = None;
    let mut stage = 0;
    while total_steps < preload.max_steps {
        let steps = per_stage.min(preload.max_steps - total_steps);
        let report = relax(
            &mut m.solver,
            &mut m.contact,
            PreloadOptions {
                tolerance: preload.tolerance,
                max_steps: steps,
                fixed_damping_per_s: Some(preload.damping_per_s),
                require_convergence: false,
                // A stage ends early once the residual is small; the relaxation goes on in the
                // next (velocities are zeroed below, when it is over).
                keep_velocities: true,
                stop: stop.clone(),
                ..Default::default()
            },
        )?;
        total_steps += report.steps;
        let final_stage = total_steps >= preload.max_steps;
        let load_error = preload_load_error(m);
        m.info.preload_load_error = load_error;
        let target = m.solver.u[m.axle_box_node][2] - m.suspension_static_compression_m;
        let moved = (m.solver.u[m.sprung_node][2] - target).abs();
        if std::env::var_os("SQUEAL_PRELOAD_TRACE").is_some() {
            eprintln!(
                "preload stage {stage}: {} steps (total {total_steps}), residual {:.2e}, \
                 wheel load error {:+.3} %, sprung mass {:.2e} m from its place",
                report.steps,
                report.relative_residual,
                100.0 * load_error,
                moved
            );
        }
        let converged =
            report.converged && moved < 1e-6 && load_error.abs() < preload.load_tolerance;
        last = Some(PreloadReport {
            converged,
            ..report
        });
        if converged || final_stage {
            break;
        }
        m.solver.u[m.sprung_node][2] = target;
        m.solver.v[m.sprung_node] = [0.0; 3];
        stage += 1;
    }
    // The run starts from rest (a stage that stopped early kept its velocities).
    m.solver.v.iter_mut().for_each(|v| *v = [0.0; 3]);
    m.solver.zero_rigid_velocities();
    let mut report = last.ok_or_else(|| {
        Error::input(
            "scenario",
            "preload.max_steps",
            "must be at least 1".to_string(),
        )
    })?;
    report.steps = total_steps;
    Ok(report)
}

/// `(F_z - W) / W`: the vertical contact force on the wheel against the static wheel load
/// (wheelset and sprung weight).
fn preload_load_error(m: &RollingModel) -> f64 {
    let (normal, tangential, _) = m.contact.pair.resultants();
    let load = m.info.static_wheel_load_n;
    (normal[2] + tangential[2] - load) / load
}

/// Holds the axle at the rolling speed and spins it at `V (1 + xi(t)) / R` (see
/// [`case::CreepageRamp`]): forward speed and spin are prescribed on the axle body from now on.
fn prescribe_creepage(
    m: &mut RollingModel,
    ramp: &case::CreepageRamp,
    speed_m_per_s: f64,
    radius_m: f64,
) -> Result<()> {
    let t0 = m.solver.time_s;
    let end = m.solver.time_s.max(ramp.end_s) + 1.0;
    let spin = |xi: f64| speed_m_per_s * (1.0 + xi) / radius_m;
    let mut times = vec![t0];
    let mut values = vec![spin(0.0)];
    if ramp.start_s > t0 {
        times.push(ramp.start_s);
        values.push(spin(0.0));
    }
    times.push(ramp.start_s.max(t0) + 1e-9);
    values.push(spin(ramp.start));
    times.push(ramp.end_s);
    values.push(spin(ramp.end));
    times.push(end);
    values.push(spin(ramp.end));
    let spin_curve = Curve::new(times, values, "creepage")?;
    hold_forward_speed(m, speed_m_per_s)?;
    let body = &mut m.solver.model.rigid_bodies[m.axle_body];
    body.prescribed_spin_rad_per_s = Some(spin_curve);
    body.torque = None;
    Ok(())
}

/// The forward guide: from now on the axle body's centre moves along x at the rolling speed
/// (see [`RollingCase::hold_forward_speed`]); the force that holds it is the body's reaction.
///
/// The engine takes the body's velocity from the curve's slope alone, so a run resumed from a
/// checkpoint gets the same guide from a curve laid from its own start.
fn hold_forward_speed(m: &mut RollingModel, speed_m_per_s: f64) -> Result<()> {
    let t0 = m.solver.time_s;
    // Longer than any case (end_time_s <= 1 s): the curve holds its last value after its end.
    let end = t0 + 2.0;
    let axle = m.axle_body;
    let centre_x = m.solver.rigid[axle].centre_m[0] - m.solver.rigid[axle].centre0_m[0];
    let forward = Curve::new(
        vec![t0, end],
        vec![centre_x, centre_x + speed_m_per_s * (end - t0)],
        "hold_forward_speed",
    )?;
    m.solver.model.rigid_bodies[axle].prescribed_translation_m[0] = Some(forward);
    Ok(())
}

/// Transit time `L / c` of every element (s): the elements' own stable steps.
fn element_transits_s(model: &Model) -> Vec<f64> {
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

fn dist2(a: P3, b: P3) -> f64 {
    (0..3).map(|i| (a[i] - b[i]) * (a[i] - b[i])).sum()
}

fn axis_distance2(x: P3, centre: P3) -> f64 {
    (x[0] - centre[0]).powi(2) + (x[2] - centre[2]).powi(2)
}

/// Nodes of the field-side face of the rim: wheelset nodes within 1 mm of the largest y among
/// nodes beyond 90 % of the largest radius.
fn rim_face_nodes(nodes: &[P3], wheelset: &[usize], centre: P3) -> Vec<usize> {
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
fn lateral_curve(case: &RollingCase) -> Result<Curve> {
    match &case.lateral_motion {
        None => Ok(Curve::constant(0.0)),
        Some(l) => l.curve(),
    }
}

/// Contact plus the rolling outputs: `contact_forces.csv`, patch snapshots and the wheel
/// vibration columns of `histories.csv`.
pub struct RollingContact {
    /// The wheel-rail contact pair.
    pub pair: ContactPair,
    rim_node: usize,
    rim_nodes: Vec<usize>,
    pub hub_nodes: Vec<usize>,
    patch_times_s: Vec<f64>,
    slip_threshold_m_per_s: f64,
    writer: Option<BufWriter<File>>,
    out_dir: PathBuf,
    /// The run resumes from a checkpoint: `contact_forces.csv` is cut at the first sample.
    resuming: bool,
    /// Start of the current loss of contact (s), if the wheel is off the rail.
    lost_since_s: Option<f64>,
    /// Longest loss of contact so far (s).
    longest_loss_s: f64,
    /// The axle-end rigid body (its reaction is the forward guide's force).
    axle_body: usize,
    /// Reference lateral position of the wheel's tape circle (m).
    tape_circle_y_m: f64,
    /// Tape-circle position of first flange contact from the profiles (m), if any.
    flange_contact_wheel_y_m: Option<f64>,
    /// Contact kinematics of the last sample.
    kinematics: Option<ContactKinematics>,
    /// Contact point and flange clearance over the run.
    pub contact_point: Option<ContactPointRecord>,
    /// Longitudinal force of the forward guide on the axle at the last sample (N).
    forward_guide_force_n: f64,
}

impl RollingContact {
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
            let append = self.resuming && path.exists();
            if append {
                truncate_csv_after(&path, time_s)?;
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

    /// Flushes `contact_forces.csv`.
    pub fn flush(&mut self) -> Result<()> {
        let path = self.out_dir.join("contact_forces.csv");
        if let Some(w) = self.writer.as_mut() {
            w.flush().map_err(|e| Error::io(&path, e))?;
        }
        Ok(())
    }
}

/// Rigid motion of the wheelset from the hub nodes: centre velocity (mean) and spin rate about
/// y, `Omega = mean((r x (v - v_c))_y / |r|^2)` with r in the x-z plane.
fn wheelset_motion(hub: &[usize], reference: &[P3], output: &OutputFields) -> (P3, P3, f64) {
    let n = hub.len().max(1) as f64;
    let mut c = [0.0; 3];
    let mut vc = [0.0; 3];
    for &h in hub {
        for i in 0..3 {
            c[i] += (reference[h][i] + output.displacement[h][i]) / n;
            vc[i] += output.velocity[h][i] / n;
        }
    }
    let mut omega = 0.0;
    for &h in hub {
        let rx = reference[h][0] + output.displacement[h][0] - c[0];
        let rz = reference[h][2] + output.displacement[h][2] - c[2];
        let dvx = output.velocity[h][0] - vc[0];
        let dvz = output.velocity[h][2] - vc[2];
        // (r x dv)_y = r_z dv_x - r_x dv_z
        let r2 = rx * rx + rz * rz;
        if r2 > 0.0 {
            omega += (rz * dvx - rx * dvz) / r2 / n;
        }
    }
    (c, vc, omega)
}

/// Velocity of node `nd` relative to the rigid motion (centre `c`, velocity `vc`, spin
/// `omega` about y): `v - v_c - omega e_y x r`, with `e_y x r = (r_z, 0, -r_x)`.
fn deformation_velocity(
    nd: usize,
    reference: &[P3],
    output: &OutputFields,
    c: P3,
    vc: P3,
    omega: f64,
) -> P3 {
    let r = [0, 1, 2].map(|i| reference[nd][i] + output.displacement[nd][i] - c[i]);
    let v = output.velocity[nd];
    [
        v[0] - vc[0] - omega * r[2],
        v[1] - vc[1],
        v[2] - vc[2] + omega * r[0],
    ]
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

    fn on_sample(&mut self, time_s: f64, _out_dir: &Path) -> Result<()> {
        self.write_forces(time_s)
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
        let (c, vc, omega) = wheelset_motion(&self.hub_nodes, reference, output);
        let point = deformation_velocity(self.rim_node, reference, output, c, vc, omega);
        let mut mean = [0.0; 3];
        for &nd in &self.rim_nodes {
            let d = deformation_velocity(nd, reference, output, c, vc, omega);
            for i in 0..3 {
                mean[i] += d[i] / self.rim_nodes.len() as f64;
            }
        }
        // Lateral = y, vertical = z, longitudinal = x.
        for x in [
            point[1], point[2], point[0], mean[1], mean[2], mean[0], omega,
        ] {
            row.push(',');
            push_num(row, x);
        }
        self.kinematics = contact_kinematics(&self.pair, reference, output, self.tape_circle_y_m);
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
            point[1] - mean[1],
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

    fn checkpoint_state(&self) -> Vec<f64> {
        self.pair.checkpoint_state()
    }

    fn restore_state(&mut self, state: &[f64]) -> Result<()> {
        self.pair.restore_state(state)
    }
}

/// Options of [`simulate`].
#[derive(Clone, Debug)]
pub struct SimulateOptions {
    /// Output directory.
    pub out_dir: PathBuf,
    /// Resume from the checkpoint in `out_dir`.
    pub resume: bool,
    /// Progress bar.
    pub progress: bool,
    /// Override of the case's end time (s), e.g. for quick checks.
    pub end_time_s: Option<f64>,
    /// Stop cleanly when set: during the rolling run a checkpoint is written and the record's
    /// status is `interrupted` (resume goes on); during the preload the result is
    /// [`Error::Interrupted`].
    pub stop: StopFlag,
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
    /// Model facts.
    pub model: ModelInfo,
    /// Preload result (None when resumed).
    pub preload: Option<PreloadReport>,
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
    /// Largest `|f_T| / (mu f_N)` over every contact node and every rolling step (since the
    /// start of rolling, or the resume): at most 1 up to rounding.
    pub largest_node_shear_over_bound: f64,
    /// Deepest penetration over every contact node and every rolling step (m), same span.
    pub deepest_penetration_m: f64,
    /// Where the contact sat on both profiles, its angle, and the flange clearance, at the
    /// start of rolling (or the resume) and over the run.
    pub contact_point: Option<ContactPointRecord>,
}

/// Largest wheel-rail gap accepted before the preload (m): the static preload settles a wheel
/// that starts on the rail; a wheel dropped from higher falls for
/// `sqrt(2 h / g)` (14 ms from 1 mm) under the preload's damping and inertia scaling.
pub const INITIAL_GAP_LIMIT_M: f64 = 1e-3;

/// Longest loss of contact accepted as a bounce (s); longer is lift-off or derailment.
pub const LIFT_OFF_LIMIT_S: f64 = 0.002;

/// Runs one case into `opts.out_dir`.
pub fn simulate(loaded: &LoadedCase, opts: &SimulateOptions) -> Result<RunRecord> {
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
    std::fs::create_dir_all(&opts.out_dir).map_err(|e| Error::io(&opts.out_dir, e))?;
    if opts.resume && case.creepage.is_some() {
        // The spin history depends on the loaded rolling radius measured after the preload,
        // which a checkpoint does not hold.
        return Err(Error::input(
            loaded.source.display().to_string(),
            "creepage",
            "runs with a prescribed creepage cannot be resumed; start them again",
        ));
    }
    let mut m = build(&loaded_case)?;
    m.contact.out_dir = opts.out_dir.clone();
    let mut preload = None;
    if !opts.resume {
        if let Some(dt) = case.preload.time_step_s {
            m.solver.set_inertia_scaling(&m.preload_added_mass_kg, dt)?;
        }
        // Frictionless preload: while the wheel settles its rim turns a little and the contact
        // points creep sideways; with friction that path would leave the lateral stick forces
        // saturated at the bound before the wheel has even started rolling.
        let friction = m.contact.pair.friction;
        m.contact.pair.friction = crate::contact::FrictionLaw::Coulomb { mu: 0.0 };
        let report = staged_preload(&mut m, &case.preload, &opts.stop);
        m.solver.clear_inertia_scaling();
        m.contact.pair.friction = friction;
        for st in m.contact.pair.state.iter_mut() {
            st.tangential_force_n = [0.0; 3];
            st.mu = friction.mu(0.0);
        }
        let report = report?;
        if !m.contact.pair.state.iter().any(|s| s.active) {
            return Err(Error::input(
                loaded.source.display().to_string(),
                "model_scenario: wheel_position.initial_gap_mm",
                "the wheel is not in contact with the rail after the preload: the initial gap is \
                 too large or the contact surfaces do not face each other",
            ));
        }
        if opts.progress {
            eprintln!(
                "preload: {} steps, relative residual {:.2e}{}",
                report.steps,
                report.relative_residual,
                if report.converged {
                    ""
                } else {
                    " (step limit reached; run continues)"
                }
            );
        }
        preload = Some(report);
        // Rolling: v = V e_x + (V / R) e_y x (x - centre) on the wheelset; the sprung mass
        // moves with it.
        // The preloaded wheel has sunk into its track: take the centre from the hub nodes and
        // the rolling radius from it to the loaded contact nodes (force-weighted), so that the
        // contact points start without slip.
        let speed = case.speed_m_per_s();
        let (centre, radius) = loaded_centre_and_radius(&m);
        m.info.rolling_radius_m = radius;
        m.info.wheel_centre_m = centre;
        let omega = [0.0, speed / radius, 0.0];
        let nodes = m.wheelset_nodes.clone();
        m.solver
            .set_initial_velocity(Some(&nodes), [speed, 0.0, 0.0], omega, centre);
        m.solver.v[m.sprung_node] = [speed, 0.0, 0.0];
        if let Some(ramp) = case.creepage {
            prescribe_creepage(&mut m, &ramp, speed, radius)?;
        } else if case.hold_forward_speed {
            hold_forward_speed(&mut m, speed)?;
        }
        m.solver.rebase_energy();
    } else if case.hold_forward_speed {
        hold_forward_speed(&mut m, case.speed_m_per_s())?;
    }
    let sample_interval_s = 1.0 / case.output.sample_rate_hz;
    let run_opts = RunOptions {
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
    };
    m.contact.resuming = opts.resume;
    // The invariants are the rolling run's: the frictionless preload's steps are left out.
    m.contact.pair.reset_monitors();
    let summary = run(&mut m.solver, &mut m.contact, &run_opts)?;
    m.contact.flush()?;
    let (traction, initial_n) =
        force_statistics(&opts.out_dir.join("contact_forces.csv"), case.end_time_s);
    let record = RunRecord {
        case: case.name.clone(),
        case_file: loaded.source.display().to_string(),
        scenario: loaded.scenario.scenario.name.clone(),
        settings: case,
        model: m.info,
        preload,
        run: summary,
        measured_traction_coefficient: traction,
        initial_normal_force_n: initial_n,
        longest_contact_loss_s: m.contact.longest_loss_s,
        largest_node_shear_over_bound: m.contact.pair.largest_shear_over_bound,
        deepest_penetration_m: m.contact.pair.deepest_penetration_m,
        contact_point: m.contact.contact_point,
    };
    let path = opts.out_dir.join("run.json");
    let text =
        serde_json::to_string_pretty(&record).map_err(|e| Error::Numerical(e.to_string()))?;
    std::fs::write(&path, text).map_err(|e| Error::io(&path, e))?;
    Ok(record)
}

/// Current wheel centre (mean of the hub bore nodes) and the force-weighted distance from it to
/// the loaded contact nodes (the nominal radius when nothing is in contact).
fn loaded_centre_and_radius(m: &RollingModel) -> (P3, f64) {
    let nodes = &m.solver.model.mesh.nodes;
    let u = &m.solver.u;
    let hub = &m.contact.hub_nodes;
    let mut c = [0.0; 3];
    for &h in hub {
        for i in 0..3 {
            c[i] += (nodes[h][i] + u[h][i]) / hub.len() as f64;
        }
    }
    let (mut weighted, mut total) = (0.0, 0.0);
    for (k, st) in m.contact.pair.state.iter().enumerate() {
        if st.active {
            let n = m.contact.pair.slaves[k];
            let dx = nodes[n][0] + u[n][0] - c[0];
            let dz = nodes[n][2] + u[n][2] - c[2];
            weighted += st.normal_force_n * (dx * dx + dz * dz).sqrt();
            total += st.normal_force_n;
        }
    }
    let radius = if total > 0.0 {
        weighted / total
    } else {
        m.info.rolling_radius_m
    };
    (c, radius)
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
