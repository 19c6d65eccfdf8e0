//! The static tangent's pattern and values.
//!
//! - Pattern: the pair keys of the elements and springs ([`base_keys`]), of the rank-one
//!   (contact) terms ([`term_keys`]) and of the ring reserved around the contact so that the
//!   active set can grow without a new pattern ([`widened_contact_keys`]).
//! - Values: `Tᵀ (K_el + K_springs + sum_j k_j b_j b_jᵀ) T + m omega_r^2` with the held
//!   directions' pivots ([`assemble`]); when only the rank-one terms changed on the same
//!   pattern, the old terms are taken out and the new ones put in ([`update_terms`]): the
//!   elements' stiffness is linearised at the reference state, so it is the same at every
//!   Newton step and is assembled once per pattern.

// Index loops mirror the block layout (direction indices i, m).
#![allow(clippy::needless_range_loop)]

use rayon::prelude::*;

use super::super::aux::RankOneStiffness;
use super::super::model::Elements;
use super::super::solver::Solver;
use super::dofs::ReducedDofs;
use super::element_assembly;
use super::stiffness::{pair_key, Block, Tangent};

/// Pair keys of a list of mesh nodes (every pair of their reduced nodes).
fn node_list_keys(solver: &Solver, dofs: &ReducedDofs, nodes: &[usize], out: &mut Vec<u64>) {
    let mut reduced: Vec<u32> = Vec::with_capacity(4 * nodes.len());
    let mut buf = [(0u32, 0.0f64); 4];
    for &nd in nodes {
        let k = dofs.expand(solver, nd, &mut buf);
        reduced.extend(buf[..k].iter().map(|e| e.0));
    }
    reduced.sort_unstable();
    reduced.dedup();
    for (j, &a) in reduced.iter().enumerate() {
        for &b in &reduced[j..] {
            out.push(pair_key(a, b));
        }
    }
}

/// Sorted pair keys of the elements and springs.
pub(super) fn base_keys(solver: &Solver, dofs: &ReducedDofs) -> Vec<u64> {
    let model = &solver.model;
    let mut keys: Vec<u64> = (0..model.elements.len())
        .into_par_iter()
        .fold(Vec::new, |mut out, e| {
            let nodes = model.elements.nodes(e).map(|x| x as usize);
            node_list_keys(solver, dofs, &nodes, &mut out);
            out
        })
        .reduce(Vec::new, |mut a, b| {
            a.extend_from_slice(&b);
            a
        });
    for s in &model.springs {
        let nodes: Vec<usize> = std::iter::once(s.node_a).chain(s.node_b).collect();
        node_list_keys(solver, dofs, &nodes, &mut keys);
    }
    keys.par_sort_unstable();
    keys.dedup();
    keys
}

/// The nodes of each rank-one term, in order: what identifies an active set.
pub(super) fn term_signature(terms: &[RankOneStiffness]) -> Vec<[usize; 5]> {
    terms.iter().map(|t| t.nodes).collect()
}

/// Pair keys between every reduced node within one element of a term's slave and every one
/// within one element of its face (the node graph of the element and spring pattern `keys`).
pub(super) fn widened_contact_keys(
    keys: &[u64],
    n: usize,
    solver: &Solver,
    dofs: &ReducedDofs,
    terms: &[RankOneStiffness],
) -> Vec<u64> {
    let mut is_slave = vec![false; n];
    let mut is_face = vec![false; n];
    let mut buf = [(0u32, 0.0f64); 4];
    for t in terms {
        for j in 0..5 {
            if t.coefficients[j] == 0.0 {
                continue;
            }
            let k = dofs.expand(solver, t.nodes[j], &mut buf);
            for &(r, _) in &buf[..k] {
                if j == 0 {
                    is_slave[r as usize] = true;
                } else {
                    is_face[r as usize] = true;
                }
            }
        }
    }
    // One ring: a node joins a side when a pattern pair links it to a node of that side.
    let (mut slaves, mut faces) = (is_slave.clone(), is_face.clone());
    for &key in keys {
        let (c, r) = ((key >> 32) as usize, (key & 0xffff_ffff) as usize);
        for (a, b) in [(c, r), (r, c)] {
            slaves[a] |= is_slave[b];
            faces[a] |= is_face[b];
        }
    }
    let slave_nodes: Vec<u32> = (0..n as u32).filter(|&r| slaves[r as usize]).collect();
    let face_nodes: Vec<u32> = (0..n as u32).filter(|&r| faces[r as usize]).collect();
    let mut out = Vec::with_capacity(slave_nodes.len() * face_nodes.len());
    for &a in &slave_nodes {
        for &b in &face_nodes {
            out.push(pair_key(a, b));
        }
    }
    out
}

