// Dense reference kernels index rows and columns the way the formulas read.
#![allow(clippy::needless_range_loop)]

//! Both sparse eigen solvers (the 3D block Lanczos, `modal::solve`, and the axisymmetric
//! solver's Lanczos, `modal::axisym::eigen::solve_below`) and the Sturm count they share
//! (`modal::inertia`, on simplicial and supernodal factors) against one dense reference on
//! seeded random FE-like pencils: `M = L Lᵀ` by a plain Cholesky, `C = L⁻¹ K L⁻ᵀ`, eigenvalues
//! of `C` by cyclic Jacobi rotations, all written here without faer.

mod jacobi;

use std::f64::consts::PI;
use std::sync::Arc;

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, SymmetricOrdering,
};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::{SparseColMat, Triplet};
use faer::{Par, Side};
use squeal::linalg::inertia::negative_pivots;
use squeal::modal::axisym::eigen::{
    amd_order, solve_below, EigenSettings, Pattern, PencilMatrices,
};
use squeal::modal::{solve, ModalOptions};

use jacobi::jacobi_eigenvalues;

/// A random FE-like pencil: `n` dofs in a chain with springs to the next dof and to one a few
/// places on (like element couplings), each spring adding `k (e_i - e_j)(e_i - e_j)ᵀ` to K and
/// a consistent two-node mass `m / 6 [[2, 1], [1, 2]]` to M, plus a few ground springs and a
/// lumped mass per dof (M positive definite, K positive definite: every dof reaches ground).
struct Pencil {
    n: usize,
    /// Upper-triangle pairs `(i, j)`, `i <= j`, with K and M values (duplicates summed).
    pairs: Vec<(usize, usize)>,
    k: Vec<f64>,
    m: Vec<f64>,
}

fn xorshift(state: &mut u64) -> f64 {
    *state ^= *state << 13;
    *state ^= *state >> 7;
    *state ^= *state << 17;
    (*state >> 11) as f64 / (1u64 << 53) as f64
}

impl Pencil {
    fn random(n: usize, seed: u64) -> Pencil {
        Pencil::graded(n, seed, 2.0)
    }

    /// As [`Pencil::random`] with spring stiffnesses spread over `decades` decades from 1e6 N/m.
    fn graded(n: usize, seed: u64, decades: f64) -> Pencil {
        let mut s = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
        let mut p = Pencil {
            n,
            pairs: Vec::new(),
            k: Vec::new(),
            m: Vec::new(),
        };
        let add = |p: &mut Pencil, i: usize, j: usize, k: f64, m: f64| {
            let (a, b) = (i.min(j), i.max(j));
            p.pairs.push((a, b));
            p.k.push(k);
            p.m.push(m);
        };
        for i in 0..n {
            // Lumped mass 0.5-1.5 kg per dof.
            add(&mut p, i, i, 0.0, 0.5 + xorshift(&mut s));
            let reach = 1 + (xorshift(&mut s) * 7.0) as usize;
            for j in [i + 1, i + reach + 1] {
                if j >= n {
                    continue;
                }
                // Springs 1e6-1e8 N/m: frequencies from tens of Hz to a few kHz.
                let k = 10f64.powf(6.0 + decades * xorshift(&mut s));
                let m = 0.3 * xorshift(&mut s);
                add(&mut p, i, i, k, m / 3.0);
                add(&mut p, j, j, k, m / 3.0);
                add(&mut p, i, j, -k, m / 6.0);
            }
            if i % 17 == 0 {
                add(&mut p, i, i, 1e6 * (1.0 + xorshift(&mut s)), 0.0);
            }
        }
        p
    }

    fn dense(&self) -> (Vec<Vec<f64>>, Vec<Vec<f64>>) {
        let mut k = vec![vec![0.0; self.n]; self.n];
        let mut m = vec![vec![0.0; self.n]; self.n];
        for (t, &(i, j)) in self.pairs.iter().enumerate() {
            k[i][j] += self.k[t];
            m[i][j] += self.m[t];
            if i != j {
                k[j][i] += self.k[t];
                m[j][i] += self.m[t];
            }
        }
        (k, m)
    }

    /// Lower triangles as faer matrices (the 3D solver's input).
    fn lower(&self) -> (SparseColMat<usize, f64>, SparseColMat<usize, f64>) {
        let tri = |v: &[f64]| -> Vec<Triplet<usize, usize, f64>> {
            self.pairs
                .iter()
                .zip(v)
                .map(|(&(i, j), &x)| Triplet::new(j, i, x))
                .collect()
        };
        let k = SparseColMat::try_new_from_triplets(self.n, self.n, &tri(&self.k)).unwrap();
        let m = SparseColMat::try_new_from_triplets(self.n, self.n, &tri(&self.m)).unwrap();
        (k, m)
    }
}

