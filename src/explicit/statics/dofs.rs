//! The static problem's unknowns: the engine's constraints written as a linear map `u = T q`.
//!
//! - A free mesh node (not a tie slave, not in a rigid body) is a reduced node of its own, with
//!   three unknowns; a fixed or prescribed direction is *held* (its increment is zero and its
//!   out-of-balance force is a reaction).
//! - A rigid body is one reduced node: the translation of its centre. Its rotation is held, so
//!   each member moves by the centre's translation (`u_i = u_c`, whatever the body's current
//!   orientation). Prescribed translations, and those the caller asks to hold (a direction in
//!   which the body has no stiffness, such as a wheelset's rolling direction on frictionless
//!   contact), are held.
//! - A tie slave has no unknowns: `u_s = sum_a w_a u_a` over its master face's nodes, which
//!   are free nodes or rigid members (the engine refuses chained ties).
//!
//! The reduced residual is `Tᵀ (f_ext - f_int + f_aux)`: the engine passes tie slaves' forces to
//! their masters itself, so a free node's residual is read as it is, and a rigid body's is the
//! sum over its members, as in `Solver::residual_norms`.

// Index loops mirror the tensor notation (the project's style for kernels).
#![allow(clippy::needless_range_loop)]

use super::super::solver::{Solver, PRESCRIBED_SHIFT, ROLE_RIGID, ROLE_SLAVE};
use crate::mesh::P3;
use crate::{Error, Result};

/// No reduced node (a tie slave).
pub(super) const NONE: u32 = u32::MAX;

/// The reduced nodes and which of their directions are held.
pub(super) struct ReducedDofs {
    /// Mesh node of each free reduced node (the first `free_nodes.len()` reduced nodes).
    pub(super) free_nodes: Vec<usize>,
    /// Per mesh node: its reduced node (free node: its own; rigid member: its body's), or
    /// [`NONE`] for a tie slave.
    pub(super) reduced_of: Vec<u32>,
    /// Per mesh node: the index of the tie it is the slave of, or [`NONE`].
    pub(super) tie_of: Vec<u32>,
    /// Per reduced node: held directions.
    pub(super) held: Vec<[bool; 3]>,
    /// Per reduced node: the mass the regularisation scales with (kg).
    pub(super) mass_kg: Vec<f64>,
}

impl ReducedDofs {
    /// The map of the solver's model. `held_rigid_translations[b]` holds directions of rigid
    /// body `b` beyond its prescribed ones (missing entries: none).
    pub(super) fn new(solver: &Solver, held_rigid_translations: &[[bool; 3]]) -> Result<Self> {
        let model = &solver.model;
        let n = solver.u.len();
        if held_rigid_translations.len() > model.rigid_bodies.len() {
            return Err(Error::input(
                "static solve",
                "held_rigid_translations",
                format!(
                    "{} entries for {} rigid bodies",
                    held_rigid_translations.len(),
                    model.rigid_bodies.len()
                ),
            ));
        }
        let mut reduced_of = vec![NONE; n];
        let mut free_nodes = Vec::new();
        let mut held = Vec::new();
        let mut mass_kg = Vec::new();
        for nd in 0..n {
            let role = solver.role[nd];
            if role & (ROLE_SLAVE | ROLE_RIGID) != 0 {
                continue;
            }
            reduced_of[nd] = free_nodes.len() as u32;
            free_nodes.push(nd);
            held.push(std::array::from_fn(|i| {
                role & ((1 << i) | (1 << (i + PRESCRIBED_SHIFT as usize))) != 0
            }));
            mass_kg.push(solver.gravity_mass[nd]);
        }
        for (b, body) in model.rigid_bodies.iter().enumerate() {
            let r = (free_nodes.len() + b) as u32;
            for &nd in &body.nodes {
                reduced_of[nd] = r;
            }
            let extra = held_rigid_translations
                .get(b)
                .copied()
                .unwrap_or([false; 3]);
            held.push(std::array::from_fn(|i| {
                body.prescribed_translation_m[i].is_some() || extra[i]
            }));
            mass_kg.push(solver.rigid[b].mass_kg);
        }
        let mut tie_of = vec![NONE; n];
        for (k, p) in model.ties.iter().enumerate() {
            tie_of[p.slave] = k as u32;
        }
        Ok(ReducedDofs {
            free_nodes,
            reduced_of,
            tie_of,
            held,
            mass_kg,
        })
    }

