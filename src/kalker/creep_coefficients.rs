//! Kalker's creep coefficients C11, C22, C23 and the linear (no-slip) theory.
//!
//! Linear theory (Kalker 1967; docs/references.md, section 5), with `c = sqrt(a b)` and shear modulus G:
//! `Fx = -G c^2 C11 xi`, `Fy = -G c^2 C22 eta - G c^3 C23 phi`.
//!
//! The coefficients are those of Kalker, *Three-dimensional elastic bodies in rolling contact*
//! (1990), Table E.3, rows a/b = 0.2, 0.5, 1.0 and b/a = 0.5, 0.2 (as docs/references.md lists them), each for
//! nu = 0, 0.25, 0.5. Interpolation:
//! * in nu, as Kalker's CONTACT does, quadratically in 1/C (Lagrange through nu = 0, 0.25, 0.5):
//!   `1/C(nu) = 8(nu-.25)(nu-.5)/C0 - 16(nu-.5)nu/C.25 + 8 nu(nu-.25)/C.5`;
//! * in the axis ratio, piecewise linearly: for a/b <= 1 in C against a/b (C changes slowly there);
//!   for a/b >= 1 in `C * (b/a)` against b/a. The latter product varies by only a few per cent
//!   across the rows (e.g. C11 at nu = .25: 4.12, 2.55, 1.56 for b/a = 1, .5, .2 — close to a
//!   straight line), while C itself grows like a/b, so interpolating the product is much more
//!   accurate between the coarse rows.
//!
//! Outside 0.2 <= a/b <= 5 the table gives no data; the functions return an error rather than
//! extrapolate.

use crate::{Error, Result};

/// Kalker's creep coefficients (dimensionless).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct CreepCoefficients {
    /// Longitudinal coefficient C11.
    pub c11: f64,
    /// Lateral coefficient C22.
    pub c22: f64,
    /// Lateral-spin coefficient C23 (C32 = -C23).
    pub c23: f64,
}

/// One table row: axis-ratio node and `[C11, C22, C23]` at nu = 0, 0.25, 0.5.
struct TableRow {
    a_over_b: f64,
    coefficients: [[f64; 3]; 3],
}

/// Kalker (1990) Table E.3, the rows given in docs/references.md, section 5 (ordered by a/b).
// 3.14 below is a tabulated C22, not an approximation of pi.
#[allow(clippy::approx_constant)]
const TABLE_E3: [TableRow; 5] = [
    TableRow {
        a_over_b: 0.2,
        coefficients: [
            [2.59, 3.37, 4.81],
            [2.59, 2.63, 2.66],
            [0.483, 0.603, 0.809],
        ],
    },
    TableRow {
        a_over_b: 0.5,
        coefficients: [[2.88, 3.62, 4.83], [2.88, 3.01, 3.14], [0.827, 0.929, 1.07]],
    },
    TableRow {
        a_over_b: 1.0,
        coefficients: [[3.40, 4.12, 5.20], [3.40, 3.67, 3.98], [1.33, 1.47, 1.63]],
    },
    TableRow {
        a_over_b: 2.0,
        coefficients: [[4.37, 5.10, 6.11], [4.37, 4.90, 5.56], [2.35, 2.62, 2.96]],
    },
    TableRow {
        a_over_b: 5.0,
        coefficients: [[6.96, 7.78, 8.82], [6.96, 8.14, 9.79], [5.72, 6.63, 7.89]],
    },
];

/// CONTACT's interpolation in nu: quadratic Lagrange interpolation of 1/C through nu = 0, .25, .5.
fn interpolate_in_poisson_ratio(values: [f64; 3], poisson_ratio: f64) -> f64 {
    let nu = poisson_ratio;
    let inverse = 8.0 * (nu - 0.25) * (nu - 0.5) / values[0] - 16.0 * (nu - 0.5) * nu / values[1]
        + 8.0 * nu * (nu - 0.25) / values[2];
    1.0 / inverse
}

