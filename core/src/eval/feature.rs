//! Exact evaluation of meshes with boundaries, creases, corners, holes and
//! non-manifold parts ([`FeatureEvaluator`]), by local refinement until the
//! query point lies in a bicubic piece \[OSD\].
//!
//! The parameterisation is the one of [`crate::Evaluator`]: a quad face has
//! one sub-face with `(0,0)` at its first corner, `(1,0)` at the second; an
//! `N`-gon has `N` sub-faces, sub-face `k` being its level-1 child at corner
//! `k`. On a closed smooth mesh both evaluators give the same surface.
//!
//! Cost: a point in a cached piece (see [`FeatureEvaluator`]: a quadtree
//! per irregular level-1 face, [`FeatureCache::depth`] levels deep, whose
//! pieces along straight semi-sharp creases are crease strips) is a walk
//! down the tree (one load per level) and one bicubic or eigen-kernel
//! evaluation; a point closer to an irregular corner than the tree reaches
//! costs one gather of the patch neighbourhood plus one local refinement
//! step (linear in the patch size) per halving of the distance to the
//! nearest irregular corner or semi-sharp edge (`log2(1/d)` steps; bounded
//! by 1,100 for any `f64` parameter). At an
//! irregular corner itself the position is the exact limit (eigenvector of
//! the corner's one-ring matrix); `du` and `dv` there are unit vectors along
//! the two parameter lines' tangents (chords at parameter distance 2^-40;
//! their lengths carry no meaning), second derivatives zero.
//!
//! Layer 5 (with the rest of `eval/`): imports `math` and `mesh`.

pub(super) use super::feature_pack::WIDE;
use super::feature_pack::{block_hint, hinted_window, pack, put, Kids};
use crate::eigen::TableSet;
use crate::error::Error;
use crate::eval::{rot_back, rot_param, Query};
use crate::math::{bspline, simd, Eval};
use crate::mem::arena::{Arena, Layout};
use crate::mesh::features::FeatureMesh;
use crate::mesh::local::LocalPatch;
use crate::mesh::sharpness::FeatureOptions;
use crate::mesh::strip::{across_is_v, crease_at_zero, CreaseStrip, MAX_PIECES};

/// Most local refinement steps of one evaluation: every halving of the
/// distance to an irregular corner is one step, and an `f64` in `(0, 1]`
/// halves at most 1,075 times before it is zero.
pub const MAX_STEPS: usize = 1100;

/// Evaluates a [`FeatureMesh`]. [`FeatureEvaluator::build`] finds, once,
/// every level-1 patch that is already a B-spline (most of a typical mesh)
/// and splits the others into a quadtree that follows every irregular
/// piece (next to a special vertex, or along an edge still semi-sharp)
/// down to [`FeatureCache::depth`] levels below the level-1 face: the
/// B-spline pieces met on the way keep their 16 control points in caller
/// memory (smooth extraordinary pieces from the grandchildren on as eigen
/// projections). A piece along a straight crease of one semi-sharp value
/// between regular vertices is not split: it is a crease strip
/// ([`crate::mesh::strip`]), the `K + 1` bicubic pieces across the crease
/// that its value takes `K` levels to decay through (cut at the tree's
/// depth), found by the distance to the crease instead of a walk. A query walks the tree (one load and one parameter
/// doubling per level) to the piece that contains it and costs one bicubic
/// (or eigen-kernel) evaluation; only points closer than `2^-depth` of a
/// level-1 face to an irregular corner (or on a semi-sharp edge that has
/// not decayed by then) refine locally at each query.
///
/// Memory: the B-spline quadrants of a split piece share the 5 x 5 control
/// grid of the four (a quadrant is a 4 x 4 window into it, 24 bytes per
/// point), when their common points are equal bit for bit, as they are
/// when refined from one patch (else each keeps its own 16). Next to an
/// irregular corner each level of the tree holds the three B-spline
/// quadrants around the corner's piece, `25 x 24` bytes plus 32 bytes of
/// node group (four entries and where their groups' windows lie), so about
/// 0.6 KiB per level and irregular level-2 piece (5.5 KiB at the default
/// depth 10); a crease strip of `K + 1` pieces takes `24 + 384 (K + 1)`
/// bytes (2.3 KiB for a crease of sharpness 6: on catmark_car 7.9 MB in
/// all, against 25.8 MB when such pieces were split); along a semi-sharp
/// edge where the strip's conditions fail (its ends, irregular vertices,
/// other sharp edges near it) the irregular pieces double per level for
/// about `s` levels. [`FeatureEvaluator::required_bytes_with`] is exact.
#[derive(Clone, Copy)]
pub struct FeatureEvaluator<'m, 'a> {
    pub(super) mesh: &'m FeatureMesh<'a>,
    /// Standard Catmull-Clark eigen tables: smooth extraordinary patches
    /// (one smooth corner of valence != 4, three regular smooth corners)
    /// are evaluated with the eigen kernel instead of local refinement.
    tables: Option<&'m TableSet>,
    /// Per level-1 face: its cached piece (see [`STAM`]), or 0.
    pub(super) grid_of: &'m [u32],
    /// Per level-1 face that is not a B-spline: index + 1 of the node
    /// group of its children in `nodes`, or 0.
    pub(super) tree_of: &'m [u32],
    /// Node groups of [`GROUP`] values, one per split piece: 4 entries
    /// (quadrant order), each a cached piece (see [`STAM`]), [`NODE`] `|
    /// (group + 1)` of a piece split further, or 0 (refined at each query);
    /// then per entry that leads to a group, where that group's B-spline
    /// windows lie ([`block_hint`]), so a query asks for its window's cache
    /// lines one level early. The groups of one tree lie together, breadth
    /// first ([`breadth_first`]), and a query asks for the first ten of
    /// them at once: a walk waits for about two misses (the tree's upper
    /// levels, then the window) instead of one per level and one for the
    /// window.
    pub(super) nodes: &'m [u32],
    /// The control points of the cached B-spline pieces, x y z each. A
    /// piece is a 4 x 4 window into them (see [`WIDE`]): the B-spline
    /// children of one split piece share one block of the refined grid (5
    /// x 5 points for four children instead of 4 x 16), whenever their
    /// shared points are equal bit for bit (checked at build). Stored
    /// depth by depth (level-1 faces first): the larger pieces, which
    /// uniform points meet most, lie together in fewer pages (on car, 41 %
    /// fewer simulated second-level TLB misses per near-feature point).
    pub(super) grids: &'m [f64],
    /// Cached B-spline pieces (windows into `grids`).
    pieces: usize,
    /// Per cached eigen patch `2 + 3 (2n + 8)` values: the corner `r` of
    /// the extraordinary vertex, its valence `n`, then the eigen
    /// projection (a patch's code holds the index of its first value).
    /// Per cached crease strip ([`crate::mesh::strip`]) `3 + 48 K`
    /// values: [`STRIP`] + its side, its number of stored pieces `K`,
    /// whether they are all of them (1; else 0: the strip was cut at the
    /// tree's depth, and points nearer the crease than its last piece
    /// refine locally), then their grids.
    stams: &'m [f64],
    /// Cached eigen patches.
    eigen: usize,
    /// Cached crease strips.
    strips: usize,
    /// Depth of the cache tree (see [`FeatureCache`]).
    depth: u32,
}

