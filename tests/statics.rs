//! The static solver (`explicit::statics`: Newton's method with a sparse Cholesky of the
//! tangent) against statics that can be checked independently: global force balance, beam
//! theory, dynamic relaxation on the same discrete model (a second method), and its refusals.
#![allow(clippy::needless_range_loop)]
use std::collections::BTreeMap;

use squeal::explicit::element::{ElasticMaterial, Formulation, Hourglass};
use squeal::explicit::model::Model;
use squeal::explicit::preload::{relax, PreloadOptions};
use squeal::explicit::statics::{solve_static, LinearSolver, StaticOptions};
use squeal::explicit::{Curve, NoAux, Solver, Spring};
use squeal::mesh::{cuboid, Mesh};
use squeal::Error;

mod common;

const STEEL: ElasticMaterial = ElasticMaterial {
    density_kg_per_m3: 7850.0,
    youngs_modulus_pa: 210e9,
    poisson_ratio: 0.3,
};

fn model(mesh: Mesh) -> Model {
    let steel: BTreeMap<u32, ElasticMaterial> = [(1, STEEL)].into_iter().collect();
    Model::from_mesh(mesh, &steel, Formulation::default(), "test").expect("model")
}

fn tight() -> StaticOptions {
    StaticOptions {
        tolerance: 1e-10,
        ..Default::default()
    }
}

/// Dynamic relaxation to a relative residual of `tolerance` (the second method).
fn relax_to(solver: &mut Solver, tolerance: f64) {
    relax(
        solver,
        &mut NoAux,
        PreloadOptions {
            tolerance,
            max_steps: 2_000_000,
            ..Default::default()
        },
    )
    .unwrap();
}

/// A steel block on ground springs under gravity and a 50 kN load, solved both ways. At
/// equilibrium the springs carry load + weight (the elements' forces sum to zero for any
/// displacement, so the balance is exact up to the residual): the static solve to 1e-8 (its
/// residual is 1e-10 of the forces), dynamic relaxation at its default tolerance (1e-4) to
/// 1 %. The problem is linear but for the kernel's geometric terms (strains ~1e-5), so a right
/// tangent converges in at most three iterations; a tangent missing the springs or the
/// elements would need many (the modified Newton step then converges at the rate of what is
/// missing) or none at all.
#[test]
fn block_on_springs_carries_load_and_weight() {
    let build = || {
        let mesh = cuboid([6, 6, 3], [0.3, 0.3, 0.15], 1);
        let mut m = model(mesh);
        m.gravity_m_per_s2 = [0.0, 0.0, -9.81];
        m.add_ground_springs("z0", [2e8; 3], [0.0; 3]).unwrap();
        m.add_load("z1", [0.0, 0.0, -50_000.0], Curve::constant(1.0))
            .unwrap();
        let expected = 50_000.0 + m.total_mass_kg() * 9.81;
        (Solver::new(m, None).unwrap(), expected)
    };
    let spring_force = |s: &Solver| -> f64 {
        s.model
            .springs
            .iter()
            .map(|sp| -sp.stiffness_n_per_m[2] * s.u[sp.node_a][2])
            .sum()
    };
    let (mut s, expected) = build();
    let report = solve_static(&mut s, &mut NoAux, &tight()).unwrap();
    let (mut r, _) = build();
    let relaxation = relax(&mut r, &mut NoAux, PreloadOptions::default()).unwrap();
    let (fs, fr) = (spring_force(&s), spring_force(&r));
    eprintln!("{report:?}; springs {fs} N (relaxation {fr} N) of {expected} N");
    assert!((fs / expected - 1.0).abs() < 1e-8, "{report:?}");
    assert!((fr / expected - 1.0).abs() < 0.01, "{relaxation:?}");
    assert!(relaxation.relative_residual < 1e-4);
    assert!(report.iterations <= 3, "{report:?}");
    // The springs hold the block in every direction: no approach step.
    assert_eq!(report.approach_steps, 0, "{report:?}");
    // Rigid settlement on the springs: (load + weight) / k_total, plus the block's own
    // compression (under 1 %: E A / h is 120 times k_total).
    let settlement = expected / 2e8;
    let top = s.model.node_set("z1").unwrap();
    let w = -top.iter().map(|&n| s.u[n][2]).sum::<f64>() / top.len() as f64;
    assert!((w / settlement - 1.0).abs() < 0.02, "{w} vs {settlement}");
    // The run that follows starts at rest.
    assert!(s.v.iter().all(|v| *v == [0.0; 3]));
}

