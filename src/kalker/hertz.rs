//! Hertz theory of elliptic contact between two identical elastic bodies.
//!
//! Undeformed gap `h(x, y) = A x^2 + B y^2` (A, B > 0, x rolling direction). The contact area is
//! an ellipse with semi-axes a (along x) and b (along y) and the pressure is
//! `p = p0 sqrt(1 - x^2/a^2 - y^2/b^2)`, `p0 = 3 Fn / (2 pi a b)`.
//! With the major semi-axis `a_maj`, the minor `b_min`, `g = b_min/a_maj` and eccentricity
//! `e^2 = 1 - g^2` (Johnson, *Contact Mechanics*, 1985, eq. 4.39; docs/references.md, section 5):
//! * `B_min/A_maj = [E(e)/g^2 - K(e)] / [K(e) - E(e)]` where `A_maj` is the curvature along the
//!   major axis (the smaller one) and `B_min` the larger one;
//! * `A_maj = 3 Fn (K - E) / (2 pi E* a_maj^3 e^2)`, solved here for `a_maj`;
//! * approach `delta = p0 b_min K(e) / E*`;
//! * `E* = E / (2 (1 - nu^2))` for identical bodies.
//!
//! With `D = (K - E)/e^2` the ratio is `(K/D - 1)/g^2`, free of the 0/0 of the circular limit.

use super::elliptic::{complete_elliptic_integrals, elliptic_d};
use super::Material;
use crate::{Error, Result};
use std::f64::consts::PI;

/// A Hertzian contact solution.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct HertzContact {
    /// Curvature A of the gap along x (1/m): `h = A x^2 + B y^2`.
    pub curvature_x_per_m: f64,
    /// Curvature B of the gap along y (1/m).
    pub curvature_y_per_m: f64,
    /// Normal force (N).
    pub normal_force_n: f64,
    /// Semi-axis a along the rolling direction x (m).
    pub semi_axis_a_m: f64,
    /// Semi-axis b along the lateral direction y (m).
    pub semi_axis_b_m: f64,
    /// Ellipticity, here the axis ratio b/a (the g of docs/references.md when a is the major axis).
    pub ellipticity: f64,
    /// Mutual approach of distant points of the two bodies (m).
    pub approach_m: f64,
    /// Peak pressure p0 = 3 Fn / (2 pi a b) (Pa).
    pub peak_pressure_pa: f64,
    /// The elastic constants used.
    pub material: Material,
}

impl HertzContact {
    /// Hertz solution for gap curvatures `A` (x) and `B` (y), normal force and material.
    pub fn from_curvatures(
        curvature_x_per_m: f64,
        curvature_y_per_m: f64,
        normal_force_n: f64,
        material: Material,
    ) -> Result<HertzContact> {
        for (value, field) in [
            (curvature_x_per_m, "curvature A (x)"),
            (curvature_y_per_m, "curvature B (y)"),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(Error::input(
                    "hertz",
                    field,
                    format!("must be > 0 1/m for a Hertzian (elliptic) contact, got {value}"),
                ));
            }
        }
        super::validate_normal_force(normal_force_n, "hertz")?;
        Material::validated(material.youngs_modulus_pa, material.poisson_ratio, "hertz")?;
        let combined_modulus_pa = material.combined_modulus_pa();
        // The major axis lies along the direction of the smaller curvature.
        let (curvature_major, curvature_minor) = if curvature_x_per_m <= curvature_y_per_m {
            (curvature_x_per_m, curvature_y_per_m)
        } else {
            (curvature_y_per_m, curvature_x_per_m)
        };
        let axis_ratio = solve_axis_ratio(curvature_minor / curvature_major)?;
        let eccentricity = (1.0 - axis_ratio * axis_ratio).max(0.0).sqrt();
        let (elliptic_k, _) = complete_elliptic_integrals(eccentricity)?;
        let elliptic_dd = elliptic_d(eccentricity)?;
        let major_m = (3.0 * normal_force_n * elliptic_dd
            / (2.0 * PI * combined_modulus_pa * curvature_major))
            .cbrt();
        let minor_m = axis_ratio * major_m;
        let peak_pressure_pa = 3.0 * normal_force_n / (2.0 * PI * major_m * minor_m);
        let approach_m = peak_pressure_pa * minor_m * elliptic_k / combined_modulus_pa;
        let (semi_axis_a_m, semi_axis_b_m) = if curvature_x_per_m <= curvature_y_per_m {
            (major_m, minor_m)
        } else {
            (minor_m, major_m)
        };
        Ok(HertzContact {
            curvature_x_per_m,
            curvature_y_per_m,
            normal_force_n,
            semi_axis_a_m,
            semi_axis_b_m,
            ellipticity: semi_axis_b_m / semi_axis_a_m,
            approach_m,
            peak_pressure_pa,
            material,
        })
    }

    /// Wheel of rolling radius `wheel_radius_m` with a flat (cylindrical) tread on a rail with
    /// crown radius `rail_crown_radius_m`: `A = 1/(2 R_w)`, `B = 1/(2 R_r)`.
    pub fn wheel_on_rail(
        wheel_radius_m: f64,
        rail_crown_radius_m: f64,
        normal_force_n: f64,
        material: Material,
    ) -> Result<HertzContact> {
        for (value, field) in [
            (wheel_radius_m, "--wheel-radius-m"),
            (rail_crown_radius_m, "--rail-radius-m"),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(Error::input(
                    "command line",
                    field,
                    format!("radius must be > 0 m, got {value}"),
                ));
            }
        }
        HertzContact::from_curvatures(
            0.5 / wheel_radius_m,
            0.5 / rail_crown_radius_m,
            normal_force_n,
            material,
        )
    }

    /// `sqrt(a b)`, the length scale of Kalker's linear theory.
    pub fn mean_semi_axis_m(&self) -> f64 {
        (self.semi_axis_a_m * self.semi_axis_b_m).sqrt()
    }

    /// Hertz pressure at (x, y) (0 outside the ellipse).
    pub fn pressure_pa(&self, x_m: f64, y_m: f64) -> f64 {
        let r2 = (x_m / self.semi_axis_a_m).powi(2) + (y_m / self.semi_axis_b_m).powi(2);
        if r2 >= 1.0 {
            0.0
        } else {
            self.peak_pressure_pa * (1.0 - r2).sqrt()
        }
    }
}