/// How deep [`FeatureEvaluator::build_with`] caches.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FeatureCache {
    /// Deepest cached level below a level-1 face (its children are depth
    /// 1); at most [`MAX_CACHE_DEPTH`], larger values count as that.
    /// Default 10: a point closer than `2^-10` (of the level-1 face) to an
    /// irregular corner refines locally, about one uniform point in `4^8`
    /// of an irregular level-2 piece. Memory near irregular corners grows
    /// by about 0.6 KiB per level and irregular level-2 piece; along
    /// semi-sharp edges the tree (or crease strip) is complete after about
    /// the edge's sharpness levels, so deeper trees cost little more there
    /// (see BENCHMARKS.md: catmark_car 5.2 MB at depth 2, 7.8 MB from 5
    /// on, where its sharpness-6 creases' strips are complete). 2 caches
    /// what the evaluator cached before the tree (children and
    /// grandchildren only; the least memory).
    pub depth: u32,
    /// Most split pieces (node groups) per level-1 face. Default 64. Next
    /// to an irregular corner a tree needs one per level; along an edge of
    /// semi-sharpness `s` the split pieces double per level for about `s`
    /// levels, and this budget bounds what such an edge costs: at most
    /// `nodes_per_face x (32 + 4 x 384)` bytes per level-1 face (99 KiB at
    /// the default; about `nodes_per_face x (32 + 600)`, 40 KiB, when the
    /// quadrants of each split piece share their 5 x 5 grid). Pieces
    /// beyond the budget are refined at each query.
    pub nodes_per_face: u32,
}

impl Default for FeatureCache {
    fn default() -> Self {
        FeatureCache {
            depth: 10,
            nodes_per_face: 64,
        }
    }
}

/// Deepest cache tree [`FeatureCache::depth`] allows.
pub const MAX_CACHE_DEPTH: u32 = 16;

/// What a [`FeatureEvaluator`] cached at build
/// ([`FeatureEvaluator::cache_counts`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CacheCounts {
    /// Cached bicubic B-spline pieces (whole level-1 faces and the cache
    /// tree's pieces).
    pub grids: usize,
    /// Cached eigen projections of smooth extraordinary patches.
    pub eigen_patches: usize,
    /// Cached pieces of straight semi-sharp creases (each a row of
    /// bicubic pieces across the crease, [`crate::mesh::strip`]).
    pub crease_strips: usize,
    /// Level-1 faces that are not one B-spline piece (split into a tree).
    pub split_faces: usize,
    /// Split pieces of all trees (node groups of four quadrants).
    pub nodes: usize,
    /// All level-1 faces.
    pub level1_faces: usize,
}

/// A cached piece is stored as the code of its B-spline grid (see
/// [`WIDE`]), or `STAM | (index + 1)` of the first value of its eigen
/// patch in `stams`.
pub(super) const STAM: u32 = 1 << 31;

/// `u32`s per node group in `nodes`: the four entries (quadrant order),
/// then per entry that leads to a group, that group's [`block_hint`] (else
/// 0).
pub(super) const GROUP: usize = 8;

/// A tree entry `NODE | (group + 1)`: the piece is split further, its
/// quadrants are node group `group`.
pub(super) const NODE: u32 = 1 << 30;

/// Set (with [`STAM`]) in the code of a crease strip cut at the tree's
/// depth, the only cached piece that does not answer every point of its
/// square (see [`FeatureEvaluator::covers`]).
const CUT: u32 = NODE;

/// A tree entry (see [`FeatureEvaluator`]'s `nodes`).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub(super) enum Entry {
    /// Not cached: refined at each query.
    Local,
    /// A cached piece (see [`STAM`]).
    Piece(u32),
    /// Split further: the index of the quadrants' node group.
    Node(usize),
}

/// The entry code `c` decoded.
#[inline(always)]
pub(super) fn entry(c: u32) -> Entry {
    if c == 0 {
        Entry::Local
    } else if c & (STAM | NODE) == NODE {
        Entry::Node((c & !NODE) as usize - 1)
    } else {
        Entry::Piece(c)
    }
}

/// Values a cached eigen patch of valence `n` takes (corner, valence,
/// projection).
const fn stam_values(n: usize) -> usize {
    2 + 3 * (2 * n + 8)
}

/// Values a cached crease strip of `count` pieces takes (`STRIP + side`,
/// `count`, complete or cut, then each piece's 16 control points, x y z
/// each).
const fn strip_values(count: usize) -> usize {
    3 + 48 * count
}

/// The first value of a cached crease strip is `STRIP + side` (an eigen
/// patch's is its corner, 0 to 3).
const STRIP: f64 = 4.0;

/// One cached piece of a level-1 face (a temporary of the build, on the
/// stack; the size difference of the variants does not matter there).
#[derive(Clone, Copy)]
#[allow(clippy::large_enum_variant)]
enum Piece {
    /// A bicubic B-spline (16 control points).
    Grid([glam::DVec3; 16]),
    /// A smooth extraordinary patch: corner, valence, eigen projection.
    Stam(u8, usize, [f64; 3 * crate::config::MAX_K]),
    /// A piece of a straight semi-sharp crease ([`crate::mesh::strip`]),
    /// the number of its bicubic pieces kept (made when stored) and
    /// whether that is all of them.
    Strip(CreaseStrip, usize, bool),
}

impl Piece {
    /// The piece of `patch`, if it is a B-spline, a piece of a straight
    /// semi-sharp crease (its pieces no smaller than `2^-levels` across,
    /// as the tree's would be: where the value takes more levels to decay,
    /// the strip is cut there) or (with tables) a smooth extraordinary
    /// patch.
    fn of<const NF: usize, const NV: usize, const NE: usize>(
        patch: &LocalPatch<NF, NV, NE>,
        opts: &FeatureOptions,
        tables: Option<&TableSet>,
        levels: u32,
    ) -> Option<Piece> {
        if let Some(g) = patch.regular_grid() {
            return Some(Piece::Grid(g));
        }
        if let Some(strip) = patch.crease_strip() {
            // K + 1 pieces, the last one 2^-K wide.
            match strip.steps(opts.creasing, &mut [0.0; MAX_PIECES]) {
                Some(k) if k as u32 <= levels => return Some(Piece::Strip(strip, k + 1, true)),
                Some(_) if levels > 0 => return Some(Piece::Strip(strip, levels as usize, false)),
                _ => {}
            }
        }
        let (r, n, pts) = patch.stam_patch(crate::config::MAX_VALENCE)?;
        let table = tables?.get(n)?;
        let mut ghat = [0.0; 3 * crate::config::MAX_K];
        table.project(&pts[..2 * n + 8], &mut ghat);
        Some(Piece::Stam(r as u8, n, ghat))
    }
}

impl core::fmt::Debug for FeatureEvaluator<'_, '_> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("FeatureEvaluator")
            .field("faces", &self.mesh.num_faces())
            .field("eigen_tables", &self.tables.is_some())
            .field("cached_grids", &self.pieces)
            .field("cached_eigen_patches", &self.eigen)
            .finish()
    }
}

