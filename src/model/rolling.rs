//! The rolling model of a case, described without a solver: the scenario's mesh, the materials
//! per mesh material id, the track supports (fixed directions, ballast and pad springs), the
//! axle ends as one rigid body with the lateral motion and the torque, the sprung mass on the
//! primary suspension, the wheel-rail contact pair's definition and the nodes the outputs
//! follow (Yang & Li 2019; docs/physics.md, "Rolling model").
//!
//! [`crate::rolling::build`] applies this description to the explicit engine; keeping the two
//! apart lets another solver (an implicit static preload, a linear stability model) read the
//! same model.

use std::collections::BTreeMap;

use super::case::{LoadedCase, RollingCase};
use super::curve::Curve;
use super::spring::Spring;
use crate::friction::FrictionLaw;
use crate::material::Material;
use crate::mesh::{material, Mesh, P3};
use crate::{Error, Result};

/// Standard gravity (m/s^2).
pub const G_M_PER_S2: f64 = 9.81;

/// Height of the sprung-mass node above the axle box (m). Only its position in the output
/// files depends on it: the suspension spring acts along the coordinate axes, not along the
/// line between its nodes.
pub const SPRUNG_MASS_HEIGHT_M: f64 = 0.5;

/// Nodes the vibration outputs follow.
#[derive(Clone, Debug)]
pub struct RimAndHub {
    /// The rim point: the top node of the field-side rim face.
    pub rim_node: usize,
    /// Every node of the field-side rim face (the rim mean).
    pub rim_nodes: Vec<usize>,
    /// The hub bore nodes (the wheel centre and its spin).
    pub hub_nodes: Vec<usize>,
    /// The ring of rim nodes the run decomposes by nodal diameter (None: not asked for).
    pub ring: Option<RingNodes>,
}

/// Equally spaced nodes around one circle of the field-side rim face, in the order of their
/// material angle about the axle.
#[derive(Clone, Debug, PartialEq)]
pub struct RingNodes {
    /// The nodes, at angles `theta_0 + 2 pi k / N`.
    pub nodes: Vec<usize>,
    /// Material angle of the first (rad): `atan2(x - x_c, z - z_c)` on the upright wheel, 0
    /// at the top, growing towards the front (+x).
    pub theta0_rad: f64,
    /// Radius of the circle (m).
    pub radius_m: f64,
    /// Highest nodal diameter recorded.
    pub n_max: usize,
}

/// The axle ends as one rigid body that turns only about the axle axis (y), as in its
/// bearings, with the prescribed lateral displacement and the driving torque. With the two
/// ends free to move apart in x and to turn about z, the half wheelset would yaw under the
/// single wheel's traction, and the yaw angle is a lateral creepage (Yang & Li 2019: the same
/// lateral motion at both ends so that "the angle of attack stays about zero").
#[derive(Clone, Debug)]
pub struct AxleBody {
    /// Node set of both end faces (added to the mesh as `axle_ends`).
    pub node_set: String,
    /// Lateral displacement against time (m).
    pub lateral_m: Curve,
    /// Driving torque about the axle axis against time (N m).
    pub torque_n_m: Curve,
    /// The axle's axis (unit vector): `e_y` turned about the vertical by the angle of attack,
    /// `(sin psi, cos psi, 0)` ([`crate::model::case::CurvingSpec`]); the body turns about it
    /// and the torque acts about it.
    pub axis: P3,
}

/// The sprung mass on the primary suspension, joined to the axle-box node nearest the axis.
#[derive(Clone, Debug)]
pub struct SprungMass {
    /// The axle-box node (on the outer axle end face).
    pub axle_box_node: usize,
    /// Where the sprung-mass node sits (m).
    pub position_m: P3,
    /// Mass (kg).
    pub mass_kg: f64,
    /// Suspension stiffness per direction (N/m).
    pub stiffness_n_per_m: f64,
    /// Suspension damping per direction (N s/m).
    pub damping_n_s_per_m: f64,
    /// Static compression of the suspension under the sprung weight (m): the sprung mass
    /// starts there, because its 1-2 Hz bounce would otherwise need seconds of relaxation.
    pub static_compression_m: f64,
}

