//! Polygon assembly (second half of the paper's AdaptiveRendering): one
//! polygon per leaf cell, counter-clockwise in the slot's (u, v) (outward).
//!
//! Crack elimination: each side of a leaf is replaced by the polyline of
//! all vertices on it. Those are the leaf's two corners plus the midpoints
//! of the finer cells on the other side: inside the slot, the subtree of
//! the same-level neighbour (if split) read in order along the shared side;
//! on the slot boundary, the subtrees of the slot(s) across the base edge
//! or internal N-gon edge, located by descending their trees to the
//! matching dyadic interval (plus the N-gon edge midpoint between two
//! half-edge pieces). Both polygons of an edge therefore list the same
//! vertices: the output is watertight by construction.

use super::carrier::{Piece, FP};
use super::forest::{along, along_index, increasing, on_boundary, opposite, Forest};
use super::hash::Table;
use super::mark::child_ij;
use super::scratch::{Scratch, LEVELS, NONE};
use super::triangulate::triangulate;
use super::vertices::{child_links, load_links, INDEX};
use super::{PolygonCell, MAX_LEVEL, TOO_DEEP};
use crate::Error;

/// Where polygons go (`None` in [`assemble`]: count only).
pub(crate) struct PolyOut<'o> {
    pub sizes: &'o mut [u32],
    pub indices: &'o mut [u32],
    pub triangles: Option<&'o mut [u32]>,
    pub cells: Option<&'o mut [PolygonCell]>,
    pub positions: &'o [f64],
}

/// Appends a polygon's vertex indices (or only counts them).
struct Sink<'d> {
    dst: Option<&'d mut [u32]>,
    at: usize,
    count: usize,
    overflow: bool,
}

impl Sink<'_> {
    #[inline]
    fn push(&mut self, v: u32) {
        if let Some(d) = self.dst.as_deref_mut() {
            match d.get_mut(self.at + self.count) {
                Some(x) => *x = v,
                None => self.overflow = true,
            }
        }
        self.count += 1;
    }
}

/// Read access for the in-order walks.
struct Walk<'f, 'r> {
    f: &'f Forest<'f>,
    recs: &'r [u32],
}

impl Walk<'_, '_> {
    /// Calls `emit` with the midpoints on side `side` of the subtree of node
    /// `x` of slot `s`, in increasing (or decreasing) coordinate order.
    fn along_side(&self, s: usize, x: u32, side: usize, inc: bool, emit: &mut impl FnMut(u32)) {
        let order = along(side);
        let (first, second) = if inc {
            (order[0], order[1])
        } else {
            (order[1], order[0])
        };
        let mut stack = [0u32; MAX_LEVEL as usize + 2];
        let mut top = 0usize;
        let mut cur = x;
        loop {
            loop {
                let c = self.f.child(s, cur);
                if c == 0 || top >= stack.len() {
                    break;
                }
                stack[top] = cur;
                top += 1;
                cur = c + first as u32;
            }
            if top == 0 {
                break;
            }
            top -= 1;
            let p = stack[top];
            let c = self.f.child(s, p);
            emit(self.recs[5 * self.f.rec(s, c) + 1 + side] & INDEX);
            cur = c + second as u32;
        }
    }

    /// The node of slot `s` at `level` touching side `side` at index `x`
    /// along it, if the tree reaches that deep.
    fn descend(&self, s: usize, side: usize, level: u32, x: u64) -> Option<u32> {
        let order = along(side);
        let mut node = 0u32;
        for l in 0..level {
            let c = self.f.child(s, node);
            if c == 0 {
                return None;
            }
            let bit = ((x >> (level - 1 - l)) & 1) as usize;
            node = c + order[bit] as u32;
        }
        Some(node)
    }

    /// Points on side `side` of leaf (level, i, j) of slot `s` coming from
    /// the slot(s) across the slot boundary, in counter-clockwise order.
    #[allow(clippy::too_many_arguments)]
    fn across(
        &self,
        table: &Table,
        s: usize,
        level: u32,
        i: u32,
        j: u32,
        side: usize,
        emit: &mut impl FnMut(u32),
    ) {
        let topo = &self.f.topo;
        let m = topo.side_map(s, side as u32);
        let x = along_index(i, j, side) as u64;
        let w0 = x << (32 - level);
        let w1 = (x + 1) << (32 - level);
        let (ws, we) = if increasing(side) { (w0, w1) } else { (w1, w0) };
        let (cs, ce) = (m.to_carrier(ws), m.to_carrier(we));
        let (lo, hi) = (cs.min(ce), cs.max(ce));
        let up = ce > cs;
        let mut ps = [Piece {
            slot: 0,
            side: 0,
            lo: 0,
            hi: 0,
            map: m,
            twin: false,
        }; 2];
        let np = topo.pieces(s, side as u32, &mut ps);
        for k in 0..np {
            let p = if up { ps[k] } else { ps[np - 1 - k] };
            if k == 1 && lo < FP / 2 && FP / 2 < hi {
                let key = topo.carrier_key(m.carrier, FP / 2);
                if let Some(idx) = table.get(key) {
                    emit(idx);
                }
            }
            let (a, b) = (lo.max(p.lo), hi.min(p.hi));
            if a >= b {
                continue;
            }
            let (ca, cb) = if up { (a, b) } else { (b, a) };
            let (wa, wb) = (p.w_of(ca), p.w_of(cb));
            let (plo, len) = (wa.min(wb), wa.max(wb) - wa.min(wb));
            if len == 0 || !len.is_power_of_two() || len > FP {
                continue;
            }
            let pl = 32 - len.trailing_zeros();
            let ps_slot = p.slot as usize;
            if let Some(node) = self.descend(ps_slot, p.side as usize, pl, plo >> (32 - pl)) {
                self.along_side(ps_slot, node, p.side as usize, wb > wa, emit);
            }
        }
    }
}

