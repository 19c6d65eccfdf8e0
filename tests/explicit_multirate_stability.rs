//! Long-run stability of multi-rate (subcycled) stepping (`squeal::explicit::multirate`): free
//! vibration of small graded blocks, undamped, from seeded random velocities. Single-rate
//! central differences keep such a block's energy bounded for ever (below its stable step the
//! scheme conserves a modified energy). The subcycled update, a nodal partition with linear
//! interpolation of the coarse nodes (Belytschko, Yen & Mullen 1979), does not when its coarse
//! levels step their elements at their own stable step: at some ratios of the element sizes a
//! coarse interface node's update, which samples the forces of its fine-rate elements once per
//! coarse step, resonates with the fine side's fastest modes, and the energy grows
//! exponentially. With the coarse levels at half their elements' stable step
//! (`STABLE_COARSE_COURANT`, the engine's rule since 2026-11-26) no block tried grows.
//!
//! The fast test shows both on blocks that grow under the old rule; the ignored one sweeps the
//! coarse element size over two block families (`.ci/long` records it).

use squeal::explicit::levels::{LevelScheme, COURANT_FACTOR};
use squeal::explicit::{Formulation, Model, NoAux, Solver};
use squeal::material::Material;
use squeal::mesh::cuboid;

/// A bar 16 x 16 mm across, `across` elements each way, with the element lengths along x given
/// (`spacings_m`): 1 mm elements next to coarser ones make a level interface. Free: nothing
/// held.
fn graded_block(spacings_m: &[f64], across: usize) -> Model {
    let n = spacings_m.len();
    let mut mesh = cuboid([n, across, across], [n as f64, 0.016, 0.016], 1);
    let mut x = vec![0.0];
    for s in spacings_m {
        x.push(x.last().unwrap() + s);
    }
    for p in mesh.nodes.iter_mut() {
        p[0] = x[p[0].round() as usize];
    }
    let materials = [(1, Material::STEEL)].into_iter().collect();
    Model::from_mesh(mesh, &materials, Formulation::default(), "test").unwrap()
}

/// 20 elements of 1 mm, then 20 of `coarse_m`.
fn two_sizes(coarse_m: f64) -> Vec<f64> {
    [vec![1e-3; 20], vec![coarse_m; 20]].concat()
}

/// Seeded uniform random velocities in (-0.5, 0.5) mm/s on every node and direction: every
/// mode of the block starts with some energy, the fastest ones included. Small enough for the
/// elements to stay linear.
fn random_velocities(s: &mut Solver) {
    let mut state: u64 = 0x9E37_79B9_7F4A_7C15;
    for v in s.v.iter_mut() {
        for c in v.iter_mut() {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            *c = 1e-3 * ((state >> 11) as f64 / (1u64 << 53) as f64 - 0.5);
        }
    }
}

/// Largest stored energy (kinetic + strain + hourglass) over `steps` steps, relative to the
/// first report, with reports every 1024 steps; infinite once a value is not finite. `levels`:
/// subcycled with that scheme (and the partition's elements per level), or single rate.
fn energy_growth(model: Model, levels: Option<LevelScheme>, steps: u64) -> (f64, Vec<usize>) {
    let mut s = Solver::new(model, None).unwrap();
    let mut counts = vec![];
    if let Some(scheme) = levels {
        counts = s
            .enable_multi_rate_with(scheme, &[])
            .unwrap()
            .counts
            .clone();
    }
    random_velocities(&mut s);
    let mut first = None;
    let mut worst: f64 = 0.0;
    for k in 0..steps {
        // 1024 is a multiple of every cycle here (at most 16 fine steps), so every level has
        // just updated at a report.
        let report = k % 1024 == 0;
        s.step_with(&mut NoAux, false, report).unwrap();
        if let Some(e) = report.then(|| s.last_energy()).flatten() {
            let stored = e.kinetic_j + e.strain_j + e.hourglass_j;
            if !stored.is_finite() {
                return (f64::INFINITY, counts);
            }
            let e0 = *first.get_or_insert(stored);
            worst = worst.max(stored / e0);
        }
    }
    (worst, counts)
}