/// Solves `(K/D - 1)/g^2 = ratio` (ratio = larger / smaller curvature >= 1) for `g` in (0, 1].
/// The left side decreases monotonically from +inf (g -> 0) to 1 (g = 1), so bisection in log g
/// is certain to converge; 200 halvings of [1e-6, 1] reach machine precision.
pub fn solve_axis_ratio(curvature_ratio: f64) -> Result<f64> {
    if !(curvature_ratio.is_finite() && curvature_ratio >= 1.0) {
        return Err(Error::Numerical(format!(
            "curvature ratio must be >= 1, got {curvature_ratio}"
        )));
    }
    if curvature_ratio - 1.0 < 1e-14 {
        return Ok(1.0);
    }
    let ratio_of = |g: f64| -> Result<f64> {
        let eccentricity = (1.0 - g * g).max(0.0).sqrt();
        let (elliptic_k, _) = complete_elliptic_integrals(eccentricity)?;
        Ok((elliptic_k / elliptic_d(eccentricity)? - 1.0) / (g * g))
    };
    let (mut log_low, mut log_high) = ((1e-6_f64).ln(), 0.0_f64);
    if ratio_of(1e-6)? < curvature_ratio {
        return Err(Error::Numerical(format!(
            "curvature ratio {curvature_ratio} too extreme for an elliptic contact"
        )));
    }
    for _ in 0..200 {
        let log_mid = 0.5 * (log_low + log_high);
        if ratio_of(log_mid.exp())? > curvature_ratio {
            log_low = log_mid;
        } else {
            log_high = log_mid;
        }
        if log_high - log_low < 1e-15 {
            break;
        }
    }
    Ok((0.5 * (log_low + log_high)).exp())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn circle_limit() {
        // Equal curvatures: a = b = (3 F R / (4 E*))^(1/3) with R = 1/(2A) (Johnson eq. 4.22).
        let material = Material::STEEL;
        let hertz = HertzContact::from_curvatures(1.0, 1.0, 1e4, material).unwrap();
        let expected = (3.0 * 1e4 * 0.5 / (4.0 * material.combined_modulus_pa())).cbrt();
        assert!((hertz.semi_axis_a_m / expected - 1.0).abs() < 1e-12);
        assert!((hertz.semi_axis_b_m / expected - 1.0).abs() < 1e-12);
        // delta = a^2 / R.
        assert!((hertz.approach_m / (expected * expected * 2.0) - 1.0).abs() < 1e-10);
    }

    #[test]
    fn swapped_curvatures_swap_axes() {
        let first = HertzContact::from_curvatures(1.0, 3.0, 5e4, Material::STEEL).unwrap();
        let second = HertzContact::from_curvatures(3.0, 1.0, 5e4, Material::STEEL).unwrap();
        assert!((first.semi_axis_a_m - second.semi_axis_b_m).abs() < 1e-15);
        assert!((first.approach_m - second.approach_m).abs() < 1e-18);
    }
}
