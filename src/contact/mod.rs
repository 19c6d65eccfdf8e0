//! Node-to-segment penalty contact with Coulomb friction (Yang & Li 2019; docs/physics.md, "Explicit engine"), as an
//! auxiliary force of the explicit engine.
//!
//! Each step, for each slave node (wheel tread) of the region of interest ([`region`]: the
//! slaves near the master surface, chosen again when a slave has moved a median face size;
//! the others cannot touch a face before then, and the result is the full search's bit for bit):
//! 1. candidate master faces (rail top quads) come from a bucket grid over the faces' bounding
//!    boxes, rebuilt only when some node has moved more than half the search margin since the
//!    last build;
//! 2. the node is projected on each candidate (closest point on the bilinear face); the face
//!    with the projection inside it and the deepest penetration `g = (x_s - x_p) . n < 0` wins;
//! 3. normal force `f_N = -k g` along the face normal, with the penalty stiffness
//!    `k = s K A^2 / V` of the master face (LS-DYNA's solid-segment formula: `s` the scale factor
//!    of the scenario, `K` the bulk modulus, `A` the face area, `V` the volume of the element
//!    owning it);
//! 4. friction: trial force `f* = f_T(t) - k de` from the tangential movement `de` of the node
//!    relative to the master surface during the step, traction bound `mu |f_N|`, and return to
//!    the bound when exceeded; `mu` constant or falling, `mu(v) = mu_d + (mu_s - mu_d) exp(-c |v|)`
//!    with `v = |de| / dt` per node per step, or with one `v` for all, the patch's mean sliding
//!    velocity of the last step ([`SlipSpeed`]: why the node's own speed makes each node an
//!    oscillator of its own);
//! 5. the reaction goes to the face's four nodes with the bilinear weights of the projection.
//!
//! The engine's time step must stay below `min sqrt(m / k)` over the slaves; [`ContactPair::time_step_bound_s`]
//! gives it and the scenario registers it with the engine.
//!
//! Steps 3 and 4 are the penalty enforcement ([`Enforcement::Penalty`], the paper's). With
//! [`Enforcement::Exact`] the same search feeds forward-increment Lagrange multipliers instead
//! ([`exact`]): no penetration, no penalty stiffness, stick without elastic slip.

// Index loops mirror the vector notation of the equations; `!(x > 0.0)` also rejects NaN.
#![allow(clippy::needless_range_loop, clippy::neg_cmp_op_on_partial_ord)]

mod clearance;
pub mod exact;
mod grid;
pub mod patch;
pub mod region;

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::explicit::aux::{RankOneStiffness, StepPredictor};
use crate::explicit::AuxForces;
use crate::mesh::tie::project_on_face;
use crate::mesh::{Mesh, P3};
use crate::{Error, Result};

pub use clearance::Clearance;
use grid::BucketGrid;
pub use region::ContactSearch;
use region::{Region, SlaveForce, NO_FORCE};

pub use crate::friction::{FrictionLaw, SlipSpeed};

pub use crate::model::enforcement::Enforcement;

/// A master face found under a slave: gap (m), face, bilinear weights, unit normal.
pub(super) type FoundFace = (f64, u32, [f64; 4], P3);

/// Per-slave contact state (what the patch output reads).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct SlaveState {
    /// In contact in the last step.
    pub active: bool,
    /// Normal force magnitude (N).
    pub normal_force_n: f64,
    /// Tangential force on the slave (N).
    pub tangential_force_n: P3,
    /// Unit normal of the master face (pointing out of the master, towards the slave).
    pub normal: P3,
    /// Slip velocity `de / dt` (m/s) of the last step, tangential.
    pub slip_velocity_m_per_s: P3,
    /// Friction coefficient used.
    pub mu: f64,
    /// Whether the tangential force was at the traction bound (slip).
    pub at_bound: bool,
    /// Penetration depth (m, >= 0).
    pub penetration_m: f64,
    /// Master face index and projection weights.
    pub face: u32,
    /// Bilinear weights of the projection on the face.
    pub weights: [f64; 4],
}

