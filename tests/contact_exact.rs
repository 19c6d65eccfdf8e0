//! Exact contact (forward-increment Lagrange multipliers, src/contact/exact.rs) against
//! independent references:
//! - Coulomb's law: a block sliding on a fixed plate decelerates at mu g, and the friction
//!   force is mu N at every instant (all nodes slide, so the projection puts each at its bound);
//! - exact stick: pushed below the bound, the block's bottom does not move on the plate at
//!   all (a penalty lets it creep by its elastic slip `F / k`); above it, the block accelerates
//!   at `(F - mu W) / m`;
//! - Newton's third law: between two free bodies the contact forces are internal, so the total
//!   momentum does not change through an impact;
//! - the contact conditions themselves: no penetration at any step, and forces that do not
//!   depend on the thread count.
use std::collections::BTreeMap;

use squeal::contact::{ContactPair, Enforcement, FrictionLaw};
use squeal::explicit::element::{ElasticMaterial, Formulation};
use squeal::explicit::model::Model;
use squeal::explicit::{Curve, Solver};

mod common;

use common::STEEL;
const G: f64 = 9.81;

struct Scene {
    solver: Solver,
    pair: ContactPair,
    block: Vec<usize>,
    plate: Vec<usize>,
    block_mass_kg: f64,
    plate_fixed: bool,
}

/// The scene with exact enforcement: the plate fixed (or free, without gravity), and a force
/// `push_n` along x on the block's top nodes, applied from the start.
fn scene(friction: FrictionLaw, plate_fixed: bool, push_n: f64) -> Scene {
    scene_with_push(friction, plate_fixed, push_n, Curve::constant(1.0))
}

/// [`scene`] with the push's time curve.
fn scene_with_push(friction: FrictionLaw, plate_fixed: bool, push_n: f64, curve: Curve) -> Scene {
    let (mesh, slaves, faces, _) = common::sliding_block_on_plate();
    let bulk = STEEL.youngs_modulus_pa / (3.0 * (1.0 - 2.0 * STEEL.poisson_ratio));
    let mut pair = ContactPair::new("exact", &mesh, slaves, faces, 0.1, bulk, friction).unwrap();
    pair.enforcement = Enforcement::Exact;
    let materials: BTreeMap<u32, ElasticMaterial> = [(1, STEEL), (2, STEEL)].into_iter().collect();
    let mut model = Model::from_mesh(mesh, &materials, Formulation::default(), "test").unwrap();
    if plate_fixed {
        model.gravity_m_per_s2 = [0.0, 0.0, -G];
        model.fix_set("plate", [true, true, true]).unwrap();
    }
    let block = model.node_set("block").unwrap();
    let plate = model.node_set("plate").unwrap();
    if push_n != 0.0 {
        let top: Vec<usize> = model
            .node_set("z1")
            .unwrap()
            .into_iter()
            .filter(|n| block.contains(n))
            .collect();
        model.mesh.node_sets.insert("block_top".into(), top);
        model
            .add_load("block_top", [push_n, 0.0, 0.0], curve)
            .unwrap();
    }
    let block_mass_kg: f64 = block.iter().map(|&n| model.nodal_mass_kg[n]).sum();
    // No contact step bound: exact enforcement adds no stiffness.
    let solver = Solver::new(model, None).unwrap();
    Scene {
        solver,
        pair,
        block,
        plate,
        block_mass_kg,
        plate_fixed,
    }
}

fn mean_velocity_x(s: &Solver, nodes: &[usize]) -> f64 {
    nodes.iter().map(|&n| s.v[n][0]).sum::<f64>() / nodes.len() as f64
}