/// Pair keys of the rank-one terms.
pub(super) fn term_keys(
    solver: &Solver,
    dofs: &ReducedDofs,
    terms: &[RankOneStiffness],
) -> Vec<u64> {
    let mut keys = Vec::new();
    for t in terms {
        let nodes: Vec<usize> = (0..5)
            .filter(|&j| t.coefficients[j] != 0.0)
            .map(|j| t.nodes[j])
            .collect();
        node_list_keys(solver, dofs, &nodes, &mut keys);
    }
    keys.sort_unstable();
    keys.dedup();
    keys
}

/// Adds the node blocks `blocks[a][b]` (row node `nodes[a]`, column node `nodes[b]`, all
/// ordered pairs) through the constraint map: each lands in the lower block of its reduced
/// pair once (a pair `r < c` is added by its mirror `(c, r)`).
pub(super) fn add_node_blocks(
    solver: &Solver,
    dofs: &ReducedDofs,
    nodes: &[usize],
    block: impl Fn(usize, usize) -> Block,
    tangent: &mut Tangent,
) {
    let mut expanded = vec![([(0u32, 0.0f64); 4], 0usize); nodes.len()];
    for (a, &nd) in nodes.iter().enumerate() {
        let mut buf = [(0u32, 0.0f64); 4];
        let k = dofs.expand(solver, nd, &mut buf);
        expanded[a] = (buf, k);
    }
    for a in 0..nodes.len() {
        for b in 0..nodes.len() {
            let kab = block(a, b);
            let (ea, ka) = &expanded[a];
            let (eb, kb) = &expanded[b];
            for &(ra, wa) in &ea[..*ka] {
                for &(rb, wb) in &eb[..*kb] {
                    if ra < rb {
                        continue;
                    }
                    let w = wa * wb;
                    let scaled: Block = kab.map(|row| row.map(|x| w * x));
                    tangent.add(dofs, ra, rb, &scaled);
                }
            }
        }
    }
}

/// The tangent's values: elements, springs, rank-one terms, regularisation, held diagonals.
pub(super) fn assemble(
    solver: &Solver,
    dofs: &ReducedDofs,
    terms: &[RankOneStiffness],
    regularisation_hz: f64,
    tangent: &mut Tangent,
) {
    tangent.clear();
    let model = &solver.model;
    if let Elements::OnePoint(els) = &model.elements {
        element_assembly::add_elements(
            solver,
            dofs,
            els,
            model.physical_hourglass,
            element_assembly::COLUMN_RANGES,
            tangent,
        );
    }
    for s in &model.springs {
        let nodes: Vec<usize> = std::iter::once(s.node_a).chain(s.node_b).collect();
        let k = s.stiffness_n_per_m;
        add_node_blocks(
            solver,
            dofs,
            &nodes,
            |a, b| {
                let sign = if a == b { 1.0 } else { -1.0 };
                std::array::from_fn(|i| {
                    std::array::from_fn(|m| if i == m { sign * k[i] } else { 0.0 })
                })
            },
            tangent,
        );
    }
    add_terms(solver, dofs, terms, 1.0, tangent);
    add_regularisation(dofs, regularisation_hz, tangent);
    set_held_pivots(dofs, tangent);
}

/// The regularisation `m omega_r^2` on the diagonal of every direction not held.
fn add_regularisation(dofs: &ReducedDofs, regularisation_hz: f64, tangent: &mut Tangent) {
    let omega_r = 2.0 * std::f64::consts::PI * regularisation_hz;
    for r in 0..dofs.len() {
        for i in 0..3 {
            if !dofs.held[r][i] {
                tangent.add_diagonal(r, i, dofs.mass_kg[r] * omega_r * omega_r);
            }
        }
    }
}

/// Held directions: a unit pivot at the matrix's scale, the mean diagonal of the directions
/// not held (their right-hand side is zero, so the value only keeps the matrix's scale).
fn set_held_pivots(dofs: &ReducedDofs, tangent: &mut Tangent) {
    let mut diagonal_sum = 0.0;
    let mut count = 0usize;
    for r in 0..dofs.len() {
        for i in 0..3 {
            if !dofs.held[r][i] {
                diagonal_sum += tangent.diagonal(r, i);
                count += 1;
            }
        }
    }
    let scale = if count > 0 {
        diagonal_sum / count as f64
    } else {
        1.0
    };
    for r in 0..dofs.len() {
        for i in 0..3 {
            if dofs.held[r][i] {
                tangent.set_diagonal(r, i, scale);
            }
        }
    }
}

/// The tangent assembled with the rank-one terms `old` turned into one with `new`, on the same
/// pattern: `old` subtracted, `new` added, the held pivots set again. The elements, springs and
/// regularisation, which do not change between Newton steps (the elements' stiffness is
/// linearised at the reference state), are not assembled again. The values are the full
/// assembly's up to the rounding of `old`'s subtraction (`tests` below).
pub(super) fn update_terms(
    solver: &Solver,
    dofs: &ReducedDofs,
    old: &[RankOneStiffness],
    new: &[RankOneStiffness],
    tangent: &mut Tangent,
) {
    add_terms(solver, dofs, old, -1.0, tangent);
    add_terms(solver, dofs, new, 1.0, tangent);
    set_held_pivots(dofs, tangent);
}

