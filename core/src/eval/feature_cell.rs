//! What the limit surface of a [`FeatureEvaluator`] is over one dyadic cell
//! of a sub-face: one bicubic piece, or (next to a vertex that stays
//! irregular, or before a semi-sharp value has decayed) a region known only
//! to lie in the convex hull of its control points.
//!
//! A cell of level `l` of sub-face `(face, sub)` is the parameter square
//! `[i/2^l, (i+1)/2^l] x [j/2^l, (j+1)/2^l]`, with `i` along `u`. This is
//! what the adaptive consumers (tessellation, voxelization, measure, depth)
//! need to bound the surface over a cell without sampling:
//!
//! * [`CellGeom::Poly`]: the surface over the cell is the bicubic B-spline
//!   of 16 control points (phantoms across infinitely sharp sides included)
//!   restricted to a dyadic sub-rectangle of its domain, so the exact Bezier
//!   net of the cell follows (\[OSD\]; `math::bezier::net_over_points`).
//! * [`CellGeom::Hull`]: every Catmull-Clark rule with OpenSubdiv's sharp,
//!   semi-sharp and boundary variants (and every limit mask) is a convex
//!   combination, and the surface over a quad depends only on the quad and
//!   the faces around its corners, so the surface over the cell lies in the
//!   convex hull of the points of the cell's [`LocalPatch`]. The summary
//!   [`HullBound`] keeps their bounding box and the radius of their ball
//!   about the box centre. This bound shrinks like the cell (not like its
//!   square): consumers refine hull cells deeper than polynomial ones.
//! * [`CellGeom::Split`]: the level-0 cell of a quad face covers its four
//!   level-1 patches; it has no single piece (consumers split it).
//!
//! A cell that is not in the evaluator's cache costs one local refinement
//! step per level from level 1, so a walk that asks for every cell of a
//! chain down to level `L` one by one costs `O(L^2)` steps. Walks go
//! through one of two variants with the same results, bit for bit:
//! [`FeatureEvaluator::cell_in`] keeps the patches of the last path in a
//! caller's [`CellCursor`] (a depth-first walk then refines once per
//! cell), and [`FeatureEvaluator::cell_children`] gives a cell's four
//! children from one descent (for walks that split into all four at once
//! and keep no cursor).
//!
//! Layer 5 (with the rest of `eval/`): imports `error`, `math`, `mesh`.

use super::feature::{Entry, FeatureEvaluator, STAM};
use crate::error::Error;
use crate::mesh::local::LocalPatch;
use glam::DVec3;

/// Deepest cell level [`FeatureEvaluator::cell`] accepts (dyadic
/// parameters of this level are exact in `f64` and in 32-bit fixed point).
pub const MAX_CELL_LEVEL: u32 = 30;

/// The convex hull of a cell's control points, summarised.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HullBound {
    /// Lower corner of the points' bounding box.
    pub lo: DVec3,
    /// Upper corner of the points' bounding box.
    pub hi: DVec3,
    /// Largest distance of a point from the box centre `(lo + hi) / 2`.
    pub radius: f64,
}

impl HullBound {
    /// The hull of `points` (which must not be empty).
    pub fn of(points: &[DVec3]) -> HullBound {
        let mut lo = DVec3::splat(f64::INFINITY);
        let mut hi = DVec3::splat(f64::NEG_INFINITY);
        for &p in points {
            lo = lo.min(p);
            hi = hi.max(p);
        }
        let c = (lo + hi) * 0.5;
        let radius = points.iter().map(|&p| p.distance(c)).fold(0.0, f64::max);
        HullBound { lo, hi, radius }
    }

    /// Centre of the bounding box.
    pub fn centre(&self) -> DVec3 {
        (self.lo + self.hi) * 0.5
    }

    /// An upper bound on the distance between any two points of the hull
    /// (the smaller of the ball's diameter and the box diagonal). Any
    /// two points of the surface over the cell, or of a polygon whose
    /// vertices lie on it, are at most this far apart.
    pub fn diameter(&self) -> f64 {
        (2.0 * self.radius).min((self.hi - self.lo).length())
    }
}

