//! The tessellation object: memory layout, marking of all slots, counting,
//! emission.
//!
//! Layout of the caller buffer (each piece 8-byte aligned):
//! scratch | face starts, twins, origins (copied from the topology, so
//! that the object does not refer to it) | slot starts, slot faces,
//! half-edge faces | slot node offsets | slot corner vertices | vertex per
//! slot-corner identity | start and length of each slot side's point list
//! and own midpoints | quadtree nodes | node records (5 vertex indices per
//! internal node) | side lists | own midpoints and working lists
//! (numbering only) | saved corner-cell expansions (per split corner cell
//! its five new points and the nets of its split ring-region children, in
//! reverse preorder, so that emission does not redo the eigen expansions;
//! none for uniform tessellations). The pieces from the quadtree nodes on
//! depend on the marking, so [`Tessellation::build`] marks straight into the tail
//! of the buffer (nodes from the front, saved expansions from the back)
//! and, when it runs out, finishes in count-only mode to report the exact
//! size. [`Tessellation::build_marked`] makes the saved expansions itself
//! (one per corner cell, as emission otherwise would).

use super::carrier::Topo;
use super::cells::{self, Kind, CORNER, SPLIT};
use super::feature::{feature_positions, mark_feature};
use super::field::ToleranceField;
use super::forest::Forest;
use super::mark::{
    as_f64s_mut, mark, mark_field, top_down_bound, uniform_passes as slot_passes, SlotId,
};
use super::polygons::{assemble, PolyOut};
use super::scratch::Scratch;
use super::sides::{own_len, pts_len, SideLists};
use super::triangulate::Pos;
use super::vertices::{assign, positions, NoSingle, Single, VertOut};
use super::{Counts, Criterion, Keep, Options, Output, PolygonSink, SlotMark, Stats};
use crate::error::Error;
use crate::eval::{Evaluator, FeatureEvaluator};
use crate::mem::arena::{Arena, Layout};
use crate::mem::{as_u32s, bytes_of};
use crate::mesh::features::FeatureMesh;
use crate::mesh::topology::Topology;

/// The surface a tessellation is of.
#[derive(Clone, Copy)]
pub(super) enum Surface<'a> {
    /// A closed mesh without features ([`Tessellation::build`]).
    Smooth(&'a Evaluator<'a>),
    /// A mesh with features, boundaries, holes or non-manifold parts
    /// ([`Tessellation::build_feature`]).
    Feature(&'a FeatureEvaluator<'a, 'a>),
}

/// An adaptive tessellation of one evaluator's surface: marked quadtrees
/// and everything needed to emit (see the module docs).
pub struct Tessellation<'a> {
    pub(super) surface: Surface<'a>,
    opts: Options,
    topo: Topo<'a>,
    slot_node: &'a [u32],
    nodes: &'a [u32],
    recs: &'a mut [u32],
    corners: &'a mut [u32],
    /// Vertex per slot-corner identity (numbering only).
    vid: &'a mut [u32],
    /// Start and length of each slot side's list in `pts` (8 per slot).
    side_at: &'a mut [u32],
    /// Side lists ((w, vertex) pairs).
    pts: &'a mut [[u32; 2]],
    /// Start and length of each slot side's own midpoints (numbering only).
    own_at: &'a mut [u32],
    /// Own midpoints of the slot sides (numbering only).
    own: &'a mut [[u32; 2]],
    /// A slot's midpoints, then a carrier's union (numbering only).
    tmp: &'a mut [[u32; 2]],
    /// Saved corner-cell expansions, in preorder over all slots, each below
    /// the one before (empty for uniform tessellations).
    cache: &'a [f64],
    /// What it keeps between marking and emission.
    keep: Keep,
    scratch: &'a mut Scratch,
    pub(super) counts: Counts,
    stats: Stats,
    /// Euler characteristic of the base mesh (of its faces that are not
    /// holes, with their edges and vertices).
    chi: i64,
}

/// Sizes of the connectivity a tessellation copies: base vertices, faces,
/// half-edges, slots; feature meshes also their base edges (whose
/// half-edge lists replace the twins) and the most faces on one edge.
#[derive(Clone, Copy)]
struct Dims {
    nv: usize,
    nf: usize,
    nh: usize,
    ns: usize,
    ne: Option<usize>,
    kmax: usize,
}

impl Dims {
    fn smooth(topo: &Topology, ns: usize) -> Dims {
        Dims {
            nv: topo.num_vertices(),
            nf: topo.num_faces(),
            nh: topo.num_half_edges(),
            ns,
            ne: None,
            kmax: 0,
        }
    }

    /// Bytes of the fixed part (everything up to the quadtree nodes).
    fn fixed(&self) -> usize {
        let mut l = fixed_layout(self.nv, self.nf, self.nh, self.ns);
        if let Some(ne) = self.ne {
            l.u32s(ne + 1);
            l.u32s(self.nh);
        }
        l.bytes()
    }
}

/// The fixed part of the buffer, carved (see the module docs).
struct Fixed<'a> {
    scratch: &'a mut Scratch,
    fstart: &'a mut [u32],
    twin: &'a mut [u32],
    origin: &'a mut [u32],
    slot_start: &'a mut [u32],
    slot_face: &'a mut [u32],
    he_face: &'a mut [u32],
    slot_node: &'a mut [u32],
    corners: &'a mut [u32],
    vid: &'a mut [u32],
    side_at: &'a mut [u32],
    own_at: &'a mut [u32],
    /// Feature meshes: each base edge's first entry in `edge_he` (E + 1).
    edge_start: &'a mut [u32],
    /// Feature meshes: the half-edges of each base edge, canonical first.
    edge_he: &'a mut [u32],
    /// The rest of the buffer (u32 values).
    rest: &'a mut [u32],
}

