//! The explicit model: elements, lumped masses, discrete parts, loads and constraints.
//!
//! Built from a [`Mesh`] and a material per element id, then extended with point masses,
//! spring-dampers, rigid node sets, fixed directions, prescribed motions, nodal loads, torques
//! and gravity. Every node set is looked up by name, and a missing name is an error that lists
//! the names there are.

// `!(x > 0.0)` is meant: it also rejects NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use super::element::{
    lumped_masses, ElasticMaterial, Formulation, FullElement, Hourglass, OnePointElement,
};
use crate::mesh::tie::TiePair;
use crate::mesh::{Mesh, P3};
use crate::model::curve::Curve;
pub use crate::model::spring::Spring;
use crate::{Error, Result};

/// The element arrays of one formulation.
#[derive(Clone, Debug)]
pub enum Elements {
    /// One-point elements with hourglass control.
    OnePoint(Vec<OnePointElement>),
    /// Fully integrated elements.
    Full(Vec<FullElement>),
}

impl Elements {
    /// Number of elements.
    pub fn len(&self) -> usize {
        match self {
            Elements::OnePoint(e) => e.len(),
            Elements::Full(e) => e.len(),
        }
    }
    /// True when there are no elements.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// Nodes of element `e`.
    pub fn nodes(&self, e: usize) -> [u32; 8] {
        match self {
            Elements::OnePoint(v) => v[e].nodes,
            Elements::Full(v) => v[e].nodes,
        }
    }
}

/// What a prescribed motion curve gives.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum MotionKind {
    /// Displacement (m) from the reference position.
    Displacement,
    /// Velocity (m/s).
    Velocity,
}

/// A prescribed displacement or velocity of a node set in one direction.
#[derive(Clone, Debug, PartialEq)]
pub struct PrescribedMotion {
    /// Name (node set name).
    pub name: String,
    /// Nodes.
    pub nodes: Vec<usize>,
    /// Direction 0 = x, 1 = y, 2 = z.
    pub direction: usize,
    /// Displacement or velocity.
    pub kind: MotionKind,
    /// The curve (m or m/s against s).
    pub curve: Curve,
}

/// A force on a node set, shared equally by its nodes and scaled by a curve.
#[derive(Clone, Debug, PartialEq)]
pub struct NodalLoad {
    /// Name.
    pub name: String,
    /// Nodes.
    pub nodes: Vec<usize>,
    /// Total force at curve value 1 (N).
    pub total_force_n: [f64; 3],
    /// Scale factor against time.
    pub curve: Curve,
}

/// A torque about a rigid body's centre of mass.
#[derive(Clone, Debug, PartialEq)]
pub struct TorqueLoad {
    /// Unit axis.
    pub axis: [f64; 3],
    /// Torque magnitude (N m) against time.
    pub curve_n_m: Curve,
}

/// A node set that moves as one rigid body (e.g. the half-axle end, driven as one).
#[derive(Clone, Debug, PartialEq)]
pub struct RigidBodySpec {
    /// Name.
    pub name: String,
    /// Member nodes.
    pub nodes: Vec<usize>,
    /// Prescribed displacement of the centre of mass per direction (m), if any.
    pub prescribed_translation_m: [Option<Curve>; 3],
    /// Applied torque.
    pub torque: Option<TorqueLoad>,
    /// If set (a unit vector), the body turns only about this fixed axis through its centre
    /// (an axle in its bearings): the moment components normal to it are taken by reactions
    /// that do no work, so `I_aa dω/dt = M·a` with `I_aa = aᵀ I a`.
    pub rotation_axis: Option<P3>,
    /// Prescribed spin about `rotation_axis` (rad/s against time; needs the axis). The moment
    /// that holds it is a reaction, booked as external work.
    pub prescribed_spin_rad_per_s: Option<Curve>,
}

/// The explicit model.
#[derive(Clone, Debug)]
pub struct Model {
    /// The mesh (for output and node sets); point masses append nodes to it.
    pub mesh: Mesh,
    /// Elements.
    pub elements: Elements,
    /// Material id per element (copied from the mesh).
    pub element_wave_speed_m_per_s: Vec<f64>,
    /// Lumped nodal masses (kg), before ties are condensed.
    pub nodal_mass_kg: Vec<f64>,
    /// Spring-dampers.
    pub springs: Vec<Spring>,
    /// Tie constraints (slave bound to a master face).
    pub ties: Vec<TiePair>,
    /// Rigid bodies.
    pub rigid_bodies: Vec<RigidBodySpec>,
    /// Fixed directions per node (bit 0 = x, 1 = y, 2 = z).
    pub fixed: Vec<u8>,
    /// Prescribed motions.
    pub prescribed: Vec<PrescribedMotion>,
    /// Nodal loads.
    pub loads: Vec<NodalLoad>,
    /// Gravity acceleration (m/s^2), e.g. `[0, 0, -9.81]`.
    pub gravity_m_per_s2: [f64; 3],
    /// Rayleigh mass-proportional damping alpha (1/s): `f = -alpha m v`.
    pub mass_damping_per_s: f64,
    /// Rayleigh stiffness-proportional damping beta (s).
    pub stiffness_damping_s: f64,
    /// Whether the hourglass form is viscous.
    pub viscous_hourglass: bool,
    /// Whether the hourglass form is the physical one.
    pub physical_hourglass: bool,
    /// Extra stable-step bounds registered by other modules (name, seconds).
    pub time_step_bounds: Vec<(String, f64)>,
}