/// A cantilever (L/h = 20, four elements through the thickness) under a tip load: the tip
/// deflection within 2 % of Euler-Bernoulli `P L^3 / (3 E I)` (shear adds 0.2 %; the element's
/// own error is the 2 % the dynamic-relaxation test of the same beam allows), and within 1e-5
/// of dynamic relaxation converged to a relative residual of 1e-7 on the same mesh (measured
/// 4.3e-7): both solve the same discrete equations, so they differ by the relaxation's
/// residual amplified by the beam's conditioning. A tangent or constraint error would show as
/// a difference of the size of the error.
#[test]
fn cantilever_matches_beam_theory_and_dynamic_relaxation() {
    let (l, b, h) = (0.2, 0.02, 0.01);
    let p = 10.0;
    let build = || {
        let mesh = cuboid([20, 1, 4], [l, b, h], 1);
        let mut m = model(mesh);
        m.fix_set("x0", [true, true, true]).unwrap();
        m.add_load("x1", [0.0, 0.0, -p], Curve::constant(1.0))
            .unwrap();
        let tip = m.node_set("x1").unwrap();
        (Solver::new(m, None).unwrap(), tip)
    };
    let tip_deflection =
        |s: &Solver, tip: &[usize]| -tip.iter().map(|&n| s.u[n][2]).sum::<f64>() / tip.len() as f64;
    let (mut implicit, tip) = build();
    let report = solve_static(&mut implicit, &mut NoAux, &tight()).unwrap();
    let (mut relaxed, _) = build();
    relax_to(&mut relaxed, 1e-7);
    let inertia = b * h * h * h / 12.0;
    let beam = p * l * l * l / (3.0 * STEEL.youngs_modulus_pa * inertia);
    let (wi, wr) = (
        tip_deflection(&implicit, &tip),
        tip_deflection(&relaxed, &tip),
    );
    eprintln!(
        "beam {beam:.6e}, implicit {wi:.6e} ({} iterations), relaxation {wr:.6e}; difference {:.2e}",
        report.iterations,
        (wi / wr - 1.0).abs()
    );
    assert!((wi / beam - 1.0).abs() < 0.02);
    // Measured 11: the geometric terms left out of the tangent cost a few iterations.
    assert!(report.iterations <= 15, "{report:?}");
    assert!((wi / wr - 1.0).abs() < 1e-5);
    // Every node, not only the tip.
    let scale = wi;
    for n in 0..implicit.u.len() {
        for c in 0..3 {
            assert!(
                (implicit.u[n][c] - relaxed.u[n][c]).abs() < 1e-5 * scale,
                "node {n} direction {c}: {} vs {}",
                implicit.u[n][c],
                relaxed.u[n][c]
            );
        }
    }
}