/// A slave node set against a master surface.
pub struct ContactPair {
    /// Name.
    pub name: String,
    /// Slave nodes.
    pub slaves: Vec<usize>,
    /// Tributary area per slave (m^2), for pressures.
    pub slave_area_m2: Vec<f64>,
    /// Largest penalty per slave (N/m); infinite unless capped for the time step.
    pub slave_stiffness_cap: Vec<f64>,
    /// Master faces (outward node order: the normal points out of the master body).
    pub faces: Vec<[usize; 4]>,
    /// Penalty stiffness per face (N/m).
    pub face_stiffness_n_per_m: Vec<f64>,
    /// Per slave: its own penalty `s K A_s / L` (N/m) when the pair uses a penalty per unit
    /// area ([`ContactPair::use_area_penalty`]); None: the master faces' penalties.
    pub slave_penalty_n_per_m: Option<Vec<f64>>,
    /// Friction law.
    pub friction: FrictionLaw,
    /// Which slip speed the law reads: each node's own (default) or the patch's.
    pub slip_speed: SlipSpeed,
    /// Penalty (default) or exact enforcement. Exact applies to steps that give a prediction
    /// ([`AuxForces::add_forces_predicted`]); the static solver's steps stay penalty.
    pub enforcement: Enforcement,
    exact: exact::ExactSolver,
    /// The faces found under the region's slaves in an exact step (aligned with the region).
    found: Vec<Option<FoundFace>>,
    /// The patch's sliding velocity of the last step with a slave in contact (m/s): the
    /// normal-force-weighted mean of the active slaves' slip velocities ([`SlipSpeed::Patch`];
    /// zero before any contact and after a frictionless phase).
    patch_slip_velocity_m_per_s: P3,
    /// Per-slave state.
    pub state: Vec<SlaveState>,
    /// Penalty scale factor `s` of `k = s K A^2 / V`.
    pub penalty_scale: f64,
    /// Largest `|f_T| / (mu f_N)` over every active slave and every step since the last
    /// [`ContactPair::reset_monitors`]: the return mapping keeps it at 1 up to rounding
    /// (Yang & Li 2019: the tangential force never exceeds the traction bound); infinite if a slave
    /// with a zero bound carried a tangential force.
    pub largest_shear_over_bound: f64,
    /// Deepest penetration over every slave and every step since the last reset (m).
    pub deepest_penetration_m: f64,
    reference: Vec<P3>,
    search_margin_m: f64,
    /// How far a master node may move before the grid is rebuilt: a quarter of the median
    /// face size.
    rebuild_distance_m: f64,
    /// Median master face size (m): bounds the penetration searched below a face.
    median_face_size_m: f64,
    grid: BucketGrid,
    /// The master faces' nodes, sorted and once each: the rebuild check reads only these.
    master_nodes: Vec<usize>,
    /// Their positions when the grid was built (aligned with `master_nodes`).
    positions_at_build: Vec<P3>,
    forces: Vec<SlaveForce>,
    /// Which slaves are searched each step ([`ContactSearch::Region`] by default).
    pub search: ContactSearch,
    /// Run the region's guard ([`region::Region::misses`]) every this many steps and panic
    /// on a miss (0: never). Debug builds check every 64 steps; tests ask for every step.
    pub verify_region_every_steps: usize,
    steps: usize,
    region: Region,
}

/// Unit outward normal of a face and the length of `face_normal`'s vector (about the area).
#[inline]
fn unit_normal(p: &[P3; 4]) -> (P3, f64) {
    let n = crate::mesh::hex::face_normal(p[0], p[1], p[2], p[3]);
    let len = dot(n, n).sqrt();
    ([n[0] / len, n[1] / len, n[2] / len], len)
}

/// Signed distance `g = (x_s - x_p) . n` of `xs` from its projection `x_p` on the face, and the
/// projection's bilinear weights, when `xs` lies over the face. The projection is clamped to the
/// face: a node beside the face (not over it) has a tangential offset from its closest point;
/// only nodes over the face count, to 2 % of the face size (`4e-4 area`: the offset of a node
/// just past a shared edge).
#[inline]
fn distance_over_face(p: &[P3; 4], n: P3, area: f64, xs: P3) -> Option<(f64, [f64; 4])> {
    let (_, _, w, _) = project_on_face(p, xs);
    let xp = [0, 1, 2].map(|d| w[0] * p[0][d] + w[1] * p[1][d] + w[2] * p[2][d] + w[3] * p[3][d]);
    let d = sub(xs, xp);
    let g = dot(d, n);
    let tangential = [d[0] - g * n[0], d[1] - g * n[1], d[2] - g * n[2]];
    (dot(tangential, tangential) <= 4e-4 * area).then_some((g, w))
}

/// Bounding box (lowest and highest corner) of a face's four points.
fn face_box(points: [P3; 4]) -> (P3, P3) {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in points {
        for d in 0..3 {
            lo[d] = lo[d].min(p[d]);
            hi[d] = hi[d].max(p[d]);
        }
    }
    (lo, hi)
}

fn sub(a: P3, b: P3) -> P3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn dot(a: P3, b: P3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Slaves per parallel chunk of the contact loop.
const SLAVE_CHUNK: usize = 256;
/// Master nodes per parallel chunk of the rebuild check.
const MASTER_CHUNK: usize = 4096;

/// What one slave's contact update reads (shared by the parallel chunks).
struct SlaveContext<'a> {
    grid: &'a BucketGrid,
    faces: &'a [[usize; 4]],
    face_stiffness_n_per_m: &'a [f64],
    slave_penalty_n_per_m: Option<&'a [f64]>,
    slave_stiffness_cap: &'a [f64],
    friction: &'a FrictionLaw,
    /// The patch's slip speed when every node reads it ([`SlipSpeed::Patch`]); None: each its own.
    patch_slip_speed_m_per_s: Option<f64>,
    search_margin_m: f64,
    /// Accept slaves above a face (within the plane test's tolerance) as well as penetrating
    /// ones: exact enforcement decides from the step's motion whether they touch.
    accept_open_gap: bool,
    reference: &'a [P3],
    slaves: &'a [usize],
    u: &'a [P3],
    v: &'a [P3],
    dt_s: f64,
}

