//! Central-difference time integration (Yang & Li 2019; docs/physics.md, "Explicit engine"):
//!
//! ```text
//! a(t_n)       = M^-1 (f_ext(t_n) - f_int(u_n, v_{n-1/2}) + f_aux(t_n))
//! v_{n+1/2}    = v_{n-1/2} + dt a(t_n)
//! u_{n+1}      = u_n + dt v_{n+1/2}
//! ```
//! with a lumped (diagonal) mass. Constraints act on the updated velocities: fixed directions
//! get zero, prescribed directions the curve's velocity, rigid bodies the rigid motion, tie
//! slaves the interpolation of their master face.
//!
//! Parallelism without races or thread-dependent sums: elements are grouped into blocks of
//! consecutive elements, and the blocks are coloured so that no two blocks of one colour share
//! a node. Colours run one after another; the blocks of a colour run in parallel and scatter
//! into disjoint nodes. Every node's force is therefore summed in the same order whatever the
//! thread count, and the results are bitwise identical for 1 and N threads. Node loops work on
//! fixed chunks whose partial sums are added in chunk order.
//!
//! Energy bookkeeping, at integer steps with the centred
//! velocity `vbar_n = (v_{n-1/2} + v_{n+1/2}) / 2`: kinetic energy `sum m |vbar|^2 / 2`; strain and
//! hourglass energies as potentials of `u_n`; spring energy `k d^2 / 2`; work increments
//! `dt f_n . vbar_n` for external forces, constraint reactions and dissipation. The balance error
//! is `kinetic + internal + springs + dissipated + absorbed by auxiliary forces - work`.

// Index loops mirror the tensor notation of the equations (the project's style for kernels);
// `!(x > 0.0)` is meant: it also rejects NaN.
#![allow(clippy::needless_range_loop, clippy::neg_cmp_op_on_partial_ord)]

use std::ops::Range;

use rayon::prelude::*;

pub use super::aux::{AuxForces, NoAux};
use super::batch::{add_block_forces, ElementBatch, LANES};
use super::colour::{colour_blocks, SharedMut};
use super::element::{
    full_forces, one_point_forces, ElementEnergy, FullElement, KernelOptions, OnePointElement,
};
use super::levels::LevelWork;
use super::model::{Elements, Model, MotionKind, RigidBodySpec};
use super::node_update::NodeUpdate;
use super::phase_clock::{PhaseClock, StepPhase};
use super::rotation::{cross, dot, mat_mul, mat_vec, transpose};
pub use super::state::{EnergyReport, OutputFields, RigidState, WorkTotals};
use crate::mesh::P3;
use crate::{Error, Result};

/// The fraction of the stable step the engine runs at (defined with the critical step).
pub use crate::mesh::quality::COURANT_FACTOR;

/// Elements per colouring block.
pub(super) const BLOCK_ELEMENTS: usize = 256;
pub(super) use super::node_update::{NODE_CHUNK, PRESCRIBED_SHIFT, ROLE_RIGID, ROLE_SLAVE};