/// A block tied onto a fixed plate, its top a rigid body, a point mass hanging from it on a
/// spring: the solver, the base nodes, the hanging mass's node and the total weight (N).
fn tied_block_with_hanger() -> (Solver, Vec<usize>, usize, f64) {
    let (mut mesh, _, offset, base) = common::tied_block_on_plate([4, 4, 2]);
    let top_z = mesh.nodes[offset..]
        .iter()
        .map(|p| p[2])
        .fold(f64::MIN, f64::max);
    let top: Vec<usize> = (offset..mesh.nodes.len())
        .filter(|&n| (mesh.nodes[n][2] - top_z).abs() < 1e-12)
        .collect();
    mesh.add_node_set("block_top", top.clone());
    // The hanger acts at the top's centre (the block is symmetric about it), so it puts no
    // moment on the rigid top: the static solver holds rigid rotations, relaxation does not.
    let centre = *top
        .iter()
        .min_by(|&&a, &&b| {
            let d = |n: usize| (mesh.nodes[n][0] - 0.05).hypot(mesh.nodes[n][1] - 0.05);
            d(a).total_cmp(&d(b))
        })
        .unwrap();
    let mut m = model(mesh);
    m.gravity_m_per_s2 = [0.0, 0.0, -9.81];
    m.fix_nodes(&base, [true, true, true]);
    m.add_rigid_body("block_top").unwrap();
    let hanging = m
        .add_point_mass("hanging", [0.05, 0.05, 0.3], 500.0)
        .unwrap();
    m.add_spring(Spring {
        name: "hanger".into(),
        node_a: centre,
        node_b: Some(hanging),
        stiffness_n_per_m: [1e7, 1e7, 1e7],
        damping_n_s_per_m: [0.0; 3],
    })
    .unwrap();
    let weight = m.total_mass_kg() * 9.81;
    (Solver::new(m, None).unwrap(), base, hanging, weight)
}

/// The constraints the rolling model uses, together: a fine block tied on a coarse plate, a
/// rigid set on the block's top, a point mass hanging from it by a spring, gravity. The
/// support reactions carry the whole weight, the spring carries the point mass's weight, and
/// the displacements agree with dynamic relaxation of the same model to 1e-6 of the largest
/// displacement (ten times the relaxation's residual of 1e-7; measured 3.6e-10). With the
/// hanger off the centre the two differ by 4e-4 of it: relaxation lets the rigid top tilt,
/// the static solver holds rigid rotations (module documentation).
#[test]
fn ties_rigid_bodies_and_point_masses_match_dynamic_relaxation() {
    let build = tied_block_with_hanger;
    let (mut implicit, base, hanging, weight) = build();
    let report = solve_static(&mut implicit, &mut NoAux, &tight()).unwrap();
    let (mut relaxed, ..) = build();
    relax_to(&mut relaxed, 1e-7);
    let (f_int, _) = implicit.force_arrays();
    let mass = implicit.effective_mass();
    let reaction: f64 = base.iter().map(|&n| f_int[n][2] + mass[n] * 9.81).sum();
    assert!(
        (reaction / weight - 1.0).abs() < 1e-8,
        "reaction {reaction} vs weight {weight}; {report:?}"
    );
    let stretch = implicit.u[hanging][2] - implicit.u[implicit.model.springs[0].node_a][2];
    assert!(
        (-stretch * 1e7 / (500.0 * 9.81) - 1.0).abs() < 1e-8,
        "spring stretch {stretch}"
    );
    let largest = implicit
        .u
        .iter()
        .flat_map(|u| u.iter())
        .fold(0.0f64, |m, x| m.max(x.abs()));
    let mut worst = 0.0f64;
    for n in 0..implicit.u.len() {
        for c in 0..3 {
            let d = (implicit.u[n][c] - relaxed.u[n][c]).abs();
            worst = worst.max(d);
        }
    }
    eprintln!("{report:?}; largest displacement {largest:.3e} m, largest difference {worst:.3e} m");
    assert!(worst < 1e-6 * largest);
    // The tangent holds the ties, the rigid body and the spring: the nonlinear residual is
    // met in a few steps (measured 3; a tangent without them would not converge this fast).
    assert!(report.iterations <= 4, "{report:?}");
}