/// The wheel-rail contact pair: the wheel's tread nodes (slaves) on the rail's top faces
/// (masters), with the penalty `k = s K A^2 / V` from the steel's bulk modulus.
#[derive(Clone, Debug)]
pub struct ContactSpec {
    /// Slave nodes (`wheel_tread`).
    pub slaves: Vec<usize>,
    /// Master faces (`rail_top`).
    pub faces: Vec<[usize; 4]>,
    /// Penalty scale `s`.
    pub penalty_scale: f64,
    /// Bulk modulus of the steel (Pa).
    pub bulk_modulus_pa: f64,
    /// Friction law.
    pub friction: FrictionLaw,
}

/// The rolling model of a case.
#[derive(Clone, Debug)]
pub struct RollingDescription {
    /// The scenario's mesh (with the `axle_ends` set).
    pub mesh: Mesh,
    /// The wheel file's steel (wheel, axle, bands, rail).
    pub steel: Material,
    /// Material per mesh material id (the sleepers are the case's concrete).
    pub materials: BTreeMap<u32, Material>,
    /// Gravity (m/s^2).
    pub gravity_m_per_s2: [f64; 3],
    /// Mass-proportional damping (1/s).
    pub mass_damping_per_s: f64,
    /// Nodes of the wheelset (wheel, axle, band), which get the rolling velocity.
    pub wheelset_nodes: Vec<usize>,
    /// Wheel centre at the tape circle (m).
    pub wheel_centre_m: P3,
    /// Rolling radius at the tape circle (m).
    pub rolling_radius_m: f64,
    /// Nodes the outputs follow.
    pub rim_and_hub: RimAndHub,
    /// Fixed directions `[x, y, z]` per node set, in order.
    pub fixed_sets: Vec<(String, [bool; 3])>,
    /// Ballast and pad springs, sleeper by sleeper (ground springs, then pads).
    pub track_springs: Vec<Spring>,
    /// The axle ends.
    pub axle: AxleBody,
    /// The sprung mass.
    pub sprung_mass: SprungMass,
    /// The contact pair.
    pub contact: ContactSpec,
}

/// Describes the rolling model of a loaded case.
pub fn describe(loaded: &LoadedCase) -> Result<RollingDescription> {
    let case = &loaded.case;
    let source = loaded.source.display().to_string();
    let sc = &loaded.scenario;
    let mut mesh = sc.model_mesh();
    let steel = sc.wheel.material;
    let materials = [
        (material::WHEEL, steel),
        (material::AXLE, steel),
        (material::TREAD_BAND, steel),
        (material::RAIL, steel),
        (material::RAIL_BAND, steel),
        (material::SLEEPER, case.sleeper_material),
    ]
    .into_iter()
    .collect();
    let wheelset_nodes = wheelset_nodes(&mesh);
    let centre = sc.wheel_placement().tape_circle_centre_m;
    let rolling_radius_m = sc.wheel.tread_radius_mm(0.0) * 1e-3;
    let mut rim_and_hub = rim_and_hub(&mesh, &wheelset_nodes, centre, &source)?;
    if let Some(spec) = &case.output.ring {
        rim_and_hub.ring = Some(ring_nodes(
            &mesh.nodes,
            &rim_and_hub.rim_nodes,
            centre,
            spec.nodes,
            spec.n_max,
            &source,
        )?);
    }
    let contact = contact_spec(&mesh, case, steel, &source)?;
    let (fixed_sets, track_springs) = track_supports(&mesh, case, &source)?;
    let axle = axle_body(&mut mesh, case, &source)?;
    let sprung_mass = sprung_mass(&mesh, case, centre, &source)?;
    // Last: the rim, hub, axle-box and contact nodes were found on the upright wheelset.
    yaw_wheelset(
        &mut mesh,
        &wheelset_nodes,
        centre,
        case.angle_of_attack_rad(),
    );
    Ok(RollingDescription {
        mesh,
        steel,
        materials,
        gravity_m_per_s2: [0.0, 0.0, -G_M_PER_S2],
        mass_damping_per_s: case.mass_damping_per_s,
        wheelset_nodes,
        wheel_centre_m: centre,
        rolling_radius_m,
        rim_and_hub,
        fixed_sets,
        track_springs,
        axle,
        sprung_mass,
        contact,
    })
}

