//! The node phase of a central-difference step: per node, with the forces of t_n gathered,
//!
//! `v_{n+1/2} = v_{n-1/2} + dt M^-1 (f_aux - f_int + m g - alpha m v_{n-1/2})`,
//! `u_{n+1} = u_n + dt v_{n+1/2}`,
//!
//! over fixed chunks of [`NODE_CHUNK`] nodes in parallel. Constrained components take zero or
//! their prescribed velocity and the reaction's work is booked; a node of multi-rate level k
//! updates every 2^k steps with the step 2^k dt and drifts at its velocity in between
//! (multirate.rs). Each chunk returns its work sums (trapezoidal `dt f . v_bar` with
//! `v_bar = (v_{n-1/2} + v_{n+1/2}) / 2`) and, on output steps, its kinetic energy; the caller
//! adds the chunks in chunk order, so the sums do not depend on the thread count.
//!
//! Nothing here allocates; the per-node helpers are inlined into the chunk loop, so that the
//! sums stay in registers and the operations keep their order (the same bits as one loop).

use super::colour::SharedMut;
use super::levels::{LevelInterface, LevelWork};
use super::state::WorkTotals;
use crate::mesh::P3;

/// Nodes per chunk of the node loops (fixed, so sums do not depend on the thread count).
pub(super) const NODE_CHUNK: usize = 2048;

/// Node role bits: bits 0-2 a fixed component, bits 3-5 ([`PRESCRIBED_SHIFT`]) a prescribed
/// one, and these two whole-node roles, which the node loop leaves to their owners.
pub(super) const ROLE_SLAVE: u8 = 1 << 6;
pub(super) const ROLE_RIGID: u8 = 1 << 7;
pub(super) const PRESCRIBED_SHIFT: u8 = 3;

/// What one step's node update reads and writes (borrowed from the solver for the step).
pub(super) struct NodeUpdate<'a> {
    pub(super) dt: f64,
    pub(super) step: u64,
    /// Fill the output fields (displacement, velocity, acceleration) and the kinetic energy.
    pub(super) output: bool,
    /// Free nodes take the short path (no output, no subcycling).
    pub(super) plain_step: bool,
    pub(super) gravity_m_per_s2: P3,
    pub(super) mass_damping_per_s: f64,
    pub(super) f_int: &'a [P3],
    pub(super) f_aux: &'a [P3],
    pub(super) aux_node: &'a [bool],
    pub(super) inv_mass: &'a [f64],
    pub(super) eff_mass: &'a [f64],
    pub(super) gravity_mass: &'a [f64],
    pub(super) role: &'a [u8],
    pub(super) prescribed_velocity: &'a [P3],
    pub(super) u: SharedMut<P3>,
    pub(super) v: SharedMut<P3>,
    pub(super) out_displacement: SharedMut<P3>,
    pub(super) out_velocity: SharedMut<P3>,
    pub(super) out_acceleration: SharedMut<P3>,
    /// Multi-rate only: each node's level, last acceleration, pending first update (during the
    /// first updates), and the level interfaces.
    pub(super) node_level: Option<&'a [u8]>,
    pub(super) last_acceleration: Option<SharedMut<P3>>,
    pub(super) first_update_pending: Option<SharedMut<bool>>,
    pub(super) interface: Option<&'a LevelInterface>,
}

// SAFETY: the raw pointers are written at disjoint node indices (each node belongs to one
// chunk); everything else is shared read-only.
unsafe impl Sync for NodeUpdate<'_> {}

/// A chunk's running sums (J), as plain locals of the chunk loop.
#[derive(Default)]
struct ChunkSums {
    internal_j: f64,
    aux_j: f64,
    gravity_j: f64,
    mass_damping_j: f64,
    reaction_j: f64,
    kinetic_j: f64,
}