/// A body that nothing holds is moved by its translation alone, without a solve (the approach
/// step, `explicit::statics::approach`), and that step is the capped Newton step of the full
/// tangent (the second method: the same iteration with `approach_steps` off). Two bodies: a
/// free block, and a block on vertical ground springs pushed sideways (free in x and y only).
/// The loads act through the centre of mass (gravity with a sideways part, a load spread over
/// the top face), so the regularisation carries a translation and no rotation. The analytic
/// step is `max_increment_m F / |F|` on every node, `F` the resultant in the free directions
/// (to 1e-12, rounding). The full solve differs from it by the blocks' deformation scaled by
/// the cap: about 1e-9 of the step for the free block (the top load's squeeze against a
/// 623 m free fall) and 1.05e-5 for the block on springs (its 0.26 mm settlement against a
/// 24.8 m sideways slide), and by the rounding of a solve whose matrix has a condition number
/// of `(f_max / f_r)^2`, about 1e12 here (measured: 2.2e-6 of the step for the free block);
/// 1e-4 of the step bounds both. A wrong direction, or a supported direction moved, would be
/// off by the step itself.
#[test]
fn approach_step_is_the_capped_solve_of_a_free_body() {
    let cap = StaticOptions::default().max_increment_m;
    let cases: [(&str, Option<[f64; 3]>); 2] = [
        ("free block", None),
        ("block on vertical springs", Some([0.0, 0.0, 2e8])),
    ];
    for (name, springs) in cases {
        let gravity = [9.81, 0.0, -9.81];
        let load = [0.0, 0.0, -50_000.0];
        let build = || {
            let mut m = model(cuboid([3, 3, 3], [0.3, 0.3, 0.3], 1));
            m.gravity_m_per_s2 = gravity;
            if let Some(k) = springs {
                m.add_ground_springs("z0", k, [0.0; 3]).unwrap();
            }
            m.add_load("z1", load, Curve::constant(1.0)).unwrap();
            Solver::new(m, None).unwrap()
        };
        let one_iteration = |approach_steps: bool| {
            let mut s = build();
            let opts = StaticOptions {
                max_iterations: 1,
                approach_steps,
                ..tight()
            };
            let e = solve_static(&mut s, &mut NoAux, &opts).unwrap_err();
            assert!(e.to_string().contains("did not converge"), "{name}: {e}");
            s
        };
        let approached = one_iteration(true);
        let solved = one_iteration(false);
        let mass = approached.model.total_mass_kg();
        let free: [bool; 3] = std::array::from_fn(|i| springs.is_none_or(|k| k[i] == 0.0));
        let force: [f64; 3] = std::array::from_fn(|i| {
            if free[i] {
                load[i] + mass * gravity[i]
            } else {
                0.0
            }
        });
        let length = force.iter().map(|f| f * f).sum::<f64>().sqrt();
        let (mut analytic, mut second) = (0.0f64, 0.0f64);
        for n in 0..approached.u.len() {
            for i in 0..3 {
                let expected = cap * force[i] / length;
                analytic = analytic.max((approached.u[n][i] - expected).abs());
                second = second.max((approached.u[n][i] - solved.u[n][i]).abs());
            }
        }
        eprintln!(
            "{name}: against the analytic step {:.2e}, against the capped solve {:.2e} of the \
             step",
            analytic / cap,
            second / cap
        );
        assert!(analytic < 1e-12 * cap, "{name}: {analytic:e}");
        assert!(second < 1e-4 * cap, "{name}: {second:e}");
    }
}

fn cantilever() -> Solver {
    let mesh = cuboid([10, 1, 2], [0.2, 0.02, 0.01], 1);
    let mut m = model(mesh);
    m.fix_set("x0", [true, true, true]).unwrap();
    m.add_load("x1", [0.0, 0.0, -100.0], Curve::constant(1.0))
        .unwrap();
    Solver::new(m, None).unwrap()
}

fn input_field(e: Error) -> String {
    match e {
        Error::Input { field, .. } => field,
        other => panic!("expected an input error, got {other}"),
    }
}

