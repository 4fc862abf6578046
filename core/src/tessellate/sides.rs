//! Vertices on slot boundaries: their numbering, carrier by carrier, and
//! the point list of every slot side that the polygon pass reads.
//!
//! The points on a carrier (a base edge or an internal N-gon edge, see
//! [`super::carrier`]) are the side midpoints of the internal nodes that
//! touch it, from the slots on both sides, plus the midpoint of a base
//! edge next to an N-gon (a slot corner there). The slot walk of the
//! numbering ([`super::vertices::assign`]) meets a node's midpoint on side
//! k when it moves on to the node's second child along that side, which
//! is the midpoint's in-order place: so each slot side's own points come
//! sorted along the side for free ([`SideLists::push`],
//! [`SideLists::end_slot`]). The points of a carrier are then the merge of
//! two sorted sequences, one per face ([`number`]): equal parameters are one
//! vertex, numbered once and written into the records of both nodes (the
//! one in the earlier slot with [`OWN`]: it writes the position). No
//! hashing, no comparison of floats.
//!
//! The union is written out per slot side as `(w, vertex)` pairs in
//! increasing side coordinate `w`. A leaf's polygon needs the points
//! strictly inside its side's interval; leaves along a side are visited
//! monotonically by the polygon pass's depth-first walk (sides 0, 1 and 3
//! in increasing `w`, side 2 decreasing), so a cursor per side finds them
//! without searching ([`Cursors`]).

use super::carrier::{FaceSide, Part, Topo, FP};
use super::forest::along_index;
use super::record::{INDEX, OWN};
use crate::error::Error;

/// One point of a side list: side coordinate `w` (< [`FP`]) and vertex
/// (or, in a slot's own points, the position of the record entry).
pub(crate) type Pt = [u32; 2];

/// The side lists and the numbering's working lists (caller memory).
pub(crate) struct SideLists<'a> {
    /// Start and length in `pts` of each slot side's list (8 per slot).
    at: &'a mut [u32],
    /// The lists: every vertex strictly inside each slot side.
    pts: &'a mut [Pt],
    /// Start and length in `own` of each slot side's own points.
    own_at: &'a mut [u32],
    /// The midpoints of each slot side's own nodes (record positions).
    own: &'a mut [Pt],
    /// The slot being walked: its midpoints in walk order (side in the low
    /// two bits of `w`); later one carrier's face sequences and union.
    tmp: &'a mut [Pt],
    nown: usize,
    ntmp: usize,
    /// Midpoints of the slot being walked per side.
    count: [usize; 4],
    /// Pairs written to `pts`.
    npts: usize,
    /// Feature meshes: the sum over carriers of `(faces - 2)` times the
    /// output edges along the carrier (for the polygon-index count).
    pub extra: i64,
}

/// u32 values of the side lists for `side_mids` boundary midpoints in a
/// mesh of `nh` half-edges whose carriers have at most `kmax` faces: with
/// `kmax <= 2` every point of a carrier lies on one side of each face,
/// except an N-gon edge's midpoint (a slot corner, on a quad side at
/// most), so at most `2 side_mids + nh` pairs; with more, every point of a
/// carrier (its own midpoints and at most one edge midpoint per carrier)
/// lies on at most `kmax` sides.
pub(crate) fn pts_len(side_mids: usize, nh: usize, kmax: usize) -> usize {
    if kmax <= 2 {
        2 * (2 * side_mids + nh)
    } else {
        2 * kmax * (side_mids + nh)
    }
}

/// u32 values of the own points (`own`: `side_mids` of all slots) and of
/// `tmp`: a slot's midpoints (at most `max_slot`, the most of one slot); or
/// a carrier's face sequences (at most the midpoints of two slots and one
/// edge midpoint per face) and their union (at most as long).
///
/// `kmax = 0`: a mesh with twins (two faces per carrier, one of them
/// read in place). Otherwise (feature meshes, at most `kmax` faces per
/// base edge): every face's sequence, a (cursor, end) pair per face and
/// the union.
pub(crate) fn own_len(side_mids: usize, max_slot: usize, kmax: usize) -> (usize, usize) {
    if kmax == 0 {
        return (2 * side_mids, 4 * (4 * max_slot + 2));
    }
    let k = kmax.max(2);
    (2 * side_mids, 2 * (2 * k * (2 * max_slot + 1) + k))
}

const SMALL: Error = Error::InvalidArgument("internal: side lists beyond their size");

/// The list `k` (slot side `4 s + side`) of `at` / `pts`.
#[inline(always)]
fn list<'p>(at: &[u32], pts: &'p [Pt], k: usize) -> &'p [Pt] {
    let (a, n) = (at[2 * k] as usize, at[2 * k + 1] as usize);
    pts.get(a..a + n).unwrap_or(&[])
}

