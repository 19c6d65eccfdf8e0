//! Multi-rate (subcycled) central differences on a power-of-two level partition
//! ([`super::levels`]): a nodal partition in the manner of Belytschko, Yen & Mullen ("Mixed
//! methods for time integration", CMAME 17/18, 1979) with linear interpolation of the coarse
//! nodes' motion across the interface.
//!
//! The engine steps at the finest step `dt`. A node of level k is updated every `2^k` steps,
//! at the steps `n` with `n mod 2^k = 0`, with its own step `dt_k = 2^k dt`:
//!
//! ```text
//! v_{m+1/2} = v_{m-1/2} + dt_k M^-1 f(t_m),     then every fine step  u += dt v_{m+1/2}
//! ```
//!
//! so that over its step it moves linearly, `u(t) = u_m + (t - t_m) v_{m+1/2}`, and arrives at
//! `u_{m+1} = u_m + dt_k v_{m+1/2}`: the central difference at its own step. Elements are
//! evaluated at the rate of their finest node (an element of level k at the steps with
//! `n mod 2^k = 0`), so at a node's update every one of its elements has been evaluated at that
//! instant, with the coarse neighbours' displacements on their straight paths: the interface
//! elements see the coarse side interpolated, as the mixed method prescribes. With one level
//! the update is the single-rate one operation for operation.
//!
//! A node's updates fall on the steps where `n mod 2^k = 0` of the solver's step count.
//!
//! Stability: the update is not stable at the elements' own stable steps. A coarse interface
//! node samples its fine-rate elements' forces once per coarse step, the coupling is not
//! symmetric in time, and at some ratios of the element sizes the fine side's fastest modes
//! resonate with the coarse side's: the energy grows exponentially. The levels therefore step
//! their elements at no more than half their own stable step
//! ([`super::levels::STABLE_COARSE_COURANT`], with the measurements; the finest level at 0.9),
//! with which no growth was found on any of the graded blocks of
//! tests/explicit_multirate_stability.rs.
//!
//! Nodes that other parts of the engine move or load every step stay at level 0: tie slaves and
//! masters, rigid-body nodes, prescribed nodes, spring and load nodes, and the caller's (the
//! contact's slaves and master faces). The energy balance is exact bookkeeping at the steps where
//! every level updates (`n mod 2^(L-1) = 0`): each node's work increments are its own step's,
//! `dt_k f . vbar`.
//!
//! # Energy by level
//!
//! Level k's energy is its nodes' kinetic energy and its elements' strain and hourglass energy.
//! At an update of a node of level k >= 1 the work `dt_k f . vbar` is split: gravity, the
//! auxiliary forces, the reactions and mass damping are work from outside the model; the
//! internal force is split by the level of the elements it comes from (`LevelInterface`
//! records `f_int` after each finer level's elements at the interface nodes), and the part of
//! a finer level j's elements is energy that leaves level k for level j. So for k >= 1
//!
//! ```text
//! error_k = (E_k - E_k,0) - W_ext,k - T_k,    T_k = sum_(k'>k) W[k'][k] - sum_(j<k) W[k][j]
//! ```
//!
//! with `W[k][j]` the work of level j's elements on level k's nodes; the transfers sum to zero
//! over the levels. What is left of the whole model's balance error is level 0's, which also
//! holds every rigid body, tie, spring, load and contact node. Each level's error is a real
//! check: its elements' energy against the work their forces did on every node they touch,
//! the coarser ones included at their own updates.

use super::batch::{ElementBatch, LANES};
use super::colour::{colour_blocks, SharedMut};
use super::levels::{
    add_level_forces, partition_with, LevelInterface, LevelPartition, LevelScheme, LevelWork,
    MultiRate, MAX_BINARY_LEVELS,
};
use super::model::{Elements, Model};
use super::solver::{Solver, BLOCK_ELEMENTS, ROLE_RIGID, ROLE_SLAVE};
use crate::mesh::P3;
use crate::{Error, Result};

/// Stable step of every element (s): its transit `L / c` (the characteristic length over the
/// dilatational wave speed).
pub fn element_transits_s(model: &Model) -> Vec<f64> {
    let mesh = &model.mesh;
    mesh.elements
        .iter()
        .enumerate()
        .map(|(e, conn)| {
            let x: [P3; 8] = std::array::from_fn(|a| mesh.nodes[conn[a]]);
            crate::mesh::hex::characteristic_length(&x) / model.element_wave_speed_m_per_s[e]
        })
        .collect()
}