/// What the build finds in a level-1 face, in a fixed order (the size
/// query and the build replay it).
enum Found<'p> {
    /// The face is one piece.
    Root(&'p Piece),
    /// The face is split: node group `group` holds its children.
    Tree(usize),
    /// Quadrant `q` of node group `group` is this eigen piece.
    Piece(usize, usize, &'p Piece),
    /// The B-spline quadrants of node group `group` (see [`pack`]), `depth`
    /// levels below the level-1 face.
    Block {
        group: usize,
        depth: usize,
        kids: &'p Kids,
    },
    /// Quadrant `q` of node group `group` is split into node group `child`.
    Node(usize, usize, usize),
}

/// A split piece whose quadrants are still to be looked at: the quadrant
/// path from the level-1 face (2 bits per level, first step lowest), its
/// depth and the node group of its quadrants.
#[derive(Clone, Copy, Default)]
struct Pending {
    path: u32,
    depth: u32,
    group: usize,
}

/// Most pending pieces of one tree: at most three siblings wait per level.
const MAX_PENDING: usize = 3 * MAX_CACHE_DEPTH as usize + 1;

/// Levels of the cache tree a layout distinguishes: the level-1 face
/// (depth 0) down to [`MAX_CACHE_DEPTH`].
const LEVELS: usize = MAX_CACHE_DEPTH as usize + 1;

/// The build's three local patches (reused for every face) and its node
/// group counter (the node groups of one tree are numbered together, so a
/// walk stays within a few cache lines).
struct PlanScratch {
    bufs: [LocalPatch<64, 196, 256>; 3],
    groups: usize,
}

/// Patch `i` to read and patch `j` to write of `bufs`.
fn pair<T>(bufs: &mut [T; 3], i: usize, j: usize) -> (&T, &mut T) {
    debug_assert!(i != j);
    if i < j {
        let (a, b) = bufs.split_at_mut(j);
        (&a[i], &mut b[0])
    } else {
        let (a, b) = bufs.split_at_mut(i);
        (&b[0], &mut a[j])
    }
}

impl PlanScratch {
    fn new() -> Self {
        PlanScratch {
            bufs: [
                LocalPatch::empty(),
                LocalPatch::empty(),
                LocalPatch::empty(),
            ],
            groups: 0,
        }
    }

    /// The patch of the piece at `path`, `depth` levels below level-1 face
    /// `f`, into a buffer (its index), refined from a fresh gather.
    fn derive(&mut self, mesh: &FeatureMesh, f: usize, path: u32, depth: u32) -> Option<usize> {
        let opts = mesh.options;
        self.bufs[0].gather_into(mesh, f, 0).ok()?;
        let mut cur = 0;
        for level in 0..depth {
            let q = ((path >> (2 * level)) & 3) as usize;
            let (src, dst) = pair(&mut self.bufs, cur, 1 - cur);
            src.child_into(&opts, q, dst).ok()?;
            cur = 1 - cur;
        }
        Some(cur)
    }

    /// Calls `found` with what level-1 face `f` caches, down to `depth`
    /// levels (see [`Found`]); node groups are numbered on from
    /// `self.groups`. A B-spline piece is cached whole; an irregular one is
    /// split, except from the grandchildren on, where a smooth
    /// extraordinary piece is cached as an eigen projection (B-spline
    /// quarters are cheaper to evaluate than the kernel, so the kernel
    /// takes only the quarter of a quarter that touches the vertex).
    fn plan(
        &mut self,
        mesh: &FeatureMesh,
        f: usize,
        tables: Option<&TableSet>,
        cache: FeatureCache,
        mut found: impl FnMut(Found),
    ) {
        let depth = cache.depth.min(MAX_CACHE_DEPTH);
        let opts = mesh.options;
        if self.bufs[0].gather_into(mesh, f, 0).is_err() {
            return;
        }
        if let Some(g) = self.bufs[0].regular_grid() {
            found(Found::Root(&Piece::Grid(g)));
            return;
        }
        if depth == 0 || cache.nodes_per_face == 0 {
            return;
        }
        // (Eigen patches from the grandchildren on, see below.)
        if let Some(strip @ Piece::Strip(..)) = Piece::of(&self.bufs[0], &opts, None, depth) {
            found(Found::Root(&strip));
            return;
        }
        let root = self.groups;
        self.groups += 1;
        found(Found::Tree(root));
        let mut pending = [Pending::default(); MAX_PENDING];
        let mut np = 1;
        pending[0] = Pending {
            path: 0,
            depth: 0,
            group: root,
        };
        // Buffer 0 holds the level-1 patch for the first pending piece.
        let mut fresh = true;
        while np > 0 {
            np -= 1;
            let mut p = pending[np];
            let mut cur = if fresh {
                0
            } else {
                match self.derive(mesh, f, p.path, p.depth) {
                    Some(c) => c,
                    None => continue,
                }
            };
            fresh = false;
            // Walk down the first irregular quadrant of each piece; its
            // irregular siblings wait in `pending`.
            loop {
                let d = p.depth + 1;
                // Children go to `child`; the one walked into stays in the
                // buffer it was made in (then the third buffer takes the rest).
                let mut child = (cur + 1) % 3;
                let mut next = None;
                let mut kids: Kids = [None; 4];
                for q in 0..4 {
                    let (src, dst) = pair(&mut self.bufs, cur, child);
                    if src.child_into(&opts, q, dst).is_err() {
                        continue;
                    }
                    let dst = &self.bufs[child];
                    let tables = if d >= 2 { tables } else { None };
                    let piece = Piece::of(dst, &opts, tables, depth - d);
                    match piece {
                        Some(Piece::Grid(g)) => {
                            kids[q] = Some(g);
                            continue;
                        }
                        Some(piece) => {
                            found(Found::Piece(p.group, q, &piece));
                            continue;
                        }
                        None => {}
                    }
                    if d >= depth || self.groups - root >= cache.nodes_per_face as usize {
                        continue;
                    }
                    let g = self.groups;
                    self.groups += 1;
                    found(Found::Node(p.group, q, g));
                    let at = Pending {
                        path: p.path | (q as u32) << (2 * p.depth),
                        depth: d,
                        group: g,
                    };
                    if next.is_none() {
                        next = Some((at, child));
                        child = 3 - cur - child;
                    } else if np < MAX_PENDING {
                        pending[np] = at;
                        np += 1;
                    }
                }
                found(Found::Block {
                    group: p.group,
                    depth: d as usize,
                    kids: &kids,
                });
                match next {
                    Some((at, kept)) => {
                        p = at;
                        cur = kept;
                    }
                    None => break,
                }
            }
        }
    }
}

/// What a cache holds (counted before the build).
#[derive(Clone, Copy, Default)]
struct Sizes {
    faces: usize,
    groups: usize,
    /// Control points of the B-spline pieces.
    points: usize,
    /// Control points per depth of their pieces: stored depth by depth,
    /// so the pieces a uniform point most likely meets (the larger ones)
    /// lie together.
    points_at: [usize; LEVELS],
    /// B-spline pieces.
    pieces: usize,
    /// Values of the eigen patches.
    stams: usize,
    /// Eigen patches.
    eigen: usize,
    /// Crease strips.
    strips: usize,
}

/// Where each depth's run starts when runs of `counts` points are stored
/// depth by depth.
fn starts(counts: &[usize; LEVELS]) -> [usize; LEVELS] {
    let (mut at, mut sum) = ([0; LEVELS], 0);
    for (a, c) in at.iter_mut().zip(counts) {
        *a = sum;
        sum += c;
    }
    at
}

impl Sizes {
    /// Bytes of the caller block.
    fn layout(&self) -> usize {
        let mut l = Layout::default();
        l.u32s(self.faces);
        l.u32s(self.faces);
        l.u32s(GROUP * self.groups);
        l.f64s(3 * self.points);
        l.f64s(self.stams);
        l.bytes()
    }
}

/// Renumbers the node groups of one tree (`nodes` holds them, the first
/// being the root, group `first` of the whole array) breadth first: the
/// root, its children, their children... (each parent's in quadrant
/// order), so the groups every walk through the tree reads first share
/// cache lines. Uses the hint slots of the groups as scratch (they are
/// zero before and after).
fn breadth_first(nodes: &mut [u32], first: usize) {
    let k = nodes.len() / GROUP;
    if k == 0 {
        return;
    }
    let child = |nodes: &[u32], g: usize, q: usize| match entry(nodes[GROUP * g + q]) {
        Entry::Node(c) => Some(c - first),
        _ => None,
    };
    // Slot 4 of record `i`: the old group at new position `i`.
    const OLD: usize = 4;
    // Slot 5 of group `g`: its new position.
    const NEW: usize = 5;
    nodes[OLD] = 0;
    let mut len = 1;
    for i in 0..k {
        let g = nodes[GROUP * i + OLD] as usize;
        nodes[GROUP * g + NEW] = i as u32;
        for q in 0..4 {
            if let Some(c) = child(nodes, g, q) {
                nodes[GROUP * len + OLD] = c as u32;
                len += 1;
            }
        }
    }
    debug_assert_eq!(len, k);
    for g in 0..k {
        for q in 0..4 {
            if let Some(c) = child(nodes, g, q) {
                nodes[GROUP * g + q] = NODE | (first as u32 + nodes[GROUP * c + NEW] + 1);
            }
        }
    }
    // Each swap puts one record at its new position.
    for i in 0..k {
        loop {
            let j = nodes[GROUP * i + NEW] as usize;
            if j == i {
                break;
            }
            for s in 0..GROUP {
                nodes.swap(GROUP * i + s, GROUP * j + s);
            }
        }
    }
    for r in nodes.chunks_exact_mut(GROUP) {
        r[4..].fill(0);
    }
}

/// The quadrant of `(s, t)` (ties to the lower one) and the parameters in it.
#[inline]
fn quadrant(s: f64, t: f64) -> (usize, f64, f64) {
    let (cx, cy) = (s > 0.5, t > 0.5);
    let q = match (cx, cy) {
        (false, false) => 0,
        (true, false) => 1,
        (true, true) => 2,
        (false, true) => 3,
    };
    let s = 2.0 * s - if cx { 1.0 } else { 0.0 };
    let t = 2.0 * t - if cy { 1.0 } else { 0.0 };
    (q, s, t)
}

impl<'m, 'a> FeatureEvaluator<'m, 'a> {
    /// Exact bytes [`FeatureEvaluator::build`] uses for `mesh` with these
    /// `tables` (the default [`FeatureCache`]). It finds the cached pieces,
    /// which costs one neighbourhood gather per level-1 face and four local
    /// refinement steps per split piece (the build does the same work
    /// again).
    pub fn required_bytes(mesh: &FeatureMesh, tables: Option<&TableSet>) -> usize {
        Self::required_bytes_with(mesh, tables, FeatureCache::default())
    }

    /// Exact bytes [`FeatureEvaluator::build_with`] uses for `mesh` with
    /// these `tables` and `cache`.
    pub fn required_bytes_with(
        mesh: &FeatureMesh,
        tables: Option<&TableSet>,
        cache: FeatureCache,
    ) -> usize {
        Self::count(mesh, tables, cache).layout()
    }

    fn count(mesh: &FeatureMesh, tables: Option<&TableSet>, cache: FeatureCache) -> Sizes {
        let mut z = Sizes {
            faces: mesh.level1.num_faces(),
            ..Sizes::default()
        };
        let mut scratch = PlanScratch::new();
        for f in 0..z.faces {
            scratch.plan(mesh, f, tables, cache, |found| match found {
                Found::Root(p) | Found::Piece(_, _, p) => match p {
                    Piece::Grid(_) => {
                        // (Counted with the level-1 faces' pieces.)
                        z.points += 16;
                        z.points_at[0] += 16;
                        z.pieces += 1;
                    }
                    Piece::Stam(_, n, _) => {
                        z.stams += stam_values(*n);
                        z.eigen += 1;
                    }
                    Piece::Strip(_, count, _) => {
                        z.stams += strip_values(*count);
                        z.strips += 1;
                    }
                },
                Found::Block { depth, kids, .. } => pack(kids, |b| {
                    z.points += b.len;
                    z.points_at[depth] += b.len;
                    z.pieces += b.window.iter().flatten().count();
                }),
                Found::Tree(_) | Found::Node(..) => z.groups += 1,
            });
        }
        z
    }

    /// The evaluator of `mesh`, with the cached pieces in `mem` (see
    /// [`FeatureEvaluator::required_bytes`], with the same `tables`), the
    /// cache tree of the default depth ([`FeatureCache`]). With
    /// `tables` (built with [`crate::mesh::Weights::STANDARD`], else an error),
    /// smooth extraordinary patches are evaluated with the eigen kernel
    /// (\[Stam98\]): cached as eigen projections in the tree, and in one
    /// step when met deeper; without, they are refined like every other
    /// irregular piece (same surface, slower).
    pub fn build(
        mesh: &'m FeatureMesh<'a>,
        tables: Option<&'m TableSet>,
        mem: &'m mut [u64],
    ) -> Result<Self, Error> {
        Self::build_with(mesh, tables, FeatureCache::default(), mem)
    }

    /// [`FeatureEvaluator::build`] with the cache tree `cache` (memory:
    /// [`FeatureEvaluator::required_bytes_with`] with the same arguments).
    pub fn build_with(
        mesh: &'m FeatureMesh<'a>,
        tables: Option<&'m TableSet>,
        cache: FeatureCache,
        mem: &'m mut [u64],
    ) -> Result<Self, Error> {
        if tables.is_some_and(|t| *t.weights() != crate::mesh::Weights::STANDARD) {
            return Err(Error::InvalidArgument(
                "feature evaluation needs eigen tables of the standard Catmull-Clark rule",
            ));
        }
        let depth = cache.depth.min(MAX_CACHE_DEPTH);
        let z = Self::count(mesh, tables, cache);
        let need = z.layout();
        if crate::mem::bytes_of(mem.len()) < need {
            return Err(Error::BufferTooSmall { required: need });
        }
        if z.points >= WIDE as usize - 1 || z.stams >= NODE as usize || z.groups >= NODE as usize {
            return Err(Error::InvalidArgument(
                "feature evaluator: more than 2^29 cached points or 2^30 cached values",
            ));
        }
        let n = z.faces;
        let mut arena = Arena::new(mem);
        let grid_of = arena.u32s(n);
        let tree_of = arena.u32s(n);
        let nodes = arena.u32s(GROUP * z.groups);
        let grids = arena.f64s(3 * z.points);
        let stams = arena.f64s(z.stams);
        grid_of.fill(0);
        tree_of.fill(0);
        nodes.fill(0);
        // Next point of each depth's run in `grids`, next stam value.
        let (mut kp, mut ks) = (starts(&z.points_at), 0usize);
        // An eigen patch or a crease strip in `stams`: its code.
        let creasing = mesh.options.creasing;
        let mut record = |piece: &Piece, stams: &mut [f64]| {
            let len = match piece {
                Piece::Stam(r, valence, ghat) => {
                    let len = stam_values(*valence);
                    let b = &mut stams[ks..ks + len];
                    b[0] = *r as f64;
                    b[1] = *valence as f64;
                    b[2..].copy_from_slice(&ghat[..len - 2]);
                    len
                }
                Piece::Strip(strip, count, complete) => {
                    let len = strip_values(*count);
                    let b = &mut stams[ks..ks + len];
                    b[0] = STRIP + strip.side as f64;
                    b[1] = *count as f64;
                    b[2] = if *complete { 1.0 } else { 0.0 };
                    let mut at = 3;
                    strip.pieces(creasing, *count, |grid| {
                        for p in grid {
                            b[at..at + 3].copy_from_slice(&[p.x, p.y, p.z]);
                            at += 3;
                        }
                    });
                    debug_assert_eq!(at, len);
                    len
                }
                Piece::Grid(_) => unreachable!("B-spline pieces go to `grids`"),
            };
            ks += len;
            let cut = matches!(piece, Piece::Strip(_, _, false));
            STAM | if cut { CUT } else { 0 } | (ks - len + 1) as u32
        };
        let mut scratch = PlanScratch::new();
        for f in 0..n {
            let root = scratch.groups;
            scratch.plan(mesh, f, tables, cache, |found| match found {
                Found::Root(Piece::Grid(g)) => grid_of[f] = put(g, 4, grids, &mut kp[0])(0),
                Found::Root(piece) => grid_of[f] = record(piece, stams),
                Found::Tree(g) => tree_of[f] = g as u32 + 1,
                Found::Piece(g, q, Piece::Grid(p)) => {
                    nodes[GROUP * g + q] = put(p, 4, grids, &mut kp[0])(0)
                }
                Found::Piece(g, q, piece) => nodes[GROUP * g + q] = record(piece, stams),
                Found::Block { group, depth, kids } => pack(kids, |b| {
                    let code = put(&b.pts[..b.len], b.stride, grids, &mut kp[depth]);
                    for (q, at) in b.window.iter().enumerate() {
                        if let Some(at) = *at {
                            nodes[GROUP * group + q] = code(at);
                        }
                    }
                }),
                Found::Node(g, q, child) => nodes[GROUP * g + q] = NODE | (child as u32 + 1),
            });
            breadth_first(&mut nodes[GROUP * root..GROUP * scratch.groups], root);
        }
        // Beside each entry that leads to a node group, where that group's
        // B-spline windows lie (see `block_hint`).
        for g in 0..z.groups {
            for q in 0..4 {
                if let Entry::Node(child) = entry(nodes[GROUP * g + q]) {
                    let codes = core::array::from_fn(|k| match entry(nodes[GROUP * child + k]) {
                        Entry::Piece(code) if code & STAM == 0 => Some(code),
                        _ => None,
                    });
                    nodes[GROUP * g + 4 + q] = block_hint(codes);
                }
            }
        }
        Ok(FeatureEvaluator {
            mesh,
            tables,
            grid_of,
            tree_of,
            nodes,
            grids,
            pieces: z.pieces,
            stams,
            eigen: z.eigen,
            strips: z.strips,
            depth,
        })
    }

    /// The cached piece `code` (see [`STAM`]) evaluated at `(s, t)`.
    #[inline(always)]
    fn piece(&self, code: u32, s: f64, t: f64, scale: f64, second: bool) -> Result<Eval, Error> {
        if code & STAM == 0 {
            Ok(self.cached(code, s, t, scale, second))
        } else {
            self.eigen_piece(code, s, t, scale, second)
        }
    }

    /// A cached eigen patch (`code` has [`STAM`]) evaluated at `(s, t)`.
    #[inline(never)]
    fn eigen_piece(
        &self,
        code: u32,
        s: f64,
        t: f64,
        scale: f64,
        second: bool,
    ) -> Result<Eval, Error> {
        let k = (code & !(STAM | CUT)) as usize - 1;
        if self.stams[k] >= STRIP {
            return Ok(self.strip_piece(k, s, t, scale, second));
        }
        let (r, n) = (self.stams[k] as u8, self.stams[k + 1] as usize);
        let b = &self.stams[k..k + stam_values(n)];
        let table = self
            .tables
            .and_then(|t| t.get(n))
            .ok_or(Error::MissingTable { valence: n as u32 })?;
        let (u, v) = rot_param(r, s, t);
        let ghat = &b[2..2 + 3 * (2 * n + 8)];
        let mut e = if second {
            table.eval_projected::<true>(ghat, None, u, v)
        } else {
            table.eval_projected::<false>(ghat, None, u, v)
        };
        Ok(rotated(r, &mut e, scale, second))
    }

    /// The header of the crease strip whose values start at `stams[k]`:
    /// its side, its stored pieces and whether they are all of them.
    #[inline]
    fn strip_head(&self, k: usize) -> (usize, usize, bool) {
        let side = (self.stams[k] - STRIP) as usize;
        (side, self.stams[k + 1] as usize, self.stams[k + 2] != 0.0)
    }

    /// Whether the cached piece `code` answers `(s, t)`: every piece does
    /// but a crease strip cut at the tree's depth, at points nearer the
    /// crease than its last piece.
    #[inline(always)]
    fn covers(&self, code: u32, s: f64, t: f64) -> bool {
        if code & (STAM | CUT) != STAM | CUT {
            return true;
        }
        let k = (code & !(STAM | CUT)) as usize - 1;
        let (side, count, _) = self.strip_head(k);
        strip_level(side, s, t).1 <= count
    }

    /// The crease strip whose values start at `stams[k]` (which must cover
    /// `(s, t)`, see [`FeatureEvaluator::covers`]): its side and the piece
    /// that holds `(s, t)`, as the piece's grid, the parameters in it and
    /// the factor by which the piece is narrower across the crease than
    /// the strip. The parameters in the piece are exact (a power-of-two
    /// scaling and a subtraction of nearby values).
    #[inline]
    fn strip_at(&self, k: usize, s: f64, t: f64) -> (usize, [glam::DVec3; 16], f64, f64, f64) {
        let (side, count, complete) = self.strip_head(k);
        let across_v = across_is_v(side);
        let (across, l) = strip_level(side, s, t);
        // Piece l - 1 holds distances [2^-l, 2^-(l-1)); a complete strip's
        // last piece (K + 1 of them) those below 2^-K.
        let piece = if complete && l >= count {
            count - 1
        } else {
            l - 1
        };
        let (level, at) = strip_span(side, piece, count, complete);
        let m = (1u64 << level) as f64;
        let a = across * m - at as f64;
        let first = k + 3 + 48 * piece;
        let pts = window::<4, 48>(self.stams[first..first + 48].try_into().expect("48 values"));
        let (s, t) = if across_v { (s, a) } else { (a, t) };
        (side, pts, s, t, m)
    }

    /// When the cached piece `code` is a crease strip and cell `(i, j)` of
    /// depth `d` of its unit square (`i` along `s`) lies in one of the
    /// strip's pieces: the grid of the square part of that piece (`2^-l`
    /// along the crease by `2^-l` across, the piece split `l` times along
    /// by B-spline subdivision) that holds the cell, and the cell inside
    /// that part's unit square (`[s0, s1, t0, t1]`, a dyadic square,
    /// exact), as every consumer of a cell's grid expects.
    pub(super) fn strip_cell(
        &self,
        code: u32,
        d: u32,
        i: u32,
        j: u32,
    ) -> Option<([glam::DVec3; 16], [f64; 4])> {
        if code & STAM == 0 {
            return None;
        }
        let k = (code & !(STAM | CUT)) as usize - 1;
        if self.stams[k] < STRIP {
            return None;
        }
        let (side, count, complete) = self.strip_head(k);
        let across_v = across_is_v(side);
        let (along, across) = if across_v { (i, j) } else { (j, i) };
        for piece in 0..count {
            let (l, at) = strip_span(side, piece, count, complete);
            if d < l || across >> (d - l) != at {
                continue;
            }
            let mask = (1u32 << (d - l)) - 1;
            let h = 1.0 / (1u64 << (d - l)) as f64;
            let a = [(across & mask) as f64 * h, ((across & mask) + 1) as f64 * h];
            let b = [(along & mask) as f64 * h, ((along & mask) + 1) as f64 * h];
            let first = k + 3 + 48 * piece;
            let mut pts =
                window::<4, 48>(self.stams[first..first + 48].try_into().expect("48 values"));
            // Halve along the crease l times, towards the cell.
            let part = along >> (d - l);
            for step in (0..l).rev() {
                pts = bspline_half(&pts, across_v, part >> step & 1 == 1);
            }
            let rect = if across_v {
                [b[0], b[1], a[0], a[1]]
            } else {
                [a[0], a[1], b[0], b[1]]
            };
            return Some((pts, rect));
        }
        None
    }

    /// A cached crease strip (values from `stams[k]`) evaluated at `(s, t)`.
    fn strip_piece(&self, k: usize, s: f64, t: f64, scale: f64, second: bool) -> Eval {
        let (side, pts, s, t, m) = self.strip_at(k, s, t);
        let across_v = across_is_v(side);
        let mut e = if second {
            bspline::eval_points::<true>(&pts, s, t)
        } else {
            bspline::eval_points::<false>(&pts, s, t)
        };
        // The piece is `m` times narrower across the crease.
        e.duv *= m;
        if across_v {
            e.dv *= m;
            e.dvv *= m * m;
        } else {
            e.du *= m;
            e.duu *= m * m;
        }
        finish(e, scale)
    }

    /// The 16 control points of the cached B-spline piece `code` (see
    /// [`WIDE`]).
    #[inline]
    pub(super) fn grid_points(&self, code: u32) -> [glam::DVec3; 16] {
        let first = 3 * ((code & (WIDE - 1)) as usize - 1);
        // One bounds check; constant offsets in the window.
        if code & WIDE != 0 {
            window::<5, 57>(self.grids[first..first + 57].try_into().expect("57 values"))
        } else {
            window::<4, 48>(self.grids[first..first + 48].try_into().expect("48 values"))
        }
    }

    /// The cached B-spline piece `code` evaluated at `(s, t)`.
    #[inline]
    fn cached(&self, code: u32, s: f64, t: f64, scale: f64, second: bool) -> Eval {
        let pts = self.grid_points(code);
        finish(
            if second {
                bspline::eval_points::<true>(&pts, s, t)
            } else {
                bspline::eval_points::<false>(&pts, s, t)
            },
            scale,
        )
    }

    /// Number of sub-faces of base face `f` (1 for a quad, `N` for an
    /// `N`-gon).
    pub fn num_subfaces(&self, f: usize) -> usize {
        let n = self.mesh.base.face(f).len();
        if n == 4 {
            1
        } else {
            n
        }
    }

    /// Number of base faces.
    pub fn num_faces(&self) -> usize {
        self.mesh.num_faces()
    }

    /// What the build cached: B-spline pieces, eigen patches (smooth
    /// extraordinary corners), level-1 faces split into a tree and the
    /// split pieces of the trees (see [`FeatureEvaluator`]).
    pub fn cache_counts(&self) -> CacheCounts {
        CacheCounts {
            grids: self.pieces,
            eigen_patches: self.eigen,
            crease_strips: self.strips,
            split_faces: self.tree_of.iter().filter(|&&t| t != 0).count(),
            nodes: self.nodes.len() / GROUP,
            level1_faces: self.grid_of.len(),
        }
    }

    /// Depth of the cache tree (see [`FeatureCache`]).
    pub fn cache_depth(&self) -> u32 {
        self.depth
    }

    /// Checks a query without evaluating it: face and sub-face in range,
    /// parameters in `[0, 1]`, face not a hole.
    pub fn check(&self, q: &Query) -> Result<(), Error> {
        q.check_ranges(self.mesh.num_faces(), |f| self.num_subfaces(f))?;
        if self.mesh.hole[self.mesh.child_face(q.face as usize, 0)] != 0 {
            return Err(Error::HoleFace { face: q.face });
        }
        Ok(())
    }

    /// Whether a (valid) query is answered from the cached B-spline pieces
    /// (one bicubic evaluation) rather than by local refinement.
    pub fn is_cached(&self, q: &Query) -> bool {
        self.piece_depth(q).is_some()
    }

    /// How many levels below its level-1 face the cached piece answering a
    /// (valid) query lies: 0 for a level-1 face that is one piece, 1 and 2
    /// for the pieces of levels 2 and 3, deeper for the cache tree's pieces
    /// near special vertices and semi-sharp edges; `None` when the query is
    /// refined locally or invalid.
    pub fn piece_depth(&self, q: &Query) -> Option<u32> {
        if self.check(q).is_err() {
            return None;
        }
        let (face1, s, t) = self.level1(q.face as usize, q.sub as usize, q.u, q.v);
        self.cached_at(face1, s, t)
            .map(|(_, _, _, smaller)| libm::log2(smaller) as u32)
    }

    /// The cached piece of level-1 face `face1` that contains `(s, t)`: its
    /// code (see [`STAM`]), the parameters in it and the factor by which it
    /// is smaller (`2^depth`).
    #[inline(always)]
    fn cached_at(&self, face1: usize, mut s: f64, mut t: f64) -> Option<(u32, f64, f64, f64)> {
        let root = self.grid_of[face1];
        if root != 0 {
            return self.covers(root, s, t).then_some((root, s, t, 1.0));
        }
        let mut group = (self.tree_of[face1] as usize).checked_sub(1)?;
        // The tree's upper levels lie together (breadth first): ask for
        // the root and the next nine groups at once, instead of one miss
        // per level.
        simd::prefetch(
            self.nodes.as_ptr().wrapping_add(GROUP * group),
            10 * 4 * GROUP,
        );
        let mut smaller = 1.0;
        let (mut q, mut s1, mut t1) = quadrant(s, t);
        loop {
            (s, t) = (s1, t1);
            smaller *= 2.0;
            let at = GROUP * group + q;
            match entry(self.nodes[at]) {
                Entry::Piece(code) => {
                    return self.covers(code, s, t).then_some((code, s, t, smaller))
                }
                Entry::Node(g) => {
                    group = g;
                    (q, s1, t1) = quadrant(s, t);
                    // The window the next level most likely answers with:
                    // its lines load while the group's entry does.
                    if let Some(first) = hinted_window(self.nodes[at + 4], q) {
                        // (A window spans at most 3 rows of 5 points and
                        // 4 points: 456 bytes.)
                        simd::prefetch(self.grids.as_ptr().wrapping_add(3 * first), 456);
                    }
                }
                Entry::Local => return None,
            }
        }
    }

    /// Entry `q` of node group `group` of the cache tree.
    #[inline]
    pub(super) fn tree_entry(&self, group: usize, q: usize) -> Entry {
        entry(self.nodes[GROUP * group + q])
    }

    /// Level-1 face of a base query and the parameters there.
    fn level1(&self, f: usize, sub: usize, u: f64, v: f64) -> (usize, f64, f64) {
        let fm = self.mesh;
        if fm.base.face(f).len() == 4 {
            let (k, s, t) = quadrant(u, v);
            (fm.child_face(f, k), s, t)
        } else {
            (fm.child_face(f, sub), u, v)
        }
    }

    /// Position, first derivatives and normal at `(u, v)` of sub-face `sub`
    /// of base face `face`.
    pub fn eval(&self, face: u32, sub: u32, u: f64, v: f64) -> Result<Eval, Error> {
        self.eval_impl(face, sub, u, v, false)
    }

    /// As [`FeatureEvaluator::eval`], plus second derivatives.
    pub fn eval_second(&self, face: u32, sub: u32, u: f64, v: f64) -> Result<Eval, Error> {
        self.eval_impl(face, sub, u, v, true)
    }

    fn eval_impl(&self, face: u32, sub: u32, u: f64, v: f64, second: bool) -> Result<Eval, Error> {
        let fm = self.mesh;
        let f = face as usize;
        self.check(&Query { face, sub, u, v })?;
        // Level-1 face and parameters there.
        let (face1, s, t) = self.level1(f, sub as usize, u, v);
        let scale = if fm.base.face(f).len() == 4 { 2.0 } else { 1.0 };
        if let Some((code, s, t, smaller)) = self.cached_at(face1, s, t) {
            return self.piece(code, s, t, smaller * scale, second);
        }
        // The smallest capacity that holds the neighbourhood: a fresh patch
        // is zeroed memory, a sizeable part of a short descent.
        let at = (s, t, scale);
        let tiny = self.descend::<32, 100, 128>(face1, at, face, sub, (u, v), second);
        let Err(Error::NeighbourhoodTooLarge { .. }) = tiny else {
            return tiny;
        };
        let small = self.descend::<64, 196, 256>(face1, at, face, sub, (u, v), second);
        let Err(Error::NeighbourhoodTooLarge { .. }) = small else {
            return small;
        };
        self.descend::<400, 1204, 1600>(face1, at, face, sub, (u, v), second)
    }

    /// Local refinement of level-1 face `face1` towards `(s, t)` with a
    /// patch of the given capacity (a frame of its own, so the large one
    /// costs stack only when used).
    #[inline(never)]
    #[allow(clippy::too_many_arguments)]
    fn descend<const NF: usize, const NV: usize, const NE: usize>(
        &self,
        face1: usize,
        (mut s, mut t, mut scale): (f64, f64, f64),
        face: u32,
        sub: u32,
        (u, v): (f64, f64),
        second: bool,
    ) -> Result<Eval, Error> {
        let opts = self.mesh.options;
        let too_large = |_| Error::NeighbourhoodTooLarge { face };
        // Two patches, each step refining one into the other.
        let mut first = LocalPatch::<NF, NV, NE>::empty();
        first.gather_into(self.mesh, face1, face)?;
        let mut other = LocalPatch::<NF, NV, NE>::empty();
        let (mut patch, mut next) = (&mut first, &mut other);
        for _ in 0..MAX_STEPS {
            if let Some(g) = patch.regular_grid() {
                let e = if second {
                    bspline::eval_points::<true>(&g, s, t)
                } else {
                    bspline::eval_points::<false>(&g, s, t)
                };
                return Ok(finish(e, scale));
            }
            // Exactly at an irregular corner: the exact limit there, once
            // its semi-sharp values have decayed (until then, refining
            // towards it keeps the point at the same corner).
            let at = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)];
            if let Some(k) = at.iter().position(|&c| c == (s, t)) {
                let c = patch.corners()[k];
                if !patch.corner_is_regular(c) && patch.corner_is_stationary(c) {
                    return self.at_corner(patch.clone(), k, face, sub, u, v);
                }
            }
            if let Some(e) = self.stam::<NF, NV, NE>(patch, s, t, scale, second)? {
                return Ok(e);
            }
            let (q, s1, t1) = quadrant(s, t);
            patch.child_into(&opts, q, next).map_err(too_large)?;
            core::mem::swap(&mut patch, &mut next);
            s = s1;
            t = t1;
            scale *= 2.0;
        }
        Err(Error::InvalidArgument(
            "internal: local refinement did not reach a regular patch",
        ))
    }

    /// The eigen-kernel evaluation of `patch` when it is a smooth
    /// extraordinary patch and tables were given.
    fn stam<const NF: usize, const NV: usize, const NE: usize>(
        &self,
        patch: &LocalPatch<NF, NV, NE>,
        s: f64,
        t: f64,
        scale: f64,
        second: bool,
    ) -> Result<Option<Eval>, Error> {
        let Some(tables) = self.tables else {
            return Ok(None);
        };
        let Some((r, n, pts)) = patch.stam_patch(crate::config::MAX_VALENCE) else {
            return Ok(None);
        };
        let Some(table) = tables.get(n) else {
            return Ok(None);
        };
        let (u, v) = rot_param(r as u8, s, t);
        let mut e = table.eval_patch(&pts[..2 * n + 8], u, v, second)?;
        Ok(Some(rotated(r as u8, &mut e, scale, second)))
    }

    /// The limit at irregular corner `k` of `patch` (the query point), with
    /// unit tangent directions from chords along the two parameter lines.
    fn at_corner<const NF: usize, const NV: usize, const NE: usize>(
        &self,
        mut patch: LocalPatch<NF, NV, NE>,
        k: usize,
        face: u32,
        sub: u32,
        u: f64,
        v: f64,
    ) -> Result<Eval, Error> {
        let opts = self.mesh.options;
        let too_large = |_| Error::NeighbourhoodTooLarge { face };
        // Semi-sharp values decay within about ten steps towards the corner.
        for _ in 0..64 {
            if patch.corner_is_stationary(patch.corners()[k]) {
                break;
            }
            patch = patch.child(&opts, k).map_err(too_large)?;
        }
        let p = patch.corner_limit(&opts, k).map_err(too_large)?;
        // Chords towards increasing / decreasing u and v within the face.
        const H: f64 = 1.0 / (1u64 << 40) as f64;
        let du_sign = if u < 0.5 { 1.0 } else { -1.0 };
        let dv_sign = if v < 0.5 { 1.0 } else { -1.0 };
        let pu = self.eval_impl(face, sub, u + du_sign * H, v, false)?.p;
        let pv = self.eval_impl(face, sub, u, v + dv_sign * H, false)?.p;
        let du = ((pu - p) * du_sign).normalize_or_zero();
        let dv = ((pv - p) * dv_sign).normalize_or_zero();
        Ok(Eval {
            p,
            du,
            dv,
            normal: du.cross(dv).normalize_or_zero(),
            ..Eval::default()
        })
    }
}

