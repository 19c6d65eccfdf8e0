//! The approach step: a body that nothing holds yet (a wheelset hanging over its rail before
//! the contact closes) is moved towards its support by a rigid translation, without a linear
//! solve.
//!
//! Bodies. The reduced nodes are grouped into components: nodes joined by an element, by a
//! spring between two nodes, by a tie (a slave's masters) or by a rank-one (contact) term. A
//! component is *free* in direction `i` when none of its reduced nodes is held in `i` and no
//! ground spring on it has stiffness in `i`.
//!
//! Why the translation needs no solve. Let `z` be the translation of a free component `c` in
//! direction `i` (one on its nodes, zero elsewhere). The elements and the springs inside `c`
//! do not resist it (`K z = 0`), so the tangent `K_T = K + omega_r^2 M` sees it only through
//! the regularisation, and `zᵀ K_T dq = zᵀ R` reads `omega_r^2 zᵀ M dq = zᵀ R`: the Newton
//! step's mass-weighted mean translation of `c` is exactly
//! `a_i = F_i / (omega_r^2 M_c)`, with `F_i` the component's resultant out-of-balance force
//! and `M_c` its regularisation mass. The rest of the step (the bodies' deformation) has energy
//! `(omega_r / omega_1)^2` times smaller than the translation's, `omega_1` the body's lowest
//! elastic frequency, which the regularisation must stay far below anyway.
//!
//! When the translation alone exceeds `max_increment_m`, the Newton step is one the
//! regularisation carries and the solver would scale it down to `max_increment_m`
//! (`cap_increment`): the deformation, scaled by the same factor, is then below
//! `(omega_r / omega_1)^2` of the step. So the step is taken as the translation alone, scaled
//! the same way, and the factorisation or the preconditioner of a tangent whose only use is to
//! drop a body by `max_increment_m` is never made. The next iteration's tangent has the
//! contact the step closed. On the `paper` model this saves the first of the iterative solver's
//! two preconditioner set-ups.

// Index loops mirror the tensor notation (the project's style for kernels); `!(x > y)` is
// meant: it also rejects NaN.
#![allow(clippy::needless_range_loop, clippy::neg_cmp_op_on_partial_ord)]

use super::super::aux::RankOneStiffness;
use super::super::solver::Solver;
use super::dofs::{ReducedDofs, NONE};

/// Union-find over `0..n` with path halving: the root of a set is its smallest member, so the
/// labels do not depend on the order of the unions.
struct DisjointSets {
    parent: Vec<u32>,
}

impl DisjointSets {
    fn new(n: usize) -> Self {
        DisjointSets {
            parent: (0..n as u32).collect(),
        }
    }

    fn find(&mut self, mut x: u32) -> u32 {
        while self.parent[x as usize] != x {
            let grand = self.parent[self.parent[x as usize] as usize];
            self.parent[x as usize] = grand;
            x = grand;
        }
        x
    }

    fn union(&mut self, a: u32, b: u32) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra < rb {
            self.parent[rb as usize] = ra;
        } else if rb < ra {
            self.parent[ra as usize] = rb;
        }
    }
}

/// The model's bodies as the elements, springs and ties join them (contact left out).
pub(super) struct Bodies {
    /// Per reduced node: its body.
    body_of: Vec<u32>,
    /// Per body: the directions something holds (a held node, a ground spring).
    supported: Vec<[bool; 3]>,
    /// Per body: the regularisation mass (kg).
    mass_kg: Vec<f64>,
    /// The regularisation's `omega_r^2` (1/s^2).
    omega_r2: f64,
    /// The step's cap (m).
    max_increment_m: f64,
}

/// An approach step taken: how far the fastest body would have fallen, and the scale.
#[derive(Clone, Copy, Debug)]
pub(super) struct ApproachStep {
    /// Free bodies moved.
    pub(super) bodies_moved: usize,
    /// The largest free translation of the Newton step, before scaling (m).
    pub(super) free_translation_m: f64,
}

