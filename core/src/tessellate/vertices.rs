//! Vertex numbering and vertex output (first half of the paper's
//! AdaptiveRendering).
//!
//! Splitting an internal node creates its centre and the midpoints of its
//! four sides. Every vertex of the tessellation is a slot corner or such a
//! point, so the vertices are numbered ([`assign`], at build time) by
//! walking the internal nodes, slot by slot, depth first:
//!
//! * a slot corner has an identity ([`super::carrier::Topo::corner_id`]):
//!   the first slot to meet it numbers it, the others find it there;
//! * a centre is new;
//! * an interior side midpoint is shared with the same-level neighbour
//!   across that side when that neighbour is split too: whichever of the
//!   two comes first creates it and writes it into both records;
//! * midpoints on the slot boundary are numbered afterwards, carrier by
//!   carrier, by merging the points of the slots on both sides
//!   ([`super::sides`]).
//!
//! Each internal node's record holds the indices of its five points
//! (centre, then the midpoints of sides 0..4), which the emission reads:
//! [`positions`] walks the nodes again with their Bezier nets and writes
//! each point at its index, from the children's nets (corner points and
//! first control-point differences: exact), falling back to
//! [`Evaluator::eval`] where no polynomial child has the point as a corner;
//! slot corners (extraordinary vertices among them) are always evaluated.

use super::cells::{self, CORNER, POLY};
use super::forest::{is_bottom, mirror, on_boundary, opposite, rec_at, touches, Forest};
use super::mark::{cell_size, child_ij, corner_uv};
use super::record::{AT, DIAG, INDEX, OWN};
use super::scratch::{next_child, pair, Level, Scratch, LEVELS, NONE};
use super::sides::{self, SideLists};
use super::triangulate;
use super::TOO_DEEP;
use crate::error::Error;
use crate::eval::{Evaluator, Query};
use crate::math::bezier;
use glam::DVec3;

/// Where vertices go.
pub(crate) struct VertOut<'o, S: Single = NoSingle> {
    pub positions: &'o mut [f64],
    pub normals: Option<&'o mut [f64]>,
    pub params: Option<&'o mut [Query]>,
    /// Triangles are wanted: record the cuts of the bottom nodes' quads
    /// ([`DIAG`]) for the polygon pass.
    pub cuts: bool,
    /// [`super::Tessellation::emit_f32`]: positions (and normals) by
    /// [`Evaluator::eval_f32`] at each vertex's parameters, instead of
    /// `positions` and `normals`.
    /// A type parameter, not an `Option`: the `f64` passes are compiled
    /// without it (the firmware's frames and code stay as they were).
    pub single: S,
}

/// The `f32` vertex output of [`VertOut`], or none.
pub(crate) trait Single {
    /// Whether vertices go here instead of the `f64` outputs.
    const ACTIVE: bool;
    /// Vertex `i` at `q`.
    fn put(&mut self, i: usize, q: Query, params: Option<&mut [Query]>) -> Result<(), Error>;
}

/// No `f32` output ([`Tessellation::emit`](super::Tessellation::emit)).
pub(crate) struct NoSingle;

impl Single for NoSingle {
    const ACTIVE: bool = false;
    fn put(&mut self, _: usize, _: Query, _: Option<&mut [Query]>) -> Result<(), Error> {
        Ok(())
    }
}

/// Where [`super::Tessellation::emit_f32`] puts vertices.
pub(crate) struct SingleOut<'o> {
    pub ev: &'o Evaluator<'o>,
    pub positions: &'o mut [f32],
    pub normals: Option<&'o mut [f32]>,
}

impl Single for SingleOut<'_> {
    const ACTIVE: bool = true;
    /// Vertex `i` at `q` by [`Evaluator::eval_f32`] (by `eval`, rounded,
    /// where `q` is not exact in `f32`: see `single.rs`). Not inlined:
    /// the passes' frames stay those of the `f64` emission.
    #[inline(never)]
    fn put(&mut self, i: usize, q: Query, params: Option<&mut [Query]>) -> Result<(), Error> {
        let (u, v) = (q.u as f32, q.v as f32);
        let e = if u as f64 == q.u && v as f64 == q.v {
            self.ev.eval_f32(q.face, q.sub, u, v)?
        } else {
            let e = self.ev.eval(q.face, q.sub, q.u, q.v)?;
            let r = |a: DVec3| [a.x as f32, a.y as f32, a.z as f32];
            crate::eval::EvalF32 {
                p: r(e.p),
                du: r(e.du),
                dv: r(e.dv),
                normal: r(e.normal),
            }
        };
        let Some(dst) = self.positions.get_mut(3 * i..3 * i + 3) else {
            return Err(Error::InvalidArgument(
                "internal: vertex index beyond count",
            ));
        };
        dst.copy_from_slice(&e.p);
        if let Some(d) = self
            .normals
            .as_deref_mut()
            .and_then(|n| n.get_mut(3 * i..3 * i + 3))
        {
            d.copy_from_slice(&e.normal);
        }
        if let Some(d) = params.and_then(|ps| ps.get_mut(i)) {
            *d = q;
        }
        Ok(())
    }
}

