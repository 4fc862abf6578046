//! Polygon assembly (second half of the paper's AdaptiveRendering): one
//! polygon per leaf cell, counter-clockwise in the slot's (u, v) (outward).
//!
//! Crack elimination: each side of a leaf is replaced by the polyline of
//! all vertices on it. Those are the leaf's two corners plus the midpoints
//! of the finer cells on the other side: inside the slot, the subtree of
//! the same-level neighbour (if split) read in order along the shared side;
//! on the slot boundary, the points of the side's list strictly inside the
//! leaf's side ([`super::sides`]: every vertex on that base edge or
//! internal N-gon edge, from the slots on both sides). Both polygons of an
//! edge therefore list the same vertices: the output is watertight by
//! construction. A leaf with no extra point on any side is a plain quad.

use super::forest::{along, along_index, increasing, is_bottom, mirror, opposite, rec_at, Forest};
use super::mark::child_ij;
use super::record::{DIAG, INDEX};
use super::scratch::{next_child, Scratch, LEVELS, NONE};
use super::sides::{Cursors, Pt};
use super::triangulate::{quad, quad_cut, triangulate, Pos};
use super::vertices::{child_links, links_of, load_links};
use super::{PolygonCell, PolygonSink, MAX_LEVEL, TOO_DEEP};
use crate::error::Error;

/// Where polygons go. With `stream`, the buffers hold one polygon
/// (`sizes` one value, `indices` its vertices, `triangles` its triangles):
/// each polygon is handed to `stream` (positions, vertices, triangles) as soon as it
/// is made and the buffers are reused; a polygon that does not fit is
/// skipped and counted ([`assemble`] then reports the size needed).
pub(crate) struct PolyOut<'o> {
    pub sizes: &'o mut [u32],
    pub indices: &'o mut [u32],
    pub triangles: Option<&'o mut [u32]>,
    pub cells: Option<&'o mut [PolygonCell]>,
    pub positions: Pos<'o>,
    pub stream: Option<&'o mut PolygonSink<'o>>,
}

/// Appends a polygon's vertex indices.
struct Sink<'d> {
    dst: &'d mut [u32],
    at: usize,
    overflow: bool,
}

impl Sink<'_> {
    #[inline(always)]
    fn push(&mut self, v: u32) {
        match self.dst.get_mut(self.at) {
            Some(x) => *x = v,
            None => self.overflow = true,
        }
        self.at += 1;
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
        let tree = self.f.tree(s);
        let rbase = self.f.rec(s, 1);
        let mut stack = [0u32; MAX_LEVEL as usize + 2];
        let mut top = 0usize;
        let mut cur = x;
        loop {
            loop {
                let c = tree[cur as usize];
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
            let c = tree[p as usize];
            emit(self.recs[5 * rec_at(rbase, c) + 1 + side] & INDEX);
            cur = c + second as u32;
        }
    }
}

/// Pushes the vertices of `pts` (a side list's points, increasing `w`) in
/// increasing (`inc`) or decreasing order.
#[inline(always)]
fn push_along(pts: &[Pt], inc: bool, sink: &mut Sink) {
    if inc {
        for p in pts {
            sink.push(p[1]);
        }
    } else {
        for p in pts.iter().rev() {
            sink.push(p[1]);
        }
    }
}

/// Output state of the polygon pass.
struct Emit<'o, 'p, 'l> {
    out: &'p mut PolyOut<'o>,
    /// The current slot's side lists.
    cur: Cursors<'l>,
    np: usize,
    ni: usize,
    nt: usize,
    /// Streaming: polygons and indices handed out before the current
    /// one, and the most vertices of a polygon that did not fit.
    sent: (usize, usize),
    too_big: usize,
}

const SMALL: Error = Error::InvalidArgument("internal: polygon count beyond size");