/// Nodes of wheel, axle and band elements.
fn wheelset_nodes(mesh: &Mesh) -> Vec<usize> {
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
    (0..mesh.nodes.len()).filter(|&n| in_wheelset[n]).collect()
}

fn named_set<'a>(mesh: &'a Mesh, name: &str, source: &str) -> Result<&'a [usize]> {
    match mesh.node_set(name) {
        Some(ids) if !ids.is_empty() => Ok(ids),
        _ => Err(Error::input(
            source,
            "model_scenario",
            format!("the mesh has no (or an empty) `{name}` node set"),
        )),
    }
}

/// The rim point (top node of the field-side rim face), the rim face and the hub bore.
fn rim_and_hub(mesh: &Mesh, wheelset: &[usize], centre: P3, source: &str) -> Result<RimAndHub> {
    let rim_nodes = rim_face_nodes(&mesh.nodes, wheelset, centre);
    let rim_node = *rim_nodes
        .iter()
        .max_by(|&&a, &&b| mesh.nodes[a][2].total_cmp(&mesh.nodes[b][2]))
        .ok_or_else(|| Error::input(source, "model_scenario", "no rim nodes found"))?;
    let hub_nodes = named_set(mesh, "hub_bore", source)?.to_vec();
    Ok(RimAndHub {
        rim_node,
        rim_nodes,
        hub_nodes,
        ring: None,
    })
}

/// The ring of `count` equally spaced nodes on the rim face: of the circles of the face (its
/// nodes grouped by radius, to 0.01 mm) the outermost that holds a node within 1e-6 rad of
/// every angle `theta_0 + 2 pi k / count`, `theta_0` the angle of its first node. The wheel
/// body's circles qualify when `count` divides their divisions; the tread band's, graded
/// around the wheel, do not.
pub fn ring_nodes(
    nodes: &[P3],
    rim_face: &[usize],
    centre: P3,
    count: usize,
    n_max: usize,
    source: &str,
) -> Result<RingNodes> {
    use std::f64::consts::TAU;
    let angle = |n: usize| (nodes[n][0] - centre[0]).atan2(nodes[n][2] - centre[2]);
    let mut circles: BTreeMap<i64, Vec<usize>> = BTreeMap::new();
    for &n in rim_face {
        let r_mm = axis_distance2(nodes[n], centre).sqrt() * 1e3;
        circles
            .entry((r_mm * 100.0).round() as i64)
            .or_default()
            .push(n);
    }
    let mut found = Vec::new();
    for (key, members) in circles.iter().rev() {
        found.push(format!("{:.2} mm: {}", *key as f64 / 100.0, members.len()));
        let Some(&first) = members
            .iter()
            .min_by(|&&a, &&b| angle(a).total_cmp(&angle(b)))
        else {
            continue;
        };
        let theta0 = angle(first);
        let ring: Option<Vec<usize>> = (0..count)
            .map(|k| {
                let target = theta0 + TAU * k as f64 / count as f64;
                members.iter().copied().find(|&n| {
                    let d = (angle(n) - target).rem_euclid(TAU);
                    d.min(TAU - d) < 1e-6
                })
            })
            .collect();
        if let Some(ring) = ring {
            return Ok(RingNodes {
                nodes: ring,
                theta0_rad: theta0,
                radius_m: *key as f64 / 100.0 * 1e-3,
                n_max,
            });
        }
    }
    Err(Error::input(
        source,
        "output.ring.nodes",
        format!(
            "no circle of the field-side rim face holds {count} equally spaced nodes: the count \
             must be a divisor of the nodes on one of its circles, e.g. of the wheel mesh's \
             circumferential_divisions (nodes per circle, outermost first: {})",
            found.join(", ")
        ),
    ))
}

