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
                return Ok(CellGeom::Split);
            }
            let (q, i, j) = quadrant_of(level, i, j);
            (fm.child_face(f, q), level - 1, i, j)
        } else {
            (fm.child_face(f, sub as usize), level, i, j)
        };
        if let Some(g) = self.cached_cell(face1, d, i, j) {
            return Ok(g);
        }
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
            if code == 0 || code & STAM != 0 {
                return None;
            }
            let k = code as usize - 1;
            let g = &self.grids[48 * k..48 * k + 48];
            let mut pts = [DVec3::ZERO; 16];
            for (n, p) in pts.iter_mut().enumerate() {
                *p = DVec3::new(g[3 * n], g[3 * n + 1], g[3 * n + 2]);
            }
            Some(CellGeom::Poly {
                grid: pts,
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