impl Emit<'_, '_, '_> {
    /// The polygon of leaf (level, i, j) of slot `s` (its slot-boundary
    /// sides read from the slot's side lists, see [`Cursors`]).
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn leaf(
        &mut self,
        w: &Walk,
        s: usize,
        level: u32,
        i: u32,
        j: u32,
        corner: &[u32; 4],
        nb: &[u32; 4],
        nbc: &[u32; 4],
    ) -> Result<(), Error> {
        let start = self.ni;
        let last = (1u32 << level) - 1;
        let bnd = [j == 0, i == last, j == last, i == 0];
        // Side coordinates of the cell's sides on the slot boundary.
        let sh = 32 - level;
        let count;
        let mut at = [0usize, 1, 2, 3];
        // Extra points on a side: interior sides when the neighbour is
        // split, boundary sides when their list has points inside.
        let mut on: [&[Pt]; 4] = [&[]; 4];
        let mut extra = false;
        for side in 0..4 {
            extra |= if bnd[side] {
                let x = along_index(i, j, side) as u64;
                on[side] = self.cur.inside(side, x << sh, (x + 1) << sh);
                !on[side].is_empty()
            } else {
                nbc[side] != 0
            };
        }
        let o = &mut *self.out;
        if !extra {
            // A plain quad (the common case).
            let Some(d) = o.indices.get_mut(start..start + 4) else {
                return self.skip(4);
            };
            d.copy_from_slice(corner);
            count = 4;
        } else {
            let mut sink = Sink {
                dst: &mut o.indices[..],
                at: start,
                overflow: false,
            };
            for side in 0..4 {
                at[side] = sink.at - start;
                sink.push(corner[side]);
                if bnd[side] {
                    push_along(on[side], increasing(side), &mut sink);
                } else if nbc[side] != 0 {
                    w.along_side(s, nb[side], opposite(side), increasing(side), &mut |v| {
                        sink.push(v)
                    });
                }
            }
            let (overflow, end) = (sink.overflow, sink.at);
            if overflow {
                return self.skip(end - start);
            }
            count = end - start;
        }
        self.finish(w, s, (level, i, j), corner, count, at, None)
    }

    /// A plain quad with corners `corner` (a leaf with no extra point on
    /// any side), cut along corners 1-3 when `cut` says so (`None`: the
    /// shorter diagonal, from the positions).
    #[inline(always)]
    fn quad(
        &mut self,
        w: &Walk,
        s: usize,
        cell: (u32, u32, u32),
        corner: &[u32; 4],
        cut: Option<bool>,
    ) -> Result<(), Error> {
        let start = self.ni;
        let Some(d) = self.out.indices.get_mut(start..start + 4) else {
            return self.skip(4);
        };
        d.copy_from_slice(corner);
        self.finish(w, s, cell, corner, 4, [0, 1, 2, 3], cut)
    }

    /// Four plain quads `cc` with known cuts (record `rec`, see [`DIAG`])
    /// written at once, as four [`Emit::quad`] calls would: false (nothing
    /// written) when polygon cells are wanted or a buffer is short, for
    /// the caller to take the one-by-one path.
    #[inline(always)]
    fn quads4(&mut self, cc: &[[u32; 4]; 4], rec: [u32; 5]) -> bool {
        let o = &mut *self.out;
        if o.cells.is_some() || o.stream.is_some() {
            return false;
        }
        let (np, ni, nt) = (self.np, self.ni, self.nt);
        let (Some(sz), Some(ix)) = (o.sizes.get_mut(np..np + 4), o.indices.get_mut(ni..ni + 16))
        else {
            return false;
        };
        if let Some(tri) = o.triangles.as_deref_mut() {
            let Some(t) = tri.get_mut(3 * nt..3 * nt + 24) else {
                return false;
            };
            for (q, c) in cc.iter().enumerate() {
                let c13 = rec[1 + q] & DIAG != 0;
                // Six indices always fit in the chunk.
                let _ = quad_cut(c, c13, &mut t[6 * q..6 * q + 6]);
            }
            self.nt += 8;
        }
        sz.fill(4);
        for (d, c) in ix.chunks_exact_mut(4).zip(cc) {
            d.copy_from_slice(c);
        }
        self.np += 4;
        self.ni += 16;
        true
    }

    /// Completes the polygon whose `count` indices were written at
    /// `self.ni` (its corners at offsets `at`; a quad's cut `cut`, if
    /// known): size, cell, triangles.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn finish(
        &mut self,
        w: &Walk,
        s: usize,
        (level, i, j): (u32, u32, u32),
        corner: &[u32; 4],
        count: usize,
        at: [usize; 4],
        cut: Option<bool>,
    ) -> Result<(), Error> {
        let o = &mut *self.out;
        let start = self.ni;
        *o.sizes.get_mut(self.np).ok_or(SMALL)? = count as u32;
        if let Some(cs) = o.cells.as_deref_mut() {
            let (face, sub) = w.f.topo.face_sub(s);
            *cs.get_mut(self.np).ok_or(SMALL)? = PolygonCell {
                face,
                sub,
                level,
                i,
                j,
            };
        }
        if let Some(tri) = o.triangles.as_deref_mut() {
            let dst = tri.get_mut(3 * self.nt..).ok_or(SMALL)?;
            self.nt += if let (4, Some(c13)) = (count, cut) {
                quad_cut(corner, c13, dst)
            } else if count == 4 {
                quad(corner, o.positions, dst)
            } else {
                triangulate(&o.indices[start..start + count], at, o.positions, dst)
            }
            .ok_or(SMALL)?;
        }
        self.np += 1;
        self.ni += count;
        if let Some(sink) = o.stream.as_deref_mut() {
            let tri = o.triangles.as_deref().unwrap_or(&[]);
            let Pos::F64(ps) = o.positions else {
                return Err(Error::InvalidArgument("internal: streamed f32 positions"));
            };
            sink(
                ps,
                &o.indices[..count],
                tri.get(..3 * self.nt).unwrap_or(&[]),
            );
            self.sent = (self.sent.0 + 1, self.sent.1 + count);
            (self.np, self.ni, self.nt) = (0, 0, 0);
        }
        Ok(())
    }

    /// A polygon of `count` vertices that does not fit the buffers: an
    /// error, but when streaming, counted as sent (not handed out) and its
    /// size remembered.
    fn skip(&mut self, count: usize) -> Result<(), Error> {
        if self.out.stream.is_none() {
            return Err(SMALL);
        }
        self.too_big = self.too_big.max(count);
        self.sent = (self.sent.0 + 1, self.sent.1 + count);
        Ok(())
    }

    /// The polygons of the four children of a bottom node (internal, all
    /// children leaves) at (level, i, j) with corners `corner`, first child
    /// `first`, record `rec` (raw: with the [`DIAG`] flags) and the first
    /// children `nbc` of its same-level neighbours, in quadrant order, as
    /// four [`Emit::leaf`] calls would make them. A child's inner sides face
    /// leaf siblings (no extra points); only its two outer sides are looked
    /// at.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn bottom(
        &mut self,
        w: &Walk,
        s: usize,
        (level, i, j): (u32, u32, u32),
        corner: [u32; 4],
        first: u32,
        rec: [u32; 5],
        nbc: &[u32; 4],
    ) -> Result<(), Error> {
        let cc = &child_corners(corner, rec.map(|x| x & INDEX));
        // The quads' cuts when the emission of the positions found them.
        let cut = |q: usize| (rec[0] & DIAG != 0).then_some(rec[1 + q] & DIAG != 0);
        let last = (1u32 << level) - 1;
        let tree = w.f.tree(s);
        // Whether the two children along each side (quadrants A and B by
        // increasing side coordinate, across from the neighbour's
        // quadrants mirror(A) and mirror(B)) have extra points there: bits
        // A and B.
        let bnd = [j == 0, i == last, j == last, i == 0];
        let sh = 32 - level;
        // Per side: (A, B, mirror(A), mirror(B)), made at compile time.
        const ALONG: [(usize, usize, u32, u32); 4] = {
            let mut t = [(0, 0, 0, 0); 4];
            let mut side = 0;
            while side < 4 {
                let [a, b] = along(side);
                t[side] = (a, b, mirror(a, side) as u32, mirror(b, side) as u32);
                side += 1;
            }
            t
        };
        let mut extra = 0u32;
        for (side, &(a, b, ma, mb)) in ALONG.iter().enumerate() {
            extra |= if bnd[side] {
                // Points inside the node's side, below and above its own
                // midpoint (itself a point of the list).
                let x = along_index(i, j, side) as u64;
                let (w0, w1) = (x << sh, (x + 1) << sh);
                let wm = (w0 + w1) / 2;
                let on = self.cur.inside(side, w0, w1);
                let lo = on.first().is_some_and(|p| (p[0] as u64) < wm) as u32;
                let hi = on.last().is_some_and(|p| (p[0] as u64) > wm) as u32;
                (lo << a) | (hi << b)
            } else if nbc[side] != 0 {
                let split = |n: u32| tree.get(n as usize).is_some_and(|&c| c != 0) as u32;
                (split(nbc[side] + ma) << a) | (split(nbc[side] + mb) << b)
            } else {
                0
            };
        }
        // Without triangles the cuts are not needed (nor recorded).
        let cuts_known = rec[0] & DIAG != 0 || self.out.triangles.is_none();
        if extra == 0 && cuts_known && self.quads4(cc, rec) {
            return Ok(());
        }
        for q in 0..4 {
            let (ci, cj) = child_ij(i, j, q);
            let cell = (level + 1, ci, cj);
            if extra & (1 << q) == 0 {
                self.quad(w, s, cell, &cc[q], cut(q))?;
                continue;
            }
            // The general path: the child's same-level neighbours (its
            // siblings are leaves).
            let (qnb, qnbc) = links_of(tree, first, &[0; 4], nbc, q);
            self.leaf(w, s, level + 1, ci, cj, &cc[q], &qnb, &qnbc)?;
        }
        Ok(())
    }
}

