//! Deterministic pseudo-random numbers: Marsaglia's xorshift64 (G. Marsaglia, "Xorshift
//! RNGs", J. Stat. Softw. 8(14), 2003; shifts 13, 7, 17), for reproducible choices (the
//! ordering's matchings and roots) and seeded test inputs. Not for statistics: its low bits
//! are weak, and `below` has a modulo bias of order `n / 2^64`.

/// The generator's state (any non-zero value; zero stays zero).
#[derive(Clone, Debug)]
pub struct XorShift64(pub u64);

impl XorShift64 {
    /// A generator from any seed (zero included): the seed is spread over the bits by a
    /// Fibonacci-hashing multiply and made odd, so the state is never zero.
    pub fn seeded(seed: u64) -> XorShift64 {
        XorShift64(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }

    /// The next 64-bit value.
    pub fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }

    /// A value in `[-0.5, 0.5)` from the top 53 bits.
    pub fn centred_uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    }

    /// A value in `0..n` (`0` for `n = 0`).
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n.max(1) as u64) as usize
    }
}
