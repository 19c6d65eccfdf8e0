//! Nodal-diameter decomposition of a field sampled on a ring: the discrete Fourier series
//! around the circumference.
//!
//! Math: `N` points at the angles `theta_k = theta_0 + 2 pi k / N` carry values `f_k`. The
//! real discrete Fourier series
//!
//! `f(theta) = c_0 + sum_(n=1)^(N/2) (c_n cos(n theta) + s_n sin(n theta))`
//!
//! interpolates them exactly, with
//! - `c_0 = (1/N) sum_k f_k` (the mean: every point alike, n = 0),
//! - `c_n = (2/N) sum_k f_k cos(n theta_k)`, `s_n = (2/N) sum_k f_k sin(n theta_k)` for
//!   `1 <= n < N/2`,
//!
//! (and a one-sided `n = N/2` term for even N, which the rule below keeps out of reach), so
//! that a field `A cos(n theta) + B sin(n theta)` reads `c_n = A`, `s_n = B` whatever
//! `theta_0` is. `sqrt(c_n^2 + s_n^2)` is the amplitude of harmonic n, independent of where
//! the pattern stands on the wheel.
//!
//! Aliasing: on N points, `cos(n' theta)` and `cos((N - n') theta)` take the same values, and
//! `sin(n' theta)` those of `-sin((N - n') theta)` (for `theta_0 = 0`). A harmonic above N/2 is
//! read as `N - n'`. A ring resolves the harmonics `0..=n_max` without confusing them only
//! if no harmonic in the field reaches `N - n_max`; hence the rule `N >= 2 n_max + 1`
//! ([`RingDft::new`]), which at least keeps `0..=n_max` distinct from each other.
//!
//! The tables of cosines and sines are computed once; [`RingDft::transform`] allocates nothing
//! (it runs at every output sample of a rolling run).

use crate::{Error, Result};

/// The discrete Fourier series of `N` equally spaced ring points, harmonics `0..=n_max`.
#[derive(Clone, Debug)]
pub struct RingDft {
    /// Points on the ring.
    points: usize,
    /// Highest harmonic.
    n_max: usize,
    /// `w_n cos(n theta_k)` at `[n * points + k]`, with `w_n` the series' weight of n.
    cos_table: Vec<f64>,
    /// `w_n sin(n theta_k)`, same layout.
    sin_table: Vec<f64>,
}

impl RingDft {
    /// The series of `points` points at `theta_0 + 2 pi k / points` (rad), harmonics
    /// `0..=n_max`. Refused unless `points >= 2 n_max + 1` (module docs).
    pub fn new(points: usize, theta0_rad: f64, n_max: usize) -> Result<RingDft> {
        if points < 2 * n_max + 1 {
            return Err(Error::input(
                "ring",
                "nodes",
                format!(
                    "a ring resolving the harmonics 0..={n_max} needs at least {} points \
                     (2 n_max + 1), got {points}",
                    2 * n_max + 1
                ),
            ));
        }
        let mut cos_table = vec![0.0; (n_max + 1) * points];
        let mut sin_table = vec![0.0; (n_max + 1) * points];
        for n in 0..=n_max {
            // 1/N for the mean, 2/N for the others (n < N/2 by the rule above).
            let weight = if n == 0 {
                1.0 / points as f64
            } else {
                2.0 / points as f64
            };
            for k in 0..points {
                let theta = theta0_rad + 2.0 * std::f64::consts::PI * k as f64 / points as f64;
                let (s, c) = (n as f64 * theta).sin_cos();
                cos_table[n * points + k] = weight * c;
                sin_table[n * points + k] = weight * s;
            }
        }
        Ok(RingDft {
            points,
            n_max,
            cos_table,
            sin_table,
        })
    }

    /// Points on the ring.
    pub fn points(&self) -> usize {
        self.points
    }

    /// Highest harmonic.
    pub fn n_max(&self) -> usize {
        self.n_max
    }