/// The corners of the four children of a node with corners `c` and
/// points `r` (centre, midpoints of sides 0..4).
#[inline(always)]
fn child_corners(c: [u32; 4], r: [u32; 5]) -> [[u32; 4]; 4] {
    let [a, b, cc, d] = c;
    let [ctr, mb, mr, mt, ml] = r;
    [
        [a, mb, ctr, ml],
        [mb, b, mr, ctr],
        [ctr, mr, cc, mt],
        [ml, ctr, mt, d],
    ]
}

/// Walks every leaf of every slot and emits its polygon (and triangles).
/// Needs the records, slot corners and side lists (`at`, `pts`) of
/// [`super::vertices::assign`]. Returns (polygons, indices, the most
/// vertices of a streamed polygon that did not fit: 0 when all did).
#[inline(never)]
pub(crate) fn assemble(
    f: &Forest,
    recs: &[u32],
    corners: &[u32],
    (at, pts): (&[u32], &[Pt]),
    scratch: &mut Scratch,
    out: &mut PolyOut,
) -> Result<(usize, usize, usize), Error> {
    if f.num_slots() == 0 {
        // (A feature mesh whose faces are all holes.)
        return Ok((0, 0, 0));
    }
    let w = Walk { f, recs };
    let mut e = Emit {
        out,
        cur: Cursors::new(at, pts, 0),
        np: 0,
        ni: 0,
        nt: 0,
        sent: (0, 0),
        too_big: 0,
    };
    let lv = &mut scratch.levels;
    let rec5 = |x: usize| -> [u32; 5] { core::array::from_fn(|k| recs[x + k] & INDEX) };
    for s in 0..f.num_slots() {
        e.cur = Cursors::new(at, pts, s);
        let c4: [u32; 4] = core::array::from_fn(|q| corners[4 * s + q] & INDEX);
        let tree = f.tree(s);
        let rbase = f.rec(s, 1);
        let c0 = tree[0];
        if c0 == 0 {
            e.leaf(&w, s, 0, 0, 0, &c4, &[NONE; 4], &[0; 4])?;
            continue;
        }
        let d = &mut lv[0];
        (
            d.node, d.first, d.level, d.i, d.j, d.q, d.nb, d.nbc, d.corner,
        ) = (0, c0, 0, 0, 0, 0, [NONE; 4], [0; 4], c4);
        d.cc = child_corners(c4, rec5(5 * rbase));
        load_links(tree, d);
        let mut l = 0usize;
        while let Some(q) = next_child(lv, &mut l) {
            let cur = &lv[l];
            let (nb, nbc) = child_links(tree, cur, q);
            let (ci, cj) = child_ij(cur.i, cur.j, q);
            let cl = cur.level + 1;
            let cc = cur.own[q];
            if cc == 0 {
                e.leaf(&w, s, cl, ci, cj, &cur.cc[q], &nb, &nbc)?;
                continue;
            }
            if l + 1 >= LEVELS {
                return Err(Error::InvalidArgument(TOO_DEEP));
            }
            let node = cur.first + q as u32;
            let corner = cur.cc[q];
            let r = 5 * rec_at(rbase, cc);
            if is_bottom(tree, cc) {
                let raw = core::array::from_fn(|k| recs[r + k]);
                e.bottom(&w, s, (cl, ci, cj), corner, cc, raw, &nbc)?;
                continue;
            }
            let dst = &mut lv[l + 1];
            (
                dst.node, dst.first, dst.level, dst.i, dst.j, dst.q, dst.nb, dst.corner,
            ) = (node, cc, cl, ci, cj, 0, nb, corner);
            dst.nbc = nbc;
            dst.cc = child_corners(corner, rec5(r));
            load_links(tree, dst);
            l += 1;
        }
    }
    Ok((e.sent.0 + e.np, e.sent.1 + e.ni, e.too_big))
}
