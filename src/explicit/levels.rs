//! Partition of a model into power-of-two time-step levels, the first stage of multi-rate
//! (subcycled) explicit integration (Belytschko, Yen & Mullen, "Mixed methods for time
//! integration", CMAME 17/18, 1979: a nodal partition; LS-DYNA's subcycling likewise groups
//! elements by powers of two of the smallest step).
//!
//! An element's own level is the largest k with `2^k dt <= c t_e` (at most `max_levels - 1`):
//! `t_e` is its stable step (transit time), `dt = 0.9 t_min` the finest level's step
//! ([`COURANT_FACTOR`] of the smallest transit) and `c` the scheme's `coarse_courant`, so
//! `k = floor(log2(c t_e / (0.9 t_min)))`, and 0 where that is negative. With `c = 0.9` a
//! coarse level steps its elements at their own stable step (the rule before 2026-11-26); the
//! engine's schemes use [`STABLE_COARSE_COURANT`] = 0.5, because the subcycled update resonates
//! at the elements' own steps ([`STABLE_COARSE_COURANT`] gives the measurements). With a level ratio
//! `r = 2^p` above 2 ([`LevelScheme`]) only every p-th of these binary levels is used: the own level
//! is rounded down to a multiple of p, so neighbouring levels step `r` times apart. A node
//! moves at the finest level among its elements, and an element is updated as often as its
//! finest node, so an element next to a finer one is updated at the finer rate (the interface).
//! Nodes that must stay at the finest level (contact slaves and master faces) pull their
//! elements down to level 0.
//!
//! The element work of a multi-rate step of the coarsest level, relative to single-rate
//! stepping at `t_min`, is `sum_k n_k 2^-k / N` (`n_k` elements at level k of N): what
//! subcycling would save on the element forces. The integration itself is
//! [`super::multirate`]'s; its per-level state ([`MultiRate`]) and the element loop of one
//! level (`add_level_forces`) sit here, below the solver that uses them.

use std::ops::Range;

use rayon::prelude::*;

use super::batch::{add_block_forces, ElementBatch};
use super::colour::SharedMut;
pub use crate::mesh::quality::COURANT_FACTOR;
use crate::mesh::P3;
pub use crate::model::time_stepping::{LevelScheme, MAX_BINARY_LEVELS, STABLE_COARSE_COURANT};

/// The levels of a model.
#[derive(Clone, Debug, PartialEq)]
pub struct LevelPartition {
    /// Level of every element (0: the finest, stepping at `t_min`).
    pub element_level: Vec<u8>,
    /// Level of every node: the finest among its elements' own levels (0 for the finest
    /// nodes and for nodes in no element).
    pub node_level: Vec<u8>,
    /// Elements per level.
    pub counts: Vec<usize>,
    /// The smallest stable step (s).
    pub finest_step_s: f64,
    /// Element work of multi-rate stepping relative to single-rate (`sum n_k 2^-k / N`).
    pub element_work_fraction: f64,
}

/// Partitions elements (`elements[e]`: node indices; `transit_s[e]`: stable step) into at most
/// `max_levels` levels, with `finest_nodes` held at level 0 (module documentation).
pub fn partition(
    elements: &[[usize; 8]],
    transit_s: &[f64],
    node_count: usize,
    finest_nodes: &[usize],
    max_levels: usize,
) -> LevelPartition {
    partition_with(
        elements,
        transit_s,
        node_count,
        finest_nodes,
        LevelScheme::binary(max_levels),
    )
}

