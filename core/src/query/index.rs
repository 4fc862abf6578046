//! A bounding-box index over the slots of a surface, so that a query
//! visits only the slots its ray, point or planes can reach.
//!
//! Without an index every walk (`ray.rs`, `closest.rs`, `slice.rs`) makes
//! the root cell of every slot `(face, sub)` (its Bezier net, corner ball
//! or hull, and for extraordinary slots the eigen terms of the ball) and
//! tests it: on a mesh with thousands of slots that is most of a ray's or
//! a closest point's time, however few slots the query touches. The index
//! stores, in a caller slice of [`IndexNode`]s:
//!
//! * per slot, in slot order, the axis-aligned box of its root cell's
//!   guaranteed bound (the box of the net, ball or hull, \[CL-R ch. 7\];
//!   for a root without a bound, the union of its children's), grown by a
//!   relative `1e-12` for the rounding of the box itself;
//! * a complete binary tree over those boxes with the slots in Morton
//!   order of their box centres (node `k` has children `2k`, `2k + 1`;
//!   the leaves hold one slot each, padded to a power of two with empty
//!   boxes).
//!
//! A walk asks its [`Visit::Box`] question of a box (may the query reach
//! anything inside it, and how near is it) and runs its [`Visit::Slot`]
//! body on the slots that pass. A slot is skipped only when the query's
//! own test, grown by its tolerance and rounding terms, proves that its
//! walk would report nothing there, so the answers keep their guarantees:
//! the ray's hits, the closest point and the slice segments are those of
//! the walk over every slot (tests `index_*`). [`in_order`] keeps the slot
//! order (all hits of a ray and slices, whose merging and chaining see the
//! same sequence: bit-identical outputs); [`nearest`] visits the tree
//! nearest box first (first hit, closest point), so that the first answers
//! are good and prune the rest.
//!
//! The index also keeps the surface's magnitude (`rounding.rs`), which the
//! walks would otherwise recompute over all patches per query.
//!
//! ```
//! use ccss_core::mem::words_for;
//! use ccss_core::query::{closest, ClosestOptions, IndexNode, Indexed, QueryWork, SlotIndex};
//! use ccss_core::{BuildScratch, DVec3, Evaluator, MeshInput, TableSet, Topology};
//! # fn main() -> Result<(), ccss_core::Error> {
//! # let p = [-1.,-1.,-1., 1.,-1.,-1., 1.,1.,-1., -1.,1.,-1., -1.,-1.,1., 1.,-1.,1., 1.,1.,1., -1.,1.,1.];
//! # let sizes = [4u32; 6];
//! # let idx = [0,3,2,1, 4,5,6,7, 0,1,5,4, 1,2,6,5, 2,3,7,6, 3,0,4,7];
//! # let mesh = MeshInput { positions: &p, face_sizes: &sizes, indices: &idx };
//! # let mut tables = Box::new(TableSet::ZERO);
//! # tables.build_into(&Default::default(), &mut Box::new(BuildScratch::ZERO))?;
//! # let mut tmem = vec![0u64; words_for(Topology::required_bytes(8, &sizes))];
//! # let topo = Topology::build(mesh, &mut tmem)?;
//! # let mut emem = vec![0u64; words_for(Evaluator::required_bytes(&topo, &tables)?)];
//! let ev = Evaluator::build(&topo, &tables, &mut emem)?;
//! let mut nodes = vec![IndexNode::default(); SlotIndex::required_len(&ev)];
//! let index = SlotIndex::build(&ev, &mut nodes)?;
//! let surf = Indexed::new(&ev, &index)?;
//! let mut work = Box::new(QueryWork::ZERO);
//! let q = DVec3::new(2.0, 0.1, 0.2);
//! let a = closest(&surf, q, &ClosestOptions::default(), &mut work)?;
//! let b = closest(&ev, q, &ClosestOptions::default(), &mut work)?;
//! assert!((a.dist - b.dist).abs() <= 1e-9);
//! # Ok(())
//! # }
//! ```

use super::cell::{Bound, Cell, CellSurface};
pub use super::slots::{IndexNode, SlotIndex};
use crate::error::Error;
use crate::math::Eval;
use glam::DVec3;

/// Total slots of a surface.
fn slot_count<S: CellSurface + ?Sized>(surf: &S) -> usize {
    (0..surf.faces()).map(|f| surf.subfaces(f)).sum()
}

/// Leaves of the tree: the slots padded to a power of two.
fn leaves_for(slots: usize) -> usize {
    slots.max(1).next_power_of_two()
}

/// The guaranteed box of a root cell; a root without a bound takes the
/// union of its children's (infinite if one of them has none either).
fn root_box<S: CellSurface + ?Sized>(surf: &S, c: &Cell) -> (DVec3, DVec3) {
    if c.bound != Bound::None {
        return c.aabb();
    }
    let mut kids = [Cell::ZERO; 4];
    surf.split(c, &mut kids);
    let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
    for k in &kids {
        let (l, h) = k.aabb();
        lo = lo.min(l);
        hi = hi.max(h);
    }
    (lo, hi)
}