/// Carves `mem` (at least `d.fixed()` bytes) into the fixed part and the
/// rest.
fn carve<'m>(d: &Dims, mem: &'m mut [u64]) -> Result<Fixed<'m>, Error> {
    let Dims { nv, nf, nh, ns, .. } = *d;
    let fixed = d.fixed();
    let rest_len = bytes_of(mem.len()) - fixed;
    let mut arena = Arena::new(mem);
    let scratch = Scratch::from_words(arena.words(Scratch::BYTES))
        .ok_or(Error::InvalidArgument("internal: scratch size"))?;
    let fstart = arena.u32s(nf + 1);
    let twin = arena.u32s(nh);
    let origin = arena.u32s(nh);
    let slot_start = arena.u32s(nf + 1);
    let slot_face = arena.u32s(ns);
    let he_face = arena.u32s(nh);
    let slot_node = arena.u32s(ns + 1);
    let corners = arena.u32s(4 * ns);
    let vid = arena.u32s(nv + nf + nh);
    let side_at = arena.u32s(8 * ns);
    let own_at = arena.u32s(8 * ns);
    let (edge_start, edge_he) = match d.ne {
        Some(ne) => (arena.u32s(ne + 1), arena.u32s(nh)),
        None => (&mut [][..], &mut [][..]),
    };
    // Not zeroed: every entry is written before it is read (nodes by
    // the marking; records, side lists and the corner identities'
    // vertices by the numbering, which clears the latter first).
    let rest = as_u32s(arena.words(rest_len / 8 * 8));
    Ok(Fixed {
        scratch,
        fstart,
        twin,
        origin,
        slot_start,
        slot_face,
        he_face,
        slot_node,
        corners,
        vid,
        side_at,
        own_at,
        edge_start,
        edge_he,
        rest,
    })
}

/// A feature mesh's dimensions (slots: `N` per `N`-gon, one per quad,
/// none for holes) and Euler characteristic of its faces that are not
/// holes.
fn feature_dims(fm: &FeatureMesh) -> (Dims, i64) {
    let b = &fm.base;
    let is_hole = |f: usize| fm.hole[fm.child_face(f, 0)] != 0;
    let (nv, nf, ne) = (b.num_vertices(), b.num_faces(), b.num_edges());
    let mut ns = 0usize;
    let mut chi = 0i64;
    for f in 0..nf {
        if !is_hole(f) {
            let n = b.face(f).len();
            ns += if n == 4 { 1 } else { n };
            chi += 1;
        }
    }
    let mut kmax = 1usize;
    for e in 0..ne {
        let k = b
            .edge_faces(e)
            .iter()
            .filter(|&&f| !is_hole(f as usize))
            .count();
        kmax = kmax.max(k);
        chi -= (k > 0) as i64;
    }
    for v in 0..nv {
        chi += b.vertex_faces(v).iter().any(|&f| !is_hole(f as usize)) as i64;
    }
    let d = Dims {
        nv,
        nf,
        nh: b.face_vert.len(),
        ns,
        ne: Some(ne),
        kmax,
    };
    (d, chi)
}

/// u32 count rounded as the arena rounds it (8 bytes).
#[inline]
fn even(n: usize) -> usize {
    n + (n & 1)
}

fn fixed_layout(nv: usize, nf: usize, nh: usize, ns: usize) -> Layout {
    let mut l = Layout::default();
    l.raw(Scratch::BYTES);
    l.u32s(nf + 1);
    l.u32s(nh);
    l.u32s(nh);
    l.u32s(nf + 1);
    l.u32s(ns);
    l.u32s(nh);
    l.u32s(ns + 1);
    l.u32s(4 * ns);
    l.u32s(nv + nf + nh);
    l.u32s(8 * ns);
    l.u32s(8 * ns);
    l
}

/// Midpoints on slot boundaries: all slots' and the most of one slot.
#[derive(Clone, Copy, Default)]
struct Mids {
    sum: usize,
    max: usize,
}

impl Mids {
    fn add(&mut self, m: &SlotMark) {
        self.sum += m.side_mids as usize;
        self.max = self.max.max(m.side_mids as usize);
    }
}

/// (records, side list values, own midpoint values, working values) for
/// `nodes` nodes, `side` midpoints on slot boundaries (see [`Dims`]).
fn sizes(nodes: usize, side: Mids, d: &Dims) -> [usize; 4] {
    let internal = (nodes - d.ns) / 4;
    let (own, tmp) = own_len(side.sum, side.max, d.kmax);
    [5 * internal, pts_len(side.sum, d.nh, d.kmax), own, tmp]
}

fn variable_bytes(nodes: usize, side: Mids, d: &Dims, corner_bytes: usize) -> usize {
    let n = sizes(nodes, side, d);
    4 * (even(nodes) + n.iter().map(|&x| even(x)).sum::<usize>()) + corner_bytes
}