/// `sign` times the rank-one terms `k (c_a c_b) n nᵀ` on their nodes' blocks.
fn add_terms(
    solver: &Solver,
    dofs: &ReducedDofs,
    terms: &[RankOneStiffness],
    sign: f64,
    tangent: &mut Tangent,
) {
    for t in terms {
        let used: Vec<usize> = (0..5).filter(|&j| t.coefficients[j] != 0.0).collect();
        let nodes: Vec<usize> = used.iter().map(|&j| t.nodes[j]).collect();
        let n = t.direction;
        add_node_blocks(
            solver,
            dofs,
            &nodes,
            |a, b| {
                let s = sign
                    * (t.stiffness_n_per_m * t.coefficients[used[a]] * t.coefficients[used[b]]);
                std::array::from_fn(|i| std::array::from_fn(|m| s * n[i] * n[m]))
            },
            tangent,
        );
    }
}

#[cfg(test)]
mod tests {
    use std::collections::BTreeMap;

    use super::*;
    use crate::explicit::element::{ElasticMaterial, Formulation};
    use crate::explicit::model::Model;
    use crate::random::XorShift64;

    /// `count` rank-one terms like the contact's: a node and four others with weights, a
    /// random unit direction, a stiffness of the elements' order.
    fn random_terms(rng: &mut XorShift64, nodes: usize, count: usize) -> Vec<RankOneStiffness> {
        (0..count)
            .map(|_| {
                let d = [0, 1, 2].map(|_| rng.centred_uniform());
                let norm = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
                let w = [0, 1, 2, 3].map(|_| 0.1 + rng.centred_uniform().abs());
                let sum: f64 = w.iter().sum();
                RankOneStiffness {
                    stiffness_n_per_m: 1e9 * (1.0 + rng.centred_uniform().abs()),
                    direction: d.map(|x| x / norm),
                    nodes: [0, 1, 2, 3, 4].map(|_| rng.below(nodes)),
                    coefficients: [1.0, -w[0] / sum, -w[1] / sum, -w[2] / sum, -w[3] / sum],
                }
            })
            .collect()
    }

    /// The tangent with the rank-one terms of one active set replaced by another's
    /// ([`update_terms`]) against the full assembly with the second set, on a steel block
    /// with its base held (so that the held pivots, which follow the mean diagonal, must be
    /// set again). They differ by the rounding of taking the old terms out,
    /// `2 eps (|K| + |k b bᵀ|)` per entry: 1e-12 of the largest entry allows it with room,
    /// while a term left in or out, or a stale pivot, is off by 1e-4 of it or more.
    #[test]
    fn updated_terms_are_the_full_assembly_to_rounding() {
        let steel: BTreeMap<u32, ElasticMaterial> = [(1, ElasticMaterial::steel())].into();
        let mesh = crate::mesh::cuboid([5, 4, 3], [0.5, 0.3, 0.2], 1);
        let mut model = Model::from_mesh(mesh, &steel, Formulation::default(), "test").unwrap();
        model.fix_set("z0", [true, true, true]).unwrap();
        let solver = Solver::new(model, None).unwrap();
        let dofs = ReducedDofs::new(&solver, &[]).unwrap();
        let nodes = solver.u.len();
        let mut rng = XorShift64::seeded(11);
        let old = random_terms(&mut rng, nodes, 12);
        let mut new = random_terms(&mut rng, nodes, 9);
        // Part of the set stays active, as in a Newton step of the contact.
        new.extend_from_slice(&old[..4]);
        let mut keys = base_keys(&solver, &dofs);
        keys.extend(term_keys(&solver, &dofs, &old));
        keys.extend(term_keys(&solver, &dofs, &new));
        keys.sort_unstable();
        keys.dedup();
        let mut updated = Tangent::from_keys(dofs.len(), &keys);
        assemble(&solver, &dofs, &old, 0.1, &mut updated);
        let before = updated.values.clone();
        update_terms(&solver, &dofs, &old, &new, &mut updated);
        let mut full = Tangent::from_keys(dofs.len(), &keys);
        assemble(&solver, &dofs, &new, 0.1, &mut full);
        let largest = full.values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let worst = updated
            .values
            .iter()
            .zip(&full.values)
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        let moved = before
            .iter()
            .zip(&full.values)
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        assert!(dofs.held.iter().flatten().any(|h| *h));
        assert!(moved > 1e-4 * largest, "the two sets differ: {moved:e}");
        assert!(worst <= 1e-12 * largest, "{worst:e} of {largest:e}");
    }
}