/// The surface over one cell (see the module docs). A value type returned
/// by value (no heap in the core), hence the size difference of its variants.
#[derive(Clone, Copy, Debug, PartialEq)]
#[allow(clippy::large_enum_variant)]
pub enum CellGeom {
    /// The level-0 cell of a quad face: four level-1 patches, no one piece.
    Split,
    /// One bicubic piece: B-spline control points (row by row, `i` along
    /// `u`, in the sub-face's orientation) whose unit square maps to the
    /// piece; the cell is its sub-rectangle `[u0, u1] x [v0, v1]`
    /// (`rect = [u0, u1, v0, v1]`, dyadic).
    Poly {
        /// The 16 control points.
        grid: [DVec3; 16],
        /// The cell inside the piece's unit square.
        rect: [f64; 4],
    },
    /// Not polynomial at this level: the surface over the cell lies in the
    /// convex hull summarised here.
    Hull(HullBound),
}

/// The quadrant (0: `(0,0)`, 1: `(1,0)`, 2: `(1,1)`, 3: `(0,1)`) holding
/// cell `(i, j)` of depth `d >= 1`, and the cell's index inside it.
#[inline]
fn quadrant_of(d: u32, i: u32, j: u32) -> (usize, u32, u32) {
    let (ci, cj) = ((i >> (d - 1)) & 1, (j >> (d - 1)) & 1);
    let q = match (ci, cj) {
        (0, 0) => 0,
        (1, 0) => 1,
        (1, 1) => 2,
        _ => 3,
    };
    let mask = (1u32 << (d - 1)) - 1;
    (q, i & mask, j & mask)
}

/// Cell `(i, j)` of depth `d` inside a piece's unit square.
#[inline]
fn rect(d: u32, i: u32, j: u32) -> [f64; 4] {
    let h = 1.0 / (1u64 << d) as f64;
    [
        i as f64 * h,
        (i + 1) as f64 * h,
        j as f64 * h,
        (j + 1) as f64 * h,
    ]
}

/// Where [`FeatureEvaluator::locate`] found a cell.
#[allow(clippy::large_enum_variant)]
enum Located {
    Done(CellGeom),
    Descend {
        face1: usize,
        d: u32,
        i: u32,
        j: u32,
    },
}

/// The local patches a [`CellCursor`] keeps (the evaluator's first
/// capacity: 32 faces).
type CursorPatch = LocalPatch<32, 100, 128>;

/// Local patches a [`CellCursor`] keeps along its path (levels 1 to
/// `CURSOR_STATES`; deeper cells refine on from the last one).
pub const CURSOR_STATES: usize = 16;

/// The local patches along the path of the last cell
/// [`FeatureEvaluator::cell_in`] refined: the level-1 face's patch and its
/// refinements towards the cell, one per level (up to [`CURSOR_STATES`]).
/// The next cell reuses the longest common part of the path, so walks down
/// a quadtree refine once per cell. About 131 KiB (the caller keeps one
/// per thread and walk; [`CellCursor::BYTES`]); tied to one mesh by the
/// lifetime `'m`.
pub struct CellCursor<'m> {
    /// Address of the mesh the states belong to (0: none yet).
    mesh: usize,
    /// Level-1 face of the states.
    face1: usize,
    /// Valid states: `states[0..len]`.
    len: usize,
    /// `quads[k]`: the quadrant refined from `states[k]` to `states[k + 1]`.
    quads: [u8; CURSOR_STATES],
    states: [CursorPatch; CURSOR_STATES],
    /// Two more patches for cells deeper than the stored path.
    tail: [CursorPatch; 2],
    _mesh: core::marker::PhantomData<&'m ()>,
}

impl Default for CellCursor<'_> {
    fn default() -> Self {
        Self::new()
    }
}

