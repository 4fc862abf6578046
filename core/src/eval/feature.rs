//! Exact evaluation of meshes with boundaries, creases, corners, holes and
//! non-manifold parts ([`FeatureEvaluator`]), by local refinement until the
//! query point lies in a bicubic piece \[OSD\].
//!
//! The parameterisation is the one of [`crate::Evaluator`]: a quad face has
//! one sub-face with `(0,0)` at its first corner, `(1,0)` at the second; an
//! `N`-gon has `N` sub-faces, sub-face `k` being its level-1 child at corner
//! `k`. On a closed smooth mesh both evaluators give the same surface.
//!
//! Cost: a point in a cached piece (see [`FeatureEvaluator`]) is one
//! bicubic or eigen-kernel evaluation; any other point costs one gather of
//! the patch neighbourhood plus one local refinement step (linear in the
//! patch size) per halving of the distance to the nearest irregular corner
//! or semi-sharp edge (`log2(1/d)` steps; bounded by 1,100 for any `f64`
//! parameter). At an
//! irregular corner itself the position is the exact limit (eigenvector of
//! the corner's one-ring matrix); `du` and `dv` there are unit vectors along
//! the two parameter lines' tangents (chords at parameter distance 2^-40;
//! their lengths carry no meaning), second derivatives zero.
//!
//! Layer 5 (with the rest of `eval/`): imports `math` and `mesh`.

use crate::eigen::TableSet;
use crate::error::Error;
use crate::eval::{rot_back, rot_param, Query};
use crate::math::{bspline, Eval};
use crate::mem::arena::{Arena, Layout};
use crate::mesh::features::FeatureMesh;
use crate::mesh::local::LocalPatch;

/// Most local refinement steps of one evaluation: every halving of the
/// distance to an irregular corner is one step, and an `f64` in `(0, 1]`
/// halves at most 1,075 times before it is zero.
pub const MAX_STEPS: usize = 1100;

/// Evaluates a [`FeatureMesh`]. [`FeatureEvaluator::build`] finds, once,
/// every level-1 patch that is already a B-spline (most of a typical mesh)
/// and, for the others, every child (level 2) and grandchild (level 3) that
/// is one, and keeps their 16 control points in caller memory (smooth
/// extraordinary grandchildren as eigen projections). A query that lands in
/// a cached piece costs one bicubic evaluation; only the level-3 pieces
/// that stay irregular (next to a special vertex, about 1/16 of such a
/// level-1 patch, or along an edge whose semi-sharp value exceeds 2)
/// refine locally at each query.
#[derive(Clone, Copy)]
pub struct FeatureEvaluator<'m, 'a> {
    pub(super) mesh: &'m FeatureMesh<'a>,
    /// Standard Catmull-Clark eigen tables: smooth extraordinary patches
    /// (one smooth corner of valence != 4, three regular smooth corners)
    /// are evaluated with the eigen kernel instead of local refinement.
    tables: Option<&'m TableSet>,
    /// Per level-1 face: its cached piece (see [`STAM`]), or 0.
    pub(super) grid_of: &'m [u32],
    /// Per level-1 face that is not a B-spline: index + 1 of its 20 nodes
    /// in `nodes`, or 0.
    pub(super) tree_of: &'m [u32],
    /// Per tree: the 4 children (quadrant order) then the 16 grandchildren
    /// (`4 + 4 q + q2`), each its cached piece (see [`STAM`]), or 0.
    pub(super) nodes: &'m [u32],
    /// 48 values (16 points, x y z) per cached grid.
    pub(super) grids: &'m [f64],
    /// [`STAM_BLOCK`] values per cached eigen patch: the corner `r` of the
    /// extraordinary vertex, its valence `n`, then the `3 (2n + 8)` values
    /// of the eigen projection.
    stams: &'m [f64],
}

/// What a [`FeatureEvaluator`] cached at build
/// ([`FeatureEvaluator::cache_counts`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CacheCounts {
    /// Cached bicubic B-spline pieces (levels 1 to 3).
    pub grids: usize,
    /// Cached eigen projections of smooth extraordinary patches.
    pub eigen_patches: usize,
    /// Level-1 faces that are not one B-spline piece (their children and
    /// grandchildren are looked at).
    pub split_faces: usize,
    /// All level-1 faces.
    pub level1_faces: usize,
}

/// A cached piece is stored as `index + 1` of its grid, or `STAM | (index
/// + 1)` of its eigen projection.
pub(super) const STAM: u32 = 1 << 31;

/// Values per cached eigen patch (corner, valence, projection).
const STAM_BLOCK: usize = 2 + 3 * crate::config::MAX_K;

/// One cached piece of a level-1 face (a temporary of the build, on the
/// stack; the size difference of the variants does not matter there).
#[derive(Clone, Copy)]
#[allow(clippy::large_enum_variant)]
enum Piece {
    /// A bicubic B-spline (16 control points).
    Grid([glam::DVec3; 16]),
    /// A smooth extraordinary patch: corner, valence, eigen projection.
    Stam(u8, usize, [f64; 3 * crate::config::MAX_K]),
}

