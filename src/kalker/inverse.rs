//! Force-prescribed mode: given the creep forces `(Fx, Fy)` (and Fn, mu, spin phi), find the
//! creepages `(xi, eta)` — what CONTACT does when the FE forces are given to it (Yang & Li 2019).
//!
//! * `|F_t| > mu Fn` (beyond a relative 1e-9) cannot be carried by Coulomb friction: input error.
//! * `|F_t| >= mu Fn (1 - 1e-9)`: the contact is saturated and every creepage beyond the
//!   saturation point gives the same force, so no unique answer exists. The result is labelled
//!   `unique: false` and reports the smallest creepage along the direction opposite to the force
//!   at which the force reaches `mu Fn` (bisection on its magnitude).
//! * Otherwise: Newton's method on `F(xi, eta) - F_target = 0` with a finite-difference Jacobian,
//!   started from the linear theory scaled by Carter's saturation law
//!   (`f = 2k - k^2` inverted), and damped by step halving whenever the residual does not
//!   decrease (the force is monotone but flattens towards saturation, where full Newton steps
//!   overshoot).

use super::creep_coefficients::kalker_creep_coefficients;
use super::rolling::{RollingContactSolution, RollingSolver};
use super::tangential::Creepages;
use crate::{Error, Result};

/// Result of the force-prescribed mode.
#[derive(Debug, Clone, serde::Serialize)]
pub struct ForcePrescribedResult {
    /// The creepages found (phi as given).
    pub creepages: Creepages,
    /// False when the forces are saturated and the creepages are not unique.
    pub unique: bool,
    /// "unique" or "not unique (saturated)".
    pub note: String,
    /// Newton iterations (or bisection steps when saturated).
    pub iterations: usize,
    /// Forward solution at the creepages found.
    pub solution: RollingContactSolution,
}

/// Relative tolerance of the saturation test `|F_t| vs mu Fn`.
pub const SATURATION_TOLERANCE: f64 = 1e-9;

/// Solves for `(xi, eta)` such that the solver's forces equal `(Fx, Fy)` for spin `phi_per_m`.
/// `semi_axes_m` (a, b) give the linear-theory starting point.
///
/// The phases: checks of the targets against Coulomb's bound, the linear-theory creepages,
/// then either the saturated search or Newton's method from the Carter-scaled guess.
pub fn solve_force_prescribed(
    solver: &RollingSolver,
    semi_axes_m: (f64, f64),
    force_x_n: f64,
    force_y_n: f64,
    phi_per_m: f64,
) -> Result<ForcePrescribedResult> {
    let target = Target {
        force_x_n,
        force_y_n,
        phi_per_m,
    };
    let (limit_n, tangential_n) = check_target(solver, &target)?;
    let linear = LinearTheory::new(solver, semi_axes_m, &target)?;

    if tangential_n >= limit_n * (1.0 - SATURATION_TOLERANCE) {
        return saturated(
            solver,
            force_x_n,
            force_y_n,
            phi_per_m,
            linear.xi.hypot(linear.eta),
            limit_n,
        );
    }

    // Carter-law scaling of the linear guess: f = |F|/(mu Fn) = 2k - k^2 with linear f = 2k.
    let fraction = tangential_n / limit_n;
    let scale = if fraction > 1e-12 {
        2.0 * (1.0 - (1.0 - fraction).sqrt()) / fraction
    } else {
        1.0
    };
    let start = (linear.xi * scale, linear.eta * scale);
    newton(solver, &target, &linear, start, limit_n)
}

/// The prescribed forces and spin.
struct Target {
    force_x_n: f64,
    force_y_n: f64,
    phi_per_m: f64,
}

impl Target {
    /// The creepages `(xi, eta)` with the prescribed spin.
    #[inline]
    fn creep(&self, xi: f64, eta: f64) -> Creepages {
        Creepages {
            xi,
            eta,
            phi_per_m: self.phi_per_m,
        }
    }

    /// The forces' residual against the targets.
    #[inline]
    fn residual(&self, forces: (f64, f64)) -> (f64, f64) {
        (forces.0 - self.force_x_n, forces.1 - self.force_y_n)
    }
}

/// The targets must be finite, and the tangential force within Coulomb's bound `mu Fn` (up to
/// [`SATURATION_TOLERANCE`]). Returns the bound and the tangential force `|F_t|` (N).
fn check_target(solver: &RollingSolver, target: &Target) -> Result<(f64, f64)> {
    let (force_x_n, force_y_n) = (target.force_x_n, target.force_y_n);
    for (value, name) in [
        (force_x_n, "--force-x-n"),
        (force_y_n, "--force-y-n"),
        (target.phi_per_m, "--phi-per-m"),
    ] {
        if !value.is_finite() {
            return Err(Error::input(
                "command line",
                name,
                format!("must be finite, got {value}"),
            ));
        }
    }
    let limit_n = solver.mu() * solver.normal_force_n();
    let tangential_n = force_x_n.hypot(force_y_n);
    if tangential_n > limit_n * (1.0 + SATURATION_TOLERANCE) {
        return Err(Error::input(
            "command line",
            "--force-x-n/--force-y-n",
            format!(
                "creep force |F_t| = {tangential_n:.6e} N exceeds the traction bound mu Fn = {limit_n:.6e} N; Coulomb friction cannot carry it"
            ),
        ));
    }
    Ok((limit_n, tangential_n))
}