impl<'m> CellCursor<'m> {
    /// Bytes of a cursor.
    pub const BYTES: usize = core::mem::size_of::<CellCursor<'static>>();

    /// An empty cursor.
    pub fn new() -> Self {
        CellCursor {
            mesh: 0,
            face1: 0,
            len: 0,
            quads: [0; CURSOR_STATES],
            states: core::array::from_fn(|_| CursorPatch::empty()),
            tail: [CursorPatch::empty(), CursorPatch::empty()],
            _mesh: core::marker::PhantomData,
        }
    }

    /// Cell `(d, i, j)` of level-1 face `face1` (the descent of
    /// `FeatureEvaluator::descend_cell`, from the longest stored part of
    /// its path), or None if a patch overflowed the cursor's capacity.
    fn descend(
        &mut self,
        fe: &FeatureEvaluator<'m, '_>,
        face1: usize,
        d: u32,
        i: u32,
        j: u32,
        face: u32,
    ) -> Option<Result<CellGeom, Error>> {
        let opts = fe.mesh.options;
        let mesh = fe.mesh as *const _ as usize;
        // Quadrants of the path from level 1 to the cell.
        let mut path = [0u8; MAX_CELL_LEVEL as usize + 1];
        {
            let (mut dd, mut ii, mut jj) = (d, i, j);
            for p in path.iter_mut().take(d as usize) {
                let (q, i1, j1) = quadrant_of(dd, ii, jj);
                *p = q as u8;
                (dd, ii, jj) = (dd - 1, i1, j1);
            }
        }
        if self.mesh != mesh || self.face1 != face1 || self.len == 0 {
            self.len = 0;
            match self.states[0].gather_into(fe.mesh, face1, face) {
                Ok(()) => {}
                Err(Error::NeighbourhoodTooLarge { .. }) => return None,
                Err(e) => return Some(Err(e)),
            }
            self.mesh = mesh;
            self.face1 = face1;
            self.len = 1;
        }
        // Deepest stored state on the path: states[k] is the patch after
        // k steps along `path`.
        let mut k = 0usize;
        while k + 1 < self.len && k < d as usize && self.quads[k] == path[k] {
            k += 1;
        }
        self.len = k + 1;
        let (mut dd, mut ii, mut jj) = (d - k as u32, i, j);
        let mask = |dd: u32| if dd >= 32 { u32::MAX } else { (1u32 << dd) - 1 };
        ii &= mask(dd);
        jj &= mask(dd);
        // Stored part.
        loop {
            let patch = &self.states[k];
            if let Some(grid) = patch.regular_grid() {
                return Some(Ok(CellGeom::Poly {
                    grid,
                    rect: rect(dd, ii, jj),
                }));
            }
            if dd == 0 {
                return Some(Ok(CellGeom::Hull(HullBound::of(patch.points()))));
            }
            let (q, i1, j1) = quadrant_of(dd, ii, jj);
            if k + 1 == CURSOR_STATES {
                break;
            }
            let (done, rest) = self.states.split_at_mut(k + 1);
            if done[k].child_into(&opts, q, &mut rest[0]).is_err() {
                self.len = k + 1;
                return None;
            }
            self.quads[k] = q as u8;
            k += 1;
            self.len = k + 1;
            (dd, ii, jj) = (dd - 1, i1, j1);
        }
        // Deeper than the stored path: two patches in turn.
        let (q, i1, j1) = quadrant_of(dd, ii, jj);
        let [a, b] = &mut self.tail;
        if self.states[k].child_into(&opts, q, a).is_err() {
            return None;
        }
        (dd, ii, jj) = (dd - 1, i1, j1);
        let (mut patch, mut next) = (a, b);
        loop {
            if let Some(grid) = patch.regular_grid() {
                return Some(Ok(CellGeom::Poly {
                    grid,
                    rect: rect(dd, ii, jj),
                }));
            }
            if dd == 0 {
                return Some(Ok(CellGeom::Hull(HullBound::of(patch.points()))));
            }
            let (q, i1, j1) = quadrant_of(dd, ii, jj);
            if patch.child_into(&opts, q, next).is_err() {
                return None;
            }
            core::mem::swap(&mut patch, &mut next);
            (dd, ii, jj) = (dd - 1, i1, j1);
        }
    }
}