impl NodeUpdate<'_> {
    /// Update the nodes of chunk `c`: its work sums, kinetic energy (output steps) and per-level
    /// work (multi-rate).
    pub(super) fn chunk(&self, c: usize) -> (WorkTotals, f64, LevelWork) {
        let mut s = ChunkSums::default();
        let mut lw = LevelWork::default();
        let n = self.f_int.len();
        for nd in c * NODE_CHUNK..((c + 1) * NODE_CHUNK).min(n) {
            let r = self.role[nd];
            if r & (ROLE_SLAVE | ROLE_RIGID) != 0 {
                continue;
            }
            // SAFETY: each node index belongs to exactly one chunk.
            let (un, vn) = unsafe { (&mut *self.u.at(nd), &mut *self.v.at(nd)) };
            if self.plain_step && r == 0 {
                self.plain_free_node(nd, un, vn, &mut s);
                continue;
            }
            // A node of level k updates every 2^k steps with the step 2^k dt and between its
            // updates moves on at its velocity (multirate.rs).
            let period = self.node_level.map_or(1u64, |l| 1u64 << l[nd]);
            if self.step & (period - 1) != 0 {
                self.drift_between_updates(nd, period, un, vn, &mut s);
                continue;
            }
            self.update_node(nd, r, period, un, vn, &mut s, &mut lw);
        }
        let w = WorkTotals {
            internal_j: s.internal_j,
            aux_j: s.aux_j,
            gravity_j: s.gravity_j,
            mass_damping_j: s.mass_damping_j,
            reaction_j: s.reaction_j,
            ..WorkTotals::default()
        };
        (w, s.kinetic_j, lw)
    }

    /// A free node on a step without output, subcycling or constraints: [`Self::update_node`]
    /// with its branches taken out (the same operations in the same order, so the same bits;
    /// dt_node = dt). Profiled on the default run's model, this path took the node update
    /// from 1.0 to 0.7 ms a step.
    #[inline(always)]
    fn plain_free_node(&self, nd: usize, un: &mut P3, vn: &mut P3, s: &mut ChunkSums) {
        let (dt, g, alpha) = (self.dt, self.gravity_m_per_s2, self.mass_damping_per_s);
        let (m, mg, im) = (self.eff_mass[nd], self.gravity_mass[nd], self.inv_mass[nd]);
        let fi = self.f_int[nd];
        // Undeclared nodes' auxiliary forces are zero (aux_nodes.rs): not read.
        let fa = if self.aux_node[nd] {
            self.f_aux[nd]
        } else {
            [0.0; 3]
        };
        let mut vnew = [0.0; 3];
        for i in 0..3 {
            let force = fa[i] - fi[i] + mg * g[i] - alpha * m * vn[i];
            vnew[i] = vn[i] + dt * force * im;
            let vbar = 0.5 * (vn[i] + vnew[i]);
            s.internal_j += dt * fi[i] * vbar;
            s.aux_j += dt * fa[i] * vbar;
            s.gravity_j += dt * mg * g[i] * vbar;
            s.mass_damping_j += dt * alpha * m * vn[i] * vbar;
            un[i] += dt * vnew[i];
        }
        *vn = vnew;
    }

    /// A multi-rate node between its updates: it moves on at its velocity; on output steps its
    /// velocity at t_n comes from its last two half-step velocities (v_{m+1/2} at
    /// t_m + dt_k / 2 and the last acceleration between them): second order, and the centred
    /// velocity of the update at t_m itself.
    #[inline(always)]
    fn drift_between_updates(
        &self,
        nd: usize,
        period: u64,
        un: &mut P3,
        vn: &mut P3,
        s: &mut ChunkSums,
    ) {
        let dt = self.dt;
        if let (true, Some(la)) = (self.output, self.last_acceleration) {
            let m = self.eff_mass[nd];
            // SAFETY: as in `chunk`; last_acceleration is Some whenever node_level is.
            let a = unsafe { *la.at(nd) };
            let since = (self.step & (period - 1)) as f64 * dt - 0.5 * dt * period as f64;
            let vt = [0, 1, 2].map(|i| vn[i] + since * a[i]);
            s.kinetic_j += 0.5 * m * (vt[0] * vt[0] + vt[1] * vt[1] + vt[2] * vt[2]);
            // SAFETY: as in `chunk`.
            unsafe {
                *self.out_displacement.at(nd) = *un;
                *self.out_velocity.at(nd) = vt;
                *self.out_acceleration.at(nd) = a;
            }
        }
        for i in 0..3 {
            un[i] += dt * vn[i];
        }
    }

    /// The general update of a node at its own step `period dt`: constraints (zero or
    /// prescribed velocity, with the reaction's work `(m a - f) . v_bar dt`), output fields,
    /// and the multi-rate bookkeeping (last acceleration, per-level work, interface transfer).
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn update_node(
        &self,
        nd: usize,
        r: u8,
        period: u64,
        un: &mut P3,
        vn: &mut P3,
        s: &mut ChunkSums,
        lw: &mut LevelWork,
    ) {
        let (dt, g, alpha) = (self.dt, self.gravity_m_per_s2, self.mass_damping_per_s);
        let (m, mg, im) = (self.eff_mass[nd], self.gravity_mass[nd], self.inv_mass[nd]);
        // With one level (or none) period is 1 and this is dt exactly.
        let mut dt_node = dt * period as f64;
        if let Some(first) = self.first_update_pending {
            // SAFETY: as in `chunk`.
            let pending = unsafe { &mut *first.at(nd) };
            if *pending {
                // The held velocity is of the last fine half step (multirate.rs).
                dt_node = 0.5 * (dt_node + dt);
                *pending = false;
            }
        }
        // Undeclared nodes' auxiliary forces are zero (aux_nodes.rs): not read.
        let fi = self.f_int[nd];
        let fa = if self.aux_node[nd] {
            self.f_aux[nd]
        } else {
            [0.0; 3]
        };
        let mut vnew = [0.0; 3];
        let mut vbar_node = [0.0; 3];
        let external_before = s.aux_j + s.gravity_j + s.reaction_j - s.mass_damping_j;
        for i in 0..3 {
            let force = fa[i] - fi[i] + mg * g[i] - alpha * m * vn[i];
            vnew[i] = vn[i] + dt_node * force * im;
            if r & (1 << i) != 0 {
                vnew[i] = 0.0;
            } else if r & (1 << (i + PRESCRIBED_SHIFT as usize)) != 0 {
                vnew[i] = self.prescribed_velocity[nd][i];
            }
            let vbar = 0.5 * (vn[i] + vnew[i]);
            vbar_node[i] = vbar;
            if r & ((1 << i) | (1 << (i + PRESCRIBED_SHIFT as usize))) != 0 {
                // Reaction = m a - f: its work keeps the balance honest.
                let reaction = m * (vnew[i] - vn[i]) / dt_node - force;
                s.reaction_j += dt_node * reaction * vbar;
            }
            s.internal_j += dt_node * fi[i] * vbar;
            s.aux_j += dt_node * fa[i] * vbar;
            s.gravity_j += dt_node * mg * g[i] * vbar;
            s.mass_damping_j += dt_node * alpha * m * vn[i] * vbar;
            if self.output {
                s.kinetic_j += 0.5 * m * vbar * vbar;
                // SAFETY: as in `chunk`.
                unsafe {
                    (*self.out_displacement.at(nd))[i] = un[i];
                    (*self.out_velocity.at(nd))[i] = vbar;
                    (*self.out_acceleration.at(nd))[i] = (vnew[i] - vn[i]) / dt_node;
                }
            }
            un[i] += dt * vnew[i];
        }
        if let Some(la) = self.last_acceleration {
            // SAFETY: as in `chunk`.
            unsafe {
                *la.at(nd) = [0, 1, 2].map(|i| (vnew[i] - vn[i]) / dt_node);
            }
        }
        let level = self.node_level.map_or(0, |l| l[nd] as usize);
        if let (true, Some(iface)) = (level > 0, self.interface) {
            // Per-level bookkeeping (multirate.rs, "Energy by level").
            lw.external_j[level] +=
                s.aux_j + s.gravity_j + s.reaction_j - s.mass_damping_j - external_before;
            iface.add_transfer(nd, level, dt_node, &vbar_node, lw);
        }
        *vn = vnew;
    }
}
