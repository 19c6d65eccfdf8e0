//! The least-squares complex-frequency (LSCF) estimator (Guillaume, Verboven, Vanlanduit,
//! Van der Auweraer, Peeters, "A poly-reference implementation of the least-squares complex
//! frequency-domain estimator", IMAC XXI, 2003; here with one reference).
//!
//! Model: every FRF shares one denominator, `H_o(w) = N_o(W) / d(W)`, polynomials of order n in
//! the z-domain basis `W_k^j = exp(i j w_k dt)` with `dt = 1 / (2 f_max)` (so `w_k dt` spans at
//! most [0, pi] and the basis is well conditioned). The linearised equation error
//! `N_o(W_k) - H_o(w_k) d(W_k)` is minimised in least squares over the lines of the band. With
//! real coefficients the normal equations are, per output o,
//! `R = Re(X^H X)`, `S_o = Re(X^H Y_o)`, `T_o = Re(Y_o^H Y_o)`, `X_kj = W_k^j`,
//! `Y_o,kj = -H_o(w_k) W_k^j`; eliminating the numerators leaves the reduced equations
//! `M alpha = 0`, `M = sum_o (T_o - S_o^T R^-1 S_o)`, solved with `alpha_n = 1`.
//!
//! All three matrices are Toeplitz in `l - j` (their entries are sums of `exp(i (l - j) w_k dt)`
//! weighted by 1, `H_o` or `|H_o|^2`), so they are built from 2n+1 sums per output.
//!
//! Poles: the roots `z_r` of `d(z)` (eigenvalues of its companion matrix), `lambda_r = ln(z_r) /
//! dt`; a physical pole has `Im lambda > 0` and `Re lambda < 0` (`|z| < 1`), natural frequency
//! `|lambda| / 2 pi` and damping ratio `-Re lambda / |lambda|`.

use nalgebra::DMatrix;
use rustfft::num_complex::Complex;

use super::frf::FrfSet;
use crate::{Error, Result};

/// A pole of the fitted denominator.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pole {
    /// `lambda = -zeta w_n + i w_n sqrt(1 - zeta^2)`, rad/s.
    pub lambda: Complex<f64>,
    /// `|lambda| / 2 pi`, Hz.
    pub frequency_hz: f64,
    /// `-Re lambda / |lambda|`.
    pub damping_ratio: f64,
}

impl Pole {
    /// The pole with continuous-time value `lambda`.
    pub fn new(lambda: Complex<f64>) -> Self {
        let magnitude = lambda.norm();
        Pole {
            lambda,
            frequency_hz: magnitude / (2.0 * std::f64::consts::PI),
            damping_ratio: -lambda.re / magnitude,
        }
    }
}

/// The LSCF fit of one band, ready to give the poles at any order up to `max_order`.
pub struct Lscf {
    dt_s: f64,
    fmin_hz: f64,
    fmax_hz: f64,
    max_order: usize,
    /// `c_m = sum_k cos(m theta_k)`, m = 0..=max_order (R's Toeplitz entries, symmetric).
    r_sums: Vec<f64>,
    /// Per output: `s_m = -sum_k Re(H exp(i m theta))`, m = -max_order..=max_order (index m + n).
    s_sums: Vec<Vec<f64>>,
    /// Per output: `t_m = sum_k |H|^2 cos(m theta)`, m = 0..=max_order.
    t_sums: Vec<Vec<f64>>,
}

