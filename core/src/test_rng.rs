//! The pseudo-random numbers of the unit tests: Marsaglia's xorshift64
//! (shifts 13, 7, 17), one generator instead of a copy per test.

/// A xorshift64 generator; the seed must not be zero.
pub(crate) struct XorShift(pub(crate) u64);

impl XorShift {
    /// The next state.
    pub(crate) fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }

    /// The next state's top 53 bits as a number in `[0, 1)`.
    pub(crate) fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
}