/// The 4 x 4 points of a window whose rows are `S` points apart (`N =
/// 3 (3 S + 4)` values from its first point).
#[inline(always)]
fn window<const S: usize, const N: usize>(g: &[f64; N]) -> [glam::DVec3; 16] {
    let mut pts = [glam::DVec3::ZERO; 16];
    for r in 0..4 {
        for c in 0..4 {
            let i = 3 * (r * S + c);
            pts[4 * r + c] = glam::DVec3::new(g[i], g[i + 1], g[i + 2]);
        }
    }
    pts
}

/// The parameter across the crease of a strip on `side` at `(s, t)`, and
/// the level `l` of its distance `x` to the crease: `x` in `[2^-l,
/// 2^-(l-1))` (1 from 1/2 on; `usize::MAX` on the crease). Exact: `1 -
/// across` rounds only above 1/2.
#[inline]
fn strip_level(side: usize, s: f64, t: f64) -> (f64, usize) {
    let across = if across_is_v(side) { t } else { s };
    let x = if crease_at_zero(side) {
        across
    } else {
        1.0 - across
    };
    let l = if x >= 0.5 {
        1
    } else if x > 0.0 {
        (-libm::ilogb(x)) as usize
    } else {
        usize::MAX
    };
    (across, l)
}

/// Where piece `piece` of a crease strip on `side` (`count` pieces stored,
/// all of them if `complete`) lies across the crease: dyadic interval
/// `at` of level `l` of the strip's unit square (piece `k - 1` at
/// distances `[2^-k, 2^-(k-1)]` from the crease, a complete strip's last
/// one at `[0, 2^-K]`), as `(l, at)`.
#[inline]
fn strip_span(side: usize, piece: usize, count: usize, complete: bool) -> (u32, u32) {
    let last = complete && piece + 1 == count;
    let l = if last { piece } else { piece + 1 } as u32;
    let from_zero = if last { 0 } else { 1 };
    if crease_at_zero(side) {
        (l, from_zero)
    } else {
        // Counted from the other end: the mirror interval.
        (l, (1u32 << l) - 1 - from_zero)
    }
}