/// The central-difference solver.
pub struct Solver {
    /// The model.
    pub model: Model,
    /// Displacements at t_n.
    pub u: Vec<P3>,
    /// Velocities at t_{n-1/2}.
    pub v: Vec<P3>,
    /// Time t_n (s).
    pub time_s: f64,
    /// Step count n.
    pub step: u64,
    /// Time step (s).
    pub dt_s: f64,
    /// Work totals up to t_{n-1/2}.
    pub work: WorkTotals,
    /// Rigid bodies.
    pub rigid: Vec<RigidState>,
    /// Output fields of the last output step.
    pub output: OutputFields,
    pub(super) f_int: Vec<P3>,
    pub(super) f_aux: Vec<P3>,
    pub(super) inv_mass: Vec<f64>,
    pub(super) eff_mass: Vec<f64>,
    /// Masses gravity acts on: `eff_mass` unless inertia scaling is on.
    pub(super) gravity_mass: Vec<f64>,
    /// The step without inertia scaling.
    pub(super) unscaled_dt_s: f64,
    pub(super) role: Vec<u8>,
    pub(super) prescribed_velocity: Vec<P3>,
    pub(super) colours: Vec<Vec<Range<usize>>>,
    pub(super) chunk_partials: Vec<(WorkTotals, f64, LevelWork)>,
    pub(super) discrete_nodes: Vec<usize>,
    pub(super) discrete_v_old: Vec<P3>,
    pub(super) spring_force: Vec<P3>,
    pub(super) kernel: KernelOptions,
    pub(super) batches: Vec<ElementBatch>,
    pub(super) avx2: bool,
    pub(super) last_energy: Option<EnergyReport>,
    pub(super) baseline_pending: bool,
    /// Multi-rate stepping, when on ([`super::multirate`], state in [`super::levels`]).
    pub(super) multi_rate: Option<super::levels::MultiRate>,
    /// The ties' force pass as a per-master gather, built from `model.ties` by [`Solver::new`].
    pub(super) tie_gather: super::tie_update::TieGather,
    /// Per node: the index of its tie in `model.ties` when it is a tie slave, else `u32::MAX`.
    pub(super) tie_of_node: Vec<u32>,
    /// Wall time by phase of the step, when asked for ([`Solver::time_phases`]).
    pub(super) phase_clock: Option<PhaseClock>,
    /// Whether a node's auxiliary force can be non-zero ([`super::aux_nodes`]; all by default).
    pub(super) aux_force_node: Vec<bool>,
    /// The nodes whose auxiliary force a step zeroes; `None`: every node.
    pub(super) aux_zero: Option<super::state::AuxNodeSet>,
    /// The ties' pass of auxiliary forces, from the declared slaves only (`None`: all ties).
    pub(super) tie_gather_aux: Option<super::tie_update::TieGather>,
}

/// Ties in the node roles and masses: marks each slave (a node may be the slave of one tie
/// only, and no master may be a slave: chained ties are refused), and condenses the slave's
/// mass onto its masters.
fn condense_ties(model: &Model, eff_mass: &mut [f64], role: &mut [u8]) -> Result<()> {
    // Ties: the slave's mass goes to its masters with the interpolation weights (row sum
    // of T^T M T for a lumped M).
    for p in &model.ties {
        if role[p.slave] & ROLE_SLAVE != 0 {
            return Err(Error::Mesh(format!(
                "node {} is the slave of two ties",
                p.slave
            )));
        }
        role[p.slave] |= ROLE_SLAVE;
    }
    for p in &model.ties {
        for m in p.master {
            if role[m] & ROLE_SLAVE != 0 {
                return Err(Error::Mesh(format!(
                    "node {m} is both a tie master and a tie slave (chained ties)"
                )));
            }
        }
        let ms = eff_mass[p.slave];
        for (k, m) in p.master.iter().enumerate() {
            eff_mass[*m] += p.weights[k] * ms;
        }
        eff_mass[p.slave] = 0.0;
    }
    Ok(())
}

/// Marks the prescribed directions of each prescribed motion's nodes in the node roles.
fn mark_prescribed(model: &Model, role: &mut [u8]) {
    for pm in &model.prescribed {
        for &nd in &pm.nodes {
            role[nd] |= 1 << (pm.direction as u8 + PRESCRIBED_SHIFT);
        }
    }
}

/// The rigid bodies' initial states, in the model's order (after the ties: a tie slave cannot
/// be a member), their members marked rigid in the node roles.
fn gather_rigid_bodies(
    model: &Model,
    eff_mass: &[f64],
    role: &mut [u8],
) -> Result<Vec<RigidState>> {
    let mut rigid = Vec::new();
    for rb in &model.rigid_bodies {
        rigid.push(rigid_body_state(rb, &model.mesh.nodes, eff_mass, role)?);
    }
    Ok(rigid)
}