/// Coarse levels at their elements' own stable step (the old rule).
fn own_step(max_levels: usize) -> LevelScheme {
    LevelScheme::binary(max_levels).with_coarse_courant(COURANT_FACTOR)
}

/// Two blocks whose coarse part is one and two levels above the 1 mm elements under either
/// rule (4.19 mm and 8.34 mm elements): over 65 536 fine steps (10 ms) the old rule's
/// subcycling grows by orders of magnitude, the engine's keeps the energy as single rate does.
/// Measured (2026-11-26): see the printed line; the sweep (ignored test below) found 12 of 44
/// sizes growing under the old rule and none of 78 under the engine's.
#[test]
fn coarse_levels_at_their_own_stable_step_resonate_and_at_half_of_it_do_not() {
    let steps = 65_536;
    for coarse_m in [4.19e-3, 8.34e-3] {
        let block = || graded_block(&two_sizes(coarse_m), 1);
        let (single, _) = energy_growth(block(), None, steps);
        let (old, old_levels) = energy_growth(block(), Some(own_step(8)), steps);
        let (engine, levels) = energy_growth(block(), Some(LevelScheme::binary(8)), steps);
        println!(
            "1 | {:.2} mm, largest energy over {steps} steps: single rate {single:.3}; coarse \
             levels at their own step {old:.3e} (elements per level {old_levels:?}); at half \
             {engine:.3} ({levels:?})",
            coarse_m * 1e3
        );
        assert!(old_levels.len() >= 2 && levels.len() >= 2, "no interface");
        // Single rate: the stored energy at the reports fluctuates about its start (the
        // kinetic part is taken at the centred velocity); 1.2 leaves room for that.
        assert!(single < 1.2, "single rate: {single}");
        assert!(engine < 1.2, "engine's levels: {engine}");
        // Growth by 100 is an instability, not a fluctuation.
        assert!(old > 100.0, "old rule: {old}");
    }
}

/// The sweep: the coarse element size from 1 to 16 mm in 48 steps, on blocks one element
/// across and two across, each within 1.2 of its starting energy over 200 000 fine steps
/// (30 ms) with the engine's levels; and three blocks graded over three and four levels.
/// Sizes without a level interface are skipped (counted in the output).
#[test]
#[ignore]
fn subcycled_graded_blocks_keep_their_energy() {
    let steps = 200_000;
    let mut grew = Vec::new();
    let mut tested = 0;
    for across in [1, 2] {
        for k in 0..48 {
            let coarse_m = 1.0e-3 * (1.0 + 15.0 * (k as f64 / 47.0));
            let (worst, levels) = energy_growth(
                graded_block(&two_sizes(coarse_m), across),
                Some(LevelScheme::binary(8)),
                steps,
            );
            if levels.len() < 2 {
                continue;
            }
            tested += 1;
            println!(
                "{across} across, 1 | {:.2} mm, levels {levels:?}: largest energy {worst:.3}",
                coarse_m * 1e3
            );
            if worst >= 1.2 {
                grew.push(format!("{across} across, {:.2} mm", coarse_m * 1e3));
            }
        }
    }
    for (name, spacings) in [
        (
            "1 | 3.7 | 7.3 mm",
            [vec![1e-3; 10], vec![3.7e-3; 10], vec![7.3e-3; 10]].concat(),
        ),
        (
            "1 | 3.7 | 7.3 | 14.6 mm",
            [
                vec![1e-3; 10],
                vec![3.7e-3; 10],
                vec![7.3e-3; 10],
                vec![14.6e-3; 10],
            ]
            .concat(),
        ),
        (
            "1 | 4 | 9.5 | 15 mm",
            [
                vec![1e-3; 10],
                vec![4e-3; 10],
                vec![9.5e-3; 10],
                vec![15e-3; 10],
            ]
            .concat(),
        ),
    ] {
        let (worst, levels) = energy_growth(
            graded_block(&spacings, 1),
            Some(LevelScheme::binary(8)),
            steps,
        );
        tested += 1;
        println!("{name}, levels {levels:?}: largest energy {worst:.3}");
        if worst >= 1.2 {
            grew.push(name.to_string());
        }
    }
    println!("{tested} blocks with a level interface; grew: {grew:?}");
    assert!(grew.is_empty(), "energy grew under subcycling: {grew:?}");
}