/// Kalker's linear theory for the patch: the creepages that give the target forces, and the
/// diagonal stiffnesses `G c^2 C11`, `G c^2 C22` (N) that also step a flat Jacobian.
struct LinearTheory {
    /// Linear-theory longitudinal creepage.
    xi: f64,
    /// Linear-theory lateral creepage (spin contribution removed from Fy).
    eta: f64,
    /// `G c^2 C11` (N).
    stiffness_x_n: f64,
    /// `G c^2 C22` (N).
    stiffness_y_n: f64,
}

impl LinearTheory {
    /// Kalker's coefficients for the patch's `a/b` (clamped to his table) and the linear
    /// creepages for the target forces.
    fn new(solver: &RollingSolver, semi_axes_m: (f64, f64), target: &Target) -> Result<Self> {
        let (force_x_n, force_y_n, phi_per_m) =
            (target.force_x_n, target.force_y_n, target.phi_per_m);
        let (a, b) = semi_axes_m;
        let shear_modulus_pa = solver.material().shear_modulus_pa();
        let ratio = (a / b).clamp(0.2, 5.0);
        let coefficients = kalker_creep_coefficients(ratio, solver.material().poisson_ratio)?;
        let c2 = a * b;
        let stiffness_x_n = shear_modulus_pa * c2 * coefficients.c11;
        let stiffness_y_n = shear_modulus_pa * c2 * coefficients.c22;
        // Linear-theory creepages for the target forces (spin contribution removed from Fy).
        let linear_xi = -force_x_n / stiffness_x_n;
        let linear_eta = -(force_y_n
            + shear_modulus_pa * c2 * c2.sqrt() * coefficients.c23 * phi_per_m)
            / stiffness_y_n;
        Ok(LinearTheory {
            xi: linear_xi,
            eta: linear_eta,
            stiffness_x_n,
            stiffness_y_n,
        })
    }
}

/// Newton's method on `F(xi, eta) - F_target = 0` from `start`: converged when the residual is
/// below `1e-10 mu Fn`, or (after 100 iterations or a step that no halving improves) below
/// `1e-7 mu Fn`; otherwise a numerical error.
fn newton(
    solver: &RollingSolver,
    target: &Target,
    linear: &LinearTheory,
    start: (f64, f64),
    limit_n: f64,
) -> Result<ForcePrescribedResult> {
    let (mut xi, mut eta) = start;
    let mut residual = target.residual(solver.forces(&target.creep(xi, eta))?);
    let tolerance_n = 1e-10 * limit_n;
    let creepage_scale = linear.xi.hypot(linear.eta).max(1e-9);
    for iteration in 1..=100 {
        if residual.0.hypot(residual.1) <= tolerance_n {
            return unique(solver, target, (xi, eta), iteration - 1);
        }
        // Central differences, step small against the creepage scale.
        let step = 1e-5 * creepage_scale.max(xi.hypot(eta));
        // Perturbed solutions start from the base solution (cheap for the exact solver).
        let base = solver.solve(&target.creep(xi, eta))?;
        let delta = newton_direction(solver, target, linear, &base, (xi, eta), step, residual)?;
        match damped_step(solver, target, &base, (xi, eta), delta, residual)? {
            Some(((new_xi, new_eta), trial)) => {
                xi = new_xi;
                eta = new_eta;
                residual = trial;
            }
            None => break,
        }
    }
    if residual.0.hypot(residual.1) <= 1e-7 * limit_n {
        return unique(solver, target, (xi, eta), 100);
    }
    Err(Error::Numerical(format!(
        "force-prescribed mode did not converge: residual ({:.3e}, {:.3e}) N",
        residual.0, residual.1
    )))
}

/// The result at converged creepages `(xi, eta)`, with the forward solution there.
fn unique(
    solver: &RollingSolver,
    target: &Target,
    (xi, eta): (f64, f64),
    iterations: usize,
) -> Result<ForcePrescribedResult> {
    let solution = solver.solve(&target.creep(xi, eta))?;
    Ok(ForcePrescribedResult {
        creepages: target.creep(xi, eta),
        unique: true,
        note: "unique".into(),
        iterations,
        solution,
    })
}