impl<'m, 'a> FeatureEvaluator<'m, 'a> {
    /// The feature mesh this evaluator evaluates.
    pub fn mesh(&self) -> &'m crate::mesh::features::FeatureMesh<'a> {
        self.mesh
    }

    /// The surface over cell `(i, j)` of level `level` of sub-face `sub`
    /// of base face `face` (see the module docs). Cost: a lookup where the
    /// cached B-spline pieces cover the cell, else one neighbourhood gather
    /// and one local refinement step per level below 1.
    ///
    /// Errors: face, sub-face or cell out of range (`level` above
    /// [`MAX_CELL_LEVEL`], `i` or `j` not below `2^level`), a hole face,
    /// [`Error::NeighbourhoodTooLarge`].
    pub fn cell(&self, face: u32, sub: u32, level: u32, i: u32, j: u32) -> Result<CellGeom, Error> {
        match self.locate(face, sub, level, i, j)? {
            Located::Done(g) => Ok(g),
            Located::Descend { face1, d, i, j } => self.descend_any(face1, d, i, j, face),
        }
    }

    /// [`FeatureEvaluator::cell`] through a [`CellCursor`]: the same result
    /// (bit for bit), but the local patches of the cursor's last path are
    /// reused, so a walk down the quadtree (children after their parent,
    /// siblings one after the other) costs one local refinement step per
    /// cell instead of one per level. Cells the cursor cannot hold (a
    /// neighbourhood beyond its capacity) take [`FeatureEvaluator::cell`]'s
    /// route.
    pub fn cell_in(
        &self,
        cursor: &mut CellCursor<'m>,
        face: u32,
        sub: u32,
        level: u32,
        i: u32,
        j: u32,
    ) -> Result<CellGeom, Error> {
        match self.locate(face, sub, level, i, j)? {
            Located::Done(g) => Ok(g),
            Located::Descend { face1, d, i, j } => match cursor.descend(self, face1, d, i, j, face)
            {
                Some(g) => g,
                None => self.descend_any(face1, d, i, j, face),
            },
        }
    }

    /// The four children of cell `(level, i, j)` (quadrants 0: `(2i, 2j)`,
    /// 1: `(2i+1, 2j)`, 2: `(2i+1, 2j+1)`, 3: `(2i, 2j+1)`), each exactly
    /// what [`FeatureEvaluator::cell`] returns for it, from one descent to
    /// the parent and one refinement step per child (not one descent per
    /// child): for walks that split a cell into all four at once.
    pub fn cell_children(
        &self,
        face: u32,
        sub: u32,
        level: u32,
        i: u32,
        j: u32,
    ) -> Result<[CellGeom; 4], Error> {
        const KIDS: [(u32, u32); 4] = [(0, 0), (1, 0), (1, 1), (0, 1)];
        if level >= MAX_CELL_LEVEL {
            // The children are out of range: the error of `cell`.
            self.locate(face, sub, level.saturating_add(1), 2 * i, 2 * j)?;
        }
        let mut out = [CellGeom::Split; 4];
        let mut pending = [None; 4];
        for (q, (di, dj)) in KIDS.iter().enumerate() {
            match self.locate(face, sub, level + 1, 2 * i + di, 2 * j + dj)? {
                Located::Done(g) => out[q] = g,
                Located::Descend { face1, d, i, j } => pending[q] = Some((face1, d, i, j)),
            }
        }
        let Some((face1, d, ..)) = pending.iter().flatten().next().copied() else {
            return Ok(out);
        };
        // The pending children share their level-1 face and parent (both
        // are at depth >= 1 below it: a child at depth 0 would be a
        // level-1 face, whose parent is a Split cell, or of an N-gon's
        // sub-face, whose children are at depth 1).
        let same = pending
            .iter()
            .flatten()
            .all(|&(f1, d1, ..)| f1 == face1 && d1 == d && d >= 1);
        if same {
            if let Some(()) = self.children_from_parent::<32, 100, 128>(&mut out, &pending, face) {
                return Ok(out);
            }
        }
        for (q, p) in pending.iter().enumerate() {
            if let Some((face1, d, i, j)) = *p {
                out[q] = self.descend_any(face1, d, i, j, face)?;
            }
        }
        Ok(out)
    }

