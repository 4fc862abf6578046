//! Slot sides, the edges they lie on ("carriers"), and the identities of
//! slot corners.
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
//! Across a base half-edge `h` the twin sees `c' = 1 - c`; a base edge's
//! canonical parameter is measured from the origin of the smaller of its
//! two half-edges. Every slot side is one [`Part`] of its carrier: a base
//! edge has one part per quad and two per N-gon on either side, an internal
//! N-gon edge two (sub k's side 1, sub k+1's side 2).
//!
//! Slot corners are identified without comparing floats
//! ([`Topo::corner_id`]): base vertex; N-gon centre (face); midpoint of a
//! base edge next to an N-gon (canonical half-edge).
//!
//! Meshes with boundaries and non-manifold edges (feature meshes) have no
//! twins: there `twin[h]` is the edge's canonical half-edge (the smallest
//! of its half-edges, so `h.min(twin[h])` is canonical either way) and
//! [`Topo::edges`] lists the half-edges of every base edge (one for a
//! boundary edge, three or more for a non-manifold one, in either
//! direction); a face's parts are measured from the canonical half-edge's
//! origin whatever its direction ([`Topo::base_side`]).

/// Fixed-point 1.0 of slot and carrier parameters.
pub(crate) const FP: u64 = 1 << 32;

/// A slot side as a piece of its carrier: canonical carrier parameter
/// `c = neg ? 1 - (w >> sh) : w >> sh` of side coordinate `w`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Part {
    pub slot: u32,
    pub side: u32,
    pub sh: u32,
    pub neg: bool,
}

impl Part {
    /// Carrier parameter of side coordinate `w`.
    #[inline]
    pub fn c(self, w: u64) -> u64 {
        if self.neg {
            FP - (w >> self.sh)
        } else {
            w >> self.sh
        }
    }

    /// Side coordinate of carrier parameter `c` (inside [`Part::range`]).
    #[inline]
    pub fn w(self, c: u64) -> u64 {
        (if self.neg { FP - c } else { c }) << self.sh
    }

    /// The closed carrier interval the side covers.
    #[inline]
    pub fn range(self) -> (u64, u64) {
        let len = FP >> self.sh;
        if self.neg {
            (FP - len, FP)
        } else {
            (0, len)
        }
    }
}

/// One side of a carrier: the parts of one face in increasing carrier
/// parameter (one for a quad or an internal edge, two for an N-gon's base
/// edge, with the edge midpoint, a slot corner, between them: `mid`).
#[derive(Clone, Copy, Debug)]
pub(crate) struct FaceSide {
    pub parts: [Part; 2],
    pub n: usize,
    /// Slot and corner of the midpoint (N-gon base edges only).
    pub mid: Option<(u32, u32)>,
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
    /// Face of each half-edge.
    pub he_face: &'a [u32],
    /// Base vertices.
    pub nv: usize,
    /// Feature meshes: the half-edges of base edge `e` are
    /// `edges.1[edges.0[e]..edges.0[e + 1]]`, the canonical one first (see
    /// the module docs); `None`: every half-edge has a twin.
    pub edges: Option<(&'a [u32], &'a [u32])>,
}