/// One rigid body at rest in its reference orientation: mass and centre of its members'
/// effective masses, inertia about the centre (regularised, so that it has an inverse).
fn rigid_body_state(
    rb: &RigidBodySpec,
    nodes: &[P3],
    eff_mass: &[f64],
    role: &mut [u8],
) -> Result<RigidState> {
    let mut mass = 0.0;
    let mut c = [0.0; 3];
    for &nd in &rb.nodes {
        if role[nd] & ROLE_SLAVE != 0 {
            return Err(Error::Mesh(format!(
                "rigid body {}: node {nd} is a tie slave",
                rb.name
            )));
        }
        role[nd] |= ROLE_RIGID;
        let m = eff_mass[nd];
        mass += m;
        for i in 0..3 {
            c[i] += m * nodes[nd][i];
        }
    }
    if !(mass > 0.0) {
        return Err(Error::input("model", &rb.name, "rigid body has no mass"));
    }
    c = c.map(|x| x / mass);
    let mut inertia = [[0.0; 3]; 3];
    for &nd in &rb.nodes {
        let m = eff_mass[nd];
        let r = [0, 1, 2].map(|i| nodes[nd][i] - c[i]);
        let r2 = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
        for i in 0..3 {
            for j in 0..3 {
                inertia[i][j] += m * (if i == j { r2 } else { 0.0 } - r[i] * r[j]);
            }
        }
    }
    // A rigid set on a line (or one node) has a singular inertia: regularise with a
    // tiny isotropic part so that the inverse exists (its rotation is then free).
    let trace = inertia[0][0] + inertia[1][1] + inertia[2][2];
    let reg = 1e-9 * trace.max(mass * 1e-12);
    for (i, row) in inertia.iter_mut().enumerate() {
        row[i] += reg;
    }
    let det = super::element::det3(&inertia);
    let inertia0_inv = super::element::inverse3(&inertia, det);
    Ok(RigidState {
        mass_kg: mass,
        centre0_m: c,
        centre_m: c,
        velocity_m_per_s: [0.0; 3],
        rotation: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        angular_momentum: [0.0; 3],
        inertia0: inertia,
        inertia0_inv,
    })
}

/// Inverse masses of the free nodes (tie slaves and rigid members move with their masters
/// and bodies, and keep 0); a free node without mass is refused.
fn inverse_masses(eff_mass: &[f64], role: &[u8]) -> Result<Vec<f64>> {
    let n = eff_mass.len();
    let mut inv_mass = vec![0.0; n];
    for i in 0..n {
        if role[i] & (ROLE_SLAVE | ROLE_RIGID) == 0 {
            if !(eff_mass[i] > 0.0) {
                return Err(Error::Mesh(format!(
                    "node {i} has no mass (not in any element and no point mass)"
                )));
            }
            inv_mass[i] = 1.0 / eff_mass[i];
        }
    }
    Ok(inv_mass)
}

/// Colours of element blocks: per colour, the element (or batch) ranges of its blocks.
type Colours = Vec<Vec<Range<usize>>>;

/// The element records' layout: the packed batches of the fast path (empty otherwise) and the
/// colours of their blocks (or of the plain elements' blocks), so that no two blocks of one
/// colour share a node.
fn element_layout(model: &Model, n: usize) -> Result<(Vec<ElementBatch>, Colours)> {
    // Fast path: one-point elements without element damping run four at a time.
    let fast = matches!(model.elements, Elements::OnePoint(_))
        && !model.viscous_hourglass
        && model.stiffness_damping_s == 0.0;
    let batches: Vec<ElementBatch> = match &model.elements {
        Elements::OnePoint(els) if fast => els.chunks(LANES).map(ElementBatch::pack).collect(),
        _ => Vec::new(),
    };
    let colours = if fast {
        colour_blocks(batches.len(), BLOCK_ELEMENTS / LANES, n, |b| {
            batches[b]
                .nodes
                .iter()
                .flat_map(|lanes| lanes.iter().copied())
                .collect()
        })?
    } else {
        colour_blocks(model.elements.len(), BLOCK_ELEMENTS, n, |e| {
            model.elements.nodes(e).to_vec()
        })?
    };
    Ok((batches, colours))
}

/// The nodes of springs and loads, sorted and each once: the discrete parts' nodes, whose
/// previous velocities the solver keeps beside them for the work of springs and loads.
fn discrete_part_nodes(model: &Model) -> Vec<usize> {
    let mut discrete_nodes: Vec<usize> = model
        .springs
        .iter()
        .flat_map(|s| std::iter::once(s.node_a).chain(s.node_b))
        .chain(model.loads.iter().flat_map(|l| l.nodes.iter().copied()))
        .collect();
    discrete_nodes.sort_unstable();
    discrete_nodes.dedup();
    discrete_nodes
}