impl Piece {
    /// The piece of `patch`, if it is a B-spline or (with tables) a smooth
    /// extraordinary patch.
    fn of<const NF: usize, const NV: usize, const NE: usize>(
        patch: &LocalPatch<NF, NV, NE>,
        tables: Option<&TableSet>,
    ) -> Option<Piece> {
        if let Some(g) = patch.regular_grid() {
            return Some(Piece::Grid(g));
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
            .field("cached_grids", &(self.grids.len() / 48))
            .field("cached_eigen_patches", &(self.stams.len() / STAM_BLOCK))
            .finish()
    }
}

/// Where a cached piece of a level-1 face sits: the face itself, or node
/// `i` of its tree (children `0..4`, grandchildren `4 + 4 q + q2`).
#[derive(Clone, Copy)]
enum Slot {
    Root,
    Node(usize),
}

/// The three local patches the build refines in (reused for every face).
struct PlanScratch {
    patch: LocalPatch<64, 196, 256>,
    child: LocalPatch<64, 196, 256>,
    grand: LocalPatch<64, 196, 256>,
}

impl PlanScratch {
    fn new() -> Self {
        PlanScratch {
            patch: LocalPatch::empty(),
            child: LocalPatch::empty(),
            grand: LocalPatch::empty(),
        }
    }