impl Solver {
    /// Switches on multi-rate stepping with at most `max_levels` levels (1 to 16), holding
    /// `finest_nodes` (and the nodes listed in the module docs) at the finest level; returns the
    /// partition. The finest step stays the solver's `dt_s`.
    ///
    /// Needs the batched element kernel (one-point elements without element damping): an error
    /// otherwise. The levels' phases follow the solver's step count, so a run resumed from a
    /// checkpoint steps exactly as the run it continues. Switched on after other stepping (a
    /// preload), a coarse node's first update takes its velocity of the last fine step as that
    /// of half its own step earlier: a start-up error of the size of the central difference's
    /// own first half step.
    pub fn enable_multi_rate(
        &mut self,
        max_levels: usize,
        finest_nodes: &[usize],
    ) -> Result<&LevelPartition> {
        self.enable_multi_rate_with(LevelScheme::binary(max_levels), finest_nodes)
    }

    /// The partition that multi-rate stepping with `scheme` would use, with `finest_nodes` and
    /// the engine's own fixed nodes (module docs) at level 0, without switching it on: for
    /// deciding whether subcycling pays. Errors as [`Solver::enable_multi_rate_with`].
    pub fn plan_multi_rate(
        &self,
        scheme: LevelScheme,
        finest_nodes: &[usize],
    ) -> Result<LevelPartition> {
        scheme.check("multi-rate", "")?;
        if !matches!(self.model.elements, Elements::OnePoint(_)) {
            return Err(Error::input(
                "multi-rate",
                "formulation",
                "multi-rate stepping needs one-point elements (the batched kernel)",
            ));
        }
        if self.batches.is_empty() {
            return Err(Error::input(
                "multi-rate",
                "formulation",
                "multi-rate stepping needs the batched kernel (no viscous hourglass, no \
                 stiffness damping)",
            ));
        }
        let n = self.model.node_count();
        let mut finest: Vec<usize> = finest_nodes.iter().copied().filter(|&i| i < n).collect();
        for (i, &r) in self.role.iter().enumerate() {
            // Tie slaves, rigid nodes, and fixed or prescribed directions that ride on a
            // curve (prescribed bits) stay fine; plain fixed directions may subcycle.
            if r & (ROLE_SLAVE | ROLE_RIGID) != 0 || r & 0b0011_1000 != 0 {
                finest.push(i);
            }
        }
        for t in &self.model.ties {
            finest.push(t.slave);
            finest.extend(t.master.iter().copied());
        }
        finest.extend(self.discrete_nodes.iter().copied());
        for pm in &self.model.prescribed {
            finest.extend(pm.nodes.iter().copied());
        }
        Ok(partition_with(
            &self.model.mesh.elements,
            &element_transits_s(&self.model),
            n,
            &finest,
            scheme,
        ))
    }

    /// [`Solver::enable_multi_rate`] with levels `scheme.ratio` apart (a power of two; an
    /// error names `level_ratio` otherwise).
    pub fn enable_multi_rate_with(
        &mut self,
        scheme: LevelScheme,
        finest_nodes: &[usize],
    ) -> Result<&LevelPartition> {
        let p = self.plan_multi_rate(scheme, finest_nodes)?;
        let n = self.model.node_count();
        let Elements::OnePoint(elements) = &self.model.elements else {
            unreachable!("plan_multi_rate refuses other formulations");
        };
        // Batches ordered by level, each level packed and coloured on its own (the single-rate
        // batches freed first: at paper scale they are hundreds of MB).
        let capacity = self.batches.len() + p.counts.len();
        self.batches = Vec::new();
        let mut batches: Vec<ElementBatch> = Vec::with_capacity(capacity);
        let mut level_colours = Vec::with_capacity(p.counts.len());
        for level in 0..p.counts.len() {
            let members: Vec<_> = (0..elements.len())
                .filter(|&e| p.element_level[e] as usize == level)
                .map(|e| elements[e])
                .collect();
            let offset = batches.len();
            batches.extend(members.chunks(LANES).map(ElementBatch::pack));
            let count = batches.len() - offset;
            let colours = colour_blocks(count, BLOCK_ELEMENTS / LANES, n, |b| {
                batches[offset + b]
                    .nodes
                    .iter()
                    .flat_map(|lanes| lanes.iter().copied())
                    .collect()
            })?;
            level_colours.push(
                colours
                    .into_iter()
                    .map(|c| {
                        c.into_iter()
                            .map(|r| r.start + offset..r.end + offset)
                            .collect()
                    })
                    .collect(),
            );
        }
        self.batches = batches;
        let node_level = p.node_level.clone();
        let levels_used = p.counts.len();
        let interface = LevelInterface::new(&self.model.mesh.elements, &p);
        self.multi_rate = Some(MultiRate {
            interface,
            level_work: LevelWork::default(),
            level_work_at_report: LevelWork::default(),
            level_baseline: None,
            partition: p,
            node_level,
            level_colours,
            last_acceleration: vec![[0.0; 3]; n],
            first_update_pending: vec![true; n],
            first_updates_end_step: self.step + (1u64 << (levels_used.max(1) - 1)),
        });
        Ok(&self.multi_rate.as_ref().expect("set above").partition)
    }