impl<'a> SideLists<'a> {
    /// Over caller memory: `at` and `own_at` 8 per slot, `pts` and `own`,
    /// `tmp` as [`pts_len`] and [`own_len`] say.
    pub fn new(
        at: &'a mut [u32],
        pts: &'a mut [Pt],
        own_at: &'a mut [u32],
        own: &'a mut [Pt],
        tmp: &'a mut [Pt],
    ) -> Self {
        SideLists {
            at,
            pts,
            own_at,
            own,
            tmp,
            nown: 0,
            ntmp: 0,
            count: [0; 4],
            npts: 0,
            extra: 0,
        }
    }

    /// Records the midpoints of the sides `due` (bit per side) of the node
    /// at `(level, i, j)` of the slot being walked, whose record is at
    /// `r`, in walk order.
    #[inline(always)]
    pub fn push(
        &mut self,
        (level, i, j): (u32, u32, u32),
        due: u32,
        r: usize,
    ) -> Result<(), Error> {
        // Internal nodes lie above the deepest level (trees made elsewhere
        // are checked here), so the two low bits of w are free for the side.
        if level >= super::MAX_LEVEL {
            return Err(Error::InvalidArgument(super::TOO_DEEP));
        }
        for side in 0..4 {
            if due & (1 << side) != 0 {
                let x = along_index(i, j, side) as u64;
                let w = ((2 * x + 1) << (31 - level)) as u32 | side as u32;
                *self.tmp.get_mut(self.ntmp).ok_or(SMALL)? = [w, (r + 1 + side) as u32];
                self.ntmp += 1;
                self.count[side] += 1;
            }
        }
        Ok(())
    }

    /// Ends slot `s`: its midpoints become the own lists of its sides, in
    /// increasing `w` (the walk met side 2's in decreasing order).
    pub fn end_slot(&mut self, s: usize) -> Result<(), Error> {
        let seen = &self.tmp[..self.ntmp];
        let count = self.count;
        let start = self.nown;
        let dst = self.own.get_mut(start..start + seen.len()).ok_or(SMALL)?;
        let mut at = [
            0,
            count[0],
            count[0] + count[1],
            count[0] + count[1] + count[2],
        ];
        let ends = [at[1], at[2], at[3], seen.len()];
        for e in seen {
            let k = (e[0] & 3) as usize;
            // Side 2 from the back of its range.
            let d = if k == 2 {
                ends[2] - 1 - (at[2] - ends[1])
            } else {
                at[k]
            };
            at[k] += 1;
            *dst.get_mut(d).ok_or(SMALL)? = [e[0] & !3, e[1]];
        }
        for side in 0..4 {
            let k = 2 * (4 * s + side);
            let d = self.own_at.get_mut(k..k + 2).ok_or(SMALL)?;
            d.copy_from_slice(&[
                (start + ends[side] - count[side]) as u32,
                count[side] as u32,
            ]);
        }
        self.nown += seen.len();
        self.ntmp = 0;
        self.count = [0; 4];
        Ok(())
    }
}

/// Flag of a face sequence's source: a slot corner's vertex (an N-gon
/// edge's midpoint), not the position of a record entry.
const CORNER_FLAG: u32 = 1 << 31;