impl Topo<'_> {
    #[inline]
    fn size(&self, f: usize) -> u32 {
        self.fstart[f + 1] - self.fstart[f]
    }

    /// Faces.
    #[inline]
    pub fn num_faces(&self) -> usize {
        self.fstart.len() - 1
    }

    /// (face, sub) of a slot.
    #[inline]
    pub fn face_sub(&self, slot: usize) -> (u32, u32) {
        let f = self.slot_face[slot];
        (f, slot as u32 - self.slot_start[f as usize])
    }

    /// Identity of corner `q` ((0,0), (1,0), (1,1), (0,1)) of `slot`, below
    /// `nv + F + H`: base vertex `v`; N-gon centre `nv + f`; edge midpoint
    /// `nv + F + h` (`h` the smaller half-edge of the edge).
    pub fn corner_id(&self, slot: usize, q: usize) -> usize {
        let (f, k) = self.face_sub(slot);
        let n = self.size(f as usize);
        let fs = self.fstart[f as usize];
        if n == 4 {
            return self.origin[(fs + q as u32) as usize] as usize;
        }
        let mid = |h: u32| self.nv + self.num_faces() + h.min(self.twin[h as usize]) as usize;
        match q & 3 {
            0 => self.origin[(fs + k) as usize] as usize,
            1 => mid(fs + k),
            2 => self.nv + f as usize,
            _ => mid(fs + (k + n - 1) % n),
        }
    }

    /// The parts of base half-edge `h`'s face on its edge, in increasing
    /// parameter measured from the origin of `canonical` (`h` or its twin).
    pub fn base_side(&self, h: u32, canonical: u32) -> FaceSide {
        let f = self.he_face[h as usize] as usize;
        let fs = self.fstart[f];
        let n = self.size(f);
        let k = h - fs;
        // Same direction as the canonical half-edge (with twins: `h` is
        // it, a twin runs the other way).
        let own = h == canonical || self.origin[h as usize] == self.origin[canonical as usize];
        let ss = self.slot_start[f];
        if n == 4 {
            // c_own = w (sides 0, 1) or 1 - w (sides 2, 3).
            let part = Part {
                slot: ss,
                side: k,
                sh: 0,
                neg: (k >= 2) == own,
            };
            return FaceSide {
                parts: [part; 2],
                n: 1,
                mid: None,
            };
        }
        // First half: sub k's side 0 (c_own = w/2); second half: sub
        // k+1's side 3 (c_own = 1 - w/2).
        let first = Part {
            slot: ss + k,
            side: 0,
            sh: 1,
            neg: !own,
        };
        let second = Part {
            slot: ss + (k + 1) % n,
            side: 3,
            sh: 1,
            neg: own,
        };
        FaceSide {
            parts: if own {
                [first, second]
            } else {
                [second, first]
            },
            n: 2,
            mid: Some((ss + k, 1)),
        }
    }

    /// The two sides of internal edge k of N-gon face `f`: sub k's side 1
    /// and sub k+1's side 2, both `c = w`.
    pub fn inner_sides(&self, f: usize, k: u32) -> [FaceSide; 2] {
        let n = self.size(f);
        let ss = self.slot_start[f];
        let side = |slot, side| {
            let p = Part {
                slot,
                side,
                sh: 0,
                neg: false,
            };
            FaceSide {
                parts: [p; 2],
                n: 1,
                mid: None,
            }
        };
        [side(ss + k, 1), side(ss + (k + 1) % n, 2)]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A quad (face 0, half-edges 0..4) next to a triangle (face 1,
    /// half-edges 4..7) across half-edges 1 and 4: the parts of the two
    /// faces cover the edge in increasing canonical parameter, and a point
    /// of the quad's side maps to the same canonical parameter as the same
    /// point of the triangle's sub-face sides.
    #[test]
    fn parts_agree_across_an_edge() {
        let fstart = [0, 4, 7];
        let mut twin = [0u32; 7];
        twin[1] = 4;
        twin[4] = 1;
        let origin = [0, 1, 2, 3, 2, 1, 4];
        let t = Topo {
            fstart: &fstart,
            twin: &twin,
            origin: &origin,
            slot_start: &[0, 1, 4],
            slot_face: &[0, 1, 1, 1],
            he_face: &[0, 0, 0, 0, 1, 1, 1],
            nv: 5,
            edges: None,
        };
        let quad = t.base_side(1, 1);
        let tri = t.base_side(4, 1);
        assert_eq!(quad.n, 1);
        assert_eq!(tri.n, 2);
        // Quad side 1 runs from vertex 1 to 2 with w = v: c = w.
        let q = quad.parts[0];
        assert_eq!((q.slot, q.side, q.neg), (0, 1, false));
        // Triangle's half-edge 4 runs 2 -> 1: canonical c = 1 - c_own. Its
        // first canonical half (near vertex 1) is sub 1's side 3.
        let [a, b] = tri.parts;
        assert_eq!((a.slot, a.side), (2, 3));
        assert_eq!((b.slot, b.side), (1, 0));
        assert_eq!(a.range(), (0, FP / 2));
        assert_eq!(b.range(), (FP / 2, FP));
        assert_eq!(tri.mid, Some((1, 1)));
        for x in [1u64, 3, 5, 7] {
            let c = x << 29;
            let p = if c < FP / 2 { a } else { b };
            assert_eq!(p.c(p.w(c)), c);
            assert_eq!(q.c(q.w(c)), c);
        }
        // The edge midpoint is the same corner for both sub-faces.
        assert_eq!(t.corner_id(1, 1), t.corner_id(2, 3));
        assert_eq!(t.corner_id(1, 1), 5 + 2 + 1);
        assert_eq!(t.corner_id(1, 2), 5 + 1);
    }
}