    /// Calls `found` with every cached piece of level-1 face `f`, in slot
    /// order: the face's piece if it is one, else the pieces among its
    /// children and grandchildren.
    fn plan(
        &mut self,
        mesh: &FeatureMesh,
        f: usize,
        tables: Option<&TableSet>,
        mut found: impl FnMut(Slot, &Piece),
    ) {
        let opts = mesh.options;
        if self.patch.gather_into(mesh, f, 0).is_err() {
            return;
        }
        // A B-spline face is one piece; an extraordinary one is split even
        // when the eigen kernel could take it whole: B-spline quarters are
        // cheaper to evaluate than the kernel, which takes the quarter of a
        // quarter (level 3) that touches the extraordinary vertex.
        if let Some(g) = self.patch.regular_grid() {
            found(Slot::Root, &Piece::Grid(g));
            return;
        }
        for q in 0..4 {
            if self.patch.child_into(&opts, q, &mut self.child).is_err() {
                continue;
            }
            // As at the root: B-spline children whole, the others split
            // once more (their B-spline quarters are cheaper than the kernel).
            if let Some(g) = self.child.regular_grid() {
                found(Slot::Node(q), &Piece::Grid(g));
                continue;
            }
            for q2 in 0..4 {
                if self.child.child_into(&opts, q2, &mut self.grand).is_ok() {
                    if let Some(p) = Piece::of(&self.grand, tables) {
                        found(Slot::Node(4 + 4 * q + q2), &p);
                    }
                }
            }
        }
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
    /// `tables`. It finds the cached pieces, which costs one neighbourhood
    /// gather per level-1 face and up to 20 local refinement steps per
    /// irregular one (the build does the same work again).
    pub fn required_bytes(mesh: &FeatureMesh, tables: Option<&TableSet>) -> usize {
        let (n, trees, grids, stams) = Self::count(mesh, tables);
        Self::layout(n, trees, grids, stams).bytes()
    }

    fn count(mesh: &FeatureMesh, tables: Option<&TableSet>) -> (usize, usize, usize, usize) {
        let n = mesh.level1.num_faces();
        let (mut trees, mut grids, mut stams) = (0, 0, 0);
        let mut scratch = PlanScratch::new();
        for f in 0..n {
            let mut has_tree = false;
            scratch.plan(mesh, f, tables, |slot, p| {
                match p {
                    Piece::Grid(_) => grids += 1,
                    Piece::Stam(..) => stams += 1,
                }
                has_tree |= matches!(slot, Slot::Node(_));
            });
            trees += usize::from(has_tree);
        }
        (n, trees, grids, stams)
    }

    fn layout(n: usize, trees: usize, grids: usize, stams: usize) -> Layout {
        let mut l = Layout::default();
        l.u32s(n);
        l.u32s(n);
        l.u32s(20 * trees);
        l.f64s(48 * grids);
        l.f64s(STAM_BLOCK * stams);
        l
    }

    /// The evaluator of `mesh`, with the cached pieces in `mem` (see
    /// [`FeatureEvaluator::required_bytes`], with the same `tables`). With
    /// `tables` (built with [`crate::mesh::Weights::STANDARD`], else an error),
    /// smooth extraordinary patches are evaluated with the eigen kernel
    /// (\[Stam98\]): cached as eigen projections down to level 3, and in one
    /// step when met deeper; without, they are refined like every other
    /// irregular piece (same surface, slower).
    pub fn build(
        mesh: &'m FeatureMesh<'a>,
        tables: Option<&'m TableSet>,
        mem: &'m mut [u64],
    ) -> Result<Self, Error> {
        if tables.is_some_and(|t| *t.weights() != crate::mesh::Weights::STANDARD) {
            return Err(Error::InvalidArgument(
                "feature evaluation needs eigen tables of the standard Catmull-Clark rule",
            ));
        }
        let (n, trees_n, grids_n, stams_n) = Self::count(mesh, tables);
        let need = Self::layout(n, trees_n, grids_n, stams_n).bytes();
        if crate::mem::bytes_of(mem.len()) < need {
            return Err(Error::BufferTooSmall { required: need });
        }
        let mut arena = Arena::new(mem);
        let grid_of = arena.u32s(n);
        let tree_of = arena.u32s(n);
        let nodes = arena.u32s(20 * trees_n);
        let grids = arena.f64s(48 * grids_n);
        let stams = arena.f64s(STAM_BLOCK * stams_n);
        let (mut kg, mut ks, mut t) = (0usize, 0usize, 0usize);
        let mut store = |p: &Piece, grids: &mut [f64], stams: &mut [f64]| match p {
            Piece::Grid(g) => {
                for (i, q) in g.iter().enumerate() {
                    grids[48 * kg + 3 * i] = q.x;
                    grids[48 * kg + 3 * i + 1] = q.y;
                    grids[48 * kg + 3 * i + 2] = q.z;
                }
                kg += 1;
                kg as u32
            }
            Piece::Stam(r, valence, ghat) => {
                let b = &mut stams[STAM_BLOCK * ks..STAM_BLOCK * (ks + 1)];
                b[0] = *r as f64;
                b[1] = *valence as f64;
                b[2..].copy_from_slice(ghat);
                ks += 1;
                STAM | ks as u32
            }
        };
        let mut scratch = PlanScratch::new();
        for f in 0..n {
            scratch.plan(mesh, f, tables, |slot, p| match slot {
                Slot::Root => grid_of[f] = store(p, grids, stams),
                Slot::Node(i) => {
                    // The face's first node opens its tree.
                    if tree_of[f] == 0 {
                        t += 1;
                        tree_of[f] = t as u32;
                    }
                    nodes[20 * (t - 1) + i] = store(p, grids, stams);
                }
            });
        }
        Ok(FeatureEvaluator {
            mesh,
            tables,
            grid_of,
            tree_of,
            nodes,
            grids,
            stams,
        })
    }

    /// The cached piece `code` (see [`STAM`]) evaluated at `(s, t)`.
    #[inline(always)]
    fn piece(&self, code: u32, s: f64, t: f64, scale: f64, second: bool) -> Result<Eval, Error> {
        if code & STAM == 0 {
            Ok(self.cached(code as usize - 1, s, t, scale, second))
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
        let k = (code & !STAM) as usize - 1;
        let b = &self.stams[STAM_BLOCK * k..STAM_BLOCK * (k + 1)];
        let (r, n) = (b[0] as u8, b[1] as usize);
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

    /// The cached B-spline piece `k` (0-based) evaluated at `(s, t)`.
    #[inline]
    fn cached(&self, k: usize, s: f64, t: f64, scale: f64, second: bool) -> Eval {
        let g = &self.grids[48 * k..48 * k + 48];
        let mut pts = [glam::DVec3::ZERO; 16];
        for (i, p) in pts.iter_mut().enumerate() {
            *p = glam::DVec3::new(g[3 * i], g[3 * i + 1], g[3 * i + 2]);
        }
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
    /// extraordinary corners) and level-1 faces split into a tree of
    /// children and grandchildren (see [`FeatureEvaluator`]).
    pub fn cache_counts(&self) -> CacheCounts {
        CacheCounts {
            grids: self.grids.len() / 48,
            eigen_patches: self.stams.len() / STAM_BLOCK,
            split_faces: self.nodes.len() / 20,
            level1_faces: self.grid_of.len(),
        }
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
        if self.check(q).is_err() {
            return false;
        }
        let (face1, s, t) = self.level1(q.face as usize, q.sub as usize, q.u, q.v);
        self.cached_at(face1, s, t).is_some()
    }

    /// The cached piece of level-1 face `face1` that contains `(s, t)`: its
    /// code (see [`STAM`]), the parameters in it and the factor by which it
    /// is smaller (1, 2 or 4).
    #[inline]
    fn cached_at(&self, face1: usize, s: f64, t: f64) -> Option<(u32, f64, f64, f64)> {
        if self.grid_of[face1] != 0 {
            return Some((self.grid_of[face1], s, t, 1.0));
        }
        let tree = (self.tree_of[face1] as usize).checked_sub(1)?;
        let nodes = &self.nodes[20 * tree..20 * tree + 20];
        let (q, s1, t1) = quadrant(s, t);
        if nodes[q] != 0 {
            return Some((nodes[q], s1, t1, 2.0));
        }
        let (q2, s2, t2) = quadrant(s1, t1);
        let code = nodes[4 + 4 * q + q2];
        (code != 0).then_some((code, s2, t2, 4.0))
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