impl SlaveContext<'_> {
    /// The master face slave `k` meets: the deepest penetrated face over which it lies (with
    /// `accept_open_gap`, the nearest face it lies over, penetrated or not), its gap, the
    /// projection's weights and the face's unit normal.
    fn find_face(&self, k: usize) -> Option<FoundFace> {
        let (reference, u) = (self.reference, self.u);
        let pos = |n: usize| -> P3 { [0, 1, 2].map(|i| reference[n][i] + u[n][i]) };
        let xs = pos(self.slaves[k]);
        let mut best: Option<FoundFace> = None;
        for &fi in self.grid.candidates(xs) {
            let (blo, bhi) = (
                self.grid.face_lo[fi as usize],
                self.grid.face_hi[fi as usize],
            );
            if (0..3).any(|d| xs[d] < blo[d] || xs[d] > bhi[d]) {
                continue;
            }
            let f = self.faces[fi as usize];
            let p = f.map(pos);
            let (n, area) = unit_normal(&p);
            // Cheap plane test first: a node above the face's mean plane (beyond 5 % of
            // the face size, for warped faces) is not in contact with it.
            let centroid = [0, 1, 2].map(|d| 0.25 * (p[0][d] + p[1][d] + p[2][d] + p[3][d]));
            if dot(sub(xs, centroid), n) > 0.05 * area.sqrt() {
                continue;
            }
            let Some((gap, w)) = distance_over_face(&p, n, area, xs) else {
                continue;
            };
            // Penetrations deeper than a face size are the far side of a thin part.
            if (gap < 0.0 || self.accept_open_gap)
                && gap > -self.search_margin_m
                && best.is_none_or(|b| gap < b.0)
            {
                best = Some((gap, fi, w, n));
            }
        }
        best
    }

    /// Contact of slave `k`: closest penetrated master face, normal penalty force, friction
    /// (trial force and return to the bound); updates its state and returns its total force,
    /// the master point's weights and the face (`u32::MAX`: no contact).
    fn update(&self, k: usize, st: &mut SlaveState) -> (P3, [f64; 4], u32) {
        let (v, dt_s) = (self.v, self.dt_s);
        let s = self.slaves[k];
        let Some((gap, fi, w, n)) = self.find_face(k) else {
            // Most slaves are far from the rail: leave their (already clear) state untouched
            // rather than write it every step.
            if st.active {
                *st = SlaveState {
                    mu: st.mu,
                    ..Default::default()
                };
            }
            return ([0.0; 3], [0.0; 4], u32::MAX);
        };
        let kf = penalty_of(
            self.slave_penalty_n_per_m,
            self.face_stiffness_n_per_m,
            k,
            fi as usize,
        )
        .min(self.slave_stiffness_cap[k]);
        let f_n = -kf * gap;
        // Tangential movement of the slave relative to the master point in the last step.
        let f = self.faces[fi as usize];
        let vm = [0, 1, 2]
            .map(|d| w[0] * v[f[0]][d] + w[1] * v[f[1]][d] + w[2] * v[f[2]][d] + w[3] * v[f[3]][d]);
        let vr = sub(v[s], vm);
        let vn = dot(vr, n);
        let vt = [vr[0] - vn * n[0], vr[1] - vn * n[1], vr[2] - vn * n[2]];
        let de = vt.map(|c| c * dt_s);
        let slip_speed = dot(vt, vt).sqrt();
        let mu = self
            .friction
            .mu(self.patch_slip_speed_m_per_s.unwrap_or(slip_speed));
        // Previous tangential force, rotated into the current tangent plane (magnitude kept).
        let ft_old = if st.active {
            st.tangential_force_n
        } else {
            [0.0; 3]
        };
        let on = dot(ft_old, n);
        let mut ft = [
            ft_old[0] - on * n[0],
            ft_old[1] - on * n[1],
            ft_old[2] - on * n[2],
        ];
        let old_mag = dot(ft_old, ft_old).sqrt();
        let new_mag = dot(ft, ft).sqrt();
        if new_mag > 0.0 {
            ft = ft.map(|c| c * old_mag / new_mag);
        }
        // Trial force f* = f_T - k de; return to the bound mu |f_N| when exceeded.
        let trial = [ft[0] - kf * de[0], ft[1] - kf * de[1], ft[2] - kf * de[2]];
        let trial_mag = dot(trial, trial).sqrt();
        let bound = mu * f_n;
        let (ft_new, at_bound) = if trial_mag > bound {
            let s = bound / trial_mag;
            (trial.map(|c| c * s), true)
        } else {
            (trial, false)
        };
        *st = SlaveState {
            active: true,
            normal_force_n: f_n,
            tangential_force_n: ft_new,
            normal: n,
            slip_velocity_m_per_s: vt,
            mu,
            at_bound,
            penetration_m: -gap,
            face: fi,
            weights: w,
        };
        let total = [0, 1, 2].map(|d| f_n * n[d] + ft_new[d]);
        (total, w, fi)
    }
}

/// The penalty of slave `k` on master face `face` (N/m): the slave's own under a penalty per
/// unit area, else the face's `s K A^2 / V`.
fn penalty_of(slave_penalty: Option<&[f64]>, face_stiffness: &[f64], k: usize, face: usize) -> f64 {
    match slave_penalty {
        Some(p) => p[k],
        None => face_stiffness[face],
    }
}