impl Lscf {
    /// Prepares the fit of `set` over `fmin_hz..=fmax_hz` for orders up to `max_order`.
    pub fn new(set: &FrfSet, fmin_hz: f64, fmax_hz: f64, max_order: usize) -> Result<Lscf> {
        let band = set.band(fmin_hz, fmax_hz);
        let lines = band.len();
        if max_order < 2 || lines < max_order + 1 {
            return Err(Error::input(
                "lscf",
                "--max-order",
                format!(
                    "{max_order} with {lines} frequency lines in [{fmin_hz}, {fmax_hz}] Hz; allowed: \
                     2 ..= lines - 1 (the fit needs more lines than coefficients)"
                ),
            ));
        }
        let dt_s = 1.0 / (2.0 * fmax_hz);
        let theta: Vec<f64> = set.frequency_hz[band.clone()]
            .iter()
            .map(|f| 2.0 * std::f64::consts::PI * f * dt_s)
            .collect();
        // Scaled so the largest |H| is 1 (the poles do not depend on the scale).
        let scale = set
            .frf
            .iter()
            .flat_map(|h| h[band.clone()].iter().map(|v| v.norm()))
            .fold(0.0, f64::max);
        if !(scale > 0.0 && scale.is_finite()) {
            return Err(Error::input(
                "lscf",
                "FRFs",
                "every FRF is zero (or not finite) in the band",
            ));
        }
        let n = max_order;
        let r_sums = (0..=n)
            .map(|m| theta.iter().map(|t| (m as f64 * t).cos()).sum())
            .collect();
        let mut s_sums = Vec::with_capacity(set.frf.len());
        let mut t_sums = Vec::with_capacity(set.frf.len());
        for h in &set.frf {
            let h: Vec<Complex<f64>> = h[band.clone()].iter().map(|v| v / scale).collect();
            let s: Vec<f64> = (0..=2 * n)
                .map(|index| {
                    let m = index as f64 - n as f64;
                    -h.iter()
                        .zip(&theta)
                        .map(|(v, t)| (v * Complex::from_polar(1.0, m * t)).re)
                        .sum::<f64>()
                })
                .collect();
            let t: Vec<f64> = (0..=n)
                .map(|m| {
                    h.iter()
                        .zip(&theta)
                        .map(|(v, t)| v.norm_sqr() * (m as f64 * t).cos())
                        .sum()
                })
                .collect();
            s_sums.push(s);
            t_sums.push(t);
        }
        Ok(Lscf {
            dt_s,
            fmin_hz,
            fmax_hz,
            max_order,
            r_sums,
            s_sums,
            t_sums,
        })
    }

    /// Denominator coefficients `alpha_0..=alpha_order` (`alpha_order = 1`) at `order`.
    pub fn denominator(&self, order: usize) -> Result<Vec<f64>> {
        assert!(
            (1..=self.max_order).contains(&order),
            "order within the prepared range"
        );
        let size = order + 1;
        let n = self.max_order;
        let r = DMatrix::from_fn(size, size, |j, l| self.r_sums[j.abs_diff(l)]);
        let cholesky = r.cholesky().ok_or_else(|| {
            Error::Numerical(format!(
                "LSCF: the basis matrix at order {order} is not positive definite (too few \
                 distinct lines in the band)"
            ))
        })?;
        let mut m = DMatrix::<f64>::zeros(size, size);
        for (s, t) in self.s_sums.iter().zip(&self.t_sums) {
            // S[j][l] = s_(l - j); T[j][l] = t_|l - j|.
            let s_matrix = DMatrix::from_fn(size, size, |j, l| s[n + l - j]);
            let t_matrix = DMatrix::from_fn(size, size, |j, l| t[j.abs_diff(l)]);
            let r_inv_s = cholesky.solve(&s_matrix);
            m += t_matrix - s_matrix.transpose() * r_inv_s;
        }
        // alpha_order = 1: M[..order, ..order] alpha' = -M[..order, order].
        let leading = m.view((0, 0), (order, order)).into_owned();
        let rhs = -m.view((0, order), (order, 1)).into_owned();
        let solution = leading.lu().solve(&rhs).ok_or_else(|| {
            Error::Numerical(format!("LSCF: singular reduced equations at order {order}"))
        })?;
        let mut alpha: Vec<f64> = solution.iter().copied().collect();
        alpha.push(1.0);
        Ok(alpha)
    }

    /// Physical poles at `order` inside the band, by increasing frequency.
    pub fn poles(&self, order: usize) -> Result<Vec<Pole>> {
        let alpha = self.denominator(order)?;
        // Companion matrix of the monic z^n + alpha_(n-1) z^(n-1) + ... + alpha_0.
        let companion = DMatrix::from_fn(order, order, |i, j| {
            if i == 0 {
                -alpha[order - 1 - j]
            } else if i == j + 1 {
                1.0
            } else {
                0.0
            }
        });
        let mut poles: Vec<Pole> = companion
            .complex_eigenvalues()
            .iter()
            .filter(|z| z.im > 0.0 && z.norm() < 1.0)
            .map(|z| Pole::new(z.ln() / self.dt_s))
            .filter(|p| {
                p.frequency_hz >= self.fmin_hz
                    && p.frequency_hz <= self.fmax_hz
                    && p.damping_ratio > 0.0
                    && p.damping_ratio < 1.0
            })
            .collect();
        poles.sort_by(|a, b| a.frequency_hz.total_cmp(&b.frequency_hz));
        Ok(poles)
    }

    /// The highest order prepared.
    pub fn max_order(&self) -> usize {
        self.max_order
    }
}