/// The B-spline grid (row by row, `i` along `u`) of the lower (`upper`
/// false) or upper half of `g`'s unit square along `u` (`along_u`) or `v`:
/// one step of cubic B-spline subdivision per row (or column).
fn bspline_half(g: &[glam::DVec3; 16], along_u: bool, upper: bool) -> [glam::DVec3; 16] {
    let mut out = [glam::DVec3::ZERO; 16];
    for line in 0..4 {
        let at = |k: usize| if along_u { line * 4 + k } else { k * 4 + line };
        let [p0, p1, p2, p3] = [g[at(0)], g[at(1)], g[at(2)], g[at(3)]];
        let e01 = (p0 + p1) * 0.5;
        let v1 = (p0 + p1 * 6.0 + p2) * 0.125;
        let e12 = (p1 + p2) * 0.5;
        let v2 = (p1 + p2 * 6.0 + p3) * 0.125;
        let e23 = (p2 + p3) * 0.5;
        let half = if upper {
            [v1, e12, v2, e23]
        } else {
            [e01, v1, e12, v2]
        };
        for (k, p) in half.into_iter().enumerate() {
            out[at(k)] = p;
        }
    }
    out
}

/// Scales a B-spline evaluation of a level-k patch to the base face's
/// parameters (`scale = 2^k`) and adds the normal.
fn finish(mut e: Eval, scale: f64) -> Eval {
    e.du *= scale;
    e.dv *= scale;
    e.duu *= scale * scale;
    e.duv *= scale * scale;
    e.dvv *= scale * scale;
    e.normal = e.du.cross(e.dv).normalize_or_zero();
    e
}