fn contact_spec(
    mesh: &Mesh,
    case: &RollingCase,
    steel: Material,
    source: &str,
) -> Result<ContactSpec> {
    let slaves = named_set(mesh, "wheel_tread", source)?.to_vec();
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
    Ok(ContactSpec {
        slaves,
        faces,
        penalty_scale: case.penalty_scale,
        bulk_modulus_pa: steel.bulk_modulus_pa(),
        friction: case.friction,
    })
}

/// The track's supports of a case on a mesh holding the track's node sets: the fixed
/// directions per set (rail ends and sleeper bottoms held along and across the track, the
/// sleepers' centre faces across it where the case is symmetric about the track centre) and
/// the ballast and pad springs ([`track_springs`]). The rolling model and the stability
/// analysis's check of its rail against the FE track read the same supports.
#[allow(clippy::type_complexity)]
pub fn track_supports(
    mesh: &Mesh,
    case: &RollingCase,
    source: &str,
) -> Result<(Vec<(String, [bool; 3])>, Vec<Spring>)> {
    let mut fixed_sets = vec![
        ("rail_ends".to_string(), [true, true, false]),
        ("sleeper_bottoms".to_string(), [true, true, false]),
    ];
    if case.track_centre_symmetry {
        fixed_sets.push(("sleeper_centre_faces".to_string(), [false, true, false]));
    }
    Ok((fixed_sets, track_springs(mesh, case, source)?))
}

/// Track supports (Yang & Li 2019): ballast as vertical spring-dampers from each sleeper
/// bottom to the ground (the totals shared equally); rail pads as spring-dampers from each
/// rail-foot node over a sleeper to its nearest sleeper-top node, the pad's totals shared
/// equally, in shear a fraction of the vertical values.
fn track_springs(mesh: &Mesh, case: &RollingCase, source: &str) -> Result<Vec<Spring>> {
    let sleeper_count = mesh
        .node_sets
        .keys()
        .filter(|k| k.starts_with("sleeper_top_"))
        .count();
    let pad = case.rail_pad;
    let shear = pad.shear_fraction;
    let mut springs = Vec::new();
    for k in 0..sleeper_count {
        let tops = named_set(mesh, &format!("sleeper_top_{k}"), source)?;
        let bottoms_name = format!("sleeper_bottom_{k}");
        let bottoms = named_set(mesh, &bottoms_name, source)?;
        let share = 1.0 / bottoms.len() as f64;
        for &n in bottoms {
            springs.push(Spring {
                name: bottoms_name.clone(),
                node_a: n,
                node_b: None,
                stiffness_n_per_m: [0.0, 0.0, case.ballast.stiffness_n_per_m * share],
                damping_n_s_per_m: [0.0, 0.0, case.ballast.damping_n_s_per_m * share],
            });
        }
        let pad_nodes = named_set(mesh, &format!("rail_pad_{k}"), source)?;
        let share = 1.0 / pad_nodes.len() as f64;
        for &n in pad_nodes {
            let x = mesh.nodes[n];
            let nearest = *tops
                .iter()
                .min_by(|&&a, &&b| dist2(mesh.nodes[a], x).total_cmp(&dist2(mesh.nodes[b], x)))
                .expect("named_set is not empty");
            let (kz, cz) = (pad.stiffness_n_per_m * share, pad.damping_n_s_per_m * share);
            springs.push(Spring {
                name: format!("rail_pad_{k}"),
                node_a: n,
                node_b: Some(nearest),
                stiffness_n_per_m: [shear * kz, shear * kz, kz],
                damping_n_s_per_m: [shear * cz, shear * cz, cz],
            });
        }
    }
    Ok(springs)
}