    /// The pending children of [`FeatureEvaluator::cell_children`] (same
    /// level-1 face, depth `d >= 1`) by one descent to their parent with
    /// patches of the given capacity; None if a patch overflowed or the
    /// gather failed (the caller then takes `cell`'s route, which reports
    /// the error).
    fn children_from_parent<const NF: usize, const NV: usize, const NE: usize>(
        &self,
        out: &mut [CellGeom; 4],
        pending: &[Option<(usize, u32, u32, u32)>; 4],
        face: u32,
    ) -> Option<()> {
        let opts = self.mesh.options;
        let (face1, d, ci, cj) = pending.iter().flatten().next().copied()?;
        let (mut dd, mut i, mut j) = (d - 1, ci >> 1, cj >> 1);
        let mut first = LocalPatch::<NF, NV, NE>::empty();
        first.gather_into(self.mesh, face1, face).ok()?;
        let mut other = LocalPatch::<NF, NV, NE>::empty();
        let (mut patch, mut next) = (&mut first, &mut other);
        // To the parent, as `descend_cell` (a regular patch on the way
        // holds all four children).
        loop {
            if let Some(grid) = patch.regular_grid() {
                for (q, p) in pending.iter().enumerate() {
                    if let Some((_, _, ci, cj)) = *p {
                        let m = (1u32 << (dd + 1)) - 1;
                        out[q] = CellGeom::Poly {
                            grid,
                            rect: rect(dd + 1, ci & m, cj & m),
                        };
                    }
                }
                return Some(());
            }
            if dd == 0 {
                break;
            }
            let (q, i1, j1) = quadrant_of(dd, i, j);
            patch.child_into(&opts, q, next).ok()?;
            core::mem::swap(&mut patch, &mut next);
            (dd, i, j) = (dd - 1, i1, j1);
        }
        // One step per child, into the spare patch.
        for (q, p) in pending.iter().enumerate() {
            if let Some((_, _, ci, cj)) = *p {
                let (k, ..) = quadrant_of(1, ci & 1, cj & 1);
                patch.child_into(&opts, k, next).ok()?;
                out[q] = match next.regular_grid() {
                    Some(grid) => CellGeom::Poly {
                        grid,
                        rect: rect(0, 0, 0),
                    },
                    None => CellGeom::Hull(HullBound::of(next.points())),
                };
            }
        }
        Some(())
    }

    /// Checks a cell and finds it in the cache, or names the level-1 face
    /// to refine and the cell's depth and index inside it.
    fn locate(&self, face: u32, sub: u32, level: u32, i: u32, j: u32) -> Result<Located, Error> {
        let fm = self.mesh;
        let f = face as usize;
        if f >= fm.num_faces() {
            return Err(Error::FaceOutOfRange { face });
        }
        if sub as usize >= self.num_subfaces(f) {
            return Err(Error::SubFaceOutOfRange { face, sub });
        }
        if level > MAX_CELL_LEVEL || i >> level != 0 || j >> level != 0 {
            return Err(Error::InvalidArgument(
                "cell level above 30 or cell index outside the sub-face",
            ));
        }
        if fm.hole[fm.child_face(f, 0)] != 0 {
            return Err(Error::HoleFace { face });
        }
        // Level-1 patch and the cell's depth and index inside it.
        let (face1, d, i, j) = if fm.base.face(f).len() == 4 {
            if level == 0 {
                return Ok(Located::Done(CellGeom::Split));
            }
            let (q, i, j) = quadrant_of(level, i, j);
            (fm.child_face(f, q), level - 1, i, j)
        } else {
            (fm.child_face(f, sub as usize), level, i, j)
        };
        if let Some(g) = self.cached_cell(face1, d, i, j) {
            return Ok(Located::Done(g));
        }
        Ok(Located::Descend { face1, d, i, j })
    }