impl Solver {
    /// Prepares the solver: effective masses (ties condensed, rigid bodies gathered), colours,
    /// time step `0.9 x` the stable step (or `dt_s` if given and stable).
    ///
    /// The arrays are laid out in the order they depend on each other: masses and node roles
    /// (ties, prescribed motions, rigid bodies), inverse masses, element records and colours,
    /// the discrete parts' nodes, then the step bounds of the assembled solver.
    pub fn new(model: Model, dt_s: Option<f64>) -> Result<Solver> {
        let n = model.node_count();
        let mut eff_mass = model.nodal_mass_kg.clone();
        let mut role = model.fixed.clone();
        condense_ties(&model, &mut eff_mass, &mut role)?;
        mark_prescribed(&model, &mut role);
        let rigid = gather_rigid_bodies(&model, &eff_mass, &mut role)?;
        let inv_mass = inverse_masses(&eff_mass, &role)?;
        let (batches, colours) = element_layout(&model, n)?;
        let discrete_nodes = discrete_part_nodes(&model);
        let n_chunks = n.div_ceil(NODE_CHUNK);
        let kernel = KernelOptions {
            viscous_hourglass: model.viscous_hourglass,
            physical_hourglass: model.physical_hourglass,
            stiffness_damping_s: model.stiffness_damping_s,
        };
        let mut solver = Solver {
            u: vec![[0.0; 3]; n],
            v: vec![[0.0; 3]; n],
            time_s: 0.0,
            step: 0,
            dt_s: 0.0,
            work: WorkTotals::default(),
            rigid,
            output: OutputFields {
                displacement: vec![[0.0; 3]; n],
                velocity: vec![[0.0; 3]; n],
                acceleration: vec![[0.0; 3]; n],
                rigid_reaction_force_n: vec![[0.0; 3]; model.rigid_bodies.len()],
            },
            f_int: vec![[0.0; 3]; n],
            f_aux: vec![[0.0; 3]; n],
            inv_mass,
            gravity_mass: eff_mass.clone(),
            eff_mass,
            role,
            prescribed_velocity: vec![[0.0; 3]; n],
            colours,
            chunk_partials: Vec::with_capacity(n_chunks),
            discrete_v_old: vec![[0.0; 3]; discrete_nodes.len()],
            discrete_nodes,
            spring_force: vec![[0.0; 3]; model.springs.len()],
            kernel,
            batches,
            avx2: super::batch::uses_avx2(),
            last_energy: None,
            baseline_pending: true,
            multi_rate: None,
            unscaled_dt_s: 0.0,
            tie_gather: super::tie_update::TieGather::new(&model.ties, n),
            tie_of_node: {
                let mut of = vec![u32::MAX; n];
                for (i, t) in model.ties.iter().enumerate() {
                    of[t.slave] = i as u32;
                }
                of
            },
            phase_clock: None,
            aux_force_node: vec![true; n],
            aux_zero: None,
            tie_gather_aux: None,
            model,
        };
        solver.set_initial_time_step(dt_s)?;
        Ok(solver)
    }

    /// The step of a new solver: `COURANT_FACTOR x` the stable step, or `dt_s` if given and
    /// stable (a larger one is refused, naming what sets the limit); the unscaled step starts
    /// equal to it.
    fn set_initial_time_step(&mut self, dt_s: Option<f64>) -> Result<()> {
        let stable = self.stable_time_step_s()?;
        self.dt_s = match dt_s {
            None => COURANT_FACTOR * stable.0,
            Some(dt) if dt > 0.0 && dt <= stable.0 => dt,
            Some(dt) => {
                return Err(Error::input(
                    "command line",
                    "time_step_s",
                    format!(
                        "{dt:.4e} s is above the stable limit {:.4e} s (set by {}); allowed: (0, {:.4e}]",
                        stable.0, stable.1, stable.0
                    ),
                ))
            }
        };
        self.unscaled_dt_s = self.dt_s;
        Ok(())
    }

    /// Scales the solver's step (and the step it returns to after an inertia scaling) by
    /// `factor` in (0, 1]: a smaller step than the engine's own, for a time-step convergence
    /// study; a larger one would pass the stable limit and is refused.
    pub fn scale_time_step(&mut self, factor: f64) -> Result<()> {
        if !(factor > 0.0 && factor <= 1.0) {
            return Err(Error::input(
                "case",
                "time_stepping.step_scale",
                format!("must lie in (0, 1] (got {factor})"),
            ));
        }
        self.dt_s *= factor;
        self.unscaled_dt_s = self.dt_s;
        Ok(())
    }

