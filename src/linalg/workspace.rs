//! Buffers reused from one block Lanczos step to the next.
//!
//! A step of the 294 k dof wheel's solve works on `n x 16` blocks of 38 MB: the solve's
//! row-major copy, the M products' tiles, the residual block, its orthonormalised copies. Each
//! was a fresh allocation, which the allocator maps anew (blocks this large are above its
//! mapping threshold) and unmaps on release, so every page was faulted in and zeroed by the
//! kernel again in every step: 6.2 M minor faults and 36 s of system time in a 167 s solve
//! (measured 2026-11-27). A [`Workspace`] keeps the released buffers and hands them out again,
//! so a step touches memory that is already mapped.
//!
//! A buffer from [`Workspace::take`] holds stale values from its last use: callers overwrite
//! it (a product with `Accum::Replace`, a copy) or zero it.

/// A free list of `f64` buffers.
#[derive(Default)]
pub(crate) struct Workspace {
    free: Vec<Vec<f64>>,
}

impl Workspace {
    /// An empty workspace (buffers are allocated on first use).
    pub(crate) fn new() -> Workspace {
        Workspace::default()
    }

    /// A buffer of `len` values, contents unspecified: the free buffer of least capacity that
    /// holds `len` in less than twice its size, or a new one. The bound keeps a block-sized
    /// buffer from serving a half-block request (a tile of the M product): the next block-sized
    /// request would then find none and allocate, and the free list would end up holding both
    /// sizes (measured: 76 MB more peak memory on the 294 k dof wheel without the bound).
    pub(crate) fn take(&mut self, len: usize) -> Vec<f64> {
        let best = self
            .free
            .iter()
            .enumerate()
            .filter(|(_, v)| v.capacity() >= len && v.capacity() < 2 * len.max(1))
            .min_by_key(|(_, v)| v.capacity())
            .map(|(i, _)| i);
        match best {
            Some(i) => {
                let mut v = self.free.swap_remove(i);
                // Within capacity: no reallocation; only values past the old length are written.
                v.resize(len, 0.0);
                v
            }
            None => vec![0.0; len],
        }
    }

    /// Returns a buffer for later [`Workspace::take`]s.
    pub(crate) fn give(&mut self, v: Vec<f64>) {
        if v.capacity() > 0 {
            self.free.push(v);
        }
    }

    /// Values held in free buffers (their capacity).
    #[cfg(test)]
    fn held_values(&self) -> usize {
        self.free.iter().map(|v| v.capacity()).sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_released_buffer_is_handed_out_again_without_a_new_allocation() {
        let mut ws = Workspace::new();
        let mut a = ws.take(1000);
        a[999] = 7.0;
        let ptr = a.as_ptr();
        ws.give(a);
        // The same storage comes back for any length it holds, stale values included.
        let b = ws.take(1000);
        assert_eq!(b.as_ptr(), ptr);
        assert_eq!(b[999], 7.0);
        ws.give(b);
        let c = ws.take(600);
        assert_eq!((c.as_ptr(), c.len()), (ptr, 600));
        // A longer request than any free buffer gets a new one, zero-filled.
        let d = ws.take(2000);
        assert_ne!(d.as_ptr(), ptr);
        assert!(d.iter().all(|&x| x == 0.0));
        ws.give(c);
        ws.give(d);
        // Best fit: the smaller of two free buffers that hold the request.
        let e = ws.take(1000);
        assert_eq!(e.as_ptr(), ptr);
        assert_eq!(ws.held_values(), 2000);
        // A request for half a free buffer or less gets a new one: the 2000 stays free for a
        // request of its own size.
        let f = ws.take(1000);
        assert_eq!(f.capacity(), 1000);
        assert_eq!(ws.held_values(), 2000);
    }
}