    /// The cell by local refinement from level 1, with the smallest
    /// capacity that holds the neighbourhood.
    fn descend_any(
        &self,
        face1: usize,
        d: u32,
        i: u32,
        j: u32,
        face: u32,
    ) -> Result<CellGeom, Error> {
        // The smallest capacity that holds the neighbourhood (a fresh patch
        // is zeroed memory, a sizeable part of a short descent).
        let tiny = self.descend_cell::<32, 100, 128>(face1, d, i, j, face);
        let Err(Error::NeighbourhoodTooLarge { .. }) = tiny else {
            return tiny;
        };
        let small = self.descend_cell::<64, 196, 256>(face1, d, i, j, face);
        let Err(Error::NeighbourhoodTooLarge { .. }) = small else {
            return small;
        };
        self.descend_cell::<400, 1204, 1600>(face1, d, i, j, face)
    }

    /// The cell from the cached B-spline grids of level-1 face `face1`, if
    /// one of them covers it.
    fn cached_cell(&self, face1: usize, d: u32, i: u32, j: u32) -> Option<CellGeom> {
        let grid = |code: u32, d: u32, i: u32, j: u32| -> Option<CellGeom> {
            if code == 0 {
                return None;
            }
            if code & STAM != 0 {
                let (grid, rect) = self.strip_cell(code, d, i, j)?;
                return Some(CellGeom::Poly { grid, rect });
            }
            Some(CellGeom::Poly {
                grid: self.grid_points(code),
                rect: rect(d, i, j),
            })
        };
        if let Some(g) = grid(self.grid_of[face1], d, i, j) {
            return Some(g);
        }
        // Down the cache tree to the piece that holds the cell.
        let mut group = (self.tree_of[face1] as usize).checked_sub(1)?;
        let (mut d, mut i, mut j) = (d, i, j);
        while d > 0 {
            let (q, i1, j1) = quadrant_of(d, i, j);
            (d, i, j) = (d - 1, i1, j1);
            match self.tree_entry(group, q) {
                Entry::Piece(code) => return grid(code, d, i, j),
                Entry::Node(g) => group = g,
                Entry::Local => return None,
            }
        }
        None
    }

    /// The cell by local refinement of level-1 face `face1` with a patch of
    /// the given capacity.
    #[inline(never)]
    fn descend_cell<const NF: usize, const NV: usize, const NE: usize>(
        &self,
        face1: usize,
        mut d: u32,
        mut i: u32,
        mut j: u32,
        face: u32,
    ) -> Result<CellGeom, Error> {
        let opts = self.mesh.options;
        let too_large = |_| Error::NeighbourhoodTooLarge { face };
        // Two patches, each step refining one into the other (as the
        // evaluator's descent: no patch copied or zeroed per step).
        let mut first = LocalPatch::<NF, NV, NE>::empty();
        first.gather_into(self.mesh, face1, face)?;
        let mut other = LocalPatch::<NF, NV, NE>::empty();
        let (mut patch, mut next) = (&mut first, &mut other);
        loop {
            if let Some(grid) = patch.regular_grid() {
                return Ok(CellGeom::Poly {
                    grid,
                    rect: rect(d, i, j),
                });
            }
            if d == 0 {
                return Ok(CellGeom::Hull(HullBound::of(patch.points())));
            }
            let (q, i1, j1) = quadrant_of(d, i, j);
            patch.child_into(&opts, q, next).map_err(too_large)?;
            core::mem::swap(&mut patch, &mut next);
            (d, i, j) = (d - 1, i1, j1);
        }
    }
}