/// Creep coefficients for the semi-axis ratio a/b (a along the rolling direction) and Poisson's
/// ratio nu. Errors outside 0.2 <= a/b <= 5 and 0 <= nu <= 0.5.
pub fn kalker_creep_coefficients(a_over_b: f64, poisson_ratio: f64) -> Result<CreepCoefficients> {
    if !(a_over_b.is_finite() && (0.2 - 1e-12..=5.0 + 1e-12).contains(&a_over_b)) {
        return Err(Error::input(
            "creep coefficients",
            "a/b",
            format!("Kalker's table (1990, E.3) covers 0.2 <= a/b <= 5, got {a_over_b}"),
        ));
    }
    if !(poisson_ratio.is_finite() && (0.0..=0.5).contains(&poisson_ratio)) {
        return Err(Error::input(
            "creep coefficients",
            "nu",
            format!("must be in [0, 0.5], got {poisson_ratio}"),
        ));
    }
    let row_value = |row: &TableRow, which: usize| {
        interpolate_in_poisson_ratio(row.coefficients[which], poisson_ratio)
    };
    let mut result = [0.0; 3];
    for (which, value) in result.iter_mut().enumerate() {
        *value = if a_over_b <= 1.0 {
            // Linear in a/b over the rows a/b = 0.2, 0.5, 1.0.
            let upper = if a_over_b <= 0.5 { 1 } else { 2 };
            let (low, high) = (&TABLE_E3[upper - 1], &TABLE_E3[upper]);
            let t = (a_over_b - low.a_over_b) / (high.a_over_b - low.a_over_b);
            (1.0 - t) * row_value(low, which) + t * row_value(high, which)
        } else {
            // Linear in b/a of C * (b/a) over the rows b/a = 1, 0.5, 0.2.
            let b_over_a = 1.0 / a_over_b;
            let upper = if a_over_b <= 2.0 { 3 } else { 4 };
            let (low, high) = (&TABLE_E3[upper - 1], &TABLE_E3[upper]);
            let (t_low, t_high) = (1.0 / low.a_over_b, 1.0 / high.a_over_b);
            let t = (b_over_a - t_low) / (t_high - t_low);
            ((1.0 - t) * row_value(low, which) * t_low + t * row_value(high, which) * t_high)
                / b_over_a
        };
    }
    Ok(CreepCoefficients {
        c11: result[0],
        c22: result[1],
        c23: result[2],
    })
}

/// Kalker's linear theory: `(Fx, Fy)` in N for creepages xi, eta (-) and spin phi (1/m).
pub fn linear_creep_forces(
    shear_modulus_pa: f64,
    semi_axis_a_m: f64,
    semi_axis_b_m: f64,
    coefficients: CreepCoefficients,
    xi: f64,
    eta: f64,
    phi_per_m: f64,
) -> (f64, f64) {
    let c = (semi_axis_a_m * semi_axis_b_m).sqrt();
    let force_x_n = -shear_modulus_pa * c * c * coefficients.c11 * xi;
    let force_y_n = -shear_modulus_pa * c * c * coefficients.c22 * eta
        - shear_modulus_pa * c * c * c * coefficients.c23 * phi_per_m;
    (force_x_n, force_y_n)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reproduces_table_nodes() {
        for row in &TABLE_E3 {
            for (node, nu) in [0.0, 0.25, 0.5].into_iter().enumerate() {
                let c = kalker_creep_coefficients(row.a_over_b, nu).unwrap();
                assert!((c.c11 / row.coefficients[0][node] - 1.0).abs() < 1e-12);
                assert!((c.c22 / row.coefficients[1][node] - 1.0).abs() < 1e-12);
                assert!((c.c23 / row.coefficients[2][node] - 1.0).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn out_of_table_is_an_error() {
        assert!(kalker_creep_coefficients(0.1, 0.3).is_err());
        assert!(kalker_creep_coefficients(6.0, 0.3).is_err());
        assert!(kalker_creep_coefficients(1.0, 0.6).is_err());
    }
}