/// [`partition`] with levels `scheme.ratio` apart (a power of two; a ratio that is not is taken
/// as the power of two below it, so check the scheme first). The partition's levels are the
/// engine's binary ones: with ratio `2^p` only every p-th holds elements.
pub fn partition_with(
    elements: &[[usize; 8]],
    transit_s: &[f64],
    node_count: usize,
    finest_nodes: &[usize],
    scheme: LevelScheme,
) -> LevelPartition {
    assert_eq!(elements.len(), transit_s.len(), "one transit per element");
    let step = scheme.ratio_log2().max(1);
    let max_levels = scheme.binary_levels().clamp(1, MAX_BINARY_LEVELS);
    let finest_step_s = transit_s
        .iter()
        .copied()
        .filter(|t| *t > 0.0)
        .fold(f64::INFINITY, f64::min);
    let own: Vec<u8> = transit_s
        .iter()
        .map(|&t| {
            // 2^k dt <= c t_e with dt = COURANT_FACTOR t_min (module docs).
            let ratio = (t / finest_step_s * scheme.coarse_courant / COURANT_FACTOR).max(1.0);
            // 1e-12: an element exactly at 2^k t_min stays at level k despite rounding.
            let binary = (ratio.log2() + 1e-12).floor().min((max_levels - 1) as f64) as usize;
            (binary / step * step) as u8
        })
        .collect();
    let mut node_level = vec![u8::MAX; node_count];
    for (e, nodes) in elements.iter().enumerate() {
        for &n in nodes {
            node_level[n] = node_level[n].min(own[e]);
        }
    }
    for &n in finest_nodes {
        if n < node_count {
            node_level[n] = 0;
        }
    }
    for l in node_level.iter_mut().filter(|l| **l == u8::MAX) {
        *l = 0;
    }
    let element_level: Vec<u8> = elements
        .iter()
        .map(|nodes| nodes.iter().map(|&n| node_level[n]).min().unwrap_or(0))
        .collect();
    let mut counts = vec![0usize; max_levels];
    for &l in &element_level {
        counts[l as usize] += 1;
    }
    while counts.len() > 1 && counts[counts.len() - 1] == 0 {
        counts.pop();
    }
    let total = elements.len().max(1) as f64;
    let element_work_fraction = counts
        .iter()
        .enumerate()
        .map(|(k, &c)| c as f64 / 2f64.powi(k as i32))
        .sum::<f64>()
        / total;
    LevelPartition {
        element_level,
        node_level,
        counts,
        finest_step_s,
        element_work_fraction,
    }
}

/// Per-level work totals of a multi-rate run (J), for the per-level energy balance
/// ([`super::multirate`], "Energy by level"). Levels above 0 only: level 0's balance is what
/// remains of the whole model's.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LevelWork {
    /// Work done on the level's nodes by gravity, the auxiliary forces and the reactions, less
    /// what mass damping took from them.
    pub external_j: [f64; MAX_BINARY_LEVELS],
    /// Energy the level's elements took in through other levels' nodes, less what other
    /// levels' elements took in through the level's nodes: the transfer across the level's
    /// interfaces. Sums to zero over the levels.
    pub transfer_j: [f64; MAX_BINARY_LEVELS],
}

impl LevelWork {
    /// `self + s o`.
    pub(super) fn add_scaled(&mut self, o: &LevelWork, s: f64) {
        for k in 0..MAX_BINARY_LEVELS {
            self.external_j[k] += s * o.external_j[k];
            self.transfer_j[k] += s * o.transfer_j[k];
        }
    }
}

/// Where the internal force of an interface node comes from, level by level: an interface
/// node is a node of level k >= 1 with elements of a finer level. At its updates (steps that
/// are multiples of `2^k`) every level up to k is evaluated, finest first, into `f_int`; its
/// `k` slots hold `f_int` after each finer level j < k, so that differences of neighbouring
/// slots are the force of each finer level's elements on it.
#[derive(Clone, Debug, Default)]
pub(super) struct LevelInterface {
    /// Per node, its first slot in `force_after_level` (`u32::MAX`: not an interface node).
    pub(super) base: Vec<u32>,
    /// Per level j, `(node, slot)` of the interface nodes coarser than j: where `f_int` is
    /// recorded after level j's elements.
    pub(super) record: Vec<Vec<(u32, u32)>>,
    /// The recorded forces (N).
    pub(super) force_after_level: Vec<P3>,
}

