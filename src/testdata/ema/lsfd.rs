//! Mode shapes for known poles: the least-squares frequency-domain (LSFD) fit of every FRF,
//!
//! `H_o(w) = sum_r [A_or / (i w - lambda_r) + conj(A_or) / (i w - conj(lambda_r))]
//!           + L_o / (i w)^2 + U_o`,
//!
//! with complex residues `A_or` and real lower and upper residuals `L_o`, `U_o` (the modes below
//! and above the band). The residues are linear in the data: writing `A = a + i b`, the pole pair
//! contributes `a g1 + b g2` with `g1 = 1/(iw - lambda) + 1/(iw - conj lambda)` and
//! `g2 = i (1/(iw - lambda) - 1/(iw - conj lambda))`, and the real and imaginary parts of every
//! line give a real least-squares problem (solved by SVD, columns scaled to unit norm). For one
//! reference, `A_or` is proportional to the mode shape at response o (Ewins 2000, section 2.6).

use nalgebra::{DMatrix, DVector};
use rustfft::num_complex::Complex;

use super::frf::FrfSet;
use crate::{Error, Result};

/// Residues `A[r][o]` of the poles `lambdas` in every FRF of `set` over `fmin_hz..=fmax_hz`.
pub fn residues(
    set: &FrfSet,
    lambdas: &[Complex<f64>],
    fmin_hz: f64,
    fmax_hz: f64,
) -> Result<Vec<Vec<Complex<f64>>>> {
    // Lines at 0 Hz carry no information on 1/(iw)^2: left out.
    let lines: Vec<usize> = set
        .band(fmin_hz, fmax_hz)
        .filter(|&k| set.frequency_hz[k] > 0.0)
        .collect();
    let unknowns = 2 * lambdas.len() + 2;
    if 2 * lines.len() < unknowns {
        return Err(Error::input(
            "lsfd",
            "band",
            format!(
                "{} lines for {} modes: the fit needs more lines",
                lines.len(),
                lambdas.len()
            ),
        ));
    }
    let i = Complex::new(0.0, 1.0);
    // Complex basis functions per line: (g1, g2) per pole, then 1/(iw)^2 and 1.
    let basis: Vec<Vec<Complex<f64>>> = lines
        .iter()
        .map(|&k| {
            let iw = i * (2.0 * std::f64::consts::PI * set.frequency_hz[k]);
            let mut row = Vec::with_capacity(unknowns);
            for lambda in lambdas {
                let (p, q) = (1.0 / (iw - lambda), 1.0 / (iw - lambda.conj()));
                row.push(p + q);
                row.push(i * (p - q));
            }
            row.push(1.0 / (iw * iw));
            row.push(Complex::new(1.0, 0.0));
            row
        })
        .collect();
    let rows = 2 * lines.len();
    let mut a = DMatrix::from_fn(rows, unknowns, |row, column| {
        let value = basis[row / 2][column];
        if row % 2 == 0 {
            value.re
        } else {
            value.im
        }
    });
    let column_scale: Vec<f64> = (0..unknowns)
        .map(|c| {
            let norm = a.column(c).norm();
            if norm > 0.0 {
                1.0 / norm
            } else {
                1.0
            }
        })
        .collect();
    for (c, s) in column_scale.iter().enumerate() {
        a.column_mut(c).scale_mut(*s);
    }
    let svd = a.svd(true, true);
    let mut out = vec![Vec::with_capacity(set.frf.len()); lambdas.len()];
    for h in &set.frf {
        let b = DVector::from_fn(rows, |row, _| {
            let value = h[lines[row / 2]];
            if row % 2 == 0 {
                value.re
            } else {
                value.im
            }
        });
        let x = svd
            .solve(&b, 1e-12)
            .map_err(|e| Error::Numerical(format!("LSFD least squares: {e}")))?;
        for (r, residues) in out.iter_mut().enumerate() {
            residues.push(Complex::new(
                x[2 * r] * column_scale[2 * r],
                x[2 * r + 1] * column_scale[2 * r + 1],
            ));
        }
    }
    Ok(out)
}