/// The axle body: both end faces as the set `axle_ends`, the lateral motion and the torque
/// (ramped to its maximum, then held).
fn axle_body(mesh: &mut Mesh, case: &RollingCase, source: &str) -> Result<AxleBody> {
    let mut both_ends = named_set(mesh, "axle_inner_end", source)?.to_vec();
    both_ends.extend_from_slice(named_set(mesh, "axle_outer_end", source)?);
    mesh.add_node_set("axle_ends", both_ends);
    let torque_n_m = Curve::new(
        vec![
            0.0,
            case.torque.ramp_end_s,
            case.end_time_s.max(case.torque.ramp_end_s) + 1.0,
        ],
        vec![0.0, case.torque.max_n_m, case.torque.max_n_m],
        "torque",
    )?;
    Ok(AxleBody {
        node_set: "axle_ends".into(),
        lateral_m: lateral_curve(case)?,
        torque_n_m,
        axis: yawed_axle_axis(case.angle_of_attack_rad()),
    })
}

/// The axle axis of a wheelset yawed by `psi` (rad): `e_y` turned about `e_z` by `-psi`, so
/// that the rolling direction `a x e_z` is `(cos psi, -sin psi, 0)` (towards the track
/// centre for psi > 0, [`crate::model::case::CurvingSpec`]).
pub fn yawed_axle_axis(psi_rad: f64) -> P3 {
    if psi_rad == 0.0 {
        // Exactly e_y: the upright wheelset's runs stay bit for bit what they were.
        return [0.0, 1.0, 0.0];
    }
    [psi_rad.sin(), psi_rad.cos(), 0.0]
}

/// Turns the wheelset's nodes about the vertical through the wheel centre by `-psi` (the
/// rotation that takes `e_y` to [`yawed_axle_axis`]). The contact point under the centre stays
/// where it was; a tread point a distance `x` ahead of it moves sideways by `psi x`.
fn yaw_wheelset(mesh: &mut Mesh, wheelset: &[usize], centre: P3, psi_rad: f64) {
    if psi_rad == 0.0 {
        return;
    }
    let (sin, cos) = (-psi_rad).sin_cos();
    for &n in wheelset {
        let p = mesh.nodes[n];
        let (dx, dy) = (p[0] - centre[0], p[1] - centre[1]);
        mesh.nodes[n] = [
            centre[0] + cos * dx - sin * dy,
            centre[1] + sin * dx + cos * dy,
            p[2],
        ];
    }
}

fn sprung_mass(mesh: &Mesh, case: &RollingCase, centre: P3, source: &str) -> Result<SprungMass> {
    let axle_box_node = *named_set(mesh, "axle_outer_end", source)?
        .iter()
        .min_by(|&&a, &&b| {
            let da = axis_distance2(mesh.nodes[a], centre);
            let db = axis_distance2(mesh.nodes[b], centre);
            da.total_cmp(&db)
        })
        .expect("named_set is not empty");
    let b = mesh.nodes[axle_box_node];
    let ps = case.primary_suspension;
    Ok(SprungMass {
        axle_box_node,
        position_m: [b[0], b[1], b[2] + SPRUNG_MASS_HEIGHT_M],
        mass_kg: case.sprung_mass_kg,
        stiffness_n_per_m: ps.stiffness_n_per_m,
        damping_n_s_per_m: ps.damping_n_s_per_m,
        static_compression_m: case.sprung_mass_kg * G_M_PER_S2 / ps.stiffness_n_per_m,
    })
}

/// Lateral displacement of the axle ends against time (C1, see [`super::lateral`]).
pub fn lateral_curve(case: &RollingCase) -> Result<Curve> {
    match &case.lateral_motion {
        None => Ok(Curve::constant(0.0)),
        Some(l) => l.curve(),
    }
}

fn dist2(a: P3, b: P3) -> f64 {
    (0..3).map(|i| (a[i] - b[i]) * (a[i] - b[i])).sum()
}

/// Squared distance from the wheel axis (the y line through `centre`).
pub fn axis_distance2(x: P3, centre: P3) -> f64 {
    (x[0] - centre[0]).powi(2) + (x[2] - centre[2]).powi(2)
}

/// Nodes of the field-side face of the rim: wheelset nodes within 1 mm of the largest y among
/// nodes beyond 90 % of the largest radius.
pub fn rim_face_nodes(nodes: &[P3], wheelset: &[usize], centre: P3) -> Vec<usize> {
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