impl<S: Single> VertOut<'_, S> {
    #[inline(always)]
    pub(super) fn put(
        &mut self,
        i: u32,
        p: DVec3,
        n: DVec3,
        q: impl FnOnce() -> Query,
    ) -> Result<(), Error> {
        let i = i as usize;
        if S::ACTIVE {
            return self.single.put(i, q(), self.params.as_deref_mut());
        }
        let Some(dst) = self.positions.get_mut(3 * i..3 * i + 3) else {
            return Err(Error::InvalidArgument(
                "internal: vertex index beyond count",
            ));
        };
        dst.copy_from_slice(&p.to_array());
        if let Some(ns) = self.normals.as_deref_mut() {
            if let Some(d) = ns.get_mut(3 * i..3 * i + 3) {
                d.copy_from_slice(&n.to_array());
            }
        }
        if let Some(ps) = self.params.as_deref_mut() {
            if let Some(d) = ps.get_mut(i) {
                *d = q();
            }
        }
        Ok(())
    }
}

/// Corners of the four children of a node as indices into its nine grid
/// points (its corners 0..4, then its centre and side midpoints 0..4), in
/// the order of `polygons::child_corners`.
const CHILD_GRID: [[usize; 4]; 4] = [[0, 5, 4, 8], [5, 1, 6, 4], [4, 6, 2, 7], [8, 4, 7, 3]];

/// Slot coordinates of the centre (0) or side midpoint (1 + k) of a cell.
pub(super) fn point_uv(level: u32, i: u32, j: u32, which: usize) -> (f64, f64) {
    let (di, dj) = [(1, 1), (1, 0), (2, 1), (1, 2), (0, 1)][which];
    let s = cell_size(level + 1);
    ((2 * i + di) as f64 * s, (2 * j + dj) as f64 * s)
}

/// Numbering state of the slot walks.
struct Ctx<'t> {
    /// Vertex of each slot-corner identity, or [`NONE`].
    vid: &'t mut [u32],
    next: u32,
    /// Record of the slot's root (its records follow in walk order).
    rbase: usize,
}

/// Record entry of a midpoint on the slot boundary until the boundary
/// numbering ([`super::sides::number`]) writes it.
const PENDING: u32 = INDEX;

impl Ctx<'_> {
    /// Vertex of the slot corner with identity `id`, with [`OWN`] if this
    /// call created it.
    fn corner(&mut self, id: usize) -> Result<u32, Error> {
        let v = self
            .vid
            .get_mut(id)
            .ok_or(Error::InvalidArgument("internal: corner identity"))?;
        if *v != NONE {
            return Ok(*v);
        }
        *v = self.next;
        self.next += 1;
        Ok(*v | OWN)
    }

    /// Numbers the five points of the expanded node `lev` (its record at
    /// `recs[r..r + 5]`). An interior side midpoint shared with a
    /// split same-level neighbour is numbered by whichever of the two comes
    /// first in the walk and written into both records: the marking
    /// allocates children groups in the walk's preorder, so the neighbour
    /// came first exactly when its first child is smaller. Midpoints on the
    /// slot boundary are left [`PENDING`].
    /// Returns the sides whose midpoints are pending (bit per side).
    #[inline(always)]
    fn points(&mut self, lev: &Level, recs: &mut [u32], r: usize) -> Result<u32, Error> {
        let mut pending = 0;
        recs[r] = self.next | OWN;
        self.next += 1;
        for side in 0..4 {
            let nc = lev.nbc[side];
            if nc != 0 && nc < lev.first {
                // Numbered by the neighbour, which came first.
                continue;
            }
            let e = if nc == 0 && on_boundary(lev.level, lev.i, lev.j, side) {
                pending |= 1 << side;
                PENDING
            } else {
                let idx = self.next;
                self.next += 1;
                if nc != 0 {
                    let at = 5 * rec_at(self.rbase, nc) + 1 + opposite(side);
                    *recs.get_mut(at).ok_or(ORDER)? = idx;
                }
                idx | OWN
            };
            recs[r + 1 + side] = e;
        }
        Ok(pending)
    }
}