impl SideLists<'_> {
    /// Writes the points of one face on a carrier into `tmp[at..]`, in
    /// increasing canonical parameter: `(c, source)`, the source a record
    /// entry's position or a slot corner's vertex | [`CORNER_FLAG`] (the own
    /// points of the parts, read backwards where `c` falls with `w`, with
    /// the edge midpoint between two parts). Returns the count.
    fn face(&mut self, side: FaceSide, corners: &[u32], at: usize) -> Result<usize, Error> {
        let mut n = at;
        for (k, &p) in side.parts[..side.n].iter().enumerate() {
            if k == 1 {
                let (s, q) = side.mid.unwrap_or((0, 0));
                let v = corners[4 * s as usize + q as usize] & INDEX;
                *self.tmp.get_mut(n).ok_or(SMALL)? = [(FP / 2) as u32, v | CORNER_FLAG];
                n += 1;
            }
            let own = list(self.own_at, self.own, 4 * p.slot as usize + p.side as usize);
            let dst = self.tmp.get_mut(n..n + own.len()).ok_or(SMALL)?;
            let conv = |e: &Pt| [p.c(e[0] as u64) as u32, e[1]];
            if p.neg {
                for (d, e) in dst.iter_mut().zip(own.iter().rev()) {
                    *d = conv(e);
                }
            } else {
                for (d, e) in dst.iter_mut().zip(own) {
                    *d = conv(e);
                }
            }
            n += own.len();
        }
        Ok(n - at)
    }

    /// Numbers the points of the carrier whose two faces are `a` and `b`
    /// (vertices from `next` on) and writes the lists of its slot sides.
    fn carrier(
        &mut self,
        recs: &mut [u32],
        corners: &[u32],
        a: FaceSide,
        b: FaceSide,
        next: &mut u32,
    ) -> Result<(), Error> {
        // A face with two parts is written out first (with the edge
        // midpoint); a face with one is read straight from its own list.
        let na = if a.n == 2 {
            self.face(a, corners, 0)?
        } else {
            0
        };
        let nb = if b.n == 2 {
            self.face(b, corners, na)?
        } else {
            0
        };
        let SideLists {
            own_at, own, tmp, ..
        } = self;
        let (seqs, union) = tmp.split_at_mut(na + nb);
        /// A face's sequence and how to read it.
        fn read<'s>(f: FaceSide, seq: &'s [Pt], own_at: &[u32], own: &'s [Pt]) -> (&'s [Pt], Part) {
            if f.n == 2 {
                let plain = Part {
                    slot: 0,
                    side: 0,
                    sh: 0,
                    neg: false,
                };
                (seq, plain)
            } else {
                let p = f.parts[0];
                (list(own_at, own, 4 * p.slot as usize + p.side as usize), p)
            }
        }
        let (sa, qa) = read(a, &seqs[..na], own_at, own);
        let (sb, qb) = read(b, &seqs[na..], own_at, own);
        let union = union.get_mut(..sa.len() + sb.len()).ok_or(SMALL)?;
        // Point i of a sequence in increasing parameter: (c, source); past
        // the end a parameter above every point.
        #[inline(always)]
        fn at(s: &[Pt], p: Part, i: usize) -> (u64, u32) {
            match s.get(if p.neg {
                s.len().wrapping_sub(1 + i)
            } else {
                i
            }) {
                Some(e) => (p.c(e[0] as u64), e[1]),
                None => (u64::MAX, 0),
            }
        }
        let (mut i, mut j, mut n) = (0usize, 0usize, 0usize);
        loop {
            // The smaller parameter first; equal ones are the same vertex.
            // A point of one face only has `q = p`.
            let ((ca, pa), (cb, pb)) = (at(sa, qa, i), at(sb, qb, j));
            let (c, p, q) = if ca < cb {
                i += 1;
                (ca, pa, pa)
            } else if cb < ca {
                j += 1;
                (cb, pb, pb)
            } else if ca == u64::MAX {
                break;
            } else {
                (i, j) = (i + 1, j + 1);
                (ca, pa, pb)
            };
            let v = if (p | q) & CORNER_FLAG != 0 {
                // The slot corner's owner writes it.
                let v = if p & CORNER_FLAG != 0 { p } else { q } & !CORNER_FLAG;
                for r in [p, q] {
                    if r & CORNER_FLAG == 0 {
                        *recs.get_mut(r as usize).ok_or(SMALL)? = v;
                    }
                }
                v
            } else {
                let v = *next;
                *next += 1;
                // The earlier slot's node (records are in slot order)
                // writes the point.
                *recs.get_mut(p.max(q) as usize).ok_or(SMALL)? = v;
                *recs.get_mut(p.min(q) as usize).ok_or(SMALL)? = v | OWN;
                v
            };
            *union.get_mut(n).ok_or(SMALL)? = [c as u32, v];
            n += 1;
        }
        let at = na + nb;
        for side in [a, b] {
            for &p in &side.parts[..side.n] {
                self.write_list(p, at, n)?;
            }
        }
        Ok(())
    }

    /// Writes the list of part `p` from the union, `tmp[at..at + n]`.
    fn write_list(&mut self, p: Part, at: usize, n: usize) -> Result<(), Error> {
        let u = &self.tmp[at..at + n];
        let (c0, c1) = p.range();
        let (mut lo, mut hi) = (0, n);
        if p.sh != 0 {
            // Half an edge: the union points on its side of the midpoint.
            lo = u.partition_point(|e| e[0] as u64 <= c0);
            hi = u.partition_point(|e| (e[0] as u64) < c1);
        }
        let len = hi.saturating_sub(lo);
        let used = self.npts;
        let dst = self.pts.get_mut(used..used + len).ok_or(SMALL)?;
        let inside = &u[lo..lo + len];
        let conv = |e: &Pt| [p.w(e[0] as u64) as u32, e[1]];
        if p.neg {
            for (d, e) in dst.iter_mut().zip(inside.iter().rev()) {
                *d = conv(e);
            }
        } else {
            for (d, e) in dst.iter_mut().zip(inside) {
                *d = conv(e);
            }
        }
        let k = 2 * (4 * p.slot as usize + p.side as usize);
        let at = self.at.get_mut(k..k + 2).ok_or(SMALL)?;
        at.copy_from_slice(&[used as u32, len as u32]);
        self.npts += len;
        Ok(())
    }
}