/// Impossible options are refused with the field named; a factor that would not fit, a model
/// the solver cannot linearise, and a solve that runs out of iterations each stop with a
/// diagnosis that names the remedy.
#[test]
fn refusals_name_the_field_and_the_remedy() {
    let bad = [
        (
            StaticOptions {
                tolerance: 0.0,
                ..Default::default()
            },
            "tolerance",
        ),
        (
            StaticOptions {
                tolerance: 1.5,
                ..Default::default()
            },
            "tolerance",
        ),
        (
            StaticOptions {
                max_increment_m: -1.0,
                ..Default::default()
            },
            "max_increment_m",
        ),
        (
            StaticOptions {
                regularisation_hz: f64::NAN,
                ..Default::default()
            },
            "regularisation_hz",
        ),
        (
            StaticOptions {
                max_iterations: 0,
                ..Default::default()
            },
            "max_iterations",
        ),
        (
            StaticOptions {
                held_rigid_translations: vec![[true; 3]],
                ..Default::default()
            },
            "held_rigid_translations",
        ),
    ];
    for (opts, field) in bad {
        let e = solve_static(&mut cantilever(), &mut NoAux, &opts).unwrap_err();
        assert_eq!(input_field(e), field);
    }
    let e = solve_static(
        &mut cantilever(),
        &mut NoAux,
        &StaticOptions {
            memory_limit_bytes: Some(1000),
            ..Default::default()
        },
    )
    .unwrap_err();
    let text = e.to_string();
    assert!(
        text.contains("GB") && text.contains("dynamic_relaxation"),
        "{text}"
    );
    // The geometric terms need a second iteration at this tolerance.
    let e = solve_static(
        &mut cantilever(),
        &mut NoAux,
        &StaticOptions {
            tolerance: 1e-12,
            max_iterations: 1,
            ..Default::default()
        },
    )
    .unwrap_err();
    let text = e.to_string();
    assert!(
        text.contains("did not converge in 1 iterations") && text.contains("dynamic relaxation"),
        "{text}"
    );
    let mesh = cuboid([4, 1, 1], [0.2, 0.02, 0.01], 1);
    let steel: BTreeMap<u32, ElasticMaterial> = [(1, STEEL)].into_iter().collect();
    let viscous = Formulation::OnePoint {
        hourglass: Hourglass::Viscous { kappa: 0.1 },
    };
    let mut m = Model::from_mesh(mesh, &steel, viscous, "test").unwrap();
    m.fix_set("x0", [true, true, true]).unwrap();
    let mut s = Solver::new(m, None).unwrap();
    let e = solve_static(&mut s, &mut NoAux, &StaticOptions::default()).unwrap_err();
    assert_eq!(input_field(e), "formulation");
}

/// The iterative linear solver (conjugate gradients, two-level preconditioner) against the
/// Cholesky factor inside the same Newton iteration, on the cantilever (held base) and on the
/// tied block with its rigid top and hanging mass (ties, a rigid body's reduced node, a point
/// mass on a spring in the coarse space): the same equilibrium. Both stop at a residual of
/// 1e-10 of the forces; the displacements then agree far inside the 1e-6 asked (the bound the
/// relaxation comparisons above use).
#[test]
fn iterative_linear_solver_matches_the_direct_one() {
    type Build = fn() -> Solver;
    let cases: [(&str, Build); 2] = [
        ("cantilever", cantilever),
        ("tied block", || tied_block_with_hanger().0),
    ];
    for (name, build) in cases {
        let mut direct = build();
        let d = solve_static(&mut direct, &mut NoAux, &tight()).unwrap();
        let mut iterative = build();
        let opts = StaticOptions {
            linear_solver: LinearSolver::Iterative,
            ..tight()
        };
        let i = solve_static(&mut iterative, &mut NoAux, &opts).unwrap();
        assert!(
            i.relative_residual < 1e-10 && i.cg_iterations > 0,
            "{name}: {i:?}"
        );
        assert_eq!(i.linear_solver, LinearSolver::Iterative);
        let largest = direct
            .u
            .iter()
            .flat_map(|u| u.iter())
            .fold(0.0f64, |m, x| m.max(x.abs()));
        let worst = (0..direct.u.len())
            .flat_map(|n| (0..3).map(move |c| (n, c)))
            .map(|(n, c)| (direct.u[n][c] - iterative.u[n][c]).abs())
            .fold(0.0f64, f64::max);
        eprintln!(
            "{name}: direct {} iterations, iterative {} ({} CG); largest difference \
             {worst:.3e} of {largest:.3e} m",
            d.iterations, i.iterations, i.cg_iterations
        );
        assert!(worst < 1e-6 * largest, "{name}: {worst:e} of {largest:e}");
    }
}