/// Steps until `t_s` past now, asserting at every step that no slave penetrates and that no
/// tangential force exceeds its bound. The penetration allowed: on the fixed flat plate,
/// rounding (1e-12 m, a millionth of the micrometre a penalty contact of this scene sinks);
/// on a free plate the face's normal and the projection's weights, held over a step, move by
/// the step's motion, a second-order error of `(dt v)^2 / L`, below 1e-9 m at 1 m/s.
fn run_for(sc: &mut Scene, t_s: f64, mut each_step: impl FnMut(&Scene)) {
    let allowed_m = if sc.plate_fixed { 1e-12 } else { 1e-9 };
    let t_end = sc.solver.time_s + t_s;
    while sc.solver.time_s < t_end {
        sc.solver.step_with(&mut sc.pair, false, false).unwrap();
        for s in &sc.pair.state {
            assert!(
                s.penetration_m <= allowed_m,
                "penetration {} m",
                s.penetration_m
            );
            if s.active {
                let ft = s
                    .tangential_force_n
                    .iter()
                    .map(|c| c * c)
                    .sum::<f64>()
                    .sqrt();
                assert!(ft <= s.mu * s.normal_force_n * (1.0 + 1e-12));
            }
        }
        each_step(sc);
    }
}

#[test]
fn a_block_sliding_on_exact_contact_decelerates_at_mu_g_with_mu_n_at_every_step() {
    let mu = 0.3;
    let mut sc = scene(FrictionLaw::Coulomb { mu }, true, 0.0);
    // Set down at rest under gravity: the block rings on the plate in its vertical modes
    // (undamped, +-40 % of the weight), and the normal force carries the weight on the mean.
    let (mut normal_sum, mut steps) = (0.0, 0);
    run_for(&mut sc, 0.005, |sc| {
        normal_sum += sc.pair.resultants().0[2];
        steps += 1;
    });
    let weight = sc.block_mass_kg * G;
    // 1 %: a mean over some 370 periods of the ringing.
    assert!(
        (normal_sum / steps as f64 / weight - 1.0).abs() < 0.01,
        "{} vs {weight}",
        normal_sum / steps as f64
    );
    for &n in &sc.block {
        sc.solver.v[n][0] = 1.0;
    }
    let v0 = mean_velocity_x(&sc.solver, &sc.block);
    let t0 = sc.solver.time_s;
    let block = sc.block.clone();
    let (mut friction_impulse, mut normal_impulse) = (0.0, 0.0);
    run_for(&mut sc, 0.1, |sc| {
        let (n, t, _) = sc.pair.resultants();
        friction_impulse += -t[0];
        normal_impulse += n[2];
        // Every node slides while the block does: the force ratio is mu to rounding.
        // Every node slides while the block does: each is at its bound, and the force ratio
        // is mu up to the direction of each node's slip, which the block's rocking turns out
        // of x by a little (a relative 1e-8 measured; 1e-6 allowed).
        assert!(sc.pair.state.iter().all(|s| !s.active || s.at_bound));
        if n[2] > 0.0 {
            assert!(
                (-t[0] / n[2] / mu - 1.0).abs() < 1e-6,
                "ratio {}",
                -t[0] / n[2]
            );
        }
    });
    let v1 = mean_velocity_x(&sc.solver, &block);
    let decel = (v0 - v1) / (sc.solver.time_s - t0);
    // 0.5 %: the mean normal force is the weight up to the block's vertical ringing.
    assert!(
        (decel / (mu * G) - 1.0).abs() < 0.005,
        "deceleration {decel} vs {}",
        mu * G
    );
    assert!((friction_impulse / normal_impulse / mu - 1.0).abs() < 1e-6);
    let (sweeps, unconverged, held) = sc.pair.exact_statistics();
    assert!(
        sweeps >= 1 && unconverged == 0,
        "sweeps {sweeps}, unconverged {unconverged}"
    );
    // The fixed plate's nodes are held for the contact (infinite mass), as documented.
    assert!(held > 0);
}