impl Model {
    /// Builds elements and lumped masses. `materials` maps mesh material ids to materials;
    /// `source_name` names the input in errors.
    pub fn from_mesh(
        mesh: Mesh,
        materials: &BTreeMap<u32, ElasticMaterial>,
        formulation: Formulation,
        source_name: &str,
    ) -> Result<Model> {
        for (id, m) in materials {
            m.validate(source_name, &format!("materials[{id}]"))?;
        }
        // Tie slaves onto their master faces, so that ties are exact under large rotation.
        let mut mesh = mesh;
        mesh.snap_tie_slaves();
        let n_nodes = mesh.nodes.len();
        let mut nodal_mass_kg = vec![0.0; n_nodes];
        let mut wave_speed = Vec::with_capacity(mesh.elements.len());
        let mut one_point = Vec::new();
        let mut full = Vec::new();
        let (hourglass, viscous) = match formulation {
            Formulation::OnePoint { hourglass } => {
                let kappa = hourglass.coefficient();
                if !(0.0..=5.0).contains(&kappa) {
                    return Err(Error::input(
                        source_name,
                        "formulation.hourglass",
                        format!("coefficient must lie in [0, 5] (got {kappa})"),
                    ));
                }
                (hourglass, matches!(hourglass, Hourglass::Viscous { .. }))
            }
            Formulation::Full => (Hourglass::default(), false),
        };
        for (e, conn) in mesh.elements.iter().enumerate() {
            let id = mesh.material.get(e).copied().unwrap_or(0);
            let mat = materials.get(&id).ok_or_else(|| {
                Error::input(
                    source_name,
                    "materials",
                    format!(
                        "element {e} has material id {id}, which has no material (ids given: {:?})",
                        materials.keys().collect::<Vec<_>>()
                    ),
                )
            })?;
            let x = mesh.element_coords(e);
            let inverted = || {
                Error::input(
                    source_name,
                    format!("element {e}"),
                    format!(
                        "is inverted or degenerate (nodes {conn:?}): its volume must be positive \
                         at every node; check the mesh settings that built it"
                    ),
                )
            };
            let m = lumped_masses(&x, mat.density_kg_per_m3).ok_or_else(inverted)?;
            for a in 0..8 {
                nodal_mass_kg[conn[a]] += m[a];
            }
            wave_speed.push(mat.dilatational_wave_speed_m_per_s());
            match formulation {
                Formulation::OnePoint { .. } => one_point
                    .push(OnePointElement::new(*conn, &x, mat, hourglass).ok_or_else(inverted)?),
                Formulation::Full => {
                    full.push(FullElement::new(*conn, &x, mat).ok_or_else(inverted)?)
                }
            }
        }
        let ties: Vec<TiePair> = mesh
            .ties
            .iter()
            .flat_map(|t| t.pairs.iter().cloned())
            .collect();
        let elements = match formulation {
            Formulation::OnePoint { .. } => Elements::OnePoint(one_point),
            Formulation::Full => Elements::Full(full),
        };
        Ok(Model {
            elements,
            element_wave_speed_m_per_s: wave_speed,
            nodal_mass_kg,
            springs: Vec::new(),
            ties,
            rigid_bodies: Vec::new(),
            fixed: vec![0; n_nodes],
            prescribed: Vec::new(),
            loads: Vec::new(),
            gravity_m_per_s2: [0.0; 3],
            mass_damping_per_s: 0.0,
            stiffness_damping_s: 0.0,
            viscous_hourglass: viscous,
            physical_hourglass: matches!(
                formulation,
                Formulation::OnePoint {
                    hourglass: Hourglass::Physical { .. }
                }
            ),
            time_step_bounds: Vec::new(),
            mesh,
        })
    }

    /// Number of nodes (mesh nodes plus point masses).
    pub fn node_count(&self) -> usize {
        self.nodal_mass_kg.len()
    }