/// The error of a walk that does not meet the marking's preorder.
const ORDER: Error = Error::InvalidArgument("internal: node records out of order");

/// Reads, once per expanded node, its children's tree entries (their
/// first children).
#[inline(always)]
pub(crate) fn load_links(tree: &[u32], p: &mut Level) {
    let k = &tree[p.first as usize..p.first as usize + 4];
    p.own = [k[0], k[1], k[2], k[3]];
}

/// Same-level neighbours of child `q` of the expanded node `p` (after
/// [`load_links`]) and their first children (0: none or a leaf): a sibling,
/// or a child of the node's neighbour (read from the tree here).
#[inline(always)]
pub(crate) fn child_links(tree: &[u32], p: &Level, q: usize) -> ([u32; 4], [u32; 4]) {
    links_of(tree, p.first, &p.own, &p.nbc, q)
}

/// [`child_links`] of child `q` of a node given by its first child
/// `first`, its children's first children `own` and its neighbours' first
/// children `nbc`.
#[inline(always)]
pub(crate) fn links_of(
    tree: &[u32],
    first: u32,
    own: &[u32; 4],
    nbc: &[u32; 4],
    q: usize,
) -> ([u32; 4], [u32; 4]) {
    let mut nb = [NONE; 4];
    let mut cnbc = [0u32; 4];
    for side in 0..4 {
        let mq = mirror(q, side);
        if touches(q, side) {
            let pc = nbc[side];
            if pc != 0 {
                nb[side] = pc + mq as u32;
                cnbc[side] = tree[(pc + mq as u32) as usize];
            }
        } else {
            nb[side] = first + mq as u32;
            cnbc[side] = own[mq];
        }
    }
    (nb, cnbc)
}

/// Numbers all vertices: fills `recs` (5 per internal node), `corners`
/// (4 per slot), `vid` (one per slot-corner identity; emptied first) and
/// the side lists. Returns the vertex count.
///
/// The walk is the marking's preorder, so the records of a slot come in
/// order; that is checked, and every record is written (no clearing).
#[inline(never)]
pub(crate) fn assign(
    f: &Forest,
    recs: &mut [u32],
    corners: &mut [u32],
    vid: &mut [u32],
    lists: &mut SideLists,
    scratch: &mut Scratch,
) -> Result<usize, Error> {
    vid.fill(NONE);
    let mut cx = Ctx {
        vid,
        next: 0,
        rbase: 0,
    };
    let lv = &mut scratch.levels;
    // Per level of the walk: the node's sides with pending midpoints.
    let mut pending = [0u32; LEVELS];
    for s in 0..f.num_slots() {
        for q in 0..4 {
            corners[4 * s + q] = cx.corner(f.topo.corner_id(s, q))?;
        }
        let tree = f.tree(s);
        let c0 = *tree.first().ok_or(ORDER)?;
        if c0 == 0 {
            lists.end_slot(s)?;
            continue;
        }
        // The root's children are the slot's first group.
        if c0 != 1 {
            return Err(ORDER);
        }
        cx.rbase = f.rec(s, c0);
        // Record of the next node in the walk.
        let mut next_rec = cx.rbase;
        let d = &mut lv[0];
        (d.first, d.level, d.i, d.j, d.q, d.nbc) = (c0, 0, 0, 0, 0, [0; 4]);
        load_links(tree, d);
        pending[0] = cx.points(&lv[0], recs, 5 * next_rec)?;
        next_rec += 1;
        let mut l = 0usize;
        while let Some(q) = next_child(lv, &mut l) {
            let cur = &lv[l];
            // A node's midpoint on side k comes, in order along the side,
            // between its two children along k: before child 1 (side 0),
            // 2 (side 1) or 3 (sides 2 and 3; side 2 is walked backwards).
            let due = pending[l] & [0, 1, 2, 12][q];
            if due != 0 {
                let r = 5 * rec_at(cx.rbase, cur.first);
                lists.push((cur.level, cur.i, cur.j), due, r)?;
            }
            let c = cur.own[q];
            if c == 0 {
                continue;
            }
            if l + 1 >= LEVELS {
                return Err(Error::InvalidArgument(TOO_DEEP));
            }
            if rec_at(cx.rbase, c) != next_rec {
                return Err(ORDER);
            }
            let (p, dst) = pair(lv, l);
            let (ci, cj) = child_ij(p.i, p.j, q);
            dst.nbc = child_links(tree, p, q).1;
            (dst.first, dst.level, dst.i, dst.j, dst.q) = (c, p.level + 1, ci, cj, 0);
            load_links(tree, dst);
            let r = 5 * next_rec;
            let due = cx.points(dst, recs, r)?;
            next_rec += 1;
            if dst.own != [0; 4] {
                l += 1;
                pending[l] = due;
            } else if due != 0 {
                // A bottom node (all children leaves) has nothing below:
                // its midpoints are in order now.
                lists.push((dst.level, dst.i, dst.j), due, r)?;
            }
        }
        lists.end_slot(s)?;
    }
    Ok(sides::number(f.topo, recs, corners, lists, cx.next)? as usize)
}