impl LevelInterface {
    /// At the update of node `nd` of level `level` over `dt_node` with centred velocity
    /// `vbar`: the work of each finer level's elements on it, `dt_k (F_j - F_(j-1)) . vbar`,
    /// moves energy from this level to level j (nothing for a node that is not an interface
    /// node).
    #[inline]
    pub(super) fn add_transfer(
        &self,
        nd: usize,
        level: usize,
        dt_node: f64,
        vbar: &P3,
        work: &mut LevelWork,
    ) {
        let base = self.base[nd];
        if base == u32::MAX {
            return;
        }
        let mut before = [0.0; 3];
        for j in 0..level {
            let after = self.force_after_level[base as usize + j];
            let mut w = 0.0;
            for i in 0..3 {
                w += dt_node * (after[i] - before[i]) * vbar[i];
            }
            // The finer level's elements took `w` in through this level's node.
            work.transfer_j[j] += w;
            work.transfer_j[level] -= w;
            before = after;
        }
    }

    /// The interface nodes of `partition` over `elements`.
    pub(super) fn new(elements: &[[usize; 8]], partition: &LevelPartition) -> Self {
        let node_level = &partition.node_level;
        let levels = partition.counts.len();
        let mut finest_element = node_level.clone();
        for (e, nodes) in elements.iter().enumerate() {
            for &n in nodes {
                finest_element[n] = finest_element[n].min(partition.element_level[e]);
            }
        }
        let mut base = vec![u32::MAX; node_level.len()];
        let mut record = vec![Vec::new(); levels];
        let mut slots = 0u32;
        for (n, &k) in node_level.iter().enumerate() {
            if k == 0 || finest_element[n] >= k {
                continue;
            }
            base[n] = slots;
            for (j, list) in record.iter_mut().enumerate().take(k as usize) {
                list.push((n as u32, slots + j as u32));
            }
            slots += k as u32;
        }
        LevelInterface {
            base,
            record,
            force_after_level: vec![[0.0; 3]; slots as usize],
        }
    }
}

/// The multi-rate state of a solver ([`super::multirate`]).
#[derive(Clone, Debug)]
pub struct MultiRate {
    /// The partition: element levels, counts, work fraction.
    pub partition: LevelPartition,
    /// Level of every node.
    pub node_level: Vec<u8>,
    /// Per level, its colours: ranges of the solver's element batches (the batches are
    /// ordered by level).
    pub(super) level_colours: Vec<Vec<Vec<Range<usize>>>>,
    /// Acceleration of each node at its last update (output between updates).
    pub(super) last_acceleration: Vec<P3>,
    /// Nodes that have not updated since multi-rate stepping began: their velocity is that of
    /// the last fine half step, so their first update spans `(dt_k + dt) / 2` (a start like
    /// the central difference's own first half step).
    pub(super) first_update_pending: Vec<bool>,
    /// Every node has updated once by this step: the pending flags need no look after it.
    pub(super) first_updates_end_step: u64,
    /// The interface nodes' forces by level, for the transfer across levels.
    pub(super) interface: LevelInterface,
    /// Per-level work up to t_{n-1/2}.
    pub(super) level_work: LevelWork,
    /// Per-level work up to t_n of the last energy report.
    pub(super) level_work_at_report: LevelWork,
    /// Per level, energy less work at the first per-level balance: its baseline.
    pub(super) level_baseline: Option<[f64; MAX_BINARY_LEVELS]>,
}

impl MultiRate {
    /// Number of levels.
    pub fn levels(&self) -> usize {
        self.level_colours.len()
    }

    /// The steps at which every level updates: multiples of this.
    pub fn full_cycle_steps(&self) -> u64 {
        1u64 << (self.levels().max(1) - 1)
    }
}

