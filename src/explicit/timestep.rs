// Index loops mirror the tensor notation of the equations (the project's style for kernels);
// `!(x > 0.0)` is meant: it also rejects NaN.
#![allow(clippy::needless_range_loop, clippy::neg_cmp_op_on_partial_ord)]

//! The engine's time step, owned here: the stable step (element transit, springs, the bounds
//! other modules register), the Courant factor, and the inertia scaling of a quasi-static phase
//! that runs at a longer step.

use rayon::prelude::*;

use super::solver::{Solver, ROLE_RIGID, ROLE_SLAVE};
use crate::mesh::P3;
use crate::{Error, Result};

impl Solver {
    /// Inertia scaling for a quasi-static phase (preload): adds `added_kg[n]` to the inertia of
    /// node `n` (tie slaves pass theirs to their masters; rigid-body members are left as they
    /// are) while gravity keeps acting on the true masses, and runs at step `dt_s`. Static
    /// equilibrium does not depend on inertia, so a larger step reaches it in fewer steps. The
    /// caller chooses `added_kg` so that `dt_s` is stable (see `rolling::preload_scaling`).
    pub fn set_inertia_scaling(&mut self, added_kg: &[f64], dt_s: f64) -> Result<()> {
        if added_kg.len() != self.eff_mass.len() || !(dt_s > 0.0 && dt_s.is_finite()) {
            return Err(Error::input(
                "model",
                "inertia_scaling",
                "needs one added mass per node and a positive step",
            ));
        }
        let mut added = added_kg.to_vec();
        for p in &self.model.ties {
            let ms = added[p.slave];
            for (k, m) in p.master.iter().enumerate() {
                added[*m] += p.weights[k] * ms;
            }
            added[p.slave] = 0.0;
        }
        for i in 0..self.eff_mass.len() {
            if self.role[i] & (ROLE_SLAVE | ROLE_RIGID) == 0 {
                self.eff_mass[i] = self.gravity_mass[i] + added[i].max(0.0);
                self.inv_mass[i] = 1.0 / self.eff_mass[i];
            }
        }
        self.dt_s = dt_s;
        Ok(())
    }

    /// Back to the true inertia and the step the solver was built with.
    pub fn clear_inertia_scaling(&mut self) {
        for i in 0..self.eff_mass.len() {
            if self.role[i] & (ROLE_SLAVE | ROLE_RIGID) == 0 {
                self.eff_mass[i] = self.gravity_mass[i];
                self.inv_mass[i] = 1.0 / self.eff_mass[i];
            }
        }
        self.dt_s = self.unscaled_dt_s;
    }

    /// Stable time step (s) and what sets it: the smallest element transit `L / c_L` (current
    /// configuration, `L = V / A_max`), spring limits `2 sqrt(m_eff / k)`, and registered bounds.
    pub fn stable_time_step_s(&self) -> Result<(f64, String)> {
        let n_el = self.model.elements.len();
        let (mut best, mut what) = (f64::INFINITY, String::from("nothing"));
        if n_el > 0 {
            let (dt, e) = (0..n_el)
                .into_par_iter()
                .map(|e| {
                    let nodes = self.model.elements.nodes(e);
                    let x: [P3; 8] = std::array::from_fn(|a| {
                        let nd = nodes[a] as usize;
                        [0, 1, 2].map(|i| self.model.mesh.nodes[nd][i] + self.u[nd][i])
                    });
                    (
                        crate::mesh::hex::characteristic_length(&x)
                            / self.model.element_wave_speed_m_per_s[e],
                        e,
                    )
                })
                .reduce(
                    || (f64::INFINITY, 0),
                    |a, b| {
                        if b.0 < a.0 || (b.0 == a.0 && b.1 < a.1) {
                            b
                        } else {
                            a
                        }
                    },
                );
            if !(dt > 0.0) {
                return Err(Error::Numerical(format!(
                    "element {e} has a non-positive characteristic length"
                )));
            }
            best = dt;
            what = format!("element {e}");
        }
        for s in &self.model.springs {
            let k = s.stiffness_n_per_m.iter().fold(0.0f64, |m, &k| m.max(k));
            if k <= 0.0 {
                continue;
            }
            let ma = self.eff_mass_for_bound(s.node_a);
            let inv = 1.0 / ma
                + s.node_b
                    .map(|b| 1.0 / self.eff_mass_for_bound(b))
                    .unwrap_or(0.0);
            let dt = 2.0 / (k * inv).sqrt();
            if dt < best {
                best = dt;
                what = format!("spring {}", s.name);
            }
        }
        for (name, dt) in &self.model.time_step_bounds {
            if *dt < best {
                best = *dt;
                what = name.clone();
            }
        }
        if !best.is_finite() {
            return Err(Error::input(
                "model",
                "elements",
                "the model has no element and no spring",
            ));
        }
        Ok((best, what))
    }

    pub(super) fn eff_mass_for_bound(&self, node: usize) -> f64 {
        if self.role[node] & ROLE_RIGID != 0 {
            // Member of a rigid body: the body's mass moves with it.
            for (rb, st) in self.model.rigid_bodies.iter().zip(&self.rigid) {
                if rb.nodes.binary_search(&node).is_ok() {
                    return st.mass_kg;
                }
            }
        }
        self.eff_mass[node].max(1e-300)
    }
}