#[test]
fn below_the_bound_the_block_sticks_exactly_and_above_it_accelerates_at_f_minus_mu_w_over_m() {
    let mu = 0.3;
    // The weight of the block: 50 x 50 x 20 mm of steel.
    let weight = 0.05 * 0.05 * 0.02 * 7850.0 * G;
    // Stick: half the bound, ramped in over 2 ms once the block has settled (with mass
    // damping, then none): a block set down at once rings, and the Poisson part of its ringing
    // slides the bottom corners whenever their normal force dips.
    let mut sc = scene_with_push(
        FrictionLaw::Coulomb { mu },
        true,
        0.5 * mu * weight,
        Curve::ramp(0.003, 0.005, 1.0),
    );
    sc.solver.model.mass_damping_per_s = 2e5;
    run_for(&mut sc, 0.003, |_| {});
    sc.solver.model.mass_damping_per_s = 0.0;
    let bottom = sc.pair.slaves.clone();
    let before: Vec<f64> = bottom.iter().map(|&n| sc.solver.u[n][0]).collect();
    let mut at_bound = 0;
    run_for(&mut sc, 0.01, |sc| {
        at_bound += sc.pair.state.iter().filter(|s| s.at_bound).count();
    });
    assert_eq!(at_bound, 0, "node-steps at the bound");
    for (k, &n) in bottom.iter().enumerate() {
        let slip = sc.solver.u[n][0] - before[k];
        // 1e-12 m: rounding of the displacement sums (a penalty contact of this scene would let
        // the bottom creep by its elastic slip, F / k of order 1e-8 m).
        assert!(slip.abs() < 1e-12, "node {n} slipped {slip} m");
    }
    let (_, t, _) = sc.pair.resultants();
    // The friction force balances the push (the ramp leaves a small ringing: 2 %).
    assert!(
        (-t[0] / (0.5 * mu * weight) - 1.0).abs() < 0.02,
        "friction {}",
        t[0]
    );
    // Slide: twice the bound. Acceleration (F - mu W) / m = mu g.
    let push = 2.0 * mu * weight;
    let mut sc = scene(FrictionLaw::Coulomb { mu }, true, push);
    let block = sc.block.clone();
    run_for(&mut sc, 0.002, |_| {});
    let (v0, t0) = (mean_velocity_x(&sc.solver, &block), sc.solver.time_s);
    run_for(&mut sc, 0.02, |_| {});
    let accel = (mean_velocity_x(&sc.solver, &block) - v0) / (sc.solver.time_s - t0);
    let expected = (push - mu * weight) / sc.block_mass_kg;
    // 1 %: the pushed block rocks a little on the plate, which makes the normal force ring.
    assert!(
        (accel / expected - 1.0).abs() < 0.01,
        "acceleration {accel} vs {expected}"
    );
}

/// Two free bodies without gravity: the block moves onto the plate at 1 m/s from 20 um above
/// it. Momentum is conserved through the impact, no step penetrates, and the plate picks up
/// momentum (the contact acted).
fn impact(threads: usize) -> (Vec<[f64; 3]>, [f64; 3], [f64; 3], f64) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        let mut sc = scene(FrictionLaw::Coulomb { mu: 0.3 }, false, 0.0);
        for &n in &sc.block.clone() {
            sc.solver.u[n][2] += 20e-6;
            sc.solver.v[n] = [0.2, 0.0, -1.0];
        }
        let momentum = |s: &Solver| -> [f64; 3] {
            let m = s.effective_mass();
            let mut p = [0.0; 3];
            for (k, v) in s.v.iter().enumerate() {
                for d in 0..3 {
                    p[d] += m[k] * v[d];
                }
            }
            p
        };
        let p0 = momentum(&sc.solver);
        run_for(&mut sc, 0.0005, |_| {});
        let p1 = momentum(&sc.solver);
        let plate = sc.plate.clone();
        let plate_vz = plate.iter().map(|&n| sc.solver.v[n][2]).sum::<f64>() / plate.len() as f64;
        (sc.solver.u.clone(), p0, p1, plate_vz)
    })
}

#[test]
fn an_impact_between_free_bodies_conserves_momentum_and_does_not_depend_on_the_threads() {
    let (u2, p0, p1, plate_vz) = impact(2);
    let scale = p0.iter().map(|c| c.abs()).fold(0.0, f64::max);
    for d in 0..3 {
        // Rounding of the sums over 1700 nodes.
        assert!(
            (p1[d] - p0[d]).abs() < 1e-12 * scale.max(1.0),
            "momentum {d}: {p0:?} -> {p1:?}"
        );
    }
    assert!(plate_vz < -1e-3, "the plate did not move: {plate_vz} m/s");
    let (u1, _, _, _) = impact(1);
    assert!(u1 == u2, "the result depends on the thread count");
}
