//! The forces of a state and what is read off them: the element, load, spring, contact and
//! tie forces gathered for a step (shared by the time step and the static solver, so that both
//! see the same forces), the springs' and loads' work over a step, and the out-of-balance norm
//! of the last step's forces (the dynamic relaxation's convergence measure).

// Index loops mirror the tensor notation of the equations (the project's style for kernels).
#![allow(clippy::needless_range_loop)]

use super::aux::{AuxForces, StepPredictor};
use super::phase_clock::StepPhase;
use super::solver::{Solver, PRESCRIBED_SHIFT, ROLE_RIGID, ROLE_SLAVE};
use crate::mesh::P3;

impl Solver {
    /// The forces of the state `(u_n, v_{n-1/2})` at time `t`: elements into `f_int`; nodal
    /// loads, springs and the caller's forces (contact) into `f_aux`; tie slaves' forces passed
    /// on to their masters (the element forces before the caller's, so that its prediction of
    /// the masters' motion has them: [`StepPredictor`]). Shared by the time step and the static
    /// solver, so that both see the same forces.
    pub(super) fn gather_forces<A: AuxForces + ?Sized>(&mut self, aux: &mut A, t: f64, dt: f64) {
        self.element_forces();
        self.lap(StepPhase::Elements);
        // Tie slaves pass their element forces to the masters (the same sums, in the same
        // order, as passing them with the auxiliary forces below).
        self.tie_gather.pass(&mut self.f_int);
        // Auxiliary forces: nodal loads, springs, then the caller's (contact).
        self.zero_aux_forces();
        self.lap(StepPhase::AuxZero);
        for load in &self.model.loads {
            let s = load.curve.value(t) / load.nodes.len() as f64;
            for &nd in &load.nodes {
                for i in 0..3 {
                    self.f_aux[nd][i] += s * load.total_force_n[i];
                }
            }
        }
        for (k, sp) in self.model.springs.iter().enumerate() {
            let (ua, va) = (self.u[sp.node_a], self.v[sp.node_a]);
            let (ub, vb) = match sp.node_b {
                Some(b) => (self.u[b], self.v[b]),
                None => ([0.0; 3], [0.0; 3]),
            };
            let f: P3 = [0, 1, 2].map(|i| {
                sp.stiffness_n_per_m[i] * (ub[i] - ua[i])
                    + sp.damping_n_s_per_m[i] * (vb[i] - va[i])
            });
            self.spring_force[k] = f;
            for i in 0..3 {
                self.f_aux[sp.node_a][i] += f[i];
            }
            if let Some(b) = sp.node_b {
                for i in 0..3 {
                    self.f_aux[b][i] -= f[i];
                }
            }
        }
        self.lap(StepPhase::Discrete);
        let predictor = StepPredictor {
            dt_s: dt,
            f_int: &self.f_int,
            inv_mass: &self.inv_mass,
            eff_mass: &self.eff_mass,
            gravity_mass: &self.gravity_mass,
            gravity_m_per_s2: self.model.gravity_m_per_s2,
            mass_damping_per_s: self.model.mass_damping_per_s,
            role: &self.role,
            ties: &self.model.ties,
            tie_of_node: &self.tie_of_node,
            multi_rate: self.multi_rate.is_some(),
        };
        aux.add_forces_predicted(t, dt, &self.u, &self.v, &mut self.f_aux, &predictor);
        self.lap(StepPhase::Contact);
        // Tie slaves pass their auxiliary forces to the masters.
        match &self.tie_gather_aux {
            // Undeclared slaves carry no auxiliary force: their masters get none to pass on.
            Some(aux_gather) => aux_gather.pass(&mut self.f_aux),
            None => self.tie_gather.pass(&mut self.f_aux),
        }
        self.lap(StepPhase::TiePass);
    }

    /// Work increments, over the step just taken, of the springs' forces on their nodes, of the
    /// spring dampers (dissipation), and of the nodal loads: forces of t_n times the centred
    /// velocity `vbar_n = (v_{n-1/2} + v_{n+1/2}) / 2`, the same product the node loop uses, so
    /// that the contact share of the auxiliary work is exact.
    pub(super) fn discrete_work(&self, t: f64, dt: f64) -> (f64, f64, f64) {
        let vbar = |nd: usize| -> P3 {
            let k = self
                .discrete_nodes
                .binary_search(&nd)
                .expect("discrete node");
            [0, 1, 2].map(|i| 0.5 * (self.discrete_v_old[k][i] + self.v[nd][i]))
        };
        let v_old = |nd: usize| -> P3 {
            let k = self
                .discrete_nodes
                .binary_search(&nd)
                .expect("discrete node");
            self.discrete_v_old[k]
        };
        let (mut work, mut damp, mut load) = (0.0, 0.0, 0.0);
        for (sp, f) in self.model.springs.iter().zip(&self.spring_force) {
            let va = vbar(sp.node_a);
            let vb = sp.node_b.map(vbar).unwrap_or([0.0; 3]);
            let dva_old = v_old(sp.node_a);
            let dvb_old = sp.node_b.map(v_old).unwrap_or([0.0; 3]);
            for i in 0..3 {
                work += dt * f[i] * (va[i] - vb[i]);
                damp += dt * sp.damping_n_s_per_m[i] * (dvb_old[i] - dva_old[i]) * (vb[i] - va[i]);
            }
        }
        for l in &self.model.loads {
            let s = l.curve.value(t) / l.nodes.len() as f64;
            for &nd in &l.nodes {
                let vb = vbar(nd);
                for i in 0..3 {
                    load += dt * s * l.total_force_n[i] * vb[i];
                }
            }
        }
        (work, damp, load)
    }

    /// Out-of-balance force norm `|f_ext - f_int|` over the free directions of the free nodes,
    /// and a reference force norm `|f_int| + |f_ext|` (N), with the forces of the last step.
    pub fn residual_norms(&self) -> (f64, f64) {
        let g = self.model.gravity_m_per_s2;
        let (mut res, mut fi2, mut fe2) = (0.0, 0.0, 0.0);
        for nd in 0..self.u.len() {
            let r = self.role[nd];
            if r & (ROLE_SLAVE | ROLE_RIGID) != 0 {
                continue;
            }
            for i in 0..3 {
                if r & ((1 << i) | (1 << (i + PRESCRIBED_SHIFT as usize))) != 0 {
                    continue;
                }
                let fe = self.f_aux[nd][i] + self.gravity_mass[nd] * g[i];
                let fi = self.f_int[nd][i];
                res += (fe - fi) * (fe - fi);
                fi2 += fi * fi;
                fe2 += fe * fe;
            }
        }
        for (b, st) in self.rigid.iter().enumerate() {
            let mut f = [0.0; 3];
            for &nd in &self.model.rigid_bodies[b].nodes {
                for i in 0..3 {
                    f[i] += self.f_aux[nd][i] - self.f_int[nd][i] + self.eff_mass[nd] * g[i];
                }
            }
            for (i, fi) in f.iter().enumerate() {
                if self.model.rigid_bodies[b].prescribed_translation_m[i].is_none() {
                    res += fi * fi;
                }
            }
            let _ = st;
        }
        (res.sqrt(), fi2.sqrt() + fe2.sqrt())
    }

    /// Element and auxiliary force arrays of the last step.
    pub fn force_arrays(&self) -> (&[P3], &[P3]) {
        (&self.f_int, &self.f_aux)
    }
}
