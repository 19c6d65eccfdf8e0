// Index loops mirror the tensor notation of the equations (the project's style for kernels);
// `!(x > 0.0)` is meant: it also rejects NaN.
#![allow(clippy::needless_range_loop, clippy::neg_cmp_op_on_partial_ord)]

//! Rigid bodies of the engine: a node set that moves as one body, with prescribed translations,
//! an optional fixed rotation axis and prescribed spin, and an applied torque; the reactions
//! that hold the prescriptions are booked as work and kept for output.

use super::model::RigidBodySpec;
use super::rotation::{cross, dot, mat_mul, mat_t_vec, mat_vec, rotation_from_vector, transpose};
use super::solver::Solver;
use super::state::{RigidState, WorkTotals};
use crate::mesh::P3;

impl Solver {
    /// Advances rigid body `b` (forces of its members at t_n) and moves its nodes.
    ///
    /// The phases run in the order of the equations: resultants of the members' forces,
    /// translation (with its prescribed parts), angular momentum (with the fixed axis and
    /// prescribed spin), the body's own state, then its nodes. The work of each phase is added
    /// to one `WorkTotals` in that order; nothing is allocated (this runs every step).
    pub(super) fn advance_rigid_body(
        &mut self,
        b: usize,
        t: f64,
        dt: f64,
        output: bool,
    ) -> (WorkTotals, f64) {
        let (force, moment, applied_torque) = self.rigid_body_resultants(b, t);
        let mut w = WorkTotals::default();
        let spec = &self.model.rigid_bodies[b];
        let st = &mut self.rigid[b];
        let (v_new, reactions) = rigid_translation(spec, st, &force, t, dt, &mut w);
        if output {
            self.output.rigid_reaction_force_n[b] = reactions;
        }
        let l_new = rigid_angular_momentum(spec, st, &moment, t, dt, &mut w);
        move_rigid_state(st, &applied_torque, v_new, l_new, dt, &mut w);
        let kinetic = self.move_rigid_body_nodes(b, dt, output, &mut w);
        (w, kinetic)
    }

    /// The resultant force and moment (about the current centre) on rigid body `b` at t_n,
    /// from its members' auxiliary, internal, gravity and mass-damping forces, plus the
    /// applied torque (returned on its own too, for the torque's work).
    #[inline]
    fn rigid_body_resultants(&self, b: usize, t: f64) -> (P3, P3, P3) {
        let spec = &self.model.rigid_bodies[b];
        let st = &self.rigid[b];
        let g = self.model.gravity_m_per_s2;
        let alpha = self.model.mass_damping_per_s;
        let mut force = [0.0; 3];
        let mut moment = [0.0; 3];
        for &nd in &spec.nodes {
            let m = self.eff_mass[nd];
            let x = [0, 1, 2].map(|i| self.model.mesh.nodes[nd][i] + self.u[nd][i]);
            let f: P3 = [0, 1, 2].map(|i| {
                self.f_aux[nd][i] - self.f_int[nd][i] + m * g[i] - alpha * m * self.v[nd][i]
            });
            for i in 0..3 {
                force[i] += f[i];
            }
            let r = [0, 1, 2].map(|i| x[i] - st.centre_m[i]);
            let mm = cross(r, f);
            for i in 0..3 {
                moment[i] += mm[i];
            }
        }
        let mut applied_torque = [0.0; 3];
        if let Some(tq) = &spec.torque {
            let s = tq.curve_n_m.value(t);
            applied_torque = tq.axis.map(|a| a * s);
            for i in 0..3 {
                moment[i] += applied_torque[i];
            }
        }
        (force, moment, applied_torque)
    }

    /// Moves the member nodes of rigid body `b` with the body's new state (centre and rotation
    /// at t_{n+1}): their velocities are the displacement change over the step, and the work
    /// of the forces on them is booked with the centred velocity. Returns the members' kinetic
    /// energy on output steps (0 otherwise), when the output fields are filled too.
    #[inline]
    fn move_rigid_body_nodes(
        &mut self,
        b: usize,
        dt: f64,
        output: bool,
        w: &mut WorkTotals,
    ) -> f64 {
        let spec = &self.model.rigid_bodies[b];
        let st = &self.rigid[b];
        let g = self.model.gravity_m_per_s2;
        let alpha = self.model.mass_damping_per_s;
        let mut kinetic = 0.0;
        for &nd in &spec.nodes {
            let x0 = self.model.mesh.nodes[nd];
            let r0 = [0, 1, 2].map(|i| x0[i] - st.centre0_m[i]);
            let r = mat_vec(&st.rotation, r0);
            let m = self.eff_mass[nd];
            let mut vnew = [0.0; 3];
            for i in 0..3 {
                let u_new = st.centre_m[i] + r[i] - x0[i];
                vnew[i] = (u_new - self.u[nd][i]) / dt;
                let vbar = 0.5 * (self.v[nd][i] + vnew[i]);
                let fi = self.f_int[nd][i];
                let fa = self.f_aux[nd][i];
                w.internal_j += dt * fi * vbar;
                w.aux_j += dt * fa * vbar;
                w.gravity_j += dt * m * g[i] * vbar;
                w.mass_damping_j += dt * alpha * m * self.v[nd][i] * vbar;
                if output {
                    kinetic += 0.5 * m * vbar * vbar;
                    self.output.displacement[nd][i] = self.u[nd][i];
                    self.output.velocity[nd][i] = vbar;
                    self.output.acceleration[nd][i] = (vnew[i] - self.v[nd][i]) / dt;
                }
                self.u[nd][i] = u_new;
            }
            self.v[nd] = vnew;
        }
        kinetic
    }
}