    /// Sets an initial velocity field `v = v0 + omega x (X - centre)` on `nodes` (all when None),
    /// and the matching rigid-body momenta.
    pub fn set_initial_velocity(
        &mut self,
        nodes: Option<&[usize]>,
        translation_m_per_s: P3,
        omega_rad_per_s: P3,
        centre_m: P3,
    ) {
        let all: Vec<usize>;
        let list = match nodes {
            Some(l) => l,
            None => {
                all = (0..self.model.node_count()).collect();
                &all
            }
        };
        for &nd in list {
            let x = self.model.mesh.nodes[nd];
            let r = [0, 1, 2].map(|i| x[i] + self.u[nd][i] - centre_m[i]);
            let w = cross(omega_rad_per_s, r);
            self.v[nd] = [0, 1, 2].map(|i| translation_m_per_s[i] + w[i]);
        }
        for (rb, st) in self.model.rigid_bodies.iter().zip(self.rigid.iter_mut()) {
            if rb.nodes.iter().all(|n| list.contains(n)) {
                let r = [0, 1, 2].map(|i| st.centre_m[i] - centre_m[i]);
                let w = cross(omega_rad_per_s, r);
                st.velocity_m_per_s = [0, 1, 2].map(|i| translation_m_per_s[i] + w[i]);
                let inertia = mat_mul(
                    &mat_mul(&st.rotation, &st.inertia0),
                    &transpose(&st.rotation),
                );
                let omega = match rb.rotation_axis {
                    Some(a) => a.map(|x| x * dot(a, omega_rad_per_s)),
                    None => omega_rad_per_s,
                };
                st.angular_momentum = mat_vec(&inertia, omega);
            }
        }
    }

    /// Only the element loop of a step (internal forces of the current state), for profiling
    /// the split between element and node work.
    pub fn compute_internal_forces(&mut self) {
        self.element_forces();
    }

    /// Elements' internal forces into `f_int` (colour by colour).
    pub(super) fn element_forces(&mut self) {
        let n = self.f_int.len();
        let f_ptr = SharedMut(self.f_int.as_mut_ptr());
        // Zero in parallel chunks.
        self.f_int
            .par_chunks_mut(NODE_CHUNK)
            .for_each(|c| c.fill([0.0; 3]));
        let _ = n;
        let (u, v, opts) = (&self.u, &self.v, self.kernel);
        if let Some(mr) = &mut self.multi_rate {
            // Levels whose elements are due at this step, finest first (multirate.rs).
            for (level, colours) in mr.level_colours.iter().enumerate() {
                if self.step & ((1u64 << level) - 1) != 0 {
                    break;
                }
                super::levels::add_level_forces(
                    &self.batches,
                    colours,
                    u,
                    f_ptr,
                    opts.physical_hourglass,
                    self.avx2,
                );
                // The interface nodes' force so far, for the transfer across levels.
                let recorded = &mut mr.interface.force_after_level;
                for &(nd, slot) in &mr.interface.record[level] {
                    recorded[slot as usize] = self.f_int[nd as usize];
                }
            }
            return;
        }
        if !self.batches.is_empty() {
            let (batches, physical, avx2) = (&self.batches, opts.physical_hourglass, self.avx2);
            for colour in &self.colours {
                colour.par_iter().for_each(|range| {
                    // SAFETY: blocks of one colour share no node; indices come from the mesh.
                    unsafe {
                        add_block_forces(&batches[range.clone()], u, f_ptr.ptr(), physical, avx2)
                    }
                });
            }
            return;
        }
        for colour in &self.colours {
            match &self.model.elements {
                Elements::OnePoint(els) => colour.par_iter().for_each(|range| {
                    let mut fe = [[0.0; 3]; 8];
                    for el in &els[range.clone()] {
                        one_point_forces::<false>(el, u, v, opts, &mut fe);
                        for a in 0..8 {
                            // SAFETY: blocks of one colour share no node.
                            let dst = unsafe { &mut *f_ptr.at(el.nodes[a] as usize) };
                            dst[0] += fe[a][0];
                            dst[1] += fe[a][1];
                            dst[2] += fe[a][2];
                        }
                    }
                }),
                Elements::Full(els) => colour.par_iter().for_each(|range| {
                    let mut fe = [[0.0; 3]; 8];
                    for el in &els[range.clone()] {
                        full_forces::<false>(el, u, opts.stiffness_damping_s, v, &mut fe);
                        for a in 0..8 {
                            // SAFETY: blocks of one colour share no node.
                            let dst = unsafe { &mut *f_ptr.at(el.nodes[a] as usize) };
                            dst[0] += fe[a][0];
                            dst[1] += fe[a][1];
                            dst[2] += fe[a][2];
                        }
                    }
                }),
            }
        }
    }

