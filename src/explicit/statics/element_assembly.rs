//! The elements' share of the static tangent, assembled in parallel. The reduced-node columns
//! are split into [`COLUMN_RANGES`] fixed ranges; one task writes one range's values, from the
//! elements that touch it, in element order. Every entry thus sums the same terms in the same
//! order as a serial pass over the elements: the tangent is the serial one bit for bit, whatever
//! the thread count. An element whose nodes lie in two ranges is evaluated by both tasks (on a
//! mesh numbered with locality, a small share).

use rayon::prelude::*;

use super::dofs::ReducedDofs;
use super::stiffness::{Block, Tangent};
use crate::explicit::element::OnePointElement;
use crate::explicit::linearised::one_point_stiffness;
use crate::explicit::Solver;

/// Column ranges (fixed, so that the split never depends on the thread count).
pub(super) const COLUMN_RANGES: usize = 64;

/// Adds the elements' stiffness `Tᵀ K_e T` to `tangent`, the columns in `ranges` parts.
pub(super) fn add_elements(
    solver: &Solver,
    dofs: &ReducedDofs,
    elements: &[OnePointElement],
    physical_hourglass: bool,
    ranges: usize,
    tangent: &mut Tangent,
) {
    let n = dofs.len();
    let ranges = ranges.clamp(1, n.max(1));
    let bounds: Vec<usize> = (0..=ranges).map(|k| k * n / ranges).collect();
    let range_of = |r: u32| bounds.partition_point(|&b| b <= r as usize) - 1;
    // The elements touching each range (a node's column holds its pairs with later nodes).
    let mut lists: Vec<Vec<u32>> = vec![Vec::new(); ranges];
    let mut buf = [(0u32, 0.0f64); 4];
    for (e, el) in elements.iter().enumerate() {
        let mut touched: Vec<usize> = Vec::with_capacity(8);
        for &nd in &el.nodes {
            let k = dofs.expand(solver, nd as usize, &mut buf);
            touched.extend(buf[..k].iter().map(|&(r, _)| range_of(r)));
        }
        touched.sort_unstable();
        touched.dedup();
        for k in touched {
            lists[k].push(e as u32);
        }
    }
    let mut values = std::mem::take(&mut tangent.values);
    let pattern: &Tangent = tangent;
    let mut parts: Vec<(usize, &mut [f64])> = Vec::with_capacity(ranges);
    let mut rest: &mut [f64] = &mut values;
    let mut consumed = 0;
    for k in 0..ranges {
        let span = pattern.value_range(bounds[k], bounds[k + 1]);
        let (head, tail) = std::mem::take(&mut rest).split_at_mut(span.end - consumed);
        parts.push((span.start, head));
        rest = tail;
        consumed = span.end;
    }
    parts
        .into_par_iter()
        .zip(lists.par_iter())
        .enumerate()
        .for_each(|(k, ((base, part), list))| {
            let (c0, c1) = (bounds[k], bounds[k + 1]);
            for &e in list {
                let el = &elements[e as usize];
                let stiffness = one_point_stiffness(el, physical_hourglass);
                let mut expanded = [([(0u32, 0.0f64); 4], 0usize); 8];
                for (a, &nd) in el.nodes.iter().enumerate() {
                    let mut b = [(0u32, 0.0f64); 4];
                    let count = dofs.expand(solver, nd as usize, &mut b);
                    expanded[a] = (b, count);
                }
                // The serial order: node pairs (a, b), then their expansions.
                for a in 0..8 {
                    for b in 0..8 {
                        let (ea, ka) = &expanded[a];
                        let (eb, kb) = &expanded[b];
                        for &(ra, wa) in &ea[..*ka] {
                            for &(rb, wb) in &eb[..*kb] {
                                if ra < rb || (rb as usize) < c0 || (rb as usize) >= c1 {
                                    continue;
                                }
                                let w = wa * wb;
                                let block: Block = std::array::from_fn(|i| {
                                    std::array::from_fn(|m| w * stiffness[3 * a + i][3 * b + m])
                                });
                                pattern.add_to(part, base, dofs, ra, rb, &block);
                            }
                        }
                    }
                }
            }
        });
    tangent.values = values;
}

#[cfg(test)]
mod tests {
    use std::collections::BTreeMap;

    use super::super::assembly::{add_node_blocks, base_keys};
    use super::*;
    use crate::explicit::element::{ElasticMaterial, Formulation};
    use crate::explicit::model::{Elements, Model};

    /// The parallel assembly against the serial pass it replaces (`add_node_blocks` element by
    /// element): bit for bit, for range counts that split the columns evenly, unevenly, into
    /// one range, and into more ranges than a thread pool has threads.
    #[test]
    fn parallel_element_assembly_is_the_serial_one_bit_for_bit() {
        let steel: BTreeMap<u32, ElasticMaterial> = [(1, ElasticMaterial::steel())].into();
        let mesh = crate::mesh::cuboid([7, 4, 3], [0.7, 0.3, 0.2], 1);
        let model = Model::from_mesh(mesh, &steel, Formulation::default(), "test").unwrap();
        let solver = Solver::new(model, None).unwrap();
        let dofs = ReducedDofs::new(&solver, &[]).unwrap();
        let keys = base_keys(&solver, &dofs);
        let Elements::OnePoint(els) = &solver.model.elements else {
            panic!("the default formulation is the one-point element")
        };
        let physical = solver.model.physical_hourglass;
        let mut serial = Tangent::from_keys(dofs.len(), &keys);
        for el in els {
            let k = one_point_stiffness(el, physical);
            let nodes = el.nodes.map(|x| x as usize);
            add_node_blocks(
                &solver,
                &dofs,
                &nodes,
                |a, b| std::array::from_fn(|i| std::array::from_fn(|m| k[3 * a + i][3 * b + m])),
                &mut serial,
            );
        }
        assert!(serial.values.iter().any(|&v| v != 0.0));
        for ranges in [1, 3, 7, COLUMN_RANGES, 10_000] {
            let mut parallel = Tangent::from_keys(dofs.len(), &keys);
            add_elements(&solver, &dofs, els, physical, ranges, &mut parallel);
            let same = serial
                .values
                .iter()
                .zip(&parallel.values)
                .all(|(a, b)| a.to_bits() == b.to_bits());
            assert!(same, "{ranges} ranges");
        }
    }
}