/// `bits` bits of `x` in `[0, 1]`, spread to every third bit.
fn spread(x: f64, bits: u32) -> u32 {
    let m = (1u32 << bits) - 1;
    let q = if x.is_finite() {
        ((x.clamp(0.0, 1.0) * m as f64) as u32).min(m)
    } else {
        0
    };
    let mut r = 0u32;
    for i in 0..bits {
        r |= ((q >> i) & 1) << (3 * i);
    }
    r
}

impl<'a> SlotIndex<'a> {
    /// Nodes [`SlotIndex::build`] needs for `surf`: one per slot plus the
    /// tree's `2 P` (`P` the slots rounded up to a power of two).
    pub fn required_len<S: CellSurface + ?Sized>(surf: &S) -> usize {
        let n = slot_count(surf);
        n + 2 * leaves_for(n)
    }

    /// Builds the index of `surf` in `nodes` (at least
    /// [`SlotIndex::required_len`]; a shorter slice is
    /// [`Error::BufferTooSmall`] with that length, nothing written; more
    /// than `u32::MAX - 1` slots is [`Error::InvalidArgument`]). Work: one
    /// root cell per slot and a sort of the slots.
    pub fn build<S: CellSurface + ?Sized>(
        surf: &S,
        nodes: &'a mut [IndexNode],
    ) -> Result<SlotIndex<'a>, Error> {
        let n = slot_count(surf);
        let p = leaves_for(n);
        let required = n + 2 * p;
        if nodes.len() < required {
            return Err(Error::BufferTooSmall { required });
        }
        if n >= u32::MAX as usize - 1 {
            return Err(Error::InvalidArgument("too many slots for the index"));
        }
        let magnitude = surf.magnitude();
        let (slots, tree) = nodes[..required].split_at_mut(n);
        let (mut all_lo, mut all_hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
        let mut k = 0;
        for face in 0..surf.faces() {
            for sub in 0..surf.subfaces(face) {
                let root = surf.root(face as u32, sub as u32);
                let (lo, hi) = root_box(surf, &root);
                let grow = 1e-12 * lo.abs().max(hi.abs()).max_element();
                let (lo, hi) = (lo - DVec3::splat(grow), hi + DVec3::splat(grow));
                slots[k] = IndexNode {
                    lo: lo.to_array(),
                    hi: hi.to_array(),
                    a: face as u32,
                    b: sub as u32,
                };
                if lo.is_finite() && hi.is_finite() {
                    all_lo = all_lo.min(lo);
                    all_hi = all_hi.max(hi);
                }
                k += 1;
            }
        }
        // Leaves: the slots with their Morton keys (10 bits per axis of the
        // box centre in the box of all finite boxes), sorted.
        let span = (all_hi - all_lo).max(DVec3::splat(f64::MIN_POSITIVE));
        for (i, leaf) in tree[p..].iter_mut().enumerate() {
            *leaf = IndexNode::default();
            if i < n {
                let s = &slots[i];
                let c = (0.5 * (DVec3::from_array(s.lo) + DVec3::from_array(s.hi)) - all_lo) / span;
                *leaf = IndexNode {
                    a: i as u32,
                    b: spread(c.x, 10) | spread(c.y, 10) << 1 | spread(c.z, 10) << 2,
                    ..*s
                };
            }
        }
        tree[p..p + n].sort_unstable_by_key(|l| (l.b, l.a));
        for k in (1..p).rev() {
            let (l, r) = (tree[2 * k], tree[2 * k + 1]);
            tree[k] = IndexNode {
                lo: DVec3::from_array(l.lo)
                    .min(DVec3::from_array(r.lo))
                    .to_array(),
                hi: DVec3::from_array(l.hi)
                    .max(DVec3::from_array(r.hi))
                    .to_array(),
                a: u32::MAX - 1,
                b: 0,
            };
        }
        tree[0] = IndexNode::default();
        Ok(SlotIndex {
            nodes: &nodes[..required],
            slots: n,
            leaves: p,
            magnitude,
        })
    }
}

/// A surface with its [`SlotIndex`]: every query accepts it in place of
/// the surface itself and visits only the slots the index lets through.
pub struct Indexed<'a, S: ?Sized> {
    surf: &'a S,
    index: &'a SlotIndex<'a>,
}

impl<'a, S: CellSurface + ?Sized> Indexed<'a, S> {
    /// Pairs `surf` with `index`, which must have been built from it (a
    /// different number of slots is [`Error::InvalidArgument`]; an index of
    /// another surface with as many slots is not detected and gives wrong
    /// answers).
    pub fn new(surf: &'a S, index: &'a SlotIndex<'a>) -> Result<Self, Error> {
        if slot_count(surf) != index.slots {
            return Err(Error::InvalidArgument(
                "slot index was built for another surface",
            ));
        }
        Ok(Indexed { surf, index })
    }
}

