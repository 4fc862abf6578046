//! Checksums that two machines can compare to a relative tolerance.

/// A weighted sum of values and the same sum of their magnitudes: two runs
/// agree to `tol` when `|a.sum - b.sum| <= tol * max(a.abs, b.abs)` and the
/// magnitudes agree to `tol` relative (no cancellation can hide a
/// difference in the signed sum, since the magnitude sum bounds it).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Sum {
    /// Signed weighted sum.
    pub sum: f64,
    /// Weighted sum of magnitudes.
    pub abs: f64,
    /// Values added.
    pub count: u64,
}

impl Sum {
    /// Adds `x` with a weight that depends on its position in the stream
    /// (1, 2, ..., 7, 1, ...), so that a permutation changes the sum.
    pub fn add(&mut self, x: f64) {
        let w = (self.count % 7 + 1) as f64;
        self.sum += w * x;
        self.abs += w * libm_fabs(x);
        self.count += 1;
    }

    /// Adds the three coordinates of a point.
    pub fn add3(&mut self, p: [f64; 3]) {
        for x in p {
            self.add(x);
        }
    }
}

fn libm_fabs(x: f64) -> f64 {
    f64::from_bits(x.to_bits() & !(1u64 << 63))
}

/// A stream of `u32` values folded into one `u64` (FNV-1a over the
/// little-endian bytes): integer results must agree exactly.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Hash(pub u64);

impl Default for Hash {
    fn default() -> Self {
        Hash(0xcbf2_9ce4_8422_2325)
    }
}

impl Hash {
    /// Folds in one value.
    pub fn add(&mut self, x: u32) {
        for b in x.to_le_bytes() {
            self.0 ^= b as u64;
            self.0 = self.0.wrapping_mul(0x0100_0000_01b3);
        }
    }
}