/// Bits `w` of the points of a record this node created ([`OWN`]).
#[inline(always)]
fn owned(own: [u32; 5]) -> u32 {
    (0..5).fold(0u32, |m, w| m | (((own[w] & OWN) >> 31) << w))
}

/// A polynomial bottom node as the positions pass sees it: its record at
/// `recs[r..r + 5]`, Bezier net and offset, cell and slot.
struct BottomAt<'n> {
    r: usize,
    net: &'n bezier::Net,
    off: DVec3,
    cell: (u32, u32, u32),
    face: u32,
    sub: u32,
}

/// Writes the points a polynomial bottom node created (`pt(w)`: point `w`
/// as [`bezier::node_points`] gives it, with the normal where owned) and,
/// when `cuts` (triangles wanted), records the cuts of its four child
/// quads, from its corners and points (see [`DIAG`]).
#[inline(always)]
fn bottom_out<S: Single>(
    out: &mut VertOut<S>,
    recs: &mut [u32],
    at: &BottomAt,
    cuts: bool,
    pt: impl Fn(usize) -> (DVec3, DVec3),
) -> Result<(), Error> {
    let (r, o) = (at.r, at.off);
    let (cl, ci, cj) = at.cell;
    for which in 0..5 {
        let e = recs[r + which];
        if e & OWN != 0 {
            let (p, nm) = pt(which);
            out.put(e & INDEX, p + o, nm, || {
                let (u, v) = point_uv(cl, ci, cj, which);
                Query {
                    face: at.face,
                    sub: at.sub,
                    u,
                    v,
                }
            })?;
        }
    }
    if !cuts {
        return Ok(());
    }
    let g: [[f64; 3]; 9] = core::array::from_fn(|k| {
        if k < 4 {
            (bezier::corner(at.net, k) + o).to_array()
        } else {
            (pt(k - 4).0 + o).to_array()
        }
    });
    for (k, quad) in CHILD_GRID.iter().enumerate() {
        let cut = triangulate::cut13(quad.map(|x| g[x]));
        recs[r + 1 + k] = (recs[r + 1 + k] & !DIAG) | if cut { DIAG } else { 0 };
    }
    recs[r] |= DIAG;
    Ok(())
}

