//! Deterministic pseudo-random numbers: Marsaglia's xorshift64 (G. Marsaglia, "Xorshift
//! RNGs", J. Stat. Softw. 8(14), 2003; shifts 13, 7, 17), for reproducible choices (the
//! ordering's matchings and roots) and seeded test inputs. Not for statistics: its low bits
//! are weak, and `below` has a modulo bias of order `n / 2^64`.

/// The generator's state (any non-zero value; zero stays zero).
#[derive(Clone, Debug)]
pub struct XorShift64(pub u64);

impl XorShift64 {
    /// The next 64-bit value.
    pub fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }

    /// A value in `0..n` (`0` for `n = 0`).
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n.max(1) as u64) as usize
    }
}