    /// Element energies of the current state (strain, hourglass, smallest det F and where).
    pub fn element_energy(&self) -> (ElementEnergy, usize) {
        let n = self.model.elements.len();
        let n_blocks = n.div_ceil(BLOCK_ELEMENTS);
        let (u, v, opts) = (&self.u, &self.v, self.kernel);
        let per_block: Vec<(ElementEnergy, usize)> = (0..n_blocks)
            .into_par_iter()
            .map(|b| {
                let mut acc = ElementEnergy {
                    min_det_f: f64::INFINITY,
                    ..Default::default()
                };
                let mut worst = 0;
                let mut fe = [[0.0; 3]; 8];
                for e in b * BLOCK_ELEMENTS..((b + 1) * BLOCK_ELEMENTS).min(n) {
                    let en = match &self.model.elements {
                        Elements::OnePoint(els) => {
                            one_point_forces::<true>(&els[e], u, v, opts, &mut fe)
                        }
                        Elements::Full(els) => full_forces::<true>(&els[e], u, 0.0, v, &mut fe),
                    };
                    acc.strain_j += en.strain_j;
                    acc.hourglass_j += en.hourglass_j;
                    if !(en.min_det_f >= acc.min_det_f) {
                        acc.min_det_f = en.min_det_f;
                        worst = e;
                    }
                }
                (acc, worst)
            })
            .collect();
        let mut total = ElementEnergy {
            min_det_f: f64::INFINITY,
            ..Default::default()
        };
        let mut worst = 0;
        for (en, w) in per_block {
            total.strain_j += en.strain_j;
            total.hourglass_j += en.hourglass_j;
            if !(en.min_det_f >= total.min_det_f) {
                total.min_det_f = en.min_det_f;
                worst = w;
            }
        }
        (total, worst)
    }

    /// Spring potential energy (J) of the current state.
    pub fn spring_energy_j(&self) -> f64 {
        let mut e = 0.0;
        for s in &self.model.springs {
            let ub = s.node_b.map(|b| self.u[b]).unwrap_or([0.0; 3]);
            for i in 0..3 {
                let d = ub[i] - self.u[s.node_a][i];
                e += 0.5 * s.stiffness_n_per_m[i] * d * d;
            }
        }
        e
    }

    /// Starts (or, with `false`, stops) timing the phases of each step
    /// ([`super::phase_clock`]); starting resets the clock.
    pub fn time_phases(&mut self, on: bool) {
        self.phase_clock = on.then(PhaseClock::new);
    }

    /// The phase clock, while [`Solver::time_phases`] has it on.
    pub fn phase_clock(&self) -> Option<&PhaseClock> {
        self.phase_clock.as_ref()
    }

    /// Charges the time since the last lap to `phase` when the phase clock is on.
    #[inline]
    pub(super) fn lap(&mut self, phase: StepPhase) {
        if let Some(clock) = self.phase_clock.as_mut() {
            clock.lap(phase);
        }
    }

    /// One step without auxiliary forces.
    pub fn step(&mut self) -> Result<()> {
        self.step_with(&mut NoAux, false, false)
    }

    /// One central-difference step. `output` fills [`Solver::output`] with the state of t_n;
    /// `energy` also makes the energy report of t_n (returned by [`Solver::last_energy`]).
    ///
    /// Phases, in the order of the update: the forces of t_n and the prescribed velocities of
    /// t_{n+1/2} ([`Self::prepare_step`]); the nodes ([`Self::update_nodes`]); the rigid
    /// bodies, the tie slaves and the springs' and loads' work ([`Self::finish_step`]). None of
    /// them allocates, and each keeps its order of floating-point operations, so the results do
    /// not depend on the thread count.
    pub fn step_with<A: AuxForces + ?Sized>(
        &mut self,
        aux: &mut A,
        output: bool,
        energy: bool,
    ) -> Result<()> {
        let output = output || energy;
        let (t, dt) = (self.time_s, self.dt_s);
        // What the caller did since the last step.
        self.lap(StepPhase::Other);
        self.prepare_step(aux, t, dt, energy)?;
        self.lap(StepPhase::Other);
        let (inc, kinetic) = self.update_nodes(dt, output, energy);
        self.finish_step(t, dt, output, energy, inc, kinetic);
        self.time_s = t + dt;
        self.step += 1;
        self.lap(StepPhase::Other);
        Ok(())
    }