/// Writes every vertex's position, normal and parameters at the index the
/// numbering ([`assign`]) gave it, reading the node records: a depth-first
/// walk of the internal nodes with their Bezier nets, without neighbour
/// links or lookups. A vertex shared by several nodes (or slots) is written
/// once, by the one that created it ([`OWN`]). The cuts of the bottom
/// nodes' quads ([`DIAG`]) are recorded only when triangles are wanted
/// ([`VertOut::cuts`]); otherwise the flags are left as they are and the
/// polygon pass does not read them.
#[allow(clippy::too_many_arguments)]
#[inline(never)]
pub(crate) fn positions<S: Single>(
    f: &Forest,
    ev: &Evaluator,
    recs: &mut [u32],
    corners: &[u32],
    cache: &[f64],
    light: Option<f64>,
    scratch: &mut Scratch,
    out: &mut VertOut<S>,
) -> Result<(), Error> {
    let cuts = out.cuts;
    // Without saved expansions (`light`: the absolute tolerance of a
    // tessellation that keeps none), a light corner split's five points
    // are redone here as the marking saved them (into `pts`, which only
    // polynomial cells use otherwise).
    let lv = &mut scratch.levels;
    // Values of saved corner expansions read so far (preorder, from the
    // back, as the marking saved them).
    let mut used = 0usize;
    let mut pts = [(DVec3::ZERO, DVec3::ZERO); 5];
    let mut p4 = bezier::Points4::ZERO;
    for s in 0..f.num_slots() {
        let (face, sub) = f.topo.face_sub(s);
        // The marking's light-split test (rounding term included).
        let eps_s = light.map(|e| e - super::mark::slot_round(ev, s).unwrap_or(f64::INFINITY));
        let write = |out: &mut VertOut<S>,
                     idx: u32,
                     u: f64,
                     v: f64,
                     lev: Option<(&Level, usize)>|
         -> Result<(), Error> {
            let q = Query { face, sub, u, v };
            if let Some((l, which)) = lev {
                for &(c, k) in &AT[which] {
                    if l.kinds[c].tag == POLY {
                        if let Some(n) = bezier::corner_normal(&l.nets[c], k) {
                            let p = bezier::corner(&l.nets[c], k) + DVec3::from_array(l.offs[c]);
                            return out.put(idx, p, n, || q);
                        }
                    }
                }
            }
            let e = ev.eval(face, sub, u, v)?;
            out.put(idx, e.p, e.normal, || q)
        };
        for q in 0..4 {
            let e = corners[4 * s + q];
            if e & OWN != 0 {
                let (u, v) = corner_uv(0, 0, 0, q);
                write(out, e & INDEX, u, v, None)?;
            }
        }
        let tree = f.tree(s);
        let c0 = tree[0];
        if c0 == 0 {
            continue;
        }
        let root = cells::root(ev, s);
        let rbase = f.rec(s, 1);
        let d = &mut lv[0];
        d.start(0, c0, 0, 0, 0);
        let mut l = 0usize;
        let mut fresh = true;
        loop {
            if fresh {
                // The node at level l: its own cell is the root or child
                // `q - 1` of level l - 1. Its five points come straight
                // from its net when it is polynomial and not split (no quadrant
                // nets); the quadrant nets are made only when a child is split,
                // or for the generic path.
                let (p, cur) = if l == 0 {
                    (None, &mut lv[0])
                } else {
                    let (p, cur) = pair(lv, l - 1);
                    (Some(p), cur)
                };
                let (kind, n, off) = match p {
                    None => (&root.kind, &root.net, root.off.to_array()),
                    Some(p) => {
                        let q = (p.q - 1) as usize;
                        (&p.kinds[q], &p.nets[q], p.offs[q])
                    }
                };
                let r = 5 * rec_at(rbase, cur.first);
                recs[r] &= !DIAG;
                let own: [u32; 5] = core::array::from_fn(|w| recs[r + w]);
                let mask = owned(own);
                let split = (0..4).any(|q| tree[(cur.first + q) as usize] != 0);
                // A split node makes its quadrant nets anyway: its points
                // are then read from them (node_points gives the same bits).
                let fast = !split
                    && kind.tag == POLY
                    && mask != 0
                    && bezier::node_points(n, mask, &mut pts);
                // The marking's saved expansion of a corner cell, if any.
                // Nothing saved: a light split's points redone (found mask).
                let mut light_found = None;
                let saved = if kind.tag != CORNER {
                    None
                } else if let Some(eps_s) = eps_s {
                    if cells::light_split(ev, kind, eps_s).is_some() {
                        light_found = cells::light_points(ev, kind, &mut pts);
                    }
                    None
                } else {
                    let end = cache.len() - used;
                    cells::saved_corner(cache, end, kind.rho).map(|(a, h)| {
                        used += end - a;
                        (&cache[a..end], h)
                    })
                };
                // A saved expansion, or a redone light split (its header:
                // no ring-region child split, nothing else read).
                let loaded = saved.or(light_found.map(|h| (&[][..], h)));
                if let Some((e, h)) = loaded {
                    if split {
                        cells::load_corner(
                            ev,
                            kind,
                            e,
                            h,
                            &mut cur.kinds,
                            &mut cur.nets,
                            &mut cur.offs,
                        );
                    }
                } else if split || (!fast && mask != 0) {
                    cells::expand(
                        ev,
                        kind,
                        n,
                        off,
                        &mut cur.kinds,
                        &mut cur.nets,
                        &mut cur.offs,
                    );
                }
                let o = DVec3::from_array(off);
                let (cl, ci, cj) = (cur.level, cur.i, cur.j);
                let q = |which| {
                    let (u, v) = point_uv(cl, ci, cj, which);
                    Query { face, sub, u, v }
                };
                if let Some((se, h)) = saved {
                    // A corner cell: its points as `write` would find them
                    // among the children, else evaluated.
                    for (which, &e) in own.iter().enumerate() {
                        if e & OWN != 0 {
                            match cells::saved_point(se, h, which) {
                                Some((pt, nm)) => out.put(e & INDEX, pt, nm, || q(which))?,
                                None => {
                                    let (u, v) = point_uv(cl, ci, cj, which);
                                    write(out, e & INDEX, u, v, None)?;
                                }
                            }
                        }
                    }
                } else if let Some(h) = light_found {
                    // The same, from the redone points.
                    for (which, &e) in own.iter().enumerate() {
                        if e & OWN != 0 {
                            if h & (1 << which) != 0 {
                                let (pt, nm) = pts[which];
                                out.put(e & INDEX, pt, nm, || q(which))?;
                            } else {
                                let (u, v) = point_uv(cl, ci, cj, which);
                                write(out, e & INDEX, u, v, None)?;
                            }
                        }
                    }
                } else {
                    for (which, &e) in own.iter().enumerate() {
                        if e & OWN != 0 {
                            if fast {
                                let (pt, nm) = pts[which];
                                out.put(e & INDEX, pt + o, nm, || q(which))?;
                            } else {
                                let (u, v) = point_uv(cl, ci, cj, which);
                                write(out, e & INDEX, u, v, Some((cur, which)))?;
                            }
                        }
                    }
                }
                fresh = false;
            }
            let Some(q) = next_child(lv, &mut l) else {
                break;
            };
            // Four polynomial bottom nodes (all children of this node):
            // their points in one four-lane call; `internal` marks those
            // done (a node whose normals degenerate takes the paths below).
            if q == 0 {
                let p = &lv[l];
                let cs: [u32; 4] = core::array::from_fn(|k| tree[(p.first + k as u32) as usize]);
                let mut done = 0;
                if p.kinds.iter().all(|k| k.tag == POLY) && cs.iter().all(|&c| is_bottom(tree, c)) {
                    let rs = cs.map(|c| 5 * rec_at(rbase, c));
                    let own: [[u32; 5]; 4] = rs.map(|r| core::array::from_fn(|w| recs[r + w]));
                    done = bezier::node_points4(&p.nets, own.map(owned), &mut p4);
                    for k in 0..4 {
                        if done & (1 << k) != 0 {
                            let (ci, cj) = child_ij(p.i, p.j, k);
                            let at = BottomAt {
                                r: rs[k],
                                net: &p.nets[k],
                                off: DVec3::from_array(p.offs[k]),
                                cell: (p.level + 1, ci, cj),
                                face,
                                sub,
                            };
                            bottom_out(out, recs, &at, cuts, |w| p4.get(k, w))?;
                        }
                    }
                }
                lv[l].internal = done;
            }
            if lv[l].internal & (1 << q) != 0 {
                continue;
            }
            let node = lv[l].first + q as u32;
            let c = tree[node as usize];
            if c == 0 {
                continue;
            }
            let (p, dst) = pair(lv, l);
            let (ci, cj) = child_ij(p.i, p.j, q);
            // A polynomial bottom node (all four children leaves): its
            // points straight from its net, as the walk below would find
            // them, without descending.
            if p.kinds[q].tag == POLY && is_bottom(tree, c) {
                let r = 5 * rec_at(rbase, c);
                let own: [u32; 5] = core::array::from_fn(|w| recs[r + w]);
                let n = &p.nets[q];
                if bezier::node_points(n, owned(own), &mut pts) {
                    let at = BottomAt {
                        r,
                        net: n,
                        off: DVec3::from_array(p.offs[q]),
                        cell: (p.level + 1, ci, cj),
                        face,
                        sub,
                    };
                    bottom_out(out, recs, &at, cuts, |w| pts[w])?;
                    continue;
                }
            }
            if l + 1 >= LEVELS {
                return Err(Error::InvalidArgument(TOO_DEEP));
            }
            dst.start(node, c, p.level + 1, ci, cj);
            l += 1;
            fresh = true;
        }
    }
    Ok(())
}
