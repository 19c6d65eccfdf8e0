//! Complete elliptic integrals of the first and second kind by the arithmetic-geometric mean.
//!
//! With modulus k (0 <= k < 1):
//! `K(k) = int_0^{pi/2} dt / sqrt(1 - k^2 sin^2 t)`, `E(k) = int_0^{pi/2} sqrt(1 - k^2 sin^2 t) dt`.
//! AGM (Abramowitz & Stegun 17.6): `a0 = 1, b0 = sqrt(1 - k^2), c0 = k`,
//! `a_{n+1} = (a_n + b_n)/2, b_{n+1} = sqrt(a_n b_n), c_{n+1} = (a_n - b_n)/2 = c_n^2/(4 a_{n+1})`;
//! `K = pi / (2 a_N)`, `E = K (1 - sum_{n>=0} 2^{n-1} c_n^2)`. Convergence is quadratic, so a
//! handful of steps reach full double precision.

use crate::{Error, Result};
use std::f64::consts::FRAC_PI_2;

/// `(K(k), E(k))` for modulus `k` in [0, 1). `k = 1` (K infinite) and values outside are errors.
pub fn complete_elliptic_integrals(modulus: f64) -> Result<(f64, f64)> {
    if !(modulus.is_finite() && (0.0..1.0).contains(&modulus)) {
        return Err(Error::Numerical(format!(
            "elliptic modulus must be in [0, 1), got {modulus}"
        )));
    }
    let mut arithmetic = 1.0_f64;
    let mut geometric = (1.0 - modulus * modulus).sqrt();
    let mut weighted_sum = 0.5 * modulus * modulus; // 2^{-1} c_0^2
    let mut power_of_two = 1.0; // 2^{n-1} for n = 1
    let mut half_difference = modulus; // c_0
    for _ in 0..64 {
        let next_arithmetic = 0.5 * (arithmetic + geometric);
        // c_{n+1} = (a_n - b_n)/2 = c_n^2 / (4 a_{n+1}): the second form avoids the cancellation
        // of a_n - b_n as the means converge.
        half_difference = half_difference * half_difference / (4.0 * next_arithmetic);
        geometric = (arithmetic * geometric).sqrt();
        arithmetic = next_arithmetic;
        weighted_sum += power_of_two * half_difference * half_difference;
        power_of_two *= 2.0;
        if half_difference.abs() <= 1e-17 * arithmetic {
            break;
        }
    }
    let first_kind = FRAC_PI_2 / arithmetic;
    Ok((first_kind, first_kind * (1.0 - weighted_sum)))
}

/// `D(k) = (K(k) - E(k)) / k^2`, finite at k = 0 (series `pi/4 (1 + 3k^2/8 + ...)` for small k,
/// where the difference K - E would cancel).
pub fn elliptic_d(modulus: f64) -> Result<f64> {
    if modulus < 1e-4 {
        let m = modulus * modulus;
        return Ok(std::f64::consts::FRAC_PI_4 * (1.0 + 0.375 * m + 0.2734375 * m * m));
    }
    let (first_kind, second_kind) = complete_elliptic_integrals(modulus)?;
    Ok((first_kind - second_kind) / (modulus * modulus))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn known_values() {
        // Reference values: Abramowitz & Stegun Table 17.1 / DLMF 19.6 (m = k^2).
        let (k, e) = complete_elliptic_integrals(0.0).unwrap();
        assert!((k - FRAC_PI_2).abs() < 1e-15 && (e - FRAC_PI_2).abs() < 1e-15);
        let (k, e) = complete_elliptic_integrals(0.5).unwrap(); // m = 0.25
        assert!((k - 1.685_750_354_812_596).abs() < 1e-14, "{k}");
        assert!((e - 1.467_462_209_339_427).abs() < 1e-14, "{e}");
        let (k, e) = complete_elliptic_integrals(0.5_f64.sqrt()).unwrap(); // m = 0.5
        assert!((k - 1.854_074_677_301_372).abs() < 1e-14, "{k}");
        assert!((e - 1.350_643_881_047_675_5).abs() < 1e-14, "{e}");
        let (k, e) = complete_elliptic_integrals(0.9_f64.sqrt()).unwrap(); // m = 0.9
        assert!((k - 2.578_092_113_348_173).abs() < 1e-13, "{k}");
        assert!((e - 1.104_774_732_704_073).abs() < 1e-13, "{e}");
        assert!(complete_elliptic_integrals(1.0).is_err());
    }

    #[test]
    fn d_series_matches_agm() {
        let k = 2e-4;
        let (kk, ee) = complete_elliptic_integrals(k).unwrap();
        let direct = (kk - ee) / (k * k);
        assert!((elliptic_d(0.99e-4).unwrap() - direct).abs() < 1e-6);
    }
}