    /// Number of reduced nodes (three unknowns each).
    pub(super) fn len(&self) -> usize {
        self.held.len()
    }

    /// The reduced nodes a mesh node's displacement is made of, with their weights (one entry,
    /// or a tie slave's four masters); returns how many were written.
    pub(super) fn expand(&self, solver: &Solver, node: usize, out: &mut [(u32, f64); 4]) -> usize {
        let r = self.reduced_of[node];
        if r != NONE {
            out[0] = (r, 1.0);
            return 1;
        }
        let tie = &solver.model.ties[self.tie_of[node] as usize];
        for (k, &m) in tie.master.iter().enumerate() {
            out[k] = (self.reduced_of[m], tie.weights[k]);
        }
        4
    }

    /// The reduced residual `Tᵀ r` of the forces the solver gathered last (held directions
    /// zero), into `out` (3 per reduced node); returns the reference norm `|f_int| + |f_ext|`
    /// over the unknowns, as `Solver::residual_norms` defines it.
    pub(super) fn residual(&self, solver: &Solver, out: &mut [f64]) -> f64 {
        let g = solver.model.gravity_m_per_s2;
        let (f_int, f_aux) = (&solver.f_int, &solver.f_aux);
        let (mut fi2, mut fe2) = (0.0, 0.0);
        for (r, &nd) in self.free_nodes.iter().enumerate() {
            for i in 0..3 {
                let fe = f_aux[nd][i] + solver.gravity_mass[nd] * g[i];
                let fi = f_int[nd][i];
                out[3 * r + i] = fe - fi;
                if !self.held[r][i] {
                    fi2 += fi * fi;
                    fe2 += fe * fe;
                }
            }
        }
        let free = self.free_nodes.len();
        for (b, body) in solver.model.rigid_bodies.iter().enumerate() {
            let mut f = [0.0; 3];
            for &nd in &body.nodes {
                for i in 0..3 {
                    f[i] += f_aux[nd][i] - f_int[nd][i] + solver.eff_mass[nd] * g[i];
                }
            }
            out[3 * (free + b)..3 * (free + b) + 3].copy_from_slice(&f);
        }
        fi2.sqrt() + fe2.sqrt()
    }

    /// Moves the model by the reduced increment `dq` (3 per reduced node): free nodes, rigid
    /// bodies' centres and members, then tie slaves from their masters.
    pub(super) fn apply_increment(&self, solver: &mut Solver, dq: &[f64]) {
        for (r, &nd) in self.free_nodes.iter().enumerate() {
            for i in 0..3 {
                solver.u[nd][i] += dq[3 * r + i];
            }
        }
        let free = self.free_nodes.len();
        for b in 0..solver.rigid.len() {
            let d: P3 = std::array::from_fn(|i| dq[3 * (free + b) + i]);
            for i in 0..3 {
                solver.rigid[b].centre_m[i] += d[i];
            }
            for k in 0..solver.model.rigid_bodies[b].nodes.len() {
                let nd = solver.model.rigid_bodies[b].nodes[k];
                for i in 0..3 {
                    solver.u[nd][i] += d[i];
                }
            }
        }
        for p in &solver.model.ties {
            let mut us = [0.0; 3];
            for (k, &m) in p.master.iter().enumerate() {
                for i in 0..3 {
                    us[i] += p.weights[k] * solver.u[m][i];
                }
            }
            solver.u[p.slave] = us;
        }
    }
}
