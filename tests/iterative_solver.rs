//! The iterative solver (`squeal::linalg::iterative`): the block product against dense arithmetic on
//! seeded random matrices, conjugate gradients with the two-level preconditioner against an
//! element-by-element residual on a clamped, graded elastic beam, the preconditioner's effect
//! against block-Jacobi-free CG, thread-count independence, and the error paths.

use squeal::fem::hex8::element_matrices;
use squeal::linalg::iterative::block_matrix::Block3;
use squeal::linalg::iterative::pcg::{dot, Identity};
use squeal::linalg::iterative::{
    conjugate_gradients, BlockMatrix, PcgOptions, TwoLevel, TwoLevelOptions,
};
use squeal::material::Material;
use squeal::mesh::hex::structured;
use squeal::random::XorShift64;
use std::collections::BTreeMap;

mod common;

/// A hexahedral beam `[0, L] x [0, 0.1] x [0, 0.1]` m, `nx x ny x nz` elements, graded along x
/// (element lengths growing geometrically by `grading` over the length), clamped at x = 0,
/// with its element stiffnesses; nodes numbered x-fastest.
struct Beam {
    coords: Vec<[f64; 3]>,
    held: Vec<[bool; 3]>,
    elements: Vec<([usize; 8], [[f64; 24]; 24])>,
    nodes_x: usize,
}

fn beam(nx: usize, ny: usize, nz: usize, length_m: f64, grading: f64) -> Beam {
    let ratio = grading.powf(1.0 / (nx.max(2) - 1) as f64);
    let mut xs = vec![0.0];
    let first = if grading == 1.0 {
        length_m / nx as f64
    } else {
        length_m * (ratio - 1.0) / (ratio.powi(nx as i32) - 1.0)
    };
    for i in 0..nx {
        xs.push(xs[i] + first * ratio.powi(i as i32));
    }
    let (px, py, pz) = (nx + 1, ny + 1, nz + 1);
    let id = |i: usize, j: usize, k: usize| i + px * (j + py * k);
    let mut coords = vec![[0.0; 3]; px * py * pz];
    let mut held = vec![[false; 3]; px * py * pz];
    for k in 0..pz {
        for j in 0..py {
            for i in 0..px {
                coords[id(i, j, k)] = [
                    xs[i],
                    0.1 * j as f64 / ny as f64,
                    0.1 * k as f64 / nz as f64,
                ];
                held[id(i, j, k)] = [i == 0; 3];
            }
        }
    }
    let mut elements = Vec::new();
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                // VTK order: bottom face counter-clockwise, then the top face.
                let nodes = structured(i, j, k, id);
                let x = nodes.map(|n| coords[n]);
                let em = element_matrices(&x, &Material::steel(), true).expect("valid element");
                elements.push((nodes, em.k));
            }
        }
    }
    Beam {
        coords,
        held,
        elements,
        nodes_x: px,
    }
}

impl Beam {
    /// The assembled matrix; held directions decoupled with a unit-scaled diagonal, as the
    /// static tangent holds them.
    fn matrix(&self) -> BlockMatrix {
        let n = self.coords.len();
        let mut blocks: BTreeMap<(usize, usize), Block3> = BTreeMap::new();
        for (nodes, k) in &self.elements {
            for a in 0..8 {
                for b in 0..8 {
                    let (r, c) = (nodes[a], nodes[b]);
                    if r < c {
                        continue;
                    }
                    let e = blocks.entry((c, r)).or_insert([[0.0; 3]; 3]);
                    for d in 0..3 {
                        for i in 0..3 {
                            if !self.held[r][d] && !self.held[c][i] {
                                e[d][i] += k[3 * a + d][3 * b + i];
                            }
                        }
                    }
                }
            }
        }
        let scale = 1e9;
        for r in 0..n {
            for d in 0..3 {
                if self.held[r][d] {
                    blocks.get_mut(&(r, r)).expect("diagonal")[d][d] = scale;
                }
            }
        }
        let (mut col_ptr, mut rows, mut values) = (vec![0usize], Vec::new(), Vec::new());
        let mut it = blocks.iter().peekable();
        for c in 0..n {
            while let Some(((cc, r), b)) = it.peek() {
                if *cc != c {
                    break;
                }
                rows.push(*r as u32);
                values.push(**b);
                it.next();
            }
            col_ptr.push(rows.len());
        }
        BlockMatrix::from_lower_columns(n, &col_ptr, &rows, &values).expect("valid pattern")
    }