    /// The cosine and sine parts `c_n`, `s_n` (n = 0..=n_max) of the values `f_k` at the ring's
    /// points, into `cos_out` and `sin_out` (each `n_max + 1` long; `s_0` is 0).
    ///
    /// # Panics
    /// If the slices have other lengths (a programming error: the caller sizes them once).
    pub fn transform(&self, values: &[f64], cos_out: &mut [f64], sin_out: &mut [f64]) {
        assert_eq!(values.len(), self.points, "one value per ring point");
        assert_eq!(cos_out.len(), self.n_max + 1);
        assert_eq!(sin_out.len(), self.n_max + 1);
        for n in 0..=self.n_max {
            let row = n * self.points..(n + 1) * self.points;
            let (mut c, mut s) = (0.0, 0.0);
            for ((f, wc), ws) in values
                .iter()
                .zip(&self.cos_table[row.clone()])
                .zip(&self.sin_table[row])
            {
                c += f * wc;
                s += f * ws;
            }
            cos_out[n] = c;
            sin_out[n] = s;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// The field `sum_j (A_j cos(n_j theta) + B_j sin(n_j theta))` on the ring.
    fn field(points: usize, theta0: f64, terms: &[(usize, f64, f64)]) -> Vec<f64> {
        (0..points)
            .map(|k| {
                let theta = theta0 + 2.0 * PI * k as f64 / points as f64;
                terms
                    .iter()
                    .map(|&(n, a, b)| a * (n as f64 * theta).cos() + b * (n as f64 * theta).sin())
                    .sum()
            })
            .collect()
    }

    fn harmonics(dft: &RingDft, values: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let mut c = vec![0.0; dft.n_max() + 1];
        let mut s = vec![0.0; dft.n_max() + 1];
        dft.transform(values, &mut c, &mut s);
        (c, s)
    }

    #[test]
    fn recovers_each_harmonic_of_a_known_field() {
        // Seeded random amplitudes on every harmonic 0..=10 of a 32-point ring at an offset
        // start angle: each (c_n, s_n) comes back to round-off (1e-12 on amplitudes of order
        // 1: sums of 32 products).
        let mut rng = crate::random::XorShift64::seeded(57);
        let theta0 = 0.3;
        let terms: Vec<(usize, f64, f64)> = (0..=10)
            .map(|n| {
                let a = rng.centred_uniform();
                let b = if n == 0 { 0.0 } else { rng.centred_uniform() };
                (n, a, b)
            })
            .collect();
        let dft = RingDft::new(32, theta0, 10).unwrap();
        let (c, s) = harmonics(&dft, &field(32, theta0, &terms));
        for &(n, a, b) in &terms {
            assert!((c[n] - a).abs() < 1e-12, "c_{n} {} against {a}", c[n]);
            assert!((s[n] - b).abs() < 1e-12, "s_{n} {} against {b}", s[n]);
        }
    }

    #[test]
    fn the_amplitude_does_not_depend_on_where_the_pattern_stands() {
        // cos(4 (theta - phase)) for several phases: sqrt(c_4^2 + s_4^2) = 1, nothing else.
        let dft = RingDft::new(64, 0.0, 12).unwrap();
        for phase in [0.0, 0.1, 0.77, 2.0] {
            let values: Vec<f64> = (0..64)
                .map(|k| (4.0 * (2.0 * PI * k as f64 / 64.0 - phase)).cos())
                .collect();
            let (c, s) = harmonics(&dft, &values);
            assert!((c[4].hypot(s[4]) - 1.0).abs() < 1e-12);
            for n in (0..=12).filter(|&n| n != 4) {
                assert!(c[n].hypot(s[n]) < 1e-12, "n = {n} at phase {phase}");
            }
        }
    }

    #[test]
    fn a_harmonic_above_half_the_ring_aliases_to_n_minus_it() {
        // The aliasing bound: on 16 points, n' = 13 reads as 16 - 13 = 3, its sine part with
        // the opposite sign; n' = 16 reads as the mean. This is why a ring needs more points
        // than twice the highest harmonic a run excites.
        let dft = RingDft::new(16, 0.0, 7).unwrap();
        let (c, s) = harmonics(&dft, &field(16, 0.0, &[(13, 0.5, 0.25)]));
        assert!((c[3] - 0.5).abs() < 1e-12);
        assert!((s[3] + 0.25).abs() < 1e-12);
        let (c, _) = harmonics(&dft, &field(16, 0.0, &[(16, 2.0, 0.0)]));
        assert!((c[0] - 2.0).abs() < 1e-12);
    }

    #[test]
    fn too_few_points_for_the_harmonics_are_refused() {
        let e = RingDft::new(20, 0.0, 10).unwrap_err();
        assert!(e.to_string().contains("at least 21 points"), "{e}");
        assert_eq!(e.exit_code(), 2);
        assert!(RingDft::new(21, 0.0, 10).is_ok());
    }
}
