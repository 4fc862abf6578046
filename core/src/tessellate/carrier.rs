//! Slot sides, the edges they lie on ("carriers"), and canonical vertex
//! keys.
//!
//! Parameters are fixed point: [`FP`] = 1.0, so a dyadic value of level
//! `l <= 31` is exact. A slot side has a coordinate `w` (the slot's u on
//! sides 0 and 2, v on sides 1 and 3) and lies on a carrier with parameter
//! `c`:
//!
//! * quad face, side k = base half-edge `h_k` (corner k -> k+1):
//!   `c = w` (sides 0, 1) or `c = 1 - w` (sides 2, 3), measured from the
//!   half-edge's origin;
//! * sub-face k of an N-gon: side 0 (v = 0) is the first half of `h_k`,
//!   `c = w/2`; side 3 (u = 0) the second half of `h_(k-1)`, `c = 1 - w/2`;
//!   side 1 (u = 1) is internal edge k (from the midpoint of `h_k` to the
//!   centre), `c = w`; side 2 (v = 1) is internal edge k-1, `c = w`. So
//!   sub k's `(1, t)` is sub k+1's `(t, 1)`.
//!
//! Across a base half-edge `h` the twin sees `c' = 1 - c`. Keys identify
//! vertices globally without comparing floats: base vertex id; base edge
//! (the smaller of its two half-edge indices) + `c` measured from that
//! half-edge's origin; N-gon centre (face id); internal edge (`h_k`) + `c`.
//! Points inside a slot need no key (see `vertices.rs`).

/// Fixed-point 1.0 of slot and carrier parameters.
pub(crate) const FP: u64 = 1 << 32;

const T_EDGE: u64 = 1 << 61;
const T_CENTRE: u64 = 2 << 61;
const T_INNER: u64 = 3 << 61;

/// What a slot side lies on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Carrier {
    /// Base half-edge (parameter from its origin).
    Base(u32),
    /// Internal edge k of an N-gon, identified by `h_k` (parameter from the
    /// midpoint of `h_k` towards the centre).
    Inner(u32),
}

/// A slot side and its map to the carrier: `c = flip ? 1 - (w >> sh) : w >> sh`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct SideMap {
    pub carrier: Carrier,
    pub sh: u32,
    pub flip: bool,
}

impl SideMap {
    #[inline]
    pub fn to_carrier(self, w: u64) -> u64 {
        let x = w >> self.sh;
        if self.flip {
            FP - x
        } else {
            x
        }
    }
}

/// The mesh connectivity tessellation needs (copied into plan memory).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Topo<'a> {
    /// First half-edge of each face (F+1).
    pub fstart: &'a [u32],
    /// Twin of each half-edge.
    pub twin: &'a [u32],
    /// Origin vertex of each half-edge.
    pub origin: &'a [u32],
    /// First slot of each face (F+1).
    pub slot_start: &'a [u32],
    /// Face of each slot.
    pub slot_face: &'a [u32],
}

impl Topo<'_> {
    #[inline]
    fn size(&self, f: usize) -> u32 {
        self.fstart[f + 1] - self.fstart[f]
    }

    /// (face, sub) of a slot.
    #[inline]
    pub fn face_sub(&self, slot: usize) -> (u32, u32) {
        let f = self.slot_face[slot];
        (f, slot as u32 - self.slot_start[f as usize])
    }

    /// The carrier map of side `side` (0 bottom, 1 right, 2 top, 3 left) of
    /// `slot`.
    pub fn side_map(&self, slot: usize, side: u32) -> SideMap {
        let (f, k) = self.face_sub(slot);
        let n = self.size(f as usize);
        let fs = self.fstart[f as usize];
        if n == 4 {
            return SideMap {
                carrier: Carrier::Base(fs + side),
                sh: 0,
                flip: side >= 2,
            };
        }
        let km1 = (k + n - 1) % n;
        match side & 3 {
            0 => SideMap {
                carrier: Carrier::Base(fs + k),
                sh: 1,
                flip: false,
            },
            1 => SideMap {
                carrier: Carrier::Inner(fs + k),
                sh: 0,
                flip: false,
            },
            2 => SideMap {
                carrier: Carrier::Inner(fs + km1),
                sh: 0,
                flip: false,
            },
            _ => SideMap {
                carrier: Carrier::Base(fs + km1),
                sh: 1,
                flip: true,
            },
        }
    }

    /// Key of the point at carrier parameter `c` (0 < c < 1) of `carrier`.
    #[inline]
    pub fn carrier_key(&self, carrier: Carrier, c: u64) -> u64 {
        match carrier {
            Carrier::Base(h) => {
                let t = self.twin[h as usize];
                let (hc, cc) = if h <= t { (h, c) } else { (t, FP - c) };
                T_EDGE | (hc as u64) << 33 | cc
            }
            Carrier::Inner(hk) => T_INNER | (hk as u64) << 33 | c,
        }
    }

    /// Key of corner `q` ((0,0), (1,0), (1,1), (0,1)) of `slot`.
    pub fn corner_key(&self, slot: usize, q: usize) -> u64 {
        let (f, k) = self.face_sub(slot);
        let n = self.size(f as usize);
        let fs = self.fstart[f as usize];
        if n == 4 {
            return self.origin[(fs + q as u32) as usize] as u64;
        }
        match q & 3 {
            0 => self.origin[(fs + k) as usize] as u64,
            1 => self.carrier_key(Carrier::Base(fs + k), FP / 2),
            2 => T_CENTRE | f as u64,
            _ => self.carrier_key(Carrier::Base(fs + (k + n - 1) % n), FP / 2),
        }
    }
}