impl SideLists<'_> {
    /// [`SideLists::carrier`] for a base edge of a feature mesh with any
    /// number of faces (half-edges `hs`, the canonical one first): every
    /// face's points in increasing canonical parameter, merged; equal
    /// parameters are one vertex, written by the first record in slot
    /// order ([`OWN`]) or by the slot corner that is the edge midpoint.
    fn carrier_multi(
        &mut self,
        t: Topo,
        recs: &mut [u32],
        corners: &[u32],
        hs: &[u32],
        next: &mut u32,
    ) -> Result<(), Error> {
        let Some(&canon) = hs.first() else {
            return Ok(());
        };
        // The faces' sequences one after the other, then a (cursor, end)
        // pair per face, then the union.
        let k = hs.len();
        let mut n = 0usize;
        for &h in hs {
            n += self.face(t.base_side(h, canon), corners, n)?;
        }
        let mut start = 0usize;
        for (f, &h) in hs.iter().enumerate() {
            // The length [`SideLists::face`] wrote: own points of the parts
            // and the midpoint between two.
            let side = t.base_side(h, canon);
            let len = side.parts[..side.n]
                .iter()
                .map(|p| list(self.own_at, self.own, 4 * p.slot as usize + p.side as usize).len())
                .sum::<usize>()
                + side.n
                - 1;
            *self.tmp.get_mut(n + f).ok_or(SMALL)? = [start as u32, (start + len) as u32];
            start += len;
        }
        if start != n {
            return Err(SMALL);
        }
        let (seqs, rest) = self.tmp.split_at_mut(n);
        let (cur, union) = rest.split_at_mut(k);
        let at = n + k;
        let mut m = 0usize;
        loop {
            // The smallest parameter among the faces' next points.
            let mut c = u64::MAX;
            for e in cur.iter() {
                if e[0] < e[1] {
                    c = c.min(seqs[e[0] as usize][0] as u64);
                }
            }
            if c == u64::MAX {
                break;
            }
            // Its sources: a slot corner (the edge midpoint) or the
            // smallest record position owns it.
            let mut corner = None;
            let mut first = u32::MAX;
            for e in cur.iter() {
                if e[0] < e[1] && seqs[e[0] as usize][0] as u64 == c {
                    let src = seqs[e[0] as usize][1];
                    if src & CORNER_FLAG != 0 {
                        corner = Some(src & !CORNER_FLAG);
                    } else {
                        first = first.min(src);
                    }
                }
            }
            let v = match corner {
                Some(v) => v,
                None => {
                    *next += 1;
                    *next - 1
                }
            };
            for e in cur.iter_mut() {
                if e[0] < e[1] && seqs[e[0] as usize][0] as u64 == c {
                    let src = seqs[e[0] as usize][1];
                    if src & CORNER_FLAG == 0 {
                        let own = if corner.is_none() && src == first {
                            OWN
                        } else {
                            0
                        };
                        *recs.get_mut(src as usize).ok_or(SMALL)? = v | own;
                    }
                    e[0] += 1;
                }
            }
            *union.get_mut(m).ok_or(SMALL)? = [c as u32, v];
            m += 1;
        }
        self.extra += (hs.len() as i64 - 2) * (m as i64 + 1);
        for &h in hs {
            let side = t.base_side(h, canon);
            for &p in &side.parts[..side.n] {
                self.write_list(p, at, m)?;
            }
        }
        Ok(())
    }
}