impl Bodies {
    /// The bodies of `solver`'s model, for a solve with the regularisation `omega_r2` and the
    /// cap `max_increment_m`.
    pub(super) fn new(
        solver: &Solver,
        dofs: &ReducedDofs,
        omega_r2: f64,
        max_increment_m: f64,
    ) -> Self {
        let n = dofs.len();
        let mut sets = DisjointSets::new(n);
        let mut expanded = [(0u32, 0.0); 4];
        let model = &solver.model;
        // Every mesh node's reduced nodes, joined to the first reduced node of the group.
        let mut join = |sets: &mut DisjointSets, nodes: &mut dyn Iterator<Item = usize>| {
            let mut first = NONE;
            for nd in nodes {
                let k = dofs.expand(solver, nd, &mut expanded);
                for &(r, _) in &expanded[..k] {
                    if first == NONE {
                        first = r;
                    } else {
                        sets.union(first, r);
                    }
                }
            }
        };
        for e in 0..model.elements.len() {
            let nodes = model.elements.nodes(e);
            join(&mut sets, &mut nodes.iter().map(|&nd| nd as usize));
        }
        for s in &model.springs {
            join(&mut sets, &mut std::iter::once(s.node_a).chain(s.node_b));
        }
        // A tie slave's masters move together through it even where no element joins them.
        for p in &model.ties {
            join(&mut sets, &mut std::iter::once(p.slave));
        }
        let mut body_of = vec![0u32; n];
        let mut label = vec![NONE; n];
        let mut bodies = 0u32;
        for r in 0..n {
            let root = sets.find(r as u32) as usize;
            if label[root] == NONE {
                label[root] = bodies;
                bodies += 1;
            }
            body_of[r] = label[root];
        }
        let mut supported = vec![[false; 3]; bodies as usize];
        let mut mass_kg = vec![0.0; bodies as usize];
        for r in 0..n {
            let b = body_of[r] as usize;
            mass_kg[b] += dofs.mass_kg[r];
            for i in 0..3 {
                supported[b][i] |= dofs.held[r][i];
            }
        }
        for s in model.springs.iter().filter(|s| s.node_b.is_none()) {
            let k = dofs.expand(solver, s.node_a, &mut expanded);
            for &(r, _) in &expanded[..k] {
                let b = body_of[r as usize] as usize;
                for i in 0..3 {
                    supported[b][i] |= s.stiffness_n_per_m[i] > 0.0;
                }
            }
        }
        Bodies {
            body_of,
            supported,
            mass_kg,
            omega_r2,
            max_increment_m,
        }
    }

    /// The approach step for the residual `rhs` (held directions zero) with the rank-one
    /// `terms` joining bodies: writes it into `increment` and returns what it did, or returns
    /// `None` (and leaves `increment`) when no free translation exceeds `max_increment_m`.
    pub(super) fn approach_step(
        &self,
        solver: &Solver,
        dofs: &ReducedDofs,
        terms: &[RankOneStiffness],
        rhs: &[f64],
        increment: &mut [f64],
    ) -> Option<ApproachStep> {
        let (omega_r2, max_increment_m) = (self.omega_r2, self.max_increment_m);
        let bodies = self.mass_kg.len();
        // Bodies joined by contact terms form one group.
        let mut sets = DisjointSets::new(bodies);
        let mut expanded = [(0u32, 0.0); 4];
        for t in terms {
            let mut first = NONE;
            for j in (0..5).filter(|&j| t.coefficients[j] != 0.0) {
                let k = dofs.expand(solver, t.nodes[j], &mut expanded);
                for &(r, _) in &expanded[..k] {
                    let b = self.body_of[r as usize];
                    if first == NONE {
                        first = b;
                    } else {
                        sets.union(first, b);
                    }
                }
            }
        }
        let group: Vec<usize> = (0..bodies as u32).map(|b| sets.find(b) as usize).collect();
        let mut supported = vec![[false; 3]; bodies];
        let mut mass_kg = vec![0.0; bodies];
        for b in 0..bodies {
            mass_kg[group[b]] += self.mass_kg[b];
            for i in 0..3 {
                supported[group[b]][i] |= self.supported[b][i];
            }
        }
        // Resultants, summed in node order (the same sums for any thread count).
        let mut force_n = vec![[0.0; 3]; bodies];
        for (r, &b) in self.body_of.iter().enumerate() {
            let g = group[b as usize];
            for i in 0..3 {
                force_n[g][i] += rhs[3 * r + i];
            }
        }
        let mut translation_m = vec![[0.0; 3]; bodies];
        let (mut largest, mut moved) = (0.0f64, 0);
        for g in 0..bodies {
            if group[g] != g || !(mass_kg[g] > 0.0) {
                continue;
            }
            for i in 0..3 {
                if !supported[g][i] {
                    translation_m[g][i] = force_n[g][i] / (omega_r2 * mass_kg[g]);
                }
            }
            let length = translation_m[g].iter().map(|a| a * a).sum::<f64>().sqrt();
            if length > 0.0 {
                moved += 1;
            }
            largest = largest.max(length);
        }
        if !(largest > max_increment_m) {
            return None;
        }
        let scale = max_increment_m / largest;
        for (r, &b) in self.body_of.iter().enumerate() {
            let a = translation_m[group[b as usize]];
            for i in 0..3 {
                increment[3 * r + i] = scale * a[i];
            }
        }
        Some(ApproachStep {
            bodies_moved: moved,
            free_translation_m: largest,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The labels are the same whatever the order of the unions (the root is the smallest
    /// member), and disjoint sets stay apart.
    #[test]
    fn disjoint_sets_join_only_what_was_joined() {
        let mut a = DisjointSets::new(6);
        a.union(4, 5);
        a.union(1, 4);
        a.union(2, 3);
        let mut b = DisjointSets::new(6);
        b.union(2, 3);
        b.union(5, 1);
        b.union(4, 1);
        for x in 0..6 {
            assert_eq!(a.find(x), b.find(x), "node {x}");
        }
        assert_eq!(a.find(5), 1);
        assert_eq!(a.find(3), 2);
        assert_eq!(a.find(0), 0);
        assert_ne!(a.find(1), a.find(2));
    }
}