impl ContactPair {
    /// Sets up a pair on `mesh`: slave nodes, master faces (outward order), the penalty scale
    /// factor, the bulk modulus of the master (Pa) and the friction law. The element owning each
    /// master face gives its volume for the penalty stiffness.
    pub fn new(
        name: &str,
        mesh: &Mesh,
        slaves: Vec<usize>,
        faces: Vec<[usize; 4]>,
        penalty_scale: f64,
        bulk_modulus_pa: f64,
        friction: FrictionLaw,
    ) -> Result<ContactPair> {
        friction.validate("scenario", "contact.friction")?;
        if !(penalty_scale > 0.0 && penalty_scale <= 100.0) {
            return Err(Error::input(
                "scenario",
                "contact.penalty_scale",
                format!("must lie in (0, 100] (got {penalty_scale})"),
            ));
        }
        if slaves.is_empty() || faces.is_empty() {
            return Err(Error::input(
                "scenario",
                name,
                "contact needs slave nodes and master faces",
            ));
        }
        // Owner volume of each face.
        let owners: std::collections::HashMap<[usize; 4], usize> = mesh
            .boundary_faces()
            .into_iter()
            .map(|(f, e)| {
                let mut key = f;
                key.sort_unstable();
                (key, e)
            })
            .collect();
        let mut stiffness = Vec::with_capacity(faces.len());
        for (k, f) in faces.iter().enumerate() {
            let mut key = *f;
            key.sort_unstable();
            let e = *owners.get(&key).ok_or_else(|| {
                Error::input(
                    "scenario",
                    name,
                    format!("master face {k} ({f:?}) is not on the boundary of the mesh"),
                )
            })?;
            let x = mesh.element_coords(e);
            let volume = crate::mesh::hex::volume(&x);
            let p = f.map(|n| mesh.nodes[n]);
            let area = crate::mesh::hex::face_area(p[0], p[1], p[2], p[3]);
            stiffness.push(penalty_scale * bulk_modulus_pa * area * area / volume);
        }
        // Tributary areas of the slaves: a quarter of each boundary face around them.
        let slave_index: std::collections::HashMap<usize, usize> =
            slaves.iter().enumerate().map(|(i, &n)| (n, i)).collect();
        let mut slave_area = vec![0.0; slaves.len()];
        for (f, _) in mesh.boundary_faces() {
            if f.iter().all(|n| slave_index.contains_key(n)) {
                let p = f.map(|n| mesh.nodes[n]);
                let a = crate::mesh::hex::face_area(p[0], p[1], p[2], p[3]);
                for n in f {
                    slave_area[slave_index[&n]] += 0.25 * a;
                }
            }
        }
        let face_size = faces
            .iter()
            .map(|f| {
                let p = f.map(|n| mesh.nodes[n]);
                crate::mesh::hex::face_area(p[0], p[1], p[2], p[3]).sqrt()
            })
            .fold(0.0, f64::max);
        let mut face_sizes: Vec<f64> = faces
            .iter()
            .map(|f| {
                let p = f.map(|n| mesh.nodes[n]);
                crate::mesh::hex::face_area(p[0], p[1], p[2], p[3]).sqrt()
            })
            .collect();
        face_sizes.sort_by(f64::total_cmp);
        let median_face_size = face_sizes[face_sizes.len() / 2];
        let n_slaves = slaves.len();
        let mut master_nodes: Vec<usize> = faces.iter().flatten().copied().collect();
        master_nodes.sort_unstable();
        master_nodes.dedup();
        let mut pair = ContactPair {
            name: name.to_string(),
            slaves,
            slave_stiffness_cap: vec![f64::INFINITY; n_slaves],
            slave_area_m2: slave_area,
            faces,
            face_stiffness_n_per_m: stiffness,
            slave_penalty_n_per_m: None,
            friction,
            slip_speed: SlipSpeed::Node,
            enforcement: Enforcement::Penalty,
            exact: exact::ExactSolver::new(n_slaves, mesh.nodes.len()),
            found: Vec::with_capacity(n_slaves),
            patch_slip_velocity_m_per_s: [0.0; 3],
            state: vec![SlaveState::default(); n_slaves],
            penalty_scale,
            largest_shear_over_bound: 0.0,
            deepest_penetration_m: 0.0,
            reference: mesh.nodes.clone(),
            search_margin_m: face_size,
            rebuild_distance_m: 0.25 * median_face_size,
            median_face_size_m: median_face_size,
            grid: BucketGrid::default(),
            master_nodes,
            positions_at_build: Vec::new(),
            forces: vec![NO_FORCE; n_slaves],
            search: ContactSearch::Region,
            verify_region_every_steps: if cfg!(debug_assertions) { 64 } else { 0 },
            steps: 0,
            // A slave may move one median face size before the region is rebuilt: on the paper
            // model a few hundred steps of the rolling tread.
            region: Region::new(n_slaves, median_face_size),
        };
        let zero = vec![[0.0; 3]; mesh.nodes.len()];
        pair.build_grid(&zero);
        Ok(pair)
    }