/// Numbers the points on slot boundaries (after the slot walks of
/// [`super::vertices::assign`] numbered everything else, slot corners
/// among them, up to `next`), writes them into the records and fills the
/// side lists. Returns the vertex count.
pub(crate) fn number(
    t: Topo,
    recs: &mut [u32],
    corners: &[u32],
    lists: &mut SideLists,
    mut next: u32,
) -> Result<u32, Error> {
    lists.npts = 0;
    lists.extra = 0;
    if let Some((start, hes)) = t.edges {
        for e in 0..start.len().saturating_sub(1) {
            let hs = hes
                .get(start[e] as usize..start[e + 1] as usize)
                .ok_or(SMALL)?;
            lists.carrier_multi(t, recs, corners, hs, &mut next)?;
        }
    } else {
        for h in 0..t.twin.len() as u32 {
            let tw = t.twin[h as usize];
            if h < tw {
                lists.carrier(
                    recs,
                    corners,
                    t.base_side(h, h),
                    t.base_side(tw, h),
                    &mut next,
                )?;
            }
        }
    }
    for face in 0..t.num_faces() {
        let n = t.fstart[face + 1] - t.fstart[face];
        // (Hole faces of feature meshes have no slots.)
        if n != 4 && t.slot_start[face + 1] > t.slot_start[face] {
            for k in 0..n {
                let [a, b] = t.inner_sides(face, k);
                lists.carrier(recs, corners, a, b, &mut next)?;
            }
        }
    }
    Ok(next)
}

/// Per-slot cursors into the four side lists for the polygon pass.
pub(crate) struct Cursors<'p> {
    lists: [&'p [Pt]; 4],
    /// Sides 0, 1, 3: the first point not behind the walk; side 2 (walked
    /// in decreasing `w`): one past the last such point.
    cur: [usize; 4],
}

impl<'p> Cursors<'p> {
    /// The cursors of slot `s`.
    pub fn new(at: &[u32], pts: &'p [Pt], s: usize) -> Self {
        let lists: [&[Pt]; 4] = core::array::from_fn(|k| list(at, pts, 4 * s + k));
        Cursors {
            cur: [0, 0, lists[2].len(), 0],
            lists,
        }
    }

    /// The points of side `side` strictly inside `(w0, w1)`, in increasing
    /// `w`. The intervals asked for along a side must come in the polygon
    /// pass's order: the lower ends never decreasing on sides 0, 1 and 3,
    /// the upper ends never increasing on side 2.
    #[inline(always)]
    pub fn inside(&mut self, side: usize, w0: u64, w1: u64) -> &'p [Pt] {
        let l = self.lists[side & 3];
        if side == 2 {
            let mut hi = self.cur[2];
            while hi > 0 && l[hi - 1][0] as u64 >= w1 {
                hi -= 1;
            }
            self.cur[2] = hi;
            let mut lo = hi;
            while lo > 0 && l[lo - 1][0] as u64 > w0 {
                lo -= 1;
            }
            &l[lo..hi]
        } else {
            let side = side & 3;
            let mut lo = self.cur[side];
            while lo < l.len() && l[lo][0] as u64 <= w0 {
                lo += 1;
            }
            self.cur[side] = lo;
            let mut hi = lo;
            while hi < l.len() && (l[hi][0] as u64) < w1 {
                hi += 1;
            }
            &l[lo..hi]
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A cursor gives the same points as filtering the list, for the
    /// interval sequences of a walk along each side (a level-2 bottom
    /// node's interval, then its two halves, and so on).
    #[test]
    fn cursors_match_filtering() {
        let q = FP / 16;
        let pts: [Pt; 6] = [1, 2, 4, 8, 12, 13].map(|x| [(x * q) as u32, x as u32]);
        let at = [0u32, 6, 0, 6, 0, 6, 0, 6];
        let filter = |w0: u64, w1: u64| -> [u32; 6] {
            let mut r = [0u32; 6];
            let inside = pts
                .iter()
                .filter(|p| (p[0] as u64) > w0 && (p[0] as u64) < w1);
            for (d, p) in r.iter_mut().zip(inside) {
                *d = p[1];
            }
            r
        };
        let got = |s: &[Pt]| -> [u32; 6] {
            let mut r = [0u32; 6];
            for (d, p) in r.iter_mut().zip(s) {
                *d = p[1];
            }
            r
        };
        // Increasing sides: [0, 1/4], [0, 1/8], [1/8, 1/4], [1/4, 1/2],
        // [1/2, 1], [1/2, 3/4], [3/4, 1].
        let inc = [(0, 4), (0, 2), (2, 4), (4, 8), (8, 16), (8, 12), (12, 16)];
        for side in [0, 1, 3] {
            let mut c = Cursors::new(&at, &pts, 0);
            for &(a, b) in &inc {
                let (w0, w1) = (a * q, b * q);
                assert_eq!(got(c.inside(side, w0, w1)), filter(w0, w1), "{a} {b}");
            }
        }
        // Side 2 is walked in decreasing w: the mirror image.
        let mut c = Cursors::new(&at, &pts, 0);
        for &(a, b) in &inc {
            let (w0, w1) = (16 * q - b * q, 16 * q - a * q);
            assert_eq!(got(c.inside(2, w0, w1)), filter(w0, w1), "{a} {b}");
        }
    }
}
