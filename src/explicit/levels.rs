//! Partition of a model into power-of-two time-step levels, the first stage of multi-rate
//! (subcycled) explicit integration (Belytschko, Yen & Mullen, "Mixed methods for time
//! integration", CMAME 17/18, 1979: a nodal partition; LS-DYNA's subcycling likewise groups
//! elements by powers of two of the smallest step).
//!
//! An element's own level is `floor(log2(t_e / t_min))`, `t_e` its stable step (transit time)
//! and `t_min` the smallest over the model, capped at `max_levels - 1`. A node moves at the
//! finest level among its elements, and an element is updated as often as its finest node,
//! so an element next to a finer one is updated at the finer rate (the interface). Nodes that
//! must stay at the finest level (contact slaves and master faces) pull their elements down
//! to level 0.
//!
//! The element work of a multi-rate step of the coarsest level, relative to single-rate
//! stepping at `t_min`, is `sum_k n_k 2^-k / N` (`n_k` elements at level k of N): what
//! subcycling would save on the element forces. This module reports the partition; the engine
//! does not integrate multi-rate yet.

/// The levels of a model.
#[derive(Clone, Debug, PartialEq)]
pub struct LevelPartition {
    /// Level of every element (0: the finest, stepping at `t_min`).
    pub element_level: Vec<u8>,
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
    assert_eq!(elements.len(), transit_s.len(), "one transit per element");
    let max_levels = max_levels.clamp(1, 16);
    let finest_step_s = transit_s
        .iter()
        .copied()
        .filter(|t| *t > 0.0)
        .fold(f64::INFINITY, f64::min);
    let own: Vec<u8> = transit_s
        .iter()
        .map(|&t| {
            let ratio = (t / finest_step_s).max(1.0);
            // 1e-12: an element exactly at 2^k t_min stays at level k despite rounding.
            (ratio.log2() + 1e-12).floor().min((max_levels - 1) as f64) as u8
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
        counts,
        finest_step_s,
        element_work_fraction,
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
        let transits = [1.0, 2.0, 4.0, 8.0, 8.0, 8.0, 8.0, 8.0];
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
}