    /// Nodes of a named set; the error lists the sets there are.
    pub fn node_set(&self, name: &str) -> Result<Vec<usize>> {
        match self.mesh.node_sets.get(name) {
            Some(ids) if !ids.is_empty() => Ok(ids.clone()),
            Some(_) => Err(Error::input("model", name, "node set is empty")),
            None => Err(Error::input(
                "model",
                name,
                format!(
                    "no node set of that name; there are: {}",
                    self.mesh
                        .node_sets
                        .keys()
                        .cloned()
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            )),
        }
    }

    /// Adds a point mass as a new node (no element) at `position_m`; returns its id. It is also
    /// recorded as a one-node set `name`.
    pub fn add_point_mass(&mut self, name: &str, position_m: P3, mass_kg: f64) -> Result<usize> {
        if !(mass_kg > 0.0 && mass_kg.is_finite()) {
            return Err(Error::input(
                "model",
                format!("{name}.mass_kg"),
                format!("must be > 0 (got {mass_kg})"),
            ));
        }
        let id = self.mesh.nodes.len();
        self.mesh.nodes.push(position_m);
        self.nodal_mass_kg.push(mass_kg);
        self.fixed.push(0);
        self.mesh.add_node_set(name, [id]);
        Ok(id)
    }

    /// Adds a spring-damper after checking its values.
    pub fn add_spring(&mut self, spring: Spring) -> Result<()> {
        for c in 0..3 {
            let (k, d) = (spring.stiffness_n_per_m[c], spring.damping_n_s_per_m[c]);
            if !(k >= 0.0 && k.is_finite()) {
                return Err(Error::input(
                    "model",
                    format!("{}.stiffness_n_per_m[{c}]", spring.name),
                    format!("must be >= 0 (got {k})"),
                ));
            }
            if !(d >= 0.0 && d.is_finite()) {
                return Err(Error::input(
                    "model",
                    format!("{}.damping_n_s_per_m[{c}]", spring.name),
                    format!("must be >= 0 (got {d})"),
                ));
            }
        }
        let n = self.node_count();
        if spring.node_a >= n || spring.node_b.is_some_and(|b| b >= n) {
            return Err(Error::input(
                "model",
                &spring.name,
                format!("node id out of range (0..{n})"),
            ));
        }
        self.springs.push(spring);
        Ok(())
    }

    /// Springs from every node of `set` to the ground, the given totals shared equally (rail
    /// pads, ballast).
    pub fn add_ground_springs(
        &mut self,
        set: &str,
        total_stiffness_n_per_m: [f64; 3],
        total_damping_n_s_per_m: [f64; 3],
    ) -> Result<()> {
        let nodes = self.node_set(set)?;
        let share = 1.0 / nodes.len() as f64;
        for n in nodes {
            self.add_spring(Spring {
                name: set.to_string(),
                node_a: n,
                node_b: None,
                stiffness_n_per_m: total_stiffness_n_per_m.map(|k| k * share),
                damping_n_s_per_m: total_damping_n_s_per_m.map(|c| c * share),
            })?;
        }
        Ok(())
    }

    /// Fixes directions (`[x, y, z]`) of every node of a named set.
    pub fn fix_set(&mut self, set: &str, directions: [bool; 3]) -> Result<()> {
        let nodes = self.node_set(set)?;
        self.fix_nodes(&nodes, directions);
        Ok(())
    }

    /// Fixes directions of nodes.
    pub fn fix_nodes(&mut self, nodes: &[usize], directions: [bool; 3]) {
        let mask = directions
            .iter()
            .enumerate()
            .fold(0u8, |m, (i, &d)| if d { m | (1 << i) } else { m });
        for &n in nodes {
            self.fixed[n] |= mask;
        }
    }

    /// Prescribes a displacement or velocity curve on a named set in one direction.
    pub fn prescribe(
        &mut self,
        set: &str,
        direction: usize,
        kind: MotionKind,
        curve: Curve,
    ) -> Result<()> {
        if direction > 2 {
            return Err(Error::input(
                "model",
                format!("{set}.direction"),
                "must be 0 (x), 1 (y) or 2 (z)",
            ));
        }
        curve.validate("model", &format!("{set}.curve"))?;
        let nodes = self.node_set(set)?;
        self.prescribed.push(PrescribedMotion {
            name: set.to_string(),
            nodes,
            direction,
            kind,
            curve,
        });
        Ok(())
    }

    /// A force on a named set, shared equally, scaled by `curve`.
    pub fn add_load(&mut self, set: &str, total_force_n: [f64; 3], curve: Curve) -> Result<()> {
        curve.validate("model", &format!("{set}.curve"))?;
        let nodes = self.node_set(set)?;
        self.loads.push(NodalLoad {
            name: set.to_string(),
            nodes,
            total_force_n,
            curve,
        });
        Ok(())
    }

    /// Makes a named set one rigid body; returns its index.
    pub fn add_rigid_body(&mut self, set: &str) -> Result<usize> {
        let nodes = self.node_set(set)?;
        for rb in &self.rigid_bodies {
            if rb.nodes.iter().any(|n| nodes.binary_search(n).is_ok()) {
                return Err(Error::input(
                    "model",
                    set,
                    format!("shares nodes with rigid body {}", rb.name),
                ));
            }
        }
        self.rigid_bodies.push(RigidBodySpec {
            name: set.to_string(),
            nodes,
            prescribed_translation_m: [None, None, None],
            torque: None,
            rotation_axis: None,
            prescribed_spin_rad_per_s: None,
        });
        Ok(self.rigid_bodies.len() - 1)
    }

    /// Registers a stable time-step bound from another module (e.g. contact penalty).
    pub fn register_time_step_bound(&mut self, name: &str, seconds: f64) {
        self.time_step_bounds.push((name.to_string(), seconds));
    }

    /// Total mass (kg).
    pub fn total_mass_kg(&self) -> f64 {
        self.nodal_mass_kg.iter().sum()
    }
}