    /// Switches the pair to a penalty per unit area: slave `k` gets `s K A_k / L`, with its
    /// tributary area `A_k`, the pair's scale `s`, the master's bulk modulus `K` and the length
    /// `L` (m), whatever master face it meets (see `RollingCase::penalty_length_mm`).
    pub fn use_area_penalty(&mut self, bulk_modulus_pa: f64, length_m: f64) {
        let per_area = self.penalty_scale * bulk_modulus_pa / length_m;
        self.slave_penalty_n_per_m =
            Some(self.slave_area_m2.iter().map(|a| per_area * a).collect());
    }

    /// The stiffest penalty a slave can meet (N/m): its own, or the stiffest master face's.
    fn stiffest_penalty(&self, k: usize, stiffest_face: f64) -> f64 {
        match &self.slave_penalty_n_per_m {
            Some(p) => p[k],
            None => stiffest_face,
        }
    }

    /// The stable-step bound `min sqrt(m_s / k)` over slaves (with the stiffest face or the
    /// slave's own penalty, or the slave's cap), given the engine's effective nodal masses.
    pub fn time_step_bound_s(&self, mass_kg: &[f64]) -> f64 {
        let k_max = self
            .face_stiffness_n_per_m
            .iter()
            .fold(0.0f64, |m, &k| m.max(k));
        self.slaves
            .iter()
            .enumerate()
            .map(|(k, &n)| {
                let stiffest = self.stiffest_penalty(k, k_max);
                (mass_kg[n] / stiffest.min(self.slave_stiffness_cap[k])).sqrt()
            })
            .fold(f64::INFINITY, f64::min)
    }

    /// Caps each slave's penalty at `m_s / dt^2` so that the contact never asks for a step
    /// below `dt_s` (the idea of LS-DYNA's soft constraint, SOFT = 1: light slave nodes on
    /// stiff thin master segments would otherwise control the step of the whole model).
    /// Returns how many slaves were capped.
    pub fn cap_stiffness_for_step(&mut self, mass_kg: &[f64], dt_s: f64) -> usize {
        let k_max = self
            .face_stiffness_n_per_m
            .iter()
            .fold(0.0f64, |m, &k| m.max(k));
        let mut capped = 0;
        for (k, &n) in self.slaves.iter().enumerate() {
            let cap = mass_kg[n] / (dt_s * dt_s);
            self.slave_stiffness_cap[k] = cap;
            if cap < k_max {
                capped += 1;
            }
        }
        capped
    }

    /// The largest penalty scale that the time step `dt_s` (after
    /// [`ContactPair::cap_stiffness_for_step`]) can carry: the scale at which the softest master
    /// face's penalty `s K A^2 / V` (with a penalty per unit area, the softest slave's
    /// `s K A_s / L`) reaches the median slave's cap `m_s / dt^2`. Above it, half
    /// the slaves or more get the cap against every master face, whatever the scale, so the
    /// scale asked for is not what the model computes. Requires the caps to be set.
    pub fn largest_penalty_scale(&self) -> f64 {
        let softest_face = self
            .slave_penalty_n_per_m
            .as_deref()
            .unwrap_or(&self.face_stiffness_n_per_m)
            .iter()
            .fold(f64::INFINITY, |m, &k| m.min(k));
        let mut caps = self.slave_stiffness_cap.clone();
        caps.sort_by(f64::total_cmp);
        let median_cap = caps[caps.len() / 2];
        // k scales linearly with s: s_max / s = cap / k.
        self.penalty_scale * median_cap / softest_face
    }

    /// Error naming `field` when the penalty scale exceeds [`ContactPair::largest_penalty_scale`].
    pub fn check_penalty_scale_against_step(&self, source: &str, field: &str) -> Result<()> {
        let largest = self.largest_penalty_scale();
        if self.penalty_scale > largest {
            return Err(Error::input(
                source,
                field,
                format!(
                    "{} violates the time step: even on the softest master face the penalty \
                     exceeds the stable value m / dt^2 of half the slave nodes, which would \
                     all be held at that cap instead; must lie in (0, {largest:.3}] for this \
                     mesh and step",
                    self.penalty_scale
                ),
            ));
        }
        Ok(())
    }

    /// The search's bookkeeping before a step: the bucket grid rebuilt when master nodes have
    /// moved, the region of interest chosen again when slaves have, and the region's guard.
    fn prepare_search(&mut self, u: &[P3]) {
        if self.needs_rebuild(u) {
            // Rare (when nodes moved half a face): allocation here is outside the steady loop.
            self.build_grid(u);
        }
        let (reference, slaves) = (&self.reference, &self.slaves);
        let position = |k: usize| -> P3 {
            let n = slaves[k];
            [0, 1, 2].map(|i| reference[n][i] + u[n][i])
        };
        if self.region.needs_rebuild(&position) {
            self.region.rebuild(
                &self.grid,
                self.search,
                &position,
                &mut self.state,
                &mut self.forces,
            );
        }
        self.steps += 1;
        if self.verify_region_every_steps > 0
            && self.steps.is_multiple_of(self.verify_region_every_steps)
        {
            let misses = self.region.misses(&self.grid, &position);
            assert!(
                misses == 0,
                "contact `{}`: {misses} slaves outside the region of interest lie inside a \
                 master face's box at step {}",
                self.name,
                self.steps
            );
        }
    }

