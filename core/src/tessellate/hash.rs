//! Open-addressing hash table (linear probing) from vertex keys to vertex
//! indices, in caller memory. Only vertices on slot boundaries (base
//! vertices, points on base edges and internal N-gon edges, N-gon centres)
//! go through it; its capacity is a power of two at least twice the number
//! of such points the marking can create.

/// Keys are stored as (high, low) u32 halves; an empty slot has both
/// halves `u32::MAX` (no key has the top bits 0b111).
const EMPTY: u32 = u32::MAX;

/// Capacity (entries) for at most `n` keys.
pub(crate) fn capacity(n: usize) -> usize {
    n.saturating_mul(2).max(16).next_power_of_two()
}

/// The table over caller slices: `keys.len() == 2 * vals.len()`, a power
/// of two entries.
pub(crate) struct Table<'a> {
    keys: &'a mut [u32],
    vals: &'a mut [u32],
    shift: u32,
}

impl<'a> Table<'a> {
    pub fn new(keys: &'a mut [u32], vals: &'a mut [u32]) -> Self {
        let cap = vals.len().max(1);
        let bits = cap.trailing_zeros();
        let mut t = Table {
            keys,
            vals,
            shift: 64 - bits,
        };
        t.clear();
        t
    }

    /// The table over slices filled by an earlier `new` (not cleared).
    pub fn attach(keys: &'a mut [u32], vals: &'a mut [u32]) -> Self {
        let bits = vals.len().max(1).trailing_zeros();
        Table {
            keys,
            vals,
            shift: 64 - bits,
        }
    }

    pub fn clear(&mut self) {
        self.keys.fill(EMPTY);
    }

    #[inline]
    fn home(&self, key: u64) -> usize {
        if self.shift >= 64 {
            0
        } else {
            (key.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> self.shift) as usize
        }
    }

    /// The index stored for `key`, or `None`.
    #[inline]
    pub fn get(&self, key: u64) -> Option<u32> {
        let mask = self.vals.len() - 1;
        let (hi, lo) = ((key >> 32) as u32, key as u32);
        let mut i = self.home(key) & mask;
        for _ in 0..self.vals.len() {
            let (kh, kl) = (self.keys[2 * i], self.keys[2 * i + 1]);
            if kh == hi && kl == lo {
                return Some(self.vals[i]);
            }
            if kh == EMPTY && kl == EMPTY {
                return None;
            }
            i = (i + 1) & mask;
        }
        None
    }

    /// The index of `key`, inserting `fresh` if absent: `(index, inserted)`;
    /// `None` if the table is full (cannot happen within its capacity).
    #[inline]
    pub fn get_or_insert(&mut self, key: u64, fresh: u32) -> Option<(u32, bool)> {
        let mask = self.vals.len() - 1;
        let (hi, lo) = ((key >> 32) as u32, key as u32);
        let mut i = self.home(key) & mask;
        for _ in 0..self.vals.len() {
            let (kh, kl) = (self.keys[2 * i], self.keys[2 * i + 1]);
            if kh == hi && kl == lo {
                return Some((self.vals[i], false));
            }
            if kh == EMPTY && kl == EMPTY {
                self.keys[2 * i] = hi;
                self.keys[2 * i + 1] = lo;
                self.vals[i] = fresh;
                return Some((fresh, true));
            }
            i = (i + 1) & mask;
        }
        None
    }
}