/// Eigenvalues of the dense pencil, ascending: Cholesky of M, `C = L⁻¹ K L⁻ᵀ`, cyclic Jacobi
/// (tests/jacobi).
fn dense_eigenvalues(k: &[Vec<f64>], m: &[Vec<f64>]) -> Vec<f64> {
    let n = k.len();
    let mut l = vec![vec![0.0; n]; n];
    for j in 0..n {
        let d = m[j][j] - (0..j).map(|p| l[j][p] * l[j][p]).sum::<f64>();
        assert!(d > 0.0, "M not positive definite");
        l[j][j] = d.sqrt();
        for i in j + 1..n {
            l[i][j] = (m[i][j] - (0..j).map(|p| l[i][p] * l[j][p]).sum::<f64>()) / l[j][j];
        }
    }
    // Y = L⁻¹ K (forward substitution per column), then C = L⁻¹ Yᵀ (K symmetric).
    let forward = |b: &[f64]| -> Vec<f64> {
        let mut x = vec![0.0; n];
        for i in 0..n {
            x[i] = (b[i] - (0..i).map(|p| l[i][p] * x[p]).sum::<f64>()) / l[i][i];
        }
        x
    };
    let y: Vec<Vec<f64>> = (0..n).map(|c| forward(&k[c])).collect(); // y[c] = L⁻¹ K e_c
    let mut a = vec![vec![0.0; n]; n];
    for i in 0..n {
        let row: Vec<f64> = (0..n).map(|c| y[c][i]).collect(); // (L⁻¹ K)[i, :]
        let col = forward(&row); // L⁻¹ (L⁻¹ K)ᵀ e_i
        for (r, v) in col.into_iter().enumerate() {
            a[r][i] = v;
        }
    }
    for i in 0..n {
        for j in 0..i {
            let s = 0.5 * (a[i][j] + a[j][i]);
            a[i][j] = s;
            a[j][i] = s;
        }
    }
    jacobi_eigenvalues(a)
}

/// A band edge halfway between the reference eigenvalues `count - 1` and `count` (so that no
/// solver meets an eigenvalue on the edge).
fn edge_between(reference: &[f64], count: usize) -> f64 {
    0.5 * (reference[count - 1] + reference[count])
}

// Why 1e-9: both solvers accept a mode at a relative residual of 1e-8 or better; for a
// symmetric pencil the eigenvalue error is at most the residual and in practice its square
// (Rayleigh quotient), while the Jacobi reference is accurate to ~1e-13 of the largest
// eigenvalue, i.e. ~1e-11 relative for the band's lowest (a spread of about 100 in lambda).
const EIGENVALUE_TOLERANCE: f64 = 1e-9;

#[test]
fn both_lanczos_solvers_match_the_dense_reference_on_random_pencils() {
    for (seed, n, wanted) in [(1u64, 240usize, 30usize), (2, 300, 45), (3, 260, 12)] {
        let pencil = Pencil::random(n, seed);
        let (kd, md) = pencil.dense();
        let reference = dense_eigenvalues(&kd, &md);
        let lambda_max = edge_between(&reference, wanted);

        // The 3D block Lanczos (n >= 200: not its dense path).
        let (k, m) = pencil.lower();
        let opts = ModalOptions {
            fmax_hz: lambda_max.sqrt() / (2.0 * PI),
            rigid_below_hz: 0.0,
            ..ModalOptions::default()
        };
        let sol = solve(&k, &m, &opts).unwrap();
        assert_eq!(sol.sturm_count, Some(wanted), "seed {seed}: 3D Sturm count");
        assert_eq!(sol.modes.len(), wanted, "seed {seed}: 3D modes");
        let mut worst_3d: f64 = 0.0;
        for (mode, &r) in sol.modes.iter().zip(&reference) {
            worst_3d = worst_3d.max((mode.eigenvalue / r - 1.0).abs());
        }

        // The axisymmetric solver's Lanczos on the same pencil.
        let perm_inv = amd_order(n, pencil.pairs.clone()).unwrap();
        let pattern = Arc::new(Pattern::new(n, &pencil.pairs, perm_inv).unwrap());
        let matrices = PencilMatrices::from_values(pattern, &pencil.k, &pencil.m);
        let settings = EigenSettings {
            lambda_max,
            sigma: -0.05 * lambda_max,
            ritz_tolerance: 1e-10,
        };
        let result = solve_below(&matrices, &settings, &[]).unwrap();
        assert_eq!(
            result.sturm_count, wanted,
            "seed {seed}: axisym Sturm count"
        );
        assert_eq!(result.values.len(), wanted, "seed {seed}: axisym modes");
        let mut worst_axi: f64 = 0.0;
        for (&v, &r) in result.values.iter().zip(&reference) {
            worst_axi = worst_axi.max((v / r - 1.0).abs());
        }
        println!(
            "seed {seed}, n {n}, {wanted} modes: worst relative eigenvalue error 3D {worst_3d:.1e}, \
             axisymmetric {worst_axi:.1e}"
        );
        assert!(worst_3d < EIGENVALUE_TOLERANCE, "3D: {worst_3d:e}");
        assert!(worst_axi < EIGENVALUE_TOLERANCE, "axisym: {worst_axi:e}");
    }
}

