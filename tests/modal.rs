//! Modal analysis: hex8 element, assembly, shift-invert Lanczos against analytic and dense
//! references, residuals, error paths, classification.

use std::collections::BTreeMap;
use std::f64::consts::PI;

use faer::{Mat, Side};
use squeal::analysis::identify::ModeFamily;
use squeal::fem::hex8::ElasticMaterial;
use squeal::fem::{assemble, Constraints, Hex8Kind, MassKind, Materials};
use squeal::mesh::cuboid;
use squeal::modal::classify::{classify_shape, nodal_weights};
use squeal::modal::{solve, ModalOptions};

fn steel_nu(nu: f64) -> Materials {
    let mut m = BTreeMap::new();
    m.insert(
        1,
        ElasticMaterial {
            poisson_ratio: nu,
            ..ElasticMaterial::steel()
        },
    );
    m
}

#[test]
fn patch_test_linear_field_has_no_interior_force() {
    let mut mesh = cuboid([2, 2, 2], [1.0, 1.0, 1.0], 1);
    let centre = 1 + 3 * (1 + 3); // node (1,1,1)
    mesh.nodes[centre] = [0.45, 0.55, 0.6]; // distorted interior node
    let a = assemble(
        &mesh,
        &steel_nu(0.3),
        &Constraints::default(),
        MassKind::Consistent,
        Hex8Kind::Standard,
    )
    .unwrap();
    let grad = [
        [1e-3, 2e-4, -3e-4],
        [5e-4, -2e-3, 1e-4],
        [0.0, 3e-4, 1.5e-3],
    ];
    let u: Vec<f64> = mesh
        .nodes
        .iter()
        .flat_map(|p| (0..3).map(move |c| (0..3).map(|k| grad[c][k] * p[k]).sum::<f64>()))
        .collect();
    let mut f = vec![0.0; u.len()];
    squeal::fem::assembly::sym_lower_matvec(&a.k, &u, &mut f);
    let scale = f.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    for c in 0..3 {
        // interior node: equilibrium of a constant stress state up to round-off
        assert!(
            f[3 * centre + c].abs() < 1e-10 * scale,
            "{}",
            f[3 * centre + c]
        );
    }
}

/// Axial modes of a clamped-free bar: f_k = (2k - 1) / (4 L) sqrt(E / rho). With nu = 0 the 3D
/// bar's axial motion is exactly one-dimensional, so the only error is the discretisation along
/// the bar, O(h²) (consistent mass: from above).
fn bar_axial_frequencies(n: usize) -> Vec<f64> {
    let l = 1.0;
    let mesh = cuboid([n, 1, 1], [l, 0.05, 0.05], 1);
    let a = assemble(
        &mesh,
        &steel_nu(0.0),
        &Constraints {
            clamped_sets: vec!["x0".into()],
            ties: false,
        },
        MassKind::Consistent,
        Hex8Kind::Standard,
    )
    .unwrap();
    let sol = solve(
        &a.k,
        &a.m,
        &ModalOptions {
            fmax_hz: 7000.0,
            ..Default::default()
        },
    )
    .unwrap();
    sol.modes
        .iter()
        .filter(|m| {
            let u = a.expand(&m.vector);
            let ex: f64 = u.iter().map(|v| v[0] * v[0]).sum();
            let et: f64 = u.iter().map(|v| v.iter().map(|c| c * c).sum::<f64>()).sum();
            ex > 0.99 * et
        })
        .map(|m| {
            assert!(m.residual < 1e-8);
            m.frequency_hz
        })
        .collect()
}

#[test]
fn clamped_free_bar_axial_modes_converge_to_analytic() {
    let c = (210e9f64 / 7850.0).sqrt();
    let exact: Vec<f64> = (1..=3).map(|k| (2 * k - 1) as f64 / 4.0 * c).collect();
    let coarse = bar_axial_frequencies(20);
    let fine = bar_axial_frequencies(40);
    assert!(coarse.len() >= 3 && fine.len() >= 3, "{coarse:?} {fine:?}");
    for k in 0..3 {
        let e1 = (coarse[k] - exact[k]) / exact[k];
        let e2 = (fine[k] - exact[k]) / exact[k];
        println!(
            "axial k={} exact {:.2} n=20 {:.2} ({:+.4}%) n=40 {:.2} ({:+.4}%)",
            k + 1,
            exact[k],
            coarse[k],
            100.0 * e1,
            fine[k],
            100.0 * e2
        );
        // O(h²): the error falls ~4x per halving; consistent mass errs high
        assert!(e2 > 0.0 && e1 > e2 && e1 / e2 > 3.5);
        // second-order error bound ((k pi h / 2L)²/... at most ~0.5 % for the third mode at n=40
        assert!(e2 < 5e-3);
    }
}