    /// What the slaves' search and update read this step.
    fn context<'a>(
        &'a self,
        u: &'a [P3],
        v: &'a [P3],
        dt_s: f64,
        accept_open_gap: bool,
    ) -> SlaveContext<'a> {
        SlaveContext {
            grid: &self.grid,
            faces: &self.faces,
            face_stiffness_n_per_m: &self.face_stiffness_n_per_m,
            slave_penalty_n_per_m: self.slave_penalty_n_per_m.as_deref(),
            slave_stiffness_cap: &self.slave_stiffness_cap,
            friction: &self.friction,
            patch_slip_speed_m_per_s: self.patch_slip_speed(),
            search_margin_m: self.search_margin_m,
            accept_open_gap,
            reference: &self.reference,
            slaves: &self.slaves,
            u,
            v,
            dt_s,
        }
    }

    /// The patch's slip speed when every node reads it ([`SlipSpeed::Patch`]); None: each its own.
    fn patch_slip_speed(&self) -> Option<f64> {
        match self.slip_speed {
            SlipSpeed::Node => None,
            SlipSpeed::Patch => {
                let v = self.patch_slip_velocity_m_per_s;
                Some(dot(v, v).sqrt())
            }
        }
    }

    /// Adds the region's slave forces (`forces`) to the slaves and their faces' nodes.
    fn scatter_forces(&mut self, force: &mut [P3]) {
        // Scatter (serial: slaves share master nodes), and the invariants' monitors over the
        // slaves in contact: only the region's can be (the others' entries are empty), visited
        // in slave order as a loop over every slave would.
        let (mut largest_ratio, mut deepest) =
            (self.largest_shear_over_bound, self.deepest_penetration_m);
        // The patch's sliding velocity for the next step, summed in slave order (serially, so
        // that it does not depend on the thread count).
        let (mut weighted_slip, mut normal_sum) = ([0.0; 3], 0.0);
        for &k in &self.region.slaves {
            let k = k as usize;
            let s = self.slaves[k];
            let (f, w, fi) = self.forces[k];
            if fi == u32::MAX {
                continue;
            }
            let st = &self.state[k];
            let bound = st.mu * st.normal_force_n;
            let shear = dot(st.tangential_force_n, st.tangential_force_n).sqrt();
            let ratio = if bound > 0.0 {
                shear / bound
            } else if shear > 0.0 {
                f64::INFINITY
            } else {
                0.0
            };
            largest_ratio = largest_ratio.max(ratio);
            deepest = deepest.max(st.penetration_m);
            for d in 0..3 {
                weighted_slip[d] += st.normal_force_n * st.slip_velocity_m_per_s[d];
            }
            normal_sum += st.normal_force_n;
            for d in 0..3 {
                force[s][d] += f[d];
            }
            let face = self.faces[fi as usize];
            for (j, &m) in face.iter().enumerate() {
                for d in 0..3 {
                    force[m][d] -= w[j] * f[d];
                }
            }
        }
        self.largest_shear_over_bound = largest_ratio;
        self.deepest_penetration_m = deepest;
        // A step with no slave in contact (a block chattering on its penalty springs) has no
        // sliding velocity of its own: the last one holds, rather than the static coefficient
        // for the slaves that touch down next.
        if normal_sum > 0.0 {
            self.patch_slip_velocity_m_per_s = weighted_slip.map(|c| c / normal_sum);
        }
    }

    fn build_grid(&mut self, u: &[P3]) {
        let pos = |n: usize| -> P3 { [0, 1, 2].map(|i| self.reference[n][i] + u[n][i]) };
        // Each face's box is widened by the rebuild distance (how far its nodes may move before
        // a rebuild) plus the deepest penetration searched below it: half its size, but at
        // most half the median face size. A coarse face far from the patch (120 mm on the
        // paper's rail ends) would otherwise reach 60 mm above the rail and hand its box to
        // every wheel node over it; a penalty penetration is a few tens of micrometres.
        let margin = self.rebuild_distance_m;
        let raw: Vec<(P3, P3)> = self.faces.iter().map(|f| face_box(f.map(pos))).collect();
        let mut sizes: Vec<f64> = raw
            .iter()
            .map(|(lo, hi)| (0..3).map(|d| hi[d] - lo[d]).fold(0.0, f64::max))
            .collect();
        let boxes: Vec<(P3, P3)> = raw
            .iter()
            .zip(&sizes)
            .map(|((lo, hi), &size)| {
                let widen = margin + 0.5 * size.min(self.median_face_size_m);
                (lo.map(|x| x - widen), hi.map(|x| x + widen))
            })
            .collect();
        // Cells of about twice the small faces' size (the tenth percentile of the sizes).
        sizes.sort_by(f64::total_cmp);
        let small = sizes.get(sizes.len() / 10).copied().unwrap_or(1e-3);
        self.grid = BucketGrid::new(&boxes, small);
        self.positions_at_build = self.master_nodes.iter().map(|&n| pos(n)).collect();
        // The faces' boxes changed: the region is chosen again against them.
        self.region.valid = false;
    }

    /// The patch's sliding velocity of the last step (m/s): the normal-force-weighted mean of
    /// the active slaves' slip velocities, which [`SlipSpeed::Patch`] evaluates the law at.
    pub fn patch_slip_velocity_m_per_s(&self) -> P3 {
        self.patch_slip_velocity_m_per_s
    }

    /// Exact enforcement so far ([`exact`]): the most Gauss-Seidel sweeps a step took, the
    /// steps that stopped at [`exact::MAX_SWEEPS`] unconverged, and the contact node-steps
    /// held for want of a free motion (fixed, prescribed, tied or rigid nodes).
    pub fn exact_statistics(&self) -> (usize, usize, usize) {
        (
            self.exact.largest_sweeps,
            self.exact.unconverged_steps,
            self.exact.held_node_steps,
        )
    }

    /// Slaves searched in the last step (all of them with [`ContactSearch::Full`]).
    pub fn searched_slaves(&self) -> usize {
        self.region.slaves.len()
    }

    /// Makes the next step choose the region of interest afresh.
    pub fn invalidate_region(&mut self) {
        self.region.valid = false;
    }

    /// Times the region of interest was built so far.
    pub fn region_rebuilds(&self) -> usize {
        self.region.rebuilds
    }

    fn needs_rebuild(&self, u: &[P3]) -> bool {
        let limit = self.rebuild_distance_m;
        let limit2 = limit * limit;
        // Only the master faces are binned; slaves look up the cell of their current position,
        // so a rolling wheel's slaves never force a rebuild. The master nodes are read once
        // each, in node order (the faces' own lists would read each node up to four times, at
        // random, from the whole model's arrays).
        // Fixed chunks, as the other parallel loops: a bounded number of jobs.
        self.master_nodes
            .par_chunks(MASTER_CHUNK)
            .zip(self.positions_at_build.par_chunks(MASTER_CHUNK))
            .any(|(nodes, at_build)| {
                nodes.iter().zip(at_build).any(|(&n, p)| {
                    let x = [0, 1, 2].map(|i| self.reference[n][i] + u[n][i]);
                    let d = sub(x, *p);
                    dot(d, d) > limit2
                })
            })
    }

    /// Switches friction off (a frictionless phase, e.g. the static preload) and returns the
    /// law to put back.
    pub fn suspend_friction(&mut self) -> FrictionLaw {
        let law = self.friction;
        self.friction = FrictionLaw::Coulomb { mu: 0.0 };
        law
    }

    /// Puts `law` back (after [`ContactPair::suspend_friction`]) and starts every slave's
    /// tangential force from zero: the frictionless phase left none, and its path must not
    /// leave stick forces behind.
    pub fn resume_friction(&mut self, law: FrictionLaw) {
        self.friction = law;
        self.patch_slip_velocity_m_per_s = [0.0; 3];
        for st in self.state.iter_mut() {
            st.tangential_force_n = [0.0; 3];
            st.mu = law.mu(0.0);
        }
    }

    /// Starts the invariants' monitors afresh (`largest_shear_over_bound`,
    /// `deepest_penetration_m`), e.g. after a frictionless preload.
    pub fn reset_monitors(&mut self) {
        self.largest_shear_over_bound = 0.0;
        self.deepest_penetration_m = 0.0;
    }

    /// Sum of the contact forces on the slaves (N) and the traction bound `sum mu |f_N|`.
    pub fn resultants(&self) -> (P3, P3, f64) {
        let mut normal = [0.0; 3];
        let mut tangential = [0.0; 3];
        let mut bound = 0.0;
        for s in &self.state {
            if s.active {
                for d in 0..3 {
                    normal[d] += s.normal_force_n * s.normal[d];
                    tangential[d] += s.tangential_force_n[d];
                }
                bound += s.mu * s.normal_force_n;
            }
        }
        (normal, tangential, bound)
    }
}

