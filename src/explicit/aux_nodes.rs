//! The nodes whose auxiliary force can be non-zero. A rolling model's auxiliary forces (contact,
//! springs, loads) act on a fifth of its nodes, yet zeroing the whole `f_aux` array and reading
//! it in the node update streamed 72 bytes a node a step. Once the caller has declared the
//! nodes its [`AuxForces`] writes ([`Solver::declare_aux_force_nodes`]), the step zeroes and
//! reads `f_aux` at the declared nodes, the springs' and loads' nodes, and the tie masters that
//! receive a declared slave's force (the ties pass on the auxiliary forces of declared slaves
//! only); everywhere else the array stays zero, so the arithmetic is that of the full array bit
//! for bit (a zero force adds exactly zero work).
//!
//! The declaration is checked, not trusted: at every energy report the step confirms that no
//! auxiliary force landed outside the set ([`Solver::aux_forces_outside_declared`]) and stops
//! with a diagnosis if one did.

use rayon::prelude::*;

use super::aux::AuxForces;
use super::solver::{Solver, NODE_CHUNK};
use super::state::AuxNodeSet;
use super::tie_update::TieGather;
use crate::{Error, Result};

impl Solver {
    /// Narrows the auxiliary forces to `nodes` (those the caller's [`AuxForces`] can write:
    /// [`AuxForces::force_nodes`]) plus the springs', the loads' and the tie masters of declared
    /// slaves; `None` widens them to every node again (the default). Call it with the model
    /// complete; an index outside the model is an error naming it.
    pub fn declare_aux_force_nodes(&mut self, nodes: Option<&[usize]>) -> Result<()> {
        let n = self.u.len();
        let Some(list) = nodes else {
            self.aux_force_node = vec![true; n];
            self.aux_zero = None;
            self.tie_gather_aux = None;
            return Ok(());
        };
        let mut flag = vec![false; n];
        for &nd in list {
            if nd >= n {
                return Err(Error::input(
                    "auxiliary forces",
                    "force_nodes",
                    format!(
                        "node {nd} is not in the model (0 to {})",
                        n.saturating_sub(1)
                    ),
                ));
            }
            flag[nd] = true;
        }
        for load in &self.model.loads {
            for &nd in &load.nodes {
                flag[nd] = true;
            }
        }
        for sp in &self.model.springs {
            flag[sp.node_a] = true;
            if let Some(b) = sp.node_b {
                flag[b] = true;
            }
        }
        // The tie pass adds a slave's auxiliary force to its masters (no chained ties).
        for t in &self.model.ties {
            if flag[t.slave] {
                for &m in &t.master {
                    flag[m] = true;
                }
            }
        }
        let declared_ties: Vec<_> = self
            .model
            .ties
            .iter()
            .filter(|t| flag[t.slave])
            .cloned()
            .collect();
        self.tie_gather_aux = Some(TieGather::new(&declared_ties, n));
        self.f_aux.fill([0.0; 3]);
        self.aux_zero = Some(AuxNodeSet {
            nodes: (0..n).filter(|&i| flag[i]).map(|i| i as u32).collect(),
            springs: self.model.springs.len(),
            loads: self.model.loads.len(),
        });
        self.aux_force_node = flag;
        Ok(())
    }

    /// [`Solver::declare_aux_force_nodes`] with the nodes `aux` says it writes.
    pub fn declare_aux_forces_of<A: AuxForces + ?Sized>(&mut self, aux: &A) -> Result<()> {
        self.declare_aux_force_nodes(aux.force_nodes().as_deref())
    }

    /// Nodes the auxiliary forces act on in the step: `None` for every node.
    pub fn aux_force_nodes(&self) -> Option<&[u32]> {
        self.aux_zero.as_ref().map(|s| s.nodes.as_slice())
    }

    /// Zeroes the auxiliary forces before a step gathers them: at the declared nodes, or the
    /// whole array.
    pub(super) fn zero_aux_forces(&mut self) {
        let changed = self.aux_zero.as_ref().is_some_and(|s| {
            s.springs != self.model.springs.len() || s.loads != self.model.loads.len()
        });
        if changed {
            // Springs or loads added since the declaration: their nodes are not in the set.
            self.aux_force_node.fill(true);
            self.aux_zero = None;
            self.tie_gather_aux = None;
        }
        match &self.aux_zero {
            Some(set) => {
                for &nd in &set.nodes {
                    self.f_aux[nd as usize] = [0.0; 3];
                }
            }
            None => self
                .f_aux
                .par_chunks_mut(NODE_CHUNK)
                .for_each(|c| c.fill([0.0; 3])),
        }
    }

    /// The first node outside the declared set whose auxiliary force is not zero, if any (the
    /// step's check of the declaration).
    pub fn aux_forces_outside_declared(&self) -> Option<usize> {
        self.aux_zero.as_ref()?;
        self.f_aux
            .iter()
            .zip(&self.aux_force_node)
            .position(|(f, &declared)| !declared && *f != [0.0; 3])
    }
}