/// The Newton step at `(xi, eta)`: the Jacobian by central differences of half-width `step`
/// (warm-started from `base`), solved against the residual; a flat Jacobian falls back to the
/// diagonal linear-theory step.
fn newton_direction(
    solver: &RollingSolver,
    target: &Target,
    linear: &LinearTheory,
    base: &RollingContactSolution,
    (xi, eta): (f64, f64),
    step: f64,
    residual: (f64, f64),
) -> Result<(f64, f64)> {
    let fx_plus = solver.forces_warm(&target.creep(xi + step, eta), Some(base))?;
    let fx_minus = solver.forces_warm(&target.creep(xi - step, eta), Some(base))?;
    let fe_plus = solver.forces_warm(&target.creep(xi, eta + step), Some(base))?;
    let fe_minus = solver.forces_warm(&target.creep(xi, eta - step), Some(base))?;
    let j11 = (fx_plus.0 - fx_minus.0) / (2.0 * step);
    let j21 = (fx_plus.1 - fx_minus.1) / (2.0 * step);
    let j12 = (fe_plus.0 - fe_minus.0) / (2.0 * step);
    let j22 = (fe_plus.1 - fe_minus.1) / (2.0 * step);
    let determinant = j11 * j22 - j12 * j21;
    Ok(if determinant.abs() > f64::MIN_POSITIVE {
        (
            (-residual.0 * j22 + residual.1 * j12) / determinant,
            (-residual.1 * j11 + residual.0 * j21) / determinant,
        )
    } else {
        // Flat Jacobian: fall back to a diagonal linear-theory step.
        (
            residual.0 / linear.stiffness_x_n,
            residual.1 / linear.stiffness_y_n,
        )
    })
}

/// Takes the step `delta` from `(xi, eta)`, halved (up to 40 times) until the residual
/// decreases: the force is monotone but flattens towards saturation, where full Newton steps
/// overshoot. Returns the new creepages and residual, or `None` when no halving helps.
#[allow(clippy::type_complexity)] // a pair of pairs: the creepages and their residual
fn damped_step(
    solver: &RollingSolver,
    target: &Target,
    base: &RollingContactSolution,
    (xi, eta): (f64, f64),
    (mut delta_xi, mut delta_eta): (f64, f64),
    residual: (f64, f64),
) -> Result<Option<((f64, f64), (f64, f64))>> {
    let old_norm = residual.0.hypot(residual.1);
    for _ in 0..40 {
        let trial = target.residual(
            solver.forces_warm(&target.creep(xi + delta_xi, eta + delta_eta), Some(base))?,
        );
        if trial.0.hypot(trial.1) < old_norm {
            return Ok(Some(((xi + delta_xi, eta + delta_eta), trial)));
        }
        delta_xi *= 0.5;
        delta_eta *= 0.5;
    }
    Ok(None)
}

/// Saturated forces: the smallest creepage magnitude at which `|F| >= mu Fn (1 - 1e-6)`, with the
/// creepage direction adjusted so that the force points along the target. (The force direction
/// at saturation is not always opposite to the creepage: FASTSIM's flexibilities differ in x
/// and y, and spin adds its own contribution.) Each trial magnitude turns the creepage angle by
/// the force-angle error until they agree to 1e-9 rad, then bisects on the magnitude.
fn saturated(
    solver: &RollingSolver,
    force_x_n: f64,
    force_y_n: f64,
    phi_per_m: f64,
    linear_magnitude: f64,
    limit_n: f64,
) -> Result<ForcePrescribedResult> {
    let target_angle = (-force_y_n).atan2(-force_x_n); // creepage roughly opposes the force
    let creep_of = |magnitude: f64, angle: f64| Creepages {
        xi: magnitude * angle.cos(),
        eta: magnitude * angle.sin(),
        phi_per_m,
    };
    let wrap = |angle: f64| {
        (angle + std::f64::consts::PI).rem_euclid(2.0 * std::f64::consts::PI) - std::f64::consts::PI
    };
    // At a given magnitude: the creepage angle that aligns the force, and whether it saturates.
    let aligned = |magnitude: f64, mut angle: f64| -> Result<(f64, bool, f64)> {
        let mut force = solver.forces(&creep_of(magnitude, angle))?;
        for _ in 0..60 {
            let error = wrap(target_angle - (-force.1).atan2(-force.0));
            if error.abs() < 1e-9 {
                break;
            }
            angle += error;
            force = solver.forces(&creep_of(magnitude, angle))?;
        }
        let magnitude_n = force.0.hypot(force.1);
        Ok((angle, magnitude_n >= limit_n * (1.0 - 1e-6), magnitude_n))
    };
    let mut high = linear_magnitude.max(1e-9);
    let mut angle = target_angle;
    let mut doublings = 0;
    loop {
        let (new_angle, saturated_here, _) = aligned(high, angle)?;
        angle = new_angle;
        if saturated_here {
            break;
        }
        high *= 2.0;
        doublings += 1;
        if doublings > 60 {
            return Err(Error::Numerical(
                "saturation creepage not found (with spin the force may approach mu Fn only asymptotically)".into(),
            ));
        }
    }
    let mut low = 0.0;
    let mut steps = 0;
    while high - low > 1e-6 * high && steps < 60 {
        let mid = 0.5 * (low + high);
        let (mid_angle, saturated_here, _) = aligned(mid, angle)?;
        if saturated_here {
            high = mid;
            angle = mid_angle;
        } else {
            low = mid;
        }
        steps += 1;
    }
    let solution = solver.solve(&creep_of(high, angle))?;
    Ok(ForcePrescribedResult {
        creepages: creep_of(high, angle),
        unique: false,
        note: "not unique (saturated): any larger creepage in this direction gives the same force"
            .into(),
        iterations: steps,
        solution,
    })
}
