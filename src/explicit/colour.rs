//! Colouring of element blocks for races-free parallel scatter: blocks of consecutive
//! elements, coloured so that no two blocks of one colour share a node; the colours run one
//! after another, each colour's blocks in parallel (bitwise identical results for any thread
//! count).

use std::ops::Range;

use crate::{Error, Result};

/// Raw pointer that may be shared between threads; every use writes disjoint indices.
#[derive(Clone, Copy)]
pub(super) struct SharedMut<T>(pub(super) *mut T);
unsafe impl<T> Send for SharedMut<T> {}
unsafe impl<T> Sync for SharedMut<T> {}
impl<T> SharedMut<T> {
    /// The pointer (a method, so that closures capture the whole `Send + Sync` wrapper).
    #[inline(always)]
    pub(super) fn ptr(self) -> *mut T {
        self.0
    }
    /// # Safety
    /// The caller guarantees that no two threads touch the same index.
    #[inline(always)]
    pub(super) unsafe fn at(self, i: usize) -> *mut T {
        self.0.add(i)
    }
}

/// Greedy colouring of blocks of `block` consecutive items (elements or batches) whose nodes
/// `nodes_of(item)` lists: blocks sharing a node get different colours.
pub(super) fn colour_blocks(
    n: usize,
    block: usize,
    node_count: usize,
    nodes_of: impl Fn(usize) -> Vec<u32>,
) -> Result<Vec<Vec<Range<usize>>>> {
    let mut node_colours: Vec<u64> = vec![0; node_count];
    let mut colours: Vec<Vec<Range<usize>>> = Vec::new();
    let mut start = 0;
    while start < n {
        let end = (start + block).min(n);
        let mut used = 0u64;
        for e in start..end {
            for nd in nodes_of(e) {
                used |= node_colours[nd as usize];
            }
        }
        let c = (!used).trailing_zeros() as usize;
        if c >= 64 {
            return Err(Error::Mesh(
                "element blocks need more than 64 colours: renumber the elements so that neighbours are close".into(),
            ));
        }
        for e in start..end {
            for nd in nodes_of(e) {
                node_colours[nd as usize] |= 1 << c;
            }
        }
        if colours.len() <= c {
            colours.resize(c + 1, Vec::new());
        }
        colours[c].push(start..end);
        start = end;
    }
    Ok(colours)
}
