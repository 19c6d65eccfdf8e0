//! A complex banded matrix and its LU factorisation with partial pivoting, for the rail's
//! direct frequency-response solves `(K + i w C - w^2 M) u = f`.
//!
//! Storage and algorithm as LAPACK's `zgbtrf` / `zgbtrs` (Golub & Van Loan, Matrix
//! Computations, 4th ed., section 4.3.5): row i holds columns `i - kl ..= i + ku + kl` (row
//! exchanges widen the upper band by kl); the multipliers of column k stay in rows
//! `k+1 ..= k+kl` of that column and the row exchanges are applied to the right-hand side in
//! the order they were made. The dynamic stiffness of an undamped stretch of rail is
//! indefinite, so pivoting is needed: without it a leading block at its own resonance would
//! give a zero pivot.

// Index loops mirror the matrix formulas term by term.
#![allow(clippy::needless_range_loop)]

use faer::c64;

use crate::{Error, Result};

/// A square complex band matrix (lower bandwidth kl, upper ku).
#[derive(Clone, Debug)]
pub struct BandMatrix {
    n: usize,
    kl: usize,
    ku: usize,
    width: usize,
    data: Vec<c64>,
}

impl BandMatrix {
    /// Zero n x n matrix with bandwidths kl (below) and ku (above the diagonal).
    pub fn zeros(n: usize, kl: usize, ku: usize) -> BandMatrix {
        let width = 2 * kl + ku + 1;
        BandMatrix {
            n,
            kl,
            ku,
            width,
            data: vec![c64::new(0.0, 0.0); n * width],
        }
    }

    /// Order n.
    pub fn order(&self) -> usize {
        self.n
    }

    fn index(&self, i: usize, j: usize) -> usize {
        i * self.width + (j + self.kl - i)
    }

    /// Adds `v` at (i, j); errors when (i, j) lies outside the band.
    pub fn add(&mut self, i: usize, j: usize, v: c64) -> Result<()> {
        if i >= self.n || j >= self.n || j + self.kl < i || j > i + self.ku {
            return Err(Error::Numerical(format!(
                "band matrix: entry ({i}, {j}) outside the band (n {}, kl {}, ku {})",
                self.n, self.kl, self.ku
            )));
        }
        let k = self.index(i, j);
        self.data[k] += v;
        Ok(())
    }

    /// Solves `A x = b` in place (A is consumed by the factorisation). Errors on a zero pivot
    /// (a singular matrix).
    pub fn solve(mut self, b: &mut [c64]) -> Result<()> {
        let (n, kl, ku) = (self.n, self.kl, self.ku);
        assert_eq!(b.len(), n, "right-hand side length");
        let mut pivots = vec![0usize; n];
        for k in 0..n {
            let last = (k + kl).min(n - 1);
            let mut p = k;
            let mut best = self.data[self.index(k, k)].norm();
            for i in k + 1..=last {
                let v = self.data[self.index(i, k)].norm();
                if v > best {
                    best = v;
                    p = i;
                }
            }
            if best == 0.0 {
                return Err(Error::Numerical(format!(
                    "band matrix: singular (column {k} has no pivot)"
                )));
            }
            pivots[k] = p;
            let right = (k + kl + ku).min(n - 1);
            if p != k {
                for j in k..=right {
                    let (a, c) = (self.index(k, j), self.index(p, j));
                    self.data.swap(a, c);
                }
            }
            let pivot = self.data[self.index(k, k)];
            for i in k + 1..=last {
                let ik = self.index(i, k);
                let l = self.data[ik] / pivot;
                self.data[ik] = l;
                if l == c64::new(0.0, 0.0) {
                    continue;
                }
                for j in k + 1..=right {
                    let (ij, kj) = (self.index(i, j), self.index(k, j));
                    let u = self.data[kj];
                    self.data[ij] -= l * u;
                }
            }
        }
        // Forward: the row exchanges and multipliers in their order.
        for k in 0..n {
            if pivots[k] != k {
                b.swap(k, pivots[k]);
            }
            let bk = b[k];
            for i in k + 1..=(k + kl).min(n - 1) {
                b[i] -= self.data[self.index(i, k)] * bk;
            }
        }
        // Backward with U (upper bandwidth kl + ku).
        for k in (0..n).rev() {
            let mut s = b[k];
            for j in k + 1..=(k + kl + ku).min(n - 1) {
                s -= self.data[self.index(k, j)] * b[j];
            }
            b[k] = s / self.data[self.index(k, k)];
        }
        Ok(())
    }
}