/// The slot `slot` of `ev`: (face, sub) by binary search.
pub(super) fn slot_id(ev: &Evaluator, slot: usize) -> Result<SlotId, Error> {
    if slot >= ev.num_slots() {
        return Err(Error::InvalidArgument("slot out of range"));
    }
    let (mut lo, mut hi) = (0usize, ev.num_faces());
    while hi - lo > 1 {
        let mid = (lo + hi) / 2;
        if ev.slot_start(mid) <= slot {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Ok(SlotId {
        slot,
        face: lo as u32,
        sub: (slot - ev.slot_start(lo)) as u32,
    })
}

/// The topology must be the evaluator's.
fn check(topo: &Topology, ev: &Evaluator, opts: &Options) -> Result<(), Error> {
    opts.validate()?;
    if topo.num_faces() != ev.num_faces() {
        return Err(Error::InvalidArgument(
            "topology and evaluator do not match",
        ));
    }
    for f in 0..topo.num_faces() {
        let n = topo.face_size(f);
        let want = if n == 4 { 1 } else { n };
        if ev.num_subfaces(f) != want {
            return Err(Error::InvalidArgument(
                "topology and evaluator do not match",
            ));
        }
    }
    Ok(())
}

/// As [`mark_slot`], under absolute flatness `eps` with a per-cell
/// tolerance: a cell is accepted when its bound is at most `min(eps,
/// field(box))`, `box` containing its surface (see [`ToleranceField`]: the
/// field must be monotone). The trees go to [`Tessellation::build_marked`]
/// with the same `opts`; the output is crack-free as for any marking.
pub fn mark_slot_field(
    ev: &Evaluator,
    opts: &Options,
    slot: usize,
    nodes: Option<&mut [u32]>,
    field: &dyn ToleranceField,
    scratch: &mut Scratch,
) -> Result<SlotMark, Error> {
    opts.validate()?;
    let at = slot_id(ev, slot)?;
    let cap = nodes.as_ref().map(|n| n.len());
    let m = mark_field(ev, opts, at, nodes, field, scratch)?;
    match cap {
        Some(c) if c < m.nodes as usize => Err(Error::BufferTooSmall {
            required: m.nodes as usize,
        }),
        _ => Ok(m),
    }
}

/// Marks slot `slot` (reentrant; for marking slots in parallel before
/// [`Tessellation::build_marked`]). With `nodes`, the quadtree is written
/// there (entry = local index of the first of four children, 0 for a leaf;
/// root 0); a too-small `nodes` gives [`Error::BufferTooSmall`] with the
/// node count. Without, only counts.
pub fn mark_slot(
    ev: &Evaluator,
    opts: &Options,
    slot: usize,
    nodes: Option<&mut [u32]>,
    scratch: &mut Scratch,
) -> Result<SlotMark, Error> {
    opts.validate()?;
    let at = slot_id(ev, slot)?;
    let cap = nodes.as_ref().map(|n| n.len());
    let m = mark(ev, opts, at, nodes, false, scratch)?;
    match cap {
        Some(c) if c < m.nodes as usize => Err(Error::BufferTooSmall {
            required: m.nodes as usize,
        }),
        _ => Ok(m),
    }
}

/// Whether the uniform tessellation of level `level` of slot `slot` meets
/// `criterion`: every level-`level` cell passes the same test as in the
/// adaptive tessellation, or lies inside a corner cell (at an extraordinary
/// vertex) whose bound covers every triangle with vertices in it and meets
/// the criterion (absolute: `bound <= eps`; relative: the corner rule,
/// `bound <= r *` the slot's diagonal; without that, uniform refinement
/// never meets a relative tolerance at an extraordinary vertex, where the
/// cells next to the corner cell keep their shape at every level).
/// Subtrees that provably pass are skipped (bounds shrink by 4 per level;
/// for relative flatness diagonals are bounded below by the derivative
/// nets), so the cost is far below one test per uniform cell.
pub fn uniform_passes(
    ev: &Evaluator,
    criterion: Criterion,
    slot: usize,
    level: u32,
    scratch: &mut Scratch,
) -> Result<bool, Error> {
    Options {
        criterion,
        max_level: super::MAX_LEVEL,
    }
    .validate()?;
    if level > super::MAX_LEVEL {
        return Err(Error::InvalidArgument("level above 30"));
    }
    slot_passes(ev, criterion, slot_id(ev, slot)?, level, scratch)
}

/// The smallest level `L` in `from..=max` such that the uniform
/// tessellation of level `L` meets `criterion` on every slot, or `None`.
/// (The adaptive tessellation's deepest level is a lower bound.)
pub fn uniform_depth(
    ev: &Evaluator,
    criterion: Criterion,
    from: u32,
    max: u32,
    scratch: &mut Scratch,
) -> Result<Option<u32>, Error> {
    let mut l = from;
    'levels: while l <= max.min(super::MAX_LEVEL) {
        for s in 0..ev.num_slots() {
            if !uniform_passes(ev, criterion, s, l, scratch)? {
                l += 1;
                continue 'levels;
            }
        }
        return Ok(Some(l));
    }
    Ok(None)
}

/// The bound the marking computes for the cell `[i/2^level, (i+1)/2^level]
/// x [j/2^level, (j+1)/2^level]` of sub-face `sub` of face `face` (top
/// down, by de Casteljau from the patch's Bezier net): the same quantity as
/// the `interpolation_bound()` of [`crate::bounds::cell_bound`] (the one
/// cell bound of the crate), up to rounding.
pub fn marking_bound(
    ev: &Evaluator,
    face: u32,
    sub: u32,
    level: u32,
    i: u32,
    j: u32,
) -> Result<f64, Error> {
    let f = face as usize;
    if f >= ev.num_faces() {
        return Err(Error::FaceOutOfRange { face });
    }
    if sub as usize >= ev.num_subfaces(f) {
        return Err(Error::SubFaceOutOfRange { face, sub });
    }
    if level > super::MAX_LEVEL || (i as u64) >> level != 0 || (j as u64) >> level != 0 {
        return Err(Error::InvalidArgument(
            "cell outside the sub-face or level above 30",
        ));
    }
    let at = SlotId {
        slot: ev.slot_start(f) + sub as usize,
        face,
        sub,
    };
    Ok(top_down_bound(ev, at, level, i, j))
}

/// Saves the expansion of every split corner cell of the trees `nodes`
/// (slot `s` at `slot_node[s]..`) into `cache` (in preorder over all
/// slots, each below the one before, from the back), as the marking of
/// [`Tessellation::build`] does. Corner cells form one chain per patch
/// with an extraordinary vertex (the corner child of a corner cell is the
/// only corner cell among its children), so only those chains are walked.
/// The size must be exactly what the marks said.
fn fill_corners(
    ev: &Evaluator,
    nodes: &[u32],
    slot_node: &[u32],
    cache: &mut [f64],
    eps: f64,
    scratch: &mut Scratch,
) -> Result<(), Error> {
    const BAD: Error = Error::InvalidArgument("trees do not match the marks");
    let mut used = 0usize;
    let lv = &mut scratch.levels[0];
    let ns = slot_node.len() - 1;
    for s in 0..ns {
        let base = slot_node[s] as usize;
        let child = |x: u32| nodes.get(base + x as usize).copied().unwrap_or(0);
        let root = cells::root(ev, s);
        // Chains start at the root, or at the children of a split root.
        let mut starts = [(root.kind, 0u32); 4];
        let mut nstart = 1;
        if root.kind.tag == SPLIT {
            let c = child(0);
            nstart = 0;
            if c != 0 {
                cells::expand(
                    ev,
                    &root.kind,
                    &root.net,
                    root.off.to_array(),
                    &mut lv.kinds,
                    &mut lv.nets,
                    &mut lv.offs,
                );
                for q in 0..4 {
                    starts[q] = (lv.kinds[q], c + q as u32);
                }
                nstart = 4;
            }
        }
        // The marking's light-split test (rounding term included).
        let eps_s = eps - super::mark::slot_round(ev, s).unwrap_or(f64::INFINITY);
        for &(kind0, x0) in &starts[..nstart] {
            let (mut kind, mut x) = (kind0, x0);
            while kind.tag == CORNER {
                let c = child(x);
                if c == 0 {
                    break;
                }
                let r = kind.rho;
                // A tolerance field (`mark_slot_field`) may split
                // ring-region children the light test at eps accepts:
                // those cells take the full path.
                let ring = (0..4).any(|q| q != r && child(c + q) != 0);
                if !ring && cells::light_split(ev, &kind, eps_s).is_some() {
                    // As the marking saved it (no ring-region child split).
                    let len = cells::corner_len(r, 0);
                    let at = cache.len().checked_sub(used + len).ok_or(BAD)?;
                    if !cells::store_corner_light(ev, &kind, &mut cache[at..at + len]) {
                        return Err(BAD);
                    }
                    used += len;
                    x = c + r;
                    kind = Kind {
                        k: kind.k + 1,
                        ..kind
                    };
                    continue;
                }
                cells::expand(
                    ev,
                    &kind,
                    &[0.0; 48],
                    [0.0; 3],
                    &mut lv.kinds,
                    &mut lv.nets,
                    &mut lv.offs,
                );
                let internal = (0..4).fold(0u32, |m, q| m | ((child(c + q) != 0) as u32) << q);
                let len = cells::corner_len(kind.rho, internal);
                let at = cache.len().checked_sub(used + len).ok_or(BAD)?;
                cells::store_corner(
                    &kind,
                    internal,
                    &lv.kinds,
                    &lv.nets,
                    &lv.offs,
                    &mut cache[at..at + len],
                );
                used += len;
                x = c + r;
                kind = lv.kinds[r as usize];
            }
        }
    }
    if used != cache.len() {
        return Err(BAD);
    }
    Ok(())
}

/// Stats of a set of slot marks.
fn stats_of(marks: impl Iterator<Item = SlotMark>) -> (Stats, usize, Mids) {
    let mut st = Stats::default();
    let (mut nodes, mut side) = (0usize, Mids::default());
    for m in marks {
        st.max_level = st.max_level.max(m.max_level);
        st.bound = st.bound.max(m.bound);
        st.max_ratio = st.max_ratio.max(m.max_ratio);
        nodes += m.nodes as usize;
        side.add(&m);
    }
    st.nodes = nodes;
    (st, nodes, side)
}

impl<'a> Tessellation<'a> {
    /// Exact bytes [`Tessellation::build`] needs (marks every slot in
    /// count-only mode).
    pub fn required_bytes(
        topo: &Topology,
        ev: &Evaluator,
        opts: &Options,
        scratch: &mut Scratch,
    ) -> Result<usize, Error> {
        Self::required_bytes_with(topo, ev, opts, Keep::default(), scratch)
    }

    /// Exact bytes [`Tessellation::build_with`] needs with `keep`.
    pub fn required_bytes_with(
        topo: &Topology,
        ev: &Evaluator,
        opts: &Options,
        keep: Keep,
        scratch: &mut Scratch,
    ) -> Result<usize, Error> {
        check(topo, ev, opts)?;
        let mut nodes = 0usize;
        let mut side = Mids::default();
        let mut corners = 0usize;
        for s in 0..ev.num_slots() {
            let m = mark(ev, opts, slot_id(ev, s)?, None, true, scratch)?;
            nodes += m.nodes as usize;
            if nodes as u64 > super::MAX_NODES {
                return Err(super::nodes_exceeded());
            }
            side.add(&m);
            if keep.corner_expansions {
                corners += m.corner_bytes as usize;
            }
        }
        Self::bytes_for(&Dims::smooth(topo, ev.num_slots()), nodes, side, corners)
    }

    fn bytes_for(d: &Dims, nodes: usize, side: Mids, corners: usize) -> Result<usize, Error> {
        if nodes as u64 > super::MAX_NODES {
            return Err(super::nodes_exceeded());
        }
        Ok(d.fixed() + variable_bytes(nodes, side, d, corners))
    }

    /// Exact bytes [`Tessellation::build_feature`] needs (marks every slot
    /// in count-only mode).
    pub fn required_bytes_feature(
        fev: &FeatureEvaluator,
        opts: &Options,
        scratch: &mut Scratch,
    ) -> Result<usize, Error> {
        opts.validate()?;
        let (d, _) = feature_dims(fev.mesh());
        let (mut nodes, mut side) = (0usize, Mids::default());
        let mut at = SlotId {
            slot: 0,
            face: 0,
            sub: 0,
        };
        let fm = fev.mesh();
        for f in 0..fm.num_faces() {
            if fm.hole[fm.child_face(f, 0)] != 0 {
                continue;
            }
            at.face = f as u32;
            for sub in 0..fev.num_subfaces(f) {
                at.sub = sub as u32;
                let m = mark_feature(fev, opts, at, None, scratch)?;
                nodes += m.nodes as usize;
                if nodes as u64 > super::MAX_NODES {
                    return Err(super::nodes_exceeded());
                }
                side.add(&m);
                at.slot += 1;
            }
        }
        Self::bytes_for(&d, nodes, side, 0)
    }

    /// Exact bytes [`Tessellation::build_marked`] needs for these marks.
    pub fn required_bytes_marked(topo: &Topology, marks: &[SlotMark]) -> Result<usize, Error> {
        let (_, nodes, side) = stats_of(marks.iter().copied());
        let corners = marks.iter().map(|m| m.corner_bytes as usize).sum();
        Self::bytes_for(&Dims::smooth(topo, marks.len()), nodes, side, corners)
    }

    /// Marks every slot and prepares emission, in `mem` (words).
    /// The topology must be the one `ev` was built from (it is copied:
    /// the result refers only to `ev` and `mem`). Too small a `mem` gives
    /// [`Error::BufferTooSmall`] with the exact size when `mem` holds at
    /// least the fixed part (scratch and topology copies), else with that
    /// fixed size.
    pub fn build(
        topo: &Topology,
        ev: &'a Evaluator<'a>,
        opts: Options,
        mem: &'a mut [u64],
    ) -> Result<Self, Error> {
        Self::build_impl(topo, ev, opts, Keep::default(), None, mem)
    }

    /// As [`Tessellation::build`], keeping what `keep` says (`mem`: at
    /// least [`Tessellation::required_bytes_with`] bytes). The output is
    /// the same bit for bit whatever `keep`.
    pub fn build_with(
        topo: &Topology,
        ev: &'a Evaluator<'a>,
        opts: Options,
        keep: Keep,
        mem: &'a mut [u64],
    ) -> Result<Self, Error> {
        Self::build_impl(topo, ev, opts, keep, None, mem)
    }

    /// As [`Tessellation::build`], from slot marks and quadtrees made by
    /// [`mark_slot`] (with the same options): `trees` is the concatenation
    /// of the slots' node arrays. Sized by
    /// [`Tessellation::required_bytes_marked`].
    pub fn build_marked(
        topo: &Topology,
        ev: &'a Evaluator<'a>,
        opts: Options,
        marks: &[SlotMark],
        trees: &[u32],
        mem: &'a mut [u64],
    ) -> Result<Self, Error> {
        if marks.len() != ev.num_slots() {
            return Err(Error::InvalidArgument("one mark per slot expected"));
        }
        let total: usize = marks.iter().map(|m| m.nodes as usize).sum();
        if total != trees.len() {
            return Err(Error::InvalidArgument("trees do not match the marks"));
        }
        // Validate the trees: indices in range, children after parents.
        let mut o = 0usize;
        for m in marks {
            let n = m.nodes as usize;
            if n == 0 || n % 4 != 1 {
                return Err(Error::InvalidArgument("bad quadtree size"));
            }
            for (x, &c) in trees[o..o + n].iter().enumerate() {
                let c = c as usize;
                if c != 0 && (c % 4 != 1 || c <= x || c + 3 >= n) {
                    return Err(Error::InvalidArgument("bad quadtree"));
                }
            }
            o += n;
        }
        Self::build_impl(topo, ev, opts, Keep::default(), Some((marks, trees)), mem)
    }

    fn build_impl(
        topo: &Topology,
        ev: &'a Evaluator<'a>,
        opts: Options,
        keep: Keep,
        marked: Option<(&[SlotMark], &[u32])>,
        mem: &'a mut [u64],
    ) -> Result<Self, Error> {
        check(topo, ev, &opts)?;
        let d = Dims::smooth(topo, ev.num_slots());
        if bytes_of(mem.len()) < d.fixed() {
            return Err(Error::BufferTooSmall {
                required: d.fixed(),
            });
        }
        let x = carve(&d, mem)?;
        let nf = d.nf;
        for f in 0..nf {
            x.fstart[f] = topo.face_half_edge(f) as u32;
            x.slot_start[f] = ev.slot_start(f) as u32;
            for s in ev.slot_start(f)..ev.slot_start(f) + ev.num_subfaces(f) {
                x.slot_face[s] = f as u32;
            }
        }
        x.fstart[nf] = d.nh as u32;
        x.slot_start[nf] = d.ns as u32;
        for h in 0..d.nh {
            x.twin[h] = topo.twin(h) as u32;
            x.origin[h] = topo.origin(h) as u32;
            x.he_face[h] = topo.face_of(h) as u32;
        }
        let chi = (0..topo.num_vertices())
            .filter(|&v| topo.valence(v) > 0)
            .count() as i64
            - (d.nh / 2) as i64
            + nf as i64;
        Self::finish(Surface::Smooth(ev), &d, chi, opts, keep, marked, x)
    }

    /// Marks every slot and prepares emission of the surface of a feature
    /// mesh (creases, corners, boundaries, holes, non-manifold parts; see
    /// the `feature` pass's docs), in `mem` (words), sized by
    /// [`Tessellation::required_bytes_feature`]. Hole faces have no slots
    /// and produce nothing; the output has the boundary loops of the
    /// faces that are not holes and is closed when they are. Too small a
    /// `mem` gives [`Error::BufferTooSmall`] as for [`Tessellation::build`].
    pub fn build_feature(
        fev: &'a FeatureEvaluator<'a, 'a>,
        opts: Options,
        mem: &'a mut [u64],
    ) -> Result<Self, Error> {
        opts.validate()?;
        let fm = fev.mesh();
        let b = &fm.base;
        let (d, chi) = feature_dims(fm);
        if bytes_of(mem.len()) < d.fixed() {
            return Err(Error::BufferTooSmall {
                required: d.fixed(),
            });
        }
        let x = carve(&d, mem)?;
        let is_hole = |f: usize| fm.hole[fm.child_face(f, 0)] != 0;
        let mut slot = 0usize;
        for f in 0..d.nf {
            x.fstart[f] = b.face_off[f];
            x.slot_start[f] = slot as u32;
            if !is_hole(f) {
                for _ in 0..fev.num_subfaces(f) {
                    x.slot_face[slot] = f as u32;
                    slot += 1;
                }
            }
            for h in b.face_off[f] as usize..b.face_off[f + 1] as usize {
                x.he_face[h] = f as u32;
            }
        }
        x.fstart[d.nf] = d.nh as u32;
        x.slot_start[d.nf] = slot as u32;
        x.origin.copy_from_slice(&b.face_vert[..d.nh]);
        // Half-edges per base edge (faces that are not holes only), in
        // increasing order: the first is the canonical one.
        let ne = b.num_edges();
        x.edge_start.fill(0);
        for h in 0..d.nh {
            x.twin[h] = h as u32;
            if !is_hole(x.he_face[h] as usize) {
                x.edge_start[b.face_edge[h] as usize + 1] += 1;
            }
        }
        for e in 0..ne {
            x.edge_start[e + 1] += x.edge_start[e];
        }
        for h in 0..d.nh {
            if !is_hole(x.he_face[h] as usize) {
                let e = b.face_edge[h] as usize;
                // edge_start[e] runs ahead while filling; shifted back below.
                let at = x.edge_start[e] as usize;
                x.edge_he[at] = h as u32;
                x.edge_start[e] += 1;
            }
        }
        for e in (0..ne).rev() {
            x.edge_start[e + 1] = x.edge_start[e];
        }
        x.edge_start[0] = 0;
        for e in 0..ne {
            let (a, z) = (x.edge_start[e] as usize, x.edge_start[e + 1] as usize);
            if let Some(&c) = x.edge_he[a..z].first() {
                for k in a..z {
                    x.twin[x.edge_he[k] as usize] = c;
                }
            }
        }
        Self::finish(
            Surface::Feature(fev),
            &d,
            chi,
            opts,
            Keep::default(),
            None,
            x,
        )
    }

    /// Marks (or copies the marks) into the rest of the buffer, carves the
    /// variable part and numbers the vertices.
    fn finish(
        surface: Surface<'a>,
        d: &Dims,
        chi: i64,
        opts: Options,
        keep: Keep,
        marked: Option<(&[SlotMark], &[u32])>,
        x: Fixed<'a>,
    ) -> Result<Self, Error> {
        let Fixed {
            scratch,
            fstart,
            twin,
            origin,
            slot_start,
            slot_face,
            he_face,
            slot_node,
            corners,
            vid,
            side_at,
            own_at,
            edge_start,
            edge_he,
            rest,
        } = x;
        let ns = d.ns;
        let fixed = d.fixed();
        let (edge_start, edge_he): (&'a [u32], &'a [u32]) = (edge_start, edge_he);
        let topo = Topo {
            fstart,
            twin,
            origin,
            slot_start,
            slot_face,
            he_face,
            nv: d.nv,
            edges: d.ne.map(|_| (edge_start, edge_he)),
        };
        // Marking, straight into the tail: nodes from the front, saved
        // corner-cell expansions from the back.
        let mut off = 0usize;
        let mut fits = true;
        let mut side = Mids::default();
        let mut ncorner = 0usize;
        let mut st = Stats::default();
        slot_node[0] = 0;
        for s in 0..ns {
            let m = match marked {
                Some((marks, trees)) => {
                    let m = marks[s];
                    let n = m.nodes as usize;
                    match rest.get_mut(off..off + n) {
                        Some(d) if fits => d.copy_from_slice(&trees[off..off + n]),
                        _ => fits = false,
                    }
                    m
                }
                None => {
                    let end = rest.len().saturating_sub(ncorner / 4);
                    let buf = if fits { rest.get_mut(off..end) } else { None };
                    let room = buf.as_ref().map_or(0, |b| b.len());
                    let m = match surface {
                        Surface::Smooth(ev) => {
                            let c = keep.corner_expansions;
                            let mut m = mark(ev, &opts, slot_id(ev, s)?, buf, c, scratch)?;
                            if !c {
                                // Not kept: emission redoes them.
                                m.corner_bytes = 0;
                            }
                            m
                        }
                        Surface::Feature(fev) => {
                            let (face, sub) = topo.face_sub(s);
                            let at = SlotId { slot: s, face, sub };
                            mark_feature(fev, &opts, at, buf, scratch)?
                        }
                    };
                    if m.nodes as usize + m.corner_bytes as usize / 4 > room {
                        fits = false;
                    }
                    m
                }
            };
            ncorner += m.corner_bytes as usize;
            let (s1, ..) = stats_of(core::iter::once(m));
            st.max_level = st.max_level.max(s1.max_level);
            st.bound = st.bound.max(s1.bound);
            st.max_ratio = st.max_ratio.max(s1.max_ratio);
            off += m.nodes as usize;
            side.add(&m);
            if off as u64 > super::MAX_NODES {
                return Err(super::nodes_exceeded());
            }
            slot_node[s + 1] = off as u32;
        }
        st.nodes = off;
        let required = fixed + variable_bytes(off, side, d, ncorner);
        if !fits || required > fixed + rest.len() * 4 {
            return Err(Error::BufferTooSmall { required });
        }
        let [nrec, npts, nown, ntmp] = sizes(off, side, d);
        let cut = rest.len() - ncorner / 4;
        let (rest, cache) = rest.split_at_mut(cut);
        let cache = as_f64s_mut(cache);
        let (nodes, tail) = rest.split_at_mut(even(off));
        if let (Some(_), Surface::Smooth(ev)) = (marked, surface) {
            if ncorner > 0 {
                // Trees marked elsewhere: save the corner-cell expansions here.
                let eps = match opts.criterion {
                    Criterion::Absolute(e) => e,
                    _ => f64::NAN,
                };
                fill_corners(ev, &nodes[..off], slot_node, cache, eps, scratch)?;
            }
        }
        let cache: &[f64] = cache;
        let (recs, tail) = tail.split_at_mut(even(nrec));
        let (pts, tail) = tail.split_at_mut(even(npts));
        let pts = pts[..npts].as_chunks_mut::<2>().0;
        let (own, tail) = tail.split_at_mut(even(nown));
        let own = own[..nown].as_chunks_mut::<2>().0;
        let tmp = tail[..ntmp].as_chunks_mut::<2>().0;
        let mut t = Tessellation {
            surface,
            opts,
            topo,
            slot_node,
            nodes: &nodes[..off],
            recs: &mut recs[..nrec],
            corners,
            vid,
            side_at,
            pts,
            own_at,
            own,
            tmp,
            cache,
            keep,
            scratch,
            counts: Counts::default(),
            stats: st,
            chi,
        };
        t.count()?;
        Ok(t)
    }

    fn forest(&self) -> Forest<'a> {
        Forest {
            topo: self.topo,
            slot_node: self.slot_node,
            nodes: self.nodes,
        }
    }

    /// Counting: vertices by numbering them (no output); polygons = leaves;
    /// polygon indices = twice the edges, by Euler's formula on the closed
    /// output (same characteristic as the base mesh; `emit` checks the
    /// actual counts).
    fn count(&mut self) -> Result<(), Error> {
        let f = self.forest();
        let mut lists = SideLists::new(
            &mut *self.side_at,
            &mut *self.pts,
            &mut *self.own_at,
            &mut *self.own,
            &mut *self.tmp,
        );
        let nv = assign(
            &f,
            &mut *self.recs,
            &mut *self.corners,
            &mut *self.vid,
            &mut lists,
            &mut *self.scratch,
        )?;
        let ns = f.num_slots();
        let np = ns + 3 * (self.nodes.len() - ns) / 4;
        let edges = nv as i64 + np as i64 - self.chi;
        // Each edge is in two polygons, but for feature meshes those on
        // base edges with k faces, in k (`extra`: the sum of k - 2 over
        // them).
        let ni = 2 * edges + lists.extra;
        if ni < 4 * np as i64 {
            return Err(Error::InvalidArgument("internal: inconsistent counts"));
        }
        let ni = ni as usize;
        self.counts = Counts {
            vertices: nv,
            polygons: np,
            polygon_indices: ni,
            triangles: ni - 2 * np,
        };
        Ok(())
    }

    /// Output sizes.
    pub fn counts(&self) -> Counts {
        self.counts
    }

    /// Deepest level, guaranteed bound, node count.
    pub fn stats(&self) -> Stats {
        self.stats
    }

    /// The options it was built with.
    pub fn options(&self) -> Options {
        self.opts
    }

    /// Number of quadtree nodes of slot `slot` and its tree (local child
    /// indices, as [`mark_slot`] writes them).
    pub fn slot_tree(&self, slot: usize) -> Option<&[u32]> {
        let a = *self.slot_node.get(slot)? as usize;
        let b = *self.slot_node.get(slot + 1)? as usize;
        self.nodes.get(a..b)
    }

    /// Writes the tessellation into `out` (see [`Output`]); each buffer
    /// must hold at least what [`Tessellation::counts`] says, else
    /// [`Error::BufferTooSmall`] with the element count of the first short
    /// buffer (positions, normals, params, polygon sizes, polygon indices,
    /// triangles, cells, in that order). May be called again.
    pub fn emit(&mut self, out: Output) -> Result<(), Error> {
        let c = self.counts;
        c.check_output_lengths([
            Some(out.positions.len()),
            out.normals.as_ref().map(|n| n.len()),
            out.params.as_ref().map(|p| p.len()),
            Some(out.polygon_sizes.len()),
            Some(out.polygon_indices.len()),
            out.triangles.as_ref().map(|t| t.len()),
            out.cells.as_ref().map(|t| t.len()),
        ])?;
        // The numbering of `build` (records, slot corners, side lists) stands;
        // only positions are computed here.
        let mut vo = VertOut {
            positions: out.positions,
            normals: out.normals,
            params: out.params,
            cuts: out.triangles.is_some(),
            single: NoSingle,
        };
        self.vertex_positions(&mut vo)?;
        let mut po = PolyOut {
            sizes: out.polygon_sizes,
            indices: out.polygon_indices,
            triangles: out.triangles,
            cells: out.cells,
            positions: Pos::F64(vo.positions),
            stream: None,
        };
        self.polygons(&mut po).map(|_| ())
    }

    /// The vertex pass: positions (and what else `vo` asks for).
    ///
    /// The passes (`assign`, `positions`, `assemble`) are not inlined
    /// into these methods and take the fields they use, not `self`: a
    /// caller's frame then holds none of their locals (the marking's stack
    /// depth stays that of the marking), and where the tessellation was
    /// built the compiler still knows its surface (a firmware without
    /// feature meshes links no feature code).
    pub(super) fn vertex_positions<S: Single>(&mut self, vo: &mut VertOut<S>) -> Result<(), Error> {
        let forest = self.forest();
        match self.surface {
            Surface::Smooth(ev) => {
                // Without saved expansions: the tolerance of the light
                // corner splits, whose points emission redoes.
                let light = match self.opts.criterion {
                    Criterion::Absolute(e) if !self.keep.corner_expansions => Some(e),
                    _ => None,
                };
                positions(
                    &forest,
                    ev,
                    &mut *self.recs,
                    &*self.corners,
                    self.cache,
                    light,
                    &mut *self.scratch,
                    vo,
                )?
            }
            Surface::Feature(fev) => feature_positions(
                &forest,
                fev,
                &mut *self.recs,
                &*self.corners,
                &mut *self.scratch,
                vo,
            )?,
        }
        Ok(())
    }

    /// The polygon pass into `po`; the most vertices of a streamed polygon
    /// that did not fit (0: all did).
    pub(super) fn polygons(&mut self, po: &mut PolyOut) -> Result<usize, Error> {
        let c = self.counts;
        let forest = self.forest();
        let (np, ni, too_big) = assemble(
            &forest,
            &*self.recs,
            &*self.corners,
            (&*self.side_at, &*self.pts),
            &mut *self.scratch,
            po,
        )?;
        if (np, ni) != (c.polygons, c.polygon_indices) {
            return Err(Error::InvalidArgument(
                "internal: emission differs from the count",
            ));
        }
        Ok(too_big)
    }

    /// The `u32` values the buffer of [`Tessellation::emit_stream`] needs:
    /// `4 m - 6` for the largest polygon, of `m` vertices (its vertices and
    /// its `m - 2` triangles). One walk over the polygons, nothing written.
    pub fn stream_len(&mut self) -> Result<usize, Error> {
        let mut none = |_: &[f64], _: &[u32], _: &[u32]| {};
        let mut po = PolyOut {
            sizes: &mut [],
            indices: &mut [],
            triangles: None,
            cells: None,
            positions: Pos::F64(&[]),
            stream: Some(&mut none),
        };
        let m = self.polygons(&mut po)?.max(3);
        Ok(4 * m - 6)
    }

    /// Emits the tessellation without whole-output buffers, as a machine
    /// controller consumes it: the vertex positions into `positions`
    /// (`3 * vertices`, as [`Tessellation::emit`]), then each polygon, in
    /// the order and with the vertices and triangles [`Tessellation::emit`]
    /// gives, handed to `sink(positions, vertices, triangles)` (all the
    /// positions, as written to `positions`; the polygon's vertex indices;
    /// its triangles, 3 indices each, `vertices.len() - 2` of them) as soon
    /// as it is made. `buf`
    /// holds one polygon and its triangles: at least
    /// [`Tessellation::stream_len`] values, else
    /// [`Error::BufferTooSmall`] with that length, before anything is
    /// handed out. Short `positions`: [`Error::BufferTooSmall`] with its
    /// length. May be called again.
    pub fn emit_stream(
        &mut self,
        positions: &mut [f64],
        buf: &mut [u32],
        sink: &mut PolygonSink,
    ) -> Result<(), Error> {
        let c = self.counts;
        if positions.len() < 3 * c.vertices {
            return Err(Error::BufferTooSmall {
                required: 3 * c.vertices,
            });
        }
        let need = self.stream_len()?;
        if buf.len() < need {
            return Err(Error::BufferTooSmall { required: need });
        }
        let mut vo = VertOut {
            positions,
            normals: None,
            params: None,
            cuts: true,
            single: NoSingle,
        };
        self.vertex_positions(&mut vo)?;
        // One polygon of m vertices and its m - 2 triangles.
        let m = (need + 6) / 4;
        let (indices, tris) = buf.split_at_mut(m);
        let mut size = [0u32; 1];
        let mut po = PolyOut {
            sizes: &mut size,
            indices,
            triangles: Some(tris),
            cells: None,
            positions: Pos::F64(vo.positions),
            stream: Some(sink),
        };
        match self.polygons(&mut po)? {
            0 => Ok(()),
            _ => Err(Error::InvalidArgument(
                "internal: a streamed polygon beyond its size",
            )),
        }
    }
}