/// An eigen-kernel evaluation in the corner-`r` frame brought back to the
/// patch's parameters (scaled by `scale`). A rotation of the parameters
/// keeps the orientation, so the kernel's normal (at the vertex itself the
/// limit normal) stands.
fn rotated(r: u8, e: &mut Eval, scale: f64, second: bool) -> Eval {
    let normal = e.normal;
    if second {
        rot_back::<true>(r, e, scale);
    } else {
        rot_back::<false>(r, e, scale);
    }
    e.normal = if normal == glam::DVec3::ZERO {
        e.du.cross(e.dv).normalize_or_zero()
    } else {
        normal
    };
    *e
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use crate::mesh::features::FeatureInput;
    use crate::mesh::sharpness::FeatureOptions;
    use crate::mesh::MeshInput;
    use std::vec;

    /// A cube with a semi-sharp edge (sharpness 4.5) and a sharp corner:
    /// every level-1 face touches a valence-3 vertex, so every one is a
    /// tree (without tables the smooth corners are split too).
    fn with_creased_cube(depth: u32, f: impl FnOnce(&FeatureEvaluator)) {
        let p = [
            0., 0., 0., 1., 0., 0., 1., 1., 0., 0., 1., 0., 0., 0., 1., 1., 0., 1., 1., 1., 1., 0.,
            1., 1.,
        ];
        let idx = [
            0, 3, 2, 1, 4, 5, 6, 7, 0, 1, 5, 4, 1, 2, 6, 5, 2, 3, 7, 6, 3, 0, 4, 7,
        ];
        let mesh = MeshInput {
            positions: &p,
            face_sizes: &[4; 6],
            indices: &idx,
        };
        let tags = FeatureInput {
            crease_vertices: &[0, 1],
            crease_sharpness: &[4.5],
            corner_vertices: &[6],
            corner_sharpness: &[10.0],
            holes: &[],
            options: FeatureOptions::default(),
        };
        let mut mm = vec![0u64; FeatureMesh::required_bytes(&mesh).unwrap() / 8 + 1];
        let fm = FeatureMesh::build(&mesh, &tags, &mut mm).unwrap();
        let cache = FeatureCache {
            depth,
            nodes_per_face: 64,
        };
        let need = FeatureEvaluator::required_bytes_with(&fm, None, cache);
        let mut em = vec![0u64; need / 8];
        f(&FeatureEvaluator::build_with(&fm, None, cache, &mut em).unwrap());
    }

    /// The node groups of every tree lie breadth first (root, its children
    /// in quadrant order, theirs...), and every hint beside an entry that
    /// leads to a group names the first point of each window it claims.
    #[test]
    #[cfg_attr(
        miri,
        ignore = "safe code only; the build refines local patches of 24 trees: minutes under Miri"
    )]
    fn trees_lie_breadth_first_and_hints_name_their_windows() {
        let depth = 6;
        with_creased_cube(depth, |ev| {
            let (mut trees, mut deepest, mut hinted) = (0, 0, 0);
            for &root in ev.tree_of.iter().filter(|&&t| t != 0) {
                trees += 1;
                // Breadth first from the root: the k-th group met is root + k.
                let root = root as usize - 1;
                let (mut queue, mut level) = (vec![root], vec![0]);
                let mut i = 0;
                while i < queue.len() {
                    let g = queue[i];
                    assert_eq!(g, root + i);
                    for q in 0..4 {
                        let hint = ev.nodes[GROUP * g + 4 + q];
                        let Entry::Node(c) = ev.tree_entry(g, q) else {
                            assert_eq!(hint, 0);
                            continue;
                        };
                        queue.push(c);
                        level.push(level[i] + 1);
                        for k in 0..4 {
                            let Some(first) = hinted_window(hint, k) else {
                                continue;
                            };
                            hinted += 1;
                            let Entry::Piece(code) = ev.tree_entry(c, k) else {
                                panic!("hint for a quadrant that is no piece");
                            };
                            assert_eq!(code & STAM, 0);
                            assert_eq!((code & (WIDE - 1)) as usize - 1, first);
                        }
                    }
                    i += 1;
                }
                deepest = deepest.max(*level.last().unwrap());
            }
            assert_eq!(trees, 24);
            assert_eq!(deepest, depth - 1);
            // Not vacuous: the walks below the roots are hinted.
            assert!(hinted >= trees * (depth as usize - 1), "{hinted}");
        });
    }
}