/// The forces of one level's elements into `f`: its colours one after another, the blocks of a
/// colour in parallel (they share no node).
pub(super) fn add_level_forces(
    batches: &[ElementBatch],
    colours: &[Vec<Range<usize>>],
    u: &[P3],
    f: SharedMut<P3>,
    physical_hourglass: bool,
    avx2: bool,
) {
    for colour in colours {
        colour.par_iter().for_each(|range| {
            // SAFETY: blocks of one colour share no node; indices come from the mesh.
            unsafe {
                add_block_forces(
                    &batches[range.clone()],
                    u,
                    f.ptr(),
                    physical_hourglass,
                    avx2,
                )
            }
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A bar of 8 elements in a row sharing faces (nodes 4i..4i+8), transits doubling along it:
    /// own levels 0, 1, 2, ... but each element follows its finest neighbour.
    fn bar(transits: &[f64]) -> (Vec<[usize; 8]>, usize) {
        let elements = (0..transits.len())
            .map(|i| std::array::from_fn(|a| 4 * i + a))
            .collect();
        (elements, 4 * transits.len() + 4)
    }

    #[test]
    fn levels_follow_the_finest_neighbour_and_the_work_fraction_counts_them() {
        // Level k >= 1 needs a transit of 2^k x 0.9 / 0.5 = 1.8 x 2^k the smallest.
        let transits = [1.0, 3.6, 7.2, 14.4, 14.4, 14.4, 14.4, 14.4];
        let (elements, nodes) = bar(&transits);
        let p = partition(&elements, &transits, nodes, &[], 8);
        // Element i shares its first four nodes with element i-1: levels 0, 0, 1, 2, 3, 3, 3, 3.
        assert_eq!(p.element_level, vec![0, 0, 1, 2, 3, 3, 3, 3]);
        assert_eq!(p.counts, vec![2, 1, 1, 4]);
        let work = (2.0 + 0.5 + 0.25 + 4.0 / 8.0) / 8.0;
        assert!((p.element_work_fraction - work).abs() < 1e-15);
        // Capped at two levels; a finest node (the last element's far face) pulls it down.
        let p = partition(&elements, &transits, nodes, &[nodes - 1], 2);
        assert_eq!(p.element_level, vec![0, 0, 1, 1, 1, 1, 1, 0]);
        // Uniform transits: one level, no saving.
        let p = partition(&elements, &[3.0; 8], nodes, &[], 8);
        assert_eq!((p.counts.clone(), p.element_work_fraction), (vec![8], 1.0));
    }

    /// Every element of a level k >= 1 has `2^k dt <= coarse_courant x t_e` (dt = 0.9 of the
    /// smallest transit), and the largest such k: checked on transits around the thresholds;
    /// with the elements' own step (0.9) the historic `floor(log2(t_e / t_min))`; and a
    /// `coarse_courant` outside (0, 0.9] refused naming the field.
    #[test]
    fn coarse_levels_keep_their_share_of_the_stable_step() {
        let transits = [1.0, 1.79, 1.81, 3.59, 3.61, 7.21, 14.5, 30.0];
        // One element per bar, so that no neighbour pulls a level down.
        let elements: Vec<[usize; 8]> = (0..transits.len())
            .map(|e| std::array::from_fn(|a| 8 * e + a))
            .collect();
        let nodes = 8 * transits.len();
        for (c, expected) in [
            (STABLE_COARSE_COURANT, vec![0, 0, 0, 0, 1, 2, 3, 4]),
            (COURANT_FACTOR, vec![0, 0, 0, 1, 1, 2, 3, 4]),
        ] {
            let scheme = LevelScheme::binary(8).with_coarse_courant(c);
            let p = partition_with(&elements, &transits, nodes, &[], scheme);
            assert_eq!(p.element_level, expected, "coarse_courant {c}");
            let dt = COURANT_FACTOR * 1.0;
            for (e, &l) in p.element_level.iter().enumerate() {
                let step = dt * f64::from(1u32 << l);
                if l > 0 {
                    assert!(step <= c * transits[e] * (1.0 + 1e-12), "element {e}");
                }
                assert!(
                    2.0 * step > c * transits[e] || l == 0,
                    "element {e} could be coarser"
                );
            }
        }
        for bad in [0.0, -0.5, 0.95, f64::NAN] {
            let e = LevelScheme::binary(4)
                .with_coarse_courant(bad)
                .check("case.json", "time_stepping.")
                .unwrap_err()
                .to_string();
            assert!(e.contains("time_stepping.coarse_courant"), "{e}");
        }
    }

    #[test]
    fn a_level_ratio_of_four_uses_every_second_binary_level() {
        let transits = [1.0, 2.0, 4.0, 8.0, 16.0, 16.0, 16.0, 16.0];
        let (elements, nodes) = bar(&transits);
        let scheme = LevelScheme {
            max_levels: 8,
            ratio: 4,
            coarse_courant: COURANT_FACTOR,
        };
        let p = partition_with(&elements, &transits, nodes, &[], scheme);
        // Own binary levels 0..4 rounded down to even: 0, 0, 2, 2, 4, 4, 4, 4; each element
        // follows its finer neighbour.
        assert_eq!(p.element_level, vec![0, 0, 0, 2, 2, 4, 4, 4]);
        assert_eq!(p.counts, vec![3, 0, 2, 0, 3]);
        let work = (3.0 + 2.0 / 4.0 + 3.0 / 16.0) / 8.0;
        assert!((p.element_work_fraction - work).abs() < 1e-15);
        // Two levels four apart: nothing beyond binary level 2.
        let two = LevelScheme {
            max_levels: 2,
            ratio: 4,
            coarse_courant: COURANT_FACTOR,
        };
        let p = partition_with(&elements, &transits, nodes, &[], two);
        assert_eq!(p.element_level, vec![0, 0, 0, 2, 2, 2, 2, 2]);
        // The binary scheme is `partition`'s.
        assert_eq!(
            partition_with(&elements, &transits, nodes, &[], LevelScheme::binary(8)),
            partition(&elements, &transits, nodes, &[], 8)
        );
    }

    #[test]
    fn a_level_ratio_that_is_not_a_power_of_two_is_refused() {
        for ratio in [0, 1, 3, 6, 12] {
            let e = LevelScheme {
                max_levels: 4,
                ratio,
                coarse_courant: STABLE_COARSE_COURANT,
            }
            .check("case.json", "time_stepping.")
            .unwrap_err()
            .to_string();
            assert!(
                e.contains("case.json") && e.contains("time_stepping.level_ratio"),
                "{e}"
            );
            assert!(
                e.contains("power of two") && e.contains(&format!("got {ratio}")),
                "{e}"
            );
        }
        // 16 binary levels at most: 8 levels four apart need 15, 9 need 17.
        let ok = LevelScheme {
            max_levels: 8,
            ratio: 4,
            coarse_courant: COURANT_FACTOR,
        };
        assert!(ok.check("c", "").is_ok());
        let e = LevelScheme {
            max_levels: 9,
            ratio: 4,
            coarse_courant: STABLE_COARSE_COURANT,
        }
        .check("c", "")
        .unwrap_err()
        .to_string();
        assert!(e.contains("max_levels") && e.contains("[1, 8]"), "{e}");
        assert!(LevelScheme::binary(16).check("c", "").is_ok());
        assert!(LevelScheme::binary(17).check("c", "").is_err());
        assert!(LevelScheme::binary(0).check("c", "").is_err());
        let widest = LevelScheme {
            max_levels: 2,
            ratio: 32768,
            coarse_courant: STABLE_COARSE_COURANT,
        };
        assert!(widest.check("c", "").is_ok());
    }
}
