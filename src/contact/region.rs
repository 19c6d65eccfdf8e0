//! The region of interest of a contact pair: the slaves that may reach a master face before
//! the region is next rebuilt. Only they are searched each step, so the contact's cost follows
//! the patch (a few hundred nodes) rather than the whole tread (tens of thousands).
//!
//! Rule: a slave belongs to the region when its position at the build lies within `margin`
//! (along every axis) of some master face's box (the boxes the search itself tests, from the
//! bucket grid of the same build). The region stays valid while no slave has moved more than
//! `margin` from its position at the build and the grid is not rebuilt: a slave outside the
//! region is then still outside every face's box, so the full search would find no face for it
//! either, and the results are the same bit for bit. Each step checks every slave's
//! displacement against the margin (a read of positions, no search), and rebuilds when needed.
//!
//! Guard: [`Region::misses`] runs the full search's box test for every slave outside the region;
//! a contact pair runs it periodically in debug builds and every step when asked (tests).

use rayon::prelude::*;

use super::{BucketGrid, SlaveState, SLAVE_CHUNK};
use crate::mesh::P3;

/// A slave's contact force, master weights and face (`u32::MAX`: none).
pub(super) type SlaveForce = (P3, [f64; 4], u32);

/// The force entry of a slave out of contact.
pub(super) const NO_FORCE: SlaveForce = ([0.0; 3], [0.0; 4], u32::MAX);

/// How slaves are chosen for the search each step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ContactSearch {
    /// Only the slaves of the region of interest (module documentation).
    Region,
    /// Every slave, every step (the reference the region is checked against).
    Full,
}

/// The region and its work buffers (all allocated once, at the pair's size).
pub(super) struct Region {
    /// Indices (into the pair's slaves) searched each step, ascending.
    pub(super) slaves: Vec<u32>,
    /// Per slave: inside the region.
    inside: Vec<bool>,
    /// Per slave: its position when the region was built.
    positions_at_build: Vec<P3>,
    /// How far a slave may move before a rebuild (m).
    pub(super) margin_m: f64,
    /// Whether the region matches the current grid.
    pub(super) valid: bool,
    /// Work copies of the region's slave states and forces, aligned with `slaves`.
    pub(super) state: Vec<SlaveState>,
    pub(super) forces: Vec<SlaveForce>,
    /// Rebuilds so far.
    pub(super) rebuilds: usize,
}

impl Region {
    /// An empty, invalid region for `slave_count` slaves.
    pub(super) fn new(slave_count: usize, margin_m: f64) -> Region {
        Region {
            slaves: Vec::with_capacity(slave_count),
            inside: vec![false; slave_count],
            positions_at_build: vec![[0.0; 3]; slave_count],
            margin_m,
            valid: false,
            state: Vec::with_capacity(slave_count),
            forces: Vec::with_capacity(slave_count),
            rebuilds: 0,
        }
    }

    /// Whether some slave moved more than the margin since the build (or the region is invalid).
    pub(super) fn needs_rebuild(&self, position: &(impl Fn(usize) -> P3 + Sync)) -> bool {
        if !self.valid {
            return true;
        }
        let limit2 = self.margin_m * self.margin_m;
        self.positions_at_build
            .par_chunks(SLAVE_CHUNK * 16)
            .enumerate()
            .any(|(c, chunk)| {
                chunk.iter().enumerate().any(|(j, p0)| {
                    let x = position(c * SLAVE_CHUNK * 16 + j);
                    let d = [x[0] - p0[0], x[1] - p0[1], x[2] - p0[2]];
                    d[0] * d[0] + d[1] * d[1] + d[2] * d[2] > limit2
                })
            })
    }

    /// Rebuilds the region from the slaves' current positions against `grid`'s face boxes
    /// (every slave with `search` [`ContactSearch::Full`]). Slaves that leave it are set out of
    /// contact, exactly as the full search would set them this step (no face box near them).
    pub(super) fn rebuild(
        &mut self,
        grid: &BucketGrid,
        search: ContactSearch,
        position: &(impl Fn(usize) -> P3 + Sync),
        state: &mut [SlaveState],
        forces: &mut [SlaveForce],
    ) {
        let margin = self.margin_m;
        self.positions_at_build
            .par_chunks_mut(SLAVE_CHUNK)
            .zip(self.inside.par_chunks_mut(SLAVE_CHUNK))
            .enumerate()
            .for_each(|(c, (positions, inside))| {
                for (j, (p, flag)) in positions.iter_mut().zip(inside.iter_mut()).enumerate() {
                    *p = position(c * SLAVE_CHUNK + j);
                    *flag = search == ContactSearch::Full || grid.near_some_box(*p, margin);
                }
            });
        self.slaves.clear();
        for (k, &inside) in self.inside.iter().enumerate() {
            if inside {
                self.slaves.push(k as u32);
            } else {
                if state[k].active {
                    state[k] = SlaveState {
                        mu: state[k].mu,
                        ..Default::default()
                    };
                }
                forces[k] = NO_FORCE;
            }
        }
        self.valid = true;
        self.rebuilds += 1;
    }

    /// The slaves outside the region that the full search would test against a face this
    /// step (their position inside some face's box): none, while the region is sound.
    pub(super) fn misses(
        &self,
        grid: &BucketGrid,
        position: &(impl Fn(usize) -> P3 + Sync),
    ) -> usize {
        (0..self.inside.len())
            .into_par_iter()
            .filter(|&k| !self.inside[k] && grid.inside_some_box(position(k)))
            .count()
    }
}