    /// The forces of t_n (elements, auxiliary forces), the check that auxiliary forces act
    /// only on declared nodes (energy steps), the prescribed velocities of t_{n+1/2}, and the
    /// velocities v_{n-1/2} of the nodes that springs and loads act on (for their work).
    fn prepare_step<A: AuxForces + ?Sized>(
        &mut self,
        aux: &mut A,
        t: f64,
        dt: f64,
        energy: bool,
    ) -> Result<()> {
        self.gather_forces(aux, t, dt);
        if energy {
            if let Some(nd) = self.aux_forces_outside_declared() {
                return Err(Error::Numerical(format!(
                    "an auxiliary force acts on node {nd}, outside the nodes declared for them \
                     (AuxForces::force_nodes): it would never be zeroed; declare every node \
                     the forces act on, or none"
                )));
            }
        }
        for pm in &self.model.prescribed {
            let vel = match pm.kind {
                MotionKind::Velocity => pm.curve.value(t + 0.5 * dt),
                MotionKind::Displacement => (pm.curve.value(t + dt) - pm.curve.value(t)) / dt,
            };
            for &nd in &pm.nodes {
                self.prescribed_velocity[nd][pm.direction] = vel;
            }
        }
        for (k, &nd) in self.discrete_nodes.iter().enumerate() {
            self.discrete_v_old[k] = self.v[nd];
        }
        Ok(())
    }

    /// Every node's update ([`super::node_update`]) over fixed chunks in parallel; the chunks'
    /// sums added in chunk order. Returns the step's work increments and the nodes' kinetic
    /// energy (output steps), and books the multi-rate levels' work.
    fn update_nodes(&mut self, dt: f64, output: bool, energy: bool) -> (WorkTotals, f64) {
        let n_chunks = self.u.len().div_ceil(NODE_CHUNK);
        let step = self.step;
        let (node_level, last_acceleration, first_update_pending, interface) =
            match &mut self.multi_rate {
                Some(mr) => (
                    Some(mr.node_level.as_slice()),
                    Some(SharedMut(mr.last_acceleration.as_mut_ptr())),
                    (step < mr.first_updates_end_step)
                        .then_some(SharedMut(mr.first_update_pending.as_mut_ptr())),
                    Some(&mr.interface),
                ),
                None => (None, None, None, None),
            };
        let update = NodeUpdate {
            dt,
            step,
            output,
            // Steps on which free nodes take the short path: no output fields to write and
            // no subcycling.
            plain_step: !output && node_level.is_none(),
            gravity_m_per_s2: self.model.gravity_m_per_s2,
            mass_damping_per_s: self.model.mass_damping_per_s,
            f_int: &self.f_int,
            f_aux: &self.f_aux,
            aux_node: &self.aux_force_node,
            inv_mass: &self.inv_mass,
            eff_mass: &self.eff_mass,
            gravity_mass: &self.gravity_mass,
            role: &self.role,
            prescribed_velocity: &self.prescribed_velocity,
            u: SharedMut(self.u.as_mut_ptr()),
            v: SharedMut(self.v.as_mut_ptr()),
            out_displacement: SharedMut(self.output.displacement.as_mut_ptr()),
            out_velocity: SharedMut(self.output.velocity.as_mut_ptr()),
            out_acceleration: SharedMut(self.output.acceleration.as_mut_ptr()),
            node_level,
            last_acceleration,
            first_update_pending,
            interface,
        };
        (0..n_chunks)
            .into_par_iter()
            .map(|c| update.chunk(c))
            .collect_into_vec(&mut self.chunk_partials);
        self.lap(StepPhase::NodeUpdate);
        let mut inc = WorkTotals::default();
        let mut inc_levels = LevelWork::default();
        let mut kinetic = 0.0;
        for (w, k, lw) in &self.chunk_partials {
            inc.add_scaled(w, 1.0);
            inc_levels.add_scaled(lw, 1.0);
            kinetic += k;
        }
        if let Some(mr) = &mut self.multi_rate {
            if energy {
                mr.level_work_at_report = mr.level_work;
                mr.level_work_at_report.add_scaled(&inc_levels, 0.5);
            }
            mr.level_work.add_scaled(&inc_levels, 1.0);
        }
        (inc, kinetic)
    }

