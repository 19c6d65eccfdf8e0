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
    /// [`AuxForces::add_forces`] with the step's prediction of where the nodes go without
    /// these forces ([`StepPredictor`]): what a constraint enforced exactly needs (contact by
    /// forward-increment Lagrange multipliers). The engine's step calls this one; by default it
    /// is `add_forces`.
    fn add_forces_predicted(
        &mut self,
        time_s: f64,
        dt_s: f64,
        u: &[P3],
        v: &[P3],
        force: &mut [P3],
        _predictor: &StepPredictor,
    ) {
        self.add_forces(time_s, dt_s, u, v, force);
    }
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

/// What a step knows of a node before the auxiliary forces are added: the half-step velocity
/// it reaches without them,
///
/// `v*_{n+1/2} = v_{n-1/2} + dt M^-1 (f_aux - f_int + m g - alpha m v_{n-1/2})`
///
/// (node_update.rs, with `f_aux` the loads and springs gathered so far), and its inverse mass,
/// so that a force `f` added at t_n moves it to `v*_{n+1/2} + dt f / m` exactly. Only for nodes
/// the update moves freely: no fixed or prescribed component, not a tie slave or a rigid
/// body's node, on a single-rate step (a multi-rate level updates at its own step). A tie
/// slave moves with its masters ([`StepPredictor::tie_masters`]); their `f_int` holds the
/// slaves' passed element forces, their `f_aux` not yet the slaves' loads and springs (passed
/// after the auxiliary forces), which the rolling models do not put on contact nodes.
pub struct StepPredictor<'a> {
    pub(super) dt_s: f64,
    pub(super) f_int: &'a [P3],
    pub(super) inv_mass: &'a [f64],
    pub(super) eff_mass: &'a [f64],
    pub(super) gravity_mass: &'a [f64],
    pub(super) gravity_m_per_s2: P3,
    pub(super) mass_damping_per_s: f64,
    pub(super) role: &'a [u8],
    pub(super) ties: &'a [crate::mesh::tie::TiePair],
    pub(super) tie_of_node: &'a [u32],
    pub(super) multi_rate: bool,
}

impl StepPredictor<'_> {
    /// The master nodes and weights of node `nd` when it is a tie slave: it then moves as
    /// `sum w_k v_k` of its masters, and a force on it acts on master k as `w_k f`.
    #[inline]
    pub fn tie_masters(&self, nd: usize) -> Option<([usize; 4], [f64; 4])> {
        let i = self.tie_of_node[nd];
        (i != u32::MAX).then(|| {
            let t = &self.ties[i as usize];
            (t.master, t.weights)
        })
    }

    /// Whether the step is multi-rate (then no node is predicted).
    pub fn multi_rate(&self) -> bool {
        self.multi_rate
    }

    /// `(v*_{n+1/2}, 1 / m)` of node `nd` with velocity `v_old` (v_{n-1/2}) and auxiliary force
    /// so far `f_aux`; None for a node the update does not move freely (type docs). The same
    /// operations in the same order as the node update's free path.
    #[inline]
    pub fn free_update(&self, nd: usize, v_old: P3, f_aux: P3) -> Option<(P3, f64)> {
        if self.multi_rate || self.role[nd] != 0 {
            return None;
        }
        let (m, mg, im) = (self.eff_mass[nd], self.gravity_mass[nd], self.inv_mass[nd]);
        let (g, alpha, fi) = (
            self.gravity_m_per_s2,
            self.mass_damping_per_s,
            self.f_int[nd],
        );
        let v_new = [0, 1, 2].map(|i| {
            let force = f_aux[i] - fi[i] + mg * g[i] - alpha * m * v_old[i];
            v_old[i] + self.dt_s * force * im
        });
        Some((v_new, im))
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