impl AuxForces for ContactPair {
    /// `contact_force_n`: the force on each slave node from the last step, normal
    /// (`f_N n`, n out of the master) plus tangential; zero elsewhere. Over the patch it is the
    /// contact pressure times each node's share of the area.
    /// `contact_force_n`: each slave node's total contact force; `contact_pressure_pa`: its
    /// normal pressure (normal force over the node's tributary area, as the patch snapshots
    /// report it) along the contact normal, so ParaView shows the pressure as the magnitude.
    fn snapshot_fields(&self, node_count: usize) -> Vec<(String, Vec<P3>)> {
        let mut force = vec![[0.0; 3]; node_count];
        let mut pressure = vec![[0.0; 3]; node_count];
        for (k, (s, &node)) in self.state.iter().zip(&self.slaves).enumerate() {
            if node < node_count && s.active {
                let pressure_pa = s.normal_force_n / self.slave_area_m2[k].max(1e-300);
                for d in 0..3 {
                    force[node][d] = s.normal_force_n * s.normal[d] + s.tangential_force_n[d];
                    pressure[node][d] = pressure_pa * s.normal[d];
                }
            }
        }
        vec![
            ("contact_force_n".to_string(), force),
            ("contact_pressure_pa".to_string(), pressure),
        ]
    }

    /// The slaves and the master faces' nodes: the only nodes the contact force acts on.
    fn force_nodes(&self) -> Option<Vec<usize>> {
        let mut nodes = self.slaves.clone();
        nodes.extend(self.faces.iter().flatten().copied());
        nodes.sort_unstable();
        nodes.dedup();
        Some(nodes)
    }

