//! The frictionless normal contact problem on the half-space grid.
//!
//! Find pressures `pn >= 0` and the approach `delta` such that the deformed gap
//! `e_I = h_I + sum_J A_nn(I-J) pn_J - delta` is zero where `pn_I > 0`, non-negative elsewhere,
//! and `sum_I pn_I dx dy = Fn` (Kalker 1990 section 5.3, the problem his NORM solves).
//! Solved with the constrained conjugate-gradient method of Polonsky & Keer (Wear 231, 1999,
//! 206-219), which keeps `pn >= 0` by projection, re-adds elements that would close with negative
//! gap, and enforces the force balance each step; influence products by FFT.

use super::halfspace::{normal_influence, Convolver, Grid, OffsetKernel};
use super::Material;
use crate::{Error, Result};

/// Solution of the normal problem.
#[derive(Debug, Clone)]
pub struct NormalSolution {
    /// Pressure per element (Pa), y fastest (see [`Grid::index`]).
    pub pressure_pa: Vec<f64>,
    /// Approach of distant points (m), relative to the zero of the supplied gap.
    pub approach_m: f64,
    /// Iterations used.
    pub iterations: usize,
}

impl NormalSolution {
    /// Number of elements carrying pressure.
    pub fn contact_elements(&self) -> usize {
        self.pressure_pa.iter().filter(|&&p| p > 0.0).count()
    }
}

/// Solves the normal problem for undeformed gap `gap_m` (per element centre, >= 0 somewhere) and
/// normal force. `relative_tolerance` bounds `sum |dp| / sum p` between iterations.
///
/// Kept in one piece: Kalker's normal-contact iteration (NORM) over the patch elements in the
/// method's order.
pub fn solve_normal(
    grid: &Grid,
    gap_m: &[f64],
    normal_force_n: f64,
    material: &Material,
    relative_tolerance: f64,
) -> Result<NormalSolution> {
    super::validate_normal_force(normal_force_n, "normal problem")?;
    if gap_m.len() != grid.len() || grid.is_empty() {
        return Err(Error::input(
            "normal problem",
            "gap",
            format!("expected {} values, got {}", grid.len(), gap_m.len()),
        ));
    }
    let combined_modulus_pa = material.combined_modulus_pa();
    let kernel = OffsetKernel::new(grid.nx, grid.ny, |di, dj| {
        normal_influence(
            di as f64 * grid.dx_m,
            dj as f64 * grid.dy_m,
            grid,
            combined_modulus_pa,
        )
    });
    let convolver = Convolver::new(grid.nx, grid.ny);
    let spectrum = convolver.kernel_spectrum(&kernel);
    let area_m2 = grid.element_area_m2();
    let n = grid.len();

    // Start from a uniform pressure on the elements whose gap is below the median-ish level: all
    // elements is the safe choice of Polonsky & Keer.
    let mut pressure_pa = vec![normal_force_n / (area_m2 * n as f64); n];
    let mut direction = vec![0.0; n];
    let mut previous_norm = 1.0;
    let mut conjugate = false;
    let mut mean_gap = 0.0;
    for iteration in 1..=20_000 {
        let displacement = convolver.convolve(&spectrum, &pressure_pa);
        let mut gap: Vec<f64> = (0..n).map(|k| gap_m[k] + displacement[k]).collect();
        let contact: Vec<bool> = pressure_pa.iter().map(|&p| p > 0.0).collect();
        let contact_count = contact.iter().filter(|&&c| c).count().max(1);
        mean_gap =
            (0..n).filter(|&k| contact[k]).map(|k| gap[k]).sum::<f64>() / contact_count as f64;
        for value in gap.iter_mut() {
            *value -= mean_gap;
        }
        let norm: f64 = (0..n)
            .filter(|&k| contact[k])
            .map(|k| gap[k] * gap[k])
            .sum();
        let beta = if conjugate { norm / previous_norm } else { 0.0 };
        previous_norm = norm.max(f64::MIN_POSITIVE);
        for k in 0..n {
            direction[k] = if contact[k] {
                gap[k] + beta * direction[k]
            } else {
                0.0
            };
        }
        let mut response = convolver.convolve(&spectrum, &direction);
        let mean_response = (0..n)
            .filter(|&k| contact[k])
            .map(|k| response[k])
            .sum::<f64>()
            / contact_count as f64;
        for value in response.iter_mut() {
            *value -= mean_response;
        }
        let numerator: f64 = (0..n)
            .filter(|&k| contact[k])
            .map(|k| gap[k] * direction[k])
            .sum();
        let denominator: f64 = (0..n)
            .filter(|&k| contact[k])
            .map(|k| response[k] * direction[k])
            .sum();
        let step = if denominator > 0.0 {
            numerator / denominator
        } else {
            0.0
        };
        let previous = pressure_pa.clone();
        for k in 0..n {
            if contact[k] {
                pressure_pa[k] = (pressure_pa[k] - step * direction[k]).max(0.0);
            }
        }
        // Elements outside the contact that would be penetrated re-enter (Polonsky & Keer step 7).
        let mut reentered = false;
        for k in 0..n {
            if pressure_pa[k] == 0.0 && gap[k] < 0.0 {
                pressure_pa[k] = -step * gap[k];
                if pressure_pa[k] > 0.0 {
                    reentered = true;
                }
            }
        }
        conjugate = !reentered;
        let total: f64 = pressure_pa.iter().sum::<f64>() * area_m2;
        if total <= 0.0 {
            return Err(Error::Numerical(
                "normal problem: all pressure vanished".into(),
            ));
        }
        let scale = normal_force_n / total;
        for value in pressure_pa.iter_mut() {
            *value *= scale;
        }
        let change: f64 = pressure_pa
            .iter()
            .zip(&previous)
            .map(|(a, b)| (a - b).abs())
            .sum::<f64>()
            * area_m2
            / normal_force_n;
        if change < relative_tolerance && iteration > 2 {
            let displacement = convolver.convolve(&spectrum, &pressure_pa);
            let contact_count = pressure_pa.iter().filter(|&&p| p > 0.0).count().max(1);
            mean_gap = (0..n)
                .filter(|&k| pressure_pa[k] > 0.0)
                .map(|k| gap_m[k] + displacement[k])
                .sum::<f64>()
                / contact_count as f64;
            return Ok(NormalSolution {
                pressure_pa,
                approach_m: mean_gap,
                iterations: iteration,
            });
        }
    }
    Err(Error::Numerical(format!(
        "normal problem did not converge (last mean gap {mean_gap:e} m)"
    )))
}
