// Index loops mirror the tensor notation of the equations (the project's style for kernels);
// `!(x > 0.0)` is meant: it also rejects NaN.
#![allow(clippy::needless_range_loop, clippy::neg_cmp_op_on_partial_ord)]

//! The energy balance of a step and the diagnosis of an unstable run (non-finite values, an
//! inverted element, a balance error above its threshold).

use super::solver::Solver;
use super::state::{EnergyReport, WorkTotals};
use crate::{Error, Result};

impl Solver {
    pub(super) fn energy_report(&self, t: f64, kinetic: f64, w: &WorkTotals) -> EnergyReport {
        let (el, worst) = self.element_energy();
        let spring = self.spring_energy_j();
        let element_damping =
            if self.kernel.viscous_hourglass || self.kernel.stiffness_damping_s > 0.0 {
                // Internal work minus the stored potentials is what the element dampers dissipated.
                (w.internal_j - el.strain_j - el.hourglass_j).max(0.0)
            } else {
                0.0
            };
        let damping = w.mass_damping_j + w.spring_damping_j + element_damping;
        // Work done on the auxiliary array that is neither springs nor loads: absorbed by contact.
        let contact = -(w.aux_j - w.spring_j - w.load_j);
        let external = w.gravity_j + w.load_j + w.torque_j + w.reaction_j + w.initial_j;
        let stored = kinetic + el.strain_j + el.hourglass_j + spring;
        let error = stored + damping + contact - external;
        let scale = stored.max(external.abs()).max(1e-300);
        EnergyReport {
            time_s: t,
            kinetic_j: kinetic,
            strain_j: el.strain_j,
            hourglass_j: el.hourglass_j,
            spring_j: spring,
            damping_j: damping,
            contact_j: contact,
            external_work_j: external,
            balance_error_j: error,
            balance_ratio: error.abs() / scale,
            min_det_f: el.min_det_f,
            min_det_f_element: worst,
        }
    }

    /// The energy report of the last output step.
    pub fn last_energy(&self) -> Option<EnergyReport> {
        self.last_energy
    }

    /// Checks the state: any non-finite displacement or an inverted element is an instability.
    pub fn check_state(&self, energy: &EnergyReport, balance_threshold: f64) -> Result<()> {
        if let Some(nd) = self.u.iter().position(|x| !x.iter().all(|c| c.is_finite())) {
            return Err(Error::Numerical(format!(
                "unstable at t = {:.6e} s (step {}): node {nd} has a non-finite displacement",
                self.time_s, self.step
            )));
        }
        if !(energy.min_det_f > 0.0) {
            let e = energy.min_det_f_element;
            return Err(Error::Numerical(format!(
                "element {e} inverted at t = {:.6e} s (step {}): det F = {:.3e}, nodes {:?}",
                energy.time_s,
                self.step,
                energy.min_det_f,
                self.model.elements.nodes(e)
            )));
        }
        if !energy.kinetic_j.is_finite() || energy.balance_ratio > balance_threshold {
            let worst = self
                .v
                .iter()
                .enumerate()
                .map(|(i, v)| (i, v[0] * v[0] + v[1] * v[1] + v[2] * v[2]))
                .fold(
                    (0, -1.0),
                    |a, b| if b.1 > a.1 || b.1.is_nan() { b } else { a },
                );
            return Err(Error::Numerical(format!(
                "energy balance lost at t = {:.6e} s (step {}): error {:.3e} J = {:.2} % of the energy (threshold {:.2} %); fastest node {} at {:.3e} m/s",
                energy.time_s,
                self.step,
                energy.balance_error_j,
                100.0 * energy.balance_ratio,
                100.0 * balance_threshold,
                worst.0,
                worst.1.sqrt()
            )));
        }
        Ok(())
    }
}
