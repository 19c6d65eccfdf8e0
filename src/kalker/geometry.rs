//! Contact geometry: undeformed gap and Hertz curvatures.
//!
//! The core is curvature based (`HertzContact::from_curvatures`). For profiles, this module works
//! with closures so that the S1002 / 54E1 profile code (in `crate::geometry`, written separately)
//! can be plugged in:
//! * `wheel_radius_offset_m(y)`: wheel rolling radius at lateral position y minus the nominal
//!   radius `R_w` (m), so the wheel radius there is `R_w + r(y)`;
//! * `rail_height_m(y)`: height of the rail top at y (m, z up).
//!
//! The wheel is a body of revolution about an axis parallel to y, so at lateral position y its
//! surface is a circle of radius `R(y) = R_w + r(y)`: height `z_w(x, y) = z_axis - sqrt(R(y)^2 - x^2)`
//! (exact), or `z_axis - R(y) + x^2 / (2 R(y))` (parabolic). Gap `h(x, y) = z_w - z_rail(y)`,
//! shifted so that its minimum over the grid is zero (the first point of contact).
//! Hertz curvatures at y0: `A = 1/(2 R(y0))` (flat-tread approximation, no contact angle),
//! `B = h''(y0)/2 = -(r''(y0) + z''(y0))/2` by central differences.

use super::halfspace::Grid;
use crate::{Error, Result};

/// How the wheel circle is represented in the rolling direction.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WheelCircle {
    /// Exact circle `R - sqrt(R^2 - x^2)`.
    Exact,
    /// Parabola `x^2 / (2R)`.
    Parabolic,
}

/// Undeformed gap (m) at the element centres of `grid`, centred on lateral position `y0_m`
/// (element y is `y0 + grid.y`). Errors when the grid is longer than the wheel or the profiles
/// give non-finite values.
pub fn profile_gap(
    grid: &Grid,
    wheel_radius_m: f64,
    wheel_radius_offset_m: impl Fn(f64) -> f64,
    rail_height_m: impl Fn(f64) -> f64,
    y0_m: f64,
    circle: WheelCircle,
) -> Result<Vec<f64>> {
    if !(wheel_radius_m.is_finite() && wheel_radius_m > 0.0) {
        return Err(Error::input(
            "geometry",
            "wheel radius",
            format!("must be > 0 m, got {wheel_radius_m}"),
        ));
    }
    let mut gap_m = vec![0.0; grid.len()];
    for j in 0..grid.ny {
        let y = y0_m + grid.y_m(j);
        let radius_m = wheel_radius_m + wheel_radius_offset_m(y);
        let rail_m = rail_height_m(y);
        if !(radius_m.is_finite() && radius_m > 0.0 && rail_m.is_finite()) {
            return Err(Error::input(
                "geometry",
                "profile",
                format!("non-finite or non-positive profile value at y = {y} m"),
            ));
        }
        for i in 0..grid.nx {
            let x = grid.x_m(i);
            if x.abs() >= radius_m {
                return Err(Error::input(
                    "geometry",
                    "grid",
                    format!(
                        "potential contact area |x| = {} m exceeds the wheel radius",
                        x.abs()
                    ),
                ));
            }
            let rise_m = match circle {
                WheelCircle::Exact => radius_m - (radius_m * radius_m - x * x).sqrt(),
                WheelCircle::Parabolic => x * x / (2.0 * radius_m),
            };
            // Wheel surface height relative to the axis height minus R_w, minus rail height.
            gap_m[grid.index(i, j)] = (wheel_radius_m - radius_m) + rise_m - rail_m;
        }
    }
    let minimum = gap_m.iter().cloned().fold(f64::INFINITY, f64::min);
    for value in gap_m.iter_mut() {
        *value -= minimum;
    }
    Ok(gap_m)
}

/// Hertz curvatures `(A, B)` (1/m) of the gap at lateral position `y0_m`, by central differences
/// with step `step_m` (e.g. 1e-4 m for profiles tabulated in mm). Errors when either is not > 0
/// (the contact is then not Hertzian).
pub fn curvatures_at(
    wheel_radius_m: f64,
    wheel_radius_offset_m: impl Fn(f64) -> f64,
    rail_height_m: impl Fn(f64) -> f64,
    y0_m: f64,
    step_m: f64,
) -> Result<(f64, f64)> {
    let gap_y = |y: f64| -wheel_radius_offset_m(y) - rail_height_m(y);
    let second_derivative =
        (gap_y(y0_m + step_m) - 2.0 * gap_y(y0_m) + gap_y(y0_m - step_m)) / (step_m * step_m);
    let curvature_x_per_m = 0.5 / (wheel_radius_m + wheel_radius_offset_m(y0_m));
    let curvature_y_per_m = 0.5 * second_derivative;
    if !(curvature_x_per_m.is_finite()
        && curvature_x_per_m > 0.0
        && curvature_y_per_m.is_finite()
        && curvature_y_per_m > 0.0)
    {
        return Err(Error::input(
            "geometry",
            "--wheel-y-m",
            format!("the gap at y = {y0_m} m is not Hertzian (curvatures A = {curvature_x_per_m:.4}, B = {curvature_y_per_m:.4} 1/m)"),
        ));
    }
    Ok((curvature_x_per_m, curvature_y_per_m))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crown_curvatures() {
        // Flat wheel of 0.46 m on a 0.3 m crown: A = 1/0.92, B = 1/0.6.
        let crown = |y: f64| -(0.3 - (0.09 - y * y).sqrt());
        let (a, b) = curvatures_at(0.46, |_| 0.0, crown, 0.0, 1e-4).unwrap();
        assert!((a - 1.0 / 0.92).abs() < 1e-12);
        assert!((b - 1.0 / 0.6).abs() < 1e-5);
        // A concave (conformal) rail is rejected.
        assert!(curvatures_at(0.46, |_| 0.0, |y: f64| y * y, 0.0, 1e-4).is_err());
    }

    #[test]
    fn gap_minimum_is_zero_and_parabolic_close_to_exact() {
        let grid = Grid::centered(0.008, 0.006, 16, 12);
        let crown = |y: f64| -y * y / 0.6;
        let exact = profile_gap(&grid, 0.46, |_| 0.0, crown, 0.0, WheelCircle::Exact).unwrap();
        let parabolic =
            profile_gap(&grid, 0.46, |_| 0.0, crown, 0.0, WheelCircle::Parabolic).unwrap();
        assert!(exact.iter().cloned().fold(f64::INFINITY, f64::min).abs() < 1e-18);
        for (e, p) in exact.iter().zip(&parabolic) {
            // exact - parabolic = x^4/(8 R^3) + O(x^6): bound by the leading series term at the largest x.
            assert!((e - p).abs() < 0.008f64.powi(4) / (8.0 * 0.46f64.powi(3)) * 1.01);
        }
    }
}
