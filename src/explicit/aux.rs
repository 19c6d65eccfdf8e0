//! What other modules add to the engine each step (contact) and at each output sample
//! (histories, checkpoints): the [`AuxForces`] hooks.

use super::state::{OutputFields, RunSummary};
use crate::mesh::P3;
use crate::{Error, Result};

/// Forces added by another module every step (contact).
pub trait AuxForces {
    /// Adds forces at time `time_s` for the state `u` (at t_n) and `v` (at t_{n-1/2}) into
    /// `force` (N). Must not allocate.
    fn add_forces(&mut self, time_s: f64, dt_s: f64, u: &[P3], v: &[P3], force: &mut [P3]);
    /// Every node [`AuxForces::add_forces`] can ever write, or `None` (the default) when it may
    /// write any. Declared to the solver ([`super::Solver::declare_aux_force_nodes`]), this
    /// lets the step zero and read the auxiliary forces of these nodes only.
    fn force_nodes(&self) -> Option<Vec<usize>> {
        None
    }
    /// The linearised stiffness `-d f / d u` of the forces added by the last
    /// [`AuxForces::add_forces`], as rank-one terms (the static solver's tangent; penalty
    /// contact gives one per active slave). None by default.
    fn stiffness_terms(&self, _out: &mut Vec<RankOneStiffness>) {}
    /// Called after each history sample at `time_s` (the module writes its own histories).
    fn on_sample(&mut self, _time_s: f64, _out_dir: &std::path::Path) -> Result<()> {
        Ok(())
    }
    /// Extra columns this module appends to `histories.csv` (e.g. wheel vibration in a
    /// co-rotating frame).
    fn history_columns(&self) -> Vec<String> {
        Vec::new()
    }
    /// Appends one `,value` per [`AuxForces::history_columns`] entry for the sample at
    /// `time_s`, from the output fields at that instant (`reference` = node coordinates).
    fn push_history_values(
        &mut self,
        _time_s: f64,
        _reference: &[P3],
        _output: &OutputFields,
        _row: &mut String,
    ) -> Result<()> {
        Ok(())
    }
    /// Point vector fields this module adds to the VTU snapshots, one value per node of a mesh
    /// of `node_count` nodes (e.g. the contact force on each node). Called at snapshots only.
    fn snapshot_fields(&self, _node_count: usize) -> Vec<(String, Vec<P3>)> {
        Vec::new()
    }
    /// Called after each periodic checkpoint with the run's record so far (status `running`,
    /// time and steps of the checkpoint, wall time of this invocation up to it), so that the
    /// module can keep its own record in step with the checkpoint: a process killed later
    /// then leaves a record a resume can merge. Nothing by default.
    fn on_checkpoint(&mut self, _summary: &RunSummary) -> Result<()> {
        Ok(())
    }
    /// State to keep in checkpoints (e.g. tangential contact forces).
    fn checkpoint_state(&self) -> Vec<f64> {
        Vec::new()
    }
    /// Restores what [`AuxForces::checkpoint_state`] returned.
    fn restore_state(&mut self, state: &[f64]) -> Result<()> {
        if state.is_empty() {
            Ok(())
        } else {
            Err(Error::input(
                "checkpoint",
                "aux_state",
                "checkpoint holds contact state this run does not have",
            ))
        }
    }
}

/// A rank-one stiffness `k b bᵀ` with `b = sum_j c_j (e_{node_j} ⊗ n)`: a penalty spring of
/// stiffness `k` along the unit direction `n` acting on the combination `sum_j c_j u_j` of node
/// displacements (contact: the slave with `c = 1`, the master face's nodes with `c = -w_j`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RankOneStiffness {
    /// Stiffness `k` (N/m).
    pub stiffness_n_per_m: f64,
    /// Unit direction `n`.
    pub direction: P3,
    /// Nodes (unused entries have coefficient 0).
    pub nodes: [usize; 5],
    /// Coefficients `c_j`.
    pub coefficients: [f64; 5],
}

/// No auxiliary forces.
pub struct NoAux;
impl AuxForces for NoAux {
    fn add_forces(&mut self, _: f64, _: f64, _: &[P3], _: &[P3], _: &mut [P3]) {}
    fn force_nodes(&self) -> Option<Vec<usize>> {
        Some(Vec::new())
    }
}