impl<S: CellSurface + ?Sized> CellSurface for Indexed<'_, S> {
    fn faces(&self) -> usize {
        self.surf.faces()
    }
    fn subfaces(&self, f: usize) -> usize {
        self.surf.subfaces(f)
    }
    fn root(&self, face: u32, sub: u32) -> Cell {
        self.surf.root(face, sub)
    }
    fn split(&self, c: &Cell, out: &mut [Cell; 4]) {
        self.surf.split(c, out)
    }
    fn eval(&self, face: u32, sub: u32, u: f64, v: f64) -> Result<Eval, Error> {
        self.surf.eval(face, sub, u, v)
    }
    fn at_floor(&self, c: &Cell) -> bool {
        self.surf.at_floor(c)
    }
    fn check_solid(&self) -> Result<(), Error> {
        self.surf.check_solid()
    }
    fn magnitude(&self) -> f64 {
        self.index.magnitude
    }
    fn index(&self) -> Option<&SlotIndex<'_>> {
        Some(self.index)
    }
}

/// What a walk is asked while the slots are enumerated.
pub(crate) enum Visit {
    /// May the query reach the box `[lo, hi]`? `Some(key)` (smaller is
    /// nearer) or `None` (nothing of the query is in it). Asked only of
    /// boxes with `lo <= hi` in every coordinate (infinite ones included):
    /// empty boxes (the tree's padding) and boxes with a NaN hold nothing
    /// and are skipped without asking ([`ask`]).
    Box(DVec3, DVec3),
    /// Walk slot `(face, sub)`.
    Slot(u32, u32),
}

/// `f`'s answer for the box `[lo, hi]`, `None` without asking for an
/// empty box or one with a NaN ([`Visit::Box`]).
fn ask(
    f: &mut impl FnMut(Visit) -> Result<Option<f64>, Error>,
    (lo, hi): (DVec3, DVec3),
) -> Result<Option<f64>, Error> {
    if lo.cmple(hi).all() {
        f(Visit::Box(lo, hi))
    } else {
        Ok(None)
    }
}

/// Runs `f` on the slots in slot order: every slot without an index, the
/// slots whose box passes with one.
pub(crate) fn in_order<S: CellSurface + ?Sized>(
    surf: &S,
    f: &mut impl FnMut(Visit) -> Result<Option<f64>, Error>,
) -> Result<(), Error> {
    match surf.index() {
        None => {
            for face in 0..surf.faces() {
                for sub in 0..surf.subfaces(face) {
                    f(Visit::Slot(face as u32, sub as u32))?;
                }
            }
        }
        Some(ix) => {
            for k in 0..ix.slots {
                let (lo, hi, face, sub) = ix.slot_box(k);
                if ask(f, (lo, hi))?.is_some() {
                    f(Visit::Slot(face, sub))?;
                }
            }
        }
    }
    Ok(())
}

/// Deepest tree walk: the leaves are at depth `log2 P <= 32`, and each
/// level leaves at most one sibling pending.
const TREE_STACK: usize = 70;

/// Runs `f` on the slots nearest box first (keys asked again when a node
/// is taken, so a tightened query prunes what was pending); without an
/// index, every slot in slot order.
pub(crate) fn nearest<S: CellSurface + ?Sized>(
    surf: &S,
    f: &mut impl FnMut(Visit) -> Result<Option<f64>, Error>,
) -> Result<(), Error> {
    let Some(ix) = surf.index() else {
        return in_order(surf, f);
    };
    let bx = |k: usize| {
        let t = ix.tree(k);
        (DVec3::from_array(t.lo), DVec3::from_array(t.hi))
    };
    let mut stack = [0usize; TREE_STACK];
    let mut len = 0;
    stack[len] = 1;
    len += 1;
    while len > 0 {
        len -= 1;
        let k = stack[len];
        if ask(f, bx(k))?.is_none() {
            continue;
        }
        if k >= ix.leaves {
            let slot = ix.tree(k).a;
            if slot != u32::MAX {
                let (_, _, face, sub) = ix.slot_box(slot as usize);
                f(Visit::Slot(face, sub))?;
            }
            continue;
        }
        let (l, r) = (ask(f, bx(2 * k))?, ask(f, bx(2 * k + 1))?);
        // Farther first, so that the nearer is taken next.
        let order = match (l, r) {
            (Some(a), Some(b)) if a <= b => [Some(2 * k + 1), Some(2 * k)],
            (Some(_), Some(_)) => [Some(2 * k), Some(2 * k + 1)],
            (Some(_), None) => [None, Some(2 * k)],
            (None, Some(_)) => [None, Some(2 * k + 1)],
            (None, None) => [None, None],
        };
        for c in order.into_iter().flatten() {
            debug_assert!(len < TREE_STACK);
            stack[len] = c;
            len += 1;
        }
    }
    Ok(())
}

/// Distance from `p` to the box `[lo, hi]` (0 inside).
pub(crate) fn box_distance(p: DVec3, lo: DVec3, hi: DVec3) -> f64 {
    let d = (lo - p).max(p - hi).max(DVec3::ZERO);
    d.length()
}