    /// The multi-rate state, when on.
    pub fn multi_rate(&self) -> Option<&MultiRate> {
        self.multi_rate.as_ref()
    }
}

impl Solver {
    /// Only the element forces of `level` (multi-rate on), added to `f_int`: for timing each
    /// level's element work (the next step zeroes `f_int` again). Does nothing with multi-rate
    /// off or past the last level.
    pub fn compute_level_forces(&mut self, level: usize) {
        let Some(mr) = &self.multi_rate else {
            return;
        };
        let Some(colours) = mr.level_colours.get(level) else {
            return;
        };
        // Accumulates into f_int without zeroing it: the timing is of the elements alone.
        let f = SharedMut(self.f_int.as_mut_ptr());
        add_level_forces(
            &self.batches,
            colours,
            &self.u,
            f,
            self.kernel.physical_hourglass,
            self.avx2,
        );
    }
}

/// The energy stored in one step level at an output step (J).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LevelEnergy {
    /// Kinetic energy of the level's nodes at their output velocities.
    pub kinetic_j: f64,
    /// Strain and hourglass energy of the level's elements.
    pub internal_j: f64,
}

impl Solver {
    /// Where the energy sits, level by level, at the last output step: each node's kinetic
    /// energy `m |v|^2 / 2` (its output velocity: the centred one at an update, the one on its
    /// straight path between updates) goes to its level, each element's strain and hourglass
    /// energy to the element's. The levels add up to the energy report's kinetic and
    /// strain + hourglass energies. Element sums run over fixed blocks added in block order,
    /// so the figures do not depend on the thread count. None without multi-rate stepping.
    pub fn level_energies(&self) -> Option<Vec<LevelEnergy>> {
        use rayon::prelude::*;
        let mr = self.multi_rate.as_ref()?;
        let levels = mr.levels();
        let mut out = vec![LevelEnergy::default(); levels];
        for (nd, v) in self.output.velocity.iter().enumerate() {
            let k = (mr.node_level[nd] as usize).min(levels - 1);
            out[k].kinetic_j += 0.5 * self.eff_mass[nd] * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        }
        let n = self.model.elements.len();
        let element_level = &mr.partition.element_level;
        let (u, v, opts) = (&self.u, &self.v, self.kernel);
        let per_block: Vec<Vec<f64>> = (0..n.div_ceil(BLOCK_ELEMENTS))
            .into_par_iter()
            .map(|b| {
                let mut acc = vec![0.0; levels];
                let mut fe = [[0.0; 3]; 8];
                for e in b * BLOCK_ELEMENTS..((b + 1) * BLOCK_ELEMENTS).min(n) {
                    let en = match &self.model.elements {
                        Elements::OnePoint(els) => {
                            super::element::one_point_forces::<true>(&els[e], u, v, opts, &mut fe)
                        }
                        Elements::Full(els) => {
                            super::element::full_forces::<true>(&els[e], u, 0.0, v, &mut fe)
                        }
                    };
                    acc[(element_level[e] as usize).min(levels - 1)] +=
                        en.strain_j + en.hourglass_j;
                }
                acc
            })
            .collect();
        for block in per_block {
            for (k, x) in block.into_iter().enumerate() {
                out[k].internal_j += x;
            }
        }
        Some(out)
    }
}

impl Solver {
    /// The energy balance of each level at the last energy report (J), from its first per-level
    /// report on (module docs, "Energy by level"): for a level k >= 1, the change of its
    /// energy (`energies[k]`, from [`Solver::level_energies`] of the same report) less the work
    /// done on its nodes from outside the model and less the energy that crossed its
    /// interfaces; for level 0, what remains of the whole model's balance error, which also
    /// holds the rigid bodies, ties, springs and contact, all at level 0. The levels add up to
    /// the change of the whole model's error. None without multi-rate stepping or a report.
    pub fn level_balance_errors(&mut self, energies: &[LevelEnergy]) -> Option<Vec<f64>> {
        let global = self.last_energy?.balance_error_j;
        let mr = self.multi_rate.as_mut()?;
        let levels = energies.len().min(MAX_BINARY_LEVELS);
        let work = &mr.level_work_at_report;
        let mut raw = [0.0; MAX_BINARY_LEVELS];
        raw[0] = global;
        for k in 1..levels {
            raw[k] = energies[k].kinetic_j + energies[k].internal_j
                - work.external_j[k]
                - work.transfer_j[k];
        }
        let baseline = *mr.level_baseline.get_or_insert(raw);
        let mut errors: Vec<f64> = (0..levels).map(|k| raw[k] - baseline[k]).collect();
        let coarse: f64 = errors[1..].iter().sum();
        errors[0] -= coarse;
        Some(errors)
    }
}