    /// The rest of the step after the nodes: rigid bodies, tie slaves following their masters,
    /// the work of springs and loads (forces at t_n times the centred velocity, to separate
    /// them from contact in the auxiliary work), the energy report of t_n (energy steps), and
    /// the running work totals.
    fn finish_step(
        &mut self,
        t: f64,
        dt: f64,
        output: bool,
        energy: bool,
        mut inc: WorkTotals,
        mut kinetic: f64,
    ) {
        for b in 0..self.rigid.len() {
            let (w, k) = self.advance_rigid_body(b, t, dt, output);
            inc.add_scaled(&w, 1.0);
            kinetic += k;
        }
        self.lap(StepPhase::RigidBodies);
        super::tie_update::follow_masters(
            &self.model.ties,
            &mut self.u,
            &mut self.v,
            output.then_some(&mut self.output),
        );
        self.lap(StepPhase::TieFollow);
        if !self.discrete_nodes.is_empty() {
            let (sp_w, sp_d, ld_w) = self.discrete_work(t, dt);
            inc.spring_j += sp_w;
            inc.spring_damping_j += sp_d;
            inc.load_j += ld_w;
        }
        self.lap(StepPhase::Discrete);
        if energy {
            let mut half = self.work;
            half.add_scaled(&inc, 0.5);
            let mut report = self.energy_report(t, kinetic, &half);
            if self.baseline_pending {
                // First report: the energy present now is the initial energy.
                self.work.initial_j += report.balance_error_j;
                report.external_work_j += report.balance_error_j;
                report.balance_error_j = 0.0;
                report.balance_ratio = 0.0;
                self.baseline_pending = false;
            }
            self.last_energy = Some(report);
        }
        self.work.add_scaled(&inc, 1.0);
    }

    /// Restarts the energy bookkeeping: the next report's energy is the new initial energy
    /// (after a preload, or after initial velocities were set by hand).
    pub fn rebase_energy(&mut self) {
        self.work = WorkTotals::default();
        self.baseline_pending = true;
    }

    /// Stops every rigid body (after a preload).
    pub fn zero_rigid_velocities(&mut self) {
        for st in &mut self.rigid {
            st.velocity_m_per_s = [0.0; 3];
            st.angular_momentum = [0.0; 3];
        }
    }

    /// Effective lumped masses (after ties), for other modules.
    pub fn effective_mass(&self) -> &[f64] {
        &self.eff_mass
    }

    /// Bytes of element data the element loop reads per element and step (the record it
    /// streams: a quarter of a four-element batch on the fast path).
    pub fn element_bytes_per_step(&self) -> usize {
        if self.batches.is_empty() {
            match &self.model.elements {
                Elements::OnePoint(_) => std::mem::size_of::<OnePointElement>(),
                Elements::Full(_) => std::mem::size_of::<FullElement>(),
            }
        } else {
            std::mem::size_of::<ElementBatch>() / LANES
        }
    }

    /// Blocks of elements in each colour of the single-rate element loop (the colours run one
    /// after another, each a parallel loop over its blocks), for reports.
    pub fn colour_blocks(&self) -> Vec<usize> {
        self.colours.iter().map(|c| c.len()).collect()
    }

    /// Crate-internal mutable access for restoring checkpoints (every part of the state).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn restore(
        &mut self,
        time_s: f64,
        step: u64,
        dt_s: f64,
        u: Vec<P3>,
        v: Vec<P3>,
        work: WorkTotals,
        rigid: Vec<RigidState>,
    ) {
        self.time_s = time_s;
        self.step = step;
        self.dt_s = dt_s;
        self.u = u;
        self.v = v;
        self.work = work;
        self.rigid = rigid;
        self.baseline_pending = false;
    }
}