#[test]
fn free_cube_has_six_rigid_modes() {
    let mesh = cuboid([2, 2, 2], [1.0, 1.0, 1.0], 1);
    let a = assemble(
        &mesh,
        &steel_nu(0.3),
        &Constraints::default(),
        MassKind::Consistent,
        Hex8Kind::Standard,
    )
    .unwrap();
    let sol = solve(
        &a.k,
        &a.m,
        &ModalOptions {
            fmax_hz: 100.0,
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(
        sol.modes.len(),
        6,
        "{:?}",
        sol.modes.iter().map(|m| m.frequency_hz).collect::<Vec<_>>()
    );
    assert!(sol.modes.iter().all(|m| m.rigid && m.residual < 1e-8));
}

#[test]
fn solver_matches_dense_reference() {
    // 384 dofs: above the dense fallback (200), so the block Lanczos path is what is checked.
    let mesh = cuboid([8, 3, 3], [0.8, 0.15, 0.15], 1);
    let a = assemble(
        &mesh,
        &steel_nu(0.3),
        &Constraints {
            clamped_sets: vec!["x0".into()],
            ties: false,
        },
        MassKind::Consistent,
        Hex8Kind::Standard,
    )
    .unwrap();
    let n = a.n_reduced;
    let dense = |s: &faer::sparse::SparseColMat<usize, f64>| {
        let mut d = Mat::<f64>::zeros(n, n);
        let cp = s.symbolic().col_ptr();
        let ri = s.symbolic().row_idx();
        for j in 0..n {
            for p in cp[j]..cp[j + 1] {
                d[(ri[p], j)] = s.val()[p];
                d[(j, ri[p])] = s.val()[p];
            }
        }
        d
    };
    let (k, m) = (dense(&a.k), dense(&a.m));
    let l = m.llt(Side::Lower).unwrap().L().to_owned();
    let linv = l.as_ref().solve_lower_triangular_in_place_copy();
    let c = &linv * &k * linv.transpose();
    let ev = c.self_adjoint_eigenvalues(Side::Lower).unwrap();
    let f_ref: Vec<f64> = ev.iter().map(|l| l.sqrt() / (2.0 * PI)).collect();
    let fmax = 0.5 * (f_ref[29] + f_ref[30]);
    // One shift below the spectrum, and the band sliced into 2 and 5 (shifts inside the band,
    // indefinite LDLᵀ, Lanczos converging from both ends of the operator's spectrum): the same
    // 30 eigenvalues as the dense solve either way.
    for slices in [1, 2, 5] {
        let sol = solve(
            &a.k,
            &a.m,
            &ModalOptions {
                fmax_hz: fmax,
                slices,
                ..Default::default()
            },
        )
        .unwrap();
        assert_eq!(sol.modes.len(), 30, "{slices} slices");
        assert_eq!(sol.shifts.len(), slices, "every slice holds modes here");
        assert!(sol.shifts[1..].iter().all(|&s| s > 0.0));
        for (m, fr) in sol.modes.iter().zip(&f_ref) {
            let lam_ref = (2.0 * PI * fr).powi(2);
            assert!(
                (m.eigenvalue - lam_ref).abs() < 1e-8 * lam_ref,
                "{slices} slices: {} vs {}",
                m.frequency_hz,
                fr
            );
            assert!(m.residual < 1e-8);
        }
        assert_eq!(sol.sturm_count, Some(30));
    }
    // The Sturm count alone, between consecutive dense eigenvalues: exactly the number below.
    // Only where the two are distinct (1e-3 apart; the square bar has repeated pairs).
    let gaps: Vec<usize> = (1..f_ref.len())
        .filter(|&k| f_ref[k] - f_ref[k - 1] > 1e-3 * f_ref[k])
        .collect();
    assert!(gaps.len() > 20);
    for below in gaps.iter().step_by(gaps.len() / 6).copied() {
        let lambda = (2.0 * PI * 0.5 * (f_ref[below - 1] + f_ref[below])).powi(2);
        assert_eq!(
            squeal::modal::lanczos::sturm_count(&a.k, &a.m, lambda).unwrap(),
            below
        );
    }
}

trait LowerInv {
    fn solve_lower_triangular_in_place_copy(self) -> Mat<f64>;
}
impl LowerInv for faer::MatRef<'_, f64> {
    fn solve_lower_triangular_in_place_copy(self) -> Mat<f64> {
        let n = self.nrows();
        let mut x = Mat::<f64>::identity(n, n);
        faer::linalg::triangular_solve::solve_lower_triangular_in_place(
            self,
            x.as_mut(),
            faer::Par::Seq,
        );
        x
    }
}

#[test]
fn bad_band_and_bad_clamp_set_are_errors() {
    let mesh = cuboid([2, 1, 1], [0.2, 0.1, 0.1], 1);
    let err = assemble(
        &mesh,
        &steel_nu(0.3),
        &Constraints {
            clamped_sets: vec!["hub_bore".into()],
            ties: false,
        },
        MassKind::Consistent,
        Hex8Kind::Standard,
    )
    .unwrap_err();
    assert!(err.to_string().contains("hub_bore"), "{err}");
    let a = assemble(
        &mesh,
        &steel_nu(0.3),
        &Constraints::default(),
        MassKind::Consistent,
        Hex8Kind::Standard,
    )
    .unwrap();
    assert!(solve(
        &a.k,
        &a.m,
        &ModalOptions {
            fmax_hz: -5.0,
            ..Default::default()
        }
    )
    .is_err());
    assert!(solve(
        &a.k,
        &a.m,
        &ModalOptions {
            fmax_hz: f64::NAN,
            ..Default::default()
        }
    )
    .is_err());
    for slices in [0, 33] {
        let err = solve(
            &a.k,
            &a.m,
            &ModalOptions {
                slices,
                ..Default::default()
            },
        )
        .unwrap_err()
        .to_string();
        assert!(err.contains("slices") && err.contains("1..=32"), "{err}");
    }
}

#[test]
fn band_without_modes_is_an_error_naming_the_band() {
    // Clamped cantilever bar 1 m long (264 dofs: the Lanczos path): its first bending mode is
    // near 40 Hz, so nothing lies below 1 Hz; the Sturm count (0) says so before any iteration.
    let mesh = cuboid([20, 1, 1], [1.0, 0.05, 0.05], 1);
    let a = assemble(
        &mesh,
        &steel_nu(0.3),
        &Constraints {
            clamped_sets: vec!["x0".into()],
            ties: false,
        },
        MassKind::Consistent,
        Hex8Kind::Standard,
    )
    .unwrap();
    assert!(
        a.k.nrows() >= 200,
        "{} dofs: not the Lanczos path",
        a.k.nrows()
    );
    let err = solve(
        &a.k,
        &a.m,
        &ModalOptions {
            fmax_hz: 1.0,
            ..Default::default()
        },
    )
    .unwrap_err()
    .to_string();
    assert!(err.contains("no mode below 1 Hz"), "{err}");
}

#[test]
fn synthetic_ring_cos3_axial_is_n3_axial() {
    // ring: a cuboid bent into an annulus around the y axis (radius 0.3..0.46 m)
    let nth = 48;
    let mut mesh = cuboid([nth, 1, 3], [1.0, 0.02, 1.0], 1);
    for p in mesh.nodes.iter_mut() {
        let th = 2.0 * PI * p[0] * (nth as f64 - 1e-9) / nth as f64;
        let r = 0.3 + 0.16 * p[2];
        *p = [r * th.cos(), p[1], r * th.sin()];
    }
    let w = nodal_weights(&mesh);
    let u: Vec<[f64; 3]> = mesh
        .nodes
        .iter()
        .map(|p| [0.0, (3.0 * p[2].atan2(p[0])).cos(), 0.0])
        .collect();
    let c = classify_shape(&mesh, &w, [0.0; 3], &u);
    assert_eq!(c.family, ModeFamily::Axial);
    assert_eq!(c.nodal_diameters, 3);
    assert_eq!(c.nodal_circles, 0);
    // radial cos(2θ): n = 2, radial
    let u: Vec<[f64; 3]> = mesh
        .nodes
        .iter()
        .map(|p| {
            let th = p[2].atan2(p[0]);
            let a = (2.0 * th).cos();
            [a * th.cos(), 0.0, a * th.sin()]
        })
        .collect();
    let c = classify_shape(&mesh, &w, [0.0; 3], &u);
    assert_eq!((c.family, c.nodal_diameters), (ModeFamily::Radial, 2));
}

/// The 3D modal pipeline as a library (what `squeal modes --wheel` runs): the default wheel at
/// 40 mm with its axle ends clamped, below 1.2 kHz, gives the zero-nodal-circle axial modes
/// (0,0)-(0,3) within 3 % above the axisymmetric solver's 229.2 / 139.6 / 369.3 / 1011.2 Hz
/// (the 3D mesh converges from above; tests/modal_vs_axisym.rs has the bounds per mode); the
/// clamp parser refuses a bad expression naming `--clamp`.
#[test]
fn modal_pipeline_runs_as_a_library() {
    use squeal::modal::pipeline::solve_and_classify;
    use squeal::model::modal::{wheel_model, Clamp};
    let mut spec: squeal::input::wheel::WheelSpec =
        squeal::input::read_json(std::path::Path::new("data/wheels/ns_intercity_920.json"))
            .unwrap();
    spec.mesh.element_size_mm = 40.0;
    let model = wheel_model(
        &spec,
        &Clamp::parse("axle-ends").unwrap(),
        squeal::fem::Hex8Kind::Incompatible,
    )
    .unwrap();
    let run = solve_and_classify(&model, 1200.0, 1).unwrap();
    for (n, reference, bound) in [
        (0, 229.2, 0.06),
        (1, 139.6, 0.07),
        (2, 369.3, 0.035),
        (3, 1011.2, 0.03),
    ] {
        let f = run
            .records
            .iter()
            .find(|r| {
                r.family == squeal::analysis::identify::ModeFamily::Axial
                    && r.nodal_circles == 0
                    && r.nodal_diameters == n
            })
            .unwrap_or_else(|| panic!("(0,{n}) missing"))
            .frequency_hz;
        assert!(
            f / reference - 1.0 > 0.0 && f / reference - 1.0 < bound,
            "(0,{n}): {f} Hz"
        );
    }
    let e = match Clamp::parse("x<<1") {
        Err(e) => e.to_string(),
        Ok(_) => panic!("accepted"),
    };
    assert!(e.contains("--clamp") && e.contains("axle-ends"), "{e}");
}

#[test]
fn purification_from_the_lanczos_relation_matches_purification_by_a_solve() {
    // A free steel block (rigid modes, near-degenerate pairs) solved twice: the Ritz vectors
    // purified from the basis (the default) and by one more solve (the textbook way). Both
    // are Op x for the same x, so the Rayleigh quotients agree to rounding (1e-9 relative: the
    // residuals are near 1e-10, and frequencies are quadratic in the vector error) and each
    // isolated mode's shape to 1e-6 in its cosine. The residuals of both are held to the
    // solver's bound by `solve` itself.
    let mesh = cuboid([6, 4, 3], [0.6, 0.4, 0.3], 1);
    let a = assemble(
        &mesh,
        &steel_nu(0.3),
        &Constraints::default(),
        MassKind::Consistent,
        Hex8Kind::Standard,
    )
    .unwrap();
    let opts = ModalOptions {
        fmax_hz: 12_000.0,
        ..Default::default()
    };
    let by_relation = solve(&a.k, &a.m, &opts).unwrap();
    let by_solve = solve(
        &a.k,
        &a.m,
        &ModalOptions {
            purify_by_solve: true,
            ..opts.clone()
        },
    )
    .unwrap();
    assert_eq!(by_relation.modes.len(), by_solve.modes.len());
    assert!(by_relation.modes.len() > 20, "{}", by_relation.modes.len());
    let flexible: Vec<usize> = (0..by_solve.modes.len())
        .filter(|&i| !by_solve.modes[i].rigid)
        .collect();
    for &i in &flexible {
        let (r, s) = (&by_relation.modes[i], &by_solve.modes[i]);
        assert!(
            (r.eigenvalue - s.eigenvalue).abs() <= 1e-9 * s.eigenvalue,
            "mode {i}: {} Hz against {} Hz",
            r.frequency_hz,
            s.frequency_hz
        );
        let isolated = [i.wrapping_sub(1), i + 1]
            .iter()
            .filter_map(|&j| by_solve.modes.get(j))
            .all(|o| (o.eigenvalue - s.eigenvalue).abs() > 1e-4 * s.eigenvalue);
        if isolated {
            let dot: f64 = r.vector.iter().zip(&s.vector).map(|(x, y)| x * y).sum();
            let nr: f64 = r.vector.iter().map(|x| x * x).sum::<f64>().sqrt();
            let ns: f64 = s.vector.iter().map(|x| x * x).sum::<f64>().sqrt();
            assert!(
                (dot.abs() / (nr * ns) - 1.0).abs() < 1e-6,
                "mode {i} at {} Hz: cosine {}",
                s.frequency_hz,
                dot.abs() / (nr * ns)
            );
        }
    }
}