/// The centre's velocity at t_{n+1/2} from the resultant `force`, with the prescribed
/// translations imposed: each prescribed direction takes the curve's velocity over the step,
/// and the force that holds it is a reaction whose work is booked. Returns the new velocity
/// and the reactions (zero in the free directions).
#[inline]
fn rigid_translation(
    spec: &RigidBodySpec,
    st: &RigidState,
    force: &P3,
    t: f64,
    dt: f64,
    w: &mut WorkTotals,
) -> (P3, P3) {
    let v_old = st.velocity_m_per_s;
    let mut v_new = [0, 1, 2].map(|i| v_old[i] + dt * force[i] / st.mass_kg);
    let mut reactions = [0.0; 3];
    for i in 0..3 {
        if let Some(c) = &spec.prescribed_translation_m[i] {
            v_new[i] = (c.value(t + dt) - c.value(t)) / dt;
            let reaction = st.mass_kg * (v_new[i] - v_old[i]) / dt - force[i];
            w.reaction_j += dt * reaction * 0.5 * (v_old[i] + v_new[i]);
            reactions[i] = reaction;
        }
    }
    (v_new, reactions)
}

/// The angular momentum at t_{n+1/2} from the resultant `moment`; with a fixed rotation axis
/// only the spin about it is kept (prescribed, if a spin curve is given, with the holding
/// moment's work booked as a reaction).
#[inline]
fn rigid_angular_momentum(
    spec: &RigidBodySpec,
    st: &RigidState,
    moment: &P3,
    t: f64,
    dt: f64,
    w: &mut WorkTotals,
) -> P3 {
    let l_old = st.angular_momentum;
    let mut l_new = [0, 1, 2].map(|i| l_old[i] + dt * moment[i]);
    if let Some(a) = spec.rotation_axis {
        // Turning about the fixed axis a only: keep L = I ω with ω along a. The axis is a
        // principal direction of the current inertia whenever the body is symmetric about
        // it; in general only the a-component of the moment drives the spin (eq. of the
        // doc of `rotation_axis`), so project L on the inertia's response to a.
        let l_a = dot(l_new, a);
        let inertia = mat_mul(
            &mat_mul(&st.rotation, &st.inertia0),
            &transpose(&st.rotation),
        );
        let i_a = mat_vec(&inertia, a);
        let i_aa = dot(a, i_a);
        let mut spin = l_a / i_aa;
        if let Some(c) = &spec.prescribed_spin_rad_per_s {
            // L lives at half steps: the spin of t + dt/2; the holding moment about a is
            // I_aa (spin_new - spin_old) / dt - M.a, and its work is booked as a reaction.
            let spin_old = dot(l_old, a) / i_aa;
            spin = c.value(t + 0.5 * dt);
            let reaction = i_aa * (spin - spin_old) / dt - dot(*moment, a);
            w.reaction_j += dt * reaction * 0.5 * (spin_old + spin);
        }
        l_new = i_a.map(|x| x * spin);
    }
    l_new
}

/// Advances the body's own state to t_{n+1}: books the applied torque's work with the
/// centred angular velocity, turns the rotation by `omega dt`, moves the centre, and stores
/// the new velocity and angular momentum.
#[inline]
fn move_rigid_state(
    st: &mut RigidState,
    applied_torque: &P3,
    v_new: P3,
    l_new: P3,
    dt: f64,
    w: &mut WorkTotals,
) {
    let l_old = st.angular_momentum;
    // omega = R I0^-1 R^T L (inertia of the current orientation).
    let omega = mat_vec(
        &st.rotation,
        mat_vec(&st.inertia0_inv, mat_t_vec(&st.rotation, l_new)),
    );
    let omega_old = mat_vec(
        &st.rotation,
        mat_vec(&st.inertia0_inv, mat_t_vec(&st.rotation, l_old)),
    );
    for i in 0..3 {
        w.torque_j += dt * applied_torque[i] * 0.5 * (omega[i] + omega_old[i]);
    }
    let dr = rotation_from_vector(omega.map(|x| x * dt));
    st.rotation = mat_mul(&dr, &st.rotation);
    for i in 0..3 {
        st.centre_m[i] += dt * v_new[i];
    }
    st.velocity_m_per_s = v_new;
    st.angular_momentum = l_new;
}