    fn add_forces(&mut self, _time_s: f64, dt_s: f64, u: &[P3], v: &[P3], force: &mut [P3]) {
        self.prepare_search(u);
        // The region's slaves, gathered so that parallel chunks own their states (the work
        // vectors are moved out and back: no allocation).
        let mut states = std::mem::take(&mut self.region.state);
        let mut forces = std::mem::take(&mut self.region.forces);
        states.clear();
        forces.clear();
        for &k in &self.region.slaves {
            states.push(self.state[k as usize]);
            forces.push(self.forces[k as usize]);
        }
        // Slaves in parallel chunks: each slave's search, penalty and friction update touch only
        // its own state, so the result does not depend on the thread count.
        let ctx = self.context(u, v, dt_s, false);
        let indices = &self.region.slaves;
        states
            .par_chunks_mut(SLAVE_CHUNK)
            .zip(forces.par_chunks_mut(SLAVE_CHUNK))
            .enumerate()
            .for_each(|(c, (states, forces))| {
                for (j, (st, out)) in states.iter_mut().zip(forces.iter_mut()).enumerate() {
                    let new = ctx.update(indices[c * SLAVE_CHUNK + j] as usize, st);
                    // A slave out of contact in both steps keeps its entry unwritten.
                    if new.2 != u32::MAX || out.2 != u32::MAX {
                        *out = new;
                    }
                }
            });
        for (j, &k) in self.region.slaves.iter().enumerate() {
            self.state[k as usize] = states[j];
            self.forces[k as usize] = forces[j];
        }
        self.region.state = states;
        self.region.forces = forces;
        self.scatter_forces(force);
    }

    /// Exact enforcement ([`exact`]) on steps that predict the free motion; the penalty's
    /// otherwise (and on multi-rate steps, which predict nothing).
    fn add_forces_predicted(
        &mut self,
        time_s: f64,
        dt_s: f64,
        u: &[P3],
        v: &[P3],
        force: &mut [P3],
        predictor: &StepPredictor,
    ) {
        if self.enforcement == Enforcement::Exact && !predictor.multi_rate() {
            self.add_exact_forces(dt_s, u, v, force, predictor);
        } else {
            self.add_forces(time_s, dt_s, u, v, force);
        }
    }

    /// One term per active slave: `kf b bᵀ` with `b = n` on the slave and `-w_j n` on the face's
    /// nodes, the derivative of the normal penalty force `-kf g n` (`g = (x_s - sum w_j x_j) . n`)
    /// with the normal and the weights held (their variation is second order in the
    /// penetration). The tangential forces are left out: the static solver runs frictionless.
    fn stiffness_terms(&self, out: &mut Vec<RankOneStiffness>) {
        for &k in &self.region.slaves {
            let k = k as usize;
            let st = &self.state[k];
            if !st.active || st.face == u32::MAX {
                continue;
            }
            let face = self.faces[st.face as usize];
            let kf = penalty_of(
                self.slave_penalty_n_per_m.as_deref(),
                &self.face_stiffness_n_per_m,
                k,
                st.face as usize,
            )
            .min(self.slave_stiffness_cap[k]);
            out.push(RankOneStiffness {
                stiffness_n_per_m: kf,
                direction: st.normal,
                nodes: [self.slaves[k], face[0], face[1], face[2], face[3]],
                coefficients: [
                    1.0,
                    -st.weights[0],
                    -st.weights[1],
                    -st.weights[2],
                    -st.weights[3],
                ],
            });
        }
    }

    /// Per slave: active, tangential force; then the patch's sliding velocity (which the next
    /// step's friction reads under [`SlipSpeed::Patch`]).
    fn checkpoint_state(&self) -> Vec<f64> {
        let mut out = Vec::with_capacity(self.state.len() * 4 + 3);
        for s in &self.state {
            out.push(if s.active { 1.0 } else { 0.0 });
            out.extend_from_slice(&s.tangential_force_n);
        }
        out.extend_from_slice(&self.patch_slip_velocity_m_per_s);
        out
    }

    /// Reads [`AuxForces::checkpoint_state`]'s layout, or the slaves' part alone (checkpoints of
    /// earlier versions, which had no patch velocity: it restarts from zero, which only
    /// [`SlipSpeed::Patch`] reads).
    fn restore_state(&mut self, state: &[f64]) -> Result<()> {
        let slaves_len = 4 * self.state.len();
        if state.len() == slaves_len + 3 {
            let v = &state[slaves_len..];
            self.patch_slip_velocity_m_per_s = [v[0], v[1], v[2]];
        } else if state.len() == slaves_len {
            self.patch_slip_velocity_m_per_s = [0.0; 3];
        } else {
            return Err(Error::input(
                "checkpoint",
                "contact",
                "checkpoint holds another contact pair",
            ));
        }
        for (s, chunk) in self.state.iter_mut().zip(state[..slaves_len].chunks(4)) {
            s.active = chunk[0] > 0.5;
            s.tangential_force_n = [chunk[1], chunk[2], chunk[3]];
        }
        self.region.valid = false;
        Ok(())
    }
}
