//! FASTSIM, Kalker's simplified theory (Kalker, "A fast algorithm for the simplified theory of
//! rolling contact", Vehicle System Dynamics 11, 1982, 1-13).
//!
//! The surface displacement is taken proportional to the local traction, `u = L p`, with
//! flexibilities chosen so that the theory reproduces the linear creep coefficients
//! (docs/references.md, section 5): `L1 = 8a/(3 C11 G)`, `L2 = 8a/(3 C22 G)`,
//! `L3 = pi a sqrt(a/b) / (4 C23 G)`. In adhesion `s = w - du/dx = 0`, so along each strip
//! y = const, marching from the leading edge x = +a(y) downstream with step dx:
//! `px -= dx (xi/L1 - phi y/L3)`, `py -= dx (eta/L2 + phi x/L3)`,
//! then `|p|` is capped at the traction bound `mu p_Hertz` (slip). The bound uses the elliptic
//! Hertz pressure `p0 sqrt(1 - x^2/a^2 - y^2/b^2)`, recommended over the parabolic one because it
//! is the actual pressure (and gives the exact saturation force mu Fn).
//!
//! Strips are equally spaced in y over (-b, b) (midpoints); each strip has `points_per_strip`
//! elements of length `2 a(y)/n` with `a(y) = a sqrt(1 - y^2/b^2)`; tractions are evaluated at
//! element midpoints (first at `a(y) - dx/2`), which makes the force of the linear regime exact
//! for any n. The sampled pressure is rescaled to carry exactly Fn.

use super::creep_coefficients::CreepCoefficients;
use super::hertz::HertzContact;
use super::tangential::{Creepages, ElementState};
use crate::{Error, Result};

/// FASTSIM solution on the strip grid. Arrays are `strips x points_per_strip`, strip-major,
/// points ordered from the leading edge.
#[derive(Debug, Clone)]
pub struct FastsimSolution {
    /// Number of strips (along y).
    pub strips: usize,
    /// Points per strip (along x).
    pub points_per_strip: usize,
    /// x of each point (m).
    pub x_m: Vec<f64>,
    /// y of each point (m).
    pub y_m: Vec<f64>,
    /// Element area of each point (m^2).
    pub area_m2: Vec<f64>,
    /// Hertz pressure at each point (Pa).
    pub pressure_pa: Vec<f64>,
    /// Traction px (Pa).
    pub traction_x_pa: Vec<f64>,
    /// Traction py (Pa).
    pub traction_y_pa: Vec<f64>,
    /// Adhesion or slip.
    pub state: Vec<ElementState>,
    /// Total Fx (N).
    pub force_x_n: f64,
    /// Total Fy (N).
    pub force_y_n: f64,
}

/// FASTSIM flexibilities (m/Pa): `[L1, L2, L3]`.
pub fn flexibilities(hertz: &HertzContact, coefficients: &CreepCoefficients) -> [f64; 3] {
    let (a, b) = (hertz.semi_axis_a_m, hertz.semi_axis_b_m);
    let shear_modulus_pa = hertz.material.shear_modulus_pa();
    [
        8.0 * a / (3.0 * coefficients.c11 * shear_modulus_pa),
        8.0 * a / (3.0 * coefficients.c22 * shear_modulus_pa),
        std::f64::consts::PI * a * (a / b).sqrt() / (4.0 * coefficients.c23 * shear_modulus_pa),
    ]
}

/// Runs FASTSIM on `strips x points_per_strip` points.
pub fn fastsim(
    hertz: &HertzContact,
    coefficients: &CreepCoefficients,
    mu: f64,
    creepages: &Creepages,
    strips: usize,
    points_per_strip: usize,
) -> Result<FastsimSolution> {
    super::validate_friction(mu, "fastsim")?;
    if strips < 2 || points_per_strip < 2 {
        return Err(Error::input(
            "fastsim",
            "grid",
            format!("need at least 2 x 2 points, got {strips} x {points_per_strip}"),
        ));
    }
    let [flex_x, flex_y, flex_spin] = flexibilities(hertz, coefficients);
    let (a, b) = (hertz.semi_axis_a_m, hertz.semi_axis_b_m);
    let total = strips * points_per_strip;
    let mut solution = FastsimSolution {
        strips,
        points_per_strip,
        x_m: Vec::with_capacity(total),
        y_m: Vec::with_capacity(total),
        area_m2: Vec::with_capacity(total),
        pressure_pa: Vec::with_capacity(total),
        traction_x_pa: Vec::with_capacity(total),
        traction_y_pa: Vec::with_capacity(total),
        state: Vec::with_capacity(total),
        force_x_n: 0.0,
        force_y_n: 0.0,
    };
    let dy = 2.0 * b / strips as f64;
    // Scale the sampled Hertz pressure so that the discrete pressures carry exactly Fn; then the
    // saturated force is exactly mu Fn, as in the continuum.
    let mut sampled_force_n = 0.0;
    for strip in 0..strips {
        let y = -b + (strip as f64 + 0.5) * dy;
        let half_length = a * (1.0 - (y / b).powi(2)).max(0.0).sqrt();
        let dx = 2.0 * half_length / points_per_strip as f64;
        for point in 0..points_per_strip {
            sampled_force_n +=
                hertz.pressure_pa(half_length - (point as f64 + 0.5) * dx, y) * dx * dy;
        }
    }
    if sampled_force_n <= 0.0 {
        return Err(Error::Numerical(
            "fastsim: sampled pressure vanished".into(),
        ));
    }
    let pressure_scale = hertz.normal_force_n / sampled_force_n;
    let (mut force_x_n, mut force_y_n) = (0.0, 0.0);
    for strip in 0..strips {
        let y = -b + (strip as f64 + 0.5) * dy;
        let half_length = a * (1.0 - (y / b).powi(2)).max(0.0).sqrt();
        let dx = 2.0 * half_length / points_per_strip as f64;
        // Rigid-slip terms divided by flexibility; the x-dependent spin term is added per point.
        let gradient_x = creepages.xi / flex_x - creepages.phi_per_m * y / flex_spin;
        let (mut px, mut py) = (0.0_f64, 0.0_f64);
        for point in 0..points_per_strip {
            let x = half_length - (point as f64 + 0.5) * dx;
            // Half a step for the first point (from the leading edge to its midpoint).
            let step = if point == 0 { 0.5 * dx } else { dx };
            let x_mid = x + 0.5 * step; // midpoint of the marched interval, for the x-linear spin term
            px -= step * gradient_x;
            py -= step * (creepages.eta / flex_y + creepages.phi_per_m * x_mid / flex_spin);
            let pressure_pa = pressure_scale * hertz.pressure_pa(x, y);
            let bound_pa = mu * pressure_pa;
            let magnitude = px.hypot(py);
            let state = if magnitude > bound_pa {
                let scale = if magnitude > 0.0 {
                    bound_pa / magnitude
                } else {
                    0.0
                };
                px *= scale;
                py *= scale;
                ElementState::Slip
            } else {
                ElementState::Adhesion
            };
            let area = dx * dy;
            force_x_n += px * area;
            force_y_n += py * area;
            solution.x_m.push(x);
            solution.y_m.push(y);
            solution.area_m2.push(area);
            solution.pressure_pa.push(pressure_pa);
            solution.traction_x_pa.push(px);
            solution.traction_y_pa.push(py);
            solution.state.push(state);
        }
    }
    solution.force_x_n = force_x_n;
    solution.force_y_n = force_y_n;
    Ok(solution)
}