/// Output state of the polygon pass.
struct Emit<'o, 'p> {
    out: Option<&'p mut PolyOut<'o>>,
    np: usize,
    ni: usize,
    nt: usize,
}

const SMALL: Error = Error::InvalidArgument("internal: polygon count beyond size");

impl Emit<'_, '_> {
    /// The polygon of leaf (level, i, j) of slot `s`.
    #[allow(clippy::too_many_arguments)]
    fn leaf(
        &mut self,
        w: &Walk,
        table: &Table,
        s: usize,
        level: u32,
        i: u32,
        j: u32,
        corner: [u32; 4],
        nb: [u32; 4],
        nbc: [u32; 4],
    ) -> Result<(), Error> {
        let f = w.f;
        let start = self.ni;
        let mut at = [0usize; 4];
        let mut sink = Sink {
            dst: self.out.as_deref_mut().map(|o| &mut o.indices[..]),
            at: start,
            count: 0,
            overflow: false,
        };
        for side in 0..4 {
            at[side] = sink.count;
            sink.push(corner[side]);
            if on_boundary(level, i, j, side) {
                w.across(table, s, level, i, j, side, &mut |v| sink.push(v));
            } else {
                if nbc[side] != 0 {
                    w.along_side(s, nb[side], opposite(side), increasing(side), &mut |v| {
                        sink.push(v)
                    });
                }
            }
        }
        let (count, overflow) = (sink.count, sink.overflow);
        if overflow {
            return Err(SMALL);
        }
        if let Some(o) = self.out.as_deref_mut() {
            *o.sizes.get_mut(self.np).ok_or(SMALL)? = count as u32;
            if let Some(cs) = o.cells.as_deref_mut() {
                let (face, sub) = f.topo.face_sub(s);
                *cs.get_mut(self.np).ok_or(SMALL)? = PolygonCell {
                    face,
                    sub,
                    level,
                    i,
                    j,
                };
            }
            if let Some(tri) = o.triangles.as_deref_mut() {
                let poly = &o.indices[start..start + count];
                let dst = tri.get_mut(3 * self.nt..).ok_or(SMALL)?;
                self.nt += triangulate(poly, at, o.positions, dst).ok_or(SMALL)?;
            }
        }
        self.np += 1;
        self.ni += count;
        Ok(())
    }
}

/// Walks every leaf of every slot and emits its polygon (and triangles),
/// or only counts when `out` is `None`. Needs the records, slot corners and
/// hash table of [`super::vertices::assign`]. Returns (polygons, indices).
pub(crate) fn assemble(
    f: &Forest,
    recs: &[u32],
    corners: &[u32],
    table: &Table,
    scratch: &mut Scratch,
    out: Option<&mut PolyOut>,
) -> Result<(usize, usize), Error> {
    let w = Walk { f, recs };
    let mut e = Emit {
        out,
        np: 0,
        ni: 0,
        nt: 0,
    };
    let lv = &mut scratch.levels;
    for s in 0..f.num_slots() {
        let c4: [u32; 4] = core::array::from_fn(|q| corners[4 * s + q] & INDEX);
        let c0 = f.child(s, 0);
        if c0 == 0 {
            e.leaf(&w, table, s, 0, 0, 0, c4, [NONE; 4], [0; 4])?;
            continue;
        }
        let d = &mut lv[0];
        (
            d.node, d.first, d.level, d.i, d.j, d.q, d.nb, d.nbc, d.corner,
        ) = (0, c0, 0, 0, 0, 0, [NONE; 4], [0; 4], c4);
        load_links(f, s, d);
        let mut l = 0usize;
        loop {
            let cur = &mut lv[l];
            if cur.q >= 4 {
                if l == 0 {
                    break;
                }
                l -= 1;
                continue;
            }
            let q = cur.q as usize;
            cur.q += 1;
            let cur = &lv[l];
            let r = 5 * f.rec(s, cur.first);
            let (ctr, mb, mr, mt, ml) = (
                recs[r] & INDEX,
                recs[r + 1] & INDEX,
                recs[r + 2] & INDEX,
                recs[r + 3] & INDEX,
                recs[r + 4] & INDEX,
            );
            let [a, b, c, d] = cur.corner;
            let corner = match q {
                0 => [a, mb, ctr, ml],
                1 => [mb, b, mr, ctr],
                2 => [ctr, mr, c, mt],
                _ => [ml, ctr, mt, d],
            };
            let (nb, nbc) = child_links(cur, q);
            let node = cur.first + q as u32;
            let (ci, cj) = child_ij(cur.i, cur.j, q);
            let cl = cur.level + 1;
            let cc = cur.own[q];
            if cc == 0 {
                e.leaf(&w, table, s, cl, ci, cj, corner, nb, nbc)?;
                continue;
            }
            if l + 1 >= LEVELS {
                return Err(Error::InvalidArgument(TOO_DEEP));
            }
            let dst = &mut lv[l + 1];
            (
                dst.node, dst.first, dst.level, dst.i, dst.j, dst.q, dst.nb, dst.corner,
            ) = (node, cc, cl, ci, cj, 0, nb, corner);
            dst.nbc = nbc;
            load_links(f, s, dst);
            l += 1;
        }
    }
    Ok((e.np, e.ni))
}