#[test]
fn sturm_counts_of_both_factor_storages_match_the_dense_inertia() {
    let pencil = Pencil::random(260, 7);
    let (kd, md) = pencil.dense();
    let reference = dense_eigenvalues(&kd, &md);
    let (k, m) = pencil.lower();
    for count in [1usize, 9, 40, 130, 259] {
        let sigma = edge_between(&reference, count);
        let mut t = Vec::new();
        for (a, scale) in [(&k, 1.0), (&m, -sigma)] {
            let cp = a.symbolic().col_ptr();
            let ri = a.symbolic().row_idx();
            for j in 0..a.ncols() {
                for p in cp[j]..cp[j + 1] {
                    t.push(Triplet::new(ri[p], j, scale * a.val()[p]));
                }
            }
        }
        let shifted = SparseColMat::try_new_from_triplets(260, 260, &t).unwrap();
        for threshold in [
            SupernodalThreshold::FORCE_SIMPLICIAL,
            SupernodalThreshold::FORCE_SUPERNODAL,
        ] {
            let params = CholeskySymbolicParams {
                supernodal_flop_ratio_threshold: threshold,
                ..Default::default()
            };
            let symbolic = factorize_symbolic_cholesky(
                shifted.symbolic(),
                Side::Lower,
                SymmetricOrdering::Amd,
                params,
            )
            .unwrap();
            let mut l_values = vec![0.0; symbolic.len_val()];
            let mut mem = MemBuffer::new(
                symbolic.factorize_numeric_ldlt_scratch::<f64>(Par::Seq, Default::default()),
            );
            symbolic
                .factorize_numeric_ldlt(
                    &mut l_values,
                    shifted.as_ref(),
                    Side::Lower,
                    Default::default(),
                    Par::Seq,
                    MemStack::new(&mut mem),
                    Default::default(),
                )
                .unwrap();
            let negative = negative_pivots(&symbolic, &l_values, sigma).unwrap();
            assert_eq!(
                negative, count,
                "{threshold:?} at the edge above {count} eigenvalues"
            );
        }
        // The 3D solver's own Sturm count (its symbolic analysis and factor) agrees too.
        assert_eq!(
            squeal::modal::lanczos::sturm_count(&k, &m, sigma).unwrap(),
            count
        );
    }
}

/// A badly graded but valid pencil (spring stiffnesses over eight decades): the low modes'
/// residuals cannot go below their rounding floor, which lies above the 1e-8 tolerance. They
/// are accepted (within `FLOOR_FACTOR` times the floor) and their eigenvalues agree with the
/// dense reference as far as its own rounding allows.
#[test]
fn modes_at_their_rounding_floor_are_accepted_and_right() {
    use squeal::modal::residual::FLOOR_FACTOR;
    let pencil = Pencil::graded(300, 11, 8.0);
    let (kd, md) = pencil.dense();
    let reference = dense_eigenvalues(&kd, &md);
    let (k, m) = pencil.lower();
    let opts = ModalOptions {
        fmax_hz: edge_between(&reference, 20).sqrt() / (2.0 * PI),
        rigid_below_hz: 0.0,
        ..ModalOptions::default()
    };
    let sol = solve(&k, &m, &opts).unwrap();
    assert_eq!(sol.modes.len(), 20);
    let above_tolerance = sol
        .modes
        .iter()
        .filter(|m| m.residual > opts.residual_tolerance)
        .count();
    // Measured: the worst residual 9.2e-8 at a floor of 9.1e-8, so a fixed 1e-8 would refuse.
    assert!(above_tolerance > 0, "the case no longer tests the floor");
    let lambda_top = reference.last().copied().unwrap();
    let mut worst: f64 = 0.0;
    for (mode, &r) in sol.modes.iter().zip(&reference) {
        assert!(mode.residual <= FLOOR_FACTOR * mode.residual_floor || mode.residual <= 1e-8);
        // The dense reference is exact to about u |C| = u lambda_top per eigenvalue (Jacobi
        // is backward stable), so compare on that scale: 1e3 u lambda_top.
        let error = (mode.eigenvalue - r).abs();
        worst = worst.max(error / (f64::EPSILON * lambda_top));
        assert!(
            error <= 1e3 * f64::EPSILON * lambda_top,
            "{} vs {r}",
            mode.eigenvalue
        );
    }
    println!(
        "{above_tolerance} of 20 modes above the 1e-8 tolerance, all within {FLOOR_FACTOR} times \
         their floor; largest eigenvalue difference {worst:.1} u lambda_max"
    );
}