    /// `b - A x` by elements (the slow reference the assembled product is checked against).
    fn residual(&self, x: &[f64], b: &[f64]) -> Vec<f64> {
        let mut r = b.to_vec();
        for (nodes, k) in &self.elements {
            for a in 0..8 {
                for d in 0..3 {
                    if self.held[nodes[a]][d] {
                        continue;
                    }
                    let mut s = 0.0;
                    for c in 0..8 {
                        for i in 0..3 {
                            if !self.held[nodes[c]][i] {
                                s += k[3 * a + d][3 * c + i] * x[3 * nodes[c] + i];
                            }
                        }
                    }
                    r[3 * nodes[a] + d] -= s;
                }
            }
        }
        for (n, h) in self.held.iter().enumerate() {
            for d in 0..3 {
                if h[d] {
                    r[3 * n + d] -= 1e9 * x[3 * n + d];
                }
            }
        }
        r
    }

    /// A tip load (N, z) spread over the free end's nodes.
    fn tip_load(&self, total_n: f64) -> Vec<f64> {
        let mut f = vec![0.0; 3 * self.coords.len()];
        let tip: Vec<usize> = (0..self.coords.len())
            .filter(|n| n % self.nodes_x == self.nodes_x - 1)
            .collect();
        for &n in &tip {
            f[3 * n + 2] = total_n / tip.len() as f64;
        }
        f
    }
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

#[test]
fn block_product_matches_dense_on_seeded_random_matrices() {
    let mut rng = XorShift64::seeded(7);
    for &n in &[1usize, 2, 5, 17, 40] {
        // Sparse random symmetric: each lower block present with probability 0.3.
        let mut dense = vec![0.0; 9 * n * n];
        for c in 0..n {
            for r in c..n {
                if r != c && rng.below(10) >= 3 {
                    continue;
                }
                for d in 0..3 {
                    for i in 0..3 {
                        let v = rng.centred_uniform();
                        let (row, col) = (3 * r + d, 3 * c + i);
                        if r == c && d < i {
                            continue;
                        }
                        dense[row + 3 * n * col] = v;
                        dense[col + 3 * n * row] = v;
                    }
                }
            }
        }
        let a = BlockMatrix::from_dense(n, &dense).expect("dense");
        let x: Vec<f64> = (0..3 * n).map(|_| rng.centred_uniform()).collect();
        let mut y = vec![0.0; 3 * n];
        a.apply(&x, &mut y);
        for row in 0..3 * n {
            let want: f64 = (0..3 * n)
                .map(|col| dense[row + 3 * n * col] * x[col])
                .sum();
            // Same products, another summation order: rounding only.
            assert!(
                (y[row] - want).abs() <= 1e-13 * (1.0 + want.abs()),
                "n {n} row {row}"
            );
        }
    }
}

#[test]
fn block_matrix_refuses_bad_patterns() {
    let b = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let cases: [(&[usize], &[u32], usize, &str); 4] = [
        (&[0, 1, 2], &[0, 0], 2, "rows must lie in [1, 2)"),
        (&[0, 1, 2], &[1, 1], 2, "column 0 has no diagonal block"),
        (&[0, 2, 3], &[0, 0, 1], 2, "repeated column"),
        (&[0, 1, 3], &[0, 1, 2], 2, "rows must lie in [1, 2)"),
    ];
    for (col_ptr, rows, n, message) in cases {
        let blocks = vec![b; rows.len()];
        let err = BlockMatrix::from_lower_columns(n, col_ptr, rows, &blocks)
            .expect_err("a bad pattern")
            .to_string();
        assert!(err.contains(message), "{err}");
    }
}

/// Solves the clamped beam with the two-level preconditioner and with none; returns the two
/// iteration counts after checking both solutions against the element-by-element residual.
fn solve_beam(nx: usize, ny: usize, nz: usize, grading: f64) -> (usize, usize) {
    let beam = beam(nx, ny, nz, 1.0, grading);
    let a = beam.matrix();
    let b = beam.tip_load(1e4);
    let opts = PcgOptions {
        tolerance: 1e-10,
        max_iterations: 20_000,
    };
    let mut pre =
        TwoLevel::new(&a, &beam.coords, &beam.held, &TwoLevelOptions::default()).expect("set-up");
    let mut x = vec![0.0; b.len()];
    let two_level = conjugate_gradients(&a, &b, &mut x, &mut pre, &opts).expect("converges");
    // The recurrence's residual is 1e-10; the true one (by elements, another summation) may
    // drift from it by rounding, a few digits at most on a matrix of condition ~1e8.
    let true_relative = norm(&beam.residual(&x, &b)) / norm(&b);
    assert!(
        true_relative < 1e-8,
        "two-level residual {true_relative:.3e}"
    );
    let mut y = vec![0.0; b.len()];
    let plain = conjugate_gradients(&a, &b, &mut y, &mut Identity, &opts).expect("converges");
    let true_relative = norm(&beam.residual(&y, &b)) / norm(&b);
    assert!(true_relative < 1e-8, "plain residual {true_relative:.3e}");
    // The two solutions agree to the solve's accuracy (the tip deflection, relative).
    let diff: Vec<f64> = x.iter().zip(&y).map(|(p, q)| p - q).collect();
    assert!(
        norm(&diff) < 1e-6 * norm(&x),
        "solutions differ by {:.3e}",
        norm(&diff) / norm(&x)
    );
    eprintln!(
        "beam {nx}x{ny}x{nz}, grading {grading}: two-level {} iterations ({:?}), plain CG {}",
        two_level.iterations,
        pre.stats(),
        plain.iterations
    );
    (two_level.iterations, plain.iterations)
}

#[test]
fn two_level_cg_solves_a_clamped_graded_beam() {
    let (two_level, plain) = solve_beam(40, 4, 4, 10.0);
    assert!(
        two_level * 10 < plain,
        "two-level {two_level}, plain {plain}"
    );
}

#[test]
fn two_level_iterations_grow_slowly_under_refinement() {
    let (coarse_mesh, _) = solve_beam(20, 2, 2, 1.0);
    let (fine_mesh, _) = solve_beam(40, 4, 4, 1.0);
    assert!(fine_mesh < 2 * coarse_mesh, "{coarse_mesh} -> {fine_mesh}");
}

#[test]
fn two_level_cg_does_not_depend_on_the_thread_count() {
    let beam = beam(24, 3, 3, 1.0, 5.0);
    let a = beam.matrix();
    let b = beam.tip_load(1e4);
    let run = |threads: usize| {
        common::on_threads(threads, || {
            let mut pre =
                TwoLevel::new(&a, &beam.coords, &beam.held, &TwoLevelOptions::default()).unwrap();
            let mut x = vec![0.0; b.len()];
            let opts = PcgOptions {
                tolerance: 1e-9,
                max_iterations: 1000,
            };
            let report = conjugate_gradients(&a, &b, &mut x, &mut pre, &opts).unwrap();
            (x, report.iterations)
        })
    };
    let (x1, i1) = run(1);
    let (x3, i3) = run(3);
    assert_eq!(i1, i3);
    assert!(x1.iter().zip(&x3).all(|(p, q)| p.to_bits() == q.to_bits()));
}

#[test]
fn iterative_solver_error_paths() {
    // A negative diagonal: not positive definite, named at set-up.
    let mut dense = vec![0.0; 9 * 4];
    for i in 0..6 {
        dense[i + 6 * i] = if i == 4 { -1.0 } else { 2.0 };
    }
    let a = BlockMatrix::from_dense(2, &dense).unwrap();
    let err = TwoLevel::new(
        &a,
        &[[0.0; 3], [1.0, 0.0, 0.0]],
        &[[false; 3]; 2],
        &Default::default(),
    )
    .err()
    .expect("refused")
    .to_string();
    assert!(
        err.contains("node 1") && err.contains("positive definite"),
        "{err}"
    );
    // Too few iterations: an error that names the residual reached.
    let beam = beam(16, 2, 2, 1.0, 1.0);
    let a = beam.matrix();
    let b = beam.tip_load(1.0);
    let mut x = vec![0.0; b.len()];
    let opts = PcgOptions {
        tolerance: 1e-12,
        max_iterations: 3,
    };
    let err = conjugate_gradients(&a, &b, &mut x, &mut Identity, &opts)
        .expect_err("not converged")
        .to_string();
    assert!(
        err.contains("in 3 iterations") && err.contains("reached"),
        "{err}"
    );
    // Bad tolerance and sizes.
    let opts = PcgOptions {
        tolerance: 0.0,
        max_iterations: 3,
    };
    assert!(conjugate_gradients(&a, &b, &mut x, &mut Identity, &opts).is_err());
    let mut short = vec![0.0; 3];
    let opts = PcgOptions {
        tolerance: 1e-6,
        max_iterations: 3,
    };
    let err = conjugate_gradients(&a, &b, &mut short, &mut Identity, &opts)
        .expect_err("sizes")
        .to_string();
    assert!(err.contains("entries for"), "{err}");
    // An indefinite matrix breaks CG down with a diagnosis.
    let mut dense = vec![0.0; 9];
    for (i, v) in [1.0, -1.0, 1.0].iter().enumerate() {
        dense[i + 3 * i] = *v;
    }
    let a = BlockMatrix::from_dense(1, &dense).unwrap();
    let b = vec![0.0, 1.0, 0.0];
    let mut x = vec![0.0; 3];
    let err = conjugate_gradients(&a, &b, &mut x, &mut Identity, &opts)
        .expect_err("indefinite")
        .to_string();
    assert!(err.contains("not positive definite"), "{err}");
    assert!(dot(&b, &b) > 0.0);
}
