//! Long-run stability of multi-rate (subcycled) stepping (`squeal::explicit::multirate`): free
//! vibration of small graded blocks, undamped, from seeded random velocities. Single-rate
//! central differences keep such a block's energy bounded for ever (below its stable step the
//! scheme conserves a modified energy). The subcycled update, a nodal partition with linear
//! interpolation of the coarse nodes (Belytschko, Yen & Mullen 1979), does not: at some step
//! ratios and element sizes a coarse interface node's update, which samples the forces of its
//! fine-rate elements once per coarse step, resonates with the fine side's fastest modes, and
//! the energy grows exponentially. Smolinski, Sleith & Belytschko (Comput. Mech. 18, 1996)
//! bound the stable steps of such nodal partitions by element frequencies, not by each
//! element's own stable step alone, which is the rule the engine's levels follow.
//!
//! This is why `auto` does not subcycle (`rolling::stepping`) and why the `paper` case 5 run
//! multi-rate went unstable at 5.2 ms (docs/run-log.md). The fast test shows the growth on one
//! block against the single-rate control; the ignored one is the acceptance test a stable
//! subcycling scheme must pass, and fails today (`.ci/long` records it).

use squeal::explicit::{Formulation, Model, NoAux, Solver};
use squeal::material::Material;
use squeal::mesh::cuboid;

/// A bar of one 16 x 16 mm element across, with the element lengths along x given
/// (`spacings_m`): 1 mm elements next to coarser ones make a level interface whose coarse side
/// is a power of two (times `1 + a little`) of the fine side's stable step. Free: nothing held.
fn graded_block(spacings_m: &[f64]) -> Model {
    let n = spacings_m.len();
    let mut mesh = cuboid([n, 1, 1], [n as f64, 0.016, 0.016], 1);
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
/// first report, with reports every 1024 steps; infinite once a value is not finite.
fn energy_growth(model: Model, multi_rate: bool, steps: u64) -> f64 {
    let mut s = Solver::new(model, None).unwrap();
    if multi_rate {
        let p = s.enable_multi_rate(8, &[]).unwrap();
        assert!(p.counts.len() >= 2, "no level interface: {:?}", p.counts);
    }
    random_velocities(&mut s);
    let mut first = None;
    let mut worst: f64 = 0.0;
    for k in 0..steps {
        // 1024 is a multiple of every cycle here (at most 8 fine steps), so every level has
        // just updated at a report.
        let report = k % 1024 == 0;
        s.step_with(&mut NoAux, false, report).unwrap();
        if let Some(e) = report.then(|| s.last_energy()).flatten() {
            let stored = e.kinetic_j + e.strain_j + e.hourglass_j;
            if !stored.is_finite() {
                return f64::INFINITY;
            }
            let e0 = *first.get_or_insert(stored);
            worst = worst.max(stored / e0);
        }
    }
    worst
}

/// 1 mm elements next to 2 mm ones (one level apart), 16 384 fine steps (2.5 ms): single rate
/// keeps the energy, subcycled it grows by orders of magnitude. Measured (2026-11-26): single
/// rate at most 1.000 of the start, subcycled 4.9e9 (about 0.14 % per fine step).
#[test]
fn subcycling_a_graded_block_resonates_where_single_rate_does_not() {
    let steps = 16_384;
    let single = energy_growth(graded_block(&two_sizes(2e-3)), false, steps);
    let multi = energy_growth(graded_block(&two_sizes(2e-3)), true, steps);
    println!("largest energy over {steps} steps: single rate {single:.3}, subcycled {multi:.3e}");
    // Single rate: the stored energy at the reports fluctuates below its start (the kinetic
    // part is taken at the centred velocity); 1.2 leaves room for that and nothing more.
    assert!(single < 1.2, "single rate: {single}");
    // Subcycled: growth by 100 in 16 k steps is an instability, not a fluctuation.
    assert!(multi > 100.0, "subcycled: {multi}");
}

/// The acceptance test for a stable subcycling scheme: blocks with one, two and three levels
/// between their sizes, and a 1-2-4 mm grading, each within 1.5 of its starting energy over
/// 200 000 fine steps (30 ms), as single rate is. Fails today: see the module docs; `.ci/long`
/// records which blocks grow.
#[test]
#[ignore = "fails today: linear-interpolation subcycling is resonance-unstable (module docs)"]
fn subcycled_graded_blocks_keep_their_energy() {
    let steps = 200_000;
    let blocks: Vec<(&str, Vec<f64>)> = vec![
        ("1 | 2 mm", two_sizes(2e-3)),
        ("1 | 2.1 mm", two_sizes(2.1e-3)),
        ("1 | 4 mm", two_sizes(4e-3)),
        ("1 | 4.8 mm", two_sizes(4.8e-3)),
        ("1 | 8.4 mm", two_sizes(8.4e-3)),
        ("1 | 9.6 mm", two_sizes(9.6e-3)),
        (
            "1 | 2.4 | 4.8 mm",
            [vec![1e-3; 10], vec![2.4e-3; 10], vec![4.8e-3; 10]].concat(),
        ),
    ];
    let mut failed = Vec::new();
    for (name, spacings) in blocks {
        let single = energy_growth(graded_block(&spacings), false, steps);
        let multi = energy_growth(graded_block(&spacings), true, steps);
        println!("{name}: largest energy, single rate {single:.3}, subcycled {multi:.3e}");
        assert!(single < 1.2, "{name}: single rate {single}");
        if !(multi < 1.5) {
            failed.push(name);
        }
    }
    assert!(failed.is_empty(), "energy grew under subcycling: {failed:?}");
}
